"""Influence coefficients of the loaded tooth contact (profilegen.contact.compliance).

Physics checks: Maxwell–Betti symmetry and positive definiteness; the pinched ring
(Roark, *Formulas for Stress and Strain*, 7th ed., Table 9.2 case 1: a thin ring under two
equal and opposite radial forces P, the diameter normal to the load line grows by
(2/π − 1/2)·P R³/(E I)); exact 1/b and 1/E scaling; no ball pulls after the ball
iteration; a single CS tooth against a cantilever (Timoshenko) beam.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import shapely

import profilegen as pg
from profilegen.contact import ContactInput
from profilegen.contact.compliance import ComplianceError, ContactCompliance, _half_ring_flex
from profilegen.geometry.kinematics import turn
from profilegen.rim.toothed import ring_sector_mesh


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_contact_compliance")


@pytest.fixture(scope="module")
def inputs(default_sketch):
    """What the contact reads of the default set's sketch design (built as the pipeline does)."""
    return ContactInput.from_design(default_sketch)


def make_points(inputs, teeth, stations=5):
    """Right-flank stations of FS teeth ``teeth`` placed by the kinematics (WG at ψ = 0, tooth
    i in CS space i), their outward normals, and the nearest points of the fitted CS flank."""
    g = inputs.gearset.gear
    tooth, motion = inputs.tooth, inputs.motion
    t = np.linspace(0.45 * tooth.length_mm, tooth.length_mm * 0.98, stations)
    local, dp, _ = tooth.evaluate(t)
    n_local = np.column_stack([dp[:, 1], -dp[:, 0]])
    line = shapely.LineString(inputs.cs_space.sample(1e-5))
    fs, nn, idx, cs = [], [], [], []
    for i in teeth:
        pose = motion.pose(np.full(stations, 2 * math.pi * i / g.flexspline_teeth))
        placed = pose.to_cs(local)
        c, s = np.cos(pose.angle), np.sin(pose.angle)
        normal = np.column_stack([n_local[:, 0] * c + n_local[:, 1] * s, n_local[:, 1] * c - n_local[:, 0] * s])
        foot = np.array([line.interpolate(line.project(shapely.Point(*p))).coords[0] for p in placed])
        angle = 2 * math.pi * i / g.circular_spline_teeth
        fs.append(turn(placed, angle))
        nn.append(turn(normal, angle))
        cs.append(turn(foot, angle))
        idx.append(np.full(stations, i))
    return np.vstack(fs), np.vstack(nn), np.concatenate(idx), np.vstack(cs)


@pytest.fixture(scope="module")
def points(inputs):
    return make_points(inputs, teeth=range(2, 14, 2))


@pytest.fixture(scope="module")
def compliance(inputs, points):
    return ContactCompliance.build(inputs, *points)


def test_symmetric_positive_definite_and_finite(compliance):
    s = compliance.matrix_mm_per_n
    assert np.all(np.isfinite(s))
    assert np.max(np.abs(s - s.T)) <= 1e-10 * np.max(np.abs(s))
    eig = np.linalg.eigvalsh(s)
    assert eig.min() > 0.0
    # the order of seed 000's S·r (its S is divided by r ≈ 50 mm and quoted as ~1e-7)
    d = np.diag(s)
    assert 2e-6 < d.min() and d.max() < 2e-4
    # the FS part dominates the CS sector (held at its outer radius); the CS ring's ovalisation is
    # added to the CS block and is its only part that couples the two zones' far-apart teeth
    ring = compliance.cs_ring_mm_per_n
    sector = compliance.cs_matrix_mm_per_n - ring
    assert np.all(np.diag(sector) < np.diag(compliance.fs_matrix_mm_per_n))
    assert np.all(np.diag(ring) > 0.0) and np.linalg.eigvalsh(ring).min() > -1e-12 * np.abs(ring).max()


