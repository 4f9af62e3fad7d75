"""Influence coefficients (compliance matrix) of the loaded tooth contact.

``ContactCompliance.build(inputs, fs_points, fs_normals, fs_tooth_index, cs_points, cs_normals)``
→ S (mm/N): S_kj = n_k·u_FS,k + n'_k·u_CS,k for a unit contact force at point j, the two bodies
loaded equally and oppositely along the common normal n_j (the FS pushed along −n_j, the CS
along +n_j; n points out of the FS tooth, as :mod:`profilegen.contact.points` gives it).

The model, in short (small displacements about the undeformed bodies, plane stress, per mm of
face: S = S_2D / b): the FS as a toothed half ring with the point-symmetric tie
u(θ + π) = −u(θ), on the wave-generator bearing's outer race (sliding on the bore, or bonded),
on radial ball supports (the balls within the wrap, or every ball of the zone one-sided at its
no-load gap, ``ball_supports="all"``); the cup's torque reaction a uniform traction on the
bore; the CS a toothed sector meshed from the fitted outline, fixed outside. One pitch of each
body is meshed and condensed onto its cuts (``ComplianceMesh(substructure=True)``, the
default) and kept in a cache between builds (:func:`clear_cache`).

Entry points:

* :meth:`ContactCompliance.build` → :class:`ContactCompliance` (``inputs`` a
  :class:`~profilegen.contact.inputs.ContactInput`; ``mesh`` a :class:`ComplianceMesh` or a
  mapping of its fields); then :meth:`~ContactCompliance.settle_balls` (drop the balls that
  pull), :meth:`~ContactCompliance.with_balls`, :meth:`~ContactCompliance.solve_unilateral`
  (teeth and balls in one complementarity problem);
* :func:`no_load_ball_gap_mm` (each ball's gap before load), :func:`settle_step` (the
  ball-settling rule), :func:`default_race_thickness_mm`, :data:`DEFAULT_BALL_COUNT`.

Errors: :class:`ComplianceError` (a ``ValueError``) naming the argument — points not (n, 2)
and finite, normals not unit, CS normals not opposite to the FS ones within 0.1 rad, tooth
indices not whole, an option out of range, a gear set with other than two waves, a contact
point off the meshed surface by more than ``on_surface_tol_mm``;
:class:`~profilegen.errors.ConvergenceError` when a stiffness is not positive definite, S is
not (two points coincide), or the ball set or the Hertz springs do not settle.

The model in full, its mesh study and its speed: docs/theory/contact.md, "The influence
coefficients".
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from functools import partial

import numpy as np
import scipy.sparse as sp

from .. import checks
from ..blas import one_blas_thread
from ..errors import ConvergenceError, ProfilegenError
from ..results import readonly as _readonly
from ..stagecache import checkpoint
from ..geometry.wgbearing import DEFAULT_BALL_COUNT, default_race_thickness_mm  # noqa: F401 (re-exported)
from .cs_ring import CSRing, CSRingError, contact_ring_compliance
from .inputs import ContactInput
from .springs import ball_totals, spring_block
from ..lcp import lemke_lcp

__all__ = ["ComplianceError", "ComplianceMesh", "ContactCompliance", "DEFAULT_BALL_COUNT", "clear_cache",
           "default_race_thickness_mm", "no_load_ball_gap_mm", "settle_step"]

log = logging.getLogger(__name__)



class ComplianceError(ProfilegenError, ValueError):
    """Bad input to the compliance model; the message names the parameter, value, unit and range."""



def _points(name: str, value, n: int | None = None) -> np.ndarray:
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ComplianceError(f"{name}: must be an (n, 2) array of numbers (mm)") from exc
    if a.ndim != 2 or a.shape[1] != 2 or a.shape[0] < 1:
        raise ComplianceError(f"{name}: must have shape (n, 2) with n ≥ 1, got {a.shape}")
    if n is not None and a.shape[0] != n:
        raise ComplianceError(f"{name}: has {a.shape[0]} rows, must have one per contact point ({n})")
    if not np.all(np.isfinite(a)):
        k = int(np.flatnonzero(~np.all(np.isfinite(a), axis=1))[0])
        raise ComplianceError(f"{name}: row {k} is not finite ({a[k].tolist()})")
    return a


def _unit(name: str, value, n: int) -> np.ndarray:
    a = _points(name, value, n)
    norm = np.linalg.norm(a, axis=1)
    bad = np.flatnonzero(np.abs(norm - 1.0) > 1e-6)
    if bad.size:
        raise ComplianceError(f"{name}: row {int(bad[0])} has length {norm[bad[0]]:.9g}, must be a unit vector (±1e-6)")
    return a / norm[:, None]


_positive = partial(checks.positive, error=ComplianceError)
_whole = partial(checks.whole, error=ComplianceError)


def _half_ring_tie(ring, n_nodes: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The point-symmetric tie u(θ + π) = −u(θ) of a half ring: every node's index among the
    kept nodes (the end cut's nodes are the start cut's), the sign of its Cartesian dofs
    there (−1 on the end cut) and the mask of kept nodes."""
    end, first = ring.end_cut_nodes, ring.start_cut_nodes
    keep = np.ones(n_nodes, bool)
    keep[end] = False
    node_red = -np.ones(n_nodes, dtype=int)
    node_red[keep] = np.arange(int(keep.sum()))
    node_red[end] = node_red[first]
    sign = np.ones(n_nodes)
    sign[end] = -1.0
    return node_red, sign, keep


# --------------------------------------------------------------------------- linear algebra


#: the condensed substructures reused across calls (see :func:`_cached`): key → (owners, value)
_CACHE: dict = {}
#: entries kept (a transmission-error run uses one FS and one CS entry; a sweep's designs each their own)
_CACHE_SIZE = 8


def clear_cache() -> None:
    """Forget the condensed pitches :meth:`ContactCompliance.build` keeps between calls."""
    _CACHE.clear()


def _cached(key: tuple, owners: tuple, make):
    """``make()`` once per ``key``: the meshed and condensed pitch of a body (and, attached to
    it, its cut system's factorisation) depends only on the body's geometry, material and
    mesh parameters, never on where the contact points or the balls sit, so the positions
    of a transmission-error run (``shift_rad``) and the calls of one design share it. ``key``
    holds the owners' ids (the gear set, the FS tooth, the CS space: frozen values) and every
    number the mesh depends on; the entry keeps ``owners`` alive, so an id cannot be reused
    while its entry lives, and is only taken when the owners are those same objects. The
    same operations on the same arrays: the results are bit for bit those of a fresh build."""
    hit = _CACHE.get(key)
    if hit is not None and all(a is b for a, b in zip(hit[0], owners)):
        _CACHE[key] = _CACHE.pop(key)  # most recently used last
        return hit[1]
    value = make()
    _CACHE[key] = (owners, value)
    while len(_CACHE) > _CACHE_SIZE:
        _CACHE.pop(next(iter(_CACHE)))
    return value


class _BandedFlex:
    """Cholesky factor of a symmetric positive definite band matrix (given in the order
    ``order``) for the flexibility Yᵀ K⁻¹ Y = WᵀW, W = L⁻¹ Y.

    Blocks of ``block`` ≥ bandwidth consecutive rows make the band matrix block
    tridiagonal; its Cholesky factor is then block bidiagonal, computed and applied with
    dense BLAS 3 blocks (LAPACK's banded ``pbtrf``/``pbtrs`` are several times slower
    here, and solve one right-hand side at a time). Only the band × band corner of a
    sub-diagonal block couples (the first ``band`` rows of a block to the last ``band``
    columns of the one before), and so is only that corner of L's sub-diagonal block: the
    factorisation and the substitution work on the corner alone. The default block is
    √2 × the band (at least 64 rows), which minimises the substitution's flops (the
    corner product 2b²m per block against the triangular solve's block·m per row). The
    forward substitution starts at the block of the first nonzero row of Y: rows before
    it stay zero in W (the callers order the dofs so that the loads come last)."""

    def __init__(self, matrix, order, where: str, block: int | None = None):
        from scipy.linalg import LinAlgError, cholesky, solve_triangular
        from scipy.linalg.blas import dsyrk

        self.perm = np.asarray(order)
        self.n = n = matrix.shape[0]
        # the lower triangle in the order ``order``: the entries' indices renamed (no fancy indexing)
        coo = sp.coo_matrix(matrix)
        where_in = np.empty(n, dtype=np.int64)
        where_in[self.perm] = np.arange(n)
        r, col = where_in[coo.row], where_in[coo.col]
        self.band = band = int(np.max(np.abs(r - col), initial=0))
        if not np.all(np.isfinite(coo.data)):
            raise ConvergenceError(f"{where}: the stiffness matrix has entries that are not finite")
        low = r >= col
        lower = sp.csr_matrix((coo.data[low], (r[low], col[low])), shape=(n, n))
        lower.sum_duplicates()
        nb = max(64 if block is None else int(block), int(math.ceil(math.sqrt(2.0) * band)) if block is None else 0,
                 band, 1)
        self.corner = c = max(band, 1)  # rows of a block that couple to the block before
        self.starts = list(range(0, n, nb))
        self.diag: list[np.ndarray] = []  # L_kk
        self.sub: list[np.ndarray | None] = []  # the corner of L_k,k−1: rows i0:i0+c, columns i0−c:i0
        previous = np.empty((0, 0))  # L_k−1: read from the second block on
        for k, i0 in enumerate(self.starts):
            checkpoint()  # an engine's design stops here when superseded (a block: ~0.1 ms)
            i1 = min(n, i0 + nb)
            p0 = i0 - c if k else i0
            # rows i0:i1, columns p0:i1 of the lower triangle, dense (a scatter from the CSR arrays)
            lo, hi = lower.indptr[i0], lower.indptr[i1]
            rows = np.zeros((i1 - i0, i1 - p0))
            rows[np.repeat(np.arange(i1 - i0), np.diff(lower.indptr[i0:i1 + 1])), lower.indices[lo:hi] - p0] = \
                lower.data[lo:hi]
            a_kk = rows[:, i0 - p0:]  # its lower triangle: all that LAPACK's potrf (lower) and syrk read
            if k:
                ch = min(c, i1 - i0)
                # L_k,k−1 = A_k,k−1 L_k−1⁻ᵀ: A's corner against the trailing c × c triangle of L_k−1
                sub = solve_triangular(previous[-c:, -c:], rows[:ch, :c].T, lower=True, check_finite=False).T
                # a_kk[:ch, :ch] −= sub subᵀ (syrk, the lower triangle: cholesky reads no other)
                a_kk[:ch, :ch] = dsyrk(-1.0, sub, beta=1.0, c=a_kk[:ch, :ch], lower=1)
            else:
                sub = None
            try:
                previous = cholesky(a_kk, lower=True, check_finite=False)
            except LinAlgError as exc:
                raise ConvergenceError(f"{where}: the stiffness matrix is not positive definite (block at row {i0}); "
                                       "a rigid-body mode is not removed") from exc
            if not np.all(np.isfinite(np.diagonal(previous))):
                raise ConvergenceError(f"{where}: the stiffness matrix is not positive definite (block at row {i0}); "
                                       "a rigid-body mode is not removed")
            self.diag.append(previous)
            self.sub.append(sub)

    def _solve_block(self, k: int, b: np.ndarray, previous: np.ndarray | None) -> np.ndarray:
        """W_k = L_kk⁻¹ (Y_k − L_k,k−1 W_k−1); ``previous`` (W_k−1) may have fewer columns than
        ``b`` (the columns it lacks are zero there)."""
        from scipy.linalg import solve_triangular

        if previous is not None and previous.shape[1]:
            sub = self.sub[k]
            if sub is None:  # a first block has no block before it, so no previous W either
                raise ConvergenceError(f"banded solve: block {k} has no block before it but was given one's W")
            b[:sub.shape[0], :previous.shape[1]] -= sub @ previous[-self.corner:]
        return solve_triangular(self.diag[k], b, lower=True, check_finite=False)

    def forward(self, rhs) -> np.ndarray:
        """W = L⁻¹ Y for a dense Y (n, m) in the matrix's own order."""
        y = np.asarray(rhs, dtype=float)[self.perm]
        w = np.empty_like(y)
        previous = None
        for k, i0 in enumerate(self.starts):
            checkpoint()  # an engine's design stops here when superseded
            i1 = i0 + self.diag[k].shape[0]
            w[i0:i1] = previous = self._solve_block(k, y[i0:i1].copy(), previous)
        return w

    def flexibility(self, loads, gauge=None) -> np.ndarray:
        """Yᵀ K⁻¹ Y = WᵀW for the sparse load columns Y (n, m), accumulated block by block
        (W is never stored: ~0.2 GB for the FS; the sum is a symmetric rank-k update, BLAS
        ``syrk``, of its upper triangle). A column of W is zero above the first nonzero row
        of its load (L⁻¹ is lower triangular), so the columns are taken in the order of their
        first loaded row and a block works only on the columns that have started: the
        callers order the dofs so that the loads come last, and along the loaded stretch the
        columns enter one by one. ``gauge`` = (c, rot): the loads are first projected, Pᵀ Y =
        Y − c (rotᵀ Y) / (cᵀ rot) (a reaction c that holds the mode rot); as L⁻¹ is linear,
        the projection is applied to the accumulated sums, and only the one dense column L⁻¹c
        is swept whole."""
        from scipy.linalg.blas import dsyrk

        y = sp.csr_matrix(loads)[self.perm]
        m = y.shape[1]
        coo = y.tocoo()
        starts = np.full(m, self.n)
        np.minimum.at(starts, coo.col, coo.row)
        columns = np.argsort(starts, kind="stable")  # by first loaded row
        starts = starts[columns]
        y = y[:, columns].tocsr()
        y.sum_duplicates()
        gram = np.zeros((m, m), order="F")  # upper triangle, columns in the order ``columns``
        if gauge is not None:
            c, rot = (np.asarray(v, dtype=float) for v in gauge)
            w_c = self.forward(c[:, None])[:, 0]
            cross = np.zeros(m)
        previous = None
        for k, i0 in enumerate(self.starts):
            checkpoint()  # an engine's design stops here when superseded
            i1 = i0 + self.diag[k].shape[0]
            a = int(np.searchsorted(starts, i1))  # columns started above row i1
            if a == 0:
                continue
            # Y's rows i0:i1, dense (their entries all lie in the first a columns)
            block = np.zeros((i1 - i0, a))
            lo, hi = y.indptr[i0], y.indptr[i1]
            if hi > lo:
                block[np.repeat(np.arange(i1 - i0), np.diff(y.indptr[i0:i1 + 1])), y.indices[lo:hi]] = y.data[lo:hi]
            w = self._solve_block(k, block, previous)
            gram[:a, :a] = dsyrk(1.0, w.T, beta=1.0, c=gram[:a, :a], trans=0, lower=0)
            if gauge is not None:
                cross[:a] += w.T @ w_c[i0:i1]
            previous = w
        gram = np.triu(gram) + np.triu(gram, 1).T
        out = np.empty((m, m))
        out[np.ix_(columns, columns)] = gram
        if gauge is not None:
            cross_out = np.empty(m)
            cross_out[columns] = cross
            alpha = (sp.csr_matrix(loads).T @ rot) / (c @ rot)
            out += (w_c @ w_c) * np.outer(alpha, alpha) - np.outer(cross_out, alpha) - np.outer(alpha, cross_out)
        return 0.5 * (out + out.T)


