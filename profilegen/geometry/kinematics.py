"""Motion of the flexspline (FS) tooth frame in the circular-spline (CS) frame.

Frames and signs (one place, used everywhere):

* CS frame: origin at the gear centre, y along the symmetry line of the CS tooth
  space that the FS tooth with φ = 0 sits in; polar angles are measured from +y
  toward +x, so a point at radius r and angle θ is ``(r sin θ, r cos θ)`` and the
  unit vectors are ``e_r(θ) = (sin θ, cos θ)``, ``e_t(θ) = (cos θ, −sin θ)``.
* Tooth frame: origin on the deformed neutral line at the tooth axis, y_R along
  the outward normal of the deformed neutral line, x_R along increasing φ. A
  tooth point p maps to ``Q = R(Φ) p + O`` with ``R(Φ) p = p_x e_t(Φ) + p_y e_r(Φ)``
  — the seed's M_RG.

With the CS fixed, the wave generator turned by ψ and the FS carrier by
−ψU/z1, the tooth with undeformed carrier angle 0 has φ = −(z2/z1)ψ and
undeformed polar angle β = −ψU/z1 = (U/z2)·φ, not (U/z1)·φ (docs/theory/envelope.md, "Kinematics").
The exact displacement geometry is::

    O = (r_m + ω) e_r(β) + υ e_t(β)
    ρ = |(r_m + ω, υ)|,   γ = β + atan2(υ, r_m + ω)
    Φ = β + atan2(υ − ω′, r_m + ω + υ′)      (normal of the deformed neutral line)

Everything the envelope needs is a :class:`Pose` — O, Φ and their first two
φ-derivatives — so any motion (the harmonic drive here, a rack in generating
motion in the tests) plugs into the same envelope code.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from .deformation import Deformation

if TYPE_CHECKING:  # pragma: no cover
    from numpy.typing import ArrayLike

__all__ = ["Pose", "Motion", "HarmonicDriveMotion", "RackMotion", "to_tooth", "turn", "unit_radial",
           "unit_tangential"]


def turn(points, angle: float | np.ndarray) -> np.ndarray:
    """Points (..., 2) turned about the gear centre by ``angle`` (rad) in our sense, +y toward +x:
    one angle, or one per point (broadcast against the points' leading shape)."""
    p = np.asarray(points, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([p[..., 0] * c + p[..., 1] * s, -p[..., 0] * s + p[..., 1] * c], -1)


def to_tooth(points, origin: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """CS-frame points (n, 2) — one per frame — to the tooth frames at ``origin`` (n, 2) and ``angle``
    (n,) (:meth:`Pose.to_tooth`; :meth:`HarmonicDriveMotion.frame` gives the two alone)."""
    d = np.asarray(points, dtype=float) - origin
    c, s = np.cos(angle), np.sin(angle)
    out = np.empty(d.shape)
    out[..., 0] = d[..., 0] * c - d[..., 1] * s
    out[..., 1] = d[..., 0] * s + d[..., 1] * c
    return out


def _placed(beta, sb, cb, rm, w, u, w1, u1) -> tuple[np.ndarray, np.ndarray]:
    """The tooth frame's origin O = (r_m + ω) e_r(β) + υ e_t(β) and angle Φ = β + atan2(υ − ω′,
    r_m + ω + υ′) (the one arithmetic of :meth:`HarmonicDriveMotion.pose` and ``frame``)."""
    origin = np.empty((np.size(beta), 2))
    a0 = rm + w
    origin[:, 0] = a0 * sb + u * cb
    origin[:, 1] = a0 * cb - u * sb
    return origin, beta + np.arctan2(u - w1, rm + w + u1)


def unit_radial(theta):
    """e_r(θ) = (sin θ, cos θ), shape (n, 2)."""
    theta = np.asarray(theta, dtype=float)
    return np.stack([np.sin(theta), np.cos(theta)], axis=-1)


def unit_tangential(theta):
    """e_t(θ) = (cos θ, −sin θ), shape (n, 2)."""
    theta = np.asarray(theta, dtype=float)
    return np.stack([np.cos(theta), -np.sin(theta)], axis=-1)


@dataclass(frozen=True, slots=True, eq=False)
class Pose:
    """Tooth-frame pose at each φ: origin O (n, 2) mm, angle Φ (n,) rad, and φ-derivatives."""

    phi: np.ndarray
    origin: np.ndarray
    origin_d1: np.ndarray
    origin_d2: np.ndarray
    angle: np.ndarray
    angle_d1: np.ndarray
    angle_d2: np.ndarray

    @property
    def cos_sin(self) -> tuple[np.ndarray, np.ndarray]:
        """cos Φ and sin Φ (n,)."""
        return np.cos(self.angle), np.sin(self.angle)

    def to_cs(self, points: np.ndarray) -> np.ndarray:
        """Tooth-frame points (n, 2) — one per pose — to the CS frame: p_x e_t(Φ) + p_y e_r(Φ) + O."""
        p = np.asarray(points, dtype=float)
        c, s = self.cos_sin
        out = np.empty(np.broadcast_shapes(p.shape, self.origin.shape))
        out[..., 0] = p[..., 0] * c + p[..., 1] * s + self.origin[..., 0]
        out[..., 1] = p[..., 1] * c - p[..., 0] * s + self.origin[..., 1]
        return out

    def to_tooth(self, points: np.ndarray) -> np.ndarray:
        """CS-frame points (n, 2) — one per pose — to the tooth frame (inverse of ``to_cs``)."""
        return to_tooth(points, self.origin, self.angle)

    def meshing_coefficients(self) -> tuple[np.ndarray, np.ndarray]:
        """``a`` and ``∂a/∂φ`` (each (n, 3)) such that the meshing function is

        ``f(t, φ) = a(φ) · [p·p′, p′_y, p′_x](t)``  (f = ∂Q/∂φ × ∂Q/∂t, a 2D cross product),

        i.e. ``f = Φ′ (p·p′) + v_x p′_y − v_y p′_x`` with v = Rᵀ O′ the origin's
        velocity in the tooth frame. The separation into φ-terms and t-terms is
        what makes the envelope's grid search one matrix product.
        """
        c, s = self.cos_sin
        o1x, o1y = self.origin_d1[:, 0], self.origin_d1[:, 1]
        o2x, o2y = self.origin_d2[:, 0], self.origin_d2[:, 1]
        # components along e_t(Φ) = (c, −s) and e_r(Φ) = (s, c)
        vx, vy = o1x * c - o1y * s, o1x * s + o1y * c
        # v′ = Φ′ Kᵀ v + Rᵀ O″,  Kᵀ v = (−v_y, v_x)
        vx_d = -self.angle_d1 * vy + (o2x * c - o2y * s)
        vy_d = self.angle_d1 * vx + (o2x * s + o2y * c)
        a = np.empty((c.size, 3))
        a_d = np.empty((c.size, 3))
        a[:, 0], a[:, 1], a[:, 2] = self.angle_d1, vx, -vy
        a_d[:, 0], a_d[:, 1], a_d[:, 2] = self.angle_d2, vx_d, -vy_d
        return a, a_d


class Motion(Protocol):
    """Anything that gives the tooth-frame pose at an array of φ, and its origin and angle alone."""

    def pose(self, phi) -> Pose: ...

    def frame(self, phi) -> tuple[np.ndarray, np.ndarray]: ...


@dataclass(frozen=True, slots=True, eq=False)
class HarmonicDriveMotion:
    """FS tooth in the fixed CS: the exact displacement geometry (docs/theory/envelope.md, "Kinematics")."""

    deformation: Deformation
    neutral_radius_mm: float
    waves: int
    cs_teeth: int

    @classmethod
    def from_gearset(cls, gearset: Any, deformation: Deformation | None = None) -> "HarmonicDriveMotion":
        """The motion of a gear set's FS tooth; ring theory unless a deformation is given. (``gearset``:
        a :class:`~profilegen.gearset.GearSet`, typed Any: the gear-set reader imports this module
        through the budget, so naming GearSet here would close an import cycle.)"""
        g = gearset.gear
        if deformation is None:
            from .deformation import ring_theory

            deformation = ring_theory(gearset.deflection_mm, g.waves)
        return cls(deformation, g.neutral_radius_mm, g.waves, g.circular_spline_teeth)

    @property
    def symmetric(self) -> bool:
        """True when ω is even and υ odd in φ, so the motion is mirror-symmetric about φ = 0."""
        return bool(getattr(self.deformation, "symmetric", False))

    @property
    def beta_rate(self) -> float:
        """dβ/dφ = U/z2."""
        return self.waves / self.cs_teeth

    def pose(self, phi: ArrayLike) -> Pose:
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        (w, w1, w2, w3), (u, u1, u2, u3) = self.deformation.evaluate(phi, order=3)
        k, rm = self.beta_rate, self.neutral_radius_mm
        beta = k * phi
        sb, cb = np.sin(beta), np.cos(beta)  # e_r(β) = (sb, cb), e_t(β) = (cb, −sb)
        # origin O = (r_m + ω) e_r + υ e_t and its φ-derivatives (de_r/dβ = e_t, de_t/dβ = −e_r)
        a1, b1 = w1 - k * u, u1 + k * (rm + w)
        a2, b2 = w2 - k * u1 - k * b1, u2 + k * w1 + k * a1

        def combine(ra, ta):
            out = np.empty((phi.size, 2))
            out[:, 0] = ra * sb + ta * cb
            out[:, 1] = ra * cb - ta * sb
            return out

        # Φ = β + atan2(N, D),  N = υ − ω′,  D = r_m + ω + υ′
        n0, n1, n2 = u - w1, u1 - w2, u2 - w3
        d0, d1, d2 = rm + w + u1, w1 + u2, w2 + u3
        q = n0 * n0 + d0 * d0
        num = n1 * d0 - n0 * d1  # q · dΦ_tilt/dφ
        tilt_d1 = num / q
        tilt_d2 = (n2 * d0 - n0 * d2) / q - num * 2.0 * (n0 * n1 + d0 * d1) / q**2
        origin, angle = _placed(beta, sb, cb, rm, w, u, w1, u1)
        return Pose(
            phi=phi,
            origin=origin,
            origin_d1=combine(a1, b1),
            origin_d2=combine(a2, b2),
            angle=angle,
            angle_d1=k + tilt_d1,
            angle_d2=tilt_d2,
        )

    def frame(self, phi: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """The tooth frame's origin O (n, 2) and angle Φ (n,) at φ — :meth:`pose` without the
        φ-derivatives (the same numbers: the deformation to first order only, half the work; the
        swept-region depth's refinement asks for thousands of single frames)."""
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        (w, w1), (u, u1) = self.deformation.evaluate(phi, order=1)
        k, rm = self.beta_rate, self.neutral_radius_mm
        beta = k * phi
        sb, cb = np.sin(beta), np.cos(beta)
        return _placed(beta, sb, cb, rm, w, u, w1, u1)

    def neutral_point(self, phi: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Polar radius ρ and angle γ of the tooth-frame origin (the seed's ρ, γ)."""
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        (w,), (u,) = self.deformation.evaluate(phi, order=0)
        return np.hypot(self.neutral_radius_mm + w, u), self.beta_rate * phi + np.arctan2(
            u, self.neutral_radius_mm + w
        )


@dataclass(frozen=True, slots=True, eq=False)
class RackMotion:
    """A rack generating an external gear of pitch radius r (gear frame fixed).

    The gear turns by φ (clockwise, our angle sense) while the rack's pitch line,
    tangent to the pitch circle at (0, r), moves by r·φ along +x. In the gear
    frame the rack frame turns by −φ: Φ = −φ, O = R(−φ)·(r φ, r). Its envelope of
    a straight flank at pressure angle α is the involute of base radius r cos α.
    """

    pitch_radius_mm: float

    def pose(self, phi: ArrayLike) -> Pose:
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        r = self.pitch_radius_mm
        # O = (rφ) e_t(−φ) + r e_r(−φ);  d/dφ e_t(−φ) = +e_r(−φ), d/dφ e_r(−φ) = −e_t(−φ)
        er, et = unit_radial(-phi), unit_tangential(-phi)
        x, ones = (r * phi)[:, None], np.ones_like(phi)
        origin = x * et + r * er
        origin_d1 = x * er  # r e_t + x e_r − r e_t
        origin_d2 = r * er - x * et
        return Pose(
            phi=phi,
            origin=origin,
            origin_d1=origin_d1,
            origin_d2=origin_d2,
            angle=-phi,
            angle_d1=-ones,
            angle_d2=0 * ones,
        )

    def frame(self, phi: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """The rack frame's origin and angle at φ (those of :meth:`pose`)."""
        pose = self.pose(phi)
        return pose.origin, pose.angle
