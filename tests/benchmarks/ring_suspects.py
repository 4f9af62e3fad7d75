"""The CS's real section and the wave generator's plug as radial compliances: what they do to the
ratcheting estimate and to K1/K2/K3 (research/ring_suspects.py; docs/theory/torsion.md,
"Suspects measured").

    python tests/benchmarks/ring_suspects.py [--sets 25:100 32:100 40:100 32:50] [--holes 16,0.6]
        [--bores 0.25,0.5,0.7,0.85] [--climb] [--stiffness] [--set SECTION.KEY=VALUE ...]
    python tests/benchmarks/ring_suspects.py --holes-sweep [--sets 32:100]

Per ``profilegen new`` set (size:ratio): the factors on the climb's free thin CS ring (mode 2):
the CS as a thick annulus (2D elasticity), its bolt holes (N holes of d = f × the ring's wall on
its mid-radius: ESTIMATES — the gear set holds no CS bolt pattern), the wave generator's plug
for each bore fraction (bore / the inner race's seat radius: ESTIMATES — the gear set holds no
plug bore), and the ``climb_ring_scale`` they make: thick × holes + plug at bore 0.5 (a solid
cam with a shaft or Oldham bore) and at 0.85 (a thin cam ring, a hollow-shaft wave generator).

``--climb``: the verify scene's estimate (``ratcheting_torque`` on the verify design's contact
inputs, as ``tests/benchmarks/ratcheting.py --verify``) with the CS ring × 1 (the product), ×
the realistic scale and × the hollow-cam scale, against the catalogue (20–60 s a set); then with the outer race and the FS rim bending across the face
between the ball row and the face's ends (``research.race_flexure``'s strip model in series with
each ball's Hertz spring: ``research.ring_suspects.flexed_bearing``), alone and with the
realistic ring.

``--holes-sweep``: the holed CS ring's factor for 8 / 16 / 24 holes of 0.4 / 0.6 / 0.8 × the wall
(FEM, 16 × 384 elements on the quarter) beside its hand bounds (~2 min a set).

``--stiffness [--verify-csv FILE ...]``: the design scene's one-section whole-gear model (every ball a one-sided Hertz
support, the chain's series parts: ``tests/benchmarks/missing_compliance.py``'s "all + Hertz")
with a radial ring compliance added to the contact's CS block (``tests/oracles/cs_ring.py``: the
free CS ring, its E divided by the scale, so its compliance × the scale) — K1/K2/K3 over the
catalogue and the compliance each adds at T1, T2 and the peak torque; then the race and rim's
axial flexure (``flexed_bearing``) alone and with the realistic ring. With ``--verify-csv`` (the CSVs
of ``python tests/benchmarks/catalogue_sizes.py --scene verify --csv FILE``) each row also gives the
verify scene's K's with the row's added rotation C·T in series at T1, T2 and the peak torque (an
estimate: the slices see the same ring). The rows build the contact's CS sector alone
(``cs_ring=False``) and add the ring to it; the product's curve takes the free thin ring (×1, the
contact's own: :mod:`profilegen.contact.cs_ring`), so its verify CSVs already hold ×1 — give
``--verify-csv`` only with CSVs of a product without the ring, or read the columns as increments.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import resource
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))


import profilegen as pg  # noqa: E402
from research.ring_suspects import Holes, flexed_bearing, plate_flexure_compliance_mm_per_n, ring_scale_factors  # noqa: E402


def _catalogue(gs):
    from profilegen.contact.chain import catalogue_for

    row = catalogue_for(gs)
    if row is None or row.get("ratcheting_torque_nm") is None:
        return row, None
    return row, {"torque_nm": row["ratcheting_torque_nm"], "source": row.get("ratcheting_source")}


def factors(gs, holes_count, hole_fraction, bores):
    from research.ring_suspects import cs_ring

    cs = cs_ring(gs)
    holes = Holes(holes_count, hole_fraction * cs.thickness_mm, cs.mean_radius_mm)
    t0 = time.process_time()
    f = ring_scale_factors(gs, holes=holes, bore_fractions=bores)
    real = f["thick"] * f["holes"] + f["plug"].get(0.5, 0.0)
    hollow = f["thick"] * f["holes"] + f["plug"].get(0.85, 0.0)
    print(f"  CS ring r {cs.inner_radius_mm:.2f}…{cs.outer_radius_mm:.2f} mm (h/R {cs.thickness_mm / cs.mean_radius_mm:.3f}),"
          f" width {cs.width_mm:g} mm; thin-ring mode 2 {f['thin_mm_per_n']:.4g} mm/N")
    print(f"  thick annulus / thin ring {f['thick']:.4f}; {holes_count} holes Ø{holes.diameter_mm:.2f} mm on "
          f"r {holes.radius_mm:.2f}: × {f['holes']:.3f} (hand bounds {f['holes_bounds'][0]:.3f} composite … "
          f"{f['holes_bounds'][1]:.3g} ligaments)")
    print("  plug (bore fraction: mode-2 compliance / the thin CS ring's): "
          + ", ".join(f"{b:g}: {v:.4f}" for b, v in f["plug"].items()))
    print(f"  climb_ring_scale: realistic (thick × holes + plug 0.5) {real:.3f}; hollow cam (… + plug 0.85) {hollow:.3f};"
          f" {time.process_time() - t0:.1f} s CPU")
    return real, hollow


def plate_over_strip(gs, divisions: int = 16) -> float:
    """The Morley plate's axial flexure over the strip model's, at the set's ball pitch and face."""
    from profilegen.contact.chain import BallBearing
    from profilegen.contact.compliance import default_race_thickness_mm
    from research.race_flexure import race_axial_flexure_compliance_mm_per_n

    b = BallBearing.from_gearset(gs)
    t_race, t_rim = default_race_thickness_mm(gs.gear), float(gs.gear.rim_thickness_mm)
    pitch = 2.0 * 3.141592653589793 * (0.5 * b.pitch_diameter_mm + 0.5 * b.ball_diameter_mm + 0.5 * t_race) / b.ball_count
    e, face = float(gs.material.youngs_modulus_mpa), float(gs.cup.face_width_mm)
    rigidity = e * (t_race ** 3 + t_rim ** 3) / (12.0 * (1.0 - 0.3 ** 2))
    strip = race_axial_flexure_compliance_mm_per_n(face, pitch, t_race, t_rim, e)
    return plate_flexure_compliance_mm_per_n(face, pitch, rigidity, divisions=divisions) / strip


