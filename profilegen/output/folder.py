"""The output folder, replaced as a whole: a run leaves the complete old set of files or the
complete new one — at every instant, also when it is killed — and nothing beside the folder.

:func:`replacing` is the one way :func:`profilegen.write_design` writes a folder ``NAME``:

1. **Lock.** ``.NAME.lock`` beside the folder is ``fcntl.flock``-ed while the files are written
   and swapped in; the kernel releases it when the process ends, also by SIGKILL. A second run
   into the same folder waits for it (``lock_wait_s``, 120 s by default), then stops with an
   :class:`~profilegen.errors.ExportError` naming the folder and the other run's process id.
   Two runs into one folder therefore leave the complete set of the one that finished last.
2. **Leftovers.** Under the lock, what an interrupted run left beside the folder is cleaned:
   staging folders ``.NAME.staging-*`` (and ``.NAME.xxxxxxxx`` of earlier profilegen versions),
   and a folder parked by the two-rename swap (``.NAME.old-*``) is moved back when ``NAME`` is
   missing (the old set returns) or else removed. A leftover holding anything profilegen does not
   write is left alone (logged). The lock file is removed at the end of every run.
3. **Only profilegen's files are replaced.** ``NAME`` must be absent or a folder holding only
   files profilegen writes (``ours``: its file names, the names the folder's ``design.json``
   lists, their temporary files, and the ``.DS_Store``/``Thumbs.db``/``desktop.ini`` an
   operating system drops). Anything else — a user's notes, a subfolder, the gear set beside
   ``--out .`` — stops the run *before* anything is moved or deleted, with an ExportError
   naming the folder and one such entry; so does ``NAME`` being the current working folder.
4. **Stage.** The new files are written into a fresh ``.NAME.staging-xxxxxxxx`` beside ``NAME``
   (same file system), each file atomically and fsynced.
5. **Swap.** ``renameat2(RENAME_EXCHANGE)`` (Linux ≥ 3.15 on ext4, xfs, btrfs, tmpfs, ...)
   exchanges the staging folder and ``NAME`` in one atomic step. Where it is unavailable (other
   systems, file systems that answer EINVAL) two renames are used, ``NAME`` → ``.NAME.old-*``,
   staging → ``NAME``: between them ``NAME`` is missing for a moment, and a run killed there
   leaves it missing until the next run (or :func:`recover`) moves the old set back.
6. **Clean.** The old set, now at the staging path, is deleted; the lock file removed.

The new folder keeps the old folder's permissions (a new one gets the umask's).
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import logging
import os
import re
import secrets
import shutil
import stat
import sys
import time
from collections.abc import Callable, Collection, Iterator
from pathlib import Path

from ..errors import ExportError

try:
    import fcntl
except ImportError:  # pragma: no cover — not POSIX: no lock, the swap still holds
    fcntl = None

__all__ = ["LOCK_WAIT_S", "replacing", "check", "recover", "leftovers", "foreign_entries", "lock_path"]

log = logging.getLogger(__name__)

LOCK_WAIT_S = 120.0  # how long a second run into the same folder waits for the first
SYSTEM_FILES = frozenset({".DS_Store", "Thumbs.db", "desktop.ini"})  # dropped by file browsers; replaced freely
_AT_FDCWD = -100
_RENAME_EXCHANGE = 2
_TOKEN = "[a-z0-9_-]{8,}"


def _load_renameat2():
    if not sys.platform.startswith("linux"):
        return None
    try:
        fn = ctypes.CDLL(None, use_errno=True).renameat2  # glibc ≥ 2.28, musl ≥ 1.2.5
    except (OSError, AttributeError):
        return None
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    return fn


_renameat2 = _load_renameat2()


def _exchange(a: Path, b: Path) -> bool:
    """Swap the paths ``a`` and ``b`` atomically; False where the system cannot."""
    if _renameat2 is None:
        return False
    if _renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP, errno.ENOTSUP):
        return False
    raise OSError(err, os.strerror(err), os.fspath(a), None, os.fspath(b))


# ----------------------------------------------------------------------------- names beside the folder


def lock_path(out: str | os.PathLike) -> Path:
    """The lock file of the output folder ``out``: ``.NAME.lock`` beside it."""
    out = _real(out)
    return out.parent / f".{out.name}.lock"


def _patterns(name: str) -> dict[str, re.Pattern]:
    n = re.escape(name)
    return {
        "staging": re.compile(rf"\.{n}\.staging-{_TOKEN}"),
        "parked": re.compile(rf"\.{n}\.old-{_TOKEN}"),
        "legacy": re.compile(rf"\.{n}\.[a-z0-9_]{{8}}"),  # tempfile.mkdtemp of profilegen ≤ 0.x
    }


def leftovers(out: str | os.PathLike) -> list[Path]:
    """What runs into ``out`` have left beside it: staging and parked folders, the lock file."""
    out = _real(out)
    pats = _patterns(out.name)
    try:
        names = os.listdir(out.parent)
    except FileNotFoundError:
        return []
    found = [out.parent / n for n in names if any(p.fullmatch(n) for p in pats.values())]
    if lock_path(out).exists():
        found.append(lock_path(out))
    return sorted(found)


# ----------------------------------------------------------------------------- whose files


def _listed(folder: Path) -> set[str]:
    """The names the folder's design.json lists under "files" (none if it is unreadable)."""
    import json

    try:
        files = json.loads((folder / "design.json").read_text(encoding="utf-8")).get("files", [])
    except (OSError, ValueError, AttributeError):
        return set()
    return {f for f in files if isinstance(f, str) and "/" not in f and f not in ("", ".", "..")} if isinstance(files, list) else set()


