"""The wave-generator balls as the compliance model's supports: the window (default) against
every ball one-sided at its no-load gap (``ball_supports="all"``).

    python tests/benchmarks/ball_supports.py [profiles/x.toml ...] [--passage 17] [--clearance 0 10 20]

For each gear set (default: the default set and seed000_csf40; design scene, so that the rim
FEM gives the no-load contact angle): the no-load gaps of the zone's balls; at T1, T2 (the
catalogue's 54 / 196 N·m for size 40) and the rated torque, right flanks, ψ = 0 — rotation,
secant mesh stiffness T/(φ − θ₀), teeth in contact, balls loaded, for the window (rigid
balls, settled: solve_contact), all balls rigid, all balls with the bearing's Hertz springs
(chain.BallBearing); the whole gear's K1, K2 (catalogue definitions on the elastic
rotation) = the mesh plus the chain's series parts (cup wall, cup bottom, CS body:
chain.compliance_chain), next to chain.torsional_curve (window or all, + Hertz + series) and the
catalogue row (catalogue.catalogue_row(40, 100): the ratio-50 row, with its note); a
bearing clearance study (every ball outside the window ``--clearance`` µm further away);
and the rotation over one ball passage with rolling balls (cage), window, all, all + Hertz.
"""

from __future__ import annotations

import argparse
import math
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

import profilegen as pg  # noqa: E402
from profilegen.contact import ContactInput, contact_points  # noqa: E402
from profilegen.contact.analysis import solve_contact  # noqa: E402
from profilegen.contact.catalogue import catalogue_row  # noqa: E402
from profilegen.contact.chain import BallBearing, compliance_chain, torsional_curve  # noqa: E402
from profilegen.contact.compliance import ContactCompliance  # noqa: E402
from profilegen.contact.transmission import ARCSEC_PER_RAD, transmission_error  # noqa: E402

SETS = [Path(pg.default_gearset_path()), ROOT / "profiles" / "seed000_csf40.toml"]
T1, T2 = 54.0, 196.0


