"""Loaded transmission error over a tooth passage (profilegen.contact.transmission).

Checks against physics, not against the module's own bookkeeping: the whole gear's torque
balance U·Σ r_k F_k = T and the contact conditions F ≥ 0, g ≥ 0, F·g = 0 with the gaps
recomputed here from each position's own points and S; closure — after one tooth passage
(ψ = 2π/z2) the mesh repeats with every tooth where its neighbour stood, so the rotation and
the tooth forces repeat, relabelled; mirror symmetry — the left flank at ψ is the mirror
image of the right flank at 2π/z2 − ψ. Default set, sketch design, 3 + 2 positions in this
process (the 16-position run and its timing: tests/benchmarks/transmission_error.py).
"""

import json
import math

import numpy as np
import pytest

import profilegen as pg
from profilegen.contact import ContactInput
from profilegen.contact.transmission import TransmissionErrorError, transmission_error


@pytest.fixture(scope="module")
def inputs():
    return ContactInput.from_design(pg.design(pg.load_gearset(pg.default_gearset_path()), scene="sketch",
                                              contact=False, stress=False))


@pytest.fixture(scope="module")
def passage_deg(inputs):
    return 360.0 / inputs.gearset.gear.circular_spline_teeth


@pytest.fixture(scope="module")
def right(inputs, passage_deg):
    """ψ = 0, half a tooth passage, one tooth passage (right flanks, rated torque)."""
    return transmission_error(inputs, inputs.gearset.torque.rated_nm, positions=3, workers=1,
                              options=dict(span=passage_deg, keep_matrices=True))


def test_equilibrium_and_complementarity_at_every_position(inputs, right):
    torque_nmm = right.torque_nm * 1e3
    waves = inputs.gearset.gear.waves
    assert right.psi_rad.size == len(right.points) == len(right.cases) == len(right.matrices) == 3
    assert right.ball_supports == "all" and len(right.compliances) == 3  # the default: every ball one-sided
    for pts, case, comp in zip(right.points, right.cases, right.compliances):
        f, phi, react = case.solution.force_n, case.rotation_rad, case.ball_reaction_n
        # the whole gear: U zones alike, each Σ r F; together the applied torque
        assert waves * float(pts.lever_mm @ f) == pytest.approx(torque_nmm, rel=1e-10)
        # separation after load of every tooth point and every ball, from this position's raw
        # flexibility blocks (rim per unit face width, CS) and the balls' no-load gaps
        b = comp.face_width_mm
        s_cc = comp._flex_cc / b + comp.cs_matrix_mm_per_n
        gap = pts.gap_mm + s_cc @ f + comp._flex_cb @ react / b - pts.lever_mm * phi
        ball_gap = comp.ball_gap_mm + comp._flex_cb.T @ f / b + comp._flex_bb @ react / b
        scale = float(np.max(np.abs(s_cc @ f)))
        assert np.all(f >= 0.0) and np.all(react >= 0.0)
        assert gap.min() >= -1e-9 * scale and ball_gap.min() >= -1e-9 * scale
        assert np.max(np.abs(f * gap)) <= 1e-9 * scale * f.max()
        assert np.max(np.abs(react * ball_gap)) <= 1e-9 * scale * react.max()
        assert 0 < np.count_nonzero(f) < f.size  # a real contact problem: some points open
        assert np.count_nonzero(react) > np.count_nonzero(comp.ball_gap_mm == 0.0) - 3  # balls outside the wrap too
    assert np.all(right.equilibrium_residual < 1e-10)
    # the recomputed points differ from position to position (nothing carried over)
    assert not np.allclose(right.points[0].gap_mm[:10], right.points[1].gap_mm[:10])
    # definitions
    assert right.error_arcsec.mean() == pytest.approx(0.0, abs=1e-9)
    assert right.peak_to_peak_arcsec == pytest.approx(np.ptp(right.error_arcsec))
    k = right.torque_nm / (right.rotation_rad - right.first_contact_rad)
    np.testing.assert_allclose(right.stiffness_nm_per_rad, k)
    assert right.stiffness_ripple >= 1.0
    out = json.loads(json.dumps(right.to_dict()))
    assert out["psi_deg"] == pytest.approx(np.degrees(right.psi_rad).tolist())
    assert out["peak_to_peak_arcsec"] == pytest.approx(right.peak_to_peak_arcsec)
    assert len(out["error_arcsec"]) == 3


