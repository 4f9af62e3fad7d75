"""Tooth deviations and eccentricity in the loaded contact (research.tooth_errors,
issue 16): both zones as one problem on the FS's whole ring.

* zero deviations: each zone carries T/2 (found by the whole gear's balance, not imposed) and
  the rotation is the one-zone model's — torsional_curve's mesh and mesh + Hertz balls;
* a uniform tangential offset s on every tooth is a rigid rotation s/r_p: the curve shifts by
  it, the forces (so the stiffness) do not change;
* with random deviations and with an eccentric CS: equilibrium (Σ_all r F = T, the loads'
  resultant carried by the balls), complementarity of teeth and balls; the eccentricity turned
  by π swaps the two zones;
* both flanks in one problem: the perfect gear is each flank's own curve (the other flank
  stays open); a backlash allowance wider than the load's reach is a rigid shift of the
  one-flank answer; an interference preloads the gear (both flanks loaded at rest) and
  makes it stiffer;
* ISO 1328-1:2013 eq. (5)/(8) at one value worked by hand.
"""

import math

import numpy as np
import pytest

from profilegen.contact.chain import compliance_chain, torsional_curve
from profilegen.contact.compliance import ContactCompliance
from profilegen.contact.inputs import ContactInput
from research.tooth_errors import (ToothErrorError, TwoZoneContact, draw_deviations,
                                             eccentricity_offsets_rad, iso1328_tolerances_um)

T1, T2 = 54.0, 196.0


@pytest.fixture(scope="module")
def zones(default_sketch):
    """The default set's sketch design: torsional_curve at T1, T2 (every ball one-sided, the
    flanks' points and compliance built there) and both zones of the right flank as one problem."""
    curve = torsional_curve(default_sketch, [-T1, T1, T2], catalogue=None, breakpoints_nm=(T1, T2))
    pts, comp = curve.sides[1]
    inputs = ContactInput.from_design(default_sketch)
    return curve, pts, TwoZoneContact(inputs, pts, comp), compliance_chain(inputs.gearset).bearing


def _check_physics(sol, two, torque_nm, theta):
    """Σ r F = T over both zones, Σ loads = 0 (balls take the resultant), F, R ≥ 0, gaps ≥ 0, F g = 0."""
    tz = torque_nm * 1e3
    assert float((two.sign * two.lever) @ sol.force_n) == pytest.approx(tz, rel=1e-10)
    assert sol.zone_moment_nmm.sum() == pytest.approx(tz, rel=1e-10)
    x = np.concatenate([sol.force_n, sol.reaction_n])
    assert np.linalg.norm(two.directions.T @ x) <= 1e-9 * x.max()
    assert x.min() >= 0.0
    # the gaps recomputed from the definition, not taken from the solver
    cmat = two.c.copy()
    if sol.springs_mm_per_n is not None:
        cmat[two.n:, two.n:] += np.diag(sol.springs_mm_per_n)
    w = cmat @ x + np.concatenate([two.lever * theta, two.ball_gap]) - np.concatenate(
        [two.sign * two.lever, np.zeros(two.nb)]) * sol.phi_rad + two.directions @ sol.translation_mm
    scale = float(np.abs(w).max())
    assert w.min() >= -1e-9 * scale
    assert float(np.max(np.abs(x * w))) <= 1e-9 * scale * x.max()


def test_iso1328_by_hand():
    """d = 100 mm, m = 0.5 mm, class 5: f_pT = 0.001·100 + 0.4·0.5 + 5 = 5.3 µm, f_fαT = 0.55·0.5 + 5
    = 5.275 µm; each class is √2 times the one below."""
    tol = iso1328_tolerances_um(100.0, 0.5, 5)
    assert tol["f_pt_um"] == pytest.approx(5.3, rel=1e-12)
    assert tol["f_falpha_um"] == pytest.approx(5.275, rel=1e-12)
    assert iso1328_tolerances_um(100.0, 0.5, 6)["f_pt_um"] == pytest.approx(5.3 * math.sqrt(2.0), rel=1e-12)
    assert not tol["extrapolated"] and iso1328_tolerances_um(80.0, 0.4, 5)["extrapolated"]
    with pytest.raises(ToothErrorError, match="grade"):
        iso1328_tolerances_um(100.0, 0.5, 12)


