"""The CS tooth space as a zoomable figure (plotly), down to sub-µm detail, offline.

``flank_figure(design)`` is the figure as a plotly figure dict: the exact flank (the swept
boundary of the FS tooth), the fitted arc–line–arc space that goes to CAD, the other fits of
the right flank (hidden, one click in the legend), the arc centres, and the FS tooth at the
pose of the smallest clearance with a light family of poses around the engagement.
``figure_html(design)`` is it as an HTML ``<div>`` with plotly.js embedded (no network: the
script comes from the installed ``plotly`` package), for ``report.html``; ``notebook_html(design)``
is the design sheet with it, for ``Design._repr_html_``.

Why SVG ``scatter`` and not ``scattergl``: WebGL draws in float32, whose spacing at 50 mm is
~4 nm, and its vertex maths loses more — a 1 µm window at y ≈ 50 mm shows steps. SVG paths are
placed from float64 data. Coordinates are written rounded to 1e-9 mm (0.001 nm), which keeps
sub-nm detail and the file small.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["flank_figure", "figure_html", "notebook_html", "FIGURE_DIV_ID"]

#: The id of the figure's ``<div>`` in report.html (the browser test looks it up).
FIGURE_DIV_ID = "cs-space"
_DIGITS = 9  # mm: 0.001 nm
_FAMILY_POSES = 25


def _xy(points) -> tuple[list, list]:
    p = np.round(np.asarray(points, dtype=float), _DIGITS)
    return p[:, 0].tolist(), p[:, 1].tolist()


def _joined(parts) -> np.ndarray:
    """Polylines joined into one (n, 2) array, NaN rows between them (a gap in the line)."""
    gap = np.full((1, 2), np.nan)
    out = []
    for p in parts:
        out += [np.asarray(p, dtype=float), gap]
    return np.vstack(out[:-1]) if out else np.empty((0, 2))


def _line(name: str, points, *, color: str, width: float, dash: str = "solid", visible=True,
          hover: bool = True, legendrank: int = 1000) -> dict:
    x, y = _xy(points)
    trace = {"type": "scatter", "mode": "lines", "name": name, "x": x, "y": y, "visible": visible,
             "line": {"color": color, "width": width, "dash": dash}, "legendrank": legendrank}
    if hover:
        trace["hovertemplate"] = "x %{x:.7f} mm<br>y %{y:.7f} mm<extra>" + name + "</extra>"
    else:
        trace["hoverinfo"] = "skip"
    return trace


def flank_figure(design, *, height_px: int = 600) -> dict:
    """The CS tooth space of ``design`` as a plotly figure dict (``{"data": [...], "layout": {...}}``),
    in the CS frame (mm, equal axes; origin on the gear axis, y through the middle of the space)."""
    from .plot import family_outlines
    from .sheet import flank_elements, format_clearance

    env, prof = design.envelope, design.profile
    data = []
    boundary = np.asarray(env.flank["boundary"], dtype=float)
    lo, hi = boundary.min(0), boundary.max(0)
    if design.tooth is not None and design.motion is not None:
        a, b = env.phi_range
        family = family_outlines(design.tooth, design.motion, np.linspace(a, b, _FAMILY_POSES))
        data.append(_line("FS tooth, poses through the mesh", _joined(family), color="#c8c8c8", width=0.8,
                          hover=False, legendrank=900))
    data.append(_line("exact flank (swept boundary)", boundary, color="#7a7a7a", width=5, legendrank=10))
    if prof is not None:
        space = np.vstack([e.sample(1e-8) for e in prof.space.elements])
        lo, hi = np.minimum(lo, space.min(0)), np.maximum(hi, space.max(0))
        data.append(_line(f"CS space to cut ({prof.method} arc–line–arc)", space, color="#1f5fbf", width=1.6,
                          legendrank=20))
        for name, fit in prof.fits.items():
            if name != prof.method:
                data.append(_line(f"{name} fit (right flank)", fit.chain.sample(1e-8), color="#d67b00", width=1.2,
                                  dash="dash", visible="legendonly", legendrank=200))
        centres, labels = [], []
        for fit in (f for f in prof.cad_fits if f is not None):
            for el in flank_elements(fit):
                if el.kind == "arc":
                    centres.append(el.centre_mm)
                    labels.append(f"{el.label} = {el.radius_mm:.4f} mm, {el.shape}")
        if centres:
            x, y = _xy(centres)
            data.append({"type": "scatter", "mode": "markers+text", "name": "arc centres (right flank)",
                         "x": x, "y": y, "text": [t.split(" =")[0] for t in labels], "textposition": "top center",
                         "customdata": labels, "marker": {"symbol": "cross-thin", "size": 10,
                                                           "line": {"width": 2, "color": "#1f5fbf"}},
                         "hovertemplate": "%{customdata}<br>centre (%{x:.4f}, %{y:.4f}) mm<extra></extra>",
                         "legendrank": 30})
            pts = np.asarray(centres)
            lo, hi = np.minimum(lo, pts.min(0)), np.maximum(hi, pts.max(0))
        if design.tooth is not None and design.motion is not None:
            phi = float(prof.clearance.at_phi)
            fs = family_outlines(design.tooth, design.motion, np.array([phi]), n_per_mm=4000.0)[0]
            data.append(_line(f"FS tooth at φ = {math.degrees(phi):.2f}° (smallest clearance, "
                              f"{format_clearance(prof.clearance.min_mm)})", fs, color="#2ca02c", width=1.4,
                              legendrank=40))
    pad = 0.06 * float(np.max(hi - lo))
    layout = {
        "template": {},  # no default template to load: the styling is all here
        "height": height_px,
        "margin": {"l": 84, "r": 8, "t": 30, "b": 36},
        "title": {"text": "CS tooth space (zoomable)", "font": {"size": 13}, "x": 0.01, "xanchor": "left",
                  "y": 0.985},
        "font": {"family": "system-ui, sans-serif", "size": 11},
        "paper_bgcolor": "white", "plot_bgcolor": "white",
        "xaxis": {"title": {"text": "x (mm)", "standoff": 4}, "range": [lo[0] - pad, hi[0] + pad],
                  "showgrid": True, "gridcolor": "#eee", "zeroline": False, "showline": True, "linecolor": "#444",
                  "ticks": "outside", "exponentformat": "none", "hoverformat": ".7f"},
        "yaxis": {"title": {"text": "y (mm)", "standoff": 6}, "range": [lo[1] - pad, hi[1] + pad],
                  "scaleanchor": "x", "scaleratio": 1, "showgrid": True, "gridcolor": "#eee", "zeroline": False,
                  "showline": True, "linecolor": "#444", "ticks": "outside", "exponentformat": "none",
                  "hoverformat": ".7f"},
        "legend": {"orientation": "h", "x": 0, "y": -0.1, "yanchor": "top", "font": {"size": 11}},
        "hovermode": "closest",
        "dragmode": "zoom",
    }
    return {"data": data, "layout": layout}


def figure_html(design, *, include_plotlyjs: bool = True, height_px: int = 600, div_id: str = FIGURE_DIV_ID) -> str:
    """:func:`flank_figure` as an HTML ``<div id="cs-space">`` with its script; plotly.js is
    embedded (``include_plotlyjs``; ~4.7 MB, works offline) — pass False where the page already
    holds it. ``div_id``: unique on the page (a notebook shows many)."""
    import plotly.io as pio

    fig = flank_figure(design, height_px=height_px)
    config = {"scrollZoom": True, "displaylogo": False, "responsive": True,
              "modeBarButtonsToRemove": ["select2d", "lasso2d"],
              "toImageButtonOptions": {"format": "svg", "filename": f"{design.gearset.name}_cs_space"}}
    hint = ('<p style="margin:0 0 0 8px;font-size:12px;color:#555">Drag a box to zoom (down to below 1 µm), '
            'scroll to zoom, double-click to reset; hover for coordinates; click a legend entry to show or hide it.</p>')
    return hint + pio.to_html(fig, config=config, include_plotlyjs=include_plotlyjs, full_html=False,
                              validate=False, div_id=div_id, default_width="100%",
                              default_height=f"{height_px}px")


def notebook_html(design, *, interference_tol_mm: float) -> str:
    """The sheet with its zoomable figure, for ``Design._repr_html_`` (Jupyter): plotly.js
    embedded (offline), the figure under a fresh id so several designs can share a notebook."""
    import uuid

    from .sheet import sheet_html

    return sheet_html(design, figure_html(design, div_id=f"cs-space-{uuid.uuid4().hex[:12]}"),
                      interference_tol_mm=interference_tol_mm)
