"""Time and size of the STEP solids (issue 17 item 4), in process, medians of ``-n`` runs, and the
issue's checks on the gear set's own chains.

    python tests/benchmarks/step_write.py [-n 3] [--scene design] [--gearset PATH] [--readback]

The design is computed once (no contact, no stresses), outside the timing. Then:

* the OCP import (first call, once per process);
* ``write_cs_step`` and ``write_fs_step`` (wall and CPU, median of ``-n``), each split into the
  solid (:func:`cs_solid` / :func:`fs_solid`) and the STEP text (:func:`step_bytes`), and the
  file sizes; whether the runs gave the same bytes;
* the checks of ``tests/unit/test_step.py`` on the default set's solids: one valid solid
  (BRepCheck), the volume against (π R_out² − chain area) · b and, for the FS, the ring by the
  chain area plus the cup by Pappus; the mid-face section's edges against the chain (1e-6 mm).
  With ``--readback`` the files themselves are read back (OCCT with its shape healing, ~10 s
  each now that the caps are cut in sectors; 524 s for the CS with one 2828-edge cap face) and
  checked; without it the solids checked are the ones written.

Prints a table; writes only to a temporary folder.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))


def _timed(fn, n: int):
    walls, cpus, outs = [], [], []
    for _ in range(n):
        w, c = time.perf_counter(), time.process_time()
        outs.append(fn())
        walls.append(time.perf_counter() - w)
        cpus.append(time.process_time() - c)
    return statistics.median(walls), statistics.median(cpus), outs


def main() -> None:
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (6_000_000_000, 6_000_000_000))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=3)
    ap.add_argument("--scene", default="design")
    ap.add_argument("--gearset", default=None)
    ap.add_argument("--readback", action="store_true", help="check the files read back, not the solids written")
    args = ap.parse_args()

    from profilegen.gearset import default_gearset_path, load_gearset
    from profilegen.output import step
    from profilegen.pipeline.design import design

    gs = load_gearset(args.gearset or default_gearset_path())
    d = design(gs, scene=args.scene, contact=False, stress=False)
    cs_chain, fs_chain = d.profile.outline, step.fs_outline(d)
    print(f"{gs.name} ({args.scene}): CS chain {len(cs_chain.elements)} elements, FS chain {len(fs_chain.elements)}")

    w = time.perf_counter()
    step._occ()
    print(f"OCP import: {time.perf_counter() - w:.2f} s wall")
    from tests.unit import test_step as t  # the checks' independent geometry and OCCT read-back helpers

    g, cup = gs.gear, gs.cup
    r_out = step.cs_outer_radius_mm(d)
    fs_args = dict(bore_radius_mm=g.neutral_radius_mm - g.rim_thickness_mm / 2,
                   wall_outer_radius_mm=g.neutral_radius_mm + g.rim_thickness_mm / 2, length_mm=cup.length_mm,
                   face_width_mm=cup.face_width_mm, bottom_thickness_mm=cup.bottom_thickness_mm,
                   boss_radius_mm=cup.boss_radius_mm,
                   boss_thickness_mm=step.BOSS_THICKNESS_PER_BOTTOM * cup.bottom_thickness_mm)
    with tempfile.TemporaryDirectory() as tmp:
        rows = []
        for name, writer, make in (
            ("circular_spline", step.write_cs_step,
             lambda: step.cs_solid(cs_chain, outer_radius_mm=r_out, face_width_mm=cup.face_width_mm)),
            ("flexspline", step.write_fs_step, lambda: step.fs_solid(fs_chain, **fs_args)),
        ):
            path = Path(tmp) / f"{name}.step"
            wall, cpu, outs = _timed(lambda: writer(path, d).read_bytes(), args.n)
            same = all(o == outs[0] for o in outs)
            s_wall, s_cpu, solids = _timed(make, args.n)
            b_wall, b_cpu, _ = _timed(lambda: step.step_bytes(solids[0], name), args.n)
            rows.append((name, wall, cpu, s_wall, s_cpu, b_wall, b_cpu, len(outs[0]), same))
            print(f"{name}.step: write {wall:.2f} s wall / {cpu:.2f} s CPU (solid {s_wall:.2f}/{s_cpu:.2f}, "
                  f"STEP text {b_wall:.2f}/{b_cpu:.2f}); {len(outs[0]) / 1e6:.2f} MB; same bytes in {args.n} runs: {same}")

            shape = solids[0]
            if args.readback:
                w = time.perf_counter()
                shape = t.read_step(path)
                print(f"  read back: {time.perf_counter() - w:.1f} s")
            found = t.solids_of(shape)
            w = time.perf_counter()
            valid = t.is_valid(found[0])
            check_s = time.perf_counter() - w
            vol = t.volume_mm3(found[0])
            b = cup.face_width_mm
            if name == "circular_spline":
                chain = cs_chain
                expected = (math.pi * r_out ** 2 - abs(t.chain_area_mm2(chain))) * b
                z_mid, inner, split = b / 2, True, r_out - 1.0
            else:
                chain = fs_chain
                a = fs_args
                r_b, r_w, tb, r0 = a["bore_radius_mm"], a["wall_outer_radius_mm"], a["bottom_thickness_mm"], a["boss_radius_mm"]
                h0, l = a["boss_thickness_mm"], a["length_mm"]
                meridian = [(0, tb - h0), (r0, tb - h0), (r0, 0), (r_w, 0), (r_w, l - b / 2), (r_b, l - b / 2),
                            (r_b, tb), (0, tb)]
                expected = (t.chain_area_mm2(chain) - math.pi * r_b ** 2) * b + t.polygon_pappus_volume(meridian)
                z_mid, inner, split = l, False, r_b + 1e-3
            sec = t.compare_section(t.section_edges(shape, z_mid), chain, inner=inner, split_radius=split)
            print(f"  solids {len(found)}, BRepCheck valid {valid} ({check_s:.1f} s); volume {vol:.6f} mm3 vs "
                  f"{expected:.6f} (rel {vol / expected - 1:+.2e}); section: {sec['edges']} edges, points off the "
                  f"chain <= {sec['point_to_chain_mm']:.1e} mm, vertices off the cut <= {sec['vertex_to_cut_mm']:.1e} mm, "
                  f"length {sec['length_mm']:.9f} vs {sec['chain_length_mm']:.9f} mm")


if __name__ == "__main__":
    main()