def test_perfect_gear_is_the_one_zone_model(zones):
    curve, pts, two, bearing = zones
    theta0 = float(pts.theta_rad.min())
    for i, t in enumerate(curve.torque_nm):
        if t < 0:
            continue
        rigid = two.solve(t)
        springs = two.solve(t, bearing=bearing)
        # each zone half the torque: the whole gear's balance finds it
        np.testing.assert_allclose(rigid.zone_moment_nmm, [t * 1e3 / 2] * 2, rtol=1e-8)
        assert rigid.phi_rad - theta0 == pytest.approx(curve.mesh_rad[i] - theta0, rel=1e-6)
        assert springs.phi_rad - theta0 == pytest.approx(curve.mesh_balls_rad[i] - theta0, rel=2e-5)
        n = pts.count
        teeth = [np.unique(pts.tooth[springs.force_n[z * n:(z + 1) * n] > 0.0]).size for z in (0, 1)]
        assert teeth == [int(curve.teeth_in_contact[i])] * 2
        _check_physics(rigid, two, t, two.theta)


def test_uniform_offset_is_a_rigid_rotation(zones):
    """Every tooth moved by s along the pitch circle: θ_k + s/r_p for every point; the balls do
    not see a rotation, so φ moves by exactly s/r_p and the forces stay."""
    _, pts, two, _ = zones
    r_p = 0.5 * two.gearset.gear.module_mm * two.gearset.gear.flexspline_teeth
    s = 3e-3  # mm
    base = two.solve(T1)
    moved = two.solve(T1, np.full(2 * pts.count, s / r_p))
    assert moved.phi_rad - base.phi_rad == pytest.approx(s / r_p, rel=1e-9)
    np.testing.assert_allclose(moved.force_n, base.force_n, atol=1e-9 * base.force_n.max())


def test_deviations_equilibrium_and_complementarity(zones):
    """A grade-6 draw: the zones no longer carry T/2 each, fewer teeth carry load than in the
    perfect gear, and the solution is still the complementarity problem's."""
    _, pts, two, bearing = zones
    gs = two.gearset
    tol = iso1328_tolerances_um(gs.gear.module_mm * gs.gear.flexspline_teeth, gs.gear.module_mm, 6)
    off = draw_deviations(pts, gs, np.random.default_rng(3), pitch_sigma_mm=tol["f_pt_um"] / 2e3,
                          profile_sigma_mm=tol["f_falpha_um"] / 2e3)
    perfect = two.solve(T1)
    sol = two.solve(T1, off, bearing=bearing)
    _check_physics(sol, two, T1, two.theta + off)
    assert abs(sol.zone_moment_nmm[0] - sol.zone_moment_nmm[1]) > 1e-3 * T1 * 1e3
    assert sol.teeth_loaded < perfect.teeth_loaded


def test_eccentricity_turned_by_pi_swaps_the_zones(zones):
    _, pts, two, _ = zones
    n = pts.count
    e = 0.01
    a = two.solve(T1, eccentricity_offsets_rad(pts, e, 0.3))
    b = two.solve(T1, eccentricity_offsets_rad(pts, e, 0.3 + math.pi))
    _check_physics(a, two, T1, two.theta + eccentricity_offsets_rad(pts, e, 0.3))
    assert a.phi_rad == pytest.approx(b.phi_rad, rel=1e-9)
    np.testing.assert_allclose(a.force_n[:n], b.force_n[n:], atol=1e-8 * a.force_n.max())
    np.testing.assert_allclose(a.zone_moment_nmm, b.zone_moment_nmm[::-1], rtol=1e-8)
    # the shrunk zone carries more
    assert abs(a.zone_moment_nmm[0] - a.zone_moment_nmm[1]) > 0.05 * T1 * 1e3


