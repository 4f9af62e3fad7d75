"""The model against the catalogue at every size (issue 29, build item 3).

    python tests/benchmarks/catalogue_sizes.py [--scene design|verify] [--sizes 14 17 ...] [--ratios 100 50]
                                              [--rim 0.024 [--rim-parts all|ring|cup]]
                                              [--set SECTION.KEY=VALUE ...] [--csv FILE]
                                              [--png FILE] [--json FILE]
                                              [--plot-only JSON] [--plot-cups JSON ...]

For each size (default 14, 17, 20, 25, 32, 40, 50, 58) and ratio (default 100): the gear set
``profilegen.new_gearset(size, ratio)`` writes (catalogue proportions, no per-size fitting: one
set of rules for every size), run through ``profilegen.design(gs, scene=...)``; then, against
the catalogue row of that size and ratio (``profilegen.contact.catalogue.catalogue_row``; ratio
100 → the "> 50" / "80 and above" row):

* K1, K2, K3: the whole gear's, as the design sheet and design.json read them
  (``Design.torsional.headline()["model_over_catalogue"]``, i.e. ``TorsionalCurve.catalogue_comparison``);
* the torsion angle at T2: the model's rotation at T2 less its first contact (θ₀, the
  no-load gap taken up) against ``torsion_angle_rad(row, T2)`` (the catalogue's three lines);
* lost motion (model, arcmin, at the curve's ± lost-motion torque) against the catalogue's
  upper limit ("< 1 arcmin": a limit, not a value — model/limit ≤ 1 is a pass, not a match);
* transmission error peak to peak (verify scene only): the loaded tooth-passage ripple at rated
  torque with the balls held at fixed angles and rigid; it leaves out every manufacturing error
  (tooth pitch and profile errors, run-out of the CS and the wave generator, bearing
  eccentricity), the balls' rolling (the cage ripple) and the Hertz ball springs — so it is a
  floor of the catalogue's transmission accuracy (also an upper limit), not a comparable value;
* the ratcheting estimate (verify scene only) against the catalogue's ratcheting torque where
  published (sizes 25, 32, 40 at ratios 50, 80, 100; table 4 of the LLC catalogue);
* with ``--rim F`` the sets' rim (and cup wall and bottom) at δ/r_m = F instead of the rule's 3 %
  (``--rim-parts ring``: the tooth ring and the wall, which may not be thicker than the ring, the
  bottom as the rule; ``cup``: the wall and the bottom, the ring as the rule); the figure then goes
  to /tmp unless ``--png`` says where:
  a study of the rim (the strength section of docs/validation/catalogue-sizes.md), not what
  ``new`` writes;
* with ``--set SECTION.KEY=VALUE`` (repeatable) any other value of the sets' TOML changed, e.g.
  ``--set tooth.addendum_coefficient=0.5 --set wave_generator.deflection_coefficient=0.8``: a study
  of a proportion ``new`` chooses (the tooth's form in docs/theory/torsion.md, "Suspects measured"),
  not what ``new`` writes; the figure then goes to /tmp unless ``--png`` says where;
* the strength checks (``Design.stress``): the tooth ring's fatigue (Goodman at the rated torque)
  and yield (momentary torque) safety and the cup bottom's yield safety, with the tooth-root
  stress taken apart: the assembly stress σ_ass = K_σ · E δ/2 · Δκ (K_σ, and Δκ over the
  ellipse value 3 w0/r_m², w0 the set's deflection, at the design section) and the load stress
  σ_load at the rated torque. The fatigue check's amplitude is σ_ass + σ_load/2, its mean σ_load/2.

It prints one table, writes it as CSV (default /tmp/catalogue_sizes.csv) and as JSON, and draws
model/catalogue against size (one line per quantity, a ±30 % band and the 1.5× lines of the
ratcheting goal) to docs/img/catalogue_sizes.png (``--png``). ``--plot-only JSON`` redraws the
figure from a JSON this script wrote (design- and verify-scene JSONs can be given together:
``--plot-only a.json b.json``, the later one winning per size). Every run under a 4 GB memory cap.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import profilegen as pg  # noqa: E402
from profilegen.contact.catalogue import catalogue_row, torsion_angle_rad  # noqa: E402

ARCMIN_PER_RAD = 60.0 * 180.0 / math.pi
SIZES = (14, 17, 20, 25, 32, 40, 50, 58)
BAND = 0.30
RATCHET_GOAL = 1.5
COLUMNS = ("size", "ratio", "scene", "verdict", "seconds",
           "K1_model", "K1_cat", "K1_ratio", "K2_model", "K2_cat", "K2_ratio", "K3_model", "K3_cat", "K3_ratio",
           "phi_T2_model_arcmin", "phi_T2_cat_arcmin", "phi_T2_ratio",
           "lost_motion_arcmin", "lost_motion_limit_arcmin", "lost_motion_ratio",
           "te_pp_arcsec", "te_torque_nm", "te_limit_arcsec",
           "ratchet_model_nm", "ratchet_cat_nm", "ratchet_ratio",
           "K1_one_section_ratio", "K2_one_section_ratio", "K3_one_section_ratio", "crowning_um", "taper_um_per_mm",
           "ring_fatigue_safety", "ring_yield_safety", "bottom_yield_safety", "rim_per_neutral_radius",
           "stress_factor", "curvature_over_ellipse", "assembly_mpa", "load_rated_mpa", "load_momentary_mpa",
           "failed_checks", "error", "settings")


def with_rim(data: dict, rim_per_neutral_radius: float, parts: str = "all") -> None:
    """Put into ``data`` (the TOML tables of a set ``profilegen new`` wrote) its rim, cup wall and
    cup bottom at δ/r_m = ``rim_per_neutral_radius`` instead of the rule's 3 % (δ solved from
    r_m = d/2 − 1.2 m − δ/2, as the rule does): a study of the rim, not a set ``new`` writes.
    ``parts``: "all"; "ring" (the ring and the wall, the bottom as written); "cup" (the wall and
    the bottom, the ring as written)."""
    g = data["gear"]
    frac = float(rim_per_neutral_radius)
    delta = round(frac * (g["module_mm"] * g["flexspline_teeth"] / 2.0 - 1.2 * g["module_mm"]) / (1.0 + frac / 2.0), 4)
    if parts not in ("all", "ring", "cup"):
        raise SystemExit(f"--rim-parts {parts!r}: one of all, ring, cup")
    if parts in ("all", "ring"):
        g["rim_thickness_mm"] = delta
    data["cup"]["wall_thickness_mm"] = delta
    if parts in ("all", "cup"):
        data["cup"]["bottom_thickness_mm"] = delta


def with_settings(data: dict, settings: list) -> None:
    """Put each ``SECTION.KEY=VALUE`` of ``settings`` (VALUE a TOML value) into ``data`` (the TOML
    tables of a set): a study of a proportion ``new`` chooses (e.g.
    ``wave_generator.deflection_coefficient=0.8``, ``tooth.addendum_coefficient=0.6``), not a set
    ``new`` writes."""
    import tomllib

    for item in settings:
        key, sep, value = item.partition("=")
        section, dot, name = key.strip().rpartition(".")
        if not sep or not dot:
            raise SystemExit(f"--set {item!r}: SECTION.KEY=VALUE, e.g. tooth.addendum_coefficient=0.6")
        table = data
        for part in section.split("."):
            table = table.setdefault(part, {})
        table[name] = tomllib.loads(f"v = {value.strip()}")["v"]


def measure(size: int, ratio: int, scene: str, rim: float | None = None, rim_parts: str = "all",
            settings: list | None = None) -> dict:
    out = dict.fromkeys(COLUMNS)
    out.update(size=size, ratio=ratio, scene=scene)
    row = catalogue_row(size, ratio)
    out["ratchet_cat_nm"] = row.get("ratcheting_torque_nm")
    made = pg.new_gearset(size, ratio)
    gs = made.gearset
    if rim is not None or settings:
        import tomllib

        from profilegen.gearset import parse_gearset

        data = tomllib.loads(made.text)
        if rim is not None:
            with_rim(data, rim, rim_parts)
        with_settings(data, settings or [])
        gs = parse_gearset(data)
        out["settings"] = "; ".join(settings or []) or None
    t0 = time.perf_counter()
    try:
        d = pg.design(gs, scene=scene)
    except Exception as exc:  # a size the pipeline refuses is a result of the study, not a crash of it
        out.update(error=f"{type(exc).__name__}: {exc}"[:200], seconds=time.perf_counter() - t0)
        return out
    out["seconds"] = time.perf_counter() - t0
    v = d.verdict.to_dict()
    out["verdict"] = v["status"]
    out["failed_checks"] = "; ".join(c["text"] or c["name"] for c in v.get("checks", []) if c.get("status") == "FAIL") or None
    curve = d.torsional
    if curve is None:
        out["error"] = "no torsional curve: " + "; ".join(str(w) for w in d.warnings)[:200]
    else:
        head = curve.headline()
        cmp = curve.catalogue_comparison()["compared"]
        for k in ("K1", "K2", "K3"):
            c = cmp.get(f"{k}_nm_per_rad")
            if c is not None:
                out.update({f"{k}_model": c["model"], f"{k}_cat": c["catalogue"], f"{k}_ratio": c["model_over_catalogue"]})
        t2 = float(row["T2_nm"])
        try:
            phi = curve.rotation_at(t2) - curve.first_contact_rad["positive"]
            cat_phi = torsion_angle_rad(row, t2)
            out.update(phi_T2_model_arcmin=phi * ARCMIN_PER_RAD, phi_T2_cat_arcmin=cat_phi * ARCMIN_PER_RAD,
                       phi_T2_ratio=phi / cat_phi)
        except Exception as exc:  # T2 not a torque of the curve (breakpoints not the catalogue's)
            out["error"] = f"torsion at T2: {exc}"[:200]
        one = head.get("one_section")  # across the face (verify): the face held straight, beside the slices
        if one:
            for k in ("K1", "K2", "K3"):
                out[f"{k}_one_section_ratio"] = (one.get("model_over_catalogue") or {}).get(f"{k}_nm_per_rad")
            out.update(crowning_um=curve.face.get("crowning_um"), taper_um_per_mm=curve.face.get("taper_um_per_mm"))
        lm, limit = head["lost_motion_arcmin"], row.get("lost_motion_max_arcmin")
        out.update(lost_motion_arcmin=lm, lost_motion_limit_arcmin=limit,
                   lost_motion_ratio=None if limit is None else lm / limit)
    strength(d, gs, out)
    te = d.transmission
    if te is not None:
        out.update(te_pp_arcsec=te.peak_to_peak_arcsec, te_torque_nm=te.torque_nm,
                   te_limit_arcsec=None if row.get("transmission_accuracy_max_arcmin") is None
                   else 60.0 * row["transmission_accuracy_max_arcmin"])
    r = d.ratcheting
    if r is None and getattr(d.scene, "ratcheting", False):
        why = [str(w) for w in d.warnings if "ratchet" in str(w).lower()]
        out["error"] = "; ".join(filter(None, [out["error"], "no ratcheting estimate: " + (why[0] if why else "?")]))[:300]
    if r is not None:
        cat = row.get("ratcheting_torque_nm")
        out.update(ratchet_model_nm=r.torque_nm, ratchet_cat_nm=cat,
                   ratchet_ratio=None if cat is None or not math.isfinite(r.torque_nm) else r.torque_nm / cat)
    return out


def strength(d, gs, out: dict) -> None:
    """The strength checks and the tooth-root stress taken apart (module docstring), into ``out``."""
    st = d.stress
    if st is None:
        return
    safety = {c.name: c.value for c in st.checks}
    ring, g = st.tooth_ring, gs.gear
    ellipse = 3.0 * gs.deflection_mm / g.neutral_radius_mm**2  # Δκ(0) of ω = w0 cos 2φ, to first order
    out.update(ring_fatigue_safety=safety.get("tooth ring fatigue"), ring_yield_safety=safety.get("tooth ring yield"),
               bottom_yield_safety=safety.get("cup bottom yield"),
               rim_per_neutral_radius=g.rim_thickness_mm / g.neutral_radius_mm,
               stress_factor=ring[0].stress_influence_factor,
               curvature_over_ellipse=ring[0].curvature_change_mm_inv / ellipse,
               assembly_mpa=ring[0].assembly_stress_mpa, load_rated_mpa=ring[0].load_stress_mpa,
               load_momentary_mpa=ring[-1].load_stress_mpa)


def strength_table(rows: list) -> str:
    """The strength columns as a markdown table."""
    head = ("size", "ratio", "δ/r_m", "K_σ", "Δκ / ellipse", "σ_ass MPa", "σ_load rated MPa", "σ_load momentary MPa",
            "ring fatigue", "ring yield", "bottom yield")
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = (r["size"], r["ratio"], fmt(r.get("rim_per_neutral_radius"), ".4f"), fmt(r.get("stress_factor"), ".2f"),
                 fmt(r.get("curvature_over_ellipse"), ".2f"), fmt(r.get("assembly_mpa"), ".0f"),
                 fmt(r.get("load_rated_mpa"), ".0f"), fmt(r.get("load_momentary_mpa"), ".0f"),
                 fmt(r.get("ring_fatigue_safety"), ".2f"), fmt(r.get("ring_yield_safety"), ".2f"),
                 fmt(r.get("bottom_yield_safety"), ".2f"))
        lines.append("| " + " | ".join(map(str, cells)) + " |")
    return "\n".join(lines)


def fmt(v, spec=".3g") -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return format(v, spec)
    return str(v)


def table(rows: list) -> str:
    head = ("size", "ratio", "scene", "verdict", "s", "K1 m/c", "K2 m/c", "K3 m/c", "φ(T2) m/c", "φ(T2) model′",
            "φ(T2) cat′", "K1, K2 m/c one section", "crown µm", "LM′", "LM/limit", "TE p-p″", "TE limit″", "ratchet N·m", "cat N·m", "ratchet m/c")
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = (r["size"], r["ratio"], r["scene"], r["verdict"] or "—", fmt(r["seconds"], ".0f"),
                 fmt(r["K1_ratio"], ".2f"), fmt(r["K2_ratio"], ".2f"), fmt(r["K3_ratio"], ".2f"),
                 fmt(r["phi_T2_ratio"], ".2f"), fmt(r["phi_T2_model_arcmin"], ".2f"), fmt(r["phi_T2_cat_arcmin"], ".2f"),
                 "—" if r.get("K1_one_section_ratio") is None else
                 f"{r['K1_one_section_ratio']:.2f}, {r['K2_one_section_ratio']:.2f}", fmt(r.get("crowning_um"), ".3g"),
                 fmt(r["lost_motion_arcmin"], ".3f"), fmt(r["lost_motion_ratio"], ".2f"), fmt(r["te_pp_arcsec"], ".2f"),
                 fmt(r["te_limit_arcsec"], ".0f"), fmt(r["ratchet_model_nm"], ".4g"), fmt(r["ratchet_cat_nm"], ".4g"),
                 fmt(r["ratchet_ratio"], ".2f"))
        lines.append("| " + " | ".join(map(str, cells)) + " |")
        for note in ("failed_checks", "error"):
            if r.get(note):
                lines.append(f"| ⤷ | {r['size']}/{r['ratio']} {r['scene']}, {note.replace('_', ' ')}: {r[note]} |"
                             + " |" * (len(head) - 2))
    return "\n".join(lines)


def plot(rows: list, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(10, 4.8), dpi=110)
    ax.axhspan(1 - BAND, 1 + BAND, color="0.88", label=f"±{BAND:.0%}")
    ax.axhline(1.0, color="0.5", lw=0.8)
    for y in (1 / RATCHET_GOAL, RATCHET_GOAL):
        ax.axhline(y, color="0.5", lw=0.8, ls=":")
    series = (("K1_ratio", "K1", "o", "C0"), ("K2_ratio", "K2", "s", "C1"), ("K3_ratio", "K3", "^", "C2"),
              ("phi_T2_ratio", "torsion angle at T2", "d", "C3"), ("ratchet_ratio", "ratcheting torque", "*", "C4"),
              ("K1_one_section_ratio", "K1, face held straight (one section)", "x", "C7"))
    ratios = sorted({r["ratio"] for r in rows}, reverse=True)
    for i, ratio in enumerate(ratios):  # the first (highest) ratio solid, the others dashed with open markers
        for key, label, marker, color in series:
            pts = [(r["size"], r[key]) for r in rows if r["ratio"] == ratio and r[key] is not None]
            if pts:
                pts.sort()
                scenes = sorted({r["scene"] for r in rows if r["ratio"] == ratio and r[key] is not None})
                ax.plot(*zip(*pts), marker=marker, ls="-" if i == 0 else "--", color=color, ms=6 if marker == "*" else 5,
                        mfc=color if i == 0 else "white", alpha=1.0 if i == 0 else 0.7,
                        label=f"{label}, ratio {ratio} ({'/'.join(scenes)} scene)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xticks(SIZES)
    ax.set_xticklabels([str(s) for s in SIZES])
    ax.minorticks_off()
    ticks = [0.3, 0.4, 0.5, 0.7, 1 - BAND, 1.0, 1 + BAND, RATCHET_GOAL, 2.0, 3.0, 4.0, 6.0]
    lo, hi = ax.get_ylim()
    ticks = sorted({round(t, 3) for t in ticks if lo <= t <= hi})
    ax.set_yticks(ticks)
    ax.set_yticklabels([f"{t:g}" for t in ticks])
    ax.set_xlabel("size")
    ax.set_ylabel("model / catalogue")
    ax.set_title("profilegen new sets against the catalogue (dotted: 1/1.5 and 1.5)", fontsize=10)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.grid(True, which="major", alpha=0.3)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    print(f"figure: {path}")


def plot_cups(runs: list, path: Path) -> None:
    """K1, K2, K3 and the torsion at T2 over the catalogue against size, one line style per run of
    this script (``--json`` files of one ratio), each labelled by its sets' δ/r_m: the rim study of
    docs/validation/catalogue-sizes.md ("The cup's thickness sets K2 and K3")."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 4.6), dpi=110)
    ax.axhspan(1 - BAND, 1 + BAND, color="0.88", label=f"±{BAND:.0%}")
    ax.axhline(1.0, color="0.5", lw=0.8)
    series = (("K1_ratio", "K1", "o", "C0"), ("K2_ratio", "K2", "s", "C1"), ("K3_ratio", "K3", "^", "C2"),
              ("phi_T2_ratio", "torsion at T2", "d", "C3"))
    styles = ("-", "--", ":", "-.")
    for i, rows in enumerate(runs):
        fracs = sorted({round(float(r["rim_per_neutral_radius"]), 4) for r in rows})
        ratios = sorted({r["ratio"] for r in rows})
        name = "/".join(f"{f:.1%}" for f in fracs) + " of r_m, ratio " + "/".join(map(str, ratios))
        for key, label, marker, color in series:
            pts = sorted((r["size"], r[key]) for r in rows if r[key] is not None)
            if pts:
                ax.plot(*zip(*pts), marker=marker, ls=styles[i % len(styles)], color=color, ms=5,
                        mfc=color if i == 0 else "white", label=f"{label}, cup {name}")
    ax.set_xscale("log")
    ax.set_xticks(SIZES)
    ax.set_xticklabels([str(s) for s in SIZES])
    ax.minorticks_off()
    ax.set_xlabel("size")
    ax.set_ylabel("model / catalogue (verify scene)")
    ax.set_title("profilegen new sets with the tooth ring, cup wall and bottom at δ/r_m", fontsize=10)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    print(f"figure: {path}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="verify", help="design scene (default verify; 'design' is the quick pass)")
    ap.add_argument("--sizes", type=int, nargs="+", default=list(SIZES))
    ap.add_argument("--ratios", type=int, nargs="+", default=[100])
    ap.add_argument("--rim", type=float, default=None,
                    help="a study of the rim: δ/r_m (e.g. 0.024) instead of the rule's 0.03, rim = wall = bottom")
    ap.add_argument("--rim-parts", default="all", choices=("all", "ring", "cup"),
                    help="with --rim: all (default), ring (ring and wall), cup (wall and bottom)")
    ap.add_argument("--set", dest="settings", action="append", default=[], metavar="SECTION.KEY=VALUE",
                    help="a study of a proportion: put VALUE (TOML) into the set's table, e.g. "
                         "wave_generator.deflection_coefficient=0.8 (repeatable; the figure then goes to /tmp)")
    ap.add_argument("--csv", type=Path, default=Path("/tmp/catalogue_sizes.csv"))
    ap.add_argument("--json", type=Path, default=None, help="default: the CSV's path with .json")
    ap.add_argument("--png", type=Path, default=None, help="default: docs/img/catalogue_sizes.png (with --rim: /tmp)")
    ap.add_argument("--plot-only", type=Path, nargs="+", default=None, help="redraw from JSONs this script wrote")
    ap.add_argument("--plot-cups", type=Path, nargs="+", default=None,
                    help="the rim study's figure from runs' JSONs (one line style each, labelled by δ/r_m)")
    a = ap.parse_args(argv)
    if a.plot_cups:
        plot_cups([json.loads(p.read_text()) for p in a.plot_cups], a.png or ROOT / "docs" / "img" / "catalogue_cup.png")
        return
    if a.png is None:  # a rim study does not overwrite the docs' figure of the sets as written
        a.png = Path("/tmp/catalogue_sizes_rim.png") if a.rim is not None or a.settings else ROOT / "docs" / "img" / "catalogue_sizes.png"
    if a.plot_only:
        merged = {}
        for p in a.plot_only:
            for r in json.loads(p.read_text()):
                merged[(r["size"], r["ratio"], r["scene"])] = r
        rows = sorted(merged.values(), key=lambda r: (r["ratio"], r["size"], r["scene"]))
        # per size and ratio, the verify scene's stiffness if there is one (the plot shows one line per quantity)
        best = {}
        for r in rows:
            key = (r["size"], r["ratio"])
            if key not in best or r["scene"] == "verify":
                best[key] = r
        print(table(rows))
        print()
        print(strength_table(rows))
        plot(sorted(best.values(), key=lambda r: (r["ratio"], r["size"])), a.png)
        return
    resource.setrlimit(resource.RLIMIT_AS, (4_000_000_000, 4_000_000_000))
    rows = []
    json_path = a.json or a.csv.with_suffix(".json")
    for ratio in a.ratios:
        for size in a.sizes:
            r = measure(size, ratio, a.scene, a.rim, a.rim_parts, a.settings)
            rows.append(r)
            print(f"size {size} ratio {ratio} ({a.scene}): {r['seconds']:.0f} s, K1/K2/K3 m/c "
                  f"{fmt(r['K1_ratio'], '.2f')}/{fmt(r['K2_ratio'], '.2f')}/{fmt(r['K3_ratio'], '.2f')}, "
                  f"φ(T2) m/c {fmt(r['phi_T2_ratio'], '.2f')}, ratchet {fmt(r['ratchet_model_nm'], '.4g')}, "
                  f"ring fatigue/yield {fmt(r['ring_fatigue_safety'], '.2f')}/{fmt(r['ring_yield_safety'], '.2f')}"
                  + (f"  [{r['error']}]" if r["error"] else ""), flush=True)
            # write as we go: a long verify run stopped half way keeps what it measured
            with a.csv.open("w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=COLUMNS)
                w.writeheader()
                w.writerows(rows)
            json_path.write_text(json.dumps(rows, indent=1, default=str))
    print()
    print(table(rows))
    print()
    print(strength_table(rows))
    print(f"\ncsv: {a.csv}; json: {json_path}")
    plot(rows, a.png)


if __name__ == "__main__":
    main()
