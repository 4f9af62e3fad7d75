"""Reading and checking gear-set files: the TOML and point-list CSV readers (size-limited,
never echoing a file's content) and the field-by-field validation of a gear-set mapping.

:class:`_Reader` checks every field of a mapping in the file schema
(:mod:`profilegen.gearset.sections`), collects one problem line per bad field (field path,
value, unit, allowed range) and builds the sections; :func:`~profilegen.gearset.types.parse_gearset`
turns them into a :class:`~profilegen.gearset.types.GearSet`. :func:`read_limited` and
:func:`read_toml` are shared with the scene and sweep files.
"""

from __future__ import annotations

import csv
import difflib
import json
import math
import numbers
import os
import re
import stat
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import GearSetError, did_you_mean
from ..geometry.teeth import MAX_POINTS  # most points a kind = "points" tooth may have: one limit, the tooth builder's
from .sections import (
    CIRCULAR_SPLINE_KEYS,
    CUP_KEYS,
    FACE_KEYS,
    FACE_CROWNING_LIMIT,
    FACE_SECTIONS_RANGE,
    FACE_TAPER_LIMIT,
    DCTA_DEFAULTS,
    GEAR_KEYS,
    MATERIAL_KEYS,
    ROLLER_ANGLE_DEG_DEFAULT,
    SECTIONS,
    TOOTH_KEYS,
    TOOTH_LENGTHS,
    TOP_KEYS,
    TORQUE_KEYS,
    WAVE_GENERATOR_KEYS,
    COEFFICIENT_SUFFIX,
    CORNER_STYLES,
    CS_MIN_WALL_PER_MODULE,
    CS_OUTER_DIAMETER_PER_ROOT,
    FIT_METHODS,
    SCENE_NAMES,
    TOOTH_KINDS,
    WAVE_GENERATOR_CONTOURS,
    CircularSpline,
    Cup,
    Face,
    DctaTooth,
    Gear,
    InvoluteTooth,
    Material,
    PointsTooth,
    Torque,
    WaveGenerator,
    check_cup_geometry,
)
from .requirements import REQUIREMENTS_KEYS, NOT_REQUIRED, REQUIREMENT_FIELDS, Requirements


_NAME_RE = re.compile(r"[a-z0-9_-]+")
_CONTROL_RE = re.compile(r"[\x00-\x1f\x7f]")
_MIN_POINTS = 8


MAX_TOML_BYTES = 4 * 1024 * 1024
"""Largest TOML file (gear set, scene file, sweep spec) read, bytes: the bundled ones are < 5 kB."""
MAX_POINTS_FILE_BYTES = 16 * 1024 * 1024
"""Largest ``tooth.points_file`` read, bytes (``MAX_POINTS`` rows of a few columns fit ~20 times over)."""
RIM_PER_DEFLECTION_MIN = 0.5
"""Thinnest rim, as a multiple of the deflection w0 = ω*·m. Catalogue flexsplines have
δ ≈ 0.6–3·w0 (ratio 30 to 160; the bundled sets 1.8–2.9); the rim stage's nonlinear ring FEM loses
its positive-definite tangent below δ ≈ 0.3·w0 at z1 = 200 and 0.6–0.8·w0 at z1 = 40–60
(measured; such sets get a named :class:`~profilegen.errors.RimSolverError` instead)."""

MODULE_MIN_MM = 1e-5
"""The smallest module the arc fit resolves, mm: the default set scaled to m = 1e-5 mm (chord 1e-8 mm,
sharp corners) fits; at 3e-6 and 1e-6 mm the one-sided fit's offset collapses an arc (its absolute
tolerances, ~1e-12 mm, are then ~1e-6 of the tooth)."""


MAX_NAME_CHARS = 100
"""Longest gear-set ``name``: it names the output folder (``export/<name>/``)."""
MAX_TEXT_CHARS = 2000
"""Longest ``description`` / ``source`` text."""


def read_limited(path: str | os.PathLike, limit: int, error: type[Exception], what: str) -> bytes:
    """The bytes of the regular file at ``path``, at most ``limit`` of them.

    Anything else is an ``error`` naming the file and ``what`` it should be, never its
    content: a missing or unreadable file, a folder, a device (``/dev/zero``), a FIFO or
    socket (opened without blocking, so a FIFO with no writer does not hang), a file over
    ``limit`` bytes (also one that grows while it is read, or a ``/proc`` file that
    reports size 0).
    """
    path = os.fspath(path)
    if "\0" in path:
        raise error(f"{_show(path)}: not a file name (contains a NUL character)")
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
    except FileNotFoundError:
        raise error(f"{path}: no such {what}") from None
    except IsADirectoryError:
        raise error(f"{path}: is a folder, not a {what}") from None
    except OSError as exc:
        raise error(f"{path}: cannot read {what} ({exc.strerror or type(exc).__name__})") from None
    try:
        info = os.fstat(fd)
        if stat.S_ISDIR(info.st_mode):
            raise error(f"{path}: is a folder, not a {what}")
        if not stat.S_ISREG(info.st_mode):
            kind = ("a FIFO" if stat.S_ISFIFO(info.st_mode) else "a socket" if stat.S_ISSOCK(info.st_mode)
                    else "a device" if stat.S_ISCHR(info.st_mode) or stat.S_ISBLK(info.st_mode) else "not a file")
            raise error(f"{path}: is {kind}, not a regular file; a {what} must be a regular file")
        if info.st_size > limit:
            raise error(f"{path}: {info.st_size} bytes, too large for a {what} (at most {limit} bytes)")
        chunks, size = [], 0
        while size <= limit:
            try:
                chunk = os.read(fd, min(1 << 20, limit + 1 - size))
            except BlockingIOError:  # pragma: no cover - a regular file does not block
                continue
            except OSError as exc:
                raise error(f"{path}: cannot read {what} ({exc.strerror or type(exc).__name__})") from None
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        if size > limit:
            raise error(f"{path}: more than {limit} bytes, too large for a {what}")
        return b"".join(chunks)
    finally:
        os.close(fd)


