"""The hostile output-folder cases of issue 26, run through the command line: what each does to a
planted target (its content hash before and after) and how the run ends.

    python tests/benchmarks/hostile_outputs.py            # every case, in a temporary folder
    python tests/benchmarks/hostile_outputs.py lock sweep  # some of them

Cases: ``lock`` (``.run.lock`` planted as a link to another file), ``designjson`` (a planted
design.json whose ``files`` lists the user's notes.txt), ``old`` (a planted ``.run.old-*`` link
to a folder of the user's; ``old_missing``: the same with no folder yet, the link to another
output folder of the user's), ``sweep`` (``--out`` a folder holding the user's results.csv and
report.html), ``journal`` (a sweep's journal.csv planted as a link), ``root`` (``sweep --out /``
as the unprivileged user nobody, where the machine allows it; ``root_named``: as this user,
only where the folder rule is in), ``optimize`` (``--out`` a
folder holding the user's report.html). Sketch-scene designs: each case takes a few seconds.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

PG = [sys.executable, "-m", "profilegen"]


def digest(path: Path) -> str:
    """sha256 of a file's bytes (a folder: of its sorted names and files), '-' when missing."""
    if not os.path.lexists(path):
        return "-"
    if path.is_dir() and not path.is_symlink():
        h = hashlib.sha256()
        for p in sorted(path.rglob("*")):
            h.update(str(p.relative_to(path)).encode() + b"\0" + (p.read_bytes() if p.is_file() else b""))
        return h.hexdigest()[:12]
    return hashlib.sha256(path.read_bytes()).hexdigest()[:12]


def run(cmd, cwd, user=None) -> tuple[int, str]:
    pre = None
    if user is not None:
        import pwd

        pw = pwd.getpwnam(user)

        def pre():  # noqa: F811
            os.setgid(pw.pw_gid)
            os.setuid(pw.pw_uid)
    p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, preexec_fn=pre, timeout=600,
                       env={**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2])})
    err = [line for line in p.stderr.splitlines() if line.strip() and not line.startswith(("WARNING", "INFO"))]
    return p.returncode, (err[-1] if err else "")[:300] + (f"  [{len(err)} stderr lines]" if len(err) > 1 else "")


def report(case, rc, msg, targets):
    print(f"{case}: exit {rc}: {msg}")
    for name, (before, after) in targets.items():
        print(f"    {name}: {before} -> {after} ({'untouched' if before == after else 'CHANGED'})")


def sweep_spec(d: Path) -> Path:
    spec = d / "one.toml"
    spec.write_text('name = "one"\ngearset = "default"\nscene = "sketch"\n'
                    '[grid]\n"wave_generator.deflection_coefficient" = [1.0]\n')
    return spec


def case_lock(d: Path):
    (d / "shared").mkdir()
    victim = d / "victim.txt"
    victim.write_text("root-owned content\n")
    os.symlink(victim, d / "shared" / ".run.lock")
    h0 = digest(victim)
    rc, msg = run([*PG, "design", "default", "--scene", "sketch", "-q", "--out", "shared/run"], d)
    report("lock", rc, msg, {"victim.txt": (h0, digest(victim))})


def case_designjson(d: Path):
    out = d / "run"
    out.mkdir()
    (out / "design.json").write_text('{"files": ["design.json", "notes.txt"]}\n')
    (out / "notes.txt").write_text("my notes\n")
    h0 = digest(out / "notes.txt")
    rc, msg = run([*PG, "design", "default", "--scene", "sketch", "-q", "--out", "run"], d)
    report("designjson", rc, msg, {"run/notes.txt": (h0, digest(out / "notes.txt"))})


def case_old(d: Path):
    run([*PG, "design", "default", "--scene", "sketch", "-q", "--out", "run"], d)  # an earlier run's folder
    mine = d / "mine"
    mine.mkdir()
    (mine / "thesis.txt").write_text("chapter 1\n")
    h0 = digest(mine)
    os.symlink(mine, d / ".run.old-deadbeef")
    rc, msg = run([*PG, "design", "default", "--scene", "sketch", "-q", "--out", "run"], d)
    left = sorted(n for n in os.listdir(d) if n.startswith(".run."))
    report("old", rc, msg + f"; beside the folder: {left}", {"mine/": (h0, digest(mine))})


