"""The face stage's clearance maps (profilegen.face.clearance.section_map): what they compute is
the pose-by-pose rule of gearform.clearance_map, bit for bit, on the face stage's sparse CS
outline (its sections' envelopes traced at a chord of 0.1 µm) — found with the 4 × candidates
nearest pairs at once and a KD-tree of small leaves — for a tooth that clears the CS and for
one that interferes (every CS point inside the tooth measured as well)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from profilegen.profile.envelope import envelope_of
from profilegen.face.clearance import section_map
from profilegen.face.modification import modified_tooth
from profilegen.face.stage import CHORD_TOL_MM
from profilegen.profile.gearform import _local_outline, circular_spline_form
from tests.oracles.clearance_rule import pose_by_pose_clearance


@pytest.fixture(scope="module")
def sparse(default_set, default_gearset):
    tooth, motion, _ = default_set
    g = default_gearset.gear
    env = envelope_of(tooth, motion, cs_teeth=g.circular_spline_teeth, waves=g.waves, chord_tol_mm=CHORD_TOL_MM)
    form = circular_spline_form(env, cs_teeth=g.circular_spline_teeth, tip_clearance_mm=0.125, root_clearance_mm=0.125)
    return tooth, motion, form


@pytest.mark.parametrize("thicker_mm", [0.0, 0.01])
def test_face_map_is_the_pose_by_pose_rule(sparse, default_gearset, thicker_mm):
    tooth, motion, form = sparse
    assert len(_local_outline(form)) <= 2000  # the face stage's sparse outline (gearform._SPARSE_OUTLINE)
    if thicker_mm:
        tooth = modified_tooth(default_gearset, thicker_mm)
    cmap = section_map(form, SimpleNamespace(tooth=tooth, motion=motion), 41)
    truth = pose_by_pose_clearance(form, tooth, motion, cmap.phi)
    if thicker_mm:  # 10 µm thicker: interfering, deeper than the candidates alone read at some pose
        assert truth.min() < -1e-3
    np.testing.assert_array_equal(cmap.clearance_mm, truth)
