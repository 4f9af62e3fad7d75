"""The cup pressed onto the wave-generator contour over the bearing's width: frictionless
unilateral contact by collocation in φ, with the cup's harmonic solves as the compliance
operator (each solve stays 2D).

The unknowns are the cam's radial forces on the bearing band's bore nodes at J collocation
angles on 0..π/2 (each the total of its four symmetric copies: a two-wave contour is symmetric
about both axes); the gaps are first order (radial, at the undeformed angle) or exact (the
displaced bore point's signed distance to the contour, re-linearised until every loaded point
is on it); the contact is a symmetric positive definite complementarity problem, solved
exactly. Options: geometric nonlinearity (modified Newton on the harmonic-balance cup), and the
wave-generator bearing's outer race between bore and balls
(:class:`~profilegen.rim.cup.bearing.BearingRace`).

Entry point: :func:`press_cup` ``(geometry_or_gearset, contour=… | radial_mm=…, …)`` →
:class:`CupContact` (the :class:`~profilegen.rim.cup.fourier.CupDeformation` with harmonics
0..2(J − 1), and the contact state: forces, gaps, the race's state). :class:`DisplacedHalves` is
a wave generator of two rigid halves pushed apart (the FEA-deformation study's model).

>>> import profilegen
>>> from profilegen.rim.cup import press_cup
>>> c = press_cup(profilegen.load_gearset("default"), gap="exact")  # doctest: +SKIP
>>> c.deformation.omega(0.0, c.z_mm[-1]), c.max_penetration_mm  # doctest: +SKIP

Errors: :class:`~profilegen.rim.cup.geometry.CupError` (a ``ValueError``) naming a bad option
or load (both or neither of ``contour`` and ``radial_mm``, odd harmonics, the exact gap without
a contour, a race off the bearing band, a basis built for another geometry);
:class:`~profilegen.errors.ConvergenceError` when a harmonic's stiffness is singular, the
contact compliance is not positive definite, or the gaps or the Newton steps do not settle.

The formulation (the QP, the exact gap, the race's complementarity problem): docs/theory/cup.md,
"The bore on the wave generator".
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from functools import partial
from typing import cast

import numpy as np

from ... import checks
from ...errors import ConvergenceError
from ...lcp import primal_dual_from_guess, spd_nnls
from ...results import readonly
from ...stagecache import checkpoint
from .bearing import BearingRace
from .fourier import CupDeformation, HarmonicBasis, harmonic_resultants, bore_load, harmonic_stiffness
from .geometry import CupError, CupGeometry, meridional_mesh

__all__ = ["GAPS", "CupContact", "DisplacedHalves", "press_cup"]

log = logging.getLogger(__name__)

GAPS = ("first_order", "exact")

_whole = partial(checks.whole, error=CupError)


@dataclass(frozen=True, slots=True, eq=False)
class CupContact:
    """The cup on its contour: ``deformation`` (ω, υ, axial, tilt at any (φ, z)); the bearing
    band's bore nodes ``z_mm`` × collocation angles ``phi_rad`` (0..π/2): the cam's force
    ``force_n`` (N, each the total of its four symmetric copies; radial with the first-order
    gap, along the contour's normal with the exact one), the gap ``gap_mm`` (first order: the
    bore's radial displacement minus the contour's w(φ); exact: the displaced bore point's
    signed distance to the contour; ≥ 0), ``active`` (force > 0); ``load_mm``: w(φ_j);
    ``compliance_s``, ``contact_s``: times (s); ``gap``, ``nonlinear``: the model;
    ``iterations``: contact re-linearisations; ``newton_steps_mm``: the nonlinear steps;
    ``band_radial_mm``, ``band_tangential_mm``: the bore's displacement at the band × angles.
    With the bearing's outer race (``race``, :class:`~profilegen.rim.cup.bearing.BearingRace`;
    None: the rigid band): ``ball_force_n`` the ball row's force at each angle (N, the total of
    its four copies), ``race_radial_mm`` the race's outer surface's radial displacement at the
    band × angles (from its circle), ``race_tilt_rad`` its tilt at each angle (+: the open-end
    side outward), ``ball_approach_mm`` the balls' Hertz approach at each angle (0: rigid)."""

    deformation: CupDeformation
    z_mm: np.ndarray
    phi_rad: np.ndarray
    force_n: np.ndarray
    gap_mm: np.ndarray
    load_mm: np.ndarray
    compliance_s: float
    contact_s: float
    time_s: float
    gap: str = "first_order"
    nonlinear: bool = False
    iterations: int = 1
    newton_steps_mm: tuple = ()
    band_radial_mm: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    band_tangential_mm: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    race: BearingRace | None = None
    ball_force_n: np.ndarray = field(default_factory=lambda: np.zeros(0))
    race_radial_mm: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    race_tilt_rad: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ball_approach_mm: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self):
        for name in ("z_mm", "phi_rad", "force_n", "gap_mm", "load_mm", "band_radial_mm", "band_tangential_mm",
                     "ball_force_n", "race_radial_mm", "race_tilt_rad", "ball_approach_mm"):
            object.__setattr__(self, name, readonly(getattr(self, name)))

    @property
    def active(self) -> np.ndarray:
        return self.force_n > 0.0

    @property
    def max_penetration_mm(self) -> float:
        return float(max(0.0, -np.min(self.gap_mm)))

    def to_dict(self) -> dict:
        from ...results import json_ready

        out = self.deformation.to_dict()
        out["model"] = ("cup as a body of revolution, Fourier harmonics of 2D meridional FEM, pressed onto the "
                        + ("contour over the bearing width (a rigid band)" if self.race is None else
                           "wave generator's " + self.race.label())
                        + ": frictionless unilateral contact by collocation in φ, "
                        + ("exact gap (distance to the contour along its normal)" if self.gap == "exact"
                           else "first-order (radial) gap")
                        + (", geometrically nonlinear (total Lagrangian, harmonic balance)" if self.nonlinear
                           else ", linear") + ", boss clamped")
        out["contact"] = json_ready({"z_mm": self.z_mm, "phi_rad": self.phi_rad, "force_n": self.force_n,
                                     "gap_mm": self.gap_mm, "load_mm": self.load_mm,
                                     "max_penetration_mm": self.max_penetration_mm,
                                     "compliance_s": self.compliance_s, "contact_s": self.contact_s,
                                     "time_s": self.time_s, "gap": self.gap, "nonlinear": self.nonlinear,
                                     "iterations": self.iterations,
                                     "newton_steps_mm": list(self.newton_steps_mm)})
        if self.race is not None:
            out["race"] = json_ready({**self.race.to_dict(), "ball_force_n": self.ball_force_n,
                                      "tilt_rad": self.race_tilt_rad, "ball_approach_mm": self.ball_approach_mm,
                                      "radial_mm": self.race_radial_mm})
        return out

    def contact_span_mm(self, phi_index: int) -> tuple[float, float] | None:
        """(first, last) z of the loaded band nodes at collocation angle ``phi_index``, or None."""
        on = np.flatnonzero(self.active[:, phi_index])
        return None if on.size == 0 else (float(self.z_mm[on[0]]), float(self.z_mm[on[-1]]))


