"""Diaphragm of a cup flexspline at the boss corner: shear stress and Goodman check (seed 000).

Seed 000 (``shared/seeds/000_*.txt``, sections 4.4 and 5.5) measures and computes (3D FEM) the
stresses next to the corner where the diaphragm meets the boss of a CSF40-100 flexspline and
finds: the radial and circumferential normal stresses do not change with the torque; the
shear stress τ_rφ is a sine wave in the wave generator's angle whose *amplitude* τ_a is set by
the elliptical deflection alone and whose *mean* τ_m grows linearly with the torque (13.6 MPa
at 110 N·m at its gauge). It proposes a Goodman diagram of (τ_m, τ_a) at the corner's
maximum-stress point (its Fig. 21) — and gives **no formula** for either τ_a or τ_m, nor the
Goodman line, nor the material limits. This module supplies them:

* τ_m = T / (2π r0² t): the torque T (N·mm) carried by the annulus of thickness t at the boss
  radius r0 (thin-walled torsion; the same expression as seed 002's τ_load), at the boss —
  its largest value on the diaphragm (:func:`mean_shear_stress_mpa`).
* τ_a: the surface shear of the diaphragm's twisting moment, from the Kirchhoff plate
  r0 ≤ r ≤ r_c clamped on the boss and driven at its outer edge by the cup wall
  (:func:`diaphragm_stress`). The wall of length l, forced by the wave generator to the
  radial displacement w0 cos 2φ at its far end and held round at the diaphragm, is
  inextensible along its generators and in shear (semi-membrane theory): w_r = w0 (z/l) cos 2φ,
  v = −(w0 z/(2l)) sin 2φ, and the edge moves axially by u_a cos 2φ with
  u_a = r_c w0 / (4 l) (:func:`edge_axial_amplitude_mm`; seed 002's w₀(φ), periodic part).
  For w = F(r) cos 2φ the plate solution is F = c1 ρ² + c2 ρ⁻² + c3 ρ⁴ + c4 (ρ = r/r_c),
  with F = F' = 0 at r0 and F = u_a at r_c, and either M_r = 0 there (``outer_edge="hinged"``:
  the thin wall takes no axial bending moment, semi-membrane theory's own assumption; the
  default) or the wall's tilt w0/l imposed on the plate's slope (``"rigid_joint"``: a rigid
  right-angled corner; F'(r_c) = 4 F(r_c)/r_c). The surface shear is
  τ_rφ = 6 M_rφ/t² = (E t/(1 + ν)) (F'/r − F/r²) sin 2φ.

  A perfectly clamped Kirchhoff edge has no twist, so τ_a = 0 exactly *at* r = r0; the seed's
  maximum lies "near the middle point of the corner" (the fillet) and its gauge "next to the
  corner". τ_a is therefore read at r0 + ``corner_offset_mm`` (default one diaphragm thickness,
  where thin-plate theory starts to hold); its maximum over the diaphragm is reported too.
* Goodman for shear: τ_a/τ_-1 + τ_m/τ_u = 1/n (:func:`goodman_shear_safety_factor`), τ_-1 the
  shear endurance limit (fully reversed), τ_u = k σ_u the ultimate shear strength with
  k = 0.577 by default (von Mises; Shigley's torsion data give 0.67 — less conservative).

Units mm, N, MPa, N·mm (torque), rad. ν here is Poisson's ratio.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import StressError
from ..results import json_ready, readonly
from .inputs import finite as _finite, non_negative as _non_negative, positive as _positive
from .plate import flexural_row, radial_basis

__all__ = [
    "OUTER_EDGES",
    "DiaphragmStress",
    "diaphragm_stress",
    "edge_axial_amplitude_mm",
    "goodman_safety_factor",
    "goodman_shear_safety_factor",
    "mean_shear_stress_mpa",
]

OUTER_EDGES = ("hinged", "rigid_joint")


# --------------------------------------------------------------------------- validation








def _limit(name: str, value, unit: str) -> float:
    if value is None:
        raise StressError(f"{name} is None: the Goodman check needs it, in (0, inf) {unit} "
                          "(or pass fatigue=False)")
    return _positive(name, value, unit)


# --------------------------------------------------------------------------- pieces


def mean_shear_stress_mpa(torque_nmm: float, radius_mm: float, thickness_mm: float) -> float:
    """τ_m = T / (2π r² t) (MPa): the shear of torque T (N·mm) in a thin annulus of radius r
    and thickness t (mm), uniform through the thickness. Linear in T; at r = r0 (the boss) it
    is the diaphragm's largest."""
    from .plate import torque_shear_mpa

    return float(torque_shear_mpa(_positive("radius_mm", radius_mm, "mm"), torque_nmm, thickness_mm))


