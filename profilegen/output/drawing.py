"""A dimensioned drawing of the circular spline: ``circular_spline_drawing.dxf``.

The CAD files of :mod:`.cad` hold the geometry only; this module lays out a drawing a
machinist can read, on an A3 landscape sheet in modelspace (1 drawing unit = 1 mm on paper):

* **view of the ring** — the whole CS outline (true LINE / ARC entities), the tip and root
  circles and the blank's outer circle, their diameters dimensioned (DIMENSION entities),
  at a standard scale that fits (1:1 for the default set); a circle marks detail A;
* **detail A** — one tooth space enlarged (the largest standard scale that fits, 50:1 for
  the default set), every arc of the space chain radius-dimensioned (concave arcs labelled
  so; a mirror pair about the space's axis once, "2x"; an arc about the gear axis, the root,
  by a leader note), every arc centre marked ``C<n>``, each line numbered by a balloon, the
  profile tolerance in a feature control frame; the dimensions show true sizes (their text,
  and DIMLFAC = 1/scale). The space chain is taken as it comes, element by element, so root
  fillets and tip corners in it are dimensioned like any other arc;
* **element table** — every element of the space: arc radius, centre, sweep, convex or
  concave; line start, length and direction (gear frame: origin on the gear axis, y along
  the space's axis);
* **notes** — tooth count, module, the flank's fit and the profile tolerance (± the fit's
  largest deviation from the conjugate profile, ``profile.max_error_mm``, in mm and µm);
* **title block** — gear set, scene, date, profilegen version, units, projection (first
  angle, with its symbol), scales, sheet.

Layers: CS (the part), construction (centre lines, reference circles), annotation (frame,
title block, table, notes), dimensions (DIMENSION entities).

Deterministic: the same design gives the same bytes. The date field comes from the ``date``
argument, else from ``SOURCE_DATE_EPOCH`` (UTC, as reproducible builds set it), else it is
left blank to be filled in when the drawing is released — never the clock.

Fast: the outline's ~2000 entities are written as text through :mod:`.cad`'s writer, only the
~20 dimensions and the texts go through ezdxf.
"""

from __future__ import annotations

import datetime as _dt
import math
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..geometry.contour import Arc, Chain, Line
from . import cad
from .export import atomic_write, dxf_document, dxf_text

if TYPE_CHECKING:  # pragma: no cover
    from ..pipeline.design import Design

__all__ = ["write_cs_drawing", "cs_drawing_dxf", "drawing_date", "DIMENSION_LAYER"]

#: The layer of the DIMENSION entities.
DIMENSION_LAYER = "dimensions"
_DIMSTYLE = "PROFILEGEN"
_SHEET = (420.0, 297.0)  # A3 landscape, mm
_BORDER = (20.0, 10.0, 10.0, 10.0)  # left (filing margin), bottom, right, top
_TITLE_W, _TITLE_H = 180.0, 48.0
_SCALES = (100.0, 50.0, 20.0, 10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01)
_TXT = 3.5  # dimension and note text height, mm on paper
_SMALL = 2.5


# ----------------------------------------------------------------------------- small geometry


def _scaled(e: Line | Arc, scale: float, origin, at) -> Line | Arc:
    """An element moved so that ``origin`` lands on ``at`` and enlarged by ``scale`` about it."""
    o, a = np.asarray(origin, float), np.asarray(at, float)
    if isinstance(e, Line):
        return Line((e.start - o) * scale + a, (e.end - o) * scale + a)
    return Arc((e.centre - o) * scale + a, e.radius * scale, e.start_angle, e.sweep)


def _scale_label(s: float) -> str:
    if s >= 1:
        return f"{s:g}:1"
    return f"1:{1 / s:g}"


def _pick_scale(size_mm: np.ndarray, box_mm: tuple[float, float]) -> float:
    for s in _SCALES:
        if size_mm[0] * s <= box_mm[0] and size_mm[1] * s <= box_mm[1]:
            return s
    return _SCALES[-1]


def _fmt(x: float, places: int = 4) -> str:
    s = f"{x:.{places}f}"
    return "0." + "0" * places if s == "-0." + "0" * places else s


@dataclass(frozen=True)
class _Rect:
    """A rotated rectangle on paper: ``o + s·u + t·v`` for s in [s0, s1], t in [t0, t1] (u ⟂ v, unit)."""

    o: np.ndarray
    u: np.ndarray
    s0: float
    s1: float
    t0: float
    t1: float

    @property
    def v(self) -> np.ndarray:
        return np.array([-self.u[1], self.u[0]])

    def corners(self) -> np.ndarray:
        s = np.array([self.s0, self.s0, self.s1, self.s1])[:, None]
        t = np.array([self.t0, self.t1, self.t0, self.t1])[:, None]
        return self.o + s * self.u + t * self.v

    def grid(self, step: float = 0.5) -> np.ndarray:
        """Points covering the rectangle, at most ``step`` apart (its edges included): at the layout
        grid's cell size they fall in every cell the rectangle covers."""
        ns = max(2, int(math.ceil((self.s1 - self.s0) / step)) + 1)
        nt = max(2, int(math.ceil((self.t1 - self.t0) / step)) + 1)
        ss = self.s0 + (self.s1 - self.s0) / (ns - 1) * np.arange(ns)
        tt = self.t0 + (self.t1 - self.t0) / (nt - 1) * np.arange(nt)
        return (self.o + (ss[None, :, None] * self.u + tt[:, None, None] * self.v)).reshape(-1, 2)


_CELL = 0.5  # mm: the detail's layout grid
_CHAR_W = 0.75  # a character's width / height, generously (LibreCAD's font: ~0.68)


def _text_rect(text: str, at, height: float, halign: str) -> _Rect:
    """A horizontal single-line text's box on paper."""
    w = _CHAR_W * height * len(text)
    x0 = {"left": 0.0, "center": -w / 2, "right": -w}[halign]
    return _Rect(np.asarray(at, float), np.array([1.0, 0.0]), x0, x0 + w, -0.25 * height, 1.15 * height)


