"""The gear-set fuzz at benchmark size: 10 000 hypothesis examples (or more) through every scene
and into files, spread over worker processes, each chunk with its own seed.

    python tests/benchmarks/fuzz.py [--examples 10000] [--workers 2]
                                    [--design-share 0.03] [--verify-share 0.001] [--write-share 0.25]
    python tests/benchmarks/fuzz.py --replay export/bench/fuzz_failures/20261124-001.json

The gear sets are those of the CI test (``tests/property/test_pipeline_fuzz.py``): DCTA,
involute and point-list teeth (clean, noisy, crossing, looping), m 0.1–2 mm, z1 60–600, 2–4
waves, z2 − z1 = U or 2U, one draw in six with a spoiled field. Each example is designed in a
scene — ``sketch`` mostly, ``design`` with probability ``--design-share``, ``verify`` with
``--verify-share`` (a verify design takes ~40 s on the default set and several minutes at
z1 = 600, a design-scene one ~5–20 s, a sketch ~1 s) — and its files are written with
``write_design`` into a temporary folder (all design and verify results, with figures;
``--write-share`` of the sketch ones, without). Every worker runs under a 4 GB address-space cap (RLIMIT_AS) and
every example under a time limit, so a runaway is counted, not an OOM kill of the machine.

Outcomes: ``ok``; a named error (the ProfilegenError subclass); ``CRASH`` (any other exception,
a MemoryError under the cap included); ``NON-FINITE`` (NaN or infinity in the result or its
files); ``OVER-TIME`` (past ``--time-limit-s``, scaled ×3 for design and ×5 for verify). A
failure does not stop the run. Writes export/bench/fuzz.json (counts, times, failures),
export/bench/fuzz_failures.csv (one row per failing example: outcome, scene, tooth kind, time,
error, reproducer command) and export/bench/fuzz_failures/<seed>-<k>.json (the scene and gear
set of each, written when it fails, which ``--replay`` runs again in-process with the traceback
shown); prints the counts
table; exits 1 if any example failed.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import statistics
import sys
import time
import traceback
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

FAILURES = ("CRASH", "NON-FINITE", "OVER-TIME")
SCENE_TIME_FACTOR = {"sketch": 1.0, "design": 3.0, "verify": 5.0}


def _classify(data: dict, scene: str, limit_s: float, write: bool) -> tuple[str, str]:
    """(outcome, error text) of one example; runs it under ``time_limit``."""
    from tests.property.fuzzrun import OverTime, outcome, time_limit

    try:
        with time_limit(limit_s):
            return outcome(data, scene, figure=scene != "sketch", write=write), ""
    except OverTime as exc:
        return "OVER-TIME", str(exc)
    except AssertionError:
        return "NON-FINITE", traceback.format_exc()
    except Exception:  # noqa: BLE001 — the fuzz records every crash and goes on
        return "CRASH", traceback.format_exc()


def _worker(args: tuple[int, int, float, float, float, float, str]) -> dict:
    """Run ``n`` examples with hypothesis seed ``seed``: outcomes per (scene, kind), failures, times.
    Each failure is also written at once to ``fail_dir``/<seed>-<k>.json (a killed run keeps them)."""
    n, seed, design_share, verify_share, limit_s, write_share, fail_dir = args
    import logging

    from hypothesis import HealthCheck, given, settings
    from hypothesis import seed as hseed

    import numpy as np

    from tests.property.fuzzrun import memory_cap
    from tests.property.gearsets import KINDS, gear_sets

    logging.disable(logging.WARNING)
    rows: list[tuple[str, str, str, float]] = []  # scene, kind, outcome, seconds
    failures: list[dict] = []
    # the scene is not drawn by hypothesis (its integers lean to the low end): a seeded generator
    # gives the shares asked for
    rng = np.random.default_rng(seed)

    @hseed(seed)
    @settings(max_examples=n, deadline=None, database=None, derandomize=False,
              suppress_health_check=list(HealthCheck))
    @given(gear_sets())
    def run(data):
        r = rng.random()
        scene = "verify" if r < verify_share else "design" if r < verify_share + design_share else "sketch"
        tooth = data.get("tooth")
        kind = tooth.get("kind") if isinstance(tooth, dict) else None
        kind = kind if kind in KINDS else "spoiled"
        t0 = time.perf_counter()
        write = scene != "sketch" or rng.random() < write_share
        name, error = _classify(data, scene, limit_s * SCENE_TIME_FACTOR[scene], write)
        dt = time.perf_counter() - t0
        rows.append((scene, kind, name, dt))
        if name in FAILURES:
            fail = {"outcome": name, "scene": scene, "kind": kind, "seconds": dt, "error": error,
                    "seed": seed, "gearset": data}
            path = Path(fail_dir) / f"{seed}-{len(failures) + 1:03d}.json"
            path.write_text(json.dumps(fail, indent=1, default=str))
            failures.append(fail | {"path": str(path)})

    with memory_cap():
        run()
    return {"rows": rows, "failures": failures}


def _table(rows, key) -> str:
    """Counts of outcomes (columns) per ``key(row)`` (rows of the table), with totals."""
    groups = sorted({key(r) for r in rows})
    names = sorted({r[2] for r in rows}, key=lambda s: (s != "ok", s in FAILURES, s))
    width = max([len(n) for n in names] + [8])
    head = f"{'':>9} " + " ".join(f"{n:>{width}}" for n in names) + f" {'total':>7}"
    lines = [head]
    for g in groups + ["total"]:
        sel = [r for r in rows if g == "total" or key(r) == g]
        c = Counter(r[2] for r in sel)
        lines.append(f"{g:>9} " + " ".join(f"{c.get(n, 0):>{width}}" for n in names) + f" {len(sel):>7}")
    return "\n".join(lines)


def _replay(path: Path) -> int:
    from tests.property.fuzzrun import memory_cap, outcome

    case = json.loads(path.read_text())
    print(f"replaying {path}: scene {case['scene']}, tooth kind {case['kind']} (was {case['outcome']})")
    with memory_cap():
        t0 = time.perf_counter()
        name = outcome(case["gearset"], case["scene"], figure=case["scene"] != "sketch")  # raises on a failure
    print(f"outcome: {name} in {time.perf_counter() - t0:.1f} s")
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=10_000, help="examples in all (default 10 000)")
    ap.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--design-share", type=float, default=0.03, help="share of design-scene examples (0.03)")
    ap.add_argument("--verify-share", type=float, default=0.001, help="share of verify-scene examples (0.001)")
    ap.add_argument("--write-share", type=float, default=0.25,
                    help="share of sketch examples whose files are written (0.25; design and verify: all)")
    ap.add_argument("--time-limit-s", type=float, default=120.0,
                    help="per sketch example (×3 design, ×5 verify; default 120)")
    ap.add_argument("--seed", type=int, default=20261124, help="base hypothesis seed")
    ap.add_argument("--out", default=str(ROOT / "export" / "bench"), help="output folder")
    ap.add_argument("--replay", type=Path, help="run one failure file again and show its traceback")
    args = ap.parse_args()
    if args.replay:
        return _replay(args.replay)
    if args.examples < 1 or args.workers < 1:
        ap.error("--examples and --workers must be ≥ 1")
    if not (0 <= args.design_share and 0 <= args.verify_share and args.design_share + args.verify_share <= 1):
        ap.error("--design-share and --verify-share must be ≥ 0 with a sum ≤ 1")
    chunks = max(4 * args.workers, math.ceil(args.examples / 100))  # a progress line per ~100 examples
    sizes = [args.examples // chunks + (k < args.examples % chunks) for k in range(chunks)]
    out = Path(args.out)
    fail_dir = out / "fuzz_failures"
    fail_dir.mkdir(parents=True, exist_ok=True)
    for old in fail_dir.glob("*.json"):
        old.unlink()
    jobs = [(n, args.seed + k, args.design_share, args.verify_share, args.time_limit_s, args.write_share,
             str(fail_dir)) for k, n in enumerate(sizes) if n]
    t0 = time.perf_counter()
    rows: list[tuple] = []
    failures: list[dict] = []
    broken = ""
    try:
        with ProcessPoolExecutor(args.workers) as pool:
            for k, part in enumerate(pool.map(_worker, jobs), start=1):
                rows += part["rows"]
                failures += part["failures"]
                c = Counter(r[2] for r in rows)
                print(f"[{k}/{len(jobs)}] {len(rows)} examples, {time.perf_counter() - t0:.0f} s: "
                      f"ok {c.get('ok', 0)}, named {sum(v for n, v in c.items() if n != 'ok' and n not in FAILURES)}, "
                      f"failed {sum(c.get(n, 0) for n in FAILURES)}", flush=True)
    except BrokenProcessPool as exc:  # a worker killed from outside (the caps should prevent it)
        broken = f"a worker process died: {exc}"
        print(broken, flush=True)
    wall = time.perf_counter() - t0

    with open(out / "fuzz_failures.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["outcome", "scene", "tooth_kind", "seconds", "error", "reproducer"])
        for fail in failures:
            path = fail["path"]
            last = fail["error"].strip().splitlines()[-1] if fail["error"].strip() else ""
            w.writerow([fail["outcome"], fail["scene"], fail["kind"], f"{fail['seconds']:.1f}", last[:300],
                        f"python tests/benchmarks/fuzz.py --replay {path}"])

    per_scene = {}
    for scene in SCENE_TIME_FACTOR:
        t = [r[3] for r in rows if r[0] == scene]
        ok = [r[3] for r in rows if r[0] == scene and r[2] == "ok"]
        if t:
            per_scene[scene] = {"examples": len(t), "results": len(ok), "total_s": sum(t),
                                "median_s": statistics.median(t), "max_s": max(t),
                                "median_result_s": statistics.median(ok) if ok else None}
    summary = {
        "command": "python tests/benchmarks/fuzz.py " + " ".join(sys.argv[1:]),
        "examples": len(rows),
        "workers": args.workers,
        "wall_s": wall,
        "design_share": args.design_share,
        "verify_share": args.verify_share,
        "outcomes": dict(Counter(r[2] for r in rows).most_common()),
        "outcomes_by_scene": {s: dict(Counter(r[2] for r in rows if r[0] == s)) for s in SCENE_TIME_FACTOR},
        "outcomes_by_kind": {k: dict(Counter(r[2] for r in rows if r[1] == k)) for k in sorted({r[1] for r in rows})},
        "time_per_scene": per_scene,
        "failures": len(failures),
        "broken": broken,
    }
    (out / "fuzz.json").write_text(json.dumps(summary, indent=1, default=str))
    cpu = sum(r[3] for r in rows)
    print(f"\n{len(rows)} examples in {wall:.0f} s on {args.workers} workers ({cpu:.0f} s of example time)")
    print("\nby scene:\n" + _table(rows, key=lambda r: r[0]))
    print("\nby tooth kind:\n" + _table(rows, key=lambda r: r[1]))
    print("\ntime per example (s):")
    for scene, st in per_scene.items():
        print(f"  {scene:>6}: {st['examples']} examples, median {st['median_s']:.2f}, max {st['max_s']:.1f}, "
              f"total {st['total_s']:.0f}")
    print(f"\nfailures (crash, non-finite, over time): {len(failures)}" + "".join(
        f"\n  {f['outcome']} {f['scene']} {f['kind']}: {f['error'].strip().splitlines()[-1][:200] if f['error'].strip() else ''}"
        for f in failures[:10]))
    print(f"written: {out / 'fuzz.json'}, {out / 'fuzz_failures.csv'}")
    return 1 if failures or broken else 0


if __name__ == "__main__":
    raise SystemExit(main())
