"""Results identical through the engine's cache (issue 31): random edit sequences designed by one
:class:`profilegen.Engine`, every design compared with a fresh, uncached :func:`profilegen.design`
of the same inputs, every number and text of design.json.

    python tests/benchmarks/engine_identity.py [--sequences 200] [--length 4] [--seed 1]

A sequence starts from a bundled set (``profiles/*.toml``) and makes ``--length`` edits; each
edit changes 1-3 things at random: a float field of the gear set by ±5 % (every section, the
torques and requirements included), the scene (the sketch scene or a copy with one key changed:
``clearance_samples``, ``fit_check_positions``, ``chord_tol_mm``, ``n_phi``, ``fit_starts``), or the
fit method.
After each edit the engine designs; so does :func:`profilegen.design`, afresh (``--contact``:
both with the loaded contact, the torsional curve and its ladder). Both must give
the same design.json (``Design.to_dict()``, which the output layer writes; the stage times and
the seconds in stage notes left out, they differ between any two runs) or the same error (type
and message). The engine's cache persists across all sequences, so later sequences also reuse
stages of earlier ones. Prints the count, the stage executions and hits, and each difference;
exits 1 on any.

``tests/unit/test_engine.py`` runs a small version (20 sequences over a few states).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import random
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

def comparable(design) -> object:
    """design.json's content (``Design.to_dict()`` through JSON) without what differs between two
    runs of the same inputs: the keys naming a time and the durations in texts (the end-to-end
    benchmark's rule, tests/benchmarks/kill_design.strip_times), and the keys in seconds (``_s``:
    the face stage's ``envelope_s`` and ``map_s``)."""
    from tests.benchmarks.kill_design import strip_times

    def no_seconds(x):
        if isinstance(x, dict):
            return {k: no_seconds(v) for k, v in x.items() if not str(k).endswith("_s")}
        if isinstance(x, list):
            return [no_seconds(v) for v in x]
        return x

    return no_seconds(strip_times(json.loads(json.dumps(design.to_dict(), default=str))))


def first_difference(a, b, path="") -> str | None:
    """The first path where ``a`` and ``b`` differ (numbers exactly; NaN equals NaN), or None."""
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            return f"{path}: keys {sorted(set(a) ^ set(b))}"
        for k in a:
            d = first_difference(a[k], b[k], f"{path}.{k}")
            if d:
                return d
        return None
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return f"{path}: length {len(a)} != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, f"{path}[{i}]")
            if d:
                return d
        return None
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return None
    if type(a) is not type(b) or a != b:
        return f"{path}: {a!r} != {b!r}"
    return None


def outcome(designer, gearset, scene, fit_method, contact: bool = False):
    """('ok', comparable design.json) or ('error', 'Type: message')."""
    from profilegen.errors import ProfilegenError

    try:
        extra = {"contact": True} if contact else {}
        return "ok", comparable(designer(gearset, scene=scene, fit_method=fit_method, **extra))
    except ProfilegenError as exc:
        return "error", f"{type(exc).__name__}: {exc}"


def float_fields(gs) -> dict[str, float]:
    out = {}
    for section, table in gs.to_dict().items():
        if isinstance(table, dict) and table.get("kind") != "points":
            out.update({f"{section}.{k}": v for k, v in table.items() if isinstance(v, float)})
    return out


def scenes():
    """The sketch scene and copies of it with one key changed (each a tier another stage reads)."""
    import profilegen as pg

    s = pg.SCENES["sketch"]
    return [s, dataclasses.replace(s, name="sketch_c", tier="sketch", clearance_samples=121),
            dataclasses.replace(s, name="sketch_f", tier="sketch", fit_check_positions=241),
            dataclasses.replace(s, name="sketch_t", tier="sketch", chord_tol_mm=8e-5),
            dataclasses.replace(s, name="sketch_p", tier="sketch", n_phi=201),
            dataclasses.replace(s, name="sketch_s", tier="sketch", fit_starts=3)]


def draw_states(rng: random.Random, sets: dict, length: int):
    """One sequence: (set name, [(changes, scene index, fit method)] × (length + 1)), each
    state the previous one with 1-3 edits."""
    name = rng.choice(sorted(sets))
    fields = float_fields(sets[name])
    changes, scene, method = {}, 0, None
    states = [(dict(changes), scene, method)]
    for _ in range(length):
        for _ in range(rng.randint(1, 3)):
            r = rng.random()
            if r < 0.8:
                path = rng.choice(sorted(fields))
                changes[path] = fields[path] * (1.0 + rng.uniform(-0.05, 0.05))
            elif r < 0.93:
                scene = rng.randrange(5)
            else:
                method = rng.choice((None, "minimax", "least_squares"))
        states.append((dict(changes), scene, method))
    return name, states


def run(sequences: int, length: int, seed: int, *, pool: int | None = None, engine=None, log=print,
        contact: bool = False) -> dict:
    """Design ``sequences`` random edit sequences through ``engine`` (a new Engine by default) and
    afresh; with ``pool``, the states are drawn from ``pool`` sequences' states only (the fresh
    designs of a state repeat). The fresh design of inputs seen before is not made again (a
    sequence starts from the unmodified set). {'designs', 'errors', 'differences', 'runs', 'hits'}."""
    import profilegen as pg
    from profilegen.errors import GearSetError

    engine = engine or pg.Engine()
    sets = {p.stem: pg.load_gearset(p) for p in sorted((ROOT / "profiles").glob("*.toml"))}
    rng = random.Random(seed)
    all_scenes = scenes()
    if pool is None:
        plans = [draw_states(rng, sets, length) for _ in range(sequences)]
    else:
        states = [(name, s) for name, seq in (draw_states(rng, sets, length) for _ in range(pool)) for s in seq]
        plans = [(None, [rng.choice(states) for _ in range(length + 1)]) for _ in range(sequences)]
    fresh: dict[str, tuple] = {}
    out = {"designs": 0, "errors": 0, "differences": []}
    for i, (name, plan) in enumerate(plans):
        for state in plan:
            set_name, (changes, scene_index, method) = (name, state) if name is not None else state
            try:
                gs = sets[set_name].with_values(changes)
            except GearSetError:
                continue  # refused before any stage: nothing to compare
            scene = all_scenes[scene_index]
            key = json.dumps([set_name, changes, scene_index, method], sort_keys=True)
            if key not in fresh:  # the same inputs again (a sequence's start): design() gives the same design
                fresh[key] = outcome(pg.design, gs, scene, method, contact)
            got = outcome(engine.design, gs, scene, method, contact)
            out["designs"] += 1
            out["errors"] += got[0] == "error"
            diff = first_difference(list(got), list(fresh[key]))
            if diff:
                out["differences"].append({"sequence": i, "set": set_name, "changes": changes, "scene": scene.name,
                                           "fit_method": method, "difference": diff[:400]})
                log(f"DIFFERENCE sequence {i}, {set_name} {changes} {scene.name} {method}: {diff[:400]}")
    out["runs"], out["hits"] = dict(engine.runs), dict(engine.hits)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sequences", type=int, default=200)
    ap.add_argument("--length", type=int, default=4)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--contact", action="store_true",
                    help="every design with the loaded contact (its torsional curve's ladder kept across designs)")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    out = run(args.sequences, args.length, args.seed, contact=args.contact)
    print(f"{args.sequences} sequences of {args.length} edits, seed {args.seed}: {out['designs']} designs compared "
          f"({out['errors']} named errors, each compared too), {len(out['differences'])} differences, "
          f"{time.perf_counter() - t0:.0f} s")
    print(f"stage executions {out['runs']}")
    print(f"cache hits       {out['hits']}")
    return 1 if out["differences"] else 0


if __name__ == "__main__":
    sys.exit(main())
