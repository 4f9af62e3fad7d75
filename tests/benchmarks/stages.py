"""Speed against accuracy of every stage and tier, each against a converged reference, in one run.

``stage_benchmark(gearset, quick=..., repeats=...)`` times each stage alone (inputs prepared
outside the timing; median wall time of up to ``repeats`` runs, a setting whose first run is
long is run once) at the tiers the scenes use and at neighbouring settings, and measures each
answer against a converged reference computed in the same run. One row per (stage, method or
setting); the reference of each stage is a row too (``role`` "reference"), its ``error`` an
estimate of its own uncertainty where one is made (else NaN). Rows whose error is within that
uncertainty say so in ``note``.

========  ==============================================  ============================================
stage     methods and settings                            converged reference and what is compared
========  ==============================================  ============================================
rim       ring theory (sketch); flat ring FEM, linear     flat nonlinear FEM, 8 layers × 512 divisions
          and nonlinear, 4 × 16 … 128 (design: 4 × 64);   (256 with ``quick``); toothed: 20 columns per
          toothed rim, 14 and 16 columns per pitch; 3D    pitch; 3D cup: 1 mm, 31 angles. Max |Δω|,
          cup (press_cup) 8 mm / 4 angles … 2 mm / 16     |Δυ| on the neutral line (µm; the cup: over
          (verify: cup3d); toothed and cup not with       the tooth ring, 11 sections)
          ``quick``
fit       Fourier series of the design tier's samples,    the rim's converged FEM, over a whole turn:
          order 1 … 16 and auto (design), general sine    max |Δω|, |Δυ| (µm) of the fitted model —
          series (verify, reported); without ``quick``    what the kinematics sees (the fitted samples'
          also the verify fits of the toothed samples     own mesh error is the floor, said in ``note``)
envelope  traced, chord 1e-4 (sketch), 1e-6 (design),     traced at chord 1e-9 mm: symmetric distance
          1e-7 (verify), 1e-5 / 1e-8; brute-force union   between the CS space boundaries (nm); the
          of 721 (and 4001: verify's cross-check) poses   brute force's boundary from the reference side
arcfit    least squares, minimax, one-sided on the        the flank of the 1e-9 mm envelope: max
          flanks of the scenes' chords; minimax with 40   distance of its points to the fitted
          starts (the best arc–line–arc found)            arc–line–arc (µm)
contact   Lemke, 5 stations per tooth, default FEM        Lemke with 9 stations, FEM 32 columns per
          (design, verify); 3 stations; finer FEM; the    pitch, 6 tooth layers (``quick``: 5, 24, 6):
          solvers alone with the FEM reused (Lemke,       rotation of the FS under each of the gear
          active-set QP, seed 000's naive LP)             set's torques, largest relative change (%)
stress    consistent Kirchhoff plate (every scene),       Morley plate, Richardson-extrapolated from
          seed002 plate, Morley 8 … 32 (64) divisions     96/128 divisions (48/64 with ``quick``): max
                                                          |σ_r| at the clamp (%), design scene's rim
========  ==============================================  ============================================

The FEM rim and contact tiers need two symmetry planes (gear.waves = 2): on other gear sets
the rim, fit and contact stages are left out (logged). BLAS runs single-threaded, as in
:func:`profilegen.pipeline.design.design`, so the times are those of the pipeline.

``write_stage_benchmark(rows, out_dir)`` writes ``stages.csv`` and ``stages.png`` (one panel
per stage, log–log time against error, the scene tiers highlighted); ``format_stage_rows``
is the plain-text table of the command line (``profilegen bench``).

Benchmark code, not product code: it lives in the source checkout (``tests/benchmarks/``, was
``profilegen/bench_stages.py``) and ``profilegen bench`` loads it from there
(:func:`profilegen.bench.load_benchmark`). It uses only public names of the package; the two
small helpers it needs that the package keeps private (the KD-tree polyline distance of
``profilegen.profile.gearform``, the rim stage's one-period mirroring) are written out here.
"""

from __future__ import annotations

import csv
import inspect
import logging
import math
import statistics
import sys
import time
from functools import cached_property
from pathlib import Path

import numpy as np

__all__ = ["STAGES", "FIELDS", "stage_benchmark", "write_stage_benchmark", "format_stage_rows"]

log = logging.getLogger(__name__)


def _oracles_importable() -> None:
    """The cross-check models live in the checkout's tests/oracles/ (not in the package): make
    ``tests.oracles`` importable however this file was loaded (``profilegen bench`` loads it by path)."""
    root = str(Path(__file__).resolve().parents[2])
    if root not in sys.path:
        sys.path.append(root)

STAGES = ("rim", "fit", "envelope", "arcfit", "contact", "stress")
#: the columns of ``stages.csv`` (every row has them all)
FIELDS = ("stage", "method", "scene", "role", "series", "time_s", "repeats", "error", "error_unit", "error_measure",
          "reference", "note")
_UNITS = {"rim": "µm", "fit": "µm", "envelope": "nm", "arcfit": "µm", "contact": "%", "stress": "%"}
_MEASURES = {
    "rim": "max |Δω|, |Δυ| on the neutral line, 0 ≤ φ ≤ π/2",
    "fit": "max |Δω|, |Δυ| of the fitted model over a whole turn",
    "envelope": "symmetric distance between the CS space boundaries",
    "arcfit": "max distance of the reference flank to the fitted arc–line–arc",
    "contact": "max over the gear set's torques of |Δ rotation| / rotation",
    "stress": "max |σ_r| at the clamp (cup bottom, bending), relative",
}
_SCALE = {"µm": 1e3, "nm": 1e6}  # mm → unit
_TOOTHED_REFERENCE = 20  # element columns per pitch of the toothed-rim reference (verify: 16)


# --------------------------------------------------------------------------- helpers


def _timed(fn, repeats: int, long_s: float, setup=None):
    """(result, median time in s, runs): ``fn()`` up to ``repeats`` times, once if the first run
    takes longer than ``long_s``; ``setup()`` runs before each, outside the timing."""
    times, result = [], None
    for _ in range(repeats):
        if setup is not None:
            setup()
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
        if times[0] > long_s:
            break
    return result, statistics.median(times), len(times)


def _row(stage, method, time_s, runs, error, *, reference, scene="", series="", note="", measure=None,
         role=None) -> dict:
    return {
        "stage": stage, "method": method, "scene": scene,
        "role": role or ("scene tier" if scene else "option"), "series": series,
        "time_s": float(time_s), "repeats": int(runs), "error": float(error), "error_unit": _UNITS[stage],
        "error_measure": measure or _MEASURES[stage], "reference": reference, "note": note,
    }


def _flag_unresolved(rows: list[dict], uncertainty: float | None, reference: str) -> None:
    """Say so in ``note`` where a row's error (against ``reference``) is within that reference's
    own uncertainty (same unit as the rows' errors): the difference is not resolved."""
    if uncertainty is None or not math.isfinite(uncertainty):
        return
    unit = rows[0]["error_unit"] if rows else ""
    for r in rows:
        if r["role"] != "reference" and r["reference"] == reference and r["error"] <= uncertainty:
            text = f"within the reference's own uncertainty ({uncertainty:.3g} {unit}): not resolved"
            r["note"] = f"{r['note']}; {text}" if r["note"] else text


