"""Face-stage warnings (issue 27, item 3): each by a case that triggers it and one that does not.

Built on one design of the default set (design scene: the face stage on a coarse 3D cup), calling
the face functions directly with modified inputs."""

import pytest

import profilegen as pg
from profilegen.face.modification import apply_modification


@pytest.fixture(scope="module")
def designed():
    gs = pg.load_gearset("default")
    d = pg.design(gs, scene="design", contact=False, stress=False)
    return gs, d


def _still(warnings):
    return [w for w in warnings if "with the tooth modification the CS still interferes" in w]


def test_modification_still_interferes_warns(designed):
    # thickening the FS tooth toward the face ends (a negative crowning: Δs > 0 away from the design
    # section) pushes every non-design section's tooth into the one CS: it must interfere
    gs, d = designed
    mod = apply_modification(gs, d.rim.cup, d.face, 0.0, -0.1)
    assert mod.max_interference_mm > d.face.interference_tol_mm
    hits = _still(mod.warnings)
    assert len(hits) == 1 and "µm" in hits[0]


def test_modification_no_change_does_not_warn(designed):
    # the face stage's own computed modification, applied as given: interference-free
    gs, d = designed
    m = d.face.modification
    mod = apply_modification(gs, d.rim.cup, d.face, m.taper_mm_per_mm, m.crowning_mm)
    assert mod.max_interference_mm <= d.face.interference_tol_mm
    assert not _still(mod.warnings)


def test_one_cs_profile_interferes_warns(designed):
    # the default set's unmodified FS teeth interfere with the one CS profile (max_interference_mm
    # above the tolerance): the face stage says so, naming the design section
    _, d = designed
    f = d.face
    assert f.max_interference_mm > f.interference_tol_mm
    hits = [w for w in f.warnings if w.startswith("the one CS profile (design section")]
    assert len(hits) == 1 and f"z = {f.design_section_z_mm:g} mm" in hits[0]
