"""The CS corners rounded for wire EDM (profilegen.profile.rootfillet): tangent arcs of wire radius +
spark gap at the root, the closed outline G1, the fillets clear of the FS tooth family, and
the named errors for a wire too thick for the space and a fillet that would cut into the mesh.

Geometry is checked against itself only through independent facts: a fillet's centre lies at
its radius from each neighbour's line or circle, the largest root fillet is the circle tangent
to both transition lines and the root circle (solved here in closed form), the clearance map
measures exact distances to the placed FS tooth surface (not the swept-depth function the
fillets are built with)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import shapely

import profilegen as pg
from profilegen.profile.arcfit import swept_depth_function
from profilegen.geometry.contour import Arc, Chain, Line
from profilegen.errors import FilletError
from profilegen.profile.gearform import clearance_map, cs_chain
from profilegen.profile.rootfillet import INSIDE, OUTSIDE, filleted_cs_chain, max_kink_deg, round_space

RADIUS = 0.125 + 0.02  # the defaults: a 0.25 mm wire and a 0.02 mm spark gap


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_root_fillet")


@pytest.fixture(scope="module")
def sketch(default_sketch):
    """The default set in the sketch scene, its corners filleted by default (conftest.py:
    computed once per worker)."""
    return default_sketch


@pytest.fixture(scope="module")
def parts(sketch):
    d = sketch
    flank = d.profile.flank_fit.chain  # the one-sided fit of the right flank, tip → root
    swept = swept_depth_function(d.tooth, d.motion, cs_teeth=d.form.cs_teeth, phi_range=d.envelope.phi_range)
    kw = dict(tip_radius_mm=d.form.tip_radius_mm, root_radius_mm=d.form.root_radius_mm, cs_teeth=d.form.cs_teeth)
    return flank, swept, kw


def _local(outline: Chain, space: Chain) -> Chain:
    n = len(space.elements) + 1
    return Chain(outline.elements[-n:] + outline.elements[: 2 * n])


def _neighbours(space: Chain, arc: Arc):
    k = next(i for i, e in enumerate(space.elements) if e is arc)
    els = space.elements
    return (els[k - 1] if k > 0 else None), (els[k + 1] if k + 1 < len(els) else None)


def _tangent_distance_error(el, arc: Arc) -> float:
    """How far the arc is from tangent to the element's line/circle: |distance − radius|."""
    if isinstance(el, Line):
        d = el.tangent()
        off = arc.centre - el.start
        return abs(abs(d[0] * off[1] - d[1] * off[0]) - arc.radius)
    dist = float(np.hypot(*(arc.centre - el.centre)))
    return min(abs(dist - (el.radius - arc.radius)), abs(dist - (el.radius + arc.radius)))


def test_max_kink_measures_corners_of_a_closed_chain():
    """A square has 90° corners (the closing one too when closed); a circle of four arcs and a
    rounded square are G1 (0 to rounding); a 1° bend is 1°."""
    sq = [np.array(p, float) for p in ((0, 0), (1, 0), (1, 1), (0, 1))]
    square = Chain(tuple(Line(sq[i], sq[(i + 1) % 4]) for i in range(4)))
    assert max_kink_deg(square) == pytest.approx(90.0, abs=1e-12)
    assert max_kink_deg(Chain(square.elements[:2]), closed=False) == pytest.approx(90.0, abs=1e-12)
    circle = Chain(tuple(Arc((0, 0), 2.0, k * math.pi / 2, math.pi / 2) for k in range(4)))
    assert max_kink_deg(circle) < 1e-12
    r = 0.25  # a rounded unit square: lines and quarter arcs
    rounded = []
    for k in range(4):
        a = k * math.pi / 2
        u, v = np.array([math.cos(a), math.sin(a)]), np.array([-math.sin(a), math.cos(a)])
        c0 = 0.5 * (u + v) - r * (u + v)  # this side's end corner centre, from the square's centre
        rounded.append(Line(c0 + r * u - 2 * (0.5 - r) * v, c0 + r * u))
        rounded.append(Arc(c0, r, a, math.pi / 2))
    assert max_kink_deg(Chain(tuple(rounded))) < 1e-9
    bend = Chain((Line((0, 0), (1, 0)), Line((1, 0), (1 + math.cos(math.radians(1)), math.sin(math.radians(1))))))
    assert max_kink_deg(bend, closed=False) == pytest.approx(1.0, abs=1e-12)


