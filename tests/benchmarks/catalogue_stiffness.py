"""Secant stiffness of the whole gear against the catalogue (issue 16 must-show, item 2 and item 7).

    python tests/benchmarks/catalogue_stiffness.py [profiles/seed000_csf40.toml profiles/csf32_100.toml]

For each gear set (design scene, no contact or stress in the design run): the catalogue row of
its size and ratio (profilegen.contact.catalogue: for ratio 100 the ratio ≥ 80 row, Harmonic
Drive AG CHA engineering data table 50.4 — the component set's values), the torsional curve of the compliance
chain (profilegen.contact.chain.torsional_curve) on the catalogue's T1/T2 → K1, K2 and the
secants at T1, T2 against the row's; then what each candidate for the missing compliance
would add, at T1 and T2, on the mesh with rigid balls settled at that torque (the Hertz ball
springs' share is the chain's and is kept as it is):

* coning across the face (research/face_load.py, the 3D cup's sections, 8 slices, the
  2D tooth uncorrected along the face): the change of the mesh rotation at T1 and T2 — one
  flank (the opposite flank's preload left out; its "K1" is then not a catalogue K1) and both
  flanks (every ball a Hertz spring at its 500 N secant; the change of the elastic rotation
  from each variant's own zero-torque position);
* the CS ring's ovalisation (tests/oracles/cs_ring.py, a free ring, the face width wide, to the
  CS's estimated outer radius from its root circle — the section that bends — or, the upper
  bound, from the contact model's sector edge 1.1 r2): S + S_ring re-solved;
* a cup wall thinner than the rim (ESTIMATE: 0.6 δ; the chain takes the wall as thick as the rim):
  the wall's tube compliance × (1/0.6 − 1) over its length below the tooth ring;
* the inner ring pressed on the cam (order of magnitude: a ring of the outer race's thickness
  compressed under one ball's load over (race thickness × bearing width)).

K1 = T1/(φ(T1) − θ0), K2 = (T2 − T1)/(φ(T2) − φ(T1)) on each variant's rotation (θ0 the 2D
first contact; with coning some slices are preloaded at no torque, so its K1 is not a
catalogue K1 — the chord K2 is the comparable number). CPU times.
"""

from __future__ import annotations

import math
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

import profilegen as pg  # noqa: E402
from profilegen.contact.analysis import solve_contact  # noqa: E402
from profilegen.contact.catalogue import catalogue_row  # noqa: E402
from profilegen.contact.chain import compliance_chain, torsional_curve  # noqa: E402
from tests.oracles.cs_ring import CSRing, cs_ring_compliance  # noqa: E402
from research.face_load import (  # noqa: E402
    cup_sections, gap_shift_mm, slice_positions, solve_face, solve_two_flanks, two_flank_sides)
from profilegen.contact.inputs import ContactInput  # noqa: E402
from profilegen.contact.solvers import solve_lemke  # noqa: E402
from profilegen.rim.cup.contact import press_cup  # noqa: E402

resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
SIZES = {"seed000_csf40": 40, "csf32_100": 32}
WALL_FRACTION = 0.6


def ks(t1, t2, phi1, phi2, theta0):
    return t1 / (phi1 - theta0), (t2 - t1) / (phi2 - phi1)


