"""Validation of profilegen.geometry.kinematics against a direct simulation of the mechanism.

Sources:

* DESIGN.md, Known trap 1 (seed 004 corrected): with the CS fixed, the wave generator
  (WG) turned by ψ and the flexspline (FS) carrier by −ψU/z1 (the reduction i = −z1/U of
  a harmonic drive with fixed circular spline), the tooth whose undeformed polar angle is
  β has φ = β − ψ; for the tooth with carrier angle 0 this gives β = (U/z2)·φ, not
  (U/z1)·φ. Successive FS teeth must generate CS spaces exactly 2π/z2 apart (closure);
  the U/z1 mix-up leaves a ~31 µm closure error around the CS.
* Differential geometry of a plane curve: the tooth axis is the outward normal of the
  deformed neutral line, i.e. perpendicular to dP/dθ at fixed ψ. Here that tangent is a
  *numerical* derivative of the simulated neutral line, so no atan2 formula of the
  package is reused.
* Envelope theory (Litvin, Gear Geometry and Applied Theory, ch. 6): the meshing function
  of a one-parameter family Q(t, φ) is f = ∂Q/∂φ × ∂Q/∂t; here both partials are finite
  differences of the placed tooth points.

Everything here is computed from the mechanism's own definition (ω, υ written out as
formulas in this file), never from the package's intermediate values.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from profilegen.geometry.deformation import HarmonicDeformation, ring_theory
from profilegen.geometry.kinematics import HarmonicDriveMotion, RackMotion
from profilegen.geometry.teeth import dcta_tooth

M, Z1, Z2, U, RM, W0 = 0.5, 200, 202, 2, 48.95, 0.5
TOOTH = dcta_tooth(module_mm=M, teeth=Z1, neutral_radius_mm=RM)
# tooth-frame points: the DCTA tip corner (both sides), its pitch point (π m/4, r1 − r_m),
# a root point, and a point far from the axis
POINTS = np.array(
    [TOOTH.tip_point, TOOTH.tip_point * [-1, 1], [math.pi * M / 4, M * Z1 / 2 - RM], TOOTH.root_point, [-0.7, 0.2]]
)

# two deformations, each with its ω, υ written out independently of the package:
# ring theory (υ′ = −ω) and a three-harmonic stretchable one (υ′ ≠ −ω, so the υ′ term in
# the normal's tilt matters)
HARM = dict(cos_mm=[0.48, 0.03, -0.004], sin_mm=[-0.25, 0.006, 0.001], mean_mm=0.01)


def _ring(phi):
    return W0 * np.cos(U * phi), -W0 / U * np.sin(U * phi)


def _harm(phi):
    k = np.arange(1, 4)[:, None] * U
    w = np.asarray(HARM["cos_mm"]) @ np.cos(k * phi[None]) + HARM["mean_mm"]
    u = np.asarray(HARM["sin_mm"]) @ np.sin(k * phi[None])
    return w, u


CASES = {
    "ring": (_ring, ring_theory(W0, U)),
    "three harmonics": (_harm, HarmonicDeformation(waves=U, **HARM)),
}


def _turn(p, a):
    """Turn points by a about the origin (polar angles from +y toward +x)."""
    c, s = np.cos(a), np.sin(a)
    return np.stack([p[..., 0] * c + p[..., 1] * s, -p[..., 0] * s + p[..., 1] * c], -1)


def _neutral(theta, psi, disp, beta_rate=None):
    """Deformed neutral-line point of the material point at carrier angle θ (WG at ψ).

    Mechanism: carrier turned by −ψU/z1, so β = θ − ψU/z1, φ = β − ψ. ``beta_rate``
    replaces this by the (wrong) model β = beta_rate·φ, φ = θ − ψ z2/z1 (trap 1).
    """
    theta = np.asarray(theta, float)
    beta = theta - psi * U / Z1
    phi = beta - psi
    if beta_rate is not None:
        beta = beta_rate * phi
    w, u = disp(np.atleast_1d(phi))
    er = np.stack([np.sin(beta), np.cos(beta)], -1)
    et = np.stack([np.cos(beta), -np.sin(beta)], -1)
    return (RM + w)[:, None] * er + u[:, None] * et


def _tooth_in_cs(k, psi, disp, points, h=1e-3, beta_rate=None):
    """Tooth k's points in the CS frame, by simulation: origin on the deformed neutral line,
    y along its outward normal (tangent dP/dθ by a 5-point difference, error ~h⁴)."""
    theta = 2 * math.pi * k / Z1
    st = theta + h * np.array([-2.0, -1.0, 1.0, 2.0])
    P = _neutral(np.concatenate([[theta], st]), psi, disp, beta_rate)
    origin = P[0]
    tangent = (P[1] - 8 * P[2] + 8 * P[3] - P[4]) / (12 * h)
    x_axis = tangent / np.hypot(*tangent)  # toward increasing θ (increasing φ)
    y_axis = np.array([-x_axis[1], x_axis[0]])  # x turned 90° counter-clockwise: outward
    return origin + points[:, :1] * x_axis + points[:, 1:] * y_axis


def _polar_angle(p):
    return np.arctan2(p[..., 0], p[..., 1])


# ----------------------------------------------------------------------------- mechanism


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("k", [0, 1, 7, 199])
def test_pose_equals_mechanism_simulation(case, k):
    """DESIGN trap 1: package pose(φ_k), turned by k·2π/z2, is tooth k of the simulated mechanism."""
    disp, model = CASES[case]
    motion = HarmonicDriveMotion(model, RM, U, Z2)
    theta = 2 * math.pi * k / Z1
    worst = 0.0
    for psi in np.linspace(-4 * math.pi, 4 * math.pi, 41) + 0.123:  # many WG angles, several turns
        phi = theta - psi * U / Z1 - psi  # φ = β − ψ of tooth k
        sim = _tooth_in_cs(k, psi, disp, POINTS)
        pose = motion.pose(np.full(len(POINTS), phi))
        pkg = _turn(pose.to_cs(POINTS), k * 2 * math.pi / Z2)
        worst = max(worst, np.max(np.hypot(*(pkg - sim).T)))
    assert worst <= 1e-9


@pytest.mark.parametrize("case", CASES)
def test_closure_successive_teeth_exactly_one_cs_pitch_apart(case):
    """DESIGN trap 1: tooth k at the same φ as tooth 0 is turned by exactly k·2π/z2."""
    disp, model = CASES[case]
    motion = HarmonicDriveMotion(model, RM, U, Z2)
    for psi0 in (0.0, 0.4, -1.3, 2.9):
        phi = -psi0 * Z2 / Z1  # tooth 0 (θ = 0): φ = −ψ(1 + U/z1)
        ref = _polar_angle(_tooth_in_cs(0, psi0, disp, POINTS))
        for k in (1, 2, 7, 101, 199):
            # tooth k reaches the same φ when the WG has turned on by k·2π/z2
            psi = psi0 + 2 * math.pi * k / Z2
            assert abs((2 * math.pi * k / Z1 - psi * U / Z1 - psi) - phi) <= 1e-12
            ang = _polar_angle(_tooth_in_cs(k, psi, disp, POINTS))
            gap = np.angle(np.exp(1j * (ang - ref - 2 * math.pi * k / Z2)))
            assert np.max(np.abs(gap)) <= 1e-12
    # the package: one pass φ ∈ [−π/U, π/U] ends where the next tooth's begins (turned by
    # 2π/z2), and a full WG turn (φ → φ + 2π) moves the tooth exactly U CS pitches
    pose = motion.pose(np.array([-math.pi / U, math.pi / U, 0.3, 0.3 + 2 * math.pi]))
    q = pose.to_cs(np.broadcast_to(POINTS[0], (4, 2)))
    gap_pass = np.angle(np.exp(1j * (_polar_angle(q[1]) - _polar_angle(q[0]) - 2 * math.pi / Z2)))
    gap_turn = np.angle(np.exp(1j * (_polar_angle(q[3]) - _polar_angle(q[2]) - U * 2 * math.pi / Z2)))
    assert abs(gap_pass) <= 1e-12 and abs(gap_turn) <= 1e-12
    np.testing.assert_allclose(np.hypot(*q[1]), np.hypot(*q[0]), rtol=0, atol=1e-12)


def test_trap_beta_rate_u_over_z1_breaks_closure():
    """DESIGN trap 1: β = (U/z1)·φ (U/z1 is the rate for ψ, not for φ) leaves a closure gap of
    tens of µm: r·2π(1/z1 − 1/z2) ≈ 15.6 µm per pass, ≈ 31 µm after a full WG turn."""
    disp, _ = CASES["ring"]
    tip = POINTS[:1]

    def pos(phi, rate):
        # tooth 0 at the WG angle that gives it this φ
        return _tooth_in_cs(0, -phi * Z1 / Z2, disp, tip, beta_rate=rate)[0]

    for rate, small in ((U / Z2, True), (U / Z1, False)):
        # pass closure: the end of tooth 0's pass meets the start of tooth 1's (turned by 2π/z2)
        gap_pass = np.hypot(*(pos(math.pi / U, rate) - _turn(pos(-math.pi / U, rate), 2 * math.pi / Z2)))
        # full-turn closure: one WG turn later the tooth is exactly U CS pitches on
        gap_turn = np.hypot(*(pos(0.3 + 2 * math.pi, rate) - _turn(pos(0.3, rate), U * 2 * math.pi / Z2)))
        if small:
            assert gap_pass <= 1e-9 and gap_turn <= 1e-9
        else:
            assert gap_pass > 10e-3 and gap_turn > 10e-3
            # the size is the angle mismatch 2π(1/z1 − 1/z2) per pass times the tip radius there
            mismatch = 2 * math.pi * (1 / Z1 - 1 / Z2)
            r_pass, r_turn = np.hypot(*pos(math.pi / U, rate)), np.hypot(*pos(0.3, rate))
            assert gap_pass == pytest.approx(r_pass * mismatch, rel=1e-3)
            assert gap_turn == pytest.approx(U * r_turn * mismatch, rel=1e-3)
            assert 25e-3 < gap_turn < 35e-3  # DESIGN: "~31 µm"


# ----------------------------------------------------------------------------- derivatives


def _d5(fun, x, h):
    return (fun(x - 2 * h) - 8 * fun(x - h) + 8 * fun(x + h) - fun(x + 2 * h)) / (12 * h)


@pytest.mark.parametrize("case", CASES)
def test_pose_derivatives_match_finite_differences(case):
    motion = HarmonicDriveMotion(CASES[case][1], RM, U, Z2)
    phi = np.linspace(-math.pi, math.pi, 61) + 0.01
    pose = motion.pose(phi)
    h = 1e-3
    np.testing.assert_allclose(pose.origin_d1, _d5(lambda x: motion.pose(x).origin, phi, h), rtol=0, atol=1e-9)
    np.testing.assert_allclose(pose.origin_d2, _d5(lambda x: motion.pose(x).origin_d1, phi, h), rtol=0, atol=1e-9)
    np.testing.assert_allclose(pose.angle_d1, _d5(lambda x: motion.pose(x).angle, phi, h), rtol=0, atol=1e-10)
    np.testing.assert_allclose(pose.angle_d2, _d5(lambda x: motion.pose(x).angle_d1, phi, h), rtol=0, atol=1e-10)
    _, a_d = pose.meshing_coefficients()
    np.testing.assert_allclose(a_d, _d5(lambda x: motion.pose(x).meshing_coefficients()[0], phi, h), rtol=0, atol=1e-9)


def test_tooth_axis_is_the_neutral_line_normal():
    """The tooth frame's y axis is perpendicular to the deformed neutral line traced by O(φ)
    at fixed ψ — checked here from the package's own O alone: at fixed ψ the neutral line is
    {(r_m + ω(φ)) e_r(β) + υ(φ) e_t(β)} with β = φ + ψ, not the path O(φ) of one tooth."""
    disp, model = CASES["three harmonics"]
    motion = HarmonicDriveMotion(model, RM, U, Z2)
    phi = np.linspace(-1.5, 1.5, 31)
    pose = motion.pose(phi)
    psi = phi * (U / Z2) - phi  # β − φ for the tooth at φ
    h = 1e-3

    def line(x, s):
        w, u = disp(x)
        b = x + s
        return (RM + w)[:, None] * np.stack([np.sin(b), np.cos(b)], -1) + u[:, None] * np.stack([np.cos(b), -np.sin(b)], -1)

    tangent = _d5(lambda x: line(x, psi), phi, h)
    np.testing.assert_allclose(line(phi, psi), pose.origin, rtol=0, atol=1e-12)
    e_r = np.stack([np.sin(pose.angle), np.cos(pose.angle)], -1)  # the tooth's y axis
    assert np.max(np.abs(np.sum(tangent * e_r, -1)) / np.hypot(*tangent.T)) <= 1e-11


# ----------------------------------------------------------------------------- meshing function


@pytest.mark.parametrize(
    "motion",
    [HarmonicDriveMotion(CASES["three harmonics"][1], RM, U, Z2), HarmonicDriveMotion(ring_theory(W0, U), RM, U, Z2), RackMotion(50.0)],
    ids=["harmonic drive (3 harmonics)", "harmonic drive (ring)", "rack"],
)
def test_meshing_coefficients_are_the_cross_product(motion):
    """f = a·[p·p′, p′_y, p′_x] equals ∂Q/∂φ × ∂Q/∂t, both partials by finite differences of Q."""
    # t inside the three DCTA segments, away from the joins (the curvature jumps there)
    br = TOOTH.breakpoints
    t = np.concatenate([np.linspace(a + 0.01, b - 0.01, 7) for a, b in zip(br[:-1], br[1:])])
    # the pass for the harmonic drive; for the rack its working range (|rφ| of a few mm: far out,
    # |Q| ~ rφ inflates the differences' round-off)
    span = 0.1 if isinstance(motion, RackMotion) else 1.4
    phi = np.linspace(-span, span, 15)
    tt, pp = (g.ravel() for g in np.meshgrid(t, phi))

    def Q(t_, phi_):
        return motion.pose(phi_).to_cs(TOOTH.point(t_))

    h = 1e-4
    dq_dphi = _d5(lambda x: Q(tt, x), pp, h)
    dq_dt = _d5(lambda x: Q(x, pp), tt, h)
    cross = dq_dphi[:, 0] * dq_dt[:, 1] - dq_dphi[:, 1] * dq_dt[:, 0]
    p, dp, _ = TOOTH.evaluate(tt)
    a, _ = motion.pose(pp).meshing_coefficients()
    terms = np.stack([np.sum(p * dp, -1), dp[:, 1], dp[:, 0]], -1)
    f = np.sum(a * terms, -1)
    assert np.max(np.abs(cross)) > 0.1  # not a trivially zero comparison
    # FD round-off ~ eps·|Q|/h in each partial: scale the tolerance by the partials' sizes
    scale = np.max(np.hypot(*dq_dphi.T)) * np.max(np.hypot(*dq_dt.T))
    np.testing.assert_allclose(f, cross, rtol=0, atol=1e-10 * max(scale, 1.0))


def test_rack_motion_rolls_without_slip():
    """RackMotion: the rack's pitch-line point (−rφ, 0) is the instant centre, on the pitch circle."""
    r = 50.0
    motion = RackMotion(r)
    phi = np.linspace(-0.3, 0.3, 13)
    pose = motion.pose(phi)
    c = np.stack([-r * phi, np.zeros_like(phi)], -1)
    q = pose.to_cs(c)
    np.testing.assert_allclose(np.hypot(*q.T), r, atol=1e-12)
    np.testing.assert_allclose(_polar_angle(q), -phi, atol=1e-14)  # the contact point turns with the gear
    velocity = _d5(lambda x: motion.pose(x).to_cs(c), phi, 1e-4)
    assert np.max(np.abs(velocity)) <= 1e-10
    # a rack point far from the pitch line moves at |Φ′|·distance (rigid rotation about the centre)
    c2 = c + [0.0, 0.7]
    v2 = _d5(lambda x: motion.pose(x).to_cs(c2), phi, 1e-4)
    np.testing.assert_allclose(np.hypot(*v2.T), 0.7, atol=1e-10)


@pytest.mark.parametrize("harmonics", [1, 4])
def test_the_frame_alone_is_the_poses_origin_and_angle(harmonics):
    """HarmonicDriveMotion.frame (the swept-region depth's refinement) skips the φ-derivatives:
    its origin and angle are the pose's, bit for bit, for a ring-theory and a many-harmonic
    deformation, at any φ."""
    if harmonics == 1:
        deformation = ring_theory(0.25, 2)
    else:
        deformation = HarmonicDeformation(2, np.array([0.25, -0.012, 0.003, -0.0007]),
                                          np.array([-0.125, 0.004, -0.001, 0.0002]), mean_mm=0.001)
    motion = HarmonicDriveMotion(deformation, 24.5, 2, 102)
    phi = np.linspace(-3.5, 3.5, 1001)
    origin, angle = motion.frame(phi)
    pose = motion.pose(phi)
    assert np.array_equal(origin, pose.origin) and np.array_equal(angle, pose.angle)
    o1, a1 = motion.frame(0.3)
    assert o1.shape == (1, 2) and np.array_equal(a1, motion.pose(0.3).angle)
