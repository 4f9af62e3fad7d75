"""One design intent across the scenes (issue 28, item 1): which rim model each scene's face stage
gets (profilegen.face.coning.rim_tier_for), and what the sheet and drawings say about the part.
No design runs here (the design scene's cup and face stage take ~10 s): the scene comparison is
tests/benchmarks/scene_agreement.py."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

import profilegen as pg
from profilegen.face.coning import RING_FEM_LABEL, UNDECIDED, modification_lines, rim_tier_for
from profilegen.pipeline.design import planned_stages


@pytest.fixture(scope="module")
def gearset():
    return pg.load_gearset(pg.default_gearset_path())


def test_the_design_scene_runs_a_coarse_cup_and_the_face_stage(gearset):
    tier = rim_tier_for(pg.SCENES["design"], gearset)
    # the verify scene's 3D cup (model "cup"), coarser: larger elements, fewer contact angles
    from profilegen.rim.stage import RIM_TIERS

    fine = RIM_TIERS["cup3d"]
    assert tier.model == fine.model == "cup" and tier.gap == fine.gap and tier.geometry == fine.geometry
    assert tier.element_mm > fine.element_mm and tier.angles < fine.angles
    assert "face" in planned_stages(gearset, scene="design")
    assert rim_tier_for(pg.SCENES["verify"], gearset) == "cup3d" and "face" in planned_stages(gearset, scene="verify")


def test_sketch_and_the_named_ring_fem_have_no_face_stage(gearset):
    assert rim_tier_for(pg.SCENES["sketch"], gearset) == "sketch"
    assert "face" not in planned_stages(gearset, scene="sketch")
    ring = dataclasses.replace(pg.SCENES["design"], rim=RING_FEM_LABEL)
    assert rim_tier_for(ring, gearset) == "design" and "face" not in planned_stages(gearset, scene=ring)


def test_three_waves_keep_the_ring_fem(gearset):
    three = SimpleNamespace(gear=SimpleNamespace(waves=3))
    assert rim_tier_for(pg.SCENES["design"], three) == "design"


def _face(taper, crowning, ds):
    mod = SimpleNamespace(taper_mm_per_mm=taper, crowning_mm=crowning, thickness_change_mm=np.asarray(ds))
    return SimpleNamespace(design_section_z_mm=70.0, design_choice="auto", modification=mod,
                           max_interference_mm=0.0106, interference_tol_mm=1e-4)


def test_the_drawings_say_the_taper_or_that_the_part_is_not_decided():
    assert modification_lines(SimpleNamespace(face=None)) == [UNDECIDED]
    assert "NOT THE PART TO CUT" in UNDECIDED
    lines = modification_lines(SimpleNamespace(face=_face(1.2e-3, 0.0, [-0.024, -0.012, 0.0])))
    assert "z = 70 mm" in lines[0]
    assert "MODIFIED" in lines[1] and "1.2 um per mm" in lines[1] and "crowning" not in lines[1]
    assert "-24 to 0 um" in lines[1]
    crowned = modification_lines(SimpleNamespace(face=_face(0.0, 2e-3, [-0.002, 0.0, -0.002])))
    assert "-2 um at the face ends" in crowned[1]
    # an interfering face left unmodified says a modification is required
    plain = _face(0.0, 0.0, [0.0, 0.0, 0.0])
    plain.modification = None
    assert "required" in modification_lines(SimpleNamespace(face=plain))[1]
    assert all(line.isascii() for line in lines + crowned)  # DXF notes
