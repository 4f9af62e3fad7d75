"""The workbench's state without a browser: undo/redo, the newest request superseding older ones
(and their results dropped), the workspace refusing paths outside it, and the form's fields
being the reader's own (every range the form shows is the one the reader enforces)."""

from __future__ import annotations

import math
import os
import threading
import time

import pytest

import profilegen as pg
from profilegen.app import schema
from profilegen.app.session import Computer, History, Session, Workspace, WorkspaceError
from profilegen.errors import GearSetError


@pytest.fixture(scope="module")
def gearset():
    return pg.load_gearset(pg.default_gearset_path())


# ------------------------------------------------------------------ undo / redo

def test_undo_redo_walks_the_states_and_a_new_edit_drops_the_redo_tail():
    h = History("a")
    assert not h.can_undo and not h.can_redo
    h.push("b")
    h.push("c")
    assert h.undo() == "b" and h.undo() == "a"
    assert h.undo() == "a" and not h.can_undo  # nothing before the first state
    assert h.redo() == "b" and h.can_redo
    h.push("d")  # an edit after undo: 'c' can no longer be redone
    assert not h.can_redo and h.current == "d"
    assert h.undo() == "b" and h.undo() == "a"
    h.push("a")  # the same state again is not a new step
    assert not h.can_undo and h.can_redo


def test_history_keeps_at_most_its_limit():
    h = History(0, limit=5)
    for i in range(1, 20):
        h.push(i)
    steps = 0
    while h.can_undo:
        h.undo()
        steps += 1
    assert steps == 4 and h.current == 15


def test_session_edit_undo_redo_and_a_bad_value_leaves_the_state(gearset, tmp_path):
    s = Session(gearset, "sketch", Workspace(tmp_path), compute=_never)
    assert s.edit({"wave_generator.deflection_coefficient": "1.1"}) == {}
    assert s.gearset.wave_generator.deflection_coefficient == 1.1
    errors = s.edit({"wave_generator.deflection_coefficient": "1.1", "gear.module_mm": "-0.5"})
    assert set(errors) == {"gear.module_mm"}
    assert errors["gear.module_mm"].startswith("gear.module_mm = -0.5 mm: must be in")  # the reader's own line
    assert s.gearset.gear.module_mm == 0.5 and s.gearset.wave_generator.deflection_coefficient == 1.1
    errors = s.edit({"torque.rated_nm": "lots"})
    assert errors == {"torque.rated_nm": 'torque.rated_nm = "lots": must be a number, got string'}
    assert s.undo().gearset.wave_generator.deflection_coefficient == 1.0
    assert s.redo().gearset.wave_generator.deflection_coefficient == 1.1
    s.set_scene("design")
    assert s.undo().scene == "sketch"


# ------------------------------------------------------------------ the computation

def _never(*a, **k):
    raise AssertionError("no design expected")


class _Gate:
    """A stand-in for redesign: each call reports its stages and waits at the first one until
    released; records the jobs it saw start and finish."""

    def __init__(self):
        self.release = threading.Event()
        self.started = threading.Event()
        self.finished = []

    def __call__(self, gearset, scene, *, progress, on_profile, on_stage, stop=None):
        progress("tooth")
        self.started.set()
        assert self.release.wait(10)
        progress("envelope")  # a newer request raises here
        result = ("design", gearset.wave_generator.deflection_coefficient)
        self.finished.append(result)
        return _Fake(result)


class _Fake:
    profile = object()

    def __init__(self, key):
        self.key = key


def test_a_newer_request_supersedes_the_running_one_and_queued_ones(gearset):
    gate = _Gate()
    c = Computer(gate)
    one = c.submit(gearset, "sketch")
    assert gate.started.wait(10)
    two = c.submit(gearset.with_values({"wave_generator.deflection_coefficient": 1.1}), "sketch")
    three = c.submit(gearset.with_values({"wave_generator.deflection_coefficient": 1.2}), "sketch")
    assert c.wait(one, timeout=0.1) is None  # superseded: the caller drops it
    gate.release.set()
    snap = c.wait(three, profile=False, timeout=10)
    assert snap is not None and snap.done and snap.design.key == ("design", 1.2)
    assert c.ran == [one, three]  # two was superseded while queued and never ran
    assert gate.finished == [("design", 1.2)]  # one was abandoned at its next stage
    assert c.wait(two, timeout=0.1) is None
    c.close()


