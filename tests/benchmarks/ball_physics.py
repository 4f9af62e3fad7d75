"""Physics check of the wave-generator balls as supports (issue 16, the ball window).

    python tests/benchmarks/ball_physics.py [profiles/x.toml ...]

Is "every ball a one-sided support at its no-load gap" what a flexible bearing does? In the
bearing the inner race sits on the cam (both taken rigid), each ball floats between the races
and the outer race is pressed into the FS bore (the race is meshed under the bore, sliding).
A ball outside the rim's no-load contact angle is loose by the space between the races minus
its diameter, which is the bore's distance to the wave generator's contour (cam + inner race
+ D + outer race): ``no_load_ball_gap_mm``. Under load the ball takes force once the race
moves in by more than that gap, and never pulls. This prints, per set (design scene):

* the zone's balls, the window (the rim's no-load contact angle) and each ball's no-load gap;
* the window model at the rated torque: how far the bore moves into each ball it leaves out
  (a physical model cannot put the race through a ball: a displacement below −gap is a
  penetration);
* the race's own bending: the rotation at the rated torque with every ball a one-sided
  support, the default race (meshed, sliding on the bore) against no race (balls on the bore)
  and a bonded race — the race's ring stiffness is in the model when these differ;
* the Hertz approach of the most loaded ball, for scale against the gaps.
"""

from __future__ import annotations

import math
import resource
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

import profilegen as pg  # noqa: E402
from profilegen.contact import ContactInput, contact_points  # noqa: E402
from profilegen.contact.chain import BallBearing  # noqa: E402
from profilegen.contact.compliance import ContactCompliance  # noqa: E402
from profilegen.contact.solvers import solve_lemke  # noqa: E402

SETS = [Path(pg.default_gearset_path()), ROOT / "profiles" / "seed000_csf40.toml"]
ARCSEC = 180.0 * 3600.0 / math.pi


def run(path: Path) -> None:
    gs = pg.load_gearset(path)
    design = pg.design(gs, scene="design", contact=False, stress=False)
    inputs = ContactInput.from_design(design)
    wrap = inputs.rim_contact_angle_rad
    rated = float(gs.torque.rated_nm)
    with threadpool_limits(limits=1, user_api="blas"):
        pts = contact_points(inputs)
        tz = rated / pts.zones * 1e3

        def build(**kw):
            return ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                           wrap_half_angle_rad=wrap, ball_supports="all", **kw)

        every = build()
        ang = np.degrees(every.ball_angle_rad)
        inside = np.abs(every.ball_angle_rad) <= wrap + 1e-12
        print(f"\n=== {gs.name}: window (rim no-load contact angle) {math.degrees(wrap):.2f}°, rated {rated:g} N·m, "
              f"race {every.mesh['fs'].get('race_thickness_mm')} mm {every.mesh['fs'].get('race_interface')}, "
              f"{every.mesh['fs'].get('race_layers')} layers")
        print("ball (°)          " + " ".join(f"{a:7.1f}" for a in ang))
        print("in window         " + " ".join(f"{'yes' if i else 'no':>7}" for i in inside))
        print("no-load gap (µm)  " + " ".join(f"{g * 1e3:7.3f}" for g in every.ball_gap_mm))
        # the window model (the default build): balls outside it are no supports at all
        window = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                         wrap_half_angle_rad=wrap)

        def forces(matrix):
            return solve_lemke(matrix, pts.theta_rad, pts.lever_mm, tz).force_n

        settled = window.settle_balls(forces(window.matrix_mm_per_n), solve=forces)
        sol_w = solve_lemke(settled.matrix_mm_per_n, pts.theta_rad, pts.lever_mm, tz)
        react = np.zeros(every.ball_angle_rad.size)
        react[np.searchsorted(every.ball_angle_rad, settled.ball_angle_rad - 1e-12)] = \
            settled.ball_reactions(sol_w.force_n)
        # outward displacement of the race's inner surface at every ball of the zone
        moved = (every._flex_cb.T @ sol_w.force_n + every._flex_bb @ react) / every.face_width_mm
        print("window, rated: race displacement at the ball (µm; < −gap = through the ball)")
        print("                  " + " ".join(f"{m * 1e3:7.2f}" for m in moved))
        through = ~inside & (moved < -every.ball_gap_mm)
        print(f"  balls the race passes through: {', '.join(f'{a:.1f}°' for a in ang[through]) or 'none'}; "
              f"rotation {sol_w.phi_rad * ARCSEC:.2f}″")
        # every ball one-sided: the race's own bending
        for label, kw in (("race 2.5 % d sliding (default)", {}), ("no race (balls on the bore)",
                                                                   {"race_thickness_mm": 0.0}),
                          ("race bonded to the bore", {"race_interface": "bonded"})):
            comp = every if not kw else build(**kw)
            sol, reaction, after = comp.solve_unilateral(pts.theta_rad, pts.lever_mm, tz)
            print(f"  all balls one-sided, {label:32s}: rotation {sol.phi_rad * ARCSEC:7.2f}″, balls loaded "
                  f"{int(np.count_nonzero(reaction))}/{reaction.size}, R max {reaction.max():6.0f} N, "
                  f"min gap after load {after.min() * 1e3:.2e} µm")
        bearing = BallBearing.from_gearset(gs)
        sol, reaction, after = every.solve_unilateral(pts.theta_rad, pts.lever_mm, tz)
        print(f"  Hertz approach at the largest ball load {reaction.max():.0f} N: "
              f"{float(bearing.approach_mm(reaction.max())) * 1e3:.1f} µm (c_H {bearing.hertz_coefficient():.3g})")


def main() -> None:
    for p in (sys.argv[1:] or SETS):
        run(Path(p))


if __name__ == "__main__":
    main()
