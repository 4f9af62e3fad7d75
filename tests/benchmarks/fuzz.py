"""The gear-set fuzz at benchmark size: 10 000 hypothesis examples (or more) through every scene
and into files, spread over worker processes, each chunk with its own seed.

    python tests/benchmarks/fuzz.py [--examples 10000] [--workers 2]
                                    [--design-share 0.03] [--verify-share 0.001] [--write-share 0.25]
    python tests/benchmarks/fuzz.py --replay export/bench/fuzz_failures/20261124-001.json

The gear sets are those of the CI test (``tests/property/test_pipeline_fuzz.py``): DCTA,
involute and point-list teeth (clean, noisy, crossing, looping), m 0.1–2 mm, z1 60–600, 2–4
waves, z2 − z1 = U or 2U, one draw in six with a spoiled field. Each example is designed in a
scene — ``sketch`` mostly, ``design`` with probability ``--design-share``, ``verify`` with
``--verify-share`` (a verify design takes ~40 s on the default set and several minutes at
z1 = 600, a design-scene one ~5–20 s, a sketch ~1 s) — and its files are written with
``write_design`` into a temporary folder (all design and verify results, with figures;
``--write-share`` of the sketch ones, without). Every worker runs under a 4 GB address-space cap (RLIMIT_AS) and
every example under a time limit, so a runaway is counted, not an OOM kill of the machine.

Outcomes: ``ok``; a named error (the ProfilegenError subclass); ``CRASH`` (any other exception,
a MemoryError under the cap included); ``NON-FINITE`` (NaN or infinity in the result or its
files); ``OVER-TIME`` (past ``--time-limit-s``, scaled ×3 for design and ×5 for verify). A
failure does not stop the run. Writes export/bench/fuzz.json (counts, times, failures),
export/bench/fuzz_failures.csv (one row per failing example: outcome, scene, tooth kind, time,
error, reproducer command) and export/bench/fuzz_failures/<seed>-<k>.json (the scene and gear
set of each, written when it fails, which ``--replay`` runs again in-process with the traceback
shown); prints the counts
table; exits 1 if any example failed.

The command-line fuzz (``--cli``, issue 26): every example is a set of files in a temporary
folder run through the ``profilegen`` command in a subprocess under a 4 GB address-space cap
(RLIMIT_AS) and a per-example timeout: ``profilegen.cli.main`` in a child forked from a worker that
has imported the package once (``--cli-exec``: ``python -m profilegen`` started for each).
Run it from a copy of a commit (``git archive HEAD | tar -x -C DIR``, then ``cd DIR``): the
script imports the package of the tree it sits in, not others' uncommitted work. Five kinds of
example: ``check`` and ``design`` of a drawn gear set (the strategy above; design in the sketch
scene), ``scene`` (a bundled set designed in a scene file: the sketch scene with its keys
redrawn, inside and beyond their documented ranges), ``sweep`` (a spec of 1–2 grid points or a
1–2 point sample over the fields below, the sketch scene) and ``optimize`` (population 4, 1
generation (one in four 2), no confirm scene); two specs in three are spoiled (an unknown key,
a wrong type, a non-finite or out-of-range value, a bad name, a long string, a field the gear set
has not). Outcomes: ``ok`` (exit 0, no traceback), ``named`` (exit 2, one line on stderr, no
traceback; ``check``: one line per problem, each naming the file and the field) and anything
else, by name: ``TRACEBACK``, ``EXIT-<n>``, ``MULTI-LINE`` (exit 2 with more than one line),
``TIMEOUT``, ``KILLED``. The summary also counts the named errors whose line names no field,
scene key or option: a field of the schema (a gear-set ``section.key`` of
profilegen.gearset.sections, a spec table's key, a scene or spec key, ``names_a_field``).

    python tests/benchmarks/fuzz.py --cli [--examples 2000] [--workers 2] [--time-limit-s 90]
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import re
import statistics
import sys
import time
import traceback
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

FAILURES = ("CRASH", "NON-FINITE", "OVER-TIME")
SCENE_TIME_FACTOR = {"sketch": 1.0, "design": 3.0, "verify": 5.0}


def _classify(data: dict, scene: str, limit_s: float, write: bool) -> tuple[str, str]:
    """(outcome, error text) of one example; runs it under ``time_limit``."""
    from tests.property.fuzzrun import OverTime, outcome, time_limit

    try:
        with time_limit(limit_s):
            return outcome(data, scene, figure=scene != "sketch", write=write), ""
    except OverTime as exc:
        return "OVER-TIME", str(exc)
    except AssertionError:
        return "NON-FINITE", traceback.format_exc()
    except Exception:  # noqa: BLE001 — the fuzz records every crash and goes on
        return "CRASH", traceback.format_exc()


def _worker(args: tuple[int, int, float, float, float, float, str]) -> dict:
    """Run ``n`` examples with hypothesis seed ``seed``: outcomes per (scene, kind), failures, times.
    Each failure is also written at once to ``fail_dir``/<seed>-<k>.json (a killed run keeps them)."""
    n, seed, design_share, verify_share, limit_s, write_share, fail_dir = args
    import logging

    from hypothesis import HealthCheck, given, settings
    from hypothesis import seed as hseed

    import numpy as np

    from tests.property.fuzzrun import memory_cap
    from tests.property.gearsets import KINDS, gear_sets

    logging.disable(logging.WARNING)
    rows: list[tuple[str, str, str, float]] = []  # scene, kind, outcome, seconds
    failures: list[dict] = []
    # the scene is not drawn by hypothesis (its integers lean to the low end): a seeded generator
    # gives the shares asked for
    rng = np.random.default_rng(seed)

    @hseed(seed)
    @settings(max_examples=n, deadline=None, database=None, derandomize=False,
              suppress_health_check=list(HealthCheck))
    @given(gear_sets())
    def run(data):
        r = rng.random()
        scene = "verify" if r < verify_share else "design" if r < verify_share + design_share else "sketch"
        tooth = data.get("tooth")
        kind = tooth.get("kind") if isinstance(tooth, dict) else None
        kind = kind if kind in KINDS else "spoiled"
        t0 = time.perf_counter()
        write = scene != "sketch" or rng.random() < write_share
        name, error = _classify(data, scene, limit_s * SCENE_TIME_FACTOR[scene], write)
        dt = time.perf_counter() - t0
        rows.append((scene, kind, name, dt))
        if name in FAILURES:
            fail = {"outcome": name, "scene": scene, "kind": kind, "seconds": dt, "error": error,
                    "seed": seed, "gearset": data}
            path = Path(fail_dir) / f"{seed}-{len(failures) + 1:03d}.json"
            path.write_text(json.dumps(fail, indent=1, default=str))
            failures.append(fail | {"path": str(path)})

    with memory_cap():
        run()
    return {"rows": rows, "failures": failures}


def _table(rows, key) -> str:
    """Counts of outcomes (columns) per ``key(row)`` (rows of the table), with totals."""
    groups = sorted({key(r) for r in rows})
    names = sorted({r[2] for r in rows}, key=lambda s: (s != "ok", s in FAILURES, s))
    width = max([len(n) for n in names] + [8])
    head = f"{'':>9} " + " ".join(f"{n:>{width}}" for n in names) + f" {'total':>7}"
    lines = [head]
    for g in groups + ["total"]:
        sel = [r for r in rows if g == "total" or key(r) == g]
        c = Counter(r[2] for r in sel)
        lines.append(f"{g:>9} " + " ".join(f"{c.get(n, 0):>{width}}" for n in names) + f" {len(sel):>7}")
    return "\n".join(lines)


def _replay(path: Path) -> int:
    from tests.property.fuzzrun import memory_cap, outcome

    case = json.loads(path.read_text())
    print(f"replaying {path}: scene {case['scene']}, tooth kind {case['kind']} (was {case['outcome']})")
    with memory_cap():
        t0 = time.perf_counter()
        name = outcome(case["gearset"], case["scene"], figure=case["scene"] != "sketch")  # raises on a failure
    print(f"outcome: {name} in {time.perf_counter() - t0:.1f} s")
    return 0

# ---------------------------------------------------------------------------------------------
# the command-line fuzz (--cli)

CLI_KINDS = ("check", "design", "scene", "sweep", "optimize")
#: shares of the example kinds. Unloaded: a check 0.4 s (forked), a sketch design ~5 s, a sweep
#: 4 s, an optimize (population 4, one generation) 7 s, a spoiled spec ~0.4 s; at a load of 17 on
#: the 2-core machine each ~10x that, so the cheap kinds are most of the 2000 examples
CLI_SHARES = (0.70, 0.04, 0.10, 0.10, 0.06)
#: share of sweep / optimize specs spoiled (the rest run)
SPOIL_SHARE = 2 / 3
#: sweep / optimize fields of the bundled sets with a sane range and a spoiling one
SPEC_FIELDS = {
    "wave_generator.deflection_coefficient": (0.85, 1.15),
    "tooth.pressure_angle_deg": (6.0, 14.0),
    "gear.rim_thickness_mm": (0.7, 1.1),
    "circular_spline.root_clearance_mm": (0.05, 0.2),
    "circular_spline.tip_clearance_mm": (0.05, 0.2),
    "tooth.addendum_coefficient": (0.6, 0.9),
}
INT_FIELDS = {"face.sections": (3, 7)}  # an integer field every bundled set takes
SWEEP_OUTPUTS = ("profile_max_error_mm", "min_clearance_mm", "deflection_mm", "cs_tip_radius_mm")
OPT_OUTPUTS = ("profile_max_error_mm", "min_clearance_mm", "stress_min_safety", "deflection_mm",
               "profile_max_backlash_mm")
BAD_SPEC_VALUES = (0, -1, 1e300, -1e300, math.nan, math.inf, "text", True, [], {}, "=HYPERLINK(\"x\")",
                   "x" * 5000, 2**63, 0.5)
SCENE_KEYS = {  # key: (kind, documented range) — profilegen/pipeline/scenes.py _KEYS
    "chord_tol_mm": ("log", (1e-9, 1e-2)), "n_t": ("count", (8, 100_000)), "n_phi": ("count", (11, 100_000)),
    "clearance_samples": ("count", (3, 100_000)), "fit_check_positions": ("count", (3, 100_000)),
    "face_slices": ("count", (0, 33)), "brute_force_check": ("bool", None), "figures": ("choice", ("all", "none")),
}


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v) if -2**63 <= v < 2**63 else json.dumps(str(v))
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {_toml_value(x)}" for k, x in v.items()) + "}"
    return json.dumps(str(v))


def toml_text(data: dict) -> str:
    """A mapping of scalars and one level of tables (values may be inline tables) as TOML."""
    lines = [f"{json.dumps(k)} = {_toml_value(v)}" for k, v in data.items() if not isinstance(v, dict)]
    for name, table in data.items():
        if isinstance(table, dict):
            lines += ["", f"[{json.dumps(name)}]"] + [f"{json.dumps(k)} = {_toml_value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


def _spoil_spec(rng, spec: dict, tables: tuple[str, ...]) -> dict:
    """One field of a sweep/optimize spec made wrong."""
    import copy

    spec = copy.deepcopy(spec)
    how = rng.choice(["top", "table", "unknown", "remove", "name", "field", "gearset", "scene"])
    if how == "top":
        spec[str(rng.choice([k for k in spec if not isinstance(spec[k], dict)] or ["name"]))] = \
            BAD_SPEC_VALUES[rng.integers(len(BAD_SPEC_VALUES))]
    elif how == "table":
        t = str(rng.choice([t for t in tables if t in spec]))
        if spec[t]:
            k = str(rng.choice(list(spec[t])))
            spec[t][k] = BAD_SPEC_VALUES[rng.integers(len(BAD_SPEC_VALUES))]
        else:
            spec[t] = BAD_SPEC_VALUES[rng.integers(len(BAD_SPEC_VALUES))]
    elif how == "unknown":
        spec["colour" if rng.random() < 0.5 else str(rng.choice(tables))] = {"x": 1} if rng.random() < 0.5 else 1
    elif how == "remove":  # not [search]: without it the default 16 x 10 search runs (160 designs, minutes)
        spec.pop(str(rng.choice([k for k in spec if k != "search"])))
    elif how == "name":
        spec["name"] = str(rng.choice(["..", "a/b", "Rim.Study\n[x]", "", "é" * 300, "x" * 101, "-", "con"]))
    elif how == "field":
        t = str(rng.choice([t for t in tables if t in spec and isinstance(spec[t], dict)] or [tables[0]]))
        spec.setdefault(t, {})
        spec[t][str(rng.choice(["gear.colour", "tooth", "gear..module_mm", "", "tooth.points_file", "name",
                                "gear.module_mm.x", "wave_generator.contour"]))] = [0.1, 0.2]
    elif how == "gearset":
        spec["gearset"] = str(rng.choice(["nope", "../../etc/passwd", "/dev/zero", "", "default.toml", "x" * 4000]))
    else:
        spec["scene"] = str(rng.choice(["nope", "/dev/zero", "verify#x", "scenes.toml#nope", "", "SKETCH"]))
    return spec


def _sweep_spec(rng) -> dict:
    spec = {"name": f"fz{rng.integers(1e6)}", "gearset": str(rng.choice(["default", "seed001_shf25"])),
            "scene": "sketch", "plot": str(rng.choice(SWEEP_OUTPUTS))}
    names = list(SPEC_FIELDS) + list(INT_FIELDS)
    fields = [str(f) for f in rng.choice(names, size=int(rng.integers(1, 3)), replace=False)]
    if len(fields) == 2 or rng.random() < 0.6:  # a grid of at most 2 points
        grid, left = {}, 2
        for f in fields:
            lo, hi = SPEC_FIELDS.get(f) or INT_FIELDS[f]
            k = int(rng.integers(1, left + 1)) if f == fields[-1] else 1
            left = max(1, left // k)
            grid[f] = [int(rng.integers(lo, hi + 1)) if f in INT_FIELDS else float(rng.uniform(lo, hi))
                       for _ in range(k)]
        spec["grid"] = grid
    else:
        f = fields[0]
        lo, hi = SPEC_FIELDS.get(f) or INT_FIELDS[f]
        spec["sample"] = {"method": str(rng.choice(["lhs", "random"])), "n": int(rng.integers(1, 3)),
                          "seed": int(rng.integers(0, 100)), f: [lo, hi]}
    if rng.random() < SPOIL_SHARE:
        spec = _spoil_spec(rng, spec, ("grid", "sample"))
    return spec


def _optimize_spec(rng) -> dict:
    names = list(SPEC_FIELDS) + list(INT_FIELDS)
    fields = [str(f) for f in rng.choice(names, size=int(rng.integers(1, 3)), replace=False)]
    variables = {}
    for f in fields:
        lo, hi = SPEC_FIELDS.get(f) or INT_FIELDS[f]
        variables[f] = [int(lo), int(hi)] if f in INT_FIELDS else [lo, hi]
    objectives = {str(o): str(rng.choice(["min", "max"]))
                  for o in rng.choice(OPT_OUTPUTS, size=int(rng.integers(1, 3)), replace=False)}
    spec = {"name": f"fz{rng.integers(1e6)}", "gearset": "default", "scene": "sketch", "confirm_scene": "",
            "search": {"population": 4, "generations": int(rng.choice([1, 1, 1, 2])),
                       "seed": int(rng.integers(0, 100))},
            "variables": variables, "objectives": objectives}
    if rng.random() < 0.5:
        out = str(rng.choice(OPT_OUTPUTS))
        spec["constraints"] = {out: {"min": float(rng.uniform(-1, 1)), "scale": 0.001}}
    if rng.random() < SPOIL_SHARE:
        spec = _spoil_spec(rng, spec, ("search", "variables", "objectives", "constraints"))
    return spec


def _scene_file(rng) -> dict:
    """The sketch scene with 1–3 keys redrawn: mostly near their defaults, one in four at or
    beyond an end of the documented range (the budget's and the validation's cases)."""
    import tomllib

    base = tomllib.loads((ROOT / "profilegen" / "pipeline" / "scenes.toml").read_text())["sketch"]
    scene = dict(base, tier="sketch")
    for key in rng.choice(list(SCENE_KEYS), size=int(rng.integers(1, 4)), replace=False):
        kind, rng_ = SCENE_KEYS[str(key)]
        extreme = rng.random() < 0.25
        if kind == "log":
            lo, hi = rng_
            scene[key] = float(rng.choice([lo, hi, 1e-300, 0.0, -1e-6, 0.1])) if extreme else \
                float(10 ** rng.uniform(-6.5, -3))
        elif kind == "count":
            lo, hi = rng_
            d = base.get(key, lo if key != "face_slices" else 1)
            scene[key] = int(rng.choice([lo, hi, lo - 1, hi + 1, 10**9])) if extreme else \
                int(max(lo, min(hi, round(d * 2 ** rng.uniform(-2, 1.5)))))
        elif kind == "bool":
            scene[key] = bool(rng.random() < 0.3) if not extreme else "yes"
        else:
            scene[key] = str(rng.choice(rng_)) if not extreme else "some"
    return {"fz": scene}


def cli_example(rng, kind: str, gearset: dict | None) -> tuple[dict, list[str]]:
    """The files (name → text) and the argument list of one command-line example."""
    if kind in ("check", "design"):
        files = {"gs.toml": toml_text(gearset)}
        args = ["check", "gs.toml"] if kind == "check" else ["design", "gs.toml", "--scene", "sketch", "--out",
                                                                "out", "-q"]
    elif kind == "scene":
        files = {"scene.toml": toml_text(_scene_file(rng))}
        args = ["design", str(rng.choice(["default", "seed001_shf25", "seed002_short_cup"])), "--scene",
                "scene.toml#fz", "--out", "out", "-q"]
    elif kind == "sweep":
        files = {"spec.toml": toml_text(_sweep_spec(rng))}
        args = ["sweep", "spec.toml", "--workers", "1", "--out", "out", "-q"]
    else:
        files = {"spec.toml": toml_text(_optimize_spec(rng))}
        args = ["optimize", "spec.toml", "--workers", "1", "--out", "out", "-q"]
    return files, args


def _cap(limit: int = 4_000_000_000):
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def run_cli(files: dict, args: list[str], limit_s: float) -> tuple[str, str, float]:
    """(outcome, stderr's last lines, seconds) of one example run as ``python -m profilegen``."""
    import os
    import subprocess
    import tempfile

    with tempfile.TemporaryDirectory(prefix="fuzzcli-") as tmp:
        for name, text in files.items():
            Path(tmp, name).write_text(text)
        env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MPLBACKEND="Agg",
                   PYTHONPATH=str(ROOT))  # this tree's package, not the editable install's
        t0 = time.perf_counter()
        try:
            p = subprocess.run([sys.executable, "-m", "profilegen", *args], cwd=tmp, env=env, capture_output=True,
                               text=True, timeout=limit_s, preexec_fn=_cap)
        except subprocess.TimeoutExpired:
            return "TIMEOUT", f"over {limit_s:g} s", time.perf_counter() - t0
        dt = time.perf_counter() - t0
    return _outcome(p.returncode, p.stderr.strip(), dt, args[0])


