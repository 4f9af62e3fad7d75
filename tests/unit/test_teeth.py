"""Unit tests of profilegen.geometry.teeth, checked against geometry computed here, not against
the module's own intermediate values.

Default case: m = 0.5 mm, z1 = 200, r_m = 48.95 mm -> r1 = 50 mm, y_p = 1.05 mm.
"""

from __future__ import annotations

import dataclasses
import json
import math
import types

import numpy as np
import pytest
import shapely
from scipy.optimize import brentq
from shapely.geometry import LineString, Polygon

from profilegen.geometry import teeth as teeth_mod
from profilegen.errors import GearSetError, ToothError
from profilegen.geometry.teeth import (
    ArcSegment,
    InvoluteSegment,
    LineSegment,
    SplineSegment,
    ToothProfile,
    dcta_tooth,
    involute_tooth,
    points_tooth,
    tooth_from_gearset,
)

GEAR = dict(module_mm=0.5, teeth=200, neutral_radius_mm=48.95)
M, Z1, RM = 0.5, 200, 48.95
R1 = M * Z1 / 2
YP = R1 - RM


@pytest.fixture(scope="module")
def dcta() -> ToothProfile:
    return dcta_tooth(**GEAR)


@pytest.fixture(scope="module")
def involute() -> ToothProfile:
    return involute_tooth(**GEAR)


def _interior(seg, n=101):
    """Parameters strictly inside a segment."""
    return np.linspace(seg.t0, seg.t1, n + 2)[1:-1]


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _angle(v):
    return np.arctan2(v[..., 1], v[..., 0])


# --------------------------------------------------------------------------- DCTA


def test_dcta_line_passes_through_pitch_point_at_given_distances(dcta):
    a = math.radians(10.0)
    d = np.array([-math.sin(a), math.cos(a)])
    P = np.array([math.pi * M / 4, YP])
    kinds = [type(s) for s in dcta.segments]
    assert kinds == [ArcSegment, LineSegment, ArcSegment]
    line = dcta.segments[1]
    B = dcta.point(line.t0)
    A = dcta.point(line.t1)
    np.testing.assert_allclose(A - P, 0.05 * d, atol=1e-14)
    np.testing.assert_allclose(P - B, 0.20 * d, atol=1e-14)
    # every line point is on the straight line through P with direction d
    p = dcta.point(_interior(line))
    assert np.max(np.abs(_cross(p - P, d))) < 1e-14
    assert line.t1 - line.t0 == pytest.approx(0.25, abs=1e-15)


def test_dcta_arcs_are_the_specified_circles(dcta):
    a = math.radians(10.0)
    d = np.array([-math.sin(a), math.cos(a)])
    n = np.array([math.cos(a), math.sin(a)])
    P = np.array([math.pi * M / 4, YP])
    A, B = P + 0.05 * d, P - 0.20 * d
    c_tip, c_root = A - 0.65 * n, B + 0.70 * n
    root, _, tip = dcta.segments
    p = dcta.point(_interior(tip))
    np.testing.assert_allclose(np.hypot(*(p - c_tip).T), 0.65, atol=1e-14)
    p = dcta.point(_interior(root))
    np.testing.assert_allclose(np.hypot(*(p - c_root).T), 0.70, atol=1e-14)


def test_dcta_ends_exactly_on_addendum_and_dedendum(dcta):
    assert dcta.tip_point[1] == pytest.approx(YP + 0.40, abs=1e-12)
    assert dcta.root_point[1] == pytest.approx(YP - 0.60, abs=1e-12)
    assert dcta.addendum_y_mm == pytest.approx(YP + 0.40, abs=1e-12)
    assert dcta.dedendum_y_mm == pytest.approx(YP - 0.60, abs=1e-12)
    assert dcta.pitch_y_mm == pytest.approx(1.05, abs=1e-12)
    # the flank rises monotonically root -> tip and narrows
    p = dcta.point(dcta.sample(2000))
    assert np.all(np.diff(p[:, 1]) > 0) and np.all(np.diff(p[:, 0]) < 0)


