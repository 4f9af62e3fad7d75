"""Stability maps: where each method fails, and whether the failure is reported.

    python tests/benchmarks/stability.py [--quick] [--only envelope,fitter,contact,rim,plate]

For each family a grid over the parameters that break it; at every grid point the outcome
is one of: a plain answer ("ok"), an answer with a warning or flag ("flagged"), a named
error (its class, and the stage or solver that raised it), or an answer that is wrong
and not flagged ("UNDETECTED", checked here against physics or an independent solver).
Writes export/bench/stability_<map>.csv and .png for each map, and
export/bench/stability_summary.json; prints a summary.

* envelope — the sketch scene (ring theory, chord 1e-4 mm, ``pg.design(..., contact=False,
  stress=False)``) over ω* (wave_generator.deflection_coefficient) × the DCTA pressure
  angle: folds, no-root length on the flank, deepest false flank, ridges, grid refinements
  of the root trace (two root curves bridged by a coarse grid), and which stage raised
  which named error.
* fitter — integer-harmonic Fourier fit (``series.fit_fourier``) and seed 004's general
  sine series (``series.fit_sine_series``) on synthetic ω, υ with known truth (ring theory
  w0 = 0.5 mm + harmonics 4…10 φ decaying from 2 µm, 360 samples on [0, 2π), Gaussian noise
  σ): max error against the truth over [0, 2π], the order each criterion picks, the sine
  series' periodicity defect; and the input domain (samples × order) where each raises
  SeriesError.
* contact — the naive phase-1 LP of seed 000 (``solve_naive_lp``) against Lemke and the
  active-set QP on random SPD problems of growing size n and condition number κ (random
  orthogonal eigenvectors, eigenvalues log-spaced over κ; θ uniform in [0, 1 mrad]; the
  torque set by a load ratio τ/θ_span log-uniform in [1e-2, 1e2]): fraction of naive-LP
  answers that are not the contact solution, that put the torque on one point, and that
  are wrong *without* a warning; Lemke–QP agreement; where the input check refuses S.
* rim — the contact (wrap) angle of the ring FEM against µm changes of the cam (its minor
  semi-axis), linear and nonlinear, three meshes, next to the change of ω; the contact
  iteration with a capped number of re-linearisations / Newton steps.
* plate — the cup bottom's seed002 variant against the consistent Kirchhoff model over the
  boss ratio r0/r_m × ν (clamp stress, strain energy, the natural condition M_r(r_m) = 0),
  and the Morley FE verdict (``morley.model_verdict``) along r0/r_m at ν = 0.3.

The full run takes ~5.5 min on the 2-core machine (one BLAS thread); --quick ~35 s.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import logging
import math
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

# one BLAS thread: the problems are small, and on the shared 2-core machine a threaded BLAS
# oversubscribed by another job slowed the contact map 13× (set the variables to override)
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.errors import ConvergenceError, ProfilegenError  # noqa: E402
from profilegen.output.export import atomic_write  # noqa: E402

OUT = ROOT / "export" / "bench"
FAMILIES = ("envelope", "fitter", "contact", "rim", "plate")

# one colour per outcome, the same in every categorical map
OUTCOME_COLOURS = {
    "ok": "#d9f0d3",
    "flagged": "#fee08b",
    "ToothError": "#b2abd2",
    "GearSetError": "#8073ac",
    "EnvelopeError": "#f4a582",
    "ConvergenceError": "#d6604d",
    "OneSidedError": "#92c5de",
    "FitError": "#4393c3",
    "SeriesError": "#f4a582",
    "ContactError": "#b2abd2",
    "RingError": "#b2abd2",
    "StressError": "#b2abd2",
    "CRASH": "#762a83",
    "UNDETECTED": "#000000",
}


# ----------------------------------------------------------------------------- output helpers


def write_csv(name: str, rows: list[dict]) -> Path:
    path = OUT / f"stability_{name}.csv"
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=keys, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: _csv_value(r.get(k)) for k in keys})
    with atomic_write(path) as f:
        f.write(buf.getvalue())
    return path


def _csv_value(v):
    if isinstance(v, float):
        return "" if not math.isfinite(v) else f"{v:.9g}"
    return "" if v is None else v


def save_figure(fig, name: str) -> Path:
    path = OUT / f"stability_{name}.png"
    with atomic_write(path, "wb") as f:
        fig.savefig(f, format="png", dpi=100)
    import matplotlib.pyplot as plt

    plt.close(fig)
    return path


def edges(values) -> np.ndarray:
    """Cell edges for pcolormesh around (possibly uneven) centres."""
    v = np.asarray(values, float)
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


def log_edges(values) -> np.ndarray:
    return 10.0 ** edges(np.log10(values))


def categorical_map(ax, xe, ye, labels: np.ndarray, *, legend=True, annotate=None, ncol=4):
    """Colour each cell by its outcome label (OUTCOME_COLOURS); labels[j, i] at (x_i, y_j). The legend
    goes under the axes."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    present = [k for k in OUTCOME_COLOURS if np.any(labels == k)]
    present += sorted({str(v) for v in labels.ravel()} - set(present))
    code = {k: i for i, k in enumerate(present)}
    z = np.vectorize(code.get)(labels).astype(float)
    cmap = ListedColormap([OUTCOME_COLOURS.get(k, "#999999") for k in present])
    ax.pcolormesh(xe, ye, z, cmap=cmap, vmin=-0.5, vmax=len(present) - 0.5, edgecolors="white", linewidth=0.3)
    if annotate is not None:
        xc, yc = 0.5 * (xe[1:] + xe[:-1]), 0.5 * (ye[1:] + ye[:-1])
        for j in range(labels.shape[0]):
            for i in range(labels.shape[1]):
                if annotate[j][i]:
                    ax.text(xc[i], yc[j], annotate[j][i], ha="center", va="center", fontsize=6.5,
                            color="white" if labels[j, i] == "UNDETECTED" else "black")
    if legend:
        ax.legend(handles=[Patch(facecolor=OUTCOME_COLOURS.get(k, "#999999"), edgecolor="grey", label=k) for k in present],
                  loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=min(ncol, len(present)), fontsize=7.5,
                  frameon=False)


def hatch_cells(ax, xe, ye, mask, label="no value (failed)"):
    """Hatch the cells where mask[j, i] (no value to show); one legend entry."""
    from matplotlib.patches import Rectangle

    first = True
    for j, i in zip(*np.nonzero(mask)):
        ax.add_patch(Rectangle((xe[i], ye[j]), xe[i + 1] - xe[i], ye[j + 1] - ye[j], facecolor="#eeeeee",
                               edgecolor="#888888", hatch="///", lw=0, label=label if first else None))
        first = False
    if not first:
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), fontsize=7.5, frameon=False)


def value_map(fig, ax, xe, ye, z, *, label: str, cmap="viridis", log=False, failed=None, vmin=None, vmax=None,
              integer=False, failed_label="no value (failed)"):
    """A colour map of z; cells in ``failed`` hatched. ``integer``: a discrete colour per count."""
    from matplotlib.colors import BoundaryNorm, LogNorm
    import matplotlib.pyplot as plt

    z = np.asarray(z, float)
    if failed is not None:
        z = np.where(failed, np.nan, z)
    if log:
        pos = z[np.isfinite(z) & (z > 0)]
        lo = vmin if vmin is not None else (pos.min() if pos.size else 1e-12)
        hi = vmax if vmax is not None else (pos.max() if pos.size else 1.0)
        zz = np.ma.masked_where(~(np.isfinite(z) & (z > 0)), z)
        m = ax.pcolormesh(xe, ye, zz, cmap=cmap, norm=LogNorm(lo, max(hi, lo * 10)))
        cb = fig.colorbar(m, ax=ax, label=label, fraction=0.046, pad=0.03)
    elif integer:
        top = int(np.nanmax(z)) if np.any(np.isfinite(z)) else 1
        top = max(top, 1)
        bounds = np.arange(-0.5, top + 1.5)
        m = ax.pcolormesh(xe, ye, np.ma.masked_invalid(z), cmap=plt.get_cmap(cmap, len(bounds) - 1),
                          norm=BoundaryNorm(bounds, len(bounds) - 1))
        cb = fig.colorbar(m, ax=ax, label=label, fraction=0.046, pad=0.03, ticks=np.arange(0, top + 1))
    else:
        m = ax.pcolormesh(xe, ye, np.ma.masked_invalid(z), cmap=cmap, vmin=vmin, vmax=vmax)
        cb = fig.colorbar(m, ax=ax, label=label, fraction=0.046, pad=0.03)
    if failed is not None and np.any(failed):
        hatch_cells(ax, xe, ye, failed, failed_label)
    return cb


def error_name(exc: BaseException) -> str:
    return type(exc).__name__


def _where(exc: BaseException) -> str:
    """file:line of the innermost frame of an exception (for crashes: a non-named error)."""
    import traceback

    frames = traceback.extract_tb(exc.__traceback__)
    return f"{Path(frames[-1].filename).name}:{frames[-1].lineno} ({frames[-1].name})" if frames else "?"


