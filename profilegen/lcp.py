"""Linear complementarity problems: every LCP solver of the package.

An LCP asks for z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0 (or, in the contact's sign,
w = S λ − q). The stages pose them — the rim on the wave generator, the cup's band, the
teeth and balls of the contact, the ratcheting climb — and solve them here:

* :func:`lemke_lcp` (and its :class:`LemkeTableau`): Lemke's complementary pivoting for any
  copositive-plus M; returns the basic set, the caller solves its own equations on it
  (the contact's bordered problem, :func:`profilegen.contact.solvers.solve_lemke`, pivots
  the same tableau).
* :func:`solve_spd` (S symmetric positive definite, NNLS on its Cholesky factor) and
  :func:`solve_p_matrix` (a nonsymmetric P-matrix, Lemke), each on a candidate set that
  grows from the points with q < 0.
* :func:`active_set_lazy` (Lawson–Hanson, one point entering at a time) and
  :func:`principal_pivoting` (block principal pivoting from a guessed set, Murty's rule when
  it stalls), for an SPD S whose columns are expensive: both form only the columns they
  touch, through a ``columns_of(nodes)`` callback.
* :func:`spd_nnls`: an SPD LCP exactly, by NNLS on the whole Cholesky factor (the fallback of
  the two above), and :func:`primal_dual_from_guess` (the cup's band: a few linear solves
  from the last set, None if that does not settle).

Each returns the solution or None (the lazy ones, when they give up) or raises
:class:`~profilegen.errors.ConvergenceError` naming the caller's ``where``.
"""

from __future__ import annotations

import numpy as np
from .errors import ConvergenceError

__all__ = ["LemkeTableau", "active_set_lazy", "lemke_lcp", "primal_dual_from_guess", "principal_pivoting",
           "solve_p_matrix", "solve_spd", "spd_nnls"]


class LemkeTableau:
    """The revised tableau of Lemke's complementary pivoting for w = M z + q (rows
    [I, −M, −1] x = q; variables 0..N−1 the w's, N..2N−1 the z's, 2N the artificial z0;
    covering vector 1) with an explicit basis inverse, O(N²) per pivot. Shared by
    :func:`lemke_lcp` and the contact's bordered LCP
    (:func:`profilegen.contact.solvers.solve_lemke`)."""

    def __init__(self, m_mat: np.ndarray, q: np.ndarray):
        self.m, self.n = m_mat, q.size
        self.binv = np.eye(self.n)
        self.rhs = q.astype(float).copy()
        self.basis = np.arange(self.n)

    def column(self, j: int) -> np.ndarray:
        """Column of variable j in the current basis."""
        n = self.n
        if j < n:
            return self.binv[:, j].copy()
        if j < 2 * n:
            return -(self.binv @ self.m[:, j - n])
        return -self.binv.sum(axis=1)

    def pivot(self, row: int, col: np.ndarray, var: int) -> int:
        """``var`` enters on ``row`` (its column ``col``); returns the variable that leaves."""
        binv, rhs = self.binv, self.rhs
        piv = binv[row] / col[row]
        prow = rhs[row] / col[row]
        binv[...] -= np.outer(col, piv)
        binv[row] = piv
        rhs -= col * prow
        rhs[row] = prow
        leaving = int(self.basis[row])
        self.basis[row] = var
        return leaving

    def ratio_row(self, col: np.ndarray) -> int | None:
        """The leaving row of the minimum-ratio test (z0's row on a tie, then lexicographic on
        the rows of B⁻¹/col); None on a ray (no positive entry)."""
        tol = 1e-11 * max(1.0, float(np.max(np.abs(col))))
        cand = np.flatnonzero(col > tol)
        if cand.size == 0:
            return None
        ratios = self.rhs[cand] / col[cand]
        best = float(np.min(ratios))
        ties = cand[ratios <= best + 1e-12 * (1.0 + abs(best))]
        if ties.size > 1:
            z0row = np.flatnonzero(self.basis[ties] == 2 * self.n)
            if z0row.size:
                ties = ties[z0row]
            else:  # lexicographic rule on the rows of B⁻¹/col
                for j in range(self.n):
                    v = self.binv[ties, j] / col[ties]
                    ties = ties[v <= np.min(v) + 1e-14 * (1.0 + np.max(np.abs(v)))]
                    if ties.size == 1:
                        break
        return int(ties[0])



