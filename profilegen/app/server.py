"""The workbench as a Dash application: the page, its callbacks, and the local server.

Why Dash: its figures are plotly's, the same zoomable SVG figures ``report.html`` and the notebook
view draw (float64 paths, sub-µm zoom), from the ``plotly`` the package already depends on; it is
a small addition (Flask and a few pure-Python packages, no pandas, no bokeh server), serves its
scripts from the installed package (offline), and runs in a Jupyter cell
(``app.run(jupyter_mode="inline")``, see :func:`profilegen.app.show`).

Every callback runs on one of the server's request threads and never lets an exception through:
a bad value is the reader's own line under its field, anything else one line in the status bar
(the traceback goes to the server's log). The designs are computed on each tab's own thread
(:class:`profilegen.app.session.Computer`).
"""

from __future__ import annotations

import logging
import sys
import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING

import dash

from ..errors import ProfilegenError
from ..gearset import GearSet, list_profiles, load_gearset
from . import schema, views
from .session import BUNDLED, Session, Sessions, Snapshot, Workspace, WorkspaceError

if TYPE_CHECKING:
    from dash.development.base_component import Component
    from dash.dependencies import Wildcard

__all__ = ["make_app", "serve", "start"]

log = logging.getLogger(__name__)

SCENES = ("sketch", "design", "verify")
POLL_MS = 200
#: how long a poll waits on the server for the next snapshot (a long poll): a design finished
#: while a poll waits reaches the page at once, not on the next tick; well under POLL_MS, so a
#: poll's response is back before the next one starts (Dash drops the response of a callback
#: when a newer call of it is on its way: with 0.12 s of 0.15 s, seen in the browser, one poll
#: in three was dropped under load and its snapshot sent again)
POLL_WAIT_S = 0.1
#: how long the request's own response waits for its design (or its profile) before it draws the
#: progress: a change that computes within it is drawn without the poll's next tick (a design-scene
#: torque change: drawn 0.35 → 0.18 s, tests/benchmarks/app_latency.py). Not longer: the poll
#: ticks within a longer wait and Dash keeps only the newest call's response (0.3 s: 0.32 s drawn)
REQUEST_WAIT_S = 0.1
#: the longest the figures' callback waits for the profile of the page's request (it returns as soon
#: as the profile is there, or a newer request supersedes it, or the design fails)
FIGURE_WAIT_S = 600.0


_CSS = """
body{margin:0;font:13px system-ui,sans-serif;color:#222;background:#f6f7f9}
.pg-head{display:flex;flex-wrap:wrap;gap:6px 10px;align-items:center;padding:6px 10px;background:#23344d;color:#fff}
.pg-head h1{font-size:15px;margin:0 10px 0 0}
.pg-head button{font-size:12px;padding:3px 8px;border-radius:3px;border:1px solid #889;background:#fff;cursor:pointer}
.pg-head button:disabled{opacity:.45;cursor:default}
.pg-head .pg-dd{width:230px;color:#222;font-size:12px}
.pg-head .pg-scene{width:120px;color:#222;font-size:12px}
.pg-head input{font-size:12px;padding:3px;width:140px;color:#222}
.pg-status{padding:3px 10px;min-height:18px;font-size:12px;background:#eef1f5;border-bottom:1px solid #ddd}
.pg-status .pg-bad{color:#b00020}
.pg-body{display:flex;gap:8px;padding:8px;align-items:flex-start}
.pg-form{width:360px;flex:none;max-height:calc(100vh - 90px);overflow-y:auto;background:#fff;border:1px solid #ddd;
 border-radius:4px;padding:6px 8px}
.pg-form h3{font-size:12px;margin:10px 0 4px;color:#23344d;text-transform:uppercase;letter-spacing:.04em}
.pg-field{display:grid;grid-template-columns:150px 1fr;gap:0 6px;align-items:center;margin:2px 0}
.pg-field label{font-size:12px;overflow:hidden;text-overflow:ellipsis;white-space:nowrap}
.pg-field input{width:100%;box-sizing:border-box;font-size:12px;padding:2px 4px;border:1px solid #bbb;border-radius:2px}
.pg-field .pg-allowed{grid-column:2;font-size:10px;color:#777}
.pg-field .pg-error{grid-column:1/3;font-size:11px;color:#b00020}
.pg-field .pg-error:empty{display:none}
.pg-slider{margin:0 0 2px}
.pg-views{flex:1;min-width:0;display:flex;flex-direction:column;gap:6px}
.pg-verdict{background:#fff;border:1px solid #ddd;border-radius:4px;padding:6px 8px}
.pg-badge{display:inline-block;padding:2px 8px;border-radius:3px;color:#fff;font-weight:600;margin-right:6px}
.pg-PASS{background:#2e7d32}.pg-FAIL{background:#c62828}.pg-INCOMPLETE{background:#b26a00}.pg-ERROR{background:#6a1b9a}
.pg-WAIT{background:#78909c}
.pg-line{font-size:12px}
.pg-checks{margin:4px 0 0;padding-left:18px;font-size:11px}
.pg-checks .pg-c-FAIL{color:#c62828;font-weight:600}
.pg-progress{font-size:11px;color:#555}
.pg-row2{display:flex;gap:6px;align-items:flex-start}
.pg-graph{background:#fff;border:1px solid #ddd;border-radius:4px;flex:1;min-width:0}
.pg-numbers{background:#fff;border:1px solid #ddd;border-radius:4px;padding:4px 6px;width:330px;flex:none;
 font-size:12px;max-height:560px;overflow-y:auto}
.pg-numbers table{border-collapse:collapse;width:100%}
.pg-numbers td,.pg-numbers th{padding:1px 4px;border-bottom:1px solid #eee;text-align:right}
.pg-numbers td:first-child,.pg-numbers th:first-child{text-align:left}
.pg-numbers .pg-changed{background:#fff3b0;font-weight:600}
.pg-numbers .pg-group td{background:#f0f3f7;font-weight:600;text-align:left;color:#23344d}
"""

