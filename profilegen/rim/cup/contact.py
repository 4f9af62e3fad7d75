"""The cup pressed onto the wave-generator contour over the bearing's width: frictionless
unilateral contact, first order, by collocation in φ with the harmonic solves as the
compliance operator (DESIGN.md, "Notes for the 3D cup": each solve stays 2D).

Unknowns: the radial force μ_ij ≥ 0 (N) of the cam on bore node i of the bearing band
(z_i) at collocation angle φ_j = j·(π/2)/(J − 1), j = 0..J − 1 — each the total of its
symmetry group (±φ_j, π ± φ_j: a two-wave contour symmetric about both axes), so the
generalised force of harmonic n (even) is P_n,i = Σ_j μ_ij cos nφ_j. With G_n the
harmonic-n compliance between the band's radial dofs (boss clamped, the rest free), the
bore's radial displacement at the collocation points is u = C μ,
C = Σ_n G_n ⊗ a_n a_nᵀ, a_n = (cos nφ_j)_j, n = 0, 2, …, 2(J − 1) (as many harmonics as
angles, so C is positive definite). The gap (first order, radial): g = u − w(φ_j) ≥ 0 with
w = ρ − r_bore of the contour; μ ≥ 0, μ·g = 0 — the convex QP min ½μᵀCμ − wᵀμ, μ ≥ 0,
solved exactly as the non-negative least-squares problem min |Lᵀμ − L⁻¹w| (C = LLᵀ) as
:func:`profilegen.rim.ring._contact_set` does.

The result is a :class:`~profilegen.rim.cup.fourier.CupDeformation` (harmonics 0..2(J − 1)) and
the contact state (:class:`CupContact`). Not yet: the O(w0²/R) exact-gap geometry of the 2D
ring (its ~4.6 µm in ω on the default set), geometric nonlinearity.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import partial

import numpy as np

from ... import checks
from ...errors import ConvergenceError
from ...results import readonly
from .fourier import CupDeformation, HarmonicBasis, _resultants, bore_load, harmonic_stiffness
from .geometry import CupError, CupGeometry, meridional_mesh

__all__ = ["CupContact", "press_cup"]

_whole = partial(checks.whole, error=CupError)


@dataclass(frozen=True, slots=True, eq=False)
class CupContact:
    """The cup on its contour: ``deformation`` (ω, υ, axial, tilt at any (φ, z)); the bearing
    band's bore nodes ``z_mm`` × collocation angles ``phi_rad`` (0..π/2): the cam's radial
    force ``force_n`` (N, each the total of its four symmetric copies), the gap ``gap_mm`` (the
    bore's radial displacement minus the contour's w(φ); ≥ 0), ``active`` (force > 0);
    ``load_mm``: w(φ_j); ``compliance_s``, ``contact_s``: times (s)."""

    deformation: CupDeformation
    z_mm: np.ndarray
    phi_rad: np.ndarray
    force_n: np.ndarray
    gap_mm: np.ndarray
    load_mm: np.ndarray
    compliance_s: float
    contact_s: float
    time_s: float

    def __post_init__(self):
        for name in ("z_mm", "phi_rad", "force_n", "gap_mm", "load_mm"):
            object.__setattr__(self, name, readonly(getattr(self, name)))

    @property
    def active(self) -> np.ndarray:
        return self.force_n > 0.0

    @property
    def max_penetration_mm(self) -> float:
        return float(max(0.0, -np.min(self.gap_mm)))

    def to_dict(self) -> dict:
        from ...results import json_ready

        out = self.deformation.to_dict()
        out["model"] = ("cup as a body of revolution, Fourier harmonics of 2D meridional FEM, pressed onto the "
                        "contour over the bearing width: frictionless unilateral contact by collocation in φ, "
                        "first-order (radial) gap, boss clamped")
        out["contact"] = json_ready({"z_mm": self.z_mm, "phi_rad": self.phi_rad, "force_n": self.force_n,
                                     "gap_mm": self.gap_mm, "load_mm": self.load_mm,
                                     "max_penetration_mm": self.max_penetration_mm,
                                     "compliance_s": self.compliance_s, "contact_s": self.contact_s,
                                     "time_s": self.time_s})
        return out

    def contact_span_mm(self, phi_index: int) -> tuple[float, float] | None:
        """(first, last) z of the loaded band nodes at collocation angle ``phi_index``, or None."""
        on = np.flatnonzero(self.active[:, phi_index])
        return None if on.size == 0 else (float(self.z_mm[on[0]]), float(self.z_mm[on[-1]]))


def press_cup(
    geometry_or_gearset,
    *,
    contour=None,
    radial_mm=None,
    angles: int = 16,
    element_mm: float = 2.0,
    layers: int = 2,
    harmonic_basis: HarmonicBasis | None = None,
) -> CupContact:
    """The cup pressed onto ``contour`` (or the bore shape ``radial_mm`` {n: w_n}, even n) over
    the bearing's width, frictionless and unilateral, boss clamped. ``angles`` J collocation
    angles on 0..π/2 (harmonics 0, 2, …, 2(J − 1)). With a GearSet and no load, its contour.

    Defaults (2 mm, 2 layers, 16 angles): within 0.3 µm in ω, 0.05 µm in υ of 1 mm / 31 angles
    over the default set's tooth ring, 3.1 s against 41 s under a load of ~8 on 2 cores
    (``python tests/benchmarks/cup3d.py``, part 6)."""
    from scipy.linalg import LinAlgError, cholesky, solve_triangular
    from scipy.optimize import nnls

    from .fourier import _factor

    start = time.perf_counter()
    if isinstance(geometry_or_gearset, CupGeometry):
        geometry, gearset = geometry_or_gearset, None
    else:
        geometry, gearset = CupGeometry.from_gearset(geometry_or_gearset), geometry_or_gearset
    angles = _whole("angles", angles, 2)
    orders = 2 * np.arange(angles)
    if radial_mm is not None and contour is not None:
        raise CupError("radial_mm and contour: give one load, not both")
    if radial_mm is None:
        if contour is None:
            if gearset is None:
                raise CupError("contour: a load is needed (contour or radial_mm) for a bare CupGeometry")
            from ...wavegen import from_gearset

            contour = from_gearset(gearset)
        phi = 0.5 * math.pi * np.arange(angles) / (angles - 1)
        w_cam = np.asarray(contour.radius(phi), dtype=float) - geometry.bore_radius_mm
        load = bore_load(contour, geometry.bore_radius_mm, max_order=int(orders[-1]))
    else:
        from .fourier import _load

        load = _load(radial_mm)
        if any(n % 2 for n in load):
            raise CupError("radial_mm: odd harmonics break the two symmetry planes the contact uses")
        phi = 0.5 * math.pi * np.arange(angles) / (angles - 1)
        w_cam = sum(w * np.cos(n * phi) for n, w in load.items())
    if harmonic_basis is None:
        harmonic_basis = harmonic_stiffness(meridional_mesh(geometry, element_mm=element_mm, layers=layers))
    elif harmonic_basis.cup_mesh.geometry is not geometry:
        raise CupError("harmonic_basis: it was built for another CupGeometry than the one given")
    hb, g = harmonic_basis, geometry
    iu, iw, iv = hb.components()
    r, z = hb.nodes
    tol = 1e-9 * max(g.outer_radius_mm, g.open_end_mm)
    b_lo, b_hi = g.bearing_span_mm
    boss = np.flatnonzero(np.abs(r - g.boss_radius_mm) < tol)
    band = np.flatnonzero((np.abs(r - g.bore_radius_mm) < tol) & (z > b_lo - tol) & (z < b_hi + tol))
    band = band[np.argsort(z[band])]
    z_wall = 0.5 * g.bottom_thickness_mm
    line = np.flatnonzero((np.abs(r - g.neutral_radius_mm) < tol) & (z > z_wall - tol))
    line = line[np.argsort(z[line])]
    bore_line = np.flatnonzero((np.abs(r - g.bore_radius_mm) < tol) & (z > z_wall - tol))
    bore_line = bore_line[np.argsort(z[bore_line])]
    clamped = np.concatenate([iu[boss], iw[boss], iv[boss]])
    free = np.setdiff1d(np.arange(hb.dof), clamped)
    where = -np.ones(hb.dof, dtype=int)
    where[free] = np.arange(free.size)
    m = band.size

    # compliance of every harmonic: the responses to unit radial forces on the band nodes
    t0 = time.perf_counter()
    responses = []
    rhs = np.zeros((free.size, m))
    rhs[where[iu[band]], np.arange(m)] = 1.0
    for n in orders:
        stiff = hb.stiffness(int(n))
        try:
            cols = _factor(stiff[free][:, free]).solve(rhs)
        except RuntimeError as exc:
            raise ConvergenceError(f"press_cup: the harmonic n = {n} stiffness is singular ({exc})") from exc
        full = np.zeros((hb.dof, m))
        full[free] = cols
        responses.append(full)
    a = np.cos(np.outer(orders, phi))  # (harmonics, angles)
    compliance = np.zeros((m * angles, m * angles))
    for k, full in enumerate(responses):
        g_n = full[iu[band]]
        g_n = 0.5 * (g_n + g_n.T)
        compliance += np.kron(g_n, np.outer(a[k], a[k]))
    t_comp = time.perf_counter() - t0

    t0 = time.perf_counter()
    q = np.tile(w_cam, m)  # (i, j) → i·J + j
    try:
        lower = cholesky(compliance, lower=True)
    except LinAlgError as exc:
        raise ConvergenceError(f"press_cup: the contact compliance ({m} band nodes × {angles} angles) is not "
                               f"positive definite ({exc})") from exc
    force, _ = nnls(lower.T, solve_triangular(lower, q, lower=True), maxiter=50 * q.size)
    if not np.all(np.isfinite(force)):
        raise ConvergenceError("press_cup: non-finite contact forces")
    gap = compliance @ force - q
    t_contact = time.perf_counter() - t0

    mu = force.reshape(m, angles)
    p = mu @ a.T  # (m, harmonics): P_n,i
    radial = np.zeros((orders.size, line.size))
    axial, tangential = np.zeros_like(radial), np.zeros_like(radial)
    bore_radial = np.zeros_like(radial)
    boss_res, bore_res = [], []
    for k, (n, full) in enumerate(zip(orders, responses)):
        x = full @ p[:, k]
        radial[k], axial[k], tangential[k] = x[iu[line]], x[iw[line]], x[iv[line]]
        bore_radial[k] = x[iu[bore_line]]
        reaction = hb.stiffness(int(n)) @ x
        boss_res.append(_resultants(int(n), reaction, (iu, iw, iv), r, z, boss))
        bore_res.append(_resultants(int(n), reaction, (iu, iw, iv), r, z, band))
    elapsed = time.perf_counter() - start
    deformation = CupDeformation(
        geometry=g, orders=orders, load_mm=np.array([load.get(int(n), 0.0) for n in orders]), z_mm=z[line],
        radial_mm=radial, axial_mm=axial, tangential_mm=tangential, bore_radial_mm=bore_radial,
        boss_reaction=tuple(boss_res), bore_reaction=tuple(bore_res), dof=hb.dof,
        elements=hb.cup_mesh.elements, element_mm=hb.cup_mesh.element_mm, layers=hb.cup_mesh.layers,
        assembly_s=hb.assembly_s, solve_s=t_comp + t_contact, time_s=elapsed,
        warnings=("unilateral contact by collocation, first-order (radial) gap",))
    return CupContact(deformation, z[band], phi, mu, gap.reshape(m, angles), w_cam, t_comp, t_contact, elapsed)
