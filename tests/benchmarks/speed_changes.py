"""The design scene's tooth change and torque change through the engine, before and after a code
change, in one run (issue 31's workbench: the compute behind a field's change).

    python tests/benchmarks/speed_changes.py [--before REF] [--after REF] [--rounds 3] [-n 3]

Each tree (``--before``, default the merge base of HEAD and ``main``; ``--after``, default ``HEAD``; git refs of this
repository, or a folder holding a ``profilegen`` package) is unpacked with ``git archive`` into a
temporary folder and run there in its own process (``PYTHONPATH`` the folder), so uncommitted
edits play no part. A process loads the default set (``profiles/default.toml``), designs it once
in the design scene through a fresh :class:`profilegen.Engine` (the cache warm) and then makes
``-n`` changes of each kind, each a new value: the FS tooth's pressure angle (10° × (1 + 0.002 k),
the engine re-runs the stages from the tooth on) and the rated torque (265 N·m × (1 + 0.02 k), the
contact and the stresses). Before each timed design the stages' own memos (the arc fit's, the
contact compliance's) are cleared, as tests/benchmarks/engine.py does. Per design: wall and CPU
time of the engine's call and each stage's own time from its report. ``--rounds`` processes per
tree, before and after alternating (and which goes first), so that the shared host's load falls
on both alike. Prints the medians over every change of a kind (rounds × n) and after/before.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

WORKER = r"""
import json, sys, time
import profilegen as pg
try:
    from profilegen.profile import arcfit
except ImportError:  # a tree from before the stage folders
    from profilegen import arcfit
from profilegen.contact import compliance
n = int(sys.argv[1])
base = pg.load_gearset(pg.default_gearset_path())
engine = pg.Engine()
engine.design(base, scene="design")
rows = []
for k in range(1, n + 1):
    for kind, field, value in (("tooth", "tooth.pressure_angle_deg", 10.0 * (1 + 0.002 * k)),
                               ("torque", "torque.rated_nm", 265.0 * (1 + 0.02 * k))):
        gs = base.with_values({field: value})
        arcfit.clear_cache()
        compliance.clear_cache()
        t0, c0 = time.perf_counter(), time.process_time()
        d = engine.design(gs, scene="design")
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        ran = set(engine.last_run)
        stages = {s.stage: s.time_s for s in d.stages if s.stage.split()[0] in ran}
        rows.append({"kind": kind, "wall": wall, "cpu": cpu, "stages": stages})
print(json.dumps(rows))
"""


def unpack(ref: str, into: Path) -> Path:
    if Path(ref).is_dir():
        return Path(ref).resolve()
    into.mkdir(parents=True)
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", ref], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    return into


def run(tree: Path, n: int) -> list[dict]:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    out = subprocess.run([sys.executable, "-c", WORKER, str(n)], env=env, cwd=str(tree), capture_output=True,
                         text=True)
    if out.returncode:
        raise RuntimeError(f"the worker in {tree} failed:\n{out.stderr[-2000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", default=None, help="default: git merge-base HEAD main")
    ap.add_argument("--after", default="HEAD")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("-n", type=int, default=3)
    args = ap.parse_args(argv)
    if args.before is None:
        args.before = subprocess.run(["git", "-C", str(ROOT), "merge-base", "HEAD", "main"], check=True,
                                     capture_output=True, text=True).stdout.strip()[:12]
    results: dict[str, list[dict]] = {"before": [], "after": []}
    with tempfile.TemporaryDirectory() as tmp:
        trees = {"before": unpack(args.before, Path(tmp) / "before"), "after": unpack(args.after, Path(tmp) / "after")}
        for r in range(args.rounds):
            order = ("before", "after") if r % 2 == 0 else ("after", "before")
            for which in order:
                results[which] += run(trees[which], args.n)
                print(f"round {r + 1}: {which} done (load {os.getloadavg()[0]:.1f})", flush=True)
    print(f"\nbefore = {args.before}, after = {args.after}; medians of {args.rounds} x {args.n} changes each")
    for kind in ("tooth", "torque"):
        rows = {w: [x for x in results[w] if x["kind"] == kind] for w in results}
        print(f"\ndesign scene, {kind} change (default set):")
        print(f"  {'':22s} {'before s':>9s} {'after s':>9s} {'after/before':>13s}")
        for label, get in (("engine.design wall", lambda x: x["wall"]), ("engine.design CPU", lambda x: x["cpu"])):
            b, a = (statistics.median(get(x) for x in rows[w]) for w in ("before", "after"))
            print(f"  {label:22s} {b:9.3f} {a:9.3f} {a / b:13.2f}")
        names = sorted({s for w in rows for x in rows[w] for s in x["stages"]},
                       key=lambda s: -statistics.median(x["stages"].get(s, 0.0) for x in rows["before"]))
        for s in names:
            b, a = (statistics.median(x["stages"].get(s, 0.0) for x in rows[w]) for w in ("before", "after"))
            print(f"  {'stage ' + s + ' (wall)':22s} {b:9.3f} {a:9.3f} {a / b if b else float('nan'):13.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
