"""Parameter studies: gear-set fields swept over a grid or a sample, one design per point.

A *sweep spec* (TOML, ``docs/sweep.md``; example ``profiles/sweeps/deflection.toml``)
names a base gear set, a scene, and either a ``[grid]`` (field → list of values, the
full Cartesian product) or a ``[sample]`` (``method = "lhs" | "random"``, ``n``,
``seed``, field → ``[lo, hi]``). Fields are the dotted paths of
:meth:`GearSet.with_values` (``"wave_generator.deflection_coefficient"``). Every point is
the base set with those values, validated like a file and run through
:func:`profilegen.pipeline.design.design`; a point that fails (a value out of range, an envelope
that cannot be classified, a fit that does not converge, ...) is recorded with its error
and the others go on.

:func:`run_sweep` runs the points on a :class:`concurrent.futures.Executor`: a local
process pool by default, a Dask cluster through :func:`dask_executor`, or any executor
given. Each finished point is appended at once, as one complete line, to a CSV journal
(``journal.csv`` in the output folder) keyed by a stable point id (a hash of the point's
values, the scene and the base gear set), so that a sweep that was interrupted (Ctrl-C, a
kill, a lost worker) resumes where it stopped when it is run again: finished points are
read back, not recomputed. The result table has one row per point, sorted by the point's
index whatever the order of completion: the swept inputs, the headline outputs
(:data:`OUTPUTS`; an output a design does not have is an empty cell), per-stage times, and
``status`` (``ok`` / ``error``), ``error_type``, ``error_message``.

>>> points = grid_points({"gear.rim_thickness_mm": [0.4, 0.5], "tooth.pressure_angle_deg": [8, 10, 12]})
>>> len(points), points[1]
(6, {'gear.rim_thickness_mm': 0.4, 'tooth.pressure_angle_deg': 10})
>>> u = sample_points({"wave_generator.deflection_coefficient": (0.8, 1.2)}, 5, method="lhs", seed=1)
>>> sorted(int((p["wave_generator.deflection_coefficient"] - 0.8) / 0.4 * 5) for p in u)  # one per stratum
[0, 1, 2, 3, 4]
"""

from __future__ import annotations

import contextlib
import csv
import errno
import hashlib
import io
import itertools
import json
import logging
import math
import os
import re
import signal
import stat
import threading
import time
import zlib
from collections import Counter
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import Executor, as_completed
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np

from ..errors import ExportError, GearSetError, ProfilegenError, SweepSpecError
from ..gearset import GearSet, looks_like_path
from ..pools import stop_pool

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

    from ..pipeline.design import Design, Scene

__all__ = [
    "OUTPUTS",
    "OUTPUT_COLUMNS",
    "SAMPLE_METHODS",
    "STATUS_COLUMNS",
    "SignalInterrupt",
    "SweepError",
    "SweepResult",
    "SweepSpec",
    "dask_executor",
    "grid_points",
    "interrupt_on_signals",
    "load_sweep_spec",
    "outputs_of",
    "parse_sweep_spec",
    "plot_sweep",
    "point_id",
    "run_sweep",
    "sample_points",
    "write_table",
    "csv_text",
    "SWEEP_FILES",
]

log = logging.getLogger(__name__)

SAMPLE_METHODS = ("lhs", "random")
JOURNAL = "journal.csv"
#: every file a sweep writes into its folder (:mod:`profilegen.output.folder`: it may hold only these)
SWEEP_FILES = frozenset({JOURNAL, "results.csv", "sweep.png", ".profilegen.json"})
MAX_POINTS = 100_000
DEFAULT_PLOT = "profile_max_error_mm"
_NAME_RE = re.compile(r"[A-Za-z0-9_.-]+")
MAX_NAME_CHARS = 100
MAX_GRID_TEXT_CHARS = 4096
"""Longest text value in a grid (the longest gear-set text field, ``tooth.points_file``)."""
_TOP_KEYS = ("name", "description", "gearset", "scene", "plot", "grid", "sample")
_SAMPLE_KEYS = ("method", "n", "seed")


class SweepError(ProfilegenError, RuntimeError):
    """A sweep could not run or finish as a whole (an executor that failed, a lost Dask
    cluster, a missing optional package); single points that fail are rows, not this."""


# ----------------------------------------------------------------------------- outputs


def _stage_time(stage: str) -> Callable[[Design], float | None]:
    def get(d: Design):
        return next((s.time_s for s in d.stages if s.stage == stage), None)

    return get


def _fit_error(method: str) -> Callable[[Any], float | None]:
    return lambda d: d.profile.fits[method].max_error_mm


def _count(kind: str, what: str) -> Callable[[Design], Any]:
    return lambda d: d.envelope.counts()[kind][what]


def _worst(values) -> float | None:
    values = [v for v in values if v is not None]
    return max(values) if values else None


def _min_safety(d: Any) -> float | None:
    return d.stress.min_safety


def _min_safety_name(d: Any) -> str | None:
    worst = d.stress.min_safety_check
    return None if worst is None else worst.name


def _verdict(d: Design) -> str | None:
    """The design's verdict: PASS, FAIL or INCOMPLETE (older Verdicts: PASS/FAIL by ``passed``)."""
    v = d.verdict.to_dict()
    return v.get("status") or ("PASS" if v.get("passed") else "FAIL")