@pytest.mark.parametrize("make", [dcta_tooth, involute_tooth])
def test_g1_continuity_and_unit_speed(make):
    tooth = make(**GEAR)
    for left, right in zip(tooth.segments[:-1], tooth.segments[1:]):
        tb = left.t1
        assert right.t0 == tb
        pl, dl, _ = left.evaluate(np.array([tb]))
        pr, dr, _ = right.evaluate(np.array([tb]))
        assert np.max(np.abs(pl - pr)) <= 1e-12
        assert abs(_angle(dr) - _angle(dl))[0] <= 1e-12
    _, dp, _ = tooth.evaluate(tooth.sample(5000))
    assert np.max(np.abs(np.hypot(dp[:, 0], dp[:, 1]) - 1.0)) <= 1e-12
    assert tooth.unit_speed_error <= 1e-12
    # the lengths add up: L = polyline length of a fine sampling (chord sag ~ 1e-10)
    p = tooth.point(tooth.sample(20000))
    assert np.sum(np.hypot(*np.diff(p, axis=0).T)) == pytest.approx(tooth.length_mm, abs=1e-8)


def test_dcta_curvature_signs(dcta):
    root, line, tip = dcta.segments
    np.testing.assert_allclose(dcta.curvature(_interior(tip)), 1 / 0.65, rtol=1e-13)  # convex
    np.testing.assert_allclose(dcta.curvature(_interior(root)), -1 / 0.70, rtol=1e-13)  # concave
    np.testing.assert_array_equal(dcta.curvature(_interior(line)), 0.0)
    # ddp = kappa * n, n = rot90(dp) (points into the tooth on the right flank)
    t = dcta.sample(500)
    _, dp, ddp = dcta.evaluate(t)
    k = dcta.curvature(t)
    n = np.stack([-dp[:, 1], dp[:, 0]], axis=1)
    np.testing.assert_allclose(ddp, k[:, None] * n, atol=1e-12)
    # a mirrored (left) flank has the mirrored derivatives and opposite dp x ddp sign
    pl, dpl, ddpl = dcta.evaluate(t, side=-1)
    p, _, _ = dcta.evaluate(t)
    np.testing.assert_array_equal(pl, p * [-1, 1])
    np.testing.assert_array_equal(dpl, dp * [-1, 1])
    np.testing.assert_array_equal(ddpl, ddp * [-1, 1])
    np.testing.assert_allclose(dcta.curvature(t, side=-1), -k, atol=1e-12)


@pytest.mark.parametrize("make", [dcta_tooth, involute_tooth])
def test_derivatives_by_complex_step(make):
    """dp = d p/dt and ddp = d dp/dt to round-off, per segment, by complex step."""
    tooth = make(**GEAR)
    h = 1e-30
    for seg in tooth.segments:
        t = _interior(seg, 51)
        p, dp, ddp = seg.evaluate(t)
        pc, dpc, _ = seg.evaluate(t + 1j * h)
        np.testing.assert_allclose(pc.real, p, atol=2e-14, rtol=0)  # |c + r_b e| ~ 49 mm
        np.testing.assert_allclose(pc.imag / h, dp, atol=2e-15, rtol=0)
        np.testing.assert_allclose(dpc.imag / h, ddp, atol=1e-13, rtol=0)


@pytest.mark.parametrize("make", [dcta_tooth, involute_tooth])
def test_derivatives_by_finite_differences(make):
    """Same check on the public, vectorised ToothProfile.evaluate (4th-order central FD)."""
    tooth = make(**GEAR)
    h = 1e-3
    for seg in tooth.segments:
        t = _interior(seg, 21)
        t = t[(t - 2 * h > seg.t0) & (t + 2 * h < seg.t1)]
        if t.size == 0:
            continue
        pts = [tooth.point(t + k * h) for k in (-2, -1, 0, 1, 2)]
        d1 = (pts[0] - 8 * pts[1] + 8 * pts[3] - pts[4]) / (12 * h)
        d2 = (-pts[0] + 16 * pts[1] - 30 * pts[2] + 16 * pts[3] - pts[4]) / (12 * h * h)
        _, dp, ddp = tooth.evaluate(t)
        assert np.max(np.abs(d1 - dp)) < 1e-10
        assert np.max(np.abs(d2 - ddp)) < 1e-6


