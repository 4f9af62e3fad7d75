"""The cup on its wave generator (profilegen.rim.cup.contact, .nonlinear): the exact contact gap,
geometric nonlinearity and seed 004's displaced halves, each against something the solver does
not compute itself:

* the harmonic-balance internal force is the linear harmonic stiffness for a small displacement
  and zero for a finite rigid rotation about the axis (the kinematics);
* a cam equal to the undeformed bore loads nothing, linear or nonlinear;
* with the exact gap the loaded bore points lie on the cam ellipse (its implicit equation, not
  the solver's distance function), while the first-order gap leaves them µm off; the two
  differ by O(w0²) (halving w0 quarters the difference);
* in the long-cup limit the cup's nonlinear change of ω, υ is the 2D nonlinear ring's;
* seed 004's halves: pushing two halves apart by ±s lengthens their hull by exactly 4s (so the
  halves of the bore's own circle would stretch the bore, and the "inextensible" halves need a
  shorter ellipse); on the hull's bridges the distance and normal are the straight line's.

Coarse meshes; tests/benchmarks/seed004_cup.py has the default-mesh runs and the table.
"""

import math

import numpy as np
import pytest

from profilegen.rim.cup import harmonic_stiffness, meridional_mesh, press_cup
from profilegen.rim.cup.contact import DisplacedHalves
from profilegen.rim.cup.nonlinear import HarmonicTotalLagrangian
from profilegen.geometry.wavegen import EllipticalCam, ellipse_perimeter

from tests.cups import NU, R_B, R_M, T, W0, E, cam, cup


GEOM = cup()


@pytest.fixture(scope="module")
def coarse():
    return harmonic_stiffness(meridional_mesh(GEOM, element_mm=4.0, layers=2))


def test_nonlinear_force_is_the_linear_stiffness_when_small_and_zero_for_a_rigid_rotation(coarse):
    orders = np.arange(0, 8, 2)
    body = HarmonicTotalLagrangian(coarse, orders)
    x = np.random.default_rng(1).standard_normal((orders.size, coarse.dof))
    eps = 1e-6
    small = (body.force(eps * x) - body.force(-eps * x)) / (2 * eps)  # central: the O(u²) part cancels
    for k, n in enumerate(orders):
        kx = coarse.stiffness(int(n)) @ x[k]
        assert np.max(np.abs(small[k] - kx)) < 1e-8 * np.max(np.abs(kx)), n
    # a finite rotation α about the axis: u_r = r(cos α − 1), u_φ = r sin α (harmonic 0) is strain free
    iu, _, iv = coarse.components()
    r = coarse.nodes[0]
    rot = np.zeros((orders.size, coarse.dof))
    rot[0, iu], rot[0, iv] = r * (math.cos(0.3) - 1.0), r * math.sin(0.3)
    assert np.max(np.abs(body.force(rot))) < 1e-12 * np.max(np.abs(coarse.stiffness(0) @ rot[0]))
    # ... which the linear stiffness is not: its strain of the same field is not zero
    assert np.max(np.abs(coarse.stiffness(0) @ rot[0])) > 1e3


def test_a_cam_equal_to_the_undeformed_bore_loads_nothing(coarse):
    bore = EllipticalCam(R_B, R_B)
    for nonlinear in (False, True):
        c = press_cup(GEOM, contour=bore, gap="exact", nonlinear=nonlinear, harmonic_basis=coarse, angles=6)
        # (the cam's distance function is exact to ~1e-14 mm: forces of that order times the stiffness)
        assert np.max(c.force_n) < 1e-6  # N; w0 = 0.5 mm needs ~1e3 N
        assert np.max(np.abs(c.deformation.radial_mm)) < 1e-12 and np.max(np.abs(c.deformation.tangential_mm)) < 1e-12


def _off_ellipse(c, contour):
    """Largest distance (mm, first order in the implicit function) of the loaded bore points from
    the cam ellipse (x/b)² + (y/a)² = 1, from the solver's bore displacements."""
    phi = c.phi_rad[None, :]
    r = R_B + c.band_radial_mm
    x = r * np.sin(phi) + c.band_tangential_mm * np.cos(phi)
    y = r * np.cos(phi) - c.band_tangential_mm * np.sin(phi)
    a, b = contour.semi_major_mm, contour.semi_minor_mm
    f = (x / b) ** 2 + (y / a) ** 2 - 1.0
    grad = np.hypot(2 * x / b**2, 2 * y / a**2)
    return float(np.max(np.abs(f / grad)[c.active]))


