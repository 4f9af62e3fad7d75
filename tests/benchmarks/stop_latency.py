"""How fast the figure workers stop: an interrupt inside ``report.rendering`` (two workers in
minute-long figures) and ``ServerPool.stop()`` (the fork server with a job running). The unit
tests (tests/unit/test_report_speed.py, tests/unit/test_forkserver.py) check the behaviour —
the running figures are ended, not waited for, nothing is left — and no wall time; the times
are measured here, medians of ``--repeat`` runs. (`profilegen sweep`'s stop on a signal:
tests/benchmarks/sweep_interrupt.py.)

    python tests/benchmarks/stop_latency.py [--repeat 5]

Before this script the unit tests asserted < 30 s (rendering) and < 10 s (stop).
"""

from __future__ import annotations

import argparse
import multiprocessing
import statistics
import time

from profilegen.output import report
from profilegen.output.forkserver import ServerPool

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _slow_png(seconds: float) -> bytes:
    time.sleep(seconds)
    return PNG_MAGIC


def _sleep(seconds: float) -> int:
    time.sleep(seconds)
    return 0


def rendering_interrupt() -> float:
    """Seconds from the KeyboardInterrupt inside the block to its exit."""
    jobs = {"a": (_slow_png, (60.0,)), "b": (_slow_png, (60.0,))}
    t0 = None
    try:
        with report.rendering(jobs, workers=2):
            time.sleep(0.5)  # the workers have started their minute-long figures
            t0 = time.perf_counter()
            raise KeyboardInterrupt
    except KeyboardInterrupt:
        pass
    dt = time.perf_counter() - t0
    assert not multiprocessing.active_children(), "workers left"
    return dt


def server_stop() -> float:
    """Seconds ServerPool.stop() takes with a job running."""
    pool = ServerPool(2)
    pool.submit(_sleep, 0.0).result(30)
    pool.submit(_sleep, 60.0)
    time.sleep(0.3)
    t0 = time.perf_counter()
    pool.stop()
    return time.perf_counter() - t0


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    for name, fn in (("rendering interrupt", rendering_interrupt), ("ServerPool.stop", server_stop)):
        times = [fn() for _ in range(args.repeat)]
        print(f"{name:22s} median {statistics.median(times):.3f} s  (min {min(times):.3f}, max {max(times):.3f}, "
              f"n = {len(times)})")


if __name__ == "__main__":
    main()
