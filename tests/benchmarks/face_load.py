"""Load across the face (issue 16 item 5): per-slice load, peak line load and the mesh stiffness
with the 3D cup's coning against today's even spread (S = S_2D/b).

    python tests/benchmarks/face_load.py [profiles/seed000_csf40.toml]

For the gear set (default seed000_csf40; design scene, no contact or stress in the design run):
the 2D contact points and compliance of the loaded flank, the cup pressed onto its cam
(profilegen.rim.cup.contact.press_cup, defaults), the gap shifts of N slices across the face
from the cup's sections and from semi-membrane coning (ω, υ ∝ z), then at 54, 196, 265 N·m
(T1, T2 of the catalogue's size 40 and the rated torque): each slice's line load against the
even spread, the peak line load of one tooth in one slice against max F_2D / b, and the
mesh's rotation — the secant from the design's first contact and the chord between 54 and
196 N·m (the catalogue's K2 interval), with and without coning; slices 4 / 8 / 16 at the rated
torque; the slices coupled (Pasternak) with λ = the tooth height and λ = √(r_m δ) (the rim as a
cylindrical shell) to bracket what the independent slices leave out. Then both flanks
(research.face_load.face_two_flanks: where coning makes the flanks overlap at no
load the one-flank model lets the FS back off freely, both flanks do not), every ball active,
rigid or as a Hertz spring (its secant at 2000 and 500 N): the torque each flank carries at
zero and the rated torque (the preload), the + flank's line load per slice, K1 = T1/(φ(T1) −
φ(0⁺)), K2 = (T2 − T1)/(φ(T2) − φ(T1)), the lost motion φ(+3 %) − φ(−3 %), with and without
coning. CPU times.
"""

from __future__ import annotations

import math
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

import profilegen as pg  # noqa: E402
from profilegen.contact.analysis import solve_contact  # noqa: E402
from research.face_load import (  # noqa: E402
    cup_sections, gap_shift_mm, semi_membrane_sections, slice_positions, solve_face, two_flank_sides)
from profilegen.contact.inputs import ContactInput  # noqa: E402
from profilegen.rim.cup.contact import press_cup  # noqa: E402

resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
TORQUES = (54.0, 196.0, 265.0)


def shifts_for(inp, pts, sections, reference):
    return np.array([gap_shift_mm(pts, inp.motion, s, reference) for s in sections])