def edge_axial_amplitude_mm(cup_radius_mm: float, deflection_mm: float, cup_length_mm: float) -> float:
    """u_a = r_c w0 / (4 l) (mm): the amplitude of the axial displacement u_a cos 2φ of the cup
    wall's end at the diaphragm (semi-membrane theory: generators inextensible, no membrane
    shear), r_c the wall's radius, w0 the radial amplitude at distance l from the diaphragm."""
    r_c = _positive("cup_radius_mm", cup_radius_mm, "mm")
    w0 = _positive("deflection_mm", deflection_mm, "mm")
    length = _positive("cup_length_mm", cup_length_mm, "mm")
    return r_c * w0 / (4.0 * length)


def goodman_safety_factor(amplitude_mpa: float, mean_mpa: float, endurance_limit_mpa: float,
                          ultimate_mpa: float) -> float:
    """Safety factor n of the Goodman line, a/e + m/u = 1/n: n = 1 / (|a|/e + |m|/u). All in
    MPa; e the fully reversed endurance limit, u the ultimate strength, in shear (τ_-1, τ_u)
    or in tension (σ_-1, σ_u). The sign of a shear mean does not matter. n = inf when
    a = m = 0."""
    tau_a = abs(_finite("amplitude_mpa", amplitude_mpa, "MPa"))
    tau_m = abs(_finite("mean_mpa", mean_mpa, "MPa"))
    tau_e = _positive("endurance_limit_mpa", endurance_limit_mpa, "MPa")
    tau_u = _positive("ultimate_mpa", ultimate_mpa, "MPa")
    if tau_e > tau_u:
        raise StressError(f"endurance_limit_mpa must be in (0, ultimate_mpa = {tau_u!r}] MPa, got {tau_e!r}")
    usage = tau_a / tau_e + tau_m / tau_u
    return math.inf if usage == 0.0 else 1.0 / usage


#: seed 000's criterion: the Goodman line in shear
goodman_shear_safety_factor = goodman_safety_factor


def _mode_coefficients(boss_ratio: float, poisson_ratio: float, outer_edge: str) -> np.ndarray:
    """c1..c4 of F(ρ) = c1 ρ² + c2 ρ⁻² + c3 ρ⁴ + c4 (unit edge amplitude, ρ = r/r_c: the
    plate's n = 2 harmonic, :func:`plate.radial_basis`) with F(ρ0) = F_ρ(ρ0) = 0, F(1) = 1 and
    M_r(1) = 0 (hinged: the cup bottom's condition) or F_ρ(1) = 4 (rigid joint)."""
    at_boss, at_edge = radial_basis(2, boss_ratio, 1.0), radial_basis(2, 1.0, 1.0)
    if outer_edge == "hinged":
        last, value = flexural_row(at_edge, 1.0, 2, poisson_ratio, "M_r"), 0.0
    else:
        last, value = at_edge[1], 4.0
    return np.linalg.solve(np.array([at_boss[0], at_boss[1], at_edge[0], last]), np.array([0.0, 0.0, 1.0, value]))


