"""Loaded tooth contact of a design: points + compliance + solver → :class:`ContactResult`.

``solve_contact(inputs, torques_nm)`` takes a :class:`~profilegen.contact.inputs.ContactInput`
(what the contact reads of a design: ``ContactInput.from_design(design)``; a Design is
accepted and read the same way) and builds the points and the compliance itself.

``analyse_contact(points, compliance, torques_nm)`` solves one engagement zone for each
torque. The U zones of a U-wave generator carry equal shares (the wave generator's U-fold
rotational symmetry maps the loads of one zone onto the next), so a zone takes
T_zone = T / U; forces, teeth in contact and the rotation are those of one zone, the teeth
in contact of the whole gear are U times as many. The rotation φ of the FS against the CS
is the same in every zone; the torsional mesh stiffness is T / φ (secant) and dT/dφ
(tangent, by differences along the torque list).

The compliance comes from :mod:`profilegen.contact.compliance` (FEM influence
coefficients) or any symmetric positive definite matrix in mm/N for the points, in the
points' order. The solver is :func:`~profilegen.contact.solvers.solve_lemke` (the
package's), or the active-set QP for a cross-check.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..blas import one_blas_thread
from .inputs import ContactInput
from .solvers import ContactError, ContactSolution, solve_lemke, solve_qp_active_set
from ..results import readonly as _readonly

if TYPE_CHECKING:  # pragma: no cover
    from .compliance import ContactCompliance
    from .points import ContactPoints

__all__ = ["ContactResult", "FLANK_SECTIONS", "LoadCase", "analyse_contact", "flank", "solve_contact"]

ARCMIN_PER_RAD = 180.0 * 60.0 / math.pi

_SOLVERS: dict[str, Callable[..., ContactSolution]] = {"lemke": solve_lemke, "active_set": solve_qp_active_set}



@dataclass(frozen=True, slots=True, eq=False)
class LoadCase:
    """One torque: the zone's solution and its per-tooth summary (N, rad, N·m)."""

    torque_nm: float
    zone_torque_nm: float
    solution: ContactSolution
    teeth: np.ndarray  # FS tooth indices of the zone's candidate points, sorted
    tooth_phi_rad: np.ndarray
    tooth_force_n: np.ndarray  # normal force per tooth (sum over its points)
    ball_angle_rad: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ball_reaction_n: np.ndarray = field(default_factory=lambda: np.zeros(0))  # > 0: ball compressed
    ball_active: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    reach_mm: float = 0.0  # φ · max r_k: how far the rigid rotation reaches at the longest lever arm
    max_gap_mm: float = math.inf  # the separation beyond which no point was searched

    def __post_init__(self):
        for name in ("teeth", "tooth_phi_rad", "tooth_force_n", "ball_angle_rad", "ball_reaction_n"):
            object.__setattr__(self, name, _readonly(getattr(self, name), int if name == "teeth" else float))
        object.__setattr__(self, "ball_active", _readonly(self.ball_active, bool))

    @property
    def rotation_rad(self) -> float:
        """Rotation φ of the FS against the CS under the torque (rad)."""
        return float(self.solution.phi_rad)

    @property
    def rotation_arcmin(self) -> float:
        return self.rotation_rad * ARCMIN_PER_RAD

    @property
    def teeth_in_contact(self) -> int:
        """Teeth carrying load in one zone."""
        return int(np.count_nonzero(self.tooth_force_n > 0.0))

    @property
    def max_tooth_force_n(self) -> float:
        return float(self.tooth_force_n.max())

    @property
    def beyond_capacity(self) -> str | None:
        """Why this torque is beyond what the modelled contact can carry, or None.

        "Beyond" means the loaded zone has reached the edge of what was searched, so the
        answer is not the contact's: every candidate point is loaded, the first or last
        candidate tooth of the zone carries load (the teeth beyond them, not in the model,
        would too), or the rotation φ reaches the points left out (φ · max r_k ≥ the search's
        ``max_gap_mm``: a station farther than that could touch). The load case is still
        returned, flagged, with this reason."""
        if self.reach_mm >= self.max_gap_mm:
            return (f"the rotation reaches {self.reach_mm * 1e3:.1f} µm at the longest lever arm, past the "
                    f"{self.max_gap_mm * 1e3:.0f} µm within which points were searched")
        if self.solution.all_points_loaded:
            return "every candidate contact point is loaded"
        edge = [int(self.teeth[k]) for k in (0, self.teeth.size - 1) if self.tooth_force_n[k] > 0.0]
        if edge:
            return f"the edge tooth {edge} of the searched zone carries load"
        return None

    def to_dict(self) -> dict:
        return {
            "torque_nm": self.torque_nm,
            "beyond_capacity": self.beyond_capacity,
            "zone_torque_nm": self.zone_torque_nm,
            "rotation_rad": self.rotation_rad,
            "rotation_arcmin": self.rotation_arcmin,
            "teeth_in_contact_per_zone": self.teeth_in_contact,
            "points_loaded": self.solution.loaded_count,
            "max_tooth_force_n": self.max_tooth_force_n,
            "max_point_force_n": self.solution.max_force_n,
            "all_points_loaded": self.solution.all_points_loaded,
            "teeth": self.teeth.tolist(),
            "tooth_phi_deg": np.degrees(self.tooth_phi_rad).tolist(),
            "tooth_force_n": self.tooth_force_n.tolist(),
            "ball_angle_deg": np.degrees(self.ball_angle_rad).tolist(),
            "ball_reaction_n": self.ball_reaction_n.tolist(),
            "ball_active": self.ball_active.tolist(),
            "solution": self.solution.to_dict(),
        }