def main(path: Path) -> None:
    gs = pg.load_gearset(path)
    t0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    inp = ContactInput.from_design(design)
    cup = press_cup(gs)
    print(f"=== {gs.name}: design + cup {time.process_time() - t0:.1f} s CPU")
    b, z0 = float(gs.cup.face_width_mm), float(gs.cup.length_mm)
    g = gs.gear
    print(f"face b = {b:g} mm, design section z0 = {z0:g} mm (cup bottom mid-plane to mid-face), "
          f"bearing {cup.deformation.geometry.bearing_span_mm} mm")
    with threadpool_limits(limits=1, user_api="blas"):
        res = solve_contact(inp, list(TORQUES))
        pts, comp = res.points, res.compliance
        print(f"{pts.count} candidate points, 2D first contact {pts.theta_rad.min() * 1e6:.3f} µrad")
        d = cup.deformation
        zs = slice_positions(b, 8, z0)
        print("cup ω at the major axis across the face (µm, against z0): "
              + " ".join(f"{(d.omega(0.0, z) - d.omega(0.0, z0)) * 1e3:+.1f}" for z in zs)
              + f"  (ω(0, z0) = {d.omega(0.0, z0):.4f} mm; semi-membrane: "
              + " ".join(f"{d.omega(0.0, z0) * (z / z0 - 1) * 1e3:+.1f}" for z in zs) + ")")
        runs = {}
        for n in (4, 8, 16):
            z = slice_positions(b, n, z0)
            secs = cup_sections(cup, np.r_[z0, z])
            runs[("cup", n)] = shifts_for(inp, pts, secs[1:], secs[0])
        z8 = slice_positions(b, 8, z0)
        runs[("semi_membrane", 8)] = shifts_for(inp, pts, semi_membrane_sections(inp.motion.deformation, z8, z0),
                                                inp.motion.deformation)
        runs[("none", 8)] = np.zeros((8, pts.count))
        for key, sh in runs.items():
            if key[1] == 8:
                print(f"gap shifts {key[0]:13s}: per slice min/max µm "
                      + " ".join(f"[{a * 1e3:+.1f},{c * 1e3:+.1f}]" for a, c in zip(sh.min(1), sh.max(1))))

        def solve(key, torque, lam=0.0):
            case = res.cases[TORQUES.index(torque)]
            matrix = comp.with_balls(case.ball_active).matrix_mm_per_n
            t = time.process_time()
            n = runs[key].shape[0]
            out = solve_face(pts, matrix, runs[key], torque, face_width_mm=b, coupling_length_mm=lam,
                             z_mm=slice_positions(b, n, z0))
            return out, time.process_time() - t

        theta0 = float(pts.theta_rad.min())
        table = {}
        for key in (("none", 8), ("cup", 8), ("semi_membrane", 8)):
            print(f"\n--- coning: {key[0]}, {key[1]} slices (independent)")
            for torque in TORQUES:
                fl, cpu = solve(key, torque)
                table[(key, torque)] = fl
                print(f"T = {torque:5.0f} N·m: line load per slice (N/mm) "
                      + " ".join(f"{v:6.1f}" for v in fl.slice_line_load_n_per_mm)
                      + f" | even {fl.reference_force_n.sum() / b:6.1f}; peak tooth line load {fl.peak_line_load_n_per_mm:6.2f}"
                      f" vs even {fl.uniform_peak_line_load_n_per_mm:6.2f} N/mm (x{fl.peak_ratio:.2f}); "
                      f"φ − θ0(2D) = {(fl.rotation_rad - theta0) * 1e6:8.2f} µrad "
                      f"(even {(fl.reference_rotation_rad - theta0) * 1e6:8.2f}); first contact "
                      f"{fl.first_contact_rad * 1e6:+.2f} µrad; eq {fl.equilibrium_residual:.1e} compl "
                      f"{fl.complementarity_residual:.1e}; {cpu:.2f} s CPU")
            a, c = table[(key, 54.0)], table[(key, 196.0)]
            chord = (196.0 - 54.0) / (c.rotation_rad - a.rotation_rad)
            chord_even = (196.0 - 54.0) / (c.reference_rotation_rad - a.reference_rotation_rad)
            r = table[(key, 265.0)]
            print(f"mesh stiffness (N·m/rad): chord 54-196 {chord:.4g} (even {chord_even:.4g}, x{chord / chord_even:.3f}); "
                  f"secant at 265 from the 2D first contact {265.0 / (r.rotation_rad - theta0):.4g} "
                  f"(even {265.0 / (r.reference_rotation_rad - theta0):.4g})")
        print("\n--- slices at the rated torque (cup coning, independent)")
        for n in (4, 8, 16):
            fl, cpu = solve(("cup", n), 265.0)
            print(f"N = {n:2d}: peak {fl.peak_line_load_n_per_mm:6.2f} N/mm (x{fl.peak_ratio:.2f}), end slices "
                  f"{fl.slice_line_load_n_per_mm[0]:6.1f} / {fl.slice_line_load_n_per_mm[-1]:6.1f} N/mm, "
                  f"φ − θ0 = {(fl.rotation_rad - theta0) * 1e6:.2f} µrad; {cpu:.2f} s CPU")
        h = float(gs.tooth.addendum_mm + gs.tooth.dedendum_mm) if hasattr(gs.tooth, "addendum_mm") else 2.0 * g.module_mm
        shell = math.sqrt(float(g.neutral_radius_mm) * float(g.rim_thickness_mm))
        print(f"\n--- coupling between slices (cup coning, 8 slices): λ = 0, tooth height {h:.3g} mm, √(r_m δ) = {shell:.3g} mm")
        for torque in (54.0, 265.0):
            for lam in (0.0, h, shell):
                fl, cpu = solve(("cup", 8), torque, lam)
                print(f"T = {torque:5.0f}, λ = {lam:5.2f} mm: per slice " + " ".join(
                    f"{v:6.1f}" for v in fl.slice_line_load_n_per_mm) + f" N/mm; peak {fl.peak_line_load_n_per_mm:6.2f}"
                    f" (x{fl.peak_ratio:.2f}); φ − θ0 = {(fl.rotation_rad - theta0) * 1e6:.2f} µrad; {cpu:.2f} s CPU")


