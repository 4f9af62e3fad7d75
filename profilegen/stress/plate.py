"""Cup-bottom plate of an ultra-short cup flexspline (seed 002), as pure functions.

The bottom of the cup is an annular Kirchhoff plate r0 ≤ r ≤ r_m of thickness t, clamped on
the boss (r = r0) and pulled axially at its outer edge (r = r_m) by the cylindrical wall,
whose end the wave generator forces into an ellipse. Units: mm, N, MPa, N·mm (torque),
radians. Symbols: φ polar angle from the wave generator's major axis; ρ(η) the deformed
neutral-surface radius at polar angle η; ω = ρ − r_m the radial displacement; w the axial
(out-of-plane) displacement of the plate; ν (seed: μ) Poisson's ratio.

Three steps, each a function:

1. :func:`edge_displacement_from_ellipse` / :func:`edge_displacement` — the axial
   displacement w(φ) of the plate's outer edge from semi-membrane shell theory
   (seed 002, eq. for w₀(φ)), corrected (docs/theory/stresses.md): integrand ρ(η) − r_m in mm and
   made periodic. Returned as harmonics, :class:`EdgeDisplacement`.
2. :func:`cup_bottom_stress` with ``model="consistent"`` — the Kirchhoff solution that is
   exact for each harmonic n of w(φ) (radial basis r^n, r^−n, r^(n+2), r^(2−n), logs for
   n = 0, 1), clamped at r0, w prescribed and M_r = 0 at r_m; surface stresses, the torque
   shear T/(2π r² t), von Mises, maxima: :class:`CupBottomStress`.
3. ``model="seed002"`` — the paper's w₁ = f(r)·w(φ) with the axisymmetric basis; reproduces
   Table 1's β (:func:`seed002_beta`); :func:`seed002_comparison` sets the paper's printed
   stresses (Table 2) beside both models.

A Morley finite-element solution of the same plate decides between the two models
(docs/theory/stresses.md).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from ..errors import StressError
from ..results import json_ready, readonly
from .inputs import choice as _choice, count as _count, finite as _finite, poisson as _poisson, positive as _positive

__all__ = [
    "SEED002_BETA",
    "SEED002_TABLE1",
    "SEED002_TABLE2",
    "CupBottomStress",
    "PlateField",
    "EdgeDisplacement",
    "cup_bottom_stress",
    "edge_displacement",
    "edge_displacement_from_ellipse",
    "ellipse_radial_harmonics",
    "radial_basis",
    "seed002_beta",
    "seed002_comparison",
    "seed_edge_integral",
    "solve_plate",
    "torque_shear_mpa",
]

#: Seed 002, Table 1 (CSG-25 ultra-short flexspline, k = l/(2 r_m) = 0.3).
SEED002_TABLE1 = {
    "mean_radius_mm": 30.685,
    "semi_major_mm": 31.035,
    "semi_minor_mm": 30.335,
    "boss_radius_mm": 15.0,
    "thickness_mm": 1.0,
    "length_mm": 18.411,
    "youngs_modulus_mpa": 206000.0,
    "poisson_ratio": 0.3,
}
#: Seed 002, Table 1: β0..β3 of f(r) = β0 + β1 r²/r_m² + β2 ln r + β3 (r²/r_m²) ln r (r in mm).
SEED002_BETA = (8.5631, 35.8121, -4.3294, -8.3394)
#: Seed 002, Table 2: the theoretical values (MPa), what each is, at which φ and torque (N·m).
SEED002_TABLE2 = (
    ("sigma_r_assembly", "max radial stress σ_r^ass at r0", 0.0, 0.0, 208.0),
    ("tau_total_rated", "max shear τ_rφ^total, rated torque", 45.0, 87.0, 68.0),
    ("tau_total_max", "max shear τ_rφ^total, max torque", 0.0, 395.0, 265.0),
    ("von_mises_max", "von Mises σ_eqv, max torque", 0.0, 395.0, 280.0),
)

MODELS = ("consistent", "seed002")
REFERENCES = ("mean", "seed")


# --------------------------------------------------------------------------- validation








def _radii(boss_radius_mm, mean_radius_mm) -> tuple[float, float]:
    r_m = _positive("mean_radius_mm", mean_radius_mm, "mm")
    r0 = _positive("boss_radius_mm", boss_radius_mm, "mm")
    if r0 >= r_m:
        raise StressError(f"boss_radius_mm must be in (0, mean_radius_mm = {r_m!r}) mm, got {r0!r}")
    return r0, r_m






# --------------------------------------------------------------------------- step 1: w(φ)


@dataclass(frozen=True, slots=True, eq=False)
class EdgeDisplacement:
    """Axial displacement of the plate's outer edge, w(φ) = Σ_n W_n cos nφ (mm).

    ``orders`` n (int, ascending) and ``amplitudes_mm`` W_n; ``mean_radius_mm`` r_m and
    ``length_mm`` l of the wall; ``reference``: ``"mean"`` (zero mean, the default) or
    ``"seed"`` (w₀(φ) − w₀(π/4) as printed, which keeps a constant for harmonics other than
    cos 2φ); ``removed_mean_mm``: the mean c₀ of ρ(η) − r_m (mm) that was removed from the
    integrand; ``drift_per_turn_mm``: what the double integral would have drifted over one
    turn with it, w(2π) − w(0) = −(r_m/l)·c₀·(2π)²/2 (the periodicity defect removed); ``truncation_mm``:
    Σ|W_n| of the harmonics beyond the series (an error bound on w, mm)."""

    orders: np.ndarray
    amplitudes_mm: np.ndarray
    mean_radius_mm: float
    length_mm: float
    reference: str = "mean"
    removed_mean_mm: float = 0.0
    drift_per_turn_mm: float = 0.0
    truncation_mm: float = 0.0

    def __post_init__(self):
        orders, amps = np.atleast_1d(self.orders), np.atleast_1d(np.asarray(self.amplitudes_mm, dtype=float))
        if orders.ndim != 1 or orders.shape != amps.shape or np.any(orders < 0) or np.any(orders != np.round(orders)):
            raise StressError(f"orders must be integers ≥ 0, one per amplitude, got {self.orders!r}")
        if not np.all(np.isfinite(amps)):
            raise StressError(f"amplitudes_mm must be finite (mm), got {self.amplitudes_mm!r}")
        _positive("mean_radius_mm", self.mean_radius_mm, "mm")
        _positive("length_mm", self.length_mm, "mm")
        object.__setattr__(self, "orders", readonly(orders, int))
        object.__setattr__(self, "amplitudes_mm", readonly(amps, float))

    @property
    def harmonics(self) -> dict[int, float]:
        """{n: W_n} (mm, coefficient of cos nφ)."""
        return {int(n): float(a) for n, a in zip(self.orders, self.amplitudes_mm)}

    def __call__(self, phi_rad, derivative: int = 0) -> np.ndarray:
        """w(φ) (mm) or its ``derivative``-th φ-derivative (mm/rad^k), vectorised over φ."""
        phi = np.asarray(phi_rad, dtype=float)
        out = np.zeros(phi.shape)
        for n, amp in zip(self.orders, self.amplitudes_mm):
            out = out + amp * _cos_derivative(n, phi, derivative)
        return out

    def scaled(self, factor: float) -> EdgeDisplacement:
        """The same w(φ) times ``factor`` (the plate is linear in w)."""
        return EdgeDisplacement(self.orders, self.amplitudes_mm * factor, self.mean_radius_mm, self.length_mm,
                                self.reference, self.removed_mean_mm * factor,
                                self.drift_per_turn_mm * factor, abs(factor) * self.truncation_mm)

    def to_dict(self) -> dict:
        return json_ready({
            "harmonics_mm": {str(n): a for n, a in self.harmonics.items()},
            "mean_radius_mm": self.mean_radius_mm,
            "length_mm": self.length_mm,
            "reference": self.reference,
            "removed_mean_mm": self.removed_mean_mm,
            "drift_per_turn_mm": self.drift_per_turn_mm,
            "truncation_mm": self.truncation_mm,
        })


def _cos_derivative(n, phi: np.ndarray, k: int) -> np.ndarray:
    """d^k/dφ^k cos nφ (n an integer, or an array of them broadcast with φ)."""
    return np.asarray(n, dtype=float) ** k * np.cos(n * phi + k * math.pi / 2.0)


def ellipse_radius_mm(eta_rad, semi_major_mm: float, semi_minor_mm: float) -> np.ndarray:
    """Polar radius ρ(η) = ab / √(a² sin²η + b² cos²η) of the ellipse with semi-axes a (along
    η = 0) and b (mm). Seed 002 prints ab / (a² sin²η + b² cos²η), without the root: that
    is ≈ 1/r_m (mm⁻¹), not a radius (see :func:`seed_edge_integral`)."""
    eta = np.asarray(eta_rad, dtype=float)
    a, b = semi_major_mm, semi_minor_mm
    return a * b / np.sqrt((a * np.sin(eta)) ** 2 + (b * np.cos(eta)) ** 2)


def ellipse_radial_harmonics(semi_major_mm: float, semi_minor_mm: float, mean_radius_mm: float, *,
                             max_order: int = 16, samples: int = 1024) -> tuple[dict[int, float], float]:
    """Cosine coefficients c_k of ρ(η) − r_m for the ellipse (mm, k = 0..max_order; only even
    k are non-zero: the ellipse has the two-fold symmetry of the two-wave generator), by FFT
    of ``samples`` equispaced values (spectrally exact), and Σ|c_k| beyond ``max_order``."""
    a = _positive("semi_major_mm", semi_major_mm, "mm")
    b = _positive("semi_minor_mm", semi_minor_mm, "mm")
    r_m = _positive("mean_radius_mm", mean_radius_mm, "mm")
    max_order = _count("max_order", max_order, 2)
    samples = max(_count("samples", samples, 8), 4 * max_order)
    eta = 2.0 * math.pi * np.arange(samples) / samples
    spectrum = np.fft.rfft(ellipse_radius_mm(eta, a, b) - r_m).real / samples
    coeffs = 2.0 * spectrum
    coeffs[0] = spectrum[0]
    coeffs[np.abs(coeffs) < 1e-15 * max(a, b)] = 0.0  # odd orders: round-off only
    tail = float(np.sum(np.abs(coeffs[max_order + 1:])))
    return {k: float(coeffs[k]) for k in range(max_order + 1)}, tail


def edge_displacement(radial_cos_mm: Mapping[int, float], *, mean_radius_mm: float, length_mm: float,
                      reference: str = "mean", tail_mm: float = 0.0) -> EdgeDisplacement:
    """w(φ) at the plate's outer edge from a radial displacement ω(η) = Σ_k c_k cos kη (mm,
    the package's integer-harmonic deformation model; ring theory: {2: w0}).

    Seed 002's semi-membrane result, corrected (docs/theory/stresses.md)::

        w₀(φ) = −(1/2k) ∫₀^φ ∫₀^θ (ρ(η) − r_m) dη dθ,   k = l/(2 r_m),   ρ − r_m = ω

    (the paper prints ab/(a² sin²η + b² cos²η) − r_m: a pure number ≈ 1/r_m minus mm). For
    each harmonic ∫₀^φ∫₀^θ cos kη = (1 − cos kφ)/k², so

        w(φ) = (r_m/l) Σ_{k≥1} (c_k/k²) cos kφ + const.

    Periodicity: the mean c₀ of ρ − r_m integrates twice into c₀φ²/2, which is not
    2π-periodic (Table 1's ellipse: c₀ = −2.99 µm, a drift of 0.099 mm per turn). c₀ is of
    second order in (a − b)/r_m (the polar radius at polar angle η and ω at the material
    angle differ at that order, and so do the perimeters of the ellipse and of the circle
    r_m), and a uniform radial displacement is not a displacement of the linear theory at all:
    zero hoop strain, ∂υ/∂φ = −ω, would make υ = −c₀φ non-periodic. So c₀ is dropped
    (first-order consistent; ``removed_mean_mm`` and ``drift_per_turn_mm`` record it). The
    inner integral of the remaining cosines is a sine series with zero mean, so no linear
    drift is left and w(φ) is exactly 2π-periodic.

    The constant: ``reference="mean"`` (default) drops it, w has zero mean. That is the
    physical choice: a constant edge lift bends the clamped plate axisymmetrically and
    needs a net axial force, which the cup wall (free at its open end) cannot supply.
    ``reference="seed"`` subtracts w₀(π/4) as the paper does; for w = W₂ cos 2φ the two are
    the same, for higher harmonics the seed's version keeps a constant Σ_k −W_k cos(kπ/4)
    (n = 0 term). Odd k are accepted (other wave counts); a two-wave generator gives only
    even k."""
    r_m = _positive("mean_radius_mm", mean_radius_mm, "mm")
    length = _positive("length_mm", length_mm, "mm")
    reference = _choice("reference", reference, REFERENCES)
    tail = abs(_finite("tail_mm", tail_mm, "mm"))
    coeffs = _radial_coefficients(radial_cos_mm)
    scale = r_m / length  # 1/(2k)
    orders = sorted(k for k in coeffs if k >= 1 and coeffs[k] != 0.0)
    amps = [scale * coeffs[k] / k**2 for k in orders]
    if reference == "seed":
        constant = -sum(a * math.cos(k * math.pi / 4.0) for k, a in zip(orders, amps))
        if abs(constant) > 1e-15 * max(1.0, *map(abs, amps)):
            orders, amps = [0] + orders, [constant] + amps
    c0 = coeffs.get(0, 0.0)
    return EdgeDisplacement(np.array(orders, int), np.array(amps, float), r_m, length, reference, c0,
                            -scale * c0 * (2.0 * math.pi) ** 2 / 2.0, scale * tail / 4.0)


def _radial_coefficients(radial_cos_mm: Mapping[int, float]) -> dict[int, float]:
    if not isinstance(radial_cos_mm, Mapping) or not radial_cos_mm:
        raise StressError(f"radial_cos_mm must be a non-empty mapping order → mm, got {radial_cos_mm!r}")
    out: dict[int, float] = {}
    for k, c in radial_cos_mm.items():
        k = _count("radial_cos_mm order", k, 0)
        out[k] = out.get(k, 0.0) + _finite(f"radial_cos_mm[{k}]", c, "mm")
    return out


def edge_displacement_from_ellipse(semi_major_mm: float, semi_minor_mm: float, *, mean_radius_mm: float,
                                   length_mm: float, reference: str = "mean",
                                   max_order: int = 16) -> EdgeDisplacement:
    """w(φ) for a wall whose neutral surface is the ellipse with semi-axes ``semi_major_mm``
    (on φ = 0) and ``semi_minor_mm`` (seed 002, Table 1: a, b): ρ(η) − r_m expanded in
    cos kη (:func:`ellipse_radial_harmonics`), then :func:`edge_displacement`. For Table 1
    (a − b = 0.7 mm, k = 0.3): W₂ = 0.14582 mm, W₄ = 0.31 µm, W₆ < 1 nm."""
    coeffs, tail = ellipse_radial_harmonics(semi_major_mm, semi_minor_mm, mean_radius_mm, max_order=max_order)
    return edge_displacement(coeffs, mean_radius_mm=mean_radius_mm, length_mm=length_mm, reference=reference,
                             tail_mm=tail)


def seed_edge_integral(phi_rad, semi_major_mm: float, semi_minor_mm: float, *, mean_radius_mm: float,
                       length_mm: float, integrand: str = "corrected", samples: int = 20001) -> np.ndarray:
    """Seed 002's w(φ) = w₀(φ) − w₀(π/4) by direct quadrature of the double integral,
    0 ≤ φ ≤ 2π (mm) — a check of the formula as printed, not the model.

    ``integrand``: ``"printed"`` ab/(a² sin²η + b² cos²η) − r_m (the paper's; with Table 1
    it gives w(2π) − w(0) ≈ 976 mm: nonsense and not periodic); ``"corrected"`` ρ(η) − r_m
    with the true polar radius (periodic up to the drift of its mean c₀, 0.099 mm per turn
    for Table 1); ``"periodic"`` ρ(η) − mean(ρ) (what :func:`edge_displacement` uses: equal
    to its harmonic series up to the quadrature error). Cumulative Simpson rule on
    ``samples`` points over [0, 2π]."""
    from scipy.integrate import cumulative_simpson

    integrand = _choice("integrand", integrand, ("printed", "corrected", "periodic"))
    a = _positive("semi_major_mm", semi_major_mm, "mm")
    b = _positive("semi_minor_mm", semi_minor_mm, "mm")
    r_m = _positive("mean_radius_mm", mean_radius_mm, "mm")
    length = _positive("length_mm", length_mm, "mm")
    phi = np.asarray(phi_rad, dtype=float)
    if np.any(~np.isfinite(phi)) or np.any(phi < 0.0) or np.any(phi > 2.0 * math.pi + 1e-12):
        raise StressError("phi_rad must be finite and in [0, 2π] rad")
    eta = np.linspace(0.0, 2.0 * math.pi, _count("samples", samples, 101) | 1)
    if integrand == "printed":
        g = a * b / ((a * np.sin(eta)) ** 2 + (b * np.cos(eta)) ** 2) - r_m
    else:
        rho = ellipse_radius_mm(eta, a, b)
        g = rho - (r_m if integrand == "corrected" else np.mean(rho[:-1]))
    inner = cumulative_simpson(g, x=eta, initial=0.0)
    w0 = -(r_m / length) * cumulative_simpson(inner, x=eta, initial=0.0)
    return np.interp(phi, eta, w0) - np.interp(math.pi / 4.0, eta, w0)


# --------------------------------------------------------------------------- step 2/3: plate


def radial_basis(order: int, r_mm, mean_radius_mm: float, *, model: str = "consistent") -> np.ndarray:
    """Radial functions g_i(r) of harmonic ``order`` n, and their first and second
    r-derivatives: array (3, 4, *r.shape) (1, mm⁻¹, mm⁻²). With ρ = r/r_m:

    * ``"consistent"``: ρ^n, ρ^−n, ρ^(n+2), ρ^(2−n) — each g_i(r) cos nφ satisfies ∇⁴w = 0;
      n = 0: 1, ln ρ, ρ², ρ² ln ρ; n = 1: ρ, 1/ρ, ρ³, ρ ln ρ (the repeated powers).
    * ``"seed002"``: 1, ρ², ln r, ρ² ln r with r in mm (seed 002's f(r), whatever n; its
      Table 1 β are for ln r in mm — the printed ln(r/r_m) spans the same functions but gives
      other β0, β1). g(r) cos nφ is biharmonic only for n = 0."""
    n = _count("order", order, 0)
    r_m = _positive("mean_radius_mm", mean_radius_mm, "mm")
    model = _choice("model", model, MODELS)
    return _radial_basis(n, np.asarray(r_mm, dtype=float), r_m, model)


def _radial_basis(n: int, r: np.ndarray, r_m: float, model: str) -> np.ndarray:
    """:func:`radial_basis` for checked arguments (a :class:`PlateField` evaluates it per harmonic)."""
    if model == "seed002":  # in r (mm): 1, r²/r_m², ln r, (r²/r_m²) ln r
        lg, s = np.log(r), 1.0 / r_m**2
        zero, one = np.zeros_like(r), np.ones_like(r)
        return np.array([[one, s * r**2, lg, s * r**2 * lg],
                         [zero, 2 * s * r, 1.0 / r, s * r * (2 * lg + 1)],
                         [zero, 2 * s * one, -1.0 / r**2, s * (2 * lg + 3)]])
    rho = r / r_m
    if n == 0:
        terms = [_power(rho, 0), _log_power(rho, 0), _power(rho, 2), _log_power(rho, 2)]
    elif n == 1:
        terms = [_power(rho, 1), _power(rho, -1), _power(rho, 3), _log_power(rho, 1)]
    else:
        terms = [_power(rho, n), _power(rho, -n), _power(rho, n + 2), _power(rho, 2 - n)]
    out = np.moveaxis(np.array(terms), 1, 0)  # (3, 4, ...) in ρ-derivatives
    out[1] /= r_m
    out[2] /= r_m**2
    return out


def _power(x: np.ndarray, p: int) -> tuple:
    """x^p and its first two x-derivatives."""
    return x**p, p * x ** float(p - 1), p * (p - 1) * x ** float(p - 2)


def _log_power(x: np.ndarray, p: int) -> tuple:
    """x^p ln x and its first two x-derivatives."""
    lg = np.log(x)
    return x**p * lg, x ** float(p - 1) * (p * lg + 1.0), x ** float(p - 2) * (p * (p - 1) * lg + 2 * p - 1)


def flexural_row(basis: np.ndarray, r: float, n: int, nu: float, moment: str) -> np.ndarray:
    """Row of a moment condition (M/(−D), per unit cos nφ) on the 4 basis functions."""
    g, g1, g2 = basis
    hoop = g1 / r - n**2 * g / r**2
    if moment == "M_r":
        return g2 + nu * hoop
    return nu * g2 + g1 / r  # seed002: M_φ = 0 with the w_φφ term dropped (axisymmetric)


def _coefficients(n: int, r0: float, r_m: float, nu: float, model: str) -> tuple[np.ndarray, float]:
    """The 4 basis coefficients for a unit edge amplitude of harmonic n, and the residual of
    the boundary conditions (relative). Consistent: w(r0) = w_r(r0) = 0, w(r_m) = 1,
    M_r(r_m) = 0 (the natural condition, see :func:`cup_bottom_stress`). seed002:
    the same essential conditions and ν f'' + f'/r = 0 at r_m (Table 1's β)."""
    b0 = radial_basis(n, r0, r_m, model=model)
    bm = radial_basis(n, r_m, r_m, model=model)
    cond = "M_r" if model == "consistent" else "M_phi"
    a = np.array([b0[0], b0[1] * r_m, bm[0], flexural_row(bm, r_m, n, nu, cond) * r_m**2])
    rhs = np.array([0.0, 0.0, 1.0, 0.0])
    coef = np.linalg.solve(a, rhs)
    residual = float(np.max(np.abs(a @ coef - rhs)))
    return coef, residual


def seed002_beta(boss_radius_mm: float = SEED002_TABLE1["boss_radius_mm"],
                 mean_radius_mm: float = SEED002_TABLE1["mean_radius_mm"],
                 poisson_ratio: float = SEED002_TABLE1["poisson_ratio"], *,
                 log_unit_mm: float = 1.0) -> np.ndarray:
    """β0..β3 of seed 002's f(r) = β0 + β1 ρ² + β2 ln(r/u) + β3 ρ² ln(r/u), ρ = r/r_m.

    What reproduces Table 1 (docs/theory/stresses.md): f(r0) = 0, f'(r0) = 0, f(r_m) = 1 and
    ν f''(r_m) + f'(r_m)/r_m = 0 — "M_φ = 0" at r_m evaluated for the axisymmetric f alone
    (the f w''/r² term of the paper's own σ_φ dropped) — with the logarithm of r in mm
    (u = ``log_unit_mm`` = 1). Table 1's inputs give (8.56323, 35.81212, −4.32945, −8.33943),
    within 1.3e-4 of the printed values.

    The paper prints the basis with ln(r/r_m) (u = r_m): that spans the same functions, so f
    is the same, but β0 = −6.2598, β1 = 7.2598; with the printed β and ln(r/r_m),
    f(r_m) = β0 + β1 = 44.4 instead of 1. Other outer conditions give other β (M_r = 0 for
    f alone: β0 = 5.87; M_φ = 0 with the −4f/r² of cos 2φ: 4.09; f'(r_m) = 0: 14.8). M_φ acts
    on radial cuts, not on the edge r = r_m, so "M_φ = 0" is not a boundary condition of the
    plate; the edge moment is M_r (see :func:`cup_bottom_stress`)."""
    r0, r_m = _radii(boss_radius_mm, mean_radius_mm)
    nu = _poisson(poisson_ratio)
    unit = _positive("log_unit_mm", log_unit_mm, "mm")
    coef, _ = _coefficients(0, r0, r_m, nu, "seed002")
    # seed002 basis uses ln r (mm); re-express for ln(r/u) = ln r − ln u
    beta = coef.copy()
    beta[0] += coef[2] * math.log(unit)
    beta[1] += coef[3] * math.log(unit)
    return beta


def torque_shear_mpa(r_mm, torque_nmm: float, thickness_mm: float) -> np.ndarray:
    """Seed 002's torque shear τ_load = T / (2π r² t) (MPa; T in N·mm, r and t in mm): the
    torque carried by a thin annulus at radius r, uniform over the thickness."""
    t = _positive("thickness_mm", thickness_mm, "mm")
    torque = _finite("torque_nmm", torque_nmm, "N·mm")
    r = np.asarray(r_mm, dtype=float)
    return torque / (2.0 * math.pi * r**2 * t)


# --------------------------------------------------------------------------- the result


@dataclass(frozen=True, slots=True, eq=False)
class PlateField:
    """Deflection field of the cup bottom and its stresses at any point.

    w(r, φ) = Σ_j R_j(r) cos(n_j φ), R_j = Σ_i ``coefficients_mm[j, i]`` g_i(r) with g_i the
    :func:`radial_basis` of n_j = ``orders[j]`` for ``model`` (seed002: the same f(r) basis for
    every n). Plate r0 = ``boss_radius_mm`` ≤ r ≤ r_m = ``mean_radius_mm``, thickness t (mm),
    E (MPa), ν; ``torque_nmm`` (N·mm) for the torque shear."""

    model: str
    orders: np.ndarray
    coefficients_mm: np.ndarray
    boss_radius_mm: float
    mean_radius_mm: float
    thickness_mm: float
    youngs_modulus_mpa: float
    poisson_ratio: float
    torque_nmm: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "orders", readonly(self.orders, int))
        object.__setattr__(self, "coefficients_mm", readonly(self.coefficients_mm).reshape(-1, 4))

    @property
    def flexural_rigidity_nmm(self) -> float:
        """D = E t³ / (12 (1 − ν²)) (N·mm)."""
        e, t, nu = self.youngs_modulus_mpa, self.thickness_mm, self.poisson_ratio
        return e * t**3 / (12.0 * (1.0 - nu**2))

    def derivatives(self, r_mm, phi_rad) -> dict[str, np.ndarray]:
        """w and its derivatives at (r, φ) (broadcast): keys ``w`` (mm), ``w_r``, ``w_rr``,
        ``w_p``, ``w_pp``, ``w_rp`` (r in mm, φ in rad)."""
        # the radial functions on r's own shape, the angular ones on φ's, broadcast at the end (an
        # (r, φ) grid given as a column and a row needs 144× fewer powers than the full grid); the
        # harmonics n ≥ 2 of the consistent model at once, as arrays of exponents
        r, phi = np.asarray(r_mm, float), np.asarray(phi_rad, float)
        r_m = _positive("mean_radius_mm", self.mean_radius_mm, "mm")
        model = _choice("model", self.model, MODELS)
        orders, coef = self.orders, self.coefficients_mm
        g = np.zeros((3,) + r.shape + (len(orders),))  # R_n, R_n', R_n'' per harmonic (last axis)
        each = np.arange(len(orders))
        if model == "consistent":
            j = np.flatnonzero(orders >= 2)
            if j.size:
                n = orders[j].astype(float)
                p = np.stack([n, -n, n + 2.0, 2.0 - n], axis=-1)  # (J, 4): ρ^n, ρ^−n, ρ^(n+2), ρ^(2−n)
                rho = (r / r_m)[..., None, None]
                c = coef[j]
                g[0][..., j] = np.sum(c * rho**p, axis=-1)
                g[1][..., j] = np.sum(c * p * rho ** (p - 1.0), axis=-1) / r_m
                g[2][..., j] = np.sum(c * p * (p - 1.0) * rho ** (p - 2.0), axis=-1) / r_m**2
            each = np.flatnonzero(orders < 2)
        for k in each:  # the repeated powers of n = 0, 1 and seed 002's basis, one harmonic at a time
            basis = _radial_basis(_count("order", orders[k], 0), r, r_m, model)
            g[(slice(None),) + (Ellipsis, k)] = np.tensordot(coef[k], basis, axes=([0], [1]))
        c0, c1, c2 = (_cos_derivative(orders.astype(float), phi[..., None], k) for k in range(3))
        return {"w": np.sum(g[0] * c0, axis=-1), "w_r": np.sum(g[1] * c0, axis=-1),
                "w_rr": np.sum(g[2] * c0, axis=-1), "w_p": np.sum(g[0] * c1, axis=-1),
                "w_pp": np.sum(g[0] * c2, axis=-1), "w_rp": np.sum(g[1] * c1, axis=-1)}

    def deflection_mm(self, r_mm, phi_rad) -> np.ndarray:
        """w(r, φ) (mm)."""
        return self.derivatives(r_mm, phi_rad)["w"]

    def curvatures(self, r_mm, phi_rad) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """κ_r = w_rr, κ_φ = w_r/r + w_φφ/r², κ_rφ = w_rφ/r − w_φ/r² (1/mm)."""
        d = self.derivatives(r_mm, phi_rad)
        r = np.asarray(r_mm, float)
        return d["w_rr"], d["w_r"] / r + d["w_pp"] / r**2, d["w_rp"] / r - d["w_p"] / r**2

    def moments_n(self, r_mm, phi_rad) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """M_r = −D(κ_r + ν κ_φ), M_φ = −D(κ_φ + ν κ_r), M_rφ = −D(1 − ν) κ_rφ (N·mm/mm; seed
        002's sign convention)."""
        k_r, k_p, k_rp = self.curvatures(r_mm, phi_rad)
        d, nu = self.flexural_rigidity_nmm, self.poisson_ratio
        return -d * (k_r + nu * k_p), -d * (k_p + nu * k_r), -d * (1.0 - nu) * k_rp

    def surface_stress_mpa(self, r_mm, phi_rad, face: int = 1) -> dict[str, np.ndarray]:
        """σ_r, σ_φ (``sigma_r``, ``sigma_phi``), τ_rφ = bending + torque (``tau``) and von Mises
        (``von_mises``) on the face z = ``face``·t/2 (±1), MPa. σ = face·6M/t²."""
        if face not in (1, -1):
            raise StressError(f"face must be +1 or -1 (z = ±t/2), got {face!r}")
        m_r, m_p, m_rp = self.moments_n(r_mm, phi_rad)
        k = face * 6.0 / self.thickness_mm**2
        s_r, s_p = k * m_r, k * m_p
        tau = k * m_rp + torque_shear_mpa(r_mm, self.torque_nmm, self.thickness_mm)
        return {"sigma_r": s_r, "sigma_phi": s_p, "tau": tau, "von_mises": _von_mises(s_r, s_p, tau)}

    def strain_energy_nmm(self, radial_points: int = 48) -> float:
        """Bending strain energy U = −½ ∫ (M_r κ_r + M_φ κ_φ + 2 M_rφ κ_rφ) dA (N·mm; M = −D·κ
        here), Gauss–Legendre in r, trapezoid rule in φ (exact for the trigonometric field)."""
        x, wq = np.polynomial.legendre.leggauss(_count("radial_points", radial_points, 2))
        r0, r_m = self.boss_radius_mm, self.mean_radius_mm
        r = 0.5 * (r_m - r0) * x + 0.5 * (r_m + r0)
        nphi = 4 * int(self.orders.max(initial=1)) + 8
        phi = 2.0 * math.pi * np.arange(nphi) / nphi
        rr, pp = np.meshgrid(r, phi, indexing="ij")
        k_r, k_p, k_rp = self.curvatures(rr, pp)
        m_r, m_p, m_rp = self.moments_n(rr, pp)
        density = -0.5 * (m_r * k_r + m_p * k_p + 2.0 * m_rp * k_rp)
        return float(np.sum(density.mean(axis=1) * 2.0 * math.pi * r * wq) * 0.5 * (r_m - r0))

    def to_dict(self) -> dict:
        return json_ready({
            "model": self.model, "orders": self.orders, "coefficients_mm": self.coefficients_mm,
            "boss_radius_mm": self.boss_radius_mm, "mean_radius_mm": self.mean_radius_mm,
            "thickness_mm": self.thickness_mm, "youngs_modulus_mpa": self.youngs_modulus_mpa,
            "poisson_ratio": self.poisson_ratio, "torque_nmm": self.torque_nmm,
        })


@dataclass(frozen=True, slots=True, eq=False)
class CupBottomStress:
    """Stresses of the cup bottom (seed 002's plate) for one w(φ) and torque.

    ``field``: the :class:`PlateField` (evaluate anywhere: ``field.surface_stress_mpa``).
    Maps on the grid ``r_mm`` × ``phi_rad`` (shape (nr, nφ)), on the face z = +t/2 where
    σ = 6M/t² (seed 002's formulas): ``sigma_r_mpa``, ``sigma_phi_mpa``, ``tau_bending_mpa``
    (6M_rφ/t²), ``tau_total_mpa`` (τ_bending + τ_load, the paper's algebraic sum), and
    ``von_mises_mpa``, the larger of the two faces (on z = −t/2 the bending stresses change
    sign, the torque shear does not, so one face always carries |τ_b| + |τ_load|).
    ``tau_load_mpa`` (nr,) = T/(2π r² t).

    Maxima, refined off the grid by a local sub-grid search: ``max_von_mises_mpa`` at
    (``max_r_mm``, ``max_phi_rad``) on face ``max_face`` (+1: z = +t/2); ``max_sigma_r_mpa``
    (|σ_r|, the bending part) at (``max_sigma_r_r_mm``, ``max_sigma_r_phi_rad``).
    ``error_estimate_mpa``: the refinement's gain over the grid maximum plus the maximum
    times the relative size of the harmonics dropped from w(φ). ``bc_residual``: largest
    residual of the (scaled) boundary-condition solves."""

    field: PlateField
    edge: EdgeDisplacement
    r_mm: np.ndarray
    phi_rad: np.ndarray
    sigma_r_mpa: np.ndarray
    sigma_phi_mpa: np.ndarray
    tau_bending_mpa: np.ndarray
    tau_load_mpa: np.ndarray
    tau_total_mpa: np.ndarray
    von_mises_mpa: np.ndarray
    max_von_mises_mpa: float
    max_r_mm: float
    max_phi_rad: float
    max_face: int
    max_sigma_r_mpa: float
    max_sigma_r_r_mm: float
    max_sigma_r_phi_rad: float
    error_estimate_mpa: float
    bc_residual: float
    time_s: float

    def __post_init__(self):
        for name in ("r_mm", "phi_rad", "sigma_r_mpa", "sigma_phi_mpa", "tau_bending_mpa",
                     "tau_load_mpa", "tau_total_mpa", "von_mises_mpa"):
            object.__setattr__(self, name, readonly(getattr(self, name)))

    @property
    def model(self) -> str:
        return self.field.model

    def to_dict(self) -> dict:
        return json_ready({
            "field": self.field.to_dict(),
            "edge": self.edge.to_dict(),
            "max_von_mises_mpa": self.max_von_mises_mpa,
            "max_r_mm": self.max_r_mm,
            "max_phi_deg": math.degrees(self.max_phi_rad),
            "max_face": self.max_face,
            "max_sigma_r_mpa": self.max_sigma_r_mpa,
            "max_sigma_r_r_mm": self.max_sigma_r_r_mm,
            "max_sigma_r_phi_deg": math.degrees(self.max_sigma_r_phi_rad),
            "error_estimate_mpa": self.error_estimate_mpa,
            "bc_residual": self.bc_residual,
            "time_s": self.time_s,
            "r_mm": self.r_mm,
            "phi_deg": np.degrees(self.phi_rad),
            "von_mises_mpa": self.von_mises_mpa,
        })


def _von_mises(s_r, s_p, tau):
    """Plane-stress von Mises (seed 002's σ_eqv): √(½[(σr−σφ)² + σr² + σφ²] + 3τ²)."""
    return np.sqrt(0.5 * ((s_r - s_p) ** 2 + s_r**2 + s_p**2) + 3.0 * tau**2)


def _grid(r0: float, r_m: float, radial_points: int, angular_points: int) -> tuple[np.ndarray, np.ndarray]:
    """Radii clustered toward the clamp (cosine spacing), φ equispaced on [0, 2π)."""
    s = 0.5 * (1.0 - np.cos(np.linspace(0.0, math.pi, radial_points)))
    return r0 + (r_m - r0) * s, 2.0 * math.pi * np.arange(angular_points) / angular_points


def _refined_max(fn, values: np.ndarray, rr, pp, bounds_r, step, rounds: int = 5) -> tuple[float, float, float]:
    """Maximum of fn(r, φ) (vectorised): the grid maximum of ``values``, then ``rounds`` of
    a 9 × 9 sub-grid search over ± one step around the best point, the step shrinking 4×
    each round (final resolution step/4⁵). Returns (value, r, φ in [0, 2π))."""
    i, j = np.unravel_index(int(np.argmax(values)), values.shape)
    best, r_b, p_b = float(values[i, j]), float(rr[i, j]), float(pp[i, j])
    (r0, r_m), (dr, dp) = bounds_r, step
    offsets = np.linspace(-1.0, 1.0, 9)
    for _ in range(rounds):
        r = np.clip(r_b + dr * offsets, r0, r_m)[:, None]
        p = (p_b + dp * offsets)[None, :]
        trial = np.asarray(fn(r, p)) * np.ones((r.size, p.size))
        k, m = np.unravel_index(int(np.argmax(trial)), trial.shape)
        if trial[k, m] > best:
            best, r_b, p_b = float(trial[k, m]), float(r[k, 0]), float(p[0, m])
        dr, dp = dr / 4.0, dp / 4.0
    return best, r_b, float(np.mod(p_b, 2.0 * math.pi))


def solve_plate(edge: EdgeDisplacement, *, boss_radius_mm: float, thickness_mm: float,
                youngs_modulus_mpa: float, poisson_ratio: float, torque_nmm: float = 0.0,
                model: str = "consistent") -> tuple[PlateField, float]:
    """The :class:`PlateField` of :func:`cup_bottom_stress` (no stress maps), and the largest
    boundary-condition residual."""
    if not isinstance(edge, EdgeDisplacement):
        raise StressError(f"edge must be an EdgeDisplacement, got {type(edge).__name__}")
    model = _choice("model", model, MODELS)
    r0, r_m = _radii(boss_radius_mm, edge.mean_radius_mm)
    t = _positive("thickness_mm", thickness_mm, "mm")
    e = _positive("youngs_modulus_mpa", youngs_modulus_mpa, "MPa")
    nu = _poisson(poisson_ratio)
    torque = _finite("torque_nmm", torque_nmm, "N·mm")
    coefs, residual = [], 0.0
    for n, amp in zip(edge.orders, edge.amplitudes_mm):
        unit, res = _coefficients(0 if model == "seed002" else int(n), r0, r_m, nu, model)
        coefs.append(amp * unit)
        residual = max(residual, res)
    return PlateField(model, edge.orders, np.reshape(coefs, (-1, 4)), r0, r_m, t, e, nu, torque), residual


def cup_bottom_stress(edge: EdgeDisplacement, *, boss_radius_mm: float, thickness_mm: float,
                      youngs_modulus_mpa: float, poisson_ratio: float, torque_nmm: float = 0.0,
                      model: str = "consistent", radial_points: int = 41,
                      angular_points: int = 144) -> CupBottomStress:
    """Stresses of the annular cup bottom r0 = ``boss_radius_mm`` ≤ r ≤ r_m =
    ``edge.mean_radius_mm`` under the edge displacement ``edge`` and the torque
    ``torque_nmm`` (N·mm); thickness t (mm), Young's modulus E (MPa), Poisson's ratio ν.

    ``model="consistent"`` (default): for each harmonic W_n cos nφ of w(φ) the exact
    Kirchhoff solution R_n(r) cos nφ, R_n in the biharmonic basis of :func:`radial_basis`,
    with w = ∂w/∂r = 0 at r0 (clamped on the boss) and, at r_m, w = W_n cos nφ and
    M_r = −D[R'' + ν(R'/r − n²R/r²)] = 0. Why M_r: a plate edge takes one condition of
    each work-conjugate pair, (w, Kirchhoff shear V_r) and (∂w/∂r, M_r). The wall
    prescribes w (the seed's compatibility); the seed calls the edge "free" — its rotation
    is not held by the thin wall — so the moment acting on the edge, M_r (the moment on a
    circle r = const), vanishes. It is the natural condition of the energy minimum with w
    prescribed, which a Morley finite-element solution converges to (docs/theory/stresses.md).
    The seed writes "M_φ = 0": M_φ acts on radial cuts, not on the edge, so it is not a
    boundary condition (Table 1's β follow from ν f'' + f'/r = 0, see :func:`seed002_beta`).

    ``model="seed002"``: the paper's w₁ = f(r)·w(φ) with f from Table 1's basis and
    conditions. f is biharmonic only as an axisymmetric function, so f(r) cos 2φ is no plate
    solution: it meets w = ∂w/∂r = 0 at r0 and w = w(φ) at r_m, but neither equilibrium
    (∇⁴w ≠ 0) nor M_r = 0. Pass ``edge`` with ``reference="seed"`` to follow the paper.

    Stresses on the faces z = ±t/2: σ = ±6M/t² (seed 002's σ_r^ass, σ_φ^ass, τ_rφ^ass),
    τ_load = T/(2π r² t) added to τ_rφ on both faces, von Mises of (σ_r, σ_φ, τ); the larger
    face is reported. Grid: ``radial_points`` radii (clustered at the clamp) ×
    ``angular_points`` angles over [0, 2π)."""
    t_start = time.perf_counter()
    field, residual = solve_plate(edge, boss_radius_mm=boss_radius_mm, thickness_mm=thickness_mm,
                                  youngs_modulus_mpa=youngs_modulus_mpa, poisson_ratio=poisson_ratio,
                                  torque_nmm=torque_nmm, model=model)
    nr, nphi = _count("radial_points", radial_points, 3), _count("angular_points", angular_points, 8)
    r0, r_m = field.boss_radius_mm, field.mean_radius_mm
    r, phi = _grid(r0, r_m, nr, nphi)
    rr, pp = np.meshgrid(r, phi, indexing="ij")
    faces = {f: field.surface_stress_mpa(r[:, None], phi[None, :], f) for f in (1, -1)}  # = on (rr, pp)
    face = 1 if faces[1]["von_mises"].max() >= faces[-1]["von_mises"].max() else -1
    step = (float(np.max(np.diff(r))), 2.0 * math.pi / nphi)
    vm = _refined_max(lambda a, b: field.surface_stress_mpa(a, b, face)["von_mises"],
                      faces[face]["von_mises"], rr, pp, (r0, r_m), step)
    sr = _refined_max(lambda a, b: np.abs(field.surface_stress_mpa(a, b)["sigma_r"]),
                      np.abs(faces[1]["sigma_r"]), rr, pp, (r0, r_m), step)
    amplitude = float(np.sum(np.abs(edge.amplitudes_mm)))
    truncation = edge.truncation_mm / amplitude if amplitude > 0.0 else 0.0
    error = abs(vm[0] - float(faces[face]["von_mises"].max())) + truncation * vm[0]
    tau_load = torque_shear_mpa(r, field.torque_nmm, field.thickness_mm)
    top = faces[1]
    return CupBottomStress(field, edge, r, phi, top["sigma_r"], top["sigma_phi"], top["tau"] - tau_load[:, None],
                           tau_load, top["tau"], np.maximum(faces[1]["von_mises"], faces[-1]["von_mises"]),
                           vm[0], vm[1], vm[2], face, sr[0], sr[1], sr[2], error, residual,
                           time.perf_counter() - t_start)


# --------------------------------------------------------------------------- seed comparison


def seed002_comparison(*, radial_points: int = 41, angular_points: int = 144) -> list[dict]:
    """Seed 002's printed theoretical stresses (Table 2) beside the seed002 variant and the
    consistent model, for Table 1's inputs and the paper's torques (87, 395 N·m).

    One row per Table 2 line, keys ``quantity``, ``where``, ``torque_nm``, ``seed_mpa``,
    ``seed002_mpa``, ``consistent_mpa``, ``reason``. Both models are read where Table 2 says
    (r = r0, the printed φ): σ_r and τ on the face z = +t/2 (the paper's algebraic sum
    τ_ass + τ_load), von Mises the larger of the two faces. The seed002 variant uses the
    paper's w(φ) (``reference="seed"``), the consistent model the zero-mean one."""
    p = SEED002_TABLE1
    res = {}
    for model, ref in (("seed002", "seed"), ("consistent", "mean")):
        edge = edge_displacement_from_ellipse(p["semi_major_mm"], p["semi_minor_mm"],
                                              mean_radius_mm=p["mean_radius_mm"], length_mm=p["length_mm"],
                                              reference=ref)
        res[model] = {
            torque: cup_bottom_stress(edge, boss_radius_mm=p["boss_radius_mm"], thickness_mm=p["thickness_mm"],
                                      youngs_modulus_mpa=p["youngs_modulus_mpa"], poisson_ratio=p["poisson_ratio"],
                                      torque_nmm=torque * 1e3, model=model, radial_points=radial_points,
                                      angular_points=angular_points)
            for torque in (0.0, 87.0, 395.0)
        }
    rows = []
    for key, what, phi_deg, torque, seed in SEED002_TABLE2:
        values = {m: _table2_value(key, res[m][torque].field, math.radians(phi_deg)) for m in res}
        rows.append({"quantity": what, "where": f"r = r0 = {p['boss_radius_mm']:g} mm, φ = {phi_deg:g}°",
                     "torque_nm": torque, "seed_mpa": seed, "seed002_mpa": values["seed002"],
                     "consistent_mpa": values["consistent"], "reason": _reason(key, seed, values, res)})
    return rows


def _table2_value(key: str, field: PlateField, phi: float) -> float:
    r0 = field.boss_radius_mm
    if key == "von_mises_max":
        return float(max(field.surface_stress_mpa(r0, phi, f)["von_mises"] for f in (1, -1)))
    s = field.surface_stress_mpa(r0, phi, 1)
    return float(abs(s["sigma_r"]) if key == "sigma_r_assembly" else abs(s["tau"]))


def _max_along(field: PlateField, phi: float, quantity: str) -> tuple[float, float]:
    """max |quantity| on the face z = +t/2 along the ray φ, and its radius."""
    r = np.linspace(field.boss_radius_mm, field.mean_radius_mm, 801)
    values = np.abs(field.surface_stress_mpa(r, phi, 1)[quantity])
    i = int(np.argmax(values))
    return float(values[i]), float(r[i])


def _reason(key: str, seed: float, values: dict, res: dict) -> str:
    """Why the printed value differs, with the numbers behind it."""
    s2, co = values["seed002"], values["consistent"]
    p = SEED002_TABLE1
    if key == "sigma_r_assembly":
        w0 = float(res["seed002"][0.0].edge(0.0))
        a_b = p["semi_major_mm"] - p["semi_minor_mm"]
        return (f"seed002 is the paper's own σ_r^ass formula with Table 1's inputs (w(0) = {w0:.4f} mm); the "
                f"printed {seed:g} is {seed / s2:.3f}× that and not reproducible: it needs w(0) = "
                f"{w0 * seed / s2:.4f} mm, close to (a − b)/8 = {a_b / 8:.4f} mm, i.e. w(φ) without the factor "
                f"r_m/l = 1/(2k) (a guess). The consistent model is {100 * (co / s2 - 1):+.1f} % from seed002: "
                "f(r) cos 2φ is not in equilibrium (∇⁴w ≠ 0) and ν f'' + f'/r = 0 is not the edge condition "
                "M_r = 0; a Morley finite-element solution of the same plate sides with the consistent model "
                "(docs/theory/stresses.md).")
    if key == "tau_total_rated":
        phi = math.radians(45.0)
        tc, rc = _max_along(res["consistent"][87.0].field, phi, "tau")
        ts, rs = _max_along(res["seed002"][87.0].field, phi, "tau")
        ac, _ = _max_along(res["consistent"][0.0].field, phi, "tau")
        as_, _ = _max_along(res["seed002"][0.0].field, phi, "tau")
        return (f"the clamp (w = ∂w/∂r = 0 along r0) makes the bending shear vanish at r0 in any model, so both "
                f"give τ = T/(2π r0² t) = {co:.1f}; the printed {seed:g} exceeds the paper's own formula at r0. "
                f"Along φ = 45° the maximum of τ_total is {tc:.1f} at r = {rc:.1f} mm (consistent) / {ts:.1f} at "
                f"r = {rs:.1f} mm (seed002); assembly only {ac:.1f} / {as_:.1f}.")
    if key == "tau_total_max":
        r_eq = math.sqrt(395e3 / (2.0 * math.pi * seed * p["thickness_mm"]))
        return (f"at φ = 0 the bending shear vanishes by symmetry (∂w/∂φ = 0) and at r0 by the clamp: both "
                f"models give τ = T/(2π r0² t) = {co:.1f}; the printed {seed:g} is {100 * (seed / co - 1):+.1f} % off the "
                f"paper's own formula (it is its value at r = {r_eq:.2f} mm).")
    tau = 395e3 / (2.0 * math.pi * p["boss_radius_mm"] ** 2 * p["thickness_mm"])
    return (f"τ_load(r0) = {tau:.1f} alone gives σ_eqv = √3 τ = {math.sqrt(3) * tau:.0f}; the printed ~{seed:g} "
            f"equals τ_load(r0) — apparently the shear, not the von Mises stress. Both models add σ_r, σ_φ at "
            f"r0; the consistent model is {100 * (co / s2 - 1):+.1f} % from seed002.")