# ----------------------------------------------------------------------------- the date


def drawing_date(date: _dt.date | str | None = None) -> str:
    """The date field: ``date`` (a ``datetime.date`` or ``YYYY-MM-DD``), else the UTC date of
    ``SOURCE_DATE_EPOCH`` when that is set, else ``""`` (left blank). Never the clock, so the
    same input gives the same file.

    >>> drawing_date("2026-01-31"), drawing_date(_dt.date(2025, 2, 1))
    ('2026-01-31', '2025-02-01')
    """
    if date is not None:
        if isinstance(date, _dt.datetime):
            return date.date().isoformat()
        if isinstance(date, _dt.date):
            return date.isoformat()
        if isinstance(date, str):
            try:
                return _dt.date.fromisoformat(date).isoformat()
            except ValueError:
                raise ValueError(f"date must be a date YYYY-MM-DD, got {date!r}") from None
        raise TypeError(f"date must be a datetime.date, a YYYY-MM-DD string or None, got {type(date).__name__}")
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch is None or not epoch.strip():
        return ""
    try:
        seconds = int(epoch)
    except ValueError:
        raise ValueError(f"SOURCE_DATE_EPOCH must be an integer number of seconds, got {epoch!r}") from None
    return _dt.datetime.fromtimestamp(seconds, tz=_dt.timezone.utc).date().isoformat()


# ----------------------------------------------------------------------------- the drawing


class _Sheet:
    """What goes on the sheet: fast-path elements (layer, Line/Arc), texts and dimensions (ezdxf)."""

    def __init__(self):
        self.elements: list[tuple[str, Line | Arc]] = []
        self.texts: list[tuple[str, tuple[float, float], float, str, str]] = []  # text, at, height, halign, layer
        self.dims: list[tuple[str, dict]] = []  # kind, arguments

    def line(self, p, q, layer: str = "annotation") -> None:
        self.elements.append((layer, Line(p, q)))

    def rect(self, x0, y0, x1, y1, layer: str = "annotation") -> None:
        for p, q in (((x0, y0), (x1, y0)), ((x1, y0), (x1, y1)), ((x1, y1), (x0, y1)), ((x0, y1), (x0, y0))):
            self.line(p, q, layer)

    def circle(self, centre, r, layer: str) -> None:
        self.elements.append((layer, Arc(centre, r, 0.0, 2 * math.pi)))

    def text(self, s: str, at, height: float = _TXT, halign: str = "left", layer: str = "annotation") -> None:
        self.texts.append((s, (float(at[0]), float(at[1])), height, halign, layer))

    def cross(self, at, size: float, layer: str = "construction") -> None:
        x, y = at
        self.line((x - size, y), (x + size, y), layer)
        self.line((x, y - size), (x, y + size), layer)


def _concave(arc: Arc, travel_sign: float) -> bool:
    """A concave arc of the part: its centre lies on the air side of the outline.

    The space is travelled about the gear axis with ``travel_sign`` (+1 counter-clockwise); the
    air (the bore, the gear axis) is then on the left of travel for +1, and an arc curving toward
    the air (sweep of that sign) is hollow in the part.
    """
    return math.copysign(1.0, arc.sweep) == travel_sign


def write_cs_drawing(path: str | os.PathLike, design: Design, *, date: _dt.date | str | None = None) -> None:
    """Write the dimensioned drawing of the circular spline (A3, mm, first angle) atomically.

    See the module docstring for what it shows. ``date`` fills the title block's date field
    (see :func:`drawing_date`: without it, ``SOURCE_DATE_EPOCH`` or blank). The file is
    byte-identical for identical input. An unwritable path raises
    :class:`~profilegen.errors.ExportError` naming it; nothing partial is left.
    """
    text = cs_drawing_dxf(design, date=date)
    with atomic_write(path, "w", encoding="utf-8") as f:
        f.write(text)


