"""Tooth deviations and assembly eccentricity in the loaded contact: a candidate for the
compliance the whole-gear model misses against the catalogue (research/README.md).

The contact model is a perfect gear: every pitch exact, CS and wave generator concentric, so
both engagement zones are images of each other and the one-zone model (the FS as a
point-symmetric half ring, :mod:`profilegen.contact.compliance`, each load standing for
itself and its image) is exact. A real gear's teeth sit a few µm off their places (pitch and
profile deviations, ISO 1328-1) and its CS axis is off the wave generator's by the assembly's
eccentricity: at low torque only some teeth — and possibly one zone — carry load.

Model
-----
* **Both zones as one problem** (:class:`TwoZoneContact`): the FS as the whole ring of z1
  pitches, built from the package's own one-pitch substructure (the rim on its sliding outer
  race, :func:`~profilegen.contact.compliance._half_ring_pitch`, condensed onto its cuts and
  chained round 2π by :func:`~profilegen.contact.compliance._chain_flex` instead of π with
  the point-symmetric tie), loaded at one zone's points and at their images (FS tooth
  i + z1/2, CS space i + z2/2), with every ball of both zones a one-sided support at its
  no-load gap. The CS of each zone is the package's sector (fixed outside, the zones do not
  meet through it). The ring's rigid translation, which the tie removed, is a free unknown
  t: the loads' resultant is carried by the balls (Σ F d + Σ R e_r = 0). Unknowns x = (F, R)
  ≥ 0, the rotation φ and t:

      w = C x + q − a φ + D t ≥ 0 ⊥ x ≥ 0,   aᵀx = T (the whole gear's torque, no T/U),   Dᵀx = 0

  (q: r_k θ_k for the teeth, the no-load gap for the balls; a: the levers r_k for the teeth,
  0 for the balls; D: each load's direction; C: the flexibility, S_2D/b, with the Hertz
  springs on the balls' diagonal). The KKT conditions of a strictly convex QP, so unique;
  solved by a primal–dual active set on the bordered system (as the chain's continuation),
  Lemke's method (:func:`~profilegen.lcp.lemke_lcp`, t = t⁺ − t⁻) when the
  active set cycles. The Hertz ball springs: the chain's secant fixed point
  (:class:`~profilegen.contact.chain.SpringIteration`). With no deviations the two zones
  carry T/2 each and reproduce the one-zone model (tests/research/test_tooth_errors.py).
* **One flank or both.** Given one flank's points, the other flank never touches (a gear
  whose backlash allowance exceeds its deviations); the curve's zero is the rigid gear's
  first contact (:meth:`TwoZoneContact.first_contact_rad`). Given both flanks (a sequence of
  :class:`~profilegen.contact.points.ContactPoints` and a compliance built for their points
  concatenated), the other flank's points resist the rotation (a = −r_k) and either torque
  sign is solved; deviations that make the flanks interfere preload the gear at rest, and
  the curve's zero is the rest position at a vanishing torque (:meth:`TwoZoneContact.zero_rad`).
  A backlash allowance j is an offset j/(2 r_p) on every point of both flanks. The model's
  conjugate tooth has none (5e-5 arcmin): with it, deviations stiffen the gear.
* **Wave generator** held on the CS axis (the balls' gaps see the FS ring's translation) or
  floating radially (``wave_generator="floating"``: an Oldham coupling; the cam's translation
  free, Σ R e_r = 0 on it; an eccentricity is then absorbed).
* **Deviations as gap offsets.** A tooth turned about the gear centre by β (a tangential
  position deviation s = β r_p at the pitch circle) moves each of its contact points along
  the common normal by r_k β: its first-contact angle θ_k = e_k / r_k grows by β. A profile
  deviation Δn along the normal adds Δn / r_k. An eccentricity e of the CS axis (the CS
  shifted by the vector e) changes every gap by n_k·e: one zone's gaps shrink, the image
  zone's (normal −n_k) grow by the same.
* **ISO 1328-1:2013** tolerances (:func:`iso1328_tolerances_um`), eq. (5) single pitch
  f_pT = (0.001 d + 0.4 m + 5)(√2)^(A−5) µm, eq. (8) profile form f_fαT = (0.55 m + 5)
  (√2)^(A−5) µm, eq. (7) profile slope f_HαT = (0.4 m + 0.001 d + 4)(√2)^(A−5) µm
  (d, m in mm; A the tolerance class; valid for 0.5 ≤ m ≤ 70 mm, 5 ≤ d ≤ 15 000 mm, the
  values before the standard's rounding). By hand, d = 100 mm, m = 0.5 mm, A = 5:
  f_pT = 0.1 + 0.2 + 5 = 5.3 µm, f_fαT = 0.275 + 5 = 5.275 µm.
* **Random draws** (:func:`draw_deviations`): every FS tooth and every CS space at its own
  tangential position deviation s ~ N(0, σ_p), σ_p = f_pT/2 (so a single pitch deviation,
  the difference of two neighbours, has σ = 0.71 f_pT: a gear at its grade's limit), and
  every FS and CS flank its own smooth profile deviation along the flank,
  σ_α (a ξ + b (3ξ² − 1)/2), a, b ~ N(0, 1), ξ ∈ [−1, 1] over the stations' arc length,
  σ_α = f_fαT/2. Cumulative pitch deviation (long-wave) is the eccentricity's family and
  is not drawn.

Numbers and what they mean: docs/catalogue_comparison.md, "Tooth deviations and eccentricity"
(tests/benchmarks/tooth_errors.py).

Left out: the deviations' effect on the compliance (the points stay where the perfect gear
puts them), helix deviations across the face, the FS's own run-out under the wave generator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from profilegen.blas import one_blas_thread
from profilegen.errors import ConvergenceError, ProfilegenError

__all__ = ["ToothErrorError", "TwoZoneContact", "TwoZoneSolution", "draw_deviations", "eccentricity_offsets_rad",
           "iso1328_tolerances_um", "active_set_loop"]


def active_set_loop(loaded, solve, *, max_iter: int):
    """The primal–dual active-set rule for an LCP with bordered equality unknowns (the whole-ring
    contact of :class:`TwoZoneContact` and the two-zone climb of :mod:`research.dedoidal`):
    ``solve(p)`` solves the system with the loads ``p`` (indices) active and the others zero →
    (x, w, tol, extra) — the loads, the gaps, the gap tolerance and whatever else the caller
    needs; a load stays active while x > 0 and an inactive one joins where w < −tol. Returns
    (x, w, loaded, extra) once the set repeats itself, or None when a set recurs (cycling), the
    system is singular, or ``max_iter`` sets have been tried — the caller then falls back to a
    pivoting method."""
    seen = set()
    loaded = np.array(loaded, dtype=bool)
    for _ in range(max_iter):
        key = loaded.tobytes()
        if key in seen:
            return None
        seen.add(key)
        try:
            x, w, tol, extra = solve(np.flatnonzero(loaded))
        except np.linalg.LinAlgError:
            return None
        new = (loaded & (x > 0.0)) | (~loaded & (w < -tol))
        if np.array_equal(new, loaded):
            return x, w, loaded, extra
        loaded = new
    return None

class ToothErrorError(ProfilegenError, ValueError):
    """Bad input to the tooth-deviation study (names the field, its value and range)."""


def iso1328_tolerances_um(reference_diameter_mm: float, module_mm: float, grade: int) -> dict:
    """ISO 1328-1:2013 flank tolerances (µm, unrounded) for tolerance class ``grade`` (1…11):
    eq. (5) single pitch f_pT, (6) total cumulative pitch F_pT, (7) profile slope f_HαT,
    (8) profile form f_fαT. The standard's range is 0.5 ≤ m ≤ 70 mm: outside it the formulas
    are extrapolated and ``"extrapolated"`` is True."""
    try:
        d, m, a = float(reference_diameter_mm), float(module_mm), int(grade)
    except (TypeError, ValueError) as exc:
        raise ToothErrorError(f"grade = {grade!r}, module_mm = {module_mm!r}, reference_diameter_mm = "
                              f"{reference_diameter_mm!r}: must be numbers") from exc
    if not 1 <= a <= 11 or a != grade:
        raise ToothErrorError(f"grade = {grade!r}: must be a whole tolerance class in [1, 11]")
    if not (math.isfinite(d) and d > 0.0 and math.isfinite(m) and m > 0.0):
        raise ToothErrorError(f"reference_diameter_mm = {d!r} mm, module_mm = {m!r} mm: must be finite and > 0")
    step = math.sqrt(2.0) ** (a - 5)
    return {
        "f_pt_um": (0.001 * d + 0.4 * m + 5.0) * step,
        "F_p_um": (0.002 * d + 0.55 * math.sqrt(d) + 0.7 * m + 12.0) * step,
        "f_Halpha_um": (0.4 * m + 0.001 * d + 4.0) * step,
        "f_falpha_um": (0.55 * m + 5.0) * step,
        "extrapolated": not (0.5 <= m <= 70.0 and 5.0 <= d <= 15000.0),
        "source": "ISO 1328-1:2013 eq. (5)-(8), values before rounding",
    }


def _flanks(points) -> list:
    """One :class:`~profilegen.contact.points.ContactPoints` or a sequence of them (flanks)."""
    return [points] if hasattr(points, "tooth") else list(points)


def _zones(parts) -> np.ndarray:
    """[(zone 1, zone 2) per flank] → zone 1 of every flank, then zone 2 of every flank."""
    return np.concatenate([p[0] for p in parts] + [p[1] for p in parts])


def draw_deviations(points, gearset, rng, *, pitch_sigma_mm: float, profile_sigma_mm: float) -> np.ndarray:
    """One random draw of the first-contact angle offsets (rad) of ``points`` (one zone's
    :class:`~profilegen.contact.points.ContactPoints`) and their images: (2n,), zone 1 then
    zone 2. Every FS tooth and CS space a tangential position deviation ~ N(0, σ_p) at the
    pitch circle, every FS and CS flank a smooth profile deviation along the normal (see the
    module docstring). ``rng``: a numpy Generator. ``points`` may be a sequence of flanks
    (the layout of :class:`TwoZoneContact` with them: zone 1 of every flank, then zone 2).
    The same generator state gives the same tooth positions on both flanks (a tooth turned
    by β opens one flank by what it closes on the other: the sign is each point's own,
    −(ẑ × p)·n / r_k) and independent profiles (each flank its own draw)."""
    for name, v in (("pitch_sigma_mm", pitch_sigma_mm), ("profile_sigma_mm", profile_sigma_mm)):
        if not (math.isfinite(float(v)) and float(v) >= 0.0):
            raise ToothErrorError(f"{name} = {v!r} mm: must be finite and ≥ 0")
    g = gearset.gear
    z1, z2 = g.flexspline_teeth, g.circular_spline_teeth
    r_p = 0.5 * g.module_mm * z1
    fs_pos = rng.normal(0.0, pitch_sigma_mm, z1)
    cs_pos = rng.normal(0.0, pitch_sigma_mm, z2)
    fs_prof_all = rng.normal(0.0, 1.0, (2, z1, 2))
    cs_prof_all = rng.normal(0.0, 1.0, (2, z2, 2))
    parts = []
    for pts in _flanks(points):
        flank = 0 if pts.side > 0 else 1
        fs_prof, cs_prof = fs_prof_all[flank], cs_prof_all[flank]
        t = np.asarray(pts.t_mm, dtype=float)
        span = float(t.max() - t.min())
        xi = np.zeros_like(t) if span <= 0.0 else 2.0 * (t - t.min()) / span - 1.0
        shape = np.column_stack([xi, 0.5 * (3.0 * xi * xi - 1.0)])
        # the gap change per unit turn of the FS tooth about the centre (ẑ × p = (p_y, −p_x) in
        # the package's angle sense, +y toward +x), over the lever: ±1 up to the point's geometry
        p, nrm = np.asarray(pts.fs_point_mm, float), np.asarray(pts.normal, float)
        sense = -(p[:, 1] * nrm[:, 0] - p[:, 0] * nrm[:, 1]) / np.asarray(pts.lever_mm, float)
        out = []
        for fs_tooth, cs_space in ((pts.tooth % z1, pts.tooth % z2),
                                   ((pts.tooth + z1 // 2) % z1, (pts.tooth + z2 // 2) % z2)):
            pitch = sense * (fs_pos[fs_tooth] - cs_pos[cs_space]) / r_p
            profile = profile_sigma_mm * (np.einsum("ij,ij->i", shape, fs_prof[fs_tooth])
                                          + np.einsum("ij,ij->i", shape, cs_prof[cs_space]))
            out.append(pitch + profile / pts.lever_mm)
        parts.append(out)
    return _zones(parts)


def eccentricity_offsets_rad(points, eccentricity_mm: float, direction_rad: float = 0.0) -> np.ndarray:
    """The first-contact angle offsets (rad, (2n,), zone 1 then its images) of the CS axis
    shifted by e = ``eccentricity_mm`` in the direction ``direction_rad`` (from the major axis
    +y toward +x, the package's frame): Δθ_k = n_k·e / r_k in zone 1, −n_k·e / r_k in the
    image zone; ``points`` may be a sequence of flanks, as in :func:`draw_deviations`."""
    e = float(eccentricity_mm)
    if not math.isfinite(e):
        raise ToothErrorError(f"eccentricity_mm = {eccentricity_mm!r}: must be finite (mm)")
    vec = e * np.array([math.sin(direction_rad), math.cos(direction_rad)])
    parts = []
    for pts in _flanks(points):
        d = (np.asarray(pts.normal, dtype=float) @ vec) / np.asarray(pts.lever_mm, dtype=float)
        parts.append((d, -d))
    return _zones(parts)


@dataclass(frozen=True, slots=True, eq=False)
class TwoZoneSolution:
    """Both zones' contact at one torque: tooth forces F (2n, N), ball reactions R (2 nb, N),
    the rotation φ (rad), the ring's translation t (mm), each zone's moment (N·mm), the gaps
    after load (teeth, balls; mm), the residuals (equilibrium relative to T, complementarity
    max |F g|, |R h| over T·(φ − θ_min), the resultant of all loads in N) and the
    balls' springs."""

    force_n: np.ndarray
    reaction_n: np.ndarray
    phi_rad: float
    translation_mm: np.ndarray
    zone_moment_nmm: np.ndarray
    gap_mm: np.ndarray
    ball_gap_mm: np.ndarray
    equilibrium_residual: float
    complementarity_residual: float
    resultant_n: float
    method: str
    #: the balls' Hertz springs at the fixed point (mm/N, 2 nb) or None (rigid balls)
    springs_mm_per_n: np.ndarray | None = None
    #: the loaded teeth and balls (bool, 2n + 2 nb): a start for a neighbouring solve
    _loaded: np.ndarray | None = None

    @property
    def teeth_loaded(self) -> int:
        return int(np.count_nonzero(self.force_n > 0.0))


class TwoZoneContact:
    """Both engagement zones of one flank as one contact problem (module docstring).

    ``inputs``: the :class:`~profilegen.contact.inputs.ContactInput`; ``points`` and
    ``compliance``: one zone's, as :func:`~profilegen.contact.chain.torsional_curve` builds them
    (``ball_supports="all"``; its CS block, ball angles and no-load ball gaps are taken, and
    its mesh parameters must be the build's defaults: 14 columns per pitch, 2 rim, 4 tooth,
    2 race layers, a sliding race)."""

    def __init__(self, inputs, points, compliance, *, race_thickness_mm: float | None = None, per_pitch: int = 14,
                 rim_layers: int = 2, tooth_layers: int = 4, race_layers: int = 2):
        from profilegen.geometry.kinematics import turn
        from profilegen.rim.toothed import toothed_half_ring_race_mesh
        from profilegen.contact import compliance as cm

        if compliance.ball_supports != "all":
            raise ToothErrorError(f"compliance.ball_supports = {compliance.ball_supports!r}: must be 'all' (every "
                                  "ball one-sided at its no-load gap)")
        from types import SimpleNamespace

        flanks = _flanks(points)
        # the flanks' points as one set; sign: +1 where the first flank's loaded rotation closes the gap
        points = SimpleNamespace(**{f: np.concatenate([np.asarray(getattr(p, f)) for p in flanks])
                                    for f in ("tooth", "fs_point_mm", "normal", "lever_mm", "theta_rad")})
        points.count = int(points.tooth.size)
        sign = np.concatenate([np.full(p.count, float(p.rotation * flanks[0].rotation)) for p in flanks])
        if compliance.count != points.count:
            raise ToothErrorError(f"compliance: built for {compliance.count} points, the flanks have {points.count} "
                                  "(build it for their points concatenated in the same order)")
        self.flanks = tuple(flanks)
        gs = inputs.gearset
        g = gs.gear
        z1, z2 = g.flexspline_teeth, g.circular_spline_teeth
        race = cm.default_race_thickness_mm(g) if race_thickness_mm is None else float(race_thickness_mm)
        if not race > 0.0:
            raise ToothErrorError(f"race_thickness_mm = {race_thickness_mm!r}: must be > 0 mm (the sliding race)")
        self.points, self.compliance, self.gearset = points, compliance, gs
        ring, bore = toothed_half_ring_race_mesh(inputs.tooth, g.rim_thickness_mm, race, race_layers=race_layers,
                                                 toothed_pitches=[0], rim_layers=rim_layers,
                                                 tooth_layers=tooth_layers, per_pitch=per_pitch, pitches=1)
        r_bore = g.neutral_radius_mm - 0.5 * g.rim_thickness_mm
        pitch, c, rot, (ix, iy, n_full, n_extra), gauges = cm._half_ring_pitch(
            ring, gs.material.youngs_modulus_mpa, gs.material.poisson_ratio, r_bore, np.asarray(bore), race_layers,
            "FS full ring (one pitch)")
        # the points in their tooth frames (contact.points' placement undone), then round the whole ring
        pose = inputs.motion.pose(2.0 * math.pi * points.tooth / z1)
        angle = 2.0 * math.pi * points.tooth / z2
        local = pose.to_tooth(turn(points.fs_point_mm, -angle))
        n_cs = turn(points.normal, -angle)
        co, si = np.cos(pose.angle), np.sin(pose.angle)
        local_n = np.column_stack([n_cs[:, 0] * co - n_cs[:, 1] * si, n_cs[:, 0] * si + n_cs[:, 1] * co])
        k = np.mod(np.concatenate([points.tooth, points.tooth + z1 // 2]), z1)
        loc, loc_n = np.vstack([local, local]), np.vstack([local_n, local_n])
        co, si = np.cos(k * ring.pitch_rad), np.sin(k * ring.pitch_rad)
        r_m = g.neutral_radius_mm
        xy = np.column_stack([loc[:, 0] * co + (loc[:, 1] + r_m) * si, -loc[:, 0] * si + (loc[:, 1] + r_m) * co])
        d_c = -np.column_stack([loc_n[:, 0] * co + loc_n[:, 1] * si, -loc_n[:, 0] * si + loc_n[:, 1] * co])
        kinds = np.zeros(z1, dtype=int)
        p_c, t_c, w_c, dist, a_c = cm._pitch_projection(xy, k, kinds, ring.pitch_rad,
                                                        [(ring.mesh.doflocs, ring.outer_nodes)])
        if dist.max() > 0.01:
            raise ConvergenceError(f"TwoZoneContact: a contact point lies {dist.max():.3g} mm off the FS tooth "
                                   "surface (> 0.01 mm)")
        balls = np.asarray(compliance.ball_angle_rad, dtype=float)
        z_half = -ring.start_rad
        theta_b = np.mod(np.concatenate([balls, balls + math.pi]) + z_half, 2.0 * math.pi) - z_half
        e_r = np.column_stack([np.sin(theta_b), np.cos(theta_b)])
        p_b, t_b, w_b, _, a_b = cm._pitch_projection((r_bore - race) * e_r,
                                                     np.floor((theta_b + z_half) / ring.pitch_rad), kinds,
                                                     ring.pitch_rad, [(ring.mesh.doflocs, ring.inner_nodes)])
        on = np.concatenate([p_c, p_b])
        y = cm._load_matrix(n_full, ix, iy, np.vstack([t_c, t_b]), np.vstack([w_c, w_b]),
                            cm._turn_back(np.vstack([d_c, e_r]), np.concatenate([a_c, a_b])))
        loads = sp.vstack([y, sp.csr_matrix((n_extra, on.size))]).tocsr()
        # held: the package's gauges (the rim's and the race's tangential dof at cut 0) and the
        # translations (radial at the rim's bore node of cut 0, tangential at cut z1/2's); the
        # translation comes back as the free unknown t
        n_cut = pitch.n_cut
        held = list(gauges) + [gauges[0] + 1, (z1 // 2) * n_cut + gauges[0]]
        with one_blas_thread():  # as the package's build: BLAS threads spin against each other on these sizes
            flex, _ = cm._chain_flex([pitch], kinds, [loads], [(on, np.arange(on.size))], cyclic=True,
                                     fixed_cut=held, gauge=([c], [rot]), where="FS full ring (cuts)")
        b = float(compliance.face_width_mm)
        n, nb = points.count, balls.size
        cmat = flex / b
        cs = np.asarray(compliance.cs_matrix_mm_per_n, dtype=float)
        cmat[:n, :n] += cs
        cmat[n:2 * n, n:2 * n] += cs
        self.n, self.nb = 2 * n, 2 * nb  # teeth of both zones, balls of both zones
        self.c = 0.5 * (cmat + cmat.T)
        self.directions = np.vstack([d_c, e_r])
        self.lever = np.concatenate([points.lever_mm, points.lever_mm])
        #: +1 for the points the positive rotation closes (the first flank's), −1 for the other flank's
        self.sign = np.concatenate([sign, sign])
        self.theta = np.concatenate([points.theta_rad, points.theta_rad])
        gap = np.zeros(nb) if compliance.ball_gap_mm is None else np.asarray(compliance.ball_gap_mm, float)
        self.ball_gap = np.concatenate([gap, gap])
        self.face_width_mm = b

    def _translations(self, wave_generator: str) -> np.ndarray:
        if wave_generator not in ("held", "floating"):
            raise ToothErrorError(f"wave_generator = {wave_generator!r}: must be 'held' (the cam fixed to the CS) or "
                                  "'floating' (radially free, an Oldham coupling)")
        dmat = self.directions
        if wave_generator == "floating":
            cam = np.zeros_like(dmat)
            cam[self.n:] = -dmat[self.n:]
            dmat = np.hstack([dmat, cam])
        return dmat

    def first_contact_rad(self, offsets_rad=None, *, wave_generator: str = "held") -> float:
        """The rotation at which the rigid gear first takes torque (the curve's zero, the
        backlash's end): the largest φ the FS can turn, translating freely, with every gap ≥ 0
        — max φ s.t. r_k (θ_k − φ) + (D t)_k ≥ 0 for the teeth and gap_b + (D t)_b ≥ 0 for the
        balls (a linear program, scipy's HiGHS). With the cam held and the balls of both
        zones at zero gap round the major axes, t = 0 and this is min θ_k; with the cam
        floating the FS and cam shift together, so an eccentricity moves it by nothing."""
        from scipy.optimize import linprog

        dmat = self._translations(wave_generator)
        theta = self.theta if offsets_rad is None else self.theta + np.asarray(offsets_rad, dtype=float)
        nd = dmat.shape[1]
        if len(self.flanks) > 1:
            raise ToothErrorError("first_contact_rad: with both flanks the curve's zero is the solve at a vanishing "
                                  "torque (zero_rad), not the first contact of one flank")
        a = np.concatenate([self.lever, np.zeros(self.nb)])
        q = np.concatenate([self.lever * theta, self.ball_gap])
        scale = float(self.lever.mean())
        # variables (ψ = φ r̄, t): a ψ / r̄ − D t ≤ q
        res = linprog(np.concatenate([[-1.0], np.zeros(nd)]), A_ub=np.column_stack([a / scale, -dmat]), b_ub=q,
                      bounds=[(None, None)] * (1 + nd), method="highs")
        if res.status != 0:
            raise ConvergenceError(f"TwoZoneContact.first_contact_rad: the linear program ended with status "
                                   f"{res.status} ({res.message})")
        return float(res.x[0]) / scale

    def zero_rad(self, offsets_rad=None, *, bearing=None, wave_generator: str = "held",
                 torque_nm: float = 1e-3) -> float:
        """The curve's zero: one flank, :meth:`first_contact_rad`; both flanks, the rotation at
        a vanishing torque ``torque_nm`` (the preloaded rest position where the deviations make
        the flanks interfere, the first contact of the loaded flank where they leave backlash)."""
        if len(self.flanks) == 1:
            return self.first_contact_rad(offsets_rad, wave_generator=wave_generator)
        return self.solve(torque_nm, offsets_rad, bearing=bearing, wave_generator=wave_generator).phi_rad

    def solve(self, torque_nm: float, offsets_rad=None, *, bearing=None, spring_tol: float = 1e-5,
              spring_iterations: int = 60, start=None, wave_generator: str = "held") -> TwoZoneSolution:
        """Both zones at the whole gear's torque ``torque_nm`` (> 0; either sign with both flanks:
        positive loads the first flank), each point's first-contact
        angle θ_k + ``offsets_rad``[k] (2n: zone 1, then the images). ``bearing``: a
        :class:`~profilegen.contact.chain.BallBearing` for the Hertz springs (None: rigid
        balls). ``start``: a loaded set (bool, 2n + 2 nb) to begin from (e.g. the last
        torque's, ``solution`` attribute ``loaded``). ``wave_generator``: "held" (the cam fixed
        to the CS: the balls' gaps see the FS ring's translation only) or "floating" (the cam
        free to translate radially, as on an Oldham coupling: a second translation c, the
        balls' gaps h − e_r·c, Σ R e_r = 0 on the cam; so the teeth's resultant vanishes too).
        ``translation_mm``: t, or (t, c) when floating."""
        from profilegen.contact.chain import SpringIteration

        t = float(torque_nm)
        two_flanks = len(self.flanks) > 1
        if not (math.isfinite(t) and (t > 0.0 or (two_flanks and t != 0.0))):
            raise ToothErrorError(f"torque_nm = {torque_nm!r}: must be finite and > 0 (N·m; ≠ 0 with both flanks)")
        dmat = self._translations(wave_generator)
        theta = self.theta.copy()
        if offsets_rad is not None:
            off = np.asarray(offsets_rad, dtype=float)
            if off.shape != theta.shape or not np.all(np.isfinite(off)):
                raise ToothErrorError(f"offsets_rad: must be {theta.size} finite angles (rad), got shape {off.shape}")
            theta = theta + off
        loaded = start
        if loaded is None and wave_generator == "floating":  # a set whose teeth can balance their resultant
            loaded = self.solve(t, offsets_rad)._loaded
        springs = None if bearing is None else SpringIteration(bearing.hertz_coefficient(), spring_tol)
        for _ in range(spring_iterations):
            c = None if springs is None else springs.springs
            out = self._solve(t * 1e3, theta, c, loaded, dmat)
            loaded = out[-1]
            if springs is None or springs.step(out[0][self.n:]):
                break
        else:
            raise ConvergenceError(f"TwoZoneContact.solve: the Hertz ball springs did not settle in "
                                   f"{spring_iterations} iterations at {t:g} N·m")
        x, phi, tr, w, method, loaded = out
        c = None if springs is None else springs.springs
        n = self.n
        force, react = x[:n], x[n:]
        tz = t * 1e3
        moment = self.sign * self.lever * force
        half = n // 2
        theta_min = float(theta[self.sign > 0].min())
        scale = abs(tz) * (abs(phi - theta_min) + 1e-12)
        comp = float(np.max(np.abs(x * w))) / scale
        resultant = float(np.linalg.norm(dmat.T @ x))
        out = TwoZoneSolution(force, react, float(phi), tr, np.array([moment[:half].sum(), moment[half:].sum()]),
                              w[:n], w[n:], abs(float(moment.sum()) - tz) / abs(tz), comp, resultant, method, c)
        object.__setattr__(out, "_loaded", loaded)
        return out

    # --- the QP's KKT conditions for given springs
    def _system(self, springs):
        cmat = self.c
        if springs is not None:
            cmat = cmat.copy()
            idx = np.arange(self.n, self.n + self.nb)
            cmat[idx, idx] += springs
        return cmat

    def _solve(self, tz, theta, springs, loaded, dmat):
        n = self.n
        cmat = self._system(springs)
        flip = 1.0 if tz > 0.0 else -1.0  # a negative torque: the other flank's problem, φ → −φ
        a = np.concatenate([flip * self.sign * self.lever, np.zeros(self.nb)])
        q = np.concatenate([self.lever * theta, self.ball_gap])
        r_bar = float(self.lever.mean())
        c0 = float(np.mean(np.diag(cmat)[:n]))
        force = abs(tz) / r_bar
        length = c0 * force
        ms, qs, as_ = cmat / c0, q / length, a / r_bar  # scaled: x̂ = x/X, lengths / L, φ̂ = φ r̄ / L
        if loaded is None:
            loaded = np.zeros(n + self.nb, bool)
            first = np.flatnonzero(a[:n] > 0.0)
            loaded[first[int(np.argmin(theta[first]))]] = True
            loaded[:n] |= theta < 0.0  # interference: loaded at rest
            loaded[n:] = self.ball_gap <= 0.0
        out = self._active_set(ms, qs, as_, dmat, loaded)
        method = "active set"
        if out is None:
            out = self._lemke(ms, qs, as_, dmat)
            method = "lemke"
        xs, phis, ts, ws, loaded = out
        return xs * force, flip * phis * length / r_bar, ts * length, ws * length, method, loaded

    @staticmethod
    def _kkt(ms, qs, as_, dmat, p):
        k, nd = p.size, dmat.shape[1]
        kkt = np.zeros((k + 1 + nd, k + 1 + nd))
        kkt[:k, :k] = ms[np.ix_(p, p)]
        kkt[:k, k] = -as_[p]
        kkt[:k, k + 1:] = dmat[p]
        kkt[k, :k] = as_[p]
        kkt[k + 1:, :k] = dmat[p].T
        rhs = np.concatenate([-qs[p], [1.0], np.zeros(nd)])
        sol = np.linalg.solve(kkt, rhs)
        x = np.zeros(qs.size)
        x[p] = sol[:k]
        phi, t = float(sol[k]), sol[k + 1:]
        w = ms @ x + qs - as_ * phi + dmat @ t
        return x, phi, t, w

    def _active_set(self, ms, qs, as_, dmat, loaded):

        def solve(p):
            x, phi, t, w = self._kkt(ms, qs, as_, dmat, p)
            return x, w, 1e-10 * (1.0 + abs(phi)), (phi, t)

        out = active_set_loop(loaded, solve, max_iter=4 * qs.size + 20)
        if out is None:
            return None
        x, w, loaded, (phi, t) = out
        w[loaded] = 0.0
        return x, phi, t, w, loaded

    def _lemke(self, ms, qs, as_, dmat):
        """Lemke on (x, ψ = φ − θ̂_min, t⁺, t⁻); the final loaded set re-solved by :meth:`_kkt`."""
        from profilegen.lcp import lemke_lcp

        m = qs.size
        n = self.n
        nd = dmat.shape[1]
        pos = np.flatnonzero(as_[:n] > 0.0)
        theta_min = float(np.min(qs[pos] / as_[pos]))
        size = m + 1 + 2 * nd
        mm = np.zeros((size, size))
        mm[:m, :m] = ms
        mm[:m, m] = -as_
        mm[:m, m + 1:m + 1 + nd] = dmat
        mm[:m, m + 1 + nd:] = -dmat
        mm[m, :m] = as_
        mm[m + 1:m + 1 + nd, :m] = -dmat.T
        mm[m + 1 + nd:, :m] = dmat.T
        qq = np.concatenate([qs - as_ * theta_min, [-1.0], np.zeros(2 * nd)])
        basic, _ = lemke_lcp(mm, qq, "TwoZoneContact (Lemke)")
        loaded = np.zeros(m, bool)
        loaded[basic[basic < m]] = True
        out = self._active_set(ms, qs, as_, dmat, loaded)
        if out is None:
            raise ConvergenceError("TwoZoneContact: the loaded set from Lemke's basis did not settle")
        return out
