"""The climb: the loaded FS teeth riding up the CS flanks, by continuation in the rotation.

The ratcheting estimate's model (:func:`profilegen.contact.ratchet.ratcheting_torque`,
``climb=True``, builds it). Units mm, N, rad; torque N·m (``zones`` × Σ F·r / 1000).

At each rotation φ of the FS against the CS the loaded teeth stand out of their CS spaces by
their retreat s (the FS side from the contact's influence coefficients, the CS side from the CS
as a free ring); the gaps and lever arms of material stations on the loaded flanks and the FS
tip corners are measured against the whole CS surface (every space and the tip lands between
them), the contact forces solve the complementarity problem on that geometry, and s is
iterated to its fixed point. T(φ) is followed over increasing φ (rotation control passes its
maximum); the ratcheting torque is the first of: the limit point max T(φ); the force-weighted
margin Σ F_k (h_k − s_k)/Σ F_k reaching 0; with ``corner_normal=False`` half of the load on
the tip-corner stations. A path that ends with no equilibrium beyond a rising T is reported as
"end of path", never as a torque.

Entry points:

* :class:`DesignClimb` — one engagement zone of a design (``inputs`` a
  :class:`~profilegen.contact.inputs.ContactInput`); options for the corner normal, the ball
  supports, the CS ring's scale and Coulomb friction (``friction_coefficient`` with
  ``friction_sliding`` one of :data:`SLIDING`);
* :class:`SlicedClimb` of :func:`section_inputs` — N axial slices of the 3D cup's sections
  sharing φ, independent or with the face held straight (``coupled``);
* :func:`climb` ``(model, phi_start, phi_step)`` → :class:`ClimbPath` (its points
  :class:`ClimbPoint`, the criterion met, the limit torque);
* :func:`sliding_tangent`, :func:`tooth_probes`; the complementarity problems are solved by
  :func:`profilegen.lcp.solve_spd` (with friction, nonsymmetric: :func:`profilegen.lcp.solve_p_matrix`).

Errors: :class:`ClimbError` (a ``ValueError``) for a bad friction option;
:class:`~profilegen.errors.ConvergenceError` when no tooth comes within ``max_gap_mm``, the
CS space's outline is not single-valued, or the retreat, the ball set or Lemke's basis does
not settle.

The model, its friction senses and what it leaves out, with the measured numbers:
docs/theory/torsion.md, "The climb".
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import partial

import numpy as np
from scipy.linalg import cho_factor, cho_solve, solve_triangular

from ..errors import ConvergenceError, ProfilegenError
from ..lcp import solve_p_matrix, solve_spd

__all__ = ["SLIDING", "ClimbError", "ClimbPath", "ClimbPoint", "DesignClimb", "SectionDeformation", "SlicedClimb",
           "climb", "section_inputs", "sliding_tangent", "tooth_probes"]


#: the sliding speed (mm per rad of φ) over which the "-elastic" senses' friction turns from
#: −μN to +μN (a regularised Coulomb law; the kinematic sliding speeds are 0.02–1 mm/rad)
SLIP_SPEED = 0.01

#: the friction's sliding senses (DesignClimb ``friction_sliding``)
SLIDING = ("static", "unloading", "forward", "backward", "forward-elastic", "backward-elastic")


class ClimbError(ProfilegenError, ValueError):
    """Bad input to a climb model (names the parameter, its value and allowed range)."""


def sliding_tangent(normal: np.ndarray, e_r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(sense, t): the unit tangent t = sense · (−n_y, n_x) of each contact normal n (out of
    the FS) with t·e_r < 0 — the direction along the CS flank out of the CS space (toward the
    CS tip, radially in: e_r points out of the gear centre, into the CS). A station whose FS
    point slides that way relative to the CS (the teeth climbing out, or leaving the mesh)
    takes the friction force μN along +t on the CS (−t on the FS): the force on the CS is
    N (n + μ t), its radial part N (sin α − μ cos α) — friction holds the tooth in. Sliding
    into the space (entering): N (n − μ t)."""
    n = np.asarray(normal, dtype=float)
    perp = np.column_stack([-n[:, 1], n[:, 0]])
    sense = np.where(np.einsum("ij,ij->i", perp, np.asarray(e_r, dtype=float)) > 0.0, -1.0, 1.0)
    return sense, sense[:, None] * perp


@dataclass(frozen=True, slots=True)
class ClimbPoint:
    """One rotation of the path: ``phi_rad``, ``torque_nm``, per tooth ``retreat_mm`` s (FS +
    CS ring) and ``retreat_fs_mm``, the station forces ``force_n``, the force-weighted
    ``margin_mm`` Σ F (h − s)/Σ F, ``alpha_deg`` (force-weighted pressure angle),
    ``corner_share`` (the load share on tip-corner stations), ``iterations``."""

    phi_rad: float
    torque_nm: float
    retreat_mm: np.ndarray
    retreat_fs_mm: np.ndarray
    force_n: np.ndarray
    margin_mm: float
    alpha_deg: float
    mean_retreat_mm: float
    corner_share: float
    iterations: int
    state: object = None


@dataclass(frozen=True, slots=True)
class ClimbPath:
    """The path and its ratcheting torque (``torque_nm``; ``criterion`` which ended it:
    "limit point", "margin", "corner", "end of path" (no equilibrium just beyond the last
    point), or "none" when the path ran out of steps or torque)."""

    points: tuple
    torque_nm: float
    phi_rad: float
    criterion: str
    warnings: tuple = field(default=())

    def column(self, name: str) -> np.ndarray:
        return np.array([getattr(p, name) for p in self.points])


def _solve_at(model, phi: float, s_fs, s_cs, state, *, tol_mm: float, max_iterations: int, depth: int = 5):
    """The fixed point s = G(s) at rotation ``phi`` (G: the retreat the contact forces cause
    with the teeth at s), by Anderson mixing of the last ``depth`` iterates (plain
    substitution diverges where the climb's geometric softening is strong): → (F, s_fs, s_cs,
    state, lever, iterations)."""
    m = s_fs.size
    x = np.concatenate([s_fs, s_cs])
    xs, gs = [], []
    change = math.inf
    for it in range(1, max_iterations + 1):
        s_tot = x[:m] + x[m:]
        gap, lever = model.geometry(s_tot, phi)
        q = gap - model.sin_alpha * s_tot[model.slot]
        f, state, p_fs, p_cs = model.respond(q, state)
        offset = model.retreat_offset(state) if hasattr(model, "retreat_offset") else 0.0
        g = np.concatenate([p_fs @ f + offset, p_cs @ f])
        r = g - x
        change = float(np.max(np.abs(r), initial=0.0))
        if change <= tol_mm and model.settled(state):
            return f, g[:m], g[m:], state, lever, it
        xs.append(x)
        gs.append(g)
        if len(xs) > depth + 1:
            xs.pop(0)
            gs.pop(0)
        if len(xs) >= 2:
            res = np.array([gg - xx for gg, xx in zip(gs, xs)])
            d_r = np.diff(res, axis=0).T
            d_g = np.diff(np.array(gs), axis=0).T
            gamma = np.linalg.lstsq(d_r, r, rcond=None)[0]
            x = g - d_g @ gamma
        else:
            x = g
    raise ConvergenceError(f"climb: the teeth's retreat did not settle at φ = {phi:.6g} rad in {max_iterations} "
                           f"iterations (last change {change:.3g} mm)")


def _point(model, phi, f, s_fs, s_cs, state, lever, iterations) -> ClimbPoint:
    s = s_fs + s_cs
    if hasattr(model, "shared_retreat"):  # a coupled model iterates on each part's own share
        s = model.shared_retreat(s)
    per = np.bincount(model.slot, weights=f, minlength=model.depth_mm.size)
    total = float(per.sum())
    torque = model.zones * float(f @ lever) / 1000.0
    if total > 0.0:
        margin = float(per @ (model.depth_mm - s)) / total
        mean_s = float(per @ s) / total
        alpha = float(np.degrees(np.arcsin(np.clip(model.sin_alpha, -1, 1))) @ f) / total
        corner = float(f[model.corner].sum()) / total
    else:
        margin, mean_s, alpha, corner = float(np.min(model.depth_mm)), 0.0, 0.0, 0.0
    return ClimbPoint(float(phi), torque, s_fs + s_cs, s_fs.copy(), f, margin, alpha, mean_s, corner, iterations, state)


