"""Sampling grids against their formulas (issue 27 item 3: a planted "endpoint counted twice"
escaped the suite). Each grid is checked against the formula its docstring states, with the
stage's expensive work replaced by a stub that records where it is asked to work:

* transmission error over one tooth passage: ψ_k = 2πk/(z2 N), k = 0 … N − 1 — the last one
  below a passage (ψ = 2π/z2 is ψ = 0 again: counting it would weigh that position twice), the
  teeth's shift δ = −ψ z2/z1; over a span in degrees both ends are included;
* the climb's wave-generator positions (ratcheting_torque(options={"climb_positions": N})): shifts
  s − k·2π/(z1 N), k = 0 … N − 1 (one FS tooth pitch, no end counted twice);
* a face section's Fourier-fit samples (face.sections.section_fit): one wave period, its end not
  sampled;
* the face slices (research face_load.slice_positions, face_curve.slice_layout): the midpoint rule's
  mid-planes and the trapezoid rule's nodes, whose cells tile the face (Σ w = b);
* the bearing's balls (clearance.radial_load_with_clearance_n): ψ_i = phase + 2πi/Z, ball i
  compressed δ cos ψ_i − c/2, its Hertz load (that / c_H)^{3/2}.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from profilegen.contact import transmission
from profilegen.contact.transmission import ARCSEC_PER_RAD, transmission_error


# --------------------------------------------------------------------------- transmission error


@pytest.fixture()
def stub_positions(monkeypatch, default_sketch):
    """transmission_error with each position's contact replaced by a stub that records ψ and
    returns a rotation known in closed form (φ(ψ) = 1e-4 + 1e-5 sin(z2 ψ) rad)."""
    seen = []
    z2 = default_sketch.gearset.gear.circular_spline_teeth

    def position(inputs, psi, opts):
        seen.append(psi)
        rot = 1e-4 + 1e-5 * math.sin(z2 * psi)
        case = SimpleNamespace(rotation_rad=rot, teeth_in_contact=3, max_tooth_force_n=10.0,
                               ball_active=np.ones(2, bool), solution=SimpleNamespace(equilibrium_residual=0.0),
                               beyond_capacity=None)
        return SimpleNamespace(theta_rad=np.array([0.0])), case, None, []

    monkeypatch.setattr(transmission, "_position", position)
    from profilegen.contact import compliance

    monkeypatch.setattr(compliance, "wrap_half_angle", lambda angle, gs: (1.0, "stub"))
    return seen


def test_tooth_passage_samples_psi_k_2pi_k_over_z2_n(stub_positions, default_sketch):
    g = default_sketch.gearset.gear
    z1, z2 = g.flexspline_teeth, g.circular_spline_teeth
    for n in (2, 3, 5):
        stub_positions.clear()
        te = transmission_error(default_sketch, 265.0, positions=n, workers=1)
        expected = 2.0 * math.pi * np.arange(n) / (z2 * n)
        np.testing.assert_allclose(te.psi_rad, expected, rtol=0, atol=1e-15)
        np.testing.assert_allclose(stub_positions, expected, rtol=0, atol=1e-15)
        assert te.psi_rad[-1] < 2.0 * math.pi / z2 * (1 - 1e-9)  # the last one below a passage
        assert np.unique(np.round(np.mod(te.psi_rad, 2 * math.pi / z2) * 1e12)).size == n  # none twice
        np.testing.assert_allclose(te.shift_rad, -te.psi_rad * z2 / z1, rtol=1e-15)
        # the error in arcsec: 3600 arcsec per degree, 180/π degrees per radian
        np.testing.assert_allclose(te.error_arcsec, (te.rotation_rad - te.rotation_rad.mean()) * 3600 * 180 / math.pi,
                                   rtol=1e-12)
    assert ARCSEC_PER_RAD == pytest.approx(math.degrees(1.0) * 3600.0, rel=1e-15)


def test_a_span_in_degrees_takes_both_ends(stub_positions, default_sketch):
    te = transmission_error(default_sketch, 265.0, positions=4, workers=1, options={"span": 30.0})
    np.testing.assert_allclose(te.psi_rad, np.radians([0.0, 10.0, 20.0, 30.0]), rtol=0, atol=1e-15)


# --------------------------------------------------------------------------- the climb's positions


def test_climb_positions_step_one_fs_pitch_over_n(monkeypatch, default_sketch):
    """ratchet._climb's positions: shift − k·2π/(z1 N), k < N; the stubs stand for the climb."""
    from profilegen.contact import climb as climb_mod
    from profilegen.contact import ratchet
    from profilegen.contact.inputs import ContactInput

    shifts = []

    class Model:
        def __init__(self, inputs, *, shift_rad, **kw):
            shifts.append(shift_rad)
            self.n, self.teeth = 1, np.zeros(1)

        def first_rotation(self, torque):
            return 0.0, 1e-3

    def fake_climb(model, start, step, *, max_torque_nm):
        col = lambda name: np.array([1.0])  # noqa: E731
        return SimpleNamespace(criterion="limit point", torque_nm=1000.0 + len(shifts), phi_rad=1e-3, warnings=(),
                               column=col)

    monkeypatch.setattr(climb_mod, "DesignClimb", Model)
    monkeypatch.setattr(climb_mod, "climb", fake_climb)
    inputs = ContactInput.from_design(default_sketch)
    gs = inputs.gearset
    z1 = gs.gear.flexspline_teeth
    for n, s0 in ((1, 0.0), (4, 0.01)):
        shifts.clear()
        torque, _, info = ratchet._climb(inputs, gs, side=1, bearing=None, cs_ring=False, race_thickness_mm=None,
                                         stations=3, max_gap_mm=0.1, linear=5000.0, max_torque_nm=None,
                                         ring_scale=1.0, extrapolated=False, warnings=[], shift_rad=s0, positions=n)
        np.testing.assert_allclose(shifts, s0 - 2.0 * math.pi * np.arange(n) / (z1 * n), rtol=0, atol=1e-15)
        assert len({round(s, 12) for s in np.mod(shifts, 2 * math.pi / z1)}) == n
        assert torque == 1001.0  # the minimum over the positions: the first run's stub torque
        assert [p["shift_rad"] for p in info["positions"]] == shifts


