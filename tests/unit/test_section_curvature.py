"""The tooth ring's assembly stress from the deformed section's own curvature (issue 28, item 4b):
:func:`profilegen.stress.tooth_ring.section_curvature` against closed forms and an independent
discrete curvature of the displaced neutral line."""

from __future__ import annotations

import math

import numpy as np
import pytest

from profilegen.geometry.deformation import HarmonicDeformation, ring_theory
from profilegen.errors import StressError
from profilegen.stress.tooth_ring import section_curvature, stress_influence_factor, tooth_ring_stress

R_M, W0 = 48.675, 0.5  # seed000_csf40's neutral radius and w0 = ω* m


def test_ring_theory_on_the_major_axis_is_the_closed_form():
    """Ring theory ω = w0 cos 2φ, υ = −(w0/2) sin 2φ: at φ = 0, ω = w0, ω'' = −4 w0, υ' = −w0 and
    ω' = υ = υ'' = 0, so R' = r_m e_t, R'' = −(r_m + 3 w0) e_r and κ = (r_m + 3 w0)/r_m² exactly
    (the classical κ − 1/r_m = −(ω + ω'')/r_m² = 3 w0/r_m², here without linearisation)."""
    kappa = section_curvature(ring_theory(W0, 2), R_M)
    assert float(kappa(0.0)[0]) == pytest.approx((R_M + 3.0 * W0) / R_M**2, rel=1e-14)
    # the minor axis: ω = −w0, ω'' = 4 w0, υ' = w0 → κ = (r_m − 3 w0)/r_m²
    assert float(kappa(math.pi / 2)[0]) == pytest.approx((R_M - 3.0 * W0) / R_M**2, rel=1e-14)


def _menger(points: np.ndarray) -> np.ndarray:
    """Curvature of the circle through three consecutive points (signed, counter-clockwise +)."""
    a, b, c = points[:-2], points[1:-1], points[2:]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    la, lb, lc = (np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1), np.linalg.norm(c - a, axis=1))
    return 2.0 * cross / (la * lb * lc)


def test_a_cup_like_section_matches_the_discrete_curvature_of_its_displaced_line():
    """A section with higher harmonics (a cup pressed over the bearing width has them): the curvature
    of the displaced points (r_m + ω) e_r + υ e_t, taken as the circle through three neighbours
    (no derivatives of ω, υ used), agrees with section_curvature to the discretisation's O(h²)."""
    section = HarmonicDeformation(2, [0.55, 0.03, -0.01, 0.004], [-0.27, -0.012, 0.003, -0.001], mean_mm=-0.01,
                                  tier="cup3d", source="test")
    h = 1e-4
    phi = np.array([0.0, 0.3, 0.9, 1.4, math.pi / 2])
    for p in phi:
        ang = p + h * np.arange(-1, 2)
        w, u = section.evaluate(ang, order=0)
        er = np.column_stack([np.cos(ang), np.sin(ang)])
        et = np.column_stack([-np.sin(ang), np.cos(ang)])
        pts = (R_M + w[0])[:, None] * er + u[0][:, None] * et
        assert float(section_curvature(section, R_M)(p)[0]) == pytest.approx(float(_menger(pts)[0]), rel=1e-6)


def test_the_assembly_stress_uses_the_given_curvature():
    """σ_ass = K_σ E δ/2 (κ(0) − 1/r_m): with ring theory's own curvature, κ(0) − 1/r_m = 3 w0/r_m²."""
    kw = dict(neutral_radius_mm=R_M, rim_thickness_mm=1.45, deflection_mm=W0, root_thickness_mm=1.0,
              fillet_radius_mm=0.3, pitch_mm=math.pi * 0.5, tooth_height_mm=1.0, equivalent_tooth_height_mm=0.5,
              face_width_mm=20.0, youngs_modulus_mpa=206000.0, tangential_force_n=100.0)
    own = tooth_ring_stress(**kw, curvature=section_curvature(ring_theory(W0, 2), R_M))
    k_sigma = float(stress_influence_factor(1.0, 0.3, 1.45))
    assert own.assembly_stress_mpa == pytest.approx(k_sigma * 206000.0 * 1.45 / 2 * 3 * W0 / R_M**2, rel=1e-12)
    assert own.inputs["curvature"] == "the deformed section's own"
    ellipse = tooth_ring_stress(**kw)
    assert ellipse.inputs["curvature"] == "the equivalent ellipse's"
    assert own.load_stress_mpa == ellipse.load_stress_mpa  # the load stress does not depend on κ


def test_bad_curvature_inputs_name_the_parameter():
    with pytest.raises(StressError, match="deformation"):
        section_curvature(object(), R_M)
    with pytest.raises(StressError, match="neutral_radius_mm"):
        section_curvature(ring_theory(W0, 2), -1.0)
    kw = dict(neutral_radius_mm=R_M, rim_thickness_mm=1.45, deflection_mm=W0, root_thickness_mm=1.0,
              fillet_radius_mm=0.3, pitch_mm=1.5, tooth_height_mm=1.0, equivalent_tooth_height_mm=0.5,
              face_width_mm=20.0, youngs_modulus_mpa=206000.0, tangential_force_n=100.0)
    with pytest.raises(StressError, match="curvature"):
        tooth_ring_stress(**kw, curvature=np.ones(91))
    with pytest.raises(StressError, match="curvature"):
        tooth_ring_stress(**kw, curvature=lambda phi: np.ones(3))
