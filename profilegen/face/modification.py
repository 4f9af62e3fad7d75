"""FS tooth modification along the face: a linear taper and a crowning of the
tooth thickness that make the one CS profile interference-free at every section with the
backlash as uniform as it can be.

The modification is a change of the FS tooth thickness on the pitch line (both flanks, mm;
negative: thinner), zero at the design section z_d (whose tooth the CS is conjugate to)::

    Δs(z) = taper · (z − z_d) − crowning · (u(z)² − u(z_d)²),   u(z) = (z − z_mid) / (b/2)

``taper_mm_per_mm`` per mm toward the open end; ``crowning_mm`` the thinning at both face ends
against the mid-face z_mid (b: the face width). A section's tooth is the gear set's with
``half_thickness_mm`` + Δs/2 (the flanks moved along the tooth's tangent, DCTA and involute
teeth).

Computed (:func:`solve_modification`) as a minimax linear programme (scipy HiGHS) in
(taper, crowning, t): minimise t, the largest backlash over the sections, subject to no
interference at any pose of any section, with every section's clearances
linear in Δs on the φ grid of the face map — c_k(φ) + σ_k(φ) Δs_k ≥ 0 at every pose, ≤ t at
the design section's engaged poses (σ: the clearance's change per mm of thickness, first from
a one-sided finite difference (thinner) at each section, then the secant of each section's own recomputed
map). Each step recomputes the modified sections' maps exactly; the steps stop when the
thickness change moves by less than STOP_MM; the interference-free step with the least largest
backlash is kept (none: the last step, with a warning).

What a thickness change cannot do: where a section's tooth goes deeper into the space than the
design section's (more ω on the major axis) its tip corners meet the CS flank near the top of
the space, and where it deflects less on the minor axis its root lands meet the CS tips — radial
interference that thinning barely relieves; the LP is then infeasible (a warning).

The radial shift (``shift_mm_per_mm``): the whole FS tooth, root to tip, moved radially by
Δy(z) = shift · (z − z_d) (> 0 away from the gear centre; 0 at the design section) — a profile
shift that varies linearly along the face, the tooth cut with the hob's radial position fed
with its axial one (a conical FS: tip and root circles tapered by Δy). It is what a cone of
the cup about the bearing's ball row asks for: with the race free to tilt each section is the
design section's deformation scaled (ω ∝ z), and a section that deflects less than the design
section sits radially further out on its way in and out of mesh (φ ≈ ±60°), where its tooth
meets the CS flank along the whole flank (seed000_csf40, ring race, design section at the open
end: 74 µm at the diaphragm end; still 10 µm with the tooth 200 µm thinner, 43 µm with its tip
200 µm lower; moved 100 µm inward it clears). Searched (:func:`_search_on_maps`) only when the
thickness taper and crowning find no interference-free part: the smallest shift, toward the
gear centre at the worst section, that is interference-free on the exact maps. The shifted
tooth is built with the neutral radius r_m − Δy (its levels r₁ − r_m + … are Δy higher in the
tooth frame) and placed by the section's own motion on the real neutral line.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from .. import checks
from ..results import json_ready, readonly
from .clearance import section_map, parabolic_minimum, section_clearance
from .sections import FaceError, cup_deformation, ring_span

if TYPE_CHECKING:  # pragma: no cover
    from .stage import FaceWidth

__all__ = ["ToothModification", "apply_modification", "modification_words", "modified_tooth", "radial_shift",
           "solve_modification",
           "thickness_change"]

#: the finite-difference step of the first sensitivity (mm of tooth thickness): thinner, the way
#: interference is removed (the clearance is a minimum over contacts: its one-sided slopes differ)
FD_STEP_MM = -4e-3
#: the LP steps stop when the thickness change moves by less than this at every section (mm)
STOP_MM = 2e-4
#: the radial shift's range searched (mm per mm of face; 0.02: 400 µm over a 20 mm face)
SHIFT_MAX_MM_PER_MM = 0.02


class _ToothFields:
    """A tooth section with ``half_thickness_mm`` replaced (for :func:`profilegen.geometry.teeth.tooth_from_gearset`)."""

    def __init__(self, tooth, half_thickness_mm: float):
        self._tooth, self.half_thickness_mm = tooth, half_thickness_mm

    def __getattr__(self, name):
        return getattr(self._tooth, name)


class _GearView:
    """A gear section with ``neutral_radius_mm`` replaced (a tooth shifted radially, module docstring)."""

    def __init__(self, gear, neutral_radius_mm: float):
        self._gear, self.neutral_radius_mm = gear, neutral_radius_mm

    def __getattr__(self, name):
        return getattr(self._gear, name)


class _GearSetView:
    def __init__(self, gearset, tooth, gear=None):
        self.gear, self.tooth = gearset.gear if gear is None else gear, tooth


def modified_tooth(gearset, thickness_change_mm: float, radial_shift_mm: float = 0.0):
    """The gear set's FS tooth with its thickness on the pitch line changed by
    ``thickness_change_mm`` (half on each flank) and, root to tip, moved radially by
    ``radial_shift_mm`` (> 0 away from the gear centre) against the neutral line: in the tooth
    frame (origin on the neutral line) its levels are that much higher. A shifted tooth carries
    the neutral radius r_m − Δy; it is placed by the section's motion (the real neutral line)."""
    from ..geometry.teeth import tooth_from_gearset

    t = gearset.tooth
    if getattr(t, "kind", None) not in ("dcta", "involute"):
        raise FaceError(f"face.taper_mm_per_mm / face.crowning_mm: a tooth of kind {getattr(t, 'kind', None)!r} "
                        "cannot be modified (its thickness is not a field); tooth.kind must be dcta or involute")
    if thickness_change_mm == 0.0 and radial_shift_mm == 0.0:
        return tooth_from_gearset(gearset)
    h = float(t.half_thickness_mm) + 0.5 * float(thickness_change_mm)
    gear = None
    if radial_shift_mm != 0.0:
        gear = _GearView(gearset.gear, float(gearset.gear.neutral_radius_mm) - float(radial_shift_mm))
    return tooth_from_gearset(_GearSetView(gearset, _ToothFields(t, h), gear))


