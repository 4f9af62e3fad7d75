"""Contact solvers on gear-shaped problems: time per solve vs number of points, in one run.

    python tests/benchmarks/contact_solvers.py [--quick] [--max-lemke N]

For n = 50, 200, 800, 2000 contact points: the median time (over repeats) of Lemke
(the package's solver), the primal active-set QP (cross-check) and HiGHS on the naive
phase-1 LP of seed 000 Eqs. 15–17; the number of loaded points, pivots / iterations, the
agreement of the two complementarity solvers (max |ΔF| / max F, |Δφ| over the elastic
rotation), the complementarity residual of each, and what the naive LP returns (loaded
points, φ, its complementarity residual). Writes export/bench/contact_solvers.{csv,png}.

The problems: points evenly along an engagement zone s ∈ [0, 1]; S (mm/N) = 2e-7·exp(−|s_i − s_j|
/ 0.03) (positive correlation decaying along the flank, SPD) + 1e-7·(0.8…1.2) on the diagonal;
θ (rad) a parabola 4e-4·((s − 0.45)/0.5)² plus a 5 µrad ripple; r = 30 + 2 cos 3s mm;
T = 2e5 N·mm (200 N·m). Lemke above ``--max-lemke`` points is skipped (default: none).
"""

from __future__ import annotations

import argparse
import csv
import io
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from profilegen.contact import solve_lemke, solve_qp_active_set
from tests.oracles.naive_lp import solve_naive_lp
from profilegen.output.export import atomic_write

SIZES = (50, 200, 800, 2000)
SOLVERS = {"lemke": solve_lemke, "qp_active_set": solve_qp_active_set, "naive_lp_highs": solve_naive_lp}


def gear_problem(n: int, rng: np.random.Generator, torque_nmm: float = 2e5):
    s = np.linspace(0.0, 1.0, n)
    K = np.exp(-np.abs(s[:, None] - s[None, :]) / 0.03)
    S = 2e-7 * K + 1e-7 * np.diag(rng.uniform(0.8, 1.2, n))
    theta = 4e-4 * ((s - 0.45) / 0.5) ** 2 + 5e-6 * (1.0 + np.sin(40.0 * s + rng.uniform(0.0, 6.0)))
    r = 30.0 + 2.0 * np.cos(3.0 * s)
    return S, theta, r, torque_nmm


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    ap.add_argument("--max-lemke", type=int, default=10**9, help="skip Lemke above this many points")
    args = ap.parse_args()
    rows, keep = [], {}
    for n in SIZES:
        rng = np.random.default_rng(n)
        S, theta, r, T = gear_problem(n, rng)
        repeats = (3 if args.quick else 9) if n <= 800 else (1 if args.quick else 3)
        results = {}
        for name, solver in SOLVERS.items():
            if name == "lemke" and n > args.max_lemke:
                print(f"n={n:5d} {name:15s} skipped (--max-lemke {args.max_lemke})", flush=True)
                continue
            times = []
            for _ in range(repeats):
                t0 = time.perf_counter()
                res = solver(S, theta, r, T)
                times.append(time.perf_counter() - t0)
            results[name] = res
            rows.append({
                "n": n,
                "solver": name,
                "time_s": statistics.median(times),
                "repeats": repeats,
                "loaded": res.loaded_count,
                "iterations": res.iterations,
                "phi_rad": res.phi_rad,
                "max_force_n": res.max_force_n,
                "complementarity_residual": res.complementarity_residual,
                "equilibrium_residual": res.equilibrium_residual,
                "agreement_force": "",
                "agreement_phi": "",
            })
            print(f"n={n:5d} {name:15s} {rows[-1]['time_s'] * 1e3:10.2f} ms  loaded {res.loaded_count:5d}  "
                  f"it {res.iterations:5d}  φ {res.phi_rad:.6e} rad  max F {res.max_force_n:9.3f} N  "
                  f"compl {res.complementarity_residual:.2e}", flush=True)
        if "lemke" in results:
            a, b = results["lemke"], results["qp_active_set"]
            df = float(np.max(np.abs(a.force_n - b.force_n))) / a.max_force_n
            dphi = abs(a.phi_rad - b.phi_rad) / (a.phi_rad - a.diagnostics["theta_min_rad"] + a.diagnostics["tau_rad"])
            for row in rows[-3:]:
                row["agreement_force"], row["agreement_phi"] = df, dphi
            print(f"n={n:5d} lemke vs qp_active_set: max|ΔF|/max F = {df:.2e}, |Δφ|/elastic φ = {dphi:.2e}, "
                  f"same active set: {a.active_set == b.active_set}", flush=True)
        keep[n] = (results, theta)
    out = ROOT / "export" / "bench"
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    with atomic_write(out / "contact_solvers.csv") as f:
        f.write(buf.getvalue())
    _plot(rows, keep, out / "contact_solvers.png")
    print(f"wrote {out / 'contact_solvers.csv'} and {out / 'contact_solvers.png'}")


def _plot(rows, keep, path: Path) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 7.5), layout="constrained")
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(2, 1)
    for name in SOLVERS:
        pts = [(row["n"], row["time_s"]) for row in rows if row["solver"] == name]
        if pts:
            x, y = zip(*pts)
            ax1.loglog(x, y, "o-", label=name)
    ax1.set_xlabel("contact points n")
    ax1.set_ylabel("median time per solve (s)")
    ax1.set_title("gear-shaped SPD problems, T = 200 N·m", fontsize=9)
    ax1.legend(fontsize=8)
    n = 800 if 800 in keep else max(keep)
    results, _theta = keep[n]
    s = np.linspace(0.0, 1.0, n)
    for name, style in (("lemke", "-"), ("qp_active_set", "--"), ("naive_lp_highs", ":")):
        if name in results:
            res = results[name]
            ax2.plot(s, res.force_n, style, label=f"{name}: {res.loaded_count} loaded, φ = {res.phi_rad * 1e6:.2f} µrad, "
                     f"compl. {res.complementarity_residual:.1e}")
    ax2.set_yscale("symlog", linthresh=1.0)
    ax2.set_xlabel(f"position along the engagement zone (n = {n})")
    ax2.set_ylabel("contact force (N)")
    ax2.legend(fontsize=7)
    for ax in (ax1, ax2):
        ax.grid(True, lw=0.3, alpha=0.5)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=150)
    with atomic_write(path, "wb") as f:
        f.write(buf.getvalue())


if __name__ == "__main__":
    main()
