"""Issue 26, items 3 and 4: what would take the machine is refused before any stage runs, and every
failure names what the user can change (the scene key or gear-set field, and a value that works).

Each refusal is checked for its type and the field it names; where a message proposes a value,
the value is applied and must then pass (the message's advice is a fact we can test, not text).
"""

from __future__ import annotations

import dataclasses
import logging
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import profilegen as pg
from profilegen.pipeline import budget
from profilegen.pipeline.budget import (
    BudgetError,
    ResolutionError,
    check_budget,
    check_resolution,
    preflight,
)
from profilegen.errors import ExportError, GearSetError
from profilegen.gearset import default_gearset_path, load_gearset
from profilegen.pipeline.scenes import SCENES, SceneError, parse_scenes
from profilegen.output.userpaths import check_out_path

GIB = 2**30
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def gs():
    return load_gearset(default_gearset_path())


def _scene(**changes):
    return dataclasses.replace(SCENES["sketch"], **changes)


def _suggested(message: str, key: str) -> float:
    """The value a message proposes for ``key`` ("lower n_phi to at most 894", "at least 1e-05")."""
    import re

    match = re.search(rf"{re.escape(key)} to at (?:most|least) ([0-9.e+-]+)", message)
    assert match, f"no value proposed for {key} in: {message}"
    return float(match.group(1))


# --------------------------------------------------------------------------- the cost model


def test_the_three_documented_extremes_are_refused_by_name_before_any_stage(gs, monkeypatch):
    """n_t = n_phi = 100000 (a 74.5 GiB grid), clearance_samples = fit_check_positions = 100000
    (2.5 GB and growing) under a 2 GiB budget: design() raises a BudgetError naming the key before
    its first stage (the progress callback is never called, nothing is allocated)."""
    monkeypatch.setenv(budget.BUDGET_ENV, "2G")
    stages = []
    with pytest.raises(BudgetError, match=r"n_t × n_phi = 100000 × 100000.*lower n_phi to at most") as err:
        pg.design(gs, scene=_scene(n_t=100_000, n_phi=100_000), progress=stages.append)
    assert stages == [] and isinstance(err.value, ValueError) and "\n" not in str(err.value)
    with pytest.raises(BudgetError, match=r"(clearance_samples|fit_check_positions) = 100000.*to at most"):
        pg.design(gs, scene=_scene(clearance_samples=100_000, fit_check_positions=100_000), progress=stages.append)
    assert stages == []


def test_a_chord_of_1e_300_is_outside_the_documented_range_and_over_any_budget(gs):
    table = {k: v for k, v in dataclasses.asdict(SCENES["sketch"]).items() if k not in ("name",) and v != ""}
    with pytest.raises(SceneError, match=r"chord_tol_mm = 1e-300: must be in \[1e-09, 0.01\] mm"):
        parse_scenes({"fine": {**table, "chord_tol_mm": 1e-300}})
    # a Scene made in Python skips the file's check; the cost model still refuses it, by name
    with pytest.raises(BudgetError, match=r"chord_tol_mm = 1e-300 .*raise chord_tol_mm to at least") as err:
        check_budget(gs, _scene(chord_tol_mm=1e-300), budget=2 * GIB)
    fine = _suggested(str(err.value), "chord_tol_mm")
    check_budget(gs, _scene(chord_tol_mm=fine), budget=2 * GIB)  # the advice is enough


@pytest.mark.parametrize("changes, key", [
    ({"n_t": 100_000, "n_phi": 100_000}, "n_phi"),
    ({"clearance_samples": 100_000}, "clearance_samples"),
    ({"fit_check_positions": 100_000}, "fit_check_positions"),
])
def test_the_proposed_value_passes(gs, changes, key):
    with pytest.raises(BudgetError) as err:
        check_budget(gs, _scene(**changes), budget=2 * GIB)
    value = int(_suggested(str(err.value), key))
    check_budget(gs, _scene(**{**changes, key: value}), budget=2 * GIB)
    with pytest.raises(BudgetError):  # and it is the largest that does, within a few per cent
        check_budget(gs, _scene(**{**changes, key: int(value * 1.05) + 1}), budget=2 * GIB)


def test_the_bundled_sets_and_scenes_are_within_a_2_gib_budget():
    """The check never refuses what the package ships (the estimates are upper bounds of a few
    hundred MB for the verify scene)."""
    for path in sorted((ROOT / "profiles").glob("*.toml")):
        gearset = load_gearset(path)
        for scene in SCENES.values():
            preflight_est = check_budget(gearset, scene, budget=2 * GIB)
            assert preflight_est.largest().bytes < 2 * GIB