def modification_words(taper_mm_per_mm: float, crowning_mm: float, shift_mm_per_mm: float = 0.0) -> str:
    """'taper T µm/mm, crowning C µm' and, when the tooth is shifted, 'radial shift S µm/mm (a conical FS)'."""
    text = f"taper {taper_mm_per_mm * 1e3:.3g} µm/mm, crowning {crowning_mm * 1e3:.3g} µm"
    if shift_mm_per_mm:
        text += f", radial shift {shift_mm_per_mm * 1e3:.4g} µm/mm (a conical FS)"
    return text


def radial_shift(z_mm, *, shift_mm_per_mm: float, design_z_mm: float) -> np.ndarray:
    """Δy(z) = shift · (z − z_d) of the module docstring (mm, > 0 away from the gear centre)."""
    return shift_mm_per_mm * (np.asarray(z_mm, dtype=float) - design_z_mm)


def thickness_change(z_mm, *, taper_mm_per_mm: float, crowning_mm: float, design_z_mm: float,
                     ring_span_mm: tuple[float, float]) -> np.ndarray:
    """Δs(z) of the module docstring (mm)."""
    lo, hi = ring_span_mm
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    z = np.asarray(z_mm, dtype=float)
    return taper_mm_per_mm * (z - design_z_mm) - crowning_mm * (((z - mid) / half) ** 2 - ((design_z_mm - mid) / half) ** 2)