def _close(rows: list[dict], stage: str, label: str, time_s: float, uncertainty: float | None, note: str) -> None:
    """Append the reference's own row (its error: its uncertainty, NaN if not estimated) and
    flag the rows it does not resolve."""
    rows.append(_row(stage, label, time_s, 1, math.nan if uncertainty is None else uncertainty, reference=label,
                     role="reference", note=note))
    _flag_unresolved(rows, uncertainty, label)


def _defaults(fn, *names):
    """The default values of ``fn``'s keyword parameters ``names`` (labels stay true to the code)."""
    params = inspect.signature(fn).parameters
    return tuple(params[n].default for n in names)


def _boundary_distance_mm(a: np.ndarray, b: np.ndarray) -> float:
    """Symmetric distance (mm) between two boundary polylines: vertices of each to the other."""
    from profilegen.profile.gearform import PolylineDistance

    return float(max(PolylineDistance(b).distance(a).max(), PolylineDistance(a).distance(b).max()))


def _change_mm(res, ref) -> float:
    """Largest |Δω|, |Δυ| (mm) of a ring solution against a reference at the solution's own
    neutral-line nodes: exact where the meshes nest, else through a cubic spline of the
    (denser) reference (linear interpolation would add ~h²ω″/8)."""
    from scipy.interpolate import CubicSpline

    common, i_r, i_f = np.intersect1d(np.round(res.phi_rad, 12), np.round(ref.phi_rad, 12), return_indices=True)
    if common.size == res.phi_rad.size:
        w, u = ref.omega_mm[i_f], ref.upsilon_mm[i_f]
        return float(max(np.max(np.abs(res.omega_mm[i_r] - w)), np.max(np.abs(res.upsilon_mm[i_r] - u))))
    w = CubicSpline(ref.phi_rad, ref.omega_mm)(res.phi_rad)
    u = CubicSpline(ref.phi_rad, ref.upsilon_mm)(res.phi_rad)
    return float(max(np.max(np.abs(res.omega_mm - w)), np.max(np.abs(res.upsilon_mm - u))))


def _model_change_mm(model, ref, *, whole_turn: bool) -> float:
    """Largest |Δω|, |Δυ| (mm) of a deformation model against a ring solution, at the
    reference's nodes on 0 ≤ φ ≤ π/2 or (``whole_turn``) mirrored to a whole turn with the
    two-wave symmetries ω(π ± φ) = ω(φ), υ(π ± φ) = ±υ(φ), ω even, υ odd."""
    phi, w, u = ref.phi_rad, ref.omega_mm, ref.upsilon_mm
    if whole_turn:
        phi = np.concatenate([phi, math.pi - phi, math.pi + phi, 2 * math.pi - phi])
        w = np.concatenate([w, w, w, w])
        u = np.concatenate([u, -u, u, -u])
    (mw,), (mu,) = model.evaluate(phi, order=0)
    return float(max(np.max(np.abs(mw - w)), np.max(np.abs(mu - u))))


def _mesh_uncertainty(changes: list[float], sizes: list[float]) -> float:
    """Error estimate of the finest of three meshes (sizes = columns per pitch, increasing) from
    the changes coarse→middle and middle→fine, assuming error ∝ size^−p with p observed. If
    the changes do not fit such a law with 1 ≤ p ≤ 4 (not yet asymptotic), the last change
    itself (an upper estimate)."""
    c1, c2 = changes
    n0, n1, n2 = sizes
    if not (c1 > c2 > 0):
        return c2

    def ratio(p):
        return (n1**-p - n2**-p) / (n0**-p - n1**-p)

    target = c2 / c1
    lo, hi = 1.0, 4.0
    if not ratio(hi) <= target <= ratio(lo):
        return c2
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ratio(mid) > target else (lo, mid)
    return c2 / ((n2 / n1) ** (0.5 * (lo + hi)) - 1.0)


# --------------------------------------------------------------------------- shared inputs


