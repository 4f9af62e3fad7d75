"""The verdict's comparison and its face check, by definition (escapes of tests/benchmarks/mutants.py):
a value exactly at its requirement passes (a minimum is "at least", a maximum "at most"), a maximum is
failed by a larger value, and the face check reads the FS teeth as they are made — the modified
teeth when the face stage modifies them, the unmodified ones only without a modification."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

import profilegen as pg
from profilegen.gearset.requirements import Requirements
from profilegen.pipeline.design import FAIL, PASS, _judge, _verdict
from profilegen.pipeline.scenes import SCENES


@pytest.mark.parametrize("value, required, sense, status", [
    (1.5, 1.5, ">=", PASS),     # a safety exactly at its requirement: "at least 1.5" holds
    (1.4999, 1.5, ">=", FAIL),
    (2.0, 1.5, ">=", PASS),
    (1e-3, 1e-3, "<=", PASS),   # a backlash exactly at its allowance: "at most" holds
    (2e-3, 1e-3, "<=", FAIL),   # a maximum exceeded fails
    (0.5e-3, 1e-3, "<=", PASS),
])
def test_judge_at_below_and_above_the_requirement(value, required, sense, status):
    check = _judge("c", "w", "k", value, required, sense=sense, fail_text="failed", note="ok")
    assert check.status == status
    assert check.text == ("ok" if status == PASS else "failed")


def _design(face):
    """What _verdict reads of a design, by hand: the default set (requirements emptied but the face
    check, which is always made), the sketch scene, no profile, contact, stresses or curves."""
    gs = pg.load_gearset("default")
    none = {f: None for f in Requirements.__dataclass_fields__}
    gs = SimpleNamespace(**{k: getattr(gs, k) for k in ("gear", "torque", "material", "cup", "tooth")},
                         requirements=Requirements(**none), warnings=())
    return SimpleNamespace(gearset=gs, scene=SCENES["sketch"], profile=None, face=face, contact=None, stress=None,
                           ratcheting=None, torsional=None, transmission=None, warnings=())


def _face_check(face):
    checks = [c for c in _verdict(_design(face)).checks if c.name == "FS teeth across the face clear of the CS"]
    assert len(checks) == 1
    return checks[0]


def test_the_face_check_reads_the_modified_teeth():
    # unmodified the teeth cut 5 µm into the CS; the modification clears them: the part as made passes
    face = SimpleNamespace(sections=(1, 2, 3), max_interference_mm=5e-3, interference_tol_mm=1e-4,
                           modification=SimpleNamespace(max_interference_mm=0.0))
    assert _face_check(face).status == PASS
    # and a modification that still interferes fails with its own depth, whatever the unmodified one
    face.max_interference_mm, face.modification.max_interference_mm = 0.0, 2e-3
    check = _face_check(face)
    assert check.status == FAIL and "2 µm" in check.text and "with the tooth modification" in check.text


def test_the_face_check_reads_the_unmodified_teeth_without_a_modification():
    face = SimpleNamespace(sections=(1, 2, 3), max_interference_mm=5e-3, interference_tol_mm=1e-4, modification=None)
    check = _face_check(face)
    assert check.status == FAIL and "5 µm" in check.text and "modification" not in check.text