def _check_choice(name: str, value, allowed: tuple) -> str:
    if value not in allowed:
        raise CupError(f"{name} = {value!r}: must be one of {', '.join(repr(a) for a in allowed)}")
    return value


def press_cup(
    geometry_or_gearset,
    *,
    contour=None,
    radial_mm=None,
    angles: int = 16,
    element_mm: float = 2.0,
    layers: int = 2,
    harmonic_basis: HarmonicBasis | None = None,
    gap: str = "first_order",
    nonlinear: bool = False,
    open_end_axial_fixed: bool = False,
    gap_tol_mm: float = 1e-9,
    newton_tol_mm: float = 1e-7,
    max_iterations: int = 50,
    race: BearingRace | None = None,
) -> CupContact:
    """The cup pressed onto ``contour`` (or the bore shape ``radial_mm`` {n: w_n}, even n) over
    the bearing's width, frictionless and unilateral, boss clamped. ``angles`` J collocation
    angles on 0..π/2 (harmonics 0, 2, …, 2(J − 1)). With a GearSet and no load, its contour.

    ``gap``: ``"first_order"`` (the bore point's radial displacement minus the contour's
    w(φ) at its *undeformed* angle, the force radial) or ``"exact"`` (the signed distance of
    the displaced bore point — radial and tangential displacement — to the contour, the force
    along the contour's normal at its foot, re-linearised until every loaded point is on the
    contour within ``gap_tol_mm``: the 2D ring's contact; needs a ``contour``).
    ``nonlinear``: geometrically nonlinear (total Lagrangian St Venant–Kirchhoff by harmonic
    balance, :mod:`profilegen.rim.cup.nonlinear`), modified Newton with the linear harmonic
    stiffnesses from the linear solution, Anderson-accelerated (memory 5), until the step is
    below ``newton_tol_mm``.
    ``open_end_axial_fixed``: the open end's axial displacement held at zero (seed 004's
    restraint), otherwise free.
    ``race``: the wave-generator bearing's outer race on its ball row
    (:class:`~profilegen.rim.cup.bearing.BearingRace`: a ring that bends, tilts about the ball
    row and rests on Hertz balls; the bore on the race and the race on the balls, both
    unilateral, one complementarity problem); None: the bore pressed onto the contour itself, a
    rigid band over the bearing width (the limit of a stiff, stress-free race).

    Defaults (2 mm, 2 layers, 16 angles): within 0.3 µm in ω, 0.05 µm in υ of 1 mm / 31 angles
    over the default set's tooth ring, 3.1 s against 41 s under a load of ~8 on 2 cores
    (``python tests/benchmarks/cup3d.py``, part 6). On the default set the exact gap moves ω by
    up to 6.4 µm and the nonlinearity by up to 7.2 µm more; first order / exact / exact +
    nonlinear took 2.2 / 2.7 / 7.2 s under that load (``python tests/benchmarks/seed004_cup.py
    --fidelity``, docs/seed004_cup.md)."""
    from ...blas import one_blas_thread

    start = time.perf_counter()
    if isinstance(geometry_or_gearset, CupGeometry):
        geometry, gearset = geometry_or_gearset, None
    else:
        geometry, gearset = CupGeometry.from_gearset(geometry_or_gearset), geometry_or_gearset
    angles = _whole("angles", angles, 2)
    gap = _check_choice("gap", gap, GAPS)
    nonlinear = bool(_check_choice("nonlinear", nonlinear, (False, True)))
    open_end_axial_fixed = bool(_check_choice("open_end_axial_fixed", open_end_axial_fixed, (False, True)))
    gap_tol_mm = checks.number("gap_tol_mm", gap_tol_mm, "mm", 0.0, error=CupError)
    newton_tol_mm = checks.number("newton_tol_mm", newton_tol_mm, "mm", 0.0, error=CupError)
    max_iterations = _whole("max_iterations", max_iterations, 1)
    _check_race(race, geometry)
    orders = 2 * np.arange(angles)
    contour, phi, w_cam, load = _cam_load(geometry, gearset, contour, radial_mm, angles, gap, orders)
    if harmonic_basis is None:
        harmonic_basis = harmonic_stiffness(meridional_mesh(geometry, element_mm=element_mm, layers=layers))
        checkpoint()
    elif harmonic_basis.cup_mesh.geometry is not geometry:
        raise CupError("harmonic_basis: it was built for another CupGeometry than the one given")
    nodes = _band_nodes(harmonic_basis, geometry, open_end_axial_fixed)
    problem = _contact_problem(harmonic_basis, geometry, nodes, orders, phi, w_cam, contour, gap == "exact", race,
                               max_iterations, gap_tol_mm)
    t_comp = problem.compliance_s

    t0 = time.perf_counter()
    with one_blas_thread(True):
        x, mu, gap_mm, iterations, newton_steps, body = _solve(problem, nonlinear, newton_tol_mm)
    t_contact = time.perf_counter() - t0
    checkpoint()  # an engine's design stops here when superseded (before the resultants)
    boss_res, bore_res = _resultants(problem, x, body)
    elapsed = time.perf_counter() - start
    notes = _notes(problem, nonlinear, newton_steps, open_end_axial_fixed)
    hb, g, line, band = harmonic_basis, geometry, nodes.line, nodes.band
    deformation = CupDeformation(
        geometry=g, orders=orders, load_mm=np.array([load.get(int(n), 0.0) for n in orders]), z_mm=nodes.z[line],
        radial_mm=x[:, nodes.iu[line]], axial_mm=x[:, nodes.iw[line]], tangential_mm=x[:, nodes.iv[line]],
        bore_radial_mm=x[:, nodes.iu[nodes.bore_line]],
        boss_reaction=tuple(boss_res), bore_reaction=tuple(bore_res), dof=hb.dof,
        elements=hb.cup_mesh.elements, element_mm=hb.cup_mesh.element_mm, layers=hb.cup_mesh.layers,
        assembly_s=hb.assembly_s, solve_s=t_comp + t_contact, time_s=elapsed, warnings=tuple(notes))
    band_r, band_t = problem.at_band(x)
    return CupContact(deformation, nodes.z[band], phi, mu, gap_mm, w_cam, t_comp, t_contact, elapsed, gap=gap,
                      nonlinear=nonlinear, iterations=iterations, newton_steps_mm=tuple(newton_steps),
                      band_radial_mm=band_r, band_tangential_mm=band_t, **_race_fields(problem))


