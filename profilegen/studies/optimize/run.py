"""An optimisation run from a spec: search in the cheap scene, confirm the front in the fine
one, write the front table, figure, gear sets and report.

Files in the output folder (default ``export/optimize/<name>/``):

* ``journal.csv``, ``confirm_journal.csv``: every finished candidate, appended as it
  finishes (the resumable journals; a run started again reads them back);
* ``evaluations.csv``: every candidate of the search (variables, outputs, status,
  ``feasible``, ``reason`` — a failed design's error type and message);
* ``front.csv``: the Pareto front — variables, objectives and constraints in the search
  scene and (``confirm_*``) in the confirm scene, status, whether each dominates the
  starting design, its gear-set file; the first row is the starting design;
* ``front.png``, ``report.html``, ``summary.json``;
* ``designs/<name>_pareto_NN.toml``: one gear set per front design; ``profilegen design``
  on it runs the confirm scene and gives the ``confirm_*`` values; its ``name`` is the spec's
  name made a gear-set name (lower case, other characters ``_``), its header comment one line
  per item (control characters shown as ``?``), so ``profilegen check`` accepts it;
* ``.profilegen.json``: the marker (which files the run wrote).

The folder follows :mod:`profilegen.output.folder`'s rules: absent, empty or an optimize run's
own (anything else is an ExportError naming it, before a design runs); locked for the run; the
journals are appended in place, and the other files arrive together in one whole-folder swap
(a run killed while writing them leaves the old set; a smaller front leaves no older
``*_pareto_NN.toml``).
"""

from __future__ import annotations

import json
import logging
import os
import re
import time
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...pools import stop_pool
from ..sweep import init_worker, signals_deferred, write_table
from .evaluate import DESIGN_OUTPUTS, STATUS_COLUMNS, VERDICT_COLUMNS, evaluate_design, evaluate_points
from .search import Problem, SearchResult, dominates, judge, rank_disagreement, search
from .spec import OptimizeSpec, load_optimize_spec

__all__ = ["OptimizeResult", "optimize", "problem_of"]

log = logging.getLogger(__name__)

JOURNALS = ("journal.csv", "confirm_journal.csv")
#: every file an optimisation writes into its folder, and the front designs' names (a pattern)
OPTIMIZE_FILES = frozenset({*JOURNALS, "evaluations.csv", "front.csv", "front.png", "report.html", "summary.json",
                            ".profilegen.json"})
DESIGN_PATTERN = r"designs/[A-Za-z0-9_.-]+_pareto_[0-9]{2,}\.toml"


@dataclass(frozen=True, slots=True, eq=False)
class OptimizeResult:
    """A finished run: the search (every candidate, the front), the front rows written to
    ``front.csv`` (search and ``confirm_*`` values), the starting design's row, the summary
    (counts, the cheap scene's disagreement with the confirm scene) and the files."""

    spec: OptimizeSpec
    search: SearchResult
    front: tuple[dict, ...]
    start: dict
    summary: dict
    files: tuple[Path, ...]
    time_s: float

    @property
    def dominating(self) -> tuple[dict, ...]:
        """The front designs that dominate the starting design (confirmed when confirmed)."""
        return tuple(r for r in self.front if r.get("dominates_start"))

    def to_dict(self) -> dict:
        return {**self.summary, "files": [str(p) for p in self.files], "time_s": self.time_s}


def problem_of(spec: OptimizeSpec, scene=None) -> Problem:
    """The search problem of a spec: designs of the base gear set in ``scene`` (default the spec's)."""
    return Problem(spec.variables, spec.objectives, spec.constraints, evaluate_design,
                   (spec.gearset, scene or spec.scene), DESIGN_OUTPUTS)


def optimize(spec: OptimizeSpec | str | os.PathLike, out_dir: str | os.PathLike | None = None, *,
             executor: Executor | None = None, workers: int | None = None,
             progress: Callable[[int, int], None] | None = None, figure: bool = True,
             lock_wait_s: float | None = None) -> OptimizeResult:
    """Run the optimisation of ``spec`` (an :class:`OptimizeSpec` or a spec file).

    ``executor``: where designs run (not shut down here), default a process pool of
    ``workers`` processes (the CPU count) closed at the end; a Dask cluster through
    :func:`profilegen.studies.sweep.dask_executor`. ``progress(done, total)`` after each design
    (the total grows by the front's size when the confirm step starts). Interrupted, it
    ends its own pool's workers and re-raises; run it again to resume from the journals.
    """
    t0 = time.perf_counter()
    if not isinstance(spec, OptimizeSpec):
        spec = load_optimize_spec(spec)
    if workers is not None and not (isinstance(workers, int) and not isinstance(workers, bool) and workers >= 1):
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    out = Path(out_dir) if out_dir is not None else Path("export") / "optimize" / spec.name
    from ...output import folder

    with folder.owning(out, ours=OPTIMIZE_FILES, patterns=(DESIGN_PATTERN,), marker=folder.MARKER,
                       command="optimize", lock_wait_s=folder.LOCK_WAIT_S if lock_wait_s is None else lock_wait_s) as owned:
        owned.begin(JOURNALS if spec.confirm_scene is not None else JOURNALS[:1])
        own = executor is None
        if own:
            from concurrent.futures import ProcessPoolExecutor

            with signals_deferred():
                executor = ProcessPoolExecutor(max_workers=workers or os.cpu_count() or 1, initializer=init_worker)
        assert executor is not None  # given, or the pool made above
        try:
            result = _run(spec, out, owned, executor, progress, figure, t0)
            if own:
                executor.shutdown(wait=True)
            return result
        except BaseException:
            if own:
                with signals_deferred():
                    stop_pool(executor, what="optimize")
            raise


