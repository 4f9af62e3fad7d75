"""The CS corners rounded for wire EDM on the bundled gear sets: per set, the fillets (radius,
centre), the largest kink along the closed CS outline, the smallest clearance of the whole
fitted outline against the FS tooth family (the design's own check) and of the rounded
corners alone (the exact clearance map — distances to the placed FS tooth surface — over
points on the fillet arcs and, where a narrow space closes with one arc, that arc).

    python tests/benchmarks/root_fillet.py                     # the four sets, design scene
    python tests/benchmarks/root_fillet.py --scene sketch default

A plain script (pytest does not collect tests/benchmarks/).
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np

SETS = ("default", "seed000_csf40", "seed001_shf25", "seed002_short_cup")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=list(SETS))
    ap.add_argument("--scene", default="design")
    ap.add_argument("--poses", type=int, default=721, help="FS tooth poses of the corner clearance map")
    args = ap.parse_args()
    resource.setrlimit(resource.RLIMIT_AS, (6_000_000_000, 6_000_000_000))

    import profilegen as pg
    from profilegen.geometry.contour import Arc
    from profilegen.profile.gearform import clearance_map
    from profilegen.profile.rootfillet import max_kink_deg

    for name in args.names:
        gs = pg.load_gearset(pg.resolve_gearset(name))
        t0 = time.perf_counter()
        d = pg.design(gs, scene=args.scene, contact=False, stress=False)
        t_design = time.perf_counter() - t0
        p, cs = d.profile, gs.circular_spline
        print(f"{name} [{args.scene}, design {t_design:.1f} s]: wire radius {cs.wire_radius_mm:g} + gap "
              f"{cs.spark_gap_mm:g} mm, corners {cs.corners}; {len(p.space.elements)} elements per space; "
              f"largest kink of the closed outline {max_kink_deg(p.outline):.3g}°; "
              f"smallest clearance of the whole outline ({p.positions} poses) {p.clearance.min_mm * 1e3:+.4f} µm")
        for f in p.corners.fillets:
            clear = "" if f.clearance_mm is None else f", {f.clearance_mm * 1e3:.1f} µm from the swept region"
            print(f"    {f.where:10s} {f.kind:7s} R {f.radius_mm:.4f} mm, centre ({f.centre_mm[0]:+.4f}, "
                  f"{f.centre_mm[1]:.4f}) mm, corner {f.kink_deg:.2f}°{clear}")
        # the rounded corners alone, and a narrow space's closing arc (centre on the axis)
        arcs = [f.arc for f in p.corners.fillets]
        arcs += [e for e in p.space.elements if isinstance(e, Arc) and e.sweep < 0 and abs(e.centre[0]) < 1e-12
                 and np.any(e.centre) and all(e is not a for a in arcs)]
        for label, pick in (("root", lambda a: a.sweep < 0), ("tip", lambda a: a.sweep > 0)):
            chosen = [a for a in arcs if pick(a)]
            if not chosen:
                continue
            pts = np.vstack([a.sample(1e-6) for a in chosen])
            cmap = clearance_map(d.form, d.tooth, d.motion, phi_range=d.envelope.phi_range, samples=args.poses,
                                 cs_points=pts)
            print(f"    exact clearance of the {label} arcs ({', '.join(f'R {a.radius:.4f}' for a in chosen)}) "
                  f"against the FS tooth family, {args.poses} poses: {cmap.min_mm * 1e3:.2f} µm "
                  f"at φ = {np.degrees(cmap.at_phi):+.2f}°")


if __name__ == "__main__":
    main()
