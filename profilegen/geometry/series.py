"""Series fits of the rim deformation: samples ω(φ), υ(φ) → a deformation model.

φ is the angle from the wave-generator major axis to a flexspline tooth's *undeformed*
position (rad); ω is the radial displacement of the neutral line (outward +, mm), υ the
tangential one (toward increasing φ, mm). A rim solver (ring theory, FEM) gives them at
discrete φ; the kinematics needs smooth functions with derivatives up to third order.

Two fitters, as in seed 004 ("Deriving Deformation Functions via Curve Fitting") but
corrected (docs/theory/rim.md, "The fit"):

* :func:`fit_fourier` — the default. Integer harmonics of the wave count U,
  ``ω = a_0 + Σ a_k cos(kUφ)``, ``υ = Σ b_k sin(kUφ)``, by linear least squares. Exactly
  periodic and symmetric (ω even, υ odd about the major axis) by construction. The result,
  a :class:`DeformationFit`, *is* a deformation model: its ``evaluate`` is that of the
  :class:`~profilegen.geometry.deformation.HarmonicDeformation` built from the coefficients.
* :func:`fit_sine_series` — seed 004's general form ``f(φ) = Σ a_i sin(b_i φ + c_i)`` by
  nonlinear least squares, one component at a time; :class:`GeneralSineDeformation`
  pairs an ω and a υ fit into a deformation model. Non-integer frequencies b_i make f
  non-periodic: the seed's printed υ drifts by ~0.019 mm over one turn. Every fit reports
  this periodicity defect f(2π) − f(0) (and that of f′).

Both report per component (:class:`FitStats`): SSE, RMSE, R², adjusted R² (with the
number of parameters), the largest error and where, and the periodicity defects.

>>> import numpy as np
>>> phi = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
>>> fit = fit_fourier(phi, 0.5 * np.cos(2 * phi), -0.25 * np.sin(2 * phi))
>>> fit.order, np.round(fit.cos_mm, 12).tolist(), np.round(fit.sin_mm, 12).tolist()
(1, [0.5], [-0.25])
>>> abs(fit.upsilon_stats.defect_mm) < 1e-15
True
"""

from __future__ import annotations

import logging
import math
import numbers
import time
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
from scipy.linalg import lapack, solve_triangular
from scipy.optimize import least_squares, leastsq, minimize_scalar

from .. import checks
from .deformation import HarmonicDeformation
from ..errors import ConvergenceError, ProfilegenError
from ..results import readonly as _readonly

if TYPE_CHECKING:  # pragma: no cover
    from numpy.typing import ArrayLike

__all__ = [
    "DeformationFit",
    "FitStats",
    "GeneralSineDeformation",
    "OrderSelection",
    "SeriesError",
    "SeriesFit",
    "fit_fourier",
    "fit_sine_series",
]

log = logging.getLogger(__name__)

TWO_PI = 2.0 * math.pi
TIERS = ("sketch", "design", "verify", "toothed", "cup3d")  # the rim stage's tiers (profilegen.rim.stage.RIM_TIERS)
# Residuals below this fraction of the component's magnitude are rounding, not signal:
# both order criteria floor the RMS at _FLOOR_REL·max|f| so that exact data (ring theory)
# do not pick harmonics by comparing rounding noise.
_FLOOR_REL = 1e-13


class SeriesError(ProfilegenError, ValueError):
    """Bad input to a series fit; the message names the parameter, its value and the allowed range."""


# --------------------------------------------------------------------------- helpers



_whole = partial(checks.whole, error=SeriesError)


def _samples(name: str, values, unit: str, n: int | None = None) -> np.ndarray:
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise SeriesError(f"{name}: must be an array of numbers ({unit}), got {type(values).__name__}") from exc
    if array.ndim != 1:
        raise SeriesError(f"{name}: must be 1-D ({unit}), got shape {array.shape}")
    if n is not None and array.size != n:
        raise SeriesError(f"{name}: {array.size} samples, does not match phi ({n} samples)")
    bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        raise SeriesError(
            f"{name}: values must be finite ({unit}); {bad.size} are not, first at index {bad[0]} ({array[bad[0]]})"
        )
    return array


def _check_order(order) -> int:
    return _whole("order", order, 0)


def _tier(tier) -> str:
    if tier not in TIERS:
        raise SeriesError(f"tier = {tier!r}: must be one of {', '.join(TIERS)}")
    return tier


def _json_float(x) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


@dataclass(frozen=True, slots=True, eq=False)
class FitStats:
    """Goodness of fit of one component (ω or υ), in mm.

    ``rmse_mm`` is the standard error of the fit, √(SSE / (n − p)) (MATLAB's and seed
    004's "RMSE"; an unbiased estimate of the noise σ); ``rms_error_mm`` is √(SSE / n).
    R² = 1 − SSE/SST with SST about the sample mean; adjusted R² =
    1 − (1 − R²)(n − 1)/(n − p). For constant data (SST = 0) R² is 1 if SSE = 0 to
    rounding, else 0. ``defect_mm`` = f(2π) − f(0) and ``slope_defect`` = f′(2π) − f′(0)
    (mm/rad): zero to rounding for integer harmonics, not for a general sine series.
    """

    n_samples: int
    n_params: int
    sse_mm2: float
    rmse_mm: float
    rms_error_mm: float
    r2: float
    adj_r2: float
    max_error_mm: float
    max_error_phi_rad: float
    defect_mm: float
    slope_defect: float

    def to_dict(self) -> dict:
        return {
            "n_samples": self.n_samples,
            "n_params": self.n_params,
            "sse_mm2": self.sse_mm2,
            "rmse_mm": self.rmse_mm,
            "rms_error_mm": self.rms_error_mm,
            "r2": self.r2,
            "adj_r2": self.adj_r2,
            "max_error_mm": self.max_error_mm,
            "max_error_phi_rad": self.max_error_phi_rad,
            "defect_mm": self.defect_mm,
            "slope_defect": self.slope_defect,
        }


