"""The compliance chain and the torsional curve (profilegen.contact.chain).

Analytic checks: the thin-walled tube against the exact polar moment (ratio 1 + (t/2r)²),
the annulus in in-plane torsion against the tube it becomes when narrow (ratio
(1 − (L/2r)²)²), both against the cup as a body of revolution in scikit-fem (the n = 0
torsion harmonic of profilegen.rim.cup.fourier); Hertz: the sphere on a flat (Johnson
§4.2: a³ = 3PR/4E*, δ = a²/R) and the elliptical contact against Hamrock & Brewe's
curve fits (J. Lubr. Technol. 105 (1983) 171: k = 1.0339 α^0.636, ℰ = 1.0003 + 0.5968/α,
𝔉 = 1.5277 + 0.6023 ln α); the ball springs in the Schur step against a one-point,
one-ball system solved by hand; the series sum; the curve on the default set's sketch
design: monotone, odd (the two flanks are mirror images), the chain softer than the mesh.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

import profilegen as pg
from profilegen.contact.chain import (
    ARCMIN_PER_RAD,
    BallBearing,
    ChainError,
    catalogue_for,
    catalogue_size,
    compliance_chain,
    cup_torsion_fem,
    hertz_point_contact,
    annulus_torsion_stiffness,
    thick_tube_torsion_stiffness,
    torsional_curve,
    tube_torsion_stiffness,
)
from profilegen.contact import ContactInput
from profilegen.contact.compliance import ComplianceError, ContactCompliance


@pytest.fixture(scope="module")
def gearset():
    return pg.load_gearset(pg.default_gearset_path())


# --------------------------------------------------------------------------- tube and annulus


def test_thin_tube_against_the_exact_polar_moment():
    """J_exact = π/2 (r_o⁴ − r_i⁴) = 2π r³ t (1 + (t/2r)²) for r_o,i = r ± t/2."""
    g, length = 80e3, 55.0
    for r, t in ((48.95, 0.9), (20.0, 3.0), (10.0, 4.0)):
        thin = tube_torsion_stiffness(g, r, t, length)
        thick = thick_tube_torsion_stiffness(g, r - t / 2, r + t / 2, length)
        assert thick / thin == pytest.approx(1.0 + (t / (2 * r)) ** 2, rel=1e-12)
    # G J / L by hand for the default wall: 80 GPa, r = 48.95, t = 0.9, L = 55
    assert tube_torsion_stiffness(g, 48.95, 0.9, 55.0) == pytest.approx(80e3 * 2 * math.pi * 48.95 ** 3 * 0.9 / 55.0)


def test_narrow_annulus_is_a_short_tube():
    """An annulus r ± L/2 twisted in its plane: K = 2πG t r³/L · (1 − (L/2r)²)² — the tube's
    formula with the wall's length L, the same family, exactly."""
    g, t, r = 80e3, 0.9, 40.0
    for length in (8.0, 1.0, 0.01):
        ann = annulus_torsion_stiffness(g, t, r - length / 2, r + length / 2)
        tube = tube_torsion_stiffness(g, r, t, length)
        assert ann / tube == pytest.approx((1.0 - (length / (2 * r)) ** 2) ** 2, rel=1e-10)


def test_cup_formulas_against_the_body_of_revolution(gearset):
    """The wall (tube, tooth ring as b/3) and the bottom (annulus) in series against the
    cup's n = 0 harmonic in scikit-fem, for the default cup and a short one whose bottom
    dominates; the FE at two mesh sizes agrees with itself."""
    chain = compliance_chain(gearset)
    formulas = 1.0 / (chain.part("cup_wall").compliance_rad_per_nm + chain.part("cup_bottom").compliance_rad_per_nm)
    coarse = cup_torsion_fem(gearset, element_mm=4.0)
    fine = cup_torsion_fem(gearset, element_mm=2.0)
    assert abs(coarse / fine - 1.0) < 5e-3
    assert abs(formulas / fine - 1.0) < 0.02
    # the bearing under the shorter tooth ring: its width and centre follow the ring's
    bearing = {k: v for k, v in (("bearing_width_mm", 10.0), ("bearing_center_mm", 15.0))
               if hasattr(gearset.cup, k)}
    short = dataclasses.replace(gearset, cup=dataclasses.replace(gearset.cup, length_mm=15.0, face_width_mm=10.0,
                                                                  bottom_thickness_mm=0.6, **bearing))
    chain_s = compliance_chain(short)
    assert chain_s.part("cup_bottom").compliance_rad_per_nm > 3.0 * chain_s.part("cup_wall").compliance_rad_per_nm
    formulas_s = 1.0 / (chain_s.part("cup_wall").compliance_rad_per_nm
                        + chain_s.part("cup_bottom").compliance_rad_per_nm)
    assert abs(formulas_s / cup_torsion_fem(short, element_mm=2.0) - 1.0) < 0.03