def _failed_checks(d: Design) -> str | None:
    """The verdict's failed checks, '; '-separated (None: none failed)."""
    return "; ".join(" ".join(str(f).split()) for f in d.verdict.to_dict().get("failures") or ()) or None


_STAGES = ("tooth", "rim", "deformation fit", "envelope", "gearform", "arcfit", "contact", "stress")

#: (column, type, getter): the headline outputs of a design, one column each. A getter
#: that fails (the design has no such part: no contact in the sketch scene, no stress, a
#: fit left out) gives an empty cell. (A getter takes the Design typed Any: it reads parts a design
#: may not have, and the AttributeError of a missing one is that empty cell.)
OUTPUTS: tuple[tuple[str, type, Callable[[Any], Any]], ...] = (
    ("deflection_mm", float, lambda d: d.gearset.deflection_mm),
    ("min_clearance_mm", float, lambda d: d.form.clearance.min_mm),
    ("profile_min_clearance_mm", float, lambda d: d.profile.clearance.min_mm),
    ("profile_max_error_mm", float, lambda d: d.profile.max_error_mm),
    ("profile_max_backlash_mm", float, lambda d: d.profile.max_backlash_mm),
    ("profile_method", str, lambda d: d.profile.method),
    ("profile_branches", int, lambda d: 1 if d.profile.branches is None else len(d.profile.branches.fits)),
    ("fit_least_squares_max_error_mm", float, _fit_error("least_squares")),
    ("fit_minimax_max_error_mm", float, _fit_error("minimax")),
    ("fit_one_sided_max_error_mm", float, _fit_error("one_sided")),
    ("conjugate_pieces", int, _count("conjugate", "pieces")),
    ("interfering_pieces", int, _count("interfering", "pieces")),
    ("tip_path_pieces", int, _count("tip_path", "pieces")),
    ("conjugate_length_mm", float, _count("conjugate", "length_mm")),
    ("ridges", int, lambda d: len(d.envelope.ridges)),
    ("folds", int, lambda d: len(d.envelope.folds)),
    ("max_interference_mm", float, lambda d: d.envelope.max_interference_mm),
    ("cs_tip_radius_mm", float, lambda d: d.form.tip_radius_mm),
    ("cs_root_radius_mm", float, lambda d: d.form.root_radius_mm),
    ("contact_rotation_arcmin", float, lambda d: d.contact.cases[0].rotation_arcmin),
    ("contact_teeth_in_contact", int, lambda d: d.contact.cases[0].teeth_in_contact),
    ("contact_max_tooth_force_n", float, lambda d: _worst(c.max_tooth_force_n for c in d.contact.cases)),
    ("contact_stiffness_nm_per_rad", float, lambda d: d.contact.secant_stiffness_nm_per_rad[0]),
    ("stress_tooth_ring_mpa", float, lambda d: _worst(d.stress.headline()["tooth_ring_total_mpa"])),
    ("stress_cup_bottom_mpa", float, lambda d: _worst(d.stress.headline()["cup_bottom_von_mises_mpa"])),
    ("stress_diaphragm_shear_amplitude_mpa", float, lambda d: d.stress.headline()["diaphragm_shear_amplitude_mpa"]),
    ("stress_min_safety", float, _min_safety),
    ("stress_min_safety_check", str, _min_safety_name),
    ("stress_passed", bool, lambda d: d.stress.passed),
    ("verdict", str, _verdict),
    ("failed_checks", str, _failed_checks),
    ("warnings", int, lambda d: len(d.warnings)),
    *((f"time_{s.replace(' ', '_')}_s", float, _stage_time(s)) for s in _STAGES),
    ("time_design_s", float, lambda d: None),  # the worker's wall time around design(), filled in by it
)
#: the output columns, in table order
OUTPUT_COLUMNS: tuple[str, ...] = tuple(c for c, _, _ in OUTPUTS)
STATUS_COLUMNS = ("status", "error_type", "error_message")
_TYPES = {c: t for c, t, _ in OUTPUTS}
_OUTPUT_ERRORS = (AttributeError, KeyError, IndexError, TypeError, ValueError, StopIteration)


def outputs_of(result: Design) -> dict[str, Any]:
    """The :data:`OUTPUTS` of one design ({column: value or None})."""
    out = {}
    for column, kind, get in OUTPUTS:
        try:
            value = get(result)
        except _OUTPUT_ERRORS:
            value = None
        out[column] = _typed(value, kind)
    return out


def _typed(value, kind: type):
    if value is None:
        return None
    if kind is bool:
        return bool(value)
    if kind is int:
        return int(value)
    if kind is float:
        v = float(value)
        return v if math.isfinite(v) else None
    return str(value)


# ----------------------------------------------------------------------------- points


def grid_points(grid: Mapping[str, Sequence]) -> list[dict]:
    """The full grid: every combination of the values, the last field varying fastest."""
    fields = list(grid)
    return [dict(zip(fields, combo)) for combo in itertools.product(*(list(grid[f]) for f in fields))]


