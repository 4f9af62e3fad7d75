"""Evaluating candidates: one design per candidate on an Executor, with a resumable journal.

The machinery is :mod:`profilegen.studies.sweep`'s, reused: its process-pool worker set-up
(``init_worker``: one BLAS thread, SIGINT ignored, a watch on the parent), its Dask
executor (:func:`profilegen.studies.sweep.dask_executor`), its append-only CSV journal (one
complete line per finished candidate, a CRC per line, a cut line dropped on reading) and
its pool clean-up (:func:`profilegen.pools.stop_pool`). A candidate is a {name: value}
mapping; its id is a hash of the values and of the *context* (for a design: the base gear
set and the scene, :func:`profilegen.studies.sweep.point_id`), so a candidate asked for again — in
a later generation, or by a run resumed after an interruption — is read back from the
journal, not recomputed.

An *evaluator* is a picklable function ``evaluator(values, context) -> {output: number}``;
:func:`evaluate_design` is the one for gear sets (``context = (gearset, scene)``); the tests
run the machinery on an analytic one with a known Pareto front (ZDT1). An
evaluator that raises makes the candidate a row with ``status = "error"`` and the error's
type and message kept; the run goes on.
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Executor, as_completed
from pathlib import Path
from typing import Any

from ..sweep import OUTPUTS, SweepError, Journal, signals_deferred, outputs_of

__all__ = [
    "CONTACT_OUTPUTS",
    "DESIGN_OUTPUTS",
    "SAFETY_CHECKS",
    "STATUS_COLUMNS",
    "VERDICT_COLUMNS",
    "context_key",
    "evaluate_design",
    "evaluate_points",
    "journal_columns",
]

log = logging.getLogger(__name__)

#: the stress checks of :mod:`profilegen.stress` (their safety factors are outputs ``safety_<name>``)
SAFETY_CHECKS = ("tooth ring yield", "cup bottom yield", "tooth ring fatigue", "cup bottom fatigue",
                 "diaphragm fatigue")


def _safety_column(check: str) -> str:
    return "safety_" + check.replace(" ", "_")


#: the numeric outputs of a design an objective or constraint may name: the sweep's headline
#: outputs (numbers only, no stage times) and each stress check's safety factor
DESIGN_OUTPUTS: tuple[str, ...] = (
    *(c for c, kind, _ in OUTPUTS if kind in (float, int) and not c.startswith("time_")),
    *(_safety_column(c) for c in SAFETY_CHECKS),
)
#: outputs only a scene with the loaded contact computes
CONTACT_OUTPUTS = tuple(c for c in DESIGN_OUTPUTS if c.startswith("contact_"))
#: the design's verdict (PASS / FAIL / INCOMPLETE) and its failed checks: text, kept with the status
VERDICT_COLUMNS = ("verdict", "failed_checks")
STATUS_COLUMNS = ("status", "error_type", "error_message", "time_s", *VERDICT_COLUMNS)
_TEXT_COLUMNS = ("status", "error_type", "error_message", *VERDICT_COLUMNS)


def evaluate_design(values: Mapping[str, Any], context) -> dict[str, float | None]:
    """The :data:`DESIGN_OUTPUTS` of the base gear set with ``values`` (field path → value),
    designed in the scene: ``context = (gearset, scene)``. A value the gear set refuses
    raises its :class:`~profilegen.errors.GearSetError`, a stage that fails its own error."""
    from ...pipeline.engine import cached_design  # this process's stage cache: a nearby candidate's stages are reused

    gearset, scene = context
    result = cached_design(gearset.with_values(dict(values)), scene=scene)
    out = outputs_of(result)
    row = {c: out.get(c) for c in DESIGN_OUTPUTS if c in out}
    row.update({c: out.get(c) for c in VERDICT_COLUMNS})  # the design's own verdict (text)
    safety = result.stress.headline()["safety"] if result.stress is not None else {}
    for check in SAFETY_CHECKS:
        v = safety.get(check)
        row[_safety_column(check)] = None if v is None or not math.isfinite(float(v)) else float(v)
    return row


def context_key(evaluator: Callable, context) -> str:
    """A stable key of an evaluator and its context (the part of a candidate's id that is not
    its values): for :func:`evaluate_design` the sweep's hash of the gear set and scene."""
    name = f"{evaluator.__module__}.{evaluator.__qualname__}"
    if evaluator is evaluate_design:
        from ..sweep import point_id

        gearset, scene = context
        return f"{name}:{point_id({}, scene, gearset)}"
    return f"{name}:{json.dumps(context, sort_keys=True, default=str)}"


