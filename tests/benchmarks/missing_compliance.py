"""The compliance the whole-gear model leaves out, against the catalogue's ratio >= 80 row (issue 16).

    python tests/benchmarks/missing_compliance.py [profiles/seed000_csf40.toml ...] [--clearance 8 20 30 51] [--race 2 1.5]

For each gear set (default seed000_csf40; design scene): the catalogue row of its size and
ratio (profilegen.contact.catalogue.catalogue_row: the CHA table's i > 50 row, the component
set's values), then the rotation at T1 and T2 of two models of the whole gear —

* **window**: the chain with the window (chain.torsional_curve(ball_supports="window"): window balls, Hertz springs, series
  cup wall + cup bottom + CS body); a candidate's change is added from the rigid-ball window
  mesh (solve_contact with the candidate's compliance, balls re-settled);
* **all + Hertz**: every ball of the zone a one-sided Hertz support at its no-load gap
  (ContactCompliance.build(ball_supports="all", cs_ring=False).solve_unilateral(bearing=)), plus the same
  series parts — P1's model, built here from the package, not from P1's files' changes;

and each candidate for the missing compliance, added to both: the CS ring's ovalisation
(tests/oracles/cs_ring.py) as a free ring (the upper bound), on the bolted face joint's foundation
(bolted_flange_foundation, ESTIMATES named in the output) and with a housing ring as thick as
the CS ring (housing_ring_foundation); the bearing's radial internal clearance
(research/bearing_clearance.py: c_r/2 added to every ball outside the window; c_r from ISO 5753's deep
groove groups for the bearing's estimated bore) — all + Hertz only (the window model has no
ball outside the window); a thinner outer race than the 2.5 %-of-pitch-diameter ESTIMATE
(``--race``: the section under the raceway groove; a sensitivity) — all + Hertz only; the race
and rim bending across the face between the ball at mid-width and the face's ends
(research/race_flexure.py, strip model, in series with each ball's Hertz spring) — all + Hertz only;
and, as sensitivities of ESTIMATES rather than missing parts, smaller balls and a looser groove,
and a cup thinner than the seed's (wall below the tooth ring and bottom at 0.6 of the rim
thickness: a series term, both models). Printed: K1, K2 and the secants T/φ at T1 and T2 (the catalogue's
K1/K2 definitions on the elastic rotation) against the catalogue's, and each candidate's
compliance at T1 and T2 (its added rotation / T, rad per N·m), and the compliance that would
close each model to the catalogue. CPU times.
"""

from __future__ import annotations

import argparse
import dataclasses
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
from profilegen.contact.analysis import solve_contact  # noqa: E402
from profilegen.contact.catalogue import catalogue_row  # noqa: E402
from profilegen.contact.chain import catalogue_size, compliance_chain, torsional_curve  # noqa: E402
from research.bearing_clearance import clearance_ball_gaps_mm, iso5753_radial_clearance_um  # noqa: E402
from profilegen.contact.compliance import ContactCompliance, default_race_thickness_mm  # noqa: E402
from tests.oracles.cs_ring import (  # noqa: E402
    CSRing, bolted_flange_foundation, cs_ring_compliance, housing_ring_foundation)
from profilegen.contact.inputs import ContactInput  # noqa: E402
from research.race_flexure import race_axial_flexure_compliance_mm_per_n  # noqa: E402

ARCSEC = 180 * 3600 / math.pi
#: the bolted face joint (ESTIMATES: a CSF-40-class CS on 16 bolts M6–M8; a clamped joint's
#: lateral stiffness ~2·10⁵ N/mm per bolt before slip; the bolt circle at 85 % of the way
#: from the ring's inner to its outer radius)
BOLTS, BOLT_K_N_PER_MM, BOLT_CIRCLE = 16, 2.0e5, 0.85
#: a thinner cup than the seed's one thickness (ESTIMATE): wall below the tooth ring and bottom × this
CUP_FRACTION = 0.6


def with_cs(comp: ContactCompliance, extra: np.ndarray) -> ContactCompliance:
    """The compliance with ``extra`` (mm/N) added to the CS block (and the matrix reassembled)."""
    cs = dataclasses.replace(comp, cs_matrix_mm_per_n=comp.cs_matrix_mm_per_n + extra)
    return cs.with_balls(comp.ball_active)


