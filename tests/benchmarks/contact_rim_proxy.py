"""Lead for issue 5: how much a stiffer ring under the teeth changes the torsional stiffness.

    python tests/benchmarks/contact_rim_proxy.py

The 2D FS ring on balls free to lift is far softer than catalogue gears. The flexible
bearing's outer race, which the FS bore sits on and which is not modelled, is a ring
thicker than the 0.9 mm rim (bending stiffness ∝ t³). As a crude proxy, not a model, this
thickens the FS rim by 1 and 2 mm (which also moves the neutral line and so the kinematics)
and prints the secant stiffness (N·m/rad) with the balls free and held, for the sketch and
design scenes. Catalogue, size 40, ratio 1/50: K1 = 10·10⁴ (0–54 N·m), K2 = 14·10⁴ N·m/rad.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.contact.analysis import analyse_contact, solve_contact  # noqa: E402

TORQUES_NM = [54.0, 265.0, 660.0]


def main() -> None:
    base = pg.load_gearset(pg.default_gearset_path())
    for scene in ("sketch", "design"):
        for extra in (0.0, 1.0, 2.0):
            gs = base.with_values({"gear.rim_thickness_mm": 0.9 + extra}) if extra else base
            design = pg.design(gs, scene=scene)
            free = solve_contact(design, TORQUES_NM)
            held = analyse_contact(free.points, free.compliance.matrix_mm_per_n, TORQUES_NM)
            print(f"{scene:6s} rim {0.9 + extra:.1f} mm: balls free K = "
                  f"{np.array2string(free.secant_stiffness_nm_per_rad / 1e4, precision=1)}·10⁴, teeth "
                  f"{[c.teeth_in_contact for c in free.cases]}, balls {[int(c.ball_active.sum()) for c in free.cases]}; "
                  f"held K = {np.array2string(held.secant_stiffness_nm_per_rad / 1e4, precision=1)}·10⁴, teeth "
                  f"{[c.teeth_in_contact for c in held.cases]}; {len(free.warnings)} warnings", flush=True)


if __name__ == "__main__":
    main()
