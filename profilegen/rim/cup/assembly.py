"""Batched assembly of the cup's stiffness matrices (scikit-fem bases, numpy matrix products).

scikit-fem's ``BilinearForm`` evaluates the form once per pair of local basis functions: a
vector 27-node hexahedron has 81² = 6561 pairs, and ``linear_elasticity`` on 84 such elements
took 286 s here (the default quadrature of ``MeshHex2`` has 343 points). The same matrices
are sums of element products Bᵀ D B over the quadrature points, computed here for all
elements at once from the *scalar* basis (its values and gradients) with one batched matrix
product per chunk of elements. The forms stay the definition: tests/unit/test_cup3d.py
checks these matrices against scikit-fem's ``BilinearForm``s (:func:`profilegen.rim.cup.
fourier.harmonic_forms`, ``skfem.models.elasticity.linear_elasticity``) to rounding.

Vector dofs are numbered node-major: the component c of scalar dof k is dof 3k + c
(the harmonic model: c = 0 radial U, 1 axial W, 2 tangential V; the solid: x, y, z).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["elasticity_3d", "harmonic_parts"]

_CHUNK = 512  # elements per batched product (3D: 512 × 81 × 81 doubles = 27 MB)


def _scatter(element_blocks, element_dofs: np.ndarray, n_dof: int):
    """Sum element matrices (nel, a, a) with vector dofs ``element_dofs`` (a, nel) into a CSR matrix."""
    a, nel = element_dofs.shape
    rows = np.broadcast_to(element_dofs.T[:, :, None], (nel, a, a)).ravel()
    cols = np.broadcast_to(element_dofs.T[:, None, :], (nel, a, a)).ravel()
    return sp.coo_matrix((element_blocks.ravel(), (rows, cols)), shape=(n_dof, n_dof)).tocsr()


def _vector_dofs(basis) -> np.ndarray:
    """(nb·3, nel): vector dof 3k + c of local function i, component c, at row 3i + c."""
    ed = basis.element_dofs  # (nb, nel)
    return (3 * ed[:, None, :] + np.arange(3)[None, :, None]).reshape(-1, ed.shape[1])


def _tables(basis):
    """Values (nb, nel, nq), gradients (nb, dim, nel, nq) of the scalar basis, dx (nel, nq)."""
    value = np.stack([np.asarray(b[0]) for b in basis.basis])
    grad = np.stack([b[0].grad for b in basis.basis])
    return value, grad, basis.dx


def harmonic_parts(basis, lam: float, mu: float):
    """K₀₀, K₀₁, K₁₁ of the harmonic-n axisymmetric elasticity (see :mod:`profilegen.rim.cup.
    fourier`) on a scalar 2D basis in (r, z), without the angular factor c_n."""
    value, grad, dx = _tables(basis)
    r = np.asarray(basis.global_coordinates())[0]
    nb, nel, nq = value.shape
    phi_r = value / r
    gr, gz = grad[:, 0], grad[:, 1]
    b0 = np.zeros((nb, 3, 6, nel, nq))
    b1 = np.zeros_like(b0)
    b0[:, 0, 0], b0[:, 0, 2], b0[:, 0, 3] = gr, phi_r, gz  # U: ε_r, ε_φ, γ_rz
    b1[:, 0, 4] = -phi_r  # U: γ_rφ ∝ n
    b0[:, 1, 1], b0[:, 1, 3] = gz, gr  # W: ε_z, γ_rz
    b1[:, 1, 5] = -phi_r  # W: γ_zφ ∝ n
    b0[:, 2, 4], b0[:, 2, 5] = gr - phi_r, gz  # V: γ_rφ, γ_zφ
    b1[:, 2, 2] = phi_r  # V: ε_φ ∝ n
    d = np.zeros((6, 6))
    d[:3, :3] = lam
    d[np.arange(3), np.arange(3)] += 2.0 * mu
    d[np.arange(3, 6), np.arange(3, 6)] = mu
    w = r * dx  # (nel, nq)
    # (nel, a, s·q) with a = (i, c)
    m0 = b0.reshape(nb * 3, 6, nel, nq).transpose(2, 0, 1, 3)
    m1 = b1.reshape(nb * 3, 6, nel, nq).transpose(2, 0, 1, 3)
    d0 = np.einsum("st,eatq,eq->easq", d, m0, w)
    d1 = np.einsum("st,eatq,eq->easq", d, m1, w)
    a = nb * 3
    flat = lambda x: x.reshape(nel, a, 6 * nq)  # noqa: E731
    k00 = flat(m0) @ flat(d0).transpose(0, 2, 1)
    k01 = flat(m0) @ flat(d1).transpose(0, 2, 1) + flat(m1) @ flat(d0).transpose(0, 2, 1)
    k11 = flat(m1) @ flat(d1).transpose(0, 2, 1)
    dofs = _vector_dofs(basis)
    n_dof = 3 * basis.N
    return tuple(_scatter(k, dofs, n_dof) for k in (k00, k01, k11))


def elasticity_3d(basis, lam: float, mu: float):
    """The isotropic linear-elastic stiffness on a scalar 3D basis, vector dofs 3k + c:
    K[(i,c),(j,d)] = ∫ λ ∂_c φ_i ∂_d φ_j + μ ∂_d φ_i ∂_c φ_j + μ δ_cd ∇φ_i·∇φ_j."""
    _, grad, dx = _tables(basis)
    nb, dim, nel, nq = grad.shape
    dofs = _vector_dofs(basis)
    blocks = np.empty((nel, 3 * nb, 3 * nb))
    eye = np.eye(3)
    for lo in range(0, nel, _CHUNK):
        hi = min(nel, lo + _CHUNK)
        g = grad[:, :, lo:hi].transpose(2, 0, 1, 3).reshape(hi - lo, nb * 3, nq)  # (e, (i,c), q)
        gw = g * dx[lo:hi, None, :]
        a = (g @ gw.transpose(0, 2, 1)).reshape(hi - lo, nb, 3, nb, 3)  # A[e, i, c, j, d]
        dot = np.einsum("eikjk->eij", a)
        k = lam * a + mu * a.transpose(0, 1, 4, 3, 2) + mu * dot[:, :, None, :, None] * eye[None, None, :, None, :]
        blocks[lo:hi] = k.reshape(hi - lo, 3 * nb, 3 * nb)
    return _scatter(blocks, dofs, 3 * basis.N)