def test_a_stale_result_is_never_published(gearset):
    """A computation that ignores the cancellation still finishes; its result is dropped: while the
    newer request runs, the tab sees no design at all (not the stale one)."""
    gates = [threading.Event(), threading.Event()]
    started = [threading.Event(), threading.Event()]
    calls = []

    def stubborn(gs, scene, *, progress, on_profile, on_stage, stop=None):  # never asks stop()
        i = len(calls)
        calls.append(i)
        started[i].set()
        assert gates[i].wait(10)
        return _Fake(gs.wave_generator.deflection_coefficient)

    c = Computer(stubborn)
    c.submit(gearset, "sketch")
    assert started[0].wait(10)
    two = c.submit(gearset.with_values({"wave_generator.deflection_coefficient": 1.1}), "sketch")
    gates[0].set()  # the stale one finishes ...
    assert started[1].wait(10)  # ... and the newer one starts after it
    assert c.latest().job == two and c.latest().design is None and c.final is None
    gates[1].set()
    snap = c.wait(two, profile=False, timeout=10)
    assert snap.design.key == 1.1
    assert c.final.job == two and c.final.design.key == 1.1
    c.close()


def test_a_superseded_computation_stops_inside_its_stage_at_its_next_checkpoint(gearset):
    """The tab's stop() is the engine's checkpoint inside a stage: a long loop that asks it between
    its steps (as the contact's continuation does between torques) stops at the next step once a
    newer request came, without waiting for the stage's end; the newer request runs next."""
    from profilegen.pipeline.engine import Cancelled

    steps, started = [], threading.Event()

    def looping(gs, scene, *, progress, on_profile, on_stage, stop):
        progress("contact")
        for i in range(1000):  # 1000 steps of 10 ms: 10 s without the checkpoint
            if stop():
                raise Cancelled("superseded")
            steps.append((gs.torque.rated_nm, i))
            started.set()
            time.sleep(0.01)
        return _Fake(gs.torque.rated_nm)

    c = Computer(looping)
    c.submit(gearset, "design")
    assert started.wait(10)
    two = c.submit(gearset.with_values({"torque.rated_nm": 200.0}), "design")
    snap = c.wait(two, profile=False, timeout=30)
    assert snap is not None and snap.error is None and snap.design.key == 200.0
    first = [i for t, i in steps if t != 200.0]
    assert 1 <= len(first) < 100  # stopped within a few steps, not after the loop's 1000
    c.close()


def test_a_poll_waits_for_the_next_snapshot_and_returns_it_at_once(gearset):
    """Computer.newer (the page's long poll): a progress line the page has not seen comes at the
    poll's timeout (they coalesce); the finished design comes as soon as it is published, not at
    the timeout; with nothing new the poll returns None after its timeout."""
    gate = _Gate()
    c = Computer(gate)
    job = c.submit(gearset, "sketch")
    assert gate.started.wait(10)
    seen = c.latest().version
    t0 = time.monotonic()
    assert c.newer(seen - 1, timeout=0.3).version == seen  # a progress line: at the timeout
    assert time.monotonic() - t0 >= 0.29
    t0 = time.monotonic()
    assert c.newer(seen, timeout=0.2) is None and time.monotonic() - t0 >= 0.19
    threading.Timer(0.1, gate.release.set).start()  # the design goes on (a progress line, then its end)
    t0 = time.monotonic()
    snap = c.newer(seen, timeout=20)
    assert snap is not None and snap.done and snap.job == job and time.monotonic() - t0 < 10
    assert c.newer(seen, timeout=20).version == snap.version  # not seen yet: at once
    c.close()


