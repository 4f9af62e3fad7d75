"""Deformation of the flexspline neutral line: ω(φ), υ(φ) and their φ-derivatives.

φ is the angle from the wave-generator major axis to the flexspline tooth's
*undeformed* position, in the wave-generator frame; ω is the radial
displacement of the neutral line (outward positive), υ the tangential one
(positive toward increasing φ). Every deformation model — ring theory here,
the FEM rim and the fitted series later — exposes the same method::

    omega, upsilon = model.evaluate(phi, order=3)   # each (order + 1, n): f, f', f'', f'''

The integer-harmonic form ``ω = Σ a_k cos(kUφ)``, ``υ = Σ b_k sin(kUφ)`` is the
single source of truth for the analytic derivatives; ring theory is its
one-harmonic case ``a_1 = w0``, ``b_1 = −w0/U`` (inextensible neutral line:
``υ′ = −ω``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

import numpy as np

from ..errors import GearSetError
from ..results import readonly as _readonly

if TYPE_CHECKING:  # pragma: no cover
    from numpy.typing import ArrayLike

__all__ = ["Deformation", "HarmonicDeformation", "ScaledDeformation", "ring_theory"]


class Deformation(Protocol):
    """What the kinematics needs from any deformation model."""

    @property
    def tier(self) -> str: ...

    @property
    def waves(self) -> int: ...

    def evaluate(self, phi: np.ndarray, order: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """ω and υ with derivatives 0..order at φ (rad), each (order + 1, n), in mm."""
        ...


def _check_waves(waves) -> None:
    if isinstance(waves, bool) or not isinstance(waves, (int, np.integer)) or waves < 1:
        raise GearSetError(f"gear.waves = {waves!r}: must be a whole number ≥ 1")



@dataclass(frozen=True, slots=True, eq=False)
class HarmonicDeformation:
    """ω = Σ a_k cos(k U φ) + a_0,  υ = Σ b_k sin(k U φ)  (k = 1..n, mm).

    Integer harmonics of the wave count U keep ω and υ exactly periodic and
    symmetric (ω even, υ odd about the major axis).
    """

    waves: int
    cos_mm: np.ndarray  # a_1..a_n
    sin_mm: np.ndarray  # b_1..b_n
    mean_mm: float = 0.0
    tier: str = "sketch"
    source: str = "ring theory"
    diagnostics: dict = field(default_factory=dict)

    def __post_init__(self):
        object.__setattr__(self, "cos_mm", _readonly(self.cos_mm))
        object.__setattr__(self, "sin_mm", _readonly(self.sin_mm))
        _check_waves(self.waves)
        if self.cos_mm.shape != self.sin_mm.shape or self.cos_mm.ndim != 1:
            raise GearSetError(
                f"cos_mm / sin_mm: the radial and tangential coefficient lists must be 1-D and equally long, "
                f"got shapes {self.cos_mm.shape} and {self.sin_mm.shape}"
            )
        if not (np.all(np.isfinite(self.cos_mm)) and np.all(np.isfinite(self.sin_mm))):
            raise GearSetError("cos_mm / sin_mm: coefficients must be finite (mm)")

    @property
    def symmetric(self) -> bool:
        """ω even and υ odd in φ (always, for cos/sin harmonics)."""
        return True

    @property
    def deflection_mm(self) -> float:
        """Radial displacement on the major axis, ω(0) (mm)."""
        return float(self.mean_mm + self.cos_mm.sum())

    def evaluate(self, phi: ArrayLike, order: int = 3) -> tuple[np.ndarray, np.ndarray]:
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        freq = self.waves * np.arange(1, self.cos_mm.size + 1)  # (n_h,)
        arg = np.multiply.outer(phi, freq)  # (n, n_h)
        c, s = np.cos(arg), np.sin(arg)
        omega = np.empty((order + 1, phi.size))
        upsilon = np.empty((order + 1, phi.size))
        for j in range(order + 1):
            scale = freq**j
            # d^j/dφ^j cos = Re(i^j e^{ikφ})-pattern: cos, -sin, -cos, sin, ...
            cj, sj = [(c, s), (-s, c), (-c, -s), (s, -c)][j % 4]
            omega[j] = cj @ (self.cos_mm * scale)
            upsilon[j] = sj @ (self.sin_mm * scale)
        omega[0] += self.mean_mm
        return omega, upsilon

    def to_dict(self) -> dict:
        return {
            "tier": self.tier,
            "source": self.source,
            "waves": self.waves,
            "mean_mm": self.mean_mm,
            "cos_mm": self.cos_mm.tolist(),
            "sin_mm": self.sin_mm.tolist(),
        }


@dataclass(frozen=True, slots=True, eq=False)
class ScaledDeformation:
    """A deformation with ω and υ (and their φ-derivatives) times ``factor``: the same wave
    generator at another deflection, or a cup section at another axial position."""

    base: Deformation
    factor: float

    @property
    def symmetric(self) -> bool:
        return bool(getattr(self.base, "symmetric", False))

    def evaluate(self, phi, order: int = 3):
        omega, upsilon = self.base.evaluate(phi, order=order)
        return self.factor * np.asarray(omega), self.factor * np.asarray(upsilon)


def ring_theory(deflection_mm: float, waves: int = 2) -> HarmonicDeformation:
    """Classical inextensible ring: ω = w0 cos Uφ, υ = −(w0/U) sin Uφ (the `sketch` tier)."""
    if not (np.isfinite(deflection_mm) and deflection_mm > 0):
        raise GearSetError(f"wave_generator.deflection_mm = {deflection_mm} mm: must be > 0")
    _check_waves(waves)
    return HarmonicDeformation(
        waves=waves,
        cos_mm=np.array([deflection_mm]),
        sin_mm=np.array([-deflection_mm / waves]),
        tier="sketch",
        source="ring theory (w0 cos Uφ, −w0/U sin Uφ)",
    )