@dataclass(frozen=True, slots=True, eq=False)
class ToothModification:
    """The modification and the face with it applied: ``taper_mm_per_mm``, ``crowning_mm``,
    ``source`` ("computed" or "given"), the thickness change of each section
    ``thickness_change_mm``, its ``table`` (SectionClearance rows) and clearance map
    ``clearance_mm`` (sections × φ) against the same CS; ``iterations`` of the LP, the
    ``predicted_backlash_mm`` of the last LP (the recomputed one is in the table); the radial
    shift ``shift_mm_per_mm`` and each section's ``radial_shift_mm`` (module docstring)."""

    taper_mm_per_mm: float
    crowning_mm: float
    source: str
    method: str
    thickness_change_mm: np.ndarray
    sections: tuple
    table: tuple
    clearance_mm: np.ndarray
    iterations: int
    predicted_backlash_mm: float | None
    time_s: float
    warnings: tuple = field(default=())
    shift_mm_per_mm: float = 0.0
    radial_shift_mm: np.ndarray | None = None

    def __post_init__(self):
        object.__setattr__(self, "thickness_change_mm", readonly(self.thickness_change_mm))
        object.__setattr__(self, "clearance_mm", readonly(self.clearance_mm))
        shift = np.zeros(len(self.thickness_change_mm)) if self.radial_shift_mm is None else self.radial_shift_mm
        object.__setattr__(self, "radial_shift_mm", readonly(shift))

    @property
    def max_interference_mm(self) -> float:
        return float(max(0.0, -min(r.min_clearance_mm for r in self.table)))

    @property
    def words(self) -> str:
        """The modification in a few words, the radial shift named when there is one (figures'
        titles, the report): 'taper 0 µm/mm, crowning 0 µm' alone hid a conical FS."""
        return modification_words(self.taper_mm_per_mm, self.crowning_mm, self.shift_mm_per_mm)

    @property
    def max_backlash_mm(self) -> float:
        return float(max(r.max_backlash_mm for r in self.table))

    def to_dict(self) -> dict:
        return json_ready({
            "taper_mm_per_mm": self.taper_mm_per_mm, "crowning_mm": self.crowning_mm, "source": self.source,
            "method": self.method,
            "definition": "tooth thickness change on the pitch line Δs(z) = taper·(z − z_d) − crowning·(u² − u_d²), "
                          "u = (z − z_mid)/(b/2); zero at the design section. Radial shift of the whole tooth "
                          "Δy(z) = shift·(z − z_d), > 0 away from the gear centre",
            "shift_mm_per_mm": self.shift_mm_per_mm, "radial_shift_mm": self.radial_shift_mm,
            "sections": [r.to_dict() for r in self.table],
            "max_interference_mm": self.max_interference_mm, "max_backlash_mm": self.max_backlash_mm,
            "iterations": self.iterations, "predicted_backlash_mm": self.predicted_backlash_mm,
            "time_s": self.time_s, "warnings": list(self.warnings)})


def _modified_sections(gearset, face: FaceWidth, ds: np.ndarray, dy: np.ndarray | None = None):
    """The sections with their teeth modified by ``ds`` and shifted by ``dy`` (same motion; the
    envelope is not traced)."""
    dy = np.zeros(len(ds)) if dy is None else dy
    return [_modified_section(gearset, s, d, y) for s, d, y in zip(face.sections, ds, dy)]


def _modified_section(gearset, section, d: float, y: float):
    """One section of :func:`_modified_sections`."""
    return section if abs(d) < 1e-12 and abs(y) < 1e-12 else \
        replace(section, tooth=modified_tooth(gearset, float(d), float(y)), envelope=None)


class _Stored:
    """A clearance map already computed (the face stage's own, of an unmodified section)."""

    def __init__(self, phi, clearance_mm):
        self.phi, self.clearance_mm = phi, clearance_mm


class _MapCache:
    """The clearance maps of the sections by (section, thickness change), each computed once: the
    LP's last step, the search's last trial and the result's table share them (on seed000_csf40's
    verify scene 5 of 27 map solves were repeats). An unmodified section's map is the face stage's."""

    def __init__(self, face):
        self.face, self.maps = face, {}

    def get(self, k: int, section, ds_k: float, dy_k: float = 0.0):
        """Section k's map with thickness change ``ds_k`` and radial shift ``dy_k``; ``section``:
        the modified section, or a function that makes it (called only when the map is computed)."""
        if abs(ds_k) < 1e-12 and abs(dy_k) < 1e-12:
            return _Stored(self.face.phi_rad, self.face.clearance_mm[k])
        key = (k, float(ds_k), float(dy_k))
        if key not in self.maps:
            self.maps[key] = section_map(self.face.form, section() if callable(section) else section,
                                         self.face.map_samples)
        return self.maps[key]


def _finish(gearset, face, secs, ds, taper, crown, source, method, iterations, predicted, start, warnings,
            cache: _MapCache | None = None, shift: float = 0.0, dy: np.ndarray | None = None):
    cache = _MapCache(face) if cache is None else cache
    dy = np.zeros(len(ds)) if dy is None else np.asarray(dy, dtype=float)
    rows, cmap_rows = [], []
    for k, (s, d, y) in enumerate(zip(secs, ds, dy)):
        same = abs(d) < 1e-12 and abs(y) < 1e-12
        row, _, c = section_clearance(face.form, s, face.engaged, samples=face.map_samples, thickness_change_mm=float(d),
                                      cmap=cache.get(k, s, float(d), float(y)),
                                      min_gap_mm=face.table[k].min_gap_mm if same else None)
        rows.append(row)
        cmap_rows.append(c)
    cmap = np.array(cmap_rows)
    mod = ToothModification(float(taper), float(crown), source, method, ds, tuple(secs), tuple(rows), cmap,
                            iterations, predicted, time.perf_counter() - start, tuple(warnings), float(shift), dy)
    if mod.max_interference_mm > face.interference_tol_mm:
        warnings.append(f"with the tooth modification the CS still interferes by {mod.max_interference_mm * 1e3:.3g} µm")
        mod = replace(mod, warnings=tuple(warnings))
    return mod


