"""Fixtures shared by the test modules, and the test process's BLAS threads."""

import pytest
import scipy.linalg  # noqa: F401 — scipy's own OpenBLAS must be loaded for the limit below to reach it
from threadpoolctl import threadpool_limits

# One BLAS thread per test process. The suite runs on two pytest-xdist workers on two cores:
# with OpenBLAS's default of a thread per core, each worker's spinning threads fight the other
# worker for the cores. profilegen.design already limits itself (pipeline.py), but the tests
# that call the stages directly did not: a (3200 × 6) lstsq of the rim stage's general sine
# fit took 3.9 ms CPU with 2 threads and 0.41 ms with 1, and test_rim_stage's toothed tier
# 82 → 25 s CPU (the sine fit's 20 starts run ~14 000 of them). Same arithmetic, one thread.
threadpool_limits(limits=1, user_api="blas")


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