def test_rigid_rotation_removed_without_any_ball(compliance):
    """The bore's mean rotation alone holds the point-symmetric ring: S stays finite and
    positive definite with every ball dropped (and is larger: the balls stiffen the rim)."""
    free = compliance.with_balls(np.zeros(compliance.ball_angle_rad.size, bool))
    assert np.linalg.eigvalsh(free.matrix_mm_per_n).min() > 0.0
    assert np.all(np.diag(free.matrix_mm_per_n) >= np.diag(compliance.matrix_mm_per_n) * (1 - 1e-12))


def test_scales_as_one_over_face_width_and_modulus(inputs, points, compliance):
    wide = ContactCompliance.build(inputs, *points, face_width_mm=2 * compliance.face_width_mm)
    np.testing.assert_allclose(wide.matrix_mm_per_n, compliance.matrix_mm_per_n / 2, rtol=1e-9)
    gs = inputs.gearset
    stiff = dataclasses.replace(inputs, gearset=gs.with_values(
        {"material.youngs_modulus_mpa": 2 * gs.material.youngs_modulus_mpa}))
    hard = ContactCompliance.build(stiff, *points)
    np.testing.assert_allclose(hard.matrix_mm_per_n, compliance.matrix_mm_per_n / 2, rtol=1e-7)


def test_no_ball_pulls_after_settling(compliance):
    """Seed 000 steps 4–6 with the contact forces held: tensile balls are dropped one at a
    time until every remaining reaction is compressive and no dropped ball is pressed."""
    forces = np.full(compliance.count, 100.0)
    first = compliance.ball_reactions(forces)
    assert first.min() < 0.0  # some ball pulls with all of them held
    settled = compliance.settle_balls(forces)
    react = settled.ball_reactions(forces)
    assert np.all(react[settled.ball_active] >= 0.0)
    assert np.all(react[~settled.ball_active] == 0.0)
    assert np.all(settled.ball_gaps_mm(forces)[~settled.ball_active] >= -1e-15)
    assert 0 < settled.ball_active.sum() < settled.ball_active.size


def test_pinched_flat_ring_against_ring_theory():
    """The half model with its point-symmetric tie is the whole ring under the load and its
    image: a radial force P at θ = 0 is the pinched ring. Reciprocity: the radial
    displacement at θ = 90° under P equals the load point's response to a force there."""
    r_in, r_out, e, nu = 48.5, 49.4, 209000.0, 0.3
    pitches, pitch = 100, math.pi / 100
    ring = ring_sector_mesh(pitch, -0.5 * pitch, [None] * pitches, [4] * pitches, mapped_radius_mm=0.5 * (r_in + r_out),
                            polar_radius_mm=r_in, mapped_layers=2, polar_layers=2, mapped_outside=True,
                            flat_radius_mm=r_out)
    theta = np.array([0.0, 0.5 * math.pi])
    pts = r_out * np.column_stack([np.sin(theta), np.cos(theta)])
    inward = -np.column_stack([np.sin(theta), np.cos(theta)])
    flex, *_ = _half_ring_flex(ring, e, nu, r_in, pts, inward, np.zeros(0), tol_mm=1e-6)
    assert abs(flex[0, 1] - flex[1, 0]) <= 1e-12 * abs(flex[0, 1])
    radius, thick = 0.5 * (r_in + r_out), r_out - r_in
    ei = e * thick**3 / 12.0  # per mm of width
    growth = (2.0 / math.pi - 0.5) * radius**3 / ei  # diameter normal to the load line, per unit P
    # an inward unit load at 0° moves the 90° point outward by growth/2: −(inward·u) there
    assert -flex[1, 0] == pytest.approx(0.5 * growth, rel=0.01)