def test_a_thinner_cup_wall_is_read(gearset):
    """[cup] wall_thickness_mm below the tooth ring (same bore, 0.6 δ): the chain's cup (wall
    and tooth ring in series, bottom to the wall's mid-surface) against the cup's n = 0
    harmonic in scikit-fem with that wall; softer than the one-thickness cup."""
    t = gearset.gear.rim_thickness_mm
    thin = dataclasses.replace(gearset, cup=dataclasses.replace(gearset.cup, wall_thickness_mm=0.6 * t))
    one, two = compliance_chain(gearset), compliance_chain(thin)
    assert two.part("cup_wall").parameters["wall_thickness_mm"] == pytest.approx(0.6 * t)
    assert two.part("cup_wall").compliance_rad_per_nm > 1.4 * one.part("cup_wall").compliance_rad_per_nm
    formulas = 1.0 / (two.part("cup_wall").compliance_rad_per_nm + two.part("cup_bottom").compliance_rad_per_nm)
    assert abs(formulas / cup_torsion_fem(thin, element_mm=2.0) - 1.0) < 0.03


def test_series_sum_and_parts(gearset):
    chain = compliance_chain(gearset)
    c = sum(1.0 / p.stiffness_nm_per_rad for p in chain.parts)
    assert chain.series_stiffness_nm_per_rad == pytest.approx(1.0 / c, rel=1e-14)
    assert chain.with_mesh(4.55e5) == pytest.approx(1.0 / (1.0 / 4.55e5 + c), rel=1e-14)
    assert chain.with_mesh(4.55e5) < min(4.55e5, chain.series_stiffness_nm_per_rad)
    # the CS ring outside the sector: annulus 1.1 r_p2 … the CS outer radius, 20 mm wide
    cs = chain.part("cs_body")
    g = gearset.material.shear_modulus_mpa
    r_s = 1.1 * gearset.gear.cs_pitch_radius_mm
    assert cs.stiffness_nm_per_rad == pytest.approx(4 * math.pi * g * 20.0 / (r_s ** -2 - 64.0 ** -2) * 1e-3)
    d = chain.to_dict()
    assert {p["name"] for p in d["parts"]} == {"cup_wall", "cup_bottom", "cs_body"} and d["left_out"]


# --------------------------------------------------------------------------- Hertz and the bearing


def test_hertz_sphere_on_flat():
    """Sphere R = 5 mm on a flat, P = 200 N: a³ = 3PR/(4E*), δ = a²/R, p0 = 3P/(2πa²);
    and a nearly circular contact (curvatures 1e-6 apart) joins it continuously."""
    e_star, r, p = 113e3, 5.0, 200.0
    a = (3 * p * r / (4 * e_star)) ** (1 / 3)
    h = hertz_point_contact(p, 1 / r, 1 / r, e_star)
    assert h.semi_major_mm == pytest.approx(a, rel=1e-13) and h.approach_mm == pytest.approx(a * a / r, rel=1e-13)
    assert h.max_pressure_mpa == pytest.approx(3 * p / (2 * math.pi * a * a), rel=1e-13)
    # slightly elliptical: δ of the sphere of radius R_e = (R'R'')^(1/2) to first order in B/A − 1,
    # on both sides of the switch to the sphere formula (B/A − 1 = 1e-5)
    for eps in (1e-7, 1e-6, 2e-5, 1e-4):
        near = hertz_point_contact(p, 1 / r, (1 + eps) / r, e_star)
        assert near.approach_mm == pytest.approx(h.approach_mm * (1 + eps) ** (1 / 6), rel=2 * eps ** 2 + 1e-13)
    # δ ∝ P^(2/3)
    assert hertz_point_contact(8 * p, 1 / r, 2 / r, e_star).approach_mm == pytest.approx(
        4 * hertz_point_contact(p, 1 / r, 2 / r, e_star).approach_mm, rel=1e-10)


