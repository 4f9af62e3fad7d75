"""Arc–line–arc (G1) fits of a circular-spline flank: least squares, minimax, one-sided.

The CS flank from the envelope is a dense polyline of exact points; wire EDM and CAD want true
arcs and lines. This stage fits one G1 composite *arc 1 – straight line – arc 2* to the flank
(or one per branch, :func:`fit_profile_per_branch`).

A composite is 8 numbers (:data:`PARAM_NAMES`, :func:`composite`): start point (x0, y0) (mm),
start tangent angle θ0 (rad, from +x, counter-clockwise), arc 1's signed curvature κ1 (1/mm,
> 0 turning left) and length s1 (mm), the line's length L ≥ 0, arc 2's κ2 and s2. It cannot
express a kink. The signed distance ``d`` of a point to it (:func:`signed_distance`; the end
arcs continued along their circles) is positive on the space side: ``space_side`` says which
side of the direction of travel the space is on ("left" for the right flank walked up from the
tip circle; "auto" finds it from the ``swept`` callable, or else takes the side facing the CS
tooth-space axis x = 0).

:func:`fit_profile` ``(points, method=...)`` → :class:`ProfileFit`, ``method`` one of
:data:`METHODS`:

* ``"least_squares"`` – min Σ d_i²;
* ``"minimax"`` – the smallest max |d_i| (Chebyshev fit), certified (``diagnostics``:
  ``lp_improvement``, the max error from every start); ``tie_break`` picks the least-RMS fit of
  a family with the same max error (within :data:`TIE_ACCEPT` of it);
* ``"one_sided"`` – every point on the space side or on the fitted flank (d_i ≥ 0: the fitted
  CS flank never enters the swept region) with the smallest max d_i, the ``backlash_mm``; with
  ``swept`` (:func:`swept_depth_function`) the fitted chain is checked against the swept region.

Fits are remembered for the last few point sets (:func:`clear_cache`): fitting the same flank by
another method reuses the shared stages, with the same result.

Errors: :class:`FitError` (a ``ValueError``) naming a bad argument (too few or non-finite points,
an unknown method or side, parameters out of range); :class:`OneSidedError` when a one-sided fit
enters the swept region deeper than ``swept_tol_mm``; :class:`~profilegen.errors.ConvergenceError`
when the least-squares or minimax iterations do not converge.

The parametrisation, the three methods' algorithms and their cost: docs/theory/arcfit.md.

>>> import numpy as np
>>> exact = composite([0.0, 0.0, np.pi / 2, -1.0, 0.6, 0.3, 2.0, 0.5])  # R −1 mm, line, R 0.5 mm
>>> fit = fit_profile(exact.sample(1e-6), method="minimax", space_side="left", starts=2)
>>> fit.max_error_mm < 1e-9, round(fit.params["r1_mm"], 9), round(fit.params["line_mm"], 9)
(True, -1.0, 0.3)
"""

from __future__ import annotations

import copy
import hashlib
import logging
import math
import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from itertools import pairwise
from typing import Any

import numpy as np
from scipy.optimize import least_squares, minimize

from .. import checks
from ..geometry.contour import Arc, Chain, Line
from ..errors import ConvergenceError, ProfilegenError
from ..results import json_ready as _json, readonly as _readonly
from .highs import solve_lp
from .marquardt import levenberg_marquardt

__all__ = [
    "METHODS",
    "PARAM_NAMES",
    "BranchFits",
    "FitError",
    "OneSidedError",
    "ProfileFit",
    "check_swept",
    "composite",
    "fit_profile",
    "fit_profile_per_branch",
    "signed_distance",
    "swept_depth_function",
]

log = logging.getLogger(__name__)

METHODS = ("least_squares", "minimax", "one_sided")
#: the 8 numbers of a composite, in the order :func:`composite` takes them as a sequence
PARAM_NAMES = ("x0_mm", "y0_mm", "theta0_rad", "curvature1_per_mm", "s1_mm", "line_mm", "curvature2_per_mm", "s2_mm")

MIN_POINTS = 12
_SPLITS = ((1 / 3, 2 / 3), (0.25, 0.75), (0.4, 0.6))  # three-piece splits for the LSQ starts
_PERTURBATIONS = (3e-3, 1e-2, 3e-2, 1e-1)  # scaled sizes of the minimax start perturbations
STRAIGHT_TOL_MM = 1e-9
LINE_CURVATURE = 1e-12  # |κ| below this (1/mm): the arc is written as a Line
MIN_ELEMENT_MM = 1e-12  # elements shorter than this are left out of the chain
SPREAD_FLOOR_MM = 1e-9  # start spreads are relative to max(best max error, this)
_I_L = 4  # index of the line length in the gauge-free state q = (mx, my, θ, κ1, L, κ2)


class FitError(ProfilegenError, ValueError):
    """The data or an option cannot be fitted as asked; the message names the parameter."""


class OneSidedError(FitError):
    """A one-sided fit cannot keep the fitted flank out of the swept region."""


# ----------------------------------------------------------------------------- geometry


def _sin_over(k, u):
    """sin(κu)/κ, = u at κ = 0 (complex-safe)."""
    return u * np.sinc(k * u / np.pi)


def _one_minus_cos_over(k, u):
    """(1 − cos κu)/κ, = 0 at κ = 0 (complex-safe)."""
    return u * np.sin(0.5 * k * u) * np.sinc(k * u / (2.0 * np.pi))


def _q_from_params(p):
    """8 public numbers → gauge-free state (mx, my, θ, κ1, L, κ2) (complex-safe)."""
    x0, y0, th0, k1, s1, L, k2, _ = p
    S, K = _sin_over(k1, s1), _one_minus_cos_over(k1, s1)
    c0, s0 = np.cos(th0), np.sin(th0)
    jx, jy = x0 + c0 * S - s0 * K, y0 + s0 * S + c0 * K
    th = th0 + k1 * s1
    return np.array([jx + 0.5 * L * np.cos(th), jy + 0.5 * L * np.sin(th), th, k1, L, k2])


def _dq_dparams(p: np.ndarray) -> np.ndarray:
    """Jacobian (6, 8) of :func:`_q_from_params`, by complex step (exact to rounding)."""
    h = 1e-30
    out = np.empty((6, 8))
    for j in range(8):
        pc = p.astype(complex)
        pc[j] += 1j * h
        out[:, j] = _q_from_params(pc).imag / h
    return out


