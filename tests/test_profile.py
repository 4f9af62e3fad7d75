"""The manufacturable CS profile through the pipeline: fits, closure, the FS check, ridges."""

from __future__ import annotations

import numpy as np
import pytest

import profilegen as pg


# on the worker of test_bench_stages.py (its xdist group): the three modules read the design scene of
# the default set (conftest.py: default_design_scene, 3.6 s CPU), computed there once
pytestmark = pytest.mark.xdist_group("bench_stages")


@pytest.fixture(scope="module")
def default_design(default_design_scene):
    return default_design_scene  # conftest.py: computed once per worker


class _DenseTooth:
    """The FS tooth with its outline and surface sampled 4 x as densely as asked."""

    def __init__(self, tooth):
        self._tooth = tooth

    def __getattr__(self, name):
        return getattr(self._tooth, name)

    def outline(self, n_per_mm=400.0):
        return self._tooth.outline(n_per_mm=4.0 * n_per_mm)

    def surface(self, n_per_mm=400.0):
        return self._tooth.surface(n_per_mm=4.0 * n_per_mm)


def test_default_profile_is_one_sided_and_closed(default_design):
    p = default_design.profile
    assert p.method == "one_sided"
    # one-sided = minimax moved by its error: backlash exactly twice the minimax deviation
    assert p.flank_fit.max_backlash_mm == pytest.approx(2 * p.fits["minimax"].max_error_mm, rel=1e-6)
    assert p.fits["minimax"].max_error_mm <= p.fits["least_squares"].max_error_mm
    assert p.outline.gaps(closed=True).max() <= 1e-9
    assert p.clearance.min_mm >= -default_design.envelope.chord_tol_mm
    # the sign-off check: 2001 FS tooth poses over one pass, exact near contact
    from profilegen.geometry.contour import Chain
    from profilegen.profile.gearform import clearance_map

    n_unit = len(p.space.elements) + 1
    local = Chain(p.outline.elements[-n_unit:] + p.outline.elements[: 2 * n_unit]).sample(1e-7)
    d = default_design
    # the FS tooth's surface at 4 x the map's 400 points/mm: at 400/mm its chords on the 0.65-0.7 mm
    # arcs sag by (1/400)^2/(8 r) = 1.1-1.2 nm, more than the 1 nm chord checked here (the design
    # scene's cup section read -1.048 nm at 400/mm, -0.024 nm at 1600/mm; issue 28)
    fine = clearance_map(d.form, _DenseTooth(d.tooth), d.motion, phi_range=d.envelope.phi_range, samples=2001,
                         cs_points=local)
    assert fine.min_mm >= -d.envelope.chord_tol_mm
    # the mirror image is the left flank: the space is symmetric about its axis
    np.testing.assert_allclose(p.space.start * [-1, 1], p.space.end, atol=1e-9)


def test_fit_method_override(default_design):
    gs = pg.load_gearset(pg.default_gearset_path())
    r = pg.design(gs, scene="sketch", fit_method="least_squares")
    assert r.profile.method == "least_squares"
    with pytest.raises(pg.GearSetError, match="fit method"):
        pg.design(gs, scene="sketch", fit_method="best")


def test_flank_with_a_ridge_is_fitted_per_branch():
    """An involute FS tooth gives a CS flank with a 12° branch-switch ridge: one composite per
    branch follows it to well under a micrometre, one composite over the kink cannot."""
    d = pg.load_gearset(pg.default_gearset_path()).to_dict()
    d["tooth"] = {"kind": "involute", "pressure_angle_deg": 20.0}
    # sharp corners: the branch fits meet at the ridge through a 26 nm line and one has a 15 µm
    # concave arc (sketch scene) — no wire cuts that: filleted, it is a FilletError
    d["circular_spline"] = {"corners": "sharp"}
    # the 2D ring FEM's section (issue 28: on the design scene's coarse-cup section at z = 70 mm the
    # minimax SLP of a branch does not converge in 200 iterations, 17 µm; left to the arc fit)
    from dataclasses import replace

    from profilegen.face.coning import RING_FEM_LABEL

    r = pg.design(pg.parse_gearset(d), scene=replace(pg.SCENES["design"], rim=RING_FEM_LABEL))
    assert any(rr.kink_deg > 5 for rr in r.envelope.ridges)
    p = r.profile
    assert p.branches is not None and len(p.branches.fits) == 2
    assert max(f.max_error_mm for f in p.branches.fits) < 1e-4 < p.fits["one_sided"].max_error_mm
    assert p.outline.gaps(closed=True).max() <= 1e-9
    assert p.clearance.min_mm >= -1e-6


def test_outline_has_no_overlaps_and_files_are_deterministic(default_design, tmp_path):
    """The closed chain bounds a simple polygon (no overlaps, no self-contact), and the same
    design writes byte-identical DXF and SVG files."""
    import shapely

    ring = shapely.LinearRing(default_design.profile.outline.sample(1e-4))
    assert ring.is_simple and shapely.Polygon(ring).is_valid
    a = pg.write_design(default_design, tmp_path / "a", figure=False)
    b = pg.write_design(default_design, tmp_path / "b", figure=False)
    for name in ("circular_spline.dxf", "tooth_space.dxf", "assembly.dxf", "circular_spline.svg"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name
    assert [p.name for p in a] == [p.name for p in b]