def _tolerance(g: CupGeometry) -> float:
    """The distance (mm) within which two mesh coordinates are the same."""
    return 1e-9 * max(g.outer_radius_mm, g.open_end_mm)


def _check_race(race, g: CupGeometry) -> None:
    """``race``: None or a BearingRace whose ball row lies on the bearing band."""
    if race is None:
        return
    if not isinstance(race, BearingRace):
        raise CupError(f"race = {race!r}: must be a BearingRace or None (the rigid band)")
    tol = _tolerance(g)
    lo_b, hi_b = g.bearing_span_mm
    if not lo_b - tol <= race.ball_row_z_mm <= hi_b + tol:
        raise CupError(f"race.ball_row_z_mm = {race.ball_row_z_mm!r} mm: must lie on the bearing band "
                       f"[{lo_b:g}, {hi_b:g}] mm")


def _cam_load(geometry: CupGeometry, gearset, contour, radial_mm, angles: int, gap: str, orders: np.ndarray):
    """The load: (contour or None, the collocation angles φ_j, the contour's w(φ_j) = ρ − r_bore,
    the bore-shape harmonics {n: w_n}) from ``contour``, ``radial_mm`` or the gear set's contour."""
    if radial_mm is not None and contour is not None:
        raise CupError("radial_mm and contour: give one load, not both")
    if radial_mm is None:
        if contour is None:
            if gearset is None:
                raise CupError("contour: a load is needed (contour or radial_mm) for a bare CupGeometry")
            from ...geometry.wavegen import from_gearset

            contour = from_gearset(gearset)
        phi = 0.5 * math.pi * np.arange(angles) / (angles - 1)
        checkpoint()  # an engine's design stops here when superseded
        w_cam = np.asarray(contour.radius(phi), dtype=float) - geometry.bore_radius_mm
        checkpoint()
        load = bore_load(contour, geometry.bore_radius_mm, max_order=int(orders[-1]))  # 1024 radii: 25-50 ms
        checkpoint()
    else:
        if gap == "exact":
            raise CupError("gap = 'exact': needs a contour (its normal and distance); a radial_mm bore shape has "
                           "only the first-order gap")
        from .fourier import radial_load

        load = radial_load(radial_mm)
        if any(n % 2 for n in load):
            raise CupError("radial_mm: odd harmonics break the two symmetry planes the contact uses")
        phi = 0.5 * math.pi * np.arange(angles) / (angles - 1)
        # radial_load raises on an empty mapping, so this is a sum of at least one array, never the int 0
        w_cam = cast(np.ndarray, sum(w * np.cos(n * phi) for n, w in load.items()))
    if gap == "exact" and not callable(getattr(contour, "closest", None)):
        raise CupError(f"contour = {contour!r}: gap = 'exact' needs a contour with closest(points)")
    return contour, phi, w_cam, load


@dataclass(frozen=True, slots=True, eq=False)
class _BandNodes:
    """The meridional mesh's nodes the contact reads: dof indices ``iu``, ``iw``, ``iv`` (radial,
    axial, tangential) of every node at (``r``, ``z``); the clamped boss ``boss``, the bearing
    band's bore nodes ``band`` (by z), the neutral line ``line`` and the bore ``bore_line`` past
    the bottom's mid-plane (by z); the unclamped dofs ``free`` and ``where`` (dof → its index
    among them, −1 clamped)."""

    iu: np.ndarray
    iw: np.ndarray
    iv: np.ndarray
    r: np.ndarray
    z: np.ndarray
    boss: np.ndarray
    band: np.ndarray
    line: np.ndarray
    bore_line: np.ndarray
    free: np.ndarray
    where: np.ndarray


