"""Ratcheting torque estimate (issue 16 item 4) and its bad inputs.

    python tests/benchmarks/ratcheting.py [profiles/seed000_csf40.toml ...]

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

SETS = [ROOT / "profiles" / "seed000_csf40.toml", Path(pg.default_gearset_path())]


def run(path: Path) -> None:
    gs = pg.load_gearset(path)
    print(f"\n=== {gs.name} ({path.name}): rated {gs.torque.rated_nm:g}, peak {gs.torque.peak_nm:g}, "
          f"momentary {gs.torque.momentary_nm:g} N·m")
    t0 = time.process_time()
    design = pg.design(gs, scene="design", contact=False, stress=False)
    print(f"design scene: {time.process_time() - t0:.2f} s CPU")
    for label, kw in (("whole model", {}), ("no CS ring", {"cs_ring": False}),
                      ("rigid balls, no ring", {"bearing": None, "cs_ring": False})):
        t0 = time.process_time()
        r = ratcheting_torque(design, **kw)
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
        if label == "whole model":
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
        ratcheting_torque(design, torques_nm=[0.0, 265.0])
    except RatchetingError as exc:
        print(f"  torques_nm=[0, 265]: {type(exc).__name__}: {exc}")
    big = BallBearing(23, 7.5, 84.5, 0.52, 2.06e5, 0.3)
    thin = dataclasses.replace(gs, wave_generator=dataclasses.replace(gs.wave_generator, bearing_thickness_mm=8.0))
    try:
        check_bearing_fits(thin, big)
    except BearingFitError as exc:
        print(f"  7.5 mm balls in an 8 mm bearing section: {type(exc).__name__}: {exc}")


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    for path in [Path(a) for a in sys.argv[1:]] or SETS:
        run(path)


if __name__ == "__main__":
    main()
