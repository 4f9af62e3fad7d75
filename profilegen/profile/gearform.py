"""The circular-spline outline from the classified envelope, and the clearance map.

One CS tooth space is the swept boundary (``Envelope.flank["boundary"]``) with two
designer's choices added, both radial clearances from the gear set:

* the CS **tip circle** r_a2 = (radius where the swept regions of two neighbouring
  FS teeth meet, on the CS tooth's axis) + ``tip_clearance_mm``;
* the CS **root circle** r_f2 = (highest point of the swept region, the FS tip on
  the major axis) + ``root_clearance_mm``. Above the last point where the flank is
  within 45° of radial, each flank continues along its tangent to the root circle
  (a convex boundary's tangent stays outside the swept region; the clearance map
  checks it).

The full outline repeats the space every 2π/z2 and joins neighbouring spaces by
arcs of the tip circle. The clearance map is the signed distance, for each φ,
between the deformed FS tooth (with its root lands) and the CS outline: ≥ 0 is
clearance, < 0 interference; on the working flank it is 0 up to the chord
tolerance.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import shapely

from ..errors import EnvelopeError
from ..geometry.deformation import ScaledDeformation
from ..geometry.kinematics import turn
from ..results import readonly as _readonly
from ..stagecache import checkpoint

if TYPE_CHECKING:  # pragma: no cover
    from .envelope import Envelope
    from ..geometry.kinematics import Motion
    from ..geometry.teeth import ToothProfile

__all__ = ["CircularSplineForm", "ClearanceMap", "PolylineDistance", "circular_spline_form", "clearance_map", "cs_chain",
           "cs_local_chain", "cs_outline", "cs_space"]



def _polar_angle(p: np.ndarray) -> np.ndarray:
    return np.arctan2(p[..., 0], p[..., 1])


def _arc(radius: float, theta_a: float, theta_b: float, chord_tol_mm: float) -> np.ndarray:
    """Points on a circle about the origin from angle θa to θb, chord sag ≤ tol (ends included)."""
    step = 2.0 * np.sqrt(2.0 * chord_tol_mm / radius)
    n = max(2, int(np.ceil(abs(theta_b - theta_a) / step)) + 1)
    th = np.linspace(theta_a, theta_b, n)
    return np.stack([radius * np.sin(th), radius * np.cos(th)], -1)


def _circle_crossing(chain: np.ndarray, radius: float) -> tuple[int, np.ndarray]:
    """First crossing of a polyline, walked from its start, with the circle r = radius."""
    r = np.hypot(chain[:, 0], chain[:, 1])
    above = r >= radius
    if above[0]:
        return 0, chain[0]
    k = int(np.argmax(above))
    if not above[k]:
        raise EnvelopeError(f"gearform: the CS flank never reaches the circle r = {radius:.6f} mm")
    a, b = chain[k - 1], chain[k]
    # solve |a + s (b − a)| = radius for s in [0, 1]
    d = b - a
    A, B, C = d @ d, 2 * a @ d, a @ a - radius**2
    s = (-B + np.sqrt(max(B * B - 4 * A * C, 0.0))) / (2 * A)
    return k, a + np.clip(s, 0, 1) * d


def _leave_point(flank: np.ndarray, max_angle_deg: float = 45.0) -> int:
    """Index of the last flank vertex (walking up) whose tangent is within max_angle of radial."""
    d = np.diff(flank, axis=0)
    mid = 0.5 * (flank[1:] + flank[:-1])
    radial = mid / np.hypot(mid[:, 0], mid[:, 1])[:, None]
    cosang = np.abs(np.sum(d * radial, 1)) / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-300)
    steep = np.nonzero(cosang >= np.cos(np.radians(max_angle_deg)))[0]
    if steep.size == 0:
        raise _NoWorkingFlank(float(np.degrees(np.arccos(np.clip(cosang.max(), 0.0, 1.0)))))
    return int(steep[-1]) + 1


class _NoWorkingFlank(EnvelopeError):
    """No stretch of the flank within 45° of radial (``steepest_deg``: its steepest stretch)."""

    def __init__(self, steepest_deg: float):
        self.steepest_deg = steepest_deg
        super().__init__(f"gearform: the CS flank is nowhere steeper than 45° from radial (at most {steepest_deg:.1f}°)")


def _angle_from_radial(points: np.ndarray) -> np.ndarray:
    """Angle (deg) of each step of a polyline from the radial direction at its middle."""
    d = np.diff(points, axis=0)
    mid = 0.5 * (points[1:] + points[:-1])
    cosang = np.abs(np.sum(d * mid, 1)) / np.maximum(np.hypot(*d.T) * np.hypot(*mid.T), 1e-300)
    return np.degrees(np.arccos(np.clip(cosang, 0.0, 1.0)))


def _tip_path_steepest(tooth, motion, phi_range, factor: float = 1.0, n: int = 4001) -> float:
    """Smallest angle (deg) from radial of the path of the FS tooth's tip (the top land's middle)
    over one pass, the deflection scaled by ``factor``. The top of the swept boundary follows
    this path: its steepest stretch is the swept flank's (0.02° apart on a ring-theory set at
    ω* 0.3–0.55)."""
    import dataclasses

    if factor != 1.0:
        motion = dataclasses.replace(motion, deformation=ScaledDeformation(motion.deformation, factor))
    pose = motion.pose(np.linspace(phi_range[0], phi_range[1], n))
    tip = pose.to_cs(np.broadcast_to(np.array([0.0, tooth.addendum_y_mm]), (n, 2)))
    return float(_angle_from_radial(tip).min())


def _no_working_flank(envelope, side: np.ndarray, r_mid: float, tip_clearance_mm: float, steepest_deg: float,
                      max_angle_deg: float = 45.0) -> str:
    """The message for a CS space with no working flank, naming the gear-set field to change and
    to what: ``circular_spline.tip_clearance_mm`` when the flank below the tip circle has a steep
    stretch (the largest clearance that keeps it), else ``wave_generator.deflection_coefficient``
    (the smallest that makes the tooth tip's path, and so the swept flank, steep enough: found
    by bisection on the deflection, the wave generator's shape kept)."""
    head = (f"gearform: no working flank — the CS space's flank above its tip circle is nowhere steeper than "
            f"{max_angle_deg:g}° from radial (at most {steepest_deg:.1f}°)")
    top = int(np.argmax(np.hypot(side[:, 0], side[:, 1])))
    below = side[: top + 1]
    ang = _angle_from_radial(below)
    steep = np.flatnonzero(ang <= max_angle_deg)
    if steep.size:
        r_steep = float(np.hypot(*below[steep[-1] + 1]))
        most = r_steep - r_mid
        if most > 0.0:
            return (f"{head}: circular_spline.tip_clearance_mm = {tip_clearance_mm:g} mm puts the tip circle above "
                    f"the flank's steep stretch; at most {0.9 * most:.4g} mm keeps it")
    gen = getattr(envelope, "generator", None)
    if gen is None:  # pragma: no cover — an envelope not made by envelope_of
        return f"{head}: the tooth moves too little radially; raise wave_generator.deflection_coefficient"
    tooth, motion = gen
    m = float(tooth.module_mm)
    w0 = float(motion.deformation.evaluate(np.zeros(1), order=0)[0][0, 0])
    now = w0 / m
    target = max_angle_deg - 1.0
    hi_factor = 3.0 / now  # wave_generator.deflection_coefficient ≤ 3
    if _tip_path_steepest(tooth, motion, envelope.phi_range, hi_factor) > target:
        return (f"{head}: wave_generator.deflection_coefficient = {now:.4g} (w0 = {w0:.4g} mm): even 3 leaves the "
                "tooth's path too flat; a taller tooth (tooth.addendum_mm) or another wave generator is needed")
    lo, hi = 1.0, hi_factor
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if _tip_path_steepest(tooth, motion, envelope.phi_range, mid) <= target:
            hi = mid
        else:
            lo = mid
        if hi - lo < 1e-3:
            break
    need = math.ceil(now * hi * 100.0) / 100.0
    return (f"{head}: the tooth moves too little radially for its slide (its tip's path is at least "
            f"{_tip_path_steepest(tooth, motion, envelope.phi_range):.1f}° from radial); raise "
            f"wave_generator.deflection_coefficient = {now:.4g} to at least {need:g} (w0 = {w0:.4g} mm → "
            f"{need * m:.4g} mm at gear.module_mm = {m:g} mm; gear.rim_thickness_mm must stay >= 0.5·w0 = "
            f"{0.5 * need * m:.4g} mm)")


def _tangent_to_circle(p: np.ndarray, direction: np.ndarray, radius: float) -> np.ndarray:
    """Where the ray p + s·direction (s ≥ 0) meets the circle r = radius from inside."""
    d = direction / np.hypot(*direction)
    B = 2 * p @ d
    C = p @ p - radius**2
    s = (-B + np.sqrt(max(B * B - 4 * C, 0.0))) / 2
    return p + s * d


@dataclass(frozen=True, slots=True, eq=False)
class ClearanceMap:
    """Signed clearance between the deformed FS tooth and the CS outline over one pass."""

    phi: np.ndarray
    clearance_mm: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "phi", _readonly(self.phi))
        object.__setattr__(self, "clearance_mm", _readonly(self.clearance_mm))

    @property
    def min_mm(self) -> float:
        return float(self.clearance_mm.min())

    @property
    def at_phi(self) -> float:
        return float(self.phi[np.argmin(self.clearance_mm)])

    def to_dict(self) -> dict:
        return {"min_clearance_mm": self.min_mm, "at_phi_rad": self.at_phi, "samples": int(self.phi.size)}


