"""The 3D cup as a rim tier (issue 15 items 1 and 6): the ``[cup]`` fields it needs, the
``cup3d`` tier of the rim stage, the scenes and ``profilegen design --rim``.

Checked against things the tier does not compute itself:

* a long cup on a narrow bearing gives the 2D flat ring's ω, υ (the design tier: nonlinear,
  exact gap) within 1 % of w0 at the bearing's section (the cup nonlinear with the exact gap,
  as the cup3d tier);
* the default-length cup cones: at the tooth ring's diaphragm end the major axis sits on the
  cam (ω = w0) and the open end flares beyond it; the kinematics' Fourier model is the 3D
  answer at the design section;
* a wall as thick as the tooth ring is the cup of one thickness, bit for bit (same mesh, same
  answer); a thinner wall ties the ring less to the diaphragm: the coning across the face
  (open end − diaphragm end, major axis) falls monotonically with it;
* bad ``[cup]`` input is a GearSetError naming the field, its value, mm and the range, with
  the same rule (and wording) as CupGeometry's CupError;
* scene resolution: verify → cup3d, the 2D toothed rim as tier "toothed", ``--rim``.

Coarse meshes (4 mm along the meridian, 8 contact angles): the file runs in a few seconds.
"""

import copy
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from profilegen.errors import GearSetError
from profilegen.gearset import default_gearset_path, load_gearset, parse_gearset
from profilegen.rim.cup import CupError, CupGeometry, meridional_mesh, press_cup, solve_cup
from profilegen.rim.stage import RIM_TIERS, RimTier, solve_rim
from profilegen.geometry.wavegen import CosineCam

COARSE = RimTier("cup3d", "cup", geometry="linear", layers=2, divisions=0, max_order=16, element_mm=4.0, angles=8)
CHEAP = RimTier("cup3d", "cup", geometry="nonlinear", layers=2, divisions=0, max_order=16, element_mm=8.0, angles=8)
E, NU, R_M, T = 209000.0, 0.295, 48.95, 0.9


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_cup_tier")


@pytest.fixture(scope="module")
def default_data():
    return tomllib.loads(Path(default_gearset_path()).read_text())


def _with_cup(data, **cup):
    d = copy.deepcopy(data)
    d.setdefault("cup", {}).update(cup)
    return d


@pytest.fixture(scope="module")
def default_rim():
    return solve_rim(load_gearset(default_gearset_path()), tier=COARSE)


# --------------------------------------------------------------------------- the tier


def test_long_cup_on_a_narrow_bearing_gives_the_2d_ring(default_data, monkeypatch):
    """A 300 mm cup pressed over 2 mm at its mid-face by the default elliptical cam is the design
    tier's 2D flat ring (nonlinear, exact gap) at that section, within 1 % of w0. Measured:
    2.4 µm in ω, 0.7 µm in υ at 8 mm / 8 angles (4 mm / 16: 2.5, 0.7; at l = 150 mm: 3.2, 0.4).
    The linear cup with the same exact gap is 15 µm off (the nonlinearity). The 2D ring sits on
    the rigid cam, so the cup does too here: the rigid band, not the outer race on its balls
    (whose ovalisation and Hertz approach take 10.7 µm more off ω)."""
    import profilegen.rim.cup.bearing as bearing

    monkeypatch.setattr(bearing, "CUP_TIER_RACE", "rigid")
    gs = parse_gearset(_with_cup(default_data, length_mm=300.0, bearing_width_mm=2.0))
    cup = solve_rim(gs, tier=CHEAP)
    ring = solve_rim(gs, tier="design")
    assert cup.section_z_mm == 300.0  # the mid-face, where the bearing is
    phi, w, u = ring.fem.phi_rad, ring.fem.omega_mm, ring.fem.upsilon_mm
    w0 = gs.deflection_mm
    cw, cu = cup.model.evaluate(phi, order=0)
    assert np.max(np.abs(cw[0] - w)) < 0.01 * w0
    assert np.max(np.abs(cu[0] - u)) < 0.01 * 0.5 * w0
    # the kinematics' model is the 3D answer at that section (the fit of its samples)
    assert np.max(np.abs(cw[0] - cup.cup.omega(phi, 300.0))) < 1e-6
    assert cup.fem.geometry == "nonlinear" and len(cup.fem.newton_steps_mm) > 0