def _band_nodes(hb: HarmonicBasis, g: CupGeometry, open_end_axial_fixed: bool) -> _BandNodes:
    """The node sets of ``hb``'s mesh (:class:`_BandNodes`): boss clamped, and the open end held
    axially when ``open_end_axial_fixed``."""
    iu, iw, iv = hb.components()
    r, z = hb.nodes
    tol = _tolerance(g)
    b_lo, b_hi = g.bearing_span_mm
    boss = np.flatnonzero(np.abs(r - g.boss_radius_mm) < tol)
    band = np.flatnonzero((np.abs(r - g.bore_radius_mm) < tol) & (z > b_lo - tol) & (z < b_hi + tol))
    band = band[np.argsort(z[band])]
    z_wall = 0.5 * g.bottom_thickness_mm
    line = np.flatnonzero((np.abs(r - g.neutral_radius_mm) < tol) & (z > z_wall - tol))
    line = line[np.argsort(z[line])]
    bore_line = np.flatnonzero((np.abs(r - g.bore_radius_mm) < tol) & (z > z_wall - tol))
    bore_line = bore_line[np.argsort(z[bore_line])]
    clamped = np.concatenate([iu[boss], iw[boss], iv[boss]])
    if open_end_axial_fixed:
        clamped = np.concatenate([clamped, iw[np.flatnonzero(np.abs(z - g.open_end_mm) < tol)]])
    free = np.setdiff1d(np.arange(hb.dof), clamped)
    where = -np.ones(hb.dof, dtype=int)
    where[free] = np.arange(free.size)
    return _BandNodes(iu, iw, iv, r, z, boss, band, line, bore_line, free, where)


def _harmonic_responses(hb: HarmonicBasis, nodes: _BandNodes, orders: np.ndarray, exact: bool):
    """Each harmonic's factorised stiffness and its responses (dof, comps·m) to unit radial (and,
    ``exact``, tangential) forces on the band's m nodes: (responses, factors, the band's
    symmetrised compliances G_n)."""
    from .fourier import factor_stiffness

    iu, iv, band, free, where = nodes.iu, nodes.iv, nodes.band, nodes.free, nodes.where
    m = band.size
    comps = 2 if exact else 1  # unit forces on the band: radial (and tangential)
    responses, factors = [], []
    rhs = np.zeros((free.size, comps * m))
    rhs[where[iu[band]], np.arange(m)] = 1.0
    if exact:
        rhs[where[iv[band]], m + np.arange(m)] = 1.0
    for n in orders:
        checkpoint()  # an engine's design stops here when superseded (a harmonic's factorisation)
        stiff = hb.stiffness(int(n))
        try:
            factor = factor_stiffness(stiff[free][:, free])
            cols = factor.solve(rhs)
        except RuntimeError as exc:
            raise ConvergenceError(f"press_cup: the harmonic n = {n} stiffness is singular ({exc})") from exc
        full = np.zeros((hb.dof, comps * m))
        full[free] = cols
        responses.append(full)
        factors.append(factor)
    band_dofs = np.concatenate([iu[band], iv[band]]) if exact else iu[band]
    blocks = []
    for full in responses:
        g_n = full[band_dofs]
        blocks.append(0.5 * (g_n + g_n.T))
    return responses, factors, blocks


@dataclass(frozen=True, slots=True, eq=False)
class _RaceOperators:
    """The bearing's outer race ``bearing`` between the collocation angles: ``w`` its radial and
    ``b`` its tilt compliance (angles × angles), ``arm`` the band nodes' lever about the ball row,
    ``bb`` / ``bc`` the race's radial compliance band ← band / band ← ball row, ``coef`` the
    contour's cosine coefficients at the angles, ``pre`` the race's own shape on the balls,
    ``ball_gain`` the ball load per unit angle force."""

    bearing: BearingRace
    w: np.ndarray
    b: np.ndarray
    arm: np.ndarray
    bb: np.ndarray
    bc: np.ndarray
    coef: np.ndarray
    pre: np.ndarray
    ball_gain: np.ndarray


def _race_operators(race: BearingRace, orders: np.ndarray, phi: np.ndarray, a_cos: np.ndarray, w_cam: np.ndarray,
                    z_band: np.ndarray) -> _RaceOperators:
    """The race's compliances between the collocation angles and the band nodes at ``z_band``."""
    m, angles = z_band.size, phi.size
    cw, cb = race.compliances(orders)
    race_w = a_cos.T @ (cw[:, None] * a_cos)  # (angles, angles): radial at φ_j per unit force at φ_k
    race_b = a_cos.T @ (cb[:, None] * a_cos)  # tilt at φ_j per unit moment at φ_k
    arm = z_band - race.ball_row_z_mm  # (m,) the band nodes' lever about the ball row
    race_bb = np.kron(np.ones((m, m)), race_w) + np.kron(np.outer(arm, arm), race_b)
    race_bc = np.kron(np.ones((m, 1)), race_w)
    # the race's own shape on the balls: the contour's harmonics n ≥ 2 (its mean is the
    # inextensible race's, not a stretch); a stress-free race is on the contour without load
    coef = np.linalg.solve(a_cos.T, w_cam)
    race_pre = (w_cam - coef[0]) if race.prestress else np.zeros(angles)
    ball_gain = race.ball_loads(np.ones(angles), phi)  # ball load per unit angle force
    return _RaceOperators(race, race_w, race_b, arm, race_bb, race_bc, coef, race_pre, ball_gain)


