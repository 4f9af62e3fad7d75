"""Load across the face (research/face_load.py, a study): slices in parallel sharing the rotation.

Checked against things the slice model does not compute itself: the 2D solve (identical
slices must reproduce it exactly, forces ÷ N), a two-slice one-point case solved by hand,
equilibrium and complementarity in every slice, a rigid rotation of the rim (the gap shift
must be −r_k·α), the exact harmonics of a section, and the coupling kernel's row sums."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from research.face_load import FaceLoadError, gap_shift_mm, slice_coupling, slice_positions, solve_face
from profilegen.contact.solvers import solve_lemke
from profilegen.geometry.kinematics import HarmonicDriveMotion, turn


def _problem(n=7, seed=3):
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, n))
    s = (a @ a.T + n * np.eye(n)) * 1e-8  # mm/N, SPD
    gap = rng.uniform(0.0, 4e-3, n)
    gap[2] = 0.0
    lever = rng.uniform(40.0, 50.0, n)
    pts = SimpleNamespace(gap_mm=gap, lever_mm=lever, tooth=np.arange(n) // 2, zones=2)
    return pts, s


def test_identical_slices_reproduce_the_2d_solve():
    pts, s = _problem()
    torque = 120.0  # N·m on the gear, 60 on the zone
    ref = solve_lemke(s, pts.gap_mm / pts.lever_mm, pts.lever_mm, torque / 2 * 1e3)
    for n_s in (1, 3, 5):
        face = solve_face(pts, s, np.zeros((n_s, s.shape[0])), torque, face_width_mm=20.0)
        np.testing.assert_allclose(face.force_n * n_s, np.broadcast_to(ref.force_n, face.force_n.shape),
                                   rtol=1e-9, atol=1e-9 * ref.force_n.max())
        assert face.rotation_rad == pytest.approx(float(ref.phi_rad), rel=1e-12)
        assert face.peak_ratio == pytest.approx(1.0, rel=1e-9)
        np.testing.assert_allclose(face.slice_line_load_n_per_mm, ref.force_n.sum() / 20.0, rtol=1e-9)


def test_two_slices_one_point_by_hand():
    # g_i = r(θ − φ) + δ_i + 2 s F_i = 0 for both slices, r(F_1 + F_2) = T → F_1 − F_2 = (δ_2 − δ_1)/(2 s)
    s, r, e, t_zone = 2e-7, 45.0, 1e-3, 30.0e3
    pts = SimpleNamespace(gap_mm=np.array([e]), lever_mm=np.array([r]), tooth=np.array([0]), zones=1)
    d1, d2 = -2e-4, -1e-4  # (δ_2 − δ_1)/(2s) = 250 N < T/r = 667 N: both slices loaded
    face = solve_face(pts, [[s]], [[d1], [d2]], t_zone * 1e-3, face_width_mm=10.0)
    total = t_zone / r
    f1 = 0.5 * (total + (d2 - d1) / (2 * s))
    np.testing.assert_allclose(face.force_n[:, 0], [f1, total - f1], rtol=1e-10)
    phi = (e + d1 + 2 * s * f1) / r
    assert face.rotation_rad == pytest.approx(phi, rel=1e-10)
    # beyond the shift difference the second slice opens: all on the first
    face = solve_face(pts, [[s]], [[d1], [d1 + 2 * s * total * 1.01]], t_zone * 1e-3)
    np.testing.assert_allclose(face.force_n[:, 0], [total, 0.0], atol=1e-9 * total)


def test_equilibrium_and_complementarity_in_every_slice():
    pts, s = _problem(n=9, seed=11)
    rng = np.random.default_rng(5)
    n_s = 4
    shift = rng.uniform(-3e-3, 3e-3, (n_s, 9))  # some gaps below zero (preload)
    for lam in (0.0, 4.0):
        face = solve_face(pts, s, shift, 80.0, face_width_mm=16.0, coupling_length_mm=lam)
        moment = float((face.force_n * pts.lever_mm).sum())
        assert moment == pytest.approx(80.0 / 2 * 1e3, rel=1e-12)
        k = slice_coupling(n_s, lam, 4.0)
        deflection = (np.kron(k, s) @ face.force_n.ravel()).reshape(n_s, 9)
        gap = pts.gap_mm + shift - pts.lever_mm * face.rotation_rad + deflection
        assert gap.min() > -1e-12
        assert np.max(np.abs(gap * face.force_n)) < 1e-12 * 80.0
        assert np.all(face.force_n >= 0.0)
    assert any("preloaded" in w for w in face.warnings)


def test_coupling_keeps_an_even_load_and_is_spd():
    k = slice_coupling(6, 5.0, 2.0)
    np.testing.assert_allclose(k.sum(axis=1), 6.0, rtol=1e-12)
    np.testing.assert_allclose(k, k.T)
    assert np.linalg.eigvalsh(k).min() > 0.0
    np.testing.assert_array_equal(slice_coupling(6, 0.0, 2.0), 6.0 * np.eye(6))
    pts, s = _problem()
    ref = solve_face(pts, s, np.zeros((1, 7)), 50.0)
    face = solve_face(pts, s, np.zeros((6, 7)), 50.0, coupling_length_mm=5.0, face_width_mm=12.0)
    np.testing.assert_allclose(face.force_n * 6, np.broadcast_to(ref.force_n, (6, 7)), rtol=1e-8,
                               atol=1e-9 * ref.force_n.max())


class _Constant:
    def __init__(self, omega, upsilon):
        self.omega, self.upsilon = omega, upsilon

    def evaluate(self, phi, order=3):
        phi = np.atleast_1d(phi)
        w, u = np.zeros((order + 1, phi.size)), np.zeros((order + 1, phi.size))
        w[0], u[0] = self.omega, self.upsilon
        return w, u


def test_gap_shift_of_a_rigid_rotation():
    # υ = c on an undeformed rim turns every tooth rigidly by atan(c/r_m): Δe_k = −α (p × n) to O(c²)
    rm, z2 = 48.675, 202
    motion = HarmonicDriveMotion(_Constant(0.0, 0.0), rm, 2, z2)
    rng = np.random.default_rng(2)
    tooth = np.array([-20, -3, 0, 7, 31])
    phi = 2 * math.pi * tooth / 200
    local = np.column_stack([rng.uniform(-0.4, 0.4, 5), rng.uniform(-0.3, 0.5, 5)])
    ang = rng.uniform(0, 2 * math.pi, 5)
    normal = np.column_stack([np.cos(ang), np.sin(ang)])
    pose = motion.pose(phi)
    p = np.array([turn(pose.to_cs(local[i:i + 1])[i], 2 * math.pi * tooth[i] / z2) for i in range(5)])
    pts = SimpleNamespace(local_mm=local, phi_rad=phi, tooth=tooth, normal=normal)
    c = 1e-5
    shift = gap_shift_mm(pts, motion, _Constant(0.0, c), _Constant(0.0, 0.0))
    alpha = math.atan2(c, rm)
    expected = -alpha * (p[:, 1] * normal[:, 0] - p[:, 0] * normal[:, 1])
    np.testing.assert_allclose(shift, expected, rtol=1e-5, atol=1e-12)
    # a radial shift ω = c moves the tooth frame outward by c along its radius (no tilt): Δe = −c n·e_r
    shift = gap_shift_mm(pts, motion, _Constant(c, 0.0), _Constant(0.0, 0.0))
    gamma = 2.0 / z2 * phi + 2 * math.pi * tooth / z2  # the tooth frame's polar angle in the CS frame
    e_r = np.column_stack([np.sin(gamma), np.cos(gamma)])
    np.testing.assert_allclose(shift, -c * np.einsum("ij,ij->i", normal, e_r), rtol=1e-6, atol=1e-13)


def test_bad_input_is_named():
    pts, s = _problem()
    with pytest.raises(FaceLoadError, match="gap_shift"):
        solve_face(pts, s, np.zeros((2, 5)), 10.0)
    with pytest.raises(FaceLoadError, match="torque_nm"):
        solve_face(pts, s, np.zeros((2, 7)), 0.0)
    with pytest.raises(FaceLoadError, match="compliance_mm_per_n"):
        solve_face(pts, s[:3, :3], np.zeros((2, 7)), 10.0)
    with pytest.raises(FaceLoadError, match="slices"):
        slice_positions(20.0, 0, 60.0)


def test_two_flanks_one_point_each_by_hand():
    # both flanks overlap by δ at no load (preload): g± = −δ ∓ rφ + s F± = 0 while both carry load, so
    # F+ + F− = 2δ/s, F+ − F− = T/r, φ = (s F+ − δ)/r
    from research.face_load import solve_two_flanks

    s, r, delta = 2e-7, 45.0, 3e-5
    for t_zone_nmm in (0.0, 5e3, -5e3):
        res = solve_two_flanks([-delta, -delta], [r, r], [1, -1], np.diag([s, s]), np.zeros((1, 2)),
                               t_zone_nmm * 1e-3, zones=1)
        fp = 0.5 * (2 * delta / s + t_zone_nmm / r)
        np.testing.assert_allclose(res.force_n[0], [fp, 2 * delta / s - fp], rtol=1e-9)
        assert res.rotation_rad == pytest.approx((s * fp - delta) / r, rel=1e-8, abs=1e-15)
        assert res.equilibrium_residual < 1e-9
    p, m = res.flank_torque_nm
    assert p - m == pytest.approx(-5.0, rel=1e-9)


def test_two_flanks_reduce_to_the_one_flank_solve_when_the_other_stays_open():
    from research.face_load import solve_two_flanks

    pts, s = _problem(n=6, seed=7)
    # a second flank 0.1 mm away cannot touch at this torque: the loaded flank's Lemke solution
    gap = np.r_[pts.gap_mm, np.full(6, 0.1)]
    big = np.block([[s, 0.3 * s], [0.3 * s, s]])
    res = solve_two_flanks(gap, np.r_[pts.lever_mm, pts.lever_mm], np.r_[np.ones(6), -np.ones(6)], big,
                           np.zeros((3, 12)), 60.0, zones=2)
    ref = solve_lemke(s, pts.gap_mm / pts.lever_mm, pts.lever_mm, 30.0e3)
    np.testing.assert_allclose(res.force_n[:, :6].sum(axis=0), ref.force_n, rtol=1e-7, atol=1e-7 * ref.force_n.max())
    assert np.all(res.force_n[:, 6:] == 0.0)
    assert res.rotation_rad == pytest.approx(float(ref.phi_rad), rel=1e-9)
    assert res.complementarity_residual < 1e-9


def test_face_load_on_every_ball_reproduces_the_contact_stage(default_sketch):
    """face_load builds the contact stage's compliance (every ball one-sided at its no-load
    gap): with identical slices (coning "none") its slices are the 2D contact, the balls the 2D
    solve loads held at their gaps — each slice 1/N of the stage's forces, the same rotation.
    Holding them at zero gap instead (the gaps left out) misses the rotation."""
    from profilegen.contact import ContactInput
    from profilegen.contact.analysis import solve_contact
    from research.face_load import face_load

    inputs = ContactInput.from_design(default_sketch)
    torque = inputs.gearset.torque.rated_nm
    stage = solve_contact(inputs, [torque])
    case = stage.cases[0]
    assert stage.compliance.ball_supports == "all"
    assert np.any(case.ball_active & (stage.compliance.ball_gap_mm > 0.0))
    face = face_load(inputs, torque, slices=3, coning="none", points=stage.points, compliance=stage.compliance)
    f = case.solution.force_n
    np.testing.assert_allclose(face.force_n * 3, np.broadcast_to(f, face.force_n.shape), rtol=0,
                               atol=1e-8 * f.max())
    assert face.rotation_rad == pytest.approx(case.rotation_rad, rel=1e-9)
    held = stage.compliance.with_balls(case.ball_active).matrix_mm_per_n
    zero_gap = solve_lemke(held, stage.points.theta_rad, stage.points.lever_mm, case.zone_torque_nm * 1e3)
    assert abs(zero_gap.phi_rad / case.rotation_rad - 1.0) > 1e-3
