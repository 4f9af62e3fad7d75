"""Sweeps judge by the verdict (issue 28, item 6): each point's verdict and failed checks are
results.csv columns, with either shape of Verdict.to_dict (status PASS/FAIL/INCOMPLETE, or the
older passed/line/failures), and sweep.png marks infeasible (FAIL) points as such."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import pytest

from profilegen.sweep import outputs_of, parse_sweep_spec, run_sweep


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
