"""The arc fit's cost against the tracing grid n_t (issue 26: work, not only memory): one design per
n_t, the flank's traced points and each stage's time.

    python tests/benchmarks/fit_points.py                          # seed002_short_cup, sketch, n_t 96 3000 30000 100000
    python tests/benchmarks/fit_points.py --scene design --n-t 96 100000 --set default

Run it under a memory cap (``ulimit -v 4000000``): n_t = 100 000 holds ~1.3 GB in the design scene.
The fit takes at most pipeline.FIT_POINTS_MAX of the flank's points.
"""

import argparse
import dataclasses
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import profilegen as pg  # noqa: E402
from profilegen.pipeline.scenes import SCENES  # noqa: E402


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", default="seed002_short_cup")
    ap.add_argument("--scene", default="sketch", choices=sorted(SCENES))
    ap.add_argument("--n-t", type=int, nargs="+", default=[96, 3000, 30000, 100000])
    a = ap.parse_args(argv)
    gs = pg.load_gearset(a.set)
    print(f"{a.set}, {a.scene} scene: n_t, wall s, flank points, stage times s")
    for n_t in a.n_t:
        t0 = time.perf_counter()
        d = pg.design(gs, scene=dataclasses.replace(SCENES[a.scene], n_t=n_t))
        wall = time.perf_counter() - t0
        stages = ", ".join(f"{s.stage} {s.time_s:.2f}" for s in d.stages)
        print(f"{n_t:>7} {wall:7.2f} {len(d.form.working_flank['right']):>7}  {stages}", flush=True)


if __name__ == "__main__":
    main()
