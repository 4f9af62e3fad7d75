"""profilegen.Engine (issue 31 item 1): the stage cache gives what an uncached design gives, and
re-runs exactly the stages downstream of what changed.

What each stage reads is physics, not the code's output: the sketch scene's rim is ring theory,
ω(φ), υ(φ) from the deflection w0 = ω*·m and the wave count alone (no tooth, no material, no
torque); no geometric stage reads a torque (the profile is the unloaded conjugate); the torques
enter at the contact and the stresses; the requirements only at the checks. The big randomized
run (200 edit sequences) is tests/benchmarks/engine_identity.py; a small one is here.
"""

import dataclasses
import threading

import pytest

import profilegen as pg
from profilegen.pipeline import engine as engine_module
from profilegen.pipeline.engine import Cancelled, Engine
from tests.benchmarks.engine_identity import comparable, first_difference, run

SKETCH = pg.SCENES["sketch"]
GEOMETRY = ("envelope", "gearform", "arcfit")  # the stages after the tooth and the rim


@pytest.fixture(scope="module")
def base():
    return pg.load_gearset(pg.default_gearset_path())


@pytest.fixture(scope="module")
def warm(base):
    """An engine that has designed the default set in the sketch scene (with and without contact)."""
    engine = Engine()
    engine.design(base, scene=SKETCH)
    assert engine.last_run == ("tooth", "rim", *GEOMETRY, "stress")  # a cold engine runs everything
    return engine


def test_twenty_random_edit_sequences_give_the_uncached_design_json():
    out = run(20, 3, seed=5, pool=2)
    assert out["designs"] >= 40
    assert out["differences"] == []
    assert out["hits"], "the sequences revisit states: the cache must have been used"


def test_the_identity_check_fails_when_a_stage_key_misses_a_field(base, monkeypatch):
    """The comparison can fail: a stress stage keyed without the torques reuses a stale result."""
    sections, scene_keys = engine_module.STAGE_INPUTS["stress"]
    monkeypatch.setitem(engine_module.STAGE_INPUTS, "stress",
                        (tuple(s for s in sections if s != "torque"), scene_keys))
    engine = Engine()
    engine.design(base, scene=SKETCH)
    changed = base.with_values({"torque.rated_nm": 150.0})
    stale = engine.design(changed, scene=SKETCH)
    assert engine.last_run == ()
    assert first_difference(comparable(stale), comparable(pg.design(changed, scene=SKETCH))) is not None


def test_a_torque_change_reruns_the_stresses_only(warm, base):
    d = warm.design(base.with_values({"torque.rated_nm": 200.0, "torque.peak_nm": 500.0}), scene=SKETCH)
    assert warm.last_run == ("stress",)
    assert d.gearset.torque.rated_nm == 200.0 and d.stress is not None


def test_a_torque_change_with_the_contact_resolves_contact_and_stresses(base):
    """With the callbacks the CLI gives (the stresses computed inside the contact stage): the same
    design.json and the same partial designs as design() hands them; then a torque change."""
    seen = {"engine": [], "plain": []}

    def recorder(who):
        return lambda d: seen[who].append((d.form is None, d.contact is None, d.stress is None, d.torsional is None))

    engine = Engine()
    cached = engine.design(base, scene=SKETCH, contact=True, on_stage=recorder("engine"))
    plain = pg.design(base, scene=SKETCH, contact=True, on_stage=recorder("plain"))
    assert first_difference(comparable(cached), comparable(plain)) is None
    assert seen["engine"] == seen["plain"] and len(seen["plain"]) == 3
    assert engine.runs["contact_flank"] == 2 and not engine.hits["contact_flank"]  # the right and the left flank
    torque = base.with_values({"torque.rated_nm": 200.0})
    d = engine.design(torque, scene=SKETCH, contact=True)
    assert engine.last_run == ("contact", "stress")
    assert d.contact.torques_nm[0] == 200.0
    # the flanks (points, compliance) read no torque: both taken from the first design, the same objects
    assert engine.runs["contact_flank"] == 2 and engine.hits["contact_flank"] == 2
    assert d.contact.compliance is cached.contact.compliance
    # the torsional curve's ladder (its torques that do not read the rated torque): each flank's from
    # the first design; only the rated torque's own (rated, the lost motion's) solved again
    assert engine.runs["curve_ladder"] == 2 and engine.hits["curve_ladder"] == 2
    assert first_difference(comparable(d), comparable(pg.design(torque, scene=SKETCH, contact=True))) is None
    # the compliance reads the material: a stiffer FS builds both flanks again
    stiffer = engine.design(base.with_values({"material.youngs_modulus_mpa": 230000.0}), scene=SKETCH, contact=True)
    assert engine.runs["contact_flank"] == 4
    assert stiffer.contact.compliance.matrix_mm_per_n[0, 0] < cached.contact.compliance.matrix_mm_per_n[0, 0]


