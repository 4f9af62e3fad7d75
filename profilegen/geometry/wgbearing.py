"""The wave generator's flexible ball bearing: its balls (:class:`BallBearing`), the Hertz
contact at one ball (:func:`hertz_point_contact`) and the estimate of its outer race's
thickness (:func:`default_race_thickness_mm`).

Below the stages that use it: the contact model's compliance chain
(:mod:`profilegen.contact.chain`) and the 3D cup tier's bearing race
(:mod:`profilegen.rim.cup.bearing`) both read the bearing from here. Lengths in mm, forces in
N, moduli in MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial

import numpy as np

from .. import checks
from ..errors import ProfilegenError

__all__ = ["BallBearing", "ChainError", "DEFAULT_BALL_COUNT", "HertzContact", "default_race_thickness_mm",
           "hertz_point_contact"]

#: Balls of the wave generator's flexible bearing: 23 in seed 000's CSF40-100 (§5.2).
DEFAULT_BALL_COUNT = 23


class ChainError(ProfilegenError, ValueError):
    """Bad input to the compliance chain, the torsional curve or the wave generator's bearing; names the parameter, value, unit, range."""


_positive = partial(checks.positive, error=ChainError)
_number = partial(checks.number, error=ChainError)
_whole = partial(checks.whole, error=ChainError)


def default_race_thickness_mm(gear) -> float:
    """ESTIMATE of the wave-generator bearing's outer-race thickness: 2.5 % of the FS pitch
    diameter (2.5 mm for the default set). The gear set gives no bearing; a flexible
    (thin-section) bearing of a size-40 wave generator has a radial section of ~10–13 mm
    and balls of ~7–8 mm, which leaves ~2–3 mm of ring on either side of the ball row
    (less under the raceway groove, more at the shoulders)."""
    return 0.025 * 2.0 * float(gear.pitch_radius_mm)


@dataclass(frozen=True, slots=True, eq=False)
class HertzContact:
    """A Hertz point contact at one load: approach δ (mm), semi-axes a ≥ b (mm), peak pressure
    p0 (MPa), eccentricity e = √(1 − b²/a²)."""

    force_n: float
    approach_mm: float
    semi_major_mm: float
    semi_minor_mm: float
    max_pressure_mpa: float
    eccentricity: float


def hertz_point_contact(force_n: float, curvature_sum_1: float, curvature_sum_2: float,
                        contact_modulus_mpa: float) -> HertzContact:
    """Hertz contact of two bodies whose gap is h = A x² + B y² (exact, elliptical).

    ``curvature_sum_1``, ``curvature_sum_2`` (1/mm): the sums of the two bodies' principal
    curvatures in the two principal planes (1/R₁ + 1/R₁' and 1/R₂ + 1/R₂'; concave negative),
    both > 0; ``contact_modulus_mpa``: E* = 1/((1 − ν₁²)/E₁ + (1 − ν₂²)/E₂).

    Johnson, *Contact Mechanics* (1985) §4.2: with A = κ₁/2 ≤ B = κ₂/2, the ellipse's
    eccentricity e (a along x) solves B/A = ((a/b)² E(e) − K(e)) / (K(e) − E(e)); then
    a³ = 3P (K − E)/(2π E* e² A), b = a √(1 − e²), p0 = 3P/(2π a b), δ = p0 b K(e)/E*
    (K, E the complete elliptic integrals of modulus e). e = 0 is the sphere:
    a³ = 3PR/(4E*), δ = a²/R with 1/R = κ₁ = κ₂."""
    from scipy.optimize import brentq
    from scipy.special import ellipe, ellipk

    p = _positive("force_n", force_n, "N")
    k1 = _positive("curvature_sum_1", curvature_sum_1, "1/mm")
    k2 = _positive("curvature_sum_2", curvature_sum_2, "1/mm")
    e_star = _positive("contact_modulus_mpa", contact_modulus_mpa, "MPa")
    a_coef, b_coef = 0.5 * min(k1, k2), 0.5 * max(k1, k2)
    ratio = b_coef / a_coef
    if ratio - 1.0 < 1e-5:
        # nearly a sphere: K − E loses its digits as e → 0, so the sphere of the mean radius
        # R_e = (R'R'')^(1/2) (Johnson eq. 4.29), exact to O((B/A − 1)²) ~ 1e-10
        r = 0.5 / math.sqrt(a_coef * b_coef)
        a = (3.0 * p * r / (4.0 * e_star)) ** (1.0 / 3.0)
        return HertzContact(p, a * a / r, a, a, 3.0 * p / (2.0 * math.pi * a * a), 0.0)

    def excess(m):  # m = e²
        k, e = ellipk(m), ellipe(m)
        return (e / (1.0 - m) - k) / (k - e) - ratio

    # B/A − 1 ≈ 3m/4 for small m: the root lies above 1e-6 when B/A − 1 ≥ 1e-5
    m = brentq(excess, 1e-7, 1.0 - 1e-15, xtol=1e-16, rtol=1e-15, maxiter=200)
    k, e = ellipk(m), ellipe(m)
    a = (3.0 * p * (k - e) / (2.0 * math.pi * e_star * m * a_coef)) ** (1.0 / 3.0)
    b = a * math.sqrt(1.0 - m)
    p0 = 3.0 * p / (2.0 * math.pi * a * b)
    return HertzContact(p, p0 * b * k / e_star, a, b, p0, math.sqrt(m))


