"""The rim numbers quoted in README and closing notes that no other script prints.

    python tests/benchmarks/rim_checks.py

* FEM → exact inextensible ring with partial wrap (tests/oracles/ring_on_cam.py) as δ/r_m → 0 (the case of
  tests/validation/test_rim_oracle.py), and the default set against its oracle;
* the default set: bore and neutral-line ω(0) against w0, linear vs nonlinear, the pitch
  circle's υ, the design tier's Fourier fit;
* seed 004's printed sine-series coefficients at φ = 0 and near 45°.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.rim import RingParameters, solve_rim, solve_ring  # noqa: E402
from tests.oracles.ring_on_cam import inextensible_ring_on_cam  # noqa: E402
from profilegen.geometry.wavegen import EllipticalCam, ellipse_perimeter, from_gearset  # noqa: E402

SEED_OMEGA = ([0.5272, 0.02677, 0.007596], [1.987, 5.965, 4.033], [1.611, 1.694, -9.533])
SEED_UPSILON = ([0.2956, 0.01807, 0.01897], [2.013, 0.2032, 4.067], [3.090, -1.919, -1.909])


def _sine_sum(phi, a, b, c):
    return sum(ai * np.sin(bi * phi + ci) for ai, bi, ci in zip(a, b, c))


def main() -> None:
    print("FEM vs oracle (equal-perimeter ellipse, r_m = 50 mm, w0 = 0.05 mm, layers 2 × 64):")
    r_m, w0 = 50.0, 0.05
    previous = None
    for delta in (2.0, 1.0, 0.5):
        r_b = r_m - delta / 2
        b = brentq(lambda b: ellipse_perimeter(r_b + w0, b) - 2 * math.pi * r_b, 0.5 * r_b, r_b + w0, xtol=1e-15)
        cam = EllipticalCam(r_b + w0, b)
        fem = solve_ring(RingParameters(r_m, delta, 2.1e5, 0.3), contour=cam, layers=2, divisions=64,
                         gap_tol_mm=1e-8 * w0)
        orc = inextensible_ring_on_cam(cam, r_m, delta)
        e = np.array([np.max(np.abs(fem.omega_mm - orc.omega(fem.phi_rad))),
                      np.max(np.abs(fem.upsilon_mm - orc.upsilon(fem.phi_rad)))]) / w0
        rate = "" if previous is None else f", rates {np.log2(previous / e)[0]:.2f} / {np.log2(previous / e)[1]:.2f}"
        print(f"  δ/r_m = {delta / r_m:.2f}: relative error ω {e[0]:.2e}, υ {e[1]:.2e}{rate}; wrap FEM "
              f"{fem.contact_angle_deg:.2f}°, oracle {orc.wrap_angle_deg:.2f}°")
        previous = e

    gs = pg.load_gearset(pg.default_gearset_path())
    g, w0 = gs.gear, gs.deflection_mm
    cam = from_gearset(gs)
    lin = solve_ring(gs, contour=cam)
    nl = solve_ring(gs, contour=cam, geometry="nonlinear")
    orc = inextensible_ring_on_cam(cam, g.neutral_radius_mm, g.rim_thickness_mm)
    print("default set:")
    print(f"  linear FEM vs oracle: ω {np.max(np.abs(lin.omega_mm - orc.omega(lin.phi_rad))) * 1e3:.3f} µm, "
          f"υ {np.max(np.abs(lin.upsilon_mm - orc.upsilon(lin.phi_rad))) * 1e3:.3f} µm; wrap FEM "
          f"{lin.contact_angle_deg:.2f}°, oracle {orc.wrap_angle_deg:.2f}°")
    print(f"  bore ω(0) − w0: linear {(lin.bore_omega_mm[0] - w0) * 1e6:.3f} nm, nonlinear "
          f"{(nl.bore_omega_mm[0] - w0) * 1e6:.3f} nm; neutral − bore: {(lin.omega_mm[0] - lin.bore_omega_mm[0]) * 1e6:.2f} nm")
    print(f"  nonlinear − linear: max |Δω| {np.max(np.abs(nl.omega_mm - lin.omega_mm)) * 1e3:.2f} µm, max |Δυ| "
          f"{np.max(np.abs(nl.upsilon_mm - lin.upsilon_mm)) * 1e3:.2f} µm; wrap {lin.contact_angle_deg:.1f}° → "
          f"{nl.contact_angle_deg:.1f}°")
    _, _, u_pitch = nl.at_radius(g.pitch_radius_mm)
    print(f"  υ at the pitch circle − υ on the neutral line: max {np.max(np.abs(u_pitch - nl.upsilon_mm)) * 1e3:.1f} µm")
    rim = solve_rim(gs, tier="design")
    fit = rim.model
    print(f"  design tier: Fourier order {fit.order}, largest residual ω {fit.omega_stats.max_error_mm * 1e6:.3f} nm, "
          f"υ {fit.upsilon_stats.max_error_mm * 1e6:.3f} nm; mesh error estimate {rim.error_estimate_mm * 1e6:.2f} nm")

    phi = np.radians(np.linspace(30.0, 60.0, 3001))
    u = _sine_sum(phi, *SEED_UPSILON)
    k = int(np.argmax(np.abs(u)))
    print(f"seed 004's printed series: ω(0) = {_sine_sum(0.0, *SEED_OMEGA):.4f} mm, |υ|max = {abs(u[k]):.4f} mm "
          f"at {math.degrees(phi[k]):.1f}°")


if __name__ == "__main__":
    main()