# --------------------------------------------------------------------------- face slices


def test_face_load_slices_are_the_midpoints_of_n_equal_cells():
    from research.face_load import slice_positions

    for n in (1, 2, 5):
        z = slice_positions(20.0, n, 3.0)
        edges = np.linspace(3.0 - 10.0, 3.0 + 10.0, n + 1)
        np.testing.assert_allclose(z, 0.5 * (edges[:-1] + edges[1:]), rtol=0, atol=1e-12)


@pytest.mark.parametrize("n", [1, 2, 3, 6])
def test_face_curve_layouts_tile_the_face(n):
    from profilegen.contact.face_curve import slice_layout

    b = 20.0
    z, w = slice_layout(b, n, "midpoint")
    np.testing.assert_allclose(z, (np.arange(n) + 0.5) * b / n, rtol=0, atol=1e-12)
    np.testing.assert_allclose(w, b / n, rtol=1e-15)
    if n >= 2:
        z, w = slice_layout(b, n, "ends")
        np.testing.assert_allclose(z, np.linspace(0.0, b, n), rtol=0, atol=1e-12)  # both face ends are nodes
        h = b / (n - 1)
        np.testing.assert_allclose(w, [0.5 * h] + [h] * (n - 2) + [0.5 * h], rtol=1e-15)  # the trapezoid rule
    assert w.sum() == pytest.approx(b, rel=1e-14)
    assert np.unique(z).size == z.size


