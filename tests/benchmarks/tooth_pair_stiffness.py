"""The contact model's tooth-pair stiffness against ISO 6336-1's, and the mesh's share of the whole
gear's compliance against the compliance the catalogue says is missing (docs/theory/torsion.md,
"Suspects measured": are the teeth the missing compliance?).

    python tests/benchmarks/tooth_pair_stiffness.py [GEARSET ...] [--soften] [--factors 5 20]

Per gear set (design scene, its rated torque's contact):

* **the model's single-pair stiffness** c_model (N/(mm·µm), per mm of face width): at each flank
  station of the loaded teeth near the zone's middle, 1 / ((S_kk − S_kj) b), with S the contact's
  influence coefficients (mm/N, along the contact normal), j the same station on the next tooth
  and b the face width. S_kk alone holds the FS rim's and the balls' motion under a load at k,
  which the next tooth's station shares almost wholly (S_kj); the difference is the pair's own
  compliance: both teeth's bending and shear, their roots' foundation and the contact's local
  term (the 2D mesh's, ~0.05 mm elements). The median over those stations, and its range.
* **ISO 6336-1:2019, 9.3** (method B): the theoretical single stiffness of a solid spur pair,
  c'_th = 1/q'_min, q'_min = 0.04723 + 0.15551/z_n1 + 0.25791/z_n2 (mm·µm/N, profile shift 0; an
  internal gear's z_n2 taken as infinite, as the standard says), and c' = c'_th C_M C_B with the
  correction factor C_M = 0.8 (measured against calculated stiffness of solid gears) and the
  basic-rack factor C_B = (1 + 0.5 (1.2 − h_fP/m)) (1 − 0.02 (20° − α_n)) for the set's dedendum
  coefficient and pressure angle. The standard's involute, 20°-type rack is not the set's tooth:
  a comparison of magnitude, not a check.
* **the mesh's share**: the chain's incremental compliances above T2 (1/K3 of the mesh alone and of
  the whole gear, ``design.torsional``) and the compliance the catalogue's K3 asks for beyond the
  model's (1/K3_catalogue − 1/K3_model): how much softer the teeth would have to be to hold it.

``--soften``: the one-section torsional curve (``chain.torsional_curve``: every ball a one-sided
Hertz support, the series parts) with each station's own pair compliance S_kk − S_kj scaled to
ISO's c' (the set's model / c' ratio, added on the diagonal of both flanks' compliances) against
the same curve as modelled: K1, K2, K3 over the catalogue before and after — what teeth as soft as
the standard's empirical single stiffness would do to the whole gear (a sensitivity: the added
term is local to each station; the teeth's bending shared along a tooth's stations is not scaled).
``--factors F ...``: the same with the pair compliance × F, each K as a ratio to the model's.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

DEFAULT_SETS = ("profiles/seed000_csf40.toml", "profiles/csf32_100.toml", "tests/corpus/csf25_100.toml", "tests/corpus/csf58_50.toml")


def iso_single_stiffness(z1: int, dedendum_coefficient: float, pressure_angle_deg: float) -> tuple[float, float]:
    """(c'_th, c') in N/(mm·µm): ISO 6336-1 method B for a spur pair of z1 teeth meshing an
    internal gear (z_n2 → ∞), no profile shift; C_M = 0.8, C_B of the basic rack."""
    q = 0.04723 + 0.15551 / z1
    c_th = 1.0 / q
    c_b = (1.0 + 0.5 * (1.2 - dedendum_coefficient)) * (1.0 - 0.02 * (20.0 - pressure_angle_deg))
    return c_th, c_th * 0.8 * c_b


def pair_stiffness(design) -> list[float]:
    """The model's single-pair stiffness (N/(mm·µm)) at each station of the loaded teeth in the
    middle half of the rated torque's zone (the teeth whose next tooth has the same stations)."""
    comp = design.contact.compliance
    case = design.contact.cases[0]
    s = comp.matrix_mm_per_n
    tooth = np.asarray(comp.tooth)
    loaded = [int(t) for t, f in zip(case.teeth, case.tooth_force_n) if f > 0.25 * case.max_tooth_force_n]
    out = []
    for t in loaded:
        ks, js = np.flatnonzero(tooth == t), np.flatnonzero(tooth == t + 1)
        if len(ks) != len(js) or not len(ks):
            continue
        for k, j in zip(ks, js):
            local = s[k, k] - s[k, j]
            if local > 0:
                out.append(1.0 / (local * comp.face_width_mm) * 1e-3)  # N/mm per mm → N/(mm·µm)
    return out


def _local(comp) -> np.ndarray:
    """Each station's own pair compliance S_kk − S_kj (mm/N; j: the station on the next tooth, or
    the previous one for the last tooth), at least 0."""
    s, tooth = comp.matrix_mm_per_n, np.asarray(comp.tooth)
    out = np.zeros(len(tooth))
    for t in np.unique(tooth):
        ks = np.flatnonzero(tooth == t)
        for other in (t + 1, t - 1):
            js = np.flatnonzero(tooth == other)
            if len(js) == len(ks):
                out[ks] = np.maximum(np.diag(s)[ks] - s[ks, js], 0.0)
                break
    return out


