"""The optimisation spec: a TOML file naming what is searched and how.

Example (``profiles/optimize/default.toml``)::

    name = "default"
    gearset = "default"        # a bundled gear-set name, or a TOML path relative to this file
    scene = "sketch"           # the search's scene (cheap)
    confirm_scene = "design"   # the front is run again in this scene ("" : not confirmed)

    [search]
    population = 16            # NSGA-II population (candidates per generation)
    generations = 12
    seed = 1

    [variables]                # gear-set field path = [lo, hi]; both integers → an integer variable
    "wave_generator.deflection_coefficient" = [0.9, 1.1]

    [objectives]               # output = "min" | "max"
    stress_min_safety = "max"

    [constraints]              # output = { min = ..., max = ..., scale = ... }
    min_clearance_mm = { min = 0.0, scale = 0.001 }

Validation is complete before anything runs or is written: an unknown key, a variable
that is not a gear-set field, bounds the gear set refuses (the gear set is built at each
bound, the other variables at the base set's values, by the gear-set reader itself), an
objective or constraint on an output that does not exist (or that the search scene does
not compute: the contact outputs need a scene with the loaded contact) are each an
:class:`~profilegen.errors.OptimizeSpecError` naming the file and the key.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, NoReturn

from ...errors import GearSetError, OptimizeSpecError
from ...gearset import GearSet
from ..sweep import check_field, flat_table, spec_header, spec_scene
from .evaluate import CONTACT_OUTPUTS, DESIGN_OUTPUTS
from .search import SENSES, Constraint, Objective, Variable

if TYPE_CHECKING:  # pragma: no cover
    from collections.abc import Callable

    from ...pipeline.scenes import Scene

    _Fail = Callable[[str, str], NoReturn]  # raises the spec's error for a key and its problem

__all__ = ["OptimizeSpec", "load_optimize_spec", "parse_optimize_spec"]

_TOP_KEYS = ("name", "description", "gearset", "scene", "confirm_scene", "search", "variables", "objectives",
             "constraints")
_SEARCH_KEYS = ("population", "generations", "seed")
_CONSTRAINT_KEYS = ("min", "max", "scale")
MAX_POPULATION = 10_000
MAX_GENERATIONS = 10_000


@dataclass(frozen=True, slots=True, eq=False)
class OptimizeSpec:
    """A validated optimisation: the base gear set, the scenes, variables, objectives,
    constraints and the search's settings; ``start``: the base set's value of each variable."""

    name: str
    gearset: GearSet
    scene: Scene
    confirm_scene: Scene | None
    variables: tuple[Variable, ...]
    objectives: tuple[Objective, ...]
    constraints: tuple[Constraint, ...]
    population: int = 16
    generations: int = 10
    seed: int = 0
    description: str = ""
    start: tuple = ()
    origin: str = "<dict>"

    def to_dict(self) -> dict:
        return {"name": self.name, "description": self.description, "gearset": self.gearset.name,
                "scene": self.scene.name, "confirm_scene": None if self.confirm_scene is None else self.confirm_scene.name,
                "variables": {v.name: [v.lo, v.hi] for v in self.variables},
                "objectives": {o.output: o.sense for o in self.objectives},
                "constraints": {c.output: {"min": c.lo, "max": c.hi, "scale": c.scale} for c in self.constraints},
                "population": self.population, "generations": self.generations, "seed": self.seed,
                "origin": self.origin}


def load_optimize_spec(path: str | os.PathLike) -> OptimizeSpec:
    """Read and validate an optimisation spec file (:class:`OptimizeSpecError` naming the key)."""
    from ...gearset import read_toml

    path = Path(path)
    data = read_toml(path, OptimizeSpecError, "optimisation spec file")
    return parse_optimize_spec(data, origin=str(path), base_dir=path.parent, default_name=path.stem)


def _number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _int(v) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


def field_value(gearset: GearSet, path: str):
    """The base set's value of a field path (as written, or its derived default)."""
    for data in (gearset.to_dict(include_defaults=False), gearset.to_dict()):
        node = data
        for part in path.split("."):
            if not isinstance(node, Mapping) or part not in node:
                break
            node = node[part]
        else:
            return node
    return None