def _criterion_met(path, *, corner_rule: bool, limit_drop: float, limit_span: float = 0.0, final: bool = True):
    """(criterion, index of the first point past it) or None. A limit point: T fell more than
    ``limit_drop`` below its largest so far and stayed below that largest while the teeth's
    force-weighted retreat grew by ``limit_span`` × the margin they had at the largest (a fall
    that T climbs back out of within the span is the stations' contact switching, not a limit
    point; a span in the rotation would be met by one coarse step); the index is then the
    point after that largest. ``final``: the path has ended (its last point is the last there
    will be), so a fall not yet confirmed counts — unless T rose above it again. The margin and
    corner criteria met while a fall waits for its span end the path at that fall's limit point
    (T had already passed its largest)."""
    top, falling = 0, False
    for k, p in enumerate(path):
        crossed = "margin" if p.margin_mm <= 0.0 else "corner" if corner_rule and p.corner_share >= 0.5 else None
        if crossed:
            return ("limit point", top + 1) if falling else (crossed, k)
        if k >= 1 and p.torque_nm < (1.0 - limit_drop) * path[top].torque_nm:
            falling = True
            t = path[top]
            if p.mean_retreat_mm - t.mean_retreat_mm >= limit_span * t.margin_mm:
                return "limit point", top + 1
        if p.torque_nm >= path[top].torque_nm:
            top, falling = k, False
    if final and falling:
        return "limit point", top + 1
    return None


def _beyond(run, pts, s_fs, s_cs, state, nominal: float):
    """The first equilibrium 1, 2 or 4 × ``nominal`` past the last point (a band where the
    substitution cycles between contact or ball sets is passed), or None."""
    for j in (1.0, 2.0, 4.0) if pts else ():
        try:
            return run(pts[-1].phi_rad + j * nominal, s_fs, s_cs, state)
        except ConvergenceError:
            continue
    return None


def _follow(run, ended, m: int, state, phi_start: float, phi_step: float, *, max_steps: int, grow: float,
            max_torque_nm: float, max_halvings: int, max_retreat_step_mm: float, min_step_fraction: float,
            warnings: list) -> tuple[list, bool]:
    """The path's points from ``phi_start`` until a criterion ends it, with the step control
    of :func:`climb` → (points, whether it ended with no equilibrium just beyond its last
    point); what stopped it short is appended to ``warnings``."""
    s_fs, s_cs = np.zeros(m), np.zeros(m)
    pts: list[ClimbPoint] = []
    phi, step = float(phi_start), float(phi_step)
    min_step = float(phi_step) * float(min_step_fraction)
    halvings = 0
    for _ in range(4 * max_steps):  # max_steps points taken; the rest: steps tried again shorter
        if len(pts) >= max_steps:
            break
        try:
            p = run(phi, s_fs, s_cs, state)
            if pts and step > min_step and p.mean_retreat_mm - pts[-1].mean_retreat_mm > max_retreat_step_mm:
                step = max(0.5 * step, min_step)  # too far in one step: resolve the path (not a failure)
                phi = pts[-1].phi_rad + step
                continue
        except ConvergenceError as exc:
            if halvings < max_halvings:  # a shorter step from the last point (or toward the start's own)
                halvings += 1
                step *= 0.5
                phi = (pts[-1].phi_rad if pts else float(phi_start) - float(phi_step)) + step
                continue
            # no fixed point just past the last point: look beyond (1, 2, 4 × the step before
            # the halvings) — only where none is found does the path end
            nominal = max(step * 2.0 ** halvings, float(phi_step))
            p = _beyond(run, pts, s_fs, s_cs, state, nominal)
            if p is None:
                warnings.append(f"{exc} (after {halvings} step halvings): no equilibrium just beyond "
                                f"φ = {pts[-1].phi_rad if pts else phi:.6g} rad")
                return pts, bool(pts)
            warnings.append(f"no fixed point found between φ = {pts[-1].phi_rad:.6g} and {p.phi_rad:.6g} rad "
                            f"({exc}); the path continued beyond (a rotation passed over, not the estimate)")
            step, halvings = nominal, 0
        pts.append(p)
        if ended(pts):
            break
        if p.torque_nm > max_torque_nm:
            warnings.append(f"the path stopped at {p.torque_nm:.4g} N·m > max_torque_nm = {max_torque_nm:.4g} N·m "
                            "with no criterion met")
            break
        s_fs, s_cs, state = p.retreat_fs_mm, p.retreat_mm - p.retreat_fs_mm, p.state
        phi += step
        step *= grow
    return pts, False


def _refine_bracket(run, ended, pts: list, refine: int, warnings: list) -> tuple[list, bool]:
    """The criterion's bracket refined ``refine`` times in quarter steps from the point before
    it → (points, stuck: not one refined rotation found a fixed point)."""
    stuck = False
    for _ in range(refine):
        hit = ended(pts)
        if hit is None or hit[1] < 2:
            break
        k = hit[1]
        base = pts[k - 2]
        h = (pts[k].phi_rad - base.phi_rad) / 4.0
        fine = [base]
        s_fs, s_cs, state = base.retreat_fs_mm, base.retreat_mm - base.retreat_fs_mm, base.state
        failed = False
        for j in range(1, 4):
            try:
                q = run(base.phi_rad + j * h, s_fs, s_cs, state)
            except ConvergenceError as exc:  # skipped: the next quarter step may have one (a fixed
                # point missed by 2e-4 mm at csf14_100's peak)
                warnings.append(f"refining the peak, one rotation was passed over, the path's points kept ({exc})")
                failed = True
                continue
            fine.append(q)
            s_fs, s_cs, state = q.retreat_fs_mm, q.retreat_mm - q.retreat_fs_mm, q.state
        stuck = len(fine) == 1  # not one refined rotation found: the same would fail again
        if failed or fine[-1].phi_rad < pts[k - 1].phi_rad:  # the refinement left a gap or stopped short:
            fine.append(pts[k - 1])  # keep the point before the criterion (it may be the peak; it was dropped)
        fine.append(pts[k])
        pts = pts[:k - 2] + sorted(fine, key=lambda x: x.phi_rad) + pts[k + 1:]
        if stuck:
            break
    return pts, stuck


def _unended_path(pts: list, found, no_equilibrium_beyond: bool, warnings: list) -> ClimbPath:
    """The path when no criterion lies on the refined points: a limit point the refinement
    followed up, the end of the path (``no_equilibrium_beyond`` its last point), or no
    criterion (the largest torque each)."""
    if found is not None and found[0] == "limit point":
        # the refinement's finer steps followed T(φ) up where the coarse step had found it
        # falling (another equilibrium branch past the peak): the peak of the refined path
        best = max(pts, key=lambda x: x.torque_nm)
        warnings.append("the limit point's refinement found T(φ) still rising: its largest torque is taken")
        return ClimbPath(tuple(pts), best.torque_nm, best.phi_rad, "limit point", tuple(warnings))
    if no_equilibrium_beyond:
        best = max(pts, key=lambda x: x.torque_nm)
        return ClimbPath(tuple(pts), best.torque_nm, best.phi_rad, "end of path", tuple(warnings))
    top = max(pts, key=lambda x: x.torque_nm) if pts else None
    warnings.append("no criterion was met on the path followed: the estimate is its largest torque")
    return ClimbPath(tuple(pts), top.torque_nm if top else math.nan, top.phi_rad if top else math.nan,
                     "none", tuple(warnings))


