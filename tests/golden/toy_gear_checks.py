"""Independent geometric checks of the golden toy-gear DXF (``tests/golden/toy_gear.dxf``).

The golden file is compared with the writer's fresh output in ``tests/unit/test_cad.py``;
that comparison alone would accept any file the writer once produced. This module decides
whether a file *is* the toy gear, from the DXF entities alone (read with ezdxf, no
profilegen code) against the toy gear's analytic definition:

    z = 12 teeth, pitch 2π/z = 30°; root circle r = 8 mm, tip circle r = 10 mm. One pitch,
    counter-clockwise from 0°: root arc 0°→6°, flank line (8, 6°)→(10, 9°), tip arc 9°→12°,
    a concave scallop (centre on r = 12 mm at 15°) from (10, 12°) to (10, 18°), tip arc
    18°→21°, flank line (10, 21°)→(8, 24°), root arc 24°→30°.

Checks (lengths to ``TOL_MM``, angles to ``TOL_RAD``):

* header in mm ($INSUNITS = 4, $MEASUREMENT = 1); layer ``CS`` holds 60 ARC and 24 LINE;
* the annotation's "z = …, r …/… mm" agrees with the geometry below;
* closure: every CS endpoint meets exactly one other, and the 84 entities form one loop;
* tangent turning of the loop (arc sweeps + corner angles) is 2π: one simple closed curve;
  the joins are G1 exactly where two arcs of one circle meet (the 12 root-circle joins at
  k·30°), corners everywhere else;
* the loop's enclosed area (Green's theorem, exact for lines and arcs) equals the analytic
  area 12·[64·6° + 100·3° + 80 sin 3° + 50 sin 6° − ½ρ²(θ − sin θ)] (angles in rad; ρ, θ:
  the scallop's radius and central angle, from its chord 2·10·sin 3° and its centre);
* radial extent: min |p| over the contour = the root radius, max = the tip radius;
  every arc is centred on the origin (radius root or tip) or is a scallop of radius ρ
  centred on r = 12 mm at 15° + k·30°;
* symmetry: the entity set maps onto itself under rotation by 2π/z and under the mirror
  y → −y, and not under rotation by π/z (exactly z teeth);
* ``construction``: circles r = root and tip about the origin.

:func:`check_toy_gear_dxf` raises :class:`ToyGearCheckError` (an ``AssertionError``)
naming the first check that fails.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import ezdxf
import numpy as np

TOL_MM = 1e-9
TOL_RAD = 1e-9

TEETH = 12
ROOT_MM, TIP_MM, SCALLOP_CENTRE_MM = 8.0, 10.0, 12.0


class ToyGearCheckError(AssertionError):
    """A golden toy-gear DXF that is not the analytic toy gear."""


def _require(ok: bool, what: str) -> None:
    if not ok:
        raise ToyGearCheckError(what)


def scallop_radius_mm() -> float:
    """Centre (12 mm, 15°) to (10 mm, 12°): law of cosines."""
    return math.sqrt(SCALLOP_CENTRE_MM**2 + TIP_MM**2 - 2 * SCALLOP_CENTRE_MM * TIP_MM * math.cos(math.radians(3.0)))


def analytic_area_mm2() -> float:
    """Area inside the toy gear, one pitch at a time, triangles and sectors from the origin."""
    rad = math.radians
    rho = scallop_radius_mm()
    theta = 2.0 * math.asin(TIP_MM * math.sin(rad(3.0)) / rho)  # the scallop's central angle (chord 2·10·sin 3°)
    pitch = (ROOT_MM**2 * rad(6.0) + TIP_MM**2 * rad(3.0)  # two root arcs of 6°, two tip arcs of 3°
             + ROOT_MM * TIP_MM * math.sin(rad(3.0))  # two flank triangles ½·8·10·sin 3°
             + 0.5 * TIP_MM**2 * math.sin(rad(6.0))  # the triangle under the scallop's chord ...
             - 0.5 * rho**2 * (theta - math.sin(theta)))  # ... less the segment the scallop cuts away
    return TEETH * pitch


# ----------------------------------------------------------------------------- entities


class _Seg:
    """A LINE or ARC of the DXF as endpoints and tangents (DXF arcs run counter-clockwise)."""

    def __init__(self, entity):
        self.kind = entity.dxftype()
        if self.kind == "LINE":
            self.p0 = np.array(tuple(entity.dxf.start)[:2], float)
            self.p1 = np.array(tuple(entity.dxf.end)[:2], float)
            d = self.p1 - self.p0
            _require(np.hypot(*d) > TOL_MM, f"LINE of zero length at {self.p0.tolist()}")
            self.t0 = self.t1 = d / np.hypot(*d)
            self.sweep = 0.0
        elif self.kind == "ARC":
            self.centre = np.array(tuple(entity.dxf.center)[:2], float)
            self.radius = float(entity.dxf.radius)
            _require(tuple(entity.dxf.extrusion) == (0.0, 0.0, 1.0), "ARC with a tilted or mirrored extrusion")
            a0, a1 = math.radians(entity.dxf.start_angle), math.radians(entity.dxf.end_angle)
            self.sweep = (a1 - a0) % (2 * math.pi)
            self.a0, self.a1 = a0, a0 + self.sweep
            self.p0 = self.centre + self.radius * np.array([math.cos(a0), math.sin(a0)])
            self.p1 = self.centre + self.radius * np.array([math.cos(self.a1), math.sin(self.a1)])
            self.t0 = np.array([-math.sin(a0), math.cos(a0)])
            self.t1 = np.array([-math.sin(self.a1), math.cos(self.a1)])
        else:
            raise ToyGearCheckError(f"layer CS holds a {self.kind}; only LINE and ARC are allowed")

    def radial_extent(self) -> tuple[float, float]:
        """Min and max distance of the entity's points from the origin."""
        if self.kind == "LINE":
            d = self.p1 - self.p0
            s = float(np.clip(-(self.p0 @ d) / (d @ d), 0.0, 1.0))
            return float(np.hypot(*(self.p0 + s * d))), float(max(np.hypot(*self.p0), np.hypot(*self.p1)))
        c = float(np.hypot(*self.centre))
        cand = [float(np.hypot(*self.p0)), float(np.hypot(*self.p1))]
        if c > TOL_MM:
            toward = math.atan2(self.centre[1], self.centre[0])
            for ang, dist in ((toward, c + self.radius), (toward + math.pi, abs(c - self.radius))):
                if (ang - self.a0) % (2 * math.pi) <= self.sweep:
                    cand.append(dist)
        return min(cand), max(cand)

    def key(self):
        """The point set, orientation-free: sorted endpoints, plus centre and radius for arcs."""
        ends = sorted([tuple(self.p0), tuple(self.p1)])
        if self.kind == "LINE":
            return np.array([*ends[0], *ends[1]])
        return np.array([*ends[0], *ends[1], *self.centre, self.radius, self.sweep])


