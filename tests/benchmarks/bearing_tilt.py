"""The wave-generator bearing under the 3D cup (issue 28 item 4a): the rigid band against the
outer race on its ball row, for every bundled gear set.

Part 1 (``--part cup``, ~1-3 s a run): the cup tier alone at the verify scene's mesh (2 mm,
16 angles, exact gap, nonlinear) under each race model of :data:`profilegen.rim.cup.bearing.
CUP_TIER_RACES` — ``rigid`` (the bore pressed onto the contour over the bearing width, the
model before), ``ring`` (the race: tilt with its ring stiffness, section free to warp axially,
bent onto Hertz balls — the cup tier's default), ``held`` (the tilt's upper bound: the race held
axially), ``free`` (its lower bound) — ω at the major/minor axis at both face ends, the race's
tilt and the ball row's force at the major axis.

``--part narrow``: the independent check's model (issue 28: "a 2 mm band free to tilt", ω major
0.420/0.588 mm at z = 50/70 on seed000_csf40), the bearing narrowed to 2 mm.

Part 2 (``--part scenes``): ``profilegen design NAME --scene S`` in a subprocess per set and
race model (the model set by :data:`~profilegen.rim.cup.bearing.CUP_TIER_RACE`), its
design.json read: ω at the face ends, the design section, the FS taper, crowning and radial shift, the
backlash and interference with the modification, the tooth-ring safety factors, K1 (sliced and
one section) against the catalogue, the verdict. One run at a time (20-190 s each on a loaded
2-core machine).

    python tests/benchmarks/bearing_tilt.py --part cup
    python tests/benchmarks/bearing_tilt.py --part narrow --sets seed000_csf40   # issue 28's 2 mm band
    python tests/benchmarks/bearing_tilt.py --part scenes --races rigid ring --out /tmp/bearing_tilt
    python tests/benchmarks/bearing_tilt.py --part table --races rigid ring --out /tmp/bearing_tilt   # reread only
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

SETS = ("seed000_csf40", "seed001_shf25", "seed002_short_cup", "csf32_100", "default")


def cup_part(sets, races) -> None:
    import numpy as np

    from profilegen.gearset import load_gearset, resolve_gearset
    from profilegen.rim.cup import CupGeometry, press_cup
    from profilegen.rim.cup.bearing import cup_tier_race
    from profilegen.rim.stage import RIM_TIERS
    from profilegen.geometry.wavegen import from_gearset

    tier = RIM_TIERS["cup3d"]
    print(f"cup tier at the verify mesh: {tier.element_mm:g} mm, {tier.angles} angles, {tier.gap} gap, nonlinear")
    print(f"{'set':18s} {'race':6s} {'ω major dia/open (mm)':>22s} {'ω minor dia/open (mm)':>23s} "
          f"{'tilt φ=0 (mrad)':>15s} {'balls φ=0 (N)':>13s} {'time (s)':>8s}")
    for name in sets:
        gs = load_gearset(resolve_gearset(name))
        g = CupGeometry.from_gearset(gs)
        contour = from_gearset(gs)
        lo, hi = g.ring_span_mm
        for model in races:
            race = cup_tier_race(gs, g, model)
            t0 = time.perf_counter()
            c = press_cup(g, contour=contour, angles=tier.angles, element_mm=tier.element_mm, layers=tier.layers,
                          gap=tier.gap, nonlinear=True, race=race)
            dt = time.perf_counter() - t0
            d = c.deformation
            om = [float(d.omega(np.array([p]), np.array([z]))[0]) for p in (0.0, 0.5 * math.pi) for z in (lo, hi)]
            tilt = f"{1e3 * c.race_tilt_rad[0]:.2f}" if race is not None else "-"
            balls = f"{c.ball_force_n[0]:.0f}" if race is not None else "-"
            print(f"{name:18s} {model:6s} {om[0]:10.4f} {om[1]:10.4f}  {om[2]:10.4f} {om[3]:10.4f}  {tilt:>15s} "
                  f"{balls:>13s} {dt:8.1f}")


def narrow_part(sets) -> None:
    """The independent check of issue 28 (a 2 mm band free to tilt): the bearing narrowed to 2 mm,
    as a rigid band and as a stress-free race free to tilt on rigid balls, at the verify mesh."""
    import numpy as np

    from profilegen.gearset import load_gearset, resolve_gearset
    from profilegen.rim.cup import BearingRace, CupGeometry, press_cup
    from profilegen.rim.stage import RIM_TIERS
    from profilegen.geometry.wavegen import from_gearset

    tier = RIM_TIERS["cup3d"]
    for name in sets:
        gs = load_gearset(resolve_gearset(name))
        g = CupGeometry.from_gearset(gs, bearing_width_mm=2.0)
        lo, hi = g.ring_span_mm
        for label, race in (("2 mm rigid band", None), ("2 mm band free to tilt",
                                                         BearingRace.from_gearset(gs, g, tilt="free", prestress=False,
                                                                                  hertz=False))):
            c = press_cup(g, contour=from_gearset(gs), angles=tier.angles, element_mm=tier.element_mm,
                          layers=tier.layers, gap=tier.gap, nonlinear=True, race=race)
            om = [float(c.deformation.omega(np.array([0.0]), np.array([z]))[0]) for z in (lo, hi)]
            print(f"{name:18s} {label:24s} ω major at z = {lo:g} / {hi:g}: {om[0]:.4f} / {om[1]:.4f} mm")


def run_scene(name: str, scene: str, race: str, out: Path) -> float:
    code = ("import sys, profilegen.rim.cup.bearing as b; b.CUP_TIER_RACE = sys.argv[1]; "
            "from profilegen.cli import main; raise SystemExit(main(sys.argv[2:]))")
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", code, race, "design", str(ROOT / "profiles" / f"{name}.toml"),
                           "--scene", scene, "--out", str(out), "-q"], capture_output=True, text=True)
    (out.parent / f"{out.name}.log").write_text(proc.stdout + proc.stderr)
    return time.perf_counter() - t0


def row(folder: Path) -> dict:
    d = json.loads((folder / "design.json").read_text())
    secs = {s["where"]: s for s in d["rim"]["cup"]["sections"]}
    face = d.get("face") or {}
    mod = face.get("modification") or {}
    safety = (d.get("stress") or {}).get("safety", {})
    tor = (d.get("contact") or {}).get("torsional") or {}
    cat = tor.get("model_over_catalogue") or {}
    one = tor.get("one_section") or {}
    k1 = tor.get("k1_nm_per_rad")
    one_cat = (one.get("k1_nm_per_rad") / k1 * cat["K1_nm_per_rad"]) if one.get("k1_nm_per_rad") and k1 and \
        cat.get("K1_nm_per_rad") else None
    return {"ω dia": secs["diaphragm end"]["omega_major_mm"], "ω open": secs["open end"]["omega_major_mm"],
            "z design": face.get("design_section_z_mm"), "taper µm/mm": 1e3 * (mod.get("taper_mm_per_mm") or 0.0),
            "crown µm": 1e3 * (mod.get("crowning_mm") or 0.0), "shift µm/mm": 1e3 * (mod.get("shift_mm_per_mm") or 0.0),
            "backlash µm": 1e3 * mod["max_backlash_mm"] if mod.get("max_backlash_mm") is not None else None,
            "interf µm": 1e3 * (mod.get("max_interference_mm") or 0.0),
            "SF yield": safety.get("tooth ring yield"), "SF fatigue": safety.get("tooth ring fatigue"),
            "K1/cat": cat.get("K1_nm_per_rad"), "K1 1-sec/cat": one_cat, "verdict": d["verdict"]["status"],
            "failed": "; ".join(f.split(":")[0] for f in d["verdict"]["failures"])}


def table(sets, races, scene: str, out: Path) -> None:
    keys = None
    for name in sets:
        for race in races:
            folder = out / f"{name}-{scene}-{race}"
            if not (folder / "design.json").exists():
                print(f"{name:18s} {race:6s} (no design.json in {folder})")
                continue
            r = row(folder)
            if keys is None:
                keys = list(r)
                print(f"{'set':18s} {'race':6s} " + " ".join(f"{k:>12s}" for k in keys[:-1]) + "  failed")
            cells = []
            for k in keys[:-1]:
                v = r[k]
                cells.append(f"{v:12.4g}" if isinstance(v, float) else f"{str(v):>12s}")
            print(f"{name:18s} {race:6s} " + " ".join(cells) + f"  {r['failed']}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--part", choices=("cup", "narrow", "scenes", "table"), default="cup")
    ap.add_argument("--sets", nargs="+", default=list(SETS))
    ap.add_argument("--races", nargs="+", default=None, help="default: all four (cup), rigid and ring (scenes)")
    ap.add_argument("--scene", default="verify")
    ap.add_argument("--out", type=Path, default=Path("/tmp/bearing_tilt"))
    a = ap.parse_args(argv)
    if a.part == "cup":
        cup_part(a.sets, a.races or ["rigid", "ring", "held", "free"])
        return
    if a.part == "narrow":
        narrow_part(a.sets)
        return
    races = a.races or ["rigid", "ring"]
    if a.part == "scenes":
        a.out.mkdir(parents=True, exist_ok=True)
        for name in a.sets:
            for race in races:
                dt = run_scene(name, a.scene, race, a.out / f"{name}-{a.scene}-{race}")
                print(f"ran {name} {a.scene} race={race}: {dt:.1f} s", flush=True)
    table(a.sets, races, a.scene, a.out)


if __name__ == "__main__":
    main()
