"""The flexspline's undeformed form as true lines and circular arcs (what CAD, EDM and a B-rep take).

Frame: the gear centre at the origin, tooth 0's axis along +y, mm; angles of
:class:`~profilegen.geometry.contour.Arc` are math angles (from +x, counter-clockwise). The tooth
frame of :mod:`profilegen.geometry.teeth` (origin on the neutral line, centre at ``(0, -r_m)``) is
moved up by ``r_m``.

One tooth (:func:`flexspline_tooth_chain`) runs counter-clockwise about the centre, as
``ToothProfile.outline`` does: from the middle of the root space on its right (x > 0, math
angle ``π/2 − π/z1``) along the root circle ``r_f = r_m + y_f`` to the right flank's root, a
radial step up to the flank's root point (the flank is truncated by the straight line
``y = y_f`` of the tooth frame, ``x²/2r`` — a few µm — outside the root circle; the tooth
defines no fillet there: ``[cup] root_fillet_radius_mm`` feeds the tooth-ring stress model
only), the right flank root → tip, the straight top land ``y = y_a``, the left flank (the
mirror image) tip → root, the step down and the root circle to the middle of the next space.

The flank's segments become elements as follows:

* DCTA (:class:`~profilegen.geometry.teeth.ArcSegment`, :class:`~profilegen.geometry.teeth.LineSegment`):
  the same arcs and line, exactly (deviation 0 up to round-off);
* involute and point-list flanks (:class:`~profilegen.geometry.teeth.InvoluteSegment`,
  :class:`~profilegen.geometry.teeth.SplineSegment`): an arc spline of G1 biarcs through points of
  the exact curve with its exact tangents (equal-tangent-length biarcs), each piece halved
  until its two-sided distance to the exact curve is ≤ ``tol_mm``.

The deviation returned is the largest distance between the elements and the exact flank,
measured both ways (points of the exact curve to the elements, exactly for lines and arcs;
points of the elements to the curve by Newton foot points), 257 points a piece.

>>> from profilegen.geometry.teeth import dcta_tooth
>>> from types import SimpleNamespace
>>> gear = SimpleNamespace(module_mm=0.5, flexspline_teeth=200, neutral_radius_mm=48.95)
>>> tooth = dcta_tooth(module_mm=0.5, teeth=200, neutral_radius_mm=48.95)
>>> chain, dev = flexspline_tooth_chain(tooth, gear)
>>> [type(e).__name__ for e in chain.elements]
['Arc', 'Line', 'Arc', 'Line', 'Arc', 'Line', 'Arc', 'Line', 'Arc', 'Line', 'Arc']
>>> dev < 1e-12, float(chain.gaps().max()) < 1e-12
(True, True)
"""

from __future__ import annotations

import logging
import math
from numbers import Real
from typing import Any

import numpy as np

from .contour import Arc, Chain, Line
from ..errors import ConvergenceError, GearSetError, ProfilegenError
from .teeth import ArcSegment, LineSegment, ToothProfile

__all__ = ["FlexsplineFormError", "flexspline_tooth_chain", "flexspline_outline", "ring_of_teeth", "flank_elements"]

log = logging.getLogger(__name__)

#: Allowed range of ``tol_mm`` (mm): below it the fit's own round-off and the piece count take over.
TOL_RANGE_MM = (1e-8, 0.1)
#: Most elements an arc-spline fit of one flank may use before it is a ConvergenceError.
MAX_PIECES = 4096
#: Points per piece at which the deviation is measured (each way).
_CHECK_POINTS = 257
#: A biarc half whose turning angle is below this (rad) is written as a line (its sagitta is
#: length × angle / 8, far below any tolerance allowed).
_LINE_ANGLE = 1e-9


class FlexsplineFormError(ProfilegenError, ValueError):
    """Bad input to the flexspline form: the message names the argument, its value, unit and range."""


# ----------------------------------------------------------------------------- inputs


