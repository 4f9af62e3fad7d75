"""The compliance model's cache across wave-generator positions, and every ball a one-sided
support at its no-load gap (``ball_supports="all"``, profilegen.contact.compliance).

Checks against things the code does not compute for itself: a cached build against a fresh
one (bit for bit); the extended complementarity problem (teeth and balls) against the
equilibrium of the whole gear and the contact conditions of every tooth point and every ball,
recomputed here from the raw flexibility blocks; the same problem solved a second way (the
final ball set's Schur complement, the balls' gaps as tooth-gap offsets, by the package's
tooth solver); the limit cases — balls far from the rim are never loaded (then the
window's answer), and more supports can only stiffen the mesh. Default set, sketch design,
ψ = 0 and one shifted position.
"""

import math

import numpy as np
import pytest

import profilegen as pg
from profilegen.contact import ContactInput, contact_points
from profilegen.contact import compliance as cm

WRAP = 1.0  # rad: the window, given (the sketch design has no rim FEM; no flat-ring solve here)


@pytest.fixture(scope="module")
def inputs():
    return ContactInput.from_design(pg.design(pg.load_gearset(pg.default_gearset_path()), scene="sketch",
                                              contact=False, stress=False))


def _build(inputs, pts, shift=0.0, **kw):
    return cm.ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                      wrap_half_angle_rad=WRAP, shift_rad=shift, **kw)


def test_cached_build_is_bitwise_a_fresh_build(inputs):
    """The meshed and condensed pitches are reused across positions: the matrices of a build
    after another position's are those of a build from nothing, bit for bit."""
    shift = -0.4 * 2.0 * math.pi / inputs.gearset.gear.flexspline_teeth
    pts0 = contact_points(inputs)
    pts1 = contact_points(inputs, shift_rad=shift)
    cm.clear_cache()
    _build(inputs, pts0)
    assert len(cm._CACHE) == 2  # one FS entry, one CS entry
    warm = _build(inputs, pts1, shift)
    cm.clear_cache()
    cold = _build(inputs, pts1, shift)
    for name in ("matrix_mm_per_n", "fs_matrix_mm_per_n", "cs_matrix_mm_per_n", "_flex_cb", "_flex_bb"):
        assert np.array_equal(getattr(warm, name), getattr(cold, name)), name
    # and the cache is keyed on the mesh: another mesh is a new entry, not the old one reused
    other = _build(inputs, pts1, shift, mesh={"per_pitch": 16})
    assert not np.allclose(other.fs_matrix_mm_per_n, cold.fs_matrix_mm_per_n, rtol=1e-6, atol=0.0)


@pytest.fixture(scope="module")
def zone(inputs):
    """ψ = 0, right flanks: the points, the 'all' compliance and the rated torque's solution."""
    pts = contact_points(inputs)
    comp = _build(inputs, pts, ball_supports="all")
    torque_nmm = inputs.gearset.torque.rated_nm / pts.zones * 1e3
    sol, reaction, gap_after = comp.solve_unilateral(pts.theta_rad, pts.lever_mm, torque_nmm)
    return pts, comp, torque_nmm, sol, reaction, gap_after


def _blocks(comp):
    b = comp.face_width_mm
    s_cc = 0.5 * (comp._flex_cc + comp._flex_cc.T) / b + comp.cs_matrix_mm_per_n
    return s_cc, comp._flex_cb / b, comp._flex_bb / b


