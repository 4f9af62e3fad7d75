"""profilegen.studies.sweep: point generation, the spec's errors, the journal (resume, cut lines),
failed points, and the same table from a process pool and a Dask cluster."""

from __future__ import annotations

import csv
import json
import math
import sys
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from profilegen.cli import main
from profilegen.errors import GearSetError, SweepSpecError
from profilegen.pipeline.design import design
from profilegen.pipeline.scenes import SCENES
from profilegen.studies.sweep import (
    OUTPUT_COLUMNS,
    SweepError,
    grid_points,
    load_sweep_spec,
    outputs_of,
    parse_sweep_spec,
    point_id,
    run_sweep,
    sample_points,
    write_table,
)

FIELD = "wave_generator.deflection_coefficient"
# three sketch designs and one value out of range (a GearSetError for that point only)
SPEC = {"name": "t", "gearset": "default", "scene": "sketch", "grid": {FIELD: [0.8, -1.0, 0.9, 1.0]}}


_DESIGNS: dict = {}


def _design_once(gs, *, scene):
    """``design(gs, scene=scene)`` of this module's default-set points, computed once per (ω*,
    scene) here: the journal tests count and check the designer's calls and the rows, not the
    design, and ran the same sketch design up to three times (0.8: in both tests below; a
    resumed point again). The results are read only."""
    key = (gs.name, gs.wave_generator.deflection_coefficient, getattr(scene, "name", scene))
    if key not in _DESIGNS:
        _DESIGNS[key] = design(gs, scene=scene)
    return _DESIGNS[key]


def _without_times(rows):
    return [{k: v for k, v in r.items() if not k.startswith("time_")} for r in rows]


def _csv_without_times(path):
    with path.open(newline="") as f:
        return _without_times(list(csv.DictReader(f)))


# ----------------------------------------------------------------------------- points


def test_grid_is_the_full_product_in_order():
    pts = grid_points({"a": [1, 2], "b": [10, 20, 30], "c": ["x"]})
    assert len(pts) == 6
    assert pts[0] == {"a": 1, "b": 10, "c": "x"} and pts[1] == {"a": 1, "b": 20, "c": "x"}  # last field fastest
    assert pts[-1] == {"a": 2, "b": 30, "c": "x"}
    assert len({tuple(p.values()) for p in pts}) == 6


def test_latin_hypercube_hits_every_stratum_once_per_field():
    ranges = {"a": (0.8, 1.2), "b": (5.0, 15.0), "c": (-1.0, 0.0)}
    n = 11
    pts = sample_points(ranges, n, method="lhs", seed=3)
    assert len(pts) == n
    for f, (lo, hi) in ranges.items():
        strata = sorted(math.floor((p[f] - lo) / (hi - lo) * n) for p in pts)
        assert strata == list(range(n)), f
    assert sample_points(ranges, n, method="lhs", seed=3) == pts  # seeded: deterministic
    assert sample_points(ranges, n, method="lhs", seed=4) != pts


def test_random_sample_is_seeded_and_in_the_box_and_integer_ranges_give_integers():
    pts = sample_points({"a": (0.8, 1.2), "n": (3, 6)}, 200, method="random", seed=0)
    assert pts == sample_points({"a": (0.8, 1.2), "n": (3, 6)}, 200, method="random", seed=0)
    assert all(0.8 <= p["a"] < 1.2 for p in pts)
    assert {p["n"] for p in pts} == {3, 4, 5, 6} and all(isinstance(p["n"], int) for p in pts)


def test_point_id_is_stable_and_depends_on_values_and_scene():
    spec = parse_sweep_spec(SPEC)
    again = parse_sweep_spec(SPEC)
    assert spec.ids == again.ids and len(set(spec.ids)) == 4
    gs = spec.gearset
    assert point_id({FIELD: 0.8}, SCENES["sketch"], gs) == spec.ids[0]
    assert point_id({FIELD: 0.8}, SCENES["design"], gs) != spec.ids[0]
    assert point_id({FIELD: 0.81}, SCENES["sketch"], gs) != spec.ids[0]


