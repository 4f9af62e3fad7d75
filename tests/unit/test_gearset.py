"""Unit tests of profilegen.gearset: loading, derived values, validation, round trips.

Derived values are checked against hand calculation from the seed-004 table
(shared/seeds/004_*.txt: m = 0.5 mm, z1 = 200, z2 = 202, ω* = 1, δ = 0.9 mm).
"""

from __future__ import annotations

import copy
import dataclasses
import json
import math

import numpy as np
import pytest

from profilegen.errors import GearSetError
from profilegen.gearset import (
    DctaTooth,
    GearSet,
    InvoluteTooth,
    PointsTooth,
    default_gearset_path,
    list_profiles,
    load_gearset,
    parse_gearset,
    profiles_dir,
    resolve_gearset,
)


def base() -> dict:
    """A minimal valid gear set (seed-004 numbers, defaults elsewhere)."""
    return {
        "name": "unit",
        "description": "unit-test gear set",
        "source": "seed 004 table",
        "gear": {
            "module_mm": 0.5,
            "flexspline_teeth": 200,
            "circular_spline_teeth": 202,
            "rim_thickness_mm": 0.9,
        },
        "tooth": {"kind": "dcta"},
        "wave_generator": {"deflection_coefficient": 1.0},
        "material": {"youngs_modulus_mpa": 209000.0, "poisson_ratio": 0.295},
        "torque": {"rated_nm": 100.0, "peak_nm": 200.0},
    }


def with_(data: dict, path: str, value) -> dict:
    """Copy of ``data`` with the dotted ``path`` set (value ``...`` deletes it)."""
    out = copy.deepcopy(data)
    *head, last = path.split(".")
    node = out
    for part in head:
        node = node.setdefault(part, {})
    if value is ...:
        node.pop(last, None)
    else:
        node[last] = value
    return out


def flank_points(n: int = 12) -> list[list[float]]:
    """A straight 10° right flank in the pitch frame, root (y = −0.6) to tip (y = 0.4)."""
    y = np.linspace(-0.6, 0.4, n)
    x = math.pi * 0.5 / 4 - y * math.tan(math.radians(10.0))
    return np.column_stack([x, y]).tolist()


def problems_of(data: dict) -> list[str]:
    with pytest.raises(GearSetError) as info:
        parse_gearset(data)
    return info.value.problems


# --------------------------------------------------------------------------- profiles


def test_profiles_folder_has_the_four_sets():
    names = {p.stem for p in list_profiles()}
    assert {"default", "seed000_csf40", "seed001_shf25", "seed002_short_cup"} <= names
    assert default_gearset_path() == profiles_dir() / "default.toml"


@pytest.mark.parametrize("path", list_profiles(), ids=lambda p: p.stem)
def test_every_profile_loads_and_round_trips(path):
    gs = load_gearset(path)
    assert gs.name == path.stem
    assert gs.origin == str(path)
    d = gs.to_dict()
    assert json.loads(json.dumps(d)) == d
    assert parse_gearset(d).to_dict() == d
    # closure of the gear data: z2 − z1 is a positive multiple of the waves
    assert gs.tooth_difference > 0 and gs.tooth_difference % gs.gear.waves == 0
    # the neutral line lies inside the rim under the teeth
    r1 = gs.gear.pitch_radius_mm
    assert 0.5 * r1 < gs.gear.neutral_radius_mm < r1 - gs.tooth.dedendum_mm


def test_default_derived_values():
    gs = load_gearset(default_gearset_path())
    assert gs.gear.pitch_radius_mm == pytest.approx(50.0)  # m z1 / 2
    assert gs.gear.cs_pitch_radius_mm == pytest.approx(50.5)  # m z2 / 2
    assert gs.gear.neutral_radius_mm == pytest.approx(50.0 - 0.6 - 0.45)  # r1 − dedendum − δ/2
    assert gs.gear.neutral_to_pitch_mm == pytest.approx(1.05)
    assert gs.deflection_mm == pytest.approx(0.5)  # ω* m
    assert gs.ratio == pytest.approx(100.0)  # z1 / (z2 − z1)
    assert gs.tooth_difference == 2
    assert isinstance(gs.tooth, DctaTooth)
    assert gs.tooth.half_thickness_mm == pytest.approx(math.pi * 0.5 / 4)
    assert gs.tooth.pressure_angle_rad == pytest.approx(math.radians(10.0))
    assert gs.circular_spline.root_clearance_mm == pytest.approx(0.125)  # 0.25 m
    assert gs.scene == "design"
    assert gs.material.shear_modulus_mpa == pytest.approx(209000 / (2 * 1.295))
    assert gs.torque.rated_nmm == pytest.approx(gs.torque.rated_nm * 1e3)


