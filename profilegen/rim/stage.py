"""The rim stage: ``solve_rim(gearset, tier=...) -> RimDeformation`` (ω, υ samples + fits).

Tiers (docs/reference/scenes.md; numbers from ``python tests/benchmarks/rim.py``):

========  ===========================================================  ==========================
tier      rim model                                                    fit
========  ===========================================================  ==========================
sketch    ring theory, ω = w0 cos Uφ, υ = −(w0/U) sin Uφ (analytic)    none (it is the model)
design    flat ring FEM, geometrically nonlinear, unilateral contact   Fourier, order ≤ 32
verify    toothed-rim FEM, nonlinear, refined (also named ``toothed``)   Fourier + general sine
cup3d     the 3D cup: body of revolution, Fourier harmonics of 2D      Fourier at the design
          meridional FEM, pressed onto the contour over the bearing    section + general sine
          width (unilateral, frictionless, exact gap; geometrically
          nonlinear: St Venant–Kirchhoff by harmonic balance)
========  ===========================================================  ==========================

The ``cup3d`` tier (:func:`profilegen.rim.cup.press_cup` on the gear set's contour, its
``[cup]`` geometry) keeps the whole 3D answer on the result (``cup``: ω, υ, axial
displacement, tilt at any (φ, z); ``cup_contact``: the contact state) and gives the
kinematics the Fourier fit of one section, ``section_z_mm`` (``solve_rim(z_mm=...)``;
default the gear set's ``[face] design_section_z_mm`` where it has one, else the mid-face
z = l; z from the cup bottom's mid-plane). Its ``fem`` is a :class:`CupSection`: that
section's samples in the shape of the 2D tiers' ring solution, so the report, the plots and
the contact stage read it as they read a ring. Its error estimate is the largest change of
ω or υ over the tooth ring (11 sections) against half the meridional resolution *and* half the
collocation angles (4 mm, 8 angles for the tier's 2 mm, 16).

Every FEM tier reports an error estimate: the largest change of ω or υ on the neutral line
when the circumferential divisions are halved (flat ring: the mesh-convergence error of the
coarser mesh; that of the tier's own mesh is smaller, by ~2^p − 1 with p ≈ 2–3 observed) or,
on the toothed rim, when the element columns per pitch go from 16 to 14 (a mesh that
cannot be halved: 14 is the fewest the default tooth takes). The FEM
models need two symmetry planes (U = 2); other wave counts fall back to ring theory with
a warning. The contour comes from :func:`profilegen.geometry.wavegen.from_gearset`.

The toothed tier lets only the bore nodes within the wrap + 10° (:data:`WRAP_MARGIN_RAD`)
carry a contact force: the wrap of a cheap flat-ring pass (2 × 32), for the tier's mesh and
its coarse companion alike. ``solve_ring`` checks that the converged contact needs no
dropped node and widens the set otherwise (a log line says so); the answer is the whole
bore's to the contact's 1e-9 mm gap tolerance (``python tests/benchmarks/toothed_rim.py``).
Its bore compliance is solved column by column as the contact asks for it (~80–150 of the
1228 kept nodes per factor, ``solve_ring(lazy_columns=...)``), and the coarse companion is
solved in a forked worker process while this one solves the fine mesh and fits it.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..geometry import series
from ..geometry.deformation import ring_theory
from ..blas import forget_blas_controller, one_blas_thread
from .ring import WRAP_WARNING, RingResult, solve_ring

if TYPE_CHECKING:  # pragma: no cover
    from ..geometry.deformation import HarmonicDeformation
    from ..gearset import GearSet
    from ..geometry.series import DeformationFit, GeneralSineDeformation
    from .cup.contact import CupContact
    from .cup.fourier import CupDeformation

__all__ = ["RIM_TIERS", "CupSection", "RimDeformation", "RimTier", "design_section_z", "one_period", "solve_rim"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class RimTier:
    """Model and mesh of one rim tier."""

    name: str
    model: str  # "ring theory" | "flat" | "toothed" | "cup"
    geometry: str = "nonlinear"
    layers: int = 4
    divisions: int = 64
    max_order: int = 32
    sine_fit: bool = False  # also fit seed 004's general sine series (reported, not used)
    tooth_layers: int = 2
    per_pitch: int = 16  # toothed: element columns per tooth pitch (≥ 14 for the default DCTA tooth)
    element_mm: float = 2.0  # cup: element size along the meridian (mm)
    angles: int = 16  # cup: collocation angles of the contact on 0..π/2 (harmonics 0, 2, …, 2(angles − 1))
    gap: str = "exact"  # cup: the contact gap, "exact" (along the contour normal, as the 2D ring) or "first_order"

    def label(self) -> str:
        if self.model == "ring theory":
            return "ring theory (analytic)"
        if self.model == "cup":
            return (f"{self.geometry} 3D cup, Fourier harmonics of meridional FEM ({self.element_mm:g} mm, "
                    f"{self.layers} layers, {self.angles} contact angles, {self.gap.replace('_', '-')} gap)")
        mesh = (f"{self.layers}×{self.divisions}" if self.model == "flat"
                else f"toothed, {self.per_pitch}/pitch, {self.layers}+{self.tooth_layers} layers")
        return f"{self.geometry} {self.model} ring FEM ({mesh})"


RIM_TIERS: dict[str, RimTier] = {
    "sketch": RimTier("sketch", "ring theory"),
    "design": RimTier("design", "flat", layers=4, divisions=64, max_order=32),
    "verify": RimTier("verify", "toothed", layers=2, divisions=0, max_order=40, sine_fit=True,
                      tooth_layers=2, per_pitch=16),
    "toothed": RimTier("toothed", "toothed", layers=2, divisions=0, max_order=40, sine_fit=True,
                       tooth_layers=2, per_pitch=16),  # the verify tier by its model's name
    "cup3d": RimTier("cup3d", "cup", geometry="nonlinear", layers=2, divisions=0, max_order=16, sine_fit=True,
                     element_mm=2.0, angles=16, gap="exact"),
}
#: the cup tier's coarse companion (the error estimate): this factor × the element size, ÷ it the angles
CUP_COARSENING = 2
#: sections of the tooth ring over which the cup tier's error estimate is taken
CUP_ERROR_SECTIONS = 11


@dataclass(frozen=True, slots=True, eq=False)
class CupSection:
    """The 3D cup at one axial section z, in the shape of a 2D tier's ring solution (what the
    report, the plots and the contact stage read from ``RimDeformation.fem``).

    ``phi_rad``, ``omega_mm``, ``upsilon_mm``: the neutral surface r = r_m at z, 0 ≤ φ ≤ π/2;
    ``bore_omega_mm``: the bore's radial displacement there. ``contact_phi_rad``: the contact
    angles (0..π/2) at which the cam presses the bore anywhere on the bearing band,
    ``contact_force_n`` the cam's radial force at each, summed over the band (N, each the total
    of its four symmetric copies) — the cup's contact is not one wrap: it varies along z
    (``RimDeformation.cup_contact`` has it per band node). ``newton_steps_mm``: the nonlinear
    iteration's steps (none when linear)."""

    z_mm: float
    phi_rad: np.ndarray
    omega_mm: np.ndarray
    upsilon_mm: np.ndarray
    bore_omega_mm: np.ndarray
    contact_phi_rad: np.ndarray
    contact_force_n: np.ndarray
    max_penetration_mm: float
    dof: int
    time_s: float
    tier: str
    warnings: tuple[str, ...] = ()
    geometry: str = "linear"
    newton_steps_mm: tuple[float, ...] = ()

    def __post_init__(self):
        from ..results import readonly

        for name in ("phi_rad", "omega_mm", "upsilon_mm", "bore_omega_mm", "contact_phi_rad", "contact_force_n"):
            object.__setattr__(self, name, readonly(getattr(self, name)))
        object.__setattr__(self, "warnings", tuple(self.warnings))

    @property
    def bore_phi_rad(self) -> np.ndarray:
        return self.phi_rad

    @property
    def contact_angle_rad(self) -> float:
        """The largest contact angle from the major axis anywhere on the bearing band (rad)."""
        return float(self.contact_phi_rad.max()) if self.contact_phi_rad.size else 0.0

    @property
    def contact_angle_deg(self) -> float:
        return math.degrees(self.contact_angle_rad)

    @classmethod
    def of(cls, contact, z_mm: float, *, samples: int, tier: str) -> CupSection:
        """The section ``z_mm`` of a :class:`~profilegen.rim.cup.CupContact` at ``samples``
        equispaced angles on 0..π/2."""
        d = contact.deformation
        phi = 0.5 * math.pi * np.arange(samples) / (samples - 1)
        on = contact.active.any(axis=0)
        nonlinear = bool(getattr(contact, "nonlinear", False))
        return cls(float(z_mm), phi, d.omega(phi, z_mm), d.upsilon(phi, z_mm), d.bore_omega(phi, z_mm),
                   contact.phi_rad[on], contact.force_n.sum(axis=0)[on], contact.max_penetration_mm, d.dof,
                   contact.time_s, tier, d.warnings, "nonlinear" if nonlinear else "linear",
                   tuple(getattr(contact, "newton_steps_mm", ())))

    def to_dict(self) -> dict:
        return {
            "tier": self.tier,
            "model": "3D cup at one section: body of revolution, Fourier harmonics of meridional FEM, unilateral "
                     f"frictionless contact over the bearing width, {self.geometry}",
            "geometry": self.geometry,
            "section_z_mm": self.z_mm,
            "dof": self.dof,
            "contact_angle_deg": self.contact_angle_deg,
            "contact_angles_deg": np.degrees(self.contact_phi_rad).tolist(),
            "contact_force_n": self.contact_force_n.tolist(),
            "max_penetration_mm": self.max_penetration_mm,
            "time_s": self.time_s,
            "phi_rad": self.phi_rad.tolist(),
            "omega_mm": self.omega_mm.tolist(),
            "upsilon_mm": self.upsilon_mm.tolist(),
            "warnings": list(self.warnings),
        }


