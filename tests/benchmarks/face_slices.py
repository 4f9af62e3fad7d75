"""The verify scene's torsional curve against its face slicing, for one gear set: the number of
slices (the scene key ``face_slices``), their layout (``--nodes``: "graded" toward the design
section, the scene's, or "ends", evenly spaced) and the rim's coupling along the face
(``FaceSlices``'s ``coupling_length_mm``: the rim's shell decay length by default, the scene's;
0, independent slices, the soft bound) — lost motion and K1.

    python tests/benchmarks/face_slices.py [--set default] [--slices 3 5 7 9 13] [--nodes graded ends]
                                           [--coupling 0 2 5 8.4 50]

A converging column says how far the scene's slices are from the converged sliced model (with
the rim coupled, and independent); the coupling rows (the scene's 7 graded slices) how much the
coupling length moves it. One verify design is run; each row re-solves only the curve.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import profilegen as pg  # noqa: E402
from profilegen.contact.chain import whole_gear_curve  # noqa: E402
from profilegen.contact.face_curve import FaceSlices, rim_coupling_length_mm  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", default="default")
    ap.add_argument("--slices", type=int, nargs="+", default=[3, 5, 7, 9, 13])
    ap.add_argument("--nodes", nargs="+", default=["graded", "ends"], choices=["graded", "ends", "midpoint"])
    ap.add_argument("--coupling", type=float, nargs="*", default=[0.0, 2.0, 5.0, 8.4, 50.0],
                    help="coupling lengths (mm) to try with the scene's 7 graded slices")
    args = ap.parse_args(argv)
    d = pg.design(pg.load_gearset(args.set), scene="verify", stress=False)
    shell = rim_coupling_length_mm(d.gearset)

    def row(n: int, nodes: str, lam: float | None) -> None:
        t0 = time.perf_counter()
        spec = FaceSlices(n, "cup", d.rim.cup, float(d.face.design_section_z_mm), d.face.modification, nodes=nodes,
                          coupling_length_mm=lam)
        head = whole_gear_curve(d, d.contact, face_slices=spec).headline()
        print(f"{n:6d} {nodes:>8s} {shell if lam is None else lam:11.2f} {head['lost_motion_arcmin']:19.3f} "
              f"{head['k1_nm_per_rad']:12.4g} {time.perf_counter() - t0:7.1f}", flush=True)

    print(f"{args.set}, verify scene (design section z = {d.face.design_section_z_mm:g} mm; the rim's shell length "
          f"{shell:.2f} mm; the run's own curve: lost motion {d.torsional.headline()['lost_motion_arcmin']:.3f} arcmin)")
    print(f"{'slices':>6s} {'nodes':>8s} {'coupling mm':>11s} {'lost motion arcmin':>19s} {'K1 N·m/rad':>12s} "
          f"{'time s':>7s}")
    for nodes in args.nodes:
        for lam in (None, 0.0):
            for n in args.slices:
                row(n, nodes, lam)
    for lam in args.coupling:
        row(7, "graded", lam)
    return 0


if __name__ == "__main__":
    sys.exit(main())
