"""The sliced torsional curve's separations: exact (``face_curve.slice_gap_shifts``, each FS
material point's signed distance to the CS outline in the slice's section) against the
first-order shift −n·Δp it used before (the coning's ``face_load.coning_gap_shifts`` plus the
modification's ``flank_offset_gap_mm`` and ``radial_offset_gap_mm``), for one gear set in the
verify scene: each slice's first contact under both, and the largest difference at the points
within 30 µm of contact.

    python tests/benchmarks/slice_separations.py [GEARSET] [--slices 5]

(default tests/corpus/csf32_50.toml: a ratio-50 set whose face stage shifts the FS tooth radially
by up to −147 µm)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.contact.face_curve import flank_offset_gap_mm, radial_offset_gap_mm, slice_gap_shifts  # noqa: E402
from research.face_load import coning_gap_shifts  # noqa: E402
from profilegen.contact.inputs import ContactInput  # noqa: E402
from profilegen.contact.points import contact_points  # noqa: E402
from profilegen.face.modification import radial_shift, thickness_change  # noqa: E402

ARCMIN = 180.0 * 60.0 / np.pi


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("gearset", nargs="?", default=str(ROOT / "tests" / "corpus" / "csf32_50.toml"))
    ap.add_argument("--slices", type=int, default=5)
    args = ap.parse_args(argv)
    gs = pg.load_gearset(args.gearset)
    d = pg.design(gs, scene="verify", contact=False, stress=False)
    inp = ContactInput.from_design(d)
    mod, zd = d.face.modification, d.face.design_section_z_mm
    b, zc = gs.cup.face_width_mm, gs.cup.length_mm
    print(f"{gs.name}: design section z = {zd:g} mm; shift {mod.shift_mm_per_mm * 1e3:.3g} µm/mm, taper "
          f"{mod.taper_mm_per_mm * 1e3:.3g} µm/mm, crowning {mod.crowning_mm * 1e3:.3g} µm (midpoint slices)")
    for side in (1, -1):
        pts = contact_points(inp, side=side)
        z, exact = slice_gap_shifts(inp, pts, args.slices, cup=d.rim.cup, design_z_mm=zd, modification=mod)
        cone = coning_gap_shifts(pts, inp.motion, gs, zd, z, coning="cup", cup=d.rim.cup)
        ds = thickness_change(z, taper_mm_per_mm=mod.taper_mm_per_mm, crowning_mm=mod.crowning_mm, design_z_mm=zd,
                              ring_span_mm=(zc - b / 2, zc + b / 2))
        dy = radial_shift(z, shift_mm_per_mm=mod.shift_mm_per_mm, design_z_mm=zd)
        linear = (cone + ds[:, None] * flank_offset_gap_mm(pts, inp.motion, 1.0)[None]
                  + dy[:, None] * radial_offset_gap_mm(pts, inp.motion, 1.0)[None])
        lever, near = np.asarray(pts.lever_mm), pts.gap_mm < 0.03
        for i, zi in enumerate(z):
            first_lin = float(np.min((pts.gap_mm + linear[i]) / lever)) * ARCMIN
            first_ex = float(np.min((pts.gap_mm + exact[i]) / lever)) * ARCMIN
            diff = float(np.max(np.abs(exact[i] - linear[i])[near])) * 1e3
            print(f"flank {side:+d}  z = {zi:6.2f} mm: first contact {first_lin:7.3f} arcmin first-order, "
                  f"{first_ex:7.3f} exact; largest difference near contact {diff:6.1f} µm")
    return 0


if __name__ == "__main__":
    sys.exit(main())
