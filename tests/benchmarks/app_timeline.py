"""Where a sketch-scene tooth change's drawn time goes, in the page: the Enter's keydown, each Dash
request (its outputs, start and end, size) and the CS-space figure's plotly afterplot, in ms after
the keydown, on the page's own clock (a fetch hook and event listeners in the page).

    python tests/benchmarks/app_timeline.py [-n 9] [--verbose] [--root CHECKOUT]

Prints the medians: keydown → the edit's request, the edit's response → the page's next request,
keydown → the figure drawn (afterplot), keydown → the finished verdict's response, and the
WebDriver's own drawn time for comparison. ``--verbose``: every change's timeline (``[outputs
start-end kB status]``). ``--root``: run the app from another checkout (its ``profilegen``
package; e.g. a ``git worktree`` of an older commit) — the A/B of a change to the app.
Needs /usr/bin/chromium and /usr/bin/chromedriver (as tests/benchmarks/app_latency.py, whose
harness it uses).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "benchmarks"))
sys.path.insert(0, str(ROOT / "tests" / "app"))
sys.path.insert(0, str(ROOT))

import app_latency as al  # noqa: E402  (the harness: the served app and the browser)
import test_app_browser as tb  # noqa: E402

HOOK = r"""
if (!window.__pg) {
  window.__pg = [];
  const f0 = window.fetch;
  window.fetch = function(url, opts) {
    const t0 = performance.now();
    let outs = '';
    try { outs = JSON.parse(opts.body).output.slice(0, 40); } catch (e) {}
    return f0.apply(this, arguments).then(r => { const t1 = performance.now();
       r.clone().text().then(b => window.__pg.push({k: 'req', outs, t0, t1, n: b.length, st: r.status}));
       return r; });
  };
  document.addEventListener('keydown', e => { if (e.key === 'Enter') window.__pg.push({k: 'enter', t: e.timeStamp}); }, true);
  const hookplot = () => { const g = document.querySelector('#space .js-plotly-plot');
     if (g && !g.__pghook) { g.__pghook = 1;
       g.on('plotly_afterplot', () => window.__pg.push({k: 'plot', t: performance.now(),
                                                         job: g._fullLayout.meta && g._fullLayout.meta.job})); } };
  setInterval(hookplot, 50);
}
"""


def main() -> None:
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import WebDriverWait

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-n", type=int, default=9, help="changes (default 9)")
    ap.add_argument("--verbose", action="store_true", help="every change's timeline")
    ap.add_argument("--root", type=Path, default=None, help="run the app from this checkout")
    a = ap.parse_args()
    if a.root is not None:
        al.ROOT = a.root.resolve()
    rows = {"enter_to_edit_request": [], "edit_response_to_next_request": [], "drawn_afterplot": [],
            "verdict_done_response": [], "drawn_webdriver": []}
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        d = al._browser(tmp)
        app = al._Served("sketch", tmp)
        try:
            d.get(app.url)
            tb._settled(d)
            d.execute_script(HOOK)
            time.sleep(0.3)
            for k in range(a.n):
                before = tb._state(d)
                d.execute_script("window.__pg.length = 0")
                box = tb._field(d, "tooth.addendum_coefficient")
                d.execute_script("arguments[0].scrollIntoView({block: 'center'})", box)
                box.send_keys(Keys.CONTROL, "a")
                box.send_keys(f"{0.800 + 0.001 * (k + 1):.6g}")
                t0 = time.perf_counter()
                box.send_keys(Keys.ENTER)
                WebDriverWait(d, 300, poll_frequency=0.02).until(
                    lambda dd, job=before["job"]: (tb._state(dd)["figure_job"] or 0) > job)
                rows["drawn_webdriver"].append((time.perf_counter() - t0) * 1e3)
                tb._settled(d, after_job=before["job"])
                ev = d.execute_script("return window.__pg")
                enter = [e["t"] for e in ev if e["k"] == "enter"]
                if not enter:
                    continue
                t_enter = enter[0]
                reqs = sorted((e for e in ev if e["k"] == "req"), key=lambda e: e["t0"])
                edit = [e for e in reqs if "ALL" in e["outs"]]
                if edit:
                    rows["enter_to_edit_request"].append(edit[0]["t0"] - t_enter)
                    after = [e["t0"] for e in reqs if e["t0"] > edit[0]["t1"]]
                    if after:
                        rows["edit_response_to_next_request"].append(min(after) - edit[0]["t1"])
                plots = [e["t"] for e in ev if e["k"] == "plot" and (e.get("job") or 0) > before["job"]]
                if plots:
                    rows["drawn_afterplot"].append(plots[0] - t_enter)
                done = [e["t1"] for e in reqs if "verdict" in e["outs"] and e["n"] > 6000]
                if done:
                    rows["verdict_done_response"].append(done[0] - t_enter)
                if a.verbose:
                    line = [f"webdriver {rows['drawn_webdriver'][-1]:.0f}"]
                    for e in sorted(ev, key=lambda e: e.get("t0", e.get("t"))):
                        if e["k"] == "req":
                            line.append(f"[{e['outs'][:14]} {e['t0'] - t_enter:.0f}-{e['t1'] - t_enter:.0f} "
                                        f"{e['n'] // 1000}k {e['st']}]")
                        elif e["k"] == "plot":
                            line.append(f"plot@{e['t'] - t_enter:.0f}")
                    print(" ".join(line), flush=True)
        finally:
            app.stop()
            d.quit()
    print(f"app from {al.ROOT}, {a.n} sketch-scene tooth changes, medians in ms after the Enter's keydown:")
    for name, vals in rows.items():
        if vals:
            print(f"  {name}: {statistics.median(vals):.0f} (n {len(vals)}, {min(vals):.0f}-{max(vals):.0f})")


if __name__ == "__main__":
    main()
