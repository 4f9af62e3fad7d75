"""Rounded corners of the CS tooth space, so that wire EDM can cut what the drawing says.

The sharp CS chain (:func:`profilegen.profile.gearform.cs_chain`) has two kinds of corner:

* **root corners**, where the transition line (or the flank's last arc) meets the root
  circle. The chain runs clockwise about the CS centre with the ring material on its left
  and the space (where the wire runs) on its right; there it turns right, so the corner is
  concave for the material: the wire, a disc of radius ``wire_radius_mm`` eroding a further
  ``spark_gap_mm`` around it, cannot reach into it and leaves a round of radius
  r_w + s_g. These **inside** corners get a tangent (G1) arc of exactly that radius. Its
  material is added to the CS, into the space, toward the FS tooth's tip path: the arc is
  checked against the FS tooth family's swept region and must stay outside it.
* **tip corners**, where the flank leaves the tip circle (and any kink between fitted
  branches that turns left). The chain turns left there: an **outside** corner, convex for
  the material, which the wire can cut sharp. They are rounded only so that the whole
  closed chain is G1; the round removes CS material (it can only add backlash) and takes
  the same radius, or the largest that fits between its neighbours (a warning).

``corners = "sharp"`` (in ``[circular_spline]``) keeps today's chain exactly.

:func:`max_kink_deg` measures the largest tangent jump along a (closed) chain.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..geometry.contour import Arc, Chain, Line
from ..errors import FilletError
from ..stagecache import checkpoint
from ..gearset.sections import CORNER_STYLES as CORNERS

__all__ = ["Fillet", "RoundedSpace", "CSChain", "max_kink_deg", "round_space", "filleted_cs_chain", "CORNERS"]

log = logging.getLogger(__name__)

INSIDE, OUTSIDE = "inside", "outside"

#: joins whose tangents differ by less than this are G1 already (the fit's joins are ~1e-13°)
_G1_DEG = 1e-7
#: points sampled on each inside fillet for the swept-region check
_CHECK_POINTS = 65


class _NoRoom(Exception):
    """A fillet's tangent points fall outside its neighbouring elements."""


def max_kink_deg(chain: Chain, *, closed: bool = True) -> float:
    """The largest tangent-angle jump (degrees) at the joins of ``chain`` — the last element
    to the first as well when ``closed``. 0 for a chain that is G1 everywhere."""
    k = chain.kinks_deg(closed=closed)
    return float(k.max()) if k.size else 0.0


@dataclass(frozen=True, slots=True, eq=False)
class Fillet:
    """One rounded corner: ``where`` (``"root left"``, ``"tip right"``, ...); ``kind`` inside
    (concave for the ring material: the wire's limit) or outside; the ``arc`` (its centre
    and radius, mm); ``asked_mm`` the radius asked for (r_w + s_g); ``corner_mm`` the sharp
    corner it replaces and ``kink_deg`` that corner's angle; ``clearance_mm`` the arc's
    smallest distance from the FS tooth family's swept region (first order; None when not
    checked: outside corners remove material)."""

    where: str
    kind: str
    arc: Arc
    asked_mm: float
    corner_mm: np.ndarray
    kink_deg: float
    clearance_mm: float | None = None

    @property
    def radius_mm(self) -> float:
        return self.arc.radius

    @property
    def centre_mm(self) -> np.ndarray:
        return self.arc.centre

    def to_dict(self) -> dict:
        return {"where": self.where, "kind": self.kind, "radius_mm": self.radius_mm, "asked_mm": self.asked_mm,
                "centre_mm": self.centre_mm.tolist(), "start_mm": self.arc.start.tolist(),
                "end_mm": self.arc.end.tolist(), "sweep_deg": math.degrees(self.arc.sweep),
                "corner_mm": np.asarray(self.corner_mm).tolist(), "corner_kink_deg": self.kink_deg,
                "clearance_to_swept_region_mm": self.clearance_mm}


@dataclass(frozen=True, slots=True, eq=False)
class RoundedSpace:
    """One CS tooth space with its corners rounded (``space``: tip circle → tip circle, as
    the sharp one), the ``fillets`` made and the ``warnings`` (radii smaller than asked)."""

    space: Chain
    fillets: tuple
    warnings: tuple = field(default_factory=tuple)


