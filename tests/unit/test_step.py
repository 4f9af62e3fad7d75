"""STEP solids (profilegen.output.step), read back by OpenCASCADE and checked against geometry
computed here, independently of the writer:

* the CS ring of a *slot gear* (z slots of width 2w: two lines from the tip circle and a
  semicircle — lines, origin-centred arcs and off-centre arcs, like the CS chain) whose enclosed
  area has a closed form, and which also checks this file's exact chain area (chord shoelace +
  circular-segment terms);
* the FS cup of a small real gear set (z1 = 24, the DCTA tooth of :mod:`profilegen.geometry.fsform`):
  tooth-ring area by the same exact chain area, the revolved cup by Pappus (polygon centroid);
* the section of each solid at mid-face (a plane cut, the inner wire's edges sampled) against
  the line/arc chain the DXF draws, both ways, to 1e-6 mm;
* a file reads back as ONE valid solid (BRepCheck), and the same input gives the same bytes.

The default set's 2000-element chains take minutes to read back with OCCT's shape healing,
so they are checked by ``tests/benchmarks/step_write.py``, not here.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from profilegen.geometry.contour import Arc, Chain, ContourError, Line
from profilegen.errors import ExportError, GearSetError

OCP = pytest.importorskip("OCP", reason="cadquery-ocp-novtk (OpenCASCADE) is not installed")

from profilegen.output import step  # noqa: E402

TOL_MM = 1e-6


# ----------------------------------------------------------------------------- independent geometry


def chain_area_mm2(chain: Chain) -> float:
    """Signed area inside a closed line/arc chain: the shoelace over the element end points plus,
    for every arc, the circular segment between its chord and the arc, (R²/2)(θ − sin θ) with
    the sign of its sweep."""
    area = 0.0
    for e in chain.elements:
        area += 0.5 * (e.start[0] * e.end[1] - e.end[0] * e.start[1])
        if isinstance(e, Arc):
            th = abs(e.sweep)
            area += math.copysign(0.5 * e.radius ** 2 * (th - math.sin(th)), e.sweep)
    return area


def slot_gear(z: int, r_tip: float, r_slot: float, w: float) -> Chain:
    """z slots (width 2w, ending in a semicircle centred at radius r_slot) cut into a disc of
    radius r_tip, as a counter-clockwise chain: line out, semicircle, line in, tip arc."""
    els = []
    y0 = math.sqrt(r_tip ** 2 - w ** 2)
    half = math.atan2(w, y0)  # half the slot's angle on the tip circle
    for k in range(z):
        c = 2 * math.pi * k / z
        u, v = np.array([math.cos(c), math.sin(c)]), np.array([-math.sin(c), math.cos(c)])

        def at(x, y):  # x across the slot (toward increasing angle), y out along its axis
            return x * v + y * u

        els.append(Line(at(-w, y0), at(-w, r_slot)))
        els.append(Arc(at(0.0, r_slot), w, c - math.pi / 2, math.pi))
        els.append(Line(at(w, r_slot), at(w, y0)))
        els.append(Arc((0.0, 0.0), r_tip, c + half, 2 * math.pi / z - 2 * half))
    chain = Chain(tuple(els))
    chain.check(closed=True, gap_tol_mm=1e-12)
    return chain


def slot_gear_area_mm2(z: int, r_tip: float, r_slot: float, w: float) -> float:
    """Closed form: the disc plus z × (the slot outside the tip circle: rectangle to r_slot
    less the circular cap under it, plus the half disc)."""
    cap = w * math.sqrt(r_tip ** 2 - w ** 2) + r_tip ** 2 * math.asin(w / r_tip)  # ∫_{-w}^{w} √(r²−x²) dx
    return math.pi * r_tip ** 2 + z * (2 * w * r_slot - cap + 0.5 * math.pi * w ** 2)


def polygon_pappus_volume(rz) -> float:
    """Volume of a closed (r, z) polygon revolved about the z axis: 2π · area · centroid radius,
    i.e. π Σ (r_i + r_{i+1})(r_i z_{i+1} − r_{i+1} z_i) / 3."""
    p = np.asarray(rz, float)
    r, zz = p[:, 0], p[:, 1]
    r1, z1 = np.roll(r, -1), np.roll(zz, -1)
    return abs(math.pi / 3.0 * float(np.sum((r + r1) * (r * z1 - r1 * zz))))


# ----------------------------------------------------------------------------- OCCT read-back helpers


def read_step(path: Path):
    from OCP.STEPControl import STEPControl_Reader
    from OCP.IFSelect import IFSelect_RetDone

    r = STEPControl_Reader()
    assert r.ReadFile(str(path)) == IFSelect_RetDone
    assert r.TransferRoots() >= 1
    return r.OneShape()


def solids_of(shape) -> list:
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    exp, out = TopExp_Explorer(shape, TopAbs_SOLID), []
    while exp.More():
        out.append(exp.Current())
        exp.Next()
    return out


def volume_mm3(shape) -> float:
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    p = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, p)
    return p.Mass()


def count_faces(shape) -> int:
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer

    exp, n = TopExp_Explorer(shape, TopAbs_FACE), 0
    while exp.More():
        n += 1
        exp.Next()
    return n


def is_valid(shape) -> bool:
    from OCP.BRepCheck import BRepCheck_Analyzer

    return BRepCheck_Analyzer(shape).IsValid()


def section_edges(shape, z: float, *, per_edge: int = 9):
    """Cut the solid with the plane z = const; per edge of the cut: sampled points (x, y), the
    edge's length and its end points."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Section
    from OCP.GCPnts import GCPnts_AbscissaPoint
    from OCP.gp import gp_Dir, gp_Pln, gp_Pnt
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    sec = BRepAlgoAPI_Section(shape, gp_Pln(gp_Pnt(0.0, 0.0, z), gp_Dir(0.0, 0.0, 1.0)))
    sec.Build()
    assert sec.IsDone()
    exp, out = TopExp_Explorer(sec.Shape(), TopAbs_EDGE), []
    while exp.More():
        c = BRepAdaptor_Curve(TopoDS.Edge(exp.Current()))
        ts = np.linspace(c.FirstParameter(), c.LastParameter(), per_edge)
        pts = np.array([[c.Value(t).X(), c.Value(t).Y(), c.Value(t).Z()] for t in ts])
        assert np.allclose(pts[:, 2], z, atol=1e-9)
        out.append((pts[:, :2], GCPnts_AbscissaPoint.Length_s(c), pts[[0, -1], :2]))
        exp.Next()
    return out


