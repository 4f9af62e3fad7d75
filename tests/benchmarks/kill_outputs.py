"""SIGKILL and SIGINT at every moment of a sweep's and an optimisation's output writing: the
folder must hold the old set or the new set, whole, and the next run must finish it from the
journals (computing nothing) and leave nothing beside the folder.

    python tests/benchmarks/kill_outputs.py            # sweep and optimize, SIGKILL and SIGINT
    python tests/benchmarks/kill_outputs.py sweep       # one of them
    PYTHONPATH=/path/to/an/older/checkout python tests/benchmarks/kill_outputs.py   # that version

How: a forked child runs the new set into a folder holding the old set; from the moment the
output writing starts (``Owned.stage`` entered) every step of it is a *moment* — before and
after each file write (``atomic_write``), journal link, folder fsync, the swap and the old set's
deletion (before the folder rule, from the first table written). A dry run counts the moments; then for each moment k a child is killed there (SIGKILL,
or SIGINT: a KeyboardInterrupt in the middle of it). After each kill the folder is compared with
the two reference sets (file names and bytes; CSVs without their time columns; the journal may
only have grown), then the run is repeated and must give the new set. Stand-in designer and
evaluator (no designs): the writing, not the designs, is under test.
"""

from __future__ import annotations

import contextlib
import csv
import hashlib
import io
import json
import os
import re
import shutil
import signal
import sys
import tempfile
import textwrap
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

from profilegen.output import export, folder  # noqa: E402
from profilegen.output import optimize as out_optimize  # noqa: E402

FIELD = "wave_generator.deflection_coefficient"


# ----------------------------------------------------------------------------- the two kinds of run


class _Stub:
    warnings = ()


def _designer(gs, *, scene):
    return _Stub()


def sweep_run(out: Path, new: bool):
    from profilegen.studies.sweep import parse_sweep_spec, run_sweep

    grid = [0.8, 0.9, 1.0] if new else [0.8, 0.9]
    spec = parse_sweep_spec({"name": "k", "gearset": "default", "scene": "sketch", "plot": "warnings",
                             "grid": {FIELD: grid}})
    with ThreadPoolExecutor(max_workers=1) as ex:
        return run_sweep(spec, out, executor=ex, designer=_designer, figure=True, **_wait(run_sweep))


def _evaluate(values, context):
    w = float(values[FIELD])
    return {"profile_max_error_mm": (w - 0.95) ** 2 + 1e-3, "stress_min_safety": 2.0 - w}


def optimize_run(out: Path, new: bool):
    from profilegen.studies.optimize import load_optimize_spec, optimize
    from profilegen.studies.optimize import run as oprun

    oprun.evaluate_design = _evaluate
    spec = SPEC_DIR / ("new.toml" if new else "old.toml")  # one place: the designs' header names it
    objectives = 'profile_max_error_mm = "min"\n' + ("" if new else 'stress_min_safety = "max"\n')
    spec.write_text(textwrap.dedent(f"""\
        name = "k"
        gearset = "default"
        scene = "sketch"
        confirm_scene = ""
        [search]
        population = 6
        generations = 2
        seed = 3
        [variables]
        "{FIELD}" = [0.85, 1.05]
        [objectives]
        """) + objectives)
    with ThreadPoolExecutor(max_workers=1) as ex:
        return optimize(load_optimize_spec(spec), out, executor=ex, figure=True, **_wait(optimize))


def _wait(fn) -> dict:
    """lock_wait_s where the function has it (not in profilegen before the folder rule: the
    script also measures that version, PYTHONPATH=its checkout)."""
    import inspect

    return {"lock_wait_s": 5} if "lock_wait_s" in inspect.signature(fn).parameters else {}


RUNS = {"sweep": sweep_run, "optimize": optimize_run}
SPEC_DIR = Path(tempfile.gettempdir())


# ----------------------------------------------------------------------------- moments


class Moments:
    """Counts the steps of the output writing; at step ``kill_at`` sends ``sig`` to itself."""

    def __init__(self, kill_at: int | None, sig: int):
        self.n, self.kill_at, self.sig, self.on = 0, kill_at, sig, False

    def step(self):
        if not self.on:
            return
        self.n += 1
        if self.n == self.kill_at:
            os.kill(os.getpid(), self.sig)  # SIGINT: a KeyboardInterrupt at the next bytecode, here

    def install(self):
        m = self
        real_atomic, real_stage = export.atomic_write, getattr(folder, "Owned", None) and folder.Owned.stage

        @contextlib.contextmanager
        def atomic_write(*a, **k):
            m.step()
            with real_atomic(*a, **k) as f:
                yield f
            m.step()

        def stage(self, *a, **k):
            m.on = True
            return real_stage(self, *a, **k)

        from profilegen.studies import sweep
        from profilegen.studies.optimize import run as oprun

        real_table = sweep.write_table

        def write_table(*a, **k):  # the first output file (before the folder rule: no stage)
            m.on = True
            return real_table(*a, **k)

        sweep.write_table = oprun.write_table = write_table

        def around(fn):
            def wrapped(*a, **k):
                m.step()
                r = fn(*a, **k)
                m.step()
                return r
            return wrapped

        export.atomic_write = atomic_write
        out_optimize.atomic_write = atomic_write
        if hasattr(folder, "Owned"):
            folder.Owned.stage = stage
        folder._swap_in = around(folder._swap_in)
        folder._fsync_dir = around(folder._fsync_dir)
        os.link = around(os.link)
        shutil.rmtree = around(shutil.rmtree)


