"""One owner rule for every output folder (issue 26): design, sweep and optimize write only into
a folder that is absent, empty or their own (a profilegen marker lists each entry and the
writer writes that name, each a regular file); lock and journal files are never followed
through a link; a planted target is left byte for byte as it was (checked by its SHA-256).

Cheap throughout: the folder machinery directly, sweeps with a stand-in designer on a thread
pool, optimisations with a stand-in evaluator; no design runs here.
"""

from __future__ import annotations

import hashlib
import json
import os
import signal
import subprocess
import sys
import textwrap
import tomllib
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from profilegen.errors import ExportError
from profilegen.output import folder as outfolder
from profilegen.studies.sweep import SWEEP_FILES, Journal, parse_sweep_spec, run_sweep

FIELD = "wave_generator.deflection_coefficient"
SPEC = {"name": "t", "gearset": "default", "scene": "sketch", "grid": {FIELD: [0.8, 0.9]}}
OURS = {"a.txt", "design.json"}


def sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def tree(folder: Path) -> dict[str, str]:
    """relative name → SHA-256 (a link: 'link → target') of everything under ``folder``."""
    out = {}
    for p in sorted(folder.rglob("*")):
        rel = str(p.relative_to(folder))
        out[rel] = f"link → {os.readlink(p)}" if p.is_symlink() else ("dir" if p.is_dir() else sha(p))
    return out


class _Stub:
    """What a stand-in designer returns: outputs_of() finds nothing on it (every output empty)."""


def stub_designer(gs, *, scene):
    return _Stub()


def _sweep(out, **kw):
    spec = parse_sweep_spec(SPEC)
    with ThreadPoolExecutor(max_workers=1) as ex:
        return run_sweep(spec, out, executor=ex, designer=kw.pop("designer", stub_designer), figure=False, **kw)


def _one_line(exc) -> str:
    text = str(exc.value)
    assert "\n" not in text
    return text


# ----------------------------------------------------------------------------- the lock


def test_a_lock_file_planted_as_a_link_is_refused_and_its_target_untouched(tmp_path, monkeypatch):
    """The planted link is refused by name, and its target is never even opened (opening a device
    or FIFO can act on it). An open that reaches the target fails the test at once: a lock opened
    through the link would otherwise be locked, found not to be the name's file, and opened again
    for ever (the mutant folder-lock-follows-link hung here until the mutation run's timeout)."""
    victim = tmp_path / "victim.txt"
    victim.write_text("root-owned content\n")
    before = sha(victim)
    shared = tmp_path / "shared"
    shared.mkdir()
    os.symlink(victim, shared / ".run.lock")
    real_open = os.open

    def guarded_open(path, flags, *args, **kw):
        fd = real_open(path, flags, *args, **kw)
        if os.path.samestat(os.fstat(fd), os.stat(victim)):
            os.close(fd)
            raise AssertionError(f"the lock file's open followed the planted link {path} to {victim}")
        return fd

    monkeypatch.setattr(os, "open", guarded_open)
    with pytest.raises(ExportError, match="symbolic link") as info:
        with outfolder.replacing(shared / "run", ours=OURS) as staging:
            (staging / "a.txt").write_text("x")
    monkeypatch.undo()
    assert ".run.lock" in _one_line(info)
    assert sha(victim) == before and sorted(os.listdir(shared)) == [".run.lock"]


def test_a_leftover_lock_file_is_not_written_but_replaced(tmp_path):
    """A lock file with a second name (a hard link to somebody's file) is refused and the file
    unchanged; a killed run's plain leftover is removed and made anew (never written into)."""
    out = tmp_path / "run"
    lock = outfolder.lock_path(out)
    other = tmp_path / "other.txt"
    other.write_text("12345 somebody's file\n")
    os.link(other, lock)
    with pytest.raises(ExportError, match="hard links"):
        with outfolder.replacing(out, ours=OURS):
            pass
    assert other.read_text() == "12345 somebody's file\n"
    os.unlink(lock)
    lock.write_text("4242\n")  # a killed run's lock file
    seen = {}
    with outfolder.replacing(out, ours=OURS) as staging:
        seen["text"] = lock.read_text()
        (staging / "a.txt").write_text("x")
    assert seen["text"] == f"{os.getpid()}\n" and not lock.exists()


# ----------------------------------------------------------------------------- whose files


