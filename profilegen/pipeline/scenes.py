"""Scenes as data: the fidelity presets read from a TOML file (``profilegen/pipeline/scenes.toml``).

A scene file has one table per scene; the table's key is the scene's name, its keys are
the fields of :class:`Scene` (documented in the bundled file). The rim
stage's tier is the ``tier`` key (one of :data:`RIM_TIER_NAMES`: ``sketch``, ``design``,
``verify`` — the toothed 2D rim, also named ``toothed`` — or ``cup3d``, the 3D cup), which a
scene named sketch or design may leave out (the bundled ``verify`` scene uses ``cup3d``).
:func:`with_rim_tier` gives a scene another rim tier (``profilegen design --rim cup3d``). A user's copy of the bundled file (or a file with one table) is
used with ``design(gearset, scene="my_scenes.toml")`` or ``profilegen design --scene
my_scenes.toml``; ``my_scenes.toml#fast`` picks the scene ``fast`` of a file with several.

Every problem is a :class:`SceneError` (a :class:`~profilegen.errors.GearSetError`, so a
``ValueError``) naming the file, the scene and the key, with the allowed values:

>>> scenes = read_scenes(bundled_scenes_path())
>>> sorted(scenes), scenes["sketch"].chord_tol_mm, scenes["verify"].contact
(['design', 'sketch', 'verify'], 0.0001, True)
>>> parse_scenes({"fast": {"tier": "quick"}}, origin="mine.toml")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
profilegen.pipeline.scenes.SceneError: ...mine.toml: scene 'fast': tier = 'quick': must be one of sketch, design, verify...
>>> scenes["verify"].rim_tier, with_rim_tier(scenes["design"], "cup3d").rim_tier
('cup3d', 'cup3d')
"""

from __future__ import annotations

import logging
import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from ..errors import GearSetError, did_you_mean
from ..gearset import SCENE_NAMES, looks_like_path

__all__ = ["RIM_TIER_NAMES", "SCENES", "SCENE_NAMES", "Scene", "SceneError", "bundled_scenes_path", "parse_scenes",
           "read_scenes", "resolve_scene", "with_rim_tier"]

#: the rim stage's tiers (the keys of :data:`profilegen.rim.stage.RIM_TIERS`, named here without
#: importing the solvers) with the label a scene gets when :func:`with_rim_tier` sets one
RIM_TIER_NAMES = ("sketch", "design", "verify", "toothed", "cup3d")
RIM_TIER_LABELS = {"sketch": "ring theory", "design": "ring FEM (nonlinear)", "verify": "toothed-rim FEM (nonlinear)",
                   "toothed": "toothed-rim FEM (nonlinear)", "cup3d": "3D cup FEM (nonlinear)"}


class SceneError(GearSetError):
    """A scene file or scene name is wrong; each problem names the file, the scene and the key."""


# key → (kind, required, allowed range / None); kinds: "text", "mm", "count", "bool"
#: the finest chord tolerance a scene may ask for, mm (the envelope's points grow as 1/√tol)
CHORD_TOL_MIN_MM = 1e-9

_KEYS: dict[str, tuple[str, bool, tuple[float, float] | tuple[str, ...] | None]] = {
    "rim": ("text", True, None),
    # [lo, hi]: 1e-9 mm (1 pm) traced the default set in 16 s and 0.39 GB (8.4 M outline points, ~1/√tol:
    # 1e-12 would be ~30× that), 100× finer than the verify scene; finer is no design's need
    "chord_tol_mm": ("mm", True, (CHORD_TOL_MIN_MM, 1e-2)),
    "n_t": ("count", True, (8, 100_000)),
    "n_phi": ("count", True, (11, 100_000)),
    "clearance_samples": ("count", True, (3, 100_000)),
    "brute_force_check": ("bool", True, None),
    "description": ("text", True, None),
    "fit_check_positions": ("count", False, (3, 100_000)),
    "fit_starts": ("count", False, (1, 50)),
    "contact": ("bool", False, None),
    "tier": ("text", False, None),
    "figures": ("choice", False, ("all", "none")),
    "ratcheting": ("bool", False, None),
    "transmission_error": ("bool", False, None),
    "face_slices": ("count", False, (0, 33)),
}
@dataclass(frozen=True, slots=True)
class Scene:
    """A fidelity preset: the tier of every stage."""

    name: str
    rim: str  # deformation tier asked for
    chord_tol_mm: float  # envelope chord error
    n_t: int  # tracing grid along the flank
    n_phi: int  # tracing grid over one pass
    clearance_samples: int
    brute_force_check: bool  # cross-check the boundary against the brute-force swept region
    description: str
    fit_check_positions: int = 2001  # FS tooth poses the fitted CS profile is checked against
    contact: bool = False  # loaded tooth contact at the gear set's torques (rated, peak, momentary)
    tier: str = ""  # the rim stage's tier (RIM_TIER_NAMES); "" → the scene's name
    figures: str = "all"  # the PNG figures of the files and reports: "all", or "none" (`--figures` draws them)
    ratcheting: bool = False  # with the contact: the ratcheting torque estimate (contact.ratchet; seconds)
    transmission_error: bool = False  # with the contact: the loaded transmission error at 16 positions (~10 s)
    #: with the contact and the face stage (tier cup3d): the torsional curve as this many axial
    #: slices, nodes on both face ends (contact.face_curve); 0: one section, the load even across the face
    face_slices: int = 0
    #: the arc fit's minimax starts (the centred least-squares fit, the other least-squares optima,
    #: perturbations); the best is kept
    fit_starts: int = 3

    @property
    def rim_tier(self) -> str:
        """The rim stage's tier: ``tier``, or the name for the bundled presets."""
        return self.tier or self.name


