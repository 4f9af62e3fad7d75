"""Dedoidal ratcheting (issue 16 item 4): does the eccentric (n = 1) mode lower the ratcheting torque?

    python tests/benchmarks/dedoidal.py [--loads 100,1000] [--ecc 5,10] [--no-scan] [--fine T0,STEP,N] [profiles/...]

Per gear set (default: seed000_csf40 and csf32_100; design scene, no contact or stress in the
design run), the climb built as ``ratcheting_torque`` builds it (9 stations, teeth within
one module (ratchet.CLIMB_GAP_PER_MODULE), every ball one-sided at its no-load gap with its Hertz spring, the free CS ring):

1. the one-zone climb (profilegen.contact.climb, the estimate today);
2. the two-zone climb (research.dedoidal.TwoZoneClimb, the FS as the whole ring, the
   FS/WG assembly free to translate, the cam floating) with no imperfection: must give the same;
3. the eccentric mode's stiffness K (2 × 2, N/mm, dedoidal.n1_stiffness, ±1 µm) at every point
   of that path, its smallest eigenvalue, and the first torque where it reaches 0
   (dedoidal.stability_limit) — the bifurcation of the symmetric path;
4. the eccentricity ``--ecc`` (µm). A free FS/WG assembly absorbs it exactly (the assembly
   shifts by e: the same path). What holds the FS tooth ring on the output axis is the cup's
   lateral stiffness k_c; ESTIMATE (upper bound): the cup wall as a Timoshenko cantilever
   clamped at a rigid bottom, loaded at the mid-face — k_c = 1/(L³/(3 E π R³ h) + L/(G π R h)),
   R the neutral radius, h the wall, L the cup length; the diaphragm's tilt (left out) makes it
   softer. The eccentricity is applied as the load it puts on the assembly, P = k_c e (radial,
   along the major axis), with the assembly otherwise free: the two-zone climb and its
   stability check along the path. (The spring's own stiffness is left out: it stabilises, so
   this is the lower end. The full ring's translation gauge is the bore at the major axis,
   not the ring's centre, so a cup spring on it would be wrong by the ring's own deformation.)
5. ``--loads`` (N): the same with a radial load P on the assembly given directly.
6. ``--fine T0,STEP,N``: the symmetric two-zone path followed again from its last point below
   T0 (N·m) in N rotation steps of STEP (mrad), each point's torque, mean retreat, the eccentric
   mode's smallest eigenvalue and whether T(φ) falls there (a snap of the discrete contact).

Prints per set the torques against the catalogue's (CSF table 4: CSF-40-100 2100 N·m,
CSF-32-100 1000 N·m) and CPU times.
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

SETS = [ROOT / "profiles" / "seed000_csf40.toml", ROOT / "profiles" / "csf32_100.toml"]


def cup_lateral_stiffness_n_per_mm(gs) -> float:
    """ESTIMATE, an upper bound: the cup wall a thin tube clamped at a rigid bottom, loaded at
    its mid-face (bending 3EI/L³ and shear G π R h / L in series)."""
    e = float(gs.material.youngs_modulus_mpa)
    g = e / (2.0 * (1.0 + float(gs.material.poisson_ratio)))
    r = float(gs.gear.neutral_radius_mm)
    h = float(gs.cup.wall_thickness_mm or gs.gear.rim_thickness_mm)
    length = float(gs.cup.bearing_center_mm or gs.cup.length_mm)
    bend = length ** 3 / (3.0 * e * math.pi * r ** 3 * h)
    shear = length / (g * math.pi * r * h)
    return 1.0 / (bend + shear)


def _setup(gs, design):
    from profilegen.contact import ratchet
    from profilegen.contact.chain import BallBearing
    from profilegen.contact.climb import DesignClimb
    from profilegen.contact.inputs import ContactInput

    inputs = ContactInput.from_design(design)
    r_mean, thick, width, _ = ratchet._cs_ring_section(gs, inputs)

    def factory(phis):
        ang = np.concatenate([phis, phis + math.pi])
        return ratchet.cs_ring_radial_compliance(ang, phis, mean_radius_mm=r_mean, thickness_mm=thick, width_mm=width,
                                                 youngs_modulus_mpa=float(gs.material.youngs_modulus_mpa))
    bearing = BallBearing.from_gearset(gs)
    zone = DesignClimb(inputs, side=1, stations=9, max_gap_mm=ratchet.CLIMB_GAP_PER_MODULE * float(gs.gear.module_mm),
                       race_thickness_mm=None, bearing=bearing,
                       ring_factory=factory, ball_supports="all")
    return inputs, zone, bearing, (r_mean, thick, width)


def _catalogue(gs):
    from profilegen.contact.chain import catalogue_for

    row = catalogue_for(gs)
    return None if row is None else row.get("ratcheting_torque_nm")


def _path_table(model, path):
    for p in path.points:
        zt = model.zone_torques_nm(p) if hasattr(model, "zone_torques_nm") else None
        tau = p.state.translation_mm[:2] * 1e3 if hasattr(p.state, "translation_mm") else None
        extra = "" if zt is None else f"  zones {zt[0]:8.1f} {zt[1]:8.1f}  τ (µm) {tau[0]:7.2f} {tau[1]:7.2f}"
        print(f"    φ {p.phi_rad * 1e3:7.4f} mrad  T {p.torque_nm:8.1f}  s̄ {p.mean_retreat_mm * 1e3:6.1f} µm{extra}")


def _scan(model, path, label):
    from research.dedoidal import stability_limit

    t0 = time.process_time()
    out = stability_limit(model, path, delta_mm=1e-3)
    print(f"  eccentric-mode check along {label}: {time.process_time() - t0:.1f} s CPU")
    for t, lam, k in out["points"]:
        print(f"    T {t:8.1f}  λ_min {lam:10.4g} N/mm  K = [[{k[0, 0]:.4g}, {k[0, 1]:.4g}], [{k[1, 0]:.4g}, "
              f"{k[1, 1]:.4g}]]")
    if out["falling"]:
        print(f"    λ_min ≤ 0 on a falling stretch of T(φ) (a snap of the discrete contact, not counted) at T = "
              f"{[round(t, 1) for t in out['falling']]}")
    if out["failed"]:
        print(f"    no fixed point for the prescribed translation at T = {out['failed']}")
    print(f"  → limit {out['torque_nm']:.1f} N·m ({out['criterion']})")
    return out


def _fine(model, path, t0_nm, step_mrad, count):
    """The symmetric path again at fine rotation steps from its last point below ``t0_nm``."""
    from profilegen.contact.climb import _point, _solve_at
    from research.dedoidal import _falling, n1_stiffness
    from profilegen.errors import ConvergenceError

    start = [p for p in path.points if p.torque_nm < t0_nm][-1]
    print(f"\n  the symmetric path from T = {start.torque_nm:.1f} N·m in steps of {step_mrad:g} mrad:")
    s_fs, s_cs, state, phi = start.retreat_fs_mm, start.retreat_mm - start.retreat_fs_mm, start.state, start.phi_rad
    for _ in range(int(count)):
        phi += step_mrad * 1e-3
        try:
            f, s_fs, s_cs, state, lever, it = _solve_at(model, phi, s_fs, s_cs, state, tol_mm=1e-6, max_iterations=80)
        except ConvergenceError:
            print(f"    φ {phi * 1e3:.4f} mrad: no fixed point")
            break
        p = _point(model, phi, f, s_fs, s_cs, state, lever, it)
        k = n1_stiffness(model, p, delta_mm=1e-3)
        lam = float(np.min(np.linalg.eigvals(k).real))
        fall = _falling(model, p, tol_mm=1e-6, max_iterations=80)
        print(f"    φ {phi * 1e3:.4f} mrad  T {p.torque_nm:8.1f}  s̄ {p.mean_retreat_mm * 1e3:6.1f} µm  λ_min "
              f"{lam:10.4g} N/mm{'  (T falls here)' if fall else ''}")


def run(path, args):
    from threadpoolctl import threadpool_limits

    from profilegen.contact.climb import climb
    from research.dedoidal import TwoZoneClimb

    gs = pg.load_gearset(path)
    cat = _catalogue(gs)
    print(f"\n=== {gs.name}: rated {gs.torque.rated_nm:g} N·m; catalogue ratcheting {cat} N·m")
    t0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    print(f"design scene {time.process_time() - t0:.1f} s CPU")
    rows = []
    with threadpool_limits(limits=1, user_api="blas"):
        inputs, zone, bearing, ring = _setup(gs, design)
        theta, phi = zone.first_rotation(float(gs.torque.rated_nm))
        step = 0.5 * (phi - theta)
        t0 = time.process_time()
        one = climb(zone, theta + step, step, max_torque_nm=20000.0)
        print(f"one-zone climb: {one.torque_nm:.1f} N·m ({one.criterion}), {time.process_time() - t0:.1f} s CPU")
        rows.append(("one-zone climb (today's estimate)", one.torque_nm, one.criterion))

        def two(label, **kw):
            t0 = time.process_time()
            model = TwoZoneClimb.from_design(inputs, zone, bearing=bearing, ring=ring, **kw)
            p = climb(model, theta + step, step, max_torque_nm=20000.0)
            print(f"\n{label}: {p.torque_nm:.1f} N·m ({p.criterion}), {time.process_time() - t0:.1f} s CPU")
            _path_table(model, p)
            rows.append((label + ", climb", p.torque_nm, p.criterion))
            if args.scan:
                out = _scan(model, p, label)
                rows.append((label + ", eccentric-mode check", out["torque_nm"], out["criterion"]))
            return p, model

        sym, sym_model = two("two-zone, e = 0 (free FS/WG, cam floating)")
        if args.fine:
            _fine(sym_model, sym, *args.fine)
        k_c = cup_lateral_stiffness_n_per_mm(gs)
        print(f"\ncup lateral stiffness (ESTIMATE, upper bound: rigid bottom) k_c = {k_c:.4g} N/mm")
        for e_um in args.ecc:
            load = k_c * e_um * 1e-3
            two(f"two-zone, e = {e_um:g} µm (P = k_c e = {load:.0f} N along the major axis)",
                external_force_n=(0.0, load))
        for load in args.loads:
            two(f"two-zone, radial load P = {load:g} N on the FS/WG", external_force_n=(0.0, load))
    print(f"\n--- {gs.name}: ratcheting torque against the catalogue's {cat} N·m")
    for label, t, crit in rows:
        ratio = "" if not cat else f"  ×{t / cat:.2f}"
        print(f"  {label:70s} {t:8.1f} N·m{ratio}  ({crit})")


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sets", nargs="*", type=Path, default=SETS)
    parser.add_argument("--ecc", type=lambda s: [float(x) for x in s.split(",") if x], default=[5.0, 10.0],
                        help="eccentricities (µm) applied as P = k_c e")
    parser.add_argument("--loads", type=lambda s: [float(x) for x in s.split(",") if x], default=[],
                        help="radial loads on the FS/WG assembly (N)")
    parser.add_argument("--no-scan", dest="scan", action="store_false", help="skip the eccentric-mode check")
    parser.add_argument("--fine", type=lambda s: [float(x) for x in s.split(",")], default=None,
                        help="T0,STEP,N: the symmetric path from below T0 (N·m) in N steps of STEP (mrad)")
    args = parser.parse_args()
    for path in args.sets:
        run(path, args)


if __name__ == "__main__":
    main()
