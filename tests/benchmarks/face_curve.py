"""The torsional curve across the face (issue 16 items 1 and 5): does the cup's coning soften the whole gear?

    python tests/benchmarks/face_curve.py [profiles/seed000_csf40.toml ...] [--slices 1 2 4 8] [--verify-slices 1 2 4 8 16]
                                          [--ends-slices 2 3 5 9 17] [--no-verify] [--timing]

For each gear set (default seed000_csf40) and the catalogue row of its size and ratio
(contact.chain.catalogue_for; T1, T2 its breakpoints, T3 the set's peak torque):

* **design scene** (the 2D section at mid-face, the CS conjugate to it, straight teeth — the
  curve the design run reports): the 2D curve (torsional_curve, every ball a one-sided Hertz
  support, series cup wall + bottom + CS body), then the same curve on N slices
  (torsional_curve(face_slices=FaceSlices(N, coning))) for the 3D cup's sections
  (press_cup of the set, defaults) and for semi-membrane coning (ω, υ ∝ z);
* **verify scene** (the gear as the package makes it: the 3D cup tier, the face stage's design
  section and its FS tooth taper/crowning — design.face): its 2D curve (the design section's
  contact), the slices with the face stage's modification for both conings, and without it;
  then the same with the slices' sections on the face ends (FaceSlices(nodes="ends"), the
  trapezoid rule: the face stage's design section is often a face end, where the first
  contact then is — N − 1 = 1, 2, 4, 8, 16 intervals); at N = 5 also with the slices' whole
  section coupled along the face (FaceSlices(coupling_length_mm=λ), a Pasternak foundation) for
  λ = 1 mm (about the tooth height) and λ = √(r_m δ) (the rim as a cylindrical shell), the stiff
  side of what the independent slices leave out.

Printed per case: the whole gear's rotation (elastic, from the loaded flank's first contact —
the curve's own zero, the smallest first contact over every slice) at T1, T2, T3 and the
rotation at ±3 % of the rated torque, K1 = T1/φ(T1), K2 = (T2 − T1)/(φ(T2) − φ(T1)), the
secant T2/φ(T2), each against the catalogue, the lost motion (φ(+3 %) − φ(−3 %), backlash
included), the backlash, the smallest two-flank play of any slice (negative: the teeth
interfere there at no load, and the one-flank curve is not the gear), the range of the loaded
flank's gap shifts Δe, the compliance the
slices add to the 2D curve's at T1 and T2 (secants, rad/(N·m)), and CPU seconds. With
``--timing``: the design run's whole curve (curve_torques_nm, ≥ 32 torques both ways) with
the flanks reused, median of 3, for each N (design scene, and the verify scene's face-end nodes).
"""

from __future__ import annotations

import argparse
import math
import resource
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))

import numpy as np  # noqa: E402

import profilegen as pg  # noqa: E402
from profilegen.contact.chain import (  # noqa: E402
    ARCMIN_PER_RAD, catalogue_for, compliance_chain, curve_torques_nm, torsional_curve)
from profilegen.contact.face_curve import FaceSlices  # noqa: E402
from profilegen.contact.inputs import ContactInput  # noqa: E402


def _catalogue_secant_t2(cat) -> float:
    t1, t2, k1, k2 = cat["T1_nm"], cat["T2_nm"], cat["K1_nm_per_rad"], cat["K2_nm_per_rad"]
    return t2 / (t1 / k1 + (t2 - t1) / k2)


def _row(label, curve, cat, base, t1, t2, t3, t_lm, play, cpu):
    k = curve.k_nm_per_rad["total"]["positive"]
    th0 = curve.first_contact_rad["positive"]
    phi = {t: curve.rotation_at(t) - th0 for t in (t1, t2, t3)}
    add = "" if base is None else (
        f" | added C(T1) {(phi[t1] - base[t1]) / t1:+.3e} C(T2) {(phi[t2] - base[t2]) / t2:+.3e} rad/(N·m)")
    lm = curve.lost_motion_rad["total"] * ARCMIN_PER_RAD
    print(f"  {label:34s} φ(T1,T2,T3) {phi[t1] * ARCMIN_PER_RAD:6.3f} {phi[t2] * ARCMIN_PER_RAD:6.3f} "
          f"{phi[t3] * ARCMIN_PER_RAD:6.3f}′  φ(±3%) {curve.rotation_at(t_lm) * ARCMIN_PER_RAD:+.4f} "
          f"{curve.rotation_at(-t_lm) * ARCMIN_PER_RAD:+.4f}′ | K1 {k['K1']:.4g} ({k['K1'] / cat['K1_nm_per_rad']:.2f}×) "
          f"K2 {k['K2']:.4g} ({k['K2'] / cat['K2_nm_per_rad']:.2f}×) sec T2 {k['secant_T2']:.4g} "
          f"({k['secant_T2'] / _catalogue_secant_t2(cat):.2f}×) | LM {lm:.3f}′ backlash "
          f"{curve.backlash_rad * ARCMIN_PER_RAD:+.3f}′ least slice play {play[0]:+.3f}′"
          + ("" if len(play) == 1 else f" Δe {play[1]:+.1f}…{play[2]:+.1f} µm") + f"{add} | {cpu:.2f} s CPU")
    return phi


