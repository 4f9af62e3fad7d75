"""Unit tests of profilegen.geometry.deformation: the ring-theory deformation and the harmonic form.

Checked against closed forms and finite differences computed here, not against the
module's own intermediate values. Ring theory (classical inextensible thin ring, the
`sketch` tier): ω = w0 cos Uφ, υ = −(w0/U) sin Uφ, so υ′ = −ω (the neutral line does
not stretch: ε = (υ′ + ω)/r_m = 0).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from profilegen.geometry.deformation import HarmonicDeformation, ring_theory
from profilegen.errors import GearSetError

W0, U = 0.5, 2
PHI = np.linspace(-math.pi, math.pi, 37)


def _central(fun, x, h):
    """5-point central difference, error ~ h⁴ f⁽⁵⁾ / 30."""
    return (fun(x - 2 * h) - 8 * fun(x - h) + 8 * fun(x + h) - fun(x + 2 * h)) / (12 * h)


def test_ring_theory_closed_form():
    omega, upsilon = ring_theory(W0, U).evaluate(PHI, order=3)
    assert omega.shape == upsilon.shape == (4, PHI.size)
    c, s = np.cos(U * PHI), np.sin(U * PHI)
    np.testing.assert_allclose(omega[0], W0 * c, atol=1e-15)
    np.testing.assert_allclose(upsilon[0], -W0 / U * s, atol=1e-15)
    # the derivatives by hand: d/dφ cos Uφ = −U sin Uφ, ...
    np.testing.assert_allclose(omega[1], -W0 * U * s, atol=1e-14)
    np.testing.assert_allclose(omega[2], -W0 * U**2 * c, atol=1e-14)
    np.testing.assert_allclose(omega[3], W0 * U**3 * s, atol=1e-14)
    np.testing.assert_allclose(upsilon[1], -W0 * c, atol=1e-14)
    np.testing.assert_allclose(upsilon[2], W0 * U * s, atol=1e-14)
    np.testing.assert_allclose(upsilon[3], W0 * U**2 * c, atol=1e-14)


def test_major_and_minor_axis():
    model = ring_theory(W0, U)
    (w,), (u,) = model.evaluate([0.0, math.pi / (2 * U), math.pi / U], order=0)
    # major axis pushed out by w0, minor axis pulled in by w0, no tangential shift on either
    np.testing.assert_allclose(w, [W0, 0.0, -W0], atol=1e-15)
    np.testing.assert_allclose(u, [0.0, -W0 / U, 0.0], atol=1e-15)
    assert model.deflection_mm == W0


def test_inextensible_neutral_line():
    omega, upsilon = ring_theory(W0, U).evaluate(PHI, order=3)
    # υ′ = −ω and, differentiated, υ″ = −ω′, υ‴ = −ω″
    np.testing.assert_allclose(upsilon[1:], -omega[:-1], atol=1e-14)


@pytest.mark.parametrize(
    "model",
    [
        ring_theory(W0, U),
        ring_theory(0.3, 3),
        HarmonicDeformation(waves=2, cos_mm=[0.48, 0.03, -0.004], sin_mm=[-0.25, 0.006, 0.001], mean_mm=0.01),
    ],
    ids=["ring U=2", "ring U=3", "three harmonics"],
)
def test_derivatives_match_finite_differences(model):
    h = 1e-3

    def value(j):
        return lambda x: np.stack(model.evaluate(x, order=3))[:, j]  # (2, n): ω⁽ʲ⁾, υ⁽ʲ⁾

    d = np.stack(model.evaluate(PHI, order=4))  # (2, 5, n)
    for j in range(4):
        np.testing.assert_allclose(d[:, j + 1], _central(value(j), PHI, h), atol=1e-10)


def test_evaluate_orders_agree():
    model = HarmonicDeformation(waves=2, cos_mm=[0.5, 0.02], sin_mm=[-0.25, -0.01])
    full = np.stack(model.evaluate(PHI, order=6))
    low = np.stack(model.evaluate(PHI, order=1))
    np.testing.assert_array_equal(low, full[:, :2])
    # order 4 and 5 follow the cos → −sin → −cos → sin → cos cycle
    np.testing.assert_allclose(full[0, 4], 0.5 * 16 * np.cos(2 * PHI) + 0.02 * 256 * np.cos(4 * PHI), atol=1e-12)
    np.testing.assert_allclose(full[1, 5], -0.25 * 32 * np.cos(2 * PHI) - 0.01 * 1024 * np.cos(4 * PHI), atol=1e-11)


@pytest.mark.parametrize(
    "model",
    [ring_theory(W0, U), HarmonicDeformation(waves=2, cos_mm=[0.5, 0.02], sin_mm=[-0.25, -0.01], mean_mm=-0.003)],
    ids=["ring", "two harmonics"],
)
def test_symmetry_and_periodicity(model):
    assert model.symmetric
    omega, upsilon = model.evaluate(PHI, order=3)
    omega_m, upsilon_m = model.evaluate(-PHI, order=3)
    sign = np.array([1.0, -1.0, 1.0, -1.0])[:, None]  # d/dφ flips the parity
    # ω even, υ odd about the major axis (DESIGN trap 3: integer harmonics keep this exact)
    np.testing.assert_allclose(omega_m, sign * omega, atol=1e-14)
    np.testing.assert_allclose(upsilon_m, -sign * upsilon, atol=1e-14)
    # and periodic with the wave period 2π/U
    omega_p, upsilon_p = model.evaluate(PHI + 2 * math.pi / model.waves, order=3)
    np.testing.assert_allclose(omega_p, omega, atol=1e-13)
    np.testing.assert_allclose(upsilon_p, upsilon, atol=1e-13)


def test_deflection_of_harmonic_form_is_omega_on_major_axis():
    model = HarmonicDeformation(waves=2, cos_mm=[0.5, 0.02], sin_mm=[-0.25, -0.01], mean_mm=-0.003)
    (w,), _ = model.evaluate([0.0], order=0)
    assert model.deflection_mm == pytest.approx(w[0], abs=1e-15)
    assert model.deflection_mm == pytest.approx(0.517, abs=1e-15)


@pytest.mark.parametrize("bad", [0.0, -0.5, float("nan"), float("inf")])
def test_bad_deflection(bad):
    with pytest.raises(GearSetError) as info:
        ring_theory(bad, U)
    assert isinstance(info.value, ValueError)
    assert "deflection_mm" in str(info.value)


def test_bad_harmonics():
    with pytest.raises(GearSetError, match="coefficient"):
        HarmonicDeformation(waves=2, cos_mm=[0.5, 0.1], sin_mm=[-0.25])
    with pytest.raises(GearSetError, match="finite"):
        HarmonicDeformation(waves=2, cos_mm=[0.5], sin_mm=[float("nan")])


def test_bad_waves():
    with pytest.raises(GearSetError, match="waves"):
        ring_theory(W0, 0)


def test_readonly_and_to_dict():
    model = ring_theory(W0, U)
    with pytest.raises(ValueError):
        model.cos_mm[0] = 1.0
    d = model.to_dict()
    assert d["waves"] == U and d["cos_mm"] == [W0] and d["sin_mm"] == [-W0 / U]