_INDEX = """<!DOCTYPE html>
<html><head>{%metas%}<title>{%title%}</title>{%favicon%}{%css%}<style>""" + _CSS + """</style></head>
<body>{%app_entry%}<footer>{%config%}{%scripts%}{%renderer%}</footer></body></html>"""


# ------------------------------------------------------------------------------------------ the page

def _field_id(kind: str, path: str | Wildcard) -> dict:
    return {"type": kind, "path": path}


def form_children(s: Session) -> list:
    """The form: the sliders first, then every field of the schema by section."""
    from dash import dcc, html

    values = s.values()
    out: list[Component] = []
    sliders = [f for f in s.fields if f.slider and isinstance(values.get(f.path), (int, float))]
    if sliders:
        out.append(html.H3("sweep by hand"))
        for f in sliders:
            lo, hi, step = schema.slider_range(f, values[f.path])
            out.append(html.Div(className="pg-slider", title=f.doc, children=[
                html.Label(f"{f.path.split('.')[-1]}{' (' + f.unit + ')' if f.unit else ''}",
                           style={"fontSize": "11px"}),
                dcc.Slider(id=_field_id("slider", f.path), min=lo, max=hi, step=step, value=float(values[f.path]),
                           marks=None, updatemode="mouseup",
                           tooltip={"placement": "bottom", "always_visible": False})]))
    section = None
    for f in s.fields:
        if f.section != section:
            section = f.section
            out.append(html.H3(f"[{section}]" if section else "the set"))
        value = values.get(f.path)
        box: Component
        if f.choices:
            box = dcc.Dropdown(id=_field_id("field", f.path), options=list(f.choices), value=value, clearable=False,
                               style={"fontSize": "12px"})
        else:
            box = dcc.Input(id=_field_id("field", f.path), type="text", value=schema.form_text(value), debounce=True,
                            spellCheck=False, autoComplete="off")
        label = f"{f.key}{' (' + f.unit + ')' if f.unit else ''}"
        out.append(html.Div(className="pg-field", children=[
            html.Label(label, title=f"{f.path}: {f.doc}" if f.doc else f.path, htmlFor=f"field-{f.path}"),
            box,
            html.Div(f.allowed, className="pg-allowed"),
            html.Div(s.errors.get(f.path, ""), id=_field_id("error", f.path), className="pg-error")]))
    return out


def _file_options(ws: Workspace) -> list[dict]:
    files = [{"label": name, "value": name} for name in ws.gearset_files()]
    bundled = [{"label": f"bundled: {p.stem}", "value": BUNDLED + p.stem} for p in list_profiles()]
    return files + bundled