def test_cs_tooth_against_cantilever_beam(inputs, compliance):
    """A CS tooth is a short cantilever on a stiff, fixed ring: its compliance under a load
    near the tip is within a factor of 3 of bending + shear of a uniform beam as long as
    the load's height above the root circle, as thick as the tooth at mid-height (a
    cantilever ignores the root's rotation, which makes real teeth softer)."""
    space = inputs.cs_space
    z2 = inputs.gearset.gear.circular_spline_teeth
    # the sector alone (the ring's ovalisation is a global mode, not the tooth's bending), mm²/N per mm of face
    cs = (compliance.cs_matrix_mm_per_n - compliance.cs_ring_mm_per_n) * compliance.face_width_mm
    # the CS point farthest from the root circle (nearest the CS tip) of the first tooth
    _, _, _, cs_pts = make_points(inputs, teeth=[2])
    k = int(np.argmin(np.hypot(*cs_pts.T)))
    r_root = float(np.max(np.hypot(*space.sample(1e-4).T)))
    h = r_root - float(np.hypot(*cs_pts[k]))
    sample = space.sample(1e-5)
    r_mid = r_root - 0.5 * h
    ang = np.arctan2(sample[:, 0], sample[:, 1])
    near = np.abs(np.hypot(*sample.T) - r_mid) < 0.02
    space_width = r_mid * (ang[near].max() - ang[near].min())
    thick = r_mid * 2 * math.pi / z2 - space_width
    e, nu = inputs.gearset.material.youngs_modulus_mpa, inputs.gearset.material.poisson_ratio
    g_mod = e / (2 * (1 + nu))
    beam = h**3 / (3 * e * thick**3 / 12) + h / (5 / 6 * g_mod * thick)
    assert 0.33 < cs[k, k] / beam < 3.0


@pytest.mark.parametrize("change, name", [
    ("shape", "fs_normals"), ("nan", "fs_points"), ("off", "fs_points"), ("width", "face_width_mm"),
    ("index", "fs_tooth_index"), ("cs_off", "cs_points"), ("balls", "ball_count")])
def test_bad_input_names_the_parameter(inputs, points, change, name):
    fs, nn, idx, cs = (np.array(a) for a in points)
    kw = {}
    if change == "shape":
        nn = nn[:-1]
    elif change == "nan":
        fs[3, 0] = np.nan
    elif change == "off":
        fs[3] += 0.05 * nn[3]
    elif change == "width":
        kw["face_width_mm"] = 0.0
    elif change == "index":
        idx = idx[:-1]
    elif change == "cs_off":
        cs[2] -= 0.05 * nn[2]
    elif change == "balls":
        kw["ball_count"] = 1
    with pytest.raises(ComplianceError, match=name):
        ContactCompliance.build(inputs, fs, nn, idx, cs, **kw)
    assert issubclass(ComplianceError, ValueError)


# --------------------------------------------------------------------------- the outer race


@pytest.fixture(scope="module")
def race_series(inputs, points):
    """S with the bearing's outer race 0 (balls on the bore: the old model), 0.5, 1.5, 2.5, 3.5 mm."""
    return {t: ContactCompliance.build(inputs, *points, race_thickness_mm=t, race_interface="bonded")
            for t in (0.0, 0.5, 1.5, 2.5, 3.5)}


def test_race_zero_is_the_old_model(inputs, points, race_series):
    """race_thickness_mm = 0 is the model without the race: the balls on the bore, and no
    difference between a sliding and a bonded race of zero thickness."""
    s = race_series[0.0].matrix_mm_per_n
    assert s.shape == (30, 30)
    assert race_series[0.0].mesh["fs"].get("race_thickness_mm") is None
    sliding = ContactCompliance.build(inputs, *points, race_thickness_mm=0.0, race_interface="sliding")
    assert np.array_equal(sliding.matrix_mm_per_n, s)


