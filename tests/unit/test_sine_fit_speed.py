"""The general sine fit's variable projection (issue 14: the verify scene's sine fit made fast):
its exact Jacobian against finite differences, its amplitudes against ``np.linalg.lstsq``,
MINPACK through ``leastsq`` against ``least_squares``, and the new fitter against the old
algorithm (``_reference=True``: lstsq amplitudes, finite-difference Jacobian) on data with
a known answer."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import least_squares

from profilegen.geometry.series import _lm, _Projection, fit_sine_series

PHI = np.linspace(0.0, np.pi, 401)
TRUE = {  # a sin(bφ + c): well separated, each term well above the others' residual
    "amplitude_mm": np.array([0.5, 0.02, 0.004]),
    "frequency_per_rad": np.array([2.0, 3.3, 5.7]),
    "phase_rad": np.array([0.3, -1.0, 2.0]),
}


def _series(phi, a, b, c):
    return np.sin(np.multiply.outer(phi, b) + c) @ a


Y = _series(PHI, TRUE["amplitude_mm"], TRUE["frequency_per_rad"], TRUE["phase_rad"])


def _central_jacobian(fun, b, rel=1e-6):
    cols = []
    for k in range(b.size):
        h = rel * max(1.0, abs(b[k]))
        up, down = b.copy(), b.copy()
        up[k] += h
        down[k] -= h
        cols.append((fun(up) - fun(down)) / (2 * h))
    return np.column_stack(cols)


@pytest.mark.parametrize("seed", range(4))
def test_projection_jacobian_matches_finite_differences(seed):
    """∂r/∂b of r(b) = y − A A⁺y (Golub–Pereyra, both terms) against central differences of r,
    at random frequency sets (not at the optimum: the second term matters there)."""
    rng = np.random.default_rng(seed)
    y = Y + 0.01 * rng.standard_normal(PHI.size)
    proj = _Projection(PHI, y, 3)
    b = np.sort(rng.uniform(0.5, 9.0, 3)) + np.array([0.0, 0.3, 0.6])
    jac = proj.jacobian(b)
    assert jac.shape == (PHI.size, 3)
    ref = _central_jacobian(lambda x: _Projection(PHI, y, 3).residual(x), b)
    assert np.max(np.abs(jac - ref)) <= 1e-6 * np.max(np.abs(ref))


def test_projection_amplitudes_are_lstsq():
    """α, β and the residual: those of np.linalg.lstsq on [sin bφ, cos bφ], also when two
    frequencies coincide (rank 4 of 6: the minimum-norm solution, lstsq's)."""
    for b in (np.array([1.7, 4.2, 6.1]), np.array([2.0, 2.0, 5.0])):
        x = np.hstack([np.sin(np.multiply.outer(PHI, b)), np.cos(np.multiply.outer(PHI, b))])
        coef, *_ = np.linalg.lstsq(x, Y, rcond=None)
        alpha, beta, resid = _Projection(PHI, Y, 3).amplitudes(b)
        scale = np.max(np.abs(coef))
        assert np.max(np.abs(np.concatenate([alpha, beta]) - coef)) <= 1e-10 * scale
        assert np.max(np.abs(resid - (Y - x @ coef))) <= 1e-12


def test_svd_branch_gives_the_qr_branch_answer(monkeypatch):
    """The branch used when a singular value would be cut (the SVD, A = U S Vᵀ) and the QR
    branch agree on the residual and the Jacobian where A has full rank (force the SVD)."""
    b = np.array([1.3, 2.9, 6.4])
    y = Y + 0.003 * np.cos(7.7 * PHI)
    qr = _Projection(PHI, y, 3)
    res_qr, jac_qr = qr.residual(b).copy(), qr.jacobian(b).copy()
    svd = _Projection(PHI, y, 3)
    monkeypatch.setattr(svd, "_full_rank", lambda r, r_inv: False)  # as if a value were cut: the SVD keeps all
    state = svd._state(b)
    assert state[2] is None  # the SVD branch ran
    assert np.max(np.abs(svd.residual(b) - res_qr)) <= 1e-13
    assert np.max(np.abs(svd.jacobian(b) - jac_qr)) <= 1e-10 * np.max(np.abs(jac_qr))


def test_lm_through_leastsq_is_least_squares_lm():
    """_lm runs MINPACK's lmder as least_squares(method='lm', x_scale='jac') does: same iterate,
    cost and evaluation count, bit for bit."""
    proj = _Projection(PHI, Y + 1e-3 * np.sin(9.1 * PHI), 3)
    b0 = np.array([1.8, 3.6, 5.2])
    x, cost, nfev, converged = _lm(proj.residual, proj.jacobian, b0, 400)
    ref = least_squares(proj.residual, b0, jac=proj.jacobian, method="lm", x_scale="jac", ftol=1e-15, xtol=1e-15,
                        gtol=1e-15, max_nfev=400)
    assert np.array_equal(x, ref.x)
    assert cost == ref.cost and nfev == ref.nfev and converged == (ref.status > 0)


def _parameter_sd(fit, sigma_mm: float) -> np.ndarray:
    """Standard deviations (terms × [amplitude, frequency, phase]) of a sine series' parameters
    fitted to data with independent noise of ``sigma_mm``: σ²(JᵀJ)⁻¹ with J of Σ a sin(bφ + c)."""
    a, b, c = fit.amplitude_mm, fit.frequency_per_rad, fit.phase_rad
    cols = []
    for k in range(a.size):
        arg = b[k] * PHI + c[k]
        cols += [np.sin(arg), a[k] * PHI * np.cos(arg), a[k] * np.cos(arg)]
    J = np.array(cols).T
    return np.sqrt(np.diag(np.linalg.inv(J.T @ J)) * sigma_mm**2).reshape(a.size, 3)


@pytest.fixture(scope="module")
def fits():
    """Old (finite differences, lstsq) and new fitters on exact and on noisy known data."""
    noise = 1e-5 * np.random.default_rng(7).standard_normal(PHI.size)
    out = {}
    for label, y in (("exact", Y), ("noisy", Y + noise)):
        out[label] = (fit_sine_series(PHI, y, terms=3, starts=6, _reference=True),
                      fit_sine_series(PHI, y, terms=3, starts=6))
    return out


def test_new_fitter_recovers_the_known_series(fits):
    """Exact data: the new fit returns the generating amplitudes, frequencies and phases."""
    _, new = fits["exact"]
    for key, value in TRUE.items():
        assert np.max(np.abs(getattr(new, key) - value)) <= 1e-9, key
    assert new.stats.sse_mm2 <= 1e-24


@pytest.mark.parametrize("label", ["exact", "noisy"])
def test_new_fitter_matches_the_old_algorithm(fits, label):
    """Same parameters as the old algorithm (to 1e-9), the same fitted curve and SSE; noisy
    data (1e-5 mm): the optimum is not the generating series, but both fitters find it."""
    old, new = fits[label]
    for key, sigma in zip(("amplitude_mm", "frequency_per_rad", "phase_rad"), _parameter_sd(new, 1e-5).T):
        # exact data: both reach the generating series, to round-off. Noisy data: the old
        # fitter's forward-difference Jacobian (relative error ~ √eps) moves its stationary
        # point by a round-off-dependent amount (1.4e-9 /rad on a frequency with OpenBLAS's
        # Prescott kernel, 3.5e-10 with Haswell): what the fitters must share is the optimum
        # to far below what the data determine, 1e-4 of each parameter's standard deviation
        # under the 1e-5 mm noise (Gauss–Newton covariance σ²(JᵀJ)⁻¹, 1.2e-6 … 9e-4)
        tol = 1e-9 if label == "exact" else 1e-4 * sigma
        assert np.all(np.abs(getattr(new, key) - getattr(old, key)) <= tol), key
    assert np.max(np.abs(new.evaluate(PHI, 0)[0] - old.evaluate(PHI, 0)[0])) <= 1e-11
    assert new.stats.sse_mm2 == pytest.approx(old.stats.sse_mm2, rel=1e-9, abs=1e-26)
    assert new.n_starts == old.n_starts and new.n_at_best == old.n_at_best
    if label == "noisy":  # the noise is left, not fitted: SSE ≈ n σ²
        assert 0.5 * PHI.size * 1e-10 < new.stats.sse_mm2 < 2 * PHI.size * 1e-10
