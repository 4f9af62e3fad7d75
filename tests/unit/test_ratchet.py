"""The ratcheting estimate (profilegen.contact.ratchet) and its bad inputs.

Analytic: the CS ring's radial compliance (curved-beam Fourier series) against Roark's closed
forms for a thin ring pulled by two opposite radial point loads — under the loads
(π/4 − 2/π)/2 · P R³/EI, at 90° −(2/π − 1/2)/2 · P R³/EI, plus the extensional n = 0 term
P R/(π E A) — and the series' truncation error falling as N⁻³. On the default set's sketch
design: the CS ring moves outward under the tooth forces' radial components, softer ball
supports (Hertz) let the loaded teeth ride further out than rigid ones, the estimate lies
above every solved torque whose margin is positive, and the bad inputs are named errors.

The climb (profilegen.contact.climb): its complementarity solve against enumeration of every
active set; one tooth on a radial spring k at radius R, solved by hand — a straight flank at
pressure angle α retreats s = T tan α /(k R), so it reaches the depth h at T = k R h cot α;
an FS tip arc (ρ1) on a CS arc (ρ2) has sin β = sin β0 + s/(ρ1 + ρ2) and
T(s) = k R s cot β(s), whose maximum is the limit point; on the sketch design, the climb's
first rotations against the package's linear contact (Lemke, same S) at the same torque.

Friction (Coulomb μ = tan ρ, the force on the CS N (n + μσt), t the flank's tangent out of
the space, σ = +1 when the FS slides out, −1 in): by hand, the one tooth's force has the
tangential part N cos(α − σρ)/cos ρ and the radial part N sin(α − σρ)/cos ρ, so
T = k R s cot(α − σρ) — the straight flank reaches h at k R h cot(α − σρ), the two arcs'
limit point is max_s k R s cot(β(s) − σρ); the nonsymmetric LCP's Lemke solve against
enumeration; on the sketch design μ = 0 through the friction path is the frictionless climb,
and the running sense: the gear driven forward puts power in through the loaded teeth's
radial motion (the wave generator pushes them into their spaces) and turns the FS the way
the CS's forces push it.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

import profilegen as pg
from profilegen.contact.chain import BallBearing
from profilegen.contact.climb import DesignClimb, climb, sliding_tangent
from profilegen.lcp import solve_p_matrix, solve_spd
from profilegen.contact.ratchet import (
    BearingFitError,
    RatchetingError,
    check_bearing_fits,
    cs_ring_radial_compliance,
    ratcheting_torque,
)

R, H, W, E = 57.5, 13.0, 20.0, 206000.0


def _ring(at, harmonics=200):
    return cs_ring_radial_compliance([0.0, math.pi], at, mean_radius_mm=R, thickness_mm=H, width_mm=W,
                                     youngs_modulus_mpa=E, harmonics=harmonics).sum(axis=1)


def test_ring_against_roark_two_opposite_loads():
    """Roark, Formulas for Stress and Strain, thin ring under two equal opposite diametral
    loads: ΔD along the loads (π/4 − 2/π) P R³/EI, across (2/π − 1/2) P R³/EI (opposite sign)."""
    inertia, area = W * H ** 3 / 12.0, W * H
    scale = R ** 3 / (E * inertia)
    extension = R / (math.pi * E * area)
    under, across = _ring([0.0, 0.5 * math.pi])
    assert under - extension == pytest.approx(0.5 * (math.pi / 4 - 2 / math.pi) * scale, rel=1e-6)
    assert across - extension == pytest.approx(-0.5 * (2 / math.pi - 0.5) * scale, rel=1e-6)


def test_ring_series_converges_as_n_cubed():
    exact = _ring([0.0], harmonics=4000)[0]
    errors = [abs(_ring([0.0], harmonics=n)[0] - exact) for n in (20, 40, 80)]
    rates = [math.log2(errors[k] / errors[k + 1]) for k in range(2)]
    assert all(2.8 < r < 3.2 for r in rates), rates


@pytest.fixture(scope="module")
def design():
    return pg.design(pg.load_gearset(pg.default_gearset_path()), scene="sketch", contact=False, stress=False)


TORQUES = [132.5, 265.0, 397.5]


@pytest.fixture(scope="module")
def whole(design):
    return ratcheting_torque(design, options=dict(torques_nm=TORQUES, stations=3, climb=False))


def test_estimate_and_its_parts(whole):
    r = whole
    assert r.valid.all()
    # the CS ring is pushed outward under the loaded teeth: the tooth forces' radial components push the CS out
    assert np.all(r.separation_cs_mm > 0.0)
    assert np.allclose(r.separation_mm, r.separation_fs_mm + r.separation_cs_mm, rtol=0, atol=1e-15)
    # the loaded teeth are in their spaces at every solved torque: the estimate lies beyond them
    assert np.all(r.margin_mm() > 0.0) and np.all(r.mean_depth_mm > 0.3)
    assert r.extrapolated and r.torque_nm > max(TORQUES)
    # proportional bound: no solved torque scaled by h̄/Δr̄ comes below it
    out = r.mean_separation_mm > 0
    assert np.all(r.torques_nm[out] * r.mean_depth_mm[out] / r.mean_separation_mm[out] >= r.torque_nm * (1 - 1e-12))
    assert r.catalogue is None and r.ratio_to_catalogue is None
    d = json.loads(json.dumps(r.to_dict()))
    assert d["torque_nm"] == pytest.approx(r.torque_nm) and d["catalogue"] is None


def test_softer_balls_let_the_teeth_ride_out(design):
    """Rigid ball supports against the Hertz springs (no CS ring in either): the rim sinks into
    the softer supports, so the loaded teeth move further out of their spaces (force-weighted)."""
    rigid = ratcheting_torque(design, options=dict(torques_nm=TORQUES, stations=3, bearing=None, cs_ring=False,
                                                  climb=False))
    hertz = ratcheting_torque(design, options=dict(torques_nm=TORQUES, stations=3, cs_ring=False, climb=False))
    assert np.all(rigid.separation_cs_mm == 0.0) and np.all(hertz.separation_cs_mm == 0.0)
    assert np.all(hertz.mean_separation_mm > rigid.mean_separation_mm + 2e-3)  # > 2 µm further out


def test_flag_and_zero_torque(whole, design):
    r = whole
    assert r.flag(265.0) is None
    assert "ratcheting estimate" in r.flag(-1.0001 * r.torque_nm)
    for bad in (0.0, float("nan")):
        with pytest.raises(RatchetingError, match="torque_nm"):
            r.flag(bad)
    with pytest.raises(RatchetingError, match=r"torques_nm\[0\] = 0.0 N·m"):
        ratcheting_torque(design, options={"torques_nm": [0.0, 265.0]})
    with pytest.raises(RatchetingError, match="bearing"):
        ratcheting_torque(design, options={"bearing": "steel"})
    for name, bad in (("climb_positions", 0), ("climb_ball_supports", "some"), ("climb_corner_normal", "yes"),
                      ("climb_friction", -0.1), ("climb_friction", 1.0), ("climb_sliding", "sideways")):
        with pytest.raises(RatchetingError, match=name):
            ratcheting_torque(design, options={name: bad})
    with pytest.raises(RatchetingError, match="options: unknown key 'climb_ring'"):
        ratcheting_torque(design, options={"climb_ring": 2.0})
    with pytest.raises(RatchetingError, match="options = 3"):
        ratcheting_torque(design, options=3)


def test_bearing_that_does_not_fit():
    gs = pg.load_gearset(pg.default_gearset_path())
    thin = dataclasses.replace(gs, wave_generator=dataclasses.replace(gs.wave_generator, bearing_thickness_mm=8.0))
    balls = BallBearing(23, 7.5, 84.5, 0.52, 2.06e5, 0.3)
    with pytest.raises(BearingFitError, match=r"ball_diameter_mm = 7.5 mm: must be in \(0, 3\] mm.*"
                                              r"wave_generator.bearing_thickness_mm = 8 mm"):
        check_bearing_fits(thin, balls)
    check_bearing_fits(thin, dataclasses.replace(balls, ball_diameter_mm=2.5))  # 2.5 + 2 × 2.5 mm races fit in 8
    with pytest.raises(BearingFitError, match="ball_diameter_mm"):
        check_bearing_fits(gs, race_thickness_mm=30.0)  # no room left inside a 30 mm race
    with pytest.raises(BearingFitError, match="race_thickness_mm = -1.0 mm"):
        check_bearing_fits(gs, race_thickness_mm=-1.0)
    assert issubclass(BearingFitError, ValueError)


# --------------------------------------------------------------------------- the climb


def test_lcp_against_enumeration():
    rng = np.random.default_rng(3)
    for _ in range(5):
        a = rng.normal(size=(6, 6))
        s = a @ a.T + 0.5 * np.eye(6)
        q = rng.normal(size=6)
        f = solve_spd(s, q)
        best = None
        for mask in range(64):  # the one active set whose solution is complementary
            idx = [k for k in range(6) if mask >> k & 1]
            g = np.zeros(6)
            if idx:
                g[idx] = np.linalg.solve(s[np.ix_(idx, idx)], -q[idx])
            if np.all(g >= -1e-12) and np.all(s @ g + q >= -1e-12):
                best = g
        np.testing.assert_allclose(f, best, atol=1e-10)
        w = s @ f + q
        assert np.all(f >= 0) and np.all(w >= -1e-12) and abs(f @ w) < 1e-10


class _OneTooth:
    """One tooth on a radial spring k (N/mm) at radius R (mm), in a frame with e_r = +y: an FS
    tip arc (radius rho1, stations over beta in [5°, 60°], normals (cos β, sin β)) on a CS arc
    (rho2) touching at beta0, or a straight FS flank on a parallel CS line at pressure angle
    beta0. The FS turned by φ moves by R φ along +x. S = u uᵀ/k + c I (u = sin β: the spring
    seen along each normal; c a local compliance), P = uᵀ/k."""

    zones = 1

    def __init__(self, *, straight=False, k=2000.0, r=50.0, c=2e-5, rho1=0.6, rho2=0.8, beta0=math.radians(15),
                 n=80, depth=0.8, mu=0.0, sigma=1.0):
        self.k, self.r, self.straight = k, r, straight
        beta = np.full(n, beta0) if straight else np.linspace(math.radians(5), math.radians(60), n)
        self.normal = np.column_stack([np.cos(beta), np.sin(beta)])
        if straight:
            self.p0 = np.linspace(-0.3, 0.3, n)[:, None] * np.array([-math.sin(beta0), math.cos(beta0)])
        else:
            self.p0 = rho1 * self.normal
            self.c2 = (rho1 + rho2) * np.array([math.cos(beta0), math.sin(beta0)])
        self.rho2 = rho2
        self.sin_alpha = self.normal[:, 1].copy()
        self.slot, self.corner = np.zeros(n, int), np.zeros(n, bool)
        self.depth_mm = np.array([depth])
        # the force on the CS per unit normal force: n + μσt (t ⊥ n, out of the space: t·e_r < 0);
        # the spring takes its radial part, the local compliance c its normal part (n·t = 0)
        self.mu = mu
        self.force = self.normal + mu * sigma * sliding_tangent(self.normal, np.array([[0.0, 1.0]] * n))[1]
        self.s = c * np.eye(n) + np.outer(self.sin_alpha, self.force[:, 1]) / k
        self.p = (self.force[:, 1] / k)[None, :]

    def geometry(self, s, phi=0.0):
        p = self.p0 + np.array([self.r * phi, -s[0]])
        gap = -(p @ self.normal[0]) if self.straight else np.linalg.norm(p - self.c2, axis=1) - self.rho2
        return gap, self.r * self.force[:, 0]

    def initial_state(self):
        return None

    def settled(self, state):
        return True

    def respond(self, q, state):
        return (solve_p_matrix if self.mu else solve_spd)(self.s, q), None, self.p, np.zeros_like(self.p)


def test_climb_straight_flank_reaches_the_depth_at_k_r_h_cot_alpha():
    alpha, h = math.radians(20), 0.3
    model = _OneTooth(straight=True, beta0=alpha, depth=h, n=20)
    path = climb(model, 1e-6, 2e-4)
    assert path.criterion == "margin"
    assert path.torque_nm == pytest.approx(model.k * model.r * h / math.tan(alpha) / 1e3, rel=1e-6)
    # along the path: s = T tan α / (k R)
    for p in path.points:
        assert p.retreat_mm[0] == pytest.approx(p.torque_nm * 1e3 * math.tan(alpha) / (model.k * model.r), rel=1e-6)


def test_climb_two_arcs_limit_point():
    rho, beta0 = 1.4, math.radians(15)
    model = _OneTooth()
    path = climb(model, 1e-6, 2e-4, refine=4)
    s = np.linspace(0.0, 1.0, 100001)
    sb = math.sin(beta0) + s / rho
    ok = sb < math.sin(math.radians(60))
    exact = np.max((model.k * model.r * s * np.sqrt(1 - sb ** 2) / sb)[ok]) / 1e3
    assert path.criterion == "limit point"
    assert path.torque_nm == pytest.approx(exact, rel=1e-2)  # stations 0.7° apart on the arc
    # the pressure angle rose from 15° on the way; a constant 15° would carry 4× more to the same depth
    assert path.points[-1].alpha_deg > 35.0
    assert path.torque_nm < 0.25 * model.k * model.r * model.depth_mm[0] / math.tan(beta0) / 1e3


class _Peak:
    """One station on a unit spring (S = 1 mm/N, no retreat), gap −φ and lever arm
    exp(−(φ/φ0)⁸): T(φ) = φ e^{−(φ/φ0)⁸}/1000 N·m, a sharp limit point at φ* = φ0 8^{−1/8},
    T* = φ* e^{−1/8}/1000. ``window``: rotations with no fixed point (a ConvergenceError)."""

    zones = 1

    def __init__(self, window=(math.inf, -math.inf)):
        self.window = window
        self.slot, self.corner, self.sin_alpha = np.zeros(1, int), np.zeros(1, bool), np.zeros(1)
        self.depth_mm = np.array([1e9])

    def geometry(self, s, phi=0.0):
        from profilegen.errors import ConvergenceError

        if self.window[0] < phi < self.window[1]:
            raise ConvergenceError("no fixed point here (the test's window)")
        return np.array([-phi]), np.array([math.exp(-phi ** 8)])

    def initial_state(self):
        return None

    def settled(self, state):
        return True

    def respond(self, q, state):
        return np.maximum(-q, 0.0), None, np.zeros((1, 1)), np.zeros((1, 1))


def test_climb_limit_point_kept_when_its_bracket_cannot_be_refined():
    """The limit point's refinement starts from the point two before the fall; where no fixed
    point is found between it and the peak's point, the peak's point must be kept (the climb
    before dropped it and took a torque 9 % low, from the falling branch's refinement) and,
    the bracket unresolved, the torque of that equilibrium taken — not a parabola through the
    coarse bracket, which overshoots a sharp peak (+1.5 % here): at most T*, within 1 % of it."""
    star = 8.0 ** (-1.0 / 8.0)
    t_star = star * math.exp(-1.0 / 8.0) / 1e3
    free = climb(_Peak(), 0.05, 0.05)
    assert free.criterion == "limit point" and free.torque_nm == pytest.approx(t_star, rel=1e-3)
    coarse = climb(_Peak(), 0.05, 0.05, refine=0).points
    i = max(range(len(coarse)), key=lambda j: coarse[j].torque_nm)
    base, top, fall = coarse[i - 1:i + 2]  # the toy has no retreat: its fall is never confirmed and
    # the path runs on to its end, where the fall after its largest torque is the limit point
    assert base.torque_nm < top.torque_nm > fall.torque_nm
    path = climb(_Peak((base.phi_rad + 1e-9, top.phi_rad - 1e-9)), 0.05, 0.05, refine=4)
    assert path.criterion == "limit point"
    assert 0.99 * t_star < path.torque_nm <= t_star
    assert path.torque_nm == top.torque_nm


class _Plateau(_Peak):
    """_Peak's station with T(φ)·1000 = φ up to 0.3, flat at 0.3 to φ = 0.6 (lowered by the
    fraction ``dip`` for 0.4 < φ < 0.5: the wiggle of the stations' contact switching where
    T(φ) is flat), rising as 0.3 + (φ − 0.6) to its peak 0.6 at φ = 0.9, then falling 2 per rad."""

    def __init__(self, dip):
        super().__init__()
        self.dip = dip

    def geometry(self, s, phi=0.0):
        t = phi if phi < 0.3 else 0.3 * (1.0 - self.dip * (0.4 < phi < 0.5)) if phi < 0.6 else \
            phi - 0.3 if phi < 0.9 else 0.6 - 2.0 * (phi - 0.9)
        return np.array([-phi]), np.array([t / phi])


def test_climb_passes_a_wiggle_of_t_below_the_limit_drop_and_a_fall_it_climbs_back_out_of():
    """Where T(φ) is flat the stations' contact switching makes it wiggle (0.1–0.5 % on
    seed000_csf40's verify scene and the default set): a dip of 0.2 % on a plateau (below the 1 %
    ``limit_drop``) is passed, and the limit point is the true peak, 0.6 mN·m at φ = 0.9, where T
    falls (the first decrease of T ended the path before, at the dip: 0.3 mN·m, half of it). A
    dip of 2 % that T climbs back out of is passed too: the toy has no retreat, so its fall is
    never confirmed by the teeth moving out (``limit_span``) and the path runs on — a fall is
    only the limit point where T does not come back above it."""
    for dip in (0.002, 0.02):
        path = climb(_Plateau(dip), 0.05, 0.05)
        assert any(0.4 < p.phi_rad < 0.5 for p in path.points)  # the dip was met
        assert path.criterion == "limit point" and path.torque_nm == pytest.approx(0.6e-3, rel=2e-2)


class _Points:
    """A path's points for the criterion alone: φ, T, the force-weighted retreat and margin."""

    def __init__(self, rows):
        self.rows = [dict(phi_rad=p, torque_nm=t, mean_retreat_mm=s, margin_mm=m, corner_share=0.0)
                     for p, t, s, m in rows]

    def __call__(self, n=None):
        return [type("P", (), r)() for r in self.rows[:n]]


