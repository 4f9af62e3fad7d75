"""The loaded contact's compliance build (ContactCompliance.build), this tree against a baseline
revision, interleaved in one process (issue 14: the first torque's build ≤ 1 s).

    python tests/benchmarks/compliance_build.py [-n 3] [--set default] [--scene design] [--baseline HEAD]

The baseline is ``profilegen/contact/compliance.py`` as committed at ``--baseline`` (a git
revision), loaded as a module of its own beside the package (everything else is this tree's).
Both builds run on the same ContactInput and contact points (those ``solve_contact`` makes
for the set's design), alternately, ``-n`` times each; printed per build: total, FS and CS
times (medians), their ratio baseline / this tree, and the largest difference of S (relative
to max |S|) and of its FS part. Times under load vary; the ratio in one run is the number.
"""

from __future__ import annotations

import argparse
import importlib.util
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("-n", type=int, default=3, help="builds of each (default 3)")
    parser.add_argument("--set", default="default", help="gear set name or path (default: the default set)")
    parser.add_argument("--scene", default="design", help="scene of the design the inputs come from")
    parser.add_argument("--baseline", default="HEAD", help="git revision of the baseline compliance.py")
    args = parser.parse_args()
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))

    path = pg.default_gearset_path() if args.set == "default" else pg.resolve_gearset(args.set)
    design = pg.design(pg.load_gearset(path), scene=args.scene)
    inputs = ContactInput.from_design(design)
    pts = contact_points(inputs, side=1, stations=5, max_gap_mm=0.12)
    base = baseline_module(args.baseline)
    builders = {"baseline": base.ContactCompliance.build, "this tree": ContactCompliance.build}
    times = {k: {"total": [], "fs": [], "cs": []} for k in builders}
    last = {}
    for _ in range(args.n):
        for name, build in builders.items():
            t0 = time.perf_counter()
            c = build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm)
            times[name]["total"].append(time.perf_counter() - t0)
            times[name]["fs"].append(c.time_s["fs"])
            times[name]["cs"].append(c.time_s["cs"])
            last[name] = c
    print(f"set {args.set}, scene {args.scene}: {pts.count} points, dof {last['this tree'].dof}, n = {args.n}")
    print(f"{'':10s} {'total s':>9s} {'FS s':>9s} {'CS s':>9s}")
    med = {k: {p: statistics.median(v) for p, v in t.items()} for k, t in times.items()}
    for name in builders:
        print(f"{name:10s} " + " ".join(f"{med[name][p]:9.3f}" for p in ("total", "fs", "cs")))
    print(f"{'ratio':10s} " + " ".join(f"{med['baseline'][p] / med['this tree'][p]:9.2f}" for p in ("total", "fs", "cs")))
    a, b = last["baseline"], last["this tree"]
    for label, x, y in (("S", a.matrix_mm_per_n, b.matrix_mm_per_n),
                        ("S_FS", a.fs_matrix_mm_per_n, b.fs_matrix_mm_per_n),
                        ("S_CS", a.cs_matrix_mm_per_n, b.cs_matrix_mm_per_n)):
        print(f"max |Δ{label}| / max |{label}| = {np.max(np.abs(x - y)) / np.max(np.abs(x)):.3g}")


if __name__ == "__main__":
    main()
