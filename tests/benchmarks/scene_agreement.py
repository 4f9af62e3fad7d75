"""Design scene against verify scene: the numbers of the design sheet side by side, and the
largest normal distance between the two CS tooth-space outlines (issue 28, item 1).

    python tests/benchmarks/scene_agreement.py                      # seed000_csf40 and csf32_100, both scenes
    python tests/benchmarks/scene_agreement.py --sets seed000_csf40  # one set
    python tests/benchmarks/scene_agreement.py --dirs OUT_A OUT_B    # two `profilegen design --out` folders

Each scene runs one after the other (a verify run is ~40-60 s on a busy 2-core machine). The outline
distance is exact: the tooth space of ``profile_fit.json`` (arcs and lines, fillets included) of A,
sampled every 0.5 µm, against B's elements (point-to-arc and point-to-segment distances), and the
other way; the larger is printed. Beside it: the design scene's rim error estimate (the coarse
cup against its own coarser companion) and both fits' largest deviation from their envelopes.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

SETS = ("seed000_csf40", "csf32_100")


def _elements(space: dict) -> list[dict]:
    return list(space["elements"])


def _sample(el: dict, step_mm: float) -> np.ndarray:
    a, b = np.asarray(el["start_mm"], float), np.asarray(el["end_mm"], float)
    n = max(2, int(math.ceil(el["length_mm"] / step_mm)) + 1)
    if el["type"] == "line":
        t = np.linspace(0.0, 1.0, n)[:, None]
        return a + t * (b - a)
    c = np.asarray(el["centre_mm"], float)
    t0 = math.atan2(a[1] - c[1], a[0] - c[0])
    t = t0 + np.radians(el["sweep_deg"]) * np.linspace(0.0, 1.0, n)
    return c + el["radius_mm"] * np.column_stack([np.cos(t), np.sin(t)])


def _distance(points: np.ndarray, el: dict) -> np.ndarray:
    a, b = np.asarray(el["start_mm"], float), np.asarray(el["end_mm"], float)
    if el["type"] == "line":
        d = b - a
        t = np.clip(((points - a) @ d) / (d @ d), 0.0, 1.0)
        return np.linalg.norm(points - (a + t[:, None] * d), axis=1)
    c, r = np.asarray(el["centre_mm"], float), float(el["radius_mm"])
    t0 = math.atan2(a[1] - c[1], a[0] - c[0])
    sweep = math.radians(el["sweep_deg"])
    ang = np.arctan2(points[:, 1] - c[1], points[:, 0] - c[0])
    rel = np.mod((ang - t0) * np.sign(sweep), 2 * math.pi)  # along the sweep from the start
    on = rel <= abs(sweep)
    radial = np.abs(np.linalg.norm(points - c, axis=1) - r)
    ends = np.minimum(np.linalg.norm(points - a, axis=1), np.linalg.norm(points - b, axis=1))
    return np.where(on, radial, ends)


def outline_distance_mm(space_a: dict, space_b: dict, step_mm: float = 5e-4) -> float:
    """The largest distance of either tooth-space outline from the other (mm)."""
    worst = 0.0
    for p, q in ((space_a, space_b), (space_b, space_a)):
        pts = np.vstack([_sample(el, step_mm) for el in _elements(p)])
        d = np.min(np.array([_distance(pts, el) for el in _elements(q)]), axis=0)
        worst = max(worst, float(d.max()))
    return worst


def numbers(folder: Path) -> dict:
    """The sheet's numbers from a ``profilegen design --out`` folder."""
    d = json.loads((folder / "design.json").read_text())
    fit = json.loads((folder / "profile_fit.json").read_text())
    stress_path = folder / "stress.json"
    stress = json.loads(stress_path.read_text()) if stress_path.exists() else {"checks": []}
    cs = d["circular_spline"]
    out = {"CS tip Ø (mm)": 2 * cs["tip_radius_mm"], "CS root Ø (mm)": 2 * cs["root_radius_mm"]}
    flank = fit["fits"][fit["method"]]["chain"]["elements"]
    arcs = 0
    for el in flank:
        if el["type"] == "arc":
            arcs += 1
            out[f"R{arcs} (mm)"] = el["radius_mm"]
        else:
            out["line length (mm)"] = el["length_mm"]
    face = d.get("face")
    out["design section z (mm)"] = None if face is None else face["design_section_z_mm"]
    out["FS taper (µm/mm)"] = None if face is None or face["taper_mm_per_mm"] is None else face["taper_mm_per_mm"] * 1e3
    mod = None if face is None else face.get("modification")
    out["backlash, face (µm)"] = (None if face is None else
                                  (mod["max_backlash_mm"] if mod else face["max_backlash_mm"]) * 1e3)
    out["backlash, fit (µm)"] = fit["max_backlash_mm"] * 1e3 if fit["max_backlash_mm"] is not None else None
    c = d.get("contact")
    if c:
        out["largest tooth force, rated (N)"] = c["max_tooth_force_n"][0]
        out["teeth per zone, rated"] = c["teeth_in_contact_per_zone"][0]
    for ch in stress["checks"]:
        out[f"{ch['name']} safety"] = ch["value"]
    stages = d["stages"]
    out["_rim_error_mm"] = stages["rim"]["error_estimate"]
    out["_fit_error_mm"] = stages["arcfit"]["error_estimate"]
    out["_time_s"] = d["time_s"]
    out["_space"] = fit["space"]
    return out