def test_a_fall_is_a_limit_point_once_the_teeth_have_moved_out_by_a_tenth_of_their_margin():
    """The rule of the limit point (profilegen.contact.climb._criterion_met), on the path of a
    CSF-32-100 with a shorter tooth (docs/theory/torsion.md): T fell 1.3 % (1174.4 → 1159.0 N·m)
    while the retreat grew 13.7 µm of the 371.8 µm margin, then rose to 1209 N·m — not a limit
    point, whether or not the path has ended after it; the same fall lasting until the retreat has
    grown by 10 % of that margin is one, at the point after the largest; a fall still waiting for
    its span when the path ends is one only once it has ended (``final``); and a margin crossing
    while a fall waits is the fall's limit point (T had passed its largest)."""
    from profilegen.contact.climb import _criterion_met

    rule = dict(corner_rule=True, limit_drop=0.01, limit_span=0.1)
    rows = [(2.561e-3, 1143.2, 0.1361, 0.3829), (2.637e-3, 1174.4, 0.1419, 0.3718),
            (2.734e-3, 1159.0, 0.1556, 0.3511)]
    back = _Points(rows + [(2.842e-3, 1209.1, 0.1651, 0.3365), (2.977e-3, 1303.5, 0.1708, 0.3230)])
    assert _criterion_met(back(), **rule, final=False) is None
    assert _criterion_met(back(), **rule, final=True) is None  # T came back above the fall
    assert _criterion_met(back(3), **rule, final=False) is None  # waiting for the span
    assert _criterion_met(back(3), **rule, final=True) == ("limit point", 2)  # the path ended there
    lasting = _Points(rows + [(2.80e-3, 1150.0, 0.1419 + 0.1 * 0.3718 + 1e-6, 0.33)])
    assert _criterion_met(lasting(), **rule, final=False) == ("limit point", 2)
    short = _Points(rows + [(2.80e-3, 1150.0, 0.1419 + 0.1 * 0.3718 - 1e-4, 0.33)])
    assert _criterion_met(short(), **rule, final=False) is None
    crossed = _Points(rows + [(2.80e-3, 1100.0, 0.16, -1e-3)])
    assert _criterion_met(crossed(), **rule, final=False) == ("limit point", 2)
    plain = _Points([(1e-3, 100.0, 0.01, 0.02), (2e-3, 150.0, 0.02, -1e-3)])
    assert _criterion_met(plain(), **rule, final=False) == ("margin", 1)


