"""The loaded contact's compliance build (ContactCompliance.build): the substructured build
against the whole-mesh reference, interleaved in one process (issue 14: the first torque's
build ≤ 1 s), and the contact results both give.

    python tests/benchmarks/compliance_build.py [-n 3] [--set default] [--scene design] [--baseline REV]

"old" is this tree's reference path (``substructure=False``: the whole FS half ring and CS
sector assembled and factorised) or, with ``--baseline REV``, ``profilegen/contact/
compliance.py`` as committed at that git revision, loaded as a module of its own beside the
package. "new" is this tree's default build. Both run on the same ContactInput and contact
points (those ``solve_contact`` makes for the set's design), alternately, ``-n`` times each.
Printed: the load average before and after; per build the medians of wall time, CPU time
(process_time: less sensitive to the other processes on the machine) and the FS / CS times,
and the ratio old / new; the largest difference of S (relative to max |S|) and of its FS
and CS parts; then ``solve_contact`` at the set's torques with each S (points and
compliance given, so no FEM is redone): the largest differences of the point forces, the
tooth forces, the ball reactions (each relative to its largest value), of the rotation and
of the secant stiffness (relative).
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.contact import ContactInput  # noqa: E402
from profilegen.contact.analysis import solve_contact  # noqa: E402
from profilegen.contact.compliance import ContactCompliance  # noqa: E402
from profilegen.contact.points import contact_points  # noqa: E402


def baseline_module(revision: str):
    """``profilegen/contact/compliance.py`` at ``revision``, imported as profilegen.contact._baseline_compliance."""
    source = subprocess.run(["git", "-C", str(ROOT), "show", f"{revision}:profilegen/contact/compliance.py"],
                            check=True, capture_output=True, text=True).stdout
    path = Path(tempfile.mkdtemp()) / "_baseline_compliance.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location("profilegen.contact._baseline_compliance", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def _rel(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    scale = np.max(np.abs(b), initial=0.0)
    return float(np.max(np.abs(a - b), initial=0.0) / scale) if scale else float(np.max(np.abs(a - b), initial=0.0))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("-n", type=int, default=3, help="builds of each (default 3)")
    parser.add_argument("--set", default="default", help="gear set name or path (default: the default set)")
    parser.add_argument("--scene", default="design", help="scene of the design the inputs come from")
    parser.add_argument("--baseline", default=None,
                        help="git revision of the old compliance.py (default: this tree's substructure=False)")
    args = parser.parse_args()
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))

    path = pg.default_gearset_path() if args.set == "default" else pg.resolve_gearset(args.set)
    design = pg.design(pg.load_gearset(path), scene=args.scene)
    inputs = ContactInput.from_design(design)
    pts = contact_points(inputs, side=1, stations=5, max_gap_mm=0.12)
    if args.baseline is None:
        old_build, old_label = (lambda *a: ContactCompliance.build(*a, mesh={"substructure": False})), "substructure=False"
    else:
        old_build, old_label = baseline_module(args.baseline).ContactCompliance.build, f"git {args.baseline}"
    builders = {"old": old_build, "new": ContactCompliance.build}
    times = {k: {"wall": [], "cpu": [], "fs": [], "cs": []} for k in builders}
    last = {}
    load_before = os.getloadavg()
    for _ in range(args.n):
        for name, build in builders.items():
            t0, c0 = time.perf_counter(), time.process_time()
            c = build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm)
            times[name]["wall"].append(time.perf_counter() - t0)
            times[name]["cpu"].append(time.process_time() - c0)
            times[name]["fs"].append(c.time_s["fs"])
            times[name]["cs"].append(c.time_s["cs"])
            last[name] = c
    load_after = os.getloadavg()
    print(f"set {args.set}, scene {args.scene}: {pts.count} points, dof {last['new'].dof}, n = {args.n}; "
          f"old = {old_label}, new = this tree's default build")
    print("load average before: " + " ".join(f"{v:.2f}" for v in load_before)
          + "; after: " + " ".join(f"{v:.2f}" for v in load_after))
    parts = ("wall", "cpu", "fs", "cs")
    print(f"{'median':8s} " + " ".join(f"{p + ' s':>9s}" for p in parts))
    med = {k: {p: statistics.median(v) for p, v in t.items()} for k, t in times.items()}
    for name in builders:
        print(f"{name:8s} " + " ".join(f"{med[name][p]:9.3f}" for p in parts))
    print(f"{'ratio':8s} " + " ".join(f"{med['old'][p] / med['new'][p]:9.2f}" for p in parts))
    for name in builders:
        print(f"{name} wall s: " + ", ".join(f"{v:.3f}" for v in times[name]["wall"]))
    a, b = last["new"], last["old"]
    for label, x, y in (("S", a.matrix_mm_per_n, b.matrix_mm_per_n),
                        ("S_FS", a.fs_matrix_mm_per_n, b.fs_matrix_mm_per_n),
                        ("S_CS", a.cs_matrix_mm_per_n, b.cs_matrix_mm_per_n)):
        print(f"max |Δ{label}| / max |{label}| = {_rel(x, y):.3g}")

    gs = inputs.gearset
    torques = [t for t in (gs.torque.rated_nm, gs.torque.peak_nm, gs.torque.momentary_nm) if t is not None]
    res = {k: solve_contact(inputs, torques, points=pts, compliance=last[k]) for k in builders}
    print(f"contact at {', '.join(f'{t:g}' for t in torques)} N·m (new against old):")
    for ca, cb in zip(res["new"].cases, res["old"].cases):
        print(f"  {ca.torque_nm:8.4g} N·m: forces {_rel(ca.solution.force_n, cb.solution.force_n):.2e}, "
              f"tooth forces {_rel(ca.tooth_force_n, cb.tooth_force_n):.2e}, "
              f"balls {_rel(ca.ball_reaction_n, cb.ball_reaction_n):.2e} "
              f"(active {'same' if np.array_equal(ca.ball_active, cb.ball_active) else 'DIFFERENT'}), "
              f"rotation {_rel(ca.rotation_rad, cb.rotation_rad):.2e}")
    k_new, k_old = res["new"].secant_stiffness_nm_per_rad, res["old"].secant_stiffness_nm_per_rad
    print(f"  secant stiffness: {_rel(k_new, k_old):.2e}"
          f" (new {', '.join(f'{k:.6g}' for k in res['new'].secant_stiffness_nm_per_rad)} N·m/rad)")


if __name__ == "__main__":
    main()
