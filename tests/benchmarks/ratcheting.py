"""Ratcheting torque estimate (issue 16 item 4) and its bad inputs.

    python tests/benchmarks/ratcheting.py --verify [--gaps 0.2,0.5,0.84,1.2] [sets]   (the verify scene's
        estimate and the climb's path; --gaps: again with the climb's teeth cut at each gap, in modules)
    python tests/benchmarks/ratcheting.py [--climb-only] [--ring-scale 2,4,8] [--shift 0.25,0.5,0.75]
        [--positions 8] [--face 2,4] [--parts] [--perturb 1,-1,100,-100]
        [--friction 0,0.05,0.1,0.15 [--sliding static,forward,backward] [--friction-only]] [profiles/...]

Studies (engineer P3, issue 16 item 4; each adds its table after the climb):
``--positions N``: the climb at N wave-generator positions evenly over one tooth passage
(each tooth at 2πi/z1 − f·2π/z1, f = k/N), and their minimum — the gear running under load
meets every position (``--positions-friction μ --positions-sliding S``: with friction). ``--face N1,N2``: the climb at the 3D cup's face-end sections
(press_cup; each section's change from the design section added to the design's
deformation, contact.climb.section_inputs), each as if the whole face were that section, and
over N independent slices sharing the rotation (contact.climb.SlicedClimb). ``--parts``: the
force-weighted retreat split into the CS ring, the Hertz balls and the FEM (rim, race, tooth)
along the path, and the climb with rigid balls, without the CS ring, with neither, with every
ball within the wrap only (ball_supports="window"; the default "all": every ball one-sided at
its no-load gap, as the contact stage), and with the FS tip-corner normal held
at the flank's (the model before P3). ``--perturb D1,D2`` (nm; engineer P3b): the climb again
with the CS flank moved by each D along its normal (every gap + D; the first rotation and the
step grid move with it) and the step grid alone ×(1 ± 1 %), each estimate's change from the
unperturbed one — the estimate must be continuous in the geometry. ``--friction M1,M2``
(engineer D): the climb with Coulomb friction μ on the tooth contacts for each ``--sliding``
sense (static pull-out: every tooth sliding out of its space; forward: running with the wave
generator driving the load, the sense per station from the kinematics; backward: the load
driving; forward-elastic / backward-elastic: the same with the change of the teeth's retreat
along the zone added to the sliding), each estimate against the frictionless one and the
catalogue; then, for the largest
μ running forward, at the path's last point: the load share of the stations sliding into /
out of their spaces, the share whose sliding the teeth's elastic retreat s(φ) (as the tooth
runs through the loaded zone) would reverse (the kinematic sense is an assumption), and the
smallest eigenvalue of the symmetric part of S on the loaded stations (> 0: S is a P-matrix
there, Lemke's method has the one solution). ``--hysteresis M1,M2``: the mesh's φ(T) loading
(teeth sliding out) and unloading (sliding in) with friction μ, the loop's width at T1, T2
and the rated torque. ``--friction-only``: only the friction studies.

The climb (profilegen.contact.climb, the default estimate since helper E2): per set the
linear estimate (climb=False, E's ladder), the climb's estimate with its path (rotation,
torque, force-weighted retreat, margin, pressure angle, load share on the FS tip corners),
CPU time of each call, and the catalogue's value (contact.catalogue.catalogue_row, CSF
table 4). ``--ring-scale``: the climb again with the CS ring's compliance × each factor (how
much more radial compliance outside the contact model the climb would need to ratchet at
the catalogue's torque). ``--shift``: the climb with the wave generator that fraction of a
tooth passage on (each tooth at 2πi/z1 − f·2π/z1). Sets: seed000_csf40, csf32_100, the default set.

For each gear set (default: seed000_csf40 and the default set; design scene, no contact or
stress in the design run): profilegen.contact.ratchet.ratcheting_torque with the whole model
(contact FEM + Hertz ball springs + the CS as a free ring), without the CS ring, and with rigid
balls and no ring (the contact model as it is): per torque the loaded teeth's force-weighted
depth h̄, separation Δr̄ and margin (the criterion), and the most loaded tooth, its depth h,
its radial separation Δr (FS side, CS ring), its pressure angle, whether the contact could
carry the torque; the estimate, its extrapolations and the ratio to the rated torque. The
catalogue's ratcheting torque for the size (CSF-40-100) is not in the repository, the seeds
or the searchable catalogue pages: the comparison is left out (None).
Then the bad inputs: zero torque, a torque beyond the estimate (flagged), balls that do not
fit the bearing section.
"""