def test_the_exact_gap_puts_the_loaded_bore_on_the_cam_and_differs_by_order_w0_squared(coarse):
    diffs = []
    for w0 in (0.5, 0.25, 0.125):
        ct = cam(w0)
        exact = press_cup(GEOM, contour=ct, gap="exact", harmonic_basis=coarse, angles=8)
        first = press_cup(GEOM, contour=ct, gap="first_order", harmonic_basis=coarse, angles=8)
        if w0 == 0.5:
            assert _off_ellipse(exact, ct) < 1e-8
            assert _off_ellipse(first, ct) > 1e-3  # the tangential displacement along a curved cam
        diffs.append(abs(exact.deformation.omega(0.0, 70.0) - first.deformation.omega(0.0, 70.0)))
    assert diffs[0] > 4e-3  # µm-level: 5.7 µm at the open end on this mesh
    # O(w0²) once the loaded set is the same in both (at w0 = 0.5 the first-order gap loads 54
    # collocation points, the exact one 60; measured 4.04 for 0.25 → 0.125, 3.999 for 0.125 → 0.0625)
    assert 3.8 < diffs[1] / diffs[2] < 4.2, diffs


def test_long_cup_nonlinearity_is_the_2d_nonlinear_rings():
    """A 300 mm cup on a 4 mm bearing: its section under the bearing is a ring, and the change
    that geometric nonlinearity makes there (−10.5 µm on the minor axis for the 2D ring, the free
    part's inextensibility at second order) is the ring's: sign, place and size (within 25 %)."""
    from profilegen.rim.ring import RingParameters, solve_ring

    ct = cam()
    ring = RingParameters(R_M, T, E, NU)
    d_ring = {g: solve_ring(ring, contour=ct, geometry=g, divisions=32) for g in ("linear", "nonlinear")}
    g = cup(300.0, bearing_width_mm=4.0)
    hb = harmonic_stiffness(meridional_mesh(g, element_mm=4.0, layers=2))
    d_cup = {nl: press_cup(g, contour=ct, gap="exact", nonlinear=nl, harmonic_basis=hb, angles=12).deformation
             for nl in (False, True)}
    phi = np.array([0.0, 0.5 * math.pi, 3 * math.pi / 8])

    def ring_at(res):
        return np.interp(phi, res.phi_rad, res.omega_mm), np.interp(phi, res.phi_rad, res.upsilon_mm)

    (wl, ul), (wn, un) = ring_at(d_ring["linear"]), ring_at(d_ring["nonlinear"])
    dw_ring, du_ring = wn - wl, un - ul
    dw_cup = d_cup[True].omega(phi, 300.0) - d_cup[False].omega(phi, 300.0)
    du_cup = d_cup[True].upsilon(phi, 300.0) - d_cup[False].upsilon(phi, 300.0)
    assert dw_ring[1] < -8e-3  # the 2D ring: about −10.5 µm on the minor axis
    assert abs(dw_cup[1] - dw_ring[1]) < 0.25 * abs(dw_ring[1]), (dw_cup, dw_ring)
    assert abs(du_cup[2] - du_ring[2]) < 0.25 * abs(du_ring[2]), (du_cup, du_ring)
    assert abs(dw_cup[0]) < 0.05 * abs(dw_ring[1])  # the major axis stays on the cam


def test_displaced_halves_hull_is_four_shifts_longer_and_its_bridges_are_straight():
    half = EllipticalCam(R_B, R_B - 1.0)
    s = 0.5
    wg = DisplacedHalves(half, s)
    theta = np.linspace(0.0, 2 * math.pi, 4001)
    r = wg.radius(theta)
    pts = np.column_stack([r * np.sin(theta), r * np.cos(theta)])
    hull = float(np.sum(np.hypot(*np.diff(pts, axis=0).T)))
    assert hull == pytest.approx(ellipse_perimeter(R_B, R_B - 1.0) + 4 * s, abs=2e-4)  # polygon: −3e-5
    assert r[0] == pytest.approx(R_B + s, abs=1e-12)  # the major axis: pushed out by s
    # a point beside the bridge: distance and normal of the line x = x_end
    foot, normal, dist = wg.closest(np.array([[R_B - 2.0, 0.2], [R_B + 1.0, -0.3]]))
    np.testing.assert_allclose(dist, [-1.0, 2.0], atol=1e-12)
    np.testing.assert_allclose(normal, [[1.0, 0.0], [1.0, 0.0]], atol=1e-15)
    np.testing.assert_allclose(foot[:, 0], R_B - 1.0, atol=1e-12)


