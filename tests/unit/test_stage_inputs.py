"""The typed inputs of the contact, stress and arcfit stages (issue 14: they took the whole
Design and read it by attribute). Each stage runs on what it is given — a hand-built input,
no Design — and reads every field it is given; a wrong type is an error naming the argument."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import profilegen.profile.arcfit as arcfit
from profilegen.profile.arcfit import FitError, swept_depth_function
from profilegen.contact import ContactError, ContactInput, ContactPointError, contact_points
from profilegen.contact.analysis import solve_contact
from profilegen.contact.compliance import ComplianceError, ContactCompliance
from profilegen.contact.points import _flank_start
from profilegen.geometry.deformation import ring_theory
from profilegen.errors import StressError
from profilegen.geometry.kinematics import HarmonicDriveMotion
from profilegen.stress import StressInput, solve_stress
from profilegen.geometry.teeth import tooth_from_gearset


@pytest.fixture(scope="module")
def sketch(default_sketch):
    return default_sketch  # conftest.py: computed once per worker


@pytest.fixture(scope="module")
def inputs(sketch):
    return ContactInput.from_design(sketch)


# --------------------------------------------------------------------------- contact


def test_contact_input_is_what_the_design_carries(sketch, inputs):
    assert inputs.gearset is sketch.gearset and inputs.tooth is sketch.tooth and inputs.motion is sketch.motion
    assert inputs.cs_space is sketch.profile.space
    assert inputs.cs_tip_radius_mm == sketch.form.tip_radius_mm
    assert inputs.rim_contact_angle_rad is None  # ring theory: no rim FEM, no contact angle
    assert ContactInput.from_design(inputs) is inputs


def test_the_rim_fem_contact_angle_is_carried(sketch):
    """With a rim FEM (the design tier) the no-load contact angle it found is the input's."""
    from profilegen.rim.stage import solve_rim

    rim = solve_rim(sketch.gearset, tier="design")
    assert rim.fem is not None and rim.fem.contact_phi_rad.size
    got = ContactInput.from_design(dataclasses.replace(sketch, rim=rim))
    assert got.rim_contact_angle_rad == rim.fem.contact_angle_rad
    assert 0.0 < got.rim_contact_angle_rad < 0.5 * math.pi


def test_the_stages_run_on_a_hand_built_input_and_read_its_fields(sketch, inputs):
    """A ContactInput made field by field (no Design) gives the design's contact points; the
    compliance takes the ball wrap from its rim contact angle; solve_contact on it agrees with
    solve_contact on the Design (the backwards-compatible path, read by from_design)."""
    hand = ContactInput(sketch.gearset, sketch.tooth, sketch.motion, sketch.profile.space,
                        float(sketch.form.tip_radius_mm))
    pts = contact_points(hand)
    ref = contact_points(inputs)
    np.testing.assert_array_equal(pts.tooth, ref.tooth)
    np.testing.assert_array_equal(pts.gap_mm, ref.gap_mm)
    # the working flank starts where the FS flank, pushed out by w0, reaches the CS tip circle:
    # a smaller tip circle is reached lower down the flank
    tooth, w0 = hand.tooth, hand.gearset.deflection_mm
    for tip in (hand.cs_tip_radius_mm, hand.cs_tip_radius_mm - 0.02):
        start = _flank_start(tooth, dataclasses.replace(hand, cs_tip_radius_mm=tip))
        p = tooth.point(np.array([start]))[0]
        assert math.hypot(p[0], p[1] + tooth.neutral_radius_mm) + w0 == pytest.approx(tip, abs=2e-3)
    assert _flank_start(tooth, dataclasses.replace(hand, cs_tip_radius_mm=hand.cs_tip_radius_mm - 0.02)) < \
        _flank_start(tooth, hand)

    wrap = 0.3  # rad: balls every 2π/23 = 0.273 rad, so 3 candidates (0, ±0.273)
    comp = ContactCompliance.build(dataclasses.replace(hand, rim_contact_angle_rad=wrap), pts.fs_point_mm,
                                   pts.normal, pts.tooth, pts.cs_point_mm)
    assert comp.wrap_half_angle_rad == wrap and comp.wrap_source == "the rim stage's no-load contact angle"
    assert comp.ball_angle_rad.size == 3 and np.all(np.abs(comp.ball_angle_rad) <= wrap)
    typed = solve_contact(hand, [100.0], points=pts, compliance=comp)
    legacy = solve_contact(sketch, [100.0], points=pts, compliance=comp)
    np.testing.assert_array_equal(typed.cases[0].solution.force_n, legacy.cases[0].solution.force_n)
    # equilibrium of the zone: Σ F_k r_k = T / U
    case = typed.cases[0]
    assert np.sum(case.solution.force_n * pts.lever_mm) == pytest.approx(100.0e3 / 2, rel=1e-9)


