"""The face width's files: ``face.png`` (the clearance map, axial
position × φ, without and with the FS tooth modification), one FS tooth DXF per section
(``face_tooth_NN.dxf``: the modified tooth of that section, through the flexspline drawings'
writer, :mod:`profilegen.output.flexspline`), and the report section.
"""

from __future__ import annotations

import html
import math
from pathlib import Path

import numpy as np

__all__ = ["FILES", "MAX_SECTIONS", "face_png", "face_png_job", "face_section_html", "write_face_dxfs"]

#: the most sections a [face] table allows (gearset.sections.FACE_SECTIONS_RANGE)
MAX_SECTIONS = 41
#: every face file name write_face_dxfs can write, numbered from the diaphragm end
FILES = tuple(f"face_tooth_{k:02d}.dxf" for k in range(1, MAX_SECTIONS + 1))
#: the colour scale of the map stops at this clearance (µm): the engaged zone is what matters
SCALE_UM = 40.0


def face_png_job(design):
    """(function, arguments) drawing ``face.png`` for the figure workers, or None without a face."""
    face = getattr(design, "face", None)
    if face is None:
        return None
    mod = face.modification
    g = design.gearset
    title = (f"{g.name}: clearance of the FS teeth against one CS profile (design section z = "
             f"{face.design_section_z_mm:g} mm), {len(face.sections)} sections")
    return face_png, (face.z_mm, face.phi_rad, face.clearance_mm, face.design_section_z_mm,
                      None if mod is None else mod.clearance_mm,
                      None if mod is None else mod.words, title,
                      face.interference_tol_mm)


def face_png(z_mm, phi_rad, clearance_mm, design_z_mm: float, modified_mm=None, modification=None,
             title: str = "", tol_mm: float = 1e-4) -> bytes:
    """The map z × φ, colour = clearance (µm, the scale stopping at SCALE_UM), interference (< 0)
    in red; where a section interferes by more than ``tol_mm`` (the envelope's chord: below it
    is the polyline's noise), the −tol contour and a cross with the depth at its deepest pose.
    The design section dashed. A second panel with the modified teeth when given, titled by
    ``modification`` (its words: :attr:`profilegen.face.modification.ToothModification.words`)."""
    from matplotlib.colors import TwoSlopeNorm

    from .plot import fixed_figure, png_bytes

    maps = [("unmodified FS teeth", np.asarray(clearance_mm))]
    if modified_mm is not None:
        maps.append((f"modified: {modification}", np.asarray(modified_mm)))
    fig, axes = fixed_figure((6.4 * len(maps), 4.2), 1, len(maps), left=0.8, right=1.0, bottom=0.6, top=0.6,
                             wgap=0.6, squeeze=False)
    z = np.asarray(z_mm, float)
    deg = np.degrees(np.asarray(phi_rad, float))
    lo_um = min(-1.0, min(float(np.min(m)) for _, m in maps) * 1e3)
    norm = TwoSlopeNorm(vmin=lo_um, vcenter=0.0, vmax=SCALE_UM)
    for ax, (label, m) in zip(axes[0], maps):
        um = np.minimum(m * 1e3, SCALE_UM)
        mesh = ax.pcolormesh(deg, z, um, cmap="RdYlGn", norm=norm, shading="nearest")
        if np.min(m) < -tol_mm and z.size > 1:
            ax.contour(deg, z, m, levels=[-tol_mm], colors="k", linewidths=0.8)
        for k in range(z.size):
            i = int(np.argmin(m[k]))
            if m[k, i] < -tol_mm:
                ax.plot(deg[i], z[k], "kx", ms=6)
                ax.annotate(f"{m[k, i] * 1e3:.2g} µm", (deg[i], z[k]), fontsize=7, xytext=(4, 3),
                            textcoords="offset points")
        ax.axhline(design_z_mm, color="k", ls="--", lw=0.8)
        ax.set_xlabel("φ (deg, from the wave generator's major axis)")
        ax.set_ylabel("z (mm, from the cup bottom)")
        ax.set_title(label, fontsize=9)
        ax.set_xlim(deg[0], deg[-1])
    cbar = fig.colorbar(mesh, ax=list(axes[0]), fraction=0.04, pad=0.02)
    cbar.set_label(f"clearance (µm; red < 0: interference; ≥ {SCALE_UM:g} shown as {SCALE_UM:g})")
    fig.suptitle(title, fontsize=9)
    return png_bytes(fig, 110)