def _play(inputs, sides, spec) -> tuple[float, float, float]:
    """The smallest two-flank play of any slice (arcmin): min θ(+) + min θ(−) per slice; and the
    range of the loaded flank's gap shifts Δe (µm)."""
    from profilegen.contact.face_curve import slice_gap_shifts

    first, shifts = {}, None
    for s, (pts, _) in sides.items():
        _, de = slice_gap_shifts(inputs, pts, spec.slices, coning=spec.coning, cup=spec.cup, nodes=spec.nodes,
                                 design_z_mm=spec.design_z_mm, modification=spec.modification)
        first[s] = ((pts.gap_mm[None, :] + de) / pts.lever_mm[None, :]).min(axis=1)
        if s == 1:
            shifts = (float(de.min()) * 1e3, float(de.max()) * 1e3)
    return (float((first[1] + first[-1]).min()) * ARCMIN_PER_RAD,) + shifts


def _face_load(inputs, sides, chain, spec, torque_nm) -> None:
    """The load per slice at ``torque_nm`` on the loaded flank (the curve's model: every ball one-sided
    with its Hertz spring in every slice), against the 2D solve spread evenly (S_2D/b)."""
    from profilegen.contact.face_curve import slice_layout
    from profilegen.contact.reduced import ReducedZone

    def solve(pts, comp, bearing):
        zone = ReducedZone(pts, comp, bearing)
        loaded = np.zeros(pts.count, bool)
        loaded[int(np.argmin(pts.theta_rad))] = True
        out = zone.solve(torque_nm, (loaded, np.asarray(comp.ball_active, bool), None), springs_on=True,
                         max_iterations=400, spring_tol=1e-5)
        if out is None:
            raise RuntimeError("face_curve benchmark: the reduced solve did not settle")
        return out

    pts2, comp2 = sides[1]
    flat = solve(pts2, comp2, chain.bearing)
    stacked, new_chain, _ = spec.apply(inputs, sides, chain)
    pts, comp = stacked[1]
    out = solve(pts, comp, new_chain.bearing)
    b = float(comp2.face_width_mm)
    zeta, w = slice_layout(b, spec.slices, spec.nodes)
    f = out["force"].reshape(spec.slices, pts2.count)
    teeth, slot = np.unique(pts2.tooth, return_inverse=True)
    per_tooth = np.array([np.bincount(slot, weights=fi, minlength=teeth.size) for fi in f])
    flat_tooth = np.bincount(slot, weights=flat["force"], minlength=teeth.size)
    line = f.sum(axis=1) / w
    peak = float((per_tooth / w[:, None]).max())
    uniform = float(flat_tooth.max()) / b
    print(f"  load across the face at {torque_nm:g} N·m ({spec.slices} slices, {spec.nodes}): line load per slice "
          f"(N/mm, from the diaphragm end) " + " ".join(f"{v:.0f}" for v in line)
          + f"; even spread {flat['force'].sum() / b:.0f}; peak line load of one tooth {peak:.1f} N/mm against "
          f"max F_2D/b {uniform:.1f} (×{peak / uniform:.2f}); teeth loaded per slice "
          + " ".join(str(int(np.count_nonzero(pt > 0))) for pt in per_tooth)
          + f" (2D {int(np.count_nonzero(flat_tooth > 0))})")