def test_all_balls_equilibrium_and_complementarity(zone):
    """Teeth and balls: F ≥ 0, R ≥ 0, every tooth gap and ball gap after load ≥ 0 and zero
    where loaded, recomputed here from the raw blocks; U Σ r F = T."""
    pts, comp, torque_nmm, sol, reaction, gap_after = zone
    s_cc, c_cb, c_bb = _blocks(comp)
    f, phi = sol.force_n, sol.phi_rad
    # the zone's balls: |θ| < π/2, the ones within the window at zero gap, the others at theirs (≥ 0)
    assert np.all(np.abs(comp.ball_angle_rad) < 0.5 * math.pi)
    assert comp.ball_angle_rad.size > np.count_nonzero(np.abs(comp.ball_angle_rad) <= WRAP)
    assert np.all(comp.ball_gap_mm[np.abs(comp.ball_angle_rad) <= WRAP] == 0.0) and np.all(comp.ball_gap_mm >= 0.0)
    g = pts.lever_mm * (pts.theta_rad - phi) + s_cc @ f + c_cb @ reaction
    h = comp.ball_gap_mm + c_cb.T @ f + c_bb @ reaction
    scale_g = float(np.max(np.abs(s_cc @ f)))
    assert float(pts.lever_mm @ f) == pytest.approx(torque_nmm, rel=1e-12)
    assert np.all(f >= 0.0) and np.all(reaction >= 0.0)
    assert g.min() >= -1e-9 * scale_g and h.min() >= -1e-9 * scale_g
    assert np.max(np.abs(f * g)) <= 1e-9 * scale_g * f.max()
    assert np.max(np.abs(reaction * h)) <= 1e-9 * scale_g * reaction.max()
    np.testing.assert_allclose(g, sol.gap_mm, atol=1e-9 * scale_g)
    np.testing.assert_allclose(h, gap_after, atol=1e-9 * scale_g)
    # a real problem for the balls: some loaded outside the window, some not loaded at all
    outside = np.abs(comp.ball_angle_rad) > WRAP
    assert np.any(reaction[outside] > 0.0) and np.any(reaction == 0.0)
    assert sol.complementarity_residual < 1e-12 and sol.equilibrium_residual < 1e-12


def test_all_balls_against_the_tooth_solver_on_the_final_ball_set(zone):
    """Solved a second way: the loaded balls A held at their gaps (a Schur complement of the
    rim's flexibility, the gaps as offsets −C_cA C_AA⁻¹ g_A of the tooth gaps) and the teeth by
    the package's tooth solver (Lemke on the reduced problem): the same forces and rotation."""
    from profilegen.contact.solvers import solve_lemke

    pts, comp, torque_nmm, sol, reaction, _ = zone
    s_cc, c_cb, c_bb = _blocks(comp)
    a = np.flatnonzero(reaction > 0.0)
    inv = np.linalg.solve(c_bb[np.ix_(a, a)], np.column_stack([c_cb[:, a].T, comp.ball_gap_mm[a]]))
    s_red = s_cc - c_cb[:, a] @ inv[:, :-1]
    theta = pts.theta_rad + (-c_cb[:, a] @ inv[:, -1]) / pts.lever_mm
    shift = float(theta.min())
    ref = solve_lemke(s_red, theta - shift, pts.lever_mm, torque_nmm)
    assert ref.phi_rad + shift == pytest.approx(sol.phi_rad, rel=1e-9)
    np.testing.assert_allclose(ref.force_n, sol.force_n, rtol=0, atol=1e-8 * sol.force_n.max())
    # and the ball reactions that hold the balls at their gaps: R_A = −C_AA⁻¹ (C_Ac F + g_A)
    r_a = -np.linalg.solve(c_bb[np.ix_(a, a)], c_cb[:, a].T @ ref.force_n + comp.ball_gap_mm[a])
    np.testing.assert_allclose(r_a, reaction[a], rtol=0, atol=1e-8 * reaction.max())


def test_all_balls_far_away_is_the_window(inputs, zone):
    """Limit case: with the balls outside the window pushed 1 mm away they never touch, and the
    answer is the window model's (rigid balls, settled by solve_contact), built separately."""
    import dataclasses

    from profilegen.contact.analysis import solve_contact

    pts, comp, torque_nmm, sol, reaction, _ = zone
    far = dataclasses.replace(comp, ball_gap_mm=np.where(np.abs(comp.ball_angle_rad) <= WRAP, 0.0, 1.0))
    alone, r_far, _ = far.solve_unilateral(pts.theta_rad, pts.lever_mm, torque_nmm)
    window = solve_contact(inputs, [2e-3 * torque_nmm], points=pts, compliance=_build(inputs, pts)).cases[0]
    assert np.all(r_far[np.abs(comp.ball_angle_rad) > WRAP] == 0.0)
    assert alone.phi_rad == pytest.approx(window.rotation_rad, rel=1e-8)
    np.testing.assert_allclose(alone.force_n, window.solution.force_n, rtol=0, atol=1e-7 * alone.force_n.max())
    # the physical choice: the balls the window leaves out carry load and stiffen the mesh
    assert sol.phi_rad < alone.phi_rad


