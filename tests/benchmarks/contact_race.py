"""Issue 5: the wave-generator bearing's outer race under the FS rim, and the torsional stiffness.

    python tests/benchmarks/contact_race.py

The default set, design scene, every wave-generator ball a one-sided support at its no-load gap
(the contact stage's model). For an outer race of
thickness 0 (the old model: balls on the bore), 1.5, 2.5 (the default ESTIMATE) and
3.5 mm, bonded to the bore, and — to bracket the joint — 1.5, 2.5 and 3.5 mm sliding
(joined radially only, frictionless), it prints the secant torsional stiffness
(N·m/rad) at 54, 265 and 660 N·m, the teeth in contact per zone, the active balls, the
solver's warnings and the first-torque time (contact points + FEM + one torque with the
ball settling; one run). The held-ball stiffness at the same torques is printed as a
bound. Catalogue, size 40, ratio >= 80 (:func:`profilegen.contact.catalogue.catalogue_row`,
CHA table 50.4): K1 = 13·10⁴ (0–54 N·m), K2 = 20·10⁴ N·m/rad (54–196 N·m), printed as the
bilinear secant at each torque (K2 continued past T2).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path


ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.contact.analysis import analyse_contact, solve_contact  # noqa: E402
from profilegen.contact.catalogue import catalogue_row  # noqa: E402

TORQUES_NM = [54.0, 265.0, 660.0]
CASES = [(0.0, "bonded"), (1.5, "bonded"), (2.5, "bonded"), (3.5, "bonded"),
         (1.5, "sliding"), (2.5, "sliding"), (3.5, "sliding")]


def _catalogue_secant(torque: float) -> float:
    c = catalogue_row(40, 100)
    if torque <= c["T1_nm"]:
        return c["K1_nm_per_rad"]
    rad = c["T1_nm"] / c["K1_nm_per_rad"] + (torque - c["T1_nm"]) / c["K2_nm_per_rad"]
    return torque / rad


def _short(warning: str) -> str:
    if "edge tooth" in warning:
        return "edge tooth@" + warning.split(" N·m")[0].removeprefix("at ")
    if "every candidate contact point" in warning:
        return "all points@" + warning.split(" N·m")[0].removeprefix("at ")
    return warning[:40]


def main() -> None:
    gs = pg.load_gearset(pg.default_gearset_path())
    design = pg.design(gs, scene="design")
    cat = [_catalogue_secant(t) for t in TORQUES_NM]
    print(f"catalogue secant K: {', '.join(f'{k / 1e4:.1f}' for k in cat)} ·10⁴ N·m/rad at "
          f"{', '.join(f'{t:g}' for t in TORQUES_NM)} N·m", flush=True)
    head = (f"{'race mm':>7s} {'joint':7s} | {'K one-sided (10⁴ N·m/rad)':22s} | {'teeth/zone':10s} | {'balls':8s} | "
            f"{'K held (10⁴)':16s} | {'first s':>7s} | warnings")
    print(head)
    print("-" * len(head))
    for race, joint in CASES:
        t0 = time.perf_counter()
        first = solve_contact(design, [TORQUES_NM[0]], race_thickness_mm=race, race_interface=joint)
        t_first = time.perf_counter() - t0
        points, compliance = first.points, first.compliance
        one_sided = solve_contact(design, TORQUES_NM, points=points, compliance=compliance)
        held = analyse_contact(points, compliance.matrix_mm_per_n, TORQUES_NM)
        k_one = " ".join(f"{k / 1e4:6.1f}" for k in one_sided.secant_stiffness_nm_per_rad)
        k_held = " ".join(f"{k / 1e4:5.1f}" for k in held.secant_stiffness_nm_per_rad)
        teeth = " ".join(f"{c.teeth_in_contact:2d}" for c in one_sided.cases)
        balls = " ".join(f"{int(c.ball_active.sum())}" for c in one_sided.cases)
        warn = sorted({_short(w) for w in one_sided.warnings})
        print(f"{race:7.1f} {joint:7s} | {k_one:22s} | {teeth:10s} | {balls:8s} | {k_held:16s} | {t_first:7.2f} | "
              f"{len(one_sided.warnings)}: {', '.join(warn) or '-'}", flush=True)
    print(f"{points.count} contact points on {points.teeth.size} teeth; candidate balls "
          f"{compliance.ball_angle_rad.size} (each with its image)")


if __name__ == "__main__":
    main()