def _transformed_keys(segs, matrix):
    out = []
    for s in segs:
        p0, p1 = matrix @ s.p0, matrix @ s.p1
        ends = sorted([tuple(p0), tuple(p1)])
        if s.kind == "LINE":
            out.append(np.array([*ends[0], *ends[1]]))
        else:
            out.append(np.array([*ends[0], *ends[1], *(matrix @ s.centre), s.radius, s.sweep]))
    return out


def _same_set(segs, matrix) -> bool:
    """Every transformed entity coincides with an entity of the same type (one-to-one)."""
    keys = {"LINE": [], "ARC": []}
    for s in segs:
        keys[s.kind].append(s.key())
    moved = {"LINE": [], "ARC": []}
    for s, k in zip(segs, _transformed_keys(segs, matrix)):
        moved[s.kind].append(k)
    for kind in keys:
        if not keys[kind]:
            continue
        a, b = np.array(keys[kind]), np.array(moved[kind])
        dist = np.max(np.abs(a[:, None, :] - b[None, :, :]), axis=2)
        if np.max(np.min(dist, axis=1)) > TOL_MM or np.max(np.min(dist, axis=0)) > TOL_MM:
            return False
        if len(set(np.argmin(dist, axis=1).tolist())) != len(a):
            return False
    return True