_NAME = re.compile(r"[A-Za-z0-9_-]+")
MAX_SCENE_NAME_CHARS = 64
"""Longest scene name (it is shown in every report and sweep table)."""
MAX_TEXT_CHARS = 2000
"""Longest ``rim`` / ``description`` text (the gear set's description has the same limit)."""


def bundled_scenes_path() -> Path:
    """Path of the scene file shipped with the package (``profilegen/pipeline/scenes.toml``)."""
    return Path(str(resources.files("profilegen.pipeline").joinpath("scenes.toml")))


def read_scenes(path: str | os.PathLike) -> dict[str, Scene]:
    """Read and validate a scene file; returns {name: Scene} in the file's order."""
    from ..gearset import read_toml

    path = Path(path)
    return parse_scenes(read_toml(path, SceneError, "scene file"), origin=str(path))


def parse_scenes(data: Mapping, *, origin: str = "<dict>") -> dict[str, Scene]:
    """Validate a mapping {name: {key: value}} and build the scenes; every problem at once."""
    if not isinstance(data, Mapping) or not data:
        raise SceneError(f"{origin}: a scene file needs at least one [name] table (one of {', '.join(SCENE_NAMES)})")
    problems: list[str] = []
    scenes: dict[str, Scene] = {}
    for name, table in data.items():
        where = f"{origin}: scene {name!r}"
        if not _NAME.fullmatch(str(name)) or len(str(name)) > MAX_SCENE_NAME_CHARS:
            where = f"{origin}: scene {str(name)[:40]!r}{'...' if len(str(name)) > 40 else ''}"
            problems.append(f"{where}: a scene name is letters, digits, '_' and '-', at most {MAX_SCENE_NAME_CHARS}")
            continue
        if not isinstance(table, Mapping):
            problems.append(f"{where}: must be a table ([{name}]), got {_type_name(table)}")
            continue
        before = len(problems)
        for key in table:
            if key not in _KEYS:
                problems.append(f"{where}: {key}: unknown key (allowed: {', '.join(_KEYS)})")
        values: dict[str, Any] = {}
        for key, (kind, required, rng) in _KEYS.items():
            if key not in table:
                if required:
                    problems.append(f"{where}: {key}: missing ({_describe(kind, rng)})")
                continue
            problem = _check(table[key], kind, rng)
            if problem:
                shown = table[key] if not isinstance(table[key], str) or len(table[key]) <= 40 else table[key][:37] + "..."
                problems.append(f"{where}: {key} = {shown!r}: {problem}")
            else:
                values[key] = float(table[key]) if kind == "mm" else table[key]
        tier: Any = values.get("tier", name if name in SCENE_NAMES else None)  # the file's value, checked below
        if "tier" in table and "tier" not in values:
            pass  # reported above
        elif tier is None:
            problems.append(f"{where}: tier: missing (the rim stage's tier, one of {', '.join(RIM_TIER_NAMES)}; only "
                            f"a scene named after a tier may leave it out)")
        elif tier not in RIM_TIER_NAMES:
            problems.append(f"{where}: tier = {tier!r}: must be one of {', '.join(RIM_TIER_NAMES)}")
        if len(problems) == before:
            values.pop("tier", None)
            scenes[name] = Scene(name=name, **values, tier="" if tier == name else tier)
            _warn_ignored(scenes[name], where)
    if problems:
        raise SceneError(problems)
    return scenes