def _fmt(v) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return f"{v:.4f}" if abs(v) >= 1 or v == 0 else f"{v:.4g}"
    return str(v)


def compare(a: Path, b: Path, labels=("A", "B")) -> float:
    na, nb = numbers(a), numbers(b)
    print(f"{'':34s} {labels[0]:>14s} {labels[1]:>14s} {'difference':>12s}")
    for key in na:
        if key.startswith("_"):
            continue
        va, vb = na[key], nb.get(key)
        diff = (va - vb) if isinstance(va, (int, float)) and isinstance(vb, (int, float)) else None
        print(f"{key:34s} {_fmt(va):>14s} {_fmt(vb):>14s} {_fmt(diff):>12s}")
    dist = outline_distance_mm(na["_space"], nb["_space"])
    print(f"{'CS tooth-space outlines apart (µm)':34s} {dist * 1e3:>14.3f}")
    rim = "none (the model itself)" if na["_rim_error_mm"] is None else f"{na['_rim_error_mm'] * 1e3:.3f} µm"
    print(f"{labels[0]} rim error estimate {rim}, fit deviation "
          f"{na['_fit_error_mm'] * 1e3:.3f} µm; {labels[1]} fit deviation {nb['_fit_error_mm'] * 1e3:.3f} µm; "
          f"design() time {na['_time_s']:.1f} / {nb['_time_s']:.1f} s")
    return dist


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", nargs="*", default=list(SETS))
    ap.add_argument("--dirs", nargs=2, metavar=("A", "B"))
    ap.add_argument("--scenes", nargs=2, default=["design", "verify"], metavar=("A", "B"),
                    help="the two scenes compared (default: design verify)")
    args = ap.parse_args(argv)
    if args.dirs:
        compare(Path(args.dirs[0]), Path(args.dirs[1]))
        return 0
    import profilegen as pg

    root = Path(__file__).resolve().parents[2] / "profiles"
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.sets:
            gs = pg.load_gearset(root / f"{name}.toml")
            folders = []
            for scene in args.scenes:
                t0 = time.perf_counter()
                result = pg.design(gs, scene=scene)
                out = Path(tmp) / f"{name}_{scene}"
                pg.write_design(result, out, figure=False)
                folders.append(out)
                print(f"{name} {scene}: {time.perf_counter() - t0:.1f} s", file=sys.stderr)
            print(f"\n== {name}: {args.scenes[0]} scene (A) against {args.scenes[1]} scene (B)")
            compare(*folders, labels=tuple(args.scenes))
    return 0


if __name__ == "__main__":
    sys.exit(main())
