"""Contours made of true lines and circular arcs — what CAD and wire EDM take.

Points are in the plane of the drawing (mm); arc angles here are the usual math
angles, from +x counter-clockwise (as in DXF), *not* the CS frame's polar angle.
An :class:`Arc` keeps its direction of travel through a signed sweep, so a
:class:`Chain` of elements runs in one direction and its continuity can be
checked element to element. ``Arc.to_ccw()`` gives the DXF form (always
counter-clockwise from ``start_angle`` to ``end_angle``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ProfilegenError

if TYPE_CHECKING:  # pragma: no cover
    from numpy.typing import ArrayLike

__all__ = ["Line", "Arc", "Polyline", "Chain", "ContourError"]


class ContourError(ProfilegenError, ValueError):
    """A contour is not what it claims to be (gap, overlap, degenerate element)."""


def _pt(p) -> np.ndarray:
    a = np.array(p, dtype=float).reshape(2)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, slots=True, eq=False)
class Line:
    """A straight segment from ``start`` to ``end`` (mm)."""

    start: np.ndarray
    end: np.ndarray

    if TYPE_CHECKING:  # the constructor takes any (x, y) pair; __post_init__ makes it a read-only array
        def __init__(self, start: ArrayLike, end: ArrayLike) -> None: ...

    def __post_init__(self):
        object.__setattr__(self, "start", _pt(self.start))
        object.__setattr__(self, "end", _pt(self.end))

    @property
    def length(self) -> float:
        return float(np.hypot(*(self.end - self.start)))

    def tangent(self, at_end: bool = False) -> np.ndarray:
        d = self.end - self.start
        return d / np.hypot(*d)

    def sample(self, chord_tol_mm: float = 1e-4) -> np.ndarray:
        return np.vstack([self.start, self.end])

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Unsigned distance of points (n, 2) to the segment."""
        return self.nearest(points)[0]

    def nearest(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distance of points (n, 2) to the segment and the segment's nearest points (n, 2)."""
        p = np.atleast_2d(points)
        d = self.end - self.start
        s = np.clip(((p - self.start) @ d) / (d @ d), 0.0, 1.0)
        foot = self.start + s[:, None] * d
        return np.hypot(*(p - foot).T), foot

    def reversed(self) -> "Line":
        return Line(self.end, self.start)

    def transformed(self, matrix: np.ndarray, offset=(0.0, 0.0)) -> "Line":
        m, o = np.asarray(matrix, float), np.asarray(offset, float)
        return Line(m @ self.start + o, m @ self.end + o)

    @classmethod
    def trusted(cls, start: np.ndarray, end: np.ndarray) -> "Line":
        """A Line from two read-only (2,) float arrays, without the constructor's conversions (for
        the thousands of copies of an already checked element: a CS outline)."""
        line = object.__new__(cls)
        object.__setattr__(line, "start", start)
        object.__setattr__(line, "end", end)
        return line

    def to_dict(self) -> dict:
        return {"type": "line", "start_mm": self.start.tolist(), "end_mm": self.end.tolist(), "length_mm": self.length}


@dataclass(frozen=True, slots=True, eq=False)
class Arc:
    """A circular arc: centre, radius, start angle and signed sweep (rad; > 0 counter-clockwise)."""

    centre: np.ndarray
    radius: float
    start_angle: float
    sweep: float

    if TYPE_CHECKING:  # the centre may be any (x, y) pair; __post_init__ makes it a read-only array
        def __init__(self, centre: ArrayLike, radius: float, start_angle: float, sweep: float) -> None: ...

    def __post_init__(self):
        object.__setattr__(self, "centre", _pt(self.centre))
        if not (self.radius > 0 and math.isfinite(self.radius)):
            raise ContourError(f"arc radius must be > 0 mm and finite, got {self.radius!r}")
        if not (0 < abs(self.sweep) <= 2 * math.pi + 1e-12):
            raise ContourError(f"arc sweep must be in (0, 2π] rad in magnitude, got {self.sweep!r}")

    @property
    def end_angle(self) -> float:
        return self.start_angle + self.sweep

    def point_at(self, angle: float) -> np.ndarray:
        return self.centre + self.radius * np.array([math.cos(angle), math.sin(angle)])

    @property
    def start(self) -> np.ndarray:
        return self.point_at(self.start_angle)

    @property
    def end(self) -> np.ndarray:
        return self.point_at(self.end_angle)

    @property
    def length(self) -> float:
        return abs(self.sweep) * self.radius

    @property
    def curvature(self) -> float:
        """Signed curvature 1/R: > 0 when the arc turns left (counter-clockwise)."""
        return math.copysign(1.0 / self.radius, self.sweep)

    def tangent(self, at_end: bool = False) -> np.ndarray:
        a = self.end_angle if at_end else self.start_angle
        s = math.copysign(1.0, self.sweep)
        return s * np.array([-math.sin(a), math.cos(a)])

    def sample(self, chord_tol_mm: float = 1e-4) -> np.ndarray:
        step = 2.0 * math.sqrt(2.0 * chord_tol_mm / self.radius) if chord_tol_mm < self.radius else math.pi / 4
        n = max(2, int(math.ceil(abs(self.sweep) / step)) + 1)
        a = np.linspace(self.start_angle, self.end_angle, n)
        return self.centre + self.radius * np.column_stack([np.cos(a), np.sin(a)])

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Unsigned distance of points (n, 2) to the arc (its circle where the point faces the arc)."""
        return self.nearest(points)[0]

    def nearest(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distance of points (n, 2) to the arc and the arc's nearest points (n, 2): on the
        circle where the point faces the arc, else the nearer end."""
        p = np.atleast_2d(points)
        rel = p - self.centre
        ang = np.arctan2(rel[:, 1], rel[:, 0])
        # fraction of the sweep at the point's angle, unwrapped from the start
        frac = np.mod((ang - self.start_angle) * math.copysign(1.0, self.sweep), 2 * math.pi) / abs(self.sweep)
        on = frac <= 1.0
        d_circle = np.abs(np.hypot(*rel.T) - self.radius)
        d_start, d_end = np.hypot(*(p - self.start).T), np.hypot(*(p - self.end).T)
        circle_foot = self.centre + self.radius * np.column_stack([np.cos(ang), np.sin(ang)])
        end_foot = np.where((d_start <= d_end)[:, None], self.start, self.end)
        return (np.where(on, d_circle, np.minimum(d_start, d_end)),
                np.where(on[:, None], circle_foot, end_foot))

    def reversed(self) -> "Arc":
        return Arc(self.centre, self.radius, self.end_angle, -self.sweep)

    def to_ccw(self) -> tuple[np.ndarray, float, float, float]:
        """(centre, radius, start_deg, end_deg) running counter-clockwise — DXF's ARC."""
        a0, a1 = (self.start_angle, self.end_angle) if self.sweep > 0 else (self.end_angle, self.start_angle)
        return self.centre, self.radius, math.degrees(a0) % 360.0, math.degrees(a1) % 360.0

    @classmethod
    def trusted(cls, centre: np.ndarray, radius: float, start_angle: float, sweep: float) -> "Arc":
        """An Arc from a read-only (2,) float array and checked numbers, without the constructor's
        conversions and checks (for the thousands of copies of an already checked element)."""
        arc = object.__new__(cls)
        object.__setattr__(arc, "centre", centre)
        object.__setattr__(arc, "radius", radius)
        object.__setattr__(arc, "start_angle", start_angle)
        object.__setattr__(arc, "sweep", sweep)
        return arc

    def transformed(self, matrix: np.ndarray, offset=(0.0, 0.0)) -> "Arc":
        """Under a rotation (det +1) or a reflection (det −1) and a shift."""
        m, o = np.asarray(matrix, float), np.asarray(offset, float)
        det = float(m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0])  # its sign only (np.linalg.det cost half the outline's time)
        start = m @ (self.start - self.centre)
        return Arc(m @ self.centre + o, self.radius, math.atan2(start[1], start[0]), self.sweep * math.copysign(1.0, det))

    def to_dict(self) -> dict:
        return {
            "type": "arc",
            "centre_mm": self.centre.tolist(),
            "radius_mm": self.radius,
            "start_mm": self.start.tolist(),
            "end_mm": self.end.tolist(),
            "sweep_deg": math.degrees(self.sweep),
            "length_mm": self.length,
        }


