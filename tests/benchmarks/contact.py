"""Loaded contact of the default set: time per torque and the torsional curve, in one run.

    python tests/benchmarks/contact.py

Writes export/bench/contact.csv and export/bench/contact.png. Times (medians): the first
torque — contact points, FEM influence coefficients, solve with seed 000's ball settling —
and each further torque with the coefficients reused (issue 5 targets: ≤ 3 s and ≤ 50 ms).
The torsional curve is computed twice: every wave-generator ball a one-sided support at its
no-load gap (the contact stage's model; no preload) and every ball within the wrap held
(bilateral, a bound); the Harmonic Drive catalogue's bilinear curve for a size-40 gear of
ratio >= 80 (:func:`profilegen.contact.catalogue.catalogue_row`, CHA table 50.4) is drawn next
to both.
"""

from __future__ import annotations

import csv
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.contact.analysis import ARCMIN_PER_RAD, analyse_contact, solve_contact  # noqa: E402
from profilegen.contact import ContactInput  # noqa: E402
from profilegen.contact.compliance import ContactCompliance  # noqa: E402
from profilegen.contact.catalogue import catalogue_row  # noqa: E402
from profilegen.contact.solvers import ContactError  # noqa: E402
from profilegen.output.plot import contact_figure  # noqa: E402

#: the comparison row: size 40, ratio >= 80 (the default set is ratio 100)
CATALOGUE = catalogue_row(40, 100)

TORQUES_NM = [5, 10, 20, 30, 54, 100, 150, 196, 265, 400, 660, 1200]


def main() -> None:
    gs = pg.load_gearset(pg.default_gearset_path())
    design = pg.design(gs, scene="design")
    firsts = []
    for _ in range(5):
        t0 = time.perf_counter()
        result = solve_contact(design, [gs.torque.rated_nm])
        firsts.append(time.perf_counter() - t0)
    points, compliance = result.points, result.compliance
    further = []
    for torque in TORQUES_NM:
        t0 = time.perf_counter()
        solve_contact(design, [torque], points=points, compliance=compliance)
        further.append(time.perf_counter() - t0)
    one_sided = solve_contact(design, TORQUES_NM, points=points, compliance=compliance)
    held = analyse_contact(points, compliance.matrix_mm_per_n, TORQUES_NM)
    print(f"{points.count} contact points on {points.teeth.size} teeth; compliance {compliance.dof}, "
          f"first torque {statistics.median(firsts):.2f} s (median of 5), further torque "
          f"{statistics.median(further) * 1e3:.1f} ms (median of {len(further)})")
    phi0 = float(points.theta_rad.min())
    rows = []
    for s, h in zip(one_sided.cases, held.cases):
        rows.append({
            "torque_nm": s.torque_nm,
            "rotation_arcmin_balls_one_sided": (s.rotation_rad - phi0) * ARCMIN_PER_RAD,
            "rotation_arcmin_balls_held": (h.rotation_rad - phi0) * ARCMIN_PER_RAD,
            "teeth_per_zone_one_sided": s.teeth_in_contact,
            "teeth_per_zone_held": h.teeth_in_contact,
            "max_tooth_force_n_one_sided": s.max_tooth_force_n,
            "max_tooth_force_n_held": h.max_tooth_force_n,
            "active_balls_one_sided": int(s.ball_active.sum()),
        })
        r = rows[-1]
        print(f"{s.torque_nm:7.0f} N·m  one-sided: {r['rotation_arcmin_balls_one_sided']:7.3f}' {s.teeth_in_contact:3d} teeth "
              f"{s.max_tooth_force_n:7.1f} N ({r['active_balls_one_sided']} balls)   held: "
              f"{r['rotation_arcmin_balls_held']:7.3f}' {h.teeth_in_contact:3d} teeth {h.max_tooth_force_n:7.1f} N")
    cat = CATALOGUE
    for label, res in (("one-sided", one_sided), ("held", held)):
        k = res.secant_stiffness_nm_per_rad
        t1 = int(np.argmin(np.abs(res.torques_nm - cat["T1_nm"])))
        print(f"secant stiffness, balls {label}: {k[t1]:.3g} N·m/rad at {res.torques_nm[t1]:g} N·m "
              f"(catalogue K1 {cat['K1_nm_per_rad']:.3g}), {k[-1]:.3g} N·m/rad at {res.torques_nm[-1]:g} N·m")
    out = ROOT / "export" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "contact.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    fig = contact_figure(one_sided, title="default set, every ball one-sided at its no-load gap; dotted: every ball held",
                         catalog=CATALOGUE, ratio=float(gs.ratio))
    ax = fig.axes[1]
    ax.plot(np.concatenate([[0.0], (held.rotations_rad - phi0) * ARCMIN_PER_RAD]),
            np.concatenate([[0.0], held.torques_nm]), "s:", ms=3, label="this model, every ball held")
    ax.legend(fontsize=7)
    fig.savefig(out / "contact.png", dpi=130)
    # discretisation: stations per tooth flank (each tooth keeps its true closest points)
    for stations in (5, 9, 13, 17):
        try:
            res = solve_contact(design, [54.0, 265.0, 660.0], stations=stations)
        except ContactError as exc:  # neighbouring stations' influence columns numerically dependent
            print(f"{stations:2d} stations/tooth: fails loudly — {exc}")
            continue
        print(f"{stations:2d} stations/tooth: {res.points.count:3d} points, K = "
              f"{np.array2string(res.secant_stiffness_nm_per_rad / 1e4, precision=1)}·10⁴ N·m/rad, teeth "
              f"{[c.teeth_in_contact for c in res.cases]}, max tooth force "
              f"{[round(c.max_tooth_force_n) for c in res.cases]} N at 54 / 265 / 660 N·m")
    # discretisation: the FEM meshes of the influence coefficients (default: 14 FS / 16 CS
    # columns per pitch, 4 tooth layers, 2 rim layers)
    pts = solve_contact(design, [54.0]).points
    for label, kw in (("default mesh", {}), ("24 columns per pitch", {"per_pitch": 24, "cs_per_pitch": 24}),
                      ("6 tooth layers", {"tooth_layers": 6, "cs_tooth_layers": 6}), ("3 rim layers", {"rim_layers": 3})):
        comp = ContactCompliance.build(ContactInput.from_design(design), pts.fs_point_mm, pts.normal, pts.tooth,
                                       pts.cs_point_mm, ball_supports="all", mesh=kw)
        res = solve_contact(design, [54.0, 265.0, 660.0], points=pts, compliance=comp)
        print(f"{label:22s} dof {comp.dof}: K = {np.array2string(res.secant_stiffness_nm_per_rad / 1e4, precision=2)}·10⁴ "
              f"N·m/rad, max tooth force {[round(c.max_tooth_force_n, 1) for c in res.cases]} N at 54 / 265 / 660 N·m")
    print(f"wrote {out / 'contact.csv'} and {out / 'contact.png'}; first contact at φ0 = "
          f"{phi0 * ARCMIN_PER_RAD:.4f} arcmin; catalogue rotation at {TORQUES_NM[8]} N·m: "
          f"{_catalog_arcmin(TORQUES_NM[8]):.2f} arcmin")


def _catalog_arcmin(torque: float) -> float:
    c = CATALOGUE
    if torque <= c["T1_nm"]:
        rad = torque / c["K1_nm_per_rad"]
    else:
        rad = c["T1_nm"] / c["K1_nm_per_rad"] + (torque - c["T1_nm"]) / c["K2_nm_per_rad"]
    return rad * 180 * 60 / math.pi


if __name__ == "__main__":
    main()