def _page(s: Session):
    from dash import dcc, html

    return html.Div([
        dcc.Store(id="sid", data=s.id), dcc.Store(id="req", data=0), dcc.Store(id="shown", data=0),
        dcc.Store(id="drawn", data=""),
        # always on: re-enabling a disabled Interval from a callback did not restart it reliably (Dash 4.4,
        # seen in the browser tests); an idle tick waits POLL_WAIT_S on the server for a new snapshot,
        # then is answered with 204 (nothing new)
        dcc.Interval(id="poll", interval=POLL_MS),
        html.Div(className="pg-head", children=[
            html.H1("profilegen workbench"),
            html.Span("scene"),
            html.Div(dcc.Dropdown(id="scene", options=list(SCENES), value=s.scene, clearable=False),
                     className="pg-scene"),
            html.Button("undo", id="undo", disabled=True), html.Button("redo", id="redo", disabled=True),
            html.Div(dcc.Dropdown(id="load-name", options=_file_options(s.workspace), placeholder="gear set to load"),
                     className="pg-dd"),
            html.Button("load", id="load"),
            html.Div(dcc.Input(id="save-name", type="text", value=f"{s.gearset.name}.toml", debounce=False),
                     style={"width": "150px"}),
            html.Button("save", id="save"),
            html.Button("export", id="export", title="every output file (DXF, report, ...) into export/<name>/ "
                                                     "in the workspace, and the gear set beside it"),
            html.Button("pin A", id="pin", title="pin this design; the next ones are drawn over it (A/B)"),
            html.Button("unpin", id="unpin"),
        ]),
        html.Div(id="status", className="pg-status"),
        html.Div(className="pg-body", children=[
            html.Div(id="form", className="pg-form", children=form_children(s)),
            html.Div(className="pg-views", children=[
                html.Div(id="verdict", className="pg-verdict", children=[
                    html.Span("…", className="pg-badge pg-WAIT"), html.Span("computing the first design",
                                                                           className="pg-line")]),
                html.Div(id="progress", className="pg-progress"),
                html.Div(className="pg-row2", children=[
                    html.Div(className="pg-graph", children=dcc.Graph(
                        id="space", figure={"data": [], "layout": {"height": 520, "template": {}}},
                        config={"scrollZoom": True, "displaylogo": False, "responsive": True},
                        style={"height": "520px"})),
                    html.Div(id="numbers", className="pg-numbers"),
                ]),
                html.Div(className="pg-graph", children=dcc.Graph(
                    id="fit-error", figure={"data": [], "layout": {"height": 260, "template": {}}},
                    config={"displaylogo": False, "responsive": True}, style={"height": "260px"})),
            ]),
        ]),
    ])


# ------------------------------------------------------------------------------------------ the views

def _verdict_children(snap: Snapshot, pinned):
    from dash import html

    if snap.error is not None:
        return [html.Span("ERROR", className="pg-badge pg-ERROR", id="verdict-status"),
                html.Span(f"this gear set does not design: {snap.error}", className="pg-line", id="verdict-line")]
    d = snap.design
    if not snap.done or d is None:
        left = [n for n in snap.planned if n not in snap.stages[:-1]]
        return [html.Span("…", className="pg-badge pg-WAIT"),
                html.Span(f"verdict after {', '.join(left) or 'the last stage'}", className="pg-line")]
    status, line, checks = views.verdict_parts(d)
    items = [html.Li([html.Span(st, className=f"pg-c-{st.replace(' ', '_')}"), f" {name}" + (f": {text}" if text
                      else "")]) for st, name, text in checks if st != "PASS"]
    rest = line[len(status):].lstrip(" :—") if line.startswith(status) else line
    head: list[Component] = [html.Span(status, className=f"pg-badge pg-{status}", id="verdict-status"),
                             html.Span(rest or "every check passed", className="pg-line", id="verdict-line")]
    if pinned is not None:
        head.append(html.Div(f"A (pinned, job {pinned.job}): {pinned.design.verdict.line}",
                             className="pg-line", style={"color": views.PINNED_COLOR}))
    return head + ([html.Ul(items, className="pg-checks")] if items else [])


def _numbers_children(snap: Snapshot, before: Snapshot | None, pinned: Snapshot | None):
    from dash import html

    rows = views.numbers(snap.design)
    changed = views.changes(rows, None if before is None or before.design is None else views.numbers(before.design))
    a = {} if pinned is None else {r.key: r for r in views.numbers(pinned.design)}
    head = [html.Th("quantity")] + ([html.Th("A", style={"color": views.PINNED_COLOR}), html.Th("B")]
                                    if pinned is not None else [html.Th("value")]) + [html.Th("")]
    body, group = [], None
    for r in rows:
        if r.group != group:
            group = r.group
            body.append(html.Tr(html.Td(group, colSpan=4), className="pg-group"))
        cell = html.Td(r.text, className="pg-changed" if r.key in changed else None,
                       title=f"was {changed[r.key]}" if r.key in changed else None, id=f"num-{r.key}")
        cells = [html.Td(r.label)]
        if pinned is not None:
            cells.append(html.Td(a[r.key].text if r.key in a else "–", style={"color": views.PINNED_COLOR}))
        body.append(html.Tr(cells + [cell, html.Td(r.unit)]))
    note = (f"highlighted: changed since the last design (job {before.job}); hover for the old value"
            if changed and before is not None else "")
    return [html.Table([html.Thead(html.Tr(head)), html.Tbody(body)]), html.Div(note, style={"fontSize": "10px"})]


