"""The clearance map by its definition, pose by pose: the rule ``profilegen.profile.gearform.clearance_map``
and the face stage's ``section_map`` implement with batched searches (tests/unit/test_clearance_search.py,
tests/unit/test_face_width.py compare them bit for bit)."""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

from profilegen.profile.gearform import PolylineDistance, _local_outline


def _local(points, origin, c, s):
    """CS points in the tooth frame of a pose (origin, cos, sin of its angle)."""
    d = points - origin
    return np.stack([d[:, 0] * c - d[:, 1] * s, d[:, 0] * s + d[:, 1] * c], -1)


def pose_by_pose_clearance(form, tooth, motion, phi, deep_check_mm=1e-7):
    """Every surface point's nearest CS point, the 128 nearest pairs (stable), their first 32
    distinct CS points and 4 neighbours either side, the least signed exact distance (mm, < 0
    inside the tooth); below −deep_check_mm, also every CS point inside the tooth."""
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
