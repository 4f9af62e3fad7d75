"""How long a change in ``profilegen app`` takes to reach the screen, against the cold CLI.

Three changes, each to a value this process has never designed (the engine's cache would
otherwise answer a value seen before at once), median of ``-n`` changes each:

* sketch scene, a tooth change (addendum coefficient 0.800 + 0.001 k): drawn = from the Enter
  that takes the typed value (the WebDriver's own typing before it is not counted) in a headless
  chromium to the new CS space in the figure;
* design scene, a torque change (rated torque 265 + 0.7 k N·m): drawn = to the finished design's
  verdict and numbers on the page (the figures stay: the profile did not change);
* design scene, a tooth change (addendum coefficient): drawn = to the new CS space in the figure;

Drawn is measured twice: on the page's own clock (the Enter's keydown event to the animation frame
after plotly has drawn the new figure, or after the progress line says "done": what a user sees)
and through the WebDriver (from this process's Enter to the 20 ms poll of the page that finds it
drawn: the key's dispatch and the polls add ~30-40 ms a user does not see). The goals are judged
on the page's clock; both are printed.

The app runs as ``profilegen app --port 0`` in a process of its own, started afresh for each case
(the browser's driver in the app's process took its interpreter lock at every poll of the page,
slowing the computation it measures). For each: compute = ``profilegen.app.compute.redesign`` alone for the same kind of change in this
warm process; bytes = what the page received for the change (the Dash responses' bodies, the
browser's resource timing); cold CLI = ``profilegen design --scene S`` in a fresh process (imports,
compute, files), as a ratio to the drawn time; and the app's cold start to its first render.

``--cancel N``: the cancellation latency as well — a design-scene change superseded at a random
moment (N times each for the tooth and the torque change), the time from the newer request until
the tab's computation thread takes it up, with the stage that was running.

Needs /usr/bin/chromium and /usr/bin/chromedriver.

    python tests/benchmarks/app_latency.py -n 5 --cancel 6
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import random
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

#: (scene, field, first value, step, what "drawn" waits for)
CASES = (("sketch", "tooth.addendum_coefficient", 0.800, 0.001, "figure"),
         ("design", "torque.rated_nm", 265.0, 0.7, "done"),
         ("design", "tooth.addendum_coefficient", 0.800, 0.001, "figure"))

#: the page's own clock: the Enter's event time, and the frame after each new CS-space plot (plotly's
#: afterplot, then the next animation frame: the one that paints it) and after each "done" on the
#: progress line, with the job each was of
_PAGE_CLOCK = """
if (!window.__lat) {
  window.__lat = {enter: null, figure: [], done: []};
  document.addEventListener('keydown', e => { if (e.key === 'Enter') window.__lat.enter = e.timeStamp; }, true);
  const frame = (list, job) => requestAnimationFrame(() => list.push([job, performance.now()]));
  const hook = () => {
    const g = document.querySelector('#space .js-plotly-plot');
    if (g && !g.__latHooked) {
      g.__latHooked = true;
      g.on('plotly_afterplot', () => frame(window.__lat.figure, g._fullLayout.meta ? g._fullLayout.meta.job : null));
    }
    const p = document.getElementById('progress');
    if (p && !p.__latHooked) {
      p.__latHooked = true;
      new MutationObserver(() => { const m = /^job ([0-9]+),.*, done/.exec(p.textContent);
                                   if (m) frame(window.__lat.done, Number(m[1])); })
        .observe(p, {childList: true, characterData: true, subtree: true});
    }
  };
  hook(); setInterval(hook, 100);
}
window.__lat.enter = null; window.__lat.figure.length = 0; window.__lat.done.length = 0;
"""

_PAGE_DRAWN = """
const l = window.__lat, kind = arguments[0], after = arguments[1];
const hit = l[kind].find(([job, t]) => job !== null && job > after);
return l.enter === null || !hit ? null : (hit[1] - l.enter) / 1000;
"""

_BYTES = """
return performance.getEntriesByType('resource').filter(e => e.name.includes('_dash-update-component'))
    .reduce((a, e) => a + (e.encodedBodySize || 0), 0);
