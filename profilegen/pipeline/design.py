"""design(gearset, scene) → Design: every stage, its tier, time and error estimate.

Scenes pick a fidelity tier per stage (docs/reference/scenes.md): the rim tier (ring theory,
nonlinear flat-ring FEM, toothed-rim FEM; :mod:`profilegen.rim.stage`) and its Fourier
fit, the envelope's chord tolerance and grids, the number of FS poses the fitted profile is
checked against.
"""

from __future__ import annotations

import logging
import math
import os
import time
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Callable

import numpy as np

from ..blas import one_blas_thread
from ..profile.envelope import Envelope, envelope_of
from ..errors import ConvergenceError, GearSetError, ProfilegenError
from ..profile.gearform import RETRACE_FACTOR, RETRACES, CircularSplineForm, circular_spline_form, clearance_map, cs_local_chain
from ..gearset import FIT_METHODS, GearSet
from ..geometry.contour import Chain, Line
from ..geometry.kinematics import HarmonicDriveMotion
from .scenes import SCENES, Scene, resolve_scene  # noqa: F401  (SCENES: profilegen.pipeline.design.SCENES, as before)
from ..stagecache import STAGE_CACHE, Beside, checkpoint as stage_checkpoint  # noqa: F401  (pipeline.stage_checkpoint, as before)
from ..geometry.teeth import tooth_from_gearset

if TYPE_CHECKING:  # pragma: no cover
    from ..profile.arcfit import BranchFits, ProfileFit
    from ..contact.analysis import ContactResult
    from ..contact.chain import TorsionalCurve
    from ..contact.ratchet import Ratcheting
    from ..contact.transmission import TransmissionError
    from ..geometry.deformation import HarmonicDeformation
    from ..face.stage import FaceWidth
    from ..profile.gearform import ClearanceMap
    from ..rim.stage import RimDeformation
    from ..profile.rootfillet import CSChain
    from ..geometry.series import DeformationFit
    from ..stress.stage import StressResult
    from ..geometry.teeth import ToothProfile

__all__ = ["StageReport", "CSProfile", "Design", "Verdict", "design", "check_gearset", "planned_stages"]

MIN_BRANCH_POINTS = 12  # flank points a branch needs for its own arc–line–arc fit
FIT_MAX_ITER = 200  # SLP iterations per start of the minimax / one-sided fits
FIT_POINTS_MAX = 5000
"""The most flank points the arc fit takes. The traced flank has ~0.77 points per ``n_t`` (seed002:
79 at n_t = 96, 23 111 at 30 000) and the fit's linear programs grow faster than their rows (1.4 s
at 2 316 points, 5.0 s at 7 707, 25 s at 23 111; 980 s at 282 779, n_t = 100 000): a longer flank
is thinned to every k-th point (its ends kept), the spacing a grid of ~6 500 would trace. No
bundled scene comes near it; the clearance map still checks the fitted outline on its own poses."""
SWEPT_GRID_MAX = 721
"""The most poses at which the swept-region check of the fitted flank first looks for each point's
deepest pose (the design and verify scenes' grid; a scene with fewer ``fit_check_positions`` takes those)."""

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class StageReport:
    """What one stage did: its tier, size, time and error estimate."""

    stage: str
    tier: str
    dof: int
    time_s: float
    error_estimate: float | None  # mm unless said otherwise in ``error_measure``
    error_measure: str
    note: str = ""

    def to_dict(self) -> dict:
        return {
            "tier": self.tier,
            "dof": self.dof,
            "time_s": self.time_s,
            "error_estimate": self.error_estimate,
            "error_measure": self.error_measure,
            "note": self.note,
        }


@dataclass(frozen=True, slots=True, eq=False)
class CSProfile:
    """The manufacturable CS profile: arc–line–arc fits of the flank and the outline they make.

    ``fits``: one ProfileFit per method (the report compares them); ``method``: the
    one used for CAD; ``branches``: per-branch fits where the working flank has a
    ridge (else None); ``space``/``outline``: contour chains of one space and of the
    closed CS; ``clearance``: the fitted outline against the FS tooth family.
    """

    fits: dict[str, ProfileFit]
    method: str
    branches: BranchFits | None
    space: Chain
    outline: Chain
    clearance: ClearanceMap
    positions: int
    notes: tuple[str, ...] = ()
    corners: CSChain | None = None  # the rounded corners, None for a bare cs_chain

    @property
    def flank_fit(self) -> ProfileFit | None:
        """The whole-flank fit of the CAD method (None if it failed on a flank with ridges)."""
        return self.fits.get(self.method)

    @property
    def cad_fits(self) -> tuple:
        """The fits the CAD flank is made of: one per branch, or the whole-flank fit."""
        return tuple(self.branches.fits) if self.branches is not None else (self.flank_fit,)

    @property
    def max_error_mm(self) -> float:
        return max(f.max_error_mm for f in self.cad_fits)

    @property
    def max_backlash_mm(self) -> float | None:
        b = [f.max_backlash_mm for f in self.cad_fits if f.max_backlash_mm is not None]
        return max(b) if b else None

    def to_dict(self) -> dict:
        return {
            "method": self.method,
            "fits": {m: fit.to_dict() for m, fit in self.fits.items()},
            "branches": None if self.branches is None else self.branches.to_dict(),
            "max_error_mm": self.max_error_mm,
            "rms_error_mm": float(np.sqrt(np.mean(np.concatenate([np.asarray(f.error_mm) ** 2 for f in self.cad_fits])))),
            "max_backlash_mm": self.max_backlash_mm,
            "space": self.space.to_dict(),
            "outline_elements": len(self.outline.elements),
            "outline_max_gap_mm": float(self.outline.gaps(closed=True).max()),
            "clearance_check": {"positions": self.positions, **self.clearance.to_dict()},
            "corners": None if self.corners is None else self.corners.to_dict(),
            "notes": list(self.notes),
        }


#: A fitted CS that cuts into the FS tooth by more than this (mm), or the scene's envelope
#: chord tolerance if larger, interferes: a warning, and a FAIL in the design's verdict. The
#: one-sided fit touches the envelope to within the chord tolerance, and the checks that sample
#: the fitted chain against the FS tooth see ~1 nm of numerical noise (1.39 nm on seed 002 in
#: the verify scene): 10 nm is ten times that and a hundred times below what wire EDM holds.
INTERFERENCE_TOL_MM = 1e-5


def interference_tol_mm(scene) -> float:
    return max(INTERFERENCE_TOL_MM, scene.chord_tol_mm)


#: The ratcheting model's estimate over the catalogue's ratcheting torque, the largest over sizes
#: 14-58 in each of the catalogue's ratio columns: (the column's ratio, factor, what it was measured
#: on). Measured in the verify scene on the sets ``profilegen new`` writes (the package's model of
#: the catalogue's gears; ω* = 0.6 and a 4 % rim at ratio 50) against the CSF ratcheting table
#: (:data:`profilegen.contact.catalogue.RATCHETING_TORQUE_NM`): ``python
#: tests/benchmarks/catalogue_sizes.py --scene verify --ratios 100 50 80 120 160``. Over the sizes:
#: ratio 50 1.64-2.00, 80 4.17-4.69, 100 4.47-5.06, 120 4.08-5.05, 160 2.99-3.33 (size 14 has no
#: cell at 120 and 160). The overestimate depends on the ratio, so each column has its own; between
#: two columns (no catalogue value) the larger of the two, above the largest the largest of all,
#: below ratio 50 none (no catalogue value compared: the check is not made). Until the model errs
#: on the safe side the verdict checks the bound estimate / factor — at or below every catalogue
#: value compared on the sets ``new`` writes (tests/unit/test_verdict.py lists them, earlier
#: models' too) — never the raw estimate.
RATCHETING_OVERESTIMATE = (
    (50, 439.09 / 220.0, "the largest estimate / catalogue of the ratio-50 column, sizes 14-58: size 20, 2.00"),
    (80, 515.49 / 110.0, "the largest estimate / catalogue of the ratio-80 column, sizes 14-58: size 14, 4.69"),
    (100, 425.00 / 84.0, "the largest estimate / catalogue of the ratio-100 column, sizes 14-58: size 14, 5.06"),
    (120, 605.72 / 120.0, "the largest estimate / catalogue of the ratio-120 column, sizes 17-58: size 17, 5.05"),
    (160, 732.03 / 220.0, "the largest estimate / catalogue of the ratio-160 column, sizes 20-58: size 20, 3.33"),
)
#: the largest of them (every column)
RATCHETING_MODEL_OVER_CATALOGUE = max(f for _, f, _ in RATCHETING_OVERESTIMATE)


