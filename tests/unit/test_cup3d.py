"""The 3D cup tier's fast formulation (profilegen.rim.cup): the cup as a body of revolution,
one meridional FEM problem per Fourier harmonic, checked against things it does not compute
itself:

* the batched assembly equals scikit-fem's BilinearForms (the harmonic forms, linear_elasticity);
* rigid-body motions of harmonics 0 and 1 store no energy (the strain operator's kinematics),
  a non-rigid one does;
* harmonic 0 against Lamé's thick cylinder (open ends), with its observed convergence rate;
* a long cup reduces to ring theory at the loaded section (inextensible ring: ω = w0 cos 2φ,
  υ = −(w0/2) sin 2φ, within 1 %), and the default-length cup does not (coning);
* the wall end's axial displacement against the stress stage's semi-membrane w(φ) (seed 002);
* mesh convergence of the cup with an observed rate; equilibrium of the reactions (n = 0, 1);
  symmetric stiffness; the 3D solid's cos 2φ antisymmetry about φ = π/4;
* the fast formulation against a plain 3D solid (27-node hexahedra) of the same cup: the
  difference falls with the solid's circumferential sectors at a rate ≥ 3;
* bad geometry raises CupError naming the field.

Meshes are coarse (the whole file runs in a few seconds); tests/benchmarks/cup3d.py has the
fine ones and the timings.
"""

import math

import numpy as np
import pytest

from profilegen.rim.cup import CupError, CupGeometry, bore_load, harmonic_stiffness, meridional_mesh, solve_cup
from profilegen.rim.cup.assembly import elasticity_3d, harmonic_parts
from profilegen.rim.cup.fourier import harmonic_forms, lame

E, NU = 209000.0, 0.295
R_M, T = 48.95, 0.9
W0 = 0.5


def cup(length=60.0, **kw):
    """The default set's cup (r_m, δ, [cup] estimates: l = 0.6 d, b = 0.2 d, t_b = δ, r0 = r_m/2)."""
    return CupGeometry(R_M, T, length, 20.0, T, 0.5 * R_M, E, NU, **kw)


@pytest.fixture(scope="module")
def default_cup():
    return cup()


# --------------------------------------------------------------------------- assembly


def test_batched_harmonic_parts_equal_the_bilinear_forms():
    from skfem import Basis, ElementQuad2, ElementVector, MeshQuad, MeshQuad2, asm

    mesh = MeshQuad2.from_mesh(MeshQuad.init_tensor(np.array([10.0, 10.7, 12.0]), np.array([0.0, 0.6, 2.0])))
    lam, mu = lame(E, NU)
    vec = Basis(mesh, ElementVector(ElementQuad2(), dim=3), intorder=4)
    scalar = Basis(mesh, ElementQuad2(), intorder=4)
    iu, iw, iv = vec.split_indices()
    assert np.allclose(vec.doflocs[:, iu], scalar.doflocs)
    order = np.column_stack([iu, iw, iv]).ravel()  # our dof 3k + c ↔ scikit-fem's
    for form, mine in zip(harmonic_forms(), harmonic_parts(scalar, lam, mu)):
        ref = asm(form, vec, lam=lam, mu=mu).toarray()[np.ix_(order, order)]
        assert np.max(np.abs(mine.toarray() - ref)) <= 1e-12 * np.max(np.abs(ref))


def test_batched_3d_elasticity_equals_linear_elasticity():
    from skfem import Basis, ElementHex1, ElementVector, MeshHex, asm
    from skfem.models.elasticity import linear_elasticity

    mesh = MeshHex.init_tensor(np.array([0.0, 1.0]), np.array([0.0, 0.5, 2.0]), np.array([0.0, 0.3]))
    mesh = mesh.translated([0.0, 0.0, 0.0])
    lam, mu = lame(E, NU)
    vec = Basis(mesh, ElementVector(ElementHex1()))
    scalar = Basis(mesh, ElementHex1())
    ix, iy, iz = vec.split_indices()
    order = np.column_stack([ix, iy, iz]).ravel()
    ref = asm(linear_elasticity(lam, mu), vec).toarray()[np.ix_(order, order)]
    mine = elasticity_3d(scalar, lam, mu).toarray()
    assert np.max(np.abs(mine - ref)) <= 1e-12 * np.max(np.abs(ref))


