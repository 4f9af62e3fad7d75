"""The wave-generator bearing's outer race under the cup's bore: a thin ring on one row of balls.

The cup tier used to press the bore onto the wave-generator contour as a rigid band over the
whole bearing width (``press_cup(race=None)``, still the limit case). The outer race is a thin
ring of radial thickness t and axial width B carried by one row of balls at the bearing's
mid-plane z_c; :class:`BearingRace` is that ring, and :func:`~profilegen.rim.cup.contact.press_cup`
(``race=...``) solves the bore on the race and the race on the balls as one contact problem.

The race (R: its centroid radius r_bore − t/2; E, ν of the gear set; linear, small rotations)
-----------------------------------------------------------------------------------------
Each section has a radial displacement w(φ) at the ball row and a tilt β(φ) about the
circumferential axis (a rigid section): the race's outer surface, which the bore touches, moves
radially by w(φ) + β(φ)(z − z_c). Loads per unit length of circumference q(φ) (radial, N/mm)
and m(φ) (moment about the circumferential axis, N·mm/mm), harmonic n = 0, 2, 4, … (the two
symmetry planes):

* radial, in-plane ring: w_n = q_n R⁴ / (E I_b (n² − 1)²) for n ≥ 2 (the inextensible ring;
  I_b = B t³/12), w_0 = q_0 R² / (E A) (hoop, A = B t);
* tilt, out-of-plane ring: β_n = m_n / k_n. With the section's axial displacement free (the balls
  hold the race radially; a deep groove at zero contact angle holds it axially only weakly) the
  classical out-of-plane ring (Timoshenko & Goodier's curved bar: bending about the radial axis
  E I_z (β + n² W/R)/R, twist G J n (β + W/R)/R, W minimised out) gives
  ``tilt="ring"``: k_n = (n² − 1)² E I_z G J / ((E I_z n² + G J) R²) (n = 0: E I_z/R², the ring
  turned into a cone; n = 1: 0, the rigid tilt), I_z = t B³/12, J = B t³/3 (1 − 0.63 t/B);
  ``tilt="held"`` (axial displacement held): k_n = (E I_z + G J n²)/R², an upper bound;
  ``tilt="free"``: k_n = 10⁻⁸ × the ring's, the bound of a race free to tilt (as a 2 mm band
  free to tilt in an independent check);
* a point force F at φ_j (the total of its four symmetric copies, as the cup's collocation
  counts it) is the line load q_n = F cos nφ_j/(πR) (n ≥ 2), q_0 = F/(2πR); a moment likewise.

``prestress`` (default True): the race is a circular ring bent onto the balls, so its own
restoring force (the harmonics n ≥ 2 of the contour, E I_b (n² − 1)²/R⁴ w_n) acts on balls and
bore — it lifts off the balls where the ring would rather be outside the contour (about the
minor axis). The contour's mean (n = 0) is taken as the inextensible race's own (its second
order shortening, not a hoop strain). ``prestress=False``: a race machined to the contour shape,
stress-free on it: with a stiff race this is the rigid band (the limit test).

The balls: one row at z_c, unilateral (a ball pushes, never pulls), each Hertz in series
(δ = c_H Q^{2/3}, :meth:`~profilegen.contact.chain.BallBearing.hertz_coefficient`, both races),
smeared over the collocation angles (a collocation angle's force over its arc, N balls on the
circumference: Q = F·2π/(N·copies·Δφ)), linearised as the secant δ/Q and iterated with the contact.
``hertz_coefficient_mm=None``: rigid balls.

Left out (stated): the race's geometric nonlinearity (its ovalisation is linear here; the cup's
is not), the groove's cut in the section (a rectangle t × B), the ball-groove axial and tilt
stiffness, the inner race and the cam (rigid), the balls' discreteness (smeared), friction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial

import numpy as np

from ... import checks
from .geometry import CupError

__all__ = ["CUP_TIER_RACE", "CUP_TIER_RACES", "TILTS", "BearingRace", "cup_tier_race"]

TILTS = ("ring", "held", "free")
#: ``tilt="free"``: the tilt stiffness as this fraction of the ring's (0 would make the race's
#: compliance infinite, 1e-9 leaves round-off above the contact's 1 pm gap tolerance at 16 angles; 1e-8
#: leaves the moment of the bore about the ball row ~1e-5 of its force × B)
FREE_FRACTION = 1e-8

_number = partial(checks.number, error=CupError)


@dataclass(frozen=True, slots=True, eq=False)
class BearingRace:
    """The outer race (mm, MPa): ``thickness_mm`` t (radial), ``width_mm`` B (axial),
    ``ball_row_z_mm`` z_c (the ball row, z from the cup bottom's mid-plane), ``outer_radius_mm``
    (the race's outer surface = the bore radius), E, ν; ``tilt`` (:data:`TILTS`), ``prestress``;
    the balls: ``ball_count`` N and ``hertz_coefficient_mm`` c_H (mm/N^{2/3}; None: rigid balls).
    ``estimates``: which numbers are estimates. See the module docstring."""

    thickness_mm: float
    width_mm: float
    ball_row_z_mm: float
    outer_radius_mm: float
    youngs_modulus_mpa: float
    poisson_ratio: float
    ball_count: int = 23
    hertz_coefficient_mm: float | None = None
    tilt: str = "ring"
    prestress: bool = True
    estimates: tuple[str, ...] = ()

    def __post_init__(self):
        t = _number("thickness_mm", self.thickness_mm, "mm", 0.0)
        _number("width_mm", self.width_mm, "mm", 0.0)
        r = _number("outer_radius_mm", self.outer_radius_mm, "mm", 0.0)
        if not t < r:
            raise CupError(f"thickness_mm = {t!r} mm: must be below the race's outer radius {r:.6g} mm")
        _number("ball_row_z_mm", self.ball_row_z_mm, "mm")
        _number("youngs_modulus_mpa", self.youngs_modulus_mpa, "MPa", 0.0)
        _number("poisson_ratio", self.poisson_ratio, "", -1.0, 0.5)
        checks.whole("ball_count", self.ball_count, 3, error=CupError)
        if self.hertz_coefficient_mm is not None:
            _number("hertz_coefficient_mm", self.hertz_coefficient_mm, "mm/N^(2/3)", 0.0, low_open=False)
        if self.tilt not in TILTS:
            raise CupError(f"tilt = {self.tilt!r}: must be one of {', '.join(repr(a) for a in TILTS)}")
        if not isinstance(self.prestress, bool):
            raise CupError(f"prestress = {self.prestress!r}: must be True or False")

    @classmethod
    def from_gearset(cls, gearset, geometry=None, *, tilt: str = "ring", prestress: bool = True,
                     hertz: bool = True, thickness_mm: float | None = None) -> "BearingRace":
        """The race under the gear set's bore: width and ball row from the cup geometry's bearing
        (``[cup] bearing_width_mm``, ``bearing_center_mm``: default the face, the mid-face), t from
        ``thickness_mm`` else the contact model's ESTIMATE (2.5 % of the FS pitch diameter,
        :func:`~profilegen.geometry.wgbearing.default_race_thickness_mm`), the balls as the contact
        model's :class:`~profilegen.geometry.wgbearing.BallBearing` (ESTIMATES: 23 balls,
        D = 0.075 × the FS pitch diameter, conformity 0.52). ``hertz=False``: rigid balls."""
        from ...geometry.wgbearing import BallBearing, default_race_thickness_mm
        from .geometry import CupGeometry

        g = CupGeometry.from_gearset(gearset) if geometry is None else geometry
        estimates = []
        if thickness_mm is None:
            thickness_mm = default_race_thickness_mm(gearset.gear)
            estimates.append(f"thickness_mm = {thickness_mm:.4g} (2.5 % of the FS pitch diameter)")
        if g.bearing_width_mm is None or g.bearing_center_mm is None:  # CupGeometry.__post_init__ fills both
            raise CupError("geometry: its bearing_width_mm and bearing_center_mm are not filled in")
        bearing = None
        if hertz:  # the balls of the contact model's bearing (its race thickness: the estimate)
            bearing = BallBearing.from_gearset(gearset)
            estimates += [e for e in bearing.estimates if not e.startswith("race_thickness")]
        return cls(float(thickness_mm), float(g.bearing_width_mm), float(g.bearing_center_mm), float(g.bore_radius_mm),
                   float(g.youngs_modulus_mpa), float(g.poisson_ratio),
                   ball_count=23 if bearing is None else int(bearing.ball_count),
                   hertz_coefficient_mm=None if bearing is None else bearing.hertz_coefficient(), tilt=tilt,
                   prestress=prestress, estimates=tuple(estimates))

    # ------------------------------------------------------------------ section and ring
    @property
    def radius_mm(self) -> float:
        """R: the centroid radius (mm)."""
        return self.outer_radius_mm - 0.5 * self.thickness_mm

    @property
    def shear_modulus_mpa(self) -> float:
        return self.youngs_modulus_mpa / (2.0 * (1.0 + self.poisson_ratio))

    def section(self) -> dict:
        """A = B t, I_b = B t³/12 (in-plane bending), I_z = t B³/12 (about the radial axis),
        J = β B t³ with β = (1 − 0.63 t/B)/3 for t ≤ B (Roark's thin rectangle; the roles of
        t and B swapped when t > B)."""
        t, b = self.thickness_mm, self.width_mm
        short, long_ = min(t, b), max(t, b)
        return {"area_mm2": b * t, "i_bending_mm4": b * t ** 3 / 12.0, "i_tilt_mm4": t * b ** 3 / 12.0,
                "j_torsion_mm4": long_ * short ** 3 / 3.0 * (1.0 - 0.63 * short / long_)}

    def radial_stiffness(self, n: int) -> float:
        """k_w,n: line load per unit radial displacement of harmonic n (MPa = N/mm per mm)."""
        s, r, e = self.section(), self.radius_mm, self.youngs_modulus_mpa
        if n == 0:
            return e * s["area_mm2"] / r ** 2
        if n == 1:
            raise CupError("harmonic n = 1: the race's rigid translation (the two symmetry planes exclude it)")
        return e * s["i_bending_mm4"] * (n * n - 1) ** 2 / r ** 4

    def tilt_stiffness(self, n: int) -> float:
        """k_β,n: moment per unit length per radian of tilt of harmonic n (N·mm/mm)."""
        s, r = self.section(), self.radius_mm
        ei, gj = self.youngs_modulus_mpa * s["i_tilt_mm4"], self.shear_modulus_mpa * s["j_torsion_mm4"]
        if self.tilt == "held":
            return (ei + gj * n * n) / r ** 2
        ring = (n * n - 1) ** 2 * ei * gj / ((ei * n * n + gj) * r ** 2)
        return ring * (FREE_FRACTION if self.tilt == "free" else 1.0)

    def compliances(self, orders) -> tuple[np.ndarray, np.ndarray]:
        """(c_w, c_β) per harmonic of ``orders``: the harmonic-n displacement (rotation) per unit
        point force (moment) of a collocation group, c = 1/(π R k_n), n = 0: 1/(2π R k_0)."""
        r = self.radius_mm
        cw, cb = [], []
        for n in (int(k) for k in orders):
            scale = 1.0 / ((2.0 if n == 0 else 1.0) * math.pi * r)
            cw.append(scale / self.radial_stiffness(n))
            cb.append(scale / self.tilt_stiffness(n))
        return np.array(cw), np.array(cb)

    def ball_loads(self, force_n, phi_rad) -> np.ndarray:
        """The load Q (N) of one ball at each collocation angle from the angle's force (the total
        of its four symmetric copies; two at φ = 0 and π/2, where pairs coincide), the balls
        smeared over the angle's arc: Q = F·2π/(N·copies·Δφ)."""
        phi = np.asarray(phi_rad, dtype=float)
        spacing = float(phi[1] - phi[0])
        copies = np.full(phi.size, 4.0)
        copies[[0, -1]] = 2.0
        return np.asarray(force_n, dtype=float) * 2.0 * math.pi / (self.ball_count * copies * spacing)

    def to_dict(self) -> dict:
        return {"thickness_mm": self.thickness_mm, "width_mm": self.width_mm, "ball_row_z_mm": self.ball_row_z_mm,
                "outer_radius_mm": self.outer_radius_mm, "radius_mm": self.radius_mm, "ball_count": self.ball_count,
                "hertz_coefficient_mm_per_n2_3": self.hertz_coefficient_mm, "tilt": self.tilt,
                "prestress": self.prestress, "section": self.section(), "estimates": list(self.estimates)}

    def label(self) -> str:
        balls = "rigid balls" if self.hertz_coefficient_mm is None else "Hertz balls"
        tilt = {"ring": "tilt with its ring stiffness", "held": "tilt with its ring stiffness, held axially",
                "free": "free to tilt"}[self.tilt]
        return (f"outer race {self.thickness_mm:.3g} × {self.width_mm:.3g} mm on one ball row ({balls}, {tilt}"
                + (", bent onto the balls" if self.prestress else ", stress-free on the contour") + ")")


