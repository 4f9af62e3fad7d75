"""Geometrically nonlinear internal force of the cup as a body of revolution, by harmonic
balance: total Lagrangian St Venant–Kirchhoff (the 2D ring's :mod:`profilegen.rim.nonlinear`
model) with the displacement kept as the Fourier series of :mod:`profilegen.rim.cup.fourier`.

The displacement u_r = Σ U_n cos nφ, u_z = Σ W_n cos nφ, u_φ = Σ V_n sin nφ (n in ``orders``;
for n = 0 the torsion u_φ = V₀, as there) is evaluated at the meridional quadrature points ×
``samples`` equispaced angles φ_s on the whole circle. There, in the orthonormal cylindrical frame (components r, z, φ),

    H = Grad u:  H_rr = ∂u_r/∂r   H_rz = ∂u_r/∂z   H_rφ = (∂u_r/∂φ − u_φ)/r
                 H_zr = ∂u_z/∂r   H_zz = ∂u_z/∂z   H_zφ = (∂u_z/∂φ)/r
                 H_φr = ∂u_φ/∂r   H_φz = ∂u_φ/∂z   H_φφ = (∂u_φ/∂φ + u_r)/r

F = I + H, E = ½(H + Hᵀ + HᵀH), S = λ tr E I + 2μ E, P = F S (exact in a fixed orthonormal
frame: the frame at the material point X). The internal virtual work ∫ P : δH dV with the
harmonic-m test functions (N cos mφ for r and z, N sin mφ for φ) gives the generalised
internal force of every harmonic: the φ-integral by the trapezoid rule on the samples (exact
for the trigonometric polynomial P : δH when ``samples`` > 4·max order, P being cubic in u),
the meridional integral by the basis's quadrature. It is the work-conjugate of the
coefficients with the same ∫cos² normalisation as :meth:`HarmonicBasis.stiffness`, so for a
small displacement R(u) → K_n u_n (tested), and a finite rigid rotation about the axis gives
R = 0 (tested).

The symmetry of a two-wave load (u_r, u_z even in φ, u_φ odd) is kept: the projection of
P : δH onto cos mφ (r, z) and sin mφ (φ) is the whole of it. The nonlinear terms couple the
harmonics (those above ``orders`` are dropped: the same truncation as the linear model).
"""

from __future__ import annotations

import math

import numpy as np

from .fourier import HarmonicBasis, lame

__all__ = ["HarmonicTotalLagrangian"]


