"""Each scene's error estimates bound the next scene (issue 28 item 2): over the recorded corpus
measurement (tests/corpus/scene_table.json, written by tests/benchmarks/scene_estimates.py) every
|sketch − design| and |design − verify| of every design-sheet number and set is within the cheaper
scene's estimate (profilegen.pipeline.scene_estimates), or that scene says 'not estimated'; no cheaper PASS
is a verify FAIL unless the cheaper verdict was INCOMPLETE naming what it did not check; and one
live sketch/design pair (the default set, the session's shared designs) shows the recorded table
is not stale in kind.

The differences are recomputed here from the recorded values (not read from the table's own
difference column), and the bound is applied as its kind defines it (absolute, × module, ×
|cheaper value|).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from profilegen.pipeline import scene_estimates as se

TABLE = Path(__file__).resolve().parents[1] / "corpus" / "scene_table.json"
PAIRS = (("sketch", "design"), ("design", "verify"))
REL_TOL = 1e-9  # round-off of the stored numbers


@pytest.fixture(scope="module")
def table():
    return json.loads(TABLE.read_text(encoding="utf-8"))


def _diff(key, a, b) -> float:
    if isinstance(a, list):
        return math.dist(a, b)
    return abs(a - b)


def _bound(est, key, cheap_value, module_mm) -> float:
    if est.kind == "absolute":
        return est.value
    if est.kind == "per_module":
        return est.value * module_mm
    assert est.kind == "relative", est
    return est.value * abs(cheap_value)


def outside(table, estimates_for=se.estimate_for) -> list[str]:
    """Every (pair, number, set) whose difference exceeds the cheaper scene's estimate, or where
    the cheaper scene claims a bound for a number it did not compute."""
    bad = []
    for cheap, dear in PAIRS:
        for name, row in table["sets"].items():
            a, b = row["scenes"][cheap]["numbers"], row["scenes"][dear]["numbers"]
            for key in se.NUMBERS:
                est = estimates_for(cheap, key)
                if isinstance(est, se.NotEstimated):
                    continue  # no claim, and it says why
                if b[key] is not None and a[key] is None:
                    bad.append(f"{cheap}/{key}/{name}: a bound claimed for a number the {cheap} scene did not compute")
                    continue
                if a[key] is None or b[key] is None:
                    continue
                d, bound = _diff(key, a[key], b[key]), _bound(est, key, a[key], row["module_mm"])
                if d > bound * (1 + REL_TOL) + 1e-15:
                    bad.append(f"{cheap}/{key}/{name}: |{a[key]} - {b[key]}| = {d:.4g} > {bound:.4g}")
    return bad


def test_the_corpus_ran_in_every_scene(table):
    assert len(table["sets"]) >= 25  # >= 20 generated + the 5 bundled
    failed = [f"{n}/{s}: {r['scenes'][s]['error']}" for n, r in table["sets"].items() for s in se.NEXT_SCENE.keys() | {"verify"}
              if r["scenes"][s].get("numbers") is None]
    assert not failed


def test_every_difference_is_within_the_cheaper_scenes_estimate(table):
    assert outside(table) == []


def test_the_check_can_fail(table):
    """The same check with every estimate at 0.6x its value finds numbers outside (the
    estimates are 1.5x the largest observed difference, so 0.6x is below it somewhere)."""
    def shrunk(scene, key):
        est = se.estimate_for(scene, key)
        return est if isinstance(est, se.NotEstimated) else se.Estimate(est.kind, 0.6 * est.value, est.observed)

    assert outside(table, shrunk)


def test_the_module_holds_the_recorded_measurement(table):
    """profilegen.pipeline.scene_estimates.ESTIMATES is the table's derivation (not edited by hand, not stale)."""
    assert se.MEASURED["commit"] == table["commit"]
    for cheap in se.NEXT_SCENE:
        for key, rec in table["estimates"][cheap].items():
            est = se.ESTIMATES[cheap][key]
            if "not_estimated" in rec:
                assert isinstance(est, se.NotEstimated), key
            elif isinstance(est, se.Estimate):
                assert (est.kind, est.value) == (rec["kind"], rec["value"]), key
                assert est.value >= se.SAFETY_FACTOR * est.observed * (1 - 1e-12), key
            # else: measured, but the module says why no bound is claimed (see its reason)