def _loads_last(order: np.ndarray, loaded_dofs: np.ndarray) -> np.ndarray:
    """``order`` or its reverse (the same band), whichever puts the first loaded dof later:
    :meth:`_BandedFlex.flexibility` skips the rows before it."""
    where = np.empty(order.size, dtype=int)
    where[order] = np.arange(order.size)
    first = int(where[loaded_dofs].min())
    last = int(where[loaded_dofs].max())
    return order if first >= order.size - 1 - last else order[::-1]


def _check_on_surface(dist: np.ndarray, tol_mm: float, tooth_index) -> None:
    """A ComplianceError naming the FS point farthest off the tooth surface, if one is beyond ``tol_mm``."""
    bad = np.flatnonzero(dist > tol_mm)
    if bad.size:
        k = int(bad[np.argmax(dist[bad])])
        which = "" if tooth_index is None else f" (tooth {int(tooth_index[k])})"
        raise ComplianceError(
            f"fs_points: point {k}{which} is {dist[k]:.3g} mm off the FS tooth surface once "
            f"mapped back to its tooth frame (tolerance on_surface_tol_mm = {tol_mm:g} mm); the points, tooth "
            "indices and inputs.motion must belong together")


def _bore_rotation(xy: np.ndarray, bore: np.ndarray, r_bore: float, ix, iy, n: int) -> np.ndarray:
    """c with c·u the bore's mean rotation (its weights: quadratic edges along the bore, L/6,
    2L/3, L/6 at each edge's nodes), over ``n`` dof."""
    c = np.zeros(n)
    th = np.arctan2(xy[0, bore], xy[1, bore])
    for e in range((bore.size - 1) // 2):
        tri = bore[2 * e:2 * e + 3]
        length = r_bore * abs(th[2 * e + 2] - th[2 * e])
        for node, w in zip(tri, (length / 6, 2 * length / 3, length / 6)):
            t = math.atan2(xy[0, node], xy[1, node])
            c[ix[node]] += w * math.cos(t)
            c[iy[node]] -= w * math.sin(t)
    return c


def _edge_projection(xy_nodes: np.ndarray, line: np.ndarray, points: np.ndarray, window=None):
    """Project ``points`` (m, 2) onto the chain of quadratic edges along the node line
    ``line`` (node indices sorted along the boundary: vertex, mid, vertex, mid, …).

    Returns (edge node triples (m, 3), shape-function weights (m, 3), distance (m,),
    foot points (m, 2))."""
    x = xy_nodes[:, line].T  # (L, 2)
    n_edges = (line.size - 1) // 2
    m = points.shape[0]
    d2 = ((points[:, None, :] - x[None, :, :]) ** 2).sum(-1) if window is None else window(points, x)
    nearest = np.argmin(d2, axis=1)
    best = np.full(m, np.inf)
    best_xi = np.zeros(m)
    best_e = np.zeros(m, dtype=int)
    for shift in (-2, -1, 0):
        checkpoint()  # an engine's design stops here when superseded (a shift's Newton: a few ms)
        e = np.clip((nearest + shift) // 2, 0, n_edges - 1)
        e = np.where(nearest + shift < 0, 0, e)
        x0, x1, x2 = x[2 * e], x[2 * e + 1], x[2 * e + 2]
        xi = np.full(m, 0.5)
        # Newton on each point's foot, 30 steps at most; a point whose step leaves it where it is
        # stays there bit for bit, so it leaves the iteration (the same numbers, fewer operations)
        act = np.arange(m)
        for _ in range(30):
            a0, a1, a2, t = x0[act], x1[act], x2[act], xi[act]
            n0, n1, n2 = (1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)
            d0, d1, d2_ = 4 * t - 3, 4 - 8 * t, 4 * t - 1
            pos = n0[:, None] * a0 + n1[:, None] * a1 + n2[:, None] * a2
            der = d0[:, None] * a0 + d1[:, None] * a1 + d2_[:, None] * a2
            sec = 4 * a0 - 8 * a1 + 4 * a2
            r = pos - points[act]
            g = (der * r).sum(1)
            h = (sec * r).sum(1) + (der * der).sum(1)
            step = np.clip(t - g / np.where(h > 0, h, 1.0), 0.0, 1.0)
            xi[act] = step
            act = act[step != t]
            if not act.size:
                break
        n0, n1, n2 = (1 - xi) * (1 - 2 * xi), 4 * xi * (1 - xi), xi * (2 * xi - 1)
        pos = n0[:, None] * x0 + n1[:, None] * x1 + n2[:, None] * x2
        dist = np.linalg.norm(pos - points, axis=1)
        better = dist < best
        best = np.where(better, dist, best)
        best_xi = np.where(better, xi, best_xi)
        best_e = np.where(better, e, best_e)
    xi = best_xi
    weights = np.column_stack([(1 - xi) * (1 - 2 * xi), 4 * xi * (1 - xi), xi * (2 * xi - 1)])
    triples = np.column_stack([line[2 * best_e], line[2 * best_e + 1], line[2 * best_e + 2]])
    foot = (weights[:, :, None] * xy_nodes[:, triples].transpose(1, 2, 0)).sum(1)
    return triples, weights, best, foot


def _load_matrix(n_dof, ix, iy, triples, weights, directions) -> sp.csc_matrix:
    """Columns: the consistent nodal forces of unit point loads along ``directions``."""
    m = triples.shape[0]
    rows = np.concatenate([ix[triples].ravel(), iy[triples].ravel()])
    cols = np.concatenate([np.repeat(np.arange(m), 3)] * 2)
    vals = np.concatenate([(weights * directions[:, :1]).ravel(), (weights * directions[:, 1:]).ravel()])
    return sp.csc_matrix((vals, (rows, cols)), shape=(n_dof, m))


def _stiffness(mesh, youngs_modulus_mpa, poisson_ratio, elements=None):
    from skfem import Basis, ElementQuad2, ElementVector

    from ..rim.nonlinear import TotalLagrangian

    if elements is None:
        basis = Basis(mesh, ElementVector(ElementQuad2()), intorder=4)
    else:
        basis = Basis(mesh, ElementVector(ElementQuad2()), intorder=4, elements=elements)
    ix, iy = basis.split_indices()
    stiffness = TotalLagrangian(basis, youngs_modulus_mpa, poisson_ratio).linear_stiffness()
    return stiffness, ix, iy


# --------------------------------------------------------------------------- the two bodies


@dataclass(frozen=True, slots=True, eq=False)
class _BodyFlex:
    """Flexibility (per mm of face width, mm²/N) of one body between its load columns."""

    flex: np.ndarray
    dof: int
    band: int
    mesh: dict
    time_s: float
    off_surface_mm: np.ndarray


def _fs_flex(tooth, gearset, local_points, local_normals, tooth_index, ball_angles, *, margin, toothed_teeth,
             per_pitch, flat_per_pitch, rim_layers, tooth_layers, tol_mm, race_thickness_mm=0.0, race_layers=2,
             race_sliding=False, substructure=True):
    """The FS half ring: flexibility between the FS contact loads (−n, FS material) and the
    candidate balls (+e_r on the bore, or on the outer race's inner surface when
    ``race_thickness_mm`` > 0), with the bore's mean rotation held. ``substructure``: one
    pitch of each kind (toothed, flat) meshed and condensed onto its cuts
    (:func:`_half_ring_flex_substructured`), else the whole half ring assembled and
    factorised (:func:`_half_ring_flex`, the reference: the same model and mesh)."""
    from ..rim.toothed import toothed_half_ring_mesh, toothed_half_ring_race_mesh

    start = time.perf_counter()
    g = gearset.gear
    z1 = g.flexspline_teeth
    half = z1 // 2
    k_mesh = np.mod(tooth_index, half)  # the image of a tooth in the other zone is the same pitch
    if toothed_teeth == "all":
        toothed = None
    else:
        near = (k_mesh[:, None] + np.arange(-margin, margin + 1)[None, :]).ravel()
        toothed = np.unique(np.mod(near, half))
    r_bore = g.neutral_radius_mm - 0.5 * g.rim_thickness_mm
    if substructure:
        return _fs_flex_substructured(tooth, gearset, local_points, local_normals, tooth_index, k_mesh, toothed,
                                      ball_angles, per_pitch=per_pitch, flat_per_pitch=flat_per_pitch,
                                      rim_layers=rim_layers, tooth_layers=tooth_layers, tol_mm=tol_mm,
                                      race_thickness_mm=race_thickness_mm, race_layers=race_layers,
                                      race_sliding=race_sliding, start=start)
    if race_thickness_mm > 0.0:
        ring, bore_nodes = toothed_half_ring_race_mesh(
            tooth, g.rim_thickness_mm, race_thickness_mm, race_layers=race_layers, toothed_pitches=toothed,
            rim_layers=rim_layers, tooth_layers=tooth_layers, per_pitch=per_pitch, flat_per_pitch=flat_per_pitch)
    else:
        ring = toothed_half_ring_mesh(tooth, g.rim_thickness_mm, toothed_pitches=toothed, rim_layers=rim_layers,
                                      tooth_layers=tooth_layers, per_pitch=per_pitch, flat_per_pitch=flat_per_pitch)
        bore_nodes = None
    # loads in the mesh frame (= the wave-generator frame at ψ = 0: tooth k at 2πk/z1)
    r_m = g.neutral_radius_mm
    ang = 2.0 * math.pi * k_mesh / z1
    c, s = np.cos(ang), np.sin(ang)
    # tooth frame → mesh: x_R along e_t(θ_k) = (c, −s), y_R along e_r(θ_k) = (s, c); origin r_m e_r
    px = local_points[:, 0] * c + (local_points[:, 1] + r_m) * s
    py = -local_points[:, 0] * s + (local_points[:, 1] + r_m) * c
    nx = local_normals[:, 0] * c + local_normals[:, 1] * s
    ny = -local_normals[:, 0] * s + local_normals[:, 1] * c
    flex, dof, band, dist = _half_ring_flex(
        ring, gearset.material.youngs_modulus_mpa, gearset.material.poisson_ratio,
        r_bore, np.column_stack([px, py]), -np.column_stack([nx, ny]),
        ball_angles, tol_mm=tol_mm, tooth_index=tooth_index, ball_radius_mm=r_bore - race_thickness_mm,
        bore_nodes=bore_nodes, sliding_race_layers=race_layers if race_sliding and race_thickness_mm > 0.0 else None)
    info = {**ring.to_dict(), "reduced_dof": dof, "band": band}
    if race_thickness_mm > 0.0:
        info.update(race_thickness_mm=race_thickness_mm, race_layers=race_layers,
                    race_interface="sliding" if race_sliding else "bonded")
    return _BodyFlex(flex, dof, band, info, time.perf_counter() - start, dist)


def _fs_flex_substructured(tooth, gearset, local_points, local_normals, tooth_index, k_mesh, toothed, ball_angles, *,
                           per_pitch, flat_per_pitch, rim_layers, tooth_layers, tol_mm, race_thickness_mm, race_layers,
                           race_sliding, start):
    """:func:`_fs_flex` by substructures: one pitch of each kind meshed (pitch 0's place)."""
    from ..rim.toothed import toothed_half_ring_mesh, toothed_half_ring_race_mesh

    g = gearset.gear
    z1 = g.flexspline_teeth
    half = z1 // 2
    pitch_kind = np.zeros(half, dtype=int) if toothed is None else np.where(np.isin(np.arange(half), toothed), 0, 1)
    kinds = [0] if toothed is None else sorted(set(pitch_kind.tolist()))
    pitch_kind = np.searchsorted(kinds, pitch_kind)  # kinds present, numbered from 0
    r_bore = g.neutral_radius_mm - 0.5 * g.rim_thickness_mm
    sliding = race_layers if race_sliding and race_thickness_mm > 0.0 else None

    def make():
        t0 = time.perf_counter()
        rings, bores = [], []
        for kind in kinds:
            checkpoint()  # an engine's design stops here when superseded (a pitch kind's mesh)
            kw = dict(toothed_pitches=[0] if kind == 0 else [], rim_layers=rim_layers, tooth_layers=tooth_layers,
                      per_pitch=per_pitch, flat_per_pitch=flat_per_pitch, pitches=1)
            if race_thickness_mm > 0.0:
                ring, bore = toothed_half_ring_race_mesh(tooth, g.rim_thickness_mm, race_thickness_mm,
                                                         race_layers=race_layers, **kw)
            else:
                ring, bore = toothed_half_ring_mesh(tooth, g.rim_thickness_mm, **kw), None
            rings.append(ring)
            bores.append(ring.inner_nodes if bore is None else bore)
        mesh_time = time.perf_counter() - t0
        checkpoint()
        parts = [_half_ring_pitch(r, gearset.material.youngs_modulus_mpa, gearset.material.poisson_ratio, r_bore,
                                  np.asarray(bores[t]) if race_thickness_mm > 0.0 else np.asarray(r.inner_nodes),
                                  sliding, "FS rim" + (" and sliding race" if sliding else "") + " (one pitch)")
                 for t, r in enumerate(rings)]
        return rings, bores, mesh_time, parts

    # the meshed and condensed pitches: the same at every wave-generator position (``_cached``)
    key = ("fs", id(gearset), id(tooth), tuple(kinds), per_pitch, flat_per_pitch, rim_layers, tooth_layers,
           float(race_thickness_mm), race_layers, sliding)
    rings, bores, mesh_time, parts = _cached(key, (gearset, tooth), make)
    # loads in the mesh frame, as _fs_flex places them (tooth k at 2πk/z1); _pitch_projection turns
    # them into their pitch's frame
    pitch_rad = rings[0].pitch_rad
    ang = k_mesh * pitch_rad
    c, s = np.cos(ang), np.sin(ang)
    r_m = g.neutral_radius_mm
    px = local_points[:, 0] * c + (local_points[:, 1] + r_m) * s
    py = -local_points[:, 0] * s + (local_points[:, 1] + r_m) * c
    nx = local_normals[:, 0] * c + local_normals[:, 1] * s
    ny = -local_normals[:, 0] * s + local_normals[:, 1] * c
    flex, dof, band, dist = _half_ring_flex_substructured(
        rings, pitch_kind, gearset.material.youngs_modulus_mpa, gearset.material.poisson_ratio, r_bore,
        np.column_stack([px, py]), -np.column_stack([nx, ny]), k_mesh, ball_angles, tol_mm=tol_mm,
        tooth_index=tooth_index, ball_radius_mm=r_bore - race_thickness_mm,
        bores=bores if race_thickness_mm > 0.0 else None, sliding_race_layers=sliding, parts=parts)
    info = {**_ring_info(rings, pitch_kind, mesh_time), "reduced_dof": dof, "band": band,
            "substructure": "one pitch per kind condensed onto its cuts; band: the cuts' system"}
    if race_thickness_mm > 0.0:
        info.update(race_thickness_mm=race_thickness_mm, race_layers=race_layers,
                    race_interface="sliding" if race_sliding else "bonded")
    return _BodyFlex(flex, dof, band, info, time.perf_counter() - start, dist)


def _half_ring_flex(ring, youngs_modulus_mpa, poisson_ratio, r_bore, points, directions, ball_angles, *, tol_mm,
                    tooth_index=None, ball_radius_mm=None, bore_nodes=None, sliding_race_layers=None):
    """Flexibility (mm²/N) of a point-symmetric half ring (``ring``: a RingSectorMesh whose
    cuts are π apart) between unit point loads on its outer surface (``points`` along
    ``directions``, mesh frame) and unit outward radial loads on its inner surface
    (``ring.inner_nodes``, radius ``ball_radius_mm``, default ``r_bore``) at ``ball_angles``,
    with the mean rotation of the bore (``bore_nodes``, radius ``r_bore``; default the inner
    surface) held. ``sliding_race_layers``: the element rows j < this value are the outer
    race, joined to the rim on the bore row radially only (each bore node gets a second,
    tangential dof for the race; the race's free spin is held at one node — its loads are
    all radial, so that holding carries no force). Returns (flex, dof, band, off-surface
    distances)."""
    r_ball = r_bore if ball_radius_mm is None else float(ball_radius_mm)
    bore = ring.inner_nodes if bore_nodes is None else np.asarray(bore_nodes)
    mesh = ring.mesh
    if sliding_race_layers is None:
        stiffness, ix, iy = _stiffness(mesh, youngs_modulus_mpa, poisson_ratio)
    else:
        race_el = np.all(np.asarray(ring.j)[mesh.t] <= sliding_race_layers, axis=0)
        k_rim, ix, iy = _stiffness(mesh, youngs_modulus_mpa, poisson_ratio, elements=np.flatnonzero(~race_el))
        k_race = _stiffness(mesh, youngs_modulus_mpa, poisson_ratio, elements=np.flatnonzero(race_el))[0]
    n_full = ix.size + iy.size
    xy = mesh.doflocs
    triples, weights, dist, _ = _edge_projection(xy, ring.outer_nodes, points)
    _check_on_surface(dist, tol_mm, tooth_index)
    loads_c = _load_matrix(n_full, ix, iy, triples, weights, directions)
    z_half = -ring.start_rad  # the start cut is at θ = −z_half, the end cut at π − z_half
    ball_mesh = np.mod(ball_angles + z_half, math.pi) - z_half
    bxy = r_ball * np.column_stack([np.sin(ball_mesh), np.cos(ball_mesh)])
    btrip, bw, _, _ = _edge_projection(xy, ring.inner_nodes, bxy)
    loads_b = _load_matrix(n_full, ix, iy, btrip, bw, np.column_stack([np.sin(ball_mesh), np.cos(ball_mesh)]))
    loads = sp.hstack([loads_c, loads_b]).tocsr()
    if sliding_race_layers is not None:
        return _sliding_half_ring_flex(ring, k_rim, k_race, ix, iy, loads, r_bore, bore, dist)

    # periodic tie u(θ + π) = −u(θ): the end cut's dofs are the start cut's, negated
    node_red, sign, keep = _half_ring_tie(ring, ix.size)
    n_nodes_red = int(keep.sum())
    rows = np.concatenate([ix, iy])
    cols = np.concatenate([2 * node_red, 2 * node_red + 1])
    tie = sp.csr_matrix((np.concatenate([sign, sign]), (rows, cols)), shape=(n_full, 2 * n_nodes_red))
    k_red = (tie.T @ stiffness @ tie).tocsr()
    b_red = (tie.T @ loads).tocsr()

    # gauge: the bore's mean rotation c·u = 0 (uniform tangential traction as its reaction)
    c_full = _bore_rotation(xy, bore, r_bore, ix, iy, n_full)
    rot_full = np.zeros(n_full)
    rot_full[ix], rot_full[iy] = xy[1], -xy[0]
    c_red = tie.T @ c_full
    rot_red = np.zeros(2 * n_nodes_red)
    rot_red[2 * node_red[keep]] = rot_full[ix[keep]]
    rot_red[2 * node_red[keep] + 1] = rot_full[iy[keep]]
    gauge = 2 * int(node_red[ring.inner_nodes[0]])  # the tangential (x) dof of the bore node on the cut
    free = np.setdiff1d(np.arange(2 * n_nodes_red), [gauge])
    # folded order round the tied ring: both directions away from the cut, interleaved
    s_red = np.empty(n_nodes_red)
    j_red = np.empty(n_nodes_red)
    s_red[node_red[keep]] = ring.s[keep]
    j_red[node_red[keep]] = ring.j[keep]
    n_s = float(ring.pitch_columns.sum())
    i2 = np.round(2 * s_red).astype(int)
    d = np.minimum(i2, int(round(2 * n_s)) - i2)
    key_node = 2 * d + (i2 > n_s)
    dof_node = free // 2
    order = np.lexsort((free % 2, j_red[dof_node], key_node[dof_node]))
    b_free = b_red[free]
    order = _loads_last(order, np.flatnonzero(np.diff(b_free.indptr)))
    factor = _BandedFlex(k_red[free][:, free], order, "FS rim")
    flex = factor.flexibility(b_free, gauge=(c_red[free], rot_red[free]))
    return flex, int(free.size), factor.band, dist


def _sliding_stiffness(xy, k_rim, k_race, ix, iy, bore):
    """Rim (``k_rim``) and race (``k_race``, the same mesh's race elements) joined on the bore
    nodes ``bore`` radially only: the stiffness on the mesh's dofs (``ix``, ``iy``) and one
    tangential race dof per bore node after them (in the order of ``bore``); a bore node's
    race copy is e_r e_rᵀ u_rim + e_t v. Returns (stiffness, the bore nodes' angles θ)."""
    n_full = ix.size + iy.size
    n_b = bore.size
    th_b = np.arctan2(xy[0, bore], xy[1, bore])
    er = np.column_stack([np.sin(th_b), np.cos(th_b)])
    et = np.column_stack([np.cos(th_b), -np.sin(th_b)])
    n_ext = n_full + n_b
    is_bore = np.zeros(ix.size, bool)
    is_bore[bore] = True
    other = np.flatnonzero(~is_bore)
    other_dofs = np.concatenate([ix[other], iy[other]])
    k = np.arange(n_b)
    rows = [other_dofs]
    cols = [other_dofs]
    vals = [np.ones(other_dofs.size)]
    for a, ia in ((0, ix), (1, iy)):
        for b_, ib in ((0, ix), (1, iy)):
            rows.append(ia[bore])
            cols.append(ib[bore])
            vals.append(er[:, a] * er[:, b_])
        rows.append(ia[bore])
        cols.append(n_full + k)
        vals.append(et[:, a])
    t_race = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n_full, n_ext))
    pad = sp.eye(n_full, n_ext, format="csr")
    return (pad.T @ k_rim @ pad + t_race.T @ k_race @ t_race).tocsr(), th_b