def test_wrong_contact_inputs_name_the_argument(sketch, inputs):
    with pytest.raises(ContactPointError, match=r"inputs: must be a ContactInput .*from_design.* got Design"):
        contact_points(sketch)
    with pytest.raises(ComplianceError, match=r"inputs: must be a ContactInput"):
        ContactCompliance.build(sketch, np.zeros((1, 2)), np.array([[0.0, 1.0]]), [0], np.zeros((1, 2)))
    with pytest.raises(ContactError, match=r"inputs: must be a ContactInput or a profilegen Design, got list"):
        solve_contact([1.0], [10.0])
    with pytest.raises(ContactError, match=r"design: must be a ContactInput or a profilegen Design, got int"):
        ContactInput.from_design(42)
    no_profile = dataclasses.replace(sketch, profile=None)
    with pytest.raises(ContactError, match=r"design: has no fitted CS profile"):
        ContactInput.from_design(no_profile)
    other = HarmonicDriveMotion(sketch.motion.deformation, sketch.motion.neutral_radius_mm, 2, 204)
    for field, value, pattern in [
        ("gearset", "default", r"gearset: must be a GearSet, got str"),
        ("tooth", None, r"tooth: must be a ToothProfile"),
        ("motion", other, r"motion: cs_teeth = 204, waves = 2 do not match .*circular_spline_teeth = 202"),
        ("cs_space", sketch.profile.outline.elements, r"cs_space: must be a Chain"),
        ("cs_tip_radius_mm", -1.0, r"cs_tip_radius_mm = -1.0 mm: must be finite and > 0"),
        ("cs_tip_radius_mm", True, r"cs_tip_radius_mm = True"),
        ("rim_contact_angle_rad", 4.0, r"rim_contact_angle_rad = 4.0 rad: must be None .* or in \[0, π\]"),
    ]:
        with pytest.raises(ContactError, match=pattern):
            dataclasses.replace(inputs, **{field: value})
    assert issubclass(ContactError, ValueError)


# --------------------------------------------------------------------------- stress


def test_stress_on_a_hand_built_input(sketch):
    """solve_stress on a StressInput made from the gear set alone (tooth, ring theory, no
    contact) gives the sketch design's stresses; and it reads the deformation it is given: a
    larger deflection bends the tooth ring harder."""
    gs = sketch.gearset
    tooth = tooth_from_gearset(gs)
    hand = StressInput(gs, tooth, ring_theory(gs.deflection_mm, gs.gear.waves))
    res = solve_stress(hand)
    assert res.force_source == "estimate"
    assert res.headline() == sketch.stress.headline()
    deeper = solve_stress(StressInput(gs, tooth, ring_theory(1.2 * gs.deflection_mm, gs.gear.waves)))
    assert deeper.tooth_ring[0].assembly_stress_mpa > 1.1 * res.tooth_ring[0].assembly_stress_mpa
    # a Design is still taken, read by StressInput.from_design
    assert solve_stress(sketch).headline() == res.headline()


def test_wrong_stress_inputs_name_the_argument(sketch):
    hand = StressInput.from_design(sketch)
    assert hand.contact is None and hand.deformation is sketch.deformation
    with pytest.raises(StressError, match=r"inputs: must be a StressInput or a profilegen Design, got str"):
        solve_stress("design")
    for field, value, pattern in [
        ("gearset", {}, r"gearset: must be a GearSet, got dict"),
        ("tooth", sketch.profile.space, r"tooth: must be a ToothProfile"),
        ("deformation", sketch.motion, r"deformation: must be a DeformationFit or a HarmonicDeformation"),
        ("contact", [1.0], r"contact: must be a ContactResult or None, got list"),
    ]:
        with pytest.raises(StressError, match=pattern):
            dataclasses.replace(hand, **{field: value})


# --------------------------------------------------------------------------- arcfit


def test_swept_depth_function_is_the_swept_region_membership(sketch):
    """Positive inside the region the FS tooth sweeps (the tooth's own mid-flank at φ = 0 is
    in it), negative in the CS tooth between two spaces; one name per meaning: arcfit no
    longer has a ``swept_region`` (that is :func:`profilegen.profile.swept.swept_region`, a polygon)."""
    g = sketch.gearset.gear
    depth = swept_depth_function(sketch.tooth, sketch.motion, cs_teeth=g.circular_spline_teeth,
                                 phi_range=sketch.envelope.phi_range)
    mid = sketch.tooth.point(np.array([0.5 * sketch.tooth.length_mm]))
    inside = sketch.motion.pose(np.zeros(1)).to_cs(np.array([[0.0, mid[0, 1]]]))  # the tooth's centre line
    r = 0.5 * (sketch.form.tip_radius_mm + sketch.form.root_radius_mm)
    a = math.pi / g.circular_spline_teeth  # the CS tooth's centre line (spaces at 0 and 2π/z2)
    cs_tooth = np.array([[r * math.sin(a), r * math.cos(a)]])
    d = depth(np.vstack([inside, cs_tooth]))
    assert d[0] > 0.0 > d[1]
    assert not hasattr(arcfit, "swept_region")
    with pytest.raises(FitError, match="cs_teeth"):
        swept_depth_function(sketch.tooth, sketch.motion, cs_teeth=2.5, phi_range=sketch.envelope.phi_range)
