"""Figures: the classified envelope of a CS tooth space, and clearance curves.

matplotlib is imported inside the functions only (``import profilegen`` stays
light), and only its object-oriented API is used — :class:`matplotlib.figure.Figure`
with an Agg canvas, never pyplot — so nothing here touches a display or the
global backend. Every function takes an optional ``ax`` and returns the ``Axes``;
:func:`envelope_figure` builds a two-panel figure fit for a paper and can save it.

Colours: conjugate flank blue (thick), tip-corner path green (thick), interfering
(false) flank red (thin), the flexspline tooth family light grey, ridges black
dots with their kink angle, folds magenta triangles.
"""

from __future__ import annotations

import io
import math
import os
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import StressError

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..stress.diaphragm import DiaphragmStress
    from ..stress.tooth_ring import ToothRingStudy

__all__ = ["CLASS_STYLE", "PAPER_RC", "envelope", "envelope_figure", "envelope_png", "clearance", "tooth_line",
           "family_outlines", "contact_figure", "torsional_figure", "stress_figure", "fixed_figure", "png_bytes",
           "plot_goodman", "plot_tooth_ring_study", "sweep_figure"]

#: Line style per envelope class, in legend order.
CLASS_STYLE: dict[str, dict[str, Any]] = {
    "conjugate": {"color": "#1f5fbf", "linewidth": 2.2, "zorder": 4},
    "tip_path": {"color": "#2ca02c", "linewidth": 2.2, "zorder": 4},
    "interfering": {"color": "#d62728", "linewidth": 0.7, "zorder": 3},
}
_OTHER_STYLE: dict[str, Any] = {"color": "0.3", "linewidth": 1.0, "zorder": 3}
_FAMILY_COLOR = "0.80"
_RIDGE_STYLE: dict[str, Any] = {"marker": "o", "color": "k", "markersize": 4.5, "linestyle": "none", "zorder": 6}
_FOLD_STYLE: dict[str, Any] = {"marker": "^", "color": "#c000c0", "markersize": 5.5, "linestyle": "none", "zorder": 6}

#: Font sizes and line widths for paper figures (used by the functions that create a figure).
PAPER_RC: dict[str, Any] = {
    "font.size": 9,
    "axes.titlesize": 9,
    "axes.labelsize": 9,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "legend.fontsize": 8,
    "figure.titlesize": 10,
    "axes.linewidth": 0.7,
    "xtick.major.width": 0.7,
    "ytick.major.width": 0.7,
    "legend.frameon": True,
    "legend.framealpha": 0.9,
    "legend.edgecolor": "0.8",
}


def fixed_figure(figsize: tuple[float, float], nrows: int = 1, ncols: int = 1, *, left: float = 0.7,
                 right: float = 0.15, bottom: float = 0.55, top: float = 0.3, wgap: float = 0.0,
                 hgap: float = 0.0, fixed_titles: bool = False, **subplot_kw: Any) -> tuple["Figure", Any]:
    """A Figure on an Agg canvas with its panels at fixed places: margins and the gaps between
    panels in inches. No layout engine, so saving draws the figure once (a constrained layout
    draws it twice and measures every text in between: half the cost of a report figure).
    ``fixed_titles``: the panels' titles sit just above the panel instead of being lifted over
    whatever overlaps them (which measures the y axis once more per panel) — for panels without
    an offset text or ticks on top. Returns (figure, axes) as ``Figure.subplots`` gives them."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    FigureCanvasAgg(fig)
    width, height = figsize
    panel_w = (width - left - right - (ncols - 1) * wgap) / ncols
    panel_h = (height - bottom - top - (nrows - 1) * hgap) / nrows
    with matplotlib.rc_context({"axes.titley": 1.0} if fixed_titles else {}):
        axes = fig.subplots(nrows, ncols, gridspec_kw={
            "left": left / width, "right": 1 - right / width, "bottom": bottom / height, "top": 1 - top / height,
            "wspace": wgap / panel_w, "hspace": hgap / panel_h}, **subplot_kw)
    return fig, axes


def png_bytes(fig: "Figure", dpi: float) -> bytes:
    """The figure as PNG bytes at ``dpi``."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, pil_kwargs={"compress_level": 3})  # 6 (PIL's default): 1.6x the time, 3 % smaller
    return buf.getvalue()


def _save(data: bytes, path: str | os.PathLike) -> None:
    from .export import atomic_write

    with atomic_write(path, "wb") as f:
        f.write(data)


def _new_axes(figsize: tuple[float, float]) -> "Axes":
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    FigureCanvasAgg(fig)
    return fig.add_subplot()


def _check_zoom(zoom: Any) -> tuple[float, float, float, float] | None:
    if zoom is None:
        return None
    try:
        z = tuple(float(v) for v in zoom)
    except (TypeError, ValueError):
        raise ValueError(f"zoom must be (xmin, xmax, ymin, ymax) in mm, got {zoom!r}") from None
    if len(z) != 4 or not all(map(math.isfinite, z)) or not (z[0] < z[1] and z[2] < z[3]):
        raise ValueError(f"zoom must be finite (xmin, xmax, ymin, ymax) in mm with xmin < xmax, ymin < ymax, got {zoom!r}")
    return z