def _limit_point(pts: list, k: int, stuck: bool, warnings: list) -> ClimbPath:
    """The limit point bracketed by the points k − 2, k − 1 and k: the parabola's peak through
    them, or the largest torque found where the bracket could not be refined."""
    a, b = pts[k - 1] if k else pts[k], pts[k]
    if stuck:  # the bracket could not be refined: the parabola through its coarse points can
        # overshoot the peak; the largest torque of an equilibrium found is taken (low by at
        # most the rise to the peak within the bracket)
        warnings.append(f"the limit point's bracket φ = {pts[k - 2].phi_rad if k >= 2 else a.phi_rad:.6g}…"
                        f"{b.phi_rad:.6g} rad could not be refined (no fixed point found in it): the largest "
                        f"torque found, {a.torque_nm:.4g} N·m at φ = {a.phi_rad:.6g} rad, is taken")
        return ClimbPath(tuple(pts), a.torque_nm, a.phi_rad, "limit point", tuple(warnings))
    if k >= 2:
        peak = _parabola_peak((pts[k - 2].phi_rad, a.phi_rad, b.phi_rad),
                              (pts[k - 2].torque_nm, a.torque_nm, b.torque_nm))
        if peak is not None:
            return ClimbPath(tuple(pts), peak[1], peak[0], "limit point", tuple(warnings))
    top = max(pts[:k + 1], key=lambda p: p.torque_nm)  # no peak pinned by the bracket: the largest found
    return ClimbPath(tuple(pts), top.torque_nm, top.phi_rad, "limit point", tuple(warnings))


def _crossing(pts: list, crit: str, k: int, warnings: list) -> ClimbPath:
    """The margin or corner criterion, interpolated linearly between the points k − 1 and k."""
    a, b = pts[k - 1] if k else pts[k], pts[k]
    if k == 0:
        warnings.append(f"the first rotation already meets the {crit} criterion")
        return ClimbPath(tuple(pts), b.torque_nm, b.phi_rad, crit, tuple(warnings))
    va, vb = (a.margin_mm, b.margin_mm) if crit == "margin" else (0.5 - a.corner_share, 0.5 - b.corner_share)
    w = va / (va - vb) if va != vb else 1.0
    return ClimbPath(tuple(pts), float(a.torque_nm + w * (b.torque_nm - a.torque_nm)),
                     float(a.phi_rad + w * (b.phi_rad - a.phi_rad)), crit, tuple(warnings))


def climb(model, phi_start: float, phi_step: float, *, max_steps: int = 100, grow: float = 1.25,
          refine: int = 3, tol_mm: float = 1e-4, max_iterations: int = 30,
          max_torque_nm: float = math.inf, max_halvings: int = 4,
          max_retreat_step_mm: float = 0.02, min_step_fraction: float = 1.0 / 64.0,
          limit_drop: float = 0.01, limit_span: float = 0.1) -> ClimbPath:
    """Follow T(φ) from ``phi_start`` in steps of ``phi_step`` (grown ×``grow`` while nothing
    ends the path) until a criterion of the module docstring is met, then refine the
    bracket ``refine`` times (quarter steps from the point before it; where not one of them
    finds a fixed point, the bracket's top point is kept and its torque, an equilibrium found,
    is the limit point's — a parabola through the coarse bracket overshoots a sharp peak, and
    dropping the top point, as before, took the falling branch's). ``model`` provides
    ``geometry(s) → (gap, lever)``, ``respond(q, state) → (F, state, S, P)``, ``ring(F)``,
    ``settled(state)``, ``initial_state()``, and arrays ``slot``, ``sin_alpha``, ``depth_mm``,
    ``corner`` and ``zones``. The path stops past ``max_torque_nm`` (N·m) or after ``max_steps``
    points (then no criterion was met: the verdict does not check it); the step control below
    halves steps near a peak, so a large gear's path takes more than 40 (size 58, ratio 100: a limit
    point at 20.4 kN·m after 53 points, where 40 ended at 19.3 kN·m with T still rising). A rotation whose
    fixed point is not found is tried again with the step halved (``max_halvings`` times);
    then rotations 1, 2 and 4 steps beyond (the step before the halvings, at least
    ``phi_step``) are tried from the last point — the substitution can cycle between contact
    or ball sets in a narrow band of φ with equilibria past it (a warning names the band) —
    and only if none converges does the path end at the last point (criterion "end of path":
    no equilibrium was found just beyond it — under rotation control the teeth would snap).

    A limit point is T falling more than ``limit_drop`` (1 %) below its largest so far: the
    stations' contact switching makes T(φ) wiggle by ~0.1–0.5 % where it is flat, and the first
    such wiggle ended the path before (seed000_csf40, verify scene: T flat at 6284–6300 N·m over
    φ = 4.65–4.77 mrad with 0.35 mm of the teeth still in their spaces, then rising to 7372 and
    falling 3 % and on — the step grid ×1.01 took the wiggle, 6290 N·m, ×1 the later 7359). The
    default set's sketch scene wiggles by 0.51 % at 4540 N·m (φ = 4.75–4.79 mrad) before its
    peak, 5484 N·m, after which T falls 2.5 % in two steps: with a 0.5 % threshold the
    estimate was 4546 or 5484 N·m as the step grid fell (a nanometre of the CS flank, or
    another CPU's round-off, chose). A fall is a limit point only once it has lasted: T stays
    below its largest while the teeth's force-weighted retreat grows by ``limit_span`` (10 %) of
    the margin they had at the largest (or the path ends: no equilibrium further on). A
    CSF-32-100 with a shorter, steeper tooth (addendum 0.5 m, 15°, tip arc 1.0 m) and the CS ring ×
    1.375 fell 1.3 % at 1174 N·m (α 19 → 22°, retreat +14 µm of a 372 µm margin, φ +3 %), then
    rose again to its peak, 1728 N·m (α 27°), and fell from there on; the first fall had ended the
    path (the estimate 32 % low, and lower than with more compliance added). Under torque control
    the gear would jump past such a local peak to the equilibrium of the same torque further on,
    its teeth still in their spaces: the ratcheting torque is the peak they do not come back from.

    Step control: a step whose force-weighted mean retreat grows by more than
    ``max_retreat_step_mm`` is not taken but tried again halved (down to ``min_step_fraction``
    × ``phi_step``, where it is taken whatever it grows: a jump of the discrete model). Without
    it the ×``grow`` steps jumped over the peak of T(φ) onto the falling branch (verify scene
    of seed000_csf40, ball window: 4.68 → 5.91 mrad in one step, retreat 139 → 310 µm, the
    peak ≈ 4.76 kN·m at 5.6 mrad missed), so where the path then ended — and the estimate —
    depended on where the step grid fell (S3: 4594 against 5452 N·m for a nanometre's change
    of the CS flank)."""
    # the corner rule stands in for a corner normal the model does not follow (DesignClimb's
    # corner_normal=False); with it, a corner riding over the CS tip round is the geometry's
    corner_rule = bool(getattr(model, "corner_criterion", True))
    warnings: list[str] = []

    def run(phi, s_fs, s_cs, state):
        f, s_fs, s_cs, state, lever, it = _solve_at(model, phi, s_fs, s_cs, state, tol_mm=tol_mm,
                                                    max_iterations=max_iterations)
        return _point(model, phi, f, s_fs, s_cs, state, lever, it)

    def ended(path, final=True):
        return _criterion_met(path, corner_rule=corner_rule, limit_drop=limit_drop, limit_span=limit_span,
                              final=final)

    pts, no_equilibrium_beyond = _follow(run, partial(ended, final=False), model.depth_mm.size, model.initial_state(), phi_start, phi_step, max_steps=max_steps,
                  grow=grow, max_torque_nm=max_torque_nm, max_halvings=max_halvings,
                  max_retreat_step_mm=max_retreat_step_mm, min_step_fraction=min_step_fraction, warnings=warnings)
    found = ended(pts)
    pts, stuck = _refine_bracket(run, ended, pts, refine, warnings)
    hit = ended(pts)
    if hit is None:
        return _unended_path(pts, found, no_equilibrium_beyond, warnings)
    crit, k = hit
    if crit == "limit point":
        return _limit_point(pts, k, stuck, warnings)
    return _crossing(pts, crit, k, warnings)


