"""What a design costs and what it can resolve, checked before any stage runs (:func:`preflight`).

:func:`check_resolution` refuses a module below :data:`MODULE_MIN_MM` and a scene whose chord
tolerance is coarse for the module (over :data:`CHORD_PER_MODULE_MAX` of it), naming
``gear.module_mm`` and ``chord_tol_mm`` with the values that work.

:func:`check_budget` estimates the largest arrays each stage will hold from the numbers that
size them — the envelope's tracing grid ``n_t × n_phi``, the envelope's point count (from the
scene's ``chord_tol_mm`` and the module, at the worst case's chord: :func:`worst_chord`), the CS outline (that count times the circular spline's
teeth), the clearance map's ``clearance_samples`` and the fitted profile's
``fit_check_positions`` (each pose against every point of the FS tooth's surface) — and raises a
:class:`BudgetError` naming the scene key or gear-set field to lower, and the value that fits,
when one of them is over the budget. :func:`profilegen.design` calls both first, so ``sweep`` and
``optimize`` (which run ``design``) refuse such a point the same way, before allocating anything.

The budget is half the memory the machine has available now (``MemAvailable`` of
``/proc/meminfo``, else ``os.sysconf``), and at most half a finite address-space limit
(``ulimit -v``). The environment variable ``PROFILEGEN_MEMORY_BUDGET`` sets it: a size such as
``8G``, ``500M`` or a number of bytes, or ``none`` for no check.

The per-item costs are measured on the default gear set (``tests/benchmarks/range_extremes.py``
runs every documented range's extreme under a 4 GB cap): the tracing grid ~42 bytes a cell
(``n_t = 100000``, ``n_phi = 241``: 1.16 GB peak against 0.16 GB at ``n_t = 8``), the clearance
map's pose × surface-point pairs ~8 bytes in each of several arrays (``clearance_samples =
100000`` on 2 004 surface points asked for 1.49 GiB arrays after 2.5 GB). The estimates
round up (48 and 40 bytes): a design the check passes may use somewhat less, never the 10-100×
more that the refused extremes would.

>>> from profilegen.gearset import load_gearset, default_gearset_path
>>> from profilegen.pipeline.scenes import SCENES
>>> import dataclasses
>>> gs = load_gearset(default_gearset_path())
>>> estimate(gs, SCENES["design"]).largest().bytes < 1e9
True
>>> check_budget(gs, dataclasses.replace(SCENES["sketch"], n_t=100_000, n_phi=100_000), budget=4 * 2**30)  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
profilegen.pipeline.budget.BudgetError: scene 'sketch': n_t × n_phi = 100000 × 100000 would need ~480 GB in the envelope ...: lower n_phi to at most 894 (with n_t = 100000), or n_t to at most 894 (with n_phi = 100000); ...
"""

from __future__ import annotations

import math
import os
import resource
from dataclasses import dataclass
from typing import cast

from ..errors import GearSetError
from ..gearset.reader import MODULE_MIN_MM  # the gear-set range's lower bound on the module

__all__ = ["BUDGET_ENV", "CHORD_PER_MODULE_MAX", "MODULE_MIN_MM", "BudgetError", "Cost", "Estimate", "ResolutionError",
           "budget_bytes", "check_budget", "check_resolution", "estimate", "preflight", "worst_chord"]

BUDGET_ENV = "PROFILEGEN_MEMORY_BUDGET"
"""Environment variable overriding the memory budget: ``8G``, ``500M``, bytes, or ``none``."""

GRID_BYTES_PER_CELL = 48
"""The envelope's tracing grid, bytes per (t, φ) cell: the meshing function, contourpy's arrays."""
POSE_BYTES_PER_PAIR = 40
"""The clearance map and the fit check, bytes per (pose, FS surface point) pair."""
ENVELOPE_POINTS_PER_SQRT = 10.0
"""Envelope points ≈ this × √(m / chord_tol_mm) + :data:`ENVELOPE_POINTS_FLOOR` (sag ∝ h²·κ, the
flank's length ∝ m, its curvature ∝ 1/m); the default set traced 6 493 points at chord 1e-6 mm."""
ENVELOPE_POINTS_FLOOR = 2000
ENVELOPE_BYTES_PER_POINT = 500
"""The traced envelope and its classification, bytes per point (both flanks, the pieces, the tip paths)."""
OUTLINE_POINTS_PER_ENVELOPE_POINT = 0.25
"""The CS outline keeps ~1/5 of a tooth space's envelope points, for every tooth space of the
circular spline (the default set, 202 teeth: 255 530 outline points at 6 493 envelope points,
chord 1e-6 mm; 8 401 786 at 195 727, chord 1e-9 mm)."""
OUTLINE_BYTES_PER_POINT = 48
"""The CS outline's polygon, its KD-tree and distance arrays, bytes per point (the default set at
chord 1e-9 mm: 0.39 GB peak, 0.11 GB at 1e-4 mm, for 8.4 M outline points: ~33 bytes a point)."""
SURFACE_POINTS_PER_MM = 800
"""The clearance map's candidate search runs over the FS surface sampled this densely (gearform)."""