def _preload() -> None:
    """Import what the command imports, once per worker: each example's process is then forked
    from here (run_cli_forked) instead of starting an interpreter (~1 s of a 1.3 s check)."""
    import matplotlib

    matplotlib.use("Agg")
    import profilegen.cli  # noqa: F401
    import profilegen.pipeline.design  # noqa: F401
    import profilegen.studies.sweep  # noqa: F401
    import profilegen.studies.optimize  # noqa: F401
    import scipy.optimize  # noqa: F401


def run_cli_forked(files: dict, args: list[str], limit_s: float) -> tuple[str, str, float]:
    """:func:`run_cli`, the command run as ``profilegen.cli.main(args)`` in a child forked from this
    (preloaded) process: its own process group, working folder, stderr file, 4 GB RLIMIT_AS and
    exit code — what ``python -m profilegen ARGS`` does, less the interpreter's start. An exception
    out of main is printed with its traceback (as the interpreter would) and exits 1."""
    import os
    import signal
    import tempfile

    with tempfile.TemporaryDirectory(prefix="fuzzcli-") as tmp:
        for name, text in files.items():
            Path(tmp, name).write_text(text)
        err_path = Path(tmp, ".stderr")
        t0 = time.perf_counter()
        pid = os.fork()
        if pid == 0:  # the child: never returns
            code = 1
            try:
                os.setpgid(0, 0)
                os.chdir(tmp)
                fd = os.open(err_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
                null = os.open(os.devnull, os.O_WRONLY)
                sys.stdout.flush()
                sys.stderr.flush()
                os.dup2(null, 1)
                os.dup2(fd, 2)
                _cap()
                sys.argv = ["profilegen", *args]
                from profilegen.cli import main

                code = main(list(args))
            except SystemExit as exc:
                code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
            except BaseException:  # noqa: BLE001 — what the interpreter does with an uncaught exception
                traceback.print_exc()
                code = 1
            finally:
                try:
                    sys.stdout.flush()
                    sys.stderr.flush()
                finally:
                    os._exit(code if isinstance(code, int) else 1)
        status = None
        while time.perf_counter() - t0 < limit_s:
            done, status = os.waitpid(pid, os.WNOHANG)
            if done:
                break
            time.sleep(0.02)
        else:
            try:
                os.killpg(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            os.waitpid(pid, 0)
            return "TIMEOUT", f"over {limit_s:g} s", time.perf_counter() - t0
        try:
            os.killpg(pid, signal.SIGKILL)  # anything the command left running in its group
        except ProcessLookupError:
            pass
        dt = time.perf_counter() - t0
        returncode = os.waitstatus_to_exitcode(status)
        err = err_path.read_text(errors="replace").strip() if err_path.exists() else ""
    return _outcome(returncode, err, dt, args[0])


def every_line_a_check_problem(err: str) -> bool:
    """``profilegen check`` prints every problem of a file, one line each, naming the file and the
    field (``gs.toml: gear.module_mm = ...``): several lines of that form are its named error."""
    lines = err.strip().splitlines()
    return bool(lines) and all(re.match(r"^\S+\.toml: [a-z_]+(\.[A-Za-z_]+)?\b", ln) for ln in lines)


def _outcome(returncode: int, err: str, dt: float, command: str = "") -> tuple[str, str, float]:
    lines = err.splitlines()
    if "Traceback (most recent call last)" in err or "MemoryError" in err:
        return "TRACEBACK", "\n".join(lines[-6:]), dt
    if returncode < 0:
        return "KILLED", f"signal {-returncode}: " + "\n".join(lines[-3:]), dt
    if returncode == 0:
        return "ok", "", dt
    if returncode == 2:
        if len(lines) == 1 or (command == "check" and every_line_a_check_problem(err)):
            return "named", lines[0] if lines else "", dt
        return "MULTI-LINE", err[-2000:], dt
    return f"EXIT-{returncode}", "\n".join(lines[-6:]), dt


def _cli_worker(job: tuple[int, int, float, str, bool]) -> dict:
    """``n`` examples with seed ``seed``: the gear sets drawn by hypothesis, the rest by a seeded
    generator; each failure written at once to ``fail_dir``/cli-<seed>-<k>.json."""
    n, seed, limit_s, fail_dir, fork = job
    import numpy as np
    from hypothesis import HealthCheck, given, settings
    from hypothesis import seed as hseed

    from tests.property.gearsets import gear_sets

    rng = np.random.default_rng(seed)
    kinds = [str(k) for k in rng.choice(CLI_KINDS, size=n, p=CLI_SHARES)]
    need = sum(k in ("check", "design") for k in kinds)
    drawn: list[dict] = []
    if need:
        @hseed(seed)
        @settings(max_examples=need, deadline=None, database=None, suppress_health_check=list(HealthCheck))
        @given(gear_sets())
        def draw(data):
            drawn.append(data)

        draw()
    rows, failures = [], []
    for i, kind in enumerate(kinds):
        gs = drawn.pop() if kind in ("check", "design") and drawn else None
        if kind in ("check", "design") and gs is None:
            kind = "scene"
        files, args = cli_example(rng, kind, gs)
        if fork:
            _preload()
        name, err, dt = (run_cli_forked if fork else run_cli)(files, args, limit_s)
        rows.append((kind, name, dt, err if name == "named" else ""))
        with open(Path(fail_dir).parent / "fuzz_cli_rows.jsonl", "a") as f:  # a killed run keeps its rows
            f.write(json.dumps({"seed": seed, "kind": kind, "outcome": name, "seconds": round(dt, 2),
                                "error": err[:300]}) + "\n")
        if name not in ("ok", "named"):
            fail = {"outcome": name, "kind": kind, "seconds": dt, "error": err, "args": args, "files": files}
            path = Path(fail_dir) / f"cli-{seed}-{len(failures) + 1:03d}.json"
            path.write_text(json.dumps(fail, indent=1))
            failures.append(fail | {"path": str(path)})
    return {"rows": rows, "failures": failures}


def schema_fields() -> tuple[set[str], set[str]]:
    """What a user can change, from the schema itself: (dotted paths — every gear-set
    ``section.key`` of profilegen.gearset.sections, every kind's tooth keys, the sweep/optimize spec
    tables' keys —, bare keys — the scene keys of profilegen.pipeline.scenes and the specs' top-level keys)."""
    from profilegen.pipeline import scenes
    from profilegen.gearset import sections as sec
    from profilegen.studies.optimize import spec as ospec
    from profilegen.studies import sweep

    tables = {"gear": sec.GEAR_KEYS, "wave_generator": sec.WAVE_GENERATOR_KEYS, "material": sec.MATERIAL_KEYS,
              "torque": sec.TORQUE_KEYS, "circular_spline": sec.CIRCULAR_SPLINE_KEYS, "cup": sec.CUP_KEYS,
              "face": sec.FACE_KEYS, "requirements": sec.REQUIREMENTS_KEYS,
              "tooth": tuple({k for keys in sec.TOOTH_KEYS.values() for k in keys} | {"kind", "points", "points_file"}),
              "search": ospec._SEARCH_KEYS, "sample": sweep._SAMPLE_KEYS}
    dotted = {f"{t}.{k}" for t, keys in tables.items() for k in keys}
    bare = set(scenes._KEYS) | set(sec.TOP_KEYS) | set(sweep._TOP_KEYS) | set(ospec._TOP_KEYS)
    bare |= {"constraints", "objectives", "variables"}
    return dotted, bare - {"n", "seed", "min", "max", "description", "source"}


_FIELDS: re.Pattern | None = None


def names_a_field(line: str) -> bool:
    """Whether an error line names something the user can change: a field of the schema
    (:func:`schema_fields`: a gear-set ``section.key``, a spec table's key, a scene or spec key)
    or a command-line option (``--name``). A section alone (``tooth: ...``) names no field."""
    global _FIELDS
    if _FIELDS is None:
        dotted, bare = schema_fields()
        words = sorted(dotted | bare, key=len, reverse=True)
        _FIELDS = re.compile(r"(?<![\w.])(" + "|".join(map(re.escape, words)) + r")(?![\w])|(?<![\w-])--[a-z]")
    body = line.removeprefix("profilegen: error: ")
    body = re.sub(r"^\S+\.toml: ", "", body)  # the file's own name is not a field
    # an unknown key the user wrote is named as written ("circular_spline.spark_gap_mm_typo: unknown key")
    return bool(_FIELDS.search(body) or re.search(r"\b[a-z_]+\.\S+: unknown key", body))


def _stage_part(line: str) -> str:
    return re.sub(r"[-+]?\d[\d.e+-]*", "#", line.removeprefix("profilegen: error: "))[:90]


def cli_table(rows, failures) -> None:
    """The counts per example kind (rows: (kind, outcome, seconds, named error)) and the failures."""
    names = ["ok", "named"] + sorted({r[1] for r in rows} - {"ok", "named"})
    print(f"{'':>9} " + " ".join(f"{n:>10}" for n in names) + f" {'total':>7} {'median s':>9} {'max s':>7}")
    for kind in list(CLI_KINDS) + ["total"]:
        sel = [r for r in rows if kind == "total" or r[0] == kind]
        if not sel:
            continue
        c = Counter(r[1] for r in sel)
        t = [r[2] for r in sel]
        print(f"{kind:>9} " + " ".join(f"{c.get(n, 0):>10}" for n in names) + f" {len(sel):>7} "
              f"{statistics.median(t):>9.2f} {max(t):>7.1f}")
    named = Counter(r[3].removeprefix("profilegen: error: ").split(": ", 2)[-2][:70] if r[3].count(": ") > 1
                    else r[3][:70] for r in rows if r[1] == "named")
    print("\nmost frequent named errors (the key each names):")
    for text, n in named.most_common(12):
        print(f"  {n:>5}  {text}")
    unnamed = Counter(_stage_part(r[3]) for r in rows if r[1] == "named" and not names_a_field(r[3]))
    print(f"\nnamed errors whose line names no field, scene key or option: {sum(unnamed.values())}")
    for text, n in unnamed.most_common(12):
        print(f"  {n:>5}  {text}")
    print(f"\nanything else: {len(failures)}" + "".join(
        f"\n  {f['outcome']} {f['kind']} ({f['path']}): "
        f"{f['error'].strip().splitlines()[-1][:200] if f['error'].strip() else ''}"
        for f in failures[:20]))


def cli_main(args) -> int:
    chunks = max(4 * args.workers, math.ceil(args.examples / 10))
    sizes = [args.examples // chunks + (k < args.examples % chunks) for k in range(chunks)]
    out = Path(args.out)
    fail_dir = out / "fuzz_failures"
    fail_dir.mkdir(parents=True, exist_ok=True)
    for old in fail_dir.glob("cli-*.json"):
        old.unlink()
    (out / "fuzz_cli_rows.jsonl").unlink(missing_ok=True)
    jobs = [(n, args.seed + k, args.time_limit_s, str(fail_dir), not args.cli_exec) for k, n in enumerate(sizes) if n]
    os.environ.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1", MPLBACKEND="Agg")
    t0 = time.perf_counter()
    rows, failures = [], []
    from concurrent.futures import as_completed

    with ProcessPoolExecutor(args.workers) as pool:
        for k, done in enumerate(as_completed([pool.submit(_cli_worker, job) for job in jobs]), start=1):
            part = done.result()
            rows += part["rows"]
            failures += part["failures"]
            c = Counter(r[1] for r in rows)
            print(f"[{k}/{len(jobs)}] {len(rows)} examples, {time.perf_counter() - t0:.0f} s: ok {c.get('ok', 0)}, "
                  f"named {c.get('named', 0)}, else {len(rows) - c.get('ok', 0) - c.get('named', 0)}", flush=True)
    wall = time.perf_counter() - t0
    print(f"\n{len(rows)} command-line examples in {wall:.0f} s on {args.workers} workers "
          f"(4 GB RLIMIT_AS, {args.time_limit_s:g} s per example, "
          f"{'python -m profilegen' if args.cli_exec else 'profilegen.cli.main forked from a preloaded worker'})\n")
    cli_table(rows, failures)
    summary = {"command": "python tests/benchmarks/fuzz.py " + " ".join(sys.argv[1:]), "examples": len(rows),
               "wall_s": wall, "outcomes": dict(Counter(r[1] for r in rows)),
               "by_kind": {k: dict(Counter(r[1] for r in rows if r[0] == k)) for k in CLI_KINDS},
               "named_no_field": sum(r[1] == "named" and not names_a_field(r[3]) for r in rows),
               "failures": [{k: v for k, v in f.items() if k != "files"} for f in failures]}
    (out / "fuzz_cli.json").write_text(json.dumps(summary, indent=1))
    print(f"written: {out / 'fuzz_cli.json'}; replay one: python tests/benchmarks/fuzz.py --replay-cli FILE")
    return 1 if failures else 0


def cli_summary(out: Path) -> int:
    """The table of a run from its rows file (a run killed or still going included)."""
    rows, failures = [], []
    for line in (out / "fuzz_cli_rows.jsonl").read_text().splitlines():
        r = json.loads(line)
        text = r["error"] if r["outcome"] in ("named", "MULTI-LINE") else ""
        rows.append((r["kind"], r["outcome"], r["seconds"], text))
    recheck = 0
    for path in sorted((out / "fuzz_failures").glob("cli-*.json")):
        f = json.loads(path.read_text())
        if f["outcome"] == "MULTI-LINE" and f["args"][0] == "check" and every_line_a_check_problem(f["error"]):
            recheck += 1  # classified before check's several problems counted as its named error
            continue
        failures.append(f | {"path": str(path)})
    if recheck:
        for k, r in enumerate(rows):
            if r[1] == "MULTI-LINE" and r[0] == "check" and recheck:
                rows[k], recheck = (r[0], "named", r[2], r[3]), recheck - 1
    print(f"{len(rows)} command-line examples (from {out / 'fuzz_cli_rows.jsonl'})\n")
    cli_table(rows, failures)
    return 1 if failures else 0


def replay_cli(path: Path) -> int:
    case = json.loads(path.read_text())
    print(f"replaying {path}: {case['kind']} (was {case['outcome']}): profilegen {' '.join(case['args'])}")
    name, err, dt = run_cli(case["files"], case["args"], 600.0)
    print(f"outcome: {name} in {dt:.1f} s\n{err}")
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=10_000, help="examples in all (default 10 000)")
    ap.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--design-share", type=float, default=0.03, help="share of design-scene examples (0.03)")
    ap.add_argument("--verify-share", type=float, default=0.001, help="share of verify-scene examples (0.001)")
    ap.add_argument("--write-share", type=float, default=0.25,
                    help="share of sketch examples whose files are written (0.25; design and verify: all)")
    ap.add_argument("--time-limit-s", type=float, default=120.0,
                    help="per sketch example (×3 design, ×5 verify; default 120)")
    ap.add_argument("--seed", type=int, default=20261124, help="base hypothesis seed")
    ap.add_argument("--out", default=str(ROOT / "export" / "bench"), help="output folder")
    ap.add_argument("--replay", type=Path, help="run one failure file again and show its traceback")
    ap.add_argument("--cli", action="store_true",
                    help="the command-line fuzz: gear sets, scenes, sweep and optimize specs through profilegen")
    ap.add_argument("--replay-cli", type=Path, help="run one command-line failure file again")
    ap.add_argument("--cli-exec", action="store_true",
                    help="with --cli: start `python -m profilegen` for each example "
                         "(default: fork main from a preloaded worker)")
    ap.add_argument("--cli-summary", type=Path, metavar="OUT", help="the table of a command-line run's rows in OUT")
    args = ap.parse_args()
    if args.cli_summary:
        return cli_summary(args.cli_summary)
    if args.replay_cli:
        return replay_cli(args.replay_cli)
    if args.cli:
        return cli_main(args)
    if args.replay:
        return _replay(args.replay)
    if args.examples < 1 or args.workers < 1:
        ap.error("--examples and --workers must be ≥ 1")
    if not (0 <= args.design_share and 0 <= args.verify_share and args.design_share + args.verify_share <= 1):
        ap.error("--design-share and --verify-share must be ≥ 0 with a sum ≤ 1")
    chunks = max(4 * args.workers, math.ceil(args.examples / 100))  # a progress line per ~100 examples
    sizes = [args.examples // chunks + (k < args.examples % chunks) for k in range(chunks)]
    out = Path(args.out)
    fail_dir = out / "fuzz_failures"
    fail_dir.mkdir(parents=True, exist_ok=True)
    for old in fail_dir.glob("*.json"):
        old.unlink()
    jobs = [(n, args.seed + k, args.design_share, args.verify_share, args.time_limit_s, args.write_share,
             str(fail_dir)) for k, n in enumerate(sizes) if n]
    t0 = time.perf_counter()
    rows: list[tuple] = []
    failures: list[dict] = []
    broken = ""
    try:
        with ProcessPoolExecutor(args.workers) as pool:
            for k, part in enumerate(pool.map(_worker, jobs), start=1):
                rows += part["rows"]
                failures += part["failures"]
                c = Counter(r[2] for r in rows)
                print(f"[{k}/{len(jobs)}] {len(rows)} examples, {time.perf_counter() - t0:.0f} s: "
                      f"ok {c.get('ok', 0)}, named {sum(v for n, v in c.items() if n != 'ok' and n not in FAILURES)}, "
                      f"failed {sum(c.get(n, 0) for n in FAILURES)}", flush=True)
    except BrokenProcessPool as exc:  # a worker killed from outside (the caps should prevent it)
        broken = f"a worker process died: {exc}"
        print(broken, flush=True)
    wall = time.perf_counter() - t0

    with open(out / "fuzz_failures.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["outcome", "scene", "tooth_kind", "seconds", "error", "reproducer"])
        for fail in failures:
            path = fail["path"]
            last = fail["error"].strip().splitlines()[-1] if fail["error"].strip() else ""
            w.writerow([fail["outcome"], fail["scene"], fail["kind"], f"{fail['seconds']:.1f}", last[:300],
                        f"python tests/benchmarks/fuzz.py --replay {path}"])

    per_scene = {}
    for scene in SCENE_TIME_FACTOR:
        t = [r[3] for r in rows if r[0] == scene]
        ok = [r[3] for r in rows if r[0] == scene and r[2] == "ok"]
        if t:
            per_scene[scene] = {"examples": len(t), "results": len(ok), "total_s": sum(t),
                                "median_s": statistics.median(t), "max_s": max(t),
                                "median_result_s": statistics.median(ok) if ok else None}
    summary = {
        "command": "python tests/benchmarks/fuzz.py " + " ".join(sys.argv[1:]),
        "examples": len(rows),
        "workers": args.workers,
        "wall_s": wall,
        "design_share": args.design_share,
        "verify_share": args.verify_share,
        "outcomes": dict(Counter(r[2] for r in rows).most_common()),
        "outcomes_by_scene": {s: dict(Counter(r[2] for r in rows if r[0] == s)) for s in SCENE_TIME_FACTOR},
        "outcomes_by_kind": {k: dict(Counter(r[2] for r in rows if r[1] == k)) for k in sorted({r[1] for r in rows})},
        "time_per_scene": per_scene,
        "failures": len(failures),
        "broken": broken,
    }
    (out / "fuzz.json").write_text(json.dumps(summary, indent=1, default=str))
    cpu = sum(r[3] for r in rows)
    print(f"\n{len(rows)} examples in {wall:.0f} s on {args.workers} workers ({cpu:.0f} s of example time)")
    print("\nby scene:\n" + _table(rows, key=lambda r: r[0]))
    print("\nby tooth kind:\n" + _table(rows, key=lambda r: r[1]))
    print("\ntime per example (s):")
    for scene, st in per_scene.items():
        print(f"  {scene:>6}: {st['examples']} examples, median {st['median_s']:.2f}, max {st['max_s']:.1f}, "
              f"total {st['total_s']:.0f}")
    print(f"\nfailures (crash, non-finite, over time): {len(failures)}" + "".join(
        f"\n  {f['outcome']} {f['scene']} {f['kind']}: {f['error'].strip().splitlines()[-1][:200] if f['error'].strip() else ''}"
        for f in failures[:10]))
    print(f"written: {out / 'fuzz.json'}, {out / 'fuzz_failures.csv'}")
    return 1 if failures or broken else 0


if __name__ == "__main__":
    raise SystemExit(main())