def _check(tooth: Any, gear: Any, tol_mm: Any) -> tuple[int, float, float]:
    """z1, r_m and the tolerance, validated; ``gear`` may be a gear set (its ``.gear`` is read)."""
    if not isinstance(tooth, ToothProfile):
        raise TypeError(f"tooth must be a profilegen.geometry.teeth.ToothProfile, got {type(tooth).__name__}")
    gear = getattr(gear, "gear", gear)
    for name in ("flexspline_teeth", "neutral_radius_mm", "module_mm"):
        if not hasattr(gear, name):
            raise TypeError(f"gear must be a gear section (or a gear set) with {name}, got {type(gear).__name__}")
    if int(gear.flexspline_teeth) != tooth.teeth:
        raise GearSetError(f"gear.flexspline_teeth = {gear.flexspline_teeth!r} but the tooth was built for "
                           f"{tooth.teeth} teeth; build the tooth from the same gear set")
    for name, theirs in (("neutral_radius_mm", tooth.neutral_radius_mm), ("module_mm", tooth.module_mm)):
        ours = float(getattr(gear, name))
        if not math.isclose(ours, theirs, rel_tol=1e-12, abs_tol=0.0):
            raise GearSetError(f"gear.{name} = {ours!r} mm but the tooth was built with {theirs!r} mm; "
                               "build the tooth from the same gear set")
    lo, hi = TOL_RANGE_MM
    if isinstance(tol_mm, bool) or not isinstance(tol_mm, Real) or not lo <= float(tol_mm) <= hi:
        raise FlexsplineFormError(f"tol_mm must be a number in [{lo:g}, {hi:g}] mm, got {tol_mm!r}")
    return tooth.teeth, tooth.neutral_radius_mm, float(tol_mm)


# ----------------------------------------------------------------------------- biarcs


def _arc_to(p: np.ndarray, tangent: np.ndarray, q: np.ndarray) -> Line | Arc:
    """The circular arc leaving ``p`` along the unit ``tangent`` and ending at ``q`` (a line
    when it hardly turns). It turns by twice the angle between the tangent and the chord."""
    chord = q - p
    half = math.atan2(tangent[0] * chord[1] - tangent[1] * chord[0], float(tangent @ chord))
    if abs(half) < _LINE_ANGLE:
        return Line(p, q)
    radius = float(np.hypot(*chord)) / (2.0 * abs(math.sin(half)))
    normal = math.copysign(1.0, half) * np.array([-tangent[1], tangent[0]])
    centre = p + radius * normal
    return Arc(centre, radius, math.atan2(p[1] - centre[1], p[0] - centre[0]), 2.0 * half)


def _biarc(p0: np.ndarray, t0: np.ndarray, p1: np.ndarray, t1: np.ndarray) -> list[Line | Arc]:
    """The G1 biarc from (p0, t0) to (p1, t1) with equal tangent lengths α: the join is the
    midpoint of q0 = p0 + α t0 and q1 = p1 − α t1, where |q1 − q0| = 2α."""
    v = p1 - p0
    s = t0 + t1
    vs, vv = float(v @ s), float(v @ v)
    denom = 2.0 * (1.0 - float(t0 @ t1))
    if denom > 1e-12:
        alpha = (-vs + math.sqrt(vs * vs + denom * vv)) / denom
    else:  # parallel end tangents
        alpha = vv / (2.0 * vs)
    if not (alpha > 0 and math.isfinite(alpha)):
        raise ConvergenceError(f"biarc: no join between {p0.tolist()} and {p1.tolist()} mm (tangent length {alpha!r})")
    join = (p0 + alpha * t0 + p1 - alpha * t1) / 2.0
    first = _arc_to(p0, t0, join)
    second = _arc_to(join, first.tangent(at_end=True), p1)
    return [first, second]


def _foot_distance(seg: Any, a: float, b: float, points: np.ndarray, t_init: np.ndarray) -> np.ndarray:
    """Distance of ``points`` to the curve ``seg`` restricted to t in [a, b] (Newton foot points)."""
    t = np.clip(t_init, a, b)
    for _ in range(8):
        p, d1, d2 = seg.evaluate(t)
        r = p - points
        g = np.sum(r * d1, axis=1)
        h = np.sum(d1 * d1, axis=1) + np.sum(r * d2, axis=1)
        t = np.clip(t - g / np.where(h > 0.1, h, 1.0), a, b)
    p, _, _ = seg.evaluate(t)
    return np.hypot(*(p - points).T)