def compare_section(edges, chain: Chain, *, inner: bool, split_radius: float) -> dict:
    """The cut's edges on the chain's side of ``split_radius`` against the chain: every sampled
    point on the chain, every chain vertex at an edge end, equal total length (so the cut covers
    the whole chain, not a part of it). Returns the numbers."""
    mine = [e for e in edges if (np.hypot(*e[0].T).max() < split_radius) == inner]
    pts = np.vstack([e[0] for e in mine])
    ends = np.vstack([e[2] for e in mine])
    vertex = np.array([e.start for e in chain.elements])
    d_vertex = np.array([np.hypot(*(ends - v).T).min() for v in vertex])
    return {
        "edges": len(mine),
        "point_to_chain_mm": float(chain.distance(pts).max()),
        "vertex_to_cut_mm": float(d_vertex.max()),
        "length_mm": sum(e[1] for e in mine),
        "chain_length_mm": chain.length,
    }


# ----------------------------------------------------------------------------- the circular spline

Z_SLOTS, R_TIP, R_SLOT, W_SLOT, FACE_MM, D_OUT = 24, 20.0, 21.0, 0.6, 5.0, 50.0


def cs_standin(chain: Chain, *, outer_diameter_mm=D_OUT, root_radius_mm=R_SLOT + W_SLOT):
    """The parts of a Design that write_cs_step reads."""
    gearset = SimpleNamespace(cup=SimpleNamespace(face_width_mm=FACE_MM),
                              circular_spline=SimpleNamespace(outer_diameter_mm=outer_diameter_mm),
                              gear=SimpleNamespace(module_mm=0.5))
    return SimpleNamespace(gearset=gearset, profile=SimpleNamespace(outline=chain),
                           form=SimpleNamespace(root_radius_mm=root_radius_mm))


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_step")


