"""Unit tests of profilegen.output.cad: DXF with true LINE/ARC entities, SVG paths, PNG preview.

The contours are built here by hand from :mod:`profilegen.geometry.contour` elements — a slot
(two half circles and two lines) and a 12-tooth toy gear (one pitch of arcs and lines,
repeated by rotation) — and every file is checked with an independent reader: ezdxf's
entities and auditor, xml.etree plus the SVG spec's arc centre formula (SVG 1.1,
appendix F.6.5), matplotlib's PNG reader. Geometric checks are exact analytic
facts: the slot's area is 8 + π mm², the gear closes after 12 pitches.

Golden file: ``tests/golden/toy_gear.dxf`` is the toy gear written by
:func:`write_contours_dxf`. :func:`test_golden_toy_gear` first checks the golden file
itself against the toy gear's analytic geometry (``tests/golden/toy_gear_checks.py``:
closure, tangent turning 2π, G1 joins, enclosed area, root/tip radii, 12-fold and mirror
symmetry, from ezdxf's entities alone), then writes the toy gear afresh in tmp_path and
compares the two semantically (entity types, layers, coordinates, radii and angles to
1e-6 mm / 1e-6°, header units, layer colours, texts), not byte by byte, so an ezdxf
upgrade that reorders the header does not break it. The tests never write the golden
file; to regenerate it deliberately (after a change of the toy gear or of the writer's
semantics) run

    python tests/golden/regen_toy_gear.py --write

which writes it only if the new file passes the same geometric checks, and commit it
together with the change that made it necessary.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import ezdxf
import numpy as np
import pytest

from profilegen.output.cad import (
    audit,
    chain_gaps,
    oriented_chain,
    read_dxf_contours,
    render_dxf_png,
    write_contours_dxf,
    write_contours_svg,
)
from profilegen.geometry.contour import Arc, Chain, ContourError, Line
from profilegen.errors import ExportError
from profilegen.output.export import DXF_LAYER_COLORS
from tests.golden.toy_gear_checks import ToyGearCheckError, analytic_area_mm2, check_toy_gear_dxf

GOLDEN = Path(__file__).resolve().parents[1] / "golden" / "toy_gear.dxf"
SVG_NS = {"svg": "http://www.w3.org/2000/svg"}


def _names(folder):
    return sorted(p.name for p in folder.iterdir())


def _rot(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def _polar(r, deg):
    return (r * math.cos(math.radians(deg)), r * math.sin(math.radians(deg)))


# ----------------------------------------------------------------------------- the shapes


def slot() -> Chain:
    """A 4 mm × 2 mm slot with round ends (radius 1), counter-clockwise: area 8 + π mm²."""
    return Chain([
        Line((0.0, -1.0), (4.0, -1.0)),
        Arc((4.0, 0.0), 1.0, -math.pi / 2, math.pi),
        Line((4.0, 1.0), (0.0, 1.0)),
        Arc((0.0, 0.0), 1.0, math.pi / 2, math.pi),
    ])


def _short_arc(centre, p, q) -> Arc:
    """The shorter arc about ``centre`` from p to q (|p − c| = |q − c|)."""
    c = np.asarray(centre, float)
    a0 = math.atan2(p[1] - c[1], p[0] - c[0])
    a1 = math.atan2(q[1] - c[1], q[0] - c[0])
    sweep = (a1 - a0 + math.pi) % (2 * math.pi) - math.pi
    return Arc(c, float(np.hypot(*(np.asarray(p) - c))), a0, sweep)


def toy_gear_pitch() -> list:
    """One 30° pitch of the toy gear, run counter-clockwise about the origin: 7 elements.

    Root arc r = 8 (0°→6°), flank line to the tip circle r = 10 at 9°, tip arc to 12°,
    a clockwise scallop (centre on r = 12 at 15°) to 18°, tip arc to 21°, flank line
    down to r = 8 at 24°, root arc to 30°.
    """
    deg = math.radians
    scallop = _short_arc(_polar(12.0, 15.0), _polar(10.0, 12.0), _polar(10.0, 18.0))
    assert scallop.sweep < 0  # the one clockwise arc of the pitch
    return [
        Arc((0, 0), 8.0, 0.0, deg(6.0)),
        Line(_polar(8.0, 6.0), _polar(10.0, 9.0)),
        Arc((0, 0), 10.0, deg(9.0), deg(3.0)),
        scallop,
        Arc((0, 0), 10.0, deg(18.0), deg(3.0)),
        Line(_polar(10.0, 21.0), _polar(8.0, 24.0)),
        Arc((0, 0), 8.0, deg(24.0), deg(6.0)),
    ]


def toy_gear() -> Chain:
    """12 pitches: the pitch turned by k·30° (``.transformed``), 84 elements, closed."""
    pitch = toy_gear_pitch()
    return Chain([e.transformed(_rot(math.radians(30.0 * k))) for k in range(12) for e in pitch])


def toy_gear_layers() -> dict:
    return {
        "CS": [toy_gear()],
        "construction": [Arc((0, 0), 8.0, 0.0, 2 * math.pi), Arc((0, 0), 10.0, 0.0, 2 * math.pi),
                         Line((-11.0, 0.0), (11.0, 0.0)), Line((0.0, -11.0), (0.0, 11.0))],
    }


TOY_TEXTS = [("annotation", (-10.0, -13.0), 1.0, "toy gear z = 12, r 8/10 mm")]


def _signed_area(chain: Chain) -> float:
    """Green's theorem, exact for lines and arcs: ½∮(x dy − y dx)."""
    total = 0.0
    for e in chain.elements:
        if isinstance(e, Line):
            total += 0.5 * (e.start[0] * e.end[1] - e.end[0] * e.start[1])
        else:
            (cx, cy), r, a0, a1 = e.centre, e.radius, e.start_angle, e.end_angle
            total += 0.5 * (r * r * e.sweep + r * (cx * (math.sin(a1) - math.sin(a0)) - cy * (math.cos(a1) - math.cos(a0))))
    return total


