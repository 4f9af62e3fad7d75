"""Wave-generator contours: exact distances, normals, the bearing offset, the perimeter rule."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from profilegen.geometry import wavegen
from profilegen.errors import ConvergenceError
from profilegen.gearset import default_gearset_path, load_gearset
from profilegen.geometry.wavegen import (
    CosineCam,
    EllipticalCam,
    RollerGenerator,
    WaveGenError,
    from_gearset,
)


@pytest.fixture(scope="module")
def gearset():
    return load_gearset(default_gearset_path())


def _ellipse(a, b, tau):
    """Point, unit tangent and outward unit normal of the ellipse u = a cos τ, v = b sin τ in
    the frame (x = v, y = u: the major axis is +y)."""
    p = np.column_stack([b * np.sin(tau), a * np.cos(tau)])
    t = np.column_stack([b * np.cos(tau), -a * np.sin(tau)])
    t /= np.linalg.norm(t, axis=1)[:, None]
    n = np.column_stack([a * np.sin(tau), b * np.cos(tau)])
    n /= np.linalg.norm(n, axis=1)[:, None]
    return p, t, n


TAU = np.linspace(-math.pi, math.pi, 73)  # includes both axes (multiples of 5°)


@pytest.mark.parametrize("d", [0.0, 1e-6, 2.5, 40.0, -1e-6, -2.0, -20.0])
def test_ellipse_signed_distance_of_known_points(d):
    a, b = 52.0, 48.0  # minimum radius of curvature b²/a = 44.3 mm > 20 mm: the foot is unique
    p, _, n = _ellipse(a, b, TAU)
    foot, normal, dist = EllipticalCam(a, b).closest(p + d * n)
    assert np.max(np.abs(dist - d)) < 1e-12
    assert np.max(np.abs(foot - p)) < 1e-12
    assert np.max(np.abs(normal - n)) < 1e-12


def test_ellipse_special_points():
    cam = EllipticalCam(52.0, 48.0)
    pts = np.array([[0.0, 0.0], [0.0, 5.0], [0.0, 60.0], [50.0, 0.0], [-48.0, 0.0], [0.0, -52.0]])
    _, normal, dist = cam.closest(pts)
    # the centre and interior points on the major axis near it: the foot is on the minor axis
    c2 = 52.0**2 - 48.0**2
    u = 52.0**2 * 5.0 / c2  # a·5 < a² − b²: the foot leaves the axis
    assert dist[0] == pytest.approx(-48.0, abs=1e-12)
    assert dist[1] == pytest.approx(-math.hypot(48.0 * math.sqrt(1 - (u / 52.0) ** 2), u - 5.0), abs=1e-12)
    assert dist[2] == pytest.approx(8.0, abs=1e-12)
    assert dist[3] == pytest.approx(2.0, abs=1e-12)
    assert dist[4] == pytest.approx(0.0, abs=1e-12)
    assert dist[5] == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(normal[[2, 3, 4, 5]], [[0, 1], [1, 0], [-1, 0], [0, -1]], atol=1e-15)


def test_normals_are_orthogonal_to_the_tangent_and_the_foot_is_on_the_ellipse():
    a, b = 49.0, 47.5
    cam = EllipticalCam(a, b)
    rng = np.random.default_rng(1)
    pts = rng.uniform(-80.0, 80.0, size=(500, 2))
    foot, normal, dist = cam.closest(pts)
    tau = np.arctan2(foot[:, 0] / b, foot[:, 1] / a)
    _, tangent, _ = _ellipse(a, b, tau)
    assert np.max(np.abs(np.einsum("ij,ij->i", normal, tangent))) < 1e-13
    assert np.max(np.abs((foot[:, 1] / a) ** 2 + (foot[:, 0] / b) ** 2 - 1.0)) < 1e-14
    # p − foot is along the normal: the foot is a stationary point of the distance
    resid = pts - foot - dist[:, None] * normal
    assert np.max(np.abs(resid)) < 1e-12
    # and the global minimum: no ellipse point is closer
    q, _, _ = _ellipse(a, b, np.linspace(-math.pi, math.pi, 20001))
    brute = np.min(np.linalg.norm(pts[:, None, :] - q[None, :, :], axis=2), axis=1)
    assert np.all(np.abs(dist) <= brute + 1e-12)
    assert np.max(brute - np.abs(dist)) < 1e-3  # the brute-force grid spacing is ~0.015 mm


def test_offset_contour_is_exactly_the_bearing_thickness_from_the_ellipse():
    cam = EllipticalCam(50.0, 46.0, bearing_thickness_mm=3.2)
    q, n = cam.point(TAU)
    _, normal, dist = cam.ellipse_closest(q)
    assert np.max(np.abs(dist - 3.2)) < 1e-12
    assert np.max(np.abs(normal - n)) < 1e-13
    # points of the offset curve are at distance 0 from the contour, and off by d along n
    for d in (0.0, 0.7, -1.5):
        assert np.max(np.abs(cam.closest(q + d * n)[2] - d)) < 1e-12
    # an offset ellipse is not an ellipse: its radius on the diagonal differs from the
    # ellipse with semi-axes a + h, b + h
    theta = np.array([math.pi / 4])
    a, b = 53.2, 49.2
    r_ellipse = a * b / math.sqrt((b * math.cos(theta[0])) ** 2 + (a * math.sin(theta[0])) ** 2)
    assert abs(cam.radius(theta)[0] - r_ellipse) > 1e-3


def test_radius_of_the_plain_ellipse_and_of_the_offset():
    a, b = 52.0, 48.0
    theta = np.linspace(-2 * math.pi, 2 * math.pi, 97)
    exact = a * b / np.sqrt((b * np.cos(theta)) ** 2 + (a * np.sin(theta)) ** 2)
    np.testing.assert_allclose(EllipticalCam(a, b).radius(theta), exact, rtol=0, atol=1e-12)
    cam = EllipticalCam(a, b, bearing_thickness_mm=2.0)
    r = cam.radius(theta)
    pts = np.column_stack([r * np.sin(theta), r * np.cos(theta)])
    assert np.max(np.abs(cam.closest(pts)[2])) < 1e-12
    assert r[np.argmin(np.abs(theta))] == pytest.approx(54.0, abs=1e-12)


def test_from_gearset_inextensible_bore(gearset):
    """Major radius r_bore + w0; perimeter 2π r_bore, checked by quadrature of |dQ/dτ|."""
    r_bore = gearset.gear.neutral_radius_mm - 0.5 * gearset.gear.rim_thickness_mm
    w0 = gearset.deflection_mm
    for h in (0.0, 2.0):
        gs = gearset.with_values({"wave_generator.bearing_thickness_mm": h}) if h else gearset
        cam = from_gearset(gs)
        assert isinstance(cam, EllipticalCam)
        assert cam.bearing_thickness_mm == h
        assert cam.radius(0.0)[0] == pytest.approx(r_bore + w0, abs=1e-12)
        a, b = cam.semi_major_mm, cam.semi_minor_mm

        def speed(tau, a=a, b=b, h=h):  # |d/dτ (E(τ) + h n(τ))| = (1 + h κ) |E′|
            ds = math.hypot(a * math.sin(tau), b * math.cos(tau))
            kappa = a * b / ds**3
            return (1.0 + h * kappa) * ds

        length = 4.0 * quad(speed, 0.0, math.pi / 2, epsabs=1e-12, epsrel=1e-13, limit=200)[0]
        assert length == pytest.approx(2 * math.pi * r_bore, abs=1e-9)
        assert cam.perimeter_mm == pytest.approx(2 * math.pi * r_bore, abs=1e-9)


def test_from_gearset_cosine_and_rollers(gearset):
    cam = from_gearset(gearset.with_values({"wave_generator.contour": "cosine_cam"}))
    r_bore = gearset.gear.neutral_radius_mm - 0.5 * gearset.gear.rim_thickness_mm
    assert isinstance(cam, CosineCam)
    assert cam.radius(0.0)[0] == pytest.approx(r_bore + gearset.deflection_mm, abs=1e-12)
    rollers = gearset.with_values({"wave_generator.contour": "rollers", "wave_generator.roller_count": 2,
                                   "wave_generator.roller_radius_mm": 10.0})
    contour = from_gearset(rollers)  # implemented now: see the roller tests below
    assert isinstance(contour, RollerGenerator)
    assert contour.radius(0.0)[0] == pytest.approx(r_bore + gearset.deflection_mm, abs=1e-12)


@pytest.mark.parametrize("d", [0.0, 0.3, -0.3, 5.0])
def test_cosine_cam_distance_along_the_normal(d):
    cam = CosineCam(48.5, 0.5)
    theta = np.linspace(-math.pi, math.pi, 91)
    r = cam.radius(theta)
    p = np.column_stack([r * np.sin(theta), r * np.cos(theta)])
    # tangent dc/dθ = r′ e_r + r e_θ; outward normal ∝ r e_r − r′ e_θ
    r1 = -2 * 0.5 * np.sin(2 * theta)
    er = np.column_stack([np.sin(theta), np.cos(theta)])
    et = np.column_stack([np.cos(theta), -np.sin(theta)])
    n = r[:, None] * er - r1[:, None] * et
    n /= np.linalg.norm(n, axis=1)[:, None]
    tangent = r1[:, None] * er + r[:, None] * et
    foot, normal, dist = cam.closest(p + d * n)
    assert np.max(np.abs(dist - d)) < 1e-12
    assert np.max(np.abs(foot - p)) < 1e-11
    assert np.max(np.abs(np.einsum("ij,ij->i", normal, tangent))) < 1e-12


@pytest.mark.parametrize(
    "make, field",
    [
        (lambda: EllipticalCam(0.0, 1.0), "semi_major_mm"),
        (lambda: EllipticalCam(40.0, 41.0), "semi_minor_mm"),
        (lambda: EllipticalCam(41.0, 40.0, bearing_thickness_mm=-1.0), "bearing_thickness_mm"),
        (lambda: EllipticalCam(41.0, float("nan")), "semi_minor_mm"),
        (lambda: CosineCam(-1.0, 0.1), "mean_radius_mm"),
        (lambda: CosineCam(50.0, 20.0), "deflection_mm"),
        (lambda: CosineCam(50.0, 0.1, waves=0), "waves"),
        (lambda: EllipticalCam(41.0, 40.0).closest(np.zeros((3, 3))), "points"),
    ],
)
def test_bad_input_names_the_field(make, field):
    with pytest.raises(WaveGenError, match=field):
        make()
    assert issubclass(WaveGenError, ValueError)


def test_protocol_is_satisfied():
    for cam in (EllipticalCam(50.0, 48.0, 1.0), CosineCam(48.0, 0.5)):
        contour: wavegen.Contour = cam
        assert contour.radius([0.0]).shape == (1,)
        assert [a.shape for a in contour.closest([[1.0, 60.0]])] == [(1, 2), (1, 2), (1,)]
    assert issubclass(ConvergenceError, RuntimeError)


# --------------------------------------------------------------------------- rollers

ROLLER_SETS = [
    RollerGenerator(10.0, 39.0),  # two rollers on the major axis
    RollerGenerator(10.0, 38.75, roller_count=4, centre_angle_rad=math.radians(29.7)),
    RollerGenerator(6.0, 6.0),  # two rollers touching at the centre
    RollerGenerator(5.0, 10.0, roller_count=4, centre_angle_rad=math.asin(0.5)),  # pairs touching
]


def _circle_samples(rollers, n=5000):
    """Dense points on every roller circle (spacing 2πR/n)."""
    t = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    ring = rollers.roller_radius_mm * np.column_stack([np.cos(t), np.sin(t)])
    return np.concatenate([c + ring for c in rollers.centres])


@pytest.mark.parametrize("rollers", ROLLER_SETS)
def test_roller_closest_against_brute_force(rollers):
    """|distance| is the distance to the nearest circle point (brute force over dense samples
    of all circles); the sign says inside (< 0) or outside (> 0) the union of the discs."""
    rng = np.random.default_rng(7)
    pts = rng.uniform(-60.0, 60.0, size=(200, 2))
    foot, normal, dist = rollers.closest(pts)
    samples = _circle_samples(rollers)
    brute = np.min(np.linalg.norm(pts[:, None, :] - samples[None, :, :], axis=2), axis=1)
    spacing = 2 * math.pi * rollers.roller_radius_mm / 5000
    assert np.all(np.abs(dist) <= brute + 1e-12)
    assert np.max(brute - np.abs(dist)) < 0.5 * spacing  # the nearest sample is ≤ half a spacing away
    inside = np.any(np.linalg.norm(pts[:, None, :] - rollers.centres[None], axis=2) < rollers.roller_radius_mm, axis=1)
    assert np.array_equal(dist < 0.0, inside) and inside.any() and (~inside).any()
    # the foot is on a roller, p − foot is along the unit normal, distance = (p − foot)·n
    on_circle = np.min(np.abs(np.linalg.norm(foot[:, None, :] - rollers.centres[None], axis=2)
                              - rollers.roller_radius_mm), axis=1)
    assert np.max(on_circle) < 1e-12
    np.testing.assert_allclose(np.linalg.norm(normal, axis=1), 1.0, atol=1e-15)
    np.testing.assert_allclose(pts - foot, dist[:, None] * normal, atol=1e-12)


def test_roller_signs_and_special_points():
    rollers = RollerGenerator(10.0, 39.0)
    pts = [[0.0, 49.0], [0.0, 50.5], [0.0, 45.0], [0.0, 39.0], [0.0, -39.0], [20.0, 0.0], [0.0, 0.0]]
    foot, normal, dist = rollers.closest(pts)
    np.testing.assert_allclose(dist, [0.0, 1.5, -4.0, -10.0, -10.0, math.hypot(20.0, 39.0) - 10.0, 29.0],
                               atol=1e-12)
    # at a centre the normal is radially outward; at the origin (a tie) the first roller wins
    np.testing.assert_array_equal(normal[[0, 3, 4, 6]], [[0, 1], [0, 1], [0, -1], [0, -1]])
    np.testing.assert_allclose(foot[3], [0.0, 49.0], atol=1e-15)


@pytest.mark.parametrize("rollers", ROLLER_SETS)
def test_roller_contour_is_symmetric_about_both_axes(rollers):
    rng = np.random.default_rng(3)
    pts = rng.uniform(-55.0, 55.0, size=(300, 2))  # no point on an axis: no ties
    foot, normal, dist = rollers.closest(pts)
    for flip in ([-1.0, 1.0], [1.0, -1.0], [-1.0, -1.0]):
        f = np.array(flip)
        foot_m, normal_m, dist_m = rollers.closest(pts * f)
        np.testing.assert_allclose(dist_m, dist, atol=1e-12)
        np.testing.assert_allclose(foot_m, foot * f, atol=1e-12)
        np.testing.assert_allclose(normal_m, normal * f, atol=1e-12)
    theta = rng.uniform(-math.pi, math.pi, 200)
    r = rollers.radius(theta)
    for mirrored in (-theta, math.pi - theta, theta + math.pi):
        np.testing.assert_allclose(rollers.radius(mirrored), r, atol=1e-12)


@pytest.mark.parametrize("rollers", ROLLER_SETS)
def test_roller_radius_is_the_outermost_hit_and_zero_on_a_miss(rollers):
    theta = np.linspace(-math.pi, math.pi, 3601)
    r = rollers.radius(theta)
    assert r.shape == theta.shape and np.all(np.isfinite(r)) and np.all(r >= 0.0)
    ray = np.column_stack([np.sin(theta), np.cos(theta)])
    hit = r > 0.0
    assert hit.any()  # two rollers touching at the centre leave no gap (rollers2)
    # on the contour where hit; just beyond it, outside every roller (the outermost crossing)
    assert np.max(np.abs(rollers.closest(r[hit, None] * ray[hit])[2])) < 1e-11
    assert np.all(rollers.closest((r[hit, None] + 1e-6) * ray[hit])[2] > 0.0)
    # a miss: the whole ray (sampled) stays outside every roller
    t = np.linspace(0.0, 70.0, 701)
    misses = (t[None, :, None] * ray[~hit][:, None, :]).reshape(-1, 2)
    assert np.all(rollers.closest(misses)[2] > 0.0)
    # the rays through the centres reach d + R
    alpha = np.arctan2(rollers.centres[:, 0], rollers.centres[:, 1])
    np.testing.assert_allclose(rollers.radius(alpha), rollers.outer_radius_mm, atol=1e-12)


@pytest.mark.parametrize(
    "make, field",
    [
        (lambda: RollerGenerator(0.0, 39.0), "roller_radius_mm"),
        (lambda: RollerGenerator(float("nan"), 39.0), "roller_radius_mm"),
        (lambda: RollerGenerator(40.0, 39.0), "roller_radius_mm"),  # the two rollers overlap
        (lambda: RollerGenerator(10.0, 30.0, roller_count=4, centre_angle_rad=0.3), "roller_radius_mm"),
        (lambda: RollerGenerator(10.0, -39.0), "centre_distance_mm"),
        (lambda: RollerGenerator(10.0, 39.0, roller_count=3), "roller_count"),
        (lambda: RollerGenerator(10.0, 39.0, roller_count=True), "roller_count"),
        (lambda: RollerGenerator(10.0, 39.0, centre_angle_rad=0.5), "centre_angle_rad"),
        (lambda: RollerGenerator(10.0, 39.0, roller_count=4), "centre_angle_rad"),
        (lambda: RollerGenerator(10.0, 39.0, roller_count=4, centre_angle_rad=math.pi / 4), "centre_angle_rad"),
        (lambda: RollerGenerator(10.0, 39.0, roller_count=4, centre_angle_rad="x"), "centre_angle_rad"),
        (lambda: RollerGenerator(10.0, 39.0).closest(np.zeros((2, 3))), "points"),
        (lambda: RollerGenerator(10.0, 39.0).closest([[0.0, float("inf")]]), "points"),
    ],
)
def test_roller_bad_input_names_the_field(make, field):
    with pytest.raises(WaveGenError, match=field):
        make()


def _rollers(gearset, count, radius, angle=None):
    changes = {"wave_generator.contour": "rollers", "wave_generator.roller_count": count,
               "wave_generator.roller_radius_mm": radius}
    if angle is not None:
        changes["wave_generator.roller_angle_deg"] = angle
    return gearset.with_values(changes)


def test_from_gearset_two_rollers_push_the_bore_out_by_w0(gearset):
    g = gearset.gear
    r_bore, w0 = g.neutral_radius_mm - 0.5 * g.rim_thickness_mm, gearset.deflection_mm
    rollers = from_gearset(_rollers(gearset, 2, 10.0))
    assert rollers.roller_count == 2 and rollers.centre_angle_rad == 0.0
    assert rollers.centre_distance_mm == pytest.approx(r_bore + w0 - 10.0, abs=1e-12)
    assert rollers.outer_radius_mm == pytest.approx(r_bore + w0, abs=1e-12)
    np.testing.assert_array_equal(rollers.centres[:, 0], [0.0, 0.0])


@pytest.mark.parametrize("angle", [None, 10.0, 40.0])
def test_from_gearset_four_rollers_touch_the_ring_theory_bore(gearset, angle):
    """Each roller is tangent to r_bore + w0 cos 2θ at θ = ±θ_r (default 30°) and lies inside it."""
    g = gearset.gear
    r_bore, w0 = g.neutral_radius_mm - 0.5 * g.rim_thickness_mm, gearset.deflection_mm
    rollers = from_gearset(_rollers(gearset, 4, 5.0, angle))
    theta_r = math.radians(30.0 if angle is None else angle)
    for th in (theta_r, -theta_r, math.pi - theta_r, math.pi + theta_r):
        r, r1 = r_bore + w0 * math.cos(2 * th), -2 * w0 * math.sin(2 * th)
        e_r, e_t = np.array([math.sin(th), math.cos(th)]), np.array([math.cos(th), -math.sin(th)])
        n = (r * e_r - r1 * e_t) / math.hypot(r, r1)
        _, normal, dist = rollers.closest([r * e_r])
        assert abs(dist[0]) < 1e-12
        np.testing.assert_allclose(normal[0], n, atol=1e-12)
    theta = np.linspace(-math.pi, math.pi, 20001)
    assert np.all(rollers.radius(theta) <= r_bore + w0 * np.cos(2 * theta) + 1e-12)
    assert rollers.radius(0.0)[0] == 0.0  # the major axis is free between the pairs
    # the centres sit a little closer to the major axis than the touching points
    assert 0.0 < theta_r - rollers.centre_angle_rad < math.radians(1.0)


@pytest.mark.parametrize("count, radius, bound", [(2, 24.6, "24.5"), (4, 16.5, "16.0859")])
def test_from_gearset_overlapping_rollers_name_the_radius(gearset, count, radius, bound):
    with pytest.raises(WaveGenError, match=rf"wave_generator\.roller_radius_mm = {radius:g} mm: must be ≤ {bound}"):
        from_gearset(_rollers(gearset, count, radius))
    from_gearset(_rollers(gearset, count, float(bound) - 1e-3))  # just fits


def test_from_gearset_rollers_need_two_waves(gearset):
    four = gearset.with_values({"gear.waves": 4, "gear.circular_spline_teeth": 204, "wave_generator.contour": "rollers",
                                "wave_generator.roller_count": 4, "wave_generator.roller_radius_mm": 5.0})
    with pytest.raises(WaveGenError, match="gear.waves"):
        from_gearset(four)


def test_roller_protocol_and_to_dict(gearset):
    import json

    rollers = from_gearset(_rollers(gearset, 4, 8.0))
    contour: wavegen.Contour = rollers
    assert contour.radius([0.5]).shape == (1,)
    assert [a.shape for a in contour.closest([[1.0, 60.0]])] == [(1, 2), (1, 2), (1,)]
    d = json.loads(json.dumps(rollers.to_dict()))
    assert d["kind"] == "rollers" and d["roller_count"] == 4 and len(d["centres_mm"]) == 4
    assert d["centre_angle_deg"] == pytest.approx(math.degrees(rollers.centre_angle_rad))
    with pytest.raises(ValueError):
        rollers.centres[0, 0] = 1.0  # read-only
