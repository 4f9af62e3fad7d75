"""``profilegen app`` in a real browser: Debian's chromium, headless, driven by Selenium through
/usr/bin/chromedriver (never Selenium Manager), as tests/validation/test_browser.py drives the report.

One server on a free port (sketch scene, a fresh workspace); each test loads the page (a new
session). What a designer does: change a field and see the profile and the verdict change, undo,
enter a bad value and read the reader's own line under the field, pin a design and compare, export
and read the DXF back; and the browser's console stays free of errors throughout.

Screenshots go to tmp_path; with ``PROFILEGEN_APP_SHOTS=docs/img`` they are written there as
``app_default.png``, ``app_fail.png`` and ``app_compare.png`` (how the docs' pictures are made):

    PROFILEGEN_APP_SHOTS=docs/img python -m pytest -q -n 0 tests/app/test_app_browser.py

Skipped, with the reason, where chromium, chromedriver or selenium is missing.
"""

from __future__ import annotations

import json
import math
import os
import threading
import time
from pathlib import Path

import pytest

from tests.chromium import driver as chrome_driver, missing as _missing

SCREEN = (1440, 900)
SHOTS_ENV = "PROFILEGEN_APP_SHOTS"
WAIT_S = 40


pytestmark = [pytest.mark.skipif(_missing() is not None, reason=_missing() or ""),
              pytest.mark.xdist_group("app_browser"), pytest.mark.slow]


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("workspace")


@pytest.fixture(scope="module")
def app(workspace):
    from profilegen.app import start

    running = start(workspace=workspace, scene="sketch")
    try:
        yield running
    finally:
        running.stop()


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    driver = chrome_driver(tmp_path_factory.mktemp("chromium-profile"), SCREEN, {"browser": "ALL"})
    try:
        yield driver
    finally:
        driver.quit()


def _shot(browser, tmp_path, name: str) -> Path:
    folder = Path(os.environ.get(SHOTS_ENV) or tmp_path)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"app_{name}.png"
    browser.execute_script("window.scrollTo(0, 0)")
    assert browser.save_screenshot(str(path))
    assert path.stat().st_size > 20_000
    return path


def _no_console_errors(browser) -> None:
    severe = [e["message"] for e in browser.get_log("browser") if e.get("level") == "SEVERE"]
    assert not severe, severe


_STATE = """
const g = document.querySelector('#space .js-plotly-plot');
const fl = g && g._fullLayout;
const space = g && g.data ? g.data.find(t => (t.name || '').startsWith('CS space')) : null;
const v = document.getElementById('verdict-status');
const p = document.getElementById('progress');
const job = p ? /^job ([0-9]+),/.exec(p.textContent) : null;
const profile = p ? /, profile of job ([0-9]+)/.exec(p.textContent) : null;
return {job: job ? Number(job[1]) : null, figure_job: fl && fl.meta ? fl.meta.job : null,
        profile_job: profile ? Number(profile[1]) : null,
        traces: g && g.data ? g.data.map(t => t.name) : [], space_name: space ? space.name : null,
        space: space ? [space.x.length, space.x[0], space.y[0], space.x[space.x.length - 1]] : null,
        status: v ? v.textContent : null, line: (document.getElementById('verdict-line') || {}).textContent || null,
        done: p ? p.textContent.includes(', done') : false, progress: p ? p.textContent : '',
        verdict: (document.getElementById('verdict') || {}).textContent || null};
"""


def _state(browser) -> dict:
    return browser.execute_script(_STATE)


def _settled(browser, *, after_job: int = 0) -> dict:
    """The page once a design newer than ``after_job`` is drawn and finished: its verdict shown and
    the figures of its profile (those of the job that first drew it: the figures travel apart from
    the numbers, once per profile)."""
    from selenium.common.exceptions import TimeoutException
    from selenium.webdriver.support.ui import WebDriverWait

    try:
        WebDriverWait(browser, WAIT_S, poll_frequency=0.05).until(
            lambda d: (lambda s: s["job"] is not None and s["job"] > after_job and s["done"] and s["status"]
                       and s["figure_job"] == s["profile_job"])(_state(d)))
    except TimeoutException:
        import sys
        import threading
        import traceback

        names = {t.ident: t.name for t in threading.enumerate()}
        stacks = "".join(f"--- {names.get(i)}\n" + "".join(traceback.format_stack(f)[-6:])
                         for i, f in sys._current_frames().items() if "compute" in str(names.get(i)))
        raise AssertionError(f"{stacks}\nno design after job {after_job}: {_state(browser)}; status "
                             f"{browser.find_element('id', 'status').text!r}") from None
    return _state(browser)