def ratcheting_overestimate(ratio: float) -> tuple[float | None, str]:
    """The factor the verdict divides the ratcheting estimate by for a gear of ``ratio``, and its
    basis (:data:`RATCHETING_OVERESTIMATE`): a catalogue column's own; between two columns the
    larger of theirs; above the largest column the largest of all; ``(None, why)`` below the
    lowest column measured."""
    columns = RATCHETING_OVERESTIMATE
    for col, factor, basis in columns:
        if abs(ratio - col) <= 1e-9 * col:
            return factor, basis
    low = columns[0]
    if ratio < low[0]:
        return None, (f"the model's overestimate of the catalogue's ratcheting torque is measured at ratios {low[0]:g} "
                      f"and above ({low[1]:.2f}× at {low[0]:g}, on sets with the deflection and rim of profilegen "
                      f"new); at ratio {ratio:.4g} no catalogue value has been compared and no bound is known to be "
                      "conservative")
    if ratio > columns[-1][0]:
        return RATCHETING_MODEL_OVER_CATALOGUE, (
            f"above the catalogue's largest ratio ({columns[-1][0]:g}) no catalogue value: the largest factor of "
            f"every column, {RATCHETING_MODEL_OVER_CATALOGUE:.3g}")
    (a, fa, _), (b, fb, _) = next((c, d) for c, d in zip(columns, columns[1:]) if c[0] < ratio < d[0])
    return max(fa, fb), (f"no catalogue value between ratios {a:g} and {b:g}: the larger factor of the two "
                         f"columns, {max(fa, fb):.3g}")

#: the verdict's three outcomes
PASS, FAIL, INCOMPLETE = "PASS", "FAIL", "INCOMPLETE"
NOT_CHECKED = "NOT CHECKED"


@dataclass(frozen=True, slots=True)
class VerdictCheck:
    """One check of the verdict: ``status`` "PASS", "FAIL" or "NOT CHECKED"; ``value`` the
    computed number against ``required`` (``sense`` ">=" or "<=", in ``unit``; None where there
    is none); ``kind`` what it is (clearance, face, capacity, safety, ratcheting, backlash,
    stiffness, lost motion: the design sheet formats by it); ``text`` the failure in words
    (FAIL), why it was not computed (NOT CHECKED) or a note (a bound, PASS)."""

    name: str
    where: str
    status: str
    kind: str
    value: float | None = None
    required: float | None = None
    unit: str = ""
    sense: str = ">="
    text: str = ""

    @property
    def passed(self) -> bool | None:
        """True / False, or None when not checked."""
        return None if self.status == NOT_CHECKED else self.status == PASS

    def to_dict(self) -> dict:
        return {"name": self.name, "where": self.where, "status": self.status, "kind": self.kind,
                "value": self.value, "required": self.required, "unit": self.unit, "sense": self.sense,
                "text": self.text}


def _judge(name, where, kind, value, required, *, unit="", sense=">=", fail_text="", note="") -> VerdictCheck:
    ok = value >= required if sense == ">=" else value <= required
    return VerdictCheck(name, where, PASS if ok else FAIL, kind, float(value), float(required), unit, sense,
                        note if ok else fail_text)


@dataclass(frozen=True, slots=True)
class Verdict:
    """The design's checks: ``PASS`` (every check ran and passed), ``FAIL: <what failed>`` or
    ``INCOMPLETE`` (nothing failed, but a check could not be computed: NOT CHECKED, with why).

    ``checks``: every check (:class:`VerdictCheck`) — an interfering fitted CS, the FS teeth
    across the face, each load case beyond the modelled contact's capacity, each safety factor
    against the gear set's ``[requirements]``, the ratcheting bound over the momentary torque,
    backlash, clearance, stiffness and lost motion where required. ``not_modelled``: effects
    the scene left out (no loaded contact, no coning across the face, ...).

    ``passed`` is True for PASS only (an INCOMPLETE design has not passed); ``failed`` for
    FAIL; ``failures`` and ``not_checked`` the lines; ``skipped`` = ``not_checked`` (the name
    callers before the three outcomes read)."""

    checks: tuple[VerdictCheck, ...] = ()
    not_modelled: tuple[str, ...] = ()

    @property
    def failures(self) -> tuple[str, ...]:
        return tuple(c.text for c in self.checks if c.status == FAIL)

    @property
    def not_checked(self) -> tuple[str, ...]:
        return tuple(f"{c.name} at {c.where}: {c.text}" for c in self.checks if c.status == NOT_CHECKED)

    @property
    def skipped(self) -> tuple[str, ...]:
        return self.not_checked

    @property
    def status(self) -> str:
        if any(c.status == FAIL for c in self.checks):
            return FAIL
        return INCOMPLETE if any(c.status == NOT_CHECKED for c in self.checks) else PASS

    @property
    def passed(self) -> bool:
        return self.status == PASS

    @property
    def failed(self) -> bool:
        return self.status == FAIL

    def _missing(self) -> str:
        """The NOT CHECKED checks grouped by their reason: 'a, b (why); c (why)'."""
        groups: dict[str, list[str]] = {}
        for c in self.checks:
            if c.status == NOT_CHECKED:
                groups.setdefault(c.text, []).append(c.name)
        return "; ".join(f"{', '.join(dict.fromkeys(names))} ({why})" for why, names in groups.items())

    @property
    def line(self) -> str:
        """One line: ``PASS``, ``FAIL: …`` (then what was not checked) or ``INCOMPLETE — NOT
        CHECKED: …``; each followed by what the scene did not model."""
        status = self.status
        if status == FAIL:
            text = "FAIL: " + "; ".join(self.failures)
            if self.not_checked:
                text += f" — NOT CHECKED: {self._missing()}"
        elif status == INCOMPLETE:
            text = f"INCOMPLETE — NOT CHECKED: {self._missing()}"
        else:
            text = PASS
        if self.not_modelled:
            text += f" — not modelled: {', '.join(self.not_modelled)}"
        return text

    def __str__(self) -> str:
        """``print(design.verdict)``: its one :attr:`line`, as the CLI prints it."""
        return self.line

    def to_dict(self) -> dict:
        return {"status": self.status, "passed": self.passed, "line": self.line, "failures": list(self.failures),
                "not_checked": list(self.not_checked), "not_modelled": list(self.not_modelled),
                "skipped": list(self.skipped), "checks": [c.to_dict() for c in self.checks]}


def _first_note(design, prefix: str) -> str | None:
    """The first warning of ``design`` that starts with ``prefix`` (its tail, cut to a line)."""
    for w in design.warnings:
        if w.startswith(prefix):
            tail = w[len(prefix):].strip(" :")
            return tail if len(tail) <= 160 else tail[:157] + "..."
    return None


def _why_no_contact(design) -> str:
    failed = _first_note(design, "loaded contact failed, skipped")
    if failed is not None:
        return f"the loaded contact failed: {failed}"
    if design.gearset.gear.waves != 2:
        return f"the contact model is for two waves (gear.waves = {design.gearset.gear.waves})"
    scene = design.scene
    return (f"no loaded contact in this run{f', the {scene.name} scene has contact = false' if not scene.contact else ''}"
            "; profilegen design --contact runs it")


def _ratcheting_check(design, required: float, why_no_contact: str) -> VerdictCheck:
    """The ratcheting bound (estimate / :func:`ratcheting_overestimate` of the set's ratio) over the momentary
    torque (the peak torque when the set gives none), or NOT CHECKED with why: no contact, a
    scene that does not estimate it, a failed estimate, a climb that did not settle."""
    gs, scene, r = design.gearset, design.scene, design.ratcheting
    t_max, which = gs.torque.momentary_nm, "momentary"
    if t_max is None:
        t_max, which = gs.torque.peak_nm, "peak (no momentary torque given)"
    where = f"{which} {t_max:g} N·m"

    def not_checked(why):
        return VerdictCheck("ratcheting bound", where, NOT_CHECKED, "ratcheting", required=required, text=why)

    if r is None:  # checked wherever it is computed; else why not
        if design.contact is None:
            return not_checked(why_no_contact)
        if not getattr(scene, "ratcheting", False):
            return not_checked(f"the {scene.name} scene does not estimate it; the verify scene does, or a scene with "
                               "ratcheting = true")
        failed = _first_note(design, "ratcheting estimate failed, skipped")
        return not_checked("the estimate failed" + ("" if failed is None else f": {failed}"))
    criterion = None if r.climb is None else r.climb.get("criterion")
    if criterion == "end of path":  # no equilibrium just beyond the path's last point: not a limit found
        return not_checked(f"the climb did not settle: its path ended at {r.torque_nm:.4g} N·m with no equilibrium "
                           "found just beyond (a failed computation, not an estimate)")
    if criterion == "none" or not np.isfinite(r.torque_nm):
        return not_checked(f"the climb met no ratcheting criterion on its path (the {r.torque_nm:.4g} N·m left is "
                           "the linear criterion's, not the climb's)")
    ratio, why = ratcheting_overestimate(gs.ratio)
    if ratio is None:
        return not_checked(f"estimate {r.torque_nm:.4g} N·m, but {why}")
    bound = r.torque_nm / ratio
    cat = (r.catalogue or {}).get("torque_nm")
    basis = (f"bound {bound:.4g} N·m = estimate {r.torque_nm:.4g} N·m / {ratio:.3g} ({why})"
             + ("" if cat is None else f"; catalogue {float(cat):.4g} N·m"))
    return _judge("ratcheting bound", where, "ratcheting", bound / t_max, required, note=basis,
                  fail_text=f"ratcheting: the bound {bound:.4g} N·m (estimate {r.torque_nm:.4g} N·m / {ratio:.3g}) "
                            f"is {bound / t_max:.2f}× the {which.split(' ')[0]} torque {t_max:g} N·m, "
                            f"below the required {required:g}×")


