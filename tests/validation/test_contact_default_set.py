"""Loaded contact of the default set (profilegen.contact): the real problem, not a toy.

Sources: seed 000 §5.1–5.2 (complementarity formulation, ball supports dropped when they
pull); DESIGN.md trap 4 (complementary pivoting, the naive LP fails).
"""

import numpy as np
import pytest

from profilegen.contact import ContactError, ContactInput, solve_lemke, solve_qp_active_set
from tests.oracles.naive_lp import solve_naive_lp
from profilegen.contact.analysis import analyse_contact, solve_contact


@pytest.fixture(scope="module")
def design(default_sketch):
    return default_sketch  # conftest.py: computed once per worker


@pytest.fixture(scope="module")
def inputs(design):
    return ContactInput.from_design(design)


@pytest.fixture(scope="module")
def rated(inputs):
    return solve_contact(inputs, [30.0, 265.0])


def test_both_solvers_agree_on_the_real_problem(inputs, rated):
    """Every ball one-sided (the default): Lemke on teeth and balls against the independent
    solve (the ball set settled around the active-set QP of the teeth); and the two solvers
    on the real teeth matrix with that ball set held."""
    pts = rated.points
    assert rated.compliance.ball_supports == "all" and rated.compliance_info["ball_supports"] == "all"
    for case in rated.cases:
        other = solve_contact(inputs, [case.torque_nm], points=pts, compliance=rated.compliance,
                              solver="active_set").cases[0]
        scale = case.solution.force_n.max()
        assert np.max(np.abs(other.solution.force_n - case.solution.force_n)) <= 1e-8 * scale
        assert other.rotation_rad == pytest.approx(case.rotation_rad, rel=1e-9)
        np.testing.assert_array_equal(other.ball_active, case.ball_active)
        np.testing.assert_allclose(other.ball_reaction_n, case.ball_reaction_n, rtol=0, atol=1e-8 * scale)
        s = rated.compliance.with_balls(case.ball_active).matrix_mm_per_n
        t = case.zone_torque_nm * 1e3
        lemke, qp = solve_lemke(s, pts.theta_rad, pts.lever_mm, t), solve_qp_active_set(s, pts.theta_rad, pts.lever_mm, t)
        assert np.max(np.abs(lemke.force_n - qp.force_n)) <= 1e-8 * lemke.force_n.max()
        assert lemke.phi_rad == pytest.approx(qp.phi_rad, rel=1e-8)


def test_complementarity_equilibrium_and_settled_balls(rated):
    """Teeth and balls complementary, recomputed from the raw FEM blocks: every ball pushes
    or is off, and a ball that is off has the rim at or outside its no-load gap."""
    pts = rated.points
    comp = rated.compliance
    b = comp.face_width_mm
    for case in rated.cases:
        sol = case.solution
        assert np.all(sol.force_n >= 0.0) and np.all(sol.gap_mm >= -1e-12)
        assert sol.complementarity_residual < 1e-9
        moment = np.sum(pts.lever_mm * sol.force_n)
        assert moment == pytest.approx(case.zone_torque_nm * 1e3, rel=1e-9)  # Σ r_k F_k = T / U
        react = case.ball_reaction_n
        h = comp.ball_gap_mm + comp._flex_cb.T @ sol.force_n / b + comp._flex_bb @ react / b
        scale_r, scale_h = np.abs(react).max(), np.abs(comp.ball_gap_mm).max() + np.abs(h).max()
        assert react.min() >= -1e-9 * scale_r and h.min() >= -1e-9 * scale_h
        assert np.max(np.abs(react * h)) <= 1e-9 * scale_r * scale_h
        # balls outside the rim's no-load contact angle carry load: the window would have left them out
        assert np.any(case.ball_active & (comp.ball_gap_mm > 0.0))


