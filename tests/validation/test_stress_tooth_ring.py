"""Tooth-ring stress of the flexspline (profilegen.stress.tooth_ring) against geometry and
hand calculations.

Source: seed 001 (shared/seeds/001_*.txt): κ(φ) of the deformed neutral line, the assembly
stress K_σ E δ/2 (ρ_a/ρ_b² − 1/r_m), K_σ = 0.344 exp(1.243 s_f/δ) + 5.833 (r1/δ + 0.482 s_f/δ
− 0.693)² + 0.886, M_yσ = q_t (h + δ/2) [K_s(1 − K_s/2)(1 − δ³/h_p³) − 0.5]/[K_s(1 − δ³/h_p³) − 1],
σ_load = 6 M_yσ/δ²; its parameter table (SHF-25: r_m = 29.119, ρ_a = 29.494, ρ_b = 28.741 mm,
E = 210 GPa, b = 10 mm, m = 0.375 mm, z1 = 160) and its stresses 242.7 / 371.1 / 496.1 MPa.
DESIGN.md trap 6. The formulas are transcribed here once more, independently of the module.
"""

import json
import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from profilegen.errors import StressError
from profilegen.stress import tooth_ring as tr

R_M, RHO_A, RHO_B, E = 29.119, 29.494, 28.741, 210000.0


# --------------------------------------------------------------------------- independent helpers