def test_climb_starts_nearer_the_first_contact_when_its_first_rotation_has_no_fixed_point():
    """A first rotation with no fixed point is tried again with the step halved toward the first
    contact (a CSF-50-50's retreat cycled at 0.26 mrad and the path ended with no point, "no
    criterion": the verdict's ratcheting NOT CHECKED); the path then runs to the true limit point."""
    star = 8.0 ** (-1.0 / 8.0)
    path = climb(_Peak((0.03, 0.06)), 0.05, 0.05)
    assert path.points[0].phi_rad == pytest.approx(0.025)
    assert path.criterion == "limit point"
    assert path.torque_nm == pytest.approx(star * math.exp(-1.0 / 8.0) / 1e3, rel=1e-3)


def test_climb_with_no_equilibrium_beyond_a_rising_path_fails_loudly():
    """Where no fixed point exists beyond some rotation while T(φ) still rises (no limit point
    reached), the path must end as "end of path" — the verdict's NOT CHECKED — never as a limit
    point, and its torque is the last point's, below the model's true peak T*."""
    star = 8.0 ** (-1.0 / 8.0)
    stop = 0.7 * star  # T still rising there
    path = climb(_Peak((stop, math.inf)), 0.05, 0.05)
    assert path.criterion == "end of path"
    assert path.torque_nm < star * math.exp(-1.0 / 8.0) / 1e3
    assert all(p.phi_rad <= stop for p in path.points)
    assert "no equilibrium just beyond" in path.warnings[-1]