def lemke_lcp(m_mat: np.ndarray, q: np.ndarray, where: str, max_pivots: int | None = None):
    """Lemke's complementary pivoting for w = M z + q, w, z ≥ 0, wᵀz = 0 (covering vector 1,
    lexicographic ratio test, revised form with an explicit basis inverse), as
    :func:`~profilegen.contact.solvers.solve_lemke` pivots; for a copositive-plus M (here
    positive semidefinite) it ends at a solution whenever one exists (Cottle, Pang & Stone
    §4.4). Returns (the indices of the basic z's, pivots)."""
    n = q.size
    z0 = 2 * n
    cap = 10 * n + 50 if max_pivots is None else int(max_pivots)
    if np.all(q >= 0.0):
        return np.zeros(0, dtype=int), 0
    tab = LemkeTableau(m_mat, q)
    leaving = tab.pivot(int(np.argmin(q)), tab.column(z0), z0)
    pivots = 1
    while leaving != z0:
        entering = leaving + n if leaving < n else leaving - n
        col = tab.column(entering)
        row = tab.ratio_row(col)
        if row is None:
            raise ConvergenceError(f"{where}: Lemke's method ended on a ray at pivot {pivots}; impossible for a "
                                   "positive definite compliance — numerical breakdown")
        if pivots >= cap:
            raise ConvergenceError(f"{where}: no complementary solution after {pivots} pivots")
        leaving = tab.pivot(row, col, entering)
        pivots += 1
    basis = tab.basis
    return np.sort(basis[(basis >= n) & (basis < z0)] - n), pivots


def _candidate_set(m: np.ndarray, q: np.ndarray, tol: float | None, solve_candidates, where: str) -> np.ndarray:
    """The candidate-set loop: F ≥ 0, w = M F + q ≥ 0, F·w = 0 solved on a candidate set — the
    points with q_j < 0 first; ``solve_candidates(idx, tol)`` gives F on the candidates (zero
    elsewhere); a point outside whose w comes out below −tol joins and the set is solved again."""
    n = q.size
    f = np.zeros(n)
    if n == 0:
        return f
    scale = float(np.max(np.abs(q))) or 1.0
    tol = 1e-12 * scale if tol is None else tol
    cand = q < 0.0
    for _ in range(n + 1):
        idx = np.flatnonzero(cand)
        f[:] = 0.0
        if idx.size:
            f[idx] = solve_candidates(idx, tol)
        w = m @ f + q
        bad = (~cand) & (w < -tol)
        if not bad.any():
            return f
        cand |= bad
    raise ConvergenceError(f"{where}: the candidate set did not settle")


def solve_spd(s: np.ndarray, q: np.ndarray, *, tol: float | None = None) -> np.ndarray:
    """F ≥ 0 with w = S F + q ≥ 0 and F·w = 0, for S symmetric positive definite: the
    minimum of ½FᵀSF + qᵀF over F ≥ 0, as a non-negative least-squares problem on the
    Cholesky factor of S restricted to the candidates (q_j < 0 first; a point whose w comes
    out below −tol joins and the problem is solved again). Exact for SPD S."""
    from scipy.linalg import solve_triangular
    from scipy.optimize import nnls

    def on_candidates(idx, _tol):
        low = np.linalg.cholesky(s[np.ix_(idx, idx)])
        rhs = -solve_triangular(low, q[idx], lower=True)
        return nnls(low.T, rhs, maxiter=50 * idx.size)[0]

    return _candidate_set(s, q, tol, on_candidates, "lcp.solve_spd")


def solve_p_matrix(m: np.ndarray, q: np.ndarray, *, tol: float | None = None) -> np.ndarray:
    """F ≥ 0 with w = M F + q ≥ 0 and F·w = 0 for a general square M — the climb with
    friction, whose M is not symmetric (the force tilted off the normal its gap is measured
    along: a non-associated contact). Lemke's complementary pivoting
    (:func:`lemke_lcp`, lexicographic ratio test) on the
    candidates (q_j < 0 first; a point whose w comes out below −tol joins and the problem is
    solved again, as :func:`solve_spd`), on M and q scaled to O(1), the forces then from the
    active set's own equations. Lemke's method ends at the solution when M is a P-matrix
    (every principal minor > 0; Cottle, Pang & Stone, The Linear Complementarity Problem, §4.4),
    which it is when its symmetric part is positive definite (S + μ·(tangential coupling)
    for small μ); the result is checked (F ≥ 0, w ≥ 0 to ``tol``), a failure raises
    :class:`ConvergenceError`."""
    scale = float(np.max(np.abs(q))) if q.size else 1.0
    scale = scale or 1.0
    d = float(np.mean(np.abs(np.diag(m)))) if q.size else 1.0
    d = d or 1.0

    def on_candidates(idx, tol_):
        sub, f = m[np.ix_(idx, idx)], np.zeros(idx.size)
        act, _ = lemke_lcp(sub / d, q[idx] / scale, "lcp.solve_p_matrix")
        if act.size:
            f[act] = np.linalg.solve(sub[np.ix_(act, act)], -q[idx[act]])
        w = sub @ f + q[idx]  # = (M F + q) on the candidates: F is zero elsewhere
        if f.min() < -1e-9 * max(float(f.max()), 1e-300) or w.min(initial=0.0) < -1e3 * tol_:
            raise ConvergenceError(f"lcp.solve_p_matrix: Lemke's basis is not a solution (min F {f.min():.3g} N, "
                                   f"min w {w.min(initial=0.0):.3g} mm): M is not a P-matrix here")
        return np.maximum(f, 0.0)

    return _candidate_set(m, q, tol, on_candidates, "lcp.solve_p_matrix")