def write_face_dxfs(staging: Path, design) -> list[str]:
    """One FS tooth DXF per section into ``staging``: the section's tooth (modified when the face
    has a modification), undeformed, lines and arcs; returns the names written."""
    from ..face.modification import modified_tooth
    from ..geometry.fsform import flexspline_tooth_chain
    from . import cad
    from .flexspline import FIT_TOL_MM, tooth_layers

    face = getattr(design, "face", None)
    if face is None:
        return []
    mod = face.modification
    g = design.gearset
    names = []
    for k, section in enumerate(face.sections):
        ds = 0.0 if mod is None else float(mod.thickness_change_mm[k])
        dy = 0.0 if mod is None else float(getattr(mod, "radial_shift_mm", np.zeros(len(face.sections)))[k])
        # a shifted tooth is drawn at the gear's neutral radius, its shift in the note
        tooth = section.tooth if mod is None else (mod.sections[k].tooth if dy == 0.0 else modified_tooth(g, ds))
        chain, dev = flexspline_tooth_chain(tooth, g.gear, tol_mm=FIT_TOL_MM)
        note = (f"{g.name}: flexspline tooth at face section z = {section.z_mm:g} mm (from the cup bottom), "
                f"m {tooth.module_mm:g} mm, z1 {tooth.teeth}, {tooth.kind}, undeformed, mm",
                f"tooth thickness change {ds * 1e3:+.3f} um against the design section z = "
                f"{face.design_section_z_mm:g} mm" + ("" if dy == 0.0 else
                f"; whole tooth (tip and root circles) moved radially {dy * 1e3:+.3f} um, not drawn")
                + ("" if tooth.kind == "dcta" else f"; flank: arcs within {dev * 1e3:.4f} um"))
        layers, texts = tooth_layers(tooth, chain, note)
        name = FILES[k]
        cad.write_contours_dxf(Path(staging) / name, layers, texts=texts)
        names.append(name)
    return names


def _rows(table) -> str:
    return "".join(
        f"<tr><td>{r.z_mm:.2f}</td><td>{r.omega_major_mm * 1e3:.1f}</td><td>{r.omega_minor_mm * 1e3:.1f}</td>"
        f"<td>{r.upsilon_max_mm * 1e3:.1f}</td><td>{r.thickness_change_mm * 1e3:+.2f}</td>"
        f"<td>{r.min_clearance_mm * 1e3:.2f}</td><td>{math.degrees(r.at_phi_rad):.1f}</td>"
        f"<td>{r.max_backlash_mm * 1e3:.2f}</td></tr>" for r in table)


_HEAD = ("<tr><th>z (mm)</th><th>ω major (µm)</th><th>ω minor (µm)</th><th>max |υ| (µm)</th>"
         "<th>thickness change (µm)</th><th>min clearance (µm)</th><th>at φ (deg)</th><th>max backlash (µm)</th></tr>")


def _limit(mod) -> str:
    """What keeps the backlash from being more uniform: the section with the most left, and the
    pose where its tooth is nearest the CS (where a thicker tooth would interfere)."""
    worst = max(mod.table, key=lambda r: r.max_backlash_mm)
    return (f"The most backlash is left at z = {worst.z_mm:g} mm: its tooth cannot be made thicker, since at "
            f"φ = {math.degrees(worst.at_phi_rad):.1f}° it already comes within "
            f"{worst.min_clearance_mm * 1e3:.2g} µm of the CS.")