@pytest.fixture(scope="module")
def coarse_basis(default_cup):
    return harmonic_stiffness(meridional_mesh(default_cup, element_mm=4.0, layers=1))


def test_rigid_body_motions_store_no_energy(coarse_basis):
    hb = coarse_basis
    r, z = hb.nodes
    iu, iw, iv = hb.components()

    def mode(u=0.0, w=0.0, v=0.0):
        x = np.zeros(hb.dof)
        x[iu], x[iw], x[iv] = u, w, v
        return x

    scale = abs(hb.stiffness(2)).max() * W0
    rigid = {0: [mode(w=1.0), mode(v=r)],  # axial translation, rotation about the axis
             1: [mode(u=1.0, v=-1.0), mode(u=z, w=-r, v=-z)]}  # translation along φ = 0, tilt about φ = π/2
    for n, modes in rigid.items():
        for x in modes:
            assert np.max(np.abs(hb.stiffness(n) @ x)) <= 1e-10 * scale * max(1.0, np.max(np.abs(x)))
    # the same fields in harmonic 2 are not rigid (an ovalisation): they must load the mesh
    assert np.max(np.abs(hb.stiffness(2) @ mode(u=1.0, v=-1.0))) > 1e-3 * scale


def test_stiffness_is_symmetric(coarse_basis):
    for n in (0, 1, 2, 6):
        k = coarse_basis.stiffness(n)
        assert abs(k - k.T).max() <= 1e-12 * abs(k).max()


# --------------------------------------------------------------------------- Lamé (n = 0)


def _lame_error(layers: int) -> float:
    """Max nodal |u_r − Lamé| of a thick tube a = 10, b = 20 mm, length 10 mm, open ends, bore
    pressed out by 0.01 mm (frictionless), outer surface free; n = 0."""
    from scipy.sparse.linalg import spsolve
    from skfem import Basis, ElementQuad2, MeshQuad, MeshQuad2

    a, b, u_a = 10.0, 20.0, 0.01
    mesh = MeshQuad2.from_mesh(MeshQuad.init_tensor(np.linspace(a, b, layers + 1), np.linspace(0.0, 10.0, 3)))
    basis = Basis(mesh, ElementQuad2(), intorder=4)
    k00 = harmonic_parts(basis, *lame(E, NU))[0] * 2.0 * math.pi
    r, z = basis.doflocs
    node = np.arange(basis.N)
    iu, iw, iv = 3 * node, 3 * node + 1, 3 * node + 2
    bore = node[np.abs(r - a) < 1e-12]
    pin = node[(np.abs(r - a) < 1e-12) & (np.abs(z) < 1e-12)]
    fixed = np.concatenate([iu[bore], iw[pin], iv])  # V: the (decoupled) torsion, held
    x = np.zeros(3 * basis.N)
    x[iu[bore]] = u_a
    free = np.setdiff1d(np.arange(x.size), fixed)
    x[free] = spsolve(k00[free][:, free].tocsc(), -(k00[free][:, fixed] @ x[fixed]))
    # Lamé, σ_z = 0: u = ((1 − ν) A r + (1 + ν) B / r)/E, σ_r = A − B/r² = 0 at b
    bb = u_a * E / ((1 - NU) * a / b**2 + (1 + NU) / a)
    exact = ((1 - NU) * bb / b**2 * r + (1 + NU) * bb / r) / E
    return float(np.max(np.abs(x[iu] - exact)))