def soften(d, factor: float) -> tuple[dict, dict]:
    """K1/K2/K3 (N·m/rad) of the one-section curve as modelled and with each station's pair
    compliance × ``factor`` (both flanks)."""
    from dataclasses import replace

    from profilegen.contact.analysis import flank
    from profilegen.contact.chain import catalogue_for, curve_torques_nm, torsional_curve
    from profilegen.contact.inputs import ContactInput

    inputs = ContactInput.from_design(d, name="design")
    cat = catalogue_for(inputs.gearset)
    bp = (float(cat["T1_nm"]), float(cat["T2_nm"]))
    wrap = d.contact.compliance.wrap_half_angle_rad
    sides = {s: flank(inputs, s, wrap_half_angle_rad=wrap, ball_supports="all") for s in (1, -1)}
    softer = {}
    for s, (pts, comp) in sides.items():
        extra = (factor - 1.0) * _local(comp)
        softer[s] = (pts, replace(comp, cs_matrix_mm_per_n=comp.cs_matrix_mm_per_n + np.diag(extra),
                                  matrix_mm_per_n=comp.matrix_mm_per_n + np.diag(extra)))
    torques = curve_torques_nm(inputs.gearset, bp)
    out = []
    for sd in (sides, softer):
        tc = torsional_curve(inputs, torques, sides=sd, breakpoints_nm=bp, catalogue=cat)
        k = tc.k_nm_per_rad["total"]["positive"]
        out.append({"K1": k["K1"], "K2": k["K2"], "K3": k["K3"]})
    return out[0], out[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("sets", nargs="*", default=list(DEFAULT_SETS))
    ap.add_argument("--soften", action="store_true", help="the whole gear with the teeth as soft as ISO's c'")
    ap.add_argument("--factors", type=float, nargs="*", default=[], help="further pair-compliance factors")
    args = ap.parse_args()
    import profilegen as pg

    for path in args.sets:
        gs = pg.load_gearset(ROOT / path if not Path(path).is_absolute() else path)
        d = pg.design(gs, scene="design")
        c = pair_stiffness(d)
        if not c:
            print(f"{gs.name}: no loaded tooth with a next tooth in the window")
            continue
        tooth = gs.tooth
        c_th, c_iso = iso_single_stiffness(int(gs.gear.flexspline_teeth), float(tooth.dedendum_mm) / float(gs.gear.module_mm),
                                           float(tooth.pressure_angle_deg))
        tc = d.torsional.to_dict()
        k = tc["stiffness_nm_per_rad"]
        cat = tc.get("catalogue") or {}
        mesh3 = 1.0 / k["mesh"]["positive"]["K3"]
        total3 = 1.0 / k["total"]["positive"]["K3"]
        print(f"{gs.name} (module {gs.gear.module_mm:g} mm, face {d.contact.compliance.face_width_mm:g} mm, "
              f"{len(c)} stations):")
        print(f"  single-pair stiffness, model: median {statistics.median(c):.1f} N/(mm·µm) "
              f"(range {min(c):.1f}–{max(c):.1f}); ISO 6336-1: c'_th {c_th:.1f}, c' {c_iso:.1f} "
              f"(model / c' = {statistics.median(c) / c_iso:.2f})")
        line = (f"  above T2: mesh 1/K3 {mesh3:.3g} rad/(N·m) of the whole gear's {total3:.3g} "
                f"({mesh3 / total3:.0%})")
        if cat.get("K3_nm_per_rad"):
            missing = 1.0 / float(cat["K3_nm_per_rad"]) - total3
            line += (f"; the catalogue's K3 asks for {missing:.3g} more ({missing / mesh3:.0%} of the mesh's: "
                     f"teeth {1 + missing / mesh3:.2f}× as compliant as modelled, if the mesh alone held it)")
        print(line)
        if args.soften and cat.get("K3_nm_per_rad"):
            f = statistics.median(c) / c_iso
            before, after = soften(d, f)
            row = {k: float(cat[f"{k}_nm_per_rad"]) for k in ("K1", "K2", "K3")}
            print("  one-section curve, model / catalogue: K1 / K2 / K3 "
                  + " / ".join(f"{before[k] / row[k]:.2f}" for k in row) + f"; with each pair's compliance × {f:.2f}: "
                  + " / ".join(f"{after[k] / row[k]:.2f}" for k in row))
        for f in args.factors:
            before, after = soften(d, f)
            print(f"  pair compliance × {f:g}: K1 / K2 / K3 × " + " / ".join(f"{after[k] / before[k]:.3f}" for k in before))
        if not math.isfinite(statistics.median(c)):
            raise SystemExit("non-finite stiffness")


if __name__ == "__main__":
    main()
