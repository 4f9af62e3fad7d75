"""Wave-generator contours: the rigid curve the flexspline bore is pressed onto.

Conventions (docs/reference/conventions.md): lengths in mm, angles in rad. θ is the polar angle measured from
the wave-generator major axis; in the CS/WG frame the major axis is +y and θ runs from +y
toward +x, so a point at radius r is ``(r sin θ, r cos θ)``. Points are ``(n, 2)`` arrays.

Every contour satisfies :class:`Contour`:

* ``radius(theta)`` — the contour's polar radius r(θ) (mm);
* ``closest(points)`` → ``(foot, normal, distance)``: the foot point on the contour, the
  outward unit normal there, and the signed distance (positive outside the contour), all
  vectorised. ``distance == (points − foot) · normal``.

Implemented:

* :class:`EllipticalCam` — seed 004's modelling: the rigid contour is "the offset curve of
  the cam's elliptical profile by the thickness of the flex bearing". An offset of an
  ellipse is not an ellipse; it is handled exactly as foot-on-ellipse + offset along the
  ellipse normal (parallel curves share their normals, so the signed distance to the
  offset is the distance to the ellipse minus the offset).
* :class:`CosineCam` — the contour of ring theory, r(θ) = r0 + w0 cos(Uθ).
* :class:`RollerGenerator` — two or four rigid rollers of radius R; the contour is the
  union of their circles (centres symmetric about both axes, so the quarter model with
  symmetry cuts at x = 0 and y = 0 stays valid).
* :func:`from_gearset` — the contour that pushes the rim's bore (r_bore = r_m − δ/2) out
  by w0 on the major axis (the rollers: onto the ring-theory bore, see there).

>>> cam = EllipticalCam(52.0, 48.0, bearing_thickness_mm=3.0)
>>> round(float(cam.radius(0.0)[0]), 12), round(float(cam.radius(np.pi / 2)[0]), 12)
(55.0, 51.0)
>>> foot, normal, dist = cam.closest([[0.0, 60.0]])
>>> round(float(dist[0]), 12), normal[0].tolist()
(5.0, [0.0, 1.0])
>>> rollers = RollerGenerator(10.0, 39.0)  # two rollers, centres (0, ±39) mm
>>> rollers.radius([0.0, np.pi / 2]).tolist()  # the ray along the minor axis misses both
[49.0, 0.0]
>>> foot, normal, dist = rollers.closest([[0.0, 50.0], [0.0, 0.0]])
>>> dist.tolist(), normal.tolist()
([1.0, 29.0], [[0.0, 1.0], [0.0, -1.0]])
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial
from typing import Protocol

import numpy as np

from .. import checks
from ..errors import ConvergenceError, GearSetError, ProfilegenError
from ..results import readonly as _readonly

__all__ = [
    "Contour",
    "CosineCam",
    "EllipticalCam",
    "RollerGenerator",
    "WaveGenError",
    "WaveGeneratorFitError",
    "ellipse_perimeter",
    "from_gearset",
]

_BISECTIONS = 200  # enough to reach adjacent floats on any interval of lengths O(r²)


class WaveGenError(ProfilegenError, ValueError):
    """Bad wave-generator input; the message names the parameter, its value, unit and range."""


class WaveGeneratorFitError(WaveGenError, GearSetError):
    """A gear set whose wave generator cannot be built for its rim (rollers that overlap or do not
    fit the deformed bore, a bearing thicker than the bore, ...): raised when the
    :class:`~profilegen.gearset.GearSet` is validated, so a ``GearSetError`` as well."""


class Contour(Protocol):
    """What the rim contact needs from a wave-generator contour."""

    def radius(self, theta) -> np.ndarray:
        """Polar radius r(θ) (mm) at polar angle θ from the major axis (rad)."""
        ...

    def closest(self, points) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(foot points (n, 2), outward unit normals (n, 2), signed distance (n,), + outside)."""
        ...


