"""``profilegen.app.show()``, the workbench in a Jupyter cell, without a notebook or a browser: the
call returns (a cell must not block), its HTML is an iframe of the served page, the page and its
layout (a new tab's form) are served from this process, and ``stop()`` ends the server."""

from __future__ import annotations

import json
import threading
import urllib.error
import urllib.request

import pytest

import profilegen as pg


def _get(url: str) -> tuple[int, str]:
    with urllib.request.urlopen(url, timeout=20) as r:
        return r.status, r.read().decode()


def test_show_serves_the_app_for_a_cell_and_stops(tmp_path):
    from profilegen.app import Notebook, show

    out = {}
    call = threading.Thread(target=lambda: out.setdefault("nb", show(pg.load_gearset("default"), workspace=tmp_path,
                                                                     scene="sketch", height=700)))
    call.start()
    call.join(30)
    assert not call.is_alive(), "show() blocked: a notebook cell would never finish"
    nb = out["nb"]
    try:
        assert isinstance(nb, Notebook)
        host, port = nb.url.removeprefix("http://").rstrip("/").split(":")
        assert host == "127.0.0.1" and int(port) > 0  # this machine only, a free port
        html = nb._repr_html_()
        assert html.startswith("<iframe") and f'src="{nb.url}"' in html and 'height="700"' in html
        status, page = _get(nb.url)
        assert status == 200 and "<title>profilegen</title>" in page
        sessions = nb.app.profilegen_sessions
        before = len(sessions._items)
        status, layout = _get(nb.url + "_dash-layout")  # what a tab gets: a new session's page
        assert status == 200
        text = json.dumps(json.loads(layout))
        assert '"torque.rated_nm"' in text and '"sid"' in text
        assert len(sessions._items) == before + 1
    finally:
        nb.stop()
    # the server is gone: refused (URLError), or reset by a listener being torn down as we connect
    with pytest.raises((urllib.error.URLError, ConnectionError)):
        _get(nb.url)
