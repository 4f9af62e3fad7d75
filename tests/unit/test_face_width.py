"""The face stage's clearance maps (profilegen.face.clearance.section_map): what they compute is
the pose-by-pose rule of gearform.clearance_map, bit for bit, on the face stage's sparse CS
outline (its sections' envelopes traced at a chord of 0.1 µm) — found with the 4 × candidates
nearest pairs at once and a KD-tree of small leaves — for a tooth that clears the CS and for
one that interferes (every CS point inside the tooth measured as well)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import shapely
from scipy.spatial import cKDTree

from profilegen.envelope import envelope_of
from profilegen.face.clearance import section_map
from profilegen.face.modification import modified_tooth
from profilegen.face.stage import CHORD_TOL_MM
from profilegen.gearform import PolylineDistance, _local_outline, circular_spline_form


@pytest.fixture(scope="module")
def sparse(default_set, default_gearset):
    tooth, motion, _ = default_set
    g = default_gearset.gear
    env = envelope_of(tooth, motion, cs_teeth=g.circular_spline_teeth, waves=g.waves, chord_tol_mm=CHORD_TOL_MM)
    form = circular_spline_form(env, cs_teeth=g.circular_spline_teeth, tip_clearance_mm=0.125, root_clearance_mm=0.125)
    return tooth, motion, form


def _local(points, origin, c, s):
    """CS points in the tooth frame of a pose (origin, cos, sin of its angle)."""
    d = points - origin
    return np.stack([d[:, 0] * c - d[:, 1] * s, d[:, 0] * s + d[:, 1] * c], -1)


def _rule(form, tooth, motion, phi, deep_check_mm=1e-7):
    """The map by its definition, pose by pose: every surface point's nearest CS point, the 128
    nearest pairs (stable), their first 32 distinct CS points and 4 neighbours either side, the
    least signed exact distance; below −deep_check_mm, also every CS point inside the tooth."""
    cs = _local_outline(form)
    tree = cKDTree(cs)
    surface_pts = tooth.surface(n_per_mm=800.0)
    surface = PolylineDistance(tooth.surface(n_per_mm=400.0))
    poly = shapely.Polygon(tooth.outline(n_per_mm=400.0))
    pose = motion.pose(phi)
    out = np.empty(phi.size)
    for i in range(phi.size):
        c, s = np.cos(pose.angle[i]), np.sin(pose.angle[i])
        placed = np.stack([surface_pts[:, 0] * c + surface_pts[:, 1] * s,
                           surface_pts[:, 1] * c - surface_pts[:, 0] * s], -1) + pose.origin[i]
        dist, idx = tree.query(placed)
        order = idx[np.argsort(dist, kind="stable")][:128]
        near = np.array(list(dict.fromkeys(order.tolist()))[:32])
        near = np.unique(np.clip(near[:, None] + np.arange(-4, 5), 0, len(cs) - 1))
        q = _local(cs[near], pose.origin[i], c, s)
        inside = shapely.contains_xy(poly, q[:, 0], q[:, 1])
        out[i] = np.min(np.where(inside, -surface.distance(q), surface.distance(q)))
        if out[i] < -deep_check_mm:
            every = _local(cs, pose.origin[i], c, s)
            every = every[shapely.contains_xy(poly, every[:, 0], every[:, 1])]
            out[i] = min(out[i], -float(np.max(surface.distance(every))))
    return out


@pytest.mark.parametrize("thicker_mm", [0.0, 0.01])
def test_face_map_is_the_pose_by_pose_rule(sparse, default_gearset, thicker_mm):
    tooth, motion, form = sparse
    assert len(_local_outline(form)) <= 2000  # the face stage's sparse outline (gearform._SPARSE_OUTLINE)
    if thicker_mm:
        tooth = modified_tooth(default_gearset, thicker_mm)
    cmap = section_map(form, SimpleNamespace(tooth=tooth, motion=motion), 41)
    truth = _rule(form, tooth, motion, cmap.phi)
    if thicker_mm:  # 10 µm thicker: interfering, deeper than the candidates alone read at some pose
        assert truth.min() < -1e-3
    np.testing.assert_array_equal(cmap.clearance_mm, truth)
