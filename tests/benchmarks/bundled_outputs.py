"""The four bundled gear sets' output folders from two source trees, compared (issue 14: the
restructure keeps behaviour and files).

Runs ``python -m profilegen design NAME --out DIR/NAME -q`` for every bundled set (its own
scene) with a given source tree first on ``sys.path``, then compares the folders file by file
with :func:`tests.benchmarks.end_to_end.compare`: JSON numbers to 1e-12 (relative) once timings
are dropped, CSV/DXF/SVG byte for byte, HTML once embedded images and timing cells are removed,
and PNGs listed where their pixels changed.

    git archive OLD | tar -x -C /tmp/old_tree
    python tests/benchmarks/bundled_outputs.py --tree /tmp/old_tree --out /tmp/bundled_old
    python tests/benchmarks/bundled_outputs.py --out /tmp/bundled_new          # this tree
    python tests/benchmarks/bundled_outputs.py --compare /tmp/bundled_old /tmp/bundled_new

Exit code 1 if a run fails or a comparison finds a difference.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from tests.benchmarks.end_to_end import compare  # noqa: E402

SETS = ("default", "seed000_csf40", "seed001_shf25", "seed002_short_cup")


def run(tree: Path, out: Path, sets: tuple[str, ...]) -> int:
    env = {**os.environ, "PYTHONPATH": str(tree), "PYTHONHASHSEED": "0"}
    failed = 0
    for name in sets:
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "profilegen", "design", name, "--out", str(out / name), "-q"],
                              cwd=tree, env=env, capture_output=True, text=True)
        print(f"{name:20s} exit {proc.returncode}  {time.perf_counter() - t0:6.1f} s", flush=True)
        if proc.returncode:
            failed += 1
            print(proc.stderr[-2000:])
    return failed


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tree", type=Path, default=ROOT, help="source tree to run (default: this one)")
    ap.add_argument("--out", type=Path, help="folder for one output folder per set")
    ap.add_argument("--sets", default=",".join(SETS), help="comma-separated bundled set names")
    ap.add_argument("--compare", nargs=2, type=Path, metavar=("OLD", "NEW"), help="compare two --out folders")
    args = ap.parse_args()
    sets = tuple(s for s in args.sets.split(",") if s)
    if args.compare:
        old, new = args.compare
        bad = 0
        for name in sets:
            print(f"== {name}")
            problems = compare(old / name, new / name)
            for p in problems:
                print(f"  DIFFERS {p}")
            print(f"  {'identical' if not problems else f'{len(problems)} difference(s)'} "
                  f"({len(list((new / name).iterdir()))} files)")
            bad += bool(problems)
        return 1 if bad else 0
    if args.out is None:
        ap.error("--out or --compare is needed")
    return 1 if run(args.tree.resolve(), args.out.resolve(), sets) else 0


if __name__ == "__main__":
    raise SystemExit(main())
