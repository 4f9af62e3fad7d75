"""A study: load across the face as N axial slices in parallel, each with its own gaps (first order).

The product's model of the face is the torsional curve's slices
(:mod:`profilegen.contact.face_curve`: exact kinematics per slice, the balls one-sided with their
Hertz springs, the rim coupling the slices). This study came first: it measured how coning
concentrates the load along the face with first-order gap shifts and the contact stage's ball
set held rigid, and both flanks' preload where coning makes them overlap. Its numbers are in
docs/catalogue_comparison.md ("Coning across the face"); ``python tests/benchmarks/face_load.py``
reproduces them. The sections it places the tooth in are the product's
(:mod:`profilegen.contact.coning_sections`).

The model of this study, in full:

The loaded contact (:mod:`profilegen.contact.analysis`) solves one section and spreads it
evenly across the face: the compliance is S = S_2D/b (b the face width) and every axial
position has the design section's initial gaps. The cup does not deform alike along its
axis: ω(φ, z), υ(φ, z) of the 3D cup (:func:`profilegen.rim.cup.contact.press_cup`) grow
from the diaphragm end toward the open end (coning), so each axial position of a tooth
stands a little higher or lower in its CS space than the design section did.

The model
---------
N slices of width b/N at z_i = z_0 − b/2 + (i + ½) b/N (z_0 the design section, the mid-face
``cup.length_mm`` of :class:`~profilegen.rim.cup.geometry.CupGeometry`). Slice i is the 2D
contact with

* the compliance of a slice b/N wide: N·S (the 2D plane-stress compliance is per unit width),
  and no coupling to the other slices (``coupling_length_mm`` = 0; see below);
* the initial gaps e_k + Δe_ki, Δe_ki = −n_k · (p_k(z_i) − p_k(z_0)): the change of the FS
  flank point p_k (tooth-frame station ``points.local_mm``, placed in the CS frame with the
  exact pose of docs/theory/envelope.md, "Kinematics") when the deformation of section z_i replaces that of
  z_0, along the common normal n_k (out of the FS tooth, the direction the FS pushes). It
  is the first-order change of the separation, and exact to first order at a separation's
  local minimum (the stations there are the minima: :mod:`profilegen.contact.points`),
  where the foot of the normal slides along the flanks without changing the distance;
* all slices share the rigid rotation φ of the FS against the CS, and the zone torque
  T/U = Σ_i Σ_k r_k F_ki.

It is one complementarity problem in N·n unknowns with block-diagonal compliance
diag(N·S, …, N·S), solved by the package's Lemke solver
(:func:`~profilegen.contact.solvers.solve_lemke`). With identical slices (Δe = 0) it is the
2D solve exactly: F_ki = F_k/N, the same φ (the 2D gaps and complementarity hold slice by
slice; the solution is unique). Where coning makes a slice's gap negative (the FS tooth
would overlap the CS flank at no load) the problem is still the same convex QP: the
separations are shifted by the smallest one, which moves φ by that amount and nothing else
(:mod:`profilegen.contact.solvers`, "Scaling").

Sections
--------
:func:`cup_sections`: the 3D cup's sections at the slices (its Fourier harmonics
interpolated in z as the cup's own elements do), as the kinematics' harmonic deformation;
the reference is the cup's section at z_0, so only the *change* along the face enters —
the design's own 2D deformation stays the one the CS was generated with.
:func:`semi_membrane_sections`: the analytic check (docs/theory/cup.md):
the wall inextensible along its generators and in shear, ω(φ, z) = ω(φ, z_0)·z/z_0 and
υ likewise, z from the cup bottom.

What is neglected, and its bound
--------------------------------
* **Coupling between slices.** The slices are independent springs (a Winkler foundation
  along the face, as ISO 6336's face-load factor K_Hβ treats the mesh); the tooth and the
  rim are plates/shells that carry load between neighbouring slices. ``coupling_length_mm``
  λ > 0 couples them as a Pasternak foundation: the slices' compliance becomes
  N·(I + (λ/Δz)² L)⁻¹ ⊗ S (L the chain Laplacian of the slices with free ends, Δz = b/N),
  whose rows sum to N·S — an even load still gives the 2D solution — while a load that
  varies along the face meets a stiffer structure. A smooth gap pattern (coning is nearly
  linear in z) therefore needs a *larger* load variation to close, and the coupled structure
  adds line loads at the face ends (the Pasternak edge term). Measured on seed000_csf40
  (``tests/benchmarks/face_load.py``): at the rated torque the peak line load is 1.72× the
  even spread's with independent slices, 1.77× with λ = the tooth height (1 mm), 5.8× with
  λ = √(r_m δ) = 8.4 mm (the rim as a cylindrical shell, applied to the whole S, an upper
  bound since the tooth's local compliance does not couple): the independent slices do not
  overstate the concentration of a coning gap pattern, they understate it.
* **The opposite flank.** :func:`solve_face` models one flank (as the 2D contact). Where
  coning makes the gap negative on the loaded flank it does on the other flank too (the
  tooth moves radially into the CS space). :func:`solve_two_flanks` / :func:`face_two_flanks`
  solve both: the overlap then preloads both flanks at zero torque, and how much depends on
  the radial support of the rim along the face, which the slices (each the design section on
  its balls) do not model — on seed000_csf40 84–625 N·m per flank and zone for Hertz-spring
  to rigid balls. The one-flank loads are the loaded flank's redistribution with that preload
  left out.
* **The cup's own radial compliance between slices.** A slice's compliance is the design
  section's (rim on the balls, per unit width); the cup wall's axial bending, which would
  let an overloaded slice's rim give way radially, is the coupling above.
* The deformation of the cup under the tooth forces themselves (the cup sections are those
  of the cup pressed onto the cam at no torque).

The balls, and the teeth these numbers are for
----------------------------------------------
:func:`face_load` holds the balls the 2D solve loads at that torque as rigid supports in every
slice (the contact stage's model, :func:`~profilegen.contact.analysis.solve_contact`). The
torsional curve's model — every ball one-sided at its no-load gap with its Hertz spring, in
every slice — is :mod:`profilegen.contact.face_curve` (``torsional_curve(face_slices=...)``),
which also takes the face stage's design section and tooth modification. The 1.72× above is
for the design scene's straight teeth with the CS conjugate to mid-face, which coning makes
interfere on both flanks at the face ends; for the gear as the face stage makes it (seed000:
CS at the open end, taper 1.19 µm/mm) the curve's slices give 1.29× at 265 N·m
(docs/catalogue_comparison.md, "Coning across the face").
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from dataclasses import dataclass, field
from functools import partial

import numpy as np

from profilegen import checks
from profilegen.contact.coning_sections import cup_sections, semi_membrane_sections
from profilegen.errors import ProfilegenError
from profilegen.geometry.kinematics import HarmonicDriveMotion
from profilegen.results import json_ready, readonly as _readonly

__all__ = [
    "FaceLoad",
    "FaceLoadError",
    "TwoFlankFace",
    "coning_gap_shifts",
    "face_load",
    "face_two_flanks",
    "gap_shift_mm",
    "slice_coupling",
    "slice_positions",
    "solve_face",
    "solve_two_flanks",
    "two_flank_sides",
]

log = logging.getLogger(__name__)


class FaceLoadError(ProfilegenError, ValueError):
    """Bad input to the across-the-face contact; names the parameter, its value, unit and range."""


_positive = partial(checks.positive, error=FaceLoadError)
_whole = partial(checks.whole, error=FaceLoadError)
_number = partial(checks.number, error=FaceLoadError)


# --------------------------------------------------------------------------- the slices


def slice_positions(face_width_mm: float, slices: int, centre_mm: float) -> np.ndarray:
    """Mid-planes z_i = z_0 − b/2 + (i + ½) b/N of N slices of a face b wide centred on z_0 (mm)."""
    b = _positive("face_width_mm", face_width_mm)
    n = _whole("slices", slices, 1)
    z0 = _number("centre_mm", centre_mm, "mm")
    return z0 - 0.5 * b + (np.arange(n) + 0.5) * b / n


def slice_coupling(slices: int, coupling_length_mm: float, slice_width_mm: float) -> np.ndarray:
    """The slices' compliance factor K (N × N) such that slice i's deflection is Σ_j K_ij S F_j.

    λ = 0: K = N·I (independent slices, each b/N wide). λ > 0: K = N (I + (λ/Δz)² L)⁻¹ with
    L the Laplacian of the chain of slices with free ends (Pasternak foundation); L·1 = 0, so
    every row sums to N and an even load gives the 2D deflection. Symmetric positive definite."""
    n = _whole("slices", slices, 1)
    lam = _positive("coupling_length_mm", coupling_length_mm, allow_zero=True)
    dz = _positive("slice_width_mm", slice_width_mm)
    if lam == 0.0 or n == 1:
        return n * np.eye(n)
    lap = np.diag(np.r_[1.0, 2.0 * np.ones(n - 2), 1.0]) - np.eye(n, k=1) - np.eye(n, k=-1)
    kern = np.linalg.inv(np.eye(n) + (lam / dz) ** 2 * lap)
    return n * 0.5 * (kern + kern.T)


# --------------------------------------------------------------------------- gaps


def gap_shift_mm(points, motion: HarmonicDriveMotion, section, reference) -> np.ndarray:
    """Δe_k (mm): the change of each point's initial separation when the deformation
    ``section`` replaces ``reference`` (both objects with ``evaluate(phi, order)``) in the
    FS tooth's pose — Δe_k = −n_k · (p_k(section) − p_k(reference)), the points placed as
    :func:`~profilegen.contact.points.contact_points` places them (tooth i in CS space i).
    Negative: the slice's tooth stands closer to the CS flank."""
    g_rm, waves, z2 = motion.neutral_radius_mm, motion.waves, motion.cs_teeth
    m_sec = HarmonicDriveMotion(section, g_rm, waves, z2)
    m_ref = HarmonicDriveMotion(reference, g_rm, waves, z2)
    local = np.asarray(points.local_mm, dtype=float)
    phi = np.asarray(points.phi_rad, dtype=float)
    d = m_sec.pose(phi).to_cs(local) - m_ref.pose(phi).to_cs(local)  # CS space 0's frame
    angle = 2.0 * math.pi * np.asarray(points.tooth, dtype=float) / z2
    c, s = np.cos(angle), np.sin(angle)
    # turn() by a per-point angle (the package's sense: +y toward +x), as the points were
    d_turned = np.column_stack([d[:, 0] * c + d[:, 1] * s, d[:, 1] * c - d[:, 0] * s])
    return -np.einsum("ij,ij->i", np.asarray(points.normal, dtype=float), d_turned)


