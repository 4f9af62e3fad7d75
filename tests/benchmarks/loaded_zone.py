"""The loaded zone at the rated torque (issue 16 item 6), and what a profile relief does.

    python tests/benchmarks/loaded_zone.py [profiles/seed000_csf40.toml ...]

For each gear set (default: the default set and seed000_csf40; design scene): the contact at
the rated torque (profilegen.contact.analysis.solve_contact, 5 stations, rigid balls, every
ball a one-sided support at its no-load gap), per FS tooth of one zone its force, force-weighted pressure angle α = asin(n·e_r),
contact position along the FS flank and its smallest no-load gap; the bands of loaded teeth;
then the same torque with reliefs (research.loadzone.ProfileRelief: an FS tip
relief, and a wave-generator flattening near the major axis) on the same compliance: largest
tooth force, teeth in contact, rotation and secant mesh stiffness. The no-load gaps are set
against the CS arc-line-arc fit's own deviation from the exact envelope at each contact's CS
foot, and the contact is solved once more with the gaps less that deviation (the exact
conjugate, to first order). Writes
export/bench/loaded_zone_<set>.png (force, pressure angle, no-load gap and contact position
against φ) and .csv.
"""

from __future__ import annotations

import dataclasses
import resource
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.contact.analysis import solve_contact  # noqa: E402
from research.loadzone import ProfileRelief, load_zone, relief_study  # noqa: E402
from profilegen.output.export import atomic_write  # noqa: E402

SETS = [Path(pg.default_gearset_path()), ROOT / "profiles" / "seed000_csf40.toml"]
RELIEFS = [ProfileRelief("tip", 0.002), ProfileRelief("tip", 0.005), ProfileRelief("tip", 0.02),
           ProfileRelief("tip", 0.005, start_mm=0.95),
           ProfileRelief("major_axis", 0.005, 8.0), ProfileRelief("major_axis", 0.01, 8.0),
           ProfileRelief("major_axis", 0.02, 10.0, "flat")]


