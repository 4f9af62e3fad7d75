"""Validation of profilegen.profile.envelope: analytic envelopes and a brute-force swept region.

Sources:

* Textbook (Litvin & Fuentes, Gear Geometry and Applied Theory, 2nd ed., §§ 6.1, 10.3;
  DESIGN.md trap 2): a straight-sided rack in generating motion envelopes the involute
  of base radius r_b = r cos α; in polar form, R = |Q| and a = arccos(r_b/R), the polar
  angle θ of every point is θ = λ ± inv a with inv a = tan a − a and λ a constant; a
  generic envelope routine must reproduce it to ~1e-12 mm.
* DESIGN.md trap 2: the meshing equation f = 0 gives candidates only — double roots, no
  roots, false (interfering) flanks up to ~0.5 mm inside the swept region, folds where
  f = ∂f/∂φ = 0, and tip-corner paths that the meshing equation cannot produce. The
  truth is the boundary of the swept region, here computed by brute force
  (``profilegen.profile.swept``: union of the tooth outline placed at n_phi poses, with its
  neighbours) — no meshing equation involved.
* Geometry: the default DCTA tooth in a ring-theory deformation (ω even, υ odd in φ) is
  mirror-symmetric about the CS space axis.

Brute-force resolution. The union of discrete placements lies inside the swept region,
in notches left where the tooth's tip corner moves; their depth falls as 1/n_phi
(measured ≈ 0.63 mm / n_phi for the DCTA set, ≈ 0.93 mm / n_phi for the involute):
at n_phi = 1441 (~0.5 s) the largest distance between our CS flank and the brute-force
boundary, either way, is 0.45 µm (DCTA) and 0.79 µm (involute), so agreement is asserted
to 2 µm. The outline polygon's chord sag (100 points per mm) is ~0.02 µm.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from profilegen.geometry.deformation import ring_theory
from profilegen.profile.envelope import (
    CONJUGATE,
    INTERFERING,
    TIP_PATH,
    Curve,
    ToothShape,
    envelope_of,
    line_curve,
    solve_envelope,
    tooth_curves,
    trace_meshing_roots,
)
from profilegen.errors import EnvelopeError
from profilegen.geometry.kinematics import HarmonicDriveMotion, RackMotion, turn
from profilegen.profile.swept import boundary_distance, swept_region
from profilegen.geometry.teeth import dcta_tooth, involute_tooth

M, Z1, Z2, U, RM = 0.5, 200, 202, 2, 48.95
GEAR = dict(module_mm=M, teeth=Z1, neutral_radius_mm=RM)
PASS = (-math.pi / U, math.pi / U)
N_PHI_BRUTE = 1441  # brute-force error ≈ 0.4–0.8 µm (see the module docstring)
BRUTE_TOL = 2e-3  # mm
SAG_TOL = 1e-4  # mm (0.1 µm): how far the brute region may exceed the true one (outline chord sag)


def _motion(w0):
    return HarmonicDriveMotion(ring_theory(w0, U), RM, U, Z2)


def _env(tooth, w0, **kw):
    return envelope_of(tooth, _motion(w0), cs_teeth=Z2, waves=U, **kw)


def _region(tooth, w0):
    return swept_region(tooth, _motion(w0), cs_teeth=Z2, waves=U, n_phi=N_PHI_BRUTE)


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_envelope")


@pytest.fixture(scope="module")
def dcta():
    return dcta_tooth(**GEAR)


@pytest.fixture(scope="module")
def env_default(dcta):  # ω* = 1: w0 = m = 0.5 mm
    return _env(dcta, 0.5)


@pytest.fixture(scope="module")
def region_default(dcta):
    return _region(dcta, 0.5)


@pytest.fixture(scope="module")
def env_08(dcta):  # ω* = 0.8
    return _env(dcta, 0.4)


# ----------------------------------------------------------------------------- helpers


def _meshing(tooth, motion, t, phi, side=1):
    """f, ∂f/∂t, ∂f/∂φ from Pose.meshing_coefficients (validated against ∂Q/∂φ × ∂Q/∂t in
    test_kinematics) and the tooth's own t-terms [p·p′, p′_y, p′_x]."""
    p, dp, ddp = tooth.evaluate(np.atleast_1d(t), side=side)
    T = np.stack([np.sum(p * dp, -1), dp[:, 1], dp[:, 0]], -1)
    Tt = np.stack([np.sum(dp * dp, -1) + np.sum(p * ddp, -1), ddp[:, 1], ddp[:, 0]], -1)
    a, a_phi = motion.pose(np.atleast_1d(phi)).meshing_coefficients()
    return np.sum(a * T, -1), np.sum(a * Tt, -1), np.sum(a_phi * T, -1)


