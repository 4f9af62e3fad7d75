"""profilegen new's rules at their boundaries (escapes of tests/benchmarks/mutants.py: the wire's spark
gap at the 0.1 mm wire, the ratio range's ends), each against the rule as the module states it."""

from __future__ import annotations

import pytest

from profilegen.catalogue_set import RATIO_RANGE, NewSetError, new_gearset, wire_for_module


@pytest.mark.parametrize("module_mm, wire", [
    (0.4, (0.05, 0.02)),    # 0.2 m = 0.08 mm: the 0.15 mm wire's 0.075 + 0.02 is over, the 0.1 mm wire's 0.07 fits
    (0.35, (0.05, 0.02)),   # 0.07 mm: the 0.1 mm wire exactly (a wire of 0.1 mm and more cuts with a 0.02 mm gap)
    (0.3, (0.035, 0.01)),   # 0.06 mm: 0.1 mm's 0.07 is over; 0.07 mm wire + its 0.01 mm gap = 0.045 fits
    (0.5, (0.075, 0.02)),   # 0.1 mm: 0.2 mm's 0.12 over, 0.15 mm's 0.095 fits
])
def test_the_wire_is_the_thickest_whose_corner_fits_with_its_gap(module_mm, wire):
    assert wire_for_module(module_mm) == pytest.approx(wire, abs=1e-15)


def test_the_ratio_range_includes_both_ends():
    assert RATIO_RANGE == (30, 320)
    for ratio in RATIO_RANGE:  # size 58: m = 147.32 mm / 640 = 0.23 mm at ratio 320, a wire fits
        g = new_gearset(58, ratio).gearset
        assert g.ratio == ratio
    for ratio in (RATIO_RANGE[0] - 1, RATIO_RANGE[1] + 1):
        with pytest.raises(NewSetError, match=rf"ratio = {ratio}: must be a whole number in \[30, 320\]"):
            new_gearset(58, ratio)