@pytest.mark.parametrize("gauged", [False, True])
def test_banded_flexibility_matches_a_sparse_lu(gauged):
    """The blocked band Cholesky (loads last, zero rows skipped, the gauge projection applied
    after the solve) against scipy's sparse LU on Pᵀ Y, for a strip stiffness (a 5 × 400
    grid Laplacian plus a small shift, shuffled into a band order) and sparse loads."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as sla

    from profilegen.contact.compliance import _BandedFlex, _loads_last

    rng = np.random.default_rng(7)
    nx, ny = 400, 5
    lap = lambda n: sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    k = (sp.kron(lap(nx), sp.eye(ny)) + sp.kron(sp.eye(nx), lap(ny)) + 1e-3 * sp.eye(nx * ny)).tocsr()
    n = k.shape[0]
    loaded = rng.choice(np.arange(int(0.6 * n), n), size=12, replace=False)
    y = sp.csr_matrix((rng.normal(size=12), (loaded, np.arange(12))), shape=(n, 12))
    order = _loads_last(np.arange(n)[::-1].copy(), loaded)  # the band order, loads last
    assert np.array_equal(order, np.arange(n))
    factor = _BandedFlex(k, order, "test strip", block=16)
    if gauged:
        c, rot = rng.normal(size=n), rng.normal(size=n)
        flex = factor.flexibility(y, gauge=(c, rot))
        py = y.toarray() - np.outer(c, rot @ y.toarray()) / (c @ rot)
    else:
        flex = factor.flexibility(y)
        py = y.toarray()
    reference = py.T @ sla.splu(k.tocsc()).solve(py)
    np.testing.assert_allclose(flex, reference, rtol=1e-10, atol=1e-12 * np.abs(reference).max())


@pytest.mark.parametrize("gauged", [False, True])
def test_banded_flexibility_matches_a_dense_inverse(gauged):
    """The blocked band Cholesky with its default block (corner-only coupling blocks, the
    columns taken in the order their loads start, a column that is never loaded) against
    the plain dense Yᵀ K⁻¹ Y (numpy solve), to 1e-9 of the largest entry: a strip stiffness
    whose band is no divisor of n, loads scattered over the last 70 % of the rows in a
    shuffled column order."""
    import scipy.sparse as sp

    from profilegen.contact.compliance import _BandedFlex

    rng = np.random.default_rng(11)
    nx, ny = 150, 7
    lap = lambda n: sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    k = (sp.kron(lap(nx), sp.eye(ny)) + sp.kron(sp.eye(nx), lap(ny)) + 1e-3 * sp.eye(nx * ny)).tocsr()
    n = k.shape[0]
    m = 25
    loaded = rng.choice(np.arange(int(0.3 * n), n), size=2 * (m - 1), replace=False)
    cols = np.concatenate([np.arange(m - 1)] * 2)  # the last column stays empty
    y = sp.csr_matrix((rng.normal(size=loaded.size), (loaded, cols)), shape=(n, m))
    factor = _BandedFlex(k, np.arange(n), "test strip")
    assert factor.band == ny and n % len(factor.starts) != 0
    assert factor.diag[0].shape[0] > factor.band  # the default block is wider than the band
    dense = k.toarray()
    py = y.toarray()
    if gauged:
        c, rot = rng.normal(size=n), rng.normal(size=n)
        flex = factor.flexibility(y, gauge=(c, rot))
        py = py - np.outer(c, rot @ py) / (c @ rot)
    else:
        flex = factor.flexibility(y)
    reference = py.T @ np.linalg.solve(dense, py)
    assert np.max(np.abs(flex - reference)) <= 1e-9 * np.max(np.abs(reference))
    assert np.array_equal(flex, flex.T)
    assert np.all(flex[-1] == 0.0) and np.all(flex[:, -1] == 0.0)
    np.testing.assert_allclose(factor.forward(py) [:, :3].T @ factor.forward(py)[:, :3],
                               py[:, :3].T @ np.linalg.solve(dense, py[:, :3]), rtol=1e-9,
                               atol=1e-12 * np.abs(reference).max())


@pytest.mark.parametrize("case", ["rigid mode", "indefinite", "not finite"])
def test_banded_flexibility_refuses_a_singular_matrix(case):
    """A stiffness with a free dof (an exactly zero pivot), a negative one or a NaN entry
    is refused with a ConvergenceError that names the body, never a silent result."""
    import scipy.sparse as sp

    from profilegen.contact.compliance import _BandedFlex
    from profilegen.errors import ConvergenceError

    n = 300
    k = sp.diags([-np.ones(n - 1), 2.5 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1]).tolil()
    if case == "rigid mode":  # dof 200 carries no stiffness at all
        k[200, :] = 0.0
        k[:, 200] = 0.0
    elif case == "indefinite":
        k[250, 250] = -1.0
    else:
        k[120, 121] = k[121, 120] = np.nan
    with pytest.raises(ConvergenceError, match="test body"):
        _BandedFlex(k.tocsr(), np.arange(n), "test body")


def test_half_ring_flexibility_matches_a_dense_solve(monkeypatch):
    """The FE path of the FS (point-symmetric tie, bore gauge, ball supports on the inner
    surface) with the band Cholesky against the same path with a plain dense solve put in
    its place: the same flexibility to 1e-9 of its largest entry, for a small flat ring."""
    import profilegen.contact.compliance as cc

    # a thick ring (t / R ≈ 0.2): a thin one's flexibility is so ill-conditioned that any two
    # correct solvers differ at ~1e-8 (the FS's 0.9 mm rim on R ≈ 49 mm: 4e-8 here)
    r_in, r_out, e, nu = 40.0, 49.4, 209000.0, 0.3
    pitches, pitch = 12, math.pi / 12
    ring = ring_sector_mesh(pitch, -0.5 * pitch, [None] * pitches, [4] * pitches, mapped_radius_mm=0.5 * (r_in + r_out),
                            polar_radius_mm=r_in, mapped_layers=2, polar_layers=2, mapped_outside=True,
                            flat_radius_mm=r_out)
    theta = np.radians([0.0, 20.0, 50.0, 90.0, 150.0])
    pts = r_out * np.column_stack([np.sin(theta), np.cos(theta)])
    tilt = theta + 0.3
    directions = -np.column_stack([np.sin(tilt), np.cos(tilt)])
    balls = np.radians([-30.0, 0.0, 30.0])
    fast, dof, band, _ = _half_ring_flex(ring, e, nu, r_in, pts, directions, balls, tol_mm=1e-6)

    class Dense:
        def __init__(self, matrix, order, where, block=None):
            self.k = matrix.toarray()
            self.band = 0

        def flexibility(self, loads, gauge=None):
            y = loads.toarray()
            if gauge is not None:
                c, rot = gauge
                y = y - np.outer(c, rot @ y) / (c @ rot)
            return y.T @ np.linalg.solve(self.k, y)

    monkeypatch.setattr(cc, "_BandedFlex", Dense)
    slow, dof_slow, _, _ = _half_ring_flex(ring, e, nu, r_in, pts, directions, balls, tol_mm=1e-6)
    assert dof == dof_slow and band > 0 and fast.shape == (8, 8)
    assert np.max(np.abs(fast - slow)) <= 1e-9 * np.max(np.abs(slow))
    assert np.array_equal(fast, fast.T)
    assert np.linalg.eigvalsh(fast).min() > 0.0


@pytest.mark.parametrize("joint", ["bonded", "sliding"])
def test_race_symmetric_positive_definite(inputs, points, race_series, joint):
    c = (race_series[2.5] if joint == "bonded"
         else ContactCompliance.build(inputs, *points, race_thickness_mm=2.5, race_interface="sliding"))
    s = c.matrix_mm_per_n
    assert np.all(np.isfinite(s))
    assert np.max(np.abs(s - s.T)) <= 1e-10 * np.max(np.abs(s))
    assert np.linalg.eigvalsh(s).min() > 0.0
    free = c.with_balls(np.zeros(c.ball_angle_rad.size, bool)).matrix_mm_per_n
    assert np.linalg.eigvalsh(free).min() > 0.0
    assert c.mesh["fs"]["race_thickness_mm"] == 2.5 and c.mesh["fs"]["race_interface"] == joint
    # the bonded race is stiffer than the sliding one (composite bending)
    if joint == "sliding":
        assert np.all(np.diag(race_series[2.5].matrix_mm_per_n) < np.diag(s))


def test_race_stiffens_monotonically(race_series):
    """A thicker race: every S_kk falls (balls within the wrap held); with every ball dropped
    (rim + race alone, the same supports) S falls in the Loewner order. With balls held the
    Loewner order need not hold: the balls move inward with the race's inner surface."""
    thick = sorted(race_series)
    for a, b in zip(thick, thick[1:]):
        sa, sb = race_series[a], race_series[b]
        assert np.all(np.diag(sb.matrix_mm_per_n) < np.diag(sa.matrix_mm_per_n)), (a, b)
        fa = sa.with_balls(np.zeros(sa.ball_angle_rad.size, bool)).matrix_mm_per_n
        fb = sb.with_balls(np.zeros(sb.ball_angle_rad.size, bool)).matrix_mm_per_n
        assert np.linalg.eigvalsh(fa - fb).min() > -1e-9 * np.abs(fa).max(), (a, b)
    d0, d25 = (np.diag(race_series[t].matrix_mm_per_n).mean() for t in (0.0, 2.5))
    assert d25 < 0.2 * d0  # the race is the rim's main stiffness (bending ∝ t³)


