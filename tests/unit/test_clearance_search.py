"""The clearance map's batched candidate search (gearform._nearest_pairs) against the
brute force it replaces: every surface point's nearest CS point, stably sorted by distance."""

import numpy as np
from scipy.spatial import cKDTree

from profilegen.profile.gearform import _nearest_pairs


def _brute(tree, surface, c, s, origin, need):
    out = []
    for ci, si, oi in zip(c, s, origin):
        placed = np.stack([surface[:, 0] * ci + surface[:, 1] * si, surface[:, 1] * ci - surface[:, 0] * si], -1) + oi
        dist, idx = tree.query(placed)
        out.append(idx[np.argsort(dist, kind="stable")][:need])
    return np.array(out)


def test_nearest_pairs_equal_the_sorted_query_of_every_surface_point():
    rng = np.random.default_rng(3)
    # a dense "CS" curve (arc + line, 1500 points) and a "tooth surface" (a parabola, 400 points)
    a = np.linspace(0.0, 1.2, 1000)
    cs = np.vstack([np.column_stack([2.0 * np.cos(a), 2.0 * np.sin(a)]),
                    np.column_stack([np.linspace(-0.5, 1.9, 500), np.full(500, -0.3)])])
    u = np.linspace(-0.6, 0.6, 400)
    surface = np.column_stack([u, 0.8 * u**2])
    # poses from touching (a surface point on a CS point) to far out (bound grown several times)
    angle = rng.uniform(-0.4, 0.4, 16)
    origin = rng.uniform(-1.0, 2.0, (16, 2))
    origin[0] = cs[500] - surface[350]
    angle[0] = 0.0
    c, s = np.cos(angle), np.sin(angle)
    tree = cKDTree(cs, leafsize=64, compact_nodes=False, balanced_tree=False)
    for need in (128, 5, 400, 500):
        got = _nearest_pairs(tree, surface, c, s, origin, need)
        assert np.array_equal(got, _brute(cKDTree(cs), surface, c, s, origin, need)), need


def test_clearance_map_takes_the_candidates_of_the_pose_by_pose_rule(default_set):
    """The whole map against the rule it implements, pose by pose: every surface point's
    nearest CS point, the 128 nearest pairs (stable), their first 32 distinct CS points and
    4 neighbours either side, the least signed exact distance — bit for bit."""
    from profilegen.profile.gearform import circular_spline_form, clearance_map
    from tests.oracles.clearance_rule import pose_by_pose_clearance

    tooth, motion, env = default_set
    form = circular_spline_form(env, cs_teeth=202, tip_clearance_mm=0.125, root_clearance_mm=0.125)
    cmap = clearance_map(form, tooth, motion, phi_range=env.phi_range, samples=41)
    np.testing.assert_array_equal(cmap.clearance_mm, pose_by_pose_clearance(form, tooth, motion, cmap.phi))