def test_a_planted_design_json_listing_a_users_file_does_not_make_it_ours(tmp_path):
    out = tmp_path / "run"
    out.mkdir()
    (out / "design.json").write_text(json.dumps({"files": ["design.json", "a.txt", "notes.txt"]}))
    (out / "notes.txt").write_text("my notes\n")
    before = tree(out)
    with pytest.raises(ExportError) as info:
        with outfolder.replacing(out, ours=OURS) as staging:
            (staging / "a.txt").write_text("x")
    assert "'notes.txt'" in _one_line(info) and str(out) in str(info.value)
    assert tree(out) == before and sorted(os.listdir(tmp_path)) == ["run"]


def test_an_entry_the_marker_lists_that_is_a_link_is_not_ours(tmp_path):
    out = tmp_path / "run"
    out.mkdir()
    victim = tmp_path / "victim.txt"
    victim.write_text("keep\n")
    (out / "design.json").write_text(json.dumps({"files": ["design.json", "a.txt"]}))
    os.symlink(victim, out / "a.txt")
    before = tree(out)
    with pytest.raises(ExportError, match=r"'a.txt' \(a symbolic link\)"):
        with outfolder.replacing(out, ours=OURS):
            pass
    assert tree(out) == before and victim.read_text() == "keep\n"


def test_profilegen_names_without_a_marker_are_not_ours(tmp_path):
    out = tmp_path / "run"
    out.mkdir()
    (out / "a.txt").write_text("the user's own a.txt\n")
    with pytest.raises(ExportError, match="no profilegen marker"):
        outfolder.check(out, ours=OURS)


@pytest.mark.parametrize("missing", [False, True], ids=["folder there", "folder missing"])
def test_a_planted_old_link_beside_the_folder_is_refused_before_anything_is_written(tmp_path, missing):
    """The issue's case: with the folder missing, HEAD moved the link into its place, wrote the
    set, failed on rmtree of the link (exit 2) and left a staging link behind."""
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "design.json").write_text(json.dumps({"files": ["design.json"]}))
    (mine / "thesis.txt").write_text("chapter 1\n")
    out = tmp_path / "run"
    if not missing:
        with outfolder.replacing(out, ours=OURS) as staging:
            (staging / "design.json").write_text(json.dumps({"files": ["design.json"]}))
    os.symlink(mine, tmp_path / ".run.old-deadbeef")
    before, listing = tree(mine), sorted(os.listdir(tmp_path))
    for attempt in (lambda: outfolder.check(out, ours=OURS), lambda: outfolder.replacing(out, ours=OURS).__enter__()):
        with pytest.raises(ExportError, match=r"\.run\.old-deadbeef' beside it is a symbolic link") as info:
            attempt()
        _one_line(info)
    assert tree(mine) == before and sorted(os.listdir(tmp_path)) == listing


def test_the_root_and_a_too_long_name_are_named_errors_and_nothing_is_made(tmp_path, monkeypatch):
    made = []
    monkeypatch.setattr(outfolder, "_locked", lambda *a, **k: made.append(a) or (_ for _ in ()).throw(AssertionError))
    with pytest.raises(ExportError, match="root") as info:
        outfolder.check("/", ours=OURS)
    _one_line(info)
    long = tmp_path / ("x" * 240)
    with pytest.raises(ExportError, match="at most 237") as info:
        with outfolder.replacing(long, ours=OURS):
            pass
    assert str(long) in _one_line(info) and made == [] and os.listdir(tmp_path) == []


# ----------------------------------------------------------------------------- the swap is durable


def test_the_parent_folder_is_fsynced_after_the_swap(tmp_path, monkeypatch):
    """The rename that swaps the set in is a change of the parent folder: it is durable only
    once the parent is fsynced, after the rename (fault injection: every fsync recorded)."""
    out = tmp_path / "run"
    events = []
    real_fsync, real_swap = os.fsync, outfolder._swap_in

    def fsync(fd):
        events.append(("fsync", os.path.realpath(f"/proc/self/fd/{fd}")))
        return real_fsync(fd)

    def swap(staging, target):
        old = real_swap(staging, target)
        events.append(("swap", str(target)))
        return old

    monkeypatch.setattr(os, "fsync", fsync)
    monkeypatch.setattr(outfolder, "_swap_in", swap)
    with outfolder.replacing(out, ours=OURS) as staging:
        (staging / "design.json").write_text(json.dumps({"files": ["design.json"]}))
    k = events.index(("swap", str(out)))
    assert ("fsync", str(tmp_path)) in events[k + 1:], events


