"""Exact distances and nearest points of lines, arcs and chains (profilegen.geometry.contour)."""

import math

import numpy as np
import shapely

from profilegen.geometry.contour import Arc, Chain, Line


def test_nearest_points_of_a_chain_against_a_dense_polyline():
    """The exact foot and distance of an arc–line–arc chain, against shapely on the chain
    sampled at 1e-9 mm chord (its sag bounds the difference)."""
    a1 = Arc(np.array([0.0, 0.0]), 2.0, math.pi / 2, -math.pi / 3)
    line = Line(a1.end, a1.end + np.array([0.5, -1.0]))
    a2 = Arc(np.array([5.0, 5.0]), 1.0, 0.0, 1.0)  # a separate arc, 0 → 1 rad
    chain = Chain((a1, line))
    rng = np.random.default_rng(3)
    pts = rng.uniform([-1.0, -1.0], [3.0, 3.0], (400, 2))
    dist, foot = chain.nearest(pts)
    dense = shapely.LineString(chain.sample(1e-9))
    ref = shapely.distance(shapely.points(pts), dense)
    np.testing.assert_allclose(dist, ref, atol=1e-8)
    np.testing.assert_allclose(np.hypot(*(pts - foot).T), dist, atol=1e-12)
    np.testing.assert_allclose(shapely.distance(shapely.points(foot), dense), 0.0, atol=1e-8)
    np.testing.assert_allclose(chain.distance(pts), dist, atol=0.0)
    # a point facing the arc lands on its circle; one beyond its end lands on the end
    d, f = a2.nearest(np.array([[8.0, 5.0], [3.0, 4.0]]))
    np.testing.assert_allclose(f[0], a2.centre + [1.0, 0.0], atol=1e-15)
    assert d[0] == 2.0
    ends = np.hypot(*(np.array([3.0, 4.0]) - np.stack([a2.start, a2.end])).T)
    np.testing.assert_allclose(f[1], [a2.start, a2.end][int(np.argmin(ends))], atol=1e-15)
    assert d[1] == ends.min()