def test_seed001_numbers():
    gs = load_gearset(resolve_gearset("seed001_shf25"))
    assert gs.gear.neutral_radius_mm == pytest.approx(29.119)  # given, not derived
    assert gs.ratio == pytest.approx(80.0)  # SHF-25-80
    assert gs.gear.rim_thickness_mm / gs.gear.neutral_radius_mm == pytest.approx(0.03375, rel=1e-3)
    # seed 001 table: ρa = r_m + w0 = 29.494 mm
    assert gs.gear.neutral_radius_mm + gs.deflection_mm == pytest.approx(29.494)
    assert (gs.torque.rated_nm, gs.torque.peak_nm, gs.torque.momentary_nm) == (67.0, 167.0, 304.0)


def test_seed002_deflection_matches_table_semi_axes():
    gs = load_gearset(resolve_gearset("seed002_short_cup"))
    # seed 002 Table 1: a = 31.035 mm, r_m = 30.685 mm → w0 = 0.35 mm
    assert gs.gear.neutral_radius_mm + gs.deflection_mm == pytest.approx(31.035, abs=1e-5)


# --------------------------------------------------------------------------- resolve


def test_resolve_by_name_and_by_path(tmp_path):
    assert resolve_gearset("default") == default_gearset_path()
    assert resolve_gearset(default_gearset_path()) == default_gearset_path()
    with pytest.raises(GearSetError, match="no_such_set"):
        resolve_gearset("no_such_set")
    with pytest.raises(GearSetError, match="missing.toml"):
        resolve_gearset(tmp_path / "missing.toml")


# --------------------------------------------------------------------------- out of range

OUT_OF_RANGE = [
    ("gear.module_mm", -0.5),
    ("gear.module_mm", 0.0),
    ("gear.module_mm", 10.5),
    ("gear.flexspline_teeth", 19),
    ("gear.flexspline_teeth", 2001),
    ("gear.waves", 1),
    ("gear.waves", 5),
    ("gear.rim_thickness_mm", 0.0),
    ("gear.rim_thickness_mm", 10.1),  # > 0.2 r1 = 10 mm
    ("gear.neutral_radius_mm", 24.9),  # <= 0.5 r1
    ("gear.neutral_radius_mm", 49.5),  # above the root radius r1 − dedendum = 49.4
    ("gear.neutral_radius_mm", 50.0),
    ("wave_generator.deflection_coefficient", 0.0),
    ("wave_generator.deflection_coefficient", 3.1),
    ("wave_generator.bearing_thickness_mm", -0.1),
    ("material.youngs_modulus_mpa", 0.0),
    ("material.youngs_modulus_mpa", 2e6),
    ("material.poisson_ratio", -0.1),
    ("material.poisson_ratio", 0.5),
    ("material.yield_strength_mpa", 0.0),
    ("material.shear_endurance_limit_mpa", -1.0),
    ("torque.rated_nm", 0.0),
    ("torque.peak_nm", 99.0),  # < rated
    ("torque.momentary_nm", 150.0),  # < peak
    ("circular_spline.root_clearance_mm", -0.01),
    ("circular_spline.tip_clearance_mm", 1.01),  # > 2 m
    ("tooth.pressure_angle_deg", 0.0),
    ("tooth.pressure_angle_deg", 45.0),
    ("tooth.line_above_pitch_mm", -0.01),
    ("tooth.line_below_pitch_mm", 2.6),  # > 5 m
    ("tooth.tip_arc_radius_mm", 0.0),
    ("tooth.root_arc_radius_mm", 5.1),  # > 10 m
    ("tooth.addendum_mm", 1.6),  # > 3 m
    ("tooth.dedendum_mm", 0.0),
    ("tooth.half_thickness_mm", 0.0),
    ("tooth.half_thickness_mm", math.pi * 0.5 / 2),  # a whole pitch: open bound
]


@pytest.mark.parametrize("path,value", OUT_OF_RANGE, ids=[f"{p}={v:g}" for p, v in OUT_OF_RANGE])
def test_out_of_range_names_the_field(path, value):
    problems = problems_of(with_(base(), path, value))
    assert len(problems) == 1, problems
    assert problems[0].startswith(f"{path} = ")
    assert "must be" in problems[0]


def test_problem_line_format():
    (line,) = problems_of(with_(base(), "gear.module_mm", -0.5))
    assert line == "gear.module_mm = -0.5 mm: must be in [1e-05, 10] (lower bound: the smallest module the arc fit resolves)"


