"""The stress stage of a design: the three seed models fed by the design's own results.

``solve_stress(inputs)`` → :class:`StressResult` at the gear set's rated, peak and
momentary torques, from a :class:`StressInput` — what the stage reads of a design: the gear
set, the FS tooth, the deformation model and the loaded contact when it ran
(``StressInput.from_design(design)``; a Design is accepted and read the same way):

* **Tooth ring** (seed 001, :mod:`profilegen.stress.tooth_ring`): the deformed neutral line
  on the major axis from the design's deformation (ρ_a = r_m + ω(0), ρ_b = r_m + ω(π/2)),
  the root thickness s_f measured on the FS tooth at the height where the root fillet
  (``cup.root_fillet_radius_mm``) meets the flank, the face width ``cup.face_width_mm``,
  h = addendum + dedendum, h0 = h/2 (ESTIMATE, seed 001 gives none) and the tangential force
  on the most loaded tooth from the loaded contact: Σ over its points of F_k·r_k/|p_k| (the
  tangential part of each normal force at its radius). Without a contact solution (the
  ``sketch`` scene) the seed-style estimate is used and the result says so.
* **Cup bottom** (seed 002, :mod:`profilegen.stress.plate`): the edge displacement w(φ)
  from the design's radial harmonics ω(η) with the cup length ``cup.length_mm``, the
  consistent Kirchhoff plate between the boss ``cup.boss_radius_mm`` and r_m, thickness
  ``cup.bottom_thickness_mm``, plus the torque's shear T/(2π r² t).
* **Diaphragm** (seed 000, :mod:`profilegen.stress.diaphragm`): the shear amplitude at the
  boss corner from the deflection, its mean from the torque, Goodman.

Safety factors (the package's criteria, stated here once):

* yield, at the momentary torque: σ_y / σ (tooth ring: σ_ass + σ_load at the root; cup
  bottom: the largest von Mises stress);
* fatigue, at the rated torque, Goodman n = 1 / (σ_a/σ_-1 + σ_m/σ_u): the tooth root sees
  σ_ass + σ_load on the major axis in mesh and about −σ_ass on the minor axis (the curvature
  change reverses), so σ_a = σ_ass + σ_load/2, σ_m = σ_load/2; the cup bottom's bending
  wave turns with the wave generator (σ_a = the assembly von Mises maximum) on the torque's
  steady shear (σ_m = √3 τ_load at the boss); the diaphragm: seed 000's shear Goodman
  (τ_-1 and τ_u = 0.577 σ_u).
* A check passes when n ≥ its required safety: ``required_safety`` (one number for every check,
  or a mapping check name → number), by default the gear set's ``[requirements]``
  (``tooth_ring_yield_safety``, ... :mod:`profilegen.gearset.requirements`; 1.5 unless the set
  says otherwise). A check whose requirement is "none" (not required) is not made.

Fatigue needs the material's endurance limits and ultimate strength; ``fatigue=None``
(default) runs it when they are in the gear set and reports the checks as skipped
otherwise, ``fatigue=True`` without them raises :class:`~profilegen.errors.StressError`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..geometry.deformation import HarmonicDeformation
from ..errors import StressError
from ..gearset import GearSet
from ..results import json_ready
from ..geometry.series import DeformationFit
from ..geometry.teeth import ToothProfile
from .diaphragm import DiaphragmStress, diaphragm_stress, goodman_safety_factor as _goodman
from .plate import CupBottomStress, cup_bottom_stress, edge_displacement
from .tooth_ring import ToothRingStress, section_curvature, tangential_force_estimate_n, tooth_ring_stress

if TYPE_CHECKING:  # pragma: no cover
    from ..contact.analysis import ContactResult

__all__ = ["SafetyCheck", "StressInput", "StressResult", "solve_stress"]

#: Teeth in mesh per zone assumed by the force estimate when there is no contact solution
#: (a quarter of the FS teeth over both zones, the most loaded 1.5 × the mean: seed-style).
_ENGAGED_FRACTION = 0.25


def _typed(name: str, value, kind, what: str) -> None:
    if not isinstance(value, kind):
        raise StressError(f"{name}: must be {what}, got {type(value).__name__}")


@dataclass(frozen=True, slots=True, eq=False)
class StressInput:
    """What the stress stage reads of a design.

    ``gearset``: the :class:`~profilegen.gearset.GearSet` (gear, cup, material, torques);
    ``tooth``: the FS tooth (:class:`~profilegen.geometry.teeth.ToothProfile`; its root thickness and
    height); ``deformation``: the rim's deformation model (a Fourier
    :class:`~profilegen.geometry.series.DeformationFit` or ring theory's
    :class:`~profilegen.geometry.deformation.HarmonicDeformation`; ω on the axes and the radial
    harmonics); ``contact``: the :class:`~profilegen.contact.analysis.ContactResult` at the
    gear set's torques, or None (the tooth force is then estimated).
    """

    gearset: GearSet
    tooth: ToothProfile
    deformation: DeformationFit | HarmonicDeformation
    contact: ContactResult | None = None

    def __post_init__(self):
        _typed("gearset", self.gearset, GearSet, "a GearSet")
        _typed("tooth", self.tooth, ToothProfile, "a ToothProfile (the FS tooth)")
        _typed("deformation", self.deformation, (DeformationFit, HarmonicDeformation),
               "a DeformationFit or a HarmonicDeformation")
        if self.contact is not None:
            from ..contact.analysis import ContactResult

            _typed("contact", self.contact, ContactResult, "a ContactResult or None")

    @classmethod
    def from_design(cls, design, *, name: str = "design") -> "StressInput":
        """The stress inputs of a :class:`profilegen.pipeline.design.Design`; a StressInput is returned
        as it is. ``name``: the argument the error names."""
        if isinstance(design, cls):
            return design
        try:
            gearset, tooth, deformation, contact = design.gearset, design.tooth, design.deformation, design.contact
        except AttributeError:
            raise StressError(f"{name}: must be a StressInput or a profilegen Design, got "
                              f"{type(design).__name__}") from None
        return cls(gearset, tooth, deformation, contact)


@dataclass(frozen=True, slots=True, eq=False)
class SafetyCheck:
    """One safety factor: ``value`` = limit / stress (or Goodman's n); None when skipped."""

    name: str
    criterion: str
    torque_nm: float
    value: float | None
    required: float
    note: str = ""

    @property
    def passed(self) -> bool | None:
        return None if self.value is None else bool(self.value >= self.required)

    def to_dict(self) -> dict:
        return json_ready({"name": self.name, "criterion": self.criterion, "torque_nm": self.torque_nm,
                           "value": self.value, "required": self.required, "passed": self.passed,
                           "note": self.note})


@dataclass(frozen=True, slots=True, eq=False)
class StressResult:
    """Flexspline stresses at the gear set's torques (MPa, N·m) and the safety checks."""

    torques_nm: tuple[float, ...]
    tangential_force_n: tuple[float, ...]
    force_source: str  # "contact" or "estimate"
    tooth_ring: tuple[ToothRingStress, ...]
    cup_bottom: tuple[CupBottomStress, ...]
    diaphragm: tuple[DiaphragmStress, ...]
    checks: tuple[SafetyCheck, ...]
    root_thickness_mm: float
    time_s: float
    warnings: tuple[str, ...] = field(default=())

    @property
    def passed(self) -> bool:
        """Every check that ran passed."""
        return all(c.passed is not False for c in self.checks)

    @property
    def min_safety(self) -> float | None:
        """The lowest safety factor of the checks that ran (None: none ran); its check is
        :attr:`min_safety_check`."""
        worst = self.min_safety_check
        return None if worst is None or worst.value is None else float(worst.value)

    @property
    def min_safety_check(self) -> SafetyCheck | None:
        """The check with the lowest safety factor (the first of equals; None: none ran)."""
        ran = [(c.value, i) for i, c in enumerate(self.checks) if c.value is not None]
        return self.checks[min(ran)[1]] if ran else None

    def headline(self) -> dict:
        """The figures design.json carries (MPa at each torque; safety factors)."""
        return json_ready({
            "torques_nm": list(self.torques_nm),
            "tangential_force_n": list(self.tangential_force_n),
            "force_source": self.force_source,
            "tooth_ring_total_mpa": [r.total_stress_mpa for r in self.tooth_ring],
            "tooth_ring_assembly_mpa": self.tooth_ring[0].assembly_stress_mpa,
            "cup_bottom_von_mises_mpa": [c.max_von_mises_mpa for c in self.cup_bottom],
            "diaphragm_shear_amplitude_mpa": self.diaphragm[0].shear_amplitude_mpa,
            "diaphragm_mean_shear_mpa": [d.mean_shear_mpa for d in self.diaphragm],
            "safety": {c.name: c.value for c in self.checks},
            "passed": self.passed,
        })

    def to_dict(self) -> dict:
        return json_ready({
            **self.headline(),
            "root_thickness_mm": self.root_thickness_mm,
            "checks": [c.to_dict() for c in self.checks],
            "tooth_ring": [r.to_dict() for r in self.tooth_ring],
            "cup_bottom": [c.to_dict() for c in self.cup_bottom],
            "diaphragm": [d.to_dict() for d in self.diaphragm],
            "time_s": self.time_s,
            "warnings": list(self.warnings),
        })


def tangential_tooth_forces_n(contact) -> tuple[float, ...]:
    """The largest tangential tooth force of each load case of a ContactResult (N): per
    tooth Σ F_k r_k / |p_k| (r_k the lever arm of the normal, |p_k| the point's radius)."""
    pts = contact.points
    share = pts.lever_mm / np.linalg.norm(pts.fs_point_mm, axis=1)
    slot = np.searchsorted(pts.teeth, pts.tooth)
    return tuple(float(np.bincount(slot, weights=c.solution.force_n * share, minlength=pts.teeth.size).max())
                 for c in contact.cases)


def root_thickness_mm(tooth, fillet_radius_mm: float) -> float:
    """s_f: the FS tooth's thickness where its root fillet meets the flank, taken at the
    height r1 above the root circle (tooth frame: origin on the neutral line, y outward):
    2|x| of the right flank there."""
    y_cut = tooth.dedendum_y_mm + fillet_radius_mm
    t = np.linspace(0.0, tooth.length_mm, 2001)
    p = tooth.evaluate(t, side=1)[0]
    above = np.flatnonzero(p[:, 1] >= y_cut)
    if above.size == 0 or above[0] == 0:
        return float(2.0 * abs(p[0, 0]))
    k = above[0]
    u = (y_cut - p[k - 1, 1]) / (p[k, 1] - p[k - 1, 1])
    return float(2.0 * abs(p[k - 1, 0] + u * (p[k, 0] - p[k - 1, 0])))


def _limits(material, fatigue: bool | None) -> tuple[bool, list[str]]:
    missing = [k for k in material.missing_strength_limits if k in material.FATIGUE_LIMITS]
    if fatigue and missing:
        raise StressError(f"material.{missing[0]}: missing, and the fatigue checks need it (give "
                          f"{', '.join('material.' + m for m in missing)} in MPa, or pass fatigue=False)")
    if fatigue is None:
        fatigue = not missing
    notes = [f"fatigue checks skipped: the gear set gives no {', '.join('material.' + m for m in missing)}"] \
        if missing and not fatigue else []
    return bool(fatigue), notes


def unsupported(gearset) -> str:
    """Why the stress models cannot take this gear set ('' if they can): they are for two
    waves (ρ_a, ρ_b on the axes of an ellipse)."""
    waves = gearset.gear.waves
    return "" if waves == 2 else (f"gear.waves = {waves}: the tooth-ring (SHF-25 study), cup-bottom (short-cup "
                                  f"study) and diaphragm (CSF-40 study) models are for two waves (ρ_a, ρ_b on the axes of an "
                                  f"ellipse): they need gear.waves = 2, got {waves}")


CHECK_NAMES = ("tooth ring yield", "cup bottom yield", "tooth ring fatigue", "cup bottom fatigue", "diaphragm fatigue")


def _required_safety(required_safety, gearset) -> dict:
    """check name → the required safety factor (None: not required): ``required_safety`` one
    number for all, a mapping by check name, or None for the gear set's ``[requirements]``."""
    def number(name, value):
        if value is None:
            return None
        if isinstance(value, bool) or not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise StressError(f"{name} = {value!r}: must be a finite number > 0")
        return float(value)

    if required_safety is None:
        req = getattr(gearset, "requirements", None)  # a stand-in gear set without one: 1.0, as before
        return {n: 1.0 if req is None else req.safety(n) for n in CHECK_NAMES}
    if isinstance(required_safety, dict):
        unknown = sorted(set(required_safety) - set(CHECK_NAMES))
        if unknown:
            raise StressError(f"required_safety[{unknown[0]!r}]: no such check (checks: {', '.join(CHECK_NAMES)})")
        base = _required_safety(None, gearset)
        return {n: number(f"required_safety[{n!r}]", required_safety[n]) if n in required_safety else base[n]
                for n in CHECK_NAMES}
    value = number("required_safety", required_safety)
    return {n: value for n in CHECK_NAMES}


def solve_stress(inputs: StressInput, *, fatigue: bool | None = None,
                 required_safety: float | dict | None = None) -> StressResult:
    """The stresses of a design at its gear set's torques, and the safety checks (see the
    module docstring). ``inputs``: a :class:`StressInput`, or a Design (read by
    :meth:`StressInput.from_design`)."""
    t0 = time.perf_counter()
    inputs = StressInput.from_design(inputs, name="inputs")  # a StressInput passes as it is
    gs = inputs.gearset
    g, cup, mat = gs.gear, gs.cup, gs.material
    required = _required_safety(required_safety, gs)
    reason = unsupported(gs)
    if reason:
        raise StressError(f"stress: {reason}")
    fatigue, warnings = _limits(mat, fatigue)
    torques = tuple(float(t) for t in (gs.torque.rated_nm, gs.torque.peak_nm, gs.torque.momentary_nm) if t is not None)

    # deformation: ω on the axes and its harmonics
    r_m = g.neutral_radius_mm
    model = inputs.deformation
    omega = model.evaluate(np.array([0.0, 0.5 * math.pi]), order=0)[0][0]
    rho_a, rho_b = r_m + float(omega[0]), r_m + float(omega[1])
    radial = {0: float(model.mean_mm), **{int(k * model.waves): float(c) for k, c in
                                          enumerate(np.asarray(model.cos_mm), start=1)}}

    # tangential force on the most loaded tooth
    contact = inputs.contact
    if contact is not None and len(contact.cases) == len(torques):
        forces, source = tangential_tooth_forces_n(contact), "contact"
        warnings += [f"the tooth force at {c.torque_nm:g} N·m comes from a contact solution beyond what the searched "
                     f"points can carry ({c.beyond_capacity}): its tooth-ring load stress is not trustworthy"
                     for c in contact.cases if c.beyond_capacity is not None]
    else:
        forces = tuple(float(tangential_force_estimate_n(t * 1e3, g.pitch_radius_mm, _ENGAGED_FRACTION * g.flexspline_teeth))
                       for t in torques)
        source = "estimate"
        warnings.append("tooth-ring load stress uses the seed-style force estimate (1.5 × the mean over a quarter of "
                        "the teeth), not a contact solution: run the design or verify scene for the loaded contact")

    tooth = inputs.tooth
    s_f = root_thickness_mm(tooth, cup.root_fillet_radius_mm)
    h = tooth.addendum_y_mm - tooth.dedendum_y_mm
    ring = tuple(tooth_ring_stress(
        neutral_radius_mm=r_m, rim_thickness_mm=g.rim_thickness_mm, deflection_mm=rho_a - r_m,
        root_thickness_mm=s_f, fillet_radius_mm=cup.root_fillet_radius_mm, pitch_mm=math.pi * g.module_mm,
        tooth_height_mm=h, equivalent_tooth_height_mm=0.5 * h, face_width_mm=cup.face_width_mm,
        youngs_modulus_mpa=mat.youngs_modulus_mpa, tangential_force_n=f, minor_semi_axis_mm=rho_b,
        curvature=section_curvature(model, r_m))  # the design section's own κ, not the ellipse's
        for f in forces)

    edge = edge_displacement(radial, mean_radius_mm=r_m, length_mm=cup.length_mm)
    plate_kw: dict[str, Any] = dict(boss_radius_mm=cup.boss_radius_mm, thickness_mm=cup.bottom_thickness_mm,
                    youngs_modulus_mpa=mat.youngs_modulus_mpa, poisson_ratio=mat.poisson_ratio)
    assembly = cup_bottom_stress(edge, torque_nmm=0.0, **plate_kw)
    bottom = tuple(cup_bottom_stress(edge, torque_nmm=t * 1e3, **plate_kw) for t in torques)

    diaphragm = tuple(diaphragm_stress(
        cup_radius_mm=r_m, boss_radius_mm=cup.boss_radius_mm, diaphragm_thickness_mm=cup.bottom_thickness_mm,
        cup_length_mm=cup.length_mm, deflection_mm=rho_a - r_m, youngs_modulus_mpa=mat.youngs_modulus_mpa,
        poisson_ratio=mat.poisson_ratio, torque_nmm=t * 1e3, fatigue=fatigue,
        shear_endurance_limit_mpa=mat.shear_endurance_limit_mpa, ultimate_strength_mpa=mat.ultimate_strength_mpa)
        for t in torques)

    checks = []
    i_mom, i_rated = len(torques) - 1, 0
    y = mat.yield_strength_mpa
    for name, stress, what in (("tooth ring yield", ring[i_mom].total_stress_mpa, "σ_ass + σ_load at the tooth root"),
                               ("cup bottom yield", bottom[i_mom].max_von_mises_mpa, "largest von Mises stress")):
        checks.append(SafetyCheck(name, f"σ_y / σ ({what})", torques[i_mom], None if y is None else y / stress,
                                  required[name], "" if y is not None else "no material.yield_strength_mpa"))
    if fatigue:  # _limits: the material gives its endurance limits and ultimate strength
        assert mat.bending_endurance_limit_mpa is not None and mat.ultimate_strength_mpa is not None
        r = ring[i_rated]
        amp, mean = r.assembly_stress_mpa + 0.5 * r.load_stress_mpa, 0.5 * r.load_stress_mpa
        checks.append(SafetyCheck(
            "tooth ring fatigue", "Goodman, σ_a = σ_ass + σ_load/2, σ_m = σ_load/2", torques[i_rated],
            _goodman(amp, mean, mat.bending_endurance_limit_mpa, mat.ultimate_strength_mpa),
            required["tooth ring fatigue"]))
        tau_m = float(bottom[i_rated].tau_load_mpa[0])
        checks.append(SafetyCheck(
            "cup bottom fatigue", "Goodman, σ_a = assembly von Mises max, σ_m = √3 τ_load at the boss",
            torques[i_rated], _goodman(assembly.max_von_mises_mpa, math.sqrt(3.0) * tau_m,
                                       mat.bending_endurance_limit_mpa, mat.ultimate_strength_mpa),
            required["cup bottom fatigue"]))
        checks.append(SafetyCheck(
            "diaphragm fatigue", "Goodman in shear (seed 000), τ_u = 0.577 σ_u", torques[i_rated],
            diaphragm[i_rated].safety_factor, required["diaphragm fatigue"]))
    else:
        for name in ("tooth ring fatigue", "cup bottom fatigue", "diaphragm fatigue"):
            checks.append(SafetyCheck(name, "Goodman", torques[i_rated], None, required[name], "skipped: no limits"))
    checks = [c for c in checks if c.required is not None]  # "none" in [requirements]: not required, not made
    for part in (*ring, *bottom, *diaphragm):
        warnings += [w for w in getattr(part, "warnings", ()) if w not in warnings]
    return StressResult(torques, tuple(forces), source, ring, bottom, diaphragm, tuple(checks), s_f,
                        time.perf_counter() - t0, tuple(warnings))
