"""`profilegen ...` — the command line. No logic of its own: it parses, calls, reports.

Exit codes: 0 success, 2 bad input (gear set, file, option) or a failed stage,
with one line on stderr naming the field (nothing is written on failure); 3 from
``design --strict`` when the design's verdict is FAIL, 4 when it is INCOMPLETE (a check
NOT CHECKED, nothing failed; the files are written either way).
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
from pathlib import Path

from .errors import ProfilegenError

__all__ = ["main"]


def _load(name_or_path: str | None):
    from .gearset import default_gearset_path, load_gearset, resolve_gearset

    path = default_gearset_path() if name_or_path is None else resolve_gearset(name_or_path)
    return load_gearset(path)


def _cmd_design(args) -> int:
    from .output import folder
    from .output.files import OUTPUT_FILES, figure_workers, profile_figures, stage_figures, write_design
    from .pipeline.engine import default_engine
    from .pipeline.design import check_gearset, planned_stages
    from .pipeline.scenes import SCENES

    if args.scene == "list":
        from .pipeline.scenes import bundled_scenes_path

        for s in SCENES.values():
            print(f"{s.name:8s} rim: {s.rim:22s} envelope chord {s.chord_tol_mm:g} mm — {s.description}")
        path = bundled_scenes_path()
        print(f"scenes file: {path}")
        print(f"to change a preset: cp {path} my_scenes.toml, edit it, then "
              "profilegen design --scene my_scenes.toml (one table: that scene; several: the gear set's, "
              "or my_scenes.toml#NAME)")
        return 0
    gearset = _with_requirements(_load(args.gearset), args.require)
    check_gearset(gearset)  # what check rejects fails here, before the first progress line
    out = Path(args.out) if args.out else Path("export") / gearset.name
    _check_out(out)
    folder.check(out, ours=OUTPUT_FILES)  # a folder holding the user's files: refused now, not after the stages
    if args.step:  # the B-rep kernel is an optional extra: say so now, not after the stages
        from .output import step as step_files

        step_files.require()
    scene = args.scene
    if args.rim is not None:  # the scene's rim tier overridden: --rim cup3d
        from .pipeline.scenes import resolve_scene, with_rim_tier

        scene = with_rim_tier(resolve_scene(gearset.scene if scene is None else scene, default=gearset.scene), args.rim)
    stages = planned_stages(gearset, scene=scene, contact=args.contact) + ("files",)
    bar = _progress(len(stages), quiet=args.quiet, what=f"design {gearset.name}")
    # the PNG figures: the scene's choice (the sketch scene draws none), or --figures
    draw = True if args.figures else None
    if draw is None:
        from .pipeline.scenes import resolve_scene

        draw = resolve_scene(gearset.scene if scene is None else scene, default=gearset.scene).figures != "none"
    # the figure workers start now: they import matplotlib and draw the profile's figures while the stages run
    with figure_workers(draw=draw) as figures:
        # through the process's engine, as sweeps and the optimiser: the same stages, the same numbers
        result = default_engine().design(
            gearset, scene=scene, fit_method=args.fit, progress=lambda name: bar(name), contact=args.contact,
            on_profile=lambda partial: profile_figures(figures, partial, draw=draw),
            on_stage=lambda partial: stage_figures(figures, partial, draw=draw))
        bar("files")
        written = write_design(result, out, figures=figures, step=args.step, draw=draw)
    bar(None)
    if not args.quiet:
        _summary(result, written)
    verdict = result.verdict
    if not args.quiet or not verdict.passed:
        print(verdict.line, file=sys.stdout if verdict.passed else sys.stderr)
    return STRICT_EXIT.get(verdict.status, 0) if args.strict else 0


#: ``design --strict``'s exit code per verdict (PASS: 0)
STRICT_EXIT = {"FAIL": 3, "INCOMPLETE": 4}


def _with_requirements(gearset, pairs):
    """The gear set with ``--require KEY=VALUE`` applied to its ``[requirements]`` (VALUE a
    number or "none"; ``yield_safety`` / ``fatigue_safety`` set every key of the group). A bad
    key or value is the reader's GearSetError, naming ``requirements.KEY``."""
    if not pairs:
        return gearset
    from .errors import GearSetError
    from .gearset.requirements import NOT_REQUIRED, REQUIREMENT_GROUPS

    changes = {}
    for pair in pairs:
        key, eq, value = pair.partition("=")
        key, value = key.strip(), value.strip()
        if not eq or not key:
            raise GearSetError(f"--require {pair!r}: must be KEY=VALUE (e.g. fatigue_safety=2 or max_backlash_mm=none)")
        try:
            value = value if value == NOT_REQUIRED else float(value)
        except ValueError:
            raise GearSetError(f"--require {key}={value}: requirements.{key} must be a number or {NOT_REQUIRED!r}") \
                from None
        for k in REQUIREMENT_GROUPS.get(key, (key,)):
            changes[f"requirements.{k}"] = value
    return gearset.with_values(changes)