def test_two_renames_a_failed_second_rename_puts_the_old_set_back(tmp_path, monkeypatch):
    """Without renameat2 the swap is NAME → .NAME.old-*, staging → NAME; if the second rename
    fails, the first is undone: the old set is back at NAME, nothing is left beside it, and the
    error names the folder (fault injection: the second rename raises EIO)."""
    out = tmp_path / "run"
    with outfolder.replacing(out, ours=OURS) as staging:
        (staging / "design.json").write_text(json.dumps({"files": ["design.json", "a.txt"]}))
        (staging / "a.txt").write_text("old\n")
    old = tree(out)
    monkeypatch.setattr(outfolder, "_renameat2", None)
    real_rename = os.rename

    def rename(src, dst, *a, **k):
        if ".staging-" in os.fspath(src):
            raise OSError(5, "Input/output error", os.fspath(src))
        return real_rename(src, dst, *a, **k)

    monkeypatch.setattr(os, "rename", rename)
    with pytest.raises(ExportError, match="Input/output error") as info:
        with outfolder.replacing(out, ours=OURS) as staging:
            (staging / "design.json").write_text(json.dumps({"files": ["design.json", "a.txt"]}))
            (staging / "a.txt").write_text("new\n")
    assert str(out) in _one_line(info)
    assert tree(out) == old and sorted(os.listdir(tmp_path)) == ["run"]


# ----------------------------------------------------------------------------- sweep


def test_sweep_into_a_folder_with_user_files_is_a_named_error_and_runs_nothing(tmp_path):
    out = tmp_path / "study"
    out.mkdir()
    (out / "results.csv").write_text("my,own\n1,2\n")
    (out / "report.html").write_text("<p>mine</p>\n")
    before = tree(out)
    calls = []
    with pytest.raises(ExportError, match="no profilegen marker") as info:
        _sweep(out, designer=lambda gs, scene: calls.append(gs) or _Stub())
    assert "'report.html'" in _one_line(info) and calls == [] and tree(out) == before


def test_sweep_out_root_is_a_named_error_and_writes_nothing(monkeypatch):
    def never(*a, **k):
        raise AssertionError("wrote something")

    monkeypatch.setattr(Journal, "_rewrite", never)
    monkeypatch.setattr(Journal, "append", never)
    monkeypatch.setattr(outfolder.Owned, "begin", never)
    with pytest.raises(ExportError, match="root") as info:
        _sweep(Path("/"))
    _one_line(info)


def test_sweep_folder_holds_its_set_and_marker_and_a_planted_journal_link_is_refused(tmp_path):
    out = tmp_path / "s"
    res = _sweep(out)
    assert res.computed == 2
    marker = json.loads((out / outfolder.MARKER).read_text())
    assert sorted(os.listdir(out)) == marker["files"] and set(marker["files"]) <= SWEEP_FILES
    assert sorted(os.listdir(tmp_path)) == ["s"]  # nothing beside it: no lock, no staging
    # a journal replaced by a link to the user's file
    victim = tmp_path / "victim.csv"
    victim.write_bytes((out / "journal.csv").read_bytes())
    os.unlink(out / "journal.csv")
    os.symlink(victim, out / "journal.csv")
    before = sha(victim)
    with pytest.raises(ExportError, match=r"'journal.csv' \(a symbolic link\)") as info:
        _sweep(out)
    _one_line(info)
    assert sha(victim) == before


def test_the_journal_never_reads_or_appends_through_a_link(tmp_path):
    victim = tmp_path / "victim.csv"
    victim.write_text("point_id,x,crc\n")
    os.symlink(victim, tmp_path / "journal.csv")
    jr = Journal(tmp_path / "journal.csv", ("point_id", "x"))
    with pytest.raises(ExportError, match="symbolic link"):
        jr.read()
    with pytest.raises(ExportError, match="symbolic link"):
        jr.append({"point_id": "a", "x": 1})
    assert victim.read_text() == "point_id,x,crc\n"


def test_a_corrupted_journal_line_is_detected_and_recomputed(tmp_path):
    """A line whose cells were changed (its CRC no longer matches) is not trusted: dropped, and
    its point run again."""
    out = tmp_path / "s"
    _sweep(out)
    lines = (out / "journal.csv").read_text().splitlines(keepends=True)
    assert len(lines) == 3
    cells = lines[1].split(",")
    k = 1 + len(parse_sweep_spec(SPEC).fields) + 1  # a cell after point_id and the field: an output
    cells[k] = "123.0"
    (out / "journal.csv").write_text(lines[0] + ",".join(cells) + lines[2])
    calls = []
    res = _sweep(out, designer=lambda gs, *, scene: calls.append(gs.wave_generator.deflection_coefficient) or _Stub())
    assert res.computed == 1 and res.reused == 1 and len(calls) == 1
    assert all(r[next(iter(r.keys() - {"index", "point_id", FIELD}))] != 123.0 for r in res.rows)


