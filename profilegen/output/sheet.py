"""The design sheet: the first screen of ``report.html`` — the verdict and the numbers to cut.

``sheet_html(design, figure_html="")`` returns an HTML fragment (its own ``<style>`` included)
that fits one 1366×768 screen: every check with its result and margin, the sizes a machinist
needs (tip and root diameters, the flank's arc–line–arc with centres, fillet, backlash,
smallest clearance) and what a designer asks next (stiffness, safety factors), each with its
unit. ``figure_html`` (see :mod:`profilegen.output.interactive`) is placed beside the numbers.

The number formats are here too, so the report, the notebook view and the command line say the
same thing: :func:`format_um` (a length in µm with a sane number of digits) and
:func:`format_clearance` ("touching (< 1 nm)" below resolution, "cuts in by …" when negative).

Shapes: an arc of the CS flank is *convex* when its centre lies in the CS tooth (material) and
*concave* when its centre lies in the tooth space; the fit's signed radius (``r1_mm`` < 0: the
arc turns right along the flank from the tip) says the same thing only together with the side
the space is on, so the sheet states the shape in words.
"""

from __future__ import annotations

import html
import math
from dataclasses import dataclass, replace

import numpy as np

from ..contact.analysis import ARCMIN_PER_RAD

__all__ = ["Check", "FlankElement", "checks", "flank_elements", "format_clearance", "format_um", "sheet_html",
           "SHEET_STYLE", "RESOLUTION_MM"]

#: Below this a length is "below resolution" on the sheet (mm): 1 nm, a thousandth of what wire EDM holds.
RESOLUTION_MM = 1e-6


def format_um(length_mm: float | None, *, digits: int = 3) -> str:
    """A length given in mm, written in µm with ``digits`` significant digits (at most 3 decimals):
    ``format_um(0.0035071)`` → ``'3.51 µm'``; below 1 nm → ``'< 0.001 µm'``.

    >>> format_um(0.0035071), format_um(0.000187), format_um(2.2e-16), format_um(-0.012345)
    ('3.51 µm', '0.187 µm', '< 0.001 µm', '−12.3 µm')
    """
    if length_mm is None or not math.isfinite(length_mm):
        return "—"
    um = float(length_mm) * 1e3
    if abs(um) < RESOLUTION_MM * 1e3:
        return "< 0.001 µm"
    decimals = min(3, max(0, digits - 1 - int(math.floor(math.log10(abs(um))))))
    return f"{um:.{decimals}f} µm".replace("-", "\u2212")


def format_clearance(clearance_mm: float | None, *, tol_mm: float | None = None) -> str:
    """The smallest clearance between two outlines (mm) in words and µm.

    ``|c|`` below 1 nm → ``'touching (< 1 nm)'``; a positive gap → ``'0.187 µm'``; a negative one
    → ``'cuts in by 0.012 µm'`` (``tol_mm``: the verdict's tolerance; within it the text says so).

    >>> format_clearance(2.220446049250313e-16), format_clearance(1.87e-4), format_clearance(-3e-6, tol_mm=1e-5)
    ('touching (< 1 nm)', '0.187 µm', 'touching (−0.003 µm, within the 0.01 µm tolerance)')
    >>> format_clearance(-2.5e-4)
    'cuts in by 0.250 µm'
    """
    if clearance_mm is None or not math.isfinite(clearance_mm):
        return "—"
    c = float(clearance_mm)
    if abs(c) < RESOLUTION_MM:
        return "touching (< 1 nm)"
    if c > 0:
        return format_um(c)
    if tol_mm is not None and -c <= tol_mm:
        return f"touching ({format_um(c)}, within the {tol_mm * 1e3:g} µm tolerance)"
    return f"cuts in by {format_um(-c)}"


@dataclass(frozen=True, slots=True)
class Check:
    """One line of the verdict: what was checked, at which load, the value against the
    requirement, the margin, and ``passed`` (None: NOT CHECKED, the reason in ``margin``)."""

    name: str
    where: str
    value: str
    required: str
    margin: str
    passed: bool | None


