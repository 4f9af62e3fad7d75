"""How long a reduced verify scene takes: the verify scene's tiers and stages (the 3D cup rim,
the face stage, the brute-force swept-region check, the loaded contact, the ratcheting estimate,
the transmission error, the torsional curve across the face) on the design scene's grids (chord
1e-6 mm, 96 × 241 tracing grid, 361 clearance poses, 721 fit-check poses) and 3 face slices
instead of 5. A candidate for tests/test_bundled.py (issue 27 item 3: the verify scene of one
bundled set in the suite); the lead decides. One run per call; wall and CPU (this process and
its children: the transmission error's and the figures' workers) with the load average.

    python tests/benchmarks/reduced_verify.py [SET ...]     # default: seed000_csf40
"""

from __future__ import annotations

import resource
import sys
import time
from pathlib import Path

import profilegen as pg

ROOT = Path(__file__).resolve().parents[2]

SCENE = ROOT / "tests" / "scenes" / "reduced_verify.toml"  # the one tests/test_bundled.py runs


def main(argv=None) -> None:
    names = (argv if argv is not None else sys.argv[1:]) or ["seed000_csf40"]
    for name in names:
        gs = pg.load_gearset(ROOT / "profiles" / f"{name}.toml")
        load0 = open("/proc/loadavg").read().split()[:3]
        c0, ch0 = time.process_time(), resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        d = pg.design(gs, scene=str(SCENE))
        wall = time.perf_counter() - t0
        ch = resource.getrusage(resource.RUSAGE_CHILDREN)
        children = ch.ru_utime + ch.ru_stime - ch0.ru_utime - ch0.ru_stime
        print(f"{name}: wall {wall:.1f} s, CPU {time.process_time() - c0:.1f} s here + {children:.1f} s in "
              f"children; load average {' '.join(load0)} before, "
              f"{' '.join(open('/proc/loadavg').read().split()[:3])} after")
        print(f"  ratcheting {d.ratcheting.torque_nm:.0f} N·m; transmission error "
              f"{d.transmission.peak_to_peak_arcsec:.3g} arcsec p-p; face slices "
              f"{d.torsional.face['slices'] if d.torsional.face else None}")


if __name__ == "__main__":
    main()
