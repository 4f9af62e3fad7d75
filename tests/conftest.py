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
    from profilegen.profile.envelope import envelope_of
    from profilegen.gearset import default_gearset_path, load_gearset
    from profilegen.geometry.kinematics import HarmonicDriveMotion
    from profilegen.geometry.teeth import tooth_from_gearset

    gs = load_gearset(default_gearset_path())
    tooth = tooth_from_gearset(gs)
    motion = HarmonicDriveMotion.from_gearset(gs)
    env = envelope_of(tooth, motion, cs_teeth=gs.gear.circular_spline_teeth, waves=gs.gear.waves)
    return tooth, motion, env


@pytest.fixture(scope="session")
def default_gearset():
    """The bundled default gear set (profiles/default.toml)."""
    from profilegen.gearset import default_gearset_path, load_gearset

    return load_gearset(default_gearset_path())


# The default set's designs that many modules read, computed once per worker process (session
# scope: one computation per xdist worker, kept across modules) instead of once per module and
# worker. Before (2026-11-25) eleven modules each computed the sketch design in a module fixture
# (0.6 s CPU each, on both workers: ~20 computations), three the sketch with contact (2.2 s),
# two the design scene (3.6 s). The results are read only (dataclasses; tests that need a
# variant take dataclasses.replace); the stress=False and contact=False variants the modules
# used before are these with the later stages' results beside them (the stages before the
# stresses do not read them).
@pytest.fixture(scope="session")
def default_sketch(default_gearset):
    """``profilegen.design(default set, scene="sketch")``: no loaded contact, stresses from the
    force estimate."""
    import profilegen as pg

    return pg.design(default_gearset, scene="sketch")


@pytest.fixture(scope="session")
def default_sketch_contact(default_gearset):
    """``profilegen.design(default set, scene="sketch", contact=True)``: with the loaded contact
    (and the stresses from its forces)."""
    import profilegen as pg

    return pg.design(default_gearset, scene="sketch", contact=True)


@pytest.fixture(scope="session")
def default_design_scene(default_gearset):
    """``profilegen.design(default set, scene="design")``: the whole design scene (nonlinear rim,
    Fourier fit, loaded contact, stresses)."""
    import profilegen as pg

    return pg.design(default_gearset, scene="design")


@pytest.fixture(scope="session")
def default_ring_design(default_gearset):
    """The design scene with the 2D ring FEM and no face stage (its ``rim`` label asks for it:
    profilegen.face.coning.RING_FEM_LABEL), no contact, no stresses: the stage studies and the
    arc-fit checks on the default flank, written for the ring FEM's section (issue 28 moved the
    design scene to a coarse 3D cup with the face stage)."""
    import dataclasses

    import profilegen as pg
    from profilegen.face.coning import RING_FEM_LABEL

    scene = dataclasses.replace(pg.SCENES["design"], rim=RING_FEM_LABEL)
    return pg.design(default_gearset, scene=scene, contact=False, stress=False)


#: Modules kept on one xdist worker from here, not by a ``pytestmark`` of their own: their files
#: belong to other engineers this session (2026-11-25). Their module fixtures (designs with the
#: loaded contact, torsional curves, the import graph: 4-15 s wall each on the busy machine,
#: --setup-only) were computed on both workers.
ONE_WORKER_MODULES = ("tests/unit/test_compliance_chain.py", "tests/unit/test_ball_supports.py",
                      "tests/unit/test_transmission_error.py", "tests/unit/test_ratchet.py",
                      "tests/unit/test_import_graph.py", "tests/unit/test_report_speed.py")


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook, which reads the xdist_group marks into the node ids
def pytest_collection_modifyitems(config, items):
    """The heavy tests (marked ``slow``) first, in their collected order, then the rest.

    With two xdist workers (``--dist loadgroup``) the run ends when the later worker ends: a
    20–40 s test handed out last keeps one worker busy while the other waits. Handing the heavy
    ones out first leaves the hundreds of sub-second tests to fill in at the end. The order is
    the same in every worker (xdist requires identical collections).

    Modules whose module-scoped fixtures cost seconds carry an ``xdist_group`` mark of their own
    (``pytestmark``): one worker runs the module and computes its fixtures once, where the
    module's tests dealt to both workers computed them on each (test_face.py's three face
    studies: 2 x 3 setups, ~7 s each on the busy machine). xdist hands the groups out first,
    the largest first (--loadscope-reorder, its default), then the single tests in this order."""
    for item in items:
        module = item.nodeid.split("::", 1)[0]
        if module in ONE_WORKER_MODULES and item.get_closest_marker("xdist_group") is None:
            item.add_marker(pytest.mark.xdist_group(module.rsplit("/", 1)[-1].removesuffix(".py")))
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)


@pytest.fixture(scope="session")
def default_sketch_run(tmp_path_factory):
    """`profilegen design default --scene sketch --out DIR`, run once as a user types it (a
    subprocess, stdout and stderr piped): (CompletedProcess, DIR). Three tests check this one
    run (tests/test_cli.py: the progress lines and the DXF; tests/test_bundled.py: the default
    set's sketch scene); they share the xdist group ``default_sketch`` so one worker runs it."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    cwd = tmp_path_factory.mktemp("default_sketch")
    out = cwd / "o"
    res = subprocess.run([sys.executable, "-m", "profilegen", "design", "default", "--scene", "sketch", "--out", str(out)],
                         cwd=cwd, capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=str(root)), timeout=300)
    return res, out