def test_error_is_a_value_error_too():
    with pytest.raises(ValueError, match="gear.module_mm"):
        parse_gearset(with_(base(), "gear.module_mm", -0.5))


@pytest.mark.parametrize(
    "path,value",
    [
        ("tooth.pressure_angle_deg", 4.9),
        ("tooth.pressure_angle_deg", 35.1),
        ("tooth.addendum_mm", 1.6),
        ("tooth.dedendum_mm", -1.0),
        ("tooth.half_thickness_mm", 0.8),
    ],
)
def test_involute_ranges(path, value):
    data = with_(base(), "tooth", {"kind": "involute"})
    (line,) = problems_of(with_(data, path, value))
    assert line.startswith(f"{path} = ")


def test_involute_defaults_scale_with_module():
    data = with_(with_(base(), "tooth", {"kind": "involute"}), "gear.module_mm", 0.4)
    gs = parse_gearset(data)
    assert isinstance(gs.tooth, InvoluteTooth)
    assert gs.tooth.pressure_angle_deg == 20.0
    assert gs.tooth.addendum_mm == pytest.approx(0.4)
    assert gs.tooth.dedendum_mm == pytest.approx(0.5)
    assert gs.tooth.half_thickness_mm == pytest.approx(math.pi * 0.4 / 4)
    assert gs.gear.neutral_radius_mm == pytest.approx(0.4 * 100 - 0.5 - 0.45)


def test_dcta_defaults_follow_the_module():
    # the default tooth is 0.8·m high above the pitch line, 1.2·m below it, ... (0.40, 0.60 mm at m = 0.5)
    for m in (0.1, 0.5, 2.0):
        gs = parse_gearset(with_(with_(base(), "gear.module_mm", m), "gear.rim_thickness_mm", 1.8 * m))
        t = gs.tooth
        assert (t.addendum_mm, t.dedendum_mm) == pytest.approx((0.8 * m, 1.2 * m))
        assert (t.line_above_pitch_mm, t.line_below_pitch_mm) == pytest.approx((0.1 * m, 0.4 * m))
        assert (t.tip_arc_radius_mm, t.root_arc_radius_mm) == pytest.approx((1.3 * m, 1.4 * m))
        assert t.half_thickness_mm == pytest.approx(math.pi * m / 4)
    at_half = parse_gearset(base()).tooth  # the seed-004 numbers, exactly
    assert (at_half.line_above_pitch_mm, at_half.line_below_pitch_mm, at_half.tip_arc_radius_mm,
            at_half.root_arc_radius_mm, at_half.addendum_mm, at_half.dedendum_mm) == (0.05, 0.2, 0.65, 0.7, 0.4, 0.6)


@pytest.mark.parametrize("kind", ["dcta", "involute"])
def test_tooth_lengths_in_module_units(kind):
    tooth = {"kind": kind, "addendum_coefficient": 0.9, "dedendum_coefficient": 1.1, "half_thickness_coefficient": 0.7}
    data = with_(with_(base(), "tooth", tooth), "gear.module_mm", 0.4)
    gs = parse_gearset(data)
    assert (gs.tooth.addendum_mm, gs.tooth.dedendum_mm) == pytest.approx((0.36, 0.44))
    assert gs.tooth.half_thickness_mm == pytest.approx(0.28)
    # written back in module units, so that a changed module scales the tooth
    assert gs.to_dict(include_defaults=False)["tooth"] == tooth
    bigger = gs.with_values({"gear.module_mm": 0.8, "gear.rim_thickness_mm": 1.6})
    assert (bigger.tooth.addendum_mm, bigger.tooth.dedendum_mm) == pytest.approx((0.72, 0.88))
    # a value in mm replaces the same length in module units (and back)
    in_mm = gs.with_values({"tooth.addendum_mm": 0.3})
    assert in_mm.tooth.addendum_mm == 0.3 and in_mm.tooth.dedendum_mm == pytest.approx(0.44)
    assert in_mm.with_values({"tooth.addendum_coefficient": 1.0}).tooth.addendum_mm == pytest.approx(0.4)


def test_tooth_length_in_both_units_is_an_error():
    (line,) = problems_of(with_(base(), "tooth", {"kind": "dcta", "addendum_mm": 0.4, "addendum_coefficient": 0.8}))
    assert line.startswith("tooth.addendum_mm, tooth.addendum_coefficient: give at most one")


@pytest.mark.parametrize("key,value", [("addendum_coefficient", 3.5), ("dedendum_coefficient", 0.1),
                                       ("tip_arc_radius_coefficient", 0.0), ("half_thickness_coefficient", 1.6),
                                       ("line_above_pitch_coefficient", -0.1), ("addendum_coefficient", math.nan),
                                       ("root_arc_radius_coefficient", "1.4")])