class _Inputs:
    """What several stages need, computed once on first use (the designs the caller passes are
    used where given)."""

    def __init__(self, gearset, designs, quick: bool, step):
        self.gearset, self.designs, self.quick, self.step = gearset, dict(designs or {}), quick, step
        self.long_s = 1.0 if quick else 5.0  # a setting whose first run is longer is run once

    @cached_property
    def design(self):
        from profilegen.pipeline.design import design

        d = self.designs.get("design")
        if d is None:
            self.step("design scene (inputs of the envelope, arcfit, contact and stress studies)")
            d = design(self.gearset, scene="design", contact=False, stress=False)
        return d

    @cached_property
    def cam(self):
        from profilegen.rim import solve_ring
        from profilegen.geometry.wavegen import from_gearset

        cam = from_gearset(self.gearset)
        solve_ring(self.gearset, contour=cam, divisions=8)  # imports and first-call set-up out of the timings
        return cam

    @cached_property
    def flat_reference(self):
        """(reference solution, its label, its uncertainty in mm — the change from half the
        divisions, an upper estimate — and its solve time in s)."""
        from profilegen.rim import solve_ring

        divisions = 256 if self.quick else 512
        self.step(f"rim reference: flat nonlinear ring FEM 8×{divisions}")
        self.cam  # noqa: B018 — set-up outside the timing
        # the flat ring's compliance condensed up front (lazy_columns=False), as for the design tier's
        # meshes: 8 x 256 has 257 bore nodes, past solve_ring's LAZY_BORE_NODES = 256 for the toothed rim,
        # and the lazy columns took 20.2 s CPU against 8.7 s (same omega to 3e-14 mm)
        t0 = time.perf_counter()
        ref = solve_ring(self.gearset, contour=self.cam, layers=8, divisions=divisions, geometry="nonlinear",
                         lazy_columns=False)
        elapsed = time.perf_counter() - t0
        half = solve_ring(self.gearset, contour=self.cam, layers=8, divisions=divisions // 2, geometry="nonlinear",
                          lazy_columns=False)
        return ref, f"flat nonlinear ring FEM 8×{divisions}", _change_mm(half, ref), elapsed

    def toothed(self, per_pitch: int, tooth_layers: int | None = None):
        """(toothed-rim solution, FEM solve time in s) of the verify tier's mesh with
        ``per_pitch`` columns; the verify design's own solutions where given."""
        from profilegen.rim import RIM_TIERS, solve_ring
        from profilegen.rim.toothed import toothed_quarter_mesh
        from profilegen.geometry.teeth import tooth_from_gearset

        tier = RIM_TIERS["verify"]
        layers = tier.tooth_layers if tooth_layers is None else tooth_layers
        given = self.designs.get("verify")
        if (given is not None and given.rim is not None and given.rim.fem is not None and given.rim.tier.model == "toothed"
                and layers == tier.tooth_layers):  # the verify scene's rim is the 3D cup now: used only if toothed
            if per_pitch == tier.per_pitch:
                return given.rim.fem, given.rim.fem_time_s
            if per_pitch == tier.per_pitch - 2 and given.rim.coarse is not None:
                return given.rim.coarse, given.rim.coarse.time_s
        cache = self.__dict__.setdefault("_toothed", {})
        if (per_pitch, layers) not in cache:
            self.step(f"rim: toothed rim FEM, {per_pitch} columns per pitch, {tier.layers}+{layers} layers")
            mesh = toothed_quarter_mesh(tooth_from_gearset(self.gearset), self.gearset.gear.rim_thickness_mm,
                                        rim_layers=tier.layers, tooth_layers=layers, per_pitch=per_pitch)
            self.cam  # noqa: B018 — set-up outside the timing
            t0 = time.perf_counter()
            res = solve_ring(self.gearset, contour=self.cam, mesh=mesh, geometry=tier.geometry)
            cache[(per_pitch, layers)] = (res, time.perf_counter() - t0)
        return cache[(per_pitch, layers)]

    @cached_property
    def toothed_reference(self):
        """(reference, label, uncertainty in mm) of the toothed rim: the verify mesh refined to
        ``_TOOTHED_REFERENCE`` columns per pitch, its error extrapolated from the changes
        between the verify tier's two meshes and the reference."""
        from profilegen.rim import RIM_TIERS

        n = RIM_TIERS["verify"].per_pitch
        sizes = [n - 2, n, _TOOTHED_REFERENCE]
        ref, _ = self.toothed(sizes[2])
        c1 = _change_mm(self.toothed(sizes[0])[0], self.toothed(sizes[1])[0])
        c2 = _change_mm(self.toothed(sizes[1])[0], ref)
        tier = RIM_TIERS["verify"]
        label = f"toothed rim FEM nonlinear {sizes[2]}/pitch, {tier.layers}+{tier.tooth_layers} layers"
        return ref, label, _mesh_uncertainty([c1, c2], sizes)

    def trace(self, chord_tol_mm: float, n_t: int, n_phi: int):
        """The classified envelope with the design scene's tooth and motion (not remembered)."""
        from profilegen.profile.envelope import envelope_of

        g = self.gearset.gear
        return envelope_of(self.design.tooth, self.design.motion, cs_teeth=g.circular_spline_teeth, waves=g.waves,
                           chord_tol_mm=chord_tol_mm, n_t=n_t, n_phi=n_phi)

    def envelope(self, chord_tol_mm: float, n_t: int, n_phi: int, *, given=None):
        """(envelope, time in s) of one setting, traced once (or ``given``: an envelope and its
        time already measured)."""
        cache = self.__dict__.setdefault("_envelopes", {})
        key = (chord_tol_mm, n_t, n_phi)
        if given is not None:
            cache[key] = given
        if key not in cache:
            self.design  # noqa: B018 — set-up outside the timing
            t0 = time.perf_counter()
            env = self.trace(chord_tol_mm, n_t, n_phi)
            cache[key] = (env, time.perf_counter() - t0)
        return cache[key]

    @cached_property
    def envelope_reference(self):
        from profilegen.pipeline.design import SCENES

        finest = SCENES["verify"]
        self.step("envelope reference: traced, chord 1e-9 mm")
        env, t = self.envelope(1e-9, finest.n_t, finest.n_phi)
        return env, t, f"traced envelope, chord 1e-9 mm (n_t {finest.n_t}, n_phi {finest.n_phi})"

    def flank(self, env, chord_tol_mm: float) -> np.ndarray:
        """The right working flank of the CS outline built from ``env`` (as the pipeline does)."""
        from profilegen.profile.gearform import circular_spline_form

        g, cs = self.gearset.gear, self.gearset.circular_spline
        form = circular_spline_form(env, cs_teeth=g.circular_spline_teeth, tip_clearance_mm=cs.tip_clearance_mm,
                                    root_clearance_mm=cs.root_clearance_mm, chord_tol_mm=chord_tol_mm)
        return np.asarray(form.working_flank["right"])

    @property
    def torques_nm(self) -> list[float]:
        t = self.gearset.torque
        return [x for x in (t.rated_nm, t.peak_nm, t.momentary_nm) if x is not None]


# --------------------------------------------------------------------------- the stages


def _rim(inp: _Inputs, repeats: int) -> list[dict]:
    from profilegen.rim import RIM_TIERS, solve_rim, solve_ring

    gs, cam = inp.gearset, inp.cam
    ref, ref_label, ref_unc, ref_time = inp.flat_reference
    um = _SCALE["µm"]
    toothed = None
    if not inp.quick:
        toothed = inp.toothed_reference
    rows = []

    def teeth_note(model=None, res=None) -> str:
        if toothed is None:
            return ""
        e = (_model_change_mm(model, toothed[0], whole_turn=False) if model is not None
             else _change_mm(res, toothed[0]))
        return f"vs the toothed-rim reference: {e * um:.3g} µm (the teeth's effect)"

    inp.step("rim: ring theory")
    rim, t, n = _timed(lambda: solve_rim(gs, tier="sketch"), repeats, inp.long_s)
    rows.append(_row("rim", "ring theory", t, n, _model_change_mm(rim.model, ref, whole_turn=False) * um,
                     reference=ref_label, scene="sketch", note=teeth_note(model=rim.model)))
    design = RIM_TIERS["design"]
    inp.step(f"rim: flat ring FEM, linear {design.layers}×{design.divisions}")
    res, t, n = _timed(lambda: solve_ring(gs, contour=cam, layers=design.layers, divisions=design.divisions,
                                          geometry="linear"), repeats, inp.long_s)
    rows.append(_row("rim", f"flat ring FEM linear {design.layers}×{design.divisions}", t, n,
                     _change_mm(res, ref) * um, reference=ref_label, note="small-strain: its error is the "
                     "geometric nonlinearity"))
    for divisions in (16, 32, 64, 128):
        inp.step(f"rim: flat ring FEM, nonlinear {design.layers}×{divisions}")
        res, t, n = _timed(lambda d=divisions: solve_ring(gs, contour=cam, layers=design.layers, divisions=d,
                                                          geometry=design.geometry), repeats, inp.long_s)
        used = divisions == design.divisions
        note = ""
        if used:
            note = f"the design scene's rim stage also solves {design.layers}×{divisions // 2} for its error estimate"
            extra = teeth_note(res=res)
            note = f"{note}; {extra}" if extra else note
        rows.append(_row("rim", f"flat ring FEM nonlinear {design.layers}×{divisions}", t, n,
                         _change_mm(res, ref) * um, reference=ref_label, scene="design" if used else "",
                         series="flat nonlinear", note=note))
    _close(rows, "rim", ref_label, ref_time, ref_unc * um,
           "error = its own uncertainty: the change from half the divisions (an upper estimate)")
    if toothed is not None:
        t_ref, t_label, t_unc = toothed
        verify = RIM_TIERS["verify"]
        trows = []
        for per_pitch in (verify.per_pitch - 2, verify.per_pitch):
            res, t = inp.toothed(per_pitch)
            used = per_pitch == verify.per_pitch
            trows.append(_row("rim", f"toothed rim FEM nonlinear {per_pitch}/pitch", t, 1, _change_mm(res, t_ref) * um,
                              reference=t_label, series="toothed",
                              note=(f"the toothed tier (--rim toothed; the verify scene's rim before the 3D cup) also "
                                    f"solves {per_pitch - 2}/pitch for its error estimate") if used else ""))
        _close(trows, "rim", t_label, inp.toothed(_TOOTHED_REFERENCE)[1], t_unc * um,
               f"error = its own uncertainty, from the {verify.per_pitch - 2} → {verify.per_pitch} → "
               f"{_TOOTHED_REFERENCE} columns changes (the last change where they follow no power law 1 ≤ p ≤ 4)")
        rows += trows
        rows += _cup_rows(inp, repeats)
    return rows


