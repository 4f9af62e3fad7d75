"""What explicit teeth change in the 3D cup (issue 15, item 1: "teeth as an equivalent band is
acceptable if you show what explicit teeth change").

    python tests/benchmarks/cup_teeth.py [--no-cup] [--sets default,seed000_csf40] [--element-mm 2 --layers 2] [--band fit|force|ribs]
        [--stringers-only --tooth-layers 3 --void 1e-6]

The 3D cup (rim tier ``cup3d``) models the tooth ring as a smooth band of the rim thickness δ
(``gear.rim_thickness_mm``, bore r_bore = r_m − δ/2). Teeth stiffen the ring. This script
calibrates that stiffening in 2D, where the package has both models, and carries it into 3D:

1. 2D, per gear set: the toothed rim (the ``toothed`` tier's FEM: nonlinear, 16 columns per
   pitch, 2 + 2 layers, exact DCTA tooth) against flat rings (the ``design`` tier's mesh,
   4 × 64, nonlinear) of thickness δ' on the *same bore* r_bore (the cam fixes the bore), so
   their mid-line is r_bore + δ'/2. Every ring is read at the toothed rim's neutral line r_m
   (``RingResult.at_radius``: the FE field). Two calibrations of the equivalent band δ_eq:
   (a) the δ' minimising max(max |Δω|, max |Δυ|) over 0 ≤ φ ≤ π/2 against the toothed rim
       (bounded Brent search); (b) the δ' whose cam force along the major axis,
       F_y = Σ λ n_y on the quarter (N per mm of face width; ∝ the ring's bending stiffness EI
       for a prescribed deflection), equals the toothed rim's (root of log F_y(δ') − log F_y).
   Printed: the toothed rim vs flat δ (today's band) and vs each δ_eq, in µm.
2. 3D, each set (unless --no-cup): ``press_cup(gap="exact", nonlinear=True)`` at the
   ``cup3d`` tier's mesh (2 mm, 2 layers, 16 angles) with the tooth ring a band of δ (today)
   and of δ_eq (a) (``--band force``: (b); ``--band ribs``: the band whose meridional bending
   stiffness is that of the teeth as continuous axial ribs, an upper bracket: isotropic, it
   also stiffens the circumferential bending far beyond δ_eq), the wall keeping δ (``CupGeometry`` built here with
   ``ring_thickness_mm = δ_eq``, ``wall_thickness_mm = δ``, ``neutral_radius_mm`` =
   r_bore + δ_eq/2: the bore unchanged). The δ_eq cup's results are moved from its band's
   mid-surface to the toothed rim's r_m: ω interpolated linearly between the bore and the
   mid-surface (both node lines), υ by plane sections (υ(r) = υ' + (r − r')(υ' − ∂ω/∂φ)/r').
   Printed: ω major / minor and max |υ| at the tooth ring's diaphragm end, mid-face and open
   end, the coning (open end minus diaphragm end), and the change δ → δ_eq.
3. 3D, each set: the teeth's meridional stiffness, which an isotropic band calibrated on the
   circumferential (2D) response cannot carry: the teeth as the smeared axial stringers of a
   stringer-stiffened shell (:func:`stringer_basis`: the meridional mesh extended to the tooth
   tip, each tooth a homogenised lamella, f(r) × plane stress in its r-z plane, nothing across)
   above a band of δ or δ_eq, in the LINEAR cup with the exact gap (the nonlinear harmonic
   balance is isotropic). Printed: the changes against the band of δ, and a check that the
   extended mesh with void teeth reproduces press_cup's own cup.
"""

from __future__ import annotations

import argparse
import math
import resource
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.rim import stage  # noqa: E402
from profilegen.rim.cup import CupGeometry, meridional_mesh, press_cup  # noqa: E402
from profilegen.rim.ring import RingParameters, solve_ring  # noqa: E402
from profilegen.geometry.wavegen import from_gearset  # noqa: E402

UM = 1e3


def _force_y(res) -> float:
    """The cam's force on the quarter along the major axis (N per mm of face width)."""
    return float(np.sum(res.contact_force_n * res.contact_normal[:, 1]))


