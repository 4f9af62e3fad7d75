"""Argument checks shared by the stage modules, each written once.

Every check takes the caller's error class as ``error`` (a ``ValueError`` subclass such as
``RingError``, ``StressError``, ``ComplianceError``), raises it with a one-line message that
names the parameter, its value, the unit and the allowed range, and returns the value
converted (``float``, ``int`` or a float array). A module binds the checks it uses to its
own error once, e.g. ``_whole = functools.partial(checks.whole, error=RingError)``.

Two families, by what they take (the wording is each family's own):

- scalars: :func:`number`, :func:`positive`, :func:`whole` —
  ``"rim_thickness_mm = -1.0 mm: must be in (0, inf)"``;
- numbers or arrays, naming the first bad element: :func:`finite`, :func:`finite_array`,
  :func:`within`, and :func:`choice` — ``"edge_mm must be in (0, inf) mm, got -1.0"``.

A boolean is never a number here (``True`` is not 1 mm), nor a whole number.

>>> whole("layers", 4, 2, even=True, error=ValueError)
4
>>> whole("layers", 3, 2, even=True, error=ValueError)
Traceback (most recent call last):
...
ValueError: layers = 3: must be an even whole number ≥ 2
>>> number("poisson_ratio", 0.5, "", -1.0, 0.5, error=ValueError)
Traceback (most recent call last):
...
ValueError: poisson_ratio = 0.5 : must be in (-1, 0.5)
"""

from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = ["choice", "finite", "finite_array", "number", "positive", "whole", "within"]


def _is_bool(value) -> bool:
    return isinstance(value, (bool, np.bool_))


def _interval(low: float, high: float, low_open: bool, high_open: bool) -> str:
    return f"{'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"


def _float(name: str, value, unit: str, error: type) -> float:
    """``value`` as a float, or ``error`` saying it must be a number (in ``unit``)."""
    if _is_bool(value):
        raise error(f"{name} = {value!r}: must be a number ({unit})")
    try:
        return float(value)
    except (TypeError, ValueError) as exc:
        raise error(f"{name} = {value!r}: must be a number ({unit})") from exc


# --------------------------------------------------------------------------- scalars


def number(name: str, value, unit: str, low: float = -math.inf, high: float = math.inf, *,
           low_open: bool = True, high_open: bool = True, error: type) -> float:
    """A finite number in the interval from ``low`` to ``high`` (each end open unless told)."""
    x = _float(name, value, unit, error)
    ok = math.isfinite(x) and (x > low if low_open else x >= low) and (x < high if high_open else x <= high)
    if not ok:
        raise error(f"{name} = {value!r} {unit}: must be in {_interval(low, high, low_open, high_open)}".rstrip())
    return x


def positive(name: str, value, unit: str = "mm", *, allow_zero: bool = False, error: type) -> float:
    """A finite number > 0 (≥ 0 with ``allow_zero``)."""
    x = _float(name, value, unit, error)
    if not (math.isfinite(x) and (x >= 0.0 if allow_zero else x > 0.0)):
        raise error(f"{name} = {value!r} {unit}: must be finite and {'≥ 0' if allow_zero else '> 0'}")
    return x


def whole(name: str, value, low: int, *, even: bool = False, error: type) -> int:
    """An integer ≥ ``low`` (and even with ``even``); floats such as ``4.0`` and booleans are refused."""
    if _is_bool(value) or not isinstance(value, numbers.Integral) or value < low or (even and value % 2):
        kind = "an even whole number" if even else "a whole number"
        raise error(f"{name} = {value!r}: must be {kind} ≥ {low}")
    return int(value)


# --------------------------------------------------------------------------- numbers or arrays


def finite(name: str, value, unit: str, *, error: type):
    """A finite number (a float) or an array of them (a float array)."""
    if _is_bool(value) or (isinstance(value, np.ndarray) and value.dtype == bool):
        raise error(f"{name} must be a finite number in {unit}, got {value!r}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise error(f"{name} must be a finite number in {unit}, got {value!r}") from None
    bad = ~np.isfinite(arr)
    if bad.any():
        raise error(f"{name} must be finite ({unit}), got {arr[bad].flat[0]!r}")
    return float(arr) if arr.ndim == 0 else arr


def finite_array(name: str, value, unit: str, *, error: type) -> np.ndarray:
    """As :func:`finite`, always an array."""
    return np.asarray(finite(name, value, unit, error=error), dtype=float)


def within(name: str, value, unit: str, low: float = -math.inf, high: float = math.inf, *,
           low_open: bool = True, high_open: bool = True, error: type):
    """As :func:`finite`, every element in the interval from ``low`` to ``high`` (open ends unless told)."""
    arr = np.asarray(finite(name, value, unit, error=error))
    wrong = ((arr <= low) if low_open else (arr < low)) | ((arr >= high) if high_open else (arr > high))
    if np.any(wrong):
        interval = _interval(low, high, low_open, high_open)
        raise error(f"{name} must be in {interval} {unit}, got {arr[wrong].flat[0]!r}")
    return float(arr) if arr.ndim == 0 else arr


def choice(name: str, value, allowed, *, error: type):
    """One of ``allowed``."""
    if value not in allowed:
        raise error(f"{name} must be one of {', '.join(map(repr, allowed))}, got {value!r}")
    return value


def options(cls, value, name: str, *, error: type):
    """``value`` as an options dataclass ``cls``: None (its defaults), an instance already, or a
    mapping of its fields; anything else, or a mapping with a key ``cls`` has no field for, is
    ``error`` naming ``name`` (and the unknown key, with the keys there are)."""
    import dataclasses
    from collections.abc import Mapping

    if value is None:
        return cls()
    if isinstance(value, cls):
        return value
    if not isinstance(value, Mapping):
        raise error(f"{name} = {value!r}: must be a {cls.__name__}, a mapping of its fields or None")
    known = {f.name for f in dataclasses.fields(cls)}
    unknown = sorted(str(k) for k in value if k not in known)
    if unknown:
        raise error(f"{name}: unknown key {unknown[0]!r} (the keys: {', '.join(sorted(known))})")
    return cls(**value)