@dataclass(frozen=True, slots=True, eq=False)
class ContactResult:
    """Loaded contact at several torques, and the torsional stiffness curve they make."""

    points: ContactPoints
    cases: tuple[LoadCase, ...]
    zones: int
    solver: str
    compliance_info: dict
    time_s: float
    warnings: tuple[str, ...] = field(default=())
    compliance: ContactCompliance | None = None  # reuse it for further torques

    @property
    def torques_nm(self) -> np.ndarray:
        return np.array([c.torque_nm for c in self.cases])

    @property
    def rotations_rad(self) -> np.ndarray:
        return np.array([c.rotation_rad for c in self.cases])

    @property
    def secant_stiffness_nm_per_rad(self) -> np.ndarray:
        """T / (φ − φ_0) with φ_0 the rotation at first contact (the smallest θ): the
        elastic part only, the no-load clearance taken out."""
        phi0 = float(np.min(self.points.theta_rad))
        return self.torques_nm / (self.rotations_rad - phi0)

    @property
    def max_tooth_force_n(self) -> float:
        return max(c.max_tooth_force_n for c in self.cases)

    def to_dict(self) -> dict:
        k = self.secant_stiffness_nm_per_rad
        return {
            "zones": self.zones,
            "solver": self.solver,
            "compliance": self.compliance_info,
            "first_contact_rotation_rad": float(np.min(self.points.theta_rad)),
            "torques_nm": self.torques_nm.tolist(),
            "rotations_arcmin": (self.rotations_rad * ARCMIN_PER_RAD).tolist(),
            "secant_stiffness_nm_per_rad": k.tolist(),
            "secant_stiffness_nm_per_arcmin": (k / ARCMIN_PER_RAD).tolist(),
            "max_tooth_force_n": self.max_tooth_force_n,
            "time_s": self.time_s,
            "points": self.points.to_dict(),
            "cases": [c.to_dict() for c in self.cases],
            "warnings": list(self.warnings),
        }