@pytest.mark.parametrize("joint", ["bonded", "sliding"])
def test_race_on_flat_ring_against_ring_theory(joint):
    """A flat rim (0.9 mm) on a flat race (2.5 mm), pinched: bonded, they bend as one
    3.4 mm ring; sliding (joined radially only), their bending stiffnesses EI/R³ add."""
    r_race, r_bore, r_out, e, nu = 46.0, 48.5, 49.4, 209000.0, 0.3
    pitches, pitch = 100, math.pi / 100
    ring = ring_sector_mesh(pitch, -0.5 * pitch, [None] * pitches, [4] * pitches, mapped_radius_mm=r_bore,
                            polar_radius_mm=r_race, mapped_layers=2, polar_layers=2, mapped_outside=True,
                            flat_radius_mm=r_out)
    bore = np.flatnonzero(ring.j == 2)
    bore = bore[np.argsort(ring.s[bore])]
    theta = np.array([0.0, 0.5 * math.pi])
    pts = r_out * np.column_stack([np.sin(theta), np.cos(theta)])
    inward = -np.column_stack([np.sin(theta), np.cos(theta)])
    flex, *_ = _half_ring_flex(ring, e, nu, r_bore, pts, inward, np.zeros(0), tol_mm=1e-6, ball_radius_mm=r_race,
                               bore_nodes=bore, sliding_race_layers=2 if joint == "sliding" else None)
    assert abs(flex[0, 1] - flex[1, 0]) <= 1e-10 * abs(flex[0, 1])
    if joint == "bonded":
        stiff = e * (r_out - r_race) ** 3 / 12.0 / (0.5 * (r_out + r_race)) ** 3
    else:
        stiff = (e * (r_out - r_bore) ** 3 / 12.0 / (0.5 * (r_out + r_bore)) ** 3
                 + e * (r_bore - r_race) ** 3 / 12.0 / (0.5 * (r_bore + r_race)) ** 3)
    growth = (2.0 / math.pi - 0.5) / stiff
    assert -flex[1, 0] == pytest.approx(0.5 * growth, rel=0.02)