#: the 3D cup's settings (mm along the meridian, contact angles), coarse → fine; the last is the reference
_CUP_SETTINGS = ((8.0, 4), (4.0, 8), (2.0, 16), (1.0, 31))
_CUP_MEASURE = ("max |Δω|, |Δυ| on r_m over the tooth ring (11 sections × 0 ≤ φ ≤ π/2), the 3D cup against its "
                "finest mesh")


def _cup_change_mm(a, b) -> float:
    """Largest |Δω|, |Δυ| (mm) between two 3D cup deformations over the tooth ring."""
    lo, hi = a.geometry.ring_span_mm
    phi = np.linspace(0.0, 0.5 * math.pi, 91)[:, None]
    z = np.linspace(lo, hi, 11)[None, :]
    return float(max(np.max(np.abs(a.omega(phi, z) - b.omega(phi, z))),
                     np.max(np.abs(a.upsilon(phi, z) - b.upsilon(phi, z)))))


def _cup_rows(inp: _Inputs, repeats: int) -> list[dict]:
    """The cup3d tier (the verify scene's rim: nonlinear, exact gap) and its neighbours against
    the finest cup mesh, press_cup alone (the stage also solves the next coarser setting for its
    estimate); and, as an option, the linear cup with the first-order gap at the tier's mesh
    (what the nonlinearity and the exact gap change, at what cost)."""
    from profilegen.rim import RIM_TIERS
    from profilegen.rim.cup import CupGeometry, press_cup

    gs, cam = inp.gearset, inp.cam
    geometry = CupGeometry.from_gearset(gs)
    tier = RIM_TIERS["cup3d"]
    model = dict(gap=tier.gap, nonlinear=tier.geometry == "nonlinear", layers=tier.layers)
    um = _SCALE["µm"]
    *settings, (ref_mm, ref_angles) = _CUP_SETTINGS
    inp.step(f"rim reference: 3D cup {ref_mm:g} mm, {ref_angles} angles")
    t0 = time.perf_counter()
    ref = press_cup(geometry, contour=cam, element_mm=ref_mm, angles=ref_angles, **model).deformation
    ref_time = time.perf_counter() - t0
    kind = f"{tier.geometry}, {tier.gap.replace('_', '-')} gap"
    label = f"3D cup {ref_mm:g} mm, {ref_angles} angles ({kind})"
    rows, changes, previous = [], [], None
    for element_mm, angles in settings:
        inp.step(f"rim: 3D cup {element_mm:g} mm, {angles} angles")
        res, t, n = _timed(lambda e=element_mm, a=angles: press_cup(geometry, contour=cam, element_mm=e, angles=a,
                                                                  **model), repeats, inp.long_s)
        d = res.deformation
        used = (element_mm, angles) == (tier.element_mm, tier.angles)
        if previous is not None:
            changes.append(_cup_change_mm(previous, d))
        previous = d
        rows.append(_row("rim", f"3D cup {element_mm:g} mm, {angles} angles", t, n, _cup_change_mm(d, ref) * um,
                         reference=label, scene="verify" if used else "", series="3D cup", measure=_CUP_MEASURE,
                         note=(f"{kind}; the verify scene's rim (cup3d) also solves {2 * element_mm:g} mm, "
                               f"{angles // 2} angles for its error estimate") if used else kind))
    changes.append(_cup_change_mm(previous, ref))
    inp.step(f"rim: 3D cup {tier.element_mm:g} mm, {tier.angles} angles, linear, first-order gap")
    res, t, n = _timed(lambda: press_cup(geometry, contour=cam, element_mm=tier.element_mm, angles=tier.angles,
                                         layers=tier.layers), repeats, inp.long_s)
    rows.append(_row("rim", f"3D cup {tier.element_mm:g} mm, {tier.angles} angles, linear, first-order gap", t, n,
                     _cup_change_mm(res.deformation, ref) * um, reference=label, measure=_CUP_MEASURE,
                     note="press_cup's defaults: its error is mostly the geometric nonlinearity and the exact gap"))
    sizes = [a for _, a in _CUP_SETTINGS[-3:]]
    unc = _mesh_uncertainty(changes[-2:], sizes)
    _close(rows, "rim", label, ref_time, unc * um,
           "error = its own uncertainty, from the changes of the last three settings (the last change where they "
           "follow no power law 1 ≤ p ≤ 4)")
    for r in rows:
        r["error_measure"] = _CUP_MEASURE
    return rows