def test_evaluate_shapes_and_range(dcta):
    p, dp, ddp = dcta.evaluate(0.3)
    assert p.shape == dp.shape == ddp.shape == (2,)
    p, dp, ddp = dcta.evaluate(np.zeros((3, 4)))
    assert p.shape == (3, 4, 2)
    # a shuffled t gives the same values as a sorted one (grouping by segment)
    t = dcta.sample(300)
    perm = np.random.default_rng(0).permutation(t.size)
    np.testing.assert_array_equal(dcta.point(t[perm]), dcta.point(t)[perm])
    np.testing.assert_array_equal(dcta.breakpoints[[0, -1]], [0.0, dcta.length_mm])
    with pytest.raises(ValueError, match="t must be in"):
        dcta.evaluate(dcta.length_mm + 1e-3)
    with pytest.raises(ValueError, match="t must be in"):
        dcta.evaluate(np.array([0.1, np.nan]))
    with pytest.raises(ValueError, match="side"):
        dcta.evaluate(0.1, side=0)


def test_results_are_frozen_and_json_safe(dcta):
    with pytest.raises(dataclasses.FrozenInstanceError):
        dcta.kind = "x"
    with pytest.raises(ValueError):
        dcta.breakpoints[0] = 1.0
    with pytest.raises(ValueError):
        dcta.segments[0].centre[0] = 1.0
    d = json.loads(json.dumps(dcta.to_dict()))
    assert d["kind"] == "dcta"
    assert [s["type"] for s in d["segments"]] == ["arc", "line", "arc"]
    assert d["segments"][2]["radius"] == 0.65
    assert d["fit_error_mm"] == 0.0


# --------------------------------------------------------------------------- involute


def _inv(a):
    return np.tan(a) - a


def test_involute_relation_holds_everywhere(involute):
    r_b = R1 * math.cos(math.radians(20))
    p = involute.point(involute.sample(3000))
    q = p - [0.0, -RM]
    r = np.hypot(*q.T)
    psi = np.arctan2(q[:, 0], q[:, 1])  # polar angle from the tooth axis, toward +x
    const = psi + _inv(np.arccos(r_b / r))
    assert np.ptp(const) < 1e-14
    # with the constant fixed by the half thickness pi m / 4 on the pitch circle
    assert const[0] == pytest.approx(math.pi * M / 4 / R1 + _inv(math.radians(20)), abs=1e-15)
    # radius of curvature of an involute: sqrt(r^2 - r_b^2), convex
    t = involute.sample(300)
    rr = np.hypot(*(involute.point(t) - [0.0, -RM]).T)
    np.testing.assert_allclose(involute.curvature(t), 1 / np.sqrt(rr**2 - r_b**2), rtol=1e-11)
    # ends on the default addendum m and dedendum 1.25 m lines
    assert involute.tip_point[1] == pytest.approx(YP + M, abs=1e-12)
    assert involute.root_point[1] == pytest.approx(YP - 1.25 * M, abs=1e-12)


@pytest.mark.parametrize("alpha_deg, half", [(20.0, None), (25.0, 0.37)])
def test_involute_pressure_angle_and_thickness_at_pitch_circle(alpha_deg, half):
    tooth = involute_tooth(**GEAR, pressure_angle_deg=alpha_deg, half_thickness_mm=half)
    c = np.array([0.0, -RM])
    t_p = brentq(lambda t: np.hypot(*(tooth.point(t) - c)) - R1, 0.0, tooth.length_mm, xtol=1e-15)
    p, dp, _ = tooth.evaluate(t_p)
    radial = (p - c) / np.hypot(*(p - c))
    angle = math.acos(abs(float(np.dot(dp, radial))))
    assert math.degrees(angle) == pytest.approx(alpha_deg, abs=1e-9)
    half_arc = R1 * math.atan2(p[0], p[1] + RM)
    assert half_arc == pytest.approx(math.pi * M / 4 if half is None else half, abs=1e-9)


