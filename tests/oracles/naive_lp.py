"""The phase-1 LP of seed 000, Eqs. (15)–(17), exactly as printed — a negative example.

The tests run it beside the package's contact solvers to show that an LP optimum is not a
contact solution (docs/theory/contact.md, docs/validation/failures.md). Not a solver to use.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from profilegen.contact.solvers import ContactSolution, _finish, scale_problem
from profilegen.errors import ConvergenceError

__all__ = ["solve_naive_lp"]


def solve_naive_lp(compliance_mm_per_n, theta_rad, radius_mm, torque_nmm) -> ContactSolution:
    """The phase-1 LP of seed 000, Eqs. (15)–(17), exactly as printed, by HiGHS — a negative example.

    min Z = Σ X (artificials) subject to ``−[S']F + φ1 + Y + Z' = θ`` (16) and ``rᵀF + X = T`` (17),
    F, φ, Y, Z', X ≥ 0, with the seed's ``S' = D⁻¹S``. Built in the scaled variables of the module
    docstring (a positive diagonal rescaling of rows and columns, which maps vertices to vertices,
    so the answer is the printed LP's, not a scaling artefact). Z = 0 at *every* feasible point;
    nothing asks for F_k·Y_k = 0, and HiGHS returns a vertex that is typically φ = 0 with the
    whole torque on one point. Its gaps are ≥ 0 and equilibrium holds (the constraints), but
    loaded points keep open gaps: the result reports that as a large ``complementarity_residual``
    and a warning. Never use it as a contact solution.
    """
    from scipy.optimize import linprog

    t0 = time.perf_counter()
    p = scale_problem(compliance_mm_per_n, theta_rad, radius_mm, torque_nmm)
    n = len(p.th)
    # scaled, unshifted θ as printed (φ ≥ 0 is a constraint there): variables [m, φ̂, Y, Z', X]
    th_abs = p.theta / p.tau
    I = np.eye(n)
    A_eq = np.zeros((n + 1, 3 * n + 2))
    A_eq[:n, :n] = -p.A
    A_eq[:n, n] = 1.0
    A_eq[:n, n + 1:2 * n + 1] = I
    A_eq[:n, 2 * n + 1:3 * n + 1] = I
    A_eq[n, :n] = 1.0
    A_eq[n, 3 * n + 1] = 1.0
    b_eq = np.concatenate([th_abs, [1.0]])
    c = np.zeros(3 * n + 2)
    c[2 * n + 1:] = 1.0
    res = linprog(c, A_eq=A_eq, b_eq=b_eq, bounds=(0, None), method="highs")
    if res.status != 0 or res.x is None:
        raise ConvergenceError(f"solve_naive_lp: HiGHS failed (status {res.status}: {res.message})")
    x = res.x
    m = np.maximum(x[:n], 0.0)
    phi_hat = float(x[n])
    psi = phi_hat - p.theta_min / p.tau
    out = _finish("naive_lp", p, m, psi, int(getattr(res, "nit", 0) or 0), t0, loaded=m > 1e-12,
                  diagnostics={"objective_Z": float(res.fun), "highs_status": int(res.status),
                               "highs_message": str(res.message)})
    if out.complementarity_residual > 1e-6:
        note = (f"the phase-1 LP point is not a contact solution: complementarity residual "
                f"{out.complementarity_residual:.3g} (loaded points with open gaps), {out.loaded_count} point(s) "
                f"loaded, φ = {out.phi_rad:.6g} rad")
        out = dataclasses.replace(out, warnings=(*out.warnings, note))
    return out
