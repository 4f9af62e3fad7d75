"""How far each scene's design-sheet numbers may be from the next scene's.

The scenes run the same gear with less or more effort: ``sketch`` → ``design`` → ``verify``. For
every number of the design sheet (the CS tip and root diameters, the flank's R1 / line / R2 and
their centres, the fillet, the design section and FS taper, backlash, smallest clearance,
stiffness, largest tooth force, each safety factor, lost motion, ratcheting) a scene states its
distance to the next scene's value as an :class:`Estimate`:

* ``absolute``: ``|this − next| ≤ value`` in the number's unit;
* ``per_module``: ``|this − next| ≤ value × m`` (lengths of the tooth, which scale with the module
  at the catalogue deflection w0 = m);
* ``relative``: ``|this − next| ≤ value × |this|`` (stiffness, forces, safety factors);
* or :class:`NotEstimated` with the reason (the scene does not compute the number, or no bound
  was measured that a designer could trust).

Every bound is MEASURED, not assumed: :data:`ESTIMATES` is the largest difference observed over
the corpus of tests/corpus (24 ``profilegen new`` sets of sizes 14–58 and ratios 50–160, CSF and
SHF, and the 5 bundled sets) times :data:`SAFETY_FACTOR`, rounded up to two digits, at the commit
and date of :data:`MEASURED` (``python tests/benchmarks/scene_estimates.py``, which writes
tests/corpus/scene_table.json and prints this table). A point (a centre) differs by the distance
between the two scenes' points. The bundled presets only: a scene that differs from the bundled
one of its name (another chord, tier, contact) reports ``not estimated``.

:func:`sheet_numbers` reads the numbers from a design folder's JSON (``design.json``,
``profile_fit.json``, ``contact.json``, ``stress.json``), the same way for every scene;
:func:`report` is what ``design.json["scene_estimates"]`` holds; :func:`note` is the short text
the design sheet prints beside a number.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from typing import Any

__all__ = ["ESTIMATES", "MEASURED", "NEXT_SCENE", "NUMBERS", "SAFETY_FACTOR", "Estimate", "NotEstimated",
           "check_key", "difference", "estimate_for", "note", "numbers_of", "report", "sheet_numbers"]

#: The next (dearer) scene of each measured scene; verify is the dearest (nothing beyond it).
NEXT_SCENE = {"sketch": "design", "design": "verify"}
#: The measured largest difference is multiplied by this to give the estimate.
SAFETY_FACTOR = 1.5

TORQUES = ("rated", "peak", "momentary")

#: key → (label on the sheet, unit, kind of estimate). The centres and the line's ends are points (x, y) in
#: mm: two scenes' points differ by the distance between them.
NUMBERS: dict[str, tuple[str, str, str]] = {
    "cs_tip_diameter_mm": ("CS tip Ø", "mm", "per_module"),
    "cs_root_diameter_mm": ("CS root Ø", "mm", "per_module"),
    "fs_tip_diameter_mm": ("FS tip Ø", "mm", "per_module"),
    "fs_root_diameter_mm": ("FS root Ø", "mm", "per_module"),
    "r1_radius_mm": ("R1", "mm", "per_module"),
    "r1_centre_mm": ("R1 centre", "mm", "per_module"),
    "line_length_mm": ("line length", "mm", "per_module"),
    "line_start_mm": ("line start", "mm", "per_module"),
    "line_end_mm": ("line end", "mm", "per_module"),
    "r2_radius_mm": ("R2", "mm", "per_module"),
    "r2_centre_mm": ("R2 centre", "mm", "per_module"),
    "root_fillet_radius_mm": ("CS root fillet", "mm", "per_module"),
    "root_fillet_centre_mm": ("CS root fillet centre", "mm", "per_module"),
    "tip_round_radius_mm": ("CS tip round", "mm", "per_module"),
    "tip_round_centre_mm": ("CS tip round centre", "mm", "per_module"),
    "design_section_z_mm": ("CS design section z", "mm", "relative"),
    "fs_taper_um_per_mm": ("FS tooth taper", "µm/mm", "absolute"),
    "fs_crowning_um": ("FS crowning", "µm", "absolute"),
    "face_interference_mm": ("FS teeth across the face: largest interference", "mm", "absolute"),
    "face_backlash_mm": ("backlash across the face (largest)", "mm", "per_module"),
    "backlash_mm": ("backlash (largest)", "mm", "per_module"),
    "fit_deviation_mm": ("fit deviation (largest)", "mm", "per_module"),
    "min_clearance_mm": ("smallest clearance", "mm", "absolute"),
    **{f"k_whole_{t}_nm_per_rad": (f"stiffness at the {t} torque (whole gear)", "N·m/rad", "relative") for t in TORQUES},
    **{f"k_mesh_{t}_nm_per_rad": (f"stiffness at the {t} torque (mesh only)", "N·m/rad", "relative") for t in TORQUES},
    "k1_nm_per_rad": ("K1", "N·m/rad", "relative"),
    **{f"max_tooth_force_{t}_n": (f"largest tooth force at the {t} torque", "N", "relative") for t in TORQUES},
    "lost_motion_arcmin": ("lost motion", "arcmin", "relative"),
    "tooth_ring_yield_safety": ("tooth ring yield safety", "", "relative"),
    "cup_bottom_yield_safety": ("cup bottom yield safety", "", "relative"),
    "tooth_ring_fatigue_safety": ("tooth ring fatigue safety", "", "relative"),
    "cup_bottom_fatigue_safety": ("cup bottom fatigue safety", "", "relative"),
    "diaphragm_fatigue_safety": ("diaphragm fatigue safety", "", "relative"),
    "ratcheting_torque_nm": ("ratcheting torque (estimate)", "N·m", "relative"),
}
POINTS = frozenset(k for k in NUMBERS if k.endswith("_centre_mm") or k in ("line_start_mm", "line_end_mm"))


# ----------------------------------------------------------------------------------------- numbers

def _flank(fit: dict) -> dict:
    """R1 / line / R2 of the first CAD fit (the sheet's naming: tip first; one arc after a line is R2)."""
    fits = fit["branches"]["branches"] if fit.get("branches") else [fit["fits"][fit["method"]]]
    elements = fits[0]["chain"]["elements"]
    out, arcs = {}, []
    for el in elements:
        if el["type"] == "arc":
            arcs.append(el)
        else:
            out["line_length_mm"] = el["length_mm"]
            out["line_start_mm"] = list(el["start_mm"])
            out["line_end_mm"] = list(el["end_mm"])
    labels = ["r2"] if len(arcs) == 1 and elements[0]["type"] == "line" else ["r1", "r2"]
    for label, el in zip(labels, arcs):
        out[f"{label}_radius_mm"] = el["radius_mm"]
        out[f"{label}_centre_mm"] = list(el["centre_mm"])
    return out


def sheet_numbers(design: dict, fit: dict | None = None, contact: dict | None = None,
                  stress: dict | None = None) -> dict:
    """Every number of :data:`NUMBERS` from a design folder's JSON (``design.json``,
    ``profile_fit.json``, ``contact.json``, ``stress.json`` as dicts); None where the run did not
    compute it (no contact, no face stage, no ratcheting ...)."""
    out: dict = dict.fromkeys(NUMBERS)
    cs = design["circular_spline"]
    out["cs_tip_diameter_mm"] = 2.0 * cs["tip_radius_mm"]
    out["cs_root_diameter_mm"] = 2.0 * cs["root_radius_mm"]
    tooth = design["tooth"]
    out["fs_tip_diameter_mm"] = 2.0 * (tooth["neutral_radius_mm"] + tooth["addendum_y_mm"])
    out["fs_root_diameter_mm"] = 2.0 * (tooth["neutral_radius_mm"] + tooth["dedendum_y_mm"])
    prof = design.get("profile")
    if prof is not None:
        out["backlash_mm"] = prof["max_backlash_mm"]
        out["fit_deviation_mm"] = prof["max_error_mm"]
        out["min_clearance_mm"] = prof["min_clearance_mm"]
        for f in (prof.get("corners") or {}).get("fillets") or ():
            if f["centre_mm"][0] < 0:  # the right-hand ones; the left are their mirror images
                continue
            key = "root_fillet" if f["kind"] == "inside" else "tip_round"
            out[f"{key}_radius_mm"] = f["radius_mm"]
            out[f"{key}_centre_mm"] = list(f["centre_mm"])
    if fit is not None:
        out.update(_flank(fit))
    face = design.get("face")
    if face is not None:
        out["design_section_z_mm"] = face["design_section_z_mm"]
        mod = face.get("modification")
        out["fs_taper_um_per_mm"] = 0.0 if mod is None else mod["taper_mm_per_mm"] * 1e3
        out["fs_crowning_um"] = 0.0 if mod is None else mod["crowning_mm"] * 1e3
        src = face if mod is None else mod  # the FS teeth as they are made (the verdict's face check)
        out["face_interference_mm"] = src["max_interference_mm"]
        out["face_backlash_mm"] = src["max_backlash_mm"]
    c = design.get("contact")
    if c is not None:
        for t, k, f in zip(TORQUES, c["secant_stiffness_nm_per_rad"], c["max_tooth_force_n"]):
            out[f"k_mesh_{t}_nm_per_rad"] = k
            out[f"max_tooth_force_{t}_n"] = f
        tors = c.get("torsional")
        if tors is not None:
            out["k1_nm_per_rad"] = tors["k1_nm_per_rad"]
            out["lost_motion_arcmin"] = tors["lost_motion_arcmin"]
        out["ratcheting_torque_nm"] = c.get("ratcheting_torque_nm")
        curve = None if contact is None else contact.get("torsional")
        if curve is not None:  # the sheet's whole-gear secant T / (φ(T) − φ at first contact)
            first = curve["first_contact_arcmin"]["positive"]
            for t, torque in zip(TORQUES, c["torques_nm"]):
                hit = [i for i, x in enumerate(curve["torque_nm"]) if x == torque]
                if hit:
                    rot = (curve["rotation_arcmin"][hit[0]] - first) / (60.0 * 180.0 / math.pi)
                    out[f"k_whole_{t}_nm_per_rad"] = torque / rot
    s = design.get("stress")
    if s is not None:
        for name, value in (s.get("safety") or {}).items():
            key = name.replace(" ", "_") + "_safety"
            if key in out:
                out[key] = value
    return out


def check_key(kind: str, name: str) -> str | None:
    """The number of :data:`NUMBERS` a verdict check judges (by the check's kind and name), or None."""
    if kind == "safety":
        key = name.replace(" ", "_") + "_safety"
        return key if key in NUMBERS else None
    return {"lost motion": "lost_motion_arcmin", "face": "face_interference_mm", "backlash": "backlash_mm",
            "clearance": "min_clearance_mm"}.get(kind)


def numbers_of(design) -> dict:
    """:func:`sheet_numbers` of a :class:`~profilegen.pipeline.design.Design` (the dicts its files hold)."""
    curve = getattr(design, "torsional", None)
    return sheet_numbers(design.to_dict(), None if design.profile is None else design.profile.to_dict(),
                         None if curve is None else {"torsional": curve.to_dict()})


def difference(key: str, a, b) -> float | None:
    """|a − b| of one number (the distance for points); None when either is missing."""
    if a is None or b is None:
        return None
    if key in POINTS:
        return math.hypot(a[0] - b[0], a[1] - b[1])
    return abs(float(a) - float(b))


# ---------------------------------------------------------------------------------------- estimates

@dataclass(frozen=True, slots=True)
class Estimate:
    """``|this scene − next scene| ≤ bound`` for one number; ``kind``: absolute, per_module or
    relative (see the module docstring); ``observed``: the largest difference measured over the
    corpus in the same kind, ``value`` = :data:`SAFETY_FACTOR` × ``observed`` rounded up."""

    kind: str
    value: float
    observed: float

    def bound(self, number: float | None, module_mm: float) -> float | None:
        """The bound in the number's unit (None: a relative bound of a number not computed)."""
        if self.kind == "absolute":
            return self.value
        if self.kind == "per_module":
            return self.value * module_mm
        return None if number is None else self.value * abs(float(number))


@dataclass(frozen=True, slots=True)
class NotEstimated:
    """No bound is claimed for this number in this scene, and why."""

    reason: str


# --- the measurement: written by `python tests/benchmarks/scene_estimates.py table --write-module` ---
#: How the estimates were measured.
MEASURED: dict[str, Any] = {
    "corpus": "tests/corpus: 24 profilegen new sets (sizes 14-58, ratios 50-160, CSF/SHF) + 5 bundled sets",
    "sets": 29,
    "commit": "9991afdaff28bc177a9604c0d0dbe65abaf60b7b",
    "date": "2026-11-29",
    "command": "python tests/benchmarks/scene_estimates.py",
    "wall_s": 427,  # the runs, 2 processes
    "safety_factor": SAFETY_FACTOR,
}

#: scene → number key → Estimate(kind, value, largest observed) | NotEstimated(reason)
ESTIMATES: dict[str, dict[str, Estimate | NotEstimated]] = {
    "sketch": {
        "cs_tip_diameter_mm": Estimate("per_module", 0.58, 0.382401),
        "cs_root_diameter_mm": Estimate("per_module", 1.1, 0.669503),
        "fs_tip_diameter_mm": Estimate("per_module", 0.0, 0),
        "fs_root_diameter_mm": Estimate("per_module", 0.0, 0),
        "r1_radius_mm": Estimate("per_module", 0.72, 0.476789),
        "r1_centre_mm": Estimate("per_module", 0.81, 0.537806),
        "line_length_mm": Estimate("per_module", 0.24, 0.155343),
        "line_start_mm": Estimate("per_module", 0.35, 0.230701),
        "line_end_mm": Estimate("per_module", 0.42, 0.274027),
        "r2_radius_mm": Estimate("per_module", 0.72, 0.476099),
        "r2_centre_mm": Estimate("per_module", 0.81, 0.535138),
        "root_fillet_radius_mm": Estimate("per_module", 0.0, 0),
        "root_fillet_centre_mm": Estimate("per_module", 0.51, 0.334972),
        "tip_round_radius_mm": Estimate("per_module", 0.0, 0),
        "tip_round_centre_mm": Estimate("per_module", 0.32, 0.207992),
        "design_section_z_mm": NotEstimated('the sketch scene has no face stage (no model of the coning across the face): no design section, FS modification or check across the face'),
        "fs_taper_um_per_mm": NotEstimated('the sketch scene has no face stage (no model of the coning across the face): no design section, FS modification or check across the face'),
        "fs_crowning_um": NotEstimated('the sketch scene has no face stage (no model of the coning across the face): no design section, FS modification or check across the face'),
        "face_interference_mm": NotEstimated('the sketch scene has no face stage (no model of the coning across the face): no design section, FS modification or check across the face'),
        "face_backlash_mm": NotEstimated('the sketch scene has no face stage (no model of the coning across the face): no design section, FS modification or check across the face'),
        "backlash_mm": Estimate("per_module", 0.013, 0.00838045),
        "fit_deviation_mm": Estimate("per_module", 0.013, 0.00838045),
        "min_clearance_mm": Estimate("absolute", 9.8e-06, 6.47878e-06),
        "k_whole_rated_nm_per_rad": NotEstimated('the sketch scene has no whole-gear torsional curve at this torque'),
        "k_whole_peak_nm_per_rad": NotEstimated('the sketch scene has no whole-gear torsional curve at this torque'),
        "k_whole_momentary_nm_per_rad": NotEstimated('the sketch scene has no whole-gear torsional curve at this torque'),
        "k_mesh_rated_nm_per_rad": NotEstimated('the sketch scene has no loaded tooth contact: no stiffness, tooth force or lost motion'),
        "k_mesh_peak_nm_per_rad": NotEstimated('the sketch scene has no loaded tooth contact: no stiffness, tooth force or lost motion'),
        "k_mesh_momentary_nm_per_rad": NotEstimated('the sketch scene has no loaded tooth contact: no stiffness, tooth force or lost motion'),
        "k1_nm_per_rad": NotEstimated('the sketch scene has no loaded tooth contact: no stiffness, tooth force or lost motion'),
        "max_tooth_force_rated_n": NotEstimated('the sketch scene has no loaded tooth contact: no stiffness, tooth force or lost motion'),
        "max_tooth_force_peak_n": NotEstimated('the sketch scene has no loaded tooth contact: no stiffness, tooth force or lost motion'),
        "max_tooth_force_momentary_n": NotEstimated('the sketch scene has no loaded tooth contact: no stiffness, tooth force or lost motion'),
        "lost_motion_arcmin": NotEstimated('the sketch scene has no loaded tooth contact: no stiffness, tooth force or lost motion'),
        "tooth_ring_yield_safety": Estimate("relative", 0.34, 0.224248),
        "cup_bottom_yield_safety": Estimate("relative", 0.041, 0.0268164),
        "tooth_ring_fatigue_safety": Estimate("relative", 0.54, 0.354179),
        "cup_bottom_fatigue_safety": Estimate("relative", 0.16, 0.104784),
        "diaphragm_fatigue_safety": Estimate("relative", 0.099, 0.0657528),
        "ratcheting_torque_nm": NotEstimated('the sketch scene computes no ratcheting torque (estimate)'),
    },
    "design": {
        "cs_tip_diameter_mm": Estimate("per_module", 0.00029, 0.000190135),
        "cs_root_diameter_mm": Estimate("per_module", 0.00046, 0.000303047),
        "fs_tip_diameter_mm": Estimate("per_module", 0.0, 0),
        "fs_root_diameter_mm": Estimate("per_module", 0.0, 0),
        "r1_radius_mm": Estimate("per_module", 0.0057, 0.00376057),
        "r1_centre_mm": Estimate("per_module", 0.0057, 0.00377326),
        "line_length_mm": Estimate("per_module", 0.0024, 0.00159632),
        "line_start_mm": Estimate("per_module", 0.0015, 0.000991193),
        "line_end_mm": Estimate("per_module", 0.0017, 0.00109223),
        "r2_radius_mm": Estimate("per_module", 0.013, 0.00801354),
        "r2_centre_mm": Estimate("per_module", 0.013, 0.00807729),
        "root_fillet_radius_mm": Estimate("per_module", 0.0, 0),
        "root_fillet_centre_mm": Estimate("per_module", 0.0012, 0.000734156),
        "tip_round_radius_mm": Estimate("per_module", 0.0, 0),
        "tip_round_centre_mm": Estimate("per_module", 0.00041, 0.000272884),
        "design_section_z_mm": Estimate("relative", 0.0, 0),
        "fs_taper_um_per_mm": Estimate("absolute", 0.027, 0.017465),
        "fs_crowning_um": Estimate("absolute", 0.063, 0.0415469),
        "face_interference_mm": Estimate("absolute", 8.2e-06, 5.44721e-06),
        "face_backlash_mm": Estimate("per_module", 0.00039, 0.000258341),
        "backlash_mm": Estimate("per_module", 2.7e-05, 1.75041e-05),
        "fit_deviation_mm": Estimate("per_module", 2.7e-05, 1.75041e-05),
        "min_clearance_mm": Estimate("absolute", 3.1e-06, 2.01045e-06),
        "k_whole_rated_nm_per_rad": Estimate("relative", 0.011, 0.00726987),
        "k_whole_peak_nm_per_rad": Estimate("relative", 0.0055, 0.00364727),
        "k_whole_momentary_nm_per_rad": Estimate("relative", 0.0055, 0.00362817),
        "k_mesh_rated_nm_per_rad": Estimate("relative", 0.0011, 0.000677612),
        "k_mesh_peak_nm_per_rad": Estimate("relative", 0.00084, 0.00055502),
        "k_mesh_momentary_nm_per_rad": Estimate("relative", 0.00066, 0.000438204),
        "k1_nm_per_rad": Estimate("relative", 0.082, 0.0542706),
        "max_tooth_force_rated_n": Estimate("relative", 0.0038, 0.00248639),
        "max_tooth_force_peak_n": Estimate("relative", 0.0039, 0.00254469),
        "max_tooth_force_momentary_n": Estimate("relative", 0.0034, 0.00225181),
        "lost_motion_arcmin": Estimate("relative", 0.38, 0.251321),
        "tooth_ring_yield_safety": Estimate("relative", 0.0022, 0.00141804),
        "cup_bottom_yield_safety": Estimate("relative", 2.6e-05, 1.70053e-05),
        "tooth_ring_fatigue_safety": Estimate("relative", 0.0033, 0.00215159),
        "cup_bottom_fatigue_safety": Estimate("relative", 9.7e-05, 6.41399e-05),
        "diaphragm_fatigue_safety": Estimate("relative", 0.00018, 0.000114218),
        "ratcheting_torque_nm": NotEstimated("the design scene has no ratcheting estimate (the verify scene's)"),
    },
}
# --- end of the measurement ---


#: Scene fields that do not change a number (the words, the figures).
_NOT_NUMBERS = frozenset({"name", "description", "figures"})


@functools.lru_cache(maxsize=None)
def _bundled_scene(name: str) -> dict | None:
    """The bundled preset's table (profilegen/pipeline/scenes.toml), read here without profilegen.pipeline.scenes,
    which would tie the sheet (and so the pipeline's notebook view) to the gear-set reader."""
    import tomllib
    from pathlib import Path

    with open(Path(__file__).with_name("scenes.toml"), "rb") as f:
        return tomllib.load(f).get(name)


def _changed(scene, bundled: dict | None) -> list[str]:
    """The number-changing fields in which ``scene`` differs from the bundled preset's table (a
    key the table leaves out has the field's default; ``tier`` defaults to the name)."""
    if bundled is None:
        return ["(no bundled preset)"]
    out = []
    for f in dataclasses.fields(scene):
        if f.name in _NOT_NUMBERS:
            continue
        if f.name == "tier":
            if scene.rim_tier != (bundled.get("tier") or scene.name):
                out.append("tier")
            continue
        if getattr(scene, f.name) != bundled.get(f.name, f.default):
            out.append(f.name)
    return out


def estimate_for(scene, key: str) -> Estimate | NotEstimated:
    """The estimate of number ``key`` in ``scene`` (a :class:`~profilegen.pipeline.scenes.Scene` or a
    bundled scene's name)."""
    name = scene if isinstance(scene, str) else scene.name
    if name == "verify":
        return NotEstimated("the dearest scene: no next scene to bound (its stages' own error estimates are in 'stages')")
    if name not in NEXT_SCENE:
        return NotEstimated(f"scene {name!r} was not measured (only the bundled sketch and design scenes are)")
    changed = [] if isinstance(scene, str) else _changed(scene, _bundled_scene(name))
    if changed:
        return NotEstimated(f"scene {name!r} is not the bundled preset measured ({', '.join(changed)} changed)")
    return ESTIMATES[name].get(key) or NotEstimated(f"not measured at {MEASURED['commit'][:7] or 'any commit'}")


def _two_digits(x: float, floor: float = 1e-3) -> str:
    """x with two significant digits, no exponent (below ``floor``: '< floor')."""
    if x < floor:
        return f"< {floor:g}"
    decimals = min(3, max(0, 1 - math.floor(math.log10(x))))
    return f"{x:.{decimals}f}"


def note(scene, key: str, number, module_mm: float) -> str:
    """The sheet's short text beside a number, its distance to the next scene's: '±0.82 µm',
    '±12 %', '±0.5 µm/mm', 'not estimated' (the reason: :func:`estimate_for`), or '' in the
    dearest scene and for a relative bound of a number not computed."""
    est = estimate_for(scene, key)
    name = scene if isinstance(scene, str) else scene.name
    if isinstance(est, NotEstimated):
        return "" if name == "verify" else "not estimated"
    b = est.bound(number, module_mm)
    if b is None:
        return ""
    if est.value == 0.0:
        return "exact"  # the same in every scene of the corpus (an input, or the wire's radius)
    unit = NUMBERS[key][1]
    if est.kind == "relative":
        return f"±{_two_digits(100.0 * est.value, 0.01)}%"
    if unit == "mm":
        return f"±{_two_digits(b * 1e3)} µm"
    return f"±{_two_digits(b)} {unit}".rstrip()


def report(scene, numbers: dict, module_mm: float) -> dict:
    """``design.json["scene_estimates"]``: per number its value, the bound to the next scene in the
    number's unit (or 'not estimated: reason') and how the bound was measured."""
    name = scene if isinstance(scene, str) else scene.name
    rows = {}
    for key, (label, unit, _) in NUMBERS.items():
        value = numbers.get(key)
        est = estimate_for(scene, key)
        row = {"label": label, "unit": unit, "value": value}
        if isinstance(est, NotEstimated):
            row["estimate"] = f"not estimated: {est.reason}"
        else:
            row.update({"estimate": est.bound(value, module_mm), "kind": est.kind, "estimate_value": est.value,
                        "observed_max": est.observed})
        if value is None:
            row["value"] = "not computed"
        rows[key] = row
    return {"next_scene": NEXT_SCENE.get(name), "measured": dict(MEASURED), "numbers": rows}