def spectral_derivative(values: np.ndarray, order: int) -> np.ndarray:
    """d^k/dφ^k of a smooth 2π-periodic sample on a uniform grid (FFT)."""
    n = values.size
    k = np.fft.fftfreq(n, 1.0 / n)
    if order % 2 == 1:
        k[n // 2] = 0.0
    return np.real(np.fft.ifft((1j * k) ** order * np.fft.fft(values)))


def parametric_ellipse_curvature(t, a, b):
    return a * b / (a**2 * np.sin(t) ** 2 + b**2 * np.cos(t) ** 2) ** 1.5


def displacements_of(points: np.ndarray, phi: np.ndarray, r_m: float):
    """ω, υ of the points R(φ) relative to the circle of radius r_m (material angle φ)."""
    e_r = np.stack([np.cos(phi), np.sin(phi)], axis=1)
    e_t = np.stack([-np.sin(phi), np.cos(phi)], axis=1)
    return np.sum(points * e_r, axis=1) - r_m, np.sum(points * e_t, axis=1)


def k_sigma(s_f, r1, delta):
    return 0.344 * math.exp(1.243 * s_f / delta) + 5.833 * (r1 / delta + 0.482 * s_f / delta - 0.693) ** 2 + 0.886


def moment_fraction(s_f, p, delta, h0):
    k_s, c = s_f / p, 1.0 - delta**3 / (delta + h0) ** 3
    return (k_s * (1 - k_s / 2) * c - 0.5) / (k_s * c - 1)


def total_stress(case, torque_nm, ratio, r1_over_m, nu):
    """Seed 001's σ_total for the case, written out from the seed's equations."""
    m, delta = case.module_mm, ratio * case.neutral_radius_mm
    s_f = math.pi * m / (1 + nu) + 2 * case.dedendum_mm * math.tan(case.flank_angle_rad)
    a = case.neutral_radius_mm + case.deflection_mm
    chi = a / case.minor_semi_axis_mm**2 - 1 / case.neutral_radius_mm
    ass = k_sigma(s_f, r1_over_m * m, delta) * E * delta / 2 * chi
    z = case.flexspline_teeth
    force = case.peak_factor * torque_nm * 1e3 / (0.5 * m * z * case.engaged_fraction * z)
    q_t = force / case.face_width_mm
    f = moment_fraction(s_f, math.pi * m, delta, case.equivalent_tooth_height_mm)
    moment = q_t * (case.tooth_height_mm + delta / 2) * f
    return ass + 6 * moment / delta**2


def base_inputs(**override):
    kw = dict(neutral_radius_mm=R_M, rim_thickness_mm=0.9, deflection_mm=RHO_A - R_M, root_thickness_mm=0.8,
              fillet_radius_mm=0.25, pitch_mm=math.pi * 0.375, tooth_height_mm=0.75, equivalent_tooth_height_mm=0.375,
              face_width_mm=10.0, youngs_modulus_mpa=E, tangential_force_n=100.0, minor_semi_axis_mm=RHO_B)
    kw.update(override)
    return kw


# --------------------------------------------------------------------------- curvature


def test_circle_and_rigid_motions_have_the_exact_curvature():
    """A circle of radius r_m + c: 1/(r_m + c). A rigid translation by d (ω = d cos φ,
    υ = −d sin φ) keeps 1/r_m; a rigid rotation (υ = c) maps the circle to one of radius
    √(r_m² + c²) — exactly, with no linearisation."""
    phi = np.linspace(0, 2 * np.pi, 37)
    zero = np.zeros_like(phi)
    assert np.allclose(tr.displaced_curvature(phi, R_M, 0.4, 0, 0, 0, 0, 0), 1 / (R_M + 0.4), rtol=1e-14)
    assert np.allclose(tr.ellipse_curvature(phi, 31.0, 31.0), 1 / 31.0, rtol=1e-14)
    d = 3.0
    kappa = tr.displaced_curvature(phi, R_M, d * np.cos(phi), -d * np.sin(phi), -d * np.cos(phi),
                                   -d * np.sin(phi), -d * np.cos(phi), d * np.sin(phi))
    assert np.allclose(kappa, 1 / R_M, rtol=1e-14)
    c = 2.0
    kappa = tr.displaced_curvature(phi, R_M, zero, zero, zero, c + zero, zero, zero)
    assert np.allclose(kappa, 1 / math.hypot(R_M, c), rtol=1e-14)
    as_callables = tr.displaced_curvature(phi, R_M, lambda p: 0 * p, 0, 0, lambda p: c + 0 * p, 0, 0)
    assert np.allclose(as_callables, kappa, rtol=1e-15)


def test_ellipse_curvature_on_the_axes_and_against_the_parametric_form():
    """κ(0) = a/b², κ(π/2) = b/a²; at any point, ab/(a² sin²t + b² cos²t)^{3/2} in the
    parameter t, the polar angle being atan2(b sin t, a cos t)."""
    a, b = RHO_A, RHO_B
    assert tr.ellipse_curvature(0.0, a, b) == pytest.approx(a / b**2, rel=1e-15)
    assert tr.ellipse_curvature(math.pi / 2, a, b) == pytest.approx(b / a**2, rel=1e-14)
    t = np.linspace(0, 2 * np.pi, 101)
    theta = np.arctan2(b * np.sin(t), a * np.cos(t))
    assert np.allclose(tr.ellipse_curvature(theta, a, b), parametric_ellipse_curvature(t, a, b), rtol=1e-13)


def test_printed_seed_curvature_is_nan_and_right_up_to_the_sign_slip():
    """Seed 001's κ(φ) as printed: both brackets are negative for c1 > 1, so real arithmetic
    gives NaN for every φ; evaluated in complex arithmetic the factors cancel and it is the
    exact ellipse curvature."""
    phi = np.linspace(0, np.pi, 19)
    c1 = RHO_A / RHO_B
    c2 = np.cos(phi) ** 2
    with np.errstate(invalid="ignore"):
        printed = np.abs(c1 / RHO_B * (c1**2 * c2 - c2 - c1**2) ** 1.5 / (c1**4 * c2 - c2 - c1**4) ** 1.5)
    assert np.all(np.isnan(printed))
    assert np.all(np.isnan(tr.seed001_printed_curvature(phi, RHO_A, RHO_B)))
    fixed = np.abs(c1 / RHO_B * (c1**2 * c2 - c2 - c1**2 + 0j) ** 1.5 / (c1**4 * c2 - c2 - c1**4 + 0j) ** 1.5)
    t = np.arctan(c1 * np.tan(phi))  # parameter of the point at polar angle φ (same quadrant up to sign)
    assert np.allclose(fixed, parametric_ellipse_curvature(t, RHO_A, RHO_B), rtol=1e-13)
    assert np.allclose(tr.seed001_printed_curvature(phi, RHO_A, RHO_B, complex_arithmetic=True),
                       tr.ellipse_curvature(phi, RHO_A, RHO_B), rtol=1e-13)


@pytest.mark.parametrize("warp", [0.0, 0.04])
def test_displaced_curvature_reproduces_the_ellipse(warp):
    """The ellipse reached by the material point at φ through the parameter t = φ + warp·sin 2φ
    (the parameter t is not the polar angle, so υ ≠ 0 even for warp = 0; the warp adds a
    tangential shift of the material points). ω, υ and their derivatives by FFT differentiation of the
    sampled displacements; κ must equal the parametric ellipse curvature at t."""
    n = 256
    phi = np.arange(n) * 2 * np.pi / n
    t = phi + warp * np.sin(2 * phi)
    pts = np.stack([RHO_A * np.cos(t), RHO_B * np.sin(t)], axis=1)
    w, u = displacements_of(pts, phi, R_M)
    d = {k: spectral_derivative(w, k) for k in (1, 2)}
    e = {k: spectral_derivative(u, k) for k in (1, 2)}
    kappa = tr.displaced_curvature(phi, R_M, w, d[1], d[2], u, e[1], e[2])
    assert np.max(np.abs(kappa / parametric_ellipse_curvature(t, RHO_A, RHO_B) - 1)) < 1e-11


def test_displaced_curvature_with_polar_projection_matches_the_polar_formula():
    """ω = ρ(φ) − r_m, υ = 0 (each point moved radially onto the ellipse): the general
    curvature must equal the exact ellipse curvature at polar angle φ."""
    n = 256
    phi = np.arange(n) * 2 * np.pi / n
    rho = RHO_A * RHO_B / np.sqrt(RHO_A**2 * np.sin(phi) ** 2 + RHO_B**2 * np.cos(phi) ** 2)
    w = rho - R_M
    zero = np.zeros(n)
    kappa = tr.displaced_curvature(phi, R_M, w, spectral_derivative(w, 1), spectral_derivative(w, 2), zero, zero, zero)
    assert np.allclose(kappa, tr.ellipse_curvature(phi, RHO_A, RHO_B), rtol=1e-11)


def test_finite_difference_curvature_of_the_displaced_curve_converges_at_second_order():
    """Central differences of the displaced points' coordinates x(φ), y(φ) give a curvature
    that tends to the exact formula's like h²."""
    def w(p, k=0):
        return [0.3 * np.cos(2 * p) + 0.05 * np.cos(4 * p), -0.6 * np.sin(2 * p) - 0.2 * np.sin(4 * p),
                -1.2 * np.cos(2 * p) - 0.8 * np.cos(4 * p)][k]

    def u(p, k=0):
        return [-0.15 * np.sin(2 * p) + 0.02 * np.sin(6 * p), -0.3 * np.cos(2 * p) + 0.12 * np.cos(6 * p),
                0.6 * np.sin(2 * p) - 0.72 * np.sin(6 * p)][k]

    probe = np.array([0.1, 0.7, 1.3, 2.9])
    exact = tr.displaced_curvature(probe, R_M, w(probe), w(probe, 1), w(probe, 2), u(probe), u(probe, 1), u(probe, 2))

    def point(p):
        return np.stack([(R_M + w(p)) * np.cos(p) - u(p) * np.sin(p), (R_M + w(p)) * np.sin(p) + u(p) * np.cos(p)])

    errors = []
    for h in (0.02, 0.01, 0.005):
        left, mid, right = point(probe - h), point(probe), point(probe + h)
        d1, d2 = (right - left) / (2 * h), (right - 2 * mid + left) / h**2
        kappa = (d1[0] * d2[1] - d1[1] * d2[0]) / np.hypot(d1[0], d1[1]) ** 3
        errors.append(np.max(np.abs(kappa - exact)))
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert errors[-1] < 1e-6
    assert np.all(np.abs(rates - 2.0) < 0.1), rates


def test_small_displacements_give_classical_ring_theory_at_second_order():
    """κ − 1/r_m = −(ω + ω'')/r_m² + O(ε²) whatever υ (here not inextensible): the error
    falls by 4 when the displacements are halved."""
    phi = np.linspace(0, np.pi, 25)
    errors = []
    for eps in (0.02, 0.01, 0.005):
        w, w1, w2 = eps * np.cos(2 * phi), -2 * eps * np.sin(2 * phi), -4 * eps * np.cos(2 * phi)
        u, u1, u2 = 0.3 * eps * np.sin(4 * phi), 1.2 * eps * np.cos(4 * phi), -4.8 * eps * np.sin(4 * phi)
        exact = tr.displaced_curvature(phi, R_M, w, w1, w2, u, u1, u2)
        errors.append(np.max(np.abs(exact - 1 / R_M + (w + w2) / R_M**2)))
    assert errors[0] < 0.01 * 3 * 0.02 / R_M**2  # < 1 % of the first-order change 3ε/r_m²
    assert np.allclose(np.array(errors[:-1]) / np.array(errors[1:]), 4.0, rtol=0.02)


def test_equal_perimeter_minor_axis_is_the_seeds_rho_b():
    """ρ_b from the perimeter condition: the ellipse's length (quadrature) is 2π r_m, and it
    is seed 001's 28.741 mm to its printed digits."""
    b = tr.equal_perimeter_minor_semi_axis(R_M, RHO_A)
    length = 4 * quad(lambda t: math.hypot(RHO_A * math.sin(t), b * math.cos(t)), 0, math.pi / 2, epsabs=1e-13)[0]
    assert length == pytest.approx(2 * math.pi * R_M, rel=1e-12)
    assert abs(b - RHO_B) < 1e-3


# --------------------------------------------------------------------------- stresses


def test_stress_influence_factor_by_hand():
    """K_σ at s_f/δ = 0.9, r1/δ = 0.3: 0.344 e^1.1187 + 5.833·0.0408² + 0.886 = 1.9486."""
    assert tr.stress_influence_factor(0.9, 0.3, 1.0) == pytest.approx(
        0.344 * math.exp(1.1187) + 5.833 * 0.0408**2 + 0.886, rel=1e-12)
    assert tr.stress_influence_factor(0.9, 0.3, 1.0) == pytest.approx(1.9486, abs=1e-4)


def test_assembly_load_and_total_stress_by_hand():
    """σ_ass = K_σ E δ/2 (ρ_a/ρ_b² − 1/r_m); σ_load = 6 (F_t/b)(h + δ/2) f / δ²; total = sum."""
    kw = base_inputs()
    res = tr.tooth_ring_stress(**kw)
    delta = kw["rim_thickness_mm"]
    ass = k_sigma(0.8, 0.25, delta) * E * delta / 2 * (RHO_A / RHO_B**2 - 1 / R_M)
    f = moment_fraction(0.8, kw["pitch_mm"], delta, 0.375)
    load = 6 * (100.0 / 10.0) * (0.75 + delta / 2) * f / delta**2
    assert res.assembly_stress_mpa == pytest.approx(ass, rel=1e-12)
    assert res.load_stress_mpa == pytest.approx(load, rel=1e-12)
    assert res.total_stress_mpa == pytest.approx(ass + load, rel=1e-12)
    assert res.curvature_change_mm_inv == pytest.approx(RHO_A / RHO_B**2 - 1 / R_M, rel=1e-12)


def test_load_stress_is_linear_in_the_force_and_the_moment():
    r1 = tr.tooth_ring_stress(**base_inputs(tangential_force_n=50.0))
    r2 = tr.tooth_ring_stress(**base_inputs(tangential_force_n=150.0))
    r0 = tr.tooth_ring_stress(**base_inputs(tangential_force_n=0.0))
    assert r0.load_stress_mpa == 0.0
    assert r2.load_stress_mpa == pytest.approx(3 * r1.load_stress_mpa, rel=1e-14)
    assert r2.assembly_stress_mpa == r1.assembly_stress_mpa
    assert tr.load_stress_mpa(2.5, 0.9) == pytest.approx(6 * 2.5 / 0.81, rel=1e-15)


def test_moment_fraction_is_a_half_at_its_limits_and_below_otherwise():
    """f = 1/2 for K_s → 0 and for h0 → 0 (δ³/h_p³ → 1); 0 ≤ f < 1/2 in between."""
    assert tr.load_moment_factor(1e-12, 1.0, 0.9, 0.4) == pytest.approx(0.5, abs=1e-11)
    assert tr.load_moment_factor(0.6, 1.0, 0.9, 1e-12) == pytest.approx(0.5, abs=1e-11)
    ks = np.linspace(0.05, 0.95, 19)
    f = tr.load_moment_factor(ks, 1.0, 0.9, 0.4)
    assert np.all((f > 0) & (f < 0.5))


def test_assembly_stress_is_largest_on_the_major_axis():
    res = tr.tooth_ring_stress(**base_inputs())
    assert int(np.argmax(res.assembly_stress_phi_mpa)) == 0
    assert res.assembly_stress_phi_mpa[-1] < 0  # the minor axis is bent flatter than the circle
    assert res.assembly_stress_phi_mpa[0] == pytest.approx(res.assembly_stress_mpa, rel=1e-14)


def test_result_is_read_only_and_json_safe():
    """(Its speed, the former 0.01 s budget, is ``python tests/benchmarks/stress_speed.py``.)"""
    res = tr.tooth_ring_stress(**base_inputs(minor_semi_axis_mm=None))
    with pytest.raises(ValueError):
        res.curvature_mm_inv[0] = 1.0
    data = json.loads(json.dumps(res.to_dict()))
    assert data["total_stress_mpa"] == pytest.approx(res.total_stress_mpa)
    assert res.time_s > 0


# --------------------------------------------------------------------------- seed 001 numbers and trends


@pytest.fixture(scope="module")
def case():
    return tr.seed001_case()


@pytest.fixture(scope="module")
def study(case):
    return tr.tooth_ring_study(case, [67.0, 108.0, 167.0, 304.0])


def test_vectorised_case_stress_matches_the_seed_equations(case):
    for torque, ratio, r1m, nu in [(0, 0.03, 0.65, 1.8), (67, 0.028, 0.5, 1.4), (304, 0.03375, 0.7, 1.8)]:
        ours = sum(tr.case_stress_mpa(case, torque, thickness_ratio=ratio, fillet_ratio=r1m, slot_ratio=nu))
        assert float(ours) == pytest.approx(total_stress(case, torque, ratio, r1m, nu), rel=1e-12)
        kw = tr.case_inputs(case, torque, thickness_ratio=ratio, fillet_ratio=r1m, slot_ratio=nu)
        one = tr.tooth_ring_stress(**kw)
        assert one.total_stress_mpa == pytest.approx(float(ours), rel=1e-12)


def test_optimal_thickness_rises_with_torque_and_is_a_true_minimum(case, study):
    """Each optimum against an independent bounded minimisation of the seed's equations."""
    assert np.all(study.optimal_thickness_interior)
    assert np.all(np.diff(study.optimal_thickness_ratio) > 0)
    for torque, found in zip(study.torques_nm, study.optimal_thickness_ratio):
        ref = minimize_scalar(lambda x: total_stress(case, torque, x, case.fillet_ratio, case.slot_ratio),
                              bounds=(0.02, 0.05), method="bounded", options={"xatol": 1e-9}).x
        assert found == pytest.approx(ref, abs=2e-6)


def test_optimal_fillet_is_the_vertex_of_k_sigma_for_every_torque(case, study):
    """The load term has no r1: r1* = 0.693 δ − 0.482 s_f whatever the torque."""
    delta = case.thickness_ratio * case.neutral_radius_mm
    s_f = math.pi * case.module_mm / (1 + case.slot_ratio) + 2 * case.dedendum_mm * math.tan(case.flank_angle_rad)
    vertex = (0.693 * delta - 0.482 * s_f) / case.module_mm
    assert np.allclose(study.optimal_fillet_ratio, vertex, atol=1e-6)


@pytest.mark.parametrize("ratio, inside", [(0.025, False), (0.030, True), (0.034, True), (0.040, False)])
def test_optimal_fillet_in_0p6_to_0p7_only_in_the_seeds_thickness_range(ratio, inside):
    """With s_f/δ = 0.9 (brief) r1*/m = (0.693 − 0.482·0.9) δ/m: inside [0.6, 0.7] for the
    seed's optimal thicknesses (3.0–3.4 %), not for thinner or thicker rings."""
    delta = ratio * R_M
    r1 = minimize_scalar(lambda r: k_sigma(0.9 * delta, r, delta), bounds=(0, delta), method="bounded",
                         options={"xatol": 1e-10}).x
    assert (0.6 <= r1 / 0.375 <= 0.7) == inside


def test_no_load_stress_is_not_linear_in_thickness(case):
    """Seed 001 says the no-load stress rises linearly with δ; with s_f fixed by the tooth,
    K_σ(δ)·δ has a minimum (the exp(1.243 s_f/δ) term)."""
    x = np.linspace(0.02, 0.05, 61)
    ass, _ = tr.case_stress_mpa(case, 0.0, thickness_ratio=x, fillet_ratio=case.fillet_ratio,
                                slot_ratio=case.slot_ratio)
    ref = np.array([total_stress(case, 0.0, v, case.fillet_ratio, case.slot_ratio) for v in x])
    assert np.allclose(ass, ref, rtol=1e-12)
    i = int(np.argmin(ass))
    assert 0 < i < x.size - 1


def test_slot_ratio_has_no_interior_optimum_in_the_model(study):
    """At each torque's optimal δ the stress falls monotonically with ν over 1–3 (trapezoidal
    tooth): the seed's ν_opt ≈ 2 does not follow from its equations."""
    assert np.all(np.diff(study.stress_vs_slot_mpa, axis=1) < 0)
    assert not np.any(study.optimal_slot_interior)
    assert np.all(np.diff(study.optimal_thickness_table, axis=1) < 0)  # larger ν → thinner optimum (holds)


def test_seed_comparison_rows(case):
    rows = tr.seed001_comparison(case)
    by_name = {}
    for r in rows:
        by_name.setdefault(r.quantity, []).append(r)
    assert abs(by_name["minor semi-axis rho_b"][0].our_value - 28.741) < 1e-3
    assert by_name["assembly stress, base configuration"][0].our_value == pytest.approx(242.7, abs=0.5)
    rated = by_name["total stress at RAT 67 N·m, base configuration"]
    assert any(r.our_value == pytest.approx(371.1, rel=1e-9) for r in rated)  # the calibrated one
    ratio = by_name["load stress ratio MIT/RAT implied by 242.7, 371.1, 496.1"][0]
    assert ratio.seed_value < 0.6 * ratio.our_value  # the seed's numbers are not linear in q_t
    json.dumps([r.to_dict() for r in rows])


def test_trend_checks_state_which_claims_fail(case, study):
    checks = {c.claim: c.holds for c in tr.seed001_trend_checks(case, study)}
    failing = {claim for claim, holds in checks.items() if not holds}
    assert failing == {
        "no load: the stress rises linearly with the thickness",
        "beyond the optimal fillet radius the returns diminish (stress flat or slightly rising)",
        "the stress against nu (at the optimal thickness) has a shallow interior minimum near nu = 2.0",
        "the optimal nu decreases as the load increases",
    }


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize("name, value", [
    ("rim_thickness_mm", 0.0), ("rim_thickness_mm", -0.9), ("root_thickness_mm", 0.0),
    ("face_width_mm", -1.0), ("youngs_modulus_mpa", float("nan")), ("tangential_force_n", float("inf")),
    ("tangential_force_n", -1.0), ("deflection_mm", 0.0), ("neutral_radius_mm", float("nan")),
    ("fillet_radius_mm", -0.1), ("root_thickness_mm", 1.5), ("minor_semi_axis_mm", 30.0),
    ("equivalent_tooth_height_mm", 0.0),
])
def test_bad_input_names_the_parameter(name, value):
    with pytest.raises(StressError, match=name):
        tr.tooth_ring_stress(**base_inputs(**{name: value}))


def test_bad_input_of_the_pieces():
    with pytest.raises(StressError, match="major_semi_axis_mm"):
        tr.equal_perimeter_minor_semi_axis(R_M, 20.0)
    with pytest.raises(StressError, match="phi_rad"):
        tr.displaced_curvature(np.array([0.0, np.nan]), R_M, 0, 0, 0, 0, 0, 0)
    with pytest.raises(StressError, match="omega_mm"):
        tr.displaced_curvature(np.zeros(3), R_M, np.zeros(4), 0, 0, 0, 0, 0)
    with pytest.raises(StressError, match="torques_nm"):
        tr.tooth_ring_study(tr.seed001_case(), [-67.0])
    with pytest.raises(StressError, match="slot_width_ratio"):
        tr.root_thickness_from_slot_ratio(0.0, 0.375, 0.45, 0.3)
    assert issubclass(StressError, ValueError)