@pytest.mark.parametrize("alpha", [2.0, 5.0, 10.0, 30.0])
def test_hertz_ellipse_against_hamrock_brewe(alpha):
    e_star, w, rx = 1e5, 100.0, 10.0
    ry = alpha * rx
    h = hertz_point_contact(w, 1 / rx, 1 / ry, e_star)
    k = 1.0339 * alpha ** 0.636
    ell = 1.0003 + 0.5968 / alpha
    fk = 1.5277 + 0.6023 * math.log(alpha)
    r_eff = 1 / (1 / rx + 1 / ry)
    delta = fk * ((9 / (2 * ell * r_eff)) * (w / (math.pi * k * 2 * e_star)) ** 2) ** (1 / 3)
    assert h.approach_mm == pytest.approx(delta, rel=0.02)
    assert h.semi_major_mm / h.semi_minor_mm == pytest.approx(k, rel=0.02)


def test_bearing_estimate_and_fit(gearset):
    b = BallBearing.from_gearset(gearset)
    assert b.ball_count == 23 and b.ball_diameter_mm == pytest.approx(7.5) and b.estimates
    # the groove conforms: the outer contact is softer than the inner (flatter in the rolling plane)
    sums = b.curvature_sums()
    assert sums["outer"][0] < sums["inner"][0]
    q = np.array([10.0, 300.0])
    assert np.allclose(b.approach_mm(q), b.hertz_coefficient() * q ** (2 / 3))
    assert np.allclose(b.secant_compliance_mm_per_n(q) * q, b.approach_mm(q))
    with pytest.raises(ChainError, match="ball_count"):
        BallBearing.from_gearset(gearset, ball_count=40)
    with pytest.raises(ChainError, match="race_thickness_mm"):
        BallBearing.from_gearset(gearset, ball_diameter_mm=30.0, race_thickness_mm=20.0)


# --------------------------------------------------------------------------- ball springs in the Schur step


def _one_point_one_ball(spring):
    """n = 1 point, 1 ball: 2D flexibilities (mm per N/mm) cc, cb, bb and a CS part, b = 20 mm."""
    cc, cb, bb, cs, b = 4.0e-3, -2.5e-3, 3.0e-3, 1.0e-3, 20.0
    comp = ContactCompliance._assemble(
        flex_cc=np.array([[cc]]), flex_cb=np.array([[cb]]), flex_bb=np.array([[bb]]), cs_flex=np.array([[cs]]),
        face_width_mm=b, tooth=np.array([0]), ball_angle_rad=np.array([0.0]), ball_active=np.array([True]),
        wrap_half_angle_rad=0.5, wrap_source="given", dof={}, time_s={}, mesh={}, warnings=())
    return comp if spring is None else comp.with_balls([True], ball_compliance_mm_per_n=spring), (cc, cb, bb, cs, b)