def sample_points(ranges: Mapping[str, Sequence], n: int, *, method: str = "lhs", seed: int = 0) -> list[dict]:
    """``n`` points in the box ``ranges`` (field → (lo, hi)).

    ``method``: ``"lhs"`` (Latin hypercube, :class:`scipy.stats.qmc.LatinHypercube`: every
    one of the n equal strata of each field holds one point) or ``"random"`` (uniform).
    Deterministic for a given ``seed``. A field whose bounds are both integers gets
    integers, each of lo..hi equally likely.
    """
    if method not in SAMPLE_METHODS:
        raise ValueError(f"method must be one of {', '.join(SAMPLE_METHODS)}, got {method!r}")
    fields = list(ranges)
    if method == "lhs":
        from scipy.stats import qmc

        try:
            engine = qmc.LatinHypercube(d=len(fields), rng=seed)
        except TypeError:  # scipy < 1.15 takes `seed`
            engine = qmc.LatinHypercube(d=len(fields), seed=seed)
        u = engine.random(n)
    else:
        u = np.random.default_rng(seed).random((n, len(fields)))
    points = []
    for row in u:
        point: dict[str, float] = {}
        for f, x in zip(fields, row):
            lo, hi = ranges[f]
            if _is_int(lo) and _is_int(hi):
                point[f] = int(min(lo + math.floor(x * (hi - lo + 1)), hi))
            else:
                point[f] = float(lo + x * (hi - lo))
        points.append(point)
    return points


def point_id(values: Mapping[str, Any], scene: Scene, gearset: GearSet) -> str:
    """A stable id of a point: a hash of its values, the scene's fields and the base set."""
    return _point_ids([values], scene, gearset)[0]


def _point_ids(points: Sequence[Mapping[str, Any]], scene: Scene, gearset: GearSet) -> list[str]:
    def canonical(obj) -> bytes:
        return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=str).encode()

    base = hashlib.sha256(canonical({"scene": asdict(scene), "gearset": gearset.to_dict()}) + b"\n")
    ids = []
    for values in points:
        h = base.copy()
        h.update(canonical(dict(values)))
        ids.append(h.hexdigest()[:16])
    return ids


def _is_int(v) -> bool:
    return isinstance(v, (int, np.integer)) and not isinstance(v, bool)


# ----------------------------------------------------------------------------- the spec


@dataclass(frozen=True, slots=True, eq=False)
class SweepSpec:
    """A validated sweep: the base gear set, the scene and the points (in index order).

    ``kind``: ``"grid"``, ``"lhs"`` or ``"random"``; ``fields``: the swept field paths;
    ``points``: one {field: value} per point; ``plot``: the output column plotted
    against each field; ``origin``: where it was read from.
    """

    name: str
    gearset: GearSet
    scene: Scene
    kind: str
    fields: tuple[str, ...]
    points: tuple[dict, ...]
    description: str = ""
    plot: str = DEFAULT_PLOT
    seed: int | None = None
    origin: str = "<dict>"
    ids: tuple[str, ...] = field(init=False)

    def __post_init__(self):
        object.__setattr__(self, "points", tuple(dict(p) for p in self.points))
        object.__setattr__(self, "ids", tuple(_point_ids(self.points, self.scene, self.gearset)))

    def to_dict(self) -> dict:
        return {"name": self.name, "description": self.description, "gearset": self.gearset.name,
                "scene": self.scene.name, "kind": self.kind, "fields": list(self.fields), "points": len(self.points),
                "seed": self.seed, "plot": self.plot, "origin": self.origin}


def load_sweep_spec(path: str | os.PathLike) -> SweepSpec:
    """Read and validate a sweep spec file (:class:`SweepSpecError` naming the key)."""
    from ..gearset import read_toml

    path = Path(path)
    data = read_toml(path, SweepSpecError, "sweep spec file")
    return parse_sweep_spec(data, origin=str(path), base_dir=path.parent, default_name=path.stem)


def spec_header(data, top_keys, fail, *, what: str, default_name: str, base_dir) -> tuple:
    """The checks a sweep and an optimisation spec share: a table of known keys, its ``name``
    (a safe folder name), ``description`` and base ``gearset`` (relative to ``base_dir``, the
    spec's folder). Returns (name, description, base folder, GearSet); ``fail(key, problem)`` raises."""
    if not isinstance(data, Mapping):
        fail("<file>", f"{what} must be a table, got {type(data).__name__}")
    for key in data:
        if key not in top_keys:
            fail(str(key), f"unknown key (allowed: {', '.join(top_keys)})")
    name = _text(data, "name", default_name, fail)
    _check_name(name, fail)
    description = _text(data, "description", "", fail)
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    return name, description, base, _base_gearset(_text(data, "gearset", "default", fail), base, fail)


def spec_scene(text: str, base: Path, gearset, fail, key: str):
    """A spec's scene: a preset name or a scenes file (relative to ``base``), resolved for ``gearset``."""
    from ..pipeline.scenes import resolve_scene

    arg = text if not looks_like_path(text) or Path(text).is_absolute() else base / text
    try:
        return resolve_scene(arg, default=gearset.scene)
    except GearSetError as exc:
        from ..output.userpaths import named_file_problem  # another file's keys and values are not shown

        fail(key, named_file_problem(exc, arg, "scene file") if looks_like_path(str(arg)) else str(exc))