def apply_modification(gearset, deformation, face: FaceWidth, taper_mm_per_mm: float,
                       crowning_mm: float, shift_mm_per_mm: float = 0.0) -> ToothModification:
    """The face with a given modification (gear-set fields ``[face] taper_mm_per_mm``, ``crowning_mm``;
    ``shift_mm_per_mm`` the radial shift, module docstring, not a gear-set field)."""
    start = time.perf_counter()
    deformation = cup_deformation(deformation)
    taper = checks.number("face.taper_mm_per_mm", taper_mm_per_mm, "mm/mm", -0.01, 0.01, low_open=False,
                          high_open=False, error=FaceError)
    crown = checks.number("face.crowning_mm", crowning_mm, "mm", -0.1, 0.1, low_open=False, high_open=False,
                          error=FaceError)
    ds = thickness_change(face.z_mm, taper_mm_per_mm=taper, crowning_mm=crown, design_z_mm=face.design_section_z_mm,
                          ring_span_mm=ring_span(deformation))
    shift = checks.number("shift_mm_per_mm", shift_mm_per_mm, "mm/mm", -SHIFT_MAX_MM_PER_MM, SHIFT_MAX_MM_PER_MM,
                          low_open=False, high_open=False, error=FaceError)
    dy = radial_shift(face.z_mm, shift_mm_per_mm=shift, design_z_mm=face.design_section_z_mm)
    secs = _modified_sections(gearset, face, ds, dy)
    return _finish(gearset, face, secs, ds, taper, crown, "given", "as given", 0, None, start, [], shift=shift, dy=dy)