def cs_drawing_dxf(design: Design, *, date: _dt.date | str | None = None) -> str:
    """The text of :func:`write_cs_drawing`'s file (DXF R2010, UTF-8 when written): module
    level and reading only the design's profile, form, gear set and scene name, so a worker
    process can make it (:func:`profilegen.output.files.write_design` does, while this
    process writes the other files: ezdxf's import is most of its time)."""
    date_text = drawing_date(date)
    from .. import __version__

    prof, form = design.profile, design.form
    assert prof is not None  # the drawing is a finished design's
    space: Chain = prof.space
    sheet = _Sheet()
    W, H = _SHEET
    left, bottom, right, top = _BORDER
    x_lo, y_lo, x_hi, y_hi = left, bottom, W - right, H - top
    sheet.rect(0.0, 0.0, W, H, "construction")  # the trimmed sheet
    sheet.rect(x_lo, y_lo, x_hi, y_hi)  # the frame

    # the right column: title block at the bottom, the notes above it, detail A on top;
    # the left column: the element table at the bottom, the ring above it
    col_x0 = x_hi - _TITLE_W - 5.0
    notes = _note_lines(design)
    notes_top = y_lo + _TITLE_H + 8.0 + 5.0 * len(notes)
    s_detail = _detail(sheet, space, (col_x0, notes_top + 4.0), (x_hi, y_hi), form, 2.0 * prof.max_error_mm)
    row_h = 5.0
    table_top = y_lo + 14.0 + (len(space.elements) + 1) * row_h
    _table(sheet, space, (x_lo + 6.0, table_top), row_h, form.root_radius_mm)

    view_lo, view_hi = np.array([x_lo, table_top + 6.0]), np.array([col_x0, y_hi])
    r_tip, r_root, r_out = form.tip_radius_mm, form.root_radius_mm, form.outer_radius_mm
    r_max = max(r_tip, r_root, r_out)
    s_ring = _pick_scale(np.array([2.0 * r_max + 40.0, 2.0 * r_max + 50.0]), tuple(view_hi - view_lo))
    # the ring low in its view: the diameters' texts go above it
    ring_c = np.array([0.5 * (view_lo[0] + view_hi[0]), view_lo[1] + 6.0 + r_max * s_ring])
    zero = np.zeros(2)
    # the outline stays in the gear's own coordinates (true size, centre at the origin, when the view
    # is 1:1: CAM can take it from the drawing as it is); the sheet is moved around it when written
    world = list(prof.outline.elements) if s_ring == 1.0 else [_scaled(e, s_ring, zero, zero) for e in prof.outline.elements]
    sheet.circle(ring_c, r_out * s_ring, "CS")
    for r in (r_tip, r_root):
        sheet.circle(ring_c, r * s_ring, "construction")
    arm = r_max * s_ring + 4.0
    sheet.line(ring_c - (arm, 0), ring_c + (arm, 0), "construction")
    sheet.line(ring_c - (0, arm), ring_c + (0, arm), "construction")
    _ring_dims(sheet, ring_c, s_ring, r_tip, r_root, r_out)
    # detail A's mark: the space on the view (the space's middle)
    ends = 0.5 * (np.asarray(space.start) + np.asarray(space.end))
    far = max((e.end for e in space.elements), key=lambda p: float(np.hypot(*p)))
    mark_c = ring_c + 0.5 * (ends + far) * s_ring
    mark_r = max(3.0, 2.0 * float(np.hypot(*(np.asarray(space.end) - np.asarray(space.start)))) * s_ring)
    sheet.circle(mark_c, mark_r, "annotation")
    sheet.text("A", mark_c + (mark_r + 0.8, mark_r + 0.3), 5.0)
    sheet.text(f"CIRCULAR SPLINE  {_scale_label(s_ring)}", (view_lo[0] + 6.0, view_hi[1] - 9.0), 5.0)

    _notes(sheet, notes, (col_x0 + 5.0, notes_top - 4.0))
    _title_block(sheet, design, (x_hi - _TITLE_W, y_lo), date_text, __version__, (s_ring, s_detail))
    return _text(sheet, world, -ring_c)


def _travel_sign(space: Chain) -> float:
    """+1 when the space runs counter-clockwise about the gear axis, −1 clockwise."""
    a, b = np.asarray(space.start), np.asarray(space.end)
    return 1.0 if a[0] * b[1] - a[1] * b[0] > 0 else -1.0


def _ring_dims(sheet: _Sheet, c: np.ndarray, s: float, r_tip: float, r_root: float, r_out: float) -> None:
    """Diameters of the tip, root and outer circles, each through the centre at its own angle."""
    over = {"dimlfac": 1.0 / s}
    # CAD programs put a diameter's text at the far end: at 60°, 120° and 150°, above the ring
    for r, angle_deg, note in ((r_tip, 240.0, " tip"), (r_root, 300.0, " root"), (r_out, 330.0, "")):
        sheet.dims.append(("diameter", dict(center=(float(c[0]), float(c[1])), radius=r * s, angle=angle_deg,
                                            text=f"%%c{_fmt(2.0 * r)}{note}", override=over)))


