"""An objective's sense and a constraint's two bounds, judged on rows whose order is known by
hand (issue 27 item 4: the mutation check found that no test had a "max" objective — minimising
it instead passed the suite). Maximising b is minimising −b: of two candidates equal in a, the
one with the larger b dominates; a candidate outside [lo, hi] violates by its distance to the
bound it crosses, scaled."""

from __future__ import annotations

import numpy as np
import pytest

from profilegen.studies.optimize.search import Constraint, Objective, Problem, judge, pareto_front


def _problem(objectives, constraints=()):
    return Problem(variables=(), objectives=tuple(objectives), constraints=tuple(constraints), evaluator=None,
                   context=None, outputs=("a", "b"))


def _row(**values):
    return {"status": "ok", **values}


def test_a_max_objective_is_minimised_negated():
    problem = _problem([Objective("a", "min"), Objective("b", "max")])
    f, g, reason = judge(problem, _row(a=1.0, b=2.0))
    np.testing.assert_array_equal(f, [1.0, -2.0])
    assert reason is None and np.all(g <= 0.0)
    rows = [_row(a=1.0, b=1.0), _row(a=1.0, b=2.0), _row(a=0.5, b=0.5)]
    f = np.array([judge(problem, r)[0] for r in rows])
    # (1, 2) beats (1, 1) in b, equal in a; (0.5, 0.5) is best in a: the front is rows 1 and 2
    assert pareto_front(f).tolist() == [1, 2]


def test_constraint_violation_is_the_distance_to_the_crossed_bound_scaled():
    c = Constraint("a", lo=1.0, hi=3.0, scale=0.5)
    assert c.violation(2.0) == 0.0
    assert c.violation(0.5) == pytest.approx((1.0 - 0.5) / 0.5)
    assert c.violation(4.0) == pytest.approx((4.0 - 3.0) / 0.5)
    problem = _problem([Objective("b")], [c])
    _, g, reason = judge(problem, _row(a=0.5, b=0.0))
    assert g[0] == pytest.approx(1.0) and reason is not None and "a" in reason
