"""Speed against accuracy of the whole pipeline: one point per scene.

``scene_benchmark(gearset)`` runs every scene (``sketch``, ``design``, ``verify``) on a gear
set, times each (median wall time of ``repeats`` runs) and measures its answer against a
converged reference: the most detailed scene run with a ten times finer envelope chord.
What is compared is what a designer takes away:

* ``flank_error_mm``: the symmetric Hausdorff distance between the scene's conjugate CS
  flank (the swept boundary of one space) and the reference's — the deformation model,
  the envelope's chord and everything upstream show up here;
* ``profile_error_mm``: the same for the fitted arc–line–arc CS space (the CAD profile);
* ``stiffness_rel``, ``tooth_force_rel``: the loaded contact at the rated torque (secant
  stiffness, largest tooth force), relative to the reference (None where a scene runs no
  contact);
* ``min_safety_rel``: the lowest safety factor of the stress checks, relative.

``write_scene_benchmark(rows, out_dir)`` writes ``pipeline.csv`` and ``pipeline.png`` (time
against flank error, log–log, one point per scene; the stage times stacked per scene).
``profilegen bench [--quick]`` runs both; ``--quick`` leaves out ``verify`` (the reference
is then the ``design`` scene refined).

Benchmark code, not product code: it lives in the source checkout (``tests/benchmarks/``, was
``profilegen/bench.py``) and ``profilegen bench`` loads it from there
(:func:`profilegen.bench.load_benchmark`), beside the per-stage study (``stages.py``).
"""

from __future__ import annotations

import csv
import statistics
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

__all__ = ["scene_benchmark", "write_scene_benchmark"]


_DENSIFY = 20  # steps per segment: shapely.hausdorff_distance(..., densify=0.05)


def _hausdorff_mm(a: np.ndarray, b: np.ndarray) -> float:
    """``shapely.hausdorff_distance(LineString(a), LineString(b), densify=0.05)``: GEOS's discrete
    Hausdorff distance — the largest distance from a point of either line (its vertices and the
    20 equal steps along each segment, p0 + i·(p1 − p0)/20) to the other line — with the
    distances from an STR tree of the other line's segments; GEOS measures every point against
    every segment (4 pairs of lines of ~10^3-10^4 vertices: 19 of `profilegen bench --quick`'s
    40 s on a busy machine). Same points, same point-to-segment distances."""
    return max(_oriented_mm(np.asarray(a, float), np.asarray(b, float)),
               _oriented_mm(np.asarray(b, float), np.asarray(a, float)))


def _oriented_mm(p: np.ndarray, q: np.ndarray) -> float:
    import shapely

    steps = np.arange(_DENSIFY, dtype=float)[None, :, None]
    start, delta = p[:-1, None, :], ((p[1:] - p[:-1]) / _DENSIFY)[:, None, :]
    points = np.vstack([(start + steps * delta).reshape(-1, 2), p[-1:]])
    if len(q) == 1:
        return float(np.max(np.hypot(*(points - q[0]).T)))
    tree = shapely.STRtree(shapely.linestrings(np.stack([q[:-1], q[1:]], axis=1)))
    _, dist = tree.query_nearest(shapely.points(points), return_distance=True, all_matches=False)
    return float(dist.max())


def _rel(value, reference) -> float | None:
    if value is None or reference is None or reference == 0:
        return None
    return float(abs(value / reference - 1.0))


def _rated(design) -> tuple[float | None, float | None]:
    c = design.contact
    if c is None:
        return None, None
    return float(c.secant_stiffness_nm_per_rad[0]), float(c.cases[0].max_tooth_force_n)


def _min_safety(design) -> float | None:
    return None if design.stress is None else design.stress.min_safety


