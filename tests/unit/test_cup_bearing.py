"""The wave-generator bearing's outer race under the 3D cup (profilegen.rim.cup.bearing and
``press_cup(race=...)``), against things the solver does not compute itself:

* the race's radial compliance is ring theory's for two diametral forces (Roark: the diameter
  along the loads grows by (π/4 − 2/π) P R³/EI, the other shrinks by (2/π − 1/2) P R³/EI), and
  its mean the hoop strain P R/(π E A);
* its tilt stiffness: a uniform tilt turns the ring into a cone (hoop strain βζ/R: E I_z/R²),
  the n = 1 tilt is the race's rigid tilt about a diameter (no stiffness), holding the race
  axially only stiffens it;
* the limit cases: a stiff race stress-free on the contour on rigid balls is the rigid band
  (the model before, ``race=None``), the difference falling as the race's compliance, 1/t³;
  a race free to tilt on a rigid ball row carries the bore's force at each angle with no
  moment about the ball row (equilibrium of each section);
* a long cup on a race free to tilt: ring theory's ω = w0 cos 2φ on a cosine cam at the ball
  row, and the race tilts with the cup's generator (the bore's slope across the band);
* complementarity of both contacts (bore on race, race on balls; Hertz approach where loaded).

Coarse meshes (4 mm, 6–8 angles); tests/benchmarks/bearing_tilt.py has the scenes' numbers.
"""

import math

import numpy as np
import pytest

from profilegen.rim.cup import CupError, CupGeometry, harmonic_stiffness, meridional_mesh, press_cup
from profilegen.rim.cup.bearing import FREE_FRACTION, BearingRace, cup_tier_race
from profilegen.geometry.wavegen import CosineCam

from tests.cups import NU, R_M, T, W0, E, cam, cup


def race(geom, **kw):
    args = dict(thickness_mm=2.5, width_mm=geom.bearing_width_mm, ball_row_z_mm=geom.bearing_center_mm,
                outer_radius_mm=geom.bore_radius_mm, youngs_modulus_mpa=E, poisson_ratio=NU)
    args.update(kw)
    return BearingRace(**args)


GEOM = cup()


@pytest.fixture(scope="module")
def coarse():
    return harmonic_stiffness(meridional_mesh(GEOM, element_mm=4.0, layers=2))


def _omega_ends(c):
    g = c.deformation.geometry
    lo, hi = g.ring_span_mm
    phi = np.array([0.0, 0.5 * math.pi])
    return np.array([[float(c.deformation.omega(p, z)) for z in (lo, hi)] for p in phi])


# --------------------------------------------------------------------------- the race alone


def test_radial_compliance_is_ring_theory_for_two_diametral_forces():
    r = race(GEOM)
    angles = 200
    orders = 2 * np.arange(angles)
    cw, _ = r.compliances(orders)
    ei = E * r.section()["i_bending_mm4"]
    big_r = r.radius_mm
    p = 0.5  # a unit force group at φ = 0 is two forces of 1/2 at 0 and π
    along = float(np.sum(cw[1:]))  # radial at φ = 0 (n ≥ 2)
    across = float(np.sum(cw[1:] * np.cos(orders[1:] * 0.5 * math.pi)))
    assert 2 * along == pytest.approx((math.pi / 4 - 2 / math.pi) * p * big_r ** 3 / ei, rel=1e-5)
    assert 2 * across == pytest.approx(-(2 / math.pi - 0.5) * p * big_r ** 3 / ei, rel=1e-5)
    assert cw[0] == pytest.approx(p * big_r / (math.pi * E * r.section()["area_mm2"]), rel=1e-12)


def test_tilt_stiffness_cone_rigid_tilt_and_the_axial_hold():
    r, held, free = race(GEOM), race(GEOM, tilt="held"), race(GEOM, tilt="free")
    s = r.section()
    cone = E * s["i_tilt_mm4"] / r.radius_mm ** 2  # hoop strain βζ/R over the section
    assert r.tilt_stiffness(0) == pytest.approx(cone, rel=1e-12)
    assert held.tilt_stiffness(0) == pytest.approx(cone, rel=1e-12)
    assert r.tilt_stiffness(1) == 0.0  # the rigid tilt about a diameter
    for n in range(2, 30, 2):
        assert 0.0 < r.tilt_stiffness(n) < held.tilt_stiffness(n)
        assert free.tilt_stiffness(n) == pytest.approx(FREE_FRACTION * r.tilt_stiffness(n), rel=1e-12)
    # a torsion-free section (G J → 0) cannot resist the n ≥ 2 tilt when it may warp axially
    assert r.tilt_stiffness(2) < 0.05 * held.tilt_stiffness(2)


