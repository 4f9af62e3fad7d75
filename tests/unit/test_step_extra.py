"""STEP is an optional extra (``pip install 'profilegen[step]'``, OpenCASCADE, ~380 MB): without
it, ``--step`` is one line naming the extra, before any stage runs, and nothing is written."""

import importlib.util

import pytest

from profilegen import cli
from profilegen.errors import ExportError
from profilegen.output import step


@pytest.fixture
def no_kernel(monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "OCP" else real(name, *a))
    step._occ.cache_clear()
    yield
    step._occ.cache_clear()


def test_design_step_without_the_kernel_is_one_line_naming_the_extra(no_kernel, tmp_path, capsys, monkeypatch):
    import profilegen.pipeline.design as pipeline

    def no_stage(*a, **k):  # the refusal comes before the stages: a stage run is a failure here
        raise AssertionError("a stage ran")

    monkeypatch.setattr(pipeline, "design", no_stage)
    out = tmp_path / "run"
    assert cli.main(["design", "--scene", "sketch", "--step", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "profilegen[step]" in err[0] and "pip install" in err[0]
    assert not out.exists()


def test_writing_step_without_the_kernel_raises_the_named_error(no_kernel):
    assert not step.available()
    with pytest.raises(ExportError, match=r"profilegen\[step\]"):
        step._occ()


def test_the_test_extras_install_the_kernel():
    """``pip install -e '.[test]'`` (the README's test command) brings the ``step`` extra, so the
    STEP tests run rather than skip."""
    assert step.available()
