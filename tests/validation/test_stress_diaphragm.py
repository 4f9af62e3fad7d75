"""Diaphragm corner shear and Goodman check (profilegen.stress.diaphragm).

Source: seed 000 (shared/seeds/000_*.txt, sections 4.4 and 5.5): at the corner of the
diaphragm with the boss the shear amplitude is set by the wave generator's deflection, the
mean grows linearly with the torque, and a Goodman diagram of (τ_m, τ_a) judges fatigue
(its Fig. 21). The seed gives no formulas; checked here: τ_m = T/(2π r0² t) by hand, the
plate solution against an independent ODE solve (scipy solve_bvp of the n = 2 biharmonic
equation), the edge amplitude against seed 002's double integral, Goodman by hand.
The speed of one evaluation (formerly a 0.01 s assertion here) is measured by
``python tests/benchmarks/stress_speed.py``.
"""

import json
import math

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid, solve_bvp

from profilegen.errors import StressError
from profilegen.output.plot import plot_goodman
from profilegen.stress import diaphragm as dg

#: A size-40 cup (seed 000's CSF40-100; its dimensions are a trade secret): ESTIMATES.
SAMPLE = dict(cup_radius_mm=48.7, boss_radius_mm=24.0, diaphragm_thickness_mm=2.2, cup_length_mm=58.0,
              deflection_mm=0.5, youngs_modulus_mpa=206000.0, poisson_ratio=0.3, torque_nmm=265e3,
              shear_endurance_limit_mpa=285.0, ultimate_strength_mpa=1100.0)


def sample(**override):
    kw = dict(SAMPLE)
    kw.update(override)
    return kw


# --------------------------------------------------------------------------- mean shear


def test_mean_shear_is_the_thin_annulus_torsion_formula():
    assert dg.mean_shear_stress_mpa(110e3, 24.0, 2.2) == pytest.approx(110e3 / (2 * math.pi * 24.0**2 * 2.2), rel=1e-15)
    res = dg.diaphragm_stress(**sample())
    assert res.mean_shear_mpa == pytest.approx(265e3 / (2 * math.pi * 24.0**2 * 2.2), rel=1e-15)
    assert np.allclose(res.mean_shear_profile_mpa, 265e3 / (2 * math.pi * res.radius_mm**2 * 2.2), rtol=1e-15)


def test_mean_is_linear_in_torque_and_amplitude_independent_of_it():
    """Seed 000 Figs. 19–20: the mean grows linearly with T, the amplitude does not change."""
    results = [dg.diaphragm_stress(**sample(torque_nmm=t)) for t in (0.0, 75e3, 150e3)]
    assert results[0].mean_shear_mpa == 0.0
    assert results[2].mean_shear_mpa == pytest.approx(2 * results[1].mean_shear_mpa, rel=1e-15)
    assert results[0].shear_amplitude_mpa == results[2].shear_amplitude_mpa


# --------------------------------------------------------------------------- amplitude


def test_edge_amplitude_is_the_periodic_part_of_seed_002s_integral():
    """w₀(φ) = −(r_m/l) ∫∫ (ρ − r_m) dη dθ with ρ − r_m = w0 cos 2η: its cos 2φ amplitude,
    by numerical double integration, is r_m w0/(4 l)."""
    r_m, w0, length = 48.7, 0.5, 58.0
    phi = np.linspace(0, 2 * np.pi, 4001)
    inner = cumulative_trapezoid(w0 * np.cos(2 * phi), phi, initial=0.0)
    w = -(r_m / length) * cumulative_trapezoid(inner, phi, initial=0.0)
    amplitude = 2 * np.trapezoid(w * np.cos(2 * phi), phi) / (2 * np.pi)
    assert abs(amplitude) == pytest.approx(dg.edge_axial_amplitude_mm(r_m, w0, length), rel=1e-5)


def bvp_mode(r0, r_c, amplitude, nu, outer_edge, slope):
    """F(r) of w = F cos 2φ from the ODE F'''' + 2F'''/r − 9F''/r² + 9F'/r³ = 0 (∇⁴w = 0, n = 2)."""
    def rhs(r, y):
        return np.vstack([y[1], y[2], y[3], -2 * y[3] / r + 9 * y[2] / r**2 - 9 * y[1] / r**3])

    def bc(ya, yb):
        last = yb[2] + nu * (yb[1] / r_c - 4 * yb[0] / r_c**2) if outer_edge == "hinged" else yb[1] - slope
        return np.array([ya[0], ya[1], yb[0] - amplitude, last])

    r = np.linspace(r0, r_c, 50)
    sol = solve_bvp(rhs, bc, r, np.zeros((4, r.size)), tol=1e-10, max_nodes=100000)
    assert sol.success
    return sol


@pytest.mark.parametrize("outer_edge", ["hinged", "rigid_joint"])
def test_plate_solution_against_an_independent_ode_solve(outer_edge):
    """Deflection amplitude and surface shear τ = E t/(1+ν) |F'/r − F/r²| from solve_bvp; for the
    rigid joint the plate's slope at r_c is the wall's tilt w0/l (same sign as F there)."""
    res = dg.diaphragm_stress(**sample(outer_edge=outer_edge, torque_nmm=0.0))
    u_a = SAMPLE["cup_radius_mm"] * SAMPLE["deflection_mm"] / (4 * SAMPLE["cup_length_mm"])
    sol = bvp_mode(24.0, 48.7, u_a, 0.3, outer_edge, SAMPLE["deflection_mm"] / SAMPLE["cup_length_mm"])
    r = res.radius_mm
    f, f1 = sol.sol(r)[0], sol.sol(r)[1]
    tau = 206000.0 * 2.2 / 1.3 * np.abs(f1 / r - f / r**2)
    assert np.max(np.abs(res.deflection_amplitude_mm - f)) < 1e-6 * u_a
    assert np.max(np.abs(res.shear_amplitude_profile_mpa - tau)) < 1e-6 * tau.max()
    r_e = 24.0 + 2.2
    fe, fe1 = sol.sol(r_e)[0], sol.sol(r_e)[1]
    assert res.shear_amplitude_mpa == pytest.approx(206000.0 * 2.2 / 1.3 * abs(fe1 / r_e - fe / r_e**2), rel=1e-6)