def _open(browser, app) -> dict:
    """The page, loaded once for the module (each load is a new session and a first design); the
    tests go on from where the one before left it."""
    if browser.current_url != app.url:
        browser.get(app.url)
    return _settled(browser)


def _by_id(browser, kind: str, path: str):
    """A pattern-matching component's element (Dash writes the dict id as JSON, keys sorted)."""
    element = browser.execute_script("return document.getElementById(arguments[0])",
                                     json.dumps({"path": path, "type": kind}, separators=(",", ":")))
    assert element is not None, (kind, path)
    return element


def _field(browser, path: str):
    return _by_id(browser, "field", path)


def _type(browser, path: str, text: str) -> None:
    from selenium.webdriver.common.keys import Keys

    box = _field(browser, path)
    browser.execute_script("arguments[0].scrollIntoView({block: 'center'})", box)
    box.send_keys(Keys.CONTROL, "a")
    box.send_keys(text + Keys.ENTER)


def _error_text(browser, path: str) -> str:
    return _by_id(browser, "error", path).text


def _click(browser, element_id: str) -> None:
    from selenium.webdriver.common.by import By

    browser.find_element(By.ID, element_id).click()


def test_a_field_change_redraws_the_profile_and_a_torque_change_fails_the_verdict(browser, app, tmp_path):
    first = _open(browser, app)
    assert "FS tooth, poses through the mesh" in first["traces"] and first["space"] is not None
    assert first["status"] in ("PASS", "INCOMPLETE")  # the sketch scene checks no contact: INCOMPLETE
    # the sketch scene chooses no design section: its legend does not call the space the part to cut
    assert first["space_name"].startswith("CS space (sketch: not the part to cut)")
    assert not any("to cut" in t and "not the part" not in t for t in first["traces"])
    _shot(browser, tmp_path, "default")
    # a deeper deflection: another envelope, another CS space
    _type(browser, "wave_generator.deflection_coefficient", "1.1")
    second = _settled(browser, after_job=first["job"])
    assert second["space"] != first["space"]
    assert "wave_generator.deflection_coefficient = 1.1" in browser.find_element("id", "status").text
    # a momentary torque far above the set's: the cup bottom yields, and the verdict says so
    _type(browser, "torque.momentary_nm", "3000")
    third = _settled(browser, after_job=second["job"])
    assert third["status"] == "FAIL"
    assert "yield safety" in third["line"] and "3000 N·m" in third["line"]
    assert third["space"] == second["space"]  # the torque does not move the profile
    assert third["figure_job"] == second["figure_job"] == second["job"]  # so its figures were not sent again
    _shot(browser, tmp_path, "fail")
    # undo: the torque back, the verdict back
    _click(browser, "undo")
    fourth = _settled(browser, after_job=third["job"])
    assert fourth["status"] == second["status"] and _field(browser, "torque.momentary_nm").get_attribute(
        "value") == "1200.0"
    _no_console_errors(browser)


def test_a_slider_step_redesigns_and_writes_its_value_into_the_box(browser, app):
    from selenium.webdriver.common.keys import Keys

    first = _open(browser, app)
    path = "wave_generator.deflection_coefficient"
    before = float(_field(browser, path).get_attribute("value"))
    handle = _by_id(browser, "slider", path).find_element("css selector", "[role=slider]")
    browser.execute_script("arguments[0].scrollIntoView({block: 'center'})", handle)
    handle.send_keys(Keys.ARROW_RIGHT)  # one step of the slider, as a drag released there
    after = _settled(browser, after_job=first["job"])
    now = float(handle.get_attribute("aria-valuenow"))
    assert now > before and float(_field(browser, path).get_attribute("value")) == now
    assert after["space"] != first["space"]
    _no_console_errors(browser)