def test_a_requirements_change_reruns_the_checks_only(warm, base):
    warm.design(base.with_values({"requirements.tooth_ring_fatigue_safety": 2.5}), scene=SKETCH)
    assert warm.last_run == ("stress",)


def test_a_tooth_change_starts_at_the_tooth_and_keeps_the_ring_theory_rim(warm, base):
    warm.design(base.with_values({"tooth.pressure_angle_deg": 10.4}), scene=SKETCH)
    assert warm.last_run == ("tooth", *GEOMETRY, "stress")


def test_a_deflection_change_starts_at_the_rim_and_keeps_the_tooth(warm, base):
    warm.design(base.with_values({"wave_generator.deflection_coefficient": 1.01}), scene=SKETCH)
    assert warm.last_run == ("rim", "envelope", "gearform", "arcfit", "stress")


def test_a_scene_change_reruns_the_tiers_that_differ(warm, base):
    warm.design(base, scene=dataclasses.replace(SKETCH, name="fit", tier="sketch", fit_check_positions=241))
    assert warm.last_run == ("arcfit", "stress")  # the fit's check poses: the trace and the form kept
    warm.design(base, scene=dataclasses.replace(SKETCH, name="chord", tier="sketch", chord_tol_mm=8e-5))
    assert warm.last_run == ("envelope", "gearform", "arcfit", "stress")  # tooth and rim kept


def test_cancel_stops_the_design_and_the_engine_goes_on(base):
    engine = Engine()

    def progress(name):
        if name == "gearform":
            engine.cancel()

    with pytest.raises(Cancelled):
        engine.design(base, scene=SKETCH, progress=progress)
    assert "arcfit" not in engine.last_run
    d = engine.design(base, scene=SKETCH)  # the next design runs, reusing what the cancelled one finished
    assert "tooth" not in engine.last_run and "arcfit" in engine.last_run
    assert first_difference(comparable(d), comparable(pg.design(base, scene=SKETCH))) is None


def test_work_beside_a_design_stops_with_it(base):
    """stagecache.Beside (the arc fit's swept-region check beside the corners and the clearance
    map) runs in a copy of its caller's context: a checkpoint on its thread stops when the design
    it serves is cancelled, and its value or error reaches the caller at result()."""
    from profilegen.stagecache import Beside, checkpoint

    assert Beside(lambda a, b: a + b, 2, 3).result() == 5
    with pytest.raises(ZeroDivisionError):
        Beside(lambda: 1 / 0).result()
    engine = Engine()
    started, release, seen = threading.Event(), threading.Event(), {}

    def work():
        started.set()
        release.wait(30)
        checkpoint()
        return "not stopped"

    def progress(name):
        if name == "gearform" and not seen:
            beside = Beside(work)
            assert started.wait(30)
            engine.cancel()
            release.set()
            try:
                seen["result"] = beside.result()
            except Cancelled:
                seen["result"] = "stopped"

    with pytest.raises(Cancelled):
        engine.design(base, scene=SKETCH, progress=progress)
    assert seen == {"result": "stopped"}


