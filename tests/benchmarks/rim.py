"""Rim FEM tiers: error vs degrees of freedom vs time, against refined references, in one run.

    python tests/benchmarks/rim.py [--quick]

Writes export/bench/rim.csv and export/bench/rim.png. Default gear set, its wave-generator
contour (offset ellipse, perimeter = the bore's). Tiers and their mesh sequences:

* linear flat ring (small-strain), 2 and 4 layers × 16 … 128 divisions — the linear tier
  (the ``solve_ring`` call a user makes for speed) is 2 × 64;
* nonlinear flat ring (St Venant–Kirchhoff, total Lagrangian), same meshes — the ``design``
  tier is 4 × 64;
* nonlinear toothed rim, 2 + 2 layers, 14, 16, 20 element columns per pitch — ``verify`` is
  16 (14 is the fewest the default DCTA tooth takes).

Errors: max over 0 ≤ φ ≤ π/2 of |Δω| and |Δυ| on the neutral line, against the nonlinear
flat ring on 8 × 512 (the flat tiers; the linear tier's error is then mostly its
modelling error) and against the toothed rim at 24 columns per pitch with 2 + 4 layers
(the toothed tier; 20 in --quick). Times are medians of repeated solves (FEM solve only, no error estimate).
The targets of issue 3 are printed: design tier ≤ 0.3 s and within 0.1 µm of the
reference; linear tier ≤ 30 ms.
"""

from __future__ import annotations

import argparse
import csv
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.rim import solve_ring  # noqa: E402
from profilegen.rim.toothed import toothed_quarter_mesh  # noqa: E402
from profilegen.geometry.wavegen import from_gearset  # noqa: E402


def _timed(repeats, fn):
    times, res = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        res = fn()
        times.append(time.perf_counter() - t0)
    return res, statistics.median(times)


