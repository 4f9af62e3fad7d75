"""The scenes' ``figures`` key (issue 14, item 2): the sketch scene ("interactive use and sweeps")
draws no PNG figures; its reports say where each picture would be and how to draw it
(``profilegen design --figures``); every other file is the same as with the figures."""

from __future__ import annotations

import json
import re

import pytest

import profilegen as pg
from profilegen.gearset import default_gearset_path, load_gearset
from profilegen.output import report
from profilegen.pipeline.scenes import SCENES, SceneError, parse_scenes

_BASE = {"rim": "ring theory", "chord_tol_mm": 1e-4, "n_t": 96, "n_phi": 241, "clearance_samples": 91,
         "brute_force_check": False, "description": "mine", "tier": "sketch"}
_IMG = re.compile(r'<img src="data:image/png;base64,[^"]*" alt="([^"]*)">')
_NOTE = re.compile(r'<p class="skip">Figure \(([^)]*)\) not drawn: [^\n]*?--figures</code> draws them\.</p>')


def test_figures_key_is_read_with_its_default_and_checked():
    assert SCENES["sketch"].figures == "none"
    assert SCENES["design"].figures == "all" and SCENES["verify"].figures == "all"
    assert parse_scenes({"fast": _BASE})["fast"].figures == "all"  # the default
    assert parse_scenes({"fast": {**_BASE, "figures": "none"}})["fast"].figures == "none"
    for bad in ("some", True, ""):
        with pytest.raises(SceneError, match=r"mine\.toml: scene 'fast': figures = .*must be one of \"all\", \"none\""):
            parse_scenes({"fast": {**_BASE, "figures": bad}}, origin="mine.toml")


@pytest.fixture(scope="module")
def sketch():
    """A sketch design of the default set (its stresses give report.html)."""
    return pg.design(load_gearset(default_gearset_path()), scene="sketch")


def _no_times(x):
    if isinstance(x, dict):
        return {k: _no_times(v) for k, v in x.items() if "time" not in k and k != "files"}
    if isinstance(x, list):
        return [_no_times(v) for v in x]
    return x


def test_sketch_writes_no_png_and_its_reports_say_how_to_draw_them(sketch, tmp_path, monkeypatch):
    """Without figures: no PNG file, no embedded picture; each picture's place in both reports is
    a line naming the picture and `--figures`, and the pages are otherwise the ones with figures.
    Every other file is byte for byte the same (design.json: but for its file list and times)."""
    monkeypatch.setenv(report.WORKERS_ENV, "0")  # drawn here: the test needs no worker processes
    none, drawn = tmp_path / "none", tmp_path / "all"
    pg.write_design(sketch, none)
    pg.write_design(sketch, drawn, draw=True)
    names = {p.name for p in none.iterdir()}
    assert not any(n.endswith(".png") for n in names)
    assert {p.name for p in drawn.iterdir()} - names == {"envelope.png", "stress.png"}
    assert sorted(json.loads((none / "design.json").read_text())["files"]) == sorted(names)
    for name in sorted(names - {"design.json", "report.html", "fit_report.html"}):
        assert (none / name).read_bytes() == (drawn / name).read_bytes(), name
    assert _no_times(json.loads((none / "design.json").read_text())) == \
        _no_times(json.loads((drawn / "design.json").read_text()))
    for page in ("report.html", "fit_report.html"):
        a, b = (none / page).read_text(encoding="utf-8"), (drawn / page).read_text(encoding="utf-8")
        assert not _IMG.search(a)
        assert _NOTE.findall(a) == _IMG.findall(b) and len(_IMG.findall(b)) >= 3  # the same pictures, named
        assert _NOTE.sub("[picture]", a) == _IMG.sub("[picture]", b)


def test_no_figures_in_the_reports_of_a_scene_that_draws_none():
    images = report.NoFigures({"cs_figure": "<div>figure</div>"})
    assert images and images.get("cs_figure") == "<div>figure</div>"
    assert report.NoFigures({}).get("cs_figure") is None  # an HTML piece not made yet: made by the report
    assert images.get("stress") == b"" and "stress" not in images  # no stress.png file written
    page = report.without_figures('<p>a</p><img src="data:image/png;base64," alt="stresses"><p>b</p>', "mine")
    assert page == ('<p>a</p><p class="skip">Figure (stresses) not drawn: the <b>mine</b> scene draws no figures '
                    '(<code>figures = "none"</code>); <code>profilegen design --scene mine --figures</code> draws '
                    'them.</p><p>b</p>')


@pytest.mark.slow
@pytest.mark.xdist_group("default_sketch")
def test_cli_sketch_writes_no_png(default_sketch_run):
    """`profilegen design default --scene sketch` (the run conftest.py shares): DXF, JSON, CSV and
    the reports, no PNG; report.html tells how to get the figures."""
    res, out = default_sketch_run
    assert res.returncode == 0, res.stderr
    names = {p.name for p in out.iterdir()}
    assert {"report.html", "fit_report.html", "circular_spline.dxf", "design.json", "envelope.csv"} <= names
    assert not any(n.endswith(".png") for n in names)
    assert "profilegen design --scene sketch --figures</code> draws them" in (out / "report.html").read_text()