def _stats(phi, y, fitted, n_params: int, evaluate) -> FitStats:
    n = y.size
    resid = y - fitted
    sse = float(resid @ resid)
    centred = y - y.mean()
    sst = float(centred @ centred)
    if sst > 0.0:
        r2 = 1.0 - sse / sst
    else:
        r2 = 1.0 if sse <= n * (_FLOOR_REL * max(1.0, float(np.max(np.abs(y))))) ** 2 else 0.0
    dof = n - n_params  # > 0: validated before fitting
    i = int(np.argmax(np.abs(resid)))
    ends = evaluate(np.array([0.0, TWO_PI]), 1)
    return FitStats(
        n_samples=n,
        n_params=n_params,
        sse_mm2=sse,
        rmse_mm=math.sqrt(sse / dof),
        rms_error_mm=math.sqrt(sse / n),
        r2=r2,
        adj_r2=1.0 - (1.0 - r2) * (n - 1) / dof,
        max_error_mm=float(abs(resid[i])),
        max_error_phi_rad=float(phi[i]),
        defect_mm=float(ends[0, 1] - ends[0, 0]),
        slope_defect=float(ends[1, 1] - ends[1, 0]),
    )


# --------------------------------------------------------------------------- Fourier

CRITERIA = ("noise", "aicc")
NOISE_FACTOR = 1.05


@dataclass(frozen=True, slots=True, eq=False)
class OrderSelection:
    """How the number of harmonics was chosen, with every order tried.

    Per order K in ``orders``: ``omega_rmse_mm`` / ``upsilon_rmse_mm`` (√(SSE/(n − p))) and
    ``aicc`` (combined, see :func:`fit_fourier`). ``*_noise_floor_mm`` is the RMSE of the
    highest order tried (floored at 1e-13·max|f|). ``noise_pick`` and ``aicc_pick`` are the
    orders each criterion picks; ``picked`` is the one used (``criterion`` says which, or
    "given" for an explicit order).
    """

    criterion: str
    picked: int
    noise_pick: int
    aicc_pick: int
    orders: np.ndarray
    omega_rmse_mm: np.ndarray
    upsilon_rmse_mm: np.ndarray
    aicc: np.ndarray
    omega_noise_floor_mm: float
    upsilon_noise_floor_mm: float

    def __post_init__(self):
        for name in ("orders", "omega_rmse_mm", "upsilon_rmse_mm", "aicc"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))

    def to_dict(self) -> dict:
        return {
            "criterion": self.criterion,
            "picked": self.picked,
            "noise_pick": self.noise_pick,
            "aicc_pick": self.aicc_pick,
            "noise_factor": NOISE_FACTOR,
            "orders": [int(k) for k in self.orders],
            "omega_rmse_mm": [_json_float(v) for v in self.omega_rmse_mm],
            "upsilon_rmse_mm": [_json_float(v) for v in self.upsilon_rmse_mm],
            "aicc": [_json_float(v) for v in self.aicc],
            "omega_noise_floor_mm": self.omega_noise_floor_mm,
            "upsilon_noise_floor_mm": self.upsilon_noise_floor_mm,
        }


