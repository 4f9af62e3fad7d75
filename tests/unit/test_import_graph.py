"""The package's import graph, read from the source (issue 14): no cycles, matplotlib and the
plotting libraries only in the output layer, and the stages never reach up into it.

Every ``import`` and ``from … import`` statement of every module under ``profilegen/`` is an
edge, wherever it stands (module level or inside a function: a lazy import still ties the
two modules together), except those under ``if TYPE_CHECKING:`` (annotations only, never run).
A relative import is resolved to the module it names: ``from ..rim import solve_ring`` is an
edge to ``profilegen.rim``, ``from .. import series`` to ``profilegen.geometry.series``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "profilegen"

#: Third-party modules that draw: imported only inside profilegen.output.
DRAWING = ("matplotlib", "plotly")

#: Modules that run stages and write files (orchestrators) — they may import the output layer.
ORCHESTRATORS = {"profilegen", "profilegen.__main__", "profilegen.cli", "profilegen.studies.sweep", "profilegen.bench",
                 "profilegen.studies.optimize.run"}
#: Front ends that drive the stages and write through the output layer, as the CLI does.
FRONT_ENDS = ("profilegen.app",)
#: Single lazy edges allowed past that: Design._repr_html_, a notebook's view of a design (issue 14, item 4).
NOTEBOOK_VIEW = {("profilegen.pipeline.design", "profilegen.output.interactive")}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _is_type_checking(node: ast.If) -> bool:
    test = node.test
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _imports(path: Path, modules: set[str]) -> set[str]:
    """The modules ``path`` imports (absolute names), TYPE_CHECKING blocks left out."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()

    def visit(node: ast.AST) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _is_type_checking(child):
                for other in child.orelse:
                    visit(other)
                continue
            if isinstance(child, ast.Import):
                found.update(alias.name for alias in child.names)
            elif isinstance(child, ast.ImportFrom):
                if child.level:
                    base = package.split(".")
                    base = base[: len(base) - (child.level - 1)]
                    target = ".".join(base + ([child.module] if child.module else []))
                else:
                    target = child.module or ""
                for alias in child.names:  # `from . import series` names a module, not an attribute
                    sub = f"{target}.{alias.name}"
                    found.add(sub if sub in modules else target)
            visit(child)

    visit(ast.parse(path.read_text(encoding="utf-8"), filename=str(path)))
    return found


@pytest.fixture(scope="module")
def graph() -> dict[str, set[str]]:
    paths = sorted(PACKAGE.rglob("*.py"))
    modules = {_module_name(p) for p in paths}
    return {_module_name(p): _imports(p, modules) for p in paths}


def _cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan), or a self-import."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def strong(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in edges:
                continue
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 or v in edges.get(v, ()):
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            strong(v)
    return out


def test_the_graph_is_read(graph):
    """The reader sees what is there: known edges, resolved from relative imports."""
    assert "profilegen.errors" in graph["profilegen.pipeline.design"]
    assert "profilegen.rim.stage" in graph["profilegen.pipeline.design"]  # a lazy import, inside design()
    assert "profilegen.geometry.series" in graph["profilegen.rim.ring"]  # `from .. import series`
    assert any(m.startswith("matplotlib") for m in graph["profilegen.output.plot"])


def test_cycle_finder_finds_a_cycle():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_cycles(graph):
    # the package's __init__ re-exports its modules' names; a module importing its own package's
    # __init__ (``from . import x`` resolved to the package) is the usual Python layout, not a cycle
    edges = {m: {t for t in ts if not (m.startswith(t + ".") and t != "profilegen")} for m, ts in graph.items()}
    edges["profilegen"] = set()  # the top-level facade (lazy __getattr__ included) imports, nothing imports it back
    assert _cycles(edges) == []


def test_drawing_libraries_only_in_the_output_layer(graph):
    offenders = sorted(f"{m} imports {t}" for m, ts in graph.items() for t in ts
                       if t.split(".")[0] in DRAWING and not m.startswith("profilegen.output"))
    assert offenders == []


def test_stages_never_import_the_output_layer(graph):
    offenders = sorted(f"{m} imports {t}" for m, ts in graph.items() for t in ts
                       if t.startswith("profilegen.output") and not m.startswith("profilegen.output")
                       and m not in ORCHESTRATORS and not m.startswith(FRONT_ENDS) and (m, t) not in NOTEBOOK_VIEW)
    assert offenders == []


#: The package's folders in pipeline order: a module may import its own folder and the folders
#: before it, never one after it. ``base`` is the top level's shared modules (errors, argument
#: checks, result conventions, BLAS threads, process pools, the stage cache's checkpoints, the LCP
#: solvers).
LAYERS = ("base", "geometry", "gearset", "rim", "profile", "face", "contact", "stress", "pipeline", "output",
          "studies", "app", "front")
BASE = {"errors", "checks", "results", "blas", "pools", "stagecache", "lcp"}
FRONT = {"cli", "bench", "__main__"}


def _layer(module: str) -> str | None:
    """The layer of a module of the package (None: the package's facade ``profilegen`` itself)."""
    parts = module.split(".")
    if len(parts) == 1:
        return None
    if parts[1] in BASE:
        return "base"
    if parts[1] in FRONT:
        return "front"
    return parts[1]


def test_every_module_has_a_layer(graph):
    unknown = sorted(m for m in graph if _layer(m) is not None and _layer(m) not in LAYERS)
    assert unknown == []


def test_layer_rule_sees_an_upward_edge():
    assert LAYERS.index(_layer("profilegen.geometry.teeth")) < LAYERS.index(_layer("profilegen.pipeline.budget"))
    assert _layer("profilegen.errors") == "base" and _layer("profilegen.cli") == "front"


def test_no_upward_edges(graph):
    """The folders read as the pipeline: nothing reaches forward into a later stage (the notebook
    view's one lazy edge excepted), so each folder can be read, tested and used with only the
    folders before it."""
    offenders = sorted(f"{m} imports {t}" for m, ts in graph.items() for t in ts
                       if t.startswith("profilegen.") and _layer(m) is not None and _layer(t) in LAYERS
                       and LAYERS.index(_layer(t)) > LAYERS.index(_layer(m)) and (m, t) not in NOTEBOOK_VIEW)
    assert offenders == []