def test_ball_loads_smear_the_angle_force_over_its_arc():
    r = race(GEOM, ball_count=20)
    phi = 0.5 * math.pi * np.arange(5) / 4
    # a uniform line load q: interior angles carry q R Δφ × 4 copies, the ends half of that × 2 copies... a ball 2πR q/N
    q = 3.0
    force = q * r.radius_mm * (phi[1] - phi[0]) * np.array([2.0, 4.0, 4.0, 4.0, 2.0])
    assert np.allclose(r.ball_loads(force, phi), 2 * math.pi * r.radius_mm * q / 20)


# --------------------------------------------------------------------------- the cup on the race


def test_a_stiff_stress_free_race_on_rigid_balls_is_the_rigid_band(coarse):
    """The race's compliance is 1/E: ×10 stiffer, the difference from the rigid band ÷ 10."""
    kw = dict(contour=cam(), gap="exact", harmonic_basis=coarse, angles=8)
    band = _omega_ends(press_cup(GEOM, **kw))
    diffs = []
    for factor in (100.0, 1000.0):
        stiff = race(GEOM, youngs_modulus_mpa=factor * E, prestress=False, tilt="held")
        diffs.append(np.max(np.abs(_omega_ends(press_cup(GEOM, race=stiff, **kw)) - band)))
    assert diffs[1] < 1e-4 * W0
    assert diffs[0] / diffs[1] == pytest.approx(10.0, rel=0.2)


def test_a_race_free_to_tilt_carries_the_bore_at_each_angle_with_no_moment(coarse):
    free = race(GEOM, thickness_mm=20.0, tilt="free", prestress=False)  # bending-stiff, free to tilt
    c = press_cup(GEOM, contour=cam(), gap="first_order", harmonic_basis=coarse, angles=8, race=free)
    arm = c.z_mm - free.ball_row_z_mm
    per_angle = c.force_n.sum(axis=0)
    scale = float(per_angle.max())
    assert scale > 0.0
    assert np.max(np.abs((arm[:, None] * c.force_n).sum(axis=0))) < 3e-5 * scale * GEOM.bearing_width_mm
    assert np.max(np.abs(c.ball_force_n - per_angle)) < 1e-3 * scale
    # it tilts: the rigid band's ω at the face ends is not kept
    band = press_cup(GEOM, contour=cam(), gap="first_order", harmonic_basis=coarse, angles=8)
    assert np.max(np.abs(_omega_ends(c) - _omega_ends(band))) > 0.02 * W0


def test_a_long_cup_on_a_race_free_to_tilt_is_ring_theory_and_the_race_follows_its_generator():
    """Far from the diaphragm and the open end (the band 6 bending lengths √(r t) from each) the
    ball row's section is ring theory's, and the free race takes the cup generator's slope (the
    cup still cones, ω ∝ z: ~w0/l) where the bore bears at both band edges (the major axis)."""
    g = CupGeometry(R_M, T, 300.0, 80.0, T, 0.5 * R_M, E, NU, bearing_width_mm=8.0)
    free = race(g, thickness_mm=20.0, tilt="free", prestress=False)
    c = press_cup(g, contour=CosineCam(g.bore_radius_mm, W0), element_mm=4.0, angles=8, race=free)
    phi = np.linspace(0.0, 0.5 * math.pi, 19)
    d = c.deformation
    assert np.max(np.abs(d.omega(phi, 300.0) - W0 * np.cos(2 * phi))) < 0.015 * W0
    assert c.force_n[0, 0] > 0.0 and c.force_n[-1, 0] > 0.0  # both band edges bear at the major axis
    lo, hi = g.bearing_span_mm
    slope = (float(d.omega(0.0, hi)) - float(d.omega(0.0, lo))) / (hi - lo)
    assert c.race_tilt_rad[0] == pytest.approx(slope, rel=1e-3)
    assert 0.8 * W0 / 300.0 < slope < 1.3 * W0 / 300.0