@dataclass(frozen=True, slots=True, eq=False)
class CSChain:
    """The CS as true arcs and lines: one ``space``, the closed ``outline`` of all z2 spaces,
    the ``fillets`` of one space (empty for sharp corners), ``corners`` (``fillet`` or
    ``sharp``) and ``warnings``."""

    space: Chain
    outline: Chain
    fillets: tuple
    corners: str
    warnings: tuple = field(default_factory=tuple)

    @property
    def max_kink_deg(self) -> float:
        """The largest tangent jump along the closed outline (degrees)."""
        return max_kink_deg(self.outline, closed=True)

    def to_dict(self) -> dict:
        return {"corners": self.corners, "fillets": [f.to_dict() for f in self.fillets],
                "outline_max_kink_deg": self.max_kink_deg}


# ----------------------------------------------------------------------------- one corner


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _offset(el, side: float, radius: float):
    """The element's offset curve toward ``side`` (+1 left of travel, −1 right) by ``radius``:
    ("line", point, direction) or ("circle", centre, radius)."""
    if isinstance(el, Line):
        t = el.tangent()
        n = np.array([-t[1], t[0]])
        return ("line", el.start + side * radius * n, t)
    toward_centre = side * math.copysign(1.0, el.sweep) > 0  # the left normal of a ccw arc points in
    r = el.radius - radius if toward_centre else el.radius + radius
    if r <= 0.0:
        raise _NoRoom
    return ("circle", el.centre, r)


def _intersections(c1, c2) -> list[np.ndarray]:
    if c1[0] == "circle" and c2[0] == "line":
        c1, c2 = c2, c1
    if c1[0] == "line" and c2[0] == "line":
        p, d, q, e = c1[1], c1[2], c2[1], c2[2]
        den = _cross(d, e)
        if abs(den) < 1e-15:
            return []
        s = _cross(q - p, e) / den
        return [p + s * d]
    if c1[0] == "line":
        p, d, c, r = c1[1], c1[2], c2[1], c2[2]
        w = p - c
        b = w @ d
        disc = b * b - (w @ w - r * r)
        if disc < 0.0:
            return []
        h = math.sqrt(disc)
        return [p + (-b - h) * d, p + (-b + h) * d]
    (c, r), (k, q) = (c1[1], c1[2]), (c2[1], c2[2])
    dv = k - c
    dist = float(np.hypot(*dv))
    if dist < 1e-15 or dist > r + q or dist < abs(r - q):
        return []
    a = (r * r - q * q + dist * dist) / (2 * dist)
    h = math.sqrt(max(r * r - a * a, 0.0))
    u = dv / dist
    n = np.array([-u[1], u[0]])
    return [c + a * u + h * n, c + a * u - h * n]


def _foot(el, x: np.ndarray) -> tuple[np.ndarray, float]:
    """The foot of the normal from x on the element's line/circle, and its fraction along the
    element (0 at its start, 1 at its end; outside [0, 1] off the element)."""
    if isinstance(el, Line):
        d = el.end - el.start
        s = float((x - el.start) @ d / (d @ d))
        return el.start + s * d, s
    rel = x - el.centre
    ang = math.atan2(rel[1], rel[0])
    foot = el.centre + el.radius * rel / np.hypot(*rel)
    off = (ang - el.start_angle) * math.copysign(1.0, el.sweep)
    off = (off + math.pi) % (2 * math.pi) - math.pi  # nearest to the start, either way
    return foot, off / abs(el.sweep)


def _trim(el, frac0: float, frac1: float, p0: np.ndarray | None = None, p1: np.ndarray | None = None):
    """The part of ``el`` between fractions frac0 and frac1 (ends given exactly by p0/p1), or
    None when nothing is left."""
    if frac1 - frac0 <= 1e-12:
        return None
    if isinstance(el, Line):
        a = el.start + frac0 * (el.end - el.start) if p0 is None else p0
        b = el.start + frac1 * (el.end - el.start) if p1 is None else p1
        return Line(a, b) if np.hypot(*(b - a)) > 1e-12 else None
    a0 = el.start_angle + frac0 * el.sweep if p0 is None else math.atan2(*(p0 - el.centre)[::-1])
    a1 = el.start_angle + frac1 * el.sweep if p1 is None else math.atan2(*(p1 - el.centre)[::-1])
    sweep = a1 - a0
    s = math.copysign(1.0, el.sweep)
    sweep = s * ((s * sweep) % (2 * math.pi))  # the element's own direction
    if abs(sweep) * el.radius <= 1e-12 or abs(sweep) > 2 * math.pi - 1e-9:
        return None
    return Arc(el.centre, el.radius, a0, sweep)


