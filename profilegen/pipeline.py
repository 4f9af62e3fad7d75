"""design(gearset, scene) → Design: every stage, its tier, time and error estimate.

Scenes pick a fidelity tier per stage (DESIGN.md, "Scenes"). Until the FEM rim and
the deformation fitter land, every scene uses the ring-theory deformation (the
`sketch` tier) and says so in ``Design.warnings``.
"""

from __future__ import annotations

import logging
import os
import shutil
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from .deformation import ring_theory
from .envelope import Envelope, envelope_of
from .errors import ExportError, GearSetError
from .gearform import CircularSplineForm, circular_spline_form, clearance_map
from .gearset import GearSet
from .kinematics import HarmonicDriveMotion
from .teeth import tooth_from_gearset

__all__ = ["Scene", "SCENES", "StageReport", "Design", "design", "write_design", "DXF_TOLERANCE_MM"]

DXF_TOLERANCE_MM = 1e-4  # the DXF polyline keeps the outline to 0.1 µm (Douglas–Peucker)

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class Scene:
    """A fidelity preset: the tier of every stage."""

    name: str
    rim: str  # deformation tier asked for
    chord_tol_mm: float  # envelope chord error
    n_t: int  # tracing grid along the flank
    n_phi: int  # tracing grid over one pass
    clearance_samples: int
    brute_force_check: bool  # cross-check the boundary against the brute-force swept region
    description: str


SCENES: dict[str, Scene] = {
    "sketch": Scene("sketch", "ring theory", 1e-4, 48, 121, 91, False, "interactive use and sweeps: analytic rim, coarse envelope"),
    "design": Scene("design", "ring FEM (nonlinear)", 1e-6, 96, 241, 361, False, "the default: 1 nm envelope, classified"),
    "verify": Scene("verify", "toothed-rim FEM", 1e-7, 192, 481, 721, True, "sign-off: 0.1 nm envelope + brute-force swept-region cross-check"),
}


@dataclass(frozen=True, slots=True)
class StageReport:
    """What one stage did: its tier, size, time and error estimate."""

    stage: str
    tier: str
    dof: int
    time_s: float
    error_estimate: float | None  # mm unless said otherwise in ``error_measure``
    error_measure: str
    note: str = ""

    def to_dict(self) -> dict:
        return {
            "tier": self.tier,
            "dof": self.dof,
            "time_s": self.time_s,
            "error_estimate": self.error_estimate,
            "error_measure": self.error_measure,
            "note": self.note,
        }


@dataclass(frozen=True, slots=True, eq=False)
class Design:
    """Everything one design run produced (inputs, stage results, reports, warnings)."""

    gearset: GearSet
    scene: Scene
    tooth: object
    deformation: object
    motion: HarmonicDriveMotion
    envelope: Envelope
    form: CircularSplineForm
    stages: tuple[StageReport, ...]
    warnings: tuple[str, ...] = field(default_factory=tuple)

    @property
    def time_s(self) -> float:
        return float(sum(s.time_s for s in self.stages))

    def to_dict(self) -> dict:
        env = self.envelope
        counts = env.counts()
        return {
            "profilegen_design": 1,
            "gearset": self.gearset.to_dict(),
            "scene": {"name": self.scene.name, "description": self.scene.description},
            "derived": {
                "pitch_radius_mm": self.gearset.gear.pitch_radius_mm,
                "cs_pitch_radius_mm": self.gearset.gear.cs_pitch_radius_mm,
                "neutral_radius_mm": self.gearset.gear.neutral_radius_mm,
                "deflection_mm": self.gearset.deflection_mm,
                "ratio": self.gearset.ratio,
            },
            "stages": {s.stage: s.to_dict() for s in self.stages},
            "time_s": self.time_s,
            "tooth": self.tooth.to_dict(),
            "deformation": self.deformation.to_dict(),
            "envelope": {
                "counts": counts,
                "ridges": [r.to_dict() for r in env.ridges],
                "folds": [f.to_dict() for f in env.folds],
                "no_root_t_mm": {k: [list(map(float, iv)) for iv in v] for k, v in env.no_root.items()},
                "max_interference_mm": env.max_interference_mm,
                "chord_tol_mm": env.chord_tol_mm,
                "root_residual": env.residual,
            },
            "circular_spline": self.form.to_dict(),
            "min_clearance_mm": None if self.form.clearance is None else self.form.clearance.min_mm,
            "warnings": list(self.warnings),
        }