def _checked_torques(torques_nm, solver: str) -> np.ndarray:
    if solver not in _SOLVERS:
        raise ContactError(f"solver = {solver!r}: must be one of {', '.join(_SOLVERS)}")
    torques = np.atleast_1d(np.asarray(torques_nm, dtype=float))
    if torques.ndim != 1 or torques.size == 0:
        raise ContactError("torques_nm: must be one torque or a list of torques (N·m)")
    bad = np.flatnonzero(~(np.isfinite(torques) & (torques > 0.0)))
    if bad.size:
        raise ContactError(f"torques_nm = {torques[bad[0]]!r} N·m: every torque must be finite and > 0")
    return torques


def load_case(points, torque: float, sol: ContactSolution, balls=None) -> tuple[LoadCase, list[str]]:
    """The per-tooth summary of one zone's solution, and what the result must warn about."""
    teeth = points.teeth
    slot = np.searchsorted(teeth, points.tooth)
    tooth_phi = np.zeros(teeth.size)
    tooth_phi[slot] = points.phi_rad
    per_tooth = np.bincount(slot, weights=sol.force_n, minlength=teeth.size)
    extra: tuple[np.ndarray, np.ndarray, np.ndarray] = (
        (np.zeros(0), np.zeros(0), np.zeros(0, bool)) if balls is None else
        (balls.ball_angle_rad, balls.ball_reactions(sol.force_n), balls.ball_active))
    case = LoadCase(float(torque), float(torque / points.zones), sol, teeth, tooth_phi, per_tooth, *extra,
                    reach_mm=float(sol.phi_rad * points.lever_mm.max()), max_gap_mm=float(points.max_gap_mm))
    warnings = []
    if case.beyond_capacity is not None:
        warnings.append(f"at {torque:g} N·m the torque is beyond what the modelled contact can carry: "
                        f"{case.beyond_capacity} — the contact zone reaches the edge of the points searched "
                        "(raise max_gap_mm, or the rim lets the ring deflect beyond what the teeth were "
                        "searched for); the result is not trustworthy")
    return case, warnings + list(sol.warnings)


def analyse_contact(points, compliance_mm_per_n, torques_nm, *, solver: str = "lemke") -> ContactResult:
    """Solve one engagement zone of ``points`` (:class:`~profilegen.contact.points.ContactPoints`)
    with ``compliance_mm_per_n`` (n × n, held fixed: no ball settling) at each torque in
    ``torques_nm`` (N·m, total on the gear)."""
    t0 = time.perf_counter()
    torques = _checked_torques(torques_nm, solver)
    s = np.asarray(compliance_mm_per_n, dtype=float)
    if s.shape != (points.count, points.count):
        raise ContactError(
            f"compliance_mm_per_n: shape {s.shape} does not match the {points.count} contact points"
        )
    cases, warnings = [], []
    for torque in torques:
        sol = _SOLVERS[solver](s, points.theta_rad, points.lever_mm, torque / points.zones * 1e3)
        case, notes = load_case(points, torque, sol)
        cases.append(case)
        warnings += notes
    return ContactResult(points, tuple(cases), int(points.zones), solver, {}, time.perf_counter() - t0,
                         tuple(warnings), None)


class BallReactions:
    """What :func:`load_case` reads of the balls: their angles, reactions (N, > 0 the ball
    compressed) and which are in contact (default: those with a reaction)."""

    __slots__ = ("ball_angle_rad", "ball_active", "_reactions")

    def __init__(self, angles, reactions, active=None):
        self.ball_angle_rad, self._reactions = angles, np.asarray(reactions, dtype=float)
        self.ball_active = self._reactions > 0.0 if active is None else np.asarray(active, dtype=bool)

    def ball_reactions(self, forces_n):
        return self._reactions


