"""Multi-objective design optimisation: gear-set fields searched by NSGA-II (pymoo) on the
sweep's Executor, a cheap scene for the search and the design scene to confirm the front.

``profilegen.optimize(spec, out_dir)`` runs a spec (:func:`run.optimize`; the module itself
is callable, so ``profilegen.optimize(...)`` works however it was imported). The pieces:

* :mod:`.spec` — the TOML spec (:func:`load_optimize_spec`), validated before anything runs;
* :mod:`.evaluate` — one design per candidate through the Executor and the resumable journal;
* :mod:`.search` — NSGA-II asked and told, constraints, the Pareto front;
* :mod:`.run` — the whole run and its files (through :mod:`profilegen.output.optimize`).
"""

from __future__ import annotations

import sys
import types

from .evaluate import CONTACT_OUTPUTS, DESIGN_OUTPUTS, evaluate_design, evaluate_points
from .run import OptimizeResult, optimize, problem_of
from .search import Constraint, Objective, Problem, SearchResult, Variable, pareto_front, search
from .spec import OptimizeSpec, load_optimize_spec, parse_optimize_spec

__all__ = [
    "CONTACT_OUTPUTS",
    "DESIGN_OUTPUTS",
    "Constraint",
    "Objective",
    "OptimizeResult",
    "OptimizeSpec",
    "Problem",
    "SearchResult",
    "Variable",
    "evaluate_design",
    "evaluate_points",
    "load_optimize_spec",
    "optimize",
    "pareto_front",
    "parse_optimize_spec",
    "problem_of",
    "search",
]


class _CallableModule(types.ModuleType):
    """``profilegen.studies.optimize`` is this package and :func:`optimize` at once."""

    def __call__(self, *args, **kwargs):
        return optimize(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