def _fit(inp: _Inputs, repeats: int) -> list[dict]:
    from profilegen.rim import RIM_TIERS
    from profilegen.rim.stage import one_period
    from profilegen.geometry.series import GeneralSineDeformation, fit_fourier, fit_sine_series

    fem = inp.design.rim.fem if inp.design.rim is not None else None
    if fem is None:
        log.info("fit study skipped: the design scene's rim has no FEM samples (ring theory)")
        return []
    ref, ref_label, ref_unc, ref_time = inp.flat_reference
    um, waves = _SCALE["µm"], inp.gearset.gear.waves
    phi, w, u = one_period(fem)
    floor = _change_mm(fem, ref)
    design, verify = RIM_TIERS["design"], RIM_TIERS["verify"]
    mesh = f"flat {design.layers}×{design.divisions}"
    rows = []

    def add(method, fit, t, n, scene="", series="", note="", reference=ref, label=ref_label, floor_mm=floor):
        err = _model_change_mm(fit, reference, whole_turn=True)
        notes = [note] if note else []
        if err <= 1.5 * floor_mm:
            notes.append(f"at the floor set by the fitted samples' own mesh error ({floor_mm * um:.3g} µm)")
        rows.append(_row("fit", method, t, n, err * um, reference=label, scene=scene, series=series,
                         note="; ".join(notes)))

    for order in (1, 2, 4, 8, 16):
        inp.step(f"fit: Fourier order {order}")
        fit, t, n = _timed(lambda k=order: fit_fourier(phi, w, u, waves=waves, order=k, tier="design"), repeats,
                           inp.long_s)
        add(f"Fourier order {order}", fit, t, n, series="Fourier")
    inp.step("fit: Fourier, order picked (design tier)")
    fit, t, n = _timed(lambda: fit_fourier(phi, w, u, waves=waves, max_order=design.max_order, tier="design"),
                       repeats, inp.long_s)
    add(f"Fourier auto ≤ {design.max_order} (order {fit.order})", fit, t, n, scene="design", series="Fourier",
        note=f"{mesh} samples")

    def sine(p, a, b):
        return GeneralSineDeformation(fit_sine_series(p, a, terms=3), fit_sine_series(p, b, terms=3), waves=waves,
                                      tier="verify")

    inp.step("fit: general sine series, 3 terms")
    model, t, n = _timed(lambda: sine(phi, w, u), repeats, inp.long_s)
    d_w, d_u = model.defect_mm
    add("general sine, 3 terms", model, t, n,
        note=f"the verify scene's second fitter (reported, not used), here on the {mesh} samples; "
             f"periodicity defect ω {d_w * um:.3g} µm, υ {d_u * um:.3g} µm over a turn")
    _close(rows, "fit", ref_label, ref_time, ref_unc * um, "the rim's converged FEM (error = its own uncertainty)")
    if not inp.quick:
        t_ref, t_label, t_unc = inp.toothed_reference
        res, _ = inp.toothed(verify.per_pitch)
        p2, w2, u2 = one_period(res)
        t_floor = _change_mm(res, t_ref)
        inp.step("fit: the verify tier's fits of the toothed samples")
        fit, t, n = _timed(lambda: fit_fourier(p2, w2, u2, waves=waves, max_order=verify.max_order, tier="verify"),
                           repeats, inp.long_s)
        add(f"Fourier auto ≤ {verify.max_order} (order {fit.order}), toothed samples", fit, t, n,
            reference=t_ref, label=t_label, floor_mm=t_floor, note=f"toothed {verify.per_pitch}/pitch samples")
        model, t, n = _timed(lambda: sine(p2, w2, u2), repeats, inp.long_s)
        d_w, d_u = model.defect_mm
        add("general sine, 3 terms, toothed samples", model, t, n, reference=t_ref,
            label=t_label, floor_mm=t_floor,
            note=f"periodicity defect ω {d_w * um:.3g} µm, υ {d_u * um:.3g} µm over a turn")
        _close(rows, "fit", t_label, inp.toothed(_TOOTHED_REFERENCE)[1], t_unc * um,
               "the toothed rim's finer FEM (error = its own uncertainty)")
    return rows


def _envelope(inp: _Inputs, repeats: int) -> list[dict]:
    from profilegen.pipeline.design import SCENES
    from profilegen.profile.swept import boundary_distance, swept_region

    ref_env, ref_t, ref_label = inp.envelope_reference
    ref = np.asarray(ref_env.flank["boundary"])
    nm = _SCALE["nm"]
    g = inp.gearset.gear
    settings = [(s.chord_tol_mm, s.n_t, s.n_phi, s.name) for s in (SCENES[n] for n in ("sketch", "design", "verify"))]
    if not inp.quick:
        d, v = SCENES["design"], SCENES["verify"]
        settings += [(1e-5, d.n_t, d.n_phi, ""), (1e-8, v.n_t, v.n_phi, "")]
    settings.sort(key=lambda s: -s[0])
    rows = []
    for chord, n_t, n_phi, scene in settings:
        inp.step(f"envelope: traced, chord {chord:g} mm")
        env, t, n = _timed(lambda c=chord, a=n_t, b=n_phi: inp.trace(c, a, b), repeats, inp.long_s)
        inp.envelope(chord, n_t, n_phi, given=(env, t))  # the arcfit study fits its flank
        err = _boundary_distance_mm(np.asarray(env.flank["boundary"]), ref) * nm
        rows.append(_row("envelope", f"traced chord {chord:g} mm", t, n, err, reference=ref_label, scene=scene,
                         series="traced", note=f"n_t {n_t}, n_phi {n_phi}"))
    brute = [721] if inp.quick else [721, 4001]
    for n_phi in brute:
        inp.step(f"envelope: brute-force union of {n_phi} poses")
        region, t, n = _timed(lambda k=n_phi: swept_region(inp.design.tooth, inp.design.motion,
                                                           cs_teeth=g.circular_spline_teeth, waves=g.waves, n_phi=k),
                              repeats, inp.long_s)
        err = float(np.max(boundary_distance(ref, region))) * nm
        rows.append(_row("envelope", f"brute force {n_phi} poses", t, n, err, reference=ref_label,
                         scene="verify (cross-check)" if n_phi == 4001 else "", series="brute force",
                         note="reference vertices to the union's boundary (its notches)"))
    _close(rows, "envelope", ref_label, ref_t, ref_env.chord_tol_mm * nm,
           "error = its own uncertainty: its chord tolerance")
    return rows


def _arcfit(inp: _Inputs, repeats: int) -> list[dict]:
    from profilegen.profile.arcfit import clear_cache, fit_profile
    from profilegen.errors import ProfilegenError
    from profilegen.gearset import FIT_METHODS
    from profilegen.pipeline.design import FIT_MAX_ITER, SCENES

    ref_env, ref_t, env_label = inp.envelope_reference
    inp.step("arcfit: the reference flank")
    ref_flank = inp.flank(ref_env, ref_env.chord_tol_mm)
    ref_label = f"CS flank of the {env_label}"
    um = _SCALE["µm"]
    cad = inp.gearset.circular_spline.fit_method
    names = {"least_squares": "least squares", "minimax": "minimax", "one_sided": "one-sided"}
    rows = []
    for scene in (SCENES["sketch"], SCENES["design"], SCENES["verify"]):
        env, _ = inp.envelope(scene.chord_tol_mm, scene.n_t, scene.n_phi)
        flank = inp.flank(env, scene.chord_tol_mm)
        methods = FIT_METHODS if scene.name == "design" else (cad,)
        for method in methods:
            inp.step(f"arcfit: {method}, flank of chord {scene.chord_tol_mm:g} mm")
            try:
                fit, t, n = _timed(lambda m=method: fit_profile(flank, method=m, space_side="left",
                                                                max_iter=FIT_MAX_ITER),
                                   repeats, inp.long_s, setup=clear_cache)
            except ProfilegenError as exc:
                log.warning("arcfit study: %s on the %s flank left out: %s", method, scene.name, exc)
                continue
            err = float(np.max(np.abs(fit.distance(ref_flank)))) * um
            role = "CAD" if method == cad else "report"
            rows.append(_row("arcfit", f"{names[method]}, flank chord {scene.chord_tol_mm:g}", t, n, err,
                             reference=ref_label, scene=f"{scene.name} ({role})", series=names[method],
                             note=f"max deviation from its own {len(flank)} flank points "
                                  f"{fit.max_error_mm * um:.4g} µm"))
    design = SCENES["design"]
    flank = inp.flank(inp.envelope(design.chord_tol_mm, design.n_t, design.n_phi)[0], design.chord_tol_mm)
    inp.step(f"arcfit: minimax with 40 starts, flank of chord {design.chord_tol_mm:g} mm")
    try:
        fit, t, n = _timed(lambda: fit_profile(flank, method="minimax", space_side="left", starts=40, seed=1,
                                               max_iter=FIT_MAX_ITER), 1, inp.long_s, setup=clear_cache)
        rows.append(_row("arcfit", f"minimax, 40 starts, flank chord {design.chord_tol_mm:g}", t, n,
                         float(np.max(np.abs(fit.distance(ref_flank)))) * um, reference=ref_label, series="minimax",
                         note="the best arc–line–arc found: the floor of every arc–line–arc fit"))
    except ProfilegenError as exc:
        log.warning("arcfit study: the 40-start minimax fit left out: %s", exc)
    _close(rows, "arcfit", ref_label, ref_t, ref_env.chord_tol_mm * um,
           "error = its own uncertainty: the envelope's chord tolerance")
    return rows


