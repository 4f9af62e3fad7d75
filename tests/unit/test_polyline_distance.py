"""PolylineDistance: the exact distance to an open polyline, the same numbers as the minimum over
every segment (GEOS's point-to-segment formula), whichever of its nearest-point searches decides."""

import numpy as np

from profilegen.profile.gearform import PolylineDistance, _segment_distance


def _brute(line: np.ndarray, pts: np.ndarray) -> np.ndarray:
    return _segment_distance(pts[:, None, :], line[None, :-1], line[None, 1:]).min(axis=1)


def test_distance_is_the_minimum_over_every_segment():
    rng = np.random.default_rng(5)
    # a dense, uneven curve with a tight bend (unequal segments: the tree's spacing is their median)
    t = np.sort(rng.uniform(0.0, 1.5 * np.pi, 600))
    line = np.column_stack([np.cos(t), 0.3 * np.sin(t)])
    base = line[rng.integers(0, len(line), 3000)]
    # near the curve (the 4 nearest tree points decide), between (the k nearest) and far (every segment)
    scale = np.exp(rng.uniform(np.log(1e-9), np.log(0.5), (3000, 1)))
    pts = base + rng.normal(size=(3000, 2)) * scale
    got = PolylineDistance(line).distance(pts)
    assert np.array_equal(got, _brute(line, pts))


def test_distance_where_the_nearest_tree_points_are_on_other_segments():
    # a straight run of 0.1 mm segments (the tree's spacing) and, looping back over it, a fine arc of
    # radius 0.021 mm about a point 0.02 mm above the run, 0.025 mm from its nearest tree points: every
    # nearest tree point lies on the arc, the foot on the run
    p = np.array([0.025, 0.02])
    run = np.column_stack([np.linspace(-1.0, 1.0, 21), np.zeros(21)])
    a = np.radians(np.linspace(150.0, 30.0, 13))
    arc = p + 0.021 * np.column_stack([np.cos(a), np.sin(a)])
    line = np.vstack([run, [[1.0, 1.0], [-1.0, 1.0]], arc])
    pts = p + np.array([[0.0, 0.0], [1e-4, 0.0], [-1e-4, 1e-4], [3e-4, -2e-4]])
    got = PolylineDistance(line).distance(pts)
    assert np.array_equal(got, _brute(line, pts))
    assert np.allclose(got, pts[:, 1], rtol=0, atol=1e-15)  # the foot on the run y = 0


def test_short_polylines_and_no_points():
    line = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    pts = np.array([[0.5, -0.25], [2.0, 0.5], [1.0, 2.0], [0.0, 0.0]])
    assert np.array_equal(PolylineDistance(line).distance(pts), [0.25, 1.0, 1.0, 0.0])
    assert PolylineDistance(line).distance(np.empty((0, 2))).shape == (0,)
