"""Tooth deviations and eccentricity against the catalogue's stiffness (issue 16).

    python tests/benchmarks/tooth_errors.py [profiles/seed000_csf40.toml] [--draws 20]

For the gear set (default seed000_csf40; design scene, no contact or stress in the design run):
torsional_curve at ±T1, T2 of the catalogue row for its size and ratio (every ball one-sided,
Hertz springs, the series parts of the chain), then both engagement zones as one problem
(research.tooth_errors.TwoZoneContact) in two models:

* **one flank** (the right flank alone: the other flank never touches — a gear with a backlash
  allowance larger than its deviations); the curve's zero is the deviated gear's first contact
  (TwoZoneContact.first_contact_rad);
* **both flanks** in one problem, with a backlash allowance j (µm at the pitch circle, j/2 on
  each flank; j = 0 is the model's conjugate, backlash-free tooth): where the deviations make
  the flanks interfere the gear is preloaded; the curve's zero is the rest position at a
  vanishing torque (TwoZoneContact.zero_rad).

Cases: the perfect gear (must give torsional_curve's K1, K2 and lost motion); ISO 1328-1:2013
pitch + profile deviations of tolerance classes 4, 5, 6 (σ = f_pT/2 per tooth position,
σ = f_fαT/2 per flank profile; FS and CS each drawn; ``--draws`` per class, seeds fixed:
1000·class + draw); class 5 pitch only, profile only, with the wave generator floating (an
Oldham coupling); a CS eccentricity e = 5, 10, 20 µm at 0, 45, 90, 135° from the major axis,
held and floating; class 5 with e = 10 µm in a random direction. Each as K1 = T1/φ(T1),
K2 = (T2 − T1)/(φ(T2) − φ(T1)), the secant at T2 (φ the elastic rotation from the zero,
+ T × the chain's series compliance) over the catalogue's; mean ± standard deviation (range)
over the draws; loaded points at T1 (both zones), the larger zone's share of T1, the lost
motion (both flanks: the rotation span between ± 3 % of the rated torque, as the chain
defines it) against the catalogue's limit. CPU times.
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
from profilegen.contact.chain import ARCMIN_PER_RAD as ARCMIN, catalogue_for, torsional_curve  # noqa: E402
from profilegen.contact.compliance import ContactCompliance  # noqa: E402
from profilegen.contact.inputs import ContactInput  # noqa: E402
from research.tooth_errors import (TwoZoneContact, draw_deviations, eccentricity_offsets_rad,  # noqa: E402
                                             iso1328_tolerances_um)


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("profile", nargs="?", default=str(ROOT / "profiles" / "seed000_csf40.toml"))
    ap.add_argument("--draws", type=int, default=20)
    ap.add_argument("--backlash-um", type=float, nargs="+", default=[0.0, 5.0, 10.0, 20.0, 40.0],
                    help="backlash allowances j of the both-flank model (µm at the pitch circle)")
    ap.add_argument("--quick", action="store_true", help="classes and one eccentricity row only")
    args = ap.parse_args()
    gs = pg.load_gearset(args.profile)
    cat = catalogue_for(gs)
    t1, t2 = cat["T1_nm"], cat["T2_nm"]
    k1c, k2c = cat["K1_nm_per_rad"], cat["K2_nm_per_rad"]
    sec2c = t2 / (t1 / k1c + (t2 - t1) / k2c)
    lm_cat = cat.get("lost_motion_max_arcmin")
    print(f"=== {gs.name}: catalogue ratio {cat.get('ratio')} row: T1 {t1:g}, K1 {k1c:.3g}, T2 {t2:g}, K2 {k2c:.3g} "
          f"N·m/rad, secant at T2 {sec2c:.4g}, lost motion < {lm_cat} arcmin")
    t0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    curve = torsional_curve(design, [-t1, t1, t2], catalogue=cat)
    print(f"design + torsional_curve: {time.process_time() - t0:.1f} s CPU")
    k_ref = curve.k_nm_per_rad["total"]["positive"]
    series = curve.chain.series_compliance_rad_per_nm
    bearing = curve.chain.bearing
    t_lm = curve.lost_motion_torque_nm
    inputs = ContactInput.from_design(design)
    (pr, cr), (pl, _) = curve.sides[1], curve.sides[-1]
    t0 = time.process_time()
    one = TwoZoneContact(inputs, pr, cr)

    def cat_(f):
        return np.concatenate([getattr(pr, f), getattr(pl, f)])

    comp2 = ContactCompliance.build(inputs, cat_("fs_point_mm"), cat_("normal"), cat_("tooth"), cat_("cs_point_mm"),
                                    ball_supports="all")
    both = TwoZoneContact(inputs, [pr, pl], comp2)
    print(f"both zones on the whole ring: {pr.count} + {pl.count} points per zone (right, left flank), {one.nb} "
          f"balls; {time.process_time() - t0:.2f} s CPU")
    g = gs.gear
    d, m = g.module_mm * g.flexspline_teeth, g.module_mm
    r_p = 0.5 * d
    n_r = pr.count

    def right_only(off2):
        """The right flank's offsets (zone 1, zone 2) out of the both-flank layout."""
        n = pr.count + pl.count
        return np.concatenate([off2[:n_r], off2[n:n + n_r]])

    def case(off2, model, wave_generator="held"):
        """model: 'one' (right flank) or j in µm (both flanks, backlash allowance j)."""
        if model == "one":
            two, off = one, None if off2 is None else right_only(off2)
            zero = two.first_contact_rad(off, wave_generator=wave_generator)
        else:
            two = both
            off = np.full(both.theta.size, 0.5 * model * 1e-3 / r_p) + (0.0 if off2 is None else off2)
            zero = two.zero_rad(off, bearing=bearing, wave_generator=wave_generator)
        s1 = two.solve(t1, off, bearing=bearing, wave_generator=wave_generator)
        s2 = two.solve(t2, off, bearing=bearing, wave_generator=wave_generator)
        e1 = s1.phi_rad - zero + t1 * series
        e2 = s2.phi_rad - zero + t2 * series
        lm = float("nan")
        if model != "one":
            lm = (two.solve(t_lm, off, bearing=bearing, wave_generator=wave_generator).phi_rad
                  - two.solve(-t_lm, off, bearing=bearing, wave_generator=wave_generator).phi_rad
                  + 2.0 * t_lm * series) * ARCMIN
        worst = max(s.equilibrium_residual for s in (s1, s2)), max(s.complementarity_residual for s in (s1, s2))
        return {"K1": t1 / e1 / k1c, "K2": (t2 - t1) / (e2 - e1) / k2c, "S2": t2 / e2 / sec2c, "C1": e1 / t1,
                "C2": e2 / t2, "pts1": s1.teeth_loaded, "split": float(np.max(s1.zone_moment_nmm)) / (t1 * 1e3),
                "LM": lm, "res": worst}

    t0 = time.process_time()
    perfect = {"one": case(None, "one"), 0.0: case(None, 0.0)}
    ref_lm = curve.lost_motion_rad["total"] * ARCMIN
    for key, p in perfect.items():
        label = "one flank" if key == "one" else "both flanks, j = 0"
        print(f"perfect gear, {label}: K1 {p['K1']:.3f}, K2 {p['K2']:.3f}, secant T2 {p['S2']:.3f} × catalogue "
              f"(torsional_curve: {k_ref['K1'] / k1c:.3f}, {k_ref['K2'] / k2c:.3f}, {k_ref['secant_T2'] / sec2c:.3f});"
              f" lost motion {p['LM']:.4f} arcmin (torsional_curve {ref_lm:.4f}); loaded points at T1 {p['pts1']}")
    print(f"({time.process_time() - t0:.2f} s CPU)")
    base = perfect["one"]

    def report(label, rows):
        a = {k: np.array([r[k] for r in rows]) for k in rows[0] if k != "res"}

        def ms(v):
            return f"{v.mean():.2f} ± {v.std(ddof=1) if v.size > 1 else 0.0:.2f} ({v.min():.2f}–{v.max():.2f})"

        lm = "" if np.isnan(a["LM"]).all() else f"; LM {a['LM'].mean():.2f} (max {a['LM'].max():.2f})′"
        added = (a["C1"].mean() - base["C1"]) * 1e6, (a["C2"].mean() - base["C2"]) * 1e6
        print(f"  {label:30s} K1 {ms(a['K1'])}  K2 {ms(a['K2'])}  secT2 {ms(a['S2'])} | +C {added[0]:+.2f}"
              f"/{added[1]:+.2f}e-6; pts {a['pts1'].mean():.1f}; zone "
              f"{a['split'].mean():.2f}{lm}; res ≤ {max(r['res'][0] for r in rows):.0e}/"
              f"{max(r['res'][1] for r in rows):.0e}")

    models = ["one"] + list(args.backlash_um)

    def name(model):
        return "one flank" if model == "one" else f"both flanks, j = {model:g} µm"

    print("\nmodel / catalogue: mean ± std (min–max) over the draws; +C: the secant compliance added to the perfect "
          "gear's at T1/T2 (rad/N·m); pts: loaded points at T1 (both zones); zone: the larger zone's share of T1; "
          "LM: lost motion (arcmin)")
    for grade in (4, 5, 6):
        tol = iso1328_tolerances_um(d, m, grade)
        sp, sa = tol["f_pt_um"] / 2e3, tol["f_falpha_um"] / 2e3
        print(f"ISO 1328-1 class {grade}: f_pT {tol['f_pt_um']:.2f} µm, f_fαT {tol['f_falpha_um']:.2f} µm"
              f"{' (formulas extrapolated)' if tol['extrapolated'] else ''}")
        draws = [draw_deviations([pr, pl], gs, np.random.default_rng(1000 * grade + i), pitch_sigma_mm=sp,
                                 profile_sigma_mm=sa) for i in range(args.draws)]
        for model in models:
            report(name(model), [case(o, model) for o in draws])
        if grade == 5:
            for label, kw in (("pitch only", {"pitch_sigma_mm": sp, "profile_sigma_mm": 0.0}),
                              ("profile only", {"pitch_sigma_mm": 0.0, "profile_sigma_mm": sa})):
                part = [draw_deviations([pr, pl], gs, np.random.default_rng(1000 * grade + i), **kw)
                        for i in range(args.draws)]
                for model in ("one", 0.0):
                    report(f"{label}, {name(model)}", [case(o, model) for o in part])
            for model in ("one", 0.0):
                report(f"WG floating, {name(model)}", [case(o, model, "floating") for o in draws])
    print("CS eccentricity (deterministic)")
    for e_um in ((10.0,) if args.quick else (5.0, 10.0, 20.0)):
        for deg in ((45.0,) if args.quick else (0.0, 45.0, 90.0, 135.0)):
            off = eccentricity_offsets_rad([pr, pl], e_um * 1e-3, math.radians(deg))
            for model in ("one", 0.0):
                report(f"e {e_um:g} µm at {deg:g}°, {name(model)}", [case(off, model)])
        off = eccentricity_offsets_rad([pr, pl], e_um * 1e-3, math.radians(45.0))
        report(f"e {e_um:g} µm at 45°, WG floating, one flank", [case(off, "one", "floating")])
    tol = iso1328_tolerances_um(d, m, 5)
    draws = []
    for i in range(args.draws):
        rng = np.random.default_rng(7000 + i)
        off = draw_deviations([pr, pl], gs, rng, pitch_sigma_mm=tol["f_pt_um"] / 2e3,
                              profile_sigma_mm=tol["f_falpha_um"] / 2e3)
        draws.append(off + eccentricity_offsets_rad([pr, pl], 0.01, rng.uniform(0.0, 2.0 * math.pi)))
    for model in models:
        report(f"class 5 + e 10 µm, {name(model)}", [case(o, model) for o in draws])


if __name__ == "__main__":
    main()