def _sliding_half_ring_flex(ring, k_rim, k_race, ix, iy, loads, r_bore, bore, dist):
    """:func:`_half_ring_flex` with the race joined to the bore radially only (frictionless)."""
    xy = ring.mesh.doflocs
    n_full = ix.size + iy.size
    n_b = bore.size
    stiffness, th_b = _sliding_stiffness(xy, k_rim, k_race, ix, iy, bore)
    n_ext = n_full + n_b
    k = np.arange(n_b)
    loads = sp.vstack([loads, sp.csr_matrix((n_b, loads.shape[1]))]).tocsr()

    # periodic tie: Cartesian dofs u_end = −u_start; the race's tangential dof v_end = +v_start
    node_red, sign, keep = _half_ring_tie(ring, ix.size)
    n_nodes_red = int(keep.sum())
    # bore sorted by s: bore[0] on the start cut, bore[-1] on the end cut
    extra_red = 2 * n_nodes_red + np.concatenate([np.arange(n_b - 1), [0]])
    n_red = 2 * n_nodes_red + n_b - 1
    rows = np.concatenate([ix, iy, n_full + k])
    cols = np.concatenate([2 * node_red, 2 * node_red + 1, extra_red])
    tie = sp.csr_matrix((np.concatenate([sign, sign, np.ones(n_b)]), (rows, cols)), shape=(n_ext, n_red))
    k_red = (tie.T @ stiffness @ tie).tocsr()
    b_red = (tie.T @ loads).tocsr()

    # gauge: the rim bore's mean rotation c·u = 0, as in _half_ring_flex
    c_full = np.zeros(n_ext)
    for e in range((n_b - 1) // 2):
        tri = bore[2 * e:2 * e + 3]
        length = r_bore * abs(th_b[2 * e + 2] - th_b[2 * e])
        for node, w in zip(tri, (length / 6, 2 * length / 3, length / 6)):
            t = math.atan2(xy[0, node], xy[1, node])
            c_full[ix[node]] += w * math.cos(t)
            c_full[iy[node]] -= w * math.sin(t)
    rot_red = np.zeros(n_red)  # the rigid rotation of rim and race together
    rot_red[2 * node_red[keep]] = xy[1, keep]
    rot_red[2 * node_red[keep] + 1] = -xy[0, keep]
    rot_red[extra_red[:-1]] = np.hypot(xy[0, bore[:-1]], xy[1, bore[:-1]])
    c_red = tie.T @ c_full
    # two gauges: the rim's rotation (a bore node) and the race's spin (a race inner node)
    gauges = [2 * int(node_red[bore[0]]), 2 * int(node_red[ring.inner_nodes[0]])]
    free = np.setdiff1d(np.arange(n_red), gauges)
    s_dof = np.empty(n_red)
    j_dof = np.empty(n_red)
    comp = np.zeros(n_red)
    for c_ in (0, 1):
        s_dof[2 * node_red[keep] + c_] = ring.s[keep]
        j_dof[2 * node_red[keep] + c_] = ring.j[keep]
        comp[2 * node_red[keep] + c_] = c_
    s_dof[extra_red[:-1]] = ring.s[bore[:-1]]
    j_dof[extra_red[:-1]] = ring.j[bore[:-1]] - 0.25
    n_s = float(ring.pitch_columns.sum())
    i2 = np.round(2 * s_dof).astype(int)
    d = np.minimum(i2, int(round(2 * n_s)) - i2)
    key = 2 * d + (i2 > n_s)
    order = np.lexsort((comp[free], j_dof[free], key[free]))
    b_free = b_red[free]
    order = _loads_last(order, np.flatnonzero(np.diff(b_free.indptr)))
    factor = _BandedFlex(k_red[free][:, free], order, "FS rim and sliding race")
    flex = factor.flexibility(b_free, gauge=(c_red[free], rot_red[free]))
    return flex, int(free.size), factor.band, dist


# --------------------------------------------------------------------------- substructures


def _cut_rotation(n_cut: int, pairs: int, angle: float) -> np.ndarray:
    """R (n_cut × n_cut): a cut's dofs in the frame of the next pitch (turned by ``angle``)
    → in this pitch's frame, u_k = R u_k+1. The first ``pairs`` (x, y) pairs turn
    (θ from +y toward +x: Q(α) = [[cos α, sin α], [−sin α, cos α]] turns a vector by α); the
    other dofs are scalars (tangential race dofs) and stay."""
    c, s = math.cos(angle), math.sin(angle)
    r = np.eye(n_cut)
    i = 2 * np.arange(pairs)
    r[i, i], r[i, i + 1], r[i + 1, i], r[i + 1, i + 1] = c, s, -s, c
    return r


class _Pitch:
    """One pitch of a ring of identical pitches, condensed onto its two cuts (static
    condensation; exact, not an approximation).

    ``stiffness``: the pitch's own stiffness (n × n, in the frame of the pitch); ``left`` /
    ``right``: its dofs on the two cuts, node by node in the same order, the first ``pairs``
    (x, y) pairs then scalars; ``key`` (s, j, component) of every dof orders the interior
    into a band; ``fixed``: dofs held at zero; ``modes`` (n × r): the pitch's rigid-body modes
    if it has any (none when held): the condensed stiffness is projected so that they are
    its null space exactly, as they are the exact one's (the subtraction below leaves them
    ~1e-14 of K; the thin ring's flexibility is ill-conditioned enough for that to matter:
    default set, the difference of S to the whole mesh's solve 8.6e-11 → 3.7e-11).

    Pitch k of the ring is this pitch turned by k × ``pitch_rad``, with its dofs in its own
    turned frame and its right cut's in the next pitch's frame (``_cut_rotation``): then every pitch has the same condensed stiffness
    ``schur`` (2 n_cut square, the cuts' dofs [left, right]) — that of the interior
    K_BB − K_BI K_II⁻¹ K_IB, with K_II factorised once (:class:`_BandedFlex`, W = L⁻¹ Y).

    A load f on the pitch (its own frame) becomes the cut load g = Tᵀ(f_B − K_BI K_II⁻¹ f_I)
    and the interior term f_Iᵀ K_II⁻¹ f'_I between loads on the same pitch:
    fᵀ K⁻¹ f' = f_Iᵀ K_II⁻¹ f'_I + gᵀ K_cut⁻¹ g' (K_cut: the condensed pitches assembled)."""

    def __init__(self, stiffness, left, right, pairs: int, key, pitch_rad: float, where: str, fixed=(), modes=None):
        n = stiffness.shape[0]
        self.left, self.right = np.asarray(left), np.asarray(right)
        self.n_cut = self.left.size
        self.boundary = np.concatenate([self.left, self.right])
        inner = np.ones(n, bool)
        inner[self.boundary] = False
        inner[np.asarray(fixed, dtype=int)] = False
        self.interior = np.flatnonzero(inner)
        k = sp.csr_matrix(stiffness)
        k_i = k[self.interior]
        s_, j_, comp = (np.asarray(v)[self.interior] for v in key)
        self.factor = _BandedFlex(k_i[:, self.interior], np.lexsort((comp, j_, s_)), where)
        self.w_b = self.factor.forward(k_i[:, self.boundary].toarray())
        schur = k[self.boundary][:, self.boundary].toarray() - self.w_b.T @ self.w_b
        if modes is not None:
            # the rigid modes carry no energy: make them the condensed stiffness's null space exactly
            q = np.linalg.qr(np.asarray(modes)[self.boundary])[0]
            schur = schur - q @ (q.T @ schur)
            schur = schur - (schur @ q) @ q.T
        r = _cut_rotation(self.n_cut, pairs, pitch_rad)
        self.t = np.eye(2 * self.n_cut)
        self.t[self.n_cut:, self.n_cut:] = r
        self.schur = self.t.T @ schur @ self.t
        self.schur = 0.5 * (self.schur + self.schur.T)

    def condense(self, loads):
        """(g (2 n_cut × m), raw Tᵀ f_B (2 n_cut × m), W_I = L⁻¹ f_I) for the load columns ``loads``."""
        f = sp.csr_matrix(loads)
        f_b = f[self.boundary].toarray()
        w = self.factor.forward(f[self.interior].toarray())
        return self.t.T @ (f_b - self.w_b.T @ w), self.t.T @ f_b, w


def _chain_flex(kinds, pitch_kind, loads, load_pitch, *, cyclic: bool, fixed_cut=(), gauge=None, where: str):
    """Flexibility Yᵀ K⁻¹ Y of a ring (or sector) of condensed pitches (:class:`_Pitch`).

    ``kinds``: the distinct pitches; ``pitch_kind[k]``: the kind of pitch k (cuts: k on the
    left, k + 1 on the right). ``cyclic``: the right cut of the last pitch is cut 0 (in
    its frame, the periodic tie made the identity by the frames), else cuts 0 and N are
    held. ``fixed_cut``: dofs of cut 0 held (the gauge). ``loads[t]``: the load columns
    (sparse, kind t's dofs, each in its own pitch's frame) and ``load_pitch[t]`` their pitch
    and column in the result. ``gauge`` = ([c_t per kind: the pitch's reaction c], [rot_t]):
    the columns are projected as in :meth:`_BandedFlex.flexibility` (Pᵀ Y = Y − c (rotᵀ Y) /
    (cᵀ rot) over the free dofs, c and rot every pitch's together). Returns (flex, band of
    the cut system)."""
    n_p = len(pitch_kind)
    pitch_kind = np.asarray(pitch_kind)
    n_c = kinds[0].n_cut
    n_cuts = n_p if cyclic else n_p + 1
    left_cut = np.arange(n_p)
    right_cut = (left_cut + 1) % n_cuts
    m = sum(int(col.size) for _, col in load_pitch)
    # the condensed stiffness of the cuts, assembled
    idx = np.concatenate([left_cut[:, None] * n_c + np.arange(n_c)[None, :],
                          right_cut[:, None] * n_c + np.arange(n_c)[None, :]], axis=1)  # (n_p, 2 n_c)
    vals = np.stack([kinds[t].schur for t in pitch_kind])
    rows = np.broadcast_to(idx[:, :, None], vals.shape).ravel()
    cols = np.broadcast_to(idx[:, None, :], vals.shape).ravel()
    n_dof = n_cuts * n_c
    k_cut = sp.csr_matrix((vals.ravel(), (rows, cols)), shape=(n_dof, n_dof))
    held = np.zeros(n_dof, bool)
    if cyclic:
        held[np.asarray(fixed_cut, dtype=int)] = True
    else:
        held[:n_c] = held[-n_c:] = True
    free = np.flatnonzero(~held)
    n_ext = m + (gauge is not None)
    g_rows, g_cols, g_vals = [], [], []
    raw = np.zeros((n_dof, n_ext))
    local = np.zeros((n_ext, n_ext))
    if gauge is not None:
        c_kinds, rot_kinds = gauge
        rot_y = np.zeros(m)  # rotᵀ Y over the free dofs: the interiors' here, the cuts' below
    for t, kind in enumerate(kinds):
        checkpoint()  # an engine's design stops here when superseded (a kind's condensation)
        pitch, column = load_pitch[t]
        pitch = np.asarray(pitch, dtype=int)
        column = np.asarray(column, dtype=int)
        on = np.flatnonzero(pitch_kind == t)
        blocks = [loads[t]] if gauge is None else [loads[t], sp.csr_matrix(np.asarray(c_kinds[t])[:, None])]
        g, f_raw, w = kind.condense(sp.hstack(blocks).tocsr())
        mt = column.size
        # loads: their pitch's two cuts
        g_rows.append(idx[pitch].T.ravel() if mt else np.zeros(0, int))
        g_cols.append(np.broadcast_to(column, (2 * n_c, mt)).ravel())
        g_vals.append(g[:, :mt].ravel())
        raw[idx[pitch].T, np.broadcast_to(column, (2 * n_c, mt))] += f_raw[:, :mt]
        same = pitch[:, None] == pitch[None, :]
        local[np.ix_(column, column)] += np.where(same, w[:, :mt].T @ w[:, :mt], 0.0)
        if gauge is not None and on.size:
            # c: on every pitch of this kind
            g_rows.append(idx[on].ravel())
            g_cols.append(np.full(on.size * 2 * n_c, m))
            g_vals.append(np.tile(g[:, mt], on.size))
            np.add.at(raw[:, m], idx[on].ravel(), np.tile(f_raw[:, mt], on.size))
            w_c = w[:, mt]
            local[column, m] += w[:, :mt].T @ w_c
            local[m, column] = local[column, m]
            local[m, m] += on.size * float(w_c @ w_c)
            rot = np.asarray(rot_kinds[t])
            rot_y[column] = (loads[t][kind.interior].T @ rot[kind.interior]) if mt else 0.0
    g_all = sp.csr_matrix((np.concatenate(g_vals), (np.concatenate(g_rows), np.concatenate(g_cols))),
                          shape=(n_dof, n_ext))
    # the cuts folded round the ring (0, 1, N − 1, 2, N − 2, …: a band of three cuts), or in their order
    if cyclic:
        d = np.minimum(np.arange(n_cuts), n_cuts - np.arange(n_cuts))
        position = 2 * d + (np.arange(n_cuts) > n_cuts - np.arange(n_cuts))
    else:
        position = np.arange(n_cuts)
    # the cut system's factor depends on the pitches and their arrangement only: kept on the first
    # pitch (a cached one is reused across calls, see _cached)
    factors = kinds[0].__dict__.setdefault("cut_factors", {})
    fkey = (tuple(id(k) for k in kinds), pitch_kind.tobytes(), bool(cyclic), tuple(np.asarray(fixed_cut, int).tolist()))
    factor = factors.get(fkey)
    checkpoint()
    if factor is None:
        dof_cut = free // n_c
        order = np.lexsort((free % n_c, position[dof_cut]))
        factor = factors[fkey] = _BandedFlex(k_cut[free][:, free], order, where)
    gram = factor.flexibility(g_all[free]) + local
    if gauge is None:
        return 0.5 * (gram + gram.T), factor.band
    rot_cut = np.tile(np.asarray(rot_kinds[0])[kinds[0].left], n_cuts)  # every cut in its own frame
    rot_y += raw[free, :m].T @ rot_cut[free]
    c_rot = float(raw[free, m] @ rot_cut[free]) + sum(
        float(np.asarray(c_kinds[t])[kinds[t].interior] @ np.asarray(rot_kinds[t])[kinds[t].interior])
        * int(np.sum(pitch_kind == t)) for t in range(len(kinds)))
    alpha = rot_y / c_rot
    out, cross, cc = gram[:m, :m], gram[:m, m], gram[m, m]
    out = out + cc * np.outer(alpha, alpha) - np.outer(cross, alpha) - np.outer(alpha, cross)
    return 0.5 * (out + out.T), factor.band


def _pitch_projection(points, guess, pitch_kind, pitch_rad: float, lines):
    """Project ``points`` (m, 2) onto a node line of a ring of turned pitches: each point onto
    its ``guess`` pitch and the two beside it (not past the ring's ends), the nearest kept.
    ``lines[t]`` = (node coordinates (2, n), node line) of pitch kind t in pitch 0's frame.
    Returns (pitch, triples, weights, distance, angle of the pitch's frame)."""
    n_p = len(pitch_kind)
    pitch_kind = np.asarray(pitch_kind)
    m = points.shape[0]
    shifts = np.array([0, -1, 1])  # the guess first: it wins a tie
    k = np.clip(np.asarray(guess, dtype=int)[None, :] + shifts[:, None], 0, n_p - 1).ravel()  # (3 m,)
    local = _turn_back(np.tile(points, (3, 1)), k * pitch_rad)
    dist = np.full(k.size, np.inf)
    tri = np.zeros((k.size, 3), dtype=int)
    w = np.zeros((k.size, 3))
    for t, (xy, line) in enumerate(lines):  # all candidates on a line of one kind in one call
        checkpoint()  # an engine's design stops here when superseded
        sel = np.flatnonzero(pitch_kind[k] == t)
        if sel.size:
            tri[sel], w[sel], dist[sel], _ = _edge_projection(xy, line, local[sel])
    pick = np.argmin(dist.reshape(3, m), axis=0) * m + np.arange(m)
    return k[pick], tri[pick], w[pick], dist[pick], k[pick] * pitch_rad


def _turn_back(vectors, angle):
    """``vectors`` (m, 2) expressed in the frames turned by ``angle`` (m,) (θ from +y toward +x):
    a vector at θ comes out at θ − angle."""
    c, s = np.cos(angle), np.sin(angle)
    return np.column_stack([c * vectors[:, 0] - s * vectors[:, 1], s * vectors[:, 0] + c * vectors[:, 1]])


def _dof_key(ring, ix, iy, n_extra=0, extra_nodes=None):
    """(s, j, component) of every dof of a pitch (race dofs of the bore nodes just inside them)."""
    n = ix.size + iy.size + n_extra
    s_, j_, comp = np.zeros(n), np.zeros(n), np.zeros(n)
    for c_, ic in ((0, ix), (1, iy)):
        s_[ic], j_[ic], comp[ic] = ring.s, ring.j, c_
    if n_extra:
        s_[ix.size + iy.size:] = ring.s[extra_nodes]
        j_[ix.size + iy.size:] = ring.j[extra_nodes] - 0.25
    return s_, j_, comp


def _ring_info(rings, pitch_kind, time_s: float) -> dict:
    """:meth:`RingSectorMesh.to_dict` of the whole ring of pitches, from one mesh per pitch kind."""
    pitch_kind = np.asarray(pitch_kind)
    count = [int(np.sum(pitch_kind == t)) for t in range(len(rings))]
    cols = sum(c * int(r.pitch_columns.sum()) for c, r in zip(count, rings))
    layers = rings[0].layers
    nodes = (2 * cols + 1) * (2 * layers + 1)
    return {"pitches": int(pitch_kind.size),
            "toothed_pitches": sum(c * int(r.toothed.sum()) for c, r in zip(count, rings)),
            "columns": cols, "layers": layers, "elements": sum(c * r.elements for c, r in zip(count, rings)),
            "nodes": nodes, "dof": 2 * nodes,
            "min_jacobian": min(r.min_jacobian for c, r in zip(count, rings) if c),
            "jacobian_ratio": min(r.jacobian_ratio for c, r in zip(count, rings) if c), "time_s": time_s}


def _half_ring_pitch(ring, youngs_modulus_mpa, poisson_ratio, r_bore, bore, sliding_race_layers, where):
    """One pitch of the FS half ring (a one-pitch mesh, pitch 0) as a :class:`_Pitch`, with
    its share of the bore's mean-rotation reaction c and of the rigid rotation rot, its
    (ix, iy), its dof count and the positions of the gauge dofs in its left cut."""
    mesh = ring.mesh
    xy = mesh.doflocs
    if sliding_race_layers is None:
        stiffness, ix, iy = _stiffness(mesh, youngs_modulus_mpa, poisson_ratio)
        n_extra = 0
    else:
        race_el = np.all(np.asarray(ring.j)[mesh.t] <= sliding_race_layers, axis=0)
        k_rim, ix, iy = _stiffness(mesh, youngs_modulus_mpa, poisson_ratio, elements=np.flatnonzero(~race_el))
        k_race = _stiffness(mesh, youngs_modulus_mpa, poisson_ratio, elements=np.flatnonzero(race_el))[0]
        stiffness, _ = _sliding_stiffness(xy, k_rim, k_race, ix, iy, bore)
        n_extra = bore.size
    checkpoint()  # an engine's design stops here when superseded (between the assembly and the condensation)
    n_full = ix.size + iy.size
    n = n_full + n_extra
    left_nodes, right_nodes = np.asarray(ring.start_cut_nodes), np.asarray(ring.end_cut_nodes)
    left = np.column_stack([ix[left_nodes], iy[left_nodes]]).ravel()
    right = np.column_stack([ix[right_nodes], iy[right_nodes]]).ravel()
    if n_extra:  # bore sorted by s: bore[0] on the left cut, bore[-1] on the right
        left, right = np.append(left, n_full), np.append(right, n_full + bore.size - 1)
    # rigid modes: translations x, y and the rotation of rim and race together (race dofs
    # v = e_t·u), and with the sliding race the race's own spin (its nodes and v = r)
    modes = np.zeros((n, 3 + (n_extra > 0)))
    modes[ix, 0] = 1.0
    modes[iy, 1] = 1.0
    modes[ix, 2], modes[iy, 2] = xy[1], -xy[0]
    if n_extra:
        thb = np.arctan2(xy[0, bore], xy[1, bore])
        modes[n_full:, 0], modes[n_full:, 1] = np.cos(thb), -np.sin(thb)
        modes[n_full:, 2] = np.hypot(xy[0, bore], xy[1, bore])
        race = np.flatnonzero(np.asarray(ring.j) < sliding_race_layers)
        modes[ix[race], 3], modes[iy[race], 3] = xy[1, race], -xy[0, race]
        modes[n_full:, 3] = np.hypot(xy[0, bore], xy[1, bore])
    pitch = _Pitch(stiffness, left, right, left_nodes.size, _dof_key(ring, ix, iy, n_extra, bore), ring.pitch_rad,
                   where, modes=modes)
    # the bore's mean rotation c·u (as _half_ring_flex: quadratic edges, weights L/6, 2L/3, L/6)
    c = _bore_rotation(xy, bore, r_bore, ix, iy, n)
    rot = np.zeros(n)
    rot[ix], rot[iy] = xy[1], -xy[0]
    if n_extra:
        rot[n_full:] = np.hypot(xy[0, bore], xy[1, bore])
    gauges = [2 * int(np.flatnonzero(left_nodes == ring.inner_nodes[0])[0])]
    if n_extra:
        gauges.insert(0, 2 * int(np.flatnonzero(left_nodes == bore[0])[0]))
    return pitch, c, rot, (ix, iy, n_full, n_extra), gauges


def _half_ring_flex_substructured(rings, pitch_kind, youngs_modulus_mpa, poisson_ratio, r_bore, points, directions,
                                  point_pitch, ball_angles, *, tol_mm, tooth_index=None, ball_radius_mm=None,
                                  bores=None, sliding_race_layers=None, parts=None):
    """:func:`_half_ring_flex` by substructures: ``rings[t]`` a one-pitch mesh of pitch kind t
    (pitch 0's place; ``bores[t]`` its bore row, default its inner surface) and pitch k of
    the half ring of kind ``pitch_kind[k]``; ``point_pitch``: the pitch of each point (the
    nearest of it and the two beside it is taken). Each kind is condensed onto its cuts once
    (:class:`_Pitch`) and the half ring's cuts are solved together (:func:`_chain_flex`): the
    same flexibility as the whole mesh's, to rounding. ``parts``: the pitches'
    :func:`_half_ring_pitch` when already condensed (:func:`_cached`)."""
    r_ball = r_bore if ball_radius_mm is None else float(ball_radius_mm)
    bores = [np.asarray(r.inner_nodes if bores is None else bores[t]) for t, r in enumerate(rings)]
    if parts is None:
        parts = [_half_ring_pitch(r, youngs_modulus_mpa, poisson_ratio, r_bore, bores[t], sliding_race_layers,
                                  "FS rim" + (" and sliding race" if sliding_race_layers else "") + " (one pitch)")
                 for t, r in enumerate(rings)]
    pitch_rad = rings[0].pitch_rad
    # the contact points: on the tooth surface of their pitch
    pitch_c, tri_c, w_c, dist, ang_c = _pitch_projection(
        points, point_pitch, pitch_kind, pitch_rad, [(r.mesh.doflocs, r.outer_nodes) for r in rings])
    _check_on_surface(dist, tol_mm, tooth_index)
    # the balls: on the inner surface
    z_half = -rings[0].start_rad
    ball_mesh = np.mod(ball_angles + z_half, math.pi) - z_half
    e_r = np.column_stack([np.sin(ball_mesh), np.cos(ball_mesh)])
    guess = np.floor((ball_mesh + z_half) / pitch_rad).astype(int)
    pitch_b, tri_b, w_b, _, ang_b = _pitch_projection(
        r_ball * e_r, guess, pitch_kind, pitch_rad, [(r.mesh.doflocs, r.inner_nodes) for r in rings])
    pitch_all = np.concatenate([pitch_c, pitch_b])
    tri_all, w_all = np.vstack([tri_c, tri_b]), np.vstack([w_c, w_b])
    dirs = _turn_back(np.vstack([directions, e_r]), np.concatenate([ang_c, ang_b]))
    kind_of = np.asarray(pitch_kind)[pitch_all]
    loads, load_pitch = [], []
    for t, (_, _, _, (ix, iy, n_full, n_extra), _) in enumerate(parts):
        sel = np.flatnonzero(kind_of == t)
        y = _load_matrix(n_full, ix, iy, tri_all[sel], w_all[sel], dirs[sel])
        loads.append(sp.vstack([y, sp.csr_matrix((n_extra, sel.size))]).tocsr())
        load_pitch.append((pitch_all[sel], sel))
    kinds = [p[0] for p in parts]
    flex, band = _chain_flex(kinds, pitch_kind, loads, load_pitch, cyclic=True, fixed_cut=parts[0][4],
                             gauge=([p[1] for p in parts], [p[2] for p in parts]),
                             where="FS rim" + (" and sliding race" if sliding_race_layers else "") + " (cuts)")
    dof = sum(int(np.sum(np.asarray(pitch_kind) == t)) * (k.left.size + k.interior.size)
              for t, k in enumerate(kinds)) - len(parts[0][4])
    return flex, dof, band, dist


def _cs_pieces(space, cs_teeth: int):
    """The surface of one CS pitch (tooth centre → space → tooth centre) as pieces for
    :func:`profilegen.rim.toothed.pitch_surface`, polar about the gear centre."""
    from ..geometry.contour import Arc, Line

    half = math.pi / cs_teeth

    def polar(p):
        return np.arctan2(p[..., 0], p[..., 1]), np.hypot(p[..., 0], p[..., 1])

    def on_line(a, b):  # the chord a → b
        return lambda u: polar(a + u[:, None] * (b - a))

    def on_arc(el):
        return lambda u: polar(el.centre + el.radius * np.column_stack([np.cos(el.start_angle + u * el.sweep),
                                                                        np.sin(el.start_angle + u * el.sweep)]))

    start, end = np.asarray(space.start), np.asarray(space.end)
    psi_s, rho_s = polar(start)
    psi_e, rho_e = polar(end)
    # (name, length mm, curve u ↦ (ψ, ρ) on u ∈ [0, 1]), as pitch_surface takes them
    pieces: list[tuple[str, float, Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]]] = [
        ("tip land", rho_s * abs(psi_s + half), lambda u: ((1 - u) * -half + u * psi_s, np.full_like(u, rho_s)))]
    for el in space.elements:
        if isinstance(el, Line):
            a, b = np.asarray(el.start), np.asarray(el.end)
            pieces.append(("line", el.length, on_line(a, b)))
        elif isinstance(el, Arc):
            pieces.append(("arc", el.length, on_arc(el)))
        else:
            raise ComplianceError(f"cs_space: element {el!r} is not a Line or an Arc")
    pieces.append(("tip land", rho_e * abs(half - psi_e),
                   lambda u: ((1 - u) * psi_e + u * half, np.full_like(u, rho_e))))
    return pieces, max(rho_s, rho_e), max(float(np.max(polar(space.sample(1e-4))[1])), rho_s)


