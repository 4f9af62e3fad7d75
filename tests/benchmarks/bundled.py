"""Every bundled gear set in every scene, as a user runs it: `profilegen design NAME --scene S`.

The suite runs the sketch and design scenes (tests/test_bundled.py); the verify scene takes
about a minute per set, so it is here. Each run is a subprocess under a 6 GB address-space
cap; the table gives its exit code, wall time, peak memory and verdict line, and the script
exits 1 if any run does not exit 0.

    python tests/benchmarks/bundled.py                    # every set, every scene
    python tests/benchmarks/bundled.py --scenes verify    # the sign-off scene only
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from profilegen.gearset import list_profiles  # noqa: E402

CAP_BYTES = 6 * 1024**3


def _cap():
    resource.setrlimit(resource.RLIMIT_AS, (CAP_BYTES, CAP_BYTES))


def run(name: str, scene: str, out: Path) -> dict:
    """One `profilegen design` in a subprocess; its own peak RSS from wait4."""
    t0 = time.perf_counter()
    with tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen([sys.executable, "-m", "profilegen", "design", name, "--scene", scene, "--out", str(out),
                                 "-q"], stdout=subprocess.DEVNULL, stderr=err, text=True, preexec_fn=_cap, cwd=ROOT)
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = code = os.waitstatus_to_exitcode(status)
        err.seek(0)
        message = err.read().strip().splitlines()
    wall = time.perf_counter() - t0
    if code == 0:
        verdict = json.loads((out / "design.json").read_text())["verdict"]["line"]
    else:
        verdict = (message or ["(no message)"])[-1]
    return {"set": name, "scene": scene, "exit": code, "wall_s": wall, "peak_mb": usage.ru_maxrss / 1024,
            "verdict": verdict}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", nargs="+", default=["sketch", "design", "verify"])
    ap.add_argument("--sets", nargs="+", default=sorted(p.stem for p in list_profiles()))
    args = ap.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scenes:
            for name in args.sets:
                row = run(name, scene, Path(tmp) / f"{name}-{scene}")
                rows.append(row)
                print(f"{row['set']:20s} {row['scene']:7s} exit {row['exit']}  {row['wall_s']:6.1f} s  "
                      f"{row['peak_mb']:6.0f} MB  {row['verdict'][:100]}", file=sys.stderr, flush=True)
    print("| set | scene | exit | wall (s) | peak RSS (MB) | verdict |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['set']} | {r['scene']} | {r['exit']} | {r['wall_s']:.1f} | {r['peak_mb']:.0f} | {r['verdict']} |")
    bad = [r for r in rows if r["exit"] != 0]
    print(f"\n{len(rows) - len(bad)} of {len(rows)} runs exit 0")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