def _corner_fillet(a, b, radius: float):
    """A tangent arc of ``radius`` joining element ``a`` (ending at the corner) to ``b``
    (starting there), on the side the chain turns to. Returns (a trimmed or None, arc,
    b trimmed or None); _NoRoom if a tangent point falls off either element."""
    ta, tb = a.tangent(at_end=True), b.tangent()
    side = math.copysign(1.0, _cross(ta, tb))
    corner = a.end
    best = None
    for x in _intersections(_offset(a, side, radius), _offset(b, side, radius)):
        fa, sa = _foot(a, x)
        fb, sb = _foot(b, x)
        if not (-1e-12 <= sa <= 1.0 + 1e-12 and -1e-12 <= sb <= 1.0 + 1e-12):
            continue
        d = float(np.hypot(*(x - corner)))
        if best is None or d < best[0]:
            best = (d, x, fa, sa, fb, sb)
    if best is None:
        raise _NoRoom
    _, x, fa, sa, fb, sb = best
    a0 = math.atan2(*(fa - x)[::-1])
    a1 = math.atan2(*(fb - x)[::-1])
    sweep = side * ((side * (a1 - a0)) % (2 * math.pi))
    if not 0.0 < abs(sweep) < math.pi:
        raise _NoRoom
    arc = Arc(x, radius, a0, sweep)
    return _trim(a, 0.0, sa, p1=arc.start), arc, _trim(b, sb, 1.0, p0=arc.end)


# ----------------------------------------------------------------------------- one space


def _kink_deg(a, b) -> float:
    ta, tb = a.tangent(at_end=True), b.tangent()
    return math.degrees(math.atan2(_cross(ta, tb), ta @ tb))


def _round(space: Chain, radius: float, *, tip_radius_mm: float, cs_teeth: int, inside_only: bool = False,
           outside_radius: float | None = None):
    """Round every corner of ``space`` — its non-G1 joins and the two corners where it leaves
    the tip circle — inside corners with ``radius``, outside ones with ``outside_radius``
    (default ``radius``). Returns (elements, [(where, kind, arc, corner, kink_deg)]). Raises
    _NoRoom when a fillet does not fit; the caller decides what that means."""
    pitch = 2 * math.pi / cs_teeth
    a_start = math.atan2(space.start[1], space.start[0])
    a_end = math.atan2(space.end[1], space.end[0])
    land = pitch - ((a_start - a_end) % (2 * math.pi))  # the tip land between two spaces (rad)
    if land <= 0.0:
        raise _NoRoom("tip", OUTSIDE)
    # half a land before and after the space, clockwise like the chain; they share the land
    before = Arc(np.zeros(2), tip_radius_mm, a_start + 0.5 * land, -0.5 * land)
    after = Arc(np.zeros(2), tip_radius_mm, a_end, -0.5 * land)
    els = [(before, "land")] + [(e, "element") for e in space.elements] + [(after, "land")]
    done = []
    j = 0
    while j < len(els) - 1:
        (a, tag_a), (b, tag_b) = els[j], els[j + 1]
        kink = _kink_deg(a, b)
        if "fillet" in (tag_a, tag_b) or abs(kink) <= _G1_DEG:  # a fillet's joins are G1 by construction
            j += 1
            continue
        kind = INSIDE if kink < 0 else OUTSIDE  # a clockwise chain turning right: concave for the material
        if kind == OUTSIDE and inside_only:
            j += 1
            continue
        r = radius if kind == INSIDE or outside_radius is None else outside_radius
        corner = a.end
        if tag_a == "land" or tag_b == "land":
            where = "tip left" if tag_a == "land" else "tip right"
        else:
            side = "left" if corner[0] < 0 else "right"
            on_root = any(isinstance(e, Arc) and not np.any(e.centre) for e in (a, b))
            where = f"{'root' if on_root else 'flank'} {side}"
        try:
            a_t, arc, b_t = _corner_fillet(a, b, r)
        except _NoRoom:
            if where.startswith("flank"):  # a kink of the fitted flank itself (a ridge: branch fits meet,
                done.append((where, kind, None, corner, abs(kink)))  # a short line between): kept
                j += 1
                continue
            raise _NoRoom(where, kind) from None
        new = ([(a_t, tag_a)] if a_t is not None else []) + [(arc, "fillet")] + ([(b_t, tag_b)] if b_t is not None else [])
        els[j:j + 2] = new
        done.append((where, kind, arc, corner, abs(kink)))
        j += len(new) - 1
    # what is left of the lands belongs to the outline, not to the space
    return [e for e, tag in els if tag != "land"], done