def _is_ours(name: str, known: set[str], is_file: bool) -> bool:
    if not is_file:
        return False
    if name in known or name in SYSTEM_FILES:
        return True
    m = re.fullmatch(r"\.(.+)\.[A-Za-z0-9_]+\.tmp", name)  # a temporary file of export.atomic_write
    return bool(m and m.group(1) in known)


def foreign_entries(folder: str | os.PathLike, ours: Collection[str]) -> list[str]:
    """Entries of ``folder`` profilegen did not write: not a file named in ``ours`` or in the
    folder's own design.json, not their temporary files, not an OS's metadata file; every
    subfolder and link. Sorted; [] for a missing folder."""
    folder = Path(folder)
    known = set(ours) | _listed(folder)
    try:
        entries = list(os.scandir(folder))
    except FileNotFoundError:
        return []
    return sorted(e.name for e in entries if not _is_ours(e.name, known, e.is_file(follow_symlinks=False)))


# ----------------------------------------------------------------------------- lock


def _holder(path: Path) -> str:
    try:
        pid = path.read_text(encoding="ascii").split()[0]
    except (OSError, ValueError, IndexError):
        return "another profilegen run"
    return f"another profilegen run (process {pid})"


@contextlib.contextmanager
def _locked(out: Path, wait_s: float) -> Iterator[None]:
    if fcntl is None:  # pragma: no cover
        yield
        return
    path = lock_path(out)
    deadline = time.monotonic() + wait_s
    waited = False
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            if not waited:
                log.warning("'%s' is being written by %s; waiting for it (up to %g s)", out, _holder(path), wait_s)
                waited = True
            if time.monotonic() >= deadline:
                raise ExportError(errno.EBUSY, f"cannot write '{out}': {_holder(path)} is writing it (lock file "
                                               f"'{path}', waited {wait_s:g} s); wait for it or give another --out")
            time.sleep(0.05)
            continue
        # the holder before us may have removed the file between our open and our lock: then our
        # lock is on a name nobody else sees, and a newcomer would lock a new file — open again
        try:
            same = os.path.samestat(os.fstat(fd), os.stat(path))
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode("ascii"))
        yield
    finally:
        with contextlib.suppress(OSError):
            os.unlink(path)  # while still locked: a waiter then finds the name gone and opens anew
        os.close(fd)


# ----------------------------------------------------------------------------- recovery


def _remove_if_ours(folder: Path, ours: Collection[str]) -> bool:
    if not folder.is_dir() or folder.is_symlink():
        return False
    other = foreign_entries(folder, ours)
    if other:
        log.warning("left '%s' alone: it holds '%s', which profilegen does not write", folder, other[0])
        return False
    shutil.rmtree(folder)
    return True


def recover(out: str | os.PathLike, *, ours: Collection[str]) -> list[str]:
    """Clean up after interrupted runs into ``out`` (call it holding the lock, as
    :func:`replacing` does); returns what was done, one line per folder.

    If ``out`` is missing and a parked old set (``.NAME.old-*``, a two-rename swap cut between
    its renames) is beside it, that set is moved back. Every other staging or parked folder is
    deleted — if it holds only profilegen's files (else it is logged and left alone).
    """
    out = _real(out)
    pats = _patterns(out.name)
    done = []
    try:
        names = sorted(os.listdir(out.parent))
    except FileNotFoundError:
        return done
    parked = [out.parent / n for n in names if pats["parked"].fullmatch(n)]
    if parked and not os.path.lexists(out):
        newest = max(parked, key=lambda p: p.stat().st_mtime_ns)
        os.rename(newest, out)
        log.warning("restored '%s' from '%s' (a run was stopped while swapping it)", out, newest.name)
        done.append(f"restored {out.name} from {newest.name}")
    for n in names:
        p = out.parent / n
        if any(pat.fullmatch(n) for pat in pats.values()) and os.path.lexists(p):
            if _remove_if_ours(p, ours):
                log.info("removed '%s', left by an interrupted run", p)
                done.append(f"removed {n}")
    return done