def _tidy(ax: "Axes") -> None:
    from matplotlib.ticker import MaxNLocator

    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(MaxNLocator(nbins=5, steps=[1, 2, 2.5, 5, 10]))
    ax.ticklabel_format(useOffset=False, style="plain")
    ax.tick_params(direction="out", length=3)


def tooth_line(tooth: Any, *, n_per_mm: float = 400.0) -> np.ndarray:
    """The visible edge of a tooth (``ToothProfile.surface``): root land, flanks, top land."""
    if hasattr(tooth, "surface"):
        return tooth.surface(n_per_mm=n_per_mm)
    outline = np.asarray(tooth.outline(n_per_mm=n_per_mm), dtype=float)
    return np.vstack([outline, outline[:1]])


def family_outlines(tooth: Any, motion: Any, phi: np.ndarray, *, n_per_mm: float = 400.0) -> list[np.ndarray]:
    """:func:`tooth_line` placed in the CS frame at each φ (rad) — one (m, 2) array each."""
    line = tooth_line(tooth, n_per_mm=n_per_mm)
    return [motion.pose(np.array([p])).to_cs(line) for p in np.asarray(phi, dtype=float)]


def _classes(env: Any) -> list[str]:
    """Classes present in ``env.pieces``, known ones in :data:`CLASS_STYLE` order first."""
    present = {p.cls for p in env.pieces}
    return [c for c in CLASS_STYLE if c in present] + sorted(present - set(CLASS_STYLE))


def envelope(
    env: Any,
    ax: "Axes | None" = None,
    *,
    tooth: Any = None,
    motion: Any = None,
    family: int = 41,
    zoom: tuple[float, float, float, float] | None = None,
    legend: bool = True,
) -> "Axes":
    """Draw a classified :class:`~profilegen.profile.envelope.Envelope` in the CS frame (mm).

    With ``tooth`` and ``motion`` the FS tooth family is drawn in light grey: the
    tooth outline at ``family`` evenly spaced φ over ``env.phi_range``. Pieces
    are drawn by class (see :data:`CLASS_STYLE`), ridges as black dots annotated
    with their kink angle, folds as magenta triangles. ``zoom`` = (xmin, xmax,
    ymin, ymax) in mm sets the view (the aspect ratio stays 1, so one range may
    grow). With ``legend`` the axes' legend lists one entry per class present,
    labelled with the class name; ridges and folds, when present, get a second,
    separate legend.
    """
    zoom = _check_zoom(zoom)
    if (tooth is None) != (motion is None):
        raise ValueError("tooth and motion must be given together (both draw the FS tooth family), got only "
                         + ("tooth" if motion is None else "motion"))
    if isinstance(family, bool) or not isinstance(family, (int, np.integer)) or family < 1:
        raise ValueError(f"family must be an integer number of tooth positions >= 1, got {family!r}")
    from matplotlib import patheffects
    from matplotlib.collections import LineCollection
    from matplotlib.legend import Legend
    from matplotlib.lines import Line2D

    if ax is None:
        ax = _new_axes((5.0, 5.0))
    if tooth is not None:
        phi = np.linspace(env.phi_range[0], env.phi_range[1], int(family)) if family > 1 else np.array([np.mean(env.phi_range)])
        ax.add_collection(LineCollection(family_outlines(tooth, motion, phi), colors=_FAMILY_COLOR,
                                         linewidths=0.45, zorder=1, label="_family"))
    handles = []
    for cls in _classes(env):
        style = CLASS_STYLE.get(cls, _OTHER_STYLE)
        segs = [np.asarray(p.points, dtype=float) for p in env.pieces if p.cls == cls]
        ax.add_collection(LineCollection(segs, colors=style["color"], linewidths=style["linewidth"],
                                         zorder=style["zorder"], capstyle="round", joinstyle="round"))
        handles.append(Line2D([], [], color=style["color"], linewidth=style["linewidth"], label=cls))
    markers = []
    if env.ridges:
        xy = np.array([r.point for r in env.ridges], dtype=float)
        ax.plot(xy[:, 0], xy[:, 1], **_RIDGE_STYLE)
        halo = [patheffects.withStroke(linewidth=2.5, foreground="white")]
        for r in env.ridges:
            out = 1.0 if r.point[0] >= 0 else -1.0  # label on the outer side of the space axis
            ax.annotate(f"{r.kink_deg:.1f}°", r.point, xytext=(5 * out, 4), textcoords="offset points",
                        ha="left" if out > 0 else "right", fontsize="small", zorder=7,
                        annotation_clip=True, path_effects=halo)
        markers.append(Line2D([], [], label="ridge (kink)", **_RIDGE_STYLE))
    if env.folds:
        xy = np.array([f.point for f in env.folds], dtype=float)
        ax.plot(xy[:, 0], xy[:, 1], **_FOLD_STYLE)
        markers.append(Line2D([], [], label="fold", **_FOLD_STYLE))
    if zoom is not None:  # exact limits; the axes box takes the aspect
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlim(zoom[0], zoom[1])
        ax.set_ylim(zoom[2], zoom[3])
    else:
        ax.set_aspect("equal", adjustable="datalim")
        ax.autoscale_view()
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    _tidy(ax)
    if legend and markers:
        ax.add_artist(Legend(ax, markers, [str(m.get_label()) for m in markers], loc="lower left"))
    if legend and handles:
        ax.legend(handles=handles, loc="lower right" if markers else "best")
    return ax