@dataclass(slots=True, eq=False)
class _RaceIterate:
    """The race's last solved state, carried from one contact solve to the next (the warm start
    of the modified Newton steps): ball forces ``lam``, Hertz secants ``secant`` and approach
    ``approach`` at each angle; the race's radial displacement ``band`` at the band, the bore's
    forces ``mu`` and normals' radial components ``n_r`` it was solved with."""

    lam: np.ndarray
    secant: np.ndarray | None = None
    approach: np.ndarray | None = None
    band: np.ndarray | None = None
    mu: np.ndarray | None = None
    n_r: np.ndarray | None = None


def _pair_compliance(blocks, rows: slice, cols: slice, ta: np.ndarray, tb: np.ndarray, m: int,
                     angles: int) -> np.ndarray:
    """The compliance between the collocation points for one pair of components (radial /
    tangential force → radial / tangential displacement), before the normals weight it:
    T[(i,j),(i',j')] = Σ_n G_n[i,i'] a_n(φ_j) a_n(φ_j')."""
    t = sum(np.einsum("ik,j,l->ijkl", blk[rows][:, cols], ta[k], tb[k]) for k, blk in enumerate(blocks))
    return t.reshape(m * angles, m * angles)


def _contact_problem(hb: HarmonicBasis, g: CupGeometry, nodes: _BandNodes, orders: np.ndarray, phi: np.ndarray,
                     w_cam: np.ndarray, contour, exact: bool, race: BearingRace | None, max_iterations: int,
                     gap_tol_mm: float) -> _CupProblem:
    """The operators of the contact problem (:class:`_CupProblem`): the harmonic responses and
    compliances, the race's, and the collocation points' frames."""
    m, angles = nodes.band.size, phi.size
    t0 = time.perf_counter()
    responses, factors, blocks = _harmonic_responses(hb, nodes, orders, exact)
    a_cos = np.cos(np.outer(orders, phi))  # (harmonics, angles)
    a_sin = np.sin(np.outer(orders, phi))
    race_ops, race_now = None, None
    if race is not None:
        race_ops = _race_operators(race, orders, phi, a_cos, w_cam, nodes.z[nodes.band])
        race_now = _RaceIterate(lam=np.zeros(angles), approach=np.zeros(angles))
    compliance_s = time.perf_counter() - t0
    # the band's bore points (m, J) in the wave-generator frame: (r sin φ, r cos φ)
    e_r = np.stack([np.sin(phi), np.cos(phi)], axis=-1)[None, :, :]
    e_t = np.stack([np.cos(phi), -np.sin(phi)], axis=-1)[None, :, :]
    x_ref = g.bore_radius_mm * e_r
    checkpoint()
    sl_u, sl_v = slice(0, m), slice(m, 2 * m)
    t_uu = _pair_compliance(blocks, sl_u, sl_u, a_cos, a_cos, m, angles)
    t_uv = t_vv = None
    if exact:
        t_uv = _pair_compliance(blocks, sl_u, sl_v, a_cos, a_sin, m, angles)
        t_vv = _pair_compliance(blocks, sl_v, sl_v, a_sin, a_sin, m, angles)
    return _CupProblem(hb, nodes, orders, phi, w_cam, contour, exact, m, angles, responses, factors, blocks, a_cos,
                       a_sin, e_r, e_t, x_ref, t_uu, t_uv, t_vv, race_ops, race_now, max_iterations, gap_tol_mm,
                       compliance_s)


def _complementary(compliance: np.ndarray, q: np.ndarray, guess: np.ndarray | None, m: int,
                   angles: int) -> np.ndarray:
    """μ ≥ 0, Cμ − q ≥ 0, μ·(Cμ − q) = 0: first a primal–dual active-set iteration from the
    ``guess`` (the last set: a few linear solves), exactly by NNLS (min |Lᵀμ − L⁻¹q|, C = LLᵀ)
    if it does not settle in 12 sets or cycles (:mod:`profilegen.lcp`). ``m`` × ``angles``: the
    band's points (for the error message)."""
    from scipy.linalg import LinAlgError

    mu = primal_dual_from_guess(compliance, q, guess, max_sets=12)
    if mu is not None:
        return mu
    try:
        return spd_nnls(compliance, q)
    except LinAlgError as exc:
        raise ConvergenceError(f"press_cup: the contact compliance ({m} band nodes × {angles} angles) is "
                               f"not positive definite ({exc})") from exc


