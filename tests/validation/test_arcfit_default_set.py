"""Validation of profilegen.profile.arcfit on the default gear set's circular-spline flank.

Sources:

* DESIGN.md trap 2 and ``profilegen.profile.envelope``: the CS flank is the boundary of the
  region swept by the FS tooth and its neighbours; ``envelope.swept_depth`` decides
  membership by placing the tooth at a φ grid refined by golden section — no meshing
  equation and no arcfit code involved. A one-sided (no-interference) fitted flank must
  stay out of that region.
* Discrete Chebyshev (minimax) approximation (E. W. Cheney, *Introduction to
  Approximation Theory*, 1966): no fit has a smaller max error than the minimax one — least squares and the
  one-sided fit included — and, with normal offsets inside the family (a parallel
  curve of an arc–line–arc is one), the one-sided optimum is the minimax fit moved by
  its error, so its max backlash lies in [minimax, 2 × minimax] and attains 2 × minimax.
* Geometry: the default DCTA tooth in a ring-theory deformation is mirror-symmetric
  about the CS space axis, so the left flank's fit is the right one's mirror image.

The numbers (max/RMS errors, backlash, times, spread over starts) are printed with
``pytest -s`` and recorded as junit properties.
"""

from __future__ import annotations


import numpy as np
import pytest

from profilegen.profile.arcfit import fit_profile, swept_depth_function
from profilegen.profile.envelope import swept_depth, tooth_curves


# on the worker of test_bench_stages.py (its xdist group): the three modules read the design scene of
# the default set (conftest.py: default_design_scene, 3.6 s CPU), computed there once
pytestmark = pytest.mark.xdist_group("bench_stages")


@pytest.fixture(scope="module")
def design(default_ring_design):
    return default_ring_design  # conftest.py: the ring FEM's design scene, computed once per worker (issue 28)


@pytest.fixture(scope="module")
def flank(design):
    return np.asarray(design.form.working_flank["right"])


@pytest.fixture(scope="module")
def fits(design, flank):
    return {
        "least_squares": fit_profile(flank, method="least_squares"),
        "minimax": fit_profile(flank, method="minimax", starts=20),
        "one_sided": fit_profile(flank, method="one_sided", swept=swept_depth_function(
            design.tooth, design.motion, cs_teeth=design.gearset.gear.circular_spline_teeth,
            phi_range=design.envelope.phi_range)),
    }


def test_space_is_on_the_left_of_the_right_flank(design, flank):
    # walking up the right flank, the swept region (the space) is on the left
    _, _, shape = tooth_curves(design.tooth)
    t = np.gradient(flank, axis=0)
    left = np.column_stack([-t[:, 1], t[:, 0]]) / np.hypot(*t.T)[:, None]
    probe = np.vstack([flank[::40] + 1e-3 * left[::40], flank[::40] - 1e-3 * left[::40]])
    depth, _ = swept_depth(
        probe, design.motion, shape, phi_range=design.envelope.phi_range, neighbour_angle=2 * np.pi / design.gearset.gear.circular_spline_teeth
    )
    half = len(probe) // 2
    assert np.all(depth[:half] > 0) and np.all(depth[half:] < 0)
    assert fit_profile(flank, method="least_squares").space_side == "left"


def test_one_sided_fit_stays_out_of_the_swept_region(design, fits, record_property):
    fit = fits["one_sided"]
    assert np.all(fit.backlash_mm >= -1e-9)
    # independent check: the fitted chain sampled every ~1.5 µm against the swept region
    _, _, shape = tooth_curves(design.tooth)
    pts = np.vstack([_sample(e, 600) for e in fit.chain.elements])
    depth, _ = swept_depth(
        pts, design.motion, shape, phi_range=design.envelope.phi_range, neighbour_angle=2 * np.pi / design.gearset.gear.circular_spline_teeth
    )
    record_property("one_sided_max_depth_mm", float(depth.max()))
    print(f"\none-sided chain: deepest point {depth.max():.2e} mm into the swept region (fit's own check {fit.diagnostics['swept_max_depth_mm']:.2e})")
    assert depth.max() <= 1e-7
    assert fit.diagnostics["swept_max_depth_mm"] <= 1e-7