def _candidate_id(key: str, values: Mapping[str, Any]) -> str:
    text = key + "\n" + json.dumps(dict(values), sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def journal_columns(variables: Sequence[str], outputs: Sequence[str]) -> tuple[str, ...]:
    return ("point_id", *variables, *outputs, *STATUS_COLUMNS)


def _run_candidate(values: dict, evaluator: Callable, context, outputs: tuple[str, ...]) -> dict:
    """One candidate (in a worker): {output: value} and status; never raises for the candidate's own errors."""
    t0 = time.perf_counter()
    row: dict[str, Any] = dict.fromkeys(outputs)
    try:
        got = evaluator(values, context)
        for c in outputs:
            v = got.get(c)
            row[c] = None if v is None or not math.isfinite(float(v)) else float(v)
        row.update(status="ok", error_type=None, error_message=None)
        row.update({c: None if got.get(c) is None else str(got.get(c)) for c in VERDICT_COLUMNS})
    except Exception as exc:  # the candidate's failure is its result: infeasible, with its reason
        log.info("candidate %s failed: %s: %s", values, type(exc).__name__, exc)
        row.update(status="error", error_type=type(exc).__name__,
                   error_message=" ".join(str(exc).split()) or repr(exc), **dict.fromkeys(VERDICT_COLUMNS))
    row["time_s"] = time.perf_counter() - t0
    return row


def _parse(text: str, column: str):
    if column in _TEXT_COLUMNS:
        return text or None
    return float(text) if text != "" else None


def evaluate_points(points: Sequence[Mapping[str, Any]], *, variables: Sequence[str], outputs: Sequence[str],
                    evaluator: Callable, context, journal: str | Path, executor: Executor,
                    on_done: Callable[[bool], None] | None = None) -> tuple[list[dict], int]:
    """Evaluate ``points`` on ``executor``; returns (one row per point, in order; how many ran).

    Points already in the ``journal`` file (same id) are read back; each finished point is
    appended to it at once. A row has ``point_id``, the variables, ``outputs`` (None when
    missing), ``status`` (``ok``/``error``), ``error_type``, ``error_message``, ``time_s``.
    ``on_done(computed)`` is called once per distinct point (False: from the journal).
    The executor is not shut down; on an interruption its futures are cancelled and the
    exception re-raised (the journal keeps what finished).
    """
    outputs = tuple(outputs)
    key = context_key(evaluator, context)
    ids = [_candidate_id(key, p) for p in points]
    jr = Journal(Path(journal), journal_columns(variables, outputs))
    wanted = set(ids)
    done = {pid: cells for pid, cells in jr.read().items() if pid in wanted}
    todo: dict[str, int] = {}
    for i, pid in enumerate(ids):
        if pid not in done and pid not in todo:
            todo[pid] = i
    if on_done:
        for _ in done:
            on_done(False)
    futures = {}
    try:
        with signals_deferred():  # a pool's processes started here begin with SIGINT/SIGTERM blocked
            for pid, i in todo.items():
                futures[executor.submit(_run_candidate, dict(points[i]), evaluator, context, outputs)] = pid
        for fut in as_completed(futures):
            pid = futures[fut]
            try:
                row = fut.result()
            except Exception as exc:  # the executor failed, not the candidate
                raise SweepError(f"the executor failed on candidate {dict(points[todo[pid]])} "
                                 f"({type(exc).__name__}: {exc}); run again to resume from the journal") from exc
            cells = {"point_id": pid, **dict(points[todo[pid]]), **row}
            jr.append(cells)
            done[pid] = jr.parse(jr.encode_cells(cells))
            if on_done:
                on_done(True)
    except BaseException:
        for fut in futures:
            fut.cancel()
        raise
    rows = []
    for i, pid in enumerate(ids):
        cells = done[pid]
        row = {"point_id": pid, **dict(points[i])}
        for c in (*outputs, *STATUS_COLUMNS):
            row[c] = _parse(cells.get(c, ""), c)
        rows.append(row)
    return rows, len(todo)
