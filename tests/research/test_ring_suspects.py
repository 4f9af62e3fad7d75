"""research/ring_suspects.py against thin-ring theory (Roark) and its own hand bounds."""

from __future__ import annotations

import math

import numpy as np
import pytest

from profilegen.contact.ratchet import cs_ring_radial_compliance
from research.ring_suspects import (
    Holes, Ring, annulus_mode_compliance, holed_ring_bounds, plug_ring, thin_ring_mode_compliance)

THIN = Ring(99.0, 101.0, 1.0, 2.0e5, 0.3)


def test_thin_ring_coefficient_is_roarks_two_opposite_loads():
    # Roark, Formulas for Stress and Strain, 7th ed., table 9.2 case 1: two opposite loads P on a
    # thin ring shorten the diameter between them by P R³/(E I) (π/4 − 2/π); half of it at each load
    # is the even bending harmonics of both loads
    r = Ring(95.0, 105.0, 4.0, 2.0e5)
    ei = r.youngs_modulus_mpa * r.width_mm * r.thickness_mm ** 3 / 12.0
    bending = 2.0 * sum(thin_ring_mode_compliance(r, n) for n in range(2, 4001, 2))
    assert bending == pytest.approx(0.5 * r.mean_radius_mm ** 3 / ei * (math.pi / 4 - 2 / math.pi), rel=1e-6)
    # and the climb's matrix (the same free ring, with its n = 0 term)
    w = cs_ring_radial_compliance([0.0, math.pi], [0.0], mean_radius_mm=100.0, thickness_mm=10.0, width_mm=4.0,
                                  youngs_modulus_mpa=2.0e5, harmonics=4000).sum()
    extension = 2.0 * r.mean_radius_mm / (r.youngs_modulus_mpa * r.width_mm * r.thickness_mm) / (2 * math.pi)
    assert w == pytest.approx(bending + extension, rel=1e-6)


@pytest.mark.parametrize("loaded", ["inner", "outer"])
@pytest.mark.parametrize("n", [2, 4])
def test_fem_annulus_tends_to_the_thin_ring(loaded, n):
    ring = Ring(THIN.inner_radius_mm, THIN.outer_radius_mm, 1.0, 2.0e5, 0.3, loaded)
    fem = annulus_mode_compliance(ring, n, n_radial=2, n_theta=48)
    assert fem == pytest.approx(thin_ring_mode_compliance(ring, n), rel=5e-3)


def test_a_thick_ring_is_softer_than_thin_theory_in_mode_2_and_more_so_in_mode_4():
    # shear and the curved section soften a thick ring, more for shorter waves
    ring = Ring(41.5, 52.0, 16.0, 2.09e5, 0.295)
    f2 = annulus_mode_compliance(ring, 2, n_radial=4, n_theta=48) / thin_ring_mode_compliance(ring, 2)
    f4 = annulus_mode_compliance(ring, 4, n_radial=4, n_theta=48) / thin_ring_mode_compliance(ring, 4)
    assert 1.0 < f2 < 1.1 < f4


def test_holes_lie_between_the_hand_bounds_and_vanish_when_small():
    ring = Ring(41.5, 52.0, 16.0, 2.09e5, 0.295)
    holes = Holes(16, 6.3, ring.mean_radius_mm)
    lo, hi = holed_ring_bounds(ring, holes)
    solid = annulus_mode_compliance(ring, n_radial=8, n_theta=192)
    holed = annulus_mode_compliance(ring, holes=holes, n_radial=8, n_theta=192)
    assert 1.0 < lo < holed / solid < hi
    # a hair-thin hole: the composite section is whole; the ligament bound splits the ring at the
    # one sample on the cut (I₀/I = 4 there: two halves), nowhere else
    lo, hi = holed_ring_bounds(ring, Holes(16, 1e-6, ring.mean_radius_mm), samples=4001)
    assert lo == pytest.approx(1.0, abs=1e-9)
    assert hi == pytest.approx(1.0 + 3.0 / 4001, rel=1e-9)


def test_holes_composite_bound_by_hand():
    # one hole as wide as the ring's pitch would be a slot everywhere: the section with the chord c
    # cut out of its middle has I = b (h³ − c³)/12 at the hole's centre line; with holes of a tiny
    # angular extent the mean tends to 1 + (fraction of the circumference) × (I₀/I − 1) — here the
    # exact mean over one hole is checked against a direct quadrature of the centred chord
    ring = Ring(90.0, 110.0, 1.0, 2.0e5)
    d = 8.0
    holes = Holes(8, d, 100.0)
    lo, _ = holed_ring_bounds(ring, holes, samples=200001)
    psi = np.linspace(-math.pi / 8, math.pi / 8, 200001)
    y = 100.0 * np.sin(psi)
    c = 2.0 * np.sqrt(np.clip(16.0 - y * y, 0.0, None))  # the chord, ≈ centred (hole on the mid-radius)
    expect = np.mean(20.0 ** 3 / (20.0 ** 3 - c ** 3))
    assert lo == pytest.approx(expect, rel=2e-3)


def test_plug_ring_is_the_cam_under_the_bearing():
    import profilegen as pg

    gs = pg.new_gearset(32, 100).gearset
    g = gs.gear
    p = plug_ring(gs, 0.5)
    seat = float(g.neutral_radius_mm) - 0.5 * float(g.rim_thickness_mm) - float(gs.wave_generator.bearing_thickness_mm)
    assert p.outer_radius_mm == pytest.approx(seat)
    assert p.inner_radius_mm == pytest.approx(0.5 * seat)
    assert p.loaded == "outer"
    with pytest.raises(ValueError):
        plug_ring(gs, 1.0)


def test_flexed_bearing_adds_the_strip_in_series_with_hertz():
    import profilegen as pg
    from profilegen.contact.chain import BallBearing
    from research.ring_suspects import flexed_bearing

    gs = pg.new_gearset(32, 100).gearset
    plain, flexed = BallBearing.from_gearset(gs), flexed_bearing(gs)
    q = np.array([10.0, 500.0, 3000.0])
    c = flexed.secant_compliance_mm_per_n(q) - plain.secant_compliance_mm_per_n(q)
    assert np.allclose(c, flexed.flexure_mm_per_n, rtol=1e-12)
    assert flexed.flexure_mm_per_n > 0.0


def test_plate_flexure_tends_to_the_strip_when_the_pitch_is_narrow():
    # a plate strip much narrower than the face bends as research/race_flexure.py's beam:
    # c_ax = b³/(320 D s); at the gear's proportions (s ≈ 0.6 b) the point support adds a little
    from research.ring_suspects import plate_flexure_compliance_mm_per_n

    b, d = 20.0, 1.0
    assert plate_flexure_compliance_mm_per_n(b, 1.0, d, divisions=8) == pytest.approx(b ** 3 / (320.0 * d), rel=2e-3)
    wide = plate_flexure_compliance_mm_per_n(16.0, 10.0, d, divisions=8)
    assert 1.0 < wide / (16.0 ** 3 / (320.0 * d * 10.0)) < 1.3
