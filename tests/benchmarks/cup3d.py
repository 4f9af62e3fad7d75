"""3D cup tier (issue 15): speed vs accuracy of the Fourier-harmonic model, and its checks on
fine meshes, in one run.

    python tests/benchmarks/cup3d.py [--quick] [--no-solid]

Default gear set's cup ([cup] estimates: l = 60 mm to mid-face, face 20 mm, bottom 0.9 mm,
boss r_m/2; wall = rim 0.9 mm; bearing = the face, centred on it).

1. Speed vs accuracy: ``solve_cup(gearset)`` (the elliptical cam's w(φ) = ρ − r_bore, harmonics
   0..16, bearing over the face) on meridional meshes of 4 … 0.25 mm along the meridian with 1, 2
   and 4 layers through the wall; time = median of 3 whole solves (mesh, assembly, every
   harmonic); error = max |Δω|, |Δυ| over the tooth ring (41 z × 91 φ) against the finest mesh
   (0.125 mm, 4 layers; 0.25 mm in --quick); observed rates.
2. The fast formulation against the plain 3D solid (27-node hexahedra, quarter) on the same
   meridional mesh (4 mm, 1 layer) with 6, 12, 24 sectors (w = w0 cos 2φ): the difference on
   the wall's neutral surface and its rate; times.
3. Long cup (l = 300 mm) vs ring theory and vs the package's 2D ring FEM (bilateral cosine cam).
4. Wall-end axial displacement vs the stress stage's semi-membrane w(φ), l = 40 … 240 mm,
   bearing the face (20 mm) or 4 mm.
5. The default set's ω, υ at the tooth ring's diaphragm end, mid-face and open end, the bore
   prescribed (bilateral) over bearings 20, 10 and 4 mm wide.
6. The default set pressed onto its cam (unilateral, ``press_cup``): ω, υ at the same sections,
   the contact's extent on the axes, against mesh and collocation angles; medians of 3.
7. Seed 004's printed 0.553 / −0.557 / 0.293 mm (ω major / minor at mid-face, υ at the open end)
   beside press_cup's extremes over φ at the tooth ring's sections, bearing 20 and 10 mm wide
   (preliminary: the cup's length, bottom and boss are [cup] estimates, the gap is first order
   and the seed's open-end axial restraint is not modelled).

Writes export/bench/cup3d.csv and export/bench/cup3d.png.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import resource
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.output.export import atomic_write  # noqa: E402
from profilegen.rim.cup import CupGeometry, harmonic_stiffness, meridional_mesh, solve_cup  # noqa: E402
from tests.oracles.solid_cup import solve_solid_cup  # noqa: E402
from profilegen.geometry.wavegen import from_gearset  # noqa: E402

W0 = 0.5


def _timed(repeats, fn):
    times, res = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        res = fn()
        times.append(time.perf_counter() - t0)
    return res, statistics.median(times)


def _ring_grid(g):
    lo, hi = g.ring_span_mm
    z = np.linspace(lo, hi, 41)[:, None]
    phi = np.linspace(0.0, 0.5 * math.pi, 91)[None, :]
    return phi, z


def _diff(a, b, g) -> tuple[float, float]:
    phi, z = _ring_grid(g)
    return (float(np.max(np.abs(a.omega(phi, z) - b.omega(phi, z)))),
            float(np.max(np.abs(a.upsilon(phi, z) - b.upsilon(phi, z)))))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="coarser reference, no 24-sector solid")
    ap.add_argument("--no-solid", action="store_true", help="skip the 3D solid comparison")
    args = ap.parse_args()
    resource.setrlimit(resource.RLIMIT_AS, (6_000_000_000, 6_000_000_000))
    gs = pg.load_gearset(pg.default_gearset_path())
    g = CupGeometry.from_gearset(gs)
    solve_cup(gs, element_mm=8.0, layers=1)  # imports and first-call set-up out of the timings
    rows = []

    print("1. speed vs accuracy (gear set's cam, harmonics 0..16)", flush=True)
    ref_h = 0.25 if args.quick else 0.125
    t0 = time.perf_counter()
    ref = solve_cup(gs, element_mm=ref_h, layers=4)
    print(f"  reference {ref_h} mm, 4 layers: {ref.dof} dof/harmonic × {ref.orders.size}, "
          f"{time.perf_counter() - t0:.2f} s", flush=True)
    for layers in (1, 2, 4):
        prev = None
        for h in (4.0, 2.0, 1.0, 0.5, 0.25):
            if layers == 4 and h == ref_h:
                continue
            res, t = _timed(3, lambda: solve_cup(gs, element_mm=h, layers=layers))
            e_w, e_u = _diff(res, ref, g)
            err = max(e_w, e_u)
            rate = "" if prev is None else f"{math.log2(prev / err):.2f}"
            prev = err
            rows.append({"part": "fourier", "mesh": f"{h} mm x {layers} layers", "dof": res.dof,
                         "harmonics": int(res.orders.size), "time_s": t, "err_omega_um": e_w * 1e3,
                         "err_upsilon_um": e_u * 1e3, "rate": rate,
                         "default_of": "cup3d" if (h, layers) == (1.0, 2) else ""})
            print(f"  {h:5.2f} mm × {layers} layers {res.dof:6d} dof × {res.orders.size} harmonics  {t:7.3f} s "
                  f"(assembly {res.assembly_s:.3f}, solves {res.solve_s:.3f})  ω {e_w * 1e3:9.4f} µm  "
                  f"υ {e_u * 1e3:9.4f} µm  rate {rate}", flush=True)

    if not args.no_solid:
        print("2. Fourier vs 3D solid (w0 cos 2φ; meridional mesh 4 mm × 1 layer)", flush=True)
        mesh = meridional_mesh(g, element_mm=4.0, layers=1)
        fourier, t_f = _timed(3, lambda: solve_cup(g, radial_mm={2: W0}, harmonic_basis=harmonic_stiffness(mesh)))
        prev = None
        for sectors in (6, 12) if args.quick else (6, 12, 24):
            solid, t_s = _timed(1, lambda: solve_solid_cup(g, radial_mm={2: W0}, cup_mesh=mesh, sectors=sectors))
            wall = solid.z_mm > 0.5 * g.bottom_thickness_mm - 1e-9
            th, z = solid.theta_rad[wall], solid.z_mm[wall]
            d_w = float(np.max(np.abs(solid.omega_mm[wall] - fourier.omega(th, z))))
            d_u = float(np.max(np.abs(solid.upsilon_mm[wall] - fourier.upsilon(th, z))))
            d_a = float(np.max(np.abs(solid.axial_mm[wall] - fourier.axial(th, z))))
            err = max(d_w, d_u)
            rate = "" if prev is None else f"{math.log2(prev / err):.2f}"
            prev = err
            rows.append({"part": "solid3d", "mesh": f"4 mm x 1 layer x {sectors} sectors/quarter", "dof": solid.dof,
                         "harmonics": "", "time_s": t_s, "err_omega_um": d_w * 1e3, "err_upsilon_um": d_u * 1e3,
                         "rate": rate, "default_of": f"vs fourier ({t_f:.3f} s)"})
            print(f"  {sectors:3d} sectors {solid.dof:6d} dof {t_s:7.2f} s (assembly {solid.assembly_s:.2f}, solve "
                  f"{solid.solve_s:.2f})  |Δω| {d_w * 1e3:8.4f} µm  |Δυ| {d_u * 1e3:8.4f} µm  |Δaxial| "
                  f"{d_a * 1e3:8.4f} µm  rate {rate}  (Fourier: {fourier.dof} dof, {t_f:.3f} s)", flush=True)

    print("3. long cup (l = 300 mm, w0 cos 2φ over the face) at mid-face", flush=True)
    from profilegen.rim import RingParameters, solve_ring
    from profilegen.geometry.wavegen import CosineCam

    long = CupGeometry(g.neutral_radius_mm, g.wall_thickness_mm, 300.0, g.face_width_mm, g.bottom_thickness_mm,
                       g.boss_radius_mm, g.youngs_modulus_mpa, g.poisson_ratio)
    res = solve_cup(long, radial_mm={2: W0}, element_mm=1.0, layers=2)
    ring = solve_ring(RingParameters(g.neutral_radius_mm, g.wall_thickness_mm, g.youngs_modulus_mpa, g.poisson_ratio),
                      contour=CosineCam(g.bore_radius_mm, W0), bilateral=True, layers=4, divisions=64)
    phi = ring.phi_rad
    w, u = res.omega(phi, 300.0), res.upsilon(phi, 300.0)
    theory_w, theory_u = W0 * np.cos(2 * phi), -0.5 * W0 * np.sin(2 * phi)
    print(f"  vs ring theory: max |Δω| = {np.max(np.abs(w - theory_w)) * 1e3:.3f} µm "
          f"({np.max(np.abs(w - theory_w)) / W0:.3%} of w0), max |Δυ| = {np.max(np.abs(u - theory_u)) * 1e3:.3f} µm "
          f"({np.max(np.abs(u - theory_u)) / (0.5 * W0):.3%} of w0/2)")
    print(f"  vs 2D ring FEM (4×64, bilateral cosine cam): max |Δω| = {np.max(np.abs(w - ring.omega_mm)) * 1e3:.3f} µm, "
          f"max |Δυ| = {np.max(np.abs(u - ring.upsilon_mm)) * 1e3:.3f} µm; the 2D ring vs theory: "
          f"{np.max(np.abs(ring.omega_mm - theory_w)) * 1e3:.3f} / {np.max(np.abs(ring.upsilon_mm - theory_u)) * 1e3:.3f} µm")

    print("4. wall-end axial displacement vs semi-membrane (stress stage, seed 002's w(φ)): FEM / (r_m w0 / 4l)")
    from profilegen.stress.plate import edge_displacement

    for length in (40.0, 60.0, 120.0, 240.0):
        line = []
        for bw in (g.face_width_mm, 4.0):
            geo = CupGeometry(g.neutral_radius_mm, g.wall_thickness_mm, length, g.face_width_mm,
                              g.bottom_thickness_mm, g.boss_radius_mm, g.youngs_modulus_mpa, g.poisson_ratio,
                              bearing_width_mm=bw)
            r = solve_cup(geo, radial_mm={2: W0}, element_mm=0.5, layers=2)
            semi = edge_displacement({2: W0}, mean_radius_mm=g.neutral_radius_mm, length_mm=length).harmonics[2]
            line.append(f"bearing {bw:4.1f} mm: {-r.axial(0.0, r.z_mm[0]) * 1e3:8.3f} / {semi * 1e3:8.3f} µm = "
                        f"{-r.axial(0.0, r.z_mm[0]) / semi:.4f}")
        print(f"  l = {length:5.1f} mm  " + "   ".join(line))

    print("5. default set (elliptical cam, bearing centred on the face, bilateral), 1 mm × 2 layers:")
    lo, hi = g.ring_span_mm
    for bw in (g.face_width_mm, 10.0, 4.0):
        res = solve_cup(gs, element_mm=1.0, layers=2) if bw == g.face_width_mm else solve_cup(
            CupGeometry.from_gearset(gs, bearing_width_mm=bw), contour=from_gearset(gs),
            element_mm=1.0, layers=2)
        print(f"  bearing {bw:4.1f} mm wide:")
        for name, z in (("diaphragm end", lo), ("mid-face", g.length_mm), ("open end", hi)):
            print(f"    {name:13s} z = {z:5.1f} mm: ω(0) = {res.omega(0.0, z):.5f}, ω(π/2) = "
                  f"{res.omega(0.5 * math.pi, z):.5f}, υ(π/4) = {res.upsilon(0.25 * math.pi, z):.5f} mm, "
                  f"axial(0) = {res.axial(0.0, z):.5f} mm, tilt(0) = {res.tilt(0.0, z) * 1e3:.4f} mrad")

    print("6. default set on its cam, unilateral (press_cup), bearing over the face:", flush=True)
    from profilegen.rim.cup import press_cup

    cases = ((4.0, 8), (2.0, 16), (1.0, 16)) if args.quick else ((4.0, 8), (2.0, 16), (1.0, 16), (1.0, 31))
    finest = None
    results = []
    for h, angles in cases:
        c, t = _timed(1 if angles > 16 else 3, lambda: press_cup(gs, element_mm=h, angles=angles))
        results.append((h, angles, c, t))
    finest = results[-1][2].deformation
    for h, angles, c, t in results:
        d = c.deformation
        e_w, e_u = _diff(d, finest, g)
        rows.append({"part": "contact", "mesh": f"{h} mm x 2 layers, {angles} angles", "dof": d.dof,
                     "harmonics": int(d.orders.size), "time_s": t, "err_omega_um": e_w * 1e3,
                     "err_upsilon_um": e_u * 1e3, "rate": "",
                     "default_of": "press_cup" if (h, angles) == (2.0, 16) else ""})
        print(f"  {h:4.1f} mm, {angles:2d} angles: {t:6.2f} s (compliance {c.compliance_s:.2f}, contact "
              f"{c.contact_s:.2f}), {int(c.active.sum())}/{c.active.size} active, vs the finest: ω {e_w * 1e3:.3f} µm, "
              f"υ {e_u * 1e3:.3f} µm; major axis bears on z = {c.contact_span_mm(0)}, minor axis on "
              f"z = {c.contact_span_mm(angles - 1)} mm")
        for name, z in (("diaphragm end", lo), ("mid-face", g.length_mm), ("open end", hi)):
            print(f"    {name:13s} z = {z:5.1f} mm: ω(0) = {d.omega(0.0, z):.5f}, ω(π/2) = "
                  f"{d.omega(0.5 * math.pi, z):.5f}, υ(π/4) = {d.upsilon(0.25 * math.pi, z):.5f} mm, "
                  f"axial(0) = {d.axial(0.0, z):.5f} mm, tilt(0) = {d.tilt(0.0, z) * 1e3:.4f} mrad")

    print("7. seed 004 (0.553 / -0.557 mm at mid-face, |υ| 0.293 mm at the open end) beside press_cup:")
    phi = np.linspace(0.0, math.pi, 721)
    for bw in (g.face_width_mm, 10.0):
        c = press_cup(CupGeometry.from_gearset(gs, bearing_width_mm=bw), contour=from_gearset(gs))
        d = c.deformation
        for name, z in (("diaphragm end", lo), ("mid-face", g.length_mm), ("open end", hi)):
            w, u = d.omega(phi, z), d.upsilon(phi, z)
            print(f"  bearing {bw:4.1f} mm, {name:13s}: ω {w.max():.4f} / {w.min():.4f} mm, |υ| max {np.abs(u).max():.4f} "
                  f"mm at {math.degrees(phi[np.abs(u).argmax()]):.1f}°")

    out = ROOT / "export" / "bench"
    keys = ["part", "mesh", "dof", "harmonics", "time_s", "err_omega_um", "err_upsilon_um", "rate", "default_of"]
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=keys)
    w.writeheader()
    w.writerows(rows)
    with atomic_write(out / "cup3d.csv") as f:
        f.write(buf.getvalue())

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
    for layers, marker in ((1, "s"), (2, "o"), (4, "D")):
        sel = [r for r in rows if r["part"] == "fourier" and r["mesh"].endswith(f"{layers} layers")]
        ax.loglog([r["time_s"] for r in sel], [max(r["err_omega_um"], r["err_upsilon_um"]) for r in sel],
                  marker + "-", label=f"Fourier cup, {layers} layers")
    sel = [r for r in rows if r["part"] == "contact"][:-1]
    ax.loglog([r["time_s"] for r in sel], [max(r["err_omega_um"], r["err_upsilon_um"]) for r in sel], "v-",
              label="press_cup (unilateral) vs its finest")
    sel = [r for r in rows if r["part"] == "solid3d"]
    if sel:
        ax.loglog([r["time_s"] for r in sel], [max(r["err_omega_um"], r["err_upsilon_um"]) for r in sel], "^-",
                  label="3D solid vs Fourier (same meridional mesh)")
    ax.axvline(10.0, color="C3", lw=0.6, ls=":")
    ax.set_xlabel("median time (s)")
    ax.set_ylabel("max |Δω|, |Δυ| over the tooth ring (µm)")
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    ax.legend(fontsize=8)
    fig.suptitle("3D cup tier, default set")
    png = io.BytesIO()
    fig.savefig(png, dpi=130, format="png")
    with atomic_write(out / "cup3d.png", "wb") as f:
        f.write(png.getvalue())
    default = next(r for r in rows if r["default_of"] == "cup3d")
    print(f"cup3d default mesh (1 mm × 2 layers): {default['time_s']:.3f} s (target ≤ 10 s), "
          f"{max(default['err_omega_um'], default['err_upsilon_um']):.4f} µm from the reference")
    contact = next(r for r in rows if r["default_of"] == "press_cup")
    print(f"press_cup default (2 mm × 2 layers, 16 angles): {contact['time_s']:.2f} s (target ≤ 10 s), "
          f"{max(contact['err_omega_um'], contact['err_upsilon_um']):.3f} µm from the finest")
    print(f"wrote {out / 'cup3d.csv'} and {out / 'cup3d.png'}")


if __name__ == "__main__":
    main()
