"""The CS outline: closure, periodicity, clearances, and the clearance map's physics."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

import profilegen as pg
from profilegen.geometry.contour import Arc, Chain, Line
from profilegen.errors import EnvelopeError
from profilegen.profile.gearform import circular_spline_form, clearance_map, cs_chain


@pytest.fixture(scope="module")
def form_default(default_set):
    tooth, motion, env = default_set
    return circular_spline_form(env, cs_teeth=202, tip_clearance_mm=0.125, root_clearance_mm=0.125)


def test_outline_is_periodic_closed_and_valid(form_default):
    f = form_default
    ring = shapely.LinearRing(f.outline)
    assert ring.is_valid and ring.is_simple
    r = np.hypot(*f.outline.T)
    assert r.min() == pytest.approx(f.tip_radius_mm, abs=1e-9)
    assert r.max() == pytest.approx(f.root_radius_mm, abs=1e-9)
    n = len(f.outline) // 202
    unit = f.outline[:n]
    turned = pg.geometry.kinematics.turn(unit, 2 * math.pi / 202)
    np.testing.assert_allclose(turned, f.outline[n : 2 * n], atol=1e-9)
    assert f.polygon().is_valid


def test_clearances_are_the_gear_set_values(form_default, default_set):
    """Tip circle = where neighbouring swept regions meet + tip clearance; root circle =
    highest point of the swept region (FS tip on the major axis) + root clearance."""
    tooth, motion, env = default_set
    chain = env.flank["boundary"]
    r_meet = max(np.hypot(*chain[0]), np.hypot(*chain[-1]))
    assert form_default.tip_radius_mm == pytest.approx(r_meet + 0.125, abs=1e-12)
    # highest FS point: a tip corner near the major axis, found here by a dense scan of φ
    phi = np.linspace(-0.05, 0.05, 200001)
    corner = np.broadcast_to(tooth.tip_point, (phi.size, 2))
    top = np.hypot(*motion.pose(phi).to_cs(corner).T).max()
    assert top > np.hypot(tooth.tip_point[0], 48.95 + 0.5 + tooth.addendum_y_mm) - 1e-12
    # (the chain's vertices find the maximum to the envelope's chord tolerance)
    assert form_default.root_radius_mm == pytest.approx(top + 0.125, abs=env.chord_tol_mm)


def test_clearance_map_zero_on_the_working_flank_never_negative(form_default, default_set):
    """Conjugate action: the tooth touches the CS over the working zone (clearance 0 to the
    chord tolerance) and never enters it."""
    tooth, motion, env = default_set
    cmap = clearance_map(form_default, tooth, motion, phi_range=env.phi_range, samples=181)
    assert cmap.min_mm >= -2 * env.chord_tol_mm
    touching = np.abs(cmap.clearance_mm) < 1e-5
    assert touching.sum() > 30  # continuous contact over a wide zone (|φ| up to ~65°)
    assert np.all(cmap.clearance_mm[np.abs(cmap.phi) > 1.45] > 0.05)  # out of mesh near the minor axis


def test_cs_chain_closes_exactly_from_any_g1_flank(form_default):
    """A G1 arc–line–arc flank (here made up) becomes a closed outline with gaps ≤ 1e-9 mm,
    starting exactly on the tip circle, mirror-symmetric."""
    f = form_default
    w = f.working_flank["right"]
    p0 = w[0] + np.array([0.003, -0.002])  # deliberately off the tip circle
    # up the flank, turning toward the space axis (−x): counter-clockwise arcs
    a1 = Arc(p0 - np.array([1.0, 0.0]), 1.0, 0.0, 0.1)
    line = Line(a1.end, a1.end + 0.2 * a1.tangent(at_end=True))
    t = line.tangent()
    n = np.array([-t[1], t[0]])  # left normal
    a2 = Arc(line.end + 0.8 * n, 0.8, math.atan2(-n[1], -n[0]), 0.2)
    space, outline = cs_chain(Chain((a1, line, a2)), tip_radius_mm=f.tip_radius_mm, root_radius_mm=f.root_radius_mm, cs_teeth=202)
    assert outline.gaps(closed=True).max() <= 1e-9
    assert np.hypot(*space.start) == pytest.approx(f.tip_radius_mm, abs=1e-12)
    assert np.hypot(*space.end) == pytest.approx(f.tip_radius_mm, abs=1e-12)
    np.testing.assert_allclose(space.start * [-1, 1], space.end, atol=1e-12)
    assert np.all(space.kinks_deg()[:2] < 1e-9)  # the flank itself stays G1
    assert len(outline.elements) == 202 * (len(space.elements) + 1)
    assert shapely.Polygon(outline.sample(1e-3)).is_valid


class _SegmentTree:
    """Distances of points to a polyline as shapely.distance to its LineString gives them (the
    least point-to-segment distance, bit for bit), from an STR tree of its segments: shapely
    tries every segment for every point (the brute-force test's 37 poses took ~10 s)."""

    def __init__(self, xy):
        xy = np.asarray(xy, float)
        self.tree = shapely.STRtree(shapely.linestrings(np.stack([xy[:-1], xy[1:]], axis=1)))

    def distance(self, points):
        return self.tree.query_nearest(shapely.points(points), return_distance=True, all_matches=False)[1]


def test_clearance_map_equals_brute_force_distance(form_default, default_set):
    """At every sampled pose the map equals the brute-force signed distance of all CS outline
    points around the space to the tooth's real surface (shapely, no candidate search):
    exactly near contact (< 10 µm, where interference would show), within 1 µm (never
    below) far out of mesh."""
    from profilegen.profile.gearform import _local_outline

    tooth, motion, env = default_set
    cmap = clearance_map(form_default, tooth, motion, phi_range=env.phi_range, samples=37)
    cs = _local_outline(form_default)
    surface = _SegmentTree(tooth.surface(n_per_mm=400.0))
    poly = shapely.Polygon(tooth.outline(n_per_mm=400.0))
    for phi, value in zip(cmap.phi, cmap.clearance_mm):
        q = motion.pose(np.array([phi])).to_tooth(cs)
        d = surface.distance(q)
        inside = shapely.contains_xy(poly, q[:, 0], q[:, 1])
        truth = np.min(np.where(inside, -d, d))
        if truth < 0.01:
            assert value == pytest.approx(truth, abs=1e-12), np.degrees(phi)
        else:
            assert truth <= value <= truth + 1e-3, np.degrees(phi)


def test_cs_chain_closes_a_narrow_space_with_one_tangent_arc(form_default):
    """A flank whose end tangent meets the space's axis inside the root circle (a thin FS
    tooth, as in seed 001's SHF-25 set) is closed by one arc centred on the axis: the whole
    space is G1 (no kink anywhere), closed, mirror-symmetric, and its apex lies on the axis
    inside the root circle, where the two end tangents' crossing bounds it."""
    f = form_default
    r_root = f.root_radius_mm
    end = np.array([0.07, r_root - 0.10])  # 0.07 mm from the axis, 0.1 mm below the root circle
    t = np.array([-1.0, 1.0]) / np.sqrt(2.0)  # 45°: the tangent meets the axis at r_root - 0.03
    start = end - 1.3 * t  # a plain line flank, from inside the tip circle
    assert np.hypot(*start) < f.tip_radius_mm
    flank = Chain((Line(start, end),))
    space, outline = cs_chain(flank, tip_radius_mm=f.tip_radius_mm, root_radius_mm=r_root, cs_teeth=202)
    assert outline.gaps(closed=True).max() <= 1e-9
    assert np.all(space.kinks_deg() < 1e-9)  # G1 through both flank ends
    np.testing.assert_allclose(space.start * [-1, 1], space.end, atol=1e-12)
    pts = space.sample(1e-5)
    top = pts[np.argmax(np.hypot(*pts.T))]
    assert abs(top[0]) < 1e-4
    crossing = end[1] + end[0] * t[1] / -t[0]  # where the end tangent meets x = 0
    assert end[1] < np.hypot(*top) < crossing < r_root


def test_a_narrow_space_runs_its_flanks_on_until_the_closure_clears_the_swept_region(form_default):
    """The closing arc of a narrow space passes over the FS tip land's corners. Where they reach
    into it (here a disk of 20 µm radius standing for a corner's path, 3 µm into the arc's apex),
    each flank runs on along its end tangent, G1, by the shortest line that lifts the arc out:
    the result clears the disk, a run 1 µm shorter does not, and with the disk far below nothing
    changes (a depth within the tolerance, or a disk far below)."""
    from profilegen.profile.gearform import _closure_arc, cs_space

    f = form_default
    r_root = f.root_radius_mm
    end = np.array([0.07, r_root - 0.10])
    t = np.array([-1.0, 1.0]) / np.sqrt(2.0)
    flank = Chain((Line(end - 1.3 * t, end),))
    plain = cs_space(flank, tip_radius_mm=f.tip_radius_mm, root_radius_mm=r_root)
    arc = _closure_arc(end, t)
    apex = arc.centre + [0.0, arc.radius]
    centre, rho = np.array([0.0, apex[1] - 0.020 + 0.003]), 0.020  # a corner's path, 3 µm into the apex

    def swept(points):  # depth > 0 inside the disk, exact
        return rho - np.hypot(*(np.asarray(points) - centre).T)

    def depth_of(space):
        return float(np.max(swept(space.sample(1e-9))))

    assert depth_of(plain) == pytest.approx(0.003, abs=1e-7)
    fixed = cs_space(flank, tip_radius_mm=f.tip_radius_mm, root_radius_mm=r_root, swept=swept, swept_tol_mm=1e-5)
    assert depth_of(fixed) <= 1e-7  # out, to 0.1 nm (the search samples the arc, refined at its worst point)
    assert np.all(fixed.kinks_deg() < 1e-9)  # still G1: flank → run-on line → arc
    np.testing.assert_allclose(fixed.start * [-1, 1], fixed.end, atol=1e-12)
    runs = [el for el in fixed.elements if isinstance(el, Line) and el.length < 0.5]
    assert len(runs) == 2  # one run-on line per flank
    run = runs[0].length
    assert 0.0 < run < end[0] / -t[0]  # short of the tangents' meeting on the axis
    shorter = _closure_arc(end + (run - 1e-3) * t, t)
    assert float(np.max(swept(shorter.sample(1e-9)))) > 0.0  # the shortest: 1 µm less enters the disk
    # within the tolerance, or with the disk far below: the closure as before
    for c in (centre - [0.0, 0.003 - 5e-6], centre - [0.0, 0.05]):
        same = cs_space(flank, tip_radius_mm=f.tip_radius_mm, root_radius_mm=r_root,
                        swept=lambda p, c=c: rho - np.hypot(*(np.asarray(p) - c).T), swept_tol_mm=1e-5)
        assert len(same.elements) == len(plain.elements)
        np.testing.assert_allclose(same.sample(1e-5), plain.sample(1e-5), atol=1e-12)


def test_cs_chain_refuses_a_flank_past_the_axis(form_default):
    f = form_default
    flank = Chain((Line(np.array([0.2, f.tip_radius_mm + 0.01]), np.array([-0.01, f.root_radius_mm - 0.05])),))
    with pytest.raises(EnvelopeError, match="axis"):
        cs_chain(flank, tip_radius_mm=f.tip_radius_mm, root_radius_mm=f.root_radius_mm, cs_teeth=202)


def test_clearance_map_finds_the_deepest_point_of_a_dense_interfering_outline(form_default, default_set):
    """A CS outline sampled every ~0.5 µm and moved 5 µm towards the FS (radially inward)
    interferes: the 32 nearest-surface candidates all crowd where it crosses the tooth, and
    the map must still read the brute-force depth (all points inside the tooth, shapely)."""
    from profilegen.profile.gearform import _local_outline

    tooth, motion, env = default_set
    cs = _local_outline(form_default)
    r = np.hypot(*cs.T)
    near = np.abs(r - np.median(r)) < 0.6  # the working depth around the pitch circle
    seg = np.nonzero(near[:-1] & near[1:])[0]
    steps = np.maximum(1, np.ceil(np.hypot(*(cs[seg + 1] - cs[seg]).T) / 5e-4).astype(int))
    dense = np.vstack([cs[i] + np.linspace(0, 1, n, endpoint=False)[:, None] * (cs[i + 1] - cs[i])
                       for i, n in zip(seg, steps)])
    dense = dense * (1.0 - 5e-3 / np.hypot(*dense.T))[:, None]  # 5 µm towards the centre
    phis = (env.phi_range[0] + 0.45 * np.ptp(env.phi_range), env.phi_range[0] + 0.5 * np.ptp(env.phi_range))
    cmap = clearance_map(form_default, tooth, motion, phi_range=phis, samples=5, cs_points=dense)
    surface = _SegmentTree(tooth.surface(n_per_mm=400.0))
    poly = shapely.Polygon(tooth.outline(n_per_mm=400.0))
    truths = []
    for phi, value in zip(cmap.phi, cmap.clearance_mm):
        q = motion.pose(np.array([phi])).to_tooth(dense)
        inside = shapely.contains_xy(poly, q[:, 0], q[:, 1])
        truth = -float(np.max(surface.distance(q[inside]))) if inside.any() else None
        truths.append(truth)
        if truth is not None and truth < -1e-4:
            assert value == pytest.approx(truth, abs=2e-6), np.degrees(phi)
    assert min(t for t in truths if t is not None) < -1e-3  # the case does interfere by µm
    shallow = clearance_map(form_default, tooth, motion, phi_range=phis, samples=5, cs_points=dense,
                            deep_check_mm=np.inf)
    assert shallow.min_mm > cmap.min_mm + 1e-4  # without the check the depth is under-read


def test_clearance_map_the_same_with_or_without_the_first_pass_of_fewer_pairs(form_default, default_set):
    """few_first True (the 1.25 x candidates nearest pairs first, 4 x where too few) and False (4 x
    at once) are two searches for the same nearest pairs: the same map bit for bit, on the form's
    own outline and on a given one; the default (None) is one of them."""
    from profilegen.profile.gearform import _local_outline

    tooth, motion, env = default_set
    given = _local_outline(form_default)[::3]
    for cs_points in (None, given):
        maps = [clearance_map(form_default, tooth, motion, phi_range=env.phi_range, samples=41, cs_points=cs_points,
                              few_first=f).clearance_mm for f in (True, False, None)]
        np.testing.assert_array_equal(maps[0], maps[1])
        np.testing.assert_array_equal(maps[0], maps[2])


def test_the_contact_takes_the_arc_fits_cs_outline(default_sketch):
    """The contact inputs carry the outline the arc fit built (the sliced curve does not build it
    again), and that outline is the fitted space's: a build from scratch equals it point for
    point; another tip radius gives another tip land."""
    from profilegen.contact import ContactInput
    from profilegen.profile.gearform import cs_outline

    prof, form = default_sketch.profile, default_sketch.form
    assert ContactInput.from_design(default_sketch).cs_outline is prof.outline
    z2 = default_sketch.gearset.gear.circular_spline_teeth
    fresh = cs_outline(prof.space, tip_radius_mm=form.tip_radius_mm, cs_teeth=z2)
    assert fresh is not prof.outline
    np.testing.assert_array_equal(fresh.sample(1e-4), prof.outline.sample(1e-4))
    wider = cs_outline(prof.space, tip_radius_mm=form.tip_radius_mm + 0.01, cs_teeth=z2)
    assert len(wider.elements) == len(prof.outline.elements)
    assert wider.elements[len(prof.space.elements)].radius == pytest.approx(form.tip_radius_mm + 0.01)  # the tip land


def test_the_outline_is_the_space_turned_to_every_tooth(default_sketch):
    """cs_outline builds its copies in arrays and without the constructors' checks: against the
    space's elements turned one by one by the rotation matrix (Arc/Line.transformed) and joined by
    tip-circle arcs, every element's numbers agree to round-off, and every copy is what the
    constructor would have accepted (the closed chain itself checks the joints)."""
    from profilegen.profile.gearform import cs_outline

    prof, form = default_sketch.profile, default_sketch.form
    z2 = default_sketch.gearset.gear.circular_spline_teeth
    outline = cs_outline(prof.space, tip_radius_mm=form.tip_radius_mm, cs_teeth=z2)
    n = len(prof.space.elements) + 1
    assert len(outline.elements) == z2 * n
    for k in (0, 1, z2 // 3, z2 - 1):
        turn = -k * 2 * math.pi / z2
        rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
        for got, e in zip(outline.elements[k * n:(k + 1) * n - 1], prof.space.elements):
            want = e.transformed(rot)
            assert type(got) is type(want)
            if isinstance(want, Line):
                np.testing.assert_allclose([got.start, got.end], [want.start, want.end], rtol=0, atol=1e-12)
                Line(got.start, got.end)
            else:
                np.testing.assert_allclose(got.centre, want.centre, rtol=0, atol=1e-12)
                assert (got.radius, got.sweep) == (want.radius, want.sweep)
                assert math.remainder(got.start_angle - want.start_angle, 2 * math.pi) == pytest.approx(0, abs=1e-12)
                Arc(got.centre, got.radius, got.start_angle, got.sweep)
        tip = outline.elements[(k + 1) * n - 1]
        assert isinstance(tip, Arc) and tip.radius == form.tip_radius_mm and not tip.centre.flags.writeable
        assert tip.sweep < 0  # clockwise, the short way to the next space


def test_a_map_split_over_two_threads_is_the_map(default_sketch):
    """clearance_map(threads=2) measures the later half of the poses on a thread of its own: every
    pose is measured on its own, so the numbers are the single thread's, bit for bit (the fitted
    outline's check and the form's own), and the halves do not share GEOS's prepared polygon (a
    shared one corrupted the heap when first tried)."""
    from profilegen.profile.gearform import cs_local_chain

    d = default_sketch
    fitted = cs_local_chain(d.profile.space, d.profile.outline).sample(1e-7)
    for cs, samples in ((fitted, 301), (None, 257)):
        one = clearance_map(d.form, d.tooth, d.motion, phi_range=d.envelope.phi_range, samples=samples, cs_points=cs)
        two = clearance_map(d.form, d.tooth, d.motion, phi_range=d.envelope.phi_range, samples=samples, cs_points=cs,
                            threads=2)
        assert np.array_equal(one.phi, two.phi) and np.array_equal(one.clearance_mm, two.clearance_mm)
