"""Cup-bottom plate (seed 002): Morley convergence against the consistent analytic model,
and the timings of the analytic models, in one run.

    python tests/benchmarks/stress_plate.py [--quick]

Writes export/bench/stress_plate.csv and export/bench/stress_plate.png. Plate and edge: seed
002's Table 1 (ellipse a = 31.035, b = 30.335 mm, r_m = 30.685, r0 = 15, t = 1, l = 18.411 mm,
zero-mean w(φ)). For each Morley mesh (radial divisions 4 … 128, near-square cells): median
solve time and the errors against the consistent model — max vertex deflection, strain
energy, max clamp stress σ_r(r0) (O(h²)), L² curvature (O(h)) — with the observed rates
between successive meshes. Then the analytic models (consistent, seed002): median time of one
full design (41 × 144 stress maps + refined maxima) and their max clamp stress against the
finest Morley solution, Richardson-extrapolated (the seed002 variant's error is the model
error, 19 %).
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from tests.oracles.morley import clamp_sigma_r_mpa, compare_with_field, richardson, solve_morley  # noqa: E402
from profilegen.stress.plate import (SEED002_TABLE1, cup_bottom_stress, edge_displacement_from_ellipse,  # noqa: E402
                                     solve_plate)

P = SEED002_TABLE1
PLATE = dict(boss_radius_mm=P["boss_radius_mm"], thickness_mm=P["thickness_mm"],
             youngs_modulus_mpa=P["youngs_modulus_mpa"], poisson_ratio=P["poisson_ratio"])
ERRORS = ("w_max", "energy", "clamp_sigma_r_max", "clamp_moment", "curvature_l2")


def _median_time(repeats: int, fn):
    times, result = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return result, statistics.median(times)


def _atomic_write(path: Path, write) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    edge = edge_displacement_from_ellipse(P["semi_major_mm"], P["semi_minor_mm"], mean_radius_mm=P["mean_radius_mm"],
                                          length_mm=P["length_mm"])
    field, _ = solve_plate(edge, **PLATE)
    levels = (4, 8, 16, 32, 64) if args.quick else (4, 8, 16, 32, 64, 128)
    rows, sols = [], []
    for nr in levels:
        repeats = 5 if nr <= 32 else (3 if nr <= 64 else 1)
        sol, t = _median_time(repeats, lambda nr=nr: solve_morley(edge, radial_divisions=nr, **PLATE))
        row = {"kind": "morley", "model": "morley", "radial_divisions": nr, "angular_divisions": sol.angular_divisions,
               "h_mm": sol.h_mm, "dofs": sol.dofs, "time_s": t, **compare_with_field(sol, field)}
        if rows:
            prev = rows[-1]
            for key in ERRORS:
                row[f"rate_{key}"] = math.log(abs(prev[key] / row[key])) / math.log(prev["h_mm"] / row["h_mm"])
        rows.append(row)
        sols.append(sol)
        print(f"Morley {nr:4d}×{sol.angular_divisions:<4d} h {sol.h_mm:6.3f} mm {sol.dofs:7d} dof {t * 1e3:9.1f} ms  "
              + "  ".join(f"{k} {row[k]:+.2e}" + (f" (rate {row['rate_' + k]:.2f})" if "rate_" + k in row else "")
                          for k in ERRORS), flush=True)

    coarse, fine = sols[-2], sols[-1]
    reference = richardson(coarse, fine, "max_clamp_sigma_r_mpa")
    for model in ("consistent", "seed002"):
        res, t = _median_time(21, lambda model=model: cup_bottom_stress(edge, model=model, torque_nmm=87e3, **PLATE))
        f = res.field
        sigma = clamp_sigma_r_mpa(f, P["boss_radius_mm"])
        rows.append({"kind": "analytic", "model": model, "time_s": t, "clamp_sigma_r_max": sigma / reference - 1.0,
                     "max_von_mises_mpa": res.max_von_mises_mpa, "max_clamp_sigma_r_mpa": sigma,
                     "morley_clamp_sigma_r_mpa": reference, "strain_energy_nmm": f.strain_energy_nmm()})
        print(f"analytic {model:10s} {t * 1e3:7.2f} ms  max |σ_r(r0)| {sigma:.3f} MPa vs Morley (Richardson "
              f"{coarse.radial_divisions}/{fine.radial_divisions}) {reference:.3f} MPa: "
              f"{100 * (sigma / reference - 1):+.4f} %"
              f"  von Mises max (87 N·m) {res.max_von_mises_mpa:.1f} MPa", flush=True)

    out = ROOT / "export" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    keys = list(dict.fromkeys(k for r in rows for k in r))

    def write_csv(path):
        with open(path, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=keys)
            w.writeheader()
            w.writerows(rows)

    _atomic_write(out / "stress_plate.csv", write_csv)
    _plot(rows, out)
    print(f"wrote {out / 'stress_plate.csv'} and {out / 'stress_plate.png'}")


def _plot(rows, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    mor = [r for r in rows if r["kind"] == "morley"]
    ana = [r for r in rows if r["kind"] == "analytic"]
    h = np.array([r["h_mm"] for r in mor])
    t = np.array([r["time_s"] for r in mor])
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.3), layout="constrained")
    labels = {"w_max": "max vertex w", "energy": "strain energy", "clamp_sigma_r_max": "max σ_r at clamp",
              "clamp_moment": "M_r along clamp (max)", "curvature_l2": "curvatures, L²"}
    for key, marker in zip(ERRORS, "osD^v"):
        e = np.abs([r[key] for r in mor])
        last = mor[-1].get(f"rate_{key}", float("nan"))
        axes[0].loglog(h, e, marker + "-", label=f"{labels[key]} (rate {last:.2f})")
        axes[1].loglog(t, e, marker + "-", label=labels[key])
    for p, style in ((2, "k--"), (1, "k:")):
        axes[0].loglog(h, 0.5 * np.abs(mor[0]["w_max" if p == 2 else "curvature_l2"]) * (h / h[0]) ** p, style, lw=0.7,
                       label=f"O(h{'²' if p == 2 else ''})")
    for r, marker in zip(ana, "*X"):
        axes[1].loglog([r["time_s"]], [max(abs(r["clamp_sigma_r_max"]), 1e-7)], marker, ms=11,
                       label=f"analytic {r['model']}: max σ_r(r0) vs Morley (Richardson) "
                             f"{100 * r['clamp_sigma_r_max']:+.4f} %")
    from matplotlib.ticker import NullFormatter

    axes[0].xaxis.set_minor_formatter(NullFormatter())
    axes[0].set_xlabel("h, longest mesh edge (mm)")
    axes[1].set_xlabel("median solve time (s)")
    for ax in axes:
        ax.set_ylabel("relative error vs consistent model")
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
        ax.legend(fontsize=7)
    fig.suptitle("Cup bottom (seed 002, Table 1): Morley plate vs the consistent analytic model")

    def write_png(path):
        fig.savefig(path, dpi=130, format="png")

    _atomic_write(out / "stress_plate.png", write_png)
    plt.close(fig)


if __name__ == "__main__":
    main()
