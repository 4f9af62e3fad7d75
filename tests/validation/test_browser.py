"""report.html in a real browser: Debian's chromium, headless, driven by Selenium through
/usr/bin/chromedriver (never Selenium Manager, which would download a browser).

What a designer gets: the interactive CS space renders (an SVG plot with its traces), keeps
sub-µm detail when zoomed to a 1 µm window (plotly's SVG ``scatter`` draws from float64; WebGL
would step at ~4 nm and worse), the page loads nothing from the network and logs no error, and
the first screen (1366×768) holds the verdict, the checks and the diameters to cut (in the
sketch scene every number of the sheet), and nothing of the sheet's left half runs under the
figure.

The screenshot of the first screen is saved to tmp_path; with
``PROFILEGEN_DESIGN_SHEET_PNG=docs/design_sheet.png`` the test designs the default set in the
``design`` scene (contact and stresses, ~20 s) and saves the screenshot there — that is how
``docs/design_sheet.png`` is made:

    PROFILEGEN_DESIGN_SHEET_PNG=docs/design_sheet.png python -m pytest -n 0 tests/validation/test_browser.py

Skipped, with the reason, where chromium, chromedriver or selenium is missing (.ci/run installs
chromium and chromium-driver with apt-get).
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import pytest

from tests.chromium import driver as chrome_driver, missing as _missing

SCREEN = (1366, 768)
SHOT_ENV = "PROFILEGEN_DESIGN_SHEET_PNG"


pytestmark = pytest.mark.skipif(_missing() is not None, reason=_missing() or "")


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    """report.html of the default set: the ``sketch`` scene (seconds), or the ``design`` scene
    when a screenshot for the docs is asked for."""
    import profilegen as pg
    from profilegen.output.report import design_report_html

    scene = "design" if os.environ.get(SHOT_ENV) else "sketch"
    result = pg.design(pg.load_gearset(pg.default_gearset_path()), scene=scene)
    path = tmp_path_factory.mktemp("report") / "report.html"
    path.write_text(design_report_html(result), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    driver = chrome_driver(tmp_path_factory.mktemp("chromium-profile"), SCREEN, {"browser": "ALL", "performance": "ALL"})
    try:
        yield driver
    finally:
        driver.quit()


def _loaded(driver, report: Path) -> None:
    from selenium.webdriver.support.ui import WebDriverWait

    driver.get(report.as_uri())
    WebDriverWait(driver, 60).until(lambda d: d.execute_script(
        "const g = document.getElementById('cs-space'); return !!(g && g._fullLayout && g.querySelector('svg.main-svg'));"))


def test_report_renders_offline_without_errors(browser, report, tmp_path):
    text = report.read_text(encoding="utf-8")
    assert not re.search(r"<script[^>]+src=", text), "report.html loads a script from elsewhere"
    _loaded(browser, report)
    # a viewport-sized screenshot first, before anything is zoomed
    shot = Path(os.environ.get(SHOT_ENV) or tmp_path / "design_sheet.png")
    shot.parent.mkdir(parents=True, exist_ok=True)
    assert browser.save_screenshot(str(shot))
    assert shot.stat().st_size > 10_000

    traces = browser.execute_script(
        "const g = document.getElementById('cs-space');"
        "return {n: g.data.length, types: g.data.map(t => t.type),"
        "        drawn: g.querySelectorAll('g.trace.scatter path.js-line').length,"
        "        gl: g.querySelectorAll('canvas.gl-canvas').length};")
    assert traces["n"] >= 2 and set(traces["types"]) == {"scatter"}
    assert traces["drawn"] >= 2, traces  # SVG line paths, not just empty trace groups
    severe = [e for e in browser.get_log("browser") if e.get("level") == "SEVERE"]
    assert not severe, severe
    requests = [json.loads(e["message"])["message"] for e in browser.get_log("performance")]
    urls = {m["params"]["request"]["url"] for m in requests if m.get("method") == "Network.requestWillBeSent"}
    remote = sorted(u for u in urls if u.startswith(("http:", "https:", "ws:", "wss:", "ftp:")))
    assert not remote, remote

    # the first screen: the verdict and the numbers to cut are visible without scrolling
    first = browser.execute_script(
        "const r = e => e.getBoundingClientRect();"
        "const v = document.querySelector('.ds .verdict');"
        "const rows = [...document.querySelectorAll('.ds table tr')].filter(tr => /CS tip Ø|CS root Ø|smallest clearance/.test(tr.textContent));"
        "const last = [...document.querySelectorAll('.ds .numbers tr')].pop();"
        "return {verdict: r(v).bottom, rows: rows.map(tr => r(tr).bottom), h: window.innerHeight, w: window.innerWidth,"
        "        last: r(last).bottom,"
        "        wide: document.documentElement.scrollWidth,"
        "        clipped: (n => n.scrollWidth - n.clientWidth)(document.querySelector('.ds .numbers'))};")
    assert first["verdict"] < first["h"]
    assert (first["w"], first["h"]) == SCREEN
    assert len(first["rows"]) == 3 and max(first["rows"][:2]) < first["h"], first  # the diameters to cut
    if not os.environ.get(SHOT_ENV):  # the sketch scene's sheet: every number, stiffness included
        assert max(first["rows"]) < first["h"] and first["last"] < first["h"], first
    # (the design scene's, for the docs, has the face's rows and the stiffness too: they follow below)
    assert first["wide"] <= first["w"], "the first screen scrolls sideways"
    # the checks' and numbers' tables fit their half of the screen: nothing runs under the figure
    # (the checks table's margin and pass columns once did, cut off at 'marg')
    assert first["clipped"] <= 1, first


def test_zoom_to_one_micron_keeps_the_detail(browser, report):
    """Zoom to a 1 µm × 1 µm window on the fitted flank: plotly draws the flank across it as a
    line of many vertices whose pixel positions follow the data to better than a pixel (float64);
    the window's own axis range is kept to 1e-9 mm."""
    _loaded(browser, report)
    out = browser.execute_async_script("""
        const done = arguments[arguments.length - 1];
        const g = document.getElementById('cs-space');
        const k = g.data.findIndex(t => t.name.startsWith('CS space to cut'));
        const t = k >= 0 ? g.data[k] : g.data.find(t => t.name.startsWith('exact flank'));
        const kk = g.data.indexOf(t);
        // a point on the right flank, halfway up
        const idx = t.x.map((x, i) => i).filter(i => t.x[i] > 0);
        const i0 = idx[Math.floor(idx.length / 2)];
        const cx = t.x[i0], cy = t.y[i0], h = 0.0005;  // mm: a 1 µm window
        Plotly.relayout(g, {'xaxis.range': [cx - h, cx + h], 'yaxis.range': [cy - h, cy + h]}).then(() => {
            const xa = g._fullLayout.xaxis, ya = g._fullLayout.yaxis;
            const inside = idx.filter(i => Math.abs(t.x[i] - cx) < h && Math.abs(t.y[i] - cy) < h);
            // pixel of each vertex from the axes' float64 maps, and from the drawn path
            const path = g.querySelectorAll('g.trace.scatter')[kk].querySelector('path.js-line');
            const d = path ? path.getAttribute('d') : '';
            const drawn = (d.match(/-?\\d+(\\.\\d+)?,-?\\d+(\\.\\d+)?/g) || []).length;
            done({cx: cx, cy: cy, inside: inside.length, drawn: drawn,
                  xr: xa.range, yr: ya.range, px: inside.map(i => [xa.c2p(t.x[i]), ya.c2p(t.y[i])]),
                  type: t.type, w: xa._length, hpx: ya._length});
        });
    """)
    assert out["type"] == "scatter"
    # the range the browser holds is the 1 µm window, to 1e-9 mm (float32 would be ~4e-6 mm off at 50 mm)
    # (equal axes: plotly widens the longer side of the plot area's window to keep the scale)
    spans = sorted((out["xr"][1] - out["xr"][0], out["yr"][1] - out["yr"][0]))
    assert spans[0] == pytest.approx(1e-3, abs=1e-9) and spans[1] < 2.5e-3, out
    assert out["inside"] >= 3, out  # the data has sub-µm vertex spacing
    assert out["drawn"] >= 3, out  # and the SVG line is drawn through the window
    px = out["px"]
    # consecutive vertices < 1 µm apart land on distinct, ordered pixels across the window
    ys = [p[1] for p in px]
    assert max(ys) - min(ys) > 0.2 * out["hpx"], out
    assert all(abs(a - b) > 0.5 for a, b in zip(ys, ys[1:])), out