def test_ball_supports_bad_input(inputs, zone):
    from profilegen.contact.transmission import TransmissionErrorError, transmission_error

    pts, comp, torque_nmm, sol, _, _ = zone
    with pytest.raises(cm.ComplianceError, match="ball_supports"):
        _build(inputs, pts, ball_supports="some")
    with pytest.raises(TransmissionErrorError, match="ball_supports"):
        transmission_error(inputs, 100.0, positions=2, options={"ball_supports": "some"})
    with pytest.raises(TransmissionErrorError, match="hertz_balls"):
        transmission_error(inputs, 100.0, positions=2, options={"hertz_balls": True, "ball_supports": "window"})
    with pytest.raises(cm.ComplianceError, match="solve_unilateral"):
        comp.settle_balls(sol.force_n)


def test_all_balls_with_hertz_springs_is_the_hertz_law(inputs, zone):
    """With the bearing's Hertz balls: at the fixed point every loaded ball's spring is
    compressed by the Hertz approach δ(R) = c_H R^{2/3} of its own reaction (the law, not its
    linearisation), the contact conditions hold with the springs, and the softer balls turn
    the FS further than rigid ones."""
    from profilegen.contact.chain import BallBearing

    pts, comp, torque_nmm, rigid, _, _ = zone
    bearing = BallBearing.from_gearset(inputs.gearset)
    sol, reaction, gap_after = comp.solve_unilateral(pts.theta_rad, pts.lever_mm, torque_nmm, bearing=bearing)
    springs = np.asarray(sol.diagnostics["ball_compliance_mm_per_n"])
    on = reaction > 0.0
    assert on.sum() >= 2
    np.testing.assert_allclose(springs[on] * reaction[on], bearing.approach_mm(reaction[on]), rtol=1e-5)
    s_cc, c_cb, c_bb = _blocks(comp)
    h = comp.ball_gap_mm + c_cb.T @ sol.force_n + (c_bb + np.diag(springs)) @ reaction
    scale = float(np.max(np.abs(s_cc @ sol.force_n)))
    assert h.min() >= -1e-9 * scale and np.max(np.abs(reaction * h)) <= 1e-9 * scale * reaction.max()
    np.testing.assert_allclose(h, gap_after, atol=1e-9 * scale)
    assert sol.phi_rad > rigid.phi_rad


# --------------------------------------------------------------------------- the torsional curve with every ball


@pytest.fixture(scope="module")
def flanks(inputs, zone):
    """Both flanks with every ball one-sided: the right flank of ``zone``, the left built."""
    left = contact_points(inputs, side=-1)
    return {1: (zone[0], zone[1]), -1: (left, _build(inputs, left, ball_supports="all"))}


CURVE_TORQUES = [-660.0, -265.0, -54.0, -8.0, 8.0, 54.0, 265.0, 660.0]


