"""The loaded zone and profile relief (research.loadzone).

On the default set's sketch design at the rated torque: the per-tooth forces add up to the
solver's and balance the zone's torque (Σ r_k F_k = T/U), the bands partition the loaded
teeth; the pressure angle of a point whose normal is known (a radial line turned by a); a zero
relief leaves the solve bitwise unchanged; a relief deeper than the rigid rotation reaches
(φ · max r_k) takes the relieved teeth out of contact while the torque stays balanced, and
the other teeth carry more.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from profilegen.contact.analysis import solve_contact
from research.loadzone import ARCMIN_PER_RAD, LoadZoneError, ProfileRelief, load_zone, pressure_angle_rad, relief_study


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_loadzone")


@pytest.fixture(scope="module")
def setup(default_gearset, default_sketch):
    gs, design = default_gearset, default_sketch  # conftest.py: computed once per worker
    res = solve_contact(design, [gs.torque.rated_nm], stations=3)
    return gs, design, res


def test_zone_balances_and_bands_partition(setup):
    gs, _, res = setup
    case, pts = res.cases[0], res.points
    zone = load_zone(case, pts, teeth_total=gs.gear.flexspline_teeth)
    assert zone.tooth_force_n.sum() == pytest.approx(case.solution.force_n.sum(), rel=1e-14)
    assert float(pts.lever_mm @ case.solution.force_n) == pytest.approx(gs.torque.rated_nm / 2 * 1e3, rel=1e-9)
    assert zone.teeth_in_contact == case.teeth_in_contact
    assert zone.fraction_in_contact == 2 * zone.teeth_in_contact / gs.gear.flexspline_teeth
    assert sum(b["count"] for b in zone.bands) == zone.teeth_in_contact
    assert sum(b["force_share"] for b in zone.bands) == pytest.approx(1.0, rel=1e-12)
    assert len(zone.bands) >= 2  # the two-band pattern of issue 16
    loaded = zone.tooth_force_n > 0
    assert np.all((zone.pressure_angle_deg[loaded] > 0) & (zone.pressure_angle_deg[loaded] < 60))
    assert np.all(zone.flank_t_mm <= zone.flank_length_mm + 1e-12)


def test_pressure_angle_of_a_known_normal(setup):
    _, _, res = setup
    pts = res.points
    a = np.linspace(-0.5, 0.8, pts.count)
    theta = np.linspace(0.1, 0.4, pts.count)  # points anywhere on a circle, normal = e_r turned by a
    e_r = np.column_stack([np.sin(theta), np.cos(theta)])
    e_t = np.column_stack([np.cos(theta), -np.sin(theta)])
    normal = np.sin(a)[:, None] * e_r + np.cos(a)[:, None] * e_t
    fake = dataclasses.replace(pts, fs_point_mm=50.0 * e_r, normal=normal)
    assert np.allclose(pressure_angle_rad(fake), a, atol=1e-12)


def test_zero_relief_is_bitwise_unchanged(setup):
    gs, design, res = setup
    zero = ProfileRelief("major_axis", 0.0)
    assert zero.apply(res.points) is res.points
    study = relief_study(design, gs.torque.rated_nm, [zero, ProfileRelief("tip", 0.0)], result=res)
    for z in study.relieved:
        assert np.array_equal(z.tooth_force_n, study.baseline.tooth_force_n)
        assert z.rotation_rad == study.baseline.rotation_rad
    assert np.array_equal(study.baseline.tooth_force_n, res.cases[0].tooth_force_n)


def test_deep_relief_takes_the_teeth_out(setup):
    gs, design, res = setup
    half = 6.0
    near = np.abs(np.degrees(res.cases[0].tooth_phi_rad)) < half
    assert res.cases[0].tooth_force_n[near].sum() > 0.0  # they carry load before
    relief = ProfileRelief("major_axis", 0.2, half, "flat")
    study = relief_study(design, gs.torque.rated_nm, [relief], result=res)
    z = study.relieved[0]
    pts = relief.apply(res.points)
    assert z.rotation_rad * pts.lever_mm.max() < 0.2  # the rotation's reach stays short of the relief
    assert np.all(z.tooth_force_n[near] == 0.0)
    assert z.max_tooth_force_n > study.baseline.max_tooth_force_n
    assert z.teeth_in_contact < study.baseline.teeth_in_contact
    case = solve_contact(design, [gs.torque.rated_nm], points=pts, compliance=res.compliance).cases[0]
    assert float(pts.lever_mm @ case.solution.force_n) == pytest.approx(gs.torque.rated_nm / 2 * 1e3, rel=1e-9)
    # a tip relief acts along the flank: the extra gap is zero below its start and grows to the depth at the tip
    tip = ProfileRelief("tip", 0.01, start_mm=0.9)
    extra = tip.extra_gap_mm(res.points)
    assert np.all(extra[res.points.t_mm <= 0.9] == 0.0)
    assert extra.max() == pytest.approx(0.01, rel=1e-12)  # at the tip corner


def test_bad_relief_input():
    with pytest.raises(LoadZoneError, match="depth_mm"):
        ProfileRelief(depth_mm=-0.01)
    with pytest.raises(LoadZoneError, match="half_angle_deg"):
        ProfileRelief(half_angle_deg=0.0)
    with pytest.raises(LoadZoneError, match="kind"):
        ProfileRelief(kind="root")
    assert math.isclose(ProfileRelief(depth_mm=0.5).depth_mm, 0.5)


def test_arcmin_constant_is_its_definition():
    # 1′ = 1°/60 = π/10800 rad (SI Brochure, 9th ed., table 4)
    assert ARCMIN_PER_RAD == pytest.approx(10800.0 / math.pi, rel=1e-15)