@pytest.mark.parametrize("sigma", [1.0, -1.0])
def test_climb_straight_flank_with_friction_reaches_the_depth_at_k_r_h_cot_alpha_less_rho(sigma):
    """Sliding out (σ = +1, the pull-out): friction holds the tooth in, T = k R h cot(α − ρ);
    sliding in (σ = −1, an entering tooth): T = k R h cot(α + ρ). μ = 0.1, α = 20°."""
    alpha, h, mu = math.radians(20), 0.3, 0.1
    rho = math.atan(mu)
    model = _OneTooth(straight=True, beta0=alpha, depth=h, n=5, mu=mu, sigma=sigma)  # parallel: degenerate, few
    path = climb(model, 1e-6, 2e-4)
    assert path.criterion == "margin"
    assert path.torque_nm == pytest.approx(model.k * model.r * h / math.tan(alpha - sigma * rho) / 1e3, rel=1e-6)
    for p in path.points:
        assert p.retreat_mm[0] == pytest.approx(p.torque_nm * 1e3 * math.tan(alpha - sigma * rho)
                                                / (model.k * model.r), rel=1e-6)


@pytest.mark.parametrize("sigma", [1.0, -1.0])
def test_climb_two_arcs_limit_point_with_friction(sigma):
    """The two arcs' limit point with the force tilted by ρ: max_s k R s cot(β(s) − σρ)."""
    rho, beta0, mu = 1.4, math.radians(15), 0.1
    model = _OneTooth(mu=mu, sigma=sigma)
    path = climb(model, 1e-6, 2e-4, refine=4)
    s = np.linspace(0.0, 1.0, 100001)
    sb = math.sin(beta0) + s / rho
    ok = sb < math.sin(math.radians(60))
    beta = np.arcsin(sb[ok])
    exact = np.max(model.k * model.r * s[ok] / np.tan(beta - sigma * math.atan(mu))) / 1e3
    assert path.criterion == "limit point"
    assert path.torque_nm == pytest.approx(exact, rel=1e-2)
    frictionless = np.max(model.k * model.r * s[ok] / np.tan(beta)) / 1e3
    assert (path.torque_nm - frictionless) * sigma > 0.05 * frictionless  # the shift is resolved, its sign right


