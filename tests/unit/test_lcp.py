"""The package's LCP solvers (profilegen.lcp) against each other and against the LCP's own
conditions, on random problems: z ≥ 0, w ≥ 0, z·w = 0 — the solution is unique when the matrix
is symmetric positive definite (or a P-matrix), so every solver must find the same z."""

import numpy as np
import pytest

from profilegen import lcp
from profilegen.errors import ConvergenceError


def _spd(rng, n):
    a = rng.normal(size=(n, n))
    return a @ a.T / n + 0.1 * np.eye(n)


def _complementary(m, z, w, scale):
    assert np.all(z >= 0.0)
    assert np.all(w >= -1e-10 * scale)
    assert abs(z @ w) <= 1e-9 * scale * max(1.0, float(np.abs(z).sum()))


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_every_spd_solver_finds_the_one_solution(seed):
    rng = np.random.default_rng(seed)
    n = 40
    s, q = _spd(rng, n), rng.normal(size=n)  # the contact sign: w = S λ − q
    ref = lcp.spd_nnls(s, q)
    _complementary(s, ref, s @ ref - q, 1.0)
    assert 0 < np.count_nonzero(ref) < n  # a mixed active set: the test can tell solvers apart

    def columns_of(nodes):
        return s[:, nodes]

    for z in (lcp.active_set_lazy(columns_of, q, max_steps=4 * n),
              lcp.principal_pivoting(columns_of, q, guess=rng.random(n) < 0.5, max_pivots=200),
              lcp.solve_spd(s, -q),                      # the climb's sign: w = S F + q
              lcp.solve_p_matrix(s, -q)):
        assert z is not None
        np.testing.assert_allclose(z, ref, rtol=1e-8, atol=1e-10)


def test_lemke_returns_the_basic_set_of_the_solution():
    rng = np.random.default_rng(7)
    n = 30
    m, q = _spd(rng, n), rng.normal(size=n)
    basic, pivots = lcp.lemke_lcp(m, q, "test")
    z = np.zeros(n)
    z[basic] = np.linalg.solve(m[np.ix_(basic, basic)], -q[basic])
    _complementary(m, z, m @ z + q, 1.0)
    assert pivots >= basic.size
    assert lcp.lemke_lcp(m, np.abs(q), "test")[0].size == 0  # q ≥ 0: z = 0 with no pivot


def test_a_nonsymmetric_p_matrix_is_solved_and_a_non_p_matrix_fails_loudly():
    rng = np.random.default_rng(11)
    n = 25
    s = _spd(rng, n)
    skew = rng.normal(size=(n, n))
    m = s + 0.05 * (skew - skew.T)  # symmetric part positive definite: a P-matrix
    q = rng.normal(size=n)
    z = lcp.solve_p_matrix(m, q)
    _complementary(m, z, m @ z + q, 1.0)
    bad = -np.eye(3)  # w = −z + q with q < 0: no solution
    with pytest.raises(ConvergenceError):
        lcp.solve_p_matrix(bad, -np.ones(3))


def test_the_primal_dual_iteration_settles_from_the_solutions_set_and_declines_without_a_guess():
    rng = np.random.default_rng(5)
    n = 40
    s, q = _spd(rng, n), rng.normal(size=n)
    ref = lcp.spd_nnls(s, q)
    near = ref > 0.0
    near[np.flatnonzero(near)[0]] = False  # one node off the solution's set: a second set settles it
    for guess in (ref > 0.0, near):
        z = lcp.primal_dual_from_guess(s, q, guess)
        assert z is not None
        np.testing.assert_allclose(z, ref, rtol=1e-8, atol=1e-10)
    assert lcp.primal_dual_from_guess(s, q, None) is None
    assert lcp.primal_dual_from_guess(s, q, np.zeros(n, dtype=bool)) is None
