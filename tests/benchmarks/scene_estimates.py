"""Scene against scene over the corpus (issue 28 item 2): every design-sheet number in the sketch,
design and verify scenes, and |sketch - design|, |design - verify| per number per set.

    python tests/benchmarks/scene_estimates.py run       # run what is missing (2 processes, 4 GB each)
    python tests/benchmarks/scene_estimates.py table     # the table from the runs: JSON + markdown
    python tests/benchmarks/scene_estimates.py           # both

The corpus is tests/corpus (``tests/corpus/make.py``: 24 generated catalogue-like sets and the 5
bundled ones). Each run writes ``profilegen design``'s files (no figures) into
``WORK/<set>/<scene>/`` (default WORK: build/scene_estimates, git-ignored) with ``run.json`` (wall
time, or the error); a folder with ``run.json`` is not run again (``--force`` reruns). Two worker
processes at most (a ``multiprocessing.Pool``: daemonic workers, so the stages' own pools stay in
the worker), each under ``RLIMIT_AS`` 4 GB, one run per worker process.

The table (``tests/corpus/scene_table.json`` and ``.md``, committed) holds every number of every run
(None: not computed by that scene, with the reason) and the differences; the estimates of
:mod:`profilegen.pipeline.scene_estimates` are derived from it (``--derive`` prints the table of maxima
the module's constants come from) and tests/unit/test_scene_estimates.py checks every difference
against them.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "corpus"))
import make as corpus_make  # noqa: E402

SCENES = ("sketch", "design", "verify")
MEMORY_CAP_BYTES = 4 * 1024 ** 3
TABLE_JSON = ROOT / "tests" / "corpus" / "scene_table.json"
TABLE_MD = ROOT / "tests" / "corpus" / "scene_table.md"


_SNAPSHOT: list[str] = []  # the package folder the workers import (set before the pool forks)


def _limit() -> None:
    import resource

    sys.path.insert(0, _SNAPSHOT[0])
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_CAP_BYTES, MEMORY_CAP_BYTES))
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def run_one(task: tuple[str, str, str, str]) -> tuple[str, str, float | None, str | None]:
    """One design run into ``out``: (set, scene, wall s or None, error or None)."""
    name, path, scene, out = task
    import traceback

    import profilegen as pg

    assert Path(pg.__file__).resolve().parents[1] == Path(sys.path[0]).resolve(), pg.__file__  # the snapshot
    out = Path(out)
    t0 = time.perf_counter()
    try:
        gs = pg.load_gearset(path)
        result = pg.design(gs, scene=scene)
        pg.write_design(result, out / "files", figure=False)
        wall, err = time.perf_counter() - t0, None
    except BaseException as exc:  # noqa: BLE001 - a run's failure is a row of the table
        wall, err = None, f"{type(exc).__name__}: {exc}".splitlines()[0][:400]
        (out).mkdir(parents=True, exist_ok=True)
        (out / "traceback.txt").write_text(traceback.format_exc(), encoding="utf-8")
    out.mkdir(parents=True, exist_ok=True)
    (out / "run.json").write_text(json.dumps({"set": name, "scene": scene, "wall_s": wall, "error": err}), encoding="utf-8")
    return name, scene, wall, err


def snapshot(commit: str) -> tuple[str, Path]:
    """The package at ``commit`` (``git archive``) under build/snapshot/<sha>: the runs measure one
    commit while the working tree changes under them. (full sha, the folder to put on sys.path)."""
    sha = subprocess.run(["git", "rev-parse", commit], cwd=ROOT, check=True, capture_output=True, text=True).stdout.strip()
    where = ROOT / "build" / "snapshot" / sha[:7]
    if not (where / "profilegen" / "__init__.py").exists():
        where.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "archive", sha, "profilegen"], cwd=ROOT, check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", str(where)], input=archive, check=True)
    return sha, where


def run(work: Path, *, force: bool = False, workers: int = 2, only: list[str] | None = None) -> None:
    sets = [(n, p) for n, p in corpus_make.corpus() if not only or n in only]
    tasks = []
    for scene in SCENES:  # every cheap run first: the sketch/design table fills while verify runs
        for name, path in sets:
            out = work / name / scene
            if force or not (out / "run.json").exists():
                tasks.append((name, str(path), scene, str(out)))
    print(f"{len(tasks)} runs to do in {work} ({min(workers, 2)} processes)", flush=True)
    t0 = time.perf_counter()
    ctx = multiprocessing.get_context("fork")  # the parent imported no profilegen: each worker imports the snapshot
    with ctx.Pool(min(workers, 2), initializer=_limit, maxtasksperchild=1) as pool:
        for name, scene, wall, err in pool.imap_unordered(run_one, tasks):
            state = f"{wall:.1f} s" if err is None else f"FAILED {err}"
            print(f"[{time.perf_counter() - t0:7.0f} s] {name:20s} {scene:7s} {state}", flush=True)
    total = time.perf_counter() - t0
    done = json.loads((work / "wall.json").read_text()) if (work / "wall.json").exists() else []
    done.append({"runs": len(tasks), "wall_s": total, "workers": min(workers, 2),
                 "finished": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
                 "load_average_1min_at_end": os.getloadavg()[0]})
    (work / "wall.json").write_text(json.dumps(done), encoding="utf-8")
    print(f"{len(tasks)} runs in {total:.0f} s wall", flush=True)


PAIRS = (("sketch", "design"), ("design", "verify"))
#: why a scene leaves a number out (keyed by the number's group)
NOT_COMPUTED = {
    "face": "no face stage (no model of the coning across the face): no design section, FS modification or check across the face",
    "contact": "no loaded tooth contact: no stiffness, tooth force or lost motion",
    "curve": "no whole-gear torsional curve at this torque",
    "ratcheting": "no ratcheting estimate (the verify scene's)",
    "flank": "the fitted flank has no such element",
}


def _group(key: str) -> str:
    if key in ("design_section_z_mm", "fs_taper_um_per_mm", "fs_crowning_um", "face_interference_mm", "face_backlash_mm"):
        return "face"
    if key.startswith("k_whole"):
        return "curve"
    if key.startswith(("k_", "k1", "max_tooth_force", "lost_motion")):
        return "contact"
    if key.startswith("ratcheting"):
        return "ratcheting"
    return "flank"


def _read(folder: Path) -> dict | None:
    files = folder / "files"
    if not (files / "design.json").exists():
        return None

    def load(name):
        p = files / name
        return json.loads(p.read_text(encoding="utf-8")) if p.exists() else None

    return {name: load(name) for name in ("design.json", "profile_fit.json", "contact.json", "stress.json")}


def _round_up(x: float) -> float:
    """Up to two significant digits (0 stays 0)."""
    if x <= 0:
        return 0.0
    mag = 10.0 ** (math.floor(math.log10(x)) - 1)
    return float(f"{math.ceil(x / mag * (1 - 1e-12)) * mag:.2g}")  # 0.35, not 0.35000000000000003


def _normalised(kind: str, d: float, cheap_value, module_mm: float) -> float:
    if kind == "per_module":
        return d / module_mm
    if kind == "relative":
        return d / abs(float(cheap_value)) if cheap_value else math.inf
    return d


def table(work: Path) -> dict:
    """The measurement table from the runs under ``work``: written to TABLE_JSON and TABLE_MD."""
    from profilegen.pipeline import scene_estimates as se

    sha = (work / "commit.txt").read_text().strip()
    sets = {}
    for name, path in corpus_make.corpus():
        import tomllib

        gear = tomllib.loads(Path(path).read_text(encoding="utf-8"))["gear"]
        row = {"module_mm": gear["module_mm"], "teeth": [gear["flexspline_teeth"], gear["circular_spline_teeth"]],
               "path": str(Path(path).relative_to(ROOT)), "scenes": {}}
        for scene in SCENES:
            run_json = work / name / scene / "run.json"
            info = json.loads(run_json.read_text()) if run_json.exists() else {"wall_s": None, "error": "not run"}
            data = _read(work / name / scene) if info.get("error") is None else None
            entry = {"wall_s": info.get("wall_s"), "error": info.get("error")}
            if data is not None:
                d = data["design.json"]
                entry["numbers"] = se.sheet_numbers(d, data["profile_fit.json"], data["contact.json"], data["stress.json"])
                v = d["verdict"]
                entry["verdict"] = {"status": v["status"], "failures": v.get("failures", []),
                                    "not_checked": v.get("not_checked", []), "not_modelled": v.get("not_modelled", []),
                                    "checks": [[c["name"], c["status"], c["value"], c["required"], c["kind"]]
                                               for c in v["checks"]]}
                entry["time_s"] = d.get("time_s")
            row["scenes"][scene] = entry
        sets[name] = row
    diffs = {}
    for cheap, dear in PAIRS:
        pair = {}
        for key, (_, _, kind) in se.NUMBERS.items():
            per = {}
            for name, row in sets.items():
                a, b = row["scenes"][cheap].get("numbers"), row["scenes"][dear].get("numbers")
                if a is None or b is None:
                    continue
                d = se.difference(key, a[key], b[key])
                # "has": which scene computed it (c: the cheaper, d: the dearer)
                per[name] = {"abs": d, "normalised": None if d is None else _normalised(kind, d, a[key], row["module_mm"]),
                             "has": ("c" if a[key] is not None else "") + ("d" if b[key] is not None else "")}
            pair[key] = per
        diffs[f"{cheap}-{dear}"] = pair
    outlines = {}  # the largest normal distance between two scenes' CS tooth-space outlines (scene_agreement.py's)
    sys.path.insert(0, str(ROOT / "tests" / "benchmarks"))
    from scene_agreement import outline_distance_mm

    for name in sets:
        spaces = {}
        for scene in SCENES:
            p = work / name / scene / "files" / "profile_fit.json"
            if p.exists():
                spaces[scene] = json.loads(p.read_text(encoding="utf-8"))["space"]
        outlines[name] = {f"{a}-{b}": outline_distance_mm(spaces[a], spaces[b]) for a, b in PAIRS
                          if a in spaces and b in spaces}
    walls = json.loads((work / "wall.json").read_text()) if (work / "wall.json").exists() else []
    out = {"commit": sha, "date": time.strftime("%Y-%m-%d", time.gmtime()), "sets": sets, "differences": diffs,
           "numbers": {k: list(v) for k, v in se.NUMBERS.items()}, "wall": walls,
           "safety_factor": se.SAFETY_FACTOR, "outline_mm": outlines}
    out["estimates"] = derive(out)
    TABLE_JSON.write_text(json.dumps(out, indent=1, sort_keys=False) + "\n", encoding="utf-8")
    TABLE_MD.write_text(markdown(out), encoding="utf-8")
    print(f"wrote {TABLE_JSON.relative_to(ROOT)} and {TABLE_MD.relative_to(ROOT)}")
    return out


#: Numbers measured but with no bound claimed, and why (decided on the measurement: see
#: docs/validation/scene-estimates.md). (cheap scene, key) -> reason.
POLICY: dict[tuple[str, str], str] = {}


def write_module(tab: dict) -> None:
    """Rewrite the measurement block of profilegen/pipeline/scene_estimates.py from the table."""
    path = ROOT / "profilegen" / "pipeline" / "scene_estimates.py"
    text = path.read_text(encoding="utf-8")
    head = "# --- the measurement: written by"
    tail = "# --- end of the measurement ---"
    i, j = text.index(head), text.index(tail)
    walls = sum(w["wall_s"] for w in tab["wall"])
    lines = [head + " `python tests/benchmarks/scene_estimates.py table --write-module` ---",
             "#: How the estimates were measured.", "MEASURED: dict[str, Any] = {",
             f'    "corpus": "tests/corpus: {len(tab["sets"]) - len(corpus_make.BUNDLED)} profilegen new sets (sizes 14-58, '
             f'ratios 50-160, CSF/SHF) + {len(corpus_make.BUNDLED)} bundled sets",',
             f'    "sets": {len(tab["sets"])},', f'    "commit": "{tab["commit"]}",', f'    "date": "{tab["date"]}",',
             '    "command": "python tests/benchmarks/scene_estimates.py",',
             f'    "wall_s": {walls:.0f},  # the runs, 2 processes',
             '    "safety_factor": SAFETY_FACTOR,', "}", "",
             "#: scene → number key → Estimate(kind, value, largest observed) | NotEstimated(reason)",
             "ESTIMATES: dict[str, dict[str, Estimate | NotEstimated]] = {"]
    for cheap, rows in tab["estimates"].items():
        lines.append(f'    "{cheap}": {{')
        for key, rec in rows.items():
            if "not_estimated" in rec:
                lines.append(f'        "{key}": NotEstimated({rec["not_estimated"]!r}),')
            else:
                lines.append(f'        "{key}": Estimate("{rec["kind"]}", {rec["value"]!r}, {rec["observed"]:.6g}),')
        lines.append("    },")
    lines.append("}")
    path.write_text(text[:i] + "\n".join(lines) + "\n" + text[j:], encoding="utf-8")
    print(f"wrote the measurement into {path.relative_to(ROOT)}")


def derive(tab: dict) -> dict:
    """Per cheap scene and number: the estimate (SAFETY_FACTOR x the largest normalised difference,
    rounded up) or 'not estimated' with the reason."""
    from profilegen.pipeline import scene_estimates as se

    out = {}
    for cheap, dear in PAIRS:
        rows = {}
        for key, (_, _, kind) in se.NUMBERS.items():
            per = tab["differences"][f"{cheap}-{dear}"][key]
            have_cheap = [n for n, v in per.items() if "c" in v["has"]]
            have_dear = [n for n, v in per.items() if "d" in v["has"]]
            both = [v["normalised"] for v in per.values() if v.get("abs") is not None]
            if not have_cheap:
                reason = (f"the {cheap} scene computes no {se.NUMBERS[key][0]}" if not have_dear else
                          f"the {cheap} scene has {NOT_COMPUTED[_group(key)]}")
                rows[key] = {"not_estimated": reason}
            elif not have_dear:
                rows[key] = {"not_estimated": f"the {dear} scene does not compute it"}
            elif not both:
                rows[key] = {"not_estimated": "never computed by both scenes in the corpus"}
            else:
                observed = max(both)
                if (cheap, key) in POLICY:
                    rows[key] = {"not_estimated": POLICY[cheap, key] + f" (largest observed: {observed:.3g}, {kind})"}
                    continue
                rows[key] = {"kind": kind, "observed": observed, "value": _round_up(se.SAFETY_FACTOR * observed),
                             "compared": len(both),
                             "one_sided": sorted(set(have_cheap) ^ set(have_dear))}
        out[cheap] = rows
    return out


def _f(x, digits=4) -> str:
    if x is None:
        return "—"
    if isinstance(x, list):
        return "(" + ", ".join(f"{v:.4f}" for v in x) + ")"
    if isinstance(x, str):
        return x
    return f"{x:.{digits}g}"


def check_flips(tab: dict) -> list[str]:
    """Each check a cheaper scene PASSES and verify FAILS, with the cheaper value, the requirement
    and the cheaper scene's estimate of the value (the flip is covered when |value - required| is
    within it)."""
    from profilegen.pipeline import scene_estimates as se

    out = []
    for n, r in tab["sets"].items():
        final = {c[0]: c for c in (r["scenes"]["verify"].get("verdict") or {"checks": []})["checks"]}
        for cheap in ("sketch", "design"):
            checks = (r["scenes"][cheap].get("verdict") or {"checks": []})["checks"]
            kinds = {c[0]: c[4] for c in checks}
            for name, status, value, required, _ in checks:
                f = final.get(name)
                if status != "PASS" or f is None or f[1] != "FAIL":
                    continue
                key = se.check_key(kinds.get(name, ""), name)
                rec = tab["estimates"][cheap].get(key, {"not_estimated": "not a sheet number"})
                if "not_estimated" in rec or value is None or required is None:
                    cover = "no estimate"
                else:
                    bound = (rec["value"] * abs(value) if rec["kind"] == "relative" else
                             rec["value"] * r["module_mm"] if rec["kind"] == "per_module" else rec["value"])
                    cover = ("covered: " if abs(value - required) <= bound else "NOT covered: ") + \
                        f"|{value:.3g} − {required:g}| vs the estimate {bound:.3g}"
                out.append(f"{n}: {name}: {cheap} PASS ({_f(value, 3)}), verify FAIL ({_f(f[2], 3)}); {cover}")
    return out


def markdown(tab: dict) -> str:
    from profilegen.pipeline import scene_estimates as se

    lines = [f"# Scene estimates: the measurement ({tab['date']}, commit {tab['commit'][:7]})", "",
             "Written by `python tests/benchmarks/scene_estimates.py` (do not edit). Each cheaper scene's "
             f"estimate is {tab['safety_factor']}x the largest difference to the next scene over the corpus, "
             "in the kind named (per_module: x m; relative: x |cheaper value|; absolute: in the number's unit).", ""]
    errors = [(n, s, r["scenes"][s]["error"]) for n, r in tab["sets"].items() for s in SCENES if r["scenes"][s]["error"]]
    lines += [f"Sets: {len(tab['sets'])}; runs failed: {len(errors)}."]
    lines += [f"- {n} {s}: {e}" for n, s, e in errors]
    for cheap, dear in PAIRS:
        lines += ["", f"## {cheap} against {dear}", "",
                  "| number | unit | kind | sets compared | largest observed | estimate | outside |",
                  "|---|---|---|---|---|---|---|"]
        for key, est in tab["estimates"][cheap].items():
            label, unit = se.NUMBERS[key][0], se.NUMBERS[key][1]
            if "not_estimated" in est:
                lines.append(f"| {label} | {unit} | — | — | — | not estimated: {est['not_estimated']} | — |")
                continue
            per = tab["differences"][f"{cheap}-{dear}"][key]
            outside = sum(1 for v in per.values() if v.get("abs") is not None and v["normalised"] > est["value"])
            lines.append(f"| {label} | {unit} | {est['kind']} | {est['compared']} | {_f(est['observed'], 3)} | "
                         f"{_f(est['value'], 3)} | {outside} |")
    lines += ["", "## Verdicts", "", "| set | sketch | design | verify |", "|---|---|---|---|"]
    for n, r in tab["sets"].items():
        cells = []
        for s in SCENES:
            v = r["scenes"][s].get("verdict")
            cells.append("run failed" if v is None else v["status"] + (f" ({len(v['failures'])} failed)" if v["failures"] else ""))
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    lines += ["", "## Checks that pass in a cheaper scene and fail in verify", ""]
    flips = check_flips(tab)
    lines += [f"- {f}" for f in flips] or ["None."]
    lines += ["", "## Every number", ""]
    for n, r in tab["sets"].items():
        lines += [f"### {n} (m = {r['module_mm']:g} mm)", "", "| number | sketch | design | verify | |s-d| | |d-v| |",
                  "|---|---|---|---|---|---|"]
        nums = {s: r["scenes"][s].get("numbers") or {} for s in SCENES}
        for key, (label, unit, _) in se.NUMBERS.items():
            vals = [nums[s].get(key) for s in SCENES]
            ds = [tab["differences"][f"{a}-{b}"][key].get(n, {}).get("abs") for a, b in PAIRS]
            lines.append(f"| {label} ({unit}) | " + " | ".join(_f(v) if v is not None else "not computed" for v in vals)
                         + " | " + " | ".join(_f(d, 3) for d in ds) + " |")
        lines.append("")
    return "\n".join(lines) + "\n"


DOCS = ROOT / "docs" / "validation" / "scene-estimates.md"
BEGIN, END = "<!-- measurement: written by tests/benchmarks/scene_estimates.py -->", "<!-- end of the measurement -->"


def _est_cell(rec: dict, unit: str) -> tuple[str, str]:
    if "not_estimated" in rec:
        return "—", "not estimated"
    kind = {"per_module": " × m", "relative": " × value", "absolute": f" {unit}".rstrip()}[rec["kind"]]
    return f"{rec['observed']:.3g}{kind}", f"**{rec['value']:.2g}{kind}**"


def _excesses(tab: dict, values: dict) -> list[str]:
    """The measured differences of ``tab`` beyond ``values`` (cheap scene → number key → the
    estimate's value in its kind, None: no estimate), one line each."""
    out = []
    for cheap, dear in PAIRS:
        for key, value in values.get(cheap, {}).items():
            if value is None:
                continue
            for name, v in tab["differences"][f"{cheap}-{dear}"].get(key, {}).items():
                if v.get("abs") is not None and v["normalised"] > value:
                    out.append(f"{cheap} {key} {name}: {v['normalised']:.3g} > {value:.3g}")
    return out


def outside_count(tab: dict) -> int:
    """Differences beyond the estimates derived from this same measurement (0 unless a policy holds
    one back)."""
    return len(_excesses(tab, {c: {k: r.get("value") for k, r in rows.items()} for c, rows in tab["estimates"].items()}))


def outside_package(tab: dict) -> list[str]:
    """The differences of this measurement beyond the package's estimates as they are now
    (profilegen.pipeline.scene_estimates.ESTIMATES, read before ``--write-module`` rewrites it):
    the check :func:`outside_count` cannot make, since it counts against the estimates derived
    from this same measurement (0 by construction)."""
    from profilegen.pipeline import scene_estimates as se

    return _excesses(tab, {c: {k: r.value if isinstance(r, se.Estimate) else None for k, r in rows.items()}
                           for c, rows in se.ESTIMATES.items()})


def docs_block(tab: dict) -> str:
    """The measurement's summary for docs/validation/scene-estimates.md."""
    from profilegen.pipeline import scene_estimates as se

    runs = [(n, s, r["scenes"][s]) for n, r in tab["sets"].items() for s in SCENES]
    failed = [(n, s, e["error"]) for n, s, e in runs if e.get("error")]
    walls = {s: [e["wall_s"] for n, s2, e in runs if s2 == s and e.get("wall_s")] for s in SCENES}
    total = sum(w["wall_s"] for w in tab["wall"])
    loads = [w["load_average_1min_at_end"] for w in tab["wall"] if "load_average_1min_at_end" in w]
    load = (f" (1-min load average at the end: {min(loads):.1f}–{max(loads):.1f})"
            if loads and len(loads) == len(tab["wall"]) else "")
    lines = [BEGIN, "",
             f"Measured at commit `{tab['commit'][:7]}` on {tab['date']}: {len(tab['sets'])} sets × 3 scenes, "
             f"{len(runs) - len(failed)} runs finished, {len(failed)} failed; "
             f"**{outside_count(tab)} numbers outside their estimate**. Wall time of the runs: {total / 60:.0f} min "
             f"on 2 processes of the shared 2-core machine{load}; one run "
             + ", ".join(f"{s} {min(w):.0f}–{max(w):.0f} s" for s, w in walls.items() if w) + ".", "",
             "| number | unit | kind | sketch → design: largest | sketch estimate | design → verify: largest | design estimate |",
             "|---|---|---|---|---|---|---|"]
    for key, (label, unit, _) in se.NUMBERS.items():
        a = _est_cell(tab["estimates"]["sketch"][key], unit)
        b = _est_cell(tab["estimates"]["design"][key], unit)
        lines.append(f"| {label} | {unit or '—'} | {se.NUMBERS[key][2].replace('_', ' ')} | {a[0]} | {a[1]} | {b[0]} | {b[1]} |")
    lines += ["", "The CS tooth-space outline as a whole (the largest normal distance between two scenes' outlines, "
              "fillets included, `tests/benchmarks/scene_agreement.py`'s measure), against the bound its elements' "
              "estimates give: a point of the outline moves by at most its element's move — an arc's centre and "
              "radius estimates added, a line's end estimates, the tip and root circles' radii (half the "
              "diameters' estimates):", ""]
    for a, b in PAIRS:
        per = [(v[f"{a}-{b}"] / tab["sets"][n]["module_mm"], v[f"{a}-{b}"], n) for n, v in tab["outline_mm"].items()
               if f"{a}-{b}" in v]
        worst = max(per)
        est = tab["estimates"][a]
        parts = {"the tip circle": est["cs_tip_diameter_mm"]["value"] / 2,
                 "the root circle": est["cs_root_diameter_mm"]["value"] / 2,
                 "R1": est["r1_centre_mm"]["value"] + est["r1_radius_mm"]["value"],
                 "the line": max(est["line_start_mm"]["value"], est["line_end_mm"]["value"]),
                 "R2": est["r2_centre_mm"]["value"] + est["r2_radius_mm"]["value"],
                 "the root fillet": est["root_fillet_centre_mm"]["value"] + est["root_fillet_radius_mm"]["value"],
                 "the tip round": est["tip_round_centre_mm"]["value"] + est["tip_round_radius_mm"]["value"]}
        which = max(parts, key=parts.get)
        bound = parts[which]
        picks = [n for n in ("seed000_csf40", "csf32_120") if n in tab["outline_mm"]]
        lines.append(f"- {a} → {b}: largest {worst[0]:.4f} × m ({worst[1] * 1e3:.3g} µm, {worst[2]}); the {a} scene's "
                     f"outline bound {bound:.2g} × m (from {which}); "
                     + ", ".join(f"{n} {tab['outline_mm'][n][f'{a}-{b}'] * 1e3:.3g} µm against "
                                 f"{bound * tab['sets'][n]['module_mm'] * 1e3:.3g} µm" for n in picks)
                     + "; every set within it: " + ("yes" if all(x <= bound for x, _, _ in per) else "NO"))
    lines += ["", "Why a number is not estimated:", ""]
    for cheap in ("sketch", "design"):
        reasons = {}
        for key, rec in tab["estimates"][cheap].items():
            if "not_estimated" in rec:
                reasons.setdefault(rec["not_estimated"], []).append(se.NUMBERS[key][0])
        for why, labels in reasons.items():
            lines.append(f"- {cheap}: {', '.join(labels)} — {why}")
    lines += ["", "The verdicts (a cheaper PASS that verify FAILs would be a wrong answer; INCOMPLETE names what "
              "the scene did not check):", "", "| set | sketch | design | verify | verify's failed checks |", "|---|---|---|---|---|"]
    for n, r in tab["sets"].items():
        cells = []
        for s in SCENES:
            v = r["scenes"][s].get("verdict")
            cells.append("run failed" if v is None else v["status"])
        fv = r["scenes"]["verify"].get("verdict") or {"failures": []}
        lines.append(f"| {n} | " + " | ".join(cells) + " | " + "; ".join(f.split(" at ")[0] for f in fv["failures"]) + " |")
    if failed:
        lines += ["", "Runs that failed:", ""] + [f"- {n} {s}: {e}" for n, s, e in failed]
    lines += ["", END]
    return "\n".join(lines)


def write_docs(tab: dict) -> None:
    text = DOCS.read_text(encoding="utf-8")
    i, j = text.index(BEGIN), text.index(END) + len(END)
    DOCS.write_text(text[:i] + docs_block(tab) + text[j:], encoding="utf-8")
    print(f"wrote the measurement into {DOCS.relative_to(ROOT)}")


CHART = ROOT / "docs" / "img" / "scene_estimates.png"
KIND_LABEL = {"per_module": "× m", "relative": "relative", "absolute": ""}


def chart(tab: dict, path: Path = CHART) -> None:
    """Number × scene: each set's difference to the next scene (dots, coloured by size), in the
    estimate's kind, on a log axis, with the cheaper scene's estimate as a bar from the axis
    to its value; a number with no estimate is named so in grey."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from profilegen.pipeline import scene_estimates as se

    keys = list(se.NUMBERS)
    fig, axes = plt.subplots(1, 2, figsize=(14, 12), sharey=True)
    floor = 1e-7
    sizes = sorted({_size(n) for n in tab["sets"]})
    cmap = plt.get_cmap("viridis")
    for ax, (cheap, dear) in zip(axes, PAIRS):
        ests = tab["estimates"][cheap]
        for i, key in enumerate(keys):
            y = len(keys) - 1 - i
            est = ests[key]
            if "not_estimated" in est:
                why = est["not_estimated"].split(":")[0].split(" (")[0].replace(f"the {cheap} scene ", "")
                ax.text(floor * 1.5, y, "not estimated: " + why[:55], va="center", fontsize=7, color="#888")
                continue
            if est["value"] > floor:
                ax.errorbar([est["value"] / 2], [y], xerr=[[est["value"] / 2 - floor], [est["value"] / 2]], fmt="none",
                            ecolor="#d62728", elinewidth=6, alpha=0.25, capsize=0)
                ax.plot([est["value"]], [y], marker="|", color="#d62728", markersize=12, mew=2)
            else:
                ax.text(floor * 1.5, y + 0.25, "exact: equal in every set", fontsize=7, color="#888", va="center")
            per = tab["differences"][f"{cheap}-{dear}"][key]
            names = [n for n, v in per.items() if v.get("abs") is not None]
            xs = np.array([max(per[n]["normalised"], floor) for n in names])
            jitter = np.linspace(-0.3, 0.3, len(names)) if len(names) > 1 else np.zeros(1)
            colours = [cmap(sizes.index(_size(n)) / max(1, len(sizes) - 1)) for n in names]
            ax.scatter(xs, y + jitter, s=9, c=colours, zorder=3, linewidths=0)
        ax.set_xscale("log")
        ax.set_xlim(floor, 5.0)
        ax.set_title(f"|{cheap} − {dear}|, the {cheap} scene's estimate as a red bar", fontsize=10)
        ax.grid(axis="x", which="major", color="#ddd")
        ax.set_xlabel(f"|difference|: × m, relative, or in the unit named ({floor:g}: equal)", fontsize=8)
    axes[0].set_yticks(range(len(keys)))
    axes[0].set_yticklabels([f"{se.NUMBERS[k][0].replace(' torque', '').replace('FS teeth across the face: largest', 'face')} "
                             f"({KIND_LABEL[se.NUMBERS[k][2]] or se.NUMBERS[k][1] or '1'})"
                             for k in reversed(keys)], fontsize=7)
    handles = [plt.Line2D([], [], marker="o", ls="", color=cmap(i / max(1, len(sizes) - 1)), label=f"size {s}")
               for i, s in enumerate(sizes)]
    fig.legend(handles=handles, loc="lower center", ncol=len(sizes), fontsize=8, frameon=False)
    fig.suptitle(f"Scene estimates over {len(tab['sets'])} gear sets (commit {tab['commit'][:7]}, {tab['date']}): "
                 f"each dot one set; estimate = {tab['safety_factor']:g} × the largest", fontsize=11)
    fig.tight_layout(rect=(0, 0.03, 1, 0.97))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"wrote {path.relative_to(ROOT)}")


def _size(name: str) -> int:
    """A corpus set's catalogue size: the generated ones by name, the bundled ones by pitch diameter."""
    import re

    m = re.match(r"(?:csf|shf|csg)(\d+)_", name)
    if m:
        return int(m.group(1))
    return {"default": 40, "seed000_csf40": 40, "seed001_shf25": 25, "seed002_short_cup": 25, "csf32_100": 32}.get(name, 0)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", nargs="?", choices=("run", "table", "all"), default="all")
    ap.add_argument("--work", type=Path, default=ROOT / "build" / "scene_estimates")
    ap.add_argument("--force", action="store_true")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--sets", nargs="*")
    ap.add_argument("--write-module", action="store_true", help="write the estimates into profilegen/pipeline/scene_estimates.py")
    ap.add_argument("--commit", default="HEAD", help="the commit whose package runs (git archive; default HEAD)")
    args = ap.parse_args(argv)
    latest = args.work / "latest.txt"
    if args.what == "table" and args.commit == "HEAD" and latest.exists():  # the runs' commit, not today's HEAD
        args.commit = latest.read_text().strip()
    sha, where = snapshot(args.commit)
    _SNAPSHOT.append(str(where))  # the workers import it; this process (the table) the working tree's
    if args.what != "table":
        args.work.mkdir(parents=True, exist_ok=True)  # a new --work folder
        latest.write_text(sha + "\n", encoding="utf-8")
    args.work = args.work / sha[:7]
    args.work.mkdir(parents=True, exist_ok=True)
    (args.work / "commit.txt").write_text(sha + "\n", encoding="utf-8")
    if args.what in ("run", "all"):
        run(args.work, force=args.force, workers=args.workers, only=args.sets)
    if args.what in ("table", "all"):
        tab = table(args.work)
        beyond = outside_package(tab)  # before --write-module rewrites the estimates
        print(f"{len(beyond)} differences beyond the package's current estimates (profilegen/pipeline/"
              "scene_estimates.py as it was)" + "".join(f"\n  {b}" for b in beyond))
        if args.write_module:
            write_module(tab)
        chart(tab)
        if DOCS.exists():
            write_docs(tab)
        print(f"{outside_count(tab)} numbers outside the estimates derived from this measurement "
              f"({tab['safety_factor']}x the largest observed: 0 unless a policy holds one back)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
