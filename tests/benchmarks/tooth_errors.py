"""Tooth deviations and eccentricity against the catalogue's stiffness (issue 16).

    python tests/benchmarks/tooth_errors.py [profiles/seed000_csf40.toml] [--draws 20]

For the gear set (default seed000_csf40; design scene, no contact or stress in the design run):
torsional_curve at T1, T2 of the catalogue row for its size and ratio (every ball one-sided,
Hertz springs, the series parts of the chain), then both engagement zones as one problem
(profilegen.contact.tooth_errors.TwoZoneContact, the right flank) with

* the perfect gear (must give torsional_curve's K1, K2),
* ISO 1328-1:2013 pitch + profile deviations of tolerance classes 4, 5, 6 (σ = f_pT/2 per tooth
  position, σ = f_fαT/2 per flank profile; FS and CS each drawn; ``--draws`` per class, seeds
  fixed: 1000·class + draw), and pitch only for class 5,
* a CS eccentricity e = 5, 10, 20 µm in the directions 0, 45, 90, 135° from the major axis,
* class 5 with e = 10 µm in a random direction (``--draws``),
* class 5 and e = 10, 20 µm with the wave generator floating radially (an Oldham coupling:
  ``TwoZoneContact.solve(wave_generator="floating")``; the rows above hold the cam on the CS axis),

each as K1 = T1/φ(T1), K2 = (T2 − T1)/(φ(T2) − φ(T1)), the secant at T2 (φ the elastic rotation
from the first contact of the deviated gear — TwoZoneContact.first_contact_rad, the rigid gear's
largest free rotation —, + T × the chain's series compliance), divided by
the catalogue's; the mean, standard deviation and range over the draws, the loaded teeth at
T1 (both zones) and the zones' moment split at T1. CPU times.
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

import numpy as np  # noqa: E402

import profilegen as pg  # noqa: E402
from profilegen.contact.chain import catalogue_for, torsional_curve  # noqa: E402
from profilegen.contact.inputs import ContactInput  # noqa: E402
from profilegen.contact.tooth_errors import (TwoZoneContact, draw_deviations, eccentricity_offsets_rad,  # noqa: E402
                                             iso1328_tolerances_um)


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("profile", nargs="?", default=str(ROOT / "profiles" / "seed000_csf40.toml"))
    ap.add_argument("--draws", type=int, default=20)
    ap.add_argument("--stations", type=int, default=5, help="contact points per flank (torsional_curve's default 5)")
    ap.add_argument("--per-pitch", type=int, default=14, help="FS mesh columns per pitch (the build's default 14)")
    args = ap.parse_args()
    gs = pg.load_gearset(args.profile)
    cat = catalogue_for(gs)
    t1, t2 = cat["T1_nm"], cat["T2_nm"]
    k1c, k2c = cat["K1_nm_per_rad"], cat["K2_nm_per_rad"]
    sec2c = t2 / (t1 / k1c + (t2 - t1) / k2c)
    print(f"=== {gs.name}: catalogue {cat.get('source', '')[:70]}… ratio {cat.get('ratio')}: T1 {t1:g}, K1 {k1c:.3g}, "
          f"T2 {t2:g}, K2 {k2c:.3g} N·m/rad, secant at T2 {sec2c:.4g}")
    t0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    sides = None
    if args.stations != 5 or args.per_pitch != 14:
        from profilegen.contact import contact_points
        from profilegen.contact.compliance import ContactCompliance

        inp = ContactInput.from_design(design)
        sides = {}
        for side in (1, -1):
            p = contact_points(inp, side=side, stations=args.stations, max_gap_mm=0.12)
            sides[side] = (p, ContactCompliance.build(inp, p.fs_point_mm, p.normal, p.tooth, p.cs_point_mm,
                                                      per_pitch=args.per_pitch, ball_supports="all"))
    curve = torsional_curve(design, [t1, t2], catalogue=cat, sides=sides)
    print(f"stations {args.stations}, FS columns per pitch {args.per_pitch}")
    print(f"design + torsional_curve: {time.process_time() - t0:.1f} s CPU")
    k_ref = curve.k_nm_per_rad["total"]["positive"]
    series = curve.chain.series_compliance_rad_per_nm
    pts, comp = curve.sides[1]
    inputs = ContactInput.from_design(design)
    t0 = time.process_time()
    two = TwoZoneContact(inputs, pts, comp, per_pitch=args.per_pitch)
    print(f"both zones on the whole ring: {pts.count} points per zone, {two.nb} balls, {time.process_time() - t0:.2f} s "
          "CPU")
    bearing = curve.chain.bearing
    g = gs.gear
    d, m = g.module_mm * g.flexspline_teeth, g.module_mm

    def case(off, wave_generator="held"):
        theta0 = two.first_contact_rad(off, wave_generator=wave_generator)
        s1 = two.solve(t1, off, bearing=bearing, wave_generator=wave_generator)
        s2 = two.solve(t2, off, bearing=bearing, wave_generator=wave_generator)
        e1 = s1.phi_rad - theta0 + t1 * series
        e2 = s2.phi_rad - theta0 + t2 * series
        worst = max(s.equilibrium_residual for s in (s1, s2)), max(s.complementarity_residual for s in (s1, s2))
        split = s1.zone_moment_nmm / (t1 * 1e3)
        return {"K1": t1 / e1 / k1c, "K2": (t2 - t1) / (e2 - e1) / k2c, "S2": t2 / e2 / sec2c,
                "C1": e1 / t1, "C2": e2 / t2, "teeth1": s1.teeth_loaded, "teeth2": s2.teeth_loaded,
                "split": float(split.max()), "res": worst}

    t0 = time.process_time()
    perfect = case(None)
    print(f"\nperfect gear: K1 {perfect['K1']:.3f}, K2 {perfect['K2']:.3f}, secant T2 {perfect['S2']:.3f} × catalogue "
          f"(torsional_curve: {k_ref['K1'] / k1c:.3f}, {k_ref['K2'] / k2c:.3f}, {k_ref['secant_T2'] / sec2c:.3f}); "
          f"loaded points at T1 / T2 {perfect['teeth1']} / {perfect['teeth2']}; {time.process_time() - t0:.2f} s CPU")
    base1, base2 = perfect["C1"], perfect["C2"]

    def report(label, rows):
        a = {k: np.array([r[k] for r in rows]) for k in rows[0]}

        def ms(v):
            return f"{v.mean():.3f} ± {v.std(ddof=1) if v.size > 1 else 0.0:.3f} ({v.min():.3f}–{v.max():.3f})"

        print(f"{label:34s} K1 {ms(a['K1'])}  K2 {ms(a['K2'])}  sec T2 {ms(a['S2'])}  | +C(T1) "
              f"{(a['C1'].mean() - base1) * 1e6:.2f}e-6, +C(T2) {(a['C2'].mean() - base2) * 1e6:.2f}e-6 rad/N·m; "
              f"points T1 {a['teeth1'].mean():.1f}, T2 {a['teeth2'].mean():.1f}; larger zone at T1 "
              f"{a['split'].mean():.3f} T; residuals ≤ {max(r['res'][0] for r in rows):.1e} / "
              f"{max(r['res'][1] for r in rows):.1e}")

    print("\nmodel / catalogue: mean ± std (min–max) over the draws; +C: the compliance the deviations add to the "
          "perfect gear's secant")
    for grade in (4, 5, 6):
        tol = iso1328_tolerances_um(d, m, grade)
        sp, sa = tol["f_pt_um"] / 2e3, tol["f_falpha_um"] / 2e3
        t0 = time.process_time()
        rows = [case(draw_deviations(pts, gs, np.random.default_rng(1000 * grade + i), pitch_sigma_mm=sp,
                                     profile_sigma_mm=sa)) for i in range(args.draws)]
        report(f"class {grade}: f_pT {tol['f_pt_um']:.2f}, f_fαT {tol['f_falpha_um']:.2f} µm", rows)
        print(f"   ({args.draws} draws, {time.process_time() - t0:.1f} s CPU"
              f"{'; formulas extrapolated' if tol['extrapolated'] else ''})")
        if grade == 5:
            rows = [case(draw_deviations(pts, gs, np.random.default_rng(1000 * grade + i), pitch_sigma_mm=sp,
                                         profile_sigma_mm=0.0)) for i in range(args.draws)]
            report("class 5, pitch only", rows)
            rows = [case(draw_deviations(pts, gs, np.random.default_rng(1000 * grade + i), pitch_sigma_mm=0.0,
                                         profile_sigma_mm=sa)) for i in range(args.draws)]
            report("class 5, profile only", rows)
            rows = [case(draw_deviations(pts, gs, np.random.default_rng(1000 * grade + i), pitch_sigma_mm=sp,
                                         profile_sigma_mm=sa), "floating") for i in range(args.draws)]
            report("class 5, wave generator floating", rows)
    for e_um in (5.0, 10.0, 20.0):
        for deg in (0.0, 45.0, 90.0, 135.0):
            report(f"eccentricity {e_um:g} µm at {deg:g}°",
                   [case(eccentricity_offsets_rad(pts, e_um * 1e-3, math.radians(deg)))])
    for e_um in (10.0, 20.0):
        report(f"eccentricity {e_um:g} µm at 45°, WG floating",
               [case(eccentricity_offsets_rad(pts, e_um * 1e-3, math.radians(45.0)), "floating")])
    tol = iso1328_tolerances_um(d, m, 5)
    rows = []
    for i in range(args.draws):
        rng = np.random.default_rng(7000 + i)
        off = draw_deviations(pts, gs, rng, pitch_sigma_mm=tol["f_pt_um"] / 2e3,
                              profile_sigma_mm=tol["f_falpha_um"] / 2e3)
        rows.append(case(off + eccentricity_offsets_rad(pts, 0.01, rng.uniform(0.0, 2.0 * math.pi))))
    report("class 5 + e 10 µm, random direction", rows)


if __name__ == "__main__":
    main()
