"""The package's layout: no private name crosses a module.

A name with a leading underscore is its module's own: another module that imports it depends on
something its owner may change without notice, and the owner's reader cannot see the dependency.
Read from the source with ast (every ``from X import _name`` under ``profilegen/``, wherever it
stands: module level or inside a function), not from an import of the package.

The exceptions left are listed below, each with its reason. The list may only shrink: a new
crossing fails :func:`test_no_new_private_name_crosses_a_module`, and an entry whose import has
gone fails :func:`test_the_known_exceptions_are_still_there` (take it out of the list).
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "profilegen"

#: (importing module, module imported from, name) → why it is left
KNOWN_EXCEPTIONS: dict[tuple[str, str, str], str] = {
    ("profilegen.gearset", "profilegen.gearset.sections", "_points_tooth"):
        "a pickling alias: PointsTooth objects pickled before the gearset split name profilegen.gearset._points_tooth",
    ("profilegen.gearset.profiles", "profilegen.gearset.reader", "_show"):
        "the gear-set reader's quoting of a value in a message; profiles.py had another engineer's uncommitted "
        "edit when this list was made: rename to public with the next change there",
    ("profilegen.gearset.types", "profilegen.gearset.reader", "_Reader"):
        "the gear-set reader class, also used by profilegen/app (another engineer's, in progress): renamed with it",
    ("profilegen.app.schema", "profilegen.gearset.reader", "_Reader"):
        "profilegen/app (another engineer's, in progress this session)",
    ("profilegen.app.schema", "profilegen.gearset.reader", "_REQUIRED"):
        "profilegen/app (another engineer's, in progress this session)",
}


def _module_name(path: Path, package: Path = PACKAGE) -> str:
    parts = list(path.relative_to(package.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def private_imports(package: Path = PACKAGE) -> set[tuple[str, str, str]]:
    """Every (importing module, module imported from, name) with a name ``_x`` (not a dunder)
    imported from another module of the package."""
    found = set()
    for path in sorted(package.rglob("*.py")):
        name = _module_name(path, package)
        pkg = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), filename=str(path))):
            if not isinstance(node, ast.ImportFrom):
                continue
            if node.level:
                base = pkg.split(".")[: len(pkg.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != package.name or target == name:
                continue
            for alias in node.names:
                if alias.name.startswith("_") and not alias.name.startswith("__"):
                    found.add((name, target, alias.name))
    return found


def test_no_new_private_name_crosses_a_module():
    new = sorted(private_imports() - set(KNOWN_EXCEPTIONS))
    assert new == [], ("private names imported from another module (make the name public where it is "
                       "defined, or move the helper to where it is used): " + "; ".join(
                           f"{m} imports {n} from {t}" for m, t, n in new))


def test_the_known_exceptions_are_still_there():
    """The list only shrinks: an exception whose import is gone is taken out of the list (an
    entry of a module not in this checkout — another engineer's, not yet committed — is skipped)."""
    present = private_imports()
    modules = {_module_name(p) for p in PACKAGE.rglob("*.py")}
    stale = sorted(k for k in KNOWN_EXCEPTIONS if k[0] in modules and k not in present)
    assert stale == [], f"no longer imported, take them out of KNOWN_EXCEPTIONS: {stale}"


def test_the_scan_finds_a_private_import(tmp_path):
    """The scan itself, on a two-module package written here: a relative and an absolute import
    of a private name are found, a public one and a dunder are not."""
    pkg = tmp_path / "profilegen"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("from .a import _hidden, shown, __version__\n", encoding="utf-8")
    (pkg / "a.py").write_text("_hidden = shown = __version__ = 1\n", encoding="utf-8")
    (pkg / "sub" / "__init__.py").write_text("", encoding="utf-8")
    (pkg / "sub" / "b.py").write_text("def f():\n    from profilegen.a import _hidden\n    from ..a import _hidden as h\n",
                                      encoding="utf-8")
    assert private_imports(pkg) == {("profilegen", "profilegen.a", "_hidden"),
                                    ("profilegen.sub.b", "profilegen.a", "_hidden")}


# ----------------------------------------------------------------------------- citations

#: DESIGN.md is background outside the repository, issue numbers are work items: a reader of the
#: package has neither. A docstring or comment points at the docs page that explains the point.
CITATION = re.compile(r"DESIGN(\.md| trap)|\bissues? \d+", re.IGNORECASE)

#: package files (relative to profilegen/) that still cite one → why they are left. May only shrink.
KNOWN_CITATIONS: dict[str, str] = {
}


def citing_files(package: Path = PACKAGE) -> dict[str, list[str]]:
    """``{file relative to the package: [the lines that cite DESIGN.md or an issue number]}``
    over the package's Python and TOML files."""
    found = {}
    for path in sorted([*package.rglob("*.py"), *package.rglob("*.toml")]):
        lines = [f"{n}: {line.strip()}" for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
                 if CITATION.search(line)]
        if lines:
            found[path.relative_to(package).as_posix()] = lines
    return found


def test_no_package_file_cites_design_md_or_an_issue():
    new = {f: lines for f, lines in citing_files().items() if f not in KNOWN_CITATIONS}
    assert new == {}, ("cite the docs page that explains it (docs/theory, docs/validation, docs/reference), or "
                       f"drop it if it is history: {new}")


def test_the_known_citations_are_still_there():
    found = citing_files()
    stale = sorted(f for f in KNOWN_CITATIONS if (PACKAGE / f).exists() and f not in found)
    assert stale == [], f"no longer cite DESIGN.md or an issue, take them out of KNOWN_CITATIONS: {stale}"


def test_the_citation_pattern():
    cites = ["(DESIGN.md trap 7)", "DESIGN trap 1", "see DESIGN.md", "(issue 28)", "issue 15, items 4 and 5",
             "issues 14"]
    fine = ["DESIGN_OUTPUTS", "DESIGN_CUP_TIER", "a design issue", "docs/theory/rim.md", "tissue 3"]
    assert [bool(CITATION.search(s)) for s in cites] == [True] * len(cites)
    assert [bool(CITATION.search(s)) for s in fine] == [False] * len(fine)
