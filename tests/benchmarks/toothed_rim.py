"""The verify tier's toothed-rim FEM: contact condensed onto every bore node against only the
wrap, in one run (issue 14: "the verify rim condensing only near the wrap").

    python tests/benchmarks/toothed_rim.py [-n REPEATS] [--per-pitch 16]

Default gear set, nonlinear toothed quarter rim (the verify tier's 2 + 2 layers, 16 columns
per pitch, 1601 bore nodes), its wave-generator contour. The two ``solve_ring`` modes are timed
alternately (medians of ``-n`` solves each, so a change of machine load hits both):

* ``whole bore``: ``condense_within_rad=None``, the compliance of all bore nodes (the
  rim stage before issue 14);
* ``wrap``: ``condense_within_rad`` = the cheap flat-ring pass's wrap + 10° (what
  ``solve_rim(tier="verify")`` does now), the pass included in the time.

Prints the times, their ratio, the max |Δ| of ω, υ on the neutral line, of the bore's ω, υ
and of every node's ω, υ (mm), the contact angles and active counts.
"""

from __future__ import annotations

import argparse
import logging
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.rim import solve_ring  # noqa: E402
from profilegen.rim.stage import RIM_TIERS, WRAP_MARGIN_RAD, _expected_wrap  # noqa: E402
from profilegen.rim.toothed import toothed_quarter_mesh  # noqa: E402
from profilegen.geometry.wavegen import from_gearset  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=3, help="solves per mode (median)")
    ap.add_argument("--per-pitch", type=int, default=16)
    args = ap.parse_args()
    logging.basicConfig(level=logging.INFO, format="%(name)s: %(message)s")
    logging.getLogger("skfem").setLevel(logging.WARNING)
    gs = pg.load_gearset(pg.default_gearset_path())
    cam = from_gearset(gs)
    tier = RIM_TIERS["verify"]
    mesh = toothed_quarter_mesh(pg.tooth_from_gearset(gs), gs.gear.rim_thickness_mm, rim_layers=tier.layers,
                                tooth_layers=tier.tooth_layers, per_pitch=args.per_pitch)

    def whole():
        return solve_ring(gs, contour=cam, mesh=mesh, geometry=tier.geometry)

    def wrap():
        within = min(0.5 * np.pi, _expected_wrap(gs, tier, cam) + WRAP_MARGIN_RAD)
        return solve_ring(gs, contour=cam, mesh=mesh, geometry=tier.geometry, condense_within_rad=within)

    times = {"whole bore": [], "wrap": []}
    results = {}
    for _ in range(args.n):
        for name, fn in (("whole bore", whole), ("wrap", wrap)):
            t0 = time.perf_counter()
            results[name] = fn()
            times[name].append(time.perf_counter() - t0)
            print(f"  {name}: {times[name][-1]:.2f} s", flush=True)
    a, b = results["whole bore"], results["wrap"]
    med = {k: statistics.median(v) for k, v in times.items()}
    print(f"toothed rim, {a.dof} dof, {a.bore_phi_rad.size} bore nodes, nonlinear, median of {args.n}:")
    for k, v in med.items():
        print(f"  {k:10s} {v:8.2f} s  ({', '.join(f'{t:.2f}' for t in times[k])})")
    print(f"  ratio whole/wrap: {med['whole bore'] / med['wrap']:.2f}×")
    diffs = {
        "neutral ω": np.max(np.abs(a.omega_mm - b.omega_mm)),
        "neutral υ": np.max(np.abs(a.upsilon_mm - b.upsilon_mm)),
        "bore ω": np.max(np.abs(a.bore_omega_mm - b.bore_omega_mm)),
        "bore υ": np.max(np.abs(a.bore_upsilon_mm - b.bore_upsilon_mm)),
        "all nodes ω": np.max(np.abs(a.node_omega_mm - b.node_omega_mm)),
        "all nodes υ": np.max(np.abs(a.node_upsilon_mm - b.node_upsilon_mm)),
    }
    for k, v in diffs.items():
        print(f"  max |Δ| {k}: {v:.3g} mm")
    print(f"  contact angle {a.contact_angle_deg:.6g}° / {b.contact_angle_deg:.6g}°, active {a.active_count} / "
          f"{b.active_count}, max |Δ contact force| "
          f"{np.max(np.abs(a.contact_force_n - b.contact_force_n)) if a.active_count == b.active_count else float('nan'):.3g} N")


if __name__ == "__main__":
    main()