def test_ball_spring_schur_step_by_hand():
    c = 2e-5  # mm/N, the order of a Hertz ball at a few hundred N
    comp, (cc, cb, bb, cs, b) = _one_point_one_ball(c)
    assert comp.matrix_mm_per_n[0, 0] == pytest.approx((cc - cb * cb / (bb + c * b)) / b + cs / b, rel=1e-14)
    f = 150.0
    r = comp.ball_reactions([f])[0]
    assert r == pytest.approx(-cb * f / (bb + c * b), rel=1e-14)
    # the bore at the ball moves in by the spring's compression c·R
    assert comp.ball_gaps_mm([f])[0] == pytest.approx(-c * r, rel=1e-12)
    rigid, _ = _one_point_one_ball(None)
    assert rigid.matrix_mm_per_n[0, 0] == pytest.approx((cc - cb * cb / bb) / b + cs / b, rel=1e-14)
    zero, _ = _one_point_one_ball(0.0)
    assert zero.matrix_mm_per_n[0, 0] == pytest.approx(rigid.matrix_mm_per_n[0, 0], rel=1e-14)
    soft, _ = _one_point_one_ball(1e6)  # a spring that carries nothing: the ball is as good as gone
    assert soft.matrix_mm_per_n[0, 0] == pytest.approx((cc + cs) / b, rel=1e-8)
    # kept through with_balls, dropped with None
    assert comp.with_balls([True]).ball_compliance_mm_per_n[0] == c
    assert comp.with_balls([True], ball_compliance_mm_per_n=None).ball_compliance_mm_per_n is None
    with pytest.raises(ComplianceError, match="ball_compliance_mm_per_n"):
        comp.with_balls([True], ball_compliance_mm_per_n=[-1.0])


# --------------------------------------------------------------------------- the torsional curve


@pytest.fixture(scope="module")
def sketch_design(gearset):
    """The default set's sketch design with the loaded contact, which runs the whole gear's
    torsional curve too (pipeline._with_contact)."""
    return pg.design(gearset, scene="sketch", contact=True, stress=False)


@pytest.fixture(scope="module")
def sides(sketch_design):
    """Both flanks' points and compliance: the contact stage's right flank and the left one
    built with its wrap angle (the sketch scene has no rim FEM: a flat-ring solve otherwise)."""
    from profilegen.contact import ContactInput
    from profilegen.contact.points import contact_points

    right = sketch_design.contact
    inputs = ContactInput.from_design(sketch_design)
    left = contact_points(inputs, side=-1)
    comp = ContactCompliance.build(inputs, left.fs_point_mm, left.normal, left.tooth, left.cs_point_mm,
                                   wrap_half_angle_rad=right.compliance.wrap_half_angle_rad,
                                   ball_supports=right.compliance.ball_supports)  # the stage's: every ball
    return {1: (right.points, right.compliance), -1: (left, comp)}


@pytest.fixture(scope="module")
def curve(sketch_design, sides):
    return torsional_curve(sketch_design, [-265.0, -54.0, -8.0, 8.0, 54.0, 265.0, 196.0, -196.0], sides=sides)


def test_curve_monotone_odd_and_softer_with_the_chain(curve):
    t = curve.torque_nm
    assert np.all(np.diff(t) > 0) and t[0] == -265.0
    for rot in (curve.mesh_rad, curve.mesh_balls_rad, curve.rotation_rad):
        assert np.all(np.diff(rot) > 0)
        # odd: the left flank under −T mirrors the right flank under +T
        assert np.allclose(rot[::-1], -rot, rtol=2e-3, atol=1e-9)
    assert curve.odd_symmetry_defect < 2e-3
    # each addition makes the gear softer; the series parts add exactly |T| Σ 1/K_i
    mag = np.abs(t)
    assert np.all(np.abs(curve.mesh_balls_rad) > np.abs(curve.mesh_rad))
    assert np.allclose(np.abs(curve.rotation_rad) - np.abs(curve.mesh_balls_rad),
                       mag * curve.chain.series_compliance_rad_per_nm, rtol=1e-12)
    k = curve.k_nm_per_rad
    for name in ("K1", "K2", "K3"):
        assert k["total"]["positive"][name] < k["mesh_balls"]["positive"][name] < k["mesh"]["positive"][name]
    # more teeth take load as the torque grows: the gear stiffens, K1 < K2 < K3
    kt = k["total"]["positive"]
    assert kt["K1"] < kt["K2"] < kt["K3"]
    # lost motion spans the backlash and the elastic rotation at ±3 % of the rated torque
    assert curve.backlash_rad >= 0.0
    assert curve.lost_motion_rad["total"] > curve.lost_motion_rad["mesh"] > curve.backlash_rad
    c = curve.compliances_at_rated
    assert c["total_rad_per_nm"] == pytest.approx(sum(v for kk, v in c.items() if kk != "total_rad_per_nm"))
    d = curve.to_dict()
    assert len(d["torque_nm"]) == len(d["rotation_arcmin"]) == 8 and d["hysteresis_arcmin"] is None


