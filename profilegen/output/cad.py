"""CAD output with true lines and arcs: DXF (LINE / ARC), SVG (path ``L`` / ``A``), a PNG preview.

Contours come in as :mod:`profilegen.geometry.contour` elements — :class:`~profilegen.geometry.contour.Line`,
:class:`~profilegen.geometry.contour.Arc` (signed sweep) and :class:`~profilegen.geometry.contour.Chain` —
grouped by layer. Nothing is sampled: a CAD system or a wire-EDM post-processor gets
the exact geometry.

* :func:`write_contours_dxf` — DXF R2010 in mm, one LINE per line and one ARC per arc
  (DXF arcs always run counter-clockwise, so a clockwise arc is written as its
  counter-clockwise twin; a full circle becomes a CIRCLE), full double precision,
  byte-identical output for identical input, optional TEXT for annotations.
* :func:`read_dxf_contours` — LINE / ARC / CIRCLE back as elements (arcs counter-clockwise);
  :func:`oriented_chain` and :func:`chain_gaps` re-orient such elements into a chain
  and measure its joins; :func:`audit` counts the errors ezdxf's auditor finds.
* :func:`write_contours_svg` — the same contours as SVG paths with true arcs, in mm,
  y pointing up as in the DXF, one ``<g>`` per layer in the layer's colour.
* :func:`render_dxf_png` — a preview rendered from the DXF file itself (ezdxf's drawing
  add-on, matplotlib's Agg canvas), so it shows what the file holds.

Every writer goes through :func:`profilegen.output.export.atomic_write`: a failure leaves
nothing partial and an ``OSError`` becomes an :class:`~profilegen.errors.ExportError`
naming the path. ezdxf and matplotlib are imported inside the functions only.

A slot (two half circles joined by two lines), written and read back:

>>> import math, pathlib, tempfile
>>> from profilegen.geometry.contour import Arc, Chain, Line
>>> slot = Chain([Line((0, -1), (4, -1)), Arc((4, 0), 1.0, -math.pi / 2, math.pi),
...               Line((4, 1), (0, 1)), Arc((0, 0), 1.0, math.pi / 2, math.pi)])
>>> path = pathlib.Path(tempfile.mkdtemp()) / "slot.dxf"
>>> write_contours_dxf(path, {"CS": [slot]})
>>> back = read_dxf_contours(path)
>>> [type(e).__name__ for e in back["CS"]], audit(path)
(['Line', 'Arc', 'Line', 'Arc'], 0)
>>> float(chain_gaps(back["CS"], closed=True).max()) < 1e-12
True
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any
from xml.sax.saxutils import escape, quoteattr

import numpy as np

from ..geometry.contour import Arc, Chain, ContourError, Line, Polyline
from . import dxftext
from .export import DXF_LAYER_COLORS, atomic_write, dxf_document, save_dxf

__all__ = [
    "write_contours_dxf",
    "read_dxf_contours",
    "oriented_chain",
    "chain_gaps",
    "audit",
    "write_contours_svg",
    "render_dxf_png",
]

_UNITS = {"mm": 4}  # DXF $INSUNITS codes; profilegen works in mm throughout
_FULL_TURN = 2.0 * math.pi
_JOIN_TOL_MM = 1e-9  # SVG: a chain element starting farther than this from the last end starts a new subpath

#: Write standard drawings from the stored template (:mod:`profilegen.output.dxftext`), not through
#: an ezdxf document: the same bytes (tests/unit/test_dxf_template.py), without ezdxf's import.
USE_TEMPLATE = True

Item = Chain | Line | Arc | Polyline
Text = tuple[str, tuple[float, float], float, str]


# ----------------------------------------------------------------------------- input checks


def _check_layers(layers: Any, texts: Sequence[Text] | None) -> tuple[list[str], dict[str, list[Item]], list[Text]]:
    """Validated layers (in writing order: the standard ones first) and texts."""
    if not isinstance(layers, Mapping):
        raise TypeError(f"layers must be a mapping layer name -> list of Chain/Line/Arc, got {type(layers).__name__}")
    seen: dict[str, str] = {}

    def name_ok(name: Any, where: str) -> str:
        if isinstance(name, str) and name in DXF_LAYER_COLORS:  # valid: no need to import ezdxf's rule
            return name
        from ezdxf.lldxf.validator import is_valid_layer_name

        if not isinstance(name, str) or not is_valid_layer_name(name):
            raise ValueError(f"{where}: {name!r} is not a valid DXF layer name")
        return name

    items: dict[str, list[Item]] = {}
    for name, elements in layers.items():
        name_ok(name, "layers")
        if name.lower() in seen:
            raise ValueError(f"layers: {name!r} and {seen[name.lower()]!r} are the same DXF layer (names ignore case)")
        seen[name.lower()] = name
        if isinstance(elements, (Chain, Line, Arc, Polyline)):
            raise TypeError(f"layers[{name!r}] must be a list of Chain/Line/Arc, "
                            f"got one {type(elements).__name__}; wrap it in a list")
        if not isinstance(elements, Iterable) or isinstance(elements, (str, bytes)):
            raise TypeError(f"layers[{name!r}] must be a list of Chain/Line/Arc, got {type(elements).__name__}")
        items[name] = []
        for i, item in enumerate(elements):
            where = f"layers[{name!r}][{i}]"
            if isinstance(item, Chain):
                for k, e in enumerate(item.elements):
                    _check_element(e, f"{where}.elements[{k}]")
            else:
                _check_element(item, where)
            items[name].append(item)

    checked_texts: list[Text] = []
    for i, t in enumerate(texts or ()):
        where = f"texts[{i}]"
        if not (isinstance(t, (tuple, list)) and len(t) == 4):
            raise TypeError(f"{where} must be (layer, (x_mm, y_mm), height_mm, string), got {t!r}")
        layer, xy, height, string = t
        name_ok(layer, where)
        layer = seen.get(layer.lower(), layer)
        p = np.asarray(xy, dtype=float)
        if p.shape != (2,) or not np.isfinite(p).all():
            raise ValueError(f"{where}: position must be two finite numbers (mm), got {xy!r}")
        if not (isinstance(height, (int, float)) and math.isfinite(height) and height > 0):
            raise ValueError(f"{where}: height_mm must be > 0 and finite, got {height!r}")
        if not isinstance(string, str) or not string or any(ord(c) < 32 for c in string):
            raise ValueError(f"{where}: string must be a non-empty single line without control characters, got {string!r}")
        checked_texts.append((layer, (float(p[0]), float(p[1])), float(height), string))
        seen.setdefault(layer.lower(), layer)

    standard = [seen.get(k.lower(), k) for k in DXF_LAYER_COLORS]
    std_lower = {k.lower() for k in DXF_LAYER_COLORS}
    others = [n for n in seen.values() if n.lower() not in std_lower]
    return standard + others, items, checked_texts


def _check_element(e: Any, where: str) -> None:
    if isinstance(e, Polyline):
        return  # validated on construction
    if isinstance(e, Line):
        if not (np.isfinite(e.start).all() and np.isfinite(e.end).all()):
            raise ValueError(f"{where}: line ends must be finite, got {e.start.tolist()} -> {e.end.tolist()}")
    elif isinstance(e, Arc):
        if not (np.isfinite(e.centre).all() and math.isfinite(e.start_angle) and math.isfinite(e.sweep)):
            raise ValueError(f"{where}: arc centre and angles must be finite, got centre {e.centre.tolist()}, "
                             f"start {e.start_angle!r} rad, sweep {e.sweep!r} rad")
        if 1e-9 < abs(e.sweep) < _FULL_TURN - 1e-9:  # its ends are > 5e-8° apart in DXF degrees (< 360)
            return
        _, _, start_deg, end_deg = e.to_ccw()
        if start_deg == end_deg and not _is_full_circle(e):  # DXF would read it as a full circle
            raise ValueError(f"{where}: arc sweep {e.sweep!r} rad is too small to tell its ends apart in DXF degrees")
    else:
        raise TypeError(f"{where} must be a Chain, Line, Arc or Polyline, got {type(e).__name__}")


def _elements(item: Item) -> tuple:
    return item.elements if isinstance(item, Chain) else (item,)


def _is_full_circle(a: Arc) -> bool:
    return abs(a.sweep) >= _FULL_TURN - 1e-12


def _extents(items: dict[str, list[Item]], texts: list[Text]) -> tuple[np.ndarray, np.ndarray] | None:
    """The drawing's exact bounding box: the ends of lines and arcs, an arc's extreme points where
    it crosses the axes, a polyline's box; one minimum and maximum over all of them (a min/max
    per element cost ~0.1 s per file)."""
    points: list = []
    boxes: list = []
    quarter = [k * math.pi / 2 for k in range(4)]
    cos, sin = math.cos, math.sin
    for layer_items in items.values():
        for item in layer_items:
            for e in _elements(item):
                if isinstance(e, Line):
                    points += (e.start, e.end)
                elif isinstance(e, Polyline):
                    boxes += (e.points.min(0), e.points.max(0))
                else:  # Arc.point_at in floats (the same roundings, without an array per point)
                    (cx, cy), r = e.centre.tolist(), e.radius
                    start, sweep = e.start_angle, e.sweep
                    a0 = start if sweep > 0 else start + sweep
                    for a in [start, start + sweep] + [q for q in quarter if (q - a0) % _FULL_TURN <= abs(sweep)]:
                        points.append((cx + r * cos(a), cy + r * sin(a)))
    for _, (x, y), h, s in texts:  # a text's box, roughly: 0.7 h per character
        boxes += ((x, y), (x + 0.7 * h * len(s), y + h))
    if not points and not boxes:
        return None
    p = np.array(points + boxes, dtype=float).reshape(-1, 2)
    lo, hi = p.min(0), p.max(0)
    return (lo, hi) if np.isfinite(lo).all() else None


def _xy_tags(pts: np.ndarray) -> str:
    """`` 10\nx\n 20\ny\n`` per point, floats as their shortest round-trip repr (ezdxf's), formatted
    by one repr of the whole list rather than one f-string a point."""
    values = repr(pts.ravel().tolist())[1:-1].split(", ") if len(pts) else []
    return (" 10\n%s\n 20\n%s\n" * len(pts)) % tuple(values)


# ----------------------------------------------------------------------------- DXF


def write_contours_dxf(
    path: str | os.PathLike,
    layers: Mapping[str, Sequence[Item]],
    *,
    units: str = "mm",
    texts: Sequence[Text] | None = None,
) -> None:
    """Write contours to a deterministic DXF R2010 file: one LINE per Line, one ARC per Arc.

    ``layers`` maps a layer name to a list of :class:`Chain`, :class:`Line` or
    :class:`Arc`; a chain's elements are written in order. The standard layers of
    :data:`profilegen.output.export.DXF_LAYER_COLORS` (CS red, FS blue, WG green,
    construction grey, annotation white) are always created, others with colour 7.
    Entities go in layer order, except that the ``construction`` layer comes first
    (CAD programs draw in file order, so construction lines lie underneath).

    DXF arcs run counter-clockwise from their start to their end angle, so a
    clockwise arc (negative sweep) is written with its ends swapped — the same
    curve; its direction of travel is not stored. A full circle (``|sweep| = 2π``)
    is written as a CIRCLE. ``texts`` is a list of ``(layer, (x_mm, y_mm),
    height_mm, string)``, each written as a left-aligned single-line TEXT whose
    baseline starts at (x, y) (use the ``annotation`` layer for drawing notes).

    Units: only ``units="mm"`` (profilegen works in mm): ``$INSUNITS = 4``,
    ``$MEASUREMENT = 1``, decimal lengths and degrees. Coordinates, radii and angles
    are written at full double precision (shortest round-trip repr); the header's
    dates and GUIDs are fixed, so identical input gives a byte-identical file.
    """
    if units not in _UNITS:
        raise ValueError(f"units must be one of {sorted(_UNITS)} (profilegen works in mm), got {units!r}")
    names, items, texts = _check_layers(layers, texts)
    extents = _extents(items, texts)
    # construction geometry first, so CAD programs (which draw in file order) show it underneath
    ordered = [(name, e) for name, layer_items in sorted(items.items(), key=lambda kv: kv[0].lower() != "construction")
               for item in layer_items for e in _elements(item)]
    if USE_TEMPLATE and extents is not None and dxftext.covers(names, DXF_LAYER_COLORS, texts):
        # the standard document without ezdxf (its import and document cost more than the geometry
        # stages): ezdxf's own text for it, from a stored template (profilegen.output.dxftext)
        handles = [f"{dxftext.FIRST_HANDLE + i:X}" for i in range(len(ordered) + len(texts))]
        body = _entities_text(ordered, handles, dxftext.OWNER) + "".join(
            dxftext.text_entity(layer, xy, height, string, handle)
            for (layer, xy, height, string), handle in zip(texts, handles[len(ordered):]))
        with atomic_write(path, "w", encoding="utf-8") as f:
            f.write(dxftext.document(body, len(handles), extents))
        return

    std_lower = {k.lower() for k in DXF_LAYER_COLORS}
    with dxf_document([n for n in names if n.lower() not in std_lower], rename={n.lower(): n for n in names}) as doc:
        msp = doc.modelspace()
        # The entities' text is made here (ezdxf's per-tag export took ~1 ms an entity, most of
        # a design's file time); the handles are reserved from the document's generator in the
        # order ezdxf would give them, so the file is byte-identical to adding them with ezdxf.
        handles = [doc.entitydb.handles.next() for _ in ordered]
        body = _entities_text(ordered, handles, msp.block_record_handle)
        for layer, xy, height, string in texts:
            msp.add_text(string, height=height, dxfattribs={"layer": layer, "insert": xy})
        save_dxf(doc, path, extents, entities=body)


_TAG = "%3d\n%s\n"


def _entities_text(ordered: Sequence[tuple[str, Any]], handles: Sequence[str], owner: str) -> str:
    """DXF R2010 text of LINE / ARC / CIRCLE / LWPOLYLINE entities, exactly as ezdxf writes them
    (group codes right-aligned in 3 columns, floats as their shortest round-trip repr)."""
    out: list[str] = []
    add = out.append
    for (layer, e), handle in zip(ordered, handles):
        head = f"  0\n%s\n  5\n{handle}\n330\n{owner}\n100\nAcDbEntity\n  8\n{layer}\n"
        if isinstance(e, Line):
            (x0, y0), (x1, y1) = e.start.tolist(), e.end.tolist()
            add(head % "LINE" + f"100\nAcDbLine\n 10\n{x0!r}\n 20\n{y0!r}\n 30\n0.0\n"
                                f" 11\n{x1!r}\n 21\n{y1!r}\n 31\n0.0\n")
        elif isinstance(e, Polyline):
            pts = e.points[:-1] if e.closed and len(e.points) > 2 else e.points
            flat = _xy_tags(pts)
            add(head % "LWPOLYLINE" + f"100\nAcDbPolyline\n 90\n{len(pts)}\n 70\n{1 if e.closed else 0}\n" + flat)
        elif _is_full_circle(e):
            cx, cy = e.centre.tolist()
            add(head % "CIRCLE" + f"100\nAcDbCircle\n 10\n{cx!r}\n 20\n{cy!r}\n 30\n0.0\n 40\n{float(e.radius)!r}\n")
        else:
            centre, radius, start_deg, end_deg = e.to_ccw()
            cx, cy = centre.tolist()
            add(head % "ARC" + f"100\nAcDbCircle\n 10\n{cx!r}\n 20\n{cy!r}\n 30\n0.0\n 40\n{float(radius)!r}\n"
                               f"100\nAcDbArc\n 50\n{float(start_deg)!r}\n 51\n{float(end_deg)!r}\n")
    return "".join(out)


def _xy(p: np.ndarray) -> tuple[float, float]:
    return float(p[0]), float(p[1])


def _ocs_flip(extrusion, where: str) -> bool:
    """True for a mirrored OCS (extrusion −z), False for +z; an entity off the XY plane is an error."""
    ex, ey, ez = (float(v) for v in extrusion)
    if abs(ex) > 1e-9 or abs(ey) > 1e-9 or abs(abs(ez) - 1.0) > 1e-9:
        raise ContourError(f"{where}: extrusion {(ex, ey, ez)} is not ±z; only 2-D drawings in the XY plane are read")
    return ez < 0


def read_dxf_contours(path: str | os.PathLike) -> dict[str, list[Line | Arc]]:
    """The LINE, ARC and CIRCLE entities of a DXF file's modelspace, by layer, in file order.

    Lines keep their direction. Arcs come back counter-clockwise (positive sweep),
    as DXF stores them — a clockwise arc written by :func:`write_contours_dxf`
    comes back reversed (see :func:`oriented_chain`); a CIRCLE comes back as a
    full arc starting at angle 0. Arcs of a mirrored coordinate system (extrusion
    −z, as some CAD programs write after a mirror) are converted to the XY plane.
    z is dropped; other entity types (TEXT, ...) are skipped; layers without
    lines or arcs are not listed. Raises ``OSError`` for an unreadable file,
    ``ezdxf.DXFStructureError`` for a broken one and
    :class:`~profilegen.geometry.contour.ContourError` naming the entity for an arc off the
    XY plane or with a radius ≤ 0.
    """
    import ezdxf

    doc = ezdxf.readfile(os.fspath(path))
    out: dict[str, list[Line | Arc]] = {}
    for e in doc.modelspace().query("LINE ARC CIRCLE"):
        kind, layer = e.dxftype(), e.dxf.layer
        where = f"{kind} #{e.dxf.handle} on layer {layer!r}"
        if kind == "LINE":
            el: Line | Arc = Line(tuple(e.dxf.start)[:2], tuple(e.dxf.end)[:2])
        else:
            cx, cy = tuple(e.dxf.center)[:2]
            radius = float(e.dxf.radius)
            if kind == "CIRCLE":
                start, sweep = 0.0, _FULL_TURN
            else:
                start_deg, end_deg = float(e.dxf.start_angle), float(e.dxf.end_angle)
                sweep_deg = (end_deg - start_deg) % 360.0
                start, sweep = math.radians(start_deg), math.radians(sweep_deg or 360.0)
            try:
                if _ocs_flip(e.dxf.extrusion, where):  # OCS x axis is −x: x → −x, angle a → π − a, sweep flips
                    el = Arc((-cx, cy), radius, math.pi - start, -sweep).reversed()
                else:
                    el = Arc((cx, cy), radius, start, sweep)
            except ContourError as exc:
                raise ContourError(f"{where}: {exc}") from exc
        out.setdefault(layer, []).append(el)
    return out


def oriented_chain(elements: Chain | Sequence[Line | Arc]) -> Chain:
    """The elements in the given order, each reversed where needed to start where the one before ends.

    For elements read back from a DXF file, whose arcs all run counter-clockwise:
    the first element is turned to face the second; each next one is reversed when
    its end, not its start, is the nearer to the previous end.
    """
    els = list(elements.elements if isinstance(elements, Chain) else elements)
    if not els:
        raise ContourError("oriented_chain: elements is empty")
    if len(els) > 1:
        a, b = els[0], els[1]
        forward = min(np.hypot(*(a.end - b.start)), np.hypot(*(a.end - b.end)))
        backward = min(np.hypot(*(a.start - b.start)), np.hypot(*(a.start - b.end)))
        if backward < forward:
            els[0] = a.reversed()
    out = [els[0]]
    for e in els[1:]:
        if np.hypot(*(out[-1].end - e.end)) < np.hypot(*(out[-1].end - e.start)):
            e = e.reversed()
        out.append(e)
    return Chain(tuple(out))


def chain_gaps(elements: Chain | Sequence[Line | Arc], closed: bool = False) -> np.ndarray:
    """Gaps (mm) at the joins of :func:`oriented_chain` (elements) — the last one back to the first if ``closed``."""
    return oriented_chain(elements).gaps(closed)


def audit(path: str | os.PathLike) -> int:
    """The number of errors ezdxf's auditor finds in a DXF file (0 for a clean file)."""
    import ezdxf

    doc = ezdxf.readfile(os.fspath(path))
    return len(doc.audit().errors)


# ----------------------------------------------------------------------------- SVG


def _num(x: float) -> str:
    """Shortest round-trip repr, no negative zero."""
    return repr(float(x) + 0.0)


#: ezdxf's aci2rgb of the standard layers' colours (tests/unit/test_sketch_files.py checks them): the SVG needs no ezdxf import (~0.4 s)
_ACI_RGB = {1: "#ff0000", 3: "#00ff00", 5: "#0000ff", 8: "#808080"}


def _svg_colour(aci: int) -> str:
    if aci == 7:  # ACI 7 is "foreground": black on the white page
        return "#000000"
    if aci in _ACI_RGB:
        return _ACI_RGB[aci]
    import ezdxf.colors

    r, g, b = ezdxf.colors.aci2rgb(aci)
    return f"#{r:02x}{g:02x}{b:02x}"


def _svg_path(item: Item) -> str:
    """Path data of one chain or element, y flipped (y_svg = −y): ``M``, ``L``, ``A``, ``Z``."""

    def pt(p) -> str:
        return f"{_num(p[0])} {_num(-p[1])}"

    els = _elements(item)
    cmds = [f"M {pt(els[0].start)}"]
    here = els[0].start
    for e in els:
        if np.hypot(*(e.start - here)) > _JOIN_TOL_MM:
            cmds.append(f"M {pt(e.start)}")
        if isinstance(e, Line):
            cmds.append(f"L {pt(e.end)}")
        elif isinstance(e, Polyline):
            cmds.extend(f"L {pt(q)}" for q in e.points[1:])
        else:
            # SVG's sweep-flag 1 turns clockwise on screen, i.e. counter-clockwise once y is flipped
            # back; arcs over half a turn (and full circles, whose ends meet) go in pieces ≤ 120°.
            n = 1 if abs(e.sweep) <= math.pi else math.ceil(abs(e.sweep) / (_FULL_TURN / 3))
            flag = 0 if e.sweep > 0 else 1
            r = _num(e.radius)
            for k in range(1, n + 1):
                end = e.end if k == n else e.point_at(e.start_angle + e.sweep * k / n)
                cmds.append(f"A {r} {r} 0 0 {flag} {pt(end)}")
        here = e.end
    if len(els) > 1 or isinstance(els[0], Arc):
        if np.hypot(*(els[-1].end - els[0].start)) <= _JOIN_TOL_MM:
            cmds.append("Z")
    return " ".join(cmds)


def write_contours_svg(
    path: str | os.PathLike,
    layers: Mapping[str, Sequence[Item]],
    *,
    stroke_mm: float = 0.01,
    texts: Sequence[Text] | None = None,
) -> None:
    """Write the contours as an SVG drawing in mm with true arcs, deterministic and atomic.

    One ``<path>`` per chain (a closed chain ends in ``Z``) and per loose element;
    lines are ``L`` and arcs ``A`` commands (arcs over 180° in pieces ≤ 120°). y is
    flipped (y_svg = −y) so the drawing looks like the DXF; the viewBox is in mm
    (``width``/``height`` carry the unit). One ``<g>`` per layer — the standard
    layers always, ``construction`` first so it lies underneath — stroked in the layer's DXF colour (ACI 7 as black) and marked
    as an Inkscape layer; a white background rectangle underlies the drawing.
    ``stroke_mm`` is the line width; ``texts`` as in :func:`write_contours_dxf`.
    Numbers are written at full precision (shortest round-trip repr).
    """
    if not (isinstance(stroke_mm, (int, float)) and math.isfinite(stroke_mm) and stroke_mm > 0):
        raise ValueError(f"stroke_mm must be > 0 and finite (mm), got {stroke_mm!r}")
    names, items, texts = _check_layers(layers, texts)
    extents = _extents(items, texts)
    if extents is None:
        lo, hi = np.array([-1.0, -1.0]), np.array([1.0, 1.0])
    else:
        lo, hi = extents
    margin = 0.02 * float(max(hi - lo)) + 2 * stroke_mm
    x0, y0 = float(lo[0]) - margin, -float(hi[1]) - margin  # top-left corner in flipped coordinates
    width, height = float(hi[0] - lo[0]) + 2 * margin, float(hi[1] - lo[1]) + 2 * margin
    colours = {k.lower(): c for k, c in DXF_LAYER_COLORS.items()}

    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        '<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" '
        f'version="1.1" width="{_num(width)}mm" height="{_num(height)}mm" '
        f'viewBox="{_num(x0)} {_num(y0)} {_num(width)} {_num(height)}">',
        "<!-- profilegen: units mm; y up as in the DXF (y_svg = -y) -->",
        f'<rect x="{_num(x0)}" y="{_num(y0)}" width="{_num(width)}" height="{_num(height)}" fill="#ffffff" stroke="none"/>',
    ]
    for name in sorted(names, key=lambda n: n.lower() != "construction"):  # construction underneath
        colour = _svg_colour(colours.get(name.lower(), 7))
        out.append(
            f'<g id={quoteattr(name)} inkscape:groupmode="layer" inkscape:label={quoteattr(name)} '
            f'stroke="{colour}" stroke-width="{_num(stroke_mm)}" fill="none" '
            'stroke-linecap="round" stroke-linejoin="round">'
        )
        for item in items.get(name, ()):
            out.append(f'<path d="{_svg_path(item)}"/>')
        for layer, (x, y), h, s in texts:
            if layer == name:
                out.append(f'<text x="{_num(x)}" y="{_num(-y)}" font-size="{_num(h)}" '
                           f'font-family="sans-serif" fill="{colour}" stroke="none">{escape(s)}</text>')
        out.append("</g>")
    out.append("</svg>")
    with atomic_write(path, "w") as f:
        f.write("\n".join(out) + "\n")


