"""The figure workers' fork server (profilegen.output.forkserver): jobs run in processes forked
from one server that imported the preload list once; results, failures, cancelling, and ending
every process (server and workers) at once."""

from __future__ import annotations

import os
import sys
import time

import pytest

from profilegen.output.forkserver import ServerPool

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="fork and PR_SET_PDEATHSIG")


def _where() -> tuple[int, int, bool]:
    return os.getpid(), os.getppid(), "colorsys" in sys.modules


def _fail() -> None:
    raise ValueError("figure x: no data")


def _sleep(s: float) -> int:
    time.sleep(s)
    return os.getpid()


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split()[2] != "Z"
    except FileNotFoundError:
        return False


def test_jobs_run_in_workers_forked_from_the_server():
    sys.modules.pop("colorsys", None)  # a module this process has not loaded: the server imports it
    pool = ServerPool(2, preload=("colorsys",))
    try:
        a, b = pool.submit(_where), pool.submit(_where)
        (pa, server_a, pre_a), (pb, server_b, pre_b) = a.result(30), b.result(30)
        assert server_a == server_b == pool._proc.pid != os.getpid()  # the server is their parent
        assert pa != os.getpid() and pb != os.getpid()
        assert pre_a and pre_b and "colorsys" not in sys.modules  # inherited from the server's import
        with pytest.raises(ValueError, match="no data"):
            pool.submit(_fail).result(30)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
    assert pool._proc.exitcode == 0


def test_cancel_only_what_no_worker_has():
    pool = ServerPool(1)
    try:
        busy = pool.submit(_sleep, 1.0)
        queued = [pool.submit(_sleep, 0.0) for _ in range(4)]  # the executor queues at most 2 of them
        time.sleep(0.3)
        assert not busy.cancel()
        cancelled = [f.cancel() for f in queued]
        assert any(cancelled)
        assert busy.result(30) != os.getpid()
        for f, c in zip(queued, cancelled):
            assert f.cancelled() == c
            if not c:
                assert f.result(30) > 0
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def test_stop_ends_the_server_and_its_workers():
    pool = ServerPool(2)
    first = pool.submit(_sleep, 0.0).result(30)  # a worker is up
    running = pool.submit(_sleep, 60.0)
    time.sleep(0.3)
    pool.stop()  # how long it takes: tests/benchmarks/stop_latency.py
    assert pool._proc.exitcode is not None  # the server has ended when stop() returns
    assert running.exception(30) is not None  # the job failed (the pool is gone), not finished
    end = time.monotonic() + 5
    while _alive(first) and time.monotonic() < end:  # the worker dies with the server (PR_SET_PDEATHSIG)
        time.sleep(0.05)
    assert not _alive(first) and not _alive(pool._proc.pid)


def test_a_ctrl_c_while_the_figure_workers_start_ends_the_server(monkeypatch):
    """figure_workers() forks the server and hands it its first job before the caller's with-block
    owns it: an interrupt there ends the server (else the run's exit would wait for it forever)."""
    from profilegen.output import files, report

    made = []
    real = report._pool

    def pool(workers, matplotlib=True):
        made.append(real(workers, matplotlib))
        return made[-1]

    def interrupted(self, jobs):
        self._submit(next(iter(jobs.values())))  # the pool forks, then the Ctrl-C
        raise KeyboardInterrupt

    monkeypatch.setattr(report, "_pool", pool)
    monkeypatch.setattr(report.FigureWorkers, "submit", interrupted)
    with pytest.raises(KeyboardInterrupt):
        files.figure_workers(2, draw=True)
    assert len(made) == 1 and isinstance(made[0], ServerPool)
    assert made[0]._proc.exitcode is not None  # ended, not left waiting for work