def _points_at(q: np.ndarray, u) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 2) and tangent angles (n,) at arc length u from the line's start J1
    (u < 0 on arc 1, 0..L on the line, > L on arc 2; end arcs continued on their circles)."""
    mx, my, th, k1, L, k2 = q
    u = np.atleast_1d(np.asarray(u, float))
    c, s = math.cos(th), math.sin(th)
    j1 = np.array([mx - 0.5 * L * c, my - 0.5 * L * s])
    j2 = np.array([mx + 0.5 * L * c, my + 0.5 * L * s])
    base = np.where((u <= 0)[:, None], j1, np.where((u >= L)[:, None], j2, j1))
    k = np.where(u <= 0, k1, np.where(u >= L, k2, 0.0))
    v = np.where(u <= 0, u, np.where(u >= L, u - L, u))
    S, K = _sin_over(k, v), _one_minus_cos_over(k, v)
    pts = base + np.column_stack([c * S - s * K, s * S + c * K])
    return pts, th + k * v


def _model(q: np.ndarray, p: np.ndarray, jac: bool = True):
    """Signed distance (left of travel +), foot arc length u (from J1) and the Jacobian
    with respect to q = (mx, my, θ, κ1, L, κ2), of the points p (n, 2); q is (6,) or a
    batch (m, 6), giving d, u (n,) or (m, n) and G (n, 6) or (m, n, 6).

    Each arc is handled in the frame of its joint with the line (a along, b left of the
    tangent): signed distance to the circle (2b − κ(a² + b²)) / (1 + |(κa, 1 − κb)|),
    foot at the turning angle atan2(κa, 1 − κb) — both smooth through κ = 0. The
    nearest of the three pieces (an orthogonal foot inside it, else its joint) wins.
    """
    Q = np.atleast_2d(np.asarray(q, float))
    mx, my, th, k1, L, k2 = (Q[:, j : j + 1] for j in range(6))
    c, s = np.cos(th), np.sin(th)
    wx, wy = p[:, 0] - mx, p[:, 1] - my
    a = wx * c + wy * s
    b = wy * c - wx * s
    k = np.stack([k1, k2])  # (2, m, 1): arc 1 from J1 backwards, arc 2 from J2 on
    aa = np.stack([a + 0.5 * L, a - 0.5 * L])
    ka, kb = k * aa, 1.0 - k * b
    dd = (2.0 * b - k * (aa * aa + b * b)) / (1.0 + np.hypot(ka, kb))
    phi = np.arctan2(ka, kb)
    nz = k != 0.0
    v = np.where(nz, phi / np.where(nz, k, 1.0), aa)
    e = np.hypot(aa, b)  # distances to the joints J1, J2
    in1, in2, inl = v[0] <= 0.0, v[1] >= 0.0, (aa[0] >= 0.0) & (aa[1] <= 0.0)
    c1 = np.where(in1, np.abs(dd[0]), e[0])
    c2 = np.where(in2, np.abs(dd[1]), e[1])
    cl = np.where(inl, np.abs(b), np.where(aa[0] < 0.0, e[0], e[1]))
    sel1 = (c1 <= cl) & (c1 <= c2)
    sel2 = ~sel1 & (c2 <= cl)
    d = np.where(sel1, dd[0], np.where(sel2, dd[1], b))
    u = np.where(sel1, v[0], np.where(sel2, L + v[1], aa[0]))
    phf = np.where(sel1, phi[0], np.where(sel2, phi[1], 0.0))
    # a nearest point that is a joint without being an orthogonal foot (far from the curve)
    sell = ~sel1 & ~sel2
    at1 = (sel1 & ~in1) | (sell & ~inl & (aa[0] < 0.0))
    at2 = (sel2 & ~in2) | (sell & ~inl & (aa[0] >= 0.0))
    joint = at1 | at2
    if joint.any():
        sgn = np.where(b >= 0.0, 1.0, -1.0)
        d = np.where(at1, sgn * e[0], np.where(at2, sgn * e[1], d))
        u = np.where(at1, 0.0, np.where(at2, L, u))
        phf = np.where(joint, 0.0, phf)
    squeeze = np.ndim(q) == 1
    if not jac:
        return (d[0], u[0], None) if squeeze else (d, u, None)
    G = np.empty(d.shape + (6,))
    cp, sp = np.cos(phf), np.sin(phf)
    G[..., 0] = s * cp + c * sp  # −n_f · e_x with the foot normal n_f = (−sin, cos)(θ + φ)
    G[..., 1] = s * sp - c * cp
    G[..., 2] = -(a * cp + b * sp)  # −t_f · (p − M)
    G[..., 4] = np.where(sel1, -0.5 * sp, np.where(sel2, 0.5 * sp, 0.0))
    # −n_f · ∂C/∂κ = −(1 − cos κv)/κ² = −(v²/2)·(sin(φ/2)/(φ/2))² for the selected arc
    vf = np.where(sel1, v[0], v[1])
    half = 0.5 * np.where(sel1, phi[0], phi[1])
    ratio = np.divide(np.sin(half), half, out=np.ones_like(half), where=half != 0.0)
    dk = -0.5 * vf * vf * ratio * ratio
    G[..., 3] = np.where(sel1, dk, 0.0)
    G[..., 5] = np.where(sel2, dk, 0.0)
    if joint.any():  # d = ±|p − J|: ∂d/∂q = −sgn ê · ∂J/∂q, J = M ∓ (L/2) t
        r = np.where(at1, e[0], e[1])
        r = np.where(r > 0, r, 1.0)
        ea = sgn * np.where(at1, aa[0], aa[1]) / r
        eb = sgn * b / r
        side = np.where(at1, -1.0, 1.0)
        Gj = np.stack(
            [-(ea * c - eb * s), -(ea * s + eb * c), -side * 0.5 * L * eb, np.zeros_like(ea), -side * 0.5 * ea, np.zeros_like(ea)], axis=-1
        )
        G = np.where(joint[..., None], Gj, G)
    return (d[0], u[0], G[0]) if squeeze else (d, u, G)


#: what a user of :func:`profilegen.design` can change when the fit fails (the fit itself takes points)
_IN_A_DESIGN = ('; in a design: --fit least_squares (circular_spline.fit_method = "least_squares") fits the flank '
                "without this step, and a scene chord_tol_mm of at most 1 % of gear.module_mm gives the fit cleaner data")


def _offset(q: np.ndarray, e: float) -> np.ndarray:
    """The parallel composite moved by e to the left of travel (mm); distances drop by e."""
    mx, my, th, k1, L, k2 = q
    if not (1.0 - k1 * e > 0.0 and 1.0 - k2 * e > 0.0):
        raise OneSidedError(
            f"one_sided: an offset of {e:.3e} mm collapses an arc (curvatures {k1:.4g}, {k2:.4g} 1/mm); "
            "the data are not consistent with a one-sided arc–line–arc" + _IN_A_DESIGN
        )
    return np.array([mx - e * math.sin(th), my + e * math.cos(th), th, k1 / (1.0 - k1 * e), L, k2 / (1.0 - k2 * e)])


def _params_from_q(q: np.ndarray, u_first: float, u_last: float) -> np.ndarray:
    """Gauge-free state + the feet of the end points → the 8 numbers of the trimmed composite."""
    L = float(q[_I_L])
    (p0,), (th0,) = _points_at(q, [u_first])
    s1 = max(0.0, min(0.0, u_last) - u_first)
    line = max(0.0, min(L, u_last) - max(0.0, u_first))
    s2 = max(0.0, u_last - max(L, u_first))
    return np.array([p0[0], p0[1], th0, q[3], s1, line, q[5], s2])


def _as_vector(params) -> np.ndarray:
    if isinstance(params, ProfileFit):
        params = params.params
    if isinstance(params, dict):
        try:
            vals = [params[k] for k in PARAM_NAMES]
        except KeyError as exc:
            raise FitError(f"params: missing {exc.args[0]!r}; expected keys {', '.join(PARAM_NAMES)}") from None
    else:
        vals = list(params)
        if len(vals) != 8:
            raise FitError(f"params: expected 8 numbers ({', '.join(PARAM_NAMES)}), got {len(vals)}")
    p = np.array(vals, dtype=float)
    if not np.all(np.isfinite(p)):
        raise FitError(f"params: must be finite, got {p.tolist()}")
    for name, i in (("s1_mm", 4), ("line_mm", 5), ("s2_mm", 7)):
        if p[i] < 0:
            raise FitError(f"params: {name} must be >= 0 mm, got {p[i]!r}")
    return p


def composite(params) -> Chain:
    """The :class:`contour.Chain` of a composite: ``params`` is a mapping with the keys
    :data:`PARAM_NAMES` (e.g. ``ProfileFit.params``) or the 8 numbers in that order.
    Elements shorter than 1e-12 mm are left out; an arc with |κ| < 1e-12 1/mm is a Line.
    Each element starts at the previous one's end, so the chain has no gaps."""
    x0, y0, th0, k1, s1, L, k2, s2 = _as_vector(params)
    elements = []
    start, th = np.array([x0, y0]), th0
    el: Arc | Line
    for k, length, is_arc in ((k1, s1, True), (0.0, L, False), (k2, s2, True)):
        if length < MIN_ELEMENT_MM:
            continue
        if is_arc and abs(k) >= LINE_CURVATURE:
            nrm = np.array([-math.sin(th), math.cos(th)])
            el = Arc(start + nrm / k, 1.0 / abs(k), th - math.copysign(0.5 * math.pi, k), k * length)
        else:
            el = Line(start, start + length * np.array([math.cos(th), math.sin(th)]))
        elements.append(el)
        start, th = np.array(el.end), th + (k * length if is_arc else 0.0)
    if not elements:
        raise FitError(f"params: the composite has no element longer than {MIN_ELEMENT_MM:g} mm")
    return Chain(tuple(elements))


def _side_sign(space_side: str) -> float:
    if space_side not in ("left", "right"):
        raise FitError(f"space_side must be 'left' or 'right' (of the direction of travel), got {space_side!r}")
    return 1.0 if space_side == "left" else -1.0


def signed_distance(params, points, *, space_side: str = "left", jac: bool = False):
    """Exact signed orthogonal distance (mm) of ``points`` (n, 2) to a composite, + on the
    space side (``space_side`` of the direction of travel), its end arcs continued along
    their circles. With ``jac=True`` also the Jacobian (n, 8) with respect to the 8
    numbers (:data:`PARAM_NAMES`; the column of s2 is zero: s2 does not move the curve)."""
    p8 = _as_vector(params)
    pts = _check_points(points, "points", min_points=1)
    sigma = _side_sign(space_side)
    q = _q_from_params(p8)
    d, _, G = _model(q, pts, jac)
    if not jac:
        return sigma * d
    return sigma * d, sigma * (G @ _dq_dparams(p8))


# ----------------------------------------------------------------------------- input


def _check_points(points, name: str, min_points: int = MIN_POINTS) -> np.ndarray:
    try:
        p = np.array(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise FitError(f"{name}: must be an (n, 2) array of numbers (mm): {exc}") from None
    if p.ndim != 2 or p.shape[1] != 2:
        raise FitError(f"{name}: must be an (n, 2) array (mm), got shape {p.shape}")
    bad = ~np.isfinite(p).all(axis=1)
    if bad.any():
        raise FitError(f"{name}: must be finite, got NaN or inf at index {int(np.argmax(bad))} ({int(bad.sum())} rows)")
    if len(p) < min_points:
        raise FitError(f"{name}: an arc–line–arc fit needs at least {min_points} points, got {len(p)}")
    return p


def _straightness(p: np.ndarray) -> float:
    c = p.mean(axis=0)
    _, _, vt = np.linalg.svd(p - c, full_matrices=False)
    return float(np.max(np.abs((p - c) @ vt[1])))


def _arclength(p: np.ndarray) -> np.ndarray:
    return np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])


def _subsample(s: np.ndarray, m: int) -> np.ndarray:
    if len(s) <= m:
        return np.arange(len(s))
    idx = np.searchsorted(s, np.linspace(0.0, s[-1], m))
    return np.unique(np.concatenate([[0, len(s) - 1], np.clip(idx, 0, len(s) - 1)]))


# ----------------------------------------------------------------------------- initial guesses


