"""Bad inputs of every kind end in a named error (issue 13, "bad input never hurts the machine").

A fast, in-process subset of ``tests/benchmarks/bad_inputs.py`` (which runs ~130 cases through the CLI
in subprocesses with memory and time limits): each test asserts the exception type, the field or file
named in the message, and that no content of a file that is not a gear set is echoed (``CANARY``).
"""

from __future__ import annotations

import math
import os
import sys

import numpy as np
import pytest

from profilegen.cli import main
from profilegen.errors import GearSetError, RimSolverError
from profilegen.gearset import (
    MAX_POINTS,
    default_gearset_path,
    load_gearset,
    parse_gearset,
    read_toml,
)
from profilegen.pipeline.scenes import SceneError, resolve_scene
from profilegen.geometry.wavegen import WaveGenError

CANARY = "CANARY-7f3a9c-root:$6$s3cr3t"
SECRET = f"root:x:0:0:{CANARY}:/root:/bin/bash\ndaemon:x:1:1::/usr/sbin:/usr/sbin/nologin\n"
DEFAULT = default_gearset_path().read_text()


def load_error(path, kind=GearSetError) -> str:
    with pytest.raises(kind) as info:
        load_gearset(path)
    message = str(info.value)
    assert CANARY not in message and "s3cr3t" not in message
    assert "\n" not in message  # one line
    return message


def points_set(tmp_path, **tooth) -> os.PathLike:
    text = DEFAULT.split("[tooth]")[0] + "[tooth]\nkind = \"points\"\n"
    text += "".join(f"{k} = {v}\n" for k, v in tooth.items())
    text += "[wave_generator]" + DEFAULT.split("[wave_generator]")[1]
    path = tmp_path / "set.toml"
    path.write_text(text)
    return path


def flank(n: int = 12) -> np.ndarray:
    y = np.linspace(-0.6, 0.4, n)
    return np.column_stack([math.pi * 0.5 / 4 - y * math.tan(math.radians(10.0)), y])


# --------------------------------------------------------------------------- files


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")
def test_dev_zero_as_gear_set_is_refused_unread():
    message = load_error("/dev/zero")
    assert message.startswith("/dev/zero: is a device, not a regular file")


def test_fifo_as_gear_set_neither_hangs_nor_reads(tmp_path):
    fifo = tmp_path / "set.toml"
    os.mkfifo(fifo)  # no writer: a blocking open would hang here
    assert "is a FIFO" in load_error(fifo)


def test_folder_as_gear_set(tmp_path):
    (tmp_path / "set.toml").mkdir()
    assert "is a folder" in load_error(tmp_path / "set.toml")


def test_oversized_toml_is_refused_before_parsing(tmp_path):
    path = tmp_path / "set.toml"
    path.write_text(DEFAULT + ("# " + CANARY + "\n") * 150_000)  # > 4 MiB of comments
    assert "too large for a gear-set file (at most 4194304 bytes)" in load_error(path)
    with pytest.raises(GearSetError, match="at most 1000 bytes"):
        read_toml(default_gearset_path(), GearSetError, "gear-set file", limit=1000)


@pytest.mark.parametrize("content,expect", [
    (b'name = "\xff\xfe' + CANARY.encode() + b'"\n', "line 1: not UTF-8 text"),
    (f'"{CANARY}" = 1\n"{CANARY}" = 2\n'.encode(), "line 2, column 35: Cannot overwrite a value"),
    (f"name = {CANARY}\n".encode(), "malformed TOML at line 1"),
    (SECRET.encode(), "malformed TOML at line 1"),
    (b"a = " + b"[" * 50_000 + b"]" * 50_000 + b"\n", "malformed TOML"),
], ids=["not-utf8", "declared-twice", "invalid-value", "passwd-like", "nested-deeply"])
def test_malformed_files_name_file_and_line_not_content(tmp_path, content, expect):
    path = tmp_path / "set.toml"
    path.write_bytes(content)
    message = load_error(path)
    assert message.startswith(f"{path}: ") and expect in message