# ----------------------------------------------------------------------------- (a) envelope


class _BridgeCounter(logging.Handler):
    """Counts the root-trace refinements (the envelope logs one per bridged grid)."""

    def __init__(self):
        super().__init__(logging.INFO)
        self.count = 0

    def emit(self, record):
        if "bridged" in record.getMessage():
            self.count += 1


def envelope_point(base, omega_star: float, pressure_deg: float, counter: _BridgeCounter) -> dict:
    from profilegen.profile.envelope import envelope_of

    row = {"omega_star": omega_star, "pressure_angle_deg": pressure_deg}
    stage = ["gearset"]
    counter.count = 0
    t0 = time.perf_counter()
    env = design = None
    try:
        gs = base.with_values({"wave_generator.deflection_coefficient": omega_star,
                               "tooth.pressure_angle_deg": pressure_deg})
        design = pg.design(gs, scene="sketch", contact=False, stress=False, progress=stage.append)
        env = design.envelope
        row.update(outcome="flagged" if design.warnings else "ok", stage="", error="", message="")
    except Exception as exc:  # noqa: BLE001 - a named error is the expected report; anything else is a crash
        named = isinstance(exc, ProfilegenError)
        outcome = error_name(exc) if named else "CRASH"
        row.update(outcome=outcome, stage=stage[-1], error=error_name(exc),
                   message=(str(exc) if named else f"{error_name(exc)}: {exc} at {_where(exc)}")[:300])
        if stage[-1] in ("gearform", "arcfit"):  # the envelope itself succeeded: measure it
            sketch = pg.SCENES["sketch"]
            g = gs.gear
            motion = pg.HarmonicDriveMotion(pg.ring_theory(gs.deflection_mm, g.waves), g.neutral_radius_mm, g.waves,
                                            g.circular_spline_teeth)
            env = envelope_of(pg.tooth_from_gearset(gs), motion, cs_teeth=g.circular_spline_teeth, waves=g.waves,
                              chord_tol_mm=sketch.chord_tol_mm, n_t=sketch.n_t, n_phi=sketch.n_phi)
            # the same design with the design scene's envelope (chord 1e-6 mm, grid 96 × 241): does the
            # failure belong to the geometry or to the sketch scene's coarse envelope?
            fine = replace(sketch, chord_tol_mm=1e-6, n_t=96, n_phi=241)
            try:
                pg.design(gs, scene=fine, contact=False, stress=False)
                row["fine_envelope_outcome"] = "ok"
            except ProfilegenError as exc2:
                row["fine_envelope_outcome"] = error_name(exc2)
            except Exception as exc2:  # not a named error: a crash, recorded as such
                row["fine_envelope_outcome"] = f"CRASH {error_name(exc2)}"
                row["fine_envelope_message"] = f"{error_name(exc2)}: {exc2} at {_where(exc2)}"
    row["time_s"] = time.perf_counter() - t0
    row["grid_refinements"] = counter.count
    if env is not None:
        tooth_len = None
        no_root = sum(hi - lo for lo, hi in env.no_root.get("right", []))
        counts = env.counts()
        row.update(folds=len(env.folds), ridges=len(env.ridges), no_root_mm=no_root,
                   max_false_flank_um=env.max_interference_mm * 1e3,
                   conjugate_mm=counts["conjugate"]["length_mm"], tip_path_mm=counts["tip_path"]["length_mm"],
                   boundary_chains=env.flank.get("chains", 0), root_residual=env.residual)
        if design is not None:
            tooth_len = float(design.tooth.length_mm)
            prof = design.profile
            row.update(flank_length_mm=tooth_len, fit_max_error_um=prof.max_error_mm * 1e3,
                       fit_min_clearance_um=prof.clearance.min_mm * 1e3,
                       warnings=" | ".join(design.warnings)[:300])
            # independent checks: nothing non-finite, and an interfering CAD profile is warned about
            numbers = [env.max_interference_mm, env.residual, prof.max_error_mm, prof.clearance.min_mm,
                       design.form.tip_radius_mm, design.form.root_radius_mm]
            pts_ok = all(np.all(np.isfinite(p.points)) for p in env.pieces)
            silent_interference = prof.clearance.min_mm < -1e-6 and not any("interferes" in w for w in design.warnings)
            if not (pts_ok and np.all(np.isfinite(numbers))) or silent_interference:
                row["outcome"] = "UNDETECTED"
    return row


def run_envelope(quick: bool) -> dict:
    import matplotlib.pyplot as plt

    base = pg.load_gearset(pg.default_gearset_path())
    if quick:
        omegas = np.round(np.arange(0.3, 1.91, 0.2), 3)
        pressures = np.array([1.0, 4.0, 7.0, 10.0, 13.0, 16.0, 19.0])
    else:
        omegas = np.round(np.arange(0.3, 1.91, 0.1), 3)
        pressures = np.arange(1.0, 21.0, 1.0)
    counter = _BridgeCounter()
    env_log = logging.getLogger("profilegen.profile.envelope")
    env_log.addHandler(counter)
    old_level = env_log.level
    env_log.setLevel(logging.INFO)
    env_log.propagate = False
    rows = []
    t0 = time.perf_counter()
    try:
        for pa in pressures:
            for w in omegas:
                rows.append(envelope_point(base, float(w), float(pa), counter))
    finally:
        env_log.removeHandler(counter)
        env_log.setLevel(old_level)
        env_log.propagate = True
    elapsed = time.perf_counter() - t0
    write_csv("envelope", rows)

    shape = (len(pressures), len(omegas))

    def grid(key, default=np.nan):
        return np.array([r.get(key, default) if r.get(key) is not None else default for r in rows], float).reshape(shape)

    outcome = np.array([r["outcome"] for r in rows], object).reshape(shape)
    stage_short = {"gearset": "gs", "tooth": "T", "deformation": "D", "envelope": "E", "gearform": "G", "arcfit": "A"}
    annotate = [[stage_short.get(rows[j * shape[1] + i]["stage"], "")
                 + ("*" if rows[j * shape[1] + i].get("fine_envelope_outcome") == "ok" else "")
                 + ("!" if str(rows[j * shape[1] + i].get("fine_envelope_outcome", "")).startswith("CRASH") else "")
                 for i in range(shape[1])] for j in range(shape[0])]
    failed = np.array([r["outcome"] not in ("ok", "flagged") for r in rows]).reshape(shape)
    no_env = np.isnan(grid("folds"))
    xe, ye = edges(omegas), edges(pressures)
    fig, axes = plt.subplots(2, 3, figsize=(16, 9.5), constrained_layout=True)
    ax = axes[0, 0]
    categorical_map(ax, xe, ye, outcome, annotate=annotate)
    ax.set_title("outcome (letter: stage that raised — T tooth, G gearform, A arcfit;\n"
                 "*: passes with the design scene's 1e-6 mm envelope, !: crashes with it)", fontsize=9)
    panels = [
        (axes[0, 1], "folds", "folds f = ∂f/∂φ = 0 (both flanks)", "magma", True),
        (axes[0, 2], "no_root_mm", "no-root length on the right flank (mm of arc length)", "viridis", False),
        (axes[1, 0], "max_false_flank_um", "deepest false (interfering) flank (µm)", "inferno", False),
        (axes[1, 1], "ridges", "branch-switch ridges on the CS flank", "cividis", True),
        (axes[1, 2], "grid_refinements", "root-trace grid doublings (root curves bridged)", "plasma", True),
    ]
    for ax, key, label, cmap, integer in panels:
        z = grid(key)
        value_map(fig, ax, xe, ye, z, label=label, cmap=cmap, integer=integer,
                  failed=no_env if key != "grid_refinements" else None, failed_label="no envelope (tooth invalid)")
        ax.set_title(label, fontsize=9)
    for ax in axes.ravel():
        ax.set_xlabel("ω* = w0 / m (deflection coefficient)")
        ax.set_ylabel("DCTA pressure angle (deg)")
    fig.suptitle("Envelope stability map: default set (m 0.5 mm, z 200/202, DCTA), sketch scene (ring theory, "
                 "chord 1e-4 mm, grid 96 × 241)", fontsize=11)
    save_figure(fig, "envelope")

    outcomes = {k: int(np.sum(outcome == k)) for k in sorted(set(outcome.ravel()))}
    ok = [r for r in rows if r["outcome"] in ("ok", "flagged")]
    by_stage = {}
    for r in rows:
        if r["error"]:
            key = f"{r['error']} ({r['stage']})"
            by_stage[key] = by_stage.get(key, 0) + 1
    with_folds = [r["omega_star"] for r in ok if r["folds"] > 0]
    summary = {
        "grid": (f"ω* {omegas[0]}…{omegas[-1]} ({len(omegas)}) × pressure angle {pressures[0]:g}…{pressures[-1]:g}° "
                 f"({len(pressures)})"),
        "points": len(rows),
        "time_s": elapsed,
        "outcomes": outcomes,
        "errors_by_stage": by_stage,
        "undetected": outcomes.get("UNDETECTED", 0),
        "folds_range": [int(min(r["folds"] for r in ok)), int(max(r["folds"] for r in ok))] if ok else None,
        "largest_omega_star_with_folds": max(with_folds) if with_folds else None,
        "failures_passing_with_fine_envelope": sum(1 for r in rows if r.get("fine_envelope_outcome") == "ok"),
        "failures_rechecked_with_fine_envelope": sum(1 for r in rows if "fine_envelope_outcome" in r),
        "failures_passing_with_fine_envelope_at": sorted({(r["omega_star"], r["pressure_angle_deg"]) for r in rows
                                                          if r.get("fine_envelope_outcome") == "ok"}),
        "boundary_chains_max": max((r.get("boundary_chains", 0) for r in rows), default=0),
        "crashes": [f"ω* {r['omega_star']}, {r['pressure_angle_deg']:g}°: {r['message']}" for r in rows
                    if r["outcome"] == "CRASH"],
        "fine_envelope_crashes": [f"ω* {r['omega_star']}, {r['pressure_angle_deg']:g}°: {r['fine_envelope_message']}"
                                  for r in rows if str(r.get("fine_envelope_outcome", "")).startswith("CRASH")],
        "max_no_root_mm": max((r["no_root_mm"] for r in ok), default=None),
        "false_flank_um_range": [min(r["max_false_flank_um"] for r in ok), max(r["max_false_flank_um"] for r in ok)] if ok else None,
        "points_with_ridges": sum(1 for r in ok if r["ridges"] > 0),
        "points_needing_grid_refinement": sum(1 for r in rows if r["grid_refinements"] > 0),
        "max_grid_refinements": max(r["grid_refinements"] for r in rows),
        "smallest_omega_star_with_working_flank": min((r["omega_star"] for r in ok), default=None),
        "examples": {},
    }
    for r in rows:
        if r["error"] and r["error"] not in summary["examples"]:
            summary["examples"][r["error"]] = f"ω* {r['omega_star']}, {r['pressure_angle_deg']:g}°: {r['message'][:200]}"
    return summary