def test_involute_segment_arc_length_closed_form():
    """s = r_b theta^2 / 2: the unrolled string length r_b theta equals the curvature radius."""
    tooth = involute_tooth(**GEAR)
    (seg,) = tooth.segments
    assert isinstance(seg, InvoluteSegment)
    t = _interior(seg, 20)
    theta = seg.roll_angle(t)
    np.testing.assert_allclose(seg.s0 + (t - seg.t0), seg.base_radius * theta**2 / 2, rtol=1e-14)
    np.testing.assert_allclose(1 / tooth.curvature(t), seg.base_radius * theta, rtol=1e-12)


# --------------------------------------------------------------------------- points


@pytest.fixture(scope="module")
def dcta_line(dcta):
    """The true DCTA flank as a very fine polyline (chord sag < 1e-9 mm)."""
    return LineString(dcta.point(dcta.sample(20000)))


def _deviation(tooth, reference: LineString, n_per_mm=2000) -> np.ndarray:
    """The distances of the tooth's points to the reference polyline: the least distance to its
    segments, from an STR tree of them (shapely.distance to the LineString tried each of its
    ~30 000 segments for each of the ~3000 points: 1-4 s a call; the same numbers)."""
    xy = shapely.get_coordinates(reference)
    tree = shapely.STRtree(shapely.linestrings(np.stack([xy[:-1], xy[1:]], axis=1)))
    _, dist = tree.query_nearest(shapely.points(tooth.point(tooth.sample(n_per_mm))), return_distance=True,
                                 all_matches=False)
    return dist


@pytest.mark.parametrize("smoothing, fit_tol, dev_tol", [(0.0, 1e-12, 2e-5), (1e-5, 1e-4, 1e-4)])
def test_points_recover_the_dcta(dcta, dcta_line, smoothing, fit_tol, dev_tol):
    pts = dcta.point(np.linspace(0.0, dcta.length_mm, 80))
    tooth = points_tooth(pts, **GEAR, smoothing_mm=smoothing)
    assert tooth.kind == "points"
    assert isinstance(tooth.segments[0], SplineSegment)
    assert tooth.fit_error_mm <= fit_tol
    assert tooth.fit_rms_mm <= tooth.fit_error_mm
    assert np.max(_deviation(tooth, dcta_line)) <= dev_tol
    # t is arc length: |p'| = 1 up to the reparametrisation error, reported
    _, dp, _ = tooth.evaluate(tooth.sample(3000))
    speed = np.abs(np.hypot(dp[:, 0], dp[:, 1]) - 1.0)
    assert np.max(speed) <= 1e-9
    assert tooth.unit_speed_error <= 1e-9
    assert tooth.length_mm == pytest.approx(dcta.length_mm, abs=10 * dev_tol)
    np.testing.assert_allclose(tooth.root_point, pts[0], atol=fit_tol + 1e-12)
    np.testing.assert_allclose(tooth.tip_point, pts[-1], atol=fit_tol + 1e-12)


def test_points_interpolation_converges_with_point_count(dcta, dcta_line):
    """Deviation from the true flank falls with point spacing h (curvature jumps at
    the joins limit the rate to about h^2)."""
    devs = []
    for n in (40, 80, 160):
        pts = dcta.point(np.linspace(0.0, dcta.length_mm, n))
        devs.append(np.max(_deviation(points_tooth(pts, **GEAR, smoothing_mm=0.0), dcta_line)))
    rates = np.log2(np.array(devs[:-1]) / np.array(devs[1:]))
    assert np.all(rates > 1.5), (devs, rates)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_points_noisy_fit_is_noise_sized_and_smooth(dcta, dcta_line, seed):
    sigma = 0.010  # 10 µm per coordinate
    pts = dcta.point(np.linspace(0.0, dcta.length_mm, 60))
    noisy = pts + np.random.default_rng(seed).normal(0.0, sigma, pts.shape)
    tooth = points_tooth(noisy, **GEAR, smoothing_mm=1.2 * sigma)
    assert 0.7 * sigma < tooth.fit_rms_mm < 1.3 * sigma
    assert sigma < tooth.fit_error_mm < 5 * sigma
    # smooth: averages the noise away from the ends, curvature stays near the true 1.5/mm
    dev = _deviation(tooth, dcta_line)
    s = tooth.sample(2000)
    inner = (s > 0.1) & (s < tooth.length_mm - 0.1)
    assert np.max(dev[inner]) < sigma
    assert np.max(dev) < 4 * sigma
    k = tooth.curvature(tooth.sample(1000))
    assert np.max(np.abs(k)) < 5.0
    assert np.count_nonzero(np.diff(np.sign(k))) <= 3
    assert tooth.unit_speed_error <= 1e-9


