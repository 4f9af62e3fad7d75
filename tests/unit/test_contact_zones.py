"""The load split between the U engagement zones, and the absolute rotation, checked
independently of the package's own zone torque (issue 16, must-show).

The contact solves one zone and gives it T_zone = T / U; the other checks compare the
moment Σ r F with that same T_zone, so a solve that put the whole torque T on each zone
would pass them. Here the expected numbers come from the whole gear instead:

* **by hand** — one or two contact points per zone with a known compliance: the whole gear's
  torque balance Σ over all U zones of r F = T, the zones alike, and compatibility
  c F + e = r φ give the forces and the rotation φ in closed form (no solver);
* **the full ring** — both zones of a two-wave gear as one problem: the FS as the whole
  ring of z1 pitches (no point-symmetric tie: the package's one-pitch substructure, condensed
  onto its cuts, chained round 2π instead of π), loaded at a few points of the default set
  *and* at their images in the other zone, on the balls of both zones; the rigid
  translations, which the tie removed, are left free and held by the balls (a saddle-point
  solve: ball reactions and translation together, the loads' resultant taken by the balls);
  the bore's mean rotation held as in the package. Each zone's CS is the package's sector
  (fixed outside: the zones do not meet through it). Then S_full = [[A, B], [B, A]] (A a
  zone's own, B the other zone's images) and the LCP with the whole torque on all 2n points,
  no zone torque anywhere: Σ_all r F = T, F ≥ 0, g = e + S_full F − r φ ≥ 0, F·g = 0
  (:func:`~profilegen.contact.solvers.solve_lemke`). The package's one-zone matrix must be
  A + B (each load stands for itself and its image), and its one-zone solve
  (:func:`~profilegen.contact.analysis.solve_contact`, the path the pipeline and the
  transmission error use) must give each zone's forces and the same rotation; with T on
  each zone it gives twice the forces and a rotation far off. Without the outer race
  (``race_thickness_mm=0``, balls on the bore: the sliding race's extra dofs are not
  rebuilt here). Every ball of the zone one-sided at its no-load gap, as the contact stage:
  the balls the one-zone solve loads are held at their gaps on the full ring (a known
  displacement in the saddle solve), the others free, and the full ring's ball reactions and
  free balls' gaps are checked for complementarity.
"""

import math

import numpy as np
import pytest

from profilegen.contact import ContactInput, ContactPoints, contact_points, solve_lemke
from profilegen.contact.analysis import analyse_contact, solve_contact
from profilegen.contact import compliance as cm
from profilegen.contact.compliance import ContactCompliance
from profilegen.geometry.kinematics import turn
from profilegen.rim.toothed import toothed_half_ring_mesh


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