# ----------------------------------------------------------------------------- (b) fitter

W0 = 0.5
OMEGA_H = {1: W0, 2: 2e-3, 3: 3e-4, 4: 4e-5, 5: 5e-6}  # cos 2kφ amplitudes (mm)
UPSILON_H = {1: -W0 / 2, 2: -1e-3, 3: -1e-4, 4: -1e-5, 5: -1e-6}  # sin 2kφ


def fitter_truth(phi):
    om = sum(a * np.cos(2 * k * phi) for k, a in OMEGA_H.items())
    up = sum(a * np.sin(2 * k * phi) for k, a in UPSILON_H.items())
    return om, up


def run_fitter(quick: bool) -> dict:
    import matplotlib.pyplot as plt
    from profilegen.geometry.series import SeriesError, fit_fourier, fit_sine_series

    n = 360
    phi = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    dense = np.linspace(0.0, 2 * np.pi, 4001)
    om_true, up_true = fitter_truth(phi)
    om_dense, up_dense = fitter_truth(dense)
    sigmas = np.logspace(-9, -3, 7 if quick else 13)
    orders = np.arange(1, 13)
    terms_list = np.arange(1, 5 if quick else 6)
    starts = 8 if quick else 20
    realisations = 1 if quick else 3
    rows = []
    t0 = time.perf_counter()
    picks = []
    for s_i, sigma in enumerate(sigmas):
        for rep in range(realisations):
            rng = np.random.default_rng(1000 * s_i + rep)
            om = om_true + sigma * rng.normal(size=n)
            up = up_true + sigma * rng.normal(size=n)
            for crit in ("noise", "aicc"):
                f = fit_fourier(phi, om, up, criterion=crit, max_order=12)
                (w,), (u,) = f.evaluate(dense, 0)
                picks.append({"sigma_mm": sigma, "rep": rep, "criterion": crit, "order": f.order,
                              "err_mm": max(np.max(np.abs(w - om_dense)), np.max(np.abs(u - up_dense))),
                              "warnings": len(f.warnings)})
            for K in orders:
                row = {"fitter": "fourier", "sigma_mm": sigma, "rep": rep, "order_or_terms": int(K)}
                try:
                    f = fit_fourier(phi, om, up, order=int(K))
                    (w,), (u,) = f.evaluate(dense, 0)
                    row.update(outcome="flagged" if f.warnings else "ok",
                               err_omega_mm=float(np.max(np.abs(w - om_dense))),
                               err_upsilon_mm=float(np.max(np.abs(u - up_dense))),
                               rmse_omega_mm=f.omega_stats.rmse_mm, defect_omega_mm=f.omega_stats.defect_mm,
                               defect_upsilon_mm=f.upsilon_stats.defect_mm)
                except SeriesError as exc:
                    row.update(outcome="SeriesError", message=str(exc))
                rows.append(row)
            if rep == 0 or not quick:
                for terms in terms_list:
                    row = {"fitter": "sine", "sigma_mm": sigma, "rep": rep, "order_or_terms": int(terms)}
                    try:
                        fw = fit_sine_series(phi, om, terms=int(terms), starts=starts, seed=rep)
                        fu = fit_sine_series(phi, up, terms=int(terms), starts=starts, seed=rep)
                        w, u = fw.evaluate(dense, 0)[0], fu.evaluate(dense, 0)[0]
                        # the defect is recomputed here from the fitted series (an independent check of the report)
                        d_w = float(fw.evaluate(np.array([0.0, 2 * np.pi]), 0)[0] @ [-1, 1])
                        bad_report = abs(d_w - fw.stats.defect_mm) > 1e-12 + 1e-9 * abs(d_w)
                        row.update(outcome="UNDETECTED" if bad_report else ("flagged" if (fw.warnings or fu.warnings) else "ok"),
                                   err_omega_mm=float(np.max(np.abs(w - om_dense))),
                                   err_upsilon_mm=float(np.max(np.abs(u - up_dense))),
                                   rmse_omega_mm=fw.stats.rmse_mm, defect_omega_mm=fw.stats.defect_mm,
                                   defect_upsilon_mm=fu.stats.defect_mm,
                                   freqs_omega=" ".join(f"{b:.6f}" for b in fw.frequency_per_rad),
                                   n_at_best=min(fw.n_at_best, fu.n_at_best),
                                   warnings=" | ".join(fw.warnings + fu.warnings))
                    except (SeriesError, ConvergenceError) as exc:
                        row.update(outcome=error_name(exc), message=str(exc))
                    rows.append(row)
    t_maps = time.perf_counter() - t0

    # the input domain: samples × order (Fourier) and samples × terms (sine), exact data
    domain = []
    ns = [3, 4, 5, 6, 7, 8, 9, 10, 12, 16, 20, 24, 32, 48]
    for m in ns:
        p = np.linspace(0.0, 2 * np.pi, m, endpoint=False)
        o, u = fitter_truth(p)
        od, ud = om_dense, up_dense
        for K in ["auto"] + list(range(1, 9)):
            row = {"fitter": "fourier", "samples": m, "order_or_terms": K}
            try:
                f = fit_fourier(p, o, u, order=None if K == "auto" else K, max_order=12)
                (w,), (v,) = f.evaluate(dense, 0)
                err = float(max(np.max(np.abs(w - od)), np.max(np.abs(v - ud))))
                phantom = err > float(np.max(np.abs(o)))
                row.update(outcome="flagged" if f.warnings else ("UNDETECTED" if phantom else "ok"), order=f.order,
                           err_mm=err,
                           message=" | ".join(f.warnings)[:300])
            except SeriesError as exc:
                row.update(outcome="SeriesError", message=str(exc)[:300])
            domain.append(row)
        for terms in range(1, 6):
            row = {"fitter": "sine", "samples": m, "order_or_terms": terms}
            try:
                fw = fit_sine_series(p, o, terms=terms, starts=4)
                err = float(np.max(np.abs(fw.evaluate(dense, 0)[0] - od)))
                # an error larger than the data themselves (a phantom term the samples cannot see) with no
                # warning is a wrong answer returned as a plain one
                phantom = err > float(np.max(np.abs(o)))
                row.update(outcome="flagged" if fw.warnings else ("UNDETECTED" if phantom else "ok"), err_mm=err,
                           defect_omega_mm=fw.stats.defect_mm, max_amplitude_mm=float(np.max(fw.amplitude_mm)),
                           frequencies=" ".join(f"{b:.6f}" for b in fw.frequency_per_rad),
                           nyquist_per_rad=math.pi * (m - 1) / float(p.max() - p.min()),
                           message=" | ".join(fw.warnings)[:300])
            except (SeriesError, ConvergenceError) as exc:
                row.update(outcome=error_name(exc), message=str(exc)[:300])
            domain.append(row)
    # bad input that must be refused by name
    bad_inputs = {}
    p = np.linspace(0.0, 2 * np.pi, 40, endpoint=False)
    o, u = fitter_truth(p)
    o_nan = o.copy()
    o_nan[7] = np.nan
    for label, call in [
        ("fourier, NaN in ω", lambda: fit_fourier(p, o_nan, u)),
        ("sine, NaN in ω", lambda: fit_sine_series(p, o_nan)),
        ("fourier, half a wave period", lambda: fit_fourier(p[:10], o[:10], u[:10])),
        ("fourier, order 10 on 40 samples (harmonic 20 aliases)", lambda: fit_fourier(p, o, u, order=10)),
        ("sine, 3 terms on 9 samples", lambda: fit_sine_series(p[:9], o[:9], terms=3)),
    ]:
        try:
            call()
            bad_inputs[label] = "UNDETECTED: returned an answer"
        except (SeriesError, ConvergenceError) as exc:
            bad_inputs[label] = f"{error_name(exc)}: {exc}"
    write_csv("fitter", rows + [dict(r, fitter=f"{r['fitter']}_pick") for r in
                               ({"fitter": "fourier", "sigma_mm": q["sigma_mm"], "rep": q["rep"],
                                 "order_or_terms": q["order"], "criterion": q["criterion"], "err_omega_mm": q["err_mm"]}
                                for q in picks)])
    write_csv("fitter_domain", domain)

    # figures
    def med(fitter, key, xs, ys):
        z = np.full((len(ys), len(xs)), np.nan)
        for j, yv in enumerate(ys):
            for i, xv in enumerate(xs):
                vals = [r.get(key) for r in rows if r["fitter"] == fitter and r["order_or_terms"] == yv
                        and r["sigma_mm"] == xv and r.get(key) is not None]
                if vals:
                    z[j, i] = float(np.median(np.abs(vals)))
        return z

    err_f = np.maximum(med("fourier", "err_omega_mm", sigmas, orders), med("fourier", "err_upsilon_mm", sigmas, orders))
    err_s = np.maximum(med("sine", "err_omega_mm", sigmas, terms_list), med("sine", "err_upsilon_mm", sigmas, terms_list))
    defect_s = np.maximum(med("sine", "defect_omega_mm", sigmas, terms_list), med("sine", "defect_upsilon_mm", sigmas, terms_list))
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.2), constrained_layout=True)
    xe = log_edges(sigmas)
    ax = axes[0]
    value_map(fig, ax, xe, edges(orders), err_f, label="max |fit − truth| over [0, 2π], ω and υ (mm)", log=True,
              cmap="viridis", vmin=1e-10, vmax=1e-2)
    for crit, marker, colour in (("noise", "o", "white"), ("aicc", "x", "red")):
        xs = [q["sigma_mm"] for q in picks if q["criterion"] == crit and q["rep"] == 0]
        ys = [q["order"] for q in picks if q["criterion"] == crit and q["rep"] == 0]
        ax.plot(xs, ys, marker=marker, color=colour, ls="-", lw=1, ms=6, label=f"order picked ({crit} rule)")
    ax.axhline(5, color="w", ls=":", lw=1)
    ax.text(sigmas[0], 5.15, "truth: 5 harmonics", color="w", fontsize=7)
    ax.legend(loc="upper right", fontsize=7)
    ax.set_xscale("log")
    ax.set_xlabel("noise σ on ω, υ (mm)")
    ax.set_ylabel("Fourier order K (harmonics of U = 2)")
    ax.set_title("Fourier fit (integer harmonics): error vs order and noise", fontsize=10)
    ax = axes[1]
    value_map(fig, ax, xe, edges(terms_list), err_s, label="max |fit − truth| over [0, 2π], ω and υ (mm)", log=True,
              cmap="viridis", vmin=1e-10, vmax=1e-2)
    ax.set_xscale("log")
    ax.set_xlabel("noise σ on ω, υ (mm)")
    ax.set_ylabel("sine terms (3 parameters each)")
    ax.set_title(f"general sine series (seed 004 form, {starts} starts): error", fontsize=10)
    ax = axes[2]
    value_map(fig, ax, xe, edges(terms_list), defect_s, label="|f(2π) − f(0)|, worse of ω and υ (mm)", log=True,
              cmap="magma", vmin=1e-12, vmax=1e-2)
    ax.set_xscale("log")
    ax.set_xlabel("noise σ on ω, υ (mm)")
    ax.set_ylabel("sine terms")
    ax.set_title("general sine series: periodicity defect (reported in stats.defect_mm)", fontsize=10)
    fig.suptitle(f"Deformation fitters on synthetic data: ring theory w0 = {W0} mm + harmonics cos/sin 4…10φ "
                 f"(2 µm … 1 nm), {n} samples on [0, 2π); median of {realisations} noise draw(s)", fontsize=11)
    save_figure(fig, "fitter")

    fig, axes = plt.subplots(1, 2, figsize=(14, 5.2), constrained_layout=True)
    for ax, fitter, ylabels, title in (
        (axes[0], "fourier", ["auto"] + list(range(1, 9)), "Fourier fit: order K (auto = noise rule, max_order 12)"),
        (axes[1], "sine", list(range(1, 6)), "general sine series: terms"),
    ):
        lab = np.array([[next(r["outcome"] for r in domain if r["fitter"] == fitter and r["samples"] == m
                              and r["order_or_terms"] == k) for m in ns] for k in ylabels], object)
        ann = [[("" if "err_mm" not in r else
                 f"{math.log10(max(r['err_mm'], 1e-16)):.0f}")
                for m in ns for r in [next(r for r in domain if r["fitter"] == fitter and r["samples"] == m
                                           and r["order_or_terms"] == k)]] for k in ylabels]
        categorical_map(ax, np.arange(len(ns) + 1) - 0.5, np.arange(len(ylabels) + 1) - 0.5, lab, annotate=ann)
        ax.set_xticks(range(len(ns)), [str(m) for m in ns])
        ax.set_yticks(range(len(ylabels)), [str(k) for k in ylabels])
        ax.set_xlabel("samples on [0, 2π) (exact data)")
        ax.set_title(title + "\nnumber in a cell: log10 of max |fit − truth| (mm)", fontsize=10)
    axes[0].set_ylabel("order K")
    axes[1].set_ylabel("terms")
    fig.suptitle("Where the fitters refuse (SeriesError) or warn (flagged: order reduced / skipped / highest tried, aliased "
                 "term);\nUNDETECTED: an error larger than the data themselves returned without a warning", fontsize=10)
    save_figure(fig, "fitter_domain")

    # summary numbers
    def pick(crit, sigma):
        return [q for q in picks if q["criterion"] == crit and q["sigma_mm"] == sigma]

    best_f = np.nanmin(err_f, axis=0)
    summary = {
        "time_s": t_maps,
        "sigmas_mm": sigmas.tolist(),
        "fourier_noise_pick": {f"{s:.0e}": [q["order"] for q in pick("noise", s)] for s in sigmas},
        "fourier_aicc_pick": {f"{s:.0e}": [q["order"] for q in pick("aicc", s)] for s in sigmas},
        "fourier_noise_pick_err_mm": {f"{s:.0e}": float(np.median([q["err_mm"] for q in pick("noise", s)])) for s in sigmas},
        "fourier_best_err_mm": {f"{s:.0e}": float(b) for s, b in zip(sigmas, best_f)},
        "sine_err_mm": {f"{s:.0e}": {int(t): float(err_s[j, i]) for j, t in enumerate(terms_list)} for i, s in enumerate(sigmas)},
        "sine_defect_mm": {f"{s:.0e}": {int(t): float(defect_s[j, i]) for j, t in enumerate(terms_list)} for i, s in enumerate(sigmas)},
        "fourier_defect_max_mm": float(max(abs(r.get("defect_omega_mm", 0.0)) for r in rows if r["fitter"] == "fourier")),
        "domain_outcomes": {f: {k: sum(1 for r in domain if r["fitter"] == f and r["outcome"] == k)
                                for k in sorted({r["outcome"] for r in domain if r["fitter"] == f})}
                            for f in ("fourier", "sine")},
        "bad_inputs": bad_inputs,
        "domain_undetected": [f"{r['fitter']} n={r['samples']} {r['order_or_terms']}: error {r['err_mm']:.3g} mm, "
                              f"largest amplitude {r.get('max_amplitude_mm', float('nan')):.3g} mm, frequencies "
                              f"{r.get('frequencies', '')} (Nyquist {r.get('nyquist_per_rad', float('nan')):.4g})"
                              for r in domain if r["outcome"] == "UNDETECTED"],
        "undetected": sum(1 for r in rows + domain if r["outcome"] == "UNDETECTED")
        + sum(1 for v in bad_inputs.values() if v.startswith("UNDETECTED")),
    }
    return summary


