"""Face width (issue 15, item 4): the envelope at axial sections of the tooth ring, one CS
profile, and the clearance of every section's FS tooth against it.

The 3D cup gives each section z its own deformation, so its own motion and swept region
(:mod:`profilegen.face.sections`). The CS is cut with one profile through its whole face: the
CS outline of the *design section* z_d (the polyline outline of
:func:`profilegen.gearform.circular_spline_form` from z_d's envelope — not the arc–line–arc
fit, which follows it within the fit's error and is one-sided). For every section k:

* the clearance map c_k(φ): :func:`profilegen.gearform.clearance_map` of section k's FS tooth
  in section k's motion against that one outline (signed distance, < 0 interference); its
  minimum, refined on a fine φ grid around the sampled minimum, is ``min_clearance_mm``;
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
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field

import numpy as np

from .. import checks
from ..results import json_ready, readonly
from .sections import FaceError, FaceSection, ring_span, signed_gap, solve_section

__all__ = ["FaceWidth", "SectionClearance", "face_width", "section_clearance"]

log = logging.getLogger(__name__)

#: Coarse envelope settings of the face stage: chord 0.1 µm (against 1 nm in the design scene; the
#: section table moves by less than 0.1 µm, tests/benchmarks/face_width.py).
CHORD_TOL_MM = 1e-4
N_T = 96
N_PHI = 241
#: FS poses of each section's clearance map over one pass; the minimum is refined around the
#: sampled one with REFINE_SAMPLES poses over ± two sample steps.
MAP_SAMPLES = 181
REFINE_SAMPLES = 41
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
    form: object
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
    modification: object = None
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
        """The deepest interference over the face (mm, ≥ 0; 0 when interference-free)."""
        return float(max(0.0, -min(r.min_clearance_mm for r in self.table)))

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
    from ..gearform import circular_spline_form

    cs = gearset.circular_spline
    return circular_spline_form(section.envelope, cs_teeth=gearset.gear.circular_spline_teeth,
                                tip_clearance_mm=cs.tip_clearance_mm, root_clearance_mm=cs.root_clearance_mm,
                                outer_radius_mm=None if cs.outer_diameter_mm is None else cs.outer_diameter_mm / 2.0,
                                chord_tol_mm=chord_tol_mm)


def _flanks(form) -> np.ndarray:
    return np.vstack([form.working_flank["right"], form.working_flank["left"]])


def _map(form, section: FaceSection, samples: int, phi_range=None):
    from ..gearform import clearance_map

    waves = section.motion.waves
    phi_range = (-math.pi / waves, math.pi / waves) if phi_range is None else phi_range
    return clearance_map(form, section.tooth, section.motion, phi_range=phi_range, samples=samples)


def engaged_zone(clearance_mm: np.ndarray) -> np.ndarray:
    """Where the design section's own tooth touches the CS (its map within ENGAGED_MM)."""
    return np.asarray(clearance_mm) <= ENGAGED_MM


def section_clearance(form, section: FaceSection, engaged: np.ndarray | None = None, *, samples: int = MAP_SAMPLES,
                      thickness_change_mm: float = 0.0, cmap=None) -> tuple[SectionClearance, np.ndarray, np.ndarray]:
    """One section's row of the face map against the CS ``form``: (SectionClearance, φ, c(φ)).
    ``engaged``: the design section's engaged poses on the same φ grid (None: this section is the
    design section, its own); ``cmap``: the map if already computed."""
    if cmap is None:
        cmap = _map(form, section, samples)
    c = cmap.clearance_mm
    i = int(np.argmin(c))
    phi = cmap.phi
    step = phi[1] - phi[0]
    lo, hi = max(phi[0], phi[i] - 2 * step), min(phi[-1], phi[i] + 2 * step)
    fine = _map(form, section, REFINE_SAMPLES, (lo, hi))
    j = int(np.argmin(fine.clearance_mm))
    c_min, at = (fine.clearance_mm[j], fine.phi[j]) if fine.clearance_mm[j] < c[i] else (c[i], phi[i])
    engaged = engaged_zone(c) if engaged is None else engaged
    backlash = float(np.max(c[engaged])) if np.any(engaged) else float("nan")
    gap = None if section.envelope is None else float(np.min(signed_gap(form.space, section.boundary)))
    row = SectionClearance(section.z_mm, section.omega_major_mm, section.omega_minor_mm, section.upsilon_max_mm,
                           float(c_min), float(at), backlash, gap, float(thickness_change_mm))
    return row, phi, c