def _solve_every_ball(points, compliance, torque_nm: float, solver: str, bearing, settle_iterations: int):
    """One torque with every ball one-sided at its no-load gap → (the teeth's ContactSolution,
    the balls). "lemke": Lemke's method on teeth and balls together (:meth:`~profilegen.contact.
    compliance.ContactCompliance.solve_unilateral`, exact). "active_set": an independent
    solve of the same problem — the ball set settled (:func:`~profilegen.contact.compliance.
    settle_step`), for each set the teeth by the primal active-set QP on the compliance with
    those balls closed at their gaps (:class:`~profilegen.contact.reduced.ReducedZone`)."""
    from ..errors import ConvergenceError

    torque_nmm = torque_nm / points.zones * 1e3
    if solver == "lemke":
        sol, reactions, _ = compliance.solve_unilateral(points.theta_rad, points.lever_mm, torque_nmm,
                                                        bearing=bearing)
        return sol, BallReactions(compliance.ball_angle_rad, reactions)
    from .reduced import ReducedZone, zone_solution

    t0 = time.perf_counter()
    zone = ReducedZone(points, compliance, bearing)
    state = (np.zeros(points.count, bool), np.asarray(compliance.ball_active, bool), None)
    out = zone.solve(torque_nm, state, springs_on=bearing is not None, spring_tol=1e-6,
                     max_iterations=settle_iterations + 2 * compliance.ball_angle_rad.size + 60, teeth="active_set")
    if out is None:
        raise ConvergenceError(f"solve_contact: the active-set solve's ball set cycles or does not settle at "
                               f"{torque_nm:g} N·m")
    return (zone_solution(zone, torque_nm, out, t0, method="active set (teeth), balls settled"),
            BallReactions(compliance.ball_angle_rad, out["reactions"], out["active"]))


def flank(inputs: ContactInput, side: int = 1, *, stations: int = 5, max_gap_mm: float = 0.12, **build):
    """(points, compliance) of one flank: :func:`~profilegen.contact.points.contact_points` and
    :meth:`ContactCompliance.build <profilegen.contact.compliance.ContactCompliance.build>` (its
    keyword arguments ``build``). Neither reads the torques: inside an engine's design
    (:func:`profilegen.pipeline.engine.reuse`) a flank built for the same geometry — the gear set's sections
    but its torques and requirements, the same FS tooth, deformation and CS space objects — is
    taken from the engine's cache, so a torque change re-solves the contact without building it."""
    from ..stagecache import checkpoint, reuse
    from .compliance import ContactCompliance
    from .points import contact_points

    def make():
        pts = contact_points(inputs, side=side, stations=stations, max_gap_mm=max_gap_mm)
        checkpoint()
        return pts, ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm, **build)

    m = inputs.motion
    key = (side, stations, max_gap_mm, sorted(build.items()), inputs.cs_tip_radius_mm, inputs.rim_contact_angle_rad,
           m.neutral_radius_mm, m.waves, m.cs_teeth)
    return reuse("contact_flank", make, gearset=inputs.gearset, sections=FLANK_SECTIONS, key=key,
                 owners=(inputs.tooth, m.deformation, inputs.cs_space))


#: the gear-set sections a flank's points and compliance read: all but the torques and the requirements
FLANK_SECTIONS = ("gear", "tooth", "wave_generator", "material", "circular_spline", "cup", "face")