def test_stop_cancels_its_own_design_only_on_a_shared_engine(base):
    """An engine shared by threads (supersede=False, as the app's tabs share the process's engine):
    one design's stop() ends that design at its next checkpoint — inside a stage too: asked in the
    gearform stage (before its clearance map), the form is never kept — while the next design on
    the same engine, with a stop() that stays False, runs to the end."""
    engine = Engine(supersede=False)
    asked = []

    def progress(name):
        asked.append(name)

    with pytest.raises(Cancelled):
        engine.design(base, scene=SKETCH, progress=progress, stop=lambda: "gearform" in asked)
    assert asked[-1] == "gearform" and "gearform" not in engine.last_run
    d = engine.design(base, scene=SKETCH, stop=lambda: False)
    assert "gearform" in engine.last_run and d.profile is not None


def test_a_newer_design_supersedes_the_running_one(base):
    engine = Engine()
    in_fit, errors, results = threading.Event(), [], []

    def progress(name):
        if name == "arcfit":
            in_fit.set()
            for _ in range(1000):  # until the newer call has taken over (it bumps the generation)
                if engine._generation > 1:
                    break
                threading.Event().wait(0.01)

    def older():
        try:
            engine.design(base, scene=SKETCH, progress=progress)
        except Cancelled as exc:
            errors.append(exc)

    first = threading.Thread(target=older)
    first.start()
    assert in_fit.wait(60)
    results.append(engine.design(base.with_values({"torque.rated_nm": 250.0}), scene=SKETCH))
    first.join(60)
    assert len(errors) == 1 and results[0].gearset.torque.rated_nm == 250.0
    assert engine.last_run == ("arcfit", "stress")  # the older run's tooth, rim and form were kept


def test_the_memory_budget_bounds_the_cache(base):
    small = Engine(memory_bytes=2_000_000)
    small.design(base, scene=SKETCH)
    assert 0 < small.stats()["bytes"] <= 2_000_000
    none = Engine(memory_bytes=0)
    none.design(base, scene=SKETCH)
    none.design(base, scene=SKETCH)
    assert none.stats()["entries"] == 0 and none.last_run == ("tooth", "rim", *GEOMETRY, "stress")


def test_a_long_run_of_objects_is_sized_by_a_sample_near_what_walking_each_gives(warm, base, monkeypatch):
    """The budget's sizes: a CS outline's ~2 800 arcs and lines sampled, against every one walked
    (the sample cannot see the arrays its elements share, so it may read high, not low), and a
    long array's buffer counted once however many times it is referred to."""
    import numpy as np

    outline = warm.design(base, scene=SKETCH).profile.outline
    sampled = engine_module.nbytes(outline)
    monkeypatch.setattr(engine_module, "_SAMPLED", 10**9)
    walked = engine_module.nbytes(outline)
    assert len(outline.elements) > 1000 and 0.9 * walked <= sampled <= 1.25 * walked
    big = np.zeros(100_000)
    assert 800_000 <= engine_module.nbytes([big] * 100 + [(big, big)] * 100) < 850_000
    # views of one buffer, in a long run of objects: the buffer once; each item's own buffer: each
    rows = [pg.geometry.contour.Line.trusted(r, r + 1.0) for r in np.zeros((1000, 2))]
    own = [pg.geometry.contour.Line((0.0, 0.0), (1.0, 1.0)) for _ in range(1000)]
    monkeypatch.setattr(engine_module, "_SAMPLED", 64)
    for items in (rows, own):
        sampled = engine_module.nbytes(items)
        monkeypatch.setattr(engine_module, "_SAMPLED", 10**9)
        walked = engine_module.nbytes(items)
        monkeypatch.setattr(engine_module, "_SAMPLED", 64)
        assert 0.9 * walked <= sampled <= 1.25 * walked, (sampled, walked)


@pytest.mark.parametrize("value", [-1, 1.5, True, "1G"])
def test_a_bad_memory_budget_is_refused_by_name(value):
    with pytest.raises(ValueError, match="memory_bytes"):
        Engine(memory_bytes=value)


def test_a_bad_memory_environment_is_refused_by_name(monkeypatch):
    monkeypatch.setenv("PROFILEGEN_ENGINE_MEMORY", "lots")
    with pytest.raises(ValueError, match="PROFILEGEN_ENGINE_MEMORY"):
        Engine()
