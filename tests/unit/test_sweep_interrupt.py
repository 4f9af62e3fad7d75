"""`profilegen sweep` stopped by a signal: SIGINT or SIGTERM to the main process alone, and
Ctrl-C to the whole process group. Each time the command must stop at once (not after the
running points), say so in one line on stderr with the conventional exit status (128 +
signal), leave a journal of complete lines and no process behind; run again, it resumes.

One point of the grid (``SLOW``) sleeps ten minutes in the worker that runs it (the
designer is wrapped in the child process, before the pool forks) and marks its end: a sweep
that waits for its running points instead of ending its workers leaves that mark (and cannot
exit before the hang guard below, a fifth of the sleep, runs out). No wall-time assertion: how
fast the command stops is tests/benchmarks/sweep_interrupt.py's measurement.
"""

from __future__ import annotations

import csv
import io
import os
import signal
import subprocess
import sys
import time
import zlib
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="signals and /proc: Linux")

FIELD = "wave_generator.deflection_coefficient"
SLOW = 0.95  # the point that sleeps; it is first, so a worker is in it when the others finish
FAST = [0.8, 1.0]  # designs that pass (at ω* = 1.05 the 0.25 mm wire's root fillet enters the FS tooth's swept region: FilletError)
STOP_WITHIN_S = 120.0  # a hang guard only (the slow point sleeps 600 s); the stop's speed is a benchmark
START_WITHIN_S = 90.0  # start-up and the first point, on a busy machine

# `profilegen sweep ...` (the CLI's main) with the designer wrapped: the SLOW point marks
# that it runs (a file) and sleeps; fork, so that the workers inherit the wrapper.
WRAPPER = f"""
import multiprocessing, os, sys, time
multiprocessing.set_start_method("fork", force=True)
import profilegen.pipeline.design as pipeline
_design = pipeline.design
def design(gearset, **kw):
    if abs(gearset.wave_generator.deflection_coefficient - {SLOW}) < 1e-9:
        open(os.environ["SLOW_MARK"], "w").close()
        time.sleep(600)
        open(os.environ["SLOW_MARK"] + ".end", "w").close()
    return _design(gearset, **kw)
pipeline.design = design
from profilegen.cli import main
sys.exit(main(sys.argv[1:]))
"""


def _spec(tmp_path: Path) -> Path:
    path = tmp_path / "stop.toml"
    values = ", ".join(repr(v) for v in [SLOW, *FAST])
    path.write_text(f'name = "stop"\ngearset = "default"\nscene = "sketch"\n[grid]\n"{FIELD}" = [{values}]\n')
    return path


def _journal_rows(path: Path) -> list[dict]:
    """The journal's rows, checking that every line is complete: it ends in a newline, has
    the header's cells, and its CRC (the last cell) is that of the other cells."""
    if not path.exists():
        return []
    raw = path.read_bytes()
    assert raw.endswith(b"\n"), "the journal ends in a cut line"
    records = list(csv.reader(io.StringIO(raw.decode())))
    header, body = records[0], records[1:]
    assert header[0] == "point_id" and header[-1] == "crc"
    for rec in body:
        assert len(rec) == len(header), f"a journal line has {len(rec)} cells, the header {len(header)}"
        assert f"{zlib.crc32(chr(31).join(rec[:-1]).encode()):08x}" == rec[-1], "a journal line's CRC is wrong"
    return [dict(zip(header, rec)) for rec in body]


def _group_alive(pgid: int) -> list[int]:
    """Processes (not zombies) in the process group ``pgid``, from /proc."""
    alive = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()  # after "pid (comm) ": state ppid pgrp ...
        if int(fields[2]) == pgid and fields[0] != "Z":
            alive.append(int(entry.name))
    return alive


def _children(pid: int) -> list:
    try:
        import psutil
    except ImportError:
        return []
    try:
        return psutil.Process(pid).children(recursive=True)
    except psutil.NoSuchProcess:
        return []