def test_the_profile_hook_runs_once_per_request_before_its_profile_is_published(gearset, tmp_path):
    """Session(on_profile=...) (the app builds the figures there): called with the tab, the job and
    the design the moment the profile is fitted and before any waiter can see it; once per request
    (a later partial design with the same profile does not call it again); never for a request
    already superseded."""
    seen = []
    profile = object()

    class Partial:
        def __init__(self, key):
            self.key, self.profile = key, profile

    def compute(gs, scene, *, progress, on_profile, on_stage, stop=None):
        key = gs.wave_generator.deflection_coefficient
        on_profile(Partial(key))
        on_stage(Partial(key))  # a slower stage adds to the design: the profile is not new
        return Partial(key)

    def hook(session, job, design):
        snap = session.computer.latest()
        seen.append((session, job, design.key, snap is not None and snap.job == job and snap.has_profile))

    s = Session(gearset, "sketch", Workspace(tmp_path), compute=compute, on_profile=hook)
    job = s.submit()
    snap = s.computer.wait(job, profile=False, timeout=10)
    assert snap is not None and snap.done
    assert seen == [(s, job, gearset.wave_generator.deflection_coefficient, False)]  # not yet published
    # a superseded request: its profile comes after a newer submit, and the hook is not called for it
    gate, late = threading.Event(), []

    def held(gs, scene, *, progress, on_profile, on_stage, stop=None):
        if not late:
            late.append(1)
            assert gate.wait(10)
        on_profile(Partial(gs.wave_generator.deflection_coefficient))
        return Partial(gs.wave_generator.deflection_coefficient)

    s.computer._compute = held
    s.edit({"wave_generator.deflection_coefficient": "1.1"})
    first = s.submit()
    while not late:
        time.sleep(0.01)
    s.edit({"wave_generator.deflection_coefficient": "1.2"})
    second = s.submit()
    gate.set()
    assert s.computer.wait(second, profile=False, timeout=10).done
    assert [j for _, j, _, _ in seen] == [job, second] and first not in [j for _, j, _, _ in seen]
    s.close()


def test_a_failing_profile_hook_does_not_fail_the_design(gearset, tmp_path, caplog):
    """The hook builds figures: its failure is logged, and the design still finishes and is
    published (the figures' callback builds them again and says why)."""
    profile = object()

    class Done:
        def __init__(self, key):
            self.key, self.profile = key, profile

    def compute(gs, scene, *, progress, on_profile, on_stage, stop=None):
        on_profile(Done(1))
        return Done(1)

    def hook(session, job, design):
        raise RuntimeError("a figure failed")

    s = Session(gearset, "sketch", Workspace(tmp_path), compute=compute, on_profile=hook)
    snap = s.computer.wait(s.submit(), profile=False, timeout=10)
    assert snap is not None and snap.done and snap.error is None and snap.design.key == 1
    assert "the profile hook failed" in caplog.text
    s.close()


def test_a_design_error_is_one_line_not_a_traceback(gearset):
    def failing(gs, scene, **k):
        raise GearSetError(["circular_spline.wire_radius_mm: the wire is too thick"])

    def buggy(gs, scene, **k):
        raise ZeroDivisionError("division by zero")

    for compute, expected in ((failing, "circular_spline.wire_radius_mm: the wire is too thick"),
                              (buggy, "internal error (ZeroDivisionError): division by zero")):
        c = Computer(compute)
        snap = c.wait(c.submit(gearset, "sketch"), profile=False, timeout=10)
        assert snap.done and snap.design is None and snap.error == expected
        c.close()


# ------------------------------------------------------------------ the workspace

@pytest.mark.parametrize("name", [
    "../outside.toml", "/etc/passwd.toml", "sets/../../outside.toml", ".hidden.toml", "a/.git/x.toml",
    "~/x.toml", "C:/x.toml", "a\\b.toml", "x.txt", "", "  ", "x\x00.toml", "sets/../../../etc/x.toml",
])
def test_the_workspace_refuses_names_outside_it(tmp_path, name):
    ws = Workspace(tmp_path)
    with pytest.raises(WorkspaceError, match="file name"):
        ws.path(name)


