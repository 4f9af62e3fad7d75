"""Kill study: SIGKILL a real `profilegen design` at many moments; the output folder must hold
exactly the complete old set or the complete new set, and the next run must leave nothing
beside it (issue 13).

    python tests/benchmarks/kill_design.py            # 16 moments: 10 in sketch runs, 6 in default-scene runs
    python tests/benchmarks/kill_design.py --quick    # 6 moments in sketch runs

Each case copies a reference old set into ``WORK/export/default``, records its SHA-256s, starts
the new command into it, polls the folder and its parent every 2 ms and sends SIGKILL at the
case's moment: a delay (a fraction of the reference run's time, spread over the computation),
the staging folder appearing, k files staged, design.json staged (the swap is next), the folder's
inode changing (the swap happened, the old set is being deleted). Then:

* found: ``old`` — every file byte-identical to the old set and nothing else; ``new`` — the new
  reference's file names, the deterministic files (DXF, SVG, CSV, PNG) byte-identical to it, the
  JSON files identical once their timings (keys with ``time``) are dropped, the HTML once its
  numbers are; anything else is a violation. Either way every file ``design.json["files"]`` lists
  must exist and parse (JSON, DXF end marker, PNG chunks, CSV columns, HTML close tag) and
  nothing else may be there.
* leftovers: what is beside the folder after the kill, and after the next run (the same command,
  run to the end: it must give the new set and leave nothing).

The runs use ``PYTHONHASHSEED=0``: the DXF writer's object order follows string hashing, so the
DXF files of two processes differ without it (the same process writes identical files).
Prints a table and exits 1 on any violation.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import resource
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

from profilegen.output import folder as outfolder

NAME = "default"
DEFAULT = []  # the default scene: with contact.json and contact.png
SKETCH = ["--scene", "sketch"]  # the gear set's one-sided fit, no contact
SKETCH_LS = ["--scene", "sketch", "--no-contact", "--fit", "least_squares"]
# old set → the command that is killed: fewer files than the old set (the stale contact files
# must go), and more files than the old set
PAIRS = {"sketch": (DEFAULT, SKETCH_LS), "design": (SKETCH, DEFAULT)}
DETERMINISTIC = (".dxf", ".svg", ".csv", ".png")


def _cmd(args: list[str], out: Path) -> list[str]:
    return [sys.executable, "-m", "profilegen", "design", *args, "--out", str(out), "-q"]


def _env() -> dict:
    return {**os.environ, "PYTHONHASHSEED": "0"}


def _run(args: list[str], out: Path) -> float:
    t0 = time.perf_counter()
    res = subprocess.run(_cmd(args, out), env=_env(), capture_output=True, text=True, timeout=900)
    if res.returncode not in (0, 3):
        raise SystemExit(f"reference run {' '.join(args) or '(default)'} failed: {res.stderr[-500:]}")
    return time.perf_counter() - t0


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def strip_times(obj):
    """obj without keys naming a time, and without durations in its texts ("FEM solve 0.687 s")."""
    if isinstance(obj, dict):
        return {k: strip_times(v) for k, v in obj.items() if "time" not in k}
    if isinstance(obj, list):
        return [strip_times(v) for v in obj]
    if isinstance(obj, str):
        return re.sub(r"\d+(\.\d+)?([eE][-+]?\d+)? ?(s|ms)\b", "# s", obj)
    return obj


def _normal(path: Path):
    """The file's content with its run-dependent parts (timings) removed."""
    if path.suffix in DETERMINISTIC:
        return _sha(path)
    if path.suffix == ".json":
        return strip_times(json.loads(path.read_text(encoding="utf-8")))
    return hashlib.sha256(re.sub(r"\d+(\.\d+)?([eE][-+]?\d+)?", "#", path.read_text(encoding="utf-8")).encode()).hexdigest()


def _parses(path: Path) -> str | None:
    """None if the file reads back as what its suffix says, else why not."""
    try:
        data = path.read_bytes()
        if path.suffix == ".json":
            json.loads(data)
        elif path.suffix == ".dxf":
            if not data.rstrip().endswith(b"EOF"):
                return "DXF without EOF"
        elif path.suffix == ".png":
            if not (data.startswith(b"\x89PNG\r\n\x1a\n") and data[-12:-4] == b"\0\0\0\0IEND"):
                return "PNG without IEND"
        elif path.suffix == ".csv":
            rows = data.decode().splitlines()
            if len(rows) < 2 or len({r.count(",") for r in rows}) != 1:
                return "CSV rows of different widths"
        elif path.suffix in (".html", ".svg"):
            if not data.rstrip().endswith(b"</html>" if path.suffix == ".html" else b"</svg>"):
                return "unclosed"
    except (OSError, ValueError) as exc:
        return f"{type(exc).__name__}"
    return None