def checks(design, interference_tol_mm: float) -> list[Check]:
    """Every check of ``design``'s verdict (:attr:`profilegen.pipeline.design.Design.verdict`, its
    ``checks``), each with its value, requirement and margin as the sheet shows them; a NOT
    CHECKED one (``passed`` None) has its reason in the margin column.
    ``interference_tol_mm``: the verdict's (:func:`profilegen.pipeline.design.interference_tol_mm`;
    passed in, so this module does not import the pipeline that shows it in notebooks)."""
    return [_check_row(c, float(interference_tol_mm)) for c in design.verdict.checks]


def _percent(x: float) -> str:
    return f"{100.0 * x:+.0f} %".replace("-", "\u2212")


def _check_row(c, tol: float) -> Check:
    """One :class:`Check` from a :class:`profilegen.pipeline.design.VerdictCheck` (by its ``kind``)."""
    ge = c.sense == ">="
    if c.kind == "clearance":
        required = f"≥ −{tol * 1e3:g} µm" if c.required is None or c.required <= -tol else f"≥ {format_um(c.required)}"
    elif c.kind in ("face", "backlash"):
        required = "—" if c.required is None else f"≤ {format_um(c.required)}"
    elif c.kind == "capacity":
        required = "inside"
    elif c.required is None:
        required = "—"
    else:
        unit = {"arcmin": " arcmin", "N·m/rad": " N·m/rad"}.get(c.unit, "")
        required = f"{'≥' if ge else '≤'} {c.required:g}{unit}" + ("× momentary" if c.kind == "ratcheting"
                                                                    and "momentary" in c.where else "")
    where = c.where.replace("momentary ", "") if c.kind == "ratcheting" else c.where  # "≥ 1× momentary" says it
    if c.passed is None:
        return Check(c.name, where, "—", required, html.escape(c.text), None)
    if c.kind == "clearance":
        value, margin = format_clearance(c.value, tol_mm=tol), format_um(c.value - c.required)
    elif c.kind in ("face", "backlash"):
        value, margin = format_um(c.value), format_um(c.required - c.value)
    elif c.kind == "capacity":
        value, margin = f"{c.value:.0f} teeth/zone", "—" if c.passed else "beyond the searched teeth"
    else:
        digits = {"arcmin": ".3f", "N·m/rad": ".4g"}.get(c.unit, ".2f")
        value = f"{c.value:{digits}}" + ({"arcmin": " arcmin", "N·m/rad": " N·m/rad"}.get(c.unit, ""))
        margin = _percent(c.value / c.required - 1.0 if ge else c.required / c.value - 1.0)
        if c.kind == "ratcheting" and c.text:  # the bound and the estimate it comes from
            value += f" ({c.text.split(' (')[0]})"
    return Check(c.name, where, value, required, margin, bool(c.passed))


@dataclass(frozen=True, slots=True)
class FlankElement:
    """One element of the fitted CS flank, from the CS tip toward the root: ``kind`` 'arc' or
    'line'; arcs carry ``radius_mm`` (> 0), ``centre_mm`` and ``shape`` ('convex': centre in the
    CS tooth; 'concave': centre in the tooth space); lines their ``start_mm``/``end_mm``."""

    label: str
    kind: str
    length_mm: float
    radius_mm: float | None = None
    centre_mm: tuple[float, float] | None = None
    shape: str = ""
    start_mm: tuple[float, float] | None = None
    end_mm: tuple[float, float] | None = None


def flank_elements(fit) -> list[FlankElement]:
    """The elements of a fitted flank (:class:`profilegen.profile.arcfit.ProfileFit`), tip first, named
    R1, line, R2 (an element shorter than the fit's minimum is absent from the chain).

    An arc turning toward the space side (its sweep's sign equal to the space side's: + for
    'left' of the direction of travel) has its centre in the space: concave."""
    from ..geometry.contour import Arc

    side = 1.0 if fit.space_side == "left" else -1.0
    out, arcs = [], 0
    for el in fit.chain.elements:
        if isinstance(el, Arc):
            arcs += 1
            concave = math.copysign(1.0, el.sweep) == side
            out.append(FlankElement(f"R{arcs}", "arc", float(el.length), radius_mm=float(el.radius),
                                    centre_mm=(float(el.centre[0]), float(el.centre[1])),
                                    shape="concave" if concave else "convex"))
        else:
            out.append(FlankElement("line", "line", float(el.length),
                                    start_mm=(float(el.start[0]), float(el.start[1])),
                                    end_mm=(float(el.end[0]), float(el.end[1]))))
    if arcs == 1 and out[0].kind == "line":  # the tip arc dropped out: the one arc left is R2
        out[-1] = replace(out[-1], label="R2")
    return out