def test_floating_wave_generator_absorbs_the_eccentricity(zones):
    """A wave generator free to move radially (an Oldham coupling) follows the CS: FS and cam
    translate by e together and every gap is the concentric gear's again, up to the
    linearisation (the FE model's directions are the undeformed tooth's, the gaps' the
    deformed tooth's normals). Held on the WG axis, the same e moves the split and the rotation."""
    _, pts, two, _ = zones
    off = eccentricity_offsets_rad(pts, 0.01, 0.7)
    perfect = two.solve(T1)
    held = two.solve(T1, off)
    floating = two.solve(T1, off, wave_generator="floating")
    np.testing.assert_allclose(floating.zone_moment_nmm, [T1 * 1e3 / 2] * 2, rtol=2e-3)
    assert floating.phi_rad == pytest.approx(perfect.phi_rad, rel=2e-3)
    assert abs(held.phi_rad - perfect.phi_rad) > 0.03 * perfect.phi_rad
    # the curve's zero: the rigid gear's first contact, held = min θ, floating = the concentric gear's
    theta0 = float(pts.theta_rad.min())
    assert two.first_contact_rad() == pytest.approx(theta0, rel=1e-9)
    assert two.first_contact_rad(off) == pytest.approx(float(np.min(two.theta + off)), rel=1e-9)
    assert two.first_contact_rad(off, wave_generator="floating") == pytest.approx(theta0, rel=2e-3)
    assert floating.resultant_n <= 1e-9 * floating.force_n.max()
    assert floating.force_n.min() >= 0.0 and floating.gap_mm.min() >= -1e-12 and floating.ball_gap_mm.min() >= -1e-12


def test_bad_offsets(zones):
    _, pts, two, _ = zones
    with pytest.raises(ToothErrorError, match="offsets_rad"):
        two.solve(T1, np.zeros(3))
    with pytest.raises(ToothErrorError, match="torque_nm"):
        two.solve(0.0)


@pytest.fixture(scope="module")
def flanks(default_sketch, zones):
    """Both flanks of both zones as one problem (the compliance built for their points together)."""
    curve, pts, _, bearing = zones
    left = curve.sides[-1][0]
    inputs = ContactInput.from_design(default_sketch)

    def cat(f):
        return np.concatenate([getattr(pts, f), getattr(left, f)])

    comp = ContactCompliance.build(inputs, cat("fs_point_mm"), cat("normal"), cat("tooth"), cat("cs_point_mm"),
                                   ball_supports="all")
    return curve, pts, left, TwoZoneContact(inputs, [pts, left], comp), bearing


def test_both_flanks_perfect_gear_and_backlash(flanks, zones):
    curve, right, left, both, bearing = flanks
    one = zones[2]
    r_p = 0.5 * both.gearset.gear.module_mm * both.gearset.gear.flexspline_teeth
    for t in (T1, -T1):
        sol = both.solve(t, bearing=bearing)
        ref = curve.mesh_balls_rad[list(curve.torque_nm).index(t)]
        assert sol.phi_rad == pytest.approx(ref, rel=2e-5)
        # only the loaded flank carries: the other's points stay open
        n = right.count + left.count
        on_right = np.concatenate([np.arange(right.count), n + np.arange(right.count)])
        carried = sol.force_n[on_right].sum() if t > 0 else sol.force_n.sum() - sol.force_n[on_right].sum()
        assert carried == pytest.approx(sol.force_n.sum(), rel=1e-12)
        _check_physics(sol, both, t, both.theta)
    # a backlash allowance j (j/2 on each flank) wider than the load's reach: the one-flank answer, shifted by j/2r_p
    j = 0.04
    shift = 0.5 * j / r_p
    wide = both.solve(T1, np.full(both.theta.size, shift))
    assert wide.phi_rad - one.solve(T1).phi_rad == pytest.approx(shift, rel=1e-7)


def test_interference_preloads_both_flanks(flanks):
    """Every tooth 1 µm too thick (j = −2 µm): at rest both flanks press (the right flank's
    moment equals the left's), the loaded gear is stiffer than the perfect one, and the
    solution is complementary with both flanks."""
    _, right, left, both, bearing = flanks
    r_p = 0.5 * both.gearset.gear.module_mm * both.gearset.gear.flexspline_teeth
    off = np.full(both.theta.size, -1e-3 / r_p)
    rest = both.solve(1e-3, off)
    n = right.count + left.count
    moment = both.sign * both.lever * rest.force_n
    on_right = np.zeros(both.n, bool)
    on_right[:right.count] = on_right[n:n + right.count] = True
    assert moment[on_right].sum() > 100.0 * 1e-3 * 1e3  # a preload ≫ the applied 1 N·mm
    assert moment[on_right].sum() + moment[~on_right].sum() == pytest.approx(1.0, rel=1e-6)
    loaded = both.solve(T1, off)
    perfect = both.solve(T1)
    assert loaded.phi_rad - rest.phi_rad < 0.9 * (perfect.phi_rad - float(right.theta_rad.min()))
    _check_physics(loaded, both, T1, both.theta + off)
