"""The load split between the U engagement zones, and the absolute rotation, checked
independently of the package's own zone torque (issue 16, must-show).

The contact solves one zone and gives it T_zone = T / U; the other checks compare the
moment Σ r F with that same T_zone, so a solve that put the whole torque T on each zone
would pass them. Here the expected numbers come from the whole gear instead:

* **by hand** — one or two contact points per zone with a known compliance: the whole gear's
  torque balance Σ over all U zones of r F = T, the zones alike, and compatibility
  c F + e = r φ give the forces and the rotation φ in closed form (no solver);
* **the full ring** — U = 2 zones solved as one problem, 2n points, the total torque T,
  no zone torque anywhere: the LCP Σ_all r F = T, F ≥ 0, g = e + S_full F − r φ ≥ 0,
  F·g = 0 (:func:`~profilegen.contact.solvers.solve_lemke` on the 2n points). S_full =
  [[A, B], [B, A]] is built from the package's own compliance S of a few points of the
  default set (ContactCompliance.build: the FS half ring whose loads each stand for
  themselves and their image, so S = A + B: A a zone's own, B the other zone's images) —
  the split into A and B is synthetic (B = S/4), the sum is the package's. The one-zone
  solve (:func:`~profilegen.contact.analysis.solve_contact`, the path the pipeline and the
  transmission error use) must give each zone's forces and the same rotation; with T on
  each zone it gives twice the forces and a rotation ~2× farther.
"""

import math

import numpy as np
import pytest

import profilegen as pg
from profilegen.contact import ContactInput, ContactPoints, contact_points, solve_lemke
from profilegen.contact.analysis import analyse_contact, solve_contact
from profilegen.contact.compliance import ContactCompliance


def _points(levers, gaps, zones=2):
    """Hand-made contact points (one per tooth), lever arms r (mm) and gaps e (mm)."""
    n = len(levers)
    z = np.zeros((n, 2))
    return ContactPoints(np.arange(n), np.zeros(n), np.zeros(n), z, z, z, np.tile([1.0, 0.0], (n, 1)),
                         np.asarray(gaps, float), np.asarray(levers, float), 1, 1, zones, 2, 1.0)


def test_one_point_per_zone_by_hand():
    """One tooth per zone, compliance c, lever r, no gap: the U teeth share T by the whole
    gear's balance, F = T/(U r); φ = c F / r = c T / (U r²)."""
    c, r, torque = 2.0e-5, 48.0, 265.0  # mm/N, mm, N·m
    for zones in (2, 3):
        res = analyse_contact(_points([r], [0.0], zones=zones), [[c]], [torque])
        case = res.cases[0]
        force = torque * 1e3 / (zones * r)
        assert case.solution.force_n[0] == pytest.approx(force, rel=1e-12)
        assert case.rotation_rad == pytest.approx(c * torque * 1e3 / (zones * r * r), rel=1e-12)


def test_two_points_per_zone_by_hand():
    """Two teeth per zone, S = [[c1, c12], [c12, c2]], levers r1, r2, gaps 0 and e2.
    Small T: only tooth 1 closes, φ = c1 T/(U r1²), tooth 2's gap e2 + c12 F1 − r2 φ > 0.
    Large T: both close, F = S⁻¹(φ r − e) with rᵀF = T/U, so
    φ = (T/U + rᵀS⁻¹e) / (rᵀS⁻¹r), S⁻¹ = [[c2, −c12], [−c12, c1]] / (c1 c2 − c12²)."""
    c1, c2, c12 = 2.0e-5, 3.0e-5, 0.8e-5
    r1, r2, e2 = 48.0, 45.0, 2.0e-3
    zones = 2
    pts = _points([r1, r2], [0.0, e2], zones)
    s = [[c1, c12], [c12, c2]]
    det = c1 * c2 - c12 * c12
    # small torque: tooth 2 stays open
    small = 10.0
    f1 = small * 1e3 / (zones * r1)
    phi = c1 * f1 / r1
    assert e2 + c12 * f1 - r2 * phi > 0.0
    case = analyse_contact(pts, s, [small]).cases[0]
    np.testing.assert_allclose(case.solution.force_n, [f1, 0.0], rtol=1e-12, atol=1e-12)
    assert case.rotation_rad == pytest.approx(phi, rel=1e-12)
    # large torque: both closed
    big = 600.0
    sir = np.array([c2 * r1 - c12 * r2, -c12 * r1 + c1 * r2]) / det  # S⁻¹ r
    sie = np.array([-c12 * e2, c1 * e2]) / det  # S⁻¹ e
    phi = (big * 1e3 / zones + r1 * sie[0] + r2 * sie[1]) / (r1 * sir[0] + r2 * sir[1])
    forces = phi * sir - sie
    assert np.all(forces > 0.0)
    case = analyse_contact(pts, s, [big]).cases[0]
    np.testing.assert_allclose(case.solution.force_n, forces, rtol=1e-10)
    assert case.rotation_rad == pytest.approx(phi, rel=1e-12)
    # the whole gear: U zones × Σ r F = T
    assert zones * (r1 * forces[0] + r2 * forces[1]) == pytest.approx(big * 1e3, rel=1e-12)