# ----------------------------------------------------------------------------- (c) contact


def contact_problem(rng, n: int, kappa: float):
    """Random SPD compliance (mm/N) with condition number κ, θ in [0, 1 mrad], r in [15, 45] mm,
    and a torque whose elastic rotation τ = a0·T is a log-uniform 1e-2…1e2 times the θ span."""
    q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    lam = np.logspace(0.0, -math.log10(kappa), n) if n > 1 else np.ones(1)
    S = (q * lam) @ q.T * 1e-7
    S = 0.5 * (S + S.T)
    theta = rng.uniform(0.0, 1e-3, n)
    r = rng.uniform(15.0, 45.0, n)
    a0 = float(np.mean(np.diag(S) / r**2))
    load = 10.0 ** rng.uniform(-2.0, 2.0)
    T = load * 1e-3 / a0
    return S, theta, r, T, load


def run_contact(quick: bool) -> dict:
    import matplotlib.pyplot as plt
    from profilegen.contact import ContactError, solve_lemke, solve_qp_active_set
    from tests.oracles.naive_lp import solve_naive_lp

    sizes = [5, 20, 100] if quick else [2, 5, 10, 20, 50, 100, 200]
    kappas = [1e0, 1e4, 1e8, 1e11, 1e13] if quick else [1e0, 1e2, 1e4, 1e6, 1e8, 1e10, 1e11, 1e12, 1e13]
    trials = 6 if quick else 20
    rows = []
    t0 = time.perf_counter()
    for n in sizes:
        for kappa in kappas:
            rng = np.random.default_rng(int(n * 1000 + math.log10(kappa)))
            for trial in range(trials):
                S, theta, r, T, load = contact_problem(rng, n, kappa)
                row = {"n": n, "kappa": kappa, "trial": trial, "load_ratio": load}
                res = {}
                for name, solver in (("lemke", solve_lemke), ("qp", solve_qp_active_set), ("lp", solve_naive_lp)):
                    try:
                        res[name] = solver(S, theta, r, T)
                        row[f"{name}_outcome"] = "ok"
                    except (ContactError, ConvergenceError) as exc:
                        row[f"{name}_outcome"] = error_name(exc)
                        row[f"{name}_message"] = str(exc)[:200]
                if "lemke" in res and "qp" in res:
                    a, b = res["lemke"], res["qp"]
                    row["lemke_qp_force_diff"] = float(np.max(np.abs(a.force_n - b.force_n)) / a.max_force_n)
                    row["lemke_qp_phi_diff"] = abs(a.phi_rad - b.phi_rad) / max(a.diagnostics["tau_rad"], 1e-300)
                    row["loaded"] = a.loaded_count
                if "lemke" in res and "lp" in res:
                    good, lp = res["lemke"], res["lp"]
                    # the naive LP's answer against the contact solution: forces, and complementarity with the gaps
                    # recomputed from the data (not the solver's own residual)
                    g = r * (theta - lp.phi_rad) + S @ lp.force_n
                    scale = T * (abs(good.phi_rad - theta.min()) + good.diagnostics["tau_rad"])
                    comp = float(np.max(np.abs(lp.force_n * g)) / scale)
                    wrong = bool(np.max(np.abs(lp.force_n - good.force_n)) > 1e-6 * good.max_force_n)
                    flagged = bool(lp.warnings)
                    row.update(lp_loaded=lp.loaded_count, lp_phi_rad=lp.phi_rad, lp_comp_true=comp,
                               lp_comp_reported=lp.complementarity_residual, lp_wrong=wrong, lp_flagged=flagged,
                               lp_one_point=bool(lp.loaded_count == 1 and good.loaded_count > 1),
                               lp_undetected=bool(wrong and not flagged),
                               lp_theta_min_over_tau=float(theta.min() / good.diagnostics["tau_rad"]))
                rows.append(row)
    elapsed = time.perf_counter() - t0
    write_csv("contact", rows)

    shape = (len(sizes), len(kappas))

    def cells(key, reduce):
        z = np.full(shape, np.nan)
        for j, n in enumerate(sizes):
            for i, k in enumerate(kappas):
                v = [r[key] for r in rows if r["n"] == n and r["kappa"] == k and key in r]
                if v:
                    z[j, i] = float(reduce(v))
        return z

    def frac(key):
        return cells(key, np.mean)

    def worst(key):
        return cells(key, np.max)

    refused = np.array([[all(r["lemke_outcome"] != "ok" for r in rows if r["n"] == n and r["kappa"] == k)
                         for k in kappas] for n in sizes])
    xe, ye = np.arange(len(kappas) + 1) - 0.5, np.arange(len(sizes) + 1) - 0.5
    fig, axes = plt.subplots(2, 2, figsize=(13, 9.5), constrained_layout=True)
    panels = [
        (axes[0, 0], frac("lp_wrong"), "naive phase-1 LP: fraction of answers ≠ the contact solution", "Reds", False, (0, 1)),
        (axes[0, 1], frac("lp_one_point"), "naive LP: fraction with the whole torque on ONE point\n(where Lemke loads > 1)",
         "Oranges", False, (0, 1)),
        (axes[1, 0], frac("lp_undetected"), "naive LP: fraction wrong AND without a warning (UNDETECTED;\n"
         "θ_min > τ makes the reported complementarity residual negative)", "Purples", False, (0, 1)),
        (axes[1, 1], worst("lemke_qp_force_diff"), "Lemke vs active-set QP: max |ΔF| / max F (worst trial)", "viridis",
         True, (1e-16, 1e-6)),
    ]
    for ax, z, label, cmap, log, (lo, hi) in panels:
        cbar = "max |ΔF| / max F" if log else "fraction of the trials in the cell"
        value_map(fig, ax, xe, ye, z, label=cbar, cmap=cmap, log=log, failed=refused, vmin=lo, vmax=hi,
                  failed_label="S refused by every solver (ContactError)")
        ax.set_xticks(range(len(kappas)), [f"1e{round(math.log10(k))}" for k in kappas])
        ax.set_yticks(range(len(sizes)), [str(s_) for s_ in sizes])
        ax.set_xlabel("condition number κ of the compliance S")
        ax.set_ylabel("contact points n")
        ax.set_title(label, fontsize=10)
        for j in range(shape[0]):
            for i in range(shape[1]):
                if np.isfinite(z[j, i]) and not refused[j, i]:
                    text = f"{z[j, i]:.2f}" if not log else f"{z[j, i]:.0e}"
                    ax.text(i, j, text, ha="center", va="center", fontsize=7,
                            color="white" if (not log and z[j, i] > 0.6) else "black")
    fig.suptitle(f"Contact solvers on random SPD problems ({trials} per cell; θ uniform in [0, 1 mrad], "
                 "elastic rotation τ = a0·T log-uniform 1e-2…1e2 × the θ span)", fontsize=11)
    save_figure(fig, "contact")

    solved = [r for r in rows if r.get("lp_outcome") == "ok" and "lp_wrong" in r]
    und = [r for r in solved if r["lp_undetected"]]
    summary = {
        "time_s": elapsed,
        "problems": len(rows),
        "naive_lp_answers": len(solved),
        "naive_lp_wrong_fraction": float(np.mean([r["lp_wrong"] for r in solved])) if solved else None,
        "naive_lp_one_point_fraction": float(np.mean([r["lp_one_point"] for r in solved])) if solved else None,
        "naive_lp_phi_zero_fraction": float(np.mean([r["lp_phi_rad"] == 0.0 for r in solved])) if solved else None,
        "naive_lp_flagged_fraction_of_wrong": float(np.mean([r["lp_flagged"] for r in solved if r["lp_wrong"]]))
        if any(r["lp_wrong"] for r in solved) else None,
        "naive_lp_undetected": len(und),
        "naive_lp_undetected_fraction": len(und) / len(solved) if solved else None,
        "undetected_reported_residual_range": [min(r["lp_comp_reported"] for r in und), max(r["lp_comp_reported"] for r in und)]
        if und else None,
        "undetected_theta_min_over_tau_min": min(r["lp_theta_min_over_tau"] for r in und) if und else None,
        "detected_theta_min_over_tau_max": max((r["lp_theta_min_over_tau"] for r in solved if r["lp_wrong"] and r["lp_flagged"]),
                                               default=None),
        "lemke_qp_max_force_diff": float(np.nanmax([r.get("lemke_qp_force_diff", np.nan) for r in rows])),
        "refused_kappa_min": min((r["kappa"] for r in rows if r["lemke_outcome"] == "ContactError"), default=None),
        "solved_kappa_max": max((r["kappa"] for r in rows if r["lemke_outcome"] == "ok"), default=None),
        "lemke_failures": sum(1 for r in rows if r["lemke_outcome"] not in ("ok", "ContactError")),
        "qp_failures": sum(1 for r in rows if r["qp_outcome"] not in ("ok", "ContactError")),
    }
    by_kappa = {}
    for k in kappas:
        sel = [r for r in rows if r["kappa"] == k]
        ok = [r for r in sel if r["lemke_outcome"] == "ok"]
        lp = [r for r in ok if "lp_wrong" in r]
        by_kappa[f"{k:.0e}"] = {
            "refused": sum(1 for r in sel if r["lemke_outcome"] == "ContactError") / len(sel),
            "lemke_qp_worst": max((r.get("lemke_qp_force_diff", 0.0) for r in ok), default=None),
            "lp_wrong": float(np.mean([r["lp_wrong"] for r in lp])) if lp else None,
            "lp_undetected": float(np.mean([r["lp_undetected"] for r in lp])) if lp else None,
        }
    summary["by_kappa"] = by_kappa
    # the iteration caps: a named ConvergenceError naming the cap
    S, theta, r, T, _ = contact_problem(np.random.default_rng(7), 30, 1e3)
    caps = {}
    for label, call in (("lemke max_pivots=2", lambda: solve_lemke(S, theta, r, T * 100, max_pivots=2)),
                        ("qp max_iter=1", lambda: solve_qp_active_set(S, theta, r, T * 100, max_iter=1))):
        try:
            call()
            caps[label] = "returned an answer"
        except ConvergenceError as exc:
            caps[label] = f"ConvergenceError: {exc}"
    summary["iteration_caps"] = caps
    return summary