@pytest.mark.parametrize("kw", [{"race_thickness_mm": -1.0}, {"race_thickness_mm": float("nan")},
                                {"race_thickness_mm": "thick"}, {"race_thickness_mm": 30.0},
                                {"race_interface": "glued"}, {"mesh": {"race_layers": 0}}])
def test_bad_race_names_the_parameter(inputs, points, kw):
    name = next(iter(kw["mesh"])) if "mesh" in kw else next(iter(kw))
    with pytest.raises(ComplianceError, match=name):
        ContactCompliance.build(inputs, *points, **kw)


def test_unknown_mesh_key_is_named(inputs, points):
    with pytest.raises(ComplianceError, match="mesh: unknown key 'columns'"):
        ContactCompliance.build(inputs, *points, mesh={"columns": 3})


def test_cs_columns_grow_to_the_pieces_of_the_profile(inputs, points, compliance):
    """A CS profile fitted per branch has more pieces per space than the default column
    count (the verify scene: 17 > 16); the sector mesh takes one column per piece at least
    instead of failing. Forced here by asking for 2 columns: the matrix stays SPD and close
    to the default mesh's (same FS, coarser CS: the CS part is ~5 % of S)."""
    coarse = ContactCompliance.build(inputs, *points, mesh={"cs_per_pitch": 2})
    s = coarse.matrix_mm_per_n
    np.linalg.cholesky(s)
    d0, d1 = np.diag(compliance.matrix_mm_per_n), np.diag(s)
    assert np.max(np.abs(d1 - d0) / d0) < 0.1


