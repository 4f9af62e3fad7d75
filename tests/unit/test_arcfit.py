"""Unit tests of profilegen.profile.arcfit: geometry of the composite, exact recovery, the
optimality of the minimax and one-sided fits, and bad input.

Sources of the expected values (not the code's own output):

* geometry: an arc–line–arc built here from centres and angles (``_build``), the
  element-wise distance of ``contour.Chain.distance`` and the nearest of dense samples;
* discrete Chebyshev (minimax) approximation (E. W. Cheney, *Introduction to
  Approximation Theory*, 1966): a best max-norm fit is a minimum of max |d_i| that no
  small change of the parameters lowers, its extremal error is attained at several
  points with both signs, and no other fit (least squares among them) has a smaller
  max error;
* parallel curves: a curve moved along its normal by e (smaller than its radii) is
  again an arc–line–arc and every distance changes by e, so the one-sided optimum is
  the minimax fit moved by its max error (max backlash = exactly 2 × minimax error).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from profilegen.profile.arcfit import (
    PARAM_NAMES,
    FitError,
    OneSidedError,
    check_swept,
    composite,
    fit_profile,
    fit_profile_per_branch,
    signed_distance,
)
from profilegen.geometry.contour import Arc
from profilegen.errors import ProfilegenError


def _build(p0, theta0, r1, sweep1, line, r2, sweep2, n_arc=120, n_line=8):
    """Points on an arc–line–arc built from centres and angles; r > 0 turns left.
    Returns (points, expected parameters)."""
    p0 = np.asarray(p0, float)
    t0 = np.array([math.cos(theta0), math.sin(theta0)])
    n0 = np.array([-t0[1], t0[0]])
    c1 = p0 + r1 * n0
    a0 = math.atan2(*(p0 - c1)[::-1])
    a = a0 + math.copysign(1.0, r1) * np.linspace(0.0, sweep1, n_arc)
    arc1 = c1 + abs(r1) * np.column_stack([np.cos(a), np.sin(a)])
    theta1 = theta0 + math.copysign(sweep1, r1)
    t1 = np.array([math.cos(theta1), math.sin(theta1)])
    n1 = np.array([-t1[1], t1[0]])
    j1 = c1 + abs(r1) * np.array([math.cos(a[-1]), math.sin(a[-1])])
    seg = j1 + np.linspace(0.0, line, n_line)[1:, None] * t1 if line > 0 else np.empty((0, 2))
    j2 = j1 + line * t1
    c2 = j2 + r2 * n1
    b0 = math.atan2(*(j2 - c2)[::-1])
    b = b0 + math.copysign(1.0, r2) * np.linspace(0.0, sweep2, n_arc)[1:]
    arc2 = c2 + abs(r2) * np.column_stack([np.cos(b), np.sin(b)])
    expected = {
        "x0_mm": p0[0],
        "y0_mm": p0[1],
        "theta0_rad": theta0,
        "r1_mm": r1,
        "s1_mm": abs(r1) * sweep1,
        "line_mm": line,
        "r2_mm": r2,
        "s2_mm": abs(r2) * sweep2,
    }
    return np.vstack([arc1, seg, arc2]), expected


# a CS-flank-like S (the default set's is R −0.76 mm, line 0.16 mm, R +0.63 mm, ~50 mm out)
CASES = {
    "convex": ((0.3, 50.0), 2.0, 0.8, 0.5, 0.2, 1.5, 0.3),
    "mixed": ((0.5, 50.0), 2.3, -0.8, 0.5, 0.15, 0.6, 0.5),
    "tiny_line": ((0.5, 50.0), 2.3, -0.8, 0.5, 1e-4, 0.6, 0.5),
}


def _params(expected):
    k = lambda r: 1.0 / r
    return [expected["x0_mm"], expected["y0_mm"], expected["theta0_rad"], k(expected["r1_mm"]), expected["s1_mm"], expected["line_mm"], k(expected["r2_mm"]), expected["s2_mm"]]


def _noisy(seed=3, amplitude=2e-3):
    pts, exp = _build(*CASES["mixed"], n_arc=150, n_line=30)
    rng = np.random.default_rng(seed)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    # a smooth wobble along the normal (a flank that is not an arc–line–arc) plus noise
    t = np.gradient(pts, axis=0)
    nrm = np.column_stack([-t[:, 1], t[:, 0]]) / np.hypot(*t.T)[:, None]
    wobble = amplitude * (np.sin(9.0 * s) + 0.3 * rng.standard_normal(len(s)))
    return pts + wobble[:, None] * nrm, exp


# ----------------------------------------------------------------------------- geometry


def _dense(element, step_mm=2e-5):
    """Points along a contour element every ~step_mm (Line.sample gives its ends only)."""
    n = max(2, int(element.length / step_mm) + 1)
    if isinstance(element, Arc):
        a = np.linspace(element.start_angle, element.end_angle, n)
        return element.centre + element.radius * np.column_stack([np.cos(a), np.sin(a)])
    return element.start + np.linspace(0.0, 1.0, n)[:, None] * (element.end - element.start)


def test_signed_distance_is_the_exact_orthogonal_distance():
    pts, exp = _build(*CASES["mixed"])
    params = _params(exp)
    chain = composite(params)
    rng = np.random.default_rng(0)
    inner = pts[30:-30]  # feet inside the composite (its ends are continued on their circles)
    probe = inner[rng.integers(0, len(inner), 300)] + rng.normal(scale=0.01, size=(300, 2))
    d = signed_distance(params, probe)
    # contour.Chain.distance: nearest of the elements, each measured on its own
    np.testing.assert_allclose(np.abs(d), chain.distance(probe), rtol=0, atol=1e-13)
    dense = np.vstack([_dense(e) for e in chain.elements])
    brute, _ = cKDTree(dense).query(probe)
    assert np.max(brute - np.abs(d)) < 1e-6 and np.min(brute - np.abs(d)) > -1e-13  # samples lie on the chain


def test_sign_is_positive_on_the_space_side():
    pts, exp = _build(*CASES["mixed"])
    params = _params(exp)
    t = np.gradient(pts, axis=0)
    left = np.column_stack([-t[:, 1], t[:, 0]]) / np.hypot(*t.T)[:, None]
    h = 1e-4
    d_left = signed_distance(params, pts[5:-5] + h * left[5:-5], space_side="left")
    d_right = signed_distance(params, pts[5:-5] + h * left[5:-5], space_side="right")
    np.testing.assert_allclose(d_left, h, atol=1e-9)
    np.testing.assert_allclose(d_right, -h, atol=1e-9)


def test_jacobian_matches_central_differences():
    pts, exp = _build(*CASES["mixed"])
    params = np.array(_params(exp))
    rng = np.random.default_rng(1)
    probe = pts[rng.integers(5, len(pts) - 5, 200)] + rng.normal(scale=0.02, size=(200, 2))
    _, jac = signed_distance(params, probe, jac=True)
    h = 1e-6
    for j in range(8):
        dp, dm = params.copy(), params.copy()
        dp[j] += h
        dm[j] -= h
        fd = (signed_distance(dp, probe) - signed_distance(dm, probe)) / (2 * h)
        assert np.max(np.abs(jac[:, j] - fd)) < 1e-7, PARAM_NAMES[j]
    assert np.all(jac[:, 7] == 0.0)  # s2 does not move the curve


def test_zero_curvature_is_a_line_without_singularity():
    base = [0.0, 0.0, 0.3, 0.0, 0.5, 0.2, 0.0, 0.4]
    probe = np.array([[0.3, 0.4], [0.6, 0.1], [0.1, 0.05]])
    d0 = signed_distance(base, probe)
    c, s = math.cos(0.3), math.sin(0.3)
    np.testing.assert_allclose(d0, probe[:, 1] * c - probe[:, 0] * s, atol=1e-15)  # left of the line
    for k in (1e-9, -1e-9, 1e-14):
        bent = list(base)
        bent[3] = bent[6] = k
        assert np.max(np.abs(signed_distance(bent, probe) - d0)) < 10 * abs(k)
    chain = composite([0.0, 0.0, 0.3, 1e-13, 0.5, 0.2, 0.0, 0.4])
    assert [type(e).__name__ for e in chain.elements] == ["Line", "Line", "Line"]


@pytest.mark.parametrize("name", sorted(CASES))
def test_composite_is_g1_and_has_the_asked_elements(name):
    _, exp = _build(*CASES[name])
    chain = composite(_params(exp))
    assert chain.gaps().max() <= 1e-12
    assert chain.kinks_deg().max() <= 1e-9
    a1, _, a2 = chain.elements
    assert isinstance(a1, Arc) and isinstance(a2, Arc)
    assert math.isclose(a1.curvature, 1 / exp["r1_mm"], rel_tol=1e-12)
    assert math.isclose(chain.length, exp["s1_mm"] + exp["line_mm"] + exp["s2_mm"], rel_tol=1e-12)


# ----------------------------------------------------------------------------- exactness


@pytest.mark.parametrize("method", ["least_squares", "minimax"])
@pytest.mark.parametrize("name", sorted(CASES))
def test_exact_arc_line_arc_is_recovered(name, method):
    pts, exp = _build(*CASES[name])
    fit = fit_profile(pts, method=method, space_side="left", starts=1)
    assert fit.max_error_mm <= 1e-9
    for key in ("x0_mm", "y0_mm", "theta0_rad", "s1_mm", "line_mm", "s2_mm"):
        assert abs(fit.params[key] - exp[key]) <= 1e-9, key
    for key in ("r1_mm", "r2_mm"):
        assert abs(fit.params[key] - exp[key]) <= 1e-9 * abs(exp[key]), key
    assert fit.chain.gaps().max() <= 1e-12 and fit.chain.kinks_deg().max() <= 1e-9


# ----------------------------------------------------------------------------- minimax, one-sided


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_arcfit")


@pytest.fixture(scope="module")
def noisy_fits():
    pts, _ = _noisy()
    lsq = fit_profile(pts, method="least_squares", space_side="left")
    mm = fit_profile(pts, method="minimax", space_side="left", tie_break=False)
    os_ = fit_profile(pts, method="one_sided", space_side="left")
    return pts, lsq, mm, os_


def test_minimax_beats_least_squares_in_max_error(noisy_fits):
    _, lsq, mm, _ = noisy_fits
    assert mm.max_error_mm <= lsq.max_error_mm
    assert lsq.rms_error_mm <= mm.rms_error_mm  # and least squares wins its own measure


def test_no_random_perturbation_lowers_the_minimax_error(noisy_fits):
    pts, _, mm, _ = noisy_fits
    p = np.array([mm.params[k] for k in PARAM_NAMES])
    scale = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0])  # s2 does not move the curve
    rng = np.random.default_rng(7)
    best = mm.max_error_mm
    for size in (1e-7, 1e-6, 1e-5, 1e-4, 1e-3):
        for _ in range(40):
            q = p + size * scale * rng.standard_normal(8)
            q[4:6] = np.abs(q[4:6])
            assert np.max(np.abs(signed_distance(q, pts))) >= best * (1 - 1e-9)


def test_minimax_equioscillates(noisy_fits):
    _, _, mm, _ = noisy_fits
    err = mm.error_mm
    top = np.abs(np.abs(err) - mm.max_error_mm) <= 1e-9 * mm.max_error_mm
    assert top.sum() >= 4
    assert set(np.sign(err[top])) == {-1.0, 1.0}
    assert mm.diagnostics["lp_improvement"] <= 1e-6


def test_one_sided_keeps_every_point_on_the_space_side(noisy_fits):
    _, _, mm, os_ = noisy_fits
    assert np.all(os_.backlash_mm >= -1e-9)
    assert np.array_equal(os_.backlash_mm, os_.error_mm)
    # can't beat minimax; the offset minimax fit attains twice its error (parallel curves)
    assert os_.max_backlash_mm >= mm.max_error_mm * (1 - 1e-9)
    assert os_.max_backlash_mm <= 2 * mm.max_error_mm * (1 + 1e-6)
    assert os_.max_backlash_mm == pytest.approx(2 * mm.max_error_mm, rel=1e-6)
    assert os_.diagnostics["lp_improvement"] <= 1e-6


def test_mirrored_flank_gives_the_mirrored_fit():
    pts, _ = _noisy()
    right = fit_profile(pts, method="minimax", space_side="left", starts=1)
    left = fit_profile(pts * [-1.0, 1.0], method="minimax", space_side="right", starts=1)
    assert left.max_error_mm == pytest.approx(right.max_error_mm, rel=1e-9)
    # the extremal errors are mirror images; where the error has slack (below the max) the
    # minimax composite is not unique, so only to 1e-5 of the max error
    np.testing.assert_allclose(left.error_mm, right.error_mm, atol=1e-5 * right.max_error_mm)


def test_swept_region_check_catches_interference():
    # the swept region = the disk on the space side of an exact arc (one arc of radius 2)
    theta = np.linspace(0.2, 0.9, 200)
    pts = 2.0 * np.column_stack([np.cos(theta), np.sin(theta)])  # counter-clockwise: disk on the left
    inside = lambda p: 2.0 - np.hypot(*np.asarray(p).T)
    wobble = pts * (1 + 2e-4 * np.sin(25 * theta))[:, None]  # the flank bulges in and out
    ok = fit_profile(wobble, method="one_sided", space_side="left", swept=lambda p: inside(p) - 5e-4, starts=1)
    assert ok.diagnostics["swept_max_depth_mm"] <= 1e-7
    with pytest.raises(OneSidedError, match="swept_tol_mm"):
        fit_profile(wobble, method="one_sided", space_side="left", swept=lambda p: inside(p) + 1e-3, starts=1)


def test_the_swept_check_apart_is_the_check_fit_profile_makes():
    """check_swept on a fit made without ``swept`` (the design runs it on a thread of its own):
    the same samples and depths as fit_profile's own check, the same error when it fails, and
    only for a one-sided fit."""
    theta = np.linspace(0.2, 0.9, 200)
    pts = 2.0 * np.column_stack([np.cos(theta), np.sin(theta)]) * (1 + 2e-4 * np.sin(25 * theta))[:, None]
    inside = lambda p: 2.0 - np.hypot(*np.asarray(p).T)  # noqa: E731
    swept = lambda p: inside(p) - 5e-4  # noqa: E731
    checked = fit_profile(pts, method="one_sided", space_side="left", swept=swept, starts=1)
    apart = fit_profile(pts, method="one_sided", space_side="left", starts=1)
    assert "swept_max_depth_mm" not in apart.diagnostics
    out = check_swept(apart, swept)
    for key in ("swept_samples", "swept_max_depth_mm", "swept_at_mm", "swept_tol_mm"):
        assert out[key] == checked.diagnostics[key] == apart.diagnostics[key]
    assert apart.diagnostics["times_s"]["swept_check_s"] > 0
    with pytest.raises(OneSidedError, match="swept_tol_mm"):
        check_swept(apart, lambda p: inside(p) + 1e-3)
    with pytest.raises(FitError, match="one_sided"):
        check_swept(fit_profile(pts, method="minimax", space_side="left", starts=1), swept)


def test_a_degenerate_least_squares_optimum_is_not_a_minimax_start():
    """A secondary least-squares optimum with an arc of ~zero radius (seen on a short branch of a
    perturbed seed-002 set: κ −5e17 1/mm) cannot be centred in its error band (the offset collapses
    the arc): it is left out of the starts, a perturbation starts instead, and the fit is the one
    without it — where it used to fail the whole fit with a OneSidedError."""
    import profilegen.profile.arcfit as arcfit

    pts, _ = _noisy()
    p, s, _ = arcfit._flank_points(pts)
    prob = arcfit._Problem(p, arcfit._side_sign("left"))
    stage = arcfit._least_squares_stage(prob, p, s, 300)
    q_lsq, runs = stage["q_lsq"], stage["lsq_runs"]
    bad = q_lsq.copy()
    bad[5] = 5e17  # κ2: a point-sized arc 2 (its sign the one the centring offset collapses)
    with pytest.raises(OneSidedError):
        arcfit._centred(prob, bad)
    clean = arcfit._minimax_stage(prob, q_lsq, runs[:1], starts=2, max_iter=60, seed=0, tie_break=True)
    with_bad = arcfit._minimax_stage(prob, q_lsq, [runs[0], (0.0, bad, 1)], starts=2, max_iter=60, seed=0,
                                     tie_break=True)
    assert with_bad["diag"]["lsq_optima_skipped"] == 1 and "lsq_optima_skipped" not in clean["diag"]
    assert with_bad["F_mm"] == clean["F_mm"] and np.array_equal(with_bad["q_best"], clean["q_best"])


def test_space_side_auto_faces_the_tooth_space_axis():
    # like a right CS flank (x > 0) walked up from the tip circle: the tooth-space axis
    # x = 0, and so the space, is on the left of travel; mirrored, on the right
    pts, _ = _noisy()
    assert fit_profile(pts, method="least_squares").space_side == "left"
    assert fit_profile(pts * [-1.0, 1.0], method="least_squares").space_side == "right"


def test_per_branch_fits_each_branch_exactly():
    a, exp_a = _build(*CASES["mixed"])
    b, _ = _build((0.0, 0.0), 1.2, 1.1, 0.4, 0.1, -0.9, 0.3)
    b = b - b[0] + a[-1]  # starts where the first ends, with a 23° kink
    pts = np.vstack([a, b[1:]])
    fits = fit_profile_per_branch(pts, [len(a) - 1], method="minimax", space_side="left", starts=1)
    assert fits.ridge_indices == (len(a) - 1,)
    assert all(f.max_error_mm <= 1e-9 for f in fits.fits)
    assert fits.fits[0].params["r1_mm"] == pytest.approx(exp_a["r1_mm"], rel=1e-9)
    assert fits.whole.max_error_mm > 1e-4  # one G1 composite cannot follow the kink
    by_point = fit_profile_per_branch(pts, [tuple(a[-1])], method="least_squares", space_side="left", whole=False)
    assert by_point.ridge_indices == fits.ridge_indices and by_point.whole is None


def test_result_is_frozen_and_json_safe(noisy_fits):
    _, _, _, os_ = noisy_fits
    d = json.loads(json.dumps(os_.to_dict()))
    assert d["method"] == "one_sided" and d["max_backlash_mm"] == pytest.approx(os_.max_backlash_mm)
    with pytest.raises(ValueError):
        os_.error_mm[0] = 1.0
    with pytest.raises(AttributeError):
        os_.method = "minimax"
    line_like = fit_profile(_build((0, 0), 0.0, 1e3, 1e-3, 0.5, 1.0, 0.3)[0], method="least_squares", space_side="left", starts=1)
    json.dumps(line_like.to_dict())


# ----------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "points, match",
    [
        (np.column_stack([np.linspace(0, 1, 11), np.linspace(0, 1, 11) ** 2]), "points.*at least 12"),
        (np.column_stack([np.linspace(0, 1, 50), 2 * np.linspace(0, 1, 50) + 1]), "points.*straight"),
        (np.where(np.arange(100)[:, None] == 40, np.nan, _build(*CASES["mixed"])[0][:100]), "points.*finite"),
        (np.zeros((30, 3)), r"points.*\(n, 2\)"),
    ],
    ids=["too_few", "straight", "nan", "shape"],
)
def test_bad_points_raise_fit_error_naming_points(points, match):
    with pytest.raises(FitError, match=match) as info:
        fit_profile(points, method="least_squares", space_side="left")
    assert isinstance(info.value, ValueError) and isinstance(info.value, ProfilegenError)


@pytest.mark.parametrize(
    "option, match",
    [
        ({"method": "chebyshev"}, "method"),
        ({"starts": 0}, "starts"),
        ({"space_side": "up"}, "space_side"),
        ({"swept": 3.0}, "swept"),
        ({"swept_tol_mm": -1.0}, "swept_tol_mm"),
        ({"max_points": 5}, "max_points"),
    ],
)
def test_bad_options_raise_fit_error_naming_the_option(option, match):
    pts, _ = _build(*CASES["mixed"])
    with pytest.raises(FitError, match=match):
        fit_profile(pts, **{"space_side": "left", **option})


def test_misspelt_option_is_a_type_error():
    pts, _ = _build(*CASES["mixed"])
    with pytest.raises(TypeError):
        fit_profile(pts, metod="minimax")


def test_bad_ridges_and_params():
    pts, _ = _build(*CASES["mixed"])
    with pytest.raises(FitError, match="ridges"):
        fit_profile_per_branch(pts, [5], space_side="left")  # a branch of 6 points
    with pytest.raises(FitError, match="ridges"):
        fit_profile_per_branch(pts, [len(pts) + 3], space_side="left")
    with pytest.raises(FitError, match="line_mm"):
        composite([0, 0, 0, 1, 0.5, -0.1, 1, 0.5])
    with pytest.raises(FitError, match="params"):
        composite([0, 0, 0, 1, 0.5])


def test_in_a_design_the_swept_check_s_error_comes_before_the_corners(monkeypatch):
    """The design runs the CAD fit's swept-region check on a thread beside the corners and the
    clearance map: when both fail, the design still names the check's error (as when the check ran
    first), and when only the check fails, its error — not a result — comes out."""
    import profilegen as pg
    import profilegen.profile.arcfit as arcfit_module
    import profilegen.profile.rootfillet as rootfillet
    from profilegen.errors import FilletError

    def failing_check(fit, swept, tol_mm=1e-7):
        raise OneSidedError("one_sided: the fitted chain enters the swept region (planted)")

    def failing_corners(*args, **kwargs):
        raise FilletError("circular_spline.wire_radius_mm: planted")

    gs = pg.load_gearset("default")
    monkeypatch.setattr(arcfit_module, "check_swept", failing_check)
    with pytest.raises(OneSidedError, match="planted"):
        pg.design(gs, scene="sketch")
    monkeypatch.setattr(rootfillet, "filleted_cs_chain", failing_corners)
    with pytest.raises(OneSidedError, match="planted"):
        pg.design(gs, scene="sketch")


def test_the_swept_check_on_the_sketch_scene_s_poses_finds_the_fine_grid_s_depth():
    """A design looks for each checked point's deepest pose on the scene's fit_check_positions (at
    most 721; the sketch scene's 181), then refines it between its neighbours: on the default
    set's sketch fit the deepest point and its depth are those of a 2001-pose search to 1e-11 mm
    (over the bundled and the 27 corpus sets the largest difference was 1.3e-12 mm)."""
    import profilegen as pg
    from profilegen.profile.arcfit import _check_swept, _clearance_minima, swept_depth_function

    d = pg.design(pg.load_gearset("default"), scene="sketch")
    fit = d.profile.fits["one_sided"]
    found = {}
    for grid in (181, 2001):
        swept = swept_depth_function(d.tooth, d.motion, cs_teeth=d.form.cs_teeth, phi_range=d.envelope.phi_range,
                                     n_grid=grid)
        found[grid] = _check_swept(fit.chain, swept, fit.diagnostics["swept_tol_mm"],
                                   float(np.median(np.diff(fit.arclength_mm))),
                                   _clearance_minima(fit.points_mm, fit.error_mm))
    assert fit.diagnostics["swept_max_depth_mm"] == found[181]["swept_max_depth_mm"]  # the design's own grid
    assert found[181]["swept_max_depth_mm"] == pytest.approx(found[2001]["swept_max_depth_mm"], abs=1e-11)
    np.testing.assert_allclose(found[181]["swept_at_mm"], found[2001]["swept_at_mm"], atol=1e-9)
