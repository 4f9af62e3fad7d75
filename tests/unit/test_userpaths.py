"""profilegen.output.userpaths.check_out_path against its limits (escapes of tests/benchmarks/mutants.py):
the output folder's own name leaves room for the staging folder's ``.NAME.staging-xxxxxxxx`` beside
it (255 bytes less 18), a folder above it does not need that room, and the path's length is counted
made absolute (a relative --out inside a deep working folder)."""

from __future__ import annotations

import pytest

from profilegen.errors import ExportError
from profilegen.output.userpaths import BESIDE, INSIDE, NAME_MAX, PATH_MAX, check_out_path


def test_the_last_name_leaves_room_for_the_staging_folder():
    assert BESIDE == len(".") + len(".staging-") + 8 == 18  # the staging name's additions, by its pattern
    check_out_path("x" * (NAME_MAX - BESIDE))
    with pytest.raises(ExportError, match=rf"--out: a folder name of {NAME_MAX - BESIDE + 1} bytes .*at most "
                                          rf"{NAME_MAX - BESIDE} "):
        check_out_path("x" * (NAME_MAX - BESIDE + 1))
    check_out_path("y" * NAME_MAX + "/out")  # a folder above the output needs no staging room
    with pytest.raises(ExportError, match="--out: a folder name of 256 bytes"):
        check_out_path("y" * (NAME_MAX + 1) + "/out")


def test_the_path_length_is_counted_made_absolute(tmp_path, monkeypatch):
    deep = tmp_path
    while len(str(deep)) < 3700:
        deep = deep / ("d" * 200)
    deep = deep / ("e" * (3950 - len(str(deep)) - 1))  # a working folder 3950 bytes deep (< PATH_MAX)
    deep.mkdir(parents=True)
    monkeypatch.chdir(deep)
    short = "o" * 120  # 120 bytes as given, over the limit once made absolute
    assert len(short) + INSIDE <= PATH_MAX < len(str(deep / short)) + INSIDE
    with pytest.raises(ExportError, match=r"--out: the path is \d+ bytes long \(made absolute\)"):
        check_out_path(short)