def test_curve_bad_input(gearset):
    with pytest.raises(ChainError, match="torques_nm"):
        torsional_curve(None, [54.0, 0.0])
    with pytest.raises(ChainError, match="lost_motion_fraction"):
        torsional_curve(None, [54.0], chain=compliance_chain(gearset), lost_motion_fraction=2.0, sides={})


def test_continuation_equals_the_reference(curve, sketch_design):
    """The curve by continuation in T on reduced systems against the reference path (every
    torque from scratch: Lemke on the assembled compliance, settling and springs around it):
    the same problem, so the same answer to the springs' tolerance."""
    torques = [-265.0, -20.0, 20.0, 265.0]
    fast = torsional_curve(sketch_design, torques, sides=curve.sides, spring_tol=1e-10, breakpoints_nm=(20.0, 265.0))
    ref = torsional_curve(sketch_design, torques, sides=curve.sides, spring_tol=1e-10, breakpoints_nm=(20.0, 265.0),
                          method="lemke")
    assert np.allclose(fast.mesh_rad, ref.mesh_rad, rtol=1e-12, atol=0.0)
    for name in ("mesh_balls_rad", "rotation_rad"):
        assert np.allclose(getattr(fast, name), getattr(ref, name), rtol=1e-9, atol=0.0)
    assert np.array_equal(fast.teeth_in_contact, ref.teeth_in_contact)
    assert np.array_equal(fast.active_balls, ref.active_balls) and fast.flags == ref.flags
    for label in ("mesh", "mesh_balls", "total"):
        for side in ("positive", "negative"):
            for key, value in ref.k_nm_per_rad[label][side].items():
                assert fast.k_nm_per_rad[label][side][key] == pytest.approx(value, rel=1e-8)
    with pytest.raises(ChainError, match="method"):
        torsional_curve(sketch_design, [54.0], sides=curve.sides, method="newton")


def test_whole_gear_in_the_design_outputs(sketch_design):
    """design.json["contact"]["torsional"] and contact.json["torsional"] (issue 16's names):
    present, finite, units in the names; the rigid-ball rotation at the rated torque is Lemke's
    answer from scratch for the same flank with every ball a one-sided support (the curve's
    default), and stiffer than the contact stage's window."""
    from profilegen.output.files import _whole_gear

    head = sketch_design.to_dict()["contact"]["torsional"]
    for key in ("k1_nm_per_rad", "k2_nm_per_rad", "k3_nm_per_rad", "lost_motion_arcmin", "backlash_arcmin"):
        assert math.isfinite(head[key]) and head[key] >= 0.0
    assert head["breakpoints_source"] == "catalogue" and head["catalogue_source"]
    tors = _whole_gear(sketch_design)["torsional"]
    json.dumps(tors, allow_nan=False)
    t = np.array(tors["torque_nm"])
    assert t.size >= 20 and (t < 0).sum() >= 10 and (t > 0).sum() >= 10
    assert np.all(np.isfinite(tors["rotation_arcmin"])) and len(tors["rotation_arcmin"]) == t.size
    assert tors["catalogue"]["source"] and "K1_nm_per_rad" in tors["catalogue"]["compared"]
    assert set(tors["compliances"]) >= {"mesh_rad_per_nm", "ball_hertz_rad_per_nm", "cup_wall_rad_per_nm",
                                        "cup_bottom_rad_per_nm", "cs_body_rad_per_nm", "total_rad_per_nm"}
    rated = sketch_design.gearset.torque.rated_nm
    lemke = sketch_design.contact.cases[0]
    assert lemke.torque_nm == rated
    mesh = np.array(tors["rotation_mesh_arcmin"])[t == rated][0] / ARCMIN_PER_RAD
    pts, window = sketch_design.contact.points, sketch_design.contact.compliance
    every = ContactCompliance.build(ContactInput.from_design(sketch_design), pts.fs_point_mm, pts.normal, pts.tooth,
                                    pts.cs_point_mm, wrap_half_angle_rad=window.wrap_half_angle_rad,
                                    ball_supports="all")
    sol, _, _ = every.solve_unilateral(pts.theta_rad, pts.lever_mm, rated / pts.zones * 1e3)
    assert mesh == pytest.approx(sol.phi_rad, rel=1e-9)
    # the contact stage's rated case solves the same model (every ball one-sided): the same rotation
    assert "one-sided balls" in lemke.solution.method and mesh == pytest.approx(lemke.rotation_rad, rel=1e-9)