@dataclass(frozen=True, slots=True, eq=False)
class BallBearing:
    """The wave generator's flexible ball bearing, as far as its radial compliance at one ball
    needs it (mm, MPa): ``ball_count`` N, ``ball_diameter_mm`` D, ``pitch_diameter_mm`` d_m
    (ball centres), ``groove_conformity`` f (groove radius f·D, both races), steel balls
    and races of the gear set's modulus and Poisson ratio. ``estimates``: the fields that
    are estimates. Construct with :meth:`from_gearset`."""

    ball_count: int
    ball_diameter_mm: float
    pitch_diameter_mm: float
    groove_conformity: float
    youngs_modulus_mpa: float
    poisson_ratio: float
    estimates: tuple[str, ...] = ()

    def __post_init__(self):
        n = _whole("ball_count", self.ball_count, 3)
        d = _positive("ball_diameter_mm", self.ball_diameter_mm)
        dm = _positive("pitch_diameter_mm", self.pitch_diameter_mm)
        _number("groove_conformity", self.groove_conformity, "", 0.5, 1.0)
        _positive("youngs_modulus_mpa", self.youngs_modulus_mpa, "MPa")
        _number("poisson_ratio", self.poisson_ratio, "", -1.0, 0.5)
        if not d < dm:
            raise ChainError(f"ball_diameter_mm = {d!r} mm: must be smaller than the pitch diameter {dm:.6g} mm")
        # N balls of diameter D on the pitch circle: their chords must not overlap (a cage needs ~10 % more)
        gap_angle = 2.0 * math.pi / n
        chord = dm * math.sin(0.5 * gap_angle)
        if not d < 0.9 * chord:
            raise ChainError(f"ball_count = {n}, ball_diameter_mm = {d:.6g} mm: the balls do not fit on the "
                             f"{dm:.6g} mm pitch circle with a cage (need D < 0.9 × the chord {chord:.6g} mm)")

    @classmethod
    def from_gearset(cls, gearset, *, ball_count: int | None = None, ball_diameter_mm: float | None = None,
                     race_thickness_mm: float | None = None, groove_conformity: float | None = None) -> "BallBearing":
        """The bearing under the FS bore: the outer race's raceway at r_bore − t_race
        (``race_thickness_mm``: default the compliance model's :func:`default_race_thickness_mm`), ball centres D/2 inside it. Defaults, ESTIMATES:
        23 balls (the CSF-40 diaphragm study's CSF40-100), D = 0.075 × the FS pitch diameter (7.5 mm for 100 mm),
        f = 0.52 (a deep-groove ball bearing's usual conformity)."""
        g = gearset.gear
        estimates = []
        if ball_count is None:
            ball_count = DEFAULT_BALL_COUNT
            estimates.append(f"ball_count = {ball_count} (the CSF-40 diaphragm study's CSF40-100)")
        if ball_diameter_mm is None:
            ball_diameter_mm = 0.075 * 2.0 * float(g.pitch_radius_mm)
            estimates.append(f"ball_diameter_mm = {ball_diameter_mm:.4g} (0.075 × the FS pitch diameter)")
        if race_thickness_mm is None:
            race_thickness_mm = default_race_thickness_mm(g)
            estimates.append(f"race_thickness_mm = {race_thickness_mm:.4g} (2.5 % of the FS pitch diameter)")
        if groove_conformity is None:
            groove_conformity = 0.52
            estimates.append("groove_conformity = 0.52 (groove radius / ball diameter)")
        d = _positive("ball_diameter_mm", ball_diameter_mm)
        t = _positive("race_thickness_mm", race_thickness_mm, allow_zero=True)
        r_bore = float(g.neutral_radius_mm) - 0.5 * float(g.rim_thickness_mm)
        r_centre = r_bore - t - 0.5 * d
        if not r_centre > 0.5 * d:
            raise ChainError(f"ball_diameter_mm = {d:.6g} mm, race_thickness_mm = {t:.6g} mm: the bearing does not "
                             f"fit in the FS bore (radius {r_bore:.6g} mm)")
        m = gearset.material
        return cls(int(ball_count), d, 2.0 * r_centre, float(groove_conformity), float(m.youngs_modulus_mpa),
                   float(m.poisson_ratio), tuple(estimates))

    @property
    def contact_modulus_mpa(self) -> float:
        """E* = E / (2 (1 − ν²)) for two bodies of the same steel."""
        return self.youngs_modulus_mpa / (2.0 * (1.0 - self.poisson_ratio ** 2))

    def curvature_sums(self) -> dict[str, tuple[float, float]]:
        """(rolling-plane, transverse) curvature sums (1/mm) of the outer and inner contact
        (ball 2/D each way; outer race −2/(d_m + D) and −1/(fD), inner +2/(d_m − D) and −1/(fD))."""
        d, dm, f = self.ball_diameter_mm, self.pitch_diameter_mm, self.groove_conformity
        groove = 2.0 / d - 1.0 / (f * d)
        return {"outer": (2.0 / d - 2.0 / (dm + d), groove), "inner": (2.0 / d + 2.0 / (dm - d), groove)}

    def hertz_coefficient(self) -> float:
        """c_H in δ = c_H Q^{2/3} (mm/N^{2/3}): the radial approach of inner and outer race at one
        ball under its load Q (both contacts in series, along the same line)."""
        sums = self.curvature_sums()
        return sum(hertz_point_contact(1.0, *sums[k], self.contact_modulus_mpa).approach_mm for k in ("outer", "inner"))

    def approach_mm(self, force_n) -> np.ndarray:
        """Radial approach (mm) at loads ``force_n`` (N, ≥ 0)."""
        q = np.maximum(np.asarray(force_n, dtype=float), 0.0)
        return self.hertz_coefficient() * q ** (2.0 / 3.0)

    def secant_compliance_mm_per_n(self, force_n, *, floor_n: float = 1.0) -> np.ndarray:
        """δ(Q)/Q = c_H Q^{−1/3} (mm/N), Q held ≥ ``floor_n`` (the secant is infinite at no load)."""
        q = np.maximum(np.asarray(force_n, dtype=float), floor_n)
        return self.hertz_coefficient() * q ** (-1.0 / 3.0)

    def to_dict(self) -> dict:
        return {"ball_count": self.ball_count, "ball_diameter_mm": self.ball_diameter_mm,
                "pitch_diameter_mm": self.pitch_diameter_mm, "groove_conformity": self.groove_conformity,
                "hertz_coefficient_mm_per_n2_3": self.hertz_coefficient(), "estimates": list(self.estimates)}
