"""Writing results to files: atomically, deterministically, with full precision.

Every writer goes through :func:`atomic_write`: the data goes to a temporary
file in the target's folder, is flushed and fsynced, and replaces the target in
one ``os.replace``. A failed run (bad data, a full disk, an unwritable folder)
leaves neither a half file nor a temporary file, and any ``OSError`` becomes an
:class:`~profilegen.errors.ExportError` naming the path and the reason.

* :func:`write_json` — sorted keys, indent 2, no NaN/inf (the offending key path
  is named), NumPy scalars and arrays converted.
* :func:`write_envelope_csv`, :func:`write_points_csv` — fixed ``%.12f``
  (1e-12 mm: nanometres are kept with room to spare).
* :func:`write_outline_dxf` — DXF R2010 in mm, one LWPOLYLINE per polyline,
  coordinates at full double precision, byte-identical output for identical
  input (the header's dates and GUIDs are fixed). :func:`read_dxf_polylines`
  reads such a file back.

ezdxf is imported inside the DXF functions only, so importing this module is cheap.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import tempfile
import threading
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import IO, Any

import numpy as np

from ..errors import ExportError

__all__ = [
    "DXF_LAYER_COLORS",
    "atomic_write",
    "deferred_sync",
    "write_json",
    "write_envelope_csv",
    "write_points_csv",
    "write_outline_dxf",
    "read_dxf_polylines",
]

#: Standard layers (always created) and their ACI colours: CS red, FS blue, WG green,
#: construction grey, annotation white/black. Other layer names get colour 7.
DXF_LAYER_COLORS: dict[str, int] = {"CS": 1, "FS": 5, "WG": 3, "construction": 8, "annotation": 7}

_CLOSE_TOL_MM = 1e-12  # first == last within this → a closed polyline (auto mode)
_FIXED_DXF_LOCK = threading.Lock()  # ezdxf's fixed-metadata switch is process-global


# ----------------------------------------------------------------------------- atomic files


def _export_error(path: Path, exc: OSError, tmp: str | None) -> ExportError:
    reason = exc.strerror or str(exc) or type(exc).__name__
    other = os.fspath(exc.filename) if exc.filename else None
    if other in (os.fspath(path), tmp):
        other = None
    blocker = next((a for a in path.parents if a.exists() and not a.is_dir()), None)
    if blocker is not None and isinstance(exc, (FileExistsError, NotADirectoryError)):
        reason = f"'{blocker}' is a file, not a folder"
    elif other:
        reason = f"{reason} ('{other}')"
    msg = f"cannot write '{path}': {reason}"
    return ExportError(exc.errno, msg) if exc.errno else ExportError(msg)


def _file_mode() -> int:
    """Permissions a plain ``open(path, "w")`` would give (mkstemp makes 0600 files)."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return 0o666 & ~int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, mode: str = "w", *, encoding: str = "utf-8") -> Iterator[IO]:
    """Open a temporary file next to ``path``; on success it replaces ``path`` atomically.

    ``mode`` is ``"w"`` (text, ``encoding``, no newline translation) or ``"wb"``.
    Parent folders are created. On any exception inside the block the temporary
    file is removed and ``path`` is left as it was; an ``OSError`` (unwritable
    folder, a folder that is a file, disk full, ...) is raised as ``ExportError``
    naming the path and the reason, other exceptions pass through unchanged.

    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with atomic_write(d / "sub" / "a.txt") as f:
    ...     _ = f.write("hello")
    >>> (d / "sub" / "a.txt").read_text(), sorted(p.name for p in (d / "sub").iterdir())
    ('hello', ['a.txt'])
    """
    if mode not in ("w", "wt", "wb"):
        raise ValueError(f"mode must be 'w', 'wt' or 'wb', got {mode!r}")
    path = Path(os.fspath(path))
    deferred = getattr(_DEFERRED, "paths", None)
    tmp: str | None = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
        f: IO[Any]
        if "b" in mode:
            f = os.fdopen(fd, "wb")
        else:
            f = os.fdopen(fd, "w", encoding=encoding, newline="")
        with f:
            yield f
            f.flush()
            if deferred is None:
                os.fsync(f.fileno())
        os.chmod(tmp, _file_mode())
        os.replace(tmp, path)
        tmp = None
        if deferred is not None:  # synced with the others when deferred_sync's block ends
            deferred.append(path)
            return
    except OSError as exc:
        if isinstance(exc, ExportError):
            raise
        raise _export_error(path, exc, tmp) from exc
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
    if hasattr(os, "O_DIRECTORY"):  # make the rename itself durable (POSIX), best effort
        with contextlib.suppress(OSError):
            dfd = os.open(path.parent, os.O_RDONLY | os.O_DIRECTORY)
            try:
                os.fsync(dfd)
            finally:
                os.close(dfd)


