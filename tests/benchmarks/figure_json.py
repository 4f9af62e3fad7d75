"""The app's CS-space figure serialised as Dash sends it (plotly.io.json.to_json_plotly), with the
standard library's json and with orjson (which plotly picks when installed): medians of 7.

    python tests/benchmarks/figure_json.py
"""

import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import profilegen as pg  # noqa: E402
from plotly.io.json import to_json_plotly  # noqa: E402
from profilegen.app.views import space_figure  # noqa: E402


def median_s(f, n: int = 7) -> tuple[float, int]:
    times, size = [], 0
    for _ in range(n):
        t0 = time.perf_counter()
        size = len(f())
        times.append(time.perf_counter() - t0)
    return statistics.median(times), size


if __name__ == "__main__":
    fig = space_figure(pg.design(pg.load_gearset("default"), scene="sketch"))
    for engine in ("json", "orjson"):
        s, size = median_s(lambda engine=engine: to_json_plotly(fig, engine=engine))
        print(f"{engine:7s} {s * 1e3:7.1f} ms  {size / 1e6:.2f} MB")