def _rotation(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def _loop(segs):
    """Order the entities into one closed loop; returns [(seg, forward)] or raises."""
    ends = np.array([[*s.p0, *s.p1] for s in segs])
    points = np.concatenate([ends[:, :2], ends[:, 2:]])  # endpoint j of entity i at i + j·n
    n = len(segs)
    dist = np.hypot(points[:, None, 0] - points[None, :, 0], points[:, None, 1] - points[None, :, 1])
    np.fill_diagonal(dist, np.inf)
    for i in range(n):  # an entity's two ends must not be its own partners
        dist[i, i + n] = dist[i + n, i] = np.inf
    partners = [np.flatnonzero(row <= TOL_MM) for row in dist]
    for k, p in enumerate(partners):
        _require(len(p) == 1, f"closure: the end {points[k].tolist()} of CS entity {k % n} meets {len(p)} other ends, "
                              "not exactly one")
    order, seg, forward = [], 0, True
    for _ in range(n):
        order.append((segs[seg], forward))
        exit_end = seg + n if forward else seg  # the end we leave by
        nxt = int(partners[exit_end][0])
        seg, forward = nxt % n, nxt < n  # enter by its start → run it forward
        if seg == 0:
            break
    _require(len(order) == n and seg == 0 and forward, f"closure: the CS entities form more than one loop "
                                                       f"({len(order)} of {n} in the first)")
    return order


def _turning_and_area(order):
    total, area, g1 = 0.0, 0.0, []
    for k, (s, fwd) in enumerate(order):
        p0, p1 = (s.p0, s.p1) if fwd else (s.p1, s.p0)
        if s.kind == "LINE":
            area += 0.5 * (p0[0] * p1[1] - p1[0] * p0[1])
        else:
            sweep = s.sweep if fwd else -s.sweep
            (cx, cy), r = s.centre, s.radius
            a0, a1 = (s.a0, s.a1) if fwd else (s.a1, s.a0)
            area += 0.5 * (r * r * sweep + r * (cx * (math.sin(a1) - math.sin(a0)) - cy * (math.cos(a1) - math.cos(a0))))
            total += sweep
        t_out = s.t1 if fwd else -s.t0
        nxt, nfwd = order[(k + 1) % len(order)]
        t_in = nxt.t0 if nfwd else -nxt.t1
        corner = math.atan2(t_out[0] * t_in[1] - t_out[1] * t_in[0], t_out @ t_in)
        total += corner
        g1.append((abs(corner) <= TOL_RAD, s, nxt))
    return total, area, g1


# ----------------------------------------------------------------------------- the check


def check_toy_gear_dxf(path: str | Path) -> dict:
    """Raise :class:`ToyGearCheckError` unless the DXF at ``path`` is the analytic toy gear;
    return the measured quantities (area, radii, turning) for a report."""
    doc = ezdxf.readfile(str(path))
    _require(doc.header.get("$INSUNITS") == 4, f"header: $INSUNITS = {doc.header.get('$INSUNITS')!r}, expected 4 (mm)")
    _require(doc.header.get("$MEASUREMENT") == 1, "header: $MEASUREMENT must be 1 (metric)")
    msp = doc.modelspace()
    cs = [e for e in msp if e.dxf.layer == "CS"]
    kinds = {k: sum(e.dxftype() == k for e in cs) for k in ("ARC", "LINE")}
    _require(len(cs) == 7 * TEETH and kinds == {"ARC": 5 * TEETH, "LINE": 2 * TEETH},
             f"layer CS: {len(cs)} entities {kinds}, expected {5 * TEETH} ARC + {2 * TEETH} LINE")
    segs = [_Seg(e) for e in cs]

    # the annotation states z and the radii; they must be the geometry's
    texts = [e.dxf.text for e in msp.query("TEXT")]
    found = [re.search(r"z\s*=\s*(\d+),\s*r\s*([\d.]+)\s*/\s*([\d.]+)\s*mm", t) for t in texts]
    found = [m for m in found if m]
    _require(len(found) == 1, f"annotation: expected one 'z = …, r …/… mm' text, got {len(found)}")
    z, r_root, r_tip = int(found[0][1]), float(found[0][2]), float(found[0][3])
    _require((z, r_root, r_tip) == (TEETH, ROOT_MM, TIP_MM),
             f"annotation: z = {z}, r {r_root}/{r_tip} mm; the toy gear is z = {TEETH}, r {ROOT_MM}/{TIP_MM} mm")

    # closure, turning, G1 joins, area
    order = _loop(segs)
    turning, area, joins = _turning_and_area(order)
    _require(abs(abs(turning) - 2 * math.pi) <= 1e-8, f"turning: the tangent turns {turning:.12g} rad, not ±2π")
    _require(area * turning > 0, "orientation: the signed area and the turning disagree")
    expected_area = analytic_area_mm2()
    _require(abs(abs(area) - expected_area) <= 1e-8, f"area: {abs(area):.12f} mm², analytic {expected_area:.12f} mm²")
    smooth = [(a, b) for ok, a, b in joins if ok]
    _require(len(smooth) == TEETH, f"G1: {len(smooth)} smooth joins, expected {TEETH} (root arc to root arc)")
    for a, b in smooth:
        _require(a.kind == b.kind == "ARC" and np.hypot(*a.centre) <= TOL_MM and np.hypot(*b.centre) <= TOL_MM
                 and abs(a.radius - ROOT_MM) <= TOL_MM and abs(b.radius - ROOT_MM) <= TOL_MM,
                 "G1: a smooth join that is not two root-circle arcs meeting")

    # radii: the contour spans exactly root … tip; arcs on the origin or scallops
    lo = min(s.radial_extent()[0] for s in segs)
    hi = max(s.radial_extent()[1] for s in segs)
    _require(abs(lo - r_root) <= TOL_MM and abs(hi - r_tip) <= TOL_MM,
             f"radii: the contour spans {lo:.12g} … {hi:.12g} mm, expected root {r_root} … tip {r_tip} mm")
    rho = scallop_radius_mm()
    counts = {"root": 0, "tip": 0, "scallop": 0}
    for s in segs:
        if s.kind != "ARC":
            continue
        if np.hypot(*s.centre) <= TOL_MM:
            name = "root" if abs(s.radius - r_root) <= TOL_MM else "tip" if abs(s.radius - r_tip) <= TOL_MM else None
            _require(name is not None, f"ARC about the origin with radius {s.radius!r} mm (neither root nor tip)")
        else:
            ang = math.degrees(math.atan2(s.centre[1], s.centre[0])) % 30.0
            _require(abs(np.hypot(*s.centre) - SCALLOP_CENTRE_MM) <= TOL_MM and abs(ang - 15.0) <= 1e-9
                     and abs(s.radius - rho) <= TOL_MM,
                     f"ARC centred at {s.centre.tolist()} r = {s.radius!r}: not a scallop (centre 12 mm at 15° + k·30°, "
                     f"r = {rho:.12g})")
            name = "scallop"
        counts[name] += 1
    _require(counts == {"root": 2 * TEETH, "tip": 2 * TEETH, "scallop": TEETH}, f"arcs: {counts}")

    # symmetry: z-fold rotation and the mirror, but not a 2z-fold rotation
    _require(_same_set(segs, _rotation(2 * math.pi / z)), f"symmetry: the contour is not invariant under 2π/{z}")
    _require(_same_set(segs, np.diag([1.0, -1.0])), "symmetry: the contour is not symmetric about the x axis")
    _require(not _same_set(segs, _rotation(math.pi / z)), f"symmetry: the contour repeats every π/{z}: more than {z} teeth")

    circles = sorted(float(e.dxf.radius) for e in msp.query("CIRCLE") if e.dxf.layer == "construction"
                     and np.hypot(*tuple(e.dxf.center)[:2]) <= TOL_MM)
    _require(np.allclose(circles, [r_root, r_tip], atol=TOL_MM, rtol=0) if len(circles) == 2 else False,
             f"construction: circles about the origin of radii {circles}, expected [{r_root}, {r_tip}]")
    return {"area_mm2": abs(area), "analytic_area_mm2": expected_area, "turning_rad": turning,
            "root_mm": lo, "tip_mm": hi, "teeth": z, "entities": len(segs)}
