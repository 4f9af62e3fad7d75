"""A plain 3D solid model of the cup (scikit-fem, 27-node hexahedra): the check of the fast
Fourier formulation (:mod:`profilegen.rim.cup.fourier`), not a tier of its own — a cross-check
model, so it lives with the tests (tests/unit/test_cup3d.py, tests/benchmarks/cup3d.py).

The meridional mesh (:func:`~profilegen.rim.cup.geometry.meridional_mesh`, the same breaks in
r and z) is swept through a quarter 0 ≤ θ ≤ π/2 in ``sectors`` equal steps (the two symmetry
planes of a two-wave load: θ = 0 (x = 0): u_x = 0; θ = π/2 (y = 0): u_y = 0; loads with even
harmonics only). Built as a tensor mesh in (θ, r, z) with the elements outside the L removed,
made quadratic (``MeshHex2``) and mapped to (r sin θ, r cos θ, z) node by node, so every node
is on its exact radius. Linear elasticity (``skfem.models.elasticity.linear_elasticity``).

Load as the Fourier model's: the bore nodes over the bearing's width get the radial
displacement w(θ) = Σ w_n cos nθ, their tangential and axial displacements free (their two
in-plane dofs are rotated to (radial, tangential) — an orthogonal change of variables of the
stiffness); the boss r = r0 is clamped. ω, υ, the axial displacement are read on the node
surface r = r_m.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import partial
from typing import Mapping

import numpy as np
import scipy.sparse as sp

from profilegen import checks
from profilegen.errors import ConvergenceError
from profilegen.results import readonly
from profilegen.rim.cup.fourier import radial_load, lame
from profilegen.rim.cup.geometry import CupError, CupGeometry, CupMesh, meridional_mesh

__all__ = ["SolidCup", "solve_solid_cup"]

_whole = partial(checks.whole, error=CupError)


@dataclass(frozen=True, slots=True, eq=False)
class SolidCup:
    """The 3D solid's displacement on the nodes of the surface r = r_m (mm): ``theta_rad``,
    ``z_mm``, ``omega_mm`` (radial), ``upsilon_mm`` (tangential, + toward increasing θ),
    ``axial_mm``; ``dof``, ``sectors``, the meridional mesh, times (s)."""

    geometry: CupGeometry
    cup_mesh: CupMesh
    theta_rad: np.ndarray
    z_mm: np.ndarray
    omega_mm: np.ndarray
    upsilon_mm: np.ndarray
    axial_mm: np.ndarray
    sectors: int
    dof: int
    assembly_s: float
    solve_s: float
    time_s: float

    def __post_init__(self):
        for name in ("theta_rad", "z_mm", "omega_mm", "upsilon_mm", "axial_mm"):
            object.__setattr__(self, name, readonly(getattr(self, name)))


def _hex_mesh(cup_mesh: CupMesh, sectors: int):
    from skfem import MeshHex, MeshHex2

    g = cup_mesh.geometry
    theta = np.linspace(0.0, 0.5 * math.pi, sectors + 1)
    box = MeshHex.init_tensor(theta, cup_mesh.r_breaks, cup_mesh.z_breaks)
    centre = box.p[:, box.t].mean(axis=1)
    keep = (centre[2] < 0.5 * g.bottom_thickness_mm) | (centre[1] > g.bore_radius_mm)
    t = box.t[:, keep]
    used = np.unique(t)
    renumber = -np.ones(box.p.shape[1], dtype=int)
    renumber[used] = np.arange(used.size)
    linear = MeshHex(box.p[:, used], renumber[t])
    quad = MeshHex2.from_mesh(linear)
    th, r, z = quad.doflocs
    from dataclasses import replace

    return replace(quad, doflocs=np.vstack([r * np.sin(th), r * np.cos(th), z])), th, r, z


def solve_solid_cup(
    geometry: CupGeometry,
    *,
    radial_mm: Mapping[int, float],
    element_mm: float = 2.0,
    layers: int = 1,
    sectors: int = 12,
    cup_mesh: CupMesh | None = None,
) -> SolidCup:
    """The quarter cup as a 3D solid with its bore pressed to w(θ) = Σ w_n cos nθ over the
    bearing's width (even n only: the quarter's symmetry), boss clamped."""
    from scipy.sparse.linalg import splu
    from skfem import Basis, ElementHex2

    from profilegen.rim.cup.assembly import elasticity_3d

    start = time.perf_counter()
    if not isinstance(geometry, CupGeometry):
        raise CupError(f"geometry: must be a CupGeometry, got {type(geometry).__name__}")
    load = radial_load(radial_mm)
    odd = [n for n in load if n % 2]
    if odd:
        raise CupError(f"radial_mm order {odd[0]}: the quarter model takes even harmonics only (two symmetry planes)")
    sectors = _whole("sectors", sectors, 1)
    if cup_mesh is None:
        cup_mesh = meridional_mesh(geometry, element_mm=element_mm, layers=layers)
    g = cup_mesh.geometry
    mesh = _hex_mesh(cup_mesh, sectors)[0]
    basis = Basis(mesh, ElementHex2(), intorder=5)  # 3 Gauss points a direction (MeshHex2's default: 7)
    x_, y_, z = basis.doflocs
    r, th = np.hypot(x_, y_), np.arctan2(x_, y_)
    lam, mu = lame(g.youngs_modulus_mpa, g.poisson_ratio)
    stiff = elasticity_3d(basis, lam, mu)
    t_asm = time.perf_counter() - start
    k3 = 3 * np.arange(basis.N)
    ix, iy, iz = k3, k3 + 1, k3 + 2
    n_dof = 3 * basis.N
    tol = 1e-9 * max(g.outer_radius_mm, g.open_end_mm)
    b_lo, b_hi = g.bearing_span_mm
    bore = np.flatnonzero((np.abs(r - g.bore_radius_mm) < tol) & (z > b_lo - tol) & (z < b_hi + tol))
    boss = np.flatnonzero(np.abs(r - g.boss_radius_mm) < tol)
    at_major = np.abs(th) < 1e-12
    at_minor = np.abs(th - 0.5 * math.pi) < 1e-12

    # rotate the bore nodes' (x, y) dofs to (radial a, tangential b):
    # u_x = a sin θ + b cos θ, u_y = a cos θ − b sin θ
    s, c = np.sin(th[bore]), np.cos(th[bore])
    rows = np.concatenate([ix[bore], ix[bore], iy[bore], iy[bore]])
    cols = np.concatenate([ix[bore], iy[bore], ix[bore], iy[bore]])  # a at ix, b at iy
    vals = np.concatenate([s, c, c, -s])
    others = np.setdiff1d(np.arange(n_dof), np.concatenate([ix[bore], iy[bore]]))
    rot = sp.csr_matrix((np.concatenate([vals, np.ones(others.size)]),
                         (np.concatenate([rows, others]), np.concatenate([cols, others]))), shape=(n_dof, n_dof))
    k_hat = (rot.T @ stiff @ rot).tocsr()

    on_bore = np.zeros(th.size, bool)
    on_bore[bore] = True
    fixed_sym = np.concatenate([
        ix[at_major & ~on_bore], iy[at_minor & ~on_bore],  # symmetry planes
        iy[at_major & on_bore], iy[at_minor & on_bore],  # the bore's tangential dof on them
    ])
    clamped = np.concatenate([ix[boss], iy[boss], iz[boss]])
    pressed = ix[bore]
    x = np.zeros(n_dof)
    x[pressed] = sum(w * np.cos(n * th[bore]) for n, w in load.items())
    fixed = np.unique(np.concatenate([fixed_sym, clamped, pressed]))
    free = np.setdiff1d(np.arange(n_dof), fixed)
    t0 = time.perf_counter()
    kff = k_hat[free][:, free].tocsc()
    rhs = -(k_hat[free][:, fixed] @ x[fixed])
    try:
        x[free] = splu(kff, permc_spec="COLAMD").solve(rhs)
    except RuntimeError as exc:
        raise ConvergenceError(f"solve_solid_cup: singular stiffness ({exc})") from exc
    t_solve = time.perf_counter() - t0
    u = rot @ x
    mid = np.flatnonzero(np.abs(r - g.neutral_radius_mm) < tol)
    t_m = th[mid]
    ux, uy, uz = u[ix[mid]], u[iy[mid]], u[iz[mid]]
    omega = ux * np.sin(t_m) + uy * np.cos(t_m)
    upsilon = ux * np.cos(t_m) - uy * np.sin(t_m)
    return SolidCup(g, cup_mesh, t_m, z[mid], omega, upsilon, uz, sectors, int(n_dof), t_asm, t_solve,
                    time.perf_counter() - start)