from __future__ import annotations

import dataclasses
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.contact.chain import BallBearing  # noqa: E402
from profilegen.contact.ratchet import (  # noqa: E402
    BearingFitError, RatchetingError, check_bearing_fits, ratcheting_torque)

SETS = [ROOT / "profiles" / "seed000_csf40.toml", ROOT / "profiles" / "csf32_100.toml", Path(pg.default_gearset_path())]
ARGS = {"climb_only": False, "ring_scale": [], "shift": [], "positions": 0, "face": [], "parts": False, "perturb": [],
        "friction": [], "sliding": ["static", "forward", "backward", "forward-elastic", "backward-elastic"],
        "friction_only": False, "hysteresis": [], "positions_friction": 0.0, "positions_sliding": "forward-elastic"}


def _climb_setup(gs, design, **kw):
    """A DesignClimb of the design as ratcheting_torque builds it (Hertz balls, the free CS ring)."""
    import math

    import numpy as np

    from profilegen.contact import ratchet
    from profilegen.contact.climb import DesignClimb
    from profilegen.contact.inputs import ContactInput

    inputs = kw.pop("inputs", None) or ContactInput.from_design(design)
    r_mean, thick, width, _ = ratchet._cs_ring_section(gs, ContactInput.from_design(design))

    def factory(phis):
        ang = np.concatenate([phis, phis + math.pi])
        return ratchet.cs_ring_radial_compliance(ang, phis, mean_radius_mm=r_mean, thickness_mm=thick, width_mm=width,
                                                 youngs_modulus_mpa=float(gs.material.youngs_modulus_mpa))
    kw.setdefault("ball_supports", "all")  # as ratcheting_torque
    return DesignClimb(inputs, side=1, stations=9, max_gap_mm=ratchet.CLIMB_GAP_PER_MODULE * float(gs.gear.module_mm),
                       race_thickness_mm=None,
                       bearing=BallBearing.from_gearset(gs), ring_factory=factory, **kw)


def _follow(model, rated):
    from threadpoolctl import threadpool_limits

    from profilegen.contact.climb import SlicedClimb, climb

    with threadpool_limits(limits=1, user_api="blas"):
        parts = model.models if isinstance(model, SlicedClimb) else [model]
        first = [m.first_rotation(rated) for m in parts]
        theta, phi = min(f[0] for f in first), max(f[1] for f in first)
        step = 0.5 * max(phi - theta, 1e-9)
        return climb(model, theta + step, step, max_torque_nm=20000.0)


def positions_run(gs, design) -> None:
    import math

    import numpy as np

    n = ARGS["positions"]
    lad = [gs.torque.rated_nm, 2 * gs.torque.rated_nm]
    mu, sliding = ARGS["positions_friction"], ARGS["positions_sliding"]
    print(f"\n-- the climb at {n} wave-generator positions over one tooth passage"
          + (f", friction μ = {mu:g} ({sliding})" if mu else ""))
    out = []
    for f in np.arange(n) / n:
        t0 = time.process_time()
        r = ratcheting_torque(design, options=dict(torques_nm=lad, climb_friction=mu, climb_sliding=sliding,
                                                   climb_shift_rad=-f * 2 * math.pi / gs.gear.flexspline_teeth))
        out.append(r.torque_nm)
        print(f"  {f:.3f} of a tooth passage: {r.torque_nm:8.1f} N·m ({r.climb['criterion']}), "
              f"{time.process_time() - t0:.1f} s CPU")
    t = np.array(out)
    print(f"  minimum {t.min():.1f} N·m at {np.argmin(t) / n:.3f}, maximum {t.max():.1f}, minimum / mean {t.min() / t.mean():.3f}")