def _xy(p) -> str:
    return f"({p[0]:.4f}, {p[1]:.4f})".replace("-", "\u2212")


def _row(label: str, value: str, note: str = "") -> str:
    return f"<tr><th>{label}</th><td>{value}</td><td class=note>{note}</td></tr>"


def _badge(passed: bool | None) -> str:
    if passed is None:
        return '<span class="skip">NOT CHECKED</span>'
    return '<span class="pass">pass</span>' if passed else '<span class="fail">FAIL</span>'


def _est(design, key: str, value) -> str:
    """The number's measured distance to the next scene's (:mod:`profilegen.pipeline.scene_estimates`), a
    small grey '±…' beside it; 'not estimated' with the reason as its tooltip; '' in verify."""
    from ..pipeline import scene_estimates as se

    text = se.note(design.scene, key, value, design.gearset.gear.module_mm)
    if not text:
        return ""
    est = se.estimate_for(design.scene, key)
    tip = est.reason if isinstance(est, se.NotEstimated) else (
        f"{se.NUMBERS[key][0]}: measured distance to the {se.NEXT_SCENE[design.scene.name]} scene "
        f"({se.SAFETY_FACTOR:g}× the largest over {se.MEASURED['sets']} sets)")
    return f' <span class=est title="{html.escape(tip)}">{html.escape(text)}</span>'


