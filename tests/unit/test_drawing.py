"""The dimensioned drawing of the circular spline (profilegen.output.drawing, issue 17 item 3).

Read back with ezdxf and checked against the design's own geometry, not against the writer's
layout: every arc of the tooth space that has a centre near the space (or its mirror twin
about the space's axis, then marked "2x") carries a radius DIMENSION whose measured length ×
DIMLFAC (the detail's 1/scale) is the arc's radius and whose point lies on the arc; a concave arc (its centre on the air side, decided here from the bore
polygon, independently of the writer's sweep-sign rule) is labelled so; the diameters are
2 × the tip, root and outer radii; the element table holds each element's numbers; the title
block the version, units, projection; the same input gives the same bytes.
"""

from __future__ import annotations

import math
import re

import ezdxf
import numpy as np
import pytest
from shapely.geometry import Point, Polygon

import profilegen as pg
from profilegen.geometry.contour import Arc, Line
from profilegen.errors import ExportError
from profilegen.output import cad
from profilegen.output.drawing import DIMENSION_LAYER, drawing_date, write_cs_drawing


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_drawing")


@pytest.fixture(scope="module")
def design(default_sketch):
    return default_sketch  # conftest.py: the default set's sketch design, once per worker


@pytest.fixture(scope="module")
def drawn(design, tmp_path_factory):
    path = tmp_path_factory.mktemp("drawing") / "circular_spline_drawing.dxf"
    write_cs_drawing(path, design, date="2026-01-31")
    return path, ezdxf.readfile(path)


def _texts(doc) -> list[str]:
    return [t.dxf.text for t in doc.modelspace().query("TEXT")]


def _dims(doc, kind: int) -> list:
    return [d for d in doc.modelspace().query("DIMENSION") if d.dimtype & 7 == kind]


def _true_length(dim) -> float:
    return dim.get_measurement() * dim.override().get("dimlfac", 1.0)


def test_audit_clean_layers_and_units(drawn):
    path, doc = drawn
    assert cad.audit(path) == 0
    assert {"CS", "FS", "WG", "construction", "annotation", DIMENSION_LAYER} <= {layer.dxf.name for layer in doc.layers}
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1
    dims = list(doc.modelspace().query("DIMENSION"))
    assert dims and all(d.dxf.layer == DIMENSION_LAYER for d in dims)
    assert all(d.dxf.geometry in doc.blocks for d in dims)  # each rendered to its block (CAD programs show it)


def _mirror(p, axis):
    return 2.0 * float(np.dot(p, axis)) * axis - np.asarray(p)


def test_every_arc_has_its_radius(design, drawn):
    _, doc = drawn
    space = design.profile.space
    axis = space.start / np.hypot(*space.start) + space.end / np.hypot(*space.end)
    axis /= np.hypot(*axis)  # the space's axis
    bore = Polygon(design.profile.outline.sample(1e-4))  # the air inside the CS
    dims = _dims(doc, 4)
    near = [a for a in space.elements if isinstance(a, Arc) and np.hypot(*a.centre) > 1.0]
    far = [a for a in space.elements if isinstance(a, Arc) and np.hypot(*a.centre) <= 1.0]
    assert len(near) >= 4

    def on_arc(d, a) -> bool:  # the dimension's point lies on the arc: its direction within the sweep
        v = (d.dxf.defpoint4.x - d.dxf.defpoint.x, d.dxf.defpoint4.y - d.dxf.defpoint.y)  # (the detail
        frac = ((math.atan2(v[1], v[0]) - a.start_angle) * math.copysign(1.0, a.sweep)) % (2 * math.pi)  # keeps them)
        return frac <= abs(a.sweep) + 1e-9

    used = set()
    for a in near:
        mid = a.point_at(a.start_angle + 0.5 * a.sweep)
        toward_centre = mid + 1e-3 * (a.centre - mid) / a.radius
        concave = bore.contains(Point(*toward_centre))  # the centre side is air: hollow in the part
        twins = [b for b in near if b is not a and abs(b.radius - a.radius) < 1e-9
                 and np.allclose(b.centre, _mirror(a.centre, axis), atol=1e-9)]
        text = ("2x " if twins else "") + f"R{a.radius:.4f}" + (" concave" if concave else "")
        match = [k for k, d in enumerate(dims) if abs(_true_length(d) - a.radius) <= 1e-9 and d.dxf.text == text
                 and any(on_arc(d, b) for b in [a, *twins])]
        assert len(match) == 1, f"not one radius dimension for the arc R{a.radius} at {a.centre}: {len(match)}"
        used.add(match[0])
    assert used == set(range(len(dims)))  # no other radius dimension
    for a in far:  # about the gear axis (the root): a note, the diameter in the ring view
        assert any(f"R{a.radius:.4f} concave (root circle)" in t for t in _texts(doc))


def test_diameters(design, drawn):
    _, doc = drawn
    form = design.form
    dims = _dims(doc, 3)
    want = sorted(2 * r for r in (form.tip_radius_mm, form.root_radius_mm, form.outer_radius_mm))
    assert sorted(_true_length(d) for d in dims) == pytest.approx(want, abs=1e-9)
    for d in dims:
        assert d.dxf.text.startswith(f"%%c{_true_length(d):.4f}")


