"""profilegen.studies.optimize: the machinery (Executor, journal, NSGA-II, front extraction) on ZDT1,
whose Pareto front is known in closed form, and the spec's validation.

ZDT1 (Zitzler, Deb & Thiele, Evolutionary Computation 8(2), 2000): f1 = x1,
g = 1 + 9·mean(x2..xn), f2 = g(1 − √(f1/g)); front f2 = 1 − √f1 on f1 ∈ [0, 1], whose
dominated area in the unit square (hypervolume, reference (1, 1)) is 2/3.
"""

from __future__ import annotations

import math
import tomllib
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

from profilegen.errors import OptimizeSpecError
from profilegen.studies.optimize import Objective, Problem, Variable, pareto_front, search
from tests.oracles.zdt1 import zdt1, zdt1_front
from profilegen.studies.sweep import init_worker


def _zdt1(n=2, **context):
    return Problem(tuple(Variable(f"x{i + 1}", 0.0, 1.0) for i in range(n)), (Objective("f1"), Objective("f2")), (),
                   zdt1, {"n": n, **context}, ("f1", "f2", "g"))


def _front(result):
    return np.array(sorted((result.rows[i]["f1"], result.rows[i]["f2"]) for i in result.front))


def _hypervolume(front, ref=(1.0, 1.0)):
    """Area dominated by a 2-objective (minimised) front inside the box up to ``ref``."""
    area, prev_f2 = 0.0, ref[1]
    for f1, f2 in sorted(map(tuple, front)):
        if f1 < ref[0] and f2 < prev_f2:
            area += (ref[0] - f1) * (prev_f2 - f2)
            prev_f2 = f2
    return area


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_optimize")


@pytest.fixture(scope="module")
def pool():
    with ProcessPoolExecutor(max_workers=2, initializer=init_worker) as ex:
        yield ex


@pytest.fixture(scope="module")
def zdt1_run(pool, tmp_path_factory):
    journal = tmp_path_factory.mktemp("zdt1") / "journal.csv"
    return search(_zdt1(), journal=journal, executor=pool, population=20, generations=30, seed=1), journal


def test_zdt1_front_matches_the_analytic_front(zdt1_run):
    result, _ = zdt1_run
    front = _front(result)
    assert len(front) >= 20
    gap = front[:, 1] - np.array([zdt1_front(f1) for f1 in front[:, 0]])
    assert gap.min() >= -1e-12  # nothing below the true front (g ≥ 1)
    assert gap.max() < 0.05  # every point within 0.05 of it
    assert front[:, 0].min() < 0.02 and front[:, 0].max() > 0.95  # and spread over the whole of it
    assert _hypervolume(front) == pytest.approx(2.0 / 3.0, abs=0.03)


def test_front_extraction_is_the_brute_force_non_dominated_set(zdt1_run):
    result, _ = zdt1_run
    f = np.array([[r["f1"], r["f2"]] for r in result.rows])
    brute = [i for i in range(len(f)) if not np.any(np.all(f <= f[i], axis=1) & np.any(f < f[i], axis=1))]
    assert sorted(result.front) == brute  # ZDT1's candidates are distinct, all feasible


def test_pareto_front_keeps_one_of_equal_rows_and_skips_infeasible():
    f = np.array([[1.0, 2.0], [2.0, 1.0], [1.0, 2.0], [0.0, 0.0]])
    assert pareto_front(f, np.array([True, True, True, False])).tolist() == [0, 1]


def test_same_seed_same_front_on_another_executor(zdt1_run, tmp_path):
    """The process pool's run again on threads, in a fresh journal: the same candidates and front."""
    result, _ = zdt1_run
    with ThreadPoolExecutor(max_workers=2) as ex:
        again = search(_zdt1(), journal=tmp_path / "j.csv", executor=ex, population=20, generations=30, seed=1)
    assert [r["point_id"] for r in again.rows] == [r["point_id"] for r in result.rows]
    np.testing.assert_array_equal(_front(again), _front(result))
    with ThreadPoolExecutor(max_workers=2) as ex:
        other = search(_zdt1(), journal=tmp_path / "k.csv", executor=ex, population=20, generations=3, seed=2)
    assert [r["point_id"] for r in other.rows][:20] != [r["point_id"] for r in result.rows][:20]