def _progress_text(snap: Snapshot, profile_job: int | None = None) -> str:
    done = snap.stages if snap.done else snap.stages[:-1]
    running = None if snap.done or not snap.stages else snap.stages[-1]
    parts = [f"{n} ✓" if n in done else (f"{n} …" if n == running else n) for n in (snap.planned or snap.stages)]
    took = time.perf_counter() - snap.started
    state = "done" if snap.done else "computing"
    # the job whose figures show this profile (an earlier one when only the loads changed)
    profile = "" if profile_job is None else f", profile of job {profile_job}"
    return f"job {snap.job}, {snap.scene} scene, {state} ({took:.2f} s){profile}: " + " → ".join(parts)


# ------------------------------------------------------------------------------------------ callbacks

def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return text[:600]


def _failure(exc: BaseException) -> str:
    if isinstance(exc, ProfilegenError):
        return _one_line(exc)
    log.exception("profilegen app: a callback failed")
    return f"internal error ({type(exc).__name__}): {_one_line(exc)}"


def _bad(text: str):
    from dash import html

    return html.Span(text, className="pg-bad")


def _register(app, sessions: Sessions) -> None:
    """The page's callbacks: the form's edits, the verdict and numbers of each snapshot, the
    figures, save and export."""
    _register_edit(app, sessions)
    _register_render(app, sessions)
    _register_figures(app, sessions)
    _register_files(app, sessions)


def _session(sessions: Sessions, sid) -> Session:
    """The page's session; a WorkspaceError when it has ended."""
    s = sessions.get(sid)
    if s is None:
        raise WorkspaceError("this page's session has ended (the server restarted or too many tabs): reload the "
                             "page")
    return s


def _register_edit(app, sessions: Sessions) -> None:
    """The form's callback: a field or slider edit, undo / redo, the scene, a loaded gear set."""
    from dash import ALL, Input, Output, State, ctx, no_update
    from dash.exceptions import PreventUpdate

    @app.callback(
        Output(_field_id("field", ALL), "value"), Output(_field_id("slider", ALL), "value"),
        Output(_field_id("error", ALL), "children"), Output("req", "data"), Output("status", "children"),
        Output("form", "children"), Output("undo", "disabled"), Output("redo", "disabled"),
        Output("scene", "value"),
        Input(_field_id("field", ALL), "value"), Input(_field_id("slider", ALL), "value"),
        Input("undo", "n_clicks"), Input("redo", "n_clicks"), Input("scene", "value"), Input("load", "n_clicks"),
        State("sid", "data"), State("load-name", "value"),
    )
    def edit(field_values, slider_values, _undo, _redo, scene, _load, sid, load_name):
        field_ids = [o["id"]["path"] for o in ctx.outputs_list[0]]
        slider_ids = [o["id"]["path"] for o in ctx.outputs_list[1]]
        error_ids = [o["id"]["path"] for o in ctx.outputs_list[2]]
        trig = ctx.triggered_id

        def nothing(ids):
            return [no_update] * len(ids)

        keep = [nothing(field_ids), nothing(slider_ids), nothing(error_ids)] + [no_update] * 6
        try:
            s = _session(sessions, sid)
            rebuild = False
            texts = dict(zip(field_ids, field_values))
            if trig in ("undo", "redo"):
                (s.undo if trig == "undo" else s.redo)()
                rebuild, status = True, f"{trig}: {s.gearset.name}, {s.scene} scene"
            elif trig == "load":
                if not load_name:
                    raise WorkspaceError("load: pick a gear set first")
                s.load(load_name)
                rebuild, status = True, f"loaded {load_name}"
            elif trig == "scene":
                if scene == s.scene:
                    raise PreventUpdate
                s.set_scene(scene)
                status = f"scene: {scene}"
            elif isinstance(trig, dict):
                return _field_edited(s, trig, texts, slider_values, field_ids, slider_ids, error_ids, keep)
            else:  # the page's first call
                status = f"{s.gearset.name}: workspace {s.workspace.root}"
            out = list(keep)
            out[3], out[4] = s.submit(), status
            if rebuild:
                out[5] = form_children(s)
            out[6], out[7], out[8] = not s.history.can_undo, not s.history.can_redo, s.scene
            return out
        except PreventUpdate:
            raise
        except Exception as exc:  # noqa: BLE001 — never a traceback in the browser
            out = list(keep)
            out[4] = _bad(_failure(exc))
            return out