def test_harmonic_zero_is_lames_thick_cylinder_with_its_convergence_rate():
    errors = [_lame_error(layers) for layers in (1, 2, 4)]
    rates = [math.log2(errors[i] / errors[i + 1]) for i in range(2)]
    assert errors[-1] < 1e-6  # mm, of a 0.01 mm load (measured 3.8e-7 with 4 layers)
    assert min(rates) > 3.5, (errors, rates)  # measured 3.8, 3.9: O(h⁴) at the nodes (quadratic elements)


# --------------------------------------------------------------------------- the cup


def test_long_cup_reduces_to_ring_theory_at_the_loaded_section():
    long = cup(length=300.0)  # l ≈ 6 r_m: the diaphragm far away
    res = solve_cup(long, radial_mm={2: W0}, element_mm=4.0, layers=2)
    phi = np.linspace(0.0, 0.5 * math.pi, 37)
    w, u = res.omega(phi, 300.0), res.upsilon(phi, 300.0)
    assert np.max(np.abs(w - W0 * np.cos(2 * phi))) < 0.01 * W0
    assert np.max(np.abs(u + 0.5 * W0 * np.sin(2 * phi))) < 0.01 * 0.5 * W0
    # ... while the default cup (l ≈ 1.2 r_m) cones: its open end's υ is ~16 % above ring theory
    short = solve_cup(cup(), radial_mm={2: W0}, element_mm=4.0, layers=2)
    assert abs(short.upsilon(math.pi / 4, 70.0) + 0.5 * W0) > 0.1 * 0.5 * W0


@pytest.mark.parametrize("length", [60.0, 120.0])
def test_wall_end_axial_displacement_is_the_semi_membrane_one(length):
    from profilegen.stress.plate import edge_displacement

    geometry = cup(length=length, bearing_width_mm=4.0)
    res = solve_cup(geometry, radial_mm={2: W0}, element_mm=2.0, layers=2)
    semi = edge_displacement({2: W0}, mean_radius_mm=R_M, length_mm=length).harmonics[2]  # r_m w0 / 4l
    end = res.z_mm[0]  # the wall's end at the bottom
    # sign: the wall end on the major axis moves away from the open end (−z), W = (r/n) ∂υ/∂z
    assert res.axial(0.0, end) < 0.0
    assert abs(-res.axial(0.0, end) / semi - 1.0) < 0.015
    assert abs(res.omega(0.0, end)) < 0.02 * W0  # the bottom holds the wall's end round


def test_mesh_convergence_has_an_observed_rate(default_cup):
    values = []
    for h in (2.0, 1.0, 0.5):
        res = solve_cup(default_cup, radial_mm={2: W0}, element_mm=h, layers=2)
        values.append([res.axial(0.0, res.z_mm[0]), res.upsilon(math.pi / 4, 70.0), res.tilt(0.0, 40.0)])
    values = np.array(values)
    d1, d2 = np.abs(values[1] - values[0]), np.abs(values[2] - values[1])
    rates = np.log2(d1 / d2)
    assert np.all(rates > 1.2), rates  # ~1.6: the bearing's edges (a rigid punch) are singular
    assert np.max(d2[:2]) < 2e-5  # mm, ω and υ settled to tens of nm
    # the open end flares: ω at the open end vs mid-face, υ beyond ring theory's w0/2
    assert -values[2][1] > 0.55 * W0


def test_equilibrium_of_the_reactions(default_cup):
    res = solve_cup(default_cup, radial_mm={0: 0.01, 1: 0.1, 2: W0}, element_mm=2.0, layers=1)
    by_n = dict(zip(res.orders.tolist(), zip(res.boss_reaction, res.bore_reaction)))
    boss1, bore1 = by_n[1]
    assert abs(bore1[0]) > 1.0 and abs(bore1[1]) > 1.0  # N, N·mm: a real load
    for boss, bore in (by_n[0], by_n[1]):
        for a, b in zip(boss, bore):
            assert abs(a + b) <= 1e-7 * max(abs(bore1[0]), abs(bore1[1]) / 60.0) * 60.0
    assert by_n[2] == ((), ())  # a cos 2φ distribution has no resultant


