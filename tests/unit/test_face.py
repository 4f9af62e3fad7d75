"""Face width and FS tooth modification along the face (profilegen.face, issue 15 items 4, 5).

Built on hand-made 3D deformations (ring theory's ω = w cos 2φ, υ = −(w/2) sin 2φ with w a
given function of the axial position z), so each check has an answer known without the code:
identical sections give identical rows; a CS made from one section's own envelope touches
that section's tooth (its 2D design-section map, computed by the 2D stages directly); a
linear change of ω across the face is compensated by a linear tooth-thickness taper.
"""

from __future__ import annotations

import numpy as np
import pytest

from profilegen.geometry.deformation import ring_theory
from profilegen.profile.envelope import envelope_of
from profilegen.face import FaceError, face_width, solve_modification
from profilegen.profile.gearform import circular_spline_form, clearance_map
from profilegen.gearset import load_gearset
from profilegen.geometry.kinematics import HarmonicDriveMotion
from profilegen.geometry.teeth import tooth_from_gearset

SPAN = (50.0, 70.0)
SAMPLES = 61  # map poses (the stage's default is 181)
TWIST = 3e-4  # υ amplitude change per mm of face (mm/mm): 6 µm over the face; 2 µm interference at mid-face


class RingAlongFace:
    """ω(φ, z) = w(z) cos 2φ, υ(φ, z) = −w(z)/2 · sin 2φ (ring theory, inextensible) on a tooth
    ring spanning SPAN."""

    ring_span_mm = SPAN

    def __init__(self, w):
        self.w = w

    def omega(self, phi, z):
        return self.w(np.asarray(z, float)) * np.cos(2 * np.asarray(phi, float))

    def upsilon(self, phi, z):
        return -0.5 * self.w(np.asarray(z, float)) * np.sin(2 * np.asarray(phi, float))


# one xdist worker runs the whole module (pyproject: --dist loadgroup): its module fixtures would
# otherwise be computed on both workers, each running a share of its tests (conftest.py)
pytestmark = pytest.mark.xdist_group("test_face")


@pytest.fixture(scope="module")
def gearset():
    return load_gearset("profiles/default.toml")


@pytest.fixture(scope="module")
def uniform(gearset):
    """The same deformation at every section: w = w0."""
    w0 = gearset.deflection_mm
    return face_width(gearset, RingAlongFace(lambda z: w0 + 0 * z), sections=3, design_section=SPAN[0],
                      map_samples=SAMPLES)


@pytest.fixture(scope="module")
def linear(gearset):
    """ω growing linearly toward the open end, ±2 % about the mid-face; the CS from the mid-face."""
    w0 = gearset.deflection_mm
    mid = 0.5 * sum(SPAN)
    return face_width(gearset, RingAlongFace(lambda z: w0 * (1.0 + 0.002 * (z - mid))), sections=3,
                      design_section=mid, map_samples=SAMPLES)


class TwistAlongFace(RingAlongFace):
    """Ring theory at every section with υ's amplitude changed linearly along the face:
    υ = (−w0/2 + k (z − z_mid)) sin 2φ — a tangential shift of the tooth that is the same on both
    flanks in mesh (sin 2φ is odd, so is the flank side), which a thickness change undoes."""

    def __init__(self, w0, k):
        super().__init__(lambda z: w0 + 0 * z)
        self.k = k

    def upsilon(self, phi, z):
        return (-0.5 * self.w(np.asarray(z, float)) + self.k * (np.asarray(z, float) - 0.5 * sum(SPAN))) * np.sin(
            2 * np.asarray(phi, float))


@pytest.fixture(scope="module")
def twisted(gearset):
    return face_width(gearset, TwistAlongFace(gearset.deflection_mm, TWIST), sections=3, design_section=SPAN[0],
                      map_samples=SAMPLES)


