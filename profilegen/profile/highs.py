"""The arc fit's small LPs (7 columns, 16–300 rows, ~30 a fit) straight to HiGHS.

:func:`solve_lp` is ``scipy.optimize.linprog(method="highs")`` without its per-call input
checks and option parsing: the same solver (scipy's own build of HiGHS), the same options and
the same answers, bit for bit (tests/unit/test_highs.py), 2.5× faster on the fit's LPs (0.41
against 1.02 ms each on the default set's sketch scene: ~19 ms of a 0.21 s design). It reaches
into scipy's bundled HiGHS bindings (``scipy.optimize._highspy._core``), which are not a public
API: where they are missing or have changed, it calls ``linprog`` instead (and says so once in
the log).
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import Any

import numpy as np
from scipy.optimize import linprog
from scipy.sparse import csc_array

log = logging.getLogger(__name__)

__all__ = ["TOLERANCES", "solve_lp"]

#: HiGHS's feasibility tolerances for the fit's LPs (absolute: the fit scales its rows to ~1)
TOLERANCES = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}


def _direct_options() -> tuple[Any, Any] | None:
    """HiGHS's options as ``linprog(method="highs")`` sets them (presolve on, the dual simplex,
    quiet) with :data:`TOLERANCES`; None when scipy's bindings are not what this expects."""
    try:
        from scipy.optimize._highspy import _core as h

        options = h.HighsOptions()
        options.presolve = "on"
        options.highs_debug_level = h.HighsDebugLevel.kHighsDebugLevelNone
        options.log_to_console = False
        options.output_flag = False
        options.simplex_strategy = int(h.simplex_constants.SimplexStrategy.kSimplexStrategyDual)
        for key, value in TOLERANCES.items():
            setattr(options, key, value)
        return h, options
    except Exception as exc:  # noqa: BLE001 — any change of scipy's internals: linprog instead
        log.info("highs: scipy's HiGHS bindings are not as expected (%s): the arc fit calls linprog", exc)
        return None


_DIRECT = _direct_options()


def solve_lp(c: np.ndarray, A_ub: np.ndarray, b_ub: np.ndarray, bounds: Sequence[tuple[float | None, float | None]],
             *, direct: bool = True) -> tuple[np.ndarray, np.ndarray] | None:
    """min c·x s.t. A_ub x ≤ b_ub and ``bounds`` (per column: (low, high), None unbounded):
    (x, the rows' marginals, ∂(min)/∂b_ub ≤ 0), or None when HiGHS finds no optimum.
    ``direct=False``: through ``linprog`` (the reference the tests compare with)."""
    global _DIRECT
    if direct and _DIRECT is not None:
        try:
            return _solve_direct(_DIRECT[0], _DIRECT[1], c, A_ub, b_ub, bounds)
        except (AttributeError, TypeError, ValueError) as exc:  # scipy's bindings changed under us
            log.info("highs: the direct call failed (%s): the arc fit calls linprog from now on", exc)
            _DIRECT = None
    res = linprog(c, A_ub=A_ub, b_ub=b_ub, bounds=bounds, method="highs", options=TOLERANCES)
    if res.status != 0:
        return None
    return res.x, np.asarray(res.ineqlin.marginals, float)


def _solve_direct(h, options, c, A_ub, b_ub, bounds):
    m, n = A_ub.shape
    A = csc_array(A_ub)
    inf = h.kHighsInf
    lp = h.HighsLp()
    lp.num_col_, lp.num_row_ = n, m
    lp.a_matrix_.num_col_, lp.a_matrix_.num_row_ = n, m
    lp.a_matrix_.format_ = h.MatrixFormat.kColwise
    lp.col_cost_ = np.asarray(c, float)
    lp.col_lower_ = np.array([-inf if lo is None else lo for lo, _ in bounds], float)
    lp.col_upper_ = np.array([inf if hi is None else hi for _, hi in bounds], float)
    lp.row_lower_ = np.full(m, -inf)
    lp.row_upper_ = np.asarray(b_ub, float)
    lp.a_matrix_.start_, lp.a_matrix_.index_, lp.a_matrix_.value_ = A.indptr, A.indices, A.data
    highs = h._Highs()
    highs.passOptions(options)
    highs.passModel(lp)
    highs.run()
    if highs.getModelStatus() != h.HighsModelStatus.kOptimal:
        return None
    solution = highs.getSolution()
    return np.array(solution.col_value), np.array(solution.row_dual)
