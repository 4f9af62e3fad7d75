"""Unit tests of profilegen.output.export: atomic files, JSON, CSV and DXF.

Files are checked by reading them back with independent readers (json, csv,
ezdxf) and against the envelope's own pieces, never against the writer's
intermediate values.
"""

from __future__ import annotations

import csv
import json
import math
import re

import ezdxf
import numpy as np
import pytest

from profilegen.errors import ExportError
from profilegen.output.export import (
    DXF_LAYER_COLORS,
    atomic_write,
    read_dxf_polylines,
    write_envelope_csv,
    write_json,
    write_outline_dxf,
    write_points_csv,
)


def _names(folder):
    return sorted(p.name for p in folder.iterdir())


# ----------------------------------------------------------------------------- atomic_write


def test_atomic_write_creates_parents_and_leaves_no_temp(tmp_path):
    target = tmp_path / "a" / "b" / "out.txt"
    with atomic_write(target) as f:
        f.write("line 1\nline 2\n")
    assert target.read_text() == "line 1\nline 2\n"
    assert _names(target.parent) == ["out.txt"]


def test_atomic_write_binary(tmp_path):
    with atomic_write(tmp_path / "x.bin", "wb") as f:
        f.write(b"\x00\x01\xff")
    assert (tmp_path / "x.bin").read_bytes() == b"\x00\x01\xff"


def test_exception_inside_leaves_no_file_and_no_temp(tmp_path):
    with pytest.raises(RuntimeError, match="boom"):
        with atomic_write(tmp_path / "out.txt") as f:
            f.write("partial")
            raise RuntimeError("boom")
    assert _names(tmp_path) == []