@pytest.fixture(scope="module", params=[1000, 30], ids=["one cap face", "cap sectors"])
def cs_case(request, tmp_path_factory):
    """The slot gear's ring with its caps as one face each, and cut into sectors of <= 30 edges
    (as the default set's 2828-edge outline is, in sectors of <= 500)."""
    chain = slot_gear(Z_SLOTS, R_TIP, R_SLOT, W_SLOT).reversed()  # clockwise, like the CS outline
    path = tmp_path_factory.mktemp("cs") / "circular_spline.step"
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(step, "_MAX_CAP_EDGES", request.param)
        step.write_cs_step(path, cs_standin(chain))
    shape = read_step(path)
    faces = count_faces(shape)
    sectors = 1 if request.param > len(chain.elements) else math.ceil(len(chain.elements) / request.param)
    assert faces == len(chain.elements) + sectors * 3  # sides + outer cylinder patches + both caps
    return chain, path, shape, request.param


def test_chain_area_formula_against_the_slot_gear_closed_form():
    chain = slot_gear(Z_SLOTS, R_TIP, R_SLOT, W_SLOT)
    exact = slot_gear_area_mm2(Z_SLOTS, R_TIP, R_SLOT, W_SLOT)
    assert chain_area_mm2(chain) == pytest.approx(exact, rel=1e-13)
    assert chain_area_mm2(chain.reversed()) == pytest.approx(-exact, rel=1e-13)


def test_cs_file_is_one_valid_solid_of_the_right_volume(cs_case):
    chain, _, shape, _ = cs_case
    solids = solids_of(shape)
    assert len(solids) == 1
    assert is_valid(solids[0])
    expected = (math.pi * (D_OUT / 2) ** 2 - abs(chain_area_mm2(chain))) * FACE_MM
    assert volume_mm3(solids[0]) == pytest.approx(expected, rel=1e-9)  # the issue asks 1e-3


def test_cs_section_at_mid_face_is_the_chain(cs_case):
    chain, _, shape, _ = cs_case
    got = compare_section(section_edges(shape, FACE_MM / 2), chain, inner=True, split_radius=D_OUT / 2 - 1.0)
    assert got["edges"] == len(chain.elements)  # one edge per line / arc: true lines and arcs, not a polyline
    assert got["point_to_chain_mm"] < TOL_MM
    assert got["vertex_to_cut_mm"] < TOL_MM
    assert got["length_mm"] == pytest.approx(got["chain_length_mm"], abs=TOL_MM)


def test_cs_file_is_deterministic(cs_case, tmp_path):
    chain, path, _, max_edges = cs_case
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(step, "_MAX_CAP_EDGES", max_edges)
        again = step.write_cs_step(tmp_path / "again.step", cs_standin(chain))
    data = path.read_bytes()
    assert again.read_bytes() == data
    header = data[: data.index(b"ENDSEC;")].decode()
    assert "FILE_NAME('circular_spline','2000-01-01T00:00:00',('profilegen')" in header
    assert str(tmp_path) not in data.decode() and "Open CASCADE STEP translator" not in data.decode()


def test_cs_outer_diameter_inside_the_root_circle_is_named(tmp_path):
    chain = slot_gear(6, R_TIP, R_SLOT, W_SLOT)
    for d_out, root in ((2 * (R_SLOT + W_SLOT) + 1.0, R_SLOT + W_SLOT), (40.0, 20.0)):  # wall 0.5 mm < 2m; inside
        with pytest.raises(GearSetError, match="circular_spline.outer_diameter_mm"):
            step.write_cs_step(tmp_path / "x.step", cs_standin(chain, outer_diameter_mm=d_out, root_radius_mm=root))
    assert not list(tmp_path.iterdir())


def test_reader_names_an_outer_diameter_inside_the_root_circle(tmp_path):
    from profilegen.gearset import default_gearset_path, load_gearset

    text = Path(default_gearset_path()).read_text()
    assert load_gearset(default_gearset_path()).circular_spline.outer_diameter_mm == 128.0  # 1.25 × 102.05, up
    bad = tmp_path / "bad.toml"
    bad.write_text(text + "\n[circular_spline]\nouter_diameter_mm = 103.0\n")  # root diameter 102.05 mm
    with pytest.raises(GearSetError, match=r"circular_spline\.outer_diameter_mm = 103(\.0)? mm"):
        load_gearset(bad)


def test_unwritable_path_is_an_export_error_and_leaves_nothing(tmp_path):
    chain = slot_gear(6, R_TIP, R_SLOT, W_SLOT)
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    with pytest.raises(ExportError, match="circular_spline.step"):
        step.write_cs_step(blocker / "circular_spline.step", cs_standin(chain))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file"]
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    try:
        if not os.access(ro, os.W_OK):  # root writes into a read-only folder: only the case above then
            with pytest.raises(ExportError, match="circular_spline.step"):
                step.write_cs_step(ro / "circular_spline.step", cs_standin(chain))
            assert list(ro.iterdir()) == []
    finally:
        ro.chmod(0o700)


