"""The shared argument checks (profilegen.checks): what each accepts, what it refuses, the error
class it raises (the caller's), and a message that names the field, the value, the unit and the
allowed range."""

from __future__ import annotations

import math

import numpy as np
import pytest

from profilegen import checks
from profilegen.contact.compliance import ComplianceError
from profilegen.errors import ProfilegenError, StressError
from profilegen.rim.ring import RingError, RingParameters
from profilegen.rim.toothed import ToothedMeshError
from profilegen.geometry.series import SeriesError, fit_fourier
from profilegen.stress import inputs
from profilegen.geometry.wavegen import EllipticalCam, WaveGenError


class FieldError(ProfilegenError, ValueError):
    """A caller's own error class, to see it passed through."""


def message(check, *args, **kwargs) -> str:
    with pytest.raises(FieldError) as info:
        check(*args, error=FieldError, **kwargs)
    return str(info.value)


# --------------------------------------------------------------------------- number / positive


@pytest.mark.parametrize("value", [True, False, np.True_])
def test_a_boolean_is_not_a_number(value):
    assert message(checks.number, "module_mm", value, "mm", 0.0) == f"module_mm = {value!r}: must be a number (mm)"
    assert "must be a number (mm)" in message(checks.positive, "module_mm", value, "mm")
    assert "must be a finite number in mm" in message(checks.finite, "module_mm", value, "mm")
    assert "must be a finite number in mm" in message(checks.within, "module_mm", np.array([True]), "mm", 0.0)


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_nan_and_inf_are_refused_even_inside_an_infinite_interval(value):
    assert message(checks.number, "e_mpa", value, "MPa") == f"e_mpa = {value!r} MPa: must be in (-inf, inf)"
    assert message(checks.positive, "e_mpa", value, "MPa") == f"e_mpa = {value!r} MPa: must be finite and > 0"
    text = message(checks.finite, "e_mpa", [1.0, value], "MPa")
    assert text.startswith("e_mpa must be finite (MPa), got") and text.rstrip(")").endswith(repr(value))


def test_not_a_number_names_field_and_unit():
    assert message(checks.number, "rim_thickness_mm", "thick", "mm") == "rim_thickness_mm = 'thick': must be a number (mm)"
    assert message(checks.positive, "gap_mm", None, "mm") == "gap_mm = None: must be a number (mm)"
    assert message(checks.finite, "gap_mm", object, "mm").startswith("gap_mm must be a finite number in mm, got")


def test_numbers_come_back_as_floats():
    assert checks.number("r_mm", 3, "mm", 0.0, error=FieldError) == 3.0
    assert type(checks.number("r_mm", np.float32(2.5), "mm", 0.0, error=FieldError)) is float
    assert type(checks.positive("r_mm", 1, "mm", error=FieldError)) is float
    assert type(checks.finite("r_mm", 1, "mm", error=FieldError)) is float
    arr = checks.finite("r_mm", [1, 2], "mm", error=FieldError)
    assert isinstance(arr, np.ndarray) and arr.dtype == float


@pytest.mark.parametrize(
    "low_open, high_open, low_ok, high_ok, text",
    [(True, True, False, False, "(-1, 0.5)"), (False, True, True, False, "[-1, 0.5)"),
     (True, False, False, True, "(-1, 0.5]"), (False, False, True, True, "[-1, 0.5]")],
)
def test_bounds_open_or_closed(low_open, high_open, low_ok, high_ok, text):
    bounds = dict(low_open=low_open, high_open=high_open)
    for check, args in ((checks.number, ("nu", None, "", -1.0, 0.5)), (checks.within, ("nu", None, "", -1.0, 0.5))):
        for edge, ok in ((-1.0, low_ok), (0.5, high_ok)):
            call = (args[0], edge, *args[2:])
            if ok:
                assert check(*call, error=FieldError, **bounds) == edge
            else:
                assert text in message(check, *call, **bounds)
        inside = (args[0], 0.25, *args[2:])
        assert check(*inside, error=FieldError, **bounds) == 0.25
        beyond = (args[0], np.nextafter(0.5, 1.0), *args[2:])
        assert text in message(check, *beyond, **bounds)