def _verdict(d) -> Verdict:
    """The checks of design ``d`` (see :class:`Verdict`): the geometry's, the loaded contact's, the
    flexspline's safety factors, ratcheting, backlash, and the whole gear's stiffness and lost
    motion — each against the gear set's ``[requirements]`` — and what the run left out."""
    from ..gearset.requirements import Requirements

    req = getattr(d.gearset, "requirements", None) or Requirements()
    no_contact = _why_no_contact(d)
    checks = [*_geometry_checks(d, req), *_contact_checks(d, no_contact), *_safety_checks(d, req)]
    if req.ratcheting_margin is not None:
        checks.append(_ratcheting_check(d, req.ratcheting_margin, no_contact))
    checks += [*_backlash_checks(d, req), *_torsion_checks(d, req, no_contact)]
    return Verdict(tuple(checks), tuple(_left_out(d)))


def _geometry_checks(d, req) -> list[VerdictCheck]:
    """The fitted CS against the FS tooth (always; a clearance beyond "no cut" only when
    required), and the FS teeth across the face as they are made (modified when the face stage
    modifies them)."""
    checks: list[VerdictCheck] = []
    add = checks.append
    tol = interference_tol_mm(d.scene)
    prof = d.profile
    need = -tol if req.min_clearance_mm is None else max(-tol, req.min_clearance_mm)
    if prof is None:
        add(VerdictCheck("fitted CS clear of the FS tooth", "—", NOT_CHECKED, "clearance", required=need, unit="mm",
                         text="no CS profile was fitted"))
    else:
        c = prof.clearance.min_mm
        fail = (f"interference: the fitted CS ({prof.method}) cuts into the FS tooth by {-c * 1e3:.3g} µm" if c < -tol
                else f"smallest clearance {c * 1e3:.3g} µm, less than the required {need * 1e3:g} µm")
        add(_judge("fitted CS clear of the FS tooth", f"{prof.positions} positions", "clearance", c, need, unit="mm",
                   fail_text=fail))
    face = d.face
    if face is not None:
        mod = face.modification
        depth = face.max_interference_mm if mod is None else mod.max_interference_mm
        add(_judge("FS teeth across the face clear of the CS", f"{len(face.sections)} sections", "face", depth,
                   face.interference_tol_mm, unit="mm", sense="<=",
                   fail_text=f"interference across the face: the FS teeth cut into the one CS profile by "
                             f"{depth * 1e3:.3g} µm{'' if mod is None else ' with the tooth modification'}"))
    return checks


def _contact_checks(d, no_contact: str) -> list[VerdictCheck]:
    """The loaded contact inside the teeth it searched, at every torque of the gear set."""
    gs = d.gearset
    torques = [t for t in (gs.torque.rated_nm, gs.torque.peak_nm, gs.torque.momentary_nm) if t is not None]
    if d.contact is None:
        return [VerdictCheck("contact inside the searched teeth", ", ".join(f"{t:g}" for t in torques) + " N·m",
                             NOT_CHECKED, "capacity", text=no_contact)]
    checks = []
    for case in d.contact.cases:
        inside = case.beyond_capacity is None
        checks.append(VerdictCheck("contact inside the searched teeth", f"{case.torque_nm:g} N·m",
                                   PASS if inside else FAIL, "capacity", float(case.teeth_in_contact), None,
                                   "teeth/zone", text="" if inside else f"contact at {case.torque_nm:g} N·m beyond capacity"))
    return checks


def _safety_checks(d, req) -> list[VerdictCheck]:
    """The flexspline's safety factors, each against its ``[requirements]`` value; NOT CHECKED,
    with the reason, where a material limit is missing or the stresses were not computed."""
    from ..stress.stage import CHECK_NAMES, unsupported

    gs = d.gearset
    checks: list[VerdictCheck] = []
    add = checks.append
    if d.stress is None:
        why = unsupported(gs) or "the stresses were not computed in this run (design(stress=False))"
        for name in CHECK_NAMES:
            if req.safety(name) is not None:
                add(VerdictCheck(name, "—", NOT_CHECKED, "safety", required=req.safety(name), text=why))
        return checks
    mat = gs.material
    fatigue_missing = [k for k in ("bending_endurance_limit_mpa", "shear_endurance_limit_mpa",
                                   "ultimate_strength_mpa") if getattr(mat, k) is None]
    for c in d.stress.checks:
        where = f"{c.torque_nm:g} N·m"
        if c.value is None:
            why = (c.note or "no material limit") if "yield" in c.name else \
                "no " + ", ".join(f"material.{k}" for k in fatigue_missing) if fatigue_missing else \
                "the fatigue checks were not run"
            add(VerdictCheck(c.name, where, NOT_CHECKED, "safety", required=c.required, text=why))
        else:
            add(_judge(c.name, where, "safety", c.value, c.required,
                       fail_text=f"{c.name} safety {c.value:.2f} < {c.required:g} at {c.torque_nm:g} N·m"))
    return checks


def _backlash_checks(d, req) -> list[VerdictCheck]:
    """The fitted CS's largest one-sided backlash, when the requirements bound it."""
    if req.max_backlash_mm is None:
        return []
    prof = d.profile
    bl = None if prof is None else prof.max_backlash_mm
    if bl is None:
        return [VerdictCheck("backlash (largest)", "—", NOT_CHECKED, "backlash", required=req.max_backlash_mm,
                             unit="mm", sense="<=", text="no CS profile was fitted" if prof is None else
                             f"the {prof.method} fit leaves no one-sided backlash")]
    return [_judge("backlash (largest)", f"{prof.method} fit", "backlash", bl, req.max_backlash_mm, unit="mm",
                   sense="<=", fail_text=f"backlash {bl * 1e3:.3g} µm, more than the allowed "
                                         f"{req.max_backlash_mm * 1e3:g} µm")]


def _torsion_checks(d, req, no_contact: str) -> list[VerdictCheck]:
    """The whole gear's torsional curve: K1, K1 over the catalogue's, lost motion — each when
    the requirements ask for it."""
    checks: list[VerdictCheck] = []
    add = checks.append
    curve = d.torsional
    if d.contact is None:
        no_curve = no_contact
    else:
        failed = _first_note(d, "torsional curve (both directions, compliance chain) failed, skipped")
        no_curve = "the torsional curve was not computed" + ("" if failed is None else f": {failed}")
    head = None if curve is None else curve.headline()
    across = "" if head is None or not head.get("face_slices") else f", {head['face_slices']} face slices"
    if req.min_k1_nm_per_rad is not None:
        if head is None:
            add(VerdictCheck("stiffness K1", "—", NOT_CHECKED, "stiffness", required=req.min_k1_nm_per_rad,
                             unit="N·m/rad", text=no_curve))
        else:
            k1 = head["k1_nm_per_rad"]
            add(_judge("stiffness K1", f"whole gear{across}", "stiffness", k1, req.min_k1_nm_per_rad, unit="N·m/rad",
                       fail_text=f"stiffness K1 {k1:.3g} N·m/rad, less than the required {req.min_k1_nm_per_rad:.3g}"))
    if req.min_k1_to_catalogue is not None:
        ratio = None if head is None else (head.get("model_over_catalogue") or {}).get("K1_nm_per_rad")
        if ratio is None:
            add(VerdictCheck("K1 over the catalogue's", "—", NOT_CHECKED, "stiffness", required=req.min_k1_to_catalogue,
                             text=no_curve if head is None else "no catalogue row for this size and ratio"))
        else:
            add(_judge("K1 over the catalogue's", f"whole gear{across}", "stiffness", ratio, req.min_k1_to_catalogue,
                       fail_text=f"K1 {ratio:.2f}× the catalogue's, less than the required "
                                 f"{req.min_k1_to_catalogue:g}×"))
    if req.max_lost_motion_arcmin is not None:
        if head is None:
            add(VerdictCheck("lost motion", "—", NOT_CHECKED, "lost motion", required=req.max_lost_motion_arcmin,
                             unit="arcmin", sense="<=", text=no_curve))
        elif head["lost_motion_arcmin"] < 0.0:  # free play cannot be negative: the model's, not the gear's
            add(VerdictCheck("lost motion", f"±{head['lost_motion_torque_nm']:.3g} N·m{across}", NOT_CHECKED,
                             "lost motion", required=req.max_lost_motion_arcmin, unit="arcmin", sense="<=",
                             text=f"the torsional curve gives {head['lost_motion_arcmin']:.3g} arcmin, below zero: its "
                                  "two flanks overlap at no load, and it solves one flank at a time, so it cannot "
                                  "give the free play of a preloaded mesh (a failed computation, not a value)"))
        else:
            lm = head["lost_motion_arcmin"]
            add(_judge("lost motion", f"±{head['lost_motion_torque_nm']:.3g} N·m{across}", "lost motion", lm,
                       req.max_lost_motion_arcmin, unit="arcmin", sense="<=",
                       fail_text=f"lost motion {lm:.3g} arcmin, more than the allowed "
                                 f"{req.max_lost_motion_arcmin:g} arcmin"))
    return checks


def _left_out(d) -> list[str]:
    """What this run left out, from what it ran."""
    left = []
    if d.contact is None:
        left.append("loaded tooth contact")
    if d.face is None:
        left.append("coning across the face")
    curve = d.torsional
    if d.contact is not None and curve is None:
        left.append("the whole gear's compliance (bearing, cup, CS body)")
    elif curve is not None and d.face is not None and getattr(curve, "face", None) is None:
        left.append("the coning in the torsional curve (one section)")
    return left