def face_run(gs, design) -> None:
    import numpy as np

    from profilegen.contact.climb import SlicedClimb, section_inputs
    from profilegen.contact.coning_sections import cup_sections
    from research.face_load import slice_positions
    from profilegen.contact.inputs import ContactInput
    from profilegen.rim.cup.contact import press_cup

    inputs = ContactInput.from_design(design)
    cup = press_cup(gs)
    b, z0 = float(gs.cup.face_width_mm), float(gs.cup.length_mm)
    rated = float(gs.torque.rated_nm)
    print(f"\n-- across the face (3D cup press_cup, face {b:g} mm, design section z0 = {z0:g} mm)")
    ends = np.array([z0 - 0.5 * b, z0 + 0.5 * b])
    secs = cup_sections(cup, np.r_[z0, ends])
    for z, sec in zip(ends, secs[1:]):
        dw = float(sec.evaluate(np.zeros(1), order=0)[0][0, 0] - secs[0].evaluate(np.zeros(1), order=0)[0][0, 0])
        t0 = time.process_time()
        m = _climb_setup(gs, design, inputs=section_inputs(inputs, sec, secs[0]))
        path = _follow(m, rated)
        print(f"  section z = {z:g} mm (ω on the major axis {dw * 1e3:+.1f} µm against the design section), the whole "
              f"face so: {path.torque_nm:.1f} N·m ({path.criterion}); corner depth h̄ {np.mean(m.depth_mm):.3f} mm; "
              f"{time.process_time() - t0:.1f} s CPU")
    for n in ARGS["face"]:
        z = slice_positions(b, n, z0)
        secs = cup_sections(cup, np.r_[z0, z])
        t0 = time.process_time()
        models = [_climb_setup(gs, design, inputs=section_inputs(inputs, sec, secs[0]), width_fraction=1.0 / n)
                  for sec in secs[1:]]
        for coupled in (False, True):
            t1 = time.process_time()
            sliced = SlicedClimb(models, coupled=coupled)
            path = _follow(sliced, rated)
            last = path.points[-1]
            share = [float(np.sum(last.force_n[a:c])) for a, c in zip(sliced._pt_off[:-1], sliced._pt_off[1:])]
            shared = sliced.shared_retreat(last.retreat_mm)
            margin = [float(np.sum(last.force_n[a:c] * (sliced.depth_mm - shared)[sliced.slot[a:c]])
                            / max(np.sum(last.force_n[a:c]), 1e-300)) for a, c in zip(sliced._pt_off[:-1], sliced._pt_off[1:])]
            print(f"  {n} slices at z = {np.round(z, 2).tolist()} mm, "
                  f"{'the face held straight (coupled)' if coupled else 'independent'}: {path.torque_nm:.1f} N·m "
                  f"({path.criterion}); at the last point the slices' shares of the normal force "
                  f"{np.round(np.array(share) / sum(share), 3).tolist()}, their force-weighted margins h − s "
                  f"{np.round(margin, 3).tolist()} mm; {time.process_time() - t1 + (t1 - t0 if not coupled else 0):.1f} s CPU")


