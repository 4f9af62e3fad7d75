"""Inputs the command-line fuzz (tests/benchmarks/fuzz.py --cli) found ending in a traceback, each
now a named error: the clean outcome the fuzz asks for (an error of the package's own type whose
message names the field)."""

from __future__ import annotations

import pytest

import profilegen as pg
from profilegen.gearset import resolve_gearset
from profilegen.sweep import parse_sweep_spec


@pytest.mark.parametrize("text", ["x" * 300, "x" * 251, "folder/" + "x" * 300 + ".toml"])
def test_a_gear_set_name_too_long_for_a_file_name_is_not_found_by_name(text):
    # a bare name's lookup tries profiles/NAME.toml: over 255 bytes the system refused it with
    # OSError ENAMETOOLONG (a traceback from `profilegen design NAME`, check, and a spec's gearset)
    with pytest.raises(pg.GearSetError, match="no such"):
        resolve_gearset(text)


def test_a_sweep_spec_naming_a_gear_set_too_long_is_a_spec_error_naming_gearset():
    spec = {"gearset": "x" * 4000, "grid": {"gear.rim_thickness_mm": [0.9]}}
    with pytest.raises(pg.ProfilegenError, match=r"gearset"):
        parse_sweep_spec(spec, origin="spec.toml")