def _mode_shape(coef: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """F, F_ρ, F_ρρ of the unit mode at ρ = x."""
    f, f1, f2 = np.tensordot(coef, radial_basis(2, x, 1.0), axes=(0, 1))
    return f, f1, f2


# --------------------------------------------------------------------------- result


@dataclass(frozen=True, slots=True, eq=False)
class DiaphragmStress:
    """Shear of the diaphragm near the boss corner and its Goodman check (MPa, mm).

    Profiles over ``radius_mm`` (r0 … r_c): the axial deflection amplitude F(r) (mm, of
    cos 2φ), the surface shear amplitude τ_a(r) and radial bending stress amplitude σ_r(r)
    (of sin 2φ / cos 2φ) and the torque's mean shear τ_m(r). Scalars: τ_a at
    ``evaluation_radius_mm``, its maximum over the diaphragm, τ_m at the boss, the corner's
    σ_r amplitude (at r0; not in seed 000's criterion), the Goodman safety factor (None when
    fatigue was not asked for)."""

    radius_mm: np.ndarray
    deflection_amplitude_mm: np.ndarray
    shear_amplitude_profile_mpa: np.ndarray
    radial_stress_amplitude_profile_mpa: np.ndarray
    mean_shear_profile_mpa: np.ndarray
    edge_axial_amplitude_mm: float
    evaluation_radius_mm: float
    shear_amplitude_mpa: float
    max_shear_amplitude_mpa: float
    max_shear_amplitude_radius_mm: float
    corner_radial_stress_amplitude_mpa: float
    mean_shear_mpa: float
    shear_endurance_limit_mpa: float | None
    shear_ultimate_mpa: float | None
    safety_factor: float | None
    outer_edge: str
    inputs: dict
    time_s: float
    warnings: tuple[str, ...] = field(default=())

    def __post_init__(self):
        for name in ("radius_mm", "deflection_amplitude_mm", "shear_amplitude_profile_mpa",
                     "radial_stress_amplitude_profile_mpa", "mean_shear_profile_mpa"):
            object.__setattr__(self, name, readonly(getattr(self, name)))
        object.__setattr__(self, "inputs", dict(self.inputs))

    @property
    def max_shear_mpa(self) -> float:
        """τ_m + τ_a: the peak of the shear wave (at the evaluation radius's amplitude)."""
        return self.mean_shear_mpa + self.shear_amplitude_mpa

    def to_dict(self) -> dict:
        out = {name: getattr(self, name) for name in self.__slots__}
        out["max_shear_mpa"] = self.max_shear_mpa
        return json_ready(out)


def diaphragm_stress(*, cup_radius_mm: float, boss_radius_mm: float, diaphragm_thickness_mm: float,
                     cup_length_mm: float, deflection_mm: float, youngs_modulus_mpa: float, poisson_ratio: float,
                     torque_nmm: float, shear_endurance_limit_mpa: float | None = None,
                     ultimate_strength_mpa: float | None = None, shear_ultimate_ratio: float = 0.577,
                     fatigue: bool = True, outer_edge: str = "hinged", corner_offset_mm: float | None = None,
                     samples: int = 201) -> DiaphragmStress:
    """Shear amplitude and mean at the diaphragm–boss corner of a cup flexspline, and the
    Goodman safety factor (seed 000's criterion, with the model of this module's docstring).

    Inputs (mm, MPa, N·mm): r_c ``cup_radius_mm`` (mid-wall radius of the cup where the
    diaphragm joins it); r0 ``boss_radius_mm`` (< r_c); t ``diaphragm_thickness_mm``;
    l ``cup_length_mm`` (diaphragm to the wave generator's section); w0 ``deflection_mm``
    (radial cos 2φ amplitude there); E, ν; T ``torque_nmm`` (≥ 0). Fatigue (``fatigue=True``)
    needs τ_-1 ``shear_endurance_limit_mpa`` and σ_u ``ultimate_strength_mpa``;
    τ_u = ``shear_ultimate_ratio`` · σ_u. τ_a is read at r0 + ``corner_offset_mm`` (default t);
    ``samples`` radii for the profiles.

    The Goodman point pairs τ_m at the boss (its maximum) with τ_a at the evaluation radius —
    conservative by the factor (1 + offset/r0)² on τ_m against a strict single-point check
    (9 % for r0 = 24 mm, t = 1.1 mm); ``mean_shear_profile_mpa`` gives τ_m at any radius."""
    t_start = time.perf_counter()
    r_c = _positive("cup_radius_mm", cup_radius_mm, "mm")
    r0 = _positive("boss_radius_mm", boss_radius_mm, "mm")
    if r0 >= r_c:
        raise StressError(f"boss_radius_mm must be in (0, cup_radius_mm = {r_c!r}) mm, got {r0!r}")
    t = _positive("diaphragm_thickness_mm", diaphragm_thickness_mm, "mm")
    u_a = edge_axial_amplitude_mm(r_c, deflection_mm, cup_length_mm)
    e = _positive("youngs_modulus_mpa", youngs_modulus_mpa, "MPa")
    nu = _finite("poisson_ratio", poisson_ratio, "(dimensionless)")
    if not -1.0 < nu < 0.5:
        raise StressError(f"poisson_ratio must be in (-1, 0.5), got {nu!r}")
    torque = _non_negative("torque_nmm", torque_nmm, "N·mm")
    if outer_edge not in OUTER_EDGES:
        raise StressError(f"outer_edge must be one of {', '.join(map(repr, OUTER_EDGES))}, got {outer_edge!r}")
    offset = t if corner_offset_mm is None else _non_negative("corner_offset_mm", corner_offset_mm, "mm")
    if r0 + offset >= r_c:
        raise StressError(f"corner_offset_mm must be in [0, cup_radius_mm − boss_radius_mm = {r_c - r0!r}) mm, "
                          f"got {offset!r}")
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 3:
        raise StressError(f"samples must be an integer in [3, inf), got {samples!r}")
    tau_e: float | None
    tau_u: float | None
    n: float | None
    if fatigue:
        tau_e = _limit("shear_endurance_limit_mpa", shear_endurance_limit_mpa, "MPa")
        sigma_u = _limit("ultimate_strength_mpa", ultimate_strength_mpa, "MPa")
        k = _finite("shear_ultimate_ratio", shear_ultimate_ratio, "(dimensionless)")
        if not 0.0 < k <= 1.0:
            raise StressError(f"shear_ultimate_ratio must be in (0, 1], got {k!r}")
        tau_u = k * sigma_u

    coef = _mode_coefficients(r0 / r_c, nu, outer_edge)
    shear_scale = e * t * u_a / ((1.0 + nu) * r_c**2)
    bend_scale = e * t * u_a / (2.0 * (1.0 - nu * nu) * r_c**2)

    def shear(x):
        f, f1, _ = _mode_shape(coef, x)
        return shear_scale * np.abs(f1 / x - f / x**2)

    r = np.linspace(r0, r_c, int(samples))
    x = r / r_c
    f, f1, f2 = _mode_shape(coef, x)
    tau_profile = shear(x)
    sigma_profile = bend_scale * np.abs(f2 + nu * (f1 / x - 4.0 * f / x**2))
    r_eval = r0 + offset
    tau_a = float(shear(np.array(r_eval / r_c)))
    i_max = int(np.argmax(tau_profile))
    tau_m = mean_shear_stress_mpa(torque, r0, t)
    warnings = []
    if fatigue:
        assert tau_e is not None and tau_u is not None  # read above
        n = goodman_shear_safety_factor(tau_a, tau_m, tau_e, tau_u)
        if n < 1.0:
            warnings.append(f"Goodman safety factor {n:.3g} < 1: the diaphragm corner is expected to fail in fatigue")
    else:
        tau_e = tau_u = n = None
    if offset > 0.25 * (r_c - r0):
        warnings.append(f"corner_offset_mm = {offset:g} mm is over a quarter of the diaphragm's width: "
                        "τ_a is read far from the corner")
    inputs = {
        "cup_radius_mm": r_c, "boss_radius_mm": r0, "diaphragm_thickness_mm": t, "cup_length_mm": float(cup_length_mm),
        "deflection_mm": float(deflection_mm), "youngs_modulus_mpa": e, "poisson_ratio": nu, "torque_nmm": torque,
        "shear_endurance_limit_mpa": shear_endurance_limit_mpa, "ultimate_strength_mpa": ultimate_strength_mpa,
        "shear_ultimate_ratio": shear_ultimate_ratio, "fatigue": bool(fatigue), "corner_offset_mm": offset,
    }
    return DiaphragmStress(
        radius_mm=r, deflection_amplitude_mm=u_a * f, shear_amplitude_profile_mpa=tau_profile,
        radial_stress_amplitude_profile_mpa=sigma_profile, mean_shear_profile_mpa=torque / (2.0 * math.pi * r**2 * t),
        edge_axial_amplitude_mm=u_a, evaluation_radius_mm=r_eval, shear_amplitude_mpa=tau_a,
        max_shear_amplitude_mpa=float(tau_profile[i_max]), max_shear_amplitude_radius_mm=float(r[i_max]),
        corner_radial_stress_amplitude_mpa=float(sigma_profile[0]), mean_shear_mpa=tau_m,
        shear_endurance_limit_mpa=tau_e, shear_ultimate_mpa=tau_u, safety_factor=n, outer_edge=outer_edge,
        inputs=inputs, time_s=time.perf_counter() - t_start, warnings=tuple(warnings),
    )