def parts_run(gs, design) -> None:
    import numpy as np

    rated = float(gs.torque.rated_nm)
    print("\n-- the retreat's parts along the climb (force-weighted over the loaded teeth, µm)")
    m = _climb_setup(gs, design)
    path = _follow(m, rated)
    print(f"  {'T (N·m)':>8} {'retreat':>8} {'CS ring':>8} {'Hertz':>8} {'FEM':>8} {'ball gaps':>9}  balls")
    for p in path.points[::2] + (path.points[-1],):
        st = p.state
        m.geometry(p.retreat_mm, p.phi_rad)
        _, pfs_h, pcs = m._effective(*m._matrices(st.active, st.springs)[:2])
        _, pfs_r, _ = m._effective(*m._matrices(st.active, None)[:2])
        f = p.force_n
        w = np.bincount(m.slot, weights=f, minlength=m.teeth.size)
        w = w / w.sum()
        ring, hertz, fem = w @ (pcs @ f), w @ ((pfs_h - pfs_r) @ f), w @ (pfs_r @ f)
        gaps = w @ np.broadcast_to(st.offset, w.shape)  # the closed balls' no-load gaps (springs as loaded)
        print(f"  {p.torque_nm:8.0f} {w @ p.retreat_mm * 1e3:8.1f} {ring * 1e3:8.1f} {hertz * 1e3:8.1f} {fem * 1e3:8.1f} "
              f"{gaps * 1e3:9.1f}  "
              f"{int(st.active.sum())}/{st.active.size}")
    last = path.points[-1]
    per = np.bincount(m.slot, weights=last.force_n, minlength=m.teeth.size)
    print(f"  the loaded teeth at the last point ({last.torque_nm:.0f} N·m): tooth, φ (°), corner depth h (mm), retreat s "
          f"(mm), margin h − s, share of the normal force")
    for k in np.flatnonzero(per > 0.01 * per.max()):
        print(f"    {int(m.teeth[k]):4d} {np.degrees(m.phis[k]):7.1f} {m.depth_mm[k]:7.3f} {last.retreat_mm[k]:7.3f} "
              f"{m.depth_mm[k] - last.retreat_mm[k]:7.3f} {per[k] / per.sum():6.3f}")
    lad = [rated, 2 * rated]
    for label, kw in (("rigid balls", {"bearing": None}), ("no CS ring", {"cs_ring": False}),
                      ("rigid balls, no CS ring", {"bearing": None, "cs_ring": False}),
                      ("the balls within the wrap only (the window)", {"climb_ball_supports": "window"}),
                      ("the FS tip-corner normal held at the flank's", {"climb_corner_normal": False})):
        t0 = time.process_time()
        r = ratcheting_torque(design, options=dict(torques_nm=lad, **kw))
        print(f"  {label}: {r.torque_nm:.1f} N·m ({r.climb['criterion']}), {time.process_time() - t0:.1f} s CPU")


def _catalogue(gs):
    """The catalogue's ratcheting torque for the set's size and ratio, as the pipeline takes it."""
    from profilegen.contact.chain import catalogue_for

    row = catalogue_for(gs)
    if row is None or row.get("ratcheting_torque_nm") is None:
        return None
    return {"torque_nm": row["ratcheting_torque_nm"], "source": row.get("ratcheting_source")}


def climb_run(gs, design) -> None:
    cat = _catalogue(gs)
    runs = [(1.0, 0.0)] + [(x, 0.0) for x in ARGS["ring_scale"]] + [(1.0, x) for x in ARGS["shift"]]
    for scale, shift in runs:
        t0 = time.process_time()
        r = ratcheting_torque(design, catalogue=cat, options=dict(
            climb_ring_scale=scale, climb_shift_rad=-shift * 2 * 3.141592653589793 / gs.gear.flexspline_teeth))
        cpu = time.process_time() - t0
        c = r.climb
        print(f"\n-- climb (CS ring x {scale:g}, wave generator {shift:g} tooth passage on): {cpu:.2f} s CPU; {c['teeth']} teeth, {c['points']} stations; "
              f"criterion {c['criterion']}")
        print(f"{'phi (mrad)':>10} {'T (N·m)':>9} {'retreat µm':>10} {'margin':>7} {'alpha °':>7} {'corner':>6}")
        for row in zip(c["phi_path_rad"], c["torque_path_nm"], c["mean_retreat_mm"], c["margin_mm"],
                       c["pressure_angle_deg"], c["corner_share"]):
            phi, t, sr, mg, a, co = row
            print(f"{phi * 1e3:10.4f} {t:9.1f} {sr * 1e3:10.1f} {mg:7.3f} {a:7.1f} {co:6.2f}")
        ratio = "—" if r.ratio_to_catalogue is None else f"{r.ratio_to_catalogue:.2f}"
        print(f"ratcheting torque {r.torque_nm:.4g} N·m (climb; linear diagnostics {r.torque_linear_nm:.4g}); "
              f"catalogue {None if cat is None else cat['torque_nm']} N·m; estimate / catalogue {ratio}")
        for w in r.warnings:
            if w.startswith("climb") or "climb" in w:
                print("  warning:", w)