def contact_mesh_label() -> str:
    """The product's contact FEM as the contact study's rows name it (its mesh defaults)."""
    from profilegen.contact.compliance import ComplianceMesh

    mesh = ComplianceMesh()
    return f"FEM {mesh.per_pitch}/{mesh.cs_per_pitch} col./pitch, {mesh.tooth_layers} layers"


def _contact(inp: _Inputs, repeats: int) -> list[dict]:
    from profilegen.contact import ContactInput
    from profilegen.contact.analysis import solve_contact
    from profilegen.contact.compliance import ContactCompliance
    _oracles_importable()
    from tests.oracles.naive_lp import solve_naive_lp
    from profilegen.errors import ProfilegenError

    d = inp.design
    torques = inp.torques_nm
    stations, = _defaults(solve_contact, "stations")
    from profilegen.contact.compliance import ComplianceMesh

    layers = ComplianceMesh().tooth_layers
    default_fem = contact_mesh_label()

    def build(points, cols, tooth_layers):
        return ContactCompliance.build(ContactInput.from_design(d), points.fs_point_mm, points.normal, points.tooth,
                                       points.cs_point_mm,
                                       mesh=dict(per_pitch=cols, cs_per_pitch=cols, tooth_layers=tooth_layers,
                                                 cs_tooth_layers=tooth_layers))

    ref_stations, ref_cols, ref_layers = (stations, 24, 6) if inp.quick else (9, 32, 6)
    ref_label = f"Lemke, {ref_stations} stations, FEM {ref_cols} col./pitch, {ref_layers} layers"
    inp.step(f"contact reference: {ref_label}")
    t0 = time.perf_counter()
    ref_pts = solve_contact(d, torques[:1], stations=ref_stations).points
    ref = solve_contact(d, torques, points=ref_pts, compliance=build(ref_pts, ref_cols, ref_layers))
    ref_time = time.perf_counter() - t0
    rot_ref = np.array([c.rotation_rad for c in ref.cases])
    force_ref = np.array([c.max_tooth_force_n for c in ref.cases])

    def errors(rotations, forces=None) -> tuple[float, str]:
        err = float(np.max(np.abs(np.asarray(rotations) / rot_ref - 1.0))) * 100.0
        if forces is None:
            return err, ""
        df = float(np.max(np.abs(np.asarray(forces) / force_ref - 1.0))) * 100.0
        return err, f"largest tooth force {df:.2g} % off"

    def add(method, result, t, n, scene="", series="", note=""):
        err, extra = errors([c.rotation_rad for c in result.cases], [c.max_tooth_force_n for c in result.cases])
        rows.append(_row("contact", method, t, n, err, reference=ref_label, scene=scene, series=series,
                         note="; ".join(x for x in (extra, note) if x)))

    rows = []
    inp.step(f"contact: Lemke, {stations} stations, {default_fem}")
    res, t, n = _timed(lambda: solve_contact(d, torques), repeats, inp.long_s)
    add(f"Lemke, {stations} stations, {default_fem}", res, t, n, scene="design, verify", series="FEM",
        note="the whole stage: points, FEM influence coefficients, solves")
    pts, comp = res.points, res.compliance
    for solver, name in (("lemke", "Lemke"), ("active_set", "active-set QP")):
        inp.step(f"contact: {name}, FEM reused")
        out, t, n = _timed(lambda s=solver: solve_contact(d, torques, points=pts, compliance=comp, solver=s),
                           repeats, inp.long_s)
        add(f"{name}, FEM reused", out, t, n,
            note="solves and ball settling only" + ("; the pipeline's cross-check" if solver == "active_set" else ""))
    inp.step("contact: seed 000's naive LP, FEM reused")
    try:
        def naive():
            return [solve_naive_lp(comp.matrix_mm_per_n, pts.theta_rad, pts.lever_mm, tq / pts.zones * 1e3)
                    for tq in torques]

        sols, t, n = _timed(naive, repeats, inp.long_s)
        err, _ = errors([s.phi_rad for s in sols])
        rows.append(_row("contact", "naive LP (seed 000), FEM reused", t, n, err, reference=ref_label,
                         note="balls held; a phase-1 LP vertex, not a contact solution (seed 000's LP as published)"))
    except ProfilegenError as exc:
        log.warning("contact study: the naive LP left out: %s", exc)
    inp.step("contact: Lemke, 3 stations")
    out, t, n = _timed(lambda: solve_contact(d, torques, stations=3), repeats, inp.long_s)
    add(f"Lemke, 3 stations, {default_fem}", out, t, n, series="stations")
    unc = None
    if not inp.quick:
        for cols, tl in ((24, layers), (24, 6)):
            inp.step(f"contact: FEM {cols} columns per pitch (FS and CS), {tl} tooth layers")
            out, t, n = _timed(lambda c=cols, k=tl: solve_contact(d, torques, points=pts,
                                                                  compliance=build(pts, c, k)), repeats, inp.long_s)
            add(f"Lemke, {stations} stations, FEM {cols} col./pitch, {tl} layers", out, t, n, series="FEM")
        unc = rows[-1]["error"]
    _close(rows, "contact", ref_label, ref_time, unc,
           "error = its own uncertainty: its change from the last mesh refinement (an upper estimate)"
           if unc is not None else "uncertainty not estimated with --quick")
    return rows


