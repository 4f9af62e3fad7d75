"""Candidates for the compliance the whole-gear model leaves out (issue 16), each against an
analytic case: the CS ring on an elastic foundation (the housing), the wave-generator
bearing's radial clearance; and the catalogue row they are compared with."""

from __future__ import annotations

import math

import numpy as np
import pytest

from profilegen.contact.catalogue import CatalogueError, catalogue_row
from research.bearing_clearance import (
    ClearanceError, clearance_ball_gaps_mm, iso5753_radial_clearance_um, radial_load_with_clearance_n)
from tests.oracles.cs_ring import (
    CSRing, CSRingError, bolted_flange_foundation, cs_ring_compliance, housing_ring_foundation)

E = 2.0e5


def test_ring_on_a_stiff_foundation_is_hetenyis_beam_under_a_point_load():
    """A large ring (βR ≫ 1) on a radial Winkler foundation k under a radial point force P
    deflects under it as an infinite beam on an elastic foundation: w = Pβ/(2k), β =
    (k/4EI)^¼ (Hetényi) — an independent solution (the beam's, not the ring's modes); the
    zone copy at π is e^{−βπR} away."""
    r, t, w, k = 1000.0, 5.0, 10.0, 1.0e3
    ring = CSRing(r - t / 2, r + t / 2, w, E).held(k, 0.0)
    beta = (k / (4.0 * E * w * t ** 3 / 12.0)) ** 0.25
    assert beta * r > 50
    s = cs_ring_compliance(ring, [[0.0, r]], [[0.0, 1.0]], harmonics=4000)
    assert s[0, 0] == pytest.approx(beta / (2.0 * k), rel=2e-3)
    # the free ring is softer, a stiffer foundation stiffer (the bracket free ≥ held ≥ rigid)
    free = cs_ring_compliance(CSRing(r - t / 2, r + t / 2, w, E), [[0.0, r]], [[0.0, 1.0]], harmonics=400)
    stiff = cs_ring_compliance(ring.held(100 * k, 0.0), [[0.0, r]], [[0.0, 1.0]], harmonics=4000)
    assert free[0, 0] > s[0, 0] > stiff[0, 0] > 0.0


def test_ovalisation_mode_on_a_foundation_and_the_housing_ring():
    """A load p₂cos 2θ (radial) on a ring on a foundation (k_r, k_t) deflects
    w₂ = R⁴p₂/(9EI + R⁴(k_r + k_t/4)) (the mode's energy); a tangential t₂ sin 2θ gives
    v = R⁴t₂/4 / (…) sin 2θ. A housing ring bending with the CS (housing_ring_foundation) is
    the same as the CS ring with EI + EI_h in that mode."""
    r, t, w = 60.0, 12.0, 20.0
    ring = CSRing(r - t / 2, r + t / 2, w, E).held(300.0, 700.0)
    ei = E * w * t ** 3 / 12.0
    th = math.pi * np.arange(12) / 12  # one zone's half; the U = 2 copies make 24 points round the ring
    e_r, e_t = np.column_stack([np.sin(th), np.cos(th)]), np.column_stack([np.cos(th), -np.sin(th)])
    den = 9 * ei + r ** 4 * (300.0 + 700.0 / 4)
    p2 = 24 / (2 * math.pi * r)  # unit point forces cos 2θ_j, 24 round the ring: line load amplitude
    radial = cs_ring_compliance(ring, r * e_r, e_r, harmonics=2) @ np.cos(2 * th)
    np.testing.assert_allclose(radial, r ** 4 * p2 / den * np.cos(2 * th), rtol=1e-12, atol=1e-15)
    tang = cs_ring_compliance(ring, r * e_r, e_t, harmonics=2) @ np.sin(2 * th)
    np.testing.assert_allclose(tang, r ** 4 * p2 / 4 / den * np.sin(2 * th), rtol=1e-12, atol=1e-15)
    bare = CSRing(r - t / 2, r + t / 2, w, E)
    housed = bare.held(housing_ring_foundation(bare, 8.0), 0.0)
    thick = CSRing(r - t / 2, r + t / 2, w, E * (1.0 + (8.0 / t) ** 3))  # EI + EI_h, same radius
    a = cs_ring_compliance(housed, r * e_r, e_r, harmonics=2)
    b = cs_ring_compliance(thick, r * e_r, e_r, harmonics=2)
    area = w * t  # the hoop mode n = 0 (w₀ = p₀/(EA/R² + k_r), U = 2 copies) differs: take it out of both
    hoop_a = 2 / (2 * math.pi * r * (E * area / r ** 2 + housed.foundation_radial_n_per_mm2))
    hoop_b = 2 / (2 * math.pi * r * (thick.youngs_modulus_mpa * area / r ** 2))
    np.testing.assert_allclose(a - hoop_a, b - hoop_b, rtol=1e-10)
    assert bolted_flange_foundation(16, 2e5, 62.0) == pytest.approx(16 * 2e5 / (2 * math.pi * 62.0))
    with pytest.raises(CSRingError, match="foundation_radial_n_per_mm2"):
        bare.held(-1.0)
    with pytest.raises(CSRingError, match="bolts"):
        bolted_flange_foundation(0, 2e5, 62.0)


