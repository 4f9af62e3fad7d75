"""The torsional curve in both directions and the compliance chain, against the catalogue.

    python tests/benchmarks/torsional_curve.py [profiles/seed000_csf40.toml ...]

For each gear set (default: seed000_csf40 and the default set; design scene, no contact or
stress in the design run): the series compliances of profilegen.contact.chain (cup wall,
cup bottom, CS body) in N·m/rad, the cup's formulas against the cup's torsion harmonic in
scikit-fem at 4 / 2 / 1 / 0.5 mm, the bearing's Hertz coefficient; then the rotation
against torque at ±8 … ±1200 N·m — mesh only (rigid balls: the contact model as it is),
mesh + Hertz ball springs, and the whole chain — with K1, K2, K3 on the catalogue's
T1/T2 (K3 from T2 to the set's peak torque), the secants at T1 and T2, lost motion at ±3 %
of the rated torque and the backlash, against the Harmonic Drive CSF/CSG catalogue's row for
the set's size (contact.chain.catalogue_for: table 42, ratio 1/50; our sets are ratio 100,
which the catalogue lists stiffer). Other sets: ``python tests/benchmarks/torsional_curve.py
profiles/csf32_100.toml``.
Times: the first call (points and compliance of both flanks built) and, with them reused,
the design run's curve (contact.chain.curve_torques_nm: 32 torques, both ways, to the
momentary torque, + the breakpoints) by continuation in T (median of 5, CPU) and by the
reference path (Lemke from scratch at every torque; median of 3), with their largest
difference.
"""

from __future__ import annotations

import math
import resource
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.contact.chain import (  # noqa: E402
    ARCMIN_PER_RAD, catalogue_for, compliance_chain, cup_torsion_fem, curve_torques_nm,
    torsional_curve, whole_gear_curve)

TORQUES_NM = [-1200, -660, -265, -196, -100, -54, -8, 8, 54, 100, 196, 265, 660, 1200]
SETS = [ROOT / "profiles" / "seed000_csf40.toml", Path(pg.default_gearset_path())]


def _catalogue_rotation_rad(torque: float, cat: dict) -> float:
    """The catalogue's bilinear curve (K2 continued past T2: the repository has no K3)."""
    t1, k1, k2 = cat["T1_nm"], cat["K1_nm_per_rad"], cat["K2_nm_per_rad"]
    t = abs(torque)
    rad = t / k1 if t <= t1 else t1 / k1 + (t - t1) / k2
    return math.copysign(rad, torque)


