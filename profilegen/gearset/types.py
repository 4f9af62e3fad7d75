"""The gear set as a value: :class:`GearSet`, frozen and validated, with the section types it
holds (from :mod:`profilegen.gearset.sections`), and its constructors :func:`parse_gearset`
(from a mapping in the file schema) and :func:`load_gearset` (from a TOML file).

A :class:`GearSet` validates itself when built (through the reader,
:mod:`profilegen.gearset.reader`, which checks every field), so that ``dataclasses.replace``
and :meth:`GearSet.with_values` give validated sets too.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import GearSetError
from .reader import format_number, _Reader, read_toml
from .requirements import Requirements
from .sections import (
    CIRCULAR_SPLINE_KEYS,
    CUP_KEYS,
    FACE_KEYS,
    GEAR_KEYS,
    MATERIAL_KEYS,
    SECTION_TYPES,
    TOOTH_KEYS,
    TORQUE_KEYS,
    WAVE_GENERATOR_KEYS,
    COEFFICIENT_SUFFIX,
    CircularSpline,
    Cup,
    Face,
    DctaTooth,
    Gear,
    InvoluteTooth,
    Material,
    PointsTooth,
    Tooth,
    Torque,
    WaveGenerator,
)

__all__ = [
    "GearSet",
    "Gear",
    "DctaTooth",
    "InvoluteTooth",
    "PointsTooth",
    "Tooth",
    "WaveGenerator",
    "Material",
    "Torque",
    "CircularSpline",
    "Cup",
    "Requirements",
    "load_gearset",
    "parse_gearset",
]


_TORQUE_PER_D2B = math.sqrt(265.0 / (100.0**2 * 20.0) * 67.0 / (60.0**2 * 10.0))  # N·m/mm³, see size_torque_nm
_TORQUE_FACTOR_HIGH = 3.0  # a torque over 3× its catalogue value for the size is noted
_TORQUE_FACTOR_LOW = 10.0  # a rated torque under 1/10 of it too (a set copied to another size)


def _type_label(kind) -> str:
    if isinstance(kind, tuple):
        return " or ".join(k.__name__ for k in kind)
    return kind.__name__


def _json_value(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value


def _optional_fields(obj, keys) -> dict[str, Any]:
    out = {}
    for key in keys:
        value = getattr(obj, key)
        if value is not None:
            out[key] = _json_value(value)
    return out


def _twin_keys(parts: list[str]) -> tuple[str, ...]:
    """The other spelling of a tooth length (``addendum_mm`` ↔ ``addendum_coefficient``), or of a point list
    (``points`` ↔ ``points_file``)."""
    if len(parts) != 2 or parts[0] != "tooth":
        return ()
    key = parts[1]
    if key in ("points", "points_file"):  # a point list replaces the file and back (a sweep over points_file)
        return ("points_file" if key == "points" else "points",)
    if key.endswith(COEFFICIENT_SUFFIX):
        return (key[: -len(COEFFICIENT_SUFFIX)] + "_mm",)
    if key.endswith("_mm"):
        return (key[: -len("_mm")] + COEFFICIENT_SUFFIX,)
    return ()


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class GearSet:
    """One validated strain wave gear set (see ``docs/gearset.md``).

    Build it with :func:`load_gearset` / :func:`parse_gearset`; constructing it
    directly (or through :func:`dataclasses.replace` / :meth:`replace`) validates
    it as well. ``origin`` says where it was read from; ``given`` holds the field
    paths that were explicit in the input (``None``: all of them), so that
    :meth:`with_values` re-derives the defaults that depend on a changed value
    (e.g. the involute addendum = m, the neutral radius).
    """

    name: str
    description: str
    source: str
    scene: str = "design"
    gear: Gear
    tooth: Tooth
    wave_generator: WaveGenerator
    material: Material
    torque: Torque
    circular_spline: CircularSpline
    cup: Cup
    face: Face = field(default_factory=Face)
    requirements: Requirements = field(default_factory=Requirements)
    origin: str = field(default="<dict>", repr=False)
    given: frozenset[str] | None = field(default=None, repr=False)

    def __post_init__(self):
        if self.given is not None:
            object.__setattr__(self, "given", frozenset(self.given))
        wrong = [
            f"{name}: must be a {_type_label(kind)}, got {type(getattr(self, name)).__name__}"
            for name, kind in SECTION_TYPES.items()
            if not isinstance(getattr(self, name), kind)
        ]
        if wrong:
            raise GearSetError(wrong)
        reader = _Reader(base_dir=None)
        reader.read(self.to_dict())
        if reader.problems:
            raise GearSetError(reader.problems)
        # the wave generator must exist for this rim (rollers that fit, a cam inside the bore):
        # checked here, by the one function that builds it, so that check, every scene (the sketch
        # scene never builds it) and a sweep refuse the same sets. Two waves only: the rim stage
        # builds no contour for other wave counts (ring theory, with a warning).
        if self.gear.waves == 2:
            from ..geometry.wavegen import WaveGenError, WaveGeneratorFitError, from_gearset

            try:
                from_gearset(self)
            except WaveGenError as exc:
                raise WaveGeneratorFitError(" ".join(str(exc).split())) from None

    # ----------------------------------------------------------- derived values
    @property
    def deflection_mm(self) -> float:
        """Radial deflection of the neutral line on the major axis, w0 = ω*·m (mm)."""
        return self.wave_generator.deflection_coefficient * self.gear.module_mm

    @property
    def tooth_difference(self) -> int:
        """z2 − z1."""
        return self.gear.tooth_difference

    @property
    def ratio(self) -> float:
        """Reduction ratio z1/(z2 − z1), wave generator in, FS out, CS fixed.

        The FS turns opposite to the wave generator; the ratio is given as a
        positive number.
        """
        return self.gear.flexspline_teeth / self.gear.tooth_difference

    @property
    def size_torque_nm(self) -> float:
        """The rated torque a catalogue gear of this size carries, N·m (an ESTIMATE): rated torque
        ∝ pitch diameter² × face width, T = k·d²·b, the tooth-root bending capacity of a gear
        whose tooth proportions follow the module. k = 1.57e-3 N·m/mm³ is the geometric mean of
        the two catalogue sizes in the bundled sets: seed 000's CSF-40 (265 N·m, d = 100 mm,
        b = 20 mm, the estimated face width) gives 1.33e-3, seed 001's SHF-25 (67 N·m, d = 60 mm,
        b = 10 mm) 1.86e-3; seed 002's CSG-25 (87 N·m) is predicted as 79 N·m."""
        d = self.gear.module_mm * self.gear.flexspline_teeth
        return _TORQUE_PER_D2B * d * d * self.cup.face_width_mm

    @property
    def warnings(self) -> tuple[str, ...]:
        """Notes about a set that is valid but unusual (``profilegen check`` prints them): each
        torque far from what the size carries (:attr:`size_torque_nm`; peak and momentary
        compared with the catalogue ratios 167/67 and 304/67 of seed 001)."""
        out = []
        size = self.size_torque_nm
        for key, ratio in (("rated_nm", 1.0), ("peak_nm", 167.0 / 67.0), ("momentary_nm", 304.0 / 67.0)):
            value = getattr(self.torque, key)
            if value is None:
                continue
            expected = ratio * size
            if value > _TORQUE_FACTOR_HIGH * expected or (key == "rated_nm" and value < expected / _TORQUE_FACTOR_LOW):
                how = "above" if value > expected else "below"
                out.append(
                    f"torque.{key} = {format_number(value)} N·m is far {how} the ≈ {expected:.3g} N·m a catalogue gear of this "
                    f"size carries (pitch diameter {format_number(self.gear.module_mm * self.gear.flexspline_teeth)} mm, face "
                    f"width {format_number(self.cup.face_width_mm)} mm; scaling law T ∝ d²·b on seeds 000/001, "
                    "GearSet.size_torque_nm): do the torques belong to this size?"
                )
        return tuple(out)

    # ------------------------------------------------------------- conversions
    def to_dict(self, *, include_defaults: bool = True) -> dict[str, Any]:
        """JSON-safe nested dict in the file schema; ``parse_gearset`` of it gives an equal one.

        With ``include_defaults=False`` only the fields that were explicit in
        the input are written (tooth points always inline), so that values
        derived from others (neutral radius, module-relative defaults) are
        derived again when the dict is parsed.
        """
        g, t, w, mat, tq, cs, cup = (
            self.gear,
            self.tooth,
            self.wave_generator,
            self.material,
            self.torque,
            self.circular_spline,
            self.cup,
        )
        tooth: dict[str, Any] = {"kind": t.kind}
        if isinstance(t, PointsTooth):
            tooth["points"] = np.asarray(t.points, dtype=float).tolist()
            tooth["smoothing_mm"] = float(t.smoothing_mm)
        else:
            for key in TOOTH_KEYS[t.kind][1:]:
                if not key.endswith(COEFFICIENT_SUFFIX):
                    tooth[key] = _json_value(getattr(t, key))
            if not include_defaults:  # a length given in units of the module stays so (it follows m)
                for key, coefficient in t.coefficients:
                    coefficient_key = key[: -len("_mm")] + COEFFICIENT_SUFFIX
                    if f"tooth.{coefficient_key}" in (self.given or ()):
                        tooth[coefficient_key] = coefficient
        out: dict[str, Any] = {
            "name": self.name,
            "description": self.description,
            "source": self.source,
            "scene": self.scene,
            "gear": {key: _json_value(getattr(g, key)) for key in GEAR_KEYS},
            "tooth": tooth,
            "wave_generator": _optional_fields(w, WAVE_GENERATOR_KEYS),
            "material": _optional_fields(mat, MATERIAL_KEYS),
            "torque": _optional_fields(tq, TORQUE_KEYS),
            "circular_spline": {key: _json_value(getattr(cs, key)) for key in CIRCULAR_SPLINE_KEYS},
            "cup": {key: _json_value(getattr(cup, key)) for key in CUP_KEYS},
            "face": {key: ("auto" if getattr(self.face, key) is None else _json_value(getattr(self.face, key)))
                     for key in FACE_KEYS},
            "requirements": self.requirements.to_dict(),
        }
        if include_defaults or self.given is None:
            return out
        given = self.given
        keep_always = {"name", "description", "source", "tooth.kind", "tooth.points"}
        explicit: dict[str, Any] = {}
        for key, value in out.items():
            if isinstance(value, dict):
                section = {
                    k: v
                    for k, v in value.items()
                    if f"{key}.{k}" in given or f"{key}.{k}" in keep_always
                }
                if section or key not in ("circular_spline", "cup", "face", "requirements"):
                    explicit[key] = section
            elif key in given or key in keep_always:
                explicit[key] = value
        return explicit

    def with_values(self, changes: Mapping[str, Any]) -> GearSet:
        """A new validated gear set with some fields changed (for sweeps).

        ``changes`` maps dotted field paths to values, e.g.
        ``{"wave_generator.deflection_coefficient": 0.8, "gear.module_mm": 0.4}``;
        a value ``None`` removes the field so that its default applies again.
        Defaults that depend on a changed value are derived again.
        """
        if not isinstance(changes, Mapping):
            raise GearSetError(
                f"with_values: changes must be a mapping of field paths, got {type(changes).__name__}"
            )
        data = copy.deepcopy(self.to_dict(include_defaults=False))
        problems = []
        for path, value in changes.items():
            parts = str(path).split(".")
            if not all(parts):
                problems.append(
                    f"{path}: not a field path (expected 'section.field' or a top-level key)"
                )
                continue
            node = data
            for depth, part in enumerate(parts[:-1]):
                child = node.setdefault(part, {})
                if not isinstance(child, dict):
                    problems.append(f"{path}: {'.'.join(parts[: depth + 1])} is not a section")
                    break
                node = child
            else:
                for other in _twin_keys(parts):  # tooth.addendum_mm replaces tooth.addendum_coefficient
                    node.pop(other, None)
                if value is None:
                    node.pop(parts[-1], None)
                else:
                    node[parts[-1]] = _json_value(value) if isinstance(value, np.ndarray) else value
        if problems:
            raise GearSetError(problems)
        return parse_gearset(data, origin=self.origin)

    def replace(self, **changes: Any) -> GearSet:
        """:func:`dataclasses.replace` with validation; the result treats every field as explicit."""
        changes.setdefault("given", None)
        return dataclasses.replace(self, **changes)


