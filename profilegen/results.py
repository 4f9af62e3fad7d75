"""Conventions shared by the result types (STYLE.md: frozen dataclasses, read-only arrays,
JSON-safe ``to_dict()``): one definition of each, used by every stage module."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["json_ready", "readonly"]


def readonly(values, dtype=float) -> np.ndarray:
    """A read-only copy of ``values`` as an array of ``dtype``."""
    array = np.array(values, dtype=dtype)
    array.setflags(write=False)
    return array


def json_ready(obj):
    """``obj`` with numpy scalars and arrays turned into Python ones, non-finite floats into
    None (for diagnostics; :func:`profilegen.output.export.write_json` refuses NaN in results)."""
    if isinstance(obj, dict):
        return {str(k): json_ready(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_ready(v) for v in obj]
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind in "iub" or (obj.dtype.kind == "f" and obj.dtype.itemsize <= 8 and np.isfinite(obj).all()):
            return obj.tolist()  # already Python ints, bools or finite floats: the same lists, not walked again
        return json_ready(obj.tolist())
    if isinstance(obj, (np.bool_, bool)):
        return bool(obj)
    if isinstance(obj, (np.integer, int)):
        return int(obj)
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    return obj