#: the race the rim stage's cup tier puts under the bore: ``"ring"`` (:meth:`BearingRace.from_gearset`
#: with its defaults: tilt with the ring's stiffness, bent onto Hertz balls — the physics, the
#: default), ``"held"`` (the tilt's upper bound), ``"free"`` (its lower bound) or ``"rigid"`` (no
#: race: the bore pressed onto the contour over the bearing width — a bound, not the part: it
#: holds the bore straight over the bearing and pushes the diaphragm end out by up to 119 µm).
#: docs/theory/cup.md, "The wave-generator bearing"; tests/benchmarks/bearing_tilt.py runs the
#: scenes with each.
CUP_TIER_RACE = "ring"
CUP_TIER_RACES = ("ring", "held", "free", "rigid")


def cup_tier_race(gearset, geometry=None, model: str | None = None) -> BearingRace | None:
    """The race for the cup tier: ``model`` (default :data:`CUP_TIER_RACE`) on ``gearset``."""
    model = CUP_TIER_RACE if model is None else model
    if model not in CUP_TIER_RACES:
        raise CupError(f"model = {model!r}: must be one of {', '.join(repr(a) for a in CUP_TIER_RACES)}")
    if model == "rigid":
        return None
    return BearingRace.from_gearset(gearset, geometry, tilt=model)