def test_tooth_coefficient_ranges(key, value):
    (line,) = problems_of(with_(base(), f"tooth.{key}", value))
    assert line.startswith(f"tooth.{key} = ")


def test_copy_of_the_default_set_with_another_module_works():
    # issue 13 item 8: the bundled default set, module changed (and the rim, which is in mm)
    gs = load_gearset(default_gearset_path())
    big = gs.with_values({"gear.module_mm": 2.0, "gear.rim_thickness_mm": 3.6})
    assert big.tooth.addendum_mm == pytest.approx(1.6) and big.tooth.dedendum_mm == pytest.approx(2.4)
    # every length ∝ m (rim too): the tooth is the default one magnified 4×, point for point
    from profilegen.geometry.teeth import tooth_from_gearset

    small_tooth, big_tooth = tooth_from_gearset(gs), tooth_from_gearset(big)
    assert big_tooth.length_mm == pytest.approx(4.0 * small_tooth.length_mm, rel=1e-12)
    t = np.linspace(0.0, small_tooth.length_mm, 41)
    np.testing.assert_allclose(big_tooth.evaluate(4.0 * t)[0], 4.0 * small_tooth.evaluate(t)[0], rtol=0, atol=1e-10)
    # its torques (for m = 0.5) are now far below what the size carries: a note names them
    (note,) = big.warnings
    assert note.startswith("torque.rated_nm = 265 N·m is far below")
    assert gs.warnings == ()


def test_tooth_from_another_module_is_refused_by_its_size():
    # the default tooth's absolute mm on an m = 10 gear: 0.04·m high — a tooth in mm for another module
    data = with_(with_(base(), "gear.module_mm", 10.0), "gear.rim_thickness_mm", 18.0)
    data["tooth"] = {"kind": "dcta", "addendum_mm": 0.4, "dedendum_mm": 0.6}
    problems = problems_of(data)
    assert [p.split(" = ")[0] for p in problems] == ["tooth.addendum_mm", "tooth.dedendum_mm"]
    assert "0.2·m to 3·m" in problems[0]


def test_rim_thin_for_its_deflection_is_refused():
    # issue 13: m = 10 with the default 0.9 mm rim passed validation and failed inside the rim FEM
    problems = problems_of(with_(base(), "gear.module_mm", 10.0))
    assert any(p.startswith("gear.rim_thickness_mm = 0.9 mm: must be >= 5 mm") for p in problems)
    thin = with_(base(), "gear.rim_thickness_mm", 0.4)
    assert parse_gearset(thin).gear.rim_thickness_mm == 0.4  # w0 = 0.5 mm
    (line,) = problems_of(with_(thin, "wave_generator.deflection_coefficient", 2.0))  # w0 = 1 mm
    assert line.startswith("gear.rim_thickness_mm = 0.4 mm: must be >= 0.5 mm")
    assert "wave_generator.deflection_coefficient" in line
    assert parse_gearset(with_(base(), "gear.rim_thickness_mm", 0.25)).gear.rim_thickness_mm == 0.25  # = 0.5·w0
    (line,) = problems_of(with_(base(), "gear.rim_thickness_mm", 0.24))
    assert line.startswith("gear.rim_thickness_mm = 0.24 mm: must be >= 0.25 mm (0.5·w0")


@pytest.mark.parametrize("torque,field", [({"rated_nm": 2000.0, "peak_nm": 2000.0}, "rated_nm"),
                                          ({"rated_nm": 10.0, "peak_nm": 20.0}, "rated_nm"),
                                          ({"rated_nm": 265.0, "peak_nm": 3000.0}, "peak_nm"),
                                          ({"rated_nm": 265.0, "peak_nm": 660.0, "momentary_nm": 5000.0},
                                           "momentary_nm")])
def test_torque_far_from_the_size_is_a_note_not_an_error(torque, field):
    gs = parse_gearset(with_(base(), "torque", torque))  # valid
    (note,) = gs.warnings
    assert note.startswith(f"torque.{field} = ")


def test_size_torque_is_calibrated_on_the_catalogue_sets():
    by_name = {p.stem: load_gearset(p) for p in list_profiles()}
    # seed 000 CSF-40 265 N·m, seed 001 SHF-25 67 N·m, seed 002 CSG-25 87 N·m: within 20 %
    for name, rated in (("seed000_csf40", 265.0), ("seed001_shf25", 67.0), ("seed002_short_cup", 87.0)):
        assert by_name[name].size_torque_nm == pytest.approx(rated, rel=0.2)
        assert by_name[name].warnings == ()