def case_old_missing(d: Path):
    run([*PG, "design", "default", "--scene", "sketch", "-q", "--out", "mine"], d)  # the user's other output folder
    h0 = digest(d / "mine")
    os.symlink(d / "mine", d / ".run.old-deadbeef")
    rc, msg = run([*PG, "design", "default", "--scene", "sketch", "-q", "--out", "run"], d)
    left = sorted(n for n in os.listdir(d) if n.startswith(".run."))
    kind = "a link" if os.path.islink(d / "run") else ("a folder" if (d / "run").is_dir() else "missing")
    report("old_missing", rc, msg + f"; run is {kind}; beside the folder: {left}", {"mine/": (h0, digest(d / "mine"))})


def case_sweep(d: Path):
    out = d / "study"
    out.mkdir()
    (out / "results.csv").write_text("my,own\n1,2\n")
    (out / "report.html").write_text("<p>mine</p>\n")
    h = {n: digest(out / n) for n in ("results.csv", "report.html")}
    rc, msg = run([*PG, "sweep", str(sweep_spec(d)), "-q", "--workers", "1", "--out", "study"], d)
    report("sweep", rc, msg, {f"study/{n}": (h[n], digest(out / n)) for n in h})


def case_journal(d: Path):
    out = d / "s"
    out.mkdir()
    victim = d / "victim.csv"
    run([*PG, "sweep", str(sweep_spec(d)), "-q", "--workers", "1", "--out", "ref"], d)
    victim.write_text((d / "ref" / "journal.csv").read_text().splitlines(keepends=True)[0])  # a valid header
    os.symlink(victim, out / "journal.csv")
    h0 = digest(victim)
    rc, msg = run([*PG, "sweep", str(sweep_spec(d)), "-q", "--workers", "1", "--out", "s"], d)
    report("journal", rc, msg, {"victim.csv": (h0, digest(victim))})


def case_root(d: Path):
    if os.geteuid() != 0:
        print("root: skipped (needs root to become nobody)")
        return
    if not os.access(sys.executable, os.X_OK, effective_ids=False) or _unreadable_by_others(sys.executable):
        print(f"root: skipped (user nobody cannot run {sys.executable})")
        return
    os.chmod(d, 0o755)
    spec = sweep_spec(d)
    os.chmod(spec, 0o644)
    before = sorted(os.listdir("/"))
    rc, msg = run([*PG, "sweep", str(spec), "-q", "--workers", "1", "--out", "/"], "/tmp", user="nobody")
    after = sorted(os.listdir("/"))
    print(f"root (as nobody): exit {rc}: {msg}; new entries in /: {sorted(set(after) - set(before))}")


def case_root_named(d: Path):
    """``sweep --out /`` as this user: only with the folder rule in the checked-out package
    (before it, a root run would write /journal.csv and /results.csv)."""
    root = str(Path(__file__).resolve().parents[2])
    probe = subprocess.run([sys.executable, "-c", "import profilegen.output.folder as f; f.owning"],
                           env={**os.environ, "PYTHONPATH": root}, capture_output=True)
    if probe.returncode != 0:
        print("root_named: skipped (this checkout has no folder rule: the run would write into /)")
        return
    before = sorted(os.listdir("/"))
    rc, msg = run([*PG, "sweep", str(sweep_spec(d)), "-q", "--workers", "1", "--out", "/"], d)
    print(f"root_named: exit {rc}: {msg}; new entries in /: {sorted(set(os.listdir('/')) - set(before))}")


def case_optimize(d: Path):
    out = d / "opt"
    out.mkdir()
    (out / "report.html").write_text("<p>my report</p>\n")
    h0 = digest(out / "report.html")
    spec = d / "o.toml"
    spec.write_text(textwrap.dedent("""\
        name = "o"
        gearset = "default"
        scene = "sketch"
        confirm_scene = ""
        [search]
        population = 4
        generations = 1
        seed = 1
        [variables]
        "wave_generator.deflection_coefficient" = [0.9, 1.1]
        [objectives]
        profile_max_error_mm = "min"
        """))
    rc, msg = run([*PG, "optimize", str(spec), "-q", "--workers", "1", "--out", "opt"], d)
    report("optimize", rc, msg, {"opt/report.html": (h0, digest(out / "report.html"))})


def _unreadable_by_others(path) -> bool:
    p = Path(path).resolve()
    return any(not (a.stat().st_mode & 0o001) for a in p.parents) or not (p.stat().st_mode & 0o005)


CASES = {"lock": case_lock, "designjson": case_designjson, "old": case_old, "old_missing": case_old_missing, "sweep": case_sweep,
         "journal": case_journal, "root": case_root, "root_named": case_root_named, "optimize": case_optimize}


def main(argv):
    for name in argv or CASES:
        with tempfile.TemporaryDirectory(prefix=f"hostile_{name}_") as tmp:
            CASES[name](Path(tmp))


if __name__ == "__main__":
    main(sys.argv[1:])