def test_no_twist_at_a_clamped_edge():
    """w = ∂w/∂r = 0 on r0 for every φ ⇒ ∂²w/∂r∂φ = 0: τ_a vanishes at the boss itself, the
    radial bending stress does not."""
    res = dg.diaphragm_stress(**sample())
    assert res.shear_amplitude_profile_mpa[0] < 1e-10 * res.max_shear_amplitude_mpa
    assert res.corner_radial_stress_amplitude_mpa > res.shear_amplitude_mpa
    assert res.evaluation_radius_mm == pytest.approx(24.0 + 2.2)


def test_amplitude_is_linear_in_deflection_and_modulus_and_inverse_in_length():
    ref = dg.diaphragm_stress(**sample()).shear_amplitude_mpa
    assert dg.diaphragm_stress(**sample(deflection_mm=1.0)).shear_amplitude_mpa == pytest.approx(2 * ref, rel=1e-13)
    half_e = dg.diaphragm_stress(**sample(youngs_modulus_mpa=103000.0)).shear_amplitude_mpa
    assert half_e == pytest.approx(ref / 2, rel=1e-13)
    assert dg.diaphragm_stress(**sample(cup_length_mm=116.0)).shear_amplitude_mpa == pytest.approx(ref / 2, rel=1e-13)


# --------------------------------------------------------------------------- Goodman


@pytest.mark.parametrize("tau_a, tau_m, tau_e, tau_u, n", [
    (100.0, 0.0, 200.0, 600.0, 2.0),  # pure alternating: τ_-1/τ_a
    (0.0, 300.0, 200.0, 600.0, 2.0),  # pure mean: τ_u/τ_m
    (50.0, 150.0, 200.0, 600.0, 2.0),  # 0.25 + 0.25 = 1/2
    (-50.0, -150.0, 200.0, 600.0, 2.0),  # shear sign does not matter
    (40.0, 60.0, 160.0, 480.0, 1.0 / (0.25 + 0.125)),
    (0.0, 0.0, 200.0, 600.0, math.inf),
])
def test_goodman_by_hand(tau_a, tau_m, tau_e, tau_u, n):
    assert dg.goodman_shear_safety_factor(tau_a, tau_m, tau_e, tau_u) == pytest.approx(n, rel=1e-15)


def test_result_safety_factor_uses_0p577_sigma_u_by_hand():
    res = dg.diaphragm_stress(**sample())
    tau_u = 0.577 * 1100.0
    assert res.shear_ultimate_mpa == pytest.approx(tau_u)
    by_hand = 1 / (res.shear_amplitude_mpa / 285.0 + res.mean_shear_mpa / tau_u)
    assert res.safety_factor == pytest.approx(by_hand, rel=1e-14)
    other = dg.diaphragm_stress(**sample(shear_ultimate_ratio=0.67))
    assert other.safety_factor > res.safety_factor
    assert dg.diaphragm_stress(**sample(fatigue=False, shear_endurance_limit_mpa=None,
                                        ultimate_strength_mpa=None)).safety_factor is None


def test_plot_goodman_and_json(tmp_path):
    res = dg.diaphragm_stress(**sample())
    ax = plot_goodman(res)
    assert len(ax.lines) >= 3
    ax.figure.savefig(tmp_path / "goodman.png")
    data = json.loads(json.dumps(res.to_dict()))
    assert data["safety_factor"] == pytest.approx(res.safety_factor)
    with pytest.raises(ValueError):
        res.radius_mm[0] = 0.0
    with pytest.raises(StressError, match="safety_factor"):
        plot_goodman(dg.diaphragm_stress(**sample(fatigue=False)))


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize("name, value", [
    ("diaphragm_thickness_mm", 0.0), ("diaphragm_thickness_mm", -2.2), ("boss_radius_mm", 48.7),
    ("boss_radius_mm", 60.0), ("cup_radius_mm", float("nan")), ("cup_length_mm", 0.0),
    ("deflection_mm", -0.5), ("youngs_modulus_mpa", float("inf")), ("poisson_ratio", 0.5),
    ("torque_nmm", float("nan")), ("torque_nmm", -1.0), ("shear_endurance_limit_mpa", None),
    ("ultimate_strength_mpa", None), ("shear_endurance_limit_mpa", float("nan")), ("outer_edge", "free"),
    ("corner_offset_mm", 30.0), ("shear_ultimate_ratio", 1.5),
])
def test_bad_input_names_the_parameter(name, value):
    with pytest.raises(StressError, match=name):
        dg.diaphragm_stress(**sample(**{name: value}))


def test_bad_goodman_input():
    with pytest.raises(StressError, match="endurance_limit_mpa"):
        dg.goodman_shear_safety_factor(10.0, 10.0, 0.0, 600.0)
    with pytest.raises(StressError, match="amplitude_mpa"):
        dg.goodman_shear_safety_factor(float("nan"), 10.0, 200.0, 600.0)
    with pytest.raises(StressError, match="endurance_limit_mpa"):
        dg.goodman_shear_safety_factor(10.0, 10.0, 700.0, 600.0)
