"""The flexspline as lines and arcs (profilegen.geometry.fsform) and its drawings (profilegen.output.flexspline).

Checked against things the module does not compute itself: the tooth's own outline polygon
(ToothProfile.surface / outline), its exact arc length, dense exact points of the involute and
the point-list spline with an independent polyline distance, the shoelace area of the exact
tooth polygon (shapely) against Green's theorem on the arcs, the motion's own point mapping
(Pose.to_cs + kinematics.turn) for the assembly, and the DXF read back by ezdxf.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from profilegen.geometry.contour import Arc, Chain, Line
from profilegen.errors import GearSetError
from profilegen.geometry.fsform import FlexsplineFormError, flexspline_outline, flexspline_tooth_chain, ring_of_teeth
from profilegen.geometry.teeth import dcta_tooth, involute_tooth, points_tooth

M, Z1, R_M = 0.5, 200, 48.95
GEAR = SimpleNamespace(module_mm=M, flexspline_teeth=Z1, neutral_radius_mm=R_M)
SHIFT = np.array([0.0, R_M])  # tooth frame -> gear centre at the origin


@pytest.fixture(scope="module")
def teeth():
    dcta = dcta_tooth(module_mm=M, teeth=Z1, neutral_radius_mm=R_M)
    inv = involute_tooth(module_mm=M, teeth=Z1, neutral_radius_mm=R_M)
    # a point-list tooth: 24 points of the involute flank, interpolated (a quintic spline in arc length)
    pts = inv.point(np.linspace(0.0, inv.length_mm, 24))
    points = points_tooth(pts, module_mm=M, teeth=Z1, neutral_radius_mm=R_M, smoothing_mm=0.0)
    return {"dcta": dcta, "involute": inv, "points": points}


def _flank(chain: Chain) -> list:
    """The right flank's elements: after the half root arc and the radial step, up to the top land."""
    els = list(chain.elements)
    top = next(i for i, e in enumerate(els) if isinstance(e, Line) and abs(e.start[1] - e.end[1]) < 1e-15
               and e.start[0] > 0 > e.end[0])
    step = els[1]
    d = step.end - step.start
    radial = isinstance(step, Line) and abs(step.start[0] * d[1] - step.start[1] * d[0]) < 1e-9 * step.length * 60
    first = 2 if radial else 1
    return els[first:top]