@pytest.mark.parametrize("n, toward", [(2, None), (3, 0.0), (7, None), (7, 20.0), (7, 9.0), (9, 15.5)])
def test_graded_slices_refine_toward_the_design_section(n, toward):
    from profilegen.contact.face_curve import GRADING, slice_layout

    b = 20.0
    z, w = slice_layout(b, n, "graded", toward)
    t = b if toward is None else toward
    assert z[0] == 0.0 and z[-1] == b and np.all(np.diff(z) > 0.0)  # both face ends, in order
    assert np.min(np.abs(z - t)) < 1e-12  # a node on the design section
    h = np.diff(z)
    k = int(np.argmin(np.abs(z - t)))
    # the intervals grow by GRADING away from it, on either side
    np.testing.assert_allclose(h[k + 1:] / h[k:-1], GRADING, rtol=1e-12)
    np.testing.assert_allclose(h[:k - 1] / h[1:k], GRADING, rtol=1e-12)
    # the trapezoid rule on these nodes: the cells tile the face and integrate a linear load exactly
    assert w.sum() == pytest.approx(b, rel=1e-14)
    assert w @ (3.0 + 0.5 * z) == pytest.approx(3.0 * b + 0.25 * b * b, rel=1e-14)
    # a design section a rounding error past a face end (z_d − (z_c − b/2) in floating point) is that end
    if toward in (None, 20.0):
        np.testing.assert_array_equal(slice_layout(b, n, "graded", b * (1 + 1e-15))[0], z)
    elif toward == 0.0:
        np.testing.assert_array_equal(slice_layout(b, n, "graded", -1e-15)[0], z)


# --------------------------------------------------------------------------- the balls


def test_balls_at_phase_plus_2pi_i_over_z():
    """Each ball's load (δ cos ψ_i − c/2)^{3/2}/c_H^{3/2} at ψ_i = phase + 2πi/Z, no ball twice;
    with no clearance the sum F_r = Σ Q_i cos ψ_i."""
    from research.bearing_clearance import radial_load_with_clearance_n

    z, ch, dr, c, phase = 9, 1e-3, 0.01, 0.004, 0.1
    fr, q = radial_load_with_clearance_n(dr, c, z, ch, phase_rad=phase)
    psi = phase + 2.0 * math.pi * np.arange(z) / z
    delta = dr * np.cos(psi) - 0.5 * c
    expected = np.where(delta > 0, np.clip(delta, 0, None) / ch, 0.0) ** 1.5
    np.testing.assert_allclose(q, expected, rtol=1e-12, atol=0)
    assert float(fr) == pytest.approx(float(expected @ np.cos(psi)), rel=1e-12)
    # a symmetric set (phase 0, Z odd): the loads mirror about ψ = 0
    _, q0 = radial_load_with_clearance_n(dr, 0.0, z, ch)
    np.testing.assert_allclose(q0[1:], q0[1:][::-1], rtol=1e-12)


# --------------------------------------------------------------------------- a face section's samples


def test_face_section_fit_samples_one_wave_period_without_its_end():
    """face.sections.section_fit samples ω, υ at φ_k = (2π/U) k / N, k < N (N = max(181, 8·order
    + 8)): the period's end is its start again. The fit of a two-harmonic stub is exact."""
    from profilegen.face.sections import section_fit

    class Stub:
        def omega(self, phi, z):
            return 0.5 * np.cos(2 * phi) + 0.01 * np.cos(6 * phi)

        def upsilon(self, phi, z):
            return -0.25 * np.sin(2 * phi) - 0.01 / 3 * np.sin(6 * phi)

    fit, phi, omega, upsilon = section_fit(Stub(), 10.0, waves=2, max_order=8)
    n = max(181, 8 * 8 + 8)
    np.testing.assert_allclose(phi, math.pi * np.arange(n) / n, rtol=0, atol=1e-15)
    assert phi[-1] < math.pi * (1 - 1e-9)
    np.testing.assert_allclose(omega, Stub().omega(phi, 10.0), rtol=0, atol=1e-15)
