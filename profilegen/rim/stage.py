"""The rim stage: ``solve_rim(gearset, tier=...) -> RimDeformation`` (ω, υ samples + fits).

Tiers (DESIGN.md "Scenes"; numbers from ``python tests/benchmarks/rim.py``):

========  ===========================================================  ==========================
tier      rim model                                                    fit
========  ===========================================================  ==========================
sketch    ring theory, ω = w0 cos Uφ, υ = −(w0/U) sin Uφ (analytic)    none (it is the model)
design    flat ring FEM, geometrically nonlinear, unilateral contact   Fourier, order ≤ 32
verify    toothed-rim FEM, nonlinear, refined                          Fourier + general sine
========  ===========================================================  ==========================

Every FEM tier reports an error estimate: the largest change of ω or υ on the neutral line
when the circumferential divisions are halved (flat ring: the mesh-convergence error of the
coarser mesh; that of the tier's own mesh is smaller, by ~2^p − 1 with p ≈ 2–3 observed) or,
on the toothed rim, when the element columns per pitch go from 16 to 14 (a mesh that
cannot be halved: 14 is the fewest the default tooth takes). The FEM
models need two symmetry planes (U = 2); other wave counts fall back to ring theory with
a warning. The contour comes from :func:`profilegen.wavegen.from_gearset`.

The toothed tier condenses the rim only onto the bore nodes within the wrap + 10°
(:data:`WRAP_MARGIN_RAD`): the wrap of a cheap flat-ring pass (2 × 32) for the tier's mesh,
that of the tier's mesh for its coarse companion. ``solve_ring`` checks that the converged
contact needs no dropped node and widens the set otherwise (a log line says so); the
answer is the whole bore's to the contact's 1e-9 mm gap tolerance (``python tests/
benchmarks/toothed_rim.py``).
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field

import numpy as np

from .. import series
from ..deformation import ring_theory
from .ring import WRAP_WARNING, RingResult, solve_ring

__all__ = ["RIM_TIERS", "RimDeformation", "RimTier", "one_period", "solve_rim"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class RimTier:
    """Model and mesh of one rim tier."""

    name: str
    model: str  # "ring theory" | "flat" | "toothed"
    geometry: str = "nonlinear"
    layers: int = 4
    divisions: int = 64
    max_order: int = 32
    sine_fit: bool = False  # also fit seed 004's general sine series (reported, not used)
    tooth_layers: int = 2
    per_pitch: int = 16  # toothed: element columns per tooth pitch (≥ 14 for the default DCTA tooth)

    def label(self) -> str:
        if self.model == "ring theory":
            return "ring theory (analytic)"
        mesh = (f"{self.layers}×{self.divisions}" if self.model == "flat"
                else f"toothed, {self.per_pitch}/pitch, {self.layers}+{self.tooth_layers} layers")
        return f"{self.geometry} {self.model} ring FEM ({mesh})"


RIM_TIERS: dict[str, RimTier] = {
    "sketch": RimTier("sketch", "ring theory"),
    "design": RimTier("design", "flat", layers=4, divisions=64, max_order=32),
    "verify": RimTier("verify", "toothed", layers=2, divisions=0, max_order=40, sine_fit=True,
                      tooth_layers=2, per_pitch=16),
}


@dataclass(frozen=True, slots=True, eq=False)
class RimDeformation:
    """Result of the rim stage.

    ``model``: the deformation model the kinematics uses (a Fourier :class:`~profilegen.
    series.DeformationFit`, or ring theory). ``fem``: the FEM solution (None for ring
    theory); ``coarse``: the FEM solution on the halved mesh behind ``error_estimate_mm``.
    ``sine``: seed 004's general sine series on the same samples (verify tier) or None.
    ``reference``: ring theory with the same w0, for the report.
    """

    tier: RimTier
    model: object
    fem: RingResult | None
    coarse: RingResult | None
    sine: object
    reference: object
    fem_time_s: float
    fit_time_s: float
    error_estimate_mm: float | None
    error_measure: str
    warnings: tuple[str, ...] = field(default=())

    @property
    def dof(self) -> int:
        return 0 if self.fem is None else self.fem.dof

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
        }


def one_period(res: RingResult) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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
    from ..teeth import tooth_from_gearset
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
    from ..teeth import tooth_from_gearset
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


def solve_rim(gearset, *, tier: str | RimTier = "design") -> RimDeformation:
    """ω(φ), υ(φ) of the gear set's rim on its wave generator, fitted for the kinematics."""
    from ..errors import GearSetError
    from ..wavegen import from_gearset

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
    t0 = time.perf_counter()
    per_pitch = _toothed_per_pitch(gearset, tier) if tier.model == "toothed" else None  # once: it builds the tooth
    if per_pitch is not None and per_pitch != tier.per_pitch:
        warnings.append(f"the toothed rim mesh uses {per_pitch} columns per pitch instead of the tier's "
                        f"{tier.per_pitch}: this tooth's pieces need them (its coarse companion needs {per_pitch - 2})")
    fem = _solve_named(gearset, tier, contour, coarse=False, per_pitch=per_pitch)
    fem_time = time.perf_counter() - t0
    coarse = _solve_named(gearset, tier, contour, coarse=True, per_pitch=per_pitch,
                          wrap_rad=fem.contact_angle_rad if tier.model == "toothed" else None)
    d_w, d_u = _mesh_change(fem, coarse)
    error = float(max(d_w, d_u))
    measure = ("max |Δω|, |Δυ| on the neutral line between this mesh and one with half the circumferential "
               "divisions (mm; an upper estimate of this mesh's discretisation error)" if tier.model == "flat" else
               f"max |Δω|, |Δυ| on the neutral line between {per_pitch} and {per_pitch - 2} element columns per "
               "tooth pitch (mm)")
    t0 = time.perf_counter()
    phi, w, u = one_period(fem)
    fit = series.fit_fourier(phi, w, u, waves=waves, max_order=tier.max_order, tier=tier.name)
    sine = None
    if tier.sine_fit:
        from ..series import GeneralSineDeformation, fit_sine_series

        sine = GeneralSineDeformation(fit_sine_series(phi, w, terms=3), fit_sine_series(phi, u, terms=3),
                                      waves=waves, tier=tier.name)
    fit_time = time.perf_counter() - t0
    # "order picked = max_order": the wrap edge (a jump of ω'') holds every harmonic; the fit
    # residual is reported as the fit stage's error instead of as a warning
    warnings += [w_ for w_ in fem.warnings if w_ != WRAP_WARNING]
    warnings += [w_ for w_ in fit.warnings if not w_.startswith("order picked")]
    return RimDeformation(tier, fit, fem, coarse, sine, reference, fem_time, fit_time, error, measure,
                          tuple(warnings))
