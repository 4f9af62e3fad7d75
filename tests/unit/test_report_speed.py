"""The design's pictures are drawn once, in worker processes or here, with the same bytes:
report.png_jobs / report.rendering and write_design's use of them (issue 14, item 2).

No timings here (they are in tests/benchmarks/end_to_end.py): these tests check that a figure
drawn in a worker is the figure drawn in this process, that both reports embed the files' PNGs
instead of drawing their own, that a pool that cannot start or a worker that dies falls back
to drawing here, and that an interrupted block leaves no worker behind.
"""

from __future__ import annotations

import base64
import multiprocessing
import os
import re
import time

import pytest

import profilegen as pg
from profilegen.output import report
from profilegen.gearset import default_gearset_path, load_gearset

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def sketch():
    """A sketch design of the default set with the loaded contact and the stresses."""
    return pg.design(load_gearset(default_gearset_path()), scene="sketch", contact=True)


def _embedded(page: str) -> list[bytes]:
    # <img> tags only: the embedded plotly.js holds a data-URI PNG of its own
    return [base64.b64decode(m) for m in re.findall(r'<img src="data:image/png;base64,([^"]*)"', page)]


def _png_size(data: bytes) -> tuple[int, int]:
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def test_png_jobs_name_every_picture_of_the_files(sketch):
    jobs = report.png_jobs(sketch)
    assert set(jobs) == {"stress", "contact", "torsional", "envelope", "fit_profile", "fit_error", "fit_clearance"}
    # no FEM rim in the sketch scene: no deformation figures; without stress and contact, none of theirs
    from dataclasses import replace

    bare = report.png_jobs(replace(sketch, contact=None, stress=None, torsional=None))
    assert set(bare) == {"envelope", "fit_profile", "fit_error", "fit_clearance"}


def _slow_png(seconds: float) -> bytes:
    time.sleep(seconds)
    return PNG_MAGIC


def _die_in_worker(parent: int) -> bytes:
    if os.getpid() != parent:
        os._exit(3)  # the worker dies without a word
    return PNG_MAGIC + b"drawn here"


def _pid() -> int:
    return os.getpid()


def test_workers_draw_the_bytes_this_process_draws(sketch):
    jobs = report.png_jobs(sketch)
    chosen = {k: jobs[k] for k in ("stress", "fit_error", "envelope")}
    with report.rendering(chosen, workers=0) as collect:
        here = collect()
    with report.rendering(chosen, workers=2) as collect:
        there = collect()
    assert set(here) == set(chosen) and here == there
    for name, data in here.items():
        assert data[:8] == PNG_MAGIC, name
    assert _png_size(here["stress"]) == (13 * 120, 8 * 120)  # 13 x 8 in at 120 dpi
    assert _png_size(here["envelope"]) == (round(7.2 * 150), round(4.3 * 150))


def test_workers_are_other_processes():
    with report.rendering({"a": (_pid, ()), "b": (_pid, ())}, workers=2) as collect:
        pids = collect()
    assert os.getpid() not in pids.values()
    with report.rendering({"a": (_pid, ())}, workers=0) as collect:
        assert collect() == {"a": os.getpid()}


def test_no_pool_draws_here(monkeypatch):
    def no_fork(method=None):
        raise ValueError(f"cannot find context for {method!r}")

    monkeypatch.setattr(multiprocessing, "get_context", no_fork)
    with report.rendering({"a": (_pid, ()), "b": (_pid, ())}, workers=2) as collect:
        assert collect() == {"a": os.getpid(), "b": os.getpid()}


def test_a_dead_worker_is_drawn_here(caplog):
    jobs = {"dies": (_die_in_worker, (os.getpid(),)), "fine": (_slow_png, (0.0,))}
    with caplog.at_level("WARNING", logger="profilegen.output.report"):
        with report.rendering(jobs, workers=1) as collect:
            images = collect()
    assert images["dies"] == PNG_MAGIC + b"drawn here"
    assert images["fine"] == PNG_MAGIC
    assert any("figure dies" in r.getMessage() for r in caplog.records)


def _marked_png(seconds: float, mark: str) -> bytes:
    """A figure that marks its start, takes ``seconds`` and marks its end (files named ``mark``)."""
    with open(mark + ".start", "w"):
        pass
    time.sleep(seconds)
    with open(mark + ".end", "w"):
        pass
    return PNG_MAGIC


def test_an_interrupted_block_ends_its_workers(tmp_path):
    """An interrupt inside the block ends the running figures instead of waiting for them: the
    workers' minute-long figures never reach their end mark, and no worker is left. (How long the
    exit takes is a benchmark: tests/benchmarks/stop_latency.py.)"""
    before = {p.pid for p in multiprocessing.active_children()}
    marks = [str(tmp_path / name) for name in ("a", "b")]
    jobs = {name: (_marked_png, (60.0, mark)) for name, mark in zip(("a", "b"), marks)}
    with pytest.raises(KeyboardInterrupt):
        with report.rendering(jobs, workers=2):
            deadline = time.monotonic() + 60.0  # a hang guard: the workers start their figures
            while not all(os.path.exists(m + ".start") for m in marks) and time.monotonic() < deadline:
                time.sleep(0.02)
            raise KeyboardInterrupt
    left = {p.pid for p in multiprocessing.active_children()} - before
    assert not left
    started = [os.path.exists(m + ".start") for m in marks]
    assert any(started)  # the interrupt came while a worker was in its figure
    assert not any(os.path.exists(m + ".end") for m in marks)  # ended, not waited for