def run(path: Path) -> None:
    gs = pg.load_gearset(path)
    rated = float(gs.torque.rated_nm)
    print(f"\n=== {gs.name} ({path.name}): rated {rated:g} N·m")
    t0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    print(f"design scene: {time.process_time() - t0:.2f} s CPU")
    t0 = time.process_time()
    res = solve_contact(design, [rated], stations=5)
    print(f"contact: {res.points.count} points, {time.process_time() - t0:.2f} s CPU")
    z1 = gs.gear.flexspline_teeth
    zone = load_zone(res.cases[0], res.points, teeth_total=z1)
    print(f"teeth in contact: {zone.teeth_in_contact} per zone, {zone.fraction_in_contact:.1%} of z1; largest tooth "
          f"force {zone.max_tooth_force_n:.1f} N; rotation {zone.rotation_rad * 3437.7467707849:.4f} arcmin; "
          f"secant mesh stiffness {zone.secant_stiffness_nm_per_rad:.4g} N·m/rad")
    for b in zone.bands:
        print(f"  band φ {b['phi_deg'][0]:6.1f} … {b['phi_deg'][1]:6.1f}°: {b['count']} teeth, "
              f"{b['force_share']:.1%} of the force, largest {b['max_force_n']:.1f} N, α {b['pressure_angle_deg']:.1f}°")
    print(f"{'tooth':>5} {'φ (°)':>6} {'F (N)':>7} {'α (°)':>6} {'t (mm)':>7} {'gap0 µm':>8}   (flank length "
          f"{zone.flank_length_mm:.4f} mm; t, α of the loaded points, else of the closest)")
    for k in range(zone.teeth.size):
        if zone.min_gap_mm[k] < 0.03 or zone.tooth_force_n[k] > 0:
            print(f"{zone.teeth[k]:5d} {zone.tooth_phi_deg[k]:6.1f} {zone.tooth_force_n[k]:7.1f} "
                  f"{zone.pressure_angle_deg[k]:6.1f} {zone.flank_t_mm[k]:7.3f} {zone.min_gap_mm[k] * 1e3:8.2f}")
    # the no-load gap against the CS fit's own deviation from the exact envelope at the contact's CS foot:
    # the one-sided arc-line-arc fit stands off the envelope by 0 … max_error_mm
    fit_dev = _fit_deviation(design, res.points)
    best = {}
    for k in range(res.points.count):
        i = int(res.points.tooth[k])
        if i not in best or res.points.gap_mm[k] < res.points.gap_mm[best[i]]:
            best[i] = k
    ks = np.array([best[i] for i in zone.teeth])
    print(f"\nno-load gap of each tooth's closest point against the CS fit's deviation from the envelope at its foot "
          f"(fit max error {design.profile.max_error_mm * 1e3:.3f} µm):")
    diff = res.points.gap_mm[ks] - fit_dev[ks]
    mid = (zone.tooth_phi_deg > 6.0) & (zone.tooth_phi_deg < 62.0)
    print(f"  φ 6…62°: |gap − fit deviation| ≤ {np.abs(diff[mid]).max() * 1e3:.3f} µm over {mid.sum()} teeth; "
          f"gap there {res.points.gap_mm[ks][mid].min() * 1e3:.2f} … {res.points.gap_mm[ks][mid].max() * 1e3:.2f} µm")
    exact = dataclasses.replace(res.points, gap_mm=np.maximum(res.points.gap_mm - fit_dev, 0.0))
    ex = solve_contact(design, [rated], points=exact, compliance=res.compliance)
    ez = load_zone(ex.cases[0], exact, teeth_total=z1)
    print(f"  the gaps less the fit's deviation (the exact envelope, to first order; same compliance): "
          f"{ez.teeth_in_contact} teeth ({ez.fraction_in_contact:.1%}), largest force {ez.max_tooth_force_n:.1f} N, "
          f"K mesh {ez.secant_stiffness_nm_per_rad:.4g} N·m/rad; bands "
          + "; ".join(f"{b['phi_deg'][0]:.1f}…{b['phi_deg'][1]:.1f}° {b['count']} teeth α {b['pressure_angle_deg']:.1f}°"
                      for b in ez.bands))
    t0 = time.process_time()
    study = relief_study(design, rated, RELIEFS, result=res)
    print(f"\nreliefs at {rated:g} N·m ({time.process_time() - t0:.2f} s CPU for {len(RELIEFS)}):")
    print(f"{'relief':42s} {'F max':>7} {'teeth':>5} {'rot′':>7} {'K mesh':>10}  bands (φ°, teeth, share, α°)")
    rows = [("none", zone)] + [(_label(r), z) for r, z in zip(study.reliefs, study.relieved)]
    for label, z in rows:
        bands = "; ".join(f"{b['phi_deg'][0]:.1f}…{b['phi_deg'][1]:.1f} {b['count']} {b['force_share']:.2f} "
                          f"{b['pressure_angle_deg']:.1f}" for b in z.bands)
        print(f"{label:42s} {z.max_tooth_force_n:7.1f} {z.teeth_in_contact:5d} {z.rotation_rad * 3437.7467707849:7.4f} "
              f"{z.secant_stiffness_nm_per_rad:10.4g}  {bands}" + (f"  FLAG {z.beyond_capacity}" if z.beyond_capacity
                                                                     else ""))
    for w in study.warnings:
        print("  warning:", w)
    _write(gs.name, zone, study, fit_dev[ks], ez)


def _fit_deviation(design, points) -> np.ndarray:
    """The CS flank fit's deviation from the envelope (ProfileFit.error_mm, mm) at the fit point
    nearest to each contact point's CS foot (turned back to space 0; both flanks)."""
    import math

    from profilegen.geometry.kinematics import turn

    ff = design.profile.flank_fit
    z2 = design.gearset.gear.circular_spline_teeth
    cloud = np.vstack([ff.points_mm, ff.points_mm * np.array([-1.0, 1.0])])
    err = np.concatenate([ff.error_mm, ff.error_mm])
    out = np.empty(points.count)
    for k in range(points.count):
        c = turn(points.cs_point_mm[k:k + 1], -2.0 * math.pi * int(points.tooth[k]) / z2)[0]
        out[k] = err[np.argmin(np.hypot(*(cloud - c).T))]
    return out


