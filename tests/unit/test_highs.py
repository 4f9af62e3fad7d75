"""profilegen.profile.highs: the arc fit's LPs straight to scipy's HiGHS give what linprog gives.

The reference is ``scipy.optimize.linprog(method="highs")`` itself, on the LPs a real fit solves
(the default flank's trust-region LPs, recorded), on an infeasible and on an unbounded LP; and when
scipy's internal bindings are not what the direct call expects, the fit goes through linprog.
"""

import numpy as np
import pytest

import profilegen.profile.arcfit as arcfit
from profilegen.profile import highs
from profilegen.profile.highs import solve_lp


@pytest.fixture(scope="module")
def fit_lps():
    """The LPs of a one-sided fit of a wobbly arc (as a CS flank: minimax starts, one-sided stage)."""
    theta = np.linspace(0.2, 0.9, 200)
    pts = 2.0 * np.column_stack([np.cos(theta), np.sin(theta)]) * (1 + 2e-4 * np.sin(25 * theta))[:, None]
    seen = []

    def record(c, A, b, bounds, **kw):
        seen.append((np.array(c), np.array(A), np.array(b), list(bounds)))
        return solve_lp(c, A, b, bounds, **kw)

    mp = pytest.MonkeyPatch()
    mp.setattr(arcfit, "solve_lp", record)
    arcfit.clear_cache()
    try:
        arcfit.fit_profile(pts, method="one_sided", space_side="left", starts=3)
    finally:
        mp.undo()
        arcfit.clear_cache()
    assert len(seen) >= 10
    return seen


def test_the_direct_call_is_in_use_here():
    assert highs._DIRECT is not None  # scipy as pinned by this project's tests: the fast path runs


def test_a_fit_s_lps_solve_bit_for_bit_as_linprog_solves_them(fit_lps):
    for c, A, b, bounds in fit_lps:
        direct, reference = solve_lp(c, A, b, bounds), solve_lp(c, A, b, bounds, direct=False)
        assert direct is not None and reference is not None
        assert np.array_equal(direct[0], reference[0]) and np.array_equal(direct[1], reference[1])
        x, marginals = direct
        assert np.all(A @ x <= b + 1e-9) and np.all(marginals <= 0.0)  # feasible; ≤ rows' duals of a min
        assert c @ x == pytest.approx(b @ marginals + sum(
            (lo if lam > 0 else hi) * lam for (lo, hi), lam in zip(bounds, c - A.T @ marginals) if abs(lam) > 1e-12),
            abs=1e-9)  # strong duality: the primal and dual objectives agree


@pytest.mark.parametrize("direct", [True, False])
def test_no_optimum_is_none(direct):
    c = np.array([1.0, 0.0])
    infeasible = solve_lp(c, np.array([[1.0, 0.0], [-1.0, 0.0]]), np.array([-1.0, -1.0]), [(None, None)] * 2,
                          direct=direct)  # x ≤ −1 and x ≥ 1
    unbounded = solve_lp(c, np.array([[0.0, 1.0]]), np.array([1.0]), [(None, None)] * 2, direct=direct)
    assert infeasible is None and unbounded is None


def test_changed_scipy_internals_fall_back_to_linprog(fit_lps, monkeypatch):
    c, A, b, bounds = fit_lps[0]
    reference = solve_lp(c, A, b, bounds, direct=False)
    monkeypatch.setattr(highs, "_DIRECT", (object(), object()))  # bindings without what the call needs
    got = solve_lp(c, A, b, bounds)
    assert highs._DIRECT is None  # the fit calls linprog from now on
    assert np.array_equal(got[0], reference[0]) and np.array_equal(got[1], reference[1])