def test_identical_sections_give_identical_rows(gearset, uniform):
    rows = uniform.table
    assert len(rows) == 3
    for key in ("min_clearance_mm", "max_backlash_mm", "omega_major_mm", "upsilon_max_mm"):
        values = [getattr(r, key) for r in rows]
        assert np.ptp(values) < 1e-12, key
    # every section's map is the design section's: the spread over the face is zero
    assert np.max(np.ptp(uniform.clearance_mm, axis=0)) < 1e-12
    # every row touches the CS (the one profile is each section's own envelope)
    assert abs(rows[0].min_clearance_mm) < 10 * uniform.chord_tol_mm
    assert rows[0].max_backlash_mm < 1e-3
    assert rows[0].omega_major_mm == pytest.approx(gearset.deflection_mm, rel=1e-12)


def test_design_section_irrelevant_for_identical_sections(gearset, uniform):
    other = face_width(gearset, RingAlongFace(lambda z: gearset.deflection_mm + 0 * z), sections=3,
                       design_section=SPAN[1], map_samples=SAMPLES)
    assert other.design_section_z_mm == SPAN[1] and uniform.design_section_z_mm == SPAN[0]
    np.testing.assert_allclose(other.clearance_mm, uniform.clearance_mm, atol=1e-12)
    assert other.max_interference_mm == pytest.approx(uniform.max_interference_mm, abs=1e-12)


def test_design_row_is_the_2d_design_map(gearset, linear):
    """The face map's row at the design section = the clearance map the 2D stages give for that
    section (ring theory with its w, traced, formed and mapped directly)."""
    d = linear.design_index
    zd = linear.design_section_z_mm
    assert zd == pytest.approx(60.0)
    g = gearset.gear
    tooth = tooth_from_gearset(gearset)
    motion = HarmonicDriveMotion.from_gearset(gearset, ring_theory(gearset.deflection_mm))  # w(z_d) = w0
    env = envelope_of(tooth, motion, cs_teeth=g.circular_spline_teeth, waves=g.waves, chord_tol_mm=1e-4)
    cs = gearset.circular_spline
    form = circular_spline_form(env, cs_teeth=g.circular_spline_teeth, tip_clearance_mm=cs.tip_clearance_mm,
                                root_clearance_mm=cs.root_clearance_mm)
    cmap = clearance_map(form, tooth, motion, phi_range=env.phi_range, samples=SAMPLES)
    # exact near contact; farther out of mesh (> 10 µm) the map's candidate search reads up to ~1 µm high
    near = cmap.clearance_mm < 1e-2
    np.testing.assert_allclose(linear.clearance_mm[d][near], cmap.clearance_mm[near], atol=2e-7)
    np.testing.assert_allclose(linear.clearance_mm[d], cmap.clearance_mm, atol=1e-3)
    assert linear.clearance_mm[d].min() == pytest.approx(cmap.min_mm, abs=2e-7)
    # and the map's minimum over the face at the design section is that section's row: the sampled
    # one (its own CS touches it; a parabola through the edge of the touching poses dips below 0)
    assert linear.table[d].min_clearance_mm == linear.clearance_mm[d].min()


def test_a_touching_minimum_is_the_samples_not_a_parabola_through_a_kink():
    """The design section touches its own CS (c ≈ 0) over the engaged poses and its clearance rises
    beyond them: the parabola through the last touching samples and the first rising one has its
    vertex between two zeros and below them — csf58_50 with ω* = 0.6, design scene: −2.77 µm, which no
    tooth modification could clear (the design section never moves), and the face FAILed where the
    verify scene cleared it. An interfering minimum between samples is still refined."""
    from profilegen.face.clearance import parabolic_minimum

    phi = np.radians(np.arange(-62.0, -54.0))
    plateau = np.array([8e-3, 3.0e-3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])  # rising beyond the engaged zone
    low, _ = parabolic_minimum(phi, plateau)
    assert low == 0.0  # a touch is the sample's
    assert parabolic_minimum(phi, plateau - 1e-3)[0] < -1e-3 - 1e-4  # an interfering one is refined
    smooth = (np.degrees(phi) + 57.6) ** 2 * 1e-4 - 5e-3  # an interference between samples, at -57.6°
    value, at = parabolic_minimum(phi, smooth)
    assert value == pytest.approx(-5e-3, abs=1e-12) and np.degrees(at) == pytest.approx(-57.6)


