"""The face stage before and after a change (issue 31: a design-scene tooth change in ≤ 1.5 s): the
same numbers, and the time.

    python tests/benchmarks/face_identity.py [--before REF] [--after REF] [--repeats 3]
                                             [--sets default ...] [--design-repeats 3] [--whole]

The "after" tree is ``--after`` (git, of this repository; default HEAD); the "before" tree is the
same with the face stage's code (``--paths``: profilegen/face and profilegen/profile/gearform.py) as it was
at ``--before`` (default e5bce8f, before the face stage's speed-up), so the design's total differs
by that code alone; ``--whole``: the whole ``--before`` tree instead. Each is unpacked with ``git
archive`` into a temporary folder and run there in its own process (``PYTHONPATH`` the folder), so
uncommitted edits in the working tree play no part. In each, for every bundled set (``--sets``;
default the five bundled: default, seed000_csf40, seed001_shf25, seed002_short_cup, csf32_100):
``profilegen.design(set, scene="design")`` runs until its face stage (:func:`profilegen.face.face_width`
is wrapped to take its arguments and stop the design there) and the face stage runs once on those
arguments (its results compared; a warm-up). Then the two processes, side by side, run each set's
face stage ``--repeats`` times and the default set's whole design scene ``--design-repeats`` times
(after one warm-up), one run at a time, before and after alternating (and which goes first), so
that the shared machine's load falls on both alike: wall and CPU time of each run.

Compared, set by set, before against after: the design section (z and index), the modification
(taper, crowning, radial shift, iterations), every section's minimum clearance, its φ, backlash
and signed gap in the unmodified table and in the modification's table, and the two clearance maps
(sections × φ) elementwise. Prints the largest difference (mm) of each and overall, the face
stage's median times and their ratio, the design's; exits 1 when any difference exceeds
``--tol`` (1e-9 mm) or a design section / iteration count differs.
"""

from __future__ import annotations

import argparse
import math
import os
import pickle
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SETS = ("default", "seed000_csf40", "seed001_shf25", "seed002_short_cup", "csf32_100")
BEFORE = "e5bce8f"


def _rows(table) -> list:
    return [[r.z_mm, r.min_clearance_mm, r.at_phi_rad, r.max_backlash_mm,
             math.nan if r.min_gap_mm is None else r.min_gap_mm, r.thickness_change_mm] for r in table]


def _summary(face) -> dict:
    mod = face.modification
    out = {"design_index": face.design_index, "design_z_mm": face.design_section_z_mm,
           "table": _rows(face.table), "clearance_mm": face.clearance_mm.tolist(),
           "warnings": list(face.warnings)}
    if mod is not None:
        out.update(taper=mod.taper_mm_per_mm, crowning=mod.crowning_mm, shift=mod.shift_mm_per_mm,
                   iterations=mod.iterations, mod_table=_rows(mod.table), mod_clearance_mm=mod.clearance_mm.tolist())
    return out


def worker(sets, out: str) -> None:
    """In the unpacked tree (first on sys.path): each set's face stage arguments (its design run up
    to the face stage), one face stage each (its results kept; a warm-up), then commands from stdin,
    one a line, each answered with one line: ``face NAME`` (one run: "wall cpu"), ``design`` (the
    default set's whole design scene once: "wall cpu"), ``dump`` (the results into ``out``)."""
    import profilegen
    import profilegen.face as face_module

    class _Stop(Exception):
        pass

    captured = {}
    real = face_module.face_width

    def capture(gearset, deformation, **kw):
        captured["args"] = (gearset, deformation, kw)
        raise _Stop

    print(f"  profilegen from {Path(profilegen.__file__).parent}", file=sys.stderr, flush=True)
    inputs, result = {}, {}
    for name in sets:
        face_module.face_width = capture
        try:
            profilegen.design(profilegen.load_gearset(name), scene="design")
        except _Stop:
            pass
        finally:
            face_module.face_width = real
        inputs[name] = captured.pop("args")
        gs, dfm, kw = inputs[name]
        result[name] = _summary(real(gs, dfm, **kw))
    default = profilegen.load_gearset("default")
    for line in sys.stdin:
        cmd = line.split()
        if cmd[0] == "dump":
            with open(out, "wb") as f:
                pickle.dump(result, f)
            print("ok", flush=True)
            continue
        t0, c0 = time.perf_counter(), time.process_time()
        if cmd[0] == "face":
            gs, dfm, kw = inputs[cmd[1]]
            real(gs, dfm, **kw)
        else:
            profilegen.design(default, scene="design")
        print(time.perf_counter() - t0, time.process_time() - c0, flush=True)


