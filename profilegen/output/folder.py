"""The output folder, replaced as a whole: a run leaves the complete old set of files or the
complete new one — at every instant, also when it is killed — and nothing beside the folder.

:func:`replacing` is the one way :func:`profilegen.write_design` writes a folder ``NAME``:

1. **Lock.** ``.NAME.lock`` beside the folder is ``fcntl.flock``-ed while the files are written
   and swapped in; the kernel releases it when the process ends, also by SIGKILL. It is created
   with ``O_CREAT | O_EXCL | O_NOFOLLOW`` and only a file this run created is written to; one
   left by a killed run is locked (read-only, ``O_NOFOLLOW``), removed, and created anew. A
   lock file that is a link, not a regular file, or another user's is an ExportError naming
   it (in a shared folder another user cannot make the run write through it). A second run
   into the same folder waits for it (``lock_wait_s``, 120 s by default), then stops with an
   :class:`~profilegen.errors.ExportError` naming the folder and the other run's process id.
   Two runs into one folder therefore leave the complete set of the one that finished last.
2. **Leftovers.** Under the lock, what an interrupted run left beside the folder is cleaned:
   staging folders ``.NAME.staging-*`` (and ``.NAME.xxxxxxxx`` of earlier profilegen versions),
   and a folder parked by the two-rename swap (``.NAME.old-*``) is moved back when ``NAME`` is
   missing (the old set returns) or else removed. A leftover holding anything profilegen does not
   write is left alone (logged); one that is a link (profilegen never makes one) is an
   ExportError naming it, before anything is written. The lock file is removed at the end of
   every run.
3. **Only profilegen's files are replaced.** ``NAME`` must be absent, empty, or a folder that a
   profilegen *marker* claims (``design.json`` of ``profilegen design``, ``.profilegen.json`` of
   ``sweep`` and ``optimize``) and whose every entry is one the marker's run wrote: a regular file
   (not a link) whose name the marker lists *and* the writer can write (``ours``: its file names
   and ``patterns``; a subfolder such as ``designs/`` only with such files in it), their
   temporary files, and the ``.DS_Store``/``Thumbs.db``/``desktop.ini`` an operating system
   drops. So a planted marker listing a user's ``notes.txt`` does not make it ours. Anything
   else — a user's notes, a subfolder, a link, the gear set beside ``--out .``, files with no
   marker — stops the run *before* anything is moved or deleted, with an ExportError naming
   the folder and one such entry; so do ``NAME`` being the current working folder or the
   file system's root, and a name too long for the staging names beside it.
4. **Stage.** The new files are written into a fresh ``.NAME.staging-xxxxxxxx`` beside ``NAME``
   (same file system), each file atomically and fsynced.
5. **Swap.** ``renameat2(RENAME_EXCHANGE)`` (Linux ≥ 3.15 on ext4, xfs, btrfs, tmpfs, ...)
   exchanges the staging folder and ``NAME`` in one atomic step. Where it is unavailable (other
   systems, file systems that answer EINVAL) two renames are used, ``NAME`` → ``.NAME.old-*``,
   staging → ``NAME``: between them ``NAME`` is missing for a moment, and a run killed there
   leaves it missing until the next run (or :func:`recover`) moves the old set back.
6. **Clean.** The old set, now at the staging path, is deleted; the lock file removed.

The new folder keeps the old folder's permissions (a new one gets the umask's).

:func:`owning` is the same under one lock for a run that keeps files in the live folder while it
computes (the resumable journals of ``sweep`` and ``optimize``): :meth:`Owned.begin` makes the
folder (with its marker) if it is missing, and :meth:`Owned.stage` writes the finished set into
a staging folder, carries the journals over (hard links) and swaps it in as a whole.
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
from collections.abc import Collection, Iterator
from pathlib import Path

from ..errors import ExportError

try:
    import fcntl
except ImportError:  # pragma: no cover — not POSIX: no lock, the swap still holds
    fcntl = None  # type: ignore[assignment]

__all__ = ["LOCK_WAIT_S", "MARKER", "Owned", "check", "foreign_entries", "leftovers", "lock_path", "owning", "recover",
           "replacing", "write_marker"]

log = logging.getLogger(__name__)

LOCK_WAIT_S = 120.0  # how long a second run into the same folder waits for the first
SYSTEM_FILES = frozenset({".DS_Store", "Thumbs.db", "desktop.ini"})  # dropped by file browsers; replaced freely
_AT_FDCWD = -100
_RENAME_EXCHANGE = 2
_TOKEN = "[a-z0-9_-]{8,}"
MARKER = ".profilegen.json"  # the marker of sweep and optimize folders (a design folder's is design.json)
DESIGN_MARKER = "design.json"
NAME_MAX = 255  # a file name's length limit (ext4, xfs, btrfs, tmpfs, APFS, NTFS)
_LONGEST_BESIDE = len(".") + len(".staging-") + 8  # the staging name adds these to NAME (the lock: 6)
_O_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_O_CLOEXEC = getattr(os, "O_CLOEXEC", 0)


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


def _listed(folder: Path, marker: str = DESIGN_MARKER) -> set[str] | None:
    """The names the folder's marker lists under "files" (None: no marker, a link, or unreadable).
    A name is a file of the folder or ``SUB/file`` of one subfolder."""
    import json

    try:
        fd = os.open(folder / marker, os.O_RDONLY | _O_NOFOLLOW | _O_CLOEXEC)
    except OSError:
        return None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return None
        with os.fdopen(fd, "rb", closefd=False) as f:
            files = json.loads(f.read(4_000_000).decode("utf-8")).get("files", [])
    except (OSError, ValueError, AttributeError):
        return None
    finally:
        os.close(fd)
    if not isinstance(files, list):
        return None
    return {f for f in files if isinstance(f, str) and f.count("/") <= 1
            and all(part not in ("", ".", "..") for part in f.split("/"))}


def _writable(name: str, ours: Collection[str], patterns: Collection[str]) -> bool:
    """Whether the writer can write a file of this (relative) name."""
    return name in ours or any(re.fullmatch(p, name) for p in patterns)


def _is_tmp_of(rel: str, ours: Collection[str], patterns: Collection[str]) -> bool:
    sub, _, name = rel.rpartition("/")
    m = re.fullmatch(r"\.(.+)\.[A-Za-z0-9_]+\.tmp", name)  # a temporary file of export.atomic_write
    return bool(m and _writable(f"{sub}/{m.group(1)}" if sub else m.group(1), ours, patterns))


def _regular(entry: os.DirEntry) -> bool:
    try:
        return entry.is_file(follow_symlinks=False)
    except OSError:
        return False


def foreign_entries(folder: str | os.PathLike, ours: Collection[str], *, marker: str = DESIGN_MARKER,
                    patterns: Collection[str] = (), staging: bool = False) -> list[str]:
    """Entries of ``folder`` that are not a run's own: everything but regular files whose names
    the folder's ``marker`` lists and the writer writes (``ours``, ``patterns``), the marker
    itself, their temporary files and an OS's metadata files; every link; a subfolder unless
    each of its entries is such a file (``SUB/name``). Without a marker every entry is foreign
    (but OS metadata). ``staging``: a staging folder of an interrupted run (its marker is
    written last): regular files of the writer's names are its own, marker or not. Sorted; []
    for a missing or empty folder."""
    folder = Path(folder)
    try:
        entries = list(os.scandir(folder))
    except (FileNotFoundError, NotADirectoryError):
        return []
    listed = _listed(folder, marker) or set()
    if marker not in ours:
        ours = {*ours, marker}

    def own_file(e: os.DirEntry, rel: str) -> bool:
        if not _regular(e):
            return False
        if "/" not in rel and (rel in SYSTEM_FILES or rel == marker and listed is not None):
            return True
        if _is_tmp_of(rel, ours, patterns):
            return True
        return (staging or rel in listed) and _writable(rel, ours, patterns)

    foreign = []
    for e in entries:
        if e.is_dir(follow_symlinks=False):
            try:
                inner = list(os.scandir(e.path))
            except OSError:
                foreign.append(e.name)
                continue
            bad = [f"{e.name}/{i.name}" for i in inner if not own_file(i, f"{e.name}/{i.name}")]
            if bad or not (staging or any(n.startswith(e.name + "/") for n in listed)):
                foreign.append(bad[0] if bad else e.name)
        elif not own_file(e, e.name):
            foreign.append(e.name)
    return sorted(foreign)


def write_marker(folder: Path, command: str, files: Collection[str]) -> None:
    """The marker of a sweep or optimize folder: which command wrote it and its files."""
    from .export import atomic_write
    import json

    with atomic_write(folder / MARKER) as f:
        f.write(json.dumps({"profilegen": command, "files": sorted({*files, MARKER})}, indent=1) + "\n")


# ----------------------------------------------------------------------------- lock


def _holder(path: Path) -> str:
    try:
        fd = os.open(path, os.O_RDONLY | _O_NOFOLLOW | _O_CLOEXEC)
        try:
            pid = os.read(fd, 32).decode("ascii").split()[0]
        finally:
            os.close(fd)
        if not pid.isdigit():
            raise ValueError(pid)
    except (OSError, ValueError, IndexError):
        return "another profilegen run"
    return f"another profilegen run (process {pid})"


def _open_lock(path: Path, given: str) -> tuple[int, bool]:
    """(fd, created): the lock file created now (O_EXCL), or the one already there opened
    read-only without following a link; one that is not a plain file of this user is refused."""
    flags = _O_NOFOLLOW | _O_CLOEXEC
    try:
        return os.open(path, os.O_RDWR | os.O_CREAT | os.O_EXCL | flags, 0o600), True
    except FileExistsError:
        pass
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | flags)
    except FileNotFoundError:
        return -1, False  # removed meanwhile: create it anew
    except OSError as exc:
        if exc.errno == errno.ELOOP or os.path.islink(path):
            raise ExportError(f"cannot write '{given}': its lock file '{path}' is a symbolic link, "
                                  "which profilegen never makes; remove the link (nothing was changed)") from None
        raise
    st = os.fstat(fd)
    problem = ("not a regular file" if not stat.S_ISREG(st.st_mode) else
               f"owned by another user (uid {st.st_uid})" if hasattr(os, "geteuid") and st.st_uid != os.geteuid() else
               f"a file with {st.st_nlink} hard links" if st.st_nlink != 1 else None)
    if problem:
        os.close(fd)
        raise ExportError(f"cannot write '{given}': its lock file '{path}' is {problem}, so not one "
                          "profilegen made for this user; remove it or give another --out (nothing was changed)")
    return fd, False


@contextlib.contextmanager
def _locked(out: Path, wait_s: float, given: str | None = None) -> Iterator[None]:
    if fcntl is None:  # pragma: no cover
        yield
        return
    given = os.fspath(out) if given is None else given
    path = lock_path(out)
    deadline = time.monotonic() + wait_s
    waited = False
    while True:
        fd, created = _open_lock(path, given)
        if fd < 0:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            if not waited:
                log.warning("'%s' is being written by %s; waiting for it (up to %g s)", out, _holder(path), wait_s)
                waited = True
            if time.monotonic() >= deadline:
                raise ExportError(errno.EBUSY, f"cannot write '{out}': {_holder(path)} is writing it (lock file "
                                               f"'{path}', waited {wait_s:g} s); wait for it or give another --out") from None
            time.sleep(0.05)
            continue
        # the holder before us may have removed the file between our open and our lock: then our
        # lock is on a name nobody else sees, and a newcomer would lock a new file — open again
        try:
            same = os.path.samestat(os.fstat(fd), os.lstat(path))
        except FileNotFoundError:
            same = False
        if same and created:
            break
        if same:  # a killed run's lock file (nobody holds it): ours to remove, then create our own
            with contextlib.suppress(FileNotFoundError):
                os.unlink(path)
        os.close(fd)
    try:
        os.write(fd, f"{os.getpid()}\n".encode("ascii"))  # into the file created above, nothing else
        yield
    finally:
        with contextlib.suppress(OSError):
            if os.path.samestat(os.fstat(fd), os.lstat(path)):
                os.unlink(path)  # while still locked: a waiter then finds the name gone and opens anew
        os.close(fd)


# ----------------------------------------------------------------------------- recovery


def _real_dir(path: Path) -> bool:
    """A folder itself, not a link to one."""
    try:
        return stat.S_ISDIR(os.lstat(path).st_mode)
    except OSError:
        return False


def _remove_if_ours(folder: Path, ours: Collection[str], marker: str = DESIGN_MARKER,
                    patterns: Collection[str] = ()) -> bool:
    if not _real_dir(folder):
        return False
    other = foreign_entries(folder, ours, marker=marker, patterns=patterns, staging=True)
    if other:
        log.warning("left '%s' alone: it holds '%s', which profilegen does not write", folder, other[0])
        return False
    shutil.rmtree(folder)
    return True


def _links_beside(out: Path, given: str) -> None:
    """Refuse a staging, parked or legacy name beside the folder that is not a folder of its
    own (a link, a file): profilegen never makes one, and would otherwise move or delete it."""
    pats = _patterns(out.name)
    try:
        names = sorted(os.listdir(out.parent))
    except (FileNotFoundError, NotADirectoryError):  # no parent yet, or a file there: _check_target names it
        return
    for n in names:
        if any(p.fullmatch(n) for p in pats.values()) and not _real_dir(out.parent / n):
            kind = "a symbolic link" if os.path.islink(out.parent / n) else "not a folder"
            raise ExportError(f"cannot write '{given}': '{out.parent / n}' beside it is {kind}, which profilegen never "
                              "makes there; remove it or give another --out (nothing was changed)")


def recover(out: str | os.PathLike, *, ours: Collection[str], marker: str = DESIGN_MARKER,
            patterns: Collection[str] = ()) -> list[str]:
    """Clean up after interrupted runs into ``out`` (call it holding the lock, as
    :func:`replacing` does); returns what was done, one line per folder.

    If ``out`` is missing and a parked old set (``.NAME.old-*``, a two-rename swap cut between
    its renames) is beside it, that set is moved back. Every other staging or parked folder is
    deleted — if it holds only profilegen's files (else it is logged and left alone). Links
    and files with those names are never followed, moved or deleted.
    """
    out = _real(out)
    pats = _patterns(out.name)
    done: list[str] = []
    try:
        names = sorted(os.listdir(out.parent))
    except (FileNotFoundError, NotADirectoryError):
        return done
    parked = [out.parent / n for n in names if pats["parked"].fullmatch(n) and _real_dir(out.parent / n)
              and not foreign_entries(out.parent / n, ours, marker=marker, patterns=patterns)]
    if parked and not os.path.lexists(out):
        newest = max(parked, key=lambda p: os.lstat(p).st_mtime_ns)
        os.rename(newest, out)
        log.warning("restored '%s' from '%s' (a run was stopped while swapping it)", out, newest.name)
        done.append(f"restored {out.name} from {newest.name}")
    for n in names:
        p = out.parent / n
        if any(pat.fullmatch(n) for pat in pats.values()) and _real_dir(p):
            if _remove_if_ours(p, ours, marker, patterns):
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


def check(out_dir: str | os.PathLike, *, ours: Collection[str], marker: str = DESIGN_MARKER,
          patterns: Collection[str] = ()) -> None:
    """Raise the ExportError :func:`replacing` would raise for ``out_dir`` as it is now (the
    root, a file, the current folder, entries profilegen did not write, a link beside it) — to
    ask before a long computation."""
    given = os.fspath(out_dir)
    out = _real(out_dir)
    _check_name(out, given)
    _check_target(out, given, ours, marker, patterns)
    _links_beside(out, given)


def _check_name(out: Path, given: str) -> None:
    if not out.name or out == out.parent:
        raise ExportError(f"cannot write '{given}': the output folder must have a name (not the file system's root); "
                          "give --out a folder of its own (nothing was changed)")
    longest = NAME_MAX - _LONGEST_BESIDE
    if len(os.fsencode(out.name)) > longest:
        raise ExportError(errno.ENAMETOOLONG, f"cannot write '{given}': the folder name is "
                                              f"{len(os.fsencode(out.name))} bytes long; at most {longest} (the staging "
                                              "folder beside it adds 18 to a file name's 255); give a shorter --out")


def _check_target(out: Path, given: str, ours: Collection[str], marker: str = DESIGN_MARKER,
                  patterns: Collection[str] = ()) -> None:
    _check_name(out, given)
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
    other = foreign_entries(out, ours, marker=marker, patterns=patterns)
    if other:
        why = "which profilegen did not write" if _listed(out, marker) is not None else \
            f"which no profilegen marker ({marker}) lists"
        link = " (a symbolic link)" if os.path.islink(out / other[0]) else ""
        raise ExportError(f"cannot write '{given}': it holds '{other[0]}'{link}"
                          + (f" and {len(other) - 1} more entries" if len(other) > 1 else "")
                          + f", {why}, and profilegen replaces the output folder as a whole; "
                          f"move {'them' if len(other) > 1 else 'it'} elsewhere or give another --out (nothing was changed)")


class Owned:
    """An output folder held under its lock by :func:`owning`: ``out`` (the resolved path),
    :meth:`begin` to make it hold the run's journals while it computes, :meth:`stage` to
    write the finished set and swap it in as a whole."""

    def __init__(self, out: Path, given: str, ours: Collection[str], marker: str, patterns: Collection[str],
                 command: str):
        self.out, self.given, self.ours, self.marker, self.patterns = out, given, ours, marker, patterns
        self.command = command

    def begin(self, files: Collection[str]) -> Path:
        """The folder, made now if it is missing (its marker listing ``files``, the run's
        resumable files kept in the live folder); an existing folder's marker gets them added."""
        if not os.path.lexists(self.out):
            os.mkdir(self.out, _folder_mode(self.out))
        listed = _listed(self.out, self.marker) or set()
        if not set(files) <= listed:
            write_marker(self.out, self.command, listed | set(files))
        return self.out

    @contextlib.contextmanager
    def stage(self, keep: Collection[str] = ()) -> Iterator[Path]:
        """Yield an empty staging folder; when the block ends normally, the files ``keep`` of the
        live folder (the journals) are linked into it, and it becomes the folder as a whole."""
        staging: Path | None  # the new set, then the old one to delete, then None
        staging = self.out.parent / f".{self.out.name}.staging-{secrets.token_hex(4)}"
        os.mkdir(staging)
        os.chmod(staging, _folder_mode(self.out))
        try:
            yield staging
            for name in keep:
                src = self.out / name
                if _real_file(src):
                    try:
                        os.link(src, staging / name, follow_symlinks=False)
                    except OSError:
                        shutil.copyfile(src, staging / name, follow_symlinks=False)
            old = _swap_in(staging, self.out)
            staging = old  # from here on: the old set, to delete
            _fsync_dir(self.out.parent)
            if old is not None:
                shutil.rmtree(old)
            staging = None
        finally:
            if staging is not None:
                shutil.rmtree(staging, ignore_errors=True)


