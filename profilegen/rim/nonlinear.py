"""Geometrically nonlinear plane stress: total Lagrangian, St Venant–Kirchhoff material.

The rim's strains are ~1e-3 but its points move by w0 ≈ r_m/100 and its cross-sections turn
by ~w0/r_m: the *kinematics* is nonlinear (~7–10 µm in ω, docs/theory/rim.md), the *material*
is not. St Venant–Kirchhoff — the second Piola–Kirchhoff stress S = C : E with the Green
strain E = ½(FᵀF − I), F = I + ∇u, and C the linear plane-stress tensor — is the
small-strain, large-rotation model: at u = 0 its tangent is the linear stiffness.

Weak form (reference configuration, per mm of face width):

* internal force  f_i(u) = ∫ S : δE_i dA,  δE_i = sym(Fᵀ ∇N_i);
* tangent        K_ij(u) = ∫ δE_i : C : δE_j + ∇N_i : (∇N_j S) dA  (material + geometric).

Assembled with numpy from scikit-fem's basis (its element gradients and quadrature): the
element matrices are batched matrix products, ~10× faster than a ``BilinearForm`` with a
Python integrand, which matters because the Newton loop assembles every iteration. The
tangent is checked against finite differences of f and, at u = 0, against
``skfem.models.elasticity.linear_elasticity`` (tests/unit/test_rim_nonlinear.py).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["TotalLagrangian"]


class TotalLagrangian:
    """Internal force and tangent stiffness of a plane-stress St Venant–Kirchhoff body.

    ``basis``: a scikit-fem ``Basis`` on a vector element; ``youngs_modulus_mpa``,
    ``poisson_ratio`` as usual. Call ``(u)`` → ``(K (csr), f)``; ``force(u)`` → f only.
    """

    def __init__(self, basis, youngs_modulus_mpa: float, poisson_ratio: float):
        self.grad = np.ascontiguousarray(np.stack([b[0].grad for b in basis.basis]))  # (n_loc, 2, 2, ne, nq)
        self.dofs = np.asarray(basis.element_dofs)  # (n_loc, ne)
        self.dx = np.asarray(basis.dx)  # (ne, nq)
        e, nu = float(youngs_modulus_mpa), float(poisson_ratio)
        self.D = e / (1.0 - nu * nu) * np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0], [0.0, 0.0, 0.5 * (1.0 - nu)]])
        n_loc, ne = self.dofs.shape
        self.rows = np.broadcast_to(self.dofs.T[:, :, None], (ne, n_loc, n_loc)).ravel()
        self.cols = np.broadcast_to(self.dofs.T[:, None, :], (ne, n_loc, n_loc)).ravel()
        self.n = int(basis.N)

    def _kinematics(self, u):
        g = self.grad
        h = np.einsum("ie,iabeq->abeq", np.asarray(u)[self.dofs], g)  # ∇u
        f = h.copy()
        f[0, 0] += 1.0
        f[1, 1] += 1.0
        c = np.einsum("abeq,aceq->bceq", f, f)  # FᵀF
        strain = np.stack([0.5 * (c[0, 0] - 1.0), 0.5 * (c[1, 1] - 1.0), c[0, 1]])  # Voigt, engineering shear
        stress = np.einsum("kl,leq->keq", self.D, strain)  # S11, S22, S12
        ftg = np.einsum("abeq,iaceq->ibceq", f, g)  # Fᵀ∇N_i
        b = np.stack([ftg[:, 0, 0], ftg[:, 1, 1], ftg[:, 0, 1] + ftg[:, 1, 0]], axis=1)  # (n_loc, 3, ne, nq)
        return b, stress

    def force(self, u) -> np.ndarray:
        b, stress = self._kinematics(u)
        f_loc = np.einsum("ikeq,keq,eq->ie", b, stress, self.dx)
        return np.bincount(self.dofs.ravel(), f_loc.ravel(), minlength=self.n)

    def linear_stiffness(self) -> sp.csr_matrix:
        """The tangent at u = 0 — the linear plane-stress stiffness — without the geometric
        part (zero stress there) and without the kinematics of a displaced state."""
        g = self.grad  # (n_loc, 2, 2, ne, nq): component a of N_i, derivative b
        n_loc, _, _, ne, nq = g.shape
        b = np.stack([g[:, 0, 0], g[:, 1, 1], g[:, 0, 1] + g[:, 1, 0]], axis=1)  # (n_loc, 3, ne, nq)
        b_e = b.transpose(2, 0, 1, 3).reshape(ne, n_loc, 3 * nq)
        db = np.einsum("kl,ileq,eq->ikeq", self.D, b, self.dx).transpose(2, 1, 3, 0).reshape(ne, 3 * nq, n_loc)
        k = np.matmul(b_e, db)
        return sp.coo_matrix((k.ravel(), (self.rows, self.cols)), shape=(self.n, self.n)).tocsr()

    def __call__(self, u) -> tuple[sp.csr_matrix, np.ndarray]:
        b, stress = self._kinematics(u)
        n_loc, _, ne, nq = b.shape
        f_loc = np.einsum("ikeq,keq,eq->ie", b, stress, self.dx)
        force = np.bincount(self.dofs.ravel(), f_loc.ravel(), minlength=self.n)
        # material part: B_iᵀ D B_j, contracted over (Voigt, quadrature point) per element
        b_e = b.transpose(2, 0, 1, 3).reshape(ne, n_loc, 3 * nq)
        db = np.einsum("kl,ileq,eq->ikeq", self.D, b, self.dx).transpose(2, 1, 3, 0).reshape(ne, 3 * nq, n_loc)
        k = np.matmul(b_e, db)
        # geometric part: ∇N_i : (∇N_j S)
        s = np.array([[stress[0], stress[2]], [stress[2], stress[1]]])  # (2, 2, ne, nq)
        gs = np.einsum("jaceq,cbeq,eq->jabeq", self.grad, s, self.dx)
        g_e = self.grad.transpose(3, 0, 1, 2, 4).reshape(ne, n_loc, 4 * nq)
        gs_e = gs.transpose(3, 1, 2, 4, 0).reshape(ne, 4 * nq, n_loc)
        k += np.matmul(g_e, gs_e)
        stiffness = sp.coo_matrix((k.ravel(), (self.rows, self.cols)), shape=(self.n, self.n)).tocsr()
        return stiffness, force