# --------------------------------------------------------------------------- gear rules


def test_tooth_difference_must_be_a_multiple_of_the_waves():
    (line,) = problems_of(with_(base(), "gear.circular_spline_teeth", 203))
    assert line.startswith("gear.circular_spline_teeth = 203")
    assert "z2 − z1 = 3" in line and "waves = 2" in line


@pytest.mark.parametrize("z2", [200, 198])
def test_tooth_difference_must_be_positive(z2):
    (line,) = problems_of(with_(base(), "gear.circular_spline_teeth", z2))
    assert line.startswith("gear.circular_spline_teeth")
    assert "positive multiple" in line


def test_three_waves():
    data = with_(with_(base(), "gear.waves", 3), "gear.circular_spline_teeth", 203)
    gs = parse_gearset(data)
    assert gs.tooth_difference == 3 and gs.ratio == pytest.approx(200 / 3)


def test_neutral_radius_given_is_kept():
    gs = parse_gearset(with_(base(), "gear.neutral_radius_mm", 48.8))
    assert gs.gear.neutral_radius_mm == 48.8


# --------------------------------------------------------------------------- keys and types


def test_unknown_key_in_a_section():
    data = with_(base(), "gear.modul_mm", 0.5)
    (line,) = problems_of(data)
    assert line.startswith("gear.modul_mm: unknown key (allowed: module_mm, flexspline_teeth")
    assert "module_mm" in line


def test_unknown_key_at_top_level_and_unknown_section():
    data = base()
    data["colour"] = "red"
    data["lubricant"] = {"kind": "grease"}
    problems = problems_of(data)
    assert [p.split(":")[0] for p in problems] == ["colour", "lubricant"]
    assert all("unknown key" in p for p in problems)


def test_key_of_another_tooth_kind_is_unknown():
    data = with_(base(), "tooth", {"kind": "involute", "tip_arc_radius_mm": 0.65})
    (line,) = problems_of(data)
    assert line.startswith('tooth.tip_arc_radius_mm: unknown key for kind "involute"')
    assert '"dcta"' in line


def test_unknown_tooth_kind():
    (line,) = problems_of(with_(base(), "tooth.kind", "cycloid"))
    assert line.startswith('tooth.kind = "cycloid": must be one of')


@pytest.mark.parametrize(
    "path,value,expect",
    [
        ("gear.module_mm", "0.5", "must be a number, got string"),
        ("gear.module_mm", True, "must be a number, got boolean"),
        ("gear.flexspline_teeth", 200.0, "must be an integer, got float"),
        ("gear.waves", "2", "must be an integer, got string"),
        ("material.poisson_ratio", [0.3], "must be a number, got array"),
        ("torque.rated_nm", float("nan"), "must be finite"),
        ("name", 3, "must be a string, got integer"),
        ("name", "Default Set", "must match"),
        ("scene", "draft", "must be one of"),
        ("wave_generator.contour", "ellipse", "must be one of"),
    ],
)
def test_wrong_type_is_named(path, value, expect):
    (line,) = problems_of(with_(base(), path, value))
    assert line.startswith(f"{path} = ")
    assert expect in line


def test_section_that_is_not_a_table():
    (line,) = problems_of(with_(base(), "torque", 100.0))
    assert line.startswith("torque = 100.0: must be a table")


@pytest.mark.parametrize(
    "path",
    [
        "name",
        "description",
        "source",
        "gear.module_mm",
        "gear.flexspline_teeth",
        "gear.circular_spline_teeth",
        "gear.rim_thickness_mm",
        "tooth.kind",
        "material.youngs_modulus_mpa",
        "material.poisson_ratio",
        "torque.rated_nm",
        "torque.peak_nm",
    ],
)
def test_missing_required_field_is_named(path):
    problems = problems_of(with_(base(), path, ...))
    assert any(p.startswith(f"{path}: missing") for p in problems), problems


@pytest.mark.parametrize("section", ["gear", "tooth", "wave_generator", "material", "torque"])
def test_missing_required_section(section):
    data = base()
    del data[section]
    problems = problems_of(data)
    assert problems[0] == f"{section}: missing required section [{section}]"


def test_circular_spline_section_is_optional():
    gs = parse_gearset(base())
    assert gs.circular_spline.tip_clearance_mm == pytest.approx(0.25 * 0.5)


def test_all_problems_are_collected():
    data = with_(with_(base(), "gear.module_mm", -0.5), "material.poisson_ratio", 0.7)
    problems = problems_of(data)
    assert len(problems) == 2
    assert problems[0].startswith("gear.module_mm")
    assert problems[1].startswith("material.poisson_ratio")
    with pytest.raises(GearSetError) as info:
        parse_gearset(data)
    assert "gear.module_mm" in str(info.value) and "material.poisson_ratio" in str(info.value)