def test_a_cheaper_pass_is_never_a_verify_fail(table):
    """A cheaper PASS where verify FAILs would send a failing part to the shop; a cheaper
    INCOMPLETE must name what it did not check."""
    wrong = []
    for name, row in table["sets"].items():
        final = row["scenes"]["verify"]["verdict"]
        for cheap in se.NEXT_SCENE:
            v = row["scenes"][cheap]["verdict"]
            if v["status"] == "INCOMPLETE":
                assert v["not_checked"], f"{name}/{cheap}: INCOMPLETE without naming what was not checked"
            if v["status"] == "PASS" and final["status"] == "FAIL":
                wrong.append(f"{name}: {cheap} PASS, verify FAIL ({'; '.join(final['failures'])})")
    assert wrong == []


def test_a_scene_not_measured_claims_no_bound():
    import dataclasses

    import profilegen as pg

    finer = dataclasses.replace(pg.SCENES["sketch"], chord_tol_mm=1e-5)
    assert isinstance(se.estimate_for(finer, "cs_tip_diameter_mm"), se.NotEstimated)
    assert isinstance(se.estimate_for("verify", "cs_tip_diameter_mm"), se.NotEstimated)
    assert isinstance(se.estimate_for("mine", "cs_tip_diameter_mm"), se.NotEstimated)


def test_live_sketch_and_design_are_within_the_estimates(table, default_sketch, default_design_scene):
    """The default set now, in the sketch and design scenes: the same numbers computed (None in
    the same places) as recorded, and |sketch − design| within the sketch scene's estimates."""
    live = {"sketch": se.numbers_of(default_sketch), "design": se.numbers_of(default_design_scene)}
    recorded = table["sets"]["default"]["scenes"]
    for scene, nums in live.items():
        assert {k for k, v in nums.items() if v is None} == \
            {k for k, v in recorded[scene]["numbers"].items() if v is None}, scene
    m = default_sketch.gearset.gear.module_mm
    for key in se.NUMBERS:
        est = se.estimate_for(default_sketch.scene, key)
        a, b = live["sketch"][key], live["design"][key]
        if isinstance(est, se.NotEstimated) or a is None or b is None:
            continue
        assert _diff(key, a, b) <= _bound(est, key, a, m) * (1 + REL_TOL), key


def test_a_check_that_flips_to_fail_in_verify_was_within_its_estimate(table):
    """Each check a cheaper scene PASSES and verify FAILS: the cheaper value was within the
    cheaper scene's estimate of the requirement (its sheet showed that the check could go either
    way), never a clear pass."""
    def by_name(checks):  # a check made at several torques appears once per torque, in the same order
        out: dict = {}
        for c in checks:
            out.setdefault(c[0], []).append(c)
        return out

    for name, row in table["sets"].items():
        final = by_name(row["scenes"]["verify"]["verdict"]["checks"])
        for cheap in se.NEXT_SCENE:
            cheap_checks = by_name(row["scenes"][cheap]["verdict"]["checks"])
            pairs = [(check, c, there) for check, same in cheap_checks.items()
                     for c, there in zip(same, final.get(check, []))]
            for check, (_, status, value, required, kind), there in pairs:
                if status != "PASS" or there[1] != "FAIL":
                    continue
                est = se.estimate_for(cheap, se.check_key(kind, check) or "")
                assert isinstance(est, se.Estimate), f"{name}/{cheap}/{check}: no estimate for a check that flips"
                margin = abs(value - required)
                assert margin <= _bound(est, None, value, row["module_mm"]) * (1 + REL_TOL), (name, cheap, check)
