"""The torsional curve across the face (profilegen.contact.face_curve, torsional_curve(face_slices=N)).

Checked against what the slice model does not compute itself: the 2D curve (identical slices,
and one slice with the ring's twist, must reproduce it), a two-slice one-point case and the
ring's twist solved by hand, the ring kernel against its defining double integral, the
thickness offset against a rigid tangential move, Lemke from scratch on the stacked problem, and
equilibrium and complementarity of teeth and balls in every slice recomputed from the 2D
compliance's own matrices."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import profilegen as pg
from profilegen.contact.chain import compliance_chain, torsional_curve
from profilegen.contact.compliance import ContactCompliance
from profilegen.contact.face_curve import (
    FaceCurveError, FaceSlices, flank_offset_gap_mm, local_fraction, rim_coupling_length_mm, ring_twist_kernel,
    slice_chain, slice_coupling_matrix, slice_gap_shifts, slice_layout, stack_slices)
from research.face_load import slice_coupling
from profilegen.contact.inputs import ContactInput
from profilegen.contact.points import ContactPoints
from profilegen.contact.reduced import ReducedZone

TORQUES = [-196.0, -54.0, 54.0, 196.0]


# --------------------------------------------------------------------------- by hand


def _one_point(s_mm_per_n=2e-6, lever=45.0, gap=1e-3, zones=2, b=10.0):
    """One tooth point on a compliance s (whole face), one ball far away and uncoupled."""
    pts = ContactPoints(tooth=np.array([0]), phi_rad=np.zeros(1), t_mm=np.zeros(1), local_mm=np.array([[0.3, 1.0]]),
                        fs_point_mm=np.zeros((1, 2)), cs_point_mm=np.zeros((1, 2)), normal=np.array([[1.0, 0.0]]),
                        gap_mm=np.array([gap]), lever_mm=np.array([lever]), side=1, rotation=1, zones=zones,
                        stations=1, max_gap_mm=0.12)
    m = np.array([[s_mm_per_n]])
    comp = ContactCompliance(
        matrix_mm_per_n=m, fs_matrix_mm_per_n=m, cs_matrix_mm_per_n=np.zeros((1, 1)), face_width_mm=b,
        tooth=np.array([0]), ball_angle_rad=np.array([1.0]), ball_active=np.array([False]), wrap_half_angle_rad=0.5,
        wrap_source="test", dof={}, time_s={}, mesh={}, _flex_cc=m * b, _flex_cb=np.zeros((1, 1)),
        _flex_bb=np.array([[1.0]]), ball_supports="all", ball_gap_mm=np.array([1.0]))
    return pts, comp


def _solve(pts, comp, torque_nm, bearing=None):
    zone = ReducedZone(pts, comp, bearing)
    loaded = np.zeros(pts.count, bool)
    loaded[int(np.argmin(pts.theta_rad))] = True
    out = zone.solve(torque_nm, (loaded, np.asarray(comp.ball_active, bool), None), springs_on=bearing is not None,
                     max_iterations=200, spring_tol=1e-10)
    assert out is not None
    return out


def test_two_slices_with_a_gap_offset_by_hand():
    # slice i (width b/2): 2 s F_i = r (φ − θ) − Δ_i ≥ 0; slice 0 closes first, slice 1 once 2 s F_0 = Δ
    s, r, e, delta, zones = 2e-6, 45.0, 1e-3, 4e-3, 2
    pts, comp = _one_point(s, r, e, zones)
    spts, scomp = stack_slices(pts, comp, [[0.0], [delta]])
    onset_nm = zones * r * delta / (2.0 * s) * 1e-3  # T* = U r F_0, F_0 = Δ/(2s)
    below = _solve(spts, scomp, 0.5 * onset_nm)
    f0 = 0.5 * onset_nm * 1e3 / zones / r
    np.testing.assert_allclose(below["force"], [f0, 0.0], rtol=1e-12, atol=1e-12 * f0)
    assert below["phi"] == pytest.approx(e / r + 2.0 * s * f0 / r, rel=1e-12)
    above = _solve(spts, scomp, 2.0 * onset_nm)
    tz = 2.0 * onset_nm * 1e3 / zones
    psi = (tz / r + delta / (2.0 * s)) * s / r  # F_0 + F_1 = tz/r, 2s F_0 = rψ, 2s F_1 = rψ − Δ
    assert above["phi"] == pytest.approx(e / r + psi, rel=1e-12)
    np.testing.assert_allclose(above["force"], [r * psi / (2 * s), (r * psi - delta) / (2 * s)], rtol=1e-12)
    # unequal widths, equal gaps: slice i is b/w_i times as compliant, so it carries w_i/b of the load
    spts, scomp = stack_slices(pts, comp, [[0.0], [0.0]], widths_mm=[2.5, 7.5])
    out = _solve(spts, scomp, onset_nm)
    total = onset_nm * 1e3 / zones / r
    np.testing.assert_allclose(out["force"], [0.25 * total, 0.75 * total], rtol=1e-12)
    assert out["phi"] == pytest.approx(e / r + s * total / r, rel=1e-12)


def test_ring_twist_by_hand():
    s, r, e, zones, b = 2e-6, 45.0, 1e-3, 2, 12.0
    c_ring = 3e-10  # rad per N·mm per mm (small enough that both slices stay loaded)
    pts, comp = _one_point(s, r, e, zones, b)
    tz = 40e3
    # one slice: the 2D rotation shifted by T b / (3 G J), T = U tz the gear's torque
    one = _solve(*stack_slices(pts, comp, [[0.0]], ring_compliance_rad_per_nmm=c_ring), tz * zones * 1e-3)
    assert one["phi"] == pytest.approx(e / r + s * tz / r ** 2 + zones * tz * c_ring * b / 3.0, rel=1e-12)
    # two identical slices: 2 s F_i + r² U c Σ_j L_ij F_j = r ψ, L = [[b/6, b/4], [b/4, b/2 + b/6]]
    two = _solve(*stack_slices(pts, comp, [[0.0], [0.0]], ring_compliance_rad_per_nmm=c_ring), tz * zones * 1e-3)
    lmat = np.array([[b / 6.0, b / 4.0], [b / 4.0, b / 2.0 + b / 6.0]])
    a = 2.0 * s * np.eye(2) + r * r * zones * c_ring * lmat
    unit = np.linalg.solve(a, np.ones(2))  # F per unit rψ
    assert np.all(unit > 0.0)
    psi = tz / r / unit.sum() / r
    assert two["phi"] == pytest.approx(e / r + psi, rel=1e-12)
    np.testing.assert_allclose(two["force"], r * psi * unit, rtol=1e-12)
    assert two["force"][0] > two["force"][1]  # the diaphragm end lags less: it carries more


def test_ring_kernel_is_its_double_integral():
    b = 18.0
    g = (np.arange(400) + 0.5) / 400  # midpoint rule on each cell, exact to O(h²) for min(ζ, ζ′)
    for nodes, n in (("midpoint", 3), ("ends", 4)):
        zeta, w = slice_layout(b, n, nodes)
        assert w.sum() == pytest.approx(b, rel=1e-14)
        lo = np.r_[0.0, np.cumsum(w)[:-1]]
        assert np.all((zeta >= lo - 1e-12) & (zeta <= lo + w + 1e-12))  # each node inside its cell
        kern = ring_twist_kernel(w)
        for i in range(n):
            for j in range(n):
                zi, zj = lo[i] + g * w[i], lo[j] + g * w[j]
                assert kern[i, j] == pytest.approx(np.minimum.outer(zi, zj).mean(), rel=1e-5)
        assert w @ kern @ w / b ** 2 == pytest.approx(b / 3.0, rel=1e-14)  # an even load: the curve's b/3
    np.testing.assert_allclose(slice_layout(b, 4, "ends")[0], [0.0, 6.0, 12.0, 18.0])
    with pytest.raises(FaceCurveError, match="widths_mm"):
        ring_twist_kernel([1.0, 0.0])
    with pytest.raises(FaceCurveError, match="nodes"):
        slice_layout(b, 3, "gauss")


def test_coupling_matrix_against_face_load_and_an_even_load():
    b, lam = 20.0, 3.0
    zeta, w = slice_layout(b, 5)
    # equal cells: face_load's kernel (its own implementation), N (I + (λ/Δz)² L)⁻¹
    np.testing.assert_allclose(slice_coupling_matrix(zeta, w, lam), slice_coupling(5, lam, b / 5), rtol=1e-12)
    np.testing.assert_allclose(slice_coupling_matrix(zeta, w), np.diag(b / w), rtol=1e-15)
    # face-end cells: an even line load (P ∝ w) deflects every slice alike, as the whole face under the total
    zeta, w = slice_layout(b, 6, "ends")
    k = slice_coupling_matrix(zeta, w, lam)
    np.testing.assert_allclose(k @ (w / b), np.ones(6), rtol=1e-12)
    assert np.all(np.linalg.eigvalsh(k) > 0.0)
    with pytest.raises(FaceCurveError, match="coupling_length_mm"):
        slice_coupling_matrix(zeta, w, -1.0)


class _Hertz:
    """A bearing of Hertz coefficient c_H (mm/N^(2/3)): δ = c_H Q^(2/3) at one ball."""

    def __init__(self, c_hertz):
        self.c = c_hertz

    def hertz_coefficient(self):
        return self.c


def test_a_ball_is_one_body_across_the_slices():
    # one tooth point on a rim that presses into one ball: flexibility per unit width
    # [[a, m], [m, k]] (tooth, ball seat), the ball closed at zero gap, a Hertz bearing c_H
    a, m, k, b, r, e, zones, c_h = 2e-5, -1e-5, 1e-5, 10.0, 45.0, 1e-3, 2, 1e-5
    flex = np.array([[a / b]])
    pts = _one_point(a / b, r, e, zones, b)[0]
    comp = ContactCompliance(
        matrix_mm_per_n=flex, fs_matrix_mm_per_n=flex, cs_matrix_mm_per_n=np.zeros((1, 1)), face_width_mm=b,
        tooth=np.array([0]), ball_angle_rad=np.array([0.0]), ball_active=np.array([True]), wrap_half_angle_rad=0.5,
        wrap_source="test", dof={}, time_s={}, mesh={}, _flex_cc=np.array([[a]]), _flex_cb=np.array([[m]]),
        _flex_bb=np.array([[k]]), ball_supports="all", ball_gap_mm=np.array([0.0]))
    torque = 9.0  # N·m: tz = 4.5e3 N·mm, F = 100 N
    f0 = torque * 1e3 / zones / r
    # slice 1 held off by its gap: slice 0 (width b/2, flexibility ×2) carries F and meets the whole
    # ball, 2 m F/b + 2 k R/b + c_H R^(2/3) = 0 — not a half ball under 2R (c_H (2R)^(2/3))
    from scipy.optimize import brentq

    def reaction(share):
        return brentq(lambda q: 2 * m * f0 / b + 2 * k * q / b + c_h * (share * q) ** (2 / 3), 1e-9, 1e4, xtol=1e-14)

    whole, halved = reaction(1.0), reaction(2.0)
    assert halved < 0.95 * whole  # the two laws differ here
    out = _solve(*stack_slices(pts, comp, [[0.0], [0.05]]), torque, _Hertz(c_h))
    np.testing.assert_allclose(out["force"], [f0, 0.0], rtol=1e-12)
    np.testing.assert_allclose(out["reactions"], [whole, 0.0], rtol=1e-9)
    assert out["phi"] == pytest.approx(e / r + (2 * a * f0 + 2 * m * whole) / (b * r), rel=1e-9)
    # the idle slice's share: the ball has moved away from it by its approach under the whole load
    assert out["ball_gap"][1] == pytest.approx(c_h * whole ** (2 / 3), rel=1e-9)
    # equal slices, no offset: each half carries half and the ball the whole — the 2D section
    one = _solve(*stack_slices(pts, comp, [[0.0]]), torque, _Hertz(c_h))
    two = _solve(*stack_slices(pts, comp, [[0.0], [0.0]]), torque, _Hertz(c_h))
    assert two["phi"] == pytest.approx(one["phi"], rel=1e-9)
    np.testing.assert_allclose(two["reactions"], 0.5 * one["reactions"][0], rtol=1e-9)


def test_local_fraction_of_a_far_field_plus_a_tooth_block():
    # a rim far field smooth in the tooth offset (A − B Δ², which the parabola through ±1, ±2 gives
    # back exactly) plus a local part L on each tooth's own block: f = L / (A + L)
    from types import SimpleNamespace

    a, bb, loc = 4e-6, 8e-9, 1.5e-6
    tooth = np.repeat(np.arange(-6, 7), 3)
    dt = tooth[:, None] - tooth[None, :]
    s = a - bb * dt ** 2 + np.where(dt == 0, loc, 0.0)
    f = local_fraction(SimpleNamespace(tooth=tooth), SimpleNamespace(fs_matrix_mm_per_n=s))
    assert f == pytest.approx(loc / (a + loc), rel=1e-12)
    # no point with teeth ±1 and ±2 on both sides: nothing to split
    assert local_fraction(SimpleNamespace(tooth=np.array([0, 1, 2])),
                         SimpleNamespace(fs_matrix_mm_per_n=np.eye(3))) == 0.0


def test_rim_coupling_length_is_the_shells_decay_length():
    # a cylindrical shell's bending boundary layer decays as exp(−z/L), L = √(r δ) / (3(1 − ν²))^(1/4)
    from types import SimpleNamespace

    gs = SimpleNamespace(gear=SimpleNamespace(neutral_radius_mm=50.0, rim_thickness_mm=1.0),
                         material=SimpleNamespace(poisson_ratio=0.3))
    assert rim_coupling_length_mm(gs) == pytest.approx(math.sqrt(50.0) / 1.2854, rel=1e-4)


# --------------------------------------------------------------------------- on a design


@pytest.fixture(scope="module")
def design():
    gs = pg.load_gearset(pg.default_gearset_path())
    return pg.design(gs, scene="sketch", contact=False, stress=False)


@pytest.fixture(scope="module")
def curve_2d(design):
    return torsional_curve(design, TORQUES, stations=3)


def test_identical_slices_are_the_2d_curve(design, curve_2d):
    chain = compliance_chain(design.gearset)
    b_face = float(design.gearset.cup.face_width_mm)
    _, c_ring = slice_chain(chain, [b_face], b_face)
    ring = float(design.gearset.cup.face_width_mm) / 3.0 * c_ring * 1e3  # rad per N·m: the curve's b/3 of ring
    for spec, ring_in_mesh in ((FaceSlices(3, "none", ring_twist=False), 0.0), (FaceSlices(1, "none"), ring),
                               (FaceSlices(3, "none", ring_twist=False, nodes="ends", coupling_length_mm=4.0), 0.0)):
        c = torsional_curve(design, TORQUES, sides=curve_2d.sides, face_slices=spec)
        # rigid balls: exact (one slice with the ring: the ring's series term moved into the mesh)
        np.testing.assert_allclose(c.mesh_rad, curve_2d.mesh_rad + ring_in_mesh * np.asarray(TORQUES), rtol=1e-9)
        # the springs' fixed point to its tolerance (1e-5 on each spring)
        np.testing.assert_allclose(c.rotation_rad, curve_2d.rotation_rad, rtol=2e-6)
        assert c.lost_motion_rad["total"] == pytest.approx(curve_2d.lost_motion_rad["total"], rel=2e-6)
        assert c.warnings == curve_2d.warnings


def test_thickness_offset_is_a_tangential_move(design, curve_2d):
    pts = curve_2d.sides[1][0]
    motion = ContactInput.from_design(design).motion
    # thicker by Δs: each loaded-flank point's first-contact angle falls by ≈ Δs/2 / r_pitch ... exactly −n·(Δs/2 e_t)
    d = flank_offset_gap_mm(pts, motion, 2e-3)
    assert np.all(d < 0.0)
    np.testing.assert_allclose(flank_offset_gap_mm(pts, motion, -2e-3), -d, rtol=1e-9)
    # the normal's component along e_t bounds it: |Δe| ≤ Δs/2
    assert np.all(np.abs(d) <= 1e-3 * (1 + 1e-12))
    # the slices' separations are exact: each material point's signed distance to the CS outline,
    # the tooth moved by Δs(z)/2 per flank (slice 0 thinner, slice 1 thicker)
    b = float(design.gearset.cup.face_width_mm)
    _, none = slice_gap_shifts(design, pts, 2, coning="none")
    assert np.all(none == 0.0)  # the design section's own tooth in every slice: nothing moves
    near = pts.gap_mm < 0.01
    for taper in (4e-4, 5e-5):
        ds = taper * np.array([-b / 4, b / 4])
        _, de = slice_gap_shifts(design, pts, 2, coning="none", modification=(taper, 0.0))
        # a distance is 1-Lipschitz: a point moved by |Δs|/2 changes its separation by at most that
        assert np.all(np.abs(de) <= 0.5 * np.abs(ds)[:, None] * (1 + 1e-9))
        assert np.all(de[0, near] > 0.0) and np.all(de[1, near] < 0.0)  # thinner opens, thicker closes
    # small moves: the first-order shift −n·Δp, to within the angle between the pair's normal and
    # the CS outline's at the foot (2.8 % measured near contact on this set)
    lin = np.outer(ds, flank_offset_gap_mm(pts, motion, 1.0))
    assert np.max(np.abs(de - lin)[:, near]) <= 0.05 * np.max(np.abs(lin)[:, near])


@pytest.fixture(scope="module")
def coned(design, curve_2d):
    """Two slices with semi-membrane coning, stacked, and the per-slice solve at 100 N·m."""
    spec = FaceSlices(2, "semi_membrane", coupling_length_mm=0.0)  # independent slices (the rim coupled: below)
    gs = design.gearset
    chain = compliance_chain(gs)
    sides, new_chain, _ = spec.apply(design, curve_2d.sides, chain)
    pts, comp = sides[1]
    out = _solve(pts, comp, 100.0, new_chain.bearing)
    return spec, sides, new_chain, out


def test_equilibrium_and_complementarity_in_every_slice(design, curve_2d, coned):
    spec, sides, chain, out = coned
    pts2, comp2 = curve_2d.sides[1]
    _, de = slice_gap_shifts(design, pts2, 2, coning="semi_membrane")
    n, nb, ns = pts2.count, comp2.ball_angle_rad.size, 2
    b = float(comp2.face_width_mm) / ns
    tz = 100.0e3 / pts2.zones
    force, react, phi = out["force"].reshape(ns, n), out["reactions"].reshape(ns, nb), out["phi"]
    springs = np.exp(out["log_springs"]).reshape(ns, nb)
    r = np.asarray(pts2.lever_mm)
    c_ring = chain.part("cup_wall").parameters["ring_compliance_rad_per_nmm2"]
    kern = ring_twist_kernel(np.full(ns, float(comp2.face_width_mm) / ns))
    moment = force @ r
    gap_b = np.asarray(comp2.ball_gap_mm)
    cc = 0.5 * (comp2._flex_cc + comp2._flex_cc.T)
    ring = np.asarray(comp2.cs_ring_mm_per_n)  # the CS ring: one body across the face
    sector = comp2.cs_matrix_mm_per_n - ring
    assert np.abs(ring).max() > 0.1 * np.abs(sector).max()  # the ring is there and not negligible
    assert moment.sum() == pytest.approx(tz, rel=1e-12)
    assert np.all(moment > 0.0)  # both slices carry at 100 N·m
    for i in range(ns):
        # from the 2D compliance's own blocks, slice width b: teeth, balls, the CS sector ×N, the CS
        # ring's ovalisation under every slice's forces, the tooth ring's twist
        twist = pts2.zones * c_ring * float(kern[i] @ moment)
        g = r * ((pts2.gap_mm + de[i]) / r - phi + twist) + cc @ force[i] / b \
            + ns * sector @ force[i] + ring @ force.sum(axis=0) + comp2._flex_cb @ react[i] / b
        act = react[i] > 0.0
        # every slice's copy of a ball is a share of that ball: its spring carries the shares' sum
        h = gap_b + comp2._flex_cb.T @ force[i] / b + comp2._flex_bb @ react[i] / b + springs[i] * react.sum(axis=0)
        scale = float(np.abs(g).max())
        assert np.all(force[i] >= 0.0) and np.all(react[i] >= 0.0)
        assert g.min() >= -1e-9 * scale and np.abs(force[i] * g).max() <= 1e-9 * scale * force.max()
        assert h.min() >= -1e-9 * scale and np.abs(react[i] * h).max() <= 1e-9 * scale * react.max()
        # each loaded ball's spring is the Hertz secant of the whole ball at its shares' summed reaction
        # (floored at max(1 N, 1e-3 × the largest), where the secant → ∞: contact.reduced.SpringIteration)
        total = react.sum(axis=0)
        q = np.maximum(total[act], max(1.0, 1e-3 * total.max()))
        np.testing.assert_allclose(springs[i][act], chain.bearing.hertz_coefficient() * q ** (-1 / 3), rtol=2e-5)


def test_the_rim_coupled_slices_in_equilibrium_and_complementary(design, curve_2d):
    # the same two coned slices with the rim coupled along the face (λ = 6 mm): recomputed from the
    # 2D blocks, the local part (f of each tooth's own block) per slice, the rim's far field and the
    # balls' seats through K = b (W + λ² L_h)⁻¹, the CS per slice
    spec = FaceSlices(2, "semi_membrane", coupling_length_mm=6.0)
    chain = compliance_chain(design.gearset)
    sides, chain, _ = spec.apply(design, curve_2d.sides, chain)
    pts, comp = sides[1]
    out = _solve(pts, comp, 100.0, chain.bearing)
    pts2, comp2 = curve_2d.sides[1]
    _, de = slice_gap_shifts(design, pts2, 2, coning="semi_membrane")
    n, nb, ns, b = pts2.count, comp2.ball_angle_rad.size, 2, float(comp2.face_width_mm)
    zeta, w = slice_layout(b, ns)
    k = slice_coupling_matrix(zeta, w, 6.0)
    assert k[0, 1] > 0.0  # coupled
    f = local_fraction(pts2, comp2)
    assert 0.05 < f < 0.6
    same = pts2.tooth[:, None] == pts2.tooth[None, :]
    local = np.where(same, f * b * comp2.fs_matrix_mm_per_n, 0.0)
    rim = comp2._flex_cc - local
    force, react, phi = out["force"].reshape(ns, n), out["reactions"].reshape(ns, nb), out["phi"]
    springs = np.exp(out["log_springs"]).reshape(ns, nb)
    r = np.asarray(pts2.lever_mm)
    c_ring = chain.part("cup_wall").parameters["ring_compliance_rad_per_nmm2"]
    kern = ring_twist_kernel(w)
    moment = force @ r
    ring = np.asarray(comp2.cs_ring_mm_per_n)
    sector = comp2.cs_matrix_mm_per_n - ring
    assert moment.sum() == pytest.approx(100.0e3 / pts2.zones, rel=1e-12)
    for i in range(ns):
        twist = pts2.zones * c_ring * float(kern[i] @ moment)
        g = r * ((pts2.gap_mm + de[i]) / r - phi + twist) + (b / w[i]) * (local @ force[i]) / b \
            + sum(k[i, j] * (rim @ force[j] + comp2._flex_cb @ react[j]) for j in range(ns)) / b \
            + (b / w[i]) * sector @ force[i] + ring @ force.sum(axis=0)
        h = np.asarray(comp2.ball_gap_mm) + springs[i] * react.sum(axis=0) \
            + sum(k[i, j] * (comp2._flex_cb.T @ force[j] + comp2._flex_bb @ react[j]) for j in range(ns)) / b
        scale = float(np.abs(g).max())
        assert np.all(force[i] >= 0.0) and np.all(react[i] >= 0.0)
        assert g.min() >= -1e-9 * scale and np.abs(force[i] * g).max() <= 1e-9 * scale * force.max()
        assert h.min() >= -1e-9 * scale and np.abs(react[i] * h).max() <= 1e-9 * scale * react.max()
    # the coupled rim resists the slices' differential deflection: the gear turns less under the same
    # torque than with independent slices (and the load follows the coning's gaps more unevenly)
    alone = _solve(*FaceSlices(2, "semi_membrane", coupling_length_mm=0.0).apply(design, curve_2d.sides,
                                                                                 compliance_chain(design.gearset))[0][1],
                   100.0, chain.bearing)
    assert out["phi"] < alone["phi"]


def test_continuation_against_lemke_with_coning(design, curve_2d, coned):
    spec, sides, chain, out = coned
    pts, comp = sides[1]
    shift = float(pts.theta_rad.min())
    assert shift < 0.0  # semi-membrane coning closes some slice gaps below zero
    tz = 100.0e3 / pts.zones
    # Lemke from scratch on the stacked teeth and balls, at the continuation's converged springs
    sol, react, _ = comp._solve_unilateral(pts.theta_rad - shift, pts.lever_mm, tz, np.exp(out["log_springs"]))
    assert float(sol.phi_rad) + shift == pytest.approx(out["phi"], rel=1e-9)
    np.testing.assert_allclose(sol.force_n, out["force"], rtol=1e-7, atol=1e-7 * out["force"].max())
    np.testing.assert_allclose(react, out["reactions"], rtol=1e-7, atol=1e-7 * out["reactions"].max())
    # rigid balls: the continuation's own rigid solve against Lemke
    rigid = _solve(pts, comp, 100.0)
    sol, _, _ = comp._solve_unilateral(pts.theta_rad - shift, pts.lever_mm, tz, None)
    assert float(sol.phi_rad) + shift == pytest.approx(rigid["phi"], rel=1e-9)
    # coning spreads the first contacts: softer at T1 than the even spread
    c = torsional_curve(design, TORQUES, sides=curve_2d.sides, face_slices=spec)
    assert c.k_nm_per_rad["total"]["positive"]["K1"] < curve_2d.k_nm_per_rad["total"]["positive"]["K1"]


def test_bad_input_named():
    with pytest.raises(FaceCurveError, match="face_slices"):
        FaceSlices.of(0)
    with pytest.raises(FaceCurveError, match="face_slices"):
        FaceSlices.of(2.5)
    with pytest.raises(FaceCurveError, match="coning"):
        FaceSlices(2, "conical")
    pts, comp = _one_point()
    with pytest.raises(FaceCurveError, match="ball_supports"):
        stack_slices(pts, dataclasses.replace(comp, ball_supports="window"), [[0.0]])
    with pytest.raises(FaceCurveError, match="gap_shift"):
        stack_slices(pts, comp, [[0.0, 1.0]])
    with pytest.raises(FaceCurveError, match="face_width_mm"):
        slice_chain(compliance_chain(pg.load_gearset(pg.default_gearset_path())), [1.0], -1.0)
    with pytest.raises(FaceCurveError, match="widths_mm"):
        stack_slices(pts, comp, [[0.0], [0.0]], widths_mm=[5.0, 4.0])


def test_the_slices_are_kept_for_a_torque_change_inside_an_engine(design, curve_2d, coned):
    """The slices read no torque: inside an engine's design the second apply on the same flanks,
    design and modification takes the first's stacked flanks (the same objects, as a plain apply
    makes them); another modification (a different owner) stacks them again."""
    from profilegen.pipeline.engine import Engine, _Run
    from profilegen.stagecache import STAGE_CACHE

    spec, plain, _, _ = coned
    chain = compliance_chain(design.gearset)
    engine = Engine()
    token = STAGE_CACHE.set(_Run(engine, engine._generation))
    try:
        first, _, w1 = spec.apply(design, curve_2d.sides, chain)
        again, chain2, w2 = spec.apply(design, curve_2d.sides, chain)
        other, _, _ = dataclasses.replace(spec, modification=(1e-4, 0.0)).apply(design, curve_2d.sides, chain)
    finally:
        STAGE_CACHE.reset(token)
    assert engine.runs["face_slices"] == 2 and engine.hits["face_slices"] == 1
    assert all(again[s][k] is first[s][k] for s in (1, -1) for k in (0, 1)) and w1 == w2
    assert other[1][0] is not first[1][0]
    assert not np.array_equal(other[1][0].gap_mm, first[1][0].gap_mm)  # the modification moves the gaps
    for s in (1, -1):  # what a plain apply (no engine) makes
        np.testing.assert_array_equal(first[s][0].gap_mm, plain[s][0].gap_mm)
        np.testing.assert_array_equal(first[s][1].matrix_mm_per_n, plain[s][1].matrix_mm_per_n)
    b = float(design.gearset.cup.face_width_mm)  # the sliced chain is made afresh either way
    widths = slice_layout(b, spec.slices, spec.nodes, 0.5 * b)[1]
    assert chain2.series_compliance_rad_per_nm == slice_chain(chain, widths, b)[0].series_compliance_rad_per_nm


def test_rigid_ball_pieces_kept_by_the_ball_set(curve_2d):
    """ReducedZone._balls with rigid balls depends on the ball set alone: the same set again gives
    the same (read-only) arrays, equal to a fresh computation; another set its own; with springs
    nothing is kept."""
    pts, comp = curve_2d.sides[1]
    zone = ReducedZone(pts, comp, None)
    active = np.asarray(comp.ball_active, bool)
    first, again = zone._balls(active, None), zone._balls(active.copy(), None)
    assert all(x is y for x, y in zip(first, again))
    assert not first[1].flags.writeable
    for x, y in zip(first, zone._balls_made(active, None)):
        np.testing.assert_array_equal(x, y)
    fewer = active.copy()
    fewer[np.flatnonzero(active)[0]] = False
    assert zone._balls(fewer, None)[1].shape[0] == first[1].shape[0] - 1
    springs = np.full(active.size, 1e-6)
    assert zone._balls(active, springs)[1] is not zone._balls(active, springs)[1]