@dataclass(frozen=True, slots=True, eq=False)
class _CupProblem:
    """One press_cup's contact problem, built whole by :func:`_contact_problem`: the harmonic
    basis ``hb`` and its ``nodes``; the harmonic ``orders``, collocation angles ``phi`` and the
    contour's ``w_cam`` there (``contour`` for the exact gap); the band's ``m`` nodes × ``angles``;
    each harmonic's ``responses`` to unit band forces, its stiffness ``factors`` and band
    compliance ``blocks``; ``a_cos``, ``a_sin`` (harmonics × angles); the points' frames ``e_r``,
    ``e_t`` and undeformed positions ``x_ref``; the pair compliances ``t_uu``, ``t_uv``, ``t_vv``;
    the race (``race``, None: the rigid band) and its last iterate ``race_now``; the
    re-linearisations' limit ``max_iterations`` and ``gap_tol_mm``; ``compliance_s`` the time the
    harmonic responses and the race's compliances took (s).

    Its methods are the steps of the solve, each a function of these operators; only
    :meth:`contact` writes, to ``race_now`` (the race's warm start for the next solve)."""

    hb: HarmonicBasis
    nodes: _BandNodes
    orders: np.ndarray
    phi: np.ndarray
    w_cam: np.ndarray
    contour: object
    exact: bool
    m: int
    angles: int
    responses: list
    factors: list
    blocks: list
    a_cos: np.ndarray
    a_sin: np.ndarray
    e_r: np.ndarray
    e_t: np.ndarray
    x_ref: np.ndarray
    t_uu: np.ndarray
    t_uv: np.ndarray | None
    t_vv: np.ndarray | None
    race: _RaceOperators | None
    race_now: _RaceIterate | None
    max_iterations: int
    gap_tol_mm: float
    compliance_s: float

    def state(self, u_r, u_t):
        """(n_r, n_t, signed distance) of the bore points displaced by (u_r, u_t) (m, J)."""
        if not self.exact:
            return np.ones_like(u_r), np.zeros_like(u_r), u_r - self.w_cam[None, :]
        e_r, e_t, m, angles = self.e_r, self.e_t, self.m, self.angles
        pos = self.x_ref + u_r[..., None] * e_r + u_t[..., None] * e_t
        _, normal, dist = self.contour.closest(pos.reshape(-1, 2))
        normal = normal.reshape(m, angles, 2)
        return (np.einsum("ija,ija->ij", normal, np.broadcast_to(e_r, normal.shape)),
                np.einsum("ija,ija->ij", normal, np.broadcast_to(e_t, normal.shape)), dist.reshape(m, angles))

    def generalised(self, mu, n_r, n_t):
        """The harmonic generalised forces (harmonics, comps·m) of the point forces μ along n."""
        p_u = (mu * n_r) @ self.a_cos.T  # (m, harmonics)
        if not self.exact:
            return p_u.T
        return np.concatenate([p_u, (mu * n_t) @ self.a_sin.T], axis=0).T

    def band_displacement(self, p):
        """(u_r, u_t) (m, J) at the collocation points of the band for generalised forces p."""
        m = self.m
        y = np.stack([blk @ p[k] for k, blk in enumerate(self.blocks)])  # (harmonics, comps·m)
        u_r = y[:, :m].T @ self.a_cos
        u_t = y[:, m:].T @ self.a_sin if self.exact else np.zeros_like(u_r)
        return u_r, u_t

    def assemble(self, n_r, n_t):
        """The contact compliance C = Σ_n B_nᵀ G_n B_n between the points, along their normals."""
        a, b = n_r.ravel(), n_t.ravel()
        c = a[:, None] * self.t_uu * a[None, :]
        if self.exact:
            cross = a[:, None] * self.t_uv * b[None, :]
            c = c + cross + cross.T + b[:, None] * self.t_vv * b[None, :]
        return 0.5 * (c + c.T)

    def race_state(self, mu, lam, n_r):
        """The race under the ball forces λ and the bore's μ (radial part n_r μ): (its outer
        surface's radial displacement from its circle at the band (m, J), at the ball row (J),
        its tilt (J)), the contour's mean and the race's own shape included."""
        race = cast(_RaceOperators, self.race)
        arm = race.arm
        pushed = n_r * mu
        force = lam - pushed.sum(axis=0)
        tilt = race.b @ (-(arm[:, None] * pushed).sum(axis=0))
        at_row = race.w @ force
        mean = race.coef[0] if race.bearing.prestress else 0.0
        shift = 0.0 if race.bearing.prestress else self.w_cam  # a stress-free race sits on the contour unloaded
        return at_row[None, :] + arm[:, None] * tilt[None, :] + mean + shift, at_row + mean + shift, tilt

    def with_race(self, compliance, q, n_r, secant):
        """The bore's contact and the ball row's as one problem: unknowns (μ, λ), the gaps
        (bore − race, race − balls' reach) ≥ 0."""
        race = cast(_RaceOperators, self.race)
        m, angles = self.m, self.angles
        a = n_r.ravel()
        full = np.empty((m * angles + angles,) * 2)
        k = m * angles
        full[:k, :k] = compliance + a[:, None] * race.bb * a[None, :]
        full[:k, k:] = -a[:, None] * race.bc
        full[k:, :k] = full[:k, k:].T
        full[k:, k:] = race.w + np.diag(secant)
        return full, np.concatenate([q - a * np.repeat(race.pre[None, :], m, axis=0).ravel(), race.pre])

    def secants(self, lam):
        """The Hertz secants δ/F (mm/N per unit angle force) at the angles' forces (a 1 N ball
        load floor, as the contact chain's); zeros with rigid balls."""
        race = cast(_RaceOperators, self.race)
        if race.bearing.hertz_coefficient_mm is None:
            return np.zeros(self.angles)
        q_ball = np.maximum(race.ball_gain * lam, 1.0)
        return race.bearing.hertz_coefficient_mm * race.ball_gain * q_ball ** (-1.0 / 3.0)

    def contact(self, now_r, now_t, base_r, base_t, guess=None):
        """Unilateral contact for band displacement (now + base + G f), the gap re-linearised
        at the current iterate until the loaded points sit on the contour (with the race: on
        the race, the race on its balls, the Hertz secants settled): (μ, n_r, n_t, gap,
        iterations)."""
        m, angles, w_cam, race_now = self.m, self.angles, self.w_cam, self.race_now
        gap_tol_mm = self.gap_tol_mm
        disp_r, disp_t = base_r.copy(), base_t.copy()
        n_r, n_t, dist = self.state(now_r + disp_r, now_t + disp_t)
        if race_now is not None:
            if guess is not None and guess.size == m * angles:
                guess = np.concatenate([guess, race_now.lam > 0.0])
            secant = race_now.secant if race_now.secant is not None else self.secants(race_now.lam)
        for iteration in range(1, self.max_iterations + 1):
            checkpoint()  # an engine's design stops here when superseded (a re-linearisation: a few ms)
            q = (n_r * (disp_r - base_r) + n_t * (disp_t - base_t) - dist).ravel()
            compliance = self.assemble(n_r, n_t)
            if race_now is not None:
                compliance, q = self.with_race(compliance, q, n_r, secant)
            force = _complementary(compliance, q, guess, m, angles)
            if not np.all(np.isfinite(force)):
                raise ConvergenceError(f"press_cup: non-finite contact forces at iteration {iteration}")
            mu = force[:m * angles].reshape(m, angles)
            guess = force > 0.0
            used = n_r, n_t
            d_r, d_t = self.band_displacement(self.generalised(mu, n_r, n_t))
            disp_r, disp_t = base_r + d_r, base_t + d_t
            n_r, n_t, dist = self.state(now_r + disp_r, now_t + disp_t)
            settled, gap_now = True, dist
            if race_now is not None:
                lam = force[m * angles:]
                band_race, _, _ = self.race_state(mu, lam, used[0])
                gap_now = dist - n_r * (band_race - w_cam[None, :])  # the bore's gap to the race
                approach = self.secants(lam) * lam  # Hertz c_H Q^(2/3); linear below the 1 N floor
                settled = float(np.max(np.abs(secant * lam - approach), initial=0.0)) <= max(gap_tol_mm, 1e-12)
                log.debug("press_cup race: iteration %d, Hertz residual %.3g mm, balls on %d", iteration,
                          float(np.max(np.abs(secant * lam - approach), initial=0.0)), int((lam > 0).sum()))
                race_now.lam, race_now.secant, race_now.approach = lam, secant, approach
                race_now.band, race_now.mu, race_now.n_r = band_race, mu, used[0]
                secant = self.secants(lam)  # the secant fixed point (c_H Q^(-1/3): a contraction by ~1/3)
            on = mu > 0.0
            if (settled and np.max(np.abs(gap_now[on]), initial=0.0) <= gap_tol_mm
                    and np.min(gap_now[~on], initial=0.0) >= -gap_tol_mm):
                return mu, used[0], used[1], gap_now, iteration
        raise ConvergenceError(
            f"press_cup: the contact gaps did not close in {self.max_iterations} re-linearisations (largest gap "
            f"error {np.max(np.abs(gap_now[mu > 0]), initial=0.0):.3g} mm, deepest penetration "
            f"{-np.min(gap_now[mu <= 0], initial=0.0):.3g} mm)")

    def solve_field(self, rhs_of):
        """Displacement (harmonics, dof) for the generalised force rhs_of(k) of each harmonic."""
        free = self.nodes.free
        out = np.zeros((self.orders.size, self.hb.dof))
        for k, factor in enumerate(self.factors):
            out[k, free] = factor.solve(rhs_of(k)[free])
        return out

    def response(self, mu, n_r, n_t):
        """Displacement (harmonics, dof) under the point forces μ along the normals (n_r, n_t)."""
        p = self.generalised(mu, n_r, n_t)
        return np.stack([full @ p[k] for k, full in enumerate(self.responses)])

    def at_band(self, x):
        """(radial, tangential) displacement (m, J) of the band's points for the harmonics ``x``."""
        band = self.nodes.band
        return x[:, self.nodes.iu[band]].T @ self.a_cos, x[:, self.nodes.iv[band]].T @ self.a_sin

    def final_state(self, u_r, u_t):
        """state() with the gap measured to the race (its last solved position) when there is one."""
        n_r, n_t, dist = self.state(u_r, u_t)
        if self.race_now is not None:
            dist = dist - n_r * (self.race_now.band - self.w_cam[None, :])
        return n_r, n_t, dist