def _flat(gs, contour, delta_mm: float):
    """The design tier's flat ring (4 × 64, nonlinear) of thickness δ' on the gear set's bore."""
    g, mat = gs.gear, gs.material
    bore = g.neutral_radius_mm - 0.5 * g.rim_thickness_mm
    params = RingParameters(bore + 0.5 * delta_mm, delta_mm, mat.youngs_modulus_mpa, mat.poisson_ratio, waves=g.waves)
    return solve_ring(params, contour=contour, layers=4, divisions=64, geometry="nonlinear")


def _against(toothed, flat, r_m: float) -> tuple[float, float]:
    """max |Δω|, max |Δυ| (mm) of a flat ring read at r_m against the toothed rim's neutral line."""
    from scipy.interpolate import CubicSpline

    phi, w, u = flat.at_radius(r_m)
    return (float(np.max(np.abs(CubicSpline(phi, w)(toothed.phi_rad) - toothed.omega_mm))),
            float(np.max(np.abs(CubicSpline(phi, u)(toothed.phi_rad) - toothed.upsilon_mm))))


def calibrate(name: str) -> dict:
    from scipy.optimize import brentq, minimize_scalar

    path = pg.default_gearset_path() if name == "default" else ROOT / "profiles" / f"{name}.toml"
    gs = pg.load_gearset(path)
    g = gs.gear
    contour = from_gearset(gs)
    delta, r_m = g.rim_thickness_mm, g.neutral_radius_mm
    t0 = time.perf_counter()
    toothed = stage._solve_named(gs, stage.RIM_TIERS["toothed"], contour, coarse=False)
    t_toothed = time.perf_counter() - t0
    f_t = _force_y(toothed)
    cache: dict[float, object] = {}

    def flat(d):
        key = round(float(d), 9)
        if key not in cache:
            cache[key] = _flat(gs, contour, key)
        return cache[key]

    def misfit(d):
        return max(_against(toothed, flat(d), r_m))

    t0 = time.perf_counter()
    hi = delta + (g.module_mm * 2.5)  # the band can be no thicker than rim + whole tooth
    best = minimize_scalar(misfit, bounds=(delta, hi), method="bounded", options={"xatol": 2e-4})
    d_fit = float(best.x)
    d_force = float(brentq(lambda d: math.log(_force_y(flat(d)) / f_t), delta, hi, xtol=2e-4))
    t_search = time.perf_counter() - t0
    # the 3D readout's check in 2D: the δ_eq ring's ω, υ moved from its mid-line to r_m by the
    # formulas _cup_numbers uses (ω linear from the bore, υ by plane sections) against its FE field at r_m
    f = flat(d_fit)
    r_mid = f.parameters.neutral_radius_mm
    s = (r_m - f.parameters.bore_radius_mm) / (r_mid - f.parameters.bore_radius_mm)
    from scipy.interpolate import CubicSpline

    slope = CubicSpline(f.phi_rad, f.omega_mm)(f.phi_rad, 1)
    w_shift = f.bore_omega_mm + s * (f.omega_mm - f.bore_omega_mm)
    u_shift = f.upsilon_mm + (r_m - r_mid) * (f.upsilon_mm - slope) / r_mid
    _, w_fe, u_fe = f.at_radius(r_m)
    readout = (float(np.max(np.abs(w_shift - w_fe))), float(np.max(np.abs(u_shift - u_fe))), r_mid - r_m)
    rows = []
    for label, d in (("flat δ (today's band)", delta), ("δ_eq (a): best ω, υ", d_fit),
                     ("δ_eq (b): same cam force", d_force)):
        f = flat(d)
        dw, du = _against(toothed, f, r_m)
        rows.append((label, d, dw, du, _force_y(f), f.contact_angle_deg))
    d_ribs, ribs_ratio = rib_band(gs)
    return {"name": name, "gearset": gs, "d_ribs": d_ribs, "ribs_ratio": ribs_ratio, "delta": delta, "r_m": r_m, "z1": g.flexspline_teeth, "m": g.module_mm,
            "toothed": toothed, "f_t": f_t, "rows": rows, "d_fit": d_fit, "d_force": d_force,
            "t_toothed": t_toothed, "t_search": t_search, "flat_solves": len(cache),
            "readout": readout}