def test_a_bad_value_shows_the_readers_line_under_its_field(browser, app):
    first = _open(browser, app)
    _type(browser, "gear.module_mm", "-0.5")
    from selenium.webdriver.support.ui import WebDriverWait

    WebDriverWait(browser, WAIT_S).until(lambda d: _error_text(d, "gear.module_mm"))
    assert _error_text(browser, "gear.module_mm").startswith("gear.module_mm = -0.5 mm: must be in [1e-05, 10]")
    _type(browser, "torque.rated_nm", "lots")
    WebDriverWait(browser, WAIT_S).until(lambda d: _error_text(d, "torque.rated_nm"))
    assert _error_text(browser, "torque.rated_nm") == 'torque.rated_nm = "lots": must be a number, got string'
    time.sleep(0.3)
    assert _state(browser)["job"] == first["job"]  # nothing was computed from a bad set
    _type(browser, "gear.module_mm", "0.5")
    _type(browser, "torque.rated_nm", "265")
    WebDriverWait(browser, WAIT_S).until(lambda d: not _error_text(d, "torque.rated_nm"))
    assert not _error_text(browser, "gear.module_mm")
    assert "Traceback" not in browser.page_source
    _no_console_errors(browser)


def test_pin_a_design_and_compare_the_next_one_over_it(browser, app, tmp_path):
    first = _open(browser, app)
    _click(browser, "pin")
    from selenium.webdriver.support.ui import WebDriverWait

    WebDriverWait(browser, WAIT_S).until(lambda d: "A (pinned): CS space" in _state(d)["traces"])
    _type(browser, "tooth.dedendum_coefficient", "1.3")
    second = _settled(browser, after_job=first["job"])
    assert "A (pinned): CS space" in second["traces"] and second["space"] != first["space"]
    table = browser.find_element("id", "numbers").text
    assert "A" in table.split("\n")[0] and "B" in table.split("\n")[0]
    changed = browser.find_elements("css selector", "#numbers .pg-changed")
    assert changed, "the numbers that moved are highlighted"
    # the fit error follows the CS space (its own callback, on the space drawn): A under B there too
    WebDriverWait(browser, WAIT_S).until(lambda d: "A (pinned)" in d.execute_script(_ERROR_TRACES))
    _shot(browser, tmp_path, "compare")
    _click(browser, "unpin")
    WebDriverWait(browser, WAIT_S).until(lambda d: "A (pinned): CS space" not in _state(d)["traces"])
    WebDriverWait(browser, WAIT_S).until(lambda d: "A (pinned)" not in d.execute_script(_ERROR_TRACES))
    _no_console_errors(browser)


_ERROR_TRACES = """
const g = document.querySelector('#fit-error .js-plotly-plot');
return g && g.data ? g.data.map(t => t.name) : [];
"""


_FS_AT = """
const t = document.querySelector('#space .js-plotly-plot').data.find(t => (t.name || '').startsWith('FS tooth at'));
return [t.x, t.y];
"""


def _off_line(points, xs, ys):
    """Each point's distance (mm) to the polyline xs, ys (None: a gap)."""
    import numpy as np

    line = np.array([[np.nan, np.nan] if x is None else [x, y] for x, y in zip(xs, ys)], float)
    a, b = line[:-1], line[1:]
    ok = np.all(np.isfinite(a) & np.isfinite(b), axis=1)
    a, b = a[ok], b[ok]
    d = b - a
    p = np.asarray(points, float)[:, None, :]
    t = np.clip(np.sum((p - a) * d, axis=2) / np.maximum(np.sum(d * d, axis=1), 1e-300), 0.0, 1.0)
    return np.min(np.linalg.norm(p - (a + t[..., None] * d), axis=2), axis=1)


def _zoom_to(browser, centre, half: float) -> None:
    """Zoom the CS space to the box of half-width ``half`` (mm) about ``centre``, as a drag does."""
    browser.execute_script("""
        Plotly.relayout(document.querySelector('#space .js-plotly-plot'),
                        {'xaxis.range': [arguments[0] - arguments[2], arguments[0] + arguments[2]],
                         'yaxis.range': [arguments[1] - arguments[2], arguments[1] + arguments[2]]});""",
                           float(centre[0]), float(centre[1]), half)


