"""Loaded transmission error over a wave-generator turn: the contact at several positions ψ.

As the wave generator turns by ψ with the CS fixed, FS tooth i moves against the major axis from
φ_i = 2πi/z1 to φ_i + δ, δ = −ψ z2/z1; after one *tooth passage* (ψ = 2π/z2) the mesh repeats
with the teeth relabelled. At each ψ everything that moves with the teeth is recomputed —
the contact points and their gaps (``contact_points(shift_rad=δ)``) and the influence
coefficients (``ContactCompliance.build(shift_rad=δ)``) — and the teeth and every ball of the
zone are solved together (:func:`~profilegen.contact.analysis.solve_contact`, as the contact
stage does), one zone with T/U. The wrap angle and the meshes are computed once and reused
(they do not depend on ψ). The series compliances of :mod:`profilegen.contact.chain` add the
same rotation at every ψ: they move the mean, not the error.

Entry point: :func:`transmission_error` ``(inputs, torque_nm, positions=16, workers=None,
options=None)`` → :class:`TransmissionError` (per position ψ: the loaded rotation φ beyond the
kinematic position, the no-load first contact φ₀, the teeth and balls in contact; over ψ: the
error φ − mean φ in arcsec and its peak-to-peak, the secant mesh stiffness and its ripple).
``inputs``: a design or a :class:`~profilegen.contact.inputs.ContactInput`. ``options``: a
:class:`TransmissionOptions` or a mapping of its fields — ``span`` ("tooth": one tooth passage),
the flank, ``ball_motion`` ("wave_generator": the balls held at fixed angles from the major
axis, the result exactly periodic; "cage": the balls rolling with the cage), ``ball_supports``,
``hertz_balls``. Positions run in a process pool of ``workers`` (fork) when there are more than
two.

>>> import profilegen
>>> from profilegen.contact.transmission import transmission_error
>>> design = profilegen.design(profilegen.load_gearset("default"))  # doctest: +SKIP
>>> te = transmission_error(design, 265.0)  # doctest: +SKIP
>>> te.peak_to_peak_arcsec, te.stiffness_ripple  # doctest: +SKIP

Errors: :class:`TransmissionErrorError` (a ``ValueError``) naming a bad torque, position count,
worker count or option.

The model, its accuracy and cost and why every ball is a support: docs/theory/torsion.md,
"The transmission error".
"""

from __future__ import annotations

import logging
import math
import os
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..blas import one_blas_thread
from ..errors import ProfilegenError
from ..results import json_ready, readonly as _readonly
from .inputs import ContactInput

__all__ = ["ARCSEC_PER_RAD", "TransmissionError", "TransmissionErrorError", "TransmissionOptions", "transmission_error"]

log = logging.getLogger(__name__)

ARCSEC_PER_RAD = 180.0 * 3600.0 / math.pi

_BALL_MOTIONS = ("wave_generator", "cage")


class TransmissionErrorError(ProfilegenError, ValueError):
    """Bad input to the transmission-error run; names the parameter, value, unit and range."""


