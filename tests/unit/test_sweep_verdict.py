"""Sweeps and the optimiser judge by the verdict (issue 28, item 6): each point's verdict and
failed checks are results.csv columns, with either shape of Verdict.to_dict (status
PASS/FAIL/INCOMPLETE, or the older passed/line/failures), and sweep.png marks infeasible (FAIL)
points as such; a candidate whose verdict is FAIL is infeasible in the search, and the report
says in words what each front design changes and buys."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import pytest

from profilegen.studies.sweep import outputs_of, parse_sweep_spec, run_sweep


class _Verdict:
    def __init__(self, d):
        self._d = d

    def to_dict(self):
        return dict(self._d)


class _Design:
    def __init__(self, d):
        self.verdict = _Verdict(d)


@pytest.mark.parametrize("d, verdict, failed", [
    ({"status": "FAIL", "passed": False, "failures": ["interference -1.1 um", "tooth ring\nfatigue 0.9 < 1.5"]},
     "FAIL", "interference -1.1 um; tooth ring fatigue 0.9 < 1.5"),
    ({"status": "INCOMPLETE", "passed": False, "failures": []}, "INCOMPLETE", None),
    ({"passed": True, "line": "PASS", "failures": []}, "PASS", None),  # the older shape: no status
    ({"passed": False, "line": "FAIL: x", "failures": ["x"]}, "FAIL", "x"),
])
def test_verdict_and_failed_checks_columns(d, verdict, failed):
    out = outputs_of(_Design(d))
    assert out["verdict"] == verdict and out["failed_checks"] == failed


def test_sweep_png_draws_infeasible_points_apart(tmp_path):
    """The figure's legend counts the FAIL points under their own label."""
    spec = parse_sweep_spec({"name": "t", "gearset": "default", "scene": "sketch",
                             "plot": "warnings", "grid": {"wave_generator.deflection_coefficient": [0.8, 0.9, 1.0]}})

    class D(_Design):
        warnings = ()

    def designer(gs, *, scene):
        w = gs.wave_generator.deflection_coefficient
        return D({"status": "FAIL" if w > 0.95 else "PASS", "failures": ["x"] if w > 0.95 else []})

    with ThreadPoolExecutor(max_workers=1) as ex:
        res = run_sweep(spec, tmp_path / "s", executor=ex, designer=designer, figure=False)
    assert [r["verdict"] for r in res.rows] == ["PASS", "PASS", "FAIL"]
    ax = res.plot()
    labels = ax.get_legend_handles_labels()[1]
    assert "PASS (2)" in labels and "FAIL (infeasible) (1)" in labels


# ----------------------------------------------------------------------------- the optimiser


def test_front_in_words_says_what_changes_and_what_it_buys_and_marks_infeasible():
    from profilegen.output.optimize import front_in_words

    start = {"x": 1.0, "y": 5, "err": 10.0, "safety": 2.0}
    front = [{"x": 0.9, "y": 5, "err": 8.0, "safety": 1.5, "feasible": True, "verdict": "PASS"},
             {"x": 1.2, "y": 5, "err": 10.0, "safety": 2.2, "feasible": False, "reason": "violates err <= 9",
              "verdict": "FAIL", "failed_checks": "interference -1.1 um"}]
    lines = front_in_words(front, start, variables=["x", "y"], objectives=[("err", "min"), ("safety", "max")])
    assert lines[0] == ("#1: changes x 1 → 0.9; buys err 10 → 8 (-20.0 %); "
                        "gives up safety 2 → 1.5 (-25.0 %); verdict PASS.")
    assert lines[1].startswith("#2: INFEASIBLE — violates err <= 9; changes x 1 → 1.2; buys safety 2 → 2.2 (+10.0 %)")
    assert lines[1].endswith("verdict FAIL: interference -1.1 um.") and "y" not in lines[1].split(";")[1]


def test_a_design_whose_verdict_fails_is_infeasible_in_the_search_and_marked_in_the_report(tmp_path, monkeypatch):
    import csv
    import textwrap

    from profilegen.studies.optimize import load_optimize_spec, optimize
    from profilegen.studies.optimize import run as oprun

    field = "wave_generator.deflection_coefficient"

    def evaluate(values, context):  # the verdict fails above w = 1.0 (as interference does in the bundled set)
        w = float(values[field])
        return {"profile_max_error_mm": (w - 1.2) ** 2 + 1e-3, "stress_min_safety": 2.0 - w,
                "verdict": "FAIL" if w > 1.0 else "PASS", "failed_checks": "interference" if w > 1.0 else None}

    monkeypatch.setattr(oprun, "evaluate_design", evaluate)
    spec = tmp_path / "o.toml"
    spec.write_text(textwrap.dedent(f"""\
        name = "v"
        gearset = "default"
        scene = "sketch"
        confirm_scene = ""
        [search]
        population = 8
        generations = 3
        seed = 2
        [variables]
        "{field}" = [0.85, 1.15]
        [objectives]
        profile_max_error_mm = "min"
        stress_min_safety = "max"
        """))
    with ThreadPoolExecutor(max_workers=1) as ex:
        res = optimize(load_optimize_spec(spec), tmp_path / "out", executor=ex, figure=False)
    assert res.front and all(r[field] <= 1.0 and r["verdict"] == "PASS" for r in res.front)
    failed = [r for r in res.search.rows if r["verdict"] == "FAIL"]
    assert failed and all(not r["feasible"] and "verdict FAIL (interference)" in r["reason"] for r in failed)
    with (tmp_path / "out" / "evaluations.csv").open(newline="") as f:
        assert {r["verdict"] for r in csv.DictReader(f)} == {"PASS", "FAIL"}
    page = (tmp_path / "out" / "report.html").read_text()
    assert "What each front design changes and buys" in page and page.count("<li>#") == len(res.front)