def test_integers_too_long_for_python_or_the_message(tmp_path):
    path = tmp_path / "set.toml"
    path.write_text(DEFAULT.replace("flexspline_teeth = 200", "flexspline_teeth = " + "2" * 5000))
    assert load_error(path).endswith("malformed TOML: a value TOML cannot hold (an integer too long?)")
    path.write_text(DEFAULT.replace("flexspline_teeth = 200", "flexspline_teeth = " + "2" * 4000))
    message = load_error(path)
    assert "gear.flexspline_teeth = 222222222222... (4000 digits): must be in [20, 2000]" in message
    assert len(message) < 300


def test_cli_names_a_fifo_given_by_bare_name(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    os.mkfifo("fifo")
    assert main(["check", "fifo"]) == 2
    assert capsys.readouterr().err.strip() == "fifo: is a FIFO, not a regular file; a gear-set file must be a regular file"


# --------------------------------------------------------------------------- point lists


def test_points_file_that_is_not_a_point_list_is_not_echoed(tmp_path):
    (tmp_path / "passwd").write_text(SECRET)
    message = load_error(points_set(tmp_path, points_file='"passwd"'))
    assert 'tooth.points_file = "passwd"' in message and "line 1" in message and "x_mm and y_mm" in message


def test_points_file_bad_row_names_its_line_only(tmp_path):
    rows = "".join(f"{float(x)!r},{float(y)!r}\n" for x, y in flank())
    (tmp_path / "p.csv").write_text(f"x_mm,y_mm\n{rows}0.3,{CANARY}\n")
    message = load_error(points_set(tmp_path, points_file='"p.csv"'))
    assert "line 14: column y_mm is not a number" in message


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")
def test_points_file_dev_zero(tmp_path):
    message = load_error(points_set(tmp_path, points_file='"/dev/zero"'))
    assert 'tooth.points_file = "/dev/zero"' in message and "is a device" in message


def test_too_many_points(tmp_path):
    rows = "".join(f"{0.39 - 1e-5 * i!r},{-0.6 + 5e-5 * i!r}\n" for i in range(MAX_POINTS + 1))
    (tmp_path / "p.csv").write_text("x_mm,y_mm\n" + rows)
    assert f"at most {MAX_POINTS} points" in load_error(points_set(tmp_path, points_file='"p.csv"'))
    data = load_gearset(default_gearset_path()).to_dict()
    data["tooth"] = {"kind": "points", "points": np.repeat(flank(), 1000, axis=0).tolist()}
    with pytest.raises(GearSetError, match=rf"tooth\.points: at most {MAX_POINTS}"):
        parse_gearset(data)


# --------------------------------------------------------------------------- fields


@pytest.mark.parametrize("value,expect", [
    ("a" * 5000, "must be at most 100 characters, got 5000"),
    ("../etc", "must match"),
    ("a\nb", "must match"),
], ids=["long", "path", "newline"])
def test_name_is_a_safe_folder_name(value, expect):
    data = load_gearset(default_gearset_path()).to_dict()
    data["name"] = value
    with pytest.raises(GearSetError) as info:
        parse_gearset(data)
    (line,) = info.value.problems
    assert line.startswith("name = ") and expect in line and len(line) < 200


def test_description_without_control_characters():
    data = load_gearset(default_gearset_path()).to_dict()
    data["description"] = "two\nlines"
    with pytest.raises(GearSetError, match="description = .*control characters"):
        parse_gearset(data)


def test_module_10_copy_of_the_default_set_names_the_rim():
    # issue 13: passed check, then failed inside the rim FEM naming no input
    with pytest.raises(GearSetError) as info:
        load_gearset(default_gearset_path()).with_values({"gear.module_mm": 10.0})
    (line,) = info.value.problems
    assert line.startswith("gear.rim_thickness_mm = 0.9 mm: must be >= 5 mm")


def test_rollers_that_design_refuses_are_refused_when_loading():
    gs = load_gearset(default_gearset_path())
    with pytest.raises(GearSetError) as info:
        gs.with_values({"wave_generator.contour": "rollers", "wave_generator.roller_count": 4,
                        "wave_generator.roller_radius_mm": 20.0})
    assert isinstance(info.value, WaveGenError)
    assert str(info.value).startswith("wave_generator.roller_radius_mm = 20 mm: must be ≤ 16.0859 mm")


@pytest.mark.parametrize("failure", ["convergence", "linalg"])
def test_rim_solver_failure_becomes_a_named_error(monkeypatch, failure):
    from profilegen.errors import ConvergenceError
    from profilegen.rim import stage

    def fail(*args, **kwargs):
        if failure == "linalg":
            raise np.linalg.LinAlgError("23-th leading minor of the array is not positive definite")
        raise ConvergenceError("solve_ring: contact problem not solvable at iteration 1")

    monkeypatch.setattr(stage, "_solve", fail)
    gs = load_gearset(default_gearset_path())
    with pytest.raises(RimSolverError) as info:
        stage.solve_rim(gs, tier="design")
    message = str(info.value)
    assert isinstance(info.value, ConvergenceError) and isinstance(info.value, RuntimeError)
    assert "leading minor" in message or "not solvable" in message  # what the solver said
    for name in ("gear.rim_thickness_mm = 0.9 mm (δ/w0 = 1.8)", "wave_generator.deflection_coefficient = 1",
                 "gear.module_mm = 0.5 mm"):
        assert name in message


@pytest.mark.slow
def test_rim_fem_failure_names_the_inputs():
    # valid (δ = 0.5·w0) but a thin rim for a large deflection on few teeth: the nonlinear ring's
    # tangent loses positive definiteness (measured); the error names the fields that decide it
    from profilegen.rim.stage import solve_rim

    gs = load_gearset(default_gearset_path()).with_values(
        {"gear.module_mm": 1.0, "gear.flexspline_teeth": 60, "gear.circular_spline_teeth": 62,
         "gear.rim_thickness_mm": 0.95, "wave_generator.deflection_coefficient": 1.9})
    with pytest.raises(RimSolverError) as info:
        solve_rim(gs, tier="design")
    message = str(info.value)
    assert isinstance(info.value, RuntimeError)
    for name in ("gear.rim_thickness_mm = 0.95 mm", "wave_generator.deflection_coefficient = 1.9",
                 "gear.module_mm = 1 mm", "δ/w0 = 0.5"):
        assert name in message


# --------------------------------------------------------------------------- scenes and the CLI


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")
def test_scene_dev_zero_and_unknown_name():
    with pytest.raises(SceneError, match="^/dev/zero: is a device"):
        resolve_scene("/dev/zero")
    with pytest.raises(SceneError, match="scene = 'fast': must be one of sketch, design, verify"):
        resolve_scene("fast")


def test_check_names_the_file_once_per_line(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(DEFAULT.replace("module_mm = 0.5", "module_mm = -0.5")
                    .replace("addendum_coefficient = 0.8", "addendum_coefficient = 2.8"))
    assert main(["check", str(path)]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert lines and all(line.startswith(f"{path}: ") and line.count(str(path)) == 1 for line in lines)
    # a tooth that cannot be built (tooth stage) is named with the path too
    path.write_text(DEFAULT.replace("addendum_coefficient = 0.8", "addendum_coefficient = 2.8"))
    assert main(["check", str(path)]) == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert line.startswith(f"{path}: tooth.") and line.count(str(path)) == 1


def test_check_notes_torques_that_do_not_fit_the_size(tmp_path, capsys):
    path = tmp_path / "big.toml"
    path.write_text(DEFAULT.replace("module_mm = 0.5", "module_mm = 2.0")
                    .replace("rim_thickness_mm = 0.9", "rim_thickness_mm = 3.6"))
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert f"{path}: ok" in out and "note: torque.rated_nm = 265 N·m is far below" in out


if sys.platform == "win32":  # pragma: no cover
    pytest.skip("POSIX files (FIFO, /dev/zero)", allow_module_level=True)