def _frame(points: np.ndarray, margin: float, *, ratio: float, anchor_top: bool = False) -> tuple[float, float, float, float]:
    """Limits around ``points`` with a margin, widened to width/height = ``ratio``.

    The short side grows symmetrically, or, with ``anchor_top``, downward only
    (below a CS space lie the FS tooth and the false flanks; above it, CS material).
    """
    lo, hi = points.min(0), points.max(0)
    pad = margin * max(float(np.max(hi - lo)), 1e-3)
    x0, x1, y0, y1 = lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad
    w, h = x1 - x0, y1 - y0
    if w / h > ratio:
        grow = w / ratio - h
        y0, y1 = (y0 - grow, y1) if anchor_top else (y0 - grow / 2, y1 + grow / 2)
    else:
        grow = h * ratio - w
        x0, x1 = x0 - grow / 2, x1 + grow / 2
    return float(x0), float(x1), float(y0), float(y1)


def envelope_figure(
    env: Any,
    tooth: Any,
    motion: Any,
    *,
    title: str = "",
    path: str | os.PathLike | None = None,
) -> "Figure":
    """Two panels: (a) the whole tooth space, (b) a zoom on the right flank; saved as PNG.

    (a) is framed on the CS space boundary ``env.flank["boundary"]`` with a
    margin, (b) on its x ≥ 0 half ``env.flank["right"]``; the zoom region is
    outlined in (a). ``title`` becomes the suptitle. With ``path`` the figure is
    written as a 150 dpi PNG, atomically (an unwritable path raises
    ``ExportError`` and leaves nothing behind).
    """
    fig, png = _envelope_figure(env, tooth, motion, title=title, png=path is not None)
    if path is not None:
        assert png is not None  # asked for (png=True)
        _save(png, path)
    return fig


def envelope_png(env: Any, tooth: Any, motion: Any, *, title: str = "") -> bytes:
    """:func:`envelope_figure` as PNG bytes (150 dpi)."""
    png = _envelope_figure(env, tooth, motion, title=title, png=True)[1]
    assert png is not None  # asked for (png=True)
    return png


def _envelope_figure(env: Any, tooth: Any, motion: Any, *, title: str, png: bool) -> tuple["Figure", bytes | None]:
    import matplotlib
    from matplotlib.lines import Line2D
    from matplotlib.patches import Rectangle

    flank = getattr(env, "flank", None) or {}
    allpts = np.concatenate([np.asarray(p.points, dtype=float) for p in env.pieces])
    boundary = np.asarray(flank.get("boundary", allpts), dtype=float)
    right = np.asarray(flank.get("right", boundary[boundary[:, 0] >= 0]), dtype=float)
    if len(right) < 2:
        right = boundary
    with matplotlib.rc_context(PAPER_RC):  # type: ignore[arg-type]  # (its stubs: rc keys a Literal of names)
        # two square panels (equal aspect) between a title band and a band for x labels and the legend
        fig, (ax_all, ax_zoom) = fixed_figure((7.2, 4.3), 1, 2, left=0.62, right=0.1, bottom=0.78,
                                              top=0.55 if title else 0.3, wgap=0.62,
                                              fixed_titles=True)  # _tidy: no offset text
        whole = _frame(boundary, 0.12, ratio=1.0, anchor_top=True)
        zoom = _frame(right, 0.06, ratio=1.0)
        envelope(env, ax_all, tooth=tooth, motion=motion, zoom=whole, legend=False)
        envelope(env, ax_zoom, tooth=tooth, motion=motion, zoom=zoom, legend=False)
        ax_all.add_patch(Rectangle((zoom[0], zoom[2]), zoom[1] - zoom[0], zoom[3] - zoom[2], fill=False,
                                   edgecolor="0.35", linewidth=0.7, linestyle=(0, (4, 2)), zorder=8))
        ax_all.set_title("(a) CS tooth space", loc="left")
        ax_zoom.set_title("(b) right flank", loc="left")
        ax_zoom.set_ylabel("")
        handles = [Line2D([], [], color=CLASS_STYLE.get(c, _OTHER_STYLE)["color"],
                          linewidth=CLASS_STYLE.get(c, _OTHER_STYLE)["linewidth"], label=c) for c in _classes(env)]
        if env.ridges:
            handles.append(Line2D([], [], label="ridge (kink)", **_RIDGE_STYLE))
        if env.folds:
            handles.append(Line2D([], [], label="fold", **_FOLD_STYLE))
        fig.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 0.005), ncols=len(handles),
                   frameon=False)
        if title:
            fig.suptitle(title, y=1 - 0.08 / 4.3, va="top")
        data = png_bytes(fig, 150) if png else None  # inside the rc context: tick labels are made as it draws
    return fig, data