_DEFERRED = threading.local()  # .paths: the files deferred_sync's block wrote in this thread


@contextlib.contextmanager
def deferred_sync(*, sync: bool = True) -> Iterator[None]:
    """Inside the block, :func:`atomic_write` in this thread renames each file into place without
    waiting for the disk; when the block ends normally every file it wrote is fsynced, all at
    once in threads (one journal commit can take them together), then each folder — ~7 ms a
    file one by one on this machine's disk, a few ms for twenty together. For a folder nobody
    sees until the block has ended (:func:`profilegen.output.folder.replacing`'s staging
    folder, swapped in after it): there a file is durable before it is visible, as before.
    An ``OSError`` of the sync is raised as an ExportError naming the file.

    ``sync=False``: the files are never synced (a temporary folder, read back and removed
    inside the block), also not by an enclosing block."""
    outer = getattr(_DEFERRED, "paths", None)
    paths: list[Path] = []
    _DEFERRED.paths = paths
    try:
        yield
    finally:
        _DEFERRED.paths = outer
    if not sync:
        return
    if outer is not None:  # nested: the outer block syncs them
        outer.extend(paths)
        return
    _sync_files(paths)


def _sync_one(path: Path, directory: bool = False) -> None:
    fd = os.open(path, os.O_RDONLY | (os.O_DIRECTORY if directory else 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _sync_files(paths: list[Path]) -> None:
    if not paths:
        return
    from concurrent.futures import ThreadPoolExecutor

    def sync(path: Path) -> None:
        try:
            _sync_one(path)
        except OSError as exc:
            raise _export_error(path, exc, None) from exc

    with ThreadPoolExecutor(max_workers=min(16, len(paths))) as pool:
        list(pool.map(sync, paths))
    if hasattr(os, "O_DIRECTORY"):  # the renames, best effort as atomic_write's
        for folder in dict.fromkeys(p.parent for p in paths):
            with contextlib.suppress(OSError):
                _sync_one(folder, directory=True)


# ----------------------------------------------------------------------------- JSON


def _json_safe(obj: Any, where: str) -> Any:
    """Plain-Python copy of ``obj``; a non-finite float or an unknown type names its key path."""
    if isinstance(obj, np.ndarray):
        obj = obj.tolist()
    elif isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, Mapping):
        out = {}
        for k, v in obj.items():
            if isinstance(k, np.generic):
                k = k.item()
            if not isinstance(k, (str, int, float, bool)) and k is not None:
                raise TypeError(f"write_json: key {k!r} at {where or '<root>'} is a {type(k).__name__}, not a str")
            out[k] = _json_safe(v, f"{where}.{k}" if where else str(k))
        return out
    if isinstance(obj, (list, tuple)):
        return [_json_safe(v, f"{where}[{i}]") for i, v in enumerate(obj)]
    if isinstance(obj, float) and not math.isfinite(obj):
        raise ValueError(f"{where or '<root>'} is {obj!r}")
    if obj is None or isinstance(obj, (str, int, float, bool)):
        return obj
    raise TypeError(f"write_json: {where or '<root>'} is a {type(obj).__name__}, which JSON cannot hold")


_STR = json.encoder.encode_basestring_ascii  # json.dumps' own (C) string quoting
_FLOAT_REPR = float.__repr__
_INT_REPR = int.__repr__


def _json_key(k: Any) -> str:
    """A key as json.dumps writes it (the keys _json_safe lets through)."""
    if isinstance(k, str):
        return _STR(k)
    if k is True:
        return '"true"'
    if k is False:
        return '"false"'
    if k is None:
        return '"null"'
    if isinstance(k, float):
        if not math.isfinite(k):
            raise ValueError(f"Out of range float values are not JSON compliant: {k!r}")
        return _STR(_FLOAT_REPR(k))
    return _STR(_INT_REPR(k))


def _json_text(obj: Any, where: str, nl: str) -> str:
    """``json.dumps(_json_safe(obj, where), sort_keys=True, indent=2, allow_nan=False)``, the same
    text (``nl``: a newline and the current indent), written in one pass: json.dumps with an indent
    runs its pure-Python encoder, which with _json_safe's copy took ~0.1 s for a design's
    stress.json. Lists of floats (arrays, the bulk of the files) are joined at once."""
    if isinstance(obj, np.ndarray):
        obj = obj.tolist()
    elif isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, str):
        return _STR(obj)
    if obj is None:
        return "null"
    if obj is True:
        return "true"
    if obj is False:
        return "false"
    if isinstance(obj, float):
        if not math.isfinite(obj):
            raise ValueError(f"{where or '<root>'} is {obj!r}")
        return _FLOAT_REPR(obj)
    if isinstance(obj, int):
        return _INT_REPR(obj)
    inner = nl + "  "
    if isinstance(obj, Mapping):
        items = {}
        for k, v in obj.items():
            if isinstance(k, np.generic):
                k = k.item()
            if not isinstance(k, (str, int, float, bool)) and k is not None:
                raise TypeError(f"write_json: key {k!r} at {where or '<root>'} is a {type(k).__name__}, not a str")
            items[k] = v
        if not items:
            return "{}"
        parts = [inner + _json_key(k) + ": " + _json_text(v, f"{where}.{k}" if where else str(k), inner)
                 for k, v in sorted(items.items())]
        return "{" + ",".join(parts) + nl + "}"
    if isinstance(obj, (list, tuple)):
        if not obj:
            return "[]"
        if all(type(v) is float for v in obj):
            text = ("," + inner).join(map(_FLOAT_REPR, obj))
            if "n" not in text:  # no 'nan' nor 'inf': finite reprs hold digits, '.', 'e', '+', '-' only
                return "[" + inner + text + nl + "]"
        parts = [inner + _json_text(v, f"{where}[{i}]", inner) for i, v in enumerate(obj)]
        return "[" + ",".join(parts) + nl + "]"
    raise TypeError(f"write_json: {where or '<root>'} is a {type(obj).__name__}, which JSON cannot hold")


