"""profilegen new's rules at their boundaries (escapes of tests/benchmarks/mutants.py: the wire's spark
gap at the 0.1 mm wire, the ratio range's ends), each against the rule as the module states it."""

from __future__ import annotations

import pytest

from profilegen.gearset.new import RATIO_RANGE, NewSetError, new_gearset, wire_for_module


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


@pytest.mark.parametrize("size, ratio", [(14, 100), (32, 50), (58, 100)])
def test_the_material_is_the_flexspline_steel_its_source_names(size, ratio):
    """The material rule: the flexspline steel of the published FEA-deformation study (seed 004:
    35CrMnSiA, E = 209 GPa, nu = 0.295), with the strength limits the bundled default set (that
    study's set) estimates for it: the same at every size and ratio, and each written field
    commented with where it comes from."""
    import tomllib
    from pathlib import Path

    from profilegen.gearset import load_gearset

    made = new_gearset(size, ratio)
    m = made.gearset.material
    assert (m.youngs_modulus_mpa, m.poisson_ratio) == (209000.0, 0.295)  # seed 004's values
    default = load_gearset(Path(__file__).parents[2] / "profiles" / "default.toml").material
    for key in ("yield_strength_mpa", "ultimate_strength_mpa", "bending_endurance_limit_mpa",
                "shear_endurance_limit_mpa"):
        assert getattr(m, key) == getattr(default, key), key
    # the endurance limits follow the stated rules of thumb: sigma_-1 ~ 0.4 R_m, tau_-1 ~ 0.58 sigma_-1
    assert m.bending_endurance_limit_mpa == pytest.approx(0.4 * m.ultimate_strength_mpa, rel=0.01)
    assert m.shear_endurance_limit_mpa == pytest.approx(0.58 * m.bending_endurance_limit_mpa, rel=0.01)
    section = made.text.split("[material]")[1].split("\n[")[0]
    assert "35CrMnSiA" in section and "seed 004" in section and "ESTIMATES" in section
    assert tomllib.loads(made.text)["material"]["bending_endurance_limit_mpa"] == 650.0