def _root_count(tooth, motion, t, n=40001):
    """Number of roots φ of f(t, φ) = 0 over the pass, by sign changes on a fine grid."""
    phi = np.linspace(*PASS, n)
    a, _ = motion.pose(phi).meshing_coefficients()
    p, dp, _ = tooth.evaluate(np.atleast_1d(t))
    F = a @ np.stack([np.sum(p * dp, -1), dp[:, 1], dp[:, 0]])  # (n, len(t))
    return np.sum(np.sign(F[1:]) * np.sign(F[:-1]) < 0, axis=0), np.min(np.abs(F), axis=0)


def _brute_window(region, chain):
    """Brute-force boundary points (every 2 µm) in the CS space of the chain: within the
    chain's polar-angle range and above its lowest radius (the rest of the swept region's
    boundary — the rim's neutral line — lies ~1.5 mm lower)."""
    pts = shapely.get_coordinates(shapely.segmentize(region.boundary, 2e-3))
    ang, r = np.arctan2(pts[:, 0], pts[:, 1]), np.hypot(*pts.T)
    ca = np.arctan2(chain[:, 0], chain[:, 1])
    sel = (ang >= ca.min()) & (ang <= ca.max()) & (r >= np.hypot(*chain.T).min() - 1e-3)
    return pts[sel]


def _check_against_brute_force(env, region):
    """Both ways: our CS flank on the brute-force boundary, the brute-force boundary on our
    flank; boundary pieces never inside the brute region; deep false flanks inside it.
    Returns the measured distances (mm)."""
    chain = np.asarray(env.flank["boundary"])
    ours = boundary_distance(chain, region).max()
    window = _brute_window(region, chain)
    theirs = shapely.distance(shapely.points(window), shapely.LineString(chain)).max()
    assert len(window) > 100
    assert ours <= BRUTE_TOL, f"CS flank {ours * 1e3:.3f} µm from the brute-force boundary"
    assert theirs <= BRUTE_TOL, f"brute-force boundary {theirs * 1e3:.3f} µm from the CS flank"
    worst_inside = 0.0
    for piece in env.pieces:
        inside = shapely.contains_xy(region, piece.points[:, 0], piece.points[:, 1])
        if piece.cls in (CONJUGATE, TIP_PATH):
            d = boundary_distance(piece.points, region)
            assert d.max() <= BRUTE_TOL
            worst_inside = max(worst_inside, float(np.max(d * inside)))
        elif piece.depth_mm > 0.02:  # deep enough to be seen at this resolution
            s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(piece.points, axis=0).T))])
            mid = piece.points[np.argmin(np.abs(s - s[-1] / 2))]
            assert shapely.contains_xy(region, *mid), f"{piece.source} piece classified interfering is outside"
    # the brute region lies inside the true one, up to the outline's chord sag
    assert worst_inside <= SAG_TOL
    return ours, theirs, worst_inside


# ----------------------------------------------------------------------------- the reference itself


def test_brute_force_reference(dcta, region_default):
    """The reference's own conventions: a turn by +a adds a to the polar angle (clockwise from
    +y), and the region of a symmetric tooth in a symmetric deformation is its own mirror image."""
    p = np.array([[0.3, 50.0], [-1.0, 49.0]])
    q = turn(p, 0.01)
    np.testing.assert_allclose(np.arctan2(q[:, 0], q[:, 1]), np.arctan2(p[:, 0], p[:, 1]) + 0.01, atol=1e-15)
    np.testing.assert_allclose(np.hypot(*q.T), np.hypot(*p.T), atol=1e-13)
    mirrored = shapely.transform(region_default, lambda c: c * [-1.0, 1.0])
    assert shapely.symmetric_difference(region_default, mirrored).area <= 1e-12
    assert region_default.geom_type == "Polygon" and not region_default.interiors
    with pytest.raises(ValueError, match="n_phi"):
        swept_region(dcta, _motion(0.5), cs_teeth=Z2, waves=U, n_phi=1)


# ----------------------------------------------------------------------------- rack → involute


def _inv(a):
    return np.tan(a) - a


