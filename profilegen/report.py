"""Reports a designer signs a profile off with: self-contained HTML, pictures embedded.

``fit_report_html(design, fits, clearance)`` — for every arc–line–arc fit method:
the error along the flank, max/RMS and where, the one-sided fit's backlash, ridges,
the fit time, and the fitted profile's clearance against the FS tooth family.
"""

from __future__ import annotations

import base64
import html
import io

import numpy as np

__all__ = ["fit_report_html", "figure_png"]


def figure_png(fig, dpi: int = 130) -> str:
    """A matplotlib Figure as a base64 PNG data URI."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def _figure(width=7.0, height=3.2, ncols=1):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, ncols)
    return fig, axes


def _error_figure(fits: dict) -> str:
    fig, ax = _figure()
    for name, fit in fits.items():
        ax.plot(fit.arclength_mm, np.asarray(fit.error_mm) * 1e3, label=f"{name} (max {fit.max_error_mm * 1e3:.3f} µm)")
    ax.axhline(0, color="0.5", lw=0.6)
    ax.set_xlabel("position along the CS flank from the tip circle (mm)")
    ax.set_ylabel("deviation from the envelope (µm)")
    ax.legend(fontsize=8)
    ax.grid(True, lw=0.3, alpha=0.5)
    return figure_png(fig)


def _profile_figure(design, fits: dict) -> str:
    fig, axes = _figure(7.0, 4.0, ncols=2)
    flank = design.form.working_flank["right"]
    for ax in axes:
        ax.plot(*design.envelope.flank["boundary"].T, color="0.6", lw=3, label="swept boundary (exact)")
        for name, fit in fits.items():
            pts = fit.chain.sample(1e-5)
            ax.plot(*pts.T, lw=1, label=f"{name} arc–line–arc")
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
    axes[0].set_title("CS space")
    lo, hi = flank.min(0), flank.max(0)
    pad = 0.05 * np.ptp(flank, 0).max()
    axes[1].set_xlim(lo[0] - pad, hi[0] + pad)
    axes[1].set_ylim(lo[1] - pad, hi[1] + pad)
    axes[1].set_title("right flank, fitted part")
    axes[1].legend(fontsize=7)
    return figure_png(fig)


def _clearance_figure(clearance) -> str:
    fig, ax = _figure()
    ax.plot(np.degrees(clearance.phi), clearance.clearance_mm * 1e3, lw=1)
    ax.axhline(0, color="0.5", lw=0.6)
    k = int(np.argmin(clearance.clearance_mm))
    ax.plot(np.degrees(clearance.phi[k]), clearance.clearance_mm[k] * 1e3, "v", color="C3",
            label=f"min {clearance.clearance_mm[k] * 1e3:.4f} µm at φ = {np.degrees(clearance.phi[k]):.2f}°")
    ax.set_xlabel("φ (deg)")
    ax.set_ylabel("clearance FS tooth ↔ fitted CS (µm)")
    ax.legend(fontsize=8)
    ax.grid(True, lw=0.3, alpha=0.5)
    return figure_png(fig)


def fit_report_html(design, fits: dict, *, chosen: str, clearance, positions: int) -> str:
    """The fit-error report as one self-contained HTML page."""
    g = design.gearset
    rows = []
    for name, fit in fits.items():
        at = fit.at_max_mm
        r_at = float(np.hypot(*at))
        backlash = getattr(fit, "backlash_mm", None)
        bl = "—" if backlash is None else f"{np.max(backlash) * 1e3:.3f}"
        rows.append(
            f"<tr><td>{html.escape(name)}{' (used)' if name == chosen else ''}</td>"
            f"<td>{fit.max_error_mm * 1e3:.4f}</td><td>{fit.rms_error_mm * 1e3:.4f}</td>"
            f"<td>({at[0]:.4f}, {at[1]:.4f}), r = {r_at:.4f}</td><td>{bl}</td><td>{fit.time_s * 1e3:.1f}</td></tr>"
        )
    ridges = design.envelope.ridges
    ridge_text = (
        "none: every junction of the swept boundary is tangential"
        if not ridges
        else "; ".join(f"({r.point[0]:.4f}, {r.point[1]:.4f}) mm, kink {r.kink_deg:.2f}° between {r.sources[0]} and {r.sources[1]}" for r in ridges)
    )
    profile = design.profile
    cad = profile.cad_fits if profile is not None else (fits[chosen],)
    params = ""
    for b, fit in enumerate(cad):
        head = f"branch {b + 1}: " if len(cad) > 1 else ""
        params += "".join(f"<tr><td>{html.escape(head + k)}</td><td>{v:.9g}</td></tr>" for k, v in fit.params.items())
    verdict = "no interference" if clearance.min_mm >= -1e-6 else f"INTERFERES by {-clearance.min_mm * 1e3:.3f} µm"
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Fit report — {html.escape(g.name)}</title>
<style>body{{font-family:sans-serif;max-width:60em;margin:2em auto;line-height:1.4}}
table{{border-collapse:collapse}}td,th{{border:1px solid #aaa;padding:.2em .5em;text-align:right}}
td:first-child,th:first-child{{text-align:left}}img{{max-width:100%}}</style></head><body>
<h1>Arc–line–arc fit of the CS flank — {html.escape(g.name)}</h1>
<p>{html.escape(g.description)}. m = {g.gear.module_mm:g} mm, z = {g.gear.flexspline_teeth}/{g.gear.circular_spline_teeth},
ω* = {g.wave_generator.deflection_coefficient:g}, scene <b>{html.escape(design.scene.name)}</b>
(deformation: {html.escape(design.deformation.source)}). The fitted part of the flank runs from the CS tip
circle (r = {design.form.tip_radius_mm:.4f} mm) to where the flank leaves the swept boundary; the exact
envelope has a chord error of {design.envelope.chord_tol_mm * 1e6:g} nm.</p>
<h2>Errors</h2>
<table><tr><th>method</th><th>max |error| (µm)</th><th>RMS (µm)</th><th>worst point (mm)</th><th>max backlash (µm)</th><th>time (ms)</th></tr>
{''.join(rows)}</table>
<p>Deviation is the signed normal distance from the envelope to the fitted flank (positive: the fit
leaves clearance, i.e. lies toward the CS material). Branch-switch ridges: {html.escape(ridge_text)}.</p>
<img src="{_error_figure(fits)}" alt="error along the flank">
<img src="{_profile_figure(design, fits)}" alt="fitted profiles">
<h2>The profile used: {html.escape(chosen)}{" per branch" if len(cad) > 1 else ""}</h2>
<table><tr><th>parameter</th><th>value</th></tr>{params}</table>
<p>Checked against the FS tooth family at {positions} positions over one pass (shapely distances to the
tooth surface): <b>{verdict}</b>; smallest clearance {clearance.min_mm * 1e3:.4f} µm at
φ = {np.degrees(clearance.at_phi):.2f}°.</p>
<img src="{_clearance_figure(clearance)}" alt="clearance map">
</body></html>
"""