"""


def _browser(tmp: Path):
    from tests.chromium import driver

    return driver(tmp / "chromium", tb.SCREEN, {"browser": "ALL"})


def _changes(driver, path: str, values, *, until: str) -> tuple[list[float], list[float], list[int]]:
    """Per change: the drawn time as this process sees it through the WebDriver (from the Enter
    sent to the poll that finds it drawn), the same on the page's own clock (the Enter's event to
    the frame that paints it: what the user sees, without the WebDriver's key dispatch and its
    20 ms polls), and the bytes the page received."""
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import WebDriverWait

    times, page, sizes = [], [], []
    for v in values:
        before = tb._state(driver)
        driver.execute_script("performance.clearResourceTimings()")
        driver.execute_script(_PAGE_CLOCK)
        box = tb._field(driver, path)  # the value typed, then the clock starts at its Enter
        driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", box)
        box.send_keys(Keys.CONTROL, "a")
        box.send_keys(f"{v:.6g}")
        t0 = time.perf_counter()
        box.send_keys(Keys.ENTER)
        if until == "done":
            tb._settled(driver, after_job=before["job"])
        else:
            WebDriverWait(driver, 300, poll_frequency=0.02).until(
                lambda d, job=before["job"]: (tb._state(d)["figure_job"] or 0) > job)
        times.append(time.perf_counter() - t0)
        tb._settled(driver, after_job=before["job"])  # let the rest finish before the next change
        seen = driver.execute_script(_PAGE_DRAWN, "done" if until == "done" else "figure", before["job"])
        if seen is None:
            raise RuntimeError(f"{path} = {v}: the page's clock did not see the change drawn")
        page.append(float(seen))
        sizes.append(int(driver.execute_script(_BYTES)))
    return times, page, sizes


class _Served:
    """``profilegen app`` in its own process (as a user runs it): the browser's driver in this one
    would take the GIL from the app's computation at every poll of the page."""

    def __init__(self, scene: str, workspace: Path):
        import re
        import signal

        self.proc = subprocess.Popen(
            [sys.executable, "-m", "profilegen", "app", "--scene", scene, "--port", "0", "--workspace", str(workspace)],
            cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
        line = self.proc.stdout.readline()
        found = re.search(r"(http://\S+/)", line)
        if not found:
            self.proc.kill()
            raise RuntimeError(f"profilegen app did not say its address: {line!r}")
        self.url = found.group(1)

    def stop(self) -> None:
        import signal

        self.proc.send_signal(signal.SIGINT)
        try:
            self.proc.wait(30)
        except subprocess.TimeoutExpired:
            self.proc.kill()


def _compute(gearset, scene: str, path: str, values) -> list[float]:
    from profilegen.app.compute import redesign

    redesign(gearset, scene)  # warm: the set as given (the app's first design)
    times = []
    for v in values:
        gs = gearset.with_values({path: float(v)})
        t0 = time.perf_counter()
        redesign(gs, scene)
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


def _cancel(gearset, trials: int, seed: int = 1) -> dict:
    """Design-scene changes superseded at a random moment of their computation (the tab's
    Computer, the real engine): the time until the computation thread takes up the newer request."""
    from profilegen.app.session import Computer

    c = Computer()
    rng = random.Random(seed)

    def run(gs) -> float:
        t0 = time.perf_counter()
        c.wait(c.submit(gs, "design"), profile=False, timeout=900)
        return time.perf_counter() - t0

    run(gearset)
    kinds = {"torque": ("torque.rated_nm", 400.0, 0.7), "tooth": ("tooth.addendum_coefficient", 0.750, 0.001)}
    count = collections.Counter()

    def fresh(kind):
        path, first, step = kinds[kind]
        count[kind] += 1
        return gearset.with_values({path: first + step * count[kind]})

    took = {k: run(fresh(k)) for k in kinds}
    rows = []
    for _ in range(trials):
        for kind in kinds:
            job = c.submit(fresh(kind), "design")
            time.sleep(rng.uniform(0.0, took[kind]))
            snap = c.latest()
            if snap is None or snap.job != job or snap.done:
                continue  # finished before the newer request: nothing to cancel
            stage = snap.stages[-1] if snap.stages else "queued"
            t0 = time.perf_counter()
            newer = c.submit(gearset, "design")  # designed before: every stage cached
            while newer not in c.ran:
                time.sleep(0.0005)
            rows.append((kind, stage, time.perf_counter() - t0))
            c.wait(newer, profile=False, timeout=900)
    c.close()
    by_stage = collections.defaultdict(list)
    for kind, stage, s in rows:
        by_stage[stage].append(s)
    return {"trials": len(rows), "median_s": statistics.median(r[2] for r in rows),
            "max_s": max(r[2] for r in rows),
            "by_kind": {k: statistics.median(r[2] for r in rows if r[0] == k) for k in kinds
                        if any(r[0] == k for r in rows)},
            "by_stage": {k: {"n": len(v), "median_s": statistics.median(v), "max_s": max(v)}
                         for k, v in by_stage.items()}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-n", type=int, default=5, help="changes per case (default 5)")
    ap.add_argument("--cli-runs", type=int, default=2, help="cold CLI runs per scene (default 2)")
    ap.add_argument("--cancel", type=int, default=0, help="superseded designs per kind (default 0: none)")
    args = ap.parse_args()
    import profilegen as pg

    gs = pg.load_gearset(pg.default_gearset_path())
    rows, cli = {}, {}
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        driver = _browser(tmp)
        try:
            for i, (scene, path, first, step, until) in enumerate(CASES):
                t0 = time.perf_counter()
                app = _Served(scene, tmp)  # a fresh process: the cold start is the user's
                try:
                    driver.get(app.url)
                    tb._settled(driver)
                    first_render = time.perf_counter() - t0
                    # the browser's values and the compute's: each fresh (never designed in this process)
                    drawn, page, sizes = _changes(driver, path, [first + step * (k + 1) for k in range(args.n)],
                                                  until=until)
                finally:
                    app.stop()
                compute = _compute(gs, scene, path, [first - step * (k + 1) for k in range(args.n)])
                if scene not in cli:
                    cli[scene] = statistics.median(_cold_cli(scene, args.cli_runs, tmp))
                rows[f"{scene}: {path}"] = {
                    "first_render_s": first_render, "drawn_s": statistics.median(drawn),
                    "drawn_page_s": statistics.median(page),
                    "compute_s": statistics.median(compute), "bytes": statistics.median(sizes),
                    "cold_cli_s": cli[scene], "cli_over_drawn": cli[scene] / statistics.median(drawn)}
        finally:
            driver.quit()
    cancel = _cancel(gs, args.cancel) if args.cancel else None
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs (medians of -n {args.n})")
    for name, r in rows.items():
        print(f"{name}: drawn {r['drawn_page_s']:.3f} s on the page's clock ({r['drawn_s']:.3f} s through the "
              f"WebDriver), compute {r['compute_s']:.3f} s, {r['bytes'] / 1e3:.0f} kB to the "
              f"page, cold CLI {r['cold_cli_s']:.2f} s ({r['cli_over_drawn']:.1f}x the drawn change); app cold start "
              f"to first render {r['first_render_s']:.2f} s")
    if cancel is not None:
        print(f"cancellation (design scene, {cancel['trials']} superseded designs): median {cancel['median_s']:.3f} s, "
              f"max {cancel['max_s']:.3f} s; by kind " + ", ".join(f"{k} {v:.3f} s" for k, v in cancel["by_kind"].items())
              + "; by stage " + ", ".join(f"{k} {v['median_s']:.3f} s (n {v['n']}, max {v['max_s']:.3f})"
                                          for k, v in cancel["by_stage"].items()))
    print(json.dumps({"cases": rows, "cancel": cancel}, indent=1))


if __name__ == "__main__":
    main()
