"""The arc fit's input thinned to at most FIT_POINTS_MAX flank points (pipeline._fit_points): a
very fine tracing grid (n_t up to 100 000, inside its documented range) no longer makes the fit's
linear programs run for many minutes, and the thinned fit is still checked by the clearance map."""

import numpy as np
import pytest

import profilegen as pg
from profilegen.pipeline import design as pipeline


def test_a_long_flank_keeps_its_ends_and_order_and_a_short_one_is_untouched():
    flank = np.c_[np.linspace(0.0, 1.0, 12_345), np.linspace(5.0, 6.0, 12_345) ** 2]
    thin, note = pipeline._fit_points(flank)
    assert len(thin) <= pipeline.FIT_POINTS_MAX and len(thin) > pipeline.FIT_POINTS_MAX // 2
    assert np.array_equal(thin[0], flank[0]) and np.array_equal(thin[-1], flank[-1])
    assert np.all(np.diff(thin[:, 0]) > 0)  # a subsequence, in order
    assert note is not None and "12345" in note
    short = flank[: pipeline.FIT_POINTS_MAX]
    same, none = pipeline._fit_points(short)
    assert same is short and none is None


@pytest.mark.slow
def test_a_thinned_fit_says_so_and_its_outline_clears_the_fs_tooth(monkeypatch):
    """seed002's sketch flank (79 points) fitted from at most 30: the design says so, and the
    clearance map — the FS tooth's poses against the fitted CS outline, independent of the fit's
    points — finds no interference beyond the verdict's tolerance."""
    gs = pg.load_gearset("seed002_short_cup")
    full = pg.design(gs, scene="sketch")
    assert len(full.form.working_flank["right"]) > 30
    monkeypatch.setattr(pipeline, "FIT_POINTS_MAX", 30)
    thin = pg.design(gs, scene="sketch")
    assert any("the arc fit took every" in w for w in thin.warnings)
    assert not any("the arc fit took every" in w for w in full.warnings)
    assert len(thin.profile.fits[thin.profile.method].points_mm) <= 30
    assert thin.profile.clearance.min_mm >= -pipeline.INTERFERENCE_TOL_MM
