"""The verify scene's torsional curve against its number of face slices (the scene key
``face_slices``): lost motion, K1 and the first contact, for one gear set.

    python tests/benchmarks/face_slices.py [--set default] [--slices 3 5 9 17]

A converging column says how far the verify scene's five slices are from the converged sliced model.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import profilegen as pg  # noqa: E402
from profilegen.scenes import resolve_scene  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", default="default")
    ap.add_argument("--slices", type=int, nargs="+", default=[3, 5, 9, 17])
    args = ap.parse_args(argv)
    gs = pg.load_gearset(args.set)
    print(f"{'slices':>6s} {'lost motion arcmin':>19s} {'K1 N·m/rad':>12s} {'time s':>7s}")
    for n in args.slices:
        scene = dataclasses.replace(resolve_scene("verify"), face_slices=n)
        t0 = time.perf_counter()
        d = pg.design(gs, scene=scene, stress=False)
        head = d.torsional.headline()
        print(f"{n:6d} {head['lost_motion_arcmin']:19.3f} {head['k1_nm_per_rad']:12.4g} {time.perf_counter() - t0:7.1f}",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