def _geometry_rows(design) -> str:
    g, form, tooth = design.gearset, design.form, design.tooth
    fs_tip, fs_root = 2 * (tooth.neutral_radius_mm + tooth.addendum_y_mm), 2 * (tooth.neutral_radius_mm + tooth.dedendum_y_mm)
    rows = [
        _row("module, teeth", f"{g.gear.module_mm:g} mm, {g.gear.flexspline_teeth} FS / {g.gear.circular_spline_teeth} CS"),
        _row("CS tip Ø", f"{2 * form.tip_radius_mm:.4f} mm" + _est(design, "cs_tip_diameter_mm", 2 * form.tip_radius_mm),
             "inner (tooth tips)"),
        _row("CS root Ø", f"{2 * form.root_radius_mm:.4f} mm" + _est(design, "cs_root_diameter_mm", 2 * form.root_radius_mm),
             "outer (tooth roots)"),
        _row("FS tip Ø", f"{fs_tip:.4f} mm" + _est(design, "fs_tip_diameter_mm", fs_tip), "undeformed"),
        _row("FS root Ø", f"{fs_root:.4f} mm" + _est(design, "fs_root_diameter_mm", fs_root), "undeformed"),
    ]
    prof = design.profile
    if prof is None:
        rows.append(_row("CS flank", "not fitted", "this scene stops at the envelope"))
        return "".join(rows)
    fits = [f for f in prof.cad_fits if f is not None]
    for b, fit in enumerate(fits):
        head = f"branch {b + 1} " if len(fits) > 1 else ""
        for el in flank_elements(fit):
            e = (lambda key, value: _est(design, key, value)) if b == 0 else (lambda key, value: "")  # measured: branch 1
            if el.kind == "arc":
                k = el.label.lower()
                rows.append(_row(f"{head}{el.label}", f"{el.radius_mm:.4f} mm <b>{el.shape}</b>" + e(f"{k}_radius_mm", el.radius_mm),
                                 f"centre {_xy(el.centre_mm)}" + e(f"{k}_centre_mm", el.centre_mm)))
            else:
                rows.append(_row(f"{head}line", f"{el.length_mm:.4f} mm long" + e("line_length_mm", el.length_mm),
                                 f"{_xy(el.start_mm)} → {_xy(el.end_mm)}" + e("line_end_mm", el.end_mm)))
    fillets = () if getattr(prof, "corners", None) is None else prof.corners.fillets
    if not fillets:
        rows.append(_row("CS root fillet", "none (sharp corner)", "flank meets the root by a straight run"))
    for f in fillets:  # the right-hand ones; the left are their mirror images
        if f.centre_mm[0] < 0:
            continue
        label = "CS root fillet" if f.kind == "inside" else f"CS {f.where.split()[0]} round"
        key = "root_fillet" if f.kind == "inside" else "tip_round"
        why = (f"wire radius + spark gap, {html.escape(format_um(f.clearance_mm))} clear of the FS tooth path"
               if f.kind == "inside" and f.clearance_mm is not None else
               "wire radius + spark gap" if f.kind == "inside" else "convex corner, rounded for a G1 outline")
        centre_est = _est(design, f"{key}_centre_mm", f.centre_mm)  # beside the radius: the note wraps
        rows.append(_row(label, f"{f.radius_mm:.4f} mm" + _est(design, f"{key}_radius_mm", f.radius_mm)
                         + (centre_est.replace(">", ">centre ", 1) if centre_est else ""),
                         f"centre {_xy(f.centre_mm)} (left: mirrored); {why}"))

    face = getattr(design, "face", None)
    if face is None:
        rows.append(_row("design section, FS taper", "<b>not decided</b>",
                         "this scene has no face stage"))
    else:
        mod = face.modification
        rows.append(_row("CS design section", f"z = {face.design_section_z_mm:g} mm"
                         + _est(design, "design_section_z_mm", face.design_section_z_mm), f"from the cup bottom ({face.design_choice})"))
        if mod is not None:  # a short note: a wrapped one pushed the clearance row below the first screen
            ds = [float(v) * 1e3 for v in mod.thickness_change_mm]
            rows.append(_row("FS tooth taper", f"<b>{mod.taper_mm_per_mm * 1e3:.4g} µm/mm</b>"
                             + _est(design, "fs_taper_um_per_mm", mod.taper_mm_per_mm * 1e3),
                             f"tooth thickness on the pitch line, toward the open end, 0 at the design section "
                             f"({min(ds):.3g} … {max(ds):.3g} µm over the face)"))
            if abs(mod.crowning_mm) >= 1e-9:
                rows.append(_row("FS crowning", f"{mod.crowning_mm * 1e3:.4g} µm" + _est(design, "fs_crowning_um", mod.crowning_mm * 1e3),
                                 "thinner at both face ends"))
            shift = float(getattr(mod, "shift_mm_per_mm", 0.0))
            if abs(shift) >= 1e-9:
                dy = [float(v) * 1e3 for v in mod.radial_shift_mm]
                rows.append(_row("FS radial shift", f"<b>{shift * 1e3:.4g} µm/mm</b>",
                                 f"the whole tooth (tip and root circles) outward, toward the open end, 0 at the design "
                                 f"section ({min(dy):.3g} … {max(dy):.3g} µm over the face)"))
    bl = prof.max_backlash_mm
    rows.append(_row("backlash (largest)", "—" if bl is None else html.escape(format_um(bl)) + _est(design, "backlash_mm", bl),
                     "normal gap the fit leaves to the exact flank" if bl is not None
                     else f"{html.escape(prof.method)} fit: no one-sided backlash"))
    rows.append(_row("fit deviation (largest)", html.escape(format_um(prof.max_error_mm))
                     + _est(design, "fit_deviation_mm", prof.max_error_mm), "from the exact (envelope) flank"))
    rows.append(_row("smallest clearance", html.escape(format_clearance(prof.clearance.min_mm))
                     + _est(design, "min_clearance_mm", prof.clearance.min_mm),
                     f"fitted CS ↔ FS tooth at φ = {math.degrees(prof.clearance.at_phi):.2f}°"))
    return "".join(rows)


def _stiffness_scope(design) -> str:
    curve = getattr(design, "torsional", None)
    if curve is not None:
        face = getattr(curve, "face", None)
        across = "" if face is None else f", {face['slices']} face slices"
        return f"secant; mesh, balls, cup and CS body{across}, wave generator locked"
    return "mesh only: no bearing, cam or cup wind-up"