def test_exception_inside_keeps_the_old_file(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(KeyError):
        with atomic_write(target) as f:
            f.write("new, partial")
            raise KeyError("x")
    assert target.read_text() == "old"
    assert _names(tmp_path) == ["out.txt"]


def test_path_under_a_regular_file_is_an_export_error(tmp_path):
    blocker = tmp_path / "file.txt"
    blocker.write_text("I am a file")
    target = blocker / "sub" / "out.json"
    with pytest.raises(ExportError, match="out.json") as info:
        write_json(target, {"a": 1})
    assert isinstance(info.value, OSError)
    assert str(target) in str(info.value) and "file.txt" in str(info.value)
    assert _names(tmp_path) == ["file.txt"] and blocker.read_text() == "I am a file"


def test_path_that_is_a_folder_is_an_export_error(tmp_path):
    (tmp_path / "d").mkdir()
    with pytest.raises(ExportError, match="d"):
        with atomic_write(tmp_path / "d") as f:
            f.write("x")
    assert _names(tmp_path) == ["d"] and _names(tmp_path / "d") == []


def test_atomic_write_rejects_read_modes(tmp_path):
    with pytest.raises(ValueError, match="mode"):
        with atomic_write(tmp_path / "x", "r"):
            pass


# ----------------------------------------------------------------------------- JSON


def test_json_sorted_indented_numpy_converted(tmp_path):
    path = tmp_path / "r.json"
    write_json(path, {"b": np.float64(0.25), "a": np.arange(3), "c": {"z": np.int64(7), "y": (1, 2)}})
    text = path.read_text()
    assert json.loads(text) == {"a": [0, 1, 2], "b": 0.25, "c": {"y": [1, 2], "z": 7}}
    assert text.index('"a"') < text.index('"b"') < text.index('"c"')
    assert '\n  "a": [' in text and text.endswith("\n")


@pytest.mark.parametrize(
    "data, where",
    [
        ({"pieces": [{"depth_mm": 0.1}, {"depth_mm": float("nan")}]}, "pieces[1].depth_mm"),
        ({"x": np.array([1.0, np.inf])}, "x[1]"),
        (float("-inf"), "<root>"),
    ],
)
def test_json_rejects_non_finite_naming_the_key(tmp_path, data, where):
    with pytest.raises(ExportError, match=re.escape(where)):
        write_json(tmp_path / "r.json", data)
    assert _names(tmp_path) == []


def test_json_unserialisable_names_the_key(tmp_path):
    with pytest.raises(TypeError, match=r"a\.b"):
        write_json(tmp_path / "r.json", {"a": {"b": object()}})
    assert _names(tmp_path) == []


# ----------------------------------------------------------------------------- CSV


def test_envelope_csv_round_trip(tmp_path, default_set):
    _, _, env = default_set
    path = tmp_path / "envelope.csv"
    write_envelope_csv(path, env)
    with path.open(newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["x_mm", "y_mm", "phi_rad", "class"]
    body = rows[1:]
    assert len(body) == sum(len(p.points) for p in env.pieces)
    xy = np.array([[float(r[0]), float(r[1])] for r in body])
    phi = np.array([float(r[2]) for r in body])
    cls = [r[3] for r in body]
    i = 0
    for piece in env.pieces:
        n = len(piece.points)
        assert set(cls[i : i + n]) == {piece.cls}
        assert np.max(np.abs(xy[i : i + n] - piece.points)) <= 1e-12  # %.12f keeps nm (and pm)
        assert np.max(np.abs(phi[i : i + n] - piece.phi)) <= 1e-12
        i += n
    assert set(cls) == {p.cls for p in env.pieces} and set(cls) <= {"conjugate", "interfering", "tip_path"}
    assert all(len(r[0].split(".")[1]) == 12 for r in body[:50])  # fixed precision


def test_points_csv_round_trip(tmp_path):
    pts = np.array([[0.123456789012345, 50.5], [-1e-9, 49.0000000005]])
    write_points_csv(tmp_path / "p.csv", pts, header=("u_mm", "v_mm"))
    lines = (tmp_path / "p.csv").read_text().splitlines()
    assert lines[0] == "u_mm,v_mm" and len(lines) == 3
    back = np.loadtxt(tmp_path / "p.csv", delimiter=",", skiprows=1)
    assert np.max(np.abs(back - pts)) <= 5e-13


def test_points_csv_bad_input_names_the_parameter(tmp_path):
    with pytest.raises(ValueError, match="points"):
        write_points_csv(tmp_path / "p.csv", np.zeros((3, 3)))
    with pytest.raises(ValueError, match="points"):
        write_points_csv(tmp_path / "p.csv", [[0.0, float("nan")]])
    with pytest.raises(ValueError, match="header"):
        write_points_csv(tmp_path / "p.csv", np.zeros((3, 2)), header=("a,b", "c"))
    assert _names(tmp_path) == []


# ----------------------------------------------------------------------------- DXF


@pytest.fixture(scope="module")
def dxf_layers(default_set):
    tooth, motion, env = default_set
    outline = tooth.outline(n_per_mm=200.0)
    fs = motion.pose(np.array([0.0])).to_cs(outline)
    return {
        "CS": [np.asarray(env.flank["boundary"])],
        "FS": [np.vstack([fs, fs[:1]])],  # first point repeated: auto-closed
        "construction": [np.array([[0.0, 48.0], [0.0, 52.0]])],
    }


def test_dxf_round_trip_coordinates(tmp_path, dxf_layers):
    path = tmp_path / "outline.dxf"
    write_outline_dxf(path, dxf_layers)
    back = read_dxf_polylines(path)
    assert set(back) == set(dxf_layers)
    for name, lines in dxf_layers.items():
        assert len(back[name]) == len(lines)
        for a, b in zip(lines, back[name]):
            assert a.shape == b.shape
            assert np.max(np.abs(a - b)) <= 1e-9


def test_dxf_units_layers_and_audit(tmp_path, dxf_layers):
    path = tmp_path / "outline.dxf"
    write_outline_dxf(path, dxf_layers)
    doc = ezdxf.readfile(path)
    assert doc.dxfversion == "AC1024"  # R2010
    assert doc.header["$INSUNITS"] == 4 and doc.units == ezdxf.units.MM
    assert doc.header["$MEASUREMENT"] == 1
    assert doc.header["$LUNITS"] == 2 and doc.header["$AUNITS"] == 0
    colours = {layer.dxf.name: layer.dxf.color for layer in doc.layers}
    for name, colour in DXF_LAYER_COLORS.items():
        assert colours[name] == colour
    assert (colours["CS"], colours["FS"], colours["WG"]) == (1, 5, 3)  # red, blue, green
    auditor = doc.audit()
    assert len(auditor.errors) == 0
    assert {e.dxftype() for e in doc.modelspace()} == {"LWPOLYLINE"}


def test_dxf_is_deterministic(tmp_path, dxf_layers):
    write_outline_dxf(tmp_path / "a.dxf", dxf_layers)
    write_outline_dxf(tmp_path / "b.dxf", dxf_layers)
    a, b = (tmp_path / "a.dxf").read_bytes(), (tmp_path / "b.dxf").read_bytes()
    assert a == b
    assert b"$FINGERPRINTGUID" in a
    assert not ezdxf.options.write_fixed_meta_data_for_testing  # the global switch is restored


def test_dxf_closed_flag(tmp_path):
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]])
    open_line = np.array([[0.0, 0.0], [1.0, 0.5], [2.0, 0.0]])
    path = tmp_path / "c.dxf"
    write_outline_dxf(path, {"CS": [square, open_line], "FS": [open_line]}, closed={"FS": True})
    msp = ezdxf.readfile(path).modelspace()
    by_layer = {}
    for e in msp.query("LWPOLYLINE"):
        by_layer.setdefault(e.dxf.layer, []).append((e.closed, len(e)))
    assert by_layer["CS"] == [(True, 4), (False, 3)]  # auto: the repeated point is dropped
    assert by_layer["FS"] == [(True, 3)]
    write_outline_dxf(path, {"CS": [square]}, closed=False)
    (e,) = ezdxf.readfile(path).modelspace().query("LWPOLYLINE")
    assert not e.closed and len(e) == 5


def test_dxf_bad_input_names_the_parameter(tmp_path):
    line = np.array([[0.0, 0.0], [1.0, 1.0]])
    with pytest.raises(ValueError, match="closed"):
        write_outline_dxf(tmp_path / "x.dxf", {"CS": [line]}, closed={"CX": True})
    with pytest.raises(ValueError, match="layer name"):
        write_outline_dxf(tmp_path / "x.dxf", {"a/b": [line]})
    with pytest.raises(ValueError, match=r"layers\['CS'\]\[0\]"):
        write_outline_dxf(tmp_path / "x.dxf", {"CS": [np.array([[0.0, math.nan], [1.0, 1.0]])]})
    with pytest.raises(TypeError, match="list"):
        write_outline_dxf(tmp_path / "x.dxf", {"CS": line})
    assert _names(tmp_path) == []


def test_dxf_unwritable_path(tmp_path):
    (tmp_path / "f").write_text("x")
    with pytest.raises(ExportError, match="outline.dxf"):
        write_outline_dxf(tmp_path / "f" / "outline.dxf", {"CS": [np.array([[0.0, 0.0], [1.0, 1.0]])]})
    assert _names(tmp_path) == ["f"]
