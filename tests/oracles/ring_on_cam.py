"""Ring-theory oracle: the thin inextensible ring pressed by a cam, with partial wrap.

Classical linear theory of thin circular rings (Timoshenko & Gere, *Theory of Elastic
Stability*, §7.1–7.2; Timoshenko & Goodier / Roark's ring formulas; the inextensible-ring
assumption of harmonic-drive theory, seed 004's ω = w0 cos 2φ), solved as a unilateral
contact (obstacle) problem on a rigid wave-generator contour (:mod:`profilegen.geometry.wavegen`).

Notation (docs/reference/conventions.md): R = r_m the neutral radius, δ the rim thickness, r_b = R − δ/2 the
bore, EI = Eδ³/12 the bending stiffness per mm of face width (plane stress, as the FEM),
U the wave count, φ from the major axis, ω radial (outward +), υ tangential (+ toward
increasing φ), ′ = d/dφ, L = d²/dφ² + 1.

Equations
---------
* Inextensible neutral line (linear kinematics): ε = (υ′ + ω)/R = 0, so υ′ = −ω,
  υ(0) = 0 (υ odd) and ∫ω dφ = 0 over a wave period P = 2π/U (υ periodic).
* Curvature change Δκ = −(ω″ + ω)/R² (the major-axis ends bend tighter); bending energy
  (EI/2R³)∫(Lω)² dφ. Frictionless cam: radial pressure p only. Stationarity of
  energy − work − λ·∫ω (λ the hoop-force multiplier of the inextensibility constraint)
  gives EI/R⁴ · L²ω = p + λ/R, L²ω = ω⁗ + 2ω″ + ω.
* Free zone (p = 0), symmetric about the minor axis ψ = φ − π/U = 0:
  L²ω = a0 ⇒ ω = a0 + a1 cos ψ + a2 ψ sin ψ (Lω = a0 + 2a2 cos ψ: the moment is
  A + B cos ψ, M″ + M = const).
* Contact zone |φ| ≤ α (and its images every P): the bore follows the contour,
  ω = f(φ). ``contact="first_order"``: f = ρ(φ) − r_b with ρ = ``contour.radius`` (the
  linearised statement). ``contact="exact_gap"`` (default): the bore point of the linear
  kinematics, (r_b + ω) e_r + υ_b e_θ with υ_b = υ + z(υ − ω′)/R, z = −δ/2 (Kirchhoff),
  lies *exactly* on the contour: √((r_b + f)² + υ_b²) = ρ(φ + atan2(υ_b, r_b + f)), with υ, ω′
  those of f itself (fixed point). This is the model of the linear FEM
  (:func:`profilegen.rim.ring.solve_ring`: small strain, exact gap) and the one it converges to.
* Pressure p = EI/R⁴ (L²f − a0) ≥ 0 in the contact zone; at φ = α, ω, ω′, ω″ are continuous
  (the moment is continuous; smooth fit of the obstacle problem), ω‴ may jump: an edge line
  force F = EI [ω‴]/R³ ≥ 0 ([·] = free side − contact side). The free part must not
  penetrate: g = ω − f ≥ 0 for α < φ < P − α.
* Unknowns a0, a1, a2, α: three continuity conditions (linear in a) and ∫₀^{P/2} ω dφ = 0
  (a scalar root in α).

Why the wrap is partial, and why it is ill-conditioned
--------------------------------------------------------
To first order, a contour whose perimeter equals the bore's (``from_gearset``) has
mean(ρ − r_b) = 0, and ∫ω = 0 with g ≥ 0 then forces *full* wrap: the partial wrap is
decided by O(w0²/R) terms. The polar radius of such a contour has
mean(ρ − r_b) = −mean(ρ′²/2ρ) ≈ −w0²/R, and the linear kinematics lengthens the neutral line by
∫(ω′ − υ)²/2R dφ (≈ (9/16)w0²/R in mean radius for ω = w0 cos 2φ), so the two models differ:
on the default set α ≈ 30.9° (first_order) and 37.7° (exact_gap; the FEM gives 38.0°). A
geometrically exact inextensible ring cannot lift off a contour of equal perimeter at all
(an enclosing closed curve of the same length coincides with it): the partial wrap of the
linear models is an artefact of their kinematics, µm in size (docs/theory/rim.md: the gap of
the free part, and the ~7 µm effect of geometric nonlinearity). Because the free span
2(P/2 − α) grows like (mismatch/w0)^(1/7), α moves by degrees per µm of mean radius;
:attr:`OracleResult.wrap_sensitivity_deg_per_um` reports it.

Accuracy: thin-ring theory, errors O((δ/R)²) (shear, thickness, extensibility) relative to
w0; the exact_gap contact keeps the O(w0²/R) terms of the contact geometry (errors
O(w0³/R²)). The FEM and the oracle agree to (δ/R)² only where (δ/R)² ≪ w0/R: below that the
wrap is decided by the thick-ring terms the oracle does not have.

>>> from profilegen.geometry.wavegen import CosineCam
>>> res = full_wrap_on_cam(CosineCam(49.0, 0.5), 49.5, 1.0)
>>> (np.round(res.omega([0.0, math.pi / 4, math.pi / 2]), 12) + 0.0).tolist(), res.wrap_angle_deg
([0.5, 0.0, -0.5], 90.0)
>>> round(float(res.upsilon(math.pi / 4)[0]), 12)  # −(w0/2) sin 2φ
-0.25
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import partial

import numpy as np

from profilegen import checks
from profilegen.errors import ConvergenceError, ProfilegenError
from profilegen.rim.ring import WRAP_WARNING, RingError
from profilegen.results import readonly as _readonly

__all__ = [
    "InadmissibleContactError",
    "OracleResult",
    "RingError",
    "full_wrap_on_cam",
    "inextensible_ring_on_cam",
]

CONTACT_MODELS = ("exact_gap", "first_order")
_SAMPLES = 512  # contour samples per wave period (cosine series of up to 256 harmonics)
_CHECK = 2001  # grid for the sign checks of p and g

_number = partial(checks.number, error=RingError)
_whole = partial(checks.whole, error=RingError)


class InadmissibleContactError(ProfilegenError, ValueError):
    """The contour admits no single contact zone per half wave with p ≥ 0, F ≥ 0 and no
    penetration (or an inextensible ring cannot be mounted on it); names where and by how much."""



def _cos_series(values: np.ndarray, what: str, reference_mm: float) -> np.ndarray:
    """Coefficients F_k of Σ F_k cos(U k φ) from samples on one period; checks evenness and decay."""
    n = values.size
    spec = np.fft.rfft(values) / n
    coef = 2.0 * spec.real
    coef[0] = spec[0].real
    if n % 2 == 0:
        coef[-1] = spec[-1].real
    scale = max(float(np.max(np.abs(coef[1:]))), 1e-300)
    odd = float(np.max(np.abs(spec.imag)))
    if odd > 1e-9 * scale:
        raise RingError(f"contour = {what}: its radius must be even about the major axis and periodic with period "
                        f"2π/U (sine content {odd:.3g} mm)")
    if float(np.max(np.abs(coef[n // 8:]))) > 1e-11 * scale:
        raise RingError(f"contour = {what}: its radius is not smooth enough for a {n // 8}-harmonic cosine series "
                        f"(tail {float(np.max(np.abs(coef[n // 8:]))):.3g} mm)")
    # drop the rounding noise of the samples (|ρ − r_b| ~ w0 from ρ ~ r_b: ~1e-14 r_b), which
    # L² = (1 − k²)² would amplify by k⁴
    floor = 1e-14 * max(float(np.max(np.abs(values))), reference_mm)
    keep = int(np.max(np.flatnonzero(np.abs(coef) > floor), initial=1)) + 1
    return coef[:keep].copy()


def _series(coef: np.ndarray, waves: int, phi: np.ndarray, derivative: int) -> np.ndarray:
    """d^n/dφ^n of Σ F_k cos(U k φ); derivative = −1 is the integral from 0 without the F_0 φ term."""
    k = waves * np.arange(coef.size, dtype=float)
    arg = np.multiply.outer(phi, k)
    if derivative == -1:
        kk = np.where(k == 0.0, 1.0, k)
        return np.sin(arg) @ (coef / kk * (k != 0.0))
    if derivative == 4:  # L²: (1 − k²)² for the operator ω⁗ + 2ω″ + ω
        return np.cos(arg) @ (coef * (1.0 - k**2) ** 2)
    factor = k**derivative
    trig = (np.cos, lambda x: -np.sin(x), lambda x: -np.cos(x), np.sin)[derivative]
    return trig(arg) @ (coef * factor)


def _free_basis(psi, derivative: int) -> np.ndarray:
    """(1, cos ψ, ψ sin ψ) and their derivatives; derivative = −1: integrals from 0. Shape (3, ...)."""
    psi = np.asarray(psi, dtype=float)
    c, s, one, zero = np.cos(psi), np.sin(psi), np.ones_like(psi), np.zeros_like(psi)
    rows = {
        -1: (psi, s, s - psi * c),
        0: (one, c, psi * s),
        1: (zero, -s, s + psi * c),
        2: (zero, -c, 2.0 * c - psi * s),
        3: (zero, s, -3.0 * s - psi * c),
    }[derivative]
    return np.array(rows)


def _contact_shape(contour, r_b: float, r_m: float, waves: int, model: str) -> tuple[np.ndarray, int]:
    """Cosine series of f(φ), the radial displacement that puts the bore on the contour."""
    period = 2.0 * math.pi / waves
    phi = np.arange(_SAMPLES) * period / _SAMPLES
    try:
        rho = np.asarray(contour.radius(phi), dtype=float).reshape(phi.shape)
    except (AttributeError, TypeError, ValueError) as exc:
        raise RingError(f"contour = {contour!r}: must be a wave-generator contour with radius(theta) (mm)") from exc
    if not np.all(np.isfinite(rho)):
        raise RingError(f"contour = {contour!r}: radius(theta) must be finite (mm)")
    f = rho - r_b
    if not f[0] > 0.0:
        raise RingError(f"contour = {contour!r}: its major radius {rho[0]:.9g} mm must exceed the bore radius "
                        f"r_m − δ/2 = {r_b:.9g} mm (the cam must push the rim out)")
    if model == "first_order":
        return _cos_series(f, repr(contour), r_b), 0
    z = r_b - r_m
    for outer in range(1, 41):
        coef = _cos_series(f, repr(contour), r_b)
        ups = -_series(coef, waves, phi, -1)
        ups_bore = ups + z * (ups - _series(coef, waves, phi, 1)) / r_m
        w = f
        for _ in range(60):
            polar = phi + np.arctan2(ups_bore, r_b + w)
            w_new = np.sqrt(np.asarray(contour.radius(polar), dtype=float) ** 2 - ups_bore**2) - r_b
            done = np.max(np.abs(w_new - w)) <= 4e-16 * r_b
            w = w_new
            if done:
                break
        change = float(np.max(np.abs(w - f)))
        f = w
        if change <= 4e-15 * r_b:
            return _cos_series(f, repr(contour), r_b), outer
    raise ConvergenceError(f"inextensible_ring_on_cam: exact-gap contact shape did not converge in 40 iterations "
                           f"(last change {change:.3g} mm)")


@dataclass(frozen=True, slots=True, eq=False)
class OracleResult:
    """Thin inextensible ring on a contour (mm, rad; pressures per unit EI unless E was given).

    ``shape_cos_mm``: F_k of the contact shape f(φ) = Σ F_k cos(U k φ) (ω in the contact zone).
    ``free_coefficients_mm``: (a0, a1, a2) of ω = a0 + a1 cos ψ + a2 ψ sin ψ, ψ = φ − π/U,
    in the free zone. ``edge_force_per_ei`` = F/EI (1/mm²) at each edge of contact (2U edges).
    ``min_pressure_per_ei`` (1/mm³) and ``min_gap_mm`` are the checked minima of p/EI in the
    contact zone and of g in the free zone. ``mean_mismatch_mm`` = F_0, the mean of f, whose
    sign decides the wrap (< 0 partial, = 0 full, > 0 not mountable).
    """

    contour: object
    neutral_radius_mm: float
    rim_thickness_mm: float
    waves: int
    contact: str
    youngs_modulus_mpa: float | None
    wrap_angle_rad: float
    shape_cos_mm: np.ndarray
    free_coefficients_mm: np.ndarray
    edge_force_per_ei: float
    min_pressure_per_ei: float
    min_gap_mm: float
    max_gap_mm: float
    mean_mismatch_mm: float
    integral_residual_mm: float
    wrap_sensitivity_deg_per_um: float
    shape_iterations: int
    time_s: float
    warnings: tuple[str, ...] = ()

    def __post_init__(self):
        for name in ("shape_cos_mm", "free_coefficients_mm"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        object.__setattr__(self, "warnings", tuple(self.warnings))

    # -- derived values ------------------------------------------------------------------------
    @property
    def wrap_angle_deg(self) -> float:
        return math.degrees(self.wrap_angle_rad)

    @property
    def full_wrap(self) -> bool:
        return self.wrap_angle_rad >= math.pi / self.waves

    @property
    def bore_radius_mm(self) -> float:
        return self.neutral_radius_mm - 0.5 * self.rim_thickness_mm

    @property
    def deflection_mm(self) -> float:
        """ω(0) on the neutral line (mm)."""
        return float(self.omega(0.0)[0])

    @property
    def bending_stiffness_n_mm(self) -> float:
        """EI = Eδ³/12 per mm of face width (N·mm); needs ``youngs_modulus_mpa``."""
        if self.youngs_modulus_mpa is None:
            raise RingError("youngs_modulus_mpa = None: give it to inextensible_ring_on_cam for forces (MPa, > 0)")
        return self.youngs_modulus_mpa * self.rim_thickness_mm**3 / 12.0

    @property
    def edge_force_n(self) -> float:
        """Line force at each edge of contact, N per mm of face width."""
        return self.edge_force_per_ei * self.bending_stiffness_n_mm

    # -- fields over φ ------------------------------------------------------------------------
    def _fold(self, phi):
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        if not np.all(np.isfinite(phi)):
            raise RingError("phi: angles must be finite (rad)")
        period = 2.0 * math.pi / self.waves
        t = np.remainder(phi, period)
        upper = t > 0.5 * period
        t = np.where(upper, period - t, t)
        return t, np.where(upper, -1.0, 1.0), t > self.wrap_angle_rad

    def _derivative(self, t, free, n: int) -> np.ndarray:
        out = _series(self.shape_cos_mm, self.waves, t, n)
        if n == -1:
            out = out + self.shape_cos_mm[0] * t
        if np.any(free):
            psi = t[free] - math.pi / self.waves
            a = self.free_coefficients_mm
            if n == -1:
                alpha = self.wrap_angle_rad
                at_edge = _series(self.shape_cos_mm, self.waves, np.array([alpha]), -1)[0] + self.shape_cos_mm[0] * alpha
                psi_a = alpha - math.pi / self.waves
                out[free] = at_edge + a @ (_free_basis(psi, -1) - _free_basis(psi_a, -1)[:, None])
            else:
                out[free] = a @ _free_basis(psi, n)
        return out

    def omega(self, phi, radius_mm: float | None = None, *, poisson_ratio: float = 0.0) -> np.ndarray:
        """ω(φ) (mm). At ``radius_mm`` r ≠ r_m (Kirchhoff, z = r − r_m): ω − ν Δκ z²/2, the
        plane-stress thickening, Δκ = −(ω″ + ω)/r_m² (``poisson_ratio`` ν; 0: ω itself)."""
        t, _, free = self._fold(phi)
        w = self._derivative(t, free, 0)
        if radius_mm is None:
            return w
        z = self._offset(radius_mm)
        nu = _number("poisson_ratio", poisson_ratio, "", -1.0, 0.5)
        dk = -(self._derivative(t, free, 2) + w) / self.neutral_radius_mm**2
        return w - nu * dk * z * z / 2.0

    def upsilon(self, phi, radius_mm: float | None = None) -> np.ndarray:
        """υ(φ) = −∫₀^φ ω (mm), odd. At ``radius_mm`` r (Kirchhoff, z = r − r_m): υ + z(υ − ω′)/r_m."""
        t, sign, free = self._fold(phi)
        u = -self._derivative(t, free, -1)
        if radius_mm is not None:
            z = self._offset(radius_mm)
            u = u + z * (u - self._derivative(t, free, 1)) / self.neutral_radius_mm
        return sign * u

    def gap_mm(self, phi) -> np.ndarray:
        """g = ω − f: 0 in the contact zone, ≥ 0 (lift-off from the contour) in the free zone (mm)."""
        t, _, free = self._fold(phi)
        return self._derivative(t, free, 0) - _series(self.shape_cos_mm, self.waves, t, 0)

    def pressure_per_ei(self, phi) -> np.ndarray:
        """Distributed contact pressure p/EI (1/mm³), 0 in the free zone; the edge line forces
        (``edge_force_per_ei``) come on top."""
        t, _, free = self._fold(phi)
        p = (_series(self.shape_cos_mm, self.waves, t, 4) - self.free_coefficients_mm[0]) / self.neutral_radius_mm**4
        return np.where(free, 0.0, p)

    def pressure_mpa(self, phi) -> np.ndarray:
        """Contact pressure p (N/mm² per mm of face width); needs ``youngs_modulus_mpa``."""
        return self.pressure_per_ei(phi) * self.bending_stiffness_n_mm

    def _offset(self, radius_mm) -> float:
        r = _number("radius_mm", radius_mm, "mm", self.bore_radius_mm, self.neutral_radius_mm + 0.5 * self.rim_thickness_mm,
                    low_open=False, high_open=False)
        return r - self.neutral_radius_mm

    def to_dict(self) -> dict:
        contour = self.contour.to_dict() if hasattr(self.contour, "to_dict") else repr(self.contour)
        out = {
            "tier": "sketch",
            "model": "thin inextensible ring (linear), unilateral cam contact, one contact zone per half wave",
            "contact": self.contact,
            "contour": contour,
            "neutral_radius_mm": self.neutral_radius_mm,
            "rim_thickness_mm": self.rim_thickness_mm,
            "waves": self.waves,
            "youngs_modulus_mpa": self.youngs_modulus_mpa,
            "wrap_angle_deg": self.wrap_angle_deg,
            "full_wrap": self.full_wrap,
            "deflection_mm": self.deflection_mm,
            "shape_cos_mm": self.shape_cos_mm.tolist(),
            "free_coefficients_mm": self.free_coefficients_mm.tolist(),
            "edge_force_per_ei": self.edge_force_per_ei,
            "min_pressure_per_ei": self.min_pressure_per_ei,
            "min_gap_mm": self.min_gap_mm,
            "max_gap_mm": self.max_gap_mm,
            "mean_mismatch_mm": self.mean_mismatch_mm,
            "integral_residual_mm": self.integral_residual_mm,
            "wrap_sensitivity_deg_per_um": self.wrap_sensitivity_deg_per_um,
            "shape_iterations": self.shape_iterations,
            "time_s": self.time_s,
            "warnings": list(self.warnings),
        }
        if self.youngs_modulus_mpa is not None:
            out["bending_stiffness_n_mm"] = self.bending_stiffness_n_mm
            out["edge_force_n"] = self.edge_force_n
        return out


def _inputs(contour, neutral_radius_mm, rim_thickness_mm, waves, contact, youngs_modulus_mpa):
    r_m = _number("neutral_radius_mm", neutral_radius_mm, "mm", 0.0)
    delta = _number("rim_thickness_mm", rim_thickness_mm, "mm", 0.0, r_m)
    waves = _whole("waves", waves, 2)
    if contact not in CONTACT_MODELS:
        raise RingError(f"contact = {contact!r}: must be one of {', '.join(CONTACT_MODELS)}")
    e = None if youngs_modulus_mpa is None else _number("youngs_modulus_mpa", youngs_modulus_mpa, "MPa", 0.0)
    if not (hasattr(contour, "radius") and callable(contour.radius)):
        raise RingError(f"contour = {contour!r}: must be a wave-generator contour with radius(theta) (mm)")
    return r_m, delta, waves, e


def _edge_solution(coef, waves, alpha):
    """(a0, a1, a2) from ω, ω′, ω″ continuous at φ = α, and ∫₀^{π/U} ω dφ."""
    psi = alpha - math.pi / waves
    lhs = np.array([_free_basis(psi, n) for n in range(3)])
    rhs = np.array([_series(coef, waves, np.array([alpha]), n)[0] for n in range(3)])
    a = np.linalg.solve(lhs, rhs)
    integral = (_series(coef, waves, np.array([alpha]), -1)[0] + coef[0] * alpha
                + a @ (_free_basis(0.0, -1) - _free_basis(psi, -1)))
    return a, float(integral)


_INDETERMINATE = ("full wrap: the uniform part of the pressure (the hoop force) is indeterminate in inextensible "
                  "theory; the least one that keeps p ≥ 0 is reported")


def _full_wrap(contour, r_m, delta, waves, contact, e, coef, iterations, start, *warnings) -> OracleResult:
    """ω = f all round; a0 = min L²f, the least uniform pressure with p ≥ 0."""
    half = math.pi / waves
    a0 = float(np.min(_series(coef, waves, np.linspace(0.0, half, _CHECK), 4)))
    mismatch = float(coef[0])
    return OracleResult(
        contour=contour, neutral_radius_mm=r_m, rim_thickness_mm=delta, waves=waves, contact=contact,
        youngs_modulus_mpa=e, wrap_angle_rad=half, shape_cos_mm=coef, free_coefficients_mm=[a0, 0.0, 0.0],
        edge_force_per_ei=0.0, min_pressure_per_ei=0.0, min_gap_mm=0.0, max_gap_mm=0.0, mean_mismatch_mm=mismatch,
        integral_residual_mm=mismatch * half, wrap_sensitivity_deg_per_um=math.inf, shape_iterations=iterations,
        time_s=time.perf_counter() - start, warnings=(*warnings, _INDETERMINATE),
    )


def inextensible_ring_on_cam(
    contour,
    neutral_radius_mm: float,
    rim_thickness_mm: float,
    *,
    waves: int = 2,
    contact: str = "exact_gap",
    youngs_modulus_mpa: float | None = None,
) -> OracleResult:
    """Thin inextensible ring (neutral radius r_m, thickness δ) pressed by ``contour``: ω, υ,
    the wrap angle α, the contact pressure and the edge forces (see the module docstring).

    ``contact``: ``"exact_gap"`` (the bore lies exactly on the contour under the linear
    kinematics — the FEM's model) or ``"first_order"`` (ω = ρ − r_b in the contact zone).
    ``youngs_modulus_mpa`` (optional) turns p/EI and F/EI into N/mm² and N/mm.

    Raises :class:`RingError` for bad input, :class:`InadmissibleContactError` when no
    single-zone contact with p ≥ 0, F ≥ 0 and g ≥ 0 exists (or the ring would have to stretch).
    """
    start = time.perf_counter()
    r_m, delta, waves, e = _inputs(contour, neutral_radius_mm, rim_thickness_mm, waves, contact, youngs_modulus_mpa)
    r_b = r_m - 0.5 * delta
    coef, iterations = _contact_shape(contour, r_b, r_m, waves, contact)
    half = math.pi / waves
    w0 = float(np.sum(coef))
    mismatch = float(coef[0])
    tol = 1e-12 * r_b
    warnings = [WRAP_WARNING]
    if mismatch > tol:
        raise InadmissibleContactError(
            f"contour = {contour!r}: the bore would have to stretch to go round it (mean of ρ − r_b = {mismatch:.6g} mm "
            f"> 0 with contact = {contact!r}); an inextensible ring cannot be mounted on it")
    if mismatch >= -tol:
        return _full_wrap(contour, r_m, delta, waves, contact, e, coef, iterations, start, WRAP_WARNING)

    def integral(alpha):
        return _edge_solution(coef, waves, alpha)[1]

    # scan down from the minor axis for the first sign change of ∫ω (the free span grows with
    # the mismatch like its 1/7 power, so β = π/U − α ≥ 1e-3 covers mismatches ≳ 1e-21 w0)
    betas = np.geomspace(1e-3, half - 1e-3, 200)
    alphas = half - betas
    values = np.array([integral(a) for a in alphas])
    change = np.flatnonzero(values > 0.0)
    if change.size == 0 or change[0] == 0:
        raise InadmissibleContactError(
            f"contour = {contour!r}: no wrap angle α in (0, {math.degrees(half):g}]° gives ∫ω dφ = 0 "
            f"(mean mismatch {mismatch:.6g} mm, contact = {contact!r})")
    i = int(change[0])
    from scipy.optimize import brentq

    alpha = brentq(integral, alphas[i], alphas[i - 1], xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
    a, residual = _edge_solution(coef, waves, alpha)
    psi_a = alpha - half
    jump = float(a @ _free_basis(psi_a, 3) - _series(coef, waves, np.array([alpha]), 3)[0])
    edge = jump / r_m**3
    # dα/ds for a uniform shift s of the contour: ∫ω shifts by s·π/U
    step = 1e-7 * max(alpha, 1e-3)
    slope = (integral(alpha + step) - integral(alpha - step)) / (2 * step)
    sensitivity = math.degrees(-half / slope) * 1e-3 if slope != 0.0 else math.inf

    contact_grid = np.linspace(0.0, alpha, _CHECK)
    pressure = (_series(coef, waves, contact_grid, 4) - a[0]) / r_m**4
    free_grid = np.linspace(alpha, half, _CHECK)[1:]
    gap = a @ _free_basis(free_grid - half, 0) - _series(coef, waves, free_grid, 0)
    p_scale = float(np.max(np.abs(pressure)))
    if float(np.min(pressure)) < -1e-9 * p_scale:
        k = int(np.argmin(pressure))
        raise InadmissibleContactError(
            f"contour = {contour!r}: tensile contact pressure p/EI = {pressure[k]:.6g} /mm³ at φ = "
            f"{math.degrees(contact_grid[k]):.6g}° inside the wrap α = {math.degrees(alpha):.6g}° (contact = {contact!r})")
    if edge < -1e-9 * p_scale * r_m:
        raise InadmissibleContactError(
            f"contour = {contour!r}: tensile edge force F/EI = {edge:.6g} /mm² at the edge of contact φ = "
            f"{math.degrees(alpha):.6g}° (contact = {contact!r})")
    if float(np.min(gap)) < -1e-10 * abs(w0):
        k = int(np.argmin(gap))
        raise InadmissibleContactError(
            f"contour = {contour!r}: the free part penetrates the contour by {-gap[k]:.6g} mm at φ = "
            f"{math.degrees(free_grid[k]):.6g}° (wrap α = {math.degrees(alpha):.6g}°, contact = {contact!r})")
    return OracleResult(
        contour=contour, neutral_radius_mm=r_m, rim_thickness_mm=delta, waves=waves, contact=contact,
        youngs_modulus_mpa=e, wrap_angle_rad=float(alpha), shape_cos_mm=coef, free_coefficients_mm=a,
        edge_force_per_ei=edge, min_pressure_per_ei=float(np.min(pressure)), min_gap_mm=float(np.min(gap)),
        max_gap_mm=float(np.max(gap)), mean_mismatch_mm=mismatch, integral_residual_mm=residual,
        wrap_sensitivity_deg_per_um=sensitivity, shape_iterations=iterations, time_s=time.perf_counter() - start,
        warnings=tuple(warnings),
    )


def full_wrap_on_cam(
    contour,
    neutral_radius_mm: float,
    rim_thickness_mm: float,
    *,
    waves: int = 2,
    youngs_modulus_mpa: float | None = None,
) -> OracleResult:
    """The ring held on the contour all round (bilateral, first-order contact): ω = ρ − r_b
    everywhere, υ = −∫ω. On a cosine cam r_b + w0 cos Uφ this is ring theory's
    ω = w0 cos Uφ, υ = −(w0/U) sin Uφ. The mean of ρ − r_b must vanish (to 1e-12 r_b, else
    :class:`InadmissibleContactError`: an inextensible ring cannot follow it all round); the
    uniform pressure is the least one with p ≥ 0."""
    start = time.perf_counter()
    r_m, delta, waves, e = _inputs(contour, neutral_radius_mm, rim_thickness_mm, waves, "first_order",
                                   youngs_modulus_mpa)
    r_b = r_m - 0.5 * delta
    coef, _ = _contact_shape(contour, r_b, r_m, waves, "first_order")
    mismatch = float(coef[0])
    if abs(mismatch) > 1e-12 * r_b:
        raise InadmissibleContactError(
            f"contour = {contour!r}: mean of ρ − r_b = {mismatch:.6g} mm ≠ 0: an inextensible ring of bore "
            f"{r_b:.9g} mm cannot follow it all round (use inextensible_ring_on_cam for partial wrap)")
    return _full_wrap(contour, r_m, delta, waves, "first_order", e, coef, 0, start)