def test_not_a_mapping():
    with pytest.raises(GearSetError, match="table"):
        parse_gearset([1, 2, 3])


# --------------------------------------------------------------------------- wave generator


def test_rollers_need_count_and_radius():
    data = with_(base(), "wave_generator", {"contour": "rollers"})
    problems = problems_of(data)
    assert any(p.startswith("wave_generator.roller_count: missing") for p in problems)
    assert any(p.startswith("wave_generator.roller_radius_mm: missing") for p in problems)


def test_rollers_valid_and_ranges():
    wg = {"contour": "rollers", "roller_count": 4, "roller_radius_mm": 10.0}
    gs = parse_gearset(with_(base(), "wave_generator", wg))
    assert gs.wave_generator.roller_count == 4
    (line,) = problems_of(with_(base(), "wave_generator", {**wg, "roller_count": 3}))
    assert line.startswith("wave_generator.roller_count = 3")
    (line,) = problems_of(with_(base(), "wave_generator", {**wg, "roller_radius_mm": 0.0}))
    assert line.startswith("wave_generator.roller_radius_mm = 0.0 mm")


@pytest.mark.parametrize("key,value", [("roller_count", 2), ("roller_radius_mm", 5.0)])
def test_roller_fields_forbidden_on_a_cam(key, value):
    (line,) = problems_of(with_(base(), f"wave_generator.{key}", value))
    assert line.startswith(f"wave_generator.{key}: only allowed with contour")


def test_bearing_thickness_only_on_the_elliptical_cam():
    data = with_(base(), "wave_generator", {"contour": "cosine_cam", "bearing_thickness_mm": 2.0})
    (line,) = problems_of(data)
    assert line.startswith("wave_generator.bearing_thickness_mm: only allowed")
    gs = parse_gearset(with_(base(), "wave_generator.bearing_thickness_mm", 2.0))
    assert gs.wave_generator.bearing_thickness_mm == 2.0


# --------------------------------------------------------------------------- points tooth


def test_points_inline():
    pts = flank_points()
    gs = parse_gearset(with_(base(), "tooth", {"kind": "points", "points": pts}))
    assert isinstance(gs.tooth, PointsTooth)
    assert gs.tooth.points.shape == (12, 2)
    assert not gs.tooth.points.flags.writeable
    assert gs.tooth.dedendum_mm == pytest.approx(0.6)
    assert gs.tooth.addendum_mm == pytest.approx(0.4)
    assert gs.tooth.half_thickness_mm == pytest.approx(math.pi * 0.5 / 4)
    assert gs.tooth.smoothing_mm == 0.0005
    assert gs.gear.neutral_radius_mm == pytest.approx(48.95)
    d = gs.to_dict()
    assert parse_gearset(d).to_dict() == d


def test_points_file_relative_to_the_toml(tmp_path):
    csv_path = tmp_path / "flank.csv"
    rows = "\n".join(f"{x!r},{y!r}" for x, y in flank_points())
    csv_path.write_text("# right flank, pitch frame\nx_mm,y_mm\n" + rows + "\n")
    toml = tmp_path / "set.toml"
    toml.write_text(
        'name = "pts"\ndescription = "d"\nsource = "s"\n'
        "[gear]\nmodule_mm = 0.5\nflexspline_teeth = 200\ncircular_spline_teeth = 202\n"
        "rim_thickness_mm = 0.9\n"
        '[tooth]\nkind = "points"\npoints_file = "flank.csv"\n'
        "[wave_generator]\n[material]\nyoungs_modulus_mpa = 2.1e5\npoisson_ratio = 0.3\n"
        "[torque]\nrated_nm = 10\npeak_nm = 20\n"
    )
    gs = load_gearset(toml)
    np.testing.assert_allclose(gs.tooth.points, flank_points())
    assert gs.tooth.points_file == "flank.csv"
    # to_dict writes the points inline, so the dict does not depend on the folder
    assert parse_gearset(gs.to_dict()).tooth.points.shape == (12, 2)


def test_points_file_missing(tmp_path):
    data = with_(base(), "tooth", {"kind": "points", "points_file": "nope.csv"})
    with pytest.raises(GearSetError) as info:
        parse_gearset(data, base_dir=tmp_path)
    (line,) = info.value.problems
    assert line.startswith('tooth.points_file = "nope.csv": ') and line.endswith("nope.csv: no such point-list CSV file")