def test_both_contacts_are_complementary_and_the_loaded_balls_reach_the_contour(coarse):
    r = race(GEOM, hertz_coefficient_mm=2.5e-4)  # the ring, bent onto Hertz balls
    c = press_cup(GEOM, contour=cam(), gap="exact", nonlinear=True, harmonic_basis=coarse, angles=8, race=r)
    scale = float(np.max(c.force_n))
    assert np.all(c.force_n >= 0.0) and np.all(c.ball_force_n >= 0.0)
    assert c.max_penetration_mm < 1e-9 and np.max(np.abs(c.force_n * c.gap_mm)) < 1e-9 * scale
    row = int(np.argmin(np.abs(c.z_mm - r.ball_row_z_mm)))
    assert c.z_mm[row] == pytest.approx(r.ball_row_z_mm)
    reach = c.race_radial_mm[row] - c.load_mm + c.ball_approach_mm  # race − (contour − Hertz approach)
    on = c.ball_force_n > 0.0
    assert 0 < on.sum() < on.size  # the race lifts off its balls about the minor axis
    assert np.max(np.abs(reach[on])) < 1e-8 and np.min(reach[~on]) > -1e-8
    q = r.ball_loads(c.ball_force_n, c.phi_rad)
    assert np.allclose(c.ball_approach_mm[q >= 1.0], 2.5e-4 * q[q >= 1.0] ** (2.0 / 3.0), rtol=1e-6)
    import json

    assert json.loads(json.dumps(c.to_dict()))["race"]["tilt"] == "ring"


# --------------------------------------------------------------------------- inputs


def test_from_gearset_takes_the_bearing_and_the_contact_models_balls():
    from profilegen.contact.chain import BallBearing
    from profilegen.contact.compliance import default_race_thickness_mm
    from profilegen.gearset import default_gearset_path, load_gearset

    gs = load_gearset(default_gearset_path())
    g = CupGeometry.from_gearset(gs)
    r = cup_tier_race(gs, g, "ring")
    assert (r.width_mm, r.ball_row_z_mm, r.outer_radius_mm) == (g.bearing_width_mm, g.bearing_center_mm,
                                                                g.bore_radius_mm)
    assert r.thickness_mm == default_race_thickness_mm(gs.gear)
    assert r.hertz_coefficient_mm == BallBearing.from_gearset(gs).hertz_coefficient()
    assert cup_tier_race(gs, g, "rigid") is None and cup_tier_race(gs, g, "held").tilt == "held"
    assert r.tilt == "ring" and r.prestress and cup_tier_race(gs, g, "free").tilt == "free"


@pytest.mark.parametrize("kw, name", [({"thickness_mm": -1.0}, "thickness_mm"), ({"width_mm": 0.0}, "width_mm"),
                                      ({"tilt": "loose"}, "tilt"), ({"prestress": 1}, "prestress"),
                                      ({"ball_count": 2}, "ball_count"), ({"hertz_coefficient_mm": -1.0},
                                                                          "hertz_coefficient_mm"),
                                      ({"thickness_mm": 60.0}, "thickness_mm")])
def test_bad_race_fields_are_named(kw, name):
    with pytest.raises(CupError, match=name):
        race(GEOM, **kw)


def test_bad_race_arguments_are_named(coarse):
    with pytest.raises(CupError, match="race"):
        press_cup(GEOM, contour=cam(), harmonic_basis=coarse, angles=6, race="ring")
    with pytest.raises(CupError, match="ball_row_z_mm"):
        press_cup(GEOM, contour=cam(), harmonic_basis=coarse, angles=6, race=race(GEOM, ball_row_z_mm=20.0))
    from profilegen.gearset import default_gearset_path, load_gearset

    with pytest.raises(CupError, match="model"):
        cup_tier_race(load_gearset(default_gearset_path()), None, "loose")


def test_the_rim_stage_cup_tier_puts_the_chosen_race_under_the_bore(monkeypatch):
    """The cup tier takes :data:`CUP_TIER_RACE`: ``rigid`` is the rigid band (no race on the
    result), ``ring`` the race, whose face ends differ from the band's (the cup's cone about the
    ball row: the diaphragm end lower) — and the stage's coarse companion (its error estimate)
    runs on the same race."""
    import profilegen.rim.cup.bearing as bearing
    from profilegen.gearset import default_gearset_path, load_gearset
    from profilegen.rim.stage import RimTier, solve_rim

    tier = RimTier("cup3d", "cup", geometry="linear", layers=2, divisions=0, max_order=16, element_mm=4.0, angles=8)
    gs = load_gearset(default_gearset_path())
    runs = {}
    for model in ("rigid", "ring"):
        monkeypatch.setattr(bearing, "CUP_TIER_RACE", model)
        runs[model] = solve_rim(gs, tier=tier)
    assert runs["rigid"].cup_contact.race is None
    race = runs["ring"].cup_contact.race
    assert race is not None and race.tilt == "ring" and any("outer race" in w for w in runs["ring"].warnings)
    lo, hi = runs["ring"].cup.geometry.ring_span_mm
    assert runs["ring"].cup.omega(0.0, lo) < runs["rigid"].cup.omega(0.0, lo) - 0.02 * gs.deflection_mm
    assert runs["ring"].error_estimate_mm < 0.1 * gs.deflection_mm  # the coarse companion agrees: the same race