def run(path: Path, clearances_um, races_mm=()) -> None:
    gs = pg.load_gearset(path)
    size = catalogue_size(gs)
    row = catalogue_row(size, int(round(gs.ratio)))
    t1, t2 = float(row["T1_nm"]), float(row["T2_nm"])
    c1, c2 = float(row["K1_nm_per_rad"]), float(row["K2_nm_per_rad"])
    cat_phi1, cat_phi2 = t1 / c1, t1 / c1 + (t2 - t1) / c2
    print(f"\n=== {gs.name}: size {size}, ratio {gs.ratio:g}; catalogue {row['source']}: T1 {t1:g}, K1 {c1:.3g}, "
          f"T2 {t2:g}, K2 {c2:.3g} N·m/rad (secant T2 {t2 / cat_phi2:.4g}); {row['values_of']}")
    c0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    inputs = ContactInput.from_design(design)
    chain = compliance_chain(gs)
    series = chain.series_compliance_rad_per_nm
    bearing = chain.bearing
    import inspect

    window_opt = {"ball_supports": "window"} if "ball_supports" in inspect.signature(torsional_curve).parameters \
        else {}  # the chain as landed at 690b35d has only the window
    curve = torsional_curve(design, [-t2, -t1, t1, t2], chain=chain, catalogue=row, **window_opt)
    theta0 = curve.first_contact_rad["positive"]
    tq = np.asarray(curve.torque_nm)
    base_window = {t: float(np.asarray(curve.rotation_rad)[np.flatnonzero(tq == t)[0]]) - theta0 for t in (t1, t2)}
    pts = curve.sides[1][0]
    wrap = inputs.rim_contact_angle_rad
    with threadpool_limits(limits=1, user_api="blas"):
        window = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                         wrap_half_angle_rad=wrap, cs_ring=False)
    print(f"design + chain curve {time.process_time() - c0:.1f} s CPU; series parts {series:.4g} rad/(N·m); "
          f"first contact {theta0 * ARCSEC:.3f}″; no-load contact angle {math.degrees(wrap):.2f}°")
    c0 = time.process_time()
    with threadpool_limits(limits=1, user_api="blas"):
        every = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                        wrap_half_angle_rad=wrap, ball_supports="all", cs_ring=False)
    print(f"all-balls compliance {time.process_time() - c0:.1f} s CPU; balls at "
          + " ".join(f"{a:.1f}" for a in np.degrees(every.ball_angle_rad)) + "°, no-load gaps "
          + " ".join(f"{g * 1e3:.2f}" for g in every.ball_gap_mm) + " µm")

    def window_phi(comp):  # rigid balls, settled: the mesh's elastic rotation
        with threadpool_limits(limits=1, user_api="blas"):
            res = solve_contact(inputs, [t1, t2], points=pts, compliance=comp)
        return {t: float(c.rotation_rad) - theta0 for t, c in zip((t1, t2), res.cases)}

    def all_phi(comp, balls=bearing):
        out = {}
        with threadpool_limits(limits=1, user_api="blas"):
            for t in (t1, t2):
                sol, reaction, _ = comp.solve_unilateral(pts.theta_rad, pts.lever_mm, t / pts.zones * 1e3,
                                                         bearing=balls)
                out[t] = float(sol.phi_rad) - theta0 + t * series
        return out

    window_mesh0 = window_phi(window)
    all0 = all_phi(every)
    if window_opt:  # P1's chain with every ball one-sided, for a cross-check of all_phi
        other = torsional_curve(design, [-t2, -t1, t1, t2], chain=chain, catalogue=row, ball_supports="all")
        ot = np.asarray(other.torque_nm)
        th = other.first_contact_rad["positive"]
        print("chain.torsional_curve(ball_supports='all'): elastic rotation "
              + ", ".join(f"{t:g} N·m {(float(np.asarray(other.rotation_rad)[np.flatnonzero(ot == t)[0]]) - th) * ARCSEC:.2f}″"
                          for t in (t1, t2)) + "; here: " + ", ".join(f"{all0[t] * ARCSEC:.2f}″" for t in (t1, t2)))
    models = {"window chain": ({}, base_window), "all + Hertz": ({}, all0)}

    # CS ring candidates
    ring = CSRing.from_gearset(gs)
    r_bolt = ring.inner_radius_mm + BOLT_CIRCLE * ring.thickness_mm
    k_bolt = bolted_flange_foundation(BOLTS, BOLT_K_N_PER_MM, r_bolt)
    k_house = housing_ring_foundation(ring, ring.thickness_mm)
    ei = ring.youngs_modulus_mpa * ring.second_moment_mm4
    print(f"CS ring r {ring.inner_radius_mm:.2f}…{ring.outer_radius_mm:.2f} mm, width {ring.width_mm:g} mm: n = 2 bending "
          f"stiffness EI·9/R⁴ = {ei * 9 / ring.radius_mm ** 4:.4g} N/mm²; bolted face joint ({BOLTS} bolts × "
          f"{BOLT_K_N_PER_MM:.3g} N/mm on R_b {r_bolt:.1f} mm, ESTIMATE) k_r = k_t = {k_bolt:.4g} N/mm²; housing ring "
          f"{ring.thickness_mm:.1f} mm thick (ESTIMATE) ≙ k_r {k_house:.4g} N/mm²")
    rings = {"CS ring free (upper bound)": ring,
             "CS ring on the bolted face joint": ring.held(k_bolt, note="bolted face joint (ESTIMATE)"),
             "CS ring + housing ring": ring.held(k_house, 0.0, note="housing ring as thick as the CS ring (ESTIMATE)")}
    for name, rg in rings.items():
        s_ring = cs_ring_compliance(rg, pts.cs_point_mm, pts.normal, zones=pts.zones)
        w = window_phi(with_cs(window, s_ring))
        models["window chain"][0][name] = {t: w[t] - window_mesh0[t] for t in (t1, t2)}
        a = all_phi(dataclasses.replace(every, cs_matrix_mm_per_n=every.cs_matrix_mm_per_n + s_ring))
        models["all + Hertz"][0][name] = {t: a[t] - all0[t] for t in (t1, t2)}
    # bearing clearance
    t_race = default_race_thickness_mm(gs.gear)
    bore = bearing.pitch_diameter_mm - bearing.ball_diameter_mm - 2.0 * t_race
    groups = {g: iso5753_radial_clearance_um(bore, g) for g in ("C2", "Normal", "C3")}
    print(f"bearing bore ≈ d_m − D − 2 t_race = {bore:.1f} mm (ESTIMATE: the inner ring as thick as the outer race); "
          "ISO 5753 deep-groove radial clearance " + ", ".join(f"{g} {lo:g}–{hi:g}" for g, (lo, hi) in groups.items())
          + " µm")
    for c_um in clearances_um:
        gaps = clearance_ball_gaps_mm(every.ball_gap_mm, c_um * 1e-3)
        a = all_phi(dataclasses.replace(every, ball_gap_mm=gaps))
        models["all + Hertz"][0][f"clearance c_r = {c_um:g} µm"] = {t: a[t] - all0[t] for t in (t1, t2)}
    # the outer race thinner than the ESTIMATE (its section under the groove; a sensitivity, not a sourced value)
    for t_r in races_mm:
        with threadpool_limits(limits=1, user_api="blas"):
            thin = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                           wrap_half_angle_rad=wrap, ball_supports="all", race_thickness_mm=t_r, cs_ring=False)
        a = all_phi(thin)
        models["all + Hertz"][0][f"race {t_r:g} mm (model {t_race:g} mm)"] = {t: a[t] - all0[t] for t in (t1, t2)}
    # the race and rim bending across the face between the ball (mid-width) and the face's ends (strip model)
    r_race = 0.5 * bearing.pitch_diameter_mm + 0.5 * bearing.ball_diameter_mm + 0.5 * t_race
    strip = 2.0 * math.pi * r_race / bearing.ball_count
    c_ax = race_axial_flexure_compliance_mm_per_n(float(gs.cup.face_width_mm), strip, t_race,
                                                  float(gs.gear.rim_thickness_mm),
                                                  float(gs.material.youngs_modulus_mpa))
    print(f"race axial flexure (strip model: b {float(gs.cup.face_width_mm):g} mm, strip = ball pitch {strip:.2f} mm, "
          f"race {t_race:g} + rim {float(gs.gear.rim_thickness_mm):g} mm sliding): c_ax {c_ax:.3g} mm/N per ball, "
          f"against the Hertz secant {float(bearing.secant_compliance_mm_per_n(500.0)):.3g} mm/N at 500 N")

    class _Plus:  # the bearing's Hertz secant + the strip's linear compliance, in series at each ball
        def secant_compliance_mm_per_n(self, q):
            return np.asarray(bearing.secant_compliance_mm_per_n(q)) + c_ax

    a = all_phi(every, _Plus())
    models["all + Hertz"][0]["race axial flexure (strip)"] = {t: a[t] - all0[t] for t in (t1, t2)}
    # the bearing's ESTIMATED ball size and groove conformity (sensitivity: Hertz at the balls)
    from profilegen.contact.chain import BallBearing

    for label, kw in (("balls 6 mm (ESTIMATE 0.075 d)", {"ball_diameter_mm": 6.0}),
                      ("groove conformity 0.54 (ESTIMATE 0.52)", {"groove_conformity": 0.54})):
        a = all_phi(every, BallBearing.from_gearset(gs, **kw))
        models["all + Hertz"][0][label] = {t: a[t] - all0[t] for t in (t1, t2)}
    # the seed's cup against a thinner one (ESTIMATE of a catalogue cup: wall below the tooth ring 0.6 δ,
    # bottom 0.6 t): tube and annulus compliances ∝ 1/t, a series term in both models
    wall, bottom = chain.part("cup_wall"), chain.part("cup_bottom")
    wp = wall.parameters
    d_cup = (wall.compliance_rad_per_nm * wp["wall_length_mm"] / wp["effective_length_mm"]
             + bottom.compliance_rad_per_nm) * (1.0 / CUP_FRACTION - 1.0)
    for model in models.values():
        model[0][f"cup wall and bottom {CUP_FRACTION:g}× (ESTIMATE)"] = {t: t * d_cup for t in (t1, t2)}
    # a combination: the held ring + a Normal-group clearance (its middle)
    mid = 0.5 * sum(groups["Normal"])
    s_ring = cs_ring_compliance(rings["CS ring on the bolted face joint"], pts.cs_point_mm, pts.normal, zones=pts.zones)
    a = all_phi(dataclasses.replace(every, cs_matrix_mm_per_n=every.cs_matrix_mm_per_n + s_ring,
                                    ball_gap_mm=clearance_ball_gaps_mm(every.ball_gap_mm, mid * 1e-3)))
    models["all + Hertz"][0][f"bolted CS ring + clearance {mid:g} µm"] = {t: a[t] - all0[t] for t in (t1, t2)}

    print(f"\n{'model / + candidate':46s} {'φ(T1)″':>8s} {'φ(T2)″':>8s} {'K1':>9s} {'/cat':>5s} {'K2':>9s} {'/cat':>5s} "
          f"{'T2/φ2':>9s} {'/cat':>5s} {'C(T1)':>9s} {'C(T2)':>9s}   (C: added rad/(N·m) = Δφ/T)")
    for model, (cands, base) in models.items():
        for name, d in [("", {t1: 0.0, t2: 0.0})] + list(cands.items()):
            p1, p2 = base[t1] + d[t1], base[t2] + d[t2]
            k1, k2, ks2 = t1 / p1, (t2 - t1) / (p2 - p1), t2 / p2
            label = model if not name else "  + " + name
            print(f"{label:46s} {p1 * ARCSEC:8.2f} {p2 * ARCSEC:8.2f} {k1:9.4g} {k1 / c1:5.2f} {k2:9.4g} {k2 / c2:5.2f} "
                  f"{ks2:9.4g} {ks2 * cat_phi2 / t2:5.2f} {d[t1] / t1:9.3g} {d[t2] / t2:9.3g}")
        need1, need2 = cat_phi1 / t1 - base[t1] / t1, cat_phi2 / t2 - base[t2] / t2
        print(f"  {model}: missing compliance to the catalogue {need1:.3g} rad/(N·m) at T1, {need2:.3g} at T2 "
              f"(secants; model {base[t1] / t1:.3g} / {base[t2] / t2:.3g}, catalogue {cat_phi1 / t1:.3g} / "
              f"{cat_phi2 / t2:.3g})")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sets", nargs="*", type=Path, default=[ROOT / "profiles" / "seed000_csf40.toml"])
    ap.add_argument("--clearance", type=float, nargs="*", default=[8.0, 20.0, 30.0, 51.0], help="µm (c_r)")
    ap.add_argument("--race", type=float, nargs="*", default=[2.0, 1.5], help="outer-race thickness, mm")
    args = ap.parse_args()
    for p in args.sets:
        run(p, args.clearance, args.race)


if __name__ == "__main__":
    main()