def clearance(phi_rad: Any, clearance_mm: Any, ax: "Axes | None" = None) -> "Axes":
    """Clearance (µm) against φ (degrees), with the zero line and the minimum marked."""
    phi = np.asarray(phi_rad, dtype=float)
    c = np.asarray(clearance_mm, dtype=float)
    if phi.ndim != 1 or phi.size < 1:
        raise ValueError(f"phi_rad must be a non-empty 1-D array (rad), got shape {phi.shape}")
    if c.shape != phi.shape:
        raise ValueError(f"clearance_mm must have the shape of phi_rad {phi.shape}, got {c.shape}")
    for name, a in (("phi_rad", phi), ("clearance_mm", c)):
        if not np.isfinite(a).all():
            raise ValueError(f"{name} must be finite, got {a[~np.isfinite(a)][0]} at index {int(np.argmax(~np.isfinite(a)))}")
    if ax is None:
        ax = _new_axes((5.0, 3.0))
    deg, um = np.degrees(phi), c * 1e3
    ax.axhline(0.0, color="0.55", linewidth=0.8, zorder=1)
    ax.plot(deg, um, color=CLASS_STYLE["conjugate"]["color"], linewidth=1.4, zorder=2)
    k = int(np.argmin(um))
    ax.plot(deg[k], um[k], "o", color="k", markersize=4, zorder=3)
    right_half = deg[k] > 0.5 * (deg.min() + deg.max())
    ax.annotate(f"min {um[k]:.2f} µm at φ = {deg[k]:.2f}°".replace("-", "\u2212"), (deg[k], um[k]),
                xytext=(-6 if right_half else 6, -6), textcoords="offset points", fontsize="small",
                ha="right" if right_half else "left", va="top")
    ax.margins(x=0.02, y=0.15)
    ax.set_xlabel("φ (°)")
    ax.set_ylabel("clearance (µm)")
    ax.ticklabel_format(useOffset=False, style="plain")
    return ax


def contact_figure(result: Any, *, title: str = "", path: str | os.PathLike | None = None,
                   catalog: dict | None = None, ratio: float | None = None, size: int | None = None) -> "Figure":
    """Load sharing along the engagement (force per tooth vs φ, one line per torque), the
    torsional curve (torque vs rotation in arcmin, the catalog's bilinear curve for comparison)
    and the ball reactions. ``catalog`` None: the catalogue row of ``size`` (default 40) and
    ``ratio`` (default 50) (:func:`profilegen.contact.catalogue.catalogue_row`); ``ratio``: the
    gear set's, named beside the catalog row's own so the two are not confused."""
    fig, (ax1, ax2, ax3) = fixed_figure((14.0, 4.0), 1, 3, left=0.62, right=0.45, bottom=0.5,
                                        top=0.32 if title else 0.12, wgap=0.78)
    for case in result.cases:
        ax1.plot(np.degrees(case.tooth_phi_rad), case.tooth_force_n, "o-", ms=3, lw=1,
                 label=f"{case.torque_nm:g} N·m: {case.teeth_in_contact} teeth/zone, max {case.max_tooth_force_n:.0f} N")
    ax1.set_xlabel("FS tooth position φ from the major axis (deg)")
    ax1.set_ylabel("normal force per tooth (N)")
    ax1.legend(fontsize=7)
    _tidy(ax1)
    phi0 = float(np.min(result.points.theta_rad))
    rot = (result.rotations_rad - phi0) * 180 * 60 / math.pi
    ax2.plot(np.concatenate([[0.0], rot]), np.concatenate([[0.0], result.torques_nm]), "o-", ms=3,
             label="this model (mesh only, no clearance)")
    cat = catalog
    if catalog is None:
        from ..contact.catalogue import CatalogueError, catalogue_row

        try:
            cat = catalogue_row(40 if size is None else size, 50 if ratio is None else int(round(ratio)))
        except CatalogueError:
            cat = None
    if cat:
        t1, t2 = cat["T1_nm"], cat["T2_nm"]
        a1 = t1 / cat["K1_nm_per_rad"]
        a2 = a1 + (t2 - t1) / cat["K2_nm_per_rad"]
        k = 180 * 60 / math.pi
        row = cat.get("ratio", 50)
        ax2.plot([0.0, a1 * k, a2 * k], [0.0, t1, t2], "k--", lw=1,
                 label=f"catalog, size {cat.get('size', 40)}, ratio {row:g}{'+' if row == 80 else ''} (whole gear, "
                       "K1/K2)" + ("" if ratio is None or ratio == row else f"; this set: ratio {ratio:g}"))
    ax2.set_xlabel("elastic rotation of the FS against the CS (arcmin)")
    ax2.set_ylabel("torque (N·m)")
    ax2.legend(fontsize=7, loc="lower right")  # the curves rise from the origin: the lower right stays clear
    _tidy(ax2)
    width = min(2.0, 10.0 / max(len(result.cases), 1))  # deg: the bars of one ball stay within ±5°
    for i, case in enumerate(result.cases):
        if case.ball_angle_rad.size:
            offset = (i - 0.5 * (len(result.cases) - 1)) * width
            ax3.bar(np.degrees(case.ball_angle_rad) + offset, case.ball_reaction_n, width=width,
                    label=f"{case.torque_nm:g} N·m ({int(case.ball_active.sum())} balls loaded)")
    ax3.axhline(0.0, color="0.5", lw=0.6)
    ax3.set_xlabel("ball position from the major axis (deg)")
    ax3.set_ylabel("ball reaction on the rim (N)")
    ax3.legend(fontsize=7, title="> 0 compressed; a ball not touching carries 0", title_fontsize=7)
    _tidy(ax3)
    if title:
        fig.suptitle(title, fontsize=9, y=1 - 0.06 / 4.0, va="top")
    if path is not None:
        _save(png_bytes(fig, 130), path)
    return fig