def in_child(fn, kill_at, sig) -> tuple[int, int]:
    """Run fn with the moments installed in a forked child; (how it ended, moments counted)."""
    r, w = os.pipe()
    sys.stdout.flush(), sys.stderr.flush()
    pid = os.fork()
    if pid == 0:  # pragma: no cover — the child
        os.close(r)
        m = Moments(kill_at, sig)
        code = 0
        try:
            m.install()
            fn()
        except KeyboardInterrupt:
            code = 130
        except BaseException as exc:  # noqa: BLE001
            print(f"child: {type(exc).__name__}: {exc}", file=sys.stderr)
            code = 1
        os.write(w, str(m.n).encode())
        os._exit(code)
    os.close(w)
    n = os.read(r, 64)
    os.close(r)
    _, status = os.waitpid(pid, 0)
    how = -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)
    return how, int(n or 0)


# ----------------------------------------------------------------------------- sets


def _csv_without_times(data: bytes) -> bytes:
    rows = list(csv.reader(io.StringIO(data.decode())))
    keep = [k for k, c in enumerate(rows[0]) if not c.startswith("time")] if rows else []
    return "\n".join(",".join(r[k] for k in keep) for r in rows).encode()


def fingerprint(out: Path) -> dict[str, str]:
    """relative name → hash of everything but the journals (CSVs without time columns)."""
    fp = {}
    for p in sorted(out.rglob("*")):
        rel = str(p.relative_to(out))
        if p.is_dir() or rel.endswith("journal.csv"):
            continue
        data = p.read_bytes()
        if rel.endswith(".csv"):
            data = _csv_without_times(data)
        if rel == ".profilegen.json":  # a run lists its journals there before it starts them
            data = json.dumps([f for f in json.loads(data)["files"] if not f.endswith("journal.csv")]).encode()
        if rel in ("summary.json", "report.html"):  # how many designs ran and how many were read back
            data = re.sub(rb'("?(?:computed|reused)"?(?::|</th><td>)\s*)\d+', rb"\1#", data)
        fp[rel] = hashlib.sha256(data).hexdigest()[:16]
    return fp


def journals(out: Path) -> dict[str, list[bytes]]:
    return {p.name: p.read_bytes().splitlines() for p in out.glob("*journal.csv")}


def beside(out: Path) -> list[str]:
    return sorted(n for n in os.listdir(out.parent) if n.startswith(f".{out.name}."))


def main(argv):
    global SPEC_DIR
    kinds = argv or list(RUNS)
    bad = 0
    for kind in kinds:
        run = RUNS[kind]
        with tempfile.TemporaryDirectory(prefix=f"kill_{kind}_") as tmp:
            tmp = SPEC_DIR = Path(tmp)
            ref_old, ref_new = tmp / "ref_old" / "o", tmp / "ref_new" / "o"
            for ref, new in ((ref_old, False), (ref_new, True)):
                ref.parent.mkdir()
                how, _ = in_child(lambda: run(ref, new), None, 0)
                assert how == 0, how
            old_fp, new_fp = fingerprint(ref_old), fingerprint(ref_new)
            assert old_fp != new_fp
            # the moments of one uninterrupted run from the old set to the new
            dry = tmp / "dry" / "o"
            shutil.copytree(ref_old, dry)
            how, count = in_child(lambda: run(dry, True), None, 0)
            if how != 0 or fingerprint(dry) != new_fp:
                extra = sorted(set(fingerprint(dry)) - set(new_fp))
                print(f"{kind}: an uninterrupted run over the old set ended {how} and did not leave the new set "
                      f"(files of the old set left: {extra})")
                bad += 1
            print(f"{kind}: {count} moments in the output writing (old set {len(old_fp)} files, new {len(new_fp)})")
            for sig in (signal.SIGKILL, signal.SIGINT):
                tally = {"old": 0, "new": 0, "mixed": 0}
                for k in range(1, count + 1):
                    case = tmp / f"{sig.name}_{k}" / "o"
                    shutil.copytree(ref_old, case)
                    before = journals(case)
                    how, _ = in_child(lambda: run(case, True), k, sig)
                    fp = fingerprint(case)
                    which = "old" if fp == old_fp else "new" if fp == new_fp else "mixed"
                    grown = all(journals(case).get(n, [])[:len(lines)] == lines for n, lines in before.items())
                    tally[which] += 1
                    # the next run finishes from the journals: the new set, nothing computed, nothing beside
                    again_how, _ = in_child(lambda: run(case, True), None, 0)
                    ok = (which != "mixed" and grown and again_how == 0 and fingerprint(case) == new_fp
                          and beside(case) == [])
                    if not ok:
                        bad += 1
                        print(f"  {sig.name} at moment {k}: ended {how}, folder {which}, journals kept {grown}; "
                              f"rerun ended {again_how}, new set {fingerprint(case) == new_fp}, beside {beside(case)}")
                    shutil.rmtree(case.parent)
                print(f"  {sig.name} at {count} moments: old set {tally['old']}, new set {tally['new']}, "
                      f"mixed {tally['mixed']}")
    print("all whole" if not bad else f"{bad} bad cases")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