def parse_sweep_spec(data: Mapping, *, origin: str = "<dict>", base_dir: str | os.PathLike | None = None,
                     default_name: str = "sweep") -> SweepSpec:
    """Validate a spec mapping (the TOML's tables) and build the :class:`SweepSpec`.

    Relative gear-set and scene file paths are taken from ``base_dir`` (the spec's folder).
    """

    def fail(key: str, problem: str):
        raise SweepSpecError(f"{origin}: {key}: {problem}")

    name, description, base, gearset = spec_header(data, _TOP_KEYS, fail, what="a sweep spec",
                                                   default_name=default_name, base_dir=base_dir)
    scene = spec_scene(_text(data, "scene", "sketch", fail), base, gearset, fail, "scene")
    plot = _text(data, "plot", DEFAULT_PLOT, fail)
    if plot not in OUTPUT_COLUMNS:
        fail("plot", f"{plot!r} is not an output column (one of {', '.join(OUTPUT_COLUMNS)})")
    has_grid, has_sample = "grid" in data, "sample" in data
    if has_grid == has_sample:
        fail("grid/sample", "give exactly one of a [grid] table (field = [values]) or a [sample] table "
                            "(method, n, seed, field = [lo, hi])")
    seed = None
    if has_grid:
        grid = flat_table(data["grid"], "grid", fail)
        if not grid:
            fail("grid", "needs at least one field = [values]")
        for f, values in grid.items():
            if not isinstance(values, list) or not values:
                fail(f"grid.{f}", f"must be a non-empty array of values, got {values!r}")
            for i, v in enumerate(values):
                if not isinstance(v, (bool, int, float, str)):
                    fail(f"grid.{f}[{i}]", f"values must be numbers, texts or booleans, got {type(v).__name__}")
                if isinstance(v, float) and not math.isfinite(v):
                    fail(f"grid.{f}[{i}]", f"{v!r} is not a finite number")
        count = math.prod(len(v) for v in grid.values())
        if count > MAX_POINTS:
            fail("grid", f"{count} points: at most {MAX_POINTS}")
        points, kind = grid_points(grid), "grid"
        first = {f: v[0] for f, v in grid.items()}
    else:
        table = data["sample"]
        if not isinstance(table, Mapping):
            fail("sample", f"must be a table, got {type(table).__name__}")
        kind = table.get("method", "lhs")
        if kind not in SAMPLE_METHODS:
            fail("sample.method", f"{kind!r}: must be one of {', '.join(SAMPLE_METHODS)}")
        n = table.get("n")
        if not _is_int(n) or not 1 <= n <= MAX_POINTS:
            fail("sample.n", f"{'missing' if n is None else repr(n)}: must be an integer in [1, {MAX_POINTS}]")
        seed = table.get("seed", 0)
        if not _is_int(seed) or seed < 0:
            fail("sample.seed", f"{seed!r}: must be an integer >= 0")
        ranges = flat_table({k: v for k, v in table.items() if k not in _SAMPLE_KEYS}, "sample", fail)
        if not ranges:
            fail("sample", "needs at least one field = [lo, hi]")
        for f, rng in ranges.items():
            ok = (isinstance(rng, list) and len(rng) == 2 and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                               and math.isfinite(v) for v in rng) and rng[0] < rng[1])
            if not ok:
                fail(f"sample.{f}", f"must be [lo, hi] with finite numbers lo < hi, got {rng!r}")
        points = sample_points(ranges, n, method=kind, seed=seed)
        first = {f: r[0] for f, r in ranges.items()}
    if has_grid:
        for f, values in grid.items():
            _check_grid_values(gearset, f, values, fail)
    else:
        for f, v in first.items():
            check_field(gearset, f, v, f"sample.{f}", fail)
    return SweepSpec(name=name, gearset=gearset, scene=scene, kind=kind, fields=tuple(first), points=tuple(points),
                     description=description, plot=plot, seed=seed, origin=origin)


def _check_name(name: str, fail) -> None:
    """The name is a folder inside the sweeps folder: it must not leave it or hide in it."""
    if len(name) > MAX_NAME_CHARS:
        fail("name", f"at most {MAX_NAME_CHARS} characters (it names the output folder), got {len(name)}")
    if not _NAME_RE.fullmatch(name):
        fail("name", "must be letters, digits, '_', '-' or '.' (it names the output folder; no path "
                     "separators, spaces or control characters)")
    if not name.strip("."):
        fail("name", f"{name!r} is not a folder name (it names the output folder)")


def _text(data: Mapping, key: str, default: str, fail) -> str:
    value = data.get(key, default)
    if not isinstance(value, str) or (key != "description" and not value.strip()):
        fail(key, f"must be a text, got {value!r}")
    return value


def _base_gearset(text: str, base: Path, fail: Callable[[str, str], NoReturn]) -> GearSet:
    from ..gearset import load_gearset, resolve_gearset

    path: str | Path = text  # what the message names if the name does not resolve
    try:
        if looks_like_path(text) and not Path(text).is_absolute():
            path = base / text
            if not path.is_file():
                fail("gearset", f"{path}: no such gear-set file")
        else:
            path = resolve_gearset(text)
        return load_gearset(path)
    except GearSetError as exc:
        from ..output.userpaths import named_file_problem  # another file's keys and values are not shown

        fail("gearset", named_file_problem(exc, path, "gear-set file"))


def flat_table(table, prefix: str, fail, _path: str = "") -> dict:
    """A (possibly nested) TOML table as {dotted path: value}: `a.b = 1` and `"a.b" = 1` alike."""
    if not isinstance(table, Mapping):
        fail(prefix, f"must be a table, got {type(table).__name__}")
    out = {}
    for key, value in table.items():
        path = f"{_path}.{key}" if _path else str(key)
        if isinstance(value, Mapping):
            out.update(flat_table(value, prefix, fail, path))
        else:
            out[path] = value
    return out