def test_nonsymmetric_lcp_against_enumeration():
    """Lemke on S + (a nonsymmetric coupling) — a P-matrix — against the one complementary
    active set found by enumeration."""
    rng = np.random.default_rng(5)
    for _ in range(5):
        a = rng.normal(size=(6, 6))
        s = a @ a.T + 0.5 * np.eye(6) + 0.3 * rng.normal(size=(6, 6))
        assert np.linalg.eigvalsh(0.5 * (s + s.T)).min() > 0.0
        q = rng.normal(size=6)
        f = solve_p_matrix(s, q)
        found = []
        for mask in range(64):
            idx = [k for k in range(6) if mask >> k & 1]
            g = np.zeros(6)
            if idx:
                g[idx] = np.linalg.solve(s[np.ix_(idx, idx)], -q[idx])
            if np.all(g >= -1e-12) and np.all(s @ g + q >= -1e-12):
                found.append(g)
        assert len(found) == 1
        np.testing.assert_allclose(f, found[0], atol=1e-10)


def test_climb_starts_as_the_linear_contact(design):
    """At the first rotations the retreat is µm: the climb's torque must be the package's linear
    contact (Lemke on the same S, settled balls and springs) at the same rotation's torque."""
    from profilegen.contact.inputs import ContactInput
    from profilegen.contact.solvers import solve_lemke

    inputs = ContactInput.from_design(design)
    gs = inputs.gearset
    model = DesignClimb(inputs, side=1, stations=5, max_gap_mm=0.08, race_thickness_mm=None,
                        bearing=BallBearing.from_gearset(gs), ring_factory=None)
    theta, phi_rated = model.first_rotation(float(gs.torque.rated_nm))
    path = climb(model, theta + 0.25 * (phi_rated - theta), 0.25 * (phi_rated - theta), max_steps=2, refine=0)
    for p in path.points:
        gap, lever = model.geometry(np.zeros(model.teeth.size))
        s_mat = model.station_matrix(p.state)
        sol = solve_lemke(s_mat, np.maximum(gap, 0) / lever, lever, p.torque_nm / model.zones * 1e3)
        assert sol.phi_rad == pytest.approx(p.phi_rad, rel=2e-2)
        assert abs(p.mean_retreat_mm) < 0.005  # force-weighted: µm


@pytest.fixture(scope="module")
def corner_model(design):
    from profilegen.contact.inputs import ContactInput

    return DesignClimb(ContactInput.from_design(design), side=1, stations=5, max_gap_mm=0.08, race_thickness_mm=None,
                       bearing=None, ring_factory=None)


def test_stations_closer_than_the_mesh_resolves_are_thinned_not_a_failure(design, corner_model):
    """Thirteen stations a tooth on the default set (0.076 mm apart on the flank) make the contact's
    compliance singular (the FE mesh's elements hold more stations than nodes): the model keeps
    every second station of each tooth, counted from its tip, and says so — a CSF-32-50 with
    omega* = 0.6 (its engaged flank short against the mesh) had no ratcheting estimate at all."""
    from profilegen.contact.inputs import ContactInput

    dense = DesignClimb(ContactInput.from_design(design), side=1, stations=13, max_gap_mm=0.08,
                        race_thickness_mm=None, bearing=None, ring_factory=None)
    assert len(dense.notes) == 1 and "every second station" in dense.notes[0]
    assert corner_model.notes == []  # five stations: built as they are
    assert np.bincount(dense.slot).max() <= 7
    assert dense.corner.any()  # counted from the tip: the tip corners stay


def test_corner_normal_turns_with_the_cs_tip_round(corner_model):
    """The FS tip corners of the teeth leaving the engagement stand over the CS tip rounds
    (circles): the contact normal of a sharp corner facing a circle passes through the
    circle's centre, so wherever a corner's normal lies strictly between the flank's and the
    tip land's, its lever arm must be that of the unit vector from the corner to the round's
    centre, its radial part (sin α) above the flank's — checked over radial lifts of each
    tooth, with the rounds taken from the CS space's arcs."""
    from profilegen.geometry.contour import Arc

    model = corner_model
    rounds = [e for e in model._space.elements if isinstance(e, Arc) and abs(float(e.radius)) < 0.5
              and np.hypot(*np.asarray(e.centre)) > model._tip_r - 1.0]
    assert rounds, "the fitted CS space has tip rounds"
    corners = np.flatnonzero(model.corner)
    checked = 0
    for lift in np.linspace(-0.02, 0.05, 8):
        s = np.full(model.teeth.size, lift)
        gap, lever = model.geometry(s)
        for j, k in enumerate(corners):
            a, b = model._a[j], model._b[j]
            if not (gap[k] > 1e-4 and a > 1e-3 and b > 1e-3):
                continue
            p = model._p0[k] - lift * model._e0[model.slot[k]]
            c = min(rounds, key=lambda e: abs(np.hypot(*(p - np.asarray(e.centre))) - abs(float(e.radius))))
            if abs(np.hypot(*(p - np.asarray(c.centre))) - abs(float(c.radius)) - gap[k]) > 1e-9:
                continue  # its nearest CS point is not on a round
            u = (np.asarray(c.centre) - p) / np.linalg.norm(np.asarray(c.centre) - p)
            assert lever[k] == pytest.approx(model.rotation * (p[1] * u[0] - p[0] * u[1]), abs=1e-9)
            assert model.sin_alpha[k] > model._sa_flank[k]
            checked += 1
    assert checked >= 5


def test_corner_columns_reduce_to_the_flank_when_b_is_zero(corner_model):
    """With every corner's normal on its flank (a = 1, b = 0) the stations' S is the one built
    along the flank normals alone (the extra tip-land columns drop out of the congruence)."""
    model = corner_model
    model._a[:], model._b[:] = 1.0, 0.0
    full, probe, _ = model._matrices(model._combined.ball_active, None)
    s_mat = model._effective(full, probe)[0]
    np.testing.assert_array_equal(s_mat, full[:model.n, :model.n])
    model._b[:] = 0.5  # any b > 0 changes the corners' rows
    model._a[:] = 0.5
    assert not np.allclose(model._effective(full, probe)[0][model._ci], s_mat[model._ci])
    model.geometry(np.zeros(model.teeth.size))


