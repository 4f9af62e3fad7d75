"""Reports a designer signs a profile off with: self-contained HTML, pictures embedded.

``design_report_html(design)`` — the whole design on one page: the profile and its fit
error, the loaded contact, the flexspline stresses with every safety factor against the
material's limits (pass/fail).

``fit_report_html(design, fits, clearance)`` — for every arc–line–arc fit method:
the error along the flank, max/RMS and where, the one-sided fit's backlash, ridges,
the fit time, and the fitted profile's clearance against the FS tooth family.

``png_jobs(design)`` — every picture of a design's files (``envelope.png``, ``contact.png``,
``stress.png``) and reports, as (function, arguments) pairs; ``rendering(jobs)`` draws them
in two forked worker processes while the caller writes its other files, and hands the PNG
bytes to both reports, so no figure is drawn twice.
"""

from __future__ import annotations

import base64
import contextlib
import html
import logging
import os
import signal
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

import numpy as np

from ..pools import stop_pool
from .forkserver import die_with as _die_with
from .interactive import figure_html
from ..pipeline.design import interference_tol_mm
from .sheet import format_clearance, sheet_html

if TYPE_CHECKING:  # pragma: no cover
    from concurrent.futures import Future, ProcessPoolExecutor

    from .forkserver import ServerPool

__all__ = ["deformation_fit_dict", "deformation_section_html", "design_report_html", "fit_report_html", "figure_png",
           "png_jobs", "rendering", "FigureWorkers"]

log = logging.getLogger(__name__)

def figure_png(fig, dpi: int = 130) -> str:
    """A matplotlib Figure as a base64 PNG data URI."""
    from .plot import png_bytes

    return _png_uri(png_bytes(fig, dpi))


def _figure(width=7.0, height=3.2, ncols=1, nrows=1, *, left=0.72, right=0.12, bottom=0.5, top=0.12,
            wgap=0.0, hgap=0.0, **subplot_kw):
    """A report figure with fixed margins in inches (see :func:`profilegen.output.plot.fixed_figure`)."""
    from .plot import fixed_figure

    return fixed_figure((width, height), nrows, ncols, left=left, right=right, bottom=bottom, top=top,
                        wgap=wgap, hgap=hgap, **subplot_kw)


def error_png(fits: dict) -> bytes:
    """The deviation of every fit from the envelope along the flank (µm), as PNG bytes."""
    from .plot import png_bytes

    fig, ax = _figure()
    for name, fit in fits.items():
        ax.plot(fit.arclength_mm, np.asarray(fit.error_mm) * 1e3, label=f"{name} (max {fit.max_error_mm * 1e3:.3f} µm)")
    ax.axhline(0, color="0.5", lw=0.6)
    ax.set_xlabel("position along the CS flank from the tip circle (mm)")
    ax.set_ylabel("deviation from the envelope (µm)")
    ax.legend(fontsize=8)
    ax.grid(True, lw=0.3, alpha=0.5)
    return png_bytes(fig, 130)


def profile_png(boundary, flank, fits: dict) -> bytes:
    """The swept boundary with every fitted arc–line–arc flank: the whole CS space and the
    fitted part of the right flank (``flank``: its points, which set the zoom), as PNG bytes."""
    from .plot import png_bytes

    boundary = np.asarray(boundary, dtype=float)
    flank = np.asarray(flank, dtype=float)
    lo, hi = flank.min(0), flank.max(0)
    pad = 0.05 * np.ptp(flank, 0).max()
    # equal aspect in both panels: the zoom on the flank (tall) gets what its full height needs,
    # at least 2 in (its title and legend), the whole space (wide) the rest of the 5.3 in
    zoom_aspect = (hi[0] - lo[0] + 2 * pad) / max(hi[1] - lo[1] + 2 * pad, 1e-9)
    zoom_w = float(np.clip(3.2 * zoom_aspect, 2.0, 2.65))
    fig, axes = _figure(7.0, 4.3, ncols=2, left=0.75, right=0.1, bottom=0.8, top=0.3, wgap=0.85,
                        width_ratios=[5.3 - zoom_w, zoom_w])
    samples = {name: fit.chain.sample(1e-5) for name, fit in fits.items()}
    for ax in axes:
        ax.plot(*boundary.T, color="0.6", lw=3, label="swept boundary (exact)")
        for name, pts in samples.items():
            ax.plot(*pts.T, lw=1, label=f"{name} arc–line–arc")
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
    axes[0].set_title("CS space")
    axes[1].set_xlim(lo[0] - pad, hi[0] + pad)
    axes[1].set_ylim(lo[1] - pad, hi[1] + pad)
    axes[1].set_title("right flank, fitted part")
    handles, labels = axes[1].get_legend_handles_labels()  # below both panels: a legend in an axes hides the flank
    fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 0.0), ncols=len(labels), fontsize=7,
               frameon=False)
    return png_bytes(fig, 130)


def _profile_args(design, fits: dict) -> tuple:
    return design.envelope.flank["boundary"], design.form.working_flank["right"], fits


def clearance_png(clearance) -> bytes:
    """Clearance between the FS tooth and the fitted CS along φ, its minimum marked, as PNG bytes."""
    from .plot import png_bytes

    fig, ax = _figure()
    ax.plot(np.degrees(clearance.phi), clearance.clearance_mm * 1e3, lw=1)
    ax.axhline(0, color="0.5", lw=0.6)
    k = int(np.argmin(clearance.clearance_mm))
    ax.plot(np.degrees(clearance.phi[k]), clearance.clearance_mm[k] * 1e3, "v", color="C3",
            label=f"min {format_clearance(clearance.clearance_mm[k])} at φ = {np.degrees(clearance.phi[k]):.2f}°")
    ax.set_xlabel("φ (deg)")
    ax.set_ylabel("clearance FS tooth ↔ fitted CS (µm)")
    ax.legend(fontsize=8)
    ax.grid(True, lw=0.3, alpha=0.5)
    return png_bytes(fig, 130)


def _image(images: dict | None, name: str, draw, *args) -> str:
    """The data URI of ``images[name]`` (PNG bytes drawn before), or of ``draw(*args)``."""
    png = (images or {}).get(name)
    return _png_uri(draw(*args) if png is None else png)