def _detail(sheet: _Sheet, space: Chain, box_lo, box_hi, form, tolerance_mm: float) -> float:
    """Detail A in the box (lo, hi corners, mm on paper): the space enlarged with its half lands,
    the reference circles, the radius / length dimensions and the arc centres. Returns its scale."""
    travel = _travel_sign(space)
    els = list(space.elements)
    arcs = [(i, e) for i, e in enumerate(els) if isinstance(e, Arc)]
    pts = np.vstack([e.sample(1e-4) for e in els])
    # arc centres shown: those within a few space widths (not the gear axis of a root arc)
    width = float(np.ptp(pts[:, 0])) + float(np.ptp(pts[:, 1]))
    near = [(i, a) for i, a in arcs if np.hypot(*(a.centre - pts.mean(0))) < 3.0 * width]
    allpts = np.vstack([pts] + [a.centre[None, :] for _, a in near])
    lo, hi = allpts.min(0), allpts.max(0)
    span = hi - lo
    box_lo, box_hi = np.asarray(box_lo, float), np.asarray(box_hi, float)
    room = box_hi - box_lo - (0.0, 10.0)  # the title on top
    S = _pick_scale(span * (1.25, 1.9), tuple(room))
    centre_gear = 0.5 * (lo + hi)
    at = np.array([0.5 * (box_lo[0] + box_hi[0]), box_lo[1] + 0.42 * room[1]])  # the root side, up, is the busier

    def to_sheet(p) -> np.ndarray:
        return (np.asarray(p, float) - centre_gear) * S + at

    # half lands either side (when the space starts and ends on the tip circle)
    r_tip = form.tip_radius_mm
    pitch = 2 * math.pi / form.cs_teeth
    a_start = math.atan2(space.start[1], space.start[0])
    a_end = math.atan2(space.end[1], space.end[0])
    gap = abs(math.remainder(a_end - a_start, 2 * math.pi))
    half_land = 0.5 * (pitch - gap)
    lands = []
    if half_land > 1e-9 and abs(np.hypot(*space.start) - r_tip) < 1e-6 and abs(np.hypot(*space.end) - r_tip) < 1e-6:
        lands = [Arc((0, 0), r_tip, a_start - travel * half_land, travel * half_land),
                 Arc((0, 0), r_tip, a_end, travel * half_land)]
    for e in els + lands:
        sheet.elements.append(("CS", _scaled(e, S, centre_gear, at)))
    # reference circles (tip, root) across the view and the space's axis
    axis_angle = math.atan2(centre_gear[1], centre_gear[0])
    half = 0.45 * (box_hi[0] - box_lo[0]) / S / form.root_radius_mm
    for r in (form.tip_radius_mm, form.root_radius_mm):
        sheet.elements.append(("construction", _scaled(Arc((0, 0), r, axis_angle - half, 2 * half), S, centre_gear, at)))
    u_axis = np.array([math.cos(axis_angle), math.sin(axis_angle)])
    sheet.line(to_sheet(u_axis * (form.tip_radius_mm - 0.12 * span[1])),
               to_sheet(u_axis * (form.root_radius_mm + 0.12 * span[1])), "construction")
    title = f"DETAIL A  {_scale_label(S)}"
    title_at = (at[0], box_hi[1] - 6.0)
    sheet.text(title, title_at, 5.0, "center")

    # what the dimension texts must keep clear of, as points on paper
    layout = _Layout(to_sheet(np.vstack([e.sample(1e-5) for e in els + lands])), box_lo + 1.0, box_hi - 1.0)
    layout.add_segment(to_sheet(u_axis * (form.tip_radius_mm - 0.12 * span[1])),
                       to_sheet(u_axis * (form.root_radius_mm + 0.12 * span[1])), 1.0)
    layout.add_rect(_text_rect(title, title_at, 5.0, "center"))
    over = {"dimlfac": 1.0 / S}
    mark = 1.5
    for i, a in near:
        c = to_sheet(a.centre)
        sheet.cross(c, mark)
        label = f"C{i + 1}"
        side = 1.0 if c[0] >= at[0] else -1.0
        lab_at = c + (side * (mark + 0.6), 0.6)
        halign = "left" if side > 0 else "right"
        sheet.text(label, lab_at, _SMALL, halign)
        layout.add_rect(_text_rect(label, lab_at, _SMALL, halign))
        layout.add_points(np.array([c + (-mark, 0), c + (mark, 0), c + (0, -mark), c + (0, mark), c]))

    # arcs: a radius dimension each — LibreCAD and ezdxf both draw it from the centre through a point
    # of the arc, the text beyond the arc along that line; the point is chosen along the arc so that
    # the text is clear. An arc about the gear axis (the root) gets a leader note: its centre is far.
    # a mirror pair about the space's axis (the same radius, mirrored centres) is dimensioned once, "2x"
    u_mid = np.asarray(space.start) / np.hypot(*space.start) + np.asarray(space.end) / np.hypot(*space.end)
    u_mid /= np.hypot(*u_mid)
    groups: list[list[Arc]] = []
    for i, a in near:
        twin = 2.0 * float(a.centre @ u_mid) * u_mid - a.centre
        for g in groups:
            b = g[0]
            if len(g) == 1 and abs(b.radius - a.radius) <= 1e-9 * max(1.0, a.radius) \
                    and np.hypot(*(b.centre - twin)) <= 1e-9 * max(1.0, float(np.hypot(*twin))) \
                    and _concave(a, travel) == _concave(b, travel) and b is not a:
                g.append(a)
                break
        else:
            groups.append([a])
    for g in groups:
        a = g[0]
        text = ("2x " if len(g) == 2 else "") + "R" + _fmt(a.radius) + (" concave" if _concave(a, travel) else "")
        k, mpoint = layout.radius_spot(g, to_sheet, S, text)
        sheet.dims.append(("radius", dict(center=tuple(map(float, to_sheet(g[k].centre))),
                                          mpoint=tuple(map(float, mpoint)), text=text, override=over)))
    for i, a in arcs:
        if (i, a) not in near:
            _root_note(sheet, layout, a, i + 1, to_sheet, _concave(a, travel), form)
    # the table's row numbers: an arc's is its centre's label (C<n>, the radius line runs from it),
    # the root arc's starts its note, a line's is in a balloon beside it
    for i, e in enumerate(els):
        if isinstance(e, Line):
            _balloon(sheet, layout, e, i + 1, to_sheet, at)
    _profile_frame(sheet, layout, els, to_sheet, at, tolerance_mm)
    return S


def _profile_frame(sheet: _Sheet, layout: "_Layout", els: list, to_sheet, at, tolerance_mm: float) -> None:
    """ISO 1101 feature control frame "profile of a line, zone ``tolerance_mm``" with a leader to the
    first flank element, in the first clear spot beside the profile."""
    value = _fmt(tolerance_mm)
    h = 2.0 * _TXT
    w = h + 1.6 + _CHAR_W * _TXT * len(value) + 1.6
    e = next((e for e in els if isinstance(e, Line)), els[0])  # a flank line; else the first arc, off its middle
    target = to_sheet(e.point_at(e.start_angle + 0.3 * e.sweep) if isinstance(e, Arc) else 0.5 * (e.start + e.end))
    side = -1.0 if target[0] < at[0] else 1.0  # outward, on the flank's side
    found = None
    for dy in (0.0, -6.0, 6.0, -12.0, 12.0, -18.0, 18.0, -24.0, 24.0, -30.0):
        for dx in (12.0, 18.0, 24.0, 30.0, 36.0, 44.0, 52.0, 60.0):
            x0 = target[0] + side * dx - (w if side < 0 else 0.0)
            rect = _Rect(np.array([x0, target[1] + dy - h / 2]), np.array([1.0, 0.0]), 0.0, w, 0.0, h)
            attach = np.array([x0 + (w if side < 0 else 0.0), target[1] + dy])
            if layout.free(rect, 0.8) and layout.clear_segment(attach, target + 2.0 * (attach - target) / np.hypot(*(attach - target)), 0.4):
                found = (x0, attach)
                break
        if found:
            break
    if found is None:
        return  # the note on the sheet states it
    x0, attach = found
    y0 = attach[1] - h / 2
    sheet.rect(x0, y0, x0 + w, y0 + h, DIMENSION_LAYER)
    sheet.line((x0 + h, y0), (x0 + h, y0 + h), DIMENSION_LAYER)
    sheet.elements.append((DIMENSION_LAYER, Arc((x0 + h / 2, y0 + 0.3 * h), 0.28 * h, 0.0, math.pi)))  # "profile of a line"
    sheet.text(value, (x0 + h + 1.6, y0 + 0.5 * h - 0.5 * _TXT), _TXT, "left", DIMENSION_LAYER)
    sheet.line(attach, target, DIMENSION_LAYER)
    u = (target - attach) / np.hypot(*(target - attach))
    for turn in (0.3, -0.3):
        v = -np.array([math.cos(turn) * u[0] - math.sin(turn) * u[1], math.sin(turn) * u[0] + math.cos(turn) * u[1]])
        sheet.line(target, target + 2.2 * v, DIMENSION_LAYER)
    layout.add_rect(_Rect(np.array([x0, y0]), np.array([1.0, 0.0]), 0.0, w, 0.0, h))
    layout.add_segment(attach, target)