def _check_out(out: Path) -> None:
    """An output path too long for the file system: one line naming --out, before any stage runs."""
    from .output.userpaths import check_out_path

    check_out_path(out)


def _summary(result, written) -> None:
    from .output.sheet import format_clearance  # '2.22e-10 nm' was printed for a touching outline

    env = result.envelope
    c = env.counts()
    print(f"gear set {result.gearset.name!r}, scene {result.scene.name!r}")
    for s in result.stages:
        err = "" if s.error_estimate is None else f"  error {s.error_estimate:.3g}"
        print(f"  {s.stage:12s} {s.tier:28s} {s.time_s * 1e3:8.1f} ms{err}")
    print(
        f"  envelope: {c['conjugate']['pieces']} conjugate, {c['interfering']['pieces']} interfering, "
        f"{c['tip_path']['pieces']} tip-path pieces; {len(env.ridges)} ridges, {len(env.folds)} folds; "
        f"deepest false flank {env.max_interference_mm * 1e3:.1f} µm"
    )
    f = result.form
    print(f"  CS: tip circle r = {f.tip_radius_mm:.4f} mm, root circle r = {f.root_radius_mm:.4f} mm, "
          f"min clearance {format_clearance(f.clearance.min_mm)} (chord tolerance {result.scene.chord_tol_mm * 1e6:g} nm)")
    if result.profile is not None:
        p = result.profile
        fits = ", ".join(f"{m} {fit.max_error_mm * 1e3:.3f}" for m, fit in p.fits.items())
        branches = "" if p.branches is None else f" per branch ({len(p.branches.fits)} branches, max {p.max_error_mm * 1e3:.3f} µm)"
        print(f"  arc–line–arc fit, max deviation (µm): {fits}; CAD uses {p.method}{branches}"
              + (f", max backlash {p.max_backlash_mm * 1e3:.3f} µm" if p.max_backlash_mm is not None else ""))
        print(f"  fitted CS vs FS tooth at {p.positions} positions: min clearance {format_clearance(p.clearance.min_mm)}")
    if result.contact is not None:
        for case in result.contact.cases:
            print(f"  contact at {case.torque_nm:g} N·m: {case.teeth_in_contact} teeth per zone "
                  f"({result.contact.zones} zones), rotation {case.rotation_arcmin:.3f} arcmin, "
                  f"max tooth force {case.max_tooth_force_n:.0f} N"
                  + ("" if case.beyond_capacity is None else f" — BEYOND CAPACITY: {case.beyond_capacity}"))
    if result.stress is not None:
        res = result.stress
        ring = ", ".join(f"{r.total_stress_mpa:.0f}" for r in res.tooth_ring)
        print(f"  stress at {', '.join(f'{t:g}' for t in res.torques_nm)} N·m: tooth root {ring} MPa, cup bottom "
              f"von Mises {', '.join(f'{b.max_von_mises_mpa:.0f}' for b in res.cup_bottom)} MPa")
        for c in res.checks:
            verdict = "skipped" if c.value is None else f"{c.value:.2f} ({'pass' if c.passed else 'FAIL'})"
            print(f"    safety, {c.name} at {c.torque_nm:g} N·m: {verdict}")
    for w in result.warnings:
        print(f"  note: {w}")
    for p in written:
        print(f"  wrote {p}")