#: largest distance of the CS sector mesh's quadratic element edges from the fitted CS surface
_CS_SAG_MM = 1e-3


def _edge_sag_mm(top, columns: int) -> float:
    """Largest distance between the surface ``top`` (column coordinate → polar (ψ, ρ)) and its
    quadratic interpolation through each column's nodes (at whole and half values)."""
    a = np.arange(columns)[:, None] + np.array([0.0, 0.5, 1.0])[None, :]
    u = np.linspace(0.0, 1.0, 9)
    basis = np.stack([(1 - u) * (1 - 2 * u), 4 * u * (1 - u), u * (2 * u - 1)])  # (3, 9)

    def xy(psi, rho):
        return np.stack([rho * np.sin(psi), rho * np.cos(psi)], -1)

    nodes = xy(*top(a.ravel())).reshape(columns, 3, 2)
    quad = np.einsum("cnk,nu->cuk", nodes, basis)
    true = xy(*top((np.arange(columns)[:, None] + u[None, :]).ravel())).reshape(columns, u.size, 2)
    return float(np.max(np.linalg.norm(quad - true, axis=-1)))


def _cs_flex(space, gearset, points, normals, *, margin, per_pitch, tooth_layers, back_layers, outer_radius_mm,
             tol_mm, substructure=True):
    """The CS sector: flexibility between the CS contact loads. ``substructure``: one space
    meshed and condensed onto its cuts, else the whole sector (the reference)."""
    from ..rim.toothed import pitch_surface, ring_sector_mesh

    start = time.perf_counter()
    z2 = gearset.gear.circular_spline_teeth
    pitch = 2.0 * math.pi / z2
    idx = np.round(np.arctan2(points[:, 0], points[:, 1]) / pitch).astype(int)
    lo, hi = int(idx.min()) - margin, int(idx.max()) + margin

    def surface():
        pieces, _, r_root = _cs_pieces(space, z2)
        # every piece needs a column of its own (a profile fitted per branch has 17 pieces per space
        # in the verify scene), and the quadratic element edges must follow the true arcs: more
        # columns until their sag is below _CS_SAG_MM (an involute tooth's per-branch profile has
        # short pieces that took the columns its long arcs needed: 0.16 mm off with 16)
        columns = max(per_pitch, len(pieces))
        top, _ = pitch_surface(pieces, columns)
        for _ in range(8):
            if _edge_sag_mm(top, columns) <= _CS_SAG_MM:
                break
            columns = int(math.ceil(1.25 * columns))
            top, _ = pitch_surface(pieces, columns)
        tip = min(float(np.hypot(*space.start)), float(np.hypot(*space.end)))
        return {"top": top, "per_pitch": columns, "r_back": r_root + 0.5 * (r_root - tip)}

    # the space's surface and (substructured) its meshed, condensed space: the same for any points (``_cached``)
    prepared = _cached(("cs", id(gearset), id(space), per_pitch, tooth_layers, back_layers, float(outer_radius_mm)),
                       (gearset, space), surface)
    checkpoint()  # an engine's design stops here when superseded (between the surface and the mesh)
    top, per_pitch, r_back = prepared["top"], prepared["per_pitch"], prepared["r_back"]
    if not outer_radius_mm > r_back:
        raise ComplianceError(f"cs_outer_radius_mm = {outer_radius_mm:g} mm: must be > {r_back:.6g} mm (the CS root "
                              "circle plus half a tooth height)")
    n_p = hi - lo + 1
    if substructure:
        return _cs_flex_substructured(gearset, points, normals, pitch, lo, n_p, top, per_pitch, r_back, outer_radius_mm,
                                      tooth_layers, back_layers, tol_mm, start, prepared)
    ring = ring_sector_mesh(pitch, (lo - 0.5) * pitch, [top] * n_p, [per_pitch] * n_p, mapped_radius_mm=r_back,
                            polar_radius_mm=outer_radius_mm, mapped_layers=tooth_layers, polar_layers=back_layers,
                            mapped_outside=False, polar_grading=1.6)
    mesh = ring.mesh
    stiffness, ix, iy = _stiffness(mesh, gearset_cs_modulus(gearset), gearset.material.poisson_ratio)
    n_full = stiffness.shape[0]
    triples, weights, dist, _ = _edge_projection(mesh.doflocs, ring.inner_nodes, points)
    bad = np.flatnonzero(dist > tol_mm)
    if bad.size:
        k = int(bad[np.argmax(dist[bad])])
        raise ComplianceError(f"cs_points: point {k} is {dist[k]:.3g} mm off the fitted CS surface (tolerance "
                              f"on_surface_tol_mm = {tol_mm:g} mm)")
    loads = _load_matrix(n_full, ix, iy, triples, weights, -normals).tocsr()  # the FS pushes the CS along −n_CS
    fixed_nodes = np.concatenate([ring.outer_nodes, ring.start_cut_nodes, ring.end_cut_nodes])
    fixed = np.unique(np.concatenate([ix[fixed_nodes], iy[fixed_nodes]]))
    free = np.setdiff1d(np.arange(n_full), fixed)
    node_of = np.empty(n_full, dtype=int)
    node_of[ix], node_of[iy] = np.arange(ix.size), np.arange(iy.size)
    order = np.lexsort((free % 2, ring.j[node_of[free]], ring.s[node_of[free]]))
    factor = _BandedFlex(stiffness[free][:, free], order, "CS ring")
    flex = factor.flexibility(loads[free])
    info = {**ring.to_dict(), "spaces": [lo, hi], "outer_radius_mm": outer_radius_mm, "band": factor.band}
    return _BodyFlex(flex, int(free.size), factor.band, info, time.perf_counter() - start, dist)