def perturb_run(gs, design) -> None:
    """The estimate's change for the CS flank moved by each --perturb (nm), and for the step grid ×(1 ± 1 %)."""
    import profilegen.contact.climb as climb_module

    geometry, follow = climb_module.DesignClimb.geometry, climb_module.climb
    shift = {"gap": 0.0, "grid": 1.0}

    def moved_geometry(self, s, phi=0.0):
        gap, lever = geometry(self, s, phi)
        return gap + shift["gap"], lever

    def scaled_climb(model, phi_start, phi_step, **kw):
        return follow(model, phi_start * shift["grid"], phi_step * shift["grid"], **kw)

    climb_module.DesignClimb.geometry, climb_module.climb = moved_geometry, scaled_climb
    try:
        base = ratcheting_torque(design).torque_nm
        print(f"\n-- perturbations: unperturbed {base:.2f} N·m")
        cases = [(d, 1.0) for d in ARGS["perturb"]] + [(0.0, 0.99), (0.0, 1.01)]
        for d, g in cases:
            shift["gap"], shift["grid"] = d * 1e-6, g
            r = ratcheting_torque(design)
            print(f"  flank {d:+g} nm, step x{g:g}: {r.torque_nm:.2f} N·m ({100 * (r.torque_nm / base - 1):+.3f} %), "
                  f"{r.climb['criterion']}")
    finally:
        climb_module.DesignClimb.geometry, climb_module.climb = geometry, follow


def friction_run(gs, design) -> None:
    """The climb with Coulomb friction (--friction, --sliding): the estimate per μ and sense."""
    cat = _catalogue(gs)
    lad = [gs.torque.rated_nm, 2 * gs.torque.rated_nm]
    print("\n-- friction on the tooth contacts (Coulomb μ; the force on the CS along n + μσt, the gap along n)")
    print(f"  {'μ':>5} {'sliding':>9} {'T (N·m)':>9} {'/ μ = 0':>8} {'/ catalogue':>11} {'criterion':>12} {'α end °':>7} "
          f"{'CPU s':>6}")
    base = None
    for mu in ARGS["friction"]:
        for sliding in (["static"] if mu == 0.0 else ARGS["sliding"]):
            t0 = time.process_time()
            r = ratcheting_torque(design, catalogue=cat,
                                  options=dict(torques_nm=lad, climb_friction=mu, climb_sliding=sliding))
            cpu = time.process_time() - t0
            base = r.torque_nm if mu == 0.0 else base
            rel = "—" if base is None else f"{r.torque_nm / base:.3f}"
            ratio = "—" if r.ratio_to_catalogue is None else f"{r.ratio_to_catalogue:.2f}"
            print(f"  {mu:5.3g} {sliding if mu else '—':>9} {r.torque_nm:9.1f} {rel:>8} {ratio:>11} "
                  f"{r.climb['criterion']:>12} {r.climb['pressure_angle_deg'][-1]:7.1f} {cpu:6.1f}", flush=True)
    mu = max(ARGS["friction"], default=0.0)
    for sliding in ("forward", "forward-elastic"):
        if mu > 0.0 and sliding in ARGS["sliding"]:
            friction_check(gs, design, mu, sliding)


def hysteresis_run(gs, design) -> None:
    """--hysteresis M1,M2: the mesh's rotation φ(T) loading (every tooth sliding out of its
    space: "static") and unloading (sliding back in: "unloading") with friction μ, and the
    loop's width at T1, T2 and the rated torque (the climb's φ: mesh, balls, CS ring — no cup,
    no chain). Sliding without stick: at T → 0 every contact opens and the loop closes."""
    import math

    import numpy as np
    from threadpoolctl import threadpool_limits

    from profilegen.contact.chain import catalogue_for
    from profilegen.contact.climb import climb

    rated = float(gs.torque.rated_nm)
    row = catalogue_for(gs) or {}
    marks = [row.get("T1_nm") or 0.2 * rated, row.get("T2_nm") or 0.74 * rated, rated]
    arcmin = 180.0 * 60.0 / math.pi
    print(f"\n-- hysteresis of the mesh from friction: φ(T) loading − unloading at T = {marks} N·m (arcmin)")
    base = _climb_setup(gs, design)
    theta, phi = base.first_rotation(rated)
    step = 0.125 * (phi - theta)

    def curve(model):
        with threadpool_limits(limits=1, user_api="blas"):
            path = climb(model, theta + 2.0 * step, step, grow=1.0, max_steps=60, refine=0, max_torque_nm=1.05 * rated)
        t, f = path.column("torque_nm"), path.column("phi_rad")
        if t.max() < max(marks):
            raise RuntimeError(f"hysteresis: the path reached only {t.max():.4g} N·m ({path.criterion})")
        return np.interp(marks, t, f)

    ref = curve(base)
    print(f"  μ = 0: φ = {np.round(ref * arcmin, 4).tolist()} arcmin")
    for mu in ARGS["hysteresis"]:
        t0 = time.process_time()
        up = curve(_climb_setup(gs, design, friction_coefficient=mu, friction_sliding="static"))
        down = curve(_climb_setup(gs, design, friction_coefficient=mu, friction_sliding="unloading"))
        print(f"  μ = {mu:g}: loading {np.round(up * arcmin, 4).tolist()}, unloading {np.round(down * arcmin, 4).tolist()}; "
              f"width {np.round((down - up) * arcmin, 4).tolist()} arcmin ({time.process_time() - t0:.1f} s CPU)")


