"""Input checks shared by the stress models: :mod:`profilegen.checks` bound to
:class:`~profilegen.errors.StressError`. Each names the parameter, the allowed range and the unit,
and returns the value as a float (or a float array when given one)."""

from __future__ import annotations

import math

import numpy as np

from .. import checks
from ..errors import StressError

__all__ = ["choice", "count", "finite", "finite_array", "in_open", "non_negative", "poisson", "positive"]


def finite(name: str, value, unit: str):
    return checks.finite(name, value, unit, error=StressError)


def finite_array(name: str, value, unit: str) -> np.ndarray:
    """As :func:`finite`, always an array."""
    return checks.finite_array(name, value, unit, error=StressError)


def positive(name: str, value, unit: str):
    return checks.within(name, value, unit, 0.0, math.inf, error=StressError)


def non_negative(name: str, value, unit: str):
    return checks.within(name, value, unit, 0.0, math.inf, low_open=False, error=StressError)


def in_open(name: str, value, low: float, high: float, unit: str):
    return checks.within(name, value, unit, low, high, error=StressError)


def poisson(value) -> float:
    return in_open("poisson_ratio", value, -1.0, 0.5, "(dimensionless)")


def count(name: str, value, low: int) -> int:
    return checks.whole(name, value, low, error=StressError)


def choice(name: str, value, allowed) -> str:
    return checks.choice(name, value, allowed, error=StressError)