def parse_optimize_spec(data: Mapping, *, origin: str = "<dict>", base_dir: str | os.PathLike | None = None,
                        default_name: str = "optimize") -> OptimizeSpec:
    """Validate a spec mapping (the TOML's tables) and build the :class:`OptimizeSpec`."""

    def fail(key: str, problem: str) -> NoReturn:
        raise OptimizeSpecError(f"{origin}: {key}: {problem}")

    name, description, base, gearset = spec_header(data, _TOP_KEYS, fail, what="an optimisation spec",
                                                   default_name=default_name, base_dir=base_dir)
    scene = _spec_scene(data, "scene", "sketch", base, gearset, fail)
    # an empty confirm scene: no confirmation
    confirm = None if data.get("confirm_scene") == "" else _spec_scene(data, "confirm_scene", "design", base,
                                                                       gearset, fail)
    population, generations, seed = _search_settings(data, fail)
    variables, start = _variables(data, gearset, fail)
    objectives = _objectives(data, scene, confirm, fail)
    constraints = _constraints(data, scene, confirm, fail)
    return OptimizeSpec(name=name, gearset=gearset, scene=scene, confirm_scene=confirm, variables=tuple(variables),
                        objectives=tuple(objectives), constraints=tuple(constraints), population=population,
                        generations=generations, seed=seed, description=description, start=tuple(start),
                        origin=origin)


def _spec_scene(data: Mapping, key: str, default: str, base: Path, gearset: GearSet, fail: _Fail) -> Scene:
    """The scene named by ``key`` (``default`` when absent)."""
    text = data.get(key, default)
    if not isinstance(text, str):
        fail(key, f"must be a text, got {text!r}")
    return spec_scene(text, base, gearset, fail, key)


def _search_settings(data: Mapping, fail: _Fail) -> tuple[int, int, int]:
    """The ``[search]`` table's population, generations and seed, checked against their ranges."""
    search = data.get("search", {})
    if not isinstance(search, Mapping):
        fail("search", f"must be a table, got {type(search).__name__}")
    for key in search:
        if key not in _SEARCH_KEYS:
            fail(f"search.{key}", f"unknown key (allowed: {', '.join(_SEARCH_KEYS)})")
    population = search.get("population", 16)
    if not _int(population) or not 4 <= population <= MAX_POPULATION:
        fail("search.population", f"{population!r}: must be an integer in [4, {MAX_POPULATION}]")
    generations = search.get("generations", 10)
    if not _int(generations) or not 1 <= generations <= MAX_GENERATIONS:
        fail("search.generations", f"{generations!r}: must be an integer in [1, {MAX_GENERATIONS}]")
    seed = search.get("seed", 0)
    if not _int(seed) or seed < 0:
        fail("search.seed", f"{seed!r}: must be an integer >= 0")
    return population, generations, seed


def _variables(data: Mapping, gearset: GearSet, fail: _Fail) -> tuple[list[Variable], list]:
    """The ``[variables]`` (field = [lo, hi]) and the base set's value of each; the gear set must
    take each bound with the other variables at their base values."""
    if "variables" not in data:
        fail("variables", "missing: give at least one gear-set field = [lo, hi]")
    ranges = flat_table(data["variables"], "variables", fail)
    if not ranges:
        fail("variables", "needs at least one gear-set field = [lo, hi]")
    variables = []
    start = []
    for path, rng in ranges.items():
        key = f"variables.{path}"
        if not (isinstance(rng, list) and len(rng) == 2 and all(_number(v) for v in rng) and rng[0] < rng[1]):
            fail(key, f"must be [lo, hi] with finite numbers lo < hi, got {rng!r}")
        lo, hi = rng
        check_field(gearset, path, lo, key, fail)  # not a field, or a value of the wrong type
        variables.append(Variable(path, lo, hi, integer=_int(lo) and _int(hi)))
        start.append(field_value(gearset, path))
    base_values = {v.name: s for v, s in zip(variables, start) if s is not None}
    for v in variables:  # the gear set at each bound, the others at the base set's values
        for bound in (v.lo, v.hi):
            try:
                gearset.with_values({**base_values, v.name: bound})
            except GearSetError as exc:
                lines = "; ".join(" ".join(str(p).split()) for p in exc.problems)
                fail(f"variables.{v.name}", f"bound {bound!r} is outside what the gear set takes ({lines})")
    return variables, start


