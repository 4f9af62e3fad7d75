"""The files of a design: every output file :func:`write_design` writes, in one folder that changes as a whole.

The pipeline computes a :class:`~profilegen.pipeline.design.Design`; this module turns it into files
(DXF, SVG, CSV, JSON, PNG, HTML) through the writers of the output layer
(:mod:`.cad`, :mod:`.export`, :mod:`.plot`, :mod:`.report`) and :mod:`.folder`.
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..pipeline import scene_estimates
from ..geometry.contour import Arc, Line, Polyline
from . import face as face_files

if TYPE_CHECKING:  # pragma: no cover
    from ..pipeline.design import Design
    from .report import FigureWorkers

__all__ = ["OUTPUT_FILES", "WORKER_FILES", "figure_workers", "file_jobs", "flexspline_jobs", "profile_figures",
           "stage_figures", "write_design"]


#: Every file name :func:`write_design` can write (the output folder may hold only these, see
#: :mod:`profilegen.output.folder`); a new output file must be added here.
OUTPUT_FILES = frozenset({
    "envelope.csv", "circular_spline.dxf", "tooth_space.dxf", "assembly.dxf", "circular_spline.svg",
    "circular_spline.csv", "profile_fit.json", "deformation_fit.json", "fit_report.html", "envelope.png",
    "contact.json", "contact.png", "torsional.png", "stress.json", "stress.png", "report.html", "design.json",
    "flexspline_tooth.dxf", "flexspline.dxf", "circular_spline_drawing.dxf",
    "circular_spline.step", "flexspline.step",  # with step=True (profilegen design --step)
    "face.png", *face_files.FILES,  # the face width, with the cup3d rim tier (profilegen.face)
})


def figure_workers(workers: int | None = None, *, draw: bool = True):
    """Figure workers for one design run, started now (a context manager): open them before
    :func:`profilegen.pipeline.design.design`, hand them the design once it has its profile
    (``design(..., on_profile=lambda d: profile_figures(figures, d))``), and pass them to
    :func:`write_design` — the figures are then drawn while the contact and stresses are
    computed. ``workers``: see :func:`profilegen.output.report.rendering`; ``draw``: false for
    a run without PNG figures (the workers then make report.html's pieces without importing
    matplotlib)."""
    from . import report

    if not draw:  # the report's two pieces and the drawing: one worker has time for them, beside the stages
        workers = min(1, report._default_workers() if workers is None else int(workers))
    figures = report.FigureWorkers(workers, matplotlib=draw)
    try:
        _start(figures, draw)
    except BaseException:  # a Ctrl-C here, before the caller's with-block owns them: end them now
        figures.close(error=True)
        raise
    return figures


def _start(figures, draw: bool) -> None:
    from . import report

    if not draw:  # the workers fork now, start on the seed tables (no design needed) and ezdxf's import (~0.4 s)
        figures.submit(report.WARM_UP_JOB)
        figures.submit({"ezdxf": (_import_ezdxf, ())})
    elif figures.workers >= 2:  # with the PNGs one server process forks now and imports matplotlib and the
        # stage modules the jobs name, once, on the CPU the stages leave free; its workers fork from it
        # (report._pool). One worker forks when the profile comes (profile_figures), inheriting the stage
        # modules the parent has loaded by then (~0.6 s CPU to import for unpickling the jobs)
        figures.submit(report.WARM_UP_JOB)


def _import_ezdxf() -> None:
    import ezdxf  # noqa: F401


def profile_figures(figures, design: Design, *, draw: bool | None = None) -> None:
    """Hand the figures of a design that has its CS profile to ``figures`` (the PNGs of its
    envelope, fit and rim, and report.html's zoomable CS figure), or, when it draws no PNG, the
    files a worker makes (:func:`file_jobs`). ``draw``: see :func:`write_design`."""
    from . import report

    if _draws(design, draw):
        figures.submit(report.png_jobs(design))
        if figures.workers >= 2:  # the drawing and the flexspline's files too, while the load stages run
            figures.submit(file_jobs(design))  # (one worker is the slower side: they are written here then)
    else:
        figures.submit(file_jobs(design))
    figures.submit(report.report_pieces(design))


def stage_figures(figures, design: Design, *, draw: bool | None = None) -> None:
    """Hand the figures of the stage results a design has so far (the rim and envelope, then the
    contact, stresses and torsional curve: :func:`profilegen.pipeline.design.design`'s ``on_stage``) to
    ``figures``, when the run draws PNGs (``draw``: see :func:`write_design`); with the envelope,
    also the flexspline's drawings (:func:`flexspline_jobs`) where a worker makes the files."""
    from . import report

    # before the profile only to a figure server, which has imported what the jobs need: one worker
    # forked now would import the modules of the later jobs' pickles itself (~0.6 s CPU), not inherit them
    if _draws(design, draw) and (design.profile is not None or figures.workers >= 2):
        figures.submit(report.png_jobs(design))
    if design.profile is None and (not _draws(design, draw) or figures.workers >= 2):
        figures.submit(flexspline_jobs(design))  # the flexspline's drawings need only the tooth


#: The files :func:`file_jobs` makes, by job: the CS drawing (ezdxf's import is most of its time) with
#: the assembly (it poses the flexspline's tooth chain; one job: the CS outline both draw is pickled
#: once, ~50 ms of the main process's CPU a pickle), and the flexspline's drawings (the tooth alone:
#: handed over with the envelope, :func:`stage_figures`).
WORKER_FILES = {"files:drawing": ("circular_spline_drawing.dxf", "assembly.dxf"),
                "files:flexspline": ("flexspline_tooth.dxf", "flexspline.dxf")}


def file_jobs(design: Design) -> dict:
    """The files of :data:`WORKER_FILES` as jobs for the figure workers (made there while this
    process writes the others), ``{job: (function, arguments)}``; each returns ``{file name:
    bytes}``. The design goes without what the files do not read. Empty when the drawing's
    date field cannot be read (``SOURCE_DATE_EPOCH`` not a number): the files are then made in
    this process, which raises the error where it did."""
    from dataclasses import replace

    from .drawing import drawing_date

    try:
        date = drawing_date()
    except ValueError:
        return {}
    # the files read the form's radii and tooth count, not its polygon outline of the whole CS (4 MB:
    # ~60 ms to pickle per job, on the main process's path)
    # (fields the files do not read emptied: passed as a dict[str, Any], as a finished design's types have no None)
    form = None if design.form is None else replace(design.form, **_none("outline"))
    slim = replace(design, **_none("envelope", "rim", "contact", "stress", "torsional", "ratcheting",
                                   "transmission"), form=form, face=_face_notes(design.face))
    return {"files:drawing": (_drawing_files, (slim, date)), **flexspline_jobs(design)}


def flexspline_jobs(design: Design) -> dict:
    """The flexspline's two drawings (:data:`WORKER_FILES`) as a job: they read only the tooth and
    the gear set, so a design without its profile gives the same bytes."""
    from dataclasses import replace

    tooth_only = replace(design, **_none("envelope", "rim", "contact", "stress", "torsional", "ratcheting",
                                         "transmission", "deformation", "motion", "form", "profile"),
                         stages=(), warnings=(), face=_face_notes(design.face))
    return {"files:flexspline": (_flexspline_files, (tooth_only,))}


def _face_notes(face: Any) -> Any:
    """The face stage's result as the drawings' notes read it (``face.coning.modification_lines``:
    the design section, the choice, the modification, the interference), without the sections'
    maps and envelopes; None stays None. The drawings of a design with a face stage must say its
    design section and FS modification, not "no face stage", whichever process draws them."""
    from dataclasses import replace
    from types import SimpleNamespace

    if face is None:
        return None
    mod = face.modification
    if mod is not None:
        mod = replace(mod, sections=(), table=(), clearance_mm=np.zeros(0))
    return SimpleNamespace(design_section_z_mm=face.design_section_z_mm, design_choice=face.design_choice,
                           modification=mod, max_interference_mm=face.max_interference_mm,
                           interference_tol_mm=face.interference_tol_mm)


def _none(*fields: str) -> dict[str, Any]:
    """``{field: None}``: a result's fields emptied for a worker that does not read them."""
    return dict.fromkeys(fields)


def _drawing_files(design: Design, date: str) -> dict[str, bytes]:
    """The CS drawing (it reads the profile, form, gear set and scene) and the assembly."""
    from .drawing import cs_drawing_dxf

    return {"circular_spline_drawing.dxf": cs_drawing_dxf(design, date=date or None).encode("utf-8"),
            **_assembly_file(design)}


def _flexspline_files(design: Design) -> dict[str, bytes]:
    import tempfile

    from .export import deferred_sync

    from . import flexspline

    # a temporary folder, read back at once: no file there needs to reach the disk
    with tempfile.TemporaryDirectory(prefix="profilegen-") as tmp, deferred_sync(sync=False):
        flexspline.write_flexspline_dxfs(Path(tmp), design)
        return {name: (Path(tmp) / name).read_bytes() for name in WORKER_FILES["files:flexspline"]}


def _assembly_file(design: Design) -> dict[str, bytes]:
    import tempfile

    from ..geometry.fsform import flexspline_tooth_chain
    from . import flexspline
    from .export import deferred_sync

    # the tooth chain write_flexspline_dxfs makes (the same call): the flexspline's drawings are another job
    fs_tooth, _ = flexspline_tooth_chain(design.tooth, design.gearset.gear, tol_mm=flexspline.FIT_TOL_MM)
    with tempfile.TemporaryDirectory(prefix="profilegen-") as tmp, deferred_sync(sync=False):
        _write_assembly(Path(tmp), design, fs_tooth)
        return {"assembly.dxf": (Path(tmp) / "assembly.dxf").read_bytes()}


def _write_flexspline(folder: Path, result: Design) -> None:
    """flexspline_tooth.dxf, flexspline.dxf and assembly.dxf into ``folder``."""
    from . import flexspline

    fs_tooth = flexspline.write_flexspline_dxfs(folder, result)  # flexspline_tooth.dxf, flexspline.dxf
    _write_assembly(folder, result, fs_tooth)


def _write_assembly(folder: Path, result: Design, fs_tooth) -> None:
    from . import cad

    cad.write_contours_dxf(folder / "assembly.dxf", _assembly_layers(result, fs_tooth), texts=_note(result))


def _note(result: Design) -> list:
    """The CAD files' note: the gear set and the flank's fit, below the gear."""
    prof, g = result.profile, result.gearset
    assert prof is not None  # the files are a finished design's
    label = (f"{g.name}: m {g.gear.module_mm:g} mm, z1 {g.gear.flexspline_teeth}, z2 {g.gear.circular_spline_teeth}, "
             f"w* {g.wave_generator.deflection_coefficient:g}; CS flank: arc-line-arc ({prof.method}), "
             f"max deviation {prof.max_error_mm * 1e3:.3f} um")
    r_out = result.form.root_radius_mm
    return [("annotation", (-0.6 * r_out, -1.15 * r_out), 0.02 * r_out, label)]


def write_design(result: Design, out_dir: str | os.PathLike, *, figure: bool = True,
                 figures: FigureWorkers | None = None,
                 step: bool = False, draw: bool | None = None) -> list[Path]:
    """Write every output file of a design into out_dir (see the README, "Outputs"); returns their paths.

    The folder changes as a whole (:mod:`profilegen.output.folder`): the files are written into a
    staging folder beside ``out_dir``, which then takes its place in one atomic exchange. A failed
    or killed run leaves the complete old set, a finished one exactly the new set — files of an
    earlier run that this one does not write (``contact.json`` after a ``--no-contact`` run) are
    gone, and ``design.json["files"]`` lists exactly the folder's files. What an interrupted run
    left beside the folder is cleaned by the next run; a second run into the same folder waits
    for the first (a lock file beside it).

    ``out_dir`` must be absent or hold only profilegen's files: a folder with anything else in it
    (a user's notes, a subfolder, ``--out .`` in a project folder) raises an ExportError naming the
    folder and one such entry, and nothing is changed. Every failure is an ExportError naming the path.

    ``draw``: the PNG figures (``envelope.png``, ``contact.png``, ``stress.png`` and the reports'
    pictures); None: the scene's ``figures`` key (``"none"`` in the sketch scene: the reports are
    written without pictures, each replaced by a line saying how to draw it). ``figure=False``
    writes neither figures nor reports.
    """
    from . import folder

    from .export import deferred_sync

    # the staging folder's files are fsynced together at the end of its block, before it is swapped in
    with folder.replacing(out_dir, ours=OUTPUT_FILES) as staging, deferred_sync():
        names = _write_files(result, staging, figure=figure, figures=figures, step=step, draw=draw)
    out = Path(out_dir)
    return [out / name for name in names]


def _draws(result: Design, draw: bool | None) -> bool:
    """Whether a run draws the PNG figures: ``draw``, or the scene's ``figures`` key."""
    return bool(draw) if draw is not None else getattr(result.scene, "figures", "all") != "none"


def _write_files(result: Design, staging: Path, *, figure: bool, figures=None, step: bool = False,
                 draw: bool | None = None) -> list[str]:
    """Write the design's files into the empty folder ``staging``, design.json last; their names, sorted.

    With ``figure`` the pictures are drawn first thing, in worker processes where two CPUs are
    free (:func:`profilegen.output.report.rendering`), while the CAD, CSV and JSON files are written
    here; each is drawn once and the reports embed the same PNG bytes as the files. Without PNGs
    (the sketch scene) a worker makes the drawing, the flexspline's DXFs and the assembly
    (:func:`file_jobs`) meanwhile, the same bytes as here."""
    from . import cad, drawing, export, report

    pieces = report.html_jobs(result) if figure else {}  # last: while the workers draw, collect() makes them here
    draw = figure and _draws(result, draw)
    # without PNGs, a worker makes these while the files here are written; with them, when they were handed
    # to the workers with the profile (profile_figures, two workers or more; one is the slower side)
    made = file_jobs(result) if figure else {}
    if draw and made:
        made = {name: job for name, job in made.items() if figures is not None and figures.has(name)}
    jobs = {**(report.png_jobs(result) if draw else {}), **made, **pieces} if figure else {}
    own = figures is None or not figure
    workers = report.FigureWorkers(min(report._default_workers(), len(jobs)), matplotlib=draw) if own else figures
    with workers if own else contextlib.nullcontext(workers):
        workers.submit(jobs)
        export.write_envelope_csv(staging / "envelope.csv", result.envelope)
        data = result.to_dict()
        prof = result.profile
        assert prof is not None  # the files are a finished design's
        circles = [Arc(np.zeros(2), r, 0.0, 2 * np.pi) for r in (result.form.tip_radius_mm, result.form.root_radius_mm)]
        g = result.gearset
        cad.write_contours_dxf(staging / "circular_spline.dxf", {"CS": [prof.outline], "construction": circles},
                               texts=_note(result))
        cad.write_contours_dxf(staging / "tooth_space.dxf", {"CS": [prof.space], "construction": _space_guides(result)})
        if not made:  # the files of WORKER_FILES here; the drawing dated by SOURCE_DATE_EPOCH, else blank
            drawing.write_cs_drawing(staging / "circular_spline_drawing.dxf", result)
            _write_flexspline(staging, result)
        face_files.write_face_dxfs(staging, result)  # face_tooth_NN.dxf, one per face section (cup3d tier)
        cad.write_contours_svg(staging / "circular_spline.svg", {"CS": [prof.outline], "construction": circles})
        export.write_points_csv(staging / "circular_spline.csv", prof.space.sample(1e-5))
        fit_data = {"gearset": g.name, "scene": result.scene.name, **prof.to_dict()}
        export.write_json(staging / "profile_fit.json", fit_data)
        export.write_json(staging / "deformation_fit.json", report.deformation_fit_dict(result))
        if step:  # the STEP solids (OpenCASCADE, imported only here: seconds)
            from . import step as step_files

            step_files.write_cs_step(staging / "circular_spline.step", result)
            step_files.write_fs_step(staging / "flexspline.step", result)
        contact_data = None
        if result.contact is not None:
            contact_data = {"gearset": g.name, "scene": result.scene.name, **result.contact.to_dict(), **_whole_gear(result)}
            export.write_json(staging / "contact.json", contact_data)
        if result.stress is not None:
            export.write_json(staging / "stress.json", {"gearset": g.name, "scene": result.scene.name,
                                                        **result.stress.to_dict()})
        if figure:
            images = workers.collect(jobs, steal=(*made, *pieces))
            for job in made:
                for name, content in images.pop(job).items():
                    with export.atomic_write(staging / name, "wb") as f:
                        f.write(content)
            if not draw:  # no PNG: each picture's place in the reports says how to draw it
                images = report.NoFigures(images)
            for name in ("envelope", "contact", "torsional", "stress", "face"):
                if name in images:
                    with export.atomic_write(staging / f"{name}.png", "wb") as f:
                        f.write(images[name])
            html = report.fit_report_html(result, prof.fits, chosen=prof.method, clearance=prof.clearance,
                                          positions=prof.positions, images=images)
            if not draw:
                html = report.without_figures(html, result.scene.name)
            with export.atomic_write(staging / "fit_report.html", "w") as f:
                f.write(html)
            if result.stress is not None:
                with export.atomic_write(staging / "report.html", "w") as f:
                    page = report.design_report_html(result, images=images)
                    f.write(page if draw else report.without_figures(page, result.scene.name))
    names = sorted({p.name for p in staging.iterdir()} | {"design.json"})
    unknown = sorted(set(names) - OUTPUT_FILES)
    if unknown:  # a new output file must be named in OUTPUT_FILES, or the next run would refuse the folder
        raise RuntimeError(f"write_design wrote {unknown[0]!r}, which OUTPUT_FILES does not list")
    data["files"] = names
    # each sheet number's measured distance to the next scene's (profilegen.pipeline.scene_estimates)
    data["scene_estimates"] = scene_estimates.report(result.scene, scene_estimates.sheet_numbers(data, fit_data, contact_data),
                                                     g.gear.module_mm)
    export.write_json(staging / "design.json", data)  # last: a staging folder with design.json is complete
    return names


def _whole_gear(result: Design) -> dict:
    """contact.json's whole-gear parts: the torsional curve, when the run made one."""
    out = {}
    torsional = getattr(result, "torsional", None)
    ratchet = getattr(result, "ratcheting", None)
    if torsional is not None:
        out["torsional"] = torsional.to_dict()
        if ratchet is not None:  # the curve's torques at or beyond the ratcheting estimate, flagged
            out["torsional"]["beyond_ratcheting"] = [ratchet.flag(t) for t in torsional.torque_nm]
    if ratchet is not None:
        out["ratcheting_torque_nm"] = ratchet.torque_nm
        out["ratcheting"] = ratchet.to_dict()
    transmission = getattr(result, "transmission", None)
    if transmission is not None:
        out["transmission_error"] = transmission.to_dict()
    return out


def _space_guides(result: Design) -> list:
    """Construction for the one-space drawing: tip and root circle arcs over the space, its axis."""
    f = result.form
    half = 1.5 * np.pi / f.cs_teeth
    arcs = [Arc(np.zeros(2), r, np.pi / 2 - half, 2 * half) for r in (f.tip_radius_mm, f.root_radius_mm)]
    guides: list[Arc | Line] = [*arcs, Line((0.0, f.tip_radius_mm - 0.2), (0.0, f.root_radius_mm + 0.2))]
    return guides


def _assembly_layers(result: Design, fs_tooth) -> dict:
    """CS (true arcs), the deformed FS in its assembled position (all z1 teeth as lines and arcs, each
    tooth chain ``fs_tooth`` posed rigidly, wave generator at ψ = 0, major axis along +y) and the
    wave-generator contour, i.e. the deformed rim bore."""
    from .flexspline import posed_teeth

    g = result.gearset.gear
    fs = posed_teeth(fs_tooth, result.motion, g.flexspline_teeth, g.neutral_radius_mm)
    phi = np.linspace(0.0, 2 * np.pi, 4 * g.flexspline_teeth + 1)
    (w,), (u,) = result.deformation.evaluate(phi, order=0)
    r_bore = g.neutral_radius_mm - g.rim_thickness_mm / 2 + w
    from ..geometry.kinematics import unit_radial, unit_tangential

    bore = r_bore[:, None] * unit_radial(phi) + u[:, None] * unit_tangential(phi)
    bore[-1] = bore[0]
    assert result.profile is not None  # the files are a finished design's
    return {"CS": [result.profile.outline], "FS": fs + [Polyline(bore)], "WG": [Polyline(bore)]}


