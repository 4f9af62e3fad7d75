"""Envelope speed against accuracy, traced vs brute force, in one run.

    python tests/benchmarks/envelope.py [--quick]

Writes export/bench/envelope.csv and export/bench/envelope.png. The reference is
the traced, classified envelope of the default set at a chord tolerance of 1e-9
mm. For each method and resolution: the median time of repeated runs and the
error of the CS space boundary against the reference (the largest distance of a
reference vertex to the method's boundary — which includes the chord sag — and of
the method's vertices to the reference). The brute-force method is the union of
the tooth placed at n_phi positions (``profilegen.profile.swept``), whose boundary error
falls only as 1/n_phi (a sharp corner leaves notches); the speed ratio at equal
accuracy is measured where both methods reach the same error in this run, and
extrapolated to 1 nm along the brute force's fitted time and error laws.
"""

from __future__ import annotations

import argparse
import csv
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import shapely

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.profile.swept import swept_region  # noqa: E402


def median_time(fn, repeats: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def hausdorff(vertices: np.ndarray, geometry, reference: np.ndarray) -> float:
    """Symmetric distance between a method's boundary and the reference polyline: the
    reference vertices to the method's boundary geometry, and the method's boundary
    vertices (near this space) to the reference."""
    d1 = shapely.distance(shapely.points(reference), geometry).max()
    d2 = shapely.distance(shapely.points(vertices), shapely.LineString(reference)).max()
    return float(max(d1, d2))


def brute_boundary(region, reference: np.ndarray) -> np.ndarray:
    """The part of the brute-force region's boundary that bounds this CS space: the
    boundary vertices within the reference chain's angular and radial range."""
    rings = [region.exterior] if region.geom_type == "Polygon" else [g.exterior for g in region.geoms]
    pts = np.vstack([np.asarray(r.coords) for r in rings] + [np.asarray(i.coords) for g in ([region] if region.geom_type == "Polygon" else region.geoms) for i in g.interiors])
    th, r = np.arctan2(pts[:, 0], pts[:, 1]), np.hypot(pts[:, 0], pts[:, 1])
    th_ref, r_ref = np.arctan2(reference[:, 0], reference[:, 1]), np.hypot(reference[:, 0], reference[:, 1])
    keep = (th >= th_ref.min()) & (th <= th_ref.max()) & (r >= r_ref.min() + 1e-3)
    return pts[keep]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats and resolutions")
    args = ap.parse_args()
    repeats = 3 if args.quick else 11
    gs = pg.load_gearset(pg.default_gearset_path())
    tooth = pg.tooth_from_gearset(gs)
    g = gs.gear
    motion = pg.HarmonicDriveMotion(pg.ring_theory(gs.deflection_mm, g.waves), g.neutral_radius_mm, g.waves, g.circular_spline_teeth)
    kw = dict(cs_teeth=g.circular_spline_teeth, waves=g.waves)
    print("reference: traced envelope at chord 1e-9 mm ...", flush=True)
    t_ref, ref_env = median_time(lambda: pg.envelope_of(tooth, motion, chord_tol_mm=1e-9, **kw), 1)
    reference = ref_env.flank["boundary"]
    rows = []
    scenes = {s.chord_tol_mm: s.name for s in pg.SCENES.values()}
    tols = [1e-4, 1e-5, 1e-6, 1e-7] if not args.quick else [1e-4, 1e-6]
    for tol in tols:
        t, env = median_time(lambda: pg.envelope_of(tooth, motion, chord_tol_mm=tol, **kw), repeats)
        chain = env.flank["boundary"]
        err = hausdorff(chain, shapely.LineString(chain), reference)
        rows.append({"method": "traced", "resolution": tol, "time_s": t, "error_mm": err,
                     "points": int(len(env.flank["boundary"])), "scene": scenes.get(tol, "")})
        print(f"traced  chord {tol:7.0e} mm: {t * 1e3:8.2f} ms  error {err * 1e6:9.3f} nm  {scenes.get(tol, '')}", flush=True)
    n_list = [181, 361, 721, 1441, 2881, 5761] if not args.quick else [181, 721, 2881]
    for n in n_list:
        rep = max(1, repeats // 4) if n > 1000 else max(1, repeats // 2)
        t, region = median_time(lambda: swept_region(tooth, motion, n_phi=n, **kw), rep)
        err = hausdorff(brute_boundary(region, reference), region.boundary, reference)
        rows.append({"method": "brute force", "resolution": n, "time_s": t, "error_mm": err, "points": 0, "scene": ""})
        print(f"brute   n_phi {n:7d}   : {t * 1e3:8.1f} ms  error {err * 1e6:9.1f} nm", flush=True)
    out = ROOT / "export" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "envelope.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    traced = [r for r in rows if r["method"] == "traced"]
    brute = [r for r in rows if r["method"] == "brute force"]
    # brute-force laws: error = A n^-p, time = B n^q (least squares in log-log)
    ln = np.log([r["resolution"] for r in brute])
    p, lnA = np.polyfit(ln, np.log([r["error_mm"] for r in brute]), 1)
    q, lnB = np.polyfit(ln, np.log([r["time_s"] for r in brute]), 1)
    n_1nm = np.exp((np.log(1e-6) - lnA) / p)
    t_1nm = np.exp(lnB) * n_1nm**q
    design = next(r for r in traced if r["resolution"] == 1e-6)
    finest = brute[-1]
    match = min(traced, key=lambda r: abs(np.log(r["error_mm"] / finest["error_mm"])) if r["error_mm"] >= 0.5 * finest["error_mm"] else 1e9)
    print(f"design tier: {design['time_s'] * 1e3:.1f} ms median at {design['error_mm'] * 1e6:.3f} nm")
    print(f"brute force error ∝ n^{p:.2f}, time ∝ n^{q:.2f}; 1 nm needs n ≈ {n_1nm:.3g} positions ≈ {t_1nm:.3g} s (extrapolated)")
    print(f"ratio at equal accuracy, measured: brute {finest['time_s']:.3f} s at {finest['error_mm'] * 1e6:.0f} nm vs traced "
          f"{match['time_s'] * 1e3:.1f} ms at {match['error_mm'] * 1e6:.1f} nm → {finest['time_s'] / match['time_s']:.0f}×")
    print(f"ratio at 1 nm (brute extrapolated): {t_1nm / design['time_s']:.3g}×")
    _plot(rows, out / "envelope.png", (n_1nm, t_1nm))
    print(f"wrote {out / 'envelope.csv'} and {out / 'envelope.png'}")


def _plot(rows, path: Path, extrapolated) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.4))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    for method, style in (("traced", "o-"), ("brute force", "s--")):
        sel = [r for r in rows if r["method"] == method]
        ax.loglog([r["error_mm"] * 1e6 for r in sel], [r["time_s"] * 1e3 for r in sel], style, label=method)
        for r in sel:
            label = f"{r['resolution']:.0e} mm" if method == "traced" else f"n={r['resolution']}"
            if r.get("scene"):
                label += f" ({r['scene']})"
            ax.annotate(label, (r["error_mm"] * 1e6, r["time_s"] * 1e3), fontsize=7, xytext=(4, 3), textcoords="offset points")
    ax.loglog([1.0], [extrapolated[1] * 1e3], "x", color="C1", label="brute force at 1 nm (extrapolated)")
    ax.axvline(1.0, color="0.6", lw=0.8, ls=":")
    ax.set_xlabel("boundary error (nm)")
    ax.set_ylabel("time, median (ms)")
    ax.set_title("Classified envelope of the default set: time vs error")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    fig.tight_layout()
    fig.savefig(path, dpi=150)


if __name__ == "__main__":
    main()
