"""No cliff under a slider (issue 31 item 3): random perturbations of the bundled gear sets, each
designed in one warm process, counted as ok / named failure / other; every failure's two
neighbours (each perturbed value × (1 ± 0.001)) designed too, and a failure whose neighbours
both design is a *cliff* — a value between two that design cleanly that does not.

    python tests/benchmarks/perturbation.py [--n 2000] [--seed 31] [--design 40] [--design-only] [--plain]
                                            [--start J] [--stop K] [--replay LOG ...]

``--start``/``--stop`` run a slice of the job list (one run split over two processes: the counts
are the sum); ``--replay`` runs again only the jobs printed as failures in earlier runs' logs (the
code changed on the failure path only: the other jobs' outcomes stand).
                                            [--out export/bench/perturbation.json]

Each perturbation takes one bundled set (``profiles/*.toml``, uniformly) and multiplies 1 to 4
of its float fields (``GearSet.to_dict()``: every section, the requirements included; the
integer fields — teeth, waves, face sections — are left alone: ±5 % of a tooth count breaks
z2 − z1 = waves, a GearSetError by construction) each by (1 + u), u uniform in [-0.05, 0.05].
All are designed in the sketch scene; the first ``--design`` of them also in the design
scene. ``--plain`` designs with :func:`profilegen.design` (no cache, no retry: the engine as
it was); by default with one :class:`profilegen.Engine` (the stage cache and the engine's
retries). The process runs under a 4 GB address-space cap (RLIMIT_AS) and each design under a
CPU-time limit (``--time-limit-s``, ×4 in the design scene; CPU, not wall: the host is shared); a
design over it is ``other``.

Outcomes: ``ok`` (a Design came back, whatever its verdict); ``named`` (a ProfilegenError: the
set refused with the field and range, or a stage's named limit — its type and message kept);
``other`` (anything else: a bug). Writes the counts, every failure with its neighbours and the
cliffs to ``--out`` (JSON) and prints the table.
"""

from __future__ import annotations

import argparse
import json
import random
import resource
import signal
import sys
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

NEIGHBOUR = 1e-3  # the neighbours: each perturbed value × (1 ± this)


class OverTime(Exception):
    pass


def _alarm(signum, frame):
    raise OverTime("over the time limit")


def float_fields(gs) -> dict[str, float]:
    """Every float field of the set, by its dotted path (``gear.module_mm``, ...)."""
    out = {}
    for section, table in gs.to_dict().items():
        if not isinstance(table, dict) or section == "tooth" and table.get("kind") == "points":
            continue
        for key, value in table.items():
            if isinstance(value, float):
                out[f"{section}.{key}"] = value
    return out