def face_map(form, secs, design_index: int, *, samples: int = MAP_SAMPLES, thickness_change_mm=None):
    """Every section's row against ``form``, the design section's engaged zone first:
    (rows, φ, clearance (sections × φ), engaged)."""
    n = len(secs)
    ds = np.zeros(n) if thickness_change_mm is None else np.asarray(thickness_change_mm, dtype=float)
    rows, maps = [None] * n, [None] * n
    row, phi, c = section_clearance(form, secs[design_index], samples=samples,
                                    thickness_change_mm=ds[design_index])
    engaged = engaged_zone(c)
    rows[design_index], maps[design_index] = row, c
    for k, s in enumerate(secs):
        if k != design_index:
            rows[k], _, maps[k] = section_clearance(form, s, engaged, samples=samples, thickness_change_mm=ds[k])
    return rows, phi, np.array(maps), engaged


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
    start = time.perf_counter()
    deformation = _cup_deformation(deformation)
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

    from ..teeth import tooth_from_gearset

    tooth = tooth_from_gearset(gearset)
    t0 = time.perf_counter()
    secs = [solve_section(gearset, deformation, float(zk), tooth, chord_tol_mm=chord, n_t=n_t, n_phi=n_phi)
            for zk in z]
    envelope_s = time.perf_counter() - t0

    # candidates: each computed section's CS against every section's swept region
    forms = [_cs_form(gearset, s, chord) for s in secs]
    min_gap = np.array([[np.min(signed_gap(f.space, s.boundary)) for s in secs] for f in forms])
    max_bl = np.full(min_gap.shape, np.nan)  # the maps' backlash, for the candidates whose maps are computed
    t0 = time.perf_counter()
    if given is not None:
        d = int(np.argmin(np.abs(z - given)))
        choice = "given"
        found = {d: face_map(forms[d], secs, d, samples=samples)}
    else:
        worst = min_gap.min(axis=1)
        ok = np.flatnonzero(worst >= -tol)
        if not ok.size:
            ok = np.array([int(np.argmax(worst))])
            warnings.append(f"no computed section's CS is interference-free over the face; the least interfering "
                            f"(z = {z[ok[0]]:g} mm, {-worst[ok[0]] * 1e3:.3g} µm) is the design section")
        found = {int(k): face_map(forms[k], secs, int(k), samples=samples) for k in ok}
        d = min(found, key=lambda k: max(r.max_backlash_mm for r in found[k][0]))
        choice = "auto"
    for k, (rows_k, *_ ) in found.items():
        max_bl[k] = [r.max_backlash_mm for r in rows_k]
    rows, phi, cmap, engaged = found[d]
    map_s = time.perf_counter() - t0
    result = FaceWidth(tuple(secs), d, choice, forms[d], phi, cmap, tuple(rows), min_gap, max_bl, engaged, tol, chord,
                       samples, envelope_s, map_s, time.perf_counter() - start, None, tuple(warnings))
    if result.max_interference_mm > tol:
        warnings.append(f"the one CS profile (design section z = {result.design_section_z_mm:g} mm) interferes with "
                        f"the FS tooth by {result.max_interference_mm * 1e3:.3g} µm over the face")
    mod = None
    if modification is not None:
        from .modification import apply_modification, solve_modification

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


def _cup_deformation(obj):
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
