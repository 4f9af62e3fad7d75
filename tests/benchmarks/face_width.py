"""Face width (issue 15 items 4, 5): speed and accuracy of the face stage on the default set.

    python tests/benchmarks/face_width.py [--repeats N]

1. The 3D cup pressed onto the default set's cam as the cup3d rim tier solves it
   (``solve_rim(tier="cup3d")``: 2 mm, 2 layers, 16 angles, exact gap, geometrically nonlinear,
   and its coarse companion): its time (not part of the face stage's budget).
2. ``face_width`` without modification — five sections' envelopes (chord 1e-4 mm), the design
   section's choice, the clearance map (181 poses per section, the minimum refined) — median
   wall and CPU time of N runs (default 5), split into the envelopes and the maps (budget: 2 s;
   the machine is shared, so the CPU time of the one process is the unloaded wall time).
3. Accuracy of the settings (sections traced at a chord of 1e-4 mm, 181 map poses): the section
   table (min clearance, the gap to the swept regions, max backlash) against chord 1e-6 mm and 721
   poses; the largest difference (the map at 1e-6 mm misses interference: see
   profilegen.face.stage.CHORD_TOL_MM — the gap column is the check).
4. The tooth modification (``solve_modification``): its numbers, its time, and the section table
   with it.

Prints the tables; writes export/bench/face_width.csv (one row per setting and section).
"""

from __future__ import annotations

import argparse
import csv
import io
import os
import resource
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from profilegen.face import face_width, solve_modification  # noqa: E402
from profilegen.gearset import load_gearset  # noqa: E402
from profilegen.output.export import atomic_write  # noqa: E402
from profilegen.rim.stage import solve_rim  # noqa: E402


def _table(rows) -> str:
    out = [f"{'z mm':>7} {'w_maj um':>9} {'w_min um':>9} {'|u|max um':>9} {'ds um':>7} {'min cl um':>10} "
           f"{'at deg':>7} {'backlash um':>11} {'gap um':>9}"]
    for r in rows:
        out.append(f"{r.z_mm:7.2f} {r.omega_major_mm * 1e3:9.2f} {r.omega_minor_mm * 1e3:9.2f} "
                   f"{r.upsilon_max_mm * 1e3:9.2f} {r.thickness_change_mm * 1e3:7.2f} {r.min_clearance_mm * 1e3:10.4f} "
                   f"{np.degrees(r.at_phi_rad):7.1f} {r.max_backlash_mm * 1e3:11.4f} "
                   f"{'—' if r.min_gap_mm is None else format(r.min_gap_mm * 1e3, '.4f'):>9}")
    return "\n".join(out)


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--speed-only", action="store_true", help="parts 1 and 2 only")
    args = ap.parse_args()
    from threadpoolctl import threadpool_limits

    gs = load_gearset(ROOT / "profiles" / "default.toml")
    csv_rows = []
    with threadpool_limits(limits=1, user_api="blas"):
        t0 = time.perf_counter()
        rim = solve_rim(gs, tier="cup3d")
        cup = rim.cup_contact
        print(f"1. solve_rim(default set, tier cup3d: {rim.tier.label()}): {time.perf_counter() - t0:.2f} s")

        runs = []
        for _ in range(args.repeats):
            t0, c0 = time.perf_counter(), time.process_time()
            fw = face_width(gs, cup)
            runs.append((time.perf_counter() - t0, time.process_time() - c0, fw.envelope_s, fw.map_s))
        total, cpu, env, maps = (statistics.median(x) for x in zip(*runs))
        print(f"\n2. face_width, {len(fw.sections)} sections, no modification, median of {args.repeats}: "
              f"{total:.3f} s wall, {cpu:.3f} s CPU (one process; envelopes {env:.3f} s, maps {maps:.3f} s wall; "
              f"all runs wall {[round(r[0], 3) for r in runs]}, CPU {[round(r[1], 3) for r in runs]}; "
              f"load average {os.getloadavg()[0]:.1f})")
        print(f"   design section z = {fw.design_section_z_mm:g} mm ({fw.design_choice}); largest interference "
              f"{fw.max_interference_mm * 1e3:.4f} um, largest backlash {fw.max_backlash_mm * 1e3:.3f} um")
        print("   candidates (rows: CS from section d; columns: section k) min gap um:")
        print(np.array2string(fw.candidate_min_gap_mm * 1e3, precision=3, suppress_small=True))
        print(_table(fw.table))
        for r in fw.table:
            csv_rows.append(["coarse", r.z_mm, r.min_clearance_mm, r.max_backlash_mm, total])

        if args.speed_only:
            return
        t0 = time.perf_counter()
        fine = face_width(gs, cup, chord_tol_mm=1e-6, map_samples=721)
        t_fine = time.perf_counter() - t0
        d_min = max(abs(a.min_clearance_mm - b.min_clearance_mm) for a, b in zip(fw.table, fine.table))
        d_bl = max(abs(a.max_backlash_mm - b.max_backlash_mm) for a, b in zip(fw.table, fine.table))
        d_gap = max(abs(a.min_gap_mm - b.min_gap_mm) for a, b in zip(fw.table, fine.table))
        print(f"\n3. against chord 1e-6 mm, 721 poses ({t_fine:.2f} s; design section z = "
              f"{fine.design_section_z_mm:g} mm): max |d min clearance| {d_min * 1e3:.4f} um, max |d gap| "
              f"{d_gap * 1e3:.4f} um, "
              f"max |d backlash| {d_bl * 1e3:.4f} um")
        print(_table(fine.table))
        for r in fine.table:
            csv_rows.append(["fine", r.z_mm, r.min_clearance_mm, r.max_backlash_mm, t_fine])

        t0 = time.perf_counter()
        mod = solve_modification(gs, cup, fw)
        t_mod = time.perf_counter() - t0
        print(f"\n4. modification ({t_mod:.2f} s, {mod.iterations} LP steps): taper {mod.taper_mm_per_mm * 1e3:.4f} "
              f"um/mm, crowning {mod.crowning_mm * 1e3:.4f} um; largest interference {mod.max_interference_mm * 1e3:.4f} "
              f"um, largest backlash {mod.max_backlash_mm * 1e3:.3f} um (predicted by the LP "
              f"{mod.predicted_backlash_mm * 1e3:.3f} um); warnings {list(mod.warnings)}")
        print(_table(mod.table))
        for r in mod.table:
            csv_rows.append(["modified", r.z_mm, r.min_clearance_mm, r.max_backlash_mm, t_mod])

    out = ROOT / "export" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["setting", "z_mm", "min_clearance_mm", "max_backlash_mm", "time_s"])
    w.writerows(csv_rows)
    with atomic_write(out / "face_width.csv", "w") as f:
        f.write(buf.getvalue())


if __name__ == "__main__":
    main()
