"""Loaded transmission error over a tooth passage: the numbers and the time of 16 positions.

    python tests/benchmarks/transmission_error.py [profiles/seed000_csf40.toml ...] [--repeats 3]

For each gear set (default: the default set and seed000_csf40; design scene, no contact or
stress in the design run): profilegen.contact.transmission.transmission_error at the rated
torque, 16 wave-generator positions over one tooth passage (ψ in [0, 2π/z2)), the balls
held against the major axis — the error (loaded rotation minus its mean, arcsec) against ψ,
its peak-to-peak, the no-load error (first contact), the secant mesh stiffness and its
ripple, teeth in contact; then the same with the balls rolling (cage), over one ball
passage with the balls rolling (33 positions), the candidate-ball window at ψ = 0 (the
rim's contact angle, +7.5°, 80°: rotation, and how far the bore moves into the balls the
window leaves out), and at the peak torque. Times: the 16
positions in this process (workers=1) and in a pool of 2 (fork), ``--repeats`` each,
medians of wall time and of CPU (this process + its reaped children), with the load
average before each run (the machine is shared).
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

resource.setrlimit(resource.RLIMIT_AS, (6_000_000_000, 6_000_000_000))

import numpy as np  # noqa: E402

import profilegen as pg  # noqa: E402
from profilegen.contact import ContactInput  # noqa: E402
from profilegen.contact.chain import BallBearing  # noqa: E402
from profilegen.contact.transmission import transmission_error  # noqa: E402

SETS = [Path(pg.default_gearset_path()), ROOT / "profiles" / "seed000_csf40.toml"]


def _cpu() -> float:
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def _timed(fn):
    w, c = time.perf_counter(), _cpu()
    out = fn()
    return out, time.perf_counter() - w, _cpu() - c


def _table(te) -> None:
    k = te.stiffness_nm_per_rad
    print(f"{'ψ (deg)':>9} {'error″':>8} {'no-load″':>9} {'k (N·m/rad)':>12} {'teeth':>5} {'F_max (N)':>9} {'balls':>5}")
    for row in zip(te.psi_deg, te.error_arcsec, te.no_load_error_arcsec, k, te.teeth_in_contact, te.max_tooth_force_n,
                   te.active_balls, te.flags):
        p, e, e0, kk, n, f, b, flag = row
        print(f"{p:9.4f} {e:8.4f} {e0:9.4f} {kk:12.5g} {n:5d} {f:9.1f} {b:5d}" + (f"  FLAG {flag}" if flag else ""))


def _summary(label: str, te) -> None:
    d = te.to_dict()
    print(f"{label}: TE peak-to-peak {te.peak_to_peak_arcsec:.4f} arcsec (no load {d['no_load_peak_to_peak_arcsec']:.4f}),"
          f" mean rotation {d['mean_rotation_arcsec']:.2f} arcsec, stiffness {te.stiffness_nm_per_rad.min():.5g} … "
          f"{te.stiffness_nm_per_rad.max():.5g} N·m/rad, ripple {te.stiffness_ripple:.6f} "
          f"({(te.stiffness_ripple - 1) * 100:.3f} %), teeth in contact {te.teeth_in_contact.min()}–"
          f"{te.teeth_in_contact.max()}, max equilibrium residual {te.equilibrium_residual.max():.1e}")


def _window_study(inputs, torque: float) -> None:
    """ψ = 0: the candidate-ball window (the compliance model's wrap angle) against the
    rotation, and how far the bore moves into the balls the window leaves out."""
    from profilegen.contact import contact_points
    from profilegen.contact.analysis import solve_contact
    from profilegen.contact.compliance import ContactCompliance

    pts = contact_points(inputs)
    base = inputs.rim_contact_angle_rad
    if base is None:
        print("window study skipped: no rim FEM contact angle")
        return
    wide = None
    for wrap in (base, base + np.radians(7.5), np.radians(80.0)):
        comp = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                       wrap_half_angle_rad=float(wrap))
        case = solve_contact(inputs, [torque], points=pts, compliance=comp).cases[0]
        on = np.round(np.degrees(case.ball_angle_rad[case.ball_active]), 1).tolist()
        print(f"  window ±{np.degrees(wrap):.2f}°: rotation {case.rotation_rad * 206264.806:.2f} arcsec, active balls "
              f"at {on}°")
        if wide is None:
            first = case
        wide = comp
    # the first window's solution on the widest window's balls: the bore's radial motion at each
    act = np.isin(np.round(wide.ball_angle_rad, 9), np.round(first.ball_angle_rad[first.ball_active], 9))
    gaps = wide.with_balls(act).ball_gaps_mm(first.solution.force_n) * 1e3
    print("  with the first window, the bore's radial displacement at every ball within ±80° (µm, < 0 inward): "
          + ", ".join(f"{a:.1f}°: {g:.1f}" for a, g in zip(np.degrees(wide.ball_angle_rad), gaps)))


def run(path: Path, repeats: int) -> None:
    gs = pg.load_gearset(path)
    g = gs.gear
    print(f"\n=== {gs.name} ({path.name}): z1 {g.flexspline_teeth}, z2 {g.circular_spline_teeth}, rated "
          f"{gs.torque.rated_nm:g} N·m, peak {gs.torque.peak_nm:g} N·m; one tooth passage = "
          f"{360.0 / g.circular_spline_teeth:.4f}° of ψ")
    design, w, c = _timed(lambda: pg.design(gs, scene="design", contact=False, stress=False))
    print(f"design scene: {w:.2f} s wall, {c:.2f} s CPU")
    inputs = ContactInput.from_design(design)
    rated = gs.torque.rated_nm
    times = {}
    for workers in (1, 2):
        wall, cpu = [], []
        for _ in range(repeats):
            print(f"  load average {os.getloadavg()[0]:.2f}", end="", flush=True)
            te, w, c = _timed(lambda: transmission_error(inputs, rated, positions=16, workers=workers))
            print(f" → workers={workers}: {w:.2f} s wall, {c:.2f} s CPU")
            wall.append(w)
            cpu.append(c)
        times[workers] = (statistics.median(wall), statistics.median(cpu))
    for workers, (w, c) in times.items():
        print(f"16 positions, workers={workers}: median {w:.2f} s wall, {c:.2f} s CPU (of {repeats})")
    _table(te)
    _summary(f"rated {rated:g} N·m, balls held", te)
    cage = transmission_error(inputs, rated, positions=16, options={"ball_motion": "cage"})
    _summary(f"rated {rated:g} N·m, balls rolling (cage), one tooth passage", cage)
    bearing = BallBearing.from_gearset(gs)
    period = 360.0 / bearing.ball_count / (0.5 * (1.0 + bearing.ball_diameter_mm / bearing.pitch_diameter_mm))
    balls = transmission_error(inputs, rated, positions=33, options={"span": period, "ball_motion": "cage"})
    _summary(f"rated {rated:g} N·m, balls rolling (cage), one ball passage ψ = 0 … {period:.3f}° (33 positions)",
             balls)
    print(f"  error over the ball passage (arcsec): {np.array2string(balls.error_arcsec, precision=3)}")
    print(f"  active balls: {balls.active_balls.tolist()}")
    _window_study(inputs, rated)
    peak = transmission_error(inputs, gs.torque.peak_nm, positions=16)
    _summary(f"peak {gs.torque.peak_nm:g} N·m, balls held", peak)
    if te.warnings:
        print("warnings:", "; ".join(te.warnings))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sets", nargs="*", type=Path, default=SETS)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    np.set_printoptions(precision=4, suppress=True)
    for path in args.sets:
        run(path, args.repeats)


if __name__ == "__main__":
    main()
