"""Every documented range's extreme, run as a user runs it, under a 4 GB address-space cap (issue 26).

Each case is one scene key or gear-set field at an end of its documented range (the header of
``profilegen/pipeline/scenes.toml``, the ranges :mod:`profilegen.gearset.reader` checks), everything else
as in ``profiles/default.toml`` with a sketch-tier scene. It runs ``python -m profilegen design``
in a subprocess under ``resource.setrlimit(RLIMIT_AS, 4 GB)`` and a timeout; the table gives the
field, the value, the outcome — ``ok`` (exit 0, or 3: the design's verdict), ``named error``
(exit 2 with one ``profilegen: error:`` line naming what to change) or ``other`` (a traceback, a
kill, a timeout: each is a bug) — the child's peak RSS and its wall time.

    python tests/benchmarks/range_extremes.py                 # every case, 120 s each
    python tests/benchmarks/range_extremes.py -k n_t -k module   # the cases whose field contains n_t or module
    python tests/benchmarks/range_extremes.py --timeout 60 --cap-gb 4
    python tests/benchmarks/range_extremes.py --show           # each case's stderr last line too

An open end (``deflection_coefficient`` in (0, 3]) is run at a value approaching it; a module is
run with the rim thickness scaled with it (1.8·m, the default set's). Exit code 1 if any case is
``other``.
"""

from __future__ import annotations

import argparse
import copy
import os
import resource
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from profilegen.output.optimize import gearset_toml

SKETCH = {"rim": "ring theory", "chord_tol_mm": 1e-4, "n_t": 96, "n_phi": 241, "clearance_samples": 91,
          "brute_force_check": False, "description": "range extremes", "fit_check_positions": 181,
          "figures": "none", "tier": "sketch"}

# (field, value): "scene.KEY" changes the sketch scene, "SECTION.KEY" the default gear set
# (a dict of several changes for fields that only make sense together)
CASES: list[tuple[str, object]] = [
    # scene keys (profilegen/pipeline/scenes.toml's header)
    ("scene.chord_tol_mm", 1e-2),
    ("scene.chord_tol_mm", 1e-9),
    ("scene.chord_tol_mm", 1e-300),
    ("scene.n_t", 8),
    ("scene.n_t", 100_000),
    ("scene.n_phi", 11),
    ("scene.n_phi", 100_000),
    ("scene.n_t+n_phi", {"scene.n_t": 100_000, "scene.n_phi": 100_000}),
    ("scene.clearance_samples", 3),
    ("scene.clearance_samples", 100_000),
    ("scene.fit_check_positions", 3),
    ("scene.fit_check_positions", 100_000),
    ("scene.clearance_samples+fit_check_positions",
     {"scene.clearance_samples": 100_000, "scene.fit_check_positions": 100_000}),
    # the largest the cost model lets through under the 4 GB cap (its budget 2 GiB): they must run
    ("scene.n_t+n_phi (at the budget)", {"scene.n_t": 100_000, "scene.n_phi": 447}),
    ("scene.clearance_samples (at the budget)", {"scene.clearance_samples": 26_789}),
    ("scene.fit_check_positions (at the budget)", {"scene.fit_check_positions": 26_789}),
    ("scene.brute_force_check", True),
    ("scene.face_slices", 33),  # a sketch tier: ignored, with a warning
    # gear set: [gear]
    ("gear.module_mm", {"gear.module_mm": 1e-6, "gear.rim_thickness_mm": 1.8e-6}),  # below the range: named
    ("gear.module_mm", {"gear.module_mm": 1e-5, "gear.rim_thickness_mm": 1.8e-5}),  # sketch chord: too coarse
    ("gear.module_mm", {"gear.module_mm": 1e-3, "gear.rim_thickness_mm": 1.8e-3}),
    ("gear.module_mm", {"gear.module_mm": 10.0, "gear.rim_thickness_mm": 18.0}),
    ("gear.flexspline_teeth", {"gear.flexspline_teeth": 20, "gear.circular_spline_teeth": 22,
                               "gear.rim_thickness_mm": 0.5}),
    ("gear.flexspline_teeth", {"gear.flexspline_teeth": 2000, "gear.circular_spline_teeth": 2002}),
    ("gear.waves", {"gear.waves": 3, "gear.circular_spline_teeth": 203}),
    ("gear.waves", {"gear.waves": 4, "gear.circular_spline_teeth": 204}),
    ("gear.rim_thickness_mm", 0.25),  # RIM_PER_DEFLECTION_MIN · w0
    ("gear.rim_thickness_mm", 10.0),  # 0.2 · r1
    # [wave_generator]
    ("wave_generator.deflection_coefficient", 3.0),
    ("wave_generator.deflection_coefficient", 1e-3),
    # [tooth] (dcta)
    ("tooth.pressure_angle_deg", 1e-3),
    ("tooth.pressure_angle_deg", 44.999),
    # [circular_spline]
    ("circular_spline.tip_clearance_mm", 0.0),
    ("circular_spline.tip_clearance_mm", 1.0),  # 2 m
    ("circular_spline.root_clearance_mm", 0.0),
    ("circular_spline.root_clearance_mm", 1.0),
    ("circular_spline.wire_radius_mm", 1e-6),
    ("circular_spline.spark_gap_mm", 0.0),
    # [torque]
    ("torque.rated_nm", 1e-9),
    ("torque.rated_nm", {"torque.rated_nm": 1e9, "torque.peak_nm": 1e9, "torque.momentary_nm": 1e9}),
    # [material]
    ("material.poisson_ratio", 0.0),
    ("material.poisson_ratio", 0.4999),
    ("material.youngs_modulus_mpa", 1e6),
]