_positive = partial(checks.positive, error=WaveGenError)


def _points(points) -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim == 1 and p.size == 2:
        p = p.reshape(1, 2)
    if p.ndim != 2 or p.shape[1] != 2:
        raise WaveGenError(f"points: must be an (n, 2) array (mm), got shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise WaveGenError("points: coordinates must be finite (mm)")
    return p


def ellipse_perimeter(semi_major_mm: float, semi_minor_mm: float) -> float:
    """Perimeter 4 a E(1 − b²/a²) of an ellipse (mm), complete elliptic integral E."""
    a, b = max(semi_major_mm, semi_minor_mm), min(semi_major_mm, semi_minor_mm)
    return float(4.0 * a * _ellipe(1.0 - (b / a) ** 2))


# scipy.special.ellipe and scipy.optimize.brentq, written out: importing scipy's modules took
# ~1 s (their docstrings are parsed on import), longer than `profilegen check` as a whole, which
# builds the wave generator of every set it reads. The same operations in the same order as
# scipy's C code (cephes ellpe, scipy's brentq.c), so the results are the same to the last bit
# (tests/unit/test_wavegen.py compares them with scipy's).
_ELLPE_P = (1.53552577301013293365E-4, 2.50888492163602060990E-3, 8.68786816565889628429E-3,
            1.07350949056076193403E-2, 7.77395492516787092951E-3, 7.58395289413514708519E-3,
            1.15688436810574127319E-2, 2.18317996015557253103E-2, 5.68051945617860553470E-2,
            4.43147180560990850618E-1, 1.00000000000000000299E0)
_ELLPE_Q = (3.27954898576485872656E-5, 1.00962792679356715133E-3, 6.50609489976927491433E-3,
            1.68862163993311317300E-2, 2.61769742454493659583E-2, 3.34833904888224918614E-2,
            4.27180926518931511717E-2, 5.85936634471101055642E-2, 9.37499997197644278445E-2,
            2.49999999999888314361E-1)


def _polevl(x: float, coef: tuple[float, ...]) -> float:
    ans = coef[0]
    for c in coef[1:]:
        ans = ans * x + c
    return ans


def _ellipe(m: float) -> float:
    """Complete elliptic integral of the second kind E(m), parameter m = k² (scipy.special.ellipe)."""
    x = 1.0 - float(m)
    if not x > 0.0:
        return 1.0 if x == 0.0 else math.nan
    if x > 1.0:
        return _ellipe(1.0 - 1.0 / x) * math.sqrt(x)  # m < 0, as cephes
    return _polevl(x, _ELLPE_P) - math.log(x) * (x * _polevl(x, _ELLPE_Q))


def _brentq(f, xa: float, xb: float, *, xtol: float, rtol: float, maxiter: int) -> float:
    """A root of f in [xa, xb] by Brent's method, f(xa) and f(xb) of opposite signs (scipy.optimize.brentq)."""
    xpre, xcur = float(xa), float(xb)
    xblk = fblk = spre = scur = 0.0
    fpre, fcur = f(xpre), f(xcur)
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    if math.copysign(1.0, fpre) == math.copysign(1.0, fcur):
        raise ValueError("f(a) and f(b) must have different signs")
    for _ in range(maxiter):
        if fpre != 0.0 and fcur != 0.0 and math.copysign(1.0, fpre) != math.copysign(1.0, fcur):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # interpolate
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # extrapolate
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):  # good short step
                spre, scur = scur, stry
            else:  # bisect
                spre = scur = sbis
        else:  # bisect
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        fcur = f(xcur)
    raise ConvergenceError(f"wave generator: Brent's method did not converge in {maxiter} iterations "
                           f"(last x = {xcur!r} mm)")