def _parabola_peak(x, y) -> tuple[float, float] | None:
    """The vertex (x_v, y_v) of the parabola through three points, if it is a maximum inside
    [x_0, x_2] at or above the largest y by no more than the three y's spread; else None.
    Newton's divided differences, exact for three points and well conditioned however close the
    points (a bracket refined to ~1e-9 rad made numpy's polyfit, which fits the raw monomials,
    warn of a poorly conditioned fit). The rise's bound: two abscissae a few ulps apart with
    torques 0.02 N·m apart (a climb's refinement, a size-25 ratio-80 set with a thinner rim) made
    a curvature of ~1e20 and a "peak" of 3.4e10 N·m between points of ~2440 N·m; a vertex that far
    above its points is not pinned by them, and the caller takes the largest point instead (the
    safe side: below the peak by at most the rise within the bracket)."""
    x0, x1, x2 = x
    y0, y1, y2 = y
    if not (x0 < x1 < x2):
        return None
    d1 = (y1 - y0) / (x1 - x0)
    c2 = ((y2 - y1) / (x2 - x1) - d1) / (x2 - x0)
    if not c2 < 0.0:
        return None
    xv = 0.5 * (x0 + x1) - d1 / (2.0 * c2)
    if not x0 <= xv <= x2:
        return None
    yv = y0 + d1 * (xv - x0) + c2 * (xv - x0) * (xv - x1)
    # a peak inside the bracket is above its points; one below them is round-off (abscissae ulps
    # apart), one far above is not pinned by them
    if not max(y) <= yv <= max(y) + (max(y) - min(y)):
        return None
    return float(xv), float(yv)


# --------------------------------------------------------------------------- a design's teeth


def tooth_probes(inputs, points, shift_rad: float = 0.0):
    """Per candidate tooth: the FS tip-land centre (CS frame), e_r there, the CS space's root
    centre, and the loaded flank's tip corner (CS frame); ``shift_rad`` as in
    :func:`~profilegen.contact.points.contact_points` (another wave-generator position)."""
    from ..geometry.kinematics import turn

    g = inputs.gearset.gear
    teeth = points.teeth
    phis = 2.0 * math.pi * teeth / g.flexspline_teeth + float(shift_rad)
    pose = inputs.motion.pose(phis)
    tooth = inputs.tooth
    tip_y = float(tooth.tip_point[1])
    corner = tooth.evaluate(np.array([tooth.length_mm]), side=points.side)[0][0]
    fs = pose.to_cs(np.broadcast_to(np.array([0.0, tip_y]), (teeth.size, 2)).copy())
    cn = pose.to_cs(np.broadcast_to(corner, (teeth.size, 2)).copy())
    _, foot = inputs.cs_space.nearest(np.array([[0.0, 2.0 * float(g.cs_pitch_radius_mm)]]))
    angles = 2.0 * math.pi * teeth / g.circular_spline_teeth
    fs = np.vstack([turn(fs[k:k + 1], a) for k, a in enumerate(angles)])
    cn = np.vstack([turn(cn[k:k + 1], a) for k, a in enumerate(angles)])
    cs = np.vstack([turn(foot, a) for a in angles])
    e_r = fs / np.linalg.norm(fs, axis=1)[:, None]
    return teeth, phis, fs, e_r, cs, cn



def _every_nth_from_tip(tooth, t_mm, keep, n: int) -> np.ndarray:
    """A mask keeping, of each tooth's kept stations ordered along the flank, every ``n``-th
    counted from its tip end (so the tip corner stays)."""
    out = np.zeros(keep.size, bool)
    if n <= 1:
        return keep.copy()
    for t in np.unique(tooth[keep]):
        idx = np.flatnonzero(keep & (tooth == t))
        idx = idx[np.argsort(t_mm[idx])][::-1]  # from the tip
        out[idx[::n]] = True
    return out


class _State:
    __slots__ = ("active", "springs", "done", "offset")

    def __init__(self, active, springs, done=False, offset=0.0):
        self.active, self.springs, self.done, self.offset = active, springs, done, offset