# --------------------------------------------------------------------------- outline


@pytest.mark.parametrize("kind", ["dcta", "involute", "points"])
def test_outline_is_valid_symmetric_polygon(dcta, kind):
    if kind == "dcta":
        tooth = dcta
    elif kind == "involute":
        tooth = involute_tooth(**GEAR)
    else:
        tooth = points_tooth(dcta.point(np.linspace(0, dcta.length_mm, 50)), **GEAR, smoothing_mm=0)
    o = tooth.outline()
    poly = Polygon(o)
    assert poly.is_valid
    assert poly.exterior.is_ccw
    assert not np.array_equal(o[0], o[-1])
    mirror = Polygon(o * [-1.0, 1.0])
    assert poly.symmetric_difference(mirror).area < 1e-12
    # sector bounds: the mid-space lines at +-pi/z1 and the neutral circle r_m
    q = o - [0.0, -RM]
    psi = np.arctan2(q[:, 0], q[:, 1])
    assert np.max(np.abs(psi)) == pytest.approx(math.pi / Z1, abs=1e-15)
    assert np.min(np.hypot(*q.T)) == pytest.approx(RM, abs=1e-12)
    # the whole flank is in the outline, the tip land is the straight chord at y_a
    ring = poly.exterior
    flank = tooth.point(tooth.sample(300))  # not at the vertices: chord sag h^2 k / 8 ~ 5e-8
    assert np.max(shapely.distance(shapely.points(flank), ring)) < 1e-7
    assert np.max(shapely.distance(shapely.points(flank * [-1, 1]), ring)) < 1e-7
    top = o[np.isclose(o[:, 1], tooth.addendum_y_mm, atol=1e-12)]
    assert len(top) == 2 and top[0, 0] == -top[1, 0]


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "kwargs, fields",
    [
        (dict(tip_arc_radius_mm=0.30), ["tooth.tip_arc_radius_mm", "tooth.addendum_mm"]),
        (dict(addendum_mm=0.80), ["tooth.tip_arc_radius_mm", "tooth.addendum_mm"]),
        (dict(root_arc_radius_mm=0.40), ["tooth.root_arc_radius_mm", "tooth.dedendum_mm"]),
        (dict(half_thickness_mm=0.10), ["tooth.half_thickness_mm", "tooth.pressure_angle_deg"]),
        (dict(half_thickness_mm=0.55), ["tooth.half_thickness_mm"]),
        (dict(dedendum_mm=1.10), ["tooth.dedendum_mm"]),
        (dict(line_above_pitch_mm=0.5), ["tooth.line_above_pitch_mm"]),
        (dict(line_below_pitch_mm=0.7), ["tooth.line_below_pitch_mm"]),
        (dict(tip_arc_radius_mm=-0.65), ["tooth.tip_arc_radius_mm"]),
        (dict(pressure_angle_deg=float("nan")), ["tooth.pressure_angle_deg"]),
    ],
)
def test_dcta_bad_geometry_names_the_field(kwargs, fields):
    with pytest.raises(ToothError) as err:
        dcta_tooth(**GEAR, **kwargs)
    msg = str(err.value)
    for f in fields:
        assert f in msg, msg
    assert isinstance(err.value, ValueError)


def test_dcta_half_thickness_too_wide_overlaps_the_neighbour():
    # independent bound: the root point x must stay below (r_m + y_f) sin(pi/z1)
    with pytest.raises(ToothError, match="neighbour") as err:
        dcta_tooth(**GEAR, half_thickness_mm=0.55)
    assert f"{(RM + YP - 0.6) * math.sin(math.pi / Z1):.6g}" in str(err.value)