def solve_modification(gearset, deformation, face: FaceWidth, *, crowning: bool = True,
                       iterations: int = 6) -> ToothModification:
    """The taper (and crowning, unless ``crowning=False``) that make the one CS interference-free
    at every section with the least largest backlash (minimax LP, see the module docstring)."""
    from scipy.optimize import linprog

    start = time.perf_counter()
    span = ring_span(cup_deformation(deformation))
    z, zd = face.z_mm, face.design_section_z_mm
    a = z - zd
    mid, half = 0.5 * (span[0] + span[1]), 0.5 * (span[1] - span[0])
    c = -(((z - mid) / half) ** 2 - ((zd - mid) / half) ** 2)
    c0 = face.clearance_mm
    engaged = face.engaged
    samples = face.map_samples

    # first sensitivities: each section's tooth made thinner by |FD_STEP_MM| (the nearest CS point at a
    # pose differs from section to section, so does the clearance's response)
    d = face.design_index
    thick = modified_tooth(gearset, FD_STEP_MM)
    sens = np.zeros_like(c0)
    for k, s in enumerate(face.sections):
        if k != d:
            sens[k] = (section_map(face.form, replace(s, tooth=thick, envelope=None), samples).clearance_mm - c0[k]) / FD_STEP_MM

    nvar = 3 if crowning else 2
    cache = _MapCache(face)
    warnings: list[str] = []
    taper = crown = 0.0
    ds = np.zeros(z.size)
    secs = list(face.sections)
    predicted = None
    method = ("minimax LP (scipy HiGHS): the least largest backlash over the sections' engaged poses, no "
              "interference at any pose of any section; clearances linear in the thickness change, recomputed "
              "after each step (secant sensitivities)")
    done, best, lp_failed = 0, None, ""
    for it in range(1, iterations + 1):
        rows_ub, rhs_ub = [], []
        for k in range(z.size):
            basis = np.array([a[k], c[k]])[: nvar - 1]
            m = sens[k][:, None] * basis[None, :]
            if k != d:  # the design section's tooth is not modified (its own map is ~0 within the chord)
                rows_ub.append(np.hstack([-m, np.zeros((m.shape[0], 1))]))  # c + σΔs ≥ 0
                rhs_ub.append(c0[k])
            rows_ub.append(np.hstack([m[engaged], -np.ones((int(engaged.sum()), 1))]))  # c + σΔs ≤ t
            rhs_ub.append(-c0[k][engaged])
        cost = np.zeros(nvar)
        cost[-1] = 1.0
        lp = linprog(cost, A_ub=np.vstack(rows_ub), b_ub=np.concatenate(rhs_ub),
                     bounds=[(-0.01, 0.01)] + ([(-0.1, 0.1)] if crowning else []) + [(None, None)], method="highs")
        if lp.status != 0:
            lp_failed = f"the LP failed at step {it} ({lp.message})"
            break
        taper, crown = float(lp.x[0]), (float(lp.x[1]) if crowning else 0.0)
        predicted = float(lp.x[-1])
        ds_new = a * taper + c * crown
        secs = _modified_sections(gearset, face, ds_new)
        cmaps = np.array([cache.get(k, secs[k], ds_new[k]).clearance_mm for k in range(z.size)])
        done = it
        for k in range(z.size):  # the secant of each section's own clearances
            if abs(ds_new[k]) > 1e-9:
                sens[k] = (cmaps[k] - c0[k]) / ds_new[k]
        moved = float(np.max(np.abs(ds_new - ds)))
        ds = ds_new
        if float(cmaps.min()) >= -face.interference_tol_mm:
            backlash = float(np.max(cmaps[:, engaged]))
            if best is None or backlash < best[0]:
                best = (backlash, taper, crown, ds, secs, predicted)
            if moved < STOP_MM:
                break
    shift, dy = 0.0, None
    if best is None:
        found = _search_on_maps(gearset, face, a, c if crowning else None, cache=cache)
        if found is not None:
            warnings.append(f"tooth modification: the LP found no interference-free step ({lp_failed or f'{done} steps'}: "
                            "the clearance is not linear in the thickness there); a search (regula falsi) on the exact "
                            "maps along the taper or the crowning found one")
            method += "; fallback: regula falsi on the exact maps along the taper, then the crowning"
        else:
            found = _search_on_maps(gearset, face, a, None, cache=cache, shift=True)
            if found is None:
                warnings.append(f"tooth modification: still interfering after {done} LP steps"
                                f"{f' ({lp_failed})' if lp_failed else ''} and the search along the taper and "
                                "crowning and along the radial shift")
            else:
                warnings.append(f"tooth modification: no thickness taper or crowning clears the face "
                                f"({lp_failed or f'{done} LP steps'}, and the search along them); the FS tooth is "
                                "shifted radially along the face (a conical "
                                f"FS: {found[5] * 1e3:.3g} µm/mm, {np.min(found[6]) * 1e3:.3g} … "
                                f"{np.max(found[6]) * 1e3:.3g} µm over the face, > 0 outward)")
                method += ("; fallback: regula falsi on the exact maps along the taper, then the crowning, then the "
                           "radial shift of the whole tooth")
        if found is not None:
            backlash, taper, crown, ds, secs, shift, dy = found
            predicted = None
    else:
        _, taper, crown, ds, secs, predicted = best
        if lp_failed:
            warnings.append(f"tooth modification: {lp_failed}; the best interference-free step before it is kept")
    return _finish(gearset, face, secs, ds, taper, crown, "computed", method, done, predicted, start, warnings, cache,
                   shift, dy)