def test_fillets_are_tangent_arcs_of_wire_radius_plus_gap(sketch):
    """Two root fillets (inside corners) and two tip rounds (outside), each of radius
    r_w + s_g, each tangent to both neighbours — its centre one radius from the
    neighbour's line or circle to 1e-9 mm, no gap, no kink; the root feet on the root circle."""
    prof = sketch.profile
    fillets = prof.corners.fillets
    assert sorted((f.where, f.kind) for f in fillets) == [("root left", INSIDE), ("root right", INSIDE),
                                                          ("tip left", OUTSIDE), ("tip right", OUTSIDE)]
    r_root = sketch.form.root_radius_mm
    for f in fillets:
        assert f.radius_mm == pytest.approx(RADIUS, abs=1e-12)
        before, after = _neighbours(prof.space, f.arc)
        for el in (before, after):
            if el is not None:
                assert _tangent_distance_error(el, f.arc) < 1e-9, f.where
        if before is not None:
            assert np.hypot(*(before.end - f.arc.start)) < 1e-9
            assert prof.space.kinks_deg()[prof.space.elements.index(f.arc) - 1] < 1e-9
        if after is not None:
            assert np.hypot(*(after.start - f.arc.end)) < 1e-9
        if f.kind == INSIDE:
            ends = np.hypot(*np.array([f.arc.start, f.arc.end]).T)
            assert np.min(np.abs(ends - r_root)) < 1e-9  # one foot on the root circle
            assert f.arc.sweep < 0 and f.clearance_mm > 0  # turns as the root does; clear of the FS
    # a tip round starts the space on the tip circle, where the land arc takes over
    for p in (prof.space.start, prof.space.end):
        assert np.hypot(*p) == pytest.approx(sketch.form.tip_radius_mm, abs=1e-12)
    # the space is still the mirror image of itself
    np.testing.assert_allclose(prof.space.start * [-1, 1], prof.space.end, atol=1e-9)


def test_closed_outline_is_g1_everywhere(sketch):
    outline = sketch.profile.outline
    assert max_kink_deg(outline) < 0.01
    assert max_kink_deg(outline) < 1e-6  # in fact to rounding
    assert outline.gaps(closed=True).max() <= 1e-9
    assert len(outline.elements) == 202 * (len(sketch.profile.space.elements) + 1)
    assert sketch.profile.to_dict()["corners"]["outline_max_kink_deg"] == max_kink_deg(outline)
    assert shapely.LinearRing(outline.sample(1e-3)).is_simple


def test_root_fillet_adds_material_tip_round_removes_it(sketch, parts):
    """The root fillet fills the space's corner (CS material into the space, toward the FS
    tip path); the tip round cuts the CS tooth's corner (material away)."""
    flank, _, kw = parts
    sharp = filleted_cs_chain(flank, corners="sharp", **kw)
    prof = sketch.profile
    void_sharp = shapely.Polygon(_local(sharp.outline, sharp.space).sample(1e-5))
    void_round = shapely.Polygon(_local(prof.outline, prof.space).sample(1e-5))
    for f in prof.corners.fillets:
        mid = f.arc.point_at(f.arc.start_angle + 0.5 * f.arc.sweep)
        in_sharp = void_sharp.contains(shapely.Point(*mid))
        assert in_sharp if f.kind == INSIDE else not in_sharp, f.where
        corner_in_round = void_round.contains(shapely.Point(*f.corner_mm))
        assert (not corner_in_round) if f.kind == INSIDE else corner_in_round, f.where


def test_filleted_cs_clears_the_fs_tooth_family(sketch):
    """The exact clearance of the FS tooth (its real surface, placed at each pose) against the
    filleted outline is ≥ 0 (to the chord tolerance), and against the root fillets alone it is
    the tens of µm the swept-depth check reported."""
    d = sketch
    assert d.profile.clearance.min_mm >= -d.envelope.chord_tol_mm
    roots = [f for f in d.profile.corners.fillets if f.kind == INSIDE]
    pts = np.vstack([f.arc.sample(1e-6) for f in roots])
    cmap = clearance_map(d.form, d.tooth, d.motion, phi_range=d.envelope.phi_range, samples=181, cs_points=pts)
    assert cmap.min_mm > 0.0
    assert cmap.min_mm == pytest.approx(min(f.clearance_mm for f in roots), rel=0.05)


def test_sharp_corners_reproduce_the_bare_chain(parts):
    """corners = "sharp" is the chain gearform.cs_chain makes, element for element, bit for bit,
    with its sharp root corners (kink ~45°) still there."""
    flank, _, kw = parts
    sharp = filleted_cs_chain(flank, corners="sharp", **kw)
    space, outline = cs_chain(flank, **kw)
    assert sharp.fillets == () and len(space.elements) == 9
    for a, b in zip(sharp.outline.elements + sharp.space.elements, outline.elements + space.elements, strict=True):
        assert type(a) is type(b)
        assert a.to_dict() == b.to_dict()
    assert max_kink_deg(sharp.outline) > 40.0