def test_resume_after_interruption_recomputes_nothing_finished(tmp_path):
    problem = _zdt1()
    journal = tmp_path / "journal.csv"
    seen = []

    def stop_after(computed):
        seen.append(computed)
        if len(seen) == 25:
            raise KeyboardInterrupt

    with ThreadPoolExecutor(max_workers=2) as ex:
        with pytest.raises(KeyboardInterrupt):
            search(problem, journal=journal, executor=ex, population=10, generations=6, seed=3, on_done=stop_after)
        finished = len(journal.read_text().splitlines()) - 1  # header
        assert finished == 25
        resumed = search(problem, journal=journal, executor=ex, population=10, generations=6, seed=3)
    assert resumed.reused == 25
    assert resumed.computed == len(resumed.rows) - 25
    with ThreadPoolExecutor(max_workers=2) as ex:
        fresh = search(problem, journal=tmp_path / "fresh.csv", executor=ex, population=10, generations=6, seed=3)
    assert fresh.computed == len(fresh.rows)
    np.testing.assert_array_equal(_front(resumed), _front(fresh))
    # and once more: everything from the journal
    with ThreadPoolExecutor(max_workers=1) as ex:
        third = search(problem, journal=journal, executor=ex, population=10, generations=6, seed=3)
    assert third.computed == 0


def test_a_failing_candidate_is_recorded_and_the_run_goes_on(tmp_path):
    with ThreadPoolExecutor(max_workers=2) as ex:
        result = search(_zdt1(fail_between=[0.3, 0.6]), journal=tmp_path / "j.csv", executor=ex, population=12,
                        generations=8, seed=1)
    failed = [r for r in result.rows if r["status"] == "error"]
    assert failed and result.failed == len(failed)
    for r in failed:
        assert 0.3 < r["x1"] < 0.6
        assert r["error_type"] == "AnalyticProblemError" and "failing region" in r["error_message"]
        assert not r["feasible"] and r["reason"].startswith("AnalyticProblemError: x1 = ")
        assert r["f1"] is None
    front = _front(result)
    assert len(front) and not np.any((front[:, 0] > 0.3) & (front[:, 0] < 0.6))
    assert result.generations == 8  # ran to the end


def test_integer_variables_are_integers_and_constraints_are_kept(tmp_path):
    from profilegen.studies.optimize import Constraint

    problem = Problem((Variable("x1", 0.0, 1.0), Variable("x2", 0, 3, integer=True)),
                      (Objective("f1"), Objective("f2")), (Constraint("f1", lo=0.25),), zdt1, {"n": 2},
                      ("f1", "f2", "g"))
    with ThreadPoolExecutor(max_workers=2) as ex:
        result = search(problem, journal=tmp_path / "j.csv", executor=ex, population=10, generations=6, seed=0)
    assert all(isinstance(r["x2"], int) and 0 <= r["x2"] <= 3 for r in result.rows)
    front = [result.rows[i] for i in result.front]
    assert front and all(r["f1"] >= 0.25 and r["x2"] == 0 for r in front)
    assert any(not r["feasible"] and r["reason"] == "violates f1 ≥ 0.25" for r in result.rows)


# ----------------------------------------------------------------------------- the spec

_GOOD = """
name = "t"
gearset = "default"
scene = "sketch"
confirm_scene = "design"
[search]
population = 8
generations = 2
seed = 1
[variables]
"wave_generator.deflection_coefficient" = [0.9, 1.1]
"tooth.pressure_angle_deg" = [8.0, 12.0]
[objectives]
stress_min_safety = "max"
profile_max_error_mm = "min"
[constraints]
min_clearance_mm = { min = 0.0, scale = 0.001 }
stress_min_safety = { min = 1.5 }
"""


