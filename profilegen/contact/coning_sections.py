"""The cup's deformation at axial sections of the face, as deformations the kinematics takes.

The face stage and the torsional curve across the face (:mod:`profilegen.contact.face_curve`)
place the FS tooth at several axial positions z of the face. Each position's deformation is one
of these sections:

* :func:`cup_sections` — the 3D cup's own (a :class:`~profilegen.rim.cup.fourier.CupDeformation`
  or the :class:`~profilegen.rim.cup.contact.CupContact` of :func:`~profilegen.rim.cup.contact.press_cup`),
  its even harmonics projected exactly from ω(φ, z), υ(φ, z);
* :func:`semi_membrane_sections` — the analytic check (docs/theory/cup.md): the wall inextensible
  along its generators and in shear, ω(φ, z) = ω(φ, z_ref)·z/z_ref and υ likewise, z from the
  cup bottom.

>>> import numpy as np
>>> from profilegen.geometry.deformation import ring_theory
>>> near, far = semi_membrane_sections(ring_theory(0.5), [30.0, 60.0], reference_z_mm=60.0)
>>> omega_near, _ = near.evaluate(np.array([0.0]), order=0)  # ω at the major axis, half way down the cup
>>> omega_far, _ = far.evaluate(np.array([0.0]), order=0)
>>> float(omega_near[0, 0]), float(omega_far[0, 0])
(0.25, 0.5)
"""

from __future__ import annotations

import math

import numpy as np

from .. import checks
from ..errors import ProfilegenError
from ..geometry.deformation import ScaledDeformation

__all__ = ["SectionError", "cup_sections", "semi_membrane_sections"]


class SectionError(ProfilegenError, ValueError):
    """Bad input to a face section; names the parameter, its value, unit and range."""


def semi_membrane_sections(deformation, z_mm, reference_z_mm: float) -> list:
    """Semi-membrane coning: the deformation at z is the reference section's times z/z_ref
    (z from the cup bottom's mid-plane). Returns one deformation per z (with ``evaluate``)."""
    zr = checks.positive("reference_z_mm", reference_z_mm, error=SectionError)
    z = np.atleast_1d(np.asarray(checks.finite("z_mm", z_mm, "mm", error=SectionError), dtype=float))
    if np.any(z <= 0.0):
        raise SectionError(f"z_mm = {float(z[z <= 0.0][0])!r} mm: must be > 0 (from the cup bottom)")
    return [ScaledDeformation(deformation, float(zi / zr)) for zi in z]


def cup_sections(cup, z_mm) -> list:
    """The 3D cup's sections (a :class:`~profilegen.rim.cup.fourier.CupDeformation`, or the
    :class:`~profilegen.rim.cup.contact.CupContact` of :func:`press_cup`) at ``z_mm``, each as a
    :class:`~profilegen.geometry.deformation.HarmonicDeformation` (mean, cos 2kφ, sin 2kφ) on the
    neutral surface: its even harmonics projected exactly from ω(φ, z), υ(φ, z)."""
    from ..geometry.deformation import HarmonicDeformation

    deformation = getattr(cup, "deformation", cup)
    if not hasattr(deformation, "omega") or not hasattr(deformation, "orders"):
        raise SectionError(f"cup: must be a CupDeformation or CupContact (press_cup), got {type(cup).__name__}")
    orders = np.asarray(deformation.orders, dtype=int)
    if np.any(orders % 2):
        raise SectionError("cup: odd harmonics present; the sections need a two-wave (even) deformation")
    k = orders // 2  # harmonic of cos 2kφ
    kmax = int(k.max())
    m = 4 * (kmax + 1)
    phi = math.pi * np.arange(m) / m  # 2φ covers a full period: exact DFT for 2k < 2m
    z = np.atleast_1d(np.asarray(z_mm, dtype=float))
    out = []
    for zi in z:
        w = deformation.omega(phi, zi)
        u = deformation.upsilon(phi, zi)
        kk = np.arange(1, kmax + 1)
        a = 2.0 / m * (np.cos(2.0 * np.outer(kk, phi)) @ w)
        b = 2.0 / m * (np.sin(2.0 * np.outer(kk, phi)) @ u)
        out.append(HarmonicDeformation(2, a, b, float(w.mean()), tier="cup3d", source=f"cup section z = {zi:g} mm"))
    return out