def print_calibration(c: dict) -> None:
    t = c["toothed"]
    print(f"\n## {c['name']}: z1 = {c['z1']}, m = {c['m']:g} mm, δ = {c['delta']:g} mm, r_m = {c['r_m']:g} mm "
          f"(toothed FEM {c['t_toothed']:.1f} s, {t.dof} dof; search {c['t_search']:.1f} s, "
          f"{c['flat_solves']} flat solves)")
    print(f"toothed rim: ω(0) = {t.omega_mm[0]:.5f} mm, ω(90°) = {t.omega_mm[-1]:.5f} mm, "
          f"max |υ| = {np.max(np.abs(t.upsilon_mm)):.5f} mm, F_y = {c['f_t']:.4f} N/mm, wrap {t.contact_angle_deg:.1f}°")
    print("| flat band | thickness (mm) | δ'/δ | max \\|Δω\\| (µm) | max \\|Δυ\\| (µm) | F_y (N/mm) | F_y / toothed "
          "| wrap (°) |")
    print("|---|---|---|---|---|---|---|---|")
    for label, d, dw, du, f, wrap in c["rows"]:
        print(f"| {label} | {d:.4f} | {d / c['delta']:.3f} | {dw * UM:.3f} | {du * UM:.3f} | {f:.4f} | "
              f"{f / c['f_t']:.3f} | {wrap:.1f} |")
    print(f"teeth as continuous axial ribs (meridional bending, smeared over the pitch): I = {c['ribs_ratio']:.2f} × "
          f"the δ band's, a band of {c['d_ribs']:.4f} mm ({c['d_ribs'] / c['delta']:.3f} δ; --band ribs)")
    dw, du, shift = c["readout"]
    print(f"readout check (the 3D table's move from the band's mid-line to r_m, {shift * UM:+.1f} µm, on the 2D δ_eq "
          f"ring against its FE field at r_m): max |Δω| {dw * UM:.3f} µm, max |Δυ| {du * UM:.3f} µm")


def rib_band(gs) -> tuple[float, float]:
    """(t_mer, I_ribbed / I_band): the band thickness (same bore) whose meridional bending
    stiffness per unit circumference equals that of the tooth ring with its teeth as continuous
    axial ribs, smeared over the pitch (beam theory: ∫ f(r) (r − r_c)² dr, f the solid fraction
    of the pitch at radius r from the exact flank, 1 from the bore to the root circle)."""
    from profilegen.geometry.teeth import tooth_from_gearset

    tooth = tooth_from_gearset(gs)
    r_m, delta = tooth.neutral_radius_mm, gs.gear.rim_thickness_mm
    p = tooth.point(np.linspace(0.0, tooth.length_mm, 4001))
    rho, psi = np.hypot(p[:, 0], p[:, 1] + r_m), np.arctan2(p[:, 0], p[:, 1] + r_m)
    r = np.linspace(r_m - 0.5 * delta, rho.max(), 20001)
    f = np.where(r > rho[0], np.interp(r, rho, psi) / (math.pi / tooth.teeth), 1.0)
    area = np.trapezoid(f, r)
    centroid = np.trapezoid(f * r, r) / area
    inertia = np.trapezoid(f * (r - centroid) ** 2, r)
    return float((12.0 * inertia) ** (1.0 / 3.0)), float(inertia / (delta ** 3 / 12.0))


def _cup_numbers(contact, r_read: float) -> dict:
    """ω major / minor and max |υ| at the tooth ring's ends and mid-face, read at radius r_read."""
    d = contact.deformation
    geo = d.geometry
    r_mid, r_bore = geo.neutral_radius_mm, geo.bore_radius_mm
    lo, hi = geo.ring_span_mm
    phi = np.linspace(0.0, 0.5 * math.pi, 361)
    out = {}
    for where, z in (("diaphragm end", lo), ("mid-face", geo.length_mm), ("open end", hi)):
        w_mid, w_bore, u_mid = d.omega(phi, z), d.bore_omega(phi, z), d.upsilon(phi, z)
        s = (r_read - r_bore) / (r_mid - r_bore)
        w = w_bore + s * (w_mid - w_bore)
        h = 1e-6
        dw = (d.omega(phi + h, z) - d.omega(phi - h, z)) / (2 * h)
        u = u_mid + (r_read - r_mid) * (u_mid - dw) / r_mid
        out[where] = (float(z), float(w[0]), float(w[-1]), float(np.max(np.abs(u))))
    return out


