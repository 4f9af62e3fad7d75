"""Dedoidal ratcheting: both engagement zones in one climb, the FS and wave generator free to
go off-centre in the CS (the eccentric, n = 1 mode).

The one-zone climb (:mod:`profilegen.contact.climb`) is symmetric in the two zones: each load
stands for itself and its image, so the FS can only ovalise, never shift. In a gear the wave
generator floats on its Oldham coupling and the FS tooth ring can translate against the CS;
the failure the catalogue's ratcheting torque guards against is "dedoidal" — the FS ends up
eccentric in the CS and the teeth skip in one zone. This module lets the climb take that path.

Model (:class:`TwoZoneClimb`, a model for :func:`profilegen.contact.climb.climb`)
-------------------------------------------------------------------------------------
* **Per zone, the climb's geometry**: the zone's :class:`~profilegen.contact.climb.DesignClimb`
  (its stations, their gaps g(s) and lever arms r(s) on the geometry with each tooth s out of
  its CS space and the FS turned by φ, the FS tip corner's normal following the CS surface).
  Zone 2 is zone 1 turned by π (FS tooth i + z1/2 in CS space i + z2/2): the same geometry in
  its own frame, with its own retreats s₂.
* **Both zones in one complementarity problem, sharing φ**: the compliance is the FS as the
  whole ring (:class:`~research.tooth_errors.TwoZoneContact`'s full-ring build for
  the climb's stations, the corners' tip-land columns and the tip-land probes of both zones),
  every ball of both zones a one-sided support at its no-load gap (an LCP unknown, not settled
  by a loop), the Hertz ball springs by the climb's lagged secant, each zone's CS sector, and
  the CS as a free thin ring loaded by both zones' radial forces
  (:func:`~profilegen.contact.ratchet.cs_ring_radial_compliance`, the harmonics n ≥ 2 — the odd
  ones couple the zones antisymmetrically — and n = 0).
* **The translation** of the FS ring against the CS, τ (2 components, mm), and of the cam, c:
  every load's separation changes by d·τ (d its direction on the FS; the balls' by e_r·(τ − c)).
  The cam floats (``wave_generator="floating"``: Σ R e_r = 0 on it) or is held on the CS axis
  ("held"). The FS ring is free (``cup_stiffness_n_per_mm`` = 0: Σ loads on it + P = 0, P an
  ``external_force_n`` on the assembly) or held by the cup's lateral spring k toward the output
  bearing's axis, which stands ``e`` (the assembly eccentricity, ``eccentricity_mm`` along
  ``eccentricity_direction_rad`` from the major axis) off the CS axis: Σ loads + P = k (τ − e).
  With k = 0 an eccentricity is absorbed exactly (the whole FS/WG assembly shifts by it).
  :meth:`TwoZoneClimb.from_design` takes k = 0 only: the whole ring's τ is gauged at its bore
  on the major axis (TwoZoneContact's held node; under the symmetric load it moves 92 µm at
  seed000_csf40's limit), not at the ring's centre, which a spring would need; an eccentricity
  held by the cup enters there as the load P = k_c e. ``translation_mm`` prescribes τ (the
  n = 1 stiffness; gauge-free where it vanishes).
* **The retreat** of tooth k is its probe's separation: the FS side (the ring's and balls'
  response to every load of both zones) plus −e_r,k·τ (a translation toward the tooth pushes
  it into its space) plus the CS ring's: s = P x + D_probe τ + s_CS. The geometry is evaluated
  at that s per zone, the first-order part taken out (lagged, as the climb does), so at small s
  this is the linear two-zone contact exactly.

Unknowns per rotation: the station forces of both zones and the ball reactions (≥ 0, with
complementarity), τ and c (equalities), solved by a primal–dual active set on the bordered
system from the last loaded set, else by Newton ascent on the concave dual in the translations
with the climb's NNLS solve inside; the retreat's fixed point by the climb's Anderson
iteration. Left out: the translation's tangential part enters the gaps linearly (its normal
is the station's at no shift); the cup's tilt; the CS's own n = 1 (held by the housing).

Numbers (design scene, ``python tests/benchmarks/dedoidal.py [--fine T0,STEP,N]``; catalogue
CSF-40-100 2100, CSF-32-100 1000 N·m). With no imperfection the two-zone climb is the one-zone
climb: seed000_csf40 4749.0 N·m (zones 2374.5 each), csf32_100 2531.2. Along it the eccentric
mode's smallest stiffness eigenvalue is 2–5·10⁴ N/mm mid-path (K_xx ~ 10⁶) and 1.2–2.1·10⁴
(seed000, above 4100 N·m) / 0.9–2·10⁴ (csf32, above 2000 N·m) near the end; it is negative only
at isolated points at the discrete contact's snaps (T(φ) dropping a few N·m as a tooth's load
moves to the next station, or just after one): seed000 4290.6 and 4722.1 N·m (falling),
csf32 2429.9 (the fine scan: 2378.9 falling, 2431.2 just after, 1.4–1.7·10⁴ between). No
smooth crossing before the symmetric end: the check gives 4749.0 (×2.26) and 2394.7 (×2.39, at
that isolated point). With a radial load on the FS/WG: 100 N, seed000 4705.8 (its check 4589.1),
csf32 2199.9 (path ends; check 2111.3, ×2.11); an eccentricity of 5 / 10 µm as the load of an
upper-bound cup stiffness (2.45·10⁵ / 1.96·10⁵ N/mm): seed000 4424.9 / 4854.8, csf32
2596.2 / 2742.9 (the deeper zone carries more). With a free assembly an eccentricity is absorbed
(the same torque). So the n = 1 mode moves the estimate by −17 … +8 %: it is not what puts
the model at ×2.3–2.5 of the catalogue.

The n = 1 stiffness (:func:`n1_stiffness`): on a path point, τ prescribed ± δ along x and y,
the retreat's fixed point solved again, K = −∂(Σ loads on the FS)/∂τ (2 × 2, N/mm); the
symmetric path is stable in the eccentric mode while K's eigenvalues (plus the cup's k) are
positive. Its zero is the bifurcation (:func:`hand_two_spring_model` is the hand-solvable case).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from profilegen.errors import ConvergenceError, ProfilegenError
from profilegen.lcp import solve_spd

__all__ = ["DedoidalError", "TwoZoneClimb", "TwoZoneState", "n1_stiffness", "stability_limit"]


class DedoidalError(ProfilegenError, ValueError):
    """Bad input to the two-zone climb (names the field, its value, unit and range)."""


@dataclass(slots=True)
class TwoZoneState:
    """The climb's state between calls: springs (mm/N per ball, or None: rigid), the ball
    reactions (N), the translations (FS τ then cam c, mm), the loaded set (bool), whether the
    springs have settled, and the FS retreat they cause beyond P·F (mm per tooth)."""

    springs: np.ndarray | None
    reaction_n: np.ndarray
    translation_mm: np.ndarray
    loaded: np.ndarray | None
    done: bool = False
    offset: np.ndarray | float = 0.0
    net_force_n: np.ndarray | None = None


def _positive(name, value, unit, *, allow_zero=False):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise DedoidalError(f"{name} = {value!r}: must be a number ({unit})") from None
    if not math.isfinite(v) or v < 0.0 or (v == 0.0 and not allow_zero):
        raise DedoidalError(f"{name} = {value!r} {unit}: must be finite and {'≥' if allow_zero else '>'} 0")
    return v


class TwoZoneClimb:
    """Both zones' climb with the FS/WG translation free (module docstring).

    The general form (a model for :func:`~profilegen.contact.climb.climb`): ``zone1``,
    ``zone2`` each provide the climb's one-zone geometry — ``geometry(s, phi) → (gap, lever)``
    (which sets its ``sin_alpha`` and, for its FS tip-corner stations ``_ci``, the cone weights
    ``_a``, ``_b``), and ``n``, ``slot``, ``depth_mm``, ``corner`` (a
    :class:`~profilegen.contact.climb.DesignClimb` does); ``compliance_mm_per_n``: the
    flexibility of the built columns, per zone [stations (n), the corners' tip-land columns
    (nc), the tip-land probes (m)], zone 1 then zone 2, then the balls (nb): (2(n + nc + m) + nb)²;
    ``directions``: each built column's load direction on the FS (global frame, (…, 2));
    ``ball_gap_mm``: the balls' no-load gaps; ``ring_mm_per_n``: the CS ring's radial
    compliance at the 2m teeth for radial loads at them (None: no ring); ``bearing``: the
    Hertz balls (None: rigid). Options of the module docstring: ``wave_generator``,
    ``cup_stiffness_n_per_mm``, ``eccentricity_mm``, ``eccentricity_direction_rad``,
    ``external_force_n`` (a radial load on the FS/WG assembly, N, 2: an imperfection the free
    assembly cannot absorb), ``translation_mm`` (the FS ring's τ prescribed; None: solved).
    :meth:`from_design` builds it for a design's zone."""

    def __init__(self, zone1, zone2, compliance_mm_per_n, directions, *, ball_gap_mm=None, ring_mm_per_n=None,
                 bearing=None, wave_generator: str = "floating", cup_stiffness_n_per_mm: float = 0.0,
                 eccentricity_mm: float = 0.0, eccentricity_direction_rad: float = 0.0, external_force_n=None,
                 translation_mm=None, spring_tol: float = 1e-3):
        if wave_generator not in ("floating", "held"):
            raise DedoidalError(f"wave_generator = {wave_generator!r}: must be 'floating' (an Oldham coupling) or "
                                "'held' (the cam on the CS axis)")
        k_cup = _positive("cup_stiffness_n_per_mm", cup_stiffness_n_per_mm, "N/mm", allow_zero=True)
        ecc = float(eccentricity_mm)
        if not math.isfinite(ecc):
            raise DedoidalError(f"eccentricity_mm = {eccentricity_mm!r}: must be finite (mm)")
        self.zone1, self.zone2 = zone1, zone2
        n, ci = int(zone1.n), np.asarray(zone1._ci, dtype=int)
        m = int(np.asarray(zone1.depth_mm).size)
        nc = ci.size
        big = n + nc + m
        c = np.asarray(compliance_mm_per_n, dtype=float)
        nb = c.shape[0] - 2 * big
        if c.ndim != 2 or c.shape[0] != c.shape[1] or nb < 0 or (wave_generator == "floating" and nb == 0):
            raise DedoidalError(f"compliance_mm_per_n: shape {c.shape} does not fit 2 zones of {big} columns "
                                "(+ balls; a floating cam needs balls)")
        dirs = np.asarray(directions, dtype=float)
        if dirs.shape != (c.shape[0], 2):
            raise DedoidalError(f"directions: shape {dirs.shape}, must be ({c.shape[0]}, 2)")
        self.n_zone, self.m_zone, self._ci, self._big, self.nb = n, m, ci, big, nb
        self.bearing = bearing
        # the unknowns: the stations of both zones, then the balls; the corners' columns combined per call
        sel = np.concatenate([np.arange(n), big + np.arange(n), 2 * big + np.arange(nb)])
        self._sel = sel
        self._corner_cols = np.concatenate([ci, n + ci])  # in the unknowns
        self._corner_built = np.concatenate([ci, big + ci])
        self._tip_built = np.concatenate([n + np.arange(nc), big + n + np.arange(nc)])
        self._probe = np.concatenate([np.arange(n + nc, big), big + np.arange(n + nc, big)])
        self._c = 0.5 * (c + c.T)
        self._cols = self._c[:, sel]
        self._ball_gap = np.zeros(nb) if ball_gap_mm is None else np.asarray(ball_gap_mm, dtype=float)
        cols = [dirs]
        if wave_generator == "floating":
            cam = np.zeros_like(dirs)
            cam[2 * big:] = -dirs[2 * big:]
            cols.append(cam)
        self._trans = np.hstack(cols)  # (built, 2 or 4): the FS ring's τ, the cam's c
        nd = self._trans.shape[1]
        self._k = np.zeros(nd)
        self._k[:2] = k_cup
        self._rest = np.zeros(nd)
        self._rest[:2] = ecc * np.array([math.sin(eccentricity_direction_rad), math.cos(eccentricity_direction_rad)])
        self._load = np.zeros(nd)
        if external_force_n is not None:
            self._load[:2] = np.asarray(external_force_n, dtype=float).reshape(2)
        self._fixed = None if translation_mm is None else np.asarray(translation_mm, dtype=float).reshape(2)
        self._ring = None if ring_mm_per_n is None else np.asarray(ring_mm_per_n, dtype=float)
        self.wave_generator = wave_generator
        self._spring_tol = float(spring_tol)
        # the model interface of climb()
        self.zones = 1  # T = Σ F r over both zones
        self.n = 2 * n
        self.slot = np.concatenate([zone1.slot, np.asarray(zone2.slot) + m])
        self.depth_mm = np.concatenate([zone1.depth_mm, zone2.depth_mm])
        self.corner = np.concatenate([zone1.corner, zone2.corner])
        self.corner_criterion = bool(getattr(zone1, "corner_criterion", False))
        self.sin_alpha = np.concatenate([zone1.sin_alpha, zone2.sin_alpha])
        self._ab = (np.ones(2 * nc), np.zeros(2 * nc))

    @classmethod
    def from_design(cls, inputs, zone, *, bearing=None, ring=None, ring_scale: float = 1.0,
                    race_thickness_mm: float | None = None, **options) -> "TwoZoneClimb":
        """The two-zone climb of a design: ``zone`` its one-zone :class:`~profilegen.contact.
        climb.DesignClimb` (built with ``shift_rad`` = 0; its stations, corners and probes are
        both zones'; zone 2 is its copy, the same geometry in its own frame), the FS as the whole
        ring (:class:`~research.tooth_errors.TwoZoneContact`'s build for those
        columns, every ball one-sided at its no-load gap), ``ring`` = (mean radius, radial
        thickness, width) of the free CS ring in mm (None: no ring; × ``ring_scale``)."""
        from profilegen.geometry.kinematics import turn
        from profilegen.contact.climb import tooth_probes
        from profilegen.contact.compliance import ContactCompliance
        from profilegen.contact.ratchet import cs_ring_radial_compliance
        from research.tooth_errors import TwoZoneContact

        if getattr(zone, "_ci", None) is None or not hasattr(zone, "points"):
            raise DedoidalError(f"zone = {zone!r}: must be a profilegen.contact.climb.DesignClimb")
        if float(options.get("cup_stiffness_n_per_mm", 0.0)) != 0.0:
            raise DedoidalError(f"cup_stiffness_n_per_mm = {options['cup_stiffness_n_per_mm']!r} N/mm: must be 0 here "
                                "— the whole ring's translation is gauged at its bore on the major axis, not at its "
                                "centre, so a spring on it would act on the ring's own deformation; give the load the "
                                "cup puts on the assembly as external_force_n (k_c e for an eccentricity e)")
        pts = zone.points
        gs = inputs.gearset
        z2 = gs.gear.circular_spline_teeth
        ci = np.asarray(zone._ci, dtype=int)
        teeth, phis, fs_probe, e_r, cs_probe, _ = tooth_probes(inputs, pts)
        # the corners' tip-land normals in the CS frame, as DesignClimb builds its columns
        pose = inputs.motion.pose(pts.phi_rad[ci]) if ci.size else None
        tip_n = np.zeros((0, 2)) if pose is None else np.column_stack([np.sin(pose.angle), np.cos(pose.angle)])
        tip = np.vstack([turn(tip_n[k:k + 1], 2.0 * math.pi * t / z2) for k, t in enumerate(pts.tooth[ci])]) \
            if ci.size else np.zeros((0, 2))
        fs = np.vstack([pts.fs_point_mm, pts.fs_point_mm[ci], fs_probe])
        normal = np.vstack([pts.normal, tip, e_r])
        tooth = np.concatenate([pts.tooth, pts.tooth[ci], teeth])
        comp = ContactCompliance.build(inputs, fs, normal, tooth,
                                       np.vstack([pts.cs_point_mm, pts.cs_point_mm[ci], cs_probe]),
                                       race_thickness_mm=race_thickness_mm, ball_supports="all",
                                       cs_ring=False)  # the ring: ring_matrix below, as the climb's
        layout = SimpleNamespace(tooth=tooth, fs_point_mm=fs, normal=normal, lever_mm=np.ones(tooth.size),
                                 theta_rad=np.zeros(tooth.size), rotation=pts.rotation, side=pts.side,
                                 count=int(tooth.size))
        full = TwoZoneContact(inputs, layout, comp, race_thickness_mm=race_thickness_mm)
        ring_matrix = None
        if ring is not None:
            r_mean, thick, width = ring
            ang = np.concatenate([phis, phis + math.pi])
            ring_matrix = float(ring_scale) * cs_ring_radial_compliance(
                ang, ang, mean_radius_mm=r_mean, thickness_mm=thick, width_mm=width,
                youngs_modulus_mpa=float(gs.material.youngs_modulus_mpa))
        out = cls(zone, copy.copy(zone), full.c, full.directions, ball_gap_mm=full.ball_gap,
                  ring_mm_per_n=ring_matrix, bearing=bearing, **options)
        out.teeth = teeth
        return out

    # ------------------------------------------------------------------ options
    def with_translation(self, translation_mm) -> "TwoZoneClimb":
        """A copy with the FS ring's translation prescribed (mm, 2; None: solved)."""
        out = copy.copy(self)
        out.zone1, out.zone2 = copy.copy(self.zone1), copy.copy(self.zone2)
        out._fixed = None if translation_mm is None else np.asarray(translation_mm, dtype=float).reshape(2)
        return out

    def with_imperfection(self, *, external_force_n=None, eccentricity_mm: float = 0.0,
                          eccentricity_direction_rad: float = 0.0) -> "TwoZoneClimb":
        """A copy (the matrices shared) with another radial load on the FS/WG assembly (N, 2)
        and eccentricity (mm, the cup's rest position; acts only through a cup spring)."""
        ecc = float(eccentricity_mm)
        if not math.isfinite(ecc):
            raise DedoidalError(f"eccentricity_mm = {eccentricity_mm!r}: must be finite (mm)")
        out = self.with_translation(self._fixed)
        out._load = np.zeros_like(self._load)
        if external_force_n is not None:
            out._load[:2] = np.asarray(external_force_n, dtype=float).reshape(2)
        out._rest = np.zeros_like(self._rest)
        out._rest[:2] = ecc * np.array([math.sin(eccentricity_direction_rad), math.cos(eccentricity_direction_rad)])
        return out

    # ------------------------------------------------------------------ climb's interface
    def initial_state(self) -> TwoZoneState:
        return TwoZoneState(None, np.zeros(self.nb), np.zeros(self._trans.shape[1]), None)

    def settled(self, state) -> bool:
        return state.done

    def retreat_offset(self, state):
        return state.offset

    def geometry(self, s, phi: float = 0.0):
        """Both zones' gaps and levers (zone 1's stations, then zone 2's) with their teeth ``s``
        (2m, mm) out of their spaces and the FS turned by ``phi``; keeps the corner cones."""
        m = self.m_zone
        s = np.asarray(s, dtype=float)
        g1, r1 = self.zone1.geometry(s[:m], phi)
        g2, r2 = self.zone2.geometry(s[m:], phi)
        self.sin_alpha = np.concatenate([self.zone1.sin_alpha, self.zone2.sin_alpha])
        if self._ci.size:
            self._ab = (np.concatenate([self.zone1._a, self.zone2._a]), np.concatenate([self.zone1._b, self.zone2._b]))
        return np.concatenate([g1, g2]), np.concatenate([r1, r2])

    def matrices(self, springs):
        """(M, P, D, D_probe, P_cs) at the last geometry: the unknowns' compliance (stations of
        both zones, then balls; mm/N; a corner station's row and column a n_f + b n_t of its
        flank's and tip land's, a congruence), the probes' rows (the teeth's FS retreat per
        unknown), the translations' directions on the unknowns and on the probes, and the CS
        ring's retreat per station force."""
        a, b = self._ab
        cols = self._cols.copy()
        jc, jb, jt = self._corner_cols, self._corner_built, self._tip_built
        if jc.size:
            cols[:, jc] = a * self._c[:, jb] + b * self._c[:, jt]
        m_mat = cols[self._sel]
        trans = self._trans[self._sel]
        if jc.size:
            m_mat[jc] = a[:, None] * cols[jb] + b[:, None] * cols[jt]
            trans[jc] = a[:, None] * self._trans[jb] + b[:, None] * self._trans[jt]
        nst = self.n
        if springs is not None:
            idx = np.arange(nst, nst + self.nb)
            m_mat[idx, idx] += springs
        if self._ring is not None:
            p_cs = self._ring[:, self.slot] * self.sin_alpha[None, :]
            s_ring = self.sin_alpha[:, None] * p_cs[self.slot]
            m_mat[:nst, :nst] += 0.5 * (s_ring + s_ring.T)
        else:
            p_cs = np.zeros((2 * self.m_zone, nst))
        return 0.5 * (m_mat + m_mat.T), cols[self._probe], trans, self._trans[self._probe], p_cs

    def respond(self, q, state):
        nst = self.n
        m_mat, p, d, d_probe, p_cs = self.matrices(state.springs)
        qf = np.concatenate([np.asarray(q, dtype=float), self._ball_gap])
        x, tau, loaded = self.solve_mixed(m_mat, qf, d, state)
        react = x[nst:]
        springs, done = state.springs, True
        if self.bearing is not None:
            floor = max(1.0, 1e-3 * float(react.max(initial=0.0)))
            new = self.bearing.secant_compliance_mm_per_n(react, floor_n=floor)
            done = springs is not None and bool(np.all(np.abs(new / springs - 1.0) <= self._spring_tol))
            springs = new
        offset = p[:, nst:] @ react + d_probe @ tau
        net = d[:, :2].T @ x
        return x[:nst], TwoZoneState(springs, react, tau, loaded, done, offset, net), p[:, :nst], p_cs

    # ------------------------------------------------------------------ the mixed LCP
    def solve_mixed(self, m_mat, qf, d, state):
        """x ≥ 0, w = M x + q + D τ ≥ 0, x·w = 0, with the translations' balance
        Dᵀx − k (τ − τ₀) + P = 0 (the loads on the FS along their directions, the cup's spring,
        the external load; k = 0: a free translation) and the FS's τ prescribed when
        ``translation_mm`` is given → (x, τ, loaded set)."""
        k, rest, load = self._k.copy(), self._rest.copy(), self._load.copy()
        free = np.ones(k.size, bool)
        q = qf.copy()
        tau = np.zeros(k.size)
        if self._fixed is not None:
            free[:2] = False
            tau[:2] = self._fixed
            q = q + d[:, :2] @ self._fixed
        df = d[:, free]
        out = None
        if state.loaded is not None:
            out = self._active_set(m_mat, q, df, k[free], rest[free], load[free], state.loaded)
        if out is None:
            out = self._newton(m_mat, q, df, k[free], rest[free], load[free], state.translation_mm[free])
        x, t_free, loaded = out
        tau[free] = t_free
        return x, tau, loaded

    @staticmethod
    def _bordered(m_mat, q, df, k, rest, load, p):
        kp = p.size
        nd = df.shape[1]
        a = np.zeros((kp + nd, kp + nd))
        a[:kp, :kp] = m_mat[np.ix_(p, p)]
        a[:kp, kp:] = df[p]
        a[kp:, :kp] = df[p].T
        a[kp:, kp:] = -np.diag(k)
        rhs = np.concatenate([-q[p], -k * rest - load])
        sol = np.linalg.solve(a, rhs)
        x = np.zeros(q.size)
        x[p] = sol[:kp]
        return x, sol[kp:]

    def _active_set(self, m_mat, q, df, k, rest, load, loaded):
        from research.tooth_errors import active_set_loop

        tol = 1e-12 * (float(np.max(np.abs(q))) or 1.0)

        def solve(p):
            x, tau = self._bordered(m_mat, q, df, k, rest, load, p)
            return x, m_mat @ x + q + df @ tau, tol, tau

        out = active_set_loop(loaded, solve, max_iter=4 * q.size + 20)
        if out is None:
            return None
        x, _, loaded, tau = out
        return x, tau, loaded

    def _newton(self, m_mat, q, df, k, rest, load, tau):
        """Newton ascent on the concave dual h(τ) = min_{x≥0} ½xᵀMx + (q + Dτ)ᵀx − ½(τ−τ₀)ᵀk(τ−τ₀)
        + Pᵀτ, whose gradient is the translations' balance Dᵀx − k (τ − τ₀) + P."""
        tau = np.asarray(tau, dtype=float).copy()
        if not tau.size:  # nothing free: the plain LCP
            x = solve_spd(m_mat, q)
            return x, tau, x > 0.0

        def at(t):
            x = solve_spd(m_mat, q + df @ t)
            h = 0.5 * x @ (m_mat @ x) + (q + df @ t) @ x - 0.5 * (t - rest) @ (k * (t - rest)) + load @ t
            return x, h, df.T @ x - k * (t - rest) + load

        x, h, g = at(tau)
        scale = max(float(np.abs(x).max(initial=0.0)), 1e-300) * max(float(np.abs(df).max()), 1.0)
        for _ in range(100):
            if float(np.abs(g).max(initial=0.0)) <= 1e-10 * scale:
                return x, tau, x > 0.0
            p = np.flatnonzero(x > 0.0)
            jac = -np.diag(k) - (df[p].T @ cho_solve(cho_factor(m_mat[np.ix_(p, p)]), df[p]) if p.size else 0.0)
            jac = jac - 1e-12 * np.abs(jac).max(initial=1.0) * np.eye(k.size)
            step = np.linalg.solve(jac, -g)
            lam = 1.0
            for _ in range(40):
                x2, h2, g2 = at(tau + lam * step)
                if h2 >= h + 1e-4 * lam * (g @ step) or lam < 1e-9:
                    break
                lam *= 0.5
            tau, x, h, g = tau + lam * step, x2, h2, g2
        raise ConvergenceError(f"TwoZoneClimb: the translations' balance did not close (residual "
                               f"{float(np.abs(g).max()):.3g} N)")

    # ------------------------------------------------------------------ diagnostics
    def zone_torques_nm(self, point) -> np.ndarray:
        """Each zone's share of the torque (N·m) at a climb point (its forces and its levers)."""
        _, lever = self.geometry(point.retreat_mm, point.phi_rad)
        n = self.n_zone
        f = point.force_n
        return np.array([f[:n] @ lever[:n], f[n:] @ lever[n:]]) / 1e3


def n1_stiffness(model: TwoZoneClimb, point, *, delta_mm: float = 1e-3, tol_mm: float = 1e-6,
                 max_iterations: int = 80) -> np.ndarray:
    """The eccentric mode's stiffness at a point of the climb (N/mm, 2 × 2, x then y): the FS
    ring's translation prescribed at the point's ±``delta_mm`` along x and along y at the
    point's rotation, the retreat's fixed point found again from the point's (the climb's
    Anderson iteration to ``tol_mm``; ×10, ×100 if it does not settle), and
    K[:, j] = −Δ(Σ contact loads on the FS)/(2δ) — the cup's spring not included. The path
    is stable against going off-centre while K + k_c·I has no eigenvalue ≤ 0."""
    from profilegen.contact.climb import _solve_at

    delta = _positive("delta_mm", delta_mm, "mm")
    k = np.zeros((2, 2))
    base = np.asarray(point.state.translation_mm[:2], dtype=float)
    for j in range(2):
        nets = []
        for sign in (1.0, -1.0):
            tr = base.copy()
            tr[j] += sign * delta
            probe = model.with_translation(tr)
            state = copy.copy(point.state)
            state.loaded = None
            for tol in (tol_mm, 10.0 * tol_mm, 100.0 * tol_mm):
                try:
                    out = _solve_at(probe, point.phi_rad, point.retreat_fs_mm.copy(),
                                    (point.retreat_mm - point.retreat_fs_mm).copy(), state, tol_mm=tol,
                                    max_iterations=max_iterations)
                    break
                except ConvergenceError:
                    if tol == 100.0 * tol_mm:
                        raise
            nets.append(out[3].net_force_n)
        k[:, j] = -(nets[0] - nets[1]) / (2.0 * delta)
    return k


def _falling(model, point, *, tol_mm: float, max_iterations: int, fraction: float = 1e-3) -> bool:
    """Whether ``point`` lies on a stretch where T(φ) falls: the path solved again a little
    before it (φ (1 − ``fraction``), from the point's state) carries more torque."""
    from profilegen.contact.climb import _point, _solve_at

    phi = point.phi_rad * (1.0 - fraction)
    state = copy.copy(point.state)
    try:
        f, s_fs, s_cs, st, lever, it = _solve_at(model, phi, point.retreat_fs_mm.copy(),
                                                 (point.retreat_mm - point.retreat_fs_mm).copy(), state,
                                                 tol_mm=tol_mm, max_iterations=max_iterations)
    except ConvergenceError:
        return False
    return _point(model, phi, f, s_fs, s_cs, st, lever, it).torque_nm > point.torque_nm


def stability_limit(model: TwoZoneClimb, path, *, cup_stiffness_n_per_mm: float = 0.0, delta_mm: float = 1e-3,
                    tol_mm: float = 1e-6, max_iterations: int = 80) -> dict:
    """The climb's path checked point by point in the eccentric mode: the smallest real part
    of the eigenvalues of K + k_c·I (:func:`n1_stiffness`; N/mm) at every point, and the first
    torque where it reaches 0 (linear in the torque between the last stable point and the
    first unstable one) — under rotation control the FS/WG assembly then goes off-centre
    and the loaded zone skips (a stable path's largest torque ends earlier only at its own
    limit). A point on a stretch where T(φ) falls (solved again 0.1 % of φ before it: more
    torque there) is a snap of the discrete contact — a tooth's load moving to the next
    station, T dropping by a few N·m on seed000_csf40 — unstable in every mode; its stiffness
    is reported (``falling``) but it is not taken as the eccentric mode's bifurcation.
    → {"torque_nm": the limit (the path's own when it stays stable), "criterion":
    "eccentric mode" or the path's, "points": [(T, λ_min, K)…], "falling": [T…],
    "failed": [T…] (points where the probe's fixed point did not settle)}."""
    k_cup = _positive("cup_stiffness_n_per_mm", cup_stiffness_n_per_mm, "N/mm", allow_zero=True)
    rows, failed, falling = [], [], []
    prev = None
    for p in path.points:
        try:
            k = n1_stiffness(model, p, delta_mm=delta_mm, tol_mm=tol_mm, max_iterations=max_iterations)
        except ConvergenceError:
            failed.append(float(p.torque_nm))
            continue
        lam = float(np.min(np.linalg.eigvals(k + k_cup * np.eye(2)).real))
        rows.append((float(p.torque_nm), lam, k))
        if lam <= 0.0:
            if _falling(model, p, tol_mm=tol_mm, max_iterations=max_iterations):
                falling.append(float(p.torque_nm))
                continue
            if prev is None:
                t = float(p.torque_nm)
            else:
                (t0, l0), t1 = prev, float(p.torque_nm)
                t = t0 + l0 / (l0 - lam) * (t1 - t0)
            return {"torque_nm": t, "criterion": "eccentric mode", "points": rows, "falling": falling,
                    "failed": failed}
        prev = (float(p.torque_nm), lam)
    return {"torque_nm": float(path.torque_nm), "criterion": path.criterion, "points": rows, "falling": falling,
            "failed": failed}
