"""The loaded contact of one flank on reduced systems: the continuation solver of
:func:`~profilegen.contact.chain.torsional_curve` (:class:`ReducedZone`), the Hertz ball
springs' fixed point (:class:`SpringIteration`) and the ContactSolution of a reduced solve
(:func:`zone_solution`). Also the independent solve of
:func:`~profilegen.contact.analysis.solve_contact` (``solver="active_set"`` with every ball:
``ReducedZone.solve(teeth="active_set")``). Its own module so that both
:mod:`profilegen.contact.chain` and :mod:`profilegen.contact.analysis` use it without importing
each other."""

from __future__ import annotations

import time

import numpy as np

from .springs import ball_totals, spring_block

__all__ = ["ReducedZone", "SpringIteration", "zone_solution"]


class SpringIteration:
    """The Hertz ball springs' secant fixed point, in log c: c = c_H R(c)^(−1/3) per ball.

    Plain steps contract by ~1/3 (12 steps to 1e-6 on the default set); a per-ball secant
    estimate q of the map's slope (Steffensen) takes x + (g − x)/(1 − q) instead, and a start
    from a neighbouring torque's springs leaves a few steps. A reaction is held ≥ max(1 N,
    1e-3 × the largest) in the secant (the secant is infinite at no load; the spring of a
    ball that carries nothing does not enter the solve). ``x``: the current log springs (None:
    rigid balls so far, the first step takes the secants at their reactions)."""

    __slots__ = ("c_hertz", "tol", "x", "x_prev", "g_prev")

    def __init__(self, c_hertz: float, tol: float, x=None):
        self.c_hertz = float(c_hertz) if np.ndim(c_hertz) == 0 else np.asarray(c_hertz, dtype=float)  # one per ball
        self.tol, self.x = float(tol), x
        self.x_prev = self.g_prev = None

    def step(self, reactions_n) -> bool:
        """True when the springs ``x`` reproduce themselves at these reactions to ``tol``
        (relative); else ``x`` moves to the next iterate and False."""
        react = np.asarray(reactions_n, dtype=float)
        floor = max(1.0, 1e-3 * float(react.max(initial=0.0)))
        g = np.log(self.c_hertz * np.maximum(react, floor) ** (-1.0 / 3.0))
        x = self.x
        if x is not None and np.all(np.abs(np.expm1(g - x)) <= self.tol):
            return True
        step = g
        if x is not None and self.x_prev is not None:
            dx, dg = x - self.x_prev, g - self.g_prev
            q = np.clip(np.divide(dg, dx, out=np.zeros_like(dx), where=np.abs(dx) > 1e-14), -0.9, 0.5)
            step = x + (g - x) / (1.0 - q)
        if x is not None:
            self.x_prev, self.g_prev = x, g
        self.x = step
        return False

    @property
    def springs(self):
        return None if self.x is None else np.exp(self.x)