_HOLD = """
import sys, time
from profilegen.output import folder
with folder.owning(sys.argv[1], ours={"journal.csv"}, marker=folder.MARKER):
    print("locked", flush=True)
    time.sleep(60)
"""


def test_a_second_sweep_into_a_locked_folder_is_refused_and_computes_nothing(tmp_path):
    out = tmp_path / "s"
    holder = subprocess.Popen([sys.executable, "-c", _HOLD, str(out)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        calls = []
        with pytest.raises(ExportError, match=f"process {holder.pid}") as info:
            _sweep(out, designer=lambda gs, *, scene: calls.append(1) or _Stub(), lock_wait_s=0.2)
        _one_line(info)
        assert calls == []
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait()
    assert _sweep(out, lock_wait_s=5).computed == 2
    assert _sweep(out, lock_wait_s=5).computed == 0  # the next one reuses the journal


def test_sweep_killed_in_the_swap_leaves_the_old_set_and_the_journal_appendable(tmp_path, monkeypatch):
    """An exception where the new set would be swapped in: the old results stay, the journal
    keeps every point, no staging folder is left, and the next run reuses all of them."""
    out = tmp_path / "s"
    _sweep(out)
    old = tree(out)

    def boom(staging, target):
        raise KeyboardInterrupt

    monkeypatch.setattr(outfolder, "_swap_in", boom)
    spec = parse_sweep_spec({**SPEC, "grid": {FIELD: [0.8, 0.9, 1.0]}})
    with ThreadPoolExecutor(max_workers=1) as ex, pytest.raises(KeyboardInterrupt):
        run_sweep(spec, out, executor=ex, designer=stub_designer, figure=False)
    now = tree(out)
    assert {k: v for k, v in now.items() if k != "journal.csv"} == {k: v for k, v in old.items() if k != "journal.csv"}
    assert len((out / "journal.csv").read_text().splitlines()) == 1 + 3
    assert sorted(os.listdir(tmp_path)) == ["s"]
    monkeypatch.undo()
    with ThreadPoolExecutor(max_workers=1) as ex:
        again = run_sweep(spec, out, executor=ex, designer=stub_designer, figure=False)
    assert again.computed == 0 and again.reused == 3


# ----------------------------------------------------------------------------- optimize


def _fake_evaluate(values, context):
    w = float(values[FIELD])
    return {"profile_max_error_mm": (w - 0.95) ** 2 + 1e-3, "stress_min_safety": 2.0 - w}


def _optimize(tmp_path, out, *, name="Rim.Study", population=6, origin_dir=None, monkeypatch=None,
              objectives='profile_max_error_mm = "min"\nstress_min_safety = "max"\n', spec_name="o.toml"):
    from profilegen.studies.optimize import load_optimize_spec, optimize
    from profilegen.studies.optimize import run as oprun

    monkeypatch.setattr(oprun, "evaluate_design", _fake_evaluate)
    where = origin_dir or tmp_path
    where.mkdir(parents=True, exist_ok=True)
    path = where / spec_name
    path.write_text(textwrap.dedent(f"""\
        name = "{name}"
        gearset = "default"
        scene = "sketch"
        confirm_scene = ""
        [search]
        population = {population}
        generations = 2
        seed = 3
        [variables]
        "{FIELD}" = [0.85, 1.05]
        [objectives]
        """) + objectives)
    with ThreadPoolExecutor(max_workers=1) as ex:
        return optimize(load_optimize_spec(path), out, executor=ex, figure=False)


def test_optimize_into_a_folder_with_user_files_is_a_named_error(tmp_path, monkeypatch):
    out = tmp_path / "opt"
    out.mkdir()
    (out / "report.html").write_text("<p>my report</p>\n")
    before = tree(out)
    with pytest.raises(ExportError, match="'report.html'") as info:
        _optimize(tmp_path, out, monkeypatch=monkeypatch)
    _one_line(info)
    assert tree(out) == before


def test_optimize_front_designs_pass_check_and_a_smaller_front_leaves_no_old_design(tmp_path, monkeypatch, capsys):
    """A spec named Rim.Study in a folder whose name holds a line break: every front design is a
    gear set `profilegen check` accepts, its header comments stay comments; a rerun with a
    smaller front leaves exactly its own designs."""
    from profilegen.cli import main

    out = tmp_path / "opt"
    res = _optimize(tmp_path, out, origin_dir=tmp_path / 'x\nname = "evil"\n[gear]\nz = 1\n#', monkeypatch=monkeypatch)
    designs = sorted((out / "designs").iterdir())
    assert len(designs) == len(res.front) >= 2
    for k, p in enumerate(designs, start=1):
        text = p.read_text()
        data = tomllib.loads(text)  # the path's 'name = "evil"' and '[gear] z = 1' stayed in a comment
        assert data["name"] == f"rim_study_pareto_{k:02d}" and "z" not in data["gear"]
        assert all(line.startswith("#") for line in text.split("\nname = ")[0].splitlines())
        assert main(["check", str(p)]) == 0, capsys.readouterr()
    marker = json.loads((out / outfolder.MARKER).read_text())
    listing = sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file())
    assert listing == marker["files"]
    # the same folder, a run whose front is smaller: only its designs remain
    res2 = _optimize_small(tmp_path, out, monkeypatch)
    assert len(res2.front) < len(designs)
    assert sorted(p.name for p in (out / "designs").iterdir()) == sorted(Path(r["toml"]).name for r in res2.front)
    assert not [n for n in os.listdir(tmp_path) if n.startswith(".opt.")]  # no lock, no staging left


def _optimize_small(tmp_path, out, monkeypatch):
    """The same spec with one objective: its front is one design."""
    return _optimize(tmp_path, out, monkeypatch=monkeypatch, objectives='profile_max_error_mm = "min"\n',
                     spec_name="small.toml")


# ----------------------------------------------------------------------------- a second user


_AS_NOBODY = """
import os, pwd, sys
pw = pwd.getpwnam("nobody")
os.setgid(pw.pw_gid); os.setuid(pw.pw_uid)
from profilegen.errors import ExportError
from profilegen.output import folder
try:
    with folder.replacing(sys.argv[1], ours={"a.txt", "design.json"}) as staging:
        pass
except ExportError as exc:
    print("ExportError:", exc)
"""


def test_a_lock_file_of_another_user_is_refused_by_an_unprivileged_run(tmp_path):
    """In a shared (sticky, world-writable) folder, root's lock file is not followed, written or
    removed by user nobody's run: it is refused by name."""
    if os.geteuid() != 0:
        pytest.skip("needs root to start a process as the user nobody")
    try:
        import pwd

        pwd.getpwnam("nobody")
    except (ImportError, KeyError):
        pytest.skip("no user nobody on this machine")
    exe = Path(sys.executable).resolve()
    if any(not (os.stat(p).st_mode & 0o001) for p in exe.parents) or not os.access(exe, os.R_OK):
        pytest.skip(f"the user nobody cannot run {exe} (a folder above it is not world-searchable)")
    shared = tmp_path / "shared"
    shared.mkdir()
    os.chmod(tmp_path, 0o755)
    os.chmod(shared, 0o1777)
    lock = shared / ".run.lock"
    lock.write_text("root's\n")
    p = subprocess.run([sys.executable, "-c", _AS_NOBODY, str(shared / "run")], capture_output=True, text=True,
                       timeout=60)
    assert "ExportError" in p.stdout and "another user" in p.stdout, p.stdout + p.stderr
    assert lock.read_text() == "root's\n"


# ----------------------------------------------------------------------------- the command line


@pytest.mark.parametrize("command", ["sweep", "optimize"])
def test_the_command_refuses_a_users_folder_with_exit_2_and_one_line(tmp_path, capsys, command):
    spec = tmp_path / "s.toml"
    if command == "sweep":
        spec.write_text(f'name = "s"\ngearset = "default"\nscene = "sketch"\n[grid]\n"{FIELD}" = [0.9]\n')
    else:
        spec.write_text(textwrap.dedent(f"""\
            name = "s"
            gearset = "default"
            scene = "sketch"
            confirm_scene = ""
            [variables]
            "{FIELD}" = [0.9, 1.0]
            [objectives]
            profile_max_error_mm = "min"
            """))
    out = tmp_path / "mine"
    out.mkdir()
    (out / "report.html").write_text("<p>mine</p>\n")
    before = tree(out)
    from profilegen.cli import main

    assert main([command, str(spec), "-q", "--workers", "1", "--out", str(out)]) == 2
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(err) == 1 and "'report.html'" in err[0] and str(out) in err[0], err
    assert tree(out) == before and sorted(os.listdir(tmp_path)) == ["mine", "s.toml"]