def _field_edited(s: Session, trig: dict, texts: dict, slider_values, field_ids, slider_ids, error_ids, keep) -> list:
    """The form's outputs after a field's or a slider's edit: its errors, or the submitted request,
    the other control of that field, the status, and a new form when the fields changed."""
    from dash import no_update

    def nothing(ids):
        return [no_update] * len(ids)

    if trig.get("type") == "slider":
        texts[trig["path"]] = slider_values[slider_ids.index(trig["path"])]
    before, shown = s.history.current, dict(s.errors)  # the errors the page shows (the last edit's)
    errors = s.edit(texts)
    # only the marks that change: each output prop the page gets is a round of its renderer over every
    # component (61 empty marks took ~50 ms of the browser's CPU beside the computation, on 2 cores)
    err_out = [errors.get(p, "") if p in errors or p in shown else no_update for p in error_ids]
    if errors:
        stray = errors.get("")
        out = list(keep)
        out[2], out[4] = err_out, _bad(stray or "a value is not accepted: see the marked field")
        return out
    if s.history.current is before:  # nothing changed (a form re-rendered, or the same value)
        out = list(keep)
        out[2] = err_out
        return out
    out = list(keep)
    if trig.get("type") == "slider":
        out[0] = [schema.form_text(texts[trig["path"]]) if p == trig["path"] else no_update
                  for p in field_ids]
    else:
        value = s.values().get(trig["path"])
        out[1] = [float(value) if p == trig["path"] and isinstance(value, (int, float)) else no_update
                  for p in slider_ids]
    out[2], out[3] = err_out, s.submit()
    out[4] = f"{trig['path']} = {schema.form_text(s.values().get(trig['path']))}"
    if [f.path for f in s.fields] != field_ids:  # the form itself changed (another tooth kind)
        out[0], out[1], out[2] = nothing(field_ids), nothing(slider_ids), nothing(error_ids)
        out[5] = form_children(s)
    out[6], out[7] = not s.history.can_undo, not s.history.can_redo
    return out


def _register_render(app, sessions: Sessions) -> None:
    """The verdict, numbers and progress callback (the request's first snapshot, then the long poll)."""
    from dash import Input, Output, State, ctx, no_update
    from dash.exceptions import PreventUpdate

    @app.callback(
        Output("verdict", "children"), Output("numbers", "children"), Output("progress", "children"),
        Output("shown", "data"),
        Input("req", "data"), Input("poll", "n_intervals"), Input("pin", "n_clicks"), Input("unpin", "n_clicks"),
        State("sid", "data"), State("shown", "data"),
        prevent_initial_call=True,
    )
    def render(req, _n, pin, unpin, sid, shown):
        """The verdict, the numbers and the progress line of the newest snapshot (the figures go
        their own way: :func:`figures`). On the poll it is a long poll: it waits up to POLL_WAIT_S
        for a snapshot newer than the page's (``shown``) and draws it in the same response."""
        trig = ctx.triggered_id
        try:
            s = sessions.get(sid) if trig == "poll" else _session(sessions, sid)
            if s is None:
                raise PreventUpdate
            if trig == "req":
                # the request's snapshot: its finished design if it comes within REQUEST_WAIT_S (a torque
                # change: ~0.07 s), which then reaches the page without waiting for the poll's next
                # tick; else the newest at that time, the rest by the poll
                snap = s.computer.newer(shown, timeout=REQUEST_WAIT_S) if req else None
                if snap is None or snap.job != req:
                    raise PreventUpdate  # superseded: the newer request draws
            elif trig == "poll":
                snap = s.computer.newer(shown, timeout=POLL_WAIT_S)
                if snap is None:
                    raise PreventUpdate  # nothing new (answered with 204)
            else:
                s.clicked(trig, pin if trig == "pin" else unpin)
                snap = s.computer.latest()
                if snap is None:
                    raise PreventUpdate
            out = [no_update] * 4
            design = snap.design
            token = None if design is None or design.profile is None else s.profile_token(design.profile, snap.job)
            out[2], out[3] = _progress_text(snap, token), snap.version
            if token is not None:
                with s.lock:
                    s.profile_snap = snap
                s.drawn(snap)
                before = s.before if snap.done else s.shown
                if before is not None and before.job == snap.job:
                    before = s.before
                out[1] = _numbers_children(snap, before, s.pinned)
            out[0] = _verdict_children(snap, s.pinned)
            return out
        except PreventUpdate:
            raise
        except Exception as exc:  # noqa: BLE001
            from dash import html

            return ([html.Span("ERROR", className="pg-badge pg-ERROR"), _bad(_failure(exc))],) + (no_update,) * 3