def friction_check(gs, design, mu, sliding="forward") -> None:
    """At the last point of the forward-running climb with μ: who slides which way, whether
    the elastic retreat's change along the zone would reverse it (the kinematic sense), and the
    P-matrix check."""
    import numpy as np

    m = _climb_setup(gs, design, friction_coefficient=mu, friction_sliding=sliding)
    path = _follow(m, float(gs.torque.rated_nm))
    last = path.points[-1]
    f = last.force_n
    m.geometry(last.retreat_mm, last.phi_rad)
    s_mat = m.station_matrix(last.state)
    on = np.flatnonzero(f > 1e-9 * f.max())
    sub = s_mat[np.ix_(on, on)]
    eig = np.linalg.eigvalsh(0.5 * (sub + sub.T))
    asym = np.abs(sub - sub.T).max() / np.abs(sub).max()
    share = f / f.sum()
    into = m._sigma < 0.0
    # the elastic part of the sliding as the tooth runs through the zone (forward: φ falls for
    # rotation +1): the FS stands −s(φ) e_r from its place, so it moves by rotation·ds/dφ·e_r per
    # unit of −rotation·φ; along the tangent out of the space: rotation · ds/dφ · (e_r·t)
    ds = np.gradient(last.retreat_mm, m.phis)[m.slot]
    elastic = m.rotation * ds * (m._js * m._tp_flank)
    flips = np.sign(m.sliding_speed + elastic) != np.sign(m.sliding_speed)
    print(f"\n-- {sliding} running with μ = {mu:g}, the last point of the path ({last.torque_nm:.1f} N·m, "
          f"{path.criterion}): {on.size} loaded stations on {np.unique(m.slot[on]).size} teeth")
    print(f"  load share sliding into the spaces (entering teeth) {share[into].sum():.3f}, out of them "
          f"{share[~into].sum():.3f}; loaded teeth at φ = {np.degrees(m.phis[m.slot[on]]).min():.1f} … "
          f"{np.degrees(m.phis[m.slot[on]]).max():.1f}°")
    print(f"  kinematic sliding speed on the loaded stations |v_t| {np.abs(m.sliding_speed[on]).min():.3f} … "
          f"{np.abs(m.sliding_speed[on]).max():.3f} mm/rad of φ; the retreat's change along the zone "
          f"|ds/dφ·(e_r·t)| up to {np.abs(elastic[on]).max():.3f} mm/rad; the load share whose sense it would "
          f"reverse {share[flips].sum():.3f}")
    print(f"  S on the loaded stations: asymmetry max|S − Sᵀ|/max|S| {asym:.3g}; symmetric part's eigenvalues "
          f"{eig.min():.3g} … {eig.max():.3g} mm/N "
          f"({'positive definite: a P-matrix' if eig.min() > 0 else 'NOT positive definite'})")


