"""The rim stage (profilegen.rim.stage.solve_rim): tiers, fits, error estimates, fallbacks."""

import json
import math

import numpy as np
import pytest

from profilegen.errors import GearSetError
from profilegen.gearset import default_gearset_path, load_gearset
from profilegen.rim import RIM_TIERS, solve_rim


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_rim_stage")


@pytest.fixture(scope="module")
def gearset():
    return load_gearset(default_gearset_path())


@pytest.fixture(scope="module")
def design_rim(gearset):
    return solve_rim(gearset, tier="design")


def test_sketch_is_ring_theory(gearset):
    rim = solve_rim(gearset, tier="sketch")
    assert rim.fem is None and rim.error_estimate_mm is None and rim.dof == 0
    w, u = rim.model.evaluate(np.array([0.0, math.pi / 4]), order=0)
    assert w[0, 0] == pytest.approx(gearset.deflection_mm) and u[0, 1] == pytest.approx(-gearset.deflection_mm / 2)


def test_design_tier_is_the_nonlinear_ring_with_a_fourier_fit(gearset, design_rim):
    rim = design_rim
    assert rim.fem.geometry == "nonlinear" and rim.tier.model == "flat"
    assert rim.dof == rim.fem.dof > 1000
    # the bore stays on the cam at the major axis (trap 7)
    assert rim.fem.bore_omega_mm[0] == pytest.approx(gearset.deflection_mm, abs=1e-6)
    # the fit reproduces its samples to well below a µm, and is exactly symmetric
    fit = rim.model
    assert fit.symmetric and fit.order <= RIM_TIERS["design"].max_order
    assert max(fit.omega_stats.max_error_mm, fit.upsilon_stats.max_error_mm) < 2e-7
    assert abs(fit.upsilon_stats.defect_mm) < 1e-14
    # mesh error estimate: the halved mesh differs by ~1 nm at the shared nodes (observed 0.9 nm)
    assert 1e-11 < rim.error_estimate_mm < 1e-5
    # it differs from ring theory by µm, not by mm
    phi, w, u = rim.samples
    rw, ru = rim.reference.evaluate(phi, order=0)
    assert 1e-4 < np.max(np.abs(rw[0] - w)) < 2e-2
    json.dumps(rim.to_dict())


def test_fit_derivatives_are_consistent(design_rim):
    """The kinematics needs ω′, ω″, ω‴: they must be the derivatives of ω (central differences)."""
    phi = np.linspace(0.1, 3.0, 7)
    h = 1e-4
    w, _ = design_rim.model.evaluate(phi, order=3)
    for k in range(3):
        lo, _ = design_rim.model.evaluate(phi - h, order=3)
        hi, _ = design_rim.model.evaluate(phi + h, order=3)
        fd = (hi[k] - lo[k]) / (2 * h)
        assert np.max(np.abs(fd - w[k + 1])) < 1e-6 * max(1.0, np.max(np.abs(w[k + 1])))


def test_other_wave_counts_fall_back_to_ring_theory_with_a_warning(gearset):
    three = gearset.with_values({"gear.waves": 3, "gear.circular_spline_teeth": 203,
                                 "wave_generator.contour": "cosine_cam"})
    rim = solve_rim(three, tier="design")
    assert rim.fem is None and any("gear.waves = 3" in w for w in rim.warnings)


def test_unknown_tier_names_the_parameter(gearset):
    with pytest.raises(GearSetError, match="rim tier"):
        solve_rim(gearset, tier="fast")


@pytest.mark.slow
def test_toothed_tier_with_both_fitters(gearset):
    """The verify path on a lighter mesh (linear, 16 → 14 columns per pitch for the estimate):
    toothed FEM, Fourier fit used, general sine fit reported with its periodicity defect."""
    from profilegen.rim import RimTier

    tier = RimTier("verify", "toothed", geometry="linear", layers=2, divisions=0, max_order=40, sine_fit=True,
                   tooth_layers=2, per_pitch=16)
    rim = solve_rim(gearset, tier=tier)
    assert rim.fem.tier == "linear toothed ring FEM" and rim.dof > 20000
    # the 14-column mesh is not nested in the 16-column one: compared through a cubic spline
    assert 1e-9 < rim.error_estimate_mm < 1e-4
    assert "columns per tooth pitch" in rim.error_measure
    sine = rim.sine
    assert sine is not None and not sine.symmetric
    assert sine.omega_fit.stats.r2 > 0.999999 and sine.upsilon_fit.stats.r2 > 0.999999
    assert abs(rim.model.omega_stats.defect_mm) < 1e-13  # the Fourier fit is periodic …
    assert max(abs(d) for d in sine.defect_mm) > 1e-7  # … the general sine series is not
    json.dumps(rim.to_dict())


@pytest.fixture(scope="module", params=["linear", "nonlinear"])
def whole_bore(request, gearset):
    """The flat ring (4 × 64) with the contact condensed onto every bore node, solved once per
    geometry for the two tests below (each compares a condensed solve with it)."""
    from profilegen.rim import solve_ring
    from profilegen.geometry.wavegen import from_gearset

    return request.param, solve_ring(gearset, contour=from_gearset(gearset), layers=4, divisions=64,
                                     geometry=request.param)