def _load_rows(design) -> str:
    rows = []
    c = design.contact
    if c is None:
        rows.append(_row("stiffness", "not computed", "this scene runs no loaded contact"))
    else:
        curve = getattr(design, "torsional", None)
        for t, case, k in zip(("rated", "peak", "momentary"), c.cases, np.asarray(c.secant_stiffness_nm_per_rad, dtype=float)):
            if curve is not None and np.any(curve.torque_nm == case.torque_nm):
                # the whole gear's secant T / (φ(T) − φ at first contact), the mesh's beside it
                rot = curve.rotation_at(case.torque_nm)
                whole = case.torque_nm / (rot - curve.first_contact_rad["positive"])
                rows.append(_row(f"stiffness at {case.torque_nm:g} N·m",
                                 f"{whole / 1e3:,.0f} kN·m/rad".replace(",", "\u2009") + _est(design, f"k_whole_{t}_nm_per_rad", whole),
                                 f"{rot * ARCMIN_PER_RAD:.2f} arcmin; mesh only "
                                 + f"{k / 1e3:,.0f}".replace(",", "\u2009") + " kN·m/rad"))
                continue
            rows.append(_row(f"stiffness at {case.torque_nm:g} N·m",
                             f"{k / 1e3:,.0f} kN·m/rad".replace(",", "\u2009") + _est(design, f"k_mesh_{t}_nm_per_rad", k),
                             f"{k / ARCMIN_PER_RAD:.0f} N·m/arcmin; rotation {case.rotation_arcmin:.2f} arcmin"))
    return "".join(rows)


#: The sheet's CSS: compact, one screen at 1366×768; classes are prefixed ``ds-``.
SHEET_STYLE = """<style>
.ds{font-family:system-ui,sans-serif;font-size:13px;line-height:1.25;color:#111}
.ds h1{font-size:19px;margin:0 0 2px}.ds .sub{color:#444;margin:0 0 4px}
.ds .verdict{font-size:17px;font-weight:bold;padding:3px 10px;border-radius:4px;display:inline-block;margin:0 0 3px}
.ds .verdict.ok{background:#e3f4e3;color:#125c12}.ds .verdict.bad{background:#fbe3e3;color:#a00}
.ds .verdict.incomplete{background:#fdf1d6;color:#7a4b00}.ds .verdict{white-space:normal}
.ds .grid{display:grid;grid-template-columns:minmax(0,60fr) minmax(0,40fr);gap:0 14px;align-items:start}
.ds h2 .unit{font-weight:normal;font-size:12px;color:#555}
.ds h2{font-size:14px;margin:4px 0 2px;border-bottom:1px solid #ccc}
.ds table{border-collapse:collapse;width:100%;margin:0}
.ds td,.ds th{padding:1px 5px;border:0;border-bottom:1px solid #e4e4e4;text-align:left;vertical-align:top;white-space:nowrap}
.ds th{font-weight:normal;color:#333}.ds td.num{text-align:right}.ds td.note{color:#555;white-space:normal}
.ds td.wrap{white-space:normal}
.ds thead th{font-weight:bold;color:#111}
.ds .pass{color:#1a7f1a;font-weight:bold}.ds .fail{color:#c00;font-weight:bold}.ds .skip{color:#777}
.ds .fig{min-height:300px;position:sticky;top:0}.ds .est{color:#777;font-size:10px;white-space:nowrap}.ds .nw{white-space:nowrap}.ds .checks td,.ds .checks th{padding:1px 3px}
.ds .checks td:nth-child(2){white-space:normal}
.ds .numbers{overflow-x:auto}
</style>"""


_VERDICT_CLASS = {"PASS": "ok", "FAIL": "bad", "INCOMPLETE": "incomplete"}