@pytest.mark.parametrize("which", ["both", "neither"])
def test_points_and_points_file_exactly_one(which):
    tooth = {"kind": "points"}
    if which == "both":
        tooth.update(points=flank_points(), points_file="flank.csv")
    (line,) = problems_of(with_(base(), "tooth", tooth))
    assert "tooth.points" in line and "tooth.points_file" in line and which in line


@pytest.mark.parametrize(
    "points,expect",
    [
        (flank_points(5), "at least 8"),
        (flank_points()[::-1], "root to tip"),
        ([[0.3, y] for y in np.linspace(0.1, 0.5, 10)], "cross the pitch circle"),
        ([[x + 2.0, y] for x, y in flank_points()], "half a pitch"),
        ([[0.3, "a"]] + flank_points(), "pair of numbers"),
    ],
    ids=["too-few", "tip-to-root", "above-pitch", "too-wide", "not-numbers"],
)
def test_bad_points(points, expect):
    (line,) = problems_of(with_(base(), "tooth", {"kind": "points", "points": points}))
    assert line.startswith("tooth.points")
    assert expect in line


def test_smoothing_range():
    tooth = {"kind": "points", "points": flank_points(), "smoothing_mm": 0.2}
    (line,) = problems_of(with_(base(), "tooth", tooth))
    assert line.startswith("tooth.smoothing_mm = 0.2 mm: must be in [0, 0.1]")


# --------------------------------------------------------------------------- files