def _piece_deviation(seg: Any, a: float, b: float, els: list[Line | Arc], shift: np.ndarray) -> float:
    """Two-sided distance between the curve on [a, b] and the elements (tooth frame + ``shift``)."""
    t = np.linspace(a, b, _CHECK_POINTS)
    curve = seg.evaluate(t)[0] + shift
    there = float(np.max(Chain(tuple(els)).distance(curve)))
    back = 0.0
    for e in els:
        if isinstance(e, Arc):
            ang = np.linspace(e.start_angle, e.end_angle, _CHECK_POINTS)
            pts = e.centre + e.radius * np.column_stack([np.cos(ang), np.sin(ang)])
        else:
            pts = e.start + np.linspace(0.0, 1.0, _CHECK_POINTS)[:, None] * (e.end - e.start)
        # initial foot: the nearest curve sample
        k = np.argmin(np.hypot(pts[:, None, 0] - curve[None, :, 0], pts[:, None, 1] - curve[None, :, 1]), axis=1)
        back = max(back, float(np.max(_foot_distance(seg, a, b, pts - shift, t[k]))))
    return max(there, back)


def _fit_segment(seg: Any, shift: np.ndarray, tol: float) -> tuple[list[Line | Arc], float]:
    """An arc spline of ``seg`` (tooth frame, moved by ``shift``) within ``tol``, left to right."""
    todo = [(seg.t0, seg.t1)]
    out: list[Line | Arc] = []
    worst = 0.0
    while todo:
        a, b = todo.pop()
        (pa, pb), (ta, tb), _ = seg.evaluate(np.array([a, b]))
        ta, tb = ta / np.hypot(*ta), tb / np.hypot(*tb)
        els = _biarc(pa + shift, ta, pb + shift, tb)
        dev = _piece_deviation(seg, a, b, els, shift)
        if dev <= tol:
            out += els
            worst = max(worst, dev)
            continue
        if len(out) + 2 * (len(todo) + 2) > MAX_PIECES:
            raise ConvergenceError(
                f"flank arc spline: {MAX_PIECES} elements do not reach tol_mm = {tol:g} mm "
                f"(piece t in [{a:.9g}, {b:.9g}] mm still {dev:.3g} mm off)")
        mid = 0.5 * (a + b)
        todo += [(mid, b), (a, mid)]  # the left half is popped first
    return out, worst


def flank_elements(tooth: ToothProfile, *, shift_mm: float = 0.0, tol_mm: float = 1e-4
                   ) -> tuple[list[Line | Arc], float]:
    """The right flank root → tip as lines and arcs (tooth frame moved up by ``shift_mm``) and
    their largest distance to the exact flank (mm). Arc and line segments are taken as they
    are; other segments are fitted by G1 biarcs within ``tol_mm``."""
    shift = np.array([0.0, float(shift_mm)])
    out: list[Line | Arc] = []
    worst = 0.0
    els: list[Line | Arc]
    for seg in tooth.segments:
        if isinstance(seg, LineSegment):
            els = [Line(seg.start + shift, seg.end + shift)]
        elif isinstance(seg, ArcSegment):
            els = [Arc(seg.centre + shift, seg.radius, seg.start_angle, seg.sweep)]
        else:
            els, dev = _fit_segment(seg, shift, tol_mm)
            worst = max(worst, dev)
            log.debug("flank %s t in [%.6g, %.6g] mm: %d elements, deviation %.3g mm",
                      type(seg).__name__, seg.t0, seg.t1, len(els), dev)
            out += els
            continue
        worst = max(worst, _piece_deviation(seg, seg.t0, seg.t1, els, shift))
        out += els
    return out, worst


# ----------------------------------------------------------------------------- the tooth and the gear


