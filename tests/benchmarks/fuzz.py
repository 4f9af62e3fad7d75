"""The gear-set fuzz at benchmark size: 10 000 hypothesis examples (or more) through the sketch
pipeline, spread over worker processes, each with its own seed.

    python tests/benchmarks/fuzz.py [--examples 10000] [--workers 2]

Every example must end in a result whose outputs are finite (no NaN or infinity in the design's
JSON, outline, fitted profile, stage times or stresses) or in a named ProfilegenError. Unlike the
test (``tests/property/test_pipeline_fuzz.py``, 1 000 examples, derandomized), a crash does not
stop the run: it is recorded with its traceback and the gear set that caused it. Writes
export/bench/fuzz.json (outcome counts, crashes, the slowest examples, times) and prints a
summary; exits 1 if any example crashed or returned a non-finite output.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
import traceback
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))


def _worker(args: tuple[int, int]) -> dict:
    """Run ``n`` examples with hypothesis seed ``seed``: outcome counts, crashes, times."""
    n, seed = args
    from hypothesis import HealthCheck, given, settings
    from hypothesis import seed as hseed

    from tests.property.gearsets import gear_sets
    from tests.property.test_pipeline_fuzz import outcome

    counts: Counter = Counter()
    crashes: list[dict] = []
    times: list[tuple[float, str]] = []

    @hseed(seed)
    @settings(max_examples=n, deadline=None, database=None, derandomize=False,
              suppress_health_check=list(HealthCheck))
    @given(gear_sets())
    def run(data):
        t0 = time.perf_counter()
        try:
            name = outcome(data)
        except AssertionError as exc:  # a non-finite output (or an unnamed error message)
            name = "NON-FINITE"
            crashes.append({"kind": name, "error": repr(exc), "traceback": traceback.format_exc(), "gearset": data})
        except Exception as exc:  # noqa: BLE001 — the fuzz records every crash and goes on
            name = "CRASH"
            crashes.append({"kind": name, "error": repr(exc), "traceback": traceback.format_exc(), "gearset": data})
        counts[name] += 1
        times.append((time.perf_counter() - t0, name))

    run()
    return {"counts": dict(counts), "crashes": crashes, "times": times}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=10_000, help="examples in all (default 10 000)")
    ap.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--seed", type=int, default=20261124, help="base hypothesis seed")
    ap.add_argument("--out", default=str(ROOT / "export" / "bench"), help="output folder")
    args = ap.parse_args()
    if args.examples < 1 or args.workers < 1:
        ap.error("--examples and --workers must be ≥ 1")
    chunks = 4 * args.workers  # several chunks per worker: a progress line per chunk
    sizes = [args.examples // chunks + (k < args.examples % chunks) for k in range(chunks)]
    jobs = [(n, args.seed + k) for k, n in enumerate(sizes) if n]
    t0 = time.perf_counter()
    counts: Counter = Counter()
    crashes, times = [], []
    with ProcessPoolExecutor(args.workers) as pool:
        for k, part in enumerate(pool.map(_worker, jobs), start=1):
            counts.update(part["counts"])
            crashes += part["crashes"]
            times += part["times"]
            print(f"[{k}/{len(jobs)}] {sum(counts.values())} examples, {time.perf_counter() - t0:.0f} s: "
                  f"{dict(counts.most_common())}", flush=True)
    wall = time.perf_counter() - t0
    per = [t for t, _ in times]
    ok = [t for t, name in times if name == "ok"]
    summary = {
        "command": "python tests/benchmarks/fuzz.py " + " ".join(sys.argv[1:]),
        "examples": sum(counts.values()),
        "workers": args.workers,
        "wall_s": wall,
        "outcomes": dict(counts.most_common()),
        "crashes": crashes,
        "time_per_example_s": {"median": statistics.median(per), "mean": statistics.fmean(per), "max": max(per)},
        "time_per_result_s": {"median": statistics.median(ok), "max": max(ok)} if ok else None,
    }
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "fuzz.json").write_text(json.dumps(summary, indent=1, default=str))
    print(f"{summary['examples']} examples in {wall:.0f} s on {args.workers} workers "
          f"(median {summary['time_per_example_s']['median'] * 1e3:.0f} ms, mean "
          f"{summary['time_per_example_s']['mean'] * 1e3:.0f} ms per example)")
    print("outcomes:", summary["outcomes"])
    print(f"crashes or non-finite outputs: {len(crashes)}" + "".join(
        f"\n  {c['kind']}: {c['error'][:200]}" for c in crashes[:10]))
    print(f"written: {out / 'fuzz.json'}")
    return 1 if crashes else 0


if __name__ == "__main__":
    raise SystemExit(main())
