"""End to end, as a user runs it: each command's wall time beside its stage sum (issue 14, item 2).

Every command runs N times (interleaved, so a load change hits them alike) as a subprocess,
`python -m profilegen ...` with a fresh output folder; the table gives the median wall time,
the median stage sum from design.json (``time_s``), their ratio, the CPU time of the command
with its worker processes (user + system), and the load average at the start of the command's
runs. ``--workers 0,1,2`` runs each design command once per figure-worker count
(``PROFILEGEN_FIGURE_WORKERS``). In the same run, in-process: one ``design()`` per scene, then
``write_design`` N times into fresh folders (the first call pays matplotlib's import and font
cache; it is given apart from the median of the later calls; CPU time includes the figure
workers). Later calls favour a tree that draws in this process: matplotlib stays imported here,
while fresh figure workers import it again (unless this process has imported it).

    python tests/benchmarks/end_to_end.py                 # sketch, default scene, check; N = 3
    python tests/benchmarks/end_to_end.py -n 5 --verify   # also the verify scene
    python tests/benchmarks/end_to_end.py --profile       # + cProfile top 15 of write_design per scene
    python tests/benchmarks/end_to_end.py --cli-profile   # + cProfile top 20 of each command, as run
    python tests/benchmarks/end_to_end.py --save /tmp/e2e-before     # keep one output folder per command
    python tests/benchmarks/end_to_end.py --compare /tmp/e2e-before  # files now vs then, timings removed
    python tests/benchmarks/end_to_end.py --no-bytecode   # every command compiles the sources (no .pyc)
    git archive OLD | tar -x -C /tmp/old && python tests/benchmarks/end_to_end.py --baseline /tmp/old
                                                        # the same commands from an older tree, alternating

``--compare`` checks that every file keeps its name, that JSON files agree to 1e-12 (relative)
once keys naming a time are dropped (and durations inside texts), that CSV, DXF and SVG are
byte-identical, that the HTML pages agree once embedded images and numbers in timing cells are
removed, and lists the PNGs whose pixels changed (their size in pixels, before and after).
Exit code 1 if a comparison fails.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import math
import os
import pstats
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from tests.benchmarks.kill_design import strip_times as _strip_times  # noqa: E402  (one rule for what a timing is)

CAP_BYTES = 4 * 1024**3
TEXT_SUFFIXES = (".csv", ".dxf", ".svg")


def _cap():
    resource.setrlimit(resource.RLIMIT_AS, (CAP_BYTES, CAP_BYTES))


#: where the commands' bytecode goes (None: as the environment says; see --no-bytecode)
_PYCACHE: Path | None = None


def _env() -> dict:
    # this tree, whatever the installed (editable) package points at; --baseline replaces it
    env = {**os.environ, "PYTHONHASHSEED": "0", "PYTHONPATH": str(ROOT)}
    if _PYCACHE is not None:  # compiled once, as an installed package is: not the tree's __pycache__
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = str(_PYCACHE)
    return env


def _compile(tree: Path) -> None:
    """Byte-compile a tree's package into the benchmark's pycache prefix (before the runs)."""
    env = {**_env(), "PYTHONPATH": str(tree)}
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(tree / "profilegen")], env=env,
                   capture_output=True, timeout=300, check=False)


def _commands(verify: bool) -> dict[str, list[str]]:
    cmds = {
        "design --scene sketch": ["design", "--scene", "sketch", "-q"],
        "design": ["design", "-q"],
        "check default": ["check", "default"],
    }
    if verify:  # the 2D tiers: since the verify scene's rim is the 3D cup (issue 15), its toothed 2D rim by --rim
        cmds["design --scene verify --rim toothed"] = ["design", "--scene", "verify", "--rim", "toothed", "-q"]
    return cmds


def _for_tree(cmd: list[str], tree: Path | None) -> list[str]:
    """``cmd`` as an older tree takes it: without ``--rim toothed`` where its CLI has no --rim
    (its verify scene was the toothed 2D rim then)."""
    if tree is None or "--rim" not in cmd or "--rim" in (tree / "profilegen" / "cli.py").read_text():
        return cmd
    i = cmd.index("--rim")
    return cmd[:i] + cmd[i + 2:]


def _run(args: list[str], out: Path, env: dict) -> tuple[float, float | None, float]:
    """(wall s, stage sum s or None, CPU s of the command and its worker processes) of one command."""
    cmd = [sys.executable, "-m", "profilegen", *args]
    if args[0] == "design":
        cmd += ["--out", str(out)]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    # cwd: a folder without a profilegen package (`python -m` puts the cwd first on sys.path)
    res = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=900, preexec_fn=_cap,
                         cwd=out.parent)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    if res.returncode not in (0, 3):
        raise SystemExit(f"{' '.join(args)} exited {res.returncode}: {res.stderr[-800:]}")
    stages = None
    if args[0] == "design":
        stages = float(json.loads((out / "design.json").read_text(encoding="utf-8"))["time_s"])
    return wall, stages, cpu


def _cli_profile(args: list[str], out: Path, env: dict, top: int = 20) -> str:
    """cProfile of one run of the command (this process only: the figure workers are not in it),
    its top entries by cumulative and by own time."""
    prof = out.parent / f"{out.name}.prof"
    cmd = [sys.executable, "-m", "cProfile", "-o", str(prof), "-m", "profilegen", *args]
    if args[0] == "design":
        cmd += ["--out", str(out)]
    res = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=900, preexec_fn=_cap, cwd=out.parent)
    if res.returncode not in (0, 3):
        return f"failed ({res.returncode}): {res.stderr[-300:]}"
    buf = io.StringIO()
    stats = pstats.Stats(str(prof), stream=buf)
    stats.sort_stats("cumulative").print_stats(top)
    stats.sort_stats("tottime").print_stats(top)
    return "\n".join(line for line in buf.getvalue().splitlines() if line.strip())


def _in_process(n: int, profile: bool, scenes: list[str], tmp: Path) -> dict[str, dict]:
    """design() once per scene, then write_design n times; optionally one profiled write."""
    from profilegen.gearset import default_gearset_path, load_gearset
    from profilegen.output.files import write_design
    from profilegen.pipeline.design import design

    gs = load_gearset(default_gearset_path())
    out = {}
    for scene in scenes:
        result = design(gs, scene=scene)
        times, cpus = [], []
        for i in range(n):
            folder = tmp / f"inproc-{scene}-{i}"
            c0, r0 = time.process_time(), resource.getrusage(resource.RUSAGE_CHILDREN)
            t0 = time.perf_counter()
            write_design(result, folder)
            times.append(time.perf_counter() - t0)
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)  # the figure workers, joined by now
            cpus.append(time.process_time() - c0 + (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime))
            shutil.rmtree(folder)
        row = {"first": times[0], "median": statistics.median(times[1:]) if n > 1 else times[0],
               "cpu_first": cpus[0], "cpu": statistics.median(cpus[1:]) if n > 1 else cpus[0],
               "stages": result.time_s}
        if profile:
            folder = tmp / f"prof-{scene}"
            pr = cProfile.Profile()
            pr.enable()
            write_design(result, folder)
            pr.disable()
            buf = io.StringIO()
            pstats.Stats(pr, stream=buf).sort_stats("cumulative").print_stats(15)
            row["profile"] = buf.getvalue()
            shutil.rmtree(folder)
        out[scene] = row
    return out


# ---------------------------------------------------------------------------------------- comparison

def _json_diff(a, b, where: str = "") -> list[str]:
    """Places where a and b differ (floats by more than 1e-12 relative)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = [f"{where}/{k}: only in one" for k in sorted(set(a) ^ set(b))]
        for k in sorted(set(a) & set(b)):
            out += _json_diff(a[k], b[k], f"{where}/{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{where}: length {len(a)} != {len(b)}"]
        out = []
        for i, (x, y) in enumerate(zip(a, b)):
            out += _json_diff(x, y, f"{where}[{i}]")
            if len(out) > 5:
                break
        return out
    if isinstance(a, float) and isinstance(b, float):
        if a == b or (math.isnan(a) and math.isnan(b)) or abs(a - b) <= 1e-12 * max(abs(a), abs(b)):
            return []
        return [f"{where}: {a!r} != {b!r}"]
    return [] if a == b else [f"{where}: {str(a)[:60]!r} != {str(b)[:60]!r}"]