@dataclass(frozen=True, slots=True, eq=False)
class Design:
    """Everything one design run produced (inputs, stage results, reports, warnings)."""

    gearset: GearSet
    scene: Scene
    tooth: ToothProfile
    deformation: DeformationFit | HarmonicDeformation
    motion: HarmonicDriveMotion
    envelope: Envelope
    form: CircularSplineForm
    stages: tuple[StageReport, ...]
    warnings: tuple[str, ...] = field(default_factory=tuple)
    profile: "CSProfile | None" = None
    rim: RimDeformation | None = None
    contact: ContactResult | None = None  # at the gear set's torques (None when the scene skips it)
    stress: StressResult | None = None  # at the gear set's torques (None when skipped)
    face: FaceWidth | None = None  # across the tooth ring (profilegen.face; the cup3d rim tier only)
    #: the whole gear's torsional curve (both directions, with the compliance chain), run with the
    #: contact; None when the contact was not run or it failed
    torsional: TorsionalCurve | None = None
    #: the ratcheting estimate and the loaded transmission error over a tooth passage, when the
    #: scene asks for them
    ratcheting: Ratcheting | None = None
    transmission: TransmissionError | None = None

    @property
    def time_s(self) -> float:
        return float(sum(s.time_s for s in self.stages))

    @property
    def verdict(self) -> "Verdict":
        """Every check of the design in one place, against the gear set's ``[requirements]``
        (see :class:`Verdict`): each computed here from what the scene ran, or NOT CHECKED
        with why."""
        return _verdict(self)

    def _repr_html_(self) -> str:
        """The design sheet and the zoomable CS space, for notebooks (plotly.js embedded, offline)."""
        from ..output.interactive import notebook_html

        return notebook_html(self, interference_tol_mm=interference_tol_mm(self.scene))

    def to_dict(self) -> dict:
        env = self.envelope
        counts = env.counts()
        return {
            "profilegen_design": 1,
            "gearset": self.gearset.to_dict(),
            "scene": {"name": self.scene.name, "description": self.scene.description},
            "derived": {
                "pitch_radius_mm": self.gearset.gear.pitch_radius_mm,
                "cs_pitch_radius_mm": self.gearset.gear.cs_pitch_radius_mm,
                "neutral_radius_mm": self.gearset.gear.neutral_radius_mm,
                "deflection_mm": self.gearset.deflection_mm,
                "ratio": self.gearset.ratio,
            },
            "stages": {s.stage: s.to_dict() for s in self.stages},
            "time_s": self.time_s,
            "tooth": self.tooth.to_dict(),
            "deformation": self.deformation.to_dict(),
            "rim": None if self.rim is None else {k: v for k, v in self.rim.to_dict().items() if k != "fem"},
            "envelope": {
                "counts": counts,
                "ridges": [r.to_dict() for r in env.ridges],
                "folds": [f.to_dict() for f in env.folds],
                "no_root_t_mm": {k: [list(map(float, iv)) for iv in v] for k, v in env.no_root.items()},
                "max_interference_mm": env.max_interference_mm,
                "chord_tol_mm": env.chord_tol_mm,
                "root_residual": env.residual,
            },
            "circular_spline": self.form.to_dict(),
            "min_clearance_mm": None if self.form.clearance is None else self.form.clearance.min_mm,
            "profile": None if self.profile is None else {
                "method": self.profile.method,
                "max_error_mm": self.profile.max_error_mm,
                "max_backlash_mm": self.profile.max_backlash_mm,
                "min_clearance_mm": self.profile.clearance.min_mm,
                "clearance_positions": self.profile.positions,
                "corners": None if self.profile.corners is None else self.profile.corners.to_dict(),
            },
            "contact": None if self.contact is None else {
                "torques_nm": self.contact.torques_nm.tolist(),
                "rotation_arcmin": [c.rotation_arcmin for c in self.contact.cases],
                "teeth_in_contact_per_zone": [c.teeth_in_contact for c in self.contact.cases],
                "zones": self.contact.zones,
                "max_tooth_force_n": [c.max_tooth_force_n for c in self.contact.cases],
                "beyond_capacity": [c.beyond_capacity for c in self.contact.cases],
                "secant_stiffness_nm_per_rad": self.contact.secant_stiffness_nm_per_rad.tolist(),
                "warnings": list(self.contact.warnings),
                "torsional": None if self.torsional is None else self.torsional.headline(),
                "ratcheting_torque_nm": None if self.ratcheting is None else self.ratcheting.torque_nm,
                "ratcheting": None if self.ratcheting is None else {
                    "torque_nm": self.ratcheting.torque_nm, "extrapolated": self.ratcheting.extrapolated,
                    "ratio_to_rated": self.ratcheting.ratio_to_rated,
                    "ratio_to_catalogue": self.ratcheting.ratio_to_catalogue,
                    "catalogue": self.ratcheting.catalogue},
                "transmission_error": None if self.transmission is None else {
                    "torque_nm": self.transmission.torque_nm, "positions": int(self.transmission.psi_rad.size),
                    "peak_to_peak_arcsec": self.transmission.peak_to_peak_arcsec,
                    "stiffness_ripple": self.transmission.stiffness_ripple},
            },
            "stress": None if self.stress is None else self.stress.headline(),
            "face": None if self.face is None else self.face.to_dict(),
            "verdict": self.verdict.to_dict(),
            "warnings": list(self.warnings),
        }


def design(
    gearset: GearSet,
    *,
    scene: str | os.PathLike | Scene | None = None,
    fit_method: str | None = None,
    progress: Callable[[str], None] | None = None,
    contact: bool | None = None,
    stress: bool = True,
    on_profile: Callable[[Design], None] | None = None,
    on_stage: Callable[[Design], None] | None = None,
) -> Design:
    """Run every stage for one gear set (see the module docstring).

    ``contact``: run the loaded tooth contact at the set's rated, peak and momentary
    torques (default: the scene's choice — ``design`` and ``verify``, not ``sketch``; it
    adds ~3 s, and its torsional stiffness is a mesh-only model, see the README).

    ``stress``: the flexspline stresses and safety checks (:mod:`profilegen.stress`; fed by
    the contact's tooth forces when the contact ran, by an estimate otherwise).

    ``fit_method`` overrides ``gearset.circular_spline.fit_method`` for the CAD profile.

    ``on_profile``: called with the design as it stands once the CS profile is fitted (no
    contact, no stresses yet), before the load stages run: the CLI's figure workers start
    drawing the profile's figures then (:class:`profilegen.output.report.FigureWorkers`).

    ``on_stage``: called with the design as it stands each time a stage adds a result the files
    draw: once the envelope is traced (no CS form yet: ``form`` is None), once the contact is
    solved and checked (with its stresses, which need only the
    contact's tooth forces and are computed then, before the contact's torsional curve), and
    once the torsional curve is there. The stage reports, warnings and numbers are
    those of the contact stage followed by the stress stage either way.

    BLAS runs single-threaded inside (``threadpoolctl``): every matrix here is small, and
    with another process on this 2-core machine OpenBLAS's spinning threads made the rim
    stage 7–13× slower (0.21 s → 1.5–2.9 s measured), the contact's blocks 8×.
    """
    import scipy.linalg  # noqa: F401 — scipy's own OpenBLAS must be loaded for the limit to reach it

    with one_blas_thread():
        return _design(gearset, scene=scene, fit_method=fit_method, progress=progress, contact=contact,
                       stress=stress, on_profile=on_profile, on_stage=on_stage)


def check_gearset(gearset: GearSet) -> None:
    """Everything :func:`design` rejects about the gear set itself, before any stage runs: the
    fields and the wave generator (checked by :class:`GearSet` when it is made) and the tooth,
    as design's first stage builds it and as the envelope stage takes it (a flank monotone in
    x). Raises the error design would raise; ``profilegen check`` and ``design`` both call it."""
    from ..profile.envelope import tooth_curves

    tooth_curves(tooth_from_gearset(gearset))


def planned_stages(gearset: GearSet, *, scene: str | os.PathLike | Scene | None = None,
                   contact: bool | None = None, stress: bool = True) -> tuple[str, ...]:
    """The names :func:`design` will pass to its ``progress`` callback, in order, for these
    arguments (a progress display's total). The contact and stress models need two waves."""
    scene = resolve_scene(gearset.scene if scene is None else scene, default=gearset.scene)
    names = ["tooth", "deformation", "envelope", "gearform", "arcfit"]
    from ..face.coning import rim_tier_for

    if not isinstance(rim_tier_for(scene, gearset), str) or scene.rim_tier == "cup3d":
        if gearset.gear.waves == 2:
            names.insert(2, "face")
    two_waves = gearset.gear.waves == 2
    if two_waves and (contact or (contact is None and scene.contact)):
        names.append("contact")
    if two_waves and stress:
        names.append("stress")
    return tuple(names)




def _stage(name: str, parent, compute: Callable, gearset: GearSet, scene: Scene, extra: tuple = (),
           on_hit: Callable[[], None] | None = None):
    """(``compute()``, its key): the stage ``name`` run, or its result from the engine's cache
    (:data:`STAGE_CACHE`; the key None without one). ``parent``: the upstream stage's key (or a
    tuple of them); ``extra``: the arguments the stage takes beside the gear set and scene;
    ``on_hit``: called instead of ``compute`` on a hit (the progress line the stage would say)."""
    cache = STAGE_CACHE.get()
    if cache is None:
        return compute(), None
    return cache.stage(name, parent, compute, gearset, scene, extra, on_hit)