def run(path: Path, passage: int, clearances) -> None:
    import dataclasses

    gs = pg.load_gearset(path)
    design = pg.design(gs, scene="design", contact=False, stress=False)
    inputs = ContactInput.from_design(design)
    rated = gs.torque.rated_nm
    wrap = inputs.rim_contact_angle_rad
    print(f"\n=== {gs.name} ({path.name}): rated {rated:g} N·m; rim no-load contact angle "
          f"{math.degrees(wrap):.2f}°")
    bearing = BallBearing.from_gearset(gs)
    torques = (T1, T2, rated)
    with threadpool_limits(limits=1, user_api="blas"):
        pts = contact_points(inputs)
        theta0 = float(pts.theta_rad.min())
        window = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                         wrap_half_angle_rad=wrap)
        every = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                        wrap_half_angle_rad=wrap, ball_supports="all")
        print("balls (deg):      " + " ".join(f"{a:7.1f}" for a in np.degrees(every.ball_angle_rad)))
        print("no-load gap (µm): " + " ".join(f"{g:7.3f}" for g in every.ball_gap_mm * 1e3))
        phi = {"window": {}, "all": {}, "all + Hertz": {}}
        print(f"{'T (N·m)':>8} {'model':>12} {'rot (″)':>9} {'k_mesh (N·m/rad)':>17} {'teeth':>5} {'balls':>6} "
              f"{'R_max (N)':>9} {'compl.':>7}")
        for t in torques:
            zone_nmm = t / pts.zones * 1e3
            case = solve_contact(inputs, [t], points=pts, compliance=window).cases[0]
            rows = [("window", case.rotation_rad, case.teeth_in_contact,
                     f"{int(case.ball_active.sum())}/{case.ball_active.size}", float(case.ball_reaction_n.max()),
                     case.solution.complementarity_residual)]
            for label, kw in (("all", {}), ("all + Hertz", {"bearing": bearing})):
                sol, reaction, _ = every.solve_unilateral(pts.theta_rad, pts.lever_mm, zone_nmm, **kw)
                rows.append((label, sol.phi_rad, len(np.unique(pts.tooth[sol.force_n > 0.0])),
                             f"{int(np.count_nonzero(reaction))}/{reaction.size}", float(reaction.max()),
                             sol.complementarity_residual))
            for label, p, teeth, balls, rmax, comp in rows:
                phi[label][t] = p
                print(f"{t:8g} {label:>12} {p * ARCSEC_PER_RAD:9.2f} {t / (p - theta0):17.4g} {teeth:5d} {balls:>6} "
                      f"{rmax:9.0f} {comp:7.0e}")
        series = compliance_chain(gs).series_compliance_rad_per_nm
        print(f"first contact θ₀ {theta0 * ARCSEC_PER_RAD:.3f}″; series parts (cup wall, cup bottom, CS body) "
              f"{series:.4g} rad/(N·m) = 1/{1.0 / series:.4g}")
        for label, p in phi.items():
            e1, e2 = p[T1] - theta0, p[T2] - theta0
            g1, g2 = e1 + T1 * series, e2 + T2 * series
            print(f"  {label:>12}: mesh K1 {T1 / e1:.4g}, K2 {(T2 - T1) / (e2 - e1):.4g}; whole gear K1 {T1 / g1:.4g}, "
                  f"K2 {(T2 - T1) / (g2 - g1):.4g} N·m/rad")
        for supports in ("window", "all"):
            t0 = time.process_time()
            curve = torsional_curve(inputs, [-rated, -T2, -T1, T1, T2, rated], ball_supports=supports)
            k = curve.k_nm_per_rad
            print(f"  chain.torsional_curve ({supports} + Hertz + series, {time.process_time() - t0:.1f} s CPU): "
                  f"whole gear K1 {k['total']['positive']['K1']:.4g}, K2 {k['total']['positive']['K2']:.4g}; "
                  f"mesh + balls K1 {k['mesh_balls']['positive']['K1']:.4g}, K2 {k['mesh_balls']['positive']['K2']:.4g}")
        row = catalogue_row(40, 100)
        print(f"  catalogue: K1 {row['K1_nm_per_rad']:.4g}, K2 {row['K2_nm_per_rad']:.4g} N·m/rad (T1 {row['T1_nm']:g}, "
              f"T2 {row['T2_nm']:g}; ratio-{row['ratio']} row; {row['note']})")
        # bearing clearance (not modelled: every ball outside the window that much further away)
        for c_um in clearances:
            gaps = np.where(every.ball_gap_mm > 0.0, every.ball_gap_mm + c_um * 1e-3, 0.0)
            loose = dataclasses.replace(every, ball_gap_mm=gaps)
            out = []
            for t in torques:
                sol, reaction, _ = loose.solve_unilateral(pts.theta_rad, pts.lever_mm, t / pts.zones * 1e3,
                                                          bearing=bearing)
                out.append(f"{t:g} N·m {sol.phi_rad * ARCSEC_PER_RAD:.2f}″ ({int(np.count_nonzero(reaction))} balls)")
            print(f"  all + Hertz, +{c_um:g} µm clearance outside the window: " + ", ".join(out))
    if passage:
        period = 360.0 / bearing.ball_count / (0.5 * (1.0 + bearing.ball_diameter_mm / bearing.pitch_diameter_mm))
        for supports, hertz in (("window", False), ("all", False), ("all", True)):
            c0 = time.process_time()
            te = transmission_error(inputs, rated, positions=passage, workers=1,
                                    options=dict(span=period, ball_motion="cage", ball_supports=supports,
                                                 hertz_balls=hertz))
            supports += " + Hertz" if hertz else ""
            r = te.rotation_rad * ARCSEC_PER_RAD
            print(f"  ball passage ψ = 0 … {period:.3f}° ({passage} positions, rolling balls), {supports}: rotation "
                  f"{r.min():.2f} … {r.max():.2f}″ (p-p {np.ptp(r):.2f}, largest step {np.max(np.abs(np.diff(r))):.2f}),"
                  f" mesh stiffness {te.stiffness_nm_per_rad.min():.4g} … {te.stiffness_nm_per_rad.max():.4g}, "
                  f"balls {te.active_balls.min()}–{te.active_balls.max()}, {time.process_time() - c0:.1f} s CPU")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sets", nargs="*", type=Path, default=SETS)
    ap.add_argument("--passage", type=int, default=17, help="positions over a ball passage (0: skip)")
    ap.add_argument("--clearance", type=float, nargs="*", default=[0.0, 10.0, 20.0], help="µm")
    args = ap.parse_args()
    for path in args.sets:
        run(path, args.passage, args.clearance)


if __name__ == "__main__":
    main()
