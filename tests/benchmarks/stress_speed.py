"""Speed of the stress models: the wall-clock budgets the validation tests used to assert.

    python tests/benchmarks/stress_speed.py [--repeats N]

The tests in tests/validation/test_stress_{plate,tooth_ring,diaphragm}.py check physics only;
their former timing assertions live here, on the same cases, as medians of ``--repeats``
runs after one warm-up call (imports, first-call caches of numpy/scipy):

* cup bottom, consistent analytic model (seed 002's Table 1 ellipse, T = 395 N·m):
  one full design (stress maps + refined maxima), budget 0.1 s;
* cup bottom, Morley FE plate on 8/16/32 radial divisions (edge W₂ cos 2φ + W₄ cos 4φ),
  budget 2 s for the 32-division mesh, and the ratio Morley(32) / analytic measured in
  the same run (the analytic model is the one that runs in every design);
* tooth ring (seed 001's SHF-25 ring, ellipse from ρ_a only): budget 0.01 s;
* diaphragm + Goodman check (size-40 estimate): budget 0.01 s.

Prints one line per case: median, min, max (s), the budget and whether the median met it.
Writes nothing. The budgets are the tests' former numbers, not guarantees: a busy machine
can miss them without anything being wrong, which is why they are not tests.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from profilegen.stress import diaphragm as dg  # noqa: E402
from profilegen.stress import tooth_ring as tr  # noqa: E402
from tests.oracles.morley import solve_morley  # noqa: E402
from profilegen.stress.plate import (SEED002_TABLE1, cup_bottom_stress, edge_displacement,  # noqa: E402
                                     edge_displacement_from_ellipse)
from tests.validation.test_stress_diaphragm import SAMPLE as DIAPHRAGM_SAMPLE  # noqa: E402
from tests.validation.test_stress_tooth_ring import base_inputs as ring_inputs  # noqa: E402

P = SEED002_TABLE1
PLATE = dict(boss_radius_mm=P["boss_radius_mm"], thickness_mm=P["thickness_mm"],
             youngs_modulus_mpa=P["youngs_modulus_mpa"], poisson_ratio=P["poisson_ratio"])


def timings(repeats: int, fn) -> list[float]:
    """Wall-clock times of ``repeats`` calls of fn after one warm-up call."""
    fn()
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return out


def line(name: str, times: list[float], budget_s: float | None = None) -> float:
    med = statistics.median(times)
    verdict = "" if budget_s is None else f"  budget {budget_s:g} s: {'met' if med < budget_s else 'MISSED'}"
    print(f"{name:<44s} median {med * 1e3:9.3f} ms  (min {min(times) * 1e3:.3f}, max {max(times) * 1e3:.3f}, "
          f"n = {len(times)}){verdict}")
    return med


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7, help="timed runs per case (default 7)")
    args = ap.parse_args(argv)
    n = max(1, args.repeats)

    ellipse = edge_displacement_from_ellipse(P["semi_major_mm"], P["semi_minor_mm"], mean_radius_mm=P["mean_radius_mm"],
                                             length_mm=P["length_mm"])
    analytic = line("cup bottom, consistent analytic",
                    timings(n, lambda: cup_bottom_stress(ellipse, torque_nmm=395e3, **PLATE)), 0.1)
    line("cup bottom, seed002 variant",
         timings(n, lambda: cup_bottom_stress(ellipse, torque_nmm=395e3, model="seed002", **PLATE)))

    edge = edge_displacement({2: 0.35, 4: 0.02}, mean_radius_mm=P["mean_radius_mm"], length_mm=P["length_mm"])
    morley = {}
    for div in (8, 16, 32):
        reps = n if div < 32 else max(1, min(n, 3))
        morley[div] = line(f"cup bottom, Morley {div} radial divisions",
                           timings(reps, lambda d=div: solve_morley(edge, radial_divisions=d, **PLATE)),
                           2.0 if div == 32 else None)
    print(f"{'Morley(32) / consistent analytic':<44s} ratio {morley[32] / analytic:9.1f}×  (same run)")

    kw = ring_inputs(minor_semi_axis_mm=None)
    line("tooth ring (seed 001 SHF-25)", timings(n, lambda: tr.tooth_ring_stress(**kw)), 0.01)
    line("diaphragm + Goodman (size-40 estimate)", timings(n, lambda: dg.diaphragm_stress(**DIAPHRAGM_SAMPLE)), 0.01)


if __name__ == "__main__":
    main()
