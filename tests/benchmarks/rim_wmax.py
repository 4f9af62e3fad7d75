"""Which modelling choice could make ω_max exceed w0? (seed 004: 0.553 mm for w0 = 0.5 mm)

    python tests/benchmarks/rim_wmax.py

Default gear set (r_m = 48.95 mm, δ = 0.9 mm, w0 = 0.5 mm). Every row is a 2D rim model
pressed onto a wave-generator contour; printed: ω at the major axis on the neutral line and
at the bore, ω at the minor axis, max |υ| and where — next to the seed's 0.553 / −0.557 /
0.293 mm. Writes export/bench/rim_wmax.csv. The cone lever at the end is arithmetic, not a
simulation: with straight generators (the cup's classical assumption) ω grows linearly with
the distance z from the diaphragm, so ω_max/w0 = z_read / z_contact.
"""

from __future__ import annotations

import csv
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.rim import solve_ring, toothed_quarter_mesh  # noqa: E402
from profilegen.geometry.wavegen import CosineCam, EllipticalCam, from_gearset  # noqa: E402

SEED = {"omega_major_mm": 0.553, "omega_minor_mm": -0.557, "upsilon_max_mm": 0.293}


def main() -> None:
    gs = pg.load_gearset(pg.default_gearset_path())
    g = gs.gear
    w0 = gs.deflection_mm
    r_bore = g.neutral_radius_mm - g.rim_thickness_mm / 2
    tooth = pg.tooth_from_gearset(gs)
    with_bearing = from_gearset(gs.with_values({"wave_generator.bearing_thickness_mm": 5.0}))
    two_rollers = from_gearset(gs.with_values({"wave_generator.contour": "rollers", "wave_generator.roller_count": 2,
                                               "wave_generator.roller_radius_mm": 10.0}))
    cases = [
        ("offset ellipse (h = 0), perimeter = bore's; linear flat ring", from_gearset(gs), "linear", None),
        ("same; nonlinear flat ring (the design tier)", from_gearset(gs), "nonlinear", None),
        ("same; nonlinear toothed rim (the verify tier)", from_gearset(gs), "nonlinear", "toothed"),
        ("offset ellipse with a 5 mm flex bearing; nonlinear", with_bearing, "nonlinear", None),
        ("ellipse a = r + w0, b = r − w0 (perimeter 8 µm longer); nonlinear",
         EllipticalCam(r_bore + w0, r_bore - w0), "nonlinear", None),
        ("cosine cam r + w0 cos 2θ (ring theory's contour); nonlinear", CosineCam(r_bore, w0), "nonlinear", None),
        ("two rollers R = 10 mm; nonlinear", two_rollers, "nonlinear", None),
    ]
    rows = []
    for name, contour, geometry, mesh in cases:
        kw = {}
        if mesh == "toothed":
            kw["mesh"] = toothed_quarter_mesh(tooth, g.rim_thickness_mm, rim_layers=2, tooth_layers=2, per_pitch=16)
        res = solve_ring(gs, contour=contour, geometry=geometry, **kw)
        k = int(np.argmax(np.abs(res.upsilon_mm)))
        row = {
            "model": name,
            "omega_major_mm": float(res.omega_mm[0]),
            "bore_omega_major_mm": float(res.bore_omega_mm[0]),
            "omega_minor_mm": float(res.omega_mm[-1]),
            "upsilon_max_mm": float(abs(res.upsilon_mm[k])),
            "upsilon_max_at_deg": math.degrees(res.phi_rad[k]),
            "wrap_deg": res.contact_angle_deg,
        }
        rows.append(row)
        print(f"{name:70s} ω(0) {row['omega_major_mm']:.6f} (bore {row['bore_omega_major_mm']:.6f})  "
              f"ω(90°) {row['omega_minor_mm']:+.6f}  |υ|max {row['upsilon_max_mm']:.6f} at "
              f"{row['upsilon_max_at_deg']:.1f}°  wrap {row['wrap_deg']:.1f}°", flush=True)
    print(f"{'seed 004 (3D cup, Abaqus)':70s} ω(0) {SEED['omega_major_mm']:.3f}            "
          f"ω(90°) {SEED['omega_minor_mm']:+.3f}     |υ|max {SEED['upsilon_max_mm']:.3f}")
    scale = np.mean([SEED["omega_major_mm"] / w0, -SEED["omega_minor_mm"] / w0, 2 * SEED["upsilon_max_mm"] / w0])
    print(f"seed / ring theory: ω(0) {SEED['omega_major_mm'] / w0:.3f}, ω(90°) {-SEED['omega_minor_mm'] / w0:.3f}, "
          f"2|υ|max {2 * SEED['upsilon_max_mm'] / w0:.3f} — one common factor ≈ {scale:.3f}")
    print(f"cone lever: ω ∝ z from the diaphragm → the seed's section lies {100 * (SEED['omega_major_mm'] / w0 - 1):.1f} % "
          f"farther from the diaphragm than the cam's contact line (e.g. {80 * (1 - w0 / SEED['omega_major_mm']):.1f} mm "
          "inboard of the open end on an 80 mm cup)")
    out = ROOT / "export" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "rim_wmax.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {out / 'rim_wmax.csv'}")


if __name__ == "__main__":
    main()
