"""profilegen.profile.marquardt: the arc fit's Levenberg–Marquardt, against scipy's and bit for bit
the same on every call (which MINPACK's, under scipy 1.17.1, was not on an ill-conditioned branch)."""

import dataclasses

import numpy as np
import pytest
from scipy.optimize import least_squares

import profilegen as pg
import profilegen.profile.arcfit as arcfit
from profilegen.profile.marquardt import levenberg_marquardt


def _exponential(seed=4):
    """y = a + b·exp(c·t) + noise: a small nonlinear fit with a known answer (scipy's LM)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 3.0, 60)
    y = 0.5 + 2.0 * np.exp(-1.3 * t) + 0.01 * rng.standard_normal(t.size)

    def residuals(x):
        e = np.exp(x[2] * t)
        return x[0] + x[1] * e - y, np.column_stack([np.ones_like(t), e, x[1] * t * e])

    return residuals


def test_the_minimum_is_scipys():
    residuals = _exponential()
    ours = levenberg_marquardt(residuals, np.array([0.0, 1.0, -0.5]))
    ref = least_squares(lambda x: residuals(x)[0], np.array([0.0, 1.0, -0.5]), jac=lambda x: residuals(x)[1],
                        method="lm", ftol=1e-15, xtol=1e-15, gtol=1e-15)
    assert ours.status > 0 and ours.cost == pytest.approx(ref.cost, rel=1e-12)
    np.testing.assert_allclose(ours.x, ref.x, rtol=1e-8)
    assert ours.optimality <= 1e-10


def test_an_exact_fit_ends_at_zero_and_a_spent_budget_says_so():
    t = np.linspace(0.0, 1.0, 20)
    line = lambda x: (x[0] + x[1] * t - (1.0 + 2.0 * t), np.column_stack([np.ones_like(t), t]))  # noqa: E731
    exact = levenberg_marquardt(line, np.zeros(2))
    assert exact.status > 0 and exact.cost <= 1e-28
    np.testing.assert_allclose(exact.x, [1.0, 2.0], rtol=1e-12)
    spent = levenberg_marquardt(_exponential(), np.array([0.0, 1.0, -0.5]), max_nfev=3)
    assert spent.status == 0 and spent.nfev == 3
    nan = levenberg_marquardt(lambda x: (np.full(3, np.nan), np.ones((3, 1))), np.zeros(1))
    assert nan.status == -1


@pytest.fixture(scope="module")
def short_branch():
    """The flank branch MINPACK's LM gave two answers on: the first branch (75 points) of a
    perturbed seed-002 set's fit in the sketch scene with an 8e-5 mm chord."""
    gs = pg.load_gearset("seed002_short_cup").with_values({
        "tooth.line_below_pitch_mm": 0.1227221366536166, "tooth.pressure_angle_deg": 9.993485204094242,
        "gear.module_mm": 0.3237937031277023, "tooth.tip_arc_radius_mm": 0.4189782367376258})
    scene = dataclasses.replace(pg.SCENES["sketch"], name="sketch_t", tier="sketch", chord_tol_mm=8e-5)
    branches = pg.design(gs, scene=scene).profile.branches
    assert branches is not None and len(branches.fits[0].points_mm) >= 60
    return np.array(branches.fits[0].points_mm)


def test_the_least_squares_stage_gives_the_same_bits_on_every_call(short_branch):
    p, s, _ = arcfit._flank_points(short_branch)
    got = set()
    for _ in range(8):
        prob = arcfit._Problem(p.copy(), arcfit._side_sign("left"))
        got.add(arcfit._least_squares_stage(prob, p.copy(), s.copy(), 300)["q_lsq"].tobytes())
    assert len(got) == 1