@pytest.mark.parametrize("alpha_deg", [20.0, 25.0])
@pytest.mark.parametrize("r", [50.0, 20.0])
def test_rack_generates_involute(alpha_deg, r):
    """Textbook: a rack flank at pressure angle α, rolling on the pitch circle r, envelopes the
    involute of r_b = r cos α.

    Rack frame (RackMotion): x along the pitch line, y outward, origin on the pitch circle at
    φ = 0. The flank passes through the pitch-line point (s, 0) with direction
    d = (−sin α, cos α), i.e. at α to the rack's y axis. At φ = −s/r that point is the
    instant centre, so the envelope passes through the pitch circle at polar angle s/r; the
    flank leans toward −x going out, so the involute's polar angle falls with radius:
    θ = λ − inv a, λ = s/r + inv α. The contact point is the foot of the perpendicular from
    the instant centre (−rφ, 0): t = t_s + (rφ + s) sin α along the flank.
    """
    a = math.radians(alpha_deg)
    s, below, above = math.pi * M / 4, 0.6, 0.6
    d = np.array([-math.sin(a), math.cos(a)])
    curve = line_curve("right", [s, 0.0] - below * d, [s, 0.0] + above * d)
    roots, folds = trace_meshing_roots(curve, RackMotion(r), phi_range=(-0.2, 0.2), chord_tol_mm=1e-7)
    assert len(roots) == 1 and not folds  # one root per flank point, no folds
    rc = roots[0]
    assert rc.t.min() == 0.0 and rc.t.max() == pytest.approx(below + above, abs=1e-12)
    Q = rc.points
    R = np.hypot(*Q.T)
    rb = r * math.cos(a)
    alpha_R = np.arctan2(np.sqrt(R**2 - rb**2), rb)  # arccos(r_b/R), well conditioned
    theta = np.arctan2(Q[:, 0], Q[:, 1])
    residual_mm = np.abs(theta + _inv(alpha_R) - (s / r + _inv(a))) * R
    assert residual_mm.max() <= 1e-10
    # the contact point is the foot of the perpendicular from the instant centre
    np.testing.assert_allclose(rc.t, below + (r * rc.phi + s) * math.sin(a), rtol=0, atol=1e-10)
    # and the chord tolerance holds: consecutive points are close enough that the involute
    # (curvature 1/(R sin a)) bulges < 1e-7 mm from each chord
    chord = np.hypot(*np.diff(Q, axis=0).T)
    rho = np.minimum(R[1:], R[:-1]) * np.sin(np.minimum(alpha_R[1:], alpha_R[:-1]))
    assert np.max(chord**2 / (8 * rho)) <= 1e-7 * 1.01


# ----------------------------------------------------------------------------- default DCTA, ω* = 1


def test_double_conjugation_and_false_flanks(dcta, env_default, region_default):
    """DESIGN trap 2: flank points with two roots; false flanks deeper than 0.3 mm."""
    motion = _motion(0.5)
    fold_t = np.array([f.t for f in env_default.folds if f.curve == "right"])
    t = np.linspace(0.01, dcta.length_mm - 0.01, 157)
    t = t[np.min(np.abs(t[:, None] - fold_t[None]), axis=1) > 2e-3]  # two roots near a fold merge
    # roots per t on the traced branches (all classes) of the right flank ...
    right = [p for p in env_default.pieces if p.source == "right"]
    traced = sum(np.sum(np.diff(np.sign(p.t[:, None] - t[None]), axis=0) != 0, axis=0) for p in right)
    # ... equal the sign changes of f on a fine φ grid, independently of the tracing
    brute, _ = _root_count(dcta, motion, t)
    np.testing.assert_array_equal(traced, brute)
    assert traced.max() == 2 and np.mean(traced == 2) > 0.9  # nearly every flank point meshes twice
    # the traced vertices are roots: |f| / |∇f| (distance to f = 0 in (t, φ))
    for p in right:
        f, ft, fp = _meshing(dcta, motion, p.t[1:-1], p.phi[1:-1])
        assert np.max(np.abs(f) / np.hypot(ft, fp)) <= 1e-12
    # false flanks: meshing roots from the flanks inside the swept region, the deepest by far
    # more than 0.3 mm (brute-force depth, which is a lower bound of the true depth)
    depth = []
    for p in env_default.pieces:
        if p.cls == INTERFERING and p.source in ("right", "left"):
            s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p.points, axis=0).T))])
            mid = p.points[np.argmin(np.abs(s - s[-1] / 2))]
            if shapely.contains_xy(region_default, *mid):
                depth.append(float(boundary_distance(mid[None], region_default)[0]))
    assert max(depth) > 0.3
    assert env_default.max_interference_mm > 0.3


