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