def run(path: Path) -> list:
    gs = pg.load_gearset(path)
    size = SIZES.get(gs.name, 40)
    row = catalogue_row(size, int(round(gs.ratio)))
    t1, t2 = row["T1_nm"], row["T2_nm"]
    print(f"\n=== {gs.name}: size {size}, ratio {gs.ratio:g}; catalogue {row['source']}: T1 {t1:g}, K1 "
          f"{row['K1_nm_per_rad']:.3g}, T2 {t2:g}, K2 {row['K2_nm_per_rad']:.3g} N·m/rad" + (f"\n    NOTE: {row['note']}" if row['note'] else ""))
    t0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    inp = ContactInput.from_design(design)
    print(f"design {time.process_time() - t0:.1f} s CPU")
    chain = compliance_chain(gs)
    torques = [-t2, -t1, t1, t2, float(gs.torque.rated_nm)]
    t0 = time.process_time()
    import inspect

    # the candidates below are solved on the window mesh (solve_contact settles the window's balls): keep the
    # chain's window even where torsional_curve offers every ball one-sided (tests/benchmarks/missing_compliance.py)
    window = {"ball_supports": "window"} if "ball_supports" in inspect.signature(torsional_curve).parameters else {}
    curve = torsional_curve(design, torques, chain=chain, catalogue=row, **window)
    print(f"torsional curve {time.process_time() - t0:.1f} s CPU; series parts (N·m/rad): "
          + ", ".join(f"{p.name} {p.stiffness_nm_per_rad:.3g}" for p in chain.parts))
    k = curve.k_nm_per_rad["total"]["positive"]
    km = curve.k_nm_per_rad["mesh"]["positive"]
    kb = curve.k_nm_per_rad["mesh_balls"]["positive"]
    print(f"chain: K1 {k['K1']:.4g} (mesh {km['K1']:.4g}, +balls {kb['K1']:.4g}), K2 {k['K2']:.4g} (mesh "
          f"{km['K2']:.4g}, +balls {kb['K2']:.4g}); secant T1 {k['secant_T1']:.4g}, T2 {k['secant_T2']:.4g}; "
          f"negative side K1 {curve.k_nm_per_rad['total']['negative']['K1']:.4g} K2 "
          f"{curve.k_nm_per_rad['total']['negative']['K2']:.4g}")
    theta0 = curve.first_contact_rad["positive"]
    order = np.argsort(curve.torque_nm)
    tq, rot = curve.torque_nm[order], curve.rotation_rad[order]
    phi_total = {t: float(rot[np.flatnonzero(tq == t)[0]]) for t in (t1, t2)}

    pts, comp = curve.sides[1]
    with threadpool_limits(limits=1, user_api="blas"):
        res = solve_contact(inp, [t1, t2], points=pts, compliance=comp)
        mats = {t: comp.with_balls(c.ball_active).matrix_mm_per_n for t, c in zip((t1, t2), res.cases)}
        base = {t: float(c.rotation_rad) for t, c in zip((t1, t2), res.cases)}
        extra = {}
        # coning
        t0 = time.process_time()
        cup = press_cup(gs)
        b, z0 = float(gs.cup.face_width_mm), float(gs.cup.length_mm)
        z = slice_positions(b, 8, z0)
        secs = cup_sections(cup, np.r_[z0, z])
        shifts = np.array([gap_shift_mm(pts, inp.motion, s, secs[0]) for s in secs[1:]])
        face = {t: solve_face(pts, mats[t], shifts, t, face_width_mm=b, z_mm=z) for t in (t1, t2)}
        extra["coning, one flank"] = {t: face[t].rotation_rad - base[t] for t in (t1, t2)}
        print(f"coning: gap shifts {shifts.min() * 1e3:+.1f} … {shifts.max() * 1e3:+.1f} µm; peak line load at T2 "
              f"{face[t2].peak_line_load_n_per_mm:.1f} vs even {face[t2].uniform_peak_line_load_n_per_mm:.1f} N/mm "
              f"(one flank); {time.process_time() - t0:.1f} s CPU")
        # both flanks, every ball a Hertz spring at its 500 N secant: the elastic rotation with coning minus without
        t0 = time.process_time()
        pos, neg, both = two_flank_sides(inp)
        cone = np.array([np.r_[gap_shift_mm(pos, inp.motion, sec, secs[0]), gap_shift_mm(neg, inp.motion, sec, secs[0])]
                         for sec in secs[1:]])
        matrix = both.with_balls(np.ones_like(both.ball_active),
                                 ball_compliance_mm_per_n=float(chain.bearing.secant_compliance_mm_per_n(500.0))
                                 ).matrix_mm_per_n
        gap2, lev2 = np.r_[pos.gap_mm, neg.gap_mm], np.r_[pos.lever_mm, neg.lever_mm]
        sense = np.r_[np.ones(pos.count), -np.ones(neg.count)]

        def elastic(shifts):
            phi = {t: solve_two_flanks(gap2, lev2, sense, matrix, shifts, t, zones=pos.zones).rotation_rad
                   for t in (1e-6, t1, t2)}
            return {t: phi[t] - phi[1e-6] for t in (t1, t2)}

        with_cone, without = elastic(cone), elastic(np.zeros_like(cone))
        extra["coning, both flanks"] = {t: with_cone[t] - without[t] for t in (t1, t2)}
        print(f"coning, both flanks (every ball a Hertz spring at 500 N): elastic rotation at T1 {with_cone[t1] * 1e6:.2f}"
              f" vs {without[t1] * 1e6:.2f} µrad without, at T2 {with_cone[t2] * 1e6:.2f} vs {without[t2] * 1e6:.2f}; "
              f"{time.process_time() - t0:.1f} s CPU")
        # CS ring
        for inner, label in (("root", "CS ring (free, root→outer)"), ("sector", "CS ring (free, 1.1r2→outer)")):
            ring = CSRing.from_gearset(gs, inner=inner)
            s_ring = cs_ring_compliance(ring, pts.cs_point_mm, pts.normal, zones=pts.zones)
            ring_phi = {t: float(solve_lemke(mats[t] + s_ring, pts.theta_rad, pts.lever_mm,
                                             t / pts.zones * 1e3).phi_rad) for t in (t1, t2)}
            extra[label] = {t: ring_phi[t] - base[t] for t in (t1, t2)}
            print(f"{label}: r {ring.inner_radius_mm:.2f} … {ring.outer_radius_mm:.2f} mm, width {ring.width_mm:g} "
                  f"mm, I {ring.second_moment_mm4:.4g} mm⁴; estimates: {'; '.join(ring.estimates)}")
    # thinner wall
    wall = chain.part("cup_wall")
    p = wall.parameters
    c_wall = wall.compliance_rad_per_nm * p["wall_length_mm"] / p["effective_length_mm"] * (1.0 / WALL_FRACTION - 1.0)
    extra[f"cup wall {WALL_FRACTION:g}·δ (ESTIMATE)"] = {t: t * c_wall for t in (t1, t2)}
    # inner ring on the cam (order of magnitude, not added to 'all')
    bearing = chain.bearing
    q = 500.0
    from profilegen.contact.compliance import default_race_thickness_mm

    t_race = default_race_thickness_mm(gs.gear)
    squeeze = q * t_race / (gs.material.youngs_modulus_mpa * t_race * b)
    print(f"inner ring on the cam at one ball (Q = {q:g} N): ~{squeeze * 1e3:.3f} µm against the balls' Hertz "
          f"{bearing.approach_mm(q) * 1e3:.2f} µm — {squeeze / float(bearing.approach_mm(q)):.1%} of the ball term, "
          "left out")

    rows = [("chain, window balls + Hertz + series", phi_total[t1], phi_total[t2])]
    for name, d in extra.items():
        rows.append((f"+ {name}", phi_total[t1] + d[t1], phi_total[t2] + d[t2]))
    def plus(*names):
        return (phi_total[t1] + sum(extra[n][t1] for n in names), phi_total[t2] + sum(extra[n][t2] for n in names))

    names = list(extra)
    _, coning, ring_root, ring_sector, thin = names
    rows.append(("+ ring (root) + wall", *plus(ring_root, thin)))
    rows.append(("+ ring (root) + wall + coning (2 flanks)", *plus(ring_root, thin, coning)))
    rows.append(("+ ring (sector) + wall", *plus(ring_sector, thin)))
    c1, c2 = row["K1_nm_per_rad"], row["K2_nm_per_rad"]
    print(f"\n{'variant':42s} {'K1':>10s} {'/cat':>6s} {'K2':>10s} {'/cat':>6s} {'T1/φ1':>10s} {'T2/φ2':>10s}"
          f"   (catalogue K1 {c1:.3g}, K2 {c2:.3g}, secant at T2 {t2 / (t1 / c1 + (t2 - t1) / c2):.3g})")
    out = []
    for name, p1, p2 in rows:
        k1, k2 = ks(t1, t2, p1, p2, theta0)
        print(f"{name:42s} {k1:10.4g} {k1 / c1:6.2f} {k2:10.4g} {k2 / c2:6.2f} {t1 / (p1 - theta0):10.4g} "
              f"{t2 / (p2 - theta0):10.4g}")
        out.append((gs.name, name, k1, k2))
    for name, d in extra.items():
        print(f"  {name}: adds {d[t1] / t1:.3g} rad/N·m at T1, {(d[t2] - d[t1]) / (t2 - t1):.3g} rad/N·m between T1 and T2")
    return out


if __name__ == "__main__":
    paths = [Path(a) for a in sys.argv[1:]] or [ROOT / "profiles" / "seed000_csf40.toml",
                                                 ROOT / "profiles" / "csf32_100.toml"]
    for p in paths:
        run(p)
