"""The multi-objective search: pymoo's NSGA-II, asked and told, evaluating on an Executor.

pymoo's ask/tell interface leaves the evaluation to us: each generation's candidates go
through :func:`profilegen.studies.optimize.evaluate.evaluate_points` (the sweep's Executor and
journal). The search is deterministic for a seed (pymoo draws from its own
``numpy.random.Generator``) and the evaluations are deterministic, so a run resumed after
an interruption asks for the same candidates and reads the finished ones back from the
journal: nothing finished is recomputed.

Objectives are minimised internally (a ``max`` objective negated). Constraints
``lo ≤ output ≤ hi`` become pymoo's ``g ≤ 0``, each divided by its ``scale`` so that a
violation in mm and one in safety factor weigh alike; a candidate that failed (its
evaluator raised) or lacks an output it is judged on is infeasible, with a violation far
above any real one. The front is the non-dominated set of every feasible candidate
evaluated (:func:`pareto_front`), not only the last population.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .evaluate import evaluate_points

__all__ = ["Constraint", "Objective", "Problem", "SearchResult", "Variable", "judge", "pareto_front", "search"]

log = logging.getLogger(__name__)

SENSES = ("min", "max")
_FAILED_F = 1e20  # the objectives of a candidate that has none (never on the front: it is infeasible)
_FAILED_G = 1e6  # its violation, far above any real (scaled) one


@dataclass(frozen=True, slots=True)
class Variable:
    """A design variable: a name (a gear-set field path) and its bounds; integer → rounded."""

    name: str
    lo: float
    hi: float
    integer: bool = False

    def decode(self, x: float):
        x = min(max(float(x), self.lo), self.hi)
        return int(round(x)) if self.integer else x


@dataclass(frozen=True, slots=True)
class Objective:
    """An output minimised or maximised (``sense``: ``"min"`` / ``"max"``)."""

    output: str
    sense: str = "min"

    @property
    def sign(self) -> float:
        return 1.0 if self.sense == "min" else -1.0


@dataclass(frozen=True, slots=True)
class Constraint:
    """``lo ≤ output ≤ hi`` (either bound may be None); violations divided by ``scale``."""

    output: str
    lo: float | None = None
    hi: float | None = None
    scale: float = 1.0

    def violation(self, value: float) -> float:
        v = 0.0
        if self.lo is not None:
            v = max(v, self.lo - value)
        if self.hi is not None:
            v = max(v, value - self.hi)
        return v / self.scale

    def describe(self) -> str:
        if self.lo is not None and self.hi is not None:
            return f"{self.lo:g} ≤ {self.output} ≤ {self.hi:g}"
        return f"{self.output} ≥ {self.lo:g}" if self.lo is not None else f"{self.output} ≤ {self.hi:g}"


@dataclass(frozen=True, slots=True, eq=False)
class Problem:
    """What is searched: variables, objectives, constraints, and how a candidate is evaluated
    (``evaluator(values, context) -> {output: value}``, picklable; ``outputs``: every output
    recorded in the journal and tables)."""

    variables: tuple[Variable, ...]
    objectives: tuple[Objective, ...]
    constraints: tuple[Constraint, ...]
    evaluator: Callable
    context: Any
    outputs: tuple[str, ...]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(v.name for v in self.variables)

    def decode(self, x: Sequence[float]) -> dict:
        return {v.name: v.decode(xi) for v, xi in zip(self.variables, x)}


_VERDICT_G = 1.0  # a design whose verdict is FAIL: as infeasible as a violation of one constraint scale


def judge(problem: Problem, row: dict) -> tuple[np.ndarray, np.ndarray, str | None]:
    """(objectives to minimise, scaled constraint violations g ≤ 0 with a last 'evaluated'
    entry — positive also when the design's verdict is FAIL —, the reason it is infeasible or
    None) of one evaluated row."""
    n_c = len(problem.constraints)
    if row["status"] != "ok":
        reason = f"{row['error_type']}: {row['error_message']}"
        return np.full(len(problem.objectives), _FAILED_F), np.r_[np.zeros(n_c), _FAILED_G], reason
    needed = [o.output for o in problem.objectives] + [c.output for c in problem.constraints]
    missing = [c for c in needed if row.get(c) is None]
    if missing:
        reason = f"no value for {', '.join(dict.fromkeys(missing))}"
        return np.full(len(problem.objectives), _FAILED_F), np.r_[np.zeros(n_c), _FAILED_G], reason
    f = np.array([o.sign * row[o.output] for o in problem.objectives], dtype=float)
    failed = row.get("verdict") == "FAIL"  # the design's own checks failed: infeasible whatever the constraints say
    g = np.array([c.violation(row[c.output]) for c in problem.constraints] + [_VERDICT_G if failed else 0.0], dtype=float)
    broken = [c.describe() for c, gi in zip(problem.constraints, g) if gi > 0]
    if failed:
        broken.append(f"verdict FAIL ({row.get('failed_checks') or 'a check failed'})")
    return f, g, ("violates " + "; ".join(broken)) if broken else None


def pareto_front(f: np.ndarray, feasible: np.ndarray | None = None) -> np.ndarray:
    """Indices of the non-dominated rows of ``f`` (n × k, minimised) among ``feasible`` ones,
    in row order; of equal rows the first is kept.

    >>> pareto_front(np.array([[1, 2], [2, 1], [2, 2], [1, 2]]))
    array([0, 1])
    """
    f = np.asarray(f, dtype=float)
    ok = np.ones(len(f), bool) if feasible is None else np.asarray(feasible, bool)
    idx = np.flatnonzero(ok)
    if idx.size == 0:
        return idx
    g = f[idx]
    le = (g[:, None, :] <= g[None, :, :]).all(axis=2)  # le[i, j]: i no worse than j everywhere
    lt = (g[:, None, :] < g[None, :, :]).any(axis=2)
    dominated = (le & lt).any(axis=0)
    equal = le & le.T
    earlier_equal = np.triu(equal, k=1).any(axis=0)  # an equal row comes before
    return idx[~dominated & ~earlier_equal]


@dataclass(frozen=True, slots=True, eq=False)
class SearchResult:
    """Every candidate evaluated (``rows``, in the order first asked, each with ``generation``,
    ``feasible`` and ``reason``), the front (indices into ``rows``), the counts."""

    rows: tuple[dict, ...]
    front: tuple[int, ...]
    computed: int
    reused: int
    generations: int

    @property
    def failed(self) -> int:
        return sum(r["status"] != "ok" for r in self.rows)


def search(problem: Problem, *, journal: str | Path, executor: Executor, population: int, generations: int,
           seed: int, on_done: Callable[[bool], None] | None = None) -> SearchResult:
    """NSGA-II (pymoo) on ``problem``: ``generations`` generations of ``population``
    candidates (the first sampled at random in the bounds), every candidate evaluated on
    ``executor`` with the journal ``journal``."""
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.evaluator import Evaluator
    from pymoo.core.problem import Problem as PymooProblem
    from pymoo.core.repair import Repair
    from pymoo.problems.static import StaticProblem

    xl = np.array([v.lo for v in problem.variables], float)
    xu = np.array([v.hi for v in problem.variables], float)
    ints = np.array([v.integer for v in problem.variables], bool)

    class RoundIntegers(Repair):
        def _do(self, _problem, X, **kwargs):
            X = np.array(X, float)
            X[:, ints] = np.round(X[:, ints])
            return X

    pp = PymooProblem(n_var=len(xl), n_obj=len(problem.objectives), n_ieq_constr=len(problem.constraints) + 1,
                      xl=xl, xu=xu)
    algorithm = NSGA2(pop_size=population, repair=RoundIntegers(), eliminate_duplicates=True)
    algorithm.setup(pp, termination=("n_gen", generations), seed=seed, verbose=False)
    by_id: dict[str, dict] = {}
    computed = reused = 0
    generation = 0
    while algorithm.has_next():
        pop = algorithm.ask()
        if pop is None or len(pop) == 0:
            break
        generation += 1
        points = [problem.decode(x) for x in pop.get("X")]
        rows, ran = evaluate_points(points, variables=problem.names, outputs=problem.outputs,
                                    evaluator=problem.evaluator, context=problem.context, journal=journal,
                                    executor=executor, on_done=on_done)
        distinct = len({r["point_id"] for r in rows})
        computed += ran
        reused += distinct - ran
        judged = [judge(problem, r) for r in rows]
        F = np.array([j[0] for j in judged])
        G = np.array([j[1] for j in judged])
        for r, (_, g, reason) in zip(rows, judged):
            if r["point_id"] not in by_id:
                by_id[r["point_id"]] = {**r, "generation": generation, "feasible": reason is None, "reason": reason}
        Evaluator().eval(StaticProblem(pp, F=F, G=G), pop)
        algorithm.tell(infills=pop)
        log.info("generation %d: %d candidates, %d run, %d feasible so far", generation, len(rows), ran,
                 sum(r["feasible"] for r in by_id.values()))
    all_rows = tuple(by_id.values())
    if all_rows:
        F = np.array([judge(problem, r)[0] for r in all_rows])
        front = pareto_front(F, np.array([r["feasible"] for r in all_rows]))
    else:
        front = np.zeros(0, int)
    return SearchResult(all_rows, tuple(int(i) for i in front), computed, reused, generation)


def dominates(a: Sequence[float] | np.ndarray, b: Sequence[float] | np.ndarray) -> bool:
    """a (minimised) no worse than b in every objective and better in one."""
    x, y = np.asarray(a, float), np.asarray(b, float)
    return bool(np.all(x <= y) and np.any(x < y)) and bool(np.all(np.isfinite(x)))


def rank_disagreement(cheap: np.ndarray, fine: np.ndarray) -> tuple[int, int]:
    """(pairs whose order in some objective flips between two evaluations, pairs compared):
    for each objective, each pair of designs ordered one way by ``cheap`` and the other by
    ``fine`` (ties in either not counted as flips)."""
    cheap, fine = np.asarray(cheap, float), np.asarray(fine, float)
    n = len(cheap)
    flips = pairs = 0
    for k in range(cheap.shape[1] if n else 0):
        for i in range(n):
            for j in range(i + 1, n):
                pairs += 1
                a, b = cheap[i, k] - cheap[j, k], fine[i, k] - fine[j, k]
                if a * b < 0 and math.isfinite(a) and math.isfinite(b):
                    flips += 1
    return flips, pairs
