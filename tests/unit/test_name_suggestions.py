"""A misspelt bundled gear-set name, scene or rim tier: the same one-line error as before, ending
with the closest valid names (issue 30: load_gearset takes bundled names like the CLI)."""

import subprocess
import sys

import pytest

import profilegen as pg
from profilegen.errors import GearSetError, did_you_mean
from profilegen.gearset import list_profiles
from profilegen.pipeline.scenes import SceneError, resolve_scene, with_rim_tier


def test_the_suggestion_names_the_closest_choices_and_only_close_ones():
    assert did_you_mean("defualt", ["default", "seed000_csf40"]) == "; did you mean 'default'?"
    assert did_you_mean("zzzz", ["default", "design"]) == ""  # nothing close: no guess


def test_a_misspelt_bundled_name_suggests_the_bundled_set():
    names = {p.stem for p in list_profiles()}
    assert "default" in names and "csf32_100" in names
    with pytest.raises(GearSetError, match=r"gear set 'defualt': no such profile .*; did you mean 'default'\?$"):
        pg.load_gearset("defualt")
    with pytest.raises(GearSetError, match=r"did you mean 'csf32_100'\?$"):
        pg.load_gearset("csf32_10")


def test_a_misspelt_scene_and_rim_tier_suggest_theirs():
    with pytest.raises(SceneError, match=r"scene = 'verfy': must be one of .*; did you mean 'verify'\?$"):
        resolve_scene("verfy")
    sketch = resolve_scene("sketch")
    with pytest.raises(SceneError, match=r"rim tier = 'cup3': .*; did you mean 'cup3d'\?$"):
        with_rim_tier(sketch, "cup3")


def test_the_cli_says_it_in_one_line_with_exit_2(tmp_path):
    res = subprocess.run([sys.executable, "-m", "profilegen", "design", "defualt", "--scene", "sketch",
                          "--out", str(tmp_path / "out")], capture_output=True, text=True, timeout=120)
    assert res.returncode == 2
    (line,) = res.stderr.splitlines()
    assert line.endswith("did you mean 'default'?") and not (tmp_path / "out").exists()