CHORD_PER_MODULE_MAX = 0.01
"""The coarsest envelope the arc fit takes: chord_tol_mm at most this × gear.module_mm. Measured on the
default set scaled in module (sharp corners): 0.001-0.014 fit (m = 0.5, 0.01, 1e-3 ... 1e-5 mm);
0.02 (m = 0.5 mm, chord 0.01) and 0.1 (m = 0.001 mm in the sketch scene) fail in the one-sided fit."""


class BudgetError(GearSetError):
    """A scene or gear set would need more memory than the budget; names the key and the value that fits."""


class ResolutionError(GearSetError):
    """A scene's chord is too coarse for the gear set's module (or the module below what the arc fit
    resolves); names ``gear.module_mm`` and ``chord_tol_mm`` with the values that work."""


@dataclass(frozen=True, slots=True)
class Cost:
    """One item's estimated peak memory and what sizes it."""

    what: str  # the stage's array
    bytes: float
    fields: tuple[str, ...]  # the scene keys / gear-set fields that size it


@dataclass(frozen=True, slots=True)
class Estimate:
    """Every item's :class:`Cost`; the stages run one after another, so the peak is the largest."""

    costs: tuple[Cost, ...]

    def largest(self) -> Cost:
        return max(self.costs, key=lambda c: c.bytes)


def budget_bytes() -> float | None:
    """The memory budget in bytes (None: no check): ``PROFILEGEN_MEMORY_BUDGET``, else half the
    available memory, at most half a finite address-space limit."""
    text = os.environ.get(BUDGET_ENV, "").strip()
    if text:
        return _parse_size(text)
    avail = _available_bytes()
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft not in (resource.RLIM_INFINITY, -1) and soft > 0:
        avail = soft if avail is None else min(avail, soft)
    return None if avail is None else 0.5 * avail


