"""Unit tests of profilegen.geometry.series: Fourier and general sine-series fits of ω(φ), υ(φ).

Checked against closed forms computed here, least-squares theory and finite differences,
not against the module's own intermediate values:

* ring theory (classical inextensible ring, w0 = 0.5 mm, U = 2): ω = w0 cos 2φ,
  υ = −(w0/2) sin 2φ — exactly one harmonic;
* a 3-harmonic signal plus white noise σ: the residual RMS estimates σ and the
  coefficient errors follow the least-squares covariance σ²(XᵀX)⁻¹, which for n uniform
  samples over a full turn is σ²/n for the mean and 2σ²/n for each harmonic;
* seed 004 ("Deriving Deformation Functions via Curve Fitting", the two coefficient
  tables for ω and υ, n = 3 sine terms): its non-integer frequencies make υ drift by
  ~0.019 mm over one turn (DESIGN.md trap 3).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from profilegen.geometry.deformation import ring_theory
from profilegen.errors import GearSetError, ProfilegenError
from profilegen.geometry.kinematics import HarmonicDriveMotion
from profilegen.geometry.series import (
    DeformationFit,
    GeneralSineDeformation,
    SeriesError,
    SeriesFit,
    fit_fourier,
    fit_sine_series,
)

W0, U = 0.5, 2
N = 720
PHI = np.linspace(0.0, 2 * math.pi, N, endpoint=False)

# seed 004, tables after "Deriving Deformation Functions via Curve Fitting" (mm, rad⁻¹, rad)
SEED_OMEGA = (
    np.array([0.5272, 0.02677, 0.007596]),  # a_i, mm
    np.array([1.987, 5.965, 4.033]),  # b_i, rad⁻¹
    np.array([1.611, 1.694, -9.533]),  # c_i, rad
)
SEED_UPSILON = (
    np.array([0.2956, 0.01807, 0.01897]),
    np.array([2.013, 0.2032, 4.067]),
    np.array([3.090, -1.919, -1.909]),
)


def sine_sum(phi, a, b, c):
    """Σ a_i sin(b_i φ + c_i), written out here independently of the module."""
    phi = np.asarray(phi, dtype=float)
    return sum(ai * np.sin(bi * phi + ci) for ai, bi, ci in zip(a, b, c))


def ring_samples(phi=PHI):
    return W0 * np.cos(U * phi), -(W0 / U) * np.sin(U * phi)


def _central(fun, x, h):
    """5-point central difference, error ~ h⁴ f⁽⁵⁾ / 30."""
    return (fun(x - 2 * h) - 8 * fun(x - h) + 8 * fun(x + h) - fun(x + 2 * h)) / (12 * h)


def _angle_diff(a, b):
    return np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b)))))


# --------------------------------------------------------------------------- Fourier: ring theory


def test_fourier_recovers_ring_theory_exactly():
    fit = fit_fourier(PHI, *ring_samples(), waves=U)
    assert isinstance(fit, DeformationFit)
    assert fit.order == 1 and fit.selection.picked == 1
    np.testing.assert_allclose(fit.cos_mm, [W0], atol=1e-12)
    np.testing.assert_allclose(fit.sin_mm, [-W0 / U], atol=1e-12)
    assert abs(fit.mean_mm) < 1e-12
    for stats in (fit.omega_stats, fit.upsilon_stats):
        assert stats.r2 == pytest.approx(1.0, abs=1e-12)
        assert stats.adj_r2 == pytest.approx(1.0, abs=1e-12)
        assert stats.max_error_mm < 1e-12
        assert stats.n_samples == N
    assert (fit.omega_stats.n_params, fit.upsilon_stats.n_params) == (2, 1)
    # a deformation model: the protocol's attributes
    assert fit.waves == U and fit.symmetric is True and fit.tier == "design"
    assert fit.deflection_mm == pytest.approx(W0, abs=1e-12)


def test_fourier_ring_theory_derivatives_are_the_analytic_ones():
    fit = fit_fourier(PHI, *ring_samples(), waves=U)
    phi = np.linspace(-math.pi, math.pi, 41)
    omega, upsilon = fit.evaluate(phi, order=3)
    assert omega.shape == upsilon.shape == (4, phi.size)
    c, s = np.cos(U * phi), np.sin(U * phi)
    # by hand: d/dφ cos Uφ = −U sin Uφ, ...; υ = −(w0/U) sin Uφ
    expected_omega = [W0 * c, -W0 * U * s, -W0 * U**2 * c, W0 * U**3 * s]
    expected_upsilon = [-W0 / U * s, -W0 * c, W0 * U * s, W0 * U**2 * c]
    for j in range(4):
        np.testing.assert_allclose(omega[j], expected_omega[j], atol=1e-11)
        np.testing.assert_allclose(upsilon[j], expected_upsilon[j], atol=1e-11)
    # inextensible neutral line: υ′ = −ω
    np.testing.assert_allclose(upsilon[1], -omega[0], atol=1e-12)


def test_fourier_one_wave_period_and_unsorted_samples_suffice():
    rng = np.random.default_rng(7)
    phi = rng.permutation(np.linspace(0.0, math.pi, 101))  # one period 2π/U, shuffled
    fit = fit_fourier(phi, *ring_samples(phi), waves=U)
    assert fit.order == 1
    np.testing.assert_allclose([fit.cos_mm[0], fit.sin_mm[0]], [W0, -W0 / U], atol=1e-12)


def test_fitted_ring_theory_drives_the_kinematics_like_ring_theory():
    fit = fit_fourier(PHI, *ring_samples(), waves=U)
    phi = np.linspace(-0.8, 0.8, 17)
    fitted = HarmonicDriveMotion(fit, 48.95, U, 202)
    exact = HarmonicDriveMotion(ring_theory(W0, U), 48.95, U, 202)
    assert fitted.symmetric
    p, q = fitted.pose(phi), exact.pose(phi)
    for name in ("origin", "origin_d1", "origin_d2", "angle", "angle_d1", "angle_d2"):
        np.testing.assert_allclose(getattr(p, name), getattr(q, name), atol=1e-11)


# --------------------------------------------------------------------------- Fourier: noise


TRUE_MEAN = 0.01
TRUE_COS = np.array([0.5, 0.02, 0.005])
TRUE_SIN = np.array([-0.25, -0.012, 0.003])
SIGMA = 1e-3  # 1 µm


def noisy_three_harmonics(seed):
    k = U * np.arange(1, 4)
    omega = TRUE_MEAN + np.cos(np.outer(PHI, k)) @ TRUE_COS
    upsilon = np.sin(np.outer(PHI, k)) @ TRUE_SIN
    rng = np.random.default_rng(seed)
    return omega + SIGMA * rng.standard_normal(N), upsilon + SIGMA * rng.standard_normal(N)


@pytest.mark.parametrize("seed", [0, 1, 2, 3, 4])
def test_fourier_noise_picks_three_harmonics_and_errors_follow_the_covariance(seed):
    fit = fit_fourier(PHI, *noisy_three_harmonics(seed), waves=U)
    assert fit.order == 3 and fit.selection.criterion == "noise"
    # the residual RMS (n − p degrees of freedom) estimates σ; its relative sd is 1/√(2n) ≈ 2.6 %
    assert fit.omega_stats.rmse_mm == pytest.approx(SIGMA, rel=0.12)
    assert fit.upsilon_stats.rmse_mm == pytest.approx(SIGMA, rel=0.12)
    # covariance of least squares on n uniform samples over a full turn: XᵀX = diag(n, n/2, ...)
    se_mean, se_harmonic = SIGMA / math.sqrt(N), SIGMA * math.sqrt(2 / N)
    assert abs(fit.mean_mm - TRUE_MEAN) < 4 * se_mean
    assert np.all(np.abs(fit.cos_mm - TRUE_COS) < 4 * se_harmonic)
    assert np.all(np.abs(fit.sin_mm - TRUE_SIN) < 4 * se_harmonic)
    # and the fit's own standard errors agree with that closed form (σ̂ ≈ σ)
    assert fit.mean_se_mm == pytest.approx(se_mean, rel=0.12)
    np.testing.assert_allclose(fit.cos_se_mm, se_harmonic, rtol=0.12)
    np.testing.assert_allclose(fit.sin_se_mm, se_harmonic, rtol=0.12)
    # the selection table covers every order and both criteria
    sel = fit.selection
    assert list(sel.orders) == list(range(1, 13))
    assert sel.aicc.shape == sel.omega_rmse_mm.shape == (12,)
    assert np.all(np.isfinite(sel.aicc))
    assert sel.aicc_pick >= 3  # AICc never under-fits this signal (it over-fits in ~20 % of draws)


def test_fourier_residuals_are_orthogonal_to_the_basis():
    """Normal equations: the residual of a least-squares fit is orthogonal to every column."""
    omega, upsilon = noisy_three_harmonics(11)
    fit = fit_fourier(PHI, omega, upsilon, waves=U, order=3)
    w, u = fit.evaluate(PHI, order=0)
    k = U * np.arange(1, 4)
    x_omega = np.column_stack([np.ones(N), np.cos(np.outer(PHI, k))])
    x_upsilon = np.sin(np.outer(PHI, k))
    assert np.max(np.abs(x_omega.T @ (omega - w[0]))) < 1e-12
    assert np.max(np.abs(x_upsilon.T @ (upsilon - u[0]))) < 1e-12
    # SSE, R² from their definitions
    sse = float(np.sum((omega - w[0]) ** 2))
    assert fit.omega_stats.sse_mm2 == pytest.approx(sse, rel=1e-10)
    sst = float(np.sum((omega - omega.mean()) ** 2))
    assert fit.omega_stats.r2 == pytest.approx(1 - sse / sst, rel=1e-12)
    assert fit.omega_stats.adj_r2 == pytest.approx(1 - (sse / sst) * (N - 1) / (N - 4), rel=1e-12)
    i = int(np.argmax(np.abs(omega - w[0])))
    assert fit.omega_stats.max_error_phi_rad == PHI[i]


def test_fourier_aicc_criterion_on_request():
    fit = fit_fourier(PHI, *noisy_three_harmonics(0), waves=U, criterion="aicc")
    assert fit.selection.criterion == "aicc"
    assert fit.order == fit.selection.aicc_pick
    assert fit.order == int(fit.selection.orders[np.argmin(fit.selection.aicc)])
    exact = fit_fourier(PHI, *ring_samples(), waves=U, criterion="aicc")
    assert exact.order == 1  # rounding floor: exact data stop at the exact order


# --------------------------------------------------------------------------- seed 004


def test_seed004_printed_coefficients_give_the_seeds_extremes():
    """Issue 3: the printed table evaluates to ω ≈ 0.554 mm at φ = 0 (the seed's FEM: 0.553)
    and |υ| ≈ 0.295 mm near 45° (0.293)."""
    assert sine_sum(0.0, *SEED_OMEGA) == pytest.approx(0.554, abs=5e-4)
    phi = np.radians(np.linspace(30.0, 60.0, 3001))
    u = sine_sum(phi, *SEED_UPSILON)
    k = int(np.argmax(np.abs(u)))
    assert abs(u[k]) == pytest.approx(0.295, abs=5e-4)
    assert math.degrees(phi[k]) == pytest.approx(45.0, abs=1.0)


def test_seed004_printed_coefficients_are_not_periodic():
    """DESIGN.md trap 3: the printed υ drifts by ~0.019 mm over one turn."""
    d_upsilon = sine_sum(2 * math.pi, *SEED_UPSILON) - sine_sum(0.0, *SEED_UPSILON)
    d_omega = sine_sum(2 * math.pi, *SEED_OMEGA) - sine_sum(0.0, *SEED_OMEGA)
    assert abs(d_upsilon) == pytest.approx(0.019, abs=0.003)
    assert abs(d_omega) < 0.005  # −1.5 µm: ω's frequencies are closer to whole numbers
    # the sine-series fit of the seed's own curves recovers the printed table and the same defect
    for (a, b, c), d in ((SEED_OMEGA, d_omega), (SEED_UPSILON, d_upsilon)):
        fit = fit_sine_series(PHI, sine_sum(PHI, a, b, c), terms=3, starts=8)
        order = np.argsort(-a)
        np.testing.assert_allclose(fit.amplitude_mm, a[order], atol=1e-9)
        np.testing.assert_allclose(fit.frequency_per_rad, b[order], atol=1e-9)
        assert np.all(_angle_diff(fit.phase_rad, c[order]) < 1e-8)
        assert fit.stats.defect_mm == pytest.approx(d, abs=1e-10)
        slope = sum(ai * bi * (math.cos(bi * 2 * math.pi + ci) - math.cos(ci)) for ai, bi, ci in zip(a, b, c))
        assert fit.stats.slope_defect == pytest.approx(slope, abs=1e-9)


def test_seed004_curves_fitted_by_fourier_are_periodic():
    omega = sine_sum(PHI, *SEED_OMEGA)
    upsilon = sine_sum(PHI, *SEED_UPSILON)
    fit = fit_fourier(PHI, omega, upsilon, waves=U)
    for stats in (fit.omega_stats, fit.upsilon_stats):
        assert abs(stats.defect_mm) < 1e-15
        assert abs(stats.slope_defect) < 1e-13
    w, u = fit.evaluate(np.array([0.0, 2 * math.pi]), order=3)
    np.testing.assert_allclose(w[:, 1], w[:, 0], atol=1e-12)
    np.testing.assert_allclose(u[:, 1], u[:, 0], atol=1e-12)
    # No periodic curve can follow one whose ends differ by d to better than ≈ d/2:
    # at the seam the errors at φ → 0 and φ → 2π differ by d.
    h, slope_max = PHI[1], 0.6  # sample spacing; |υ′| ≤ Σ a_i b_i ≈ 0.6 mm/rad
    d_upsilon = sine_sum(2 * math.pi, *SEED_UPSILON) - sine_sum(0.0, *SEED_UPSILON)
    assert fit.upsilon_stats.max_error_mm >= abs(d_upsilon) / 2 - h * slope_max
    # A symmetric two-wave series also cannot hold the seed's asymmetric and 1/turn content;
    # least squares beats any other member of its family, e.g. ring theory with w0 = 0.5 mm.
    ring_w, ring_u = ring_samples()
    assert fit.omega_stats.sse_mm2 <= float(np.sum((omega - ring_w) ** 2))
    assert fit.upsilon_stats.sse_mm2 <= float(np.sum((upsilon - ring_u) ** 2))
    # ... and does no better than a full 2π-periodic series (all harmonics 1..12, sin and cos)
    k = np.arange(1, 13)
    x = np.column_stack([np.ones(N), np.cos(np.outer(PHI, k)), np.sin(np.outer(PHI, k))])
    for y, stats in ((omega, fit.omega_stats), (upsilon, fit.upsilon_stats)):
        r = y - x @ np.linalg.lstsq(x, y, rcond=None)[0]
        assert stats.sse_mm2 >= float(r @ r)
    assert 1e-3 < fit.upsilon_stats.rmse_mm < 0.05  # tens of µm: what the symmetric model leaves out


# --------------------------------------------------------------------------- general sine series


OWN = (np.array([0.4, 0.03, 0.01]), np.array([2.07, 5.9, 3.6]), np.array([1.5, -0.7, 2.2]))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_sine_series_recovers_its_own_model(seed):
    a, b, c = OWN
    fit = fit_sine_series(PHI, sine_sum(PHI, a, b, c), terms=3, starts=10, seed=seed)
    assert isinstance(fit, SeriesFit) and fit.terms == 3
    np.testing.assert_allclose(fit.amplitude_mm, a, atol=1e-9)  # already sorted by amplitude
    np.testing.assert_allclose(fit.frequency_per_rad, b, atol=1e-9)
    assert np.all(_angle_diff(fit.phase_rad, c) < 1e-9)
    assert fit.n_at_best >= 3  # several starts reach the global minimum
    assert fit.stats.r2 == pytest.approx(1.0, abs=1e-12)
    assert fit.stats.n_params == 9
    expected = sine_sum(2 * math.pi, a, b, c) - sine_sum(0.0, a, b, c)
    assert fit.stats.defect_mm == pytest.approx(expected, abs=1e-10)
    assert abs(fit.stats.defect_mm) > 1e-3  # non-integer frequencies: not periodic


@pytest.mark.parametrize("seed", [3, 4])
def test_sine_series_on_noisy_samples(seed):
    """White noise σ = 1 µm on the 3-term model: the fit's RMSE estimates σ (χ² with n − 9
    degrees of freedom: within 10 % for n = 720), each frequency to 5 of its Cramér–Rao
    standard deviations √12·σ/(a_i·2π·√n) (2e-3 rad⁻¹ for the 0.01 mm term), the amplitudes
    to 5 σ/√(n/2), and the periodicity defect is that of the model to within the noise."""
    a, b, c = OWN
    sigma = 1e-3
    rng = np.random.default_rng(seed)
    y = sine_sum(PHI, a, b, c) + sigma * rng.standard_normal(N)
    fit = fit_sine_series(PHI, y, terms=3, starts=10, seed=seed)
    assert fit.stats.rmse_mm == pytest.approx(sigma, rel=0.1)
    crlb = math.sqrt(12) * sigma / (a * 2 * math.pi * math.sqrt(N))
    assert np.all(np.abs(fit.frequency_per_rad - b) < 5 * crlb)
    np.testing.assert_allclose(fit.amplitude_mm, a, atol=5 * sigma / math.sqrt(N / 2))
    expected = sine_sum(2 * math.pi, a, b, c) - sine_sum(0.0, a, b, c)
    assert fit.stats.defect_mm == pytest.approx(expected, abs=5 * sigma)


def test_sine_series_on_ring_theory_finds_two_waves_and_no_defect():
    omega, upsilon = ring_samples()
    fw = fit_sine_series(PHI, omega, terms=1, starts=4)
    fu = fit_sine_series(PHI, upsilon, terms=1, starts=4)
    assert fw.frequency_per_rad[0] == pytest.approx(2.0, abs=1e-9)
    assert fu.frequency_per_rad[0] == pytest.approx(2.0, abs=1e-9)
    assert fw.amplitude_mm[0] == pytest.approx(W0, abs=1e-12)
    assert fu.amplitude_mm[0] == pytest.approx(W0 / U, abs=1e-12)
    assert _angle_diff(fw.phase_rad[0], math.pi / 2) < 1e-9  # cos x = sin(x + π/2)
    assert _angle_diff(fu.phase_rad[0], math.pi) < 1e-9  # −sin x = sin(x + π)
    for f in (fw, fu):
        assert abs(f.stats.defect_mm) < 1e-9
        assert abs(f.stats.slope_defect) < 1e-8
    model = GeneralSineDeformation(fw, fu, waves=U)
    assert model.symmetric is False and model.waves == U
    w, u = model.evaluate(PHI[:50], order=1)
    np.testing.assert_allclose(u[1], -w[0], atol=1e-9)  # inextensible: υ′ = −ω


def test_general_sine_deformation_evaluates_the_seed_table():
    fw = fit_sine_series(PHI, sine_sum(PHI, *SEED_OMEGA), starts=6)
    fu = fit_sine_series(PHI, sine_sum(PHI, *SEED_UPSILON), starts=6)
    model = GeneralSineDeformation(fw, fu, waves=U)
    phi = np.linspace(-1.0, 7.0, 33)  # beyond the sampled turn, too: no wrapping
    w, u = model.evaluate(phi, order=0)
    np.testing.assert_allclose(w[0], sine_sum(phi, *SEED_OMEGA), atol=1e-9)
    np.testing.assert_allclose(u[0], sine_sum(phi, *SEED_UPSILON), atol=1e-9)
    d_w, d_u = model.defect_mm
    assert abs(d_u) == pytest.approx(0.019, abs=0.003)
    assert abs(d_w) < 0.005
    assert not HarmonicDriveMotion(model, 48.95, U, 202).symmetric


def test_sine_series_derivatives_of_high_order_are_closed_form():
    a, b, c = OWN
    fit = fit_sine_series(PHI, sine_sum(PHI, a, b, c), starts=4)
    phi = np.linspace(-2.0, 8.0, 23)
    f = fit.evaluate(phi, order=6)
    assert f.shape == (7, phi.size)
    # d⁶/dφ⁶ sin(bφ + c) = −b⁶ sin(bφ + c); d⁵ = b⁵ cos(bφ + c)
    np.testing.assert_allclose(f[6], -sine_sum(phi, a * b**6, b, c), rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(f[5], sine_sum(phi, a * b**5, b, c + math.pi / 2), rtol=1e-8, atol=1e-8)


# --------------------------------------------------------------------------- derivatives vs finite differences


def _models():
    fourier = fit_fourier(PHI, *noisy_three_harmonics(3), waves=U)
    fw = fit_sine_series(PHI, sine_sum(PHI, *SEED_OMEGA), starts=4)
    fu = fit_sine_series(PHI, sine_sum(PHI, *SEED_UPSILON), starts=4)
    return fourier, GeneralSineDeformation(fw, fu, waves=U)


@pytest.fixture(scope="module")
def models():
    return _models()


@pytest.mark.parametrize("which", [0, 1])
def test_derivatives_match_five_point_differences(models, which):
    model = models[which]
    phi = np.linspace(-math.pi, math.pi, 29) + 0.1
    h = 1e-3
    exact_w, exact_u = model.evaluate(phi, order=3)
    for j in range(3):
        for comp, exact in ((0, exact_w), (1, exact_u)):
            numeric = _central(lambda x, j=j, comp=comp: model.evaluate(x, order=j)[comp][j], phi, h)
            scale = max(1.0, float(np.max(np.abs(exact[j + 1]))))
            np.testing.assert_allclose(numeric, exact[j + 1], atol=1e-8 * scale)


# --------------------------------------------------------------------------- results


def test_results_are_frozen_readonly_and_json_safe(models):
    fourier, general = models
    for arr in (fourier.cos_mm, fourier.sin_mm, fourier.cos_se_mm, fourier.selection.aicc,
                general.omega_fit.amplitude_mm, general.omega_fit.frequency_per_rad, general.upsilon_fit.phase_rad):
        with pytest.raises(ValueError):
            arr[0] = 1.0
    with pytest.raises(AttributeError):
        fourier.time_s = 0.0  # frozen
    with pytest.raises(AttributeError):
        general.omega_fit.stats.rmse_mm = 0.0
    for obj in (fourier, general, general.omega_fit):
        text = json.dumps(obj.to_dict(), allow_nan=False)
        assert json.loads(text)
    d = fourier.to_dict()
    assert d["order"] == 3 and d["selection"]["criterion"] == "noise" and len(d["selection"]["aicc"]) == 12
    assert d["omega"]["defect_mm"] == fourier.omega_stats.defect_mm
    assert fourier.time_s > 0 and general.omega_fit.time_s > 0


# --------------------------------------------------------------------------- bad input


def _raises(name, fun, *args, **kwargs):
    with pytest.raises(SeriesError, match=name) as info:
        fun(*args, **kwargs)
    assert isinstance(info.value, ValueError) and isinstance(info.value, ProfilegenError)
    assert not isinstance(info.value, GearSetError)
    return info.value


def test_bad_input_names_the_parameter():
    w, u = ring_samples()
    _raises("omega", fit_fourier, PHI, w[:-1], u)
    _raises("upsilon", fit_fourier, PHI, w, u[:-2])
    bad = w.copy()
    bad[5] = np.nan
    _raises("omega", fit_fourier, PHI, bad, u)
    bad_phi = PHI.copy()
    bad_phi[3] = np.inf
    _raises("phi", fit_fourier, bad_phi, w, u)
    _raises("phi", fit_fourier, PHI[:100], w[:100], u[:100])  # 0.87 rad < π
    _raises("phi", fit_fourier, np.array([0.0, 3.2]), [1.0, 0.0], [0.0, 0.0])  # 2 samples
    few = np.linspace(0.0, math.pi, 4, endpoint=False)
    _raises("phi", fit_fourier, few, *ring_samples(few), order=3)  # 4 samples, 4 parameters
    alias = np.linspace(0.0, math.pi, 8, endpoint=False)
    _raises("order", fit_fourier, alias, *ring_samples(alias), order=4)  # sin 8φ vanishes on the samples
    _raises("waves", fit_fourier, PHI, w, u, waves=0)
    _raises("order", fit_fourier, PHI, w, u, order=0)
    _raises("max_order", fit_fourier, PHI, w, u, max_order=1.5)
    _raises("criterion", fit_fourier, PHI, w, u, criterion="bic")
    _raises("tier", fit_fourier, PHI, w, u, tier="draft")

    _raises("terms", fit_sine_series, PHI, w, terms=0)
    _raises("starts", fit_sine_series, PHI, w, starts=0)
    _raises("phi", fit_sine_series, PHI[:9], w[:9], terms=3)  # 9 samples, 9 parameters
    _raises("values", fit_sine_series, PHI, w[:10])
    _raises("values", fit_sine_series, PHI, np.where(PHI > 1, np.inf, w))
    _raises("phi", fit_sine_series, np.zeros(20), np.ones(20), terms=1)
    fit = fit_sine_series(PHI, w, terms=1, starts=2)
    _raises("waves", GeneralSineDeformation, fit, fit, waves=0)
    _raises("upsilon_fit", GeneralSineDeformation, fit, "υ", waves=2)
    _raises("order", fit.evaluate, PHI, order=-1)