def _classify(out: Path, old: dict[str, str], new_ref: dict[str, object]) -> tuple[str, list[str]]:
    """('old' | 'new' | 'VIOLATION', problems) for the folder as it is now."""
    problems = []
    if not out.is_dir():
        return "VIOLATION", [f"{out.name} missing"]
    names = sorted(os.listdir(out))
    try:
        listed = sorted(json.loads((out / "design.json").read_text())["files"])
    except (OSError, ValueError, KeyError) as exc:
        listed = None
        problems.append(f"design.json unreadable ({type(exc).__name__})")
    if listed is not None and listed != names:
        problems.append(f"listed ≠ present: extra {sorted(set(names) - set(listed))}, "
                        f"missing {sorted(set(listed) - set(names))}")
    problems += [f"{n}: {why}" for n in names if (why := _parses(out / n))]
    if names == sorted(old) and all(_sha(out / n) == old[n] for n in names):
        return ("old" if not problems else "VIOLATION"), problems
    if names == sorted(new_ref):
        off = [n for n in names if _normal(out / n) != new_ref[n]]
        if not off:
            return ("new" if not problems else "VIOLATION"), problems
        problems.append(f"differ from both sets: {off[:4]}")
    else:
        problems.append(f"names match neither set: {names}")
    return "VIOLATION", problems


def _beside(out: Path) -> list[str]:
    return [p.name.replace(f".{NAME}.", ".N.") for p in outfolder.leftovers(out)]


def _staging(out: Path) -> Path | None:
    for n in os.listdir(out.parent):
        if n.startswith(f".{NAME}.staging-"):
            return out.parent / n
    return None


