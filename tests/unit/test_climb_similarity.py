"""The ratcheting climb scales like the gear: geometrically similar gear sets climb on the same
teeth and give the same torque over size³.

`profilegen new` writes every size of a ratio with the same proportions (lengths ∝ the size, the
same material), so an elastic model's torques go as size³ — the whole-gear stiffness does to
within 4 % (docs/validation/catalogue-sizes.md). The climb took its teeth within an absolute
0.15 mm of the CS: every tooth the limit point's rotation can bring into contact at size 14,
only those within 0.2 m at size 58, whose estimate (verify scene, ratio 100) rose 40 % with the
rest. The cut is now :data:`~profilegen.contact.ratchet.CLIMB_GAP_PER_MODULE` modules, and a
path that turns its stations farther than the cut says so.

Design scene, 5 stations a tooth, ratio 50 (the smallest teeth count: ~5 s a set). Measured at
the change: T/size³ of size 58 over size 14 1.022 with the module-relative cut, 0.939 with the
absolute one (31 and 20 teeth).
"""

from __future__ import annotations

import pytest

from profilegen import design
from profilegen.contact.ratchet import CLIMB_GAP_PER_MODULE, ratcheting_torque
from profilegen.gearset.new import new_gearset

SIZES = (14, 58)


@pytest.fixture(scope="module")
def similar():
    """{size: (design, module, the product's climb)} for two similar ratio-50 sets."""
    out = {}
    for size in SIZES:
        gs = new_gearset(size, 50).gearset
        d = design(gs, scene="design", stress=False)
        out[size] = (d, float(gs.gear.module_mm), ratcheting_torque(d, catalogue=None, options={"climb_stations": 5}))
    return out


def test_similar_gears_climb_on_the_same_teeth_and_torque_over_size_cubed(similar):
    teeth = {s: similar[s][2].climb["teeth"] for s in SIZES}
    assert teeth[14] == teeth[58] > 0
    for s in SIZES:
        assert similar[s][2].climb["max_gap_mm"] == pytest.approx(CLIMB_GAP_PER_MODULE * similar[s][1])
    per_cube = {s: similar[s][2].torque_nm / s ** 3 for s in SIZES}
    assert per_cube[58] / per_cube[14] == pytest.approx(1.0, abs=0.05)


def test_the_linear_diagnostics_are_not_the_estimates_warnings(similar):
    """With the climb giving the estimate, what the linear diagnostics say (an estimate of their
    own, extrapolated) is kept apart: a user read it among the verify run's notes as the estimate."""
    for s in SIZES:
        r = similar[s][2]
        assert r.climb["criterion"] != "none"
        assert not [w for w in r.warnings if "linear diagnostics" in w]
        assert all(w.startswith("linear diagnostics") for w in r.diagnostics)
        assert r.to_dict()["diagnostics"] == list(r.diagnostics)


def test_a_cut_the_path_turns_beyond_is_said(similar):
    """A fifth of a module: the limit point turns the stations farther than that (φ·r ≈ 0.5 m)."""
    d, m, product = similar[58]
    assert not [w for w in product.warnings if "could have touched" in w]
    cut = ratcheting_torque(d, catalogue=None, options={"climb_stations": 5, "climb_max_gap_mm": 0.2 * m})
    assert cut.climb["teeth"] < product.climb["teeth"]
    assert [w for w in cut.warnings if "a tooth left out could have touched" in w and "raise climb_max_gap_mm" in w]
