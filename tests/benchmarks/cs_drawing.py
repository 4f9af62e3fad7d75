"""Time of ``circular_spline_drawing.dxf`` (issue 17 item 3), in process, medians of ``-n`` runs.

    python tests/benchmarks/cs_drawing.py [-n 5] [--scene sketch] [--gearset PATH] [--png OUT.png]

For the gear set's design (computed once, outside the timing), alternating in one process:
``output.drawing.write_cs_drawing`` and, as the yardstick on the same (shared, busy) machine,
``circular_spline.dxf`` as ``write_design`` writes it (the same outline through
``cad.write_contours_dxf``); wall (``time.perf_counter``) and CPU (``time.process_time``),
medians, plus the file sizes and the drawing's ezdxf audit. With ``--png`` it prints the
drawing with LibreCAD (``librecad dxf2pdf -a``, then ``pdftoppm -r 150``) to that PNG
(docs/circular_spline_drawing.png is made so, with ``SOURCE_DATE_EPOCH`` unset: blank date).
Writes nothing else outside a temporary folder.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import tempfile
import time
from pathlib import Path


def librecad_png(dxf: Path, png: Path, work: Path, dpi: int = 150) -> None:
    out = work / "pdf"
    out.mkdir(parents=True, exist_ok=True)
    (work / "run").mkdir(mode=0o700, exist_ok=True)
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen", HOME=str(work), XDG_CONFIG_HOME=str(work / ".config"),
               XDG_RUNTIME_DIR=str(work / "run"))
    subprocess.run(["librecad", "dxf2pdf", "-a", "-t", str(out), str(dxf)], env=env, check=True,
                   capture_output=True, timeout=300)
    subprocess.run(["pdftoppm", "-png", "-r", str(dpi), "-singlefile", str(out / (dxf.stem + ".pdf")),
                    str(work / "page")], check=True, capture_output=True, timeout=300)
    shutil.copyfile(work / "page.png", png)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=5)
    ap.add_argument("--scene", default="sketch")
    ap.add_argument("--gearset", default=None)
    ap.add_argument("--png", default=None, help="also print the drawing with LibreCAD to this PNG")
    args = ap.parse_args()

    import numpy as np

    import profilegen as pg
    from profilegen.geometry.contour import Arc
    from profilegen.output import cad, drawing

    gs = pg.load_gearset(args.gearset or pg.default_gearset_path())
    design = pg.design(gs, scene=args.scene)
    prof, form = design.profile, design.form
    circles = [Arc(np.zeros(2), r, 0.0, 2 * np.pi) for r in (form.tip_radius_mm, form.root_radius_mm)]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        a, b = tmp / "circular_spline_drawing.dxf", tmp / "circular_spline.dxf"
        times: dict[str, list[tuple[float, float]]] = {a.name: [], b.name: []}
        jobs = {a.name: lambda: drawing.write_cs_drawing(a, design),
                b.name: lambda: cad.write_contours_dxf(b, {"CS": [prof.outline], "construction": circles})}
        for name, job in jobs.items():  # once each, untimed: imports
            job()
        for _ in range(args.n):
            for name, job in jobs.items():
                w, c = time.perf_counter(), time.process_time()
                job()
                times[name].append((time.perf_counter() - w, time.process_time() - c))
        print(f"{gs.name}, scene {args.scene}: {len(prof.outline.elements)} outline elements, "
              f"{len(prof.space.elements)} in the space; medians of {args.n}")
        for name, tw in times.items():
            wall = statistics.median(t[0] for t in tw)
            cpu = statistics.median(t[1] for t in tw)
            size = (tmp / name).stat().st_size
            print(f"  {name:32s} wall {wall:6.3f} s  cpu {cpu:6.3f} s  {size:8d} B")
        print(f"  audit errors of the drawing: {cad.audit(a)}")
        if args.png:
            librecad_png(a, Path(args.png), tmp)
            print(f"  LibreCAD print: {args.png}")


if __name__ == "__main__":
    main()
