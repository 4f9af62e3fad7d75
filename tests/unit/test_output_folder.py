"""profilegen.output.folder and write_design: the output folder changes as a whole.

A run that fails or is killed (SIGKILL, at exact moments in forked children and once in a real
``profilegen design --scene sketch``) leaves exactly the complete old set of files, byte for byte;
a finished run exactly the new set, with ``design.json["files"]`` equal to the folder's listing;
the next run leaves nothing beside the folder. Files profilegen did not write are never touched.
The full kill study is ``tests/benchmarks/kill_design.py``.
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import pytest

import profilegen as pg
from profilegen.output import folder as outfolder
from profilegen.errors import ExportError
from profilegen.output.files import OUTPUT_FILES

OURS = {"a.txt", "b.txt", "c.txt", "d.txt", "design.json"}


def _fingerprint(folder: Path) -> dict[str, str]:
    """name → SHA-256 of every file in the folder (a subfolder → "folder")."""
    return {p.name: "folder" if p.is_dir() else hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.iterdir())}


def _beside(out: Path) -> list[str]:
    return sorted(p.name for p in out.parent.iterdir() if p.name != out.name)


def _write_set(out: Path, tag: str, names=("a.txt", "b.txt", "c.txt"), *, kill_after: int | None = None, **kw):
    """A small set through outfolder.replacing: the named files holding ``tag``, design.json listing them."""
    with outfolder.replacing(out, ours=OURS, **kw) as staging:
        for k, name in enumerate(names):
            if kill_after == k:
                os.kill(os.getpid(), signal.SIGKILL)
            (staging / name).write_text(f"{tag} {name}\n")
        (staging / "design.json").write_text(json.dumps({"files": sorted([*names, "design.json"]), "tag": tag}))


def _in_killed_child(fn) -> None:
    """Run fn() in a forked child that must die by SIGKILL (fn arranges it)."""
    sys.stdout.flush(), sys.stderr.flush()
    pid = os.fork()
    if pid == 0:  # pragma: no cover — the child
        try:
            fn()
        finally:
            os._exit(0)  # reached only if fn did not kill us: the parent sees status 0 and fails
    _, status = os.waitpid(pid, 0)
    assert os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL, f"child ended with status {status}"


# ----------------------------------------------------------------------------- the folder, small sets


@pytest.fixture
def old_new(tmp_path):
    """An output folder holding the old set, and the fingerprints of the old and the new set."""
    ref = tmp_path / "ref"
    ref.mkdir()
    _write_set(ref / "new", "new", ("a.txt", "b.txt", "d.txt"))
    new = _fingerprint(ref / "new")
    out = tmp_path / "run" / "out"
    _write_set(out, "old")
    return out, _fingerprint(out), new


def test_a_finished_run_leaves_exactly_the_new_set_and_nothing_beside(old_new):
    out, old, new = old_new
    assert old != new and set(old) != set(new)  # c.txt only in the old set, d.txt only in the new
    _write_set(out, "new", ("a.txt", "b.txt", "d.txt"))
    assert _fingerprint(out) == new
    assert _beside(out) == []
    assert (out.stat().st_mode & 0o777) == (0o777 & ~_umask())


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


MOMENTS = {"after 0 files": "old", "after 2 files": "old", "before the swap": "old", "after the swap": "new",
           "while deleting the old set": "new"}  # moment of the SIGKILL → the set the folder must hold


@pytest.mark.parametrize("moment", sorted(MOMENTS))
@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "two renames"])
def test_sigkill_leaves_old_or_new_set_and_the_next_run_cleans_up(old_new, moment, exchange, monkeypatch):
    out, old, new = old_new
    if not exchange:
        monkeypatch.setattr(outfolder, "_renameat2", None)
    elif outfolder._renameat2 is None:
        pytest.skip("no renameat2 on this system")

    def child():
        kill = lambda *a, **k: os.kill(os.getpid(), signal.SIGKILL)  # noqa: E731
        if moment.startswith("after") and "files" in moment:
            _write_set(out, "new", ("a.txt", "b.txt", "d.txt"), kill_after=int(moment.split()[1]))
        swap = outfolder._swap_in
        if moment == "before the swap":
            outfolder._swap_in = kill
        elif moment == "after the swap":
            outfolder._swap_in = lambda s, o: (swap(s, o), kill())
        elif moment == "while deleting the old set":
            def half_then_kill(folder, *a, **k):
                os.unlink(sorted(Path(folder).iterdir())[0])
                kill()
            outfolder.shutil.rmtree = half_then_kill
        _write_set(out, "new", ("a.txt", "b.txt", "d.txt"))

    _in_killed_child(child)
    left = _beside(out)
    assert f".{out.name}.lock" in left  # the killed run's lock file stays, its lock went with the process
    assert _fingerprint(out) == {"old": old, "new": new}[MOMENTS[moment]]
    if moment == "after the swap":  # the old set waits for deletion: at the staging path (exchanged) or parked
        assert any(n.startswith(f".{out.name}.{'staging' if exchange else 'old'}-") for n in left), left
    # the next run: it cleans up before it writes, and leaves nothing beside the folder
    _write_set(out, "third")
    assert json.loads((out / "design.json").read_text())["tag"] == "third"
    assert _beside(out) == []


def test_two_renames_cut_between_them_restore_the_old_set(old_new, monkeypatch):
    """Without renameat2 the folder is missing between the two renames; recover() (run by the
    next run, under the lock) moves the old set back."""
    out, old, _ = old_new
    monkeypatch.setattr(outfolder, "_renameat2", None)

    def child():
        real = os.rename
        calls = []

        def rename(a, b):
            calls.append(a)
            if len(calls) == 2:  # NAME → .NAME.old-*, then staging → NAME: die between them
                os.kill(os.getpid(), signal.SIGKILL)
            real(a, b)
        outfolder.os.rename = rename
        _write_set(out, "new", ("a.txt", "b.txt", "d.txt"))

    _in_killed_child(child)
    assert not out.exists()
    assert any(n.startswith(f".{out.name}.old-") for n in _beside(out))
    done = outfolder.recover(out, ours=OURS)
    assert done[0].startswith(f"restored {out.name}")
    assert _fingerprint(out) == old
    assert _beside(out) == [f".{out.name}.lock"]  # the staging and parked folders are gone


def test_an_exception_in_the_block_keeps_the_old_set_and_leaves_nothing(old_new):
    out, old, _ = old_new
    with pytest.raises(KeyError):
        with outfolder.replacing(out, ours=OURS) as staging:
            (staging / "a.txt").write_text("half")
            raise KeyError("boom")
    assert _fingerprint(out) == old and _beside(out) == []


def test_user_files_are_refused_and_nothing_is_changed(old_new):
    out, old, _ = old_new
    (out / "my notes.txt").write_text("keep me")
    before = _fingerprint(out)
    with pytest.raises(ExportError, match="my notes.txt"):
        outfolder.check(out, ours=OURS)  # the same answer before a run
    with pytest.raises(ExportError, match="my notes.txt") as info:
        _write_set(out, "new")
    assert str(out) in str(info.value)
    assert _fingerprint(out) == before and _beside(out) == []
    (out / "my notes.txt").unlink()
    (out / "drawings").mkdir()
    with pytest.raises(ExportError, match="drawings"):
        _write_set(out, "new")
    assert _fingerprint(out) == {**old, "drawings": "folder"}


def test_os_metadata_and_temporary_files_are_replaced_but_a_name_design_json_lists_is_not_enough(old_new):
    """.DS_Store and a killed atomic_write's temporary file are not the user's; a name the folder's
    design.json lists that profilegen does not write (a planted listing) is: refused, untouched."""
    out, old, new = old_new
    listed = json.loads((out / "design.json").read_text())
    (out / "later.json").write_text("{}")
    (out / "design.json").write_text(json.dumps({**listed, "files": listed["files"] + ["later.json"]}))
    before = _fingerprint(out)
    with pytest.raises(ExportError, match="later.json") as info:
        _write_set(out, "new", ("a.txt", "b.txt", "d.txt"))
    assert str(out) in str(info.value) and "\n" not in str(info.value)
    assert _fingerprint(out) == before and _beside(out) == []
    os.unlink(out / "later.json")
    (out / ".DS_Store").write_bytes(b"\0")
    (out / ".b.txt.k2j3h4.tmp").write_text("a temporary file of a killed atomic_write")
    _write_set(out, "new", ("a.txt", "b.txt", "d.txt"))
    assert _fingerprint(out) == new


def test_the_current_folder_and_a_file_are_refused(tmp_path, monkeypatch):
    out = tmp_path / "out"
    out.mkdir()
    monkeypatch.chdir(out)
    with pytest.raises(ExportError, match="current folder"):
        _write_set(Path("."), "x")
    assert list(out.iterdir()) == []
    (tmp_path / "f").write_text("")
    with pytest.raises(ExportError, match="not a folder") as info:
        _write_set(tmp_path / "f", "x")
    assert str(tmp_path / "f") in str(info.value)
    with pytest.raises(ExportError, match="is a file") as info:
        _write_set(tmp_path / "f" / "sub", "x")
    assert str(tmp_path / "f") in str(info.value)


def test_leftovers_of_earlier_versions_are_removed_but_not_if_they_hold_user_files(old_new):
    out, _, new = old_new
    legacy = out.parent / f".{out.name}.ab12_xyz"  # tempfile.mkdtemp's name in profilegen before this change
    legacy.mkdir()
    (legacy / "a.txt").write_text("half")
    foreign = out.parent / f".{out.name}.staging-0badcafe"
    foreign.mkdir()
    (foreign / "thesis.tex").write_text("not ours")
    _write_set(out, "new", ("a.txt", "b.txt", "d.txt"))
    assert _fingerprint(out) == new
    assert _beside(out) == [foreign.name] and (foreign / "thesis.tex").exists()


_HOLD = """
import fcntl, os, sys, time
fd = os.open(sys.argv[1], os.O_RDWR | os.O_CREAT)
fcntl.flock(fd, fcntl.LOCK_EX)
os.write(fd, str(os.getpid()).encode())
print("locked", flush=True)
time.sleep(60)
"""


def test_a_second_run_waits_for_the_lock_then_names_the_other_run(old_new, caplog):
    out, old, new = old_new
    holder = subprocess.Popen([sys.executable, "-c", _HOLD, str(outfolder.lock_path(out))], stdout=subprocess.PIPE,
                              text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        with pytest.raises(ExportError, match=f"process {holder.pid}") as info:
            _write_set(out, "new", ("a.txt", "b.txt", "d.txt"), lock_wait_s=0.3)
        assert str(out) in str(info.value) and info.value.errno == errno.EBUSY
        assert f"process {holder.pid}" in caplog.text and "waiting" in caplog.text  # said when it starts to wait
        assert _fingerprint(out) == old
        holder.send_signal(signal.SIGKILL)  # the kernel releases the lock of a killed process
        holder.wait()
        _write_set(out, "new", ("a.txt", "b.txt", "d.txt"), lock_wait_s=5)
    finally:
        holder.kill()
        holder.wait()
    assert _fingerprint(out) == new and _beside(out) == []


# ----------------------------------------------------------------------------- write_design


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_output_folder")


@pytest.fixture(scope="module")
def sketch_contact(default_sketch_contact):
    """A sketch design of the default set with the loaded contact (contact.json) and stresses
    (conftest.py: computed once per worker)."""
    return default_sketch_contact


@pytest.fixture(scope="module")
def contact_folder(sketch_contact, tmp_path_factory):
    """An output folder written from the contact design (the old set of the tests below)."""
    out = tmp_path_factory.mktemp("contact") / "default"
    pg.write_design(sketch_contact, out, figure=False)
    return out


def _copy(folder: Path, tmp_path: Path) -> Path:
    out = tmp_path / "export" / folder.name
    shutil.copytree(folder, out)
    return out


def _listed_files(out: Path) -> list[str]:
    return json.loads((out / "design.json").read_text())["files"]


def test_design_json_lists_exactly_the_folder_after_a_no_contact_run_follows_a_contact_run(
        sketch_contact, contact_folder, tmp_path):
    out = _copy(contact_folder, tmp_path)
    assert "contact.json" in _listed_files(out) and (out / "contact.json").exists()
    assert set(_listed_files(out)) <= OUTPUT_FILES
    written = pg.write_design(replace(sketch_contact, contact=None), out, figure=False)
    names = sorted(os.listdir(out))
    assert _listed_files(out) == names == [p.name for p in written]
    assert "contact.json" not in names and "stress.json" in names
    assert _beside(out) == []


@pytest.mark.parametrize("failing_write", [1, 4])
def test_an_error_between_writes_keeps_the_old_set(sketch_contact, contact_folder, tmp_path, monkeypatch,
                                                   failing_write):
    """A disk that fills up at the k-th file: an ExportError naming the file, the old set intact."""
    out = _copy(contact_folder, tmp_path)
    old = _fingerprint(out)
    real, calls = os.replace, []

    def replace_fails(a, b):
        calls.append(b)
        if len(calls) == failing_write:
            raise OSError(errno.ENOSPC, "No space left on device", a)
        real(a, b)
    monkeypatch.setattr(os, "replace", replace_fails)
    with pytest.raises(ExportError, match="No space left") as info:
        pg.write_design(replace(sketch_contact, contact=None), out, figure=False)
    assert Path(calls[-1]).name in str(info.value)
    monkeypatch.undo()
    assert _fingerprint(out) == old and _beside(out) == []


def test_a_killed_profilegen_design_leaves_the_old_set_and_the_next_run_cleans_up(
        sketch_contact, contact_folder, tmp_path):
    """SIGKILL to a real `profilegen design --scene sketch` after its second staged file."""
    out = _copy(contact_folder, tmp_path)
    old = _fingerprint(out)
    cmd = [sys.executable, "-m", "profilegen", "design", "--scene", "sketch", "--no-contact", "--out", str(out), "-q"]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    staged = 0
    try:
        deadline = time.monotonic() + 600
        while proc.poll() is None and time.monotonic() < deadline:
            stagings = [p for p in out.parent.iterdir() if p.name.startswith(f".{out.name}.staging-")]
            with_files = [p for p in stagings if p.is_dir() and len(os.listdir(p)) >= 2] if stagings else []
            if with_files:
                staged = len(os.listdir(with_files[0]))
                proc.send_signal(signal.SIGKILL)
                break
            time.sleep(0.005)
    finally:
        proc.kill()
        proc.wait()
    assert staged >= 2, f"the run ended before it was killed: {proc.returncode}, {proc.stderr.read()[-300:]!r}"
    assert _fingerprint(out) == old
    assert any(n.startswith(f".{out.name}.staging-") for n in _beside(out))
    pg.write_design(replace(sketch_contact, contact=None), out, figure=False)  # the next run
    assert _beside(out) == [] and _listed_files(out) == sorted(os.listdir(out))