def _same_curve(a, b, tol=1e-9):
    """Same type and the same point set: lines either way round, arcs by centre, radius and (unordered) ends."""
    assert type(a) is type(b)
    if isinstance(a, Line):
        d = min(max(np.abs(a.start - b.start).max(), np.abs(a.end - b.end).max()),
                max(np.abs(a.start - b.end).max(), np.abs(a.end - b.start).max()))
        assert d <= tol
    else:
        assert np.abs(a.centre - b.centre).max() <= tol and abs(a.radius - b.radius) <= tol
        assert abs(abs(a.sweep) - abs(b.sweep)) * a.radius <= tol
        ends_a = (a.start, a.end) if a.sweep > 0 else (a.end, a.start)  # both as counter-clockwise
        ends_b = (b.start, b.end) if b.sweep > 0 else (b.end, b.start)
        assert max(np.abs(ends_a[0] - ends_b[0]).max(), np.abs(ends_a[1] - ends_b[1]).max()) <= tol


# ----------------------------------------------------------------------------- the shapes themselves


def test_shapes_are_closed_and_have_the_analytic_area():
    assert slot().gaps(closed=True).max() <= 1e-12
    assert _signed_area(slot()) == pytest.approx(8.0 + math.pi, abs=1e-12)
    gear = toy_gear()
    assert len(gear.elements) == 84 and gear.gaps(closed=True).max() <= 1e-12


# ----------------------------------------------------------------------------- DXF


@pytest.mark.parametrize("direction", ["ccw", "cw"])
def test_slot_round_trip(tmp_path, direction):
    chain = slot() if direction == "ccw" else slot().reversed()
    path = tmp_path / "slot.dxf"
    write_contours_dxf(path, {"CS": [chain]})
    back = read_dxf_contours(path)
    assert list(back) == ["CS"]
    els = back["CS"]
    assert [type(e).__name__ for e in els] == [type(e).__name__ for e in chain.elements]
    for a, b in zip(chain.elements, els):
        _same_curve(a, b)
    assert all(e.sweep > 0 for e in els if isinstance(e, Arc))  # DXF arcs come back counter-clockwise
    assert chain_gaps(els, closed=True).max() <= 1e-9
    back_chain = oriented_chain(els)
    assert np.abs(back_chain.start - chain.start).max() <= 1e-9  # the first line keeps its direction
    sign = 1.0 if direction == "ccw" else -1.0
    assert _signed_area(back_chain) == pytest.approx(sign * (8.0 + math.pi), abs=1e-9)