@dataclass(frozen=True, slots=True, eq=False)
class DeformationFit:
    """A Fourier fit of ω(φ), υ(φ) — and the deformation model it defines.

    ``evaluate(phi, order)`` is that of ``model`` (a :class:`HarmonicDeformation`):
    ω = mean_mm + Σ cos_mm[k−1] cos(kUφ), υ = Σ sin_mm[k−1] sin(kUφ), k = 1..``order``.

    Diagnostics: per-component :class:`FitStats`; the coefficients' standard errors
    (√diag(σ̂²(XᵀX)⁻¹), σ̂ = the component's rmse_mm); the :class:`OrderSelection`;
    ``time_s``; ``warnings``.
    """

    model: HarmonicDeformation
    omega_stats: FitStats
    upsilon_stats: FitStats
    mean_se_mm: float
    cos_se_mm: np.ndarray
    sin_se_mm: np.ndarray
    selection: OrderSelection
    time_s: float
    warnings: tuple[str, ...] = ()

    def __post_init__(self):
        for name in ("cos_se_mm", "sin_se_mm"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        object.__setattr__(self, "warnings", tuple(self.warnings))

    # the Deformation protocol
    @property
    def tier(self) -> str:
        return self.model.tier

    @property
    def source(self) -> str:
        return self.model.source

    @property
    def waves(self) -> int:
        return self.model.waves

    @property
    def symmetric(self) -> bool:
        """ω even and υ odd in φ (always, for cos/sin harmonics)."""
        return True

    def evaluate(self, phi, order: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """ω and υ with derivatives 0..order at φ (rad), each (order + 1, n), mm."""
        return self.model.evaluate(phi, _check_order(order))

    # the coefficients
    @property
    def order(self) -> int:
        """Number of harmonics fitted (k = 1..order)."""
        return int(self.model.cos_mm.size)

    @property
    def mean_mm(self) -> float:
        return float(self.model.mean_mm)

    @property
    def cos_mm(self) -> np.ndarray:
        return self.model.cos_mm

    @property
    def sin_mm(self) -> np.ndarray:
        return self.model.sin_mm

    @property
    def deflection_mm(self) -> float:
        """ω(0), the radial displacement on the major axis (mm)."""
        return self.model.deflection_mm

    def to_dict(self) -> dict:
        return {
            "kind": "fourier",
            **self.model.to_dict(),
            "order": self.order,
            "symmetric": True,
            "mean_se_mm": self.mean_se_mm,
            "cos_se_mm": self.cos_se_mm.tolist(),
            "sin_se_mm": self.sin_se_mm.tolist(),
            "omega": self.omega_stats.to_dict(),
            "upsilon": self.upsilon_stats.to_dict(),
            "selection": self.selection.to_dict(),
            "time_s": self.time_s,
            "warnings": list(self.warnings),
        }


def _fourier_design(phi, waves: int, order: int) -> tuple[np.ndarray, np.ndarray]:
    """Design matrices [1, cos kUφ] for ω and [sin kUφ] for υ, k = 1..order."""
    arg = np.multiply.outer(phi, waves * np.arange(1, order + 1))
    x_omega = np.empty((phi.size, order + 1))
    x_omega[:, 0] = 1.0
    x_omega[:, 1:] = np.cos(arg)
    return x_omega, np.sin(arg)


class _NestedLeastSquares:
    """One QR of the full design matrix X = QR solves every leading-column subproblem:
    the first k columns of X have the QR factors Q[:, :k], R[:k, :k]."""

    def __init__(self, x, y):
        self.x, self.y = x, y
        self.q, self.r = np.linalg.qr(x)
        self.qty = self.q.T @ y
        diag = np.abs(np.diag(self.r))
        self.tol = diag.max() * x.shape[0] * np.finfo(float).eps * 1e3 if diag.size else 0.0

    def full_rank(self, k: int) -> bool:
        return bool(k == 0 or np.abs(np.diag(self.r)[:k]).min() > self.tol)

    def solve(self, k: int):
        """Coefficients, fitted values and diag((XᵀX)⁻¹) of the first k columns."""
        r = self.r[:k, :k]
        coef = solve_triangular(r, self.qty[:k])
        r_inv = solve_triangular(r, np.eye(k))
        return coef, self.x[:, :k] @ coef, np.sum(r_inv**2, axis=1)  # (XᵀX)⁻¹ = R⁻¹R⁻ᵀ


def _aicc(sse: float, n: int, p: int, floor: float) -> float:
    """AICc of a Gaussian linear model with p coefficients and its own variance (k = p + 1)."""
    k = p + 1
    return n * math.log(max(sse, floor) / n) + 2 * k + 2 * k * (k + 1) / (n - k - 1)


def fit_fourier(
    phi: ArrayLike,
    omega: ArrayLike,
    upsilon: ArrayLike,
    *,
    waves: int = 2,
    order: int | None = None,
    max_order: int = 12,
    criterion: str = "noise",
    tier: str = "design",
) -> DeformationFit:
    """Fit ω = a_0 + Σ a_k cos(kUφ), υ = Σ b_k sin(kUφ) (k = 1..K) to samples.

    Linear least squares (one QR for all orders), ω and υ separately. ``phi`` (rad) must
    cover at least one wave period 2π/U (spacing included: n samples spaced h cover n·h);
    samples need not be uniform or sorted. ``waves`` is U; ``tier`` is passed on to the
    model.

    ``order=None`` picks K in 1..max_order. Default ``criterion="noise"``: the smallest K
    whose RMSE (√(SSE/(n − p))) is within a factor 1.05 of the noise floor, for ω and υ
    both; the noise floor of a component is its RMSE at the highest order tried (an
    unbiased estimate of σ if that order holds all the signal), floored at 1e-13·max|f| so
    that exact data stop at the smallest exact order. ``criterion="aicc"``: the smallest
    corrected Akaike information criterion on the combined residuals,
    AICc(K) = Σ_{ω,υ} [n ln(SSE/n) + 2k + 2k(k+1)/(n−k−1)], k = coefficients + 1 (a noise
    variance per component; ω has K + 1 coefficients, υ has K; SSE floored as above).
    AICc adds a harmonic it does not need in ~20 % of noisy samples (3 true harmonics, σ =
    1 µm, 720 samples); the noise rule did not in 400 trials, hence the default. Both
    criteria are computed for every order and kept in ``selection``. Orders whose design
    matrix is rank-deficient (aliasing: too few samples per period) or that leave
    n − k − 1 ≤ 0 are skipped; a pick equal to ``max_order`` is reported in ``warnings``.

    The fit assumes symmetry (ω even, υ odd about the major axis); asymmetric data shows
    up as a large RMSE, not as sine terms in ω.

    >>> phi = np.linspace(0.0, np.pi, 90, endpoint=False)   # one wave period is enough
    >>> fit_fourier(phi, np.cos(2 * phi), -0.5 * np.sin(2 * phi)).order
    1
    >>> fit_fourier(phi[:40], np.cos(2 * phi[:40]), np.sin(2 * phi[:40]))
    Traceback (most recent call last):
    ...
    profilegen.geometry.series.SeriesError: phi: the samples cover 1.396 rad, less than one wave period 2π/U = 3.142 rad (waves = 2)
    """
    start = time.perf_counter()
    waves = _whole("waves", waves, 1)
    max_order = _whole("max_order", max_order, 1)
    if order is not None:
        order = _whole("order", order, 1)
    if criterion not in CRITERIA:
        raise SeriesError(f"criterion = {criterion!r}: must be one of {', '.join(CRITERIA)}")
    tier = _tier(tier)
    phi, omega, upsilon = _wave_samples(phi, omega, upsilon, waves)
    n = phi.size
    top, warnings = _highest_order(n, order, max_order)
    x_omega, x_upsilon = _fourier_design(phi, waves, top)
    ls_w, ls_u = _NestedLeastSquares(x_omega, omega), _NestedLeastSquares(x_upsilon, upsilon)
    floor_w = n * (_FLOOR_REL * max(float(np.max(np.abs(omega))), 1e-150)) ** 2
    floor_u = n * (_FLOOR_REL * max(float(np.max(np.abs(upsilon))), 1e-150)) ** 2
    selection = _select_order(ls_w, ls_u, omega, upsilon, order=order, top=top, waves=waves, criterion=criterion,
                              floors=(floor_w, floor_u), warnings=warnings)
    best, used = selection.picked, selection.criterion

    coef_w, fitted_w, cov_w = ls_w.solve(best + 1)
    coef_u, fitted_u, cov_u = ls_u.solve(best)
    model = HarmonicDeformation(
        waves=waves,
        cos_mm=coef_w[1:],
        sin_mm=coef_u,
        mean_mm=float(coef_w[0]),
        tier=tier,
        source=f"Fourier fit, {best} harmonic(s) of U = {waves}, {n} samples",
    )
    stats_w = _stats(phi, omega, fitted_w, best + 1, lambda p, o: model.evaluate(p, o)[0])
    stats_u = _stats(phi, upsilon, fitted_u, best, lambda p, o: model.evaluate(p, o)[1])
    se_w = stats_w.rmse_mm * np.sqrt(cov_w)
    se_u = stats_u.rmse_mm * np.sqrt(cov_u)
    elapsed = time.perf_counter() - start
    log.debug("Fourier fit: order %d (%s), RMSE ω %.3g mm, υ %.3g mm, %.3g s", best, used,
              stats_w.rmse_mm, stats_u.rmse_mm, elapsed)
    return DeformationFit(
        model=model,
        omega_stats=stats_w,
        upsilon_stats=stats_u,
        mean_se_mm=float(se_w[0]),
        cos_se_mm=se_w[1:],
        sin_se_mm=se_u,
        selection=selection,
        time_s=elapsed,
        warnings=tuple(warnings),
    )


def _wave_samples(phi, omega, upsilon, waves: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """φ, ω and υ as checked sample arrays of one length; φ must cover one wave period 2π/U."""
    phi = _samples("phi", phi, "rad")
    n = phi.size
    omega = _samples("omega", omega, "mm", n)
    upsilon = _samples("upsilon", upsilon, "mm", n)
    if n < 2:
        raise SeriesError(f"phi: {n} samples; need more samples than parameters (≥ 3 for one harmonic)")
    period = TWO_PI / waves
    covered = float(phi.max() - phi.min()) * n / (n - 1)
    if covered < period * (1.0 - 1e-9):
        raise SeriesError(
            f"phi: the samples cover {covered:.4g} rad, less than one wave period 2π/U = {period:.4g} rad "
            f"(waves = {waves})"
        )
    return phi, omega, upsilon


def _highest_order(n: int, order: int | None, max_order: int) -> tuple[int, list[str]]:
    """The highest order to try with ``n`` samples (``order`` when given), and a warning when
    the samples lower ``max_order``."""
    warnings: list[str] = []
    if order is not None:
        if n <= order + 1:
            raise SeriesError(
                f"phi: {n} samples, not more than the {order + 1} parameters of ω at order = {order}; "
                f"need ≥ {order + 2} samples"
            )
        return order, warnings
    top = min(max_order, n - 4)  # AICc needs n − k − 1 > 0 for ω: k = K + 2
    if top < 1:
        raise SeriesError(
            f"phi: {n} samples, too few to choose an order (≥ 5 needed for one harmonic); "
            f"give more samples or an explicit order"
        )
    if top < max_order:
        warnings.append(f"max_order = {max_order} reduced to {top} by the number of samples ({n})")
    return top, warnings


def _select_order(ls_w: _NestedLeastSquares, ls_u: _NestedLeastSquares, omega: np.ndarray, upsilon: np.ndarray, *,
                  order: int | None, top: int, waves: int, criterion: str, floors: tuple[float, float],
                  warnings: list[str]) -> OrderSelection:
    """Every order up to ``top`` (only ``order`` when given) scored by RMSE and AICc, and the
    pick by ``criterion``; what it skipped or where it stopped goes to ``warnings``."""
    n = omega.size
    floor_w, floor_u = floors
    orders, aiccs, rmse_w, rmse_u, skipped = [], [], [], [], []
    for k in range(1 if order is None else order, top + 1):
        if not (ls_w.full_rank(k + 1) and ls_u.full_rank(k)):
            skipped.append(k)
            continue
        sse_w = float(np.sum((omega - ls_w.solve(k + 1)[1]) ** 2))
        sse_u = float(np.sum((upsilon - ls_u.solve(k)[1]) ** 2))
        orders.append(k)
        aiccs.append(_aicc(sse_w, n, k + 1, floor_w) + _aicc(sse_u, n, k, floor_u) if n - k - 3 > 0 else math.nan)
        rmse_w.append(math.sqrt(sse_w / (n - k - 1)))
        rmse_u.append(math.sqrt(sse_u / (n - k)))
    if skipped:
        if order is not None:
            raise SeriesError(
                f"order = {order}: the design matrix is rank-deficient for these {n} samples "
                f"(harmonic {order * waves}/turn aliases); give more samples per wave period or a lower order"
            )
        warnings.append(f"orders {skipped} skipped: rank-deficient design (too few samples per wave period)")
    if not orders:
        raise SeriesError(f"phi: no order in 1..{top} can be fitted to these {n} samples (rank-deficient)")

    rmse_w_arr, rmse_u_arr = np.array(rmse_w), np.array(rmse_u)
    noise_w = max(rmse_w[-1], math.sqrt(floor_w / n))
    noise_u = max(rmse_u[-1], math.sqrt(floor_u / n))
    within = (rmse_w_arr <= NOISE_FACTOR * noise_w) & (rmse_u_arr <= NOISE_FACTOR * noise_u)
    noise_pick = orders[int(np.argmax(within))]  # the last order is always within
    aicc_pick = orders[int(np.nanargmin(aiccs))] if np.any(np.isfinite(aiccs)) else orders[-1]
    if order is not None:
        best, used = order, "given"
    else:
        best, used = (noise_pick, "noise") if criterion == "noise" else (aicc_pick, "aicc")
        if best == orders[-1] and len(orders) > 1:
            warnings.append(
                f"order picked = {best}, the highest tried: the data hold more harmonics than max_order "
                f"(or are not periodic in 2π/U)"
            )
    return OrderSelection(
        criterion=used,
        picked=best,
        noise_pick=noise_pick,
        aicc_pick=aicc_pick,
        orders=np.asarray(orders),
        omega_rmse_mm=rmse_w_arr,
        upsilon_rmse_mm=rmse_u_arr,
        aicc=np.asarray(aiccs),
        omega_noise_floor_mm=noise_w,
        upsilon_noise_floor_mm=noise_u,
    )


# --------------------------------------------------------------------------- general sine series


def _sine_eval(amplitude, frequency, phase, phi, order: int) -> np.ndarray:
    """Σ a b^j sin(bφ + c + jπ/2) for j = 0..order, shape (order + 1, n)."""
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    arg = np.multiply.outer(phi, frequency) + phase  # (n, terms)
    s, c = np.sin(arg), np.cos(arg)
    out = np.empty((order + 1, phi.size))
    for j in range(order + 1):
        base = (s, c, -s, -c)[j % 4]  # sin(x + jπ/2)
        out[j] = base @ (amplitude * frequency**j)
    return out


@dataclass(frozen=True, slots=True, eq=False)
class SeriesFit:
    """A general sine series f(φ) = Σ a_i sin(b_i φ + c_i) fitted to one component.

    Canonical form: a_i ≥ 0, b_i ≥ 0, c_i in (−π, π], terms sorted by decreasing a_i.
    b_i are in rad⁻¹ and in general not integers: f is then not 2π-periodic
    (``stats.defect_mm``). Diagnostics: ``stats``; of the ``n_starts`` nonlinear
    least-squares starts, ``n_success`` converged and ``n_at_best`` reached the best cost
    (within 1e-6 relative, or 1e-28 mm² absolute); ``cost_by_start`` (½ SSE);
    ``nfev`` (total residual evaluations); ``time_s``; ``warnings``.
    """

    amplitude_mm: np.ndarray
    frequency_per_rad: np.ndarray
    phase_rad: np.ndarray
    stats: FitStats
    n_starts: int
    n_success: int
    n_at_best: int
    nfev: int
    cost_by_start: np.ndarray
    time_s: float
    warnings: tuple[str, ...] = ()

    def __post_init__(self):
        for name in ("amplitude_mm", "frequency_per_rad", "phase_rad", "cost_by_start"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        object.__setattr__(self, "warnings", tuple(self.warnings))

    @property
    def terms(self) -> int:
        return int(self.amplitude_mm.size)

    def evaluate(self, phi, order: int = 3) -> np.ndarray:
        """f and its derivatives 0..order at φ (rad), shape (order + 1, n), mm (per radᵏ)."""
        return _sine_eval(self.amplitude_mm, self.frequency_per_rad, self.phase_rad, phi, _check_order(order))

    def to_dict(self) -> dict:
        return {
            "kind": "sine series",
            "amplitude_mm": self.amplitude_mm.tolist(),
            "frequency_per_rad": self.frequency_per_rad.tolist(),
            "phase_rad": self.phase_rad.tolist(),
            "stats": self.stats.to_dict(),
            "n_starts": self.n_starts,
            "n_success": self.n_success,
            "n_at_best": self.n_at_best,
            "nfev": self.nfev,
            "cost_by_start": [_json_float(v) for v in self.cost_by_start],
            "time_s": self.time_s,
            "warnings": list(self.warnings),
        }


@dataclass(frozen=True, slots=True, eq=False)
class GeneralSineDeformation:
    """Deformation model from two general sine series: ω = omega_fit, υ = upsilon_fit.

    Not symmetric in general (``symmetric`` is False) and not periodic unless every
    frequency is an integer: see ``defect_mm``. φ is used as given, not wrapped into the
    sampled range, so ω(φ + 2π) ≠ ω(φ) in general.
    """

    omega_fit: SeriesFit
    upsilon_fit: SeriesFit
    waves: int
    tier: str = "verify"

    def __post_init__(self):
        for name in ("omega_fit", "upsilon_fit"):
            value = getattr(self, name)
            if not isinstance(value, SeriesFit):
                raise SeriesError(f"{name}: must be a SeriesFit (from fit_sine_series), got {type(value).__name__}")
        object.__setattr__(self, "waves", _whole("waves", self.waves, 1))
        _tier(self.tier)

    @property
    def symmetric(self) -> bool:
        return False

    @property
    def defect_mm(self) -> tuple[float, float]:
        """(ω(2π) − ω(0), υ(2π) − υ(0)) in mm."""
        return self.omega_fit.stats.defect_mm, self.upsilon_fit.stats.defect_mm

    def evaluate(self, phi, order: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """ω and υ with derivatives 0..order at φ (rad), each (order + 1, n), mm."""
        return self.omega_fit.evaluate(phi, order), self.upsilon_fit.evaluate(phi, order)

    def to_dict(self) -> dict:
        return {
            "tier": self.tier,
            "source": "general sine series",
            "waves": self.waves,
            "symmetric": False,
            "omega": self.omega_fit.to_dict(),
            "upsilon": self.upsilon_fit.to_dict(),
        }


def _unpack(x, terms):
    """Parameters x = [α_1, β_1, b_1, α_2, ...]: f = Σ α sin bφ + β cos bφ."""
    x = x.reshape(terms, 3)
    return x[:, 0], x[:, 1], x[:, 2]


def _linear_amplitudes(phi, y, freqs):
    """Least-squares α, β for fixed frequencies (f = Σ α sin bφ + β cos bφ)."""
    arg = np.multiply.outer(phi, freqs)
    x = np.hstack([np.sin(arg), np.cos(arg)])
    coef = np.linalg.lstsq(x, y, rcond=None)[0]
    return coef[: freqs.size], coef[freqs.size :], y - x @ coef


def _single_sse(phi, y, b):
    return float(np.sum(_linear_amplitudes(phi, y, np.array([b]))[2] ** 2))


def _spectrum(phi, y, pad: int = 16):
    """Amplitude spectrum of y resampled on a uniform grid (zero-padded FFT); ω in rad⁻¹."""
    order = np.argsort(phi)
    x, v = phi[order], y[order]
    m = max(x.size, 64)
    grid = np.linspace(x[0], x[-1], m)
    h = grid[1] - grid[0]
    values = np.interp(grid, x, v) * np.hanning(m)
    amp = np.abs(np.fft.rfft(values, n=pad * m))
    freq = TWO_PI * np.fft.rfftfreq(pad * m, d=h)
    return freq, amp, TWO_PI / (m * h)  # one bin of the unpadded record


def _peaks(freq, amp, count):
    inner = np.flatnonzero((amp[1:-1] >= amp[:-2]) & (amp[1:-1] >= amp[2:])) + 1
    idx = np.concatenate([[0] if amp[0] >= amp[1] else [], inner]).astype(int)
    idx = idx[np.argsort(amp[idx])[::-1]][:count]
    return freq[idx]


def _refine(phi, y, b0, width, b_max):
    lo, hi = max(0.0, b0 - width), min(b_max, b0 + width)
    if hi <= lo:
        return b0
    res = minimize_scalar(lambda b: _single_sse(phi, y, b), bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-10 * max(1.0, b0)})
    return float(res.x) if res.fun <= _single_sse(phi, y, b0) else b0


def _pursuit(phi, y, count, b_max):
    """Matching pursuit: take the strongest FFT peak of the residual, refine its frequency,
    refit all amplitudes, repeat ``count`` times; the frequencies in the order found."""
    freqs = []
    resid = y
    for _ in range(count):
        freq, amp, res = _spectrum(phi, resid)
        b = _refine(phi, resid, float(_peaks(freq, amp, 1)[0]), res, b_max)
        freqs.append(b)
        resid = _linear_amplitudes(phi, y, np.array(freqs))[2]
    return np.array(freqs)


class _Projection:
    """Variable projection of f = Σ α_i sin b_iφ + β_i cos b_iφ onto the frequencies b:
    the residual r(b) = y − A(b)c(b) of the linear least-squares amplitudes c = A⁺y
    (A = [sin bφ, cos bφ], n × 2·terms) and its exact Jacobian ∂r/∂b (Golub & Pereyra 1973).

    c is the solution ``np.linalg.lstsq(A, y, rcond=None)`` gives: by a Householder QR of A
    (LAPACK geqrf/orgqr, A = QR) when every singular value of R (those of A) exceeds
    lstsq's cut eps·max(n, 2·terms)·s_max, else — frequencies (nearly) coinciding — by the
    SVD A = (QW) S Vᵀ (R = W S Vᵀ) without the cut values, the minimum-norm solution.
    With U an orthonormal basis of A's (kept) column space, P⊥ = I − UUᵀ and
    D_k = ∂A/∂b_k (nonzero only in the two columns of term k):

        ∂r/∂b_k = −(P⊥ D_k c + (A⁺)ᵀ D_kᵀ r),   (A⁺)ᵀ = Q R⁻ᵀ  (or U S⁻¹ Vᵀ),

    D_k c = φ (α_k cos b_kφ − β_k sin b_kφ), D_kᵀ r = (φ cos b_kφ · r, −φ sin b_kφ · r) at
    rows k, terms + k. The factors of the last two points are kept: the optimizer asks the
    Jacobian at a point whose residual it has just evaluated.
    """

    def __init__(self, phi, y, terms):
        self.phi, self.y, self.terms = phi, y, terms
        k = 2 * terms
        self.cut = np.finfo(float).eps * max(phi.size, k)
        self._upper = np.triu(np.ones((k, k)))
        self._cache = []  # [(b, state)] of the last two points
        self.factorizations = 0

    def _state(self, b):
        key = b.tobytes()
        for cached, state in self._cache:
            if cached == key:
                return state
        self.factorizations += 1
        t, y = self.terms, self.y
        trig = np.empty((2 * t, self.phi.size))  # rows sin b_kφ, then cos b_kφ: A = trig.T, Fortran order
        arg = np.multiply.outer(b, self.phi)
        np.sin(arg, out=trig[:t])
        np.cos(arg, out=trig[t:])
        qr, tau, _, info = lapack.dgeqrf(trig.T)
        r = qr[: 2 * t]  # R in its upper triangle (trtri, trtrs read no more)
        r_inv, info_inv = lapack.dtrtri(r)
        if info == 0 and info_inv == 0 and self._full_rank(r, r_inv):
            q, _, info = lapack.dorgqr(qr, tau)
            qty = q.T @ y
            r_inv *= self._upper  # trtri leaves the strict lower triangle as it was
            state = (trig, q, r_inv, None, None, lapack.dtrtrs(r, qty)[0], y - q @ qty)
        else:  # rank cut: the minimum-norm solution of the kept singular triplets
            q, r = np.linalg.qr(trig.T)
            w, sv, vt = np.linalg.svd(r)
            keep = sv > self.cut * sv[0]
            u = q @ w[:, keep]
            uty = u.T @ y
            coef = vt[keep].T @ (uty / sv[keep])
            state = (trig, u, None, sv[keep], vt[keep], coef, y - u @ uty)
        self._cache = [(key, state)] + self._cache[:1]
        return state

    def _full_rank(self, r, r_inv) -> bool:
        """Whether lstsq would keep every singular value of R (upper triangle of ``r``; its
        inverse in that of ``r_inv``): σ_min ≥ 1/‖R⁻¹‖_F and σ_max ≤ ‖R‖_F, so when that ratio
        clears the cut, so does σ_min/σ_max; else decide by the singular values."""
        a, b = r * self._upper, r_inv * self._upper
        if float(np.vdot(a, a)) * float(np.vdot(b, b)) * self.cut**2 < 1.0:
            return True
        _, sv, _, info = lapack.dgesdd(a, compute_uv=0)
        return info == 0 and sv[-1] > self.cut * sv[0]

    def amplitudes(self, b):
        """α, β and the residual y − f at frequencies b (the minimum-norm least-squares α, β)."""
        coef, resid = self._state(b)[5:]
        return coef[: self.terms], coef[self.terms :], resid

    def residual(self, b):
        return self._state(b)[6]

    def jacobian(self, b):
        trig, u, r_inv, sv, vt, coef, resid = self._state(b)
        t, phi = self.terms, self.phi
        s, c = trig[:t], trig[t:]  # (t, n)
        g = (c * coef[:t, None] - s * coef[t:, None]) * phi  # row k: (D_k c)ᵀ
        pr = phi * resid
        d_sin, d_cos = c @ pr, -(s @ pr)  # D_kᵀ r = d_sin[k] e_k + d_cos[k] e_{t+k}
        # (A⁺)ᵀ D_kᵀ r = U z_k with z_k = Mᵀ D_kᵀ r = d_sin[k] M[k] + d_cos[k] M[t + k] (rows of M),
        # M = R⁻¹ (A = QR) or M = (S⁻¹Vᵀ)ᵀ (A = USVᵀ)
        m = r_inv if r_inv is not None else (vt / sv[:, None]).T
        zt = d_sin[:, None] * m[:t] + d_cos[:, None] * m[t:]  # row k: z_k
        # ∂r/∂b_k = −(P⊥ D_k c + (A⁺)ᵀ D_kᵀ r) = U (Uᵀ D_k c − z_k) − D_k c
        jac = (g @ u - zt) @ u.T  # (t, n): the Jacobian's transpose, so .T is Fortran order for MINPACK
        jac -= g
        return jac.T


def _residual_and_jacobian(phi, y, terms):
    cache = {}

    def trig(x):
        key = x.tobytes()
        if key not in cache:
            cache.clear()
            arg = np.multiply.outer(phi, x.reshape(terms, 3)[:, 2])
            cache[key] = (np.sin(arg), np.cos(arg))
        return cache[key]

    def residual(x):
        alpha, beta, _ = _unpack(x, terms)
        s, c = trig(x)
        return s @ alpha + c @ beta - y

    def jacobian(x):
        alpha, beta, _ = _unpack(x, terms)
        s, c = trig(x)
        jac = np.empty((phi.size, terms, 3))
        jac[:, :, 0] = s
        jac[:, :, 1] = c
        jac[:, :, 2] = phi[:, None] * (alpha * c - beta * s)
        return jac.reshape(phi.size, 3 * terms)

    return residual, jacobian


def _lm(fun, jac, x0, max_nfev):
    """MINPACK's Levenberg–Marquardt (lmder) from x0 to tolerance 1e-15: (x, ½SSE, nfev, converged).

    The run ``least_squares(fun, x0, jac=jac, method="lm", x_scale="jac", ftol=xtol=gtol=1e-15,
    max_nfev=max_nfev)`` makes (the same iterates, bit for bit: it calls the same lmder with
    diag=None, factor=100), through ``leastsq``, which skips least_squares' per-call wrapper
    (≈ a third of the time of these small residuals). "Converged" is MINPACK's info 1–4 (a
    tolerance met), least_squares' status > 0; with tolerances above eps, info 6–8 cannot occur.
    """
    x, _, info, _, ier = leastsq(fun, x0, Dfun=jac, full_output=True, ftol=1e-15, xtol=1e-15, gtol=1e-15,
                                 maxfev=max_nfev)
    f = info["fvec"]
    return x, 0.5 * float(f @ f), int(info["nfev"]), ier in (1, 2, 3, 4)


def fit_sine_series(phi: ArrayLike, values: ArrayLike, *, terms: int = 3, starts: int = 20, seed: int | None = 0,
                    _reference: bool = False) -> SeriesFit:
    """Fit seed 004's f(φ) = Σ_{i=1..terms} a_i sin(b_i φ + c_i) to samples (mm).

    Nonlinear least squares by MINPACK's Levenberg–Marquardt (lmder, as
    ``scipy.optimize.least_squares(method="lm")`` runs it) in the form
    Σ α_i sin b_iφ + β_i cos b_iφ. Each of the ``starts`` starting frequency sets is first
    solved by variable projection (only the b_i are iterated; α_i, β_i by linear least
    squares, a QR of the sin/cos matrix, at every step; the exact Golub–Pereyra Jacobian of
    the projected residual), then the best one is polished in all 3·terms parameters with
    the analytic Jacobian. (``_reference=True``: the variable projection of the first version,
    ``np.linalg.lstsq`` and a finite-difference Jacobian — 3–4× the CPU time, the same fit
    to rounding; kept for tests/benchmarks/sine_fit.py.) Starting frequencies come from FFT peaks:
    matching pursuit takes the strongest peak of the residual's spectrum, refines its
    frequency by a 1-D search, refits the amplitudes and repeats (2·terms + 2 times).
    Start 0 is its first ``terms`` frequencies; odd starts draw ``terms`` of the pursuit
    frequencies at random (``seed``), even starts jitter start 0, each by up to half a
    frequency bin. The lowest SSE wins. Needs more samples than the 3·terms parameters.

    The result is not periodic in general (docs/theory/rim.md, "The fit"); see ``stats.defect_mm``.
    Pair an ω and a υ fit with :class:`GeneralSineDeformation` for the kinematics.

    >>> phi = np.linspace(0.0, 2 * np.pi, 200, endpoint=False)
    >>> fit = fit_sine_series(phi, 0.3 * np.sin(2.5 * phi + 0.4), terms=1, starts=3)
    >>> np.round([fit.amplitude_mm[0], fit.frequency_per_rad[0], fit.phase_rad[0]], 12).tolist()
    [0.3, 2.5, 0.4]
    >>> round(fit.stats.defect_mm, 6)   # 0.3 (sin(5π + 0.4) − sin 0.4)
    -0.233651
    """
    start_time = time.perf_counter()
    terms = _whole("terms", terms, 1)
    starts = _whole("starts", starts, 1)
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, numbers.Integral)):
        raise SeriesError(f"seed = {seed!r}: must be a whole number or None")
    phi, values, span = _sine_samples(phi, values, terms)
    n, n_params = phi.size, 3 * terms
    b_max = math.pi * (n - 1) / span  # Nyquist of the mean spacing
    initial = _start_frequencies(phi, values, terms, starts, seed, span, b_max)
    projection = _Projection(phi, values, terms)
    best_b, best_cost, costs, n_success, nfev = _best_start(projection, initial, _reference)
    x, evals = _polished(projection, best_b, best_cost, _reference)
    nfev += evals
    amplitude, b, phase = _sine_terms(x, terms)

    costs_arr = np.array(costs)
    tol = max(1e-6 * best_cost, 1e-28)
    n_at_best = int(np.sum(costs_arr <= best_cost + tol))
    warnings = []
    if n_at_best < 2 and starts > 1:
        warnings.append(f"only 1 of {starts} starts reached the best SSE: the minimum may not be global")
    if np.any(b >= b_max * (1.0 - 1e-6)):  # at Nyquist a sine vanishes at every sample: any amplitude fits
        warnings.append(f"a frequency reaches the sampling Nyquist {b_max:.4g} rad⁻¹: aliased term")

    fitted = _sine_eval(amplitude, b, phase, phi, 0)[0]
    stats = _stats(phi, values, fitted, n_params, lambda p, o: _sine_eval(amplitude, b, phase, p, o))
    elapsed = time.perf_counter() - start_time
    log.debug("sine series: %d terms, RMSE %.3g mm, defect %.3g mm, %d/%d starts at best, %.3g s",
              terms, stats.rmse_mm, stats.defect_mm, n_at_best, starts, elapsed)
    return SeriesFit(
        amplitude_mm=amplitude,
        frequency_per_rad=b,
        phase_rad=phase,
        stats=stats,
        n_starts=starts,
        n_success=n_success,
        n_at_best=n_at_best,
        nfev=nfev,
        cost_by_start=costs_arr,
        time_s=elapsed,
        warnings=tuple(warnings),
    )


def _sine_samples(phi, values, terms: int) -> tuple[np.ndarray, np.ndarray, float]:
    """φ and the values as checked sample arrays, more of them than the 3·terms parameters, and
    the range of φ they span (> 0)."""
    phi = _samples("phi", phi, "rad")
    n = phi.size
    values = _samples("values", values, "mm", n)
    n_params = 3 * terms
    if n <= n_params:
        raise SeriesError(
            f"phi: {n} samples, not more than the {n_params} parameters of {terms} sine terms; "
            f"need ≥ {n_params + 1} samples (or fewer terms)"
        )
    span = float(phi.max() - phi.min())
    if span <= 0.0:
        raise SeriesError("phi: all samples at the same angle; need a range of φ (rad)")
    return phi, values, span


def _start_frequencies(phi, values, terms: int, starts: int, seed, span: float, b_max: float) -> list[np.ndarray]:
    """The ``starts`` starting frequency sets: the pursuit's first ``terms`` frequencies, then
    alternately a random draw from the pursuit's (odd) and those jittered (even), each by up to
    half a frequency bin."""
    rng = np.random.default_rng(seed)
    resolution = TWO_PI / span  # one bin of the record
    pool = _pursuit(phi, values, 2 * terms + 2, b_max)
    greedy = pool[:terms]
    initial = [greedy]
    for i in range(1, starts):
        b = rng.choice(pool, size=terms, replace=False) if i % 2 else greedy
        initial.append(np.abs(b + rng.uniform(-0.5, 0.5, terms) * resolution))
    return initial


def _best_start(projection: _Projection, initial: list[np.ndarray], reference: bool) -> tuple:
    """Each start solved by variable projection (only the frequencies iterated): the best
    frequencies, their cost, the cost of every start, how many converged, the evaluations."""
    phi, values, terms = projection.phi, projection.y, projection.terms

    def projected(b):  # the first version's fitter (_reference): SVD least squares, finite-difference Jacobian
        return _linear_amplitudes(phi, values, b)[2]

    best_b, best_cost = None, math.inf
    costs, n_success, nfev = [], 0, 0
    for b0 in initial:
        if reference:
            res = least_squares(projected, b0, method="lm", x_scale="jac", ftol=1e-15, xtol=1e-15, gtol=1e-15,
                                max_nfev=100 * (terms + 1))
            x, cost, evals, converged = res.x, float(res.cost), int(res.nfev), res.status > 0
        else:
            x, cost, evals, converged = _lm(projection.residual, projection.jacobian, b0, 100 * (terms + 1))
        nfev += evals
        n_success += int(converged)
        cost = cost if np.all(np.isfinite(x)) and math.isfinite(cost) else math.inf
        costs.append(cost)
        if cost < best_cost:
            best_b, best_cost = x, cost
    if best_b is None:
        raise ConvergenceError(f"fit_sine_series: no start of {len(initial)} gave a finite fit ({terms} terms, "
                               f"{phi.size} samples)")
    return best_b, best_cost, costs, n_success, nfev


def _polished(projection: _Projection, best_b: np.ndarray, best_cost: float, reference: bool) -> tuple:
    """The best start polished in all parameters (α, β, b) with the analytic Jacobian (kept only
    when it lowers the cost): the parameters and the evaluations it took."""
    phi, values, terms = projection.phi, projection.y, projection.terms
    alpha, beta, _ = (_linear_amplitudes(phi, values, best_b) if reference else projection.amplitudes(best_b))
    x0 = np.column_stack([alpha, beta, best_b]).ravel()
    residual, jacobian = _residual_and_jacobian(phi, values, terms)
    if reference:
        polished = least_squares(residual, x0, jac=jacobian, method="lm", x_scale="jac",
                                 ftol=1e-15, xtol=1e-15, gtol=1e-15, max_nfev=50 * 3 * terms)
        x_pol, cost_pol, evals = polished.x, polished.cost, int(polished.nfev)
    else:
        x_pol, cost_pol, evals, _ = _lm(residual, jacobian, x0, 50 * 3 * terms)
    return (x_pol if cost_pol <= best_cost and np.all(np.isfinite(x_pol)) else x0), evals


def _sine_terms(x: np.ndarray, terms: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(amplitudes, frequencies ≥ 0, phases in (−π, π]) of the parameters (α, β, b), strongest term first."""
    alpha, beta, b = _unpack(x, terms)
    amplitude = np.hypot(alpha, beta)
    phase = np.arctan2(beta, alpha)
    negative = b < 0  # a sin(−|b|φ + c) = a sin(|b|φ − c + π)
    b = np.abs(b)
    phase = np.where(negative, math.pi - phase, phase)
    phase = math.pi - np.remainder(math.pi - phase, TWO_PI)  # wrap to (−π, π]
    order = np.argsort(-amplitude, kind="stable")
    return amplitude[order], b[order], phase[order]
