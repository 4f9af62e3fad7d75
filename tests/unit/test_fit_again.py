"""No cliff under a slider (issue 31 item 3): the CAD fit that does not converge within its SLP
iterations is tried again with more iterations and starts (pipeline._fit_again) instead of
failing the design, and says so; a second failure names both tries."""

import pytest

import profilegen as pg
import profilegen.profile.arcfit as arcfit
import profilegen.pipeline.design as pipeline
from profilegen.errors import ConvergenceError


@pytest.fixture(scope="module")
def base():
    return pg.load_gearset(pg.default_gearset_path())


def _first_try_fails(monkeypatch, *, always=False):
    real = arcfit.fit_profile
    tries = []

    def flaky(points, **options):
        if options.get("method") == "one_sided":
            tries.append(options.get("max_iter"))
            if always or options.get("max_iter") == pipeline.FIT_MAX_ITER:
                raise ConvergenceError("arcfit one_sided: no convergence in 200 SLP iterations (stand-in)")
        return real(points, **options)

    monkeypatch.setattr(arcfit, "fit_profile", flaky)
    return tries


def test_a_fit_that_stops_short_is_tried_again_and_the_design_holds(base, monkeypatch):
    tries = _first_try_fails(monkeypatch)
    d = pg.design(base, scene="sketch", stress=False)
    assert tries == [pipeline.FIT_MAX_ITER, pipeline.FIT_RETRY["max_iter"]]
    assert any("converged on a second try" in w for w in d.warnings)
    # the second try's profile is a one-sided fit like any: it keeps clear of the FS tooth family
    # to within the interference tolerance, and follows the envelope to the scene's fit accuracy
    assert d.profile.method == "one_sided"
    assert d.profile.clearance.min_mm >= -pipeline.interference_tol_mm(d.scene)
    assert d.profile.max_error_mm < 0.01 * base.gear.module_mm


def test_two_failed_tries_are_one_named_error(base, monkeypatch):
    _first_try_fails(monkeypatch, always=True)
    with pytest.raises(ConvergenceError, match="tried again with") as err:
        pg.design(base, scene="sketch", stress=False)
    assert "\n" not in str(err.value) and "one_sided" in str(err.value)