def two_flanks(path: Path) -> None:
    from profilegen.contact.chain import BallBearing
    from research.face_load import solve_two_flanks

    gs = pg.load_gearset(path)
    design = pg.design(gs, scene="design", contact=False, stress=False)
    inp = ContactInput.from_design(design)
    cup = press_cup(gs)
    b, z0 = float(gs.cup.face_width_mm), float(gs.cup.length_mm)
    rated = float(gs.torque.rated_nm)
    small = 1e-6
    torques = (small, -small, 0.03 * rated, -0.03 * rated, 54.0, 196.0, rated)
    bearing = BallBearing.from_gearset(gs)
    with threadpool_limits(limits=1, user_api="blas"):
        t0 = time.process_time()
        pos, neg, comp = two_flank_sides(inp)
        print(f"\n=== both flanks, {gs.name}: {pos.count} + {neg.count} points, one compliance "
              f"({time.process_time() - t0:.1f} s CPU); every ball active")
        z = slice_positions(b, 8, z0)
        secs = cup_sections(cup, np.r_[z0, z])
        cone = np.array([np.r_[gap_shift_mm(pos, inp.motion, sec, secs[0]), gap_shift_mm(neg, inp.motion, sec, secs[0])]
                         for sec in secs[1:]])
        gap = np.r_[pos.gap_mm, neg.gap_mm]
        lever = np.r_[pos.lever_mm, neg.lever_mm]
        sense = np.r_[np.ones(pos.count), -np.ones(neg.count)]
        supports = {"rigid balls": None}
        for q in (2000.0, 500.0):
            supports[f"Hertz balls (secant at {q:g} N)"] = float(bearing.secant_compliance_mm_per_n(q))
        for support, c in supports.items():
            matrix = comp.with_balls(np.ones_like(comp.ball_active), ball_compliance_mm_per_n=c).matrix_mm_per_n
            for coning, shifts in (("none", np.zeros_like(cone)), ("cup", cone)):
                phi = {}
                t0 = time.process_time()
                for t in torques:
                    r = solve_two_flanks(gap, lever, sense, matrix, shifts, t, zones=pos.zones)
                    phi[t] = r.rotation_rad
                    if t in (small, rated):
                        fp, fn = r.flank_torque_nm
                        loaded = r.force_n[:, :pos.count]
                        line = loaded.sum(axis=1) / (b / 8)
                        per_tooth = np.array([np.bincount(np.searchsorted(np.unique(pos.tooth), pos.tooth), weights=row)
                                              for row in loaded])
                        print(f"  {support:28s} {coning:4s} T = {t:7.3g}: zone torque on the + / − flank {fp:7.2f} / "
                              f"{fn:7.2f} N·m; + flank per slice (N/mm) " + " ".join(f"{v:6.1f}" for v in line)
                              + f"; peak tooth line load {per_tooth.max() / (b / 8):6.2f} N/mm; eq "
                              f"{r.equilibrium_residual:.0e} compl {r.complementarity_residual:.0e}")
                k1 = 54.0 / (phi[54.0] - phi[small])
                k2 = (196.0 - 54.0) / (phi[196.0] - phi[54.0])
                lm = (phi[0.03 * rated] - phi[-0.03 * rated]) * 180 * 60 / math.pi
                print(f"{support:30s} {coning:4s}: mesh K1 {k1:.4g}, K2 {k2:.4g} N·m/rad; lost motion at ±{0.03 * rated:.3g}"
                      f" N·m {lm:.4f} arcmin; free play {(phi[small] - phi[-small]) * 1e6:.4f} µrad "
                      f"({time.process_time() - t0:.1f} s CPU, {len(torques)} torques)")


if __name__ == "__main__":
    target = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "profiles" / "seed000_csf40.toml"
    main(target)
    two_flanks(target)
