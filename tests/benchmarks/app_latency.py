"""How long a change in ``profilegen app`` takes to reach the screen, against the cold CLI.

For a sketch-scene tooth change (addendum coefficient 0.80 <-> 0.81) and a design-scene torque
change (rated torque 265 <-> 266 N·m), median of ``-n`` changes each:

* drawn: from the field's Enter in a headless chromium to the new design drawn (the tooth change:
  the new profile in the figure; the torque change: the finished design's numbers and verdict);
* compute: ``profilegen.app.compute.redesign`` alone for the same change, in this warm process;
* cold CLI: ``profilegen design --scene S`` in a fresh process (imports, compute, files);

and the app's cold start to its first render. Needs /usr/bin/chromium and /usr/bin/chromedriver.

    python tests/benchmarks/app_latency.py -n 5
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "app"))
sys.path.insert(0, str(ROOT))  # tests.chromium, which the browser tests import

import test_app_browser as tb  # noqa: E402  (the browser tests' helpers)


def _browser(tmp: Path):
    from tests.chromium import driver

    return driver(tmp / "chromium", tb.SCREEN, {"browser": "ALL"})


def _changes(driver, path: str, values, *, until_done: bool, n: int) -> list[float]:
    times = []
    for i in range(n):
        before = tb._state(driver)
        t0 = time.perf_counter()
        tb._type(driver, path, values[(i + 1) % 2])
        if until_done:
            tb._settled(driver, after_job=before["job"])
        else:
            from selenium.webdriver.support.ui import WebDriverWait

            WebDriverWait(driver, 120, poll_frequency=0.01).until(
                lambda d, job=before["job"]: (tb._state(d)["job"] or 0) > job)
        times.append(time.perf_counter() - t0)
        tb._settled(driver, after_job=before["job"])  # let the rest finish before the next change
    return times


def _compute(gearset, scene: str, path: str, values, n: int) -> list[float]:
    from profilegen.app.compute import redesign

    sets = [gearset.with_values({path: float(v)}) for v in values]
    redesign(sets[0], scene)  # warm
    times = []
    for i in range(n):
        t0 = time.perf_counter()
        redesign(sets[(i + 1) % 2], scene)
        times.append(time.perf_counter() - t0)
    return times


def _cold_cli(scene: str, n: int, tmp: Path) -> list[float]:
    times = []
    for i in range(n):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "profilegen", "design", "--scene", scene, "-q", "--out",
                        str(tmp / f"cli_{scene}_{i}")], check=True, cwd=ROOT)
        times.append(time.perf_counter() - t0)
    return times


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-n", type=int, default=5, help="changes per case (default 5)")
    ap.add_argument("--cli-runs", type=int, default=2, help="cold CLI runs per scene (default 2)")
    args = ap.parse_args()
    import profilegen as pg
    from profilegen.app import start

    gs = pg.load_gearset(pg.default_gearset_path())
    rows = {}
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        driver = _browser(tmp)
        try:
            for scene, path, values, done in (("sketch", "tooth.addendum_coefficient", ("0.8", "0.81"), False),
                                              ("design", "torque.rated_nm", ("265", "266"), True)):
                t0 = time.perf_counter()
                app = start(workspace=tmp, scene=scene)
                try:
                    driver.get(app.url)
                    tb._settled(driver)
                    first = time.perf_counter() - t0
                    drawn = _changes(driver, path, values, until_done=done, n=args.n)
                finally:
                    app.stop()
                compute = _compute(gs, scene, path, values, args.n)
                cli = _cold_cli(scene, args.cli_runs, tmp)
                rows[f"{scene}: {path}"] = {
                    "first_render_s": first, "drawn_s": statistics.median(drawn),
                    "compute_s": statistics.median(compute), "cold_cli_s": statistics.median(cli),
                    "cli_over_drawn": statistics.median(cli) / statistics.median(drawn)}
        finally:
            driver.quit()
    import os

    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs (medians of -n {args.n})")
    for name, r in rows.items():
        print(f"{name}: drawn {r['drawn_s']:.3f} s, compute {r['compute_s']:.3f} s, cold CLI {r['cold_cli_s']:.2f} s "
              f"({r['cli_over_drawn']:.1f}x the drawn change); app cold start to first render {r['first_render_s']:.2f} s")
    print(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