def _polyline_distance(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Distance of points to a polyline, by brute force over its segments."""
    a, b = vertices[:-1], vertices[1:]
    d = b - a
    out = np.full(len(points), np.inf)
    for lo in range(0, len(points), 256):
        p = points[lo:lo + 256, None, :]
        s = np.clip(np.sum((p - a) * d, axis=-1) / np.sum(d * d, axis=-1), 0.0, 1.0)
        out[lo:lo + 256] = np.min(np.hypot(*np.moveaxis(p - a - s[..., None] * d, -1, 0)), axis=1)
    return out


def _green_area(chain: Chain) -> float:
    """Area enclosed by a closed chain of lines and arcs (Green's theorem, exact for arcs)."""
    total = 0.0
    for e in chain.elements:
        if isinstance(e, Line):
            total += e.start[0] * e.end[1] - e.end[0] * e.start[1]
        else:
            (cx, cy), r, a0, a1 = e.centre, e.radius, e.start_angle, e.end_angle
            total += r * cx * (math.sin(a1) - math.sin(a0)) - r * cy * (math.cos(a1) - math.cos(a0)) + r * r * e.sweep
    return 0.5 * total


# ----------------------------------------------------------------------------- the tooth chain


def test_dcta_chain_is_the_exact_tooth(teeth):
    tooth = teeth["dcta"]
    chain, dev = flexspline_tooth_chain(tooth, GEAR)
    assert dev <= 1e-12
    # the tooth's own surface polygon (exact points: lands, steps, flanks) lies on the chain
    surface = tooth.surface(n_per_mm=400.0) + SHIFT
    assert chain.distance(surface).max() <= 1e-9
    # ... and the chain is no longer: both flanks have the tooth's exact arc length
    flank = _flank(chain)
    assert sum(e.length for e in flank) == pytest.approx(tooth.length_mm, abs=1e-12)
    assert [type(e).__name__ for e in flank] == ["Arc", "Line", "Arc"]
    # it starts and ends mid-space on the root circle, and is G0 (round-off) throughout
    r_f = R_M + tooth.dedendum_y_mm
    for p, psi in ((chain.start, math.pi / Z1), (chain.end, -math.pi / Z1)):  # polar angle from +y toward +x
        assert p == pytest.approx([r_f * math.sin(psi), r_f * math.cos(psi)], abs=1e-12)
    assert chain.gaps().max() <= 1e-12
    # mirror symmetric about the axis: the left half is the right half mirrored
    back = chain.transformed(np.diag([-1.0, 1.0])).reversed()
    assert np.abs(back.sample(1e-6) - chain.sample(1e-6)).max() <= 1e-12


@pytest.mark.parametrize("kind", ["involute", "points"])
@pytest.mark.parametrize("tol", [1e-4, 1e-6])
def test_fitted_flank_within_tolerance_and_g1(teeth, kind, tol):
    tooth = teeth[kind]
    chain, dev = flexspline_tooth_chain(tooth, GEAR, tol_mm=tol)
    assert 0 < dev <= tol
    flank = _flank(chain)
    assert all(isinstance(e, (Line, Arc)) for e in flank)
    # independent two-sided distance: dense exact points (2 µm apart: chord sag < 1e-9 mm here)
    exact = tooth.point(np.linspace(0.0, tooth.length_mm, int(tooth.length_mm / 2e-3) + 1)) + SHIFT
    there = Chain(tuple(flank)).distance(exact).max()
    back = _polyline_distance(Chain(tuple(flank)).sample(1e-7), exact).max()
    assert max(there, back) <= tol
    assert max(there, back) == pytest.approx(dev, rel=0.05, abs=2e-9)
    # G0 everywhere, G1 along the flank (a smooth curve), the ends on the exact root and tip points
    assert chain.gaps().max() <= 1e-12
    assert Chain(tuple(flank)).kinks_deg().max() <= 1e-6
    assert flank[0].start == pytest.approx(tooth.root_point + SHIFT, abs=1e-12)
    assert flank[-1].end == pytest.approx(tooth.tip_point + SHIFT, abs=1e-12)


def test_tighter_tolerance_takes_more_arcs_at_the_biarc_rate(teeth):
    """Halving pieces shrinks a biarc's error as h³: 100x tighter takes about 100^(1/3) ≈ 4.6x the arcs."""
    counts = [len(_flank(flexspline_tooth_chain(teeth["involute"], GEAR, tol_mm=t)[0])) for t in (1e-5, 1e-7)]
    assert 2.0 <= counts[1] / counts[0] <= 10.0


# ----------------------------------------------------------------------------- the outline


@pytest.mark.parametrize("kind", ["dcta", "involute"])
def test_outline_closes_with_z1_teeth_and_the_exact_area(teeth, kind):
    import shapely

    tooth = teeth[kind]
    outline, dev = flexspline_outline(tooth, GEAR, tol_mm=1e-6)
    assert outline.gaps(closed=True).max() <= 1e-12
    r_a = R_M + tooth.addendum_y_mm
    tops = [e for e in outline.elements if isinstance(e, Line)
            and abs(float(np.hypot(*(e.start + e.end) / 2)) - r_a) < 1e-9]
    assert len(tops) == Z1
    axes = np.sort(np.mod([math.atan2(*((e.start + e.end) / 2)[::-1]) for e in tops], 2 * math.pi))
    assert np.diff(axes) == pytest.approx(2 * math.pi / Z1, abs=1e-12)
    # area: z1 exact tooth sectors (the tooth's own polygon, down to the neutral circle) + the neutral disc
    sector = shapely.Polygon(tooth.outline(n_per_mm=4000.0)).area
    expected = Z1 * sector + math.pi * R_M**2
    # the polygon's chords cut ~1e-7 mm² a tooth; a fitted flank may move the area by at most its
    # length times its deviation, on two flanks of z1 teeth
    assert abs(_green_area(outline) - expected) <= 2e-5 + 2 * Z1 * tooth.length_mm * dev
    ring = shapely.LinearRing(outline.sample(1e-4))
    assert ring.is_simple and ring.is_ccw


def test_bad_inputs_are_named(teeth):
    tooth = teeth["dcta"]
    for bad in (0.0, -1e-4, 1.0, float("nan"), True, "1e-4"):
        with pytest.raises(FlexsplineFormError, match="tol_mm"):
            flexspline_tooth_chain(tooth, GEAR, tol_mm=bad)
    with pytest.raises(GearSetError, match="gear.flexspline_teeth"):
        flexspline_tooth_chain(tooth, SimpleNamespace(module_mm=M, flexspline_teeth=100, neutral_radius_mm=R_M))
    with pytest.raises(GearSetError, match="gear.neutral_radius_mm"):
        flexspline_outline(tooth, SimpleNamespace(module_mm=M, flexspline_teeth=Z1, neutral_radius_mm=48.0))
    with pytest.raises(TypeError, match="tooth"):
        flexspline_tooth_chain(tooth.surface(), GEAR)
    with pytest.raises(FlexsplineFormError, match="tooth_chain"):
        ring_of_teeth(Chain((Line((0, 0), (1, 0)),)), Z1)


# ----------------------------------------------------------------------------- files


def test_dxf_reads_back_to_the_same_elements(tmp_path):
    """An involute tooth on a 50-tooth gear (a small file): both drawings read back, element by element."""
    from profilegen.output import cad, flexspline

    r_m = 0.5 * 50 / 2 - 0.625 - 0.45
    gear = SimpleNamespace(module_mm=M, flexspline_teeth=50, neutral_radius_mm=r_m)
    tooth = involute_tooth(module_mm=M, teeth=50, neutral_radius_mm=r_m)
    result = SimpleNamespace(tooth=tooth, gearset=SimpleNamespace(name="test", gear=gear))
    chain = flexspline.write_flexspline_dxfs(tmp_path, result)
    for name, expected in (("flexspline_tooth.dxf", chain), ("flexspline.dxf", ring_of_teeth(chain, 50))):
        path = tmp_path / name
        assert cad.audit(path) == 0, name
        back = cad.oriented_chain(cad.read_dxf_contours(path)["FS"])
        assert len(back.elements) == len(expected.elements)
        for a, b in zip(back.elements, expected.elements):
            assert type(a) is type(b)
            assert np.abs(np.vstack([a.start, a.end]) - np.vstack([b.start, b.end])).max() <= 1e-12
            if isinstance(a, Arc):
                assert a.radius == pytest.approx(b.radius, rel=1e-15)
                assert np.abs(a.centre - b.centre).max() <= 1e-12
    assert back.gaps(closed=True).max() <= 1e-12  # the whole gear, as read back, closes


def test_assembly_poses_each_tooth_rigidly_and_stays_small(tmp_path):
    """The posed tooth chain is the motion's own point mapping (Pose.to_cs then turn) applied to the
    chain's points; the default set's assembly.dxf is written from it, under 1 MB (the dense
    polylines it replaces made 2.8 MB; the filleted CS is ~0.5 MB of it, the FS ~0.42 MB)."""
    import profilegen as pg
    from profilegen.geometry.kinematics import turn
    from profilegen.output import cad
    from profilegen.output.flexspline import posed_teeth

    gs = pg.load_gearset(pg.default_gearset_path())
    d = pg.design(gs, scene="sketch", contact=False, stress=False)
    g = gs.gear
    chain, _ = flexspline_tooth_chain(d.tooth, g)
    posed = posed_teeth(chain, d.motion, g.flexspline_teeth, g.neutral_radius_mm)
    pts = chain.sample(1e-5)
    for k in (0, 37, 50, 199):
        theta = 2 * math.pi * k / g.flexspline_teeth
        mapped = turn(d.motion.pose(np.array([theta])).to_cs(pts - [0.0, g.neutral_radius_mm]),
                      theta - d.motion.beta_rate * theta)
        assert np.abs(posed[k].sample(1e-5) - mapped).max() <= 1e-11
    pg.write_design(d, tmp_path / "out", figure=False)
    path = tmp_path / "out" / "assembly.dxf"
    assert path.stat().st_size < 1_000_000
    # the FS layer's own share (2200 lines and arcs and the bore polyline): a few hundred kB
    fs_bytes = sum(len(e) for e in path.read_text().split("\n  0\n") if "\n  8\nFS\n" in e)
    assert 100_000 < fs_bytes < 500_000
    import ezdxf

    doc = ezdxf.readfile(path)  # read once: audit and count the FS layer's lines and arcs
    assert not doc.audit().errors
    fs = doc.modelspace().query('LINE ARC[layer=="FS"]')
    assert len(fs) == len(chain.elements) * g.flexspline_teeth
