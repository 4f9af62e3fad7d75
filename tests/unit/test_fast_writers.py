"""The writers' fast paths give exactly the text of the plain ones (issue 14, item 2: files unchanged).

write_json's one-pass encoder against json.dumps(sort_keys, indent 2) of _json_safe's copy;
json_ready's array shortcut against walking every element; the DXF point tags and drawing
extents against the per-point / per-element forms they replaced.
"""

import json
import math
import random

import numpy as np
import pytest

from profilegen.geometry.contour import Arc, Chain, Line, Polyline
from profilegen.output import cad
from profilegen.output.export import _json_safe, _json_text, write_json
from profilegen.results import json_ready


def _plain(data) -> str:
    return json.dumps(_json_safe(data, ""), sort_keys=True, indent=2, allow_nan=False)


def _random_data(rng: random.Random, depth: int = 0):
    r = rng.random()
    if depth > 3 or r < 0.3:
        return rng.choice([1.5, -0.0, 1e-300, 5e-324, 3, -7, 10**30, 1e22, True, False, None, "é\"x\n\t",
                           np.float64(2.5), np.int64(7), np.bool_(True), np.float32(0.1)])
    if r < 0.5:
        return [_random_data(rng, depth + 1) for _ in range(rng.randint(0, 4))]
    if r < 0.6:
        return tuple(_random_data(rng, depth + 1) for _ in range(rng.randint(0, 3)))
    if r < 0.72:
        return np.array([rng.random() * 10 ** rng.randint(-20, 20) for _ in range(rng.randint(0, 6))])
    if r < 0.78:
        return np.arange(rng.randint(0, 6)).reshape(-1, 1) if rng.random() < 0.5 else np.zeros((0, 2))
    return {rng.choice("abczA_é") + str(rng.randint(0, 9)): _random_data(rng, depth + 1)
            for _ in range(rng.randint(0, 4))}


def test_json_text_is_json_dumps_of_the_safe_copy():
    rng = random.Random(3)
    for _ in range(5000):
        data = _random_data(rng)
        assert _json_text(data, "", "\n") == _plain(data)


@pytest.mark.parametrize("data", [{1: 2, 3: [1.0, 2.0]}, {2.5: 1}, {True: 1, False: None}, {None: [1, "x"]},
                                  {np.int64(3): 4}, {"x": np.array([[1.0, 2.0], [3.0, 4.0]])}, [], {}, [[]], 1.0])
def test_json_text_keys_and_shapes(data):
    assert _json_text(data, "", "\n") == _plain(data)


@pytest.mark.parametrize("data, where", [([1.0, 2.0, float("nan")], "[2] is nan"),
                                         ({"a": {"b": [1.0, float("inf")]}}, "a.b[1] is inf"),
                                         ({"a": np.array([1.0, -np.inf])}, "a[1] is -inf")])
def test_json_text_names_a_non_finite_value_as_before(data, where, tmp_path):
    with pytest.raises(ValueError) as plain:
        _json_safe(data, "")
    with pytest.raises(ValueError) as fast:
        _json_text(data, "", "\n")
    assert str(fast.value) == str(plain.value) == where
    with pytest.raises(Exception, match="non-finite value"):
        write_json(tmp_path / "x.json", data)
    assert not (tmp_path / "x.json").exists()


def test_json_text_refuses_what_json_cannot_hold():
    for bad in ({"a": object()}, {(1, 2): 3}, [1, {2, 3}]):
        with pytest.raises(TypeError):
            _json_text(bad, "", "\n")


def _json_ready_walked(obj):
    """json_ready as it was: every array element walked."""
    if isinstance(obj, dict):
        return {str(k): _json_ready_walked(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_json_ready_walked(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _json_ready_walked(obj.tolist())
    if isinstance(obj, (np.bool_, bool)):
        return bool(obj)
    if isinstance(obj, (np.integer, int)):
        return int(obj)
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    return obj


@pytest.mark.parametrize("array", [np.linspace(0, 1, 7), np.array([[1.0, np.nan], [np.inf, 2.0]]),
                                   np.arange(5, dtype=np.int32), np.array([True, False]), np.zeros((0, 3)),
                                   np.array([0.1, 0.2], dtype=np.float32), np.array([1.0, 2.0], dtype=np.float16),
                                   np.array([1 + 2j]), np.array(["a", "b"])])
def test_json_ready_arrays_as_walked(array):
    got, want = json_ready({"a": array}), _json_ready_walked({"a": array})
    assert json.dumps(got, sort_keys=True) == json.dumps(want, sort_keys=True, default=repr) \
        if array.dtype.kind != "c" else repr(got) == repr(want)


def test_dxf_point_tags_are_the_per_point_text():
    rng = np.random.default_rng(2)
    pts = rng.normal(size=(500, 2)) * 10.0 ** rng.integers(-8, 8, size=(500, 2))
    pts[0] = (0.0, -0.0)
    want = "".join(f" 10\n{x!r}\n 20\n{y!r}\n" for x, y in pts.tolist())
    assert cad._xy_tags(pts) == want
    assert cad._xy_tags(pts[:0]) == ""


def _extents_per_element(items, texts):
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    for layer_items in items.values():
        for item in layer_items:
            for e in cad._elements(item):
                if isinstance(e, Line):
                    p = np.vstack([e.start, e.end])
                elif isinstance(e, Polyline):
                    p = e.points
                else:
                    a0 = e.start_angle if e.sweep > 0 else e.end_angle
                    quads = [k * math.pi / 2 for k in range(4) if (k * math.pi / 2 - a0) % (2 * math.pi) <= abs(e.sweep)]
                    p = np.vstack([e.start, e.end] + [e.point_at(q) for q in quads])
                lo, hi = np.minimum(lo, p.min(0)), np.maximum(hi, p.max(0))
    for _, (x, y), h, s in texts:
        lo, hi = np.minimum(lo, (x, y)), np.maximum(hi, (x + 0.7 * h * len(s), y + h))
    return (lo, hi) if np.isfinite(lo).all() else None


def test_extents_are_the_per_element_box():
    rng = np.random.default_rng(4)
    for _ in range(200):
        items = {"CS": [], "FS": []}
        for _ in range(rng.integers(1, 8)):
            c, r = rng.normal(size=2) * 20, float(rng.uniform(0.1, 30))
            a0, sweep = float(rng.uniform(-7, 7)), float(rng.choice([-1, 1]) * rng.uniform(0.01, 2 * math.pi))
            items["CS"].append(Arc(c, r, a0, sweep))
            items["CS"].append(Line(rng.normal(size=2) * 30, rng.normal(size=2) * 30))
        items["FS"].append(Chain([Line((0, 0), (1, 0)), Arc((1, 1), 1.0, -math.pi / 2, math.pi / 2)]))
        items["FS"].append(Polyline(rng.normal(size=(10, 2)) * 40))
        texts = [("annotation", (float(rng.normal() * 50), 3.0), 1.5, "label")] if rng.random() < 0.5 else []
        lo, hi = cad._extents(items, texts)
        want_lo, want_hi = _extents_per_element(items, texts)
        assert lo.tolist() == want_lo.tolist() and hi.tolist() == want_hi.tolist()
    assert cad._extents({"CS": []}, []) is None
