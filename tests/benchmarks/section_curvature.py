"""The tooth ring's curvature change on the major axis at the design section: the deformed
section's own (what the stress stage rates, ``stress.tooth_ring.section_curvature``) against the
equivalent ellipse through the same section's ω on the two axes, for every bundled set, with the
cup tier's race (``profilegen.rim.cup.bearing.CUP_TIER_RACE``) as given. Also the section's own
curvature change at every face section, to show which one the face's worst is.

    python tests/benchmarks/section_curvature.py                        # design scene, the default race (ring)
    python tests/benchmarks/section_curvature.py --races ring rigid --scene verify

No contact or stress stage runs (the curvature needs only the rim and the face).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
import profilegen.rim.cup.bearing as bearing  # noqa: E402
from profilegen.stress.tooth_ring import ellipse_curvature, section_curvature  # noqa: E402

SETS = ("default", "seed000_csf40", "seed001_shf25", "seed002_short_cup", "csf32_100")


def row(name: str, scene: str) -> dict:
    d = pg.design(pg.load_gearset(name), scene=scene, contact=False, stress=False)
    r_m = d.rim.cup.geometry.neutral_radius_mm
    model = d.rim.model  # the design section's fit: what the stress stage reads
    w, _ = model.evaluate(np.array([0.0, 0.5 * np.pi]), order=0)
    own = float(section_curvature(model, r_m)(np.array([0.0]))[0]) - 1.0 / r_m
    ellipse = float(ellipse_curvature(0.0, r_m + w[0][0], r_m + w[0][1])) - 1.0 / r_m
    sections = []
    for s in d.face.sections:
        m = d.rim.at_section(s.z_mm).model
        sections.append((s.z_mm, float(section_curvature(m, r_m)(np.array([0.0]))[0]) - 1.0 / r_m))
    return {"set": name, "z": d.face.design_section_z_mm, "w_major": w[0][0], "w_minor": w[0][1], "own": own,
            "ellipse": ellipse, "sections": sections}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="design", choices=("design", "verify"))
    ap.add_argument("--races", nargs="+", default=[bearing.CUP_TIER_RACE], choices=bearing.CUP_TIER_RACES)
    ap.add_argument("--sets", nargs="+", default=list(SETS))
    args = ap.parse_args(argv)
    print(f"{'set':18s} {'race':6s} {'z mm':>7s} {'ω maj':>8s} {'ω min':>8s} {'Δκ own':>10s} {'Δκ ellipse':>10s} "
          f"{'own/ell':>8s}  worst face section (Δκ own at each z, 1/mm)")
    for race in args.races:
        bearing.CUP_TIER_RACE = race
        for name in args.sets:
            r = row(name, args.scene)
            worst = max(r["sections"], key=lambda s: s[1])
            print(f"{r['set']:18s} {race:6s} {r['z']:7.3f} {r['w_major']:8.4f} {r['w_minor']:8.4f} {r['own']:10.3e} "
                  f"{r['ellipse']:10.3e} {r['own'] / r['ellipse']:8.3f}  z = {worst[0]:g}: "
                  + " ".join(f"{k:.3e}" for _, k in r["sections"]), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
