"""Bad and edge inputs, end to end: every case is a small gear-set TOML (or CLI argv) in a temp folder, run
as ``profilegen check`` and as ``profilegen design --scene sketch --out <tmp>/out -q`` in a subprocess
with an address-space limit and a timeout. A case behaves when both runs

* exit with code 2,
* print exactly one line on stderr for design (-q: no progress lines), naming the expected field or file,
  and for check one line per problem, each starting with the file, one of them naming the field,
* never print the canary planted in every file that is not a gear set (``CANARY``),
* write nothing to the output folder and leave nothing but their inputs in the case folder,
* stay under ``--max-rss-mb`` peak resident memory (getrusage of the child, via os.wait4) and
  ``--max-seconds`` wall time.

It prints a markdown table (one row per case) and a summary, and exits 1 if any case misbehaves.

    python tests/benchmarks/bad_inputs.py                 # every case (~90; 3–6 min on one core)
    python tests/benchmarks/bad_inputs.py -k points -v    # cases whose name contains "points"

Issue 13 ("bad input never hurts the machine"). Not collected by pytest; tests/unit/test_bad_inputs.py
runs a fast subset in-process.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_TOML = ROOT / "profiles" / "default.toml"
CANARY = "CANARY-7f3a9c-root:$6$s3cr3t"  # in every non-gear-set file; must never be printed

# --------------------------------------------------------------------------- TOML writing


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)  # JSON escapes are TOML basic-string escapes
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def dumps(data: dict) -> str:
    lines = [f"{json.dumps(k)} = {_value(v)}" for k, v in data.items() if not isinstance(v, dict)]
    for k, v in data.items():
        if isinstance(v, dict):
            lines.append(f"\n[{json.dumps(k)}]")
            lines += [f"{json.dumps(kk)} = {_value(vv)}" for kk, vv in v.items()]
    return "\n".join(lines) + "\n"


BASE = tomllib.loads(DEFAULT_TOML.read_text())
DELETE = object()


def gearset_with(**changes) -> dict:
    """The default set with dotted-path changes (``DELETE`` removes a key); keys use '__' for '.'."""
    data = json.loads(json.dumps(BASE))
    for path, value in changes.items():
        *head, last = path.split("__")
        node = data
        for part in head:
            node = node.setdefault(part, {})
        if value is DELETE:
            node.pop(last, None)
        else:
            node[last] = value
    return data


def points_tooth(**tooth) -> dict:
    data = gearset_with()
    data["tooth"] = {"kind": "points", **tooth}
    return data


def flank(n: int = 12, m: float = 0.5) -> list[list[float]]:
    ys = [-1.2 * m + 2.0 * m * i / (n - 1) for i in range(n)]
    return [[math.pi * m / 4 - y * math.tan(math.radians(10.0)), y] for y in ys]


# --------------------------------------------------------------------------- cases


@dataclass
class Case:
    name: str
    expect: str  # text every error line must contain (a field path or a file name)
    files: dict = field(default_factory=dict)  # name -> str | bytes | dict (a gear set) | "FIFO" | "DIR"
    gearset: str = "set.toml"  # the gear-set argument (relative names are in the case folder)
    scene: str = "sketch"
    check: bool = True  # also run `profilegen check`


def cases() -> list[Case]:
    out: list[Case] = []

    def field_case(name, path, value, expect=None, **extra):
        data = gearset_with(**{path.replace(".", "__"): value}, **extra)
        out.append(Case(name, expect or path, {"set.toml": data}))

    # every numeric gear field: out of range, wrong type, nan, inf, huge
    for path, values in {
        "gear.module_mm": [-0.5, 0.0, math.nan, math.inf, 1e300, "0.5", True],
        "gear.flexspline_teeth": [19, 200.0, 10**12, -200, int("9" * 4000)],
        "gear.circular_spline_teeth": [203, 200, 202.0],
        "gear.waves": [1, 5, 2.5],
        "gear.rim_thickness_mm": [0.0, 50.0, math.nan, 0.1],
        "gear.neutral_radius_mm": [60.0, 10.0, math.inf],
        "tooth.pressure_angle_deg": [0.0, 45.0, math.nan],
        "tooth.addendum_coefficient": [5.0, 0.05, "0.8"],
        "tooth.half_thickness_coefficient": [2.0],
        "wave_generator.deflection_coefficient": [0.0, 3.5, math.nan, -math.inf],
        "wave_generator.bearing_thickness_mm": [-1.0, 1e9],
        "material.youngs_modulus_mpa": [0.0, 1e9, math.nan],
        "material.poisson_ratio": [0.5, -0.1, [0.3]],
        "torque.rated_nm": [0.0, -1.0, math.nan, "big"],
        "torque.peak_nm": [100.0],
        "torque.momentary_nm": [600.0],
        "circular_spline.root_clearance_mm": [-0.1],
        "circular_spline.tip_clearance_mm": [5.0],
        "cup.length_mm": [0.0],
        "cup.face_width_mm": [1e6],
        "cup.boss_radius_mm": [100.0],
        "cup.bottom_thickness_mm": [math.nan],
        "cup.root_fillet_radius_mm": [5.0],
    }.items():
        for v in values:
            field_case(f"{path} = {_value(v)[:24]}", path, v)
    field_case("both addendum units", "tooth.addendum_mm", 0.4, "tooth.addendum_coefficient")
    field_case("tip arc misses the addendum", "tooth.tip_arc_radius_coefficient", 0.3, "tooth.tip_arc_radius_mm")
    field_case("material yield > ultimate", "material.yield_strength_mpa", 2000.0)
    field_case("contour unknown", "wave_generator.contour", "square")
    field_case("rollers overlap", "wave_generator.roller_radius_mm", 20.0,
               wave_generator__contour="rollers", wave_generator__roller_count=4)
    field_case("roller_count 3", "wave_generator.roller_count", 3,
               wave_generator__contour="rollers", wave_generator__roller_radius_mm=5.0)
    field_case("roller angle 60", "wave_generator.roller_angle_deg", 60.0, wave_generator__contour="rollers",
               wave_generator__roller_count=4, wave_generator__roller_radius_mm=5.0)
    field_case("roller key on a cam", "wave_generator.roller_radius_mm", 5.0)
    field_case("fit_method unknown", "circular_spline.fit_method", "best")
    field_case("unknown key in [gear]", "gear.modul_mm", 0.5)
    field_case("unknown tooth key", "tooth.foo", 1.0)
    field_case("scene unknown in file", "scene", "fast")
    # module 10: the default set as it was (tooth in mm for m = 0.5) and as it is (module units)
    old_tooth = {"kind": "dcta", "pressure_angle_deg": 10.0, "line_above_pitch_mm": 0.05, "line_below_pitch_mm": 0.2,
                 "tip_arc_radius_mm": 0.65, "root_arc_radius_mm": 0.7, "addendum_mm": 0.4, "dedendum_mm": 0.6}
    out.append(Case("module 10, mm tooth of m 0.5", "tooth.addendum_mm",
                    {"set.toml": gearset_with(gear__module_mm=10.0, tooth=old_tooth, gear__rim_thickness_mm=18.0)}))
    out.append(Case("module 10, default copy (rim 0.9)", "gear.rim_thickness_mm",
                    {"set.toml": gearset_with(gear__module_mm=10.0)}))
    # top level
    field_case("name 5000 chars", "name", "a" * 5000)
    field_case("name with /", "name", "../etc")
    field_case("name ..", "name", "..")
    field_case("name with newline", "name", "a\nb")
    field_case("name empty", "name", "")
    field_case("description 10000 chars", "description", "d" * 10000)
    field_case("description with NUL", "description", "a\u0000b")
    field_case("source missing", "source", DELETE)
    field_case("unknown top-level key", "colour", "red")
    field_case("unknown section", "extra", {"a": 1})
    field_case("no [gear]", "gear", DELETE)
    field_case("no [material]", "material", DELETE)
    field_case("[torque] not a table", "torque", 5)
    field_case("tooth kind missing", "tooth.kind", DELETE)
    field_case("tooth kind unknown", "tooth.kind", "spur")
    # files that are no gear set
    secret = f"root:x:0:0:{CANARY}:/root:/bin/bash\ndaemon:x:1:1::/usr/sbin:/usr/sbin/nologin\n"
    out += [
        Case("malformed TOML", "set.toml", {"set.toml": f"[gear\n{CANARY} = 1\n"}),
        Case("TOML key declared twice", "set.toml", {"set.toml": f'"{CANARY}" = 1\n"{CANARY}" = 2\n'}),
        Case("TOML invalid character", "set.toml", {"set.toml": f"name = {CANARY}\n"}),
        Case("passwd-like text as gear set", "set.toml", {"set.toml": secret}),
        Case("non-UTF-8", "set.toml", {"set.toml": b'name = "\xff\xfe' + CANARY.encode() + b'"\n'}),
        Case("binary file", "set.toml", {"set.toml": bytes(range(256)) * 8 + CANARY.encode() + b"\0" * 64}),
        Case("empty file", "name", {"set.toml": ""}),
        Case("deeply nested array", "set.toml", {"set.toml": "a = " + "[" * 100_000 + "]" * 100_000 + "\n"}),
        Case("oversized TOML (5 MiB)", "set.toml", {"set.toml": ("# " + CANARY + "\n") * 180_000}),
        Case("gear set /dev/zero", "/dev/zero", gearset="/dev/zero"),
        Case("gear set a folder", "folder.toml", {"folder.toml": "DIR"}, gearset="folder.toml"),
        Case("gear set a FIFO", "fifo.toml", {"fifo.toml": "FIFO"}, gearset="fifo.toml"),
        Case("gear set missing", "missing.toml", gearset="missing.toml"),
        Case("no such profile name", "nosuchprofile", gearset="nosuchprofile"),
        Case("gear set a FIFO, bare name", "fifo: is a FIFO", {"fifo": "FIFO"}, gearset="fifo"),
        Case("integer of 5000 digits", "set.toml", {"set.toml": DEFAULT_TOML.read_text().replace(
            "flexspline_teeth = 200", "flexspline_teeth = " + "2" * 5000)}),
    ]
    # point lists
    bad_rows = "x_mm,y_mm\n" + "\n".join(f"{x!r},{y!r}" for x, y in flank()[:5]) + f"\n0.1,{CANARY}\n"
    crossing = flank(12)
    crossing[5], crossing[6] = [crossing[6][0] + 0.3, crossing[5][1]], [crossing[5][0] - 0.3, crossing[6][1]]
    looping = flank(12)
    looping[6:6] = [[0.6, 0.05], [0.7, -0.2], [0.2, -0.1]]
    zigzag = [[0.39 + (0.2 if i % 2 else 0.0), -0.6 + i * 0.05] for i in range(20)]
    out += [
        Case("points_file /dev/zero", "tooth.points_file", {"set.toml": points_tooth(points_file="/dev/zero")}),
        Case("points_file a FIFO", "tooth.points_file", {"set.toml": points_tooth(points_file="p.csv"), "p.csv": "FIFO"}),
        Case("points_file a folder", "tooth.points_file", {"set.toml": points_tooth(points_file="p.csv"), "p.csv": "DIR"}),
        Case("points_file passwd-like", "tooth.points_file", {"set.toml": points_tooth(points_file="passwd"), "passwd": secret}),
        Case("points_file non-UTF-8", "tooth.points_file",
             {"set.toml": points_tooth(points_file="p.csv"), "p.csv": b"x_mm,y_mm\n\xff\xfe," + CANARY.encode() + b"\n"}),
        Case("points_file NUL byte", "tooth.points_file",
             {"set.toml": points_tooth(points_file="p.csv"), "p.csv": "x_mm,y_mm\n0.1,\0" + CANARY + "\n"}),
        Case("points_file oversized (17 MiB)", "tooth.points_file",
             {"set.toml": points_tooth(points_file="p.csv"), "p.csv": "x_mm,y_mm\n" + ("0.3,0.1," + CANARY + "\n") * 500_000}),
        Case("points_file 20 000 rows", "tooth.points_file",
             {"set.toml": points_tooth(points_file="p.csv"),
              "p.csv": "x_mm,y_mm\n" + "".join(f"{0.39 - 1e-5 * i!r},{-0.6 + 5e-5 * i!r}\n" for i in range(20_000))}),
        Case("points_file missing", "tooth.points_file", {"set.toml": points_tooth(points_file="nope.csv")}),
        Case("points_file name with NUL", "tooth.points_file", {"set.toml": points_tooth(points_file="p\u0000.csv")}),
        Case("points_file a text row", "tooth.points_file", {"set.toml": points_tooth(points_file="p.csv"), "p.csv": bad_rows}),
        Case("points_file nan rows", "tooth.points_file",
             {"set.toml": points_tooth(points_file="p.csv"),
              "p.csv": "x_mm,y_mm\n" + "".join(f"{x!r},{y!r}\n" for x, y in flank()) + "nan,nan\n"}),
        Case("points too few", "tooth.points", {"set.toml": points_tooth(points=flank(5))}),
        Case("points 20 000 inline", "tooth.points", {"set.toml": points_tooth(points=flank(20_000))}),
        Case("points huge coordinates", "tooth.points", {"set.toml": points_tooth(points=[[x * 1e300, y] for x, y in flank()])}),
        Case("points nan", "tooth.points", {"set.toml": points_tooth(points=flank()[:6] + [[math.nan, 0.0]] + flank()[7:])}),
        Case("points tip to root", "tooth.points", {"set.toml": points_tooth(points=flank()[::-1])}),
        Case("points above the pitch line", "tooth.points", {"set.toml": points_tooth(points=[[0.3, 0.05 + 0.03 * i] for i in range(10)])}),
        Case("points repeated", "tooth.points", {"set.toml": points_tooth(points=flank()[:4] + flank()[3:])}),
        Case("points not pairs", "tooth.points", {"set.toml": points_tooth(points=[[0.3, 0.1, 0.2]] * 10)}),
        Case("points crossing", "tooth", {"set.toml": points_tooth(points=crossing)}),
        Case("points looping", "tooth.", {"set.toml": points_tooth(points=looping)}),
        Case("points zigzag", "tooth.", {"set.toml": points_tooth(points=zigzag)}),
        Case("points and points_file", "tooth.points", {"set.toml": points_tooth(points=flank(), points_file="p.csv")}),
    ]
    # scenes (design only)
    ok = {"set.toml": gearset_with()}
    out += [
        Case("--scene /dev/zero", "/dev/zero", dict(ok), scene="/dev/zero", check=False),
        Case("--scene a FIFO", "fifo.toml", dict(ok, **{"fifo.toml": "FIFO"}), scene="fifo.toml", check=False),
        Case("--scene a folder", "dir: is a folder", dict(ok, **{"dir": "DIR"}), scene="dir/", check=False),
        Case("--scene unknown name", "scene", dict(ok), scene="fast", check=False),
        Case("--scene missing file", "nope.toml", dict(ok), scene="nope.toml", check=False),
        Case("--scene malformed", "s.toml", dict(ok, **{"s.toml": f"[fast\n{CANARY}\n"}), scene="s.toml", check=False),
        Case("--scene oversized", "s.toml", dict(ok, **{"s.toml": ("# " + CANARY + "\n") * 180_000}), scene="s.toml",
             check=False),
        Case("--scene bad key", "n_t", dict(ok, **{"s.toml": '[fast]\ntier = "sketch"\nn_t = 1e12\n'}),
             scene="s.toml", check=False),
    ]
    return out


# --------------------------------------------------------------------------- running


@dataclass
class Run:
    code: int | None
    stderr: list[str]
    stdout: str
    seconds: float
    rss_mb: float


def run(argv: list[str], cwd: Path, *, as_bytes: int, timeout: float) -> Run:
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (as_bytes, as_bytes))

    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MPLBACKEND="Agg")
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen(argv, cwd=cwd, stdout=out, stderr=err, stdin=subprocess.DEVNULL, preexec_fn=limit,
                                env=env, start_new_session=True)
        code, usage = None, None
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                code = os.waitstatus_to_exitcode(status)
                break
            if time.perf_counter() - t0 > timeout:
                os.killpg(proc.pid, signal.SIGKILL)
                _, status, usage = os.wait4(proc.pid, 0)
                break
            time.sleep(0.02)
        seconds = time.perf_counter() - t0
        proc.returncode = code if code is not None else -9
        out.seek(0)
        err.seek(0)
        stderr = err.read().decode("utf-8", "replace").splitlines()
        return Run(code, stderr, out.read().decode("utf-8", "replace"), seconds, usage.ru_maxrss / 1024.0)


def materialise(case: Case, folder: Path) -> None:
    for name, content in case.files.items():
        path = folder / name
        if content == "FIFO":
            os.mkfifo(path)
        elif content == "DIR":
            path.mkdir()
        elif isinstance(content, dict):
            path.write_text(dumps(content))
        elif isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content)


def judge(case: Case, which: str, r: Run, *, folder: Path, before: set, args) -> list[str]:
    bad = []
    if r.code != 2:
        bad.append(f"{which}: exit {r.code}")
    if which == "design" and len(r.stderr) != 1:
        bad.append(f"{which}: {len(r.stderr)} stderr lines")
    if which == "check" and not r.stderr:
        bad.append("check: no stderr")
    if which == "design" and not all(case.expect in line for line in r.stderr):
        bad.append(f"design: a line without {case.expect!r}")
    if which == "check":  # one line per problem, each naming the file once; the expected one among them
        if not any(case.expect in line for line in r.stderr):
            bad.append(f"check: no line with {case.expect!r}")
        named = [line for line in r.stderr if line.split(": ", 1)[0].endswith(case.gearset)]
        if len(named) != len(r.stderr):
            bad.append("check: a line not starting with the file")
    if CANARY in r.stdout or CANARY in "\n".join(r.stderr) or "s3cr3t" in "\n".join(r.stderr):
        bad.append(f"{which}: file content echoed")
    if (folder / "out").exists():
        bad.append(f"{which}: wrote the output folder")
    left = {p.name for p in folder.iterdir()} - before
    if left:
        bad.append(f"{which}: left {sorted(left)}")
    if r.rss_mb > args.max_rss_mb:
        bad.append(f"{which}: {r.rss_mb:.0f} MB")
    if r.seconds > args.max_seconds:
        bad.append(f"{which}: {r.seconds:.1f} s")
    return bad


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-k", default="", help="run only cases whose name contains this text")
    ap.add_argument("-v", action="store_true", help="print each case's stderr")
    ap.add_argument("--as-gb", type=float, default=2.0, help="address-space limit per run (GB, default 2)")
    ap.add_argument("--max-rss-mb", type=float, default=1024.0)
    ap.add_argument("--max-seconds", type=float, default=10.0)
    ap.add_argument("--timeout", type=float, default=60.0)
    args = ap.parse_args(argv)
    selected = [c for c in cases() if args.k in c.name]
    names = [c.name for c in cases()]
    assert len(names) == len(set(names)), "case names must be distinct"
    exe = [sys.executable, "-m", "profilegen"]
    rows, failures = [], 0
    peak_rss, peak_s = 0.0, 0.0
    with tempfile.TemporaryDirectory(prefix="bad_inputs_") as tmp:
        for i, case in enumerate(selected, 1):
            folder = Path(tmp) / f"case{i:03d}"
            folder.mkdir()
            materialise(case, folder)
            before = {p.name for p in folder.iterdir()}
            runs = {}
            if case.check:
                runs["check"] = run(exe + ["check", case.gearset], folder, as_bytes=int(args.as_gb * 2**30),
                                    timeout=args.timeout)
            runs["design"] = run(exe + ["design", case.gearset, "--scene", case.scene, "--out", "out", "-q"], folder,
                                 as_bytes=int(args.as_gb * 2**30), timeout=args.timeout)
            bad = [b for which, r in runs.items() for b in judge(case, which, r, folder=folder, before=before, args=args)]
            failures += bool(bad)
            rss = max(r.rss_mb for r in runs.values())
            secs = max(r.seconds for r in runs.values())
            peak_rss, peak_s = max(peak_rss, rss), max(peak_s, secs)
            first = runs["design"].stderr[0] if runs["design"].stderr else ""
            shown = first.removeprefix("profilegen: error: ")
            shown = shown if len(shown) <= 110 else shown[:107] + "..."
            codes = "/".join(str(r.code) for r in runs.values())
            rows.append(f"| {i} | {case.name} | {codes} | {len(runs['design'].stderr)} | {rss:.0f} | {secs:.1f} | "
                        f"{'ok' if not bad else 'FAIL: ' + '; '.join(bad)} | {shown.replace('|', '/')} |")
            if args.v:
                for which, r in runs.items():
                    for line in r.stderr:
                        print(f"    [{case.name}] {which}: {line}", file=sys.stderr)
            print(f"{i:3d}/{len(selected)} {'ok  ' if not bad else 'FAIL'} {case.name}", file=sys.stderr, flush=True)
            shutil.rmtree(folder, ignore_errors=True)
    print("| # | case | exit (check/design) | design stderr lines | peak RSS MB | max s | verdict | design's message |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    print(f"\n{len(selected)} cases ({sum(c.check for c in selected)} also through check), {failures} misbehaved; "
          f"peak RSS {peak_rss:.0f} MB, slowest run {peak_s:.1f} s (limits {args.max_rss_mb:.0f} MB, "
          f"{args.max_seconds:g} s; RLIMIT_AS {args.as_gb:g} GB)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