def test_involute_bad_geometry_names_the_field():
    small = dict(module_mm=1.0, teeth=20, neutral_radius_mm=8.0)  # r1 10, r_b 9.397
    with pytest.raises(ToothError, match="tooth.dedendum_mm") as err:
        involute_tooth(**small)  # root radius 8.75 < base radius
    assert "base circle" in str(err.value)
    ok = involute_tooth(**small, dedendum_mm=0.3)
    assert ok.root_point[1] == pytest.approx(1.7, abs=1e-12)
    # pointed: for z = 20, alpha 20, s = pi m / 2 the flanks meet at r = 11.54 mm
    with pytest.raises(ToothError, match="tooth.addendum_mm") as err:
        involute_tooth(**small, dedendum_mm=0.3, addendum_mm=1.8)
    assert "pointed" in str(err.value)
    involute_tooth(**small, dedendum_mm=0.3, addendum_mm=1.45)  # just below pointed: fine
    with pytest.raises(ToothError, match="tooth.dedendum_mm"):
        involute_tooth(**GEAR, dedendum_mm=1.2)  # y_f below the neutral line


def test_gear_fields_are_validated():
    with pytest.raises(GearSetError, match="gear.module_mm"):
        dcta_tooth(module_mm=-0.5, teeth=200, neutral_radius_mm=48.95)
    with pytest.raises(GearSetError, match="gear.flexspline_teeth"):
        dcta_tooth(module_mm=0.5, teeth=200.5, neutral_radius_mm=48.95)
    with pytest.raises(GearSetError, match="gear.neutral_radius_mm"):
        involute_tooth(module_mm=0.5, teeth=200, neutral_radius_mm=51.0)
    with pytest.raises(TypeError):
        dcta_tooth(**GEAR, tip_radius_mm=0.65)  # misspelt option


def test_points_bad_input_names_the_field(dcta):
    pts = dcta.point(np.linspace(0.0, dcta.length_mm, 30))
    with pytest.raises(ToothError, match="tooth.points"):
        points_tooth(pts[:5], **GEAR)
    with pytest.raises(ToothError, match="tooth.points"):
        points_tooth(pts[::-1], **GEAR)  # tip -> root
    bad = pts.copy()
    bad[10] = np.nan
    with pytest.raises(ToothError, match="tooth.points"):
        points_tooth(bad, **GEAR)
    loop = pts.copy()
    loop[[22, 24]] = loop[[24, 22]]  # out of order: the polyline crosses itself
    with pytest.raises(ToothError, match="tooth.points.*crosses itself"):
        points_tooth(loop, **GEAR, smoothing_mm=0.0)
    shifted = pts * [1.0, 1.0] + [-0.5, 0.0]  # flank across the tooth axis
    with pytest.raises(ToothError, match="tooth.points"):
        points_tooth(shifted, **GEAR, smoothing_mm=0.0)
    with pytest.raises(ToothError, match="tooth.smoothing_mm"):
        points_tooth(pts, **GEAR, smoothing_mm=-1e-3)


# --------------------------------------------------------------------------- points: bounded cost


def _noisy(dcta, n, sigma, seed=0):
    pts = dcta.point(np.linspace(0.0, dcta.length_mm, n))
    return pts + np.random.default_rng(seed).normal(0.0, sigma, pts.shape)


def test_a_flank_rising_root_to_tip_is_no_longer_than_its_extent(dcta, involute):
    """The bound behind MAX_LENGTH_PER_EXTENT: a curve along which x falls and y rises is at
    most as long as x range + y range (|dx| + |dy| >= |ds|); real flanks sit well inside it."""
    for tooth in (dcta, involute):
        p = tooth.point(tooth.sample(2000))
        assert np.all(np.diff(p[:, 1]) > 0) and np.all(np.diff(p[:, 0]) < 0)
        extent = np.ptp(p[:, 0]) + np.ptp(p[:, 1])
        assert tooth.length_mm <= extent
        assert tooth.length_mm * teeth_mod.MAX_LENGTH_PER_EXTENT > 3 * extent


