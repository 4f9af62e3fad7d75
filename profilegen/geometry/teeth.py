"""Flexspline tooth profiles p(t), p'(t), p''(t) in one arc-length parameter.

The tooth frame
---------------
Origin on the flexspline rim's *neutral line* at the tooth axis; ``y`` along
the tooth axis (outward), ``x`` tangential. The flexspline centre is at
``(0, -r_m)`` (``r_m`` = neutral radius). The pitch line is ``y_p = r1 - r_m``
with ``r1 = m z1 / 2`` the pitch radius.

Every tooth kind is truncated *rack-like* by the straight (Cartesian) lines
``y = y_a`` (tip, ``y_a = y_p + addendum``) and ``y = y_f`` (root,
``y_f = y_p - dedendum``) of this frame, and the DCTA flank is defined on the
straight pitch line ``y = y_p`` rather than on the pitch circle. This is a
definition choice: at the tooth's half width (x ~ 0.4 mm, r ~ 50 mm) a line
and a circle through the same point on the axis differ by x²/2r ~ 1-4 µm.

The profile described is the RIGHT flank (x > 0); the parameter ``t`` is the
arc length in mm from the root end (dedendum) to the tip end (addendum),
``t in [0, L]``. The left flank is the mirror ``x -> -x`` (``side=-1``).

Derivatives are taken with respect to ``t``: ``dp`` is the unit tangent and
``ddp = kappa * n`` with ``n`` the left normal (``n = rot90(dp)``, pointing
into the tooth for the right flank) and ``kappa = dp x ddp`` the signed
curvature, positive where the flank is convex (turns toward the tooth
interior), negative where it is concave (root fillet). Mirroring flips the
sign of ``kappa`` as computed by ``dp x ddp``.

Kinds
-----
``dcta``      line - arc (double-circular-arc common-tangent) tooth:
              concave root arc, straight common tangent through the pitch
              point, convex tip arc; G1 at both joins.
``involute``  involute of the flexspline pitch circle (base radius
              ``r1 cos alpha``) about the flexspline centre, arc-length
              parametrised in closed form (``s = r_b theta^2 / 2``).
``points``    a smoothing spline through measured / imported points,
              reparametrised by arc length (quintic in ``s``).
"""

from __future__ import annotations

import json
import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from numbers import Integral, Real
from typing import Any

import numpy as np

from profilegen.errors import GearSetError, ToothError

__all__ = [
    "LineSegment",
    "ArcSegment",
    "InvoluteSegment",
    "SplineSegment",
    "ToothProfile",
    "dcta_tooth",
    "involute_tooth",
    "points_tooth",
    "tooth_from_gearset",
]

log = logging.getLogger(__name__)

#: Relative tolerance on the parameter range accepted by ``evaluate``.
_T_TOL = 1e-9


# --------------------------------------------------------------------------- helpers


def _ro(a: Any, shape: tuple[int, ...] | None = None) -> np.ndarray:
    """A read-only float copy of ``a``."""
    arr = np.array(a, dtype=float, copy=True)
    if shape is not None and arr.shape != shape:
        raise ValueError(f"expected shape {shape}, got {arr.shape}")
    arr.flags.writeable = False
    return arr


def _e(theta: np.ndarray) -> np.ndarray:
    """Unit vectors (cos theta, sin theta), shape theta.shape + (2,)."""
    return np.stack([np.cos(theta), np.sin(theta)], axis=-1)


def _e_perp(theta: np.ndarray) -> np.ndarray:
    """d/dtheta of _e: (-sin theta, cos theta)."""
    return np.stack([-np.sin(theta), np.cos(theta)], axis=-1)


def _as_t(t: Any) -> np.ndarray:
    """``t`` as an array, keeping complex dtype (complex-step tests)."""
    arr = np.asarray(t)
    if not np.iscomplexobj(arr):
        arr = arr.astype(float, copy=False)
    return arr


def _num(value: Any, name: str, *, lo: float | None = None, hi: float | None = None,
         lo_open: bool = True, hi_open: bool = False, unit: str = "mm",
         error: type[GearSetError] = ToothError) -> float:
    """Validate a real scalar and return it as float; the message names ``name``."""
    rng = (("(" if lo_open else "[") + ("-inf" if lo is None else f"{lo:g}") + ", "
           + ("inf" if hi is None else f"{hi:g}") + (")" if hi_open or hi is None else "]"))
    if isinstance(value, bool) or not isinstance(value, Real):
        raise error(f"{name} must be a real number in {rng} {unit}, got {value!r}")
    v = float(value)
    bad = not math.isfinite(v)
    if lo is not None:
        bad |= v <= lo if lo_open else v < lo
    if hi is not None:
        bad |= v >= hi if hi_open else v > hi
    if bad:
        raise error(f"{name} must be in {rng} {unit}, got {value!r}")
    return v


def _gear_args(module_mm: Any, teeth: Any, neutral_radius_mm: Any) -> tuple[float, int, float]:
    m = _num(module_mm, "gear.module_mm", lo=0.0, hi=10.0, error=GearSetError)
    if isinstance(teeth, bool) or not isinstance(teeth, Integral) or not 3 <= int(teeth) <= 100000:
        raise GearSetError(f"gear.flexspline_teeth must be an integer in [3, 100000], got {teeth!r}")
    z1 = int(teeth)
    r1 = m * z1 / 2.0
    r_m = _num(neutral_radius_mm, "gear.neutral_radius_mm", lo=0.0, hi=r1, hi_open=True,
               error=GearSetError)
    return m, z1, r_m


def _tooth_levels(m: float, z1: int, r_m: float, ha: float, hf: float, half_thickness_mm: Any) -> tuple[float, float, float, float]:
    """Half thickness h and the pitch, addendum and dedendum lines y_p, y_a, y_f of the
    tooth frame; the dedendum line must lie above the neutral line."""
    h = math.pi * m / 4.0 if half_thickness_mm is None else _num(
        half_thickness_mm, "tooth.half_thickness_mm", lo=0.0)
    y_p = m * z1 / 2.0 - r_m
    y_a, y_f = y_p + ha, y_p - hf
    if y_f <= 0.0:
        raise ToothError(
            f"tooth.dedendum_mm = {hf:g} mm puts the dedendum line y_f = y_p - dedendum = "
            f"{y_f:.6g} mm at or below the neutral line (y_p = r1 - r_m = {y_p:.6g} mm); "
            f"must be < {y_p:.6g} mm")
    return h, y_p, y_a, y_f


# --------------------------------------------------------------------------- segments