def _fits(space, radius, *, tip_radius_mm, cs_teeth, swept, swept_tol_mm) -> bool:
    """Whether the inside corners take fillets of ``radius`` (room and the swept region)."""
    checkpoint()  # an engine's design stops here when superseded (a bisection step: a swept-depth call)
    try:
        els, done = _round(space, radius, tip_radius_mm=tip_radius_mm, cs_teeth=cs_teeth, inside_only=True)
    except _NoRoom:
        return False
    if any(isinstance(e, Arc) and e.sweep < 0 and e.radius < radius * (1 - 1e-9) for e in els):
        return False
    inside = [arc for _, kind, arc, _, _ in done if kind == INSIDE and arc is not None]
    if swept is not None and inside:  # one call for every fillet: the swept depth is the costly part
        return float(np.max(swept(np.vstack([_arc_points(arc) for arc in inside])))) <= swept_tol_mm
    return True


def _arc_points(arc: Arc) -> np.ndarray:
    a = arc.start_angle + np.linspace(0.0, 1.0, _CHECK_POINTS) * arc.sweep
    return arc.centre + arc.radius * np.column_stack([np.cos(a), np.sin(a)])


def _largest(ok, hi: float) -> float:
    """The largest r in [0, hi] with ok(r), by bisection to 1e-6·hi (ok monotone: true below,
    false above)."""
    lo = 0.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if ok(mid):
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-6 * hi:  # a micrometre in a metre: far below what a shop holds
            break
    return lo


def _largest_clear(space, radius, *, tip_radius_mm, cs_teeth, swept, swept_tol_mm) -> float:
    """The largest inside-fillet radius ≤ ``radius`` that stays out of the swept region (room
    for ``radius`` known): the root of (deepest fillet point − tolerance) by Brent's method —
    smooth in the radius, so ~8 swept-depth calls instead of bisection's 20."""
    from scipy.optimize import brentq

    def excess(r):
        checkpoint()
        _, done = _round(space, r, tip_radius_mm=tip_radius_mm, cs_teeth=cs_teeth, inside_only=True)
        pts = [_arc_points(arc) for _, kind, arc, _, _ in done if kind == INSIDE and arc is not None]
        return float(np.max(swept(np.vstack(pts)))) - swept_tol_mm if pts else -1.0

    lo = 1e-6 * radius
    if excess(lo) > 0.0:
        return 0.0  # the sharp corner itself is in the swept region
    return brentq(excess, lo, radius, xtol=1e-6 * radius)


