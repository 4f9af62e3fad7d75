"""Loaded tooth contact as a complementarity problem: the solvers (pure math).

``n`` candidate contact points k (pairs of points on the FS and CS flanks): ``S`` (n×n, mm/N)
the compliance, symmetric positive definite; ``θ_k`` (rad, ≥ 0) the initial angular separation
and ``r_k`` (mm, > 0) the lever arm of the common normal; ``T`` (N·mm, > 0) the torque on the
flexspline. Unknowns: the contact forces ``F_k ≥ 0`` (N) and the rigid rotation ``φ`` (rad) of
the FS against the fixed CS, with the normal gaps after load (mm)

    g_k = r_k (θ_k − φ) + Σ_j S_kj F_j ≥ 0,     F_k g_k = 0,     Σ_k r_k F_k = T.

The solution is unique (it is the minimiser of a strictly convex QP in the moments r_k F_k, φ
the multiplier of the equilibrium), and φ never decreases as T grows.

* :func:`solve_lemke` — the package's contact solver: Lemke's complementary pivoting, which is
  the CSF-40 study's "modified simplex" (restricted basis entry) made deterministic;
* :func:`solve_qp_active_set` — an independent primal active-set method on the QP, for
  cross-checks.

Each returns a :class:`ContactSolution` (forces, rotation, gaps, the active set, the
complementarity and equilibrium residuals, warnings). Lemke's tableau itself, shared with the
teeth-and-balls problem, is :mod:`profilegen.lcp`'s.

Errors, rather than silent answers: ``T ≤ 0`` or non-finite, ``S`` not square / not
symmetric / not positive definite / numerically singular, ``θ < 0``, ``r ≤ 0``, NaN or inf
anywhere → :class:`ContactError` (a ``ValueError``) naming the parameter, its value, unit and
allowed range; a pivot or iteration cap, a ray termination, a basis that is not a solution
after reinversion, or a result with no loaded point →
:class:`~profilegen.errors.ConvergenceError` naming the solver, the pivot, the applied torque
fraction and the residual. When every candidate point is loaded the answer is only a bound
(points not discretised would have closed too): ``all_points_loaded = True`` and a warning.

The KKT derivation, the scaling, why Lemke is Conry–Seireg's method and what its pivots mean:
docs/theory/contact.md, "The contact problem and its solvers".

>>> import numpy as np
>>> S = np.array([[2.0, 0.5], [0.5, 1.0]]) * 1e-7      # mm/N
>>> res = solve_lemke(S, [0.0, 1e-6], [30.0, 30.0], 2.0e4)
>>> res.loaded.tolist(), round(float(res.force_n.sum() * 30.0), 6)
([True, True], 20000.0)
>>> res.complementarity_residual < 1e-12 and res.equilibrium_residual < 1e-12
True
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla

from ..errors import ConvergenceError, ProfilegenError
from ..lcp import LemkeTableau
from ..results import json_ready as _json, readonly as _readonly

__all__ = [
    "ContactError",
    "ContactSolution",
    "solve_lemke",
    "solve_qp_active_set",
]

log = logging.getLogger(__name__)


#: reciprocal condition number of the scaled compliance below which it counts as singular
_RCOND_MIN = 1e-12
#: relative asymmetry of S tolerated (then symmetrised)
_SYM_TOL = 1e-8
#: scaled feasibility tolerance (m and ĝ are O(1)) for the final checks
_FEAS_TOL = 1e-9


class ContactError(ProfilegenError, ValueError):
    """Bad input to a contact solver; the message names the parameter, its value, unit and range."""


# ----------------------------------------------------------------------------- result




@dataclass(frozen=True, slots=True, eq=False)
class ContactSolution:
    """The solution of one contact problem (one torque).

    ``force_n`` (N, ≥ 0) and ``moment_nmm`` = r·F (N·mm) per point; ``phi_rad`` the rigid rotation
    of the FS against the CS; ``gap_mm`` the normal gaps after load (≥ 0, 0 where loaded, up to
    round-off); ``loaded`` the active set (F > 0) as a boolean mask; ``iterations`` pivots (Lemke),
    active-set changes (QP) or HiGHS iterations (naive LP); ``complementarity_residual`` =
    max|F·g| / (T (φ − θ_min + τ)) and ``equilibrium_residual`` = |Σ r F − T| / T;
    ``all_points_loaded``: every candidate point carries load (the answer is then a bound);
    ``warnings``: human-readable flags; ``diagnostics``: scales (``tau_rad``, ``theta_min_rad``,
    ``a0_rad_per_nmm``), solver specifics.
    """

    method: str
    torque_nmm: float
    force_n: np.ndarray
    moment_nmm: np.ndarray
    phi_rad: float
    gap_mm: np.ndarray
    loaded: np.ndarray
    iterations: int
    complementarity_residual: float
    equilibrium_residual: float
    time_s: float
    all_points_loaded: bool
    warnings: tuple[str, ...] = ()
    diagnostics: dict = field(default_factory=dict)

    def __post_init__(self):
        object.__setattr__(self, "force_n", _readonly(self.force_n))
        object.__setattr__(self, "moment_nmm", _readonly(self.moment_nmm))
        object.__setattr__(self, "gap_mm", _readonly(self.gap_mm))
        object.__setattr__(self, "loaded", _readonly(self.loaded, bool))
        object.__setattr__(self, "warnings", tuple(self.warnings))
        object.__setattr__(self, "diagnostics", dict(self.diagnostics))

    @property
    def active_set(self) -> tuple[int, ...]:
        """Indices of the loaded points, ascending."""
        return tuple(int(i) for i in np.flatnonzero(self.loaded))

    @property
    def loaded_count(self) -> int:
        return int(np.count_nonzero(self.loaded))

    @property
    def max_force_n(self) -> float:
        return float(np.max(self.force_n))

    def to_dict(self) -> dict:
        return _json(
            {
                "method": self.method,
                "torque_nmm": self.torque_nmm,
                "phi_rad": self.phi_rad,
                "force_n": self.force_n,
                "moment_nmm": self.moment_nmm,
                "gap_mm": self.gap_mm,
                "active_set": list(self.active_set),
                "loaded_count": self.loaded_count,
                "max_force_n": self.max_force_n,
                "iterations": self.iterations,
                "complementarity_residual": self.complementarity_residual,
                "equilibrium_residual": self.equilibrium_residual,
                "all_points_loaded": self.all_points_loaded,
                "time_s": self.time_s,
                "warnings": list(self.warnings),
                "diagnostics": self.diagnostics,
            }
        )


# ----------------------------------------------------------------------------- input


@dataclass(frozen=True, slots=True)
class _Scaled:
    """The problem in the scaled variables (docs/theory/contact.md, "The contact problem and
    its solvers": a₀, τ, m = M/T, Â, θ̂, ψ)."""

    S: np.ndarray  # mm/N, symmetrised
    theta: np.ndarray  # rad
    r: np.ndarray  # mm
    T: float  # N·mm
    A: np.ndarray  # Â, dimensionless
    th: np.ndarray  # θ̂ = (θ − θ_min)/τ
    theta_min: float
    a0: float
    tau: float


def scale_problem(compliance_mm_per_n, theta_rad, radius_mm, torque_nmm) -> _Scaled:
    try:
        T = float(torque_nmm)
    except (TypeError, ValueError):
        raise ContactError(f"torque_nmm must be a number in (0, inf) N·mm, got {torque_nmm!r}") from None
    if not math.isfinite(T) or T <= 0.0:
        raise ContactError(f"torque_nmm must be finite and in (0, inf) N·mm, got {T!r}")

    def vector(name, value, unit, rng):
        try:
            a = np.array(value, dtype=float)
        except (TypeError, ValueError):
            raise ContactError(f"{name} must be a 1-D array of numbers ({unit}), got {value!r}") from None
        if a.ndim != 1 or a.size == 0:
            raise ContactError(f"{name} must be a non-empty 1-D array ({unit}), got shape {a.shape}")
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            i = int(bad[0])
            raise ContactError(f"{name} must be finite ({unit}, {rng}), got {name}[{i}] = {a[i]!r}")
        return a

    theta = vector("theta_rad", theta_rad, "rad", "range [0, inf)")
    r = vector("radius_mm", radius_mm, "mm", "range (0, inf)")
    n = theta.size
    if r.size != n:
        raise ContactError(f"radius_mm must have one entry per contact point ({n}, as theta_rad), got {r.size}")
    if np.any(theta < 0.0):
        i = int(np.argmin(theta))
        raise ContactError(f"theta_rad must be in [0, inf) rad (an initial separation), got theta_rad[{i}] = {theta[i]!r}")
    if np.any(r <= 0.0):
        i = int(np.argmin(r))
        raise ContactError(f"radius_mm must be in (0, inf) mm (lever arm of the common normal), got radius_mm[{i}] = {r[i]!r}")
    try:
        S = np.array(compliance_mm_per_n, dtype=float)
    except (TypeError, ValueError):
        raise ContactError(f"compliance_mm_per_n must be an n×n array of numbers (mm/N), got {compliance_mm_per_n!r}") from None
    if S.shape != (n, n):
        raise ContactError(
            f"compliance_mm_per_n must be square, one row and column per contact point ({n}×{n}, mm/N), got shape {S.shape}"
        )
    bad = np.argwhere(~np.isfinite(S))
    if bad.size:
        i, j = (int(v) for v in bad[0])
        raise ContactError(f"compliance_mm_per_n must be finite (mm/N), got compliance_mm_per_n[{i}, {j}] = {S[i, j]!r}")
    smax = float(np.max(np.abs(S)))
    if smax == 0.0:
        raise ContactError("compliance_mm_per_n must be symmetric positive definite (mm/N), got all zeros (singular)")
    asym = float(np.max(np.abs(S - S.T))) / smax
    if asym > _SYM_TOL:
        i, j = (int(v) for v in np.unravel_index(int(np.argmax(np.abs(S - S.T))), S.shape))
        raise ContactError(
            f"compliance_mm_per_n must be symmetric (mm/N, relative asymmetry ≤ {_SYM_TOL:g}), got "
            f"S[{i}, {j}] = {S[i, j]!r} vs S[{j}, {i}] = {S[j, i]!r} (relative asymmetry {asym:.3g})"
        )
    S = 0.5 * (S + S.T)
    diag = np.diag(S)
    if np.any(diag <= 0.0):
        i = int(np.argmin(diag))
        raise ContactError(
            f"compliance_mm_per_n must be positive definite (mm/N): diagonal entries in (0, inf), "
            f"got compliance_mm_per_n[{i}, {i}] = {diag[i]!r}"
        )
    a0 = float(np.mean(diag / r**2))
    A = S / np.outer(r, r) / a0
    try:
        c, _ = sla.cho_factor(A, lower=False, check_finite=False)
    except np.linalg.LinAlgError:
        w = float(np.linalg.eigvalsh(A)[0])
        raise ContactError(
            f"compliance_mm_per_n must be positive definite (mm/N), got a matrix with smallest eigenvalue "
            f"{w * a0 * float(np.mean(r)) ** 2:.3g} mm/N of the scaled D⁻¹SD⁻¹ (singular or indefinite)"
        ) from None
    anorm = float(np.max(np.sum(np.abs(A), axis=0)))
    rcond, info = sla.lapack.dpocon(c, anorm)
    if info != 0 or not rcond > _RCOND_MIN:
        raise ContactError(
            f"compliance_mm_per_n must be positive definite and not singular (mm/N): reciprocal condition "
            f"number of D⁻¹SD⁻¹ must be > {_RCOND_MIN:g}, got {rcond:.3g}"
        )
    tau = a0 * T
    theta_min = float(np.min(theta))
    th = (theta - theta_min) / tau
    return _Scaled(S=S, theta=theta, r=r, T=T, A=A, th=th, theta_min=theta_min, a0=a0, tau=tau)


def _finish(method: str, p: _Scaled, m: np.ndarray, psi: float, iterations: int, t0: float, *, loaded=None,
            warnings=(), diagnostics=None) -> ContactSolution:
    """Back to physical units, residuals, flags."""
    T, r, tau = p.T, p.r, p.tau
    g_hat = p.A @ m + p.th - psi
    force = T * m / r
    moment = r * force
    phi = p.theta_min + tau * psi
    gap = r * tau * g_hat
    if loaded is None:
        loaded = m > 0.0
    # |φ − θ_min|: a non-physical φ below the first contact (the naive LP's φ = 0) must not make it negative
    comp = float(np.max(np.abs(force * gap))) / (T * (abs(phi - p.theta_min) + tau))
    equi = abs(float(np.sum(moment)) - T) / T
    warnings = list(warnings)
    all_loaded = bool(np.all(loaded))
    if all_loaded:
        warnings.append(
            f"all {len(m)} candidate points are loaded: the torque {T:.6g} N·mm has used up the contact "
            "points given; points not in the list (further teeth or flank) would close too"
        )
    diag = {"tau_rad": tau, "theta_min_rad": p.theta_min, "a0_rad_per_nmm": p.a0, "points": len(m)}
    diag.update(diagnostics or {})
    return ContactSolution(
        method=method,
        torque_nmm=T,
        force_n=force,
        moment_nmm=moment,
        phi_rad=phi,
        gap_mm=gap,
        loaded=loaded,
        iterations=int(iterations),
        complementarity_residual=comp,
        equilibrium_residual=equi,
        time_s=time.perf_counter() - t0,
        all_points_loaded=all_loaded,
        warnings=tuple(warnings),
        diagnostics=diag,
    )


# ----------------------------------------------------------------------------- Lemke


def _lemke_reinvert(p: _Scaled, idx: np.ndarray, where: str) -> tuple[np.ndarray, float]:
    """Solve the bordered KKT system on the final basis' loaded points directly (reinversion)
    and check that it is a complementary solution; small negative round-off is clipped."""
    n = len(p.th)
    k = len(idx)
    K = np.zeros((k + 1, k + 1))
    K[:k, :k] = p.A[np.ix_(idx, idx)]
    K[:k, k] = -1.0
    K[k, :k] = 1.0
    rhs = np.concatenate([-p.th[idx], [1.0]])
    sol = np.linalg.solve(K, rhs)
    m = np.zeros(n)
    m[idx] = sol[:k]
    psi = float(sol[k])
    neg = float(np.min(m[idx]))
    if neg < -_FEAS_TOL:
        raise ConvergenceError(f"{where}: final basis is not feasible after reinversion (min m = {neg:.3g}, scaled)")
    m[m < 0.0] = 0.0
    g = p.A @ m + p.th - psi
    free = np.ones(n, bool)
    free[idx] = False
    if free.any():
        gmin = float(np.min(g[free]))
        if gmin < -_FEAS_TOL * (1.0 + abs(psi)):
            raise ConvergenceError(
                f"{where}: final basis leaves a penetration after reinversion "
                f"(gap {gmin:.3g} scaled at point {int(np.flatnonzero(free)[np.argmin(g[free])])})"
            )
    return m, psi



def solve_lemke(compliance_mm_per_n, theta_rad, radius_mm, torque_nmm, *, max_pivots: int | None = None) -> ContactSolution:
    """Contact forces and rotation by Conry–Seireg's restricted-entry simplex, as Lemke's method.

    ``compliance_mm_per_n`` (n×n, mm/N, SPD), ``theta_rad`` (n, rad, ≥ 0), ``radius_mm`` (n, mm, > 0),
    ``torque_nmm`` (N·mm, > 0). Lemke's complementary pivoting on the scaled LCP of the module
    docstring (covering vector 1, lexicographic ratio test, revised form with an explicit basis
    inverse, O(n²) per pivot); the final basis is reinverted (a direct solve on its loaded
    block) so the answer is accurate to round-off. ``max_pivots`` (default ``10 (n + 1) + 50``)
    caps the pivots; reaching it raises :class:`~profilegen.errors.ConvergenceError`.

    Cost: one pivot per point that closes (plus two), each O(n²) on the dense basis inverse.
    Gear-shaped problems with ~17 % of the points loaded (tests/benchmarks/contact_solvers.py):
    n = 200: 7 ms, 800: 0.23 s, 2000: 2.3 s (the active-set cross-check: 3 ms, 51 ms, 0.35 s).
    """
    t0 = time.perf_counter()
    p = scale_problem(compliance_mm_per_n, theta_rad, radius_mm, torque_nmm)
    n = len(p.th)
    N = n + 1
    cap = 10 * N + 50 if max_pivots is None else int(max_pivots)
    if cap < 1:
        raise ContactError(f"max_pivots must be an integer in [1, inf), got {max_pivots!r}")
    Mm = np.zeros((N, N))
    Mm[:n, :n] = p.A
    Mm[:n, n] = -1.0
    Mm[n, :n] = 1.0
    q = np.concatenate([p.th, [-1.0]])
    # variables: 0..N-1 w_j, N..2N-1 z_j, 2N z0; rows of [I, −𝕄, −1] x = q
    Z0 = 2 * N
    tab = LemkeTableau(Mm, q)
    basis = tab.basis

    # initial pivot: z0 in on the row of the most negative q (the equilibrium row, q = −1)
    row: int | None  # None: a ray (ratio_row)
    row = int(np.argmin(q))
    leaving = tab.pivot(row, tab.column(Z0), Z0)
    pivots = 1
    path: list[tuple[int, str, str]] = []  # (pivot, entering variable, leaving variable) – the loading history, kept short
    while True:
        entering = leaving + N if leaving < N else leaving - N  # complement of the variable that left
        col = tab.column(entering)
        row = tab.ratio_row(col)
        applied = 1.0 - float(tab.rhs[basis == Z0][0]) if np.any(basis == Z0) else 1.0
        if row is None:
            raise ConvergenceError(
                f"solve_lemke: ray termination at pivot {pivots} (entering {_name(entering, n)}, applied torque "
                f"fraction {applied:.6g}); impossible for an SPD compliance — numerical breakdown"
            )
        if pivots >= cap:
            raise ConvergenceError(
                f"solve_lemke: no complementary solution after {pivots} pivots (max_pivots = {cap}); applied torque "
                f"fraction {applied:.6g}, {int(np.count_nonzero((basis >= N) & (basis < N + n)))} points loaded, "
                f"entering {_name(entering, n)}"
            )
        leaving = tab.pivot(row, col, entering)
        pivots += 1
        if len(path) < 200:
            path.append((pivots, _name(entering, n), _name(leaving, n)))
        if leaving == Z0:
            break
    idx = np.sort(basis[(basis >= N) & (basis < N + n)] - N)
    if idx.size == 0:
        raise ConvergenceError(f"solve_lemke: terminated after {pivots} pivots with no loaded point (all gaps open)")
    m, psi = _lemke_reinvert(p, idx, f"solve_lemke (pivot {pivots})")
    loaded = m > 0.0
    log.debug("solve_lemke: n=%d, %d pivots, %d loaded", n, pivots, int(loaded.sum()))
    return _finish("lemke", p, m, psi, pivots, t0, loaded=loaded,
                   diagnostics={"max_pivots": cap, "path": [list(s) for s in path]})


def _name(var: int, n: int) -> str:
    N = n + 1
    if var == 2 * N:
        return "z0"
    if var < N:
        return "gap[equilibrium]" if var == n else f"gap[{var}]"
    return "phi" if var - N == n else f"F[{var - N}]"


# ----------------------------------------------------------------------------- active set


def solve_qp_active_set(compliance_mm_per_n, theta_rad, radius_mm, torque_nmm, *,
                        max_iter: int | None = None) -> ContactSolution:
    """The same problem by a primal active-set method on the QP in ``m = M / T`` (cross-check).

    Starts feasible with the whole torque on the point of smallest θ; each iteration solves
    the equality-constrained QP on the working set P (``Â_PP m_P − ψ1 = −θ̂_P``, ``Σ m_P = 1``
    by a Schur complement on the Cholesky factor of ``Â_PP``, grown by rank-one appends), then
    either steps toward it and drops the blocking point (a force would go negative), or adds
    the most penetrated point (most negative gap), or stops (all gaps ≥ 0). Strict convexity
    makes it finite. ``max_iter`` (default ``10 n + 50``) caps the iterations; reaching it
    raises :class:`~profilegen.errors.ConvergenceError`. Arguments as :func:`solve_lemke`.
    """
    t0 = time.perf_counter()
    p = scale_problem(compliance_mm_per_n, theta_rad, radius_mm, torque_nmm)
    A, th = p.A, p.th
    n = len(th)
    cap = 10 * n + 50 if max_iter is None else int(max_iter)
    if cap < 1:
        raise ContactError(f"max_iter must be an integer in [1, inf), got {max_iter!r}")
    P = [int(np.argmin(th))]
    R = np.array([[math.sqrt(A[P[0], P[0]])]])  # upper Cholesky factor of A_PP
    m = np.zeros(n)
    m[P[0]] = 1.0
    psi = float(th[P[0]] + A[P[0], P[0]])
    it = 0
    adds = drops = 0
    while True:
        it += 1
        if it > cap:
            g = A @ m + th - psi
            raise ConvergenceError(
                f"solve_qp_active_set: not converged after {cap} iterations (max_iter); {len(P)} points in the "
                f"working set, most negative gap {float(np.min(g)):.3g} (scaled)"
            )
        e = np.ones(len(P))
        x = sla.cho_solve((R, False), e, check_finite=False)
        y = sla.cho_solve((R, False), th[P], check_finite=False)
        psi_new = (1.0 + float(e @ y)) / float(e @ x)
        mP = psi_new * x - y
        cur = m[P]
        if np.all(mP > 0.0):
            m[:] = 0.0
            m[P] = mP
            psi = psi_new
            g = A @ m + th - psi
            g[P] = np.inf
            j = int(np.argmin(g))
            if g[j] >= -1e-12 * (1.0 + abs(psi)):
                break
            # append j to the working set: R ← [[R, u], [0, d]]
            u = sla.solve_triangular(R, A[P, j], trans="T", lower=False, check_finite=False)
            d2 = float(A[j, j] - u @ u)
            if d2 <= 0.0:
                raise ConvergenceError(
                    f"solve_qp_active_set: Cholesky append of point {j} failed at iteration {it} (pivot {d2:.3g})")
            k = len(P)
            Rn = np.zeros((k + 1, k + 1))
            Rn[:k, :k] = R
            Rn[:k, k] = u
            Rn[k, k] = math.sqrt(d2)
            R = Rn
            P.append(j)
            adds += 1
        else:
            step = mP - cur
            neg = step < 0.0
            alphas = np.where(neg, cur / np.where(neg, -step, 1.0), np.inf)
            alpha = min(1.0, float(np.min(alphas)))
            newP = cur + alpha * step
            drop = {P[i] for i in np.flatnonzero((mP <= 0.0) & (alphas <= alpha * (1 + 1e-12)))}
            if not drop:
                drop = {P[int(np.argmin(alphas))]}
            m[:] = 0.0
            m[P] = newP
            for i in drop:
                m[i] = 0.0
            P = [i for i in P if i not in drop]
            if not P:
                raise ConvergenceError(f"solve_qp_active_set: working set emptied at iteration {it}")
            R = sla.cholesky(A[np.ix_(P, P)], lower=False, check_finite=False)
            drops += len(drop)
    loaded = m > 0.0
    return _finish("qp_active_set", p, m, psi, it, t0, loaded=loaded,
                   diagnostics={"max_iter": cap, "added": adds, "dropped": drops})