@dataclass(frozen=True, slots=True, eq=False)
class Polyline:
    """Points joined by straight segments (mm) — for drawn shapes that are not made of
    arcs (the deformed flexspline, the wave generator), not for manufactured profiles."""

    points: np.ndarray

    def __post_init__(self):
        p = np.array(self.points, dtype=float)
        if p.ndim != 2 or p.shape[1] != 2 or len(p) < 2 or not np.isfinite(p).all():
            raise ContourError(f"polyline points must be finite (n ≥ 2, 2) mm, got shape {p.shape}")
        p.setflags(write=False)
        object.__setattr__(self, "points", p)

    @property
    def start(self) -> np.ndarray:
        return self.points[0]

    @property
    def end(self) -> np.ndarray:
        return self.points[-1]

    @property
    def closed(self) -> bool:
        return bool(np.all(np.abs(self.points[-1] - self.points[0]) <= 1e-12))

    @property
    def length(self) -> float:
        return float(np.sum(np.hypot(*np.diff(self.points, axis=0).T)))

    def tangent(self, at_end: bool = False) -> np.ndarray:
        d = self.points[-1] - self.points[-2] if at_end else self.points[1] - self.points[0]
        return d / np.hypot(*d)

    def sample(self, chord_tol_mm: float = 1e-4) -> np.ndarray:
        return self.points

    def reversed(self) -> "Polyline":
        return Polyline(self.points[::-1])

    def transformed(self, matrix: np.ndarray, offset=(0.0, 0.0)) -> "Polyline":
        return Polyline(self.points @ np.asarray(matrix, float).T + np.asarray(offset, float))

    def to_dict(self) -> dict:
        return {"type": "polyline", "points": int(len(self.points)), "length_mm": self.length}