def _error(res, ref) -> tuple[float, float]:
    """Max |Δω|, |Δυ| at the tier's own nodes, the reference through a cubic spline of its
    (much denser) neutral-line nodes (linear interpolation would add ~h²ω″/8 ≈ 0.6 nm)."""
    from scipy.interpolate import CubicSpline

    d_w = np.max(np.abs(res.omega_mm - CubicSpline(ref.phi_rad, ref.omega_mm)(res.phi_rad)))
    d_u = np.max(np.abs(res.upsilon_mm - CubicSpline(ref.phi_rad, ref.upsilon_mm)(res.phi_rad)))
    return float(d_w), float(d_u)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats and a coarser reference")
    args = ap.parse_args()
    repeats = 3 if args.quick else 7
    gs = pg.load_gearset(pg.default_gearset_path())
    cam = from_gearset(gs)
    tooth = pg.tooth_from_gearset(gs)
    solve_ring(gs, contour=cam, divisions=8)  # imports and first-call set-up out of the timings

    print("references ...", flush=True)
    t0 = time.perf_counter()
    ref_flat = solve_ring(gs, contour=cam, layers=8, divisions=256 if args.quick else 512, geometry="nonlinear")
    print(f"  flat nonlinear 8 × {ref_flat.divisions}: {ref_flat.dof} dof, {time.perf_counter() - t0:.1f} s")

    def toothed(per_pitch, rim_layers=2, tooth_layers=2):
        mesh = toothed_quarter_mesh(tooth, gs.gear.rim_thickness_mm, rim_layers=rim_layers,
                                    tooth_layers=tooth_layers, per_pitch=per_pitch)
        return solve_ring(gs, contour=cam, mesh=mesh, geometry="nonlinear")

    t0 = time.perf_counter()
    ref_pitch = 20 if args.quick else 24
    ref_tooth = toothed(ref_pitch, 2, 4)
    print(f"  toothed nonlinear {ref_pitch}/pitch, 2 + 4 layers: {ref_tooth.dof} dof, {time.perf_counter() - t0:.1f} s")

    rows = []
    for geometry, layers in (("linear", 2), ("linear", 4), ("nonlinear", 4)):
        for divisions in (16, 32, 64, 128):
            res, t = _timed(repeats, lambda: solve_ring(gs, contour=cam, layers=layers, divisions=divisions,
                                                        geometry=geometry))
            e_w, e_u = _error(res, ref_flat)
            rows.append({"tier": f"{geometry} flat {layers} layers", "mesh": f"{layers}x{divisions}", "dof": res.dof, "time_s": t,
                         "err_omega_um": e_w * 1e3, "err_upsilon_um": e_u * 1e3, "reference": "flat nonlinear",
                         "default_of": "design" if (geometry, divisions) == ("nonlinear", 64) else ""})
            if (geometry, layers, divisions) == ("linear", 2, 64):
                rows[-1]["default_of"] = "linear"
            print(f"{geometry:9s} flat {layers}×{divisions:<4d} {res.dof:6d} dof {t * 1e3:8.1f} ms  "
                  f"ω {e_w * 1e3:9.4f} µm  υ {e_u * 1e3:9.4f} µm", flush=True)
    for per_pitch in (14, 16, 20) if not args.quick else (14, 16):
        res, t = _timed(max(1, repeats // 3), lambda: toothed(per_pitch))
        e_w, e_u = _error(res, ref_tooth)
        f_w, f_u = _error(res, ref_flat)
        rows.append({"tier": "nonlinear toothed", "mesh": f"{per_pitch}/pitch, 2+2 layers", "dof": res.dof,
                     "time_s": t, "err_omega_um": e_w * 1e3, "err_upsilon_um": e_u * 1e3,
                     "reference": "toothed nonlinear", "default_of": "verify" if per_pitch == 16 else "",
                     "teeth_effect_omega_um": f_w * 1e3, "teeth_effect_upsilon_um": f_u * 1e3})
        print(f"nonlinear toothed {per_pitch}/pitch {res.dof:6d} dof {t:8.2f} s  ω {e_w * 1e3:9.4f} µm  "
              f"υ {e_u * 1e3:9.4f} µm  (vs flat: ω {f_w * 1e3:.3f} µm, υ {f_u * 1e3:.3f} µm)", flush=True)

    out = ROOT / "export" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    keys = sorted({k for r in rows for k in r}, key=lambda k: list(rows[-1]).index(k) if k in rows[-1] else 99)
    with open(out / "rim.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    for tier, marker in (("linear flat 2 layers", "s"), ("linear flat 4 layers", "D"), ("nonlinear flat 4 layers", "o"),
                         ("nonlinear toothed", "^")):
        sel = [r for r in rows if r["tier"] == tier]
        err = [max(r["err_omega_um"], r["err_upsilon_um"]) for r in sel]
        axes[0].loglog([r["dof"] for r in sel], err, marker + "-", label=tier)
        axes[1].loglog([r["time_s"] for r in sel], err, marker + "-", label=tier)
        for r, e in zip(sel, err):
            if r["default_of"]:
                for ax, x in ((axes[0], r["dof"]), (axes[1], r["time_s"])):
                    ax.annotate(r["default_of"], (x, e), textcoords="offset points", xytext=(5, 5), fontsize=8)
    for ax in axes:
        ax.axhline(0.1, color="C3", lw=0.6, ls="--")
        ax.set_ylabel("max |Δω|, |Δυ| vs reference (µm)")
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
    axes[0].set_xlabel("degrees of freedom")
    axes[1].set_xlabel("median FEM solve time (s)")
    axes[1].axvline(0.3, color="C3", lw=0.6, ls=":")
    axes[0].legend(fontsize=8)
    fig.suptitle(f"Rim FEM tiers, default set (reference: flat nonlinear 8×{ref_flat.divisions} / toothed {ref_pitch} per pitch)")
    fig.savefig(out / "rim.png", dpi=130)

    design = next(r for r in rows if r["default_of"] == "design")
    linear = next(r for r in rows if r["default_of"] == "linear")
    d_err = max(design["err_omega_um"], design["err_upsilon_um"])
    print(f"design tier: {design['time_s'] * 1e3:.1f} ms (target ≤ 300), {d_err:.4f} µm from the reference (target ≤ 0.1)")
    print(f"linear tier: {linear['time_s'] * 1e3:.1f} ms (target ≤ 30)")
    print(f"wrote {out / 'rim.csv'} and {out / 'rim.png'}")


if __name__ == "__main__":
    main()