def _progress(total: int, *, quiet: bool, what: str = "design"):
    """Stage progress on stderr: one line per stage as it starts (elapsed time, stage k of
    total), also when stderr is a pipe or a file, and a tqdm bar under them on a terminal.
    Silent when quiet. Call with None at the end (closes the bar)."""
    if quiet:
        return lambda name: None
    import time

    t0 = time.perf_counter()
    bar = None
    if sys.stderr.isatty():
        from tqdm import tqdm

        bar = tqdm(total=total, desc=what, unit="stage", leave=False, file=sys.stderr)
    state = {"k": 0}

    def step(name):
        if bar is not None and state["k"]:
            bar.update(1)
        if name is None:
            if bar is not None:
                bar.close()
            return
        state["k"] += 1
        line = f"profilegen: {what} [{state['k']}/{total}] {name} ({time.perf_counter() - t0:.1f} s)"
        if bar is not None:
            bar.set_postfix_str(name)
            bar.write(line, file=sys.stderr)
        else:
            print(line, file=sys.stderr, flush=True)

    return step


def _cmd_sweep(args) -> int:
    import signal

    from .studies.sweep import dask_executor, interrupt_on_signals, load_sweep_spec, run_sweep

    spec = out = None
    bar = lambda done, total: None  # noqa: E731
    try:
        with interrupt_on_signals((signal.SIGTERM,)):  # SIGTERM stops the sweep as cleanly as Ctrl-C
            spec = load_sweep_spec(args.spec)
            table = None
            if args.out is None:
                out = Path("export") / "sweeps" / spec.name
            elif args.out.endswith(".parquet"):  # the table as Parquet there; the folder beside it, same name
                table, out = Path(args.out), Path(args.out).with_suffix("")
            else:
                out = Path(args.out)
            _check_out(out)
            bar = _sweep_progress(len(spec.points), quiet=args.quiet)
            if args.dask:
                with dask_executor(args.dask) as executor:
                    result = run_sweep(spec, out, executor=executor, progress=bar, table=table)
            else:
                result = run_sweep(spec, out, workers=args.workers, progress=bar, table=table)
    except KeyboardInterrupt as exc:  # SIGINT, or SIGTERM as a SignalInterrupt: the workers are already ended
        bar(None, None)
        signum = getattr(exc, "signum", signal.SIGINT)
        what = "sweep" if spec is None else f"sweep {spec.name!r}"
        resume = "" if out is None else (f"; the finished points are in {out / 'journal.csv'} — "
                                         "run the same command again to resume")
        print(f"profilegen: {what} stopped by {signal.Signals(signum).name}{resume}", file=sys.stderr)
        return 128 + signum
    bar(None, None)
    if not args.quiet:
        where = f"Dask at {args.dask}" if args.dask else f"{args.workers or os.cpu_count()} local worker(s)"
        print(f"sweep {spec.name!r}: {len(result.rows)} points ({spec.kind}, scene {spec.scene.name}) on {where}: "
              f"{result.ok} ok, {result.failed} failed; {result.computed} run, {result.reused} from the journal; "
              f"{result.time_s:.1f} s")
        for p in result.files:
            print(f"  wrote {p}")
    return 0