# ----------------------------------------------------------------------------- PNG preview


def render_dxf_png(path_dxf: str | os.PathLike, path_png: str | os.PathLike, *, dpi: float = 150) -> None:
    """Render a DXF file's modelspace to PNG with ezdxf's drawing add-on (white background).

    The picture comes from the file itself, not from the elements that were
    written, so it shows what a CAD program gets. The figure is 8 inches on its
    longer side (1200 px at 150 dpi), in the drawing's aspect ratio; layer colours
    as in the file, ACI 7 drawn black. Raises ``OSError`` / ``ezdxf.DXFStructureError``
    for a bad input file and :class:`~profilegen.errors.ExportError` when the PNG
    cannot be written (nothing partial is left).
    """
    if not (isinstance(dpi, (int, float)) and math.isfinite(dpi) and 10 <= dpi <= 2400):
        raise ValueError(f"dpi must be in [10, 2400], got {dpi!r}")
    import ezdxf
    from ezdxf.addons.drawing import Frontend, RenderContext
    from ezdxf.addons.drawing.config import BackgroundPolicy, ColorPolicy, Configuration
    from ezdxf.addons.drawing.matplotlib import MatplotlibBackend  # imports pyplot; only the OO API is used
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    doc = ezdxf.readfile(os.fspath(path_dxf))
    fig = Figure(dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    config = Configuration(background_policy=BackgroundPolicy.WHITE, color_policy=ColorPolicy.COLOR)
    Frontend(RenderContext(doc), MatplotlibBackend(ax, adjust_figure=False), config=config).draw_layout(
        doc.modelspace(), finalize=True
    )
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    w, h = abs(x1 - x0), abs(y1 - y0)
    side = 8.0
    if w > 0 and h > 0:
        fig.set_size_inches(side * min(1.0, w / h), side * min(1.0, h / w))
    else:
        fig.set_size_inches(side, side)
    with atomic_write(Path(os.fspath(path_png)), "wb") as f:
        fig.savefig(f, format="png", dpi=dpi, facecolor="white", metadata={"Software": None})
