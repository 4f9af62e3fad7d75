"""Inputs the command-line fuzz (tests/benchmarks/fuzz.py --cli) found ending in a traceback, each
now a named error: the clean outcome the fuzz asks for (an error of the package's own type whose
message names the field)."""

from __future__ import annotations

import pytest

import profilegen as pg
from profilegen.gearset import resolve_gearset
from profilegen.studies.sweep import parse_sweep_spec


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


def test_the_sheet_numbers_of_a_per_branch_fit_read_its_first_branch():
    # a CS flank fitted per branch (a ridge splits it): profile_fit.json's "branches" holds the
    # branches' fits under "branches" (and "whole": None); the design's files raised KeyError 'fits'
    # (fuzz: a drawn DCTA set at pressure angle 1.1°, m = 1.5 mm, z = 336/340, sketch scene)
    from profilegen.pipeline.scene_estimates import sheet_numbers

    arc1 = {"type": "arc", "radius_mm": 2.0, "centre_mm": [1.0, 2.0]}
    line = {"type": "line", "length_mm": 0.5, "start_mm": [0.1, 0.2], "end_mm": [0.3, 0.4]}
    arc2 = {"type": "arc", "radius_mm": 3.0, "centre_mm": [4.0, 5.0]}
    other = {"type": "arc", "radius_mm": 9.0, "centre_mm": [9.0, 9.0]}
    fit = {"method": "least_squares", "fits": {},
           "branches": {"ridge_indices": [10], "max_error_mm": 1e-3, "whole": None,
                        "branches": [{"chain": {"elements": [arc1, line, arc2]}},
                                     {"chain": {"elements": [other]}}]}}
    design = {"circular_spline": {"tip_radius_mm": 50.0, "root_radius_mm": 51.0},
              "tooth": {"neutral_radius_mm": 49.0, "addendum_y_mm": 1.4, "dedendum_y_mm": 0.4}}
    out = sheet_numbers(design, fit)
    assert (out["r1_radius_mm"], out["r1_centre_mm"]) == (2.0, [1.0, 2.0])
    assert (out["line_length_mm"], out["line_start_mm"], out["line_end_mm"]) == (0.5, [0.1, 0.2], [0.3, 0.4])
    assert (out["r2_radius_mm"], out["r2_centre_mm"]) == (3.0, [4.0, 5.0])