def _largest_root_circle(space: Chain, r_root: float) -> float:
    """The circle centred on the space's axis tangent to the right transition line and to the
    root circle from inside: the largest root fillet (the two fillets meet on the axis)."""
    line = next(e for e in space.elements if isinstance(e, Line) and e.start[0] > 0 and np.hypot(*e.start) > r_root - 1e-9)
    d, p = line.tangent(), line.start
    # centre (0, c), radius ρ = r_root − c, distance to the line |d × ((0, c) − p)| = ρ
    # d × ((0, c) − p) = d_x (c − p_y) + d_y p_x; the centre is on the space side (sign −)
    for s in (1.0, -1.0):
        c = (s * r_root + d[0] * p[1] - d[1] * p[0]) / (d[0] + s)
        rho = r_root - c
        foot = p + ((np.array([0.0, c]) - p) @ d) * d
        if rho > 0 and foot[0] > 0:
            return rho
    raise AssertionError("no circle")


def test_too_thick_wire_is_a_named_error_with_the_largest_that_fits(parts):
    flank, swept, kw = parts
    with pytest.raises(FilletError, match=r"circular_spline\.wire_radius_mm.*0\.2 mm.*largest that fits") as err:
        filleted_cs_chain(flank, radius_mm=0.2, swept=swept, **kw)
    assert isinstance(err.value, ValueError)
    largest = float(re.search(r"largest that fits is ([0-9.e-]+) mm", str(err.value)).group(1))
    sharp = filleted_cs_chain(flank, corners="sharp", **kw)
    assert largest == pytest.approx(_largest_root_circle(sharp.space, kw["root_radius_mm"]), rel=1e-3)
    # just below it, it fits, and the two root fillets nearly meet on the axis
    ok = filleted_cs_chain(flank, radius_mm=0.999 * largest, swept=swept, **kw)
    root = [e for e in ok.space.elements if isinstance(e, Arc) and not np.any(e.centre)]
    assert len(root) == 1 and root[0].length < 0.01


def test_narrow_space_closed_by_an_arc_tighter_than_the_wire_is_refused(parts):
    """A space whose flank tangents meet on the axis inside the root circle is closed by one
    tangent arc on the axis (seed 001's SHF-25 set): a wire whose radius + gap exceeds that
    arc cannot cut it."""
    _, _, kw = parts
    r_root = kw["root_radius_mm"]
    end = np.array([0.07, r_root - 0.10])  # the flank ends 0.07 mm off the axis, heading up at 45°
    t = np.array([-1.0, 1.0]) / np.sqrt(2.0)
    # a 0.5 mm arc turning 39.3° counter-clockwise (toward the axis) into that end, after a
    # nearly radial line: G1, the tip well inside one pitch
    bend = Arc(end + 0.5 * np.array([-t[1], t[0]]), 0.5, math.radians(45.0 - 39.3), math.radians(39.3))
    np.testing.assert_allclose(bend.end, end, atol=1e-12)
    steep = bend.tangent()
    flank = Chain((Line(bend.start - 0.7 * steep, bend.start), bend))
    tight = 0.07 / t[1]  # the closing arc: centre on the axis on the flank end's normal
    with pytest.raises(FilletError, match=r"wire_radius_mm.*concave arc of 0\.09899") as err:
        filleted_cs_chain(flank, radius_mm=0.1, **kw)
    assert f"largest that fits is {tight:.4g} mm" in str(err.value)
    ok = filleted_cs_chain(flank, radius_mm=0.09, **kw)
    assert max_kink_deg(ok.outline) < 1e-6


def test_fillet_that_would_cut_into_the_mesh_is_a_named_error(parts):
    """An FS tooth family 0.1 mm fatter (its swept region grown by 0.1 mm) reaches into the
    default root fillets, which are ~83 µm clear of the real one: FilletError naming the field,
    the radius asked and the largest that stays clear — which just touches the grown region."""
    flank, swept, kw = parts
    grown = lambda p: swept(p) + 0.1  # noqa: E731
    with pytest.raises(FilletError, match=r"wire_radius_mm: a root (left|right) fillet of 0\.145 mm .*cut into the mesh"
                                          r".*largest root fillet that stays clear is") as err:
        filleted_cs_chain(flank, radius_mm=RADIUS, swept=grown, swept_tol_mm=1e-5, **kw)
    largest = float(re.search(r"stays clear is ([0-9.e-]+) mm", str(err.value)).group(1))
    assert 0.0 < largest < RADIUS
    at = filleted_cs_chain(flank, radius_mm=largest, swept=grown, swept_tol_mm=1e-5, **kw)
    clear = min(f.clearance_mm for f in at.fillets if f.kind == INSIDE)
    assert -1e-5 <= clear < 2e-4  # touching the grown region, to the bisection's step
    with pytest.raises(FilletError):
        filleted_cs_chain(flank, radius_mm=1.02 * largest, swept=grown, swept_tol_mm=1e-5, **kw)