def test_the_budget_follows_the_environment_and_the_address_space_limit(monkeypatch):
    monkeypatch.setenv(budget.BUDGET_ENV, "500M")
    assert budget.budget_bytes() == 500 * 2**20
    monkeypatch.setenv(budget.BUDGET_ENV, "none")
    assert budget.budget_bytes() is None
    monkeypatch.setenv(budget.BUDGET_ENV, "lots")
    with pytest.raises(BudgetError, match=budget.BUDGET_ENV):
        budget.budget_bytes()
    monkeypatch.delenv(budget.BUDGET_ENV)
    monkeypatch.setattr(budget.resource, "getrlimit", lambda what: (4 * GIB, 4 * GIB))
    assert budget.budget_bytes() <= 2 * GIB  # at most half a 4 GB cap (ulimit -v)


# --------------------------------------------------------------------------- resolution of the module


def test_a_chord_coarse_for_the_module_names_both_fields_and_the_advice_works(gs):
    small = gs.with_values({"gear.module_mm": 0.001, "gear.rim_thickness_mm": 0.0018})
    with pytest.raises(ResolutionError, match=r"gear\.module_mm = 0\.001 mm.*chord_tol_mm = 0\.0001") as err:
        preflight(small, SCENES["sketch"])
    check_resolution(small, _scene(chord_tol_mm=_suggested(str(err.value), "chord_tol_mm")))
    big = _suggested(str(err.value), "gear.module_mm")
    check_resolution(gs.with_values({"gear.module_mm": big, "gear.rim_thickness_mm": 1.8 * big}), SCENES["sketch"])


def test_a_module_below_what_the_arc_fit_resolves_is_refused_by_the_reader(gs):
    with pytest.raises(GearSetError, match=r"gear\.module_mm = 1e-06 mm: must be in \[1e-05, 10\]"):
        gs.with_values({"gear.module_mm": 1e-6, "gear.rim_thickness_mm": 1.8e-6})


# --------------------------------------------------------------------------- the output path


def _cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "profilegen", *args], check=False, capture_output=True, text=True, cwd=cwd,
                          timeout=120)


@pytest.mark.parametrize("command", ["design", "sweep"])
def test_an_out_name_too_long_is_one_line_exit_2_naming_out(tmp_path, command):
    target = "profiles/sweeps/deflection.toml" if command == "sweep" else "default"
    run = _cli(command, str(ROOT / target) if command == "sweep" else target, "-q", "--out", "x" * 300, cwd=tmp_path)
    assert run.returncode == 2
    assert run.stderr.count("\n") == 1 and run.stderr.startswith("profilegen: error: --out: a folder name of 300 bytes")
    assert list(tmp_path.iterdir()) == []  # nothing written, not even a lock file


def test_a_path_longer_than_the_system_allows_names_out():
    with pytest.raises(ExportError, match=r"--out: the path is \d+ bytes long"):
        check_out_path("/".join(["d" * 200] * 25))
    check_out_path("export/" + "n" * 200)  # a long name that fits


# --------------------------------------------------------------------------- the stages' messages


def test_a_wire_too_thick_names_sharp_corners_and_a_wire_gap_pair_that_fits():
    """The narrow space of test_root_fillet (closed on the axis by a 0.099 mm arc): the message
    offers corners = "sharp" and a wire radius with a spark gap; that pair then fits."""
    import re

    from profilegen.geometry.contour import Arc, Chain, Line
    from profilegen.errors import FilletError
    from profilegen.profile.rootfillet import filleted_cs_chain

    kw = {"tip_radius_mm": 50.07, "root_radius_mm": 51.03, "cs_teeth": 202}
    end = np.array([0.07, kw["root_radius_mm"] - 0.10])
    t = np.array([-1.0, 1.0]) / np.sqrt(2.0)
    bend = Arc(end + 0.5 * np.array([-t[1], t[0]]), 0.5, math.radians(45.0 - 39.3), math.radians(39.3))
    flank = Chain((Line(bend.start - 0.7 * bend.tangent(), bend.start), bend))
    with pytest.raises(FilletError) as err:
        filleted_cs_chain(flank, radius_mm=0.125 + 0.02, **kw)
    text = str(err.value)
    assert 'circular_spline.corners = "sharp"' in text and "\n" not in text
    wire, gap = map(float, re.search(r"wire_radius_mm = ([0-9.e-]+) with spark_gap_mm = ([0-9.e-]+)", text).groups())
    assert wire > 0 and gap > 0
    filleted_cs_chain(flank, radius_mm=wire + gap, **kw)  # the pair fits
    filleted_cs_chain(flank, corners="sharp", **kw)  # and so do sharp corners


