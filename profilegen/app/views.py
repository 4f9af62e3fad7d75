"""What the workbench draws from a design: the CS tooth space with the FS tooth poses (zoomable,
the pinned design over it), the fit's error along the flank and the clearance through the mesh,
the verdict, and the design sheet's numbers with what changed since the last design.

Plain data (plotly figure dicts, rows of numbers): the server module turns them into the page.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Row", "SCREEN_CHORD_MM", "View", "changes", "error_figure", "heavy_traces", "initial_view", "lighter",
           "numbers", "space_figure", "space_name", "verdict_parts", "view_after"]

PINNED_COLOR = "#d62728"
#: the chord tolerance the workbench samples the fitted arcs at (mm): 0.2 nm, a tenth of a pixel of
#: the 520-px figure zoomed to a 1 µm window (report.html's figure samples them at 1e-8 mm: 5× the
#: points of the CS space, most of the payload after the FS poses)
SCREEN_CHORD_MM = 2e-7
#: how report.html's figure (profilegen.output.interactive.flank_figure) names the fitted CS space
_SPACE = "CS space to cut"
_FIT = " fit (right flank)"


def space_name(design) -> str:
    """The fitted CS space's legend entry: "CS space to cut" once a face stage has chosen the
    design section (the design and verify scenes; as the design sheet's "To cut"), else it says
    that this profile is not the part to cut (the sketch scene decides no section)."""
    return _SPACE if getattr(design, "face", None) is not None else "CS space (sketch: not the part to cut)"


def _xy(points) -> tuple[list, list]:
    p = np.round(np.asarray(points, dtype=float), 9)
    return p[:, 0].tolist(), p[:, 1].tolist()


def space_figure(design, *, pinned=None, job: int | None = None, height_px: int = 520) -> dict:
    """The CS tooth space (:func:`profilegen.output.interactive.flank_figure`: the exact flank, the
    fitted space, the arc centres, the FS tooth poses through the mesh), with the pinned design's
    flank and space dashed over it. The zoom is kept across redesigns (``uirevision``)."""
    from ..output.interactive import flank_figure

    fig = flank_figure(design, height_px=height_px)
    prof, name = design.profile, space_name(design)
    for trace in fig["data"] if prof is not None else ():
        label = trace.get("name", "")
        if label.startswith(_SPACE):  # the fitted space at the screen's chord, under the scene's name
            trace["x"], trace["y"] = _xy(_sampled(prof.space.elements))
            trace["name"] = name + label[len(_SPACE):]
            trace["hovertemplate"] = trace.get("hovertemplate", "").replace(label, trace["name"])
        elif label.endswith(_FIT) and prof.fits.get(label[:-len(_FIT)]) is not None:  # the other fits (hidden)
            trace["x"], trace["y"] = _xy(_sampled(prof.fits[label[:-len(_FIT)]].chain.elements))
    if pinned is not None and pinned.profile is not None:
        space = _sampled(pinned.profile.space.elements)
        x, y = _xy(space)
        fig["data"].append({"type": "scatter", "mode": "lines", "name": "A (pinned): CS space", "x": x, "y": y,
                            "line": {"color": PINNED_COLOR, "width": 1.4, "dash": "dash"}, "legendrank": 25,
                            "hovertemplate": "A: x %{x:.7f} mm<br>y %{y:.7f} mm<extra></extra>"})
        x, y = _xy(pinned.envelope.flank["boundary"])
        fig["data"].append({"type": "scatter", "mode": "lines", "name": "A (pinned): exact flank", "x": x, "y": y,
                            "line": {"color": PINNED_COLOR, "width": 3, "dash": "dot"}, "opacity": 0.5,
                            "legendrank": 26, "hoverinfo": "skip"})
    layout = fig["layout"]
    layout["uirevision"] = "space"
    layout["meta"] = {"job": job, "gearset": design.gearset.name}
    layout["title"]["text"] = "CS tooth space, FS tooth poses (drag: zoom)"
    return fig


# ------------------------------------------------------------------ the CS space's points, per view
#: the widest plot (px) the space figure is taken to have: its real width (the page's, responsive) is
#: at most this, so a data unit per pixel from it is at most the real one (its height is given)
MAX_PLOT_WIDTH_PX = 2000
#: the largest distance (px) a dropped point may lie from the line drawn without it
DROP_TOLERANCE_PX = 0.25
#: lines of fewer points are sent whole
_FEW = 200
#: the most points of a line simplified as one piece (:func:`_simplified`)
_PIECE = 64


@dataclass(frozen=True)
class View:
    """What the space figure shows: the axes' ranges (mm). ``window`` (x0, x1, y0, y1): the part
    of the plane whose points are sent (the ranges widened for the equal axes, which may show more
    than was asked for), and ``tol_mm``: the distance a dropped point may lie from the drawn line
    (a quarter of a pixel at the widest plot)."""

    x_range: tuple[float, float]
    y_range: tuple[float, float]
    height_px: int = 520

    @property
    def tol_mm(self) -> float:
        (x0, x1), (y0, y1) = self.x_range, self.y_range
        return DROP_TOLERANCE_PX * max(abs(x1 - x0) / MAX_PLOT_WIDTH_PX, abs(y1 - y0) / self.height_px)

    @property
    def window(self) -> tuple[float, float, float, float]:
        (x0, x1), (y0, y1) = self.x_range, self.y_range
        span = max(abs(x1 - x0), abs(y1 - y0))
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        # equal axes: the plot may show up to its aspect ratio more along x, and a little more along y
        return (cx - 2.0 * span, cx + 2.0 * span, cy - span, cy + span)


def initial_view(fig: dict) -> View:
    """The view a figure of :func:`space_figure` opens with (its axes' ranges)."""
    layout = fig["layout"]
    (x0, x1), (y0, y1) = layout["xaxis"]["range"], layout["yaxis"]["range"]
    return View((float(x0), float(x1)), (float(y0), float(y1)), int(layout.get("height", 520)))


def view_after(relayout: dict | None, view: View, initial: View) -> View | None:
    """The view after a plotly ``relayoutData`` event (a zoom, a pan, a reset), from ``view``:
    None when the event does not move the axes (a resize, a legend click)."""
    if not relayout:
        return None
    if relayout.get("xaxis.autorange") or relayout.get("yaxis.autorange"):
        return initial
    ranges = []
    for axis, now in (("xaxis", view.x_range), ("yaxis", view.y_range)):
        pair = relayout.get(f"{axis}.range")
        if pair is None and f"{axis}.range[0]" in relayout and f"{axis}.range[1]" in relayout:
            pair = (relayout[f"{axis}.range[0]"], relayout[f"{axis}.range[1]"])
        try:
            ranges.append(now if pair is None else (float(pair[0]), float(pair[1])))
        except (TypeError, ValueError, IndexError):
            ranges.append(now)
    if ranges[0] == view.x_range and ranges[1] == view.y_range:
        return None
    return View(ranges[0], ranges[1], view.height_px)


def _simplified(x: np.ndarray, y: np.ndarray, starts: np.ndarray, ends: np.ndarray, tol: float) -> np.ndarray:
    """Which points Douglas–Peucker keeps of the polylines x[a:b], y[a:b] (a, b of ``starts``,
    ``ends``; no gaps inside): every dropped point lies within ``tol`` of the line through the kept
    ones (the ends are kept). All the lines' segments are split a level at a time, in numpy: each
    at its point farthest from its chord (the first of equals) while that is more than ``tol`` off."""
    keep = np.zeros(x.size, bool)
    # the lines cut into pieces of _PIECE points (their ends kept): fewer levels of splitting, a few
    # more points sent
    count = -(-(ends - 1 - starts) // _PIECE)
    lo = np.repeat(starts, count) + _PIECE * (np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count))
    hi = np.minimum(lo + _PIECE, np.repeat(ends - 1, count))
    keep[lo] = keep[hi] = True
    while True:
        wide = hi - lo >= 2
        lo, hi = lo[wide], hi[wide]
        if lo.size == 0:
            return keep
        inner = hi - lo - 1
        first = np.cumsum(inner) - inner
        owner = np.repeat(np.arange(lo.size), inner)
        idx = lo[owner] + 1 + np.arange(int(inner.sum())) - first[owner]
        dx, dy = (x[hi] - x[lo])[owner], (y[hi] - y[lo])[owner]
        px, py = x[idx] - x[lo][owner], y[idx] - y[lo][owner]
        norm = np.hypot(dx, dy)
        with np.errstate(invalid="ignore", divide="ignore"):
            d = np.where(norm > 0.0, np.abs(px * dy - py * dx) / norm, np.hypot(px, py))
        far = np.maximum.reduceat(d, first)
        hit = np.flatnonzero(d == far[owner])
        at = idx[hit[np.unique(owner[hit], return_index=True)[1]]]  # each segment's first farthest point
        split = far > tol
        at = at[split]
        keep[at] = True
        lo, hi = np.concatenate([lo[split], at]), np.concatenate([at, hi[split]])


def _thinned(xs, ys, view: View) -> tuple[list, list]:
    """A polyline's points (None or NaN: gaps) for ``view``: the pieces that cross its window,
    each simplified to its tolerance, a gap between pieces."""
    x = np.array([math.nan if v is None else v for v in xs], dtype=float)
    y = np.array([math.nan if v is None else v for v in ys], dtype=float)
    ok = np.isfinite(x) & np.isfinite(y)
    x0, x1, y0, y1 = view.window
    # the segments whose box meets the window: both their ends are sent (a line through the window
    # with no point inside it is drawn too)
    seg = ok[:-1] & ok[1:]
    seg &= (np.minimum(x[:-1], x[1:]) <= x1) & (np.maximum(x[:-1], x[1:]) >= x0)
    seg &= (np.minimum(y[:-1], y[1:]) <= y1) & (np.maximum(y[:-1], y[1:]) >= y0)
    sent = np.zeros(x.size, bool)
    sent[:-1] |= seg
    sent[1:] |= seg
    sent |= ok & (x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)  # lone points inside
    edges = np.diff(np.concatenate([[0], sent.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    if starts.size == 0:
        return [], []
    k = np.flatnonzero(_simplified(x, y, starts, ends, view.tol_mm))
    piece = np.searchsorted(starts, k, side="right")  # each kept point's piece: a gap (None) between pieces
    gap = np.flatnonzero(np.diff(piece)) + 1
    out_x, out_y = np.insert(x[k], gap, np.nan).tolist(), np.insert(y[k], gap, np.nan).tolist()
    return [None if v != v else v for v in out_x], [None if v != v else v for v in out_y]


def heavy_traces(fig: dict) -> list[int]:
    """The indices of the figure's lines with many points (those :func:`lighter` thins)."""
    return [i for i, t in enumerate(fig["data"])
            if t.get("mode") == "lines" and len(t.get("x") or ()) >= _FEW]


def lighter(fig: dict, view: View | None = None) -> dict:
    """``fig`` (of :func:`space_figure`, not changed) with the points of its long lines that draw
    the same at ``view`` (default: the view it opens with) left out: only the parts of each line
    that cross the view's window, and of those only the points that lie more than a quarter of a
    pixel from the line through their neighbours kept (Douglas–Peucker). Zoomed in, the page asks
    again for the new view (the server keeps the whole figure), so the points under a sub-µm zoom
    are those of the whole figure there. The default set's sketch: 39 000 points (1.0 MB) to ~1 800 (48 kB).

    The axes open at ``view``: a page zoomed before a redesign keeps its zoom with the new
    profile's points for it (the new figure's own opening ranges would otherwise override the
    zoom — plotly keeps a user's zoom only while the figure's ranges stay — and show lines thinned
    to a window the page no longer shows)."""
    start = initial_view(fig)
    view = start if view is None else view
    out = {**fig, "data": list(fig["data"])}
    for i in heavy_traces(fig):
        t = fig["data"][i]
        x, y = _thinned(t["x"], t["y"], view)
        out["data"][i] = {**t, "x": x, "y": y}
    if view != start:
        layout = fig["layout"]
        out["layout"] = {**layout, "xaxis": {**layout["xaxis"], "range": list(view.x_range)},
                         "yaxis": {**layout["yaxis"], "range": list(view.y_range)}}
    return out


def _sampled(elements) -> np.ndarray:
    return np.vstack([e.sample(SCREEN_CHORD_MM) for e in elements])


def _fit_traces(design, *, name: str, color: str, dash: str = "solid") -> list[dict]:
    prof = design.profile
    out = []
    for i, fit in enumerate(f for f in prof.cad_fits if f is not None):
        out.append({"type": "scatter", "mode": "lines", "name": name if i == 0 else f"{name} ({i + 1})",
                    "x": np.round(np.asarray(fit.arclength_mm, float), 7).tolist(),
                    "y": np.round(np.asarray(fit.error_mm, float) * 1e3, 6).tolist(),
                    "line": {"color": color, "width": 1.5, "dash": dash}, "xaxis": "x", "yaxis": "y",
                    "hovertemplate": "s %{x:.4f} mm<br>%{y:.4f} µm<extra>" + name + "</extra>"})
    cl = prof.clearance
    out.append({"type": "scatter", "mode": "lines", "name": f"{name}: clearance", "showlegend": False,
                "x": np.round(np.degrees(np.asarray(cl.phi, float)), 5).tolist(),
                "y": np.round(np.asarray(cl.clearance_mm, float) * 1e3, 6).tolist(),
                "line": {"color": color, "width": 1.5, "dash": dash}, "xaxis": "x2", "yaxis": "y2",
                "hovertemplate": "φ %{x:.3f}°<br>%{y:.4f} µm<extra>" + name + "</extra>"})
    return out


def error_figure(design, *, pinned=None, height_px: int = 260) -> dict:
    """Left: the fitted CS flank's signed error along the flank (µm; + on the space side: backlash
    for the one-sided fit). Right: the smallest clearance between the fitted CS and the FS tooth
    at each pose through the mesh (µm against φ; below 0 it cuts in)."""
    data = _fit_traces(design, name="B" if pinned is not None else "fit", color="#1f5fbf")
    if pinned is not None and pinned.profile is not None:
        data += _fit_traces(pinned, name="A (pinned)", color=PINNED_COLOR, dash="dash")
    axis = {"showgrid": True, "gridcolor": "#eee", "zeroline": True, "zerolinecolor": "#999", "showline": True,
            "linecolor": "#444", "ticks": "outside", "exponentformat": "none"}
    layout = {
        "template": {}, "height": height_px, "margin": {"l": 60, "r": 10, "t": 28, "b": 40},
        "font": {"family": "system-ui, sans-serif", "size": 11}, "paper_bgcolor": "white", "plot_bgcolor": "white",
        "xaxis": {**axis, "domain": [0, 0.46], "title": {"text": "along the flank s (mm)", "standoff": 2}},
        "yaxis": {**axis, "title": {"text": "fit error (µm)", "standoff": 2}},
        "xaxis2": {**axis, "domain": [0.56, 1], "anchor": "y2", "title": {"text": "φ (deg)", "standoff": 2}},
        "yaxis2": {**axis, "anchor": "x2", "title": {"text": "clearance (µm)", "standoff": 2}},
        "annotations": [
            {"text": "fitted flank − exact flank", "xref": "paper", "yref": "paper", "x": 0, "y": 1.1,
             "showarrow": False, "xanchor": "left", "font": {"size": 12}},
            {"text": "smallest clearance through the mesh", "xref": "paper", "yref": "paper", "x": 0.56, "y": 1.1,
             "showarrow": False, "xanchor": "left", "font": {"size": 12}}],
        "legend": {"orientation": "h", "x": 0, "y": -0.25, "font": {"size": 10}},
        "uirevision": "error", "hovermode": "closest",
    }
    return {"data": data, "layout": layout}


@dataclass(frozen=True)
class Row:
    """One number of the sheet: ``key`` (stable), its label, value, unit and the text shown."""

    key: str
    group: str
    label: str
    value: float | None
    unit: str
    text: str


def _row(rows, group, key, label, value, unit, digits=4):
    if value is None:
        return
    v = float(value)
    text = f"{v:.{digits}g}" if math.isfinite(v) else str(v)
    rows.append(Row(key, group, label, v, unit, text))


def numbers(design) -> list[Row]:
    """The design sheet's numbers, as far as the design got (the slower stages add theirs)."""
    rows: list[Row] = []
    g, form, prof = design.gearset, design.form, design.profile
    _row(rows, "geometry", "ratio", "ratio z1/(z2−z1)", g.ratio, "")
    _row(rows, "geometry", "w0", "radial deflection w0", g.deflection_mm * 1e3, "µm")
    if form is not None:
        _row(rows, "geometry", "tip_d", "CS tip diameter", 2 * form.tip_radius_mm, "mm", 7)
        _row(rows, "geometry", "root_d", "CS root diameter", 2 * form.root_radius_mm, "mm", 7)
    if prof is not None:
        _row(rows, "fit", "fit_err", "fit error, max", prof.max_error_mm * 1e3, "µm")
        _row(rows, "fit", "clearance", "smallest clearance", prof.clearance.min_mm * 1e3, "µm")
        _row(rows, "fit", "backlash", "backlash, max", None if prof.max_backlash_mm is None
             else prof.max_backlash_mm * 1e3, "µm")
    c = design.contact
    if c is not None:
        for tq, case in zip(c.torques_nm, c.cases):
            teeth = np.max(np.atleast_1d(np.asarray(case.teeth_in_contact, dtype=float)))
            _row(rows, "contact", f"teeth_{tq:g}", f"teeth in contact at {tq:g} N·m", teeth, "per zone")
            _row(rows, "contact", f"force_{tq:g}", f"max tooth force at {tq:g} N·m", case.max_tooth_force_n, "N")
    t = design.torsional
    if t is not None:
        h = t.headline()
        for k in ("k1_nm_per_rad", "k2_nm_per_rad", "k3_nm_per_rad"):
            if h.get(k) is not None:
                _row(rows, "torsion", k, k.split("_")[0].upper() + " stiffness", h[k] / 1e3, "kN·m/rad")
        _row(rows, "torsion", "lost_motion", "lost motion", h.get("lost_motion_arcmin"), "arcmin")
    s = design.stress
    if s is not None:
        for name, value in s.headline().get("safety", {}).items():
            _row(rows, "stress", f"safety_{name}", f"safety, {name}", value, "", 3)
    r = design.ratcheting
    if r is not None and getattr(r, "torque_nm", None) is not None:
        _row(rows, "torsion", "ratcheting", "ratcheting torque (estimate)", r.torque_nm, "N·m")
    return rows


def changes(now: list[Row], before: list[Row] | None) -> dict[str, str]:
    """key -> the earlier value's text, for the numbers that changed since ``before`` (a number
    that is new, or gone, is not a change)."""
    if before is None:
        return {}
    old = {r.key: r for r in before}
    out = {}
    for r in now:
        o = old.get(r.key)
        if o is not None and r.value is not None and o.value is not None:
            if not math.isclose(r.value, o.value, rel_tol=1e-9, abs_tol=1e-12):
                out[r.key] = o.text
    return out


def verdict_parts(design) -> tuple[str, str, list[tuple[str, str, str]]]:
    """(status, the verdict's line, [(status, check name at where, text), ...])."""
    v = design.verdict
    checks = [(c.status, f"{c.name} at {c.where}" if c.where else c.name, c.text) for c in v.checks]
    return v.status, v.line, checks
