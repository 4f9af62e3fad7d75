"""The cost model's envelope estimate covers the pipeline's retrace (profilegen.pipeline.budget.worst_chord).

profilegen.pipeline.design.traced_form traces the envelope again at a finer chord when the CS form finds a
grazing crossing it missed (UnresolvedBoundaryError); the preflight must estimate the envelope and
the CS outline at the finest chord that can happen, not at the scene's. Checked against the chords
traced_form really asks for (its envelope and CS form stubbed: every trace fails) and against the
estimate's formula, points = 10·√(m / chord) + 2000 at that chord."""

from __future__ import annotations

import dataclasses
import math

import pytest

import profilegen as pg
from profilegen.pipeline import budget
from profilegen.pipeline import design as pipeline
from profilegen.profile.gearform import UnresolvedBoundaryError
from profilegen.pipeline.scenes import SCENES


@pytest.fixture(scope="module")
def gs():
    return pg.load_gearset("default")


def test_worst_chord_is_the_finest_chord_traced_form_traces(gs, monkeypatch):
    chords = []

    def envelope_of(tooth, motion, *, chord_tol_mm, **kwargs):
        chords.append(chord_tol_mm)
        return object()

    def circular_spline_form(env, **kwargs):
        raise UnresolvedBoundaryError("gearform: planted: an unresolved stretch (a grazing crossing)")

    monkeypatch.setattr(pipeline, "envelope_of", envelope_of)
    monkeypatch.setattr(pipeline, "circular_spline_form", circular_spline_form)
    scene = SCENES["design"]
    with pytest.raises(UnresolvedBoundaryError, match="retraced at chord"):
        pipeline.traced_form(None, None, gs, scene)
    assert len(chords) == pipeline.RETRACES + 1 and chords[0] == scene.chord_tol_mm
    assert budget.worst_chord(scene.chord_tol_mm) == pytest.approx(min(chords), rel=1e-15)
    assert budget.worst_chord(1e-6) == pytest.approx(1e-6 / 16, rel=1e-15)  # two retraces, 4x finer each


@pytest.mark.parametrize("scene", ["sketch", "design", "verify"])
def test_the_envelope_and_outline_estimates_are_at_the_worst_chord(gs, scene):
    sc = SCENES[scene]
    m, z2 = gs.gear.module_mm, gs.gear.circular_spline_teeth
    points = 10.0 * math.sqrt(m / (sc.chord_tol_mm / 16.0)) + 2000.0  # 4x the points of the scene's chord, + floor
    costs = {c.what: c.bytes for c in budget.estimate(gs, sc).costs}
    assert costs["the traced envelope"] == pytest.approx(500.0 * points, rel=1e-12)
    assert costs["the circular spline's outline"] == pytest.approx(48.0 * 0.25 * points * z2, rel=1e-12)


def test_the_advised_chord_fits_with_the_retrace_and_a_finer_one_does_not(gs):
    # a budget between the estimate at 1e-9 mm's retrace and at 1e-8 mm's: the advice must account for
    # the retrace (a chord that fits only without it would be refused again)
    limit = 0.5 * 2**30
    scene = dataclasses.replace(SCENES["sketch"], chord_tol_mm=1e-9)
    with pytest.raises(budget.BudgetError, match=r"chord_tol_mm = 1e-09 .*retraced at 6.25e-11 mm.*raise chord_tol_mm "
                                                   r"to at least ([0-9.e+-]+);") as err:
        budget.check_budget(gs, scene, budget=limit)
    advised = float(str(err.value).split("raise chord_tol_mm to at least ")[1].split(";")[0])
    budget.check_budget(gs, dataclasses.replace(scene, chord_tol_mm=advised), budget=limit)
    # the advice without the retrace's factor 16 (what fits if the envelope is traced at the scene's
    # chord only) is refused: the estimate is at the retrace's chord
    with pytest.raises(budget.BudgetError):
        budget.check_budget(gs, dataclasses.replace(scene, chord_tol_mm=advised / 16.0), budget=limit)


def test_the_grid_advice_divides_by_the_other_key(gs):
    # n_t × n_phi cells at 48 bytes each: with n_t kept, n_phi ≤ budget / 48 / n_t, and the other way
    # round (an unequal grid, so the two advices differ)
    limit = 0.5 * 2**30
    scene = dataclasses.replace(SCENES["sketch"], n_t=100_000, n_phi=241)
    with pytest.raises(budget.BudgetError) as err:
        budget.check_budget(gs, scene, budget=limit)
    cells = limit / 48.0
    n_phi, n_t = int(cells // 100_000), int(cells // 241)
    assert f"lower n_phi to at most {n_phi} (with n_t = 100000), or n_t to at most {n_t} (with n_phi = 241)" \
        in str(err.value)
    budget.check_budget(gs, dataclasses.replace(scene, n_phi=n_phi), budget=limit)
    budget.check_budget(gs, dataclasses.replace(scene, n_t=n_t), budget=limit)
    with pytest.raises(budget.BudgetError):
        budget.check_budget(gs, dataclasses.replace(scene, n_t=n_t + 1), budget=limit)
