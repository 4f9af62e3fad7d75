"""What the workbench sends the browser: the CS space sampled at the screen's chord (on the fitted
arcs and lines, fewer points than report.html's figure), named by whether the scene chose the part
to cut, and the figures sent again only when the profile changed (a torque change keeps them)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import profilegen as pg
from profilegen.app import views
from profilegen.app.session import Session, Workspace
from profilegen.output.interactive import flank_figure


@pytest.fixture(scope="module")
def sketch():
    return pg.design(pg.load_gearset(pg.default_gearset_path()), scene="sketch")


def _trace(fig, prefix):
    return next(t for t in fig["data"] if t["name"].startswith(prefix))


def test_the_sketch_space_is_not_called_the_part_to_cut(sketch):
    assert sketch.face is None  # the sketch scene has no face stage: no design section chosen
    fig = views.space_figure(sketch, job=1)
    names = [t["name"] for t in fig["data"]]
    space = _trace(fig, "CS space")
    assert space["name"].startswith("CS space (sketch: not the part to cut)")
    assert not any(n.startswith("CS space to cut") for n in names)
    assert "to cut" not in space["hovertemplate"].replace("not the part to cut", "")
    # with a face stage (design, verify) the same space is the part to cut, as the design sheet's "To cut"
    chosen = dataclasses.replace(sketch, face=object())
    assert views.space_name(chosen) == "CS space to cut"


def test_the_space_is_sampled_on_the_fitted_elements_at_the_screen_chord(sketch):
    fig = views.space_figure(sketch, job=1)
    space = _trace(fig, "CS space")
    pts = np.column_stack([space["x"], space["y"]])
    chain = sketch.profile.space
    # every point on the fitted arcs and lines (to the 1e-9 mm rounding of the coordinates)
    assert float(np.max(chain.distance(pts))) < 2e-9
    # every chord's midpoint within the screen chord of them (an arc's sagitta is the chord error)
    mid = 0.5 * (pts[1:] + pts[:-1])
    assert float(np.max(chain.distance(mid))) <= views.SCREEN_CHORD_MM * (1 + 1e-6) + 2e-9
    report = _trace(flank_figure(sketch), "CS space to cut")
    assert len(space["x"]) < len(report["x"]) / 3  # the arcs at a 20× coarser chord: √20 ≈ 4.5× fewer points
    assert (space["x"][0], space["y"][0]) == (report["x"][0], report["y"][0])  # the same ends
    assert (space["x"][-1], space["y"][-1]) == (report["x"][-1], report["y"][-1])


def test_the_figures_are_sent_again_only_for_another_profile(sketch, tmp_path):
    """profile_token: a later job with the same profile object (a torque change: the engine's cached
    profile) keeps the first job's token, so the page's figures are not sent again; another profile
    (or the same values in another object) gets its own job."""
    s = Session(sketch.gearset, "sketch", Workspace(tmp_path), compute=lambda *a, **k: None)
    other = dataclasses.replace(sketch.profile)  # equal values, another object
    assert s.profile_token(sketch.profile, 3) == 3
    assert s.profile_token(sketch.profile, 4) == 3
    assert s.profile_token(other, 5) == 5
    assert s.profile_token(sketch.profile, 6) == 3
    for job in range(7, 20):  # the tab keeps a few profiles: an old one comes back as new
        s.profile_token(dataclasses.replace(sketch.profile), job)
    assert s.profile_token(sketch.profile, 20) == 20
    s.close()


def _segment_distance(points, xs, ys):
    """Each point's distance (mm) to the polyline xs, ys (None: a gap)."""
    x = np.array([np.nan if v is None else v for v in xs], float)
    y = np.array([np.nan if v is None else v for v in ys], float)
    a = np.column_stack([x[:-1], y[:-1]])
    b = np.column_stack([x[1:], y[1:]])
    ok = np.all(np.isfinite(a), axis=1) & np.all(np.isfinite(b), axis=1)
    a, b = a[ok], b[ok]
    lone = np.column_stack([x, y])[np.isfinite(x)]
    out = np.full(len(points), np.inf)
    for p_chunk in np.array_split(np.arange(len(points)), max(1, len(points) // 200)):
        p = points[p_chunk][:, None, :]
        d = b - a
        t = np.clip(np.sum((p - a) * d, axis=2) / np.maximum(np.sum(d * d, axis=1), 1e-300), 0.0, 1.0)
        seg = np.min(np.hypot(*np.moveaxis(p - (a + t[..., None] * d), 2, 0)), axis=1, initial=np.inf)
        pts = np.min(np.hypot(*np.moveaxis(p - lone[None, :, :], 2, 0)), axis=1, initial=np.inf)
        out[p_chunk] = np.minimum(seg, pts)
    return out


@pytest.mark.parametrize("zoom", [None, 1e-3, 2e-5])
def test_the_lighter_space_draws_every_point_to_a_quarter_pixel(sketch, zoom):
    """views.lighter leaves out points, never moves one: every point of the whole figure inside
    the view lies within the view's tolerance (a quarter pixel) of the line sent, the points sent
    are points of the figure, and the short traces go as they are. At the opening view: a tenth of
    the points or fewer; zoomed (a box of ``zoom`` mm on the exact flank) the points there."""
    fig = views.space_figure(sketch, job=1)
    start = views.initial_view(fig)
    view = start
    if zoom is not None:
        flank = _trace(fig, "exact flank")
        k = len(flank["x"]) // 3
        cx, cy = flank["x"][k], flank["y"][k]
        view = views.view_after({"xaxis.range[0]": cx - zoom, "xaxis.range[1]": cx + zoom,
                                 "yaxis.range[0]": cy - zoom, "yaxis.range[1]": cy + zoom}, start, start)
    light = views.lighter(fig, view)
    heavy = set(views.heavy_traces(fig))
    assert heavy and len(light["data"]) == len(fig["data"])
    x0, x1, y0, y1 = view.window
    sent = total = 0
    for i, (whole, thin) in enumerate(zip(fig["data"], light["data"])):
        if i not in heavy:
            assert thin is whole
            continue
        pts = np.column_stack([whole["x"], whole["y"]]).astype(float)
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        inside = pts[(pts[:, 0] >= x0) & (pts[:, 0] <= x1) & (pts[:, 1] >= y0) & (pts[:, 1] <= y1)]
        kept = {(a, b) for a, b in zip(thin["x"], thin["y"]) if a is not None}
        assert kept <= set(map(tuple, pts.tolist()))
        if len(inside) > 3000:  # a sample of them: the distances are all pairs
            inside = inside[np.random.default_rng(0).choice(len(inside), 3000, replace=False)]
        if len(inside):
            assert float(np.max(_segment_distance(inside, thin["x"], thin["y"]))) <= view.tol_mm * (1 + 1e-9)
        sent += len(kept)
        total += len(pts)
    if zoom is None:
        assert sent < total / 10
    else:
        assert sent > 0
    # the axes open at the view the points were thinned for (a redesign while zoomed keeps the zoom)
    assert (tuple(light["layout"]["xaxis"]["range"]), tuple(light["layout"]["yaxis"]["range"])) == (
        view.x_range, view.y_range)
    assert views.initial_view(fig) == start  # the whole figure kept by the session is not changed


def test_the_view_follows_zoom_pan_and_reset():
    start = views.View((0.0, 2.0), (50.0, 51.0))
    zoom = {"xaxis.range[0]": 1.0, "xaxis.range[1]": 1.001, "yaxis.range[0]": 50.5, "yaxis.range[1]": 50.5008}
    view = views.view_after(zoom, start, start)
    assert (view.x_range, view.y_range) == ((1.0, 1.001), (50.5, 50.5008))
    assert view.tol_mm == pytest.approx(0.25 * 0.0008 / 520)  # a quarter of a pixel of the 520 px height
    assert views.view_after({"xaxis.autorange": True, "yaxis.autorange": True}, view, start) == start
    assert views.view_after({"autosize": True}, view, start) is None  # the axes did not move
    assert views.view_after({"xaxis.range": [1.0, 1.001], "yaxis.range": [50.5, 50.5008]}, view, start) is None
    assert views.view_after(None, view, start) is None


def test_a_line_through_the_view_with_no_point_in_it_is_still_drawn():
    """Zoomed between two points of a line, the two points outside are sent: the line crosses
    the view (drawn, not a blank plot)."""
    x = np.linspace(-1.0, 1.0, 300)  # no point within 3 µm of x = 0.0003
    fig = {"data": [{"type": "scatter", "mode": "lines", "name": "a line", "x": x.tolist(), "y": (0.5 * x).tolist()}],
           "layout": {"height": 520, "xaxis": {"range": [-1.0, 1.0]}, "yaxis": {"range": [-1.0, 1.0]}}}
    start = views.initial_view(fig)
    view = views.view_after({"xaxis.range[0]": 0.0002, "xaxis.range[1]": 0.0004, "yaxis.range[0]": 0.0001,
                             "yaxis.range[1]": 0.0002}, start, start)
    light = views.lighter(fig, view)["data"][0]
    assert 2 <= len(light["x"]) < 10
    centre = np.array([[0.0003, 0.00015]])
    assert float(_segment_distance(centre, light["x"], light["y"])[0]) < 1e-12
