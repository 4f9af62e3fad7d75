"""profilegen.profile.swept.boundary_distance: the nearest boundary segment from an STR tree is the
distance to the whole boundary (shapely.distance to ``region.boundary``, the plain definition)."""

import numpy as np
import pytest
import shapely

from profilegen.profile.swept import boundary_distance


@pytest.mark.parametrize("region", [
    shapely.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(1, 1), (2, 1), (2, 2), (1, 2)]]),  # a hole: two rings
    shapely.MultiPolygon([shapely.box(0, 0, 4, 4), shapely.Point(10, 0).buffer(1.0, 64)]),
])
def test_boundary_distance_is_the_distance_to_the_whole_boundary(region):
    points = np.random.default_rng(1).uniform(-2.0, 12.0, (400, 2))
    expected = shapely.distance(shapely.points(points), region.boundary)
    assert np.array_equal(boundary_distance(points, region), expected)
    assert boundary_distance([(1.5, 0.5)], region)[0] == pytest.approx(0.5)  # inside, nearest edge below
    assert boundary_distance(np.zeros((0, 2)), region).shape == (0,)