def test_the_default_cup_cones_and_its_section_is_the_model(default_rim):
    """The bore on the outer race, the race on its ball row at the bearing's mid-plane: on the
    major axis the section over the balls sits on the cam, within 2 % of w0 (less the race's
    ovalisation and the balls' Hertz approach: −3.2 µm on the nonlinear design mesh; +5.2 µm on
    this coarse linear one), and the cup cones about it (ω ∝ z from the cup bottom: 50/60/70 mm
    → 0.85/1/1.17 of the ball row's, z ratios 0.83/1.17)."""
    rim = default_rim
    g = rim.cup.geometry
    lo, hi = g.ring_span_mm
    w0 = 0.5
    zc = g.bearing_center_mm
    assert rim.section_z_mm == g.length_mm
    at_balls = rim.cup.omega(0.0, zc)
    assert at_balls == pytest.approx(w0, abs=0.02 * w0)
    for z in (lo, hi):
        assert rim.cup.omega(0.0, z) / at_balls == pytest.approx(z / zc, rel=0.03)  # the cone about the ball row
    phi, w, u = rim.samples
    fw, fu = rim.model.evaluate(phi, order=0)
    assert np.max(np.abs(fw[0] - w)) < 1e-6 and np.max(np.abs(fu[0] - u)) < 1e-6
    assert np.max(np.abs(w - rim.cup.omega(phi, g.length_mm))) < 1e-12  # the samples are that section's
    # the stand-in ring solution the report and the contact stage read
    assert rim.fem.omega_mm[0] == pytest.approx(float(rim.cup.omega(0.0, g.length_mm)))
    assert 0.0 < rim.fem.contact_angle_rad <= 0.5 * math.pi and rim.dof == rim.cup.dof
    # against half the resolution (8 mm, 4 angles: too few for the wrap, hence the large change)
    assert 0.0 < rim.error_estimate_mm < 0.1 * w0 and "8 mm and 4 angles" in rim.error_measure


def test_design_section_argument_and_summary(default_data, default_rim):
    import json

    gs = parse_gearset(default_data)
    d = json.loads(json.dumps(default_rim.to_dict()))
    ends = {s["where"]: s for s in d["cup"]["sections"]}
    assert ends["open end"]["omega_major_mm"] > ends["mid-face"]["omega_major_mm"] > ends["diaphragm end"]["omega_major_mm"]
    with pytest.raises(CupError, match=r"z_mm = 75.0 mm: must be in \[50, 70\]"):
        solve_rim(gs, tier=COARSE, z_mm=75.0)
    # the section moved on the same 3D answer: the open end's ω, υ are the kinematics' model there
    moved = default_rim.at_section(70.0)
    phi = np.linspace(0.0, math.pi, 37)
    fw, fu = moved.model.evaluate(phi, order=0)
    assert np.max(np.abs(fw[0] - default_rim.cup.omega(phi, 70.0))) < 1e-6
    assert np.max(np.abs(fu[0] - default_rim.cup.upsilon(phi, 70.0))) < 1e-6
    assert moved.section_z_mm == 70.0 and moved.error_estimate_mm == default_rim.error_estimate_mm
    with pytest.raises(CupError, match="z_mm"):
        default_rim.at_section(49.0)
    assert RIM_TIERS["cup3d"].model == "cup" and RIM_TIERS["toothed"].model == RIM_TIERS["verify"].model == "toothed"


# --------------------------------------------------------------------------- the wall


def _cup(wall=None, length=60.0, **kw):
    if wall is None:
        return CupGeometry(R_M, T, length, 20.0, T, 0.5 * R_M, E, NU, **kw)
    return CupGeometry(R_M, wall, length, 20.0, T, 0.5 * R_M, E, NU, ring_thickness_mm=T, **kw)