def traced_form(tooth, motion: HarmonicDriveMotion, gearset: GearSet, scene: Scene,
                step: Callable[[str], None] | None = None, *,
                _parent=None) -> tuple[Envelope, CircularSplineForm, list[str]]:
    """The envelope at the scene's chord and the CS form built from it; where the trace missed a
    grazing crossing above the CS tip circle (``UnresolvedBoundaryError``), retraced at a chord
    ``RETRACE_FACTOR`` finer, up to ``RETRACES`` times, with a warning saying so.

    Why: a grazing crossing falls between grid lines only for some values of a field — the
    default set's sketch scene failed at deflection coefficient 1.002 with pressure angle 10.1°
    and at 1.003 / 10.0° while every neighbour 0.001 and 0.1° away passed; at a 4× finer chord
    (2.5e-5 mm) both design, their tip circles within 10 nm of the next finer chord's. A value
    between two that design cleanly designs too, and the user never has to tune the chord.

    ``step``: the progress callback, told "gearform" once, when the CS form is first built (a
    failure there is the gearform stage's, as the progress display says). ``_parent``: the keys
    of the tooth and deformation stages in the engine's cache (:func:`_stage`; each trace is
    looked up there by its chord)."""
    from ..profile.gearform import UnresolvedBoundaryError

    g, cs = gearset.gear, gearset.circular_spline
    chord, notes = scene.chord_tol_mm, []
    for attempt in range(RETRACES + 1):
        env, _ = _stage("envelope", _parent, lambda chord=chord: envelope_of(
            tooth, motion, cs_teeth=g.circular_spline_teeth, waves=g.waves, chord_tol_mm=chord, n_t=scene.n_t,
            n_phi=scene.n_phi), gearset, scene, (chord,))
        if attempt == 0 and step is not None:
            step("gearform")
        try:
            form = circular_spline_form(env, cs_teeth=g.circular_spline_teeth, tip_clearance_mm=cs.tip_clearance_mm,
                                        root_clearance_mm=cs.root_clearance_mm,
                                        outer_radius_mm=_half(cs.outer_diameter_mm),  # = the STEP ring's
                                        chord_tol_mm=chord)
        except UnresolvedBoundaryError as exc:
            if attempt == RETRACES:
                raise UnresolvedBoundaryError(f"{exc} (retraced at chord {chord:g} mm too)") from None
            chord /= RETRACE_FACTOR
            notes.append(f"envelope retraced at chord {chord:g} mm (the scene's {scene.chord_tol_mm:g} mm missed a "
                         f"grazing crossing above the CS tip circle: {str(exc).split(': ', 2)[-1].split(' (a grazing')[0]})")
            continue
        return env, form, notes
    raise AssertionError("unreachable")


def _design(gearset: GearSet, *, scene, fit_method, progress, contact, stress, on_profile=None,
            on_stage=None) -> Design:
    # Each stage below is one _stage(...) call: run here, or taken from the engine's stage cache
    # (profilegen.pipeline.engine) when one is active; without one, every stage runs, as it always did.
    scene = resolve_scene(gearset.scene if scene is None else scene, default=gearset.scene)
    from .budget import preflight

    preflight(gearset, scene)  # a scene too coarse for the module, or over the memory budget: named, before any stage
    step = progress or (lambda name: None)
    warnings: list[str] = list(gearset.warnings)
    stages: list[StageReport] = []

    step("tooth")
    (tooth, report), k_tooth = _stage("tooth", None, lambda: _tooth_stage(gearset), gearset, scene)
    stages.append(report)

    step("deformation")
    rim, face, k_deformation, rim_reports, rim_warnings = _deformation_stages(gearset, scene, step)
    stages += rim_reports
    warnings += rim_warnings
    deformation = rim.model
    motion = HarmonicDriveMotion.from_gearset(gearset, deformation)

    step("envelope")
    traced: list[bool] = []  # the trace ran here (not taken from the cache)

    def gearform_stage():
        env, env_report, notes, form = _envelope_stage(tooth, motion, gearset, scene, step, (k_tooth, k_deformation))
        traced.append(True)
        if on_stage is not None:  # the rim's and the envelope's figures can be drawn from here on
            on_stage(Design(gearset, scene, tooth, deformation, motion, env, None, tuple(stages) + (env_report,),
                            tuple(warnings + notes), rim=rim, face=face))
        return (env, env_report, tuple(notes)) + _gearform_stage(env, form, tooth, motion, gearset, scene)

    (env, env_report, env_notes, form, form_report, form_notes), k_form = _stage(
        "gearform", (k_tooth, k_deformation), gearform_stage, gearset, scene, on_hit=lambda: step("gearform"))
    stages.append(env_report)
    warnings += env_notes
    if on_stage is not None and not traced:  # a cached trace: the partial design now, with its form
        on_stage(Design(gearset, scene, tooth, deformation, motion, env, form, tuple(stages), tuple(warnings),
                        rim=rim, face=face))
    stages.append(form_report)
    warnings += form_notes

    step("arcfit")
    method = _fit_method(gearset, fit_method)
    (profile, report, notes), k_fit = _stage(
        "arcfit", k_form, lambda: _arcfit_stage(env, form, tooth, motion, method, gearset, scene), gearset, scene,
        (method,))
    warnings += notes
    stages.append(report)
    result = Design(gearset, scene, tooth, deformation, motion, env, form, tuple(stages), tuple(warnings), profile, rim,
                    face=face)
    if on_profile is not None:
        on_profile(result)
    return _with_load(result, k_fit, contact=contact, stress=stress, step=step, on_stage=on_stage)


def _tooth_stage(gearset: GearSet) -> tuple:
    """The FS tooth of ``gearset`` and its stage report."""
    t0 = time.perf_counter()
    tooth = tooth_from_gearset(gearset)
    return tooth, StageReport("tooth", tooth.kind, len(tooth.segments), time.perf_counter() - t0,
                              float(tooth.fit_error_mm),
                              "max distance of the input points to the smoothed flank (0 for analytic teeth)")


def _deformation_stages(gearset: GearSet, scene: Scene, step) -> tuple:
    """The FS rim's deformation (the rim stage) and, on the 3D cup, the face stage's design section:
    (rim, face or None, the deformation's stage key, the stage reports, the warnings)."""
    from ..rim.stage import solve_rim  # scipy's solvers load only when a design runs (not in the stage time)
    from ..face.coning import rim_tier_for

    tier = rim_tier_for(scene, gearset)  # design: a coarse 3D cup for the face stage

    def rim_stage():
        t0 = time.perf_counter()
        rim = solve_rim(gearset, tier=tier)
        return rim, time.perf_counter() - t0

    (rim, rim_time), k_rim = _stage("rim", None, rim_stage, gearset, scene, (tier,))
    face, face_report, k_deformation = None, None, k_rim
    if getattr(rim, "cup", None) is not None:  # the 3D cup: the face stage picks the CS's design section
        (rim, face, face_report), k_deformation = _stage("face", k_rim, lambda: _with_face(gearset, rim, step),
                                                         gearset, scene, on_hit=lambda: step("face"))
    stages = _rim_reports(rim, rim_time)
    warnings = list(rim.warnings)
    if face is not None and face_report is not None:
        stages.append(face_report)
        warnings += list(face.warnings)
    else:  # no face stage: the design section and the FS modification are not decided
        from ..face.coning import UNDECIDED

        warnings.append(UNDECIDED)
    return rim, face, k_deformation, stages, warnings


def _rim_reports(rim, rim_time: float) -> list[StageReport]:
    """The rim's stage report, and with a FEM rim the report of its deformation's Fourier fit."""
    if rim.fem is None:
        return [StageReport("rim", rim.tier.label(), 0, rim_time, None, rim.error_measure)]
    fem, fit = rim.fem, rim.model
    return [
        StageReport(
            "rim", rim.tier.label(), rim.dof, rim_time - rim.fit_time_s, rim.error_estimate_mm,
            rim.error_measure,
            f"FEM solve {rim.fem_time_s:.3f} s ({len(fem.newton_steps_mm)} Newton iterations), the rest is the "
            f"coarser-mesh solve for the error estimate; contact angle {fem.contact_angle_deg:.1f}° (ill-conditioned)"),
        StageReport(
            "deformation fit", f"Fourier, order {fit.order} (criterion {fit.selection.criterion})",
            2 * fit.order + 1, rim.fit_time_s,
            max(fit.omega_stats.max_error_mm, fit.upsilon_stats.max_error_mm),
            "max |fit − FEM sample| of ω and υ (mm)")]


def _envelope_stage(tooth, motion: HarmonicDriveMotion, gearset: GearSet, scene: Scene, step, parents) -> tuple:
    """The traced envelope, its stage report, its notes and the CS form built with the trace
    (:func:`traced_form`; ``parents``: the tooth's and the deformation's stage keys)."""
    env, form, notes = traced_form(tooth, motion, gearset, scene, step=step, _parent=parents)
    env_report = StageReport("envelope", f"traced, chord {env.chord_tol_mm:g} mm",
                             int(sum(len(p.points) for p in env.pieces)), env.time_s, env.chord_tol_mm,
                             "chord error of the traced envelope (mm)")
    if env.flank.get("chains", 1) > 1:
        notes.append(f"the swept boundary is in {env.flank['chains']} pieces; the CS outline uses the longest")
    return env, env_report, notes, form