def _wrap(gearset, geometry, within, caplog):
    """The same ring with the contact condensed onto the bore nodes with θ ≤ ``within`` only;
    returns the result and the log."""
    import logging

    from profilegen.rim import solve_ring
    from profilegen.geometry.wavegen import from_gearset

    with caplog.at_level(logging.INFO, logger="profilegen.rim.ring"):
        wrap = solve_ring(gearset, contour=from_gearset(gearset), layers=4, divisions=64, geometry=geometry,
                          condense_within_rad=within)
    return wrap, caplog.text


def test_condensing_near_the_wrap_gives_the_whole_bores_answer(gearset, whole_bore, caplog):
    """The verify tier condenses the rim onto the bore nodes within the wrap + a margin: the
    same ω, υ (to the contact's own 1e-9 mm gap tolerance) and the same contact nodes."""
    geometry, whole = whole_bore
    wrap, text = _wrap(gearset, geometry, whole.contact_angle_rad + math.radians(10.0), caplog)
    assert "widened" not in text
    assert np.max(np.abs(wrap.omega_mm - whole.omega_mm)) < 1e-9
    assert np.max(np.abs(wrap.upsilon_mm - whole.upsilon_mm)) < 1e-9
    assert np.array_equal(wrap.contact_phi_rad, whole.contact_phi_rad)
    assert wrap.max_penetration_mm <= 1e-9  # every bore node, the dropped ones included


def test_a_kept_set_narrower_than_the_wrap_is_widened(gearset, whole_bore, caplog):
    """Kept nodes only up to 10° (the wrap is ~40–60°): the contact reaches the dropped nodes,
    solve_ring says so, widens the kept set and returns the whole bore's answer."""
    geometry, whole = whole_bore
    wrap, text = _wrap(gearset, geometry, math.radians(10.0), caplog)
    assert whole.contact_angle_deg > 20.0
    assert "widened" in text
    assert np.max(np.abs(wrap.omega_mm - whole.omega_mm)) < 1e-9
    assert np.array_equal(wrap.contact_phi_rad, whole.contact_phi_rad)


def test_bad_condense_angle_is_named(gearset):
    from profilegen.rim import RingError, solve_ring
    from profilegen.geometry.wavegen import from_gearset

    with pytest.raises(RingError, match="condense_within_rad"):
        solve_ring(gearset, contour=from_gearset(gearset), layers=2, divisions=16, condense_within_rad=-0.1)


def test_lazy_columns_give_the_condensed_answer(gearset, whole_bore):
    """The toothed rim solves the bore compliance's columns only as the contact asks for them
    (the first contact solve from the empty set, one node entering at a time): forced on the
    flat ring, the same ω, υ and contact nodes as condensing every bore node up front."""
    from profilegen.rim import solve_ring
    from profilegen.geometry.wavegen import from_gearset

    geometry, whole = whole_bore
    lazy = solve_ring(gearset, contour=from_gearset(gearset), layers=4, divisions=64, geometry=geometry,
                      lazy_columns=True)
    assert np.max(np.abs(lazy.omega_mm - whole.omega_mm)) < 1e-11
    assert np.max(np.abs(lazy.upsilon_mm - whole.upsilon_mm)) < 1e-11
    assert np.array_equal(lazy.contact_phi_rad, whole.contact_phi_rad)
    assert lazy.max_penetration_mm <= 1e-9


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_lazy_lcp_solves_the_complementarity_problem(seed):
    """The active-set LCP solver that forms S's columns only for nodes entering the set: on a
    random SPD problem (a compliance of 60 nodes, 2 dofs each), from the empty set and from a
    wrong guess, λ ≥ 0, w = Sλ − q ≥ 0 and λ·w = 0, and it asked for fewer columns than all."""
    from profilegen.lcp import active_set_lazy
    from profilegen.rim.ring import _DenseCompliance, s_columns

    rng = np.random.default_rng(seed)
    n = 60
    a = rng.normal(size=(2 * n, 2 * n))
    g = a @ a.T / (2 * n) + np.eye(2 * n)
    asked = set()

    class Counting(_DenseCompliance):
        def take(self, nodes):
            asked.update(int(j) for j in np.ravel(nodes))
            return super().take(nodes)

    comp = Counting(g.reshape(n, 2, n, 2))
    normal = rng.normal(size=(n, 2))
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    q = rng.normal(size=n)
    s = np.einsum("ia,iajb,jb->ij", normal, g.reshape(n, 2, n, 2), normal)
    for guess in (None, rng.random(n) < 0.5):
        asked.clear()
        lam = active_set_lazy(s_columns(normal, comp, n), q, max_steps=4 * n, guess=guess)
        w = s @ lam - q
        assert np.all(lam >= 0.0) and np.all(w >= -1e-10)
        assert abs(lam @ w) < 1e-10
        assert 0 < np.count_nonzero(lam) < n
        if guess is None:
            assert len(asked) < n
