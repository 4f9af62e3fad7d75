"""The cup as a body of revolution under a non-axisymmetric load: one 2D meridional FEM
problem per Fourier harmonic (scikit-fem), the fast formulation of the 3D cup tier.

Displacement (cylindrical r, φ, z; φ from the wave-generator major axis)::

    u_r = Σ_n U_n(r, z) cos nφ,   u_z = Σ_n W_n(r, z) cos nφ,   u_φ = Σ_n V_n(r, z) sin nφ

(for n = 0 the φ-component is u_φ = V_0(r, z): torsion). Strains of harmonic n (Voigt,
engineering shears), each the cos nφ or sin nφ coefficient::

    ε_r = ∂U/∂r        ε_z = ∂W/∂z        ε_φ = (U + nV)/r        γ_rz = ∂U/∂z + ∂W/∂r
    γ_rφ = ∂V/∂r − (V + nU)/r             γ_zφ = ∂V/∂z − nW/r

written ε = E₀(u) + n E₁(u) so that the stiffness of every harmonic is
K_n = c_n (K₀₀ + n K₀₁ + n² K₁₁), c_n = ∫cos²nφ dφ = π (n ≥ 1), 2π (n = 0), from three
matrices assembled once (scikit-fem ``BilinearForm``s on the meridional mesh, 9-node
quadrilaterals, three components). Isotropic linear elasticity, small strain; harmonics do
not couple (the body is axisymmetric and linear).

Load (this first step): the bore r = r_m − t/2 is given the radial displacement w(φ) =
Σ w_n cos nφ over the bearing's width, frictionless (u_z, u_φ free there) — a prescribed
shape, as ring theory's bilateral cam; the boss r = r0 is clamped. A contour's w(φ) is its
polar radius minus the bore radius, expanded in cos nφ (:func:`bore_load`): the
first-order contact statement (docs/theory/rim.md: the O(w0²/R) terms of the contact
geometry and the unilateral wrap are the next step).

Results are read on the neutral surface r = r_m of the wall (a node line of every mesh:
quadratic elements put a node at mid-thickness), from the bottom junction to the open end,
and interpolated in z with the elements' own quadratic shape: ω(φ, z) (radial), υ(φ, z)
(tangential, + toward increasing φ), the axial displacement, and the generator tilt ∂ω/∂z
(rad, + when the generator leans outward toward the open end).
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from functools import partial
from typing import TYPE_CHECKING, Mapping

import numpy as np

from ... import checks
from ...errors import ConvergenceError
from ...results import json_ready, readonly
from .geometry import CupError, CupGeometry, CupMesh, meridional_mesh

if TYPE_CHECKING:
    from scipy.sparse import csr_matrix
    from skfem import CellBasis

__all__ = ["CupDeformation", "HarmonicBasis", "bore_load", "harmonic_forms", "harmonic_stiffness", "lame", "solve_cup"]

log = logging.getLogger(__name__)

_number = partial(checks.number, error=CupError)
_whole = partial(checks.whole, error=CupError)


# --------------------------------------------------------------------------- the forms


def _strain_parts(u, r):
    """E₀(u), E₁(u): the strain of harmonic n is E₀ + n E₁ (components r, z, φ of u)."""
    U, W, V = u[0], u[1], u[2]
    dU, dW, dV = u.grad
    zero = 0.0 * U
    e0 = (dU[0], dW[1], U / r, dU[1] + dW[0], dV[0] - V / r, dV[1])
    e1 = (zero, zero, V / r, zero, -U / r, -W / r)
    return e0, e1


def _energy(a, b, lam, mu):
    """The bilinear strain energy density a : C : b (Voigt, engineering shears)."""
    trace = (a[0] + a[1] + a[2]) * (b[0] + b[1] + b[2])
    normal = a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    shear = a[3] * b[3] + a[4] * b[4] + a[5] * b[5]
    return lam * trace + 2.0 * mu * normal + mu * shear


def harmonic_forms():
    """The three parts K₀₀, K₀₁, K₁₁ as scikit-fem ``BilinearForm``s on a vector basis with three
    components (r, z, φ), keyword parameters ``lam``, ``mu`` (MPa): the definition that
    :func:`profilegen.rim.cup.assembly.harmonic_parts` computes batched (the forms are
    evaluated once per pair of local basis functions: 27² per 9-node element)."""
    from skfem import BilinearForm

    @BilinearForm
    def k00(u, v, w):
        r = w.x[0]
        return _energy(_strain_parts(u, r)[0], _strain_parts(v, r)[0], w.lam, w.mu) * r

    @BilinearForm
    def k01(u, v, w):
        r = w.x[0]
        (u0, u1), (v0, v1) = _strain_parts(u, r), _strain_parts(v, r)
        return (_energy(u0, v1, w.lam, w.mu) + _energy(u1, v0, w.lam, w.mu)) * r

    @BilinearForm
    def k11(u, v, w):
        r = w.x[0]
        return _energy(_strain_parts(u, r)[1], _strain_parts(v, r)[1], w.lam, w.mu) * r

    return k00, k01, k11


def lame(youngs_modulus_mpa: float, poisson_ratio: float) -> tuple[float, float]:
    e, nu = youngs_modulus_mpa, poisson_ratio
    return e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu))


@dataclass(frozen=True, slots=True, eq=False)
class HarmonicBasis:
    """The meridional mesh with its quadratic scalar basis and the three parts of the harmonic
    stiffness (vector dofs 3k + c, c = 0 radial U, 1 axial W, 2 tangential V of scalar node k);
    :meth:`stiffness` gives K_n."""

    cup_mesh: CupMesh
    basis: CellBasis
    k00: csr_matrix
    k01: csr_matrix
    k11: csr_matrix
    assembly_s: float

    @property
    def dof(self) -> int:
        return 3 * int(self.basis.N)

    @property
    def nodes(self) -> np.ndarray:
        """(2, nodes): (r, z) of every scalar node (vertices, edge midpoints, centres)."""
        return self.basis.doflocs

    def stiffness(self, n: int):
        """K_n = c_n (K₀₀ + n K₀₁ + n² K₁₁) (N/mm, generalised: the work of harmonic-n nodal
        forces on harmonic-n displacements includes the ∫cos² dφ)."""
        c = 2.0 * math.pi if n == 0 else math.pi
        return (c * (self.k00 + float(n) * self.k01 + float(n * n) * self.k11)).tocsr()

    def components(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """dof indices of U (radial), W (axial), V (tangential) of every node, in node order."""
        k = 3 * np.arange(self.basis.N)
        return k, k + 1, k + 2


def harmonic_stiffness(cup_mesh: CupMesh, *, intorder: int = 4) -> HarmonicBasis:
    """Assemble the three parts of the harmonic stiffness on ``cup_mesh`` (9-node
    quadrilaterals, batched: :func:`profilegen.rim.cup.assembly.harmonic_parts`)."""
    from skfem import Basis, ElementQuad2, MeshQuad2

    from .assembly import harmonic_parts

    t0 = time.perf_counter()
    g = cup_mesh.geometry
    lam, mu = lame(g.youngs_modulus_mpa, g.poisson_ratio)
    basis = Basis(MeshQuad2.from_mesh(cup_mesh.mesh), ElementQuad2(), intorder=intorder)
    k00, k01, k11 = harmonic_parts(basis, lam, mu)
    return HarmonicBasis(cup_mesh, basis, k00, k01, k11, time.perf_counter() - t0)


# --------------------------------------------------------------------------- loads


def bore_load(contour, bore_radius_mm: float, *, max_order: int = 32, samples: int = 1024) -> dict[int, float]:
    """w(φ) = ρ(φ) − r_bore of a wave-generator contour as {n: w_n} (cos nφ, mm), n = 0..max_order
    (FFT of ``samples`` equispaced values; spectrally exact for a smooth contour). Only even
    orders survive on a two-wave contour; coefficients below 1e-13 mm are dropped."""
    r_b = _number("bore_radius_mm", bore_radius_mm, "mm", 0.0)
    max_order = _whole("max_order", max_order, 0)
    samples = max(_whole("samples", samples, 8), 4 * max_order + 4)
    phi = 2.0 * math.pi * np.arange(samples) / samples
    values = np.asarray(contour.radius(phi), dtype=float) - r_b
    if not np.all(np.isfinite(values)) or np.any(values <= -r_b):
        raise CupError("contour: its polar radius must be positive and finite all round (a closed cam contour)")
    spec = np.fft.rfft(values) / samples
    coef = 2.0 * spec.real
    coef[0] = spec[0].real
    return {k: float(coef[k]) for k in range(max_order + 1) if abs(coef[k]) > 1e-13}


def radial_load(radial_mm) -> dict[int, float]:
    if not isinstance(radial_mm, Mapping) or not radial_mm:
        raise CupError(f"radial_mm must be a non-empty mapping harmonic order → mm, got {radial_mm!r}")
    out: dict[int, float] = {}
    for k, c in radial_mm.items():
        k = _whole("radial_mm order", k, 0)
        out[k] = out.get(k, 0.0) + float(checks.finite(f"radial_mm[{k}]", c, "mm", error=CupError))
    return dict(sorted(out.items()))


# --------------------------------------------------------------------------- the result


def _quadratic(z_nodes: np.ndarray, values: np.ndarray, z, derivative: int = 0) -> np.ndarray:
    """Piecewise quadratic interpolation (the 9-node elements' shape along a node line):
    ``z_nodes`` = [vertex, mid, vertex, mid, …, vertex]; ``values`` (..., len(z_nodes))."""
    z = np.asarray(z, dtype=float)
    zv = z_nodes[0::2]
    k = np.clip(np.searchsorted(zv, z, side="right") - 1, 0, zv.size - 2)
    x0, x1, x2 = z_nodes[2 * k], z_nodes[2 * k + 1], z_nodes[2 * k + 2]
    f0, f1, f2 = values[..., 2 * k], values[..., 2 * k + 1], values[..., 2 * k + 2]
    if derivative == 0:
        l0 = (z - x1) * (z - x2) / ((x0 - x1) * (x0 - x2))
        l1 = (z - x0) * (z - x2) / ((x1 - x0) * (x1 - x2))
        l2 = (z - x0) * (z - x1) / ((x2 - x0) * (x2 - x1))
    else:
        l0 = (2 * z - x1 - x2) / ((x0 - x1) * (x0 - x2))
        l1 = (2 * z - x0 - x2) / ((x1 - x0) * (x1 - x2))
        l2 = (2 * z - x0 - x1) / ((x2 - x0) * (x2 - x1))
    return f0 * l0 + f1 * l1 + f2 * l2


@dataclass(frozen=True, slots=True, eq=False)
class CupDeformation:
    """The cup's displacement on the neutral surface r = r_m of the wall (mm, rad).

    ``orders`` n and ``load_mm`` w_n: the harmonics solved and the prescribed bore radial
    displacement of each. ``z_mm``: the node line (bottom junction → open end, vertex and
    mid-edge nodes). ``radial_mm``, ``axial_mm``, ``tangential_mm``: (harmonics, z) the
    coefficients U_n, W_n (of cos nφ) and V_n (of sin nφ) there. ``bore_radial_mm``: U_n on the
    bore line (the same z). ``boss_reaction`` / ``bore_reaction``: per harmonic, the resultants
    of the reactions at the clamped boss and at the loaded bore (:func:`harmonic_resultants`): n = 0 the
    axial force F_z (N) and the torque M_z (N·mm); n = 1 the force along φ = 0, F_x (N), and
    the moment about the axis φ = π/2 through z = 0, M_y (N·mm); none for n ≥ 2 (a cos nφ
    distribution has no resultant).
    """

    geometry: CupGeometry
    orders: np.ndarray
    load_mm: np.ndarray
    z_mm: np.ndarray
    radial_mm: np.ndarray
    axial_mm: np.ndarray
    tangential_mm: np.ndarray
    bore_radial_mm: np.ndarray
    boss_reaction: tuple
    bore_reaction: tuple
    dof: int
    elements: int
    element_mm: float
    layers: int
    assembly_s: float
    solve_s: float
    time_s: float
    warnings: tuple[str, ...] = field(default=())

    def __post_init__(self):
        object.__setattr__(self, "orders", readonly(self.orders, int))
        for name in ("load_mm", "z_mm", "radial_mm", "axial_mm", "tangential_mm", "bore_radial_mm"):
            object.__setattr__(self, name, readonly(getattr(self, name)))
        object.__setattr__(self, "warnings", tuple(self.warnings))

    def _check_z(self, z) -> np.ndarray:
        z = np.asarray(checks.finite("z_mm", z, "mm", error=CupError), dtype=float)
        lo, hi = float(self.z_mm[0]), float(self.z_mm[-1])
        bad = (z < lo - 1e-9) | (z > hi + 1e-9)
        if np.any(bad):
            raise CupError(f"z_mm = {z[bad].flat[0]!r} mm: must be on the wall, in [{lo:g}, {hi:g}] mm "
                           "(from the cup bottom's mid-plane)")
        return z

    def _series(self, table, phi, z, trig, derivative: int = 0):
        phi = np.asarray(phi, dtype=float)
        z = self._check_z(z)
        phi, z = np.broadcast_arrays(phi, z)
        coef = _quadratic(self.z_mm, table, z, derivative)  # (harmonics, *shape)
        n = self.orders.reshape((-1,) + (1,) * phi.ndim)
        return np.sum(coef * trig(n * phi), axis=0)

    def omega(self, phi_rad, z_mm) -> np.ndarray:
        """ω(φ, z): radial displacement of the neutral surface (mm, outward +); broadcasts."""
        return self._series(self.radial_mm, phi_rad, z_mm, np.cos)

    def upsilon(self, phi_rad, z_mm) -> np.ndarray:
        """υ(φ, z): tangential displacement of the neutral surface (mm, + toward increasing φ)."""
        return self._series(self.tangential_mm, phi_rad, z_mm, np.sin)

    def axial(self, phi_rad, z_mm) -> np.ndarray:
        """Axial displacement of the neutral surface (mm, + toward the open end)."""
        return self._series(self.axial_mm, phi_rad, z_mm, np.cos)

    def tilt(self, phi_rad, z_mm) -> np.ndarray:
        """Generator tilt ∂ω/∂z on the neutral surface (rad, + leaning outward toward the open end)."""
        return self._series(self.radial_mm, phi_rad, z_mm, np.cos, derivative=1)

    def bore_omega(self, phi_rad, z_mm) -> np.ndarray:
        """Radial displacement of the bore r = r_bore (mm, outward +) at (φ, z) on the wall; broadcasts."""
        return self._series(self.bore_radial_mm, phi_rad, z_mm, np.cos)

    def section(self, z_mm: float, samples: int = 181) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(φ, ω, υ) at the axial position ``z_mm`` over one wave period 0 ≤ φ < π (mm)."""
        samples = _whole("samples", samples, 8)
        phi = math.pi * np.arange(samples) / samples
        return phi, self.omega(phi, z_mm), self.upsilon(phi, z_mm)

    def fit(self, z_mm: float, *, waves: int = 2, max_order: int = 16, tier: str = "cup3d"):
        """The section at ``z_mm`` as the kinematics' integer-harmonic Fourier model
        (:func:`profilegen.geometry.series.fit_fourier`)."""
        from ...geometry import series

        phi, w, u = self.section(z_mm, samples=max(181, 8 * max_order + 8))
        return series.fit_fourier(phi, w, u, waves=waves, max_order=max_order, tier=tier)

    def to_dict(self) -> dict:
        return json_ready({
            "model": "cup as a body of revolution, Fourier harmonics of 2D meridional FEM (9-node quads), "
                     "prescribed bore radial displacement over the bearing width, boss clamped",
            "geometry": self.geometry.to_dict(),
            "orders": self.orders,
            "load_mm": self.load_mm,
            "z_mm": self.z_mm,
            "radial_mm": self.radial_mm,
            "axial_mm": self.axial_mm,
            "tangential_mm": self.tangential_mm,
            "dof": self.dof,
            "elements": self.elements,
            "element_mm": self.element_mm,
            "layers": self.layers,
            "assembly_s": self.assembly_s,
            "solve_s": self.solve_s,
            "time_s": self.time_s,
            "warnings": list(self.warnings),
        })


def harmonic_resultants(n: int, reaction: np.ndarray, dofs, r: np.ndarray, z: np.ndarray, nodes: np.ndarray) -> tuple:
    """Force and moment resultants of generalised harmonic-n nodal reactions on ``nodes``
    (the virtual work of the reactions on the rigid-body modes of harmonic n)."""
    iu, iw, iv = dofs
    ru, rw, rv = reaction[iu[nodes]], reaction[iw[nodes]], reaction[iv[nodes]]
    rr, zz = r[nodes], z[nodes]
    if n == 0:  # axial translation (W = 1), rotation about the axis (V = r)
        return float(rw.sum()), float((rv * rr).sum())
    if n == 1:  # translation along φ = 0 (U = 1, V = −1); rotation about φ = π/2 (U = z, W = −r, V = −z)
        return float((ru - rv).sum()), float((ru * zz - rw * rr - rv * zz).sum())
    return ()


# --------------------------------------------------------------------------- the solve


def factor_stiffness(matrix):
    """A factorisation of a harmonic's stiffness (symmetric positive definite once the boss is
    clamped): the rim stage's banded Cholesky after reverse Cuthill–McKee (a meridional mesh is
    a long strip, bandwidth ~ 3 × the nodes across it), SuperLU with COLAMD if it is not
    positive definite. One thread: the solves are small and the machine is shared."""
    from ...blas import one_blas_thread
    from ..ring import StiffnessFactor

    with one_blas_thread(True):
        return StiffnessFactor(matrix)


def solve_cup(
    geometry_or_gearset,
    *,
    radial_mm: Mapping[int, float] | None = None,
    contour=None,
    max_order: int = 16,
    element_mm: float = 1.0,
    layers: int = 2,
    bottom_layers: int | None = None,
    harmonic_basis: HarmonicBasis | None = None,
) -> CupDeformation:
    """The cup with its bore pressed to w(φ) over the bearing's width, boss clamped.

    ``geometry_or_gearset``: a :class:`CupGeometry` or a GearSet (:meth:`CupGeometry.from_gearset`).
    The load: ``radial_mm`` {n: w_n} (mm, coefficient of cos nφ), or ``contour`` (its
    ρ(φ) − r_bore up to ``max_order``, :func:`bore_load`); with a GearSet and neither, the
    gear set's wave-generator contour. Mesh: ``layers`` quadratic elements through the wall,
    elements of ``element_mm`` along the meridian (:func:`~profilegen.rim.cup.geometry.
    meridional_mesh`), or a prepared ``harmonic_basis`` (its mesh is used as is).
    """
    start = time.perf_counter()
    if isinstance(geometry_or_gearset, CupGeometry):
        geometry, gearset = geometry_or_gearset, None
    else:
        geometry, gearset = CupGeometry.from_gearset(geometry_or_gearset), geometry_or_gearset
    if radial_mm is not None and contour is not None:
        raise CupError("radial_mm and contour: give one load, not both")
    if radial_mm is None:
        if contour is None:
            if gearset is None:
                raise CupError("radial_mm: a load is needed (radial_mm or contour) for a bare CupGeometry")
            from ...geometry.wavegen import from_gearset

            contour = from_gearset(gearset)
        load = bore_load(contour, geometry.bore_radius_mm, max_order=max_order)
    else:
        load = radial_load(radial_mm)
    if harmonic_basis is None:
        harmonic_basis = harmonic_stiffness(meridional_mesh(geometry, element_mm=element_mm, layers=layers,
                                                            bottom_layers=bottom_layers))
    elif harmonic_basis.cup_mesh.geometry is not geometry:
        raise CupError("harmonic_basis: it was built for another CupGeometry than the one given")
    hb = harmonic_basis
    g = geometry
    iu, iw, iv = hb.components()
    r, z = hb.nodes
    tol = 1e-9 * max(g.outer_radius_mm, g.open_end_mm)
    b_lo, b_hi = g.bearing_span_mm
    boss = np.flatnonzero(np.abs(r - g.boss_radius_mm) < tol)
    bore = np.flatnonzero((np.abs(r - g.bore_radius_mm) < tol) & (z > b_lo - tol) & (z < b_hi + tol))
    z_wall = 0.5 * g.bottom_thickness_mm
    line = np.flatnonzero((np.abs(r - g.neutral_radius_mm) < tol) & (z > z_wall - tol))
    line = line[np.argsort(z[line])]
    bore_line = np.flatnonzero((np.abs(r - g.bore_radius_mm) < tol) & (z > z_wall - tol))
    bore_line = bore_line[np.argsort(z[bore_line])]
    if bore.size == 0 or boss.size == 0 or line.size < 3 or bore_line.size != line.size:
        raise ConvergenceError("solve_cup: the meridional mesh has no node line on the bore band, the boss or r_m")
    clamped = np.concatenate([iu[boss], iw[boss], iv[boss]])
    pressed = iu[bore]
    fixed = np.concatenate([clamped, pressed])
    free = np.setdiff1d(np.arange(hb.dof), fixed)

    orders = np.array(sorted(load), dtype=int)
    radial = np.zeros((orders.size, line.size))
    axial = np.zeros_like(radial)
    tangential = np.zeros_like(radial)
    bore_radial = np.zeros_like(radial)
    boss_res, bore_res = [], []
    t_solve = time.perf_counter()
    for k, n in enumerate(orders):
        stiff = hb.stiffness(int(n))
        x = np.zeros(hb.dof)
        x[pressed] = load[int(n)]
        kff = stiff[free][:, free].tocsc()
        rhs = -(stiff[free][:, pressed] @ x[pressed])
        try:
            x[free] = factor_stiffness(kff).solve(rhs)
        except RuntimeError as exc:  # "Factor is exactly singular"
            raise ConvergenceError(f"solve_cup: the harmonic n = {n} stiffness is singular ({exc})") from exc
        if not np.all(np.isfinite(x)):
            raise ConvergenceError(f"solve_cup: non-finite displacement in harmonic n = {n}")
        reaction = stiff @ x
        radial[k], axial[k], tangential[k] = x[iu[line]], x[iw[line]], x[iv[line]]
        bore_radial[k] = x[iu[bore_line]]
        boss_res.append(harmonic_resultants(int(n), reaction, (iu, iw, iv), r, z, boss))
        bore_res.append(harmonic_resultants(int(n), reaction, (iu, iw, iv), r, z, bore))
    t_solve = time.perf_counter() - t_solve
    elapsed = time.perf_counter() - start
    log.debug("cup (Fourier): %d harmonics × %d dof, assembly %.3g s, solves %.3g s", orders.size, hb.dof,
              hb.assembly_s, t_solve)
    return CupDeformation(
        geometry=g, orders=orders, load_mm=np.array([load[int(n)] for n in orders]), z_mm=z[line],
        radial_mm=radial, axial_mm=axial, tangential_mm=tangential, bore_radial_mm=bore_radial,
        boss_reaction=tuple(boss_res), bore_reaction=tuple(bore_res), dof=hb.dof,
        elements=hb.cup_mesh.elements, element_mm=hb.cup_mesh.element_mm, layers=hb.cup_mesh.layers,
        assembly_s=hb.assembly_s, solve_s=t_solve, time_s=elapsed)