# --------------------------------------------------------------------------- the solve


@dataclass(frozen=True, slots=True, eq=False)
class FaceLoad:
    """The contact of one engagement zone across the face (mm, N, rad).

    ``z_mm`` (N,) the slices' mid-planes, ``slice_width_mm`` b/N; ``force_n`` (N, n): the
    normal force of point k in slice i; ``gap_shift_mm`` (N, n): Δe_ki; ``rotation_rad`` φ;
    ``first_contact_rad``: the smallest initial angular separation over every slice (the
    rotation at which the first point touches); ``zone_torque_nmm``; ``coupling_length_mm``;
    the solver's residuals; ``reference``: the same solve with even slices (Δe = 0: the
    2D contact spread evenly) as (force_n (n,), rotation_rad, first_contact_rad)."""

    z_mm: np.ndarray
    slice_width_mm: float
    tooth: np.ndarray
    lever_mm: np.ndarray
    force_n: np.ndarray
    gap_shift_mm: np.ndarray
    rotation_rad: float
    first_contact_rad: float
    zone_torque_nmm: float
    coupling_length_mm: float
    complementarity_residual: float
    equilibrium_residual: float
    reference_force_n: np.ndarray
    reference_rotation_rad: float
    reference_first_contact_rad: float
    time_s: float
    zones: int = 1
    warnings: tuple[str, ...] = field(default=())

    def __post_init__(self):
        for name in ("z_mm", "lever_mm", "force_n", "gap_shift_mm", "reference_force_n"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        object.__setattr__(self, "tooth", _readonly(self.tooth, int))

    @property
    def slices(self) -> int:
        return int(self.z_mm.size)

    @property
    def face_width_mm(self) -> float:
        return self.slice_width_mm * self.slices

    @property
    def slice_force_n(self) -> np.ndarray:
        """Total normal force on each slice (N)."""
        return self.force_n.sum(axis=1)

    @property
    def slice_line_load_n_per_mm(self) -> np.ndarray:
        """Each slice's total normal force per mm of face (N/mm); the even spread is ΣF/b."""
        return self.slice_force_n / self.slice_width_mm

    def _per_tooth(self, forces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        teeth, slot = np.unique(self.tooth, return_inverse=True)
        f = np.atleast_2d(forces)
        out = np.zeros((f.shape[0], teeth.size))
        for i in range(f.shape[0]):
            out[i] = np.bincount(slot, weights=f[i], minlength=teeth.size)
        return teeth, out

    @property
    def peak_line_load_n_per_mm(self) -> float:
        """The largest line load of one tooth in one slice: max_{tooth, i} F / (b/N) (N/mm)."""
        return float(self._per_tooth(self.force_n)[1].max() / self.slice_width_mm)

    @property
    def uniform_peak_line_load_n_per_mm(self) -> float:
        """Today's assumption: the 2D solve's largest tooth force spread evenly, max F_2D / b (N/mm)."""
        return float(self._per_tooth(self.reference_force_n)[1].max() / self.face_width_mm)

    @property
    def peak_ratio(self) -> float:
        """Peak line load across the face over the even spread's (the face-load factor K_Hβ)."""
        return self.peak_line_load_n_per_mm / self.uniform_peak_line_load_n_per_mm

    @property
    def stiffness_nm_per_rad(self) -> float:
        """Zone torque × U over the elastic rotation, T / (φ − first contact) (N·m/rad): the
        mesh's secant stiffness with the gaps across the face."""
        return self._zones_torque_nm / (self.rotation_rad - self.first_contact_rad)

    @property
    def reference_stiffness_nm_per_rad(self) -> float:
        """The same for the even spread (the 2D contact)."""
        return self._zones_torque_nm / (self.reference_rotation_rad - self.reference_first_contact_rad)

    @property
    def _zones_torque_nm(self) -> float:
        return self.zone_torque_nmm * 1e-3 * self.zones

    def to_dict(self) -> dict:
        return json_ready({
            "model": "face as N independent axial slices (compliance N·S each) sharing the rotation; slice gaps "
                     "shifted by the change of the cup deformation from the design section"
                     + (f"; Pasternak coupling λ = {self.coupling_length_mm:g} mm" if self.coupling_length_mm else ""),
            "z_mm": self.z_mm, "slice_width_mm": self.slice_width_mm,
            "slice_force_n": self.slice_force_n, "slice_line_load_n_per_mm": self.slice_line_load_n_per_mm,
            "uniform_line_load_n_per_mm": float(self.reference_force_n.sum() / self.face_width_mm),
            "peak_line_load_n_per_mm": self.peak_line_load_n_per_mm,
            "uniform_peak_line_load_n_per_mm": self.uniform_peak_line_load_n_per_mm,
            "peak_ratio": self.peak_ratio,
            "gap_shift_um_min_max": [float(self.gap_shift_mm.min() * 1e3), float(self.gap_shift_mm.max() * 1e3)],
            "rotation_rad": self.rotation_rad, "first_contact_rad": self.first_contact_rad,
            "reference_rotation_rad": self.reference_rotation_rad,
            "complementarity_residual": self.complementarity_residual,
            "equilibrium_residual": self.equilibrium_residual,
            "time_s": self.time_s, "warnings": list(self.warnings),
        })


def coning_gap_shifts(points, motion: HarmonicDriveMotion, gearset, reference_z_mm: float, z_mm, *,
                      coning: str = "cup", cup=None) -> np.ndarray:
    """Δe (len(z_mm), points.count, mm): each point's separation change (:func:`gap_shift_mm`)
    when the section at each z replaces the one at ``reference_z_mm`` — the 3D cup's sections
    (``coning="cup"``: :func:`cup_sections` of ``cup``, default press_cup of the set), the
    semi-membrane check (:func:`semi_membrane_sections`), or none (zeros)."""
    z_mm = np.asarray(z_mm, dtype=float)
    if coning == "none":
        return np.zeros((z_mm.size, points.count))
    if coning == "cup":
        if cup is None:
            from profilegen.rim.cup.contact import press_cup

            cup = press_cup(gearset)
        secs = cup_sections(cup, np.r_[reference_z_mm, z_mm])
    else:
        secs = [motion.deformation] + semi_membrane_sections(motion.deformation, z_mm, reference_z_mm)
    return np.array([gap_shift_mm(points, motion, sec, secs[0]) for sec in secs[1:]])


def _solve_slices(compliance, theta, lever, torque_nmm, coupling):
    """Lemke on the stacked slices; θ may be negative (shifted by its minimum, exact)."""
    from profilegen.contact.solvers import solve_lemke

    n_s = coupling.shape[0]
    big = np.kron(coupling, compliance)
    th = theta.ravel()
    shift = float(th.min())
    sol = solve_lemke(big, th - shift, np.tile(lever, n_s), torque_nmm)
    return sol, shift


def solve_face(points, compliance_mm_per_n, gap_shift, torque_nm: float, *, coupling_length_mm: float = 0.0,
               face_width_mm: float | None = None, z_mm=None) -> FaceLoad:
    """One zone across the face at the gear torque ``torque_nm`` (N·m; the zone takes T/U).

    ``points``: :class:`~profilegen.contact.points.ContactPoints` (or anything with ``gap_mm``,
    ``lever_mm``, ``tooth``, ``zones``); ``compliance_mm_per_n``: their n × n compliance for the
    whole face (S = S_2D/b, as the contact builds it); ``gap_shift`` (N, n) mm: Δe_ki per slice
    (zeros: identical slices). ``face_width_mm``: b, for the line loads and the coupling
    (default N mm: slices 1 mm wide); ``z_mm``: the slices' positions to report (default
    their mid-planes from 0)."""
    t0 = time.perf_counter()
    s = np.asarray(compliance_mm_per_n, dtype=float)
    e = np.asarray(points.gap_mm, dtype=float)
    r = np.asarray(points.lever_mm, dtype=float)
    n = e.size
    if s.shape != (n, n):
        raise FaceLoadError(f"compliance_mm_per_n: shape {s.shape} does not match the {n} contact points")
    de = np.atleast_2d(np.asarray(gap_shift, dtype=float))
    if de.ndim != 2 or de.shape[1] != n:
        raise FaceLoadError(f"gap_shift: shape {de.shape} must be (slices, {n}) mm")
    if not np.all(np.isfinite(de)):
        raise FaceLoadError("gap_shift: every shift must be finite (mm)")
    torque = _positive("torque_nm", torque_nm, "N·m")
    n_s = de.shape[0]
    b = float(n_s) if face_width_mm is None else _positive("face_width_mm", face_width_mm)
    dz = b / n_s
    coupling = slice_coupling(n_s, coupling_length_mm, dz)
    tz = torque / points.zones * 1e3
    theta = (e[None, :] + de) / r[None, :]
    sol, shift = _solve_slices(s, theta, r, tz, coupling)
    ref, ref_shift = _solve_slices(s, (e / r)[None, :], r, tz, np.eye(1))
    warnings = list(sol.warnings)
    if np.any(theta < 0.0):
        warnings.append(f"coning closes {int(np.count_nonzero(theta < 0.0))} of {theta.size} slice gaps below zero "
                        f"(down to {float((e[None, :] + de).min()) * 1e3:.2f} µm): those slices are preloaded at no "
                        "torque; the opposite flank, not modelled, would push back (the load there is an upper bound)")
    result = FaceLoad(
        z_mm=np.arange(n_s) * dz + 0.5 * dz if z_mm is None else np.asarray(z_mm, dtype=float), slice_width_mm=dz, tooth=np.asarray(points.tooth), lever_mm=r,
        force_n=sol.force_n.reshape(n_s, n), gap_shift_mm=de, rotation_rad=float(sol.phi_rad) + shift,
        first_contact_rad=float(theta.min()), zone_torque_nmm=tz, coupling_length_mm=float(coupling_length_mm),
        complementarity_residual=float(sol.complementarity_residual),
        equilibrium_residual=float(sol.equilibrium_residual), reference_force_n=ref.force_n,
        reference_rotation_rad=float(ref.phi_rad) + ref_shift, reference_first_contact_rad=float((e / r).min()),
        time_s=time.perf_counter() - t0, zones=int(points.zones), warnings=tuple(warnings))
    return result


def face_load(inputs, torque_nm: float, *, slices: int = 8, cup=None, coning: str = "cup",
              coupling_length_mm: float = 0.0, points=None, compliance=None, side: int = 1) -> FaceLoad:
    """The contact across the face of a design (or :class:`~profilegen.contact.inputs.ContactInput`)
    at ``torque_nm``: ``slices`` N; ``coning`` "cup" (the 3D cup's sections; ``cup`` a
    :class:`~profilegen.rim.cup.contact.CupContact` / CupDeformation, default
    :func:`~profilegen.rim.cup.contact.press_cup` of the gear set), "semi_membrane" (the
    analytic z/z_0 scaling of the design's deformation) or "none" (identical slices).
    ``points``, ``compliance``: a :class:`~profilegen.contact.compliance.ContactCompliance` and its
    points from an earlier solve, else built; the compliance's balls are settled at this
    torque on the 2D solve first (every ball one-sided at its no-load gap, the contact stage's
    model, or the window's loop) and then held (at their gaps)."""
    from profilegen.contact.analysis import solve_contact
    from profilegen.contact.inputs import ContactInput

    inputs = ContactInput.from_design(inputs, name="inputs")
    gs = inputs.gearset
    cup_geo = gs.cup
    if cup_geo is None:
        raise FaceLoadError("inputs.gearset.cup: the cup is needed for the face width and the design section")
    checks.choice("coning", coning, ("cup", "semi_membrane", "none"), error=FaceLoadError)
    b, z0 = float(cup_geo.face_width_mm), float(cup_geo.length_mm)
    z = slice_positions(b, slices, z0)
    res = solve_contact(inputs, [torque_nm], side=side, points=points, compliance=compliance)
    pts, comp = res.points, res.compliance
    assert comp is not None  # solve_contact returns the compliance it solved with
    settled = comp.with_balls(res.cases[0].ball_active)
    shifts = coning_gap_shifts(pts, inputs.motion, gs, z0, z, coning=coning, cup=cup)
    if getattr(comp, "ball_supports", "window") == "all":
        # every ball one-sided at its no-load gap (the contact stage's model): the balls the 2D solve
        # loads are held at their gaps, which moves each point's separation alike on every slice
        from profilegen.contact.reduced import ReducedZone

        _, _, theta, _ = ReducedZone(pts, comp, None)._balls(np.asarray(res.cases[0].ball_active), None)
        pts = dataclasses.replace(pts, gap_mm=pts.lever_mm * theta)
    return solve_face(pts, settled.matrix_mm_per_n, shifts, torque_nm, coupling_length_mm=coupling_length_mm,
                      face_width_mm=b, z_mm=z)


# --------------------------------------------------------------------------- both flanks


@dataclass(frozen=True, slots=True, eq=False)
class TwoFlankFace:
    """Both flanks across the face at one signed torque (mm, N, rad).

    ``rotation_rad``: φ of the FS against the CS in the package's angle sense (+y toward +x);
    ``force_n`` (N, n): per slice and point (the points of both flanks); ``sense`` (n,): +1
    for points loaded by a positive rotation, −1 for the others; ``gap_mm`` (N, n): the gaps
    after load; residuals as the contact solvers define them."""

    torque_nm: float
    rotation_rad: float
    force_n: np.ndarray
    sense: np.ndarray
    lever_mm: np.ndarray
    gap_mm: np.ndarray
    equilibrium_residual: float
    complementarity_residual: float
    iterations: int
    warnings: tuple[str, ...] = field(default=())

    def __post_init__(self):
        for name in ("force_n", "sense", "lever_mm", "gap_mm"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))

    @property
    def flank_torque_nm(self) -> tuple[float, float]:
        """The zone torque carried by the positive-sense and by the negative-sense flank (N·m,
        both ≥ 0; their difference is the zone's T/U, their smaller one the preload)."""
        m = (self.force_n * self.lever_mm[None, :]).sum(axis=0) * 1e-3
        return float(m[self.sense > 0].sum()), float(m[self.sense < 0].sum())


def solve_two_flanks(gap_mm, lever_mm, sense, compliance_mm_per_n, gap_shift, torque_nm: float, *,
                     zones: int) -> TwoFlankFace:
    """The contact of both flanks of a zone across the face at a signed gear torque (N·m).

    Points of both flanks in one list: initial separations ``gap_mm`` e_k (mm, any sign after
    ``gap_shift`` (N, n) is added: a negative one is an overlap at no load, i.e. preload),
    lever arms ``lever_mm`` r_k > 0 about the centre in the sense that loads each point,
    ``sense`` s_k = ±1 that sense in the package's angle; ``compliance_mm_per_n`` S (n × n) of
    all the points for the whole face (S_2D/b), each of the N slices N·S, independent.
    Gaps g_ki = e_k + Δe_ki − s_k r_k φ + N (S F_i)_k ≥ 0, F ≥ 0, F·g = 0, Σ s_k r_k F_ki = T/U.

    The Lemke form of :mod:`~profilegen.contact.solvers` needs every lever in one sense; here
    the two flanks pull φ both ways. For a fixed φ each slice is the bound-constrained convex
    QP min ½ Fᵀ(N S)F + cᵀF, F ≥ 0 (c = e + Δe − s r φ), solved exactly as the non-negative
    least-squares problem min |Lᵀ F + L⁻¹ c| (N S = L Lᵀ; Lawson–Hanson, scipy's ``nnls``).
    Its moment Σ s r F(φ) is non-decreasing and continuous in φ (φ is the multiplier of the
    torque constraint of the joint QP, whose dual is concave), so the φ that carries T is found
    by Brent's method to 1e-14 rad. With no preload and |T| → 0 the root is anywhere in the
    free play; a caller wanting the first contact passes a tiny torque of the sign wanted."""
    from scipy.linalg import LinAlgError, cholesky, solve_triangular
    from scipy.optimize import brentq, nnls

    e = np.asarray(gap_mm, dtype=float)
    r = np.asarray(lever_mm, dtype=float)
    sg = np.asarray(sense, dtype=float)
    n = e.size
    if r.shape != (n,) or sg.shape != (n,) or np.any(r <= 0.0) or not np.all(np.isin(sg, (-1.0, 1.0))):
        raise FaceLoadError(f"lever_mm, sense: must be {n} lever arms > 0 (mm) and {n} signs ±1")
    s = np.asarray(compliance_mm_per_n, dtype=float)
    if s.shape != (n, n):
        raise FaceLoadError(f"compliance_mm_per_n: shape {s.shape} does not match the {n} contact points")
    de = np.atleast_2d(np.asarray(gap_shift, dtype=float))
    if de.ndim != 2 or de.shape[1] != n or not np.all(np.isfinite(de)):
        raise FaceLoadError(f"gap_shift: shape {de.shape} must be (slices, {n}) finite mm")
    torque = _number("torque_nm", torque_nm, "N·m")
    u = _whole("zones", zones, 1)
    n_s = de.shape[0]
    tz = torque / u * 1e3
    scale = float(np.mean(np.diag(s))) * n_s
    try:
        low = cholesky(n_s * s / scale, lower=True)
    except LinAlgError as exc:
        raise FaceLoadError("compliance_mm_per_n: not positive definite") from exc
    sr = sg * r
    count = [0]

    def forces(phi):
        count[0] += 1
        c = (e[None, :] + de - sr[None, :] * phi) / scale
        out = np.empty((n_s, n))
        for i in range(n_s):
            out[i] = nnls(low.T, -solve_triangular(low, c[i], lower=True), maxiter=50 * n)[0]
        return out

    def excess(phi):
        return float((forces(phi) * sr[None, :]).sum()) - tz

    # bracket: the rigid closure of the extreme gaps, widened until the moment changes sign
    reach = float(np.max(np.abs(e[None, :] + de) / r[None, :])) + 1e-6
    lo, hi = -reach, reach
    f_lo, f_hi = excess(lo), excess(hi)
    for _ in range(60):
        if f_lo <= 0.0 <= f_hi:
            break
        if f_lo > 0.0:
            lo = 2.0 * lo - hi
            f_lo = excess(lo)
        if f_hi < 0.0:
            hi = 2.0 * hi - lo
            f_hi = excess(hi)
    else:
        raise FaceLoadError(f"torque_nm = {torque!r} N·m: no rotation carries it (the moment stays one-signed)")
    if f_lo == 0.0:
        phi = lo
    elif f_hi == 0.0:
        phi = hi
    else:
        phi = brentq(excess, lo, hi, xtol=1e-15, rtol=1e-14, maxiter=200)
    f = forces(phi)
    gap = e[None, :] + de - sr[None, :] * phi + (n_s * (f @ s))  # S symmetric: (N S F_i)_k
    carried = float(np.abs(f * r[None, :]).sum())  # both flanks' moments: the scale when T ≈ 0 (preload)
    scale_t = max(abs(tz), carried, 1e-300)
    return TwoFlankFace(torque, float(phi), f, sg, r, gap, abs(float((f * sr[None, :]).sum()) - tz) / scale_t,
                        float(np.max(np.abs(f * gap))) / (scale_t * (abs(phi) + 1e-6)), count[0])


def two_flank_sides(inputs, *, stations: int = 5, max_gap_mm: float = 0.12) -> tuple:
    """(points of the positive-sense flank, points of the other, one
    :class:`~profilegen.contact.compliance.ContactCompliance` of both lists together) for a
    design or :class:`~profilegen.contact.inputs.ContactInput`: the two flanks share the FS and
    CS bodies, so their points are coupled through S."""
    from profilegen.contact.compliance import ContactCompliance
    from profilegen.contact.inputs import ContactInput
    from profilegen.contact.points import contact_points

    inputs = ContactInput.from_design(inputs, name="inputs")
    a, b = (contact_points(inputs, side=s, stations=stations, max_gap_mm=max_gap_mm) for s in (1, -1))
    pos, neg = (a, b) if a.rotation > 0 else (b, a)
    comp = ContactCompliance.build(inputs, np.r_[pos.fs_point_mm, neg.fs_point_mm], np.r_[pos.normal, neg.normal],
                                   np.r_[pos.tooth, neg.tooth], np.r_[pos.cs_point_mm, neg.cs_point_mm])
    return pos, neg, comp


def face_two_flanks(inputs, torque_nm: float, *, slices: int = 8, coning: str = "cup", cup=None,
                    sides: tuple | None = None, settle_iterations: int = 20) -> TwoFlankFace:
    """Both flanks across the face of a design at a signed torque (N·m): the slices of
    :func:`face_load` (``coning`` "cup", "semi_membrane" or "none"), both flanks' points
    (``sides`` from :func:`two_flank_sides`, else built), the balls settled on the whole
    face's forces with this solve (seed 000's loop) and held. Where coning makes the flanks
    overlap at no load, both carry load at zero torque (:attr:`TwoFlankFace.flank_torque_nm`)."""
    from profilegen.contact.inputs import ContactInput

    inputs = ContactInput.from_design(inputs, name="inputs")
    gs = inputs.gearset
    if gs.cup is None:
        raise FaceLoadError("inputs.gearset.cup: the cup is needed for the face width and the design section")
    checks.choice("coning", coning, ("cup", "semi_membrane", "none"), error=FaceLoadError)
    pos, neg, comp = two_flank_sides(inputs) if sides is None else sides
    b, z0 = float(gs.cup.face_width_mm), float(gs.cup.length_mm)
    z = slice_positions(b, slices, z0)
    if coning == "cup" and cup is None:
        from profilegen.rim.cup.contact import press_cup

        cup = press_cup(gs)  # once, for both flanks
    shifts = np.hstack([coning_gap_shifts(flank, inputs.motion, gs, z0, z, coning=coning, cup=cup)
                        for flank in (pos, neg)])
    gap = np.r_[pos.gap_mm, neg.gap_mm]
    lever = np.r_[pos.lever_mm, neg.lever_mm]
    sense = np.r_[np.ones(pos.count), -np.ones(neg.count)]
    zones = int(pos.zones)

    def solve(matrix):
        return solve_two_flanks(gap, lever, sense, matrix, shifts, torque_nm, zones=zones)

    from profilegen.errors import ConvergenceError

    first = solve(comp.matrix_mm_per_n)
    try:
        settled = comp.settle_balls(first.force_n.sum(axis=0), max_iterations=settle_iterations,
                                    solve=lambda m: solve(m).force_n.sum(axis=0))
    except ConvergenceError as exc:
        # with both flanks preloaded the ball reactions are small differences of large tooth forces, and seed
        # 000's one-ball-at-a-time loop can cycle: keep every ball (rigid supports all round), say so
        log.warning("face_two_flanks at %g N·m: %s; every ball kept", torque_nm, exc)
        return dataclasses.replace(first, warnings=(f"ball settling did not converge ({exc}); every ball kept",))
    return first if settled is comp else solve(settled.matrix_mm_per_n)