def scene_benchmark(gearset, *, scenes=("sketch", "design", "verify"), repeats: int = 3,
                    progress=None) -> list[dict]:
    """One row per scene (see the module docstring) plus the reference's row (``scene`` =
    "reference"). ``progress(text)`` is called before each run."""
    from profilegen.pipeline.design import SCENES, design

    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 1:
        raise ValueError(f"repeats = {repeats!r}: must be a whole number ≥ 1")
    unknown = [s for s in scenes if s not in SCENES]
    if unknown or not scenes:
        raise ValueError(f"scenes = {scenes!r}: each must be one of {', '.join(SCENES)}")
    step = progress or (lambda text: None)
    finest = SCENES[scenes[-1]]
    ref_scene = replace(finest, chord_tol_mm=finest.chord_tol_mm / 10.0, contact=True)
    step(f"reference: {finest.name} scene, chord {ref_scene.chord_tol_mm:g} mm")
    t0 = time.perf_counter()
    ref = design(gearset, scene=ref_scene, contact=True)
    ref_time = time.perf_counter() - t0
    ref_flank = ref.envelope.flank["boundary"]
    ref_space = ref.profile.space.sample(1e-6)
    ref_k, ref_f = _rated(ref)
    ref_safety = _min_safety(ref)
    rows = []
    for name in scenes:
        times, result = [], None
        for k in range(repeats):
            step(f"{name} scene, run {k + 1} of {repeats}")
            t0 = time.perf_counter()
            result = design(gearset, scene=name)
            times.append(time.perf_counter() - t0)
        k_rated, f_rated = _rated(result)
        rows.append({
            "scene": name,
            "time_s": statistics.median(times),
            "repeats": repeats,
            "flank_error_mm": _hausdorff_mm(result.envelope.flank["boundary"], ref_flank),
            "profile_error_mm": _hausdorff_mm(result.profile.space.sample(1e-6), ref_space),
            "stiffness_rel": _rel(k_rated, ref_k),
            "tooth_force_rel": _rel(f_rated, ref_f),
            "min_safety_rel": _rel(_min_safety(result), ref_safety),
            "stages_s": {s.stage: s.time_s for s in result.stages},
        })
    rows.append({"scene": "reference", "time_s": ref_time, "repeats": 1, "flank_error_mm": 0.0,
                 "profile_error_mm": 0.0, "stiffness_rel": 0.0, "tooth_force_rel": 0.0, "min_safety_rel": 0.0,
                 "stages_s": {s.stage: s.time_s for s in ref.stages},
                 "reference": f"{finest.name} scene, envelope chord {ref_scene.chord_tol_mm:g} mm, contact on"})
    return rows


def write_scene_benchmark(rows: list[dict], out_dir, *, title: str = "") -> list[Path]:
    """``pipeline.csv`` and ``pipeline.png`` in ``out_dir`` (see the module docstring)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    # by earliest position in any row; ties in first-seen order (a set's order follows string hashing)
    stages = sorted(dict.fromkeys(s for r in rows for s in r["stages_s"]), key=lambda s: min(
        list(r["stages_s"]).index(s) if s in r["stages_s"] else 99 for r in rows))
    fields = ["scene", "time_s", "repeats", "flank_error_mm", "profile_error_mm", "stiffness_rel",
              "tooth_force_rel", "min_safety_rel"] + [f"stage_{s}_s" for s in stages]
    with open(out / "pipeline.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({**r, **{f"stage_{s}_s": r["stages_s"].get(s, "") for s in stages}})

    fig = Figure(figsize=(12.0, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    ax, bx = fig.subplots(1, 2)
    scenes = [r for r in rows if r["scene"] != "reference"]
    for r in scenes:
        err = max(r["flank_error_mm"], 1e-9) * 1e3
        ax.loglog(r["time_s"], err, "o", ms=8)
        extra = "" if r["tooth_force_rel"] is None else f"\ntooth force {100 * r['tooth_force_rel']:.1f} %"
        ax.annotate(f"{r['scene']}: {r['time_s']:.1f} s, {err:.3g} µm{extra}", (r["time_s"], err),
                    textcoords="offset points", xytext=(8, 4), fontsize=8)
    ax.set_xlabel("wall time of the whole pipeline (s, median)")
    ax.set_ylabel("CS flank vs the reference (µm, Hausdorff)")
    ax.set_title("speed against accuracy, one point per scene", fontsize=9)
    ax.grid(True, which="both", color="0.9", lw=0.5)
    lo = min(r["time_s"] for r in scenes)
    ax.set_xlim(lo / 2, 4 * max(r["time_s"] for r in scenes))
    bottom = np.zeros(len(rows))
    x = np.arange(len(rows))
    for s in stages:
        v = np.array([r["stages_s"].get(s, 0.0) for r in rows])
        bx.bar(x, v, bottom=bottom, label=s)
        bottom += v
    bx.set_xticks(x, [r["scene"] for r in rows])
    bx.set_ylabel("stage time (s)")
    bx.legend(fontsize=7, ncol=2, loc="upper left")
    bx.set_ylim(0, 1.35 * float(bottom.max()))
    bx.set_title("where the time goes", fontsize=9)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.savefig(out / "pipeline.png", dpi=120)
    return [out / "pipeline.csv", out / "pipeline.png"]


def format_rows(rows: list[dict]) -> str:
    """The rows as a plain-text table (for the command line)."""
    def pct(x):
        return "—" if x is None else f"{100 * x:.2f} %"

    lines = [f"{'scene':10s} {'time':>9s} {'flank err':>11s} {'profile err':>12s} {'stiffness':>10s} "
             f"{'tooth F':>9s} {'min safety':>10s}"]
    for r in rows:
        lines.append(f"{r['scene']:10s} {r['time_s']:8.2f}s {r['flank_error_mm'] * 1e3:9.4f}µm "
                     f"{r['profile_error_mm'] * 1e3:10.4f}µm {pct(r['stiffness_rel']):>10s} "
                     f"{pct(r['tooth_force_rel']):>9s} {pct(r['min_safety_rel']):>10s}")
    return "\n".join(lines)