def _wait_for(condition, proc: subprocess.Popen, what: str) -> None:
    deadline = time.monotonic() + START_WITHIN_S
    while not condition():
        if proc.poll() is not None:
            out, err = proc.communicate()
            pytest.fail(f"the sweep ended (exit {proc.returncode}) before {what}: {err.decode()[-2000:]}")
        if time.monotonic() > deadline:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
            pytest.fail(f"no {what} within {START_WITHIN_S} s")
        time.sleep(0.05)


def _interrupt(tmp_path: Path, spec: Path, out: Path, sig: int, *, group: bool, new_point: bool) -> list[dict]:
    """Start the sweep, wait until the slow point runs (and, with ``new_point``, another
    point is finished), send ``sig`` to the main process (or its group); check how it
    stopped; return the journal's rows."""
    mark = tmp_path / "slow-point-running"
    mark.unlink(missing_ok=True)
    before = len(_journal_rows(out / "journal.csv")) if new_point else -1
    env = {**os.environ, "SLOW_MARK": str(mark)}
    proc = subprocess.Popen([sys.executable, "-c", WRAPPER, "sweep", str(spec), "--out", str(out), "--workers", "2"],
                            cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            start_new_session=True,  # its own process group (pgid = pid), as a shell job has
                            # SIGINT as a terminal gives it: a test run started in the background (`cmd &` in
                            # a script) ignores SIGINT, children inherit that, and Python keeps an inherited SIG_IGN
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        _wait_for(lambda: mark.exists() and len(_journal_rows(out / "journal.csv")) > before,
                  proc, "slow point running" + (" and a new finished point" if new_point else ""))
        workers = _children(proc.pid)
        (os.killpg if group else os.kill)(proc.pid, sig)
        try:
            _, err = proc.communicate(timeout=STOP_WITHIN_S)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
            pytest.fail(f"{signal.Signals(sig).name} to the {'group' if group else 'main process'}: "
                        f"the sweep did not stop within {STOP_WITHIN_S} s (the hang guard)")
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    err = err.decode()
    assert proc.returncode == 128 + sig, (proc.returncode, err)
    assert "Traceback" not in err, err
    lines = err.splitlines()
    assert len(lines) == 1 and signal.Signals(sig).name in lines[0] and "journal.csv" in lines[0], err
    assert not Path(str(mark) + ".end").exists(), "the sweep waited for its running point"
    assert _group_alive(proc.pid) == [], "processes of the sweep are left"
    assert not any(w.is_running() and w.status() != "zombie" for w in workers), "workers are left"
    return _journal_rows(out / "journal.csv")


def test_a_signal_stops_a_sweep_at_once_and_the_rerun_resumes(tmp_path):
    spec, out = _spec(tmp_path), tmp_path / "out"
    journal: list[dict] = []
    # the first run until a point is finished (to resume from); the others stop while starting
    for sig, group in ((signal.SIGINT, False), (signal.SIGTERM, False), (signal.SIGINT, True)):
        rows = _interrupt(tmp_path, spec, out, sig, group=group, new_point=not journal)
        assert rows[:len(journal)] == journal  # append-only: earlier points are kept as they were
        assert len(rows) >= 1 and all(r["status"] == "ok" for r in rows)
        assert str(SLOW) not in {r[FIELD] for r in rows}  # the slow point was stopped, not finished
        journal = rows
    # the plain command finishes the sweep and reuses every point of the journal
    done = subprocess.run(["profilegen", "sweep", str(spec), "--out", str(out), "--workers", "2"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    total = 1 + len(FAST)
    assert f"{total - len(journal)} run, {len(journal)} from the journal" in done.stdout, done.stdout
    final = _journal_rows(out / "journal.csv")
    assert final[:len(journal)] == journal and len(final) == total
    assert len({r["point_id"] for r in final}) == total  # no point ran twice
    with (out / "results.csv").open(newline="") as f:
        results = list(csv.DictReader(f))
    assert [float(r[FIELD]) for r in results] == [SLOW, *FAST] and all(r["status"] == "ok" for r in results)