def test_bearing_clearance_stribeck_and_the_onset():
    """Z balls, Hertz Q = (δ/c_H)^{3/2}: without clearance Z·Q_max/F_r → 4.37 (Stribeck,
    1/J_r(½)); with a clearance c_r nothing is carried until δ_r = c_r/2, and past it the
    load is the clearance-free one at δ_r − c_r/2 on the top ball."""
    ch = 1e-3  # mm/N^(2/3)
    fr, q = radial_load_with_clearance_n(0.01, 0.0, 200, ch)
    assert 200 * q.max() / fr == pytest.approx(1 / 0.2288, rel=2e-3)
    c = 0.02
    below, _ = radial_load_with_clearance_n([0.0, 0.5 * c - 1e-9], c, 23, ch)
    assert np.all(below == 0.0)
    _, q1 = radial_load_with_clearance_n(0.5 * c + 0.004, c, 23, ch)
    assert q1.max() == pytest.approx((0.004 / ch) ** 1.5)
    # the gaps the contact takes: c_r/2 added outside the window, the window's balls held at 0
    np.testing.assert_allclose(clearance_ball_gaps_mm([0.0, 0.0, 1.9e-4, 1.07e-3], 0.02),
                               [0.0, 0.0, 0.01019, 0.01107])
    assert iso5753_radial_clearance_um(70.9, "Normal") == (10.0, 30.0)
    assert iso5753_radial_clearance_um(60.0, "C3") == (23.0, 43.0)
    with pytest.raises(ClearanceError, match="bore_mm"):
        iso5753_radial_clearance_um(300.0)
    with pytest.raises(ClearanceError, match="radial_clearance_mm"):
        clearance_ball_gaps_mm([0.0], -0.01)


def test_catalogue_rows_for_ratio_80_and_above_are_stiffer_and_sourced():
    """The ≥ 80 rows (CHA table 50.3/50.4) hold the catalogue's own trend — stiffer than
    ratio 50 at every size, same T1/T2 — and the definitions: secant at T2 from K1, K2."""
    for size in (25, 32, 40):
        hi, lo = catalogue_row(size, 100), catalogue_row(size, 50)
        assert hi["ratio"] == 80 and lo["ratio"] == 50 and lo["note"] is None and "ratio 100" in hi["note"]
        assert (hi["T1_nm"], hi["T2_nm"]) == (lo["T1_nm"], lo["T2_nm"])
        assert hi["K1_nm_per_rad"] > lo["K1_nm_per_rad"] and hi["K2_nm_per_rad"] > lo["K2_nm_per_rad"]
        assert "1018854" in hi["source"] and "component set" in hi["values_of"]
    row = catalogue_row(40, 80)
    assert row["note"] is None and (row["K1_nm_per_rad"], row["K2_nm_per_rad"], row["K3_nm_per_rad"]) == (13e4, 20e4, 23e4)
    with pytest.raises(CatalogueError, match="ratio"):
        catalogue_row(40, 20)