def _verdict_head(v) -> str:
    """The verdict's box: PASS, FAIL (how many failed) or INCOMPLETE (how many NOT CHECKED)."""
    if v.status == "FAIL":
        return f"FAIL: {len(v.failures)} check{'s' if len(v.failures) > 1 else ''} failed"
    if v.status == "INCOMPLETE":
        return f"INCOMPLETE: {len(v.not_checked)} check{'s' if len(v.not_checked) > 1 else ''} NOT CHECKED"
    return html.escape(v.status)


def _margin_cell(c: Check) -> str:
    """A check's margin; a NOT CHECKED one's reason (the verdict line above says it in words) as
    the cell's tooltip, so that the reasons do not widen the table past its half of the screen."""
    if c.passed is None:
        return f"<td class=num title=\"{html.escape(c.margin)}\">—</td>"
    return f"<td class=num>{c.margin}</td>"


def _next_scene_words(design) -> str:
    """What the grey '±…' beside the numbers are (none in the dearest scene)."""
    from ..pipeline.scene_estimates import NEXT_SCENE

    nxt = NEXT_SCENE.get(design.scene.name)
    return "" if nxt is None else f" <span class=unit>(grey ±: the measured distance to the {nxt} scene's number)</span>"


def _with_est(value: str, est: str) -> str:
    """A value and its estimate on one line (the check table's value column wraps long values)."""
    return value if not est else f"<span class=nw>{value}{est}</span>"


def _check_est(design, c) -> str:
    """A check's value's distance to the next scene (safety factors, lost motion, clearance)."""
    from ..pipeline.scene_estimates import check_key

    key = check_key(c.kind, c.name)
    if c.kind in ("clearance", "backlash"):  # the 'smallest clearance' and 'backlash' rows' numbers, estimated there
        return ""
    return "" if key is None or c.value is None else _est(design, key, c.value)


def sheet_html(design, figure_html: str = "", *, interference_tol_mm: float) -> str:
    """The first screen of the design report (an HTML fragment): name and description, the
    verdict with every check and its margin, the numbers to cut and the load numbers, each with
    its unit; ``figure_html`` (the interactive CS space, optional) beside them.
    ``interference_tol_mm``: see :func:`checks`."""
    g = design.gearset
    v = design.verdict
    check_rows = "".join(
        f"<tr><th>{html.escape(c.name)}</th><td>{html.escape(c.where)}</td><td class='num wrap'>{_with_est(html.escape(c.value), _check_est(design, vc))}</td><td>{html.escape(c.required)}</td>{_margin_cell(c)}<td>{_badge(c.passed)}</td></tr>"
        for c, vc in zip(checks(design, interference_tol_mm), v.checks))
    gear = (f"ratio {g.ratio:g}, deflection ω* = {g.wave_generator.deflection_coefficient:g}, "
            f"torques {g.torque.rated_nm:g} / {g.torque.peak_nm:g}"
            + ("" if g.torque.momentary_nm is None else f" / {g.torque.momentary_nm:g}")
            + f" N·m (rated / peak{'' if g.torque.momentary_nm is None else ' / momentary'}), "
            f"scene <b>{html.escape(design.scene.name)}</b>")
    return f"""{SHEET_STYLE}<div class="ds">
<h1>{html.escape(g.name)} — design sheet</h1>
<p class="sub">{html.escape(g.description)}</p>
<div class="grid">
<div class="numbers">
<div class="verdict {_VERDICT_CLASS.get(v.status, 'bad')}">{_verdict_head(v)}</div>
{'' if v.line == v.status else f'<p class="sub">{html.escape(v.line)}</p>'}
<p class="sub">{gear}</p>
<h2>Checks{_next_scene_words(design)}</h2>
<table class=checks><thead><tr><th>check</th><th>at</th><th>value</th><th>required</th><th>margin</th><th></th></tr></thead>
{check_rows}</table>
<h2>{'To cut' if getattr(design, 'face', None) is not None else 'Not the part to cut'} <span class="unit">(mm; CS frame: origin on the gear axis, y through the middle of the space)</span></h2>
<table>{_geometry_rows(design)}</table>
<h2>Stiffness <span class="unit">({_stiffness_scope(design)})</span></h2>
<table>{_load_rows(design)}</table></div>
<div class="fig">{figure_html}</div>
</div>
</div>"""

