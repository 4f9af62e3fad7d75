"""The design sheet (profilegen.output.sheet) and the interactive figure's data
(profilegen.output.interactive): what they say must follow from the geometry and the checks."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from profilegen.output import interactive, sheet


@pytest.fixture(scope="module")
def sketch(default_sketch):
    return default_sketch  # conftest.py: computed once per worker


@pytest.mark.parametrize("mm, text", [
    (2.220446049250313e-16, "touching (< 1 nm)"),  # was printed as "2.22e-10 nm"
    (-4e-7, "touching (< 1 nm)"),
    (1.87e-4, "0.187 µm"),
    (3.5070e-3, "3.51 µm"),
    (0.1234, "123 µm"),
    (-2.5e-4, "cuts in by 0.250 µm"),
])
def test_clearance_words(mm, text):
    assert sheet.format_clearance(mm) == text


def test_clearance_within_the_verdict_tolerance_says_so():
    assert sheet.format_clearance(-3e-6, tol_mm=1e-5).startswith("touching (−0.003 µm")
    assert sheet.format_clearance(-3e-5, tol_mm=1e-5) == "cuts in by 0.030 µm"


def test_um_digits():
    assert sheet.format_um(0.0035071) == "3.51 µm"
    assert sheet.format_um(1e-10) == "< 0.001 µm"
    assert sheet.format_um(None) == "—"
    assert sheet.format_um(float("nan")) == "—"


def test_flank_shape_follows_where_the_centre_lies(sketch):
    """'concave' exactly when the arc's centre lies on the tooth-space side of the flank
    (the fit's own signed distance, + on the space side), 'convex' when it lies in the CS tooth;
    the centres are at the stated radius from the arcs they belong to."""
    fit = sketch.profile.flank_fit
    arcs = [e for e in sheet.flank_elements(fit) if e.kind == "arc"]
    assert [e.label for e in arcs] == ["R1", "R2"]
    for el in arcs:
        side = float(fit.distance(np.array([el.centre_mm]))[0])
        assert abs(abs(side) - el.radius_mm) < 1e-9 or abs(side) < el.radius_mm  # on the arc's circle or nearer
        assert (el.shape == "concave") == (side > 0), (el, side)
    # and against the signed radii in the fit's parameters: the minus sign alone does not say which
    signs = [math.copysign(1, fit.params["r1_mm"]), math.copysign(1, fit.params["r2_mm"])]
    assert {(s, e.shape) for s, e in zip(signs, arcs)} in ({(-1.0, "convex"), (1.0, "concave")},
                                                           {(1.0, "convex"), (-1.0, "concave")})


def test_checks_match_the_verdict(sketch):
    from profilegen.pipeline.design import interference_tol_mm

    rows = sheet.checks(sketch, interference_tol_mm(sketch.scene))
    assert rows, "a sketch has at least the interference check"
    failed = [c for c in rows if c.passed is False]
    unchecked = [c for c in rows if c.passed is None]
    assert bool(failed) == sketch.verdict.failed
    assert len(unchecked) == len(sketch.verdict.not_checked) == len(sketch.verdict.skipped)
    # three outcomes: FAIL if a row failed, else INCOMPLETE if a row was not checked, else PASS
    assert sketch.verdict.status == ("FAIL" if failed else "INCOMPLETE" if unchecked else "PASS")
    assert sketch.verdict.passed == (sketch.verdict.status == "PASS")
    assert all(c.margin for c in unchecked)  # the reason, in the margin column


def test_sheet_text(sketch):
    html = sheet.sheet_html(sketch, interference_tol_mm=1e-5)
    text = re.sub(r"<[^>]+>", " ", html)
    assert sketch.verdict.line in text
    assert text.count(sketch.gearset.description) == 1
    for label in ("CS tip Ø", "CS root Ø", "R1", "R2", "CS root fillet", "smallest clearance", "backlash"):
        assert label in text, label
    root = next(f for f in sketch.profile.corners.fillets if f.where == "root right")  # wire EDM corners
    assert f"{root.radius_mm:.4f} mm" in text and "CS tip round" in text
    assert re.search(r"\d+\.\d{4} mm\s+convex", text) and re.search(r"\d+\.\d{4} mm\s+concave", text)
    assert "e-" not in re.sub(r"<style>.*?</style>", "", html, flags=re.S)  # no 2.22e-10 style numbers
    assert f"{2 * sketch.form.tip_radius_mm:.4f} mm" in text
    assert "not computed" in text  # the sketch scene runs no contact: no stiffness


def test_figure_keeps_sub_micron_detail(sketch):
    """The figure's data are plain SVG scatter traces whose fitted flank is sampled finer than
    0.5 µm and written to 1e-9 mm: a 1 µm window holds several vertices."""
    fig = interactive.flank_figure(sketch)
    assert {t["type"] for t in fig["data"]} == {"scatter"}
    space = next(t for t in fig["data"] if t["name"].startswith("CS space to cut"))
    xy = np.column_stack([space["x"], space["y"]])
    steps = np.hypot(*np.diff(xy, axis=0).T)
    arcs = steps[steps > 0]
    assert np.median(arcs) < 5e-4
    exact = sketch.profile.space.elements[0].sample(1e-8)
    assert np.max(np.abs(np.asarray(exact)[:5] - xy[:5])) <= 5e-10  # rounded to 1e-9 mm, not to float32
