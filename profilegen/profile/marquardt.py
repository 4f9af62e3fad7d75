"""Levenberg–Marquardt for the arc fit's small least-squares problems, the same on every call.

The arc fit's least-squares stage (6 unknowns, up to a few thousand residuals) ran
``scipy.optimize.least_squares(method="lm")`` (MINPACK). With scipy 1.17.1 that call is not
reproducible on ill-conditioned data: on one 75-point branch of a perturbed seed-002 flank, the
same call with the same inputs stepped to points one ulp apart on some calls and not on others
(its evaluations matched to the bit up to the 83rd; two distinct results in 40 calls), and the
minimax fit started from it differed by 3e-9 of its max error — the same design's numbers changed
from run to run. :func:`levenberg_marquardt` is the textbook method (Marquardt's scaling by the
columns' norms, Nielsen's damping update) in numpy, whose 6 × 6 solves and products give the same
bits on every call.

Stops (``status``, as MINPACK's): 1 when the actual and the predicted relative reductions of the
cost are both at most ``ftol``, 2 when the scaled step is at most ``xtol`` of the scaled point,
4 when every column of the Jacobian is within ``gtol`` of orthogonal to the residuals, 0 when
``max_nfev`` evaluations are spent, −1 when a residual is not finite at the start.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["LMResult", "levenberg_marquardt"]


@dataclass(frozen=True)
class LMResult:
    """The point ``x``, ``cost`` = ½ Σ r², residual evaluations ``nfev``, ``status`` (module
    docstring) and ``optimality`` = max |Jᵀ r| (the first-order optimality, as scipy's)."""

    x: np.ndarray
    cost: float
    nfev: int
    status: int
    optimality: float


def levenberg_marquardt(residuals: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]], x0: np.ndarray, *,
                        ftol: float = 1e-15, xtol: float = 1e-15, gtol: float = 1e-15,
                        max_nfev: int = 200) -> LMResult:
    """min ½ Σ r(x)² from ``x0``; ``residuals(x)`` gives (r (m,), its Jacobian (m, n))."""
    x = np.array(x0, dtype=float)
    r, J = residuals(x)
    nfev = 1
    if not (np.all(np.isfinite(r)) and np.all(np.isfinite(J))):
        return LMResult(x, float("inf"), nfev, -1, float("inf"))
    cost = 0.5 * float(r @ r)
    A, g = J.T @ J, J.T @ r
    scale = np.sqrt(np.diag(A))
    scale[scale == 0.0] = 1.0
    mu, grow = 1e-3, 2.0  # the damping relative to the scaled curvature, and its growth on a rejected step
    status = 0
    while True:
        if cost == 0.0 or float(np.max(np.abs(g) / (scale * np.sqrt(2.0 * cost)))) <= gtol:
            status = 4
            break
        if nfev >= max_nfev:
            break
        D2 = scale * scale
        try:
            step = np.linalg.solve(A + mu * np.diag(D2), -g)
        except np.linalg.LinAlgError:
            mu *= grow
            grow *= 2.0
            continue
        small = float(np.linalg.norm(scale * step)) <= xtol * max(float(np.linalg.norm(scale * x)), 1e-300)
        x_new = x + step
        r_new, J_new = residuals(x_new)
        nfev += 1
        cost_new = 0.5 * float(r_new @ r_new) if np.all(np.isfinite(r_new)) else float("inf")
        predicted = -float(g @ step + 0.5 * step @ A @ step)
        actual = cost - cost_new
        if predicted > 0.0 and actual > 0.0 and np.all(np.isfinite(J_new)):
            rho = actual / predicted
            converged = actual <= ftol * cost and predicted <= ftol * cost
            x, r, cost = x_new, r_new, cost_new
            A, g = J_new.T @ J_new, J_new.T @ r_new
            scale = np.maximum(scale, np.sqrt(np.diag(A)))
            mu *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
            grow = 2.0
            if converged:
                status = 1
                break
            if small:
                status = 2
                break
        else:
            if small:  # no decrease, and the step is at the rounding of the point: it is a minimum
                status = 2
                break
            mu *= grow
            grow *= 2.0
    return LMResult(x, cost, nfev, status, float(np.max(np.abs(g))))