def _search_on_maps(gearset, face: FaceWidth, a: np.ndarray, c: np.ndarray | None, *, steps: int = 9,
                    cache: _MapCache | None = None, shift: bool = False):
    """When the LP's linearisation finds no interference-free step (the clearance is a minimum over
    contacts, and where the nearest contact changes a finite-difference slope says little): along the
    taper (its sign thins the worst-interfering section) and then the crowning, the smallest multiple
    within the field's range that is interference-free on the exact recomputed maps (to a tenth of the
    interference tolerance: the margin is real, not the tolerance's), to 2^-``steps`` of the range
    (1/512). Returns (largest backlash, taper, crowning, Δs, sections, shift, Δy) of the better one,
    or None. ``shift``: along the radial shift instead (:data:`SHIFT_MAX_MM_PER_MM`, its sign moves
    the worst-interfering section toward the gear centre), the thickness unchanged.

    The multiple is bracketed by the Illinois variant of regula falsi on the lowest clearance of the
    *active* sections — at first only the worst-interfering one, whose map alone is recomputed at each
    trial — and checked on every section's map at the end; a section found interfering there joins
    the active ones and the search goes on from the bracket it had. The same bracket width as a
    bisection of every map (``steps`` halvings); on seed000_csf40 the face stage solves 16 maps
    instead of 54 (the bisection's 40, and the result's table again), taper 1.196 µm/mm against the
    bisection's 1.191 (its grid: 0.0195 µm/mm)."""
    c0 = face.clearance_mm
    worst = int(np.argmin(c0.min(axis=1)))
    tol = 0.1 * face.interference_tol_mm
    own = face.design_index
    directions = []
    if shift:
        if abs(a[worst]) > 0:  # the worst section moved toward the gear centre, to the shift's bound
            directions.append((0.0, 0.0, -np.sign(a[worst]) * SHIFT_MAX_MM_PER_MM))
    else:
        if abs(a[worst]) > 0:
            directions.append((-np.sign(a[worst]) * 0.01, 0.0, 0.0))  # taper to its bound, thinning the worst section
        if c is not None and c[worst] < 0:
            directions.append((0.0, 0.1, 0.0))  # crowning to its bound (thins the ends against the design section)
    best = None
    width = 2.0 ** -steps
    cache = _MapCache(face) if cache is None else cache

    def thickness(mult, taper_max, crown_max, shift_max):
        """(Δs, Δy) of the sections at ``mult`` of the direction."""
        return a * (mult * taper_max) + (0.0 if c is None else c * (mult * crown_max)), a * (mult * shift_max)

    def lowest(dsy, ks):
        """The lowest clearance (as the rows report it) of sections ``ks`` with thickness change and
        radial shift ``dsy``, and their maps (a modified tooth is built only for a map not yet computed:
        the search's trials need one or two sections of five)."""
        ds, dy = dsy
        rows = {}
        for k in ks:
            make = partial(_modified_section, gearset, face.sections[k], ds[k], dy[k])
            rows[k] = cache.get(k, make, float(ds[k]), float(dy[k])).clearance_mm
        return min(level(k, rows[k]) for k in ks), rows

    def level(k, clearance):
        """Section k's lowest clearance; the design section's tooth is never modified (its map is the
        stage's own, ~0 within the chord), so it is held to the stage's tolerance, not a tenth of it."""
        return parabolic_minimum(face.phi_rad, clearance)[0] + (face.interference_tol_mm - tol if k == own else 0.0)

    for taper_max, crown_max, shift_max in directions:
        direction = (taper_max, crown_max, shift_max)
        active = [worst]
        low, high = 0.0, 1.0
        f_low = float(c0[worst].min()) + tol  # < 0: the worst section interferes unmodified
        f_high = lowest(thickness(1.0, *direction), active)[0] + tol
        if f_high < 0.0:
            continue
        side, found = 0, None
        for _ in range(4 * steps):
            if high - low > width:
                mid = high - f_high * (high - low) / (f_high - f_low) if f_high != f_low else 0.5 * (low + high)
                mid = min(max(mid, low + 0.01 * (high - low)), high - 0.01 * (high - low))
                f_mid = lowest(thickness(mid, *direction), active)[0] + tol
                if f_mid >= 0.0:
                    high, f_high = mid, f_mid
                    f_low = 0.5 * f_low if side == 1 else f_low  # Illinois: the stale end's value halved
                    side = 1
                else:
                    low, f_low = mid, f_mid
                    f_high = 0.5 * f_high if side == -1 else f_high
                    side = -1
                continue
            dsy = thickness(high, *direction)
            everyone = list(range(dsy[0].size))
            value, rows = lowest(dsy, everyone)
            if value >= -tol:
                cmaps = np.array([rows[k] for k in everyone])
                found = (float(np.max(cmaps[:, face.engaged])), high, dsy, _modified_sections(gearset, face, *dsy))
                break
            bad = [k for k in everyone if k not in active and level(k, rows[k]) < -tol]
            active += bad
            f_high = lowest(thickness(1.0, *direction), active)[0] + tol
            if f_high < 0.0:
                break
            high, side = 1.0, 0
            f_low = lowest(thickness(low, *direction), active)[0] + tol if low > 0 else \
                min(float(c0[k].min()) for k in active) + tol
        if found is None:
            continue
        backlash, mult, (ds, dy), secs = found
        candidate = (backlash, mult * taper_max, mult * crown_max, ds, secs, mult * shift_max, dy)
        if best is None or candidate[0] < best[0]:
            best = candidate
    return best