def test_climb_gaps_are_periodic_in_the_cs_pitch(design, corner_model):
    """The CS is periodic in its pitch 2π/z2: the FS turned one CS pitch further stands in the
    next spaces exactly as before, so every station's signed gap, lever arm and contact normal
    (the corners' cone factors) must be the same. Measured against its own space alone (the
    climb before), a station that had moved into a neighbouring space took its distance to the
    wrong space."""
    model = corner_model
    pitch = 2.0 * math.pi / design.gearset.gear.circular_spline_teeth
    s = np.full(model.teeth.size, 0.01)
    for phi in (0.0, 0.3 * pitch):
        g0, l0 = model.geometry(s, phi)
        a0, b0 = model._a.copy(), model._b.copy()
        for k in (1, -1):
            g1, l1 = model.geometry(s, phi + k * pitch)
            np.testing.assert_allclose(g1, g0, rtol=0, atol=1e-9)
            np.testing.assert_allclose(l1, l0, rtol=0, atol=1e-9)
            np.testing.assert_allclose(model._a, a0, atol=1e-9)
            np.testing.assert_allclose(model._b, b0, atol=1e-9)
    model.geometry(np.zeros(model.teeth.size))


def test_climb_gap_over_the_cs_tip_land_is_the_distance_to_the_tip_circle(design, corner_model):
    """Between two spaces the CS surface is its tip land, the tip circle: a point over it at
    radius r has the signed gap r_tip − r (in the CS material beyond it), continuous through the
    tip circle. The climb before took the distance to the space's end with the sign of
    r ≷ r_tip there — a jump of twice that (0.39 mm on the verify scene of csf14_100) where an
    FS tip corner crossed the tip circle, and its path ended (no fixed point)."""
    model = corner_model
    pitch = 2.0 * math.pi / design.gearset.gear.circular_spline_teeth
    end = float(model._rim_theta[-1])  # the space's outline ends on the tip circle here
    assert float(model._rim_r[-1]) == pytest.approx(model._tip_r, abs=1e-9)
    tip = model._tip_r
    for theta in (0.5 * (end + 0.5 * pitch), pitch - 0.5 * (end + 0.5 * pitch)):  # over the land, both sides
        room = tip * (0.5 * pitch - end) / 4.0  # well within the land: the space's outline farther
        delta = np.array([-1.0, -0.1, -1e-4, 1e-4, 0.1, 1.0]) * room
        r = tip + delta
        p = np.column_stack([r * math.sin(theta), r * math.cos(theta)])
        gap = model.signed_gap(p)[0]
        np.testing.assert_allclose(gap, -delta, rtol=0, atol=1e-12)
    # within the space's mouth nothing changes: the distance to the space's outline
    theta = np.linspace(-0.9, 0.9, 7) * end
    r = np.full(theta.size, tip + 0.05)
    p = np.column_stack([r * np.sin(theta), r * np.cos(theta)])
    dist, _ = model._space.nearest(p)
    np.testing.assert_allclose(np.abs(model.signed_gap(p)[0]), dist, rtol=0, atol=1e-12)


def _respond(model, s, phi):
    """One response of a climb model at retreat ``s`` and rotation ``phi`` from its initial
    state: (station forces, the retreat they cause)."""
    gap, _ = model.geometry(s, phi)
    state = model.initial_state()
    q = gap - model.sin_alpha * s[model.slot]
    f, state, p_fs, p_cs = model.respond(q, state)
    return f, p_fs @ f + model.retreat_offset(state) + p_cs @ f


def test_identical_slices_are_the_one_section_climb(design, corner_model):
    """N identical axial slices, each a DesignClimb of the same section with a 1/N share of the
    face (every compliance ×N), sharing φ: each carries 1/N of the one-section forces and
    the teeth retreat alike — the sliced climb reduces to the 2D one (face_load's limit)."""
    from profilegen.contact.climb import SlicedClimb
    from profilegen.contact.inputs import ContactInput

    half = DesignClimb(ContactInput.from_design(design), side=1, stations=5, max_gap_mm=0.08, race_thickness_mm=None,
                       bearing=None, ring_factory=None, width_fraction=0.5)
    sliced = SlicedClimb([half, half])
    theta, phi = corner_model.first_rotation(265.0)
    s = np.full(corner_model.teeth.size, 2e-3)
    f1, r1 = _respond(corner_model, s, phi)
    f2, r2 = _respond(sliced, np.r_[s, s], phi)
    assert f1.max() > 1.0
    np.testing.assert_allclose(f2, 0.5 * np.r_[f1, f1], rtol=1e-6, atol=1e-9 * f1.max())
    np.testing.assert_allclose(r2, np.r_[r1, r1], rtol=1e-6, atol=1e-12)
    # the face held straight: every tooth retreats by the mean of its slices' — the same here
    f3, r3 = _respond(SlicedClimb([half, half], coupled=True), np.r_[s, s], phi)
    np.testing.assert_allclose(f3, f2, rtol=1e-12, atol=1e-12 * f1.max())
    np.testing.assert_allclose(r3, r2, rtol=1e-9, atol=1e-12)


def test_every_ball_one_sided_with_far_balls_is_the_window(design, corner_model):
    """ball_supports='all' puts every ball of the zone in as a one-sided support at its no-load
    gap; with the balls outside the wrap moved 1 mm away (never reached) the response is the
    window model's, and with their own gaps (some close under load) the rim is held more."""
    from profilegen.contact.inputs import ContactInput

    every = DesignClimb(ContactInput.from_design(design), side=1, stations=5, max_gap_mm=0.08,
                        race_thickness_mm=None, bearing=None, ring_factory=None, ball_supports="all")
    assert every._g0.size > corner_model._g0.size and np.all(every._g0 >= 0.0)
    theta, phi = corner_model.first_rotation(2 * 265.0)
    s = np.zeros(corner_model.teeth.size)
    f_win, r_win = _respond(corner_model, s, phi)
    g0 = every._g0.copy()
    every._g0 = np.where(g0 > 0.0, g0 + 1.0, 0.0)
    f_far, r_far = _respond(every, s, phi)
    np.testing.assert_allclose(f_far, f_win, rtol=1e-6, atol=1e-9 * f_win.max())
    np.testing.assert_allclose(r_far, r_win, rtol=1e-6, atol=1e-12)
    every._g0 = g0
    f_all, _ = _respond(every, s, phi)
    assert every.zones * f_all @ every.geometry(s, phi)[1] > every.zones * f_win @ corner_model.geometry(s, phi)[1]


class _Shifted(DesignClimb):
    """The CS flank moved by ``delta_mm`` along its normal (every gap grows by it)."""

    delta_mm = 0.0

    def geometry(self, s, phi: float = 0.0):
        gap, lever = super().geometry(s, phi)
        return gap + self.delta_mm, lever