@dataclass(frozen=True, slots=True, eq=False)
class CircularSplineForm:
    """One CS tooth space, the whole CS inner outline, and the clearance map.

    ``space``: left tip-circle point → left flank → root → right flank → right
    tip-circle point (mm, CS frame). ``outline``: the closed inner outline of all
    z2 spaces (first point not repeated). ``working_flank``: per side, the part of
    the swept boundary kept as the CS flank (tip circle → leave point).
    """

    space: np.ndarray
    outline: np.ndarray
    working_flank: dict
    tip_radius_mm: float
    root_radius_mm: float
    outer_radius_mm: float
    cs_teeth: int
    clearance: ClearanceMap | None
    time_s: float
    warnings: tuple[str, ...] = field(default_factory=tuple)

    def polygon(self) -> shapely.Polygon:
        """The CS ring as shapely geometry: outer circle with the toothed outline as its hole."""
        outer = _arc(self.outer_radius_mm, 0.0, 2 * np.pi, 1e-4)[:-1]
        return shapely.Polygon(outer, holes=[self.outline])

    def to_dict(self) -> dict:
        return {
            "tip_radius_mm": self.tip_radius_mm,
            "root_radius_mm": self.root_radius_mm,
            "outer_radius_mm": self.outer_radius_mm,
            "space_points": int(len(self.space)),
            "outline_points": int(len(self.outline)),
            "clearance": None if self.clearance is None else self.clearance.to_dict(),
            "time_s": self.time_s,
            "warnings": list(self.warnings),
        }