def holes_sweep(gs) -> None:
    from research.ring_suspects import annulus_mode_compliance, cs_ring, holed_ring_bounds

    cs = cs_ring(gs)
    solid = annulus_mode_compliance(cs, n_radial=16, n_theta=384)
    for count in (8, 16, 24):
        for frac in (0.4, 0.6, 0.8):
            holes = Holes(count, frac * cs.thickness_mm, cs.mean_radius_mm)
            f = annulus_mode_compliance(cs, holes=holes, n_radial=16, n_theta=384) / solid
            lo, hi = holed_ring_bounds(cs, holes)
            print(f"  {count} holes of {frac:g} × the wall (Ø{holes.diameter_mm:.2f} mm): × {f:.3f} (hand bounds {lo:.3f} "
                  f"… {hi:.3g})", flush=True)


def climb_runs(gs, scales) -> None:
    from profilegen.contact.inputs import ContactInput
    from profilegen.contact.ratchet import ratcheting_torque

    _, cat = _catalogue(gs)
    t0 = time.perf_counter()
    design = pg.design(gs, scene="verify", contact=False, stress=False)
    inputs = ContactInput.from_design(design)
    print(f"  verify design {time.perf_counter() - t0:.1f} s")
    flexed = flexed_bearing(gs)
    print(f"  race + rim axial flexure (strip model) {flexed.flexure_mm_per_n:.3g} mm/N per ball in series with Hertz "
          f"({float(flexed.secant_compliance_mm_per_n(500.0)) - flexed.flexure_mm_per_n:.3g} mm/N at 500 N); "
          f"the plate (Morley) / the strip: {plate_over_strip(gs):.3f}")
    base = None
    runs = [(label, s, True) for label, s in scales] + [("+ race/rim axial flexure", 1.0, flexed),
                                                        (f"{scales[1][0]} + flexure", scales[1][1], flexed)]
    for label, s, bearing in runs:
        t0 = time.perf_counter()
        r = ratcheting_torque(inputs, catalogue=cat, options={"climb_ring_scale": s, "bearing": bearing})
        base = r.torque_nm if base is None else base
        ratio = "—" if cat is None else f"{r.torque_nm / cat['torque_nm']:.2f}"
        print(f"  ring × {s:.3f} ({label}): {r.torque_nm:.0f} N·m ({r.climb['criterion']}), {r.torque_nm / base:.3f} of "
              f"×1, / catalogue {ratio} (catalogue {None if cat is None else cat['torque_nm']}); "
              f"{time.perf_counter() - t0:.1f} s")


