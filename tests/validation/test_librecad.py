"""Validation of profilegen.output.cad's DXF against an independent CAD program: LibreCAD.

Source: LibreCAD 2.2 (Debian package ``librecad``), whose DXF reader is libdxfrw — no
ezdxf code involved. Its command line prints a DXF to PDF,
``librecad dxf2pdf [-a] [-c] [-s SCALE] -t OUTDIR FILE.dxf`` → ``OUTDIR/FILE.pdf``,
headless with ``QT_QPA_PLATFORM=offscreen``; poppler's ``pdftoppm -png -r 100``
rasterises the page. Install both (Debian 12: LibreCAD 2.2.0, poppler 22.12; ~14 s
with a warm apt cache, 33.5 MB to download, 199 MB on disk) with

    apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y librecad poppler-utils

What is checked:

* the golden toy gear (``tests/golden/toy_gear.dxf``: 60 ARCs — 12 of them clockwise
  in the contour, stored counter-clockwise —, 26 LINEs, 2 CIRCLEs, 1 TEXT) prints,
  fitted to the page, with dark pixels and red (CS layer) pixels on a white page;
* units: printed at scale 1:1 (``-s 1``), the 22 mm construction cross is 22 mm long
  on paper (LibreCAD reads ``$INSUNITS = 4``; with ``$INSUNITS = 1`` it would lay
  the same numbers out in inches);
* a real circular spline: five tooth spaces of the default gear set's CS (sketch scene),
  each flank replaced by three arcs through its polyline, root and tip lands as arcs
  about the gear centre, written by ``write_contours_dxf``, prints with red pixels;
* the dimensioned drawing (``circular_spline_drawing.dxf``, profilegen.output.drawing),
  printed at scale 1 (``-c -s 1``): the A3 sheet fills the A3 page (nothing, e.g. a
  dimension line to a far centre, lies outside it), the ring view's red outer circle is
  the blank's diameter in mm on paper (the view is 1:1), detail A's red profile one
  pitch × 50 wide (its scale, 50:1).

Skipped with the reason when LibreCAD or pdftoppm is missing. LibreCAD keeps its
settings under ``$HOME/.config``; HOME points into tmp_path so nothing outside is touched.
"""

from __future__ import annotations

import math
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from profilegen.output.cad import chain_gaps, read_dxf_contours, write_contours_dxf
from profilegen.geometry.contour import Arc, Chain

GOLDEN = Path(__file__).resolve().parents[1] / "golden" / "toy_gear.dxf"
DPI = 100

pytestmark = [
    pytest.mark.skipif(shutil.which("librecad") is None,
                       reason="LibreCAD is not installed (apt-get install -y librecad poppler-utils)"),
    pytest.mark.skipif(shutil.which("pdftoppm") is None,
                       reason="pdftoppm is not installed (apt-get install -y poppler-utils)"),
]


def _librecad_png(dxf: Path, work: Path, *options: str) -> np.ndarray:
    """Print ``dxf`` with LibreCAD to PDF, rasterise the page at DPI, return it as RGB floats in [0, 1]."""
    import matplotlib.image

    out = work / "pdf"
    out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen", HOME=str(work),
               XDG_CONFIG_HOME=str(work / ".config"), XDG_RUNTIME_DIR=str(work / "run"))
    (work / "run").mkdir(mode=0o700, exist_ok=True)
    run = subprocess.run(["librecad", "dxf2pdf", *options, "-t", str(out), str(dxf)],
                         env=env, capture_output=True, text=True, timeout=120)
    pdf = out / (dxf.stem + ".pdf")
    assert run.returncode == 0 and pdf.exists(), f"librecad failed ({run.returncode}):\n{run.stdout}\n{run.stderr}"
    assert pdf.stat().st_size > 2000, f"{pdf} is only {pdf.stat().st_size} bytes"
    subprocess.run(["pdftoppm", "-png", "-r", str(DPI), "-singlefile", str(pdf), str(out / dxf.stem)],
                   check=True, capture_output=True, timeout=120)
    img = matplotlib.image.imread(out / (dxf.stem + ".png"))
    return img[..., :3].astype(float)


def _dark(img):
    return img.min(axis=-1) < 0.6


def _red(img):
    return (img[..., 0] > 0.6) & (img[..., 1] < 0.4) & (img[..., 2] < 0.4)