# a gear-set problem line that says the value has the wrong type (not that it is out of range)
_TYPE_PROBLEM_RE = re.compile(r": (must be (?:a number|an integer|a string|a table[^,]*), got \w+|must be finite)$")


def _check_grid_values(gearset: GearSet, path: str, values: Sequence, fail) -> None:
    """Each type among a field's grid values is checked once, with the first value of that type."""
    first_of: dict[type, int] = {}
    for i, v in enumerate(values):
        first_of.setdefault(type(v), i)
        if isinstance(v, str) and len(v) > MAX_GRID_TEXT_CHARS:  # a 3 MB text drew its tick label for 100 s
            fail(f"grid.{path}[{i}]", f"a text of {len(v)} characters: at most {MAX_GRID_TEXT_CHARS} (a file name's "
                 "length; the longest gear-set text, tooth.points_file, is 4096)")
    for i in sorted(first_of.values()):
        check_field(gearset, path, values[i], f"grid.{path}[{i}]", fail, field_key=f"grid.{path}")


def check_field(gearset: GearSet, path: str, value, key: str, fail, *, field_key: str | None = None) -> None:
    """A field path the gear set does not have, or a value of the wrong type for the field (a
    text for a number, a boolean, a float for an integer, nan/inf), is a spec error at ``key``;
    a value of the right type out of its range is the point's error (a row)."""
    try:
        gearset.with_values({path: value})
    except GearSetError as exc:
        parts = path.split(".")
        prefixes = tuple(".".join(parts[:i]) + ":" for i in range(1, len(parts) + 1))  # a section or the field
        for line in exc.problems:
            if line.startswith(prefixes) and ("unknown key" in line or "not a field path" in line
                                              or "is not a section" in line):
                fail(field_key or key, f"not a gear-set field ({line})")
        for line in exc.problems:
            m = _TYPE_PROBLEM_RE.search(line)
            if line.startswith(f"{path} =") and m:
                fail(key, m.group(1))


# ----------------------------------------------------------------------------- running


@dataclass(frozen=True, slots=True, eq=False)
class SweepResult:
    """The table of a sweep: one row per point, in index order.

    ``rows``: dicts with ``index``, ``point_id``, the swept fields, :data:`OUTPUT_COLUMNS`
    and :data:`STATUS_COLUMNS` (None for an empty cell); ``computed``: points run by this
    call, ``reused``: points read back from the journal; ``files``: written files.
    """

    spec: SweepSpec
    rows: tuple[dict, ...]
    computed: int
    reused: int
    time_s: float
    files: tuple[Path, ...] = ()

    @property
    def columns(self) -> tuple[str, ...]:
        return ("index", "point_id", *self.spec.fields, *OUTPUT_COLUMNS, *STATUS_COLUMNS)

    @property
    def ok(self) -> int:
        return sum(r["status"] == "ok" for r in self.rows)

    @property
    def failed(self) -> int:
        return len(self.rows) - self.ok

    def column(self, name: str) -> list:
        """One column, in row order."""
        if name not in self.columns:
            raise KeyError(f"{name!r} is not a column (columns: {', '.join(self.columns)})")
        return [r[name] for r in self.rows]

    def to_dict(self) -> dict:
        return {"spec": self.spec.to_dict(), "points": len(self.rows), "ok": self.ok, "failed": self.failed,
                "computed": self.computed, "reused": self.reused, "time_s": self.time_s,
                "files": [str(p) for p in self.files]}

    def plot(self, output: str | None = None, *, ax: Axes | None = None):
        """The output (default: the spec's ``plot``) against each swept field; returns the Axes."""
        return plot_sweep(self, output, ax=ax)


def _run_point(index: int, values: dict, gearset: GearSet, scene: Scene, designer) -> dict:
    """Run one point (in a worker): {column: value} with status; never raises for the point's own errors."""
    from ..pipeline.engine import cached_design  # this process's engine: the stages a nearby point shares are reused

    row: dict[str, Any] = {"index": index}
    t0 = time.perf_counter()
    try:
        gs = gearset.with_values(values)
        result = (designer or cached_design)(gs, scene=scene)
        row.update(outputs_of(result))
        row["time_design_s"] = time.perf_counter() - t0
        row.update(status="ok", error_type=None, error_message=None)
    except Exception as exc:  # any failure of the point is its result (brief: it must not stop the sweep)
        log.info("sweep point %d failed: %s: %s", index, type(exc).__name__, exc)
        row.update({c: None for c in OUTPUT_COLUMNS})
        row["time_design_s"] = time.perf_counter() - t0
        row.update(status="error", error_type=type(exc).__name__, error_message=" ".join(str(exc).split()) or repr(exc))
    return row


_ONE_THREAD = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS")


