"""Sweep benchmark: 100 sketch-scene designs of the default set (ω* from 0.80 to 1.05),
swept with 1 and 2 local worker processes; wall time of each (process start-up included),
per-point time and the scaling with workers. Writes export/bench/sweep.csv.

    python tests/benchmarks/sweep.py [--points 100] [--workers 1 2] [--repeat 1]

The issue's target: 100 sketch designs in ≤ 30 s on 2 cores.
"""

from __future__ import annotations

import argparse
import csv
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from profilegen.studies.sweep import parse_sweep_spec, run_sweep  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=100)
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--repeat", type=int, default=1, help="runs per worker count (the median is reported)")
    args = ap.parse_args()
    values = [round(float(v), 6) for v in np.linspace(0.80, 1.05, args.points)]
    spec = parse_sweep_spec({"name": "bench", "gearset": "default", "scene": "sketch",
                             "grid": {"wave_generator.deflection_coefficient": values}}, origin="<benchmark>")
    rows = []
    load = os.getloadavg()[0]
    if load > 0.5:
        print(f"note: the machine is busy (load average {load:.2f} before the run): times are upper bounds", flush=True)
    for workers in args.workers:
        times = []
        for _ in range(args.repeat):
            with tempfile.TemporaryDirectory() as tmp:
                t0 = time.perf_counter()
                result = run_sweep(spec, Path(tmp) / "out", workers=workers, figure=False)
                times.append(time.perf_counter() - t0)
        wall = statistics.median(times)
        design_s = [r["time_design_s"] for r in result.rows if r["time_design_s"] is not None]
        rows.append({"workers": workers, "points": len(result.rows), "ok": result.ok, "failed": result.failed,
                     "wall_s": wall, "per_point_s": wall / len(result.rows),
                     "median_design_s": statistics.median(design_s),
                     "sum_design_s": sum(design_s), "runs": len(times),
                     "load_before": round(load, 2), "cpus": os.cpu_count()})
        print(f"{workers} worker(s): {len(result.rows)} points ({result.ok} ok, {result.failed} failed) in {wall:.1f} s "
              f"wall ({wall / len(result.rows):.3f} s per point; design() median {statistics.median(design_s):.3f} s, "
              f"sum {sum(design_s):.1f} s)",
              flush=True)
    base = rows[0]["wall_s"] * rows[0]["workers"]
    for r in rows:
        r["speedup_vs_1"] = rows[0]["wall_s"] / r["wall_s"] if rows[0]["workers"] == 1 else None
        r["efficiency"] = base / (r["wall_s"] * r["workers"])
    for r in rows[1:]:
        print(f"scaling {rows[0]['workers']} → {r['workers']} workers: {rows[0]['wall_s'] / r['wall_s']:.2f}× "
              f"(parallel efficiency {r['efficiency']:.0%})")
    out = ROOT / "export" / "bench" / "sweep.csv"
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