def _decode_utf8(data: bytes, path, error: type[Exception], what: str) -> str:
    """``data`` as text; not UTF-8 is an ``error`` naming the line (never the bytes)."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise error(f"{path}: line {line}: not UTF-8 text (a {what} must be UTF-8 text)") from None


# tomllib messages that quote the file (a character, a key): keep what they say, not what they quote
_TOML_QUOTING = (
    (re.compile(r"^Found invalid character .*", re.S), "invalid character"),
    (re.compile(r"^Illegal character .*", re.S), "illegal (control) character"),
    (re.compile(r"^Cannot declare .* twice$", re.S), "a key or table declared twice"),
    (re.compile(r"^Cannot mutate immutable namespace .*", re.S), "a key redefines an inline table or array"),
    (re.compile(r"^Cannot redefine namespace .*", re.S), "a table redefined"),
    (re.compile(r"^Duplicate inline table key .*", re.S), "a duplicate key in an inline table"),
)
_TOML_WHERE = re.compile(r"^(.*) \(at (line \d+, column \d+|end of document)\)$", re.S)


def _toml_reason(exc: Exception) -> str:
    """tomllib's message without any text of the file: what is wrong and where."""
    text = str(exc)
    match = _TOML_WHERE.match(text)
    what, where = (match.group(1), match.group(2)) if match else (text, "")
    for pattern, replacement in _TOML_QUOTING:
        if pattern.match(what):
            what = replacement
            break
    else:
        if not re.fullmatch(r"[A-Za-z ,'=\[\]{}\-.\"]{1,80}", what):
            what = "not valid TOML"
    return f"{where}: {what}" if where else what


def read_toml(path: str | os.PathLike, error: type[Exception], what: str, *, limit: int = MAX_TOML_BYTES) -> dict:
    """The TOML file at ``path`` as a dict; every failure (missing, a folder, a device or
    FIFO, over ``limit`` bytes, unreadable, malformed, not UTF-8) is an ``error`` naming
    the file, the line and ``what`` it should be, never quoting the file."""
    text = _decode_utf8(read_limited(path, limit, error, what), path, error, what)
    if text.startswith("\ufeff"):  # a UTF-8 byte-order mark (Excel, Windows editors): not content
        text = text[1:]
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: malformed TOML at {_toml_reason(exc)}") from None
    except RecursionError:
        raise error(f"{path}: malformed TOML: nested too deeply") from None
    except ValueError:  # e.g. an integer of more than 4300 digits (sys.get_int_max_str_digits)
        raise error(f"{path}: malformed TOML: a value TOML cannot hold (an integer too long?)") from None


# --------------------------------------------------------------------------- validation

_REQUIRED = object()


class _Range:
    """An interval with open/closed ends, printed as ``(0, 10]``."""

    __slots__ = ("lo", "hi", "lo_open", "hi_open", "note")

    def __init__(self, lo, hi=math.inf, *, lo_open=False, hi_open=False, note=""):
        self.lo, self.hi, self.lo_open, self.hi_open, self.note = lo, hi, lo_open, hi_open, note

    def __contains__(self, v) -> bool:
        above = v > self.lo if self.lo_open else v >= self.lo
        below = v < self.hi if self.hi_open or math.isinf(self.hi) else v <= self.hi
        return above and below

    def describe(self) -> str:
        if math.isinf(self.hi):
            text = f"must be {'>' if self.lo_open else '>='} {format_number(self.lo)}"
        else:
            text = (
                f"must be in {'(' if self.lo_open else '['}{format_number(self.lo)}, "
                f"{format_number(self.hi)}{')' if self.hi_open else ']'}"
            )
        return f"{text} ({self.note})" if self.note else text


def format_number(x) -> str:
    if isinstance(x, numbers.Integral):
        return str(int(x))
    return f"{float(x):.6g}"


def _show(value) -> str:
    """A value as it would read in the TOML file (short)."""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, str):  # escaped (one line, no control characters) and cut to ~40 characters
        text = json.dumps(value if len(value) <= 40 else value[:37], ensure_ascii=False)
        return text if len(value) <= 40 else text[:-1] + '..." (' + f"{len(value)} characters)"
    if isinstance(value, numbers.Integral):
        value = int(value)
        if abs(value) >= 10**30:
            return f"{'-' if value < 0 else ''}{str(abs(value))[:12]}... ({len(str(abs(value)))} digits)"
        return str(value)
    if isinstance(value, numbers.Real):
        return repr(float(value))
    if isinstance(value, Mapping):
        return "{...}"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _key(key) -> str:
    """A key as a message shows it: a plain key as it is, any other quoted, escaped and cut."""
    text = str(key)
    return text if re.fullmatch(r"[A-Za-z0-9_-]{1,60}", text) else _show(text)


def _type_name(value) -> str:
    if isinstance(value, (bool, np.bool_)):
        return "boolean"
    if isinstance(value, str):
        return "string"
    if isinstance(value, numbers.Integral):
        return "integer"
    if isinstance(value, numbers.Real):
        return "float"
    if isinstance(value, Mapping):
        return "table"
    if isinstance(value, (list, tuple)):
        return "array"
    return type(value).__name__


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