def init_worker() -> None:
    """Process-pool workers: one BLAS thread each, as Dask's workers have by default (the
    pool is the parallelism; and a BLAS's thread count changes its rounding, so both give
    the same table). The variables cover the libraries loaded later (scipy's own BLAS).

    A worker ignores SIGINT (a Ctrl-C reaches the whole process group: the main process
    decides, and ends the workers) and dies on SIGTERM (the parent's handler, inherited
    through fork, is not the worker's); both were blocked while the pool started."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, _STOP_SIGNALS)
    for name in _ONE_THREAD:
        os.environ[name] = "1"
    from threadpoolctl import threadpool_limits

    from ..profile.arcfit import clear_cache

    threadpool_limits(1)
    clear_cache()  # a forked worker starts without its parent's remembered fits
    # a stage's warning is the point's (its design's warnings, the table's `warnings` column); logged
    # here it reached the terminal with no handler but Python's last resort, a line with no point
    # named — an optimisation printed 136 of them
    logging.getLogger("profilegen").setLevel(logging.ERROR)
    # a worker whose sweep was killed (kill -9: no shutdown) would wait for work forever
    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(1.0)
        os._exit(1)

    threading.Thread(target=watch, name="profilegen-sweep-parent-watch", daemon=True).start()


_STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class SignalInterrupt(KeyboardInterrupt):
    """A signal (SIGTERM by default) arrived in :func:`interrupt_on_signals`: raised in the
    main thread as SIGINT raises :class:`KeyboardInterrupt`, so the same clean-up runs;
    ``signum`` is the signal's number (exit status 128 + signum by convention)."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = int(signum)


