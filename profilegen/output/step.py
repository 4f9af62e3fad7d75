"""STEP solids (ISO 10303-21, AP214, mm) of the circular spline and the undeformed flexspline cup.

Both solids are built from the same line/arc chains the DXF files draw, as true B-rep lines and
circles — not from polylines and not by cutting z spaces one boolean at a time:

* :func:`cs_solid` — one planar face bounded by the outer circle (``[circular_spline]
  outer_diameter_mm``) with the CS outline chain as its hole, extruded over the face width
  (``[cup] face_width_mm``), z ∈ [0, b];
* :func:`fs_solid` — the tooth ring (the face between the bore circle and the FS outline of all
  z1 teeth, extruded over z ∈ [l − b/2, l + b/2], l = ``[cup] length_mm`` from the cup bottom to
  the ring's mid-face) fused once with the revolved cup body: the wall (bore r_m − δ/2, outer
  radius r_m + δ/2, δ = ``gear.rim_thickness_mm``) from the bottom to the ring, the bottom plate
  (``bottom_thickness_mm``, z ∈ [0, t]) and the boss (radius ``boss_radius_mm``, axial thickness
  :data:`BOSS_THICKNESS_PER_BOTTOM` × t from the inner bottom face outward — an ESTIMATE: the
  gear set has no field for it). The wall beyond the ring keeps the rim thickness, the corners
  are sharp, and the boss has no holes: a body to mesh against and to check, not a drawing of
  the maker's cup.

The files are deterministic (same input, same bytes): the header's name, time stamp, author,
organisation and system are fixed, and the product is named after the part. They are written
through :func:`profilegen.output.export.atomic_write` (temporary file in the same folder, then
``os.replace``): a failed run leaves no partial file, an unwritable path is an ExportError.

The B-rep kernel is OpenCASCADE through CadQuery's OCP bindings (the ``cadquery-ocp-novtk``
wheel, the one build123d itself depends on). It takes ~2–7 s to import, so it is imported
inside the functions here, never at the import of :mod:`profilegen` or of the output layer.
"""

from __future__ import annotations

import functools
import io
import math
import os
import threading
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..geometry.contour import Arc, Chain, ContourError, Line
from ..errors import ExportError, GearSetError
from ..gearset.sections import CS_MIN_WALL_PER_MODULE, CS_OUTER_DIAMETER_PER_ROOT

if TYPE_CHECKING:  # pragma: no cover
    from ..pipeline.design import Design

__all__ = [
    "BOSS_THICKNESS_PER_BOTTOM",
    "cs_outer_radius_mm",
    "cs_solid",
    "fs_solid",
    "fs_outline",
    "step_bytes",
    "write_cs_step",
    "write_fs_step",
]

#: The boss's axial thickness in units of the cup's bottom thickness (ESTIMATE: the gear set
#: has no boss-thickness field; a boss is typically a few bottom thicknesses thick).
BOSS_THICKNESS_PER_BOTTOM = 3.0


_CLOSE_TOL_MM = 1e-6  # a chain must close within this to bound a face
_MAX_CAP_EDGES = 500  # most outline edges in one planar cap face (see _ring_sectors)
_LOCK = threading.Lock()  # OCCT's message printers and Interface_Static parameters are process-global
_HEADER = {"timestamp": "2000-01-01T00:00:00", "author": "profilegen", "system": "profilegen"}


# ----------------------------------------------------------------------------- the kernel


#: the one line a user without the kernel gets from ``--step`` / :func:`write_step`
MISSING_KERNEL = ("STEP needs OpenCASCADE, an optional extra of profilegen: pip install 'profilegen[step]' "
                  "(in a checkout: pip install -e '.[step]')")


def available() -> bool:
    """Whether the B-rep kernel (``cadquery-ocp-novtk``, the ``step`` extra) is installed, without importing it."""
    import importlib.util

    return importlib.util.find_spec("OCP") is not None


def require() -> None:
    """Raise :class:`ExportError` naming the ``step`` extra when the kernel is not installed: the
    CLI calls it before any stage runs, so ``--step`` fails in its first second, not after the design."""
    if not available():
        raise ExportError(MISSING_KERNEL)


