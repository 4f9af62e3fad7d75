"""The incremental engine's speed (issue 31 "Must show"): from a field's change to the new design,
warm, through :class:`profilegen.Engine` (cached) and :func:`profilegen.design` (uncached, same
warm process), and through the cold command line — medians and ratios, in one run.

    python tests/benchmarks/engine.py [-n 5] [--cli 3] [--cases sketch_tooth,design_torque,design_tooth]
                                      [--cancel 8]

Cases (the default set, ``profiles/default.toml``):

* ``sketch_tooth``: the DCTA pressure angle changed (10° × (1 + 0.002 k)), sketch scene;
* ``design_torque``: the rated torque changed (265 N·m × (1 + 0.02 k)), design scene;
* ``design_tooth``: the pressure angle changed, design scene.

Each change is a new value (k = 1..n), so every cached design is a real change, after one warm-up
design of the base set in the engine (its cache warm) and one uncached (imports, JIT-free numpy
caches). The uncached designs get the same gear sets in the same order. The cold CLI runs
``python -m profilegen design FILE --scene S --out TMP -q`` on the changed set's TOML, ``--cli``
times each (subprocess wall time: imports, stages, files). Every cached design's design.json is
compared with its uncached one (``engine_identity.comparable``) and the stages the engine ran
are printed. The stages' own memos (arcfit's, the contact compliance's) are cleared before each
timed design: otherwise the uncached design of the same set, right after the cached one, would
reuse its fits. The machine's load average is printed with each case: the host is shared.

``--cancel``: the time from :meth:`Engine.cancel` to the running design raising
:class:`profilegen.pipeline.engine.Cancelled`, a tooth change cancelled at a random moment, per scene.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from tests.benchmarks.engine_identity import comparable, first_difference  # noqa: E402

CASES = {
    "sketch_tooth": ("sketch", "tooth.pressure_angle_deg", 0.002),
    "design_torque": ("design", "torque.rated_nm", 0.02),
    "design_tooth": ("design", "tooth.pressure_angle_deg", 0.002),
}


def _cli_seconds(gs, scene: str, work: Path) -> tuple[float, float]:
    from profilegen.output.optimize import write_gearset_toml

    path = write_gearset_toml(gs.to_dict(), work / f"{gs.name}.toml")
    out = work / f"out{time.monotonic_ns()}"
    t0, c0 = time.perf_counter(), _children_cpu()
    res = subprocess.run([sys.executable, "-m", "profilegen", "design", str(path), "--scene", scene, "--out", str(out),
                          "-q"], capture_output=True, text=True, cwd=work)
    wall, cpu = time.perf_counter() - t0, _children_cpu() - c0
    if res.returncode != 0 and "FAIL" not in res.stderr and "INCOMPLETE" not in res.stderr:
        raise RuntimeError(f"profilegen design failed: {res.stderr[-500:]}")
    return wall, cpu


def _forget_inner_caches() -> None:
    """The stages' own memos (the arc fit's least-squares and minimax stages by the flank's bytes,
    the contact's condensed pitches): the design just before had the same inputs, and the second
    would find them — which neither an edit in the app nor the cold CLI does."""
    from profilegen.profile import arcfit
    from profilegen.contact import compliance

    arcfit.clear_cache()
    compliance.clear_cache()


def _children_cpu() -> float:
    import resource

    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def cancel_latency(engine, gs, scene: str, delay_s: float) -> float | None:
    """Seconds from :meth:`Engine.cancel` (``delay_s`` after a design of ``gs`` started in a thread)
    to that design raising Cancelled; None when it finished first."""
    import threading

    from profilegen.pipeline.engine import Cancelled

    done = {}

    def work():
        try:
            engine.design(gs, scene=scene)
        except Cancelled:
            done["t"] = time.perf_counter()

    th = threading.Thread(target=work)
    th.start()
    time.sleep(delay_s)
    t0 = time.perf_counter()
    engine.cancel()
    th.join()
    return done["t"] - t0 if "t" in done else None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-n", type=int, default=5, help="changes per case")
    ap.add_argument("--cli", type=int, default=3, help="cold CLI runs per case (0: none)")
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--cancel", type=int, default=8, help="cancellation trials per scene (0: none)")
    ap.add_argument("--cancel-scenes", default="sketch,design")
    args = ap.parse_args(argv)

    import profilegen as pg

    base = pg.load_gearset(pg.default_gearset_path())
    rows, bad = [], 0
    with tempfile.TemporaryDirectory() as tmp:
        for case in args.cases.split(","):
            scene, field, step = CASES[case]
            value = base.to_dict()[field.split(".")[0]][field.split(".")[1]]
            changed = [base.with_values({field: value * (1 + step * k)}) for k in range(1, args.n + 1)]
            engine = pg.Engine()
            engine.design(base, scene=scene)  # warm: the base set's stages in the cache
            pg.design(base, scene=scene)
            load = os.getloadavg()[0]
            cached, plain, ran, sizes, cached_cpu, plain_cpu = [], [], set(), [], [], []
            for gs in changed:
                _forget_inner_caches()
                t0, c0 = time.perf_counter(), time.process_time()
                d = engine.design(gs, scene=scene)
                cached.append(time.perf_counter() - t0)
                cached_cpu.append(time.process_time() - c0)
                ran.add(engine.last_run)
                _forget_inner_caches()
                t0, c0 = time.perf_counter(), time.process_time()
                ref = pg.design(gs, scene=scene)
                plain.append(time.perf_counter() - t0)
                plain_cpu.append(time.process_time() - c0)
                diff = first_difference(comparable(d), comparable(ref))
                if diff:
                    bad += 1
                    print(f"DIFFERENCE {case} {gs.to_dict()[field.split('.')[0]]}: {diff}")
            sizes.append(engine.stats()["bytes"])
            cli = [_cli_seconds(gs, scene, Path(tmp)) for gs in changed[: args.cli]]
            nan = float("nan")
            row = {"case": case, "cached": statistics.median(cached), "uncached": statistics.median(plain),
                   "cli": statistics.median(c[0] for c in cli) if cli else nan,
                   "cached_cpu": statistics.median(cached_cpu), "uncached_cpu": statistics.median(plain_cpu),
                   "cli_cpu": statistics.median(c[1] for c in cli) if cli else nan,
                   "load": load, "ran": sorted(ran), "cache_mb": sizes[-1] / 1e6}
            rows.append(row)
            print(f"{case}: wall cached {row['cached']:.3f} s, uncached {row['uncached']:.3f} s, cold CLI {row['cli']:.2f} s; "
                  f"CPU {row['cached_cpu']:.3f} / {row['uncached_cpu']:.3f} / {row['cli_cpu']:.2f} s (medians of "
                  f"{len(cached)}/{len(plain)}/{len(cli)}; load {load:.1f}); engine ran {sorted(ran)}; "
                  f"cache {row['cache_mb']:.0f} MB", flush=True)
    print()
    for what, suffix in (("wall", ""), ("CPU (the host is shared: wall times stretch with its load)", "_cpu")):
        print(f"{what}:")
        print(f"  {'case':15s} {'cached s':>9s} {'uncached s':>11s} {'cold CLI s':>11s} {'uncached/cached':>16s} "
              f"{'CLI/cached':>11s}")
        for r in rows:
            c, u, k = r["cached" + suffix], r["uncached" + suffix], r["cli" + suffix]
            print(f"  {r['case']:15s} {c:9.3f} {u:11.3f} {k:11.2f} {u / c:16.1f} {k / c:11.1f}")
    print(f"design.json identical cached vs uncached: {'yes' if not bad else f'NO ({bad} differ)'}")
    if args.cancel:
        import random

        rng = random.Random(7)
        for scene, span in (("sketch", 1.0), ("design", 8.0)):
            if scene not in args.cancel_scenes.split(","):
                continue
            lat = []
            engine = pg.Engine()
            engine.design(base, scene=scene)
            for k in range(args.cancel):  # each a new tooth: nothing cached from the tooth on
                gs = base.with_values({"tooth.pressure_angle_deg": 10.0 * (1 - 0.003 * (k + 1))})
                t = cancel_latency(engine, gs, scene, rng.uniform(0.0, span))
                if t is not None:
                    lat.append(t)
            if lat:
                print(f"cancel -> Cancelled, {scene} scene, a tooth change cancelled at a random time in the first "
                      f"{span:g} s: median {statistics.median(lat):.3f} s, max {max(lat):.3f} s ({len(lat)} of "
                      f"{args.cancel} were still running)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