def _cmd_optimize(args) -> int:
    import signal

    from .studies.optimize import load_optimize_spec, optimize
    from .studies.sweep import dask_executor, interrupt_on_signals

    spec = out = None
    bar = lambda done, total: None  # noqa: E731
    try:
        with interrupt_on_signals((signal.SIGTERM,)):  # SIGTERM stops the run as cleanly as Ctrl-C
            spec = load_optimize_spec(args.spec)  # validated in full before anything is written
            out = Path(args.out) if args.out else Path("export") / "optimize" / spec.name
            _check_out(out)
            bar = _sweep_progress(spec.population * spec.generations, quiet=args.quiet, desc="optimize", unit="design")
            if args.dask:
                with dask_executor(args.dask) as executor:
                    result = optimize(spec, out, executor=executor, progress=bar)
            else:
                result = optimize(spec, out, workers=args.workers, progress=bar)
    except KeyboardInterrupt as exc:
        bar(None, None)
        signum = getattr(exc, "signum", signal.SIGINT)
        resume = "" if out is None else f"; finished designs are in {out / 'journal.csv'} — run the same command again to resume"
        print(f"profilegen: optimize stopped by {signal.Signals(signum).name}{resume}", file=sys.stderr)
        return 128 + signum
    bar(None, None)
    if not args.quiet:
        s = result.summary
        print(f"optimize {spec.name!r}: {s['candidates']} designs in scene {s['scene']} ({s['computed']} run, {s['reused']} from "
              f"the journal, {s['failed']} failed, {s['feasible']} feasible); front of {s['front']}, "
              f"{s['dominating_start']} dominate the starting design; {result.time_s:.1f} s")
        if s.get("confirm_scene"):
            print(f"  confirmed in scene {s['confirm_scene']}: {s['confirm_infeasible']} infeasible, {s['confirm_dominated']} "
                  f"dominated; objective order flipped in {s['rank_flips']} of {s['rank_pairs']} pairs")
        for p in result.files:
            print(f"  wrote {p}")
    return 0


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {value}")
    return value


def _sweep_progress(total: int, *, quiet: bool, desc: str = "sweep", unit: str = "point"):
    """A tqdm bar over the points on stderr (silent when quiet or not a terminal); call (None, None) to close."""
    if quiet or not sys.stderr.isatty():
        return lambda done, total: None
    from tqdm import tqdm

    bar = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr)

    def step(done, _total):
        if done is None:
            bar.close()
        else:
            if _total is not None and _total != bar.total:  # optimize: the confirm step adds the front's designs
                bar.total = _total
                bar.refresh()
            bar.update(done - bar.n)

    return step


def _cmd_check(args) -> int:
    """Everything ``design`` checks of the gear set itself before a stage runs: the file, every field
    and the wave generator (``load_gearset``: rollers that do not fit, ...), and the tooth
    (:func:`profilegen.geometry.teeth.tooth_from_gearset`, design's first stage, and the envelope stage's
    :func:`profilegen.profile.envelope.tooth_curves`). One line per problem on
    stderr, each naming the file once; notes (``GearSet.warnings``) on stdout."""
    from .errors import GearSetError
    from .gearset import load_gearset, resolve_gearset
    from .pipeline.design import check_gearset

    status = 0
    for name in args.gearsets:
        where = name
        try:
            path = resolve_gearset(name)
            where = str(path)
            gs = load_gearset(path)
            check_gearset(gs)
        except ProfilegenError as exc:
            status = 2
            lines = exc.problems if isinstance(exc, GearSetError) else [str(exc)]
            for line in lines:
                line = " ".join(str(line).split())  # one line each, whatever the message
                for prefix in (f"{where}: ", f"{name}: "):  # name the file once
                    if line.startswith(prefix):
                        line = line[len(prefix):]
                        break
                print(f"{where}: {line}", file=sys.stderr)
        else:
            from .gearset.new import format_derived

            print(f"{where}: ok ({gs.name}: m {gs.gear.module_mm:g} mm, z {gs.gear.flexspline_teeth}/{gs.gear.circular_spline_teeth})")
            print(f"{where}: derived: {format_derived(gs)}")
            for note in gs.warnings:
                print(f"{where}: note: {note}")
            missing = gs.material.missing_strength_limits
            if missing:
                print(f"{where}: note: no {', '.join('material.' + m for m in missing)}: `profilegen design` will "
                      "leave the strength checks that need them NOT CHECKED and its verdict INCOMPLETE (give them in "
                      "[material], MPa)")
    return status