def _balloon(sheet: _Sheet, layout: "_Layout", e, number: int, to_sheet, at) -> None:
    """The element's number in a circle beside it, joined to a point of it by a straight line: the
    first clear spot from its middle outward, along its normal and then turned up to ±60° from it."""
    r = 2.2
    ps = to_sheet(e.sample(1e-5))
    found = None
    for dist in (4.5, 6.0, 7.5, 9.0, 11.0, 13.0, 16.0):
        for frac in (0.5, 0.35, 0.65, 0.2, 0.8):
            k = min(max(int(round(frac * (len(ps) - 1))), 1), len(ps) - 1)
            p = ps[k]
            d = ps[k] - ps[k - 1]
            n = np.array([-d[1], d[0]]) / np.hypot(*d)
            toward = 1.0 if float(np.dot(n, at - p)) > 0 else -1.0  # into the space first
            for turn in (0.0, 0.5, -0.5, 1.0, -1.0):
                for side in (toward, -toward):
                    v = side * np.array([math.cos(turn) * n[0] - math.sin(turn) * n[1],
                                         math.sin(turn) * n[0] + math.cos(turn) * n[1]])
                    c = p + dist * v
                    rect = _Rect(c - (r, r), np.array([1.0, 0.0]), 0.0, 2 * r, 0.0, 2 * r)
                    if layout.free(rect, 0.4) and layout.clear_segment(p + 1.8 * v, c - r * v, 0.4):
                        found = (p, c, v)
                        break
                if found:
                    break
            if found:
                break
        if found:
            break
    if found is None:
        return  # no room: the table still lists it
    p, c, v = found
    sheet.circle(c, r, "annotation")
    sheet.line(p + 0.3 * v, c - r * v, "annotation")
    sheet.text(str(number), c - (0.0, 0.9), 1.8, "center")
    layout.add_rect(_Rect(c - (r, r), np.array([1.0, 0.0]), 0.0, 2 * r, 0.0, 2 * r))
    layout.add_segment(p, c)


def _root_note(sheet: _Sheet, layout: "_Layout", a: Arc, number: int, to_sheet, concave: bool, form) -> None:
    """An arc about the gear axis: a leader from a point of it out into the material and a note
    starting with its row number in the table."""
    on_root = abs(a.radius - form.root_radius_mm) < 1e-9
    text = f"{number}: R{_fmt(a.radius)}{' concave' if concave else ''}" + (" (root circle)" if on_root else " (centre: gear axis)")
    w = _CHAR_W * _SMALL * len(text)

    def candidates():
        for way in (1.0, -1.0):  # out into the material, else in across the space
            for frac in (0.9, 0.1, 0.5):  # off the middle, clear of the axis
                mid = a.point_at(a.start_angle + frac * a.sweep)
                p = to_sheet(mid)
                u = way * mid / np.hypot(*mid)  # radial
                for dist in np.arange(6.0, 72.0, 2.0):
                    knee = p + u * dist
                    for side in (1.0, -1.0):
                        start = knee + (side * 1.5, 0.6)
                        yield p, u, knee, side, start, _text_rect(text, start, _SMALL, "left" if side > 0 else "right")

    best, text_clear = None, None
    for cand in candidates():
        if layout.free(cand[5], 0.8):
            if layout.clear_segment(cand[0] + cand[1] * 2.0, cand[2], 0.4):
                best = cand
                break
            text_clear = text_clear or cand  # the text clear, its leader crossing something
    # else the first spot where the text is clear; else where it covers the fewest marks (it must be there)
    best = best or text_clear or min(candidates(), key=lambda c: layout.overlap(c[5], 0.8))
    p, u, knee, side, start, rect = best
    sheet.line(p, knee, DIMENSION_LAYER)
    sheet.line(knee, knee + (side * (1.5 + w), 0.0), DIMENSION_LAYER)
    for turn in (0.3, -0.3):  # an open arrowhead at the arc
        v = np.array([math.cos(turn) * u[0] - math.sin(turn) * u[1], math.sin(turn) * u[0] + math.cos(turn) * u[1]])
        sheet.line(p, p + 2.2 * v, DIMENSION_LAYER)
    sheet.text(text, start, _SMALL, "left" if side > 0 else "right", DIMENSION_LAYER)
    layout.add_rect(rect)
    layout.add_segment(p, knee)