def test_positive_and_allow_zero():
    assert message(checks.positive, "h_mm", 0.0, "mm") == "h_mm = 0.0 mm: must be finite and > 0"
    assert checks.positive("h_mm", 0.0, "mm", allow_zero=True, error=FieldError) == 0.0
    assert message(checks.positive, "h_mm", -1e-12, "mm", allow_zero=True) == "h_mm = -1e-12 mm: must be finite and ≥ 0"
    assert checks.positive("h_mm", 5e-324, "mm", error=FieldError) == 5e-324


def test_within_names_the_first_bad_element_of_an_array():
    values = np.array([0.3, 0.1, -2.0, -5.0])
    text = message(checks.within, "t_mm", values, "mm", 0.0)
    assert text.startswith("t_mm must be in (0, inf) mm, got") and "-2.0" in text and "-5.0" not in text
    out = checks.within("t_mm", values[:2], "mm", 0.0, error=FieldError)
    np.testing.assert_array_equal(out, values[:2])


# --------------------------------------------------------------------------- whole


@pytest.mark.parametrize("value", [True, False, np.True_, 2.0, "2", None, 2.5])
def test_whole_refuses_booleans_floats_and_text(value):
    assert message(checks.whole, "layers", value, 0) == f"layers = {value!r}: must be a whole number ≥ 0"


def test_whole_low_bound_and_even_counts():
    assert checks.whole("layers", 2, 2, error=FieldError) == 2
    assert message(checks.whole, "layers", 1, 2) == "layers = 1: must be a whole number ≥ 2"
    assert checks.whole("layers", np.int64(6), 2, even=True, error=FieldError) == 6
    assert type(checks.whole("layers", np.int64(6), 2, even=True, error=FieldError)) is int
    assert message(checks.whole, "layers", 7, 2, even=True) == "layers = 7: must be an even whole number ≥ 2"
    assert message(checks.whole, "layers", 0, 2, even=True) == "layers = 0: must be an even whole number ≥ 2"
    assert checks.whole("n", 10**30, 0, error=FieldError) == 10**30


def test_choice():
    assert checks.choice("edge", "clamped", ("clamped", "simple"), error=FieldError) == "clamped"
    assert message(checks.choice, "edge", "free", ("clamped", "simple")) == "edge must be one of 'clamped', 'simple', got 'free'"


# --------------------------------------------------------------------------- the callers' error classes


@pytest.mark.parametrize(
    "call, error, text",
    [
        (lambda: RingParameters(60.0, -1.0, 2.0e5, 0.3), RingError, "rim_thickness_mm = -1.0 mm: must be in (0, 120)"),
        (lambda: RingParameters(60.0, 1.0, 2.0e5, 0.5), RingError, "poisson_ratio = 0.5 : must be in (-1, 0.5)"),
        (lambda: RingParameters(60.0, True, 2.0e5, 0.3), RingError, "rim_thickness_mm = True: must be a number (mm)"),
        (lambda: EllipticalCam(semi_major_mm=-1.0, semi_minor_mm=1.0, bearing_thickness_mm=0.0), WaveGenError,
         "semi_major_mm = -1.0 mm: must be finite and > 0"),
        (lambda: fit_fourier(np.linspace(0, 3, 40), np.zeros(40), np.zeros(40), waves=0), SeriesError, "waves = 0: must be a whole number ≥ 1"),
        (lambda: inputs.positive("e_mpa", -3.0, "MPa"), StressError, "e_mpa must be in (0, inf) MPa, got"),
        (lambda: inputs.count("radial_divisions", 1, 2), StressError, "radial_divisions = 1: must be a whole number ≥ 2"),
        (lambda: inputs.poisson(0.5), StressError, "poisson_ratio must be in (-1, 0.5) (dimensionless), got"),
    ],
)
def test_callers_keep_their_error_class(call, error, text):
    with pytest.raises(error) as info:
        call()
    assert str(info.value).startswith(text)
    assert isinstance(info.value, ValueError) and isinstance(info.value, ProfilegenError)


def test_bound_checks_raise_the_module_error():
    from profilegen.contact import compliance
    from profilegen.rim import toothed

    with pytest.raises(ToothedMeshError, match=r"per_pitch = 3: must be an even whole number ≥ 2"):
        toothed._whole("per_pitch", 3, 2, even=True)
    with pytest.raises(ComplianceError, match=r"face_width_mm = 0.0 mm: must be finite and > 0"):
        compliance._positive("face_width_mm", 0.0, "mm")
    with pytest.raises(ComplianceError, match=r"ball_count = 2: must be a whole number ≥ 3"):
        compliance._whole("ball_count", 2, 3)