def test_curve_continuation_keeps_teeth_and_balls_complementary(inputs, flanks):
    """The continuation solver along the curve (|T| ascending, each from the previous state,
    Hertz springs): at every torque, recomputed here from the raw flexibility blocks with the
    springs it converged to — U Σ r F = T; teeth F ≥ 0, g ≥ 0, F g = 0; balls R ≥ 0, h ≥ 0,
    R h = 0 (h the gap after load, a loaded ball's spring compressed by c R); every loaded
    ball's spring is the Hertz law at its own reaction, c R = c_H R^{2/3}. The ball set
    changes along the curve (more balls take load as the torque grows)."""
    from profilegen.contact.chain import BallBearing, ReducedZone

    bearing = BallBearing.from_gearset(inputs.gearset)
    for side, (pts, comp) in flanks.items():
        zone = ReducedZone(pts, comp, bearing)
        s_cc, c_cb, c_bb = _blocks(comp)
        loaded = np.zeros(pts.count, bool)
        loaded[int(np.argmin(pts.theta_rad))] = True
        state, sets = (loaded, np.asarray(comp.ball_active, bool), None), []
        for m in sorted({abs(t) for t in CURVE_TORQUES}):
            out = zone.solve(m, state, springs_on=True, max_iterations=80, spring_tol=1e-10)
            assert out is not None, (side, m)
            state = (out["loaded"], out["active"], out["log_springs"])
            f, react, phi, c = out["force"], out["reactions"], out["phi"], np.exp(out["log_springs"])
            tz = m / pts.zones * 1e3
            assert inputs.gearset.gear.waves * float(pts.lever_mm @ f) == pytest.approx(2.0 * tz, rel=1e-10)
            g = pts.lever_mm * (pts.theta_rad - phi) + s_cc @ f + c_cb @ react
            h = comp.ball_gap_mm + c_cb.T @ f + (c_bb + np.diag(c)) @ react
            scale = float(np.max(np.abs(s_cc @ f)))
            assert np.all(f >= 0.0) and np.all(react >= 0.0), (side, m)
            assert g.min() >= -1e-9 * scale and h.min() >= -1e-9 * scale, (side, m)
            assert np.max(np.abs(f * g)) <= 1e-9 * scale * f.max(), (side, m)
            assert np.max(np.abs(react * h)) <= 1e-9 * scale * react.max(), (side, m)
            on = react > 0.0
            np.testing.assert_allclose(c[on] * react[on], bearing.approach_mm(react[on]), rtol=1e-8)
            sets.append(int(on.sum()))
        assert len(set(sets)) > 1 and max(sets) > np.count_nonzero(comp.ball_gap_mm == 0.0) - 2, sets


def test_curve_continuation_against_lemke_from_scratch(inputs, zone, flanks):
    """The curve by continuation against the reference — Lemke from scratch on teeth and balls
    at every torque: with rigid balls (the whole curve, both flanks) to rounding and the same
    loaded balls and teeth; with the Hertz balls (Lemke at every step of the springs' fixed
    point) at two torques, one per flank, to the springs' tolerance. The rated torque's rigid
    rotation is ContactCompliance.solve_unilateral's (the public LCP) for the same flank."""
    from profilegen.contact.chain import BallBearing, _solve_side_unilateral, compliance_chain, torsional_curve

    kw = dict(sides=flanks, breakpoints_nm=(54.0, 196.0), catalogue=None)
    rigid = compliance_chain(inputs.gearset, bearing=None)
    fast = torsional_curve(inputs, CURVE_TORQUES, chain=rigid, **kw)
    ref = torsional_curve(inputs, CURVE_TORQUES, chain=rigid, method="lemke", **kw)
    np.testing.assert_allclose(fast.mesh_rad, ref.mesh_rad, rtol=1e-12, atol=0.0)
    assert np.array_equal(fast.active_balls, ref.active_balls)
    assert np.array_equal(fast.teeth_in_contact, ref.teeth_in_contact)
    assert fast.mesh_rad[fast.torque_nm == 265.0][0] == pytest.approx(zone[3].phi_rad, rel=1e-12)
    # odd: the left flank under −T mirrors the right flank under +T
    np.testing.assert_allclose(fast.mesh_rad[::-1], -fast.mesh_rad, rtol=2e-3)
    hertz = torsional_curve(inputs, CURVE_TORQUES, spring_tol=1e-10, **kw)
    bearing = BallBearing.from_gearset(inputs.gearset)
    for t in (265.0, -54.0):
        side = 1 if t > 0 else -1
        pts, comp = flanks[side]
        _, phi, _, _, balls, _ = _solve_side_unilateral(pts, comp, abs(t), bearing, spring_iterations=60,
                                                        spring_tol=1e-10)
        assert side * hertz.mesh_balls_rad[hertz.torque_nm == t][0] == pytest.approx(phi, rel=1e-9)
        assert hertz.active_balls[hertz.torque_nm == t][0] == int(np.count_nonzero(balls.ball_active))


