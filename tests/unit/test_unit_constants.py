"""Unit constants against their definitions (issue 27 item 3: an arcsec/arcmin mix-up escaped
the suite). 1° = π/180 rad, 1′ (arcmin) = 1°/60, 1″ (arcsec) = 1°/3600 (SI Brochure, 9th ed.,
table 4: non-SI units accepted for use with the SI); 1 N·m = 1000 N·mm; 1 MPa = 1 N/mm².
Each constant the package defines is checked against the definition, and the results that
convert with it are checked against the quantity in radians / N·mm they carry, and against an
independent fact where one exists (the moment balance Σ F r = T/U of a load case, in N·mm).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

DEG = math.pi / 180.0  # rad per degree, by definition
ARCMIN = DEG / 60.0
ARCSEC = DEG / 3600.0


def test_module_constants_are_their_definitions():
    from profilegen.contact import analysis, chain, transmission

    for mod in (analysis, chain):
        assert mod.ARCMIN_PER_RAD == pytest.approx(1.0 / ARCMIN, rel=1e-15), mod.__name__
    assert transmission.ARCSEC_PER_RAD == pytest.approx(1.0 / ARCSEC, rel=1e-15)
    assert transmission.ARCSEC_PER_RAD == pytest.approx(60.0 * chain.ARCMIN_PER_RAD, rel=1e-15)
    assert 1.0 / ARCMIN == pytest.approx(3437.7467707849396, rel=1e-15)  # 10800/π, the printed value


def test_gear_set_torques_in_n_mm(default_gearset):
    t = default_gearset.torque
    assert t.rated_nmm == pytest.approx(1000.0 * t.rated_nm, rel=1e-15)
    assert t.peak_nmm == pytest.approx(1000.0 * t.peak_nm, rel=1e-15)
    if t.momentary_nm is not None:
        assert t.momentary_nmm == pytest.approx(1000.0 * t.momentary_nm, rel=1e-15)


def test_load_cases_balance_the_torque_in_n_mm(default_sketch_contact):
    """Σ_k F_k r_k (N·mm) of one zone = T/U × 1000: the moment balance carries the N·m → N·mm
    conversion; the rotation in arcmin is the radians × 60·180/π."""
    res = default_sketch_contact.contact
    lever = res.points.lever_mm
    for case in res.cases:
        f = case.solution.force_n
        assert float(f @ lever) == pytest.approx(case.torque_nm / res.zones * 1000.0, rel=1e-6)
        assert case.zone_torque_nm == pytest.approx(case.torque_nm / res.zones, rel=1e-15)
        assert case.rotation_arcmin == pytest.approx(case.rotation_rad / ARCMIN, rel=1e-14)
        assert 0.0 < case.rotation_arcmin < 60.0  # a stiff gear turns by arcmin, not by degrees
    d = res.to_dict()
    if "rotations_arcmin" in d:
        np.testing.assert_allclose(d["rotations_arcmin"], np.asarray(res.rotations_rad) / ARCMIN, rtol=1e-14)


def test_fixed_compliance_analysis_balances_the_torque_in_n_mm(default_sketch_contact):
    """analyse_contact (one zone, S held fixed): the same moment balance, Σ F r = T/U × 1000 N·mm."""
    from profilegen.contact.analysis import analyse_contact

    res = default_sketch_contact.contact
    out = analyse_contact(res.points, res.compliance.matrix_mm_per_n, [265.0, 530.0])
    for case in out.cases:
        assert float(case.solution.force_n @ res.points.lever_mm) == pytest.approx(case.torque_nm / 2 * 1000.0,
                                                                                  rel=1e-6)
    assert out.cases[1].rotation_rad > out.cases[0].rotation_rad > 0.0


def test_torsional_curve_in_arcmin(default_sketch_contact):
    curve = default_sketch_contact.torsional
    if curve is None:
        pytest.skip("no torsional curve in this design")
    np.testing.assert_allclose(curve.rotation_arcmin, curve.rotation_rad / ARCMIN, rtol=1e-14)
    d = curve.to_dict()
    assert d["lost_motion_arcmin"] == pytest.approx(curve.lost_motion_rad["total"] / ARCMIN, rel=1e-14)
    assert d["backlash_arcmin"] == pytest.approx(curve.backlash_rad / ARCMIN, rel=1e-14, abs=1e-18)
    np.testing.assert_allclose(d["rotation_mesh_arcmin"], np.asarray(curve.mesh_rad) / ARCMIN, rtol=1e-14)
    h = curve.headline()
    assert h["lost_motion_arcmin"] == pytest.approx(curve.lost_motion_rad["total"] / ARCMIN, rel=1e-14)


def test_ring_stiffness_in_mpa_and_mm():
    """E in MPa = N/mm², lengths in mm: a ring's hoop term R/(2π E A) comes out in mm/N — 1 N
    on a steel ring 1 m round, 1 cm² in section, spreads it by R/(2πEA) = 1.23e-6 mm
    (R = 159.15 mm, A = 100 mm², E = 206 000 MPa)."""
    from profilegen.contact.ratchet import cs_ring_radial_compliance

    r = 1000.0 / (2.0 * math.pi)
    w = cs_ring_radial_compliance([0.0], [0.0], mean_radius_mm=r, thickness_mm=10.0, width_mm=10.0,
                                  youngs_modulus_mpa=206000.0, harmonics=2)
    hoop = r / (2.0 * math.pi * 206000.0 * 100.0)
    assert hoop == pytest.approx(1.2297e-6, rel=1e-3)
    bending = w[0, 0] - hoop
    assert bending == pytest.approx(r ** 3 / (206000.0 * 10.0 * 1000.0 / 12.0 * 9.0) / math.pi, rel=1e-12)