def _parse_size(text: str) -> float | None:
    if text.lower() in ("none", "off", "0"):
        return None
    scale = {"k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}
    body, unit = (text[:-1], text[-1].lower()) if text[-1].lower() in scale else (text, "")
    body = body.strip().removesuffix("i") if unit else body
    try:
        value = float(body) * scale.get(unit, 1)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value <= 0:
        raise BudgetError(f"{BUDGET_ENV} = {text[:40]!r}: must be a size such as 8G, 500M or a number of bytes, "
                          "or none")
    return value


def _available_bytes() -> float | None:
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None


def envelope_points(module_mm: float, chord_tol_mm: float) -> float:
    """Estimated points of one tooth space's traced envelope (see :data:`ENVELOPE_POINTS_PER_SQRT`)."""
    return ENVELOPE_POINTS_PER_SQRT * math.sqrt(module_mm / chord_tol_mm) + ENVELOPE_POINTS_FLOOR


def worst_chord(chord_tol_mm: float) -> float:
    """The finest chord the envelope may be traced at for a scene's ``chord_tol_mm``:
    :func:`profilegen.pipeline.design.traced_form` retraces a trace that missed a grazing crossing at a
    chord ``RETRACE_FACTOR`` finer, up to ``RETRACES`` times, so chord / 4² = chord / 16 (4× the
    points, points ∝ chord^-1/2). The envelope and the CS outline are estimated there: the retrace
    is rare, but a run the check passed must not then take the machine when it happens."""
    from ..profile.gearform import RETRACE_FACTOR, RETRACES

    return chord_tol_mm / RETRACE_FACTOR**RETRACES


def _surface_points(gearset) -> int:
    """Points of the FS tooth's surface as the clearance map samples it (0 if the tooth cannot be built:
    the stage that builds it names the problem)."""
    from ..geometry.teeth import tooth_from_gearset

    try:
        return len(tooth_from_gearset(gearset).surface(n_per_mm=SURFACE_POINTS_PER_MM))
    except Exception:  # noqa: BLE001 — a tooth that cannot be built is the tooth stage's error to name
        return 0


def estimate(gearset, scene) -> Estimate:
    """The estimated peak memory of each stage's largest arrays for ``gearset`` in ``scene``."""
    m = gearset.gear.module_mm
    z2 = gearset.gear.circular_spline_teeth
    env = envelope_points(m, worst_chord(scene.chord_tol_mm))
    surface = _surface_points(gearset)
    costs = [
        Cost("the envelope stage's tracing grid", GRID_BYTES_PER_CELL * scene.n_t * scene.n_phi, ("n_t", "n_phi")),
        Cost("the traced envelope", ENVELOPE_BYTES_PER_POINT * env, ("chord_tol_mm",)),
        Cost("the circular spline's outline", OUTLINE_BYTES_PER_POINT * OUTLINE_POINTS_PER_ENVELOPE_POINT * env * z2,
             ("chord_tol_mm", "gear.circular_spline_teeth")),
        Cost("the clearance map", POSE_BYTES_PER_PAIR * scene.clearance_samples * surface, ("clearance_samples",)),
        Cost("the fitted profile's check", POSE_BYTES_PER_PAIR * scene.fit_check_positions * surface,
             ("fit_check_positions",)),
    ]
    return Estimate(tuple(costs))


def preflight(gearset, scene) -> Estimate:
    """Everything :func:`profilegen.design` refuses about the pair before any stage runs:
    :func:`check_resolution`, then :func:`check_budget`. Returns the memory estimate."""
    check_resolution(gearset, scene)
    return check_budget(gearset, scene)


def check_resolution(gearset, scene) -> None:
    """Raise a :class:`ResolutionError` if the module is below :data:`MODULE_MIN_MM` or the scene's
    chord tolerance over :data:`CHORD_PER_MODULE_MAX` × the module."""
    m = gearset.gear.module_mm
    if m < MODULE_MIN_MM:
        raise ResolutionError(f"gear.module_mm = {m:g} mm: below {MODULE_MIN_MM:g} mm, the smallest module the arc fit "
                              f"resolves: raise gear.module_mm to at least {MODULE_MIN_MM:g}")
    tol = scene.chord_tol_mm
    if tol > CHORD_PER_MODULE_MAX * m:
        raise ResolutionError(
            f"gear.module_mm = {m:g} mm with chord_tol_mm = {tol:g} mm (scene {scene.name!r}): the envelope's chord "
            f"error would be {100 * tol / m:.3g} % of the module, more than the {100 * CHORD_PER_MODULE_MAX:g} % the arc "
            f"fit resolves: "
            f"lower chord_tol_mm to at most {CHORD_PER_MODULE_MAX * m:.3g} (a finer scene: design or verify), or raise "
            f"gear.module_mm to at least {tol / CHORD_PER_MODULE_MAX:.3g}")


def check_budget(gearset, scene, *, budget: float | None | str = "auto") -> Estimate:
    """Raise a :class:`BudgetError` if an item of :func:`estimate` is over ``budget`` bytes
    (``"auto"``: :func:`budget_bytes`; None: no limit); returns the estimate."""
    est = estimate(gearset, scene)
    limit = budget_bytes() if budget == "auto" else cast("float | None", budget)
    if limit is None:
        return est
    over = [c for c in est.costs if c.bytes > limit]
    if over:
        worst = max(over, key=lambda c: c.bytes / limit)
        raise BudgetError(_message(worst, gearset, scene, limit))
    return est


def _size(n: float) -> str:
    return f"{n / 1e9:.3g} GB" if n >= 1e8 else f"{n / 1e6:.3g} MB"


def _message(cost: Cost, gearset, scene, limit: float) -> str:
    where = f"scene {scene.name!r}"
    tail = f"{BUDGET_ENV} sets the budget (now {_binary(limit)})"
    over = f"would need ~{_size(cost.bytes)} in {cost.what}, over the memory budget of {_size(limit)}"
    if cost.fields == ("n_t", "n_phi"):
        cells = limit / GRID_BYTES_PER_CELL
        return (f"{where}: n_t × n_phi = {scene.n_t} × {scene.n_phi} {over}: lower n_phi to at most "
                f"{int(cells // scene.n_t)} (with n_t = {scene.n_t}), or n_t to at most {int(cells // scene.n_phi)} "
                f"(with n_phi = {scene.n_phi}); {tail}")
    m = gearset.gear.module_mm
    if cost.fields[0] == "chord_tol_mm":
        z2 = gearset.gear.circular_spline_teeth
        per_point = ENVELOPE_BYTES_PER_POINT + (OUTLINE_BYTES_PER_POINT * OUTLINE_POINTS_PER_ENVELOPE_POINT * z2
                                                if len(cost.fields) > 1 else 0)
        points = max(limit / per_point - ENVELOPE_POINTS_FLOOR, 1.0)
        tol = m * (ENVELOPE_POINTS_PER_SQRT / points) ** 2 * (scene.chord_tol_mm / worst_chord(scene.chord_tol_mm))
        return (f"{where}: chord_tol_mm = {scene.chord_tol_mm:g} {over} "
                f"(~{envelope_points(m, worst_chord(scene.chord_tol_mm)):.3g} envelope points at module {m:g} mm"
                f"{f', {z2} CS teeth' if len(cost.fields) > 1 else ''}, if the envelope is retraced at "
                f"{worst_chord(scene.chord_tol_mm):.3g} mm): raise "
                f"chord_tol_mm to at least {_round_up(tol):g}; {tail}")
    key = cost.fields[0]
    value = getattr(scene, key)
    most = int(value * limit / cost.bytes)
    return f"{where}: {key} = {value} {over}: lower {key} to at most {most}; {tail}"


def _round_up(x: float) -> float:
    """``x`` rounded up to two significant digits (a tolerance that surely fits)."""
    if x <= 0 or not math.isfinite(x):
        return x
    e = math.floor(math.log10(x)) - 1
    return math.ceil(x / 10**e) * 10**e


def _binary(n: float) -> str:
    return f"{n / 2**30:.3g} GiB" if n >= 2**28 else f"{n / 2**20:.3g} MiB"