def stiffness_runs(gs, scales, verify=None) -> None:
    """``verify``: the verify scene's (K1, K2, K3) / catalogue of this set (catalogue_sizes.py's CSV),
    to which each row's added rotation C·T is added in series (an estimate), or None."""
    from threadpoolctl import threadpool_limits

    from profilegen.contact.chain import compliance_chain, torsional_curve
    from profilegen.contact.compliance import ContactCompliance
    from profilegen.contact.inputs import ContactInput
    from tests.oracles.cs_ring import CSRing, cs_ring_compliance

    row, _ = _catalogue(gs)
    t1, t2, t3 = float(row["T1_nm"]), float(row["T2_nm"]), float(gs.torque.peak_nm)
    c1, c2, c3 = (float(row[k]) for k in ("K1_nm_per_rad", "K2_nm_per_rad", "K3_nm_per_rad"))
    design = pg.design(gs, scene="design", contact=False, stress=False)
    inputs = ContactInput.from_design(design)
    chain = compliance_chain(gs)
    series = chain.series_compliance_rad_per_nm
    curve = torsional_curve(design, [-t2, -t1, t1, t2], chain=chain, catalogue=row, ball_supports="all")
    theta0 = curve.first_contact_rad["positive"]
    pts = curve.sides[1][0]
    with threadpool_limits(limits=1, user_api="blas"):
        every = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                        wrap_half_angle_rad=inputs.rim_contact_angle_rad, ball_supports="all", cs_ring=False)

    def phis(comp, bearing=chain.bearing):
        out = {}
        with threadpool_limits(limits=1, user_api="blas"):
            for t in (t1, t2, t3):
                sol, _, _ = comp.solve_unilateral(pts.theta_rad, pts.lever_mm, t / pts.zones * 1e3,
                                                  bearing=bearing)
                out[t] = float(sol.phi_rad) - theta0 + t * series
        return out

    base = phis(every)
    ring = CSRing.from_gearset(gs)
    print(f"  one section, every ball one-sided + Hertz + series parts (design scene); catalogue K1 {c1:.3g}, K2 {c2:.3g}, "
          f"K3 {c3:.3g} N·m/rad on T1 {t1:g}, T2 {t2:g}, peak {t3:g} N·m")
    print(f"  {'radial ring added to the CS block':40s} {'K1/cat':>7s} {'K2/cat':>7s} {'K3/cat':>7s} {'C(T1)':>9s} "
          f"{'C(T2)':>9s} {'C(T3)':>9s}  (C: added rotation / T, rad/(N·m))")
    flexed = flexed_bearing(gs)
    rows = [("none (the CS sector alone)", 0.0, chain.bearing)] + [(lab, s, chain.bearing) for lab, s in scales] + [
        ("race/rim axial flexure (strip)", 0.0, flexed), (f"{scales[1][0]} + flexure", scales[1][1], flexed)]
    for label, s, bearing in rows:
        if s == 0.0:
            p = phis(every, bearing)
        else:
            rg = dataclasses.replace(ring, youngs_modulus_mpa=ring.youngs_modulus_mpa / s)
            extra = cs_ring_compliance(rg, pts.cs_point_mm, pts.normal, zones=pts.zones)
            p = phis(dataclasses.replace(every, cs_matrix_mm_per_n=every.cs_matrix_mm_per_n + extra), bearing)
        k1, k2, k3 = t1 / p[t1], (t2 - t1) / (p[t2] - p[t1]), (t3 - t2) / (p[t3] - p[t2])
        d = {t: (p[t] - base[t]) / t for t in (t1, t2, t3)}
        line = f"  {label:40s} {k1 / c1:7.3f} {k2 / c2:7.3f} {k3 / c3:7.3f} {d[t1]:9.3g} {d[t2]:9.3g} {d[t3]:9.3g}"
        if verify is not None:  # the verify scene's sliced curve + the same added rotation C·T (an estimate)
            q1 = t1 / (verify[0] * c1) + d[t1] * t1
            q2 = t1 / (verify[0] * c1) + (t2 - t1) / (verify[1] * c2) + d[t2] * t2
            q3 = t1 / (verify[0] * c1) + (t2 - t1) / (verify[1] * c2) + (t3 - t2) / (verify[2] * c3) + d[t3] * t3
            line += (f"   verify + C·T: {t1 / q1 / c1:.2f} / {(t2 - t1) / (q2 - q1) / c2:.2f} / "
                     f"{(t3 - t2) / (q3 - q2) / c3:.2f}")
        print(line)


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    warnings.filterwarnings("ignore")
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sets", nargs="*", default=["25:100", "32:100", "40:100", "32:50"], help="size:ratio")
    ap.add_argument("--holes", default="16,0.6", help="hole count, hole diameter / the CS ring's wall")
    ap.add_argument("--bores", default="0.25,0.5,0.7,0.85", help="plug bore / the inner race's seat radius")
    ap.add_argument("--climb", action="store_true", help="the verify scene's ratcheting estimate per scale")
    ap.add_argument("--stiffness", action="store_true", help="K1/K2/K3 with the radial ring compliance")
    ap.add_argument("--verify-csv", type=Path, nargs="*", default=[],
                    help="catalogue_sizes.py CSVs (--scene verify): each set's K's + the added C·T, in series")
    ap.add_argument("--holes-sweep", action="store_true", help="the holes' factor over count and diameter only")
    ap.add_argument("--set", dest="settings", action="append", default=[], metavar="SECTION.KEY=VALUE",
                    help="a proportion of the sets changed (catalogue_sizes.py --set), e.g. tooth.addendum_coefficient=0.5")
    args = ap.parse_args()
    count, frac = args.holes.split(",")
    verify = {}
    for path in args.verify_csv:
        with open(path, newline="", encoding="utf-8") as fh:
            for row in csv.DictReader(fh):
                verify[(int(row["size"]), int(row["ratio"]))] = tuple(float(row[k]) for k in ("K1_ratio", "K2_ratio",
                                                                                              "K3_ratio"))
    bores = tuple(float(x) for x in args.bores.split(","))
    for spec in args.sets:
        size, ratio = (int(x) for x in spec.split(":"))
        made = pg.new_gearset(size, ratio)
        gs = made.gearset
        if args.settings:
            import tomllib

            from catalogue_sizes import with_settings  # this script's folder: the same study knob

            from profilegen.gearset import parse_gearset

            data = tomllib.loads(made.text)
            with_settings(data, args.settings)
            gs = parse_gearset(data)
        print(f"\n=== CSF-{size}-{ratio} (profilegen new{''.join(' --set ' + x for x in args.settings)})")
        if args.holes_sweep:
            holes_sweep(gs)
            continue
        real, hollow = factors(gs, int(count), float(frac), bores)
        scales = [("CS thick + holes + plug bore 0.5", real), ("… + plug bore 0.85, a hollow cam", hollow)]
        if args.climb:
            climb_runs(gs, [("the product: free thin CS ring", 1.0)] + scales)
        if args.stiffness:
            stiffness_runs(gs, [("free thin CS ring (×1)", 1.0)] + [(f"free CS ring × {s:.3f}: {lab}", s)
                                                                   for lab, s in scales], verify.get((size, ratio)))


if __name__ == "__main__":
    main()