def _html_normal(text: str) -> list[str]:
    """The page's lines without embedded images and without the numbers of timing cells."""
    text = re.sub(r'src="data:image/png;base64,[^"]*"', 'src="#"', text)
    lines = []
    for line in text.splitlines():
        if re.search(r"time|ms\)|solve [\d.]+ s", line):  # stage table rows, fit times, FEM solve time
            line = re.sub(r"\d+(\.\d+)?([eE][-+]?\d+)?", "#", line)
        elif ", r = " in line:  # the fit report's error table: its rows end with the fit time (ms)
            line = re.sub(r"<td>[\d.]+</td></tr>", "<td>#</td></tr>", line)
        lines.append(line)
    return lines


def _stage_row_normal(lines: list[str]) -> list[str]:
    # a stage-table row: <tr><td>stage</td><td class=text>tier</td><td>ms</td>... -> ms cell removed
    return [re.sub(r"(<tr><td>[a-z_ ]+</td><td class=text>[^<]*</td>)<td>[\d.]+</td>", r"\1<td>#</td>", s) for s in lines]


def _png_size(data: bytes) -> tuple[int, int]:
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def compare(old: Path, new: Path) -> list[str]:
    """Problems (empty: same files, same numbers); prints what differs."""
    problems = []
    a_names = sorted(p.name for p in old.iterdir())
    b_names = sorted(p.name for p in new.iterdir())
    if a_names != b_names:
        problems.append(f"file names differ: {sorted(set(a_names) ^ set(b_names))}")
    for name in sorted(set(a_names) & set(b_names)):
        pa, pb = old / name, new / name
        if name.endswith(".json"):
            d = _json_diff(_strip_times(json.loads(pa.read_text())), _strip_times(json.loads(pb.read_text())))
            if d:
                problems.append(f"{name}: " + "; ".join(d[:5]))
        elif name.endswith(TEXT_SUFFIXES):
            if pa.read_bytes() != pb.read_bytes():
                problems.append(f"{name}: bytes differ")
        elif name.endswith(".html"):
            la = _stage_row_normal(_html_normal(pa.read_text()))
            lb = _stage_row_normal(_html_normal(pb.read_text()))
            diff = [(x, y) for x, y in zip(la, lb) if x != y]
            if len(la) != len(lb) or diff:
                problems.append(f"{name}: {len(diff)} lines differ ({len(la)} vs {len(lb)} lines), first: "
                                + (repr(diff[0])[:300] if diff else ""))
            imgs = [len(re.findall(r"data:image/png", p.read_text())) for p in (pa, pb)]
            if imgs[0] != imgs[1]:
                problems.append(f"{name}: {imgs[0]} embedded images before, {imgs[1]} after")
        elif name.endswith(".png"):
            da, db = pa.read_bytes(), pb.read_bytes()
            if da != db:
                print(f"  {name}: pixels changed, {_png_size(da)} -> {_png_size(db)} px, "
                      f"{len(da) / 1e3:.0f} -> {len(db) / 1e3:.0f} kB")
    return problems


