"""Input checks shared by the stress models: each raises :class:`~profilegen.errors.StressError`
naming the parameter, the allowed range and the unit, and returns the value as a float (or a
float array when given one)."""

from __future__ import annotations

import numpy as np

from ..errors import StressError

__all__ = ["choice", "count", "finite", "finite_array", "in_open", "non_negative", "poisson", "positive"]


def finite(name: str, value, unit: str):
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise StressError(f"{name} must be a finite number in {unit}, got {value!r}") from None
    bad = ~np.isfinite(arr)
    if bad.any():
        raise StressError(f"{name} must be finite ({unit}), got {arr[bad].flat[0]!r}")
    return float(arr) if arr.ndim == 0 else arr


def finite_array(name: str, value, unit: str) -> np.ndarray:
    """As :func:`finite`, always an array."""
    return np.asarray(finite(name, value, unit), dtype=float)


def _where(name: str, value, unit: str, bad, interval: str):
    arr = np.asarray(finite(name, value, unit))
    wrong = bad(arr)
    if np.any(wrong):
        raise StressError(f"{name} must be in {interval} {unit}, got {arr[wrong].flat[0]!r}")
    return float(arr) if arr.ndim == 0 else arr


def positive(name: str, value, unit: str):
    return _where(name, value, unit, lambda a: a <= 0.0, "(0, inf)")


def non_negative(name: str, value, unit: str):
    return _where(name, value, unit, lambda a: a < 0.0, "[0, inf)")


def in_open(name: str, value, low: float, high: float, unit: str):
    return _where(name, value, unit, lambda a: (a <= low) | (a >= high), f"({low:g}, {high:g})")


def poisson(value) -> float:
    return in_open("poisson_ratio", value, -1.0, 0.5, "(dimensionless)")


def count(name: str, value, low: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
        raise StressError(f"{name} must be an integer in [{low}, inf), got {value!r}")
    return int(value)


def choice(name: str, value, allowed) -> str:
    if value not in allowed:
        raise StressError(f"{name} must be one of {', '.join(map(repr, allowed))}, got {value!r}")
    return value