class _Layout:
    """What a new text on detail A must keep clear of, as an occupancy grid over the view (cells of
    ``_CELL`` mm): the profile, the lines drawn and the texts placed so far mark their cells; a
    rectangle is free when it lies inside the view and none of the cells under it is marked."""

    def __init__(self, points: np.ndarray, lo, hi):
        self.lo, self.hi = np.asarray(lo, float), np.asarray(hi, float)  # the view's box
        self.shape = tuple(int(v) for v in np.ceil((self.hi - self.lo) / _CELL) + 1)
        self.occ = np.zeros(self.shape, dtype=bool)
        self.txt = np.zeros(self.shape, dtype=bool)  # the cells under texts (a text over a text is worst)
        self.add_points(points)

    def _cells(self, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        ij = np.floor((pts - self.lo) / _CELL).astype(int)
        ok = (ij[:, 0] >= 0) & (ij[:, 0] < self.shape[0]) & (ij[:, 1] >= 0) & (ij[:, 1] < self.shape[1])
        return ij[ok, 0], ij[ok, 1]

    def add_points(self, pts) -> None:
        self.occ[self._cells(np.asarray(pts, float).reshape(-1, 2))] = True

    def add_segment(self, p, q, step: float = 0.5 * _CELL) -> None:
        n = max(2, int(np.hypot(*(np.asarray(q) - np.asarray(p))) / step) + 1)
        t = np.linspace(0.0, 1.0, n)[:, None]
        self.add_points(np.asarray(p, float) * (1 - t) + np.asarray(q, float) * t)

    def add_rect(self, rect: _Rect) -> None:
        cells = self._cells(rect.grid(_CELL))
        self.occ[cells] = True
        self.txt[cells] = True

    def _block(self, grown: _Rect, grid: np.ndarray | None = None) -> tuple[np.ndarray, int]:
        """The cells under an upright rectangle (a block of the grid) and how many lie outside the view."""
        lo = np.floor((grown.o + (grown.s0, grown.t0) - self.lo) / _CELL).astype(int)
        hi = np.floor((grown.o + (grown.s1, grown.t1) - self.lo) / _CELL).astype(int) + 1
        a, b = np.maximum(lo, 0), np.maximum(np.minimum(hi, self.shape), np.maximum(lo, 0))
        block = (self.occ if grid is None else grid)[a[0]:b[0], a[1]:b[1]]
        return block, int(np.prod(hi - lo)) - block.size

    def _marked(self, rect: _Rect, margin: float) -> bool:
        grown = _Rect(rect.o, rect.u, rect.s0 - margin, rect.s1 + margin, rect.t0 - margin, rect.t1 + margin)
        if rect.u[0] == 1.0 and rect.u[1] == 0.0:  # upright: the block of cells under it
            return bool(self._block(grown)[0].any())
        return bool(self.occ[self._cells(grown.grid(_CELL))].any())

    def overlap(self, rect: _Rect, margin: float) -> int:
        """How many marked cells the rectangle covers — a text's ten times —, plus its cells outside the view."""
        grown = _Rect(rect.o, rect.u, rect.s0 - margin, rect.s1 + margin, rect.t0 - margin, rect.t1 + margin)
        if rect.u[0] == 1.0 and rect.u[1] == 0.0:
            block, outside = self._block(grown)
            return int(block.sum()) + 9 * int(self._block(grown, self.txt)[0].sum()) + outside
        pts = grown.grid(_CELL)
        i, j = self._cells(pts)
        return int(self.occ[i, j].sum()) + 9 * int(self.txt[i, j].sum()) + (len(pts) - len(i))

    def free(self, rect: _Rect, margin: float = 0.8) -> bool:
        corners = rect.corners()
        if np.any(corners < self.lo) or np.any(corners > self.hi):
            return False
        return not self._marked(rect, margin)

    def clear_segment(self, p, q, gap: float = 0.6) -> bool:
        """No marked cell within ``gap`` of the segment p–q."""
        p, q = np.asarray(p, float), np.asarray(q, float)
        length = float(np.hypot(*(q - p)))
        if length == 0.0:
            return True
        return not self._marked(_Rect(p, (q - p) / length, 0.0, length, 0.0, 0.0), gap)

    def radius_spot(self, arcs: list[Arc], to_sheet, S: float, text: str) -> tuple[int, np.ndarray]:
        """Which of the arcs (a mirror pair, or one) and which point of it (on paper) take the radius
        dimension: the text runs outward along the radial line beyond the point, on either side of
        the line (ezdxf puts it above the line as read, and estimates a character as wide as high;
        LibreCAD's text is narrower and starts farther out), so the strip from 2 mm beyond the arc
        to past the text's end, one text height plus the gap each side, must be clear, and so must
        the dimension line from the centre. Tried from each arc's middle outward; if nothing is
        clear, where the strip covers the fewest marks."""
        length = 3.3 + _TXT * len(text) + 1.0
        half = _TXT + 1.0

        def strip(k, frac):
            a = arcs[k]
            c = to_sheet(a.centre)
            ang = a.start_angle + frac * a.sweep
            u = np.array([math.cos(ang), math.sin(ang)])
            mpoint = c + a.radius * S * u
            return c, mpoint, u, _Rect(mpoint, u, 2.0, length, -half, half)

        best, chosen = None, None
        for frac in (0.5, 0.4, 0.6, 0.3, 0.7, 0.2, 0.8, 0.1, 0.9):
            for k in range(len(arcs)):
                c, mpoint, u, rect = strip(k, frac)
                if self.free(rect, 0.3) and self.clear_segment(c + u * 2.2, mpoint - u * 2.5, 0.3):
                    chosen = (k, c, mpoint, u, rect)
                    break
                overlap = self.overlap(rect, 0.3)
                if best is None or overlap < best[0]:
                    best = (overlap, k, frac)
            if chosen:
                break
        if chosen is None:
            assert best is not None  # every strip was tried
            chosen = (best[1], *strip(best[1], best[2]))
        k, c, mpoint, u, rect = chosen
        self.add_rect(rect)
        self.add_segment(c, mpoint)  # the dimension line from the centre
        return k, mpoint


_G1_DEG = 0.01  # a join turning less than this is tangent


def _kinks_deg(chain: Chain) -> np.ndarray:
    """The angle (deg) between each element's end tangent and the next one's start tangent."""
    els = chain.elements
    out = []
    for a, b in zip(els[:-1], els[1:]):
        ta, tb = a.tangent(at_end=True), b.tangent()
        out.append(math.degrees(math.atan2(abs(ta[0] * tb[1] - ta[1] * tb[0]), float(ta @ tb))))
    return np.array(out)


def _table(sheet: _Sheet, space: Chain, top_left, row_h: float, root_r: float) -> None:
    """The space's elements: arc radius / centre / sweep / convex-concave, line start / length / direction."""
    travel = _travel_sign(space)
    cols = [("No.", 8.0), ("TYPE", 13.0), ("R / LENGTH", 22.0), ("X", 21.0), ("Y", 21.0),
            ("SWEEP / DIR.", 24.0), ("NOTE", 40.0)]
    x, y = float(top_left[0]), float(top_left[1])
    width = sum(w for _, w in cols)
    n = len(space.elements)
    sheet.text("TOOTH SPACE ELEMENTS  (mm, deg; origin on the gear axis, y along the space's axis)", (x, y + 2.0), _SMALL)
    sheet.text("X, Y: arc centre / line start.  SWEEP: + counter-clockwise.", (x, y - (n + 1) * row_h - 4.0), _SMALL)
    sheet.text("DIR.: the line's angle to the y axis, clockwise +.", (x, y - (n + 1) * row_h - 8.0), _SMALL)
    sheet.rect(x, y - (n + 1) * row_h, x + width, y)
    for k in range(1, n + 1):
        sheet.line((x, y - k * row_h), (x + width, y - k * row_h))
    cx = x
    for name, w in cols[:-1]:
        cx += w
        sheet.line((cx, y), (cx, y - (n + 1) * row_h))
    rows = [[c for c, _ in cols]]
    kinks = _kinks_deg(space)
    for i, e in enumerate(space.elements):
        around = kinks[max(i - 1, 0): i + 1]  # the joins before and after it
        corner = f"corner {around.max():.2f} deg" if around.size and around.max() > _G1_DEG else ""
        if isinstance(e, Arc):
            note = ""
            if np.hypot(*e.centre) < 1e-9:
                note = ", root circle" if abs(e.radius - root_r) < 1e-9 else ", gear axis"
            kind = "concave" if _concave(e, travel) else "convex"
            rows.append([str(i + 1), "ARC", "R" + _fmt(e.radius), _fmt(e.centre[0]), _fmt(e.centre[1]),
                         f"{math.degrees(e.sweep):+.4f}", kind + note + (f"; {corner}" if corner else "")])
        else:
            d = e.end - e.start
            direction = math.degrees(math.atan2(d[0], d[1]))  # from +y, clockwise positive
            direction = (direction + 90.0) % 180.0 - 90.0  # the line, not its direction of travel
            rows.append([str(i + 1), "LINE", _fmt(e.length), _fmt(e.start[0]), _fmt(e.start[1]),
                         f"{direction:+.4f}", corner or "tangent"])
    for r, row in enumerate(rows):
        cx = x
        for (name, w), cell in zip(cols, row):
            sheet.text(cell, (cx + 1.2, y - (r + 1) * row_h + 1.4), _SMALL)
            cx += w


def _note_lines(design) -> list[str]:
    prof, g = design.profile, design.gearset
    gear = g.gear
    e_mm = prof.max_error_mm
    method = prof.method.replace("_", "-")
    kinks = _kinks_deg(prof.space)
    worst = float(kinks.max()) if kinks.size else 0.0
    joins = (f"the elements join tangentially (largest kink {worst:.4f} deg)" if worst <= _G1_DEG
             else f"largest kink between elements {worst:.2f} deg")
    lines = [
        "NOTES",
        f"1. Circular spline (internal teeth): z2 = {gear.circular_spline_teeth} teeth, module m = {gear.module_mm:g} mm;",
        f"   mates a flexspline z1 = {gear.flexspline_teeth}, {gear.waves} waves.",
        f"2. Tooth space (detail A, element table): arc-line-arc flanks, {method} fit;",
        f"   {joins}.",
        f"3. PROFILE TOLERANCE of the tooth space: %%p{_fmt(e_mm)} mm (%%p{e_mm * 1e3:.1f} \u00b5m) about the drawn",
        "   profile (zone " + _fmt(2 * e_mm) + " mm): the arc-line-arc fit's largest deviation from the conjugate profile.",
        "4. All dimensions in mm; detail A's dimensions give true size.",
    ]
    from ..face.coning import modification_lines  # the face stage's choice

    for k, text in enumerate(modification_lines(design)):
        lines += _wrapped(f"{5 + k}. " + text)
    return lines


def _wrapped(text: str, width: int = 88) -> list[str]:
    """A note line broken into lines of at most ``width`` characters, the rest indented."""
    import textwrap

    return textwrap.wrap(text, width, subsequent_indent="   ")


def _notes(sheet: _Sheet, lines: list[str], at) -> None:
    x, y = at
    for k, s in enumerate(lines):
        sheet.text(s, (x, y - k * 5.0), _SMALL if k else _TXT)


def _title_block(sheet: _Sheet, design, at, date_text: str, version: str, scales: tuple[float, float]) -> None:
    """ISO 7200-like block, 180 x 48 mm: label (small) over value in each cell."""
    g = design.gearset
    x0, y0 = at
    w, h = _TITLE_W, _TITLE_H
    sheet.rect(x0, y0, x0 + w, y0 + h)
    rows = [12.0, 12.0, 12.0, 12.0]  # bottom to top
    ys = [y0]
    for r in rows:
        ys.append(ys[-1] + r)
    for y in ys[1:-1]:
        sheet.line((x0, y), (x0 + w, y))
    cells = [  # (row from bottom, x from, x to, label, value)
        (0, 0, 60, "DATE", date_text or ""),
        (0, 60, 120, "SOFTWARE", f"profilegen {version}"),
        (0, 120, 180, "SHEET", "A3  1/1"),
        (1, 0, 40, "UNITS", "mm"),
        (1, 40, 100, "SCALE", f"{_scale_label(scales[0])}  (detail A {_scale_label(scales[1])})"),
        (1, 100, 180, "PROJECTION", "first angle"),
        (2, 0, 100, "GEAR SET", g.name),
        (2, 100, 180, "SCENE", design.scene.name),
        (3, 0, 180, "TITLE", "CIRCULAR SPLINE - tooth profile"),
    ]
    verticals = set()
    for row, a, b, label, value in cells:
        if a > 0:
            verticals.add((row, a))
        ya = ys[row]
        sheet.text(label, (x0 + a + 1.5, ya + rows[row] - 3.2), 1.8)
        sheet.text(value, (x0 + a + 1.5, ya + 2.0), 5.0 if row == 3 else _TXT)
    for row, a in sorted(verticals):
        sheet.line((x0 + a, ys[row]), (x0 + a, ys[row + 1]))
    # first-angle projection symbol (ISO 128): the cone's end view on the right of its side view
    sx, sy = x0 + 155.0, ys[1] + 5.0
    small, big, length = 1.6, 3.0, 7.0
    sheet.line((sx - length, sy - small), (sx - length, sy + small))
    sheet.line((sx, sy - big), (sx, sy + big))
    sheet.line((sx - length, sy + small), (sx, sy + big))
    sheet.line((sx - length, sy - small), (sx, sy - big))
    sheet.circle((sx + 7.0, sy), big, "annotation")
    sheet.circle((sx + 7.0, sy), small, "annotation")


# ----------------------------------------------------------------------------- writing


_DIMVARS = {  # ISO-like: 3.5 mm text above the line, aligned with it; 2.5 mm arrows; 4 decimals, "." separator
    "dimtxt": _TXT, "dimasz": 2.5, "dimexe": 1.25, "dimexo": 0.625, "dimgap": 0.8, "dimdec": 4, "dimzin": 0,
    "dimdsep": ord("."), "dimtad": 1, "dimtih": 0, "dimtoh": 0, "dimcen": 0.0, "dimtofl": 1, "dimlunit": 2,
    "dimscale": 1.0, "dimlfac": 1.0,
}


def _dimstyle(doc) -> None:
    """The drawing's dimension style; the same values as the header's $DIM variables, which
    LibreCAD uses (it draws dimensions itself from their definition points, with the header's
    settings and the entity's text — which is why every dimension carries its text)."""
    doc.dimstyles.new(_DIMSTYLE, dxfattribs={**_DIMVARS, "dimtxsty": "Standard",
                                             "dimclrd": 256, "dimclre": 256, "dimclrt": 256})
    for name, value in _DIMVARS.items():
        doc.header[f"${name.upper()}"] = value


def _shifted(e: Line | Arc, t: np.ndarray) -> Line | Arc:
    if isinstance(e, Line):
        return Line(e.start + t, e.end + t)
    return Arc(e.centre + t, e.radius, e.start_angle, e.sweep)


_HALIGN = {"left": 0, "center": 1, "right": 2}


def _texts_text(texts, handles, owner: str, t: np.ndarray) -> str:
    """DXF R2010 text of single-line TEXT entities (style Standard), as ezdxf writes them: the
    insertion point, and for a centred or right-aligned text the alignment point (group 11) too."""
    out = []
    for (string, (x, y), height, halign, layer), handle in zip(texts, handles):
        string = "".join(c if ord(c) >= 32 else " " for c in string)  # a DXF value is one line (a gear set's name)
        x, y = float(x + t[0]) + 0.0, float(y + t[1]) + 0.0
        code = _HALIGN[halign]
        align = f" 72\n{code}\n" if code else ""
        out.append(f"  0\nTEXT\n  5\n{handle}\n330\n{owner}\n100\nAcDbEntity\n  8\n{layer}\n100\nAcDbText\n"
                   f" 10\n{x!r}\n 20\n{y!r}\n 30\n0.0\n 40\n{float(height)!r}\n  1\n{string}\n{align}"
                   f" 11\n{x!r}\n 21\n{y!r}\n 31\n0.0\n100\nAcDbText\n")
    return "".join(out)


def _text(sheet: _Sheet, world: list, shift: np.ndarray) -> str:
    """The sheet moved by ``shift`` (so the ring's centre is the drawing's origin) and the ring's
    outline as it is; lines, arcs and texts written as DXF text, the dimensions by ezdxf."""
    t = np.asarray(shift, float)
    ordered = [(layer, _shifted(e, t)) for layer, e in sheet.elements if layer == "construction"]
    ordered += [("CS", e) for e in world]
    ordered += [(layer, _shifted(e, t)) for layer, e in sheet.elements if layer != "construction"]
    extents = (t, t + _SHEET)
    with dxf_document([DIMENSION_LAYER], rename=None) as doc:
        msp = doc.modelspace()
        handles = [doc.entitydb.handles.next() for _ in range(len(ordered) + len(sheet.texts))]
        owner = msp.block_record_handle
        body = (cad._entities_text(ordered, handles[: len(ordered)], owner)
                + _texts_text(sheet.texts, handles[len(ordered):], owner, t))
        _dimstyle(doc)
        attribs = {"layer": DIMENSION_LAYER}

        def moved(p):
            return (float(p[0] + t[0]), float(p[1] + t[1]))

        for kind, k in sheet.dims:
            common = dict(text=k["text"], dimstyle=_DIMSTYLE, override=k["override"], dxfattribs=attribs)
            if kind == "diameter":
                dim = msp.add_diameter_dim(moved(k["center"]), radius=k["radius"], angle=k["angle"], **common)
            else:
                dim = msp.add_radius_dim(moved(k["center"]), mpoint=moved(k["mpoint"]), **common)
            dim.render()
        return dxf_text(doc, extents, entities=body)
