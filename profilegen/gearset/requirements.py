"""The gear set's ``[requirements]`` table: what the design's verdict requires of the gear.

One :class:`RequirementField` per key (unit, range, default and where the default comes from),
:class:`Requirements` the validated values (None: not required). The reader
(:mod:`profilegen.gearset.reader`) checks the table; :attr:`profilegen.pipeline.design.Design.verdict`
and :func:`profilegen.stress.solve_stress` read it. ``"none"`` for any key means *not required*:
the check is not made and its absence does not make the verdict INCOMPLETE.

Sources of the defaults (each field says which it uses):

* **FKM guideline** "Analytical Strength Assessment of Components" (Forschungskuratorium
  Maschinenbau, 6th ed. 2012): the safety factor against the yield strength j_p = 1.5 (static
  strength, ductile steel, severe consequences of failure and a high probability of the load:
  its highest class), and the fatigue safety j_D = j_F·j_S = 1.5 (non-welded steel, no regular
  inspection, severe consequences: j_F = 1.5; design loads j_S = 1).
* **Harmonic Drive catalogues** (:mod:`profilegen.contact.catalogue`): lost motion < 1 arcmin at
  every ratio 30–160 and size 14–58 (``ACCURACY_LIMITS_ARCMIN``); the momentary maximum torque
  below the ratcheting torque (seed 001's SHF-25-80: 304 N·m against table 4's 680 N·m for the
  CSF-25-80; seed 002's CSG-25-100: 395 against 500 N·m).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

__all__ = ["NOT_REQUIRED", "REQUIREMENT_FIELDS", "REQUIREMENT_GROUPS", "RequirementField", "Requirements"]

#: the word that switches a requirement off in a gear-set file, a scene or ``--require``
NOT_REQUIRED = "none"


@dataclass(frozen=True, slots=True)
class RequirementField:
    """One key of ``[requirements]``: ``sense`` "min" (the computed value must be ≥ it) or "max"
    (≤ it); ``lo``/``hi`` the allowed range (``lo_open``: lo excluded); ``default`` None = not
    required; ``source`` where the default comes from (or why there is none)."""

    key: str
    unit: str
    sense: str
    default: float | None
    lo: float
    hi: float
    lo_open: bool
    meaning: str
    source: str


_FKM_YIELD = ("FKM guideline (6th ed. 2012), static strength of ductile steel: j_p = 1.5 against the yield strength "
              "(severe consequences, high probability of the load; the momentary torque is rarer, so this is on the "
              "safe side)")
_FKM_FATIGUE = ("FKM guideline (6th ed. 2012), fatigue of non-welded steel: j_D = j_F·j_S = 1.5 (j_F = 1.5: no "
                "regular inspection, severe consequences; j_S = 1)")
_SAFETY_RANGE: dict[str, Any] = dict(lo=1.0, hi=10.0, lo_open=False)

REQUIREMENT_FIELDS: tuple[RequirementField, ...] = (
    RequirementField("tooth_ring_yield_safety", "", "min", 1.5, **_SAFETY_RANGE,
                     meaning="tooth ring: σ_y / (σ_ass + σ_load) at the tooth root, at the momentary torque",
                     source=_FKM_YIELD),
    RequirementField("tooth_ring_fatigue_safety", "", "min", 1.5, **_SAFETY_RANGE,
                     meaning="tooth ring: Goodman safety at the rated torque", source=_FKM_FATIGUE),
    RequirementField("cup_bottom_yield_safety", "", "min", 1.5, **_SAFETY_RANGE,
                     meaning="cup bottom (diaphragm plate): σ_y / largest von Mises stress, at the momentary torque",
                     source=_FKM_YIELD),
    RequirementField("cup_bottom_fatigue_safety", "", "min", 1.5, **_SAFETY_RANGE,
                     meaning="cup bottom (diaphragm plate): Goodman safety at the rated torque", source=_FKM_FATIGUE),
    RequirementField("diaphragm_fatigue_safety", "", "min", 1.5, **_SAFETY_RANGE,
                     meaning="diaphragm at the boss corner: Goodman safety in shear at the rated torque",
                     source=_FKM_FATIGUE),
    RequirementField("ratcheting_margin", "", "min", 1.0, **_SAFETY_RANGE,
                     meaning="the ratcheting torque's conservative bound over the momentary torque (the peak torque "
                             "when the set gives no momentary torque)",
                     source="Harmonic Drive catalogues: the momentary maximum torque lies below the ratcheting torque "
                            "(an SHF-25-80: 304 N·m against 680 N·m; a CSG-25-100: 395 against 500 N·m; CSF catalogue table 4)"),
    RequirementField("max_backlash_mm", "mm", "max", None, 0.0, 1.0, True,
                     meaning="largest backlash (normal gap) the fitted CS flank leaves to the exact flank",
                     source="not required: the fit's backlash is a design choice, and the catalogues give lost motion, "
                            "not a backlash in mm"),
    RequirementField("min_clearance_mm", "mm", "min", None, 0.0, 0.5, False,
                     meaning="smallest clearance between the fitted CS and the FS tooth over the motion, beyond the "
                             "interference check the verdict always makes (no cut deeper than its 10 nm tolerance)",
                     source="not required: a one-sided fit touches the envelope by design; give a running clearance "
                            "here if the shop's tolerances need one"),
    RequirementField("min_k1_nm_per_rad", "N·m/rad", "min", None, 0.0, 1e12, True,
                     meaning="smallest torsional stiffness K1 of the whole gear (wave generator locked), from the "
                             "torsional curve",
                     source="not required: the stiffness an application needs is its own"),
    RequirementField("min_k1_to_catalogue", "", "min", None, 0.0, 10.0, True,
                     meaning="smallest K1 as a multiple of the catalogue's K1 for the size and ratio",
                     source="not required: the model's K1 is 1.05–1.29× the catalogue's on profilegen new sets of "
                            "sizes 17–58 today (1.26–1.54 at size 14), K2 and K3 1.24–1.75×: a model still stiffer "
                            "than the catalogue's gear, too far for a default"),
    RequirementField("max_lost_motion_arcmin", "arcmin", "max", 1.0, 0.0, 60.0, True,
                     meaning="largest lost motion of the whole gear (the torsional curve's, at ±3 % of the rated "
                             "torque)",
                     source="Harmonic Drive AG CHA engineering data (1018854, p. 50, tables 50.1/50.2): lost motion "
                            "< 1 arcmin at every ratio 30–160 (profilegen.contact.catalogue.ACCURACY_LIMITS_ARCMIN)"),
)

FIELDS_BY_KEY = {f.key: f for f in REQUIREMENT_FIELDS}

#: shorthand keys (``--require fatigue_safety=2``) that set every field of the group
REQUIREMENT_GROUPS = {
    "yield_safety": tuple(f.key for f in REQUIREMENT_FIELDS if f.key.endswith("_yield_safety")),
    "fatigue_safety": tuple(f.key for f in REQUIREMENT_FIELDS if f.key.endswith("_fatigue_safety")),
}


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class Requirements:
    """The validated ``[requirements]`` (see :data:`REQUIREMENT_FIELDS`); None: not required."""

    tooth_ring_yield_safety: float | None = 1.5
    tooth_ring_fatigue_safety: float | None = 1.5
    cup_bottom_yield_safety: float | None = 1.5
    cup_bottom_fatigue_safety: float | None = 1.5
    diaphragm_fatigue_safety: float | None = 1.5
    ratcheting_margin: float | None = 1.0
    max_backlash_mm: float | None = None
    min_clearance_mm: float | None = None
    min_k1_nm_per_rad: float | None = None
    min_k1_to_catalogue: float | None = None
    max_lost_motion_arcmin: float | None = 1.0

    def safety(self, check_name: str) -> float | None:
        """The required safety factor of a stress check by its name ("tooth ring fatigue" →
        ``tooth_ring_fatigue_safety``); None when not required."""
        return getattr(self, check_name.strip().replace(" ", "_") + "_safety")

    def to_dict(self) -> dict:
        """In the file schema: every key, ``"none"`` where not required."""
        return {f.name: NOT_REQUIRED if getattr(self, f.name) is None else getattr(self, f.name) for f in fields(self)}


REQUIREMENTS_KEYS = tuple(f.key for f in REQUIREMENT_FIELDS)
assert REQUIREMENTS_KEYS == tuple(f.name for f in fields(Requirements))  # one list, two spellings: kept equal
assert all(FIELDS_BY_KEY[f.name].default == f.default for f in fields(Requirements))