def cup_table(c: dict, element_mm: float, layers: int, band: str = "fit") -> None:
    gs = c["gearset"]
    base = CupGeometry.from_gearset(gs)
    contour = from_gearset(gs)
    tier = stage.RIM_TIERS["cup3d"]
    delta, r_m = c["delta"], c["r_m"]
    bore = r_m - 0.5 * delta
    runs = {}
    d_band = {"fit": c["d_fit"], "force": c["d_force"], "ribs": c["d_ribs"]}[band]
    for label, d in (("δ", delta), ("δ_eq", d_band)):
        geo = CupGeometry(bore + 0.5 * d, base.wall_thickness_mm, base.length_mm, base.face_width_mm,
                          base.bottom_thickness_mm, base.boss_radius_mm, base.youngs_modulus_mpa, base.poisson_ratio,
                          bearing_width_mm=base.bearing_width_mm, bearing_center_mm=base.bearing_center_mm,
                          ring_thickness_mm=d)
        t0 = time.perf_counter()
        contact = press_cup(geo, contour=contour, angles=tier.angles, element_mm=element_mm, layers=layers,
                            gap=tier.gap, nonlinear=tier.geometry == "nonlinear")
        runs[label] = (d, _cup_numbers(contact, r_m), time.perf_counter() - t0, contact.max_penetration_mm)
    print(f"\n## 3D cup, {c['name']} set: tooth ring as a band of δ and of δ_eq ({dict(fit='a', force='b', ribs='ribs')[band]}), wall {base.wall_thickness_mm:g} mm; "
          f"press_cup exact gap, nonlinear, {element_mm:g} mm × {layers} layers, {tier.angles} angles; "
          f"read at r_m = {r_m:g} mm")
    for label, (d, _, secs, pen) in runs.items():
        print(f"band {label} = {d:.4f} mm: {secs:.1f} s, max penetration {pen * UM:.2g} µm")
    print("| section | z (mm) | ω major δ | ω major δ_eq | Δ (µm) | ω minor δ | ω minor δ_eq | Δ (µm) | max\\|υ\\| δ "
          "| max\\|υ\\| δ_eq | Δ (µm) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    a, b = runs["δ"][1], runs["δ_eq"][1]
    for where in a:
        za, wa, ma, ua = a[where]
        _, wb, mb, ub = b[where]
        print(f"| {where} | {za:g} | {wa:.5f} | {wb:.5f} | {(wb - wa) * UM:+.2f} | {ma:.5f} | {mb:.5f} | "
              f"{(mb - ma) * UM:+.2f} | {ua:.5f} | {ub:.5f} | {(ub - ua) * UM:+.2f} |")
    ends = ("open end", "diaphragm end")
    for k, axis in ((1, "major"), (2, "minor")):
        ca = a[ends[0]][k] - a[ends[1]][k]
        cb = b[ends[0]][k] - b[ends[1]][k]
        print(f"coning ω_{axis} (open end − diaphragm end): δ {ca * UM:+.2f} µm, δ_eq {cb * UM:+.2f} µm, "
              f"change {(cb - ca) * UM:+.2f} µm ({(cb - ca) / ca * 100:+.2f} %)")


# --------------------------------------------------------------------------- 3. teeth as smeared stringers

VARIANTS = {  # name: (isotropic band to r_bore + this, stringers above it)
    "δ": ("delta", False),
    "δ_eq": ("d_fit", False),
    "δ + stringers": ("delta", True),
    "δ_eq + stringers": ("d_fit", True),
}


def stringer_basis(geometry, tooth, band_mm: float, d_top_mm: float, stringers: bool, *, element_mm: float,
                   layers: int, tooth_layers: int = 3, void: float = 1e-6):
    """The harmonic stiffness (:class:`~profilegen.rim.cup.fourier.HarmonicBasis`) of the cup
    ``geometry`` (its tooth ring a band of δ) on a meridional mesh extended over the tooth ring
    from r_bore + δ to the tooth tip r_m + y_a (node lines also at r_bore + ``band_mm`` and
    r_bore + ``d_top_mm``, ``tooth_layers`` layers above the latter). Material: isotropic up to
    r_bore + ``band_mm``; above it, with ``stringers``, the teeth as continuous axial ribs
    smeared over the pitch (the stringer-stiffened shell's smeared stiffener; the homogenised
    lamella: in the rib's r-z plane f(r) × plane stress, σ_φ = τ_rφ = τ_zφ = 0; f the solid
    fraction of the pitch at radius r from the exact flank), else void; ``void`` × the
    isotropic stiffness is added above the band so that the stringers' φ-dofs are not free."""
    from skfem import Basis, BilinearForm, ElementQuad2, ElementVector, MeshQuad, MeshQuad2, asm

    from profilegen.rim.cup.fourier import HarmonicBasis, _energy, _strain_parts, lame
    from profilegen.rim.cup.geometry import CupMesh

    g = geometry
    r_m, rb, delta = g.neutral_radius_mm, g.bore_radius_mm, g.ring_thickness_mm
    r_tip = r_m + tooth.addendum_y_mm
    base = meridional_mesh(g, element_mm=element_mm, layers=layers)
    r_top = rb + d_top_mm
    r_all = np.concatenate([base.r_breaks, [rb + band_mm], np.linspace(r_top, r_tip, tooth_layers + 1)])
    r_all = np.unique(np.round(r_all, 9))  # rb + δ is already a break: no zero-width elements
    z_all = base.z_breaks
    ring_lo = g.ring_span_mm[0]
    box = MeshQuad.init_tensor(r_all, z_all)
    c = box.p[:, box.t].mean(axis=1)
    keep = ((c[1] < 0.5 * g.bottom_thickness_mm) | (c[0] > rb)) & ((c[0] < rb + delta) | (c[1] > ring_lo))
    t = box.t[:, keep]
    used = np.unique(t)
    renumber = -np.ones(box.p.shape[1], dtype=int)
    renumber[used] = np.arange(used.size)
    mesh = MeshQuad(box.p[:, used], renumber[t])

    p = tooth.point(np.linspace(0.0, tooth.length_mm, 4001))
    rho, psi = np.hypot(p[:, 0], p[:, 1] + r_m), np.arctan2(p[:, 0], p[:, 1] + r_m)
    half_pitch = math.pi / tooth.teeth
    lam, mu = lame(g.youngs_modulus_mpa, g.poisson_ratio)
    e, nu = g.youngs_modulus_mpa, g.poisson_ratio
    e_p, shear = e / (1.0 - nu * nu), e / (2.0 * (1.0 + nu))
    edge = rb + band_mm + 1e-9

    def energy(a, b, x):
        r = x[0]
        iso = _energy(a, b, lam, mu)
        rib = 0.0 * iso
        if stringers:
            f = np.where(r > rho[0], np.interp(r, rho, psi, right=0.0) / half_pitch, 1.0)
            rib = f * (e_p * (a[0] * b[0] + a[1] * b[1] + nu * (a[0] * b[1] + a[1] * b[0])) + shear * a[3] * b[3])
        return np.where(r < edge, iso, rib + void * iso)

    @BilinearForm
    def k00(u, v, w):
        r = w.x[0]
        return energy(_strain_parts(u, r)[0], _strain_parts(v, r)[0], w.x) * r

    @BilinearForm
    def k01(u, v, w):
        r = w.x[0]
        (u0, u1), (v0, v1) = _strain_parts(u, r), _strain_parts(v, r)
        return (energy(u0, v1, w.x) + energy(u1, v0, w.x)) * r

    @BilinearForm
    def k11(u, v, w):
        r = w.x[0]
        return energy(_strain_parts(u, r)[1], _strain_parts(v, r)[1], w.x) * r

    t0 = time.perf_counter()
    quad2 = MeshQuad2.from_mesh(mesh)
    scalar = Basis(quad2, ElementQuad2(), intorder=4)
    vec = Basis(quad2, ElementVector(ElementQuad2(), dim=3), intorder=4)
    iu, iw, iv = vec.split_indices()
    order = np.column_stack([iu, iw, iv]).ravel()  # the harmonic model's dof 3k + c ↔ scikit-fem's
    parts = [asm(form, vec)[order][:, order].tocsr() for form in (k00, k01, k11)]
    return HarmonicBasis(CupMesh(g, mesh, r_all, z_all, element_mm, layers), scalar, *parts, time.perf_counter() - t0)


def stringer_table(c: dict, element_mm: float, layers: int, tooth_layers: int = 3, void: float = 1e-6) -> None:
    from profilegen.geometry.teeth import tooth_from_gearset

    gs = c["gearset"]
    geo = CupGeometry.from_gearset(gs)
    contour = from_gearset(gs)
    tooth = tooth_from_gearset(gs)
    tier = stage.RIM_TIERS["cup3d"]
    r_m = c["r_m"]

    def press(hb=None):
        return _cup_numbers(press_cup(geo, contour=contour, angles=tier.angles, element_mm=element_mm, layers=layers,
                                      gap=tier.gap, nonlinear=False, harmonic_basis=hb), r_m)

    plain = press()
    runs = {}
    for name, (band, stringers) in VARIANTS.items():
        band_mm = c["delta"] if band == "delta" else c[band]
        hb = stringer_basis(geo, tooth, band_mm, band_mm, stringers, element_mm=element_mm, layers=layers,
                            tooth_layers=tooth_layers, void=void)
        runs[name] = press(hb)
    check = max(abs(runs["δ"][k][i] - plain[k][i]) for k in plain for i in (1, 2, 3))
    print(f"\n## 3D cup, {c['name']} set, LINEAR (exact gap): the teeth as smeared axial stringers above the band "
          f"(tooth tip r_m + {tooth.addendum_y_mm:g} mm, {tooth_layers} layers, void {void:g}); {element_mm:g} mm × "
          f"{layers} layers, {tier.angles} angles; "
          f"change against the band of δ (µm), read at r_m")
    print(f"check: the band of δ on the extended mesh (void teeth) against press_cup's own mesh: max |Δ| "
          f"{check * UM:.4f} µm")
    print("| tooth ring | ω major diaphragm | mid-face | open end | ω minor diaphragm | mid-face | open end "
          "| max\|υ\| diaphragm | mid-face | open end | coning ω_major |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    a = runs["δ"]
    cone = a["open end"][1] - a["diaphragm end"][1]
    print("| band of δ (mm) | " + " | ".join(f"{a[k][i]:.5f}" for i in (1, 2, 3) for k in a) + f" | {cone * UM:.2f} µm |")
    for name, b in runs.items():
        if name == "δ":
            continue
        cb = b["open end"][1] - b["diaphragm end"][1]
        print(f"| {name} | " + " | ".join(f"{(b[k][i] - a[k][i]) * UM:+.2f}" for i in (1, 2, 3) for k in a)
              + f" | {(cb - cone) * UM:+.2f} ({(cb - cone) / cone * 100:+.1f} %) |")


def main() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--no-cup", action="store_true", help="the 2D calibration only")
    ap.add_argument("--sets", default="default,seed000_csf40", help="gear sets (profiles/NAME.toml; default: the bundled)")
    ap.add_argument("--element-mm", type=float, default=stage.RIM_TIERS["cup3d"].element_mm,
                    help="the cup's meridional element size (mm; default the cup3d tier's)")
    ap.add_argument("--layers", type=int, default=stage.RIM_TIERS["cup3d"].layers,
                    help="element layers through the cup's band (even: r_m must be a node line; default the tier's)")
    ap.add_argument("--band", choices=("fit", "force", "ribs"), default="fit",
                    help="the 3D cup's δ_eq: (a) the best ω, υ (default), (b) the same cam force, or the teeth's "
                         "meridional bending stiffness as axial ribs (an upper bracket)")
    ap.add_argument("--tooth-layers", type=int, default=3, help="part 3: element layers over the teeth")
    ap.add_argument("--void", type=float, default=1e-6, help="part 3: the isotropic stiffness above the band (× E)")
    ap.add_argument("--stringers-only", action="store_true", help="part 3 only (after the 2D calibration)")
    args = ap.parse_args()
    results = []
    for name in args.sets.split(","):
        c = calibrate(name.strip())
        print_calibration(c)
        results.append(c)
    if not args.no_cup:
        if not args.stringers_only:
            for c in results:
                cup_table(c, args.element_mm, args.layers, args.band)
        for c in results:
            stringer_table(c, args.element_mm, args.layers, args.tooth_layers, args.void)


if __name__ == "__main__":
    main()
