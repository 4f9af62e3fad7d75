"""How fast `profilegen sweep` stops on a signal: SIGINT and SIGTERM sent to the main
process alone and to its whole process group (a terminal's Ctrl-C), each while points are
running on 2 workers. Measures the time from the signal to the command's exit (and checks
the exit status, the one-line message, the journal and that no process is left).
Writes export/bench/sweep_interrupt.csv.

    python tests/benchmarks/sweep_interrupt.py [--repeat 3] [--workers 2]

The real command on the sketch scene (no wrapper): the signal comes once the journal has a
line, when both workers are in a design.
"""

from __future__ import annotations

import argparse
import csv
import importlib.util
import os
import resource
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("sweep_interrupt_test", ROOT / "tests/unit/test_sweep_interrupt.py")
_test = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_test)

CASES = (("SIGINT", False), ("SIGTERM", False), ("SIGINT", True), ("SIGTERM", True))


def one_run(tmp: Path, sig: int, group: bool, workers: int) -> dict:
    values = ", ".join(f"{0.8 + 0.01 * k:.2f}" for k in range(30))
    spec = tmp / "bench.toml"
    spec.write_text(f'name = "bench"\ngearset = "default"\nscene = "sketch"\n[grid]\n"{_test.FIELD}" = [{values}]\n')
    out = tmp / "out"
    proc = subprocess.Popen(["profilegen", "sweep", str(spec), "--out", str(out), "--workers", str(workers)],
                            cwd=tmp, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    try:
        _test._wait_for(lambda: len(_test._journal_rows(out / "journal.csv")) >= 1, proc, "a finished point")
        workers_seen = len(_test._children(proc.pid))
        t0 = time.perf_counter()
        (os.killpg if group else os.kill)(proc.pid, sig)
        _, err = proc.communicate(timeout=120)
        stop_s = time.perf_counter() - t0
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    err = err.decode()
    rows = _test._journal_rows(out / "journal.csv")
    return {"signal": signal.Signals(sig).name, "to": "group" if group else "main", "stop_s": stop_s,
            "exit": proc.returncode, "stderr_lines": len(err.splitlines()), "traceback": "Traceback" in err,
            "journal_points": len(rows), "workers_seen": workers_seen, "left": len(_test._group_alive(proc.pid))}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    load = os.getloadavg()[0]
    if load > 0.5:
        print(f"note: the machine is busy (load average {load:.2f} before the run): times are upper bounds", flush=True)
    runs = []
    for name, group in CASES:
        for _ in range(args.repeat):
            with tempfile.TemporaryDirectory() as tmp:
                r = one_run(Path(tmp), getattr(signal, name), group, args.workers)
            runs.append(r)
            print(f"{r['signal']:7s} to {r['to']:5s}: stopped in {r['stop_s']:.3f} s, exit {r['exit']}, "
                  f"{r['stderr_lines']} stderr line(s), traceback {r['traceback']}, {r['journal_points']} point(s) in "
                  f"the journal, {r['left']} process(es) left", flush=True)
    out = ROOT / "export" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    with (out / "sweep_interrupt.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(runs[0]) + ["load_before"], lineterminator="\n")
        w.writeheader()
        for r in runs:
            w.writerow({**r, "load_before": round(load, 2)})
    for name, group in CASES:
        times = [r["stop_s"] for r in runs if r["signal"] == name and r["to"] == ("group" if group else "main")]
        print(f"{name} to {'group' if group else 'main'}: median {statistics.median(times):.3f} s, "
              f"max {max(times):.3f} s over {len(times)} run(s)")
    print(f"wrote {out / 'sweep_interrupt.csv'}")


if __name__ == "__main__":
    sys.exit(main())
