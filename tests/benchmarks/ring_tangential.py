"""The ratcheting climb loads the CS ring with the teeth's radial force parts only; the contact's
compliance loads it along the full normals (docs/theory/contact.md). How much the tangential
parts change the ring's radial displacement at the loaded teeth: the force-weighted mean radial
displacement of the ring at the contact points under the contact stage's forces, from the radial
parts alone and from the whole forces, at 1×, 4× and 10× the rated torque.

    python tests/benchmarks/ring_tangential.py [profiles/default.toml profiles/seed000_csf40.toml]
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.contact.analysis import solve_contact  # noqa: E402
from profilegen.contact.cs_ring import CSRing, ring_compliance  # noqa: E402
from profilegen.contact.inputs import ContactInput  # noqa: E402


def main(paths) -> None:
    print("| set | torque (N·m) | radial parts only (µm) | whole forces (µm) | ratio | force-weighted sin α |")
    print("|---|---|---|---|---|---|")
    for path in paths:
        gs = pg.load_gearset(path)
        inputs = ContactInput.from_design(pg.design(gs, scene="sketch", contact=False, stress=False))
        ring = CSRing.of(inputs)
        for mult in (1.0, 4.0, 10.0):
            torque = float(gs.torque.rated_nm) * mult
            c = solve_contact(inputs, [torque])
            pts, f = c.points, c.cases[0].solution.force_n
            theta = np.arctan2(pts.cs_point_mm[:, 0], pts.cs_point_mm[:, 1])
            e_r = np.column_stack([np.sin(theta), np.cos(theta)])
            e_t = np.column_stack([np.cos(theta), -np.sin(theta)])
            a = np.einsum("ij,ij->i", pts.normal, e_r)
            b = np.einsum("ij,ij->i", pts.normal, e_t)
            radial = ring_compliance(ring, theta, theta, load_directions=np.column_stack([a, 0.0 * b])) @ f
            whole = ring_compliance(ring, theta, theta, load_directions=np.column_stack([a, b])) @ f
            w = f / f.sum()
            print(f"| {Path(path).stem} | {torque:.0f} | {w @ radial * 1e3:.2f} | {w @ whole * 1e3:.2f} | "
                  f"{(w @ whole) / (w @ radial):.3f} | {w @ a:.3f} |")


if __name__ == "__main__":
    main(sys.argv[1:] or [str(ROOT / "profiles" / "default.toml"), str(ROOT / "profiles" / "seed000_csf40.toml")])