def _halves(tooth: ToothProfile, z1: int, r_m: float, tol: float) -> tuple[Arc, list[Line | Arc], float]:
    """The right half root arc, the right side from the root circle up to the tip corner
    (radial step, flank) and the deviation."""
    flank, dev = flank_elements(tooth, shift_mm=r_m, tol_mm=tol)
    r_f = r_m + tooth.dedendum_y_mm
    root = flank[0].start
    a_root = math.atan2(root[1], root[0])  # math angle of the flank's root point
    a_mid = math.pi / 2 - math.pi / z1     # middle of the root space on the right
    if not a_root > a_mid:
        raise GearSetError(f"the flank's root point lies beyond the half pitch (angle {math.degrees(a_root):.6g} deg, "
                           f"mid-space {math.degrees(a_mid):.6g} deg); check the tooth fields")
    half_root = Arc(np.zeros(2), r_f, a_mid, a_root - a_mid)
    side: list[Line | Arc] = []
    if float(np.hypot(*root)) - r_f > 1e-12:  # the step from the root circle up to the line y = y_f
        side.append(Line(half_root.end, root))
    return half_root, side + flank, dev


def _mirror_reversed(elements: list[Line | Arc]) -> list[Line | Arc]:
    """The mirror image x → −x of elements, in reverse order and direction."""
    m = np.diag([-1.0, 1.0])
    return [e.transformed(m).reversed() for e in reversed(elements)]


def flexspline_tooth_chain(tooth: ToothProfile, gear: Any, *, tol_mm: float = 1e-4) -> tuple[Chain, float]:
    """One flexspline tooth with its root, undeformed, as lines and arcs, and its deviation (mm).

    From the middle of the root space right of the axis (x > 0, math angle π/2 − π/z1) to the
    middle of the next one (π/2 + π/z1), counter-clockwise about the gear centre (the origin), tooth axis
    along +y, mm (see the module docstring for the pieces). ``gear`` is the gear set's gear
    section (or the gear set): its ``flexspline_teeth``, ``neutral_radius_mm`` and ``module_mm``
    must be the tooth's. The float is the largest distance between the chain's flank elements
    and the tooth's exact flank (round-off for a DCTA tooth; ≤ ``tol_mm`` for fitted flanks;
    the root and top lands are exact).
    """
    z1, r_m, tol = _check(tooth, gear, tol_mm)
    half_root, side, dev = _halves(tooth, z1, r_m, tol)
    tip = side[-1].end
    right = [half_root] + side
    top = Line(tip, tip * np.array([-1.0, 1.0]))
    return Chain(tuple(right + [top] + _mirror_reversed(right))), dev


def flexspline_outline(tooth: ToothProfile, gear: Any, *, tol_mm: float = 1e-4) -> tuple[Chain, float]:
    """The closed outline of all z1 undeformed teeth (lines and arcs) and its deviation (mm).

    The chain of :func:`flexspline_tooth_chain` turned z1 times (see :func:`ring_of_teeth`);
    the deviation is the tooth chain's (the turns are rigid).
    """
    chain, dev = flexspline_tooth_chain(tooth, gear, tol_mm=tol_mm)
    return ring_of_teeth(chain, tooth.teeth), dev


def ring_of_teeth(tooth_chain: Chain, teeth: int) -> Chain:
    """The closed outline of ``teeth`` copies of a tooth chain from :func:`flexspline_tooth_chain`.

    Tooth k is the chain turned counter-clockwise by 2πk/z1 about the origin (tooth 0's axis
    along +y); the two half root arcs that meet in the middle of a space are written as one
    arc of the root circle, so the outline is, from tooth 0's right root point: [step, right
    flank, top land, left flank, step, root-space arc] × z1, closed (its last arc ends where
    the first element starts), G0 at every join up to round-off and G1 along each flank.
    """
    els = tooth_chain.elements
    first, last = els[0], els[-1]
    if not (isinstance(first, Arc) and isinstance(last, Arc) and len(els) >= 3):
        raise FlexsplineFormError("tooth_chain must start and end with half root arcs "
                                  "(a chain from flexspline_tooth_chain)")
    core = list(els[1:-1])
    pitch = 2.0 * math.pi / teeth
    a_root, a_left = first.end_angle, last.start_angle
    elements: list[Line | Arc] = []
    for k in range(teeth):
        turn = k * pitch
        c, s = math.cos(turn), math.sin(turn)
        rot = np.array([[c, -s], [s, c]])
        elements += [e.transformed(rot) for e in core] if k else core
        elements.append(Arc(first.centre, first.radius, a_left + turn, a_root + pitch - a_left))
    return Chain(tuple(elements))
