"""The cup's sections along the face (profilegen.contact.coning_sections): the 3D cup's
harmonics projected exactly, semi-membrane coning as a scale factor, bad input named.

The CS ring oracle against Roark's two-load ring, and the catalogue's sourced rows, are checked
here too (they were written beside the face-load study, which is research now)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from profilegen.contact.coning_sections import SectionError, cup_sections, semi_membrane_sections
from profilegen.geometry.deformation import HarmonicDeformation


def test_sections_are_exact_and_semi_membrane_scales():
    class FakeCup:
        orders = np.array([0, 2, 4, 6])

        def omega(self, phi, z):
            return 0.01 * z + 0.5 * (z / 60) * np.cos(2 * phi) - 0.02 * np.cos(4 * phi) + 1e-3 * z * np.cos(6 * phi)

        def upsilon(self, phi, z):
            return -0.25 * (z / 60) * np.sin(2 * phi) + 0.005 * np.sin(4 * phi)

    secs = cup_sections(FakeCup(), [30.0, 60.0])
    phi = np.linspace(0, 2 * math.pi, 37)
    for sec, z in zip(secs, (30.0, 60.0)):
        w, u = sec.evaluate(phi, order=1)
        np.testing.assert_allclose(w[0], FakeCup().omega(phi, z), atol=1e-15)
        np.testing.assert_allclose(u[0], FakeCup().upsilon(phi, z), atol=1e-15)
    base = HarmonicDeformation(2, np.array([0.5, 0.01]), np.array([-0.25, 0.002]))
    half, same = semi_membrane_sections(base, [30.0, 60.0], 60.0)
    w0, u0 = base.evaluate(phi, order=2)
    w1, u1 = half.evaluate(phi, order=2)
    np.testing.assert_allclose(w1, 0.5 * w0)
    np.testing.assert_allclose(u1, 0.5 * u0)
    assert same.factor == 1.0


def test_bad_input_is_named():
    with pytest.raises(SectionError, match="z_mm"):
        semi_membrane_sections(HarmonicDeformation(2, np.array([0.5]), np.array([-0.25])), [-1.0], 60.0)
    with pytest.raises(SectionError, match="reference_z_mm"):
        semi_membrane_sections(HarmonicDeformation(2, np.array([0.5]), np.array([-0.25])), [1.0], 0.0)
    with pytest.raises(SectionError, match="cup"):
        cup_sections(object(), [1.0])


def test_cs_ring_two_opposite_loads_match_roark():
    # Roark, thin circular ring, two equal opposite radial loads P: ΔD along them +0.1488 PR³/EI, across −0.1366;
    # the ring here is also extensible in hoop (n = 0): + U·R/(2π E A) on every radial term
    from tests.oracles.cs_ring import CSRing, CSRingError, cs_ring_compliance

    ring = CSRing(50.0, 60.0, 10.0, 200000.0)
    r, ei = ring.radius_mm, ring.youngs_modulus_mpa * ring.second_moment_mm4
    hoop = 2 * r / (2 * math.pi * ring.youngs_modulus_mpa * ring.area_mm2)
    pts = np.array([[0.0, 55.0], [55.0, 0.0], [40.0, 40.0]])
    dirs = np.array([[0.0, 1.0], [1.0, 0.0], [0.6, -0.8]])
    s = cs_ring_compliance(ring, pts, dirs, harmonics=4000)
    assert s[0, 0] - hoop == pytest.approx(0.1488 / 2 * r ** 3 / ei, rel=2e-3)
    assert s[1, 0] - hoop == pytest.approx(-0.1366 / 2 * r ** 3 / ei, rel=2e-3)
    np.testing.assert_allclose(s, s.T)
    assert np.linalg.eigvalsh(s).min() > -1e-12 * s.max()
    # even tangential forces all round (torsion, n = 0) are the chain's cs_body term, not this one: only the
    # harmonics n = 36k of 36 point forces remain (~1/36⁴ of a radial pair's)
    th = 2 * math.pi * np.arange(18) / 36  # one zone's half; the U = 2 copies give the other 18
    ring_pts = 55.0 * np.column_stack([np.sin(th), np.cos(th)])
    t = cs_ring_compliance(ring, ring_pts, np.column_stack([np.cos(th), -np.sin(th)]))
    assert np.abs(t.sum(axis=1)).max() < 1e-5 * s[0, 0]
    with pytest.raises(CSRingError, match="outer_radius_mm"):
        CSRing(60.0, 50.0, 10.0, 200000.0)


def test_catalogue_rows_are_the_sourced_ones_with_the_ratio_caveat():
    from profilegen.contact.catalogue import CatalogueError, catalogue_row

    row = catalogue_row(40, 100)
    assert (row["T1_nm"], row["K1_nm_per_rad"], row["T2_nm"], row["K2_nm_per_rad"]) == (54.0, 1.3e5, 196.0, 2e5)
    assert row["ratio"] == 80 and row["note"] and "table 50.4" in row["source"]
    assert catalogue_row(40, 50)["K1_nm_per_rad"] == 1e5 and "table 42" in catalogue_row(40, 50)["source"]
    assert row["ratcheting_torque_nm"] == 2100.0
    assert catalogue_row(32, 50)["note"] is None
    with pytest.raises(CatalogueError, match="size"):
        catalogue_row(11, 100)


def test_cs_ring_of_a_gearset_root_section_is_stiffer_than_the_sector_part():
    from tests.oracles.cs_ring import CSRing, CSRingError
    from profilegen.gearset import default_gearset_path, load_gearset

    gs = load_gearset(default_gearset_path())
    root, sector = CSRing.from_gearset(gs), CSRing.from_gearset(gs, inner="sector")
    assert root.inner_radius_mm < 1.1 * gs.gear.cs_pitch_radius_mm == pytest.approx(sector.inner_radius_mm)
    assert root.outer_radius_mm == sector.outer_radius_mm and root.second_moment_mm4 > 3 * sector.second_moment_mm4
    with pytest.raises(CSRingError, match="inner"):
        CSRing.from_gearset(gs, inner="bore")