# --------------------------------------------------------------------------- substructures


@pytest.fixture(scope="module")
def small_set():
    """A small gear set (z1 = 40, z2 = 42, the default set's tooth and rim otherwise): its
    sketch design's contact inputs and candidate points (3 stations per flank)."""
    from profilegen.contact.points import contact_points

    gs = pg.load_gearset(pg.default_gearset_path()).with_values(
        {"gear.flexspline_teeth": 40, "gear.circular_spline_teeth": 42})
    small = ContactInput.from_design(pg.design(gs, scene="sketch"))
    pts = contact_points(small, side=1, stations=3, max_gap_mm=0.12)
    return small, (pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm)


@pytest.mark.parametrize("kw", [{}, {"race_interface": "bonded"}, {"race_thickness_mm": 0.0},
                                {"toothed_teeth": "loaded", "margin_teeth": 1}],
                         ids=["sliding race", "bonded race", "no race", "flat unloaded pitches"])
def test_substructured_build_is_the_whole_mesh_assembly(small_set, kw):
    """The default build condenses one pitch of each kind onto its cuts and solves the cuts;
    the reference (substructure=False) assembles and factorises the whole FS half ring and CS
    sector. Static condensation is exact, so both are the same matrix up to rounding: S, its
    parts and the ball flexibilities to 1e-9 of their largest entries (seen: ≤ 1.1e-10), the
    same dof and mesh counts, on a coarse mesh of a small set (rotation invariance of the
    pitches, the periodic tie in turned frames, the gauge projection, two pitch kinds)."""
    small, pts = small_set
    model = {k: v for k, v in kw.items() if k.startswith("race_")}  # the race's model; the rest is the mesh's
    coarse = dict(per_pitch=14, tooth_layers=2, rim_layers=1, race_layers=1, cs_tooth_layers=2, cs_back_layers=1,
                  **{k: v for k, v in kw.items() if k not in model})
    fast = ContactCompliance.build(small, *pts, wrap_half_angle_rad=1.0, mesh=coarse, **model)
    whole = ContactCompliance.build(small, *pts, wrap_half_angle_rad=1.0, mesh=dict(substructure=False, **coarse),
                                    **model)
    assert "substructure" in fast.mesh["fs"] and "substructure" not in whole.mesh["fs"]
    for name in ("matrix_mm_per_n", "fs_matrix_mm_per_n", "cs_matrix_mm_per_n", "_flex_cc", "_flex_cb", "_flex_bb"):
        a, b = getattr(fast, name), getattr(whole, name)
        assert a.shape == b.shape and np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(b)), name
    assert fast.dof == whole.dof
    for body in ("fs", "cs"):
        for key in ("pitches", "toothed_pitches", "columns", "layers", "elements", "nodes", "dof"):
            assert fast.mesh[body][key] == whole.mesh[body][key], (body, key)
        assert fast.mesh[body]["min_jacobian"] == pytest.approx(whole.mesh[body]["min_jacobian"], rel=1e-9)
    if kw.get("toothed_teeth") == "loaded":
        assert 0 < fast.mesh["fs"]["toothed_pitches"] < fast.mesh["fs"]["pitches"]  # both pitch kinds