# --------------------------------------------------------------------------- seed 004's numbers


def test_a_rigid_cam_stops_the_minor_axis_at_its_radius_whatever_the_cup_length():
    """What the refutation of the rigid-contour reading (a) of seed 004 rests on: where the
    bearing covers a section, the bore cannot go inside the cam, so ω on the minor axis is never
    below the cam's minor radius − r_bore (−0.503 mm for w0 = 0.5), for a short or a long cup —
    the seed's −0.557 mm is 54 µm deeper; and the cup does reach it (it bears there)."""
    ct = cam()
    floor = ct.semi_minor_mm - R_B
    zs = np.linspace(50.0, 70.0, 41)
    for length in (60.0, 180.0):
        g = cup(length)
        d = press_cup(g, contour=ct, gap="exact", element_mm=4.0, angles=8).deformation
        w = d.omega(0.5 * math.pi, zs + (length - 60.0))
        # the neutral surface sits half a wall out from the bore, whose thickness changes by ~0.25 µm
        assert np.min(w) > floor - 5e-4, (length, np.min(w), floor)
        assert np.min(w) < floor + 1e-3  # it bears on the cam's minor axis (at the open end)
    assert floor > -0.557 + 0.05


SEED004_OMEGA = ((0.5272, 1.987, 1.611), (0.02677, 5.965, 1.694), (0.007596, 4.033, -9.533))
SEED004_UPSILON = ((0.2956, 2.013, 3.090), (0.01807, 0.2032, -1.919), (0.01897, 4.067, -1.909))


def test_seed_004_printed_series_are_recovered_by_the_package_fit_and_give_its_extremes():
    """Seed 004's printed sine-series fits (the rim's middle cross-section, by its text), sampled
    over a turn and fitted again by the package's seed-004 fitter (series.fit_sine_series, 3
    terms): a noise-free sum of three sines is recovered term by term (amplitudes, frequencies),
    and the fit's extremes are 0.554 / −0.555 mm — the seed's printed 0.553 / −0.557 to its
    fitting error — with a υ amplitude of 0.2965 mm over the half turn: the three printed numbers
    describe the middle section, not the open end. (Replaces a check of the printed series alone,
    which called no package code.)"""
    from profilegen.geometry.series import fit_sine_series

    phi = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
    dense = np.linspace(0.0, 2 * math.pi, 20001)
    got = {}
    for name, terms in (("omega", SEED004_OMEGA), ("upsilon", SEED004_UPSILON)):
        y = sum(a * np.sin(b * phi + c) for a, b, c in terms)
        fit = fit_sine_series(phi, y, terms=3, starts=8)
        order = np.argsort([-a for a, _, _ in terms])
        np.testing.assert_allclose(fit.amplitude_mm, [terms[k][0] for k in order], rtol=1e-6)
        np.testing.assert_allclose(fit.frequency_per_rad, [terms[k][1] for k in order], rtol=1e-6)
        assert fit.stats.max_error_mm < 1e-9
        got[name] = fit.evaluate(dense, order=0)[0]
    w, u = got["omega"], got["upsilon"]
    assert w.max() == pytest.approx(0.553, abs=2e-3) and w.min() == pytest.approx(-0.557, abs=3e-3)
    half = dense <= math.pi
    assert np.abs(u[half]).max() == pytest.approx(0.2965, abs=5e-4)


def test_bad_contact_options_are_named(coarse):
    from profilegen.rim.cup import CupError

    for kw, name in (({"gap": "second_order"}, "gap"), ({"nonlinear": "yes"}, "nonlinear"),
                     ({"open_end_axial_fixed": 2}, "open_end_axial_fixed"), ({"gap_tol_mm": -1.0}, "gap_tol_mm")):
        with pytest.raises(CupError, match=name):
            press_cup(GEOM, contour=cam(), harmonic_basis=coarse, **kw)
    with pytest.raises(CupError, match="gap = 'exact'"):
        press_cup(GEOM, radial_mm={2: W0}, gap="exact", harmonic_basis=coarse)
    with pytest.raises(CupError, match="shift_mm"):
        DisplacedHalves(cam(), -0.1)