def _cs_flex_substructured(gearset, points, normals, pitch, lo, n_p, top, per_pitch, r_back, outer_radius_mm,
                           tooth_layers, back_layers, tol_mm, start, prepared=None):
    """:func:`_cs_flex` by substructures: space 0 meshed, condensed onto its two radial cuts
    (its outer surface held), and the sector's spaces lo … lo + n_p − 1 (their frames
    turned by the pitch) joined at their cuts, the sector's two end cuts held. ``prepared``:
    a dict that keeps the meshed, condensed space between calls (:func:`_cached`)."""
    from ..rim.toothed import ring_sector_mesh

    prepared = {} if prepared is None else prepared
    if "space" not in prepared:
        ring = ring_sector_mesh(pitch, -0.5 * pitch, [top], [per_pitch], mapped_radius_mm=r_back,
                                polar_radius_mm=outer_radius_mm, mapped_layers=tooth_layers, polar_layers=back_layers,
                                mapped_outside=False, polar_grading=1.6)
        stiffness, ix, iy = _stiffness(ring.mesh, gearset_cs_modulus(gearset), gearset.material.poisson_ratio)
        checkpoint()  # an engine's design stops here when superseded (between the assembly and the condensation)
        outer = np.asarray(ring.outer_nodes)
        left_nodes = np.asarray(ring.start_cut_nodes)[:-1]  # sorted by j: the last is on the held outer surface
        right_nodes = np.asarray(ring.end_cut_nodes)[:-1]
        space = _Pitch(stiffness, np.column_stack([ix[left_nodes], iy[left_nodes]]).ravel(),
                       np.column_stack([ix[right_nodes], iy[right_nodes]]).ravel(), left_nodes.size,
                       _dof_key(ring, ix, iy), pitch, "CS ring (one space)",
                       fixed=np.concatenate([ix[outer], iy[outer]]))
        prepared.update(ring=ring, n_full=stiffness.shape[0], ix=ix, iy=iy, space=space)
    ring, n_full, ix, iy, space = (prepared[k] for k in ("ring", "n_full", "ix", "iy", "space"))
    mesh = ring.mesh
    guess = np.round(np.arctan2(points[:, 0], points[:, 1]) / pitch).astype(int) - lo
    kind = np.zeros(n_p, dtype=int)
    # frames: space lo + k turned by (lo + k) × pitch; the points turned into space lo's first
    turned = _turn_back(points, np.full(points.shape[0], lo * pitch))
    k, triples, weights, dist, ang = _pitch_projection(turned, guess, kind, pitch, [(mesh.doflocs, ring.inner_nodes)])
    bad = np.flatnonzero(dist > tol_mm)
    if bad.size:
        j = int(bad[np.argmax(dist[bad])])
        raise ComplianceError(f"cs_points: point {j} is {dist[j]:.3g} mm off the fitted CS surface (tolerance "
                              f"on_surface_tol_mm = {tol_mm:g} mm)")
    directions = _turn_back(-normals, (k + lo) * pitch)  # the FS pushes the CS along −n_CS
    loads = _load_matrix(n_full, ix, iy, triples, weights, directions).tocsr()
    flex, band = _chain_flex([space], kind, [loads], [(k, np.arange(points.shape[0]))], cyclic=False,
                             where="CS ring (cuts)")
    n_s, n_j = n_p * per_pitch, ring.layers
    dof = 2 * (2 * n_s - 1) * (2 * n_j)  # all nodes but the outer surface's and the two end cuts'
    info = {**_ring_info([ring], kind, ring.time_s), "spaces": [lo, lo + n_p - 1], "outer_radius_mm": outer_radius_mm,
            "band": band, "substructure": "one space condensed onto its cuts; band: the cuts' system"}
    return _BodyFlex(flex, dof, band, info, time.perf_counter() - start, dist)


