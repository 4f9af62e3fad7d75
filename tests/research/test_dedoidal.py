"""The two-zone (dedoidal, n = 1) climb (research.dedoidal, issue 16 item 4).

* By hand: two zones as nonlinear radial springs on a floating body. Each zone one radial
  contact on a radial spring k, the contact's own compliance c₀, its gap G(s) − rφ with
  G(s) = s − s²/(2 s_c) (the flank turning radial as the tooth rides out), the body (the FS and
  wave generator) free along y and held by a cup spring k_c. Solved by hand (module docstring
  of the test): the contact force F = (rφ − G(s))/c₀, s = F/k ∓ τ; the symmetric path
  rφ = G(F/k) + c₀F ends at F* = k s_c (1 + k c₀) (T* = 2 r F*); the eccentric mode's
  stiffness is K = 2G′/(c₀ + G′/k), zero at s = s_c, before the symmetric end; with the cup
  spring the symmetric path loses stability where K + k_c = 0. The climb of the two-zone model
  with a small radial load on the body must leave the symmetric path there and end below T*,
  at the torque an independent solve of the hand equations gives.
* The design (default set, sketch scene, few stations): with no imperfection the two-zone
  climb is the one-zone climb (both zones' torque equal, the rotation's torque the same at the
  same φ); the floating body's equilibrium (Σ loads on the FS = the external load, Σ ball
  reactions on the cam = 0); an eccentricity of the CS is absorbed by the free FS/WG assembly.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from profilegen.contact.climb import climb
from research.dedoidal import DedoidalError, TwoZoneClimb, n1_stiffness, stability_limit

K, C0, R, SC = 1.0e4, 2.0e-5, 50.0, 0.02  # N/mm, mm/N, mm, mm


class _Zone:
    """One radial contact (sin α = 1) whose gap is G(s) − rφ (the test's hand model)."""

    n = 1
    _ci = np.zeros(0, int)
    _a = _b = np.zeros(0)
    slot = np.array([0])
    depth_mm = np.array([10.0])
    corner = np.array([False])
    corner_criterion = False

    def __init__(self):
        self.sin_alpha = np.array([1.0])

    def geometry(self, s, phi=0.0):
        s = float(np.asarray(s)[0])
        return np.array([s - s * s / (2.0 * SC) - R * phi]), np.array([R])


def _toy(**options):
    # built columns per zone: the station, its probe (the tooth's radial retreat); radial spring
    # k under both, c₀ the contact's own; zone 1 at +y (load on the FS along −y), zone 2 at −y
    one = np.array([[1.0 / K + C0, 1.0 / K], [1.0 / K, 1.0 / K]])
    c = np.zeros((4, 4))
    c[:2, :2] = c[2:, 2:] = one
    dirs = np.array([[0.0, -1.0], [0.0, -1.0], [0.0, 1.0], [0.0, 1.0]])
    options.setdefault("wave_generator", "held")
    return TwoZoneClimb(_Zone(), _Zone(), c, dirs, **options)


def _hand_limit(k_cup, load):
    """The largest torque of the path, independently: per φ the hand equations
    F_z = (rφ − G(s_z))/c₀, s₁ = F₁/k − τ, s₂ = F₂/k + τ, F₂ − F₁ − k_c τ + P = 0, solved
    for τ by bisection on the branch the load opens (the continuation from τ = 0)."""

    def zone(phi, tau, sign):
        # s = F/k ∓ τ with F = (rφ − G(s))/c₀: a quadratic in s, the root on the loading branch
        a, b, c = 1.0 / (2.0 * SC * K * C0), -(1.0 + 1.0 / (K * C0)), R * phi / (K * C0) - sign * tau
        disc = b * b - 4.0 * a * c
        if disc < 0.0:
            return None
        s = (-b - math.sqrt(disc)) / (2.0 * a)
        return (R * phi - (s - s * s / (2.0 * SC))) / C0

    def balance(phi, tau):
        f1, f2 = zone(phi, tau, 1.0), zone(phi, tau, -1.0)
        if f1 is None or f2 is None:
            return None
        return f2 - f1 - k_cup * tau + load, f1, f2

    best, tau = 0.0, 0.0
    for phi in np.linspace(1e-6, 2.0e-3, 4001):
        # τ from the last: bracket outward in the load's direction
        lo, hi = tau - 1e-6, tau + 5e-4
        blo, bhi = balance(phi, lo), balance(phi, hi)
        if blo is None or bhi is None or blo[0] * bhi[0] > 0.0:
            break
        tau = brentq(lambda t: balance(phi, t)[0], lo, hi, xtol=1e-14)
        _, f1, f2 = balance(phi, tau)
        best = max(best, R * (f1 + f2) / 1e3)
    return best


def test_hand_model_symmetric_end_and_eccentric_stiffness():
    """No load on the body: the path is the symmetric one and ends at T* = 2 r k s_c (1 + k c₀);
    along it the eccentric stiffness is 2G′/(c₀ + G′/k) at the path's s (prescribed ± δ)."""
    model = _toy(cup_stiffness_n_per_mm=1.0)
    path = climb(model, 1e-5, 2e-5, max_steps=200, max_torque_nm=1e9, max_retreat_step_mm=1e-3, tol_mm=1e-10, max_iterations=60)
    t_star = 2.0 * R * K * SC * (1.0 + K * C0) / 1e3
    for p in path.points:  # the hand equations at every point: F = (rφ − G(s))/c₀, s = F/k
        s, f = p.retreat_mm, p.force_n
        np.testing.assert_allclose(s, f / K, rtol=1e-9)
        np.testing.assert_allclose(f, (R * p.phi_rad - (s - s * s / (2.0 * SC))) / C0, rtol=1e-6)
    # the fold's square root: the last point the fixed point reaches lies a few % below T*
    assert 0.95 * t_star < path.torque_nm <= t_star
    for p in path.points[::15]:
        s = float(p.retreat_mm[0])
        g1 = 1.0 - s / SC
        k_hand = 2.0 * g1 / (C0 + g1 / K)
        k_num = n1_stiffness(model, p, delta_mm=1e-5, tol_mm=1e-11, max_iterations=200)
        assert k_num[1, 1] == pytest.approx(k_hand, rel=1e-4, abs=1e-4 * 2 * K)
        assert abs(k_num[0, 0]) < 1e-6  # nothing resists x but the cup (not counted in K)


def test_hand_model_bifurcation_with_a_cup_spring():
    """A cup spring k_c: the symmetric path loses its eccentric stability where K + k_c = 0,
    at s_b = s_c (1 + k_c c₀ / (2 + k_c / k)), T_b = 2 r k s_b < T*; with a 1 N radial load on
    the body the path leaves the symmetric one and its eccentric mode gives way at the hand
    equations' largest torque, below T_b (the climb's fixed point then jumps to another branch:
    the stability check, not the climb's own end, finds the limit)."""
    k_cup = 0.2 * K
    t_star = 2.0 * R * K * SC * (1.0 + K * C0) / 1e3
    s_b = SC * (1.0 + k_cup * C0 / (2.0 + k_cup / K))
    t_b = 2.0 * R * K * s_b / 1e3
    opts = dict(max_steps=200, max_torque_nm=1e9, max_retreat_step_mm=1e-3, tol_mm=1e-10, max_iterations=60)
    check = dict(cup_stiffness_n_per_mm=k_cup, delta_mm=1e-6, tol_mm=1e-11, max_iterations=60)
    model = _toy(cup_stiffness_n_per_mm=k_cup)
    path = climb(model, 1e-5, 2e-5, **opts)
    sym = stability_limit(model, path, **check)
    assert sym["criterion"] == "eccentric mode"
    assert sym["torque_nm"] == pytest.approx(t_b, rel=1e-2)
    assert path.torque_nm > 1.1 * t_b  # the climb alone runs on along the unstable symmetric path
    loaded = _toy(cup_stiffness_n_per_mm=k_cup, external_force_n=(0.0, 1.0))
    bent = climb(loaded, 1e-5, 2e-5, **opts)
    out = stability_limit(loaded, bent, **check)
    hand = _hand_limit(k_cup, 1.0)
    assert hand < t_b < t_star
    assert out["criterion"] == "eccentric mode"
    assert out["torque_nm"] == pytest.approx(hand, rel=1.5e-2)
    # before it gives way, zone 1 (the load pushes the body toward it) carries more
    stable = [p for p in bent.points if p.torque_nm < hand]
    assert stable[-1].force_n[0] > stable[-1].force_n[1] > 0.0


def test_eccentricity_is_the_cup_springs_load():
    """The FS/WG assembly on a cup spring k_c whose rest position stands e off the CS axis:
    Σ loads + P = k_c (τ − e) (module docstring), so an eccentricity e is the radial load
    P = k_c e on the body: the same path point for point (along +y, direction 0: zone 1, at +y,
    carries more), and the mirror image for −P; without either the zones share alike. Replaces a
    comparison on the design whose free assembly (k_c = 0) could not feel the eccentricity."""
    k_cup, e = 0.2 * K, 2e-3
    opts = dict(max_steps=10, max_torque_nm=1e9, max_retreat_step_mm=1e-3, tol_mm=1e-12, max_iterations=60)
    ecc = climb(_toy(cup_stiffness_n_per_mm=k_cup, eccentricity_mm=e), 1e-5, 2e-5, **opts)
    same = climb(_toy(cup_stiffness_n_per_mm=k_cup).with_imperfection(eccentricity_mm=e), 1e-5, 2e-5, **opts)
    load = climb(_toy(cup_stiffness_n_per_mm=k_cup, external_force_n=(0.0, k_cup * e)), 1e-5, 2e-5, **opts)
    mirror = climb(_toy(cup_stiffness_n_per_mm=k_cup, external_force_n=(0.0, -k_cup * e)), 1e-5, 2e-5, **opts)
    plain = climb(_toy(cup_stiffness_n_per_mm=k_cup), 1e-5, 2e-5, **opts)
    assert len(ecc.points) == len(load.points) == len(same.points) == 10
    for a, b, c, m in zip(ecc.points, load.points, same.points, mirror.points):
        np.testing.assert_allclose(a.force_n, b.force_n, rtol=1e-9)
        np.testing.assert_allclose(c.force_n, b.force_n, rtol=1e-9)
        np.testing.assert_allclose(a.state.translation_mm, b.state.translation_mm, rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(m.force_n, b.force_n[::-1], rtol=1e-9)
    f = ecc.points[-1].force_n
    assert f[0] > 1.01 * f[1] > 0.0  # the eccentricity moves load to zone 1
    assert ecc.points[-1].state.translation_mm[1] > 0.0
    g = plain.points[-1].force_n
    assert g[0] == pytest.approx(g[1], rel=1e-12)


def test_bad_options():
    with pytest.raises(DedoidalError, match="wave_generator"):
        _toy(wave_generator="loose")
    with pytest.raises(DedoidalError, match="cup_stiffness_n_per_mm"):
        _toy(cup_stiffness_n_per_mm=-1.0)
    with pytest.raises(DedoidalError, match="eccentricity_mm"):
        _toy(eccentricity_mm=math.nan)
    with pytest.raises(DedoidalError, match="compliance_mm_per_n"):  # a floating cam needs balls
        _toy(wave_generator="floating")


# --------------------------------------------------------------------------- a design


@pytest.fixture(scope="module")
def design_zones(default_sketch):
    """The default set's sketch design: its one-zone climb (4 stations, teeth within 0.05 mm,
    Hertz balls, the free CS ring, as ratcheting_torque builds it) and the two-zone model."""
    from profilegen.contact import ratchet
    from profilegen.contact.chain import BallBearing
    from profilegen.contact.climb import DesignClimb
    from profilegen.contact.inputs import ContactInput

    inputs = ContactInput.from_design(default_sketch)
    gs = inputs.gearset
    r_mean, thick, width, _ = ratchet._cs_ring_section(gs, inputs)

    def factory(phis):
        ang = np.concatenate([phis, phis + math.pi])
        return ratchet.cs_ring_radial_compliance(ang, phis, mean_radius_mm=r_mean, thickness_mm=thick, width_mm=width,
                                                 youngs_modulus_mpa=float(gs.material.youngs_modulus_mpa))
    bearing = BallBearing.from_gearset(gs)
    zone = DesignClimb(inputs, side=1, stations=4, max_gap_mm=0.05, race_thickness_mm=None, bearing=bearing,
                       ring_factory=factory, ball_supports="all")
    two = TwoZoneClimb.from_design(inputs, zone, bearing=bearing, ring=(r_mean, thick, width))
    theta, phi = zone.first_rotation(float(gs.torque.rated_nm))
    return inputs, zone, two, bearing, (r_mean, thick, width), theta, phi


def test_design_symmetric_two_zone_is_the_one_zone_climb(design_zones):
    """No imperfection: the whole ring with the FS/WG free gives the one-zone climb's torque at
    the same rotations (up to 4 × the rated rotation, the climb's lagged geometry included),
    each zone half of it, and no eccentricity."""
    _, zone, two, _, _, theta, phi = design_zones
    step = 2.0 * (phi - theta)
    one = climb(zone, theta + step, step, max_steps=3, grow=1.0)
    both = climb(two, theta + step, step, max_steps=3, grow=1.0)
    for a, b in zip(one.points, both.points):
        assert b.phi_rad == a.phi_rad
        assert b.torque_nm == pytest.approx(a.torque_nm, rel=1e-6)
        zt = two.zone_torques_nm(b)  # (the levers at the final retreat: the torque's are the last iterate's)
        assert zt[0] == pytest.approx(zt[1], rel=1e-9)
        assert zt.sum() == pytest.approx(b.torque_nm, rel=1e-5)
        assert abs(b.state.translation_mm[0]) < 1e-9  # across the major axis: nothing (the y part is the gauge)


def test_design_floating_body_equilibrium(design_zones):
    """A radial load P on the FS/WG assembly: the contact loads on the FS balance it
    (Σ x d = −P), the balls' reactions on the floating cam balance each other (Σ R e_r = 0),
    x ≥ 0, w ≥ 0, x·w = 0 from the matrices; the loaded zone (the load pushes the assembly
    toward zone 1) carries more torque. (An eccentricity acts only through a cup spring, which
    from_design refuses: it is tested on the hand model, test_eccentricity_is_the_cup_springs_load.)"""
    _, _, two, _, _, theta, phi = design_zones
    load = np.array([0.0, 200.0])
    model = two.with_imperfection(external_force_n=load)
    path = climb(model, phi, phi - theta, max_steps=1)
    p = path.points[-1]
    st = p.state
    model.geometry(p.retreat_mm, p.phi_rad)  # the corner cones at the point
    m_mat, _, d, _, _ = model.matrices(st.springs)
    x = np.concatenate([p.force_n, st.reaction_n])
    np.testing.assert_allclose(d[:, :2].T @ x, -load, atol=1e-8 * load[1])
    np.testing.assert_allclose(d[model.n:, 2:].T @ st.reaction_n, 0.0, atol=1e-8 * st.reaction_n.max())
    assert x.min() >= 0.0
    zt = model.zone_torques_nm(p)
    assert zt[0] > zt[1]
