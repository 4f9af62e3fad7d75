"""Ratcheting: the torque at which the loaded FS teeth ride up the CS flanks until they skip.

``ratcheting_torque(design, catalogue=..., options=None) -> Ratcheting`` (``torque_nm``,
``model``, ``flag(torque)``, ``to_dict()``); how it solves is :class:`RatchetingOptions`
(``options=``, in the style of scipy.optimize's). Units mm, N, MPa inside; torque N·m. The model,
its checks and its numbers against the catalogue: docs/theory/torsion.md, "Ratcheting and
transmission error".

The estimate (``climb=True``, the default): :mod:`profilegen.contact.climb` follows the loaded
contact by rotation control with the teeth's radial retreat fed back into the geometry — at each
rotation φ the FS teeth stand out of their CS spaces by their computed retreat s_k (FS side from
the contact's influence coefficients with the tip-land probes below, each active ball a Hertz
spring; CS side the free ring below), the gaps and lever arms of fine stations on the loaded
flanks and the FS tip corners are measured again against the whole CS surface, and s is iterated
to its fixed point. The ratcheting torque is the path's limit point (T(φ) falling more than 0.5 %
below its largest value so far, the peak refined); a path that ends with no equilibrium just
beyond a still-rising T is reported as such (``climb["criterion"]`` "end of path", a warning),
which the verdict takes as a failed computation, never as the torque. ``climb_positions = N``
takes the least of N wave-generator positions over one tooth passage; ``climb_friction`` μ with
``climb_sliding`` puts Coulomb friction on the tooth contacts (a study option: μ is not a gear-set
field); ``climb_ring_scale`` multiplies the CS ring's compliance (a study option).

The linear diagnostics (``climb=False``, and ``torque_linear_nm`` beside the climb): under torque
the tooth forces' radial components F_k sin α_k push the FS rim inward and the CS outward. The
radial separation Δr_k(T) of FS tooth k from its CS space is read from the contact's FEM influence
coefficients with two probe points per tooth (the FS tooth's tip-land centre, radial, paired with
the CS space's root centre), the balls as Hertz springs settled at their own reactions, plus the
CS's own ovalisation (``cs_ring=True``): the CS as a free thin ring (mean radius R between its root
and outer circles, radial thickness h, width the face width) under both zones' radial forces,

    w(θ) = Σ_k P_k [R/(2π E A) + (1/π) Σ_{n = 2, 4, …} cos n(θ − θ_k) R³/(E I (n² − 1)²)]

(for two opposite loads Roark's ring, tested; ESTIMATE: a CS bolted on its face is stiffer, so
the free ring is an upper bound of this compliance). Tooth k's available depth h_k is its no-load
engagement at the corners (|FS tip corner of the loaded flank| − r_CS,tip); the gear ratchets
where the force-weighted margin Σ F_k (h_k − Δr_k)/Σ F_k reaches 0, interpolated in a ladder of
torques, else extrapolated by the proportional bound min_T T h̄(T)/Δr̄(T) (flagged).

Left out (stated): the inner ring's and the cam's compliance; the cup's bending under the radial
forces; the CS's bolted joint and housing (the ring is taken free); friction (an option above).

Bad input: a zero or non-finite torque is a :class:`RatchetingError`; a wave-generator
bearing that does not fit (:func:`check_bearing_fits`) is a :class:`BearingFitError` naming
the field, its value, unit and range; a torque at or beyond the estimate is flagged by
:meth:`Ratcheting.flag` (a reason string, ``None`` below it).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import partial
from typing import Any

import numpy as np

from .. import checks
from ..blas import one_blas_thread
from ..errors import ConvergenceError, ProfilegenError
from ..results import json_ready, readonly as _readonly
from .climb import tooth_probes as _probes

__all__ = [
    "BearingFitError",
    "CATALOGUE_RATCHETING",
    "CLIMB_GAP_PER_MODULE",
    "Ratcheting",
    "RatchetingError",
    "RatchetingOptions",
    "check_bearing_fits",
    "cs_ring_radial_compliance",
    "ratcheting_torque",
]

log = logging.getLogger(__name__)

#: The default ``catalogue`` argument: None (no comparison). The sourced values are in
#: :data:`profilegen.contact.catalogue.RATCHETING_TORQUE_NM` (CSF table 4: CSF-40-100 2100 N·m);
#: the pipeline passes its row (``contact.chain.catalogue_for``).
CATALOGUE_RATCHETING = None

#: the climb's teeth: every tooth whose no-load gap to the CS is within this many modules. At the
#: limit point the FS has turned by φ·r ≈ 0.5-0.7 m at its stations on `profilegen new`'s sets
#: (φ ≈ 5.6-6.7 mrad, r ≈ 100 m at ratio 100), so a tooth farther than that cannot touch before it.
#: An absolute 0.15 mm (before) took every such tooth at size 14 (0.84 m) and left out those
#: beyond 0.20 m at size 58, whose estimate rose 40 % with them (20448 -> 28594 N·m; 28593 at
#: 1.2 m; ``tests/benchmarks/ratcheting.py --verify --gaps``): the cut must scale with the gear. A
#: path that turns farther is said (``_climb``).
CLIMB_GAP_PER_MODULE = 1.0


class RatchetingError(ProfilegenError, ValueError):
    """Bad input to the ratcheting estimate (a zero or non-finite torque, an unknown
    option); names the parameter, its value, unit and allowed range."""


class BearingFitError(RatchetingError):
    """The wave-generator bearing does not fit between the FS bore and the cam; names the
    field or keyword, its value, unit and allowed range."""


_positive = partial(checks.positive, error=RatchetingError)
_number = partial(checks.number, error=RatchetingError)


def _flag(name: str, value) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise RatchetingError(f"{name} = {value!r}: must be True or False")
    return bool(value)


@dataclass(frozen=True)
class RatchetingOptions:
    """How :func:`ratcheting_torque` solves (``options=``, in the style of scipy.optimize's): the
    defaults are the model the product runs; the rest are the accuracy and the studies' choices.

    ``torques_nm``: the ladder to solve (N·m, > 0; default 0.25 … 4.5 × the rated torque, up to
    the momentary one; with the climb rated × (0.5, 1, 2): the linear part is a diagnostic);
    ``side``: the loaded flank (+1/−1); ``bearing``: a
    :class:`~profilegen.contact.chain.BallBearing`, True (its estimate for the gear set) or
    None/False (rigid balls); ``cs_ring``: add the CS ring's ovalisation; ``stations``,
    ``max_gap_mm``, ``race_thickness_mm``, ``settle_iterations``, ``spring_iterations``,
    ``spring_tol``: the linear diagnostics' contact points, race and ball-spring iteration.

    ``climb``: follow the climb (:mod:`profilegen.contact.climb`: ``climb_stations`` material
    stations per tooth on the teeth within ``climb_max_gap_mm`` of the CS, the rotation
    continued until a criterion or ``climb_max_torque_nm``, default 1.5 × the linear
    estimate; ``climb_max_gap_mm`` None: :data:`CLIMB_GAP_PER_MODULE` × the module, so that
    geometrically similar gears climb on the same teeth); its torque is the estimate when a criterion ends it, the linear one stays in
    ``torque_linear_nm``. ``climb_positions``: the climb at that many wave-generator positions
    evenly over one tooth passage (shift − k·2π/(z1·N)), the estimate their minimum (the gear
    running under load meets every position; each in ``climb["positions"]``; N× the time);
    ``climb_friction``: the Coulomb coefficient μ on the tooth contacts (0, the default: no
    friction; lubricated steel 0.05–0.15), ``climb_sliding`` the sense of the teeth's sliding it
    opposes: "static" (the pull-out the climb models), "forward" (running, the wave generator
    driving the load) or "backward" (running, the load driving) — see
    docs/theory/torsion.md, "Friction in the climb".

    Study knobs (docs/theory/torsion.md, "Ratcheting and transmission error"; 1 / 0 / True /
    "all" is the model): ``climb_ring_scale`` multiplies the CS ring's compliance in the climb
    (missing radial compliance); ``climb_shift_rad`` puts the wave generator elsewhere in the
    tooth passage (each tooth at 2πi/z1 + shift, rad); ``climb_corner_normal`` False takes the
    flank's normal at the FS tip corner instead of the CS surface's; ``climb_ball_supports``
    "window" supports the rim on the balls within its no-load contact angle only (settled)
    instead of every ball one-sided at its no-load gap.
    """

    torques_nm: object = None
    side: int = 1
    bearing: object = True
    cs_ring: bool = True
    stations: int = 5
    max_gap_mm: float = 0.12
    race_thickness_mm: float | None = None
    settle_iterations: int = 20
    spring_iterations: int = 60
    spring_tol: float = 1e-6
    climb: bool = True
    climb_stations: int = 9
    climb_max_gap_mm: float | None = None
    climb_max_torque_nm: float | None = None
    climb_positions: int = 1
    climb_friction: float = 0.0
    climb_sliding: str = "static"
    climb_ring_scale: float = 1.0
    climb_shift_rad: float = 0.0
    climb_corner_normal: bool = True
    climb_ball_supports: str = "all"

    @classmethod
    def of(cls, options) -> "RatchetingOptions":
        """``options`` as a :class:`RatchetingOptions`: None (the defaults), one already, or a
        mapping of its fields (an unknown key is a :class:`RatchetingError` naming it)."""
        return checks.options(cls, options, "options", error=RatchetingError)


def _torque(name: str, value) -> float:
    t = checks.number(name, value, "N·m", error=RatchetingError)
    if not math.isfinite(t) or t == 0.0:
        raise RatchetingError(f"{name} = {t!r} N·m: must be finite and ≠ 0 (zero torque loads no flank: "
                              "there is nothing to ratchet)")
    return t


# --------------------------------------------------------------------------- the bearing fits


def check_bearing_fits(gearset, bearing=None, *, race_thickness_mm: float | None = None,
                       inner_race_thickness_mm: float | None = None) -> None:
    """Raise :class:`BearingFitError` unless the wave-generator bearing fits between the FS
    bore and the cam. ``bearing``: a :class:`~profilegen.contact.chain.BallBearing` (default
    its estimate for the gear set). Radially, from the bore in: the outer race
    (``race_thickness_mm``, default the contact model's estimate), the balls (D), the inner
    race (``inner_race_thickness_mm``, default = the outer race's) and the cam. With
    ``wave_generator.bearing_thickness_mm`` = h given (the cam is h below the bore), the
    section must fit in it: t_o + D + t_i ≤ h. Always: the ball row's pitch radius
    r_bore − t_o − D/2 must exceed D/2 (the cam needs a centre)."""
    from .chain import BallBearing, ChainError
    from .compliance import default_race_thickness_mm

    g = gearset.gear
    r_bore = float(g.neutral_radius_mm) - 0.5 * float(g.rim_thickness_mm)
    t_o = default_race_thickness_mm(g) if race_thickness_mm is None else \
        checks.positive("race_thickness_mm", race_thickness_mm, "mm", allow_zero=True, error=BearingFitError)
    t_i = t_o if inner_race_thickness_mm is None else \
        checks.positive("inner_race_thickness_mm", inner_race_thickness_mm, "mm", allow_zero=True,
                        error=BearingFitError)
    if bearing is None:
        try:
            bearing = BallBearing.from_gearset(gearset, race_thickness_mm=t_o)
        except ChainError as exc:
            raise BearingFitError(str(exc)) from None
    elif not isinstance(bearing, BallBearing):
        raise BearingFitError(f"bearing = {bearing!r}: must be a BallBearing (profilegen.contact.chain) or None")
    d = float(bearing.ball_diameter_mm)
    room = r_bore - t_o
    if not d < room:
        raise BearingFitError(f"ball_diameter_mm = {d:.6g} mm: must be in (0, {room:.6g}) mm — the balls must fit "
                              f"inside the outer race (FS bore radius {r_bore:.6g} mm less race_thickness_mm = "
                              f"{t_o:.6g} mm) around a cam")
    h = getattr(gearset.wave_generator, "bearing_thickness_mm", None)
    if h is not None:
        space = float(h) - t_o - t_i
        if not d <= space:
            raise BearingFitError(
                f"ball_diameter_mm = {d:.6g} mm: must be in (0, {max(space, 0.0):.6g}] mm — it does not fit between "
                f"the races in wave_generator.bearing_thickness_mm = {float(h):.6g} mm (outer race {t_o:.6g} mm + "
                f"balls + inner race {t_i:.6g} mm); give a thicker bearing or smaller balls")


# --------------------------------------------------------------------------- the CS ring


def cs_ring_radial_compliance(angles_rad, at_rad, *, mean_radius_mm: float, thickness_mm: float,
                              width_mm: float, youngs_modulus_mpa: float, harmonics: int = 200) -> np.ndarray:
    """Radial displacement (mm, outward) of a free thin ring at ``at_rad`` per unit outward
    radial point load (N) at each of ``angles_rad``: an (m, k) matrix —
    :func:`profilegen.contact.cs_ring.ring_compliance` for one zone, radial loads:
    w = 1/(2π) R/(E A) + (1/π) Σ_{n≥2} cos n(θ − θ_k) R³/(E I (n² − 1)²), A = w h, I = w h³/12."""
    from .cs_ring import CSRing, CSRingError, ring_compliance

    try:
        ring = CSRing(mean_radius_mm, thickness_mm, width_mm, youngs_modulus_mpa)
        return ring_compliance(ring, at_rad, angles_rad, zones=1, harmonics=harmonics)
    except CSRingError as exc:
        raise RatchetingError(str(exc)) from exc


def _cs_ring_section(gearset, inputs) -> tuple[float, float, float, list[str]]:
    """(mean radius, radial thickness, width) of the CS ring (mm) and the estimates in them: the
    contact's own ring (:meth:`profilegen.contact.cs_ring.CSRing.of`)."""
    from .cs_ring import CSRing

    ring = CSRing.of(inputs)
    return ring.mean_radius_mm, ring.thickness_mm, ring.width_mm, list(ring.estimates)


# --------------------------------------------------------------------------- the result


@dataclass(frozen=True, slots=True, eq=False)
class Ratcheting:
    """The ratcheting estimate (see the module docstring).

    ``torque_nm``: the estimate (N·m; ``inf`` if the teeth never separate in this model);
    ``torque_fitted_nm`` / ``torque_proportional_nm``: the fitted and the proportional extrapolation
    (None when the criterion is met inside the solved torques); ``mean_depth_mm`` h̄ and
    ``mean_separation_mm`` Δr̄ per torque (the criterion's);
    ``model``/``criterion``: words; ``extrapolated``: the criterion lies beyond the torques
    the contact could carry; ``exponent``: p of Δr ∝ T^p used to extrapolate. Per solved
    torque (``torques_nm``): ``tooth`` the most loaded tooth, ``depth_mm`` its h,
    ``separation_mm`` its Δr (FS side + CS ring), ``separation_fs_mm``, ``separation_cs_mm``,
    ``pressure_angle_deg`` its force-weighted α, ``valid`` (not flagged by the contact),
    ``flags`` (the contact's reason, or None). ``catalogue``: {"torque_nm", "source"} or None.
    ``diagnostics``: what the linear diagnostics say when the climb gives the estimate (not
    warnings of the estimate; with no climb, or a climb that met no criterion, they are warnings).
    """

    torque_nm: float
    model: str
    criterion: str
    torques_nm: np.ndarray
    tooth: np.ndarray
    tooth_phi_deg: np.ndarray
    depth_mm: np.ndarray
    separation_mm: np.ndarray
    separation_fs_mm: np.ndarray
    separation_cs_mm: np.ndarray
    pressure_angle_deg: np.ndarray
    valid: np.ndarray
    flags: tuple
    extrapolated: bool
    exponent: float | None
    rated_torque_nm: float
    catalogue: dict | None
    parts: dict
    estimates: tuple[str, ...]
    time_s: float
    warnings: tuple[str, ...] = field(default=())
    torque_fitted_nm: float | None = None
    torque_proportional_nm: float | None = None
    mean_depth_mm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    mean_separation_mm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    torque_linear_nm: float | None = None
    climb: dict | None = None
    diagnostics: tuple[str, ...] = field(default=())

    def __post_init__(self):
        for name in ("torques_nm", "tooth_phi_deg", "depth_mm", "separation_mm", "separation_fs_mm",
                     "separation_cs_mm", "pressure_angle_deg", "mean_depth_mm", "mean_separation_mm"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        object.__setattr__(self, "tooth", _readonly(self.tooth, int))
        object.__setattr__(self, "valid", _readonly(self.valid, bool))

    @property
    def ratio_to_rated(self) -> float:
        return self.torque_nm / self.rated_torque_nm

    @property
    def ratio_to_catalogue(self) -> float | None:
        """estimate / catalogue, or None without a sourced catalogue value."""
        if not self.catalogue or self.catalogue.get("torque_nm") is None:
            return None
        return self.torque_nm / float(self.catalogue["torque_nm"])

    def margin_mm(self) -> np.ndarray:
        """The force-weighted margin h̄ − Δr̄ of the loaded teeth, per solved torque (mm; ≤ 0: ratcheted)."""
        return self.mean_depth_mm - self.mean_separation_mm

    def flag(self, torque_nm: float) -> str | None:
        """Why ``torque_nm`` (N·m, either sign) is beyond the ratcheting estimate, or None.
        Zero or a non-finite torque: :class:`RatchetingError`."""
        t = abs(_torque("torque_nm", torque_nm))
        if not t >= self.torque_nm:
            return None
        how = ("extrapolated" if self.extrapolated else "interpolated") if self.climb is None or \
            self.climb.get("criterion") in (None, "none") else f"climb, {self.climb['criterion']}"
        return (f"{t:g} N·m is at or beyond the ratcheting estimate {self.torque_nm:.4g} N·m ({how}; the loaded FS "
                "teeth ride up the CS flanks until their tips meet): the teeth may skip")

    def to_dict(self) -> dict:
        return json_ready({
            "torque_nm": self.torque_nm,
            "ratio_to_rated": self.ratio_to_rated,
            "model": self.model,
            "criterion": self.criterion,
            "extrapolated": self.extrapolated,
            "exponent": self.exponent,
            "torque_fitted_nm": self.torque_fitted_nm,
            "torque_proportional_nm": self.torque_proportional_nm,
            "torque_linear_nm": self.torque_linear_nm,
            "climb": self.climb,
            "catalogue": self.catalogue,
            "ratio_to_catalogue": self.ratio_to_catalogue,
            "torques_nm": self.torques_nm.tolist(),
            "tooth": self.tooth.tolist(),
            "tooth_phi_deg": self.tooth_phi_deg.tolist(),
            "depth_mm": self.depth_mm.tolist(),
            "separation_mm": self.separation_mm.tolist(),
            "mean_depth_mm": self.mean_depth_mm.tolist(),
            "mean_separation_mm": self.mean_separation_mm.tolist(),
            "separation_fs_mm": self.separation_fs_mm.tolist(),
            "separation_cs_mm": self.separation_cs_mm.tolist(),
            "pressure_angle_deg": self.pressure_angle_deg.tolist(),
            "valid": self.valid.tolist(),
            "beyond_capacity": list(self.flags),
            "parts": self.parts,
            "estimates": list(self.estimates),
            "time_s": self.time_s,
            "warnings": list(self.warnings),
            "diagnostics": list(self.diagnostics),
        })


# --------------------------------------------------------------------------- the estimate


def _split(combined, n: int):
    """The contact points' ContactCompliance out of one built with the probes after them (the
    same FEM flexibilities, sliced: exact)."""
    from .compliance import ContactCompliance

    b = combined.face_width_mm
    return ContactCompliance._assemble(
        flex_cc=combined._flex_cc[:n, :n], flex_cb=combined._flex_cb[:n], flex_bb=combined._flex_bb,
        cs_flex=combined.cs_matrix_mm_per_n[:n, :n] * b, face_width_mm=b, tooth=combined.tooth[:n],
        ball_angle_rad=combined.ball_angle_rad, ball_active=combined.ball_active,
        wrap_half_angle_rad=combined.wrap_half_angle_rad, wrap_source=combined.wrap_source, dof=combined.dof,
        time_s=combined.time_s, mesh=combined.mesh, warnings=combined.warnings,
        ball_compliance=combined.ball_compliance_mm_per_n)


def _solve(points, comp, torque_nm: float, bearing, *, settle_iterations: int, spring_iterations: int,
           spring_tol: float):
    """One torque: Lemke with ball settling and, with a bearing, the Hertz secant springs
    iterated to their fixed point. → (solution, the settled compliance with its springs)."""
    from .solvers import solve_lemke

    tz = torque_nm / points.zones * 1e3

    def forces_for(matrix):
        return solve_lemke(matrix, points.theta_rad, points.lever_mm, tz).force_n

    def settled(c):
        first = solve_lemke(c.matrix_mm_per_n, points.theta_rad, points.lever_mm, tz)
        s = c.settle_balls(first.force_n, max_iterations=settle_iterations, solve=forces_for)
        sol = first if s is c else solve_lemke(s.matrix_mm_per_n, points.theta_rad, points.lever_mm, tz)
        return s, sol

    comp, sol = settled(comp.with_balls(comp.ball_active, ball_compliance_mm_per_n=None))
    if bearing is None:
        return sol, comp
    springs = None
    for _ in range(spring_iterations):
        react = comp.ball_reactions(sol.force_n)
        floor = max(1.0, 1e-3 * float(react.max(initial=0.0)))
        new = bearing.secant_compliance_mm_per_n(react, floor_n=floor)
        if springs is not None and np.all(np.abs(new / springs - 1.0) <= spring_tol):
            return sol, comp
        springs = new
        comp, sol = settled(comp.with_balls(comp.ball_active, ball_compliance_mm_per_n=springs))
    raise ConvergenceError(f"ratcheting_torque: the Hertz ball springs did not settle in {spring_iterations} "
                           f"iterations at {torque_nm:g} N·m")


def _default_ladder(gearset) -> np.ndarray:
    rated = float(gearset.torque.rated_nm)
    top = float(gearset.torque.momentary_nm or gearset.torque.peak_nm)
    ladder = rated * np.array([0.25, 0.5, 1.0, 1.5, 2.0, 3.0])
    return np.unique(np.append(ladder[ladder < top], top))


def _ratcheting_torques(torques_nm, climb: bool, gs) -> np.ndarray:
    """The torques the linear model is solved at (N·m, ascending): ``torques_nm`` checked, or
    the default ladder (the climb's three when it gives the estimate)."""
    if torques_nm is None:
        return _default_ladder(gs) if not climb else float(gs.torque.rated_nm) * np.array([0.5, 1.0, 2.0])
    torques = np.atleast_1d(np.asarray(torques_nm, dtype=float)) if not isinstance(torques_nm, (int, float)) \
        else np.array([float(torques_nm)])
    if torques.ndim != 1 or torques.size < 2:
        raise RatchetingError(f"torques_nm: must be at least 2 torques (N·m), got {torques.size}")
    for k, t in enumerate(torques):
        if not _torque(f"torques_nm[{k}]", float(t)) > 0.0:
            raise RatchetingError(f"torques_nm[{k}] = {t!r} N·m: must be > 0 (the flank is chosen by side)")
    return np.unique(torques)


def _checked_climb_options(o: RatchetingOptions) -> tuple[bool, int, float]:
    """The side and the climb's options checked → (corner_normal, positions, friction)."""
    if o.side not in (1, -1):
        raise RatchetingError(f"side = {o.side!r}: must be +1 (right FS flank loaded) or −1 (left)")
    corner_normal = _flag("climb_corner_normal", o.climb_corner_normal)
    checks.choice("climb_ball_supports", o.climb_ball_supports, ("window", "all"), error=RatchetingError)
    positions = checks.whole("climb_positions", o.climb_positions, 1, error=RatchetingError)
    friction = checks.number("climb_friction", o.climb_friction, "", 0.0, 1.0, low_open=False,
                             error=RatchetingError)
    from .climb import SLIDING

    checks.choice("climb_sliding", o.climb_sliding, SLIDING, error=RatchetingError)
    return corner_normal, positions, friction


def _wave_generator_bearing(bearing, gs, race_thickness_mm):
    """The ``bearing`` option as the ball bearing the model uses (None: rigid balls), checked to fit."""
    from .chain import BallBearing

    if bearing is True:
        check_bearing_fits(gs, race_thickness_mm=race_thickness_mm)
        return BallBearing.from_gearset(gs, race_thickness_mm=race_thickness_mm)
    if bearing is False or bearing is None:
        return None
    if isinstance(bearing, BallBearing):
        check_bearing_fits(gs, bearing, race_thickness_mm=race_thickness_mm)
        return bearing
    raise RatchetingError(f"bearing = {bearing!r}: must be a BallBearing, True (estimated) or None (rigid balls)")


@dataclass(frozen=True, slots=True, eq=False)
class _LinearModel:
    """The linear criterion's model: the contact points with the tip-land probes' compliance,
    each probe tooth's corner depth, and the CS ring's radial compliance (None: no ring)."""

    points: Any
    combined: Any
    comp: Any
    teeth: np.ndarray
    phis: np.ndarray
    depth: np.ndarray
    slot: np.ndarray
    sin_alpha: np.ndarray
    ring: np.ndarray | None
    ring_info: dict | None


def _linear_model(inputs, gs, o: RatchetingOptions, estimates: list) -> _LinearModel:
    """The contact points, probes and compliances of the linear criterion; the CS ring's
    section estimates are appended to ``estimates``."""
    from .compliance import ContactCompliance
    from .points import contact_points

    points = contact_points(inputs, side=o.side, stations=o.stations, max_gap_mm=o.max_gap_mm)
    teeth, phis, fs_probe, e_r, cs_probe, corner = _probes(inputs, points)
    combined = ContactCompliance.build(
        inputs, np.vstack([points.fs_point_mm, fs_probe]), np.vstack([points.normal, e_r]),
        np.concatenate([points.tooth, teeth]), np.vstack([points.cs_point_mm, cs_probe]),
        race_thickness_mm=o.race_thickness_mm, cs_ring=False)  # the ring: below, radial, per tooth
    comp = _split(combined, points.count)
    depth = np.linalg.norm(corner, axis=1) - inputs.cs_tip_radius_mm
    slot = np.searchsorted(teeth, points.tooth)
    e_r_pts = points.fs_point_mm / np.linalg.norm(points.fs_point_mm, axis=1)[:, None]
    sin_alpha = np.einsum("ij,ij->i", points.normal, e_r_pts)
    ring = ring_info = None
    if o.cs_ring:
        r_mean, thick, width, notes = _cs_ring_section(gs, inputs)
        estimates += notes
        # both zones: tooth i at φ_i and its image at φ_i + π (U = 2)
        ang = np.concatenate([phis, phis + math.pi])
        ring = cs_ring_radial_compliance(ang, phis, mean_radius_mm=r_mean, thickness_mm=thick, width_mm=width,
                                         youngs_modulus_mpa=float(gs.material.youngs_modulus_mpa))
        ring_info = {"mean_radius_mm": r_mean, "thickness_mm": thick, "width_mm": width}
    return _LinearModel(points, combined, comp, teeth, phis, depth, slot, sin_alpha, ring, ring_info)


def _loaded_tooth(lm: _LinearModel, sol, settled, case):
    """At one torque: the most loaded tooth's row (tooth, φ deg, depth, separation, its FS and
    CS parts, pressure angle deg) and the force-weighted (depth, separation) over the teeth."""
    n = lm.points.count
    full = lm.combined.with_balls(settled.ball_active, ball_compliance_mm_per_n=settled.ball_compliance_mm_per_n)
    f = sol.force_n
    # S·F along a probe = the separation of the two bodies along it (the FS pushed along −e_r)
    sep_fs = full.matrix_mm_per_n[n:, :n] @ f
    sep_cs = np.zeros(lm.teeth.size)
    if lm.ring is not None:
        radial = np.bincount(lm.slot, weights=f * lm.sin_alpha, minlength=lm.teeth.size)  # outward on the CS
        sep_cs = lm.ring @ np.concatenate([radial, radial])
    per_tooth = case.tooth_force_n
    k = int(np.argmax(per_tooth))
    on = lm.slot == k
    angle = float(np.degrees(np.arcsin(np.clip(np.sum(f[on] * lm.sin_alpha[on]) / max(np.sum(f[on]), 1e-300),
                                               -1.0, 1.0))))
    total = sep_fs + sep_cs
    w = per_tooth / per_tooth.sum()
    row = (int(lm.teeth[k]), math.degrees(lm.phis[k]), float(lm.depth[k]), float(sep_fs[k] + sep_cs[k]),
           float(sep_fs[k]), float(sep_cs[k]), angle)
    return row, (float(w @ lm.depth), float(w @ total))


def _linear_path(lm: _LinearModel, torques, bearing, o: RatchetingOptions):
    """The linear model solved at each torque → (rows, flags, force-weighted (depth, separation) per torque)."""
    from .analysis import load_case

    rows, flags, every = [], [], []
    with one_blas_thread():
        for t in torques:
            sol, settled = _solve(lm.points, lm.comp, float(t), bearing, settle_iterations=o.settle_iterations,
                                  spring_iterations=o.spring_iterations, spring_tol=o.spring_tol)
            case, _ = load_case(lm.points, float(t), sol, settled)
            flags.append(case.beyond_capacity)
            row, weighted = _loaded_tooth(lm, sol, settled, case)
            every.append(weighted)
            rows.append(row)
    return rows, flags, every


def _model_texts(o: RatchetingOptions, climbed: bool, friction: float) -> tuple[str, str]:
    """The estimate's model and criterion, in words."""
    model = ("force-weighted radial separation of the loaded teeth from their CS spaces against their corner depth; FS side "
             "from the contact's FEM influence coefficients (tip-land probes, Hertz ball springs, settled balls)"
             + ("; CS side a free thin ring (bending harmonics n = 2, 4, … and n = 0)" if o.cs_ring else
                "; CS held by the contact model's sector (no ring ovalisation)"))
    criterion = ("Σ F_k (h_k − Δr_k) / Σ F_k = 0 with h_k = |FS tip corner| − r_CS,tip (the loaded teeth's tips "
                 "meet the CS tips while the flanks slide, on the load-weighted mean); interpolated linearly in the "
                 "margin inside the solved torques, else the proportional bound min T h̄/Δr̄ over them")
    if climbed:
        model = ("the climb (profilegen.contact.climb): material stations on the loaded flanks, gaps and lever arms "
                 "recomputed on the geometry with each tooth shifted out of its space by its computed retreat and the FS "
                 "turned by φ (rotation control), the contact's influence coefficients + Hertz ball springs + the CS "
                 "ring; the retreat's fixed point per φ"
                 + (f"; Coulomb friction μ = {friction:g} on the tooth contacts against the teeth's sliding "
                    f"({o.climb_sliding}; the force on the CS N (n + μσt), the gap along n: Lemke on the nonsymmetric S)"
                    if friction > 0.0 else "; no friction")
                 + ". Linear diagnostics: " + model)
        criterion = ("the first of: the limit point max T(φ); the force-weighted margin Σ F (h − s)/Σ F = 0; half the load "
                     "on the FS tip corners; the end of the path (no equilibrium found just beyond its last point). "
                     "Linear diagnostics: " + criterion)
    return model, criterion


def ratcheting_torque(design, *, catalogue: dict | None = CATALOGUE_RATCHETING,
                      options: RatchetingOptions | Mapping | None = None) -> Ratcheting:
    """The ratcheting torque of a design (or a :class:`~profilegen.contact.inputs.ContactInput`),
    by the model of the module docstring.

    ``catalogue``: {"torque_nm": …, "source": …} to compare with (a value only with its source),
    or None. ``options``: how to solve, a :class:`RatchetingOptions` or a mapping of its fields
    (default: the product's model — the climb, every ball one-sided, the CS ring)."""
    o = RatchetingOptions.of(options)
    from .inputs import ContactInput

    t0 = time.perf_counter()
    inputs = ContactInput.from_design(design, name="design")
    gs = inputs.gearset
    torques = _ratcheting_torques(o.torques_nm, o.climb, gs)
    corner_normal, positions, friction = _checked_climb_options(o)
    bearing = _wave_generator_bearing(o.bearing, gs, o.race_thickness_mm)
    if catalogue is not None and (not isinstance(catalogue, dict) or "source" not in catalogue
                                  or "torque_nm" not in catalogue):
        raise RatchetingError("catalogue: must be None or {'torque_nm': …, 'source': …} (a value only with its source)")

    estimates = list(bearing.estimates) if bearing is not None else []
    lm = _linear_model(inputs, gs, o, estimates)
    rows, flags, every = _linear_path(lm, torques, bearing, o)
    warnings: list[str] = []
    tooth_k, phi_k, h, sep, sep_fs, sep_cs, alpha = (np.array(c) for c in zip(*rows))
    valid = np.array([fl is None for fl in flags])
    rated = float(gs.torque.rated_nm)
    mean_h, mean_sep = (np.array(c) for c in zip(*every))
    torque, extrapolated, exponent, fitted, proportional = _criterion(torques, mean_h, mean_sep, valid, warnings)
    linear = float(torque)
    climb_info = None
    diagnostics: list[str] = []
    if o.climb:
        # the climb gives the estimate: the linear criterion's words are its diagnostics (kept in
        # ``diagnostics``, not among the estimate's warnings), unless the climb meets no criterion
        diagnostics = [f"linear diagnostics (torque_linear_nm, not the estimate): {w}" for w in warnings]
        warnings.clear()
        torque, extrapolated, climb_info = _climb(inputs, gs, side=o.side, bearing=bearing, cs_ring=o.cs_ring,
                                                  race_thickness_mm=o.race_thickness_mm, stations=o.climb_stations,
                                                  max_gap_mm=o.climb_max_gap_mm, linear=linear,
                                                  max_torque_nm=o.climb_max_torque_nm, ring_scale=o.climb_ring_scale,
                                                  shift_rad=_number("climb_shift_rad", o.climb_shift_rad, "rad"),
                                                  extrapolated=extrapolated, warnings=warnings,
                                                  corner_normal=corner_normal, ball_supports=o.climb_ball_supports,
                                                  positions=positions, friction=friction,
                                                  sliding=o.climb_sliding)
    if climb_info is not None and climb_info["criterion"] == "none":  # the linear estimate stands: its words too
        warnings[:0] = diagnostics
        diagnostics = []
    cat = None if catalogue is None else dict(catalogue)
    if cat is None:
        warnings.append("no catalogue ratcheting torque with a source: the comparison is left out")
    model, criterion = _model_texts(o, climb_info is not None, friction)
    parts = {"bearing": None if bearing is None else bearing.to_dict(),
             "cs_ring": lm.ring_info if o.cs_ring else None,
             "points": int(lm.points.count), "probe_teeth": int(lm.teeth.size)}
    return Ratcheting(float(torque), model, criterion, torques, tooth_k, phi_k, h, sep, sep_fs, sep_cs, alpha, valid,
                      tuple(flags), extrapolated, exponent, rated, cat, parts, tuple(estimates),
                      time.perf_counter() - t0, tuple(dict.fromkeys(warnings)), fitted, proportional, mean_h, mean_sep,
                      linear, climb_info, tuple(diagnostics))


def _climb(inputs, gs, *, side, bearing, cs_ring, race_thickness_mm, stations, max_gap_mm, linear, max_torque_nm,
           ring_scale, extrapolated, warnings, shift_rad=0.0, corner_normal=True, ball_supports="window",
           positions=1, friction=0.0, sliding="static"):
    """The climb's estimate: → (torque, extrapolated, summary dict)."""
    from .climb import DesignClimb, climb

    t0 = time.perf_counter()
    factory = None
    if cs_ring:
        r_mean, thick, width, _ = _cs_ring_section(gs, inputs)

        def factory(phis):
            ang = np.concatenate([phis, phis + math.pi])
            return cs_ring_radial_compliance(ang, phis, mean_radius_mm=r_mean, thickness_mm=thick, width_mm=width,
                                             youngs_modulus_mpa=float(gs.material.youngs_modulus_mpa))
    rated = float(gs.torque.rated_nm)
    if max_gap_mm is None:
        max_gap_mm = CLIMB_GAP_PER_MODULE * float(gs.gear.module_mm)
    else:
        max_gap_mm = _positive("climb_max_gap_mm", max_gap_mm, "mm")
    if max_torque_nm is None:
        max_torque_nm = 1.5 * linear if math.isfinite(linear) else 20.0 * rated
    else:
        max_torque_nm = _positive("climb_max_torque_nm", max_torque_nm, "N·m")
    ring_scale = _positive("climb_ring_scale", ring_scale, "")
    passage = 2.0 * math.pi / gs.gear.flexspline_teeth
    shifts = [shift_rad - k * passage / positions for k in range(positions)]
    runs = []
    with one_blas_thread():
        for sh in shifts:
            model = DesignClimb(inputs, side=side, stations=stations, max_gap_mm=max_gap_mm,
                                race_thickness_mm=race_thickness_mm, bearing=bearing, ring_factory=factory,
                                ring_scale=ring_scale, shift_rad=sh, corner_normal=corner_normal,
                                ball_supports=ball_supports, friction_coefficient=friction,
                                friction_sliding=sliding if friction > 0.0 else None)
            theta_min, phi_rated = model.first_rotation(rated)
            step = 0.5 * max(phi_rated - theta_min, 1e-9)
            runs.append((climb(model, theta_min + step, step, max_torque_nm=max_torque_nm), model, sh))
    # the gear running under load meets every position: the lowest estimate of those that ended on a criterion
    ok = [r for r in runs if r[0].criterion != "none" and math.isfinite(r[0].torque_nm)]
    path, model, shift_rad = min(ok or runs, key=lambda r: r[0].torque_nm if math.isfinite(r[0].torque_nm) else math.inf)
    warnings += [f"climb: {w}" for w in getattr(model, "notes", ())]
    warnings += [w if w.startswith("climb") else f"climb: {w}" for w in path.warnings]
    points = getattr(model, "points", None)  # (a study's duck-typed model may have none)
    reach = path.phi_rad * float(np.max(points.lever_mm)) if points is not None else math.nan
    if reach >= max_gap_mm:  # NaN (no points, no limit point) compares False
        warnings.append(f"climb: at its end the FS has turned {reach * 1e3:.0f} µm at its stations, beyond the "
                        f"{max_gap_mm * 1e3:.0f} µm gap within which its teeth were taken: a tooth left out could "
                        "have touched (raise climb_max_gap_mm)")
    info = {"criterion": path.criterion, "torque_nm": path.torque_nm, "phi_rad": path.phi_rad,
            "max_torque_nm": max_torque_nm, "stations_per_tooth": stations, "max_gap_mm": max_gap_mm,
            "points": model.n, "teeth": int(model.teeth.size), "ring_scale": ring_scale, "shift_rad": shift_rad,
            "corner_normal": corner_normal, "ball_supports": ball_supports,
            "friction": {"coefficient": friction, "sliding": sliding if friction > 0.0 else None},
            "phi_path_rad": path.column("phi_rad").tolist(), "torque_path_nm": path.column("torque_nm").tolist(),
            "mean_retreat_mm": path.column("mean_retreat_mm").tolist(),
            "margin_mm": path.column("margin_mm").tolist(), "pressure_angle_deg": path.column("alpha_deg").tolist(),
            "corner_share": path.column("corner_share").tolist(), "time_s": time.perf_counter() - t0,
            "positions": [{"shift_rad": sh, "torque_nm": p.torque_nm, "criterion": p.criterion} for p, _, sh in runs]}
    if path.criterion == "none" or not math.isfinite(path.torque_nm):
        warnings.append(f"the climb met no criterion up to {max(info['torque_path_nm'], default=0.0):.4g} N·m: the "
                        f"estimate stays the linear one ({linear:.4g} N·m)")
        return linear, extrapolated, info
    if path.criterion == "end of path":
        warnings.append(f"the climb's path ends at {path.torque_nm:.4g} N·m (no equilibrium found just beyond, "
                        "step halved 4 times, 1, 2, 4 steps beyond tried): no limit point was reached — a failed "
                        "computation, not an estimate (the verdict does not check it)")
    return float(path.torque_nm), False, info


def _criterion(torques, depth, sep, valid, warnings):
    """(T_r, extrapolated, p, T with the fitted p, T proportional) from the force-weighted depth
    h̄ and separation Δr̄ per torque (see the module docstring)."""
    t = torques[valid]
    h, s = depth[valid], sep[valid]
    if t.size < 2:
        raise ConvergenceError(f"ratcheting_torque: only {t.size} of the {torques.size} torques lie within what the "
                               "contact model can carry; give lower torques_nm")
    margin = h - s
    hit = np.flatnonzero(margin <= 0.0)
    if hit.size:
        k = int(hit[0])
        if k == 0:
            warnings.append(f"the lowest torque {t[0]:g} N·m already reaches the criterion")
            return float(t[0]), False, None, None, None
        m0, m1 = margin[k - 1], margin[k]  # linear in the margin between the bracketing torques
        return float(t[k - 1] + m0 / (m0 - m1) * (t[k] - t[k - 1])), False, None, None, None
    out = s > 0.0
    if not out.any():
        warnings.append("the loaded teeth do not move out of their spaces on the load-weighted mean (Δr̄ ≤ 0) at any "
                        "valid torque: this model predicts no ratcheting")
        return math.inf, True, None, None, None
    proportional = float(np.min(t[out] * h[out] / s[out]))
    last = slice(max(0, t.size - 3), t.size)
    fitted, p = None, None
    if np.all(s[last] > 0.0):
        p = float(np.polyfit(np.log(t[last]), np.log(s[last]), 1)[0])
        if p > 0.0:
            fitted = float(t[-1] * (h[-1] / s[-1]) ** (1.0 / p))
    if p is None or p <= 0.0:
        warnings.append("Δr̄ does not grow with the torque at the highest valid torques (the load moves to teeth the "
                        "rim pushes into mesh): the estimate is the proportional bound")
    k = int(np.argmax(np.where(out, s / t, -np.inf)))
    warnings.append(f"the criterion lies beyond the torques the contact model carries ({t[-1]:g} N·m): the estimate "
                    f"{proportional:.4g} N·m is Δr̄ ∝ T from {t[k]:g} N·m, the torque with the largest Δr̄/T"
                    + ("" if fitted is None else f" (Δr̄ ∝ T^{p:.3f} from the last three: {fitted:.4g} N·m)"))
    return proportional, True, p, fitted, proportional
