"""The ratcheting model's CS ring (issue 27 item 3: the ring section's thickness and width
swapped in the ratcheting model moved the estimate by +55 % and no test failed).

* The radial compliance of a free thin ring against its formula, term by term, with the
  section's own dimensions: w = R/(2π E A) + (1/π) Σ_{n≥2} cos n(θ − θ_k) R³/(E I (n² − 1)²),
  A = b h, I = b h³/12 (b the width along the axis, h the radial thickness); its scaling:
  everything ∝ 1/b; the bending part ∝ h⁻³, the hoop part ∝ h⁻¹; and the same numbers from
  the second implementation of the ring (tests/oracles/cs_ring.py, two zones, radial directions).
* CSRing's section properties from their definitions (I = b h³/12 with h = r_o − r_i).
* The section the ratcheting model takes (ratchet._cs_ring_section) against the CS ring module's
  own estimate (CSRing.from_gearset: the root circle as r1 + addendum + w0 + 0.25 m, the face
  width wide) — two estimates of the same ring, from the fitted CS space and from the gear set.
* ``ratcheting_torque(climb=True)`` once, end to end, on the sketch design with few stations:
  the ring it hands the climb has that section (width = the face width, thickness = the radial
  one: not swapped), the estimate is finite and well above the rated torque (a gear rated at T
  does not skip at T; the catalogue's ratcheting torques are 5–10× the rated ones), the path's
  torque rises with the rotation up to the estimate (rotation control: the limit point is T's
  first maximum), a catalogue value given is compared and no warning says it is missing.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from profilegen.contact import ratchet
from tests.oracles.cs_ring import CSRing, cs_ring_compliance
from profilegen.contact.ratchet import cs_ring_radial_compliance

R, H, B, E = 57.5, 13.0, 20.0, 206000.0


def _w(at, loads, *, h=H, b=B, harmonics=200):
    return cs_ring_radial_compliance(loads, at, mean_radius_mm=R, thickness_mm=h, width_mm=b,
                                     youngs_modulus_mpa=E, harmonics=harmonics)


def test_ring_compliance_is_the_formula_with_the_sections_own_dimensions():
    at, loads = np.array([0.0, 0.3, 1.7]), np.array([0.0, 2.0])
    area, inertia = B * H, B * H ** 3 / 12.0  # b along the axis, h radial
    n = np.arange(2, 201)
    d = at[:, None] - loads[None, :]
    expected = R / (2.0 * math.pi * E * area) + (np.cos(d[..., None] * n) @ (R ** 3 / (E * inertia * (n * n - 1.0) ** 2))) / math.pi
    np.testing.assert_allclose(_w(at, loads), expected, rtol=1e-12)


def test_ring_compliance_scales_as_one_over_width_and_thickness_cubed():
    at, loads = np.array([0.0, 0.5 * math.pi]), np.array([0.0])
    base = _w(at, loads)
    np.testing.assert_allclose(_w(at, loads, b=2 * B), 0.5 * base, rtol=1e-12)  # ∝ 1/b, hoop and bending alike
    hoop = R / (2.0 * math.pi * E * B * H)
    bending = base - hoop
    np.testing.assert_allclose(_w(at, loads, h=2 * H) - hoop / 2.0, bending / 8.0, rtol=1e-12)  # bending ∝ h⁻³
    # swapping the two dimensions is not a symmetry: (b, h) → (h, b) scales the bending by (h/b)²
    swapped = _w(at, loads, h=B, b=H) - R / (2.0 * math.pi * E * B * H)
    np.testing.assert_allclose(swapped, bending * (H / B) ** 2, rtol=1e-12)


def test_ring_compliance_agrees_with_the_cs_ring_module():
    """Two implementations of the same ring: ratchet's per-load radial compliance summed over a
    load and its image at θ + π (the two zones), and cs_ring's two-zone S for radial directions."""
    theta = np.array([-0.4, 0.0, 0.25, 0.9])
    pts = R * np.column_stack([np.sin(theta), np.cos(theta)])  # the package's angle: from +y toward +x
    dirs = pts / R  # radial, outward on the CS
    ring = CSRing(R - 0.5 * H, R + 0.5 * H, B, E)
    s = cs_ring_compliance(ring, pts, dirs, zones=2, harmonics=200)
    w = _w(theta, np.concatenate([theta, theta + math.pi]))
    np.testing.assert_allclose(s, w[:, :4] + w[:, 4:], rtol=1e-9)