def test_toy_gear_prints_fitted(tmp_path):
    img = _librecad_png(GOLDEN, tmp_path, "-a")
    h, w = img.shape[:2]
    assert (w, h) == pytest.approx((420 / 25.4 * DPI, 297 / 25.4 * DPI), abs=2)  # A3 landscape
    assert np.median(img) > 0.99  # a white page ...
    assert _dark(img).sum() > 2000 and _red(img).sum() > 1000  # ... with the drawing, the CS in red
    ys, xs = np.nonzero(_red(img))
    # fitted and centred: the gear's red outline is round (as wide as high) and mid-page
    assert (xs.max() - xs.min()) == pytest.approx(ys.max() - ys.min(), rel=0.03)
    assert (xs.max() + xs.min()) / 2 == pytest.approx(w / 2, rel=0.02)


def test_toy_gear_prints_at_scale_one_in_mm(tmp_path):
    img = _librecad_png(GOLDEN, tmp_path, "-c", "-s", "1")
    ys, xs = np.nonzero(_dark(img))
    rows = np.bincount(ys)
    axis_row = int(np.argmax(rows))  # the horizontal construction line, −11 … 11 mm
    cols = np.nonzero(_dark(img)[axis_row])[0]
    length_mm = (cols.max() - cols.min() + 1) / DPI * 25.4
    assert length_mm == pytest.approx(22.0, abs=0.6)  # ± 2 px at 100 dpi


# ----------------------------------------------------------------------------- a real CS


def real_cs_sector(spaces: int = 5):
    """Five spaces of the default gear set's fitted CS outline (sketch scene: one-sided
    arc–line–arc flanks, transition lines, root and tip arcs), and the circles' arcs."""
    from profilegen.gearset import default_gearset_path, load_gearset
    from profilegen.pipeline.design import design

    result = design(load_gearset(default_gearset_path()), scene="sketch")
    form, prof = result.form, result.profile
    n_unit = len(prof.space.elements) + 1  # a space and the tip land after it
    half = spaces // 2
    elements = prof.outline.elements[-half * n_unit :] + prof.outline.elements[: (spaces - half) * n_unit - 1]
    span = (half + 1) * 2 * math.pi / form.cs_teeth
    circles = [Arc((0, 0), r, math.pi / 2 - span, 2 * span) for r in (form.tip_radius_mm, form.root_radius_mm)]
    return Chain(tuple(elements)), circles, form


def test_real_cs_sector_prints(tmp_path):
    chain, circles, form = real_cs_sector()
    assert chain.gaps().max() <= 1e-9
    dxf = tmp_path / "cs_sector.dxf"
    write_contours_dxf(dxf, {"CS": [chain], "construction": circles},
                       texts=[("annotation", (-3.0, form.tip_radius_mm - 1.0), 0.25, "default CS, 5 spaces, arcs")])
    back = read_dxf_contours(dxf)["CS"]
    assert len(back) == len(chain.elements) and chain_gaps(back).max() <= 1e-9
    img = _librecad_png(dxf, tmp_path, "-a")
    assert np.median(img) > 0.99 and _red(img).sum() > 1000


def test_cs_drawing_prints_at_its_scales(tmp_path):
    from profilegen.gearset import default_gearset_path, load_gearset
    from profilegen.output.drawing import write_cs_drawing
    from profilegen.pipeline.design import design

    result = design(load_gearset(default_gearset_path()), scene="sketch", contact=False, stress=False)
    form = result.form
    dxf = tmp_path / "circular_spline_drawing.dxf"
    write_cs_drawing(dxf, result, date="2026-01-31")
    img = _librecad_png(dxf, tmp_path, "-c", "-s", "1")
    mm = 25.4 / DPI
    ys, xs = np.nonzero(_dark(img))
    assert (xs.max() - xs.min()) * mm == pytest.approx(420.0, abs=2.0)  # the whole A3 sheet, on the page
    assert (ys.max() - ys.min()) * mm == pytest.approx(297.0, abs=2.0)
    ys, xs = np.nonzero(_red(img))
    ring = xs < 0.55 * img.shape[1]
    assert (xs[ring].max() - xs[ring].min() + 1) * mm == pytest.approx(2 * form.outer_radius_mm, abs=0.8)
    assert (ys[ring].max() - ys[ring].min() + 1) * mm == pytest.approx(2 * form.outer_radius_mm, abs=0.8)
    pitch_chord = 2 * form.tip_radius_mm * math.sin(math.pi / form.cs_teeth)  # the space and two half lands
    assert (xs[~ring].max() - xs[~ring].min() + 1) * mm == pytest.approx(50 * pitch_chord, abs=0.8)
