"""The clearance of one section's FS teeth against the one CS outline: the map c(φ), its refined
minimum, the backlash over the design section's engaged poses (see :mod:`profilegen.face.stage`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .sections import FaceSection, signed_gap

__all__ = ["ENGAGED_MM", "MAP_SAMPLES", "SectionClearance", "engaged_zone", "face_map",
           "section_clearance"]

#: FS poses of each section's clearance map over one pass; the minimum is refined by the parabola
#: through the sampled minimum and its neighbours (a second map around it cost as much as the
#: first: the map's set-up, not its poses, is its time).
MAP_SAMPLES = 181
#: The design section's engaged poses: where its own clearance map is within this of contact (mm);
#: the coarse envelope's polyline CS touches its own tooth within ~0.1 µm there.
ENGAGED_MM = 1e-3


@dataclass(frozen=True, slots=True, eq=False)
class SectionClearance:
    """One section against the one CS outline (mm): ``min_clearance_mm`` (clearance map, < 0
    interference) at ``at_phi_rad``; ``max_backlash_mm`` (the largest clearance over the design
    section's engaged poses); ``min_gap_mm`` (smallest gap of the whole CS space to the section's
    swept boundary; None for a modified section, whose envelope is not traced)."""

    z_mm: float
    omega_major_mm: float
    omega_minor_mm: float
    upsilon_max_mm: float
    min_clearance_mm: float
    at_phi_rad: float
    max_backlash_mm: float
    min_gap_mm: float | None
    thickness_change_mm: float = 0.0

    def to_dict(self) -> dict:
        return {"z_mm": self.z_mm, "omega_major_mm": self.omega_major_mm, "omega_minor_mm": self.omega_minor_mm,
                "upsilon_max_mm": self.upsilon_max_mm, "min_clearance_mm": self.min_clearance_mm,
                "max_backlash_mm": self.max_backlash_mm, "at_phi_deg": math.degrees(self.at_phi_rad),
                "min_gap_mm": self.min_gap_mm, "thickness_change_mm": self.thickness_change_mm}


def section_map(form, section: FaceSection, samples: int, phi_range=None):
    from ..profile.gearform import clearance_map

    waves = section.motion.waves
    phi_range = (-math.pi / waves, math.pi / waves) if phi_range is None else phi_range
    # few_first=False: the maps' poses nearly all need the 4 × candidates nearest pairs (3426 of 3439 on
    # the default set's design-scene face stage), so the first pass of fewer pairs was spent in vain;
    # the same maps, bit for bit (tests/benchmarks/face_identity.py)
    return clearance_map(form, section.tooth, section.motion, phi_range=phi_range, samples=samples,
                         few_first=False)


#: a sampled minimum at or above −TOUCH_MM (mm) is a touch: it is not refined by the parabola
TOUCH_MM = 1e-6


def parabolic_minimum(phi: np.ndarray, c: np.ndarray) -> tuple[float, float]:
    """The sampled minimum of c(φ), refined by the parabola through it and its two neighbours
    (kept only when its vertex lies between them and below the sample) — where the sample
    interferes (below −:data:`TOUCH_MM`). A touching minimum stays the sample's: near a touch
    c(φ) has a kink, not a parabola's bottom (a tooth touches its CS, c ≈ 0, over the engaged
    poses and the clearance rises beyond them), and the parabola through the last touching samples
    and the first rising one has its vertex between two zeros and below them: csf58_50 with
    ω* = 0.6, design scene, −2.77 µm at the design section's engaged edge, which no tooth
    modification can clear (the design section never moves): the face FAILed where the verify
    scene cleared it."""
    i = int(np.argmin(c))
    if 0 < i < c.size - 1 and c[i] < -TOUCH_MM:
        h = phi[i + 1] - phi[i]
        a, b = 0.5 * (c[i + 1] + c[i - 1]) - c[i], 0.5 * (c[i + 1] - c[i - 1])
        if a > 0 and abs(b) < 2 * a:
            x = -b / (2 * a)
            return float(c[i] - b * b / (4 * a)), float(phi[i] + x * h)
    return float(c[i]), float(phi[i])


def engaged_zone(clearance_mm: np.ndarray) -> np.ndarray:
    """Where the design section's own tooth touches the CS (its map within ENGAGED_MM)."""
    return np.asarray(clearance_mm) <= ENGAGED_MM


def section_clearance(form, section: FaceSection, engaged: np.ndarray | None = None, *, samples: int = MAP_SAMPLES,
                      thickness_change_mm: float = 0.0, cmap=None,
                      min_gap_mm: float | None = None) -> tuple[SectionClearance, np.ndarray, np.ndarray]:
    """One section's row of the face map against the CS ``form``: (SectionClearance, φ, c(φ)).
    ``engaged``: the design section's engaged poses on the same φ grid (None: this section is the
    design section, its own); ``cmap``: the map if already computed."""
    if cmap is None:
        cmap = section_map(form, section, samples)
    c = cmap.clearance_mm
    phi = cmap.phi
    c_min, at = parabolic_minimum(phi, c)
    engaged = engaged_zone(c) if engaged is None else engaged
    backlash = float(np.max(c[engaged])) if np.any(engaged) else float("nan")
    gap = min_gap_mm
    if gap is None and section.envelope is not None:
        gap = float(np.min(signed_gap(form.space, section.boundary)))
    row = SectionClearance(section.z_mm, section.omega_major_mm, section.omega_minor_mm, section.upsilon_max_mm,
                           float(c_min), float(at), backlash, gap, float(thickness_change_mm))
    return row, phi, c


def face_map(form, secs, design_index: int, *, samples: int = MAP_SAMPLES, thickness_change_mm=None,
             min_gap_mm=None):
    """Every section's row against ``form``, the design section's engaged zone first:
    (rows, φ, clearance (sections × φ), engaged). ``min_gap_mm``: each section's smallest signed
    gap to ``form`` if known (else computed from its envelope)."""
    n = len(secs)
    ds = np.zeros(n) if thickness_change_mm is None else np.asarray(thickness_change_mm, dtype=float)
    gaps = [None] * n if min_gap_mm is None else [float(g) for g in min_gap_mm]
    rows: list[SectionClearance | None] = [None] * n  # every entry is set below
    maps: list[np.ndarray | None] = [None] * n
    row, phi, c = section_clearance(form, secs[design_index], samples=samples,
                                    thickness_change_mm=ds[design_index], min_gap_mm=gaps[design_index])
    engaged = engaged_zone(c)
    rows[design_index], maps[design_index] = row, c
    for k, s in enumerate(secs):
        if k != design_index:
            rows[k], _, maps[k] = section_clearance(form, s, engaged, samples=samples, thickness_change_mm=ds[k],
                                                    min_gap_mm=gaps[k])
    return rows, phi, np.array(maps), engaged