def _circle_fit(p: np.ndarray) -> float:
    """Signed curvature (1/mm, + turning left along the points' order) of the algebraic
    circle A(x²+y²) + Bx + Cy + D = 0 that fits the points best (a line when A = 0)."""
    c = p.mean(axis=0)
    scale = max(float(np.max(np.abs(p - c))), 1e-300)
    x, y = ((p - c) / scale).T
    _, _, vt = np.linalg.svd(np.column_stack([x * x + y * y, x, y, np.ones_like(x)]), full_matrices=False)
    A, B, C, _ = vt[-1]
    m = len(p) // 2
    grad = np.array([2 * A * x[m] + B, 2 * A * y[m] + C])
    t = p[-1] - p[0]
    nrm = np.array([-t[1], t[0]])
    gnorm = float(np.hypot(*grad))
    if gnorm == 0.0:
        return 0.0
    return float(-2.0 * A / gnorm * math.copysign(1.0, nrm @ grad)) / scale


def _split_guess(p: np.ndarray, s: np.ndarray, f1: float, f2: float) -> np.ndarray:
    """Three-piece guess: circle fits to s < f1·len and s > f2·len, a line in between."""
    i1 = max(int(np.searchsorted(s, f1 * s[-1])), 3)
    i2 = min(int(np.searchsorted(s, f2 * s[-1])), len(p) - 3)
    mid = p[i1 : i2 + 1] if i2 - i1 >= 2 else p[max(i1 - 1, 0) : i1 + 2]
    c = mid.mean(axis=0)
    _, _, vt = np.linalg.svd(mid - c, full_matrices=False)
    t = vt[0] if vt[0] @ (mid[-1] - mid[0]) >= 0 else -vt[0]
    along = (mid - c) @ t
    L = max(float(along.max() - along.min()), 1e-3 * s[-1])
    centre = c + 0.5 * (along.max() + along.min()) * t
    return np.array([centre[0], centre[1], math.atan2(t[1], t[0]), _circle_fit(p[: i1 + 1]), L, _circle_fit(p[i2:])])


def _turning_guess(p: np.ndarray, s: np.ndarray, segments: int = 40) -> np.ndarray:
    """Guess from the turning of the flank: the chord angles of ``segments`` equal
    stretches, fitted by the angle of an arc–line–arc, θ(s) = θ0 + κ1·min(s, a) +
    κ2·max(s − b, 0), over a grid of the breakpoints a ≤ b (linear least squares each)."""
    knots = np.interp(np.linspace(0.0, s[-1], segments + 1), s, np.arange(len(s)))
    xy = np.column_stack([np.interp(knots, np.arange(len(s)), p[:, 0]), np.interp(knots, np.arange(len(s)), p[:, 1])])
    d = np.diff(xy, axis=0)
    phi = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    sm = 0.5 * (np.linspace(0.0, s[-1], segments + 1)[1:] + np.linspace(0.0, s[-1], segments + 1)[:-1])
    grid = np.linspace(0.0, s[-1], 21)
    a, b = np.meshgrid(grid, grid, indexing="ij")
    keep = a <= b
    a, b = a[keep], b[keep]
    X = np.stack([np.ones((len(a), segments)), np.minimum(sm[None], a[:, None]), np.maximum(sm[None] - b[:, None], 0.0)], axis=-1)
    XtX = np.einsum("kni,knj->kij", X, X) + 1e-12 * np.eye(3)
    Xty = np.einsum("kni,n->ki", X, phi)
    coef = np.linalg.solve(XtX, Xty[..., None])[..., 0]
    res = np.sum((np.einsum("kni,ki->kn", X, coef) - phi[None]) ** 2, axis=1)
    k = int(np.argmin(res))
    th0, k1, k2 = coef[k]
    a_k, b_k = a[k], b[k]
    mid = np.array([np.interp(0.5 * (a_k + b_k), s, p[:, 0]), np.interp(0.5 * (a_k + b_k), s, p[:, 1])])
    return np.array([mid[0], mid[1], th0 + k1 * a_k, k1, max(b_k - a_k, 1e-3 * s[-1]), k2])


# ----------------------------------------------------------------------------- solvers


class _Problem:
    """The data, the side of the space, the scaling; evaluates D = σ·d and its Jacobian."""

    def __init__(self, p: np.ndarray, sigma: float):
        self.p, self.sigma = p, sigma
        self.s = _arclength(p)
        self.length = float(self.s[-1])
        ell = self.length
        self.scale = np.array([ell, ell, 1.0, 1.0 / ell, ell, 1.0 / ell])
        # rounding floor of a distance computed from coordinates of this size (mm)
        self.noise = 64.0 * np.finfo(float).eps * max(float(np.max(np.abs(p))), ell)
        self.evaluations = 0

    def eval(self, q, idx=None, jac=True):
        self.evaluations += 1
        pts = self.p if idx is None else self.p[idx]
        d, u, G = _model(q, pts, jac)
        return self.sigma * d, u, (None if G is None else self.sigma * G * self.scale)


def _lsq(prob: _Problem, q0: np.ndarray, idx, max_nfev: int = 200):
    cache: dict = {}

    def both(z):
        key = z.tobytes()
        if key not in cache:
            cache.clear()
            D, _, G = prob.eval(z * prob.scale, idx)
            cache[key] = (D, G)
        return cache[key]

    z0 = q0 / prob.scale
    z0[_I_L] = max(z0[_I_L], 1e-6)
    # Levenberg–Marquardt first (profilegen.profile.marquardt: the same bits on every call, which
    # MINPACK's is not); the bounded trust-region reflective method if the line length wants to go
    # negative
    res = levenberg_marquardt(both, z0, ftol=1e-15, xtol=1e-15, gtol=1e-15, max_nfev=max_nfev)
    if not res.x[_I_L] >= 0.0:
        lo = np.full(6, -np.inf)
        lo[_I_L] = 0.0
        res = least_squares(
            lambda z: both(z)[0], z0, jac=lambda z: both(z)[1], bounds=(lo, np.inf), method="trf", ftol=1e-15, xtol=1e-15, gtol=1e-15, max_nfev=max_nfev
        )
    return res.x * prob.scale, res