def test_toy_gear_entities_coordinates_and_closure(tmp_path):
    path = tmp_path / "gear.dxf"
    layers = toy_gear_layers()
    write_contours_dxf(path, layers, texts=TOY_TEXTS)
    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    kinds = {}
    for e in msp:
        kinds.setdefault((e.dxf.layer, e.dxftype()), 0)
        kinds[(e.dxf.layer, e.dxftype())] += 1
    assert msp[0].dxf.layer == "construction"  # written first: drawn underneath
    assert kinds == {("CS", "LINE"): 24, ("CS", "ARC"): 60, ("construction", "CIRCLE"): 2,
                     ("construction", "LINE"): 2, ("annotation", "TEXT"): 1}
    back = read_dxf_contours(path)
    gear = toy_gear()
    assert len(back["CS"]) == 84
    for a, b in zip(gear.elements, back["CS"]):
        _same_curve(a, b)
    assert chain_gaps(back["CS"], closed=True).max() <= 1e-9
    # three radii: root 8, tip 10 and the scallop's (law of cosines); DXF angles in [0, 360]°
    scallop_r = math.sqrt(12.0**2 + 10.0**2 - 2 * 12.0 * 10.0 * math.cos(math.radians(3.0)))
    radii = sorted({round(e.dxf.radius, 9) for e in msp.query("ARC")})
    assert radii == pytest.approx(sorted([8.0, 10.0, scallop_r]), abs=1e-9)
    for e in msp.query("ARC"):
        assert 0.0 <= e.dxf.start_angle <= 360.0 and 0.0 <= e.dxf.end_angle <= 360.0
    (text,) = msp.query("TEXT")
    assert text.dxf.text == TOY_TEXTS[0][3] and text.dxf.height == 1.0
    assert tuple(text.dxf.insert)[:2] == (-10.0, -13.0)


def test_scallop_radius_is_the_chord_geometry(tmp_path):
    """The CW scallop: centre on r = 12 at 15°, through r = 10 at 12° and 18° (law of cosines)."""
    path = tmp_path / "gear.dxf"
    write_contours_dxf(path, {"CS": [toy_gear()]})
    expected = math.sqrt(12.0**2 + 10.0**2 - 2 * 12.0 * 10.0 * math.cos(math.radians(3.0)))
    scallops = [e for e in read_dxf_contours(path)["CS"] if isinstance(e, Arc) and np.hypot(*e.centre) > 11.0]
    assert len(scallops) == 12
    for k, e in enumerate(sorted(scallops, key=lambda a: math.atan2(a.centre[1], a.centre[0]) % (2 * math.pi))):
        assert e.radius == pytest.approx(expected, abs=1e-12)
        assert np.abs(e.centre - _polar(12.0, 15.0 + 30.0 * k)).max() <= 1e-12


def test_units_layers_audit(tmp_path):
    path = tmp_path / "gear.dxf"
    write_contours_dxf(path, toy_gear_layers(), texts=TOY_TEXTS)
    doc = ezdxf.readfile(path)
    assert doc.dxfversion >= "AC1024"  # R2010 or later
    assert doc.header["$INSUNITS"] == 4 and doc.units == ezdxf.units.MM
    assert doc.header["$MEASUREMENT"] == 1
    colours = {layer.dxf.name: layer.dxf.color for layer in doc.layers}
    for name, colour in DXF_LAYER_COLORS.items():
        assert colours[name] == colour
    assert (colours["CS"], colours["FS"], colours["WG"], colours["construction"], colours["annotation"]) == (1, 5, 3, 8, 7)
    assert audit(path) == 0
    lo, hi = doc.header["$EXTMIN"], doc.header["$EXTMAX"]
    assert lo[0] == pytest.approx(-11.0) and hi[1] == pytest.approx(11.0)


def test_full_precision(tmp_path):
    """Coordinates that need all 17 digits survive: the file holds the shortest round-trip repr."""
    x, y = 0.1 + 0.2, 1.0 / 3.0
    arc = Arc((x, y), 50.000000000000014, 0.1, 1.0)
    write_contours_dxf(tmp_path / "p.dxf", {"CS": [Line((x, y), (y, x)), arc]})
    line, back = read_dxf_contours(tmp_path / "p.dxf")["CS"]
    assert tuple(line.start) == (x, y) and tuple(line.end) == (y, x)
    assert tuple(back.centre) == (x, y) and back.radius == arc.radius
    assert "0.30000000000000004" in (tmp_path / "p.dxf").read_text()


