"""A gear set of catalogue proportions from what a designer starts with: a size, a ratio, a series
(``profilegen new --size 32 --ratio 100``, :func:`new_gearset`).

A catalogue gives a strain wave gear's size and ratio and its torques, not its module, rim or
cup. Every other number of the set is an ESTIMATE by a rule stated here and written beside the
value in the file, with its source:

* **pitch diameter** d = 2.54 mm × size (:data:`PITCH_DIAMETER_PER_SIZE_MM`): the size is the
  pitch diameter in tenths of an inch, the rule :func:`profilegen.contact.chain.catalogue_size`
  reads a set's size by (so a new set is compared with its own size's catalogue row). The
  bundled sets lie 2-6 % below it: seed 001's SHF-25-80, the one catalogue size whose module
  and tooth count the bundled sets hold from a publication (profiles/seed001_shf25.toml:
  m = 0.375 mm, z1 = 160), has d = 60.0 mm = 0.945 × 63.5 mm; the estimates seed000_csf40
  (100 mm for size 40) and csf32_100 (80 mm for size 32) are 0.984 ×. A rule 5.5 % smaller
  (2.4 mm × size) would read size 50's 120 mm as size 45. m = d / z1, rounded to 6 decimals.
* **teeth**: z1 = U·ratio, z2 = z1 + U with U = 2 waves (ratio = z1/(z2 − z1)).
* **rim** δ: δ/r_m = 3 % (:data:`RIM_PER_NEUTRAL_RADIUS`, seed 001's rule of thumb; the
  bundled sets 1.84 % (``default``, seed 004's ring) to 3.38 %) from ratio 80 up, 4 % at ratio
  50 and below (:func:`deflection_and_rim`, with the deflection below), r_m = d/2 − dedendum − δ/2
  solved for δ. The cup's wall and bottom are as thick (the reader's defaults). This thickness
  sets K2 and K3: at 2 % the model meets the catalogue's stiffness
  (docs/validation/catalogue-sizes.md, "The cup's thickness sets K2 and K3").
* **tooth**: the project's default DCTA tooth in units of the module (as every bundled set).
* **deflection and rim at low ratios** (:func:`deflection_and_rim`): ω* = 1 (w0 = m) from ratio 80
  up; ω* = 0.6 and δ/r_m = 4 % at ratio 50 and below; linear in the ratio between. The ring's
  bending strain at the major axis goes as δ·w0/r_m², and w0/r_m ≈ ω*/ratio: with ω* = 1 and 3 %
  every ratio-50 set failed the tooth ring's fatigue check in every scene (safety 0.77 at the rated
  torque, yield 1.22 at the momentary: design scene, sizes 14–58). Over ω* 0.5–0.7 × δ/r_m 3–5 %
  at size 32, ratio 50 (``tests/benchmarks/catalogue_sizes.py --scene design --sizes 32 --ratios
  50 --rim F --set wave_generator.deflection_coefficient=K``), 0.6 and 4 % is the only pair that
  passes (fatigue 1.57, yield 2.43; 3 % 1.33, 5 % 1.45 — the seed-001 stress factor K_σ falls as
  the ring thickens against the tooth, the shell stress rises); ω* = 0.5 leaves the default tooth
  no working flank. Ratios 60 and 70 on the ramp: fatigue 1.83 and 2.02. Below ratio 50 the rules
  give no sound set (size 32, ratio 30: fatigue 0.35, yield 0.62): :attr:`CatalogueSet.notes` and
  the file's header say so; between ratios 50 and 80 they say that the verify scene's ratcheting
  check takes the larger of the two ratios' bounds, which the ratio-60 sets of sizes 25–40 pass
  by 1–2 % only (``tests/benchmarks/catalogue_sizes.py --scene verify --sizes 25 32 40 --ratios 60
  70``: the bound 1.01–1.02× the momentary torque; ratio 70 1.63×). The catalogue's own
  ratio-50 gears are not published in this detail; its ratcheting torques, lower at ratio 50 than at
  80 (size 40: 1800 against 2800 N·m) though the teeth are larger, say that they engage less deep
  than ω* = 1 would.
* **wave generator**: ω* as above, an elliptical cam under a flexible ball bearing whose
  radial section is the contact model's own estimate: two races of 2.5 % d
  (:func:`profilegen.contact.compliance.default_race_thickness_mm`) and balls of 7.5 % d
  (:meth:`profilegen.contact.chain.BallBearing.from_gearset`), 12.5 % d in all.
* **EDM wire** (circular spline): the thickest wire of the usual diameters
  (:data:`WIRE_DIAMETERS_MM`) whose corner radius (wire radius + spark gap) is at most
  :data:`WIRE_CORNER_PER_MODULE` × m. The CS tooth space of the default DCTA tooth takes a root
  round of ~0.28 m (seed001_shf25's comment: at most 0.105 mm at m = 0.375 mm), so 0.2 m keeps
  a margin of ~30 %. Spark gap: 0.02 mm (the reader's default) for wires of 0.1 mm and more,
  0.01 mm for finer ones (ESTIMATE: fine wires cut at low discharge energy).
* **cup**: length 0.6 d, face width 0.2 d, bottom thickness = wall = δ, boss radius r_m/2,
  root fillet 0.6 m, the bearing as wide as the face and centred on it (the reader's defaults,
  docs/gearset.md, written out).
* **material**: the flexspline steel of the published FEA-deformation study (seed 004, the
  bundled ``default`` set): 35CrMnSiA, heat-treated and nitrided, E = 209 GPa, ν = 0.295 (the
  study's values); strength limits as ``profiles/default.toml`` estimates them (ESTIMATES: the
  usual minimum tensile/yield strength of 35CrMnSiA quenched and low-temperature tempered,
  1620/1280 MPa; σ_-1 ≈ 0.4 R_m, τ_-1 ≈ 0.58 σ_-1). Before: seed000_csf40's 4340-type steel
  (1100/950 MPa, σ_-1 = 495 MPa), which no source names for a flexspline (seed 000 names no
  material). With it the tooth ring's fatigue safety of every ratio-100 set was 1.35 < 1.5
  (design scene: σ_ass = 325 MPa, σ_load = 57 MPa at the rated torque); with 35CrMnSiA 1.78.
  With ω* = 1 and a 3 % rim ratio 50 failed with either (docs/validation/catalogue-sizes.md,
  "Strength"): hence the low-ratio rule above.
* **torques**: rated T = k·d²·b (:attr:`profilegen.gearset.GearSet.size_torque_nm`, the law the
  gear set's own torque check uses); peak and momentary ×167/67 and ×304/67 (seed 001's
  SHF-25-80 catalogue torques); CSG: ×1.3 (Harmonic Drive LLC's CSF & CSG catalogue, "Harmonic
  Drive Gear Revolution" beside the ordering information, p. 4 of the copy at
  slideshare.net/Electromate/harmonic-csf-csgcatalog: "The CSG achieved a 30% increase in torque
  capacity"). The catalogue rates ratio 30 lower than the
  higher ratios; this rule does not (give ``torque_rated_nm`` for it). Any torque can be given.

The sizes are those of the catalogue stiffness tables (:data:`SIZES`: the CHA tables 50.3/50.4
of :mod:`profilegen.contact.catalogue`, sizes 14–58); ratios are whole numbers from 30
(:data:`RATIO_RANGE`). SHF (hat type) sets are written as cups with the same toothed ring (the
hat's flange is not modelled here; the tooth ring and rim are what the stages use).

:func:`derived_quantities` gives what ``profilegen check`` prints for any set (the same
``GearSet`` properties ``Design.to_dict()["derived"]`` reads).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass

from ..errors import ProfilegenError

__all__ = ["CatalogueSet", "NewSetError", "PITCH_DIAMETER_PER_SIZE_MM", "RATIO_RANGE", "SERIES", "SIZES",
           "WIRE_DIAMETERS_MM", "deflection_and_rim", "derived_quantities", "new_gearset", "wire_for_module"]


class NewSetError(ProfilegenError, ValueError):
    """A bad argument to :func:`new_gearset`; names the parameter, its value and what is allowed."""


#: The sizes this generator writes: those of the catalogue stiffness tables (profilegen.contact.catalogue).
SIZES = (14, 17, 20, 25, 32, 40, 50, 58)
#: Series: CSF (standard cup), CSG (high-torque cup), SHF (hat type, written as a cup).
SERIES = ("csf", "csg", "shf")
#: Ratios: whole numbers in this range (the catalogue's 30 … 160, and room above).
RATIO_RANGE = (30, 320)
WAVES = 2
PITCH_DIAMETER_PER_SIZE_MM = 2.54
RIM_PER_NEUTRAL_RADIUS = 0.03
#: the deflection ω* and rim δ/r_m from FULL_RATIO up (1, RIM_PER_NEUTRAL_RADIUS) and at LOW_RATIO and
#: below (DEFLECTION_AT_LOW_RATIO, RIM_AT_LOW_RATIO), linear between (:func:`deflection_and_rim`)
FULL_RATIO, LOW_RATIO = 80, 50
DEFLECTION_AT_LOW_RATIO, RIM_AT_LOW_RATIO = 0.6, 0.04
WIRE_DIAMETERS_MM = (0.02, 0.03, 0.05, 0.07, 0.1, 0.15, 0.2, 0.25)
WIRE_CORNER_PER_MODULE = 0.2
CSG_TORQUE_FACTOR = 1.3
PEAK_PER_RATED = 167.0 / 67.0
MOMENTARY_PER_RATED = 304.0 / 67.0
BEARING_SECTION_PER_PITCH_DIAMETER = 0.025 + 0.075 + 0.025  # outer race + balls + inner race

# the default DCTA tooth (every bundled set), in units of the module
_TOOTH = (("pressure_angle_deg", 10.0), ("line_above_pitch_coefficient", 0.1),
          ("line_below_pitch_coefficient", 0.4), ("tip_arc_radius_coefficient", 1.3),
          ("root_arc_radius_coefficient", 1.4), ("addendum_coefficient", 0.8), ("dedendum_coefficient", 1.2))
_DEDENDUM = 1.2


@dataclass(frozen=True)
class CatalogueSet:
    """What :func:`new_gearset` makes: the TOML text and the validated set read back from it."""

    text: str
    gearset: object  # profilegen.gearset.GearSet
    #: what the rules could not do for this set (the CLI prints them; the file says them too)
    notes: tuple[str, ...] = ()

    def write(self, path) -> None:
        from pathlib import Path

        Path(path).write_text(self.text, encoding="utf-8")


def wire_for_module(module_mm: float) -> tuple[float, float]:
    """(wire radius, spark gap) in mm for a CS of module ``module_mm`` (the rule in the module
    docstring): the thickest wire of :data:`WIRE_DIAMETERS_MM` with radius + gap ≤ 0.2·m."""
    for diameter in sorted(WIRE_DIAMETERS_MM, reverse=True):
        gap = 0.02 if diameter >= 0.1 else 0.01
        if diameter / 2.0 + gap <= WIRE_CORNER_PER_MODULE * module_mm + 1e-12:
            return diameter / 2.0, gap
    raise NewSetError(f"module_mm = {module_mm:g} mm: no EDM wire of {', '.join(map(str, WIRE_DIAMETERS_MM))} mm "
                      f"fits its CS tooth space (corner radius ≤ {WIRE_CORNER_PER_MODULE:g}·m)")


def _whole(name: str, value, allowed: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value != int(value):
        raise NewSetError(f"{name} = {value!r}: must be a whole number ({allowed})")
    return int(value)


def _torque(name: str, value) -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise NewSetError(f"{name} = {value!r}: must be a number > 0 (N·m)")
    return float(value)


def _g(x: float, digits: int = 6) -> str:
    """A float as TOML writes it (always with a point)."""
    text = f"{round(float(x), digits):.{digits}f}".rstrip("0")
    return text + "0" if text.endswith(".") else text


def new_gearset(size: int, ratio: int, *, series: str = "csf", torque_rated_nm: float | None = None,
                torque_peak_nm: float | None = None, torque_momentary_nm: float | None = None,
                name: str | None = None) -> CatalogueSet:
    """A complete, commented gear-set TOML for a cup strain wave gear of catalogue proportions
    (the rules in the module docstring), and the :class:`~profilegen.gearset.GearSet` read back
    from it. ``size``: one of :data:`SIZES`; ``ratio``: a whole number in :data:`RATIO_RANGE`;
    ``series``: one of :data:`SERIES`; torques in N·m (default: the rating rule). Raises
    :class:`NewSetError` naming the bad argument."""
    from . import parse_gearset

    size = _whole("size", size, f"one of {', '.join(map(str, SIZES))}")
    if size not in SIZES:
        raise NewSetError(f"size = {size}: must be one of {', '.join(map(str, SIZES))} (the catalogue sizes modelled)")
    ratio = _whole("ratio", ratio, f"{RATIO_RANGE[0]} to {RATIO_RANGE[1]}")
    if not RATIO_RANGE[0] <= ratio <= RATIO_RANGE[1]:
        raise NewSetError(f"ratio = {ratio}: must be a whole number in [{RATIO_RANGE[0]}, {RATIO_RANGE[1]}]")
    if not isinstance(series, str) or series.lower() not in SERIES:
        raise NewSetError(f"series = {series!r}: must be one of {', '.join(SERIES)}")
    series = series.lower()
    rated, peak, momentary = (_torque("torque_rated_nm", torque_rated_nm), _torque("torque_peak_nm", torque_peak_nm),
                              _torque("torque_momentary_nm", torque_momentary_nm))
    p = _proportions(size, ratio, series, name or f"new_{series}{size}_{ratio}")
    # the rating rule needs the set's size torque (GearSet.size_torque_nm): read a draft first
    draft = parse_gearset(tomllib.loads(_set_text(p, 1.0, 1.0, 1.0, "")))
    rated, peak, momentary, rule = _torques(draft.size_torque_nm, series, rated, peak, momentary)
    text = _set_text(p, rated, peak, momentary, rule)
    try:
        gearset = parse_gearset(tomllib.loads(text))
    except ProfilegenError as exc:  # a given torque out of order (peak < rated, ...): the reader's own line
        raise NewSetError(str(exc)) from None
    return CatalogueSet(text=text, gearset=gearset, notes=_notes(ratio))


def _notes(ratio: int) -> tuple[str, ...]:
    """What the rules cannot promise for ``ratio`` (a line of the file and of the CLI each)."""
    if LOW_RATIO < ratio < FULL_RATIO:
        return (f"ratio {ratio} lies between the catalogue's ratios {LOW_RATIO} and {FULL_RATIO}, and no catalogue "
                "ratcheting torque lies between them: the verify scene's ratcheting check takes the larger of the "
                "two ratios' bounds on the model's overestimate, which can FAIL a set that passes every other "
                f"check (ratio 60, sizes 25-40: the bound 1.01-1.02x the momentary torque, a 1-2 % margin; ratio "
                "70: 1.63x)",)
    if ratio >= LOW_RATIO:
        return ()
    return (f"ratio {ratio} is below {LOW_RATIO}: with these rules the tooth ring fails its strength check "
            f"(size 32, ratio 30, design scene: fatigue safety 0.35, yield 0.62), and the default tooth has no "
            f"working flank below omega* = {DEFLECTION_AT_LOW_RATIO:g}: give the tooth, deflection and rim "
            "yourself",)


@dataclass(frozen=True)
class _Proportions:
    """A set's given size, ratio, series and name, and its proportions by the module docstring's
    rules (lengths in mm)."""

    size: int
    ratio: int
    series: str
    name: str
    z1: int  # flexspline teeth
    z2: int  # circular spline teeth
    m: float  # module
    d: float  # pitch diameter, m·z1
    rim: float  # rim thickness δ
    r_m: float  # neutral radius of the rim
    bearing: float  # the wave generator bearing's radial section
    wire_r: float  # EDM wire radius
    gap: float  # spark gap
    length: float  # cup length
    face: float  # face width
    boss: float  # boss radius
    fillet: float  # root fillet radius
    kappa: float  # deflection coefficient ω* (w0 = ω* m)
    rim_fraction: float  # δ/r_m


def deflection_and_rim(ratio: float) -> tuple[float, float]:
    """(ω*, δ/r_m) of a set ``new`` writes for ``ratio`` (the module docstring's rule): 1 and 3 %
    from :data:`FULL_RATIO` (80) up, 0.6 and 4 % at :data:`LOW_RATIO` (50) and below, linear
    between (ω* rounded to 4 decimals, as the file writes it)."""
    f = min(1.0, max(0.0, (FULL_RATIO - ratio) / (FULL_RATIO - LOW_RATIO)))
    kappa = round(1.0 + f * (DEFLECTION_AT_LOW_RATIO - 1.0), 4)
    return kappa, RIM_PER_NEUTRAL_RADIUS + f * (RIM_AT_LOW_RATIO - RIM_PER_NEUTRAL_RADIUS)


def _proportions(size: int, ratio: int, series: str, name: str) -> _Proportions:
    """The proportions of a set of ``size`` and ``ratio`` by the rules in the module docstring."""
    z1 = WAVES * ratio
    z2 = z1 + WAVES
    d = PITCH_DIAMETER_PER_SIZE_MM * size
    m = round(d / z1, 6)
    d = m * z1
    kappa, frac = deflection_and_rim(ratio)
    # δ = frac · r_m, r_m = d/2 - dedendum - δ/2
    rim = round(frac * (d / 2.0 - _DEDENDUM * m) / (1.0 + frac / 2.0), 4)
    r_m = d / 2.0 - _DEDENDUM * m - rim / 2.0
    bearing = math.ceil(BEARING_SECTION_PER_PITCH_DIAMETER * d * 100.0 + 1e-9) / 100.0  # up to 0.01 mm
    wire_r, gap = wire_for_module(m)
    length, face = round(0.6 * d, 3), round(0.2 * d, 3)
    boss = round(r_m / 2.0, 3)
    fillet = round(0.6 * m, 4)
    return _Proportions(size, ratio, series, name, z1, z2, m, d, rim, r_m, bearing, wire_r, gap, length, face, boss,
                        fillet, kappa, frac)


def _torques(size_torque_nm: float, series: str, rated: float | None, peak: float | None,
             momentary: float | None) -> tuple[float, float, float, str]:
    """The rated, peak and momentary torques (N·m): those given, the others by the rating rule from
    the set's size torque; and the comment lines that say which is which."""
    factor = CSG_TORQUE_FACTOR if series == "csg" else 1.0
    size_torque = size_torque_nm * factor
    lines = []
    if rated is None:
        rated = float(f"{size_torque:.3g}")
        lines.append(f"# ESTIMATE: rated = k d^2 b = {size_torque:.4g} N.m, 3 digits (GearSet.size_torque_nm, k fitted on the\n"
                     "# catalogue torques of seeds 000/001"
                     + (";\n# x1.3 for the CSG: the CSF & CSG catalogue's 'a 30 % increase in torque capacity'" if factor != 1 else "")
                     + ").\n# The catalogue rates ratio 30 lower; this rule does not.")
    else:
        lines.append("# given: rated torque (profilegen new --torque-rated)")
    if peak is None:
        peak = float(f"{max(rated * PEAK_PER_RATED, rated):.3g}")
        lines.append("# ESTIMATE: peak = rated x 167/67 (the SHF-25-80's catalogue torques, as the SHF-25 tooth-ring study quotes them), 3 digits.")
    if momentary is None:
        momentary = float(f"{max(rated * MOMENTARY_PER_RATED, peak):.3g}")
        lines.append("# ESTIMATE: momentary = rated x 304/67 (the SHF-25-80's catalogue torques, as the SHF-25 tooth-ring study quotes them), 3 digits.")
    return rated, peak, momentary, "\n".join(lines)


def _rim_rule(p: _Proportions) -> str:
    """The rim rule's words for ``p``'s ratio (a comment of the file)."""
    if p.ratio >= FULL_RATIO:
        return "3 % (seed 001's rule of thumb)"
    if p.ratio <= LOW_RATIO:
        return (f"{100 * RIM_AT_LOW_RATIO:g} % at ratio {LOW_RATIO} and below (with omega* = "
                f"{DEFLECTION_AT_LOW_RATIO:g}: the tooth\n# ring's strength)")
    return (f"{100 * p.rim_fraction:.3g} % (3 % from ratio {FULL_RATIO}, {100 * RIM_AT_LOW_RATIO:g} % at {LOW_RATIO}, "
            "linear between:\n# the tooth ring's strength)")


def _deflection_lines(p: _Proportions) -> str:
    """The [wave_generator] deflection line and its comment for ``p``'s ratio."""
    w0 = _g(round(p.kappa * p.m, 6))
    if p.kappa == 1.0:
        return f"deflection_coefficient = 1.0  # ESTIMATE: the standard omega* = 1 (w0 = m = {w0} mm)"
    return (f"# ESTIMATE: omega* = 1 from ratio {FULL_RATIO} up, {DEFLECTION_AT_LOW_RATIO:g} at ratio {LOW_RATIO} and below, "
            "linear between\n"
            f"# (profilegen.gearset.new.deflection_and_rim): with omega* = 1 and a 3 % rim every ratio-{LOW_RATIO} set failed\n"
            "# the tooth ring's fatigue check (safety 0.77); the ring's bending strain goes as delta w0 / r_m^2.\n"
            f"deflection_coefficient = {_g(p.kappa, 4)}  # w0 = {w0} mm")


def _note_lines(ratio: int) -> str:
    """:func:`_notes` as comment lines of the file's header ("" when there are none)."""
    import textwrap

    return "".join("\n" + "\n".join(textwrap.wrap("NOTE: " + n, 96, initial_indent="# ", subsequent_indent="# "))
                   for n in _notes(ratio))


def _set_text(p: _Proportions, t_rated: float, t_peak: float, t_mom: float, rule: str) -> str:
    """The gear-set TOML of proportions ``p`` and these torques, each number with the rule it comes
    from (``rule``: the torques' comment lines)."""
    size, ratio, series, name, z1, z2, m, d = p.size, p.ratio, p.series, p.name, p.z1, p.z2, p.m, p.d
    rim, r_m, bearing, wire_r, gap = p.rim, p.r_m, p.bearing, p.wire_r, p.gap
    length, face, boss, fillet = p.length, p.face, p.boss, p.fillet
    label = {"csf": "CSF", "csg": "CSG", "shf": "SHF"}[series]
    shf = ("\n# SHF is a hat-type flexspline: written here as a cup with the same toothed ring (the hat's\n"
           "# flange is not modelled; the rim, tooth ring and bearing are what the stages use).") if series == "shf" else ""
    return f"""# A {label}-{size}-{ratio} strain wave gear of catalogue proportions, written by
# `profilegen new --size {size} --ratio {ratio} --series {series}` (profilegen.gearset.new).
# Given: the size ({size}), the ratio ({ratio}) and the series. Every other number is an ESTIMATE
# by the rule named beside it (the rules and their sources: profilegen/gearset/new.py).{shf}{_note_lines(ratio)}

name = "{name}"
description = "{label}-{size}-{ratio} (catalogue proportions, estimated): m = {_g(m)} mm, z = {z1}/{z2}, d = {_g(d, 3)} mm"
source = "profilegen new: size {size}, ratio {ratio}, series {label}; geometry, material and torques are ESTIMATES by the rules of profilegen/gearset/new.py (see comments)"
scene = "design"

[gear]
# ratio {ratio} = z1/(z2 - z1) with U = 2 waves -> z1 = 2*{ratio} = {z1}, z2 = z1 + 2 = {z2}.
# ESTIMATE: pitch diameter d = size in tenths of an inch = 2.54 mm x {size} = {_g(PITCH_DIAMETER_PER_SIZE_MM * size, 3)} mm (the
# size rule of profilegen.contact.chain.catalogue_size; seed 001's published SHF-25 has m = 0.375 mm,
# z1 = 160, d = 60 mm = 0.945 x 63.5 mm), m = d / z1 rounded to 6 decimals.
module_mm = {_g(m)}
flexspline_teeth = {z1}
circular_spline_teeth = {z2}
waves = 2
# ESTIMATE: delta/r_m = {_rim_rule(p)},
# r_m = d/2 - 1.2 m - delta/2: delta = {_g(rim, 4)} mm, the derived r_m = {_g(r_m, 4)} mm (delta/w0 = {rim / (p.kappa * m):.2f}).
# Published rings span 1.84-3.4 % of r_m; this thickness (and the cup's wall and bottom, as thick)
# sets the stiffness K2/K3: at 2 % the model meets the catalogue's (docs/validation/catalogue-sizes.md).
rim_thickness_mm = {_g(rim, 4)}

[tooth]
# ESTIMATE: the project's default DCTA tooth (every bundled set), its lengths in units of the module.
kind = "dcta"
""" + "".join(f"{k} = {_g(v)}\n" for k, v in _TOOTH) + f"""
[wave_generator]
{_deflection_lines(p)}
contour = "elliptical_cam"    # cup-type sets: an elliptical cam under a flexible ball bearing
# ESTIMATE: the bearing's radial section 12.5 % of d, the contact model's own bearing estimate
# (races 2.5 % of d each, balls 7.5 % of d), rounded up to 0.01 mm.
bearing_thickness_mm = {_g(bearing, 2)}

[material]
# The flexspline steel of the published FEA-deformation study (seed 004; the bundled default set):
# 35CrMnSiA, heat-treated and nitrided, E = 209 GPa, nu = 0.295 (the study's values).
youngs_modulus_mpa = 209000.0
poisson_ratio = 0.295
# ESTIMATES (not in the study): the usual minimum tensile/yield strength of 35CrMnSiA quenched and
# low-temperature tempered; endurance limits sigma_-1 ~ 0.4 R_m, tau_-1 ~ 0.58 sigma_-1.
# Check them against a material certificate.
yield_strength_mpa = 1280.0
ultimate_strength_mpa = 1620.0
bending_endurance_limit_mpa = 650.0
shear_endurance_limit_mpa = 375.0

[torque]
{rule}
rated_nm = {_g(t_rated, 1)}
peak_nm = {_g(t_peak, 1)}
momentary_nm = {_g(t_mom, 1)}

[circular_spline]
# ESTIMATE: the thickest EDM wire (0.02-0.25 mm) whose corner round (radius + spark gap) is at most
# 0.2 m = {_g(0.2 * m, 4)} mm (the default tooth's CS space takes ~0.28 m): a {_g(2 * wire_r, 3)} mm wire,
# spark gap {_g(gap, 3)} mm per side (0.02 mm for wires >= 0.1 mm, 0.01 mm below).
wire_radius_mm = {_g(wire_r, 4)}
spark_gap_mm = {_g(gap, 3)}
# root and tip clearance: 0.25 m; outer diameter 1.25 x the root diameter (the reader's defaults).

[cup]
# ESTIMATES (the reader's defaults, docs/gearset.md, written out): length 0.6 d, face width 0.2 d,
# bottom and wall thickness = delta, boss radius r_m/2, root fillet 0.6 m; the wave generator's
# bearing as wide as the face and centred on it (z from the cup bottom's mid-plane).
length_mm = {_g(length, 3)}
face_width_mm = {_g(face, 3)}
bottom_thickness_mm = {_g(rim, 4)}
boss_radius_mm = {_g(boss, 3)}
root_fillet_radius_mm = {_g(fillet, 4)}
wall_thickness_mm = {_g(rim, 4)}
bearing_width_mm = {_g(face, 3)}
bearing_center_mm = {_g(length, 3)}
"""


def derived_quantities(gearset) -> dict:
    """What a set's fields imply, as ``profilegen check`` prints it: the ratio, the deflection
    w0, the neutral radius, the FS and CS pitch radii (the same ``GearSet`` properties as
    ``Design.to_dict()["derived"]``), the rim against them (δ/r_m, δ/w0) and the rated torque
    against what a catalogue gear of the size carries (``rated_level``: rated /
    :attr:`~profilegen.gearset.GearSet.size_torque_nm`, the law T ∝ d²·b)."""
    g = gearset.gear
    size_torque = gearset.size_torque_nm
    return {
        "ratio": gearset.ratio,
        "deflection_mm": gearset.deflection_mm,
        "neutral_radius_mm": g.neutral_radius_mm,
        "pitch_radius_mm": g.pitch_radius_mm,
        "cs_pitch_radius_mm": g.cs_pitch_radius_mm,
        "rim_per_neutral_radius": g.rim_thickness_mm / g.neutral_radius_mm,
        "rim_per_deflection": g.rim_thickness_mm / gearset.deflection_mm,
        "size_torque_nm": size_torque,
        "rated_level": gearset.torque.rated_nm / size_torque,
    }


def format_derived(gearset) -> str:
    """:func:`derived_quantities` on one line."""
    q = derived_quantities(gearset)
    return (f"ratio {q['ratio']:g}, w0 {q['deflection_mm']:.4g} mm, r_m {q['neutral_radius_mm']:.4f} mm, "
            f"pitch radii {q['pitch_radius_mm']:.4f}/{q['cs_pitch_radius_mm']:.4f} mm, "
            f"rim {100 * q['rim_per_neutral_radius']:.2f} % of r_m = {q['rim_per_deflection']:.2f} w0, "
            f"rated {gearset.torque.rated_nm:g} N·m = {q['rated_level']:.2f} x the size's "
            f"{q['size_torque_nm']:.4g} N·m (T ~ d²·b)")