def _label(r: ProfileRelief) -> str:
    if r.kind == "tip":
        start = "0.8 L" if r.start_mm is None else f"{r.start_mm:g} mm"
        return f"tip {r.depth_mm * 1e3:g} µm from t = {start}"
    return f"major axis {r.depth_mm * 1e3:g} µm, ±{r.half_angle_deg:g}° {r.shape}"


def _write(name: str, zone, study, fit_dev, exact_zone) -> None:
    out = ROOT / "export" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    tip = study.relieved[1]
    lines = ["tooth,phi_deg,force_n,pressure_angle_deg,flank_t_mm,min_gap_mm,force_tip_relief_5um_n"]
    for k in range(zone.teeth.size):
        lines.append(f"{zone.teeth[k]},{zone.tooth_phi_deg[k]:.6g},{zone.tooth_force_n[k]:.6g},"
                     f"{zone.pressure_angle_deg[k]:.6g},{zone.flank_t_mm[k]:.6g},{zone.min_gap_mm[k]:.6g},"
                     f"{tip.tooth_force_n[k]:.6g}")
    with atomic_write(out / f"loaded_zone_{name}.csv") as fh:
        fh.write("\n".join(lines) + "\n")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    phi = zone.tooth_phi_deg
    fig, ax = plt.subplots(4, 1, figsize=(8, 10), sharex=True)
    ax[0].bar(phi - 0.35, zone.tooth_force_n, 0.7, label="no relief")
    ax[0].bar(phi + 0.35, tip.tooth_force_n, 0.7, label="FS tip relief 5 µm", alpha=0.7)
    ax[0].set_ylabel("tooth force (N)")
    ax[0].set_title(f"{name}: one zone at {zone.torque_nm:g} N·m")
    ax[0].legend(fontsize=8)
    on = zone.tooth_force_n > 0
    ax[1].plot(phi, zone.pressure_angle_deg, ".", color="0.6", label="closest point (unloaded)")
    ax[1].plot(phi[on], zone.pressure_angle_deg[on], "o", label="loaded (force-weighted)")
    ax[1].set_ylabel("pressure angle α (°)")
    ax[1].legend()
    ax[2].semilogy(phi, np.maximum(zone.min_gap_mm * 1e3, 1e-3), ".-", label="no-load gap")
    ax[2].semilogy(phi, np.maximum(fit_dev * 1e3, 1e-3), "x", label="CS fit's deviation from the envelope at the foot")
    ax[2].set_ylabel("smallest no-load gap (µm)")
    ax[2].legend(fontsize=8)
    ax[0].plot(exact_zone.tooth_phi_deg, exact_zone.tooth_force_n, "k.-", lw=0.8,
               label="gaps less the fit's deviation")
    ax[3].plot(phi, zone.flank_t_mm, ".", color="0.6")
    ax[3].plot(phi[on], zone.flank_t_mm[on], "o")
    ax[3].axhline(zone.flank_length_mm, ls=":", color="k")
    ax[3].set_ylabel("contact on FS flank t (mm)")
    ax[3].set_xlabel("φ from the major axis (°)")
    for a in ax:
        a.grid(alpha=0.3)
    fig.tight_layout()
    with atomic_write(out / f"loaded_zone_{name}.png", "wb") as fh:
        fig.savefig(fh, dpi=110, format="png")
    plt.close(fig)
    print(f"wrote export/bench/loaded_zone_{name}.png, .csv")


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    for path in [Path(a) for a in sys.argv[1:]] or SETS:
        run(path)


if __name__ == "__main__":
    main()