@pytest.mark.parametrize("n, sigma, smoothing, against", [
    (200, 0.05, 5e-4, "point polygon"),  # noise 100x the point spacing, smoothing 100x below it
    (400, 0.2, 5e-4, "points' extent"),  # the smoothed curve follows a 140 mm zig-zag
    (400, 0.2, 0.05, "points' extent"),
])
def test_points_that_loop_or_zigzag_are_refused_by_their_length(dcta, n, sigma, smoothing, against):
    """Inputs like these once sized the arc-length grid by a smoothed curve thousands of mm
    long (23 GB and more); now the length is measured on the knot spans first and refused."""
    pts = _noisy(dcta, n, sigma)
    pts[:, 0] = np.clip(pts[:, 0], 1e-3, None)
    with pytest.raises(ToothError, match=r"tooth\.points: the smoothed flank's arc length") as err:
        points_tooth(pts, **GEAR, smoothing_mm=smoothing)
    assert against in str(err.value) and "x the" in str(err.value)


def test_points_bound_errors_name_the_points_file(dcta):
    pts = _noisy(dcta, 200, 0.05) - [0.0, YP]
    gs = _gearset(kind="points", points=pts, points_file="flank.csv", smoothing_mm=5e-4)
    with pytest.raises(ToothError, match=r'tooth\.points_file = "flank\.csv": the smoothed flank'):
        tooth_from_gearset(gs)
    many = np.repeat(dcta.point(np.linspace(0.0, dcta.length_mm, 30)), 400, axis=0) - [0.0, YP]
    gs = _gearset(kind="points", points=many, points_file="dense.csv", smoothing_mm=5e-4)
    with pytest.raises(ToothError, match=rf'tooth\.points_file = "dense\.csv" .*n <= {teeth_mod.MAX_POINTS}'):
        tooth_from_gearset(gs)


def _first_crossing_pairwise(pts):
    """Reference: every pair of non-adjacent segments, by exact orientation tests."""
    def orient(p, q, r):
        return np.sign((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]))

    n = len(pts) - 1
    for i in range(n):
        for j in range(i + 2, n):
            p1, q1, p2, q2 = pts[i], pts[i + 1], pts[j], pts[j + 1]
            if (orient(p1, q1, p2) * orient(p1, q1, q2) <= 0 and orient(p2, q2, p1) * orient(p2, q2, q1) <= 0
                    and np.all(np.minimum(p1, q1) <= np.maximum(p2, q2))
                    and np.all(np.maximum(p1, q1) >= np.minimum(p2, q2))):
                return i, j
    return None


@pytest.mark.parametrize("seed", range(6))
def test_first_crossing_is_the_pairwise_answer(seed):
    rng = np.random.default_rng(seed)
    walk = np.cumsum(rng.normal(0.0, 1.0, (40, 2)) + [0.0, 0.3 * seed], axis=0)
    assert teeth_mod._first_crossing(walk) == _first_crossing_pairwise(walk)


def test_first_crossing_finds_the_first_of_many_in_a_long_polyline():
    """A 100 000-segment spiral (no crossing) with one late loop: found without n² work."""
    s = np.linspace(0.0, 1.0, 100_001)
    pts = np.column_stack([s, 0.1 * np.sin(40 * s)])
    assert teeth_mod._first_crossing(pts) is None
    pts[70_000:70_010] = pts[70_000:70_010][::-1]  # ten points reversed: segments cross
    i, j = teeth_mod._first_crossing(pts)
    assert 69_990 < i < j < 70_020
    assert _first_crossing_pairwise(pts[69_990:70_020]) == (i - 69_990, j - 69_990)


def test_points_tooth_on_a_large_gear_has_a_bounded_grid():
    """z1 = 600, m = 2 mm: a 4.5 mm flank at a 0.2 µm step (22 500 samples, under MAX_GRID)
    recovers the DCTA it was sampled from."""
    big = dict(module_mm=2.0, teeth=600, neutral_radius_mm=600.0 - 2.4 - 1.8)
    ref = dcta_tooth(**big, line_above_pitch_mm=0.2, line_below_pitch_mm=0.8, tip_arc_radius_mm=2.6,
                     root_arc_radius_mm=2.8, addendum_mm=1.6, dedendum_mm=2.4)
    tooth = points_tooth(ref.point(np.linspace(0.0, ref.length_mm, 60)), **big, smoothing_mm=0.0)
    seg = tooth.segments[0]
    assert seg.coefficients.shape[0] <= teeth_mod.MAX_GRID
    assert tooth.length_mm == pytest.approx(ref.length_mm, rel=1e-4)
    assert tooth.unit_speed_error < 1e-9