def test_stiffnesses_follow_their_definitions_from_the_arrays(sketch_design):
    """K1 = T1/φ(T1), K2 = (T2 − T1)/(φ(T2) − φ(T1)), K3 = (T3 − T2)/(φ(T3) − φ(T2)) on the
    elastic rotation (first contact θ0 taken out), lost motion = φ(+f T_r) − φ(−f T_r), the
    total compliance at the rated torque = (φ(T_r) − θ0)/T_r — recomputed from contact.json's
    torque and rotation arrays."""
    from profilegen.output.files import _whole_gear

    tors = _whole_gear(sketch_design)["torsional"]
    t = np.array(tors["torque_nm"])
    rot = np.array(tors["rotation_arcmin"]) / ARCMIN_PER_RAD

    def phi(torque):
        hit = np.flatnonzero(np.isclose(t, torque, rtol=1e-12, atol=0.0))
        assert hit.size == 1, torque
        return rot[hit[0]]

    bp = tors["breakpoints_nm"]
    t1, t2, t3 = bp["T1"], bp["T2"], bp["T3"]
    for sign, name, key in ((1, "positive", None), (-1, "negative", None)):
        th0 = tors["first_contact_arcmin"][name] / ARCMIN_PER_RAD
        e1, e2, e3 = (sign * phi(sign * tt) - th0 for tt in (t1, t2, t3))
        k = tors["stiffness_nm_per_rad"]["total"][name]
        assert k["K1"] == pytest.approx(t1 / e1, rel=1e-12)
        assert k["K2"] == pytest.approx((t2 - t1) / (e2 - e1), rel=1e-12)
        assert k["K3"] == pytest.approx((t3 - t2) / (e3 - e2), rel=1e-12)
    assert tors["k1_nm_per_rad"] == tors["stiffness_nm_per_rad"]["total"]["positive"]["K1"]
    f_t = tors["lost_motion_torque_nm"]
    assert f_t == pytest.approx(0.03 * sketch_design.gearset.torque.rated_nm)
    assert tors["lost_motion_arcmin"] == pytest.approx((phi(f_t) - phi(-f_t)) * ARCMIN_PER_RAD, rel=1e-12)
    rated = sketch_design.gearset.torque.rated_nm
    th0 = tors["first_contact_arcmin"]["positive"] / ARCMIN_PER_RAD
    assert tors["compliances"]["total_rad_per_nm"] == pytest.approx((phi(rated) - th0) / rated, rel=1e-12)
    # the catalogue comparison is the model's value over the table's
    cmp = tors["catalogue"]["compared"]["K1_nm_per_rad"]
    assert cmp["model_over_catalogue"] == pytest.approx(tors["k1_nm_per_rad"] / tors["catalogue"]["K1_nm_per_rad"])


def test_catalogue_size_and_table(gearset):
    """Size = the nominal pitch diameter in tenths of an inch: the default set's 100 mm is size
    40 (101.6 mm); a 70 mm gear is no catalogue size (64 and 81 mm are the nearest)."""
    assert catalogue_size(gearset) == 40
    cat = catalogue_for(gearset)
    assert cat["size"] == 40 and cat["source"] and "ratio 100" in cat["note"] and cat["ratio"] != 100
    from types import SimpleNamespace

    odd = SimpleNamespace(gear=SimpleNamespace(module_mm=0.35, flexspline_teeth=200), ratio=100.0)
    assert catalogue_size(odd) is None and catalogue_for(odd) is None
    size25 = SimpleNamespace(gear=SimpleNamespace(module_mm=0.4, flexspline_teeth=160), ratio=80.0)  # 64 mm
    assert catalogue_size(size25) == 25