def outcome(run, gs_base, changes: dict, scene: str, limit_s: float) -> tuple[str, str]:
    """('ok' | 'named' | 'other', what) of designing ``gs_base`` with ``changes`` in ``scene``."""
    from profilegen.errors import ProfilegenError

    signal.setitimer(signal.ITIMER_PROF, limit_s)
    try:
        gs = gs_base.with_values(changes)
        run(gs, scene)
        return "ok", ""
    except ProfilegenError as exc:
        return "named", f"{type(exc).__name__}: {' '.join(str(exc).split())[:300]}"
    except OverTime:
        return "other", f"OverTime: over {limit_s:g} s CPU"
    except BaseException as exc:  # noqa: BLE001 — a bug or a MemoryError under the cap: counted
        if isinstance(exc, KeyboardInterrupt):
            raise
        return "other", f"{type(exc).__name__}: {' '.join(str(exc).split())[:300]}"
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=31)
    ap.add_argument("--design", type=int, default=40, help="how many of them also in the design scene")
    ap.add_argument("--design-only", action="store_true", help="the design-scene subset only")
    ap.add_argument("--start", type=int, default=0, help="run jobs [start, stop) of the list only (split a run)")
    ap.add_argument("--stop", type=int, default=None)
    ap.add_argument("--replay", nargs="+", default=None, metavar="LOG",
                    help="run only the jobs that failed in these logs of earlier runs (same --n, --seed, --design)")
    ap.add_argument("--plain", action="store_true", help="profilegen.design, no engine (the 'before' count)")
    ap.add_argument("--time-limit-s", type=float, default=60.0)
    ap.add_argument("--out", default=str(ROOT / "export" / "bench" / "perturbation.json"))
    args = ap.parse_args(argv)
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
    signal.signal(signal.SIGPROF, _alarm)

    import profilegen as pg
    from profilegen.gearset import load_gearset

    if args.plain:
        def run(gs, scene):
            return pg.design(gs, scene=scene)
    else:
        engine = pg.Engine()

        def run(gs, scene):
            return engine.design(gs, scene=scene)

    sets = {p.stem: load_gearset(p) for p in sorted((ROOT / "profiles").glob("*.toml"))}
    fields = {name: float_fields(gs) for name, gs in sets.items()}
    rng = random.Random(args.seed)
    cases = []
    for i in range(args.n):
        name = rng.choice(sorted(sets))
        k = 1 if rng.random() < 0.5 else rng.randint(2, 4)
        paths = rng.sample(sorted(fields[name]), k)
        changes = {p: fields[name][p] * (1.0 + rng.uniform(-0.05, 0.05)) for p in paths}
        cases.append((i, name, changes))
    jobs = [] if args.design_only else [(i, name, changes, "sketch") for i, name, changes in cases]
    jobs += [(i, name, changes, "design") for i, name, changes in cases[: args.design]]

    total = len(jobs)
    indexed = list(enumerate(jobs))[args.start:args.stop]
    if args.replay:  # the failures of earlier runs (their printed lines: "[J/total] scene set {...}: named ...")
        import re

        failed = {int(m.group(1)) - 1 for log in args.replay for m in
                  re.finditer(r"^\[(\d+)/\d+\] (?:sketch|design) \S+ \{", Path(log).read_text(), re.M)}
        indexed = [(j, job) for j, job in indexed if j in failed]
        print(f"replaying {len(indexed)} failures of {', '.join(args.replay)}")
    counts: dict[str, Counter] = {"sketch": Counter(), "design": Counter()}
    failures, t0, c0 = [], time.perf_counter(), time.process_time()
    for j, (i, name, changes, scene) in indexed:
        limit = args.time_limit_s * (4 if scene == "design" else 1)
        kind, what = outcome(run, sets[name], changes, scene, limit)
        counts[scene][kind] += 1
        if kind != "ok":
            neighbours = []
            for sign in (+1, -1):
                near = {p: v * (1.0 + sign * NEIGHBOUR) for p, v in changes.items()}
                neighbours.append(outcome(run, sets[name], near, scene, limit))
            cliff = all(k == "ok" for k, _ in neighbours)
            failures.append({"case": i, "set": name, "scene": scene, "changes": changes, "outcome": kind,
                             "error": what, "neighbours": [list(n) for n in neighbours], "cliff": cliff})
            print(f"[{j + 1}/{total}] {scene} {name} {changes}: {kind} {what[:160]}"
                  f"{'  CLIFF' if cliff else ''}", flush=True)
        if (j + 1) % 100 == 0 and not args.replay:
            print(f"[{j + 1}/{total}] {time.perf_counter() - t0:.0f} s {dict(counts['sketch'])} "
                  f"{dict(counts['design'])}", flush=True)

    cliffs = [f for f in failures if f["cliff"]]
    errors = Counter(f["error"].split(":")[0] for f in failures)
    summary = {"n": args.n, "seed": args.seed, "plain": args.plain, "jobs": [j for j, _ in indexed] if args.replay else
               [args.start, args.start + len(indexed)], "time_s": time.perf_counter() - t0,
               "cpu_s": time.process_time() - c0,
               "counts": {s: dict(c) for s, c in counts.items()}, "cliffs": len(cliffs),
               "failures_by_type": dict(errors), "failures": failures}
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(summary, indent=1))
    print(f"\n{'plain profilegen.design' if args.plain else 'profilegen.Engine'}, seed {args.seed}, "
          f"{time.perf_counter() - t0:.0f} s wall, {time.process_time() - c0:.0f} s CPU")
    for scene, c in counts.items():
        print(f"  {scene:7s} ok {c['ok']:5d}  named {c['named']:4d}  other {c['other']:3d}")
    print(f"  failures by type: {dict(errors)}")
    print(f"  cliffs (both neighbours design): {len(cliffs)}")
    for f in cliffs:
        print(f"    {f['scene']} {f['set']} {f['changes']}: {f['error'][:200]}")
    print(f"  -> {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