def _kill_at(args: list[str], out: Path, moment: tuple[str, float]) -> str:
    """Start the command into out, SIGKILL it at the moment; what was seen when it was killed."""
    kind, value = moment
    inode = out.stat().st_ino
    t0 = time.perf_counter()
    proc = subprocess.Popen(_cmd(args, out), env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    seen = ""
    try:
        while proc.poll() is None:
            t = time.perf_counter() - t0
            st = _staging(out)
            try:
                staged = sorted(os.listdir(st)) if st else []
            except FileNotFoundError:
                staged = []
            files = [n for n in staged if not n.endswith(".tmp")]
            fire = {
                "delay": t >= value,
                "staging": st is not None,
                "files": len(files) >= value,
                "design.json": "design.json" in files,
                "swapped": out.exists() and out.stat().st_ino != inode,
            }[kind]
            if fire:
                proc.send_signal(signal.SIGKILL)
                swapped = out.exists() and out.stat().st_ino != inode
                seen = f"t {t:5.1f} s, " + ("swap done" if swapped else f"staged {len(files)} files" if st
                                             else "no staging yet")
                break
            time.sleep(0.002)
    finally:
        proc.kill()
        proc.wait()
    if not seen:
        seen = f"ended by itself (status {proc.returncode}) before the moment"
    return seen


def main() -> int:
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="6 moments in the sketch scene only")
    ap.add_argument("--work", default=None, help="work folder (default: a new one under /tmp)")
    args = ap.parse_args()
    import tempfile

    work = Path(args.work or tempfile.mkdtemp(prefix="kill_design."))
    pairs = {k: v for k, v in PAIRS.items() if k == "sketch" or not args.quick}
    refs, ref_time = {}, {}
    for a in {tuple(a) for pair in pairs.values() for a in pair}:
        d = work / "ref" / ("_".join(a).replace("-", "") or "default") / NAME
        shutil.rmtree(d, ignore_errors=True)
        ref_time[a] = _run(list(a), d)
        print(f"reference run {' '.join(a) or '(default scene)'}: {ref_time[a]:.1f} s", flush=True)
        refs[a] = d
    sketch_t = ref_time.get(tuple(SKETCH_LS), 20.0)
    n_sketch = len(os.listdir(refs[tuple(SKETCH_LS)]))
    cases = [("sketch", m) for m in [("delay", 0.1 * sketch_t), ("staging", 0), ("files", 1), ("files", 3)]]
    cases += [("sketch", m) for m in [("delay", 0.2 * sketch_t), ("files", 6), ("files", 9), ("files", n_sketch - 1),
                                      ("design.json", 0), ("swapped", 0)]] if not args.quick else \
        [("sketch", ("files", n_sketch - 1))]
    if not args.quick:
        design_t = ref_time.get(tuple(DEFAULT), 40.0)
        n_design = len(os.listdir(refs[tuple(DEFAULT)]))
        cases += [("design", m) for m in [("delay", 0.2 * design_t), ("staging", 0), ("files", 4), ("files", 12),
                                           ("files", n_design - 1), ("swapped", 0)]]
    rows, bad = [], 0
    for i, (key, moment) in enumerate(cases, 1):
        old_dir, new_dir = (refs[tuple(a)] for a in pairs[key])
        old = {p.name: _sha(p) for p in old_dir.iterdir()}
        case = work / f"case{i:02d}"
        shutil.rmtree(case, ignore_errors=True)
        out = case / NAME
        shutil.copytree(old_dir, out)
        seen = _kill_at(pairs[key][1], out, moment)
        killed = case / "as_killed"  # the folder as the kill left it (the next run replaces it)
        shutil.copytree(out, killed)
        before = _beside(out)
        _run(pairs[key][1], out)  # the next run, to the end
        after = _beside(out)
        # the new set: what the same command gives when it runs to the end (compared after
        # dropping timings); it must have the reference run's file names
        new_ref = {p.name: _normal(p) for p in out.iterdir()}
        after_found, after_problems = _classify(out, old, new_ref)
        if sorted(new_ref) != sorted(p.name for p in new_dir.iterdir()):
            after_found = "VIOLATION"
            after_problems.append(f"the next run's files {sorted(new_ref)} are not the reference run's")
        found, problems = _classify(killed, old, new_ref)
        ok = found in ("old", "new") and after_found == "new" and not after
        bad += not ok
        what = f"{moment[0]} {moment[1]:.1f} s" if moment[0] == "delay" else \
            (f"{moment[1]:g} files staged" if moment[0] == "files" else moment[0])
        rows.append((i, key, what, seen, found, ", ".join(before) or "-", after_found, ", ".join(after) or "-",
                     "ok" if ok else "VIOLATION"))
        print(f"case {i:2d} {key:6s} {what:22s} {seen:34s} found {found:9s} beside {rows[-1][5]}", flush=True)
        for p in problems + after_problems:
            print(f"        {p}", flush=True)
    if not args.quick:  # two runs into one folder at once: one complete set, the other waited for the lock
        case = work / f"case{len(cases) + 1:02d}"
        shutil.rmtree(case, ignore_errors=True)
        out = case / NAME
        shutil.copytree(refs[tuple(DEFAULT)], out)
        procs = [subprocess.Popen(_cmd(a, out), env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
                 for a in (SKETCH, SKETCH_LS)]
        codes = [p.wait(timeout=900) for p in procs]
        found = [_classify(out, {}, {p.name: _normal(p) for p in refs[tuple(a)].iterdir()})[0] for a in (SKETCH, SKETCH_LS)]
        after = _beside(out)
        ok = codes == [0, 0] and sorted(found) == ["VIOLATION", "new"] and not after
        bad += not ok
        which = "sketch" if found[0] == "new" else "sketch least_squares" if found[1] == "new" else "neither"
        rows.append((len(rows) + 1, "sketch", "two runs at once", f"exit codes {codes}", f"{which}'s set", "-", "-",
                     ", ".join(after) or "-", "ok" if ok else "VIOLATION"))
    head = ("#", "scene", "moment", "at the kill", "found", "beside after kill", "next run", "beside after next", "")
    widths = [max(len(str(r[k])) for r in [head, *rows]) for k in range(len(head))]
    print()
    for r in [head, *rows]:
        print("  ".join(str(c).ljust(w) for c, w in zip(r, widths)).rstrip())
    kills = sum(not str(r[3]).startswith(("ended", "exit codes")) for r in rows)
    print(f"\n{len(rows)} cases ({kills} killed runs), {bad} violations. Old set → killed command: sketch: default scene → "
          f"{' '.join(SKETCH_LS)}" + ("" if args.quick else f"; design: {' '.join(SKETCH)} → default scene")
          + f". Work folder {work}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