def test_climb_estimate_is_continuous_in_a_nanometre_of_the_flank(design):
    """A nanometre of the CS flank (and the 1 % shift of the step grid such a change makes
    through the first rotation) must move the ratcheting estimate by far less than 1 %: the
    path resolves the peak of T(φ) (steps capped in retreat) and passes a band where the
    fixed point cycles. Before (engineer P3b), on this design the estimate went 4304 → 4365
    N·m (+1.4 %) with the step ×1.01, and to 1979 N·m with ×1.02 (a spurious end of path)."""
    from profilegen.contact.inputs import ContactInput
    from threadpoolctl import threadpool_limits

    from profilegen.contact.ratchet import _cs_ring_section

    inputs = ContactInput.from_design(design)
    gs = inputs.gearset
    r_mean, thick, width, _ = _cs_ring_section(gs, inputs)

    def ring(phis):
        return cs_ring_radial_compliance(np.concatenate([phis, phis + math.pi]), phis, mean_radius_mm=r_mean,
                                         thickness_mm=thick, width_mm=width,
                                         youngs_modulus_mpa=float(gs.material.youngs_modulus_mpa))

    model = _Shifted(inputs, side=1, stations=5, max_gap_mm=0.08, race_thickness_mm=None,
                     bearing=BallBearing.from_gearset(gs), ring_factory=ring, ball_supports="all")
    theta, phi_rated = model.first_rotation(float(gs.torque.rated_nm))
    step = 0.5 * (phi_rated - theta)
    with threadpool_limits(limits=1, user_api="blas"):  # as ratcheting_torque runs it
        base = climb(model, theta + step, step)
        model.delta_mm = 1e-6
        moved = climb(model, theta + 1.01 * step, 1.01 * step)
    assert base.criterion in ("limit point", "end of path") and base.torque_nm > 2.0 * gs.torque.rated_nm
    assert moved.torque_nm == pytest.approx(base.torque_nm, rel=0.01)


# --------------------------------------------------------------------------- friction on the design


@pytest.fixture(scope="module")
def running(design):
    from profilegen.contact.inputs import ContactInput

    return DesignClimb(ContactInput.from_design(design), side=1, stations=5, max_gap_mm=0.08, race_thickness_mm=None,
                       bearing=None, ring_factory=None, friction_coefficient=0.1, friction_sliding="forward-elastic")


def test_friction_zero_is_the_frictionless_climb(design, corner_model):
    """μ = 0 through the friction path (the nonsymmetric solve, the forces spread over the
    built and probe columns) follows the frictionless climb's path."""
    from profilegen.contact.inputs import ContactInput

    zero = DesignClimb(ContactInput.from_design(design), side=1, stations=5, max_gap_mm=0.08, race_thickness_mm=None,
                       bearing=None, ring_factory=None, friction_sliding="static")
    corner_model.geometry(np.zeros(corner_model.teeth.size))  # its corners as built (another test moves them)
    theta, phi = corner_model.first_rotation(265.0)
    assert zero.first_rotation(265.0) == (theta, phi)
    step = 0.5 * (phi - theta)
    a = climb(corner_model, theta + step, step, max_steps=4, refine=0)
    b = climb(zero, theta + step, step, max_steps=4, refine=0)
    assert len(a.points) == len(b.points) == 4
    for p, q in zip(a.points, b.points):
        assert q.torque_nm == pytest.approx(p.torque_nm, rel=1e-9)
        np.testing.assert_allclose(q.retreat_mm, p.retreat_mm, rtol=0, atol=1e-12)


def test_running_forward_the_wave_generator_pushes_the_loaded_teeth_in(running):
    """The gear driven forward takes its power in through the wave generator: the loaded teeth
    move radially out, into their CS spaces, against the radial parts of their forces
    (Σ F sin α v_r > 0, the input power), and the FS turns the way the CS's forces push it
    (the load brakes it). So most of the load slides into the spaces (σ = −1: a tooth just
    past the major axis leaves), and friction tilts those forces toward the radial."""
    m = running
    theta, phi = m.first_rotation(265.0)
    f, _ = _respond(m, np.zeros(m.teeth.size), phi)  # no retreat: the kinematic sense
    on = f > 1e-6 * f.max()
    assert on.sum() >= 5
    e_r = m._e0[m.slot]
    v = m.sliding_velocity
    v_r = np.einsum("ij,ij->i", v, e_r)
    assert f @ (m.sin_alpha * v_r) > 0.0
    assert f[v_r > 0.0].sum() > 0.8 * f.sum()
    # the FS turns (package angle sense: a turn dα moves p by dα (p_y, −p_x)) with the moment
    # of the CS's forces on it, −rotation Σ F lever (the forces on the FS are −F n)
    p = m._p0
    omega = np.einsum("ij,ij->i", v, np.column_stack([p[:, 1], -p[:, 0]])) / np.einsum("ij,ij->i", p, p)
    assert np.sign(f @ omega) == -m.rotation
    into = m._sigma < 0.0
    clear = on & (np.abs(v_r) > 0.02)  # moving radially: the sense along the flank is the radial one
    assert f[into].sum() > 0.8 * f.sum() and np.all(np.sign(v_r[clear]) == -np.sign(m._sigma[clear]))
    # so the radial part of the force on the CS grows with μ on them (sin α + μ cos α), falls on the others
    assert np.all(m._rad[on & into] > m.sin_alpha[on & into]) and np.all(m._rad[on & ~into] < m.sin_alpha[on & ~into])


