"""One field of a bundled set scanned finely in one warm process: each value's outcome (ok, or the
named error's type and, for a FilletError, the largest fillet that fits), and whether the failures
form one threshold (no value that designs between two that fail, or the reverse: no cliff).

    python tests/benchmarks/verdict_scan.py csf32_100 tooth.addendum_mm 0.3200 0.3230 31 \\
        --set circular_spline.wire_radius_mm=0.125 [--scene sketch]

Arguments: the set (``profiles/NAME.toml``), the dotted field, the first and last value and the
number of values (evenly spaced, both ends included); ``--set FIELD=VALUE`` (repeatable) changes
other fields first (above: the 0.25 mm default wire, which csf32_100 carried when the perturbation
study found its cliff). A plain script (pytest does not collect tests/benchmarks/).
"""

from __future__ import annotations

import argparse
import logging
import re
import resource
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("name")
    ap.add_argument("field")
    ap.add_argument("first", type=float)
    ap.add_argument("last", type=float)
    ap.add_argument("count", type=int)
    ap.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE")
    ap.add_argument("--scene", default="sketch")
    args = ap.parse_args(argv)
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
    logging.disable(logging.WARNING)

    import profilegen as pg
    from profilegen.errors import ProfilegenError

    base = pg.load_gearset(ROOT / "profiles" / f"{args.name}.toml")
    fixed = {k: float(v) for k, v in (s.split("=", 1) for s in args.set)}
    outcomes = []
    t0, c0 = time.perf_counter(), time.process_time()
    for value in np.linspace(args.first, args.last, args.count):
        try:
            pg.design(base.with_values({**fixed, args.field: float(value)}), scene=args.scene, stress=False)
            kind, what = "ok", ""
        except ProfilegenError as exc:
            kind = type(exc).__name__
            m = re.search(r"the largest (?:that fits|root fillet that stays clear) is ([0-9.]+) mm", str(exc))
            what = f"largest fillet {m.group(1)} mm" if m else " ".join(str(exc).split())[:120]
        outcomes.append(kind)
        print(f"{args.field} = {value:.6f}: {kind:14s} {what}", flush=True)
    changes = sum(a != b for a, b in zip(outcomes, outcomes[1:]))
    print(f"\n{len(outcomes)} values, {changes} change(s) of outcome along the scan "
          f"({'one threshold' if changes <= 1 else 'NOT one threshold'}); "
          f"{time.perf_counter() - t0:.0f} s wall, {time.process_time() - c0:.0f} s CPU")
    return 0


if __name__ == "__main__":
    sys.exit(main())