def circular_spline_form(
    envelope: Envelope,
    *,
    cs_teeth: int,
    tip_clearance_mm: float,
    root_clearance_mm: float,
    outer_radius_mm: float | None = None,
    chord_tol_mm: float = 1e-6,
) -> CircularSplineForm:
    """Build the CS outline from the classified swept boundary (see the module docstring)."""
    t0 = time.perf_counter()
    chain = envelope.flank.get("boundary")
    if chain is None or len(chain) < 3:
        raise EnvelopeError("gearform: the envelope has no swept boundary to build the CS from")
    warnings = []
    if envelope.flank.get("chains", 1) > 1:
        warnings.append(f"the swept boundary came in {envelope.flank['chains']} chains; the longest is used")
    r = np.hypot(chain[:, 0], chain[:, 1])
    r_mid = float(max(r[0], r[-1]))  # where the neighbours' swept regions meet
    r_top = float(r.max())
    tip_r = r_mid + tip_clearance_mm
    root_r = r_top + root_clearance_mm
    if tip_r >= r_top:
        raise EnvelopeError(
            f"gearform: the tip circle r_a2 = {tip_r:.4f} mm (meeting radius {r_mid:.4f} + "
            f"circular_spline.tip_clearance_mm {tip_clearance_mm}) lies above the space's top {r_top:.4f} mm"
        )
    warnings += _unresolved(envelope, tip_r, r_mid)
    sides = {}
    for name, ch in (("right", chain), ("left", chain[::-1])):
        k, p_tip = _circle_crossing(ch, tip_r)
        flank = np.vstack([p_tip, ch[k:]])
        top = int(np.argmax(np.hypot(flank[:, 0], flank[:, 1])))
        flank = flank[: top + 1]
        try:
            j = _leave_point(flank)
        except _NoWorkingFlank as exc:
            raise EnvelopeError(_no_working_flank(envelope, ch, r_mid, tip_clearance_mm, exc.steepest_deg)) from None
        work = flank[: j + 1]
        p_root = _tangent_to_circle(work[-1], work[-1] - work[-2], root_r)
        sides[name] = (work, p_root)
    (wr, pr), (wl, pl) = sides["right"], sides["left"]
    th_r, th_l = float(_polar_angle(pr)), float(_polar_angle(pl))
    if th_r <= th_l:
        # the two tangent extensions cross before reaching the root circle: a pointed root
        d1, d2 = pr - wr[-1], pl - wl[-1]
        den = d1[0] * d2[1] - d1[1] * d2[0]
        s = ((wl[-1] - wr[-1])[0] * d2[1] - (wl[-1] - wr[-1])[1] * d2[0]) / den
        apex = wr[-1] + s * d1
        root = apex[None]
        warnings.append(
            f"the flank extensions meet at r = {np.hypot(*apex):.4f} mm below the root circle "
            f"{root_r:.4f} mm: a narrow space whose root circle is not reached (the CAD outline closes it with "
            f"an arc tangent to both flanks; a smaller circular_spline.root_clearance_mm reaches the root circle)"
        )
    else:
        root = _arc(root_r, th_l, th_r, chord_tol_mm)
    # space: left tip point → up the left flank → root (left to right) → down the right flank
    space = np.vstack([wl, root, wr[::-1]])
    keep = np.concatenate([[True], np.hypot(*np.diff(space, axis=0).T) > 1e-12])
    space = space[keep]
    pitch = 2 * np.pi / cs_teeth
    th_space_r, th_space_l = float(_polar_angle(space[-1])), float(_polar_angle(space[0]))
    land = _arc(tip_r, th_space_r, th_space_l + pitch, chord_tol_mm)[1:-1]
    unit = np.vstack([space, land])
    outline = np.vstack([turn(unit, k * pitch) for k in range(cs_teeth)])
    if outer_radius_mm is None:
        outer_radius_mm = 1.25 * root_r
    form = CircularSplineForm(
        space=_readonly(space),
        outline=_readonly(outline),
        working_flank={"right": _readonly(wr), "left": _readonly(wl)},
        tip_radius_mm=tip_r,
        root_radius_mm=root_r,
        outer_radius_mm=float(outer_radius_mm),
        cs_teeth=cs_teeth,
        clearance=None,
        time_s=time.perf_counter() - t0,
        warnings=tuple(warnings),
    )
    return form


class UnresolvedBoundaryError(EnvelopeError):
    """The swept boundary has a stretch the trace did not resolve above the CS tip circle (a
    grazing crossing between two grid lines). A finer chord resolves it: the pipeline retraces
    the envelope itself (:func:`profilegen.pipeline.design.traced_form`) before this reaches a user."""

#: On an :class:`UnresolvedBoundaryError` the pipeline traces again at a chord ``RETRACE_FACTOR``
#: finer, up to ``RETRACES`` times (the memory preflight budgets for the finest of those traces).
RETRACES, RETRACE_FACTOR = 2, 4.0


def _unresolved(envelope, tip_r: float, r_mid: float) -> list[str]:
    """What the envelope's unresolved stretches (``diagnostics["unresolved"]``) mean for the CS.

    A boundary stretch counts where it lies on the swept-boundary chain the outline is built
    from (a stray one off the chain is already in the "N pieces" warning); an interfering
    stretch that comes back to the boundary always counts, for the boundary misses it.
    Above the tip circle the CS outline itself would be wrong: EnvelopeError. Below it the CS
    has no material, and only the meeting radius — so the tip circle's height — is in doubt:
    a warning naming the place.
    """
    from .envelope import INTERFERING

    chain = envelope.flank["boundary"]
    found = [f for f in envelope.diagnostics.get("unresolved") or []
             # a boundary stretch matters where it is in the chain the outline is built from;
             # an interfering one (a boundary part missing from the chain) always does
             if f["cls"] == INTERFERING or np.min(np.hypot(*(chain - f["point_mm"]).T)) < 1e-9]
    above = [f for f in found if f["radius_mm"] >= tip_r]
    if above:
        f = max(above, key=lambda f: f["depth_mm"])
        raise UnresolvedBoundaryError(
            f"gearform: the swept boundary is not resolved above the CS tip circle r_a2 = {tip_r:.4f} mm: {f['what']} "
            f"at ({f['point_mm'][0]:.4f}, {f['point_mm'][1]:.4f}) mm, r = {f['radius_mm']:.4f} mm, "
            f"{1e3 * f['depth_mm']:.3g} µm deep (a grazing crossing the trace missed); a finer chord_tol_mm or a "
            f"slightly different deflection coefficient avoids it")
    if not found:
        return []
    f = max(found, key=lambda f: f["depth_mm"])
    return [f"the swept boundary is not resolved below the CS tip circle, near where neighbouring spaces meet "
            f"(r = {f['radius_mm']:.4f} mm against the meeting radius {r_mid:.4f} mm): {f['what']}, "
            f"{1e3 * f['depth_mm']:.3g} µm deep — a crossing the trace missed, such as with the FS root land's sweep, "
            f"which is not traced; the tip circle r_a2 may sit that much too low"]


def _local_outline(form: CircularSplineForm, neighbours: int = 1) -> np.ndarray:
    """The CS outline around space 0: spaces −n..n with their tip lands, as one polyline."""
    pitch = 2 * np.pi / form.cs_teeth
    n_unit = len(form.outline) // form.cs_teeth
    unit = form.outline[:n_unit]
    parts = [turn(unit, k * pitch) for k in range(-neighbours, neighbours + 1)]
    return np.vstack(parts)