def fit_report_html(design, fits: dict, *, chosen: str, clearance, positions: int,
                    images: dict | None = None) -> str:
    """The fit-error report as one self-contained HTML page. ``images``: PNG bytes already drawn
    for this design (:func:`png_jobs` names: ``fit_error``, ``fit_profile``, ``fit_clearance``,
    ``deformation_samples``, ``deformation_residuals``), embedded as they are; the others are drawn."""
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
        params += "".join(f"<tr><td>{html.escape(head + k)}</td><td>{v:.9g}{_radius_shape(fit, k)}</td></tr>"
                          for k, v in fit.params.items())
    verdict = "no interference" if clearance.min_mm >= -1e-6 else f"INTERFERES by {-clearance.min_mm * 1e3:.3f} µm"
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Fit report — {html.escape(g.name)}</title>
<style>body{{font-family:sans-serif;max-width:60em;margin:2em auto;line-height:1.4}}
table{{border-collapse:collapse}}td,th{{border:1px solid #aaa;padding:.2em .5em;text-align:right}}
td:first-child,th:first-child{{text-align:left}}img{{max-width:100%}}</style></head><body>
<h1>Arc–line–arc fit of the CS flank — {html.escape(g.name)}</h1>
<p>{html.escape(g.description)}{_gear_numbers(g)},
ω* = {g.wave_generator.deflection_coefficient:g}, scene <b>{html.escape(design.scene.name)}</b>
(deformation: {html.escape(design.deformation.source)}). The fitted part of the flank runs from the CS tip
circle (r = {design.form.tip_radius_mm:.4f} mm) to where the flank leaves the swept boundary; the exact
envelope has a chord error of {design.envelope.chord_tol_mm * 1e6:g} nm.</p>
<h2>Errors</h2>
<table><tr><th>method</th><th>max |error| (µm)</th><th>RMS (µm)</th><th>worst point (mm)</th><th>max backlash (µm)</th><th>time (ms)</th></tr>
{''.join(rows)}</table>
<p>Deviation is the signed normal distance from the envelope to the fitted flank (positive: the fit
leaves clearance, i.e. lies toward the CS material). Branch-switch ridges: {html.escape(ridge_text)}.</p>
<img src="{_image(images, "fit_error", error_png, fits)}" alt="error along the flank">
<img src="{_image(images, "fit_profile", profile_png, *_profile_args(design, fits))}" alt="fitted profiles">
<h2>The profile used: {html.escape(chosen)}{" per branch" if len(cad) > 1 else ""}</h2>
<table><tr><th>parameter</th><th>value</th></tr>{params}</table>
<p>Checked against the FS tooth family at {positions} positions over one pass (shapely distances to the
tooth surface): <b>{verdict}</b>; smallest clearance {html.escape(format_clearance(clearance.min_mm))} at
φ = {np.degrees(clearance.at_phi):.2f}°.</p>
<img src="{_image(images, "fit_clearance", clearance_png, clearance)}" alt="clearance map">
{deformation_section_html(design, images)}
</body></html>
"""


def deformation_samples_png(rim) -> bytes:
    """The FEM samples of ω and υ along φ with the Fourier fit, the general sine and ring
    theory, as PNG bytes."""
    from .plot import png_bytes

    phi_s, w_s, u_s = rim.samples
    phi = np.linspace(0.0, np.pi, 721)
    ref_w, ref_u = rim.reference.evaluate(phi, order=0)
    fw, fu = rim.model.evaluate(phi, order=0)
    fig, axes = _figure(7.0, 3.4, ncols=2, left=0.75, right=0.1, top=0.1, wgap=0.85)
    for ax, s, f, r, name in ((axes[0], w_s, fw, ref_w, "ω"), (axes[1], u_s, fu, ref_u, "υ")):
        ax.plot(np.degrees(phi_s), s, ".", ms=2.5, color="0.3", label="FEM samples")
        ax.plot(np.degrees(phi), f[0], lw=1, label=f"Fourier, order {rim.model.order}")
        if rim.sine is not None:
            sw, su = rim.sine.evaluate(phi, order=0)
            ax.plot(np.degrees(phi), (sw if name == "ω" else su)[0], lw=1, ls="--", label="general sine")
        ax.plot(np.degrees(phi), r[0], lw=0.8, color="C3", ls=":", label="ring theory")
        ax.set_xlabel("φ (deg)")
        ax.set_ylabel(f"{name} (mm)")
        ax.grid(True, lw=0.3, alpha=0.5)
    axes[0].legend(fontsize=7)
    return png_bytes(fig, 130)


def deformation_residuals_png(rim) -> bytes:
    """Fit − FEM (nm) and ring theory − FEM (µm) for ω and υ at the FEM samples, the ends
    of the wrap marked, as PNG bytes."""
    from .plot import png_bytes

    phi_s, w_s, u_s = rim.samples
    fig, axes = _figure(7.0, 5.6, ncols=2, nrows=2, left=0.82, right=0.1, top=0.1, wgap=0.9, hgap=0.15,
                        sharex=True)
    fw_s, fu_s = rim.model.evaluate(phi_s, order=0)
    tw_s, tu_s = rim.reference.evaluate(phi_s, order=0)
    sine = rim.sine.evaluate(phi_s, order=0) if rim.sine is not None else None
    edge = np.degrees(rim.fem.contact_angle_rad)
    for col, (s, f, t, name) in enumerate(((w_s, fw_s, tw_s, "ω"), (u_s, fu_s, tu_s, "υ"))):
        top, bottom = axes[0, col], axes[1, col]
        top.plot(np.degrees(phi_s), (f[0] - s) * 1e6, lw=1, label="Fourier − FEM")
        if sine is not None:
            top.plot(np.degrees(phi_s), (sine[col][0] - s) * 1e6, lw=1, ls="--", label="general sine − FEM")
        top.set_ylabel(f"{name}: fit − FEM (nm)")
        bottom.plot(np.degrees(phi_s), (t[0] - s) * 1e3, lw=1, color="C3", label="ring theory − FEM")
        bottom.set_ylabel(f"{name}: ring theory − FEM (µm)")
        bottom.set_xlabel("φ (deg); grey: end of the contact (wrap)")
        for ax in (top, bottom):
            ax.axvline(edge, color="0.6", lw=0.6)
            ax.axvline(180 - edge, color="0.6", lw=0.6)
            ax.grid(True, lw=0.3, alpha=0.5)
    axes[0, 0].legend(fontsize=7)
    axes[1, 0].legend(fontsize=7)
    return png_bytes(fig, 130)


def _stats_rows(label: str, omega, upsilon) -> str:
    rows = ""
    for comp, st in (("ω", omega), ("υ", upsilon)):
        rows += (f"<tr><td>{html.escape(label)}, {comp}</td><td>{st.n_params}</td><td>{st.sse_mm2:.3e}</td>"
                 f"<td>{st.rmse_mm * 1e3:.4g}</td><td>{st.r2:.12f}</td><td>{st.adj_r2:.12f}</td>"
                 f"<td>{st.max_error_mm * 1e3:.4g} at {np.degrees(st.max_error_phi_rad):.2f}°</td>"
                 f"<td>{st.defect_mm * 1e3:.3g}</td></tr>")
    return rows


def deformation_fit_dict(design) -> dict:
    """Contents of ``deformation_fit.json``: FEM samples (φ in deg), both fits, ring theory, the wrap."""
    rim = design.rim
    out = {"gearset": design.gearset.name, "scene": design.scene.name, "deflection_w0_mm": design.gearset.deflection_mm,
           "rim": None if rim is None else rim.tier.label()}
    if rim is None or rim.fem is None:
        out["model"] = design.deformation.to_dict()
        out["note"] = "ring theory: no FEM samples and no fit at this tier"
        return out
    fem = rim.fem
    phi_s, w_s, u_s = rim.samples
    tw, tu = rim.reference.evaluate(phi_s, order=0)
    out.update({
        "dof": rim.dof,
        "fem_time_s": rim.fem_time_s,
        "error_estimate_mm": rim.error_estimate_mm,
        "error_measure": rim.error_measure,
        "samples": {"phi_deg": np.degrees(phi_s).tolist(), "omega_mm": w_s.tolist(), "upsilon_mm": u_s.tolist(),
                    "read_on": "neutral line r_m (node line of the mesh)"},
        "omega_at_major_axis_mm": float(fem.omega_mm[0]),
        "bore_omega_at_major_axis_mm": float(fem.bore_omega_mm[0]),
        "fourier": rim.model.to_dict(),
        "general_sine": None if rim.sine is None else rim.sine.to_dict(),
        "ring_theory_max_difference_mm": {"omega": float(np.max(np.abs(tw[0] - w_s))),
                                          "upsilon": float(np.max(np.abs(tu[0] - u_s)))},
        "contact_angle_deg": fem.contact_angle_deg,
        "contact_angle_warning": next((w for w in fem.warnings if "ill-conditioned" in w), ""),
    })
    return out


def deformation_section_html(design, images: dict | None = None) -> str:
    """The deformation part of the fit report: FEM vs fits vs ring theory, residuals, metrics, wrap.
    ``images``: PNG bytes drawn before (``deformation_samples``, ``deformation_residuals``)."""
    rim = design.rim
    if rim is None or rim.fem is None:
        return (f"<h2>Deformation</h2><p>{html.escape(design.deformation.source)}: the analytic model of the "
                f"<b>{html.escape(design.scene.name)}</b> scene, no FEM samples to fit. Run the <code>design</code> or "
                "<code>verify</code> scene for the FEM rim and its fit.</p>")
    fem = rim.fem
    samples_png = _image(images, "deformation_samples", deformation_samples_png, rim)
    residual_png = _image(images, "deformation_residuals", deformation_residuals_png, rim)
    rows = _stats_rows(f"Fourier (order {rim.model.order})", rim.model.omega_stats, rim.model.upsilon_stats)
    if rim.sine is not None:
        rows += _stats_rows("general sine series Σ a_i sin(b_i φ + c_i)", rim.sine.omega_fit.stats, rim.sine.upsilon_fit.stats)
    wrap = next((w for w in fem.warnings if "ill-conditioned" in w), "")
    est = "—" if rim.error_estimate_mm is None else f"{rim.error_estimate_mm * 1e3:.3g} µm"
    return f"""<h2>Deformation: {html.escape(rim.tier.label())}</h2>
<p>{rim.dof} degrees of freedom, FEM solve {rim.fem_time_s:.3f} s, mesh error estimate {est}
({html.escape(rim.error_measure)}). ω(0) = {fem.omega_mm[0]:.6f} mm on the neutral line,
{fem.bore_omega_mm[0]:.6f} mm at the bore (w0 = {design.gearset.deflection_mm:g} mm). The kinematics uses the Fourier fit.</p>
<img src="{samples_png}" alt="FEM samples, fits and ring theory">
<img src="{residual_png}" alt="residuals along φ">
<table><tr><th>fit</th><th>parameters</th><th>SSE (mm²)</th><th>RMSE (µm)</th><th>R²</th><th>adjusted R²</th>
<th>max |error| (µm)</th><th>periodicity defect f(2π) − f(0) (µm)</th></tr>{rows}</table>
<p>Contact (wrap) angle: {fem.contact_angle_deg:.2f}° from the major axis. <b>Warning:</b> {html.escape(wrap)}.</p>
"""


_STYLE = """<style>body{font-family:sans-serif;max-width:1360px;margin:.5em auto;padding:0 8px;line-height:1.4}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #aaa;padding:.2em .5em;text-align:right}
td:first-child,th:first-child{text-align:left}td.text{text-align:left;max-width:40em}img{max-width:100%}
.pass{color:#1a7f1a;font-weight:bold}.fail{color:#c00;font-weight:bold}.skip{color:#777}</style>"""


def _gear_numbers(g) -> str:
    """'. m = …, z = …/…' unless the gear set's description already says both (it is printed once)."""
    m, z = f"m = {g.gear.module_mm:g} mm", f"z = {g.gear.flexspline_teeth}/{g.gear.circular_spline_teeth}"
    return "" if m in g.description and z in g.description else f". {m}, {z}"


def _radius_shape(fit, key: str) -> str:
    """' (convex: centre in the CS tooth)' after a fitted radius ``r1_mm``/``r2_mm``: its sign alone
    (the turn along the flank) does not say which way the flank curves."""
    if key not in ("r1_mm", "r2_mm") or not np.isfinite(fit.params[key]):
        return ""
    concave = (fit.params[key] > 0) == (fit.space_side == "left")
    return " (concave: centre in the tooth space)" if concave else " (convex: centre in the CS tooth)"


def _num(x, fmt=".1f") -> str:
    return "—" if x is None else format(x, fmt)


def _verdict(check) -> str:
    if check.passed is None:
        return '<span class="skip">NOT CHECKED</span>'
    return '<span class="pass">pass</span>' if check.passed else '<span class="fail">FAIL</span>'


def _face_section(design, images: dict) -> str:
    """Across the face width (:func:`profilegen.output.face.face_section_html`), face.png embedded."""
    from .face import face_png_job, face_section_html

    job = face_png_job(design)
    if job is None:
        return ""
    return face_section_html(design, _image(images, "face", job[0], *job[1]))


def _png_uri(png: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def _contact_section(design, png: bytes | None = None) -> str:
    c = design.contact
    if c is None:
        return ("<h2>Loaded contact</h2><p>Not run in this scene (run the <code>design</code> or <code>verify</code> "
                "scene, or <code>--contact</code>); the tooth-ring load stress below uses a force estimate.</p>")
    from . import plot

    k = c.secant_stiffness_nm_per_rad
    rows = "".join(
        f"<tr><td>{case.torque_nm:g}</td><td>{case.teeth_in_contact}</td><td>{case.rotation_arcmin:.3f}</td>"
        f"<td>{case.max_tooth_force_n:.0f}</td><td>{ki:.3g}</td>"
        f"<td class=text>{html.escape(case.beyond_capacity or 'within the searched zone')}</td></tr>"
        for case, ki in zip(c.cases, k))
    uri = _png_uri(png) if png is not None else figure_png(plot.contact_figure(c, title="", ratio=design.gearset.ratio, size=_catalogue_size(design.gearset)), dpi=100)
    whole = ("; the whole gear's stiffness, which the catalogue's K1/K2 are, is in the section above"
             if getattr(design, "torsional", None) is not None else
             "; the whole gear's stiffness (the catalogue's K1/K2) comes from the design and verify scenes' torsional curve")
    return f"""<h2>Loaded contact (the tooth mesh)</h2>
<p>{c.points.count} candidate points on {c.points.teeth.size} teeth per zone, {c.zones} zones; FEM influence
coefficients (face width {c.compliance_info.get('face_width_mm', float('nan')):.4g} mm), Lemke's complementary
pivoting on the teeth and {'every wave-generator ball (each a rigid one-sided support at its no-load gap)'
if c.compliance_info.get('ball_supports') == 'all' else 'the balls within the rim’s no-load contact angle'}.
The rotation and stiffness here are <b>the mesh's alone</b> (teeth, rim and the CS ring's ovalisation, on rigid
balls: no ball Hertz, inner ring, cam or cup wind-up){whole}.</p>
<table><tr><th>torque (N·m)</th><th>teeth in contact per zone</th><th>mesh rotation (arcmin)</th>
<th>max tooth force (N)</th><th>mesh-only secant stiffness (N·m/rad)</th><th>capacity</th></tr>{rows}</table>
<img src="{uri}" alt="loaded contact">"""


def _ratcheting_and_error_section(design) -> str:
    """The ratcheting estimate and the loaded transmission error, when the scene ran them."""
    out = []
    r = getattr(design, "ratcheting", None)
    if r is not None:
        cat = r.catalogue or {}
        against = ("" if r.ratio_to_catalogue is None else
                   f" The catalogue gives {float(cat['torque_nm']):g} N·m ({html.escape(str(cat.get('source')))}): "
                   f"this estimate is {r.ratio_to_catalogue:.2f} times that.")
        how = ("extrapolated beyond the torques the contact could carry" if r.extrapolated
               else "interpolated between solved torques")
        beyond = [f"{c.torque_nm:g}" for c in design.contact.cases if r.flag(c.torque_nm) is not None] \
            if design.contact is not None else []
        out.append(f"""<h3>Ratcheting</h3>
<p>Under torque the tooth forces push the flexspline rim inward and the circular spline outward, so the
loaded teeth slide up the flanks; when they have climbed as far as the teeth overlap, they skip. This model
puts that torque at about <b>{r.torque_nm:.4g} N·m</b> ({r.ratio_to_rated:.2f} × the rated torque;
{how}).{against} {'Torques at or beyond it: ' + ', '.join(beyond) + ' N·m (a failure in the verdict).'
                     if beyond else 'The set’s torques are all below it.'}
Model: {html.escape(r.model)}</p>""")
    te = getattr(design, "transmission", None)
    if te is not None:
        out.append(f"""<h3>Transmission error under load</h3>
<p>At the rated torque ({te.torque_nm:g} N·m) the contact was solved at {te.psi_rad.size} wave-generator
positions over one tooth passage, the contact points and gaps found afresh at each. The output lags its
ideal position by an amount that varies by <b>{te.peak_to_peak_arcsec:.3g} arcsec peak to peak</b> over the
passage; the mesh stiffness varies by a factor {te.stiffness_ripple:.4f} (max/min). The balls are held
against the wave generator's major axis (the tooth-passage error alone, without the cage's slower ripple).</p>""")
    return "\n".join(out)


def _quantity(value, key: str) -> str:
    """A stiffness in whole N·m/rad with thin-space thousands (196 346), an angle to 0.001 arcmin."""
    if value is None:
        return "—"
    if key.endswith("_nm_per_rad"):
        return f"{float(value):,.0f}".replace(",", "\u2009")
    return f"{float(value):.3f}"


def _free_play(arcmin: float) -> str:
    """The backlash at zero torque in words: a negative one is an overlap of the two flanks."""
    if arcmin < 0.0:
        return (f"at zero torque the two flanks overlap by {-arcmin:.3g} arcmin (the teeth interfere at no load, "
                "see the notes: the gear is preloaded there, which this one-flank curve counts as rotation)")
    return f"the free play at zero torque is {arcmin:.3g} arcmin"


def _torsional_section(design, png: bytes | None = None) -> str:
    """The whole gear in torsion, in plain words, against the catalogue (docs/theory/torsion.md); then the
    ratcheting estimate and the transmission error when the scene ran them."""
    curve = getattr(design, "torsional", None)
    if curve is None:
        return _ratcheting_and_error_section(design)
    arcmin = 180 * 60 / np.pi
    k = curve.k_nm_per_rad["total"]
    cmp = curve.catalogue_comparison()
    compared = {} if cmp is None else cmp["compared"]
    names = {"K1_nm_per_rad": "K1, 0 … T1 (N·m/rad)", "K2_nm_per_rad": "K2, T1 … T2 (N·m/rad)",
             "K3_nm_per_rad": "K3, T2 … peak (N·m/rad)", "secant_T1_nm_per_rad": "secant T/φ at T1 (N·m/rad)",
             "secant_T2_nm_per_rad": "secant T/φ at T2 (N·m/rad)", "lost_motion_arcmin": "lost motion (arcmin)"}
    model = {"K1_nm_per_rad": k["positive"]["K1"], "K2_nm_per_rad": k["positive"]["K2"],
             "K3_nm_per_rad": k["positive"]["K3"], "secant_T1_nm_per_rad": k["positive"]["secant_T1"],
             "secant_T2_nm_per_rad": k["positive"]["secant_T2"],
             "lost_motion_arcmin": curve.lost_motion_rad["total"] * arcmin}
    rows = "".join(
        f"<tr><td class=text>{label}</td><td>{_quantity(model[key], key)}</td>"
        f"<td>{_quantity(compared[key]['catalogue'], key) if key in compared else '—'}</td>"
        f"<td>{_num(compared[key]['model_over_catalogue'], '.2f') if key in compared else '—'}</td></tr>"
        for key, label in names.items())
    c = curve.compliances_at_rated
    total = c["total_rad_per_nm"]
    parts = {p.name: p for p in curve.chain.parts}
    words = {"mesh": "the teeth, the rim and the CS ring's ovalisation in mesh (FEM influence coefficients, a free "
                     "thin CS ring, rigid balls)",
             "ball_hertz": "the wave-generator balls: Hertz contact at both races, iterated with the contact",
             "cup_wall": "cup wall in torsion (thin tube)", "cup_bottom": "cup bottom (diaphragm) twisted in its plane",
             "cs_body": "the CS body twisted outside the modelled sector"}
    comp_rows = "".join(
        f"<tr><td class=text>{html.escape(n[:-len('_rad_per_nm')].replace('_', ' '))}</td><td>{v * 1e6:.4g}</td>"
        f"<td>{v / total:.0%}</td><td class=text>"
        f"{html.escape(words.get(n[:-len('_rad_per_nm')], ''))}"
        f"{html.escape('; ' + parts[n[:-len('_rad_per_nm')]].formula) if n[:-len('_rad_per_nm')] in parts else ''}"
        f"</td></tr>"
        for n, v in c.items() if n != "total_rad_per_nm")
    estimates = [e for p in curve.chain.parts for e in p.estimates]
    if curve.chain.bearing is not None:
        estimates += list(curve.chain.bearing.estimates)
    estimates = list(dict.fromkeys(estimates))
    bp = curve.breakpoints_nm
    if cmp is None:
        against = ("<p>No catalogue table for this size is in the repository: T1 and T2 are "
                   f"{'estimates (0.2 and 0.75 of the rated torque)' if curve.breakpoints_source == 'estimate' else 'as given'}"
                   ", and nothing is compared.</p>")
    else:
        ratio = compared.get("secant_T2_nm_per_rad", {}).get("model_over_catalogue")
        verdict = "" if ratio is None else (
            f" At T2 this model is {'stiffer' if ratio > 1 else 'softer'} than the catalogue by a factor "
            f"{max(ratio, 1 / ratio):.2f} (secant stiffness).")
        against = (f"<p>Compared with {html.escape(str(cmp.get('source')))}."
                   f"{' ' + html.escape(cmp['note'][:1].upper() + cmp['note'][1:]) + '.' if cmp.get('note') else ''}{verdict}</p>")
    flagged = [f"{t:g}" for t, f in zip(curve.torque_nm, curve.flags) if f is not None]
    face = getattr(curve, "face", None)
    across = ""
    if face is not None:  # the curve across the face (the scene's face_slices)
        one = face["one_section"]
        ratios = one.get("model_over_catalogue") or {}
        mod = ("straight FS teeth" if face.get("taper_um_per_mm") is None else
               f"the FS teeth modified as made (taper {face['taper_um_per_mm']:.3g} µm/mm, "
               f"crowning {face['crowning_um']:.3g} µm"
               + (f", radial shift {face['shift_um_per_mm']:.4g} µm/mm" if face.get("shift_um_per_mm") else "") + ")")
        across = (f"<p>Across the face: the curve is solved as {face['slices']} axial slices sharing the rotation, "
                  f"nodes on both face ends, each with the 3D cup's coning (the CS cut at z = "
                  f"{face['design_section_z_mm']:g} mm) and {html.escape(mod)}; the slices are independent, the soft "
                  "bound (the face held straight gives the one-section curve). With one section, the load even "
                  f"across the face, K1, K2, K3 would be "
                  f"{', '.join(_quantity(one[n], '_nm_per_rad') for n in ('k1_nm_per_rad', 'k2_nm_per_rad', 'k3_nm_per_rad'))}"
                  f" N·m/rad and lost motion {one['lost_motion_arcmin']:.3g} arcmin"
                  + (f" (model / catalogue: K1 {ratios['K1_nm_per_rad']:.2f}, K2 {ratios['K2_nm_per_rad']:.2f})"
                     if "K1_nm_per_rad" in ratios and "K2_nm_per_rad" in ratios else "") + ".</p>")
    uri = _png_uri(png) if png is not None else None
    img = "" if uri is None else f'<img src="{uri}" alt="torsional curve">'
    return f"""<h2>The whole gear in torsion</h2>
<p>The wave generator is held and a torque turns the flexspline against the circular spline, in both
directions, at {len(curve.torque_nm)} torques up to ±{float(np.max(np.abs(curve.torque_nm))):g} N·m. The twist
adds up from the tooth mesh (both flanks solved, each for its own direction), the balls of the wave-generator
bearing, the cup wall and bottom, and the CS ring. The catalogue's stiffnesses are read off this curve the
catalogue's way: K1 = T1/φ(T1), K2 = (T2 − T1)/(φ(T2) − φ(T1)), K3 from T2 to the peak torque, with
T1 = {bp['T1']:g} N·m, T2 = {bp['T2']:g} N·m ({curve.breakpoints_source}), T3 = {bp['T3']:g} N·m. Lost motion is
the rotation between ±{curve.lost_motion_torque_nm:.3g} N·m (3 % of the rated torque); {_free_play(curve.backlash_rad * arcmin)}. No friction is modelled, so there is no hysteresis:
loading and unloading give one curve. In the other direction K1, K2, K3 are
{', '.join(_quantity(k['negative'][n], '_nm_per_rad') for n in ('K1', 'K2', 'K3'))} N·m/rad.</p>
{against}
{across}
<table><tr><th>whole gear</th><th>this model</th><th>catalogue</th><th>model / catalogue</th></tr>{rows}</table>
<p>Where the twist comes from at the rated torque ({float(design.gearset.torque.rated_nm):g} N·m):</p>
<table><tr><th>part</th><th>compliance (10⁻⁶ rad/N·m)</th><th>share</th><th>model</th></tr>{comp_rows}</table>
<p>Estimated inputs: {html.escape('; '.join(estimates)) or 'none'}. Left out: {html.escape('; '.join(curve.chain.left_out))}.
{'Torques beyond the modelled contact (flagged): ' + ', '.join(flagged) + ' N·m.' if flagged else ''}</p>
{img}
{_ratcheting_and_error_section(design)}"""


def _stress_section(design, png: bytes | None = None) -> str:
    res = design.stress
    from . import plot

    checks = "".join(
        f"<tr><td>{html.escape(c.name)}</td><td class=text>{html.escape(c.criterion)}</td><td>{c.torque_nm:g}</td>"
        f"<td>{_num(c.value, '.2f')}</td><td>{c.required:g}</td><td>{_verdict(c)}</td></tr>" for c in res.checks)
    per_torque = "".join(
        f"<tr><td>{t:g}</td><td>{f:.0f}</td><td>{r.assembly_stress_mpa:.1f}</td><td>{r.load_stress_mpa:.1f}</td>"
        f"<td>{r.total_stress_mpa:.1f}</td><td>{b.max_von_mises_mpa:.1f}</td><td>{float(b.tau_load_mpa[0]):.1f}</td>"
        f"<td>{d.shear_amplitude_mpa:.1f}</td><td>{d.mean_shear_mpa:.1f}</td></tr>"
        for t, f, r, b, d in zip(res.torques_nm, res.tangential_force_n, res.tooth_ring, res.cup_bottom, res.diaphragm))
    uri = _png_uri(png) if png is not None else figure_png(plot.stress_figure(res), dpi=100)
    g = design.gearset
    cup = g.cup
    unchecked = [c.name for c in res.checks if c.passed is None]  # no material limits: not a pass
    overall = ('<span class="fail">a check FAILS</span>' if not res.passed else
               f'<span class="skip">INCOMPLETE: NOT CHECKED {html.escape(", ".join(unchecked))} (no material '
               'limits)</span>' if unchecked else '<span class="pass">every check passes</span>')
    return f"""<h2>Flexspline stresses and safety factors</h2>
<p>Overall: {overall}. Inputs: rim δ = {g.gear.rim_thickness_mm:g} mm, r_m = {g.gear.neutral_radius_mm:.4g} mm,
face width {cup.face_width_mm:g} mm, root fillet {cup.root_fillet_radius_mm:g} mm (root thickness s_f =
{res.root_thickness_mm:.4f} mm, measured on the tooth), cup length {cup.length_mm:g} mm, bottom thickness
{cup.bottom_thickness_mm:g} mm, boss radius {cup.boss_radius_mm:g} mm; tangential tooth forces from the
{html.escape(res.force_source)}.</p>
<table><tr><th>check</th><th>criterion</th><th>torque (N·m)</th><th>safety factor</th><th>required</th><th></th></tr>
{checks}</table>
<table><tr><th>torque (N·m)</th><th>F_t max tooth (N)</th><th>tooth ring σ_ass</th><th>σ_load</th><th>σ_total</th>
<th>cup bottom von Mises max</th><th>τ_load at the boss</th><th>diaphragm τ_a</th><th>diaphragm τ_m</th></tr>
{per_torque}</table><p>Stresses in MPa.</p>
<img src="{uri}" alt="stresses">"""


def design_report_html(design, images: dict | None = None) -> str:
    """The design report of this gear: the design sheet, then how it was computed — stages,
    flank fit, the whole gear in torsion, the loaded contact (the mesh alone), the face,
    stresses and safety factors (pass/fail against the gear set's material limits); one HTML
    page. (The published examples and the project's research are in the docs' validation
    section, not in a gear's report.) ``images``: PNG bytes already drawn (``"contact"``,
    ``"stress"``, ``"fit_profile"``, ``"fit_error"``; see :func:`png_jobs`), embedded as they
    are; the others are drawn. It may also hold the HTML piece of :func:`html_jobs` made
    already (``"cs_figure"``)."""
    images = images or {}
    g = design.gearset
    prof = design.profile
    stages = "".join(
        f"<tr><td>{html.escape(s.stage)}</td><td class=text>{html.escape(s.tier)}</td><td>{s.time_s * 1e3:.1f}</td>"
        f"<td>{_num(s.error_estimate, '.3g')}</td><td class=text>{html.escape(s.error_measure)}</td></tr>"
        for s in design.stages)
    fit = ""
    if prof is not None:
        fit = f"""<h2>Flank fit</h2>
<p>CS flank: arc–line–arc, <b>{html.escape(prof.method)}</b> fit, largest deviation from the envelope
{prof.max_error_mm * 1e3:.3f} µm{'' if prof.max_backlash_mm is None else f', largest backlash {prof.max_backlash_mm * 1e3:.3f} µm'};
checked against the FS tooth at {prof.positions} positions: smallest clearance {html.escape(format_clearance(prof.clearance.min_mm))}.
CS tip circle r = {design.form.tip_radius_mm:.4f} mm, root circle r = {design.form.root_radius_mm:.4f} mm.
The full fit-error report is <code>fit_report.html</code>; the CAD files are the DXFs beside this page.</p>
<img src="{_image(images, "fit_profile", profile_png, *_profile_args(design, prof.fits))}" alt="fitted profile">
<img src="{_image(images, "fit_error", error_png, prof.fits)}" alt="fit error along the flank">"""
    warnings = "".join(f"<li>{html.escape(w)}</li>" for w in design.warnings)
    stress = "" if design.stress is None else _stress_section(design, images.get("stress"))
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Design report — {html.escape(g.name)}</title>{_STYLE}</head><body>
{sheet_html(design, images.get("cs_figure") or figure_html(design), interference_tol_mm=interference_tol_mm(design.scene))}
<h2 style="margin-top:1.5em">How it was computed</h2>
<p>Scene <b>{html.escape(design.scene.name)}</b>: each stage, the model it used, its time and its own error estimate.</p>
<table><tr><th>stage</th><th>tier</th><th>time (ms)</th><th>error estimate</th><th>error measure</th></tr>{stages}</table>
{fit}
{_torsional_section(design, images.get("torsional"))}
{_contact_section(design, images.get("contact"))}
{_face_section(design, images)}
{stress}
<h2>Notes</h2><ul>{warnings}</ul>
</body></html>
"""


# ------------------------------------------------------------------------------------ rendering

def _envelope_png(env, tooth, motion, title: str) -> bytes:
    from .plot import envelope_png

    return envelope_png(env, tooth, motion, title=title)


def _catalogue_size(gearset) -> int | None:
    from ..contact.chain import catalogue_size

    return catalogue_size(gearset)


def _contact_png(contact, title: str, ratio: float | None = None, size: int | None = None) -> bytes:
    from .plot import contact_figure, png_bytes

    return png_bytes(contact_figure(contact, title=title, ratio=ratio, size=size), 130)


def _torsional_png(curve, title: str, ratio: float | None = None) -> bytes:
    from .plot import png_bytes, torsional_figure

    return png_bytes(torsional_figure(curve, title=title, ratio=ratio), 110)


def _stress_png(stress, title: str) -> bytes:
    from .plot import png_bytes, stress_figure

    return png_bytes(stress_figure(stress, title=title), 120)


def png_jobs(design) -> dict[str, tuple[Callable[..., bytes], tuple]]:
    """Every PNG a design's files hold, by name, as ``(function, arguments)``: the function is
    module level (it pickles), takes the result pieces it draws and returns PNG bytes.

    ``envelope``, ``contact``, ``stress`` are the files ``NAME.png`` (contact and stress when the
    design has them; ``stress`` is also embedded in ``report.html``, ``contact`` too);
    ``fit_error``, ``fit_profile``, ``fit_clearance``, ``deformation_samples`` and
    ``deformation_residuals`` (with a FEM rim) are embedded in ``fit_report.html``, the first
    two in ``report.html`` as well. The slowest first, for a pool."""
    g = design.gearset
    jobs: dict[str, tuple[Callable[..., bytes], tuple]] = {}
    if design.stress is not None:
        torques = ", ".join(f"{t:g}" for t in design.stress.torques_nm)
        jobs["stress"] = (_stress_png, (design.stress, f"{g.name}: flexspline stresses at {torques} N·m"))
    if design.contact is not None:
        c = design.contact
        jobs["contact"] = (_contact_png, (c, f"{g.name}: loaded contact, {c.zones} zones, "
                                             f"{c.points.count} candidate points per zone", g.ratio,
                                             _catalogue_size(g)))
    if getattr(design, "torsional", None) is not None:
        jobs["torsional"] = (_torsional_png, (design.torsional, f"{g.name}: the whole gear in torsion, wave "
                                                                "generator locked", g.ratio))
    title = (f"{g.name}: m {g.gear.module_mm:g} mm, z {g.gear.flexspline_teeth}/{g.gear.circular_spline_teeth}, "
             f"ω* {g.wave_generator.deflection_coefficient:g}, scene {design.scene.name}")
    from .face import face_png_job

    if (face_job := face_png_job(design)) is not None:
        jobs["face"] = face_job
    jobs["envelope"] = (_envelope_png, (design.envelope, design.tooth, design.motion, title))
    prof = design.profile
    if prof is not None:
        jobs["fit_profile"] = (profile_png, _profile_args(design, prof.fits))
        jobs["fit_error"] = (error_png, (prof.fits,))
        jobs["fit_clearance"] = (clearance_png, (prof.clearance,))
    rim = getattr(design, "rim", None)
    if rim is not None and rim.fem is not None:
        jobs["deformation_residuals"] = (deformation_residuals_png, (rim,))
        jobs["deformation_samples"] = (deformation_samples_png, (rim,))
    return jobs


def _workers_ready() -> None:
    """Nothing: a first job that makes the figure workers start while the stages run."""


#: A first job for the figure workers, handed over before the design has its profile, so that
#: they fork (and import what they draw with) while the stages run.
WARM_UP_JOB = {"workers_ready": (_workers_ready, ())}

#: The HTML pieces of :func:`report_pieces` (not pictures: made in every run).
_HTML_PIECES = ("cs_figure",)


class NoFigures(dict):
    """``images`` for reports without the PNG figures (a scene with ``figures = "none"``): the
    HTML pieces made already, and an empty PNG for every picture, whose ``<img>`` tag
    :func:`without_figures` turns into a line saying how to draw it."""

    def __bool__(self) -> bool:
        return True

    def get(self, key, default=None):
        if key in self or key in _HTML_PIECES:
            return super().get(key, default)
        return b""


def without_figures(page: str, scene: str) -> str:
    """``page`` (made with :class:`NoFigures`) with each picture's empty tag replaced by a line
    saying that this run drew no figures and how to draw them."""
    import re

    how = (f"not drawn: the <b>{html.escape(scene)}</b> scene draws no figures (<code>figures = \"none\"</code>); "
           f"<code>profilegen design --scene {html.escape(scene)} --figures</code> draws them")
    return re.sub(r'<img src="data:image/png;base64," alt="([^"]*)">',
                  lambda m: f'<p class="skip">Figure ({m.group(1)}) {how}.</p>', page)


def html_jobs(design) -> dict[str, tuple[Callable[..., str], tuple]]:
    """The piece of ``report.html`` that takes time, as a job for :func:`rendering` beside the PNGs:
    the zoomable CS figure (plotly's first page ~0.3 s). Drawn in the figure workers it leaves the
    parent's path; :func:`design_report_html` takes it from its ``images``. None without the
    stresses (no report.html then); :func:`report_pieces` makes it for a design that has its
    profile."""
    return report_pieces(design) if design.stress is not None else {}


def report_pieces(design) -> dict[str, tuple[Callable[..., str], tuple]]:
    """:func:`html_jobs` for a design whose stresses are still to come."""
    from dataclasses import replace

    # the figure reads the envelope, tooth, motion and fitted profile: the rest is not pickled to the worker;
    # of the profile not the whole CS outline nor its corners (z2 spaces of small elements: ~45 ms to
    # pickle here, on the stages' path, and ~35 ms to unpickle there)
    prof = design.profile
    if prof is not None:
        prof = replace(prof, outline=None, corners=None)
    slim = replace(design, form=None, rim=None, contact=None, stress=None, profile=prof)
    return {"cs_figure": (figure_html, (slim,))}


#: Environment variable: how many worker processes draw the figures (0: none, draw in the
#: calling process); unset: see :func:`rendering`.
WORKERS_ENV = "PROFILEGEN_FIGURE_WORKERS"
_STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def _default_workers() -> int:
    text = os.environ.get(WORKERS_ENV)
    if text is not None:
        try:
            n = int(text)
            if 0 <= n <= 64:
                return n
        except ValueError:
            pass
        log.warning("%s must be an integer in [0, 64], got %.20r; using the default", WORKERS_ENV, text)
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if cpus < 2:
        return 0
    # Two workers need a CPU beside this process's own: on a busy machine the second one's
    # matplotlib import (~0.5 s CPU) costs more than it brings; one worker costs nothing extra.
    return 2 if _busy_cpus() < cpus - 0.5 else 1


def _busy_cpus() -> float:
    """How many CPUs other work keeps busy now: the tasks running or ready to run besides this
    one (Linux: /proc/loadavg's fourth field), else the 1-minute load average. The average lags
    by a minute: after a run of profilegen design (two CPUs for ~6 s) it stays above 1.5 for
    the next run, which then took one worker on an otherwise idle machine (the end-to-end
    benchmark's back-to-back runs: 8.1-8.7 s with one worker against ~6.1 s with two)."""
    try:
        with open("/proc/loadavg", encoding="ascii") as f:
            return max(int(f.read().split()[3].split("/")[0]) - 1, 0)
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.getloadavg()[0]
    except (AttributeError, OSError):
        return 0.0


@contextlib.contextmanager
def _signals_blocked() -> Iterator[None]:
    """SIGINT and SIGTERM blocked in this thread: processes forked here start with them blocked
    (the worker unblocks them once its handlers are set), and a clean-up is not cut short."""
    masked = hasattr(signal, "pthread_sigmask")
    old = signal.pthread_sigmask(signal.SIG_BLOCK, _STOP_SIGNALS) if masked else None
    try:
        yield
    finally:
        if old is not None:  # (masked)
            signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _init_worker(parent: int, matplotlib: bool = True) -> None:
    """A figure worker: ignores SIGINT (a Ctrl-C reaches the whole process group; the parent
    decides and ends the workers), dies on SIGTERM and with its parent, and imports matplotlib
    while the parent writes its other files (unless ``matplotlib`` is false: a run that draws
    no PNG figures)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, _STOP_SIGNALS)
    _die_with(parent)
    if not matplotlib:
        return
    from matplotlib import figure  # noqa: F401
    from matplotlib.backends import backend_agg  # noqa: F401


#: What the figure server imports before it forks its workers (:func:`_pool`): matplotlib, and the
#: modules the jobs' pickles name (the design's pieces), which each worker would otherwise import to
#: unpickle its first job.
PRELOAD = ("matplotlib.figure", "matplotlib.backends.backend_agg", "profilegen.output.plot", "profilegen.output.report",
           "profilegen.profile.arcfit", "profilegen.profile.rootfillet", "profilegen.rim.stage", "profilegen.contact.analysis",
           "profilegen.contact.chain", "profilegen.stress.stage",
           "ezdxf", "profilegen.output.drawing", "profilegen.output.flexspline")  # the files of files.file_jobs


def _pool(workers: int, matplotlib: bool = True) -> ServerPool | ProcessPoolExecutor:
    """``workers`` figure workers (ValueError where fork is not available): with ``matplotlib`` and two
    or more, a :class:`~profilegen.output.forkserver.ServerPool` — one server process imports
    matplotlib and :data:`PRELOAD` once and forks the workers from itself; else a fork-based
    process pool whose workers import matplotlib each."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    if matplotlib and workers >= 2:  # one worker: forked from here when the profile comes, nothing to share
        from .forkserver import ServerPool

        return ServerPool(workers, preload=PRELOAD)
    ctx = multiprocessing.get_context("fork")  # a fork shares the loaded modules; spawn would re-import all
    return ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker,
                               initargs=(os.getpid(), matplotlib))


class FigureWorkers:
    """Worker processes that draw a design's figures while the caller goes on.

    ``submit(jobs)`` hands jobs over as soon as their inputs exist — the CLI opens the workers
    before the stages run and submits the profile's figures while the contact and stresses are
    computed (:func:`profilegen.pipeline.design.design`'s ``on_profile``), so their matplotlib import
    and most of the drawing overlap the stages. A name is drawn once: a later ``submit`` of a
    name already given is ignored (the jobs of one design run draw the same pieces, so the bytes
    are the same). ``collect(jobs, steal=())`` submits what is new, waits for the named jobs and
    returns their bytes by name; it draws here every job that no worker has (no pool, fewer than
    one worker) or that a worker failed, and first takes back the ``steal`` jobs no worker has
    started (pieces that need no matplotlib: the caller would otherwise only wait). ``close()``
    ends the workers — at once with ``error=True``. A context manager: leaving the block by an
    exception (a Ctrl-C included) ends them at once; a run killed outright takes them with it
    (Linux: PR_SET_PDEATHSIG).

    ``workers``: see :func:`rendering`; the pool forks all its workers at the first ``submit``.
    ``matplotlib``: the workers import it as they start (false: a run without PNG figures)."""

    def __init__(self, workers: int | None = None, *, matplotlib: bool = True):
        self.workers = _default_workers() if workers is None else int(workers)
        self._matplotlib = bool(matplotlib)
        self._executor: ServerPool | ProcessPoolExecutor | None = None
        self._futures: dict[str, Future] = {}
        self._jobs: dict[str, tuple[Callable, tuple]] = {}
        self._no_pool = self.workers < 1

    def __enter__(self) -> "FigureWorkers":
        return self

    def __exit__(self, kind, value, traceback) -> None:
        self.close(error=kind is not None)

    def submit(self, jobs: dict[str, tuple[Callable, tuple]]) -> None:
        for name, job in jobs.items():
            if name in self._jobs:
                continue
            self._jobs[name] = job
            future = self._submit(job)
            if future is not None:
                self._futures[name] = future

    def has(self, name: str) -> bool:
        """Whether a job of this name has been handed over (to a worker, or to be made here)."""
        return name in self._jobs

    def _submit(self, job: tuple[Callable, tuple]):
        if self._no_pool:
            return None
        func, args = job
        try:
            with _signals_blocked():  # the workers fork here and start with SIGINT/SIGTERM blocked
                if self._executor is None:
                    self._executor = _pool(self.workers, self._matplotlib)
                return self._executor.submit(func, *args)
        except Exception as exc:  # noqa: BLE001 - no fork, a daemonic process, no resources, a broken pool: draw here
            log.info("figures drawn in this process: no worker pool (%s: %s)", type(exc).__name__, exc)
            self._no_pool = True
            return None

    def collect(self, jobs: dict[str, tuple[Callable, tuple]], steal: tuple[str, ...] = ()) -> dict[str, Any]:
        self.submit(jobs)
        out = {}
        for name in steal:
            fut = self._futures.get(name)
            if name in jobs and fut is not None and fut.cancel():  # not started by a worker: made here
                func, args = self._jobs[name]
                out[name] = func(*args)
        for name in jobs:
            if name in out:
                continue
            fut = self._futures.get(name)
            if fut is not None:
                try:
                    out[name] = fut.result()
                    continue
                except Exception as exc:  # noqa: BLE001 - a dead worker or a failed figure: draw it here
                    log.warning("figure %s: the worker failed (%s: %s); drawing it in this process",
                                name, type(exc).__name__, exc)
            func, args = self._jobs[name]
            out[name] = func(*args)
        return {name: out[name] for name in jobs}

    def close(self, *, error: bool = False) -> None:
        executor, self._executor, self._no_pool = self._executor, None, True
        if executor is None:
            return
        with _signals_blocked():
            if not error:
                executor.shutdown(wait=True, cancel_futures=True)
            elif hasattr(executor, "stop"):  # a forkserver.ServerPool
                executor.stop()
            else:
                stop_pool(executor, what="figures")


@contextlib.contextmanager
def rendering(jobs: dict[str, tuple[Callable[..., bytes], tuple]], *,
              workers: int | None = None, steal: tuple[str, ...] = ()) -> Iterator[Callable[[], dict[str, bytes]]]:
    """Draw ``jobs`` (see :func:`png_jobs`) while the block runs; yields ``collect()``, which
    waits for them and returns the PNG bytes by name (:class:`FigureWorkers` takes jobs handed
    over in steps).

    ``workers`` ≥ 1 draws them in that many forked processes (no more than there are jobs),
    which start at once and import matplotlib while the caller writes its other files; they get
    the result pieces pickled and send PNG bytes back, and write nothing. The default is the
    environment variable ``PROFILEGEN_FIGURE_WORKERS`` if set, else none on one CPU, two where
    the tasks running now leave a CPU free beside this process (:func:`_busy_cpus`), one
    otherwise. Where no pool can start (no fork, a daemonic process, no resources), with ``workers`` < 1, and for
    any figure whose worker failed, ``collect()`` draws in this process — the same bytes either
    way. Leaving the block by an exception (a Ctrl-C included) ends the workers at once.
    ``steal``: names of jobs that need no matplotlib (:func:`html_jobs`): ``collect()`` first
    takes back those no worker has started and makes them here, while the workers draw."""
    n = _default_workers() if workers is None else int(workers)
    with FigureWorkers(min(n, len(jobs))) as figures:
        figures.submit(jobs)
        yield lambda: figures.collect(jobs, steal)
