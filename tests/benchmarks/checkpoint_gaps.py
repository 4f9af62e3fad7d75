"""Where a superseded design cannot stop soon (issue 31: ≤ 0.1 s anywhere): the longest spans
between two checkpoints (:func:`profilegen.stagecache.checkpoint`) of one design, with the stage
that ran and the code at each end. A stand-in for the engine's run records the time of every
checkpoint (it never cancels), so a span here is how long a stop asked inside it would wait.

    python tests/benchmarks/checkpoint_gaps.py [--set default] [--scene design] [--top 12] [--over 0.05]
        [--where contact/compliance.py --where rim/cup/contact.py]

``--where``: only the spans with an end in code whose place contains that text (repeatable).

Times are wall times on this machine (a loaded machine stretches them); the places are the point.
"""

from __future__ import annotations

import argparse
import sys
import time
import traceback
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import profilegen as pg  # noqa: E402
from profilegen.stagecache import STAGE_CACHE  # noqa: E402


def _where() -> str:
    """The innermost package frame that called checkpoint (file:line function)."""
    for f in reversed(traceback.extract_stack()[:-3]):
        if "/profilegen/" in f.filename and not f.filename.endswith("stagecache.py"):
            return f"{f.filename.split('/profilegen/')[-1]}:{f.lineno} {f.name}"
    return "?"


class Recorder:
    """The engine run's interface the pipeline uses (stage, checkpoint, reuse), recording only."""

    def __init__(self):
        self.stage_name, self.last, self.last_at = "start", time.perf_counter(), "design start"
        self.spans: list[tuple[float, str, str, str]] = []

    def _mark(self, at: str) -> None:
        now = time.perf_counter()
        self.spans.append((now - self.last, self.stage_name, self.last_at, at))
        self.last, self.last_at = now, at

    def checkpoint(self) -> None:
        self._mark(_where())

    def stage(self, name, parent, compute, gearset, scene, extra, on_hit):
        self._mark(f"stage {name} begins")
        self.stage_name = name
        value = compute()
        self._mark(f"stage {name} ends")
        return value, (name, parent)

    def reuse(self, name, compute, gearset, sections, key, owners):
        return compute()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", default="default")
    ap.add_argument("--scene", default="design")
    ap.add_argument("--top", type=int, default=12)
    ap.add_argument("--over", type=float, default=0.05, help="count the spans longer than this (s)")
    ap.add_argument("--where", action="append", default=[],
                    help="only the spans with an end whose place contains this text (repeatable)")
    args = ap.parse_args(argv)
    gs = pg.load_gearset(args.set)
    pg.design(gs, scene=args.scene)  # warm: imports and the process's first-call costs
    rec = Recorder()
    token = STAGE_CACHE.set(rec)
    try:
        t0 = time.perf_counter()
        pg.design(gs, scene=args.scene)
        total = time.perf_counter() - t0
    finally:
        STAGE_CACHE.reset(token)
    spans = sorted(rec.spans, reverse=True)
    if args.where:
        spans = [s for s in spans if any(w in s[2] or w in s[3] for w in args.where)]
    long = [s for s in spans if s[0] > args.over]
    print(f"{args.set}, {args.scene} scene: {total:.2f} s, {len(rec.spans)} checkpoints and stage ends; "
          f"{len(long)} spans over {args.over * 1e3:.0f} ms" + (f" at {', '.join(args.where)}" if args.where else ""))
    for dt, stage, a, b in spans[: args.top]:
        print(f"{dt * 1e3:8.1f} ms  [{stage}]  {a}  ->  {b}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
