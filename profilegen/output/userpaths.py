"""Paths a user gives and files a spec names: the output path's length limits, and errors about
another file that do not show its content.

**The output path** (``--out``), checked before any stage runs.

A path whose folder name is longer than a file name may be (255 bytes on the usual file systems,
less what the staging folder's name adds beside it), or whose whole length with the files written
in it is over the system's path limit (4096 bytes on Linux), would fail deep in the writers with
``OSError [Errno 36] File name too long``, and a path where nothing can be made (``/proc/x``, a
read-only mount) failed only after every stage had run; :func:`check_out_path` makes each one line
naming the option:

>>> check_out_path("results/" + "x" * 300)  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
profilegen.errors.ExportError: --out: a folder name of 300 bytes ('xxxxxxxxxxxxxxxxxxxx…'), at most 237 ...
>>> check_out_path("export/default")

**A file a spec names** (a sweep's or optimiser's ``gearset`` / ``scene``): its validation
problems quote its keys and values (``secret_table: unknown key``, ``name = "..."``), which is
right for ``profilegen check FILE`` but not inside another file's error; :func:`named_file_problem`
keeps what reading the file says (missing, too large, malformed at line N: no content) and
otherwise counts the problems and names the command that lists them.
"""

from __future__ import annotations

import os

from ..errors import ExportError

__all__ = ["NAME_MAX", "PATH_MAX", "check_out_path", "named_file_problem"]

NAME_MAX = 255
"""A file name's length limit, bytes (ext4, xfs, btrfs, tmpfs, APFS, NTFS)."""
PATH_MAX = 4096
"""A path's length limit, bytes (Linux)."""
BESIDE = len(".") + len(".staging-") + 8
"""What the output folder's staging name (``.NAME.staging-xxxxxxxx``) adds to NAME."""
INSIDE = 80
"""Room kept for the longest path written inside the output folder (``designs/<name>_pareto_NN.toml``,
``circular_spline_drawing.dxf``, a staging folder's name)."""


def _short(part: str) -> str:
    return part if len(part) <= 20 else part[:20] + "…"


def check_out_path(path: str | os.PathLike, *, option: str = "--out") -> None:
    """Raise an :class:`~profilegen.errors.ExportError` naming ``option`` if ``path`` cannot hold
    the output folder: a name longer than :data:`NAME_MAX` less :data:`BESIDE` bytes, or the whole
    path (made absolute) with :data:`INSIDE` bytes for what is written in it over :data:`PATH_MAX`."""
    text = os.fspath(path)
    parts = [p for p in text.replace(os.sep, "/").split("/") if p]
    for k, part in enumerate(parts):
        size = len(os.fsencode(part))
        limit = NAME_MAX - (BESIDE if k == len(parts) - 1 else 0)
        if size > limit:
            raise ExportError(f"{option}: a folder name of {size} bytes ({_short(part)!r}), at most {limit} "
                              f"(a file name's limit is {NAME_MAX} bytes"
                              f"{f', and the staging folder beside it adds {BESIDE}' if k == len(parts) - 1 else ''})"
                              f"; give a shorter {option}")
    total = len(os.fsencode(os.path.abspath(text)))
    if total + INSIDE > PATH_MAX:
        raise ExportError(f"{option}: the path is {total} bytes long (made absolute), at most {PATH_MAX - INSIDE} "
                          f"(the system's limit on a path is {PATH_MAX} bytes, less {INSIDE} for the files written in "
                          f"it); give a shorter {option}")
    _check_writable(text, option)


def _check_writable(text: str, option: str) -> None:
    """The nearest folder of ``text`` that exists (the folder itself, else the first parent that
    does) must take a new file: an anonymous one is made there and dropped, so nothing is left."""
    import tempfile

    here = os.path.abspath(text)
    while not os.path.exists(here):
        up = os.path.dirname(here)
        if up == here:
            break
        here = up
    if os.path.exists(here) and not os.path.isdir(here):
        return  # a file where the folder should be: the output folder's own check names it
    try:
        with tempfile.TemporaryFile(dir=here):
            pass
    except OSError as exc:
        raise ExportError(f"{option}: cannot write {text!r}: nothing can be made in '{here}' "
                          f"({exc.strerror or exc}); give a folder you can write") from None


def named_file_problem(exc: Exception, path: str | os.PathLike, what: str, command: str = "check") -> str:
    """The problem of the ``what`` file at ``path`` (a spec's gear set or scene file) for the spec's
    error, without the file's content: the read error as it is (it names the file and the line, never
    the text), else the number of problems and ``profilegen check PATH`` to list them."""
    from ..errors import GearSetError
    from ..gearset.reader import read_toml

    text = os.fspath(path).partition("#")[0] if what == "scene file" else os.fspath(path)
    try:
        read_toml(text, GearSetError, what)
    except GearSetError as read_error:  # missing, a folder, too large, not UTF-8, malformed TOML (at line N)
        return str(read_error)
    except Exception:  # noqa: BLE001 — any other read failure: say only that it is not a valid file
        return f"{text}: cannot read the {what}"
    problems = getattr(exc, "problems", None) or [str(exc)]
    count = f"{len(problems)} problem{'s' if len(problems) != 1 else ''}"
    how = (f"profilegen check {text}" if what == "gear-set file"
           else f"profilegen design --scene {text}")
    return f"{text}: not a valid {what} ({count}; `{how}` lists them)"