class DesignClimb:
    """The climb model of a design's engagement zone (docs/theory/torsion.md, "The climb"):
    material stations ``stations`` per tooth on the loaded flank of every tooth whose no-load gap is within
    ``max_gap_mm``, their influence coefficients with one radial probe per tooth (FS tip-land
    centre against the CS space's root, as :mod:`profilegen.contact.ratchet`), the Hertz ball
    springs of ``bearing`` (None: rigid balls) and the CS ring ``ring_matrix`` (m × 2m, the
    ring's radial compliance at the teeth for loads at the teeth and their images; None: no
    ring; ``ring_scale`` multiplies it: a study of how much more radial compliance outside the
    contact's S the climb would need); ``shift_rad``: the wave generator elsewhere in a tooth
    passage (every tooth at 2πi/z1 + shift from the major axis, as
    :func:`~profilegen.contact.points.contact_points`). Built by :func:`profilegen.contact.ratchet.ratcheting_torque`."""

    def __init__(self, inputs, *, side: int, stations: int, max_gap_mm: float, race_thickness_mm, bearing,
                 ring_factory=None, ring_scale: float = 1.0, spring_tol: float = 1e-3, shift_rad: float = 0.0,
                 corner_normal: bool = True, width_fraction: float = 1.0, ball_supports: str = "window",
                 friction_coefficient: float = 0.0, friction_sliding: str | None = None,
                 friction_tangents: str = "probe"):
        from ..geometry.kinematics import turn
        from .compliance import ContactCompliance
        from .points import contact_points

        every = contact_points(inputs, side=side, stations=stations, max_gap_mm=10.0, shift_rad=shift_rad)
        best = {int(t): float(every.gap_mm[every.tooth == t].min()) for t in every.teeth}
        keep = np.isin(every.tooth, [t for t, g in best.items() if g <= max_gap_mm])
        # a refined minimum can land next to a fixed station: two stations closer than a fifth of
        # the spacing make S numerically singular — keep the first
        spacing = (float(inputs.tooth.length_mm) - float(np.min(every.t_mm))) / max(stations - 1, 1)
        close = np.zeros(keep.size, bool)
        close[1:] = (every.tooth[1:] == every.tooth[:-1]) & (np.diff(every.t_mm) < 0.2 * spacing)
        keep &= ~close
        if not keep.any():
            raise ConvergenceError(f"climb: no tooth comes within max_gap_mm = {max_gap_mm} mm of the CS")
        #: what the model had to change to be built (e.g. stations thinned), for the estimate's warnings
        self.notes: list[str] = []
        g = inputs.gearset.gear
        self._space = inputs.cs_space
        # the space's outline in polar form (angle from +y, radius): CS material lies beyond it
        outline = _dense(np.asarray(inputs.cs_space.sample(1e-3), dtype=float), 5e-3)
        th = np.arctan2(outline[:, 0], outline[:, 1])
        order = np.argsort(th)
        self._rim_theta, self._rim_r = th[order], np.hypot(outline[order, 0], outline[order, 1])
        self._tip_r = float(inputs.cs_tip_radius_mm)
        self._cs_pitch = 2.0 * math.pi / g.circular_spline_teeth
        if np.any(np.diff(np.hypot(outline[:, 0], outline[:, 1])[np.argsort(th)]) > 0.5) or not (
                np.all(np.diff(th) > 0) or np.all(np.diff(th) < 0)):
            raise ConvergenceError("climb: the CS space's outline is not single-valued in the polar angle; "
                                   "the overlap of a station cannot be told")
        thin = 1
        while True:  # stations closer than the FE mesh resolves make S singular: every 2nd, then 4th
            sub = keep & _every_nth_from_tip(every.tooth, every.t_mm, keep, thin)
            pts = _Subset(every, sub)
            teeth, phis, fs_probe, e_r, cs_probe, corner = tooth_probes(inputs, pts, shift_rad)
            self.teeth, self.phis = teeth, phis
            self.slot = np.searchsorted(teeth, pts.tooth)
            self.n, self.zones, self.rotation = pts.count, int(pts.zones), int(pts.rotation)
            back = -2.0 * math.pi * pts.tooth / g.circular_spline_teeth
            self._p0 = np.vstack([turn(pts.fs_point_mm[k:k + 1], a) for k, a in enumerate(back)])
            self._n0 = np.vstack([turn(pts.normal[k:k + 1], a) for k, a in enumerate(back)])
            tb = -2.0 * math.pi * teeth / g.circular_spline_teeth
            self._e0 = np.vstack([turn(e_r[k:k + 1], a) for k, a in enumerate(tb)])
            e_pts = pts.fs_point_mm / np.linalg.norm(pts.fs_point_mm, axis=1)[:, None]
            self.sin_alpha = np.einsum("ij,ij->i", pts.normal, e_pts)
            self.depth_mm = np.linalg.norm(corner, axis=1) - inputs.cs_tip_radius_mm
            self.corner = pts.t_mm >= float(inputs.tooth.length_mm) - 1e-9
            self.t_mm = pts.t_mm
            self.points = pts
            #: the FS tip-corner stations whose contact normal follows the CS surface (corner_normal):
            #: a second influence column each, along the tip land's outward normal (tooth frame +y)
            self._ci = np.flatnonzero(self.corner) if corner_normal else np.zeros(0, int)
            self.corner_criterion = not corner_normal
            pose = inputs.motion.pose(pts.phi_rad[self._ci]) if self._ci.size else None
            tip_n = np.zeros((0, 2)) if pose is None else np.column_stack([np.sin(pose.angle), np.cos(pose.angle)])
            self._tn0 = tip_n  # CS space 0's frame, as _n0
            self._sa_flank = self.sin_alpha.copy()
            tip_actual = np.vstack([turn(tip_n[k:k + 1], -b) for k, b in enumerate(back[self._ci])]) if self._ci.size \
                else np.zeros((0, 2))
            self._sa_tip = np.einsum("ij,ij->i", tip_actual, e_pts[self._ci])
            nc = self._ci.size
            self._a, self._b = np.ones(nc), np.zeros(nc)
            self._setup_friction(inputs, pts, e_pts, tip_actual, friction_coefficient, friction_sliding,
                                 friction_tangents, e_r[self.slot])
            # "exact": a tangent column at every flank station (a corner's tangent is a combination
            # of its n_f and n_t columns: a third direction at one point is singular)
            fi = self._fi if self._friction and self._tangents == "exact" else np.zeros(0, int)
            nt = fi.size
            try:
                self._combined = ContactCompliance.build(
                    inputs, np.vstack([pts.fs_point_mm, pts.fs_point_mm[self._ci], pts.fs_point_mm[fi], fs_probe]),
                    np.vstack([pts.normal, tip_actual, self._tf[fi] if nt else np.zeros((0, 2)), e_r]),
                    np.concatenate([pts.tooth, pts.tooth[self._ci], pts.tooth[fi], teeth]),
                    np.vstack([pts.cs_point_mm, pts.cs_point_mm[self._ci], pts.cs_point_mm[fi], cs_probe]),
                    race_thickness_mm=race_thickness_mm, shift_rad=shift_rad, ball_supports=ball_supports,
                    cs_ring=False)  # the ring is ring_factory's: radial, per tooth, with the current sin α
            except ConvergenceError as exc:
                if thin >= 4 or "not positive definite" not in str(exc):
                    raise
                spacing_now = thin * spacing
                thin *= 2
                self.notes.append(f"the stations {spacing_now:.3g} mm apart on the flank make the contact's "
                                  f"compliance singular (the FE mesh does not resolve them): every "
                                  f"{'second' if thin == 2 else 'fourth'} station of each tooth kept")
                continue
            break
        #: each candidate ball's no-load gap to the bore (mm; 0 within the wrap; the window: all 0)
        gb = self._combined.ball_gap_mm
        self._g0 = np.zeros(self._combined.ball_angle_rad.size) if gb is None else np.asarray(gb, dtype=float)
        self._nn = self.n + nc + nt  # stations + the corners' tip-land columns (+ the stations' tangents)
        self.bearing = bearing
        m = teeth.size
        ring = np.zeros((m, 2 * m)) if ring_factory is None else ring_scale * ring_factory(phis)
        #: the CS ring's radial compliance at the teeth, the image zone's load folded in (m × m);
        #: its part of the retreat and of S is formed per call with the current sin α (_effective)
        self._ring = ring[:, :m] + ring[:, m:]
        self._spring_tol = spring_tol
        c = self._combined
        #: a slice of the face (width_fraction of it): every compliance per unit width over the
        #: slice's width, the CS ring's likewise, the Hertz springs at the whole face's ball load
        self._fraction = float(width_fraction)
        self._width = c.face_width_mm * self._fraction
        self._ring = self._ring / self._fraction
        self._base = 0.5 * (c._flex_cc + c._flex_cc.T) / self._width + c.cs_matrix_mm_per_n / self._fraction

    # -- the model interface of climb()
    def geometry(self, s, phi: float = 0.0):
        """Signed gaps (mm, < 0: overlap) of the stations with their teeth ``s`` out of their
        spaces and the FS turned by ``phi`` against the CS, and the lever arms (mm)."""
        from ..geometry.kinematics import turn

        p = turn(self._p0 - s[self.slot, None] * self._e0[self.slot], self.rotation * phi)
        n = turn(self._n0, self.rotation * phi)
        gap, pw, wrap, land = self.signed_gap(p)
        r = np.hypot(pw[:, 0], pw[:, 1])
        ci = self._ci
        if ci.size:
            # the FS tip corner against the CS: the contact normal is the CS surface's (the
            # foot's direction, out of the FS), kept within the corner's cone of normals
            # between the flank's n_f and the tip land's n_t: n = a n_f + b n_t, a, b ≥ 0
            nf, nt = n[ci], turn(self._tn0, self.rotation * phi)
            pc, rc, on_land = pw[ci], r[ci], land[ci]
            v = self._surface_normal(pc)
            _, foot = self._space.nearest(pc)
            if on_land.any():  # the tip land's normal: radial, its nearest point on the tip circle
                v[on_land] = pc[on_land] / rc[on_land, None]
                foot[on_land] = pc[on_land] * (self._tip_r / rc[on_land])[:, None]
            # into the CS (the contact normal out of the FS): a point 5 µm from the nearest CS
            # point along v lies in the CS material — the surface's own side, not the cone's
            # (turning v to the cone's side flipped it where v stands across the cone — a corner
            # over a neighbouring space's far flank near the minor axis — and the normal, the
            # force and the retreat's fixed point jumped back and forth: csf20_120, verify scene)
            probe = foot + 5e-3 * v
            into = np.hypot(probe[:, 0], probe[:, 1]) > np.interp(
                np.arctan2(probe[:, 0], probe[:, 1]), self._rim_theta, self._rim_r, left=self._tip_r,
                right=self._tip_r)
            v = np.where(into[:, None], v, -v)
            v = turn(v, wrap[ci] * self._cs_pitch) if np.any(wrap[ci]) else v
            d = np.linalg.norm(v, axis=1)
            a, b = np.ones(ci.size), np.zeros(ci.size)
            ok = d > 1e-12
            if ok.any():
                u = v[ok] / d[ok, None]
                det = nf[ok, 0] * nt[ok, 1] - nf[ok, 1] * nt[ok, 0]
                aa = (u[:, 0] * nt[ok, 1] - u[:, 1] * nt[ok, 0]) / det
                bb = (nf[ok, 0] * u[:, 1] - nf[ok, 1] * u[:, 0]) / det
                # outside the cone: the nearer of its edges (the larger u·n) — beyond the tip
                # land's normal the tip land, within the flank's the flank, and behind the
                # cone (both < 0: a corner over a neighbouring space) the nearer too, so that
                # the normal does not jump where u leaves the cone on the flank's side
                out = (aa < 0.0) | (bb < 0.0)
                tip = np.einsum("ij,ij->i", u, nt[ok]) > np.einsum("ij,ij->i", u, nf[ok])
                a[ok] = np.where(out, np.where(tip, 0.0, 1.0), aa)
                b[ok] = np.where(out, np.where(tip, 1.0, 0.0), bb)
            self._a, self._b = a, b
            n = n.copy()
            n[ci] = a[:, None] * nf + b[:, None] * nt
            self.sin_alpha = self._sa_flank.copy()
            self.sin_alpha[ci] = a * self._sa_flank[ci] + b * self._sa_tip
        if self._friction:
            # the force on the CS per unit normal force: n + μσ t (t = the tangent out of the
            # space, σ = +1 sliding out, −1 in); its radial part for the CS ring and its lever
            if self._elastic and self.teeth.size > 1:
                ds = np.gradient(np.asarray(s, dtype=float), self.phis)
                # Coulomb's sign regularised over ±SLIP_SPEED (a station whose sliding stops
                # in the iteration must not flip its force back and forth)
                self._sigma = np.clip((self.sliding_speed + ds[self.slot] * self._er_t) / SLIP_SPEED, -1.0, 1.0)
            ms = self._mu * self._sigma
            te = self._js * self._tp_flank
            if ci.size:
                te[ci] = self._js[ci] * (self._a * self._tp_flank[ci] + self._b * self._tp_tip)
            self._rad = self.sin_alpha + ms * te
            n = n + ms[:, None] * (self._js[:, None] * np.column_stack([-n[:, 1], n[:, 0]]))
        lever = self.rotation * (p[:, 1] * n[:, 0] - p[:, 0] * n[:, 1])
        return gap, lever

    def signed_gap(self, p):
        """The signed distance (mm, < 0: in the CS material) of points ``p`` (CS space 0's frame)
        to the CS surface — every space and the tip lands between them: each point is measured in
        the space it stands in (its own, or a neighbour's where it has moved more than half a CS
        pitch: the CS is periodic), and beyond the space's outline, which ends on the CS tip
        circle, the surface is the tip land (the tip circle). → (gap, the point in its space's
        frame, the number of pitches it was turned back by, whether the tip land is nearest)."""
        from ..geometry.kinematics import turn

        p = np.asarray(p, dtype=float)
        theta = np.arctan2(p[:, 0], p[:, 1])
        wrap = np.round(theta / self._cs_pitch)
        pw = turn(p, -wrap * self._cs_pitch) if np.any(wrap) else p
        theta = theta - wrap * self._cs_pitch
        dist, _ = self._space.nearest(pw)
        r = np.hypot(pw[:, 0], pw[:, 1])
        inside = r > np.interp(theta, self._rim_theta, self._rim_r, left=self._tip_r, right=self._tip_r)
        land = ((theta < self._rim_theta[0]) | (theta > self._rim_theta[-1])) & (np.abs(r - self._tip_r) < dist)
        dist = np.where(land, np.abs(r - self._tip_r), dist)
        return np.where(inside, -dist, dist), pw, wrap, land

    def _setup_friction(self, inputs, pts, e_pts, tip_actual, mu, sliding, tangents, e_probe):
        """Coulomb friction on the stations (docs/theory/torsion.md, "Friction in the climb"): the
        tangents out of the spaces, their radial parts, the corners' tangents in the built columns, and the
        sliding sense σ of every station (+1: the FS slides out of the space along the flank)."""
        from ..geometry.kinematics import turn

        self._friction = sliding is not None
        self._mu = float(mu)
        self._elastic = False
        if not self._friction:
            if self._mu != 0.0:
                raise ClimbError(f"friction_coefficient = {mu!r}: needs friction_sliding (one of {SLIDING})")
            return
        if sliding not in SLIDING:
            raise ClimbError(f"friction_sliding must be one of {', '.join(map(repr, SLIDING))}, got {sliding!r}")
        if not (math.isfinite(self._mu) and 0.0 <= self._mu < 1.0):
            raise ClimbError(f"friction_coefficient = {mu!r}: must be in [0, 1)")
        if tangents not in ("probe", "exact"):
            raise ClimbError(f"friction_tangents must be 'probe' or 'exact', got {tangents!r}")
        self._tangents = tangents
        self.friction_sliding = sliding
        self._js, self._tf = sliding_tangent(pts.normal, e_pts)  # the built tangent columns (actual frame)
        perp = np.column_stack([-pts.normal[:, 1], pts.normal[:, 0]])
        self._tp_flank = np.einsum("ij,ij->i", perp, e_pts)
        ci = self._ci
        perp_t = np.column_stack([-tip_actual[:, 1], tip_actual[:, 0]])
        self._tp_tip = np.einsum("ij,ij->i", perp_t, e_pts[ci])
        self._fi = np.setdiff1d(np.arange(pts.count), ci)
        # a corner's tangent t = J(a n_f + b n_t), J = the quarter turn out of the space, in its
        # built columns n_f, n_t: J n_f = e1 n_f + e2 n_t, J n_t = g1 n_f + g2 n_t
        nf, nt = pts.normal[ci], tip_actual
        det = nf[:, 0] * nt[:, 1] - nf[:, 1] * nt[:, 0]

        def split(u):
            return (u[:, 0] * nt[:, 1] - u[:, 1] * nt[:, 0]) / det, (nf[:, 0] * u[:, 1] - nf[:, 1] * u[:, 0]) / det

        self._e1, self._e2 = split(self._js[ci, None] * perp[ci])
        self._g1, self._g2 = split(self._js[ci, None] * perp_t)
        # "probe": a flank station's tangent t = x n + y e_r, its own normal's column and the
        # radial column of its tooth's probe (the FS tip-land centre against the CS root):
        # the friction force's radial part moved from the flank to the tooth's probe point
        fi = self._fi
        nn_, ee = pts.normal[fi], e_probe[fi]
        dd = nn_[:, 0] * ee[:, 1] - nn_[:, 1] * ee[:, 0]
        tt = self._tf[fi]
        self._tx = (tt[:, 0] * ee[:, 1] - tt[:, 1] * ee[:, 0]) / dd
        self._ty = (nn_[:, 0] * tt[:, 1] - nn_[:, 1] * tt[:, 0]) / dd
        self._rad = self.sin_alpha.copy()
        if sliding in ("static", "unloading"):  # every tooth sliding out of its space / back in
            self._sigma = np.full(pts.count, 1.0 if sliding == "static" else -1.0)
            self.sliding_speed = self.sliding_velocity = None
            return
        # running: the station's motion relative to its CS space as the tooth goes through the
        # mesh, d/dφ of its place (space 0's frame); the gear running forward (the wave
        # generator driving the load) turns the FS against the CS the way the CS's forces
        # push it — against the rotation that loads the flank — so φ falls for rotation +1
        h = 1e-6
        pose_p, pose_m = inputs.motion.pose(pts.phi_rad + h), inputs.motion.pose(pts.phi_rad - h)
        v = (pose_p.to_cs(pts.local_mm) - pose_m.to_cs(pts.local_mm)) / (2.0 * h)
        way = 1.0 if sliding.startswith("forward") else -1.0
        v *= -self.rotation * way
        #: the stations' velocity relative to their CS spaces (space 0's frame, mm per rad of |φ|)
        self.sliding_velocity = v
        back = -2.0 * math.pi * pts.tooth / inputs.gearset.gear.circular_spline_teeth
        t0 = np.vstack([turn(self._tf[k:k + 1], a) for k, a in enumerate(back)])
        #: the stations' sliding speed out of their spaces along the flank (mm per rad of φ,
        #: < 0: into the space)
        self.sliding_speed = np.einsum("ij,ij->i", v, t0)
        self._sigma = np.sign(self.sliding_speed)
        # "-elastic": the teeth's retreat s(φ) is stationary in the wave generator's frame, so a
        # tooth running through the zone also moves by −ds/dφ e_r per unit of φ: along t
        # (forward, φ falling for rotation +1) rotation · ds/dφ · (e_r·t) — σ from the sum,
        # with s the fixed point's current iterate (geometry)
        self._elastic = sliding.endswith("-elastic")
        self._er_t = way * self.rotation * np.einsum("ij,ij->i", self._e0[self.slot], t0)

    def _surface_normal(self, p):
        """The CS space's unit normal (either sense) at the nearest point of each of ``p``: of
        the nearest element, exact for its arcs and lines — not the direction to the foot,
        which turns over as a point crosses the surface."""
        from ..geometry.contour import Arc, Line

        found = [e.nearest(p) for e in self._space.elements]
        best = np.argmin(np.stack([d for d, _ in found]), axis=0)
        out = np.zeros_like(p)
        for k, e in enumerate(self._space.elements):
            on = best == k
            if not on.any():
                continue
            foot = found[k][1][on]
            if isinstance(e, Arc):
                v = foot - np.asarray(e.centre, dtype=float)
            elif isinstance(e, Line):
                t = np.asarray(e.end, dtype=float) - np.asarray(e.start, dtype=float)
                v = np.broadcast_to(np.array([-t[1], t[0]]), foot.shape).copy()
            else:  # any other element: the direction to its foot
                v = foot - p[on]
            out[on] = v / np.maximum(np.linalg.norm(v, axis=1), 1e-300)[:, None]
        return out

    def _expand(self, f):
        """Station forces → forces on the built columns (the corners split into a n_f + b n_t)."""
        if self._friction:  # the built columns and the probes
            out = np.zeros(self._combined._flex_cc.shape[0])
            cf, cb, ct = self._friction_columns()
            n, nc = self.n, self._ci.size
            out[:n] = cf * f
            out[n:n + nc] = cb * f[self._ci]
            np.add.at(out, self._tangent_columns(), ct * f[self._fi])
            return out
        out = np.zeros(self._nn)
        out[:self.n] = f
        if self._ci.size:
            out[self._ci] = self._a * f[self._ci]
            out[self.n:] = self._b * f[self._ci]
        return out

    def _friction_columns(self):
        """The force n + μσ t of every station in the built columns: (its n_f column's factor
        (every station), the corners' n_t columns' factors, the flank stations' t columns')."""
        ms = self._mu * self._sigma
        cf = np.ones(self.n)
        ci, a, b, fi = self._ci, self._a, self._b, self._fi
        cb = b + ms[ci] * (a * self._e2 + b * self._g2)
        cf[ci] = a + ms[ci] * (a * self._e1 + b * self._g1)
        if self._tangents == "exact":
            return cf, cb, ms[fi]
        cf[fi] = 1.0 + ms[fi] * self._tx
        return cf, cb, ms[fi] * self._ty

    def _tangent_columns(self):
        """The columns (of the built ones and the probes) the flank stations' friction goes to."""
        n, nc, fi = self.n, self._ci.size, self._fi
        if self._tangents == "exact":
            return n + nc + np.arange(fi.size)
        return self._nn + self.slot[fi]

    def _effective(self, full, probe):
        """(S, P_fs, P_cs) of the stations from the built columns: the corners' columns and rows
        combined with the current (a, b) (a congruence: S stays positive definite), and the CS
        ring's part with the current sin α."""
        n, ci = self.n, self._ci
        if self._friction:
            return self._effective_friction(full, probe)
        if ci.size:
            cols = full[:, :n].copy()
            cols[:, ci] = self._a * full[:, ci] + self._b * full[:, n:]
            s_mat = cols[:n].copy()
            s_mat[ci] = self._a[:, None] * cols[ci] + self._b[:, None] * cols[n:]
            p_fs = probe[:, :n].copy()
            p_fs[:, ci] = self._a * probe[:, ci] + self._b * probe[:, n:]
        else:
            s_mat, p_fs = full.copy(), probe
        p_cs = self._ring[:, self.slot] * self.sin_alpha[None, :]
        s_ring = self.sin_alpha[:, None] * p_cs[self.slot]
        s_mat += 0.5 * (s_ring + s_ring.T)
        return s_mat, p_fs, p_cs

    def _effective_friction(self, full, probe):
        """(S, P_fs, P_cs) with friction: the gaps measured along the normals n (rows as
        without friction), the forces along n + μσ t (columns): S is not symmetric."""
        n, ci, nc, fi = self.n, self._ci, self._ci.size, self._fi
        cf, cb, ct = self._friction_columns()
        tang = self._tangent_columns()
        cols = full[:, :n] * cf
        p_fs = probe[:, :n] * cf
        cols[:, fi] += full[:, tang] * ct
        p_fs[:, fi] += probe[:, tang] * ct
        if nc:
            cols[:, ci] += full[:, n:n + nc] * cb
            p_fs[:, ci] += probe[:, n:n + nc] * cb
        s_mat = cols[:n].copy()
        if nc:
            s_mat[ci] = self._a[:, None] * cols[ci] + self._b[:, None] * cols[n:n + nc]
        ring = self._ring[:, self.slot]
        p_cs = ring * self._rad[None, :]
        s_ring = self.sin_alpha[:, None] * (ring * self.sin_alpha[None, :])[self.slot]
        s_mat += 0.5 * (s_ring + s_ring.T) + self.sin_alpha[:, None] * (ring * (self._rad - self.sin_alpha))[self.slot]
        return s_mat, p_fs, p_cs

    def station_matrix(self, state) -> np.ndarray:
        """S of the stations (mm/N) with ``state``'s balls and springs at the last geometry."""
        full, probe, _ = self._matrices(state.active, state.springs)
        return self._effective(full, probe)[0]

    def initial_state(self):
        return _State(self._combined.ball_active.copy(), None)

    def settled(self, state) -> bool:
        return state.done

    def _matrices(self, active, springs):
        """(S, P, support factor) for a ball set and springs: the combined compliance's
        Schur step (:meth:`ContactCompliance.with_balls`) without its positive-definiteness
        check, which the build made."""
        c = self._combined
        b = c.face_width_mm
        act = np.flatnonzero(active)
        full = self._base.copy()
        fa = None
        if act.size:
            block = c._flex_bb[np.ix_(act, act)]
            if springs is not None:
                block = block + np.diag(springs[act] * b)
            fa = cho_factor(block, lower=True)
            w = solve_triangular(fa[0], c._flex_cb[:, act].T, lower=True)
            full -= (w.T @ w) / self._width
        n = self._nn
        if self._friction:  # the probes' columns too (the friction's radial parts, "probe")
            return full[:n], full[n:], fa
        return full[:n, :n], full[n:, :n], fa

    def _reactions(self, f, active, fa):
        """Ball reactions (N, > 0 compressed) and the bore's radial gap at every candidate ball
        (after load, its no-load gap included: an active ball closes its gap)."""
        c = self._combined
        b = self._width
        fp = np.zeros(c._flex_cc.shape[0])
        e = self._expand(f)
        fp[:e.size] = e
        react = np.zeros(c.ball_angle_rad.size)
        act = np.flatnonzero(active)
        if act.size:
            react[act] = -cho_solve(fa, c._flex_cb[:, act].T @ fp + b * self._g0[act])
        gaps = c._flex_cb.T @ (fp / b) + c._flex_bb @ (react / b) + self._g0
        return react, gaps

    def _offset(self, active, fa):
        """The separations (built columns then probes, mm) that closing the active balls' no-load
        gaps causes at no tooth load: −C_cb,A (C_bb,A + springs)⁻¹ g_A (0 for the window)."""
        act = np.flatnonzero(active)
        out = np.zeros(self._combined._flex_cb.shape[0])
        if act.size and np.any(self._g0[act] != 0.0):
            out = -self._combined._flex_cb[:, act] @ cho_solve(fa, self._g0[act])
        n, ci = self.n, self._ci
        st = out[:n].copy()
        if ci.size:
            st[ci] = self._a * out[ci] + self._b * out[n:n + ci.size]
        return st, out[self._nn:]

    def retreat_offset(self, state):
        """The FS retreat (mm, per tooth) that the active balls' no-load gaps alone cause."""
        return state.offset

    def respond(self, q, state):
        from .compliance import settle_step

        active, springs = state.active.copy(), state.springs
        seen = set()
        for _ in range(4 * active.size + 4):
            full, probe, fa = self._matrices(active, springs)
            s_mat, p_mat, p_cs = self._effective(full, probe)
            off_st, off_probe = self._offset(active, fa)
            f = (solve_p_matrix if self._friction else solve_spd)(s_mat, q + off_st)
            react, gaps = self._reactions(f, active, fa)
            active, step = settle_step(active, react, gaps)
            if step is None:
                break
            key = active.tobytes()
            if key in seen and step == "return":
                raise ConvergenceError("climb: the ball set cycles")
            seen.add(key)
        else:
            raise ConvergenceError("climb: the ball set did not settle")
        done = bool(np.array_equal(active, state.active))
        if self.bearing is not None:
            floor = max(1.0, 1e-3 * float(react.max(initial=0.0)))
            new = self.bearing.secant_compliance_mm_per_n(react / self._fraction, floor_n=floor / self._fraction)
            done = done and springs is not None and bool(np.all(np.abs(new / springs - 1.0) <= self._spring_tol))
            springs = new
        return f, _State(active, springs, done, off_probe), p_mat, p_cs

    def first_rotation(self, torque_nm: float) -> tuple[float, float]:
        """(θ_min, φ at ``torque_nm`` in the linear contact with rigid balls, no shift;
        without friction: only the path's first rotation and step come from it)."""
        if self._friction:
            mu, self._mu = self._mu, 0.0
            try:
                return self._first_rotation(torque_nm)
            finally:
                self._mu = mu
        return self._first_rotation(torque_nm)

    def _first_rotation(self, torque_nm: float) -> tuple[float, float]:
        from .solvers import ContactError, solve_lemke

        gap, lever = self.geometry(np.zeros(self.teeth.size))
        full, probe, fa = self._matrices(self._combined.ball_active, None)
        s_mat = self._effective(full, probe)[0]
        gap = gap + self._offset(self._combined.ball_active, fa)[0]
        # stations whose normal carries torque; a section overlapping at no load (coning) has
        # θ < 0: the separations shifted by the smallest (exact: contact.solvers, "Scaling")
        on = np.flatnonzero(lever > 1e-9)
        theta = gap[on] / lever[on]
        shift = min(float(theta.min()), 0.0)
        try:
            sol = solve_lemke(s_mat[np.ix_(on, on)], theta - shift, lever[on], torque_nm / self.zones * 1e3)
            return float(theta.min()), float(sol.phi_rad) + shift
        except ContactError:  # Lemke's conditioning guard: the same LCP by bisection on φ
            pass

        def torque(phi):
            return self.zones * float(lever @ solve_spd(s_mat, gap - lever * phi)) / 1e3

        lo, hi = float(theta.min()), float(theta.min()) + 1e-4
        while torque(hi) < torque_nm:
            lo, hi = hi, hi + 2.0 * (hi - lo)
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if torque(mid) < torque_nm else (lo, mid)
        return float(theta.min()), 0.5 * (lo + hi)