def _register_figures(app, sessions: Sessions) -> None:
    """The figures' callback: the CS space and the fit error, once per profile (waited for from the
    page's request) and on pin / unpin; the CS space's points again at each zoom or pan."""
    from dash import Input, Output, Patch, State, ctx, no_update
    from dash.exceptions import PreventUpdate

    @app.callback(
        Output("space", "figure"), Output("drawn", "data"),
        Input("req", "data"), Input("pin", "n_clicks"), Input("unpin", "n_clicks"),
        Input("space", "relayoutData"),
        State("sid", "data"), State("drawn", "data"),
        prevent_initial_call=True,
    )
    def figures(req, pin, unpin, relayout, sid, drawn):
        """The CS space (and, by ``drawn``, the error figure after it: :func:`error_figure`): once
        per profile and on pin / unpin. The page's
        request (``req``) waits here for its design's profile, and the figures leave the moment it
        is there: not a round trip after the verdict's response has reached the page (an input
        downstream of the verdict's callback would make the page hold this one until that
        callback's response). A torque change keeps the profile (the engine's cached object): its
        figures are not sent again. A callback of its own, so that the snapshots that only add
        numbers never overlap a render that sends them; and the only one that writes the figures:
        the browser keeps only the newest response of a callback, so a zoom (or a pin) while a
        request waits waits for that profile in its turn and sends its figures (what the page shows
        is read from ``drawn``).

        The CS space goes with the points that draw the same at the view the page shows
        (:func:`profilegen.app.views.lighter`: ~1 800 of the default sketch's 39 000); a zoom or a
        pan (``relayoutData``) sends the long lines' points again for the new view, as a Patch of
        their x and y alone, from the whole figure kept in the session (so a sub-µm zoom gets every
        point there is). In this callback too, so that a zoom's answer can never land on a newer
        profile's figure."""
        fired = {p.split(".")[0] for p in ctx.triggered_prop_ids}
        try:
            s = _session(sessions, sid)
            with s.lock:
                shown, waiting = s.space, s.figure_wait
            if fired == {"space"} and waiting is None and shown is not None and shown[0] == drawn:
                # a zoom alone on the figure the page shows (the renderer merges triggers that come while
                # one runs, and keeps only the newest response: a zoom, or the first figure's autosize,
                # that supersedes a figure on its way sends that figure instead, below)
                return _zoomed(s, relayout, shown), no_update
            if "space" in fired and shown is not None:
                _keep_view(s, relayout, shown)  # the figure on its way opens at the page's new view
            for trig in ("pin", "unpin"):
                if trig in fired:
                    s.clicked(trig, pin if trig == "pin" else unpin)
            job = req if "req" in fired else waiting
            snap = _request_profile(s, job) if job else None
            with s.lock:
                pinned, shown = s.pinned, s.space
                if snap is None and not job:
                    snap = s.profile_snap
            if snap is None:
                raise PreventUpdate
            design = snap.design
            token = s.profile_token(design.profile, snap.job)
            key = f"{token}:{id(pinned)}"
            if key == drawn:
                raise PreventUpdate
            with s.lock:
                ready, s.prebuilt = s.prebuilt, None
            # the figures built as the profile came, if they are of this design, pin and view
            fresh = ready is not None and ready[0] is design and ready[1][0] == key
            built = ready[1] if fresh and ready[1][3] == _view(shown, ready[1][2]) else (
                _figures_of(design, pinned, token, shown))
            with s.lock:
                s.space, s.error_figure = built[:4], (key, built[5])
            return built[4], key
        except PreventUpdate:
            raise
        except Exception as exc:  # noqa: BLE001 — the status bar says it (the figures stay)
            log.warning("profilegen app: the figures failed: %s", _failure(exc))
            raise PreventUpdate from None

    @app.callback(Output("fit-error", "figure"), Input("drawn", "data"), State("sid", "data"),
                  prevent_initial_call=True)
    def error_figure(drawn, sid):
        """The fit error and the clearance through the mesh of the CS space the page has just drawn
        (``drawn``): sent after it, so that the page draws the CS space alone first (plotly took
        11-19 ms for this figure on top of the CS space's 14-17 ms, in the same response)."""
        s = sessions.get(sid)
        if s is None:
            raise PreventUpdate
        with s.lock:
            shown = s.error_figure
        if shown is None or shown[0] != drawn:
            raise PreventUpdate
        return shown[1]

    def _request_profile(s: Session, job: int):
        """The snapshot of request ``job`` once it has its profile (also noted as the figures'
        design for a later pin); None when a newer request superseded it or it failed."""
        with s.lock:
            s.figure_wait = job
        try:
            snap = s.computer.wait(job, profile=True, timeout=FIGURE_WAIT_S)
        finally:
            with s.lock:
                if s.figure_wait == job:
                    s.figure_wait = None
        if snap is None or snap.design is None or snap.design.profile is None:
            return None
        with s.lock:
            if s.profile_snap is None or s.profile_snap.job <= snap.job:
                s.profile_snap = snap
        return snap

    def _keep_view(s: Session, relayout, shown: tuple) -> None:
        """Note a zoom that came while a request waits: its figures open at it (:func:`_view`)."""
        new = views.view_after(relayout, shown[3], shown[2])
        with s.lock:
            if new is not None and s.space is shown:
                s.space = (*shown[:3], new)

    def _zoomed(s: Session, relayout, shown):
        from dash.exceptions import PreventUpdate

        key, fig, start, view = shown
        new = views.view_after(relayout, view, start)
        if new is None:
            raise PreventUpdate  # a resize, a legend click: the axes did not move
        light = views.lighter(fig, new)
        patch = Patch()
        for i in views.heavy_traces(fig):
            patch["data"][i]["x"] = light["data"][i]["x"]
            patch["data"][i]["y"] = light["data"][i]["y"]
        with s.lock:
            if s.space is shown:
                s.space = (key, fig, start, new)
        return patch