@dataclass(frozen=True, slots=True, eq=False)
class RimDeformation:
    """Result of the rim stage.

    ``model``: the deformation model the kinematics uses (a Fourier :class:`~profilegen.
    series.DeformationFit`, or ring theory). ``fem``: the FEM solution (None for ring
    theory); ``coarse``: the FEM solution on the halved mesh behind ``error_estimate_mm``.
    ``sine``: seed 004's general sine series on the same samples (verify tier) or None.
    ``reference``: ring theory with the same w0, for the report. The cup tier: ``fem`` and
    ``coarse`` are :class:`CupSection` objects at ``section_z_mm``; ``cup`` the whole 3D answer
    (:class:`~profilegen.rim.cup.CupDeformation`: ω, υ, axial, tilt at any (φ, z)),
    ``cup_contact`` its contact state (:class:`~profilegen.rim.cup.CupContact`); None for the
    2D tiers.
    """

    tier: RimTier
    model: DeformationFit | HarmonicDeformation
    fem: RingResult | CupSection | None
    coarse: RingResult | CupSection | None
    sine: GeneralSineDeformation | None
    reference: HarmonicDeformation
    fem_time_s: float
    fit_time_s: float
    error_estimate_mm: float | None
    error_measure: str
    warnings: tuple[str, ...] = field(default=())
    cup: CupDeformation | None = None
    cup_contact: CupContact | None = None
    section_z_mm: float | None = None

    @property
    def dof(self) -> int:
        return 0 if self.fem is None else self.fem.dof

    def at_section(self, z_mm: float, *, waves: int = 2) -> RimDeformation:
        """The cup tier's result with the kinematics' section moved to ``z_mm`` (mm from the cup
        bottom's mid-plane), from the same 3D solution: that section's samples (``fem``) and their
        Fourier (and general sine) fits, as :func:`solve_rim` makes them. ``coarse`` and the
        error estimate stay: it is taken over the whole tooth ring, not at one section."""
        from .cup.geometry import CupError

        if self.cup is None or self.cup_contact is None:
            raise CupError(f"at_section: the {self.tier.name} tier has one section (only the cup tier has others)")
        from .. import checks

        lo, hi = self.cup.geometry.ring_span_mm
        z = checks.number("z_mm", z_mm, "mm", lo, hi, low_open=False, high_open=False, error=CupError)
        section, fit, sine, fit_time = _section_fits(self.tier, self.cup_contact, z, waves)
        return dataclasses.replace(self, model=fit, fem=section, sine=sine, fit_time_s=fit_time, section_z_mm=z)

    @property
    def samples(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """FEM samples (φ, ω, υ) mirrored to one wave period 0 ≤ φ < π (empty for ring theory)."""
        if self.fem is None:
            return np.zeros(0), np.zeros(0), np.zeros(0)
        return one_period(self.fem)

    def to_dict(self) -> dict:
        return {
            "tier": self.tier.name,
            "model": self.tier.label(),
            "dof": self.dof,
            "fem_time_s": self.fem_time_s,
            "fit_time_s": self.fit_time_s,
            "error_estimate_mm": self.error_estimate_mm,
            "error_measure": self.error_measure,
            "fem": None if self.fem is None else self.fem.to_dict(),
            "fourier": self.model.to_dict() if hasattr(self.model, "to_dict") else None,
            "sine": None if self.sine is None else self.sine.to_dict(),
            "warnings": list(self.warnings),
            "cup": None if self.cup is None else _cup_summary(self),
        }


def _cup_summary(rim: RimDeformation) -> dict:
    """The cup tier's 3D answer in a few numbers (design.json["rim"]["cup"]): the geometry, the
    design section, ω on the axes and max |υ| at the tooth ring's diaphragm end, mid-face and
    open end, where the cam touches the bore on the axes."""
    d, c = rim.cup, rim.cup_contact
    assert d is not None  # the cup tier's
    g = d.geometry
    lo, hi = g.ring_span_mm
    phi = np.linspace(0.0, 0.5 * math.pi, 91)
    sections = []
    for where, z in (("diaphragm end", lo), ("mid-face", g.length_mm), ("open end", hi)):
        sections.append({"where": where, "z_mm": float(z), "omega_major_mm": float(d.omega(0.0, z)),
                         "omega_minor_mm": float(d.omega(0.5 * math.pi, z)),
                         "upsilon_max_mm": float(np.max(np.abs(d.upsilon(phi, z)))),
                         "axial_major_mm": float(d.axial(0.0, z)), "tilt_major_rad": float(d.tilt(0.0, z))})
    spans = {}
    if c is not None:
        for name, j in (("major_axis", 0), ("minor_axis", c.phi_rad.size - 1)):
            span = c.contact_span_mm(j)
            spans[name] = None if span is None else list(span)
    return {"geometry": g.to_dict(), "section_z_mm": rim.section_z_mm, "z_frame": "z from the cup bottom's "
            "mid-plane toward the open end (mm)", "dof": d.dof, "elements": d.elements, "element_mm": d.element_mm,
            "harmonics": d.orders.tolist(), "sections": sections, "contact_span_z_mm": spans,
            "max_penetration_mm": None if c is None else c.max_penetration_mm}


def one_period(res: RingResult | CupSection) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A ring solution's neutral-line samples (φ, ω, υ) on 0 ≤ φ ≤ π/2 mirrored to one wave
    period 0 ≤ φ < π with ω(π − φ) = ω(φ), υ(π − φ) = −υ(φ): the samples the rim stage fits."""
    phi, w, u = res.phi_rad, res.omega_mm, res.upsilon_mm
    inner = slice(1, -1)
    return (np.concatenate([phi, math.pi - phi[inner][::-1]]), np.concatenate([w, w[inner][::-1]]),
            np.concatenate([u, -u[inner][::-1]]))


def _mesh_change(fine: RingResult, coarse: RingResult) -> tuple[float, float]:
    """Largest |Δω|, |Δυ| between two meshes' neutral-line samples: at the shared angles
    where the meshes nest (a halved flat ring: every other node), else through a cubic
    spline of the coarse samples (linear interpolation would add h²ω″/8 ≈ 0.15 µm at
    64 divisions — more than the mesh error it is meant to measure)."""
    from scipy.interpolate import CubicSpline

    common, i_f, i_c = np.intersect1d(np.round(fine.phi_rad, 12), np.round(coarse.phi_rad, 12), return_indices=True)
    if common.size == coarse.phi_rad.size:
        return (float(np.max(np.abs(fine.omega_mm[i_f] - coarse.omega_mm[i_c]))),
                float(np.max(np.abs(fine.upsilon_mm[i_f] - coarse.upsilon_mm[i_c]))))
    w = CubicSpline(coarse.phi_rad, coarse.omega_mm)(fine.phi_rad)
    u = CubicSpline(coarse.phi_rad, coarse.upsilon_mm)(fine.phi_rad)
    return float(np.max(np.abs(w - fine.omega_mm))), float(np.max(np.abs(u - fine.upsilon_mm)))


WRAP_MARGIN_RAD = math.radians(10.0)  # kept bore nodes beyond the expected wrap (the toothed tier's condensation)


def _expected_wrap(gearset, tier: RimTier, contour) -> float | None:
    """The wrap (contact angle from the major axis, rad) of a cheap first pass: the flat ring
    of 2 × 32 elements with the tier's geometry — within ~2° of the toothed rim's on the
    default set (59.1° against 56.7°). Only where the toothed rim's contact is condensed
    (solve_ring checks, and widens the set if the contact needs more). None (condense onto
    every bore node) if that pass does not solve."""
    try:
        return solve_ring(gearset, contour=contour, layers=2, divisions=32,
                          geometry=tier.geometry).contact_angle_rad
    except (RuntimeError, np.linalg.LinAlgError, FloatingPointError) as exc:
        log.info("rim stage: the flat-ring pass for the wrap failed (%s): the toothed rim condensed onto every "
                 "bore node", type(exc).__name__)
        return None


def _solve(gearset, tier: RimTier, contour, *, coarse: bool, per_pitch: int | None = None,
           wrap_rad: float | None = None) -> RingResult:
    if tier.model == "flat":
        divisions = tier.divisions // 2 if coarse else tier.divisions
        return solve_ring(gearset, contour=contour, layers=tier.layers, divisions=divisions,
                          geometry=tier.geometry, tier=f"{tier.geometry} flat ring FEM")
    from ..geometry.teeth import tooth_from_gearset
    from .toothed import toothed_quarter_mesh

    # the coarse mesh has 2 columns per pitch fewer (see _toothed_per_pitch)
    fine = per_pitch or _toothed_per_pitch(gearset, tier)
    per_pitch = fine - 2 if coarse else fine
    mesh = toothed_quarter_mesh(tooth_from_gearset(gearset), gearset.gear.rim_thickness_mm,
                                rim_layers=tier.layers, tooth_layers=tier.tooth_layers, per_pitch=per_pitch)
    # the cam touches the bore only over the wrap: condense onto the bore nodes there (plus a
    # margin) instead of all 1601 of the default mesh — the same answer, checked and widened
    # by solve_ring if the contact reaches the edge of the kept nodes
    within = None if wrap_rad is None else min(0.5 * math.pi, wrap_rad + WRAP_MARGIN_RAD)
    return solve_ring(gearset, contour=contour, mesh=mesh, geometry=tier.geometry,
                      tier=f"{tier.geometry} toothed ring FEM", condense_within_rad=within)


def _toothed_per_pitch(gearset, tier: RimTier) -> int:
    """Columns per pitch of the toothed tier's mesh: the tier's, or more where the tooth needs
    them — its coarse companion (2 fewer) must still mesh the tooth (one column per flank
    piece, top land, root step, root land: 14 for the default DCTA tooth, 16 for seed 001's)."""
    from ..geometry.teeth import tooth_from_gearset
    from .toothed import least_per_pitch

    return max(tier.per_pitch, least_per_pitch(tooth_from_gearset(gearset)) + 2)


def _solve_named(gearset, tier: RimTier, contour, *, coarse: bool, per_pitch: int | None = None,
                 wrap_rad: float | None = None) -> RingResult:
    """:func:`_solve`, a solver failure turned into a :class:`~profilegen.errors.RimSolverError`
    that names the gear-set fields that decide whether the rim FEM can solve the rim.

    Measured on the flat ring (design tier): the nonlinear ring's tangent stops being positive
    definite ("k-th leading minor ... not positive definite") when the rim is thin for its
    deflection — below δ ≈ 0.3·w0 at z1 = 200, 0.6–0.8·w0 at z1 = 40–60 (the validation already
    refuses δ < 0.5·w0) — so the rim thickness, the deflection coefficient and the module are named,
    with δ/w0 and w0/r_m."""
    import numpy as np

    from ..errors import ProfilegenError, RimSolverError

    try:
        if tier.model == "toothed" and wrap_rad is None:
            wrap_rad = _expected_wrap(gearset, tier, contour)
        return _solve(gearset, tier, contour, coarse=coarse, per_pitch=per_pitch, wrap_rad=wrap_rad)
    except (ProfilegenError, np.linalg.LinAlgError, RuntimeError, FloatingPointError) as exc:
        if isinstance(exc, ProfilegenError) and not isinstance(exc, RuntimeError):
            raise  # bad input to the ring model: already a named ValueError
        g = gearset.gear
        w0 = gearset.deflection_mm
        reason = " ".join(str(exc).split()) or type(exc).__name__
        raise RimSolverError(
            f"rim stage ({tier.label()}{', coarse mesh' if coarse else ''}) failed: {reason}. Inputs that decide "
            f"this: gear.rim_thickness_mm = {g.rim_thickness_mm:g} mm (δ/w0 = {g.rim_thickness_mm / w0:.3g}), "
            f"wave_generator.deflection_coefficient = {gearset.wave_generator.deflection_coefficient:g} with "
            f"gear.module_mm = {g.module_mm:g} mm (w0 = {w0:g} mm, w0/r_m = {w0 / g.neutral_radius_mm:.3g}), "
            f"gear.flexspline_teeth = {g.flexspline_teeth}; the ring FEM needs a rim thick for its deflection "
            "(δ/w0 ≳ 0.3 at z1 = 200, ≳ 0.8 at z1 = 40) — or use the sketch scene (ring theory, no FEM)"
        ) from exc


_COARSE_JOB = None  # (gearset, tier, contour, per_pitch, wrap) for the forked worker of _solve_toothed_pair


def _coarse_job():
    gearset, tier, contour, per_pitch, wrap = _COARSE_JOB
    forget_blas_controller()  # the parent's controller describes the parent's thread pools
    with one_blas_thread():
        return _solve_named(gearset, tier, contour, coarse=True, per_pitch=per_pitch, wrap_rad=wrap)


def _solve_toothed_pair(gearset, tier: RimTier, contour, per_pitch: int, t0: float, then):
    """The toothed tier's mesh and its coarse companion (the error estimate), the coarse one in a
    forked worker process while this process solves the fine one (they share nothing but the
    flat-ring pass's wrap, solved first) and then calls ``then(fine)``: (fine, coarse, the fine
    one's time in s, what ``then`` returned).

    Both condense onto the bore nodes within that wrap + :data:`WRAP_MARGIN_RAD` (the coarse one
    had the fine one's wrap before: the kept set only decides which nodes may carry a force, and
    solve_ring widens it if the contact needs more; the answer is the same to rounding). In this
    process — a daemonic worker (a sweep's pool) cannot fork, nor can a machine without fork —
    one after the other."""
    import multiprocessing
    import os

    global _COARSE_JOB
    wrap = _expected_wrap(gearset, tier, contour)
    pool = None
    if (os.cpu_count() or 1) > 1 and not multiprocessing.current_process().daemon:
        from concurrent.futures import ProcessPoolExecutor

        try:
            _COARSE_JOB = (gearset, tier, contour, per_pitch, wrap)  # inherited by the forked worker
            pool = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("fork"))
            future = pool.submit(_coarse_job)
        except (ValueError, OSError) as exc:  # no fork here, or no process to spare
            log.info("rim stage: the coarse toothed mesh solved in this process (%s)", exc)
            if pool is not None:
                pool.shutdown(cancel_futures=True)
            pool = None
        finally:
            _COARSE_JOB = None
    try:
        fem = _solve_named(gearset, tier, contour, coarse=False, per_pitch=per_pitch, wrap_rad=wrap)
        fem_time = time.perf_counter() - t0
        after = then(fem)
        if pool is None:
            coarse = _solve_named(gearset, tier, contour, coarse=True, per_pitch=per_pitch, wrap_rad=wrap)
        else:
            from concurrent.futures.process import BrokenProcessPool

            try:
                coarse = future.result()
            except BrokenProcessPool as exc:  # the worker died (killed, out of memory): solve it here
                log.info("rim stage: the coarse toothed mesh's worker failed (%s): solved in this process", exc)
                coarse = _solve_named(gearset, tier, contour, coarse=True, per_pitch=per_pitch, wrap_rad=wrap)
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
    return fem, coarse, fem_time, after


def design_section_z(gearset, z_mm: float | None = None) -> float:
    """The section the cup tier gives the kinematics (mm, z from the cup bottom's mid-plane):
    ``z_mm``, else the gear set's ``[face] design_section_z_mm`` where it has one, else the
    mid-face ``[cup] length_mm``. Checked to lie on the tooth ring l ± b/2."""
    from .cup.geometry import CupError

    cup = gearset.cup
    if z_mm is None:
        z_mm = getattr(getattr(gearset, "face", None), "design_section_z_mm", None)
    if z_mm is None:
        return float(cup.length_mm)
    lo, hi = cup.length_mm - 0.5 * cup.face_width_mm, cup.length_mm + 0.5 * cup.face_width_mm
    from .. import checks

    return checks.number("z_mm", z_mm, "mm", lo, hi, low_open=False, high_open=False, error=CupError)


def _section_fits(tier: RimTier, contact, z_mm: float, waves: int, *, section: CupSection | None = None):
    """(section, Fourier fit, general sine fit or None, fit time in s) of the cup at ``z_mm``:
    the samples the kinematics' model is fitted to (4·max_order + 1 angles on 0..π/2)."""
    if section is None:
        section = CupSection.of(contact, z_mm, samples=4 * tier.max_order + 1, tier=tier.name)
    t0 = time.perf_counter()
    phi, w, u = one_period(section)
    with one_blas_thread():  # see solve_rim
        fit = series.fit_fourier(phi, w, u, waves=waves, max_order=tier.max_order, tier=tier.name)
        sine = None
        if tier.sine_fit:
            sine = series.GeneralSineDeformation(series.fit_sine_series(phi, w, terms=3),
                                                 series.fit_sine_series(phi, u, terms=3), waves=waves, tier=tier.name)
    return section, fit, sine, time.perf_counter() - t0


def _solve_cup(gearset, tier: RimTier, contour, z_mm: float | None, reference, warnings: list[str]) -> RimDeformation:
    """The cup tier: press_cup at the tier's mesh and at half its resolution (the estimate), the
    design section's samples fitted."""
    from ..errors import ProfilegenError, RimSolverError
    from .cup import CupGeometry, press_cup
    from .cup.bearing import cup_tier_race

    geometry = CupGeometry.from_gearset(gearset)
    race = cup_tier_race(gearset, geometry)  # the bearing's outer race on its ball row (None: a rigid band)
    z = design_section_z(gearset, z_mm)
    samples = 4 * tier.max_order + 1  # on 0..π/2: 128 per wave period, 8 per period of the highest fitted harmonic
    coarse_angles = max(2, tier.angles // CUP_COARSENING)
    runs = []
    t0 = time.perf_counter()
    for element_mm, angles in ((tier.element_mm, tier.angles), (CUP_COARSENING * tier.element_mm, coarse_angles)):
        try:
            runs.append(press_cup(geometry, contour=contour, angles=angles, element_mm=element_mm, layers=tier.layers,
                                  gap=tier.gap, nonlinear=tier.geometry == "nonlinear", race=race))
        except (ProfilegenError, np.linalg.LinAlgError, RuntimeError, FloatingPointError) as exc:
            if isinstance(exc, ProfilegenError) and not isinstance(exc, RuntimeError):
                raise
            reason = " ".join(str(exc).split()) or type(exc).__name__
            raise RimSolverError(f"rim stage ({tier.label()}, {element_mm:g} mm, {angles} angles) failed: {reason}. "
                                 f"Inputs that decide this: the [cup] geometry {geometry.to_dict()}") from exc
        if len(runs) == 1:
            fem_time = time.perf_counter() - t0
    fine, coarse = runs
    section = CupSection.of(fine, z, samples=samples, tier=tier.name)
    coarse_section = CupSection.of(coarse, z, samples=samples, tier=f"{tier.name}, coarse")
    lo, hi = geometry.ring_span_mm
    phi = section.phi_rad[:, None]
    zs = np.linspace(lo, hi, CUP_ERROR_SECTIONS)[None, :]
    a, b = fine.deformation, coarse.deformation
    error = float(max(np.max(np.abs(a.omega(phi, zs) - b.omega(phi, zs))),
                      np.max(np.abs(a.upsilon(phi, zs) - b.upsilon(phi, zs)))))
    measure = (f"max |Δω|, |Δυ| on r_m over the tooth ring ({CUP_ERROR_SECTIONS} sections, 0 ≤ φ ≤ π/2) between "
               f"this mesh ({tier.element_mm:g} mm, {tier.angles} contact angles) and one with "
               f"{CUP_COARSENING * tier.element_mm:g} mm and {coarse_angles} angles (mm; an upper estimate)")
    _, fit, sine, fit_time = _section_fits(tier, fine, z, gearset.gear.waves, section=section)
    warnings += [w_ for w_ in fine.deformation.warnings]
    warnings += [w_ for w_ in fit.warnings if not w_.startswith("order picked")]
    if fine.max_penetration_mm > 1e-6:
        warnings.append(f"the 3D cup's contact leaves {fine.max_penetration_mm * 1e3:.3g} µm penetration")
    return RimDeformation(tier, fit, section, coarse_section, sine, reference, fem_time, fit_time, error, measure,
                          tuple(warnings), cup=fine.deformation, cup_contact=fine, section_z_mm=z)


def solve_rim(gearset: GearSet, *, tier: str | RimTier = "design", z_mm: float | None = None) -> RimDeformation:
    """ω(φ), υ(φ) of the gear set's rim on its wave generator, fitted for the kinematics.

    ``z_mm``: the cup tier's design section (mm from the cup bottom's mid-plane; see
    :func:`design_section_z`); the 2D tiers have one section and ignore it."""
    from ..errors import GearSetError
    from ..geometry.wavegen import from_gearset

    if isinstance(tier, str):
        if tier not in RIM_TIERS:
            raise GearSetError(f"rim tier = {tier!r}: must be one of {', '.join(RIM_TIERS)}")
        tier = RIM_TIERS[tier]
    w0, waves = gearset.deflection_mm, gearset.gear.waves
    reference = ring_theory(w0, waves)
    warnings: list[str] = []
    if tier.model != "ring theory" and waves != 2:
        note = (f"the {tier.label()} needs two symmetry planes (gear.waves = 2); gear.waves = {waves}: "
                "ring theory used")
        warnings.append(note)
        log.info(note)
        tier = RIM_TIERS["sketch"]
    if tier.model == "ring theory":
        return RimDeformation(tier, reference, None, None, None, reference, 0.0, 0.0, None,
                              "none: ring theory is the model itself", tuple(warnings))

    contour = from_gearset(gearset)
    if tier.model == "cup":
        return _solve_cup(gearset, tier, contour, z_mm, reference, warnings)
    t0 = time.perf_counter()
    per_pitch = _toothed_per_pitch(gearset, tier) if tier.model == "toothed" else None  # once: it builds the tooth
    if per_pitch is not None and per_pitch != tier.per_pitch:
        warnings.append(f"the toothed rim mesh uses {per_pitch} columns per pitch instead of the tier's "
                        f"{tier.per_pitch}: this tooth's pieces need them (its coarse companion needs {per_pitch - 2})")

    def fits(fem):
        """The fine mesh's samples fitted: (Fourier fit, general sine fit or None, time in s)."""
        t0 = time.perf_counter()
        phi, w, u = one_period(fem)
        # the fits on one BLAS thread: their matrices are thin (the general sine fit's QR of
        # 6401 × 6, ~3000 times), and OpenBLAS's threads only spin against each other — on a busy
        # 2-core machine 19.7 s CPU (55 s wall) against 1.5 s (4.0 s) for the toothed tier's two
        # sine fits called outside design() (which limits BLAS itself), the same numbers
        with one_blas_thread():
            fit = series.fit_fourier(phi, w, u, waves=waves, max_order=tier.max_order, tier=tier.name)
            sine = None
            if tier.sine_fit:
                from ..geometry.series import GeneralSineDeformation, fit_sine_series

                sine = GeneralSineDeformation(fit_sine_series(phi, w, terms=3), fit_sine_series(phi, u, terms=3),
                                              waves=waves, tier=tier.name)
        return fit, sine, time.perf_counter() - t0

    if tier.model == "toothed":  # the fits made while the coarse mesh's worker still solves
        assert per_pitch is not None
        fem, coarse, fem_time, (fit, sine, fit_time) = _solve_toothed_pair(gearset, tier, contour, per_pitch, t0,
                                                                           fits)
    else:
        fem = _solve_named(gearset, tier, contour, coarse=False, per_pitch=per_pitch)
        fem_time = time.perf_counter() - t0
        coarse = _solve_named(gearset, tier, contour, coarse=True, per_pitch=per_pitch)
        fit, sine, fit_time = fits(fem)
    d_w, d_u = _mesh_change(fem, coarse)
    error = float(max(d_w, d_u))
    if tier.model == "flat":
        measure = ("max |Δω|, |Δυ| on the neutral line between this mesh and one with half the circumferential "
                   "divisions (mm; an upper estimate of this mesh's discretisation error)")
    else:
        assert per_pitch is not None  # the toothed tier's
        measure = (f"max |Δω|, |Δυ| on the neutral line between {per_pitch} and {per_pitch - 2} element columns "
                   "per tooth pitch (mm)")
    # "order picked = max_order": the wrap edge (a jump of ω'') holds every harmonic; the fit
    # residual is reported as the fit stage's error instead of as a warning
    warnings += [w_ for w_ in fem.warnings if w_ != WRAP_WARNING]
    warnings += [w_ for w_ in fit.warnings if not w_.startswith("order picked")]
    return RimDeformation(tier, fit, fem, coarse, sine, reference, fem_time, fit_time, error, measure,
                          tuple(warnings))