@functools.cache
def _occ() -> Any:
    """The OCP modules used here, imported on first use (the import takes seconds)."""
    from types import SimpleNamespace

    require()
    from OCP import BRepAlgoAPI, BRepBuilderAPI, BRepPrimAPI, STEPControl, TopAbs, TopExp, TopoDS
    from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
    from OCP.BOPAlgo import BOPAlgo_GlueEnum
    from OCP.BRep import BRep_Builder
    from OCP.collections import List_TopoDS_Shape
    from OCP.gp import gp_Ax1, gp_Ax2, gp_Circ, gp_Dir, gp_Pnt, gp_Vec
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.Interface import Interface_Static
    from OCP.Message import Message, Message_Gravity
    from OCP.TCollection import TCollection_HAsciiString

    return SimpleNamespace(
        BRepAlgoAPI=BRepAlgoAPI, BRepBuilderAPI=BRepBuilderAPI, BRepPrimAPI=BRepPrimAPI, STEPControl=STEPControl,
        TopAbs=TopAbs, TopExp=TopExp, TopoDS=TopoDS, MakeHeader=APIHeaderSection_MakeHeader, BRep_Builder=BRep_Builder,
        gp_Ax1=gp_Ax1, gp_Ax2=gp_Ax2, gp_Circ=gp_Circ, gp_Dir=gp_Dir, gp_Pnt=gp_Pnt, gp_Vec=gp_Vec,
        RetDone=IFSelect_RetDone, Static=Interface_Static, Message=Message, Gravity=Message_Gravity,
        HString=TCollection_HAsciiString, Glue=BOPAlgo_GlueEnum, ShapeList=List_TopoDS_Shape,
    )


def _signed_area_mm2(chain: Chain) -> float:
    """Signed area of a closed chain (> 0 counter-clockwise), exact for lines and arcs:
    ½∮(x dy − y dx), an arc adding ½[R²·sweep + R·(cx·Δsin − cy·Δcos)]. Only its sign is used
    here, to orient the wire."""
    total = 0.0
    for e in chain.elements:
        if isinstance(e, Line):
            total += e.start[0] * e.end[1] - e.end[0] * e.start[1]
        else:
            a0, a1 = e.start_angle, e.end_angle
            total += e.radius ** 2 * e.sweep + e.radius * (e.centre[0] * (math.sin(a1) - math.sin(a0))
                                                           - e.centre[1] * (math.cos(a1) - math.cos(a0)))
    return 0.5 * float(total)


def _check_chain(chain: Chain, what: str) -> None:
    if not isinstance(chain, Chain):
        raise TypeError(f"{what} must be a profilegen.geometry.contour.Chain, got {type(chain).__name__}")
    bad = next((e for e in chain.elements if not isinstance(e, (Line, Arc))), None)
    if bad is not None:
        raise ContourError(f"{what}: a STEP solid is built from lines and arcs only, got a {type(bad).__name__}")
    gap = chain.gaps(closed=True)
    if gap.max() > _CLOSE_TOL_MM:
        k = int(np.argmax(gap))
        raise ContourError(f"{what}: the chain does not close: gap of {gap[k]:.3e} mm after element {k} "
                          f"(tolerance {_CLOSE_TOL_MM:g} mm)")


_SLIVER_MM = 1e-7
"""OpenCascade's Precision::Confusion (mm here): shorter elements are left out of a wire."""


def _chain_wire(chain: Chain, z: float, *, ccw: bool):
    """The chain as one closed wire at height z, running counter-clockwise if ``ccw``.

    Consecutive edges share one vertex (the start of the next element), so the wire is closed
    topologically, not only within a tolerance; arcs are circles about ±z trimmed at those vertices."""
    o = _occ()
    if (_signed_area_mm2(chain) > 0) != ccw:
        chain = chain.reversed()
    # an element shorter than OpenCascade's confusion tolerance makes no edge (a fitted arc that a root
    # fillet trimmed to a sliver: 1.1e-8 mm at z1 = 20, sketch scene); its neighbours meet across it
    els = [e for e in chain.elements if e.length >= _SLIVER_MM] or list(chain.elements)
    mk_vertex = o.BRepBuilderAPI.BRepBuilderAPI_MakeVertex
    verts = [mk_vertex(o.gp_Pnt(float(e.start[0]), float(e.start[1]), z)).Vertex() for e in els]
    up, down = o.gp_Dir(0.0, 0.0, 1.0), o.gp_Dir(0.0, 0.0, -1.0)
    builder = o.BRep_Builder()
    wire = o.TopoDS.TopoDS_Wire()
    builder.MakeWire(wire)
    mk_edge = o.BRepBuilderAPI.BRepBuilderAPI_MakeEdge
    n = len(els)
    for i, e in enumerate(els):
        v0, v1 = verts[i], verts[(i + 1) % n]
        if isinstance(e, Line):
            edge = mk_edge(v0, v1)
        else:
            axis = o.gp_Ax2(o.gp_Pnt(float(e.centre[0]), float(e.centre[1]), z), up if e.sweep > 0 else down)
            edge = mk_edge(o.gp_Circ(axis, float(e.radius)), v0, v1)
        if not edge.IsDone():
            what = "a line" if isinstance(e, Line) else f"an arc of radius {e.radius:.4g} mm"
            raise ExportError(f"STEP: element {i} of the outline, {what} {e.length:.3g} mm long, makes no edge in "
                              "OpenCascade: circular_spline.corners = \"sharp\" leaves the fillets (and the slivers "
                              "they trim) out; the DXF files need no --step")
        builder.Add(wire, edge.Edge())
    wire.Closed(True)
    return wire