@dataclass(frozen=True)
class TransmissionOptions:
    """How :func:`transmission_error` solves (``options=``, in the style of scipy.optimize's): the
    defaults are the model the product runs.

    ``span``: ``"tooth"`` (one tooth passage, ψ in [0, 2π/z2), periodic) or a number of degrees
    of ψ (ψ in [0, span], both ends). ``side``: +1 the right FS flank loaded, −1 the left.
    ``ball_motion``: "wave_generator" (balls held against the major axis) or "cage" (rolling).
    ``keep_matrices``: keep each position's settled S and compliance. ``ball_supports``: "all"
    (every ball a one-sided support at its no-load gap, solved with the teeth:
    :meth:`~profilegen.contact.compliance.ContactCompliance.solve_unilateral`; ``matrices`` then
    holds S with the loaded balls rigid) or "window" (the balls within the rim's no-load contact
    angle, rigid, settled as :func:`~profilegen.contact.analysis.solve_contact`'s window option
    settles them: over a ball passage it jumps as a ball enters the window — the comparison).
    ``hertz_balls`` (with "all" only): the balls as the bearing's Hertz springs
    (:class:`~profilegen.contact.chain.BallBearing`, iterated to the Hertz law at each ball's
    reaction). ``stations``, ``max_gap_mm``, ``face_width_mm``, ``race_thickness_mm``,
    ``race_interface``: as :func:`~profilegen.contact.analysis.solve_contact`'s.
    """

    span: object = "tooth"
    side: int = 1
    stations: int = 5
    max_gap_mm: float = 0.12
    ball_motion: str = "wave_generator"
    face_width_mm: float | None = None
    race_thickness_mm: float | None = None
    race_interface: str = "sliding"
    keep_matrices: bool = False
    ball_supports: str = "all"
    hertz_balls: bool = False

    @classmethod
    def of(cls, options) -> "TransmissionOptions":
        """``options`` as a :class:`TransmissionOptions`: None (the defaults), one already, or a
        mapping of its fields (an unknown key is a :class:`TransmissionErrorError` naming it)."""
        return checks.options(cls, options, "options", error=TransmissionErrorError)