def _gearform_stage(env: Envelope, form: CircularSplineForm, tooth, motion: HarmonicDriveMotion, gearset: GearSet,
                    scene: Scene) -> tuple:
    """The CS form with its clearance map to the FS tooth, its stage report (the minimum clearance,
    or the brute-force check's distance when the scene asks for it) and its notes."""
    t0 = time.perf_counter() - form.time_s  # the form was built with the trace (traced_form): its time counts here
    stage_checkpoint()
    cmap = clearance_map(form, tooth, motion, phi_range=env.phi_range, samples=scene.clearance_samples, threads=2)
    form = _with_clearance(form, cmap)
    error, measure = cmap.min_mm, "min signed clearance FS tooth ↔ CS outline (mm; ≈ −chord error on the working flank)"
    if scene.brute_force_check:
        from ..profile.swept import boundary_distance, swept_region

        g = gearset.gear
        region = swept_region(tooth, motion, cs_teeth=g.circular_spline_teeth, waves=g.waves, n_phi=4001)
        error = float(np.max(boundary_distance(env.flank["boundary"], region)))
        measure = ("max distance of the swept boundary to the brute-force union of 4001 tooth positions (mm); "
                   "bounded below by the brute force's own notch error, ≈ 0.6 mm / 4001 for the default set")
    form_report = StageReport("gearform", "shapely outline", len(form.outline), time.perf_counter() - t0, error,
                              measure)
    form_notes = list(form.warnings)
    if cmap.min_mm < -10 * scene.chord_tol_mm:
        form_notes.append(f"the FS tooth interferes with the CS outline by {-cmap.min_mm * 1e3:.3f} µm at "
                          f"φ = {np.degrees(cmap.at_phi):.2f}°")
    return form, form_report, tuple(form_notes)


def _fit_method(gearset: GearSet, fit_method: str | None) -> str:
    """The arc fit's method: ``fit_method``, else the gear set's; one of ``FIT_METHODS``."""
    method = fit_method or gearset.circular_spline.fit_method
    if method not in FIT_METHODS:
        raise GearSetError(f"fit method = {method!r}: must be one of {', '.join(FIT_METHODS)}")
    return method


def _arcfit_stage(env: Envelope, form: CircularSplineForm, tooth, motion: HarmonicDriveMotion, method: str,
                  gearset: GearSet, scene: Scene) -> tuple:
    """The arc–line–arc CS profile fitted to the envelope, its stage report and its notes (an
    interference of the fitted profile with the FS tooth among them)."""
    t0 = time.perf_counter()
    profile = _fit_profile(env, form, tooth, motion, method=method, positions=scene.fit_check_positions,
                           starts=scene.fit_starts,
                           cs=gearset.circular_spline)
    report = StageReport("arcfit", f"arc–line–arc, {method}", len(profile.space.elements),
                         time.perf_counter() - t0, profile.max_error_mm,
                         "max normal deviation of the fitted CS flank from the envelope (mm)")
    notes = list(profile.notes)
    if profile.clearance.min_mm < -interference_tol_mm(scene):
        notes.append(f"the fitted CS profile interferes with the FS tooth by {-profile.clearance.min_mm * 1e3:.3f} "
                     f"µm at φ = {np.degrees(profile.clearance.at_phi):.2f}° (fit method {method})")
    return profile, report, tuple(notes)


def _with_load(result: Design, k_fit, *, contact, stress, step, on_stage) -> Design:
    """``result`` (the profile's design) with the load stages: the loaded contact (asked for, or
    the scene's default) and the stresses (when asked), each through the engine's stage cache
    (``k_fit``: the arc fit's key)."""
    gearset, scene = result.gearset, result.scene
    # with a callback the stresses are computed as soon as the contact is solved (they read only its
    # tooth forces), so that their figure can be drawn while the contact stage goes on
    early = _EarlyStress(stress, on_stage) if on_stage is not None else None
    k_load, contact_ran = k_fit, []
    if contact or (contact is None and scene.contact):
        def contact_stage():
            contact_ran.append(True)
            return _contact_added(result, bool(contact), step, early)

        added, k_load = _stage("contact", k_fit, contact_stage, gearset, scene, (bool(contact),),
                               on_hit=lambda: step("contact"))
        result = _with_added(result, added)
    if not stress:
        return result
    loaded = result

    def stress_stage():
        solved = None if early is None else early.solved
        return _added(loaded, _with_stress(loaded, step, solved), ("stress",))

    added, _ = _stage("stress", k_load, stress_stage, gearset, scene, on_hit=lambda: step("stress"))
    result = _with_added(result, added)
    if on_stage is not None and result.contact is not None and not contact_ran:
        on_stage(result)  # a cached contact (the engine's): its figures from the whole design
    return result


def _contact_added(result: Design, asked: bool, step, early: "_EarlyStress | None") -> tuple:
    """What the contact stage adds to ``result`` (:func:`_added`): asked for, a failure raises; the
    scene's default, a contact model that cannot take this design leaves the profile and files
    standing, with the reason in the warnings."""
    if asked:
        after = _with_contact(result, step, early)
    else:
        try:
            after = _with_contact(result, step, early)
        except ProfilegenError as exc:
            after = replace(result, warnings=result.warnings + (f"loaded contact failed, skipped: {exc}",))
            if early is not None:  # (not reached once the stresses ran early: nothing after them raises this)
                early.solved = None
    return _added(result, after, ("contact", "torsional", "ratcheting", "transmission"))


def _added(before: Design, after: Design, names: tuple[str, ...]) -> tuple:
    """What a load stage added to ``before`` (its stage reports, warnings and the result fields
    ``names``): the value the engine's cache keeps, applied again by :func:`_with_added`."""
    return (after.stages[len(before.stages):], after.warnings[len(before.warnings):],
            tuple((n, getattr(after, n)) for n in names))


def _with_added(result: Design, added: tuple) -> Design:
    stages, warnings, fields = added
    return replace(result, stages=result.stages + stages, warnings=result.warnings + warnings, **dict(fields))


class _EarlyStress:
    """The stresses solved inside the contact stage, right after the contact solve (``on_stage``
    of :func:`design`), kept for the stress stage's report; a callback for each partial design."""

    def __init__(self, stress: bool, on_stage: Callable[[Design], None]):
        self.stress, self.on_stage = stress, on_stage
        self.solved: StressResult | None = None

    def contact_solved(self, partial: Design) -> Design:
        """``partial``: the design with its contact (no torsional curve yet); returns it with its
        stresses (when they run), after handing it to the callback."""
        if self.stress:
            from ..stress.stage import unsupported

            if not unsupported(partial.gearset):
                from ..stress import StressInput, solve_stress

                self.solved = solve_stress(StressInput.from_design(partial))
                partial = replace(partial, stress=self.solved)
        self.on_stage(partial)
        return partial


def _with_face(gearset: GearSet, rim, step):
    """The face stage (:func:`profilegen.face.face_width`) on the cup tier's 3D deformation, with
    the gear set's ``[face]`` fields: its design section (auto: chosen; the rim is then solved
    again at that section when it differs from the one the tier fitted, so the CS profile of
    the files is the chosen section's) and the FS tooth modification (both fields absent or
    "auto": computed; otherwise the given values, a missing one 0). Returns (rim, face, report)."""
    from ..face import face_width

    step("face")
    t0 = time.perf_counter()
    f = gearset.face
    design_section = "auto" if f.design_section_z_mm is None else f.design_section_z_mm
    modification: str | tuple[float, float]
    if f.taper_mm_per_mm is None and f.crowning_mm is None:
        modification = "auto"
    else:
        modification = (f.taper_mm_per_mm or 0.0, f.crowning_mm or 0.0)
    face = face_width(gearset, rim.cup, sections=f.sections, design_section=design_section, modification=modification)
    note = ""
    if rim.section_z_mm is None or abs(face.design_section_z_mm - rim.section_z_mm) > 1e-9:
        note = f"; the rim's Fourier fit moved from z = {rim.section_z_mm:g} mm to the design section"
        rim = rim.at_section(face.design_section_z_mm, waves=gearset.gear.waves)
    mod = face.modification
    report = StageReport(
        "face", f"{len(face.sections)} sections, envelope chord {face.chord_tol_mm:g} mm, map {face.map_samples} poses",
        len(face.sections), time.perf_counter() - t0, face.max_interference_mm,
        "largest interference of the FS teeth with the one CS profile over the face, unmodified teeth (mm)",
        f"design section z = {face.design_section_z_mm:g} mm ({face.design_choice}); largest backlash "
        f"{face.max_backlash_mm * 1e3:.2f} µm" + ("" if mod is None else
        f"; with the tooth modification (taper {mod.taper_mm_per_mm * 1e3:.3g} µm/mm, crowning "
        f"{mod.crowning_mm * 1e3:.3g} µm"
        + ("" if not getattr(mod, "shift_mm_per_mm", 0.0) else f", radial shift {mod.shift_mm_per_mm * 1e3:.3g} µm/mm")
        + f", {mod.source}) {mod.max_backlash_mm * 1e3:.2f} µm, interference "
        f"{mod.max_interference_mm * 1e3:.3g} µm") + note)
    return rim, face, report


