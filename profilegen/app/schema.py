"""The gear set as a form: every field the gear-set reader checks, with its unit, range and meaning.

The fields are not listed here a second time: :func:`form_fields` reads a gear set's own file
dict through the package's reader (:mod:`profilegen.gearset.reader`) and records every number
and word it asks for — the path, the unit, the allowed range as the reader prints it, the
default, the allowed words. A tooth length given in units of the module stays a
``*_coefficient`` field, one given in mm a ``*_mm`` field, as in the file. The meanings come
from the schema's tables in ``docs/gearset.md`` when the source checkout is there (a hint on
each field; an installed package goes without).

:func:`apply_form` turns the form's texts into a new gear set or into the reader's own
one-line errors, keyed by field path.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any, Mapping

from ..errors import GearSetError
from ..gearset import GearSet, parse_gearset
from ..gearset.reader import _REQUIRED, _Reader

__all__ = ["Field", "SLIDER_FIELDS", "apply_form", "errors_by_field", "form_fields", "form_text", "parse_text",
           "slider_range"]

#: The fields designers sweep by hand get a slider beside their box (a tooth length in whichever
#: form the file gives it: mm or units of the module).
SLIDER_FIELDS = (
    "wave_generator.deflection_coefficient",
    "tooth.pressure_angle_deg",
    "tooth.addendum_coefficient", "tooth.addendum_mm",
    "tooth.dedendum_coefficient", "tooth.dedendum_mm",
    "gear.rim_thickness_mm",
    "torque.rated_nm", "torque.peak_nm", "torque.momentary_nm",
)
#: a slider spans the value ± this share (clipped to the field's range)
SLIDER_SPAN = 0.3
_SECTION_ORDER = ("", "gear", "tooth", "wave_generator", "torque", "material", "circular_spline", "cup", "face",
                  "requirements")


@dataclass(frozen=True, slots=True)
class Field:
    """One form field: ``path`` as in :meth:`GearSet.with_values` (``tooth.addendum_coefficient``),
    ``kind`` "number", "integer" or "word"; ``allowed`` the reader's range text (``must be in
    [0.2, 3]``); ``lo``/``hi`` its ends (None for words); ``choices`` for words with a fixed set;
    ``doc`` the meaning (may be empty)."""

    path: str
    kind: str
    unit: str
    allowed: str
    lo: float | None
    hi: float | None
    default: Any
    choices: tuple[str, ...] = ()
    doc: str = ""

    @property
    def section(self) -> str:
        return self.path.rpartition(".")[0]

    @property
    def key(self) -> str:
        return self.path.rpartition(".")[2]

    @property
    def slider(self) -> bool:
        return self.path in SLIDER_FIELDS


class _Recorder(_Reader):
    """The reader, recording every field it reads (the checks themselves are the reader's)."""

    def __init__(self):
        super().__init__(base_dir=None)
        self.fields: dict[str, dict] = {}

    def number(self, table, prefix, key, *, unit, rng=None, default=_REQUIRED, integer=False):
        path = f"{prefix}.{key}" if prefix else key
        self.fields.setdefault(path, dict(
            path=path, kind="integer" if integer else "number", unit=unit,
            allowed=rng.describe() if rng is not None else "", default=None if default is _REQUIRED else default,
            lo=None if rng is None else float(rng.lo), hi=None if rng is None or math.isinf(rng.hi) else float(rng.hi)))
        return super().number(table, prefix, key, unit=unit, rng=rng, default=default, integer=integer)

    def string(self, table, prefix, key, *, default=_REQUIRED, choices=None, pattern=None, max_chars=None):
        path = f"{prefix}.{key}" if prefix else key
        allowed = (f"one of {', '.join(choices)}" if choices else
                   f"matching {pattern.pattern}" if pattern is not None else "text")
        self.fields.setdefault(path, dict(path=path, kind="word", unit="", allowed=allowed, lo=None, hi=None,
                                          default=None if default is _REQUIRED else default,
                                          choices=tuple(choices or ())))
        return super().string(table, prefix, key, default=default, choices=choices, pattern=pattern,
                              max_chars=max_chars)


def form_fields(gearset: GearSet) -> tuple[Field, ...]:
    """The form of ``gearset``: every field its reader checks, in the file's section order."""
    rec = _Recorder()
    data = gearset.to_dict(include_defaults=False)
    for section in ("circular_spline", "cup", "face", "requirements"):  # optional: their fields all the same
        data.setdefault(section, {})
    rec.read(data)
    docs = _docs()
    out = []
    for f in rec.fields.values():
        section, _, key = f["path"].rpartition(".")
        stem = re.sub(r"(_mm|_coefficient)$", "", key)
        doc = docs.get((section, key)) or docs.get((section, stem)) or docs.get(("", key)) or ""
        out.append(Field(**f, doc=doc))
    order = {s: i for i, s in enumerate(_SECTION_ORDER)}
    return tuple(sorted(out, key=lambda f: order.get(f.section, len(order))))


@lru_cache(maxsize=1)
def _docs() -> dict[tuple[str, str], str]:
    """(section, key) -> meaning, from docs/gearset.md's tables (empty outside a source checkout)."""
    path = Path(__file__).resolve().parents[2] / "docs" / "gearset.md"
    try:
        text = path.read_text(encoding="utf-8")
    except OSError:
        return {}
    out: dict[tuple[str, str], str] = {}
    section = ""
    for line in text.splitlines():
        head = re.match(r"#+ .*?\[([a-z_]+)\]", line)
        if head:
            section = head.group(1)
        row = re.match(r"\|\s*`([a-z_0-9]+)`\s*\|\s*([^|]+)\|", line)
        if row:
            out.setdefault((section, row.group(1)), row.group(2).strip().replace("`", ""))
            out.setdefault(("", row.group(1)), row.group(2).strip().replace("`", ""))
    return out


def form_text(value) -> str:
    """A field's value as its box shows it (as the TOML file would say it, ``""`` when absent)."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def parse_text(text, field: Field):
    """A box's text as the file would hold it: an integer or a number where it reads as one,
    else the text itself (the reader then says what it must be). Empty: None (the default)."""
    if text is None:
        return None
    if not isinstance(text, str):
        return text
    t = text.strip()
    if t == "":
        return None
    if field.kind == "word":
        return t
    try:
        return int(t)
    except ValueError:
        pass
    try:
        return float(t)
    except ValueError:
        return t


def current_values(gearset: GearSet, fields) -> dict[str, Any]:
    """Each field's value in ``gearset`` (its file dict with the defaults filled in)."""
    full, explicit = gearset.to_dict(), gearset.to_dict(include_defaults=False)
    out = {}
    for f in fields:
        section, _, key = f.path.rpartition(".")
        for data in (explicit, full):
            node = data.get(section, {}) if section else data
            if isinstance(node, Mapping) and key in node:
                out[f.path] = node[key]
                break
        else:
            out[f.path] = f.default
    return out


def errors_by_field(exc: GearSetError, paths) -> dict[str, str]:
    """The reader's problem lines, each under the field it names (``""``: a line naming no field
    of the form). Several fields in one line (``a, b: give at most one``): under each."""
    out: dict[str, str] = {}
    names = sorted(paths, key=len, reverse=True)
    for line in exc.problems:
        head = re.split(r" = |: ", line, maxsplit=1)[0]
        hits = [p for p in names if re.search(rf"(^|[ ,(]){re.escape(p)}($|[ ,)])", head)]
        if not hits:
            hits = [p for p in names if re.search(rf"\b{re.escape(p)}\b", line)][:1] or [""]
        for p in hits:
            out[p] = f"{out[p]}; {line}" if p in out else line
    return out


def apply_form(gearset: GearSet, fields, texts: Mapping[str, Any]) -> tuple[GearSet, dict[str, Any]]:
    """The gear set with the form's values: ``texts`` maps field paths to the boxes' texts (or
    values). Returns (the new gear set, the changes applied); raises :class:`GearSetError`
    (the reader's lines) for a bad value, naming the field."""
    by_path = {f.path: f for f in fields}
    now = current_values(gearset, fields)
    changes: dict[str, Any] = {}
    for path, text in texts.items():
        f = by_path.get(path)
        if f is None:
            raise GearSetError(f"{path}: not a field of this gear set's form")
        value = parse_text(text, f)
        old = now.get(path)
        if value is None and old is not None:
            changes[path] = None  # an emptied box: the default again, or the reader's own 'missing' line
        elif value is not None and not _same(value, old):
            changes[path] = value
    if not changes:
        return gearset, {}
    return gearset.with_values(changes), changes


def _same(a, b) -> bool:
    numbers = (int, float)
    if isinstance(a, numbers) and isinstance(b, numbers) and not isinstance(a, bool) and not isinstance(b, bool):
        return float(a) == float(b)
    return a == b


def slider_range(field: Field, value: float) -> tuple[float, float, float]:
    """(min, max, step) of a field's slider: the value ± :data:`SLIDER_SPAN`, inside the field's range."""
    v = float(value)
    span = abs(v) * SLIDER_SPAN or 1.0
    lo, hi = v - span, v + span
    if field.lo is not None:
        lo = max(lo, field.lo)
    if field.hi is not None:
        hi = min(hi, field.hi)
    step = 10 ** math.floor(math.log10(max(hi - lo, 1e-12) / 200))
    return lo, hi, step


def fresh(gearset: GearSet, data: Mapping) -> GearSet:
    """A gear set from a file dict (load), keeping the origin."""
    return parse_gearset(data, origin=gearset.origin)