def test_open_or_polyline_chain_refused():
    chain = slot_gear(6, R_TIP, R_SLOT, W_SLOT)
    with pytest.raises(ContourError, match="gap"):
        step.cs_solid(Chain(chain.elements[:-1]), outer_radius_mm=25.0, face_width_mm=1.0)
    with pytest.raises(GearSetError, match="cup.face_width_mm"):
        step.cs_solid(chain, outer_radius_mm=25.0, face_width_mm=0.0)


# ----------------------------------------------------------------------------- the flexspline


@pytest.fixture(scope="module")
def fs_case(tmp_path_factory):
    from profilegen.geometry.fsform import flexspline_outline
    from profilegen.gearset import default_gearset_path, load_gearset
    from profilegen.geometry.teeth import tooth_from_gearset

    text = Path(default_gearset_path()).read_text()
    text = text.replace("flexspline_teeth = 200", "flexspline_teeth = 24").replace(
        "circular_spline_teeth = 202", "circular_spline_teeth = 26")
    folder = tmp_path_factory.mktemp("fs")
    (folder / "small.toml").write_text(text)
    gs = load_gearset(folder / "small.toml")
    tooth = tooth_from_gearset(gs)
    chain, _ = flexspline_outline(tooth, gs.gear)
    with pytest.MonkeyPatch.context() as mp:  # caps in 3 sectors (240 edges), as the default set's are
        mp.setattr(step, "_MAX_CAP_EDGES", 100)
        path = step.write_fs_step(folder / "flexspline.step", SimpleNamespace(gearset=gs, tooth=tooth))
    return gs, chain, path, read_step(path)


def test_fs_file_is_one_valid_solid_of_the_right_volume(fs_case):
    gs, chain, _, shape = fs_case
    solids = solids_of(shape)
    assert len(solids) == 1
    assert is_valid(solids[0])
    g, cup = gs.gear, gs.cup
    r_b, r_w = g.neutral_radius_mm - g.rim_thickness_mm / 2, g.neutral_radius_mm + g.rim_thickness_mm / 2
    t, b, l, r0 = cup.bottom_thickness_mm, cup.face_width_mm, cup.length_mm, cup.boss_radius_mm
    h0 = step.BOSS_THICKNESS_PER_BOTTOM * t
    ring = (chain_area_mm2(chain) - math.pi * r_b ** 2) * b
    meridian = [(0, t - h0), (r0, t - h0), (r0, 0), (r_w, 0), (r_w, l - b / 2), (r_b, l - b / 2), (r_b, t), (0, t)]
    expected = ring + polygon_pappus_volume(meridian)
    assert volume_mm3(solids[0]) == pytest.approx(expected, rel=1e-9)


def test_fs_section_at_mid_face_is_the_chain(fs_case):
    gs, chain, _, shape = fs_case
    r_b = gs.gear.neutral_radius_mm - gs.gear.rim_thickness_mm / 2
    got = compare_section(section_edges(shape, gs.cup.length_mm), chain, inner=False, split_radius=r_b + 1e-3)
    assert got["point_to_chain_mm"] < TOL_MM
    assert got["vertex_to_cut_mm"] < TOL_MM
    assert got["length_mm"] == pytest.approx(got["chain_length_mm"], abs=TOL_MM)


def test_fs_cup_inputs_named():
    chain = slot_gear(6, R_TIP, R_SLOT, W_SLOT)
    base = dict(bore_radius_mm=15.0, wall_outer_radius_mm=16.0, length_mm=30.0, face_width_mm=5.0,
                bottom_thickness_mm=1.0, boss_radius_mm=5.0, boss_thickness_mm=3.0)
    for key, value, name in (("boss_radius_mm", 15.0, "cup.boss_radius_mm = 15 mm"), ("length_mm", 3.0, "cup.length_mm = 3 mm"),
                             ("bore_radius_mm", 20.5, "bore radius = 20.5 mm")):
        with pytest.raises(GearSetError, match=name):
            step.fs_solid(chain, **{**base, key: value, "wall_outer_radius_mm": max(16.0, value + 1.0)})