def test_an_arc_fit_failure_names_the_fit_method_and_the_fields():
    from profilegen.profile.arcfit import OneSidedError, _offset

    q = np.array([0.0, 0.0, 0.0, 10.0, 0.1, -5.0])  # curvature 10 1/mm: an offset of 0.2 mm collapses it
    with pytest.raises(OneSidedError) as err:
        _offset(q, 0.2)
    assert "--fit least_squares" in str(err.value) and 'fit_method = "least_squares"' in str(err.value)
    assert "chord_tol_mm" in str(err.value) and "gear.module_mm" in str(err.value)


def test_a_point_repeated_exactly_is_taken_once_by_the_arc_fit():
    """tip_clearance_mm = 0 clipped the CS flank at a point it already had ('consecutive points 0
    and 1 coincide'): the fit of the flank with the point twice is the fit without it."""
    from profilegen.profile.arcfit import fit_profile

    s = np.linspace(0.0, 1.0, 60)
    pts = np.column_stack([0.3 * np.sin(2.0 * s), s + 0.05 * s**2])
    once = fit_profile(pts, method="least_squares", space_side="left")
    twice = fit_profile(np.vstack([pts[:1], pts]), method="least_squares", space_side="left")
    assert twice.max_error_mm == pytest.approx(once.max_error_mm, rel=1e-9, abs=1e-15)


@pytest.mark.xdist_group("test_step")  # the B-rep kernel is imported once per worker (6 s)
def test_a_step_outline_with_a_sliver_arc_makes_a_wire():
    """An arc of 1.1e-8 mm (a fitted arc a root fillet trimmed, z1 = 20) made 'element 1 of the
    chain (Arc) makes no edge'; the wire is now built across it."""
    from profilegen.geometry.contour import Arc, Chain, Line
    from profilegen.output import step

    if not step.available():
        pytest.skip("the STEP writer's B-rep kernel (OCP) is not installed")
    r = 1.0
    sliver = Arc(np.zeros(2), r, math.radians(90.0), 1.1e-8)  # from (0, 1) on, 1.1e-8 mm long
    a, b = sliver.end, np.array([-1.0, -1.0])
    chain = Chain((sliver, Line(a, b), Line(b, np.array([1.0, -1.0])), Line(np.array([1.0, -1.0]), sliver.start)))
    assert step._chain_wire(chain, 0.0, ccw=True) is not None


def test_a_point_list_csv_with_a_utf8_bom_is_read(tmp_path):
    y = np.linspace(-0.6, 0.4, 12)
    x = math.pi * 0.5 / 4 - y * math.tan(math.radians(10.0))
    rows = "x_mm,y_mm\n" + "\n".join(f"{a!r},{b!r}" for a, b in zip(x.tolist(), y.tolist())) + "\n"
    (tmp_path / "bom.csv").write_text(rows, encoding="utf-8-sig")  # as Excel saves it
    (tmp_path / "plain.csv").write_text(rows)
    base = load_gearset(default_gearset_path()).to_dict()
    sets = {}
    for name in ("bom", "plain"):
        data = {**base, "tooth": {"kind": "points", "points_file": f"{name}.csv"}}
        sets[name] = pg.parse_gearset(data, base_dir=tmp_path)
    np.testing.assert_array_equal(sets["bom"].tooth.points, sets["plain"].tooth.points)


def test_a_sweep_over_the_points_file_replaces_the_point_list(tmp_path):
    y = np.linspace(-0.6, 0.4, 12)
    for name, angle in (("a", 10.0), ("b", 12.0)):
        x = math.pi * 0.5 / 4 - y * math.tan(math.radians(angle))
        (tmp_path / f"{name}.csv").write_text(
            "x_mm,y_mm\n" + "\n".join(f"{u!r},{v!r}" for u, v in zip(x.tolist(), y.tolist())) + "\n")
    base = load_gearset(default_gearset_path()).to_dict()
    gs = pg.parse_gearset({**base, "tooth": {"kind": "points", "points_file": "a.csv"}}, base_dir=tmp_path)
    cwd = os.getcwd()
    os.chdir(tmp_path)  # the sweep's worker resolves the file as the spec's reader did
    try:
        other = gs.with_values({"tooth.points_file": "b.csv"})
    finally:
        os.chdir(cwd)
    slope = np.polyfit(other.tooth.points[:, 1], other.tooth.points[:, 0], 1)[0]
    assert slope == pytest.approx(-math.tan(math.radians(12.0)), rel=1e-9)


