"""Issue 18's must-show: `profilegen optimize` on the default set within a budget on 2 cores.

    python tests/benchmarks/optimize.py                       # the bundled spec, 2 workers
    python tests/benchmarks/optimize.py --population 16 --generations 12 --reproduce 3
    python tests/benchmarks/optimize.py --dask-local          # the same run on a Dask LocalCluster too

Prints the wall time, the front, the designs that dominate the starting design with the
improvement in each objective (confirmed in the confirm scene) and their clearances; with
``--reproduce K`` runs ``profilegen design`` on K of the front's gear-set files and compares
its design.json (read independently of the optimiser's extraction) with the confirmed values;
with ``--dask-local`` runs the same seeded search on a ``distributed.LocalCluster`` (2 worker
processes, 1 thread each) and compares its candidates and front with the process pool's.
Writes into ``--out`` (default export/bench/optimize/). Not collected by pytest.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def design_json_outputs(d: dict) -> dict:
    """Outputs read from a design.json (the file `profilegen design` writes), not through outputs_of."""
    out = {"min_clearance_mm": d.get("min_clearance_mm")}
    if d.get("profile"):
        out["profile_max_error_mm"] = d["profile"]["max_error_mm"]
        out["profile_min_clearance_mm"] = d["profile"]["min_clearance_mm"]
        out["profile_max_backlash_mm"] = d["profile"]["max_backlash_mm"]
    if d.get("stress"):
        safety = {k: v for k, v in d["stress"]["safety"].items() if v is not None}
        out["stress_min_safety"] = min(safety.values()) if safety else None
        for k, v in safety.items():
            out["safety_" + k.replace(" ", "_")] = v
        out["stress_tooth_ring_mpa"] = max(d["stress"]["tooth_ring_total_mpa"])
        out["stress_cup_bottom_mpa"] = max(d["stress"]["cup_bottom_von_mises_mpa"])
    if d.get("contact"):
        out["contact_stiffness_nm_per_rad"] = d["contact"]["secant_stiffness_nm_per_rad"][0]
    return out


def _read_front(path: Path) -> list[dict]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main(argv=None) -> int:
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (8_000_000_000, 8_000_000_000))
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--spec", default=str(Path(__file__).resolve().parents[2] / "profiles" / "optimize" / "default.toml"))
    p.add_argument("--population", type=int)
    p.add_argument("--generations", type=int)
    p.add_argument("--seed", type=int)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--out", default="export/bench/optimize")
    p.add_argument("--reproduce", type=int, default=0, metavar="K", help="run profilegen design on K front designs")
    p.add_argument("--dask-local", action="store_true", help="also run on a Dask LocalCluster and compare")
    args = p.parse_args(argv)

    from profilegen.studies.optimize import load_optimize_spec, optimize

    spec = load_optimize_spec(args.spec)
    changes = {k: v for k, v in (("population", args.population), ("generations", args.generations),
                                 ("seed", args.seed)) if v is not None}
    spec = dataclasses.replace(spec, **changes)
    out = Path(args.out)
    print(f"spec {args.spec}: population {spec.population}, generations {spec.generations}, seed {spec.seed}, "
          f"scene {spec.scene.name} -> confirm {None if spec.confirm_scene is None else spec.confirm_scene.name}; "
          f"{args.workers} workers", flush=True)
    t0 = time.perf_counter()
    result = optimize(spec, out / "pool", workers=args.workers)
    wall = time.perf_counter() - t0
    s = result.summary
    print(f"process pool: {wall:.1f} s wall; {s['candidates']} candidates ({s['computed']} run, {s['reused']} from the "
          f"journal), {s['failed']} failed, {s['feasible']} feasible; front {s['front']}, {s['dominating_start']} "
          f"dominate the start")
    if spec.confirm_scene is not None:
        print(f"confirm scene: {s['confirm_failed']} failed, {s['confirm_infeasible']} infeasible, "
              f"{s['confirm_dominated']} dominated within the front; order flipped in {s['rank_flips']} of "
              f"{s['rank_pairs']} pairs ({s['rank_flip_fraction']})")
    pre = "confirm_" if spec.confirm_scene is not None else ""
    start = result.start
    print("start: " + ", ".join(f"{o.output} = {start.get(pre + o.output)!r}" for o in spec.objectives)
          + f"; min_clearance_mm = {start.get(pre + 'min_clearance_mm')!r}, profile_min_clearance_mm = "
          f"{start.get(pre + 'profile_min_clearance_mm')!r}")
    for k, r in enumerate(result.front):
        gains = []
        for o in spec.objectives:
            v, s0 = r.get(pre + o.output), start.get(pre + o.output)
            g = None if v is None or s0 in (None, 0) else (v - s0) / abs(s0) * (1 if o.sense == "max" else -1)
            gains.append(f"{o.output} {v!r} ({'—' if g is None else f'{100 * g:+.1f} %'})")
        var = ", ".join(f"{v.name} = {r[v.name]:.6g}" for v in spec.variables)
        print(f"  #{k + 1} {'DOMINATES' if r['dominates_start'] else '         '} {var}: " + "; ".join(gains)
              + f"; clearance {r.get(pre + 'min_clearance_mm')!r} mm, fitted {r.get(pre + 'profile_min_clearance_mm')!r}"
                f" mm; {r['toml']}")
    report = {"wall_s": wall, **s}
    if args.reproduce:
        worst = 0.0
        for r in result.front[: args.reproduce]:
            toml = out / "pool" / r["toml"]
            with tempfile.TemporaryDirectory() as tmp:
                cmd = [sys.executable, "-m", "profilegen", "design", str(toml), "--out", tmp, "-q"]
                run = subprocess.run(cmd, capture_output=True, text=True)
                if run.returncode not in (0, 3):
                    print(f"  {toml}: profilegen design exit {run.returncode}: {run.stderr.strip()[-300:]}")
                    continue
                got = design_json_outputs(json.loads((Path(tmp) / "design.json").read_text()))
            for o in dict.fromkeys([*(o.output for o in spec.objectives), *(c.output for c in spec.constraints)]):
                want = r.get(pre + o)
                if o in got and want is not None and got[o] is not None:
                    rel = abs(got[o] - want) / max(abs(want), 1e-300)
                    worst = max(worst, rel)
                    print(f"  reproduce {toml.name}: {o} design.json {got[o]!r} vs front {want!r} (rel {rel:.2e})")
        print(f"reproduce: largest relative difference {worst:.2e} (must be <= 1e-9)")
        report["reproduce_max_rel"] = worst
    if args.dask_local:
        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True) as cluster, \
                Client(cluster) as client:
            t1 = time.perf_counter()
            dres = optimize(spec, out / "dask", executor=client.get_executor())
            dwall = time.perf_counter() - t1
        outputs = list(dict.fromkeys([*(o.output for o in spec.objectives), *(c.output for c in spec.constraints)]))
        diff, same = 0.0, True
        for name in ("evaluations.csv", "front.csv"):
            a = _read_front(out / "pool" / name)
            b = _read_front(out / "dask" / name)
            same = same and [x["point_id"] for x in a] == [x["point_id"] for x in b]
            cols = [p + o for p in ("", "confirm_") for o in outputs if a and p + o in a[0]]
            diff = max([diff, *(abs(float(x[c]) - float(y[c])) / max(abs(float(x[c])), 1e-300)
                                for x, y in zip(a, b) for c in cols if x.get(c) and y.get(c))])
            same = same and all((x.get(c) == "") == (y.get(c) == "") for x, y in zip(a, b) for c in cols)
        print(f"dask LocalCluster: {dwall:.1f} s wall; same candidates and front designs: {same}; largest relative "
              f"difference of their objective/constraint values: {diff:.2e}; candidates {len(dres.search.rows)} vs "
              f"{len(result.search.rows)}")
        report.update(dask_wall_s=dwall, dask_same_front=same, dask_max_rel=diff)
    out.mkdir(parents=True, exist_ok=True)
    (out / "benchmark.json").write_text(json.dumps(report, indent=1, default=str) + "\n")
    print(f"wrote {out / 'benchmark.json'}")
    return 0 if all(math.isfinite(v) for v in [wall]) else 1


if __name__ == "__main__":
    sys.exit(main())