def test_first_contact_is_at_the_smallest_separation(inputs, rated):
    tiny = solve_contact(inputs, [1e-6], points=rated.points, compliance=rated.compliance)
    sol = tiny.cases[0].solution
    assert sol.loaded_count == 1
    # the loaded point is one whose angular separation the tiny rotation closes: the smallest,
    # or one tied with it (a conjugate profile touches on several teeth at once — on the
    # default set two teeth are within 5e-13 rad of each other)
    theta = rated.points.theta_rad
    assert 0 < sol.phi_rad < 1e-9
    assert theta[np.argmax(sol.force_n)] <= theta.min() + sol.phi_rad
    assert np.sum(theta <= theta.min() + sol.phi_rad) <= 3


def test_rotation_and_contact_grow_with_torque_on_fixed_supports(inputs, rated):
    """With every ball held (one compliance) the rotation and the number of teeth in
    contact never decrease as the torque grows (φ = dV/dT of a convex V)."""
    torques = [10, 30, 100, 265, 660, 1200]
    sweep = analyse_contact(rated.points, rated.compliance.matrix_mm_per_n, torques)
    phi = [c.rotation_rad for c in sweep.cases]
    teeth = [c.teeth_in_contact for c in sweep.cases]
    assert np.all(np.diff(phi) > 0) and np.all(np.diff(teeth) >= 0) and teeth[-1] > teeth[0]
    # with every ball one-sided the problem is still a convex QP in T: φ grows with T
    phi = [c.rotation_rad for c in solve_contact(inputs, torques, points=rated.points,
                                                 compliance=rated.compliance).cases]
    assert np.all(np.diff(phi) > 0)


def test_the_naive_lp_is_not_a_contact_solution(rated):
    """DESIGN.md trap 4 on the real matrix: the printed phase-1 LP returns a feasible point
    that violates complementarity."""
    case = rated.cases[-1]
    s = rated.compliance.with_balls(case.ball_active).matrix_mm_per_n
    naive = solve_naive_lp(s, rated.points.theta_rad, rated.points.lever_mm, case.zone_torque_nm * 1e3)
    assert naive.complementarity_residual > 1e-3
    assert naive.loaded_count < case.solution.loaded_count or naive.phi_rad != pytest.approx(case.solution.phi_rad)


def test_bad_input_is_named(inputs, rated):
    with pytest.raises(ContactError, match="torques_nm"):
        solve_contact(inputs, [0.0], points=rated.points, compliance=rated.compliance)
    with pytest.raises(ContactError, match="points, compliance"):
        solve_contact(inputs, [10.0], points=rated.points)


def test_a_torque_beyond_the_searched_zone_is_flagged(inputs, rated):
    """A torque whose loaded zone reaches the edge of the searched teeth is flagged on the
    load case and in the warnings (not returned as a plain answer); the rated one is not."""
    huge = solve_contact(inputs, [5e4], points=rated.points, compliance=rated.compliance)
    assert huge.cases[0].beyond_capacity is not None
    assert any("beyond what the modelled contact can carry" in w for w in huge.warnings)
    assert huge.cases[0].to_dict()["beyond_capacity"] == huge.cases[0].beyond_capacity
    assert rated.cases[1].beyond_capacity is None


def test_a_rotation_past_the_searched_separation_is_flagged(inputs):
    """A station farther than max_gap_mm was never searched; once the rotation φ turns the
    longest lever arm past that separation, such a station could touch: flagged."""
    from profilegen.contact.points import contact_points

    narrow = contact_points(inputs, max_gap_mm=0.01)
    soft = np.eye(narrow.count) * 2e-4  # mm/N: a compliant mesh turns far
    case = analyse_contact(narrow, soft, [265.0]).cases[0]
    assert case.reach_mm == pytest.approx(case.rotation_rad * narrow.lever_mm.max())
    assert case.reach_mm > 0.01 and "past the 10 µm" in case.beyond_capacity
    stiff = analyse_contact(narrow, soft * 1e-2, [1.0]).cases[0]
    assert stiff.reach_mm < 0.01 and stiff.beyond_capacity is None