def test_dxf_is_byte_deterministic(tmp_path):
    write_contours_dxf(tmp_path / "a.dxf", toy_gear_layers(), texts=TOY_TEXTS)
    write_contours_dxf(tmp_path / "b.dxf", toy_gear_layers(), texts=TOY_TEXTS)
    assert (tmp_path / "a.dxf").read_bytes() == (tmp_path / "b.dxf").read_bytes()
    assert not ezdxf.options.write_fixed_meta_data_for_testing  # the global switch is restored


def test_standard_layers_present_when_empty_and_other_layers_white(tmp_path):
    write_contours_dxf(tmp_path / "e.dxf", {"my layer": [Line((0, 0), (1, 0))]})
    doc = ezdxf.readfile(tmp_path / "e.dxf")
    colours = {layer.dxf.name: layer.dxf.color for layer in doc.layers}
    assert set(DXF_LAYER_COLORS) <= set(colours) and colours["my layer"] == 7
    write_contours_dxf(tmp_path / "empty.dxf", {})
    assert audit(tmp_path / "empty.dxf") == 0 and read_dxf_contours(tmp_path / "empty.dxf") == {}


def test_read_mirrored_ocs_arc(tmp_path):
    """An ARC with extrusion −z (what a CAD mirror can leave) comes back in the XY plane, CCW."""
    doc = ezdxf.new("R2010")
    e = doc.modelspace().add_arc((3.0, 1.0), 2.0, 10.0, 80.0, dxfattribs={"extrusion": (0, 0, -1)})
    p0, p1 = np.array(e.start_point)[:2], np.array(e.end_point)[:2]  # ezdxf's own WCS ends
    doc.saveas(tmp_path / "m.dxf")
    (arc,) = read_dxf_contours(tmp_path / "m.dxf")["0"]
    assert arc.sweep > 0 and arc.radius == 2.0
    assert np.abs(arc.centre - (-3.0, 1.0)).max() <= 1e-12
    assert {tuple(np.round(arc.start, 12)), tuple(np.round(arc.end, 12))} == {tuple(np.round(p0, 12)), tuple(np.round(p1, 12))}
    assert math.degrees(arc.sweep) == pytest.approx(70.0)


def test_read_tilted_arc_is_an_error(tmp_path):
    doc = ezdxf.new("R2010")
    doc.modelspace().add_arc((0, 0), 1.0, 0, 90, dxfattribs={"extrusion": (0, 1, 1)})
    doc.saveas(tmp_path / "t.dxf")
    with pytest.raises(ContourError, match="extrusion"):
        read_dxf_contours(tmp_path / "t.dxf")


def test_read_zero_radius_arc_names_the_entity(tmp_path):
    doc = ezdxf.new("R2010")
    doc.modelspace().add_arc((0, 0), 0.0, 0, 90, dxfattribs={"layer": "CS"})
    doc.saveas(tmp_path / "z.dxf")
    with pytest.raises(ContourError, match=r"ARC #\w+ on layer 'CS'.*radius"):
        read_dxf_contours(tmp_path / "z.dxf")


def test_dxf_bad_input_names_the_parameter(tmp_path):
    line = Line((0, 0), (1, 1))
    with pytest.raises(ValueError, match="units"):
        write_contours_dxf(tmp_path / "x.dxf", {"CS": [line]}, units="inch")
    with pytest.raises(TypeError, match=r"layers\['CS'\].*wrap it in a list"):
        write_contours_dxf(tmp_path / "x.dxf", {"CS": slot()})
    with pytest.raises(TypeError, match=r"layers\['CS'\]\[1\]"):
        write_contours_dxf(tmp_path / "x.dxf", {"CS": [line, np.zeros((2, 2))]})
    with pytest.raises(ValueError, match=r"layers\['CS'\]\[0\]\.elements\[1\]"):
        write_contours_dxf(tmp_path / "x.dxf", {"CS": [Chain([line, Line((1, 1), (math.nan, 0))])]})
    with pytest.raises(ValueError, match=r"layers\['CS'\]\[0\].*too small"):
        write_contours_dxf(tmp_path / "x.dxf", {"CS": [Arc((0, 0), 1.0, 100.0, 1e-15)]})
    with pytest.raises(ValueError, match="layer name"):
        write_contours_dxf(tmp_path / "x.dxf", {"a/b": [line]})
    with pytest.raises(ValueError, match="same DXF layer"):
        write_contours_dxf(tmp_path / "x.dxf", {"cs": [line], "CS": [line]})
    with pytest.raises(ValueError, match=r"texts\[0\].*height_mm"):
        write_contours_dxf(tmp_path / "x.dxf", {}, texts=[("annotation", (0, 0), 0.0, "x")])
    with pytest.raises(ValueError, match=r"texts\[0\].*string"):
        write_contours_dxf(tmp_path / "x.dxf", {}, texts=[("annotation", (0, 0), 1.0, "two\nlines")])
    with pytest.raises(TypeError, match=r"texts\[0\]"):
        write_contours_dxf(tmp_path / "x.dxf", {}, texts=[("annotation", (0, 0), 1.0)])
    assert _names(tmp_path) == []


