"""The package passes its linter (ruff, with the rules pyproject.toml selects: pyflakes, syntax and
statement errors, bugbear's likely bugs) — an unused import, an undefined name or a closure over a
loop variable fails the suite, not a later reader."""

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_the_package_passes_ruff():
    ruff = shutil.which("ruff")
    if ruff is None:
        pytest.skip("ruff is not installed (the test extras install it)")
    res = subprocess.run([ruff, "check", "--no-cache", "--output-format", "concise", "profilegen"], cwd=ROOT,
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stdout + res.stderr