class HarmonicTotalLagrangian:
    """Internal force R(x) of the cup for harmonic coefficients ``x`` (harmonics, dof): dof
    3k + c of scalar node k, c = 0 radial U (cos), 1 axial W (cos), 2 tangential V (sin), as
    :class:`HarmonicBasis`. ``force(x)`` → R (harmonics, dof), N (generalised)."""

    def __init__(self, harmonic_basis: HarmonicBasis, orders, *, samples: int | None = None):
        hb = harmonic_basis
        g = hb.cup_mesh.geometry
        self.lam, self.mu = lame(g.youngs_modulus_mpa, g.poisson_ratio)
        b = hb.basis
        self.value = np.stack([np.asarray(f[0]) for f in b.basis])  # (nb, ne, nq)
        self.grad = np.stack([f[0].grad for f in b.basis])  # (nb, 2, ne, nq)
        self.r = np.asarray(b.global_coordinates())[0]  # (ne, nq)
        self.w = self.r * np.asarray(b.dx)  # r dr dz weights
        self.dofs = np.asarray(b.element_dofs)  # (nb, ne)
        self.nodes = int(b.N)
        self.orders = np.asarray(orders, dtype=int)
        top = int(self.orders.max(initial=0))
        self.samples = int(samples) if samples is not None else max(16, 4 * top + 8)
        phi = 2.0 * math.pi * np.arange(self.samples) / self.samples
        n = self.orders[:, None].astype(float)
        self.cos = np.cos(n * phi)  # (H, S)
        self.sin = np.sin(n * phi)
        self.tan = np.where(self.orders[:, None] == 0, 1.0, self.sin)  # u_φ: sin nφ, and V₀ (torsion) for n = 0
        self.weight = 2.0 * math.pi / self.samples

    def _fields(self, x):
        """Value, ∂/∂r, ∂/∂z of each component's coefficient at the quadrature points:
        (3 comps, 3 kinds, H, ne, nq)."""
        x = np.asarray(x, dtype=float).reshape(self.orders.size, self.nodes, 3)
        loc = x[:, self.dofs, :]  # (H, nb, ne, 3)
        val = np.einsum("hbec,beq->cheq", loc, self.value)
        dr = np.einsum("hbec,beq->cheq", loc, self.grad[:, 0])
        dz = np.einsum("hbec,beq->cheq", loc, self.grad[:, 1])
        return val, dr, dz

    def stress(self, x):
        """First Piola–Kirchhoff stress P (3, 3, ne·nq, S) in the frame (r, z, φ), MPa."""
        val, dr, dz = self._fields(x)
        h_, e_, q_ = val.shape[1:]
        c, s = self.cos, self.sin
        n = self.orders.astype(float)[:, None]

        def synth(coef, trig):  # (H, ne, nq) → (ne·nq, S)
            return coef.reshape(h_, e_ * q_).T @ trig

        r = self.r.reshape(-1, 1)
        ur, up = synth(val[0], c), synth(val[2], self.tan)
        dur_dphi = synth(val[0], -n * s)
        duz_dphi = synth(val[1], -n * s)
        dup_dphi = synth(val[2], n * c)
        H = np.empty((3, 3) + ur.shape)
        H[0, 0], H[0, 1], H[0, 2] = synth(dr[0], c), synth(dz[0], c), (dur_dphi - up) / r
        H[1, 0], H[1, 1], H[1, 2] = synth(dr[1], c), synth(dz[1], c), duz_dphi / r
        H[2, 0], H[2, 1], H[2, 2] = synth(dr[2], self.tan), synth(dz[2], self.tan), (dup_dphi + ur) / r
        # E = ½(H + Hᵀ + HᵀH), S = λ tr E I + 2μ E, P = (I + H) S, component by component (the
        # 3 × 3 products over ~10⁵ points are faster as array sums than as einsum)
        S = np.empty_like(H)
        for i in range(3):
            for j in range(i, 3):
                e = 0.5 * (H[i, j] + H[j, i] + H[0, i] * H[0, j] + H[1, i] * H[1, j] + H[2, i] * H[2, j])
                S[i, j] = e
                if j != i:
                    S[j, i] = e
        lam_tr = self.lam * (S[0, 0] + S[1, 1] + S[2, 2])
        S *= 2.0 * self.mu
        for i in range(3):
            S[i, i] += lam_tr
        P = S.copy()  # the I S part
        for i in range(3):
            for j in range(3):
                P[i, j] += H[i, 0] * S[0, j] + H[i, 1] * S[1, j] + H[i, 2] * S[2, j]
        return P

    def force(self, x) -> np.ndarray:
        """Generalised internal force R (harmonics, dof)."""
        P = self.stress(x)
        wt = self.weight
        cos, sin, tan = self.cos.T * wt, self.sin.T * wt, self.tan.T * wt  # (S, H)
        n = self.orders.astype(float)[None, :]

        def pc(a, b):  # (ne·nq, H)
            return P[a, b] @ cos

        def ps(a, b):
            return P[a, b] @ sin

        def pt(a, b):
            return P[a, b] @ tan

        r = self.r.reshape(-1, 1)
        # coefficients of N_r, N_z and N (value) for each component and harmonic
        rows = {
            0: (pc(0, 0), pc(0, 1), (-n * ps(0, 2) + pc(2, 2)) / r),
            1: (pc(1, 0), pc(1, 1), (-n * ps(1, 2)) / r),
            2: (pt(2, 0), pt(2, 1), (-pt(0, 2) + n * pc(2, 2)) / r),
        }
        ne, nq = self.r.shape
        w = self.w.reshape(-1, 1)
        out = np.zeros((self.orders.size, self.nodes, 3))
        for comp, (a_r, a_z, a_v) in rows.items():
            a_r, a_z, a_v = ((t * w).reshape(ne, nq, -1) for t in (a_r, a_z, a_v))
            local = (np.einsum("beq,eqh->beh", self.grad[:, 0], a_r) + np.einsum("beq,eqh->beh", self.grad[:, 1], a_z)
                     + np.einsum("beq,eqh->beh", self.value, a_v))  # (nb, ne, H)
            for h in range(self.orders.size):
                out[h, :, comp] += np.bincount(self.dofs.ravel(), weights=local[:, :, h].ravel(),
                                               minlength=self.nodes)
        return out.reshape(self.orders.size, -1)