def _unpack(ref: str, into: Path, paths=()) -> str:
    """``ref``'s tree (or only its ``paths``, replacing those in ``into``) into ``into``."""
    commit = subprocess.run(["git", "rev-parse", "--short", ref], cwd=ROOT, check=True, capture_output=True,
                            text=True).stdout.strip()
    for p in paths:
        target = into / p
        if target.is_dir():
            shutil.rmtree(target)
        elif target.exists():
            target.unlink()
    archive = subprocess.run(["git", "archive", commit, *paths], cwd=ROOT, check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    return commit


def _start(tree: Path, out: Path, sets) -> subprocess.Popen:
    """This script's worker (the older tree may not hold it) in ``tree``, importing that tree's package."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    return subprocess.Popen([sys.executable, str(Path(__file__).resolve()), "--worker", str(out), "--sets", *sets],
                            cwd=tree, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)


def _ask(proc: subprocess.Popen, command: str) -> list[float]:
    proc.stdin.write(command + "\n")
    proc.stdin.flush()
    answer = proc.stdout.readline()
    if not answer:
        raise SystemExit(f"the worker stopped at {command!r} (exit {proc.wait()})")
    return [float(x) for x in answer.split() if x != "ok"]


def _measure(procs: dict, args) -> dict:
    """The runs, before and after alternating (which goes first alternates too), so that the
    machine's load falls on both alike."""
    times = {label: {name: {"wall_s": [], "cpu_s": []} for name in [*args.sets, "design"]} for label in procs}
    order = list(procs)
    jobs = [(f"face {name}", name) for _ in range(args.repeats) for name in args.sets]
    if args.design_repeats:
        jobs += [("design", None)] + [("design", "design")] * args.design_repeats  # the first: a warm-up
    for i, (command, key) in enumerate(jobs):
        for label in (order if i % 2 == 0 else order[::-1]):
            wall, cpu = _ask(procs[label], command)
            if key is not None:
                times[label][key]["wall_s"].append(wall)
                times[label][key]["cpu_s"].append(cpu)
    for label, proc in procs.items():
        _ask(proc, "dump")
        proc.stdin.close()
        proc.wait()
    return times


def _largest(a, b) -> float:
    import numpy as np

    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        return math.inf
    same_nan = np.isnan(a) & np.isnan(b)
    d = np.where(same_nan, 0.0, np.abs(a - b))
    return float(np.nanmax(np.where(np.isnan(d), math.inf, d))) if d.size else 0.0


def compare(before: dict, after: dict, tol: float) -> bool:
    ok, overall = True, 0.0
    print(f"\n{'set':<18} {'d section':>9} {'mod (taper, crown, shift)':>26} {'tables':>10} {'maps':>10}  "
          f"face before s  after s  ratio (wall medians; CPU medians)")
    for name, b in before["sets"].items():
        a = after["sets"][name]
        sb, sa = b["summary"], a["summary"]
        same_d = sb["design_index"] == sa["design_index"] and sb.get("iterations") == sa.get("iterations")
        d_mod = max((abs(sb[k] - sa[k]) for k in ("taper", "crowning", "shift") if k in sb), default=0.0)
        d_tab = max(_largest(sb["table"], sa["table"]), _largest(sb.get("mod_table", []), sa.get("mod_table", [])))
        d_map = max(_largest(sb["clearance_mm"], sa["clearance_mm"]),
                    _largest(sb.get("mod_clearance_mm", []), sa.get("mod_clearance_mm", [])))
        worst = max(d_mod, d_tab, d_map, abs(sb["design_z_mm"] - sa["design_z_mm"]))
        overall = max(overall, worst)
        ok &= same_d and worst <= tol and sb["warnings"] == sa["warnings"]
        wb, wa = statistics.median(b["wall_s"]), statistics.median(a["wall_s"])
        cb, ca = statistics.median(b["cpu_s"]), statistics.median(a["cpu_s"])
        print(f"{name:<18} {'same' if same_d else 'DIFFERS':>9} {d_mod:26.3g} {d_tab:10.3g} {d_map:10.3g}  "
              f"{wb:13.3f} {wa:8.3f} {wb / wa:6.2f}  ({cb:.3f} -> {ca:.3f} s CPU, {cb / ca:.2f})"
              + ("" if sb["warnings"] == sa["warnings"] else "  warnings DIFFER"))
    print(f"\nlargest difference over the sets: {overall:.3g} mm (tolerance {tol:g} mm): {'OK' if ok else 'FAIL'}")
    tb, ta = before["design"]["wall_s"], after["design"]["wall_s"]
    if tb and ta:
        print(f"default set, design scene, whole design: {statistics.median(tb):.3f} s -> {statistics.median(ta):.3f} s "
              f"wall (medians of {len(tb)}; ratio {statistics.median(tb) / statistics.median(ta):.2f}); CPU "
              f"{statistics.median(before['design']['cpu_s']):.3f} -> {statistics.median(after['design']['cpu_s']):.3f} s")
    return ok


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", default=BEFORE)
    ap.add_argument("--after", default="HEAD")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--design-repeats", type=int, default=3)
    ap.add_argument("--sets", nargs="+", default=list(SETS))
    ap.add_argument("--tol", type=float, default=1e-9)
    ap.add_argument("--paths", nargs="+", default=["profilegen/face", "profilegen/profile/gearform.py"])
    ap.add_argument("--whole", action="store_true", help="the whole --before tree, not only --paths")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    if args.worker:
        sys.path.insert(0, os.getcwd())
        worker(args.sets, args.worker)
        return 0
    # the refs as commits, once: both trees from the same commits even when a branch moves meanwhile
    args.after, args.before = (subprocess.run(["git", "rev-parse", "--short", ref], cwd=ROOT, check=True,
                                              capture_output=True, text=True).stdout.strip()
                               for ref in (args.after, args.before))
    with tempfile.TemporaryDirectory(prefix="face_identity_") as tmp:
        procs, outs = {}, {}
        for label in ("before", "after"):
            tree = Path(tmp) / label
            tree.mkdir()
            if label == "after" or args.whole:
                ref = args.after if label == "after" else args.before
                print(f"{label}: {ref} ({_unpack(ref, tree)})", flush=True)
            else:
                base = _unpack(args.after, tree)
                print(f"before: {args.after} ({base}) with {' '.join(args.paths)} from {args.before} "
                      f"({_unpack(args.before, tree, args.paths)})", flush=True)
            outs[label] = Path(tmp) / f"{label}.pkl"
            procs[label] = _start(tree, outs[label], args.sets)
        times = _measure(procs, args)
        results = {}
        for label in procs:
            with open(outs[label], "rb") as f:
                summaries = pickle.load(f)
            results[label] = {"sets": {name: {**times[label][name], "summary": summaries[name]} for name in args.sets},
                              "design": times[label]["design"]}
    return 0 if compare(results["before"], results["after"], args.tol) else 1


if __name__ == "__main__":
    sys.exit(main())