def run(path: Path) -> None:
    gs = pg.load_gearset(path)
    cat = catalogue_for(gs)  # the row for the set's size (and its ratio's note); None: no row
    if cat is None:
        raise SystemExit(f"{path}: no catalogue row for this set's size and ratio (profilegen/contact/catalogue.py)")
    print(f"\n=== {gs.name} ({path.name}): ratio {gs.gear.flexspline_teeth // 2}, rated {gs.torque.rated_nm:g}, "
          f"peak {gs.torque.peak_nm:g}, momentary {gs.torque.momentary_nm:g} N·m")
    chain = compliance_chain(gs)
    print("series compliances (N·m/rad):")
    for p in chain.parts:
        print(f"  {p.name:11s} {p.stiffness_nm_per_rad:10.4g}   {p.formula}")
    print(f"  in series  {chain.series_stiffness_nm_per_rad:10.4g}")
    cup_formula = 1.0 / (chain.part("cup_wall").compliance_rad_per_nm + chain.part("cup_bottom").compliance_rad_per_nm)
    fem = {}
    for h in (4.0, 2.0, 1.0, 0.5):
        t0 = time.process_time()
        fem[h] = cup_torsion_fem(gs, element_mm=h)
        print(f"  cup (wall + bottom) FE n = 0 harmonic, {h:g} mm: {fem[h]:.5g} N·m/rad "
              f"({time.process_time() - t0:.2f} s CPU); formulas {cup_formula:.5g} ({cup_formula / fem[h] - 1:+.2%})")
    b = chain.bearing
    print(f"bearing: {b.ball_count} balls of {b.ball_diameter_mm:g} mm on d_m = {b.pitch_diameter_mm:.4g} mm, "
          f"f = {b.groove_conformity}; δ = {b.hertz_coefficient():.4g}·Q^(2/3) mm (both races); at 500 N: "
          f"{b.approach_mm(500.0) * 1e3:.2f} µm. ESTIMATES: {'; '.join(b.estimates)}")

    t0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    print(f"design scene: {time.process_time() - t0:.2f} s CPU")
    t0 = time.process_time()
    curve = torsional_curve(design, TORQUES_NM, chain=chain, catalogue=cat)
    first = time.process_time() - t0
    print(f"\n{'T (N·m)':>8} {'mesh':>8} {'+balls':>8} {'+chain':>8} {'catalogue':>9} {'teeth':>5} {'balls':>5}  "
          "(rotation, arcmin)")
    for t, a, bb, r, n, nb, fl in zip(curve.torque_nm, curve.mesh_rad, curve.mesh_balls_rad, curve.rotation_rad,
                                     curve.teeth_in_contact, curve.active_balls, curve.flags):
        print(f"{t:8.0f} {a * ARCMIN_PER_RAD:8.3f} {bb * ARCMIN_PER_RAD:8.3f} {r * ARCMIN_PER_RAD:8.3f} "
              f"{_catalogue_rotation_rad(t, cat) * ARCMIN_PER_RAD:9.3f} {n:5d} {nb:5d}" + (f"  FLAG: {fl}" if fl else ""))
    k = curve.k_nm_per_rad
    cat_sec_t2 = cat["T2_nm"] / _catalogue_rotation_rad(cat["T2_nm"], cat)
    print(f"\nstiffness (10⁴ N·m/rad), positive / negative direction; T1 = {cat['T1_nm']:g}, T2 = {cat['T2_nm']:g}, "
          f"T3 = {curve.breakpoints_nm['T3']:g} N·m")
    print(f"{'':12s} {'K1':>13s} {'K2':>13s} {'K3':>13s} {'secant T1':>13s} {'secant T2':>13s}")
    for label in ("mesh", "mesh_balls", "total"):
        row = []
        for name in ("K1", "K2", "K3", "secant_T1", "secant_T2"):
            row.append(f"{k[label]['positive'][name] / 1e4:6.2f}/{k[label]['negative'][name] / 1e4:6.2f}")
        print(f"{label:12s} " + " ".join(f"{x:>13s}" for x in row))
    print(f"{'catalogue':12s} {cat['K1_nm_per_rad'] / 1e4:13.2f} {cat['K2_nm_per_rad'] / 1e4:13.2f} {'—':>13s} "
          f"{cat['K1_nm_per_rad'] / 1e4:13.2f} {cat_sec_t2 / 1e4:13.2f}   ({cat['source']})")
    tot = k["total"]["positive"]
    print(f"whole gear / catalogue: K1 {tot['K1'] / cat['K1_nm_per_rad']:.2f}, K2 {tot['K2'] / cat['K2_nm_per_rad']:.2f}, "
          f"secant T1 {tot['secant_T1'] / cat['K1_nm_per_rad']:.2f}, secant T2 {tot['secant_T2'] / cat_sec_t2:.2f}")
    lm = curve.lost_motion_rad
    print(f"lost motion at ±{curve.lost_motion_torque_nm:g} N·m (±3 % rated): mesh {lm['mesh'] * ARCMIN_PER_RAD:.3f}, "
          f"+balls {lm['mesh_balls'] * ARCMIN_PER_RAD:.3f}, whole {lm['total'] * ARCMIN_PER_RAD:.3f} arcmin "
          f"(catalogue: none in the repository; no friction, so no hysteresis); backlash at zero torque "
          f"{curve.backlash_rad * ARCMIN_PER_RAD:.2e} arcmin ({curve.backlash_rad:.3g} rad)")
    print(f"odd-symmetry defect (|φ(+T)| vs |φ(−T)|, relative): {curve.odd_symmetry_defect:.2e}")
    print(f"compliances at the rated torque ({gs.torque.rated_nm:g} N·m), 10⁻⁶ rad/N·m and share:")
    c = curve.compliances_at_rated
    for name, v in c.items():
        if name != "total_rad_per_nm":
            print(f"  {name[:-len('_rad_per_nm')]:11s} {v * 1e6:8.4f}  {v / c['total_rad_per_nm']:6.1%}  "
                  f"(K = {1 / v:.4g} N·m/rad)")
    print(f"  total       {c['total_rad_per_nm'] * 1e6:8.4f}          (K = {1 / c['total_rad_per_nm']:.4g} N·m/rad)")
    if curve.warnings:
        print("warnings:", *curve.warnings, sep="\n  ")
    # speed: the whole curve with both flanks built (reused), by continuation in T and by the reference
    many = curve_torques_nm(gs, (cat["T1_nm"], cat["T2_nm"]))
    torsional_curve(design, [float(many[-1])], chain=chain, sides=curve.sides)  # warm: imports, caches
    times = {"continuation": [], "lemke": []}
    results = {}
    for method, repeats in (("continuation", 5), ("lemke", 3)):
        for _ in range(repeats):
            t0 = time.process_time()
            results[method] = torsional_curve(design, many, chain=chain, sides=curve.sides, method=method)
            times[method].append(time.process_time() - t0)
    fast, ref = results["continuation"], results["lemke"]
    diff = {name: float(max(abs(a / b - 1.0) for a, b in zip(getattr(fast, name), getattr(ref, name))))
            for name in ("mesh_rad", "mesh_balls_rad", "rotation_rad")}
    t0 = time.process_time()
    torsional_curve(design, [float(many[-1])], chain=chain, sides=curve.sides)
    one = time.process_time() - t0
    print(f"time: first call {first:.2f} s CPU (both flanks built, {len(TORQUES_NM)} torques + breakpoints); "
          f"with the flanks reused, {len(many)} torques ({int((many < 0).sum())} each way, "
          f"{many[many > 0].min():.3g} … {many.max():g} N·m) + breakpoints, K1–K3 and lost motion included: "
          f"continuation {statistics.median(times['continuation']):.3f} s CPU (median of 5), reference (Lemke "
          f"from scratch) {statistics.median(times['lemke']):.2f} s CPU (median of 3); one torque + the breakpoints "
          f"{one:.3f} s")
    # what the curve adds to the contact stage: the stage's own solve (right flank built, rated/peak/
    # momentary) against whole_gear_curve with that flank reused (the left flank built, the curve)
    from profilegen.contact import ContactInput
    from profilegen.contact.analysis import solve_contact

    stage = {"contact": [], "curve": []}
    for _ in range(3):
        t0 = time.process_time()
        contact = solve_contact(ContactInput.from_design(design), [gs.torque.rated_nm, gs.torque.peak_nm,
                                                                   gs.torque.momentary_nm])
        stage["contact"].append(time.process_time() - t0)
        t0 = time.process_time()
        whole_gear_curve(design, contact)
        stage["curve"].append(time.process_time() - t0)
    print(f"contact stage: its solve {statistics.median(stage['contact']):.2f} s CPU, the whole-gear curve added "
          f"(left flank built, {len(many)} torques) {statistics.median(stage['curve']):.2f} s CPU (medians of 3)")
    print("continuation vs reference, max relative difference: " + ", ".join(f"{k} {v:.1e}" for k, v in diff.items())
          + f" (springs' tolerance 1e-5); teeth in contact equal: "
          f"{bool((fast.teeth_in_contact == ref.teeth_in_contact).all())}")


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    paths = [Path(a) for a in sys.argv[1:]] or SETS
    for path in paths:
        run(path)


if __name__ == "__main__":
    main()