def _shift_words(mod) -> str:
    """The radial shift in the report's sentence, when the tooth is shifted (a conical FS)."""
    if not mod.shift_mm_per_mm:
        return ""
    dy = np.asarray(mod.radial_shift_mm) * 1e3
    return (f"; and the whole tooth, tip and root circles, is <b>shifted radially by {mod.shift_mm_per_mm * 1e3:.4g} µm "
            f"per mm</b> along the face, zero at the design section ({dy.min():.3g} … {dy.max():.3g} µm over the face, "
            "> 0 outward: a conical FS, in the \"To cut\" table)")


def face_section_html(design, png_uri: str | None = None) -> str:
    """The report section "Across the face width", in plain words, or "" without a face."""
    face = getattr(design, "face", None)
    if face is None:
        return ""
    mod = face.modification
    lo, hi = face.z_mm[0], face.z_mm[-1]
    eng = face.phi_rad[face.engaged]
    engaged = (f"{math.degrees(eng[0]):.1f}° to {math.degrees(eng[-1]):.1f}°" if eng.size else "nowhere")
    if face.design_choice != "auto":
        choice = "as the gear set's [face] design_section_z_mm says"
    elif face.max_interference_mm > face.interference_tol_mm:
        choice = ("the section of deepest engagement: no section's one CS profile is interference-free at every section "
                  "with the teeth unmodified, so the tooth modification below clears the face")
    else:
        choice = ("chosen as the section whose one CS profile is interference-free at every section with the least "
                  "largest backlash")
    if mod is None:
        modtext = "<p>No tooth modification was asked for.</p>"
    else:
        how = ("computed" if mod.source == "computed" else "as given in the gear set's [face] table")
        modtext = f"""<p>The flexspline teeth are then modified along the face ({how}): their thickness on the pitch line
changes by Δs(z) = taper·(z − z_d) − crowning·(u² − u_d²), u = (z − z_mid)/(b/2), zero at the design section, with
<b>taper {mod.taper_mm_per_mm * 1e3:.3g} µm per mm</b> and <b>crowning {mod.crowning_mm * 1e3:.3g} µm</b>
(the face ends that much thinner than the mid-face){_shift_words(mod)}. {html.escape(mod.method[:1].upper() + mod.method[1:])}.
With it the largest interference over the face is {mod.max_interference_mm * 1e3:.3g} µm and the largest
backlash {mod.max_backlash_mm * 1e3:.2f} µm (without: {face.max_interference_mm * 1e3:.3g} µm and
{face.max_backlash_mm * 1e3:.2f} µm). {_limit(mod)} Each section's modified tooth is a DXF: <code>face_tooth_01.dxf</code>
(the diaphragm end) to <code>face_tooth_{len(face.sections):02d}.dxf</code> (the open end).</p>
<table>{_HEAD}{_rows(mod.table)}</table>"""
    img = "" if png_uri is None else f'<img src="{png_uri}" alt="clearance map across the face">'
    return f"""<h2>Across the face width</h2>
<p>The flexspline is a cup: it cones, so each axial section of the tooth ring deforms differently. The 3D
cup gives ω and υ at {len(face.sections)} sections from z = {lo:g} mm (the diaphragm end of the tooth ring) to
z = {hi:g} mm (the open end); each section's teeth move in their own way and sweep their own region. The
circular spline is cut with one profile through its whole face: the CS outline of the <b>design section
z = {face.design_section_z_mm:g} mm</b>, {choice}. The map below is the clearance between every section's
teeth and that one profile at every position φ of the wave generator (the polyline CS outline of the design
section's envelope, traced to {face.chord_tol_mm * 1e3:g} µm); below zero the teeth interfere. Backlash is the
largest clearance of a section while the design section's teeth are in contact ({engaged}).</p>
<table>{_HEAD}{_rows(face.table)}</table>
<p>Largest interference over the face {face.max_interference_mm * 1e3:.3g} µm, largest backlash
{face.max_backlash_mm * 1e3:.2f} µm.</p>
{modtext}
{img}"""
