"""Flexspline tooth-ring stress (seed 001), as pure functions of explicit numbers.

Seed 001 (``shared/seeds/001_*.txt``) adds two bending stresses at the dedendum fillet of a
tooth on the wave generator's major axis:

* the **assembly stress** σ_ass = K_σ · E δ/2 · (κ − 1/r_m): the curvature change of the
  tooth ring's neutral line (initial radius r_m) forced into an ellipse by the wave generator,
  as a shell bending stress, raised to the fillet's peak by the FE-fitted stress influence
  factor K_σ(s_f/δ, r1/δ) (:func:`stress_influence_factor`);
* the **load stress** σ_load = 6 M_yσ/δ² from the root moment M_yσ of the tangential mesh
  force q_t (:func:`load_moment_factor`, :func:`load_stress_mpa`);

and σ_total = σ_ass + σ_load (:func:`tooth_ring_stress` → :class:`ToothRingStress`).

Symbols and units (mm, N, MPa, N·mm, rad): r_m neutral-line radius before deformation;
δ rim (tooth-ring) thickness under the teeth; w0 radial deflection on the major axis;
ρ_a = r_m + w0, ρ_b the semi-axes of the deformed neutral line; E Young's modulus;
s_f tooth root thickness; r1 dedendum fillet radius; p = πm circular pitch; h total tooth
height; h0 equivalent tooth height (h_p = δ + h0); b face (tooth-ring) width; ν slot width
ratio (space width / tooth thickness on the pitch circle — not Poisson's ratio here).

Where the seed is wrong or silent (details in the functions):

1. Its κ(φ) gives NaN as written (:func:`seed001_printed_curvature`); the exact ellipse
   curvature is :func:`ellipse_curvature`, and :func:`displaced_curvature` is the exact
   curvature of any displaced neutral line (r_m + ω) e_r + υ e_t (docs/theory/stresses.md).
2. ρ_b is not explained; the table's 28.741 mm is the ellipse of the same perimeter as the
   neutral circle (an inextensible neutral line, :func:`equal_perimeter_minor_semi_axis`).
3. 6 M/δ² is a stress only if q_t is a force per unit face width: q_t = F_t / b.
4. The stresses of its tables depend on inputs it does not state (s_f, h, h0, q_t(T), the base
   thickness); :func:`seed001_comparison` lists what we assumed and what follows, and
   :func:`seed001_trend_checks` which of its claimed trends the model really produces.

The parametric study (:func:`tooth_ring_study`) runs standalone on a :class:`ToothRingCase`
(seed 001's SHF-25 numbers, :func:`seed001_case`) with q_t estimated from the torque
(:func:`tangential_force_estimate_n`); in the pipeline q_t should be the maximum tooth force
of the package's own contact solution (trap 6).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import StressError
from ..results import json_ready, readonly
from .inputs import count as _count, finite_array as _finite_array, in_open as _in_open, non_negative as _non_negative
from .inputs import positive as _positive

__all__ = [
    "SEED001_TABLE",
    "SEED001_TORQUES_NM",
    "SEED001_OPTIMAL_THICKNESS",
    "SEED001_STRESSES_MPA",
    "SeedComparison",
    "ToothRingCase",
    "ToothRingStress",
    "ToothRingStudy",
    "TrendCheck",
    "assembly_stress_mpa",
    "case_inputs",
    "case_stress_mpa",
    "displaced_curvature",
    "section_curvature",
    "ellipse_curvature",
    "equal_perimeter_minor_semi_axis",
    "load_moment_factor",
    "load_moment_nmm_per_mm",
    "load_stress_mpa",
    "optimal_fillet_radius_mm",
    "root_thickness_from_slot_ratio",
    "seed001_case",
    "seed001_comparison",
    "seed001_printed_curvature",
    "seed001_trend_checks",
    "stress_influence_factor",
    "tangential_force_estimate_n",
    "tooth_ring_stress",
    "tooth_ring_study",
]

#: Seed 001, parameter table (SHF-25-80 flexspline): lengths mm, E MPa.
SEED001_TABLE = {
    "module_mm": 0.375,
    "neutral_radius_mm": 29.119,
    "flexspline_teeth": 160,
    "face_width_mm": 10.0,
    "major_semi_axis_mm": 29.494,
    "minor_semi_axis_mm": 28.741,
    "youngs_modulus_mpa": 210000.0,
}
#: Seed 001, load conditions (N·m): rated, average maximum, peak start-stop, momentary maximum.
SEED001_TORQUES_NM = {"RAT": 67.0, "AVT": 108.0, "STT": 167.0, "MIT": 304.0}
#: Seed 001, optimal δ/r_m per torque (N·m) for ν = 1.4, 1.8, 2.2 (its "~" values).
SEED001_OPTIMAL_THICKNESS = {
    "slot_ratios": (1.4, 1.8, 2.2),
    67.0: (0.0295, 0.0285, 0.0275),
    108.0: (0.0310, 0.0300, 0.0290),
    167.0: (0.0320, 0.0310, 0.0300),
    304.0: (0.0345, 0.0335, 0.0325),
}
#: Seed 001, theoretical stresses of its FEA-validation paragraph (MPa).
SEED001_STRESSES_MPA = {
    "assembly_base": 242.7,  # no load, "base configuration" (δ, s_f, r1, ν not stated)
    "total_rated": 371.1,  # 67 N·m, same base configuration
    "total_mit_optimum": 496.1,  # 304 N·m, δ/r_m = 3.375 %, r1/m = 0.7, ν = 1.8
}


# --------------------------------------------------------------------------- validation












# --------------------------------------------------------------------------- curvature


def equal_perimeter_minor_semi_axis(neutral_radius_mm: float, major_semi_axis_mm: float) -> float:
    """Minor semi-axis ρ_b (mm) of the ellipse with major semi-axis ρ_a = ``major_semi_axis_mm``
    and the perimeter 2π r_m of the undeformed neutral circle (an inextensible neutral line).

    Seed 001 gives ρ_b = 28.741 mm for r_m = 29.119 mm, ρ_a = 29.494 mm without saying how;
    the equal-perimeter ellipse gives 28.74157 mm (the semi-axes' sum is not 2 r_m: the
    ellipse with ρ_a + ρ_b = 2 r_m is 2.4 µm longer). Perimeter 4 ρ_a E(1 − ρ_b²/ρ_a²),
    E the complete elliptic integral of the second kind (scipy's parameter m = k²)."""
    from scipy.optimize import brentq
    from scipy.special import ellipe

    r_m = _positive("neutral_radius_mm", neutral_radius_mm, "mm")
    given = _finite_array("major_semi_axis_mm", major_semi_axis_mm, "mm")
    if given.ndim or not r_m <= float(given) < 1.5 * r_m:
        raise StressError(f"major_semi_axis_mm must be in [neutral_radius_mm = {r_m!r}, {1.5 * r_m!r}) mm, "
                          f"got {major_semi_axis_mm!r}")
    a = float(given)
    if a == r_m:
        return r_m
    target = 2.0 * math.pi * r_m
    return float(brentq(lambda b: 4.0 * a * ellipe(1.0 - (b / a) ** 2) - target, 0.5 * r_m, r_m,
                        xtol=1e-13, rtol=4 * np.finfo(float).eps))


def ellipse_curvature(polar_angle_rad, major_semi_axis_mm: float, minor_semi_axis_mm: float) -> np.ndarray:
    """Exact curvature (1/mm) of the ellipse x²/ρ_a² + y²/ρ_b² = 1 at the point seen from its
    centre under the polar angle θ (rad, from the major axis):

        κ(θ) = (c1/ρ_b) · (c1² sin²θ + cos²θ)^{3/2} / (c1⁴ sin²θ + cos²θ)^{3/2},  c1 = ρ_a/ρ_b,

    from κ = ρ_aρ_b/(ρ_a² sin²t + ρ_b² cos²t)^{3/2} with the parameter t, tan t = c1 tan θ.
    κ(0) = ρ_a/ρ_b², κ(π/2) = ρ_b/ρ_a².

    This is seed 001's κ(φ) with the sign of both brackets corrected
    (:func:`seed001_printed_curvature`). The seed calls φ the "initial polar angle"; the
    formula is in the polar angle θ of the *deformed* point. They agree on the axes (where the
    stress is evaluated); elsewhere a material point at initial angle φ sits at
    θ = φ + atan2(υ, r_m + ω) — use :func:`displaced_curvature` for the curvature at φ."""
    a = _positive("major_semi_axis_mm", major_semi_axis_mm, "mm")
    b = _positive("minor_semi_axis_mm", minor_semi_axis_mm, "mm")
    theta = _finite_array("polar_angle_rad", polar_angle_rad, "rad")
    c1 = a / b
    s2, c2 = np.sin(theta) ** 2, np.cos(theta) ** 2
    return (c1 / b) * ((c1**2 * s2 + c2) / (c1**4 * s2 + c2)) ** 1.5


def seed001_printed_curvature(phi_rad, major_semi_axis_mm: float, minor_semi_axis_mm: float,
                              *, complex_arithmetic: bool = False) -> np.ndarray:
    """Seed 001's κ(φ) exactly as printed — kept to document why it cannot be used:

        κ(φ) = | (c1/ρ_b) (c1² cos²φ − cos²φ − c1²)^{3/2} / (c1⁴ cos²φ − cos²φ − c1⁴)^{3/2} |.

    With c1 = ρ_a/ρ_b > 1 the first bracket is (c1² − 1) cos²φ − c1² ≤ −1 < 0 for every φ,
    and the second (c1⁴ − 1) cos²φ − c1⁴ ≤ −1 < 0: each is a negative number raised to 3/2,
    which is NaN in real (NumPy) arithmetic — "NaN as written" (Python floats and MATLAB
    return a complex number instead). Both brackets are the negatives of the correct ones;
    in complex arithmetic (−x)^{3/2}/(−y)^{3/2} = (x/y)^{3/2} (the factors e^{3iπ/2} cancel),
    so ``complex_arithmetic=True`` returns the exact ellipse curvature of
    :func:`ellipse_curvature` — the formula is right up to that sign slip. Real input → NaN
    (the RuntimeWarning is silenced)."""
    a = _positive("major_semi_axis_mm", major_semi_axis_mm, "mm")
    b = _positive("minor_semi_axis_mm", minor_semi_axis_mm, "mm")
    phi = _finite_array("phi_rad", phi_rad, "rad")
    c1, c2 = a / b, np.cos(phi) ** 2
    dtype = complex if complex_arithmetic else float
    num = np.asarray(c1**2 * c2 - c2 - c1**2, dtype=dtype)
    den = np.asarray(c1**4 * c2 - c2 - c1**4, dtype=dtype)
    with np.errstate(invalid="ignore"):
        return np.abs((c1 / b) * num**1.5 / den**1.5)


def _sampled(name: str, value, phi: np.ndarray) -> np.ndarray:
    """``value`` evaluated on φ: a callable of φ, or an array broadcastable to φ's shape."""
    if callable(value):
        value = value(phi)
    arr = _finite_array(name, value, "mm")
    try:
        return np.broadcast_to(arr, phi.shape)
    except ValueError:
        raise StressError(f"{name} must have the shape of phi_rad {phi.shape}, got {arr.shape}") from None


def displaced_curvature(phi_rad, neutral_radius_mm: float, omega_mm, omega_d1_mm, omega_d2_mm,
                        upsilon_mm, upsilon_d1_mm, upsilon_d2_mm) -> np.ndarray:
    """Exact curvature (1/mm) of the displaced neutral line at the material points of initial
    polar angle φ (rad):

        R(φ) = (r_m + ω) e_r(φ) + υ e_t(φ),    e_r' = e_t, e_t' = −e_r,
        R'  = A e_r + B e_t,   A = ω' − υ,  B = r_m + ω + υ',
        R'' = (ω'' − 2υ' − r_m − ω) e_r + (2ω' − υ + υ'') e_t,
        κ   = (R' × R'') / |R'|³ = (A (2ω' − υ + υ'') − B (ω'' − 2υ' − r_m − ω)) / (A² + B²)^{3/2},

    positive where the line turns counter-clockwise (a circle: 1/r). ω, υ (mm) and their
    φ-derivatives (ω', ω'', υ', υ'' in mm per rad^k) are arrays on ``phi_rad`` or callables of
    φ. No linearisation: a rigid translation (ω = d cos φ, υ = −d sin φ) gives 1/r_m exactly,
    a rigid rotation (υ = const) 1/√(r_m² + υ²). To first order in the displacements this is
    the classical κ − 1/r_m = −(ω + ω'')/r_m², with no υ at all; υ, υ' and υ'' enter at second
    order (e.g. the term A·υ''), which is why the exact value needs υ'' too. For seed 001's ring
    (w0/r_m = 1.3 %) the linear formula with ω = w0 cos 2φ is 2.7 % below the exact ellipse
    curvature change on the major axis.

    Use it with ω, υ from a rim solution for the assembly stress at any φ
    (:func:`assembly_stress_mpa`)."""
    phi = _finite_array("phi_rad", phi_rad, "rad")
    r_m = _positive("neutral_radius_mm", neutral_radius_mm, "mm")
    w, w1, w2 = (_sampled(n, v, phi) for n, v in
                 (("omega_mm", omega_mm), ("omega_d1_mm", omega_d1_mm), ("omega_d2_mm", omega_d2_mm)))
    u, u1, u2 = (_sampled(n, v, phi) for n, v in
                 (("upsilon_mm", upsilon_mm), ("upsilon_d1_mm", upsilon_d1_mm), ("upsilon_d2_mm", upsilon_d2_mm)))
    a, b = w1 - u, r_m + w + u1
    a2, b2 = w2 - 2.0 * u1 - r_m - w, 2.0 * w1 - u + u2
    speed2 = a * a + b * b
    if np.any(speed2 <= 0.0):
        raise StressError("displaced neutral line has a cusp (|R'(φ)| = 0): ω, υ are not a deformation of "
                          f"a ring of radius {r_m!r} mm")
    return (a * b2 - b * a2) / speed2**1.5


def section_curvature(deformation, neutral_radius_mm: float):
    """The deformed section's own curvature κ(φ) (1/mm) as a function of the material angle φ
    (rad): :func:`displaced_curvature` of ``deformation``'s ω, υ and their first two derivatives
    (anything with ``evaluate(phi, order)``, e.g. the rim stage's Fourier fit at the design
    section). On the major axis (φ = 0) it is the curvature the assembly stress needs; the
    equivalent ellipse through ω(0) and ω(π/2) (:func:`ellipse_curvature`) misses the higher
    harmonics of a cup pressed onto the wave generator over the bearing width (seed000_csf40's
    verify scene, design section z = 70 mm: Δκ 1.18e-3 /mm against the ellipse's 7.0e-4)."""
    r_m = _positive("neutral_radius_mm", neutral_radius_mm, "mm")
    if not callable(getattr(deformation, "evaluate", None)):
        raise StressError(f"deformation: must have evaluate(phi, order) (a rim deformation), got "
                          f"{type(deformation).__name__}")

    def kappa(phi_rad):
        phi = _finite_array("phi_rad", phi_rad, "rad")
        w, u = deformation.evaluate(np.atleast_1d(phi), order=2)
        return displaced_curvature(np.atleast_1d(phi), r_m, w[0], w[1], w[2], u[0], u[1], u[2])

    return kappa


# --------------------------------------------------------------------------- assembly stress


def stress_influence_factor(root_thickness_mm, fillet_radius_mm, rim_thickness_mm):
    """Seed 001's stress influence factor (dimensionless), FE-fitted:

        K_σ = 0.344 exp(1.243 s_f/δ) + 5.833 (r1/δ + 0.482 s_f/δ − 0.693)² + 0.886,

    s_f tooth root thickness, r1 dedendum fillet radius, δ rim thickness (mm; arrays
    broadcast). In r1 it is a parabola with its minimum at r1 = 0.693 δ − 0.482 s_f
    (:func:`optimal_fillet_radius_mm`), rising again beyond it as fast as it fell. The seed
    gives no range of validity of the fit."""
    s_f = _positive("root_thickness_mm", root_thickness_mm, "mm")
    r1 = _non_negative("fillet_radius_mm", fillet_radius_mm, "mm")
    delta = _positive("rim_thickness_mm", rim_thickness_mm, "mm")
    x = s_f / delta
    return 0.344 * np.exp(1.243 * x) + 5.833 * (r1 / delta + 0.482 * x - 0.693) ** 2 + 0.886


def optimal_fillet_radius_mm(root_thickness_mm, rim_thickness_mm):
    """The r1 (mm) minimising K_σ — and σ_total, since the load stress does not depend on r1:
    r1* = 0.693 δ − 0.482 s_f (the vertex of K_σ's parabola in r1). May be ≤ 0: then the
    smallest fillet is best within the fit."""
    s_f = _positive("root_thickness_mm", root_thickness_mm, "mm")
    delta = _positive("rim_thickness_mm", rim_thickness_mm, "mm")
    return 0.693 * delta - 0.482 * s_f


def assembly_stress_mpa(curvature_mm_inv, neutral_radius_mm: float, rim_thickness_mm, youngs_modulus_mpa: float,
                        stress_factor=1.0):
    """Seed 001's assembly bending stress (MPa): σ = K_σ · (E δ/2) · (κ − 1/r_m), with the
    deformed curvature κ (1/mm, e.g. :func:`ellipse_curvature` or :func:`displaced_curvature`),
    r_m, δ (mm), E (MPa), K_σ = ``stress_factor`` (1 → the shell stress). Positive: tension in
    the outer (tooth-side) fibre, where the ring is bent more than its initial circle (κ > 1/r_m, the major axis)."""
    kappa = _finite_array("curvature_mm_inv", curvature_mm_inv, "1/mm")
    r_m = _positive("neutral_radius_mm", neutral_radius_mm, "mm")
    delta = _positive("rim_thickness_mm", rim_thickness_mm, "mm")
    e = _positive("youngs_modulus_mpa", youngs_modulus_mpa, "MPa")
    k = _positive("stress_factor", stress_factor, "(dimensionless)")
    return k * e * delta / 2.0 * (kappa - 1.0 / r_m)


# --------------------------------------------------------------------------- load stress


def load_moment_factor(root_thickness_mm, pitch_mm, rim_thickness_mm, equivalent_tooth_height_mm):
    """The fraction f of q_t (h + δ/2) that seed 001's M_yσ puts at the dedendum:

        f = [K_s (1 − K_s/2)(1 − δ³/h_p³) − 0.5] / [K_s (1 − δ³/h_p³) − 1],
        K_s = s_f / p,  h_p = δ + h0.

    Dimensionless; 0 ≤ f ≤ 1/2 for 0 < K_s < 1 (f = 1/2 at K_s → 0 or 1, or h0 → 0). The seed
    prints the result of its equilibrium/compatibility argument without the derivation.
    Raises :class:`StressError` unless 0 < s_f < p."""
    s_f = _positive("root_thickness_mm", root_thickness_mm, "mm")
    p = _positive("pitch_mm", pitch_mm, "mm")
    delta = _positive("rim_thickness_mm", rim_thickness_mm, "mm")
    h0 = _positive("equivalent_tooth_height_mm", equivalent_tooth_height_mm, "mm")
    k_s = np.asarray(s_f / p)
    if np.any(k_s >= 1.0):
        raise StressError(f"root_thickness_mm must be in (0, pitch_mm) mm (K_s = s_f/p < 1), got "
                          f"K_s = {k_s[k_s >= 1.0].flat[0]!r}")
    a = 1.0 - (delta / (delta + h0)) ** 3
    return (k_s * (1.0 - k_s / 2.0) * a - 0.5) / (k_s * a - 1.0)


def load_moment_nmm_per_mm(tangential_force_n, face_width_mm, tooth_height_mm, rim_thickness_mm, moment_factor):
    """Seed 001's root moment per unit face width (N·mm/mm): M_yσ = q_t (h + δ/2) f, with the
    line load q_t = F_t / b (N/mm) — the seed's σ = 6M/δ² is a stress only per unit width —
    F_t the tangential mesh force of the most loaded tooth (N), b the face width (mm), h the
    total tooth height, δ the rim thickness (mm), f :func:`load_moment_factor`."""
    f_t = _non_negative("tangential_force_n", tangential_force_n, "N")
    b = _positive("face_width_mm", face_width_mm, "mm")
    h = _positive("tooth_height_mm", tooth_height_mm, "mm")
    delta = _positive("rim_thickness_mm", rim_thickness_mm, "mm")
    f = _non_negative("moment_factor", moment_factor, "(dimensionless)")
    return f_t / b * (h + delta / 2.0) * f


def load_stress_mpa(moment_nmm_per_mm, rim_thickness_mm):
    """Seed 001's load bending stress at the dedendum (MPa): σ = 6 M_yσ / δ², M_yσ per unit
    face width (N·mm/mm), δ (mm): the section modulus δ²/6 of the rim per unit width."""
    m = _finite_array("moment_nmm_per_mm", moment_nmm_per_mm, "N·mm/mm")
    delta = _positive("rim_thickness_mm", rim_thickness_mm, "mm")
    return 6.0 * m / delta**2


def tangential_force_estimate_n(torque_nmm, pitch_radius_mm: float, teeth_in_mesh: float, peak_factor: float = 1.5):
    """A seed-style estimate of the tangential force (N) on the most loaded tooth, for running
    the model without a contact solution — NOT from seed 001, which only says q_t grows in
    proportion to the torque:

        F_t = k_peak · T / (r_p · n_mesh),

    the tangential force T/r_p (T in N·mm, r_p pitch radius in mm) shared by n_mesh teeth in
    both engagement zones, the most loaded one carrying k_peak times the mean. Linear in T.
    In the pipeline use the maximum tooth force of the contact solution instead (trap 6)."""
    torque = _non_negative("torque_nmm", torque_nmm, "N·mm")
    r_p = _positive("pitch_radius_mm", pitch_radius_mm, "mm")
    n = _positive("teeth_in_mesh", teeth_in_mesh, "(teeth)")
    k = _positive("peak_factor", peak_factor, "(dimensionless)")
    return k * torque / (r_p * n)


# --------------------------------------------------------------------------- one design


@dataclass(frozen=True, slots=True, eq=False)
class ToothRingStress:
    """Seed 001's tooth-ring stresses for one design (MPa unless named otherwise).

    ``phi_rad`` / ``curvature_mm_inv`` / ``assembly_stress_phi_mpa``: the polar angle θ over
    [0, π/2] on the deformed ellipse, its exact curvature and K_σ E δ/2 (κ − 1/r_m) — largest
    at θ = 0 (the major axis), where the scalars are evaluated."""

    phi_rad: np.ndarray
    curvature_mm_inv: np.ndarray
    assembly_stress_phi_mpa: np.ndarray
    major_semi_axis_mm: float
    minor_semi_axis_mm: float
    curvature_change_mm_inv: float  # ρ_a/ρ_b² − 1/r_m
    stress_influence_factor: float  # K_σ
    shell_assembly_stress_mpa: float  # E δ/2 (ρ_a/ρ_b² − 1/r_m), without K_σ
    assembly_stress_mpa: float  # K_σ × the shell stress
    line_load_n_per_mm: float  # q_t = F_t / b
    moment_factor: float  # f of M_yσ = q_t (h + δ/2) f
    load_moment_nmm_per_mm: float  # M_yσ
    load_stress_mpa: float  # 6 M_yσ / δ²
    inputs: dict
    time_s: float
    warnings: tuple[str, ...] = field(default=())

    def __post_init__(self):
        for name in ("phi_rad", "curvature_mm_inv", "assembly_stress_phi_mpa"):
            object.__setattr__(self, name, readonly(getattr(self, name)))
        object.__setattr__(self, "inputs", dict(self.inputs))

    @property
    def total_stress_mpa(self) -> float:
        """σ_total = σ_ass + σ_load (seed 001)."""
        return self.assembly_stress_mpa + self.load_stress_mpa

    def to_dict(self) -> dict:
        return json_ready({
            "inputs": self.inputs,
            "major_semi_axis_mm": self.major_semi_axis_mm,
            "minor_semi_axis_mm": self.minor_semi_axis_mm,
            "curvature_change_mm_inv": self.curvature_change_mm_inv,
            "stress_influence_factor": self.stress_influence_factor,
            "shell_assembly_stress_mpa": self.shell_assembly_stress_mpa,
            "assembly_stress_mpa": self.assembly_stress_mpa,
            "line_load_n_per_mm": self.line_load_n_per_mm,
            "moment_factor": self.moment_factor,
            "load_moment_nmm_per_mm": self.load_moment_nmm_per_mm,
            "load_stress_mpa": self.load_stress_mpa,
            "total_stress_mpa": self.total_stress_mpa,
            "phi_deg": np.degrees(self.phi_rad),
            "curvature_mm_inv": self.curvature_mm_inv,
            "assembly_stress_phi_mpa": self.assembly_stress_phi_mpa,
            "time_s": self.time_s,
            "warnings": list(self.warnings),
        })


def _fillet_warnings(pitch: float, s_f: float, r1: float) -> list[str]:
    space = pitch - s_f
    if 2.0 * r1 > space:
        return [f"two dedendum fillets r1 = {r1:.4g} mm do not fit in the root space p − s_f = {space:.4g} mm: "
                "if s_f is the thickness on the root circle, this fillet cannot be cut (the SHF-25 tooth-ring study "
                "does not define where s_f is measured)"]
    return []


def tooth_ring_stress(*, neutral_radius_mm: float, rim_thickness_mm: float, deflection_mm: float,
                      root_thickness_mm: float, fillet_radius_mm: float, pitch_mm: float, tooth_height_mm: float,
                      equivalent_tooth_height_mm: float, face_width_mm: float, youngs_modulus_mpa: float,
                      tangential_force_n: float, minor_semi_axis_mm: float | None = None,
                      samples: int = 91, curvature=None) -> ToothRingStress:
    """Seed 001's tooth-ring stresses on the major axis (MPa).

    Inputs (mm, MPa, N): r_m ``neutral_radius_mm``; δ ``rim_thickness_mm``; w0
    ``deflection_mm`` (ρ_a = r_m + w0); s_f ``root_thickness_mm``; r1 ``fillet_radius_mm``;
    p ``pitch_mm`` (πm); h ``tooth_height_mm``; h0 ``equivalent_tooth_height_mm``; b
    ``face_width_mm``; E ``youngs_modulus_mpa``; F_t ``tangential_force_n`` (tangential
    force on the most loaded tooth, e.g. the contact solution's maximum tooth force
    × cos of its pressure angle, or :func:`tangential_force_estimate_n`); ρ_b
    ``minor_semi_axis_mm`` (None → :func:`equal_perimeter_minor_semi_axis`).

    σ_ass = K_σ E δ/2 (ρ_a/ρ_b² − 1/r_m); σ_load = 6 M_yσ/δ², M_yσ = (F_t/b)(h + δ/2) f;
    ``samples`` angles over [0, π/2] for the assembly-stress distribution. ``curvature``: the
    deformed section's own κ(φ) (a callable of φ, :func:`section_curvature`) in place of the
    equivalent ellipse's (None); φ is then the material angle, and ρ_a, ρ_b only describe the
    section."""
    t0 = time.perf_counter()
    r_m = _positive("neutral_radius_mm", neutral_radius_mm, "mm")
    delta = _positive("rim_thickness_mm", rim_thickness_mm, "mm")
    w0 = _positive("deflection_mm", deflection_mm, "mm")
    if w0 >= 0.25 * r_m:
        raise StressError(f"deflection_mm must be in (0, {0.25 * r_m:g}) mm (a quarter of neutral_radius_mm), "
                          f"got {w0!r}")
    if delta >= 0.5 * r_m:
        raise StressError(f"rim_thickness_mm must be in (0, {0.5 * r_m:g}) mm (half of neutral_radius_mm), "
                          f"got {delta!r}")
    s_f = _positive("root_thickness_mm", root_thickness_mm, "mm")
    r1 = _non_negative("fillet_radius_mm", fillet_radius_mm, "mm")
    p = _positive("pitch_mm", pitch_mm, "mm")
    h = _positive("tooth_height_mm", tooth_height_mm, "mm")
    h0 = _positive("equivalent_tooth_height_mm", equivalent_tooth_height_mm, "mm")
    b = _positive("face_width_mm", face_width_mm, "mm")
    e = _positive("youngs_modulus_mpa", youngs_modulus_mpa, "MPa")
    f_t = _non_negative("tangential_force_n", tangential_force_n, "N")
    n = _count("samples", samples, 2)
    a = r_m + w0
    if minor_semi_axis_mm is None:
        rho_b = equal_perimeter_minor_semi_axis(r_m, a)
    else:
        rho_b = _in_open("minor_semi_axis_mm", minor_semi_axis_mm, 0.5 * r_m, r_m, "mm")
    phi = np.linspace(0.0, 0.5 * math.pi, n)
    if curvature is None:
        kappa = ellipse_curvature(phi, a, rho_b)
    elif callable(curvature):
        kappa = _finite_array("curvature", curvature(phi), "1/mm")
        if kappa.shape != phi.shape:
            raise StressError(f"curvature must give one value per angle ({phi.size}), got shape {kappa.shape}")
    else:
        raise StressError(f"curvature must be None or a callable of phi_rad (1/mm), got {type(curvature).__name__}")
    k_sigma = float(stress_influence_factor(s_f, r1, delta))
    shell = float(assembly_stress_mpa(kappa[0], r_m, delta, e))
    factor = float(load_moment_factor(s_f, p, delta, h0))
    moment = float(load_moment_nmm_per_mm(f_t, b, h, delta, factor))
    inputs = {
        "neutral_radius_mm": r_m, "rim_thickness_mm": delta, "deflection_mm": w0, "root_thickness_mm": s_f,
        "fillet_radius_mm": r1, "pitch_mm": p, "tooth_height_mm": h, "equivalent_tooth_height_mm": h0,
        "face_width_mm": b, "youngs_modulus_mpa": e, "tangential_force_n": f_t,
        "minor_semi_axis_mm": minor_semi_axis_mm,
        "curvature": "the equivalent ellipse's" if curvature is None else "the deformed section's own",
    }
    return ToothRingStress(
        phi_rad=phi, curvature_mm_inv=kappa,
        assembly_stress_phi_mpa=assembly_stress_mpa(kappa, r_m, delta, e, k_sigma),
        major_semi_axis_mm=a, minor_semi_axis_mm=rho_b, curvature_change_mm_inv=float(kappa[0] - 1.0 / r_m),
        stress_influence_factor=k_sigma, shell_assembly_stress_mpa=shell, assembly_stress_mpa=k_sigma * shell,
        line_load_n_per_mm=f_t / b, moment_factor=factor, load_moment_nmm_per_mm=moment,
        load_stress_mpa=float(load_stress_mpa(moment, delta)), inputs=inputs,
        time_s=time.perf_counter() - t0, warnings=tuple(_fillet_warnings(p, s_f, r1)),
    )


# --------------------------------------------------------------------------- standalone case


def root_thickness_from_slot_ratio(slot_width_ratio, module_mm: float, dedendum_mm: float, flank_angle_rad: float):
    """Tooth root thickness s_f (mm) of a straight-flanked (trapezoidal) tooth with slot width
    ratio ν = e/s on the pitch circle (e space, s tooth thickness, s + e = πm):

        s_f = πm / (1 + ν) + 2 h_f tan α,

    h_f dedendum (mm), α the flank's mean inclination to the tooth axis (rad). An ASSUMPTION —
    seed 001 says s_f "relates to" ν but gives no relation; a real double-arc tooth flares
    non-linearly toward the root."""
    nu = _positive("slot_width_ratio", slot_width_ratio, "(dimensionless)")
    m = _positive("module_mm", module_mm, "mm")
    h_f = _positive("dedendum_mm", dedendum_mm, "mm")
    alpha = _in_open("flank_angle_rad", flank_angle_rad, 0.0, 0.5 * math.pi, "rad")
    return math.pi * m / (1.0 + nu) + 2.0 * h_f * math.tan(alpha)


@dataclass(frozen=True, slots=True, eq=False)
class ToothRingCase:
    """The inputs of a standalone tooth-ring study, with the swept ratios' base values.

    δ = ``thickness_ratio`` · r_m, r1 = ``fillet_ratio`` · m, s_f from ``slot_ratio`` ν by
    :func:`root_thickness_from_slot_ratio`; F_t from the torque by
    :func:`tangential_force_estimate_n` with n_mesh = ``engaged_fraction`` · z1."""

    module_mm: float
    flexspline_teeth: int
    neutral_radius_mm: float
    deflection_mm: float
    face_width_mm: float
    youngs_modulus_mpa: float
    tooth_height_mm: float
    equivalent_tooth_height_mm: float
    dedendum_mm: float
    flank_angle_rad: float
    thickness_ratio: float
    fillet_ratio: float
    slot_ratio: float
    engaged_fraction: float
    peak_factor: float
    minor_semi_axis_mm: float | None = None
    notes: tuple[str, ...] = field(default=())

    @property
    def pitch_mm(self) -> float:
        return math.pi * self.module_mm

    @property
    def pitch_radius_mm(self) -> float:
        return 0.5 * self.module_mm * self.flexspline_teeth

    @property
    def effective_minor_semi_axis_mm(self) -> float:
        """ρ_b: ``minor_semi_axis_mm`` if given, else the equal-perimeter ellipse's."""
        if self.minor_semi_axis_mm is not None:
            return self.minor_semi_axis_mm
        return equal_perimeter_minor_semi_axis(self.neutral_radius_mm, self.neutral_radius_mm + self.deflection_mm)

    def tangential_force_n(self, torque_nm):
        return tangential_force_estimate_n(np.asarray(torque_nm, dtype=float) * 1e3, self.pitch_radius_mm,
                                           self.engaged_fraction * self.flexspline_teeth, self.peak_factor)

    def to_dict(self) -> dict:
        return json_ready({name: getattr(self, name) for name in self.__slots__})


def seed001_case() -> ToothRingCase:
    """Seed 001's SHF-25-80 tooth ring with the inputs it does not state filled in.

    From the seed's table: m = 0.375 mm, z1 = 160, r_m = 29.119 mm, w0 = ρ_a − r_m = 0.375 mm,
    ρ_b = 28.741 mm, b = 10 mm, E = 210 GPa. ESTIMATES (not in the seed): h = 2m = 0.75 mm,
    h0 = h/2, h_f = 0.45 mm (the project's DCTA tooth scaled to m = 0.375), α such that
    s_f/δ = 0.9 at the base δ/r_m = 3 % and ν = 1.8 (α = 22.1°, s_f = 0.786 mm); base
    r1/m = 0.65 (the seed's "general" recommendation); a quarter of the teeth in mesh
    (2 × 20) with the most loaded one 1.5 × the mean. These give σ_ass = 242.7 MPa at the
    base (seed: 242.7)."""
    r_m, m, h_f, nu, ratio = 29.119, 0.375, 0.45, 1.8, 0.03
    s_f = 0.9 * ratio * r_m
    alpha = math.atan((s_f - math.pi * m / (1.0 + nu)) / (2.0 * h_f))
    return ToothRingCase(
        module_mm=m, flexspline_teeth=160, neutral_radius_mm=r_m, deflection_mm=0.375, face_width_mm=10.0,
        youngs_modulus_mpa=210000.0, tooth_height_mm=2.0 * m, equivalent_tooth_height_mm=m, dedendum_mm=h_f,
        flank_angle_rad=alpha, thickness_ratio=ratio, fillet_ratio=0.65, slot_ratio=nu, engaged_fraction=0.25,
        peak_factor=1.5, minor_semi_axis_mm=28.741,
        notes=("m, z1, r_m, w0, rho_b, b, E: seed 001 table",
               "h = 2m, h0 = h/2, h_f = 0.45 mm: ESTIMATES",
               "flank angle: ESTIMATE, s_f/delta = 0.9 at delta/r_m = 3 %, nu = 1.8",
               "r1/m = 0.65, delta/r_m = 3 %, nu = 1.8: base values (seed's recommendations)",
               "F_t = 1.5 T / (r_p 0.25 z1): ESTIMATE, not in seed 001"),
    )


def case_inputs(case: ToothRingCase, torque_nm: float, *, thickness_ratio: float | None = None,
                fillet_ratio: float | None = None, slot_ratio: float | None = None,
                tangential_force_n: float | None = None) -> dict:
    """The keyword arguments of :func:`tooth_ring_stress` for ``case`` at ``torque_nm`` (N·m),
    with any base ratio overridden; F_t from the case's estimate unless given (N)."""
    ratio = case.thickness_ratio if thickness_ratio is None else thickness_ratio
    fillet = case.fillet_ratio if fillet_ratio is None else fillet_ratio
    nu = case.slot_ratio if slot_ratio is None else slot_ratio
    force = case.tangential_force_n(torque_nm) if tangential_force_n is None else tangential_force_n
    return {
        "neutral_radius_mm": case.neutral_radius_mm, "rim_thickness_mm": ratio * case.neutral_radius_mm,
        "deflection_mm": case.deflection_mm,
        "root_thickness_mm": root_thickness_from_slot_ratio(nu, case.module_mm, case.dedendum_mm, case.flank_angle_rad),
        "fillet_radius_mm": fillet * case.module_mm, "pitch_mm": case.pitch_mm, "tooth_height_mm": case.tooth_height_mm,
        "equivalent_tooth_height_mm": case.equivalent_tooth_height_mm, "face_width_mm": case.face_width_mm,
        "youngs_modulus_mpa": case.youngs_modulus_mpa, "tangential_force_n": float(force),
        "minor_semi_axis_mm": case.minor_semi_axis_mm,
    }


def case_stress_mpa(case: ToothRingCase, torque_nm, *, thickness_ratio, fillet_ratio, slot_ratio,
                    force_per_torque_n_per_nm: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(σ_ass, σ_load) in MPa on the major axis for ``case``; every argument broadcasts
    (torque N·m, δ/r_m, r1/m, ν). The same formulas as :func:`tooth_ring_stress`, vectorised
    for studies. ``force_per_torque_n_per_nm`` replaces the case's F_t estimate by F_t = c·T."""
    torque = _non_negative("torque_nm", torque_nm, "N·m")
    r_m, m = case.neutral_radius_mm, case.module_mm
    delta = _positive("thickness_ratio", thickness_ratio, "(δ/r_m)") * r_m
    r1 = _non_negative("fillet_ratio", fillet_ratio, "(r1/m)") * m
    nu = _positive("slot_ratio", slot_ratio, "(ν)")
    s_f = math.pi * m / (1.0 + nu) + 2.0 * case.dedendum_mm * math.tan(case.flank_angle_rad)
    a = r_m + case.deflection_mm
    kappa0 = a / case.effective_minor_semi_axis_mm**2
    sigma_ass = assembly_stress_mpa(kappa0, r_m, delta, case.youngs_modulus_mpa,
                                    stress_influence_factor(s_f, r1, delta))
    if force_per_torque_n_per_nm is None:
        force = case.tangential_force_n(torque)
    else:
        force = _non_negative("force_per_torque_n_per_nm", force_per_torque_n_per_nm, "N/(N·m)") * torque
    f = load_moment_factor(s_f, case.pitch_mm, delta, case.equivalent_tooth_height_mm)
    moment = load_moment_nmm_per_mm(force, case.face_width_mm, case.tooth_height_mm, delta, f)
    sigma_ass, sigma_load = np.broadcast_arrays(sigma_ass, load_stress_mpa(moment, delta))
    return np.array(sigma_ass), np.array(sigma_load)


# --------------------------------------------------------------------------- study


def _grid_minimum(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Minimum of y over the last axis sampled at x (uniform): the vertex of the parabola
    through the smallest sample and its neighbours. Returns (x*, y*, interior)."""
    i = np.argmin(y, axis=-1)
    n = x.size
    interior = (i > 0) & (i < n - 1)
    j = np.clip(i, 1, n - 2)
    y0 = np.take_along_axis(y, (j - 1)[..., None], -1)[..., 0]
    y1 = np.take_along_axis(y, j[..., None], -1)[..., 0]
    y2 = np.take_along_axis(y, (j + 1)[..., None], -1)[..., 0]
    h = x[1] - x[0]
    curv = y0 - 2.0 * y1 + y2
    with np.errstate(divide="ignore", invalid="ignore"):
        shift = np.where(interior & (curv > 0), 0.5 * (y0 - y2) / curv, 0.0)
    x_star = np.where(interior, x[j] + shift * h, x[i])
    y_star = np.where(interior, y1 - 0.125 * (y0 - y2) ** 2 / np.where(curv > 0, curv, np.inf),
                      np.take_along_axis(y, i[..., None], -1)[..., 0])
    return x_star, y_star, interior


@dataclass(frozen=True, slots=True, eq=False)
class ToothRingStudy:
    """Seed 001's parametric study for one case at several torques (k torques).

    * ``stress_vs_thickness_mpa`` (k, nδ): σ_total over ``thickness_ratios`` (δ/r_m) at the
      base r1/m and ν; ``optimal_thickness_ratio`` (k,) its minimum (``*_interior`` False:
      at the edge of the range, no minimum inside it).
    * ``stress_vs_fillet_mpa`` (k, nr): over ``fillet_ratios`` (r1/m) at the base δ and ν;
      ``optimal_fillet_ratio`` (k,). ``optimal_fillet_ratio_at_optimal_thickness`` (k,):
      r1*/m at each torque's own optimal δ.
    * ``stress_vs_slot_mpa`` (k, nν): over ``slot_ratios`` (ν), each at its optimal δ
      (``optimal_thickness_vs_slot`` (k, nν)), base r1/m; ``optimal_slot_ratio`` (k,).
    * ``optimal_thickness_table`` (k, 3): optimal δ/r_m at ν = ``table_slot_ratios``
      (seed 001's table)."""

    case: ToothRingCase
    torques_nm: np.ndarray
    thickness_ratios: np.ndarray
    stress_vs_thickness_mpa: np.ndarray
    assembly_vs_thickness_mpa: np.ndarray
    optimal_thickness_ratio: np.ndarray
    optimal_thickness_stress_mpa: np.ndarray
    optimal_thickness_interior: np.ndarray
    fillet_ratios: np.ndarray
    stress_vs_fillet_mpa: np.ndarray
    optimal_fillet_ratio: np.ndarray
    optimal_fillet_interior: np.ndarray
    optimal_fillet_ratio_at_optimal_thickness: np.ndarray
    slot_ratios: np.ndarray
    stress_vs_slot_mpa: np.ndarray
    optimal_thickness_vs_slot: np.ndarray
    optimal_slot_ratio: np.ndarray
    optimal_slot_interior: np.ndarray
    table_slot_ratios: np.ndarray
    optimal_thickness_table: np.ndarray
    time_s: float

    def __post_init__(self):
        for name in self.__slots__:
            value = getattr(self, name)
            if isinstance(value, np.ndarray):
                object.__setattr__(self, name, readonly(value, value.dtype))

    def to_dict(self) -> dict:
        out = {name: getattr(self, name) for name in self.__slots__ if name != "case"}
        out["case"] = self.case.to_dict()
        return json_ready(out)


def _range(name: str, values, unit: str) -> np.ndarray:
    arr = np.atleast_1d(_positive(name, values, unit)).astype(float)
    if arr.ndim != 1 or arr.size < 3 or np.any(np.diff(arr) <= 0):
        raise StressError(f"{name} must be at least 3 increasing values {unit}")
    if not np.allclose(np.diff(arr), arr[1] - arr[0], rtol=1e-9, atol=0.0):
        raise StressError(f"{name} must be uniformly spaced {unit}")
    return arr


def tooth_ring_study(case: ToothRingCase, torques_nm, *,
                     thickness_ratios=np.linspace(0.015, 0.06, 451),
                     fillet_ratios=np.linspace(0.2, 1.2, 201),
                     slot_ratios=np.linspace(1.0, 3.0, 81),
                     table_slot_ratios=(1.4, 1.8, 2.2)) -> ToothRingStudy:
    """σ_total of ``case`` against δ/r_m, r1/m and ν at each torque (N·m, ≥ 0; 0 = no load),
    and where it is smallest (grid minimum refined by a parabola through its neighbours:
    error ≪ the grid step). The ratio ranges must be uniform grids."""
    t0 = time.perf_counter()
    torques = np.atleast_1d(_non_negative("torques_nm", torques_nm, "N·m")).astype(float)
    x_d = _range("thickness_ratios", thickness_ratios, "(δ/r_m)")
    x_r = _range("fillet_ratios", fillet_ratios, "(r1/m)")
    x_n = _range("slot_ratios", slot_ratios, "(ν)")
    table = np.atleast_1d(_positive("table_slot_ratios", table_slot_ratios, "(ν)")).astype(float)
    tq = torques[:, None]

    ass, load = case_stress_mpa(case, tq, thickness_ratio=x_d[None, :], fillet_ratio=case.fillet_ratio,
                                slot_ratio=case.slot_ratio)
    d_opt, d_val, d_in = _grid_minimum(x_d, ass + load)

    s_r = np.add(*case_stress_mpa(case, tq, thickness_ratio=case.thickness_ratio, fillet_ratio=x_r[None, :],
                                  slot_ratio=case.slot_ratio))
    r_opt, _, r_in = _grid_minimum(x_r, s_r)
    s_f = root_thickness_from_slot_ratio(case.slot_ratio, case.module_mm, case.dedendum_mm, case.flank_angle_rad)
    r_at_opt = (0.693 * d_opt * case.neutral_radius_mm - 0.482 * s_f) / case.module_mm

    def optimum_over_thickness(nus: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        s = np.add(*case_stress_mpa(case, tq[:, :, None], thickness_ratio=x_d[None, None, :],
                                    fillet_ratio=case.fillet_ratio, slot_ratio=nus[None, :, None]))
        x_star, y_star, _ = _grid_minimum(x_d, s)
        return x_star, y_star

    d_vs_nu, s_vs_nu = optimum_over_thickness(x_n)
    n_opt, _, n_in = _grid_minimum(x_n, s_vs_nu)
    d_table, _ = optimum_over_thickness(table)
    return ToothRingStudy(
        case=case, torques_nm=torques, thickness_ratios=x_d, stress_vs_thickness_mpa=ass + load,
        assembly_vs_thickness_mpa=np.broadcast_to(ass, (torques.size, x_d.size)), optimal_thickness_ratio=d_opt,
        optimal_thickness_stress_mpa=d_val, optimal_thickness_interior=d_in, fillet_ratios=x_r,
        stress_vs_fillet_mpa=s_r, optimal_fillet_ratio=r_opt, optimal_fillet_interior=r_in,
        optimal_fillet_ratio_at_optimal_thickness=r_at_opt, slot_ratios=x_n, stress_vs_slot_mpa=s_vs_nu,
        optimal_thickness_vs_slot=d_vs_nu, optimal_slot_ratio=n_opt, optimal_slot_interior=n_in,
        table_slot_ratios=table, optimal_thickness_table=d_table, time_s=time.perf_counter() - t0,
    )


# --------------------------------------------------------------------------- seed 001 check


@dataclass(frozen=True, slots=True, eq=False)
class SeedComparison:
    """One row of the seed-001 comparison: a quantity, the seed's value and ours for the same
    inputs as far as the seed gives them, the unstated inputs we assumed, and why they differ."""

    quantity: str
    unit: str
    seed_value: float
    our_value: float
    assumed: str
    note: str

    def to_dict(self) -> dict:
        return json_ready({name: getattr(self, name) for name in self.__slots__})


def _optimal_thickness(case: ToothRingCase, torque_nm: float, slot_ratio: float, fillet_ratio: float,
                       force_per_torque: float | None) -> float:
    from scipy.optimize import minimize_scalar

    def total(x):
        return sum(case_stress_mpa(case, torque_nm, thickness_ratio=x, fillet_ratio=fillet_ratio,
                                   slot_ratio=slot_ratio, force_per_torque_n_per_nm=force_per_torque))

    grid = np.linspace(0.012, 0.08, 137)
    i = int(np.argmin(total(grid)))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    return float(minimize_scalar(lambda x: float(total(x)), bounds=(lo, hi), method="bounded",
                                 options={"xatol": 1e-7}).x)


def seed001_comparison(case: ToothRingCase | None = None) -> tuple[SeedComparison, ...]:
    """Seed 001's numbers beside the model's for ``case`` (default :func:`seed001_case`).

    Two load models are shown: the case's estimate (F_t = k_peak T/(r_p n_mesh)) and F_t
    calibrated so that σ_total at 67 N·m is the seed's 371.1 MPa. The last row is the ratio of
    load stresses MIT/RAT the seed's three numbers imply, against the ratio q_t ∝ T gives."""
    case = seed001_case() if case is None else case
    seed = SEED001_STRESSES_MPA
    rat, mit = SEED001_TORQUES_NM["RAT"], SEED001_TORQUES_NM["MIT"]
    base = {"thickness_ratio": case.thickness_ratio, "fillet_ratio": case.fillet_ratio, "slot_ratio": case.slot_ratio}
    mit_point = {"thickness_ratio": 0.03375, "fillet_ratio": 0.7, "slot_ratio": 1.8}
    ass_base, _ = case_stress_mpa(case, 0.0, **base)
    ass_mit, unit_load_mit = case_stress_mpa(case, mit, force_per_torque_n_per_nm=1.0, **mit_point)
    _, unit_load_base = case_stress_mpa(case, rat, force_per_torque_n_per_nm=1.0, **base)
    c_est = float(case.tangential_force_n(1.0))
    c_cal = float((seed["total_rated"] - ass_base) / unit_load_base)
    s_f = root_thickness_from_slot_ratio(case.slot_ratio, case.module_mm, case.dedendum_mm, case.flank_angle_rad)
    assumed = (f"delta/r_m = {100 * case.thickness_ratio:g} %, r1/m = {case.fillet_ratio:g}, nu = {case.slot_ratio:g}, "
               f"s_f = {s_f:.4f} mm, "
               f"h = {case.tooth_height_mm:g} mm, h0 = {case.equivalent_tooth_height_mm:g} mm")
    est = f"F_t = {c_est:.3f} N per N·m ({case.peak_factor:g} x mean over {case.engaged_fraction:g} z1 teeth)"
    cal = f"F_t = {c_cal:.3f} N per N·m (calibrated to 371.1 MPa at 67 N·m)"
    rows = [
        SeedComparison("minor semi-axis rho_b", "mm", SEED001_TABLE["minor_semi_axis_mm"],
                       equal_perimeter_minor_semi_axis(case.neutral_radius_mm,
                                                       case.neutral_radius_mm + case.deflection_mm),
                       "equal perimeter (inextensible neutral line)",
                       "the seed's rho_b is the equal-perimeter ellipse to its 3 printed decimals"),
        SeedComparison("assembly stress, base configuration", "MPa", seed["assembly_base"], float(ass_base), assumed,
                       "base delta, s_f, r1, nu are not stated; s_f/delta = 0.9 at delta/r_m = 3 % chosen to match"),
    ]
    for c, how in ((c_est, est), (c_cal, cal)):
        rated = float(sum(case_stress_mpa(case, rat, force_per_torque_n_per_nm=c, **base)))
        mit_total = float(sum(case_stress_mpa(case, mit, force_per_torque_n_per_nm=c, **mit_point)))
        rows.append(SeedComparison("total stress at RAT 67 N·m, base configuration", "MPa", seed["total_rated"], rated,
                                   f"{assumed}; {how}", "q_t is not stated; the load term scales with it"))
        rows.append(SeedComparison("total stress at MIT 304 N·m, delta/r_m = 3.375 %, r1/m = 0.7, nu = 1.8", "MPa",
                                   seed["total_mit_optimum"], mit_total, f"{assumed}; {how}",
                                   "with q_t proportional to T (the seed's own statement) 371.1 and 496.1 "
                                   "cannot both hold"))
    implied = (seed["total_mit_optimum"] - float(ass_mit)) / (seed["total_rated"] - seed["assembly_base"])
    linear = float(unit_load_mit / unit_load_base)
    rows.append(SeedComparison("load stress ratio MIT/RAT implied by 242.7, 371.1, 496.1", "-", implied, linear,
                               f"{assumed}; sigma_ass at the MIT point = {float(ass_mit):.1f} MPa from the same inputs",
                               "our value: the ratio for q_t proportional to T at the two geometries; the "
                               "seed's numbers imply a q_t that grows about half as fast as T (plausible "
                               "physically — more teeth "
                               "engage at higher torque — but not the seed's model)"))
    for torque in (rat, SEED001_TORQUES_NM["AVT"], SEED001_TORQUES_NM["STT"], mit):
        for nu, seed_opt in zip(SEED001_OPTIMAL_THICKNESS["slot_ratios"], SEED001_OPTIMAL_THICKNESS[torque]):
            ours = _optimal_thickness(case, torque, nu, case.fillet_ratio, c_est)
            rows.append(SeedComparison(f"optimal delta/r_m at {torque:g} N·m, nu = {nu:g}", "-", seed_opt, ours,
                                       f"{assumed}; {est}; s_f from nu by a trapezoidal tooth",
                                       "depends on q_t and s_f(nu), neither stated"))
    return tuple(rows)


@dataclass(frozen=True, slots=True, eq=False)
class TrendCheck:
    """A trend seed 001 claims, whether the model produces it, and the numbers that say so."""

    claim: str
    holds: bool
    evidence: str

    def to_dict(self) -> dict:
        return {"claim": self.claim, "holds": bool(self.holds), "evidence": self.evidence}


def _monotone(values: np.ndarray, sign: int) -> bool:
    return bool(np.all(sign * np.diff(values) > 0.0))


def seed001_trend_checks(case: ToothRingCase | None = None,
                         study: ToothRingStudy | None = None) -> tuple[TrendCheck, ...]:
    """Seed 001's claimed trends, each checked against the model for ``case`` (default
    :func:`seed001_case`) at its four torques. ``holds`` is computed, not asserted: a claim
    that does not follow from the model says so."""
    case = seed001_case() if case is None else case
    if study is None:
        study = tooth_ring_study(case, list(SEED001_TORQUES_NM.values()))
    x = study.thickness_ratios
    no_load = study.assembly_vs_thickness_mpa[0]
    second = np.diff(no_load, 2)
    loaded = study.torques_nm > 0.0
    d_opt, torques = study.optimal_thickness_ratio[loaded], study.torques_nm[loaded]
    m = case.module_mm
    r1_opt = lambda ratio, sf_over_delta: (0.693 - 0.482 * sf_over_delta) * ratio * case.neutral_radius_mm / m
    window = [r1_opt(r, 0.9) for r in (0.029, 0.030, 0.034, 0.0345)]
    s_nu = study.stress_vs_slot_mpa
    edge_sf = root_thickness_from_slot_ratio(case.slot_ratio, m, case.dedendum_mm, case.flank_angle_rad)
    checks = [
        TrendCheck("no load: the stress rises linearly with the thickness",
                   bool(np.all(np.diff(no_load) > 0) and np.max(np.abs(second)) < 1e-9 * np.max(no_load)),
                   "K_sigma depends on s_f/delta and r1/delta, so sigma_ass = K_sigma(delta) E delta/2 chi is not "
                   "linear; "
                   f"with s_f fixed by the tooth it has a minimum at delta/r_m = "
                   f"{100 * x[np.argmin(no_load)]:.2f} % ({no_load.min():.1f} MPa)"),
        TrendCheck("under load the stress against thickness has an interior minimum (U shape)",
                   bool(np.all(study.optimal_thickness_interior[loaded])),
                   "optimal delta/r_m " + ", ".join(f"{t:g} N·m: {100 * d:.2f} %" for t, d in zip(torques, d_opt))),
        TrendCheck("the optimal thickness rises with the torque", _monotone(d_opt, +1),
                   "optimal delta/r_m " + " < ".join(f"{100 * d:.2f} %" for d in d_opt)),
        TrendCheck("the optimal thickness lies between 2.9 % and 3.4 % for the operational loads",
                   bool(np.all((d_opt >= 0.0285) & (d_opt < 0.0345))),
                   f"{100 * d_opt.min():.2f}–{100 * d_opt.max():.2f} % at nu = {case.slot_ratio:g} with the case's "
                   "q_t estimate (2.9–3.4 % read with the seed's 0.05-point resolution; its own table spans "
                   "2.75–3.45 %); "
                   "the values scale with the unstated q_t and s_f"),
        TrendCheck("a larger slot width ratio nu gives a thinner optimal ring",
                   bool(np.all(np.diff(study.optimal_thickness_table, axis=1) < 0)),
                   "optimal delta/r_m at nu = " + "/".join(f"{v:g}" for v in study.table_slot_ratios) + ": "
                   + "; ".join("/".join(f"{100 * v:.2f}" for v in row) + " %"
                               for row in study.optimal_thickness_table)),
        TrendCheck("the optimal fillet radius is the same for every load",
                   bool(np.ptp(study.optimal_fillet_ratio) < 1e-6),
                   "at fixed delta the load stress does not depend on r1, so r1* = 0.693 delta − 0.482 s_f for "
                   f"every torque (r1*/m = {study.optimal_fillet_ratio[0]:.3f}); at each torque's own optimal delta "
                   "it moves: "
                   + ", ".join(f"{v:.2f}" for v in study.optimal_fillet_ratio_at_optimal_thickness)),
        TrendCheck("the optimal fillet radius lies in 0.6 m – 0.7 m (for s_f/delta ≈ 0.9)",
                   bool(0.6 <= window[1] and window[2] <= 0.7),
                   "r1*/m = (0.693 − 0.482 s_f/delta) delta/m: with s_f/delta = 0.9 it is "
                   f"{window[1]:.3f} at delta/r_m = 3 %, {window[2]:.3f} at 3.4 % ({window[0]:.3f} at 2.9 %, "
                   f"{window[3]:.3f} at 3.45 %) — inside 0.6–0.7 only "
                   "for delta/r_m ≈ 2.98–3.48 %, the seed's own thickness range; with s_f fixed by the tooth "
                   f"(s_f = {edge_sf:.3f} mm) r1*/m = {study.optimal_fillet_ratio[0]:.3f} at the base delta"),
        TrendCheck("beyond the optimal fillet radius the returns diminish (stress flat or slightly rising)", False,
                   "K_sigma is a parabola in r1: the stress rises beyond r1* exactly as fast as it fell before it"),
        TrendCheck("the stress against nu (at the optimal thickness) has a shallow interior minimum near nu = 2.0",
                   bool(np.all(study.optimal_slot_interior)),
                   "optimal nu " + ", ".join(
                       f"{t:g} N·m: {n:.2f}{'' if i else ' (edge of range)'}" for t, n, i in
                       zip(study.torques_nm, study.optimal_slot_ratio, study.optimal_slot_interior))
                   + f"; stress falls monotonically with nu over {study.slot_ratios[0]:g}–{study.slot_ratios[-1]:g}: "
                   + str(all(_monotone(row, -1) for row in s_nu))
                   + " (s_f from nu by a trapezoidal tooth; the model has no tooth-strength term that penalises "
                     "thin teeth)"),
        TrendCheck("the optimal nu decreases as the load increases",
                   bool(np.all(study.optimal_slot_interior) and _monotone(study.optimal_slot_ratio, -1)),
                   "no interior optimum in nu, so no shift to follow; the gain from a larger nu shrinks with torque: "
                   + ", ".join(f"{t:g} N·m: {row[0] - row[-1]:.1f} MPa" for t, row in zip(study.torques_nm, s_nu))),
    ]
    return tuple(checks)