def test_the_workers_env_variable(monkeypatch, caplog):
    monkeypatch.setenv(report.WORKERS_ENV, "0")
    assert report._default_workers() == 0
    monkeypatch.setenv(report.WORKERS_ENV, "3")
    assert report._default_workers() == 3
    monkeypatch.setenv(report.WORKERS_ENV, "many")
    with caplog.at_level("WARNING", logger="profilegen.output.report"):
        assert report._default_workers() in (0, 1, 2)
    assert any(report.WORKERS_ENV in r.getMessage() for r in caplog.records)


@pytest.mark.parametrize("workers", ["0", "2"])
def test_reports_embed_the_files_pictures(sketch, tmp_path, monkeypatch, workers):
    """Each picture drawn once: report.html embeds contact.png and stress.png as written, and the
    fit report's profile and error pictures are the design report's; with and without workers."""
    monkeypatch.setenv(report.WORKERS_ENV, workers)
    out = tmp_path / "out"
    pg.write_design(sketch, out, draw=True)  # the sketch scene draws no figures unless asked
    page = _embedded((out / "report.html").read_text(encoding="utf-8"))
    fit = _embedded((out / "fit_report.html").read_text(encoding="utf-8"))
    assert len(fit) == 3  # error, profile, clearance (no FEM rim in the sketch scene)
    assert len(page) == 5  # profile, error, torsional (the whole gear, first), contact (the mesh), stress
    assert page[0] == fit[1] and page[1] == fit[0]
    assert page[2] == (out / "torsional.png").read_bytes()
    assert page[3] == (out / "contact.png").read_bytes()
    assert page[4] == (out / "stress.png").read_bytes()
    for name in ("envelope", "contact", "torsional", "stress"):
        assert (out / f"{name}.png").read_bytes()[:8] == PNG_MAGIC


def test_html_pieces_made_anywhere_give_the_same_report(sketch):
    """report.html's slow pieces (html_jobs) made in the workers, taken back by the caller, or
    made inside design_report_html: the same page."""
    pieces = report.html_jobs(sketch)
    assert set(pieces) == {"cs_figure"}
    images = {k: f(*a) for k, (f, a) in report.png_jobs(sketch).items()}
    plain = report.design_report_html(sketch, images=images)
    with report.rendering(pieces, workers=2) as collect:
        made = collect()
    assert report.design_report_html(sketch, images={**images, **made}) == plain
    from dataclasses import replace

    assert report.html_jobs(replace(sketch, stress=None)) == {}  # no report.html without the stresses


def _pid_when(marker: str, started: str | None = None) -> int:
    """This process's id, once ``marker`` exists (30 s at most); ``started`` is created first
    (the job has begun)."""
    if started is not None:
        open(started, "w").close()
    end = time.monotonic() + 30.0
    while not os.path.exists(marker) and time.monotonic() < end:
        time.sleep(0.01)
    return os.getpid()


def test_collect_takes_back_the_pieces_no_worker_started(tmp_path):
    """steal: a job still waiting for a worker when collect() is called is made in this process
    (the caller would only wait); one a worker has begun is left to it; the order is the jobs'.
    The busy job ends only when a timer releases it, long after collect() has taken its pick (a
    fixed sleep let a descheduled test find every job done on a loaded CI machine), and collect()
    is called only once the worker has begun it."""
    import threading

    marker, started = str(tmp_path / "release"), str(tmp_path / "started")
    # three jobs behind the busy one: the executor's call queue holds max_workers + 1 = 2 of them
    # (both can be queued once the worker has taken "busy"), so at least one is still pending
    jobs = {"busy": (_pid_when, (marker, started)), "waiting": (_pid, ()), "also": (_pid, ()), "third": (_pid, ())}
    release = threading.Timer(3.0, lambda: open(marker, "w").close())
    with report.rendering(jobs, workers=1, steal=("waiting", "also", "third")) as collect:
        # the one worker runs "busy"; the others wait behind it (or sit in its queue). Wait until it
        # has begun: a fixed 0.3 s let a worker still starting on a loaded machine take every job
        end = time.monotonic() + 30.0
        while not os.path.exists(started) and time.monotonic() < end:
            time.sleep(0.01)
        release.start()
        try:
            out = collect()
        finally:
            release.cancel()
            open(marker, "w").close()
    assert list(out) == list(jobs)
    assert out["busy"] != os.getpid()
    assert os.getpid() in (out["waiting"], out["also"], out["third"])  # at most two are queued to the worker
    with report.rendering({"a": (_pid, ())}, workers=0, steal=("a",)) as collect:
        assert collect() == {"a": os.getpid()}


def test_figures_handed_over_during_the_stages_are_the_files_figures(tmp_path, monkeypatch):
    """The CLI's path: figure workers open before design(), the profile's figures handed over by
    on_profile while the contact and stresses run, the rest by write_design. Every file is the one
    the plain path writes (figures drawn in this process, after the stages), byte for byte."""
    from profilegen.output.files import figure_workers, profile_figures

    gs = load_gearset(default_gearset_path())
    seen = []

    def early(partial):
        seen.append((partial.contact, partial.stress, partial.profile is not None))
        profile_figures(figures, partial, draw=True)

    with figure_workers(2) as figures:
        result = pg.design(gs, scene="sketch", on_profile=early)
        pg.write_design(result, tmp_path / "early", figures=figures, draw=True)
    assert seen == [(None, None, True)] and result.stress is not None  # once: with the profile, before the stresses
    monkeypatch.setenv(report.WORKERS_ENV, "0")
    pg.write_design(result, tmp_path / "plain", draw=True)
    early_files = sorted(p.name for p in (tmp_path / "early").iterdir())
    assert early_files == sorted(p.name for p in (tmp_path / "plain").iterdir())
    for name in early_files:
        if name != "design.json":  # its write time differs
            assert (tmp_path / "early" / name).read_bytes() == (tmp_path / "plain" / name).read_bytes(), name
