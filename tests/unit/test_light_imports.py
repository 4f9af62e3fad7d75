"""What the light commands import, and the wave generator's scipy-free numerics.

`profilegen check` reads gear sets and builds their wave generators; it must not pay for
scipy's solvers (~1 s of docstring parsing on import), matplotlib or ezdxf. The wave
generator's elliptic integral and root finder are written out in profilegen.geometry.wavegen; they
must give scipy's results to the last bit, or every design's numbers would move.
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipe

from profilegen.geometry.wavegen import _brentq, _ellipe, ellipse_perimeter

HEAVY = ("scipy", "matplotlib", "ezdxf", "plotly")


def _imported_after(code: str) -> list[str]:
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys, json\n"
                          f"print(json.dumps(sorted({{m.split('.')[0] for m in sys.modules}} & set({HEAVY!r}))))"],
                         capture_output=True, text=True, timeout=120, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_check_imports_no_solver_plotting_or_cad_library():
    code = ("import contextlib, io\nfrom profilegen.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    assert main(['check', 'default', 'seed000_csf40', 'seed001_shf25', 'seed002_short_cup']) == 0")
    assert _imported_after(code) == []


def test_import_profilegen_is_light():
    assert _imported_after("import profilegen") == []


@pytest.mark.parametrize("m", [0.0, 1e-300, 1e-12, 1e-3, 0.1, 0.5, 0.9, 0.999, 1 - 1e-12, 1.0, -0.5, -4.0, 1.5])
def test_ellipe_is_scipys_to_the_bit(m):
    want = float(ellipe(m))
    got = _ellipe(m)
    assert got == want or (math.isnan(got) and math.isnan(want))


def test_ellipe_random_parameters_to_the_bit():
    m = np.random.default_rng(7).uniform(0.0, 1.0, 20000)
    got = np.array([_ellipe(x) for x in m.tolist()])
    assert np.array_equal(got, ellipe(m))


def test_brentq_is_scipys_to_the_bit_on_elliptical_cams():
    rng = np.random.default_rng(11)
    eps4 = 4 * np.finfo(float).eps
    n = 0
    for _ in range(300):
        r_bore, frac, h_frac = rng.uniform(5.0, 200.0), rng.uniform(1e-3, 0.05), rng.uniform(0.0, 0.2)
        a = r_bore * (1 + frac) - h_frac * r_bore
        target = 2.0 * math.pi * (r_bore - h_frac * r_bore)

        def f(b):
            return ellipse_perimeter(a, b) - target

        if not f(1e-9 * a) < 0.0 < f(a):
            continue
        n += 1
        assert _brentq(f, 1e-9 * a, a, xtol=1e-15, rtol=eps4, maxiter=200) == \
            brentq(f, 1e-9 * a, a, xtol=1e-15, rtol=eps4, maxiter=200)
    assert n > 100


def test_brentq_is_scipys_on_other_functions_and_fails_where_it_fails():
    rng = np.random.default_rng(5)
    agree = fail = 0
    for _ in range(400):
        c, lo, hi = (float(v) for v in (rng.uniform(-3, 3), rng.uniform(0.01, 5), rng.uniform(0.01, 5)))

        def f(x):
            return (x - c) ** 3 * (1 + 0.1 * math.sin(7 * x))

        xtol, rtol = float(10 ** rng.uniform(-15, -3)), float(4 * np.finfo(float).eps * 10 ** rng.uniform(0, 5))
        maxiter = int(rng.integers(5, 120))
        try:
            mine = _brentq(f, c - lo, c + hi, xtol=xtol, rtol=rtol, maxiter=maxiter)
        except RuntimeError:
            mine = None
        try:
            theirs = brentq(f, c - lo, c + hi, xtol=xtol, rtol=rtol, maxiter=maxiter)
        except RuntimeError:
            theirs = None
        assert mine == theirs
        agree += mine is not None
        fail += mine is None
    assert agree > 50 and fail > 5  # both outcomes exercised


def test_brentq_refuses_a_root_not_bracketed():
    with pytest.raises(ValueError, match="different signs"):
        _brentq(lambda x: x * x + 1.0, -1.0, 1.0, xtol=1e-12, rtol=1e-15, maxiter=50)