def test_boundary_agrees_with_brute_force(env_default, region_default):
    """DESIGN trap 2: the classified boundary is the boundary of the swept region."""
    assert env_default.flank["chains"] == 1
    assert {p.source for p in env_default.pieces if p.cls == TIP_PATH} == {"right_tip", "left_tip"}
    ours, theirs, inside = _check_against_brute_force(env_default, region_default)
    # the chain closes the space: it runs from the CS tooth tip on one side (polar angle
    # +π/z2, half a CS pitch) over the space to the other
    chain = env_default.flank["boundary"]
    np.testing.assert_allclose(np.arctan2(chain[[0, -1], 0], chain[[0, -1], 1]), [math.pi / Z2, -math.pi / Z2], atol=1e-9)


def test_mirror_symmetry(dcta, env_default):
    """Geometry: symmetric tooth, ω even and υ odd ⇒ the CS space is its own mirror image."""
    full = _env(dcta, 0.5, symmetric=False)
    b, b_sym = full.flank["boundary"], env_default.flank["boundary"]
    assert b.shape == b_sym.shape
    np.testing.assert_allclose((b * [-1.0, 1.0])[::-1], b, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b, b_sym, rtol=0, atol=1e-9)
    for (lo_r, hi_r), (lo_l, hi_l) in zip(full.no_root["right"], full.no_root["left"]):
        assert lo_l == pytest.approx(lo_r, abs=1e-9) and hi_l == pytest.approx(hi_r, abs=1e-9)
    right = sorted((f.t, f.phi) for f in full.folds if f.curve == "right")
    left = sorted((f.t, -f.phi) for f in full.folds if f.curve == "left")
    np.testing.assert_allclose(left, right, rtol=0, atol=1e-9)


def _sag(a, b, q):
    ab = b - a
    s = np.clip(np.sum((q - a) * ab, -1) / np.sum(ab * ab, -1), 0, 1)
    return np.hypot(*(a + s[:, None] * ab - q).T)


def _project(tooth, motion, t, phi, side):
    """Newton steps along ∇f onto f = 0 (written here, not the package's)."""
    for _ in range(12):
        f, ft, fp = _meshing(tooth, motion, t, phi, side)
        g2 = ft * ft + fp * fp
        t, phi = np.clip(t - f * ft / g2, 0.0, tooth.length_mm), phi - f * fp / g2
    return t, phi


@pytest.mark.parametrize("chord_tol", [1e-6, 1e-7])
def test_chord_tolerance(dcta, env_default, chord_tol):
    """Each chord of a conjugate piece is within chord_tol of the exact envelope (the root
    curve projected back onto f = 0 at ¼, ½, ¾ of the chord), and so is each chord of the
    tip-corner paths (the corner's exact position)."""
    motion = _motion(0.5)
    env = env_default if chord_tol == 1e-6 else _env(dcta, 0.5, chord_tol_mm=chord_tol)
    worst = 0.0
    for p in env.pieces:
        if p.cls == CONJUGATE and p.source in ("right", "left"):
            side = 1 if p.source == "right" else -1
            for frac in (0.25, 0.5, 0.75):
                t, phi = _project(dcta, motion, p.t[:-1] + frac * np.diff(p.t), p.phi[:-1] + frac * np.diff(p.phi), side)
                assert np.max(np.abs(_meshing(dcta, motion, t, phi, side)[0])) <= 1e-13
                q = motion.pose(phi).to_cs(dcta.evaluate(t, side=side)[0])
                worst = max(worst, _sag(p.points[:-1], p.points[1:], q).max())
        elif p.cls == TIP_PATH:
            corner = dcta.tip_point * ([1.0, 1.0] if p.source == "right_tip" else [-1.0, 1.0])
            phi = 0.5 * (p.phi[1:] + p.phi[:-1])
            q = motion.pose(phi).to_cs(np.broadcast_to(corner, (phi.size, 2)))
            worst = max(worst, _sag(p.points[:-1], p.points[1:], q).max())
    assert 0 < worst <= chord_tol