def _cmd_new(args) -> int:
    """A gear set of catalogue proportions (profilegen.gearset.new.new_gearset): to --out, or stdout."""
    from typing import cast

    from .gearset.new import format_derived, new_gearset
    from .gearset import GearSet

    made = new_gearset(args.size, args.ratio, series=args.series, torque_rated_nm=args.torque_rated,
                       torque_peak_nm=args.torque_peak, torque_momentary_nm=args.torque_momentary)
    for note in made.notes:
        print(f"note: {note}", file=sys.stderr)
    if args.out is None:
        sys.stdout.write(made.text)
        return 0
    out = Path(args.out)
    if out.exists() and not args.force:
        raise ProfilegenError(f"--out {out}: exists (give --force to overwrite it)")
    made.write(out)
    gearset = cast(GearSet, made.gearset)  # CatalogueSet.gearset is typed object; new_gearset sets parse_gearset's GearSet
    print(f"wrote {out}: {gearset.description}")
    print(f"{out}: derived: {format_derived(gearset)}")
    return 0


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None


def _cmd_profiles(args) -> int:
    from .gearset import list_profiles, load_gearset

    for path in list_profiles():
        gs = load_gearset(path)
        print(f"{path.stem:22s} {gs.description}")
    return 0


def _cmd_app(args) -> int:
    """The local web workbench (profilegen.app): serves until Ctrl-C."""
    from .app import serve

    return serve(_load(args.gearset), workspace=args.workspace, scene=args.scene, host=args.host, port=args.port)


