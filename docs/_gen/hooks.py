"""MkDocs hooks: the pages made from the package itself at build time.

* ``reference/scenes.md``: every scene key (from the key table in the header of
  ``profilegen/pipeline/scenes.toml``, checked against :class:`profilegen.Scene`'s fields) and every
  bundled scene's values (``profilegen.SCENES``).
* ``reference/api.md``: one mkdocstrings block per name in ``profilegen.__all__``, each at the
  module that defines it (the package imports some lazily, which static analysis cannot follow).
* ``gearset.md`` is written by hand; the build checks that it has a table row for every key of
  the gear-set schema and none for a key the schema does not know.

A page that cannot be made, or a gear-set page out of date, fails the build (``PluginError``).
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File

import profilegen
from profilegen.pipeline import scenes as _scenes_module

ROOT = Path(__file__).resolve().parents[2]


# ----------------------------------------------------------------------------- scenes

def scene_key_table(header: str) -> dict[str, tuple[str, str]]:
    """``{key: (kind, meaning)}`` from the ``# Keys`` block of scenes.toml's header comment."""
    keys: dict[str, list[str]] = {}
    kinds: dict[str, str] = {}
    inside = False
    last = None
    for line in header.splitlines():
        if not line.startswith("#"):
            break
        text = line[1:]
        if text.strip().startswith("Keys"):
            inside = True
            continue
        if not inside:
            continue
        if not text.strip():
            break
        m = re.match(r"\s{2,3}(\w+)\s+(\w+)\s+(.*)", text)
        if m and len(text) - len(text.lstrip()) <= 3:
            last = m.group(1)
            kinds[last] = m.group(2)
            keys[last] = [m.group(3).strip()]
        elif last is not None:
            keys[last].append(text.strip())
    return {k: (kinds[k], " ".join(v)) for k, v in keys.items()}


def toml_value(v) -> str:
    """A scene value as it is written in the TOML file."""
    if isinstance(v, bool):
        return "`true`" if v else "`false`"
    if isinstance(v, str):
        return f'`"{v}"`'
    return f"`{v!r}`"


def scenes_page() -> str:
    path = _scenes_module.bundled_scenes_path()
    text = path.read_text(encoding="utf-8")
    table = scene_key_table(text)
    fields = [f.name for f in dataclasses.fields(profilegen.Scene) if f.name != "name"]
    if set(table) != set(fields):
        raise PluginError(f"profilegen/pipeline/scenes.toml's key table and profilegen.Scene disagree: only in the "
                          f"header {sorted(set(table) - set(fields))}, only in Scene {sorted(set(fields) - set(table))}")
    defaults = {f.name: f.default for f in dataclasses.fields(profilegen.Scene)
                if f.default is not dataclasses.MISSING}
    intro = []
    for line in text.splitlines():
        if not line.startswith("#") or line.lstrip("# ").startswith("Keys"):
            break
        intro.append(line[2:] if line.startswith("# ") else line[1:])
    while intro and not intro[-1].strip():
        intro.pop()
    out = ["# Scene reference", "",
           "*Made from `profilegen/pipeline/scenes.toml` and `profilegen.Scene` when the docs are built.*", "",
           "A scene is a fidelity preset: how fine each stage of the pipeline works. The bundled ones are in "
           "`profilegen/pipeline/scenes.toml`; `profilegen design --scene list` prints them and where the file is. "
           "Copy the file, edit the copy, and run `profilegen design --scene my_scenes.toml` (in Python "
           "`pg.design(gearset, scene=\"my_scenes.toml\")`); every key is validated like a gear-set field.", "",
           "## The bundled scenes", "",
           "| key | " + " | ".join(f"`{n}`" for n in profilegen.SCENES) + " |",
           "|---|" + "---|" * len(profilegen.SCENES)]
    for key in fields:
        row = []
        for n, scene in profilegen.SCENES.items():
            v = scene.rim_tier if key == "tier" else getattr(scene, key)
            row.append(toml_value(v))
        out.append(f"| `{key}` | " + " | ".join(row) + " |")
    out += ["", "Every scene ends with the stress stage. The rim FEM needs the two symmetry planes of a two-wave "
            "generator (a quarter model); for other wave counts the scenes fall back to ring theory and say so in "
            "`design.json[\"warnings\"]`.", "",
            "## Keys", "", "| key | kind | required | default | meaning |", "|---|---|---|---|---|"]
    for key in fields:
        kind, meaning = table[key]
        required = "no" if key in defaults else "yes"
        default = "" if key not in defaults else "the scene's name" if defaults[key] == "" else toml_value(defaults[key])
        out.append(f"| `{key}` | {kind} | {required} | {default} | {meaning.replace('|', '/')} |")
    out += ["", "## The file's header", "", "```toml", *("# " + s if s else "#" for s in intro), "```", ""]
    return "\n".join(out)


# ----------------------------------------------------------------------------- API