def _support_flex(flex_bb, act, ball_compliance, face_width_mm, ball_body=None) -> np.ndarray:
    """The active balls' block of the rim's 2D flexibility (mm per N/mm), each ball's spring
    compliance c (mm/N) added as c·b (:func:`spring_block`): a ball load R = λ·b compresses the
    spring by c·R, so the bore there moves by −c·b·λ."""
    block = flex_bb[np.ix_(act, act)]
    if ball_compliance is None:
        return block
    return block + spring_block(ball_compliance, act, ball_body) * face_width_mm


def _race_thickness(value, gear) -> float:
    if value is None:
        return default_race_thickness_mm(gear)
    r_bore = float(gear.neutral_radius_mm) - 0.5 * float(gear.rim_thickness_mm)
    try:
        t = float(value)
    except (TypeError, ValueError) as exc:
        raise ComplianceError(f"race_thickness_mm = {value!r}: must be a number (mm)") from exc
    if isinstance(value, bool) or not (math.isfinite(t) and 0.0 <= t < 0.5 * r_bore):
        raise ComplianceError(f"race_thickness_mm = {value!r} mm: must be finite and in [0, {0.5 * r_bore:.6g}) "
                              "(0 = no outer race; the bound is half the FS bore radius)")
    return t


def gearset_cs_modulus(gearset) -> float:
    """The CS's Young's modulus: the gear set gives one material (the FS's); the CS is
    taken of the same steel."""
    return float(gearset.material.youngs_modulus_mpa)


def wrap_half_angle(rim_contact_angle_rad: float | None, gearset) -> tuple[float, str]:
    """The half angle that selects the candidate balls, and where it comes from: the rim
    stage's no-load contact angle when known, else a linear flat-ring solve."""
    if rim_contact_angle_rad is not None:
        return float(rim_contact_angle_rad), "the rim stage's no-load contact angle"
    from ..geometry import wavegen
    from ..rim.ring import solve_ring

    ring = solve_ring(gearset, contour=wavegen.from_gearset(gearset), layers=4, divisions=64)
    return float(ring.contact_angle_rad), "a linear flat-ring solve on the gear set's contour (4×64)"


def no_load_ball_gap_mm(inputs: ContactInput, theta_rad) -> np.ndarray:
    """The no-load radial gap (mm) between the FS bore and the wave generator's contour over a
    ball at each wave-generator angle ``theta_rad`` (from the major axis): the bore as the
    design's no-load deformation places it (``inputs.motion.deformation``: ω, υ of the neutral
    line, taken for the bore's — the rim's thickness change and the section's rotation are
    left out), its signed distance to the contour (:func:`profilegen.geometry.wavegen.from_gearset`:
    the cam offset by the bearing, i.e. where the outer race's outer surface would be were it
    on the cam), read at each ball's polar angle. ≥ 0 where the rim has left the cam; within
    the rim stage's contact angle it is the fit's error (a few 0.01 µm on the default set,
    design scene; the caller takes 0 there). Negative values (the deformation fit a little
    inside the contour) come back clipped to 0."""
    from ..geometry import wavegen

    gearset = inputs.gearset
    g = gearset.gear
    r_bore = g.neutral_radius_mm - 0.5 * g.rim_thickness_mm
    phi = np.linspace(-math.pi, math.pi, 1441)
    (w, *_), (u, *_) = inputs.motion.deformation.evaluate(phi, order=3)
    e_r = np.column_stack([np.sin(phi), np.cos(phi)])
    e_t = np.column_stack([np.cos(phi), -np.sin(phi)])
    p = (r_bore + w)[:, None] * e_r + u[:, None] * e_t
    _, _, dist = wavegen.from_gearset(gearset).closest(p)
    polar = np.unwrap(np.arctan2(p[:, 0], p[:, 1]))
    th = np.mod(np.asarray(theta_rad, dtype=float) + math.pi, 2.0 * math.pi) - math.pi
    return np.maximum(np.interp(th, polar, dist, period=2.0 * math.pi), 0.0)


def settle_step(active, reactions_n, gaps_mm, *, gap_tol_mm: float = 1e-15):
    """One step of the ball-settling rule (seed 000 steps 4–6): the most tensile active ball
    leaves (the others' reactions change with it, so one at a time); else the inactive ball the
    rim moves into most comes back.

    ``active`` (bool per ball); ``reactions_n``: each ball's reaction (N, > 0 compresses it; an
    inactive ball's is ignored); ``gaps_mm``: each ball's gap after load (mm, < 0: the rim moves
    into it; an active ball's is ignored); a reaction counts as tensile below −1e-12 × the
    largest |reaction| (at least 1 N), a gap as closed below −``gap_tol_mm``.
    Returns (the new active set, a copy; "leave", "return" or None when nothing changes — the
    set is settled). Used by :meth:`ContactCompliance.settle_balls` and the torsional curve's
    continuation (:mod:`profilegen.contact.chain`)."""
    act = np.array(active, dtype=bool)
    react = np.asarray(reactions_n, dtype=float)
    gaps = np.asarray(gaps_mm, dtype=float)
    tol = 1e-12 * max(1.0, float(np.abs(react).max(initial=0.0)))
    pulling = act & (react < -tol)
    if pulling.any():
        act[np.flatnonzero(pulling)[np.argmin(react[pulling])]] = False
        return act, "leave"
    pressed = ~act & (gaps < -gap_tol_mm)
    if pressed.any():
        act[np.flatnonzero(pressed)[np.argmin(gaps[pressed])]] = True
        return act, "return"
    return act, None


def _contact_pairs(fs_points, fs_normals, fs_tooth_index, cs_points, cs_normals):
    """The contact pairs checked (:meth:`ContactCompliance.build`'s arguments): (FS points (n, 2),
    unit FS normals, whole FS tooth indices, CS points, CS normals opposite to the FS ones within
    0.1 rad; −fs_normals when None)."""
    fs_points = _points("fs_points", fs_points)
    n = fs_points.shape[0]
    fs_normals = _unit("fs_normals", fs_normals, n)
    try:
        idx = np.asarray(fs_tooth_index)
        ok = idx.shape == (n,) and np.all(np.isfinite(idx.astype(float))) and np.all(idx == np.round(idx))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ComplianceError(f"fs_tooth_index: must be n = {n} whole numbers (one FS tooth per point), got "
                              f"{np.shape(fs_tooth_index)}")
    tooth_index = np.round(idx).astype(int)
    cs_points = _points("cs_points", cs_points, n)
    cs_normals = -fs_normals if cs_normals is None else _unit("cs_normals", cs_normals, n)
    opposite = np.einsum("ij,ij->i", fs_normals, cs_normals)
    bad = np.flatnonzero(opposite > -math.cos(0.1))
    if bad.size:
        raise ComplianceError(f"cs_normals: row {int(bad[0])} is not opposite to fs_normals (cos = "
                              f"{opposite[bad[0]]:.4g}, must be < −cos 0.1 rad)")
    return fs_points, fs_normals, tooth_index, cs_points, cs_normals


def _ball_phase(ball_phase_rad) -> float:
    """``ball_phase_rad`` as a finite float (rad)."""
    try:
        phase = float(ball_phase_rad)
    except (TypeError, ValueError) as exc:
        raise ComplianceError(f"ball_phase_rad = {ball_phase_rad!r}: must be a number (rad)") from exc
    if not math.isfinite(phase):
        raise ComplianceError(f"ball_phase_rad = {ball_phase_rad!r}: must be finite (rad)")
    return phase


def _wrap(inputs: ContactInput, wrap_half_angle_rad) -> tuple[float, str, list[str]]:
    """The wrap half-angle that selects the candidate balls: (rad, its source, warnings), from
    the rim's no-load contact angle when ``wrap_half_angle_rad`` is None."""
    warnings: list[str] = []
    if wrap_half_angle_rad is None:
        wrap, wrap_source = wrap_half_angle(inputs.rim_contact_angle_rad, inputs.gearset)
        warnings.append("the wrap angle that selects the candidate balls is ill-conditioned (docs/theory/rim.md)")
    else:
        wrap = _positive("wrap_half_angle_rad", wrap_half_angle_rad, "rad")
        if wrap > 0.5 * math.pi:
            raise ComplianceError(f"wrap_half_angle_rad = {wrap!r} rad: must be in (0, π/2]")
        wrap_source = "given"
    return wrap, wrap_source, warnings


def _tooth_frames(inputs: ContactInput, fs_points, fs_normals, tooth_index, shift: float):
    """The FS points and normals back in their teeth's frames (the inverse of
    :mod:`profilegen.contact.points`' placement, WG at ``shift`` rad): (points, normals) (n, 2)."""
    from ..geometry.kinematics import turn

    g = inputs.gearset.gear
    z1, z2 = g.flexspline_teeth, g.circular_spline_teeth
    phi = 2.0 * math.pi * tooth_index / z1 + shift
    pose = inputs.motion.pose(phi)
    angle = 2.0 * math.pi * tooth_index / z2  # one per point
    local = pose.to_tooth(turn(fs_points, -angle))  # an angle per point
    # normal: undo turn(·, angle), then the tooth frame's rotation (to_tooth without the origin)
    n_cs = turn(fs_normals, -angle)  # an angle per point
    c0, s0 = np.cos(pose.angle), np.sin(pose.angle)
    local_n = np.column_stack([n_cs[:, 0] * c0 - n_cs[:, 1] * s0, n_cs[:, 0] * s0 + n_cs[:, 1] * c0])
    return local, local_n


def _candidate_balls(inputs: ContactInput, ball_count: int, phase: float, wrap: float, ball_supports: str):
    """The zone's candidate balls: (their angles from the major axis, sorted; their no-load gaps,
    None for "window"). "window": those within the wrap of θ = 0 (their images cover θ = π);
    "all": the half ring θ in [−π/2, π/2), the others are images, gap 0 within the wrap."""
    k = np.arange(ball_count)
    theta = np.mod(phase + 2.0 * math.pi * k / ball_count + math.pi, 2.0 * math.pi) - math.pi
    if ball_supports == "window":
        return np.sort(theta[np.abs(theta) <= wrap + 1e-12]), None
    balls = np.sort(theta[(theta >= -0.5 * math.pi) & (theta < 0.5 * math.pi)])
    return balls, np.where(np.abs(balls) <= wrap + 1e-12, 0.0, no_load_ball_gap_mm(inputs, balls))


# --------------------------------------------------------------------------- the result


@dataclass(frozen=True)
class ComplianceMesh:
    """The meshes :meth:`ContactCompliance.build` computes the influence coefficients on
    (``mesh=``, in the style of scipy.optimize's ``options=``): the defaults are the product's
    (docs/theory/contact.md, "The influence coefficients"); the rest are accuracy studies.

    FS: ``per_pitch`` columns per pitch on the toothed pitches, ``flat_per_pitch`` on the flat
    rim beyond them, ``rim_layers`` / ``tooth_layers`` layers, ``toothed_teeth`` "all" (every
    pitch toothed) or "loaded" (only the loaded teeth and ``margin_teeth`` on each side),
    ``race_layers`` layers of the bearing's outer race. CS: ``cs_per_pitch``,
    ``cs_tooth_layers``, ``cs_back_layers``, fixed at ``cs_outer_radius_mm`` (default 1.1 × the
    CS pitch radius, ESTIMATE). ``on_surface_tol_mm``: how far a contact point may sit off the
    meshed surface. ``substructure``: condense one pitch of each body onto its cuts and solve
    the cuts (the default); False assembles and factorises the whole meshes (the reference:
    the same model and mesh, the same S to rounding, ~10× slower).
    """

    race_layers: int = 2
    margin_teeth: int = 2
    toothed_teeth: str = "all"
    per_pitch: int = 14
    flat_per_pitch: int = 2
    rim_layers: int = 2
    tooth_layers: int = 4
    cs_per_pitch: int = 16
    cs_tooth_layers: int = 4
    cs_back_layers: int = 3
    cs_outer_radius_mm: float | None = None
    on_surface_tol_mm: float = 0.01
    substructure: bool = True

    @classmethod
    def of(cls, mesh) -> "ComplianceMesh":
        """``mesh`` as a :class:`ComplianceMesh`: None (the defaults), one already, or a mapping of
        its fields (an unknown key is a :class:`ComplianceError` naming it)."""
        return checks.options(cls, mesh, "mesh", error=ComplianceError)