# --------------------------------------------------------------------------- loading


def parse_gearset(
    mapping: Mapping[str, Any], *, origin: str = "<dict>", base_dir: str | os.PathLike | None = None
) -> GearSet:
    """Validate a mapping in the file schema and build a :class:`GearSet`.

    ``base_dir`` is the folder that a relative ``tooth.points_file`` is resolved
    against (the current directory when ``None``). Raises :class:`GearSetError`
    listing every problem.
    """
    if not isinstance(mapping, Mapping):
        raise GearSetError(
            f"{origin}: a gear set must be a table (mapping), got {type(mapping).__name__}"
        )
    reader = _Reader(base_dir=None if base_dir is None else Path(base_dir))
    parts = reader.read(mapping)
    if reader.problems:
        raise GearSetError(reader.problems)
    return GearSet(**parts, origin=origin, given=frozenset(reader.given))


def load_gearset(path: str | os.PathLike) -> GearSet:
    """Read and validate a gear-set TOML file, or a bundled set by name (``"default"``,
    ``"csf32_100"``: the names ``profilegen profiles`` lists, as the CLI takes them).

    Every error is a :class:`GearSetError` naming the file: a missing file, a
    malformed file (with TOML's line/column message) and each invalid field
    (one line per field, prefixed with the path).
    """
    from .profiles import resolve_gearset

    path = resolve_gearset(path) if isinstance(path, str) else Path(path)
    data = read_toml(path, GearSetError, "gear-set file")
    try:
        return parse_gearset(data, origin=str(path), base_dir=path.parent)
    except GearSetError as exc:
        raise type(exc)([f"{path}: {line}" for line in exc.problems]) from None