def _ellipse_foot(pu: np.ndarray, pv: np.ndarray, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    """Closest point on u²/a² + v²/b² = 1 (a ≥ b) to points with pu, pv ≥ 0 (first quadrant).

    The foot is f_i = a_i² p_i / (a_i² + s) with s the root of
    F(s) = Σ (a_i p_i / (a_i² + s))² − 1 on (−b², ∞), where F decreases monotonically and
    the root gives the global minimum (Eberly, "Distance from a point to an ellipse").
    With t = s + b² the root is bracketed by [b·pv, √(a²pu² + b²pv²)]; bisection to
    adjacent floats (robust for points inside, near the evolute, or far away), then one
    Newton step. pv = 0 is handled in closed form.
    """
    c2 = a * a - b * b
    fu = np.empty_like(pu)
    fv = np.empty_like(pv)
    axis = pv <= 0.0
    # on the major axis: interior points near the centre have their foot off the axis
    inner = axis & (a * pu < c2)
    fu[inner] = a * a * pu[inner] / c2
    fv[inner] = b * np.sqrt(np.maximum(0.0, 1.0 - (fu[inner] / a) ** 2))
    outer = axis & ~inner
    fu[outer] = a
    fv[outer] = 0.0
    gen = ~axis
    if np.any(gen):
        u, v = pu[gen], pv[gen]
        lo = b * v
        hi = np.maximum(np.sqrt((a * u) ** 2 + (b * v) ** 2), lo)

        def f(t):
            return (a * u / (t + c2)) ** 2 + (b * v / t) ** 2 - 1.0

        for _ in range(_BISECTIONS):
            mid = 0.5 * (lo + hi)
            if np.all((mid == lo) | (mid == hi)):
                break
            pos = f(mid) > 0.0
            lo = np.where(pos, mid, lo)
            hi = np.where(pos, hi, mid)
        t = 0.5 * (lo + hi)
        fu[gen] = a * a * u / (t + c2)
        fv[gen] = b * b * v / t
    return fu, fv


@dataclass(frozen=True, slots=True, eq=False)
class EllipticalCam:
    """Elliptical cam (semi-axes a along the major axis, b along the minor axis, mm) with a
    flexible bearing of thickness h: the rigid contour is the ellipse's outward offset by h.

    ``radius(θ)`` and ``closest`` refer to the offset contour (the ellipse itself when h = 0).
    """

    semi_major_mm: float
    semi_minor_mm: float
    bearing_thickness_mm: float = 0.0

    def __post_init__(self):
        a = _positive("semi_major_mm", self.semi_major_mm)
        b = _positive("semi_minor_mm", self.semi_minor_mm)
        h = _positive("bearing_thickness_mm", self.bearing_thickness_mm, allow_zero=True)
        if b > a:
            raise WaveGenError(
                f"semi_minor_mm = {b} mm: must be ≤ semi_major_mm = {a} mm (the major axis is the longer one)"
            )
        object.__setattr__(self, "semi_major_mm", a)
        object.__setattr__(self, "semi_minor_mm", b)
        object.__setattr__(self, "bearing_thickness_mm", h)

    @property
    def major_radius_mm(self) -> float:
        """Radius of the contour on the major axis, a + h (mm)."""
        return self.semi_major_mm + self.bearing_thickness_mm

    @property
    def minor_radius_mm(self) -> float:
        """Radius of the contour on the minor axis, b + h (mm)."""
        return self.semi_minor_mm + self.bearing_thickness_mm

    @property
    def perimeter_mm(self) -> float:
        """Perimeter of the contour: ellipse perimeter + 2πh (offset of a convex closed curve)."""
        return ellipse_perimeter(self.semi_major_mm, self.semi_minor_mm) + 2.0 * math.pi * self.bearing_thickness_mm

    def ellipse_closest(self, points) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Foot, outward unit normal and signed distance to the cam *ellipse* (no offset)."""
        p = _points(points)
        a, b = self.semi_major_mm, self.semi_minor_mm
        pu, pv = p[:, 1], p[:, 0]  # u along the major axis (+y), v along the minor (+x)
        fu, fv = _ellipse_foot(np.abs(pu), np.abs(pv), a, b)
        fu = np.copysign(fu, np.where(pu == 0.0, 1.0, pu))
        fv = np.copysign(fv, np.where(pv == 0.0, 1.0, pv))
        nu, nv = fu / (a * a), fv / (b * b)
        norm = np.hypot(nu, nv)
        nu, nv = nu / norm, nv / norm
        foot = np.column_stack([fv, fu])
        normal = np.column_stack([nv, nu])
        dist = np.einsum("ij,ij->i", p - foot, normal)
        return foot, normal, dist

    def closest(self, points) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        foot, normal, dist = self.ellipse_closest(points)
        h = self.bearing_thickness_mm
        return foot + h * normal, normal, dist - h

    def point(self, tau) -> tuple[np.ndarray, np.ndarray]:
        """Contour point and outward normal at ellipse parameter τ (u = a cos τ, v = b sin τ)."""
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        a, b, h = self.semi_major_mm, self.semi_minor_mm, self.bearing_thickness_mm
        nu, nv = b * np.cos(tau), a * np.sin(tau)
        norm = np.hypot(nu, nv)
        nu, nv = nu / norm, nv / norm
        u = a * np.cos(tau) + h * nu
        v = b * np.sin(tau) + h * nv
        return np.column_stack([v, u]), np.column_stack([nv, nu])

    def radius(self, theta) -> np.ndarray:
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        # fold to [0, π/2]: the contour is symmetric about both axes
        folded = np.abs(np.remainder(theta + 0.5 * math.pi, math.pi) - 0.5 * math.pi)
        lo = np.zeros_like(folded)
        hi = np.full_like(folded, 0.5 * math.pi)
        for _ in range(_BISECTIONS):  # polar angle of the offset point grows with τ
            mid = 0.5 * (lo + hi)
            if np.all((mid == lo) | (mid == hi)):
                break
            q = self.point(mid)[0]
            ahead = np.arctan2(q[:, 0], q[:, 1]) < folded
            lo = np.where(ahead, mid, lo)
            hi = np.where(ahead, hi, mid)
        q = self.point(0.5 * (lo + hi))[0]
        return np.hypot(q[:, 0], q[:, 1])

    def to_dict(self) -> dict:
        return {
            "kind": "elliptical_cam",
            "semi_major_mm": self.semi_major_mm,
            "semi_minor_mm": self.semi_minor_mm,
            "bearing_thickness_mm": self.bearing_thickness_mm,
            "major_radius_mm": self.major_radius_mm,
            "minor_radius_mm": self.minor_radius_mm,
            "perimeter_mm": self.perimeter_mm,
        }


@dataclass(frozen=True, slots=True, eq=False)
class CosineCam:
    """Ring theory's contour r(θ) = r0 + w0 cos(Uθ) (mm)."""

    mean_radius_mm: float
    deflection_mm: float
    waves: int = 2

    def __post_init__(self):
        r0 = _positive("mean_radius_mm", self.mean_radius_mm)
        w0 = _positive("deflection_mm", self.deflection_mm, allow_zero=True)
        if isinstance(self.waves, bool) or not isinstance(self.waves, (int, np.integer)) or self.waves < 1:
            raise WaveGenError(f"waves = {self.waves!r}: must be a whole number ≥ 1")
        if w0 >= r0 / (1.0 + self.waves**2):
            raise WaveGenError(
                f"deflection_mm = {w0} mm: must be < mean_radius_mm / (1 + U²) = {r0 / (1 + self.waves ** 2):.6g} mm "
                "(a convex contour)"
            )
        object.__setattr__(self, "mean_radius_mm", r0)
        object.__setattr__(self, "deflection_mm", w0)

    def _r(self, theta):
        k, w0 = self.waves, self.deflection_mm
        c, s = np.cos(k * theta), np.sin(k * theta)
        return self.mean_radius_mm + w0 * c, -k * w0 * s, -k * k * w0 * c

    def radius(self, theta) -> np.ndarray:
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        return self._r(theta)[0]

    def closest(self, points, *, max_iterations: int = 50) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Newton on the polar angle θ of the foot, g(θ) = (c(θ) − p)·c′(θ) = 0, from the
        point's own polar angle (steps limited to 0.1 rad). Raises ConvergenceError naming
        the points that do not converge."""
        p = _points(points)
        theta = np.arctan2(p[:, 0], p[:, 1])
        for _ in range(max_iterations):
            r, r1, r2 = self._r(theta)
            er = np.column_stack([np.sin(theta), np.cos(theta)])
            et = np.column_stack([np.cos(theta), -np.sin(theta)])
            c = r[:, None] * er
            c1 = r1[:, None] * er + r[:, None] * et
            c2 = (r2 - r)[:, None] * er + 2.0 * r1[:, None] * et
            diff = c - p
            g = np.einsum("ij,ij->i", diff, c1)
            dg = np.einsum("ij,ij->i", c1, c1) + np.einsum("ij,ij->i", diff, c2)
            step = np.clip(g / dg, -0.1, 0.1)
            theta = theta - step
            if np.all(np.abs(step) <= 4e-16 * (1.0 + np.abs(theta))):
                break
        else:
            bad = np.flatnonzero(np.abs(step) > 1e-12)
            if bad.size:
                raise ConvergenceError(
                    f"CosineCam.closest: Newton on θ did not converge in {max_iterations} iterations for "
                    f"{bad.size} points, first {p[bad[0]].tolist()} (step {step[bad[0]]:.3g} rad)"
                )
        r, r1, _ = self._r(theta)
        er = np.column_stack([np.sin(theta), np.cos(theta)])
        et = np.column_stack([np.cos(theta), -np.sin(theta)])
        foot = r[:, None] * er
        normal = r[:, None] * er - r1[:, None] * et
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        dist = np.einsum("ij,ij->i", p - foot, normal)
        return foot, normal, dist

    @property
    def major_radius_mm(self) -> float:
        return self.mean_radius_mm + self.deflection_mm

    def to_dict(self) -> dict:
        return {
            "kind": "cosine_cam",
            "mean_radius_mm": self.mean_radius_mm,
            "deflection_mm": self.deflection_mm,
            "waves": int(self.waves),
        }



@dataclass(frozen=True, slots=True, eq=False)
class RollerGenerator:
    """Two or four rigid rollers of radius R (mm); the contour is the union of their circles.

    Centres (polar angle from the major axis +y toward +x, distance d from the centre):

    * ``roller_count = 2``: on the major axis, (0, ±d); ``centre_angle_rad`` must be 0;
    * ``roller_count = 4``: at ±α about each end of the major axis, (±d sin α, ±d cos α),
      0 < α < π/4.

    The set is symmetric about both axes (a quarter model with symmetry cuts at x = 0 and
    y = 0 sees it whole). The rollers must not overlap (centre spacing ≥ 2R, touching is
    allowed): then ``closest`` is exact, also inside a roller.

    * ``closest(points)``: per point, the roller with the smallest signed distance
      |p − c| − R (ties go to the roller listed first in :attr:`centres`); normal
      (p − c)/|p − c|, foot c + R·normal. A point exactly at a centre gets the normal
      c/|c| (radially outward).
    * ``radius(θ)``: the outermost intersection of the ray from the centre at θ with the
      rollers. The union is not star-shaped about the centre: a ray that misses every
      roller (between the rollers) gets **0.0** — never NaN — so that plotting
      (r sin θ, r cos θ) draws each roller joined to the centre by spokes, and ``r > 0``
      masks the angles the rollers cover.
    """

    roller_radius_mm: float
    centre_distance_mm: float
    roller_count: int = 2
    centre_angle_rad: float = 0.0

    def __post_init__(self):
        radius = _positive("roller_radius_mm", self.roller_radius_mm)
        dist = _positive("centre_distance_mm", self.centre_distance_mm)
        count = self.roller_count
        if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count not in (2, 4):
            raise WaveGenError(f"roller_count = {count!r}: must be 2 or 4")
        try:
            alpha = float(self.centre_angle_rad)
        except (TypeError, ValueError) as exc:
            raise WaveGenError(f"centre_angle_rad = {self.centre_angle_rad!r}: must be a number (rad)") from exc
        if count == 2 and alpha != 0.0:
            raise WaveGenError(
                f"centre_angle_rad = {self.centre_angle_rad!r} rad: must be 0 with roller_count = 2 "
                "(both rollers sit on the major axis)"
            )
        if count == 4 and not (math.isfinite(alpha) and 0.0 < alpha < 0.25 * math.pi):
            raise WaveGenError(
                f"centre_angle_rad = {self.centre_angle_rad!r} rad: must be in (0, π/4) = (0, {0.25 * math.pi:.6g}) "
                "with roller_count = 4"
            )
        # nearest pair: across the major axis (2d sin α) for four rollers, 2d for two
        half_spacing = dist if count == 2 else dist * math.sin(alpha)
        if radius > half_spacing:
            raise WaveGenError(
                f"roller_radius_mm = {self.roller_radius_mm!r} mm: must be ≤ {half_spacing:.6g} mm (half the spacing "
                f"of the nearest roller centres; the rollers must not overlap)"
            )
        object.__setattr__(self, "roller_radius_mm", radius)
        object.__setattr__(self, "centre_distance_mm", dist)
        object.__setattr__(self, "roller_count", int(count))
        object.__setattr__(self, "centre_angle_rad", alpha)

    @property
    def centres(self) -> np.ndarray:
        """Roller centres (k, 2) (mm), exactly symmetric about both axes."""
        d = self.centre_distance_mm
        if self.roller_count == 2:
            return _readonly([[0.0, d], [0.0, -d]])
        s, c = d * math.sin(self.centre_angle_rad), d * math.cos(self.centre_angle_rad)
        return _readonly([[s, c], [-s, c], [s, -c], [-s, -c]])

    @property
    def outer_radius_mm(self) -> float:
        """Largest polar radius of the contour, d + R (mm), reached on the rays through the centres."""
        return self.centre_distance_mm + self.roller_radius_mm

    def closest(self, points) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        p = _points(points)
        centres = self.centres
        diff = p[:, None, :] - centres[None, :, :]  # (n, k, 2)
        rho = np.hypot(diff[..., 0], diff[..., 1])
        which = np.argmin(rho, axis=1)  # smallest |p − c| = smallest signed distance (equal radii)
        rows = np.arange(p.shape[0])
        d, r = diff[rows, which], rho[rows, which]
        centre = centres[which]
        radial = centre / self.centre_distance_mm
        normal = np.where((r > 0.0)[:, None], d / np.where(r > 0.0, r, 1.0)[:, None], radial)
        foot = centre + self.roller_radius_mm * normal
        return foot, normal, r - self.roller_radius_mm

    def radius(self, theta) -> np.ndarray:
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        ray = np.stack([np.sin(theta), np.cos(theta)], axis=-1)  # (..., 2)
        proj = ray @ self.centres.T  # (..., k): e·c
        d, radius = self.centre_distance_mm, self.roller_radius_mm
        # |t e − c|² = R²  ⇔  t = e·c ± √((e·c)² − (d − R)(d + R)); the origin is never inside a roller
        disc = proj * proj - (d - radius) * (d + radius)
        hit = disc >= 0.0
        t = np.where(hit, proj + np.sqrt(np.where(hit, disc, 0.0)), 0.0)
        return np.max(np.where(hit & (t > 0.0), t, 0.0), axis=-1)

    def to_dict(self) -> dict:
        return {
            "kind": "rollers",
            "roller_count": self.roller_count,
            "roller_radius_mm": self.roller_radius_mm,
            "centre_distance_mm": self.centre_distance_mm,
            "centre_angle_deg": math.degrees(self.centre_angle_rad),
            "centres_mm": self.centres.tolist(),
            "outer_radius_mm": self.outer_radius_mm,
        }


def _rollers_from_gearset(gearset, r_bore: float, w0: float) -> RollerGenerator:
    gear, wg = gearset.gear, gearset.wave_generator
    if gear.waves != 2:
        raise WaveGenError(
            f"gear.waves = {gear.waves}: the roller generator is placed for 2 waves only (rollers about the two "
            "ends of the major axis)"
        )
    radius, count = float(wg.roller_radius_mm), int(wg.roller_count)
    name = "wave_generator.roller_radius_mm"
    if count == 2:
        theta = 0.0
    else:
        angle_deg = wg.roller_angle_deg
        if angle_deg is None or not 0.0 < angle_deg < 45.0:
            raise WaveGenError(f"wave_generator.roller_angle_deg = {angle_deg!r} deg: must be in (0, 45)")
        theta = math.radians(angle_deg)

    def curve(t):  # ring theory's bore r_bore + w0 cos 2θ: r, r′, r″
        return r_bore + w0 * np.cos(2.0 * t), -2.0 * w0 * np.sin(2.0 * t), -4.0 * w0 * np.cos(2.0 * t)

    r, r1, r2 = (float(x) for x in curve(theta))
    e_r = np.array([math.sin(theta), math.cos(theta)])
    e_t = np.array([math.cos(theta), -math.sin(theta)])
    touch = r * e_r
    normal = (r * e_r - r1 * e_t) / math.hypot(r, r1)
    if count == 2:
        touch, normal = np.array([0.0, r]), np.array([0.0, 1.0])  # exact on the axis
    centre = touch - radius * normal
    # no overlap: the nearest centres are mirror images across the minor axis (two rollers)
    # or the major axis (four): c_y ≥ R, resp. c_x ≥ R, i.e. R ≤ touch_i / (1 + n_i)
    axis = 1 if count == 2 else 0
    where = (f"on the major axis at r_bore + w0 = {r:.6g} mm" if count == 2
             else f"at θ = ±{math.degrees(theta):g}° about the major axis")
    largest = touch[axis] / (1.0 + normal[axis])
    if not radius <= largest:
        raise WaveGenError(
            f"{name} = {radius:g} mm: must be ≤ {largest:.6g} mm for roller_count = {count} (the rollers, touching "
            f"the deformed bore {where}, would overlap)"
        )
    kappa = (r * r + 2.0 * r1 * r1 - r * r2) / (r * r + r1 * r1) ** 1.5
    if not 1.0 / radius >= kappa:
        raise WaveGenError(
            f"{name} = {radius:g} mm: must be ≤ {1.0 / kappa:.6g} mm, the radius of curvature of the deformed "
            f"bore r_bore + w0 cos 2θ where the rollers touch it (θ = {math.degrees(theta):g}°)"
        )
    rollers = RollerGenerator(
        radius,
        float(np.hypot(*centre)),
        roller_count=count,
        centre_angle_rad=float(math.atan2(centre[0], centre[1])),
    )
    # and inside the deformed bore everywhere, not only near the touching point
    samples = np.linspace(0.0, 0.5 * math.pi, 4097)
    excess = rollers.radius(samples) - curve(samples)[0]
    worst = int(np.argmax(excess))
    if excess[worst] > 1e-9 * r_bore:
        raise WaveGenError(
            f"{name} = {radius:g} mm: the rollers do not fit inside the deformed bore r_bore + w0 cos 2θ (they "
            f"cross it by {excess[worst]:.3g} mm at θ = {math.degrees(samples[worst]):.4g}°)"
        )
    return rollers


def from_gearset(gearset) -> EllipticalCam | CosineCam | RollerGenerator:
    """The contour that pushes the rim's bore (r_bore = r_m − δ/2) out by w0 on the major axis.

    * ``elliptical_cam``: semi-axes chosen so that the offset contour's major radius is
      r_bore + w0 and its perimeter equals the bore's, 2π r_bore — an *inextensible bore*
      (the bore is wrapped without stretching). Bearing thickness h from
      ``wave_generator.bearing_thickness_mm`` (0 if not given); a = r_bore + w0 − h and b
      solves 4aE(1 − b²/a²) + 2πh = 2π r_bore.
    * ``cosine_cam``: r0 = r_bore, w0 as given (its perimeter exceeds 2π r_bore by O(w0²)).
    * ``rollers`` (U = 2 only), radius R = ``roller_radius_mm``: every roller is inscribed in
      ring theory's deformed bore r_b(θ) = r_bore + w0 cos 2θ, *tangent* to it at its
      touching angle: the centre lies at distance R along the curve's inward normal from
      r_b(θ_r)·e_r. Two rollers touch at θ_r = 0 and π (centre distance r_bore + w0 − R,
      the bore pushed out by w0 on the major axis); four rollers touch at ±θ_r about each
      end of the major axis, θ_r = ``roller_angle_deg`` (default 30°), and leave the major
      axis free. Tangency rather than "the roller's radially outermost point on the curve
      at θ_r": at θ_r ≠ 0 the curve is inclined to e_θ (r′ = −2w0 sin 2θ_r), so a roller
      centred on the ray θ_r would cross the curve (≈ r′²R/(2 d r) ≈ 2 µm for the default
      gear set, R = 10 mm); the tangent roller's centre is at a slightly smaller polar
      angle (≈ 0.26° there). Raises :class:`WaveGenError` naming
      ``wave_generator.roller_radius_mm`` if the rollers would overlap or do not fit
      inside r_b(θ) (curvature at the touching point, then a check on 4097 angles).
    """
    gear, wg = gearset.gear, gearset.wave_generator
    r_bore = gear.neutral_radius_mm - 0.5 * gear.rim_thickness_mm
    w0 = gearset.deflection_mm
    if wg.contour == "cosine_cam":
        return CosineCam(r_bore, w0, waves=gear.waves)
    if wg.contour == "rollers":
        return _rollers_from_gearset(gearset, r_bore, w0)
    if wg.contour != "elliptical_cam":
        raise WaveGenError(
            f"wave_generator.contour = {wg.contour!r}: must be one of 'elliptical_cam', 'cosine_cam', 'rollers'"
        )
    if gear.waves != 2:
        raise WaveGenError(f"gear.waves = {gear.waves}: an elliptical cam makes exactly 2 waves")
    h = float(wg.bearing_thickness_mm or 0.0)
    a = r_bore + w0 - h
    if not a > 0.0:
        raise WaveGenError(
            f"wave_generator.bearing_thickness_mm = {h} mm: must be < r_bore + w0 = {r_bore + w0:.6g} mm"
        )
    target = 2.0 * math.pi * (r_bore - h)  # perimeter of the ellipse itself

    def excess(b):
        return ellipse_perimeter(a, b) - target

    if not (excess(1e-9 * a) < 0.0 < excess(a)):
        raise WaveGenError(
            f"deflection_mm = {w0} mm: no ellipse with major radius r_bore + w0 = {r_bore + w0:.6g} mm has the "
            f"bore's perimeter 2π·{r_bore:.6g} mm"
        )
    b = _brentq(excess, 1e-9 * a, a, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
    return EllipticalCam(a, b, bearing_thickness_mm=h)