# ----------------------------------------------------------------------------- ω* = 0.8: folds, no root


def test_no_root_zone_and_folds(dcta, env_08):
    """DESIGN trap 2: at ω* = 0.8 part of the flank never meshes, bounded by folds."""
    motion = _motion(0.4)
    assert env_08.no_root["right"] and env_08.folds
    folds = [f for f in env_08.folds if f.curve == "right"]
    worst = 0.0
    for fold in folds:
        f, ft, fp = _meshing(dcta, motion, fold.t, fold.phi)
        worst = max(worst, abs(f[0]), abs(fp[0]))
        assert abs(ft[0]) > 0.1  # a regular fold: f_t ≠ 0, so t is extremal along the branch
        # the fold's point is the tooth point placed at its φ
        q = motion.pose([fold.phi]).to_cs(dcta.evaluate([fold.t])[0])[0]
        np.testing.assert_allclose(fold.point, q, rtol=0, atol=1e-12)
        # two roots on one side of the fold, none on the other (a fine local φ grid)
        phi = fold.phi + np.linspace(-0.05, 0.05, 20001)
        a, _ = motion.pose(phi).meshing_coefficients()
        counts = []
        for dt in (-1e-4, 1e-4):
            p, dp, _ = dcta.evaluate(np.array([fold.t + dt]))
            F = a @ np.array([np.sum(p * dp), dp[0, 1], dp[0, 0]])
            counts.append(int(np.sum(np.sign(F[1:]) * np.sign(F[:-1]) < 0)))
        assert sorted(counts) == [0, 2]
    assert worst <= 1e-10
    # independently: between the folds f(t, ·) has no zero over the whole pass, outside it has two
    lo, hi = sorted(f.t for f in folds)
    inside = np.linspace(lo, hi, 9)[1:-1]
    n, fmin = _root_count(dcta, motion, inside)
    assert np.all(n == 0) and np.all(fmin > 1e-6)
    n, _ = _root_count(dcta, motion, np.array([lo - 0.05, hi + 0.05]))
    assert np.all(n == 2)
    # the reported zone is this one: its ends are the folds
    ((r_lo, r_hi),) = env_08.no_root["right"]
    assert abs(r_lo - lo) < 1e-8 and abs(r_hi - hi) < 1e-8


@pytest.mark.parametrize("w0", [0.4, 0.5])
def test_no_root_ends_are_the_folds(dcta, w0):
    env = _env(dcta, w0)
    fold_t = np.array([f.t for f in env.folds if f.curve == "right"])
    ends = [e for iv in env.no_root["right"] for e in iv if 0.0 < e < dcta.length_mm]
    assert ends
    for e in ends:
        assert np.min(np.abs(fold_t - e)) <= 1e-8
    # physics: no flank point in a no-root interval has a root
    for lo, hi in env.no_root["right"]:
        n, _ = _root_count(dcta, _motion(w0), np.array([lo + 1e-7, hi - 1e-7]), n=200001)
        assert np.all(n == 0)


def test_interference_depth_is_the_depth_in_the_swept_region(env_default, region_default):
    """max_interference_mm is the depth of the deepest false flank where the CS has material
    (above the radius where neighbouring spaces meet): the brute-force region's boundary
    distance of those vertices (a lower bound within ~1 µm)."""
    pts = np.vstack([p.points for p in env_default.pieces if p.cls == INTERFERING])
    chain = env_default.flank["boundary"]
    r_meet = max(np.hypot(*chain[0]), np.hypot(*chain[-1]))
    pts = pts[np.hypot(pts[:, 0], pts[:, 1]) >= r_meet]  # where the CS can have material
    brute = float(np.max(boundary_distance(pts[::3], region_default)))
    assert 0.97 * brute - 2e-3 <= env_default.max_interference_mm <= brute + 2e-3, (env_default.max_interference_mm, brute)
    # DESIGN trap 2: "up to 0.5 mm inside for a standard DCTA tooth" — here deeper still
    assert env_default.max_interference_mm > 0.3


# ----------------------------------------------------------------------------- involute FS tooth


