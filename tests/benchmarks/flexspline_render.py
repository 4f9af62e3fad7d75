"""LibreCAD's rendering of the flexspline drawings (issue 17 item 2) → docs/flexspline_tooth.png.

    python tests/benchmarks/flexspline_render.py [--scene design] [--out docs/flexspline_tooth.png]

Writes the default set's design files into a temporary folder, prints ``flexspline_tooth.dxf``
with LibreCAD (``librecad dxf2pdf -a``: fitted to the page, LibreCAD's own DXF reader,
libdxfrw), and a crop of ``assembly.dxf`` — its LINE / ARC entities and its LWPOLYLINE
points inside a window over the wave generator's major axis (±3 FS pitches about the top),
written back with ``cad.write_contours_dxf`` — the same way; poppler's ``pdftoppm`` rasterises
the pages, and the two trimmed pages go side by side into one PNG. Needs ``librecad`` and
``pdftoppm`` (apt-get install -y librecad poppler-utils); HOME points into the temporary folder.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import tempfile
from pathlib import Path

import numpy as np

DPI = 150


def librecad_png(dxf: Path, work: Path) -> Path:
    out = work / "pdf"
    out.mkdir(parents=True, exist_ok=True)
    (work / "run").mkdir(mode=0o700, exist_ok=True)
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen", HOME=str(work),
               XDG_CONFIG_HOME=str(work / ".config"), XDG_RUNTIME_DIR=str(work / "run"))
    subprocess.run(["librecad", "dxf2pdf", "-a", "-t", str(out), str(dxf)], env=env, check=True,
                   capture_output=True, timeout=300)
    subprocess.run(["pdftoppm", "-png", "-r", str(DPI), "-singlefile", str(out / (dxf.stem + ".pdf")),
                    str(out / dxf.stem)], check=True, capture_output=True, timeout=300)
    return out / (dxf.stem + ".png")


def crop_assembly(src: Path, dst: Path, *, centre: tuple[float, float], half_width: float, half_height: float) -> int:
    """The entities of ``src`` whose ends lie in the window, written to ``dst``; their count."""
    import ezdxf

    from profilegen.geometry.contour import Polyline
    from profilegen.output import cad

    cx, cy = centre

    def inside(p) -> bool:
        return abs(p[0] - cx) <= half_width and abs(p[1] - cy) <= half_height

    layers: dict[str, list] = {}
    for layer, elements in cad.read_dxf_contours(src).items():
        kept = [e for e in elements if inside(e.start) and inside(e.end)]
        if kept:
            layers[layer] = kept
    for pl in ezdxf.readfile(src).modelspace().query("LWPOLYLINE"):
        pts = np.array([(x, y) for x, y, *_ in pl.get_points()])
        sel = np.array([inside(p) for p in pts])
        if pl.closed and sel.any() and not sel.all():  # start the ring outside the window: runs stay whole
            shift = int(np.argmin(sel))
            pts, sel = np.roll(pts, -shift, axis=0), np.roll(sel, -shift)
        edges = np.flatnonzero(np.diff(np.concatenate([[0], sel.astype(int), [0]])))
        for a, b in zip(edges[::2], edges[1::2]):  # each run of points inside
            if b - a >= 2:
                layers.setdefault(pl.dxf.layer, []).append(Polyline(pts[a:b]))
    n = sum(len(v) for v in layers.values())
    note = [("annotation", (cx - half_width, cy - half_height - 0.2), 0.08,
             f"assembly.dxf, window {2 * half_width:g} x {2 * half_height:g} mm over the major axis: {n} entities")]
    cad.write_contours_dxf(dst, layers, texts=note)
    return n


def trim(img):
    """The image cut to its non-white content plus a margin."""
    a = np.asarray(img.convert("L"))
    ys, xs = np.nonzero(a < 250)
    m = 20
    return img.crop((max(xs.min() - m, 0), max(ys.min() - m, 0), min(xs.max() + m, a.shape[1]), min(ys.max() + m, a.shape[0])))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="design")
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[2] / "docs" / "flexspline_tooth.png"))
    args = ap.parse_args()

    from PIL import Image, ImageDraw, ImageFont

    import profilegen as pg

    gs = pg.load_gearset(pg.default_gearset_path())
    d = pg.design(gs, scene=args.scene, contact=False, stress=False)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        pg.write_design(d, work / "out", figure=False)
        tooth_png = librecad_png(work / "out" / "flexspline_tooth.dxf", work)
        r_top = gs.gear.neutral_radius_mm + d.deformation.evaluate(np.array([0.0]), order=0)[0][0][0]
        pitch = 2 * math.pi * gs.gear.pitch_radius_mm / gs.gear.flexspline_teeth
        crop = work / "assembly_crop.dxf"
        n = crop_assembly(work / "out" / "assembly.dxf", crop, centre=(0.0, r_top + 1.0),
                          half_width=3 * pitch, half_height=1.6)
        crop_png = librecad_png(crop, work)
        top, bottom = trim(Image.open(tooth_png).convert("RGB")), trim(Image.open(crop_png).convert("RGB"))
        width = 2400
        top = top.resize((round(top.width * 1300 / top.height), 1300))
        bottom = bottom.resize((width, round(bottom.height * width / bottom.width)))
        head = 40
        sheet = Image.new("RGB", (width, 2 * head + top.height + bottom.height), "white")
        sheet.paste(top, ((width - top.width) // 2, head))
        sheet.paste(bottom, (0, 2 * head + top.height))
        draw = ImageDraw.Draw(sheet)
        font = ImageFont.load_default(size=26)
        draw.text((10, 8), f"{gs.name}: flexspline_tooth.dxf, printed by LibreCAD (dxf2pdf, fitted to the page)",
                  fill="black", font=font)
        draw.text((10, head + top.height + 8), f"{gs.name}: assembly.dxf, its {n} entities in a window over the "
                  "wave generator's major axis (FS blue, CS red, WG bore green), printed by LibreCAD",
                  fill="black", font=font)
        sheet.save(args.out)
    print(args.out, sheet.size)


if __name__ == "__main__":
    main()
