"""The clearance maps of a design-scene tooth change, before and after a code change: the same
numbers, bit for bit, and their CPU time (issue 31: the maps are ~1/3 of a tooth change's compute).

    python tests/benchmarks/clearance_maps.py [--before REF] [--after REF] [--sets default ...] [--rounds 3]

Each tree (``--before``, default the merge base of HEAD and ``main``; ``--after``, default ``HEAD``;
git refs of this repository, or a folder holding a ``profilegen`` package) is unpacked with ``git
archive`` into a temporary folder, so uncommitted edits play no part. The after tree's process
records every :func:`profilegen.profile.gearform.clearance_map` call (its arguments and its map):
for ``default``, those of a tooth change (pressure angle 10° → 10.02°) designed in the design scene
through an :class:`profilegen.Engine` after its base (the face stage's ~20 maps, the gearform's and
the arc fit's check); for any other set of ``--sets``, all of its design-scene design. Then, for
``--rounds`` rounds, each tree's own process (before and after alternating, and which goes first)
computes every recorded map once (the arguments unpickled in that tree) and reports each map's
CPU time and its values. Printed: maps whose values differ between the trees (exits 1 if any),
the sum over maps of each map's fastest round, before and after, and their ratio (the fastest of
the rounds: the shared host's load only adds).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from speed_changes import unpack  # noqa: E402  (a commit's tree, or a folder as it is)

ROOT = Path(__file__).resolve().parents[2]

RECORD = r"""
import pickle, sys
import profilegen as pg
from profilegen.profile import gearform
import profilegen.pipeline.design as pipeline_design
calls = []
plain = gearform.clearance_map
def recorded(*args, **kwargs):
    out = plain(*args, **kwargs)
    calls.append((args, kwargs))
    return out
gearform.clearance_map = recorded
pipeline_design.clearance_map = recorded  # imported there by name
root = pg.default_gearset_path().parent
for name in sys.argv[2:]:
    base = pg.load_gearset(root / f"{name}.toml")
    if name == "default":
        engine = pg.Engine()
        engine.design(base, scene="design")
        del calls[:]
        engine.design(base.with_values({"tooth.pressure_angle_deg": 10.02}), scene="design")
    else:
        pg.design(base, scene="design")
with open(sys.argv[1], "wb") as f:
    pickle.dump(calls, f)
print(len(calls))
"""

RUN = r"""
import json, pickle, sys, time
from profilegen.profile.gearform import clearance_map
with open(sys.argv[1], "rb") as f:
    calls = pickle.load(f)
rows = []
for args, kwargs in calls:
    c0 = time.process_time()
    out = clearance_map(*args, **kwargs)
    rows.append({"cpu": time.process_time() - c0, "map": out.clearance_mm.tobytes().hex()})
print(json.dumps(rows))
"""


def python(tree: Path, code: str, *args: str) -> str:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    out = subprocess.run([sys.executable, "-c", code, *args], env=env, cwd=str(tree), capture_output=True, text=True)
    if out.returncode:
        raise RuntimeError(f"the worker in {tree} failed:\n{out.stderr[-2000:]}")
    return out.stdout.strip().splitlines()[-1]


def main(argv=None) -> int:
    import json

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--before", default=None, help="default: git merge-base HEAD main")
    ap.add_argument("--after", default="HEAD")
    ap.add_argument("--sets", nargs="+", default=["default"])
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    if args.before is None:
        args.before = subprocess.run(["git", "-C", str(ROOT), "merge-base", "HEAD", "main"], check=True,
                                     capture_output=True, text=True).stdout.strip()[:12]
    with tempfile.TemporaryDirectory() as tmp:
        trees = {"before": unpack(args.before, Path(tmp) / "before"), "after": unpack(args.after, Path(tmp) / "after")}
        calls = Path(tmp) / "calls.pkl"
        count = int(python(trees["after"], RECORD, str(calls), *args.sets))
        print(f"{count} clearance maps recorded ({', '.join(args.sets)})", flush=True)
        runs: dict[str, list[list[dict]]] = {"before": [], "after": []}
        for r in range(args.rounds):
            for which in (("before", "after") if r % 2 == 0 else ("after", "before")):
                runs[which].append(json.loads(python(trees[which], RUN, str(calls))))
                print(f"round {r + 1}: {which} done (load {os.getloadavg()[0]:.1f})", flush=True)
    differ = [i for i in range(count)
              if len({run[i]["map"] for w in runs for run in runs[w]}) > 1]
    best = {w: sum(min(run[i]["cpu"] for run in runs[w]) for i in range(count)) for w in runs}
    print(f"\nbefore = {args.before}, after = {args.after}; {args.rounds} rounds")
    print(f"maps whose values differ (any round, either tree): {len(differ)} of {count}" +
          (f" ({differ[:10]})" if differ else ""))
    print(f"CPU, the sum over maps of each map's fastest round: before {best['before']:.3f} s, "
          f"after {best['after']:.3f} s, after/before {best['after'] / best['before']:.3f}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