def write_json(path: str | os.PathLike, data: Any) -> None:
    """Write ``data`` as JSON (sorted keys, indent 2, a final newline), atomically.

    A NaN or infinity anywhere raises ``ExportError`` naming its key path (e.g.
    ``pieces[3].depth_mm``) and nothing is written; NumPy scalars and arrays are
    converted to plain numbers and lists.
    """
    path = Path(os.fspath(path))
    try:
        text = _json_text(data, "", "\n") + "\n"
    except ValueError as exc:
        raise ExportError(f"cannot write '{path}': non-finite value: {exc}") from exc
    with atomic_write(path, "w") as f:
        f.write(text)


# ----------------------------------------------------------------------------- CSV


def _xy(points: Any, name: str) -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"{name} must be an (n, 2) array of mm, got shape {p.shape}")
    bad = ~np.isfinite(p).all(axis=1)
    if bad.any():
        raise ValueError(f"{name} must be finite, got {p[bad][0].tolist()} at row {int(np.argmax(bad))}")
    return p


def write_points_csv(path: str | os.PathLike, points: Any, header: Sequence[str] = ("x_mm", "y_mm")) -> None:
    """Write an (n, 2) point array as CSV with a header row, ``%.12f``, atomically."""
    p = _xy(points, "points")
    header = tuple(header)
    if len(header) != 2 or not all(isinstance(h, str) and h and "," not in h and "\n" not in h for h in header):
        raise ValueError(f"header must be two non-empty names without commas, got {header!r}")
    lines = [",".join(header)] + [f"{x:.12f},{y:.12f}" for x, y in p.tolist()]
    with atomic_write(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def write_envelope_csv(path: str | os.PathLike, envelope: Any) -> None:
    """Write every classified envelope point: ``x_mm,y_mm,phi_rad,class``, ``%.12f``, atomically.

    One row per point of ``envelope.table()`` (i.e. per point of every piece, in
    piece order); φ is the mesh angle (rad) at which the FS tooth generates the point.
    """
    pts, phi, cls = envelope.table()
    pts = _xy(pts, "envelope points")
    phi = np.asarray(phi, dtype=float)
    if phi.shape != (len(pts),) or len(cls) != len(pts):
        raise ValueError(f"envelope.table() gave {len(pts)} points, {phi.shape} phi and {len(cls)} classes")
    if not np.isfinite(phi).all():
        raise ValueError(f"envelope phi must be finite, got NaN at row {int(np.argmax(~np.isfinite(phi)))}")
    lines = ["x_mm,y_mm,phi_rad,class"]
    lines += [f"{x:.12f},{y:.12f},{p:.12f},{c}" for (x, y), p, c in zip(pts.tolist(), phi.tolist(), cls)]
    with atomic_write(path, "w") as f:
        f.write("\n".join(lines) + "\n")


# ----------------------------------------------------------------------------- DXF


def _closed_flags(layers: Mapping[str, Any], closed: bool | Mapping[str, bool] | None) -> dict[str, bool | None]:
    if closed is None or isinstance(closed, bool):
        return dict.fromkeys(layers, closed)
    if not isinstance(closed, Mapping):
        raise TypeError(f"closed must be None, a bool or a mapping layer -> bool, got {type(closed).__name__}")
    unknown = sorted(set(closed) - set(layers))
    if unknown:
        raise ValueError(f"closed names layers that are not in layers: {unknown}")
    return {name: (None if closed.get(name) is None else bool(closed[name])) for name in layers}


def write_outline_dxf(
    path: str | os.PathLike,
    layers: Mapping[str, Sequence[Any]],
    *,
    closed: bool | Mapping[str, bool] | None = None,
) -> None:
    """Write polylines (mm) to a deterministic DXF R2010 file, one LWPOLYLINE each.

    ``layers`` maps a layer name to a list of (n, 2) polylines (n ≥ 2). The
    standard layers of :data:`DXF_LAYER_COLORS` are always created, others with
    colour 7. ``closed`` is ``None`` (auto: a polyline is closed when its first and
    last points agree within 1e-12 mm, and the repeated point is dropped), a bool
    for every layer, or a mapping layer → bool (missing layers: auto). With
    ``closed=True`` a repeated last point is dropped as well.

    Units: ``$INSUNITS = 4`` (mm), ``$MEASUREMENT = 1`` (metric), decimal lengths
    and degrees. Coordinates are written at full double precision (shortest
    round-trip repr). The file is byte-identical for identical input: creation and
    update dates are fixed to 2000-01-01 and the GUIDs to zero.
    """
    from ezdxf.lldxf.validator import is_valid_layer_name

    if not isinstance(layers, Mapping):
        raise TypeError(f"layers must be a mapping layer name -> list of (n, 2) polylines, got {type(layers).__name__}")
    seen: dict[str, str] = {}
    polylines: dict[str, list[np.ndarray]] = {}
    for name, lines in layers.items():
        if not isinstance(name, str) or not is_valid_layer_name(name):
            raise ValueError(f"layers: {name!r} is not a valid DXF layer name")
        if name.lower() in seen:
            raise ValueError(f"layers: {name!r} and {seen[name.lower()]!r} are the same DXF layer (names ignore case)")
        seen[name.lower()] = name
        if isinstance(lines, np.ndarray) and lines.ndim == 2:
            raise TypeError(f"layers[{name!r}] must be a list of (n, 2) polylines, got one array; wrap it in a list")
        polylines[name] = []
        for i, line in enumerate(lines):
            p = _xy(line, f"layers[{name!r}][{i}]")
            if len(p) < 2:
                raise ValueError(f"layers[{name!r}][{i}] must have at least 2 points, got {len(p)}")
            polylines[name].append(p)
    flags = _closed_flags(layers, closed)

    standard = {k.lower() for k in DXF_LAYER_COLORS}
    extra = [n for n in polylines if n.lower() not in standard]
    with dxf_document(extra, rename=seen) as doc:
        msp = doc.modelspace()
        lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
        for name, lines in polylines.items():
            for p in lines:
                same_ends = bool(np.all(np.abs(p[-1] - p[0]) <= _CLOSE_TOL_MM))
                close = same_ends if flags[name] is None else flags[name]
                if close and same_ends and len(p) > 2:
                    p = p[:-1]
                msp.add_lwpolyline(p.tolist(), format="xy", close=close, dxfattribs={"layer": name})
                lo, hi = np.minimum(lo, p.min(0)), np.maximum(hi, p.max(0))
        save_dxf(doc, path, (lo, hi) if np.all(np.isfinite(lo)) else None)


@contextlib.contextmanager
def dxf_document(extra_layers=(), *, rename: Mapping[str, str] | None = None):
    """A new deterministic DXF R2010 document in mm with the standard layers.

    Holds the process-wide lock around ezdxf's fixed-metadata switch (fixed dates,
    GUIDs and version marker, so identical input gives a byte-identical file) until
    the block ends: write the file inside it, with :func:`save_dxf`. ``rename`` maps
    a lower-cased standard layer name to the caller's spelling.
    """
    import ezdxf

    with _FIXED_DXF_LOCK:
        saved = ezdxf.options.write_fixed_meta_data_for_testing
        ezdxf.options.write_fixed_meta_data_for_testing = True
        try:
            doc = ezdxf.new("R2010", setup=False)
            doc.units = ezdxf.units.MM  # $INSUNITS = 4
            for var, value in {
                "$MEASUREMENT": 1, "$LUNITS": 2, "$LUPREC": 6, "$AUNITS": 0, "$AUPREC": 4,
                "$TDINDWG": 0.0, "$TDUSRTIMER": 0.0,
            }.items():
                doc.header[var] = value
            rename = rename or {}
            for name, color in DXF_LAYER_COLORS.items():
                doc.layers.add(rename.get(name.lower(), name), color=color, linetype="Continuous")
            for name in extra_layers:
                doc.layers.add(name, color=7, linetype="Continuous")
            yield doc
        finally:
            ezdxf.options.write_fixed_meta_data_for_testing = saved


def _set_extents(doc, extents) -> None:
    """The modelspace's extents and the view fitted to them, from (lo, hi)."""
    msp = doc.modelspace()
    lo, hi = extents
    msp.dxf.extmin = (float(lo[0]), float(lo[1]), 0.0)
    msp.dxf.extmax = (float(hi[0]), float(hi[1]), 0.0)
    size = hi - lo
    doc.set_modelspace_vport(height=float(max(size[1], size[0] * 0.75, 1e-3) * 1.1),
                             center=(float(lo[0] + hi[0]) / 2, float(lo[1] + hi[1]) / 2))


def save_dxf(doc, path: str | os.PathLike, extents, *, entities: str = "") -> None:
    """Set the drawing extents and view from (lo, hi) (or None) and write the file atomically.

    ``entities``: DXF text of modelspace entities made outside ezdxf (their handles reserved
    from ``doc.entitydb.handles`` before any entity added with ezdxf), written first in the
    ENTITIES section."""
    if extents is not None:
        _set_extents(doc, extents)
    with atomic_write(path, "w", encoding=doc.output_encoding) as f:
        if not entities:
            _sorted_classes(doc)
            doc.write(f)
        else:
            f.write(dxf_text(doc, None, entities=entities))


def _sorted_classes(doc) -> None:
    # ezdxf adds the CLASS entries of the object types in use from a set, so their order
    # followed the string hash (PYTHONHASHSEED): add them now and sort, the same in every process
    doc.classes.add_required_classes(doc.dxfversion)
    doc.classes.classes = type(doc.classes.classes)(sorted(doc.classes.classes.items()))


def dxf_text(doc, extents, *, entities: str = "") -> str:
    """The text :func:`save_dxf` writes (encoded as ``doc.output_encoding``, UTF-8 for R2010),
    as a string: for a file made in another process. ``extents`` as in :func:`save_dxf`;
    None leaves the document's as they are."""
    import io

    if extents is not None:
        _set_extents(doc, extents)
    _sorted_classes(doc)
    buffer = io.StringIO()
    doc.write(buffer)
    text = buffer.getvalue()
    if not entities:
        return text
    marker = "  0\nSECTION\n  2\nENTITIES\n"
    at = text.index(marker) + len(marker)
    return text[:at] + entities + text[at:]


def read_dxf_polylines(path: str | os.PathLike) -> dict[str, list[np.ndarray]]:
    """The LWPOLYLINEs of a DXF file's modelspace, by layer, as (n, 2) arrays in file order.

    A closed polyline comes back with its first point repeated at the end, so a
    closed outline written in auto mode reads back as it was given. Layers
    without polylines are not listed. Raises ``OSError`` for an unreadable file
    and ``ezdxf.DXFStructureError`` for a broken one.
    """
    import ezdxf
    from ezdxf.entities import LWPolyline

    doc = ezdxf.readfile(os.fspath(path))
    out: dict[str, list[np.ndarray]] = {}
    for e in doc.modelspace().query("LWPOLYLINE"):
        assert isinstance(e, LWPolyline)  # what the query selects
        p = np.array(list(e.get_points("xy")), dtype=float).reshape(-1, 2)
        if e.closed and len(p):
            p = np.vstack([p, p[:1]])
        out.setdefault(e.dxf.layer, []).append(p)
    return out
