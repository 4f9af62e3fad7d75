"""Face-stage warnings (issue 27, item 3): each by a case that triggers it and one that does not.

Built on one design of the default set (design scene: the face stage on a coarse 3D cup), calling
the face functions directly with modified inputs."""

from types import SimpleNamespace

import numpy as np
import pytest
import scipy.optimize

import profilegen as pg
from profilegen.contact.chain import compliance_chain
from profilegen.contact.compliance import ContactCompliance
from profilegen.contact.face_curve import FaceSlices
from profilegen.contact.inputs import ContactInput
from profilegen.contact.points import contact_points
from profilegen.face import modification
from profilegen.face.modification import apply_modification, solve_modification
from profilegen.face.stage import face_width


@pytest.fixture(scope="module")
def designed():
    gs = pg.load_gearset("default")
    d = pg.design(gs, scene="design", contact=False, stress=False)
    return gs, d


@pytest.fixture(scope="module")
def designed_on_the_rigid_band():
    """The default set with the bore pressed onto a rigid band (no outer race): there the face
    stage's LP reaches a taper and crowning (with the race, the cup cones about the ball row and
    the stage needs a radial shift, which the LP does not take)."""
    import profilegen.rim.cup.bearing as bearing

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(bearing, "CUP_TIER_RACE", "rigid")
        gs = pg.load_gearset("default")
        d = pg.design(gs, scene="design", contact=False, stress=False)
    return gs, d


def _still(warnings):
    return [w for w in warnings if "with the tooth modification the CS still interferes" in w]


def test_modification_still_interferes_warns(designed):
    # thickening the FS tooth toward the face ends (a negative crowning: Δs > 0 away from the design
    # section) pushes every non-design section's tooth into the one CS: it must interfere
    gs, d = designed
    mod = apply_modification(gs, d.rim.cup, d.face, 0.0, -0.1)
    assert mod.max_interference_mm > d.face.interference_tol_mm
    hits = _still(mod.warnings)
    assert len(hits) == 1 and "µm" in hits[0]


def test_modification_no_change_does_not_warn(designed):
    # the face stage's own computed modification, applied as given: interference-free
    gs, d = designed
    m = d.face.modification
    mod = apply_modification(gs, d.rim.cup, d.face, m.taper_mm_per_mm, m.crowning_mm, m.shift_mm_per_mm)
    assert mod.max_interference_mm <= d.face.interference_tol_mm
    assert not _still(mod.warnings)


def test_one_cs_profile_interferes_warns(designed):
    # the default set's unmodified FS teeth interfere with the one CS profile (max_interference_mm
    # above the tolerance): the face stage says so, naming the design section
    _, d = designed
    f = d.face
    assert f.max_interference_mm > f.interference_tol_mm
    hits = [w for w in f.warnings if w.startswith("the one CS profile (design section")]
    assert len(hits) == 1 and f"z = {f.design_section_z_mm:g} mm" in hits[0]


def test_no_section_interference_free_warns(designed):
    # the default set's every candidate CS interferes somewhere over the face: the face stage says so,
    # takes the section of deepest engagement (the most ω on the major axis) and names it and the least
    # interfering one
    _, d = designed
    f = d.face
    worst = f.candidate_min_gap_mm.min(axis=1)
    assert worst.max() < -f.interference_tol_mm  # the condition, from the candidates' own gap matrix
    deepest = int(np.argmax([s.omega_major_mm for s in f.sections]))
    assert f.design_index == deepest
    hits = [w for w in f.warnings if w.startswith("no computed section's CS is interference-free")]
    assert len(hits) == 1
    assert f"deepest engagement (z = {f.z_mm[deepest]:g} mm" in hits[0] and "µm" in hits[0]
    assert f"at z = {f.z_mm[int(np.argmax(worst))]:g} mm" in hits[0]


class _Uniform:
    """The cup's deformation at one section z0, the same at every z of its tooth ring: no coning, so
    every section's motion, swept region and CS are the same (the conjugate CS clears every section)."""

    def __init__(self, cup, z0):
        self.cup, self.z0 = cup, z0
        self.ring_span_mm = cup.geometry.ring_span_mm

    def omega(self, phi, z):
        return self.cup.omega(phi, self.z0)

    def upsilon(self, phi, z):
        return self.cup.upsilon(phi, self.z0)