@dataclass(frozen=True, slots=True, eq=False)
class TransmissionError:
    """The loaded contact at wave-generator positions ψ (the module docstring; the model:
    docs/theory/torsion.md, "The transmission error").

    Per position: ``psi_rad`` ψ, ``shift_rad`` δ = −ψ z2/z1 (the teeth's shift against the
    major axis), ``rotation_rad`` φ, ``first_contact_rad`` φ₀, ``teeth_in_contact`` (one
    zone), ``max_tooth_force_n``, ``active_balls``, ``equilibrium_residual`` (|Σ r F − T/U|
    /(T/U), the solver's), ``flags`` (None or why the case is beyond the searched points).
    ``points`` and ``cases``: the :class:`~profilegen.contact.points.ContactPoints` and
    :class:`~profilegen.contact.analysis.LoadCase` of each position; ``matrices``: the settled
    compliance S (mm/N) of each position when asked for (``keep_matrices``), else () — with
    ``ball_supports="all"`` S with the loaded balls rigid at zero gap: a loaded ball's no-load
    gap then shifts the teeth's gaps (read them from ``compliances``: each position's
    :class:`~profilegen.contact.compliance.ContactCompliance`, kept with ``keep_matrices``).
    ``wrap_source``: where the wrap angle that selects the candidate balls came from.
    """

    torque_nm: float
    zones: int
    side: int
    ball_motion: str
    psi_rad: np.ndarray
    shift_rad: np.ndarray
    rotation_rad: np.ndarray
    first_contact_rad: np.ndarray
    teeth_in_contact: np.ndarray
    max_tooth_force_n: np.ndarray
    active_balls: np.ndarray
    equilibrium_residual: np.ndarray
    flags: tuple
    points: tuple = field(repr=False, default=())
    cases: tuple = field(repr=False, default=())
    matrices: tuple = field(repr=False, default=())
    compliances: tuple = field(repr=False, default=())
    wrap_source: str = ""
    workers: int = 1
    time_s: float = 0.0
    warnings: tuple[str, ...] = ()
    ball_supports: str = "all"
    hertz_balls: bool = False

    def __post_init__(self):
        for name in ("psi_rad", "shift_rad", "rotation_rad", "first_contact_rad", "max_tooth_force_n",
                     "equilibrium_residual"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        for name in ("teeth_in_contact", "active_balls"):
            object.__setattr__(self, name, _readonly(getattr(self, name), int))

    @property
    def psi_deg(self) -> np.ndarray:
        return np.degrees(self.psi_rad)

    @property
    def error_arcsec(self) -> np.ndarray:
        """φ(ψ) − mean φ (arcsec): the loaded transmission error about its mean."""
        return (self.rotation_rad - self.rotation_rad.mean()) * ARCSEC_PER_RAD

    @property
    def no_load_error_arcsec(self) -> np.ndarray:
        """φ₀(ψ) − mean φ₀ (arcsec): the same at no load (first contact)."""
        return (self.first_contact_rad - self.first_contact_rad.mean()) * ARCSEC_PER_RAD

    @property
    def peak_to_peak_arcsec(self) -> float:
        e = self.error_arcsec
        return float(e.max() - e.min())

    @property
    def stiffness_nm_per_rad(self) -> np.ndarray:
        """Secant mesh stiffness T / (φ − φ₀) at each ψ (N·m/rad)."""
        return self.torque_nm / (self.rotation_rad - self.first_contact_rad)

    @property
    def stiffness_ripple(self) -> float:
        """max / min of the secant mesh stiffness over ψ."""
        k = self.stiffness_nm_per_rad
        return float(k.max() / k.min())

    def to_dict(self) -> dict:
        k = self.stiffness_nm_per_rad
        return json_ready({
            "torque_nm": self.torque_nm,
            "zones": self.zones,
            "side": self.side,
            "ball_motion": self.ball_motion,
            "ball_supports": self.ball_supports,
            "hertz_balls": self.hertz_balls,
            "error_definition": "loaded rotation of the FS against the CS beyond the ideal-ratio position, minus "
                                "its mean over psi (arcsec)",
            "psi_deg": self.psi_deg,
            "error_arcsec": self.error_arcsec,
            "peak_to_peak_arcsec": self.peak_to_peak_arcsec,
            "no_load_error_arcsec": self.no_load_error_arcsec,
            "no_load_peak_to_peak_arcsec": float(np.ptp(self.no_load_error_arcsec)),
            "mean_rotation_arcsec": float(self.rotation_rad.mean() * ARCSEC_PER_RAD),
            "stiffness_nm_per_rad": k,
            "stiffness_ripple": self.stiffness_ripple,
            "teeth_in_contact_per_zone": self.teeth_in_contact,
            "max_tooth_force_n": self.max_tooth_force_n,
            "active_balls": self.active_balls,
            "flags": list(self.flags),
            "wrap_source": self.wrap_source,
            "workers": self.workers,
            "time_s": self.time_s,
            "warnings": list(self.warnings),
        })


# --------------------------------------------------------------------------- one position

#: what the forked workers inherit: (inputs, options) of the run in progress
_JOB: Any = None  # (inputs, options) in a worker process


def _position(inputs, psi: float, opts: dict):
    """The contact at one wave-generator position ψ → (points, case, settled S or None, warnings)."""
    from .analysis import solve_contact
    from .compliance import ContactCompliance
    from .points import contact_points

    g = inputs.gearset.gear
    shift = -psi * g.circular_spline_teeth / g.flexspline_teeth
    pts = contact_points(inputs, side=opts["side"], stations=opts["stations"], max_gap_mm=opts["max_gap_mm"],
                         shift_rad=shift)
    phase = 0.0 if opts["ball_motion"] == "wave_generator" else -psi * opts["cage_rate"]
    comp = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                   face_width_mm=opts["face_width_mm"], race_thickness_mm=opts["race_thickness_mm"],
                                   race_interface=opts["race_interface"], wrap_half_angle_rad=opts["wrap"],
                                   ball_phase_rad=phase, shift_rad=shift, ball_supports=opts["ball_supports"])
    res = solve_contact(inputs, [opts["torque_nm"]], points=pts, compliance=comp,
                        bearing=opts["bearing"] if opts["ball_supports"] == "all" else None)
    case = res.cases[0]
    matrix = (comp.with_balls(case.ball_active).matrix_mm_per_n, comp) if opts["keep_matrices"] else None
    return pts, case, matrix, res.warnings


def _job_position(psi: float):
    inputs, opts = _JOB
    return _position(inputs, psi, opts)


def _checked(name: str, value, unit: str, *, low: float = 0.0) -> float:
    if isinstance(value, bool):
        raise TransmissionErrorError(f"{name} = {value!r}: must be a number ({unit})")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise TransmissionErrorError(f"{name} = {value!r}: must be a number ({unit})") from None
    if not (math.isfinite(v) and v > low):
        raise TransmissionErrorError(f"{name} = {value!r} {unit}: must be finite and > {low:g}")
    return v