def _with_stress(result: Design, step, solved=None) -> Design:
    """The stress stage; ``solved``: its result computed already (:class:`_EarlyStress`), from the
    same contact forces, reported here."""
    from ..stress import StressInput, solve_stress
    from ..stress.stage import unsupported

    reason = unsupported(result.gearset)
    if reason:
        return replace(result, warnings=result.warnings + (f"stresses skipped: {reason}",))
    step("stress")

    res = solve_stress(StressInput.from_design(result)) if solved is None else solved
    worst = res.min_safety_check
    head = "" if worst is None else f"; lowest safety factor {res.min_safety:.2f} ({worst.name})"
    report = StageReport(
        "stress", f"tooth ring + cup bottom + diaphragm, forces from {res.force_source}", len(res.checks), res.time_s,
        max(c.error_estimate_mpa for c in res.cup_bottom),
        "cup bottom: change of the von Mises maximum from the grid to its refinement (MPa)",
        f"{'all checks pass' if res.passed else 'a check FAILS'}{head}")
    return replace(result, stages=result.stages + (report,), warnings=result.warnings + res.warnings, stress=res)


def _with_contact(result: Design, step, early: "_EarlyStress | None" = None) -> Design:
    gearset, stages = result.gearset, list(result.stages)
    g = gearset.gear
    if g.waves != 2:
        note = f"loaded contact skipped: the FS half-ring model needs gear.waves = 2, got {g.waves}"
        return replace(result, warnings=result.warnings + (note,))
    step("contact")
    from ..contact import ContactInput

    t0 = time.perf_counter()
    torques = [t for t in (gearset.torque.rated_nm, gearset.torque.peak_nm, gearset.torque.momentary_nm) if t is not None]
    inputs = ContactInput.from_design(result)
    ratchet = _start_ratcheting_early(result, inputs)  # the verify scene's ratcheting, beside the contact solves
    try:
        return _with_contact_solved(result, stages, torques, inputs, t0, ratchet, early)
    except BaseException:
        if ratchet is not None:
            ratchet[0].shutdown(wait=False, cancel_futures=True)
        raise


def _searched_deep_enough(contact, inputs, torques):
    """The contact again, searched deeper, where a torque's rotation reaches past the separation
    within which the points were searched (φ · the longest lever ≥ ``max_gap_mm``: a station
    farther than that could touch — a large gear at its momentary torque, e.g. size 58 ratio 50:
    204 µm against 120): the search to 1.5 × the largest reach (at least twice as deep), at most
    twice; → (contact, a note or None). A case still beyond stays flagged (the verdict's
    "contact inside the searched teeth")."""
    from ..contact.analysis import solve_contact

    note = None
    for _ in range(2):
        reach = max(c.reach_mm for c in contact.cases)
        searched = float(contact.points.max_gap_mm)
        if reach < searched:
            break
        deeper = max(2.0 * searched, 1.5 * reach)
        note = (f"contact: the rotation reaches {reach * 1e3:.0f} µm at the longest lever arm, past the "
                f"{searched * 1e3:.0f} µm within which the points were searched: searched again to {deeper * 1e3:.0f} µm")
        contact = solve_contact(inputs, torques, max_gap_mm=deeper)
        stage_checkpoint()
    return contact, note


def _with_contact_solved(result: Design, stages, torques, inputs, t0, early, stages_early=None) -> Design:
    from ..contact.analysis import solve_contact

    contact = solve_contact(inputs, torques)  # teeth and every wave-generator ball (one-sided at its no-load gap)
    stage_checkpoint()
    contact, searched = _searched_deep_enough(contact, inputs, torques)
    rated = contact.cases[0]
    pts = contact.points
    # error estimate: the independent solve (balls settled around the active-set QP of the teeth) at the rated torque
    check = solve_contact(inputs, [rated.torque_nm], points=pts, compliance=contact.compliance,
                          solver="active_set").cases[0].solution
    diff = float(np.max(np.abs(check.force_n - rated.solution.force_n)) / max(rated.solution.max_force_n, 1e-300))
    partial = None
    if stages_early is not None:  # the stresses and the contact's figure, before the torsional curve below
        # (after the error estimate: nothing that follows can drop the contact, so neither is redone)
        t_stress = time.perf_counter()
        partial = stages_early.contact_solved(replace(result, contact=contact))
        t0 += time.perf_counter() - t_stress  # the contact stage's time without the stresses and the callback
    stage_checkpoint()
    dof = 0 if contact.compliance is None else int(sum(contact.compliance.dof.values()))
    # the whole gear in torsion: both flanks (the left one built here), the compliance chain, K1–K3
    from ..contact.chain import whole_gear_curve

    notes = list(contact.warnings) + ([searched] if searched else [])
    torsional: TorsionalCurve | None = None
    try:
        curve = whole_gear_curve(result, contact, max_gap_mm=contact.points.max_gap_mm)
    except ProfilegenError as exc:
        notes.append(f"torsional curve (both directions, compliance chain) failed, skipped: {exc}")
    else:
        torsional = curve
        notes += [f"torsional curve: {w}" for w in curve.warnings]
        if partial is not None:
            t_call = time.perf_counter()
            stages_early.on_stage(replace(partial, torsional=curve))
            t0 += time.perf_counter() - t_call
    whole = "" if torsional is None else (
        f"; whole gear K1/K2/K3 {torsional.k_nm_per_rad['total']['positive']['K1']:.3g}/"
        f"{torsional.k_nm_per_rad['total']['positive']['K2']:.3g}/"
        f"{torsional.k_nm_per_rad['total']['positive']['K3']:.3g} N·m/rad, lost motion "
        f"{torsional.lost_motion_rad['total'] * 10800 / np.pi:.3f} arcmin")
    stage_checkpoint()
    ratchet, transmission = _whole_gear_extras(result, contact, notes, early=early)
    if ratchet is not None:
        whole += f"; ratcheting ≈ {ratchet.torque_nm:.4g} N·m"
    if transmission is not None:
        whole += f"; transmission error {transmission.peak_to_peak_arcsec:.3g} arcsec p-p at the rated torque"
    stages.append(StageReport(
        "contact", f"Lemke, {pts.count} points on {pts.teeth.size} teeth and every wave-generator ball, FEM influence "
        "coefficients", dof,
        time.perf_counter() - t0, diff,
        "relative max difference of the contact forces from the independent active-set solve at the rated torque",
        f"rated {rated.torque_nm:g} N·m: {rated.teeth_in_contact} teeth per zone, rotation "
        f"{rated.rotation_arcmin:.3f} arcmin, max tooth force {rated.max_tooth_force_n:.0f} N{whole}"))
    return replace(result, stages=tuple(stages), warnings=result.warnings + tuple(notes), contact=contact,
                   torsional=torsional, ratcheting=ratchet, transmission=transmission)


def _whole_gear_extras(result: Design, contact, notes: list, early=None) -> tuple:
    """The ratcheting estimate and the loaded transmission error at the rated torque (16
    positions over a tooth passage), each when the scene asks (seconds each); a failure is a
    note, not an error. Each reports its own time in its result. Both read the design's contact
    inputs with the contact's wrap angle (without a rim FEM each would solve a flat ring for it).
    ``early``: (pool, future, catalogue) of a ratcheting already started (:func:`_start_ratcheting_early`)."""
    ratchet = transmission = None
    scene, gs = result.scene, result.gearset
    if not (getattr(scene, "ratcheting", False) or getattr(scene, "transmission_error", False)):
        return ratchet, transmission
    from ..contact import ContactInput

    inputs = ContactInput.from_design(result)
    if inputs.rim_contact_angle_rad is None and contact.compliance is not None:
        inputs = replace(inputs, rim_contact_angle_rad=float(contact.compliance.wrap_half_angle_rad))
    pool, future, cat = early if early is not None else (None, None, None)
    if getattr(scene, "ratcheting", False) and future is None:
        cat = _ratcheting_catalogue(gs)
        if getattr(scene, "transmission_error", False):  # both: the ratcheting in a forked worker meanwhile
            pool, future = _start_ratcheting(inputs, cat)
        if future is None:
            ratchet = _ratcheting(inputs, cat, notes)
    if getattr(scene, "transmission_error", False):
        from ..contact.transmission import transmission_error

        try:
            transmission = transmission_error(inputs, float(gs.torque.rated_nm), positions=16)
        except ProfilegenError as exc:
            notes.append(f"transmission error failed, skipped: {exc}")
        else:
            notes += [f"transmission error: {w}" for w in transmission.warnings]
    if future is not None:
        from concurrent.futures.process import BrokenProcessPool

        try:
            ratchet, more = future.result()
            notes += more
        except BrokenProcessPool:  # the worker died: here after all
            ratchet = _ratcheting(inputs, cat, notes)
        finally:
            if pool is not None:
                pool.shutdown()
    return ratchet, transmission


_RATCHET_JOB = None  # (inputs, catalogue) for the forked worker of _start_ratcheting


def _ratcheting_catalogue(gs):
    from ..contact.chain import catalogue_for

    row = catalogue_for(gs)
    return None if row is None or row.get("ratcheting_torque_nm") is None else {
        "torque_nm": row["ratcheting_torque_nm"], "source": row.get("ratcheting_source"),
        "size": row.get("size"), "ratio": row.get("ratio_asked", row.get("ratio"))}


def _start_ratcheting_early(result: Design, inputs):
    """(pool, future, catalogue) of the ratcheting started in a forked worker before the contact
    solves, when the scene asks for it and the transmission error and the inputs already hold
    the rim's contact angle (a rim FEM: the extras would read the same inputs); else None."""
    scene = result.scene
    if not (getattr(scene, "ratcheting", False) and getattr(scene, "transmission_error", False)
            and inputs.rim_contact_angle_rad is not None):
        return None
    cat = _ratcheting_catalogue(result.gearset)
    pool, future = _start_ratcheting(inputs, cat)
    return None if future is None else (pool, future, cat)


