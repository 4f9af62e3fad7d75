"""The verify scene's general sine fit (``series.fit_sine_series``, terms = 3) on the rim
stage's real ω(φ), υ(φ) samples of the bundled sets: the old fitter against the new one, in
one process (issue 14 item 2: ``profilegen design --scene verify`` ≤ 30 s).

    python tests/benchmarks/sine_fit.py [-n 3] [--set default ...] [--samples DIR] [--baseline]

"old" is ``fit_sine_series(..., _reference=True)``: the fitter before issue 14 (variable
projection with ``np.linalg.lstsq`` amplitudes and a 2-point finite-difference Jacobian under
``least_squares``); "new" the default (the exact Golub–Pereyra Jacobian, QR amplitudes,
MINPACK's lmder through ``leastsq``). Same pursuit, starts and polish. Both run alternately,
``-n`` times each, with single-threaded BLAS (as ``profilegen design`` runs the rim stage).

The samples are what ``solve_rim(gearset, tier="verify")`` fits (``one_period`` of its
toothed-rim FEM; the FEM takes minutes under load): they are taken once per set by stopping
the stage there, and kept as ``DIR/samples_<set>.pkl`` (default DIR: a ``profilegen-sine-fit``
folder in the temporary directory) for the next run.

Printed: the load average before and after; per set and component the medians of wall and
CPU time (process_time: less sensitive to the other processes on the machine), the ratio
old / new, nfev, the largest difference of the fitted curve and its derivatives 1–3 at the
samples (mm, mm/radᵏ), the SSEs, and each term's amplitude / frequency / phase difference,
the terms matched by frequency (a term of frequency ≈ 0 — ω's near-constant — is a flat
valley of the SSE: only a·sin c and a·b·cos c are determined, so its a, b, c are printed but
are not a measure of agreement). ``--baseline`` also fits with the old fitter on the samples
in reverse order (the same problem; other rounding): how closely the old fitter reproduces
itself.
"""

from __future__ import annotations

import argparse
import os
import pickle
import resource
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from profilegen.geometry.series import fit_sine_series  # noqa: E402

SETS = ("default", "seed000_csf40", "seed001_shf25", "seed002_short_cup")


class _Samples(Exception):
    pass


def samples(name: str, folder: Path) -> dict:
    """(φ, ω, υ) the verify rim stage fits for a bundled set, cached in ``folder``."""
    path = folder / f"samples_{name}.pkl"
    if path.exists():
        with open(path, "rb") as f:
            return pickle.load(f)
    import profilegen as pg
    import profilegen.rim.stage as stage

    real = stage.one_period

    def stop(res):
        raise _Samples(real(res))

    gearset = pg.load_gearset(ROOT / "profiles" / f"{name}.toml")
    stage.one_period = stop
    t0 = time.perf_counter()
    try:
        with threadpool_limits(1, user_api="blas"):
            stage.solve_rim(gearset, tier="verify")
        raise RuntimeError(f"solve_rim({name}, tier='verify') returned without sampling one period")
    except _Samples as got:
        phi, w, u = got.args[0]
    finally:
        stage.one_period = real
    print(f"  {name}: verify rim FEM samples in {time.perf_counter() - t0:.1f} s ({phi.size} samples)", flush=True)
    data = {"name": name, "phi": phi, "w": w, "u": u}
    folder.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    with open(tmp, "wb") as f:
        pickle.dump(data, f)
    os.replace(tmp, path)
    return data