@pytest.mark.parametrize("writer", ["dxf", "svg", "png"])
def test_unwritable_path_is_an_export_error_and_leaves_nothing(tmp_path, writer):
    blocker = tmp_path / "f"
    blocker.write_text("x")
    target = blocker / "sub" / f"out.{writer}"
    layers = {"CS": [slot()]}
    with pytest.raises(ExportError, match=f"out.{writer}") as info:
        if writer == "dxf":
            write_contours_dxf(target, layers)
        elif writer == "svg":
            write_contours_svg(target, layers)
        else:
            write_contours_dxf(tmp_path / "ok.dxf", layers)
            render_dxf_png(tmp_path / "ok.dxf", target)
    assert isinstance(info.value, OSError)
    assert sorted(set(_names(tmp_path)) - {"ok.dxf"}) == ["f"] and blocker.read_text() == "x"


# ----------------------------------------------------------------------------- golden file


def _dxf_semantics(path):
    """What a CAD user sees: header units, layer colours, and each entity's type, layer and geometry."""
    doc = ezdxf.readfile(path)
    layers = {layer.dxf.name: layer.dxf.color for layer in doc.layers}
    entities = []
    for e in doc.modelspace():
        t = e.dxftype()
        if t == "LINE":
            geo = [*tuple(e.dxf.start)[:2], *tuple(e.dxf.end)[:2]]
        elif t == "ARC":
            geo = [*tuple(e.dxf.center)[:2], e.dxf.radius, e.dxf.start_angle, e.dxf.end_angle]
        elif t == "CIRCLE":
            geo = [*tuple(e.dxf.center)[:2], e.dxf.radius]
        elif t == "TEXT":
            geo = [*tuple(e.dxf.insert)[:2], e.dxf.height, e.dxf.text]
        else:
            geo = [t]
        entities.append((t, e.dxf.layer, geo))
    return {"insunits": doc.header["$INSUNITS"], "measurement": doc.header["$MEASUREMENT"],
            "layers": layers, "entities": entities}


def _angle_diff_deg(a, b):
    return abs((a - b + 180.0) % 360.0 - 180.0)


def test_golden_toy_gear(tmp_path):
    assert GOLDEN.exists(), f"{GOLDEN} is missing; see this module's docstring to regenerate it"
    measured = check_toy_gear_dxf(GOLDEN)  # the golden file is the analytic toy gear ...
    assert measured["area_mm2"] == pytest.approx(analytic_area_mm2(), abs=1e-9)
    fresh = tmp_path / "toy_gear.dxf"  # ... and the writer still produces it
    write_contours_dxf(fresh, toy_gear_layers(), texts=TOY_TEXTS)
    old, new = _dxf_semantics(GOLDEN), _dxf_semantics(fresh)
    assert (new["insunits"], new["measurement"]) == (old["insunits"], old["measurement"]) == (4, 1)
    assert new["layers"] == old["layers"]
    assert len(new["entities"]) == len(old["entities"]) == 89
    for k, ((t0, l0, g0), (t1, l1, g1)) in enumerate(zip(old["entities"], new["entities"])):
        assert (t1, l1) == (t0, l0), f"entity {k}"
        if t0 == "TEXT":
            assert g1[3] == g0[3] and np.allclose(g1[:3], g0[:3], atol=1e-6, rtol=0), f"entity {k}"
            continue
        n_xy = 4 if t0 == "LINE" else 3  # mm values (coordinates, radius) first, then angles (deg)
        assert np.allclose(g1[:n_xy], g0[:n_xy], atol=1e-6, rtol=0), f"entity {k}: {g0} -> {g1}"
        for a0, a1 in zip(g0[n_xy:], g1[n_xy:]):
            assert _angle_diff_deg(a0, a1) <= 1e-6, f"entity {k}: angle {a0} -> {a1}"