def _case_files(field: str, value, folder: Path) -> tuple[Path, Path]:
    with open(ROOT / "profiles" / "default.toml", "rb") as f:
        gs = tomllib.load(f)
    gs["scene"] = "sketch"
    scene = copy.deepcopy(SKETCH)
    changes = value if isinstance(value, dict) else {field: value}
    for path, v in changes.items():
        section, key = path.split(".", 1)
        if section == "scene":
            scene[key] = v
        else:
            gs.setdefault(section, {})[key] = v
    gpath, spath = folder / "gearset.toml", folder / "scene.toml"
    gpath.write_text(gearset_toml(gs))
    spath.write_text(gearset_toml({"extreme": scene}))
    return gpath, spath


def _limit(cap_bytes: int):
    def apply():
        resource.setrlimit(resource.RLIMIT_AS, (cap_bytes, cap_bytes))
    return apply


def run_case(field: str, value, *, cap_gb: float, timeout: float) -> dict:
    with tempfile.TemporaryDirectory(prefix="extreme_") as tmp:
        folder = Path(tmp)
        gpath, spath = _case_files(field, value, folder)
        cmd = [sys.executable, "-m", "profilegen", "design", str(gpath), "--scene", str(spath),
               "--out", str(folder / "out")]  # not -q: the warnings are counted
        env = dict(os.environ, PYTHONWARNINGS="default")
        t0 = time.perf_counter()
        with open(folder / "stderr.txt", "wb") as err_file:
            proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err_file, cwd=tmp, env=env,
                                    preexec_fn=_limit(int(cap_gb * 2**30)), start_new_session=True)
            timed_out, status, usage = False, None, None
            while status is None:  # wait4: this child's own peak RSS (with its reaped workers')
                pid, st, ru = os.wait4(proc.pid, os.WNOHANG)
                if pid:
                    status, usage = st, ru
                elif time.perf_counter() - t0 > timeout:
                    os.killpg(proc.pid, 9)
                    timed_out = True
                    _, status, usage = os.wait4(proc.pid, 0)
                else:
                    time.sleep(0.05)
            proc.returncode = os.waitstatus_to_exitcode(status)
        wall = time.perf_counter() - t0
        peak_mb = usage.ru_maxrss / 1024
        err = (folder / "stderr.txt").read_bytes()
    lines = [ln for ln in err.decode(errors="replace").splitlines() if ln.strip()]
    warned = [ln for ln in lines if ln.startswith("WARNING ")]
    lines = [ln for ln in lines if not ln.startswith("WARNING ")]
    rc = proc.returncode
    if timed_out:
        outcome = "other (timeout)"
    elif rc in (0, 3, 4):  # 3, 4: the verdict FAIL / INCOMPLETE (with --strict only)
        outcome = "ok"
    elif rc == 2 and lines and lines[-1].startswith("profilegen: error:") and not any(
            "Traceback" in ln for ln in lines):
        outcome = "named error"
    else:
        outcome = f"other (exit {rc})"
    return {"field": field, "value": value, "outcome": outcome, "peak_mb": peak_mb, "time_s": wall,
            "last": lines[-1] if lines else "", "stderr_lines": len(lines), "warnings": len(warned),
            "library_warnings": sum("py.warnings" in ln for ln in warned)}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("-k", action="append", default=[], help="only the fields containing this text")
    p.add_argument("--timeout", type=float, default=120.0)
    p.add_argument("--cap-gb", type=float, default=4.0)
    p.add_argument("--show", action="store_true", help="print each case's last stderr line")
    args = p.parse_args(argv)
    cases = [(f, v) for f, v in CASES if not args.k or any(k in f for k in args.k)]
    print(f"{'field':44s} {'value':>12s}  {'outcome':18s} {'peak RSS':>9s} {'time':>7s}  "
          "other stderr lines / warning lines (library's)")
    bad = 0
    for field, value in cases:
        row = run_case(field, value, cap_gb=args.cap_gb, timeout=args.timeout)
        shown = f"{row['peak_mb']:6.0f} MB"
        if isinstance(value, dict):
            value = value.get(field, "…")
        text = f"{value:g}" if isinstance(value, float) else str(value)
        print(f"{field:44s} {text:>12s}  {row['outcome']:18s} {shown:>9s} {row['time_s']:6.1f}s  "
              f"{row['stderr_lines']} / {row['warnings']} ({row['library_warnings']})", flush=True)
        if args.show and row["last"]:
            print(f"    {row['last'][:300]}")
        bad += row["outcome"].startswith("other")
    print(f"{len(cases)} cases, {bad} other (each a bug)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