@contextlib.contextmanager
def interrupt_on_signals(signals: Sequence[int] = (signal.SIGTERM,)) -> Iterator[None]:
    """Within the block, each of ``signals`` raises :class:`SignalInterrupt` in the main
    thread instead of its default action (for SIGTERM: dying at once, leaving the pool's
    workers to notice within a second). Restores the previous handlers on leaving. A
    signal that is ignored (SIG_IGN) stays ignored; off the main thread this does nothing.
    For the command line; a program that runs sweeps installs its own handlers."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def raise_interrupt(signum, frame):
        raise SignalInterrupt(signum)

    previous = {}
    try:
        for sig in signals:
            if signal.getsignal(sig) is not signal.SIG_IGN:
                previous[sig] = signal.signal(sig, raise_interrupt)
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


@contextlib.contextmanager
def signals_deferred() -> Iterator[None]:
    """SIGINT and SIGTERM blocked in this thread: processes forked and threads started here
    start with them blocked (a pool's workers and its manager thread), and a second Ctrl-C
    does not cut a clean-up short. A signal that came meanwhile is delivered on leaving."""
    masked = hasattr(signal, "pthread_sigmask")
    if masked:
        old_mask = signal.pthread_sigmask(signal.SIG_BLOCK, _STOP_SIGNALS)
    try:
        yield
    finally:
        if masked:
            signal.pthread_sigmask(signal.SIG_SETMASK, old_mask)


@contextlib.contextmanager
def dask_executor(address: str) -> Iterator[Executor]:
    """A :class:`concurrent.futures.Executor` on the Dask cluster at ``address``
    (``tcp://HOST:PORT``): ``distributed.Client(address).get_executor()``; the client is
    closed on leaving. Its workers need profilegen installed."""
    try:
        from distributed import Client
    except ImportError:
        raise SweepError("a Dask cluster needs dask[distributed]: pip install 'profilegen[dask]'") from None
    try:
        client = Client(address, timeout="10s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise SweepError(f"cannot connect to the Dask scheduler at {address}: {exc}") from None
    try:
        yield client.get_executor()
    finally:
        client.close()


def run_sweep(
    spec: SweepSpec,
    out_dir: str | os.PathLike,
    *,
    executor: Executor | None = None,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    designer: Callable[..., Design] | None = None,
    table: str | os.PathLike | None = None,
    figure: bool = True,
    lock_wait_s: float | None = None,
) -> SweepResult:
    """Run every point of ``spec`` not yet in ``out_dir/journal.csv``; write the table.

    ``executor``: where the points run (not shut down here); default a process pool of
    ``workers`` processes (default: the CPU count), closed at the end. ``progress(done,
    total)`` is called with the points already finished and after each point.
    ``designer(gearset, scene=...)``: the design function (default
    :func:`profilegen.pipeline.engine.cached_design`, :func:`profilegen.pipeline.design.design` through each
    worker's stage cache: the same results; it must pickle for a process pool or Dask).
    Writes ``results.csv`` (always), ``sweep.png`` (``figure``), and ``table`` if given
    (CSV, or Parquet when it ends in ``.parquet``: needs pyarrow). Interrupted
    (KeyboardInterrupt, or :class:`SignalInterrupt` within :func:`interrupt_on_signals`),
    it cancels what has not started, ends its own pool's workers at once (the points they
    were running are lost and run again on resuming) and re-raises; the journal keeps every
    finished point. A given executor's futures are cancelled; it is not shut down.

    The folder follows :mod:`profilegen.output.folder`'s rules: it must be absent, empty or a
    sweep's own (its ``.profilegen.json`` marker lists each file; anything else is an
    ExportError naming it, before a point runs); it is locked for the whole run (a second sweep
    into it waits ``lock_wait_s``, default 120 s, then stops with an ExportError — and finding
    the journal complete, computes nothing); the journal is appended in place, and the new
    results.csv and sweep.png arrive with it as one set (a whole-folder swap), so a run killed
    while writing them leaves the old set.
    """
    from ..output import folder

    t0 = time.perf_counter()
    if table is not None and str(table).endswith(".parquet"):
        _require_pyarrow(table)
    if workers is not None and not (_is_int(workers) and workers >= 1):
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    wait = folder.LOCK_WAIT_S if lock_wait_s is None else lock_wait_s
    with folder.owning(out_dir, ours=SWEEP_FILES, marker=folder.MARKER, command="sweep", lock_wait_s=wait) as owned:
        return _run_sweep(spec, Path(out_dir), owned, executor, workers, progress, designer, table, figure, t0)


def _run_sweep(spec: SweepSpec, out: Path, owned, executor, workers, progress, designer, table, figure,
               t0: float) -> SweepResult:
    from ..output import folder

    live = owned.begin([JOURNAL])
    journal = Journal(live / JOURNAL, ("point_id", *spec.fields, *OUTPUT_COLUMNS, *STATUS_COLUMNS))
    wanted = set(spec.ids)
    done: dict[str, dict] = {pid: row for pid, row in journal.read().items() if pid in wanted}
    reused = len(done)
    total = len(spec.points)
    todo: dict[str, int] = {}  # point id → first index with it (equal points run once)
    for i, pid in enumerate(spec.ids):
        if pid not in done and pid not in todo:
            todo[pid] = i
    copies = Counter(spec.ids)  # equal points share an id (and a run)
    finished = sum(copies[pid] for pid in done)
    if progress:
        progress(finished, total)
    log.info("sweep %s: %d points, %d from the journal, %d to run", spec.name, total, finished, len(todo))
    own = executor is None and bool(todo)
    if own:
        from concurrent.futures import ProcessPoolExecutor

        executor = ProcessPoolExecutor(max_workers=workers or os.cpu_count() or 1, initializer=init_worker)
    futures = {}
    try:
        with signals_deferred():  # the pool's processes start with SIGINT/SIGTERM blocked (see init_worker)
            for pid, i in todo.items():
                futures[executor.submit(_run_point, i, spec.points[i], spec.gearset, spec.scene, designer)] = pid
        for fut in as_completed(futures):
            pid = futures[fut]
            try:
                row = fut.result()
            except Exception as exc:  # the executor failed, not the point: stop, the journal keeps the rest
                raise SweepError(f"sweep {spec.name}: the executor failed on point {todo[pid]} "
                                 f"({type(exc).__name__}: {exc}); run the sweep again to resume") from exc
            cells = {"point_id": pid, **{f: spec.points[todo[pid]][f] for f in spec.fields},
                     **{c: row.get(c) for c in (*OUTPUT_COLUMNS, *STATUS_COLUMNS)}}
            journal.append(cells)
            done[pid] = journal.parse(journal.encode_cells(cells))
            finished += copies[pid]
            if progress:
                progress(finished, total)
        if own:
            executor.shutdown(wait=True)
    except BaseException:
        if own:
            with signals_deferred():
                stop_pool(executor, what="sweep")
        else:
            for fut in futures:
                fut.cancel()
        raise
    rows = tuple(_table_row(i, pid, spec, done[pid]) for i, pid in enumerate(spec.ids))
    result = SweepResult(spec, rows, len(todo), reused, 0.0)
    names = ["results.csv", *(["sweep.png"] if figure else [])]
    with owned.stage(keep=(JOURNAL,)) as staging:  # the new set and the journal, swapped in as one
        write_table(rows, _columns(spec), staging / "results.csv")
        if figure:
            plot_sweep(result, path=staging / "sweep.png")
        folder.write_marker(staging, "sweep", [*names, JOURNAL])
    files = [out / n for n in names]
    if table is not None:
        files.insert(1, write_table(rows, _columns(spec), table))
    return SweepResult(spec, rows, len(todo), reused, time.perf_counter() - t0, tuple(files))


def _columns(spec: SweepSpec) -> tuple[str, ...]:
    return ("index", "point_id", *spec.fields, *OUTPUT_COLUMNS, *STATUS_COLUMNS)


def _table_row(index: int, pid: str, spec: SweepSpec, cells: Mapping[str, str]) -> dict:
    """A result row from journal cells (text): inputs from the spec, outputs typed."""
    row: dict[str, Any] = {"index": index, "point_id": pid, **spec.points[index]}
    for c in OUTPUT_COLUMNS:
        row[c] = _parse_cell(cells.get(c, ""), _TYPES[c])
    for c in STATUS_COLUMNS:
        row[c] = cells.get(c) or None
    return row


def _cell(value) -> str:
    """A value as journal/CSV text: '' for None, shortest round-trip repr for floats."""
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    return str(value)


def _parse_cell(text: str, kind: type):
    if text == "":
        return None
    if kind is bool:
        return text == "true"
    return kind(text)


# ----------------------------------------------------------------------------- the journal


class Journal:
    """An append-only CSV of finished points, one complete line each.

    Each line is written by one ``write`` on a file opened for appending and ends with a
    CRC of its cells, so a line cut short by a kill is recognised (and dropped) when the
    journal is read back. A journal with another header (another spec, another version's
    outputs) is rewritten, atomically, with this header and the rows it had.
    """

    def __init__(self, path: Path, columns: Sequence[str]):
        self.path = path
        self.columns = tuple(columns)
        self.header = self.columns + ("crc",)

    def encode_cells(self, cells: Mapping[str, Any]) -> list[str]:
        texts = [_cell(cells.get(c)) for c in self.columns]
        return texts + [f"{zlib.crc32(chr(31).join(texts).encode()):08x}"]

    @staticmethod
    def _line(texts: Sequence[str]) -> str:
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerow(texts)
        return buf.getvalue()

    def parse(self, texts: Sequence[str]) -> dict[str, str]:
        return dict(zip(self.columns, texts))

    def read(self) -> dict[str, dict[str, str]]:
        """{point id: cells} of the complete lines; repairs a cut last line and an old header."""
        try:
            raw = _read_nofollow(self.path)
        except FileNotFoundError:
            return {}
        except OSError as exc:
            raise ExportError(f"cannot read the sweep journal {self.path}: {_why(exc)}") from exc
        cut = not raw.endswith(b"\n")
        text = raw.decode("utf-8", errors="replace")
        records = list(csv.reader(io.StringIO(text)))
        if not records:
            return {}
        header, body = tuple(records[0]), records[1:]
        rows: dict[str, dict[str, str]] = {}
        bad = 0
        for rec in body:
            if len(rec) != len(header) or header[-1:] != ("crc",):
                bad += 1
                continue
            texts = rec[:-1]
            if f"{zlib.crc32(chr(31).join(texts).encode()):08x}" != rec[-1]:
                bad += 1
                continue
            cells = dict(zip(header[:-1], texts))
            if "point_id" in cells:
                rows[cells["point_id"]] = cells
        if bad:
            log.warning("sweep journal %s: %d incomplete or damaged line(s) dropped", self.path, bad)
        if header != self.header or bad or cut:
            self._rewrite(rows)
        return {pid: {c: cells.get(c, "") for c in self.columns} for pid, cells in rows.items()}

    def _rewrite(self, rows: Mapping[str, Mapping[str, str]]) -> None:
        from ..output.export import atomic_write

        with atomic_write(self.path) as f:
            f.write(self._line(self.header))
            for cells in rows.values():
                f.write(self._line(self.encode_cells({c: cells.get(c, "") for c in self.columns})))

    def append(self, cells: Mapping[str, Any]) -> None:
        try:
            if not os.path.lexists(self.path):
                self._rewrite({})
            data = self._line(self.encode_cells(cells)).encode()
            fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | _O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0))
            try:
                if not stat.S_ISREG(os.fstat(fd).st_mode):
                    raise OSError(errno.EINVAL, "not a regular file")
                written = os.write(fd, data)
            finally:
                os.close(fd)
        except OSError as exc:
            raise ExportError(f"cannot write the sweep journal {self.path}: {_why(exc)}") from exc
        if written != len(data):
            raise ExportError(f"cannot write the sweep journal {self.path}: short write ({written} of {len(data)} bytes)")


_O_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)


def _why(exc: OSError) -> str:
    if exc.errno == errno.ELOOP:
        return "it is a symbolic link (a journal is never one; remove the link)"
    return exc.strerror or str(exc)


def _read_nofollow(path: Path) -> bytes:
    """A regular file's bytes, never through a link (ELOOP)."""
    fd = os.open(path, os.O_RDONLY | _O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0))
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise OSError(errno.EINVAL, "not a regular file", os.fspath(path))
        with os.fdopen(fd, "rb", closefd=False) as f:
            return f.read()
    finally:
        os.close(fd)