def test_one_tooth_passage_repeats_with_the_teeth_relabelled(right):
    """ψ = 2π/z2 moves every FS tooth to where its neighbour i − 1 stood at ψ = 0 (δ = −2π/z1):
    the same gaps, the same S, the same rotation; tooth i carries tooth i − 1's force. The
    points are found again at the new ψ (each tooth's closest point to 1e-7 mm of arc
    length, a flat minimum: 4e-8 mm apart here), and S moves by ~1e-6 of itself per 1e-7
    mm: the repeat holds to that — 1.8e-9 rad (3.4e-9 with the window's balls), 1/42 of the
    error's own variation over the passage with every ball a support (1/135 with the window,
    whose mesh is 6x softer and varies 6x more)."""
    p0, p1 = right.points[0], right.points[2]
    c0, c1 = right.cases[0], right.cases[2]
    np.testing.assert_array_equal(p1.tooth - 1, p0.tooth)
    np.testing.assert_allclose(p1.t_mm, p0.t_mm, atol=1e-7)
    np.testing.assert_allclose(p1.gap_mm, p0.gap_mm, atol=1e-12)
    np.testing.assert_allclose(right.matrices[2], right.matrices[0], rtol=0, atol=1e-5 * np.abs(right.matrices[0]).max())
    variation = abs(right.rotation_rad[1] - right.rotation_rad[0])
    assert variation > 1e-4 * right.rotation_rad[0]  # half way the mesh is a different one
    assert abs(c1.rotation_rad - c0.rotation_rad) < 0.05 * variation
    # (1.03e-4 of the largest force with every ball a support; < 1e-4 with the window's balls)
    np.testing.assert_allclose(c1.tooth_force_n, c0.tooth_force_n, atol=2e-4 * c0.max_tooth_force_n)


def test_left_flank_is_the_mirror_image(inputs, right, passage_deg):
    """Mirror about the major axis: the left flank at ψ is the right flank at 2π/z2 − ψ
    (the motion, the CS space and the ball set are mirror-symmetric)."""
    left = transmission_error(inputs, right.torque_nm, positions=2, workers=1,
                              options=dict(span=passage_deg / 2.0, side=-1))
    assert left.points[0].rotation == -right.points[0].rotation
    np.testing.assert_allclose(left.first_contact_rad, right.first_contact_rad[[2, 1]], rtol=1e-9)
    variation = abs(right.rotation_rad[1] - right.rotation_rad[0])
    # to the points' 1e-7 mm (see above): 1/25 of the variation over the passage, measured
    np.testing.assert_allclose(left.rotation_rad, right.rotation_rad[[2, 1]], rtol=0, atol=0.1 * variation)


@pytest.mark.parametrize("kw, name", [
    ({"torque_nm": 0.0}, "torque_nm"),
    ({"torque_nm": -10.0}, "torque_nm"),
    ({"torque_nm": math.nan}, "torque_nm"),
    ({"positions": 1}, "positions"),
    ({"positions": 2.5}, "positions"),
    ({"span": "revolution"}, "span"),
    ({"span": 400.0}, "span"),
    ({"span": 0.0}, "span"),
    ({"side": 0}, "side"),
    ({"ball_motion": "free"}, "ball_motion"),
    ({"workers": 0}, "workers"),
])
def test_bad_input_names_the_parameter(inputs, kw, name):
    args = {"torque_nm": 100.0, **kw}
    top = {k: args.pop(k) for k in ("positions", "workers") if k in args}
    with pytest.raises(TransmissionErrorError, match=name):
        transmission_error(inputs, args.pop("torque_nm"), **top, options=args)


def test_unknown_option_names_the_key(inputs):
    with pytest.raises(TransmissionErrorError, match="options: unknown key 'spam'"):
        transmission_error(inputs, 100.0, options={"spam": 1})
    with pytest.raises(TransmissionErrorError, match="options = 'tooth'"):
        transmission_error(inputs, 100.0, options="tooth")