def _cmd_bench(args) -> int:
    import time

    from .bench import load_benchmark

    # the benchmarks live in the source checkout's tests/benchmarks/ (elsewhere: one line, exit 2)
    bench_scenes = load_benchmark("scenes")
    bench_stages = None if args.no_stages else load_benchmark("stages")
    gearset = _load(args.gearset)
    scenes = ("sketch", "design") if args.quick else ("sketch", "design", "verify")
    say = (lambda text: None) if args.quiet else (lambda text: print(f"  {text}", file=sys.stderr))
    t0 = time.perf_counter()
    rows = bench_scenes.scene_benchmark(gearset, scenes=scenes, repeats=1 if args.quick else args.repeats,
                                        progress=say)
    out = Path(args.out) if args.out else Path("export") / "bench"
    _check_out(out)
    written = bench_scenes.write_scene_benchmark(rows, out, title=f"{gearset.name}: the whole pipeline per scene")
    scene_s = time.perf_counter() - t0
    if not args.quiet:
        print(bench_scenes.format_rows(rows))
        for p in written:
            print(f"  wrote {p}")
    if bench_stages is None:
        return 0
    t0 = time.perf_counter()
    stage_rows = bench_stages.stage_benchmark(gearset, quick=args.quick, repeats=args.repeats, progress=say)
    written = bench_stages.write_stage_benchmark(stage_rows, out, title=f"{gearset.name}: speed against accuracy "
                                                 f"per stage (median times; errors against converged references)")
    if not args.quiet:
        print()
        print(bench_stages.format_stage_rows(stage_rows))
        for p in written:
            print(f"  wrote {p}")
        print(f"scene benchmark {scene_s:.0f} s, stage benchmark {time.perf_counter() - t0:.0f} s")
    return 0


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="profilegen", description="Conjugate tooth profiles for strain wave gears.")
    p.add_argument("-v", "--verbose", action="store_true", help="log what each stage does")
    from . import __version__

    p.add_argument("--version", action="version", version=f"profilegen {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    d = sub.add_parser("design", help="run the pipeline on a gear set and write export/<name>/")
    d.add_argument("gearset", nargs="?", help="a gear-set TOML file or a bundled name (default: the bundled default set)")
    d.add_argument("--scene", nargs="?", const="list", metavar="sketch|design|verify|list|FILE.toml[#NAME]",
                   help="fidelity preset (default: the gear set's), or a scene file (a copy of the bundled "
                        "scenes.toml; FILE.toml#NAME picks one of its scenes); 'list' shows the presets and where "
                        "their file is (so does --scene alone)")
    d.add_argument("--rim", metavar="sketch|design|verify|toothed|cup3d",  # checked by scenes.with_rim_tier
                   help="the rim stage's tier instead of the scene's: cup3d = the 3D cup (coning across the face), "
                        "toothed (= verify) = the 2D toothed rim, design = the 2D flat ring, sketch = ring theory")
    d.add_argument("--out", help="output folder (default: export/<gear-set name>/)")
    d.add_argument("--contact", action=argparse.BooleanOptionalAction, default=None,
                   help="loaded tooth contact at the set's rated/peak/momentary torques (default: on in the design "
                        "and verify scenes, off in sketch)")
    d.add_argument("--fit", choices=["one_sided", "least_squares", "minimax"],
                   help="arc–line–arc fit of the CS flank for CAD (default: the gear set's circular_spline.fit_method)")
    d.add_argument("--strict", action="store_true",
                   help="exit 3 when the verdict is FAIL (a safety factor below its requirement, a load case beyond "
                        "the contact's capacity, a fitted CS that interferes, ...) and 4 when it is INCOMPLETE "
                        "(nothing failed, but a check was NOT CHECKED: no material limits, no contact, no ratcheting "
                        "in the scene); the files are written either way")
    d.add_argument("--require", action="append", metavar="KEY=VALUE",
                   help="override one of the gear set's [requirements] for this run (repeatable): e.g. "
                        "fatigue_safety=2 (every fatigue key; yield_safety likewise), max_backlash_mm=0.01, "
                        "ratcheting_margin=none (not required); keys in docs/gearset.md")
    d.add_argument("-q", "--quiet", action="store_true", help="print nothing on success (a FAIL or INCOMPLETE verdict "
                   "still prints its one line on stderr)")
    d.add_argument("--step", action="store_true", help="also write circular_spline.step and flexspline.step "
                   "(B-rep solids, mm; adds some seconds)")
    d.add_argument("--figures", action="store_true", help="draw the PNG figures (envelope.png, stress.png, the "
                   "reports' pictures) even where the scene draws none (the sketch scene: figures = \"none\")")
    d.set_defaults(func=_cmd_design)
    c = sub.add_parser("check", help="validate gear-set files and print every problem")
    c.add_argument("gearsets", nargs="+", help="gear-set TOML files or bundled names")
    c.set_defaults(func=_cmd_check)
    n = sub.add_parser("new", help="write a gear set of catalogue proportions for a size and ratio "
                                   "(every estimated proportion named in a comment with its rule)")
    n.add_argument("--size", type=int, required=True, help="catalogue size: 14, 17, 20, 25, 32, 40, 50 or 58")
    n.add_argument("--ratio", type=int, required=True, help="reduction ratio, a whole number 30-320 (z1 = 2·ratio)")
    n.add_argument("--series", default="csf", help="csf (default), csg (high torque, ×1.3) or shf (hat type, written as a cup)")
    n.add_argument("--torque-rated", type=_number, metavar="N·m", help="rated torque (default: the size's, T ∝ d²·b)")
    n.add_argument("--torque-peak", type=_number, metavar="N·m", help="peak torque (default: rated × 167/67)")
    n.add_argument("--torque-momentary", type=_number, metavar="N·m", help="momentary torque (default: rated × 304/67)")
    n.add_argument("--out", metavar="FILE", help="the TOML file to write (default: print it)")
    n.add_argument("--force", action="store_true", help="overwrite --out if it exists")
    n.set_defaults(func=_cmd_new)
    ls = sub.add_parser("profiles", help="list the bundled gear sets")
    ls.set_defaults(func=_cmd_profiles)
    sw = sub.add_parser("sweep", help="a parameter study: many designs over a grid or a sample (docs/sweep.md)")
    sw.add_argument("spec", help="a sweep spec TOML file (e.g. profiles/sweeps/deflection.toml)")
    sw.add_argument("--workers", type=_positive_int, metavar="N", help="local worker processes (default: the CPU count)")
    sw.add_argument("--dask", metavar="ADDRESS", help="run on the Dask cluster at ADDRESS (tcp://HOST:PORT) instead")
    sw.add_argument("--out", metavar="DIR", help="output folder (default: export/sweeps/<name>/); a path ending in .parquet also "
                                  "writes the table there as Parquet (needs pyarrow), the folder beside it")
    sw.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    sw.set_defaults(func=_cmd_sweep)
    op = sub.add_parser("optimize", help="multi-objective design optimisation of gear-set fields (NSGA-II; "
                                         "e.g. profiles/optimize/default.toml)")
    op.add_argument("spec", help="an optimisation spec TOML file (e.g. profiles/optimize/default.toml)")
    op.add_argument("--workers", type=_positive_int, metavar="N", help="local worker processes (default: the CPU count)")
    op.add_argument("--dask", metavar="ADDRESS", help="run on the Dask cluster at ADDRESS (tcp://HOST:PORT) instead")
    op.add_argument("--out", metavar="DIR", help="output folder (default: export/optimize/<name>/)")
    op.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    op.set_defaults(func=_cmd_optimize)
    a = sub.add_parser("app", help="a local web workbench: change a field, see the profile, its fit and its verdict "
                                   "(docs/guides/app.md)")
    a.add_argument("gearset", nargs="?", help="a gear-set TOML file or a bundled name (default: the bundled default set)")
    a.add_argument("--workspace", default=".", metavar="DIR", help="the only folder the app loads, saves and exports "
                   "in (default: the current folder)")
    a.add_argument("--scene", choices=["sketch", "design", "verify"], help="the scene to start in (default: the gear set's)")
    a.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1: this machine only)")
    a.add_argument("--port", type=int, default=8050, help="port (default 8050; 0: any free port)")
    a.set_defaults(func=_cmd_app)
    b = sub.add_parser("bench", help="speed against accuracy: the whole pipeline per scene, then every stage and tier "
                                     "against a converged reference (from a source checkout: the benchmarks are its "
                                     "tests/benchmarks/)")
    b.add_argument("gearset", nargs="?", help="a gear-set TOML file or a bundled name (default: the bundled default set)")
    b.add_argument("--quick", action="store_true", help="scenes: sketch and design only, one run each (the reference "
                   "is the design scene refined); stages: coarser references, no toothed-rim FEM (≈ 1 min instead of "
                   "≈ 5). Default: all three scenes, the reference the verify scene refined")
    b.add_argument("--repeats", type=_positive_int, default=3, metavar="N",
                   help="runs per scene and per stage setting, median time (default 3; a stage setting whose first "
                        "run is long runs once)")
    b.add_argument("--no-stages", action="store_true",
                   help="the scene benchmark only (pipeline.csv/.png), not the per-stage study (stages.csv/.png)")
    b.add_argument("--out", metavar="DIR", help="output folder (default: export/bench/)")
    b.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    b.set_defaults(func=_cmd_bench)
    return p