def test_a_wall_as_thick_as_the_ring_is_the_cup_of_one_thickness_bit_for_bit():
    one, same = _cup(length=300.0), _cup(wall=T, length=300.0)
    m1, m2 = meridional_mesh(one, element_mm=8.0).mesh, meridional_mesh(same, element_mm=8.0).mesh
    assert np.array_equal(m1.p, m2.p) and np.array_equal(m1.t, m2.t)
    a = solve_cup(one, radial_mm={2: 0.5}, element_mm=8.0)
    b = solve_cup(same, radial_mm={2: 0.5}, element_mm=8.0)
    for name in ("z_mm", "radial_mm", "axial_mm", "tangential_mm", "bore_radial_mm"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def test_a_thinner_wall_cones_less():
    coning = []
    for wall in (0.9, 0.7, 0.5):
        g = _cup(wall=wall)
        assert g.wall_outer_radius_mm == pytest.approx(g.bore_radius_mm + wall)
        d = press_cup(g, contour=CosineCam(g.bore_radius_mm, 0.5), element_mm=4.0, angles=8).deformation
        lo, hi = g.ring_span_mm
        coning.append(float(d.omega(0.0, hi) - d.omega(0.0, lo)))
    assert coning[0] > coning[1] > coning[2] > 0.0, coning
    # the thinner wall's mesh has the wall and bottom end at r_bore + t_w: no element beyond
    mesh = meridional_mesh(_cup(wall=0.5), element_mm=4.0).mesh
    centre = mesh.p[:, mesh.t].mean(axis=1)
    g = _cup(wall=0.5)
    below = centre[1] < g.ring_span_mm[0]
    assert np.all(centre[0][below] < g.bore_radius_mm + 0.5) and np.any(centre[0][~below] > g.bore_radius_mm + 0.5)


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize("cup, field, geometry_kw", [
    (dict(length_mm=40.0, face_width_mm=85.0), "face_width_mm", dict(length_mm=40.0, face_width_mm=85.0)),  # b ≥ 2l − t_b
    (dict(bearing_center_mm=75.0), "bearing_center_mm", dict(bearing_center_mm=75.0)),  # outside the tooth ring
    (dict(bearing_width_mm=10.0, bearing_center_mm=52.0), "bearing_center_mm",
     dict(bearing_width_mm=10.0, bearing_center_mm=52.0)),  # sticks out of it
    (dict(bearing_width_mm=25.0), "bearing_width_mm", dict(bearing_width_mm=25.0)),  # wider than the face
    (dict(boss_radius_mm=45.0, bottom_thickness_mm=5.0), "bottom_thickness_mm",
     dict(boss_radius_mm=45.0, bottom_thickness_mm=5.0)),  # thicker than the boss leaves the bottom wide
    (dict(wall_thickness_mm=0.4), "wall_thickness_mm", dict(wall=0.4)),  # thinner than δ/2
    (dict(wall_thickness_mm=1.0), "wall_thickness_mm", dict(wall=1.0)),  # thicker than the ring
])
def test_bad_cup_input_is_named_once_for_the_reader_and_the_geometry(default_data, cup, field, geometry_kw):
    with pytest.raises(GearSetError) as info:
        parse_gearset(_with_cup(default_data, **cup))
    (line,) = [p for p in info.value.problems if f"cup.{field}" in p]
    assert " mm: must be in " in line
    kw = dict(geometry_kw)
    wall = kw.pop("wall", None)
    base = dict(length_mm=60.0, face_width_mm=20.0, bottom_thickness_mm=T, boss_radius_mm=0.5 * R_M)
    base.update(kw)
    with pytest.raises(CupError) as geo:
        if wall is None:
            CupGeometry(neutral_radius_mm=R_M, wall_thickness_mm=T, youngs_modulus_mpa=E, poisson_ratio=NU, **base)
        else:
            CupGeometry(R_M, wall, 60.0, 20.0, T, 0.5 * R_M, E, NU, ring_thickness_mm=T)
    assert isinstance(geo.value, ValueError)
    assert line == f"cup.{geo.value}"  # one rule, one wording


def test_profilegen_check_names_the_cup_field(tmp_path, default_data, capsys):
    from profilegen.cli import main

    text = Path(default_gearset_path()).read_text() + "\n[cup]\nbearing_center_mm = 75.0\n"
    path = tmp_path / "bad.toml"
    path.write_text(text)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr()
    out = err.out + err.err
    assert "cup.bearing_center_mm = 75.0 mm: must be in [60, 60]" in out and "bearing width" in out


# --------------------------------------------------------------------------- scenes and the CLI


def test_scenes_pick_the_tiers(tmp_path):
    from profilegen.pipeline.scenes import RIM_TIER_NAMES, SCENES, SceneError, resolve_scene, with_rim_tier

    assert set(RIM_TIER_NAMES) == set(RIM_TIERS)
    assert SCENES["verify"].rim_tier == "cup3d" and SCENES["design"].rim_tier == "design"
    path = tmp_path / "signoff.toml"
    path.write_text('[signoff]\ntier = "toothed"\nrim = "toothed rim"\nchord_tol_mm = 1e-7\nn_t = 192\nn_phi = 481\n'
                    'clearance_samples = 721\nbrute_force_check = true\ndescription = "2D sign-off"\n')
    assert resolve_scene(str(path)).rim_tier == "toothed"
    design3d = with_rim_tier(SCENES["design"], "cup3d")
    assert design3d.rim_tier == "cup3d" and design3d.chord_tol_mm == SCENES["design"].chord_tol_mm
    assert with_rim_tier(SCENES["design"], None) is SCENES["design"]
    with pytest.raises(SceneError, match="rim tier = 'cup4d'"):
        with_rim_tier(SCENES["design"], "cup4d")


class _Stop(Exception):
    pass


def test_design_rim_flag_overrides_the_scene_tier(monkeypatch, tmp_path, capsys):
    """--rim reaches the pipeline as the scene's tier (the design itself is stopped there)."""
    import contextlib

    import profilegen.output.files as files
    import profilegen.pipeline.design as pipeline
    from profilegen.cli import main

    seen = {}

    def fake_design(gearset, *, scene, **kw):
        seen["scene"] = scene
        raise _Stop

    monkeypatch.setattr(pipeline, "design", fake_design)
    monkeypatch.setattr(files, "figure_workers", lambda *args, **kwargs: contextlib.nullcontext(None))
    with pytest.raises(_Stop):
        main(["design", "--rim", "cup3d", "--scene", "design", "--out", str(tmp_path / "d"), "-q"])
    assert seen["scene"].rim_tier == "cup3d" and seen["scene"].name == "design"
    with pytest.raises(_Stop):
        main(["design", "--scene", "verify", "--rim", "toothed", "--out", str(tmp_path / "v"), "-q"])
    assert seen["scene"].rim_tier == "toothed" and seen["scene"].brute_force_check
    assert main(["design", "--rim", "cup4d", "--out", str(tmp_path / "x"), "-q"]) == 2
    assert "rim tier = 'cup4d'" in capsys.readouterr().err