class ReducedZone:
    """One flank's contact, ball settling and Hertz springs solved on reduced systems.

    The same problem as :func:`~profilegen.contact.chain._solve_side` (whose answer is unique: the contact's QP is
    strictly convex for given springs), solved without assembling the n × n compliance or
    running Lemke's method from scratch. For a ball set B (the balls in contact) with springs
    c, each ball of B closed at its no-load gap γ_B (0 for the window's balls), the ball
    reactions are R_B = −W F − b (F_BB + C b)⁻¹ γ_B with W = (F_BB + C b)⁻¹ F_cBᵀ, C the springs'
    block (:func:`~profilegen.contact.springs.spring_block`: diag(c), or c between the shares of
    one ball in the axial slices) (a |B| × |B| Cholesky factor), so the teeth see the compliance S[:, P] = S_CS[:, P] +
    (F_cc[:, P] − F_cB W[:, P]) / b at the loaded points P and an initial separation r_k θ_k
    − (Wᵀ γ_B)_k (the closed balls' gaps pull the rim in: an offset of each point's first
    contact angle). Equilibrium and closed gaps on P are a (|P| + 1) bordered system; P
    follows the primal–dual active-set rule (keep the loaded points with F > 0, take in the
    points with a negative gap) from the previous torque's P, B and springs — continuation in
    T —, B the ball-settling rule (:func:`~profilegen.contact.compliance.settle_step`: the
    most tensile ball leaves, else the ball the rim moves into most, past its gap, comes
    back), the springs their secant fixed point (:class:`SpringIteration`), all in one loop.
    At its end teeth and balls are both complementary: F ≥ 0, g ≥ 0, F g = 0 and R ≥ 0,
    h ≥ 0, R h = 0 (h the balls' gaps after load). A loop that cycles or does not end falls
    back to the reference (Lemke from scratch) for that torque.
    """

    def __init__(self, points, compliance, bearing):
        self.points, self.compliance, self.bearing = points, compliance, bearing
        self.theta = np.asarray(points.theta_rad, dtype=float)
        self.r = np.asarray(points.lever_mm, dtype=float)
        self.b = float(compliance.face_width_mm)
        cc = np.asarray(compliance._flex_cc, dtype=float)
        self.cc = 0.5 * (cc + cc.T)
        self.cs = np.asarray(compliance.cs_matrix_mm_per_n, dtype=float)
        self.cb = np.asarray(compliance._flex_cb, dtype=float)
        self.bb = np.asarray(compliance._flex_bb, dtype=float)
        nb = self.bb.shape[0]
        gap = getattr(compliance, "ball_gap_mm", None)
        self.gap = np.zeros(nb) if gap is None else np.asarray(gap, dtype=float)
        self.body = getattr(compliance, "ball_body", None)  # shares of one ball (axial slices), or None
        self.base_diag = np.diag(self.cs) + np.diag(self.cc) / self.b
        # S_CS + F_cc / b once, transposed (C order): a column set is then a gather of contiguous rows
        # (~20× faster than gathering the columns of two C-order matrices); the same sums, elementwise
        self._base_t = np.ascontiguousarray((self.cs + self.cc / self.b).T)
        self._rigid: dict[bytes, tuple] = {}  # _balls with rigid balls, by the ball set
        self.c_hertz = None if bearing is None else bearing.hertz_coefficient()

    # --- the pieces for one ball set
    def _balls(self, active, springs):
        """→ (the active balls, W, the teeth's first-contact angles with the balls' gaps closed,
        the reactions' part from the gaps (N)). With rigid balls (``springs`` None) they depend on
        the ball set alone: kept by it (the rigid solves of a curve's torques meet the same few
        sets again and again: 223 calls, 107 sets on the default set's design scene)."""
        if springs is not None:
            return self._balls_made(active, springs)
        key = np.asarray(active, bool).tobytes()
        hit = self._rigid.get(key)
        if hit is None:
            hit = self._balls_made(active, None)
            for a in hit:
                if a is not self.theta:  # (the points' own angles where no ball has a gap: not ours to flag)
                    a.flags.writeable = False  # shared by every later call with this set
            if len(self._rigid) < 256:  # ~0.26 MB each on the sliced curve's 965 points
                self._rigid[key] = hit
        return hit

    def _balls_made(self, active, springs):
        from scipy.linalg import cho_factor, cho_solve

        act = np.flatnonzero(active)
        if act.size == 0:
            return act, np.zeros((0, self.r.size)), self.theta, np.zeros(0)
        block = self.bb[np.ix_(act, act)]
        if springs is not None:
            block = block + spring_block(springs, act, self.body) * self.b
        factor = cho_factor(block)
        w = cho_solve(factor, self.cb[:, act].T)
        gap = self.gap[act]
        if not np.any(gap):
            return act, w, self.theta, np.zeros(act.size)
        u = cho_solve(factor, gap)
        return act, w, self.theta - (self.cb[:, act] @ u) / self.r, -self.b * u

    def _columns(self, act, w, cols):
        out = np.ascontiguousarray(self._base_t[cols].T)  # C order, as the sum of two column gathers was
        if act.size:
            out -= (self.cb[:, act] @ w[:, cols]) / self.b
        return out

    def _contact(self, act, w, th, tz, loaded):
        """Contact for fixed balls from the loaded set ``loaded`` (bool), ``th`` the points'
        first-contact angles (with the closed balls' gaps): → (F, φ, gaps, loaded,
        iterations) or None when the active-set rule cycles."""
        r = self.r
        seen = set()
        for it in range(1, 4 * r.size + 20):
            key = loaded.tobytes()
            if key in seen:
                return None
            seen.add(key)
            p = np.flatnonzero(loaded)
            if p.size == 0:
                p = np.array([int(np.argmin(th))])
                loaded = np.zeros(r.size, bool)
                loaded[p] = True
            cols = self._columns(act, w, p)
            spp = 0.5 * (cols[p] + cols[p].T)
            # scaled as the solvers are (moments m = rF/T, angles over τ = a0 T)
            a0 = float(np.mean(np.diag(spp) / r[p] ** 2))
            tau = a0 * tz
            tmin = float(th[p].min())
            k = p.size
            kkt = np.zeros((k + 1, k + 1))
            kkt[:k, :k] = spp / np.outer(r[p], r[p]) / a0
            kkt[:k, k] = -1.0
            kkt[k, :k] = 1.0
            rhs = np.concatenate([-(th[p] - tmin) / tau, [1.0]])
            sol = np.linalg.solve(kkt, rhs)
            force = np.zeros(r.size)
            force[p] = tz * sol[:k] / r[p]
            phi = tmin + tau * float(sol[k])
            gap = r * (th - phi) + cols @ force[p]
            ghat = gap / (r * tau)
            tol = 1e-10 * (1.0 + abs(float(sol[k])))
            new = (loaded & (force > 0.0)) | (~loaded & (ghat < -tol))
            if np.array_equal(new, loaded):
                return force, phi, gap, loaded, it
            loaded = new
        return None

    def _contact_qp(self, act, w, th, tz, loaded):
        """:meth:`_contact` by the primal active-set QP on the whole compliance with these balls
        closed (:func:`~profilegen.contact.solvers.solve_qp_active_set`: an independent
        algorithm; ``loaded`` unused, the QP starts on its own)."""
        from .solvers import solve_qp_active_set

        cols = self._columns(act, w, np.arange(self.r.size))
        shift = float(th.min())  # the QP takes θ ≥ 0: φ measured from the smallest
        sol = solve_qp_active_set(0.5 * (cols + cols.T), th - shift, self.r, tz)
        force, phi = np.asarray(sol.force_n, dtype=float), float(sol.phi_rad) + shift
        return force, phi, self.r * (th - phi) + cols @ force, force > 0.0, sol.iterations

    def solve(self, magnitude_nm: float, state, *, springs_on: bool, max_iterations: int, spring_tol: float,
              teeth: str = "reduced"):
        """One |T| from ``state`` = (loaded points, active balls, log springs or None), the
        previous torque's: → dict (φ, F, gaps, loaded, ball set, reactions, the balls' gaps
        after load, springs, S's diagonal, iterations) or None (the loop cycled or did not
        end: use the reference). ``springs_on``: with the Hertz springs (from rigid supports
        when the state has none), else rigid balls. ``teeth``: "reduced" (the bordered
        systems on the loaded points, from the state's) or "active_set" (:meth:`_contact_qp`)."""
        from .compliance import settle_step

        tz = magnitude_nm / self.points.zones * 1e3
        loaded, active, x = state
        loaded, active = loaded.copy(), active.copy()
        springs = SpringIteration(self.c_hertz, spring_tol, x) if springs_on else None
        total = 0
        seen = set()
        for _ in range(max_iterations):
            c = None if springs is None else springs.springs
            act, w, th, react_gap = self._balls(active, c)
            out = (self._contact_qp if teeth == "active_set" else self._contact)(act, w, th, tz, loaded)
            if out is None:
                return None
            force, phi, gap, loaded, it = out
            total += it
            react = np.zeros(active.size)
            if act.size:
                react[act] = react_gap - w @ force
            # the balls' gaps after load (an active ball's: its spring's compression, ~0)
            ball_gap = self.gap + self.cb.T @ (force / self.b) + self.bb[:, act] @ (react[act] / self.b)
            if c is not None:  # each spring compressed by its ball's load (the sum over a ball's shares)
                ball_gap += c * ball_totals(react, self.body)
            active_new, change = settle_step(active, react, ball_gap)
            if change == "leave":
                active = active_new
                continue
            if change == "return":
                key = (active.tobytes(), None if springs is None or springs.x is None else springs.x.tobytes())
                if key in seen:
                    return None
                seen.add(key)
                active = active_new
                continue
            if springs is None or springs.step(ball_totals(react, self.body)):
                break
        else:
            return None
        diag = self.base_diag.copy()
        if act.size:
            diag -= np.einsum("ij,ji->i", self.cb[:, act], w) / self.b
        return {"phi": phi, "force": force, "gap": gap, "loaded": loaded, "active": active, "reactions": react,
                "ball_gap": ball_gap, "log_springs": None if springs is None else springs.x, "diag": diag,
                "iterations": total}


