"""Seed 001's parametric study of the flexspline tooth ring, and the stress models' speed.

    python tests/benchmarks/stress_ring.py

Writes export/bench/stress_ring.csv (long format: series, torque, swept ratio, σ_total) and
export/bench/stress_ring.png (σ_total against δ/r_m, r1/m and ν at each of seed 001's
torques, like its figures), for seed 001's SHF-25 tooth ring with the unstated inputs of
:func:`profilegen.stress.tooth_ring.seed001_case`. Prints the optima, the comparison with the
seed's numbers, which of its claimed trends the model produces, and the time of one
evaluation of each stress model (medians of repeated runs): the tooth ring for one design,
the whole study, and the diaphragm + Goodman check of a size-40 sample (estimated geometry).
"""

from __future__ import annotations

import csv
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from profilegen.output.export import atomic_write  # noqa: E402
from profilegen.output.plot import plot_tooth_ring_study  # noqa: E402
from profilegen.stress import diaphragm as dg  # noqa: E402
from profilegen.stress import tooth_ring as tr  # noqa: E402

TORQUES_NM = [0.0, *tr.SEED001_TORQUES_NM.values()]
#: Size-40 cup (seed 000's CSF40-100; the maker's dimensions are not published): ESTIMATES,
#: with the limits of profiles/seed000_csf40.toml.
DIAPHRAGM_SAMPLE = dict(cup_radius_mm=48.7, boss_radius_mm=24.0, diaphragm_thickness_mm=2.2, cup_length_mm=58.0,
                        deflection_mm=0.5, youngs_modulus_mpa=206000.0, poisson_ratio=0.3, torque_nmm=265e3,
                        shear_endurance_limit_mpa=285.0, ultimate_strength_mpa=1100.0)


def _median_time(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def _rows(study: tr.ToothRingStudy) -> list[dict]:
    rows = []
    series = (("thickness", "delta_over_r_m", study.thickness_ratios, study.stress_vs_thickness_mpa),
              ("fillet", "r1_over_m", study.fillet_ratios, study.stress_vs_fillet_mpa),
              ("slot", "nu", study.slot_ratios, study.stress_vs_slot_mpa))
    for name, x_name, xs, ys in series:
        for k, torque in enumerate(study.torques_nm):
            for x, y in zip(xs, ys[k]):
                rows.append({"series": name, "torque_nm": float(torque), "x_name": x_name, "x": float(x),
                             "total_stress_mpa": float(y)})
    return rows


def main() -> None:
    case = tr.seed001_case()
    study = tr.tooth_ring_study(case, TORQUES_NM)
    out = ROOT / "export" / "bench"
    rows = _rows(study)
    with atomic_write(out / "stress_ring.csv") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    axes = plot_tooth_ring_study(study)
    fig = axes[0].figure
    fig.suptitle("seed 001 SHF-25 tooth ring: σ_total = σ_ass + σ_load (unstated inputs: see seed001_case)")
    with atomic_write(out / "stress_ring.png", "wb") as f:
        fig.savefig(f, format="png", dpi=130)

    print("torque  opt δ/r_m   σ_min   r1*/m(base δ)  r1*/m(opt δ)  opt ν")
    for k, torque in enumerate(study.torques_nm):
        print(f"{torque:6.0f}  {100 * study.optimal_thickness_ratio[k]:6.3f} %"
              f"  {study.optimal_thickness_stress_mpa[k]:6.1f}"
              f"  {study.optimal_fillet_ratio[k]:8.3f}  {study.optimal_fillet_ratio_at_optimal_thickness[k]:12.3f}"
              f"  {study.optimal_slot_ratio[k]:6.2f}{'' if study.optimal_slot_interior[k] else ' (edge)'}")
    print("\nseed 001 vs model:")
    for row in tr.seed001_comparison(case):
        print(f"  {row.quantity}: seed {row.seed_value:g}, ours {row.our_value:.4g} {row.unit}  [{row.note}]")
    print("\nclaimed trends:")
    for check in tr.seed001_trend_checks(case):
        print(f"  {'holds' if check.holds else 'DOES NOT FOLLOW'}: {check.claim} — {check.evidence}")

    inputs = tr.case_inputs(case, 67.0)
    t_ring = _median_time(lambda: tr.tooth_ring_stress(**inputs), 200)
    t_study = _median_time(lambda: tr.tooth_ring_study(case, TORQUES_NM), 5)
    t_dia = _median_time(lambda: dg.diaphragm_stress(**DIAPHRAGM_SAMPLE), 200)
    dia = dg.diaphragm_stress(**DIAPHRAGM_SAMPLE)
    print(f"\ndiaphragm sample (size-40 estimate, 265 N·m): u_a = {dia.edge_axial_amplitude_mm:.4f} mm, "
          f"τ_a = {dia.shear_amplitude_mpa:.2f} MPa at r = {dia.evaluation_radius_mm:g} mm "
          f"(max {dia.max_shear_amplitude_mpa:.2f} at {dia.max_shear_amplitude_radius_mm:.1f} mm), "
          f"τ_m = {dia.mean_shear_mpa:.2f} MPa, "
          f"σ_r amplitude at the boss {dia.corner_radial_stress_amplitude_mpa:.1f} MPa, "
          f"Goodman n = {dia.safety_factor:.2f}")
    print(f"time (median): tooth ring one design {t_ring * 1e3:.3f} ms, study ({len(TORQUES_NM)} torques, "
          f"{study.slot_ratios.size}×{study.thickness_ratios.size} (ν, δ) grid) {t_study * 1e3:.1f} ms, "
          f"diaphragm + Goodman {t_dia * 1e3:.3f} ms")
    print(f"wrote {out / 'stress_ring.csv'} and {out / 'stress_ring.png'}")


if __name__ == "__main__":
    main()