# ----------------------------------------------------------------------------- (d) rim


def run_rim(quick: bool) -> dict:
    import matplotlib.pyplot as plt
    from profilegen.rim import solve_ring
    from profilegen.geometry.wavegen import EllipticalCam, from_gearset

    gs = pg.load_gearset(pg.default_gearset_path())
    cam = from_gearset(gs)
    w0 = gs.deflection_mm
    steps = [0.01, 0.1, 1.0] if quick else [0.01, 0.03, 0.1, 0.3, 1.0, 3.0]
    deltas_um = sorted([-s for s in steps] + [0.0] + steps)
    meshes = [64] if quick else [32, 64, 128]
    rows = []
    t0 = time.perf_counter()
    ref = {}
    for geometry in ("linear", "nonlinear"):
        for div in meshes:
            for d in deltas_um:
                c = EllipticalCam(cam.semi_major_mm, cam.semi_minor_mm + d * 1e-3, cam.bearing_thickness_mm)
                row = {"geometry": geometry, "divisions": div, "delta_b_um": d}
                t1 = time.perf_counter()
                try:
                    res = solve_ring(gs, contour=c, geometry=geometry, layers=4, divisions=div)
                    hist = np.array(res.active_history)
                    row.update(outcome="flagged" if res.warnings else "ok", wrap_deg=res.contact_angle_deg,
                               omega0_mm=float(res.omega_mm[0]), omega90_mm=float(res.omega_mm[-1]),
                               active_nodes=res.active_count, relinearisations=res.iterations,
                               newton_iterations=len(res.newton_steps_mm),
                               active_set_swing=int(np.max(np.abs(np.diff(hist)))) if hist.size > 1 else 0,
                               warned_wrap=any("ill-conditioned" in w for w in res.warnings))
                    if d == 0.0:
                        ref[(geometry, div)] = res
                    row["_res"] = res
                except (ConvergenceError, ProfilegenError) as exc:
                    row.update(outcome=error_name(exc), message=str(exc)[:300])
                row["time_s"] = time.perf_counter() - t1
                rows.append(row)
    for row in rows:
        res = row.pop("_res", None)
        base = ref.get((row["geometry"], row["divisions"]))
        if res is not None and base is not None:
            row["max_domega_um"] = float(np.max(np.abs(res.omega_mm - base.omega_mm)) * 1e3)
            row["max_dupsilon_um"] = float(np.max(np.abs(res.upsilon_mm - base.upsilon_mm)) * 1e3)
            row["dwrap_deg"] = res.contact_angle_deg - base.contact_angle_deg
    # the contact iteration made to fail
    caps = []
    for geometry in ("linear", "nonlinear"):
        for cap in (1, 2, 3, 4, 6, 10, 50):
            row = {"geometry": geometry, "max_iterations": cap}
            try:
                res = solve_ring(gs, contour=cam, geometry=geometry, max_iterations=cap)
                row.update(outcome="flagged" if res.warnings else "ok", relinearisations=res.iterations,
                           newton_iterations=len(res.newton_steps_mm))
            except ConvergenceError as exc:
                kind = "Newton" if "Newton" in str(exc) else "contact gaps"
                row.update(outcome="ConvergenceError", kind=kind, message=str(exc)[:300])
            caps.append(row)
    elapsed = time.perf_counter() - t0
    write_csv("rim", rows + [dict(r, table="iteration_cap") for r in caps])

    fig, axes = plt.subplots(1, 3, figsize=(17, 5), constrained_layout=True)
    styles = {32: ":", 64: "-", 128: "--"}
    colours = {"linear": "tab:blue", "nonlinear": "tab:red"}
    for geometry in ("linear", "nonlinear"):
        for div in meshes:
            sel = [r for r in rows if r["geometry"] == geometry and r["divisions"] == div and "wrap_deg" in r]
            x = [r["delta_b_um"] for r in sel]
            lab = f"{geometry}, 4×{div}"
            axes[0].plot(x, [r["wrap_deg"] for r in sel], styles[div], color=colours[geometry], marker="o", ms=3, label=lab)
            if div != 64:  # the relative changes on the design mesh only (the others say the same)
                continue
            for side in (-1, 1):
                nz = [r for r in sel if r["delta_b_um"] * side > 0.0]
                axes[1].plot([r["delta_b_um"] for r in nz], [r["max_domega_um"] * 1e-3 / w0 for r in nz], "-",
                             color=colours[geometry], marker="o", ms=3,
                             label=f"max |Δω| / w0, {geometry}" if side > 0 else None)
                axes[1].plot([r["delta_b_um"] for r in nz],
                             [max(abs(r["dwrap_deg"]) / (r["wrap_deg"] - r["dwrap_deg"]), 1e-7) for r in nz], "--",
                             color=colours[geometry], marker="s", ms=4, mfc="none",
                             label=f"|Δwrap| / wrap, {geometry}" if side > 0 else None)
    for ax in axes[:2]:
        ax.set_xscale("symlog", linthresh=0.01)
        ax.set_xlabel("change of the cam's minor semi-axis δb (µm)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("contact (wrap) angle (deg from the major axis)")
    axes[0].set_title("wrap angle: ill-conditioned (reported with a warning)", fontsize=10)
    axes[1].set_yscale("log")
    axes[1].set_ylim(5e-8, 2.0)
    axes[1].set_ylabel("relative change against δb = 0 (–)")
    axes[1].set_title("relative change on the 4×64 mesh: ω (filled) vs the wrap angle (open;\n"
                      "at 1e-7: unchanged, below one node step 90°/128 = 0.7°)", fontsize=10)
    ax = axes[2]
    cap_list = sorted({r["max_iterations"] for r in caps})
    lab = np.array([[next(r["outcome"] for r in caps if r["geometry"] == g and r["max_iterations"] == c)
                     for c in cap_list] for g in ("linear", "nonlinear")], object)
    def cap_note(r):
        if r["outcome"] == "ConvergenceError":
            return "Newton" if r["kind"] == "Newton" else "gaps"
        return f"{r['relinearisations']}/{r['newton_iterations']}"

    ann = [[cap_note(next(r for r in caps if r["geometry"] == g and r["max_iterations"] == c)) for c in cap_list]
           for g in ("linear", "nonlinear")]
    categorical_map(ax, np.arange(len(cap_list) + 1) - 0.5, np.arange(3) - 0.5, lab, annotate=ann)
    ax.set_xticks(range(len(cap_list)), [str(c) for c in cap_list])
    ax.set_yticks([0, 1], ["linear", "nonlinear"])
    ax.set_ylim(-0.5, 1.5)
    ax.set_xlabel("max_iterations (re-linearisations of the gap; Newton steps)")
    ax.set_title("contact iteration with a cap → ConvergenceError naming where\n"
                 "(cell: the loop that failed, or re-linearisations / Newton steps used)", fontsize=10)
    fig.suptitle("Rim FEM (default set, flat ring, elliptical cam, w0 = 0.5 mm): the wrap angle against µm changes of the "
                 "cam; flagged = every answer carries the wrap-angle warning", fontsize=11)
    save_figure(fig, "rim")

    def sens(geometry, div):
        sel = {r["delta_b_um"]: r for r in rows if r["geometry"] == geometry and r["divisions"] == div and "wrap_deg" in r}
        out = {}
        for d in (0.1, 1.0):
            if d in sel and -d in sel:
                out[f"±{d:g} µm"] = {"wrap_deg": [sel[-d]["wrap_deg"], sel[0.0]["wrap_deg"], sel[d]["wrap_deg"]],
                                     "max_domega_um": max(sel[-d]["max_domega_um"], sel[d]["max_domega_um"])}
        return out

    summary = {
        "time_s": elapsed,
        "solves": len(rows) + len(caps),
        "outcomes": {k: sum(1 for r in rows if r["outcome"] == k) for k in sorted({r["outcome"] for r in rows})},
        "all_answers_carry_wrap_warning": all(r.get("warned_wrap", True) for r in rows),
        "wrap_range_deg": {f"{g} 4×{d}": [min(r["wrap_deg"] for r in rows if r["geometry"] == g and r["divisions"] == d
                                               and "wrap_deg" in r),
                                           max(r["wrap_deg"] for r in rows if r["geometry"] == g and r["divisions"] == d
                                               and "wrap_deg" in r)]
                           for g in ("linear", "nonlinear") for d in meshes},
        "wrap_at_zero_by_mesh": {f"{g} 4×{d}": ref[(g, d)].contact_angle_deg for g in ("linear", "nonlinear") for d in meshes
                                 if (g, d) in ref},
        "sensitivity_64": {g: sens(g, 64) for g in ("linear", "nonlinear")},
        "max_active_set_swing": {g: max(r.get("active_set_swing", 0) for r in rows if r["geometry"] == g)
                                 for g in ("linear", "nonlinear")},
        "iteration_caps": {f"{r['geometry']} cap {r['max_iterations']}": (r["outcome"] if r["outcome"] != "ConvergenceError"
                                                                          else f"ConvergenceError ({r['kind']})")
                           for r in caps},
        "cap_example": next((r["message"] for r in caps if r["outcome"] == "ConvergenceError"), None),
        "cap_example_newton": next((r["message"] for r in caps if r.get("kind") == "Newton"), None),
    }
    return summary


# ----------------------------------------------------------------------------- (e) plate


def run_plate(quick: bool) -> dict:
    import matplotlib.pyplot as plt
    from tests.oracles.morley import model_verdict
    from profilegen.stress.plate import SEED002_TABLE1, edge_displacement_from_ellipse, solve_plate

    P = SEED002_TABLE1
    r_m = P["mean_radius_mm"]
    edge = edge_displacement_from_ellipse(P["semi_major_mm"], P["semi_minor_mm"], mean_radius_mm=r_m,
                                          length_mm=P["length_mm"])
    ratios = np.round(np.linspace(0.05, 0.95, 10 if quick else 19), 4)
    nus = np.array([0.0, 0.15, 0.3, 0.45]) if quick else np.array([0.0, 0.1, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45])
    phi = np.linspace(0.0, 0.5 * math.pi, 721)
    common = dict(thickness_mm=P["thickness_mm"], youngs_modulus_mpa=P["youngs_modulus_mpa"])
    rows = []
    t0 = time.perf_counter()
    for nu in nus:
        for q in ratios:
            r0 = float(q * r_m)
            row = {"table": "analytic", "boss_ratio": float(q), "poisson_ratio": float(nu)}
            vals = {}
            for model in ("consistent", "seed002"):
                field, residual = solve_plate(edge, boss_radius_mm=r0, poisson_ratio=float(nu), model=model, **common)
                s = float(np.max(np.abs(field.surface_stress_mpa(r0, phi)["sigma_r"])))
                m_edge = float(np.max(np.abs(field.moments_n(r_m, phi)[0])))
                m_clamp = float(np.max(np.abs(field.moments_n(r0, phi)[0])))
                vals[model] = (s, field.strain_energy_nmm(), m_edge / m_clamp, residual)
                row.update({f"{model}_clamp_sigma_r_mpa": s, f"{model}_energy_nmm": vals[model][1],
                            f"{model}_edge_Mr_over_clamp_Mr": m_edge / m_clamp, f"{model}_bc_residual": residual})
            row["seed002_sigma_off"] = vals["seed002"][0] / vals["consistent"][0] - 1.0
            row["seed002_energy_off"] = vals["seed002"][1] / vals["consistent"][1] - 1.0
            rows.append(row)
    t_analytic = time.perf_counter() - t0
    # Morley verdict along r0/r_m at ν = 0.3 (Table 1), default meshes (16, 32) and a finer pair
    morley_ratios = [0.02, 0.05, 0.1, 0.2, 0.3, 0.4886, 0.7] if quick else [0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.4886, 0.6, 0.7, 0.8]
    mesh_pairs = [(16, 32)] if quick else [(16, 32), (32, 64)]
    verdicts = []
    for q in morley_ratios:
        for pair in mesh_pairs + ([(64, 128)] if (not quick and q <= 0.1) else []):
            t1 = time.perf_counter()
            v = model_verdict(edge, boss_radius_mm=q * r_m, radial_divisions=pair)
            verdicts.append({"table": "morley", "boss_ratio": q, "poisson_ratio": P["poisson_ratio"],
                             "meshes": f"{pair[0]}/{pair[1]}", "supports": v["supports"],
                             "morley_clamp_sigma_r_mpa": v["morley_clamp_sigma_r_mpa"],
                             "consistent_clamp_sigma_r_mpa": v["consistent_clamp_sigma_r_mpa"],
                             "seed002_clamp_sigma_r_mpa": v["seed002_clamp_sigma_r_mpa"],
                             "consistent_off": v["consistent_off"], "seed002_off": v["seed002_off"],
                             "seed002_energy_off_morley": v["seed002_energy_off"], "time_s": time.perf_counter() - t1})
    elapsed = time.perf_counter() - t0
    write_csv("plate", rows + verdicts)

    shape = (len(nus), len(ratios))
    z_sigma = np.array([r["seed002_sigma_off"] for r in rows]).reshape(shape) * 100
    z_energy = np.array([r["seed002_energy_off"] for r in rows]).reshape(shape) * 100
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.2), constrained_layout=True)
    xe, ye = edges(ratios), edges(nus)
    lim = float(np.nanmax(np.abs(z_sigma)))
    value_map(fig, axes[0], xe, ye, z_sigma, label="seed002 clamp stress vs consistent (%)", cmap="OrRd", vmin=0.0, vmax=lim)
    axes[0].set_title("seed002 variant: error of max |σ_r| at the boss (%)", fontsize=10)
    value_map(fig, axes[1], xe, ye, z_energy, label="seed002 strain energy vs consistent (%)", cmap="magma")
    axes[1].set_title("seed002 variant: error of the strain energy (%)", fontsize=10)
    for ax in axes[:2]:
        ax.plot([P["boss_radius_mm"] / r_m], [P["poisson_ratio"]], "k*", ms=12, label="seed 002 Table 1")
        ax.legend(loc="upper right", fontsize=7)
        ax.set_xlabel("boss ratio r0 / r_m")
        ax.set_ylabel("Poisson's ratio ν")
        for j in range(shape[0]):
            for i in range(0, shape[1], 2):
                z = z_sigma if ax is axes[0] else z_energy
                ax.text(ratios[i], nus[j], f"{z[j, i]:.0f}", ha="center", va="center", fontsize=6,
                        color="white" if ((ax is axes[1] and z[j, i] < 0.6 * np.nanmax(z_energy))
                                          or (ax is axes[0] and z[j, i] > 0.6 * lim)) else "black")
    ax = axes[2]
    for pair, style in zip(mesh_pairs + ([] if quick else [(64, 128)]), ("-", "--", ":")):
        sel = [v for v in verdicts if v["meshes"] == f"{pair[0]}/{pair[1]}"]
        x = [v["boss_ratio"] for v in sel]
        ax.plot(x, [100 * v["seed002_off"] for v in sel], style, color="tab:red", marker="o", ms=4,
                label=f"seed002 vs Morley (meshes {pair[0]}/{pair[1]})")
        ax.plot(x, [100 * abs(v["consistent_off"]) for v in sel], style, color="tab:blue", marker="s", ms=4,
                label=f"|consistent vs Morley| (meshes {pair[0]}/{pair[1]})")
    ax.set_yscale("log")
    ax.set_xlabel("boss ratio r0 / r_m (ν = 0.3)")
    ax.set_ylabel("clamp stress deviation from the extrapolated Morley solution (%)")
    ax.set_title("model_verdict: Morley FE sides with the consistent model\n"
                 "(at small r0/r_m the default meshes do not resolve the boss)", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.suptitle("Cup bottom (seed 002 Table 1 ellipse, zero-mean w(φ)): the seed002 variant vs the consistent "
                 "Kirchhoff model vs a Morley FE plate", fontsize=11)
    save_figure(fig, "plate")

    at_nu = [r for r in rows if abs(r["poisson_ratio"] - 0.3) < 1e-12]
    table1 = min(verdicts, key=lambda v: abs(v["boss_ratio"] - P["boss_radius_mm"] / r_m) + (v["meshes"] != "16/32"))
    summary = {
        "time_s": elapsed,
        "time_analytic_s": t_analytic,
        "seed002_sigma_off_range_pct": [100 * float(np.min(z_sigma / 100)), 100 * float(np.max(z_sigma / 100))],
        "seed002_sigma_off_nu03_pct": {f"{r['boss_ratio']:.3f}": 100 * r["seed002_sigma_off"] for r in at_nu},
        "seed002_energy_off_range_pct": [float(np.min(z_energy)), float(np.max(z_energy))],
        "seed002_edge_Mr_over_clamp_Mr_max": max(r["seed002_edge_Mr_over_clamp_Mr"] for r in rows),
        "consistent_edge_Mr_over_clamp_Mr_max": max(r["consistent_edge_Mr_over_clamp_Mr"] for r in rows),
        "max_bc_residual": max(max(r["consistent_bc_residual"], r["seed002_bc_residual"]) for r in rows),
        "verdicts": {f"{v['boss_ratio']:g} ({v['meshes']})": [v["supports"], round(100 * v["consistent_off"], 3),
                                                               round(100 * v["seed002_off"], 2)] for v in verdicts},
        "verdict_always_consistent": all(v["supports"] == "consistent" for v in verdicts),
        "table1": {"boss_ratio": table1["boss_ratio"], "seed002_off_pct": 100 * table1["seed002_off"],
                   "consistent_off_pct": 100 * table1["consistent_off"]},
    }
    return summary


# ----------------------------------------------------------------------------- main


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="coarser grids, fewer trials (~35 s)")
    ap.add_argument("--only", default=",".join(FAMILIES), help=f"comma-separated subset of {', '.join(FAMILIES)}")
    args = ap.parse_args()
    only = [f.strip() for f in args.only.split(",") if f.strip()]
    unknown = set(only) - set(FAMILIES)
    if unknown:
        ap.error(f"--only: unknown families {sorted(unknown)}; choose from {', '.join(FAMILIES)}")
    import matplotlib

    matplotlib.use("Agg")
    OUT.mkdir(parents=True, exist_ok=True)
    runners = {"envelope": run_envelope, "fitter": run_fitter, "contact": run_contact, "rim": run_rim, "plate": run_plate}
    summary = {"command": "python tests/benchmarks/stability.py" + (" --quick" if args.quick else "")
               + ("" if only == list(FAMILIES) else f" --only {','.join(only)}")}
    t0 = time.perf_counter()
    for fam in only:
        print(f"[{fam}] ...", flush=True)
        summary[fam] = runners[fam](args.quick)
        summary[fam]["command"] = summary["command"]  # the run the family's numbers come from (the file merges runs)
        print(f"[{fam}] {summary[fam]['time_s']:.1f} s", flush=True)
    summary["total_time_s"] = time.perf_counter() - t0
    path = OUT / "stability_summary.json"
    existing = {}
    if path.exists() and only != list(FAMILIES):
        try:
            existing = json.loads(path.read_text())
        except (OSError, ValueError):
            existing = {}
    with atomic_write(path) as f:
        json.dump({**existing, **summary}, f, indent=1, default=float)
    print_summary(summary)