def test_ratcheting_and_transmission_error_in_the_outputs(sketch_design):
    """The verify scene's extras as the outputs carry them (small runs of the real estimates:
    two ratcheting torques, two wave-generator positions): contact.json's ratcheting_torque_nm
    and transmission_error (psi_deg, error_arcsec, peak_to_peak_arcsec) and design.json's
    headline, finite; a torque at or beyond the ratcheting estimate is flagged in the curve and
    fails the verdict, one below it does not."""
    from profilegen.contact import ContactInput
    from profilegen.contact.ratchet import ratcheting_torque
    from profilegen.contact.transmission import transmission_error
    from profilegen.output.files import _whole_gear

    inputs = dataclasses.replace(ContactInput.from_design(sketch_design),
                                 rim_contact_angle_rad=sketch_design.contact.compliance.wrap_half_angle_rad)
    ratchet = ratcheting_torque(inputs, options=dict(torques_nm=[132.5, 265.0], climb=False))  # the climb: test_ratchet.py
    te = transmission_error(inputs, 265.0, positions=2, workers=1)
    design = dataclasses.replace(sketch_design, ratcheting=ratchet, transmission=te)
    out = _whole_gear(design)
    json.dumps(out, allow_nan=False)
    assert out["ratcheting_torque_nm"] == ratchet.torque_nm > 0.0
    e = out["transmission_error"]
    assert len(e["psi_deg"]) == len(e["error_arcsec"]) == 2
    assert e["peak_to_peak_arcsec"] == pytest.approx(max(e["error_arcsec"]) - min(e["error_arcsec"]))
    head = design.to_dict()["contact"]
    assert head["ratcheting_torque_nm"] == ratchet.torque_nm
    assert head["transmission_error"]["peak_to_peak_arcsec"] == e["peak_to_peak_arcsec"]
    # the verdict checks a bound, estimate / the model's largest overestimate at the set's ratio, over the
    # momentary torque
    from profilegen.pipeline.design import ratcheting_overestimate

    overestimate, _ = ratcheting_overestimate(design.gearset.ratio)

    need = 1200.0 * design.gearset.requirements.ratcheting_margin
    assert any("ratcheting" in f for f in design.verdict.failures) == (ratchet.torque_nm / overestimate < need)
    low = dataclasses.replace(design, ratcheting=dataclasses.replace(ratchet, torque_nm=500.0))
    flags = _whole_gear(low)["torsional"]["beyond_ratcheting"]
    torques = np.array(_whole_gear(low)["torsional"]["torque_nm"])
    assert [f is not None for f in flags] == list(np.abs(torques) >= 500.0)
    failures = " ".join(low.verdict.failures)
    assert f"the bound {500.0 / overestimate:.4g} N·m (estimate 500 N·m" in failures
    assert "momentary torque 1200 N·m" in failures


def test_continuation_falls_back_to_the_reference(curve, sketch_design, monkeypatch):
    """A torque whose reduced loop gives up (cycles) is solved by the reference path, and the
    torques after it continue from the last converged state: the same curve."""
    from profilegen.contact import chain

    torques = [-54.0, 20.0, 54.0]
    plain = torsional_curve(sketch_design, torques, sides=curve.sides, breakpoints_nm=(20.0, 54.0))
    solve = chain.ReducedZone.solve
    given_up = []

    def flaky(self, magnitude_nm, state, **kw):
        if magnitude_nm == 20.0 and kw["springs_on"]:
            given_up.append(magnitude_nm)
            return None
        return solve(self, magnitude_nm, state, **kw)

    monkeypatch.setattr(chain.ReducedZone, "solve", flaky)
    mixed = torsional_curve(sketch_design, torques, sides=curve.sides, breakpoints_nm=(20.0, 54.0))
    assert given_up == [20.0, 20.0]  # both flanks
    assert np.allclose(mixed.rotation_rad, plain.rotation_rad, rtol=1e-5, atol=0.0)
    assert np.array_equal(mixed.teeth_in_contact, plain.teeth_in_contact)