def api_targets() -> list[tuple[str, str]]:
    """``(public name, dotted path of its definition)`` for every name in ``profilegen.__all__``."""
    out = []
    for name in profilegen.__all__:
        try:
            obj = getattr(profilegen, name)
        except Exception as exc:  # a name in __all__ that does not import is a broken API
            raise PluginError(f"profilegen.{name} is in __all__ but does not import: {exc}") from exc
        if name == "SCENES":
            out.append((name, "profilegen.pipeline.scenes.SCENES"))
        elif hasattr(obj, "__qualname__") and getattr(obj, "__module__", None):
            out.append((name, f"{obj.__module__}.{obj.__qualname__}"))
        elif callable(getattr(obj, name, None)):  # a callable module (profilegen.studies.optimize)
            inner = getattr(obj, name)
            out.append((name, f"{inner.__module__}.{inner.__qualname__}"))
        else:
            raise PluginError(f"profilegen.{name}: cannot tell where it is defined")
    return out


GROUPS = [
    ("Design a gear", ["design", "Design", "write_design", "Scene", "SCENES"]),
    ("Redesign in a warm process", ["Engine", "Cancelled"]),
    ("Gear sets", ["GearSet", "load_gearset", "parse_gearset", "resolve_gearset", "default_gearset_path",
                   "list_profiles", "new_gearset"]),
    ("Studies", ["optimize"]),
    ("Stages", ["dcta_tooth", "involute_tooth", "points_tooth", "tooth_from_gearset", "ToothProfile",
                "solve_rim", "solve_ring", "RimDeformation", "ring_theory", "HarmonicDeformation", "fit_fourier",
                "fit_sine_series", "HarmonicDriveMotion", "RackMotion", "envelope_of", "Envelope",
                "circular_spline_form", "CircularSplineForm", "clearance_map"]),
    ("Errors", ["ProfilegenError", "GearSetError", "ToothError", "EnvelopeError", "ConvergenceError", "ExportError"]),
]


def api_page() -> str:
    targets = dict(api_targets())
    out = ["# API reference", "",
           "*Made from the docstrings of the names in `profilegen.__all__` when the docs are built.* "
           "These names are what a script may rely on; import them from `profilegen` "
           "(`import profilegen as pg; pg.design(...)`), not from the module each is defined in.", ""]
    placed = set()
    for title, names in GROUPS:
        present = [n for n in names if n in targets]
        if not present:
            continue
        out += [f"## {title}", ""]
        for n in present:
            placed.add(n)
            out += [f"### `profilegen.{n}`", "", f"::: {targets[n]}", "    options:",
                    "      show_root_heading: true", "      heading_level: 4", "      show_root_toc_entry: false", ""]
    rest = [n for n in targets if n not in placed]
    if rest:
        out += ["## Other names", ""]
        for n in rest:
            out += [f"### `profilegen.{n}`", "", f"::: {targets[n]}", "    options:",
                    "      show_root_heading: true", "      heading_level: 4", "      show_root_toc_entry: false", ""]
    return "\n".join(out)


# ----------------------------------------------------------------------------- gear-set page

def gearset_schema_keys() -> dict[str, set[str]]:
    """Every key a gear-set file may have, by section (``""`` the top level, ``tooth.<kind>``)."""
    from profilegen.gearset import sections as s  # the schema's own lists: one implementation

    keys = {"": set(s.TOP_KEYS)}
    for section, names in s._SECTION_KEYS.items():
        keys[section] = set(names)
    for kind, names in s.TOOTH_KEYS.items():
        keys[f"tooth.{kind}"] = set(names)
    return keys


def check_gearset_page(markdown: str) -> None:
    """Fail the build when docs/gearset.md misses a schema key or documents one that is gone."""
    rows = set()
    for line in markdown.splitlines():
        m = re.match(r"\|\s*`([a-z_0-9]+)`", line)
        if m:
            rows.add(m.group(1))
    schema = set().union(*gearset_schema_keys().values())
    lengths = {k[: -len("_coefficient")] for k in schema if k.endswith("_coefficient")}
    known = schema | lengths | {"default.toml", "seed000_csf40.toml"}
    missing = sorted(k for k in schema
                     if k not in rows and not (k.endswith(("_mm", "_coefficient")) and
                                               re.sub(r"_(mm|coefficient)$", "", k) in rows))
    unknown = sorted(r for r in rows if r not in known and not r.endswith(".toml"))
    if missing or unknown:
        raise PluginError(f"docs/gearset.md is out of date with profilegen/gearset: keys without a row {missing}, "
                          f"rows for keys the schema does not have {unknown}")


# ----------------------------------------------------------------------------- hooks

def on_files(files, config):
    for path, make in (("reference/scenes.md", scenes_page), ("reference/api.md", api_page)):
        files.append(File.generated(config, path, content=make()))
    return files


def on_page_markdown(markdown, page, config, files):
    if page.file.src_uri == "gearset.md":
        check_gearset_page(markdown)
    return markdown


_SPHINX_ROLE = re.compile(r":(?:py:)?(?:mod|class|func|meth|attr|data|exc|obj|const):(<code>)~?")


def on_page_content(html, page, config, files):
    """The docstrings use Sphinx roles (:class:`X`); on the API page show them as plain code."""
    if page.file.src_uri == "reference/api.md":
        html = _SPHINX_ROLE.sub(r"\1", html)
    return html
