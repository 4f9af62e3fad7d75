"""Where the bundled gear sets are and how a name finds one: :func:`profiles_dir` (the
checkout's ``profiles/`` or the installed copy under ``<prefix>/share/profilegen/profiles``),
:func:`default_gearset_path`, :func:`list_profiles`, :func:`resolve_gearset` (a bare name or a
path) and :func:`looks_like_path`.
"""

from __future__ import annotations

import errno
import os
import sys
from pathlib import Path

from ..errors import GearSetError, did_you_mean
from .reader import _show

__all__ = ["default_gearset_path", "list_profiles", "looks_like_path", "profiles_dir", "resolve_gearset"]


def looks_like_path(text: str) -> bool:
    """Whether a name given for a gear set or scene is a file path (a ``.toml`` name, with an
    optional ``#NAME`` after it, or a name with a folder separator) rather than a bundled name."""
    return text.partition("#")[0].endswith(".toml") or os.sep in text or (os.altsep is not None and os.altsep in text)


def _profile_dir_candidates() -> list[Path]:
    return [
        Path(__file__).resolve().parents[2] / "profiles",
        Path(sys.prefix) / "share" / "profilegen" / "profiles",
    ]


def profiles_dir() -> Path:
    """The folder of the shipped profiles: ``<repo>/profiles`` if present, else the installed copy."""
    candidates = _profile_dir_candidates()
    for folder in candidates:
        if (folder / "default.toml").is_file():
            return folder
    raise GearSetError(
        "profiles folder not found (looked for default.toml in "
        + ", ".join(str(c) for c in candidates)
        + ")"
    )


def default_gearset_path() -> Path:
    """Path of ``profiles/default.toml`` (repo checkout first, then ``sys.prefix/share/profilegen``)."""
    return profiles_dir() / "default.toml"


def list_profiles() -> list[Path]:
    """The shipped gear-set files, sorted by name."""
    return sorted(profiles_dir().glob("*.toml"))


def _exists(path: Path, *, file: bool = False) -> bool:
    """``path.is_file()`` / ``path.exists()``, False for a name too long for the file system (a
    300-character bare name, whose ``NAME.toml`` the profile lookup tries, raised ENAMETOOLONG)."""
    try:
        return path.is_file() if file else path.exists()
    except OSError as exc:
        if exc.errno == errno.ENAMETOOLONG:
            return False
        raise


def resolve_gearset(name_or_path: str | os.PathLike) -> Path:
    """Path of a gear set given as a file path or as a bare profile name (``"default"``).

    A value with a folder separator or a ``.toml`` suffix is a path; a bare name
    is looked up in :func:`profiles_dir` (then, failing that, as a file in the
    current folder). Raises :class:`GearSetError` naming what was tried.
    """
    text = os.fspath(name_or_path)
    if "\0" in text or len(text) > 4096:
        raise GearSetError(f"{_show(text)}: not a file name (a NUL character or over 4096 characters)")
    candidate = Path(text)
    is_path = (
        isinstance(name_or_path, os.PathLike)
        or os.sep in text
        or (os.altsep is not None and os.altsep in text)
        or candidate.suffix == ".toml"
    )
    if is_path:
        if _exists(candidate):  # a folder, device or FIFO too: load_gearset says what it is
            return candidate
        raise GearSetError(f"{candidate}: no such gear-set file")
    try:
        folder = profiles_dir()
    except GearSetError:
        folder = None
    if folder is not None and _exists(folder / f"{text}.toml", file=True):
        return folder / f"{text}.toml"
    if _exists(candidate):
        return candidate
    names = [p.stem for p in list_profiles()] if folder is not None else []
    known = ", ".join(names) or "none found"
    raise GearSetError(f"gear set {text!r}: no such profile (known profiles: {known}) and no such file"
                       + did_you_mean(text, names))