def clearance_map(form: CircularSplineForm, tooth: ToothProfile, motion: Motion, *, phi_range: tuple[float, float],
                  samples: int = 361, candidates: int = 32,
                  cs_points: np.ndarray | None = None, search_per_mm: float = 800.0, neighbours: int = 4,
                  deep_check_mm: float = 1e-7, few_first: bool | None = None, threads: int = 1) -> ClearanceMap:
    """Signed distance between the FS tooth (with root lands) and the CS outline at each φ.

    ``cs_points`` (the CS outline around space 0, mm) defaults to the form's own
    polyline outline; pass a sampled arc-fit outline to check that instead. For each
    φ a KD-tree over the CS points finds the ``candidates`` nearest to the placed
    tooth surface, and their exact distance to that surface is taken (negative
    inside the tooth). Measured against a brute-force distance of every CS point: exact
    (to rounding) wherever the clearance is below 10 µm, i.e. near contact and for any
    interference; farther out of mesh the candidate search can read up to ~1 µm high.
    At every pose whose clearance reads below −``deep_check_mm`` (an interference beyond
    the traced envelope's own chord error) every CS point inside the tooth is measured as
    well (:func:`_deepest_inside`): near-surface candidates alone miss the deepest point of
    an interference where the outline is dense.
    ``few_first``: find the first 1.25 × ``candidates`` nearest pairs at every pose, then 4 ×
    at the poses those hold too few distinct CS points; False: 4 × at every pose at once (the same
    result: the first pairs are the same; the face stage's maps, where ~all poses need 4 ×). None
    (default): False on the form's own outline (``cs_points`` None: on the default set's design scene
    278 of 361 poses need 4 ×, and the map takes 0.15 s instead of 0.20 s), True on a given one (the
    fitted outline's check: 214 of 721).
    ``threads``: 2 measures the later half of the poses on a thread of its own (the same numbers).
    """
    if few_first is None:
        few_first = cs_points is not None
    from scipy.spatial import cKDTree

    ring = tooth.outline(n_per_mm=400.0)  # the tooth as a polygon: prepared in each thread (GEOS's
    # prepared geometries are not for two threads at once: a shared one corrupted the heap)
    # distances to the real FS surface, not to the polygon's radial sector edges and
    # neutral-line arc, which only close it
    surface = PolylineDistance(tooth.surface(n_per_mm=400.0))
    surface_pts = tooth.surface(n_per_mm=search_per_mm)  # to find the candidates
    cs = _local_outline(form) if cs_points is None else np.asarray(cs_points, float)
    # leaves of 64 points, unbalanced: faster on dense outlines (measured); on a sparse one (the face stage's
    # 564 points) leaves of 16 query faster (the same answers: the nearest point does not depend on the tree)
    tree = (cKDTree(cs, leafsize=64, compact_nodes=False, balanced_tree=False) if len(cs) > _SPARSE_OUTLINE
            else cKDTree(cs, leafsize=16))
    phis = np.linspace(phi_range[0], phi_range[1], samples)
    args = (motion, tree, cs, ring, surface, surface_pts, candidates, neighbours, deep_check_mm, few_first)
    cut = (samples // 2) // _POSE_STRIDE * _POSE_STRIDE
    if threads > 1 and cut >= _SPLIT_POSES:
        # the later poses on a thread of their own (the KD-tree's queries, shapely's and numpy's loops
        # let go of the interpreter); every pose is measured on its own, so the halves give the numbers
        # the whole does
        from ..stagecache import Beside

        later = Beside(_clearances, phis[cut:], *args)
        out = np.concatenate([_clearances(phis[:cut], *args), later.result()])
    else:
        out = _clearances(phis, *args)
    return ClearanceMap(phis, out)


#: the fewest poses in each half of a clearance map split over two threads
_SPLIT_POSES = 64


def _clearances(phis, motion, tree, cs, ring, surface, surface_pts, candidates, neighbours, deep_check_mm,
                few_first) -> np.ndarray:
    """The signed clearance at each of ``phis`` (:func:`clearance_map`'s search); ``ring``: the
    tooth's outline (a polygon of its own is prepared here)."""
    samples = len(phis)
    poly = shapely.Polygon(ring)
    shapely.prepare(poly)
    pose = motion.pose(phis)
    cos, sin = np.cos(pose.angle), np.sin(pose.angle)
    # every pose's candidates at once: the surface points nearest the CS, nearest first
    # (:func:`_nearest_pairs`), their CS points' first ``candidates`` distinct ones, and
    # those points' ``neighbours`` on either side, in CS order
    # of the 4 × candidates nearest pairs: the first pairs alone hold the first ``candidates``
    # distinct CS points wherever they hold that many (most poses: ~40 pairs for 32); the other
    # poses take all the pairs
    need = 4 * candidates
    few = min(need, candidates + candidates // 4) if few_first else need
    order = _nearest_pairs(tree, surface_pts, cos, sin, pose.origin, few)
    new = _first_appearances(order)
    short = np.flatnonzero(new.sum(axis=1) < candidates) if few < need else np.empty(0, int)
    if short.size:
        more = _nearest_pairs(tree, surface_pts, cos[short], sin[short], pose.origin[short], need)
        order = np.concatenate([order, np.full((samples, more.shape[1] - order.shape[1]), -1)], axis=1)
        order[short] = more
        new = _first_appearances(order)
    keep = new & (np.cumsum(new, axis=1) <= candidates)
    near = np.clip(order[:, :, None] + np.arange(-neighbours, neighbours + 1), 0, len(cs) - 1)
    near = np.where(keep[:, :, None], near, len(cs)).reshape(samples, -1)  # len(cs): no point
    near.sort(axis=1)
    take = near < len(cs)
    take[:, 1:] &= near[:, 1:] != near[:, :-1]
    rows, cols = np.nonzero(take)
    counts = np.count_nonzero(take, axis=1)
    d = cs[near[rows, cols]] - pose.origin[rows]
    c, s = cos[rows], sin[rows]
    q = np.stack([d[:, 0] * c - d[:, 1] * s, d[:, 0] * s + d[:, 1] * c], -1)  # (d·e_t, d·e_r)
    exact = np.empty(len(q))  # point by point: the same numbers as pose by pose
    for k in range(0, len(q), _DISTANCE_CHUNK):
        checkpoint()  # an engine's design stops here when superseded (2001 poses: ~0.3 s of distances)
        exact[k:k + _DISTANCE_CHUNK] = surface.distance(q[k:k + _DISTANCE_CHUNK])
    checkpoint()
    inside = shapely.contains_xy(poly, q[:, 0], q[:, 1])
    out = np.minimum.reduceat(np.where(inside, -exact, exact), np.concatenate([[0], np.cumsum(counts)[:-1]]))
    deep = np.nonzero(out < -deep_check_mm)[0]
    if deep.size:
        out = out.copy()
        out[deep] = _deepest_inside(poly, surface, tree, cs, pose, deep, out[deep])
    return out


#: the clearance map's CS outline up to this many points takes a KD-tree of smaller leaves
_SPARSE_OUTLINE = 2000

#: candidate points measured between two checkpoints of the clearance map (~25 ms each)
_DISTANCE_CHUNK = 16384


def _deepest_inside(poly, surface, tree, cs: np.ndarray, pose, poses: np.ndarray, found: np.ndarray) -> np.ndarray:
    """The deepest CS point inside the placed FS tooth at each of ``poses`` (which interfere).

    The candidate search takes the CS points nearest the tooth surface: where the outline
    is dense they all sit where it crosses the surface, and the deepest point of an
    interference, farther from the surface, is missed (on a 1 nm trace −2.86 µm was read for
    a −4.76 µm interference). Here every CS point within the tooth's bounding circle is
    tested for insideness, and the inside ones' exact distances are taken."""
    xy = np.asarray(poly.exterior.coords)
    centre = xy.mean(axis=0)
    radius = float(np.max(np.hypot(*(xy - centre).T))) * (1.0 + 1e-9) + 1e-9
    out = np.array(found, dtype=float)
    # all the poses at once, the same arithmetic as pose by pose (each pose's cos, sin as a scalar)
    c = np.array([np.cos(a) for a in pose.angle[poses]])
    s = np.array([np.sin(a) for a in pose.angle[poses]])
    g = np.stack([centre[0] * c + centre[1] * s, centre[1] * c - centre[0] * s], -1) + pose.origin[poses]
    found_idx = tree.query_ball_point(g, radius)
    counts = np.array([len(i) for i in found_idx], dtype=int)
    if not counts.sum():
        return out
    k = np.repeat(np.arange(len(poses)), counts)
    d = cs[np.concatenate([np.asarray(i, dtype=int) for i in found_idx])] - pose.origin[poses][k]
    loc = np.stack([d[:, 0] * c[k] - d[:, 1] * s[k], d[:, 0] * s[k] + d[:, 1] * c[k]], -1)
    inside = shapely.contains_xy(poly, loc[:, 0], loc[:, 1])
    loc, k = loc[inside], k[inside]
    dist = np.empty(len(loc))
    for j in range(0, len(loc), _DISTANCE_CHUNK):
        checkpoint()
        dist[j:j + _DISTANCE_CHUNK] = surface.distance(loc[j:j + _DISTANCE_CHUNK])
    deepest = np.full(len(poses), -np.inf)
    np.maximum.at(deepest, k, dist)
    hit = np.isfinite(deepest)
    out[hit] = np.minimum(out[hit], -deepest[hit])
    return out


def _first_appearances(order: np.ndarray) -> np.ndarray:
    """True at each row's first appearance of a CS point (−1: no point), in the row's order."""
    srt = np.argsort(order, axis=1, kind="stable")
    sorted_ = np.take_along_axis(order, srt, axis=1)
    first = np.ones(order.shape, bool)
    first[:, 1:] = sorted_[:, 1:] != sorted_[:, :-1]
    new = np.empty_like(first)
    np.put_along_axis(new, srt, first, axis=1)
    return new & (order >= 0)


#: the clearance map's reference poses for the coarse distances: every this many poses
_POSE_STRIDE = 4


def _nearest_pairs(tree, surface_pts: np.ndarray, cos: np.ndarray, sin: np.ndarray, origin: np.ndarray,
                   need: int, stride: int = 16) -> np.ndarray:
    """At each pose (rotation ``cos``, ``sin`` and ``origin`` of the placed surface, one row
    each): the nearest CS point (index into ``tree``) of the ``need`` surface points nearest
    to the CS, nearest first, ties in the surface's order — what a query of every surface
    point gives once stably sorted by distance. Returns an (m, min(need, n)) array.

    Most of the surface is far from the CS; the search skips it. Every ``stride``-th surface
    point (the coarse points) is queried first, within a bound that grows ×4 until more
    than k = need/stride + 1 are found; the pose's bound is the k-th smallest coarse distance
    (exact: those found within the query's bound are). The nearest-CS distance is
    1-Lipschitz along the surface, so a surface point farther than the bound from the CS is
    known from its coarse anchor (distance − offset > bound) without a query; the rest are
    queried. A pose with fewer than ``need`` within its bound takes 4× the bound, up to three
    times, then every surface point. All poses query the tree together, in groups of
    similar bound (a query has one ``distance_upper_bound``).
    """
    n, m = len(surface_pts), len(cos)
    coarse = np.arange(0, n, stride)
    nc = len(coarse)
    k = min(nc - 1, need // stride + 1)
    anchor = np.clip(np.rint(np.arange(n) / stride).astype(int), 0, nc - 1)
    # distance of each surface point to its anchor (rigid motions keep it; 1 nm for rounding)
    offset = np.hypot(*(surface_pts - surface_pts[coarse[anchor]]).T) + 1e-6

    def place(rows, cols):  # surface points cols at poses rows
        p, c, s = surface_pts[cols], cos[rows], sin[rows]
        return np.stack([p[:, 0] * c + p[:, 1] * s, p[:, 1] * c - p[:, 0] * s], -1) + origin[rows]

    # the coarse points' distances: exact, or a lower bound where they cannot be among the k + 1
    # smallest. Every ``_POSE_STRIDE``-th pose (and the last) queries them within a bound that
    # grows ×4 (exact within the query's last bound, that bound beyond it). A pose between takes
    # bounds from the reference pose before it: a point moved by δ from there lies within δ of
    # that distance (1-Lipschitz; 1 nm for rounding), so with U the k-th smallest upper bound only
    # the points whose lower bound is ≤ U are queried (within U: the k + 1 smallest are all there)
    placed = place(np.repeat(np.arange(m), nc), np.tile(coarse, m)).reshape(m, nc, 2)
    dc = np.empty((m, nc))
    exact = np.zeros((m, nc), bool)
    refs = np.unique(np.append(np.arange(0, m, _POSE_STRIDE), m - 1))
    pending, limit = refs, 0.05
    while pending.size:
        checkpoint()  # an engine's design stops here when superseded (the face stage maps ~20 sections)
        dist, _ = tree.query(placed[pending].reshape(-1, 2), distance_upper_bound=limit)
        dist = dist.reshape(-1, nc)
        found = np.isfinite(dist)
        dc[pending], exact[pending] = np.where(found, dist, limit), found
        pending = pending[np.count_nonzero(found, axis=1) <= k]
        limit = limit * 4.0 if limit < 100.0 else math.inf
    rest = np.setdiff1d(np.arange(m), refs)
    if rest.size:
        ref = refs[np.searchsorted(refs, rest) - 1]
        move = placed[rest] - placed[ref]
        delta = np.hypot(move[..., 0], move[..., 1]) + 1e-6
        low = np.maximum(dc[ref] - delta, 0.0)
        up = np.where(exact[ref], dc[ref] + delta, math.inf)
        cap = np.partition(up, k, axis=1)[:, k]  # ≥ the pose's k + 1 smallest distances
        ok = np.isfinite(cap)
        dc[rest] = low
        r, c = np.nonzero((low <= cap[:, None]) & ok[:, None])
        if r.size:
            dist, _ = _query_within(tree, placed[rest[r], c], cap[r])
            dc[rest[r], c] = np.where(dist <= cap[r], dist, np.maximum(low[r, c], cap[r]))
        for i in rest[~ok]:  # no upper bound: every coarse point, unbounded
            dc[i] = tree.query(placed[i])[0]
    bound = np.partition(dc, k, axis=1)[:, k]
    lower = dc[:, anchor] - offset  # ≤ each surface point's distance to the CS

    need_out = min(need, n)
    out = np.empty((m, need_out), dtype=int)
    todo = np.flatnonzero(bound > 0.0)
    full = np.flatnonzero(~(bound > 0.0))
    for _ in range(3):
        if not todo.size:
            break
        b = bound[todo] * (1.0 + 1e-9)
        r, cols = np.nonzero(lower[todo] <= b[:, None])  # pose by pose, in the surface's order
        dist, idx = _query_within(tree, place(todo[r], cols), b[r])
        ok = dist < b[r]
        done = np.bincount(r[ok], minlength=todo.size) >= need  # the `need` smallest are all within
        sel = np.flatnonzero(ok & done[r])
        rs, ds, js = r[sel], dist[sel], idx[sel]
        o = np.argsort(ds, kind="stable")
        o = o[np.argsort(rs[o], kind="stable")]  # by pose, then distance, then surface order
        rs, js = rs[o], js[o]
        start = np.searchsorted(rs, rs, side="left")
        pos = np.arange(rs.size) - start
        first = pos < need_out
        out[todo[rs[first]], pos[first]] = js[first]
        todo = todo[~done]
        bound[todo] *= 4.0
    for i in np.concatenate([full, todo]).astype(int):
        dist, idx = tree.query(place(np.full(n, i), np.arange(n)))
        out[i] = idx[np.argsort(dist, kind="stable")][:need_out]
    return out


def _query_within(tree, points: np.ndarray, bound: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Nearest tree point of each point, exact where it is within the point's ``bound`` (inf
    or a larger distance beyond): points of bounds within a factor 2 query together."""
    dist = np.full(len(points), math.inf)
    idx = np.full(len(points), tree.n)
    e = np.frexp(bound)[1]
    for g in np.unique(e):
        checkpoint()
        at = np.flatnonzero(e == g)
        dist[at], idx[at] = tree.query(points[at], distance_upper_bound=float(bound[at].max()))
    return dist, idx


class PolylineDistance:
    """Exact distance of points to an open polyline (mm), through a KD-tree over points
    spread along its segments (at most ``spacing`` apart, each labelled with its segment).

    The foot of a point p lies on a segment j that has a tree point within h/2 of the
    foot (h: the spacing), so within √(r0² + h²/4) of p, r0 being p's distance to its
    nearest tree point (≥ the true distance). When the ``k``-th nearest tree point is
    farther than that, the k nearest carry every segment that can hold the foot and the
    minimum over their segments is exact; otherwise (rare) all segments are searched. The 4
    nearest are asked for first (they carry the foot for ~9 points in 10 near a dense polyline), the
    ``k`` nearest for the rest: the same minimum, for half the segment distances.
    """

    def __init__(self, vertices: np.ndarray, *, k: int = 8):
        from scipy.spatial import cKDTree

        v = np.asarray(vertices, float)
        self.a, self.b = v[:-1], v[1:]
        lengths = np.hypot(*(self.b - self.a).T)
        positive = lengths[lengths > 0]
        self.spacing = float(np.median(positive)) if positive.size else 1.0
        per = np.maximum(np.ceil(lengths / self.spacing).astype(int), 1) + 1  # points per segment, ends included
        seg = np.repeat(np.arange(len(lengths)), per)
        # np.linspace(0, 1, n) of each segment, all at once (i · 1/(n − 1), the end exactly 1)
        f = (np.arange(per.sum()) - np.repeat(np.cumsum(per) - per, per)) * (1.0 / (per - 1))[seg]
        f[np.cumsum(per) - 1] = 1.0
        self.h = float(np.max(lengths / (per - 1)))
        self.label = seg
        self.k = int(min(k, len(seg)))
        self.tree = cKDTree(self.a[seg] + f[:, None] * (self.b[seg] - self.a[seg]))
        # each segment's terms of _segment_distance, once (the same numbers as computed there)
        ex, ey = self.b[:, 0] - self.a[:, 0], self.b[:, 1] - self.a[:, 1]
        len2 = ex * ex + ey * ey
        self._ex, self._ey, self._safe = ex, ey, np.where(len2 > 0, len2, 1.0)
        self._root, self._point = np.sqrt(len2), len2 == 0

    def distance(self, p: np.ndarray) -> np.ndarray:
        p = np.asarray(p, float)
        out = np.empty(len(p))
        todo = np.arange(len(p))
        for k in sorted({min(4, self.k), self.k}):
            if not todo.size:
                break
            r, j = self.tree.query(p[todo], k=k)
            r, j = r.reshape(len(todo), -1), j.reshape(len(todo), -1)
            sure = r[:, -1] > np.sqrt(r[:, 0] ** 2 + 0.25 * self.h**2)
            out[todo[sure]] = self._to_segments(p[todo[sure]], self.label[j[sure]]).min(axis=1)
            todo = todo[~sure]
        rare = todo
        for k in range(0, rare.size, 256):  # against every segment, 256 points at a time
            at = rare[k:k + 256]
            out[at] = _segment_distance(p[at, None, :], self.a[None], self.b[None]).min(axis=1)
        return out

    def _to_segments(self, p: np.ndarray, seg: np.ndarray) -> np.ndarray:
        """Distance of each point p[i] to the segments seg[i, :]: :func:`_segment_distance`'s
        arithmetic (the same numbers), its per-segment terms taken from ``__init__``."""
        dx, dy = p[:, 0, None] - self.a[seg, 0], p[:, 1, None] - self.a[seg, 1]
        ex, ey, safe = self._ex[seg], self._ey[seg], self._safe[seg]
        r = (dx * ex + dy * ey) / safe
        s = (dx * ey - dy * ex) / safe  # (a − p)_y e_x − (a − p)_x e_y, negations exact
        to_a = np.sqrt(dx * dx + dy * dy)
        bx, by = p[:, 0, None] - self.b[seg, 0], p[:, 1, None] - self.b[seg, 1]
        to_b = np.sqrt(bx * bx + by * by)
        return np.where(self._point[seg] | (r <= 0.0), to_a, np.where(r >= 1.0, to_b, np.abs(s) * self._root[seg]))


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of points p to segments [a, b] (broadcast over the leading axes), with
    GEOS's formula (``Distance::pointToSegment``), so that it rounds as shapely does."""
    ex, ey = b[..., 0] - a[..., 0], b[..., 1] - a[..., 1]
    len2 = ex * ex + ey * ey
    safe = np.where(len2 > 0, len2, 1.0)
    r = ((p[..., 0] - a[..., 0]) * ex + (p[..., 1] - a[..., 1]) * ey) / safe
    s = ((a[..., 1] - p[..., 1]) * ex - (a[..., 0] - p[..., 0]) * ey) / safe
    to_a = np.sqrt((p[..., 0] - a[..., 0]) ** 2 + (p[..., 1] - a[..., 1]) ** 2)
    to_b = np.sqrt((p[..., 0] - b[..., 0]) ** 2 + (p[..., 1] - b[..., 1]) ** 2)
    return np.where((len2 == 0) | (r <= 0.0), to_a, np.where(r >= 1.0, to_b, np.abs(s) * np.sqrt(len2)))


# ----------------------------------------------------------------------------- true arcs and lines


_MIRROR = np.array([[-1.0, 0.0], [0.0, 1.0]])


def _math_angle(p) -> float:
    return float(np.arctan2(p[1], p[0]))


def _clip_start_to_circle(element, radius: float):
    """The element with its start moved (along itself) onto the circle r = radius about the origin."""
    from ..geometry.contour import Arc, Line

    if isinstance(element, Line):
        d = element.tangent()
        p = element.start
        B, C = 2 * p @ d, p @ p - radius**2
        roots = np.roots([1.0, B, C]).real
        s = roots[np.argmin(np.abs(roots))]
        return Line(p + s * d, element.end)
    # arc: intersect its circle with the tip circle; keep the intersection nearest the start
    c, R = element.centre, element.radius
    dist = float(np.hypot(*c))
    a = (radius**2 - R**2 + dist**2) / (2 * dist)
    h = np.sqrt(max(radius**2 - a**2, 0.0))
    u = c / dist
    base = a * u
    cands = [base + h * np.array([-u[1], u[0]]), base - h * np.array([-u[1], u[0]])]
    p = min(cands, key=lambda q: np.hypot(*(q - element.start)))
    new_start = _math_angle(p - c)
    end = element.end_angle
    sweep = end - new_start
    sign = np.sign(element.sweep)
    sweep = (sweep - sign * 2 * np.pi) if sign * sweep > 2 * np.pi else sweep
    sweep = (sweep + sign * 2 * np.pi) if sign * sweep < 0 else sweep
    return Arc(c, R, new_start, sweep)


def cs_chain(flank, *, tip_radius_mm: float, root_radius_mm: float, cs_teeth: int):
    """(space, outline): :func:`cs_space` and the closed CS inner outline it makes
    (:func:`cs_outline`), as true arcs and lines, from a fitted right flank."""
    space = cs_space(flank, tip_radius_mm=tip_radius_mm, root_radius_mm=root_radius_mm)
    return space, cs_outline(space, tip_radius_mm=tip_radius_mm, cs_teeth=cs_teeth)


def cs_space(flank, *, tip_radius_mm: float, root_radius_mm: float, swept=None, swept_tol_mm: float = 0.0):
    """One CS tooth space as true arcs and lines, from a fitted right flank.

    ``flank`` is a contour.Chain in the CS frame running up the right flank of space 0
    (from near the tip circle toward the root). Its start is moved exactly onto the tip
    circle; from its end a line continues along its end tangent to the root circle; the
    left flank is the mirror image; the root is an arc of the root circle; neighbouring
    spaces are joined by arcs of the tip circle. Where the two end tangents meet on the
    space's axis before the root circle (a narrow space), one arc centred on the axis and
    tangent to both flank ends closes the space instead, short of the root circle. Given
    ``swept`` (the FS tooth family's swept-region depth, mm > 0 inside:
    :func:`profilegen.profile.arcfit.swept_depth_function`), where that arc would enter the swept
    region by more than ``swept_tol_mm`` (the FS tip land's corners pass under it), each flank
    first runs on along its end tangent by the shortest line that keeps the arc out. Returns the
    chain of one space (left tip point → right tip point); its corners are sharp
    (:mod:`profilegen.profile.rootfillet` rounds them).
    """
    from ..geometry.contour import Arc, Chain, Line

    els = list(flank.elements)
    els[0] = _clip_start_to_circle(els[0], tip_radius_mm)
    end = els[-1].end
    direction = els[-1].tangent(at_end=True)
    if end[0] <= 0.0:
        raise EnvelopeError(f"gearform: the fitted flank ends at x = {end[0]:.6f} mm, on or past the space's axis: "
                            "the two flanks cross — check the tooth (thickness, tip) and circular_spline.root_clearance_mm")
    hit = _tangent_to_circle(end, direction, root_radius_mm)
    if hit[0] > 0.0:  # the end tangent reaches the root circle before the axis: line + root arc
        if np.hypot(*(hit - end)) > 1e-12:
            els.append(Line(end, hit))
        right = Chain(tuple(els))
        left_up = right.transformed(_MIRROR)  # mirror keeps the travel direction: tip circle → root
        a_left, a_right = _math_angle(hit * [-1, 1]), _math_angle(hit)  # math angles, left > right
        root = Arc(np.zeros(2), root_radius_mm, a_left, a_right - a_left)  # clockwise across the top
    else:
        # The end tangents of the two flanks meet on the axis inside the root circle (a narrow
        # space: a thin FS tooth). One arc centred on the axis, tangent to both flank ends,
        # closes the space G1; its apex stays short of the root circle (the caller reports it).
        d = direction / np.hypot(*direction)
        if d[1] <= 0.0:
            raise EnvelopeError("gearform: the fitted flank turns back toward the tip circle at its end; the space "
                                "cannot be closed — check the tooth and circular_spline.root_clearance_mm")
        run = 0.0 if swept is None else _closure_run(end, d, swept, swept_tol_mm)
        if run > 0.0:
            els.append(Line(end, end + run * d))
            end = end + run * d
        root = _closure_arc(end, d)
        right = Chain(tuple(els))
        left_up = right.transformed(_MIRROR)
    return Chain(tuple(left_up.elements) + (root,) + tuple(right.reversed().elements))


def _closure_arc(end: np.ndarray, d: np.ndarray):
    """The arc centred on the space's axis, tangent to the right flank's end (``end``, unit end
    tangent ``d``) and to its mirror image, clockwise across the top."""
    from ..geometry.contour import Arc

    radius = end[0] / d[1]  # centre (0, c_y) on the flank end's normal
    centre = np.array([0.0, end[1] + radius * d[0]])
    a_right = _math_angle(end - centre)
    return Arc(centre, radius, np.pi - a_right, 2 * a_right - np.pi)


#: points sampled on a narrow space's closing arc for the swept-region check
_CLOSURE_POINTS = 64


def _closure_run(end: np.ndarray, d: np.ndarray, swept, tol: float) -> float:
    """The run-on s ≥ 0 along the flank's end tangent before the closing arc
    (:func:`_closure_arc`): 0 when the arc at the flank's end stays within ``tol`` of the swept
    region (the verdict's tolerance), else the shortest after which the arc and the run-on line
    are out of it (depth ≤ 0, no part of the tolerance spent), by bisection to 1 nm — a longer
    run lifts the arc's apex away from the FS tip land's corners that pass under it. 0 too when
    no run-on up to the tangents' meeting on the axis clears it: the clearance map then reports
    the interference."""
    def on_arc(arc, u):
        a = arc.start_angle + u * arc.sweep
        return arc.centre + arc.radius * np.column_stack([np.cos(a), np.sin(a)])

    def depth(s: float) -> float:  # the deepest point: the arc's samples, then 32 more about the worst
        checkpoint()  # an engine's design stops here when superseded (a swept-depth call)
        arc = _closure_arc(end + s * d, d)
        u = np.linspace(0.0, 1.0, _CLOSURE_POINTS)
        coarse = swept(on_arc(arc, u))
        k = int(np.argmax(coarse))
        fine = swept(on_arc(arc, np.linspace(u[max(k - 1, 0)], u[min(k + 1, len(u) - 1)], 32)))
        deepest = max(float(np.max(coarse)), float(np.max(fine)))
        if s > 0.0:  # and the run-on line
            deepest = max(deepest, float(np.max(swept(end + np.outer(np.linspace(0.0, s, 16), d)))))
        return deepest

    if depth(0.0) <= tol:
        return 0.0
    if d[0] >= 0.0:  # the tangent does not run toward the axis: a run-on only widens the arc
        return 0.0
    hi = 0.999 * end[0] / -d[0]  # just short of the tangents' meeting on the axis (radius → 0)
    if depth(hi) > 0.0:
        return 0.0
    lo = 0.0
    while hi - lo > 1e-6:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if depth(mid) <= 0.0 else (mid, hi)
    return hi


def cs_local_chain(space, outline):
    """The chain of spaces −1, 0 and 1 (with their tip lands) of a closed CS ``outline`` made by
    :func:`cs_outline` from ``space``: what a check around space 0 measures against."""
    from ..geometry.contour import Chain

    n_unit = len(space.elements) + 1  # a space and the tip-land arc after it
    return Chain(tuple(outline.elements[-n_unit:] + outline.elements[: 2 * n_unit]))


def cs_outline(space, *, tip_radius_mm: float, cs_teeth: int):
    """The closed CS inner outline: ``space`` (a contour.Chain from the tip circle to the tip
    circle, space 0) repeated every 2π/z2, neighbours joined by arcs of the tip circle."""
    from ..geometry.contour import Arc, Chain, Line

    pitch = 2 * np.pi / cs_teeth
    # our CS polar angle runs clockwise; space k+1 is space k turned by −pitch in math angles
    turn = -np.arange(cs_teeth + 1) * pitch
    cos, sin = np.cos(turn), np.sin(turn)

    def turned(p):  # the point p turned to every space (cs_teeth + 1, 2), read-only rows
        out = np.empty((cs_teeth + 1, 2))
        out[:, 0] = cos * p[0] - sin * p[1]
        out[:, 1] = sin * p[0] + cos * p[1]
        out.setflags(write=False)
        return out

    # every element's points turned to every space at once; the copies are built without the
    # constructors' checks (each is a turned copy of a checked element: 2 800 of them on the default
    # set, 15.6 → 2.3 ms)
    columns: list[tuple] = []
    for e in space.elements:
        if type(e) is Line:
            columns.append((True, turned(e.start), turned(e.end)))
        elif type(e) is Arc:
            v = turned(e.start - e.centre)
            columns.append((False, turned(e.centre), e.radius, np.arctan2(v[:, 1], v[:, 0]).tolist(), e.sweep))
        else:
            raise TypeError(f"cs_outline: a space of lines and arcs, not {type(e).__name__}")
    nxt = turned(space.start)
    centre = np.zeros(2)
    centre.setflags(write=False)
    parts: list = []
    for k in range(cs_teeth):
        els: list = []
        for col in columns:
            if col[0]:  # a line
                els.append(Line.trusted(col[1][k], col[2][k]))
            else:
                els.append(Arc.trusted(col[1][k], col[2], col[3][k], col[4]))
        a0, a1 = _math_angle(els[-1].end), _math_angle(nxt[k + 1])
        sweep = (a1 - a0 + np.pi) % (2 * np.pi) - np.pi  # the short way, clockwise (negative)
        parts += els + [Arc.trusted(centre, float(tip_radius_mm), a0, sweep)]
    return Chain(tuple(parts))