def _check_output(key: str, output: str, scene: Scene, confirm: Scene | None, fail: _Fail) -> None:
    """``output`` must be a design output, and one that needs the loaded contact only where the
    search and confirm scenes run it."""
    if output not in DESIGN_OUTPUTS:
        fail(key, f"{output!r} is not an output (one of {', '.join(DESIGN_OUTPUTS)})")
    if output in CONTACT_OUTPUTS and not scene.contact:
        fail(key, f"{output!r} needs the loaded contact, which the search scene {scene.name!r} does not run "
                  "(use a scene with contact = true)")
    if output in CONTACT_OUTPUTS and confirm is not None and not confirm.contact:
        fail(key, f"{output!r} needs the loaded contact, which the confirm scene {confirm.name!r} does not run")


def _objectives(data: Mapping, scene: Scene, confirm: Scene | None, fail: _Fail) -> list[Objective]:
    """The ``[objectives]`` (output = "min" | "max"), at least one."""
    objectives_table = data.get("objectives")
    if not isinstance(objectives_table, Mapping) or not objectives_table:
        fail("objectives", "give at least one output = \"min\" or \"max\"")
    objectives = []
    for output, sense in objectives_table.items():
        _check_output(f"objectives.{output}", str(output), scene, confirm, fail)
        if sense not in SENSES:
            fail(f"objectives.{output}", f"{sense!r}: must be \"min\" or \"max\"")
        objectives.append(Objective(str(output), sense))
    return objectives


def _constraints(data: Mapping, scene: Scene, confirm: Scene | None, fail: _Fail) -> list[Constraint]:
    """The ``[constraints]`` (output = { min, max, scale })."""
    table = data.get("constraints", {})
    if not isinstance(table, Mapping):
        fail("constraints", f"must be a table, got {type(table).__name__}")
    constraints = []
    for output, bounds in table.items():
        key = f"constraints.{output}"
        _check_output(key, str(output), scene, confirm, fail)
        constraints.append(_constraint(key, str(output), bounds, fail))
    return constraints


def _constraint(key: str, output: str, bounds, fail: _Fail) -> Constraint:
    """One constraint's table: min, max or both (min ≤ max), and a scale > 0 (default the larger |bound|, else 1)."""
    if not isinstance(bounds, Mapping) or not bounds:
        fail(key, f"must be a table {{ min = ..., max = ..., scale = ... }}, got {bounds!r}")
    for k in bounds:
        if k not in _CONSTRAINT_KEYS:
            fail(f"{key}.{k}", f"unknown key (allowed: {', '.join(_CONSTRAINT_KEYS)})")
    lo, hi = bounds.get("min"), bounds.get("max")
    if lo is None and hi is None:
        fail(key, "needs min, max or both")
    for k, given in (("min", lo), ("max", hi)):
        if given is not None and not _number(given):
            fail(f"{key}.{k}", f"must be a finite number, got {given!r}")
    if lo is not None and hi is not None and lo > hi:
        fail(key, f"min {lo!r} > max {hi!r}")
    default_scale = max(abs(x) for x in (lo, hi) if x is not None) or 1.0
    scale = bounds.get("scale", default_scale)
    if not _number(scale) or scale <= 0:
        fail(f"{key}.scale", f"must be a number > 0, got {scale!r}")
    return Constraint(output, None if lo is None else float(lo), None if hi is None else float(hi), float(scale))
