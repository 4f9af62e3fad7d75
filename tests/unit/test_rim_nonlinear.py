"""Geometrically nonlinear rim (profilegen.rim.nonlinear, solve_ring(geometry="nonlinear")).

Checks against mechanics, not against the code's own output: the tangent is the derivative
of the internal force (finite differences, second-order convergence of the central
difference); at u = 0 it is scikit-fem's linear plane-stress stiffness; a rigid rotation
produces no internal force (the linear model gives a spurious one); the nonlinear solution
tends to the linear one as w0 → 0 with a difference ∝ w0²; the quarter is in equilibrium.
"""

import math

import numpy as np
import pytest

from profilegen.errors import ConvergenceError
from profilegen.rim import RingError, RingParameters, solve_ring
from profilegen.rim.nonlinear import TotalLagrangian
from profilegen.rim.ring import _mesh
from profilegen.geometry.wavegen import CosineCam, EllipticalCam


@pytest.fixture(scope="module")
def body():
    from skfem import Basis, ElementQuad2, ElementVector

    params = RingParameters(48.95, 0.9, 209000.0, 0.295)
    mesh, th, r = _mesh(params, 2, 16)
    basis = Basis(mesh, ElementVector(ElementQuad2()), intorder=4)
    return basis, TotalLagrangian(basis, params.youngs_modulus_mpa, params.poisson_ratio), params


def test_tangent_at_rest_is_linear_plane_stress(body):
    from skfem import asm
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    basis, tl, params = body
    lam, mu = lame_parameters(params.youngs_modulus_mpa, params.poisson_ratio)
    k0 = asm(linear_elasticity(2 * lam * mu / (lam + 2 * mu), mu), basis)
    k, f = tl(np.zeros(basis.N))
    assert abs(k - k0).max() <= 1e-13 * abs(k0).max()
    assert np.max(np.abs(f)) == 0.0
    assert abs(tl.linear_stiffness() - k0).max() <= 1e-13 * abs(k0).max()


def test_tangent_is_the_derivative_of_the_internal_force(body):
    basis, tl, _ = body
    rng = np.random.default_rng(1)
    u = 0.02 * rng.standard_normal(basis.N)
    k, _ = tl(u)
    d = rng.standard_normal(basis.N)
    kd = k @ d
    errors = [np.max(np.abs((tl.force(u + h * d) - tl.force(u - h * d)) / (2 * h) - kd)) / np.max(np.abs(kd))
              for h in (1e-4, 1e-5)]
    assert errors[1] < 1e-7
    assert math.log10(errors[0] / errors[1]) == pytest.approx(2.0, abs=0.1)  # central difference: O(h²)
    assert abs(k - k.T).max() <= 1e-12 * abs(k).max()


def test_rigid_rotation_is_stress_free(body):
    """Turn the ring by 0.05 rad: the Green strain vanishes exactly, so does the internal force."""
    basis, tl, _ = body
    x, y = basis.doflocs
    a = 0.05
    u = np.empty(basis.N)
    u[0::2] = (math.cos(a) - 1) * x[0::2] - math.sin(a) * y[0::2]
    u[1::2] = math.sin(a) * x[1::2] + (math.cos(a) - 1) * y[1::2]
    k, f = tl(u)
    k0, _ = tl(np.zeros(basis.N))
    assert np.max(np.abs(f)) < 1e-9 * np.max(np.abs(k0 @ u))  # linear elasticity: k0·u ≠ 0


def test_nonlinear_tends_to_linear_as_the_deflection_shrinks():
    """Same ring on scaled cosine cams: (ω_nl − ω_lin)/w0 ∝ w0 (the geometric terms are
    O(w0²)); observed ratio 10.0 per decade of w0."""
    params = RingParameters(48.95, 0.9, 209000.0, 0.295)
    diffs = []
    for w0 in (0.5, 0.05):
        cam = CosineCam(params.bore_radius_mm, w0)
        lin = solve_ring(params, contour=cam, divisions=32, gap_tol_mm=1e-9 * w0)
        nl = solve_ring(params, contour=cam, divisions=32, geometry="nonlinear", gap_tol_mm=1e-9 * w0,
                        newton_tol_mm=1e-12 * w0 / 1e-2)
        diffs.append(np.max(np.abs(nl.omega_mm - lin.omega_mm)) / w0)
    assert diffs[0] > 1e-5  # a cosine cam holds the whole bore: the geometric terms show as ~60 nm
    assert diffs[0] / diffs[1] == pytest.approx(10.0, rel=0.1)


@pytest.fixture(scope="module")
def gearset():
    from profilegen.gearset import default_gearset_path, load_gearset

    return load_gearset(default_gearset_path())


def test_nonlinear_cam_solution_physics(gearset):
    from profilegen.geometry.wavegen import from_gearset

    default_set = gearset
    cam = from_gearset(default_set)
    res = solve_ring(default_set, contour=cam, geometry="nonlinear")
    lin = solve_ring(default_set, contour=cam)
    w0 = default_set.deflection_mm
    # the major axis stays on the cam (trap 7): ω(0) at the bore = w0 to sub-nm
    assert abs(res.bore_omega_mm[0] - w0) < 1e-6
    assert res.max_penetration_mm <= 1e-9 and res.max_gap_mm <= 1e-9
    assert np.all(res.contact_force_n > 0)
    # modified Newton (linear stiffness): linear convergence down to newton_tol_mm
    assert res.newton_steps_mm[-1] <= 1e-10 and res.newton_steps_mm[0] > 1e-3
    # equilibrium of the quarter: contact forces + cut reactions = 0 (scale: E·w0 terms)
    force = (res.contact_force_n[:, None] * res.contact_normal).sum(axis=0)
    scale = default_set.material.youngs_modulus_mpa * w0
    assert abs(force[0] + res.reaction_major_cut_n) < 1e-11 * scale
    assert abs(force[1] + res.reaction_minor_cut_n) < 1e-11 * scale
    # DESIGN trap 7: geometric nonlinearity changes ω by ~µm (here ~10 µm), υ by a few µm
    d_w = np.max(np.abs(res.omega_mm - lin.omega_mm))
    assert 1e-3 < d_w < 3e-2
    assert res.to_dict()["geometry"] == "nonlinear"


def test_bad_geometry_names_the_parameter():
    params = RingParameters(48.95, 0.9, 209000.0, 0.295)
    with pytest.raises(RingError, match="geometry"):
        solve_ring(params, contour=EllipticalCam(49.0, 48.0), geometry="large")
    with pytest.raises(RingError, match="mesh"):
        solve_ring(params, contour=EllipticalCam(49.0, 48.0), mesh="coarse")


def test_newton_iteration_limit_raises(gearset):
    from profilegen.geometry.wavegen import from_gearset

    default_set = gearset
    with pytest.raises(ConvergenceError, match="Newton"):
        solve_ring(default_set, contour=from_gearset(default_set), geometry="nonlinear", max_iterations=3)
