"""The ratcheting estimate (profilegen.contact.ratchet) and its bad inputs.

Analytic: the CS ring's radial compliance (curved-beam Fourier series) against Roark's closed
forms for a thin ring pulled by two opposite radial point loads — under the loads
(π/4 − 2/π)/2 · P R³/EI, at 90° −(2/π − 1/2)/2 · P R³/EI, plus the extensional n = 0 term
P R/(π E A) — and the series' truncation error falling as N⁻³. On the default set's sketch
design: the CS ring moves outward under the tooth forces' radial components, softer ball
supports (Hertz) let the loaded teeth ride further out than rigid ones, the estimate lies
above every solved torque whose margin is positive, and the bad inputs are named errors.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

import profilegen as pg
from profilegen.contact.chain import BallBearing
from profilegen.contact.ratchet import (
    BearingFitError,
    RatchetingError,
    check_bearing_fits,
    cs_ring_radial_compliance,
    ratcheting_torque,
)

R, H, W, E = 57.5, 13.0, 20.0, 206000.0


def _ring(at, harmonics=200):
    return cs_ring_radial_compliance([0.0, math.pi], at, mean_radius_mm=R, thickness_mm=H, width_mm=W,
                                     youngs_modulus_mpa=E, harmonics=harmonics).sum(axis=1)


def test_ring_against_roark_two_opposite_loads():
    """Roark, Formulas for Stress and Strain, thin ring under two equal opposite diametral
    loads: ΔD along the loads (π/4 − 2/π) P R³/EI, across (2/π − 1/2) P R³/EI (opposite sign)."""
    inertia, area = W * H ** 3 / 12.0, W * H
    scale = R ** 3 / (E * inertia)
    extension = R / (math.pi * E * area)
    under, across = _ring([0.0, 0.5 * math.pi])
    assert under - extension == pytest.approx(0.5 * (math.pi / 4 - 2 / math.pi) * scale, rel=1e-6)
    assert across - extension == pytest.approx(-0.5 * (2 / math.pi - 0.5) * scale, rel=1e-6)


def test_ring_series_converges_as_n_cubed():
    exact = _ring([0.0], harmonics=4000)[0]
    errors = [abs(_ring([0.0], harmonics=n)[0] - exact) for n in (20, 40, 80)]
    rates = [math.log2(errors[k] / errors[k + 1]) for k in range(2)]
    assert all(2.8 < r < 3.2 for r in rates), rates


@pytest.fixture(scope="module")
def design():
    return pg.design(pg.load_gearset(pg.default_gearset_path()), scene="sketch", contact=False, stress=False)


TORQUES = [132.5, 265.0, 397.5]


@pytest.fixture(scope="module")
def whole(design):
    return ratcheting_torque(design, torques_nm=TORQUES, stations=3)


def test_estimate_and_its_parts(whole):
    r = whole
    assert r.valid.all()
    # the CS ring is pushed outward under the loaded teeth: the tooth forces' radial components push the CS out
    assert np.all(r.separation_cs_mm > 0.0)
    assert np.allclose(r.separation_mm, r.separation_fs_mm + r.separation_cs_mm, rtol=0, atol=1e-15)
    # the loaded teeth are in their spaces at every solved torque: the estimate lies beyond them
    assert np.all(r.margin_mm() > 0.0) and np.all(r.mean_depth_mm > 0.3)
    assert r.extrapolated and r.torque_nm > max(TORQUES)
    # proportional bound: no solved torque scaled by h̄/Δr̄ comes below it
    out = r.mean_separation_mm > 0
    assert np.all(r.torques_nm[out] * r.mean_depth_mm[out] / r.mean_separation_mm[out] >= r.torque_nm * (1 - 1e-12))
    assert r.catalogue is None and r.ratio_to_catalogue is None
    d = json.loads(json.dumps(r.to_dict()))
    assert d["torque_nm"] == pytest.approx(r.torque_nm) and d["catalogue"] is None


def test_softer_balls_let_the_teeth_ride_out(design):
    """Rigid ball supports against the Hertz springs (no CS ring in either): the rim sinks into
    the softer supports, so the loaded teeth move further out of their spaces (force-weighted)."""
    rigid = ratcheting_torque(design, torques_nm=TORQUES, stations=3, bearing=None, cs_ring=False)
    hertz = ratcheting_torque(design, torques_nm=TORQUES, stations=3, cs_ring=False)
    assert np.all(rigid.separation_cs_mm == 0.0) and np.all(hertz.separation_cs_mm == 0.0)
    assert np.all(hertz.mean_separation_mm > rigid.mean_separation_mm + 2e-3)  # > 2 µm further out


def test_flag_and_zero_torque(whole, design):
    r = whole
    assert r.flag(265.0) is None
    assert "ratcheting estimate" in r.flag(-1.0001 * r.torque_nm)
    for bad in (0.0, float("nan")):
        with pytest.raises(RatchetingError, match="torque_nm"):
            r.flag(bad)
    with pytest.raises(RatchetingError, match=r"torques_nm\[0\] = 0.0 N·m"):
        ratcheting_torque(design, torques_nm=[0.0, 265.0])
    with pytest.raises(RatchetingError, match="bearing"):
        ratcheting_torque(design, bearing="steel")


def test_bearing_that_does_not_fit():
    gs = pg.load_gearset(pg.default_gearset_path())
    thin = dataclasses.replace(gs, wave_generator=dataclasses.replace(gs.wave_generator, bearing_thickness_mm=8.0))
    balls = BallBearing(23, 7.5, 84.5, 0.52, 2.06e5, 0.3)
    with pytest.raises(BearingFitError, match=r"ball_diameter_mm = 7.5 mm: must be in \(0, 3\] mm.*"
                                              r"wave_generator.bearing_thickness_mm = 8 mm"):
        check_bearing_fits(thin, balls)
    check_bearing_fits(thin, dataclasses.replace(balls, ball_diameter_mm=2.5))  # 2.5 + 2 × 2.5 mm races fit in 8
    with pytest.raises(BearingFitError, match="ball_diameter_mm"):
        check_bearing_fits(gs, race_thickness_mm=30.0)  # no room left inside a 30 mm race
    with pytest.raises(BearingFitError, match="race_thickness_mm = -1.0 mm"):
        check_bearing_fits(gs, race_thickness_mm=-1.0)
    assert issubclass(BearingFitError, ValueError)
