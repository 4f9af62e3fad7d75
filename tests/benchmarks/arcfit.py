"""Arc–line–arc fit of the default set's CS flank: error and time per method, in one run.

    python tests/benchmarks/arcfit.py [--quick]

Writes export/bench/arcfit.csv and export/bench/arcfit.png. For each method: the
median fit time over repeats, the max and RMS normal deviation from the exact
envelope (chord 1 nm), the one-sided fit's max backlash; for the minimax fit the
spread of its max error over many starts (is it the best arc–line–arc?) and the LP
certificate (how much a linearised step could still lower the max error). The
one-sided profile is then checked against the FS tooth family at 2001 positions.
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
from profilegen.profile.arcfit import fit_profile  # noqa: E402
from profilegen.profile.envelope import swept_depth, tooth_curves  # noqa: E402
from profilegen.profile.gearform import clearance_map, cs_chain  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    repeats = 3 if args.quick else 11
    gs = pg.load_gearset(pg.default_gearset_path())
    result = pg.design(gs, scene="design")
    env, form, tooth, motion = result.envelope, result.form, result.tooth, result.motion
    flank = form.working_flank["right"]
    _, _, shape = tooth_curves(tooth)

    def swept(points):
        return swept_depth(points, motion, shape, phi_range=env.phi_range, neighbour_angle=2 * np.pi / form.cs_teeth)[0]

    rows, fits = [], {}
    for method in ("least_squares", "minimax", "one_sided"):
        times = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            fit = fit_profile(flank, method=method, space_side="left")
            times.append(time.perf_counter() - t0)
        fits[method] = fit
        rows.append({
            "method": method,
            "time_s": statistics.median(times),
            "max_error_um": fit.max_error_mm * 1e3,
            "rms_error_um": fit.rms_error_mm * 1e3,
            "max_backlash_um": "" if fit.max_backlash_mm is None else fit.max_backlash_mm * 1e3,
            "lp_improvement": fit.diagnostics.get("lp_improvement", ""),
            "data_points": len(flank),
        })
        print(f"{method:14s} {rows[-1]['time_s'] * 1e3:8.1f} ms  max {rows[-1]['max_error_um']:.4f} µm  "
              f"RMS {rows[-1]['rms_error_um']:.4f} µm" + (f"  backlash {rows[-1]['max_backlash_um']:.4f} µm" if rows[-1]["max_backlash_um"] != "" else ""), flush=True)
    # is the minimax fit the best arc–line–arc? many more starts, spread of the max error
    many = fit_profile(flank, method="minimax", space_side="left", starts=40, seed=1)
    best = min(many.max_error_mm, fits["minimax"].max_error_mm)
    rel = fits["minimax"].max_error_mm / best - 1.0
    print(f"minimax with 40 starts: {many.max_error_mm * 1e3:.6f} µm; default fit is {rel * 100:.4f} % above the best found; "
          f"LP certificate {fits['minimax'].diagnostics.get('lp_improvement')}")
    # the one-sided profile against the FS tooth family
    space, outline = cs_chain(fits["one_sided"].chain, tip_radius_mm=form.tip_radius_mm, root_radius_mm=form.root_radius_mm, cs_teeth=form.cs_teeth)
    n_unit = len(space.elements) + 1
    local = pg.geometry.contour.Chain(outline.elements[-n_unit:] + outline.elements[: 2 * n_unit]).sample(1e-7)
    t0 = time.perf_counter()
    cmap = clearance_map(form, tooth, motion, phi_range=env.phi_range, samples=2001, cs_points=local)
    depth = swept(fits["one_sided"].chain.sample(1e-6))
    print(f"one-sided profile vs FS tooth at 2001 positions: min clearance {cmap.min_mm * 1e3:.5f} µm "
          f"({time.perf_counter() - t0:.2f} s); deepest point of the fitted flank in the swept region {depth.max() * 1e3:.5f} µm")
    out = ROOT / "export" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "arcfit.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    _plot(fits, cmap, out / "arcfit.png")
    print(f"wrote {out / 'arcfit.csv'} and {out / 'arcfit.png'}")


def _plot(fits, cmap, path: Path) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 6), layout="constrained")
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(2, 1)
    for name, fit in fits.items():
        ax1.plot(fit.arclength_mm, np.asarray(fit.error_mm) * 1e3, label=f"{name}: max {fit.max_error_mm * 1e3:.3f} µm, {fit.time_s * 1e3:.0f} ms")
    ax1.axhline(0, color="0.5", lw=0.6)
    ax1.set_xlabel("position along the CS flank from the tip circle (mm)")
    ax1.set_ylabel("deviation (µm)")
    ax1.legend(fontsize=8)
    ax2.plot(np.degrees(cmap.phi), cmap.clearance_mm * 1e3)
    ax2.set_xlabel("φ (deg)")
    ax2.set_ylabel("backlash, one-sided profile (µm)")
    ax2.set_ylim(-0.5, 10)
    for ax in (ax1, ax2):
        ax.grid(True, lw=0.3, alpha=0.5)
    fig.savefig(path, dpi=150)


if __name__ == "__main__":
    main()
