"""The face stage on a cup that cones about the wave generator's ball row (the race free to tilt,
``BearingRace`` "ring"): the design section of deepest engagement and the FS tooth's radial shift
along the face (issue 28, build item 4). One coarse cup (4 mm, 8 angles: the design scene's) and
three sections on coarse envelope grids, shared by the tests."""

import numpy as np
import pytest

import profilegen as pg
from profilegen.face import face_width
from profilegen.face.modification import apply_modification, modified_tooth, radial_shift
from profilegen.face.sections import solve_section
from profilegen.rim.cup import CupGeometry, press_cup
from profilegen.rim.cup.bearing import cup_tier_race
from profilegen.geometry.teeth import tooth_from_gearset
from profilegen.geometry.wavegen import from_gearset

GRID = dict(n_t=48, n_phi=121)


@pytest.fixture(scope="module")
def ring_face():
    gs = pg.load_gearset("seed000_csf40")
    g = CupGeometry.from_gearset(gs)
    cup = press_cup(g, contour=from_gearset(gs), angles=8, element_mm=4.0, layers=2, gap="exact", nonlinear=True,
                    race=cup_tier_race(gs, g, "ring"))
    return gs, cup, face_width(gs, cup, sections=3, modification="auto", **GRID)


def test_a_shifted_tooth_is_the_tooth_moved_radially():
    # a profile shift moves the whole tooth, root lands included, by Δy along the tooth axis
    gs = pg.load_gearset("seed000_csf40")
    plain = tooth_from_gearset(gs)
    for dy in (-0.1, 0.05):
        moved = modified_tooth(gs, 0.0, dy)
        np.testing.assert_allclose(moved.surface(n_per_mm=200.0), plain.surface(n_per_mm=200.0) + [0.0, dy],
                                   atol=1e-9)
        assert moved.addendum_y_mm == pytest.approx(plain.addendum_y_mm + dy, abs=1e-12)
        assert moved.dedendum_y_mm == pytest.approx(plain.dedendum_y_mm + dy, abs=1e-12)


def test_the_design_section_is_the_deepest_when_none_is_interference_free(ring_face):
    _, _, f = ring_face
    assert f.candidate_min_gap_mm.min(axis=1).max() < -f.interference_tol_mm  # the condition
    deepest = int(np.argmax([s.omega_major_mm for s in f.sections]))
    assert f.design_index == deepest
    # the cone about the ball row: the open end deflects most
    assert f.sections[-1].omega_major_mm > f.sections[0].omega_major_mm


def test_the_shift_clears_every_section_on_its_own_swept_region(ring_face):
    # independent of the clearance maps the stage searched on: each modified section's envelope traced
    # anew, the one CS's space against its swept region (the signed gap)
    gs, cup, f = ring_face
    mod = f.modification
    assert mod.shift_mm_per_mm != 0.0 and abs(mod.taper_mm_per_mm) < 1e-12 and abs(mod.crowning_mm) < 1e-12
    dy = radial_shift(f.z_mm, shift_mm_per_mm=mod.shift_mm_per_mm, design_z_mm=f.design_section_z_mm)
    np.testing.assert_allclose(mod.radial_shift_mm, dy, atol=1e-15)
    # the sections that deflect less than the design section are moved toward the gear centre
    others = np.arange(len(f.sections)) != f.design_index
    assert np.all(dy[others] < 0.0)
    for k, s in enumerate(f.sections):
        sec = solve_section(gs, cup.deformation, s.z_mm, modified_tooth(gs, 0.0, float(dy[k])), chord_tol_mm=f.chord_tol_mm,
                            fit=s.fit, **GRID)
        gap = float(np.min(pg.face.signed_gap(f.form.space, sec.boundary)))
        assert gap >= -(f.interference_tol_mm + 2e-5), (s.z_mm, gap)
    # and without the shift the same sections interfere (the shift is what clears them)
    straight = apply_modification(gs, cup, f, 0.0, 0.0)
    assert straight.max_interference_mm > 10 * f.interference_tol_mm
    given = apply_modification(gs, cup, f, 0.0, 0.0, mod.shift_mm_per_mm)
    assert given.max_interference_mm <= f.interference_tol_mm


def test_a_shift_out_of_range_names_the_field(ring_face):
    gs, cup, f = ring_face
    with pytest.raises(pg.face.FaceError, match="shift_mm_per_mm"):
        apply_modification(gs, cup, f, 0.0, 0.0, 0.5)


def test_the_drawings_say_the_shift_and_its_range(ring_face):
    # the notes of the FS drawings (face.coning.modification_lines): the shift per mm and Δy at the
    # face ends, shift · (z − z_d) at the diaphragm end and 0 at the design section (the open end)
    from types import SimpleNamespace

    from profilegen.face.coning import modification_lines

    _, _, f = ring_face
    lines = modification_lines(SimpleNamespace(face=f))
    shifted = [line for line in lines if line.startswith("FS teeth SHIFTED radially")]
    assert len(shifted) == 1
    shift = f.modification.shift_mm_per_mm
    end = shift * (f.z_mm[0] - f.design_section_z_mm) * 1e3
    assert f"{shift * 1e3:.4g} um per mm" in shifted[0] and f"from {end:.3g} to 0 um" in shifted[0]
    assert not [line for line in lines if line.startswith("FS teeth MODIFIED")]  # no thickness change here