@dataclass(frozen=True, slots=True, eq=False)
class ContactCompliance:
    """Influence coefficients of one engagement zone (the module docstring; the model:
    docs/theory/contact.md, "The influence coefficients").

    ``matrix_mm_per_n``: S (n × n, mm/N, symmetric positive definite) with the active balls
    ``ball_active``; ``fs_matrix_mm_per_n`` / ``cs_matrix_mm_per_n``: its two parts.
    ``ball_angle_rad``: the candidate balls (WG frame, from the major axis; each stands for
    itself and its image at +π). ``tooth``: the FS tooth (= CS space) index of each point.
    ``dof``: {"fs", "cs"}; ``time_s``: {"fs", "cs", "total"}.
    """

    matrix_mm_per_n: np.ndarray
    fs_matrix_mm_per_n: np.ndarray
    cs_matrix_mm_per_n: np.ndarray
    face_width_mm: float
    tooth: np.ndarray
    ball_angle_rad: np.ndarray
    ball_active: np.ndarray
    wrap_half_angle_rad: float
    wrap_source: str
    dof: dict
    time_s: dict
    mesh: dict
    _flex_cc: np.ndarray = field(repr=False)
    _flex_cb: np.ndarray = field(repr=False)
    _flex_bb: np.ndarray = field(repr=False)
    warnings: tuple[str, ...] = ()
    #: radial compliance of each candidate ball's support (mm/N, per ball, e.g. its Hertz
    #: contacts linearised: profilegen.contact.chain); None: rigid supports
    ball_compliance_mm_per_n: np.ndarray | None = None
    #: "window" (the candidate balls are those within the wrap, rigid at zero gap, settled by
    #: :meth:`settle_balls`) or "all" (every ball of the zone a one-sided support at its no-load
    #: gap ``ball_gap_mm``, solved with the teeth by :meth:`solve_unilateral`)
    ball_supports: str = "window"
    #: each candidate ball's no-load radial gap to the bore (mm, ≥ 0; 0 within the wrap); None: all 0
    ball_gap_mm: np.ndarray | None = None
    #: which ball each candidate is (int per candidate): candidates with one number are shares of
    #: one ball (the axial slices' copies, :func:`profilegen.contact.face_curve.stack_slices`),
    #: whose spring carries their summed reaction; None: every candidate its own ball
    ball_body: np.ndarray | None = None
    #: the CS ring's ovalisation at the points (n × n, mm/N, whole face; included in
    #: ``cs_matrix_mm_per_n``: :mod:`profilegen.contact.cs_ring`); None: the sector alone
    cs_ring_mm_per_n: np.ndarray | None = None
    #: the ring it is of (:class:`~profilegen.contact.cs_ring.CSRing`), or None
    cs_ring: CSRing | None = None

    def __post_init__(self):
        for name in ("matrix_mm_per_n", "fs_matrix_mm_per_n", "cs_matrix_mm_per_n", "ball_angle_rad", "_flex_cc",
                     "_flex_cb", "_flex_bb"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        if self.ball_compliance_mm_per_n is not None:
            object.__setattr__(self, "ball_compliance_mm_per_n", _readonly(self.ball_compliance_mm_per_n))
        if self.ball_gap_mm is not None:
            object.__setattr__(self, "ball_gap_mm", _readonly(self.ball_gap_mm))
        if self.ball_body is not None:
            object.__setattr__(self, "ball_body", _readonly(self.ball_body, dtype=np.int64))
        if self.cs_ring_mm_per_n is not None:
            object.__setattr__(self, "cs_ring_mm_per_n", _readonly(self.cs_ring_mm_per_n))
        object.__setattr__(self, "tooth", _readonly(self.tooth, dtype=np.int64))
        object.__setattr__(self, "ball_active", _readonly(self.ball_active, dtype=bool))

    # --- construction ---------------------------------------------------------------
    @classmethod
    def build(
        cls,
        inputs: ContactInput,
        fs_points,
        fs_normals,
        fs_tooth_index,
        cs_points,
        cs_normals=None,
        *,
        face_width_mm: float | None = None,
        race_thickness_mm: float | None = None,
        race_interface: str = "sliding",
        ball_count: int = DEFAULT_BALL_COUNT,
        ball_phase_rad: float = 0.0,
        wrap_half_angle_rad: float | None = None,
        settle_iterations: int = 0,
        forces_n=None,
        shift_rad: float = 0.0,
        ball_supports: str = "window",
        mesh: ComplianceMesh | Mapping | None = None,
        cs_ring: bool = True,
    ) -> "ContactCompliance":
        """Influence coefficients for the contact points of one engagement zone.

        ``inputs``: a :class:`~profilegen.contact.inputs.ContactInput` (gear set, FS tooth,
        motion, fitted CS space, the rim's no-load contact angle; ``ContactInput.from_design``).
        ``fs_points`` (n, 2): FS points at their no-load positions, CS frame (mm);
        ``fs_normals`` (n, 2): unit common normals, out of the FS tooth; ``fs_tooth_index`` (n,): FS tooth i of each point (it stands in CS space i, WG at
        ψ = 0); ``cs_points`` (n, 2): the CS partner points (CS frame); ``cs_normals``:
        the CS surface's outward normals (default −fs_normals; must be opposite to them
        within 0.1 rad). ``face_width_mm``: b (default the gear set's ``cup.face_width_mm``,
        whose own default is 0.2 × the pitch diameter,
        ESTIMATE). ``race_thickness_mm``: the wave-generator bearing's outer race under the
        FS bore (default :func:`default_race_thickness_mm`, ESTIMATE; 0 = no race, the balls
        on the bore); ``race_interface``: "sliding" (joined radially only, frictionless; the
        default) or "bonded" (race and bore share their nodes). All balls within the wrap start
        active; ``forces_n`` with ``settle_iterations`` > 0 runs :meth:`settle_balls` for those
        contact forces. ``mesh``: the meshes and their solve, a :class:`ComplianceMesh` or a
        mapping of its fields (default: the product's). ``shift_rad``: every FS tooth i at 2πi/z1 + shift from the
        major axis (another wave-generator position, as ``contact_points(shift_rad=…)`` places
        the points): the points are mapped back with it, and the balls (``ball_phase_rad`` and
        the wrap, from the major axis) sit at −shift in the rim's frame.
        ``ball_supports``: "window" (the candidate balls are those within the wrap, rigid at
        zero gap; the default) or "all" (every ball of the zone, |θ| < π/2, a one-sided
        support at its no-load gap :func:`no_load_ball_gap_mm`, 0 within the wrap; the balls
        within the wrap start active; solve with :meth:`solve_unilateral`). ``cs_ring``: add the
        CS ring's ovalisation under both zones' forces to the CS block (the default;
        :mod:`profilegen.contact.cs_ring`, a free thin ring) — False: the sector alone, held at
        its outer radius (a study's or a model's own ring, as the ratcheting climb's).
        """
        start = time.perf_counter()
        grid = ComplianceMesh.of(mesh)
        inputs = ContactInput.of(inputs, error=ComplianceError)
        gearset = inputs.gearset
        g = gearset.gear
        if g.waves != 2:
            raise ComplianceError(f"gearset.gear.waves = {g.waves}: the point-symmetric half ring needs U = 2")
        fs_points, fs_normals, tooth_index, cs_points, cs_normals = _contact_pairs(
            fs_points, fs_normals, fs_tooth_index, cs_points, cs_normals)
        n = fs_points.shape[0]
        b = gearset.cup.face_width_mm if face_width_mm is None else _positive("face_width_mm", face_width_mm, "mm")
        ball_count = _whole("ball_count", ball_count, 3)
        phase = _ball_phase(ball_phase_rad)
        margin = _whole("margin_teeth", grid.margin_teeth, 0)
        race = _race_thickness(race_thickness_mm, g)
        race_layers = _whole("race_layers", grid.race_layers, 1)
        if race_interface not in ("bonded", "sliding"):
            raise ComplianceError(f"race_interface = {race_interface!r}: must be 'bonded' or 'sliding'")
        if ball_supports not in ("window", "all"):
            raise ComplianceError(f"ball_supports = {ball_supports!r}: must be 'window' (the balls within the wrap, "
                                  "rigid, zero gap) or 'all' (every ball one-sided at its no-load gap)")
        if grid.toothed_teeth not in ("loaded", "all"):
            raise ComplianceError(f"toothed_teeth = {grid.toothed_teeth!r}: must be 'loaded' or 'all'")
        tol = _positive("on_surface_tol_mm", grid.on_surface_tol_mm, "mm")
        settle_iterations = _whole("settle_iterations", settle_iterations, 0)
        cs_outer_radius_mm = _positive("cs_outer_radius_mm", 1.1 * g.cs_pitch_radius_mm
                                       if grid.cs_outer_radius_mm is None else grid.cs_outer_radius_mm, "mm")
        wrap, wrap_source, warnings = _wrap(inputs, wrap_half_angle_rad)
        shift = float(shift_rad)
        local, local_n = _tooth_frames(inputs, fs_points, fs_normals, tooth_index, shift)
        balls, ball_gap = _candidate_balls(inputs, ball_count, phase, wrap, ball_supports)

        with one_blas_thread():
            fs = _fs_flex(inputs.tooth, gearset, local, local_n, tooth_index, balls - shift, margin=margin,
                          toothed_teeth=grid.toothed_teeth, per_pitch=_whole("per_pitch", grid.per_pitch, 2),
                          flat_per_pitch=_whole("flat_per_pitch", grid.flat_per_pitch, 1),
                          rim_layers=_whole("rim_layers", grid.rim_layers, 1),
                          tooth_layers=_whole("tooth_layers", grid.tooth_layers, 1), tol_mm=tol,
                          race_thickness_mm=race, race_layers=race_layers,
                          race_sliding=race_interface == "sliding", substructure=bool(grid.substructure))
            checkpoint()  # an engine's design stops here when superseded (between the FS and the CS)
            cs = _cs_flex(inputs.cs_space, gearset, cs_points, cs_normals, margin=margin,
                          per_pitch=_whole("cs_per_pitch", grid.cs_per_pitch, 2),
                          tooth_layers=_whole("cs_tooth_layers", grid.cs_tooth_layers, 1),
                          back_layers=_whole("cs_back_layers", grid.cs_back_layers, 1),
                          outer_radius_mm=cs_outer_radius_mm, tol_mm=tol, substructure=bool(grid.substructure))
            checkpoint()
            ring = ring_s = None
            cs_flex = cs.flex
            if cs_ring:
                try:
                    ring = CSRing.of(inputs, width_mm=b)
                except CSRingError as exc:
                    raise ComplianceError(str(exc)) from exc
                ring_s = contact_ring_compliance(ring, cs_points, fs_normals, zones=g.waves)
                cs_flex = cs.flex + ring_s * b  # the sector's flexibility is per unit width, the ring's whole-face
            nb = balls.size
            # inside the single-threaded block too: OpenBLAS's threads took 0.46 s for this 196 × 196
            # Cholesky on the busy machine (cProfile), against milliseconds on one thread
            result = cls._assemble(
                flex_cc=fs.flex[:n, :n], flex_cb=fs.flex[:n, n:], flex_bb=fs.flex[n:, n:], cs_flex=cs_flex,
                face_width_mm=b, tooth=tooth_index, ball_angle_rad=balls,
                ball_active=np.ones(nb, bool) if ball_gap is None else ball_gap <= 0.0,
                wrap_half_angle_rad=wrap, wrap_source=wrap_source,
                dof={"fs": fs.dof, "cs": cs.dof}, time_s={"fs": fs.time_s, "cs": cs.time_s},
                mesh={"fs": fs.mesh, "cs": cs.mesh, "fs_off_surface_max_mm": float(fs.off_surface_mm.max()),
                      "cs_off_surface_max_mm": float(cs.off_surface_mm.max())},
                warnings=tuple(warnings), start=start, ball_supports=ball_supports, ball_gap=ball_gap,
                cs_ring_matrix=ring_s, cs_ring=ring)
        if settle_iterations and forces_n is not None:
            result = result.settle_balls(forces_n, max_iterations=settle_iterations)
        return result

    @classmethod
    def _assemble(cls, *, flex_cc, flex_cb, flex_bb, cs_flex, face_width_mm, tooth, ball_angle_rad, ball_active,
                  wrap_half_angle_rad, wrap_source, dof, time_s, mesh, warnings, start=None, ball_compliance=None,
                  ball_supports="window", ball_gap=None, ball_body=None, cs_ring_matrix=None, cs_ring=None):
        act = np.flatnonzero(ball_active)
        fs2d = flex_cc.copy()
        if act.size:
            from scipy.linalg import cho_factor, cho_solve

            fa = cho_factor(_support_flex(flex_bb, act, ball_compliance, face_width_mm, ball_body))
            fs2d = fs2d - flex_cb[:, act] @ cho_solve(fa, flex_cb[:, act].T)
        fs_s = 0.5 * (fs2d + fs2d.T) / face_width_mm
        cs_s = cs_flex / face_width_mm
        total = fs_s + cs_s
        try:
            np.linalg.cholesky(total)
        except np.linalg.LinAlgError as exc:
            raise ConvergenceError("ContactCompliance: S is not positive definite (two contact points coincide, or "
                                   "a rigid-body mode is left)") from exc
        times = dict(time_s)
        if start is not None:
            times["total"] = time.perf_counter() - start
        return cls(total, fs_s, cs_s, face_width_mm, tooth, ball_angle_rad, ball_active, wrap_half_angle_rad,
                   wrap_source, dict(dof), times, mesh, flex_cc, flex_cb, flex_bb, tuple(warnings), ball_compliance,
                   ball_supports, ball_gap, ball_body, cs_ring_matrix, cs_ring)

    # --- balls ------------------------------------------------------------------------
    @property
    def count(self) -> int:
        return int(self.matrix_mm_per_n.shape[0])

    def _forces(self, forces_n) -> np.ndarray:
        f = np.asarray(forces_n, dtype=float)
        if f.shape != (self.count,) or not np.all(np.isfinite(f)):
            raise ComplianceError(f"forces_n: must be {self.count} finite contact forces (N), got shape {f.shape}")
        return f

    def ball_reactions(self, forces_n) -> np.ndarray:
        """Radial reaction of every candidate ball on the rim (N, > 0 pushes the rim
        outward, i.e. the ball is compressed; 0 for a dropped ball) for contact forces
        ``forces_n`` (N, along the common normals, ≥ 0 compressive) in this zone (the same
        in the image zone)."""
        f = self._forces(forces_n)
        out = np.zeros(self.ball_angle_rad.size)
        act = np.flatnonzero(self.ball_active)
        if act.size:
            flex = _support_flex(self._flex_bb, act, self.ball_compliance_mm_per_n, self.face_width_mm, self.ball_body)
            out[act] = -np.linalg.solve(flex, self._flex_cb[:, act].T @ f)
        return out

    def ball_gaps_mm(self, forces_n) -> np.ndarray:
        """Outward radial displacement of the bore at every candidate ball (mm; < 0: the rim
        moves into the ball) under ``forces_n``; 0 at an active rigid ball, −c·R at an active
        ball of compliance c (its spring compressed by its reaction R)."""
        f = self._forces(forces_n) / self.face_width_mm
        lam = self.ball_reactions(forces_n) / self.face_width_mm
        return self._flex_cb.T @ f + self._flex_bb @ lam

    def with_balls(self, active, *, ball_compliance_mm_per_n=False) -> "ContactCompliance":
        """The same points with another set of active balls (no new factorisation).
        ``ball_compliance_mm_per_n``: the radial compliance of every candidate ball's support
        (mm/N, one per ball or one for all, ≥ 0; None: rigid); not given: keep this one's.
        A ball of compliance c enters the Schur step as a spring: the ball block of the rim's
        flexibility gets c·b on its diagonal (b the face width: the 2D flexibility is per
        unit line load)."""
        act = np.asarray(active, dtype=bool)
        if act.shape != self.ball_angle_rad.shape:
            raise ComplianceError(f"active: must be {self.ball_angle_rad.size} booleans (one per candidate ball)")
        if ball_compliance_mm_per_n is False:
            springs = self.ball_compliance_mm_per_n
        elif ball_compliance_mm_per_n is None:
            springs = None
        else:
            springs = checks.finite_array("ball_compliance_mm_per_n", ball_compliance_mm_per_n, "mm/N",
                                          error=ComplianceError)
            springs = np.broadcast_to(springs, self.ball_angle_rad.shape).astype(float) if springs.ndim == 0 \
                else springs
            if springs.shape != self.ball_angle_rad.shape or np.any(springs < 0.0):
                raise ComplianceError(f"ball_compliance_mm_per_n: must be one number or {self.ball_angle_rad.size} "
                                      "numbers ≥ 0 (mm/N, one per candidate ball)")
        return self._assemble(
            flex_cc=self._flex_cc, flex_cb=self._flex_cb, flex_bb=self._flex_bb,
            cs_flex=self.cs_matrix_mm_per_n * self.face_width_mm, face_width_mm=self.face_width_mm, tooth=self.tooth,
            ball_angle_rad=self.ball_angle_rad, ball_active=act, wrap_half_angle_rad=self.wrap_half_angle_rad,
            wrap_source=self.wrap_source, dof=self.dof, time_s=self.time_s, mesh=self.mesh, warnings=self.warnings,
            ball_compliance=springs, ball_supports=self.ball_supports, ball_gap=self.ball_gap_mm,
            ball_body=self.ball_body, cs_ring_matrix=self.cs_ring_mm_per_n, cs_ring=self.cs_ring)

    def settle_balls(self, forces_n, *, max_iterations: int = 20, solve=None) -> "ContactCompliance":
        """Seed 000 steps 4–6 for the balls: drop the balls that pull, take back the dropped
        balls the rim moves into, until the set no longer changes.

        ``forces_n``: the contact forces (N). ``solve``: optional callable S → forces (the
        contact solve of step 5, re-run with every new S); without it the forces are held.
        Raises ConvergenceError if the set still changes after ``max_iterations``."""
        max_iterations = _whole("max_iterations", max_iterations, 1)
        if self.ball_supports == "all":
            raise ComplianceError("settle_balls: this compliance has ball_supports = 'all' (every ball one-sided at "
                                  "its no-load gap); solve it with solve_unilateral, which takes the gaps into "
                                  "account (settle_balls would put every ball at zero gap)")
        current = self
        f = current._forces(forces_n)
        seen = {tuple(current.ball_active)}
        for _ in range(max_iterations):
            active, change = settle_step(current.ball_active, current.ball_reactions(f), current.ball_gaps_mm(f))
            if change is None:
                return current
            if tuple(active) in seen and change == "return":
                raise ConvergenceError("ContactCompliance.settle_balls: the ball set cycles")
            seen.add(tuple(active))
            current = current.with_balls(active)
            if solve is not None:
                f = current._forces(solve(current.matrix_mm_per_n))
        raise ConvergenceError(f"ContactCompliance.settle_balls: the ball set still changes after {max_iterations} "
                               f"iterations ({int(current.ball_active.sum())} of {current.ball_active.size} active)")

    def solve_unilateral(self, theta_rad, lever_mm, torque_nmm: float, *, bearing=None, spring_tol: float = 1e-6,
                         max_iterations: int = 200):
        """The contact of one zone with every candidate ball a one-sided support at its gap
        (``ball_gap_mm``, 0 if None), teeth and balls in one complementarity problem, solved
        exactly (no settling loop).

        Unknowns: the tooth forces F ≥ 0 (N, one per point), the ball reactions R ≥ 0 (N,
        > 0 pushes the rim outward) and the rotation φ. With the rim's flexibility between
        tooth loads and ball loads (the blocks of :meth:`build`'s FS solve, S = S_2D/b; a
        ball's spring compliance c, if any, on its diagonal) and the CS's:

            g_k = r_k (θ_k − φ) + (S_cc F + C_cb R)_k ≥ 0 ⊥ F_k ≥ 0     (teeth)
            h_b = gap_b + (C_bc F + C_bb R)_b ≥ 0 ⊥ R_b ≥ 0             (balls: h the gap after load)
            Σ r_k F_k = T                                                (the zone's torque)

        the KKT conditions of min ½ xᵀCx + eᵀx over x = (F, R) ≥ 0, Σ rF = T (C positive
        definite): unique F, R and φ. Solved by Lemke's method on the LCP with φ − θ_min ≥ 0
        as in :func:`~profilegen.contact.solvers.solve_lemke` (the relaxation Σ rF ≥ T has the
        same solution), scaled to numbers of order one, and the final basis reinverted.
        ``theta_rad`` (n, ≥ 0) and ``lever_mm`` (n, > 0): the points' first-contact angles and
        lever arms (:class:`~profilegen.contact.points.ContactPoints` ``theta_rad``,
        ``lever_mm``); ``torque_nmm``: the zone's torque (N·mm).

        ``bearing``: a :class:`~profilegen.contact.chain.BallBearing` (anything with
        ``secant_compliance_mm_per_n(reactions)``): each ball a Hertz spring, its secant
        compliance δ(R)/R at its own reaction, iterated to a fixed point (geometric mean of
        the old and new secants; ``spring_tol`` on their log, at most ``max_iterations``, else
        a ConvergenceError); at the fixed point each loaded ball's spring is compressed by
        exactly δ(R). Without it the balls keep this compliance's springs (rigid if none).

        Returns (the teeth's :class:`~profilegen.contact.solvers.ContactSolution`, the ball
        reactions R (N), the balls' gaps after load h (mm)); the solution's
        ``complementarity_residual`` covers the balls too (max |R h| on the same scale)."""
        if bearing is None:
            return self._solve_unilateral(theta_rad, lever_mm, torque_nmm, self.ball_compliance_mm_per_n)
        tol = _positive("spring_tol", spring_tol, "")
        cap = _whole("max_iterations", max_iterations, 1)
        sol, reaction, gap = self._solve_unilateral(theta_rad, lever_mm, torque_nmm, None)
        springs = np.asarray(bearing.secant_compliance_mm_per_n(ball_totals(reaction, self.ball_body)), dtype=float)
        for it in range(1, cap + 1):
            sol, reaction, gap = self._solve_unilateral(theta_rad, lever_mm, torque_nmm, springs)
            new = np.asarray(bearing.secant_compliance_mm_per_n(ball_totals(reaction, self.ball_body)), dtype=float)
            change = float(np.max(np.abs(np.log(new / springs))))
            if change <= tol:
                diagnostics = {**sol.diagnostics, "spring_iterations": it, "ball_compliance_mm_per_n": springs.tolist()}
                return replace(sol, diagnostics=diagnostics), reaction, gap
            springs = np.sqrt(springs * new)
        raise ConvergenceError(f"ContactCompliance.solve_unilateral: the Hertz ball springs still change by "
                               f"{change:.3g} (log) after {cap} iterations (spring_tol = {tol:g})")

    def _solve_unilateral(self, theta_rad, lever_mm, torque_nmm, springs):
        """:meth:`solve_unilateral` with the ball springs ``springs`` (mm/N per ball, or None: rigid)."""
        from .solvers import ContactSolution, scale_problem

        t0 = time.perf_counter()
        b = self.face_width_mm
        s_cc = 0.5 * (self._flex_cc + self._flex_cc.T) / b + self.cs_matrix_mm_per_n
        # checks θ, r, T and S (named errors) on the teeth's S with the balls at zero gap held, as the
        # window's solve checks it: S_cc alone (the rim free of every ball) is worse conditioned by the
        # ring's near-rigid modes (rcond 9.6e-13 at 13 stations per flank on the default set), which
        # the ball rows of the LCP below hold
        p = scale_problem(self.matrix_mm_per_n, theta_rad, lever_mm, torque_nmm)
        theta, r, torque = p.theta, p.r, p.T
        n, nb = theta.size, self.ball_angle_rad.size
        c_bb = self._flex_bb / b
        if springs is not None:
            c_bb = c_bb + spring_block(np.broadcast_to(np.asarray(springs, dtype=float), (nb,)), np.arange(nb),
                                       self.ball_body)
        full = np.block([[s_cc, self._flex_cb / b], [self._flex_cb.T / b, 0.5 * (c_bb + c_bb.T)]])
        gap_b = np.zeros(nb) if self.ball_gap_mm is None else np.asarray(self.ball_gap_mm, dtype=float)
        # scales: force X = T / r̄, compliance c0 = mean S_kk, length L = c0 X, rotation ψ = (φ − θ_min) r̄ / L
        r_bar = float(r.mean())
        force = torque / r_bar
        c0 = float(np.mean(np.diag(s_cc)))
        length = c0 * force
        nt = n + nb
        m_mat = np.zeros((nt + 1, nt + 1))
        m_mat[:nt, :nt] = full / c0
        m_mat[:n, nt] = -r / r_bar
        m_mat[nt, :n] = r / r_bar
        q = np.concatenate([r * (theta - p.theta_min) / length, gap_b / length, [-1.0]])
        where = "ContactCompliance.solve_unilateral"
        basic, pivots = lemke_lcp(m_mat, q, where)
        if basic.size == 0 or basic[-1] != nt:
            raise ConvergenceError(f"{where}: the rotation is not in the final basis after {pivots} pivots")
        # reinversion: the loaded teeth and balls and ψ, solved directly
        k = basic.size
        sol = np.linalg.solve(m_mat[np.ix_(basic, basic)], np.concatenate([-q[basic[:-1]], [1.0]]))
        z = np.zeros(nt + 1)
        z[basic[:-1]] = sol[:k - 1]
        z[nt] = sol[k - 1]
        if k > 1 and float(np.min(z[basic[:-1]])) < -1e-9:
            raise ConvergenceError(f"{where}: the final basis is not feasible after reinversion (min force "
                                   f"{float(np.min(z[basic[:-1]])):.3g}, scaled)")
        z[:nt] = np.maximum(z[:nt], 0.0)
        w = m_mat @ z + q
        if float(np.min(w[:nt])) < -1e-9 * (1.0 + abs(z[nt])):
            raise ConvergenceError(f"{where}: the final basis leaves a penetration after reinversion (gap "
                                   f"{float(np.min(w[:nt])):.3g}, scaled)")
        f = force * z[:n]
        reaction = force * z[n:nt]
        phi = p.theta_min + z[nt] * length / r_bar
        gap = length * w[:n]
        gap_after = length * w[n:nt]
        tau = p.tau
        comp = max(float(np.max(np.abs(f * gap))), float(np.max(np.abs(reaction * gap_after), initial=0.0))) / (
            torque * (abs(phi - p.theta_min) + tau))
        loaded = f > 0.0
        warnings = []
        if np.all(loaded):
            warnings.append(f"all {n} candidate points are loaded: the torque {torque:.6g} N·mm has used up the "
                            "contact points given; points not in the list (further teeth or flank) would close too")
        solution = ContactSolution(
            method="lemke (teeth and one-sided balls)", torque_nmm=torque, force_n=f, moment_nmm=r * f, phi_rad=phi,
            gap_mm=gap, loaded=loaded, iterations=pivots, complementarity_residual=comp,
            equilibrium_residual=abs(float(np.sum(r * f)) - torque) / torque, time_s=time.perf_counter() - t0,
            all_points_loaded=bool(np.all(loaded)), warnings=tuple(warnings),
            diagnostics={"tau_rad": tau, "theta_min_rad": p.theta_min, "points": n, "balls": nb,
                         "balls_loaded": int(np.count_nonzero(reaction > 0.0))})
        return solution, reaction, gap_after

    # --- reporting -------------------------------------------------------------------
    def per_tooth_diagonal(self) -> dict[int, float]:
        """The mean diagonal S_kk of each tooth (mm/N)."""
        d = np.diag(self.matrix_mm_per_n)
        return {int(t): float(d[self.tooth == t].mean()) for t in np.unique(self.tooth)}

    def to_dict(self) -> dict:
        d = np.diag(self.matrix_mm_per_n)
        return {
            "model": "plane-stress FEM: FS point-symmetric toothed half ring on the bearing's outer race (if any) on "
                     "radial ball supports, bore mean "
                     "rotation held; CS toothed sector fixed outside; S = S_2D / b"
                     + ("; + the CS ring's ovalisation under both zones' forces (a free thin ring)"
                        if self.cs_ring is not None else ""),
            "count": self.count,
            "face_width_mm": self.face_width_mm,
            "diagonal_mm_per_n": {"min": float(d.min()), "max": float(d.max())},
            "fs_diagonal_mm_per_n": {"min": float(np.diag(self.fs_matrix_mm_per_n).min()),
                                     "max": float(np.diag(self.fs_matrix_mm_per_n).max())},
            "cs_diagonal_mm_per_n": {"min": float(np.diag(self.cs_matrix_mm_per_n).min()),
                                     "max": float(np.diag(self.cs_matrix_mm_per_n).max())},
            "cs_ring": None if self.cs_ring is None or self.cs_ring_mm_per_n is None else {
                **self.cs_ring.to_dict(), "diagonal_mm_per_n": {"min": float(np.diag(self.cs_ring_mm_per_n).min()),
                                                                "max": float(np.diag(self.cs_ring_mm_per_n).max())}},
            "ball_angle_deg": np.degrees(self.ball_angle_rad).tolist(),
            "ball_active": self.ball_active.tolist(),
            "wrap_half_angle_deg": math.degrees(self.wrap_half_angle_rad),
            "wrap_source": self.wrap_source,
            "dof": dict(self.dof),
            "time_s": dict(self.time_s),
            "mesh": self.mesh,
            "warnings": list(self.warnings),
        }