def run(path: Path) -> None:
    gs = pg.load_gearset(path)
    print(f"\n=== {gs.name} ({path.name}): rated {gs.torque.rated_nm:g}, peak {gs.torque.peak_nm:g}, "
          f"momentary {gs.torque.momentary_nm:g} N·m")
    t0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    print(f"design scene: {time.process_time() - t0:.2f} s CPU")
    if ARGS["hysteresis"]:
        hysteresis_run(gs, design)
    if ARGS["friction"]:
        friction_run(gs, design)
    if ARGS["friction_only"]:
        if ARGS["positions"]:
            positions_run(gs, design)
        return
    climb_run(gs, design)
    if ARGS["positions"]:
        positions_run(gs, design)
    if ARGS["face"]:
        face_run(gs, design)
    if ARGS["parts"]:
        parts_run(gs, design)
    if ARGS["perturb"]:
        perturb_run(gs, design)
    if ARGS["climb_only"]:
        return
    for label, kw in (("whole model (linear)", {"climb": False}), ("no CS ring (linear)", {"cs_ring": False, "climb": False}),
                      ("rigid balls, no ring (linear)", {"bearing": None, "cs_ring": False, "climb": False})):
        t0 = time.process_time()
        r = ratcheting_torque(design, options=kw)
        cpu = time.process_time() - t0
        print(f"\n-- {label}: {cpu:.2f} s CPU")
        print(f"{'':8s} {'loaded teeth, force-weighted':>28s}   {'most loaded tooth':>50s}")
        print(f"{'T (N·m)':>8} {'h̄ (mm)':>8} {'Δr̄ µm':>8} {'margin':>8}   {'tooth':>5} {'φ (°)':>6} {'h (mm)':>7} "
              f"{'Δr µm':>7} {'FS':>7} {'CS ring':>7} {'α (°)':>6}  contact")
        for row in zip(r.torques_nm, r.mean_depth_mm, r.mean_separation_mm, r.tooth, r.tooth_phi_deg, r.depth_mm,
                       r.separation_mm, r.separation_fs_mm, r.separation_cs_mm, r.pressure_angle_deg, r.flags):
            t, hm, sm, k, phi, h, s, sf, sc, a, fl = row
            print(f"{t:8.1f} {hm:8.3f} {sm * 1e3:8.2f} {hm - sm:8.3f}   {k:5d} {phi:6.1f} {h:7.3f} {s * 1e3:7.2f} "
                  f"{sf * 1e3:7.2f} {sc * 1e3:7.2f} {a:6.1f}  " + ("ok" if fl is None else f"not used: {fl}"))
        fitted = "—" if r.torque_fitted_nm is None else f"{r.torque_fitted_nm:.4g}"
        prop = "—" if r.torque_proportional_nm is None else f"{r.torque_proportional_nm:.4g}"
        print(f"ratcheting torque {r.torque_nm:.4g} N·m = {r.ratio_to_rated:.3g} × rated, "
              f"{r.torque_nm / gs.torque.momentary_nm:.3g} × momentary ({'extrapolated' if r.extrapolated else 'solved'};"
              f" p = {r.exponent if r.exponent is None else round(r.exponent, 3)}, Δr̄ ∝ T^p: {fitted}, "
              f"proportional bound: {prop})")
        print(f"catalogue: {r.catalogue} (ratio {r.ratio_to_catalogue})")
        for w in r.warnings:
            print("  warning:", w)
        if label == "whole model (linear)":
            whole = r
    print("\nbad input:")
    try:
        whole.flag(0.0)
    except RatchetingError as exc:
        print(f"  flag(0): {type(exc).__name__}: {exc}")
    print(f"  flag(rated {gs.torque.rated_nm:g}): {whole.flag(gs.torque.rated_nm)}")
    if whole.torque_nm < float("inf"):
        print(f"  flag(1.01 × estimate): {whole.flag(1.01 * whole.torque_nm)}")
    try:
        ratcheting_torque(design, options=dict(torques_nm=[0.0, 265.0], climb=False))
    except RatchetingError as exc:
        print(f"  torques_nm=[0, 265]: {type(exc).__name__}: {exc}")
    big = BallBearing(23, 7.5, 84.5, 0.52, 2.06e5, 0.3)
    thin = dataclasses.replace(gs, wave_generator=dataclasses.replace(gs.wave_generator, bearing_thickness_mm=8.0))
    try:
        check_bearing_fits(thin, big)
    except BearingFitError as exc:
        print(f"  7.5 mm balls in an 8 mm bearing section: {type(exc).__name__}: {exc}")