# ----------------------------------------------------------------------------- files


def _require_pyarrow(path) -> None:
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        raise SweepError(f"{path}: writing Parquet needs pyarrow (pip install pyarrow); without it, "
                         "give an output folder: results.csv is always written there") from None


def write_table(rows: Sequence[Mapping], columns: Sequence[str], path: str | os.PathLike) -> Path:
    """Write rows as CSV, or as Parquet when ``path`` ends in ``.parquet`` (needs pyarrow);
    atomically. Empty cells are empty in the CSV, nulls in Parquet."""
    from ..output.export import atomic_write

    path = Path(path)
    if path.suffix == ".parquet":
        _require_pyarrow(path)
        import pyarrow as pa
        import pyarrow.parquet as pq

        tbl = pa.table({c: [r.get(c) for r in rows] for c in columns})
        with atomic_write(path, "wb") as f:
            pq.write_table(tbl, f)
        return path
    with atomic_write(path) as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow([csv_text(c) for c in columns])
        for r in rows:
            w.writerow([csv_text(r.get(c)) for c in columns])
    return path


_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")
_NUMBER_RE = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")


def csv_text(value) -> str:
    """A value as a CSV cell a spreadsheet shows as written: a text that starts with ``=``,
    ``+``, ``-``, ``@``, a tab or a carriage return (a formula to Excel, LibreOffice and Google
    Sheets: ``=HYPERLINK(...)``) gets a leading ``'``, which they show as text; numbers (also
    negative ones, and a text that is a plain number) are written unchanged."""
    text = _cell(value)
    if text.startswith(_FORMULA_START) and not (isinstance(value, (int, float, np.number))
                                                 or _NUMBER_RE.fullmatch(text)):
        return "'" + text
    return text


def plot_sweep(result: SweepResult, output: str | None = None, *, ax: Axes | None = None,
               path: str | os.PathLike | None = None):
    """``output`` (default the spec's ``plot``) against each swept field, one panel per
    field; failed points as red crosses on the axis. Returns the Axes of the first panel,
    or the path written when ``path`` is given (PNG, atomically). The figure is drawn by
    :func:`profilegen.output.plot.sweep_figure`."""
    spec = result.spec
    output = output or spec.plot
    if output not in OUTPUT_COLUMNS:
        raise ValueError(f"output must be an output column ({', '.join(OUTPUT_COLUMNS)}), got {output!r}")
    from ..output.plot import sweep_figure

    title = f"sweep {spec.name}: {spec.kind}, {len(result.rows)} points, scene {spec.scene.name}"
    return sweep_figure(result.rows, spec.fields, output, title=title, ax=ax, path=path)