def _run(spec: OptimizeSpec, out: Path, owned, executor: Executor, progress, figure: bool, t0: float) -> OptimizeResult:
    cheap = problem_of(spec)
    names = cheap.names
    total = [spec.population * spec.generations + 1 + (1 if spec.confirm_scene is not None else 0)]
    count = [0]

    def on_done(_computed: bool) -> None:
        count[0] += 1
        if progress:
            progress(count[0], total[0])

    if progress:
        progress(0, total[0])
    start_values = {v.name: s for v, s in zip(spec.variables, spec.start) if s is not None}
    journal, confirm_journal = (owned.out / j for j in JOURNALS)
    (start_row,), _ = evaluate_points([start_values], variables=names, outputs=DESIGN_OUTPUTS,
                                      evaluator=evaluate_design, context=cheap.context, journal=journal,
                                      executor=executor, on_done=on_done)
    res = search(cheap, journal=journal, executor=executor, population=spec.population,
                 generations=spec.generations, seed=spec.seed, on_done=on_done)
    front_rows = [dict(res.rows[i]) for i in res.front]
    start = {**start_row, "feasible": judge(cheap, start_row)[2] is None, "reason": judge(cheap, start_row)[2]}
    confirm = spec.confirm_scene
    disagreement = {}
    if confirm is not None:
        fine = problem_of(spec, confirm)
        total[0] = count[0] + len(front_rows) + 1
        points = [start_values] + [{n: r[n] for n in names} for r in front_rows]
        rows, _ = evaluate_points(points, variables=names, outputs=DESIGN_OUTPUTS, evaluator=evaluate_design,
                                  context=fine.context, journal=confirm_journal, executor=executor, on_done=on_done)
        for target, row in zip([start, *front_rows], rows):
            _, _, reason = judge(fine, row)
            target.update({f"confirm_{c}": row[c] for c in (*DESIGN_OUTPUTS, *VERDICT_COLUMNS)})
            target.update(confirm_status=row["status"], confirm_feasible=reason is None, confirm_reason=reason)
        disagreement = _disagreement(cheap, fine, front_rows)
    prefix = "confirm_" if confirm is not None else ""
    s_f = _objectives(cheap, start, prefix)
    for k, r in enumerate(front_rows):
        f = _objectives(cheap, r, prefix)
        ok = r.get("confirm_feasible", r["feasible"])
        r["dominates_start"] = bool(ok and s_f is not None and f is not None and dominates(f, s_f))
        r["toml"] = f"designs/{spec.name}_pareto_{k + 1:02d}.toml"
    summary = {
        "name": spec.name, "gearset": spec.gearset.name, "scene": spec.scene.name,
        "confirm_scene": None if confirm is None else confirm.name,
        "variables": [v.name for v in spec.variables],
        "objectives": {o.output: o.sense for o in spec.objectives},
        "constraints": [c.describe() for c in spec.constraints],
        "population": spec.population, "generations": res.generations, "seed": spec.seed,
        "candidates": len(res.rows), "computed": res.computed, "reused": res.reused, "failed": res.failed,
        "feasible": sum(r["feasible"] for r in res.rows), "front": len(front_rows),
        "dominating_start": sum(r["dominates_start"] for r in front_rows),
        "start_feasible": start.get("confirm_feasible", start["feasible"]),
        **disagreement,
    }
    from ...output import folder

    with owned.stage(keep=JOURNALS) as staging:  # the new set with the journals, swapped in as one
        written = [p.relative_to(staging).as_posix() for p in _write(spec, staging, res, front_rows, start, summary,
                                                                     figure)]
        folder.write_marker(staging, "optimize", [*written, *(j for j in JOURNALS if (owned.out / j).is_file())])
    files = tuple(out / n for n in written)
    log.info("optimize %s: %d candidates (%d run), front of %d, %d dominate the start", spec.name, len(res.rows),
             res.computed, len(front_rows), summary["dominating_start"])
    return OptimizeResult(spec, res, tuple(front_rows), start, summary, files, time.perf_counter() - t0)