#: the rim tiers without a face stage: a scene's face_slices is ignored there
_NO_FACE_STAGE = ("sketch", "verify", "toothed")
_warned: set[tuple[str, ...]] = set()


def _warn_ignored(scene: Scene, where: str) -> None:
    """A scene key its tier ignores is a warning, once per file, scene and key (sweeps read a scene
    file once per point)."""
    if scene.face_slices and scene.rim_tier in _NO_FACE_STAGE:
        key = (where, "face_slices", scene.rim_tier)
        if key not in _warned:
            _warned.add(key)
            logging.getLogger(__name__).warning(
                "%s: face_slices = %d is ignored by tier %r (no face stage; the curve across the face needs "
                "tier = \"cup3d\" and the contact): set face_slices = 0 or tier = \"cup3d\"",
                where, scene.face_slices, scene.rim_tier)


def resolve_scene(scene: str | os.PathLike | Scene, *, default: str = "design") -> Scene:
    """A Scene from a bundled name, a Scene, or the path of a scene file.

    A file with one scene gives that scene; a file with several gives the one named
    ``default`` (the gear set's ``scene``).
    """
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, str) and scene in SCENES:
        return SCENES[scene]
    text = os.fspath(scene) if isinstance(scene, (str, os.PathLike)) else None
    if text is None or not (isinstance(scene, os.PathLike) or looks_like_path(text)):
        raise SceneError(f"scene = {scene!r}: must be one of {', '.join(SCENES)} or a scene TOML file"
                         + did_you_mean(scene, SCENES))
    text, _, wanted = text.partition("#") if "#" in text else (text, "", "")
    scenes = read_scenes(text)
    if wanted:
        if wanted not in scenes:
            raise SceneError(f"{text}: no scene {wanted!r}; the file has {', '.join(scenes)}" + did_you_mean(wanted, scenes))
        return scenes[wanted]
    if len(scenes) == 1:
        return next(iter(scenes.values()))
    if default not in scenes:
        raise SceneError(f"{text}: scene {default!r} (the gear set's scene) is not in the file, which has "
                         f"{', '.join(scenes)}")
    return scenes[default]


def with_rim_tier(scene: Scene, tier: str | None) -> Scene:
    """``scene`` with the rim stage's tier ``tier`` (one of :data:`RIM_TIER_NAMES`) and its label;
    ``scene`` itself for None or its own tier (``profilegen design --rim``)."""
    import dataclasses

    if tier is None or tier == scene.rim_tier:
        return scene
    if tier not in RIM_TIER_NAMES:
        raise SceneError(f"rim tier = {tier!r}: must be one of {', '.join(RIM_TIER_NAMES)}" + did_you_mean(tier, RIM_TIER_NAMES))
    return dataclasses.replace(scene, tier=tier, rim=RIM_TIER_LABELS[tier])


def _check(value, kind: str, rng) -> str:
    """'' if ``value`` is a valid ``kind`` within ``rng``, else what is wrong."""
    if kind == "text":
        if isinstance(value, str) and len(value) > MAX_TEXT_CHARS:
            return f"must be at most {MAX_TEXT_CHARS} characters, got {len(value)}"
        return "" if isinstance(value, str) and value.strip() else "must be a non-empty text"
    if kind == "bool":
        return "" if isinstance(value, bool) else f"must be true or false, got {_type_name(value)}"
    if kind == "choice":
        return "" if isinstance(value, str) and value in rng else f"must be one of {_describe(kind, rng)}"
    if kind == "count":
        if isinstance(value, bool) or not isinstance(value, int) or not rng[0] <= value <= rng[1]:
            return f"must be an integer in [{rng[0]}, {rng[1]}]"
        return ""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return f"must be a number ({_describe(kind, rng)})"
    return "" if rng[0] <= value <= rng[1] else f"must be in [{rng[0]:g}, {rng[1]:g}] mm"


def _describe(kind: str, rng) -> str:
    if kind == "count":
        return f"an integer in [{rng[0]}, {rng[1]}]"
    if kind == "mm":
        return f"mm, in [{rng[0]:g}, {rng[1]:g}]"
    if kind == "choice":
        return ", ".join(f'"{v}"' for v in rng)
    return "true or false" if kind == "bool" else "text"


def _type_name(value) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a text", list: "an array",
            dict: "a table"}.get(type(value), type(value).__name__)


# The presets are data: profilegen/pipeline/scenes.toml (a user's copy works as design(scene="path.toml"))
SCENES: dict[str, Scene] = read_scenes(bundled_scenes_path())