def test_malformed_toml_names_file_and_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\n[gear\nmodule_mm = 0.5\n')
    with pytest.raises(GearSetError) as info:
        load_gearset(bad)
    message = str(info.value)
    assert str(bad) in message and "malformed TOML" in message
    assert "line 2" in message


def test_missing_file_is_a_gearset_error(tmp_path):
    missing = tmp_path / "nowhere.toml"
    with pytest.raises(GearSetError) as info:
        load_gearset(missing)
    assert str(missing) in str(info.value)
    assert not isinstance(info.value, FileNotFoundError)


def test_problems_from_a_file_name_the_file(tmp_path):
    text = default_gearset_path().read_text().replace("module_mm = 0.5 ", "module_mm = -0.5 ")
    path = tmp_path / "neg.toml"
    path.write_text(text)
    with pytest.raises(GearSetError) as info:
        load_gearset(path)
    assert info.value.problems[0] == f"{path}: gear.module_mm = -0.5 mm: must be in [1e-05, 10] (lower bound: the smallest module the arc fit resolves)"


# --------------------------------------------------------------------------- round trip, changes


def test_to_dict_round_trip_is_json_safe():
    gs = parse_gearset(base())
    d = gs.to_dict()
    assert json.loads(json.dumps(d)) == d
    again = parse_gearset(d)
    assert again.to_dict() == d
    assert again.gear.neutral_radius_mm == gs.gear.neutral_radius_mm


def test_to_dict_without_defaults_is_the_input():
    data = base()
    gs = parse_gearset(data)
    assert gs.to_dict(include_defaults=False) == data


def test_with_values_returns_a_new_validated_set():
    gs = load_gearset(default_gearset_path())
    swept = gs.with_values({"wave_generator.deflection_coefficient": 0.8})
    assert swept.deflection_mm == pytest.approx(0.4)
    assert gs.deflection_mm == pytest.approx(0.5)  # unchanged
    with pytest.raises(GearSetError, match="wave_generator.deflection_coefficient"):
        gs.with_values({"wave_generator.deflection_coefficient": 5.0})
    with pytest.raises(GearSetError, match="gear.modul_mm: unknown key"):
        gs.with_values({"gear.modul_mm": 0.4})


def test_with_values_rederives_dependent_defaults():
    gs = load_gearset(default_gearset_path())
    thicker = gs.with_values({"gear.rim_thickness_mm": 1.2})
    assert thicker.gear.neutral_radius_mm == pytest.approx(50.0 - 0.6 - 0.6)
    smaller = gs.with_values({"gear.module_mm": 0.4})
    assert smaller.circular_spline.root_clearance_mm == pytest.approx(0.1)
    assert smaller.tooth.half_thickness_mm == pytest.approx(math.pi * 0.4 / 4)
    # None removes a field, so its default applies again
    back = gs.with_values({"tooth.pressure_angle_deg": None})
    assert back.tooth.pressure_angle_deg == 10.0


def test_construction_and_replace_validate():
    gs = parse_gearset(base())
    bad_gear = dataclasses.replace(gs.gear, module_mm=-1.0)
    with pytest.raises(GearSetError, match="gear.module_mm"):
        gs.replace(gear=bad_gear)
    with pytest.raises(GearSetError, match="gear.module_mm"):
        dataclasses.replace(gs, gear=bad_gear)
    with pytest.raises(GearSetError, match="tooth"):
        GearSet(**{f.name: getattr(gs, f.name) for f in dataclasses.fields(gs)} | {"tooth": {}})
    renamed = gs.replace(name="other")
    assert renamed.name == "other" and renamed.to_dict()["gear"] == gs.to_dict()["gear"]


def test_frozen():
    gs = parse_gearset(base())
    with pytest.raises(dataclasses.FrozenInstanceError):
        gs.name = "x"  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        gs.gear.module_mm = 1.0  # type: ignore[misc]


def test_pickles_for_process_pools():
    import pickle

    gs = parse_gearset(with_(base(), "tooth", {"kind": "points", "points": flank_points()}))
    again = pickle.loads(pickle.dumps(gs))
    assert again.to_dict() == gs.to_dict()
    assert not again.tooth.points.flags.writeable


def test_fit_method_is_validated_and_defaults_to_one_sided():
    base = load_gearset(default_gearset_path()).to_dict()
    assert parse_gearset(base).circular_spline.fit_method == "one_sided"
    base["circular_spline"]["fit_method"] = "minimax"
    assert parse_gearset(base).circular_spline.fit_method == "minimax"
    base["circular_spline"]["fit_method"] = "minimx"
    with pytest.raises(GearSetError, match=r"circular_spline\.fit_method.*did you mean \"minimax\""):
        parse_gearset(base)


# --------------------------------------------------------------------------- roller angle

ROLLERS4 = {"contour": "rollers", "roller_count": 4, "roller_radius_mm": 10.0}


def test_roller_angle_defaults_to_30_deg_for_four_rollers():
    gs = parse_gearset(with_(base(), "wave_generator", ROLLERS4))
    assert gs.wave_generator.roller_angle_deg == 30.0
    assert gs.wave_generator.roller_angle_rad == pytest.approx(math.pi / 6)
    assert "roller_angle_deg" not in gs.to_dict(include_defaults=False)["wave_generator"]
    assert parse_gearset(gs.to_dict()).wave_generator.roller_angle_deg == 30.0  # round trip
    two = gs.with_values({"wave_generator.roller_count": 2})  # the default is not carried over
    assert two.wave_generator.roller_angle_deg is None and two.wave_generator.roller_angle_rad is None


def test_roller_angle_given():
    gs = parse_gearset(with_(base(), "wave_generator", {**ROLLERS4, "roller_angle_deg": 22.5}))
    assert gs.wave_generator.roller_angle_deg == 22.5
    assert gs.to_dict(include_defaults=False)["wave_generator"]["roller_angle_deg"] == 22.5
    assert gs.with_values({"wave_generator.roller_angle_deg": 40}).wave_generator.roller_angle_deg == 40.0


@pytest.mark.parametrize("value, shown", [(0.0, "0.0 deg"), (45.0, "45.0 deg"), (-10.0, "-10.0 deg"), (60, "60.0 deg")])
def test_roller_angle_range(value, shown):
    (line,) = problems_of(with_(base(), "wave_generator", {**ROLLERS4, "roller_angle_deg": value}))
    assert line == f"wave_generator.roller_angle_deg = {shown}: must be in (0, 45)"


def test_roller_angle_type():
    (line,) = problems_of(with_(base(), "wave_generator", {**ROLLERS4, "roller_angle_deg": "30"}))
    assert line.startswith('wave_generator.roller_angle_deg = "30": must be a number')


def test_roller_angle_only_with_four_rollers():
    wg = {**ROLLERS4, "roller_count": 2, "roller_angle_deg": 30.0}
    (line,) = problems_of(with_(base(), "wave_generator", wg))
    assert line.startswith("wave_generator.roller_angle_deg: only allowed with roller_count = 4")


def test_roller_angle_forbidden_on_a_cam():
    (line,) = problems_of(with_(base(), "wave_generator.roller_angle_deg", 30.0))
    assert line.startswith("wave_generator.roller_angle_deg: only allowed with contour")


def test_roller_angle_checked_even_when_the_count_is_bad():
    problems = problems_of(with_(base(), "wave_generator", {**ROLLERS4, "roller_count": 3, "roller_angle_deg": 50.0}))
    assert len(problems) == 2
    assert problems[0].startswith("wave_generator.roller_count = 3")
    assert problems[1].startswith("wave_generator.roller_angle_deg = 50.0 deg: must be in (0, 45)")
    (line,) = problems_of(with_(base(), "wave_generator", {**ROLLERS4, "roller_count": 3, "roller_angle_deg": 20.0}))
    assert line.startswith("wave_generator.roller_count = 3")