def test_good_spec_is_read():
    from profilegen.studies.optimize import parse_optimize_spec

    spec = parse_optimize_spec(tomllib.loads(_GOOD))
    assert [v.name for v in spec.variables] == ["wave_generator.deflection_coefficient", "tooth.pressure_angle_deg"]
    assert spec.start == (1.0, 10.0)
    assert [(o.output, o.sense) for o in spec.objectives] == [("stress_min_safety", "max"),
                                                             ("profile_max_error_mm", "min")]
    assert spec.constraints[1].lo == 1.5 and spec.scene.name == "sketch" and spec.confirm_scene.name == "design"


@pytest.mark.parametrize("change, key", [
    (('"tooth.pressure_angle_deg" = [8.0, 12.0]', '"tooth.no_such_field" = [8.0, 12.0]'), "tooth.no_such_field"),
    (('"tooth.pressure_angle_deg" = [8.0, 12.0]', '"tooth.pressure_angle_deg" = [8.0, 80.0]'),
     "variables.tooth.pressure_angle_deg"),
    (('"wave_generator.deflection_coefficient" = [0.9, 1.1]', '"wave_generator.deflection_coefficient" = [-0.5, 1.1]'),
     "variables.wave_generator.deflection_coefficient"),
    (('profile_max_error_mm = "min"', 'profile_wobble_mm = "min"'), "objectives.profile_wobble_mm"),
    (('profile_max_error_mm = "min"', 'profile_max_error_mm = "least"'), "objectives.profile_max_error_mm"),
    (('stress_min_safety = { min = 1.5 }', 'no_output = { min = 1.5 }'), "constraints.no_output"),
    (('stress_min_safety = { min = 1.5 }', 'contact_stiffness_nm_per_rad = { min = 1.0 }'),
     "constraints.contact_stiffness_nm_per_rad"),
    (('seed = 1', 'seed = 1\nsize = 3'), "search.size"),
    (('name = "t"', 'name = "t"\nbudget = 3'), "budget"),
])
def test_bad_spec_is_a_named_error_exit_2_nothing_written(tmp_path, capsys, change, key):
    from profilegen.cli import main
    from profilegen.studies.optimize import load_optimize_spec

    old, new = change
    assert old in _GOOD
    spec = tmp_path / "bad.toml"
    spec.write_text(_GOOD.replace(old, new))
    with pytest.raises(OptimizeSpecError, match=key.replace(".", r"\.")):
        load_optimize_spec(spec)
    out = tmp_path / "out"
    assert main(["optimize", str(spec), "--out", str(out), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert key in err and str(spec) in err
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_pareto_gear_set_toml_round_trips_and_checks(tmp_path, capsys):
    """A front design's gear-set file is the same gear set (so `profilegen design` on it
    repeats the confirm scene's design exactly) and `profilegen check` accepts it."""
    import profilegen as pg
    from profilegen.cli import main
    from profilegen.output.optimize import write_gearset_toml

    base = pg.load_gearset(pg.default_gearset_path())
    gs = base.with_values({"wave_generator.deflection_coefficient": 0.9371234567890123,
                           "tooth.pressure_angle_deg": 11.1, "gear.rim_thickness_mm": 0.8123})
    data = gs.to_dict()
    data["name"] = "t_pareto_01"
    path = write_gearset_toml(data, tmp_path / "t_pareto_01.toml", header=["a design"])
    back = pg.load_gearset(path)
    want = dict(data)
    assert back.to_dict() == want
    assert back.gear.neutral_radius_mm == gs.gear.neutral_radius_mm
    assert main(["check", str(path)]) == 0
    assert "ok" in capsys.readouterr().out


def test_profilegen_optimize_is_callable():
    import profilegen as pg

    assert callable(pg.optimize) and pg.optimize.pareto_front is pareto_front
    assert math.isclose(zdt1({"x1": 0.25, "x2": 0.0}, {"n": 2})["f2"], 0.5)