def _mutated_golden(tmp_path, change) -> Path:
    doc = ezdxf.readfile(GOLDEN)
    change(doc)
    out = tmp_path / "mutated.dxf"
    doc.saveas(out)
    return out


def _cs(doc, kind):
    return [e for e in doc.modelspace().query(kind) if e.dxf.layer == "CS"]


def _transform_cs(matrix):
    def change(doc):
        for e in doc.modelspace():
            if e.dxf.layer == "CS":
                e.transform(matrix)
    return change


def _open_a_gap(doc):
    line = _cs(doc, "LINE")[0]
    x, y = tuple(line.dxf.end)[:2]
    line.dxf.end = (x + 1e-7, y, 0.0)


def _grow_an_arc(doc):
    arc = _cs(doc, "ARC")[3]
    arc.dxf.radius = arc.dxf.radius * (1.0 + 1e-8)


def _set_text(doc):
    (text,) = doc.modelspace().query("TEXT")
    text.dxf.text = "toy gear z = 13, r 8/10 mm"


@pytest.mark.parametrize("change, words", [
    (lambda doc: doc.header.__setitem__("$INSUNITS", 6), r"\$INSUNITS = 6"),  # metres
    (lambda doc: doc.modelspace().delete_entity(_cs(doc, "LINE")[5]), r"layer CS: 83 entities"),
    (_set_text, r"annotation: z = 13"),
    (_open_a_gap, r"closure"),
    (_grow_an_arc, r"closure"),
    (_transform_cs(ezdxf.math.Matrix44.scale(1.0001, 1.0001, 1.0)), r"area"),  # 0.01 % larger
    (_transform_cs(ezdxf.math.Matrix44.z_rotate(0.01)), r"not a scallop"),  # turned by 0.57°
], ids=["units", "missing-entity", "annotation", "gap-1e-7", "arc-radius-1e-8", "scaled", "turned"])
def test_golden_checks_reject_a_file_that_is_not_the_toy_gear(tmp_path, change, words):
    """The geometric check can fail: small edits of the golden file, each caught by name."""
    with pytest.raises(ToyGearCheckError, match=words):
        check_toy_gear_dxf(_mutated_golden(tmp_path, change))


def test_golden_regeneration_script_refuses_a_wrong_gear_and_writes_only_on_request(tmp_path, monkeypatch):
    from tests.golden import regen_toy_gear

    target = tmp_path / "golden" / "toy_gear.dxf"
    assert regen_toy_gear.main(["--output", str(target)]) == 0 and not target.exists()  # a dry run writes nothing
    assert regen_toy_gear.main(["--output", str(target), "--write"]) == 0
    assert _dxf_semantics(target) == _dxf_semantics(GOLDEN)
    before = target.read_bytes()
    turned = Chain([e.transformed(_rot(math.radians(1.0))) for e in toy_gear().elements])  # a gear, but turned by 1°
    monkeypatch.setattr(regen_toy_gear, "toy_gear_layers", lambda: {**toy_gear_layers(), "CS": [turned]})
    assert regen_toy_gear.main(["--output", str(target), "--write"]) == 1
    assert target.read_bytes() == before and sorted(p.name for p in target.parent.iterdir()) == ["toy_gear.dxf"]


# ----------------------------------------------------------------------------- SVG


def _svg_commands(d):
    """Parse path data into (command, numbers) pairs (the writer uses absolute M, L, A, Z)."""
    tokens = re.findall(r"[MLAZ]|-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?", d)
    out, i = [], 0
    arity = {"M": 2, "L": 2, "A": 7, "Z": 0}
    while i < len(tokens):
        c = tokens[i]
        n = arity[c]
        out.append((c, [float(v) for v in tokens[i + 1 : i + 1 + n]]))
        i += 1 + n
    return out


def _svg_arc_centre(p0, p1, r, large, sweep):
    """Centre of an SVG arc from its endpoint form (SVG 1.1 appendix F.6.5, no rotation)."""
    x1p, y1p = (p0[0] - p1[0]) / 2, (p0[1] - p1[1]) / 2
    rad = max(0.0, (r * r - x1p * x1p - y1p * y1p) / (x1p * x1p + y1p * y1p))
    s = math.sqrt(rad) * (-1.0 if large == sweep else 1.0)
    cxp, cyp = s * y1p, -s * x1p
    return np.array([cxp + (p0[0] + p1[0]) / 2, cyp + (p0[1] + p1[1]) / 2])