def test_linear_change_is_compensated_by_a_taper(gearset, twisted):
    # the CS from the diaphragm end interferes more and more toward the open end (linearly)
    rows = twisted.table
    assert rows[1].min_clearance_mm < -1e-3 and rows[2].min_clearance_mm < 1.5 * rows[1].min_clearance_mm
    mod = solve_modification(gearset, TwistAlongFace(gearset.deflection_mm, TWIST), twisted, crowning=False)
    assert not mod.warnings
    assert mod.taper_mm_per_mm < 0  # thinner toward the open end
    assert mod.max_interference_mm <= twisted.interference_tol_mm
    assert max(-r.min_clearance_mm for r in mod.table) <= twisted.interference_tol_mm
    assert mod.thickness_change_mm[twisted.design_index] == 0.0
    # linear in z: the open end's change is twice the mid-face's
    assert mod.thickness_change_mm[2] == pytest.approx(2 * mod.thickness_change_mm[1], rel=1e-12)
    # and the taper is not larger than it needs to be: the sections end near contact (< 1 µm)
    assert all(r.min_clearance_mm < 1e-3 for r in mod.table)


def test_radial_interference_is_left_to_the_design_section(gearset, linear):
    """ω changing along the face: the mid-face CS interferes at both ends (the deeper tooth's tip,
    the shallower tooth's root lands against the CS tips); thinning cannot help, the solver
    says so instead of returning an interfering modification silently."""
    # (the envelopes' gap, independent of the map's pose sampling)
    assert linear.table[0].min_gap_mm < -1e-3 and linear.table[2].min_gap_mm < -1e-3
    assert any("interfer" in w for w in linear.warnings)


@pytest.mark.parametrize("z", [49.0, 70.5, "middle"])
def test_design_section_outside_the_tooth_ring(gearset, z):
    with pytest.raises(FaceError, match=r"design_section_z_mm.*mm.*\[50, 70\]") as err:
        face_width(gearset, RingAlongFace(lambda z: 0.5 + 0 * z), design_section=z)
    assert isinstance(err.value, ValueError)


def test_not_a_3d_deformation(gearset):
    with pytest.raises(FaceError, match="deformation"):
        face_width(gearset, ring_theory(0.5))


def test_modified_tooth_moves_each_flank_by_half_the_thickness_change(gearset):
    from profilegen.face import modified_tooth, thickness_change

    plain, thicker = tooth_from_gearset(gearset), modified_tooth(gearset, 0.01)
    # the DCTA line through the pitch point moves along the tooth frame's x by Δs/2, nothing else
    np.testing.assert_allclose(thicker.segments[1].start - plain.segments[1].start, [0.005, 0.0], atol=1e-15)
    # Δs(z): zero at the design section, the taper's slope, the crowning at the face ends
    ds = thickness_change([50.0, 60.0, 70.0], taper_mm_per_mm=-1e-3, crowning_mm=0.02, design_z_mm=60.0,
                          ring_span_mm=SPAN)
    np.testing.assert_allclose(ds, [0.01 - 0.02, 0.0, -0.01 - 0.02], atol=1e-15)


def test_when_the_lp_finds_nothing_a_search_on_the_exact_maps_does(gearset, twisted, monkeypatch):
    """The LP linearises the clearance in the thickness change; where the nearest contact changes
    with it (three bundled sets in the verify scene) it can declare an interference-free taper
    infeasible. The fallback searches along the taper on the exact maps (regula falsi): on the twisted face,
    with the LP made to fail, it finds the LP's own taper to its resolution (1/512 of the field's
    0.01 mm/mm range), interference-free, and says which path it took."""
    import scipy.optimize

    lp = solve_modification(gearset, TwistAlongFace(gearset.deflection_mm, TWIST), twisted, crowning=False)

    class Failed:
        status, message, x = 2, "forced failure (test)", None

    monkeypatch.setattr(scipy.optimize, "linprog", lambda *a, **k: Failed())
    mod = solve_modification(gearset, TwistAlongFace(gearset.deflection_mm, TWIST), twisted, crowning=False)
    assert any("regula falsi" in w for w in mod.warnings)
    assert mod.max_interference_mm <= 0.1 * twisted.interference_tol_mm
    assert mod.taper_mm_per_mm == pytest.approx(lp.taper_mm_per_mm, abs=0.01 / 512 + 1e-9)
    assert mod.crowning_mm == 0.0