def _stress(inp: _Inputs, repeats: int) -> list[dict]:
    from profilegen.stress import solve_stress
    _oracles_importable()
    from tests.oracles.morley import clamp_sigma_r_mpa, richardson, solve_morley
    from profilegen.stress.plate import cup_bottom_stress

    inp.step("stress: the design scene's cup-bottom edge")
    res = solve_stress(inp.design)
    edge = res.cup_bottom[0].edge
    cup, mat = inp.gearset.cup, inp.gearset.material
    plate = dict(boss_radius_mm=cup.boss_radius_mm, thickness_mm=cup.bottom_thickness_mm,
                 youngs_modulus_mpa=mat.youngs_modulus_mpa, poisson_ratio=mat.poisson_ratio)

    pair = (48, 64) if inp.quick else (96, 128)
    inp.step(f"stress reference: Morley plate, {pair[0]} and {pair[1]} radial divisions")
    t0 = time.perf_counter()
    coarse, fine = (solve_morley(edge, radial_divisions=nr, **plate) for nr in pair)
    ref_time = time.perf_counter() - t0
    sigma_ref = richardson(coarse, fine, "max_clamp_sigma_r_mpa")
    unc = abs(sigma_ref - fine.max_clamp_sigma_r_mpa) / abs(sigma_ref) * 100.0
    ref_label = f"Morley plate, Richardson {pair[0]}/{pair[1]} radial divisions"

    def err(sigma):
        return abs(sigma / sigma_ref - 1.0) * 100.0

    rows = []
    for model, scene in (("consistent", "sketch, design, verify"), ("seed002", "")):
        inp.step(f"stress: {model} plate")
        out, t, n = _timed(lambda m=model: cup_bottom_stress(edge, model=m, **plate), repeats, inp.long_s)
        sigma = clamp_sigma_r_mpa(out.field, cup.boss_radius_mm)
        note = (f"one plate solution; the whole stress stage (tooth ring, {len(res.cup_bottom) + 1} plate cases, "
                f"diaphragm) took {res.time_s:.3g} s" if model == "consistent"
                else "the paper's f(r)·w(φ), not a solution of the plate (seed 002 as published)")
        rows.append(_row("stress", f"{model} plate", t, n, err(sigma), reference=ref_label, scene=scene, note=note))
    for nr in (8, 16, 32) if inp.quick else (8, 16, 32, 64):
        inp.step(f"stress: Morley plate, {nr} radial divisions")
        sol, t, n = _timed(lambda k=nr: solve_morley(edge, radial_divisions=k, **plate), repeats, inp.long_s)
        rows.append(_row("stress", f"Morley {nr} div", t, n, err(sol.max_clamp_sigma_r_mpa), reference=ref_label,
                         series="Morley",
                         note=f"{sol.radial_divisions}×{sol.angular_divisions} cells, {sol.dofs} dofs"))
    _close(rows, "stress", ref_label, ref_time, unc,
           "error = its own uncertainty: the Richardson step (an upper estimate)")
    return rows


_STUDIES = {"rim": _rim, "fit": _fit, "envelope": _envelope, "arcfit": _arcfit, "contact": _contact,
            "stress": _stress}


def stage_benchmark(gearset, *, quick: bool, repeats: int, progress=None, stages=STAGES,
                    designs=None) -> list[dict]:
    """One row per (stage, method or setting) — see the module docstring — with the keys of
    :data:`FIELDS`: ``time_s`` (median of up to ``repeats`` runs of that stage alone),
    ``error`` in ``error_unit`` (against ``reference``, of what ``error_measure`` says),
    ``scene`` (the scenes that use this tier, "" if none), ``role`` ("scene tier", "option"
    or "reference"), ``series`` (settings of one family, for the chart) and ``note``.

    ``quick``: coarser references and no toothed-rim FEM (≈ 1 min on two cores instead of ≈ 5).
    ``stages``: which studies to run (a subset of :data:`STAGES`). ``designs``: already
    computed designs by scene name (``"design"``: the inputs of the envelope, arcfit, contact
    and stress studies and the fit's samples; ``"verify"``: its toothed-rim solutions);
    computed here when missing. ``progress(text)`` is called before each step.
    """
    import scipy.linalg  # noqa: F401 — scipy's own OpenBLAS must be loaded for the limit to reach it
    from threadpoolctl import threadpool_limits

    if not isinstance(quick, bool):
        raise ValueError(f"quick = {quick!r}: must be True or False")
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 1:
        raise ValueError(f"repeats = {repeats!r}: must be a whole number ≥ 1")
    if isinstance(stages, str):
        stages = (stages,)
    unknown = [s for s in stages if s not in STAGES]
    if unknown or not stages:
        raise ValueError(f"stages = {stages!r}: each must be one of {', '.join(STAGES)}")
    step = progress or (lambda text: None)
    inp = _Inputs(gearset, designs, quick, step)
    rows = []
    with threadpool_limits(limits=1, user_api="blas"):
        for stage in STAGES:
            if stage not in stages:
                continue
            if stage in ("rim", "fit", "contact") and gearset.gear.waves != 2:
                log.info("%s study skipped: its FEM needs gear.waves = 2, got %d", stage, gearset.gear.waves)
                continue
            t0 = time.perf_counter()
            rows += _STUDIES[stage](inp, repeats)
            log.info("%s study: %.1f s", stage, time.perf_counter() - t0)
    return rows


# --------------------------------------------------------------------------- output