def _full_ring(inputs, pts, ball_angles, active, gaps_mm, face_width_mm):
    """The FS of the whole ring for ``pts`` (one zone) and their images (tooth i + z1/2, the
    same tooth-frame point), on every ball of the zone at ``ball_angles`` and its image at + π:
    the package's one-pitch substructure (14 columns, 2 rim + 4 tooth layers, its defaults)
    chained round the full circle. The ``active`` balls (and images) are held at their no-load
    gaps ``gaps_mm`` (the bore moves in by the gap there), the others free.
    → (S (2n × 2n, mm/N), the teeth's separation offset from the held balls' gaps (2n, mm),
    balls(F) → (the active balls' reactions (N), the free balls' gaps after load (mm)))."""
    gs = inputs.gearset
    g = gs.gear
    z1, z2 = g.flexspline_teeth, g.circular_spline_teeth
    ring = toothed_half_ring_mesh(inputs.tooth, g.rim_thickness_mm, toothed_pitches=[0], pitches=1, per_pitch=14,
                                  rim_layers=2, tooth_layers=4)
    r_bore = g.neutral_radius_mm - 0.5 * g.rim_thickness_mm
    pitch, c, rot, (ix, iy, n_full, _), gauges = cm._half_ring_pitch(
        ring, gs.material.youngs_modulus_mpa, gs.material.poisson_ratio, r_bore, ring.inner_nodes, None, "full ring")
    # the points in their tooth frames (the inverse of contact.points' placement), then round the ring
    pose = inputs.motion.pose(2.0 * math.pi * pts.tooth / z1)
    angle = 2.0 * math.pi * pts.tooth / z2
    local = pose.to_tooth(turn(pts.fs_point_mm, -angle))
    n_cs = turn(pts.normal, -angle)
    co, si = np.cos(pose.angle), np.sin(pose.angle)
    local_n = np.column_stack([n_cs[:, 0] * co - n_cs[:, 1] * si, n_cs[:, 0] * si + n_cs[:, 1] * co])
    k = np.mod(np.concatenate([pts.tooth, pts.tooth + z1 // 2]), z1)
    loc, loc_n = np.vstack([local, local]), np.vstack([local_n, local_n])
    co, si = np.cos(k * ring.pitch_rad), np.sin(k * ring.pitch_rad)
    r_m = g.neutral_radius_mm
    xy = np.column_stack([loc[:, 0] * co + (loc[:, 1] + r_m) * si, -loc[:, 0] * si + (loc[:, 1] + r_m) * co])
    d_c = -np.column_stack([loc_n[:, 0] * co + loc_n[:, 1] * si, -loc_n[:, 0] * si + loc_n[:, 1] * co])
    kinds = np.zeros(z1, dtype=int)  # every pitch alike, z1 of them: the whole circle
    p_c, t_c, w_c, dist, a_c = cm._pitch_projection(xy, k, kinds, ring.pitch_rad,
                                                    [(ring.mesh.doflocs, ring.outer_nodes)])
    assert dist.max() < 0.01
    z_half = -ring.start_rad
    theta = np.mod(np.concatenate([ball_angles, ball_angles + math.pi]) + z_half, 2.0 * math.pi) - z_half
    e_r = np.column_stack([np.sin(theta), np.cos(theta)])
    p_b, t_b, w_b, _, a_b = cm._pitch_projection(r_bore * e_r, np.floor((theta + z_half) / ring.pitch_rad),
                                                 kinds, ring.pitch_rad, [(ring.mesh.doflocs, ring.inner_nodes)])
    on = np.concatenate([p_c, p_b])
    loads = cm._load_matrix(n_full, ix, iy, np.vstack([t_c, t_b]), np.vstack([w_c, w_b]),
                            cm._turn_back(np.vstack([d_c, e_r]), np.concatenate([a_c, a_b]))).tocsr()
    # held: tangential + radial at the bore node of cut 0, tangential at cut z1/2's (both
    # translations and the rotation; the rotation's gauge is then the bore's mean, as the package's)
    n_cut = pitch.n_cut
    held = [gauges[0], gauges[0] + 1, (z1 // 2) * n_cut + gauges[0]]
    flex, _ = cm._chain_flex([pitch], kinds, [loads], [(on, np.arange(on.size))], cyclic=True, fixed_cut=held,
                             gauge=([c], [rot]), where="FS full ring")
    m = d_c.shape[0]
    # the held balls (rigid, radial) with the translation t free: the pinned solution plus t,
    # each held ball's bore point moved in by its gap (u_b + e_r·t = −gap), the loads' resultant
    # carried by the balls (Σ λ e_r + Σ F d = 0)
    b = face_width_mm
    act = np.flatnonzero(np.concatenate([active, active]))
    free = np.flatnonzero(~np.concatenate([active, active]))
    gap = np.concatenate([gaps_mm, gaps_mm])
    g_cc, g_cb, g_bb = flex[:m, :m], flex[:m, m:], flex[m:, m:]
    e_a = e_r[act]
    saddle = np.block([[g_bb[np.ix_(act, act)], e_a], [e_a.T, np.zeros((2, 2))]])
    coupling = np.hstack([g_cb[:, act], d_c])
    s2d = g_cc - coupling @ np.linalg.solve(saddle, coupling.T)
    held_gap = np.concatenate([gap[act], [0.0, 0.0]])
    offset = -coupling @ np.linalg.solve(saddle, held_gap)

    def balls(force_n):
        lam_t = -np.linalg.solve(saddle, coupling.T @ (force_n / b) + held_gap)  # λ (N/mm) and t (mm)
        lam, t = lam_t[:act.size], lam_t[act.size:]
        h = gap[free] + g_cb[:, free].T @ (force_n / b) + g_bb[np.ix_(free, act)] @ lam + e_r[free] @ t
        return lam * b, h

    return 0.5 * (s2d + s2d.T) / b, offset, balls


@pytest.fixture(scope="module")
def few(default_sketch):
    """The default set's sketch design: the points of the 5 teeth nearest first contact, the
    package's compliance for them (no outer race, every ball of the zone one-sided at its
    no-load gap, as the contact stage) and its one-zone solve at the rated torque, and the full
    ring for them and their images on the balls that solve loads (held at their gaps)."""
    inputs = ContactInput.from_design(default_sketch)  # conftest.py: computed once per worker
    pts = contact_points(inputs)
    first = np.argsort([pts.theta_rad[pts.tooth == t].min() for t in pts.teeth])[:5]
    sel = np.flatnonzero(np.isin(pts.tooth, pts.teeth[first]))
    sub = ContactPoints(*(getattr(pts, f)[sel] for f in ("tooth", "phi_rad", "t_mm", "local_mm", "fs_point_mm",
                                                         "cs_point_mm", "normal", "gap_mm", "lever_mm")),
                        pts.side, pts.rotation, pts.zones, pts.stations, pts.max_gap_mm)
    comp = ContactCompliance.build(inputs, sub.fs_point_mm, sub.normal, sub.tooth, sub.cs_point_mm,
                                   race_thickness_mm=0.0, ball_supports="all")
    case = solve_contact(inputs, [inputs.gearset.torque.rated_nm], points=sub, compliance=comp).cases[0]
    s_zone = comp.with_balls(case.ball_active).matrix_mm_per_n
    n = sub.count
    cs = comp.cs_matrix_mm_per_n
    fs_full, offset, balls = _full_ring(inputs, sub, comp.ball_angle_rad, case.ball_active, comp.ball_gap_mm,
                                        comp.face_width_mm)
    s_full = fs_full + np.block([[cs, np.zeros((n, n))], [np.zeros((n, n)), cs]])
    return inputs, sub, s_zone, case, s_full, offset, balls, comp


def test_the_zone_matrix_is_the_full_ring_with_its_images(few):
    """S (one zone, half ring with the tie) = A + B of the full ring: each load stands for
    itself and its image. B is not small (the other zone's loads turn the whole rim): a
    zone solved with A alone would be far too stiff."""
    _, pts, s_zone, _, s_full = few[:5]
    n = pts.count
    a, b = s_full[:n, :n], s_full[:n, n:]
    np.testing.assert_allclose(s_full[n:, n:], a, rtol=0, atol=1e-9 * np.abs(a).max())  # the zones alike
    np.testing.assert_allclose(a + b, s_zone, rtol=0, atol=1e-6 * np.abs(s_zone).max())
    assert np.abs(b).max() > 0.5 * np.abs(a).max()


def test_full_ring_split_and_rotation(few):
    """The whole torque on both zones of the full ring, its held balls at their gaps: each zone
    half the torque, the package's one-zone forces, rotation and ball reactions, and every
    ball complementary on the full ring (held balls push, free balls clear of the rim)."""
    inputs, pts, s_zone, case, s_full, offset, balls, comp = few
    zones = inputs.gearset.gear.waves
    assert zones == 2 and pts.zones == zones
    torque_nmm = inputs.gearset.torque.rated_nm * 1e3
    lever = np.concatenate([pts.lever_mm, pts.lever_mm])
    # the held balls' gaps pull the rim in: each point's first-contact angle moves by offset / r
    theta = np.concatenate([pts.theta_rad, pts.theta_rad]) + offset / lever
    shift = float(theta.min())
    full = solve_lemke(s_full, theta - shift, lever, torque_nmm)  # the whole torque, both zones, no T/U
    phi = full.phi_rad + shift
    n = pts.count
    zone_moment = [float(pts.lever_mm @ full.force_n[:n]), float(pts.lever_mm @ full.force_n[n:])]
    # the load split: each zone half the torque, found by the full solve, not imposed
    np.testing.assert_allclose(zone_moment, [torque_nmm / zones] * 2, rtol=1e-6)
    np.testing.assert_allclose(full.force_n[:n], full.force_n[n:], atol=1e-6 * full.max_force_n)
    # the one-zone solve of the package: each zone's forces, the absolute rotation, the balls
    f = case.solution.force_n
    assert 1 < np.count_nonzero(f) < f.size
    np.testing.assert_allclose(f, full.force_n[:n], atol=1e-6 * full.max_force_n)
    assert case.rotation_rad == pytest.approx(phi, rel=1e-6)
    react, free_gap = balls(full.force_n)
    k = int(np.count_nonzero(case.ball_active))
    np.testing.assert_allclose(react[:k], react[k:], rtol=1e-6)  # the zones' balls alike
    np.testing.assert_allclose(react[:k], case.ball_reaction_n[case.ball_active], rtol=1e-5)
    assert react.min() > 0.0 and free_gap.min() > -1e-9 * np.abs(comp.ball_gap_mm).max()
    # the balls outside the rim's no-load contact angle: some take load, from their gaps
    assert np.any(case.ball_active & (comp.ball_gap_mm > 0.0))
    # and the rotation is not the first contact's alone: the load moved it by most of itself
    assert phi > 1.5 * float(pts.theta_rad.min())
    # a zone that carried T instead: twice the moment, a rotation far from the full ring's
    wrong = comp.solve_unilateral(pts.theta_rad, pts.lever_mm, torque_nmm)[0]
    assert abs(wrong.phi_rad - phi) > 0.3 * (phi - float(pts.theta_rad.min()))
