"""Linear 2D plane-stress ring FEM on a rigid wave-generator contour (scikit-fem).

The flexspline rim is modelled as a flat ring (no teeth) between r_in = r_m − δ/2 and
r_out = r_m + δ/2, pressed outward by a rigid contour (:mod:`profilegen.geometry.wavegen`) through
unilateral, frictionless contact between the bore nodes and the contour, along the
contour's true normal.

Model
-----
* Quarter ring 0 ≤ θ ≤ π/2 (θ from the major axis, +y, toward +x; a point is
  (r sin θ, r cos θ)). This needs the two symmetry planes of a two-wave generator: U = 2
  only. Other wave counts need a sector 0 ≤ θ ≤ π/U whose second cut is not a coordinate
  axis, i.e. a rotated (normal-only) Dirichlet condition — not implemented.
* Symmetry: on the cut at the major axis (θ = 0, x = 0) u_x = 0; on the cut at the minor
  axis (θ = π/2, y = 0) u_y = 0. This removes the rigid-body modes.
* Structured isoparametric 9-node quadrilaterals (``MeshQuad2`` + ``ElementQuad2``, every
  node on its exact radius): ``layers`` (even) radial layers × ``divisions`` circumferential
  divisions. Plane stress (the linear stiffness is that of ``linear_elasticity`` with
  λ* = 2λμ/(λ + 2μ), assembled as the tangent of :mod:`profilegen.rim.nonlinear` at rest). Forces are per mm of
  face width (N/mm).
* Contact: every bore node against the contour, unilateral and frictionless. The gap of
  a node is linearised at the current configuration, g = g_k + n·(u − u_k) (g_k the signed
  distance of X + u_k to the contour, n the contour normal at its foot), so the contour's
  curvature is followed. With the stiffness condensed onto the bore dofs (the compliance
  G = P K⁻¹ Pᵀ, 2 columns per bore node; K with the symmetry dofs removed, factorised
  once: banded Cholesky after reverse Cuthill–McKee, SuperLU with COLAMD if it is not
  positive definite) the contact is the linear complementarity problem w = Sλ − q ≥ 0,
  λ ≥ 0, λ·w = 0 with S_ij = n_i·G_ij·n_j, solved exactly as a non-negative least-squares
  problem (:func:`_contact_set`); only the gap linearisation is iterated. (A primal–dual
  active-set iteration cycled on the default set once the nonlinear corrections moved
  the µm-close free part of the ring.) A contact that does not settle in
  ``max_iterations`` re-linearisations raises :class:`~profilegen.errors.ConvergenceError`
  naming the deepest penetration and its angle. ``condense_within_rad`` (the verify tier's
  toothed rim) condenses onto the bore nodes of the wrap + a margin only — the columns of
  K⁻¹ for those nodes give every bore node's displacement, so the gaps of the dropped nodes
  are checked from the full displacement; a converged contact that needs a dropped node (or
  loads the outermost kept one) widens the kept set and solves again (logged). 1601 bore
  nodes of the default toothed rim, 1228 of them kept (θ ≤ 69°). A bore of more than
  :data:`LAZY_BORE_NODES` nodes (the toothed rim) is not condensed up front: G's columns are
  solved as the contact solve asks for them (:class:`_LazyCompliance`; the LCP by
  Lawson–Hanson's active-set method, :func:`profilegen.lcp.active_set_lazy`, one node entering at a time, warm
  from the last set) — ~80–150 nodes' columns per factor instead of all 1228.
* Geometry: ``"linear"`` (small strain, ``linear_elasticity``) or ``"nonlinear"`` (total
  Lagrangian St Venant–Kirchhoff, :mod:`profilegen.rim.nonlinear`): modified Newton from
  the linear solution with the linear factorisation and compliance; a step that shrinks by
  less than half refreshes both with the tangent at the current state.
* ω, υ are read on the node line at r_m (the neutral line of the flat ring;
  probes do not work on quadratic meshes): ω = u·e_r, υ = u·e_θ, e_r = (sin θ, cos θ),
  e_θ = (cos θ, −sin θ) (toward increasing θ). Vertex and mid-edge nodes are both read,
  2·divisions + 1 samples on 0 ≤ φ ≤ π/2.

The contact (wrap) angle — the angle of the last active bore node from the major axis —
is ill-conditioned: the free part of the ring sits µm from the cam (docs/theory/rim.md), so a
tiny change of load or mesh moves it a lot. It is reported with that warning.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field, replace
from functools import partial
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from .. import checks
from ..geometry import series
from ..blas import one_blas_thread
from ..errors import ConvergenceError, ProfilegenError
from ..lcp import active_set_lazy, principal_pivoting, spd_nnls
from ..results import readonly as _readonly

if TYPE_CHECKING:  # pragma: no cover
    from ..gearset import GearSet
    from ..geometry.wavegen import Contour

__all__ = ["ConvergenceError", "RingError", "RingParameters", "RingResult", "solve_ring"]

log = logging.getLogger(__name__)

WRAP_WARNING = (
    "the contact (wrap) angle is ill-conditioned: the free part of the ring sits µm from the cam, "
    "so it moves with mesh and load far more than ω and υ do"
)


class RingError(ProfilegenError, ValueError):
    """Bad input to the ring model; the message names the field, its value, unit and allowed range."""


_number = partial(checks.number, error=RingError)
_whole = partial(checks.whole, error=RingError)


@dataclass(frozen=True, slots=True, eq=False)
class RingParameters:
    """The inputs of the ring model (mm, MPa). ``from_gearset`` reads them from a GearSet."""

    neutral_radius_mm: float
    rim_thickness_mm: float
    youngs_modulus_mpa: float
    poisson_ratio: float
    waves: int = 2

    def __post_init__(self):
        r_m = _number("neutral_radius_mm", self.neutral_radius_mm, "mm", 0.0)
        delta = _number("rim_thickness_mm", self.rim_thickness_mm, "mm", 0.0, 2.0 * r_m)
        e = _number("youngs_modulus_mpa", self.youngs_modulus_mpa, "MPa", 0.0)
        nu = _number("poisson_ratio", self.poisson_ratio, "", -1.0, 0.5)
        if self.waves != 2:
            raise RingError(
                f"waves = {self.waves!r}: the quarter-ring model needs U = 2 (a sector π/U with a rotated "
                "symmetry cut is not implemented)"
            )
        for name, value in (("neutral_radius_mm", r_m), ("rim_thickness_mm", delta),
                            ("youngs_modulus_mpa", e), ("poisson_ratio", nu)):
            object.__setattr__(self, name, value)

    @classmethod
    def from_gearset(cls, gearset) -> RingParameters:
        gear, mat = gearset.gear, gearset.material
        return cls(gear.neutral_radius_mm, gear.rim_thickness_mm, mat.youngs_modulus_mpa, mat.poisson_ratio,
                   waves=gear.waves)

    @property
    def bore_radius_mm(self) -> float:
        return self.neutral_radius_mm - 0.5 * self.rim_thickness_mm

    @property
    def outer_radius_mm(self) -> float:
        return self.neutral_radius_mm + 0.5 * self.rim_thickness_mm



@dataclass(frozen=True, slots=True, eq=False)
class RingResult:
    """Solution of the ring on its contour (mm, N per mm of face width, rad).

    ``phi_rad``, ``omega_mm``, ``upsilon_mm``: samples on the node line at r_m, 0 ≤ φ ≤ π/2.
    ``bore_*``: the same on the bore (r_in). ``contact_*``: the active bore nodes (angle,
    normal force λ ≥ 0 pushing the ring outward, and the contour normal it acts along —
    that of the last linearisation, which differs from the final foot's by ≲ 1e-8). ``reaction_*_n``: the
    sum of the reactions on the symmetry cuts (x on the major-axis cut, y on the
    minor-axis cut).
    """

    parameters: RingParameters
    contour: object
    phi_rad: np.ndarray
    omega_mm: np.ndarray
    upsilon_mm: np.ndarray
    bore_phi_rad: np.ndarray
    bore_omega_mm: np.ndarray
    bore_upsilon_mm: np.ndarray
    contact_phi_rad: np.ndarray
    contact_force_n: np.ndarray
    contact_normal: np.ndarray
    max_gap_mm: float
    max_penetration_mm: float
    reaction_major_cut_n: float
    reaction_minor_cut_n: float
    layers: int
    divisions: int
    dof: int
    iterations: int
    bilateral: bool
    time_s: float
    warnings: tuple[str, ...] = ()
    active_history: tuple[int, ...] = field(default=())
    geometry: str = "linear"
    tier: str = "linear flat ring FEM"
    newton_steps_mm: tuple[float, ...] = ()
    node_theta_rad: np.ndarray = field(default_factory=lambda: np.zeros(0))
    node_radius_mm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    node_omega_mm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    node_upsilon_mm: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self):
        for name in ("phi_rad", "omega_mm", "upsilon_mm", "bore_phi_rad", "bore_omega_mm", "bore_upsilon_mm",
                     "contact_phi_rad", "contact_force_n", "contact_normal", "node_theta_rad", "node_radius_mm",
                     "node_omega_mm", "node_upsilon_mm"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        object.__setattr__(self, "warnings", tuple(self.warnings))

    @property
    def active_count(self) -> int:
        return int(self.contact_phi_rad.size)

    @property
    def contact_angle_rad(self) -> float:
        """Angle of the last active bore node from the major axis (ill-conditioned; see warnings)."""
        return float(self.contact_phi_rad.max()) if self.contact_phi_rad.size else 0.0

    @property
    def contact_angle_deg(self) -> float:
        return math.degrees(self.contact_angle_rad)

    def at_radius(self, radius_mm: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(φ, ω, υ) at radius ``radius_mm`` instead of the neutral line, at the neutral-line angles.

        Inside the part of the mesh whose node rows are whole circles (the flat ring from
        bore to outer surface; the toothed rim from bore to r_m) the finite-element field
        itself: quadratic in r along each node column, exactly as the 9-node elements
        interpolate it. Beyond (the pitch circle, in the teeth or above a flat rim):
        plane sections stay plane and normal (Kirchhoff), ω(r) = ω_m and
        υ(r) = υ_m + (r − r_m)(υ_m − ω′_m)/r_m, ω′_m from a cubic spline of the neutral
        samples (at the pitch circle υ differs from the neutral line by ~16 µm: docs/theory/rim.md).
        """
        from scipy.interpolate import CubicSpline

        r = _number("radius_mm", radius_mm, "mm", 0.0)
        phi = self.phi_rad
        cols = phi.size
        keys = np.round(self.node_radius_mm, 9)
        radii, counts = np.unique(keys, return_counts=True)
        rows = radii[counts >= cols]
        tol = 1e-9 * max(r, 1.0)
        if rows.size >= 3 and rows[0] - tol <= r <= rows[-1] + tol:
            table_w = np.empty((rows.size, cols))
            table_u = np.empty((rows.size, cols))
            for k, rk in enumerate(rows):
                sel = np.flatnonzero(keys == rk)
                order = np.argsort(self.node_theta_rad[sel])
                sel = sel[order][np.searchsorted(self.node_theta_rad[sel][order], phi - 1e-12)]
                table_w[k], table_u[k] = self.node_omega_mm[sel], self.node_upsilon_mm[sel]
            first = min(2 * int((r - rows[0]) / (rows[2] - rows[0])), rows.size - 3)  # element rows 2k … 2k + 2
            x = rows[first:first + 3]
            basis = [np.prod([(r - x[j]) / (x[i] - x[j]) for j in range(3) if j != i]) for i in range(3)]
            return (phi.copy(), sum(b * table_w[first + i] for i, b in enumerate(basis)),
                    sum(b * table_u[first + i] for i, b in enumerate(basis)))
        r_m = self.parameters.neutral_radius_mm
        slope = CubicSpline(phi, self.omega_mm)(phi, 1)
        return phi.copy(), self.omega_mm.copy(), self.upsilon_mm + (r - r_m) * (self.upsilon_mm - slope) / r_m

    @property
    def deflection_mm(self) -> float:
        """ω(0) on the neutral line (mm)."""
        return float(self.omega_mm[0])

    def deformation(self, order: int | None = None, *, tier: str = "design"):
        """Integer-harmonic Fourier fit (:func:`profilegen.geometry.series.fit_fourier`) of the samples
        mirrored to one wave period 0 ≤ φ < π: ω even and υ odd about both axes of symmetry
        (ω(π − φ) = ω(φ), υ(π − φ) = −υ(φ))."""
        phi, w, u = self.phi_rad, self.omega_mm, self.upsilon_mm
        inner = slice(1, -1)  # π − 0 = π is φ = 0 of the next period; π − π/2 is π/2 again
        phi_full = np.concatenate([phi, math.pi - phi[inner][::-1]])
        w_full = np.concatenate([w, w[inner][::-1]])
        u_full = np.concatenate([u, -u[inner][::-1]])
        return series.fit_fourier(phi_full, w_full, u_full, waves=self.parameters.waves, order=order,
                                  tier=tier)

    def to_dict(self) -> dict:
        contour = self.contour.to_dict() if hasattr(self.contour, "to_dict") else repr(self.contour)
        return {
            "tier": self.tier,
            "model": (f"{self.geometry} plane-stress FEM ({'St Venant–Kirchhoff, total Lagrangian' if self.geometry == 'nonlinear' else 'small strain'}), "
                      "quarter, unilateral frictionless contact (active set)"),
            "geometry": self.geometry,
            "newton_steps_mm": list(self.newton_steps_mm),
            "neutral_radius_mm": self.parameters.neutral_radius_mm,
            "rim_thickness_mm": self.parameters.rim_thickness_mm,
            "youngs_modulus_mpa": self.parameters.youngs_modulus_mpa,
            "poisson_ratio": self.parameters.poisson_ratio,
            "contour": contour,
            "layers": self.layers,
            "divisions": self.divisions,
            "dof": self.dof,
            "iterations": self.iterations,
            "bilateral": self.bilateral,
            "active_count": self.active_count,
            "active_history": list(self.active_history),
            "contact_angle_deg": self.contact_angle_deg,
            "deflection_mm": self.deflection_mm,
            "max_gap_mm": self.max_gap_mm,
            "max_penetration_mm": self.max_penetration_mm,
            "reaction_major_cut_n": self.reaction_major_cut_n,
            "reaction_minor_cut_n": self.reaction_minor_cut_n,
            "time_s": self.time_s,
            "phi_rad": self.phi_rad.tolist(),
            "omega_mm": self.omega_mm.tolist(),
            "upsilon_mm": self.upsilon_mm.tolist(),
            "warnings": list(self.warnings),
        }


def _mesh(params: RingParameters, layers: int, divisions: int):
    from skfem import MeshQuad, MeshQuad2

    theta = np.linspace(0.0, 0.5 * math.pi, divisions + 1)
    radii = np.linspace(params.bore_radius_mm, params.outer_radius_mm, layers + 1)
    linear = MeshQuad.init_tensor(theta, radii)  # (θ, r) → (r sin θ, r cos θ) keeps orientation (det = r)
    quad = MeshQuad2.from_mesh(linear)
    th, r = quad.doflocs
    return replace(quad, doflocs=np.vstack([r * np.sin(th), r * np.cos(th)])), th, r


GEOMETRIES = ("linear", "nonlinear")


class StiffnessFactor:
    """Factorisation of a symmetric stiffness matrix for many right-hand sides.

    Ordered around the ring (``order``; reverse Cuthill–McKee if not given) a ring's matrix
    is banded (bandwidth ~ 2 × nodes across the rim), and LAPACK's banded Cholesky then solves the 2·(bore nodes) right-hand sides of
    the condensation ~2.5× faster than SuperLU (measured on the default ring, 4 × 64). A
    matrix that is not positive definite (a tangent past a limit point) falls back to
    SuperLU with COLAMD ordering."""

    def __init__(self, matrix, order=None):
        from scipy.linalg import LinAlgError, cholesky_banded
        from scipy.sparse.csgraph import reverse_cuthill_mckee

        matrix = sp.csr_matrix(matrix)
        self.perm = reverse_cuthill_mckee(matrix, symmetric_mode=True) if order is None else np.asarray(order)
        permuted = matrix[self.perm][:, self.perm].tocoo()
        upper = permuted.row <= permuted.col
        rows, cols = permuted.row[upper], permuted.col[upper]
        band = int(np.max(cols - rows, initial=0))
        self.banded = None
        self.lu = None
        self._blocks = None
        if band < 0.25 * matrix.shape[0]:
            ab = np.zeros((band + 1, matrix.shape[0]))
            ab[band + rows - cols, cols] = permuted.data[upper]
            try:
                self.banded = cholesky_banded(ab, check_finite=False)
            except LinAlgError:
                self.banded = None
        if self.banded is None:
            self.lu = splu(matrix.tocsc(), permc_spec="COLAMD")

    def solve_many(self, rhs, block: int | None = None):
        """:meth:`solve` for many right-hand sides (columns of ``rhs``) by block substitution:
        the band factor U (K = UᵀU, bandwidth b ≤ ``block``; default b, the least work: 1.23 s
        against 1.55 s with 128-row blocks for 512 columns of a 28818-row band-81 factor, one
        thread) cut into ``block``-row blocks is
        block bidiagonal, so each block row is one triangular solve and one matrix product over
        all columns at once (BLAS 3) where LAPACK's banded solve (``dpbtrs``) walks the columns
        one at a time. The forward pass starts at the first block row with a non-zero entry
        (unit right-hand sides of the condensation). Same result to rounding."""
        if self.lu is not None:
            return self.lu.solve(rhs)
        from scipy.linalg import solve_triangular

        band = self.banded.shape[0] - 1
        n = self.banded.shape[1]
        block = max(int(block or band), band, 1)
        if self._blocks is None or self._blocks[0] != block:
            starts = np.arange(0, n, block)
            diag, upper = [], []
            for k, a in enumerate(starts):
                e = min(a + block, n)
                i, j = np.meshgrid(np.arange(a, e), np.arange(a, e), indexing="ij")
                ok = (j >= i) & (j - i <= band)
                d = np.zeros((e - a, e - a))
                d[ok] = self.banded[band + i[ok] - j[ok], j[ok]]
                diag.append(d)
                if e < n:
                    e2 = min(e + block, n)
                    i, j = np.meshgrid(np.arange(a, e), np.arange(e, e2), indexing="ij")
                    ok = j - i <= band
                    o = np.zeros((e - a, e2 - e))
                    o[ok] = self.banded[band + i[ok] - j[ok], j[ok]]
                    upper.append(o)
            self._blocks = (block, starts, diag, upper)
        _, starts, diag, upper = self._blocks
        rhs = np.asarray(rhs, dtype=float)
        y = np.ascontiguousarray(rhs[self.perm])
        nz = np.flatnonzero(np.any(y != 0.0, axis=1))
        first = 0 if nz.size == 0 else int(nz[0]) // block
        y[:starts[first]] = 0.0
        for k in range(first, starts.size):  # Uᵀ y = b
            a, e = starts[k], min(starts[k] + block, n)
            if k > first:
                y[a:e] -= upper[k - 1].T @ y[starts[k - 1]:a]
            y[a:e] = solve_triangular(diag[k], y[a:e], trans="T", check_finite=False)
        for k in range(starts.size - 1, -1, -1):  # U x = y
            a, e = starts[k], min(starts[k] + block, n)
            if e < n:
                y[a:e] -= upper[k] @ y[e:min(e + block, n)]
            y[a:e] = solve_triangular(diag[k], y[a:e], check_finite=False)
        out = np.empty_like(y)
        out[self.perm] = y
        return out

    def solve(self, rhs):
        if self.lu is not None:
            return self.lu.solve(rhs)
        from scipy.linalg import cho_solve_banded

        rhs = np.asarray(rhs, dtype=float)
        out = np.empty_like(rhs)
        out[self.perm] = cho_solve_banded((self.banded, False), rhs[self.perm], check_finite=False)
        return out


#: below this many right-hand sides LAPACK's banded solve (~6 ms a column on the toothed rim) beats
#: the block substitution (~2.8 ms a column plus ~45 ms a call)
_FEW_COLUMNS = 16
#: bore nodes above which solve_ring solves the compliance's columns lazily (lazy_columns=None)
LAZY_BORE_NODES = 256


class _DenseCompliance:
    """The bore compliance G (n_b, 2, n_k, 2) of the first n_k bore nodes as one solved array
    (every column condensed up front): what :func:`_contact_set` reads through ``take`` /
    ``apply`` / ``dense``, the same interface as :class:`_LazyCompliance`."""

    def __init__(self, array):
        self.array = array

    def take(self, nodes):
        """G's columns of the kept ``nodes``: (n_b, 2, len(nodes), 2)."""
        return self.array[:, :, nodes]

    def apply(self, force):
        """The bore's displacement (n_b, 2) under the forces (n_k, 2) on the kept nodes."""
        return np.einsum("iajb,jb->ia", self.array, force)

    def dense(self, n_k: int):
        return self.array


class _LazyCompliance:
    """The bore compliance G = P K⁻¹ Pᵀ (rows: every bore dof; columns: bore node j's x and y)
    solved column pair by column pair when a contact solve first asks for it, and kept.

    The contact needs G's columns only where a force acts — the active set and the nodes a
    pivoting step tries (~80–150 of the toothed rim's 1228 kept nodes) — so condensing every
    kept node (2456 right-hand sides of a 28818-row band, two factors per mesh) was most of
    the verify tier's rim time. The columns are the same solves as the up-front condensation's
    (one BLAS thread; :meth:`StiffnessFactor.solve_many`, or the banded solve for a few), unsymmetrised (G_ij and G_ji agree to
    rounding). ``dense(n_k)`` solves every missing column of the first ``n_k`` nodes (the NNLS
    fallback) and returns the up-front condensation's array, kept block symmetrised."""

    def __init__(self, factor, n_b: int, rhs_rows, out_rows, out_cols, n_free: int):
        self.factor = factor
        self.n_b = int(n_b)
        self._rhs_rows = rhs_rows  # free-dof index of bore dof c (−1: fixed by symmetry, a zero column)
        self._out_rows, self._out_cols = out_rows, out_cols  # the free bore dofs: rows of the solution, G's rows
        self._n_free = int(n_free)
        self._cols = np.zeros((2 * self.n_b, 2 * self.n_b))  # row c: G's column c (untouched pages stay unallocated)
        self._have = np.zeros(self.n_b, dtype=bool)
        self.solves = 0  # column pairs solved (for the record)

    def _solve(self, nodes):
        dofs = (2 * nodes[:, None] + np.arange(2)).ravel()
        dofs = dofs[self._rhs_rows[dofs] >= 0]
        if dofs.size:
            rhs = np.zeros((self._n_free, dofs.size))
            rhs[self._rhs_rows[dofs], np.arange(dofs.size)] = 1.0
            with one_blas_thread():  # LAPACK's banded solve for a few columns, block substitution for many
                sol = (self.factor.solve if dofs.size < _FEW_COLUMNS else self.factor.solve_many)(rhs)
            self._cols[np.ix_(dofs, self._out_cols)] = sol[self._out_rows].T
        self._have[nodes] = True
        self.solves += int(nodes.size)

    def take(self, nodes):
        nodes = np.asarray(nodes, dtype=int).ravel()
        missing = np.unique(nodes[~self._have[nodes]])
        if missing.size:
            self._solve(missing)
        c = (2 * nodes[:, None] + np.arange(2)).ravel()
        return self._cols[c].T.reshape(self.n_b, 2, nodes.size, 2)

    def apply(self, force):
        loaded = np.flatnonzero(np.any(force != 0.0, axis=1))
        if loaded.size == 0:
            return np.zeros((self.n_b, 2))
        return np.einsum("iajb,jb->ia", self.take(loaded), force[loaded])

    def dense(self, n_k: int):
        array = self.take(np.arange(n_k)).copy().reshape(2 * self.n_b, 2 * n_k)
        kept_block = array[:2 * n_k]
        kept_block[...] = 0.5 * (kept_block + kept_block.T)
        return array.reshape(self.n_b, 2, n_k, 2)


def s_columns(normal, compliance, n: int):
    """The contact LCP's columns for :mod:`profilegen.lcp`: S_ij = n_i·G_ij·n_j of the first ``n``
    bore nodes (``compliance`` = G, a :class:`_DenseCompliance` or :class:`_LazyCompliance`;
    each S_ij the same 4-term sum whichever columns are formed with it)."""

    def columns_of(nodes):
        return np.einsum("ia,iajb,jb->ij", normal, compliance.take(nodes)[:n], normal[nodes])

    return columns_of


class _Widen(Exception):
    """The contact condensed onto a prefix of the bore nodes reached its edge (or a dropped
    node would be loaded): ``reach`` is the number of bore nodes it needs at least."""

    def __init__(self, reach: int, why: str):
        super().__init__(why)
        self.reach = int(reach)


def _edge(active, dist, n_k: int):
    """A contact solved on the first ``n_k`` bore nodes is the whole bore's when no dropped
    node penetrates the cam (its gap, from the full displacement, ≥ 0) and the outermost kept
    node is free; otherwise a :class:`_Widen` saying how far it reached (None if it holds)."""
    if n_k >= active.size:
        return None
    bad = np.flatnonzero(dist[n_k:] < 0.0)
    if not (active[n_k - 1] or bad.size):
        return None
    why = ["the outermost kept node is loaded"] if active[n_k - 1] else []
    if bad.size:
        why.append(f"{bad.size} dropped node(s) penetrate the cam (deepest {-np.min(dist[n_k:]):.3g} mm)")
    return _Widen(n_k if bad.size == 0 else n_k + int(bad[-1]) + 1, " and ".join(why))


def _contact_set(compliance, base, x_now, contour, *, bilateral, gap_tol_mm, max_iterations, where, kept=None,
                 strict=True, warm=None):
    """Contact of the bore nodes (current positions ``x_now``) with ``contour`` for a
    linear(ised) body whose bore displacement is ``base + G f`` (G = ``compliance``, f the
    bore forces, f_j = λ_j n_j; ``compliance``: a :class:`_DenseCompliance` or, for a large bore,
    a :class:`_LazyCompliance`, whose columns are solved as the contact asks for them).

    With the gap linearised at the current iterate d_k — g_i(d) = g_i(d_k) + n_i·(d − d_k),
    n_i the contour normal at the foot of x_i + d_k — the unilateral contact of *every*
    bore node is the linear complementarity problem w = Sλ − q ≥ 0, λ ≥ 0, λ·w = 0 with
    S_ij = n_i·G_ij·n_j (symmetric positive definite) and q_i = n_i·(d_k − base_i) − g_i(d_k).
    It is the convex QP min ½λᵀSλ − qᵀλ, λ ≥ 0, solved exactly as the non-negative least
    squares problem min |Lᵀλ − L⁻¹q| (S = LLᵀ; Lawson–Hanson, finite termination). A
    primal–dual active-set iteration was tried first: on the default set it cycles (nodes
    µm-close to the cam near the end of the wrap switch back and forth). The outer loop only
    re-linearises the gap (normals and distances) until every loaded node is on the contour
    and no free node penetrates, within ``gap_tol_mm``. ``bilateral``: S λ = q, every node
    held. Returns (λ per node, active mask λ > 0, normals used, gaps, bore forces (n, 2),
    iterations, active-set sizes).

    ``kept``: only the first ``kept`` bore nodes (in θ, from the major axis) may carry a
    force; ``compliance`` then holds the columns of those nodes only (every bore
    node's displacement under forces on the kept ones, exact: the condensation is exact for
    the nodes kept). The iteration converges on the kept nodes; its state is a solution of
    the whole bore's contact when, in addition, no dropped node penetrates the cam (its gap
    from the full displacement ≥ 0) and the outermost kept node is free. Otherwise
    :class:`_Widen` is raised (the caller widens the kept set and solves again) — if
    ``strict``; else the caller checks (:func:`_edge`): a Newton iterate before the last may
    reach past the kept nodes (only the converged state must not).

    ``warm``: a guess of the active set of the first ``kept`` nodes (the last call's): each
    linearisation first tries its set (then the last iteration's) by :func:`profilegen.lcp.principal_pivoting`
    and solves by NNLS only if that fails — the same unique solution, without NNLS's
    Lawson–Hanson iterations from an empty set (0.18 s a call on the toothed rim's 1228 kept
    nodes).
    """
    n_b = base.shape[0]
    n_k = n_b if kept is None else int(kept)
    if bilateral and n_k < n_b:
        raise _Widen(n_b, "bilateral contact holds every bore node")
    disp = base.copy()
    normal, dist = contour.closest(x_now + disp)[1:]
    history: list[int] = []
    guess = None if warm is None or bilateral else np.asarray(warm, dtype=bool)[:n_k]
    for iteration in range(1, max_iterations + 1):
        q_all = np.einsum("ij,ij->i", disp - base, normal) - dist
        q = q_all[:n_k]
        if isinstance(compliance, _LazyCompliance):
            forces = None if bilateral else active_set_lazy(s_columns(normal[:n_k], compliance, n_k), q,
                                                            max_steps=4 * n_k, guess=guess)
        else:
            forces = None if guess is None else principal_pivoting(s_columns(normal[:n_k], compliance, n_k), q, guess)
        try:
            if forces is not None:
                pass
            elif bilateral:
                compliance4 = compliance.dense(n_k)
                schur = np.einsum("ia,iajb,jb->ij", normal[:n_k], compliance4[:n_k], normal[:n_k])
                forces = np.linalg.solve(schur, q)
            else:
                compliance4 = compliance.dense(n_k)
                forces = spd_nnls(np.einsum("ia,iajb,jb->ij", normal[:n_k], compliance4[:n_k], normal[:n_k]), q)
        except (np.linalg.LinAlgError, RuntimeError) as exc:
            raise ConvergenceError(
                f"solve_ring: contact problem not solvable at iteration {iteration} ({exc}); the contact "
                "compliance of the bore nodes is singular or the NNLS solver stopped"
            ) from exc
        if not np.all(np.isfinite(forces)):
            raise ConvergenceError(f"solve_ring: non-finite contact forces at iteration {iteration}")
        if n_k < n_b:
            forces = np.concatenate([forces, np.zeros(n_b - n_k)])
        active = np.ones(n_b, bool) if bilateral else forces > 0.0
        if not bilateral:
            guess = active[:n_k]
        history.append(int(active.sum()))
        bore_force = forces[:, None] * normal
        used_normal = normal
        disp = base + compliance.apply(bore_force[:n_k])
        normal, dist = contour.closest(x_now + disp)[1:]
        closed = np.max(np.abs(dist[active]), initial=0.0) <= gap_tol_mm
        if closed and (bilateral or np.min(dist[:n_k][~active[:n_k]], initial=0.0) >= -gap_tol_mm):
            if strict and (edge := _edge(active, dist, n_k)) is not None:
                raise edge
            return forces, active, used_normal, dist, bore_force, iteration, history
    raise ConvergenceError(
        f"solve_ring: the contact gaps did not close in {max_iterations} re-linearisations "
        f"({int(active.sum())} loaded nodes, largest gap error {np.max(np.abs(dist[active]), initial=0.0):.3g} mm, "
        f"deepest penetration of a free node {-np.min(dist[~active], initial=0.0):.3g} mm at φ = "
        f"{np.degrees(where[np.argmin(np.where(active, np.inf, dist))]):.4f}°)"
    )


def _ring_mesh(params: RingParameters, layers: int, divisions: int, mesh):
    """The rim's mesh, node angles θ and radii r, and its kind: the flat ring's
    ``layers`` × ``divisions`` mesh when ``mesh`` is None, else the given (MeshQuad2, θ, r)."""
    if mesh is None:
        mesh, th, r = _mesh(params, layers, divisions)
        return mesh, th, r, "flat"
    try:
        mesh, th, r = mesh
    except (TypeError, ValueError) as exc:
        raise RingError("mesh: must be a (MeshQuad2, θ, r) triple (see rim.toothed)") from exc
    return mesh, np.asarray(th, dtype=float), np.asarray(r, dtype=float), "toothed"


@dataclass
class _RingSystem:
    """The quarter rim's assembled problem: the body and its linear stiffness, the symmetry
    cuts, the free dofs in band order with their factor, and the bore nodes with the maps
    between their dofs and the free dofs."""

    mesh: Any
    th: np.ndarray
    ix: np.ndarray
    iy: np.ndarray
    body: Any
    stiffness: Any
    n_dof: int
    tol_r: float
    cut_major: np.ndarray
    cut_minor: np.ndarray
    free: np.ndarray
    where: np.ndarray
    band_order: np.ndarray
    lu: Any
    bore: np.ndarray
    x_bore: np.ndarray
    n_b: int
    bore_dofs: np.ndarray
    select: Any
    rows_free: np.ndarray
    cols_free: np.ndarray

    def lazy_compliance(self, factor) -> _LazyCompliance:
        """The bore compliance of ``factor``, its columns solved as the contact asks for them."""
        return _LazyCompliance(factor, self.n_b, self.where[self.bore_dofs], self.rows_free, self.cols_free,
                               self.free.size)


def _assemble_ring(params: RingParameters, mesh, th, r) -> _RingSystem:
    """Assemble and factor the rim's linear stiffness with the symmetry cuts fixed, and find
    the bore nodes (sorted by θ) and the selection of their free dofs."""
    from skfem import Basis, ElementQuad2, ElementVector

    from .nonlinear import TotalLagrangian

    basis = Basis(mesh, ElementVector(ElementQuad2()), intorder=4)
    ix, iy = basis.split_indices()  # scalar node j ↔ dofs ix[j], iy[j]; positions mesh.doflocs[:, j]
    # the linear stiffness is the St Venant–Kirchhoff tangent at rest (equal to scikit-fem's
    # linear_elasticity with the plane-stress λ* = 2λμ/(λ + 2μ) to rounding, tests/unit/
    # test_rim_nonlinear.py), assembled by batched matrix products: 4 ms against 17 ms
    body = TotalLagrangian(basis, params.youngs_modulus_mpa, params.poisson_ratio)
    stiffness = body(np.zeros(basis.N))[0]
    n_dof = basis.N

    tol_r = 1e-9 * params.outer_radius_mm
    cut_major = np.flatnonzero(np.abs(th) < 1e-12)  # x = 0
    cut_minor = np.flatnonzero(np.abs(th - 0.5 * math.pi) < 1e-12)  # y = 0
    fixed = np.concatenate([ix[cut_major], iy[cut_minor]])
    free = np.setdiff1d(np.arange(n_dof), fixed)
    where = -np.ones(n_dof, dtype=int)
    where[free] = np.arange(free.size)
    # band-friendly order: node by node around the ring (θ, then r) — bandwidth 81 against
    # reverse Cuthill–McKee's 133 on the toothed rim
    node_of = np.empty(n_dof, dtype=int)
    node_of[ix], node_of[iy] = np.arange(ix.size), np.arange(iy.size)
    band_order = np.lexsort((r[node_of[free]], np.round(th[node_of[free]], 12)))
    # BLAS single-threaded: OpenBLAS's threaded banded Cholesky took 14 s against 0.14 s on one
    # thread for the default toothed rim (28818 dof, band 81) on a busy 2-core machine, and 5.7 s
    # CPU for the 2 × 32 flat ring of the verify tier's wrap pass at load 10 (0.18 s on one thread)
    with one_blas_thread():
        lu = StiffnessFactor(stiffness[free][:, free], order=band_order)

    bore = np.flatnonzero(np.abs(r - params.bore_radius_mm) < tol_r)
    bore = bore[np.argsort(th[bore])]
    x_bore = mesh.doflocs[:, bore].T
    n_b = bore.size
    # condense onto the bore: G = P K⁻¹ Pᵀ, the compliance between the bore dofs
    # (x, y of node j at 2j, 2j + 1; zero rows/columns for dofs fixed by symmetry)
    bore_dofs = np.column_stack([ix[bore], iy[bore]]).ravel()
    is_free = where[bore_dofs] >= 0
    select = sp.csr_matrix((np.ones(int(is_free.sum())), (where[bore_dofs[is_free]], np.flatnonzero(is_free))),
                           shape=(free.size, 2 * n_b))
    rows_free = where[bore_dofs[is_free]]
    cols_free = np.flatnonzero(is_free)
    return _RingSystem(mesh=mesh, th=th, ix=ix, iy=iy, body=body, stiffness=stiffness, n_dof=n_dof, tol_r=tol_r,
                       cut_major=cut_major, cut_minor=cut_minor, free=free, where=where, band_order=band_order,
                       lu=lu, bore=bore, x_bore=x_bore, n_b=n_b, bore_dofs=bore_dofs, select=select,
                       rows_free=rows_free, cols_free=cols_free)


def _condense(system: _RingSystem, factor, n_k: int, *, block_solve: bool, done=None, chunk: int = 512):
    """The compliance columns of the first ``n_k`` bore nodes, every bore node's rows:
    (n_b, 2, n_k, 2), the kept block symmetrised. ``done``: columns already solved with
    this factor (a narrower kept set's raw columns), reused."""
    n_b, cols_free, where, bore_dofs = system.n_b, system.cols_free, system.where, system.bore_dofs
    # in column blocks: the full K⁻¹P would be (free dofs × 2 n_b) doubles, 0.7 GB on the toothed rim
    compliance = np.zeros((2 * n_b, 2 * n_k))
    first = 0 if done is None else done.shape[1]
    if first:
        compliance[:, :first] = done
    todo = cols_free[(cols_free >= first) & (cols_free < 2 * n_k)]
    # the wrap mode solves its columns by block substitution, single-threaded (BLAS 3 on
    # bandwidth-row blocks; threads only contend on a busy machine); the whole-bore mode as before
    solve = factor.solve_many if block_solve else factor.solve
    with one_blas_thread():
        for start_col in range(0, todo.size, chunk):
            cols = todo[start_col:start_col + chunk]
            rhs = np.zeros((system.free.size, cols.size))
            rhs[where[bore_dofs[cols]], np.arange(cols.size)] = 1.0
            compliance[np.ix_(cols_free, cols)] = solve(rhs)[system.rows_free]
    raw = compliance.copy() if n_k < n_b else None
    kept_block = compliance[:2 * n_k]
    kept_block[...] = 0.5 * (kept_block + kept_block.T)
    return compliance.reshape(n_b, 2, n_k, 2), raw


def _newton_press(system: _RingSystem, compliance, u, active, iterations: int, history, n_k: int, *, contour,
                  bilateral: bool, gap_tol_mm: float, max_iterations: int, newton_tol_mm: float, lazy: bool,
                  block_solve: bool):
    """Newton iterations of the nonlinear body from the linear solution ``u`` (updated in
    place) with the contact in the same step; raises :class:`_Widen` if the converged
    contact needs a dropped bore node. Returns the contact, the counts and the reaction."""
    body, free, select, bore, n_b = system.body, system.free, system.select, system.bore, system.n_b
    ix, iy = system.ix, system.iy
    newton_steps: list[float] = []
    factor, refreshes = system.lu, 0
    for newton in range(1, max_iterations + 1):
        f_int = body.force(u)
        du = factor.solve(-f_int[free])  # the response to the out-of-balance force
        base = (select.T @ du).reshape(n_b, 2)
        if not np.all(np.isfinite(base)):
            raise ConvergenceError(f"solve_ring (nonlinear): non-finite Newton step at iteration {newton}")
        x_now = system.x_bore + np.column_stack([u[ix[bore]], u[iy[bore]]])
        forces, active, used_normal, dist, bore_force, its, hist = _contact_set(
            compliance, base, x_now, contour, bilateral=bilateral, gap_tol_mm=gap_tol_mm,
            max_iterations=max_iterations, where=system.th[bore], kept=n_k, strict=False, warm=active)
        iterations += its
        history += hist
        du += factor.solve(select @ bore_force.ravel())
        step = float(np.max(np.abs(du)))
        if not np.isfinite(step):
            raise ConvergenceError(f"solve_ring (nonlinear): non-finite Newton step at iteration {newton}")
        if newton_steps and step > 0.5 * newton_steps[-1]:
            # the linear stiffness contracts too slowly (or not at all: a ring on a few
            # point supports): refresh the tangent and its bore compliance at the current u,
            # and redo the step from there
            refreshes += 1
            tangent, _ = body(u)
            try:
                factor = StiffnessFactor(tangent[free][:, free], order=system.band_order)
            except RuntimeError as exc:  # splu: "Factor is exactly singular"
                raise ConvergenceError(f"solve_ring (nonlinear): singular tangent at Newton iteration {newton}") from exc
            compliance = (system.lazy_compliance(factor) if lazy
                          else _DenseCompliance(_condense(system, factor, n_k, block_solve=block_solve)[0]))
            newton_steps.append(float("nan"))  # marks the refresh in the record
            continue
        u[free] += du
        newton_steps.append(step)
        if step <= newton_tol_mm:
            # converged: its contact must not need a dropped node (an iterate before may)
            if (edge := _edge(active, dist, n_k)) is not None:
                raise edge
            break
    else:
        raise ConvergenceError(
            f"solve_ring (nonlinear): no convergence in {max_iterations} Newton iterations ({refreshes} tangent "
            "refreshes; last steps " + ", ".join(f"{x:.2e}" for x in newton_steps[-4:]) + " mm)"
        )
    newton_steps = [x for x in newton_steps if np.isfinite(x)]
    contact = np.zeros(system.n_dof)
    contact[ix[bore]] = forces * used_normal[:, 0]
    contact[iy[bore]] = forces * used_normal[:, 1]
    reaction = body.force(u) - contact
    return forces, active, used_normal, dist, iterations, history, newton_steps, reaction


def _press(system: _RingSystem, n_k: int, lu_columns, *, contour, bilateral: bool, gap_tol_mm: float,
           max_iterations: int, geometry: str, newton_tol_mm: float, lazy: bool, block_solve: bool):
    """The contact solve (linear, then Newton) with the compliance of the first ``n_k``
    bore nodes; raises :class:`_Widen` if the contact needs more of them. ``lu_columns``:
    the linear factor's raw columns so far (a :class:`_LazyCompliance` when ``lazy``), kept
    across widenings; returned updated with the result."""
    n_b, bore = system.n_b, system.bore
    compliance: _LazyCompliance | _DenseCompliance
    if lazy:  # one record of the linear factor's columns across widenings (its rows are every bore node's)
        if lu_columns is None:
            lu_columns = system.lazy_compliance(system.lu)
        compliance = lu_columns
    else:
        compliance4, lu_columns = _condense(system, system.lu, n_k, block_solve=block_solve, done=lu_columns)
        compliance = _DenseCompliance(compliance4)
    forces, active, used_normal, dist, bore_force, iterations, history = _contact_set(
        compliance, np.zeros((n_b, 2)), system.x_bore, contour, bilateral=bilateral, gap_tol_mm=gap_tol_mm,
        max_iterations=max_iterations, where=system.th[bore], kept=n_k, strict=geometry == "linear")
    u = np.zeros(system.n_dof)
    u[system.free] = system.lu.solve(system.select @ bore_force.ravel())
    reaction = system.stiffness @ u
    newton_steps: list[float] = []
    if geometry == "nonlinear":
        forces, active, used_normal, dist, iterations, history, newton_steps, reaction = _newton_press(
            system, compliance, u, active, iterations, history, n_k, contour=contour, bilateral=bilateral,
            gap_tol_mm=gap_tol_mm, max_iterations=max_iterations, newton_tol_mm=newton_tol_mm, lazy=lazy,
            block_solve=block_solve)
    return (u, forces, active, used_normal, dist, iterations, history, newton_steps, reaction), lu_columns


def _press_widening(press, system: _RingSystem, condense_within_rad: float | None):
    """Run ``press(n_kept, lu_columns)`` on the bore nodes with θ ≤ ``condense_within_rad``
    (every bore node when None), widening the kept set until the contact stays inside it.
    Returns the press's result and the number of kept nodes."""
    n_b, th, bore = system.n_b, system.th, system.bore
    widenings: list[tuple[int, int]] = []
    # the linear factor's raw columns, kept across widenings: lazy, a _LazyCompliance; else condense's
    # raw columns (None before the first, and when every bore node is kept)
    lu_columns: Any = None
    if condense_within_rad is None:
        n_kept = n_b
    else:
        limit = _number("condense_within_rad", condense_within_rad, "rad", 0.0)
        n_kept = min(n_b, max(2, int(np.searchsorted(th[bore], limit, side="right"))))
    while True:
        try:
            with one_blas_thread():
                result, lu_columns = press(n_kept, lu_columns)
            break
        except _Widen as exc:
            wider = min(n_b, max(exc.reach + (n_kept + 3) // 4, (3 * n_kept + 1) // 2))
            log.info("solve_ring: contact condensed onto %d of %d bore nodes (θ ≤ %.4g°) reached its edge (%s): "
                     "widened to %d nodes (θ ≤ %.4g°) and solved again", n_kept, n_b,
                     math.degrees(th[bore[n_kept - 1]]), exc, wider, math.degrees(th[bore[wider - 1]]))
            widenings.append((n_kept, wider))
            n_kept = wider
    if n_kept < n_b:
        log.debug("solve_ring: contact condensed onto %d of %d bore nodes (θ ≤ %.4g°), %d widening(s)", n_kept,
                  n_b, math.degrees(th[bore[n_kept - 1]]), len(widenings))
    return result, n_kept


def _polar(th, u, ix, iy, nodes):
    """θ and the radial ω, tangential υ displacements of ``nodes``."""
    t = th[nodes]
    ux, uy = u[ix[nodes]], u[iy[nodes]]
    return t, ux * np.sin(t) + uy * np.cos(t), ux * np.cos(t) - uy * np.sin(t)


def solve_ring(
    gearset_or_parameters: GearSet | RingParameters,
    *,
    contour: Contour,
    layers: int = 4,
    divisions: int = 64,
    bilateral: bool = False,
    max_iterations: int = 50,
    gap_tol_mm: float = 1e-9,
    geometry: str = "linear",
    newton_tol_mm: float = 1e-10,
    mesh: Iterable[Any] | None = None,
    tier: str | None = None,
    condense_within_rad: float | None = None,
    lazy_columns: bool | None = None,
) -> RingResult:
    """Press the flat rim onto ``contour`` and return ω, υ on the neutral line.

    ``gearset_or_parameters``: a GearSet or :class:`RingParameters`. ``layers`` (even, so
    that a node line lies at r_m) × ``divisions`` quadratic elements on the quarter ring.
    ``bilateral=True`` keeps every bore node on the contour (tension allowed: a prescribed
    bore shape, as ring theory assumes), otherwise the contact is unilateral.
    ``gap_tol_mm`` is the allowed penetration / residual gap of active nodes.

    ``geometry="nonlinear"``: after the linear solution, Newton iterations on the total
    Lagrangian St Venant–Kirchhoff body (:mod:`profilegen.rim.nonlinear`) with the contact
    constraints in the same saddle system (Lagrange multipliers, sparse LU with COLAMD),
    re-linearising the gap and updating the active set at every iteration; converged when
    the Newton correction is below ``newton_tol_mm``, the set is unchanged and every active
    gap is closed. A set that recurs at a converged Newton state raises ConvergenceError.

    ``mesh``: ``(MeshQuad2, θ, r)`` of another rim (e.g. :func:`profilegen.rim.toothed.
    toothed_quarter_mesh`) with exact node lines at r_bore and r_m and straight cuts at θ = 0
    and θ = π/2 (``layers``/``divisions`` then only label the result).
    ``tier``: the label recorded in ``to_dict()`` (default: from geometry and mesh).

    ``condense_within_rad``: condense the stiffness only onto the bore nodes with θ ≤ this
    angle (the wrap around the major axis plus a margin) instead of all of them — exact for
    the nodes kept, and the answer is the whole bore's (to rounding) as long as no dropped
    node would be loaded: at every contact solve the outermost kept node must stay free and
    every dropped node's linearised gap, from the full displacement of the bore, ≥ 0.
    Otherwise the kept set is widened (logged) and the solve redone from the start. None:
    every bore node (the condensation then dominates the toothed rim's time).

    ``lazy_columns``: solve the compliance's columns only as the contact asks for them
    (:class:`_LazyCompliance`; the first contact solve by :func:`profilegen.lcp.active_set_lazy` from the empty
    set) instead of condensing every kept node up front — the same answer to rounding. None:
    lazily when the bore has more than :data:`LAZY_BORE_NODES` nodes (the toothed rim's 1601,
    not the flat rings' 65–129, whose full condensation is cheap).
    """
    start = time.perf_counter()
    params = (gearset_or_parameters if isinstance(gearset_or_parameters, RingParameters)
              else RingParameters.from_gearset(gearset_or_parameters))
    layers = _whole("layers", layers, 2, even=True)
    divisions = _whole("divisions", divisions, 2)
    max_iterations = _whole("max_iterations", max_iterations, 1)
    gap_tol_mm = _number("gap_tol_mm", gap_tol_mm, "mm", 0.0)
    newton_tol_mm = _number("newton_tol_mm", newton_tol_mm, "mm", 0.0)
    if geometry not in GEOMETRIES:
        raise RingError(f"geometry = {geometry!r}: must be one of {', '.join(GEOMETRIES)}")
    if not (hasattr(contour, "closest") and callable(contour.closest)):
        raise RingError(f"contour = {contour!r}: must be a wave-generator contour with closest(points)")

    mesh, th, r, mesh_kind = _ring_mesh(params, layers, divisions, mesh)
    if tier is None:
        tier = f"{geometry} {mesh_kind} ring FEM"
    system = _assemble_ring(params, mesh, th, r)
    lazy = system.n_b > LAZY_BORE_NODES if lazy_columns is None else bool(lazy_columns)
    press = partial(_press, system, contour=contour, bilateral=bilateral, gap_tol_mm=gap_tol_mm,
                    max_iterations=max_iterations, geometry=geometry, newton_tol_mm=newton_tol_mm, lazy=lazy,
                    block_solve=condense_within_rad is not None)
    result, n_kept = _press_widening(press, system, condense_within_rad)
    u, forces, active, used_normal, dist, iterations, history, newton_steps, reaction = result

    bore, ix, iy, n_dof = system.bore, system.ix, system.iy, system.n_dof
    mid = np.flatnonzero(np.abs(r - params.neutral_radius_mm) < system.tol_r)
    mid = mid[np.argsort(th[mid])]
    phi, omega, upsilon = _polar(th, u, ix, iy, mid)
    bphi, bomega, bups = _polar(th, u, ix, iy, bore)
    all_theta, all_omega, all_upsilon = _polar(th, u, ix, iy, np.arange(ix.size))
    idx = np.flatnonzero(active)
    warnings = [WRAP_WARNING]
    elapsed = time.perf_counter() - start
    log.debug("ring FEM: %d dof, %d iterations, %d active, ω(0) = %.6g mm, %.3g s", n_dof, iterations, idx.size,
              omega[0], elapsed)
    return RingResult(
        parameters=params,
        contour=contour,
        phi_rad=phi,
        omega_mm=omega,
        upsilon_mm=upsilon,
        bore_phi_rad=bphi,
        bore_omega_mm=bomega,
        bore_upsilon_mm=bups,
        contact_phi_rad=th[bore[idx]],
        contact_force_n=forces[idx],
        contact_normal=used_normal[idx],
        max_gap_mm=float(np.max(dist[idx], initial=0.0)),
        max_penetration_mm=float(max(0.0, -np.min(dist))),
        reaction_major_cut_n=float(reaction[ix[system.cut_major]].sum()),
        reaction_minor_cut_n=float(reaction[iy[system.cut_minor]].sum()),
        layers=layers,
        divisions=divisions,
        dof=int(n_dof),
        iterations=iterations,
        bilateral=bool(bilateral),
        time_s=elapsed,
        warnings=tuple(warnings),
        active_history=tuple(history),
        geometry=geometry,
        tier=tier,
        newton_steps_mm=tuple(newton_steps),
        node_theta_rad=all_theta,
        node_radius_mm=r,
        node_omega_mm=all_omega,
        node_upsilon_mm=all_upsilon,
    )
