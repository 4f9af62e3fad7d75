"""Fixtures shared by the test modules."""

import pytest


@pytest.fixture(scope="session")
def default_set():
    """The bundled default gear set's tooth, motion (ring theory) and classified envelope."""
    from profilegen.envelope import envelope_of
    from profilegen.gearset import default_gearset_path, load_gearset
    from profilegen.kinematics import HarmonicDriveMotion
    from profilegen.teeth import tooth_from_gearset

    gs = load_gearset(default_gearset_path())
    tooth = tooth_from_gearset(gs)
    motion = HarmonicDriveMotion.from_gearset(gs)
    env = envelope_of(tooth, motion, cs_teeth=gs.gear.circular_spline_teeth, waves=gs.gear.waves)
    return tooth, motion, env