def _check_face_stage(inputs, vd, face, mod) -> None:
    """The slices' first-order gaps against the face stage's exact clearance maps at its own sections:
    the two-flank play of each section (min θ(+) + min θ(−), µm at the pitch circle) beside the face
    stage's least clearance and largest backlash there, unmodified and with its modification."""
    from profilegen.contact.face_curve import slice_gap_shifts

    sections = np.array([sec.z_mm for sec in face.sections])
    gs = inputs.gearset
    b, zc = float(gs.cup.face_width_mm), float(gs.cup.length_mm)
    nodes = np.linspace(zc - 0.5 * b, zc + 0.5 * b, sections.size)
    if not np.allclose(nodes, sections):
        print(f"  (the face stage's sections {sections} are not the face-end nodes: no check)")
        return
    curve = torsional_curve(inputs, [-1.0, 1.0])
    rp = float(gs.gear.pitch_radius_mm)
    for label, m, table in (("unmodified", None, face.table), ("modified", mod, None if mod is None else mod.table)):
        if table is None:
            continue
        first = {}
        for s, (pts, _) in curve.sides.items():
            _, de = slice_gap_shifts(inputs, pts, sections.size, coning="cup", cup=vd.rim.cup, nodes="ends",
                                     design_z_mm=face.design_section_z_mm, modification=m)
            first[s] = ((pts.gap_mm[None, :] + de) / pts.lever_mm[None, :]).min(axis=1)
        play = (first[1] + first[-1]) * rp * 1e3
        print(f"  face stage check, {label}: z (mm) / face stage least clearance, largest backlash (µm) / slices' "
              "two-flank play (µm at the pitch circle): " + "; ".join(
                  f"{r.z_mm:g}: {r.min_clearance_mm * 1e3:+.2f}, {r.max_backlash_mm * 1e3:.2f} / {p:+.2f}"
                  for r, p in zip(table, play)))


def _cases(label, inputs, cat, cup, design_z, modification, slices, conings, timing, nodes="midpoint", couplings=()):
    gs = inputs.gearset
    t1, t2, t3 = float(cat["T1_nm"]), float(cat["T2_nm"]), float(gs.torque.peak_nm)
    t_lm = 0.03 * float(gs.torque.rated_nm)
    torques = [s * t for t in (t_lm, t1, t2, t3) for s in (1.0, -1.0)]
    chain = compliance_chain(gs)
    c0 = time.process_time()
    base_curve = torsional_curve(inputs, torques, chain=chain, catalogue=cat, breakpoints_nm=(t1, t2))
    mod_text = "none (straight teeth)" if modification is None else \
        f"taper {modification.taper_mm_per_mm * 1e3:.4g} µm/mm, crowning {modification.crowning_mm * 1e3:.4g} µm"
    print(f"--- {label}: design section z = {design_z if design_z is not None else gs.cup.length_mm:g} mm, "
          f"tooth modification {mod_text}")
    base = _row("2D (even spread)", base_curve, cat, None, t1, t2, t3, t_lm, (base_curve.backlash_rad * ARCMIN_PER_RAD,),
                time.process_time() - c0)
    sides = base_curve.sides
    for coning, mods in conings:
        for mod in mods:
            for n in slices:
                spec = FaceSlices(n, coning, cup, design_z, mod, nodes=nodes)
                c0 = time.process_time()
                curve = torsional_curve(inputs, torques, chain=chain, catalogue=cat, breakpoints_nm=(t1, t2),
                                        sides=sides, face_slices=spec)
                cpu = time.process_time() - c0
                tag = f"{coning} N={n}" + ("" if nodes == "midpoint" else f" {nodes}") + ("" if mod is None or mod is modification else " unmodified") + \
                    ("" if mod is not None or modification is None else " straight")
                _row(tag, curve, cat, base, t1, t2, t3, t_lm, _play(inputs, sides, spec), cpu)
    if nodes == "ends" and conings and couplings:
        # the soft bound (independent slices) against the slices coupled along the face (Pasternak)
        n = max(n for n in slices if n <= 5)
        for lam in couplings:
            spec = FaceSlices(n, conings[0][0], cup, design_z, conings[0][1][0], nodes=nodes, coupling_length_mm=lam)
            c0 = time.process_time()
            curve = torsional_curve(inputs, torques, chain=chain, catalogue=cat, breakpoints_nm=(t1, t2), sides=sides,
                                    face_slices=spec)
            _row(f"{conings[0][0]} N={n} {nodes} λ={lam:.3g} mm", curve, cat, base, t1, t2, t3, t_lm,
                 _play(inputs, sides, spec), time.process_time() - c0)
    if nodes == "ends" and conings:
        _face_load(inputs, sides, chain, FaceSlices(max(slices), conings[0][0], cup, design_z, conings[0][1][0],
                                                    nodes=nodes), float(gs.torque.rated_nm))
    if timing:
        all_t = curve_torques_nm(gs, (t1, t2))
        for n in slices:
            spec = FaceSlices(n, conings[0][0], cup, design_z, conings[0][1][0], nodes=nodes)
            runs = []
            for _ in range(3):
                c0 = time.process_time()
                torsional_curve(inputs, all_t, chain=chain, catalogue=cat, breakpoints_nm=(t1, t2), sides=sides,
                                face_slices=spec)
                runs.append(time.process_time() - c0)
            print(f"  whole curve ({all_t.size} torques) with face_slices={n} ({nodes}): {statistics.median(runs):.2f} s CPU "
                  f"(median of 3; flanks reused, the cup's sections and slices built each time)")