def _view(shown, start):
    """The view a new figure opens at: the page's zoom when it has one (uirevision keeps it across
    redesigns, so a zoomed page gets the points of its zoom), else the figure's own start."""
    return shown[3] if shown is not None and shown[3] != shown[2] else start


def _figures_of(design, pinned, token: int, shown) -> tuple:
    """A profile's figures: (key, the whole CS-space figure, its start view, the view it opens at,
    the figure thinned for that view, the fit-error figure)."""
    a = pinned.design if pinned is not None else None
    fig = views.space_figure(design, pinned=a, job=token)
    start = views.initial_view(fig)
    view = _view(shown, start)
    return (f"{token}:{id(pinned)}", fig, start, view, views.lighter(fig, view), views.error_figure(design, pinned=a))


def prebuild_figures(s: Session, job: int, design) -> None:
    """Build a request's figures on the computation's thread the moment its profile is fitted,
    before the profile is published (``Session(on_profile=...)``): built there they take ~10 ms;
    on the figures' callback's thread, beside the stages still running and the verdict's callback,
    the interpreter's lock made that ~30 ms of every sketch change. A profile the page already has
    (a torque change: the engine's same object) builds nothing."""
    token = s.profile_token(design.profile, job)
    with s.lock:
        pinned, shown = s.pinned, s.space
    if shown is not None and shown[0] == f"{token}:{id(pinned)}":
        return
    try:
        built = _figures_of(design, pinned, token, shown)
    except Exception as exc:  # noqa: BLE001 — the figures' callback builds them again and says why
        log.warning("profilegen app: the figures failed: %s", _failure(exc))
        return
    with s.lock:
        s.prebuilt = (design, built)