def _check_choices(chosen: TransmissionOptions) -> None:
    """The flank, ball-support and ball-motion options checked (a :class:`TransmissionErrorError` naming the bad one)."""
    side, ball_supports, hertz_balls = chosen.side, chosen.ball_supports, chosen.hertz_balls
    if side not in (1, -1):
        raise TransmissionErrorError(f"side = {side!r}: must be +1 (right FS flank loaded) or −1 (left)")
    if ball_supports not in ("window", "all"):
        raise TransmissionErrorError(f"ball_supports = {ball_supports!r}: must be 'window' (the balls within the rim's "
                                     "no-load contact angle) or 'all' (every ball one-sided at its no-load gap)")
    if hertz_balls not in (True, False):
        raise TransmissionErrorError(f"hertz_balls = {hertz_balls!r}: must be True or False")
    if hertz_balls and ball_supports != "all":
        raise TransmissionErrorError("hertz_balls = True: needs ball_supports = 'all' (the window model's balls are "
                                     "rigid here; chain.torsional_curve has them as Hertz springs)")
    if chosen.ball_motion not in _BALL_MOTIONS:
        raise TransmissionErrorError(f"ball_motion = {chosen.ball_motion!r}: must be one of {', '.join(_BALL_MOTIONS)}")


def _wave_generator_positions(span, positions: int, cs_teeth: int) -> np.ndarray:
    """The positions ψ (rad): evenly over one tooth passage (``span`` "tooth", periodic) or over
    ``span`` degrees, both ends."""
    passage = 2.0 * math.pi / cs_teeth
    if isinstance(span, str):
        if span != "tooth":
            raise TransmissionErrorError(f"span = {span!r}: must be 'tooth' (one tooth passage, 2π/z2) or a number "
                                         "of degrees of wave-generator rotation in (0, 360]")
        return passage * np.arange(positions) / positions
    span_deg = _checked("span", span, "deg")
    if span_deg > 360.0:
        raise TransmissionErrorError(f"span = {span!r} deg: must be in (0, 360] (degrees of wave-generator "
                                     "rotation) or 'tooth'")
    return np.radians(span_deg) * np.arange(positions) / (positions - 1)


def _ball_bearing(inputs, chosen: TransmissionOptions):
    """(the ball bearing where the balls roll or are Hertz springs, else None; the cage's rate
    against ψ, 0 where the balls are held)."""
    cage_rate = 0.0
    bearing = None
    if chosen.ball_motion == "cage" or chosen.hertz_balls:
        from .chain import BallBearing

        bearing = BallBearing.from_gearset(inputs.gearset, race_thickness_mm=chosen.race_thickness_mm)
        if chosen.ball_motion == "cage":
            cage_rate = 0.5 * (1.0 + bearing.ball_diameter_mm / bearing.pitch_diameter_mm)
    return bearing, cage_rate


def _solve_positions(inputs, psi: np.ndarray, opts: dict, workers: int) -> tuple[list, int]:
    """Each position's contact (:func:`_position`), in a forked pool of ``workers`` where more
    than one is asked and allowed → (results in the order of ``psi``, workers used)."""
    global _JOB
    import multiprocessing

    if multiprocessing.current_process().daemon:
        workers = 1  # a daemonic worker (a multiprocessing.Pool's, Dask's) cannot have children
    if workers > 1 and psi.size > 2:
        from concurrent.futures import ProcessPoolExecutor

        _JOB = (inputs, opts)  # inherited by the forked workers
        try:
            ctx = multiprocessing.get_context("fork")
            with ProcessPoolExecutor(max_workers=int(workers), mp_context=ctx) as pool:
                return list(pool.map(_job_position, psi.tolist())), workers
        finally:
            _JOB = None
    with one_blas_thread():
        return [_position(inputs, float(p), opts) for p in psi], 1