def test_race_axial_flexure_is_two_cantilevers_under_an_even_load():
    """c_ax = b³/(320 EI): the load-weighted mean deflection of a beam of length b under an
    even load Q/b held at mid-length, by integrating M/EI twice (trapezoids), divided by Q."""
    from research.race_flexure import RaceFlexureError, race_axial_flexure_compliance_mm_per_n

    b, s, hr, hf, nu = 20.0, 12.7, 2.5, 1.45, 0.3
    ei = E / (1 - nu * nu) * s * (hr ** 3 + hf ** 3) / 12.0
    q, n = 1.0 / b, 4001  # unit ball load
    x = np.linspace(0.0, 0.5 * b, n)  # from the ball out to a face end
    moment = 0.5 * q * (0.5 * b - x) ** 2
    slope = np.concatenate([[0.0], np.cumsum(0.5 * (moment[1:] + moment[:-1]) * np.diff(x))]) / ei
    w = np.concatenate([[0.0], np.cumsum(0.5 * (slope[1:] + slope[:-1]) * np.diff(x))])
    mean = np.sum(0.5 * (w[1:] + w[:-1]) * np.diff(x)) / (0.5 * b)
    assert race_axial_flexure_compliance_mm_per_n(b, s, hr, hf, E, nu) == pytest.approx(mean, rel=1e-5)
    with pytest.raises(RaceFlexureError, match="race_thickness_mm"):
        race_axial_flexure_compliance_mm_per_n(b, s, 0.0, 0.0, E)


def test_clearance_and_housing_enter_the_contact_as_the_chain_would_take_them():
    """with_clearance_and_housing on the default set (sketch design, every ball one-sided):
    the gaps grow by c_r/2 outside the window only, the CS block by exactly the ring's S; a
    clearance far larger than any ball travel gives the window's answer (the window model
    solved by its own settling loop), and each candidate softens the mesh."""
    import profilegen as pg
    from profilegen.contact import ContactInput, contact_points
    from profilegen.contact.analysis import solve_contact
    from research.bearing_clearance import with_clearance_and_housing
    from profilegen.contact.compliance import ContactCompliance

    gs = pg.load_gearset(pg.default_gearset_path())
    inputs = ContactInput.from_design(pg.design(gs, scene="sketch", contact=False, stress=False))
    pts = contact_points(inputs)
    build = dict(wrap_half_angle_rad=1.0)
    every = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                    ball_supports="all", **build, cs_ring=False)
    window = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm, **build, cs_ring=False)
    ring = CSRing.from_gearset(gs).held(500.0)
    both = with_clearance_and_housing(every, pts, gs, radial_clearance_mm=0.02, cs_ring=ring)
    np.testing.assert_array_equal(both.ball_gap_mm, np.where(every.ball_gap_mm > 0, every.ball_gap_mm + 0.01, 0.0))
    s_ring = cs_ring_compliance(ring, pts.cs_point_mm, pts.normal, zones=pts.zones)
    np.testing.assert_allclose(both.cs_matrix_mm_per_n - every.cs_matrix_mm_per_n, s_ring, rtol=1e-12, atol=1e-18)
    torque = 100.0

    def phi(comp):
        return comp.solve_unilateral(pts.theta_rad, pts.lever_mm, torque / pts.zones * 1e3)[0].phi_rad

    loose = with_clearance_and_housing(every, pts, gs, radial_clearance_mm=2.0)
    ref = solve_contact(inputs, [torque], points=pts, compliance=window).cases[0].rotation_rad
    assert phi(loose) == pytest.approx(ref, rel=1e-9)
    p0 = phi(every)
    p_gap = phi(with_clearance_and_housing(every, pts, gs, radial_clearance_mm=0.02))
    p_ring = phi(with_clearance_and_housing(every, pts, gs, cs_ring=ring))
    assert p0 < p_gap < phi(loose) and p0 < p_ring < phi(both)
    with pytest.raises(ClearanceError, match="radial_clearance_mm"):
        with_clearance_and_housing(window, pts, gs, radial_clearance_mm=0.01)