def test_contour_load_is_its_cosine_series(default_cup):
    from profilegen.geometry.wavegen import CosineCam

    load = bore_load(CosineCam(default_cup.bore_radius_mm, W0), default_cup.bore_radius_mm)
    assert set(load) == {2} and abs(load[2] - W0) < 1e-12


def test_gearset_cup_and_its_cam(default_cup):
    from profilegen.gearset import load_gearset

    gs = load_gearset("profiles/default.toml")
    g = CupGeometry.from_gearset(gs)
    assert g.length_mm == pytest.approx(60.0) and g.face_width_mm == pytest.approx(20.0)
    res = solve_cup(gs, element_mm=4.0, layers=1)
    assert abs(res.omega(0.0, g.length_mm) - gs.deflection_mm) < 1e-3  # the cam's major axis: w0 at the bore
    assert set(res.orders.tolist()) <= set(range(0, 17, 2))


# --------------------------------------------------------------------------- against the 3D solid


def test_fourier_formulation_agrees_with_the_3d_solid(default_cup):
    from tests.oracles.solid_cup import solve_solid_cup

    mesh = meridional_mesh(default_cup, element_mm=8.0, layers=1)
    fourier = solve_cup(default_cup, radial_mm={2: W0}, harmonic_basis=harmonic_stiffness(mesh))
    diffs = []
    for sectors in (3, 6):
        solid = solve_solid_cup(default_cup, radial_mm={2: W0}, cup_mesh=mesh, sectors=sectors)
        wall = solid.z_mm > 0.5 * T - 1e-9
        th, z = solid.theta_rad[wall], solid.z_mm[wall]
        diffs.append(max(np.max(np.abs(solid.omega_mm[wall] - fourier.omega(th, z))),
                         np.max(np.abs(solid.upsilon_mm[wall] - fourier.upsilon(th, z)))))
        if sectors == 6:  # symmetry: a cos 2φ field is odd about φ = π/4 (ω) resp. even (υ)
            key = np.round(np.column_stack([th, z]), 9)
            mirror = np.round(np.column_stack([0.5 * math.pi - th, z]), 9)
            index = {tuple(k): i for i, k in enumerate(key)}
            j = np.array([index[tuple(m)] for m in mirror])
            w, u = solid.omega_mm[wall], solid.upsilon_mm[wall]
            assert np.max(np.abs(w + w[j])) < 1e-9 and np.max(np.abs(u - u[j])) < 1e-9
    assert diffs[1] < 5e-4 * W0 and diffs[0] / diffs[1] > 8.0, diffs  # the solid's sectors: rate ≥ 3


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize("kw, field", [
    (dict(face_width_mm=125.0), "face_width_mm"),  # wider than the cup: l − b/2 < t_b/2
    (dict(bearing_width_mm=25.0), "bearing_width_mm"),  # wider than the face
    (dict(bearing_center_mm=75.0), "bearing_center_mm"),  # outside the tooth ring
    (dict(bearing_width_mm=10.0, bearing_center_mm=52.0), "bearing_center_mm"),  # sticks out of it
    (dict(boss_radius_mm=48.6), "boss_radius_mm"),  # outside the bore
    (dict(bottom_thickness_mm=61.0), "bottom_thickness_mm"),
    (dict(wall_thickness_mm=-0.9), "wall_thickness_mm"),
])
def test_bad_geometry_names_the_field(kw, field):
    base = dict(neutral_radius_mm=R_M, wall_thickness_mm=T, length_mm=60.0, face_width_mm=20.0,
                bottom_thickness_mm=T, boss_radius_mm=0.5 * R_M, youngs_modulus_mpa=E, poisson_ratio=NU)
    base.update(kw)
    with pytest.raises(CupError, match=field) as info:
        CupGeometry(**base)
    assert isinstance(info.value, ValueError) and "mm" in str(info.value)