@dataclass(frozen=True, slots=True, eq=False)
class LineSegment:
    """Straight segment ``p = start + (t - t0) * direction`` (``direction`` unit)."""

    t0: float
    t1: float
    start: np.ndarray
    direction: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", _ro(self.start, (2,)))
        d = np.asarray(self.direction, dtype=float)
        object.__setattr__(self, "direction", _ro(d / np.hypot(d[0], d[1]), (2,)))

    @property
    def length_mm(self) -> float:
        return self.t1 - self.t0

    @property
    def end(self) -> np.ndarray:
        return self.start + self.length_mm * self.direction

    def evaluate(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = _as_t(t)
        u = (t - self.t0)[..., None]
        p = self.start + u * self.direction
        dp = np.broadcast_to(self.direction, p.shape).astype(p.dtype)
        return p, dp, np.zeros_like(p)

    def to_dict(self) -> dict[str, Any]:
        return {"type": "line", "t0": self.t0, "t1": self.t1,
                "start": self.start.tolist(), "end": self.end.tolist(),
                "direction": self.direction.tolist()}


@dataclass(frozen=True, slots=True, eq=False)
class ArcSegment:
    """Circular arc about ``centre``: angle ``start_angle + sign(sweep) (t - t0)/radius``.

    ``sweep`` > 0 runs counter-clockwise (convex for the right flank, curvature
    +1/radius), ``sweep`` < 0 clockwise (concave, curvature -1/radius).
    """

    t0: float
    t1: float
    centre: np.ndarray
    radius: float
    start_angle: float
    sweep: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "centre", _ro(self.centre, (2,)))
        if not self.radius > 0:
            raise ValueError(f"ArcSegment radius must be > 0, got {self.radius}")

    @property
    def length_mm(self) -> float:
        return self.t1 - self.t0

    @property
    def curvature(self) -> float:
        return math.copysign(1.0, self.sweep) / self.radius

    @property
    def end_angle(self) -> float:
        return self.start_angle + self.sweep

    def evaluate(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = _as_t(t)
        sgn = math.copysign(1.0, self.sweep)
        theta = self.start_angle + sgn * (t - self.t0) / self.radius
        er = _e(theta)
        p = self.centre + self.radius * er
        dp = sgn * _e_perp(theta)
        ddp = -er / self.radius
        return p, dp, ddp

    def to_dict(self) -> dict[str, Any]:
        return {"type": "arc", "t0": self.t0, "t1": self.t1,
                "centre": self.centre.tolist(), "radius": self.radius,
                "start_angle_deg": math.degrees(self.start_angle),
                "sweep_deg": math.degrees(self.sweep), "curvature": self.curvature}


@dataclass(frozen=True, slots=True, eq=False)
class InvoluteSegment:
    """Involute of the circle (``centre``, ``base_radius``), exact arc-length form.

    With ``tau = base_angle + theta`` the point of tangency angle and ``theta``
    the unrolled angle, ``p = c + r_b (e(tau) - theta e'(tau))``. The arc length
    from the base circle is ``s = r_b theta^2 / 2``; at global ``t`` it is
    ``s = s0 + (t - t0)``, hence ``theta = sqrt(2 s / r_b)``, ``dp = e(tau)``,
    ``ddp = e'(tau) / (r_b theta)`` (curvature radius ``r_b theta``). The
    unrolling runs counter-clockwise (right flank of an external tooth).
    """

    t0: float
    t1: float
    centre: np.ndarray
    base_radius: float
    base_angle: float
    s0: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "centre", _ro(self.centre, (2,)))
        if not (self.base_radius > 0 and self.s0 > 0):
            raise ValueError("InvoluteSegment needs base_radius > 0 and s0 > 0 (off the base circle)")

    @property
    def length_mm(self) -> float:
        return self.t1 - self.t0

    def roll_angle(self, t: Any) -> np.ndarray:
        """Unrolled angle theta (= tan of the local pressure angle) at ``t``."""
        return np.sqrt(2.0 * (self.s0 + (_as_t(t) - self.t0)) / self.base_radius)

    def evaluate(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        theta = self.roll_angle(t)
        tau = self.base_angle + theta
        et, ep = _e(tau), _e_perp(tau)
        p = self.centre + self.base_radius * (et - theta[..., None] * ep)
        ddp = ep / (self.base_radius * theta)[..., None]
        return p, et, ddp

    def to_dict(self) -> dict[str, Any]:
        return {"type": "involute", "t0": self.t0, "t1": self.t1,
                "centre": self.centre.tolist(), "base_radius": self.base_radius,
                "base_angle_deg": math.degrees(self.base_angle),
                "s0": self.s0}


@dataclass(frozen=True, slots=True, eq=False)
class SplineSegment:
    """Parametric B-spline ``p(s)``, ``s = t - t0``, fitted to be (nearly) arc-length.

    ``knots`` (n + k + 1,), ``coefficients`` (n, 2), ``degree`` k (5: quintic).
    ``unit_speed_error`` is max | |p'| - 1 | measured on a dense grid.
    """

    t0: float
    t1: float
    knots: np.ndarray
    coefficients: np.ndarray
    degree: int
    unit_speed_error: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "knots", _ro(self.knots))
        object.__setattr__(self, "coefficients", _ro(self.coefficients))
        if self.coefficients.ndim != 2 or self.coefficients.shape[1] != 2:
            raise ValueError("SplineSegment coefficients must have shape (n, 2)")

    @property
    def length_mm(self) -> float:
        return self.t1 - self.t0

    def evaluate(self, t: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        from scipy.interpolate import BSpline

        s = np.asarray(t, dtype=float) - self.t0
        spl = BSpline.construct_fast(self.knots, self.coefficients, self.degree)
        return spl(s), spl(s, 1), spl(s, 2)

    def to_dict(self) -> dict[str, Any]:
        p, _, _ = self.evaluate(np.array([self.t0, self.t1]))
        return {"type": "spline", "t0": self.t0, "t1": self.t1, "degree": self.degree,
                "n_knots": int(self.knots.size), "start": p[0].tolist(), "end": p[1].tolist(),
                "unit_speed_error": self.unit_speed_error}


Segment = LineSegment | ArcSegment | InvoluteSegment | SplineSegment


# --------------------------------------------------------------------------- profile


@dataclass(frozen=True, slots=True, eq=False)
class ToothProfile:
    """Right flank of a flexspline tooth, root -> tip, in one arc-length parameter.

    See the module docstring for the frame and sign conventions.
    ``fit_error_mm`` / ``fit_rms_mm``: max / RMS distance of the input points
    to the curve (kind ``points``; 0.0 otherwise). ``unit_speed_error``: max
    | |dp| - 1 | on a dense grid (round-off for the analytic kinds, the
    arc-length reparametrisation error for ``points``).
    """

    kind: str
    segments: tuple[Segment, ...]
    module_mm: float
    teeth: int
    neutral_radius_mm: float
    pitch_y_mm: float
    addendum_y_mm: float
    dedendum_y_mm: float
    fit_error_mm: float = 0.0
    fit_rms_mm: float = 0.0
    unit_speed_error: float = 0.0
    _breaks: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        segs = tuple(self.segments)
        if not segs:
            raise ValueError("ToothProfile needs at least one segment")
        if segs[0].t0 != 0.0:
            raise ValueError(f"first segment must start at t = 0, got {segs[0].t0}")
        for a, b in zip(segs[:-1], segs[1:]):
            if a.t1 != b.t0 or not b.t1 > b.t0:
                raise ValueError("segments must be contiguous in t with positive length")
        object.__setattr__(self, "segments", segs)
        object.__setattr__(self, "_breaks", _ro([s.t0 for s in segs] + [segs[-1].t1]))

    # --- geometry --------------------------------------------------------------
    @property
    def length_mm(self) -> float:
        """Arc length L of the flank (mm)."""
        return float(self._breaks[-1])

    @property
    def breakpoints(self) -> np.ndarray:
        """t of the segment joins, including 0 and L (read-only)."""
        return self._breaks

    @property
    def pitch_radius_mm(self) -> float:
        return self.module_mm * self.teeth / 2.0

    @property
    def centre(self) -> np.ndarray:
        """Flexspline centre (0, -r_m) in the tooth frame."""
        return np.array([0.0, -self.neutral_radius_mm])

    def evaluate(self, t: Any, side: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(p, dp, ddp)`` at ``t`` (mm of arc length from the root), each ``t.shape + (2,)``.

        ``side=-1`` gives the left flank (x -> -x), still parametrised root -> tip.
        """
        if side not in (1, -1):
            raise ValueError(f"side must be +1 (right flank) or -1 (left flank), got {side!r}")
        t = np.asarray(t, dtype=float)
        shape = t.shape
        tf = t.ravel()
        L = self.length_mm
        tol = _T_TOL * max(L, 1.0)
        bad = ~((tf >= -tol) & (tf <= L + tol))
        if bad.any():
            raise ValueError(f"t must be in [0, {L:.9g}] mm (arc length root -> tip), "
                             f"got {tf[bad][0]!r}")
        tf = np.clip(tf, 0.0, L)
        idx = np.searchsorted(self._breaks[1:-1], tf, side="right")
        p = np.empty((tf.size, 2))
        dp = np.empty((tf.size, 2))
        ddp = np.empty((tf.size, 2))
        for k, seg in enumerate(self.segments):
            sel = np.flatnonzero(idx == k)
            if sel.size:
                p[sel], dp[sel], ddp[sel] = seg.evaluate(tf[sel])
        if side == -1:
            for a in (p, dp, ddp):
                a[:, 0] *= -1.0
        return p.reshape(shape + (2,)), dp.reshape(shape + (2,)), ddp.reshape(shape + (2,))

    def point(self, t: Any, side: int = 1) -> np.ndarray:
        return self.evaluate(t, side)[0]

    def curvature(self, t: Any, side: int = 1) -> np.ndarray:
        """Signed curvature (1/mm) ``dp x ddp / |dp|^3``; > 0 convex on the right flank."""
        _, dp, ddp = self.evaluate(t, side)
        cross = dp[..., 0] * ddp[..., 1] - dp[..., 1] * ddp[..., 0]
        return cross / np.hypot(dp[..., 0], dp[..., 1]) ** 3

    @property
    def tip_point(self) -> np.ndarray:
        """Right tip corner p(L)."""
        return self.point(self.length_mm)

    @property
    def root_point(self) -> np.ndarray:
        """Right root end p(0)."""
        return self.point(0.0)

    @property
    def tip_land_width_mm(self) -> float:
        """Chord width of the top land, 2 x_tip."""
        return 2.0 * float(self.tip_point[0])

    @property
    def root_space_width_mm(self) -> float:
        """Arc width, on the root circle, of the space between this tooth and its neighbour."""
        x, y = self.root_point
        r_f = self.neutral_radius_mm + self.dedendum_y_mm
        return 2.0 * r_f * (math.pi / self.teeth - math.atan2(x, y + self.neutral_radius_mm))

    # --- outline --------------------------------------------------------------
    def sample(self, n_per_mm: float = 2000.0) -> np.ndarray:
        """t values, about ``n_per_mm`` per mm, including every breakpoint."""
        n = max(2, int(math.ceil(self.length_mm * n_per_mm)) + 1)
        return np.unique(np.concatenate([np.linspace(0.0, self.length_mm, n), self._breaks]))

    def outline(self, n_per_mm: float = 2000.0) -> np.ndarray:
        """Closed counter-clockwise polygon (m, 2) of the tooth and its rim sector.

        Right flank root -> tip, top land (straight chord y = y_a) to the left
        tip corner, left flank tip -> root, then the root circle (radius
        r_m + y_f about (0, -r_m)) out to the mid-space line at polar angle
        -pi/z1, radially down to the neutral circle (radius r_m), along it to
        +pi/z1, up to the root circle and along it back to the right root
        point. The root point lies on y = y_f, i.e. x²/2r (a few µm) outside
        the root circle: it is joined to the root circle by a short radial
        step. The first point is not repeated.
        """
        if not (isinstance(n_per_mm, Real) and n_per_mm > 0):
            raise ValueError(f"n_per_mm must be > 0, got {n_per_mm!r}")
        r_m = self.neutral_radius_mm
        r_f = r_m + self.dedendum_y_mm
        c = np.array([0.0, -r_m])
        half = math.pi / self.teeth
        right = self.point(self.sample(n_per_mm))
        left = right[::-1] * np.array([-1.0, 1.0])
        x0, y0 = right[0]
        psi_root = math.atan2(x0, y0 + r_m)  # polar angle from +y, clockwise positive

        def ring(radius: float, psi_a: float, psi_b: float, endpoints: bool) -> np.ndarray:
            n = max(2, int(math.ceil(abs(psi_b - psi_a) * radius * n_per_mm)) + 1)
            psi = np.linspace(psi_a, psi_b, n)
            if not endpoints:
                psi = psi[1:-1]
            return c + radius * np.stack([np.sin(psi), np.cos(psi)], axis=-1)

        def radial(psi: float, ra: float, rb: float) -> np.ndarray:
            n = max(2, int(math.ceil(abs(rb - ra) * n_per_mm)) + 1)
            r = np.linspace(ra, rb, n)[1:-1]
            return c + r[:, None] * np.array([math.sin(psi), math.cos(psi)])

        parts = [
            right,
            left,
            ring(r_f, -psi_root, -half, endpoints=True),
            radial(-half, r_f, r_m),
            ring(r_m, -half, half, endpoints=True),
            radial(half, r_m, r_f),
            ring(r_f, half, psi_root, endpoints=True),
        ]
        poly = np.concatenate(parts)
        # drop consecutive duplicates (e.g. a zero radial step on the axis)
        keep = np.ones(len(poly), dtype=bool)
        keep[1:] = np.any(np.abs(np.diff(poly, axis=0)) > 1e-13, axis=1)
        poly = poly[keep]
        if np.all(np.abs(poly[-1] - poly[0]) <= 1e-13):
            poly = poly[:-1]
        return poly

    # --- reporting ------------------------------------------------------------
    def surface(self, n_per_mm: float = 400.0) -> np.ndarray:
        """The tooth's real surface as an open polyline (m, 2): root land, flanks, top land,
        from the right mid-space line to the left one — ``outline()`` without the radial
        cuts and the neutral-line arc that only close it as a region."""
        outline = self.outline(n_per_mm=n_per_mm)
        r = np.hypot(outline[:, 0], outline[:, 1] + self.neutral_radius_mm)
        keep = r >= self.neutral_radius_mm + self.dedendum_y_mm - 1e-9 * max(abs(self.dedendum_y_mm), 1.0)
        first_cut = int(np.argmin(keep))  # the kept points run from after the cut round to before it
        last_cut = len(keep) - 1 - int(np.argmin(keep[::-1]))
        return np.vstack([outline[last_cut + 1 :], outline[:first_cut]])

    def to_dict(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "length_mm": self.length_mm,
            "module_mm": self.module_mm,
            "teeth": self.teeth,
            "neutral_radius_mm": self.neutral_radius_mm,
            "pitch_y_mm": self.pitch_y_mm,
            "addendum_y_mm": self.addendum_y_mm,
            "dedendum_y_mm": self.dedendum_y_mm,
            "tip_point": self.tip_point.tolist(),
            "root_point": self.root_point.tolist(),
            "tip_land_width_mm": self.tip_land_width_mm,
            "root_space_width_mm": self.root_space_width_mm,
            "breakpoints": self._breaks.tolist(),
            "segments": [s.to_dict() for s in self.segments],
            "fit_error_mm": self.fit_error_mm,
            "fit_rms_mm": self.fit_rms_mm,
            "unit_speed_error": self.unit_speed_error,
        }


def _chain(specs: list[tuple[type, dict[str, Any], float]]) -> tuple[Segment, ...]:
    """Lay segments end to end in t, dropping zero-length ones."""
    segs: list[Segment] = []
    t = 0.0
    for cls, kw, length in specs:
        if length <= 0.0:
            continue
        t1 = t + length
        segs.append(cls(t0=t, t1=t1, **kw))
        t = t1
    return tuple(segs)


def _speed_error(segments: tuple[Segment, ...], per_segment: int = 2001) -> float:
    err = 0.0
    for s in segments:
        _, dp, _ = s.evaluate(np.linspace(s.t0, s.t1, per_segment))
        err = max(err, float(np.max(np.abs(np.hypot(dp[:, 0], dp[:, 1]) - 1.0))))
    return err


def _check_placement(tooth: ToothProfile, *, cross_fields: str, overlap_fields: str) -> None:
    """Flanks must not cross (x > 0 everywhere) nor leave the tooth's pitch sector."""
    t = tooth.sample(200.0)
    p = tooth.point(t)
    r_m = tooth.neutral_radius_mm
    if np.min(p[:, 0]) <= 0.0:
        k = int(np.argmin(p[:, 0]))
        raise ToothError(
            f"{cross_fields}: the right flank reaches x = {p[k, 0]:.6g} mm <= 0 at "
            f"y = {p[k, 1]:.6g} mm (tip corner x = {p[-1, 0]:.6g} mm): the two flanks cross, "
            "the tooth self-intersects below the addendum")
    psi = np.arctan2(p[:, 0], p[:, 1] + r_m)
    half = math.pi / tooth.teeth
    if np.max(psi) >= half:
        k = int(np.argmax(psi))
        r_f = r_m + tooth.dedendum_y_mm
        raise ToothError(
            f"{overlap_fields}: the flank point ({p[k, 0]:.6g}, {p[k, 1]:.6g}) mm lies beyond the "
            f"half pitch (polar angle {math.degrees(psi[k]):.6g} deg >= pi/z1 = "
            f"{math.degrees(half):.6g} deg; x_root must be < (r_m + y_f) sin(pi/z1) = "
            f"{r_f * math.sin(half):.6g} mm): the tooth overlaps its neighbour")


# --------------------------------------------------------------------------- DCTA


def dcta_tooth(*, module_mm: float, teeth: int, neutral_radius_mm: float,
               pressure_angle_deg: float = 10.0, line_above_pitch_mm: float = 0.05,
               line_below_pitch_mm: float = 0.20, tip_arc_radius_mm: float = 0.65,
               root_arc_radius_mm: float = 0.70, addendum_mm: float = 0.40,
               dedendum_mm: float = 0.60, half_thickness_mm: float | None = None) -> ToothProfile:
    """Double-circular-arc common-tangent (DCTA) flexspline tooth.

    Right flank, root -> tip: a concave root arc (radius ``root_arc_radius_mm``)
    from ``y_f = y_p - dedendum`` up to B, the straight common tangent B -> A
    through the pitch point ``P = (half_thickness, y_p)`` inclined
    ``pressure_angle_deg`` to the tooth axis (direction ``d = (-sin a, cos a)``,
    ``A = P + line_above d``, ``B = P - line_below d``), and a convex tip arc
    (radius ``tip_arc_radius_mm``, centre ``A - R (cos a, sin a)``) up to
    ``y_a = y_p + addendum``. G1 at A and B. ``half_thickness_mm`` defaults to
    pi m / 4 (half of half the pitch, on the straight pitch line).
    """
    m, z1, r_m = _gear_args(module_mm, teeth, neutral_radius_mm)
    alpha_deg = _num(pressure_angle_deg, "tooth.pressure_angle_deg", lo=0.0, hi=60.0,
                     lo_open=False, hi_open=True, unit="deg")
    la = _num(line_above_pitch_mm, "tooth.line_above_pitch_mm", lo=0.0, lo_open=False)
    lb = _num(line_below_pitch_mm, "tooth.line_below_pitch_mm", lo=0.0, lo_open=False)
    ra = _num(tip_arc_radius_mm, "tooth.tip_arc_radius_mm", lo=0.0)
    rf = _num(root_arc_radius_mm, "tooth.root_arc_radius_mm", lo=0.0)
    ha = _num(addendum_mm, "tooth.addendum_mm", lo=0.0)
    hf = _num(dedendum_mm, "tooth.dedendum_mm", lo=0.0)
    h, y_p, y_a, y_f = _tooth_levels(m, z1, r_m, ha, hf, half_thickness_mm)
    a = math.radians(alpha_deg)
    sa, ca = math.sin(a), math.cos(a)
    d = np.array([-sa, ca])
    n_out = np.array([ca, sa])  # outward normal of the line (away from the tooth)
    P = np.array([h, y_p])
    A = P + la * d
    B = P - lb * d
    if A[1] > y_a:
        raise ToothError(
            f"tooth.line_above_pitch_mm = {la:g} mm: the line end A is at y = {A[1]:.6g} mm, "
            f"above the addendum y_a = {y_a:.6g} mm (tooth.addendum_mm = {ha:g} mm); "
            f"must be <= {ha / ca:.6g} mm")
    if B[1] < y_f:
        raise ToothError(
            f"tooth.line_below_pitch_mm = {lb:g} mm: the line end B is at y = {B[1]:.6g} mm, "
            f"below the dedendum y_f = {y_f:.6g} mm (tooth.dedendum_mm = {hf:g} mm); "
            f"must be <= {hf / ca:.6g} mm")

    # tip arc: centre inside the tooth, angle alpha at A, counter-clockwise up to y_a;
    # its tangent turns horizontal at angle pi/2 (height C_a.y + R).
    c_a = A - ra * n_out
    need = (y_a - A[1]) / (1.0 - sa)
    if not c_a[1] + ra > y_a:
        raise ToothError(
            f"tooth.tip_arc_radius_mm = {ra:g} mm: the tip arc turns horizontal at "
            f"y = {c_a[1] + ra:.6g} mm before reaching the addendum y_a = {y_a:.6g} mm; "
            f"tip_arc_radius_mm must be > {need:.6g} mm (or lower tooth.addendum_mm = {ha:g} mm)")
    th_tip = math.asin((y_a - c_a[1]) / ra)
    tip_sweep = th_tip - a

    # root arc: centre outside the tooth, angle pi + alpha at B; clockwise from the root
    # end theta_f (down at 3pi/2 the tangent is horizontal: height C_f.y - R).
    c_f = B + rf * n_out
    need = (B[1] - y_f) / (1.0 - sa)
    if not c_f[1] - rf < y_f:
        raise ToothError(
            f"tooth.root_arc_radius_mm = {rf:g} mm: the root arc turns horizontal at "
            f"y = {c_f[1] - rf:.6g} mm before reaching the dedendum y_f = {y_f:.6g} mm; "
            f"root_arc_radius_mm must be > {need:.6g} mm (or lower tooth.dedendum_mm = {hf:g} mm)")
    th_root = math.pi - math.asin((y_f - c_f[1]) / rf)
    root_sweep = (math.pi + a) - th_root  # <= 0: clockwise, concave

    x_tip = c_a[0] + ra * math.cos(th_tip)
    if x_tip <= 0.0:
        raise ToothError(
            f"tooth.half_thickness_mm = {h:g} mm / tooth.pressure_angle_deg = {alpha_deg:g} deg: "
            f"the tip corner is at x = {x_tip:.6g} mm <= 0, the flanks cross below the addendum "
            f"(self-intersecting tooth); increase half_thickness_mm, or decrease "
            f"pressure_angle_deg or tooth.addendum_mm")

    segs = _chain([
        (ArcSegment, dict(centre=c_f, radius=rf, start_angle=th_root, sweep=root_sweep),
         rf * abs(root_sweep)),
        (LineSegment, dict(start=B, direction=d), la + lb),
        (ArcSegment, dict(centre=c_a, radius=ra, start_angle=a, sweep=tip_sweep), ra * tip_sweep),
    ])
    tooth = ToothProfile(kind="dcta", segments=segs, module_mm=m, teeth=z1,
                         neutral_radius_mm=r_m, pitch_y_mm=y_p, addendum_y_mm=y_a,
                         dedendum_y_mm=y_f, unit_speed_error=_speed_error(segs))
    _check_placement(
        tooth,
        cross_fields="tooth.half_thickness_mm / tooth.pressure_angle_deg",
        overlap_fields=(f"tooth.half_thickness_mm = {h:g} mm / tooth.root_arc_radius_mm = "
                        f"{rf:g} mm / tooth.dedendum_mm = {hf:g} mm"))
    return tooth


# --------------------------------------------------------------------------- involute


def _inv(a: float) -> float:
    """Involute function tan a - a."""
    return math.tan(a) - a


def involute_tooth(*, module_mm: float, teeth: int, neutral_radius_mm: float,
                   pressure_angle_deg: float = 20.0, addendum_mm: float | None = None,
                   dedendum_mm: float | None = None,
                   half_thickness_mm: float | None = None) -> ToothProfile:
    """Involute flexspline tooth (one :class:`InvoluteSegment`).

    The involute of the pitch circle r1 = m z1 / 2 about the flexspline
    centre (0, -r_m), base radius r_b = r1 cos(alpha); placed so the half
    tooth thickness measured as arc length on the pitch circle is
    ``half_thickness_mm`` (default pi m / 4). Truncated by the lines
    y = y_p + addendum (default m) and y = y_p - dedendum (default 1.25 m,
    ISO 53 basic rack) of the tooth frame. A root below the base circle is an
    error (no fillet is invented).
    """
    m, z1, r_m = _gear_args(module_mm, teeth, neutral_radius_mm)
    alpha_deg = _num(pressure_angle_deg, "tooth.pressure_angle_deg", lo=0.0, hi=60.0,
                     hi_open=True, unit="deg")
    ha = m if addendum_mm is None else _num(addendum_mm, "tooth.addendum_mm", lo=0.0)
    hf = 1.25 * m if dedendum_mm is None else _num(dedendum_mm, "tooth.dedendum_mm", lo=0.0)
    h, y_p, y_a, y_f = _tooth_levels(m, z1, r_m, ha, hf, half_thickness_mm)
    r1 = m * z1 / 2.0
    a = math.radians(alpha_deg)
    r_b = r1 * math.cos(a)
    # polar angle from +y (clockwise positive) of the base-circle point of the right flank
    psi_b = h / r1 + _inv(a)
    base_angle = math.pi / 2.0 - psi_b  # standard angle of that point
    c = np.array([0.0, -r_m])

    def y_of(theta: float) -> float:
        tau = base_angle + theta
        return -r_m + r_b * (math.sin(tau) - theta * math.cos(tau))

    theta_max = math.pi - base_angle  # y(theta) increases while tau < pi
    y_base = y_of(0.0)
    if not y_f > y_base:
        raise ToothError(
            f"tooth.dedendum_mm = {hf:g} mm: the root line y_f = {y_f:.6g} mm lies at or below "
            f"the involute's start on the base circle (r_b = r1 cos alpha = {r_b:.6g} mm, "
            f"y = {y_base:.6g} mm); dedendum_mm must be < {y_p - y_base:.6g} mm "
            f"(or lower tooth.pressure_angle_deg)")
    if not y_a < y_of(theta_max):
        raise ToothError(f"tooth.addendum_mm = {ha:g} mm: the involute never reaches y_a = {y_a:.6g} mm")

    def theta_at(y: float) -> float:
        from scipy.optimize import brentq

        th = brentq(lambda th: y_of(th) - y, 0.0, theta_max, xtol=1e-15, rtol=4 * np.finfo(float).eps)
        for _ in range(3):  # polish with Newton: dy/dtheta = r_b theta sin(tau)
            th -= (y_of(th) - y) / (r_b * th * math.sin(base_angle + th))
        return th

    th_f = theta_at(y_f)
    th_a = theta_at(y_a)
    # pointed tooth: the flank reaches x = 0 (polar angle 0) before the addendum
    x_tip = r_b * (math.cos(base_angle + th_a) + th_a * math.sin(base_angle + th_a))
    if x_tip <= 0.0:
        # radius where the tooth becomes pointed: inv(alpha_r) = psi_b
        from scipy.optimize import brentq

        a_pt = brentq(lambda x: _inv(x) - psi_b, 0.0, math.pi / 2 - 1e-9)
        r_pt = r_b / math.cos(a_pt)
        raise ToothError(
            f"tooth.addendum_mm = {ha:g} mm: the involute flanks cross at r = {r_pt:.6g} mm "
            f"(y = {r_pt - r_m:.6g} mm), below the addendum y_a = {y_a:.6g} mm (pointed tooth); "
            f"addendum_mm must be < about {r_pt - r_m - y_p:.6g} mm "
            f"(or increase tooth.half_thickness_mm)")
    s_f = r_b * th_f**2 / 2.0
    s_a = r_b * th_a**2 / 2.0
    segs = _chain([(InvoluteSegment, dict(centre=c, base_radius=r_b, base_angle=base_angle, s0=s_f),
                    s_a - s_f)])
    tooth = ToothProfile(kind="involute", segments=segs, module_mm=m, teeth=z1,
                         neutral_radius_mm=r_m, pitch_y_mm=y_p, addendum_y_mm=y_a,
                         dedendum_y_mm=y_f, unit_speed_error=_speed_error(segs))
    _check_placement(
        tooth, cross_fields="tooth.addendum_mm / tooth.half_thickness_mm",
        overlap_fields=f"tooth.half_thickness_mm = {h:g} mm / tooth.dedendum_mm = {hf:g} mm")
    return tooth


# --------------------------------------------------------------------------- points


#: Most points a point-list tooth takes (the gear set reader's limit too: ``tooth.points`` and
#: ``tooth.points_file``): the smoothing fit's time grows faster than the point count (FITPACK adds knots
#: a batch at a time: 10 000 noisy points with a smoothing far below the noise take ~15 s per
#: fit, and the fit runs three times), while a flank of a few mm needs a few hundred points.
MAX_POINTS = 10_000

#: The smoothed flank's arc length may be at most this many times the point polygon's (an
#: interpolating spline is ~1x as long, a smoothing one shorter): longer, it loops between
#: the points.
MAX_LENGTH_PER_POLYGON = 3.0

#: ... and at most this many times the points' extent (x range + y range): a flank that rises
#: from root to tip with x falling is at most 1x as long; longer, it zig-zags or loops.
MAX_LENGTH_PER_EXTENT = 4.0

#: Most samples of the arc-length grid (the step grows past 0.2 µm beyond ~40 mm of flank).
MAX_GRID = 200_001

#: Segments per spatial query when locating a crossing (bounds the pairs held at once).
_CROSSING_CHUNK = 4096


def _first_crossing(pts: np.ndarray) -> tuple[int, int] | None:
    """Indices (i, j), i < j - 1, of the first pair of non-adjacent polyline segments that
    intersect (smallest i, then smallest j), or None.

    An R-tree of the segments (``shapely.STRtree``) is queried a chunk of segments at a time,
    so the cost is about n log n plus the pairs found, not n² (a 20 000-point resampled flank
    took minutes with the pairwise search this replaces).
    """
    import shapely

    n = len(pts) - 1
    if n < 3:
        return None
    segs = shapely.linestrings(np.stack([pts[:-1], pts[1:]], axis=1))
    tree = shapely.STRtree(segs)
    for lo in range(0, n, _CROSSING_CHUNK):
        idx = np.arange(lo, min(lo + _CROSSING_CHUNK, n))
        q, j = tree.query(segs[idx], predicate="intersects")
        i = idx[q]
        hit = j >= i + 2
        if hit.any():
            i, j = i[hit], j[hit]
            k = np.lexsort((j, i))[0]
            return int(i[k]), int(j[k])
    return None


def _crossing_message(pts: np.ndarray) -> str:
    """'' if the polyline ``pts`` is simple, else where it crosses itself."""
    from shapely.geometry import LineString

    if LineString(pts).is_simple:
        return ""
    cross = _first_crossing(pts)
    if cross is None:  # touching / overlapping only
        return "polyline touches or overlaps itself"
    i, j = cross
    return (f"polyline crosses itself: segment {i}-{i + 1} meets segment {j}-{j + 1} "
            f"near ({pts[i, 0]:.6g}, {pts[i, 1]:.6g}) mm")


@dataclass(frozen=True, slots=True, eq=False)
class _ArcLengthTable:
    """Arc length s(u) of a parametric spline ``curve``: ``s_nodes`` = s at ``u_nodes``, each
    piece between nodes integrated by ``order``-point Gauss-Legendre.

    :meth:`of` puts 8 pieces in each knot span and 16 points on each, so the length is known
    at a cost set by the knot count, before any grid is sized; :meth:`refined` adds nodes (the
    pieces then lie inside one knot span, where |p'(u)| is analytic, and are short: 6 points).
    """

    curve: Any
    u_nodes: np.ndarray
    s_nodes: np.ndarray
    order: int

    @classmethod
    def of(cls, curve: Any, ua: float, ub: float) -> "_ArcLengthTable":
        kn = np.unique(np.concatenate([[ua, ub], curve.t[(curve.t > ua) & (curve.t < ub)]]))
        frac = np.linspace(0.0, 1.0, 9)[:-1]
        un = np.append((kn[:-1, None] + (kn[1:] - kn[:-1])[:, None] * frac).ravel(), ub)
        return cls._build(curve, un, 16)

    @classmethod
    def _build(cls, curve: Any, un: np.ndarray, order: int) -> "_ArcLengthTable":
        table = cls(curve, un, np.zeros(1), order)
        s = np.concatenate([[0.0], np.cumsum(table.piece(un[:-1], un[1:]))])
        object.__setattr__(table, "s_nodes", s)
        return table

    def refined(self, u: np.ndarray, order: int = 6) -> "_ArcLengthTable":
        """The table with the nodes ``u`` added (inside [ua, ub])."""
        return self._build(self.curve, np.union1d(self.u_nodes, u), order)

    @property
    def length_mm(self) -> float:
        return float(self.s_nodes[-1])

    def piece(self, a: np.ndarray, b: np.ndarray, chunk: int = 65536) -> np.ndarray:
        """Arc length from ``a`` to ``b`` (elementwise), evaluated ``chunk`` pieces at a time."""
        gx, gw = np.polynomial.legendre.leggauss(self.order)
        out = np.empty(len(a))
        for lo in range(0, len(a), chunk):
            a0, b0 = a[lo:lo + chunk], b[lo:lo + chunk]
            nodes = (a0[:, None] + b0[:, None]) / 2 + (b0 - a0)[:, None] / 2 * gx
            d = self.curve(nodes, 1)
            out[lo:lo + chunk] = (b0 - a0) / 2 * (np.hypot(d[..., 0], d[..., 1]) @ gw)
        return out

    def s_of(self, u: np.ndarray) -> np.ndarray:
        j = np.clip(np.searchsorted(self.u_nodes, u, side="right") - 1, 0, len(self.u_nodes) - 2)
        return self.s_nodes[j] + self.piece(self.u_nodes[j], u)


def _arc_length_spline(table: _ArcLengthTable, step_mm: float
                       ) -> tuple[SplineSegment, np.ndarray, np.ndarray, np.ndarray]:
    """Re-interpolate the parametric spline of ``table`` in arc length.

    Returns the quintic :class:`SplineSegment` in s, the equal-s grid (step ``step_mm``,
    at least 1001 and at most :data:`MAX_GRID` samples), u at the grid (Newton on
    s(u) - s = 0 from a table of s(u) refined by the grid's count of equal-u samples) and
    the curve points there.
    """
    from scipy.interpolate import make_interp_spline

    curve, length = table.curve, table.length_mm
    ua, ub = float(table.u_nodes[0]), float(table.u_nodes[-1])
    n_grid = min(MAX_GRID, max(1001, int(math.ceil(length / step_mm)) + 1))
    fine = table.refined(np.linspace(ua, ub, n_grid))
    length = fine.length_mm
    s_grid = np.linspace(0.0, length, n_grid)
    uu = np.interp(s_grid, fine.s_nodes, fine.u_nodes)
    for _ in range(2):
        d = curve(uu, 1)
        uu = np.clip(uu - (fine.s_of(uu) - s_grid) / np.hypot(d[:, 0], d[:, 1]), ua, ub)
    uu[0], uu[-1] = ua, ub
    xy = curve(uu)
    q = make_interp_spline(s_grid, xy, k=5)
    s_chk = np.concatenate([s_grid, (s_grid[:-1] + s_grid[1:]) / 2])
    dp = q(s_chk, 1)
    speed_err = float(np.max(np.abs(np.hypot(dp[:, 0], dp[:, 1]) - 1.0)))
    seg = SplineSegment(t0=0.0, t1=length, knots=q.t, coefficients=q.c, degree=5,
                        unit_speed_error=speed_err)
    return seg, s_grid, uu, xy


def _check_length(table: _ArcLengthTable, pts: np.ndarray, source: str, sm: float) -> None:
    """The smoothed flank must not be much longer than its points: a spline that loops or
    follows a zig-zag would otherwise size the arc-length grid (and the time and memory of
    everything after it) by its own length, which has no bound."""
    length = table.length_mm
    polygon = float(np.sum(np.hypot(*np.diff(pts, axis=0).T)))
    extent = float(np.ptp(pts[:, 0]) + np.ptp(pts[:, 1]))
    if not math.isfinite(length) or length > MAX_LENGTH_PER_POLYGON * polygon:
        raise ToothError(
            f"{source}: the smoothed flank's arc length ({length:.6g} mm) is "
            f"{length / polygon:.3g}x the point polygon's ({polygon:.6g} mm; at most "
            f"{MAX_LENGTH_PER_POLYGON:g}x) -- the spline loops between the points: they cross, "
            "run out of order, or are very unevenly spaced")
    if length > MAX_LENGTH_PER_EXTENT * extent:
        raise ToothError(
            f"{source}: the smoothed flank's arc length ({length:.6g} mm) is "
            f"{length / extent:.3g}x the points' extent (x range + y range = {extent:.6g} mm; "
            f"a flank rising from root to tip is at most 1x, allowed {MAX_LENGTH_PER_EXTENT:g}x) "
            f"-- the points zig-zag, loop or cross (noise larger than the point spacing needs "
            f"tooth.smoothing_mm about the noise size; it is {sm:g} mm)")


def _fit_parametric(x: np.ndarray, y: np.ndarray, s: float, u: np.ndarray | None = None
                    ) -> tuple[Any, np.ndarray]:
    """Quintic parametric smoothing spline (FITPACK ``parcur`` via ``splprep``; the same
    fit as ``make_splprep``, whose Python knot search took 1.6 s for 1 000 noisy points
    against 10 ms here): the curve as a BSpline with (n, 2) coefficients and the parameters."""
    from scipy.interpolate import BSpline, splprep

    (t, c, k), u_out = splprep([x, y], u=u, k=5, s=s, quiet=1)
    coef = np.ascontiguousarray(np.array(c, dtype=float).T[: len(t) - k - 1])
    return BSpline.construct_fast(np.asarray(t, dtype=float), coef, k), np.asarray(u_out, dtype=float)


def _foot_points(seg: SplineSegment, pts: np.ndarray, s_init: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Arc-length parameter of the nearest curve point to each of ``pts`` and the distance."""
    s_i = np.clip(s_init, seg.t0, seg.t1)
    for _ in range(10):
        p, d1, d2 = seg.evaluate(s_i)
        r = p - pts
        g = np.sum(r * d1, axis=1)
        hess = np.sum(d1 * d1, axis=1) + np.sum(r * d2, axis=1)
        s_i = np.clip(s_i - g / np.where(hess > 0.1, hess, 1.0), seg.t0, seg.t1)
    p, _, _ = seg.evaluate(s_i)
    return s_i, np.hypot(*(p - pts).T)


def points_tooth(points: Any, *, module_mm: float, teeth: int, neutral_radius_mm: float,
                 smoothing_mm: float = 5e-4, source: str = "tooth.points") -> ToothProfile:
    """Tooth from points of the right flank (tooth frame, root -> tip, 8 to
    :data:`MAX_POINTS` points).

    Fit: a parametric quintic smoothing B-spline (FITPACK ``parcur``, as
    ``scipy.interpolate.splprep``) with the bound ``sum |g(u_j) - x_j|^2 <=
    n smoothing_mm^2`` -- ``smoothing_mm`` is the RMS distance of the points
    from the curve allowed (about the noise sigma per coordinate); ``0``
    interpolates the points in the order given (chord-length parameter).
    With smoothing, the chord-length parameter of noisy points is corrected
    twice (Hoschek): each point gets the arc-length parameter of its foot
    point on the previous fit, points are taken in that order, and the
    spline is refitted, so the residuals are normal distances and noise
    larger than the point spacing does not fold the curve.

    Arc length: integrated with 16-point Gauss-Legendre per eighth of a knot
    span; the curve is resampled every <= 0.2 µm of arc length (u(s) by
    Newton; at most :data:`MAX_GRID` samples) and re-interpolated as a quintic
    x(s), y(s): ``t`` is arc length up to ``unit_speed_error`` (max | |p'| - 1 |,
    ~1e-11).

    Bounded cost: at most :data:`MAX_POINTS` points, and a smoothed flank longer
    than :data:`MAX_LENGTH_PER_POLYGON` x the point polygon or
    :data:`MAX_LENGTH_PER_EXTENT` x the points' extent (x range + y range) is a
    :class:`ToothError` (the points loop, cross or zig-zag) before any grid is
    sized by that length.

    ``fit_error_mm`` / ``fit_rms_mm``: max / RMS normal distance of the input
    points to the final curve. Exact data (e.g. sampled from CAD) should be
    given with ``smoothing_mm`` below the accuracy wanted, or 0: a smoothing
    curve is *meant* to miss the points by about ``smoothing_mm``.

    ``source`` names where the points came from in error messages
    (``tooth.points``, or ``tooth.points_file = '...'``).
    """
    m, z1, r_m = _gear_args(module_mm, teeth, neutral_radius_mm)
    sm = _num(smoothing_mm, "tooth.smoothing_mm", lo=0.0, hi=1.0, lo_open=False)
    try:
        pts = np.array(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ToothError(f"{source} must be an (n, 2) array of numbers (mm), got {exc}") from None
    if pts.ndim != 2 or pts.shape[1] != 2 or not 8 <= pts.shape[0] <= MAX_POINTS:
        raise ToothError(f"{source} must be an (n, 2) array with 8 <= n <= {MAX_POINTS}, "
                         f"got shape {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise ToothError(f"{source} contains NaN or inf")
    step = np.hypot(*np.diff(pts, axis=0).T)
    if np.any(step <= 0.0):
        raise ToothError(f"{source} has repeated consecutive points (index {int(np.argmin(step))})")
    if not pts[-1, 1] > pts[0, 1]:
        raise ToothError(
            f"{source} must run root -> tip (last y > first y), got y from "
            f"{pts[0, 1]:.6g} to {pts[-1, 1]:.6g} mm")
    # A crossing of the raw polyline is fatal when it is interpolated; with smoothing,
    # noise zig-zags (noise > point spacing) are expected, and the smoothed curve is
    # checked instead.
    raw_cross = _crossing_message(pts)
    if raw_cross and sm == 0.0:
        raise ToothError(f"{source}: {raw_cross} (tooth.smoothing_mm = 0: interpolated as given)")

    npt = len(pts)
    s_budget = npt * sm**2
    step_mm = 2e-4
    curve, u = _fit_parametric(pts[:, 0], pts[:, 1], s_budget)
    order = np.arange(npt)
    passes = 2 if sm > 0.0 else 0
    for it in range(passes + 1):
        table = _ArcLengthTable.of(curve, float(u[0]), float(u[-1]))
        _check_length(table, pts, source, sm)
        seg, s_grid, uu, xy = _arc_length_spline(table, step_mm)
        s_i, dist = _foot_points(seg, pts[order], np.interp(u, uu, s_grid))
        if it == passes:
            break
        # parameter correction: order by foot point, u = foot arc length (strictly increasing)
        k = np.argsort(s_i, kind="stable")
        order, s_new = order[k], s_i[k]
        floor = 1e-9 * seg.length_mm * np.arange(npt)
        u_new = np.maximum.accumulate(s_new - floor) + floor
        curve, u = _fit_parametric(pts[order, 0], pts[order, 1], s_budget, u=u_new)
    fit_cross = _crossing_message(xy)
    if fit_cross:
        raise ToothError(
            f"{source}: the smoothed flank crosses itself ({fit_cross}; tooth.smoothing_mm = "
            f"{sm:g} mm); " + (f"the input {raw_cross}" if raw_cross else "check the point order"))
    fit_max = float(np.max(dist))
    fit_rms = float(np.sqrt(np.mean(dist**2)))
    log.debug("points tooth: L=%.6g mm, %d knots, fit max %.3g rms %.3g, |p'|-1 %.3g",
              seg.length_mm, len(curve.t), fit_max, fit_rms, seg.unit_speed_error)

    y_p = m * z1 / 2.0 - r_m
    tip, root = xy[-1], xy[0]
    if not root[1] > 0.0:
        raise ToothError(f"{source}: the root point y = {root[1]:.6g} mm is not above the "
                         "neutral line (y > 0)")
    tooth = ToothProfile(kind="points", segments=(seg,), module_mm=m, teeth=z1,
                         neutral_radius_mm=r_m, pitch_y_mm=y_p, addendum_y_mm=float(tip[1]),
                         dedendum_y_mm=float(root[1]), fit_error_mm=fit_max, fit_rms_mm=fit_rms,
                         unit_speed_error=seg.unit_speed_error)
    _check_placement(tooth, cross_fields=source, overlap_fields=source)
    from shapely.geometry import Polygon

    poly = Polygon(tooth.outline(n_per_mm=500.0))
    if not poly.is_valid:
        from shapely.validation import explain_validity

        raise ToothError(
            f"{source}: the tooth outline built on the smoothed flank is not a simple polygon "
            f"({explain_validity(poly)}); the flank must rise from its root point "
            f"({root[0]:.6g}, {root[1]:.6g}) mm to its tip ({tip[0]:.6g}, {tip[1]:.6g}) mm "
            "without dipping below the root circle or crossing the top land")
    return tooth


# --------------------------------------------------------------------------- dispatch

_DCTA_FIELDS = ("pressure_angle_deg", "line_above_pitch_mm", "line_below_pitch_mm",
                "tip_arc_radius_mm", "root_arc_radius_mm", "addendum_mm", "dedendum_mm",
                "half_thickness_mm")
_INVOLUTE_FIELDS = ("pressure_angle_deg", "addendum_mm", "dedendum_mm", "half_thickness_mm")
_POINTS_FIELDS = ("smoothing_mm",)


def tooth_from_gearset(gearset: Any) -> ToothProfile:
    """The flexspline tooth of ``gearset`` (dispatch on ``gearset.tooth.kind``).

    Reads ``gearset.gear.module_mm``, ``.flexspline_teeth``,
    ``.neutral_radius_mm`` and the tooth section's fields named like the
    constructor keywords; a field that is absent or ``None`` takes the
    constructor's default.

    ``gearset.tooth.points`` are in the gear set's *pitch frame* (origin at the
    pitch point on the tooth axis, see ``profilegen.gearset``); they are moved
    by ``r1 - r_m`` along y into the tooth frame used here.
    """
    gear = getattr(gearset, "gear", None)
    tooth = getattr(gearset, "tooth", None)
    if gear is None or tooth is None:
        raise GearSetError("gearset must have 'gear' and 'tooth' sections")
    common = dict(module_mm=getattr(gear, "module_mm", None),
                  teeth=getattr(gear, "flexspline_teeth", None),
                  neutral_radius_mm=getattr(gear, "neutral_radius_mm", None))
    kind = getattr(tooth, "kind", None)
    table: dict[str, tuple[Callable[..., ToothProfile], tuple[str, ...]]] = {
        "dcta": (dcta_tooth, _DCTA_FIELDS), "involute": (involute_tooth, _INVOLUTE_FIELDS),
        "points": (points_tooth, _POINTS_FIELDS)}
    if kind not in table:
        raise ToothError(f"tooth.kind must be one of {sorted(table)}, got {kind!r}")
    fn, names = table[kind]
    kw = {n: getattr(tooth, n) for n in names if getattr(tooth, n, None) is not None}
    if kind == "points":
        pts = getattr(tooth, "points", None)
        if pts is None:
            raise ToothError("tooth.points is required for tooth.kind = 'points'")
        points_file = getattr(tooth, "points_file", None)
        source = "tooth.points" if points_file is None else f"tooth.points_file = {json.dumps(str(points_file))}"
        try:
            pts = np.array(pts, dtype=float)
            m, z1, r_m = _gear_args(**common)
            pts = pts + [0.0, m * z1 / 2.0 - r_m]  # pitch frame -> tooth frame
        except (TypeError, ValueError) as exc:
            if isinstance(exc, GearSetError):
                raise
            raise ToothError(f"{source} must be an (n, 2) array of numbers (mm): {exc}") from None
        return fn(pts, **common, **kw, source=source)
    return fn(**common, **kw)