def round_space(space: Chain, *, radius_mm: float, tip_radius_mm: float, cs_teeth: int, swept=None,
                swept_tol_mm: float = 1e-5, field: str = "circular_spline.wire_radius_mm") -> RoundedSpace:
    """Round every corner of one sharp CS tooth space (see the module docstring).

    ``radius_mm``: r_w + s_g. ``swept``: the FS tooth family's swept-region depth (mm, > 0
    inside; :func:`profilegen.profile.arcfit.swept_depth_function`), against which each inside fillet
    is checked (None: not checked). ``field``: the gear-set field the errors name.

    Raises :class:`~profilegen.errors.FilletError` when an inside corner cannot take the
    radius: the space is too narrow for the wire (the two root fillets would overlap, or a
    concave arc of the chain is tighter than the wire), or the fillet would enter the swept
    region (it would cut into the mesh) — naming the field, the radius asked and the largest
    that fits.
    """
    if not (isinstance(radius_mm, (int, float)) and math.isfinite(radius_mm) and radius_mm > 0.0):
        raise FilletError(f"{field}: the corner radius (wire radius + spark gap) must be finite and > 0 mm, "
                          f"got {radius_mm!r}")
    kw: dict[str, Any] = dict(tip_radius_mm=tip_radius_mm, cs_teeth=cs_teeth)
    # the wire's own limit first: room for the inside fillets
    try:
        _round(space, radius_mm, inside_only=True, **kw)
    except _NoRoom as exc:
        where = exc.args[0] if exc.args else "root"
        best = _largest(lambda r: _fits(space, r, swept=None, swept_tol_mm=swept_tol_mm, **kw), radius_mm)
        raise FilletError(
            f"{field}: the wire is too thick for the CS tooth space — a fillet of {radius_mm:.4g} mm (wire radius + "
            f"spark gap) does not fit in its {where} corner (it runs past the elements beside it"
            f"{'; the two root fillets would overlap' if where.startswith('root') else ''}); the largest that fits "
            f"is {_below(best, radius_mm)} mm (wire radius + spark gap): {_what_fits(best, where)}") from None
    try:
        els, done = _round(space, radius_mm, **kw)
    except _NoRoom:  # the tip corners: the largest round that fits
        els, done = _round_shrunk(space, radius_mm, **kw)
    warnings = []
    fillets = []
    for where, kind, arc, corner, kink in done:
        if arc is None:  # a kink of the fitted flank with no room beside it for the round: kept
            shortest = min(e.length for e in space.elements
                           if min(np.hypot(*(e.start - corner)), np.hypot(*(e.end - corner))) < 1e-9)
            msg = (f"the CS {where} corner at ({corner[0]:.4f}, {corner[1]:.4f}) mm, a {kink:.3g}° kink of the fitted "
                   f"flank (where the fits of two envelope branches meet), is kept sharp: an element beside it is "
                   f"{shortest * 1e3:.3g} µm long, too short for a {radius_mm:.4g} mm round; the wire "
                   + ("rounds it itself" if kind == INSIDE else "cuts it sharp (convex)"))
            log.warning(msg)
            warnings.append(msg)
    done = [d for d in done if d[2] is not None]
    inside = [arc for _, kind, arc, _, _ in done if kind == INSIDE]
    depths = iter(np.max(swept(np.vstack([_arc_points(arc) for arc in inside])).reshape(len(inside), -1), axis=1)
                  if swept is not None and inside else [])
    for where, kind, arc, corner, kink in done:
        clearance = None
        if kind == INSIDE:
            if swept is not None:
                depth = float(next(depths))
                if depth > swept_tol_mm:
                    best = _largest_clear(space, radius_mm, swept=swept, swept_tol_mm=swept_tol_mm, **kw)
                    raise FilletError(
                        f"{field}: a {where} fillet of {radius_mm:.4g} mm (wire radius + spark gap) would cut into "
                        f"the mesh — it enters the FS tooth's swept region by {depth * 1e3:.3g} µm; the largest "
                        f"root fillet that stays clear is {_below(best, radius_mm)} mm: {_what_fits(best, 'root')}")
                clearance = -depth
        elif arc.radius < radius_mm * (1 - 1e-12):
            msg = (f"the CS {where} corner (outside, convex for the ring material) is rounded with {arc.radius:.4g} mm, "
                   f"the largest that fits, not the {radius_mm:.4g} mm of the root fillets (the wire cuts it sharp "
                   "anyway; the round only makes the outline G1)")
            log.warning(msg)
            warnings.append(msg)
        fillets.append(Fillet(where, kind, arc, radius_mm, np.asarray(corner, float), kink, clearance))
    # every concave arc must be cuttable too (a narrow space closed by one arc on the axis, a
    # tight concave arc of the fitted flank)
    for el in els:
        if isinstance(el, Arc) and el.sweep < 0 and el.radius < radius_mm * (1 - 1e-9):
            raise FilletError(
                f"{field}: the wire is too thick for the CS tooth space — it has a concave arc of {el.radius:.4g} mm "
                f"about ({el.centre[0]:.4f}, {el.centre[1]:.4f}) mm, tighter than the {radius_mm:.4g} mm the wire "
                f"(radius + spark gap) can cut; the largest that fits is {el.radius:.4g} mm: "
                f"{_what_fits(el.radius, 'arc')}")
    return RoundedSpace(Chain(tuple(els)), tuple(fillets), tuple(warnings))


