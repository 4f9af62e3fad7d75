"""The verify scene's torsional curve against its face slicing, for one gear set: the number of
slices (the scene key ``face_slices``) and the coupling between them (``FaceSlices``'s
``coupling_length_mm``: 0, independent slices, is the soft bound the scene uses) — lost motion
and K1.

    python tests/benchmarks/face_slices.py [--set default] [--slices 3 5 9 17] [--coupling 0 1 2 5]

A converging column says how far the verify scene's five slices are from the converged sliced
model; the coupling rows how much a section that spreads load along the face would change it.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import profilegen as pg  # noqa: E402
from profilegen.contact.chain import whole_gear_curve  # noqa: E402
from profilegen.contact.face_curve import FaceSlices  # noqa: E402
from profilegen.scenes import resolve_scene  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", default="default")
    ap.add_argument("--slices", type=int, nargs="+", default=[3, 5, 9, 17])
    ap.add_argument("--coupling", type=float, nargs="*", default=[0.0, 1.0, 2.0, 5.0],
                    help="coupling lengths (mm) to try with the scene's 5 slices")
    args = ap.parse_args(argv)
    gs = pg.load_gearset(args.set)
    print(f"{'slices':>6s} {'coupling mm':>11s} {'lost motion arcmin':>19s} {'K1 N·m/rad':>12s} {'time s':>7s}")
    verify = None
    for n in args.slices:
        t0 = time.perf_counter()
        d = pg.design(gs, scene=dataclasses.replace(resolve_scene("verify"), face_slices=n), stress=False)
        head = d.torsional.headline()
        print(f"{n:6d} {0.0:11.1f} {head['lost_motion_arcmin']:19.3f} {head['k1_nm_per_rad']:12.4g} "
              f"{time.perf_counter() - t0:7.1f}", flush=True)
        verify = d if n == 5 else verify
    if args.coupling:
        d = verify or pg.design(gs, scene="verify", stress=False)
        for lam in args.coupling:
            t0 = time.perf_counter()
            spec = FaceSlices(5, "cup", d.rim.cup, float(d.face.design_section_z_mm), d.face.modification,
                              nodes="ends", coupling_length_mm=lam)
            head = whole_gear_curve(d, d.contact, face_slices=spec).headline()
            print(f"{5:6d} {lam:11.1f} {head['lost_motion_arcmin']:19.3f} {head['k1_nm_per_rad']:12.4g} "
                  f"{time.perf_counter() - t0:7.1f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