@pytest.fixture(scope="module")
def few():
    """The default set's sketch design: the points of the 5 teeth that carry the most load at
    the rated torque in the full solve, their compliance from the package, and the one-zone
    solve of solve_contact at the rated torque."""
    inputs = ContactInput.from_design(pg.design(pg.load_gearset(pg.default_gearset_path()), scene="sketch",
                                                contact=False, stress=False))
    pts = contact_points(inputs)
    # the teeth nearest first contact (smallest θ): they take the load at the rated torque
    first = np.argsort([pts.theta_rad[pts.tooth == t].min() for t in pts.teeth])[:5]
    sel = np.flatnonzero(np.isin(pts.tooth, pts.teeth[first]))
    sub = ContactPoints(*(getattr(pts, f)[sel] for f in ("tooth", "phi_rad", "t_mm", "local_mm", "fs_point_mm",
                                                         "cs_point_mm", "normal", "gap_mm", "lever_mm")),
                        pts.side, pts.rotation, pts.zones, pts.stations, pts.max_gap_mm)
    comp = ContactCompliance.build(inputs, sub.fs_point_mm, sub.normal, sub.tooth, sub.cs_point_mm)
    torque = inputs.gearset.torque.rated_nm
    case = solve_contact(inputs, [torque], points=sub, compliance=comp).cases[0]
    return inputs, sub, comp.with_balls(case.ball_active).matrix_mm_per_n, case


def test_full_ring_split_and_rotation(few):
    inputs, pts, s, case = few
    zones = inputs.gearset.gear.waves
    assert zones == 2 and pts.zones == zones
    torque_nmm = inputs.gearset.torque.rated_nm * 1e3
    b = 0.25 * s  # synthetic: the image zone's share of S (any split with A − B positive definite)
    a = s - b
    s_full = np.block([[a, b], [b, a]])
    assert np.all(np.linalg.eigvalsh(a - b) > 0.0)
    theta = np.concatenate([pts.theta_rad, pts.theta_rad])
    lever = np.concatenate([pts.lever_mm, pts.lever_mm])
    full = solve_lemke(s_full, theta, lever, torque_nmm)  # the whole torque, both zones, no T/U
    n = pts.count
    zone_moment = [float(pts.lever_mm @ full.force_n[:n]), float(pts.lever_mm @ full.force_n[n:])]
    # the load split: each zone half the torque, found by the full solve, not imposed
    np.testing.assert_allclose(zone_moment, [torque_nmm / zones] * 2, rtol=1e-9)
    np.testing.assert_allclose(full.force_n[:n], full.force_n[n:], atol=1e-9 * full.max_force_n)
    # the one-zone solve of the package: each zone's forces and the absolute rotation
    f = case.solution.force_n
    assert 1 < np.count_nonzero(f) < f.size
    np.testing.assert_allclose(f, full.force_n[:n], atol=1e-8 * full.max_force_n)
    assert case.rotation_rad == pytest.approx(full.phi_rad, rel=1e-9)
    # and the rotation is not the first contact's alone: the load moved it by most of itself
    assert full.phi_rad > 1.5 * float(pts.theta_rad.min())
    # a zone that carried T instead: twice the moment, a rotation far from the full ring's
    wrong = solve_lemke(s, pts.theta_rad, pts.lever_mm, torque_nmm)
    assert abs(wrong.phi_rad - full.phi_rad) > 0.3 * (full.phi_rad - float(pts.theta_rad.min()))
    assert not math.isclose(wrong.phi_rad, case.rotation_rad, rel_tol=1e-3)