class _Subset:
    """The rows ``keep`` of a ContactPoints (the fields the climb reads)."""

    tooth: np.ndarray
    phi_rad: np.ndarray
    t_mm: np.ndarray
    local_mm: np.ndarray
    fs_point_mm: np.ndarray
    cs_point_mm: np.ndarray
    normal: np.ndarray
    gap_mm: np.ndarray
    lever_mm: np.ndarray

    def __init__(self, p, keep):
        for name in ("tooth", "phi_rad", "t_mm", "local_mm", "fs_point_mm", "cs_point_mm", "normal", "gap_mm",
                     "lever_mm"):
            setattr(self, name, np.asarray(getattr(p, name))[keep])
        self.zones, self.rotation, self.side = p.zones, p.rotation, p.side

    @property
    def count(self):
        return int(self.tooth.size)

    @property
    def teeth(self):
        return np.unique(self.tooth)


# --------------------------------------------------------------------------- across the face


class SectionDeformation:
    """The design's deformation with an axial section's change from the design section added:
    ω, υ (and their φ-derivatives) = ``base`` + (``section`` − ``reference``) — the gap shift
    of the face-load study (``research/face_load.py``) taken into the exact kinematics (the design's own
    deformation stays the one the CS was generated with; only the change along the face enters)."""

    __slots__ = ("base", "section", "reference")

    def __init__(self, base, section, reference):
        self.base, self.section, self.reference = base, section, reference

    @property
    def symmetric(self) -> bool:
        return all(bool(getattr(d, "symmetric", False)) for d in (self.base, self.section, self.reference))

    def evaluate(self, phi, order: int = 3):
        (w0, u0), (w1, u1), (w2, u2) = (d.evaluate(phi, order=order) for d in (self.base, self.section, self.reference))
        return np.asarray(w0) + np.asarray(w1) - np.asarray(w2), np.asarray(u0) + np.asarray(u1) - np.asarray(u2)