def torsional_figure(curve: Any, *, title: str = "", ratio: float | None = None,
                     path: str | os.PathLike | None = None) -> "Figure":
    """The whole gear in torsion (a :class:`~profilegen.contact.chain.TorsionalCurve`): rotation
    of the FS against the CS (arcmin) against the signed torque — the mesh on rigid balls,
    with the Hertz ball springs, and the whole gear with the series compliances (cup wall,
    cup bottom, CS body) — over the whole range (left) and to 1.25 T2 (middle), with the
    catalogue's K1/K2 lines in both directions, labelled with the catalogue table's ratio and
    the set's (``ratio``); right, each part's compliance at the rated torque."""
    k = 180 * 60 / math.pi
    # fixed titles: no panel has an offset text or ticks on top (plain tick labels, no offset), so the
    # titles stand where the automatic placement put them, without measuring each panel's x axis again
    fig, (ax1, ax2, ax3) = fixed_figure((15.0, 4.6), 1, 3, left=0.7, right=0.25, bottom=0.55,
                                        top=0.45 if title else 0.2, wgap=1.25, fixed_titles=True)
    t = np.asarray(curve.torque_nm)
    cat = curve.catalogue
    t2 = float(curve.breakpoints_nm["T2"])
    zoom = np.abs(t) <= 1.25 * t2
    face = getattr(curve, "face", None)  # solved across the face (the scene's face_slices)
    across = "" if face is None else f", {face['slices']} face slices"
    for ax, pick in ((ax1, np.ones(t.size, bool)), (ax2, zoom)):
        for rot, style, label in ((curve.rotation_rad, "o-", f"whole gear (mesh + balls + cup + CS body{across})"),
                                  (curve.mesh_balls_rad, "s--", "mesh + Hertz ball springs"),
                                  (curve.mesh_rad, "^:", "mesh only (teeth, rim, CS ring; rigid balls)")):
            ax.plot(t[pick], np.asarray(rot)[pick] * k, style, ms=3, lw=1, label=label)
        flagged = [i for i, f in enumerate(curve.flags) if f is not None and pick[i]]
        if flagged:
            ax.plot(t[flagged], np.asarray(curve.rotation_rad)[flagged] * k, "x", color="red", ms=8,
                    label="beyond the modelled contact (flagged)")
        if cat and cat.get("K1_nm_per_rad") and cat.get("K2_nm_per_rad"):
            c1, c2 = float(cat["T1_nm"]), float(cat["T2_nm"])
            a1 = c1 / float(cat["K1_nm_per_rad"])
            a2 = a1 + (c2 - c1) / float(cat["K2_nm_per_rad"])
            cat_ratio, size = cat.get("ratio"), cat.get("size")
            label = ("catalogue" + (f" size {size}" if size else "")
                     + (f", ratio 1/{float(cat_ratio):g}" if cat_ratio else "") + ": K1 to T1, K2 to T2"
                     + ("" if ratio is None or cat_ratio is None or float(cat_ratio) == float(ratio)
                        else f"\n(this gear: ratio 1/{float(ratio):g})"))
            ax.plot([-c2, -c1, 0.0, c1, c2], np.array([-a2, -a1, 0.0, a1, a2]) * k, "k--", lw=1.4, label=label)
        for name in ("T1", "T2"):
            tb = float(curve.breakpoints_nm[name])
            for sgn in (1, -1):
                ax.axvline(sgn * tb, color="0.8", lw=0.6, zorder=0)
            ax.text(tb, 0.02, f" {name}", transform=ax.get_xaxis_transform(), fontsize=7, color="0.4")
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.axvline(0.0, color="0.5", lw=0.6)
        ax.set_xlabel("torque on the FS, wave generator locked (N·m)")
        _tidy(ax)
    ax1.set_ylabel("rotation of the FS against the CS (arcmin)")
    ax1.legend(fontsize=7, loc="upper left")
    kt = curve.k_nm_per_rad["total"]["positive"]
    ax1.set_title(f"whole gear: K1 {kt['K1']:.3g}, K2 {kt['K2']:.3g}, K3 {kt['K3']:.3g} N·m/rad "
                  f"(T1, T2 {curve.breakpoints_source})", fontsize=8)
    lm = curve.lost_motion_rad["total"] * k
    ax2.set_title(f"to 1.25 T2; lost motion {lm:.3f} arcmin at ±{curve.lost_motion_torque_nm:.3g} N·m", fontsize=8)
    comp = {n[:-len("_rad_per_nm")]: v for n, v in curve.compliances_at_rated.items() if n != "total_rad_per_nm"}
    names = list(comp)
    values = np.array([comp[n] for n in names]) * 1e6
    total = float(curve.compliances_at_rated["total_rad_per_nm"]) * 1e6
    ax3.barh(range(len(names)), values, color="C0")
    for i, v in enumerate(values):
        ax3.text(v, i, f" {v:.3g} ({v / total:.0%})", va="center", fontsize=7)
    ax3.set_yticks(range(len(names)), [n.replace("_", " ") for n in names], fontsize=8)
    ax3.invert_yaxis()
    ax3.set_xlim(0.0, 1.35 * float(values.max()))
    ax3.set_xlabel("compliance at the rated torque (10⁻⁶ rad/N·m)")
    ax3.set_title(f"total {total:.3g}·10⁻⁶ rad/N·m (secant {1e6 / total:.3g} N·m/rad)", fontsize=8)
    ax3.tick_params(direction="out", length=3)
    if title:
        fig.suptitle(title, fontsize=9, y=1 - 0.06 / 4.6, va="top")
    if path is not None:
        _save(png_bytes(fig, 130), path)
    return fig