def test_involute_flank_is_only_partly_conjugate():
    """An involute flank is conjugate to a rack/gear in rigid rotation, not to the harmonic
    drive's motion: only its upper part envelopes the CS flank; the rest is a false flank,
    and the tip corner's path closes the space with a kink (branch-switch ridge)."""
    tooth = involute_tooth(**GEAR)
    env = _env(tooth, 0.5)
    conj = [p for p in env.pieces if p.source == "right" and p.cls == CONJUGATE]
    assert conj
    t_lo, t_hi = min(p.t.min() for p in conj), max(p.t.max() for p in conj)
    assert 0.1 < t_lo and t_lo < t_hi <= tooth.length_mm  # the lower flank never bounds the space
    assert any(p.source == "right" and p.cls == INTERFERING for p in env.pieces)
    _check_against_brute_force(env, _region(tooth, 0.5))
    ridge_pts = np.array([r.point for r in env.ridges])
    assert len(ridge_pts) == 2 and all(r.kink_deg > 1.0 for r in env.ridges)
    np.testing.assert_allclose(ridge_pts[0] * [-1, 1], ridge_pts[1], atol=1e-9)  # a mirrored pair


# ----------------------------------------------------------------------------- failures are loud


def test_tooth_that_never_meshes_on_its_flanks(dcta):
    """w0 = 1e-4 mm: the flanks have no root at all; the tip corners sweep the space (a
    ring of radius ≈ r_m + y_a). Not an error: the result says so and is still right."""
    env = _env(dcta, 1e-4)
    for side in ("right", "left"):
        ((lo, hi),) = env.no_root[side]
        assert lo == 0.0 and hi == pytest.approx(dcta.length_mm, abs=1e-12)
    n, _ = _root_count(dcta, _motion(1e-4), np.linspace(0, dcta.length_mm, 7))
    assert np.all(n == 0)
    assert not [p for p in env.pieces if p.source in ("right", "left")]
    assert {p.source for p in env.pieces if p.cls != INTERFERING} <= {"right_tip", "left_tip", "top"}
    _check_against_brute_force(env, _region(dcta, 1e-4))
    r = np.hypot(*np.asarray(env.flank["boundary"]).T)
    tip_r = math.hypot(*(dcta.tip_point + [0.0, RM]))
    assert np.all(np.abs(r - tip_r) < 2e-4)


def test_no_root_anywhere_is_a_named_error(dcta):
    """Without a top land (flanks only) and a tiny deflection nothing meshes: EnvelopeError."""
    curves, corners, shape = tooth_curves(dcta)
    flanks = [c for c in curves if c.name in ("right", "left")]
    with pytest.raises(EnvelopeError, match="never meshes"):
        solve_envelope(flanks, corners, _motion(1e-4), shape, phi_range=PASS, neighbour_angle=2 * math.pi / Z2)


def test_flank_not_monotone_in_x_is_a_named_error():
    # a vertical flank line (pressure angle 0): x does not decrease toward the tip
    with pytest.raises(EnvelopeError, match="tooth") as info:
        _env(dcta_tooth(**GEAR, pressure_angle_deg=0.0), 0.5)
    # it says where the flank widens and which gear-set fields to change (issue 26 item 4)
    text = str(info.value)
    assert isinstance(info.value, RuntimeError) and "widens toward the tip" in text
    assert "tooth.pressure_angle_deg" in text

    # an undercut flank: a half circle bulging outward (x rises, then falls, toward the tip)
    def bulge(t):
        t = np.atleast_1d(t)
        ang = -math.pi / 2 + t / 0.3
        u = np.stack([np.cos(ang), np.sin(ang)], -1)
        return [0.4, 1.05] + 0.3 * u, np.stack([-u[:, 1], u[:, 0]], -1), -u / 0.3

    with pytest.raises(EnvelopeError, match="tooth"):
        ToothShape.from_flank(Curve("right", 0.3 * math.pi, bulge), neutral_radius_mm=RM, teeth=Z1)


def test_unresolvable_bridge_is_a_named_convergence_error(dcta):
    """If no grid separates the root curves, the trace says where instead of returning garbage:
    with no doublings allowed, the coarse grid that bridges the default set's facing folds
    (t ≈ 0.695 / 0.723 mm at φ ≈ 0.17 rad) must fail loudly."""
    from profilegen.profile.envelope import tooth_curves, trace_meshing_roots
    from profilegen.errors import ConvergenceError

    right = tooth_curves(dcta)[0][0]
    with pytest.raises(ConvergenceError, match=r"right flank: the meshing roots near t = 0\.[67]"):
        trace_meshing_roots(right, _motion(0.5), phi_range=(-math.pi / 2, math.pi / 2), n_t=48, n_phi=121, max_doublings=0)