def _ratcheting(inputs, cat, notes: list):
    from ..contact.ratchet import ratcheting_torque

    try:
        ratchet = ratcheting_torque(inputs, catalogue=cat)
    except ProfilegenError as exc:
        notes.append(f"ratcheting estimate failed, skipped: {exc}")
        return None
    notes += [f"ratcheting: {w}" for w in ratchet.warnings]
    return ratchet


def _ratcheting_job():
    notes: list = []
    return _ratcheting(*_RATCHET_JOB, notes), notes


def _start_ratcheting(inputs, cat):
    """The ratcheting estimate in a forked worker process (while this one runs the transmission
    error): (pool, future), or (None, None) where it cannot fork (a daemonic sweep worker, no fork)."""
    import multiprocessing

    global _RATCHET_JOB
    if (os.cpu_count() or 1) < 2 or multiprocessing.current_process().daemon:
        return None, None
    from concurrent.futures import ProcessPoolExecutor

    pool = None
    try:
        _RATCHET_JOB = (inputs, cat)  # inherited by the forked worker
        pool = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("fork"))
        return pool, pool.submit(_ratcheting_job)
    except (ValueError, OSError):
        if pool is not None:
            pool.shutdown(cancel_futures=True)
        return None, None
    finally:
        _RATCHET_JOB = None


def _half(diameter_mm: float | None) -> float | None:
    return None if diameter_mm is None else diameter_mm / 2.0


def _fit_profile(env, form, tooth, motion, *, method: str, positions: int, starts: int = 3, cs=None) -> CSProfile:
    """Fit the right working flank by every method, build the CS outline from the chosen one
    (its corners rounded for wire EDM as ``cs``, the gear set's ``circular_spline``, says;
    sharp without it), and check it against the FS tooth family at ``positions`` poses."""
    from ..profile.arcfit import check_swept, fit_profile, fit_profile_per_branch, swept_depth_function
    from ..profile.rootfillet import filleted_cs_chain

    flank, thinned = _fit_points(form.working_flank["right"])
    # the swept region looked for at the scene's poses of the fitted profile's check, at most 721 (the
    # deepest pose refined between its neighbours): the sketch scene's 181 take a quarter of the grid
    swept = swept_depth_function(tooth, motion, cs_teeth=form.cs_teeth, phi_range=env.phi_range,
                                 n_grid=min(positions, SWEPT_GRID_MAX))

    # a one-sided fit touches the envelope's vertices; between them it can be inside by up to
    # the envelope's own chord error (and twice that was seen: 0.22 nm at chord 0.1 nm on seed
    # 002's verify scene), so the swept-region check allows the interference tolerance of the
    # verdict, 10 nm, or the chord error where that is larger
    tol = max(INTERFERENCE_TOL_MM, env.chord_tol_mm)
    # ridges on the fitted part of the right flank: one composite per branch is used, and one
    # composite over the whole flank (which cannot follow the kink) is only for comparison
    lo, hi = np.hypot(*flank[0]), np.hypot(*flank[-1])
    ridges: list = []
    notes = [] if thinned is None else [thinned]
    for r in env.ridges:
        if r.point[0] <= 0 or not lo < np.hypot(*r.point) < hi:
            continue
        k = int(np.argmin(np.hypot(*(flank - np.asarray(r.point)).T)))
        if MIN_BRANCH_POINTS <= k <= len(flank) - 1 - MIN_BRANCH_POINTS and all(
            abs(k - j) >= MIN_BRANCH_POINTS for j in (np.argmin(np.hypot(*(flank - np.asarray(q)).T)) for q in ridges)
        ):
            ridges.append(r.point)
        else:
            notes.append(f"the ridge at ({r.point[0]:.4f}, {r.point[1]:.4f}) mm ({r.kink_deg:.1f}°) leaves fewer than "
                         f"{MIN_BRANCH_POINTS} flank points on a branch: one composite is fitted across it")
    # the swept-region check guards the one-sided profile when it is the one used for CAD; it runs on
    # a thread of its own beside the other fits, the corners and the clearance map (mostly numpy,
    # which lets go of the interpreter: 0.03 s of the sketch scene's 0.2 s stage)
    check = swept if (method == "one_sided" and not ridges) else None
    checker = None
    fits = {}
    for m in FIT_METHODS:
        stage_checkpoint()
        try:
            fits[m] = fit_profile(flank, method=m, space_side="left", swept_tol_mm=tol, max_iter=FIT_MAX_ITER,
                                  starts=starts)
            if m == "one_sided" and check is not None:
                checker = Beside(check_swept, fits[m], check, tol)
        except ConvergenceError as exc:
            if m == method and not ridges:  # with ridges the CAD profile is the per-branch fit
                fits[m] = _fit_again(fit_profile, exc, notes, flank, method=m, space_side="left", swept=check,
                                     swept_tol_mm=tol)
                continue
            notes.append(f"the {m} fit is left out of the report: {exc}")
    branches = None
    chain = fits[method].chain if method in fits else None  # with ridges: the per-branch chain below
    if ridges:
        per_branch = {"method": method, "space_side": "left", "swept": swept if method == "one_sided" else None,
                      "swept_tol_mm": tol, "whole": False, "starts": starts}  # the whole-flank fit is fits[method]
        try:
            branches = fit_profile_per_branch(flank, ridges, max_iter=FIT_MAX_ITER, **per_branch)
        except ConvergenceError as exc:
            branches = _fit_again(lambda pts, **o: fit_profile_per_branch(pts, ridges, **o), exc, notes, flank,
                                  **per_branch)
        # each branch fit ends at the foot of its own last point: at a ridge the two fits
        # meet within the backlash, with the ridge's kink; a short line closes any gap
        els = list(branches.fits[0].chain.elements)
        for f in branches.fits[1:]:
            nxt = f.chain.elements
            if np.hypot(*(els[-1].end - nxt[0].start)) > 1e-12:
                els.append(Line(els[-1].end, nxt[0].start))
            els += list(nxt)
        chain = Chain(tuple(els))
    try:
        stage_checkpoint()
        corners = filleted_cs_chain(chain, tip_radius_mm=form.tip_radius_mm, root_radius_mm=form.root_radius_mm,
                                    cs_teeth=form.cs_teeth, corners="sharp" if cs is None else cs.corners,
                                    radius_mm=None if cs is None else cs.corner_radius_mm, swept=swept,
                                    swept_tol_mm=tol)
        stage_checkpoint()
        space, outline = corners.space, corners.outline
        notes += list(corners.warnings)
        cs_points = cs_local_chain(space, outline).sample(1e-7)
        stage_checkpoint()
        cmap = clearance_map(form, tooth, motion, phi_range=env.phi_range, samples=positions, cs_points=cs_points,
                             threads=2)
    except BaseException:
        if checker is not None:
            checker.result()  # the check's own error first, as when it ran before the corners
        raise
    if checker is not None:
        checker.result()
    return CSProfile(fits, method, branches, space, outline, cmap, positions, tuple(notes), corners)


def _fit_points(flank: np.ndarray) -> tuple[np.ndarray, str | None]:
    """``flank`` as the arc fit takes it: at most :data:`FIT_POINTS_MAX` points (every k-th, both
    ends kept), and a note when it was thinned (None otherwise)."""
    n = len(flank)
    if n <= FIT_POINTS_MAX:
        return flank, None
    step = math.ceil((n - 1) / (FIT_POINTS_MAX - 1))
    keep = np.unique(np.r_[np.arange(0, n, step), n - 1])
    return flank[keep], (f"the arc fit took every {step}th of the flank's {n} traced points ({len(keep)}, at most "
                         f"{FIT_POINTS_MAX}: a finer n_t adds points, not accuracy, and the fit's cost grows faster "
                         f"than its points); the clearance map checks the fitted outline on its own")


#: the CAD fit's second try when the first does not converge (:func:`_fit_again`): more SLP
#: iterations, more minimax starts, other perturbations
FIT_RETRY = {"max_iter": 4 * FIT_MAX_ITER, "starts": 6, "seed": 1}


def _fit_again(fit, first: ConvergenceError, notes: list, flank, **options):
    """The CAD method's fit tried again with :data:`FIT_RETRY` after ``first`` failed (a start that
    had not converged within FIT_MAX_ITER: no cliff under a slider, where a neighbouring value
    converges at once), with a note; ``first`` again, with both tries named, if it fails too."""
    try:
        result = fit(flank, **{**options, **FIT_RETRY})  # its starts over the scene's
    except ConvergenceError as exc:
        raise ConvergenceError(f"{first} (tried again with {FIT_RETRY['max_iter']} SLP iterations and "
                               f"{FIT_RETRY['starts']} starts: {str(exc).split(';')[0]})") from None
    notes.append(f"the {options['method']} fit converged on a second try ({FIT_RETRY['max_iter']} SLP iterations, "
                 f"{FIT_RETRY['starts']} starts): the first stopped with {str(first).split(';')[0]}")
    return result


def _with_clearance(form: CircularSplineForm, cmap) -> CircularSplineForm:
    from dataclasses import replace

    return replace(form, clearance=cmap)