def section_inputs(inputs, section, reference):
    """``inputs`` (a ContactInput) with the FS tooth placed by the deformation of an axial
    section: :class:`SectionDeformation` (``section`` − ``reference`` added to the design's),
    the CS space, tooth and gear set unchanged."""
    import dataclasses

    from ..geometry.kinematics import HarmonicDriveMotion

    m = inputs.motion
    motion = HarmonicDriveMotion(SectionDeformation(m.deformation, section, reference), m.neutral_radius_mm,
                                 m.waves, m.cs_teeth)
    return dataclasses.replace(inputs, motion=motion)


class SlicedClimb:
    """The climb of N axial slices in parallel, each a :class:`DesignClimb` of its section built
    with ``width_fraction`` = its share of the face, sharing the rotation φ; the torque is
    their sum. ``coupled=False`` (the face-load study's model, ``research/face_load.py``): each slice's
    teeth retreat by their own forces — the rim, the balls and the CS ring of a slice carry
    only that slice's load (a Winkler foundation). ``coupled=True``: the face held straight —
    a tooth retreats alike along the face, by the mean of the slices' retreats (each slice's
    P_i F_i is the whole face's retreat under N× its load, so the mean is the whole face's
    under the sum), while each slice's contact keeps its own local compliance (its S with the
    own-slice first-order retreat taken out of the gaps, the shared one put in). The radial
    compliance (balls, CS ring, rim) acts over the face as one; the truth lies between.
    With identical slices both are the one-section climb exactly (each slice 1/N of the load)."""

    def __init__(self, models, *, coupled: bool = False):
        self.models = tuple(models)
        if not self.models:
            raise ConvergenceError("SlicedClimb: no slices")
        self.coupled = bool(coupled)
        self.zones = self.models[0].zones
        self._tooth_off = np.cumsum([0] + [m.depth_mm.size for m in self.models])
        self._pt_off = np.cumsum([0] + [m.n for m in self.models])
        self.slot = np.concatenate([m.slot + o for m, o in zip(self.models, self._tooth_off)])
        self.depth_mm = np.concatenate([m.depth_mm for m in self.models])
        self.corner = np.concatenate([m.corner for m in self.models])
        self.n = int(self._pt_off[-1])
        self.corner_criterion = any(getattr(m, "corner_criterion", True) for m in self.models)
        # the averaging of the copies of each tooth over the slices (m_total × m_total)
        ids = np.concatenate([m.teeth for m in self.models])
        self._mean = (ids[:, None] == ids[None, :]).astype(float) / len(self.models)

    @property
    def sin_alpha(self):
        return np.concatenate([m.sin_alpha for m in self.models])

    def _split(self, x, off):
        return [x[a:b] for a, b in zip(off[:-1], off[1:])]

    def shared_retreat(self, s):
        """The teeth's retreat: each slice's own (uncoupled), or the mean over the slices of each
        tooth's (the face held straight; the climb iterates on the slices' own shares P_i F_i,
        which their S hold to first order, and the gaps see the mean)."""
        return self._mean @ s if self.coupled else s

    def geometry(self, s, phi: float = 0.0):
        s = self.shared_retreat(s)
        out = [m.geometry(si, phi) for m, si in zip(self.models, self._split(s, self._tooth_off))]
        return np.concatenate([g for g, _ in out]), np.concatenate([r for _, r in out])

    def retreat_offset(self, state):
        return np.concatenate([np.broadcast_to(m.retreat_offset(st), (m.depth_mm.size,))
                               for m, st in zip(self.models, state)])

    def initial_state(self):
        return tuple(m.initial_state() for m in self.models)

    def settled(self, state) -> bool:
        return all(m.settled(st) for m, st in zip(self.models, state))

    def respond(self, q, state):
        from scipy.linalg import block_diag

        out = [m.respond(qi, st) for m, qi, st in zip(self.models, self._split(q, self._pt_off), state)]
        return (np.concatenate([o[0] for o in out]), tuple(o[1] for o in out),
                block_diag(*[o[2] for o in out]), block_diag(*[o[3] for o in out]))


def _dense(points: np.ndarray, step_mm: float) -> np.ndarray:
    """A sampled outline with every step longer than ``step_mm`` filled with points on it: a
    contour's sample gives a line as its two ends, and a large module's flank line (0.73 mm at
    size 58, ratio 50) then read as a jump of the outline's radius in the polar lookup."""
    d = np.diff(points, axis=0)
    k = np.maximum(np.ceil(np.hypot(d[:, 0], d[:, 1]) / step_mm).astype(int), 1)
    seg = np.repeat(np.arange(len(d)), k)
    f = (np.arange(k.sum()) - np.repeat(np.cumsum(k) - k, k)) / k[seg]
    return np.vstack([points[seg] + f[:, None] * d[seg], points[-1:]])