def transmission_error(inputs, torque_nm: float, *, positions: int = 16, workers: int | None = None,
                       options: TransmissionOptions | Mapping | None = None) -> TransmissionError:
    """The loaded transmission error of a design (or a :class:`~profilegen.contact.inputs.
    ContactInput`) at ``torque_nm`` (N·m, > 0, on the whole gear) over ``positions`` (≥ 2)
    wave-generator positions ψ (default: evenly over one tooth passage). ``workers``: processes
    (default: up to 2, one per position; 1 = in this process). ``options``: how to solve, a
    :class:`TransmissionOptions` or a mapping of its fields (span, flank, ball motion and
    supports, …). The model: docs/theory/torsion.md, "The transmission error"."""
    chosen = TransmissionOptions.of(options)
    from .compliance import wrap_half_angle

    t0 = time.perf_counter()
    inputs = ContactInput.from_design(inputs, name="inputs")
    g = inputs.gearset.gear
    torque = _checked("torque_nm", torque_nm, "N·m")
    if isinstance(positions, bool) or not isinstance(positions, (int, np.integer)) or positions < 2:
        raise TransmissionErrorError(f"positions = {positions!r}: must be a whole number ≥ 2 (wave-generator "
                                     "positions)")
    _check_choices(chosen)
    psi = _wave_generator_positions(chosen.span, positions, g.circular_spline_teeth)
    if workers is None:
        workers = min(2, os.cpu_count() or 1, positions)
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise TransmissionErrorError(f"workers = {workers!r}: must be a whole number ≥ 1 (processes)")
    bearing, cage_rate = _ball_bearing(inputs, chosen)
    with one_blas_thread():  # the flat-ring solve's BLAS threads only contend
        wrap, wrap_source = wrap_half_angle(inputs.rim_contact_angle_rad, inputs.gearset)  # once: ψ-invariant
    opts = dict(side=chosen.side, stations=chosen.stations, max_gap_mm=chosen.max_gap_mm,
                ball_motion=chosen.ball_motion, cage_rate=cage_rate, face_width_mm=chosen.face_width_mm,
                race_thickness_mm=chosen.race_thickness_mm, race_interface=chosen.race_interface, wrap=wrap,
                torque_nm=torque, keep_matrices=bool(chosen.keep_matrices), ball_supports=chosen.ball_supports,
                bearing=bearing if chosen.hertz_balls else None)
    out, workers = _solve_positions(inputs, psi, opts, workers)
    result = _transmission_result(chosen, torque, g, psi, out, wrap_source, workers, t0)
    log.debug("transmission_error: %d positions, %.2f s, %d workers", positions, result.time_s, workers)
    return result


def _transmission_result(chosen: TransmissionOptions, torque: float, g, psi: np.ndarray, out: list, wrap_source,
                         workers: int, t0: float) -> TransmissionError:
    """The :class:`TransmissionError` of the positions' contacts ``out`` (the warnings once each, in order)."""
    pts = tuple(o[0] for o in out)
    cases = tuple(o[1] for o in out)
    warnings = []
    for o in out:
        warnings += list(o[3])
    keep_matrices = chosen.keep_matrices
    return TransmissionError(
        torque_nm=torque, zones=int(g.waves), side=chosen.side, ball_motion=chosen.ball_motion, psi_rad=psi,
        shift_rad=-psi * g.circular_spline_teeth / g.flexspline_teeth,
        rotation_rad=np.array([c.rotation_rad for c in cases]),
        first_contact_rad=np.array([float(np.min(p.theta_rad)) for p in pts]),
        teeth_in_contact=np.array([c.teeth_in_contact for c in cases]),
        max_tooth_force_n=np.array([c.max_tooth_force_n for c in cases]),
        active_balls=np.array([int(np.count_nonzero(c.ball_active)) for c in cases]),
        equilibrium_residual=np.array([c.solution.equilibrium_residual for c in cases]),
        flags=tuple(c.beyond_capacity for c in cases), points=pts, cases=cases,
        matrices=tuple(o[2][0] for o in out) if keep_matrices else (),
        compliances=tuple(o[2][1] for o in out) if keep_matrices else (), wrap_source=wrap_source, workers=int(workers),
        time_s=time.perf_counter() - t0, warnings=tuple(dict.fromkeys(warnings)), ball_supports=chosen.ball_supports,
        hertz_balls=bool(chosen.hertz_balls))