def test_a_zoom_gets_the_points_of_its_view(browser, app):
    """The page gets the CS space's lines thinned for the view it shows (a quarter pixel off the
    whole figure's line at most); zoomed to a 2 µm box where the opening view's line is that far
    off, the points there arrive (a Patch) and the line drawn follows the whole figure's to a
    quarter pixel of the zoom (~1 nm)."""
    import numpy as np
    from selenium.webdriver.support.ui import WebDriverWait

    _open(browser, app)
    sessions = app.app.profilegen_sessions
    with sessions._lock:  # the page's tab: the one its polls used last
        tab = next(reversed(sessions._items.values()))
    whole = next(t for t in tab.space[1]["data"] if t["name"].startswith("FS tooth at"))  # the whole figure
    pts = np.column_stack([whole["x"], whole["y"]]).astype(float)
    off = _off_line(pts, *browser.execute_script(_FS_AT))
    centre = pts[int(np.argmax(off))]
    assert 1e-5 < off.max() <= 0.25 * 1.4 / 520  # 10 nm ... a quarter pixel of the opening view (~1.4 mm high)
    opening = browser.execute_script("const l = document.querySelector('#space .js-plotly-plot').layout;"
                                     "return [l.xaxis.range.slice(), l.yaxis.range.slice()];")
    half = 1e-3
    _zoom_to(browser, centre, half)
    WebDriverWait(browser, WAIT_S, poll_frequency=0.05).until(
        lambda d: _off_line([centre], *d.execute_script(_FS_AT))[0] < 1e-9)
    box = pts[np.all(np.abs(pts - centre) <= half, axis=1)]
    assert len(box) > 3
    assert float(np.max(_off_line(box, *browser.execute_script(_FS_AT)))) <= 0.25 * 2 * half / 520
    # back to the opening view: its thinned lines again (the tests after this one see the page as opened)
    browser.execute_script("Plotly.relayout(document.querySelector('#space .js-plotly-plot'), "
                           "{'xaxis.range': arguments[0], 'yaxis.range': arguments[1]});", *opening)
    WebDriverWait(browser, WAIT_S, poll_frequency=0.05).until(
        lambda d: _off_line([centre], *d.execute_script(_FS_AT))[0] > 1e-5)
    _no_console_errors(browser)


def test_a_zoom_while_a_change_computes_gets_the_new_profile_at_its_view(browser, app):
    """The figures of a change leave from the request's own wait for its profile; a zoom while it
    waits supersedes that call on the page (the browser keeps a callback's newest response), so the
    zoom's call waits in its turn and brings the new profile's figure, thinned for the zoomed view:
    the page ends on the new job's figure, at the zoom, with the points of the zoom."""
    import numpy as np

    first = _open(browser, app)
    sessions = app.app.profilegen_sessions
    with sessions._lock:
        tab = next(reversed(sessions._items.values()))
    fast = tab.computer._compute
    started = threading.Event()

    def slow(gs, scene, **kw):  # the profile comes 1.5 s after the request: time to zoom meanwhile
        started.set()
        time.sleep(1.5)
        return fast(gs, scene, **kw)

    tab.computer._compute = slow
    try:
        value = float(_field(browser, "wave_generator.deflection_coefficient").get_attribute("value"))
        _type(browser, "wave_generator.deflection_coefficient", f"{value + 0.004:.6g}")
        assert started.wait(WAIT_S)
        x, y = browser.execute_script(_FS_AT)
        centre = np.array([np.nanmean(np.asarray(x, float)), np.nanmean(np.asarray(y, float))])
        half = 2e-3
        _zoom_to(browser, centre, half)
        assert tab.figure_wait is not None  # the zoom came while the request waited for its profile
        second = _settled(browser, after_job=first["job"])
    finally:
        tab.computer._compute = fast
    assert second["figure_job"] == second["job"] > first["job"] and second["space"] != first["space"]
    # the page stays at the zoom (its y range as asked, x widened for the equal axes)
    (x0, x1), (y0, y1) = browser.execute_script(
        "const l = document.querySelector('#space .js-plotly-plot').layout; return [l.xaxis.range, l.yaxis.range];")
    assert abs(y0 - (centre[1] - half)) < 1e-9 and abs(y1 - (centre[1] + half)) < 1e-9
    assert x0 <= centre[0] - half and centre[0] + half <= x1 and x1 - x0 < 8 * half
    whole = next(t for t in tab.space[1]["data"] if t["name"].startswith("FS tooth at"))
    pts = np.column_stack([whole["x"], whole["y"]]).astype(float)
    box = pts[np.all(np.abs(pts - centre) <= half, axis=1)]
    if len(box):  # the new pose's line through the zoom is drawn to a quarter pixel of the zoom
        assert float(np.max(_off_line(box, *browser.execute_script(_FS_AT)))) <= 0.25 * 2 * half / 520
    browser.execute_script("Plotly.relayout(document.querySelector('#space .js-plotly-plot'), "
                           "{'xaxis.autorange': true, 'yaxis.autorange': true});")
    _click(browser, "undo")
    _settled(browser, after_job=second["job"])
    _no_console_errors(browser)