def _lp_step(D, G, delta, z_lo_L, one_sided, cap: int = 150, T=None):
    """Solve the trust-region LP  min t  s.t. |D + G z| ≤ t (minimax) or 0 ≤ D + G z ≤ t
    (one-sided), |z_j| ≤ Δ, z_L ≥ z_lo_L.

    Each constraint is a row i with a sign σ and a level ℓ: σ(D_i + G_i z) ≤ ℓ t.
    Constraints that cannot bind within the trust region are dropped exactly; of the
    rest, the local maxima of σD along the flank and their neighbours go in first and
    violated ones are added until none is left (the error is smooth along the flank).
    ``T``: solve for y with z = T y (the box is then |y_j| ≤ Δ). Returns (z, t, active) or (None, None, None) if the LP fails; ``active`` = (rows,
    signs, levels, multipliers) of the binding constraints.
    """
    n = len(D)
    # HiGHS's feasibility tolerances are absolute (~1e-7): solve for D/F, G/F, t/F
    unit = max(float(np.max(np.abs(D))), 1e-300)
    D, G = D / unit, G / unit
    if T is not None:  # work in y, z = T y (a trust region shaped to the problem)
        zT = T
        G = G @ T
    reach = np.abs(G).sum(axis=1) * delta
    fam = [(1.0, 1.0), (-1.0, 0.0 if one_sided else 1.0)]
    lo_b = max(float(np.max(s * D - reach)) for s, level in fam if level > 0)  # t_LP ≥ lo_b
    cand, seed = [], []
    for s, level in fam:
        val = s * D
        may = val + reach >= (lo_b if level > 0 else 0.0)
        rows = np.nonzero(may)[0]
        cand.append(rows)
        if len(rows) <= cap:
            seed.append(rows)
            continue
        v = np.concatenate([[-np.inf], val, [-np.inf]])
        peak = np.nonzero((v[1:-1] >= v[:-2]) & (v[1:-1] >= v[2:]) & may)[0]
        peak = peak[np.argsort(-val[peak])[: max(cap // 3, 1)]]
        near = np.clip((peak[:, None] + np.arange(-1, 2)[None]).ravel(), 0, n - 1)
        seed.append(np.unique(near[may[near]]))
    bounds = [(-delta, delta)] * 6 + [(None, None)]
    lo_L = z_lo_L if T is None else z_lo_L / zT[_I_L, _I_L]  # T keeps L on its own axis
    bounds[_I_L] = (max(-delta, lo_L), delta) if lo_L < delta else (lo_L, lo_L)
    c = np.zeros(7)
    c[6] = 1.0
    work = seed
    for _ in range(12):
        rows = np.concatenate(work)
        sig = np.concatenate([np.full(len(w), s) for w, (s, _) in zip(work, fam)])
        lvl = np.concatenate([np.full(len(w), l) for w, (_, l) in zip(work, fam)])
        A = np.column_stack([sig[:, None] * G[rows], -lvl])
        b = -sig * D[rows]
        solved = solve_lp(c, A, b, bounds)
        if solved is None:
            return None, None, None
        x, marginals = solved
        z, t = x[:6], float(x[6])
        lin = D + G @ z
        tol = 1e-9  # relative to the max error (the LP is solved to 1e-10)
        added = False
        for k, (s, level) in enumerate(fam):
            over = cand[k][s * lin[cand[k]] - level * t > tol]
            over = np.setdiff1d(over, work[k])
            if len(over):
                over = over[np.argsort(-(s * lin[over]))[:cap]]
                near = np.clip((over[:, None] + np.arange(-1, 2)[None]).ravel(), 0, n - 1)
                work[k] = np.union1d(work[k], np.intersect1d(near, cand[k]))
                added = True
        if not added:
            lam = -marginals[: len(rows)]
            on = lam > 1e-10 * max(float(lam.max()), 1e-300)
            honest = float(lin.max() - min(0.0, lin.min())) if one_sided else float(np.abs(lin).max())
            return (z if T is None else zT @ z), max(t, honest) * unit, (rows[on], sig[on], lvl[on], lam[on])
    return None, None, None


def _centred(prob: _Problem, q):
    """The parallel composite in the middle of the error band (max D = −min D)."""
    D, _, _ = prob.eval(q, jac=False)
    return _offset(q, prob.sigma * 0.5 * float(D.max() + D.min()))


def _objective(D, one_sided):
    return float(D.max()) if one_sided else float(np.abs(D).max())


def _feasible(prob: _Problem, q, D):
    """One-sided: move the composite toward the material by the largest violation (exact:
    an offset composite is again an arc–line–arc)."""
    worst = float(D.min())
    if worst >= 0.0:
        return q, D
    q = _offset(q, prob.sigma * worst * (1.0 + 1e-12))  # D' = D − σe ≥ 0
    D, _, _ = prob.eval(q, jac=False)
    return q, D


def _kkt_newton(prob: _Problem, q, rows, sig, lvl, lam, *, fix_line: bool = False, max_iter: int = 12, h: float = 1e-7):
    """Newton's method on the KKT system of  min t  s.t. sig_i·D_i(q) ≤ lvl_i·t  with the
    given rows held active: sig·D = lvl·t, Σ λ sig ∇D = 0, Σ λ lvl = 1 (over the free
    parameters; ``fix_line`` holds L = 0, its bound active). Second derivatives by
    central differences of the analytic Jacobian. Returns (q, t, λ, ok)."""
    q = q.copy()
    lam = lam.astype(float).copy()
    free = np.ones(6, bool)
    if fix_line:
        q[_I_L] = 0.0
        free[_I_L] = False
    cols = np.nonzero(free)[0]
    nf, k = len(cols), len(rows)
    if not np.any(lvl > 0):
        return q, 0.0, lam, False
    D, _, _ = prob.eval(q, rows, jac=False)
    t = float(np.max((sig * D)[lvl > 0]))
    tol_d = 1e-12 * abs(t) + prob.noise
    norm0 = None
    for _ in range(max_iter):
        D, _, G = prob.eval(q, rows)
        gf = sig[:, None] * G[:, cols]
        R = np.concatenate([sig * D - lvl * t, gf.T @ lam, [lvl @ lam - 1.0]])
        if np.all(np.abs(R[:k]) <= tol_d) and np.all(np.abs(R[k:]) <= 1e-10):
            return q, t, lam, True
        norm = float(np.linalg.norm(R[:k]) / tol_d + np.linalg.norm(R[k:]) / 1e-10)
        if norm0 is not None and norm > 10.0 * norm0:
            return q, t, lam, False
        norm0 = norm if norm0 is None else min(norm0, norm)
        dq = np.zeros((2 * nf, 6))
        dq[np.arange(nf), cols] = h * prob.scale[cols]
        dq[nf + np.arange(nf), cols] = -h * prob.scale[cols]
        _, _, Gpm = prob.eval(q + dq, rows)  # (2 nf, k, 6), one batched call
        dG = (Gpm[:nf] - Gpm[nf:])[:, :, cols] / (2.0 * h)  # (nf, k, nf): ∂G/∂z_j
        H = np.einsum("i,jil->lj", sig * lam, dG)
        K = np.zeros((k + nf + 1, nf + 1 + k))
        K[:k, :nf], K[:k, nf] = gf, -lvl
        K[k : k + nf, :nf], K[k : k + nf, nf + 1 :] = 0.5 * (H + H.T), gf.T
        K[k + nf, nf + 1 :] = lvl
        step = np.linalg.lstsq(K, -R, rcond=None)[0]
        q[cols] += step[:nf] * prob.scale[cols]
        t += step[nf]
        lam += step[nf + 1 :]
        if q[_I_L] < 0.0:
            return q, t, lam, False
    D, _, G = prob.eval(q, rows)
    R = np.concatenate([sig * D - lvl * t, (sig[:, None] * G[:, cols]).T @ lam, [lvl @ lam - 1.0]])
    ok = np.all(np.abs(R[:k]) <= 10 * tol_d) and np.all(np.abs(R[k:]) <= 1e-8)
    return q, t, lam, bool(ok)


def _polish(prob: _Problem, q, act, one_sided: bool, rounds: int = 8):
    """Active-set Newton from an SLP point: exchange rows until no point exceeds the level
    and every multiplier is ≥ 0. Returns the polished q or None."""
    rows, sig, lvl, lam = (np.asarray(a).copy() for a in act)
    lam = lam / max(float(lvl @ lam), 1e-300)
    fix_line = q[_I_L] <= 1e-12 * prob.length
    for _ in range(rounds):
        q_new, t, lam_new, ok = _kkt_newton(prob, q, rows, sig, lvl, lam, fix_line=fix_line)
        if not ok and not fix_line and q_new[_I_L] < 0.0:  # the line wants to vanish: L = 0
            fix_line = True
            q_new, t, lam_new, ok = _kkt_newton(prob, q, rows, sig, lvl, lam, fix_line=True)
        if not ok or not np.isfinite(t):
            return None
        if np.any(lam_new < -1e-12):
            drop = int(np.argmin(lam_new))
            keep = np.arange(len(rows)) != drop
            rows, sig, lvl, lam = rows[keep], sig[keep], lvl[keep], np.maximum(lam_new[keep], 0.0)
            q = q_new
            continue
        D, _, _ = prob.eval(q_new, jac=False)
        tol = 1e-11 * abs(t) + prob.noise
        if one_sided:
            over = np.nonzero(D > t + tol)[0]
            under = np.nonzero(D < -tol)[0]
        else:
            over = np.nonzero(np.abs(D) > t + tol)[0]
            under = np.array([], int)
        if not len(over) and not len(under):
            return q_new
        add_r, add_s, add_l = [], [], []
        if len(over):
            i = int(over[np.argmax(np.abs(D[over]))])
            add_r.append(i)
            add_s.append(1.0 if (one_sided or D[i] >= 0) else -1.0)
            add_l.append(1.0)
        if len(under):
            i = int(under[np.argmin(D[under])])
            add_r.append(i)
            add_s.append(-1.0)
            add_l.append(0.0)
        rows = np.concatenate([rows, add_r]).astype(int)
        sig = np.concatenate([sig, add_s])
        lvl = np.concatenate([lvl, add_l])
        lam = np.concatenate([np.maximum(lam_new, 0.0), np.zeros(len(add_r))])
        q = q_new
    return None


def _metric(G: np.ndarray) -> np.ndarray:
    """T with z = T y: a unit y moves the curve by about 1 mm RMS (the Gauss–Newton
    metric). The line length keeps its own axis (z_L = T_LL y_L), so that its bound
    L ≥ 0 stays a bound of one variable."""
    M = G.T @ G / len(G)
    other = [j for j in range(6) if j != _I_L]
    w, V = np.linalg.eigh(M[np.ix_(other, other)])
    T = np.zeros((6, 6))
    T[np.ix_(other, other)] = V / np.sqrt(np.maximum(w, 1e-14 * w.max()))
    T[_I_L, _I_L] = 1.0 / math.sqrt(max(M[_I_L, _I_L], 1e-14 * w.max(), 1e-300))
    return T


def _solve(prob: _Problem, q, *, one_sided: bool, max_iter: int):
    """Sequential LP with a trust region for min max |D| (or min max D s.t. D ≥ 0).

    The trust region is a box in coordinates whitened by the Gauss–Newton matrix GᵀG/n
    (a unit step moves the curve by 1 mm RMS), starting at the current max error. Once
    the LP predicts < 5 % decrease, active-set Newton (:func:`_polish`) starts from the
    LP's binding rows; a rejected LP step is followed by a trial Gauss–Newton step.
    Stops at a KKT point (every point within the level, multipliers ≥ 0) or when the
    LP over a region ≥ the max error predicts no decrease. Returns (q, F, info)."""
    D, _, G = prob.eval(q)
    if one_sided:
        q, D = _feasible(prob, q, D)
        D, _, G = prob.eval(q)
    F = _objective(D, one_sided)
    T = _metric(G)
    delta, lps, polished, gn, how, failed = F, 0, 0, 0, "iterations", None
    it = 0
    from ..stagecache import checkpoint

    for it in range(1, max_iter + 1):
        checkpoint()  # an engine's design stops here when superseded (an SLP step: milliseconds)
        if F <= prob.noise:
            how = "zero error"
            break
        z, t, act = _lp_step(D, G, delta, -q[_I_L] / prob.scale[_I_L], one_sided, T=T)
        lps += 1
        if z is None:
            delta *= 0.25
            if delta < 1e-6 * F:
                break
            continue
        pred = F - t
        if pred <= 1e-12 * F + prob.noise:
            if delta < F:  # stationary over a small region: ask over one as large as the error
                z2, t2, _ = _lp_step(D, G, F, -q[_I_L] / prob.scale[_I_L], one_sided, T=T)
                lps += 1
                if z2 is not None and F - t2 > 1e-9 * F:
                    delta = F
                    continue
            how = "lp"
            break
        key = (tuple(act[0]), tuple(act[1])) if act is not None else None
        qn = None
        if pred <= 0.05 * F and key != failed:  # near: Newton on the LP's binding rows
            qn = _polish(prob, q, act, one_sided)
            failed = key if qn is None else None
        if qn is not None:
            Dn, _, _ = prob.eval(qn, jac=False)
            if one_sided:
                qn, Dn = _feasible(prob, qn, Dn)
            Fn = _objective(Dn, one_sided)
            if Fn <= F * (1.0 + 1e-12):
                q, F, polished, how = qn, Fn, polished + 1, "kkt"
                break
        q_new = q + z * prob.scale
        q_new[_I_L] = max(q_new[_I_L], 0.0)
        D_new, _, _ = prob.eval(q_new, jac=False)
        if one_sided:
            q_new, D_new = _feasible(prob, q_new, D_new)
        F_new = _objective(D_new, one_sided)
        rho = (F - F_new) / pred
        step = float(np.max(np.abs(np.linalg.solve(T, z))))
        if rho > 0.1:
            q, F = q_new, F_new
            D, _, G = prob.eval(q)
            if rho > 0.75 and step > 0.9 * delta:
                delta = 2.0 * delta
        else:
            delta = 0.25 * (step if step > 0 else delta)
            # a rejected LP step: try a Gauss–Newton step (second order where the
            # residuals are small, e.g. near-exact data in a curved valley)
            q_gn = q - np.linalg.lstsq(G, D - (0.5 * (D.max() + D.min()) if not one_sided else 0.0), rcond=None)[0] * prob.scale
            if q_gn[_I_L] >= 0.0:
                D_gn, _, _ = prob.eval(q_gn, jac=False)
                if one_sided:
                    q_gn, D_gn = _feasible(prob, q_gn, D_gn)
                F_gn = _objective(D_gn, one_sided)
                if F_gn < F:
                    q, F = q_gn, F_gn
                    D, _, G = prob.eval(q)
                    gn += 1
                    continue
            if delta < 1e-9 * F:
                break
    converged = how in ("zero error", "lp", "kkt")
    return q, F, {"iterations": it, "lps": lps, "newton": polished, "gauss_newton": gn, "stop": how, "converged": converged}


#: how far past F(1 + slack) the tie-break's composite may reach and still count as tied
#: (relative): SLSQP meets its constraints only to its own accuracy, a few 1e-9 of F (seen:
#: 2.5e-9 and 3.4e-9 on the same points, rounded by one BLAS thread or two). A test at that
#: level accepted one and rejected the other, and the rejected fit kept another member of
#: the family — on csf32_100 an end arc 1.4° apart, which moved the CS root by µm and
#: decided whether a 0.145 mm root fillet fits. 1e-6·F is a picometre on a µm fit.
TIE_ACCEPT = 1e-6


def _tie_break(prob: _Problem, q, F: float, *, slack: float = 1e-9, frac: float = 0.6):
    """Of the composites whose max error is F (to a relative ``slack``), the one with the
    smallest RMS error: min Σ D² s.t. |D_i| ≤ F(1 + slack) (SLSQP over the rows above
    ``frac``·F, with violated rows added; a row past F(1 + slack) by no more than
    :data:`TIE_ACCEPT`·F, SLSQP's own accuracy, is met). The minimax composite need not be
    unique — a stretch whose errors stay below F can move — and this makes it so (e.g. the
    fits of a left and a right flank are mirror images). Returns (q, ok)."""
    if F <= prob.noise:
        return q, False
    D0, _, _ = prob.eval(q, jac=False)
    work = np.nonzero(np.abs(D0) >= frac * F)[0]
    cache: dict = {}

    def ev(z):
        key = z.tobytes()
        if key not in cache:
            cache.clear()
            D, _, G = prob.eval(q + z * prob.scale)
            cache[key] = (D / F, G / F)
        return cache[key]

    bounds = [(None, None)] * 6
    bounds[_I_L] = (-q[_I_L] / prob.scale[_I_L], None)
    n = len(D0)
    for _ in range(2):
        rows = work
        cons = {
            "type": "ineq",
            "fun": lambda z, rows=rows: np.concatenate([1.0 + slack - ev(z)[0][rows], 1.0 + slack + ev(z)[0][rows]]),
            "jac": lambda z, rows=rows: np.vstack([-ev(z)[1][rows], ev(z)[1][rows]]),
        }
        res = minimize(
            lambda z: 0.5 * float(np.mean(ev(z)[0] ** 2)),
            np.zeros(6),
            jac=lambda z: ev(z)[1].T @ ev(z)[0] / n,
            constraints=[cons],
            bounds=bounds,
            method="SLSQP",
            options={"ftol": 1e-12, "maxiter": 60},
        )
        if not np.all(np.isfinite(res.x)):
            return q, False
        q_new = q + res.x * prob.scale
        q_new[_I_L] = max(q_new[_I_L], 0.0)
        D, _, _ = prob.eval(q_new, jac=False)
        over = np.nonzero(np.abs(D) > F * (1.0 + slack + TIE_ACCEPT))[0]
        if not len(over):
            if np.mean(D**2) <= np.mean(D0**2):
                return q_new, True
            return q, False
        work = np.union1d(work, over)
    return q, False


def _lp_improvement(prob: _Problem, q, one_sided: bool, delta: float = 1e-4, with_active: bool = False):
    """Relative decrease of the max error the LP finds over a small trust region at q
    (all points; ≈ 0 at a first-order optimum)."""
    D, _, G = prob.eval(q)
    F = _objective(D, one_sided)
    if F <= prob.noise:  # at the rounding floor: nothing left to measure
        return (0.0, None) if with_active else 0.0
    z, t, act = _lp_step(D, G, delta, -q[_I_L] / prob.scale[_I_L], one_sided, cap=10**9)
    imp = float("nan") if z is None else max(0.0, (F - t) / F)
    return (imp, act) if with_active else imp


def _feet(prob: _Problem, q) -> tuple[float, float, np.ndarray]:
    D, u, _ = prob.eval(q, jac=False)
    return float(u[0]), float(u[-1]), D


# ----------------------------------------------------------------------------- results




def _params_dict(p8: np.ndarray) -> dict:
    x0, y0, th0, k1, s1, L, k2, s2 = (float(v) for v in p8)

    def radius(k: float) -> float:
        return (1.0 / k) if k != 0.0 else math.inf

    return {
        "x0_mm": x0,
        "y0_mm": y0,
        "theta0_rad": th0,
        "curvature1_per_mm": k1,
        "r1_mm": radius(k1),
        "s1_mm": s1,
        "line_mm": L,
        "curvature2_per_mm": k2,
        "r2_mm": radius(k2),
        "s2_mm": s2,
    }


@dataclass(frozen=True, slots=True, eq=False)
class ProfileFit:
    """An arc–line–arc fit of a flank.

    ``params``: the composite (:data:`PARAM_NAMES`, plus the signed radii ``r1_mm``,
    ``r2_mm`` = 1/κ, > 0 turning left, inf for a line); ``chain``: it as a contour;
    ``error_mm``: signed orthogonal distance of every data point to the chain, + on the
    space side; ``arclength_mm``: position of each point along the data from its first
    point; ``backlash_mm``: one-sided fits only, = ``error_mm`` ≥ 0, the normal clearance
    the fitted flank leaves; ``diagnostics``: iterations, starts, ``lp_improvement``,
    ``start_spread``, stage times, the swept-region check, ...
    """

    method: str
    params: dict
    chain: Chain
    points_mm: np.ndarray
    error_mm: np.ndarray
    arclength_mm: np.ndarray
    backlash_mm: np.ndarray | None
    space_side: str
    time_s: float
    diagnostics: dict = field(default_factory=dict)

    def __post_init__(self):
        object.__setattr__(self, "params", dict(self.params))
        object.__setattr__(self, "points_mm", _readonly(self.points_mm))
        object.__setattr__(self, "error_mm", _readonly(self.error_mm))
        object.__setattr__(self, "arclength_mm", _readonly(self.arclength_mm))
        if self.backlash_mm is not None:
            object.__setattr__(self, "backlash_mm", _readonly(self.backlash_mm))
        object.__setattr__(self, "diagnostics", dict(self.diagnostics))

    @property
    def max_error_mm(self) -> float:
        """Largest |distance| of a data point to the fitted chain (mm)."""
        return float(np.max(np.abs(self.error_mm)))

    @property
    def rms_error_mm(self) -> float:
        return float(np.sqrt(np.mean(self.error_mm**2)))

    @property
    def at_max_mm(self) -> tuple[float, float]:
        """(x, y) of the data point with the largest |error| (mm)."""
        x, y = self.points_mm[int(np.argmax(np.abs(self.error_mm)))]
        return float(x), float(y)

    @property
    def max_backlash_mm(self) -> float | None:
        return None if self.backlash_mm is None else float(np.max(self.backlash_mm))

    def distance(self, points) -> np.ndarray:
        """Signed distance (mm, + on the space side) of other points to this fit."""
        return signed_distance(self.params, points, space_side=self.space_side)

    def to_dict(self) -> dict:
        return _json(
            {
                "method": self.method,
                "params": self.params,
                "space_side": self.space_side,
                "chain": self.chain.to_dict(),
                "max_error_mm": self.max_error_mm,
                "rms_error_mm": self.rms_error_mm,
                "at_max_mm": list(self.at_max_mm),
                "max_backlash_mm": self.max_backlash_mm,
                "points": len(self.points_mm),
                "arclength_mm": self.arclength_mm,
                "error_mm": self.error_mm,
                "time_s": self.time_s,
                "diagnostics": self.diagnostics,
            }
        )


@dataclass(frozen=True, slots=True, eq=False)
class BranchFits:
    """One fit per branch of a flank split at its branch-switch ridges, and (if asked)
    the single composite over the whole flank for comparison."""

    fits: tuple[ProfileFit, ...]
    ridge_indices: tuple[int, ...]
    whole: ProfileFit | None

    @property
    def max_error_mm(self) -> float:
        return max(f.max_error_mm for f in self.fits)

    @property
    def time_s(self) -> float:
        return float(sum(f.time_s for f in self.fits) + (self.whole.time_s if self.whole else 0.0))

    def to_dict(self) -> dict:
        return {
            "ridge_indices": list(self.ridge_indices),
            "branches": [f.to_dict() for f in self.fits],
            "max_error_mm": self.max_error_mm,
            "whole": None if self.whole is None else self.whole.to_dict(),
        }


# ----------------------------------------------------------------------------- the fit


def swept_depth_function(tooth, motion, *, cs_teeth: int, phi_range: tuple[float, float], n_grid: int = 721
                         ) -> Callable[[np.ndarray], np.ndarray]:
    """The swept-region membership of the FS ``tooth`` (a :class:`~profilegen.geometry.teeth.ToothProfile`)
    in ``motion`` over ``phi_range`` (rad, the envelope's pass), with its neighbours
    2π/``cs_teeth`` away, as ``depth(points) -> (n,)`` (mm, > 0 inside the region the tooth and
    its neighbours sweep; exact sign, first-order size near the boundary) — the ``swept``
    argument of :func:`fit_profile`. ``n_grid``: the poses over the pass each point's deepest one is
    first looked for at (then refined between its neighbours to ~1e-8 rad). (:func:`profilegen.profile.swept.swept_region`
    is another thing: the brute-force polygon of that region.)"""
    from .envelope import swept_depth, tooth_curves

    cs_teeth = checks.whole("cs_teeth", cs_teeth, 1, error=FitError)
    _, _, shape = tooth_curves(tooth)
    pitch = 2.0 * np.pi / cs_teeth

    def depth(points):
        return swept_depth(np.asarray(points, float), motion, shape, phi_range=phi_range, neighbour_angle=pitch,
                           n_grid=n_grid)[0]

    return depth


def _space_side(space_side: str, p: np.ndarray, swept) -> str:
    if space_side in ("left", "right"):
        return space_side
    if space_side != "auto":
        raise FitError(f"space_side must be 'left', 'right' or 'auto', got {space_side!r}")
    m = len(p) // 2
    t = p[min(m + 1, len(p) - 1)] - p[max(m - 1, 0)]
    nrm = np.array([-t[1], t[0]]) / np.hypot(*t)
    if swept is not None:
        h = 1e-3 * _arclength(p)[-1]
        dl, dr = np.asarray(swept(np.array([p[m] + h * nrm, p[m] - h * nrm])), float)
        if (dl > 0) == (dr > 0):
            raise FitError(f"space_side='auto': the swept region is on neither/both sides of the points near {p[m].tolist()} mm; give space_side")
        return "left" if dl > 0 else "right"
    if abs(p[m, 0]) < 1e-9 or abs(nrm[0]) < 1e-9:
        raise FitError("space_side='auto' needs a flank off the CS tooth-space axis (x = 0) or a `swept` callable; give space_side")
    return "left" if nrm[0] * p[m, 0] < 0 else "right"


def _check_swept(chain: Chain, swept, tol: float, spacing: float, contacts: np.ndarray) -> dict:
    """Sample the fitted chain (evenly, and densely around the data points where the
    clearance is ~0) and check it against the swept region."""
    n = int(np.clip(math.ceil(chain.length / max(spacing, 1e-12)), 100, 400))
    parts = [_sample_chain(chain, n)]
    for c in contacts:  # 41 points over ±3 data spacings around each contact
        parts.append(_nearest_on_chain(chain, c, 3.0 * spacing, 41))
    pts = np.vstack(parts)
    from ..stagecache import checkpoint

    depth = np.empty(len(pts))
    for i in range(0, len(pts), 128):  # ~0.3 ms a point: an engine's design may stop between the pieces
        checkpoint()
        depth[i:i + 128] = np.asarray(swept(pts[i:i + 128]), float)
    k = int(np.argmax(depth))
    out = {"swept_samples": len(pts), "swept_max_depth_mm": float(depth[k]), "swept_at_mm": pts[k].tolist(), "swept_tol_mm": tol}
    if not depth[k] <= tol:
        raise OneSidedError(
            f"one_sided: the fitted chain enters the swept region by {depth[k]:.3e} mm at "
            f"({pts[k, 0]:.6f}, {pts[k, 1]:.6f}) mm (swept_tol_mm={tol:g})" + _IN_A_DESIGN
        )
    return out


def _nearest_on_chain(chain: Chain, point: np.ndarray, half_width: float, n: int) -> np.ndarray:
    """n chain points spread over ±half_width (mm of arc length) around the chain point
    nearest to ``point``."""
    dense = _sample_chain(chain, 4001)
    s = np.linspace(0.0, chain.length, 4001)
    s0 = s[int(np.argmin(np.hypot(*(dense - point).T)))]
    return _sample_chain_between(chain, max(0.0, s0 - half_width), min(chain.length, s0 + half_width), n)


def _sample_chain(chain: Chain, n: int) -> np.ndarray:
    """n points spread evenly by arc length over a chain of Lines and Arcs."""
    return _sample_chain_between(chain, 0.0, chain.length, n)


def _sample_chain_between(chain: Chain, s_from: float, s_to: float, n: int) -> np.ndarray:
    lengths = np.array([e.length for e in chain.elements])
    edges = np.concatenate([[0.0], np.cumsum(lengths)])
    s = np.linspace(s_from, s_to, n)
    k = np.clip(np.searchsorted(edges, s, side="right") - 1, 0, len(lengths) - 1)
    out = np.empty((n, 2))
    for j, e in enumerate(chain.elements):
        sel = k == j
        f = (s[sel] - edges[j]) / max(lengths[j], 1e-300)
        if isinstance(e, Arc):
            a = e.start_angle + f * e.sweep
            out[sel] = e.centre + e.radius * np.column_stack([np.cos(a), np.sin(a)])
        else:
            out[sel] = e.start + f[:, None] * (e.end - e.start)
    return out


# The least-squares and minimax stages of a fit, kept for the next fit of the same data
# (least recently used dropped first). Keys hash the points' bytes with every option that
# the stage depends on, so a hit returns exactly what the computation would.
_STAGE_CACHE: OrderedDict = OrderedDict()
_STAGE_CACHE_SIZE = 8
_STAGE_CACHE_LOCK = threading.Lock()


def clear_cache() -> None:
    """Forget the remembered least-squares and minimax stages (e.g. in a new worker process,
    which would otherwise inherit its parent's, computed perhaps with another BLAS thread
    count and so rounded differently)."""
    with _STAGE_CACHE_LOCK:
        _STAGE_CACHE.clear()


def _stage_key(p: np.ndarray, side: str, *options) -> bytes:
    h = hashlib.blake2b(np.ascontiguousarray(p).tobytes(), digest_size=20)
    h.update(repr((p.shape, side, options)).encode())
    return h.digest()


def _cached(key: bytes, compute: Callable[[], dict]) -> dict:
    """``compute()`` or its remembered result; the result is copied (arrays and dicts)."""
    with _STAGE_CACHE_LOCK:
        hit = _STAGE_CACHE.get(key)
        if hit is not None:
            _STAGE_CACHE.move_to_end(key)
    if hit is None:
        t = time.perf_counter()
        hit = compute()
        hit["time_s"] = time.perf_counter() - t
        with _STAGE_CACHE_LOCK:
            _STAGE_CACHE[key] = hit
            while len(_STAGE_CACHE) > _STAGE_CACHE_SIZE:
                _STAGE_CACHE.popitem(last=False)
        out = dict(hit)
    else:
        out = dict(hit)
        out["time_s"] = 0.0
        log.debug("arcfit: stage reused from an identical earlier fit")
    return copy.deepcopy(out)


def _least_squares_stage(prob: _Problem, p: np.ndarray, s: np.ndarray, max_points: int) -> dict:
    """Least squares from the split starts on a subsample, the best polished on all points."""
    idx = _subsample(s, max_points)
    lsq_runs = []
    for split in (*_SPLITS, None):  # three-piece splits, and the turning-angle fit
        try:
            guess = _turning_guess(p, s) if split is None else _split_guess(p, s, *split)
            q, res = _lsq(prob, guess, idx)
        except (ValueError, FloatingPointError, np.linalg.LinAlgError) as exc:  # a degenerate guess
            log.debug("arcfit: least-squares start %s failed: %s", split or "turning", exc)
            continue
        if np.all(np.isfinite(q)):
            lsq_runs.append((float(res.cost), q, int(res.nfev)))
    if not lsq_runs:
        raise ConvergenceError("arcfit least_squares: every split start failed")
    lsq_runs.sort(key=lambda r: r[0])
    q_lsq, res = _lsq(prob, lsq_runs[0][1], None)
    if res.status == 0 and np.all(np.isfinite(q_lsq)):
        # the evaluation budget ran out while LM was still creeping at 1e-15 tolerances (seen on
        # the toothed-rim deformation of the verify scene, optimality 2e-8): carry on from there
        q_lsq, res = _lsq(prob, q_lsq, None, max_nfev=2000)
    if res.status <= 0 or not np.all(np.isfinite(q_lsq)):
        D, _, _ = prob.eval(q_lsq, jac=False)
        raise ConvergenceError(
            f"arcfit least_squares: no convergence after {res.nfev} evaluations "
            f"(rms residual {np.sqrt(np.mean(D**2)):.3e} mm, first-order optimality {res.optimality:.2e})"
            + _IN_A_DESIGN.replace('--fit least_squares (circular_spline.fit_method = "least_squares")',
                                   '--fit minimax (circular_spline.fit_method = "minimax")')
        )
    diag = {
        "subsample": len(idx),
        "lsq_starts": len(_SPLITS) + 1,
        "lsq_start_costs": [r[0] for r in lsq_runs],
        "lsq_nfev": int(res.nfev + sum(r[2] for r in lsq_runs)),
    }
    return {"q_lsq": q_lsq, "lsq_runs": lsq_runs, "diag": diag}


def _converged_at(prob: _Problem, q: np.ndarray, F_mm: float, imp: float | None = None) -> bool:
    """A minimax optimum to the fit's resolution: the LP over a small trust region at ``q``
    finds no relative decrease above 1e-6, or the absolute decrease it finds is below the
    rounding floor of the points (``prob.noise``). The second matters on near-exact fits (max
    error ~3e-7 mm): there 1e-6 relative is ~3e-13 mm, below the floor, and whether the LP's
    last digits land above or below it depends on the BLAS kernel (seen: 1.85e-6 with
    OpenBLAS's Sandybridge kernel, below 1e-6 with Haswell's)."""
    if imp is None:
        imp = _lp_improvement(prob, q, False)
    return bool(imp <= 1e-6 or imp * F_mm <= prob.noise)


def _restarted(prob: _Problem, run: tuple, *, max_iter: int, restarts: int = 3) -> tuple:
    """A start whose SLP stopped unconverged, run again from where it stopped, up to
    ``restarts`` times. A restart whitens the trust region anew (:func:`_metric` is the
    Gauss–Newton matrix at a run's first point). Seen on a flank with ridges with OpenBLAS's
    Sandybridge kernel: the third start, a secondary one capped at 20 SLP iterations, stopped
    the best of the three at 1.862e-3 mm with the LP still finding a 1.2e-3 relative decrease
    (a ConvergenceError); one restart converged at 1.844e-3 mm. Returns the run with the
    iterations and LPs of all its legs."""
    q, F, info = run
    for _ in range(restarts):
        if info["converged"] or info["stop"] != "iterations":
            break
        q2, F2, info2 = _solve(prob, q, one_sided=False, max_iter=max_iter)
        info2 = {**info2, "iterations": info["iterations"] + info2["iterations"], "lps": info["lps"] + info2["lps"]}
        if F2 > F * (1.0 + 1e-12):  # never worse than where the leg started
            q2, F2 = q, F
        q, F, info = q2, F2, info2
    return q, F, info


def _minimax_stage(prob: _Problem, q_lsq: np.ndarray, lsq_runs: list, *, starts: int, max_iter: int, seed: int, tie_break: bool) -> dict:
    """Minimax from the LSQ fit (centred in its error band), the other LSQ optima and
    perturbations; each start runs the whole SLP + Newton solve on all points."""
    cands = [_centred(prob, q_lsq)]
    skipped = 0
    for _, q, _ in lsq_runs[1:]:
        if len(cands) < starts and np.max(np.abs((q - q_lsq) / prob.scale)) > 1e-6:
            try:
                cands.append(_centred(prob, q))
            except OneSidedError:  # a degenerate optimum (an arc of ~zero radius) that cannot be centred:
                skipped += 1      # not a start (it failed the whole fit; a perturbation starts instead)
    rng = np.random.default_rng(seed)
    k = 0
    while len(cands) < starts:
        q0 = cands[0] + _PERTURBATIONS[k % len(_PERTURBATIONS)] * rng.standard_normal(6) * prob.scale
        q0[_I_L] = abs(q0[_I_L])
        cands.append(q0)
        k += 1
    runs = [_solve(prob, q0, one_sided=False, max_iter=max_iter if k == 0 else min(max_iter, 20)) for k, q0 in enumerate(cands)]

    def pick() -> tuple[np.ndarray, list[float], int]:
        # the minimax composite need not be unique (a stretch with slack may move freely);
        # of the starts that reach the best max error, keep the one with the smallest RMS
        Fs = np.array([r[1] for r in runs])
        tied = np.nonzero(Fs <= Fs.min() * (1.0 + 1e-9) + prob.noise)[0]
        rms = [float(np.sqrt(np.mean(prob.eval(runs[i][0], jac=False)[0] ** 2))) for i in tied]
        return Fs, rms, int(tied[int(np.argmin(rms))])

    Fs, rms, best = pick()
    if not _converged_at(prob, runs[best][0], runs[best][1]):  # the best start ran out of iterations
        runs[best] = _restarted(prob, runs[best], max_iter=max_iter)
        Fs, rms, best = pick()
    q_best, F_mm, info = runs[best]
    q_opt, F_opt = q_best, F_mm  # the minimax optimum the tie-break starts from
    diag: dict = {"starts_at_best": len(rms), "rms_spread_at_best": float((max(rms) - min(rms)) / max(min(rms), 1e-300))}
    if skipped:
        diag["lsq_optima_skipped"] = skipped
    if tie_break:
        q_best, ok = _tie_break(prob, q_best, F_mm)
        diag["tie_break"] = bool(ok)
        F_mm = _objective(prob.eval(q_best, jac=False)[0], False)
    diag["starts"] = int(starts)
    diag["start_max_errors_mm"] = Fs.tolist()
    ref = max(float(Fs.min()), SPREAD_FLOOR_MM)
    diag["start_spread"] = float((Fs.max() - Fs.min()) / ref)
    diag["primary_vs_best"] = float((Fs[0] - Fs.min()) / ref)
    diag["starts_within_1pct"] = int(np.sum(Fs - Fs.min() <= 0.01 * ref))
    diag["slp_iterations"] = [int(r[2]["iterations"]) for r in runs]
    diag["lp_solves"] = int(sum(r[2]["lps"] for r in runs))
    diag["starts_converged"] = int(sum(bool(r[2]["converged"]) for r in runs))
    diag["minimax_max_error_mm"] = F_mm
    imp = _lp_improvement(prob, q_best, False)
    # the tie-break's member may lie up to TIE_ACCEPT·F above the optimum, where the LP finds
    # that much decrease: then the certificate is the optimum's it was tied to
    if not _converged_at(prob, q_best, F_mm, imp) and not (q_opt is not q_best and _converged_at(prob, q_opt, F_opt)):
        raise ConvergenceError(
            f"arcfit minimax: no convergence in {max_iter} SLP iterations (max error {F_mm:.3e} mm, "
            f"the LP still finds a relative decrease of {imp:.2e}; a call of fit_profile can raise max_iter or "
            "starts)" + _IN_A_DESIGN
        )
    return {"q_best": q_best, "F_mm": F_mm, "imp": imp, "diag": diag}


def fit_profile(
    points,
    *,
    method: str = "one_sided",
    space_side: str = "auto",
    swept: Callable[[np.ndarray], np.ndarray] | None = None,
    swept_tol_mm: float = 1e-7,
    starts: int = 3,
    max_points: int = 300,
    max_iter: int = 60,
    seed: int = 0,
    tie_break: bool = True,
) -> ProfileFit:
    """Fit one G1 arc–line–arc composite to the flank ``points`` (n, 2) (mm, ordered along
    the flank, n ≥ 12).

    ``method``: "least_squares", "minimax" or "one_sided" (module docstring).
    ``space_side``: "left", "right" (of the points' direction of travel) or "auto".
    ``swept``: ``depth(points) -> (n,)``, > 0 inside the swept region (e.g.
    :func:`swept_depth_function`); a one-sided fit is checked against it (``swept_tol_mm``).
    ``starts``: minimax solves (the centred least-squares fit, other least-squares
    optima, then perturbations; use ≥ 20 for the multi-start certificate).
    ``max_points``: data subsample (by arc length) for the least-squares starts.
    ``max_iter``: SLP iterations of the first start (20 for the others).
    ``seed``: of the perturbations. ``tie_break``: of the minimax fits with the same
    max error, return the one with the smallest RMS error.

    Raises :class:`FitError` (a ``ValueError``) for bad input, :class:`OneSidedError` if a
    one-sided fit cannot stay out of the swept region, ``ConvergenceError`` (a
    ``RuntimeError``) if a solver does not converge.
    """
    t0 = time.perf_counter()
    _check_fit_options(method, starts, max_points, max_iter, swept_tol_mm, swept)
    p, s, dev = _flank_points(points)
    side = _space_side(space_side, p, swept)
    prob = _Problem(p, _side_sign(side))
    diag: dict = {"points": len(p), "space_side": side, "straightness_mm": dev}
    times: dict = {}

    # --- least squares (and, for minimax / one-sided, the minimax solve from it): both
    # depend only on the points, the side and the options, so a second fit of the same
    # flank (the pipeline fits it by every method) reuses them
    key = _stage_key(p, side, max_points)
    stage = _cached(key, lambda: _least_squares_stage(prob, p, s, max_points))
    q_lsq, lsq_runs = stage["q_lsq"], stage["lsq_runs"]
    diag.update(stage["diag"])
    times["least_squares_s"] = stage["time_s"]
    q_best = q_lsq

    if method != "least_squares":
        key = _stage_key(p, side, max_points, starts, max_iter, seed, tie_break)
        stage = _cached(key, lambda: _minimax_stage(prob, q_lsq, lsq_runs, starts=starts, max_iter=max_iter, seed=seed, tie_break=tie_break))
        q_best, F_mm = stage["q_best"], stage["F_mm"]
        diag.update(stage["diag"])
        times["minimax_s"] = stage["time_s"]
        if method == "minimax":
            diag["lp_improvement"] = stage["imp"]
            diag.update(_active_points(prob, q_best, F_mm))

    if method == "one_sided":
        t = time.perf_counter()
        q_best = _one_sided_stage(prob, q_best, max_iter, diag)
        times["one_sided_s"] = time.perf_counter() - t

    u_first, u_last, D = _feet(prob, q_best)
    if not u_last > u_first:
        raise ConvergenceError(f"arcfit {method}: the fitted composite runs against the data (feet at {u_first:.4g}, "
                               f"{u_last:.4g} mm)" + _IN_A_DESIGN)
    p8 = _params_from_q(q_best, u_first, u_last)
    chain = composite(p8)
    diag["evaluations"] = prob.evaluations
    diag["times_s"] = times
    fit = ProfileFit(
        method=method,
        params=_params_dict(p8),
        chain=chain,
        points_mm=p,
        error_mm=D,
        arclength_mm=s,
        backlash_mm=D if method == "one_sided" else None,
        space_side=side,
        time_s=time.perf_counter() - t0,
        diagnostics=diag,
    )
    if method == "one_sided" and swept is not None:
        check_swept(fit, swept, swept_tol_mm)
        object.__setattr__(fit, "time_s", time.perf_counter() - t0)
    return fit


def check_swept(fit: ProfileFit, swept: Callable[[np.ndarray], np.ndarray], tol_mm: float = 1e-7) -> dict:
    """The one-sided ``fit``'s chain checked against the swept region (``swept``, as
    :func:`fit_profile` takes it): sampled evenly and densely around the data points where its
    clearance is ~0. What :func:`fit_profile` does with ``swept``; apart, a caller can run it beside
    other work. Adds the check's numbers (``swept_max_depth_mm``, ...) and its time to the fit's
    diagnostics and returns them; raises :class:`OneSidedError` when the chain enters the region
    deeper than ``tol_mm``."""
    if fit.method != "one_sided":
        raise FitError(f"check_swept: a one_sided fit is checked against the swept region, not a {fit.method} fit")
    t = time.perf_counter()
    out = _check_swept(fit.chain, swept, tol_mm, float(np.median(np.diff(fit.arclength_mm))),
                       _clearance_minima(fit.points_mm, fit.error_mm))
    fit.diagnostics.update(out)
    fit.diagnostics.setdefault("times_s", {})["swept_check_s"] = time.perf_counter() - t
    return out


def _check_fit_options(method: str, starts, max_points, max_iter, swept_tol_mm, swept) -> None:
    """:func:`fit_profile`'s options, each checked (a :class:`FitError` naming it)."""
    if method not in METHODS:
        raise FitError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if not (isinstance(starts, (int, np.integer)) and starts >= 1):
        raise FitError(f"starts must be an integer >= 1, got {starts!r}")
    if not (isinstance(max_points, (int, np.integer)) and max_points >= MIN_POINTS):
        raise FitError(f"max_points must be an integer >= {MIN_POINTS}, got {max_points!r}")
    if not (isinstance(max_iter, (int, np.integer)) and max_iter >= 1):
        raise FitError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    if not (isinstance(swept_tol_mm, (int, float)) and swept_tol_mm >= 0 and math.isfinite(swept_tol_mm)):
        raise FitError(f"swept_tol_mm must be a finite number >= 0 mm, got {swept_tol_mm!r}")
    if swept is not None and not callable(swept):
        raise FitError(f"swept must be a callable depth(points) -> (n,) array or None, got {type(swept).__name__}")


def _flank_points(points) -> tuple[np.ndarray, np.ndarray, float]:
    """The flank's points checked: (points (n, 2) with an exact repeat dropped, their arc
    length, their largest deviation from a straight line); a straight flank or two coinciding
    points is a :class:`FitError`."""
    p = _check_points(points, "points")
    dev = _straightness(p)
    if dev <= STRAIGHT_TOL_MM:
        raise FitError(
            f"points: all {len(p)} points lie within {dev:.1e} mm of a straight line (tolerance {STRAIGHT_TOL_MM:g} mm); "
            "an arc–line–arc fit is ill-posed for a straight flank — use a single Line"
        )
    s = _arclength(p)
    if np.any(np.diff(s) == 0):  # a point repeated exactly (the tip circle's clip with tip_clearance_mm = 0): once
        p = p[np.r_[True, np.diff(s) > 0]]
        s = _arclength(p)
    if np.any(np.diff(s) <= 0):
        k = int(np.argmax(np.diff(s) <= 0))
        raise FitError(f"points: consecutive points {k} and {k + 1} coincide; points must be distinct and ordered along the flank")
    return p, s, dev


def _active_points(prob: _Problem, q: np.ndarray, F_mm: float) -> dict:
    """The minimax fit's active points (|d| at the level ``F_mm``): their count and signs."""
    D, _, _ = prob.eval(q, jac=False)
    active = np.abs(np.abs(D) - F_mm) <= 1e-9 * F_mm
    return {"active_points": int(active.sum()), "active_signs": np.sign(D[active]).astype(int).tolist()}


def _one_sided_stage(prob: _Problem, q_minimax: np.ndarray, max_iter: int, diag: dict) -> np.ndarray:
    """The one-sided fit from the minimax fit ``q_minimax`` moved toward the material by its max
    error, by the SLP with the one-sided constraint; its diagnostics into ``diag``."""
    D, _, _ = prob.eval(q_minimax, jac=False)
    q_os = _offset(q_minimax, prob.sigma * float(D.min()))  # all D ≥ 0, max D = 2 × minimax
    q_best, F, info = _solve(prob, q_os, one_sided=True, max_iter=max_iter)
    if not info["converged"]:
        imp = _lp_improvement(prob, q_best, True)
        if not imp <= 1e-6:
            raise OneSidedError(f"one_sided: no convergence in {max_iter} SLP iterations (max backlash {F:.3e} mm, "
                                f"LP improvement {imp:.2e})" + _IN_A_DESIGN)
    diag["lp_improvement"] = _lp_improvement(prob, q_best, True)
    diag["one_sided_iterations"] = int(info["iterations"])
    D, _, _ = prob.eval(q_best, jac=False)
    active = np.abs(D - F) <= 1e-9 * F
    diag["active_points"] = int(active.sum())
    diag["contact_points"] = int(np.sum(D <= 1e-9 * F))
    return q_best


def _clearance_minima(p: np.ndarray, D: np.ndarray) -> np.ndarray:
    """The data points (at most 20) where the one-sided fit's clearance ``D`` has a local
    minimum ~ 0 (below 1 % of its largest): where the fitted flank touches the data."""
    v = np.concatenate([[np.inf], D, [np.inf]])
    low = (v[1:-1] <= v[:-2]) & (v[1:-1] <= v[2:]) & (D <= 1e-2 * float(D.max()))
    return p[np.nonzero(low)[0][:20]]


def fit_profile_per_branch(
    points,
    ridges: Sequence,
    *,
    method: str = "one_sided",
    whole: bool = True,
    space_side: str = "auto",
    swept: Callable[[np.ndarray], np.ndarray] | None = None,
    swept_tol_mm: float = 1e-7,
    starts: int = 3,
    max_points: int = 300,
    max_iter: int = 60,
    seed: int = 0,
) -> BranchFits:
    """Fit one composite per branch of a flank with branch-switch ridges.

    ``ridges``: data indices or (x, y) points (mm; the nearest data point is taken) where
    the flank switches branch (``Envelope.ridges``); neighbouring branches share the
    ridge point. ``whole=True`` also fits one composite over the whole flank, for
    comparison. The other options are those of :func:`fit_profile`; the swept-region
    check (if ``swept`` is given) runs on every branch fit.
    """
    p = _check_points(points, "points")
    try:
        ridge_list = list(ridges)
    except TypeError:
        raise FitError(f"ridges: must be a sequence of data indices or (x, y) points in mm, got {ridges!r}") from None
    cut = []
    for r in ridge_list:
        if isinstance(r, (int, np.integer)) and not isinstance(r, bool):
            if not 0 < int(r) < len(p) - 1:
                raise FitError(f"ridges: index {r} is not inside the flank (allowed 1 .. {len(p) - 2})")
            cut.append(int(r))
        else:
            try:
                xy = np.asarray(r, float).reshape(2)
            except (TypeError, ValueError):
                raise FitError(f"ridges: each ridge is a data index or an (x, y) point in mm, got {r!r}") from None
            if not np.all(np.isfinite(xy)):
                raise FitError(f"ridges: a ridge point must be finite, got {xy.tolist()}")
            k = int(np.argmin(np.hypot(*(p - xy).T)))
            if not 0 < k < len(p) - 1:
                raise FitError(f"ridges: the point {xy.tolist()} mm is nearest to an end of the flank (data point {k})")
            cut.append(k)
    cut = sorted(set(cut))
    bounds = [0, *cut, len(p) - 1]
    side = _space_side(space_side, p, swept)
    for a, b in pairwise(bounds):
        if b - a + 1 < MIN_POINTS:
            raise FitError(f"ridges: the branch between data points {a} and {b} has {b - a + 1} points, fewer than {MIN_POINTS}")
    options: dict[str, Any] = {"method": method, "space_side": side, "swept_tol_mm": swept_tol_mm, "starts": starts, "max_points": max_points, "max_iter": max_iter, "seed": seed}
    fits = tuple(fit_profile(p[a : b + 1], swept=swept, **options) for a, b in pairwise(bounds))
    full = fit_profile(p, swept=None, **options) if whole else None
    return BranchFits(fits, tuple(cut), full)