def write_stage_benchmark(rows: list[dict], out_dir, *, title: str = "") -> list[Path]:
    """``stages.csv`` (the rows, columns :data:`FIELDS`) and ``stages.png`` (one log–log panel
    of time against error per stage; filled: tiers a scene uses, hollow: other settings,
    star and dotted line: the reference's own uncertainty) in ``out_dir``."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from profilegen.output.export import atomic_write

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    with atomic_write(out / "stages.csv", "w") as f:
        w = csv.DictWriter(f, fieldnames=list(FIELDS), extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if isinstance(r.get(k), float) and not math.isfinite(r[k]) else r.get(k, ""))
                        for k in FIELDS})

    stages = [s for s in STAGES if any(r["stage"] == s for r in rows)]
    ncols = 3 if len(stages) > 4 else max(1, min(2, len(stages)))
    nrows = max(1, math.ceil(len(stages) / ncols))
    fig = Figure(figsize=(6.2 * ncols, 5.0 * nrows), layout="constrained")
    FigureCanvasAgg(fig)
    axes = np.atleast_1d(fig.subplots(nrows, ncols, squeeze=False)).ravel()
    labels = [_panel(ax, [r for r in rows if r["stage"] == stage], stage) for ax, stage in zip(axes, stages)]
    for ax in axes[len(stages):]:
        ax.set_axis_off()
    fig.suptitle(title or "speed against accuracy per stage (median times; errors against converged references)",
                 fontsize=11)
    fig.draw_without_rendering()  # the layout first: labels are placed inside the final axes
    fig.set_layout_engine("none")
    for ax, text in zip(axes, labels):
        _place_labels(ax, text)
    with atomic_write(out / "stages.png", "wb") as f:
        fig.savefig(f, dpi=110, format="png")
    return [out / "stages.csv", out / "stages.png"]


def _panel(ax, rows: list[dict], stage: str) -> list:
    """Draw one stage's points; return their labels (placed once the layout is fixed)."""
    unit = rows[0]["error_unit"]
    points = [r for r in rows if r["role"] != "reference" and math.isfinite(r["time_s"]) and math.isfinite(r["error"])]
    refs = [r for r in rows if r["role"] == "reference"]
    positive = [r["error"] for r in points if r["error"] > 0]
    floor = (min(positive) / 10.0) if positive else 1e-12
    # the axes span the points; a reference uncertainty far below them is written, not drawn
    shown = [r for r in refs if math.isfinite(r["error"]) and r["error"] > 0 and r["error"] >= floor / 10.0]
    ys = [max(r["error"], floor) for r in points] + [r["error"] for r in shown]
    ts = [r["time_s"] for r in points] + [r["time_s"] for r in shown if math.isfinite(r["time_s"])]
    ax.set_xscale("log")
    ax.set_yscale("log")
    if ys and ts:
        ax.set_xlim(min(ts) / 3.0, max(ts) * 20.0)
        ax.set_ylim(min(ys) / 4.0, max(ys) * 6.0)
    series = list(dict.fromkeys(r["series"] for r in points if r["series"]))
    colours = {s: f"C{i % 10}" for i, s in enumerate(series)}
    for s in series:  # a line through each family of settings, from the coarsest (largest error)
        sel = sorted((r for r in points if r["series"] == s), key=lambda r: -r["error"])
        if len(sel) > 1:
            ax.plot([r["time_s"] for r in sel], [max(r["error"], floor) for r in sel], "-", color=colours[s],
                    lw=0.8, alpha=0.6)
    labels = []
    for r in points:
        c = colours.get(r["series"], "0.3")
        y = max(r["error"], floor)
        used = r["role"] == "scene tier"
        ax.plot(r["time_s"], y, "o", ms=8 if used else 5, color=c, mfc=c if used else "white",
                mew=1.6 if used else 1.0, zorder=3)
        labels.append(((r["time_s"], y), r["method"] + (f"\n[{r['scene']}]" if used else ""), used))
    for r in shown:
        ax.axhline(r["error"], color="0.5", lw=0.7, ls=":")
        if math.isfinite(r["time_s"]):
            ax.plot(r["time_s"], r["error"], "*", ms=10, color="0.45", zorder=3)
            text = "reference (its uncertainty)" if len(refs) == 1 else f"reference (its uncertainty):\n{r['method']}"
            labels.append(((r["time_s"], r["error"]), text, None))
    hidden = [r for r in refs if r not in shown]
    title = f"{stage}: vs {'; '.join(r['reference'] for r in refs)}"
    for r in hidden:
        which = "reference" if len(refs) == 1 else r["method"]
        title += (f"\n({which}: uncertainty not estimated)" if not math.isfinite(r["error"]) else
                  f"\n({which}: uncertainty {r['error']:.2g} {unit}, below the axis)")
    ax.set_title(title, fontsize=8)
    ax.set_xlabel("time of the stage alone (s, median)", fontsize=8)
    ax.set_ylabel(f"{rows[0]['error_measure']} ({unit})", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(True, which="both", color="0.9", lw=0.5)
    return labels


# label offsets from the point (points right, up; alignment), tried in this order
_OFFSETS = tuple((dx, dy, ha) for dy in (3, -11, 12, -20, 21, -29, 30, -38, 39, -47, 52, -60, 66, -74)
                 for dx, ha in ((6, "left"), (-6, "right"), (24, "left"), (-24, "right")))


def _place_labels(ax, labels, fontsize: float = 6.5) -> None:
    """Annotate each (point, text, used) at the first of a few offsets around its point where
    the label stays inside the axes and overlaps no earlier label nor any point; where there
    is none, where it overlaps least (display coordinates: the layout and the axes limits
    must be final). A thin leader joins label and point."""
    fig = ax.figure
    px = fig.dpi / 72.0
    frame = ax.get_window_extent()
    placed = []  # (x0, y0, x1, y1) in display pixels
    dots = [tuple(ax.transData.transform(xy)) for xy, _, _ in labels]
    pad = 4.0 * px

    def overlap(a, b):
        return max(0.0, min(a[2], b[2]) - max(a[0], b[0])) * max(0.0, min(a[3], b[3]) - max(a[1], b[1]))

    for (xy, text, used), (x, y) in zip(labels, dots):
        w = 0.56 * fontsize * px * max(len(line) for line in text.split("\n"))
        h = 1.3 * fontsize * px * (text.count("\n") + 1)
        best, best_cost = None, math.inf
        for dx, dy, ha in _OFFSETS:
            x0 = x + dx * px if ha == "left" else x + dx * px - w
            box = (x0, y + dy * px, x0 + w, y + dy * px + h)
            inside = (max(box[0], frame.x0), max(box[1], frame.y0), min(box[2], frame.x1), min(box[3], frame.y1))
            cost = 10.0 * (w * h - max(0.0, inside[2] - inside[0]) * max(0.0, inside[3] - inside[1]))
            cost += sum(overlap(box, b) for b in placed)
            cost += sum(4.0 * pad * pad for (u, v) in dots if (u, v) != (x, y)
                        and box[0] - pad < u < box[2] + pad and box[1] - pad < v < box[3] + pad)
            cost += 1e-3 * (abs(dx) + abs(dy))  # nearer is better, all else equal
            if cost < best_cost:
                best, best_cost = (dx, dy, ha, box), cost
            if cost < 1.0:
                break
        dx, dy, ha, box = best
        placed.append(box)
        ax.annotate(text, xy, textcoords="offset points", xytext=(dx, dy), ha=ha, va="bottom", fontsize=fontsize,
                    fontweight="bold" if used else "normal",
                    color="black" if used else ("0.35" if used is None else "0.25"),
                    arrowprops=dict(arrowstyle="-", lw=0.4, color="0.6", shrinkA=0, shrinkB=4))


def format_stage_rows(rows: list[dict]) -> str:
    """The rows as plain-text tables, one per stage (for the command line)."""
    def fmt_time(t):
        if not math.isfinite(t):
            return "—"
        return f"{t * 1e6:.0f} µs" if t < 1e-3 else (f"{t * 1e3:.1f} ms" if t < 1.0 else f"{t:.2f} s")

    def fmt_err(e, unit):
        return "—" if not math.isfinite(e) else f"{e:.3g} {unit}"

    out = []
    for stage in STAGES:
        sel = [r for r in rows if r["stage"] == stage]
        if not sel:
            continue
        refs = list(dict.fromkeys(r["reference"] for r in sel))
        tag = {ref: chr(ord("a") + i) for i, ref in enumerate(refs)}
        out.append(f"{stage} — {sel[0]['error_measure']} ({sel[0]['error_unit']})")
        for ref in refs:
            out.append(f"  reference{' ' + tag[ref] if len(refs) > 1 else ''}: {ref}")
        width = max(len(r["method"]) for r in sel)
        scene_w = max(len("(reference)"), max(len(r["scene"]) for r in sel))
        out.append(f"  {'method':{width}s}  {'scene':{scene_w}s}  {'time':>9s}  {'error':>12s}  note")
        for r in sel:
            method = r["method"]
            scene = r["scene"] if r["role"] != "reference" else "(reference)"
            ref_tag = f"[{tag[r['reference']]}] " if len(refs) > 1 else ""
            out.append(f"  {method:{width}s}  {scene:{scene_w}s}  {fmt_time(r['time_s']):>9s}  "
                       f"{fmt_err(r['error'], r['error_unit']):>12s}  {ref_tag}{r['note']}")
        out.append("")
    return "\n".join(out).rstrip()
