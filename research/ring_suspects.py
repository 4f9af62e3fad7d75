"""Radial compliances outside the contact model that the ratcheting climb could be missing.

The climb (:mod:`profilegen.contact.climb`) takes the CS as a free thin ring: per outward radial
point load P at θ_k the radial displacement at θ is

    w(θ) = P [R/(2π E A) + (1/π) Σ_{n = 2, 3, …} cos n(θ − θ_k) R³/(E I (n² − 1)²)]

(:func:`profilegen.contact.ratchet.cs_ring_radial_compliance`), R the mean radius between the CS
root circle and its outer circle, I = b h³/12. The estimate overshoots the catalogue by
3.7–4.5× at ratio 100 and the free ring's compliance would need ×3–4 to close it. This module
measures, each as a factor on that ring's mode-2 compliance — the harmonic that carries ≥ 95 % of
its bending for two opposite load zones (1/9 against Σ_{n even} 1/(n² − 1)² = 0.1168 for point
loads; spread zones weigh the higher harmonics less), so one factor on the whole matrix errs by
≤ 5 % × (the factor's change from mode 2 to 4: thick ring 1.04 → 1.19):

* **the CS as a thick ring** (:func:`annulus_mode_compliance`, plane stress): thin-ring theory
  for h/R ≈ 0.22 against 2D elasticity with the load on the root circle where the teeth put it;
* **the CS's bolt holes** (``holes=``): N axial through holes of diameter d at radius R_b in the
  ring's wall. Bounds by hand, :func:`holed_ring_bounds`: the section at angle ψ loses the chord
  c(ψ) of the hole — taken as one section with the hole cut out (composite, the stiff bound) or
  as two ligaments bending each about its own axis (the soft bound); the mode-n compliance of a
  curved beam is ∫ M²/(E I) dθ with M ∝ cos nθ and holes much closer than the mode's wavelength,
  so the factor is the circumferential mean of I₀/I(θ) (Castigliano; Roark, *Formulas for
  Stress and Strain*, 7th ed., ch. 9, thin rings). The 2D FEM decides between them;
* **the wave generator's plug** (:func:`plug_ring`): the elliptical cam as an annulus from its
  bore to the bearing's inner-race seat, loaded on its outer circle by the balls. Its inward
  mode-2 displacement adds to the FS teeth's retreat exactly as the CS's outward one does (the
  same radial loads, transmitted by the rim and the balls; both rings have the same harmonic
  shape, so the sum is a factor on the CS ring's compliance). The plug's bore is not in the gear
  set: it is swept (a shaft bore to a lightened, hollow plug). The shaft in the bore, pressed or
  keyed, only stiffens it; an Oldham coupling leaves it empty (the upper bound).

A third suspect is not a ring: **the outer race and the FS rim bending across the face** between
the ball row (mid-width) and the face's ends, where the tooth load also sits — the strip model of
:mod:`research.race_flexure` (c_ax = b³/(320 E I) per ball, in series with its Hertz spring),
put into the climb as :class:`FlexedBearing` (``ratcheting_torque(options={"bearing": ...})``).

Each factor enters the climb through the existing study option ``climb_ring_scale`` of
:func:`profilegen.contact.ratchet.ratcheting_torque` (``tests/benchmarks/ring_suspects.py``).

The FEM: scikit-fem, 9-node quadrilaterals (``ElementQuad2``) on a polar grid of a quarter
annulus with symmetry on both cut lines (u_y = 0 on y = 0, u_x = 0 on x = 0: the load cos 2θ
and the holes, placed at (k + ½)·2π/N with N a multiple of 4, are symmetric about both axes),
a radial line load q cos nθ on the loaded circle, its mode-n displacement read as the cos nθ
Fourier coefficient of u_r on that circle. Holes are cut from the grid (elements whose centre
lies in a hole are dropped): a stair-cased hole, converged by refining (tests/research).
Units mm, N, MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from profilegen.contact.chain import BallBearing

__all__ = [
    "FlexedBearing",
    "Holes",
    "Ring",
    "annulus_mode_compliance",
    "cs_ring",
    "flexed_bearing",
    "holed_ring_bounds",
    "plate_flexure_compliance_mm_per_n",
    "plug_ring",
    "ring_scale_factors",
    "thin_ring_mode_compliance",
]


@dataclass(frozen=True)
class Ring:
    """An annulus (mm, MPa): inner and outer radius, axial width, E, ν, and the circle the
    radial loads act on ("inner": the CS's teeth; "outer": the plug's balls)."""

    inner_radius_mm: float
    outer_radius_mm: float
    width_mm: float
    youngs_modulus_mpa: float
    poisson_ratio: float = 0.3
    loaded: str = "inner"

    def __post_init__(self):
        if not 0.0 < self.inner_radius_mm < self.outer_radius_mm:
            raise ValueError(f"inner_radius_mm = {self.inner_radius_mm!r}, outer_radius_mm = {self.outer_radius_mm!r}: "
                             "need 0 < inner < outer (mm)")
        if self.loaded not in ("inner", "outer"):
            raise ValueError(f"loaded = {self.loaded!r}: must be 'inner' or 'outer'")

    @property
    def thickness_mm(self) -> float:
        return self.outer_radius_mm - self.inner_radius_mm

    @property
    def mean_radius_mm(self) -> float:
        return 0.5 * (self.inner_radius_mm + self.outer_radius_mm)

    @property
    def load_radius_mm(self) -> float:
        return self.inner_radius_mm if self.loaded == "inner" else self.outer_radius_mm


@dataclass(frozen=True)
class Holes:
    """``count`` axial through holes of ``diameter_mm`` on the circle ``radius_mm``, centred at
    (k + ½)·2π/count (count a multiple of 4 for the quarter model's symmetry)."""

    count: int
    diameter_mm: float
    radius_mm: float

    def angles_rad(self) -> np.ndarray:
        return (np.arange(self.count) + 0.5) * 2.0 * math.pi / self.count


def thin_ring_mode_compliance(ring: Ring, n: int = 2) -> float:
    """Radial displacement amplitude per point load (mm/N) of mode n of a free thin ring, the
    climb's term: R³/(π E I (n² − 1)²), I = b h³/12 (Roark ch. 9; the same coefficient as
    :func:`profilegen.contact.ratchet.cs_ring_radial_compliance`)."""
    inertia = ring.width_mm * ring.thickness_mm ** 3 / 12.0
    return ring.mean_radius_mm ** 3 / (math.pi * ring.youngs_modulus_mpa * inertia * (n * n - 1) ** 2)


def holed_ring_bounds(ring: Ring, holes: Holes, samples: int = 4001) -> tuple[float, float]:
    """(composite, ligaments): the factors on a solid ring's bending compliance from the holes,
    the circumferential mean of I₀/I(θ) with the hole's chord c(θ) cut from the section — as one
    section about its own centroid (the stiff bound), or as two ligaments each about its own
    axis (the soft bound). Module docstring."""
    h, b = ring.thickness_mm, ring.width_mm
    ri = ring.inner_radius_mm
    i0 = b * h ** 3 / 12.0
    pitch = 2.0 * math.pi / holes.count
    # angle from the nearest hole's centre, over one pitch
    psi = (np.arange(samples) + 0.5) / samples * pitch - 0.5 * pitch
    a = 0.5 * holes.diameter_mm
    # the hole's radial extent at the polar angle ψ (the ray from the centre through the hole)
    y = holes.radius_mm * np.sin(psi)
    inside = np.abs(y) < a
    x0 = holes.radius_mm * np.cos(psi)
    half = np.sqrt(np.clip(a * a - y * y, 0.0, None))
    lo, hi = np.where(inside, x0 - half, 0.0), np.where(inside, x0 + half, 0.0)
    # ligaments in local radial coordinate s from the inner surface
    l1 = np.clip(lo - ri, 0.0, h)
    l2 = np.clip(ri + h - hi, 0.0, h)
    # composite: the section with [lo, hi] cut out, about its own centroid
    area = b * np.where(inside, l1 + l2, h)
    s1, s2 = 0.5 * l1, h - 0.5 * l2
    cen = np.where(inside, (l1 * s1 + l2 * s2) / np.maximum(l1 + l2, 1e-300), 0.5 * h)
    comp = np.where(inside, b * (l1 ** 3 + l2 ** 3) / 12.0 + b * l1 * (s1 - cen) ** 2 + b * l2 * (s2 - cen) ** 2, i0)
    lig = np.where(inside, b * (l1 ** 3 + l2 ** 3) / 12.0, i0)
    del area
    return float(np.mean(i0 / comp)), float(np.mean(i0 / np.maximum(lig, 1e-300 * i0)))


def _quarter_mesh(ring: Ring, n_radial: int, n_theta: int, holes: Holes | None):
    from skfem import MeshQuad

    r = np.linspace(ring.inner_radius_mm, ring.outer_radius_mm, n_radial + 1)
    t = np.linspace(0.0, 0.5 * math.pi, n_theta + 1)
    rr, tt = np.meshgrid(r, t, indexing="ij")
    p = np.vstack([(rr * np.cos(tt)).ravel(), (rr * np.sin(tt)).ravel()])
    idx = np.arange(p.shape[1]).reshape(rr.shape)
    quads = np.vstack([idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()])
    if holes is not None:
        c = p[:, quads].mean(axis=1)
        keep = np.ones(quads.shape[1], bool)
        for a in holes.angles_rad():
            centre = holes.radius_mm * np.array([math.cos(a), math.sin(a)])
            keep &= np.hypot(c[0] - centre[0], c[1] - centre[1]) > 0.5 * holes.diameter_mm
        quads = quads[:, keep]
        used = np.unique(quads)
        remap = -np.ones(p.shape[1], int)
        remap[used] = np.arange(used.size)
        p, quads = p[:, used], remap[quads]
    return MeshQuad(p, quads)


def annulus_mode_compliance(ring: Ring, n: int = 2, *, holes: Holes | None = None, n_radial: int = 8,
                            n_theta: int = 96) -> float:
    """Mode-n radial displacement amplitude per point load (mm/N) of the annulus in plane
    stress (2D elasticity, scikit-fem, module docstring): a radial line load q cos nθ (N/mm of
    the loaded circle, through the width b) gives u_r = A cos nθ there; a point load P is the
    line load P/(π a) cos n(θ − θ_k) in mode n (a the loaded circle's radius), so the
    compliance is A/(q π a). Sign: outward for a ring loaded outward on its inner circle (the CS),
    inward for one loaded inward on its outer circle (the plug). n even (the quarter model)."""
    from skfem import Basis, ElementQuad2, ElementVector, FacetBasis, LinearForm, asm, condense, solve
    from skfem.helpers import dot
    from skfem.models.elasticity import linear_elasticity

    if n % 2:
        raise ValueError(f"n = {n!r}: the quarter model needs an even mode")
    mesh = _quarter_mesh(ring, n_radial, n_theta, holes)
    e, nu = ring.youngs_modulus_mpa, ring.poisson_ratio
    # plane stress: λ* = E ν/(1 − ν²), μ = E/(2(1 + ν))
    lam, mu = e * nu / (1.0 - nu * nu), e / (2.0 * (1.0 + nu))
    basis = Basis(mesh, ElementVector(ElementQuad2()))
    k = asm(linear_elasticity(lam, mu), basis) * ring.width_mm
    a = ring.load_radius_mm
    sign = 1.0 if ring.loaded == "inner" else -1.0  # outward on the inner circle; inward on the outer

    tol = 0.25 * ring.thickness_mm / n_radial  # a chord's midpoint sits inside the circle by ~a(π/4/n_theta)²/2

    def on_circle(x):
        return np.abs(np.hypot(x[0], x[1]) - a) < tol

    facets = mesh.facets_satisfying(on_circle)
    fb = FacetBasis(mesh, basis.elem, facets=facets)

    @LinearForm
    def load(v, w):
        x, y = w.x
        th = np.arctan2(y, x)
        er = np.array([np.cos(th), np.sin(th)])
        return sign * np.cos(n * th) * dot(er, v)

    f = asm(load, fb)  # q = 1 N/mm over the width
    dofs = basis.get_dofs(lambda x: np.abs(x[1]) < 1e-9 * a)
    fixed = [dofs.all("u^2")]
    dofs = basis.get_dofs(lambda x: np.abs(x[0]) < 1e-9 * a)
    fixed.append(dofs.all("u^1"))
    u = solve(*condense(k, f, D=np.concatenate(fixed)))
    # u_r on the loaded circle at its nodes, the cos nθ coefficient (trapezoid on the quarter)
    nodes = np.flatnonzero(on_circle(mesh.p))
    th = np.arctan2(mesh.p[1, nodes], mesh.p[0, nodes])
    order = np.argsort(th)
    nodes, th = nodes[order], th[order]
    ux, uy = u[basis.nodal_dofs[0, nodes]], u[basis.nodal_dofs[1, nodes]]
    ur = sign * (ux * np.cos(th) + uy * np.sin(th))
    amp = np.trapezoid(ur * np.cos(n * th), th) / np.trapezoid(np.cos(n * th) ** 2, th)
    return float(amp / (math.pi * a))


def cs_ring(gearset, inputs=None) -> Ring:
    """The CS ring the climb takes (its section: the fitted CS space's root circle, or the
    estimated one without ``inputs``, to the outer circle :func:`profilegen.contact.chain.
    cs_held_radius`; the face width wide), loaded on its inner circle."""
    from profilegen.contact.chain import cs_held_radius

    r_out, _ = cs_held_radius(gearset)
    g = gearset.gear
    if inputs is not None:
        pts = np.asarray(inputs.cs_space.sample(1e-3), dtype=float)
        r_root = float(np.max(np.hypot(pts[:, 0], pts[:, 1])))
    else:
        w0 = float(gearset.wave_generator.deflection_coefficient) * float(g.module_mm)
        r_root = float(g.pitch_radius_mm) + float(gearset.tooth.addendum_mm) + w0 + 0.25 * float(g.module_mm)
    m = gearset.material
    return Ring(r_root, float(r_out), float(gearset.cup.face_width_mm), float(m.youngs_modulus_mpa),
                float(m.poisson_ratio), "inner")


def plug_ring(gearset, bore_fraction: float) -> Ring:
    """The wave generator's plug as an annulus: outer radius the inner race's seat (the FS bore
    less ``wave_generator.bearing_thickness_mm``), inner radius ``bore_fraction`` × that, the
    bearing's width (``cup.bearing_width_mm``, else the face width), the FS's steel; loaded on
    its outer circle."""
    g, wg, cup, m = gearset.gear, gearset.wave_generator, gearset.cup, gearset.material
    if not 0.0 < bore_fraction < 1.0:
        raise ValueError(f"bore_fraction = {bore_fraction!r}: must be in (0, 1)")
    r_bore = float(g.neutral_radius_mm) - 0.5 * float(g.rim_thickness_mm)
    h = wg.bearing_thickness_mm
    if h is None:
        raise ValueError("wave_generator.bearing_thickness_mm: needed for the plug's outer radius")
    r_out = r_bore - float(h)
    width = getattr(cup, "bearing_width_mm", None) or cup.face_width_mm
    return Ring(bore_fraction * r_out, r_out, float(width), float(m.youngs_modulus_mpa), float(m.poisson_ratio),
                "outer")


def ring_scale_factors(gearset, *, holes: Holes | None = None, bore_fractions=(0.25, 0.5, 0.7), inputs=None,
                       n_radial: int = 8, n_theta: int = 96) -> dict:
    """The factors on the climb's free thin CS ring (its mode-2 compliance) of each suspect:
    ``thick`` (the CS solid annulus, 2D elasticity, over thin-ring theory), ``holes`` (the holed
    CS over the solid one, FEM, with the hand bounds), ``plug`` {bore fraction: the plug's
    mode-2 compliance over the thin CS ring's}. The climb's ``climb_ring_scale`` for a set of
    them is thick × holes + plug."""
    cs = cs_ring(gearset, inputs)
    thin = thin_ring_mode_compliance(cs)
    solid = annulus_mode_compliance(cs, n_radial=n_radial, n_theta=n_theta)
    out = {"cs": cs, "thin_mm_per_n": thin, "thick": solid / thin, "holes": None, "holes_bounds": None, "plug": {}}
    if holes is not None:
        holed = annulus_mode_compliance(cs, holes=holes, n_radial=2 * n_radial, n_theta=2 * n_theta)
        solid_fine = annulus_mode_compliance(cs, n_radial=2 * n_radial, n_theta=2 * n_theta)
        out["holes"] = holed / solid_fine
        out["holes_bounds"] = holed_ring_bounds(cs, holes)
    for f in bore_fractions:
        pr = plug_ring(gearset, f)
        out["plug"][f] = annulus_mode_compliance(pr, n_radial=n_radial, n_theta=n_theta) / thin
    return out


def flexed_bearing(gearset) -> "FlexedBearing":
    """The gear set's estimated ball bearing with the race-and-rim strip's axial flexure
    (:func:`research.race_flexure.race_axial_flexure_compliance_mm_per_n`: strip = the ball pitch on
    the outer race's mid-radius, the race and the rim sliding) in series with each ball's Hertz spring."""
    from profilegen.contact.compliance import default_race_thickness_mm
    from research.race_flexure import race_axial_flexure_compliance_mm_per_n

    b = BallBearing.from_gearset(gearset)
    t_race = default_race_thickness_mm(gearset.gear)
    r_race = 0.5 * b.pitch_diameter_mm + 0.5 * b.ball_diameter_mm + 0.5 * t_race
    strip = 2.0 * math.pi * r_race / b.ball_count
    c_ax = race_axial_flexure_compliance_mm_per_n(float(gearset.cup.face_width_mm), strip, t_race,
                                                  float(gearset.gear.rim_thickness_mm),
                                                  float(gearset.material.youngs_modulus_mpa))
    return FlexedBearing(b.ball_count, b.ball_diameter_mm, b.pitch_diameter_mm, b.groove_conformity,
                         b.youngs_modulus_mpa, b.poisson_ratio, b.estimates + ("race axial flexure (strip model)",),
                         flexure_mm_per_n=c_ax)



@dataclass(frozen=True, slots=True, eq=False)
class FlexedBearing(BallBearing):
    """A :class:`~profilegen.contact.chain.BallBearing` whose ball springs have a linear
    compliance ``flexure_mm_per_n`` in series with Hertz (the secant δ/Q + c)."""

    flexure_mm_per_n: float = 0.0

    def secant_compliance_mm_per_n(self, force_n, *, floor_n: float = 1.0) -> np.ndarray:
        return BallBearing.secant_compliance_mm_per_n(self, force_n, floor_n=floor_n) + self.flexure_mm_per_n


def plate_flexure_compliance_mm_per_n(face_width_mm: float, pitch_mm: float, rigidity_nmm: float, *,
                                      divisions: int = 16) -> float:
    """The strip model's c_ax checked as a plate: the race and rim (flexural rigidity D, N·mm) as a
    Kirchhoff plate one ball pitch s wide (circumferential, x) and the face b long (axial, y),
    periodic in x (slopes zero on x = 0 and x = s/2 by symmetry), free at the face's ends, under a
    uniform pressure, held at its ball (a point at mid-width) — against the same plate held
    along the whole line x = 0 (the 2D slice's ball, a radial support across the face). The
    extra compliance is the difference of the load's mean deflections (work-conjugate, as the
    slice's even load) per ball load q·s·b. scikit-fem's Morley triangle on the quarter
    x ∈ [0, s/2], y ∈ [0, b/2] (symmetry on y = 0), ``divisions`` along the shorter side."""
    from skfem import Basis, BilinearForm, ElementTriMorley, LinearForm, MeshTri, asm, condense, solve
    from skfem.helpers import dd, ddot, trace

    b, s, d = float(face_width_mm), float(pitch_mm), float(rigidity_nmm)
    if not (b > 0.0 and s > 0.0 and d > 0.0):
        raise ValueError(f"face_width_mm = {b!r}, pitch_mm = {s!r}, rigidity_nmm = {d!r}: must be > 0")
    nu = 0.3
    hx, hy = 0.5 * s, 0.5 * b
    step = min(hx, hy) / divisions
    mesh = MeshTri.init_tensor(np.linspace(0.0, hx, max(2, round(hx / step)) + 1),
                               np.linspace(0.0, hy, max(2, round(hy / step)) + 1))

    @BilinearForm
    def plate(u, v, _):
        return d * ((1.0 - nu) * ddot(dd(u), dd(v)) + nu * trace(dd(u)) * trace(dd(v)))

    @LinearForm
    def pressure(v, _):
        return v

    basis = Basis(mesh, ElementTriMorley())
    k, f = asm(plate, basis), asm(pressure, basis)
    slope, value = basis.facet_dofs[0], basis.nodal_dofs[0]
    mid = mesh.p[:, mesh.facets].mean(axis=1)
    tol = 1e-9 * max(hx, hy)
    sym = np.flatnonzero((mid[0] < tol) | (mid[0] > hx - tol) | (mid[1] < tol))
    on_x0 = np.flatnonzero(mesh.p[0] < tol)
    corner = np.flatnonzero((mesh.p[0] < tol) & (mesh.p[1] < tol))
    means = []
    for held in (corner, on_x0):
        u = solve(*condense(k, f, D=np.unique(np.concatenate([slope[sym], value[held]]))))
        means.append(float(f @ u) / (hx * hy))
    return (means[0] - means[1]) / (s * b)