def _below(best: float, radius: float) -> str:
    """``best`` with 4 significant digits, or as many more (up to 8) as show it below ``radius``:
    near the limit the largest fillet that fits read "0.145 mm" beside the 0.145 mm asked."""
    for digits in range(4, 9):
        if f"{best:.{digits}g}" != f"{radius:.{digits}g}":
            break
    return f"{best:.{digits}g}"


def _what_fits(best: float, where: str = "") -> str:
    """What the user can change when a wire of corner radius (wire radius + spark gap) ``best`` mm fits:
    sharp corners always do; else a wire and spark gap (the default gap is 0.02 mm) summing to ``best``."""
    text = 'circular_spline.corners = "sharp" (the wire cuts the corners as it can)'
    if best > 0.0:
        digits = 10 ** (math.floor(math.log10(best)) - 2)
        gap = math.floor(min(0.02, best / 2) / digits) * digits  # rounded down: the pair surely fits
        wire = math.floor((best - gap) / digits) * digits
        if wire > 0:
            text += (f", or circular_spline.wire_radius_mm = {wire:.3g} with spark_gap_mm = {gap:.3g} "
                     f"(their sum at most {best:.4g} mm)")
    if where.startswith("root"):
        text += ", or a larger circular_spline.root_clearance_mm"
    elif where.startswith("tip"):
        text += ", or a larger circular_spline.tip_clearance_mm"
    return text


def _round_shrunk(space, radius, *, tip_radius_mm, cs_teeth):
    """Round with ``radius`` inside, and outside with the largest common radius that fits."""
    def ok(r):
        try:
            _round(space, radius, tip_radius_mm=tip_radius_mm, cs_teeth=cs_teeth, outside_radius=r)
        except _NoRoom:
            return False
        return True

    r_out = _largest(ok, radius)
    if r_out <= 0.0:
        raise FilletError("circular_spline.corners: the CS tip corners cannot be rounded at all (no room on the "
                          "tip land): corners = \"sharp\" keeps them sharp, or a larger circular_spline.tip_clearance_mm")
    return _round(space, radius, tip_radius_mm=tip_radius_mm, cs_teeth=cs_teeth, outside_radius=r_out)


def filleted_cs_chain(flank, *, tip_radius_mm: float, root_radius_mm: float, cs_teeth: int, corners: str = "fillet",
                      radius_mm: float | None = None, swept=None, swept_tol_mm: float = 1e-5) -> CSChain:
    """The closed CS outline as true arcs and lines (:func:`profilegen.profile.gearform.cs_chain`)
    with its corners rounded for wire EDM (``corners = "fillet"``, ``radius_mm`` = wire
    radius + spark gap; see :func:`round_space`) or kept sharp (``"sharp"``: the chain
    :func:`~profilegen.profile.gearform.cs_chain` makes, unchanged)."""
    from .gearform import cs_outline, cs_space

    if corners not in CORNERS:
        raise FilletError(f"circular_spline.corners = {corners!r}: must be one of {', '.join(CORNERS)}")
    space = cs_space(flank, tip_radius_mm=tip_radius_mm, root_radius_mm=root_radius_mm, swept=swept,
                     swept_tol_mm=swept_tol_mm)
    if corners == "sharp":
        return CSChain(space, cs_outline(space, tip_radius_mm=tip_radius_mm, cs_teeth=cs_teeth), (), corners)
    if radius_mm is None:
        raise FilletError("circular_spline.wire_radius_mm: corners = \"fillet\" needs the corner radius (wire radius "
                          "+ spark gap), got None")
    rounded = round_space(space, radius_mm=radius_mm, tip_radius_mm=tip_radius_mm, cs_teeth=cs_teeth, swept=swept,
                          swept_tol_mm=swept_tol_mm)
    outline = cs_outline(rounded.space, tip_radius_mm=tip_radius_mm, cs_teeth=cs_teeth)
    return CSChain(rounded.space, outline, rounded.fillets, corners, rounded.warnings)
