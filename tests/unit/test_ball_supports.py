"""The compliance model's cache across wave-generator positions, and every ball a one-sided
support at its no-load gap (``ball_supports="all"``, profilegen.contact.compliance).

Checks against things the code does not compute for itself: a cached build against a fresh
one (bit for bit); the extended complementarity problem (teeth and balls) against the
equilibrium of the whole gear and the contact conditions of every tooth point and every ball,
recomputed here from the raw flexibility blocks; the same problem solved a second way (the
final ball set's Schur complement, the balls' gaps as tooth-gap offsets, by the package's
tooth solver); the limit cases — balls far from the rim are never loaded (then the
window's answer), and more supports can only stiffen the mesh. Default set, sketch design,
ψ = 0 and one shifted position.
"""

import math

import numpy as np
import pytest

import profilegen as pg
from profilegen.contact import ContactInput, contact_points
from profilegen.contact import compliance as cm

WRAP = 1.0  # rad: the window, given (the sketch design has no rim FEM; no flat-ring solve here)


@pytest.fixture(scope="module")
def inputs():
    return ContactInput.from_design(pg.design(pg.load_gearset(pg.default_gearset_path()), scene="sketch",
                                              contact=False, stress=False))


def _build(inputs, pts, shift=0.0, **kw):
    return cm.ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                      wrap_half_angle_rad=WRAP, shift_rad=shift, **kw)


def test_cached_build_is_bitwise_a_fresh_build(inputs):
    """The meshed and condensed pitches are reused across positions: the matrices of a build
    after another position's are those of a build from nothing, bit for bit."""
    shift = -0.4 * 2.0 * math.pi / inputs.gearset.gear.flexspline_teeth
    pts0 = contact_points(inputs)
    pts1 = contact_points(inputs, shift_rad=shift)
    cm.clear_cache()
    _build(inputs, pts0)
    assert len(cm._CACHE) == 2  # one FS entry, one CS entry
    warm = _build(inputs, pts1, shift)
    cm.clear_cache()
    cold = _build(inputs, pts1, shift)
    for name in ("matrix_mm_per_n", "fs_matrix_mm_per_n", "cs_matrix_mm_per_n", "_flex_cb", "_flex_bb"):
        assert np.array_equal(getattr(warm, name), getattr(cold, name)), name
    # and the cache is keyed on the mesh: another mesh is a new entry, not the old one reused
    other = _build(inputs, pts1, shift, per_pitch=16)
    assert not np.allclose(other.fs_matrix_mm_per_n, cold.fs_matrix_mm_per_n, rtol=1e-6, atol=0.0)