def gearset_name(name: str, suffix: str = "") -> str:
    """``name`` + ``suffix`` as a gear-set name ``profilegen check`` accepts: lower case letters,
    digits, ``_`` and ``-`` (every other character ``_``), at most 100 characters."""
    from ...gearset.reader import MAX_NAME_CHARS

    text = re.sub(r"[^a-z0-9_-]", "_", (name + suffix).lower())
    if len(text) > MAX_NAME_CHARS:
        text = text[:MAX_NAME_CHARS - len(suffix)] + suffix
    return text or "optimize"


def _objectives(problem: Problem, row: dict, prefix: str) -> np.ndarray | None:
    vals = [row.get(prefix + o.output) for o in problem.objectives]
    if any(v is None for v in vals):
        return None
    return np.array([o.sign * v for o, v in zip(problem.objectives, vals) if v is not None], float)


def _disagreement(cheap: Problem, fine: Problem, front: list[dict]) -> dict:
    """How the cheap scene's verdict on the front differs from the confirm scene's."""
    both = [r for r in front if r["confirm_status"] == "ok" and _objectives(cheap, r, "confirm_") is not None]
    f_cheap = np.array([_objectives(cheap, r, "") for r in both]).reshape(len(both), len(cheap.objectives))
    f_fine = np.array([_objectives(cheap, r, "confirm_") for r in both]).reshape(len(both), len(cheap.objectives))
    flips, pairs = rank_disagreement(f_cheap, f_fine)
    feasible = np.array([r["confirm_feasible"] for r in both], bool)
    from .search import pareto_front

    still = set(pareto_front(f_fine, feasible).tolist()) if len(both) else set()
    return {
        "confirm_failed": sum(r["confirm_status"] != "ok" for r in front),
        "confirm_infeasible": sum(not r["confirm_feasible"] for r in front),
        "confirm_dominated": len(both) - len(still) - int((~feasible).sum()),
        "rank_pairs": pairs, "rank_flips": flips,
        "rank_flip_fraction": (flips / pairs) if pairs else None,
    }


def _write(spec: OptimizeSpec, out: Path, res: SearchResult, front: list[dict], start: dict, summary: dict,
           figure: bool) -> tuple[Path, ...]:
    from ...output.optimize import front_figure, optimize_report_html, write_gearset_toml

    names = [v.name for v in spec.variables]
    judged = list(dict.fromkeys([o.output for o in spec.objectives] + [c.output for c in spec.constraints]))
    files = [write_table(res.rows, ["point_id", "generation", *names, *DESIGN_OUTPUTS, *STATUS_COLUMNS, "feasible",
                                    "reason"], out / "evaluations.csv")]
    confirm = spec.confirm_scene
    cols = ["design", "point_id", *names, *judged, "status", *VERDICT_COLUMNS, "feasible", "reason"]
    if confirm is not None:
        cols += [f"confirm_{c}" for c in (*judged, *VERDICT_COLUMNS)] + ["confirm_status", "confirm_feasible",
                                                                          "confirm_reason"]
    cols += ["dominates_start", "toml"]
    table = [{**start, "design": "start", "toml": None}] + [{**r, "design": f"pareto_{k + 1:02d}"}
                                                             for k, r in enumerate(front)]
    files.append(write_table(table, cols, out / "front.csv"))
    scene_name = (confirm or spec.scene).name
    for k, r in enumerate(front):
        gs = spec.gearset.with_values({n: r[n] for n in names})
        data = gs.to_dict()
        data["name"] = gearset_name(spec.name, f"_pareto_{k + 1:02d}")
        data["description"] = f"Pareto design {k + 1} of optimisation {spec.name!r} (base: {spec.gearset.name})"
        data["scene"] = scene_name if scene_name in ("sketch", "design", "verify") else gs.scene
        header = [f"profilegen optimize {spec.origin}: Pareto design {k + 1} of {len(front)}",
                  *(f"{n} = {r[n]!r}" for n in names),
                  *(f"{o.output} = {r.get('confirm_' + o.output, r.get(o.output))!r} ({o.sense}; scene {scene_name})"
                    for o in spec.objectives)]
        files.append(write_gearset_toml(data, out / r["toml"], header=header))
    objectives = [(o.output, o.sense) for o in spec.objectives]
    if figure:
        files.append(front_figure(objectives, res.rows, front, start,
                                  confirm_label=None if confirm is None else confirm.name,
                                  title=f"optimize {spec.name}: {len(res.rows)} candidates in scene {spec.scene.name}",
                                  path=out / "front.png"))
    files.append(optimize_report_html(summary, table[1:], start, variables=names, objectives=objectives,
                                      constraints=[c.output for c in spec.constraints],
                                      figure="front.png" if figure else None, path=out / "report.html"))
    from ...output.export import atomic_write

    with atomic_write(out / "summary.json") as f:
        f.write(json.dumps(summary, indent=1, default=str) + "\n")
    files.append(out / "summary.json")
    return tuple(files)