def test_minimax_is_the_floor_and_one_sided_at_most_twice_it(fits, record_property):
    lsq, mm, os_ = fits["least_squares"], fits["minimax"], fits["one_sided"]
    for name, value in (
        ("lsq_max_mm", lsq.max_error_mm),
        ("lsq_rms_mm", lsq.rms_error_mm),
        ("minimax_max_mm", mm.max_error_mm),
        ("minimax_rms_mm", mm.rms_error_mm),
        ("one_sided_max_backlash_mm", os_.max_backlash_mm),
        ("one_sided_rms_backlash_mm", os_.rms_error_mm),
    ):
        record_property(name, value)
    print(
        f"\nLSQ max {lsq.max_error_mm * 1e3:.4f} µm rms {lsq.rms_error_mm * 1e3:.4f} µm; "
        f"minimax max {mm.max_error_mm * 1e3:.4f} µm; one-sided max backlash {os_.max_backlash_mm * 1e3:.4f} µm "
        f"(= {os_.max_backlash_mm / mm.max_error_mm:.9f} × minimax)"
    )
    assert mm.max_error_mm <= lsq.max_error_mm
    assert mm.max_error_mm * (1 - 1e-9) <= os_.max_backlash_mm <= 2 * mm.max_error_mm * (1 + 1e-6)
    assert os_.max_backlash_mm == pytest.approx(2 * mm.max_error_mm, rel=1e-6)


def test_minimax_certificate(fits, record_property):
    mm = fits["minimax"]
    d = mm.diagnostics
    errs = np.array(d["start_max_errors_mm"])
    record_property("lp_improvement", d["lp_improvement"])
    record_property("start_spread", d["start_spread"])
    print(f"\nminimax over {len(errs)} starts: LP improvement {d['lp_improvement']:.1e}, spread {d['start_spread']:.1e}, {d['starts_within_1pct']} within 1 %")
    assert len(errs) >= 20
    assert d["lp_improvement"] <= 1e-6
    assert (mm.max_error_mm - errs.min()) / errs.min() <= 0.01  # the best start is within 1 %
    assert errs.min() >= mm.max_error_mm * (1 - 1e-8)  # and no start beat the returned fit


@pytest.mark.parametrize("method", ["least_squares", "minimax", "one_sided"])
def test_fitted_chains_are_g1_and_span_the_flank(fits, flank, method):
    chain = fits[method].chain
    assert chain.gaps().max() <= 1e-12
    assert chain.kinks_deg().max() <= 1e-9
    d0, d1 = fits[method].error_mm[[0, -1]]
    # the chain starts and ends at the feet of the flank's end points
    assert np.hypot(*(chain.start - flank[0])) == pytest.approx(abs(d0), abs=1e-12)
    assert np.hypot(*(chain.end - flank[-1])) == pytest.approx(abs(d1), abs=1e-12)


def test_left_flank_fit_mirrors_the_right(design, fits):
    left = fit_profile(np.asarray(design.form.working_flank["left"]), method="one_sided")
    assert left.space_side == "right"
    assert left.max_backlash_mm == pytest.approx(fits["one_sided"].max_backlash_mm, rel=1e-9)
    assert left.params["r1_mm"] == pytest.approx(-fits["one_sided"].params["r1_mm"], rel=1e-6)


def _sample(element, n):
    from profilegen.geometry.contour import Arc

    f = np.linspace(0.0, 1.0, n)
    if isinstance(element, Arc):
        a = element.start_angle + f * element.sweep
        return element.centre + element.radius * np.column_stack([np.cos(a), np.sin(a)])
    return element.start + f[:, None] * (element.end - element.start)