def _points_set(gs):
    """The default set with a point-list tooth: a straight-flank trapezoid of the DCTA's proportions
    (pressure angle 10°, half thickness πm/4 at the pitch line, addendum 0.8 m, dedendum 1.2 m)."""
    m = gs.gear.module_mm
    y = np.linspace(-1.2 * m, 0.8 * m, 40)
    x = np.pi * m / 4 - y * np.tan(np.radians(10.0))
    data = gs.to_dict(include_defaults=False)
    data["tooth"] = {"kind": "points", "points": np.column_stack([x, y]).tolist()}
    data.pop("face", None)
    return pg.parse_gearset(data)


@pytest.fixture(scope="module")
def uniform_points_face(designed):
    """The face stage of a point-list tooth on a cup without coning (3 sections, coarse grids), with
    the modification asked for ("auto")."""
    gs, d = designed
    lo, hi = d.rim.cup.geometry.ring_span_mm
    return face_width(_points_set(gs), _Uniform(d.rim.cup, 0.5 * (lo + hi)), sections=3, modification="auto",
                      n_t=48, n_phi=121)


def test_a_point_list_tooth_gets_no_modification_and_says_why(uniform_points_face):
    f = uniform_points_face
    assert f.modification is None
    hits = [w for w in f.warnings if w.startswith("no tooth modification along the face")]
    assert len(hits) == 1 and "points tooth has no thickness field" in hits[0]


def test_a_dcta_tooth_gets_its_modification_without_that_warning(designed):
    _, d = designed
    assert d.face.modification is not None
    assert not [w for w in d.face.warnings if "no thickness field" in w]


def test_no_coning_no_interference_no_face_warning(uniform_points_face):
    # identical sections: the design section's conjugate CS clears them all (to the tolerance), so
    # neither 'no computed section ... interference-free' nor 'the one CS profile ... interferes'
    f = uniform_points_face
    assert f.candidate_min_gap_mm.min() >= -f.interference_tol_mm
    assert f.max_interference_mm <= f.interference_tol_mm
    assert not [w for w in f.warnings if "interference-free" in w or "interferes" in w]


def _failed_lp(*args, **kwargs):
    return SimpleNamespace(status=2, message="The problem is infeasible. (planted)", x=None)


def test_lp_failure_then_the_search_finds_a_step_warns_once(designed_on_the_rigid_band, monkeypatch):
    # the LP fails at once (no step): one warning, quoting the LP's message inside what the
    # regula-falsi search on the exact maps (not the LP) found — not a second note saying "the last
    # step is kept" of a step that was not kept (a new user read the two as contradicting)
    gs, d = designed_on_the_rigid_band
    monkeypatch.setattr(scipy.optimize, "linprog", _failed_lp)
    mod = solve_modification(gs, d.rim.cup, d.face)
    assert not [w for w in mod.warnings if "the last step is kept" in w or "step before it is kept" in w]
    found = [w for w in mod.warnings if "found no interference-free step (the LP failed at step 1" in w]
    assert len(found) == 1 and "regula falsi" in found[0] and "(planted)" in found[0]
    assert mod.max_interference_mm <= d.face.interference_tol_mm  # what the search promises


def test_lp_failure_and_no_search_step_warns_still_interfering(designed, monkeypatch):
    gs, d = designed
    monkeypatch.setattr(scipy.optimize, "linprog", _failed_lp)
    monkeypatch.setattr(modification, "_search_on_maps", lambda *a, **k: None)
    mod = solve_modification(gs, d.rim.cup, d.face)
    hits = [w for w in mod.warnings if w.startswith("tooth modification: still interfering after 0 LP steps")]
    assert len(hits) == 1 and "taper and crowning" in hits[0] and "the LP failed at step 1" in hits[0]
    assert mod.taper_mm_per_mm == 0.0 and mod.crowning_mm == 0.0  # nothing found: the straight tooth