def run(path: Path, slices, verify_slices, ends_slices, verify: bool, timing: bool) -> None:
    from profilegen.rim.cup.contact import press_cup

    gs = pg.load_gearset(path)
    cat = catalogue_for(gs)
    print(f"\n=== {gs.name} ({path.name}): catalogue {cat['source']}: T1 {cat['T1_nm']:g}, K1 {cat['K1_nm_per_rad']:.3g}, "
          f"T2 {cat['T2_nm']:g}, K2 {cat['K2_nm_per_rad']:.3g} N·m/rad; face {gs.cup.face_width_mm:g} mm, "
          f"mid-face z = {gs.cup.length_mm:g} mm")
    c0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    cup = press_cup(gs)
    print(f"design scene + press_cup: {time.process_time() - c0:.1f} s CPU")
    _cases("design scene (CS at mid-face, straight teeth)", ContactInput.from_design(design), cat, cup, None, None,
           slices, (("cup", (None,)), ("semi_membrane", (None,))), timing)
    if not verify:
        return
    c0 = time.process_time()
    vd = pg.design(gs, scene="verify", contact=False, stress=False)
    face = vd.face
    mod = face.modification
    print(f"verify scene design (3D cup, face stage): {time.process_time() - c0:.1f} s CPU; design section "
          f"{face.design_section_z_mm:g} mm ({face.design_choice}); modification taper "
          f"{0 if mod is None else mod.taper_mm_per_mm * 1e3:.4g} µm/mm, crowning "
          f"{0 if mod is None else mod.crowning_mm * 1e3:.4g} µm, largest backlash "
          f"{float('nan') if mod is None else mod.max_backlash_mm * 1e3:.3g} µm")
    conings = (("cup", (mod, None) if mod is not None else (None,)), ("semi_membrane", (mod,)))
    vin = ContactInput.from_design(vd)
    _check_face_stage(vin, vd, face, mod)
    _cases("verify scene (as made)", vin, cat, vd.rim.cup, face.design_section_z_mm, mod, verify_slices, conings, False)
    if ends_slices:
        _cases("verify scene (as made), nodes on the face ends (trapezoid rule)", vin, cat, vd.rim.cup,
               face.design_section_z_mm, mod, ends_slices, (("cup", (mod,)),), timing, nodes="ends",
               couplings=(1.0, math.sqrt(float(gs.gear.neutral_radius_mm) * float(gs.gear.rim_thickness_mm))))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sets", nargs="*", type=Path, default=[ROOT / "profiles" / "seed000_csf40.toml"])
    ap.add_argument("--slices", nargs="+", type=int, default=[1, 2, 4, 8])
    ap.add_argument("--verify-slices", nargs="+", type=int, default=[1, 2, 4, 8, 16])
    ap.add_argument("--ends-slices", nargs="*", type=int, default=[2, 3, 5, 9, 17],
                    help="the verify scene again with nodes on the face ends (FaceSlices(nodes='ends')); none: skip")
    ap.add_argument("--no-verify", action="store_true", help="the design scene only")
    ap.add_argument("--timing", action="store_true", help="the whole curve's CPU time for each N")
    args = ap.parse_args()
    from profilegen.blas import one_blas_thread

    with one_blas_thread():
        for path in args.sets:
            run(path, args.slices, args.verify_slices, args.ends_slices, not args.no_verify, args.timing)


if __name__ == "__main__":
    main()