def test_the_scene_asks_for_face_slices_only_where_there_is_a_face_stage():
    """whole_gear_curve's choice (chain._scene_face_slices): the scene's face_slices = N on a
    design with a face stage → N slices graded toward the face stage's design
    section and tooth modification; without one → the one-section curve and a warning naming the
    tier; N = 0, or face_slices given by the caller → the scene is not consulted."""
    from types import SimpleNamespace

    from profilegen.contact.chain import _scene_face_slices

    mod = SimpleNamespace(taper_mm_per_mm=1.2e-3, crowning_mm=0.0)
    with_face = SimpleNamespace(scene=SimpleNamespace(face_slices=5), rim=SimpleNamespace(tier="cup3d", cup="CUP"),
                                face=SimpleNamespace(design_section_z_mm=70.0, modification=mod))
    spec, note = _scene_face_slices(with_face, {})
    assert note is None
    assert (spec.slices, spec.nodes, spec.coning, spec.cup, spec.design_z_mm, spec.modification) == \
        (5, "graded", "cup", "CUP", 70.0, mod)
    assert spec.coupling_length_mm is None  # the rim's own shell length (face_curve.rim_coupling_length_mm)
    assert _scene_face_slices(with_face, {"face_slices": 3}) == (None, None)
    flat = SimpleNamespace(scene=SimpleNamespace(face_slices=5), rim=SimpleNamespace(tier="toothed", cup=None),
                           face=None)
    spec, note = _scene_face_slices(flat, {})
    assert spec is None and "face_slices = 5" in note and "toothed" in note
    off = SimpleNamespace(scene=SimpleNamespace(face_slices=0), rim=with_face.rim, face=with_face.face)
    assert _scene_face_slices(off, {}) == (None, None)


def test_catalogue_for_reads_the_catalogue_module_only():
    """One source of truth: a size-40 set of ratio 100 gets the ratio >= 80 row (CHA table 50.4:
    K1 13e4, K2 20e4 N.m/rad), ratio 50 the ratio-50 row (LLC table 42: K1 10e4); a ratio below
    every tabulated one gets no row (it used to fall back to a private copy of the ratio-50
    table), and a size the module has no row for gets none."""
    from types import SimpleNamespace

    from profilegen.contact.chain import catalogue_for

    def gs(ratio, teeth=200):
        return SimpleNamespace(gear=SimpleNamespace(module_mm=0.5, flexspline_teeth=teeth), ratio=ratio)

    r100 = catalogue_for(gs(100))
    assert (r100["size"], r100["K1_nm_per_rad"], r100["K2_nm_per_rad"]) == (40, 13e4, 20e4)
    assert catalogue_for(gs(50))["K1_nm_per_rad"] == 10e4
    assert catalogue_for(gs(20)) is None
    assert catalogue_for(gs(100, teeth=400)) is None  # 200 mm is size 80: no row for it here


def test_a_torque_off_the_ladder_is_solved_from_the_rung_below_whatever_else_is_asked(sketch_design):
    """With a ladder, a torque that is not on it is solved from the ladder's rung just below, not
    from the torque asked for before it: the same rotation and forces whether the curve asks for
    it alone or among other torques off the ladder (what lets an engine keep the ladder over a
    rated-torque change); on the ladder itself the continuation is the same as without one."""
    from profilegen.contact.chain import curve_ladder_nm, torsional_curve

    gs = sketch_design.gearset
    ladder = curve_ladder_nm(gs)
    m = float(np.sqrt(ladder[4] * ladder[5]))  # between two rungs
    alone = torsional_curve(sketch_design, [m, -m], ladder_nm=ladder)
    among = torsional_curve(sketch_design, [0.99 * m, m, 1.01 * m, -m], ladder_nm=ladder)
    at = lambda c, t: c.rotation_rad[np.flatnonzero(c.torque_nm == t)[0]]  # noqa: E731
    assert at(alone, m) == at(among, m) and at(alone, -m) == at(among, -m)
    # and the continuation through every torque (no ladder) solves the same problem: within the springs' tolerance
    plain = torsional_curve(sketch_design, [m, -m])
    assert at(plain, m) == pytest.approx(at(alone, m), rel=1e-6)