def solve_contact(inputs: ContactInput, torques_nm, *, side: int = 1, stations: int = 5, max_gap_mm: float = 0.12,
                  solver: str = "lemke", face_width_mm: float | None = None, settle_iterations: int = 20,
                  points=None, compliance=None, race_thickness_mm: float | None = None,
                  race_interface: str = "sliding", ball_supports: str = "all", bearing=None) -> ContactResult:
    """Loaded contact of a design at each torque (N·m), from its ``inputs`` (a
    :class:`~profilegen.contact.inputs.ContactInput`, or a Design, read by
    :meth:`ContactInput.from_design <profilegen.contact.inputs.ContactInput.from_design>`): the potential contact points
    (:func:`~profilegen.contact.points.contact_points`), the FEM influence coefficients
    (:class:`~profilegen.contact.compliance.ContactCompliance`, built once), then per torque
    the teeth and the wave-generator balls.

    ``ball_supports``: "all" (the default) — every ball of the zone a one-sided support at its
    no-load gap, teeth and balls in one complementarity problem solved exactly (the bearing
    model of :func:`~profilegen.contact.chain.torsional_curve` and
    :func:`~profilegen.contact.transmission.transmission_error`; see
    :mod:`profilegen.contact.chain`: the window below lets the rim pass 57/103 µm through the
    balls it leaves out); "window" — only the balls within the rim's no-load contact angle,
    rigid at zero gap, settled by seed 000's loop (solve the contact, drop the balls that
    pull, take back those the rim moves into, re-solve until the set no longer changes; at most
    ``settle_iterations``), kept for comparison. A given ``compliance`` keeps its own.
    ``solver``: "lemke" (the package's) or "active_set" (the independent cross-check: with
    every ball, the ball set settled around a primal active-set QP of the teeth).
    ``bearing``: a :class:`~profilegen.contact.chain.BallBearing` for Hertz springs at the
    balls (every ball only; default rigid balls).

    ``points`` and ``compliance``: those of an earlier result (``result.points``,
    ``result.compliance``), so that further torques skip the FEM. ``race_thickness_mm``: the
    wave-generator bearing's outer race under the FS bore and ``race_interface`` its joint to
    the bore (see :meth:`ContactCompliance.build`; 0 = none; both ignored when ``compliance``
    is given)."""

    from ..stagecache import checkpoint

    t0 = time.perf_counter()
    inputs = ContactInput.from_design(inputs, name="inputs")  # a ContactInput passes as it is
    torques = _checked_torques(torques_nm, solver)
    if ball_supports not in ("all", "window"):
        raise ContactError(f"ball_supports = {ball_supports!r}: must be 'all' (every ball one-sided at its no-load "
                           "gap) or 'window' (the balls within the rim's no-load contact angle)")
    if (points is None) != (compliance is None):
        raise ContactError("points, compliance: pass both (from an earlier solve_contact result) or neither")
    if points is None:
        points, compliance = flank(inputs, side, stations=stations, max_gap_mm=max_gap_mm, face_width_mm=face_width_mm,
                                   race_thickness_mm=race_thickness_mm, race_interface=race_interface,
                                   ball_supports=ball_supports)
    every_ball = getattr(compliance, "ball_supports", "window") == "all"
    if bearing is not None and not every_ball:
        raise ContactError("bearing: Hertz springs at the balls need ball_supports = 'all' (the window's balls are "
                           "rigid)")
    solve = _SOLVERS[solver]
    cases, warnings = [], []
    with one_blas_thread():  # n ≈ 200: threads only add overhead (9 → 1 ms per check)
        for torque in torques:
            checkpoint()  # an engine's design stops here when superseded
            if every_ball:
                sol, balls = _solve_every_ball(points, compliance, float(torque), solver, bearing, settle_iterations)
                case, notes = load_case(points, torque, sol, balls)
                cases.append(case)
                warnings += notes
                continue
            torque_nmm = torque / points.zones * 1e3

            def forces_for(matrix, torque_nmm=torque_nmm):
                return solve(matrix, points.theta_rad, points.lever_mm, torque_nmm).force_n

            first = solve(compliance.matrix_mm_per_n, points.theta_rad, points.lever_mm, torque_nmm)
            settled = compliance.settle_balls(first.force_n, max_iterations=settle_iterations, solve=forces_for)
            sol = (first if np.array_equal(settled.ball_active, compliance.ball_active)
                   else solve(settled.matrix_mm_per_n, points.theta_rad, points.lever_mm, torque_nmm))
            case, notes = load_case(points, torque, sol, settled)
            cases.append(case)
            warnings += notes
    info = {**compliance.to_dict(), "ball_supports": getattr(compliance, "ball_supports", "window")}
    return ContactResult(points, tuple(cases), int(points.zones), solver, info, time.perf_counter() - t0,
                         tuple(warnings), compliance)