def _matched(old, new):
    """Per old term, the new term of the nearest frequency: (|Δa|, |Δb|, |Δc| wrapped)."""
    rows = []
    for i, b in enumerate(old.frequency_per_rad):
        j = int(np.argmin(np.abs(new.frequency_per_rad - b)))
        dc = np.angle(np.exp(1j * (new.phase_rad[j] - old.phase_rad[i])))
        rows.append((b, abs(new.amplitude_mm[j] - old.amplitude_mm[i]), abs(new.frequency_per_rad[j] - b), abs(dc),
                     old.amplitude_mm[i]))
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=3, help="fits per fitter and component (median)")
    ap.add_argument("--set", action="append", choices=SETS, help="bundled set (repeatable; default: all four)")
    ap.add_argument("--samples", type=Path, default=Path(tempfile.gettempdir()) / "profilegen-sine-fit")
    ap.add_argument("--baseline", action="store_true", help="also the old fitter on the reversed samples")
    args = ap.parse_args()
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}", flush=True)
    fitters = {"old": lambda p, v: fit_sine_series(p, v, terms=3, _reference=True),
               "new": lambda p, v: fit_sine_series(p, v, terms=3)}
    totals = {k: [0.0, 0.0] for k in fitters}
    for name in args.set or SETS:
        data = samples(name, args.samples)
        phi = data["phi"]
        for comp, label in (("w", "ω"), ("u", "υ")):
            y = data[comp]
            wall = {k: [] for k in fitters}
            cpu = {k: [] for k in fitters}
            fits = {}
            with threadpool_limits(1, user_api="blas"):
                for _ in range(args.n):
                    for key, fit in fitters.items():
                        c0, t0 = time.process_time(), time.perf_counter()
                        fits[key] = fit(phi, y)
                        wall[key].append(time.perf_counter() - t0)
                        cpu[key].append(time.process_time() - c0)
                if args.baseline:
                    fits["old, reversed"] = fit_sine_series(phi[::-1].copy(), y[::-1].copy(), terms=3,
                                                            _reference=True)
            med = {k: (statistics.median(wall[k]), statistics.median(cpu[k])) for k in fitters}
            for k in fitters:
                totals[k][0] += med[k][0]
                totals[k][1] += med[k][1]
            old = fits["old"]
            print(f"{name} {label} ({phi.size} samples), median of {args.n}:")
            for k in fitters:
                print(f"  {k}: wall {med[k][0]:6.2f} s  cpu {med[k][1]:6.2f} s  nfev {fits[k].nfev:5d}  "
                      f"starts at best {fits[k].n_at_best}/{fits[k].n_starts}  SSE {fits[k].stats.sse_mm2:.12e} mm²")
            ratio = [med["old"][i] / med["new"][i] for i in (0, 1)]
            print(f"  ratio old/new: wall {ratio[0]:.2f}×  cpu {ratio[1]:.2f}×")
            ref = old.evaluate(phi, 3)
            for k, fit in fits.items():
                if k == "old":
                    continue
                d = np.abs(fit.evaluate(phi, 3) - ref).max(axis=1)
                sse = fit.stats.sse_mm2 - old.stats.sse_mm2
                print(f"  {k} − old: max |Δf| {d[0]:.2e} mm, |Δf'| {d[1]:.2e}, |Δf''| {d[2]:.2e}, "
                      f"|Δf'''| {d[3]:.2e}; "
                      f"ΔSSE {sse:+.2e} mm² ({sse / old.stats.sse_mm2:+.1e} relative)")
                for b, da, db, dc, a in _matched(old, fit):
                    flat = "  (b ≈ 0: flat valley, a, b, c undetermined)" if b < 1e-3 else ""
                    print(f"      term b = {b:.9g}, a = {a:.6g} mm: |Δa| {da:.1e} mm  |Δb| {db:.1e} rad⁻¹  "
                          f"|Δc| {dc:.1e} rad{flat}")
    print(f"total of the medians: old wall {totals['old'][0]:.2f} s cpu {totals['old'][1]:.2f} s; "
          f"new wall {totals['new'][0]:.2f} s cpu {totals['new'][1]:.2f} s; "
          f"ratio wall {totals['old'][0] / totals['new'][0]:.2f}× cpu {totals['old'][1] / totals['new'][1]:.2f}×")
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