def _real_file(path: Path) -> bool:
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


@contextlib.contextmanager
def owning(out_dir: str | os.PathLike, *, ours: Collection[str], marker: str = DESIGN_MARKER,
           patterns: Collection[str] = (), command: str = "", lock_wait_s: float = LOCK_WAIT_S) -> Iterator[Owned]:
    """Hold the output folder ``out_dir`` for a run: the checks of :func:`replacing` (root, name
    length, links beside it, whose files), then its lock for the whole block; yields an
    :class:`Owned`. Every ``OSError`` comes out as an ExportError naming ``out_dir``."""
    given = os.fspath(out_dir)
    out = _real(out_dir)
    try:
        _check_name(out, given)
        _check_target(out, given, ours, marker, patterns)  # before anything is made, also the parent folders
        _links_beside(out, given)
        out.parent.mkdir(parents=True, exist_ok=True)
        with _locked(out, lock_wait_s, given):
            _links_beside(out, given)
            recover(out, ours=ours, marker=marker, patterns=patterns)
            _check_target(out, given, ours, marker, patterns)
            yield Owned(out, given, ours, marker, patterns, command)
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


@contextlib.contextmanager
def replacing(out_dir: str | os.PathLike, *, ours: Collection[str], lock_wait_s: float = LOCK_WAIT_S,
              marker: str = DESIGN_MARKER, patterns: Collection[str] = ()) -> Iterator[Path]:
    """Yield an empty staging folder; when the block ends normally, it becomes ``out_dir`` as a whole.

    See the module docstring for the steps and what is refused. If the block raises (or the
    process is stopped), ``out_dir`` keeps its old files and the staging folder is removed (by
    the next run if this one is killed). Every ``OSError`` comes out as an ExportError naming
    ``out_dir``; exceptions of the block pass through unchanged.
    """
    with owning(out_dir, ours=ours, marker=marker, patterns=patterns, lock_wait_s=lock_wait_s) as owned:
        with owned.stage() as staging:
            yield staging


def _blocker(out: Path) -> Path | None:
    return next((a for a in out.parents if a.exists() and not a.is_dir()), None)