def test_running_sense_follows_the_retreat_along_the_zone(running, design):
    """"-elastic": the retreat s(φ) is stationary in the wave generator's frame, so a tooth
    running through the zone moves by −ds/dφ e_r besides its kinematic motion. A retreat that
    grows twice as fast as the tooth's kinematic radial place r(φ) (its tip-land centre, from
    the kinematics here) reverses every tooth's radial motion: the stations that slide mostly
    radially change sense; a uniform retreat changes none."""
    from profilegen.contact.inputs import ContactInput

    m = running
    inputs = ContactInput.from_design(design)
    tip = np.array([0.0, float(inputs.tooth.tip_point[1])])
    r = np.hypot(*inputs.motion.pose(m.phis).to_cs(np.broadcast_to(tip, (m.phis.size, 2)).copy()).T)
    m.geometry(np.zeros(m.teeth.size))
    kinematic = m._sigma.copy()
    m.geometry(np.full(m.teeth.size, 0.05))
    np.testing.assert_array_equal(m._sigma, kinematic)
    m.geometry(2.0 * (r - r.max()))
    # the stations whose sliding along the flank is mostly their radial motion's
    e_r = m._e0[m.slot]
    t = m._js[:, None] * np.column_stack([-m._n0[:, 1], m._n0[:, 0]])
    v_r = np.einsum("ij,ij->i", m.sliding_velocity, e_r) * np.einsum("ij,ij->i", e_r, t)
    radial = (np.abs(v_r) > 3.0 * np.abs(m.sliding_speed - v_r)) & (np.abs(v_r) > 0.05)
    radial[np.isin(m.slot, [0, m.teeth.size - 1])] = False  # ds/dφ one-sided at the ends
    assert radial.sum() > 20
    np.testing.assert_array_equal(np.sign(m._sigma[radial]), -np.sign(kinematic[radial]))
    m.geometry(np.zeros(m.teeth.size))


def test_the_climbs_polar_outline_fills_long_straight_steps():
    """The climb tells a station's overlap from the CS space's outline in polar form, and refuses
    an outline whose radius jumps (not single-valued). A contour's sample gives a line as its two
    ends, so a large module's flank line (0.73 mm at size 58, ratio 50) read as a 0.73 mm jump and
    the ratcheting estimate failed there. The outline is filled to 5 µm steps: every original
    point kept, the new ones on the segments, no step longer than 5 µm."""
    from profilegen.contact.climb import _dense

    r = 75.0
    pts = np.array([[-1.2604, 74.7774], [-1.1301, 75.5048], [-0.6096, 76.5095]])  # a line, then a chord
    out = _dense(pts, 5e-3)
    steps = np.hypot(*np.diff(out, axis=0).T)
    assert steps.max() <= 5e-3 * (1 + 1e-12) and steps.min() > 0.0
    assert all(np.min(np.hypot(*(out - p).T)) == 0.0 for p in pts)  # the ends are kept exactly
    # every new point lies on its segment: zero cross product with the segment's direction
    for a, b in zip(pts[:-1], pts[1:]):
        on = out[(out[:, 1] >= min(a[1], b[1])) & (out[:, 1] <= max(a[1], b[1]))]
        d = b - a
        assert np.max(np.abs((on[:, 0] - a[0]) * d[1] - (on[:, 1] - a[1]) * d[0])) < 1e-12
    radius = np.hypot(*out.T)
    assert np.max(np.abs(np.diff(radius))) <= 5e-3 and radius.min() < r < radius.max()


def test_a_limit_point_lies_between_its_bracket_and_the_path_top_plus_the_bracket_spread():
    """Whatever the path's spacing (abscissae ulps apart included) and its noise, the limit point
    the climb reports is at least the largest of the bracket's three torques (a parabola's peak
    inside the bracket is above its points; else the path's largest) and at most the path's
    largest plus the bracket's spread: never a torque the path did not come near (3.4e10 N·m was
    reported between points of ~2440 N·m)."""
    from types import SimpleNamespace

    from profilegen.contact.climb import _limit_point

    rng = np.random.default_rng(7)
    for _ in range(2000):
        n = int(rng.integers(3, 12))
        steps = rng.choice([1e-3, 1e-6, 1e-12, 0.0], size=n, p=[0.7, 0.1, 0.1, 0.1]) * rng.uniform(0.5, 2.0, n)
        phi = np.cumsum(steps) + 1e-3
        phi = np.array([p + k * math.ulp(p) for k, p in enumerate(phi)])  # strictly increasing, some by ulps
        torque = 2440.0 - 1e7 * (phi - phi[n // 2]) ** 2 + rng.normal(0.0, 0.05, n)
        pts = [SimpleNamespace(phi_rad=float(p), torque_nm=float(t)) for p, t in zip(phi, torque)]
        k = n - 1
        got = _limit_point(pts, k, False, []).torque_nm
        bracket = torque[max(k - 2, 0):k + 1]
        assert got >= bracket.max() - 1e-9
        assert got <= torque[:k + 1].max() + (bracket.max() - bracket.min()) + 1e-9


def test_the_peak_of_three_points_is_the_parabola_vertex_however_close_the_points():
    """The limit point's refinement takes the vertex of the parabola through the bracket's three
    points: exact for a parabola, also on a bracket of nanoradians (where fitting the raw
    monomials is ill-conditioned), and None for a minimum or a vertex outside the bracket."""
    import warnings

    from profilegen.contact.climb import _parabola_peak

    def t(phi):
        return 4200.0 - 3.0e9 * (phi - 2.1e-3) ** 2  # N·m, a peak at 2.1 mrad

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for x in ((2.0e-3, 2.05e-3, 2.2e-3), (2.1e-3 - 1e-9, 2.1e-3 + 2e-10, 2.1e-3 + 1.5e-9)):
            xv, yv = _parabola_peak(x, [t(v) for v in x])
            assert xv == pytest.approx(2.1e-3, rel=1e-9, abs=1e-15) and yv == pytest.approx(4200.0, rel=1e-12)
    assert _parabola_peak((0.0, 1.0, 2.0), (1.0, 0.0, 1.0)) is None  # a minimum
    assert _parabola_peak((0.0, 1.0, 2.0), (0.0, 1.0, 1.9)) is None  # the vertex beyond the bracket
    # two abscissae ulps apart with torques 0.02 N·m apart (a climb's refinement): a curvature of
    # ~1e20 and a "peak" of 3.4e10 N·m between points of ~2440 N·m — not pinned by its points
    x1 = 0.008104410
    assert _parabola_peak((0.00808935, x1, x1 + 4 * math.ulp(x1)), (2439.30, 2442.45, 2442.43)) is None
    # a vertex within the three points' spread above the largest is kept (an uneven bracket)
    xv, yv = _parabola_peak((2.0e-3, 2.09e-3, 2.3e-3), [t(v) for v in (2.0e-3, 2.09e-3, 2.3e-3)])
    assert xv == pytest.approx(2.1e-3, rel=1e-9) and yv == pytest.approx(4200.0, rel=1e-12)
