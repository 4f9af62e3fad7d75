"""No cliff under a slider: where the envelope's trace misses a grazing crossing above the CS tip
circle, the pipeline retraces at a finer chord itself (pipeline.traced_form).

The default set's sketch scene failed at deflection coefficient 1.002 with pressure angle 10.1°
(EnvelopeError: "... a grazing crossing the trace missed") while the neighbours 1.001 / 1.003 and
10.0° / 10.2° designed."""

import pytest

import profilegen as pg
import profilegen.pipeline.design as pipeline
from profilegen.errors import EnvelopeError

CLIFF = {"wave_generator.deflection_coefficient": 1.002, "tooth.pressure_angle_deg": 10.1}


@pytest.fixture(scope="module")
def cliff_set():
    return pg.load_gearset(pg.default_gearset_path()).with_values(CLIFF)


def test_the_missed_crossing_is_retraced_and_the_design_holds(cliff_set):
    d = pg.design(cliff_set, scene="sketch", contact=False, stress=False)
    sketch = pg.SCENES["sketch"].chord_tol_mm
    # retraced once, 4x finer, and said so
    assert d.envelope.chord_tol_mm == pytest.approx(sketch / pipeline.RETRACE_FACTOR)
    assert any("retraced at chord" in w for w in d.warnings)
    assert d.stages[[s.stage for s in d.stages].index("envelope")].error_estimate == d.envelope.chord_tol_mm
    # the CS built from the finer trace is the conjugate one: the fitted profile keeps clear of
    # the FS tooth family to within the interference tolerance over the checked poses
    assert d.profile.clearance.min_mm >= -pipeline.interference_tol_mm(d.scene)


def test_without_retraces_the_failure_names_the_fix(cliff_set, monkeypatch):
    monkeypatch.setattr(pipeline, "RETRACES", 0)
    with pytest.raises(EnvelopeError, match="chord_tol_mm") as err:
        pg.design(cliff_set, scene="sketch", contact=False, stress=False)
    assert "grazing crossing" in str(err.value) and "\n" not in str(err.value)
