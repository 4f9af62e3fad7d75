"""Contact solvers (profilegen.contact.solvers): complementarity, equilibrium, agreement,
a hand-solved two-point problem, first contact, monotonicity in T, symmetry, the naive LP's
failure (seed 000 Eqs. 15–17, DESIGN.md trap 4) and named errors for bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from profilegen.contact import (
    ContactError,
    ContactSolution,
    solve_lemke,
    solve_qp_active_set,
)
from profilegen.errors import ConvergenceError
from tests.oracles.naive_lp import solve_naive_lp

SOLVERS = [solve_lemke, solve_qp_active_set]


def random_spd(rng, n, scale=1e-7):
    """A general SPD compliance (off-diagonals of both signs) in mm/N."""
    B = rng.normal(size=(n, n))
    return (B @ B.T / n + np.diag(rng.uniform(0.1, 1.0, n))) * scale


def gear_problem(n, rng=None, torque_nmm=2e5):
    """Shaped like gear contact: decaying positive correlation along the engagement (an
    exponential kernel, SPD) plus a local term; θ from a smooth profile with a ripple."""
    rng = np.random.default_rng(1) if rng is None else rng
    s = np.linspace(0.0, 1.0, n)
    K = np.exp(-np.abs(s[:, None] - s[None, :]) / 0.03)
    S = 2e-7 * K + 1e-7 * np.diag(rng.uniform(0.8, 1.2, n))
    theta = 4e-4 * ((s - 0.45) / 0.5) ** 2 + 5e-6 * (1.0 + np.sin(40.0 * s + rng.uniform(0.0, 6.0)))
    r = 30.0 + 2.0 * np.cos(3.0 * s)
    return S, theta, r, torque_nmm


def tau(S, r, T):
    return T * float(np.mean(np.diag(S) / r**2))


def assert_contact_solution(res, S, theta, r, T, rel=1e-9):
    """Complementarity and equilibrium, with the gaps recomputed from the data (not the solver's)."""
    F, phi = np.asarray(res.force_n), res.phi_rad
    g = r * (theta - phi) + S @ F
    angle = phi - theta.min() + tau(S, r, T)
    assert np.all(F >= 0.0)
    assert np.all(g >= -rel * r * angle), float(np.min(g / (r * angle)))
    assert np.max(np.abs(F * g)) <= rel * T * angle
    assert abs(float(r @ F) - T) <= rel * T
    np.testing.assert_allclose(res.gap_mm, g, rtol=0, atol=rel * float(np.max(r)) * angle)
    assert res.loaded_count >= 1  # "all gaps open" cannot happen for T > 0
    assert res.complementarity_residual <= rel and res.equilibrium_residual <= rel


def random_problem(rng):
    n = int(rng.integers(1, 61))
    kind = rng.integers(3)
    if kind == 0:
        S = random_spd(rng, n)
    elif kind == 1:
        S = gear_problem(n, rng)[0] if n > 1 else np.array([[3e-7]])
    else:  # positive, banded, badly scaled rows/columns
        d = rng.uniform(0.5, 20.0, n)
        S = random_spd(rng, n) * np.outer(d, d)
    theta = rng.uniform(0.0, 1e-3, n)
    theta[rng.random(n) < 0.1] = theta.min()  # ties at first contact
    r = rng.uniform(15.0, 45.0, n)
    T = 10.0 ** rng.uniform(2.0, 6.5)
    return S, theta, r, T


# ----------------------------------------------------------------------------- correctness


@pytest.mark.parametrize("solver", SOLVERS, ids=lambda f: f.__name__)
def test_complementarity_and_equilibrium(solver):
    rng = np.random.default_rng(20240501)
    for _ in range(40):
        S, theta, r, T = random_problem(rng)
        assert_contact_solution(solver(S, theta, r, T), S, theta, r, T)
    S, theta, r, T = gear_problem(120)
    assert_contact_solution(solver(S, theta, r, T), S, theta, r, T)


def test_solvers_agree_on_200_random_spd_problems():
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(200):
        S, theta, r, T = random_problem(rng)
        a = solve_lemke(S, theta, r, T)
        b = solve_qp_active_set(S, theta, r, T)
        assert a.active_set == b.active_set
        fmax = float(np.max(a.force_n))
        np.testing.assert_allclose(b.force_n, a.force_n, rtol=0, atol=1e-8 * fmax)
        angle = a.phi_rad - theta.min() + tau(S, r, T)
        assert abs(a.phi_rad - b.phi_rad) <= 1e-8 * angle
        worst = max(worst, float(np.max(np.abs(a.force_n - b.force_n))) / fmax)
    assert worst < 1e-8


def test_two_point_problem_by_hand():
    """S = [[4, 1], [1, 2]]·1e-7 mm/N, θ = (0, 2e-6) rad, r = (20, 25) mm. In moments
    A_kj = S_kj/(r_k r_j): a11 = 1e-9, a12 = 2e-10, a22 = 3.2e-10 (rad per N·mm).
    One point loaded: M1 = T, φ = a11 T; point 2 closes when θ2 − φ + a12 T = 0, i.e.
    T* = θ2 / (a11 − a12) = 2e-6 / 8e-10 = 2500 N·mm. Above: φ = a11 M1 + a12 M2 =
    θ2 + a12 M1 + a22 M2 with M1 + M2 = T gives M1 = (θ2 + (a22 − a12) T) / (a11 − 2 a12 + a22)."""
    S = np.array([[4.0, 1.0], [1.0, 2.0]]) * 1e-7
    theta = np.array([0.0, 2e-6])
    r = np.array([20.0, 25.0])
    a11, a12, a22 = 1e-9, 2e-10, 3.2e-10
    for solver in SOLVERS:
        # below T* = 2500 N·mm: only point 1
        res = solver(S, theta, r, 2000.0)
        assert res.active_set == (0,)
        np.testing.assert_allclose(res.force_n, [2000.0 / 20.0, 0.0], rtol=1e-12)
        assert res.phi_rad == pytest.approx(a11 * 2000.0, rel=1e-12)
        assert res.gap_mm[1] == pytest.approx(25.0 * (2e-6 - a11 * 2000.0) + 1e-7 * 100.0, rel=1e-9)  # = 1e-5 mm
        # above: both, closed form
        T = 10000.0
        M1 = (2e-6 + (a22 - a12) * T) / (a11 - 2 * a12 + a22)  # = 3.2e-6 / 9.2e-10
        M2 = T - M1
        res = solver(S, theta, r, T)
        assert res.active_set == (0, 1)
        np.testing.assert_allclose(res.moment_nmm, [M1, M2], rtol=1e-12)
        np.testing.assert_allclose(res.force_n, [M1 / 20.0, M2 / 25.0], rtol=1e-12)
        assert res.phi_rad == pytest.approx(a11 * M1 + a12 * M2, rel=1e-12)
        assert M1 == pytest.approx(3.2e-6 / 9.2e-10, rel=1e-14)
        np.testing.assert_allclose(res.gap_mm, 0.0, atol=1e-18)


@pytest.mark.parametrize("solver", SOLVERS, ids=lambda f: f.__name__)
def test_first_contact_at_smallest_theta(solver):
    rng = np.random.default_rng(3)
    for _ in range(10):
        S, theta, r, _T = random_problem(rng)
        theta = theta + rng.uniform(1e-6, 2e-6, len(theta))  # a unique minimum, ≥ 1e-6 rad apart
        theta[int(rng.integers(len(theta)))] = 0.5e-6
        k = int(np.argmin(theta))
        T = 1e-3  # N·mm: far below any second contact
        res = solver(S, theta, r, T)
        assert res.active_set == (k,)
        assert res.force_n[k] == pytest.approx(T / r[k], rel=1e-12)
        assert res.phi_rad == pytest.approx(theta[k] + S[k, k] * T / r[k] ** 2, rel=1e-12)


def test_phi_and_contact_count_grow_with_torque():
    S, theta, r, _ = gear_problem(150)
    torques = np.geomspace(1.0, 1e7, 40)
    prev = None
    for T in torques:
        res = solve_lemke(S, theta, r, T)
        if prev is not None:
            assert res.phi_rad >= prev.phi_rad
            assert res.loaded_count >= prev.loaded_count
            assert set(prev.active_set) <= set(res.active_set)  # nested on this gear-shaped problem
        prev = res
    assert prev.loaded_count > 100
    # φ is dV/dT of a convex optimal value: non-decreasing for any SPD problem, too
    rng = np.random.default_rng(11)
    S, theta, r, _ = random_problem(rng)
    phis = [solve_lemke(S, theta, r, T).phi_rad for T in np.geomspace(10.0, 1e7, 30)]
    assert np.all(np.diff(phis) >= -1e-15)


@pytest.mark.parametrize("solver", SOLVERS, ids=lambda f: f.__name__)
def test_symmetric_problem_symmetric_answer(solver):
    n = 41
    s = np.linspace(-1.0, 1.0, n)
    S = 1e-7 * (np.exp(-np.abs(s[:, None] - s[None, :]) / 0.2) + np.diag(1.0 + s**2))
    theta = 3e-4 * s**2 + 1e-6 * np.cos(7 * s)
    r = 30.0 + s**2
    flip = np.arange(n)[::-1]
    S, theta, r = 0.5 * (S + S[np.ix_(flip, flip)]), 0.5 * (theta + theta[flip]), 0.5 * (r + r[flip])  # exact mirror
    assert np.array_equal(S[np.ix_(flip, flip)], S) and np.array_equal(theta[flip], theta)
    for T in (50.0, 5e4, 5e6):
        res = solver(S, theta, r, T)
        np.testing.assert_allclose(res.force_n[flip], res.force_n, rtol=0, atol=1e-10 * res.max_force_n)
        assert np.array_equal(res.loaded[flip], res.loaded)
    # permutation equivariance of a general problem
    rng = np.random.default_rng(5)
    S, theta, r, T = random_problem(rng)
    perm = rng.permutation(len(theta))
    a = solver(S, theta, r, T)
    b = solver(S[np.ix_(perm, perm)], theta[perm], r[perm], T)
    np.testing.assert_allclose(b.force_n, a.force_n[perm], rtol=0, atol=1e-10 * a.max_force_n)
    assert b.phi_rad == pytest.approx(a.phi_rad, rel=1e-12)


def test_units_scale_out():
    """S → cS with T → T/c leaves φ and the active set, scales F by 1/c; θ + c shifts φ by c."""
    S, theta, r, T = gear_problem(60)
    a = solve_lemke(S, theta, r, T)
    b = solve_lemke(S * 1e7, theta, r, T * 1e-7)  # S of order 1 mm/N
    assert b.active_set == a.active_set
    assert b.phi_rad == pytest.approx(a.phi_rad, rel=1e-12)
    np.testing.assert_allclose(b.force_n, a.force_n * 1e-7, rtol=1e-10)
    c = solve_lemke(S, theta + 0.01, r, T)
    assert c.phi_rad == pytest.approx(a.phi_rad + 0.01, rel=1e-12)
    np.testing.assert_allclose(c.force_n, a.force_n, rtol=0, atol=1e-9 * a.max_force_n)


def test_lemke_path_is_the_loading_history():
    """Pivots: z0 in, φ in, then one per point that closes; on a nested-loading problem
    Lemke needs exactly (loaded points + 2) pivots (the last one takes z0 out)."""
    S, theta, r, T = gear_problem(100)
    res = solve_lemke(S, theta, r, T)
    assert res.iterations == res.loaded_count + 2
    path = res.diagnostics["path"]
    assert path[0][1:] == ["phi", f"gap[{int(np.argmin(theta))}]"]
    assert path[-1][2] == "z0"


# ----------------------------------------------------------------------------- the naive LP


def test_naive_lp_returns_non_physical_answer():
    """Seed 000 Eqs. (15)–(17) solved as printed: Z = 0 is reached at a point that is feasible
    but not a contact solution — φ = 0, the torque concentrated, open gaps under load."""
    S, theta, r, T = gear_problem(200)
    good = solve_lemke(S, theta, r, T)
    bad = solve_naive_lp(S, theta, r, T)
    assert bad.diagnostics["objective_Z"] == pytest.approx(0.0, abs=1e-9)
    assert bad.equilibrium_residual < 1e-9  # it does satisfy Eq. (12) ...
    assert np.all(bad.gap_mm >= -1e-9 * np.max(np.abs(bad.gap_mm)))  # ... and Eq. (10)
    assert bad.complementarity_residual > 1e-2  # but loaded points keep open gaps
    assert bad.loaded_count < good.loaded_count / 5  # the load is concentrated
    assert bad.max_force_n > 5 * good.max_force_n
    assert bad.phi_rad < 0.5 * good.phi_rad  # no (or too little) deformation: φ = 0 here
    assert any("not a contact solution" in w for w in bad.warnings)
    assert good.complementarity_residual < 1e-12 and not good.warnings


# ----------------------------------------------------------------------------- flags, result, errors


def test_all_points_loaded_is_flagged():
    S, theta, r, _ = gear_problem(30)
    res = solve_lemke(S, theta, r, 1e9)
    assert res.all_points_loaded and res.loaded_count == 30
    assert any("all 30 candidate points are loaded" in w for w in res.warnings)
    assert not solve_lemke(S, theta, r, 1e3).all_points_loaded


def test_result_is_frozen_readonly_and_json():
    S, theta, r, T = gear_problem(20)
    res = solve_lemke(S, theta, r, T)
    assert isinstance(res, ContactSolution)
    with pytest.raises(AttributeError):
        res.phi_rad = 0.0
    for a in (res.force_n, res.moment_nmm, res.gap_mm, res.loaded):
        with pytest.raises(ValueError):
            a[0] = 1
    d = json.loads(json.dumps(res.to_dict()))
    assert d["method"] == "lemke" and d["loaded_count"] == res.loaded_count and d["time_s"] >= 0.0
    assert d["active_set"] == list(res.active_set)


@pytest.mark.parametrize("solver, option", [(solve_lemke, "max_pivots"), (solve_qp_active_set, "max_iter")])
def test_iteration_cap_names_the_solver(solver, option):
    S, theta, r, T = gear_problem(100)
    with pytest.raises(ConvergenceError, match=solver.__name__) as info:
        solver(S, theta, r, T, **{option: 3})
    assert option in str(info.value) and isinstance(info.value, RuntimeError)


def _good():
    return gear_problem(5, torque_nmm=1e4)


def _with(**change):
    S, theta, r, T = _good()
    args = {"compliance_mm_per_n": S, "theta_rad": theta, "radius_mm": r, "torque_nmm": T}
    args.update(change)
    return args


_S, _TH, _R, _ = _good()
_indef = _S.copy()
_indef[0, 1] = _indef[1, 0] = 5 * _S[0, 0]
_B = np.random.default_rng(0).normal(size=(5, 3))
_asym = _S.copy()
_asym[0, 1] *= 1.01
_nan = _S.copy()
_nan[2, 3] = np.nan

BAD = [
    ("torque_nmm", {"torque_nmm": 0.0}),
    ("torque_nmm", {"torque_nmm": -5.0}),
    ("torque_nmm", {"torque_nmm": float("nan")}),
    ("torque_nmm", {"torque_nmm": float("inf")}),
    ("torque_nmm", {"torque_nmm": "ten"}),
    ("compliance_mm_per_n", {"compliance_mm_per_n": _S[:, :4]}),
    ("compliance_mm_per_n", {"compliance_mm_per_n": _asym}),
    ("compliance_mm_per_n", {"compliance_mm_per_n": _indef}),
    ("compliance_mm_per_n", {"compliance_mm_per_n": _B @ _B.T * 1e-7}),  # singular (rank 3)
    ("compliance_mm_per_n", {"compliance_mm_per_n": np.zeros((5, 5))}),
    ("compliance_mm_per_n", {"compliance_mm_per_n": _nan}),
    ("compliance_mm_per_n", {"compliance_mm_per_n": -_S}),
    ("theta_rad", {"theta_rad": _TH - 1e-3}),
    ("theta_rad", {"theta_rad": np.where(np.arange(5) == 2, np.nan, _TH)}),
    ("theta_rad", {"theta_rad": _TH[:, None]}),
    ("radius_mm", {"radius_mm": np.where(np.arange(5) == 1, 0.0, _R)}),
    ("radius_mm", {"radius_mm": -_R}),
    ("radius_mm", {"radius_mm": _R[:4]}),
    ("radius_mm", {"radius_mm": np.where(np.arange(5) == 4, np.inf, _R)}),
]


@pytest.mark.parametrize("solver", [solve_lemke, solve_qp_active_set, solve_naive_lp], ids=lambda f: f.__name__)
@pytest.mark.parametrize("name, change", BAD, ids=[f"{n}-{i}" for i, (n, _) in enumerate(BAD)])
def test_bad_input_named_error(solver, name, change):
    with pytest.raises(ContactError, match=name) as info:
        solver(**_with(**change))
    assert isinstance(info.value, ValueError)


def test_singular_compliance_is_named():
    with pytest.raises(ContactError, match=r"compliance_mm_per_n.*(singular|positive definite)"):
        solve_lemke(_B @ _B.T * 1e-7, _TH, _R, 1e4)
    w, U = np.linalg.eigh(_S)
    nearly = (U * np.where(np.arange(5) == 0, w.max() * 1e-15, w)) @ U.T  # condition number ~1e15
    nearly = 0.5 * (nearly + nearly.T)
    with pytest.raises(ContactError, match="singular"):
        solve_qp_active_set(nearly, _TH, _R, 1e4)


def test_misspelt_option_is_type_error():
    with pytest.raises(TypeError):
        solve_lemke(*_good(), max_iter=10)


@pytest.mark.parametrize("solver", SOLVERS, ids=lambda f: f.__name__)
def test_fully_degenerate_ties(solver):
    """Equal θ, equal r, S = s·I: every ratio test ties (Lemke's lexicographic rule decides);
    by symmetry F_k = T / (n r) and φ = θ + s T / (n r²)."""
    n, s, r0, th0, T = 12, 3e-7, 25.0, 1e-4, 6e3
    res = solver(np.eye(n) * s, np.full(n, th0), np.full(n, r0), T)
    np.testing.assert_allclose(res.force_n, T / (n * r0), rtol=1e-12)
    assert res.phi_rad == pytest.approx(th0 + s * T / (n * r0**2), rel=1e-12)
    assert res.all_points_loaded
