"""The contact stage searches deeper where a torque's rotation reaches past the separation within
which its points were searched (a station farther than that could touch): the momentary torque
of a large ratio-50 gear reached 136 µm against 120 once the CS ring was in the contact."""

from __future__ import annotations

from profilegen.contact.analysis import solve_contact
from profilegen.contact.inputs import ContactInput
from profilegen.pipeline.design import _searched_deep_enough


def test_a_rotation_past_the_searched_separation_is_searched_again(default_sketch):
    inputs = ContactInput.from_design(default_sketch)
    gs = inputs.gearset
    torques = [gs.torque.rated_nm, gs.torque.momentary_nm]
    shallow = solve_contact(inputs, torques, max_gap_mm=0.01)
    reach = max(c.reach_mm for c in shallow.cases)
    assert reach >= 0.01 and any(c.beyond_capacity for c in shallow.cases)  # the search is too shallow here
    deep, note = _searched_deep_enough(shallow, inputs, torques)
    assert deep.points.max_gap_mm >= max(0.02, 1.5 * reach) - 1e-12
    assert all(c.reach_mm < deep.points.max_gap_mm for c in deep.cases)
    assert note and "searched again" in note and f"{reach * 1e3:.0f} µm" in note
    # deep enough already: the same result, no note
    again, none = _searched_deep_enough(deep, inputs, torques)
    assert again is deep and none is None
