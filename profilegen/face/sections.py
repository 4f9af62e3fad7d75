"""One axial section of the tooth ring: its deformation, motion and envelope, and the signed gap
between a CS outline and its swept region.

A 3D cup deformation gives ω(φ, z), υ(φ, z) (:class:`profilegen.rim.cup.CupDeformation`, or
anything with the same ``omega`` / ``upsilon`` methods and the tooth ring's span). At each
section z the samples over one wave period are fitted with the kinematics' integer-harmonic
Fourier model (:func:`profilegen.geometry.series.fit_fourier`), the FS tooth is moved by that section's
:class:`~profilegen.geometry.kinematics.HarmonicDriveMotion`, and its classified envelope is traced
(:func:`profilegen.profile.envelope.envelope_of`): each section's own swept region.

The signed gap (:func:`signed_gap`) of a CS point to a section's swept region: its distance to
the section's swept boundary (``Envelope.flank["boundary"]``), positive outside the swept region
(a gap: the CS has material where that section's tooth never goes), negative inside
(interference).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
import shapely

from .. import checks
from ..errors import ProfilegenError
from ..results import readonly
from ..stagecache import reuse

if TYPE_CHECKING:  # pragma: no cover
    from ..profile.envelope import Envelope
    from ..geometry.kinematics import HarmonicDriveMotion
    from ..geometry.series import DeformationFit
    from ..geometry.teeth import ToothProfile

__all__ = ["FaceError", "FaceSection", "cup_deformation", "ring_span", "section_fit", "signed_gap",
           "solve_section", "SweptRegion"]


class FaceError(ProfilegenError, ValueError):
    """Bad face-width input; the message names the field, its value, unit and allowed range."""


_number = partial(checks.number, error=FaceError)


def ring_span(deformation) -> tuple[float, float]:
    """(z at the diaphragm end, z at the open end) of the tooth ring (mm): the deformation's
    ``ring_span_mm``, or its ``geometry.ring_span_mm`` (a :class:`~profilegen.rim.cup.CupDeformation`)."""
    span = getattr(deformation, "ring_span_mm", None)
    if span is None:
        span = getattr(getattr(deformation, "geometry", None), "ring_span_mm", None)
    if span is None:
        raise FaceError("deformation: it has no tooth-ring span (ring_span_mm or geometry.ring_span_mm); "
                        "a 3D cup deformation is needed")
    lo, hi = (float(v) for v in span)
    if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
        raise FaceError(f"deformation.ring_span_mm = ({lo!r}, {hi!r}) mm: must be an interval lo < hi")
    return lo, hi


def cup_deformation(obj):
    """The 3D deformation inside ``obj``: itself when it has ω(φ, z), else its ``deformation``
    (CupContact) or its 3D cup field (the rim stage's cup3d tier)."""
    seen = 0
    while obj is not None and seen < 4:
        if callable(getattr(obj, "omega", None)) and callable(getattr(obj, "upsilon", None)):
            try:
                ring_span(obj)
                return obj
            except FaceError:
                pass
        nxt = None
        for name in ("cup", "cup3d", "contact", "deformation"):
            if getattr(obj, name, None) is not None:
                nxt = getattr(obj, name)
                break
        obj, seen = nxt, seen + 1
    raise FaceError("deformation: not a 3D cup deformation (ω(φ, z), υ(φ, z) and the tooth ring's span); run the "
                    "rim stage's cup3d tier or profilegen.rim.cup.press_cup")


def section_fit(deformation, z_mm: float, *, waves: int = 2, max_order: int = 16):
    """The section at ``z_mm`` as the kinematics' Fourier model: ω, υ sampled on one wave
    period (8·max_order + 8 points ≥ 181), :func:`profilegen.geometry.series.fit_fourier`."""
    from ..geometry import series

    samples = max(181, 8 * max_order + 8)
    period = 2.0 * math.pi / waves
    phi = period * np.arange(samples) / samples
    omega = np.asarray(deformation.omega(phi, z_mm), dtype=float)
    upsilon = np.asarray(deformation.upsilon(phi, z_mm), dtype=float)
    tier = "cup3d" if "cup3d" in series.TIERS else "design"
    fit = series.fit_fourier(phi, omega, upsilon, waves=waves, max_order=max_order, tier=tier)
    return fit, phi, omega, upsilon


@dataclass(frozen=True, slots=True, eq=False)
class FaceSection:
    """One axial section: ``z_mm``; ω on the major and minor axes and the largest |υ| of its
    samples (mm); the Fourier ``fit``, the ``motion`` and the ``envelope`` of the FS ``tooth``
    in it (the tooth modified for this section when a modification is applied)."""

    z_mm: float
    omega_major_mm: float
    omega_minor_mm: float
    upsilon_max_mm: float
    fit: DeformationFit
    motion: HarmonicDriveMotion
    envelope: Envelope
    tooth: ToothProfile
    time_s: float

    @property
    def boundary(self) -> np.ndarray:
        """The section's swept boundary (CS frame, mm)."""
        return self.envelope.flank["boundary"]


def solve_section(gearset, deformation, z_mm: float, tooth, *, chord_tol_mm: float, n_t: int, n_phi: int,
                  fit=None) -> FaceSection:
    """Fit, motion and envelope of ``tooth`` at section ``z_mm`` (see the module docstring);
    ``fit`` reuses a section's Fourier model (a modified tooth at the same section)."""
    from ..profile.envelope import envelope_of
    from ..geometry.kinematics import HarmonicDriveMotion

    t0 = time.perf_counter()
    g = gearset.gear
    period = 2.0 * math.pi / g.waves
    phi = period * np.arange(360) / 360
    upsilon = np.asarray(deformation.upsilon(phi, z_mm), dtype=float)
    if fit is None:  # it reads the rim's deformation, not the tooth: a tooth change in an engine keeps it
        fit = reuse("face_section_fit", lambda: section_fit(deformation, z_mm, waves=g.waves)[0], gearset=gearset,
                    sections=(), key=(float(z_mm), int(g.waves)), owners=(deformation,))
    motion = HarmonicDriveMotion.from_gearset(gearset, fit)
    env = envelope_of(tooth, motion, cs_teeth=g.circular_spline_teeth, waves=g.waves, chord_tol_mm=chord_tol_mm,
                      n_t=n_t, n_phi=n_phi)
    minor = period / 2.0  # the minor axis, φ = π/U
    return FaceSection(float(z_mm), float(deformation.omega(0.0, z_mm)), float(deformation.omega(minor, z_mm)),
                       float(np.max(np.abs(upsilon))), fit, motion, env, tooth, time.perf_counter() - t0)


class SweptRegion:
    """A section's swept region, bounded by its swept boundary (one CS space's, CS frame): the
    polygon of the boundary closed through the gear centre (the boundary spans one space, so the
    closure lies far below every CS point) and an exact distance to the boundary, built once for
    many queries."""

    def __init__(self, boundary: np.ndarray):
        from ..profile.gearform import PolylineDistance

        b = np.asarray(boundary, dtype=float)
        self._distance = PolylineDistance(b)
        self._region = shapely.Polygon(np.vstack([b, [[0.0, 0.0]]]))
        shapely.prepare(self._region)

    def signed_gap(self, points: np.ndarray) -> np.ndarray:
        """Signed distance (mm) of CS points: + outside the region (gap), − inside (interference)."""
        p = np.asarray(points, dtype=float)
        dist = self._distance.distance(p)
        inside = shapely.contains_xy(self._region, p[:, 0], p[:, 1])
        return readonly(np.where(inside, -dist, dist))


def signed_gap(points: np.ndarray, boundary: np.ndarray) -> np.ndarray:
    """Signed distance (mm) of CS points to the swept region bounded by ``boundary``
    (:class:`SweptRegion`): + outside (gap), − inside (interference)."""
    return SweptRegion(boundary).signed_gap(points)