def test_svg_paths_true_arcs_and_layers(tmp_path):
    path = tmp_path / "gear.svg"
    layers = {"CS": [toy_gear()], "FS": [slot().reversed(), Line((20, 0), (21, 1))],
              "construction": toy_gear_layers()["construction"]}
    write_contours_svg(path, layers, stroke_mm=0.02, texts=TOY_TEXTS)
    root = ET.parse(path).getroot()
    assert root.get("width").endswith("mm") and len(root.get("viewBox").split()) == 4
    groups = {g.get("id"): g for g in root.findall("svg:g", SVG_NS)}
    assert list(groups) == ["construction", "CS", "FS", "WG", "annotation"]  # construction underneath
    assert [groups[n].get("stroke") for n in ("CS", "FS", "WG", "construction", "annotation")] == [
        "#ff0000", "#0000ff", "#00ff00", "#808080", "#000000"]
    assert {g.get("stroke-width") for g in groups.values()} == {"0.02"}
    # one path per chain or loose element
    assert [len(groups[n].findall("svg:path", SVG_NS)) for n in ("CS", "FS", "WG", "construction")] == [1, 2, 0, 4]
    assert groups["annotation"].find("svg:text", SVG_NS).text == TOY_TEXTS[0][3]

    # the gear's path: one L per line, one A per arc, closed; every arc's centre (from the SVG
    # endpoint form) is the element's centre with y flipped, so the sweep flags are right
    (gear_path,) = groups["CS"].findall("svg:path", SVG_NS)
    cmds = _svg_commands(gear_path.get("d"))
    assert [c for c, _ in cmds].count("M") == 1 and cmds[-1][0] == "Z"
    body = [c for c in cmds if c[0] in "LA"]
    gear = toy_gear().elements
    assert [c for c, _ in body] == ["L" if isinstance(e, Line) else "A" for e in gear]
    here = np.array(cmds[0][1])
    for (c, v), e in zip(body, gear):
        end = np.array(v[-2:])
        assert np.abs(end - (e.end[0], -e.end[1])).max() <= 1e-12
        if c == "A":
            assert v[0] == v[1] == pytest.approx(e.radius, abs=1e-12)
            centre = _svg_arc_centre(here, end, v[0], int(v[3]), int(v[4]))
            assert np.abs(centre - (e.centre[0], -e.centre[1])).max() <= 1e-9
        here = end

    # full circles go in three 120° pieces (an SVG arc cannot end where it starts)
    circle = _svg_commands(groups["construction"].findall("svg:path", SVG_NS)[0].get("d"))
    assert [c for c, _ in circle] == ["M", "A", "A", "A", "Z"]
    for _, v in circle[1:4]:
        assert math.hypot(v[5], v[6]) == pytest.approx(8.0, abs=1e-12)


def test_svg_is_deterministic_and_checks_stroke(tmp_path):
    write_contours_svg(tmp_path / "a.svg", toy_gear_layers(), texts=TOY_TEXTS)
    write_contours_svg(tmp_path / "b.svg", toy_gear_layers(), texts=TOY_TEXTS)
    assert (tmp_path / "a.svg").read_bytes() == (tmp_path / "b.svg").read_bytes()
    with pytest.raises(ValueError, match="stroke_mm"):
        write_contours_svg(tmp_path / "c.svg", toy_gear_layers(), stroke_mm=0)
    assert _names(tmp_path) == ["a.svg", "b.svg"]


# ----------------------------------------------------------------------------- PNG


def test_png_preview_from_the_dxf(tmp_path):
    import matplotlib.image

    dxf, png = tmp_path / "gear.dxf", tmp_path / "gear.png"
    write_contours_dxf(dxf, toy_gear_layers(), texts=TOY_TEXTS)
    render_dxf_png(dxf, png, dpi=60)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    img = matplotlib.image.imread(png)[..., :3]
    assert img.shape[0] >= 400 and img.shape[1] >= 400  # 8 in × 60 dpi on the long side
    corner = img[:5, :5].reshape(-1, 3)
    assert np.all(corner > 0.99)  # white background
    red = (img[..., 0] > 0.8) & (img[..., 1] < 0.3) & (img[..., 2] < 0.3)
    assert red.sum() > 200  # the CS layer is drawn in red
    with pytest.raises(ValueError, match="dpi"):
        render_dxf_png(dxf, tmp_path / "x.png", dpi=0)