# ----------------------------------------------------------------------------- the swap


def _real(out: str | os.PathLike) -> Path:
    """The folder's absolute path with links resolved (a linked folder is replaced where it is)."""
    return Path(os.path.realpath(os.path.abspath(os.fspath(out))))


def _folder_mode(out: Path) -> int:
    try:
        return stat.S_IMODE(out.stat().st_mode)
    except FileNotFoundError:
        mask = os.umask(0o022)
        os.umask(mask)
        return 0o777 & ~mask


def _fsync_dir(folder: Path) -> None:
    if hasattr(os, "O_DIRECTORY"):
        with contextlib.suppress(OSError):
            fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)


def _swap_in(staging: Path, out: Path) -> Path | None:
    """Make ``staging`` the folder ``out``; returns where the old folder went (None: there was none)."""
    if not os.path.lexists(out):
        os.rename(staging, out)
        return None
    if _exchange(staging, out):
        return staging
    parked = out.parent / f".{out.name}.old-{secrets.token_hex(4)}"
    os.rename(out, parked)
    try:
        os.rename(staging, out)
    except OSError:
        os.rename(parked, out)
        raise
    return parked


def check(out_dir: str | os.PathLike, *, ours: Collection[str]) -> None:
    """Raise the ExportError :func:`replacing` would raise for ``out_dir`` as it is now (a file,
    the current folder, entries profilegen did not write) — to ask before a long computation."""
    _check_target(_real(out_dir), os.fspath(out_dir), ours)


def _check_target(out: Path, given: str, ours: Collection[str]) -> None:
    if not out.name:
        raise ExportError(f"cannot write '{given}': the output folder must have a name (not the file system's root)")
    if os.path.lexists(out) and not out.is_dir():
        raise ExportError(errno.ENOTDIR, f"cannot write '{given}': it is a file, not a folder")
    blocker = next((a for a in out.parents if os.path.lexists(a) and not a.is_dir()), None)
    if blocker is not None:
        raise ExportError(errno.ENOTDIR, f"cannot write '{given}': '{blocker}' is a file, not a folder")
    try:
        is_cwd = os.path.samefile(out, os.getcwd())
    except OSError:
        is_cwd = False
    if is_cwd:
        raise ExportError(f"cannot write '{given}': it is the current folder, and profilegen replaces the output "
                          "folder as a whole; give --out a folder of its own (e.g. export/NAME)")
    other = foreign_entries(out, ours)
    if other:
        raise ExportError(f"cannot write '{given}': it holds '{other[0]}'"
                          + (f" and {len(other) - 1} more entries" if len(other) > 1 else "")
                          + ", which profilegen did not write, and profilegen replaces the output folder as a whole; "
                          f"move {'them' if len(other) > 1 else 'it'} elsewhere or give another --out (nothing was changed)")


@contextlib.contextmanager
def replacing(out_dir: str | os.PathLike, *, ours: Collection[str], lock_wait_s: float = LOCK_WAIT_S) -> Iterator[Path]:
    """Yield an empty staging folder; when the block ends normally, it becomes ``out_dir`` as a whole.

    See the module docstring for the steps and what is refused. If the block raises (or the
    process is stopped), ``out_dir`` keeps its old files and the staging folder is removed (by
    the next run if this one is killed). Every ``OSError`` comes out as an ExportError naming
    ``out_dir``; exceptions of the block pass through unchanged.
    """
    given = os.fspath(out_dir)
    out = _real(out_dir)
    staging = None
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        with _locked(out, lock_wait_s):
            recover(out, ours=ours)
            _check_target(out, given, ours)
            mode = _folder_mode(out)
            staging = out.parent / f".{out.name}.staging-{secrets.token_hex(4)}"
            staging.mkdir()
            os.chmod(staging, mode)
            yield staging
            old = _swap_in(staging, out)
            staging = old  # from here on: the old set, to delete
            _fsync_dir(out.parent)
            if old is not None:
                shutil.rmtree(old)
            staging = None
    except ExportError:
        raise
    except OSError as exc:
        blocker = _blocker(out)
        if blocker is not None and isinstance(exc, (FileExistsError, NotADirectoryError)):
            reason = f"'{blocker}' is a file, not a folder"
        else:
            reason = exc.strerror or str(exc)
            if exc.filename and os.fspath(exc.filename) != os.fspath(out):
                reason = f"{reason} ('{os.fspath(exc.filename)}')"
        err = ExportError(exc.errno, f"cannot write '{given}': {reason}") if exc.errno else \
            ExportError(f"cannot write '{given}': {reason}")
        raise err from exc
    finally:
        if staging is not None:
            shutil.rmtree(staging, ignore_errors=True)


def _blocker(out: Path) -> Path | None:
    return next((a for a in out.parents if a.exists() and not a.is_dir()), None)
