"""Bit-identity of design.json across a speed change: dump the design scene's design.json of the
five bundled sets (and of a tooth change and a torque change of the default set, designed through
one :class:`profilegen.Engine` after its base), then compare two dumps number by number.

    PYTHONPATH=TREE python tests/benchmarks/speed_identity.py dump OUT.json [--sets default ...]
    python tests/benchmarks/speed_identity.py compare BEFORE.json AFTER.json

``dump`` imports ``profilegen`` from whatever ``PYTHONPATH`` names (so a ``git archive`` snapshot
of the tree before a change and the working tree after it can be dumped alike). design.json is
``Design.to_dict()`` through JSON, with the keys naming a time and the durations in texts left out
(``engine_identity.comparable``'s rule, copied here so that this script reads nothing of the tree
it dumps but the package). ``compare`` reports every path whose value differs (floats exactly;
NaN equals NaN), and the largest relative difference; exits 1 on any difference.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import time
from pathlib import Path

SETS = ("default", "seed000_csf40", "seed001_shf25", "seed002_short_cup", "csf32_100")


def strip(obj):
    if isinstance(obj, dict):
        return {k: strip(v) for k, v in obj.items() if "time" not in k and not str(k).endswith("_s")}
    if isinstance(obj, list):
        return [strip(v) for v in obj]
    if isinstance(obj, str):
        return re.sub(r"\d+(\.\d+)?([eE][-+]?\d+)? ?(s|ms)\b", "# s", obj)
    return obj


def comparable(design):
    return strip(json.loads(json.dumps(design.to_dict(), default=str)))


def dump(out: Path, sets) -> None:
    import profilegen as pg

    root = Path(pg.__file__).resolve().parents[1]
    result = {"package": str(Path(pg.__file__).resolve())}
    for name in sets:
        t0 = time.perf_counter()
        gs = pg.load_gearset(root / "profiles" / f"{name}.toml")
        result[name] = comparable(pg.design(gs, scene="design"))
        print(f"{name}: {time.perf_counter() - t0:.1f} s", flush=True)
    base = pg.load_gearset(root / "profiles" / "default.toml")
    engine = pg.Engine()
    engine.design(base, scene="design")
    for key, changes in (("default+tooth", {"tooth.pressure_angle_deg": 10.02}),
                         ("default+addendum", {"tooth.addendum_coefficient": 0.78}),
                         ("default+torque", {"torque.rated_nm": 270.3})):
        result[key] = comparable(engine.design(base.with_values(changes), scene="design"))
        print(f"{key}: engine ran {engine.last_run}", flush=True)
    out.write_text(json.dumps(result))


def differences(a, b, path=""):
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            yield path, f"keys {sorted(set(a) ^ set(b))}", math.inf
        for k in a.keys() & b.keys():
            yield from differences(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            yield path, f"length {len(a)} != {len(b)}", math.inf
        for i, (x, y) in enumerate(zip(a, b)):
            yield from differences(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and isinstance(b, float):
        if a != b and not (math.isnan(a) and math.isnan(b)):
            yield path, f"{a!r} != {b!r}", abs(a - b) / max(abs(a), abs(b), 1e-300)
    elif type(a) is not type(b) or a != b:
        yield path, f"{a!r} != {b!r}", math.inf


def compare(before: Path, after: Path) -> int:
    a, b = json.loads(before.read_text()), json.loads(after.read_text())
    a.pop("package", None), b.pop("package", None)
    diffs = list(differences(a, b))
    numbers = sum(1 for _ in _floats(a))
    for path, what, rel in diffs[:50]:
        print(f"DIFF {path}: {what} (relative {rel:.3g})")
    worst = max((d[2] for d in diffs), default=0.0)
    print(f"{len(a)} designs, {numbers} numbers compared: {len(diffs)} differ, largest relative difference {worst:.3g}")
    return 1 if diffs else 0


def _floats(x):
    if isinstance(x, dict):
        for v in x.values():
            yield from _floats(v)
    elif isinstance(x, list):
        for v in x:
            yield from _floats(v)
    elif isinstance(x, (int, float)) and not isinstance(x, bool):
        yield x


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    d = sub.add_parser("dump")
    d.add_argument("out", type=Path)
    d.add_argument("--sets", nargs="+", default=list(SETS))
    c = sub.add_parser("compare")
    c.add_argument("before", type=Path)
    c.add_argument("after", type=Path)
    args = ap.parse_args(argv)
    if args.cmd == "dump":
        dump(args.out, args.sets)
        return 0
    return compare(args.before, args.after)


if __name__ == "__main__":
    sys.exit(main())