def test_lp_that_solves_warns_of_nothing(designed_on_the_rigid_band):
    # the default set's own face stage on the rigid band: the LP's steps reach an interference-free
    # modification
    _, d = designed_on_the_rigid_band
    mod = d.face.modification
    assert mod.source == "computed" and mod.iterations >= 1
    assert mod.max_interference_mm <= d.face.interference_tol_mm
    assert not [w for w in mod.warnings if w.startswith("tooth modification:")]


# --------------------------------------------------------------------------- face_curve's flank overlap


def _hand_compliance(pts, b):
    """A diagonal compliance (1e-6 mm/N per point) and one far, inactive ball: the warning reads the
    gaps only, the compliance has to be of the right shape."""
    n = pts.count
    m = 1e-6 * np.eye(n)
    return ContactCompliance(
        matrix_mm_per_n=m, fs_matrix_mm_per_n=m, cs_matrix_mm_per_n=np.zeros((n, n)), face_width_mm=b,
        tooth=np.asarray(pts.tooth), ball_angle_rad=np.array([1.0]), ball_active=np.array([False]),
        wrap_half_angle_rad=0.5, wrap_source="test", dof={}, time_s={}, mesh={}, _flex_cc=m * b,
        _flex_cb=np.zeros((n, 1)), _flex_bb=np.array([[1.0]]), ball_supports="all", ball_gap_mm=np.array([1.0]))


@pytest.fixture(scope="module")
def flanks(designed):
    gs, d = designed
    b = float(gs.cup.face_width_mm)
    sides, inputs = {}, ContactInput.from_design(d)
    for s in (1, -1):
        pts = contact_points(inputs, side=s, stations=2)
        sides[s] = (pts, _hand_compliance(pts, b))
    return d, sides, compliance_chain(gs)


@pytest.mark.parametrize("taper, warns", [(2e-3, True), (-2e-3, False)])
def test_flanks_overlap_when_the_tooth_thickens_along_the_face(flanks, taper, warns):
    # no coning; the CS conjugate to the slice at the diaphragm end of the face, where both flanks
    # touch at no load (gaps ≥ 0, ~1e-11 mm): a taper thickening the tooth toward the open end (Δs > 0)
    # closes both flanks' gaps there, so they overlap; thinning it (Δs < 0) opens them
    d, sides, chain = flanks
    cup = d.gearset.cup
    spec = FaceSlices(3, "none", design_z_mm=cup.length_mm - 0.5 * cup.face_width_mm, modification=(taper, 0.0))
    _, _, warnings = spec.apply(d, sides, chain)
    hits = [w for w in warnings if "the two flanks overlap at no load" in w]
    assert len(hits) == int(warns)
    if warns:
        # the slices' mid-planes are b/6, b/2, 5b/6 from z_d: all three thicker, most the last
        assert "3 slices, none coning" in hits[0] and "in 3 slice(s)" in hits[0]
        assert f"most at z = {cup.length_mm + cup.face_width_mm / 3:.4g} mm" in hits[0]


@pytest.mark.parametrize("shift, warns", [(2e-3, True), (-2e-3, False)])
def test_flanks_overlap_when_the_tooth_moves_out_along_the_face(flanks, shift, warns):
    # the face stage's radial shift in the slices (contact.face_curve): no coning, the CS conjugate to the
    # diaphragm end's slice; the whole tooth moved away from the gear centre toward the open end (Δy > 0)
    # goes deeper into the space, whose flanks close in toward its root: both flanks' gaps close and they
    # overlap; moved toward the centre (Δy < 0) the tooth leaves the space and both gaps open
    d, sides, chain = flanks
    cup = d.gearset.cup
    mod = SimpleNamespace(taper_mm_per_mm=0.0, crowning_mm=0.0, shift_mm_per_mm=shift)
    spec = FaceSlices(3, "none", design_z_mm=cup.length_mm - 0.5 * cup.face_width_mm, modification=mod)
    _, _, warnings = spec.apply(d, sides, chain)
    hits = [w for w in warnings if "the two flanks overlap at no load" in w]
    assert len(hits) == int(warns)
    if warns:
        assert "in 3 slice(s)" in hits[0]
        assert f"most at z = {cup.length_mm + cup.face_width_mm / 3:.4g} mm" in hits[0]