def _register_files(app, sessions: Sessions) -> None:
    """The save and export callbacks (the gear set's TOML, the finished design's files)."""
    from dash import Input, Output, State, no_update

    @app.callback(
        Output("status", "children", allow_duplicate=True), Output("load-name", "options"),
        Input("save", "n_clicks"), State("save-name", "value"), State("sid", "data"),
        prevent_initial_call=True,
    )
    def save(_n, name, sid):
        try:
            s = _session(sessions, sid)
            path = s.workspace.save(s.gearset, name)
            return f"saved {path.relative_to(s.workspace.root).as_posix()}", _file_options(s.workspace)
        except Exception as exc:  # noqa: BLE001
            return _bad(_failure(exc)), no_update

    @app.callback(
        Output("status", "children", allow_duplicate=True),
        Input("export", "n_clicks"), State("sid", "data"),
        prevent_initial_call=True,
    )
    def export(_n, sid):
        try:
            s = _session(sessions, sid)
            snap = s.computer.wait(s.computer.latest_job, profile=False)
            if snap is None or snap.design is None:
                return _bad("export: no finished design to export" + (f" ({snap.error})" if snap and snap.error
                                                                       else ""))
            out = s.workspace.export(snap.design)
            files = sorted(p.name for p in out.iterdir())
            rel = out.relative_to(s.workspace.root).as_posix()
            return html_text(f"exported {rel}/ ({len(files)} files: {', '.join(files)}) and {rel}.toml")
        except Exception as exc:  # noqa: BLE001
            return _bad(_failure(exc))


def html_text(text: str):
    from dash import html

    return html.Span(text, id="export-done")


# ------------------------------------------------------------------------------------------ the app

class WorkbenchApp(dash.Dash):
    """The Dash app with its tabs' sessions (``profilegen_sessions``, closed when the server stops)."""

    profilegen_sessions: Sessions


def make_app(gearset: GearSet | None = None, *, workspace: str | Path = ".", scene: str | None = None,
             sessions_limit: int = 16) -> WorkbenchApp:
    """The Dash app for ``gearset`` (default: the bundled default set): each page load is a new
    session (its own undo history and computation), files only inside ``workspace``."""
    ws = Workspace(workspace)
    gs = gearset if gearset is not None else load_gearset("default")
    start_scene = scene or gs.scene
    if start_scene not in SCENES:
        raise ProfilegenError(f"scene = {start_scene!r}: the app takes one of {', '.join(SCENES)}")
    sessions = Sessions(lambda: Session(gs, start_scene, ws, on_profile=prebuild_figures), limit=sessions_limit)
    # update_title "": Dash's "None or ''" (the page's title stays while a callback runs)
    app = WorkbenchApp(__name__, title="profilegen", update_title="", serve_locally=True,
                       suppress_callback_exceptions=True, assets_ignore=".*")
    app.index_string = _INDEX
    app.layout = lambda: _page(sessions.new())
    _register(app, sessions)
    app.profilegen_sessions = sessions
    return app


class Running:
    """A server started by :func:`start`: ``url``, and :meth:`stop`."""

    def __init__(self, server, thread, app):
        self.server, self.thread, self.app = server, thread, app
        host, port = server.server_address[:2]
        self.url = f"http://{host}:{port}/"

    def stop(self) -> None:
        self.server.shutdown()
        self.server.server_close()
        self.app.profilegen_sessions.close()


def _server(app, host: str, port: int):
    from werkzeug.serving import make_server

    logging.getLogger("werkzeug").setLevel(logging.WARNING)
    try:
        return make_server(host, port, app.server, threaded=True)
    except OSError as exc:
        raise ProfilegenError(f"cannot listen on {host}:{port}: {exc.strerror or exc}") from None


def start(gearset: GearSet | None = None, *, workspace: str | Path = ".", scene: str | None = None,
          host: str = "127.0.0.1", port: int = 0) -> Running:
    """The app served on a background thread (``port=0``: a free port); for tests and scripts."""
    app = make_app(gearset, workspace=workspace, scene=scene)
    srv = _server(app, host, port)
    thread = threading.Thread(target=srv.serve_forever, name="profilegen-app-server", daemon=True)
    thread.start()
    return Running(srv, thread, app)


def serve(gearset: GearSet | None = None, *, workspace: str | Path = ".", scene: str | None = None,
          host: str = "127.0.0.1", port: int = 8050) -> int:
    """Serve the app until Ctrl-C (``profilegen app``): prints its URL; returns 0 when stopped."""
    app = make_app(gearset, workspace=workspace, scene=scene)
    srv = _server(app, host, port)
    h, p = srv.server_address[:2]
    print(f"profilegen app: http://{h}:{p}/  (workspace {Path(workspace).resolve()}; Ctrl-C stops it)", flush=True)
    if host not in ("127.0.0.1", "localhost", "::1"):
        print(f"profilegen app: listening on {host}: reachable from other machines", file=sys.stderr, flush=True)
    try:
        srv.serve_forever()  # werkzeug's returns on Ctrl-C (it catches the KeyboardInterrupt itself)
    except KeyboardInterrupt:
        pass
    finally:
        srv.server_close()
        app.profilegen_sessions.close()
    print("\nprofilegen app: stopped", file=sys.stderr, flush=True)
    return 0

