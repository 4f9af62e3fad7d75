"""Structured isoparametric mesh of the TOOTHED flexspline rim, quarter model (``verify`` scene).

No mesh generator: a mapped mesh of 9-node quadrilaterals (``MeshQuad2``), one structured
grid of ``(2 N_s + 1) × (2 N_j + 1)`` nodes over the quarter 0 ≤ θ ≤ π/2 (θ from the
major axis +y toward +x, a point is (r sin θ, r cos θ), as in :mod:`profilegen.rim.ring`).

Blocks
------
* Block 1, the inner half of the rim: polar tensor mesh from the bore r_bore = r_m − δ/2 to
  the neutral circle r_m (``rim_layers`` layers, uniform in r and in θ). The node lines at
  r_bore (the contact nodes) and r_m (where ω, υ are read) carry the exact radius.
* Block 2, from the neutral circle to the toothed surface (``tooth_layers`` layers): per
  tooth pitch a transfinite (Coons) map in the pitch's polar coordinates (ψ, ρ) about the
  flexspline centre. Its bottom edge is the r_m arc (uniform in θ, block 1's nodes), its
  sides the radial mid-space lines, its top edge the surface of one pitch: root land (root
  circle r_f = r_m + y_f), the short radial step from the root circle up to the root point
  on the line y = y_f (x²/2r ≈ 4 µm, see :meth:`ToothProfile.outline`), the flank segments,
  the straight top land and the mirror image. With straight radial sides the Coons map is
  the ruled blend ``(ψ, ρ) = (1 − η) bottom(ξ) + η top(ξ)``.

Every node — vertex, mid-edge and centre — is the image of its structured-grid position,
so the quadratic nodes of the surface lie on the exact curves (flank arcs, lines, involute,
spline, circles): the mesh is isoparametric, not straight-sided.

The top edge of one half pitch (tooth axis → mid-space) is split into columns of
elements: top land, each flank segment (uniform in arc length inside a segment, nodes on
every segment join), one column for the radial step, root land (uniform in angle). The
columns are shared out greedily so that the longest element edge is as short as possible;
the root land gets at least enough columns that the radial lines under the step lean
toward the mid-space (otherwise the step's element would invert).

Tooth pattern: a tooth is centred on θ = 0 (the tooth frame's axis). At θ = π/2 there is a
tooth centre when z1/4 is whole and a space centre when z1 ≡ 2 (mod 4); the quarter holds
z1/4 pitches with half pitches at the cuts, and is symmetric about both cuts. Odd z1 (no
symmetry about the minor axis) and U ≠ 2 are rejected.

Default set (z1 = 200, DCTA tooth, ``rim_layers=2, tooth_layers=4, per_pitch=16``):
50 pitches, N_s = 800 circumferential × 6 radial = 4800 elements, 1601 × 13 = 20813 nodes,
41626 dof (vector field); 1601 nodes on each of the bore and the neutral line (and on the
surface). Columns per half pitch (``ToothedRimMesh.columns``): top land 1, tip arc 1,
line 1, root arc 2, step 1, root land 2. The mesh is built in ~0.03 s; its area is within
3e-5 of the exact region (the tip arc has one element; per_pitch = 24: 1.5e-6, 48: 1e-8).

Element Jacobians are checked — positive at the points of a Gauss rule (default intorder
4, that of ``solve_ring``) and at the 9 nodes of every element (a quadratic element can
fold over along an edge while det J > 0 at all Gauss points) — and a non-positive one
raises :class:`InvertedElementError` naming the element and where it is. The elements are
ordered counter-clockwise (det J > 0; ``ring._mesh``'s are clockwise, which scikit-fem's
|det J| does not mind). The smallest per-element min/max det J of the default set is
≈ 0.03: the element under the 4 µm root step is a wedge.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, replace
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from .. import checks
from .ring import RingError
from ..results import readonly as _readonly

if TYPE_CHECKING:
    from collections.abc import Callable

    from skfem import MeshQuad2

    #: a piece of a pitch's surface: (name, length mm, curve u ↦ (ψ, r) on u ∈ [0, 1])
    _Piece = tuple[str, float, Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]]

__all__ = ["InvertedElementError", "RingSectorMesh", "ToothedMeshError", "ToothedRimMesh", "fs_pitch_pieces", "pitch_surface",
           "ring_sector_mesh", "toothed_half_ring_mesh", "toothed_half_ring_race_mesh",
           "toothed_quarter_mesh"]

log = logging.getLogger(__name__)


class ToothedMeshError(RingError):
    """Bad input to the toothed-rim mesher; the message names the parameter, value, unit and range."""


class InvertedElementError(ToothedMeshError):
    """An element of the mapped mesh has a non-positive Jacobian (the mesh parameters do not
    fit the tooth); the message names the element, where it is, and what to change."""



_whole = partial(checks.whole, error=ToothedMeshError)


class _MappedMesh:
    """What both mesh records share: they unpack like ``ring._mesh``'s (mesh, θ, r) and count
    their elements, nodes and degrees of freedom (2 per node, a 2D vector field)."""

    __slots__ = ()
    # the subclasses' fields (annotations only: no class attributes, no slots here)
    mesh: MeshQuad2
    th: np.ndarray
    r: np.ndarray

    def __iter__(self):
        return iter((self.mesh, self.th, self.r))

    @property
    def elements(self) -> int:
        return int(self.mesh.t.shape[1])

    @property
    def nodes(self) -> int:
        return int(self.th.size)

    @property
    def dof(self) -> int:
        return 2 * self.nodes


@dataclass(frozen=True, slots=True, eq=False)
class ToothedRimMesh(_MappedMesh):
    """The mapped mesh of the toothed quarter rim and where its node lines are.

    Unpacks like ``ring._mesh``'s return: ``mesh, th, r = toothed_quarter_mesh(...)``
    (``tuple(result)`` gives the plain tuple). ``th``, ``r``: undeformed polar coordinates
    of every dof location (θ from +y toward +x). Node index arrays (into ``th``/``r``/the
    mesh's dof locations): ``bore_nodes``, ``neutral_nodes``, ``surface_nodes`` sorted by θ;
    ``major_cut_nodes`` (θ = 0) and ``minor_cut_nodes`` (θ = π/2) sorted by r.
    ``columns``: (piece, number of element columns) along one half pitch, tooth axis →
    mid-space. ``min_jacobian``: the smallest det J at the checked points (mm²);
    ``jacobian_ratio``: the smallest per-element min/max det J (1 for a parallelogram).
    """

    mesh: MeshQuad2
    th: np.ndarray
    r: np.ndarray
    bore_nodes: np.ndarray
    neutral_nodes: np.ndarray
    surface_nodes: np.ndarray
    major_cut_nodes: np.ndarray
    minor_cut_nodes: np.ndarray
    teeth: int
    per_pitch: int
    rim_layers: int
    tooth_layers: int
    columns: tuple[tuple[str, int], ...]
    bore_radius_mm: float
    neutral_radius_mm: float
    root_radius_mm: float
    min_jacobian: float
    jacobian_ratio: float
    time_s: float

    def __post_init__(self):
        for name in ("th", "r"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        for name in ("bore_nodes", "neutral_nodes", "surface_nodes", "major_cut_nodes", "minor_cut_nodes"):
            object.__setattr__(self, name, _readonly(getattr(self, name), dtype=np.int64))
        object.__setattr__(self, "columns", tuple((str(a), int(b)) for a, b in self.columns))

    @property
    def pitches(self) -> float:
        """Tooth pitches in the quarter, z1/4 (half pitches at the cuts)."""
        return self.teeth / 4.0

    def to_dict(self) -> dict:
        return {
            "model": "toothed quarter rim, structured isoparametric 9-node quadrilaterals (Coons map per pitch)",
            "teeth": self.teeth,
            "pitches": self.pitches,
            "per_pitch": self.per_pitch,
            "rim_layers": self.rim_layers,
            "tooth_layers": self.tooth_layers,
            "columns": [list(c) for c in self.columns],
            "elements": self.elements,
            "nodes": self.nodes,
            "dof": self.dof,
            "bore_radius_mm": self.bore_radius_mm,
            "neutral_radius_mm": self.neutral_radius_mm,
            "root_radius_mm": self.root_radius_mm,
            "min_jacobian": self.min_jacobian,
            "jacobian_ratio": self.jacobian_ratio,
            "time_s": self.time_s,
        }


def _pieces(tooth):
    """The top edge of one half pitch, tooth axis → mid-space, as pieces ``(name, count,
    curve)``; ``curve(u)`` (u ∈ [0, 1] along the piece) returns the tooth-frame polar
    coordinates (ψ, ρ) about the flexspline centre, ψ from +y toward +x.

    The last piece ends at ψ = ``psi_mid`` (the caller's half-pitch angle) exactly."""
    r_m = float(tooth.neutral_radius_mm)
    z1 = int(tooth.teeth)
    r_f = r_m + float(tooth.dedendum_y_mm)
    half = math.pi / z1
    tip = np.asarray(tooth.point(tooth.length_mm), dtype=float)
    root = np.asarray(tooth.point(0.0), dtype=float)
    psi_root = math.atan2(root[0], root[1] + r_m)
    rho_root = math.hypot(root[0], root[1] + r_m)

    def polar(p):
        return np.arctan2(p[..., 0], p[..., 1] + r_m), np.hypot(p[..., 0], p[..., 1] + r_m)

    def top_land(u):
        return polar(np.stack([u * tip[0], np.full_like(u, tip[1])], axis=-1))

    def flank(seg):
        t0, t1 = float(seg.t0), float(seg.t1)
        return lambda u: polar(tooth.point((1.0 - u) * t1 + u * t0))  # tip → root

    def step(u):
        return np.full_like(u, psi_root), (1.0 - u) * rho_root + u * r_f

    named = {"LineSegment": "line", "ArcSegment": "arc", "InvoluteSegment": "involute", "SplineSegment": "spline"}
    pieces = [("top land", float(tip[0]), top_land)]
    n_seg = len(tooth.segments)
    for k, seg in reversed(list(enumerate(tooth.segments))):
        kind = named.get(type(seg).__name__, "flank")
        if kind == "arc" and n_seg > 1:  # DCTA: root arc, line, tip arc
            kind = "root arc" if k == 0 else "tip arc" if k == n_seg - 1 else f"arc (segment {k})"
        pieces.append((kind, float(seg.t1 - seg.t0), flank(seg)))
    # the root land runs to ψ = psi_mid (the caller's exact half-pitch angle)
    root_land_length = r_f * (half - psi_root)
    return pieces, step, (psi_root, r_f, root_land_length), half


def _allocate(lengths: list[float], minimum: list[int], total: int) -> list[int]:
    """Columns per piece: the minima, then one at a time to the piece whose element edges
    are longest (length / count), until ``total``."""
    counts = list(minimum)
    while sum(counts) < total:
        i = max(range(len(counts)), key=lambda k: lengths[k] / counts[k])
        counts[i] += 1
    return counts


def _toothed_arguments(tooth, rim_thickness_mm, *, waves, rim_layers, tooth_layers, per_pitch, check_intorder):
    """The checked arguments of :func:`toothed_quarter_mesh`: z1, r_m, δ and the counts."""
    for name in ("teeth", "neutral_radius_mm", "dedendum_y_mm", "addendum_y_mm", "segments", "point"):
        if not hasattr(tooth, name):
            raise ToothedMeshError(f"tooth = {tooth!r}: must be a ToothProfile (has no {name!r})")
    if isinstance(waves, bool) or waves != 2:
        raise ToothedMeshError(
            f"waves = {waves!r}: the quarter model needs U = 2 (two symmetry cuts at θ = 0 and π/2)")
    z1 = int(tooth.teeth)
    if z1 % 2:
        raise ToothedMeshError(
            f"tooth.teeth (z1) = {z1}: must be even — an odd tooth count is not symmetric about the "
            "minor axis (θ = π/2), so the quarter model does not apply")
    r_m = float(tooth.neutral_radius_mm)
    try:
        delta = float(rim_thickness_mm)
    except (TypeError, ValueError) as exc:
        raise ToothedMeshError(f"rim_thickness_mm = {rim_thickness_mm!r}: must be a number (mm)") from exc
    if not (math.isfinite(delta) and 0.0 < delta < 2.0 * r_m):
        raise ToothedMeshError(f"rim_thickness_mm = {rim_thickness_mm!r} mm: must be in (0, {2.0 * r_m:g})")
    rim_layers = _whole("rim_layers", rim_layers, 1)
    tooth_layers = _whole("tooth_layers", tooth_layers, 1)
    per_pitch = _whole("per_pitch", per_pitch, 2, even=True)
    check_intorder = _whole("check_intorder", check_intorder, 1)
    return z1, r_m, delta, rim_layers, tooth_layers, per_pitch, check_intorder


def _pitch_columns(pieces, root_land_length: float, root_fraction: float, per_pitch: int):
    """The surface pieces' names, their element columns per half pitch (the radial step one)
    and the column index of their joins."""
    n_half = per_pitch // 2
    rl_min, need = _quarter_columns(len(pieces), root_fraction, n_half)
    minimum = [1] * len(pieces) + [rl_min]
    if need > n_half:
        raise ToothedMeshError(
            f"per_pitch = {per_pitch}: too few columns for this tooth; must be ≥ {2 * need} (top land, "
            f"{len(pieces) - 1} flank segment(s), the radial root step and {rl_min} root-land column(s) per "
            "half pitch)")
    counts = _allocate([p[1] for p in pieces] + [root_land_length], minimum, n_half - 1)
    names = [p[0] for p in pieces] + ["step", "root land"]
    counts_all = counts[:-1] + [1, counts[-1]]
    edges = np.concatenate([[0], np.cumsum(counts_all)]).astype(float)  # column index of piece joins
    return names, counts_all, edges


def _pitch_surface(curves: list, edges, psi_root: float, psi_mid: float, r_f: float):
    """The surface of a pitch, σ ↦ (ψ, ρ) at column coordinate σ ∈ [−n_half, n_half]: the
    ``curves`` (top land to the root step) and the root land, each over its columns."""
    def root_land(u):
        return (1.0 - u) * psi_root + u * psi_mid, np.full_like(u, r_f)

    curves = curves + [root_land]

    def top(sigma):
        """(ψ, ρ) of the surface at column coordinate σ ∈ [−n_half, n_half] of a pitch."""
        a = np.abs(sigma)
        idx = np.clip(np.searchsorted(edges, a, side="right") - 1, 0, len(curves) - 1)
        psi = np.empty_like(a)
        rho = np.empty_like(a)
        for k, curve in enumerate(curves):
            sel = idx == k
            if sel.any():
                u = (a[sel] - edges[k]) / (edges[k + 1] - edges[k])
                psi[sel], rho[sel] = curve(u)
        return np.where(sigma < 0, -psi, psi), rho

    return top


def _mapped_quarter(top, n_s: int, n_j: int, rim_layers: int, per_pitch: int, r_bore: float, r_m: float):
    """The structured grid in index space (s, j), counter-clockwise 9-node elements, mapped
    onto the quarter rim: even layers from the bore to r_m, then blended to the surface ``top``.
    Returns the mesh, the grid's points and elements, every node's s, j and θ, r."""
    from skfem import MeshQuad, MeshQuad2

    n_half = per_pitch // 2
    c = 0.5 * math.pi / n_s
    s_idx, j_idx = np.meshgrid(np.arange(n_s + 1), np.arange(n_j + 1), indexing="ij")
    p = np.vstack([s_idx.ravel(), j_idx.ravel()]).astype(float)
    node = np.arange((n_s + 1) * (n_j + 1)).reshape(n_s + 1, n_j + 1)
    t = np.vstack([node[:-1, :-1].ravel(), node[1:, :-1].ravel(), node[1:, 1:].ravel(), node[:-1, 1:].ravel()])
    quad = MeshQuad2.from_mesh(MeshQuad(p, t))
    s, j = quad.doflocs  # half-integers, exact

    th = s * c
    r = np.empty_like(s)
    inner = j <= rim_layers
    a = j[inner] / rim_layers
    r[inner] = (1.0 - a) * r_bore + a * r_m
    outer = ~inner
    eta = (j[outer] - rim_layers) / (n_j - rim_layers)
    pitch = np.floor((s[outer] + n_half) / per_pitch)
    sigma = s[outer] - pitch * per_pitch
    psi_t, rho_t = top(sigma)
    th[outer] = th[outer] + eta * (psi_t - sigma * c)
    r[outer] = (1.0 - eta) * r_m + eta * rho_t
    th[s == 0] = 0.0
    minor = s == n_s
    th[minor] = 0.5 * math.pi
    x = r * np.sin(th)
    y = r * np.cos(th)
    x[minor], y[minor] = r[minor], 0.0
    mesh = replace(quad, doflocs=np.ascontiguousarray(np.vstack([x, y])))
    return mesh, p, t, s, j, th, r


def _jacobian_check(mesh, p, t, check_intorder: int, per_pitch: int, tooth_layers: int, columns: dict):
    """The smallest det J of each element and the smallest ratio to its largest, at the
    points of the check rule and the 9 nodes; raises InvertedElementError if any is ≤ 0."""
    from skfem.mapping import MappingIsoparametric
    from skfem.quadrature import get_quadrature

    # (a quadratic element can fold over near an edge while det J > 0 at every Gauss point,
    # so its 9 nodes are checked too)
    X = np.hstack([get_quadrature(mesh.elem.refdom, check_intorder)[0], mesh.elem().doflocs.T])
    det = MappingIsoparametric(mesh, mesh.elem()).detDF(X)  # (elements, points)
    worst = np.min(det, axis=1)
    if not np.all(worst > 0.0):
        e = int(np.argmin(worst))
        centre = mesh.doflocs[:, mesh.t[:, e]].mean(axis=1)
        col = int(p[0, t[0, e]]) % per_pitch
        raise InvertedElementError(
            f"toothed_quarter_mesh: element {e} has det J = {worst[e]:.3g} mm² ≤ 0 (at a Gauss point or node) "
            f"(centre θ = {math.degrees(math.atan2(centre[0], centre[1])):.5g}°, r = {math.hypot(*centre):.6g} mm, "
            f"column {col} of the pitch, layer {int(p[1, t[0, e]])}); change per_pitch = {per_pitch} or "
            f"tooth_layers = {tooth_layers} (columns per half pitch: {columns})")
    ratio = float(np.min(worst / np.max(det, axis=1)))
    return worst, ratio


def _node_line(sel, key):
    """The nodes of ``sel`` ordered by ``key``."""
    idx = np.flatnonzero(sel)
    return idx[np.argsort(key[idx], kind="stable")]


def toothed_quarter_mesh(
    tooth,
    rim_thickness_mm: float,
    *,
    rim_layers: int = 2,
    tooth_layers: int = 4,
    per_pitch: int = 16,
    waves: int = 2,
    check_intorder: int = 4,
) -> ToothedRimMesh:
    """Mapped 9-node-quad mesh of the toothed rim quarter 0 ≤ θ ≤ π/2 (see the module doc).

    ``tooth``: a :class:`~profilegen.geometry.teeth.ToothProfile` (it carries z1, r_m and the root and
    tip lines). ``rim_thickness_mm``: δ, the bore is at r_m − δ/2. ``rim_layers`` (≥ 1)
    element layers from the bore to r_m, ``tooth_layers`` (≥ 1) from r_m to the surface,
    ``per_pitch`` (even) element columns per tooth pitch. ``waves`` must be 2 (two symmetry
    cuts). ``check_intorder``: the Gauss rule whose points (with the 9 nodes) the Jacobian is
    checked at.

    Returns a :class:`ToothedRimMesh`, which unpacks as ``(mesh, th, r)``.
    """
    start = time.perf_counter()
    z1, r_m, delta, rim_layers, tooth_layers, per_pitch, check_intorder = _toothed_arguments(
        tooth, rim_thickness_mm, waves=waves, rim_layers=rim_layers, tooth_layers=tooth_layers, per_pitch=per_pitch,
        check_intorder=check_intorder)

    r_bore = r_m - 0.5 * delta
    n_half = per_pitch // 2
    pieces, step, (psi_root, r_f, root_land_length), half_pitch = _pieces(tooth)
    names, counts_all, edges = _pitch_columns(pieces, root_land_length, psi_root / half_pitch, per_pitch)

    n_s = per_pitch * z1 // 4  # circumferential elements in the quarter
    c = 0.5 * math.pi / n_s  # angle per column at the bottom
    psi_mid = n_half * c  # = π/z1 up to round-off; the mid-space line of the bottom
    top = _pitch_surface([p[2] for p in pieces] + [step], edges, psi_root, psi_mid, r_f)

    n_j = rim_layers + tooth_layers
    mesh, p, t, s, j, th, r = _mapped_quarter(top, n_s, n_j, rim_layers, per_pitch, r_bore, r_m)
    minor = s == n_s
    worst, ratio = _jacobian_check(mesh, p, t, check_intorder, per_pitch, tooth_layers, dict(zip(names, counts_all)))
    top_j = float(n_j)
    result = ToothedRimMesh(
        mesh=mesh,
        th=th,
        r=r,
        bore_nodes=_node_line(j == 0, th),
        neutral_nodes=_node_line(j == rim_layers, th),
        surface_nodes=_node_line(j == top_j, th),
        major_cut_nodes=_node_line(s == 0, r),
        minor_cut_nodes=_node_line(minor, r),
        teeth=z1,
        per_pitch=per_pitch,
        rim_layers=rim_layers,
        tooth_layers=tooth_layers,
        columns=tuple(zip(names, counts_all)),
        bore_radius_mm=r_bore,
        neutral_radius_mm=r_m,
        root_radius_mm=r_f,
        min_jacobian=float(np.min(worst)),
        jacobian_ratio=ratio,
        time_s=time.perf_counter() - start,
    )
    log.debug("toothed rim mesh: %d elements, %d nodes, columns %s, det J ≥ %.3g, ratio %.3g, %.3g s",
              result.elements, result.nodes, result.columns, result.min_jacobian, ratio, result.time_s)
    return result


# --------------------------------------------------------------------------- half ring
#
# The quarter model above needs mirror symmetry about both axes. A loaded mesh (tooth
# forces with tangential components) is only point-symmetric — u(θ + π) = R(π) u(θ) for a
# two-wave set — so the contact compliance (:mod:`profilegen.contact.compliance`) needs
# the half ring with a periodic tie of its cuts. The functions below build it; they do not
# touch ``toothed_quarter_mesh``.


@dataclass(frozen=True, slots=True, eq=False)
class RingSectorMesh(_MappedMesh):
    """A structured mapped mesh of a ring sector made of whole pitches (9-node quads).

    ``s``, ``j``: structured-grid coordinates of every dof location (half-integers; s
    along the ring, j across it, j = 0 on the inner boundary). ``th``, ``r``: undeformed
    polar coordinates (θ from +y toward +x). ``inner_nodes``/``outer_nodes``: the node
    lines j = 0 and j = n_j sorted by s; ``start_cut_nodes``/``end_cut_nodes``: s = 0 and
    s = n_s sorted by j. ``pitch_columns``: element columns of each pitch;
    ``toothed``: which pitches carry teeth (the others are a flat ring up to ``flat_radius_mm``).
    """

    mesh: MeshQuad2
    s: np.ndarray
    j: np.ndarray
    th: np.ndarray
    r: np.ndarray
    inner_nodes: np.ndarray
    outer_nodes: np.ndarray
    start_cut_nodes: np.ndarray
    end_cut_nodes: np.ndarray
    pitch_columns: np.ndarray
    toothed: np.ndarray
    start_rad: float
    pitch_rad: float
    layers: int
    min_jacobian: float
    jacobian_ratio: float
    time_s: float

    def __post_init__(self):
        for name in ("s", "j", "th", "r"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        for name in ("inner_nodes", "outer_nodes", "start_cut_nodes", "end_cut_nodes", "pitch_columns"):
            object.__setattr__(self, name, _readonly(getattr(self, name), dtype=np.int64))
        object.__setattr__(self, "toothed", _readonly(self.toothed, dtype=bool))


    def to_dict(self) -> dict:
        return {
            "pitches": int(self.pitch_columns.size),
            "toothed_pitches": int(self.toothed.sum()),
            "columns": int(self.pitch_columns.sum()),
            "layers": self.layers,
            "elements": self.elements,
            "nodes": self.nodes,
            "dof": self.dof,
            "min_jacobian": self.min_jacobian,
            "jacobian_ratio": self.jacobian_ratio,
            "time_s": self.time_s,
        }


def _quarter_columns(n_pieces: int, f_root: float, n_half: int) -> tuple[int, int]:
    """(root-land columns, columns needed) per half pitch of :func:`toothed_quarter_mesh` with
    ``n_half`` columns: the radial lines under the step must lean toward the mid-space (the step
    column's bottom right corner at least half a column left of the root point), one column
    per flank piece and one for the step."""
    rl_min = max(1, math.floor(n_half * (1.0 - f_root) + 0.5) + 1)
    return rl_min, n_pieces + rl_min + 1


def least_per_pitch(tooth) -> int:
    """The fewest (even) columns per pitch :func:`toothed_quarter_mesh` can mesh ``tooth`` with
    (14 for the default DCTA tooth; more for a tooth of more pieces, e.g. seed 001's)."""
    pieces, _, (psi_root, _, _), half_pitch = _pieces(tooth)
    n_half = 1
    while _quarter_columns(len(pieces), psi_root / half_pitch, n_half)[1] > n_half:
        n_half += 1
    return 2 * n_half


def pitch_surface(pieces: list[_Piece], columns: int, minimum: list[int] | None = None):
    """The surface of one pitch as a function of the column coordinate.

    ``pieces``: (name, length mm, curve) in order along the pitch, ``curve(u)`` (u ∈ [0, 1])
    → polar (ψ, ρ) relative to the pitch centre. ``columns`` element columns are shared out
    so that the longest element edge is as short as possible (at least ``minimum`` per
    piece, default 1). Returns ``(top, counts)``: ``top(a)`` for a ∈ [0, columns] (the
    column coordinate, nodes at whole and half values) → (ψ, ρ) arrays.
    """
    minimum = [1] * len(pieces) if minimum is None else list(minimum)
    if sum(minimum) > columns:
        raise ToothedMeshError(
            f"columns per pitch = {columns}: too few for the {len(pieces)} pieces of the surface "
            f"({', '.join(p[0] for p in pieces)}); must be ≥ {sum(minimum)}")
    counts = _allocate([p[1] for p in pieces], minimum, columns)
    edges = np.concatenate([[0], np.cumsum(counts)]).astype(float)
    curves = [p[2] for p in pieces]

    def top(a):
        a = np.asarray(a, dtype=float)
        idx = np.clip(np.searchsorted(edges, a, side="right") - 1, 0, len(curves) - 1)
        psi = np.empty_like(a)
        rho = np.empty_like(a)
        for k, curve in enumerate(curves):
            sel = idx == k
            if sel.any():
                psi[sel], rho[sel] = curve((a[sel] - edges[k]) / (edges[k + 1] - edges[k]))
        return psi, rho

    return top, tuple(counts)


def fs_pitch_pieces(tooth) -> list[_Piece]:
    """The surface of one FS pitch, mid-space → tooth → mid-space, as pieces for
    :func:`pitch_surface` (polar about the flexspline centre, relative to the tooth axis):
    root land, radial root step, flank segments root → tip, top land, and the mirror image."""
    half_pieces, step, (psi_root, r_f, root_land_length), half = _pieces(tooth)

    def root_land(u):  # from the mid-space to the root point
        return (1.0 - u) * half + u * psi_root, np.full_like(u, r_f)

    right = [("root land", root_land_length, root_land),
             ("step", 1e-3 * root_land_length + abs(step(np.array([0.0]))[1][0] - r_f),
              lambda u: step(1.0 - u))]
    for name, length, curve in reversed(half_pieces):  # root → tip, then the top land tip → axis
        right.append((name, length, (lambda c: (lambda u: c(1.0 - u)))(curve)))
    # right half: mid-space (ψ = +half) → tooth axis (ψ = 0); the pitch runs ψ = −half → +half
    left = [(name, length, (lambda c: (lambda u: (lambda p: (-p[0], p[1]))(c(u))))(curve))
            for name, length, curve in right]
    right_rev = [(name, length, (lambda c: (lambda u: c(1.0 - u)))(curve)) for name, length, curve in reversed(right)]
    return left + right_rev


def ring_sector_mesh(
    pitch_rad: float,
    start_rad: float,
    tops: list,
    pitch_columns,
    *,
    mapped_radius_mm: float,
    polar_radius_mm: float,
    mapped_layers: int,
    polar_layers: int,
    mapped_outside: bool,
    polar_grading: float = 1.0,
    flat_radius_mm: float | None = None,
    check_intorder: int = 4,
) -> RingSectorMesh:
    """Structured mapped mesh of whole pitches ``start_rad + k·pitch_rad`` (k = 0 … len(tops) − 1).

    Across the ring two blocks: a *polar* block between the circles ``mapped_radius_mm`` and
    ``polar_radius_mm`` (``polar_layers`` layers, exact circles, geometric spacing
    ``polar_grading`` from the mapped block outward/inward) and a *mapped* block between the
    circle ``mapped_radius_mm`` and the surface (``mapped_layers`` layers, the ruled Coons
    blend of :func:`toothed_quarter_mesh`). ``mapped_outside``: the surface is outside
    (an external gear, the FS) or inside (an internal gear, the CS). ``tops[k]``: the
    surface of pitch k as returned by :func:`pitch_surface` (ψ relative to the pitch centre),
    or None for a flat ring up to ``flat_radius_mm``. ``pitch_columns[k]``: element columns
    of pitch k (a toothed pitch must use the column count its ``top`` was made for).
    """
    start = time.perf_counter()
    from skfem import MeshQuad, MeshQuad2
    from skfem.mapping import MappingIsoparametric
    from skfem.quadrature import get_quadrature

    cols = np.asarray(pitch_columns, dtype=int)
    if cols.size != len(tops) or np.any(cols < 1):
        raise ToothedMeshError(f"pitch_columns = {pitch_columns!r}: must be one whole number ≥ 1 per pitch")
    n_s = int(cols.sum())
    n_j = int(mapped_layers + polar_layers)
    edges = np.concatenate([[0], np.cumsum(cols)]).astype(float)
    s_idx, j_idx = np.meshgrid(np.arange(n_s + 1), np.arange(n_j + 1), indexing="ij")
    p = np.vstack([s_idx.ravel(), j_idx.ravel()]).astype(float)
    node = np.arange((n_s + 1) * (n_j + 1)).reshape(n_s + 1, n_j + 1)
    t = np.vstack([node[:-1, :-1].ravel(), node[1:, :-1].ravel(), node[1:, 1:].ravel(), node[:-1, 1:].ravel()])
    quad = MeshQuad2.from_mesh(MeshQuad(p, t))
    s, j = quad.doflocs

    pitch = np.clip(np.searchsorted(edges, s, side="right") - 1, 0, cols.size - 1)
    a = s - edges[pitch]  # column coordinate inside the pitch
    frac = a / cols[pitch]
    centre = start_rad + (pitch + 0.5) * pitch_rad
    theta_b = start_rad + (pitch + frac) * pitch_rad  # on the circle mapped_radius_mm
    psi_t = (frac - 0.5) * pitch_rad
    rho_t = np.full_like(s, np.nan if flat_radius_mm is None else float(flat_radius_mm))
    for k, top in enumerate(tops):
        if top is None:
            continue
        sel = pitch == k
        psi_t[sel], rho_t[sel] = top(a[sel])
    if flat_radius_mm is None and np.any(np.isnan(rho_t)):
        raise ToothedMeshError("flat_radius_mm: needed when a pitch has no teeth (tops[k] is None)")

    r_c, r_p = float(mapped_radius_mm), float(polar_radius_mm)
    if mapped_outside:
        in_polar = j <= polar_layers
        eta = np.clip((j - polar_layers) / mapped_layers, 0.0, 1.0)
        x_p = j / polar_layers  # 0 at polar_radius (inner), 1 at the mapped circle
        g_from_mapped = 1.0 - x_p
    else:
        in_polar = j >= mapped_layers
        eta = np.clip(1.0 - j / mapped_layers, 0.0, 1.0)
        g_from_mapped = (j - mapped_layers) / polar_layers
    grade = float(polar_grading)
    if grade == 1.0:
        w = g_from_mapped
    else:
        w = (grade ** (g_from_mapped * polar_layers) - 1.0) / (grade ** polar_layers - 1.0)
    th = np.where(in_polar, theta_b, theta_b + eta * (centre + psi_t - theta_b))
    r = np.where(in_polar, r_c + w * (r_p - r_c), (1.0 - eta) * r_c + eta * rho_t)
    x = r * np.sin(th)
    y = r * np.cos(th)
    mesh = replace(quad, doflocs=np.ascontiguousarray(np.vstack([x, y])))

    X = np.hstack([get_quadrature(mesh.elem.refdom, check_intorder)[0], mesh.elem().doflocs.T])
    det = MappingIsoparametric(mesh, mesh.elem()).detDF(X)
    orient = 1.0 if np.median(det) > 0 else -1.0
    worst = np.min(orient * det, axis=1)
    if not np.all(worst > 0.0):
        e = int(np.argmin(worst))
        centre_e = mesh.doflocs[:, mesh.t[:, e]].mean(axis=1)
        raise InvertedElementError(
            f"ring_sector_mesh: element {e} has det J = {worst[e]:.3g} mm² ≤ 0 (centre θ = "
            f"{math.degrees(math.atan2(centre_e[0], centre_e[1])):.5g}°, r = {math.hypot(*centre_e):.6g} mm, pitch "
            f"{int(pitch[mesh.t[0, e]])}); change the columns per pitch or the layers")
    ratio = float(np.min(worst / np.max(orient * det, axis=1)))

    def line(sel, key):
        idx = np.flatnonzero(sel)
        return idx[np.argsort(key[idx], kind="stable")]

    return RingSectorMesh(
        mesh=mesh, s=s, j=j, th=th, r=r,
        inner_nodes=line(j == 0, s), outer_nodes=line(j == n_j, s),
        start_cut_nodes=line(s == 0, j), end_cut_nodes=line(s == n_s, j),
        pitch_columns=cols, toothed=np.array([top is not None for top in tops]),
        start_rad=float(start_rad), pitch_rad=float(pitch_rad), layers=n_j,
        min_jacobian=float(np.min(worst)), jacobian_ratio=ratio, time_s=time.perf_counter() - start,
    )


def toothed_half_ring_mesh(
    tooth,
    rim_thickness_mm: float,
    *,
    toothed_pitches=None,
    rim_layers: int = 2,
    tooth_layers: int = 4,
    per_pitch: int = 16,
    flat_per_pitch: int = 2,
    check_intorder: int = 4,
    pitches: int | None = None,
) -> RingSectorMesh:
    """Mapped 9-node-quad mesh of the flexspline rim's half ring −π/z1 ≤ θ ≤ π − π/z1.

    The cuts are mid-space lines (they map onto each other under the rotation by π, so the
    point-symmetric tie u(θ + π) = −u(θ) can join them); tooth k (0 ≤ k < z1/2) is centred
    at θ = 2πk/z1, as in :func:`toothed_quarter_mesh` (θ from +y toward +x). The inner
    block (bore r_m − δ/2 → neutral circle r_m, ``rim_layers`` layers) is polar; the outer
    block (``tooth_layers`` layers) is the per-pitch Coons map up to the tooth surface.
    ``toothed_pitches``: indices k of the pitches that carry a tooth (default: all);
    the others are a flat ring up to the root circle r_f with ``flat_per_pitch`` columns
    (a coarse rim where no tooth is loaded: it omits the teeth's small share of the rim's
    bending stiffness). ``per_pitch`` columns in a toothed pitch. z1 must be even.
    ``pitches``: mesh only the first ``pitches`` pitches (k = 0 … pitches − 1; default all
    z1/2): one pitch is the substructure :mod:`profilegen.contact.compliance` condenses.
    """
    for name in ("teeth", "neutral_radius_mm", "dedendum_y_mm", "addendum_y_mm", "segments", "point"):
        if not hasattr(tooth, name):
            raise ToothedMeshError(f"tooth = {tooth!r}: must be a ToothProfile (has no {name!r})")
    z1 = int(tooth.teeth)
    if z1 % 2:
        raise ToothedMeshError(f"tooth.teeth (z1) = {z1}: must be even for the point-symmetric half ring")
    r_m = float(tooth.neutral_radius_mm)
    try:
        delta = float(rim_thickness_mm)
    except (TypeError, ValueError) as exc:
        raise ToothedMeshError(f"rim_thickness_mm = {rim_thickness_mm!r}: must be a number (mm)") from exc
    if not (math.isfinite(delta) and 0.0 < delta < 2.0 * r_m):
        raise ToothedMeshError(f"rim_thickness_mm = {rim_thickness_mm!r} mm: must be in (0, {2.0 * r_m:g})")
    rim_layers = _whole("rim_layers", rim_layers, 1)
    tooth_layers = _whole("tooth_layers", tooth_layers, 1)
    per_pitch = _whole("per_pitch", per_pitch, 2, even=True)
    flat_per_pitch = _whole("flat_per_pitch", flat_per_pitch, 1)
    n_p = z1 // 2
    if toothed_pitches is None:
        toothed = np.ones(n_p, bool)
    else:
        idx = np.asarray(toothed_pitches, dtype=int).ravel()
        if idx.size and (idx.min() < 0 or idx.max() >= n_p):
            raise ToothedMeshError(f"toothed_pitches: must be in [0, {n_p}), got {idx.min()} … {idx.max()}")
        toothed = np.zeros(n_p, bool)
        toothed[idx] = True
    if pitches is not None:
        toothed = toothed[:_whole("pitches", pitches, 1)]
        if toothed.size < int(pitches):
            raise ToothedMeshError(f"pitches = {pitches!r}: must be at most z1/2 = {n_p}")
    pieces = fs_pitch_pieces(tooth)
    half_pitch = math.pi / z1
    psi_root = _pieces(tooth)[2][0]
    # the root land must reach far enough toward the mid-space (see toothed_quarter_mesh)
    def least(columns):
        rl_min = max(1, math.floor(columns // 2 * (1.0 - psi_root / half_pitch) + 0.5) + 1)
        return [rl_min] + [1] * (len(pieces) - 2) + [rl_min]

    asked = per_pitch
    while sum(least(per_pitch)) > per_pitch:  # a tooth of many pieces (steps, a point list) needs more columns
        per_pitch += 2
    if per_pitch != asked:
        log.info("toothed_half_ring_mesh: %d columns per pitch for the %d pieces of the tooth (asked %d)",
                    per_pitch, len(pieces), asked)
    minimum = least(per_pitch)
    top, _ = pitch_surface(pieces, per_pitch, minimum)
    tops = [top if k else None for k in toothed]
    cols = np.where(toothed, per_pitch, flat_per_pitch)
    r_f = r_m + float(tooth.dedendum_y_mm)
    return ring_sector_mesh(
        2.0 * half_pitch, -half_pitch, tops, cols, mapped_radius_mm=r_m, polar_radius_mm=r_m - 0.5 * delta,
        mapped_layers=tooth_layers, polar_layers=rim_layers, mapped_outside=True, flat_radius_mm=r_f,
        check_intorder=check_intorder)


def toothed_half_ring_race_mesh(
    tooth,
    rim_thickness_mm: float,
    race_thickness_mm: float,
    *,
    race_layers: int = 2,
    toothed_pitches=None,
    rim_layers: int = 2,
    tooth_layers: int = 4,
    per_pitch: int = 16,
    flat_per_pitch: int = 2,
    check_intorder: int = 4,
    pitches: int | None = None,
) -> tuple[RingSectorMesh, np.ndarray]:
    """:func:`toothed_half_ring_mesh` with a flat ring (the wave-generator bearing's outer
    race, thickness ``race_thickness_mm`` > 0, ``race_layers`` layers) added inside the bore,
    in the same structured mesh: the race and the rim share the bore's node row (a bonded
    interface). Returns ``(ring, bore_nodes)``: ``ring.inner_nodes`` is the race's inner
    surface (radius r_m − δ/2 − t), ``bore_nodes`` the FS bore row (j = ``race_layers``,
    sorted by s). The rim's polar block keeps ``rim_layers`` equal layers, the race
    ``race_layers`` equal layers (both linear in r, as in :func:`toothed_half_ring_mesh`).
    ``pitches``: only the first pitches, as in :func:`toothed_half_ring_mesh`."""
    from skfem.mapping import MappingIsoparametric
    from skfem.quadrature import get_quadrature

    r_m = float(getattr(tooth, "neutral_radius_mm", float("nan")))
    try:
        delta, t_race = float(rim_thickness_mm), float(race_thickness_mm)
    except (TypeError, ValueError) as exc:
        raise ToothedMeshError(f"race_thickness_mm = {race_thickness_mm!r}: must be a number (mm)") from exc
    race_layers = _whole("race_layers", race_layers, 1)
    rim_layers = _whole("rim_layers", rim_layers, 1)
    r_bore = r_m - 0.5 * delta
    if not (math.isfinite(t_race) and 0.0 < t_race < r_bore):
        raise ToothedMeshError(f"race_thickness_mm = {race_thickness_mm!r} mm: must be in (0, {r_bore:g}) (the FS bore "
                               "radius)")
    # one polar block from the race's inner radius to the neutral circle, then re-spaced
    ring = toothed_half_ring_mesh(tooth, delta + 2.0 * t_race, toothed_pitches=toothed_pitches,
                                  rim_layers=race_layers + rim_layers, tooth_layers=tooth_layers, per_pitch=per_pitch,
                                  flat_per_pitch=flat_per_pitch, check_intorder=check_intorder, pitches=pitches)
    j = np.asarray(ring.j)
    r_in = r_bore - t_race
    in_race = j <= race_layers
    in_rim = (j > race_layers) & (j <= race_layers + rim_layers)
    r = np.array(ring.r)
    r[in_race] = r_in + (j[in_race] / race_layers) * t_race
    r[in_rim] = r_bore + ((j[in_rim] - race_layers) / rim_layers) * (r_m - r_bore)
    th = np.asarray(ring.th)
    mesh = replace(ring.mesh, doflocs=np.ascontiguousarray(np.vstack([r * np.sin(th), r * np.cos(th)])))
    X = np.hstack([get_quadrature(mesh.elem.refdom, check_intorder)[0], mesh.elem().doflocs.T])
    det = MappingIsoparametric(mesh, mesh.elem()).detDF(X)
    orient = 1.0 if np.median(det) > 0 else -1.0
    worst = np.min(orient * det, axis=1)
    if not np.all(worst > 0.0):
        e = int(np.argmin(worst))
        raise InvertedElementError(f"toothed_half_ring_race_mesh: element {e} has det J = {worst[e]:.3g} mm² ≤ 0; "
                                   "change the race or rim layers")
    ratio = float(np.min(worst / np.max(orient * det, axis=1)))
    bore = np.flatnonzero(j == race_layers)
    bore = bore[np.argsort(np.asarray(ring.s)[bore], kind="stable")]
    out = replace(ring, mesh=mesh, r=r, min_jacobian=float(np.min(worst)), jacobian_ratio=ratio)
    return out, bore