def _solve(problem: _CupProblem, nonlinear: bool, newton_tol_mm: float):
    """The linear contact solve, then (``nonlinear``) the modified Newton loop: (x, μ, gap,
    contact iterations, Newton steps, the nonlinear body or None)."""
    hb, orders, max_iterations = problem.hb, problem.orders, problem.max_iterations
    contact, response, at_band = problem.contact, problem.response, problem.at_band
    zero = np.zeros((problem.m, problem.angles))
    mu, n_r, n_t, dist, iterations = contact(zero, zero, zero, zero)
    x = response(mu, n_r, n_t)
    newton_steps: list[float] = []
    body = None
    if nonlinear:
        from .nonlinear import HarmonicTotalLagrangian

        body = HarmonicTotalLagrangian(hb, orders)
        mixed: list[tuple[np.ndarray, np.ndarray]] = []  # Anderson history: (x_k + Δx_k, Δx_k)
        best = math.inf
        for newton in range(1, max_iterations + 1):
            checkpoint()  # an engine's design stops here when superseded (a Newton step: ~25 ms)
            internal = body.force(x)
            du = problem.solve_field(lambda k, internal=internal: -internal[k])
            now_r, now_t = at_band(x)
            base_r, base_t = at_band(du)
            mu, n_r, n_t, dist, its = contact(now_r, now_t, base_r, base_t, guess=(mu > 0.0).ravel())
            iterations += its
            du += response(mu, n_r, n_t)
            step = float(np.max(np.abs(du)))
            if not np.isfinite(step):
                raise ConvergenceError(f"press_cup (nonlinear): non-finite Newton step at iteration {newton}")
            newton_steps.append(step)
            log.debug("press_cup (nonlinear): Newton %d, step %.3g mm, %d loaded points", newton, step,
                      int((mu > 0).sum()))
            if step <= newton_tol_mm:
                x = x + du
                break
            # Anderson acceleration (memory 5) of the fixed-point map x → x + Δx of the modified
            # Newton step; the history restarts when a step grows past twice the best one
            if step > 2.0 * best:
                mixed.clear()
            best = min(best, step)
            mixed.append((x + du, du))
            mixed = mixed[-6:]
            if len(mixed) > 1:
                d_g = np.stack([(a[0] - b[0]).ravel() for a, b in zip(mixed[1:], mixed[:-1])], axis=1)
                d_f = np.stack([(a[1] - b[1]).ravel() for a, b in zip(mixed[1:], mixed[:-1])], axis=1)
                gamma = np.linalg.lstsq(d_f, du.ravel(), rcond=None)[0]
                x = x + du - (d_g @ gamma).reshape(x.shape)
            else:
                x = x + du
        else:
            raise ConvergenceError(f"press_cup (nonlinear): no convergence in {max_iterations} Newton iterations "
                                   "(last steps " + ", ".join(f"{s:.2e}" for s in newton_steps[-4:]) + " mm)")
        now_r, now_t = at_band(x)
        dist = problem.final_state(now_r, now_t)[2]
    return x, mu, dist, iterations, newton_steps, body


