"""Chain.nearest / Chain.distance (all lines and all arcs at once) against each element's own
nearest point, the minimum taken element by element, as the chain did before."""

import math
import pickle

import numpy as np

from profilegen.geometry.contour import Arc, Chain, Line


def _chain():
    a1 = Arc((0.0, 0.0), 1.0, 0.0, 0.5 * math.pi)                # ccw quarter
    l1 = Line(a1.end, (-0.5, 1.5))
    a2 = Arc((-0.5, 1.0), 0.5, 0.5 * math.pi, -1.5 * math.pi)     # cw, sweep beyond π
    l2 = Line(a2.end, (-2.0, 1.0))
    a3 = Arc((-2.0, 0.0), 1.0, 0.5 * math.pi, 2.0 * math.pi - 1e-3)  # nearly a full circle
    return Chain((a1, l1, a2, l2, a3))


def test_chain_nearest_equals_the_elements_one_by_one():
    chain = _chain()
    pts = np.random.default_rng(7).uniform(-3.5, 2.0, (4000, 2))
    pts[:3] = [chain.elements[0].centre, chain.elements[1].start, chain.elements[2].end]  # centre, joins
    found = [e.nearest(pts) for e in chain.elements]
    dist = np.stack([d for d, _ in found])
    best = np.argmin(dist, axis=0)
    k = np.arange(len(pts))
    got_d, got_f = chain.nearest(pts)
    assert np.array_equal(got_d, dist[best, k])
    assert np.array_equal(got_f, np.stack([f for _, f in found])[best, k])
    assert np.array_equal(chain.distance(pts), dist.min(axis=0))
    # the feet lie on the chain, at the distances given
    assert np.allclose(np.hypot(*(pts - got_f).T), got_d, rtol=0, atol=1e-12)
    assert np.allclose(chain.distance(got_f), 0.0, rtol=0, atol=1e-12)
    # one point, and a chain that went through pickle (the figure workers get designs so)
    again = pickle.loads(pickle.dumps(chain))
    assert np.array_equal(again.distance(pts[5]), dist[:, 5].min(keepdims=True))