def _library_warnings(quiet: bool) -> None:
    """Python warnings (numpy's, scipy's RuntimeWarning) as one log line each, ``WARNING py.warnings:
    RuntimeWarning: ... (file.py:123)``, not the message and source line printed to stderr; none with -q."""
    import warnings

    if quiet:
        warnings.simplefilter("ignore")
        return

    def show(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split())[:300]
        logging.getLogger("py.warnings").warning("%s: %s (%s:%s)", category.__name__, text,
                                                 os.path.basename(str(filename)), lineno)

    warnings.showwarning = show


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    quiet = getattr(args, "quiet", False) and not args.verbose
    logging.basicConfig(level=logging.INFO if args.verbose else logging.ERROR if quiet else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    _library_warnings(quiet)  # forked sweep/optimize workers inherit both
    try:
        return args.func(args)
    except ProfilegenError as exc:
        print(f"profilegen: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # Ctrl-C: one line, no traceback; an output folder holds its old or new set
        print(f"\nprofilegen: {args.command} interrupted", file=sys.stderr)
        # CPython 3.11 marks a KeyboardInterrupt raised inside exec() of a string as unhandled even
        # when it is caught (dataclasses define their methods so, at import: a Ctrl-C during the
        # first second often lands there), and then ends the process by SIGINT after this returns;
        # the next exec() of a string clears that mark, so the exit status is 130 either way
        exec("None")  # noqa: S102 — a constant, see above
        return 130
    except BrokenPipeError:  # output piped into e.g. `head`: not an error of ours
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