def _diaphragm_panel(diaphragm: Any, ax) -> None:
    """The diaphragm's Goodman diagram, or, when the material gives no fatigue limits (they are
    optional), its operating point (τ_m, τ_a) alone with the reason the diagram is missing."""
    if diaphragm.safety_factor is not None:
        plot_goodman(diaphragm, ax)
        return
    tau_m, tau_a = diaphragm.mean_shear_mpa, diaphragm.shear_amplitude_mpa
    ax.plot([tau_m], [tau_a], "o", color="#d62728", label=f"(τ_m, τ_a) = ({tau_m:.1f}, {tau_a:.1f}) MPa")
    # the point sits at the middle (the limits are twice its coordinates): the note goes below it
    ax.text(0.5, 0.25, "no Goodman diagram: the gear set gives no\nmaterial.shear_endurance_limit_mpa / "
            "ultimate_strength_mpa", transform=ax.transAxes, ha="center", va="center", fontsize=8, color="0.35")
    ax.set(xlabel="mean shear τ_m (MPa)", ylabel="shear amplitude τ_a (MPa)",
           xlim=(0.0, 2.0 * max(tau_m, 1e-9)), ylim=(0.0, 2.0 * max(tau_a, 1e-9)))
    ax.grid(True, linewidth=0.3)
    ax.legend(fontsize=7)


