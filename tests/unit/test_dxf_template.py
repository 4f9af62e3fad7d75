"""DXF without ezdxf (profilegen.output.dxftext): the stored template's document is, byte for
byte, the document ezdxf writes — for drawings of every element kind, with and without notes,
with extents through the origin (where ezdxf leaves the header's extents unset) — and the
drawings it does not cover (other layers, notes with DXF text codes) still go through ezdxf."""

from __future__ import annotations

import math

import ezdxf
import numpy as np
import pytest

from profilegen.geometry.contour import Arc, Chain, Line, Polyline
from profilegen.output import cad, dxftext

SAME_EZDXF = ezdxf.__version__ == dxftext.stored_version()


def _both(tmp_path, layers, texts=None):
    fast, slow = tmp_path / "fast.dxf", tmp_path / "slow.dxf"
    cad.write_contours_dxf(fast, layers, texts=texts)
    saved = cad.USE_TEMPLATE
    cad.USE_TEMPLATE = False
    try:
        cad.write_contours_dxf(slow, layers, texts=texts)
    finally:
        cad.USE_TEMPLATE = saved
    return fast, slow


def _entities(path) -> list[tuple]:
    doc = ezdxf.readfile(path)
    out = []
    for e in doc.modelspace():
        attribs = {k: (tuple(v) if hasattr(v, "__iter__") and not isinstance(v, str) else v)
                   for k, v in e.dxfattribs().items() if k not in ("handle", "owner")}
        points = tuple(map(tuple, e.get_points("xy"))) if e.dxftype() == "LWPOLYLINE" else ()
        out.append((e.dxftype(), tuple(sorted(attribs.items())), points))
    return out


SLOT = Chain([Line((0, -1), (4, -1)), Arc((4, 0), 1.0, -math.pi / 2, math.pi),
              Line((4, 1), (0, 1)), Arc((0, 0), 1.0, math.pi / 2, math.pi)])
DRAWINGS = {
    "slot": ({"CS": [SLOT]}, None),
    "every kind, construction first": (
        {"FS": [Polyline(np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 2.5]]))],
         "construction": [Arc(np.zeros(2), 5.0, 0.0, 2 * np.pi), Arc((1.0, 1.0), 2.0, 0.3, -1.1)],
         "WG": [Polyline(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 0.0]]))],
         "CS": [Line((-2.0, 0.1), (7.25, -3.5))]},
        [("annotation", (1.0, 2.0), 0.5, "CS flank: arc-line-arc (one_sided), max deviation 3.394 um"),
         ("annotation", (-3, 4), 0.25, "second note")]),
    "extents from the origin": ({"CS": [Line((0.0, 0.0), (2.0, 3.0))]}, None),
    "extents to the origin": ({"CS": [Line((-2.0, -3.0), (0.0, 0.0))]}, None),
}


@pytest.mark.parametrize("name", list(DRAWINGS))
def test_the_template_writes_what_ezdxf_writes(tmp_path, name):
    layers, texts = DRAWINGS[name]
    fast, slow = _both(tmp_path, layers, texts)
    if SAME_EZDXF:
        assert fast.read_bytes() == slow.read_bytes()
    # with any ezdxf: the same entities, layers and extents, and a clean audit
    assert _entities(fast) == _entities(slow)
    a, b = ezdxf.readfile(fast), ezdxf.readfile(slow)
    assert [layer.dxf.name for layer in a.layers] == [layer.dxf.name for layer in b.layers]
    for var in ("$EXTMIN", "$EXTMAX", "$INSUNITS", "$HANDSEED"):
        assert a.header[var] == b.header[var], var
    assert cad.audit(fast) == 0


def test_the_design_files_come_out_the_same(tmp_path):
    """A design's three CS drawings (thousands of arcs and lines, notes): the same bytes."""
    import profilegen as pg
    from profilegen.gearset import default_gearset_path, load_gearset

    d = pg.design(load_gearset(default_gearset_path()), scene="sketch", stress=False)
    outline = d.profile.outline
    r = d.form.root_radius_mm
    layers = {"CS": [outline], "construction": [Arc(np.zeros(2), r, 0.0, 2 * np.pi)]}
    texts = [("annotation", (-0.6 * r, -1.15 * r), 0.02 * r, f"{d.gearset.name}: m 0.5 mm")]
    fast, slow = _both(tmp_path, layers, texts)
    assert fast.stat().st_size > 100_000
    if SAME_EZDXF:
        assert fast.read_bytes() == slow.read_bytes()
    assert _entities(fast) == _entities(slow)


def test_what_the_template_does_not_cover_goes_through_ezdxf(tmp_path):
    for layers, texts in (({"my layer": [SLOT]}, None), ({"cs": [SLOT]}, None),
                          ({"CS": [SLOT]}, [("annotation", (0, 0), 1.0, "Ø 100 %%c")])):
        assert not dxftext.covers(list(layers), cad.DXF_LAYER_COLORS, texts or [])
        fast, slow = _both(tmp_path, layers, texts)
        assert fast.read_bytes() == slow.read_bytes()  # both through ezdxf


@pytest.mark.skipif(not SAME_EZDXF, reason=f"the stored template was made by ezdxf {dxftext.stored_version()}, "
                                           f"ezdxf {ezdxf.__version__} is installed")
def test_the_stored_template_is_the_one_ezdxf_makes():
    assert dxftext.build_template() == dxftext._template()