def test_element_table_and_notes(design, drawn):
    _, doc = drawn
    texts = set(_texts(doc))
    for i, e in enumerate(design.profile.space.elements):
        assert str(i + 1) in texts
        if isinstance(e, Arc):
            assert {f"R{e.radius:.4f}", f"{e.centre[0]:.4f}".replace("-0.0000", "0.0000"), f"{e.centre[1]:.4f}",
                    f"{math.degrees(e.sweep):+.4f}"} <= texts
        else:
            d = e.end - e.start
            angle = math.degrees(math.atan(d[0] / d[1]))  # the line's angle to the y axis, clockwise +
            assert {f"{e.length:.4f}", f"{e.start[0]:.4f}", f"{e.start[1]:.4f}", f"{angle:+.4f}"} <= texts
    gear, err = design.gearset.gear, design.profile.max_error_mm
    note = " ".join(sorted(texts))
    assert f"z2 = {gear.circular_spline_teeth} teeth, module m = {gear.module_mm:g} mm" in note
    assert f"%%p{err:.4f} mm (%%p{err * 1e3:.1f} µm)" in note  # the profile tolerance: ± the fit's deviation
    assert f"{2 * err:.4f}" in texts  # ... and its zone in the feature control frame


def test_title_block(design, drawn):
    _, doc = drawn
    texts = set(_texts(doc))
    assert {f"profilegen {pg.__version__}", "mm", "first angle", design.gearset.name, design.scene.name,
            "2026-01-31"} <= texts
    assert any(re.fullmatch(r"1:1  \(detail A \d+:1\)", t) for t in texts)  # the default ring fits at 1:1


def test_outline_true_size_at_the_origin(design, drawn):
    _, doc = drawn
    msp = doc.modelspace()
    lines = np.array([[*e.dxf.start.vec2, *e.dxf.end.vec2] for e in msp.query('LINE[layer=="CS"]')])
    arcs = np.array([[*e.dxf.center.vec2, e.dxf.radius] for e in msp.query('ARC[layer=="CS"]')])
    # every outline element is in the file as it is (the ring view is 1:1, its centre the origin)
    for e in design.profile.outline.elements:
        if isinstance(e, Line):  # DXF keeps a line's direction
            assert np.min(np.abs(lines - [*e.start, *e.end]).max(axis=1)) < 1e-12
        else:
            assert np.min(np.abs(arcs - [*e.centre, e.radius]).max(axis=1)) < 1e-12


def test_same_bytes_and_the_date(design, drawn, tmp_path, monkeypatch):
    path, _ = drawn
    again = tmp_path / "again.dxf"
    write_cs_drawing(again, design, date="2026-01-31")
    assert again.read_bytes() == path.read_bytes()
    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)
    blank, stamped = tmp_path / "blank.dxf", tmp_path / "stamped.dxf"
    write_cs_drawing(blank, design)
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1767139200")  # 2025-12-31T00:00:00Z
    write_cs_drawing(stamped, design)
    dates = re.compile(rb"^\d{4}-\d\d-\d\d$", re.MULTILINE)  # a DXF value line that is a date
    assert dates.findall(path.read_bytes()) == [b"2026-01-31"]
    assert dates.findall(stamped.read_bytes()) == [b"2025-12-31"]
    assert dates.findall(blank.read_bytes()) == []


def test_bad_date_and_unwritable_path(design, tmp_path, monkeypatch):
    with pytest.raises(ValueError, match="date"):
        write_cs_drawing(tmp_path / "x.dxf", design, date="31.01.2026")
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "yesterday")
    with pytest.raises(ValueError, match="SOURCE_DATE_EPOCH"):
        drawing_date()
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(ExportError, match="file"):
        write_cs_drawing(blocker / "x.dxf", design, date="2026-01-31")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]  # nothing partial


def test_drawings_made_by_the_figure_workers_carry_the_face_stage(default_design_scene):
    """The CS and FS drawings made by the figure workers' jobs (output.files.file_jobs: the
    design slimmed to what the files read) say the face stage's design section and FS
    modification, as the drawings made in this process do — not "NOT THE PART TO CUT: this scene
    has no face stage" for a design scene that ran it (it did before 2026-11-28: the jobs emptied
    ``face``, so `profilegen design`'s own drawings of the default set said so)."""
    import io

    from profilegen.face.coning import UNDECIDED, modification_lines
    from profilegen.output import files

    d = default_design_scene
    assert d.face is not None
    want = modification_lines(d)
    assert want != [UNDECIDED] and "design section z =" in want[0]
    made = {}
    for fn, args in files.file_jobs(d).values():
        made.update(fn(*args))
    for name in ("circular_spline_drawing.dxf", "flexspline_tooth.dxf", "flexspline.dxf"):
        text = " ".join(e.dxf.text if e.dxftype() == "TEXT" else e.text
                        for e in ezdxf.read(io.StringIO(made[name].decode("utf-8"))).modelspace()
                        if e.dxftype() in ("TEXT", "MTEXT"))
        flat = re.sub(r"\s+", " ", text)
        assert "NOT THE PART TO CUT" not in flat, name
        assert f"design section z = {d.face.design_section_z_mm:g} mm" in flat, name
