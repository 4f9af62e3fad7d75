"""How soon a superseded design stops, by the stage it is in (issue 31: ≤ 0.1 s anywhere): a fresh
:class:`profilegen.pipeline.engine.Engine` designs the default set in the design scene in a thread, and
``stop()`` turns True at a random moment; the time from then until :class:`Cancelled` is raised.

    python tests/benchmarks/face_cancel.py [-n 20] [--set default] [--scene design]

Prints each stop (the stage that was running, the latency) and the median and largest per stage.
"""

import argparse
import random
import statistics
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import profilegen as pg  # noqa: E402
from profilegen.pipeline.engine import Cancelled, Engine  # noqa: E402


def one(gs, scene: str, delay: float) -> tuple[str, float | None]:
    """(the stage running at the stop, seconds from the stop to Cancelled; None: it finished first)."""
    stage, asked, ended = ["start"], [0.0], [None]
    flag = threading.Event()

    def run():
        try:
            Engine().design(gs, scene=scene, progress=lambda name: stage.__setitem__(0, name), stop=flag.is_set)
        except Cancelled:
            ended[0] = time.perf_counter()

    t = threading.Thread(target=run)
    t.start()
    time.sleep(delay)
    asked[0] = time.perf_counter()
    running = stage[0]
    flag.set()
    t.join()
    return running, None if ended[0] is None else ended[0] - asked[0]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=20)
    ap.add_argument("--set", default="default")
    ap.add_argument("--scene", default="design")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args(argv)
    gs = pg.load_gearset(a.set)
    t0 = time.perf_counter()
    pg.design(gs, scene=a.scene)  # imports and first calls out of the way; its wall time bounds the delays
    wall = time.perf_counter() - t0
    rnd = random.Random(a.seed)
    by: dict[str, list[float]] = {}
    for _ in range(a.n):
        running, lat = one(gs, a.scene, rnd.uniform(0.05, wall))
        print(f"{running[:60]:60s} {'finished first' if lat is None else f'{lat * 1e3:8.1f} ms'}", flush=True)
        if lat is not None:
            by.setdefault(running.split(":")[0][:40], []).append(lat)
    print(f"\n{'stage':40s} {'stops':>5s} {'median ms':>10s} {'largest ms':>10s}")
    for name, lats in by.items():
        print(f"{name:40s} {len(lats):5d} {statistics.median(lats) * 1e3:10.1f} {max(lats) * 1e3:10.1f}")


if __name__ == "__main__":
    main()