class _Reader:
    """Reads one gear-set mapping; collects problems, the explicit paths and the sections."""

    def __init__(self, *, base_dir: Path | None):
        self.base_dir = base_dir
        self.problems: list[str] = []
        self.given: set[str] = set()

    # ----------------------------------------------------------------- helpers
    def problem(self, line: str) -> None:
        self.problems.append(line)

    def unknown_keys(self, table: Mapping, prefix: str, allowed, what: str = "") -> None:
        for key in table:
            if key in allowed:
                continue
            path = f"{prefix}.{_key(key)}" if prefix else _key(key)
            self.problem(f"{path}: unknown key{what} (allowed: {', '.join(allowed)})" + did_you_mean(key, allowed, n=1))

    def section(self, data: Mapping, name: str, *, required: bool = True) -> Mapping | None:
        if name not in data:
            if required:
                self.problem(f"{name}: missing required section [{name}]")
            return None
        table = data[name]
        if not isinstance(table, Mapping):
            self.problem(
                f"{name} = {_show(table)}: must be a table ([{name}] section), got {_type_name(table)}"
            )
            return None
        return table

    def number(
        self,
        table: Mapping,
        prefix: str,
        key: str,
        *,
        unit: str,
        rng: _Range | None = None,
        default: Any = _REQUIRED,
        integer: bool = False,
    ):
        """A number field; returns its value (default when absent) or None after a problem."""
        path = f"{prefix}.{key}" if prefix else key
        suffix = f" {unit}" if unit else ""
        if key not in table:
            if default is _REQUIRED:
                detail = ", ".join(x for x in ("required", unit, rng.describe() if rng else "") if x)
                self.problem(f"{path}: missing ({detail})")
                return None
            if default is None:
                return None
            if rng is not None and default not in rng:
                self.problem(
                    f"{path} = {format_number(default)}{suffix} (default): {rng.describe()}; give it explicitly"
                )
                return None
            return default
        self.given.add(path)
        value = table[key]
        want = "an integer" if integer else "a number"
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
            self.problem(f"{path} = {_show(value)}: must be {want}, got {_type_name(value)}")
            return None
        if integer:
            if not isinstance(value, numbers.Integral):
                self.problem(f"{path} = {_show(value)}: must be an integer, got float")
                return None
            value = int(value)
        else:
            value = float(value)
            if not math.isfinite(value):
                self.problem(f"{path} = {_show(value)}{suffix}: must be finite")
                return None
        if rng is not None and value not in rng:
            self.problem(f"{path} = {_show(value)}{suffix}: {rng.describe()}")
            return None
        return value

    def string(
        self,
        table: Mapping,
        prefix: str,
        key: str,
        *,
        default: Any = _REQUIRED,
        choices: tuple[str, ...] | None = None,
        pattern: re.Pattern | None = None,
        max_chars: int | None = None,
    ):
        path = f"{prefix}.{key}" if prefix else key
        if key not in table:
            if default is _REQUIRED:
                extra = f", one of {', '.join(map(_show, choices))}" if choices else ""
                self.problem(f"{path}: missing (required string{extra})")
                return None
            return default
        self.given.add(path)
        value = table[key]
        if not isinstance(value, str):
            self.problem(f"{path} = {_show(value)}: must be a string, got {_type_name(value)}")
            return None
        if choices is not None and value not in choices:
            hint = difflib.get_close_matches(value[:100], choices, n=1)
            line = f"{path} = {_show(value)}: must be one of {', '.join(map(_show, choices))}"
            self.problem(line + (f"; did you mean {_show(hint[0])}?" if hint else ""))
            return None
        if max_chars is not None and len(value) > max_chars:
            self.problem(f"{path} = {_show(value)}: must be at most {max_chars} characters, got {len(value)}")
            return None
        if choices is None and pattern is None and _CONTROL_RE.search(value):
            self.problem(f"{path} = {_show(value)}: must not contain control characters (line breaks, tabs, NUL)")
            return None
        if pattern is not None and not pattern.fullmatch(value):
            self.problem(
                f"{path} = {_show(value)}: must match {pattern.pattern} "
                "(lower-case letters, digits, _ and -)"
            )
            return None
        if choices is None and pattern is None and not value.strip():
            self.problem(f"{path} = {_show(value)}: must not be empty")
            return None
        return value

    # ----------------------------------------------------------------- sections
    def read(self, data: Mapping) -> dict[str, Any]:
        """Read everything; returns the GearSet keyword arguments (meaningful only without problems)."""
        self.unknown_keys(data, "", TOP_KEYS + SECTIONS)
        name = self.string(data, "", "name", pattern=_NAME_RE, max_chars=MAX_NAME_CHARS)
        description = self.string(data, "", "description", max_chars=MAX_TEXT_CHARS)
        source = self.string(data, "", "source", max_chars=MAX_TEXT_CHARS)
        scene = self.string(data, "", "scene", default="design", choices=SCENE_NAMES)

        gear_raw = self.read_gear(self.section(data, "gear"))
        m = gear_raw.get("module_mm")
        tooth = self.read_tooth(self.section(data, "tooth"), m)
        gear = self.finish_gear(gear_raw, tooth)
        wave_generator = self.read_wave_generator(self.section(data, "wave_generator"), gear_raw, gear)
        material = self.read_material(self.section(data, "material"))
        torque = self.read_torque(self.section(data, "torque"))
        # the FS tip's farthest radius, undeformed + w0
        reach = (None if gear is None or tooth is None or wave_generator is None else
                 gear.pitch_radius_mm + tooth.addendum_mm + wave_generator.deflection_coefficient * gear.module_mm)
        circular_spline = self.read_circular_spline(
            self.section(data, "circular_spline", required=False), m, fs_reach_mm=reach
        )
        cup = self.read_cup(self.section(data, "cup", required=False), gear)
        face = self.read_face(self.section(data, "face", required=False), cup)
        requirements = self.read_requirements(self.section(data, "requirements", required=False))
        rim = gear_raw.get("rim_thickness_mm")
        if rim is not None and m is not None and wave_generator is not None:
            w0 = wave_generator.deflection_coefficient * m
            if rim < RIM_PER_DEFLECTION_MIN * w0:
                self.problem(
                    f"gear.rim_thickness_mm = {format_number(rim)} mm: must be >= "
                    f"{format_number(RIM_PER_DEFLECTION_MIN * w0)} mm ({format_number(RIM_PER_DEFLECTION_MIN)}·w0, w0 = "
                    f"wave_generator.deflection_coefficient·gear.module_mm = {format_number(w0)} mm): a rim this thin for its "
                    "deflection is outside the ring models' range"
                )
                gear = None
        return dict(
            name=name,
            description=description,
            source=source,
            scene=scene,
            gear=gear,
            tooth=tooth,
            wave_generator=wave_generator,
            material=material,
            torque=torque,
            circular_spline=circular_spline,
            cup=cup,
            face=face,
            requirements=requirements,
        )

    def read_gear(self, t: Mapping | None) -> dict[str, Any]:
        if t is None:
            return {}
        self.unknown_keys(t, "gear", GEAR_KEYS)
        out: dict[str, Any] = {}
        out["module_mm"] = m = self.number(
            t, "gear", "module_mm", unit="mm", rng=_Range(MODULE_MIN_MM, 10, note="lower bound: the smallest module the arc fit resolves")
        )
        out["flexspline_teeth"] = z1 = self.number(
            t, "gear", "flexspline_teeth", unit="", integer=True, rng=_Range(20, 2000)
        )
        out["waves"] = waves = self.number(
            t, "gear", "waves", unit="", integer=True, rng=_Range(2, 4), default=2
        )
        z2 = self.number(t, "gear", "circular_spline_teeth", unit="", integer=True, rng=_Range(1))
        if z2 is not None and z1 is not None and waves is not None:
            diff = z2 - z1
            if diff <= 0 or diff % waves:
                self.problem(
                    f"gear.circular_spline_teeth = {z2}: z2 − z1 = {diff} must be a positive multiple "
                    f"of waves = {waves} (e.g. z2 = {z1 + waves})"
                )
                z2 = None
        out["circular_spline_teeth"] = z2
        r1 = None if m is None or z1 is None else m * z1 / 2.0
        out["pitch_radius_mm"] = r1
        rim_rng = (
            _Range(0, 0.2 * r1, lo_open=True, note="upper bound 0.2·pitch radius")
            if r1 is not None
            else _Range(0, lo_open=True)
        )
        out["rim_thickness_mm"] = self.number(t, "gear", "rim_thickness_mm", unit="mm", rng=rim_rng)
        # The neutral radius is checked once the tooth dedendum is known (finish_gear).
        out["neutral_radius_mm"] = self.number(t, "gear", "neutral_radius_mm", unit="mm", default=None)
        out["_neutral_given"] = "neutral_radius_mm" in t
        return out

    def finish_gear(self, raw: dict[str, Any], tooth) -> Gear | None:
        if not raw:
            return None
        r1 = raw["pitch_radius_mm"]
        dedendum = None if tooth is None else tooth.dedendum_mm
        r_m = raw["neutral_radius_mm"]
        if raw["_neutral_given"] and r_m is not None:
            if r1 is None:
                rng = _Range(0, lo_open=True)
            elif dedendum is None:
                rng = _Range(0.5 * r1, r1, lo_open=True, hi_open=True, note="0.5·r1 < r_m < r1")
            else:
                rng = _Range(
                    0.5 * r1,
                    r1 - dedendum,
                    lo_open=True,
                    hi_open=True,
                    note=f"0.5·r1 < r_m < root radius r1 − dedendum, r1 = {format_number(r1)} mm",
                )
            if r_m not in rng:
                self.problem(f"gear.neutral_radius_mm = {_show(r_m)} mm: {rng.describe()}")
                r_m = None
        elif not raw["_neutral_given"]:
            rim = raw["rim_thickness_mm"]
            r_m = None if None in (r1, dedendum, rim) else r1 - dedendum - rim / 2.0
        values = {k: raw[k] for k in GEAR_KEYS if k != "neutral_radius_mm"}
        if r_m is None or any(v is None for v in values.values()):
            return None
        return Gear(**values, neutral_radius_mm=r_m)

    def read_tooth(self, t: Mapping | None, m: float | None):
        if t is None:
            return None
        kind = self.string(t, "tooth", "kind", choices=TOOTH_KINDS)
        if kind is None:
            known = set().union(*TOOTH_KEYS.values())
            self.unknown_keys(t, "tooth", sorted(known, key=lambda k: (k != "kind", k)))
            return None
        allowed = TOOTH_KEYS[kind]
        for key in t:
            if key in allowed:
                continue
            owners = [k for k, keys in TOOTH_KEYS.items() if key in keys]
            belongs = f"belongs to kind {', '.join(map(_show, owners))}; " if owners else ""
            line = (
                f"tooth.{_key(key)}: unknown key for kind {_show(kind)} "
                f"({belongs}allowed: {', '.join(allowed)})"
            )
            self.problem(line + ("" if owners else did_you_mean(key, allowed, n=1)))
        if kind == "dcta":
            return self.read_dcta(t, m)
        if kind == "involute":
            return self.read_involute(t, m)
        return self.read_points(t, m)

    def _module_range(self, m, lo, factor, *, lo_open, hi_open=False, what="m"):
        if m is None:
            return _Range(lo, lo_open=lo_open)
        return _Range(
            lo, factor * m, lo_open=lo_open, hi_open=hi_open, note=f"upper bound {format_number(factor)}·{what}"
        )

    def tooth_length(self, t: Mapping, kind: str, name: str, m: float | None, coefficients: dict):
        """A tooth length given as ``<name>_mm`` (mm) or ``<name>_coefficient`` (units of m),
        or its module-relative default; the value in mm, or None after a problem."""
        spec = TOOTH_LENGTHS[kind][name]
        mm_key, c_key = f"{name}_mm", f"{name}{COEFFICIENT_SUFFIX}"
        if mm_key in t and c_key in t:
            self.given.update((f"tooth.{mm_key}", f"tooth.{c_key}"))
            self.problem(
                f"tooth.{mm_key}, tooth.{c_key}: give at most one of the two ({name.replace('_', ' ')} in mm, "
                "or in units of the module m)"
            )
            return None
        if c_key in t:
            rng = _Range(spec.lo, spec.hi, lo_open=spec.lo_open, hi_open=spec.hi_open,
                         note=f"in units of the module m{'; ' + spec.note if spec.note else ''}")
            c = self.number(t, "tooth", c_key, unit="", rng=rng)
            if c is None or m is None:  # an invalid module is reported already
                return None
            coefficients[mm_key] = c
            return c * m
        if m is None:  # an invalid module is reported already; the value's type is still checked
            self.number(t, "tooth", mm_key, unit="mm", rng=_Range(0, lo_open=spec.lo_open or spec.lo > 0),
                        default=None)
            return None
        if name == "half_thickness":
            rng = _Range(0, math.pi * m / 2.0, lo_open=True, hi_open=True, note="upper bound half a pitch π·m/2")
        elif spec.lo > 0:
            rng = _Range(spec.lo * m, spec.hi * m, lo_open=spec.lo_open, hi_open=spec.hi_open,
                         note=f"{format_number(spec.lo)}·m to {format_number(spec.hi)}·m, m = {format_number(m)} mm")
        else:
            rng = _Range(0, spec.hi * m, lo_open=spec.lo_open, hi_open=spec.hi_open,
                         note=f"upper bound {format_number(spec.hi)}·m")
        # spec.default None means required (sections._Length; no tooth length is)
        return self.number(t, "tooth", mm_key, unit="mm", rng=rng,
                           default=_REQUIRED if spec.default is None else spec.default * m)

    def read_dcta(self, t: Mapping, m: float | None) -> DctaTooth | None:
        v: dict[str, Any] = {}
        v["pressure_angle_deg"] = self.number(
            t,
            "tooth",
            "pressure_angle_deg",
            unit="deg",
            rng=_Range(0, 45, lo_open=True, hi_open=True),
            default=DCTA_DEFAULTS["pressure_angle_deg"],
        )
        coefficients: dict[str, float] = {}
        for name in TOOTH_LENGTHS["dcta"]:
            v[f"{name}_mm"] = self.tooth_length(t, "dcta", name, m, coefficients)
        if any(x is None for x in v.values()):
            return None
        return DctaTooth(**v, coefficients=tuple(coefficients.items()))

    def read_involute(self, t: Mapping, m: float | None) -> InvoluteTooth | None:
        v: dict[str, Any] = {}
        v["pressure_angle_deg"] = self.number(
            t, "tooth", "pressure_angle_deg", unit="deg", rng=_Range(5, 35), default=20.0
        )
        coefficients: dict[str, float] = {}
        for name in TOOTH_LENGTHS["involute"]:
            v[f"{name}_mm"] = self.tooth_length(t, "involute", name, m, coefficients)
        if any(x is None for x in v.values()):
            return None
        return InvoluteTooth(**v, coefficients=tuple(coefficients.items()))

    def read_points(self, t: Mapping, m: float | None) -> PointsTooth | None:
        smoothing = self.number(
            t, "tooth", "smoothing_mm", unit="mm", rng=_Range(0, 0.1), default=0.0005
        )
        has_points, has_file = "points" in t, "points_file" in t
        if has_points == has_file:
            which = "both" if has_points else "neither"
            self.problem(
                "tooth.points, tooth.points_file: give exactly one of the two for "
                f'kind "points", got {which}'
            )
            return None
        points_file = None
        if has_points:
            label = "tooth.points"
            self.given.add(label)
            points = self.point_list(t["points"])
        else:
            label = "tooth.points_file"
            self.given.add("tooth.points")
            points_file = self.string(t, "tooth", "points_file", max_chars=4096)
            points = None if points_file is None else self.points_csv(points_file)
        if points is None:
            return None
        if not self.check_points(points, label, m) or smoothing is None:
            return None
        return PointsTooth(points=points, smoothing_mm=smoothing, points_file=points_file)

    def point_list(self, value) -> np.ndarray | None:
        if not isinstance(value, (list, tuple, np.ndarray)):
            self.problem(
                f"tooth.points = {_show(value)}: must be an array of [x_mm, y_mm] pairs, "
                f"got {_type_name(value)}"
            )
            return None
        if len(value) > MAX_POINTS:
            self.problem(f"tooth.points: at most {MAX_POINTS} [x_mm, y_mm] points are allowed, got {len(value)}")
            return None
        rows = []
        for i, pair in enumerate(value):
            ok = (
                isinstance(pair, (list, tuple, np.ndarray))
                and len(pair) == 2
                and all(
                    isinstance(c, numbers.Real) and not isinstance(c, (bool, np.bool_)) for c in pair
                )
            )
            if not ok:
                self.problem(
                    f"tooth.points[{i}] = {_show(pair)}: must be an [x_mm, y_mm] pair of numbers"
                )
                return None
            rows.append((float(pair[0]), float(pair[1])))
        return np.array(rows, dtype=float).reshape(-1, 2)

    def points_csv(self, name: str) -> np.ndarray | None:
        """The x_mm, y_mm columns of the CSV ``name`` (relative to ``base_dir``), or None after
        a problem. A problem names the file and the line, never the file's content: a file
        that is not a point list (any readable text) must not be echoed back."""
        where = f"tooth.points_file = {_show(name)}"
        if "\0" in name or len(name) > 4096:
            self.problem(f"{where}: not a file name (a NUL character or over 4096 characters)")
            return None
        path = Path(name)
        if not path.is_absolute() and self.base_dir is not None:
            path = self.base_dir / path
        try:
            data = read_limited(path, MAX_POINTS_FILE_BYTES, GearSetError, "point-list CSV file")
            text = _decode_utf8(data, path, GearSetError, "point-list CSV file").removeprefix("\ufeff")  # Excel's BOM
        except GearSetError as exc:
            self.problem(f"{where}: {exc}")
            return None
        del data
        lines = [
            (n, line)
            for n, line in enumerate(text.splitlines(), 1)
            if line.strip() and not line.lstrip().startswith("#")
        ]
        del text
        if not lines:
            self.problem(f"{where}: {path} is empty (expected a header x_mm,y_mm and rows)")
            return None
        if len(lines) - 1 > MAX_POINTS:
            self.problem(
                f"{where}: {path} has {len(lines) - 1} data lines: at most {MAX_POINTS} points are allowed"
            )
            return None
        try:
            rows = list(csv.reader(line for _, line in lines))
        except csv.Error as exc:
            self.problem(f"{where}: {path}: not a CSV file ({exc.__class__.__name__} while parsing)")
            return None
        header = [h.strip() for h in rows[0]]
        if "x_mm" not in header or "y_mm" not in header:
            self.problem(
                f"{where}: {path} line {lines[0][0]}: the first non-comment line must be a header naming "
                "the columns x_mm and y_mm (not found there)"
            )
            return None
        ix, iy = header.index("x_mm"), header.index("y_mm")
        out = []
        for (number, _), row in zip(lines[1:], rows[1:]):
            try:
                out.append((float(row[ix]), float(row[iy])))
            except IndexError:
                self.problem(
                    f"{where}: {path} line {number}: has {len(row)} columns, the header puts x_mm, y_mm "
                    f"in columns {ix + 1} and {iy + 1}"
                )
                return None
            except ValueError:
                bad = "x_mm" if not _is_float(row[ix]) else "y_mm"
                self.problem(f"{where}: {path} line {number}: column {bad} is not a number")
                return None
        return np.array(out, dtype=float).reshape(-1, 2)

    def check_points(self, p: np.ndarray, label: str, m: float | None) -> bool:
        n_problems = len(self.problems)
        if len(p) < _MIN_POINTS:
            self.problem(f"{label}: must have at least {_MIN_POINTS} [x_mm, y_mm] points, got {len(p)}")
            return False
        if not np.all(np.isfinite(p)):
            self.problem(f"{label}: every coordinate must be finite (no nan/inf)")
            return False
        repeated = np.flatnonzero(np.all(np.diff(p, axis=0) == 0.0, axis=1))
        if repeated.size:
            self.problem(
                f"{label}: point {repeated[0] + 1} repeats point {repeated[0]} (zero-length segment)"
            )
        if not p[0, 1] < p[-1, 1]:
            self.problem(
                f"{label}: must run from root to tip (first y = {format_number(p[0, 1])} mm "
                f"must be below last y = {format_number(p[-1, 1])} mm)"
            )
        ymin, ymax = p[:, 1].min(), p[:, 1].max()
        if not ymin < 0.0 < ymax:
            self.problem(
                f"{label}: must cross the pitch circle (min y < 0 < max y in the pitch frame), "
                f"got y in [{format_number(ymin)}, {format_number(ymax)}] mm"
            )
        xmin, xmax = p[:, 0].min(), p[:, 0].max()
        half_pitch = None if m is None else math.pi * m / 2.0
        if xmin < 0.0 or (half_pitch is not None and xmax > half_pitch):
            allowed = (
                ">= 0" if half_pitch is None else f"in [0, {format_number(half_pitch)}] (half a pitch π·m/2)"
            )
            self.problem(
                f"{label}: x must be {allowed} for a right flank, "
                f"got x in [{format_number(xmin)}, {format_number(xmax)}] mm"
            )
        if m is not None:
            if ymax > 3.0 * m:
                self.problem(
                    f"{label}: addendum (max y) = {format_number(ymax)} mm: must be <= {format_number(3 * m)} (3·m)"
                )
            if -ymin > 3.0 * m:
                self.problem(
                    f"{label}: dedendum (−min y) = {format_number(-ymin)} mm: must be <= {format_number(3 * m)} (3·m)"
                )
        return len(self.problems) == n_problems

    def read_wave_generator(
        self, t: Mapping | None, gear_raw: dict, gear: Gear | None
    ) -> WaveGenerator | None:
        if t is None:
            return None
        self.unknown_keys(t, "wave_generator", WAVE_GENERATOR_KEYS)
        p = "wave_generator"
        v: dict[str, Any] = {}
        v["deflection_coefficient"] = self.number(
            t, p, "deflection_coefficient", unit="", rng=_Range(0, 3, lo_open=True), default=1.0
        )
        v["contour"] = contour = self.string(
            t, p, "contour", default="elliptical_cam", choices=WAVE_GENERATOR_CONTOURS
        )
        ok = all(x is not None for x in v.values())
        if contour == "rollers":
            count = self.number(t, p, "roller_count", unit="", integer=True)
            if count is not None and count not in (2, 4):
                self.problem(f"{p}.roller_count = {count}: must be 2 or 4")
                count = None
            waves = gear_raw.get("waves")
            if count is not None and waves is not None and count % waves:
                self.problem(f"{p}.roller_count = {count}: must be a multiple of gear.waves = {waves}")
                count = None
            if gear is not None:
                inner = gear.neutral_radius_mm - gear.rim_thickness_mm / 2.0
                rng = _Range(
                    0,
                    inner,
                    lo_open=True,
                    hi_open=True,
                    note="upper bound the rim's inner radius r_m − δ/2",
                )
            else:
                rng = _Range(0, lo_open=True)
            radius = self.number(t, p, "roller_radius_mm", unit="mm", rng=rng)
            v["roller_count"], v["roller_radius_mm"] = count, radius
            ok = ok and count is not None and radius is not None
            angle_rng = _Range(0, 45, lo_open=True, hi_open=True)
            if count == 2 and "roller_angle_deg" in t:
                self.problem(
                    f"{p}.roller_angle_deg: only allowed with roller_count = 4 "
                    f"(roller_count is 2: both rollers sit on the major axis)"
                )
                ok = False
            elif count == 4 or "roller_angle_deg" in t:  # a bad count is already reported
                angle = self.number(
                    t,
                    p,
                    "roller_angle_deg",
                    unit="deg",
                    rng=angle_rng,
                    default=ROLLER_ANGLE_DEG_DEFAULT if count == 4 else None,
                )
                ok = ok and angle is not None
                v["roller_angle_deg"] = angle
        elif contour is not None:
            for key in ("roller_count", "roller_radius_mm", "roller_angle_deg"):
                if key in t:
                    self.problem(
                        f'{p}.{key}: only allowed with contour = "rollers" (contour is {_show(contour)})'
                    )
                    ok = False
        if "bearing_thickness_mm" in t and contour is not None and contour != "elliptical_cam":
            self.problem(
                f'{p}.bearing_thickness_mm: only allowed with contour = "elliptical_cam" '
                f"(contour is {_show(contour)})"
            )
            ok = False
        elif contour == "elliptical_cam":
            bearing = self.number(t, p, "bearing_thickness_mm", unit="mm", rng=_Range(0), default=None)
            if "bearing_thickness_mm" in t and bearing is None:
                ok = False
            v["bearing_thickness_mm"] = bearing
        return WaveGenerator(**v) if ok else None

    def read_material(self, t: Mapping | None) -> Material | None:
        if t is None:
            return None
        p = "material"
        self.unknown_keys(t, p, MATERIAL_KEYS)
        v: dict[str, Any] = {}
        v["youngs_modulus_mpa"] = self.number(
            t, p, "youngs_modulus_mpa", unit="MPa", rng=_Range(0, 1e6, lo_open=True)
        )
        v["poisson_ratio"] = self.number(
            t, p, "poisson_ratio", unit="", rng=_Range(0, 0.5, hi_open=True)
        )
        ok = all(x is not None for x in v.values())
        for key in MATERIAL_KEYS[2:]:
            value = self.number(t, p, key, unit="MPa", rng=_Range(0, lo_open=True), default=None)
            ok = ok and not (key in t and value is None)
            v[key] = value
        ultimate = v["ultimate_strength_mpa"]
        if ultimate is not None:
            for key in (
                "yield_strength_mpa",
                "bending_endurance_limit_mpa",
                "shear_endurance_limit_mpa",
            ):
                if v[key] is not None and v[key] > ultimate:
                    self.problem(
                        f"{p}.{key} = {format_number(v[key])} MPa: must be <= "
                        f"material.ultimate_strength_mpa = {format_number(ultimate)} MPa"
                    )
                    ok = False
        return Material(**v) if ok else None

    def read_torque(self, t: Mapping | None) -> Torque | None:
        if t is None:
            return None
        p = "torque"
        self.unknown_keys(t, p, TORQUE_KEYS)
        rated = self.number(t, p, "rated_nm", unit="N·m", rng=_Range(0, lo_open=True))
        peak_rng = (
            _Range(0, lo_open=True) if rated is None else _Range(rated, note="peak >= rated torque")
        )
        peak = self.number(t, p, "peak_nm", unit="N·m", rng=peak_rng)
        if peak is None:
            momentary_rng = _Range(0, lo_open=True)
        else:
            momentary_rng = _Range(peak, note="momentary >= peak torque")
        momentary = self.number(t, p, "momentary_nm", unit="N·m", rng=momentary_rng, default=None)
        if rated is None or peak is None or ("momentary_nm" in t and momentary is None):
            return None
        return Torque(rated_nm=rated, peak_nm=peak, momentary_nm=momentary)

    def read_circular_spline(self, t: Mapping | None, m: float | None, *,
                             fs_reach_mm: float | None = None) -> CircularSpline | None:
        if t is None:
            t = {}
        p = "circular_spline"
        self.unknown_keys(t, p, CIRCULAR_SPLINE_KEYS)
        v = {"fit_method": self.string(t, p, "fit_method", default="one_sided", choices=FIT_METHODS)}
        for key in ("root_clearance_mm", "tip_clearance_mm"):
            v[key] = self.number(
                t,
                p,
                key,
                unit="mm",
                rng=self._module_range(m, 0, 2, lo_open=False),
                default=None if m is None else 0.25 * m,
            )
            if m is None and key not in t:
                v[key] = None  # derived from the module, which is invalid: already reported
        # wire EDM (profilegen.profile.rootfillet): the CS corners are rounded with wire radius + spark gap
        v["wire_radius_mm"] = self.number(t, p, "wire_radius_mm", unit="mm", rng=_Range(
            0, 0.25, lo_open=True, note="EDM wires are 0.02–0.33 mm in diameter"), default=0.125)
        v["spark_gap_mm"] = self.number(t, p, "spark_gap_mm", unit="mm", rng=_Range(
            0, 0.1, note="the spark gap per side, a few µm to some 50 µm"), default=0.02)
        v["corners"] = self.string(t, p, "corners", default="fillet", choices=CORNER_STYLES)
        # the STEP ring's outer diameter, against the root diameter estimated as 2·(FS tip reach + root clearance)
        # fs_reach_mm is None whenever m is (no gear without a valid module): testing m changes nothing but the type
        root = (None if m is None or fs_reach_mm is None or v["root_clearance_mm"] is None
                else 2 * (fs_reach_mm + v["root_clearance_mm"]))
        low = 0.0 if root is None or m is None else root + 2 * CS_MIN_WALL_PER_MODULE * m
        v["outer_diameter_mm"] = self.number(t, p, "outer_diameter_mm", unit="mm", rng=_Range(
            low, lo_open=root is None, note="" if root is None else
            f"root diameter ~{format_number(root)} mm + 2 × a wall of {format_number(CS_MIN_WALL_PER_MODULE)}·m"),
            default=None if root is None else float(math.ceil(CS_OUTER_DIAMETER_PER_ROOT * root)))
        if "outer_diameter_mm" not in t and root is None:
            v.pop("outer_diameter_mm")  # derived from the root diameter at the STEP writer
        if any(x is None for x in v.values()):
            return None
        return CircularSpline(**v)

    def read_cup(self, t: Mapping | None, gear: Gear | None) -> Cup | None:
        """The ``[cup]`` section; every field defaults to an ESTIMATE from the gear."""
        if t is None:
            t = {}
        p = "cup"
        self.unknown_keys(t, p, CUP_KEYS)
        if gear is None:  # invalid gear: already reported; the defaults cannot be derived
            return None
        d = gear.module_mm * gear.flexspline_teeth  # pitch diameter
        r_m = gear.neutral_radius_mm
        r_bore = r_m - 0.5 * gear.rim_thickness_mm
        v = {
            "length_mm": self.number(t, p, "length_mm", unit="mm", rng=_Range(0, 10 * d, lo_open=True,
                                     note="upper bound 10·pitch diameter"), default=0.6 * d),
            "face_width_mm": self.number(t, p, "face_width_mm", unit="mm", rng=_Range(0, d, lo_open=True,
                                         note="upper bound the pitch diameter"), default=0.2 * d),
            "bottom_thickness_mm": self.number(t, p, "bottom_thickness_mm", unit="mm", rng=_Range(
                0, 0.5 * r_m, lo_open=True, note="upper bound r_m/2"), default=gear.rim_thickness_mm),
            "boss_radius_mm": self.number(t, p, "boss_radius_mm", unit="mm", rng=_Range(
                0, r_bore, lo_open=True, hi_open=True, note="the boss lies inside the cup's bore"),
                default=0.5 * r_m),
            "root_fillet_radius_mm": self.number(t, p, "root_fillet_radius_mm", unit="mm", rng=_Range(
                0, 2 * gear.module_mm, lo_open=True, note="upper bound 2·m"), default=0.6 * gear.module_mm),
        }
        # the 3D cup's fields (default: wall = δ, bearing = the face, centred on the mid-face), their
        # ranges relative to the others: check_cup_geometry, the rules CupGeometry uses too
        for key in ("wall_thickness_mm", "bearing_width_mm", "bearing_center_mm"):
            v[key] = self.number(t, p, key, unit="mm", rng=_Range(0, lo_open=True), default=None)
            if key in t and v[key] is None:
                return None  # reported
        if any(v[key] is None for key in v if key not in ("wall_thickness_mm", "bearing_width_mm",
                                                          "bearing_center_mm")):
            return None
        try:
            full = check_cup_geometry(
                neutral_radius_mm=r_m, ring_thickness_mm=gear.rim_thickness_mm, length_mm=v["length_mm"],
                face_width_mm=v["face_width_mm"], bottom_thickness_mm=v["bottom_thickness_mm"],
                boss_radius_mm=v["boss_radius_mm"], wall_thickness_mm=v["wall_thickness_mm"],
                bearing_width_mm=v["bearing_width_mm"], bearing_center_mm=v["bearing_center_mm"],
                error=GearSetError, prefix="cup.", ring_name="gear.rim_thickness_mm")
        except GearSetError as exc:
            self.problem(str(exc))
            return None
        for key in ("wall_thickness_mm", "bearing_width_mm", "bearing_center_mm"):
            v[key] = full[key]
        return Cup(**v)

    def read_face(self, t: Mapping | None, cup: Cup | None) -> Face | None:
        """The ``[face]`` section: every field optional; "auto" (or absent) for the design section
        and the modification means chosen / computed by the face stage."""
        if t is None:
            return Face()
        p = "face"
        self.unknown_keys(t, p, FACE_KEYS)
        v = {}
        auto = {k: None for k in ("design_section_z_mm", "taper_mm_per_mm", "crowning_mm")
                if isinstance(t.get(k), str) and t.get(k) == "auto"}
        if "design_section_z_mm" not in auto:
            if cup is None:  # invalid cup: reported already; the tooth ring is unknown
                rng = _Range(0, lo_open=True)
            else:
                lo, hi = cup.length_mm - 0.5 * cup.face_width_mm, cup.length_mm + 0.5 * cup.face_width_mm
                rng = _Range(lo, hi, note='the tooth ring l ± b/2 of [cup], z from the cup bottom\'s mid-plane; or "auto"')
            v["design_section_z_mm"] = self.number(t, p, "design_section_z_mm", unit="mm", rng=rng, default=None)
        lo, hi = FACE_SECTIONS_RANGE
        v["sections"] = self.number(t, p, "sections", unit="", rng=_Range(lo, hi), default=5, integer=True)
        if "taper_mm_per_mm" not in auto:
            v["taper_mm_per_mm"] = self.number(t, p, "taper_mm_per_mm", unit="mm/mm", rng=_Range(
                -FACE_TAPER_LIMIT, FACE_TAPER_LIMIT, note='or "auto"'), default=None)
        if "crowning_mm" not in auto:
            v["crowning_mm"] = self.number(t, p, "crowning_mm", unit="mm", rng=_Range(
                -FACE_CROWNING_LIMIT, FACE_CROWNING_LIMIT, note='or "auto"'), default=None)
        if any(k in t and v.get(k) is None and k not in auto for k in FACE_KEYS):
            return None  # reported
        for k in auto:
            self.given.add(f"{p}.{k}")
        return Face(**{**v, **auto})

    def read_requirements(self, t: Mapping | None) -> Requirements | None:
        """The ``[requirements]`` table (:mod:`profilegen.gearset.requirements`): every key
        optional, a number in its range or ``"none"`` (not required)."""
        if t is None:
            return Requirements()
        p = "requirements"
        self.unknown_keys(t, p, REQUIREMENTS_KEYS)
        v: dict[str, Any] = {}
        ok = True
        for f in REQUIREMENT_FIELDS:
            if isinstance(t.get(f.key), str):
                self.given.add(f"{p}.{f.key}")
                v[f.key] = None
                if t[f.key] != NOT_REQUIRED:
                    self.problem(f"{p}.{f.key} = {_show(t[f.key])}: must be a number{' in ' + f.unit if f.unit else ''} "
                                 f'or "{NOT_REQUIRED}" (not required)')
                    ok = False
                continue
            note = f'or "{NOT_REQUIRED}": not required'
            v[f.key] = self.number(t, p, f.key, unit=f.unit, rng=_Range(f.lo, f.hi, lo_open=f.lo_open, note=note),
                                   default=f.default)
            ok &= not (f.key in t and v[f.key] is None)
        return Requirements(**v) if ok else None