Element = Line | Arc | Polyline


@dataclass(frozen=True, slots=True, eq=False)
class Chain:
    """Elements joined end to start, in order of travel."""

    elements: tuple
    _packed: dict | None = field(default=None, init=False, repr=False)  # the elements as arrays, made when first used

    def __post_init__(self):
        object.__setattr__(self, "elements", tuple(self.elements))
        if not self.elements:
            raise ContourError("a chain needs at least one element")

    @property
    def start(self) -> np.ndarray:
        return self.elements[0].start

    @property
    def end(self) -> np.ndarray:
        return self.elements[-1].end

    @property
    def length(self) -> float:
        return float(sum(e.length for e in self.elements))

    def gaps(self, closed: bool = False) -> np.ndarray:
        """Distances between each element's end and the next one's start (mm)."""
        els = self.elements + ((self.elements[0],) if closed else ())
        return np.array([np.hypot(*(a.end - b.start)) for a, b in zip(els[:-1], els[1:])])

    def kinks_deg(self, closed: bool = False) -> np.ndarray:
        """Tangent angle jumps at the joins (degrees; 0 for G1)."""
        els = self.elements + ((self.elements[0],) if closed else ())
        out = []
        for a, b in zip(els[:-1], els[1:]):
            ta, tb = a.tangent(at_end=True), b.tangent()
            # atan2 of cross and dot: acos loses half the digits near 0
            out.append(abs(math.degrees(math.atan2(ta[0] * tb[1] - ta[1] * tb[0], ta @ tb))))
        return np.array(out)

    def check(self, *, closed: bool = False, gap_tol_mm: float = 1e-9) -> None:
        """Raise ContourError naming the first join whose gap exceeds the tolerance."""
        g = self.gaps(closed)
        if g.size and g.max() > gap_tol_mm:
            k = int(np.argmax(g))
            raise ContourError(f"chain: gap of {g[k]:.3e} mm after element {k} (tolerance {gap_tol_mm:g} mm)")

    def sample(self, chord_tol_mm: float = 1e-4) -> np.ndarray:
        pts = [self.elements[0].sample(chord_tol_mm)]
        pts += [e.sample(chord_tol_mm)[1:] for e in self.elements[1:]]
        return np.vstack(pts)

    def distance(self, points: np.ndarray) -> np.ndarray:
        return self._each(points, feet=False)[0].min(axis=0)

    def nearest(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distance of points (n, 2) to the chain and its nearest points (n, 2) (exact for
        lines and arcs)."""
        dist, feet = self._each(points, feet=True)
        best = np.argmin(dist, axis=0)
        k = np.arange(dist.shape[1])
        return dist[best, k], feet[best, k]

    def _each(self, points, *, feet: bool):
        """Each element's distances (elements, n) and, with ``feet``, nearest points
        (elements, n, 2): the lines all at once and the arcs all at once (the contact search
        calls a chain hundreds of times on a few points; element by element the calls'
        overhead was most of its time), each with :meth:`Line.nearest`'s and
        :meth:`Arc.nearest`'s arithmetic, so the numbers are the same."""
        p = np.atleast_2d(points)
        pack = self._pack()
        dist = np.empty((len(self.elements), len(p)))
        foot: Any = np.empty((len(self.elements), len(p), 2)) if feet else None  # written only with feet
        if pack["lines"]:
            start, d, dd = pack["line_start"], pack["line_d"], pack["line_dd"]
            s = np.clip(np.matmul(p[None] - start, d[..., None])[..., 0] / dd, 0.0, 1.0)
            f = start + s[..., None] * d[:, None, :]
            r = p[None] - f
            dist[pack["lines"]] = np.hypot(r[..., 0], r[..., 1])
            if feet:
                foot[pack["lines"]] = f
        if pack["arcs"]:
            centre, radius, start, end = pack["centre"], pack["radius"], pack["arc_start"], pack["arc_end"]
            rel = p[None] - centre
            ang = np.arctan2(rel[..., 1], rel[..., 0])
            frac = np.mod((ang - pack["start_angle"]) * pack["sense"], 2 * math.pi) / pack["sweep"]
            on = frac <= 1.0
            d_circle = np.abs(np.hypot(rel[..., 0], rel[..., 1]) - radius)
            to_start, to_end = p[None] - start, p[None] - end
            d_start = np.hypot(to_start[..., 0], to_start[..., 1])
            d_end = np.hypot(to_end[..., 0], to_end[..., 1])
            dist[pack["arcs"]] = np.where(on, d_circle, np.minimum(d_start, d_end))
            if feet:
                circle_foot = centre + radius[..., None] * np.stack([np.cos(ang), np.sin(ang)], -1)
                end_foot = np.where((d_start <= d_end)[..., None], start, end)
                foot[pack["arcs"]] = np.where(on[..., None], circle_foot, end_foot)
        for i in pack["other"]:
            if feet:
                dist[i], foot[i] = self.elements[i].nearest(p)
            else:
                dist[i] = self.elements[i].distance(p)
        return dist, foot

    def _pack(self) -> dict:
        """The elements' parameters as arrays (kept: a chain does not change)."""
        pack = getattr(self, "_packed", None)  # None too on a chain pickled before the field existed
        if pack is not None:
            return pack
        els = self.elements
        lines = [i for i, e in enumerate(els) if isinstance(e, Line)]
        arcs = [i for i, e in enumerate(els) if isinstance(e, Arc)]
        pack = {"lines": lines, "arcs": arcs, "other": [i for i, e in enumerate(els) if not isinstance(e, (Line, Arc))]}
        if lines:
            start = np.array([els[i].start for i in lines])
            d = np.array([els[i].end - els[i].start for i in lines])
            pack.update(line_start=start[:, None, :], line_d=d, line_dd=np.array([x @ x for x in d])[:, None])
        if arcs:
            a = [els[i] for i in arcs]
            pack.update(centre=np.array([e.centre for e in a])[:, None, :], radius=np.array([e.radius for e in a])[:, None],
                        start_angle=np.array([e.start_angle for e in a])[:, None],
                        sense=np.array([math.copysign(1.0, e.sweep) for e in a])[:, None],
                        sweep=np.array([abs(e.sweep) for e in a])[:, None],
                        arc_start=np.array([e.start for e in a])[:, None, :], arc_end=np.array([e.end for e in a])[:, None, :])
        object.__setattr__(self, "_packed", pack)
        return pack

    def transformed(self, matrix, offset=(0.0, 0.0)) -> "Chain":
        return Chain(tuple(e.transformed(matrix, offset) for e in self.elements))

    def reversed(self) -> "Chain":
        return Chain(tuple(e.reversed() for e in reversed(self.elements)))

    def to_dict(self) -> dict:
        return {"elements": [e.to_dict() for e in self.elements], "length_mm": self.length}