# ---------------------------------------------------------------------------------------------- main

def _load() -> str:
    return "/".join(f"{x:.2f}" for x in os.getloadavg())


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-n", type=int, default=3, help="runs per command (median)")
    ap.add_argument("--verify", action="store_true", help="also `design --scene verify` (about a minute a run)")
    ap.add_argument("--profile", action="store_true", help="cProfile top 15 (cumulative) of write_design per scene")
    ap.add_argument("--cli-profile", action="store_true",
                    help="also one run of each command (this tree) under cProfile: top 20 by cumulative and own time "
                         "(the main process; the figure workers draw outside it)")
    ap.add_argument("--no-cli", action="store_true", help="skip the subprocess runs")
    ap.add_argument("--no-inproc", action="store_true", help="skip the in-process write_design timing")
    ap.add_argument("--workers", default="",
                    help="comma-separated PROFILEGEN_FIGURE_WORKERS values: each design command once per value "
                         "(0: figures drawn in the main process); default: the library's choice")
    ap.add_argument("--baseline", type=Path,
                    help="a source tree of profilegen (e.g. `git archive` of an older commit): every command also "
                         "runs from it (PYTHONPATH), alternating with this tree, rows marked 'baseline'")
    ap.add_argument("--inproc-tree", type=Path, help=argparse.SUPPRESS)  # the baseline's in-process part
    ap.add_argument("--save", type=Path, help="keep the first output folder of each design command here")
    ap.add_argument("--compare", type=Path, help="compare the first output folders with those kept by --save")
    ap.add_argument("--no-bytecode", action="store_true",
                    help="run as the environment says (PYTHONDONTWRITEBYTECODE=1 here: every command compiles the "
                         "package's sources, ~0.1 s CPU for check, ~0.4 s for design); default: bytecode compiled "
                         "once into a temporary PYTHONPYCACHEPREFIX, as an installed package has it")
    args = ap.parse_args()
    _cap()
    global _PYCACHE
    if not args.no_bytecode:
        _PYCACHE = Path(tempfile.mkdtemp(prefix="e2e-pycache-"))
        for tree in [ROOT] + ([args.baseline.resolve()] if args.baseline else []):
            _compile(tree)
    if args.inproc_tree:  # a child run: write_design of an older tree, rows only
        sys.path.insert(0, str(args.inproc_tree.resolve()))
        with tempfile.TemporaryDirectory(prefix="e2e-") as tmpname:
            res = _in_process(max(args.n, 2), False, ["sketch", "design"] + (["verify"] if args.verify else []),
                              Path(tmpname))
        for scene, r in res.items():
            print(f"| {scene} (baseline) | {r['stages']:.2f} | {r['first']:.2f} | {r['median']:.2f} "
                  f"| {r['cpu_first']:.2f} | {r['cpu']:.2f} |")
        return 0
    cmds = {}
    for label, cmd in _commands(args.verify).items():
        values = [v.strip() for v in args.workers.split(",") if v.strip()] if cmd[0] == "design" else []
        for v in values or [None]:
            env = _env() if v is None else {**_env(), "PROFILEGEN_FIGURE_WORKERS": v}
            cmds[label if v is None else f"{label} [workers {v}]"] = (cmd, env)
        if args.baseline:
            base = {**_env(), "PYTHONPATH": str(args.baseline.resolve())}
            cmds[f"{label} (baseline)"] = (_for_tree(cmd, args.baseline), base)
    rows = {k: {"wall": [], "stages": [], "cpu": [], "load": None} for k in cmds}
    problems, saved = [], set()
    print(f"# end to end, {time.strftime('%Y-%m-%d %H:%M')}, {os.cpu_count()} CPUs, load at start {_load()}, "
          f"bytecode {'compiled once' if _PYCACHE else 'as the environment says'}\n", flush=True)
    with tempfile.TemporaryDirectory(prefix="e2e-") as tmpname:
        tmp = Path(tmpname)
        if not args.no_cli:
            for i in range(args.n):
                for label, (cmd, env) in cmds.items():
                    if rows[label]["load"] is None:
                        rows[label]["load"] = _load()
                    out = tmp / f"{label.replace(' ', '_')}-{i}"
                    wall, stages, cpu = _run(cmd, out, env)
                    rows[label]["wall"].append(wall)
                    rows[label]["cpu"].append(cpu)
                    if stages is not None:
                        rows[label]["stages"].append(stages)
                    print(f"  run {i + 1}/{args.n} {label}: {wall:.2f} s wall, {cpu:.2f} s CPU"
                          + ("" if stages is None else f", stages {stages:.2f} s") + f" (load {_load()})", flush=True)
                    if i == 0 and cmd[0] == "design":
                        if label.endswith("(baseline)"):  # compared with this tree's first run
                            print(f"compare {label} -> this tree:")
                            base = label[:-len(" (baseline)")]
                            mine = next(k for k in cmds if k.split(" [")[0] == base and not k.endswith("(baseline)"))
                            p = compare(out, tmp / f"{mine.replace(' ', '_')}-0")
                            for line in p:
                                print(f"  DIFFERS {line}")
                            problems += p
                            continue
                        key = label.split(" [")[0].replace(" ", "_").replace("-", "")
                        if args.save:
                            dest = args.save / key
                            if key not in saved:
                                shutil.rmtree(dest, ignore_errors=True)
                                shutil.copytree(out, dest)
                                saved.add(key)
                        if args.compare:
                            print(f"compare {label}:")
                            p = compare(args.compare / key, out)
                            for line in p:
                                print(f"  DIFFERS {line}")
                            problems += p
                    if i > 0 or not (args.save or args.compare or args.baseline):
                        shutil.rmtree(out, ignore_errors=True)
            print("\n| command | wall (s) | stage sum (s) | wall / stages | CPU (s) | runs | load avg 1/5/15 |")
            print("|---|---:|---:|---:|---:|---:|---|")
            for label, r in rows.items():
                wall = statistics.median(r["wall"])
                st = statistics.median(r["stages"]) if r["stages"] else None
                ratio = "—" if st is None else f"{wall / st:.2f}"
                print(f"| `profilegen {label}` | {wall:.2f} | {'—' if st is None else f'{st:.2f}'} | {ratio} "
                      f"| {statistics.median(r['cpu']):.2f} | {len(r['wall'])} | {r['load']} |")
        if args.cli_profile:
            for label, cmd in _commands(args.verify).items():
                print(f"\ncProfile of `profilegen {' '.join(cmd)}` (one run, main process):\n")
                print(_cli_profile(cmd, tmp / f"prof-{label.replace(' ', '_')}", _env()))
        if not args.no_inproc:
            scenes = ["sketch", "design"] + (["verify"] if args.verify else [])
            load = _load()
            res = _in_process(max(args.n, 2), args.profile, scenes, tmp)
            print(f"\nin-process `write_design` (load at start {load}):\n")
            print("| scene | stage sum (s) | write_design first call (s) | median of later calls (s) "
                  "| CPU first call (s) | CPU later calls (s) |")
            print("|---|---:|---:|---:|---:|---:|")
            for scene, r in res.items():
                print(f"| {scene} | {r['stages']:.2f} | {r['first']:.2f} | {r['median']:.2f} "
                      f"| {r['cpu_first']:.2f} | {r['cpu']:.2f} |")
            if args.baseline:
                child = subprocess.run([sys.executable, __file__, "-n", str(args.n), "--inproc-tree", str(args.baseline)]
                                       + (["--verify"] if args.verify else []), capture_output=True, text=True,
                                       timeout=1800, cwd=tmp, env=_env())
                print(child.stdout.rstrip() or f"baseline in-process run failed: {child.stderr[-500:]}")
            print(f"(load at end of the in-process runs {_load()})")
            for scene, r in res.items():
                if "profile" in r:
                    print(f"\ncProfile of write_design, scene {scene}:\n")
                    print("\n".join(line for line in r["profile"].splitlines() if line.strip()))
    print(f"\nload at end {_load()}")
    if _PYCACHE is not None:
        shutil.rmtree(_PYCACHE, ignore_errors=True)
    if args.compare or args.baseline:
        print("comparison: " + ("same files, same numbers" if not problems else f"{len(problems)} problems"))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