def test_a_scene_key_its_tier_ignores_is_a_warning_once(caplog):
    table = {k: v for k, v in dataclasses.asdict(SCENES["sketch"]).items() if k != "name" and v != ""}
    caplog.set_level(logging.WARNING, logger="profilegen.pipeline.scenes")
    for _ in range(3):  # a sweep reads its scene file once per point
        parse_scenes({"quick": {**table, "tier": "sketch", "face_slices": 33}}, origin="once.toml")
    lines = [r.getMessage() for r in caplog.records if "face_slices" in r.getMessage()]
    assert len(lines) == 1 and "face_slices = 33 is ignored by tier 'sketch'" in lines[0]
    assert 'tier = "cup3d"' in lines[0]


def test_a_spec_does_not_echo_the_gear_set_or_scene_file_it_names(tmp_path):
    from profilegen.errors import SweepSpecError
    from profilegen.studies.sweep import load_sweep_spec

    (tmp_path / "other.toml").write_text('name = "CANARY-NAME"\n[canary_table]\ncanary_key = 1\n')
    for key, value in (("gearset", "other.toml"), ("scene", "other.toml")):
        spec = tmp_path / f"{key}.toml"
        gearset = "default" if key == "scene" else value
        scene = value if key == "scene" else "sketch"
        spec.write_text(f'name = "s"\ndescription = "d"\ngearset = "{gearset}"\nscene = "{scene}"\n'
                        '[grid]\n"gear.module_mm" = [0.5]\n')
        with pytest.raises(SweepSpecError) as err:
            load_sweep_spec(spec)
        text = str(err.value)
        assert f"{key}: " in text and "other.toml" in text and "lists them" in text
        assert "canary" not in text.lower(), text


def test_library_warnings_are_one_line_and_q_silences_every_warning_line_in_workers_too(tmp_path):
    """A command that logs a warning in its process and in a forked worker and triggers a
    RuntimeWarning: with -q nothing reaches stderr; without, one line each."""
    script = textwrap.dedent("""
        import logging, os, sys, warnings
        from profilegen import cli

        def fake(args):
            logging.getLogger("profilegen.profile.rootfillet").warning("W-main")
            warnings.warn("divide by zero\\nencountered", RuntimeWarning)
            pid = os.fork()
            if pid == 0:
                logging.getLogger("profilegen.profile.rootfillet").warning("W-worker")
                os._exit(0)
            os.waitpid(pid, 0)
            return 0

        cli._cmd_design = fake
        sys.exit(cli.main(["design"] + sys.argv[1:]))
    """)
    (tmp_path / "run.py").write_text(script)
    quiet = subprocess.run([sys.executable, "run.py", "-q"], check=False, capture_output=True, text=True, cwd=tmp_path, timeout=60)
    assert quiet.returncode == 0 and quiet.stderr == ""
    loud = subprocess.run([sys.executable, "run.py"], check=False, capture_output=True, text=True, cwd=tmp_path, timeout=60)
    lines = loud.stderr.splitlines()
    assert "WARNING profilegen.profile.rootfillet: W-main" in lines and "WARNING profilegen.profile.rootfillet: W-worker" in lines
    (warning,) = [ln for ln in lines if "RuntimeWarning" in ln]
    assert warning.startswith("WARNING py.warnings: RuntimeWarning: divide by zero encountered (run.py:")
    assert len(lines) == 3


def test_scene_names_and_texts_and_grid_texts_have_length_limits(tmp_path):
    from profilegen.errors import SweepSpecError
    from profilegen.studies.sweep import load_sweep_spec

    table = {k: v for k, v in dataclasses.asdict(SCENES["sketch"]).items() if k != "name" and v != ""}
    with pytest.raises(SceneError, match=r"a scene name is letters, digits, '_' and '-', at most 64"):
        parse_scenes({"s" * 65: table})
    with pytest.raises(SceneError, match=r"description = 'ddd.*\.\.\.': must be at most 2000 characters, got 3000") as err:
        parse_scenes({"s": {**table, "description": "d" * 3000}})
    assert len(str(err.value)) < 300  # the text is not echoed whole
    spec = tmp_path / "long.toml"
    spec.write_text('name = "s"\ndescription = "d"\ngearset = "default"\nscene = "sketch"\n'
                    f'[grid]\n"description" = ["short", "{"x" * 5000}"]\n')
    with pytest.raises(SweepSpecError, match=r"grid\.description\[1\]: a text of 5000 characters: at most 4096") as err:
        load_sweep_spec(spec)
    assert len(str(err.value)) < 300
