"""Face width: the envelope at axial sections of the tooth ring, one CS
profile, and the clearance of every section's FS tooth against it.

The 3D cup gives each section z its own deformation, so its own motion and swept region
(:mod:`profilegen.face.sections`). The CS is cut with one profile through its whole face: the
CS outline of the *design section* z_d (the polyline outline of
:func:`profilegen.profile.gearform.circular_spline_form` from z_d's envelope — not the arc–line–arc
fit, which follows it within the fit's error and is one-sided). For every section k:

* the clearance map c_k(φ): :func:`profilegen.profile.gearform.clearance_map` of section k's FS tooth
  in section k's motion against that one outline (signed distance, < 0 interference); its
  minimum, refined by the parabola through the sampled minimum and its neighbours, is
  ``min_clearance_mm``;
* the backlash ``max_backlash_mm``: the largest c_k(φ) over the *engaged* poses, those where
  the design section's own tooth touches the CS (c_d(φ) ≤ ENGAGED_MM): how far section k's
  tooth stands off the CS while the design section's drives.

Design section (``design_section="auto"``): every computed section is a candidate; the signed
gap (:func:`~profilegen.face.sections.signed_gap`) of candidate d's whole CS space (flanks,
root) to every section's swept boundary says whether d's CS is interference-free over the face
(min ≥ −tolerance; the same number as the map's minimum to ~0.01 µm on the default set); the
face maps of the interference-free candidates give their largest backlash, and the least wins
(if none is interference-free, the one with the least interference, with a warning). A number picks that
section, which is then one of the sections computed.

When no candidate is interference-free, the design section is the one of deepest engagement
(the most ω on the major axis): every other section's tooth then goes less deep into the CS
space, so what it needs is relief (a thinner tooth or one moved toward the gear centre,
:mod:`profilegen.face.modification`), never added depth. The least interfering section is no
such choice: with the wave generator's race free to tilt the cup cones about the ball row and
the mid-face section is the least interfering (seed000_csf40, 58 µm), but the open end's tooth
sits 53 µm deeper at φ = 0 there, which no thinning or inward shift of the other sections can
undo. On the rigid band the two rules pick the same section for every bundled set (the open end).
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .. import checks
from ..blas import one_blas_thread
from ..results import json_ready, readonly
from ..stagecache import checkpoint
from .clearance import ENGAGED_MM, MAP_SAMPLES, face_map
from .modification import ToothModification, apply_modification, solve_modification
from .sections import FaceError, FaceSection, SweptRegion, cup_deformation, ring_span, solve_section

if TYPE_CHECKING:  # pragma: no cover
    from ..profile.gearform import CircularSplineForm

__all__ = ["FaceWidth", "face_width"]

log = logging.getLogger(__name__)

#: Envelope settings of the face stage: every section traced at a chord of 0.1 µm. The traced
#: swept boundary's vertices lie on the curve to 1e-5 µm whatever the chord (the default set's
#: design section at 1e-4, 1e-6, 1e-7 mm; tests/benchmarks/face_width.py), so the CS outline is
#: the same; only its vertex spacing changes. The clearance map reads the distance of the CS
#: outline's vertices to the tooth, the 32 nearest per pose: with vertices ~1 µm apart (chord
#: 1 nm) those 32 crowd where the outline crosses the tooth and miss the deepest point (the default
#: cup's diaphragm end read −2.9 µm against the swept regions' −4.77 µm); at 0.1 µm they do not.
CHORD_TOL_MM = 1e-4
N_T = 96
N_PHI = 241
@dataclass(frozen=True, slots=True, eq=False)
class FaceWidth:
    """The face-width result: ``sections`` (FaceSection, ascending z), the ``design_index`` of
    the design section and how it was chosen (``design_choice``: "auto" or "given"), the one CS
    ``form``, the clearance map ``clearance_mm`` (sections × ``phi_rad``), the per-section
    ``table`` (SectionClearance), the candidates' gap matrices ``candidate_min_gap_mm`` /
    ``candidate_max_backlash_mm`` (candidate d × section k), the ``modification``
    (:class:`~profilegen.face.modification.ToothModification` or None), settings and times."""

    sections: tuple
    design_index: int
    design_choice: str
    form: CircularSplineForm
    phi_rad: np.ndarray
    clearance_mm: np.ndarray
    table: tuple
    candidate_min_gap_mm: np.ndarray
    candidate_max_backlash_mm: np.ndarray
    engaged: np.ndarray
    interference_tol_mm: float
    chord_tol_mm: float
    map_samples: int
    envelope_s: float
    map_s: float
    time_s: float
    modification: ToothModification | None = None
    warnings: tuple = field(default=())

    def __post_init__(self):
        object.__setattr__(self, "engaged", readonly(self.engaged, bool))
        for name in ("phi_rad", "clearance_mm", "candidate_min_gap_mm", "candidate_max_backlash_mm"):
            object.__setattr__(self, name, readonly(getattr(self, name)))
        object.__setattr__(self, "sections", tuple(self.sections))
        object.__setattr__(self, "table", tuple(self.table))
        object.__setattr__(self, "warnings", tuple(self.warnings))

    @property
    def z_mm(self) -> np.ndarray:
        return np.array([s.z_mm for s in self.sections])

    @property
    def design_section_z_mm(self) -> float:
        return self.sections[self.design_index].z_mm

    @property
    def max_interference_mm(self) -> float:
        """The deepest interference over the face (mm, ≥ 0; 0 when interference-free): of the maps'
        minima and the CS's signed gaps to the sections' swept regions (the gap does not depend on
        the map's pose sampling)."""
        return float(max(0.0, -min(min(r.min_clearance_mm, np.inf if r.min_gap_mm is None else r.min_gap_mm)
                                   for r in self.table)))

    @property
    def max_backlash_mm(self) -> float:
        return float(max(r.max_backlash_mm for r in self.table))

    def to_dict(self) -> dict:
        mod = self.modification
        return json_ready({
            "sections": [r.to_dict() for r in self.table],
            "design_section_z_mm": self.design_section_z_mm,
            "design_section_choice": self.design_choice,
            "max_interference_mm": self.max_interference_mm,
            "max_backlash_mm": self.max_backlash_mm,
            "taper_mm_per_mm": None if mod is None else mod.taper_mm_per_mm,
            "crowning_mm": None if mod is None else mod.crowning_mm,
            "shift_mm_per_mm": None if mod is None else mod.shift_mm_per_mm,
            "modification": None if mod is None else mod.to_dict(),
            "cs_profile": "the polyline CS outline (gearform) of the design section's envelope",
            "backlash_measure": ("the section's largest clearance (mm) over the FS poses where the design section's "
                                 f"tooth touches the CS (its own map within {ENGAGED_MM * 1e3:g} µm)"),
            "engaged_phi_deg": [math.degrees(float(self.phi_rad[self.engaged][0])),
                                math.degrees(float(self.phi_rad[self.engaged][-1]))] if self.engaged.any() else None,
            "candidates": {"z_mm": self.z_mm, "min_gap_mm": self.candidate_min_gap_mm,
                           "max_backlash_mm": self.candidate_max_backlash_mm},
            "interference_tol_mm": self.interference_tol_mm,
            "chord_tol_mm": self.chord_tol_mm,
            "map_samples": self.map_samples,
            "envelope_s": self.envelope_s,
            "map_s": self.map_s,
            "time_s": self.time_s,
            "warnings": list(self.warnings),
        })


def _cs_form(gearset, section: FaceSection, chord_tol_mm: float):
    from ..profile.gearform import circular_spline_form

    cs = gearset.circular_spline
    return circular_spline_form(section.envelope, cs_teeth=gearset.gear.circular_spline_teeth,
                                tip_clearance_mm=cs.tip_clearance_mm, root_clearance_mm=cs.root_clearance_mm,
                                outer_radius_mm=None if cs.outer_diameter_mm is None else cs.outer_diameter_mm / 2.0,
                                chord_tol_mm=chord_tol_mm)


def face_width(
    gearset,
    deformation,
    *,
    sections: int = 5,
    design_section: float | str = "auto",
    modification=None,
    chord_tol_mm: float = CHORD_TOL_MM,
    n_t: int = N_T,
    n_phi: int = N_PHI,
    map_samples: int = MAP_SAMPLES,
    interference_tol_mm: float | None = None,
) -> FaceWidth:
    """The face-width stage (see the module docstring).

    ``deformation``: the 3D cup's (ω(φ, z), υ(φ, z) and the tooth ring's span: a
    :class:`~profilegen.rim.cup.CupDeformation`, a :class:`~profilegen.rim.cup.CupContact` or
    anything with a ``deformation`` attribute that is one). ``sections``: equally spaced over the
    tooth ring, ends included (≥ 3). ``design_section``: "auto" or z (mm, in the tooth ring).
    ``modification``: None (no modification), "auto" (computed,
    :func:`profilegen.face.modification.solve_modification`) or a (taper_mm_per_mm,
    crowning_mm) pair applied as given. ``interference_tol_mm``: default the chord tolerance or
    10 nm, whichever is larger.
    """
    # BLAS on one thread: the stage's matrices are small (the sections' Fourier fits, ~17 columns),
    # and with another process on the machine OpenBLAS's spinning threads made the stage 1.4x slower
    # (the default set's design-scene face stage, medians of 4, while two designs ran beside it)
    with one_blas_thread():
        return _face_width(gearset, deformation, sections=sections, design_section=design_section,
                           modification=modification, chord_tol_mm=chord_tol_mm, n_t=n_t, n_phi=n_phi,
                           map_samples=map_samples, interference_tol_mm=interference_tol_mm)


def _face_width(gearset, deformation, *, sections: int, design_section: float | str, modification,
                chord_tol_mm: float, n_t: int, n_phi: int, map_samples: int,
                interference_tol_mm: float | None) -> FaceWidth:
    start = time.perf_counter()
    deformation = cup_deformation(deformation)
    lo, hi = ring_span(deformation)
    count = checks.whole("sections", sections, 3, error=FaceError)
    if count > 41:
        raise FaceError(f"sections = {count}: must be a whole number in [3, 41]")
    chord = checks.number("chord_tol_mm", chord_tol_mm, "mm", 0.0, 0.01, high_open=False, error=FaceError)
    samples = checks.whole("map_samples", map_samples, 11, error=FaceError)
    tol = max(1e-5, chord) if interference_tol_mm is None else checks.number(
        "interference_tol_mm", interference_tol_mm, "mm", 0.0, error=FaceError)
    z = np.linspace(lo, hi, count)
    given = None
    if isinstance(design_section, str):
        if design_section != "auto":
            raise FaceError(f"face.design_section_z_mm = {design_section!r}: must be \"auto\" or a number (mm) in "
                            f"the tooth ring [{lo:g}, {hi:g}] mm")
    else:
        given = checks.number("face.design_section_z_mm", design_section, "mm", lo, hi, low_open=False,
                              high_open=False, error=FaceError)
        if np.min(np.abs(z - given)) > 1e-9 * max(1.0, hi):
            z = np.sort(np.append(z, given))
    warnings: list[str] = []

    from ..geometry.teeth import tooth_from_gearset

    tooth = tooth_from_gearset(gearset)
    t0 = time.perf_counter()
    secs = []
    for zk in z:
        checkpoint()  # an engine's design stops here when superseded (a section's envelope: ~0.1 s)
        secs.append(solve_section(gearset, deformation, float(zk), tooth, chord_tol_mm=chord, n_t=n_t, n_phi=n_phi))
    envelope_s = time.perf_counter() - t0

    # candidates: each computed section's CS against every section's swept region
    forms = [_cs_form(gearset, s, chord) for s in secs]
    regions = [SweptRegion(s.boundary) for s in secs]
    min_gap = np.array([[np.min(r.signed_gap(f.space)) for r in regions] for f in forms])
    max_bl = np.full(min_gap.shape, np.nan)  # the maps' backlash, for the candidates whose maps are computed
    maps: dict[int, tuple] = {}  # candidate -> its face map (rows, φ, clearance, engaged)
    t0 = time.perf_counter()
    if given is not None:
        d = int(np.argmin(np.abs(z - given)))
        choice = "given"
    else:
        worst = min_gap.min(axis=1)
        ok = np.flatnonzero(worst >= -tol)
        if not ok.size:
            deepest = int(np.argmax([s.omega_major_mm for s in secs]))
            ok = np.array([deepest])
            warnings.append(f"no computed section's CS is interference-free over the face; the section of deepest "
                            f"engagement (z = {z[deepest]:g} mm, the most ω on the major axis: "
                            f"{secs[deepest].omega_major_mm:.4g} mm) is the design section, its CS interfering by "
                            f"{-worst[deepest] * 1e3:.3g} µm with the unmodified teeth (the least: "
                            f"{-worst.max() * 1e3:.3g} µm at z = {z[int(np.argmax(worst))]:g} mm)")
        if ok.size == 1:
            d = int(ok[0])
        else:  # several interference-free candidates: their maps' largest backlash decides
            for k in ok:
                maps[int(k)] = face_map(forms[k], secs, int(k), samples=samples, min_gap_mm=min_gap[k])
                max_bl[k] = [r.max_backlash_mm for r in maps[int(k)][0]]
            d = int(ok[np.argmin(np.nanmax(max_bl[ok], axis=1))])
        choice = "auto"
    form = forms[d]
    # the chosen candidate's face map, computed once (it was computed again here: 5 more maps)
    rows, phi, cmap, engaged = maps[d] if d in maps else face_map(form, secs, d, samples=samples,
                                                                  min_gap_mm=min_gap[d])
    max_bl[d] = [r.max_backlash_mm for r in rows]
    map_s = time.perf_counter() - t0
    result = FaceWidth(tuple(secs), d, choice, form, phi, cmap, tuple(rows), min_gap, max_bl, engaged, tol, chord,
                       samples, envelope_s, map_s, time.perf_counter() - start, None, tuple(warnings))
    if result.max_interference_mm > tol:
        warnings.append(f"the one CS profile (design section z = {result.design_section_z_mm:g} mm) interferes with "
                        f"the unmodified FS tooth by {result.max_interference_mm * 1e3:.3g} µm over the face"
                        + ("" if modification is None else " (the tooth modification's result follows in the face stage)"))
    mod = None
    if modification == "auto" and getattr(gearset.tooth, "kind", None) not in ("dcta", "involute"):
        warnings.append(f"no tooth modification along the face: a {gearset.tooth.kind} tooth has no thickness field "
                        "to modify")
        modification = None
    if modification is not None:
        if isinstance(modification, str):
            if modification != "auto":
                raise FaceError(f"modification = {modification!r}: must be None, \"auto\" or (taper_mm_per_mm, "
                                "crowning_mm)")
            mod = solve_modification(gearset, deformation, result)
        else:
            taper, crown = modification
            mod = apply_modification(gearset, deformation, result, taper, crown)
        warnings += list(mod.warnings)
    from dataclasses import replace

    return replace(result, modification=mod, warnings=tuple(warnings), time_s=time.perf_counter() - start)