# ----------------------------------------------------------------------------- the spec


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"grids": {FIELD: [1.0]}}, "grids"),  # unknown top-level key
        ({"grid": None}, "grid/sample"),  # neither grid nor sample (None drops the key)
        ({"sample": {"n": 3, FIELD: [0.8, 1.2]}}, "grid/sample"),  # both
        ({"grid": {FIELD: 0.9}}, f"grid.{FIELD}"),  # not a list
        ({"grid": {FIELD: []}}, f"grid.{FIELD}"),  # empty
        ({"grid": {"wave_generator.deflection_coef": [0.9]}}, "grid.wave_generator.deflection_coef"),  # no such field
        ({"grid": {"wavegen.deflection": [0.9]}}, "grid.wavegen.deflection"),  # no such section
        ({"grid": None, "sample": {"method": "sobol", "n": 4, FIELD: [0.8, 1.2]}}, "sample.method"),
        ({"grid": None, "sample": {"n": 0, FIELD: [0.8, 1.2]}}, "sample.n"),
        ({"grid": None, "sample": {FIELD: [0.8, 1.2]}}, "sample.n"),  # n missing
        ({"grid": None, "sample": {"n": 4, "seed": -1, FIELD: [0.8, 1.2]}}, "sample.seed"),
        ({"grid": None, "sample": {"n": 4, FIELD: [1.2, 0.8]}}, f"sample.{FIELD}"),  # lo ≥ hi
        ({"grid": None, "sample": {"n": 4}}, "sample"),  # no field
        ({"plot": "nonsense_mm"}, "plot"),
        ({"name": "a b/c"}, "name"),
        ({"name": ".."}, "name"),  # the parent of the sweeps folder: export/ itself
        ({"name": "."}, "name"),
        ({"name": "../x"}, "name"),
        ({"name": "a\\b"}, "name"),
        ({"name": "a\nb"}, "name"),  # a control character
        ({"name": "x" * 101}, "name"),  # longer than MAX_NAME_CHARS
        ({"name": ""}, "name"),
        ({"grid": {FIELD: [0.8, "x"]}}, f"grid.{FIELD}[1]"),  # a text for a number: the field and the index
        ({"grid": {FIELD: [0.8, 0.9, math.nan]}}, f"grid.{FIELD}[2]"),
        ({"grid": {FIELD: [math.inf]}}, f"grid.{FIELD}[0]"),
        ({"grid": {FIELD: [-math.inf, 0.8]}}, f"grid.{FIELD}[0]"),
        ({"grid": {FIELD: [0.8, True]}}, f"grid.{FIELD}[1]"),  # a boolean is not a number
        ({"grid": {FIELD: [0.8, [0.9]]}}, f"grid.{FIELD}[1]"),  # an array in the array
        ({"grid": {"gear.flexspline_teeth": [200, 180, 190.5]}}, "grid.gear.flexspline_teeth[2]"),  # not an integer
        ({"grid": {"wave_generator.contour": ["elliptical_cam", 2]}}, "grid.wave_generator.contour[1]"),
        ({"grid": None, "sample": {"n": 4, "gear.flexspline_teeth": [180.0, 220.0]}}, "sample.gear.flexspline_teeth"),
        ({"scene": "draft"}, "scene"),
        ({"gearset": "no_such_set"}, "gearset"),
    ],
)
def test_bad_spec_names_the_key(change, key):
    data = {**SPEC, **change}
    data = {k: v for k, v in data.items() if v is not None}
    with pytest.raises(SweepSpecError) as err:
        parse_sweep_spec(data, origin="spec.toml")
    assert isinstance(err.value, ValueError)
    assert str(err.value).startswith(f"spec.toml: {key}:"), str(err.value)