def test_a_link_out_of_the_workspace_is_refused(tmp_path, gearset):
    (tmp_path / "ws").mkdir()
    (tmp_path / "elsewhere").mkdir()
    ws = Workspace(tmp_path / "ws")
    ws.save(gearset, "mine.toml")
    os.symlink(tmp_path / "elsewhere", tmp_path / "ws" / "link")
    with pytest.raises(WorkspaceError, match="resolves outside the workspace"):
        ws.path("link/x.toml")
    with pytest.raises(WorkspaceError, match="resolves outside the workspace"):
        ws.save(gearset, "link/x.toml")
    assert not list((tmp_path / "elsewhere").iterdir())
    assert ws.gearset_files() == ["mine.toml"]


def test_save_and_load_round_trip_inside_the_workspace(tmp_path, gearset):
    ws = Workspace(tmp_path)
    changed = gearset.with_values({"tooth.addendum_coefficient": 0.85})
    (tmp_path / "sets").mkdir()
    path = ws.save(changed, "sets/a.toml")
    assert path == tmp_path.resolve() / "sets" / "a.toml"
    back = ws.load("sets/a.toml")
    assert back.to_dict() == changed.to_dict()
    with pytest.raises(WorkspaceError, match="no such file"):
        ws.load("sets/b.toml")
    with pytest.raises(WorkspaceError, match="not a folder"):
        Workspace(tmp_path / "nope")


# ------------------------------------------------------------------ the form is the reader's schema

def test_every_numeric_range_the_form_shows_is_the_one_the_reader_enforces(gearset):
    fields = schema.form_fields(gearset)
    numeric = [f for f in fields if f.kind in ("number", "integer") and f.hi is not None and f.lo is not None]
    assert len(numeric) >= 15
    for f in numeric:
        beyond = f.hi + max(1.0, abs(f.hi))
        if f.kind == "integer":
            beyond = int(math.ceil(beyond))
        with pytest.raises(GearSetError) as err:
            gearset.with_values({f.path: beyond})
        assert any(line.startswith(f"{f.path} = ") for line in err.value.problems), (f.path, err.value.problems)


def test_the_form_lists_the_sliders_and_the_documented_fields(gearset):
    fields = {f.path: f for f in schema.form_fields(gearset)}
    for path in ("wave_generator.deflection_coefficient", "tooth.pressure_angle_deg", "tooth.addendum_coefficient",
                 "tooth.dedendum_coefficient", "gear.rim_thickness_mm", "torque.rated_nm"):
        assert fields[path].slider
    assert fields["gear.module_mm"].unit == "mm" and fields["torque.rated_nm"].unit == "N·m"
    assert fields["tooth.kind"].choices == ("dcta", "involute", "points")
    assert fields["gear.module_mm"].doc  # the meaning from the schema's table


def test_errors_land_under_the_fields_they_name():
    exc = GearSetError(["gear.module_mm = -1 mm: must be in [1e-05, 10]",
                        "tooth.addendum_mm, tooth.addendum_coefficient: give at most one of the two",
                        "something about the whole set"])
    out = schema.errors_by_field(exc, ["gear.module_mm", "tooth.addendum_mm", "tooth.addendum_coefficient"])
    assert out["gear.module_mm"].startswith("gear.module_mm = -1 mm")
    assert out["tooth.addendum_mm"] == out["tooth.addendum_coefficient"]
    assert out[""] == "something about the whole set"


def test_the_real_computation_is_dropped_when_superseded(gearset):
    """Through profilegen.design itself: the first request is abandoned at a stage boundary."""
    c = Computer()
    first = c.submit(gearset, "sketch")
    time.sleep(0.05)
    second = c.submit(gearset.with_values({"wave_generator.deflection_coefficient": 1.05}), "sketch")
    snap = c.wait(second, profile=False, timeout=120)
    assert snap.error is None and snap.design.gearset.wave_generator.deflection_coefficient == 1.05
    assert c.wait(first, timeout=0) is None
    c.close()


def test_loading_a_bundled_set_by_name_and_refusing_another_name(gearset, tmp_path):
    s = Session(gearset.with_values({"wave_generator.deflection_coefficient": 1.1}), "sketch", Workspace(tmp_path),
                compute=_never)
    s.load("bundled:default")
    assert s.gearset.wave_generator.deflection_coefficient == 1.0 and s.history.can_undo
    with pytest.raises(WorkspaceError, match="no bundled gear set"):
        s.load("bundled:../../etc/passwd")