_RUNAWAY = """
import resource, sys
import numpy as np
resource.setrlimit(resource.RLIMIT_AS, (1_500_000_000, 1_500_000_000))
from profilegen.errors import ToothError
from profilegen.geometry.teeth import dcta_tooth, points_tooth
gear = dict(module_mm=0.5, teeth=200, neutral_radius_mm=48.95)
ref = dcta_tooth(**gear)
for n, sigma, smoothing in [(200, 0.05, 5e-4), (400, 0.2, 5e-4), (40, 0.05, 5e-4), (40, 0.1, 2e-3)]:
    pts = ref.point(np.linspace(0.0, ref.length_mm, n))
    pts = pts + np.random.default_rng(1).normal(0.0, sigma, pts.shape)
    pts[:, 0] = np.clip(pts[:, 0], 1e-3, None)
    try:
        points_tooth(pts, **gear, smoothing_mm=smoothing)
        print("ok")
    except ToothError as exc:
        print("ToothError", str(exc).split(":")[0])
"""


@pytest.mark.slow
def test_runaway_point_lists_end_in_named_errors_under_a_memory_cap():
    """The issue's runaways (a smoothed curve that loops or follows noise) in a process
    capped at 1.5 GB of address space: each ends in a ToothError naming tooth.points (or
    builds), none in a MemoryError or a kill."""
    import subprocess
    import sys

    run = subprocess.run([sys.executable, "-c", _RUNAWAY], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    lines = run.stdout.split("\n")[:-1]
    assert len(lines) == 4 and all(line in ("ok", "ToothError tooth.points") for line in lines), lines
    assert lines.count("ToothError tooth.points") >= 3


# --------------------------------------------------------------------------- dispatch


def _gearset(**tooth):
    gear = types.SimpleNamespace(module_mm=0.5, flexspline_teeth=200, neutral_radius_mm=48.95)
    return types.SimpleNamespace(gear=gear, tooth=types.SimpleNamespace(**tooth))


def test_tooth_from_gearset_dispatches_on_kind(dcta):
    gs = _gearset(kind="dcta", pressure_angle_deg=10.0, line_above_pitch_mm=0.05,
                  line_below_pitch_mm=0.20, tip_arc_radius_mm=0.65, root_arc_radius_mm=0.70,
                  addendum_mm=0.40, dedendum_mm=0.60, half_thickness_mm=None)
    t = tooth_from_gearset(gs)
    assert t.kind == "dcta"
    np.testing.assert_array_equal(t.tip_point, dcta.tip_point)
    t = tooth_from_gearset(_gearset(kind="dcta", tip_arc_radius_mm=0.8))
    assert t.segments[2].radius == 0.8
    t = tooth_from_gearset(_gearset(kind="involute", pressure_angle_deg=25.0, addendum_mm=None,
                                    dedendum_mm=0.5, half_thickness_mm=None))
    assert t.kind == "involute" and t.root_point[1] == pytest.approx(YP - 0.5, abs=1e-12)
    pts = dcta.point(np.linspace(0.0, dcta.length_mm, 40))
    pitch_frame = pts - [0.0, YP]  # gearset points: origin at the pitch point
    t = tooth_from_gearset(_gearset(kind="points", points=pitch_frame, smoothing_mm=0.0))
    assert t.kind == "points" and t.fit_error_mm < 1e-12
    np.testing.assert_allclose(t.root_point, pts[0], atol=1e-12)
    np.testing.assert_allclose(t.tip_point, pts[-1], atol=1e-12)
    with pytest.raises(ToothError, match="tooth.kind"):
        tooth_from_gearset(_gearset(kind="cycloid"))
    with pytest.raises(ToothError, match="tooth.tip_arc_radius_mm"):
        tooth_from_gearset(_gearset(kind="dcta", tip_arc_radius_mm=0.3))
    with pytest.raises(ToothError, match="tooth.points"):
        tooth_from_gearset(_gearset(kind="points"))