def test_tip_rounds_shrink_to_the_land_with_a_warning(parts, caplog):
    """More CS teeth on the same radius leave a tip land too short for two 0.145 mm rounds:
    the outside corners take the largest round that fits (the wire cuts them sharp anyway),
    with a logged warning; the root fillets keep the wire's radius; still G1."""
    flank, swept, kw = parts
    kw = dict(kw, cs_teeth=250)
    with caplog.at_level("WARNING", logger="profilegen.profile.rootfillet"):
        out = filleted_cs_chain(flank, radius_mm=RADIUS, swept=swept, **kw)
    tips = [f for f in out.fillets if f.kind == OUTSIDE]
    assert len(tips) == 2 and all(f.radius_mm < RADIUS for f in tips)
    assert all(f.radius_mm == RADIUS for f in out.fillets if f.kind == INSIDE)
    assert out.warnings and "largest that fits" in out.warnings[0] and "largest that fits" in caplog.text
    assert max_kink_deg(out.outline) < 1e-6
    lands = [e for e in out.outline.elements[:40] if isinstance(e, Arc) and not np.any(e.centre)
             and e.radius == kw["tip_radius_mm"]]
    assert lands and min(e.length for e in lands) < 1e-4  # the rounds use up the land


@pytest.mark.parametrize("key, value, text", [
    ("wire_radius_mm", 0.0, "circular_spline.wire_radius_mm = 0.0 mm: must be in (0, 0.25]"),
    ("wire_radius_mm", 0.3, "circular_spline.wire_radius_mm = 0.3 mm: must be in (0, 0.25]"),
    ("spark_gap_mm", -0.01, "circular_spline.spark_gap_mm = -0.01 mm: must be in [0, 0.1]"),
    ("corners", "round", 'circular_spline.corners = "round": must be one of "fillet", "sharp"'),
])
def test_edm_fields_are_validated(key, value, text):
    d = pg.load_gearset(pg.default_gearset_path()).to_dict()
    d["circular_spline"] = {key: value}
    with pytest.raises(pg.GearSetError) as err:
        pg.parse_gearset(d)
    assert text in str(err.value)


def test_edm_fields_default_to_a_025_mm_wire():
    cs = pg.load_gearset(pg.default_gearset_path()).circular_spline
    assert (cs.wire_radius_mm, cs.spark_gap_mm, cs.corners) == (0.125, 0.02, "fillet")
    assert cs.corner_radius_mm == pytest.approx(RADIUS, abs=1e-15)


def test_round_space_refuses_a_bad_radius(parts):
    flank, _, kw = parts
    sharp = filleted_cs_chain(flank, corners="sharp", **kw)
    with pytest.raises(FilletError, match="wire_radius_mm"):
        round_space(sharp.space, radius_mm=-1.0, tip_radius_mm=kw["tip_radius_mm"], cs_teeth=202)


def test_a_step_in_the_fitted_flank_is_kept_sharp_with_a_warning(parts, caplog):
    """Where the fits of two envelope branches meet (a ridge; the verify scene of the default
    set), a 0.5 µm line joins them at right angles: no 0.145 mm round fits beside it. Those two
    corners stay sharp, each named in a warning with the short element's length; the root
    fillets and tip rounds are made as before (not an error: the default set's verify scene
    refused its own file)."""
    flank, swept, kw = parts
    first, rest = flank.elements[0], flank.elements[1:]
    step = 5e-4 * np.array([-first.tangent(at_end=True)[1], first.tangent(at_end=True)[0]])  # 0.5 µm across the flank
    moved = [e.transformed(np.eye(2), step) for e in rest]
    stepped = Chain((first, Line(first.end, first.end + step), *moved))
    with caplog.at_level("WARNING", logger="profilegen.profile.rootfillet"):
        out = filleted_cs_chain(stepped, radius_mm=RADIUS, swept=swept, **kw)
    kept = [w for w in out.warnings if "kept sharp" in w]
    assert len(kept) == 4  # two corners of the step, on each flank
    assert all("0.5 µm long" in w and "0.145 mm round" in w for w in kept)
    assert sum("rounds it itself" in w for w in kept) == 2 and sum("cuts it sharp" in w for w in kept) == 2
    assert sorted(f.kind for f in out.fillets) == sorted(f.kind for f in filleted_cs_chain(
        flank, radius_mm=RADIUS, swept=swept, **kw).fillets)  # the same root fillets and tip rounds
    assert all(f.radius_mm == RADIUS for f in out.fillets if f.kind == INSIDE)
    assert 89.0 < max_kink_deg(out.outline) < 91.0  # the step's corners: the only non-G1 joins