def active_set_lazy(columns_of, q, max_steps: int, guess=None):
    """The LCP of :func:`principal_pivoting` (w = Sλ − q ≥ 0, λ ≥ 0, λ·w = 0, S symmetric
    positive definite) by Lawson–Hanson's active-set method on the equivalent QP
    min ½λᵀSλ − qᵀλ, λ ≥ 0, one node entering at a time: the most violated free node enters;
    λ then moves from where it is toward the loaded set's equality solution and stops where
    a loaded node's λ reaches zero, that node freed (finite: the objective falls at every
    entry). ``guess``: a set to start from (the last solve's; from λ = 0 its nodes whose
    equality solution is not positive leave first), else the empty set.

    Only the columns of S of nodes that enter are formed: ``columns_of(nodes)`` (a list of
    indices) returns S[:, nodes], each formed once (the rim's lazy compliance solves their
    columns then). Block principal pivoting (:func:`principal_pivoting`) swaps every violator in at once — after the toothed rim's first
    re-linearisation 200–400 free nodes violate by a hair, of which a few stay loaded — so
    each of those would cost a column pair; here the first entries settle the rest. Returns
    λ, or None after ``max_steps`` entries or for a singular S_AA (the caller then condenses
    everything and runs NNLS)."""
    from scipy.linalg import LinAlgError, cho_factor, cho_solve

    n = q.size
    tol = 1e-12 * max(float(np.max(np.abs(q), initial=0.0)), 1e-300)
    lam = np.zeros(n)
    passive = np.zeros(n, dtype=bool) if guess is None else np.asarray(guess, dtype=bool)[:n].copy()
    column: dict[int, np.ndarray] = {}

    def columns(idx):
        new = [j for j in idx.tolist() if j not in column]
        if new:
            made = columns_of(new)
            column.update(zip(new, made.T))
        return np.column_stack([column[j] for j in idx.tolist()])

    def settle() -> bool:
        """λ on the loaded set from its feasible value toward the set's equality solution,
        freeing the nodes whose λ reaches zero on the way (each pass frees one at least)."""
        while passive.any():
            idx = np.flatnonzero(passive)
            cols = columns(idx)
            try:
                z = cho_solve(cho_factor(cols[idx], lower=True, check_finite=False), q[idx], check_finite=False)
            except (LinAlgError, ValueError):
                return False
            if np.all(z > 0.0):
                lam[:] = 0.0
                lam[idx] = z
                return True
            old = lam[idx]
            neg = z <= 0.0
            den = old[neg] - z[neg]
            alpha = float(np.min(np.where(den > 0.0, old[neg] / np.where(den > 0.0, den, 1.0), 0.0)))
            new = old + alpha * (z - old)
            out = neg & (new <= 1e-15 * max(float(np.max(old, initial=0.0)), 1e-300))
            out[np.argmin(np.where(neg, new, np.inf))] = True  # at least the one that reached zero
            new[out] = 0.0
            lam[:] = 0.0
            lam[idx] = new
            passive[idx[out]] = False
        lam[:] = 0.0
        return True

    if passive.any() and not settle():
        return None
    for _ in range(max_steps):
        idx = np.flatnonzero(passive)
        w = (columns(idx) @ lam[idx] - q) if idx.size else -q
        free_w = np.where(passive, np.inf, w)
        t = int(np.argmin(free_w))
        if not free_w[t] < -tol:
            return lam
        passive[t] = True
        if not settle():
            return None
    return None