def print_summary(s: dict) -> None:
    print("\n=== stability summary:", s["command"], f"({s['total_time_s']:.0f} s)")
    if "envelope" in s:
        e = s["envelope"]
        print(f"envelope  {e['grid']}: {e['points']} points, {e['time_s']:.0f} s")
        print(f"  outcomes {e['outcomes']}; named errors by stage {e['errors_by_stage']}")
        print(f"  folds {e['folds_range']} (only up to ω* = {e['largest_omega_star_with_folds']}), no-root length up to "
              f"{e['max_no_root_mm']:.3f} mm, deepest false flank {e['false_flank_um_range'][0]:.0f}…"
              f"{e['false_flank_um_range'][1]:.0f} µm, ridges at {e['points_with_ridges']} points; root trace refined at "
              f"{e['points_needing_grid_refinement']} points (up to {e['max_grid_refinements']} doublings); "
              f"UNDETECTED {e['undetected']}")
        print(f"  failures re-run with the design scene's envelope (chord 1e-6 mm): "
              f"{e['failures_passing_with_fine_envelope']} of {e['failures_rechecked_with_fine_envelope']} pass "
              f"{e['failures_passing_with_fine_envelope_at']}; boundary chains up to {e['boundary_chains_max']}")
        for line in e["crashes"]:
            print(f"  CRASH (not a named error): {line}")
        for line in e["fine_envelope_crashes"]:
            print(f"  CRASH with the 1e-6 mm envelope (not a named error): {line}")
        for k, v in e["examples"].items():
            print(f"  e.g. {k}: {v}")
    if "fitter" in s:
        f = s["fitter"]
        print(f"fitter    σ = {f['sigmas_mm'][0]:.0e}…{f['sigmas_mm'][-1]:.0e} mm, {f['time_s']:.0f} s")
        print("  Fourier order picked (noise rule):", f["fourier_noise_pick"])
        print("  Fourier order picked (AICc):      ", f["fourier_aicc_pick"])
        print("  Fourier error at the noise pick (mm):", {k: f"{v:.1e}" for k, v in f["fourier_noise_pick_err_mm"].items()})
        print(f"  Fourier periodicity defect ≤ {f['fourier_defect_max_mm']:.1e} mm")
        for sig in (f"{f['sigmas_mm'][0]:.0e}", f"{f['sigmas_mm'][len(f['sigmas_mm']) // 2]:.0e}", f"{f['sigmas_mm'][-1]:.0e}"):
            print(f"  sine σ={sig}: error by terms", {k: f"{v:.1e}" for k, v in f["sine_err_mm"][sig].items()},
                  "defect", {k: f"{v:.1e}" for k, v in f["sine_defect_mm"][sig].items()})
        print("  domain outcomes:", f["domain_outcomes"])
        for k, v in f["bad_inputs"].items():
            print(f"  {k}: {v}")
        print(f"  UNDETECTED {f['undetected']}")
        for line in f["domain_undetected"]:
            print(f"    {line}")
    if "contact" in s:
        c = s["contact"]
        print(f"contact   {c['problems']} problems, {c['time_s']:.0f} s: naive LP wrong {c['naive_lp_wrong_fraction']:.2f}, "
              f"torque on one point {c['naive_lp_one_point_fraction']:.2f}, φ = 0 {c['naive_lp_phi_zero_fraction']:.2f}; "
              f"of the wrong ones flagged {c['naive_lp_flagged_fraction_of_wrong']:.2f}")
        print(f"  UNDETECTED naive-LP answers {c['naive_lp_undetected']} ({c['naive_lp_undetected_fraction']:.2f}); their "
              f"reported complementarity residual {c['undetected_reported_residual_range']}, θ_min/τ ≥ "
              f"{c['undetected_theta_min_over_tau_min']}")
        print(f"  Lemke vs QP max |ΔF|/max F {c['lemke_qp_max_force_diff']:.1e}; S refused (ContactError) from κ = "
              f"{c['refused_kappa_min']:.0e}, solved up to κ = {c['solved_kappa_max']:.0e}; other Lemke / QP failures "
              f"{c['lemke_failures']} / {c['qp_failures']}")
        for k, v in c["by_kappa"].items():
            print(f"  κ {k}: refused {v['refused']:.2f}, naive LP wrong {v['lp_wrong'] if v['lp_wrong'] is None else round(v['lp_wrong'], 2)}, "
                  f"undetected {v['lp_undetected'] if v['lp_undetected'] is None else round(v['lp_undetected'], 2)}, "
                  f"Lemke–QP worst {v['lemke_qp_worst'] if v['lemke_qp_worst'] is None else format(v['lemke_qp_worst'], '.0e')}")
        for k, v in c["iteration_caps"].items():
            print(f"  {k}: {v}")
    if "rim" in s:
        r = s["rim"]
        print(f"rim       {r['solves']} FEM solves, {r['time_s']:.0f} s; outcomes {r['outcomes']}; every answer warns: "
              f"{r['all_answers_carry_wrap_warning']}")
        print("  wrap at δb = 0 by mesh:", {k: f"{v:.2f}°" for k, v in r["wrap_at_zero_by_mesh"].items()})
        print("  wrap range over δb:", {k: f"{v[0]:.1f}…{v[1]:.1f}°" for k, v in r["wrap_range_deg"].items()})
        for g, d in r["sensitivity_64"].items():
            for k, v in d.items():
                print(f"  {g} 4×64, δb {k}: wrap {v['wrap_deg'][0]:.2f} / {v['wrap_deg'][1]:.2f} / {v['wrap_deg'][2]:.2f}°, "
                      f"max |Δω| {v['max_domega_um']:.4f} µm")
        print("  largest swing of the active-set size between re-linearisations:", r["max_active_set_swing"])
        print("  iteration caps:", r["iteration_caps"])
        print("  e.g.", r["cap_example"])
        print("  e.g.", r["cap_example_newton"])
    if "plate" in s:
        p = s["plate"]
        print(f"plate     {p['time_s']:.0f} s: seed002 clamp-stress error {p['seed002_sigma_off_range_pct'][0]:.1f}…"
              f"{p['seed002_sigma_off_range_pct'][1]:.1f} % over the map, energy {p['seed002_energy_off_range_pct'][0]:.1f}…"
              f"{p['seed002_energy_off_range_pct'][1]:.1f} %")
        print("  at ν = 0.3 by r0/r_m (%):", {k: f"{v:.1f}" for k, v in p["seed002_sigma_off_nu03_pct"].items()})
        print(f"  M_r(r_m)/max M_r(r0): seed002 up to {p['seed002_edge_Mr_over_clamp_Mr_max']:.3f}, consistent "
              f"{p['consistent_edge_Mr_over_clamp_Mr_max']:.1e}; bc residual ≤ {p['max_bc_residual']:.1e}")
        print("  Morley verdicts [supports, consistent off %, seed002 off %]:", p["verdicts"])
        print(f"  Table 1 (r0/r_m = {p['table1']['boss_ratio']:.3f}): seed002 {p['table1']['seed002_off_pct']:.1f} %, "
              f"consistent {p['table1']['consistent_off_pct']:.4f} %")


if __name__ == "__main__":
    main()
