"""The files a figure worker makes are the files made here, and the staging folder's deferred sync
(issue 14, item 2: the sketch scene end to end).

write_design hands the drawing, the flexspline's DXFs and the assembly to a worker process
(output.files.file_jobs) and fsyncs the staging folder's files together at the end
(output.export.deferred_sync). No timings here (tests/benchmarks/end_to_end.py): these check
that the bytes do not depend on where a file is made, and that every file written in a deferred
block is synced once the block ends — and not when it fails.
"""

from __future__ import annotations

import os

import pytest

import profilegen as pg
from profilegen.gearset import default_gearset_path, load_gearset
from profilegen.output import export, files, report


@pytest.fixture(scope="module")
def sketch():
    return pg.design(load_gearset(default_gearset_path()), scene="sketch")


def test_worker_files_are_the_files_written_here(sketch, tmp_path):
    here = tmp_path / "here"
    files.write_design(sketch, here, figure=False)  # no workers: every file written in this process
    jobs = files.file_jobs(sketch)
    assert set(jobs) == set(files.WORKER_FILES)
    with report.FigureWorkers(1, matplotlib=False) as workers:  # pickled to another process and back
        assert workers.workers == 1
        made = workers.collect(jobs)
    for job, names in files.WORKER_FILES.items():
        assert set(made[job]) == set(names)
        for name in names:
            assert made[job][name] == (here / name).read_bytes(), name
    # and called here, as collect() does for a job no worker took: inside write_design's deferred sync
    with export.deferred_sync():
        for job, (func, args) in jobs.items():
            assert func(*args) == made[job]


def test_bad_source_date_epoch_leaves_the_files_here(sketch, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "yesterday")
    assert files.file_jobs(sketch) == {}  # write_design then writes them here and raises as before
    with pytest.raises(ValueError, match="SOURCE_DATE_EPOCH"):
        from profilegen.output.drawing import cs_drawing_dxf

        cs_drawing_dxf(sketch)


def test_svg_colours_are_ezdxfs():
    import ezdxf.colors

    from profilegen.output import cad

    for aci, hex_rgb in cad._ACI_RGB.items():
        assert hex_rgb == "#%02x%02x%02x" % ezdxf.colors.aci2rgb(aci)
    assert cad._svg_colour(2) == "#%02x%02x%02x" % ezdxf.colors.aci2rgb(2)  # others: ezdxf's table


def test_deferred_sync_syncs_every_file_when_the_block_ends(tmp_path, monkeypatch):
    synced = []
    real = os.fsync
    monkeypatch.setattr(os, "fsync", lambda fd: (synced.append(os.readlink(f"/proc/self/fd/{fd}")), real(fd))[1])
    with export.deferred_sync():
        for k in range(5):
            with export.atomic_write(tmp_path / f"f{k}.txt") as f:
                f.write(str(k))
        with export.deferred_sync():  # nested: synced by the outer block
            with export.atomic_write(tmp_path / "inner.txt") as f:
                f.write("inner")
        assert synced == []  # in place, not yet synced
        assert (tmp_path / "f3.txt").read_text() == "3"
    names = {os.path.basename(p) for p in synced}
    assert {f"f{k}.txt" for k in range(5)} | {"inner.txt"} <= names
    assert str(tmp_path) in synced  # the folder, for the renames
    synced.clear()
    with export.atomic_write(tmp_path / "plain.txt") as f:  # outside a block: synced at once, as before
        f.write("x")
    assert any(p.endswith(".tmp") for p in synced)


def test_a_failed_block_syncs_nothing(tmp_path, monkeypatch):
    synced = []
    monkeypatch.setattr(os, "fsync", lambda fd: synced.append(fd))
    with pytest.raises(RuntimeError, match="stop"):
        with export.deferred_sync():
            with export.atomic_write(tmp_path / "a.txt") as f:
                f.write("a")
            raise RuntimeError("stop")
    assert synced == []
    with export.atomic_write(tmp_path / "b.txt") as f:  # the thread is out of the deferred mode again
        f.write("b")
    assert len(synced) == 2  # the file and its folder


def test_a_block_without_sync_syncs_nothing_also_inside_another(tmp_path, monkeypatch):
    synced = []
    monkeypatch.setattr(os, "fsync", lambda fd: synced.append(fd))
    with export.deferred_sync():
        with export.deferred_sync(sync=False):
            with export.atomic_write(tmp_path / "gone.txt") as f:
                f.write("temporary")
            (tmp_path / "gone.txt").unlink()  # a temporary folder's file, removed in the block
        with export.atomic_write(tmp_path / "kept.txt") as f:
            f.write("kept")
    assert len(synced) == 2  # kept.txt and its folder; gone.txt not looked for
