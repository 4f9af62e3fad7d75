"""The DXF entity writer of profilegen.output.cad against ezdxf itself, and DXF files that do not
depend on the process that wrote them.

write_contours_dxf makes the text of its LINE / ARC / CIRCLE / LWPOLYLINE entities directly
(ezdxf's per-tag export cost ~1 ms an entity); the reference here is the same document with
the same entities added through ezdxf's own API: the two files must be byte-identical."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from profilegen.output.cad import _elements, _extents, write_contours_dxf
from profilegen.geometry.contour import Arc, Chain, Line, Polyline
from profilegen.output.export import dxf_document, save_dxf

ROOT = Path(__file__).resolve().parents[2]


def _layers():
    rng = np.random.default_rng(7)
    slot = Chain([Line((0, -1), (4, -1)), Arc((4, 0), 1.0, -math.pi / 2, math.pi),
                  Line((4, 1), (0, 1)), Arc((0, 0), 1.0, math.pi / 2, math.pi)])
    cw = Arc(rng.normal(size=2), 2.5, 0.3, -1.1)  # clockwise: written as its counter-clockwise twin
    circle = Arc((1.0 / 3.0, -2.0 / 7.0), math.pi, 0.0, 2 * math.pi)
    pts = rng.normal(size=(40, 2)) * 10
    open_line = Polyline(pts)
    closed = Polyline(np.vstack([pts[:7], pts[:1]]))
    return {"construction": [circle], "CS": [slot, cw], "FS": [open_line, closed], "extra": [Line((1e-17, 2), (3, 1e17))]}


def _with_ezdxf(path, layers, texts):
    """The same file, every entity added through ezdxf's API (the former writer)."""
    names = list(layers)
    std = {"cs", "fs", "wg", "construction", "annotation"}
    extents = _extents(layers, texts)
    with dxf_document([n for n in names if n.lower() not in std], rename={n.lower(): n for n in names}) as doc:
        msp = doc.modelspace()
        for name, items in sorted(layers.items(), key=lambda kv: kv[0].lower() != "construction"):
            for item in items:
                for e in _elements(item):
                    attribs = {"layer": name}
                    if isinstance(e, Line):
                        msp.add_line(tuple(e.start.tolist()), tuple(e.end.tolist()), dxfattribs=attribs)
                    elif isinstance(e, Polyline):
                        p = e.points[:-1] if e.closed and len(e.points) > 2 else e.points
                        msp.add_lwpolyline(p.tolist(), format="xy", close=e.closed, dxfattribs=attribs)
                    elif abs(e.sweep) >= 2 * math.pi - 1e-12:
                        msp.add_circle(tuple(e.centre.tolist()), float(e.radius), dxfattribs=attribs)
                    else:
                        c, r, a0, a1 = e.to_ccw()
                        msp.add_arc(tuple(c.tolist()), float(r), float(a0), float(a1), dxfattribs=attribs)
        for layer, xy, height, string in texts:
            msp.add_text(string, height=height, dxfattribs={"layer": layer, "insert": xy})
        save_dxf(doc, path, extents)


def test_entity_text_is_byte_identical_to_ezdxf(tmp_path):
    layers = _layers()
    texts = [("annotation", (0.0, -5.0), 0.5, "m 0.5 mm, z 200/202")]
    write_contours_dxf(tmp_path / "ours.dxf", layers, texts=texts)
    _with_ezdxf(tmp_path / "ezdxf.dxf", layers, texts)
    ours, ref = (tmp_path / "ours.dxf").read_bytes(), (tmp_path / "ezdxf.dxf").read_bytes()
    assert b"LWPOLYLINE" in ref and b"CIRCLE" in ref and b"\nARC\n" in ref and b"\nLINE\n" in ref and b"TEXT" in ref
    assert ours == ref


def test_dxf_does_not_depend_on_the_string_hash_seed(tmp_path):
    """ezdxf adds CLASS entries from a set; unsorted, their order followed PYTHONHASHSEED (two of
    six seeds gave another file before the fix)."""
    script = ("import sys, math; from profilegen.output.cad import write_contours_dxf; from profilegen.geometry.contour import Arc;"
              "write_contours_dxf(sys.argv[1], {'CS': [Arc((0, 0), 1.0, 0.0, 1.0)]})")
    files = []
    for seed in ("0", "5", "11", "23"):
        path = tmp_path / f"seed{seed}.dxf"
        env = dict(os.environ, PYTHONHASHSEED=seed, PYTHONPATH=str(ROOT))
        subprocess.run([sys.executable, "-c", script, str(path)], check=True, env=env, timeout=120)
        files.append(path.read_bytes())
    assert all(f == files[0] for f in files[1:])
