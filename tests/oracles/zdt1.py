"""Analytic test problems with known Pareto fronts, as evaluators of the optimiser's machinery.

:func:`zdt1` is Zitzler, Deb & Thiele's ZDT1 (Evolutionary Computation 8(2), 2000, eq. T1):
variables x1..xn in [0, 1], both objectives minimised,

    f1 = x1,   g = 1 + 9/(n−1)·Σ_{i≥2} x_i,   f2 = g·(1 − √(f1/g)),

whose Pareto front is g = 1 (x2..xn = 0): f2 = 1 − √f1, f1 ∈ [0, 1]. It runs through the
same Executor, journal and front extraction as a design, so the search and the front are
checked against an answer known in closed form.

>>> zdt1({"x1": 0.25, "x2": 0.0}, {"n": 2})["f2"]
0.5
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from profilegen.errors import ProfilegenError

__all__ = ["AnalyticProblemError", "zdt1", "zdt1_front"]


class AnalyticProblemError(ProfilegenError, ValueError):
    """A test problem's candidate that is made to fail (a region declared as failing)."""


def zdt1(values: Mapping[str, float], context: Mapping) -> dict[str, float]:
    """ZDT1 at ``values`` (``x1`` .. ``xn``, ``n = context["n"]``): {"f1", "f2", "g"}.

    ``context["fail_between"] = [a, b]`` makes every candidate with a < x1 < b raise
    :class:`AnalyticProblemError` (a failing design, for tests).
    """
    n = int(context["n"])
    x = [float(values[f"x{i + 1}"]) for i in range(n)]
    hole = context.get("fail_between")
    if hole is not None and hole[0] < x[0] < hole[1]:
        raise AnalyticProblemError(f"x1 = {x[0]!r}: in the failing region ({hole[0]}, {hole[1]})")
    g = 1.0 + 9.0 * sum(x[1:]) / (n - 1)
    f1 = x[0]
    return {"f1": f1, "f2": g * (1.0 - math.sqrt(f1 / g)), "g": g}


def zdt1_front(f1: float) -> float:
    """The analytic Pareto front of ZDT1: f2 = 1 − √f1."""
    return 1.0 - math.sqrt(f1)