def test_the_contacts_ring_along_any_direction_is_the_second_implementations():
    """The package's ring (contact.cs_ring: e^{inψ} by products, the contact normals' radial and
    tangential parts) against the oracle's term-by-term cos/sin sum, for directions that are
    not radial (a tooth's normal is mostly tangential): every term of S_kj, the sin nψ one
    included, and symmetric."""
    from profilegen.contact.cs_ring import CSRing as Ring, contact_ring_compliance

    rng = np.random.default_rng(7)
    theta = rng.uniform(-0.8, 0.8, 9)
    pts = (R + rng.uniform(-3.0, 3.0, 9))[:, None] * np.column_stack([np.sin(theta), np.cos(theta)])
    dirs = rng.normal(size=(9, 2))
    dirs /= np.hypot(*dirs.T)[:, None]
    s = contact_ring_compliance(Ring(R, H, B, E), pts, dirs, zones=2)
    oracle = cs_ring_compliance(CSRing(R - 0.5 * H, R + 0.5 * H, B, E), pts, dirs, zones=2, harmonics=200)
    np.testing.assert_allclose(s, oracle, rtol=1e-12, atol=1e-12 * np.abs(oracle).max())
    assert np.abs(s - s.T).max() == 0.0
    # a tangential pair of forces only (b_k = b_j = 1): the n/n² weighting of the tangential load
    tang = contact_ring_compliance(Ring(R, H, B, E), pts[:2], np.column_stack([np.cos(theta[:2]),
                                                                               -np.sin(theta[:2])]))
    n = np.arange(2, 201, 2)
    psi = theta[0] - theta[1]
    c = 2.0 * R ** 3 / (math.pi * E * B * H ** 3 / 12.0 * (n * n - 1.0) ** 2)
    assert tang[0, 1] == pytest.approx(float(np.sum(c / (n * n) * np.cos(n * psi))), rel=1e-12)


def test_roark_two_opposite_loads_on_the_contacts_ring():
    """Two opposite radial loads P on a thin ring (Roark, thin circular rings): the diameter
    through them grows by 0.1488 P R³/EI and the one across shrinks by 0.1366 P R³/EI — here
    with the ring's hoop extension (R/(E A) on each diameter, known) taken off."""
    from profilegen.contact.cs_ring import CSRing as Ring, ring_compliance

    ring = Ring(R, H, B, E)
    w = ring_compliance(ring, [0.0, 0.5 * math.pi], [0.0], zones=2)[:, 0]
    # the hoop mode: each load P/(2πR) per unit length on both → w_0 = P R/(π E A), the diameter 2 w_0
    ei, hoop = E * ring.second_moment_mm4, 2.0 * R / (math.pi * E * ring.area_mm2)
    assert 2.0 * w[0] - hoop == pytest.approx(0.1488 * R ** 3 / ei, rel=2e-3)
    assert 2.0 * w[1] - hoop == pytest.approx(-0.1366 * R ** 3 / ei, rel=2e-3)


def test_the_contact_holds_the_ring_and_without_it_the_sector_alone(default_sketch):
    """ContactCompliance.build adds the ring at the CS points along the FS normals to the CS
    block, nothing else: the sector alone (cs_ring=False) + the ring = the default, the FS
    block untouched; the ring's section is the one the climb takes."""
    from profilegen.contact.compliance import ContactCompliance
    from profilegen.contact.cs_ring import contact_ring_compliance
    from profilegen.contact.inputs import ContactInput
    from profilegen.contact.points import contact_points

    inputs = ContactInput.from_design(default_sketch)
    pts = contact_points(inputs, side=1, stations=3, max_gap_mm=0.05)
    args = (inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm)
    with_ring = ContactCompliance.build(*args)
    alone = ContactCompliance.build(*args, cs_ring=False)
    ring = contact_ring_compliance(with_ring.cs_ring, pts.cs_point_mm, pts.normal)
    np.testing.assert_allclose(with_ring.cs_matrix_mm_per_n, alone.cs_matrix_mm_per_n + ring, rtol=1e-12,
                               atol=1e-14 * np.abs(ring).max())
    np.testing.assert_array_equal(with_ring.fs_matrix_mm_per_n, alone.fs_matrix_mm_per_n)
    assert alone.cs_ring is None and alone.cs_ring_mm_per_n is None
    r_mean, thick, width, _ = ratchet._cs_ring_section(inputs.gearset, inputs)
    assert (with_ring.cs_ring.mean_radius_mm, with_ring.cs_ring.thickness_mm, with_ring.cs_ring.width_mm) == \
        (r_mean, thick, width)
    # the two zones push the ring out at the major axis: the ring adds to every point's own compliance
    assert np.all(np.diag(ring) > 0.0)