def _resultants(problem: _CupProblem, x: np.ndarray, body) -> tuple[list, list]:
    """Each harmonic's force resultants on the boss and on the band, from the reaction forces
    (the nonlinear ``body``'s internal force, else K_n x_n)."""
    hb, nodes = problem.hb, problem.nodes
    boss_res, bore_res = [], []
    internal = body.force(x) if body is not None else None
    for k, n in enumerate(problem.orders):
        reaction = internal[k] if internal is not None else hb.stiffness(int(n)) @ x[k]  # None iff not nonlinear
        boss_res.append(harmonic_resultants(int(n), reaction, (nodes.iu, nodes.iw, nodes.iv), nodes.r, nodes.z,
                                            nodes.boss))
        bore_res.append(harmonic_resultants(int(n), reaction, (nodes.iu, nodes.iw, nodes.iv), nodes.r, nodes.z,
                                            nodes.band))
    return boss_res, bore_res


def _notes(problem: _CupProblem, nonlinear: bool, newton_steps: list, open_end_axial_fixed: bool) -> list[str]:
    """The deformation's notes: the gap, the nonlinearity, the open end's restraint, the race."""
    notes = ["unilateral contact by collocation, " + ("exact gap (the contour's distance along its normal)"
                                                        if problem.exact else "first-order (radial) gap")]
    if nonlinear:
        notes.append(f"geometrically nonlinear (harmonic balance), {len(newton_steps)} modified Newton steps")
    if open_end_axial_fixed:
        notes.append("open end held axially")
    if problem.race is not None:
        notes.append("on the wave generator's " + problem.race.bearing.label())
    return notes


def _race_fields(problem: _CupProblem) -> dict:
    """CupContact's race fields from the race's last iterate ({} for the rigid band)."""
    race_now = problem.race_now
    if race_now is None or problem.race is None:
        return {}
    band_race, _, tilt = problem.race_state(race_now.mu, race_now.lam, race_now.n_r)
    return {"race": problem.race.bearing, "ball_force_n": race_now.lam, "race_radial_mm": band_race,
            "race_tilt_rad": tilt, "ball_approach_mm": race_now.approach}


class DisplacedHalves:
    """A wave generator of two rigid halves (seed 004: "its upper and lower semi-elliptical halves
    are given prescribed displacements of +ω0 and −ω0"): the half y ≥ 0 of ``half`` (a contour
    symmetric about both axes; wave-generator frame, major axis +y) moved by +``shift_mm`` along
    the major axis, the half y ≤ 0 by −``shift_mm``. Between them, about the minor axis, the
    bore rests on the straight bridges x = ±x_end, |y| < shift (x_end = the half's radius on the
    minor axis): the convex hull, the surface a bore wrapped around the two halves touches.

    ``closest(points)`` → (foot, outward normal, signed distance, + outside) and ``radius(θ)``
    (polar radius of the hull) as the contours of :mod:`profilegen.geometry.wavegen`."""

    def __init__(self, half, shift_mm: float):
        if not (callable(getattr(half, "closest", None)) and callable(getattr(half, "radius", None))):
            raise CupError(f"half = {half!r}: must be a wave-generator contour with closest(points) and radius(θ)")
        self.half = half
        self.shift_mm = checks.number("shift_mm", shift_mm, "mm", 0.0, error=CupError, low_open=False)
        self.x_end_mm = float(np.asarray(half.radius(0.5 * math.pi)).ravel()[0])

    def closest(self, points):
        p = np.asarray(points, dtype=float).reshape(-1, 2)
        s = np.where(p[:, 1] >= 0.0, 1.0, -1.0)
        q = p.copy()
        q[:, 1] -= s * self.shift_mm
        foot, normal, dist = (np.array(a, dtype=float) for a in self.half.closest(q))
        foot[:, 1] += s * self.shift_mm
        bridge = np.abs(p[:, 1]) < self.shift_mm
        if bridge.any():
            side = np.where(p[bridge, 0] >= 0.0, 1.0, -1.0)
            foot[bridge] = np.column_stack([side * self.x_end_mm, p[bridge, 1]])
            normal[bridge] = np.column_stack([side, np.zeros_like(side)])
            dist[bridge] = np.abs(p[bridge, 0]) - self.x_end_mm
        return foot, normal, dist

    def radius(self, theta) -> np.ndarray:
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        e = np.column_stack([np.sin(theta), np.cos(theta)])
        lo = np.zeros_like(theta)
        hi = np.full_like(theta, 2.0 * (self.x_end_mm + self.shift_mm) + float(np.max(self.half.radius(0.0))))
        for _ in range(100):  # a star-shaped hull: the signed distance grows along the ray
            mid = 0.5 * (lo + hi)
            outside = self.closest(mid[:, None] * e)[2] > 0.0
            hi = np.where(outside, mid, hi)
            lo = np.where(outside, lo, mid)
        return 0.5 * (lo + hi)

    def to_dict(self) -> dict:
        half = self.half.to_dict() if callable(getattr(self.half, "to_dict", None)) else repr(self.half)
        return {"kind": "displaced_halves", "half": half, "shift_mm": self.shift_mm, "x_end_mm": self.x_end_mm}