def test_bad_load_and_position_are_named(default_cup, coarse_basis):
    with pytest.raises(CupError, match="radial_mm"):
        solve_cup(default_cup, harmonic_basis=coarse_basis)
    res = solve_cup(default_cup, radial_mm={2: W0}, harmonic_basis=coarse_basis)
    with pytest.raises(CupError, match="z_mm"):
        res.omega(0.0, 80.0)
    from tests.oracles.solid_cup import solve_solid_cup

    with pytest.raises(CupError, match="radial_mm order 1"):
        solve_solid_cup(default_cup, radial_mm={1: 0.1})


# --------------------------------------------------------------------------- unilateral contact


@pytest.fixture(scope="module")
def pressed():
    from profilegen.gearset import load_gearset
    from profilegen.rim.cup import press_cup

    return press_cup(load_gearset("profiles/default.toml"), element_mm=4.0, angles=8)


def test_contact_is_complementary_and_its_harmonics_add_up(pressed):
    c = pressed
    scale = float(np.max(c.force_n))
    assert np.all(c.force_n >= 0.0) and c.max_penetration_mm < 1e-9
    assert np.max(np.abs(c.force_n * c.gap_mm)) < 1e-9 * scale
    assert 0 < c.active.sum() < c.active.size  # partial contact: the cup cones on a straight cam
    # the deformation's own harmonic series at the bore (another path than the compliance
    # matrix): on the active set the bore sits on the cam
    d = c.deformation
    bore_z = d.z_mm  # the bore line has the neutral line's z
    rows = np.searchsorted(np.round(bore_z, 9), np.round(c.z_mm, 9))
    u_bore = np.cos(np.outer(c.phi_rad, d.orders)) @ d.bore_radial_mm[:, rows]  # (angles, band nodes)
    assert np.max(np.abs(u_bore.T - c.load_mm[None, :])[c.active]) < 1e-9
    import json

    assert json.loads(json.dumps(c.to_dict()))["contact"]["max_penetration_mm"] == c.max_penetration_mm


def test_a_coning_cup_touches_the_cam_at_the_bearing_edges(pressed):
    """On a straight (cylindrical) cam a cup whose generators tilt about the diaphragm bears on
    the major axis at the bearing's diaphragm-side edge and on the minor axis toward the open
    end; the open end flares beyond w0 (here ~+30 %) — what the bilateral model hides."""
    c, g = pressed, pressed.deformation.geometry
    lo, hi = g.bearing_span_mm
    major, minor = c.contact_span_mm(0), c.contact_span_mm(c.phi_rad.size - 1)
    assert major is not None and major[1] < lo + 0.25 * (hi - lo)
    assert minor is not None and minor[1] == pytest.approx(hi) and minor[0] > lo + 0.5 * (hi - lo)
    d = c.deformation
    assert d.omega(0.0, hi) > 1.1 * W0 and d.omega(0.0, lo) == pytest.approx(W0, abs=2e-3)


def test_long_cup_on_a_narrow_bearing_is_ring_theory():
    from profilegen.rim.cup import press_cup
    from profilegen.geometry.wavegen import CosineCam

    g = cup(length=300.0, bearing_width_mm=2.0)
    c = press_cup(g, contour=CosineCam(g.bore_radius_mm, W0), element_mm=4.0, angles=8)
    phi = np.linspace(0.0, 0.5 * math.pi, 19)
    d = c.deformation
    assert np.max(np.abs(d.omega(phi, 300.0) - W0 * np.cos(2 * phi))) < 0.01 * W0
    assert np.max(np.abs(d.upsilon(phi, 300.0) + 0.5 * W0 * np.sin(2 * phi))) < 0.01 * 0.5 * W0