def test_cs_ring_section_properties_from_their_definitions():
    ring = CSRing(51.0, 64.0, 20.0, E)
    assert ring.thickness_mm == 13.0 and ring.radius_mm == 57.5
    assert ring.second_moment_mm4 == pytest.approx(20.0 * 13.0 ** 3 / 12.0, rel=1e-15)
    assert ring.area_mm2 == pytest.approx(20.0 * 13.0, rel=1e-15)


def test_ratcheting_takes_the_cs_rings_own_section(default_sketch):
    from profilegen.contact.inputs import ContactInput
    from profilegen.contact.points import contact_points

    inputs = ContactInput.from_design(default_sketch)
    gs = inputs.gearset
    r_mean, thick, width, _ = ratchet._cs_ring_section(gs, inputs)
    ring = CSRing.from_gearset(gs)  # the gear set's estimate of the same ring
    assert width == ring.width_mm == gs.cup.face_width_mm
    assert thick == pytest.approx(ring.thickness_mm, abs=0.05)  # the fitted root circle vs r1 + ha + w0 + m/4
    assert r_mean == pytest.approx(ring.radius_mm, abs=0.05)


# --------------------------------------------------------------------------- end to end


@pytest.fixture(scope="module")
def climbed(default_sketch):
    """ratcheting_torque(climb=True) on the sketch design, few stations (~4 s), with every ring
    the climb is handed recorded."""
    calls = []
    real = ratchet.cs_ring_radial_compliance

    def spy(angles_rad, at_rad, **kw):
        calls.append(kw)
        return real(angles_rad, at_rad, **kw)

    mp = pytest.MonkeyPatch()
    mp.setattr(ratchet, "cs_ring_radial_compliance", spy)
    try:
        r = ratchet.ratcheting_torque(default_sketch,
                                      catalogue={"torque_nm": 2000.0, "source": "a stand-in value for the test"},
                                      options=ratchet.RatchetingOptions(torques_nm=[132.5, 265.0], stations=3,
                                                                        climb_stations=3, climb_max_gap_mm=0.08))
    finally:
        mp.undo()
    return r, calls


def test_climb_end_to_end_estimate(climbed, default_sketch):
    r, _ = climbed
    rated = default_sketch.gearset.torque.rated_nm
    assert r.climb is not None and r.climb["criterion"] in ("limit point", "end of path", "margin", "corner")
    assert math.isfinite(r.torque_nm) and r.torque_nm > 2.0 * rated
    assert r.torque_nm == pytest.approx(r.climb["torque_nm"])
    assert r.ratio_to_catalogue == pytest.approx(r.torque_nm / 2000.0)
    assert not any("no catalogue" in w for w in r.warnings)
    phi = np.array(r.climb["phi_path_rad"])
    torque = np.array(r.climb["torque_path_nm"])
    assert np.all(np.diff(phi) > 0.0)
    before = torque[phi <= r.climb["phi_rad"] + 1e-15]
    assert before.size >= 3 and np.all(np.diff(before) > 0.0)  # T rises with φ up to the estimate
    assert r.torque_nm >= 0.98 * before.max()


def test_climb_is_handed_the_rings_own_section(climbed, default_sketch):
    """Every ring handed out (the linear diagnostics' and the climb's factory): width = the face
    width, thickness = the radial one (not swapped), the mean radius between root and held radius."""
    r, calls = climbed
    ring = CSRing.from_gearset(default_sketch.gearset)
    assert len(calls) >= 2  # the linear part's ring and at least one of the climb's
    for kw in calls:
        assert kw["width_mm"] == ring.width_mm
        assert kw["thickness_mm"] == pytest.approx(ring.thickness_mm, abs=0.05)
        assert kw["mean_radius_mm"] == pytest.approx(ring.radius_mm, abs=0.05)
        assert kw["youngs_modulus_mpa"] == default_sketch.gearset.material.youngs_modulus_mpa
    assert r.parts["cs_ring"]["width_mm"] == ring.width_mm
