"""Time and size of the flexspline drawings (issue 17 item 2), in process, medians of ``-n`` runs.

    python tests/benchmarks/flexspline_files.py [-n 5] [--scene design] [--gearset PATH]

For the gear set's design (computed once, outside the timing): the tooth chain
(``fsform.flexspline_tooth_chain``), ``flexspline_tooth.dxf`` + ``flexspline.dxf``
(``output.flexspline.write_flexspline_dxfs``, the chain included) and ``assembly.dxf``
(the posed teeth and the file), each timed by ``time.perf_counter`` and
``time.process_time``; then the deviation and the element count of the arc spline of an
involute flank and of two point-list flanks (24 points of that involute; 40 points of the
set's DCTA tooth, whose spline smooths the arc joins) at 1e-4 … 1e-7 mm, with their time. Prints a table; writes nothing outside a temporary folder.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path


def _timed(fn, n: int) -> tuple[float, float, object]:
    walls, cpus, out = [], [], None
    for _ in range(n):
        w, c = time.perf_counter(), time.process_time()
        out = fn()
        walls.append(time.perf_counter() - w)
        cpus.append(time.process_time() - c)
    return statistics.median(walls), statistics.median(cpus), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=5)
    ap.add_argument("--scene", default="design")
    ap.add_argument("--gearset", default=None)
    args = ap.parse_args()

    import numpy as np

    import profilegen as pg
    from profilegen.geometry.fsform import flank_elements, flexspline_tooth_chain
    from profilegen.output import cad
    from profilegen.output.files import _assembly_layers
    from profilegen.output.flexspline import write_flexspline_dxfs
    from profilegen.geometry.teeth import involute_tooth, points_tooth

    gs = pg.load_gearset(args.gearset or pg.default_gearset_path())
    d = pg.design(gs, scene=args.scene, contact=False, stress=False)
    note = [("annotation", (0.0, 0.0), 1.0, "benchmark")]
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        rows = []
        w, c, (chain, dev) = _timed(lambda: flexspline_tooth_chain(d.tooth, gs.gear), args.n)
        rows.append(("tooth chain", w, c, f"{len(chain.elements)} elements, deviation {dev:.3g} mm"))
        w, c, chain = _timed(lambda: write_flexspline_dxfs(out, d), args.n)
        sizes = ", ".join(f"{p} {(out / p).stat().st_size} B" for p in ("flexspline_tooth.dxf", "flexspline.dxf"))
        rows.append(("flexspline_tooth.dxf + flexspline.dxf", w, c, sizes))
        w, c, _ = _timed(lambda: cad.write_contours_dxf(out / "assembly.dxf", _assembly_layers(d, chain), texts=note),
                         args.n)
        rows.append(("assembly.dxf", w, c, f"{(out / 'assembly.dxf').stat().st_size} B"))
    print(f"{gs.name}, scene {args.scene}, medians of {args.n} (wall / CPU, s)")
    for name, w, c, what in rows:
        print(f"  {name:40s} {w:8.4f} {c:8.4f}   {what}")

    g = gs.gear
    kw = dict(module_mm=g.module_mm, teeth=g.flexspline_teeth, neutral_radius_mm=g.neutral_radius_mm)
    inv = involute_tooth(**kw)
    dcta = d.tooth
    flanks = (("involute", inv),
              ("points: 24 of the involute", points_tooth(inv.point(np.linspace(0.0, inv.length_mm, 24)),
                                                          smoothing_mm=0.0, **kw)),
              ("points: 40 of the DCTA", points_tooth(dcta.point(np.linspace(0.0, dcta.length_mm, 40)),
                                                      smoothing_mm=0.0, **kw)))
    print("arc-spline flanks: the tooth chain, its deviation from the exact flank, elements per flank")
    for name, tooth in flanks:
        for tol in (1e-4, 1e-5, 1e-6, 1e-7):
            w, c, (ch, dev) = _timed(lambda: flexspline_tooth_chain(tooth, g, tol_mm=tol), args.n)
            per_flank = len(flank_elements(tooth, tol_mm=tol)[0])
            print(f"  {name:28s} tol {tol:7.0e} mm: deviation {dev:.3e} mm, {per_flank:3d} elements a flank, "
                  f"{w:.4f} s wall / {c:.4f} s CPU")

if __name__ == "__main__":
    main()