def _circle_wire(radius_mm: float, z: float, *, ccw: bool):
    o = _occ()
    axis = o.gp_Ax2(o.gp_Pnt(0.0, 0.0, z), o.gp_Dir(0.0, 0.0, 1.0 if ccw else -1.0))
    edge = o.BRepBuilderAPI.BRepBuilderAPI_MakeEdge(o.gp_Circ(axis, float(radius_mm))).Edge()
    return o.BRepBuilderAPI.BRepBuilderAPI_MakeWire(edge).Wire()


def _ring_prism(outer_wire, inner_wire, height_mm: float):
    """The planar face between two wires (outer counter-clockwise, inner clockwise) extruded along +z."""
    o = _occ()
    mf = o.BRepBuilderAPI.BRepBuilderAPI_MakeFace(outer_wire, True)
    mf.Add(inner_wire)
    if not mf.IsDone():
        raise ExportError("STEP: the ring face could not be built from its wires")
    prism = o.BRepPrimAPI.BRepPrimAPI_MakePrism(mf.Face(), o.gp_Vec(0.0, 0.0, float(height_mm)))
    return prism.Shape()


def _ring_sectors(outline: Chain, circle_radius_mm: float, z: float, height_mm: float) -> list:
    """The ring between ``outline`` and a circle about the origin (outside or inside it) as
    prisms of a few sectors, each bounded by a stretch of the outline, two radial lines and an
    arc of the circle; an empty list if the outline has no place to cut (see below).

    Why: OCCT's shape healing on reading (ShapeFix_Wire's self-intersection check, cubic in the
    edges of one wire) took 524 s to read back a CS ring whose caps were one face bounded by the
    2828-edge outline; with caps of at most :data:`_MAX_CAP_EDGES` edges it takes ~10 s — and
    other OCCT-based CAD (FreeCAD) reads the same way. The cuts start at tip lands of the CS /
    root lands of the FS — origin-centred arcs at the outline's smallest radius — so each radial
    line runs through solid material (a tooth of the CS, the rim of the FS) and meets the
    outline only at its end."""
    if _signed_area_mm2(outline) < 0:
        outline = outline.reversed()  # counter-clockwise: each stretch runs from a0 to a1 > a0
    els = outline.elements
    r_min = _radius_range_mm(outline)[0]
    lands = [i for i, e in enumerate(els) if isinstance(e, Arc) and float(np.hypot(*e.centre)) < 1e-9
             and abs(e.radius - r_min) < 1e-9]
    sectors = min(len(lands), math.ceil(len(els) / _MAX_CAP_EDGES))
    if sectors < 2:
        return []
    cuts = [lands[(k * len(lands)) // sectors] for k in range(sectors)]
    outside = circle_radius_mm > r_min
    out = []
    for a, b in zip(cuts, cuts[1:] + [cuts[0] + len(els)]):
        stretch = [els[i % len(els)] for i in range(a, b)]
        v0, v1 = stretch[0].start, stretch[-1].end
        a0, a1 = math.atan2(v0[1], v0[0]), math.atan2(v1[1], v1[0])
        p0, p1 = (circle_radius_mm * np.array([math.cos(x), math.sin(x)]) for x in (a0, a1))
        sweep = (a1 - a0) % (2.0 * math.pi)
        back = Arc((0.0, 0.0), circle_radius_mm, a1, -sweep)  # clockwise from a1 to a0
        loop = [Line(p0, v0), *stretch, Line(v1, p1), back] if outside else [*stretch, Line(v1, p1), back, Line(p0, v0)]
        wire = _chain_wire(Chain(tuple(loop)), z, ccw=True)
        face = _occ().BRepBuilderAPI.BRepBuilderAPI_MakeFace(wire, True)
        if not face.IsDone():
            raise ExportError("STEP: a sector face of the ring could not be built")
        out.append(_occ().BRepPrimAPI.BRepPrimAPI_MakePrism(face.Face(), _occ().gp_Vec(0.0, 0.0, float(height_mm))).Shape())
    return out


def _fuse(shapes: list, glue, what: str):
    o = _occ()
    fuse = o.BRepAlgoAPI.BRepAlgoAPI_Fuse()
    fuse.SetArguments(_shape_list(shapes[0]))
    fuse.SetTools(_shape_list(*shapes[1:]))
    fuse.SetGlue(glue)
    fuse.Build()
    if not fuse.IsDone():
        raise ExportError(f"STEP: fusing the {what}'s pieces failed")
    return fuse.Shape()


def _shape_list(*shapes):
    out = _occ().ShapeList()
    for s in shapes:
        out.Append(s)
    return out


def _one_solid(shape, what: str):
    o = _occ()
    exp = o.TopExp.TopExp_Explorer(shape, o.TopAbs.TopAbs_SOLID)
    solids = []
    while exp.More():
        solids.append(o.TopoDS.TopoDS.Solid(exp.Current()))
        exp.Next()
    if len(solids) != 1:
        raise ExportError(f"STEP: the {what} came out as {len(solids)} solids, not one")
    return solids[0]


def _radius_range_mm(chain: Chain) -> tuple[float, float]:
    """The smallest and largest distance of the chain from the origin (exact for lines and arcs)."""
    lo, hi = math.inf, 0.0
    for e in chain.elements:
        ends = (float(np.hypot(*e.start)), float(np.hypot(*e.end)))
        lo, hi = min(lo, *ends), max(hi, *ends)
        if isinstance(e, Line):
            lo = min(lo, float(e.distance(np.zeros((1, 2)))[0]))
        else:
            c = float(np.hypot(*e.centre))
            toward = math.atan2(-e.centre[1], -e.centre[0])  # the arc's point nearest the origin (c < R: farthest)
            for ang, r in ((toward, abs(c - e.radius)), (toward + math.pi, c + e.radius)):
                if ((ang - e.start_angle) * math.copysign(1.0, e.sweep)) % (2 * math.pi) <= abs(e.sweep):
                    lo, hi = min(lo, r), max(hi, r)
    return lo, hi


# ----------------------------------------------------------------------------- solids


def cs_solid(outline: Chain, *, outer_radius_mm: float, face_width_mm: float):
    """The CS ring (an OCP ``TopoDS_Solid``): the outer circle with ``outline`` (the closed CS
    inner outline, lines and arcs) as its hole, extruded over z ∈ [0, face_width_mm]."""
    _check_chain(outline, "circular spline outline")
    if not (face_width_mm > 0 and math.isfinite(face_width_mm)):
        raise GearSetError(f"cup.face_width_mm must be > 0 mm and finite, got {face_width_mm!r}")
    r_max = _radius_range_mm(outline)[1]
    if not outer_radius_mm > r_max:
        raise GearSetError(f"circular_spline.outer_diameter_mm = {2 * outer_radius_mm:g} mm: must exceed the CS "
                           f"outline's largest diameter {2 * r_max:.4f} mm")
    o = _occ()
    sectors = _ring_sectors(outline, outer_radius_mm, 0.0, face_width_mm)
    if sectors:  # the sectors share whole radial faces: "full" glue
        return _one_solid(_fuse(sectors, o.Glue.BOPAlgo_GlueFull, "circular spline"), "circular spline")
    inner = _chain_wire(outline, 0.0, ccw=False)
    return _one_solid(_ring_prism(_circle_wire(outer_radius_mm, 0.0, ccw=True), inner, face_width_mm),
                      "circular spline")


def fs_solid(outline: Chain, *, bore_radius_mm: float, wall_outer_radius_mm: float, length_mm: float,
             face_width_mm: float, bottom_thickness_mm: float, boss_radius_mm: float,
             boss_thickness_mm: float):
    """The undeformed flexspline cup (an OCP ``TopoDS_Solid``), its axis z, the outside of its
    bottom plate at z = 0 (see the module docstring): the tooth ring (bore circle to ``outline``,
    z ∈ [l − b/2, l + b/2]) fused once with the revolved wall, bottom and boss."""
    _check_chain(outline, "flexspline outline")
    b, l, t = float(face_width_mm), float(length_mm), float(bottom_thickness_mm)
    r_b, r_w, r_0, h_0 = float(bore_radius_mm), float(wall_outer_radius_mm), float(boss_radius_mm), float(boss_thickness_mm)
    r_min = _radius_range_mm(outline)[0]
    z_ring = l - b / 2.0
    for name, value, ok, rule in (
        ("cup.face_width_mm", b, b > 0, "> 0 mm"),
        ("cup.bottom_thickness_mm", t, t > 0, "> 0 mm"),
        ("cup.length_mm", l, z_ring > t, f"> bottom thickness + face width / 2 = {t + b / 2:g} mm"),
        ("cup.boss_radius_mm", r_0, 0 < r_0 < r_b, f"in (0, {r_b:g}) mm (inside the bore)"),
        ("boss thickness", h_0, h_0 >= t, f">= the bottom thickness {t:g} mm"),
        ("gear.rim_thickness_mm", r_w - r_b, 0 < r_b < r_w, "> 0 mm"),
        ("bore radius", r_b, r_min > r_b, f"< the flexspline outline's innermost radius {r_min:.4f} mm"),
    ):
        if not ok:
            raise GearSetError(f"flexspline STEP: {name} = {value:g} mm: must be {rule}")
    o = _occ()
    ring = (_ring_sectors(outline, r_b, z_ring, b)
            or [_ring_prism(_chain_wire(outline, z_ring, ccw=True), _circle_wire(r_b, z_ring, ccw=False), b)])
    # the meridian section (x = r, z), counter-clockwise, revolved once about z
    section = [(0.0, t - h_0), (r_0, t - h_0), (r_0, 0.0), (r_w, 0.0), (r_w, z_ring), (r_b, z_ring), (r_b, t), (0.0, t)]
    section = [p for i, p in enumerate(section) if p != section[i - 1]]  # a boss as thick as the bottom
    poly = o.BRepBuilderAPI.BRepBuilderAPI_MakePolygon()
    for r, z in section:
        poly.Add(o.gp_Pnt(r, 0.0, z))
    poly.Close()
    face = o.BRepBuilderAPI.BRepBuilderAPI_MakeFace(poly.Wire(), True).Face()
    axis = o.gp_Ax1(o.gp_Pnt(0.0, 0.0, 0.0), o.gp_Dir(0.0, 0.0, 1.0))
    cup = o.BRepPrimAPI.BRepPrimAPI_MakeRevol(face, axis, 2.0 * math.pi).Shape()
    # one fuse; the ring and the cup touch only on the annulus r_b..r_w at z_ring (partly
    # coinciding faces) and along the root lands, which lie on the wall's cylinder, the ring's
    # sectors on whole radial faces: "glue" skips the face/face intersections that would
    # otherwise be computed for each of the ring's ~2000 side faces (25.7 -> 10.6 s under load)
    return _one_solid(_fuse([*ring, cup], o.Glue.BOPAlgo_GlueShift, "flexspline"), "flexspline")


# ----------------------------------------------------------------------------- files


def step_bytes(solid, product: str) -> bytes:
    """The STEP file of one solid (AP214, mm, no p-curves: every CAD reader rebuilds them, and
    they would triple the file), with a fixed header: same solid, same bytes."""
    o = _occ()
    with _LOCK:
        printers = [p for p in o.Message.DefaultMessenger_s().Printers()]
        levels = [p.GetTraceLevel() for p in printers]
        for p in printers:  # library code does not print: OCCT's transfer statistics go to stdout
            p.SetTraceLevel(o.Gravity.Message_Fail)
        writer = o.STEPControl.STEPControl_Writer()  # registers the STEP parameters on first use
        keys = {"write.surfacecurve.mode": ("I", 0), "write.step.unit": ("C", "MM"),
                "write.step.schema": ("C", "AP214IS"), "write.step.product.name": ("C", product)}
        saved = {k: (o.Static.IVal_s(k) if kind == "I" else o.Static.CVal_s(k)) for k, (kind, _) in keys.items()}
        try:
            for k, (kind, v) in keys.items():
                (o.Static.SetIVal_s if kind == "I" else o.Static.SetCVal_s)(k, v)
            status = writer.Transfer(solid, o.STEPControl.STEPControl_AsIs, False)  # no check graph: O(n²), unused
            if status != o.RetDone:
                raise ExportError(f"STEP: OCCT could not transfer the {product} solid ({status})")
            model = writer.Model()
            for i in range(1, model.NbEntities() + 1):  # the product: OCCT names it "<name> <count of writes>"
                entity = model.Value(i)
                if type(entity).__name__ == "StepBasic_Product":
                    entity.SetId(o.HString(product))
                    entity.SetName(o.HString(product))
                    break
            h = o.MakeHeader(model)
            h.SetName(o.HString(product))
            h.SetTimeStamp(o.HString(_HEADER["timestamp"]))
            h.SetAuthorValue(1, o.HString(_HEADER["author"]))
            h.SetOrganizationValue(1, o.HString(""))
            h.SetPreprocessorVersion(o.HString("OCCT"))
            h.SetOriginatingSystem(o.HString(_HEADER["system"]))
            h.SetAuthorisation(o.HString(""))
            buf = io.BytesIO()
            status = writer.WriteStream(buf)
            if status != o.RetDone:
                raise ExportError(f"STEP: OCCT could not write the {product} model ({status})")
        finally:
            for k, (kind, _) in keys.items():
                (o.Static.SetIVal_s if kind == "I" else o.Static.SetCVal_s)(k, saved[k])
            for p, lvl in zip(printers, levels):
                p.SetTraceLevel(lvl)
    return buf.getvalue()


def _write(path: str | os.PathLike, data: bytes) -> Path:
    from .export import atomic_write

    with atomic_write(path, "wb") as f:
        f.write(data)
    return Path(os.fspath(path))


def cs_outer_radius_mm(design: Design) -> float:
    """The CS ring's outer radius: ``[circular_spline] outer_diameter_mm`` / 2 (if not set,
    ``CS_OUTER_DIAMETER_PER_ROOT`` × the root diameter rounded up to a whole mm, an ESTIMATE),
    checked against the design's root circle: a wall of at least ``CS_MIN_WALL_PER_MODULE`` · m."""
    g = design.gearset
    wall = CS_MIN_WALL_PER_MODULE * g.gear.module_mm
    assert design.profile is not None  # the CS of a finished design
    r_max = max(design.form.root_radius_mm, _radius_range_mm(design.profile.outline)[1])
    d_out = g.circular_spline.outer_diameter_mm
    d_out = float(math.ceil(CS_OUTER_DIAMETER_PER_ROOT * 2.0 * r_max) if d_out is None else d_out)
    if not d_out >= 2.0 * (r_max + wall):
        raise GearSetError(
            f"circular_spline.outer_diameter_mm = {d_out:g} mm: must be >= {2 * (r_max + wall):.4f} mm "
            f"(the CS root diameter {2 * r_max:.4f} mm + 2 × a wall of {CS_MIN_WALL_PER_MODULE:g}·m = {wall:g} mm)")
    return d_out / 2.0


def write_cs_step(path: str | os.PathLike, design: Design) -> Path:
    """Write ``circular_spline.step``: the CS ring with its z2 tooth spaces (see :func:`cs_solid`)."""
    r_out = cs_outer_radius_mm(design)
    assert design.profile is not None  # the CS of a finished design
    solid = cs_solid(design.profile.outline, outer_radius_mm=r_out, face_width_mm=design.gearset.cup.face_width_mm)
    return _write(path, step_bytes(solid, "circular_spline"))


def fs_outline(design: Design) -> Chain:
    """The closed outline of the z1 undeformed FS teeth as lines and arcs (:mod:`profilegen.geometry.fsform`)."""
    from ..geometry.fsform import flexspline_outline

    chain, _ = flexspline_outline(design.tooth, design.gearset.gear)
    return chain


def write_fs_step(path: str | os.PathLike, design: Design) -> Path:
    """Write ``flexspline.step``: the undeformed cup with its z1 teeth (see :func:`fs_solid`)."""
    g = design.gearset
    gear, cup = g.gear, g.cup
    solid = fs_solid(
        fs_outline(design),
        bore_radius_mm=gear.neutral_radius_mm - gear.rim_thickness_mm / 2.0,
        wall_outer_radius_mm=gear.neutral_radius_mm + gear.rim_thickness_mm / 2.0,
        length_mm=cup.length_mm,
        face_width_mm=cup.face_width_mm,
        bottom_thickness_mm=cup.bottom_thickness_mm,
        boss_radius_mm=cup.boss_radius_mm,
        boss_thickness_mm=BOSS_THICKNESS_PER_BOTTOM * cup.bottom_thickness_mm,
    )
    return _write(path, step_bytes(solid, "flexspline"))