def stress_figure(result: Any, *, title: str = "", path: str | os.PathLike | None = None) -> "Figure":
    """The flexspline stresses of a :class:`~profilegen.stress.StressResult`: the tooth-root
    stress (assembly + load) at each torque, the cup bottom's von Mises map at the largest
    torque over (r, φ), the diaphragm's Goodman diagram at the rated torque, and every safety
    factor against the required one."""
    # the right column leaves room for the safety factors' names on the left of its lower panel
    fig, axes = fixed_figure((13.0, 8.0), 2, 2, left=0.62, right=0.98, bottom=0.52, top=0.58 if title else 0.3,
                             wgap=1.62, hgap=0.78, fixed_titles=True)
    ax = axes[0, 0]
    x = np.arange(len(result.torques_nm))
    ass = [r.assembly_stress_mpa for r in result.tooth_ring]
    load = [r.load_stress_mpa for r in result.tooth_ring]
    ax.bar(x, ass, color="#1f5fbf", label="assembly σ_ass (K_σ × rim bending)")
    ax.bar(x, load, bottom=ass, color="#d62728",
           label=f"load σ_load (tangential force from the {result.force_source})")
    for xi, a, b, f in zip(x, ass, load, result.tangential_force_n):
        ax.text(xi, a + b, f"{a + b:.0f} MPa\nF_t {f:.0f} N", ha="center", va="bottom", fontsize=7)
    ax.set_xticks(x, [f"{t:g} N·m" for t in result.torques_nm])
    ax.set_ylabel("tooth-root stress on the major axis (MPa)")
    ax.set_title("tooth ring", fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    ax.set_ylim(0, 1.3 * max(a + b for a, b in zip(ass, load)))
    ax.grid(True, axis="y", color="0.9", lw=0.5)

    ax = axes[0, 1]
    bottom = result.cup_bottom[-1]
    rr, pp = np.meshgrid(bottom.r_mm, bottom.phi_rad, indexing="ij")
    mesh = ax.pcolormesh(np.degrees(pp), rr, bottom.von_mises_mpa, shading="auto", cmap="viridis")
    # the maximum sits at the boss (the panel's lower edge), often at φ = 0 (its left edge): drawn
    # unclipped, large and white-edged over the map's yellow
    ax.plot(np.degrees(bottom.max_phi_rad), bottom.max_r_mm, "*", color="#d62728", ms=16, mec="white", mew=1.2,
            clip_on=False, zorder=6,
            label=f"max {bottom.max_von_mises_mpa:.0f} MPa at r = {bottom.max_r_mm:.2f} mm, "
                  f"φ = {np.degrees(bottom.max_phi_rad):.0f}°")
    fig.colorbar(mesh, ax=ax, label="von Mises (MPa)", fraction=0.05, pad=0.02)
    ax.set_xlabel("φ from the major axis (deg)")
    ax.set_ylabel("radius r (mm), boss → wall")
    ax.set_title(f"cup bottom (plate) at {result.torques_nm[-1]:g} N·m", fontsize=9)
    ax.legend(fontsize=7, loc="upper right")

    _diaphragm_panel(result.diaphragm[0], axes[1, 0])
    axes[1, 0].set_title(f"diaphragm corner at {result.torques_nm[0]:g} N·m", fontsize=9)

    ax = axes[1, 1]
    names = [c.name for c in result.checks]
    values = [np.nan if c.value is None else c.value for c in result.checks]
    colors = ["0.7" if c.value is None else ("#2ca02c" if c.passed else "#d62728") for c in result.checks]
    y = np.arange(len(names))
    ax.barh(y, values, color=colors)
    ax.axvline(result.checks[0].required if result.checks else 1.0, color="k", ls="--", lw=1)
    for yi, c in zip(y, result.checks):
        if c.value is None:  # mid-panel (x in axes units: a log axis has no 0), clear of the required line
            ax.text(0.5, yi, "skipped: the gear set gives no limit for this material", va="center", ha="center",
                    fontsize=7, color="0.35", transform=ax.get_yaxis_transform(),
                    bbox={"facecolor": "white", "edgecolor": "none", "pad": 1.0})
        else:
            ax.text(c.value, yi, f" {c.value:.2f} at {c.torque_nm:g} N·m", va="center", fontsize=7)
    ax.set_yticks(y, names)
    if all(c.value is None for c in result.checks):  # no bar sets the range: one row each, the first on top
        ax.set_ylim(len(names) - 0.5, -0.5)
    else:
        ax.invert_yaxis()
    ax.set_xlabel("safety factor (dashed: required)")
    ax.set_xscale("log")
    shown = [c.value for c in result.checks if c.value is not None]
    if shown:  # room on the right for the longest bar's label (it ran past the panel's frame)
        ax.set_xlim(right=max(max(shown), result.checks[0].required) * 3.0)
    _plain_log_ticks(ax.xaxis, *ax.get_xlim())
    ax.set_title("safety factors (green: pass, red: fail)", fontsize=9)
    ax.grid(True, which="both", color="0.9", lw=0.5)
    if title:
        fig.suptitle(title, fontsize=10, y=1 - 0.06 / 8.0, va="top")
    if path is not None:
        _save(png_bytes(fig, 120), path)
    return fig


def _plain_log_ticks(axis, lo: float, hi: float) -> None:
    """A log axis over a short range (safety factors ~0.5-30) labelled 1, 2, 5, 10, 20 as plain numbers,
    the minor ticks unlabelled: matplotlib labels every minor tick of a range under a decade or two
    (2×10⁰3×10⁰4×10⁰ ran together in stress.png)."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    decades = range(math.floor(math.log10(max(lo, 1e-300))) - 1, math.ceil(math.log10(max(hi, 1e-300))) + 1)
    nice = [m * 10.0 ** e for e in decades for m in (1.0, 2.0, 5.0) if lo <= m * 10.0 ** e <= hi]
    axis.set_major_locator(FixedLocator(nice))
    axis.set_major_formatter(FuncFormatter(lambda x, pos: f"{x:g}"))
    axis.set_minor_formatter(NullFormatter())


def plot_goodman(result: DiaphragmStress, ax=None):
    """Goodman diagram for shear (seed 000's Fig. 21): the line τ_a/τ_-1 + τ_m/τ_u = 1, the
    line scaled by 1/n through the operating point (τ_m, τ_a) and the load line from the
    origin. ``ax``: a matplotlib Axes, or None for a new figure (Agg canvas, no pyplot).
    Returns the Axes. Needs a result computed with ``fatigue=True``."""
    if result.safety_factor is None:
        raise StressError("result.safety_factor is None: plot_goodman needs a result computed with fatigue=True")
    if ax is None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        fig = Figure(figsize=(4.8, 3.8), layout="constrained")
        FigureCanvasAgg(fig)
        ax = fig.add_subplot()
    tau_e, tau_u = result.shear_endurance_limit_mpa, result.shear_ultimate_mpa
    assert tau_e is not None and tau_u is not None  # set with safety_factor (fatigue=True)
    tau_m, tau_a, n = result.mean_shear_mpa, result.shear_amplitude_mpa, result.safety_factor
    ax.plot([0.0, tau_u], [tau_e, 0.0], "k-", label="Goodman: τ_a/τ_-1 + τ_m/τ_u = 1")
    if math.isfinite(n) and n > 0:
        ax.plot([0.0, tau_u / n], [tau_e / n, 0.0], "k--", linewidth=0.8, label=f"operating line, n = {n:.2f}")
        scale = max(1.0, n)
        ax.plot([0.0, tau_m * scale], [0.0, tau_a * scale], ":", color="0.4", linewidth=0.8, label="load line")
    ax.plot([tau_m], [tau_a], "o", color="#d62728", label=f"(τ_m, τ_a) = ({tau_m:.1f}, {tau_a:.1f}) MPa")
    ax.set(xlabel="mean shear τ_m (MPa)", ylabel="shear amplitude τ_a (MPa)", xlim=(0.0, 1.05 * tau_u),
           ylim=(0.0, 1.1 * tau_e), title="diaphragm corner, Goodman (shear)")
    ax.grid(True, linewidth=0.3)
    ax.legend(fontsize=7)
    return ax


def plot_tooth_ring_study(study: ToothRingStudy, axes=None):
    """Three panels like seed 001's figures: σ_total against δ/r_m (with the no-load
    assembly stress dashed and each optimum marked), against r1/m and against ν (at the
    optimal δ for each ν), one line per torque. ``axes``: three matplotlib Axes, or None for
    a new figure (Agg canvas, no pyplot). Returns the axes."""
    if axes is None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        fig = Figure(figsize=(11.0, 3.6), layout="constrained")
        FigureCanvasAgg(fig)
        axes = fig.subplots(1, 3)
    ax_d, ax_r, ax_n = axes
    for k, torque in enumerate(study.torques_nm):
        label = f"{torque:g} N·m"
        line, = ax_d.plot(100 * study.thickness_ratios, study.stress_vs_thickness_mpa[k], label=label)
        ax_d.plot(100 * study.optimal_thickness_ratio[k], study.optimal_thickness_stress_mpa[k], "o",
                  color=line.get_color(), markersize=4)
        ax_r.plot(study.fillet_ratios, study.stress_vs_fillet_mpa[k], color=line.get_color(), label=label)
        ax_n.plot(study.slot_ratios, study.stress_vs_slot_mpa[k], color=line.get_color(), label=label)
    ax_d.plot(100 * study.thickness_ratios, study.assembly_vs_thickness_mpa[0], "k--", linewidth=0.8,
              label="assembly only")
    c = study.case
    ax_d.set(xlabel="δ/r_m (%)", ylabel="σ_total (MPa)", title=f"r1/m = {c.fillet_ratio:g}, ν = {c.slot_ratio:g}")
    ax_r.set(xlabel="r1/m", ylabel="σ_total (MPa)",
             title=f"δ/r_m = {100 * c.thickness_ratio:g} %, ν = {c.slot_ratio:g}")
    ax_n.set(xlabel="slot width ratio ν", ylabel="σ_total at optimal δ (MPa)", title=f"r1/m = {c.fillet_ratio:g}")
    for ax in axes:
        ax.grid(True, linewidth=0.3)
    ax_d.legend(fontsize=7)
    return axes


def sweep_figure(rows, fields, output: str, *, title: str, ax=None, path=None):
    """One panel per swept field: ``output`` of the rows whose ``status`` is ok against the
    field, marked by the design's ``verdict`` (PASS filled, INCOMPLETE open, FAIL open red: an
    infeasible point), failed points as red crosses on the axis (the sweep's figure; see
    :func:`profilegen.studies.sweep.plot_sweep`). Returns the Axes of the first panel, or ``path``
    when given (PNG, written atomically)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    if ax is None:
        fig = Figure(figsize=(4.2 * len(fields), 3.4), layout="constrained")
        FigureCanvasAgg(fig)
        axes = [fig.add_subplot(1, len(fields), k + 1) for k in range(len(fields))]
    else:
        fig, axes = ax.figure, [ax]
    for a, f in zip(axes, fields):
        xs = [r[f] for r in rows]
        categorical = not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in xs)
        if categorical:
            labels = sorted({str(x) for x in xs})
            pos = {lab: k for k, lab in enumerate(labels)}
            xs = [pos[str(x)] for x in xs]
            a.set_xticks(range(len(labels)), labels)
        ran = [(x, r[output], r.get("verdict")) for x, r in zip(xs, rows) if r["status"] == "ok" and r[output] is not None]
        bad = [x for x, r in zip(xs, rows) if r["status"] != "ok"]
        style: dict[str, Any]
        for verdict, style, label in ((None, dict(color="#1f5fbf"), "ok"), ("PASS", dict(color="#1f5fbf"), "PASS"),
                                      ("INCOMPLETE", dict(color="#1f5fbf", mfc="none"), "INCOMPLETE (not all checked)"),
                                      ("FAIL", dict(color="#d62728", mfc="none", markersize=7), "FAIL (infeasible)")):
            pts = [(x, y) for x, y, v in ran if v == verdict]  # each point as its design's verdict judged it
            if pts:
                marker: dict[str, Any] = {"markersize": 4, **style}
                a.plot(*zip(*pts), "o", **marker, label=f"{label} ({len(pts)})")
        if bad:
            a.plot(bad, [0.0] * len(bad), "x", color="#d62728", markersize=6, transform=a.get_xaxis_transform(),
                   clip_on=False, label=f"failed ({len(bad)})")
        a.set_xlabel(f)
        a.set_ylabel(output)
        a.grid(True, linewidth=0.4, alpha=0.5)
        a.legend(fontsize=7)
    fig.suptitle(title, fontsize=9)
    if path is None:
        return axes[0]
    from pathlib import Path

    from .export import atomic_write

    path = Path(path)
    with atomic_write(path, "wb") as handle:
        fig.savefig(handle, format="png", dpi=120)
    return path