def test_export_writes_the_design_folder_and_the_dxf_reads_back(browser, app, workspace):
    import ezdxf

    _open(browser, app)
    _click(browser, "export")
    from selenium.webdriver.support.ui import WebDriverWait

    WebDriverWait(browser, WAIT_S).until(lambda d: d.find_elements("id", "export-done")
                                         or d.find_elements("css selector", "#status .pg-bad"))
    assert browser.find_elements("id", "export-done"), browser.find_element("id", "status").text
    folder = workspace / "export" / "default"
    doc = ezdxf.readfile(folder / "circular_spline.dxf")
    cs = [e for e in doc.modelspace() if e.dxf.layer == "CS"]
    assert cs
    # every point of the CS outline lies within two modules of the CS pitch circle, r2 = m·z2/2 = 50.5 mm
    radii = []
    for e in cs:
        if e.dxftype() == "LWPOLYLINE":
            radii += [math.hypot(x, y) for x, y in e.get_points("xy")]
        elif e.dxftype() == "ARC":
            cx, cy = e.dxf.center.x, e.dxf.center.y
            for a in (e.dxf.start_angle, e.dxf.end_angle):
                radii.append(math.hypot(cx + e.dxf.radius * math.cos(math.radians(a)),
                                        cy + e.dxf.radius * math.sin(math.radians(a))))
        elif e.dxftype() == "LINE":
            radii += [math.hypot(e.dxf.start.x, e.dxf.start.y), math.hypot(e.dxf.end.x, e.dxf.end.y)]
    assert len(radii) > 202 and all(abs(r - 50.5) < 2 * 0.5 for r in radii)
    assert (workspace / "export" / "default.toml").is_file()
    import profilegen as pg

    assert pg.load_gearset(workspace / "export" / "default.toml").gear.circular_spline_teeth == 202
    _no_console_errors(browser)


def test_two_tabs_edit_independently(browser, app):
    """Each tab is its own session: an edit, its design and its undo history in one tab leave the
    other's field, drawn design and history as they were."""
    path = "tooth.addendum_coefficient"
    first = _open(browser, app)
    tab_a = browser.current_window_handle
    value_a = _field(browser, path).get_attribute("value")
    undo_a = _by_id_plain(browser, "undo").get_attribute("disabled")
    browser.switch_to.new_window("tab")
    try:
        browser.get(app.url)
        b0 = _settled(browser)
        assert _field(browser, path).get_attribute("value") == "0.8"  # a new tab starts from the set as given
        _type(browser, path, "0.83")
        b1 = _settled(browser, after_job=b0["job"])
        assert b1["space"] != b0["space"] and _by_id_plain(browser, "undo").get_attribute("disabled") is None
        _no_console_errors(browser)
    finally:
        browser.close()
        browser.switch_to.window(tab_a)
    time.sleep(3 * 0.15)  # a few of the tab's polls: nothing new for it
    a = _state(browser)
    assert _field(browser, path).get_attribute("value") == value_a
    assert (a["job"], a["figure_job"], a["space"]) == (first["job"], first["figure_job"], first["space"])
    assert _by_id_plain(browser, "undo").get_attribute("disabled") == undo_a
    _no_console_errors(browser)


def _by_id_plain(browser, element_id: str):
    from selenium.webdriver.common.by import By

    return browser.find_element(By.ID, element_id)
