"""The stress stage of a design (profilegen.stress.stage): the seed models fed by the
design's own deformation and contact forces, the safety checks, bad input."""

import math

import numpy as np
import pytest

import profilegen as pg
from profilegen.errors import GearSetError, StressError
from profilegen.stress import StressInput, solve_stress
from profilegen.stress.stage import root_thickness_mm, tangential_tooth_forces_n


@pytest.fixture(scope="module")
def sketch(default_sketch):
    return default_sketch  # conftest.py: computed once per worker


@pytest.fixture(scope="module")
def loaded(default_sketch_contact):
    return default_sketch_contact


def test_the_design_carries_its_stresses(sketch):
    res = sketch.stress
    assert res is not None and res.force_source == "estimate"
    assert [s.stage for s in sketch.stages][-1] == "stress"
    assert res.torques_nm == (265.0, 660.0, 1200.0)
    head = sketch.to_dict()["stress"]
    assert set(head["safety"]) == {c.name for c in res.checks}
    assert all(v is not None and v > 0 for v in head["safety"].values())


def test_min_safety_is_the_lowest_safety_factor_with_its_check_beside_it(sketch):
    """A script reads d.stress.min_safety as a number (issue 30): the smallest value of the checks
    that ran, min_safety_check the check it belongs to; None when no check ran."""
    import dataclasses

    res = sketch.stress
    values = [c.value for c in res.checks if c.value is not None]
    assert isinstance(res.min_safety, float) and res.min_safety == min(values)
    assert res.min_safety_check.value == res.min_safety and res.min_safety_check in res.checks
    skipped = dataclasses.replace(res, checks=tuple(dataclasses.replace(c, value=None) for c in res.checks))
    assert skipped.min_safety is None and skipped.min_safety_check is None


def test_tangential_forces_carry_the_zone_torque(loaded):
    """Σ over the teeth of F_t × |p| = Σ F_k r_k = T / U (the contact's equilibrium), and the
    largest tooth's F_t is at most its normal force."""
    c = loaded.contact
    pts = c.points
    f_t = tangential_tooth_forces_n(c)
    for case, ft in zip(c.cases, f_t):
        share = pts.lever_mm / np.linalg.norm(pts.fs_point_mm, axis=1)
        moment = np.sum(case.solution.force_n * share * np.linalg.norm(pts.fs_point_mm, axis=1))
        assert moment == pytest.approx(case.zone_torque_nm * 1e3, rel=1e-9)
        assert 0 < ft <= case.max_tooth_force_n * (1 + 1e-12)
    assert loaded.stress.force_source == "contact"
    assert loaded.stress.tangential_force_n == pytest.approx(f_t)


def test_load_stress_is_linear_in_the_force_and_assembly_independent_of_it(sketch):
    ring = sketch.stress.tooth_ring
    forces = sketch.stress.tangential_force_n
    for r, f in zip(ring, forces):
        assert r.assembly_stress_mpa == pytest.approx(ring[0].assembly_stress_mpa, rel=1e-12)
        assert r.load_stress_mpa / f == pytest.approx(ring[0].load_stress_mpa / forces[0], rel=1e-12)


def test_cup_bottom_torque_shear_is_t_over_2_pi_r2_t(sketch):
    g = sketch.gearset
    for t, b in zip(sketch.stress.torques_nm, sketch.stress.cup_bottom):
        r0 = b.r_mm[0]
        assert r0 == pytest.approx(g.cup.boss_radius_mm)
        assert b.tau_load_mpa[0] == pytest.approx(t * 1e3 / (2 * math.pi * r0**2 * g.cup.bottom_thickness_mm), rel=1e-12)


def test_goodman_arithmetic_of_the_tooth_ring_check(sketch):
    g = sketch.gearset.material
    r = sketch.stress.tooth_ring[0]
    check = {c.name: c for c in sketch.stress.checks}["tooth ring fatigue"]
    amp, mean = r.assembly_stress_mpa + r.load_stress_mpa / 2, r.load_stress_mpa / 2
    assert check.value == pytest.approx(1 / (amp / g.bending_endurance_limit_mpa + mean / g.ultimate_strength_mpa))
    assert check.passed == (check.value >= check.required)


def test_root_thickness_is_measured_on_the_tooth(sketch):
    """s_f at the fillet's height: between the tooth's thickness on the pitch line (2 × half
    thickness) and the full pitch (a tooth flares toward its root)."""
    gs = sketch.gearset
    s_f = root_thickness_mm(sketch.tooth, gs.cup.root_fillet_radius_mm)
    assert 2 * gs.tooth.half_thickness_mm < s_f < math.pi * gs.gear.module_mm
    assert root_thickness_mm(sketch.tooth, 0.05) > s_f  # nearer the root: thicker


def test_fatigue_without_limits_is_a_named_error(sketch):
    gs = sketch.gearset.with_values({"material.shear_endurance_limit_mpa": None})
    bare = pg.design(gs, scene="sketch", stress=False)
    with pytest.raises(StressError, match="material.shear_endurance_limit_mpa"):
        solve_stress(StressInput.from_design(bare), fatigue=True)
    res = solve_stress(StressInput.from_design(bare))  # default: the fatigue checks are skipped and say so
    assert any("fatigue checks skipped" in w for w in res.warnings)
    assert all(c.value is None for c in res.checks if "fatigue" in c.name)


@pytest.mark.parametrize("field, value", [("cup.bottom_thickness_mm", 0.0), ("cup.bottom_thickness_mm", -1.0),
                                          ("cup.boss_radius_mm", 60.0), ("cup.length_mm", 0.0)])
def test_bad_cup_is_a_named_gearset_error(field, value):
    gs = pg.load_gearset(pg.default_gearset_path())
    with pytest.raises(GearSetError, match=field.replace(".", r"\.")):
        gs.with_values({field: value})


def test_a_contact_that_cannot_take_the_design_leaves_a_warning(monkeypatch):
    """The scene's default contact failing with a named error keeps the profile and says why;
    asked for explicitly (contact=True), the error reaches the caller."""
    from dataclasses import replace

    import profilegen.pipeline.design as pipeline
    from profilegen.contact.compliance import ComplianceError

    def broken(result, step, early=None):
        raise ComplianceError("cs_points: point 3 is 0.2 mm off the fitted CS surface")

    monkeypatch.setattr(pipeline, "_with_contact", broken)
    gs = pg.load_gearset(pg.default_gearset_path())
    scene = replace(pipeline.SCENES["sketch"], contact=True)
    res = pg.design(gs, scene=scene)
    assert res.contact is None and res.profile is not None
    assert any(w.startswith("loaded contact failed, skipped: cs_points") for w in res.warnings)
    assert res.stress.force_source == "estimate"
    with pytest.raises(ComplianceError, match="cs_points"):
        pg.design(gs, scene=scene, contact=True)


def test_three_waves_are_named_not_misread():
    """The seed models are for an ellipse (U = 2): ρ_b is ω at π/2, which for U = 3 is the
    mean radius, not a minor axis. Found by the gear-set fuzz as a StressError about
    minor_semi_axis_mm; now solve_stress names gear.waves, and a design skips the stresses
    with a warning, as it does the contact."""
    gs = pg.load_gearset(pg.default_gearset_path()).with_values(
        {"gear.waves": 3, "gear.circular_spline_teeth": 203})
    result = pg.design(gs, scene="sketch")
    assert result.stress is None
    assert any("stresses skipped" in w and "gear.waves = 2, got 3" in w for w in result.warnings)
    with pytest.raises(StressError, match=r"gear.waves = 3: .* two waves"):
        solve_stress(StressInput.from_design(result))