def principal_pivoting(columns_of, q, guess, max_pivots: int = 60):
    """The solution λ of the LCP w = Sλ − q ≥ 0, λ ≥ 0, λ·w = 0 found from a guessed active set,
    or None. ``columns_of(nodes)`` (a list of indices) returns S[:, nodes]; each column is
    formed once.

    S is symmetric positive definite, so the LCP has one solution; a set A whose equations
    S_AA λ_A = q_A give λ_A > 0 and w ≥ 0 off A is it (the same as Lawson–Hanson's NNLS to
    rounding). From the guess (the last solve's set: a re-linearisation changes it by a few
    to ~40 nodes) the sign violations are swapped in and out together (block principal
    pivoting) while their number falls, else one at a time, the one of largest index (Murty's
    rule, finite for a positive definite S: Júdice & Pires 1994); None after ``max_pivots``
    or for a singular S_AA (the caller then solves the whole problem by :func:`spd_nnls`).
    Only the columns of S in A are formed: |A| ≈ 50–130 of ~1200 kept nodes on the toothed rim."""
    from scipy.linalg import LinAlgError, cho_factor, cho_solve

    active = np.asarray(guess, dtype=bool).copy()
    tol = 1e-12 * max(float(np.max(np.abs(q), initial=0.0)), 1e-300)
    fewest, chances = q.size + 1, 3
    column: dict[int, np.ndarray] = {}  # S's columns formed so far (a pivot changes a few nodes)
    for _ in range(max_pivots):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            return None
        new = [j for j in idx.tolist() if j not in column]
        if new:
            made = columns_of(new)
            column.update(zip(new, made.T))
        cols = np.column_stack([column[j] for j in idx.tolist()])
        try:
            lam = cho_solve(cho_factor(cols[idx], lower=True, check_finite=False), q[idx], check_finite=False)
        except (LinAlgError, ValueError):
            return None
        w = cols @ lam - q
        bad = np.zeros(q.size, dtype=bool)
        bad[idx[~(lam > 0.0)]] = True
        bad |= ~active & (w < -tol)
        count = int(bad.sum())
        if count == 0:
            forces = np.zeros(q.size)
            forces[idx] = lam
            return forces
        if count < fewest:
            fewest, chances = count, 3
        elif chances > 0:
            chances -= 1
        else:  # the block step stalls: one node, the last violator (Murty)
            last = np.flatnonzero(bad)[-1]
            bad[:] = False
            bad[last] = True
        active ^= bad
    return None


def primal_dual_from_guess(s: np.ndarray, q: np.ndarray, guess: np.ndarray | None, *,
                           max_sets: int = 12) -> np.ndarray | None:
    """λ ≥ 0 with w = Sλ − q ≥ 0, λ·w = 0 (S symmetric positive definite) by a primal–dual
    active-set iteration from the ``guess`` (a boolean set: the last solve's, so a few linear
    solves settle it): solve S_AA λ_A = q_A, then A ← {λ > 0 on A} ∪ {w < 0 off A}. None when
    there is no guess, the set cycles, a block is singular or ``max_sets`` sets did not settle:
    the caller then solves exactly (:func:`spd_nnls`)."""
    from scipy.linalg import LinAlgError, solve

    scale = max(float(np.max(np.abs(q))), 1e-300)
    on = None if guess is None or not guess.any() else guess.copy()
    seen: set[bytes] = set()
    while on is not None and on.any() and len(seen) < max_sets:
        key = on.tobytes()
        if key in seen:  # it cycles
            return None
        seen.add(key)
        try:
            part = solve(s[np.ix_(on, on)], q[on], assume_a="pos", check_finite=False)
        except (LinAlgError, ValueError):
            return None
        lam = np.zeros_like(q)
        lam[on] = part
        slack = s @ lam - q
        if np.all(part > 0.0) and np.min(slack[~on], initial=0.0) >= -1e-12 * scale:
            return lam
        on = np.where(on, lam > 0.0, slack < -1e-12 * scale)
    return None


def spd_nnls(s: np.ndarray, q: np.ndarray) -> np.ndarray:
    """λ ≥ 0 with w = Sλ − q ≥ 0, λ·w = 0 for a symmetric positive definite S, exactly: the
    minimum of ½λᵀSλ − qᵀλ over λ ≥ 0 is min |Lᵀλ − L⁻¹q| (S = LLᵀ), a non-negative
    least-squares problem (Lawson–Hanson). Raises numpy's/scipy's ``LinAlgError`` if S is not
    positive definite and RuntimeError if NNLS stops: the caller names its problem."""
    from scipy.linalg import cholesky, solve_triangular
    from scipy.optimize import nnls

    lower = cholesky(s, lower=True)
    return nnls(lower.T, solve_triangular(lower, q, lower=True), maxiter=50 * q.size)[0]