def design(
    gearset: GearSet,
    *,
    scene: str | Scene | None = None,
    progress: Callable[[str], None] | None = None,
) -> Design:
    """Run every stage for one gear set (see the module docstring)."""
    if scene is None:
        scene = gearset.scene
    if isinstance(scene, str):
        if scene not in SCENES:
            raise GearSetError(f"scene = {scene!r}: must be one of {', '.join(SCENES)}")
        scene = SCENES[scene]
    step = progress or (lambda name: None)
    warnings: list[str] = []
    stages: list[StageReport] = []
    g = gearset.gear

    step("tooth")
    t0 = time.perf_counter()
    tooth = tooth_from_gearset(gearset)
    stages.append(
        StageReport("tooth", tooth.kind, len(tooth.segments), time.perf_counter() - t0, float(tooth.fit_error_mm),
                    "max distance of the input points to the smoothed flank (0 for analytic teeth)")
    )

    step("deformation")
    t0 = time.perf_counter()
    deformation = ring_theory(gearset.deflection_mm, g.waves)
    note = ""
    if scene.rim != "ring theory":
        note = f"scene {scene.name!r} asks for the {scene.rim} rim, which is not built yet: ring theory used"
        warnings.append(note)
        log.info(note)
    stages.append(StageReport("deformation", "ring theory", 2, time.perf_counter() - t0, None,
                              "none: ring theory is the model itself (no FEM reference yet)", note))
    motion = HarmonicDriveMotion.from_gearset(gearset, deformation)

    step("envelope")
    env = envelope_of(tooth, motion, cs_teeth=g.circular_spline_teeth, waves=g.waves,
                      chord_tol_mm=scene.chord_tol_mm, n_t=scene.n_t, n_phi=scene.n_phi)
    stages.append(StageReport("envelope", f"traced, chord {scene.chord_tol_mm:g} mm", int(sum(len(p.points) for p in env.pieces)),
                              env.time_s, scene.chord_tol_mm, "chord error of the traced envelope (mm)"))
    if env.flank.get("chains", 1) > 1:
        warnings.append(f"the swept boundary is in {env.flank['chains']} pieces; the CS outline uses the longest")

    step("gearform")
    t0 = time.perf_counter()
    form = circular_spline_form(env, cs_teeth=g.circular_spline_teeth,
                                tip_clearance_mm=gearset.circular_spline.tip_clearance_mm,
                                root_clearance_mm=gearset.circular_spline.root_clearance_mm,
                                chord_tol_mm=scene.chord_tol_mm)
    cmap = clearance_map(form, tooth, motion, phi_range=env.phi_range, samples=scene.clearance_samples)
    form = _with_clearance(form, cmap)
    error, measure = cmap.min_mm, "min signed clearance FS tooth ↔ CS outline (mm; ≈ −chord error on the working flank)"
    if scene.brute_force_check:
        from .swept import boundary_distance, swept_region

        region = swept_region(tooth, motion, cs_teeth=g.circular_spline_teeth, waves=g.waves, n_phi=4001)
        error = float(np.max(boundary_distance(env.flank["boundary"], region)))
        measure = ("max distance of the swept boundary to the brute-force union of 4001 tooth positions (mm); "
                   "bounded below by the brute force's own notch error, ≈ 0.6 mm / 4001 for the default set")
    stages.append(StageReport("gearform", "shapely outline", len(form.outline), time.perf_counter() - t0, error, measure))
    warnings += list(form.warnings)
    if cmap.min_mm < -10 * scene.chord_tol_mm:
        warnings.append(f"the FS tooth interferes with the CS outline by {-cmap.min_mm * 1e3:.3f} µm at φ = {np.degrees(cmap.at_phi):.2f}°")
    return Design(gearset, scene, tooth, deformation, motion, env, form, tuple(stages), tuple(warnings))


def _with_clearance(form: CircularSplineForm, cmap) -> CircularSplineForm:
    from dataclasses import replace

    return replace(form, clearance=cmap)


def write_design(result: Design, out_dir: str | os.PathLike, *, figure: bool = True) -> list[Path]:
    """Write envelope.csv, circular_spline.dxf, design.json (and envelope.png) into out_dir.

    Everything is first written into a temporary folder next to ``out_dir`` and
    moved into place only when all files exist: a failed run leaves nothing new.
    """
    from . import export

    out = Path(out_dir)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    except OSError as exc:
        raise ExportError(f"cannot write to {out}: {exc.strerror or exc}") from exc
    try:
        export.write_envelope_csv(staging / "envelope.csv", result.envelope)
        layers = {
            "CS": [result.form.outline_for_cad(DXF_TOLERANCE_MM)],
            "construction": [np.vstack([c, c[:1]]) for c in _circles(result)],
        }
        export.write_outline_dxf(staging / "circular_spline.dxf", layers)
        data = result.to_dict()
        data["dxf_tolerance_mm"] = DXF_TOLERANCE_MM
        data["files"] = ["envelope.csv", "circular_spline.dxf", "design.json"] + (["envelope.png"] if figure else [])
        export.write_json(staging / "design.json", data)
        if figure:
            from . import plot

            g = result.gearset
            title = (f"{g.name}: m {g.gear.module_mm:g} mm, z {g.gear.flexspline_teeth}/{g.gear.circular_spline_teeth}, "
                     f"ω* {g.wave_generator.deflection_coefficient:g}, scene {result.scene.name}")
            plot.envelope_figure(result.envelope, result.tooth, result.motion, title=title, path=staging / "envelope.png")
        out.mkdir(parents=True, exist_ok=True)
        written = []
        for f in sorted(staging.iterdir()):
            os.replace(f, out / f.name)
            written.append(out / f.name)
        return written
    except OSError as exc:
        raise ExportError(f"cannot write to {out}: {exc.strerror or exc}") from exc
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _circles(result: Design) -> list[np.ndarray]:
    from .gearform import _arc

    f = result.form
    return [_arc(r, 0.0, 2 * np.pi, 1e-4)[:-1] for r in (f.tip_radius_mm, f.root_radius_mm)]
