"""Potential contact points (profilegen.contact.points): geometry checks against the kinematics."""

import math

import numpy as np
import pytest

from profilegen.contact import ContactInput
from profilegen.contact.points import ContactPointError, contact_points
from profilegen.geometry.kinematics import turn


@pytest.fixture(scope="module")
def inputs(default_sketch):
    """What the contact reads of the default set's sketch design (built as the pipeline does)."""
    return ContactInput.from_design(default_sketch)


def test_points_lie_on_the_placed_fs_flank_and_near_the_cs_flank(inputs):
    cp = contact_points(inputs)
    g = inputs.gearset.gear
    # each FS point is its tooth's flank station placed by the kinematics, in space i
    pose = inputs.motion.pose(cp.phi_rad)
    back = turn(cp.fs_point_mm, -2 * math.pi * cp.tooth / g.circular_spline_teeth)
    local = pose.to_tooth(back)
    np.testing.assert_allclose(local, cp.local_mm, atol=1e-9)
    # the CS foot is at the reported separation, and nowhere does the FS cut the one-sided CS
    assert np.all(cp.gap_mm >= 0.0) and np.all(cp.gap_mm <= cp.max_gap_mm)
    np.testing.assert_allclose(np.linalg.norm(cp.cs_point_mm - cp.fs_point_mm, axis=1), cp.gap_mm, atol=1e-9)
    # unit normals, positive lever arms smaller than the tip radius of the FS
    np.testing.assert_allclose(np.linalg.norm(cp.normal, axis=1), 1.0, atol=1e-12)
    assert np.all(cp.lever_mm > 0) and np.all(cp.lever_mm < g.pitch_radius_mm + 1.0)
    np.testing.assert_allclose(cp.theta_rad, cp.gap_mm / cp.lever_mm)


def test_first_contact_is_near_zero_separation(inputs):
    """The one-sided CS profile touches the FS tooth family (min clearance ~0 over the pass):
    at the discrete teeth and stations the smallest separation is well below a µm."""
    cp = contact_points(inputs)
    assert cp.gap_mm.min() < 2e-3


def test_every_tooth_keeps_its_true_closest_points(inputs):
    """Each tooth's smallest separation over its working flank, from a 4001-station scan,
    is among its points to 1 nm: the coarse stations are moved to the true minima (a
    station 0.05 mm off the minimum overstates it by µm, as much as the teeth differ)."""
    import shapely

    cp = contact_points(inputs, stations=5)
    tooth, motion, g = inputs.tooth, inputs.motion, inputs.gearset.gear
    cs = inputs.cs_space.sample(1e-6)
    # the distance to the polyline is the least distance to its segments: an STR tree finds it
    # (shapely.distance to the LineString tries all ~1000 segments for each of the 4001 × ~60 points: 7 s)
    segments = shapely.STRtree(shapely.linestrings(np.stack([cs[:-1], cs[1:]], axis=1)))
    t = np.linspace(cp.t_mm.min(), tooth.length_mm, 4001)
    local = tooth.evaluate(t, side=1)[0]
    for i in cp.teeth:
        pose = motion.pose(np.full(t.size, 2 * math.pi * i / g.flexspline_teeth))
        _, gaps = segments.query_nearest(shapely.points(pose.to_cs(local)), return_distance=True, all_matches=False)
        assert cp.gap_mm[cp.tooth == i].min() <= gaps.min() + 1e-6


def test_the_other_zone_is_the_image_under_a_half_turn(inputs):
    """One engagement zone stands for both (U = 2): FS tooth i + z1/2 at φ_i + π stands in
    CS space i + z1/2, and its flank is tooth i's turned by π about the gear centre — the
    deformation has period π and the CS (z2 even) is invariant under the half turn — so
    both zones see the same separations and lever arms (the loads, being images too, are
    carried by the point-symmetric half ring of the compliance model)."""
    g = inputs.gearset.gear
    z1, z2 = g.flexspline_teeth, g.circular_spline_teeth
    assert g.waves == 2 and z1 % 2 == 0 and z2 % 2 == 0
    local = inputs.tooth.evaluate(np.linspace(0.0, inputs.tooth.length_mm, 41), side=1)[0]
    for i in (-23, -5, 0, 7, 24):
        placed = []
        for k in (i, i + z1 // 2):
            pose = inputs.motion.pose(np.full(local.shape[0], 2 * math.pi * k / z1))
            placed.append(turn(pose.to_cs(local), 2 * math.pi * k / z2))
        np.testing.assert_allclose(placed[1], turn(placed[0], math.pi), atol=1e-9)


def test_left_flank_mirrors_the_right_flank(inputs):
    """The motion is mirror-symmetric about the major axis (ω even, υ odd) and so is the CS
    space: loading the left flanks gives the mirror image, teeth i ↔ −i, rotation reversed."""
    right = contact_points(inputs, side=1)
    left = contact_points(inputs, side=-1)
    assert right.rotation == -left.rotation and right.count == left.count
    r = np.lexsort((right.t_mm, right.tooth))
    lft = np.lexsort((left.t_mm, -left.tooth))
    np.testing.assert_array_equal(right.tooth[r], -left.tooth[lft])
    # Tolerances from the algorithm: each tooth's closest point is located along the flank by a
    # golden-section search to 1e-7 mm of arc length, and near the minimum the separation is
    # flat (0.5·κ·δt² with κ ~ 2.6 /mm: ~1e-14 mm at δt = 1e-7, the distances' round-off), so
    # the two flanks' searches may stop up to ~1e-7 mm apart along the flank — the points and
    # lever arms (first order in δt, |dp/dt| = 1) agree to that, the separations (second order)
    # to far below 1e-9 mm. Seen: 3.1e-8 mm on one point with another OpenBLAS kernel.
    np.testing.assert_allclose(right.gap_mm[r], left.gap_mm[lft], atol=1e-9)
    np.testing.assert_allclose(right.lever_mm[r], left.lever_mm[lft], atol=1e-7)
    mirror = np.array([-1.0, 1.0])
    np.testing.assert_allclose(right.fs_point_mm[r], left.fs_point_mm[lft] * mirror, atol=1e-7)


def test_a_smaller_cutoff_keeps_a_subset(inputs):
    wide = contact_points(inputs, max_gap_mm=0.05)
    narrow = contact_points(inputs, max_gap_mm=0.01)
    assert 0 < narrow.count < wide.count and np.all(narrow.gap_mm <= 0.01)


@pytest.mark.parametrize("kw, name", [({"side": 0}, "side"), ({"stations": 1}, "stations"),
                                      ({"max_gap_mm": -1.0}, "max_gap_mm"), ({"max_gap_mm": 1e-12}, "max_gap_mm")])
def test_bad_input_names_the_parameter(inputs, kw, name):
    with pytest.raises(ContactPointError, match=name):
        contact_points(inputs, **kw)