def test_values_of_the_right_type_out_of_range_are_points_not_spec_errors():
    """-1.0 and 0 are numbers (the gear set rejects them per point: rows with status error);
    an integer for a float field is a number; a name with dots inside is a folder name."""
    spec = parse_sweep_spec({**SPEC, "name": "a.b..c", "grid": {FIELD: [-1.0, 0, 1]}})
    assert spec.name == "a.b..c" and spec.points == ({FIELD: -1.0}, {FIELD: 0}, {FIELD: 1})
    spec = parse_sweep_spec({**SPEC, "grid": {"gear.flexspline_teeth": [200, -3]}})
    assert len(spec.points) == 2


def test_spec_name_cannot_leave_the_sweeps_folder(tmp_path, capsys, monkeypatch):
    """A spec named '..' at the command line: one line naming the key, exit 2, nothing written."""
    spec = tmp_path / "up.toml"
    spec.write_text('name = ".."\ngearset = "default"\n[grid]\n"wave_generator.deflection_coefficient" = [0.9]\n')
    (tmp_path / "work").mkdir()
    monkeypatch.chdir(tmp_path / "work")  # the default output folder is export/sweeps/<name>/ under it
    assert main(["sweep", str(spec)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and ": name:" in err[0]
    assert list((tmp_path / "work").iterdir()) == []


def test_nested_and_quoted_field_names_are_the_same_field(tmp_path):
    quoted = tmp_path / "q.toml"
    quoted.write_text('gearset = "default"\n[grid]\n"wave_generator.deflection_coefficient" = [0.8, 0.9]\n')
    nested = tmp_path / "n.toml"
    nested.write_text('gearset = "default"\n[grid]\nwave_generator.deflection_coefficient = [0.8, 0.9]\n')
    a, b = load_sweep_spec(quoted), load_sweep_spec(nested)
    assert a.fields == b.fields == (FIELD,) and a.ids == b.ids
    assert a.name == "q" and a.scene.name == "sketch"  # defaults: the file's stem, the sketch scene


def test_bad_spec_at_the_command_line_is_one_line_and_exit_2(tmp_path, capsys):
    spec = tmp_path / "bad.toml"
    spec.write_text('gearset = "default"\n[sample]\nmethod = "lhs"\nn = -3\n"gear.rim_thickness_mm" = [0.8, 1.0]\n')
    assert main(["sweep", str(spec), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "sample.n" in err[0] and str(spec) in err[0]
    assert not (tmp_path / "o").exists()


def test_the_shipped_example_spec_is_valid():
    from pathlib import Path

    spec = load_sweep_spec(Path(__file__).resolve().parents[2] / "profiles" / "sweeps" / "deflection.toml")
    assert spec.kind == "grid" and spec.fields == (FIELD,) and len(spec.points) >= 5


# ----------------------------------------------------------------------------- running


def test_outputs_are_tolerant_of_missing_parts():
    out = outputs_of(object())  # no envelope, no profile, no contact, no stress
    assert set(out) == set(OUTPUT_COLUMNS) and all(v is None for v in out.values())


@pytest.mark.xdist_group("test_sweep_designs")  # one worker: _design_once's designs are its process's
def test_sweep_resumes_without_recomputing_finished_points(tmp_path):
    """Interrupted after 2 of 4 points (KeyboardInterrupt from the progress callback), a rerun
    computes only the other 2; a line cut short by a kill is dropped and recomputed."""
    spec = parse_sweep_spec({**SPEC, "grid": {FIELD: [0.8, 0.85, 0.9, 0.95]}})
    out = tmp_path / "s"
    calls: list[list] = [[], [], []]
    lock = threading.Lock()

    def counting(run):
        def designer(gs, *, scene):
            with lock:
                calls[run].append(gs.wave_generator.deflection_coefficient)
            return _design_once(gs, scene=scene)

        return designer

    def interrupt_after_two(done, total):
        if done >= 2:
            raise KeyboardInterrupt

    with ThreadPoolExecutor(max_workers=1) as ex:
        with pytest.raises(KeyboardInterrupt):
            run_sweep(spec, out, executor=ex, designer=counting(0), progress=interrupt_after_two, figure=False)
    journal = (out / "journal.csv").read_text().splitlines()
    assert len(journal) == 1 + 2 and not (out / "results.csv").exists()
    with ThreadPoolExecutor(max_workers=1) as ex:
        res = run_sweep(spec, out, executor=ex, designer=counting(1), figure=False)
    assert len(calls[1]) == 2 and set(calls[1]).isdisjoint(float(line.split(",")[1]) for line in journal[1:])
    assert res.computed == 2 and res.reused == 2 and res.ok == 4
    assert (out / "journal.csv").read_text().splitlines()[:3] == journal  # finished lines are not rewritten
    # a kill in the middle of a write leaves a cut line: it is dropped, and that point runs again
    lines = (out / "journal.csv").read_text().splitlines(keepends=True)
    (out / "journal.csv").write_text("".join(lines[:-1]) + lines[-1][:40])
    with ThreadPoolExecutor(max_workers=1) as ex:
        again = run_sweep(spec, out, executor=ex, designer=counting(2), figure=False)
    assert len(calls[2]) == 1 and again.reused == 3 and again.computed == 1
    assert _without_times(again.rows) == _without_times(res.rows)
    assert (out / "journal.csv").read_text().endswith("\n")


def _asleep_at_095(gs, *, scene):
    """A designer whose point ω* = 0.95 does not finish (ten minutes)."""
    import time

    if gs.wave_generator.deflection_coefficient == 0.95:
        time.sleep(600)
    return design(gs, scene=scene)


@pytest.mark.skipif(sys.platform != "linux", reason="fork: the workers find the test's designer")
def test_an_interrupted_sweep_ends_its_own_workers_at_once(tmp_path):
    """KeyboardInterrupt while a worker is in a point that does not finish: run_sweep ends its
    pool's workers (not waiting for the point), re-raises, and the journal keeps the point done."""
    psutil = pytest.importorskip("psutil")
    spec = parse_sweep_spec({**SPEC, "grid": {FIELD: [0.95, 0.8, 0.9]}})

    def interrupt_after_one(done, total):
        if done >= 1:
            raise KeyboardInterrupt

    before = {c.pid for c in psutil.Process().children(recursive=True)}
    with pytest.raises(KeyboardInterrupt):
        run_sweep(spec, tmp_path / "s", workers=2, designer=_asleep_at_095, progress=interrupt_after_one,
                  figure=False)
    left = [c for c in psutil.Process().children(recursive=True) if c.pid not in before and c.status() != "zombie"]
    assert left == []
    lines = (tmp_path / "s" / "journal.csv").read_text().splitlines()
    assert len(lines) == 2 and lines[1].split(",")[1] in ("0.8", "0.9")


def test_parquet_without_pyarrow_is_a_clear_error(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow → ImportError
    spec = parse_sweep_spec(SPEC)
    with pytest.raises(SweepError, match="pyarrow"):
        run_sweep(spec, tmp_path / "s", table=tmp_path / "t.parquet", executor=ThreadPoolExecutor(1))
    assert not (tmp_path / "s").exists()


def test_parquet_table_round_trips(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    rows = [{"index": 0, "x": 0.5, "status": "ok"}, {"index": 1, "x": None, "status": "error"}]
    write_table(rows, ["index", "x", "status"], tmp_path / "t.parquet")
    assert pq.read_table(tmp_path / "t.parquet").to_pylist() == rows


def test_process_pool_and_dask_cluster_give_the_same_table_and_a_failed_point_is_recorded(tmp_path):
    distributed = pytest.importorskip("distributed")
    spec = parse_sweep_spec(SPEC)
    pool = run_sweep(spec, tmp_path / "pool", workers=2)
    assert [r["status"] for r in pool.rows] == ["ok", "error", "ok", "ok"]
    bad = pool.rows[1]
    assert bad["error_type"] == "GearSetError" and FIELD in bad["error_message"]
    assert all(bad[c] is None for c in OUTPUT_COLUMNS if c != "time_design_s")
    ok = pool.rows[0]
    assert ok[FIELD] == 0.8 and ok["deflection_mm"] == pytest.approx(0.4)
    assert ok["min_clearance_mm"] > -1e-4 and ok["cs_root_radius_mm"] > ok["cs_tip_radius_mm"]
    assert ok["contact_rotation_arcmin"] is None  # the sketch scene has no loaded contact: an empty cell
    assert {p.name for p in pool.files} == {"results.csv", "sweep.png"}
    assert (tmp_path / "pool" / "sweep.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        dask = run_sweep(spec, tmp_path / "dask", executor=client.get_executor(), figure=False)
    assert dask.computed == 4 and dask.reused == 0
    assert _without_times(dask.rows) == _without_times(pool.rows)
    assert _csv_without_times(tmp_path / "dask" / "results.csv") == _csv_without_times(tmp_path / "pool" / "results.csv")
    # run again: everything comes from the journal, nothing is recomputed
    again = run_sweep(spec, tmp_path / "pool", workers=2, figure=False)
    assert again.computed == 0 and again.reused == 4 and again.rows == pool.rows


def test_sweep_command_writes_the_table(tmp_path, capsys):
    spec = tmp_path / "two.toml"
    spec.write_text('name = "two"\ngearset = "default"\nscene = "sketch"\nplot = "min_clearance_mm"\n'
                    '[grid]\n"wave_generator.deflection_coefficient" = [0.9, 3.5]\n')
    out = tmp_path / "o"
    assert main(["sweep", str(spec), "--workers", "1", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "1 ok, 1 failed" in text and "results.csv" in text
    with (out / "results.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["status"] for r in rows] == ["ok", "error"] and rows[1]["error_type"] == "GearSetError"
    assert np.isfinite(float(rows[0]["min_clearance_mm"])) and rows[0]["contact_rotation_arcmin"] == ""
    assert sorted(p.name for p in out.iterdir()) == [".profilegen.json", "journal.csv", "results.csv", "sweep.png"]
    assert json.loads((out / ".profilegen.json").read_text())["files"] == sorted(p.name for p in out.iterdir())


@pytest.mark.xdist_group("test_sweep_designs")  # one worker: _design_once's designs are its process's
def test_a_design_that_raises_is_recorded_with_its_type(tmp_path):
    spec = parse_sweep_spec({**SPEC, "grid": {FIELD: [0.8, 0.9]}})

    def flaky(gs, *, scene):
        if gs.wave_generator.deflection_coefficient > 0.85:
            raise GearSetError("tooth.addendum_mm = 9 mm: must be in (0, 2]")
        return _design_once(gs, scene=scene)

    with ThreadPoolExecutor(max_workers=2) as ex:
        res = run_sweep(spec, tmp_path / "s", executor=ex, designer=flaky, figure=False)
    assert [r["status"] for r in res.rows] == ["ok", "error"]
    assert res.rows[1]["error_type"] == "GearSetError" and "tooth.addendum_mm" in res.rows[1]["error_message"]


def test_a_workers_stage_warning_is_the_points_not_an_unnamed_line():
    """In a study's worker a stage's logged warning (kept in the point's design warnings and the
    table's `warnings` column) printed through the command line's handler, which a forked worker
    inherits, as a line naming no point (136 of them in one optimisation); an error still prints."""
    import subprocess
    import sys

    code = ("import logging; logging.basicConfig(level=logging.WARNING); "  # the CLI's, inherited by a forked worker
            "from profilegen.studies.sweep import init_worker; init_worker(); "
            "logging.getLogger('profilegen.profile.rootfillet').warning('kept sharp'); "
            "logging.getLogger('profilegen.profile.rootfillet').error('broken')")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert "kept sharp" not in res.stderr and "broken" in res.stderr