def zone_solution(zone: ReducedZone, magnitude_nm: float, out: dict, t0: float, *, method: str = "continuation"):
    """A ContactSolution of the reduced solve (the fields and residuals of solvers._finish)."""
    from .solvers import ContactSolution

    tz = magnitude_nm / zone.points.zones * 1e3
    r = zone.r
    force, phi, gap, loaded, iterations = out["force"], out["phi"], out["gap"], out["loaded"], out["iterations"]
    moment = r * force
    theta_min = float(zone.theta.min())
    a0 = float(np.mean(out["diag"] / r ** 2))
    tau = a0 * tz
    # teeth and balls on one scale (as ContactCompliance.solve_unilateral's residual)
    comp = max(float(np.max(np.abs(force * gap))), float(np.max(np.abs(out["reactions"] * out["ball_gap"]),
                                                                initial=0.0))) / (tz * (abs(phi - theta_min) + tau))
    equi = abs(float(np.sum(moment)) - tz) / tz
    warnings = []
    all_loaded = bool(np.all(loaded))
    if all_loaded:
        warnings.append(f"all {r.size} candidate points are loaded: the torque {tz:.6g} N·mm has used up the contact "
                        "points given; points not in the list (further teeth or flank) would close too")
    return ContactSolution(
        method=method, torque_nmm=tz, force_n=force, moment_nmm=moment, phi_rad=phi, gap_mm=gap,
        loaded=loaded, iterations=iterations, complementarity_residual=comp, equilibrium_residual=equi,
        time_s=time.perf_counter() - t0, all_points_loaded=all_loaded, warnings=tuple(warnings),
        diagnostics={"tau_rad": tau, "theta_min_rad": theta_min, "a0_rad_per_nmm": a0, "points": int(r.size),
                     "balls_loaded": int(np.count_nonzero(out["reactions"] > 0.0))})