def verify_run(path: Path) -> None:
    """``--verify``: the verify scene's ratcheting estimate as the pipeline computes it —
    ``ratcheting_torque`` on the contact inputs of the verify scene's design (its rim FEM's
    contact angle; the contact and stresses, which the estimate does not read, left out) — with
    the climb's path (T(φ), the force-weighted retreat and margin) and its criterion: a path
    that ends with no equilibrium just beyond ("end of path") is the verdict's NOT CHECKED."""
    from profilegen.contact.inputs import ContactInput

    gs = pg.load_gearset(path)
    t0 = time.perf_counter()
    design = pg.design(gs, scene="verify", contact=False, stress=False)
    inputs = ContactInput.from_design(design)
    t1 = time.perf_counter()
    r = ratcheting_torque(inputs)
    c = r.climb
    print(f"\n== {path.name}: {r.torque_nm:.1f} N·m ({c['criterion']}); design {t1 - t0:.1f} s, ratcheting "
          f"{time.perf_counter() - t1:.1f} s")
    print(f"  {'φ (mrad)':>9} {'T (N·m)':>9} {'retreat':>8} {'margin':>8}  (force-weighted, µm)")
    for phi, t, s, m in zip(c["phi_path_rad"], c["torque_path_nm"], c["mean_retreat_mm"], c["margin_mm"]):
        print(f"  {phi * 1e3:9.4f} {t:9.2f} {s * 1e3:8.2f} {m * 1e3:8.2f}")
    for w in r.warnings:
        if w.startswith("climb"):
            print(f"  {w}")
    m = float(gs.gear.module_mm)
    for g in ARGS.get("gaps") or ():  # the climb's teeth cut at g modules (the product's: CLIMB_GAP_PER_MODULE)
        t2 = time.perf_counter()
        rg = ratcheting_torque(inputs, options={"climb_max_gap_mm": g * m})
        cg = rg.climb
        print(f"  teeth within {g:g} m = {g * m:.3f} mm: {rg.torque_nm:.1f} N·m ({cg['criterion']}), {cg['teeth']} teeth, "
              f"{cg['points']} stations, {time.perf_counter() - t2:.1f} s")


def main() -> None:
    import argparse

    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))

    def floats(text):
        return [float(x) for x in text.split(",")]

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sets", nargs="*", type=Path, help="gear-set TOML files (default: seed000_csf40, csf32_100, default)")
    ap.add_argument("--climb-only", action="store_true")
    ap.add_argument("--ring-scale", type=floats, default=[], help="CS ring compliance factors, e.g. 2,4")
    ap.add_argument("--shift", type=floats, default=[])
    ap.add_argument("--positions", type=int, default=0, help="wave-generator positions over a tooth passage")
    ap.add_argument("--face", type=lambda t: [int(x) for x in t.split(",")], default=[], help="face slice counts")
    ap.add_argument("--perturb", type=floats, default=[], help="flank offsets in nm, e.g. 1,-1,100,-100")
    ap.add_argument("--parts", action="store_true")
    ap.add_argument("--friction", type=floats, default=[], help="Coulomb coefficients on the teeth, e.g. 0,0.05,0.1")
    ap.add_argument("--sliding", type=lambda t: t.split(","), default=ARGS["sliding"],
                    help="the senses of sliding friction opposes: " + ",".join(ARGS["sliding"]))
    ap.add_argument("--friction-only", action="store_true", help="only the friction studies (--friction, --hysteresis)")
    ap.add_argument("--hysteresis", type=floats, default=[], help="μ for the loading/unloading width, e.g. 0.1")
    ap.add_argument("--positions-friction", type=float, default=0.0, help="μ for --positions (default 0)")
    ap.add_argument("--positions-sliding", default="forward-elastic", help="the sliding sense for --positions")
    ap.add_argument("--verify", action="store_true",
                    help="only the verify scene's estimate with the climb's path, as the pipeline calls it")
    ap.add_argument("--gaps", type=floats, default=[],
                    help="with --verify: the climb again on the teeth within each of these gaps (in modules), e.g. "
                         "0.2,0.5,0.84,1.2 (the product's: ratchet.CLIMB_GAP_PER_MODULE)")
    args = ap.parse_args()
    ARGS.update({k: v for k, v in vars(args).items() if k != "sets"})
    for path in args.sets or SETS:
        verify_run(path) if args.verify else run(path)


if __name__ == "__main__":
    main()
