"""Wave-generator contours: exact distances, normals, the bearing offset, the perimeter rule."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from profilegen import wavegen
from profilegen.errors import ConvergenceError
from profilegen.gearset import default_gearset_path, load_gearset
from profilegen.wavegen import CosineCam, EllipticalCam, WaveGenError, from_gearset


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
    with pytest.raises(WaveGenError, match="wave_generator.contour"):
        from_gearset(rollers)


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