def test_curve_balls_far_away_is_the_window(inputs, flanks):
    """Limit case: the balls outside the window 1 mm away never touch, and the curve is the
    window model's — the compliance with only the window's balls (zero gap, settled)."""
    import dataclasses

    from profilegen.contact.chain import torsional_curve

    far, window = {}, {}
    for side, (pts, comp) in flanks.items():
        inside = comp.ball_gap_mm == 0.0
        far[side] = (pts, dataclasses.replace(comp, ball_gap_mm=np.where(inside, 0.0, 1.0)))
        keep = np.flatnonzero(inside)
        window[side] = (pts, cm.ContactCompliance._assemble(
            flex_cc=comp._flex_cc, flex_cb=comp._flex_cb[:, keep], flex_bb=comp._flex_bb[np.ix_(keep, keep)],
            cs_flex=comp.cs_matrix_mm_per_n * comp.face_width_mm, face_width_mm=comp.face_width_mm, tooth=comp.tooth,
            ball_angle_rad=comp.ball_angle_rad[keep], ball_active=np.ones(keep.size, bool),
            wrap_half_angle_rad=comp.wrap_half_angle_rad, wrap_source=comp.wrap_source, dof=comp.dof,
            time_s=comp.time_s, mesh=comp.mesh, warnings=()))
    kw = dict(spring_tol=1e-10, breakpoints_nm=(54.0, 196.0), catalogue=None)
    a = torsional_curve(inputs, CURVE_TORQUES, sides=far, **kw)
    b = torsional_curve(inputs, CURVE_TORQUES, sides=window, **kw)
    np.testing.assert_allclose(a.mesh_rad, b.mesh_rad, rtol=1e-10, atol=0.0)
    np.testing.assert_allclose(a.mesh_balls_rad, b.mesh_balls_rad, rtol=1e-8, atol=0.0)
    assert np.array_equal(a.active_balls, b.active_balls)
    # and the balls the window leaves out make the gear stiffer
    near = torsional_curve(inputs, CURVE_TORQUES, sides=flanks, **kw)
    assert np.all(np.abs(near.mesh_balls_rad) < np.abs(a.mesh_balls_rad))


def test_ball_passage_without_the_jump(inputs):
    """Rolling balls (cage) from ψ = 0 to 12°: the ball at 62.6° rolls into the window (57.3°
    here) on the way. With every ball one-sided (the default) the rotation hardly moves;
    with the window it jumps by tens of arcsec as the ball enters it."""
    import dataclasses

    from profilegen.contact.transmission import ARCSEC_PER_RAD, transmission_error

    fixed = dataclasses.replace(inputs, rim_contact_angle_rad=WRAP)
    rated = inputs.gearset.torque.rated_nm
    every = transmission_error(fixed, rated, positions=2, workers=1, options=dict(span=12.0, ball_motion="cage"))
    window = transmission_error(fixed, rated, positions=2, workers=1,
                                options=dict(span=12.0, ball_motion="cage", ball_supports="window"))
    assert every.ball_supports == "all"
    step_all = abs(float(np.diff(every.rotation_rad)[0])) * ARCSEC_PER_RAD
    step_window = abs(float(np.diff(window.rotation_rad)[0])) * ARCSEC_PER_RAD
    assert step_window > 20.0 and step_all < 0.1 * step_window, (step_all, step_window)


def test_curve_falls_back_to_lemke_with_every_ball(inputs, flanks, monkeypatch):
    """A torque whose reduced loop gives up is solved by Lemke from scratch on teeth and balls
    (_solve_side_unilateral), and the torques after it continue: the same curve."""
    from profilegen.contact import chain

    kw = dict(sides=flanks, breakpoints_nm=(20.0, 54.0), catalogue=None)
    torques = [-54.0, 20.0, 54.0]
    plain = chain.torsional_curve(inputs, torques, **kw)
    solve = chain.ReducedZone.solve
    given_up = []

    def flaky(self, magnitude_nm, state, **options):
        if magnitude_nm == 20.0 and options["springs_on"]:
            given_up.append(magnitude_nm)
            return None
        return solve(self, magnitude_nm, state, **options)

    monkeypatch.setattr(chain.ReducedZone, "solve", flaky)
    mixed = chain.torsional_curve(inputs, torques, **kw)
    assert given_up == [20.0, 20.0]  # both flanks
    np.testing.assert_allclose(mixed.rotation_rad, plain.rotation_rad, rtol=1e-5, atol=0.0)
    assert np.array_equal(mixed.active_balls, plain.active_balls)
