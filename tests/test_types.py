"""The package passes its type checker, and its declared public surface is annotated.

* mypy, with the configuration in pyproject.toml's ``[tool.mypy]``, on the whole package: a
  module not in :data:`KNOWN_ERRORS` has no error, a module in it no more than its count. The
  list may only shrink (a module that reached its count's fall is told to lower it, one at zero
  to leave the list).
* A module named only for an annotation (``if TYPE_CHECKING:``) closes no import cycle.
* Every parameter and return of the declared public surface is annotated: the functions in
  ``profilegen.__all__``, the public methods and properties of its classes and of the result
  classes a design hands back (:data:`RESULT_CLASSES`), and every field of those result classes
  has a type other than ``object``.

``python tests/test_types.py`` prints the annotation coverage of that surface and what is missing.
"""

from __future__ import annotations

import dataclasses
import importlib
import importlib.util
import inspect
import re
import subprocess
import sys
from collections import Counter
from collections.abc import Callable
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: module file (relative to the repository) → mypy errors left in it. May only shrink.
KNOWN_ERRORS: dict[str, int] = {}

#: public callable → its parameters (and "return") left bare, each with its reason. May only shrink.
KNOWN_GAPS: dict[str, list[str]] = {}

#: result fields typed ``object``, each with its reason. May only shrink.
KNOWN_UNTYPED_FIELDS: list[str] = []

#: the result classes a design hands back (Design's fields and what they hold), besides ``__all__``'s
RESULT_CLASSES = (
    "profilegen.pipeline.design:Design", "profilegen.pipeline.design:CSProfile", "profilegen.pipeline.design:StageReport",
    "profilegen.pipeline.design:Verdict", "profilegen.rim.stage:RimDeformation", "profilegen.profile.envelope:Envelope",
    "profilegen.profile.gearform:CircularSplineForm", "profilegen.profile.gearform:ClearanceMap",
    "profilegen.contact.analysis:ContactResult", "profilegen.stress.stage:StressResult",
    "profilegen.face.stage:FaceWidth", "profilegen.contact.chain:TorsionalCurve",
    "profilegen.contact.ratchet:Ratcheting", "profilegen.contact.transmission:TransmissionError",
)

ERROR_LINE = re.compile(r"^(?P<path>[^:\s]+\.py):\d+: error: ")


def mypy_errors(cache_dir: str = "/dev/null") -> tuple[Counter, str]:
    """(errors per module file, mypy's output) of mypy on the package, configured by pyproject.toml.
    ``cache_dir`` /dev/null: mypy writes no cache (a cold run, as in a fresh clone)."""
    res = subprocess.run([sys.executable, "-m", "mypy", "--cache-dir", cache_dir, "--no-pretty",
                          "--no-color-output", "--config-file", str(ROOT / "pyproject.toml")],
                         cwd=ROOT, capture_output=True, text=True, timeout=600)
    if res.returncode not in (0, 1):  # 2: mypy itself failed (a bad configuration, a crash)
        raise RuntimeError(f"mypy exited {res.returncode}: {res.stdout}{res.stderr}")
    found = Counter(m["path"] for m in map(ERROR_LINE.match, res.stdout.splitlines()) if m)
    return found, res.stdout


@pytest.mark.slow
def test_the_package_passes_mypy():
    if importlib.util.find_spec("mypy") is None:
        pytest.skip("mypy is not installed (the test extras install it)")
    found, out = mypy_errors()
    new = {f: n for f, n in found.items() if n > KNOWN_ERRORS.get(f, 0)}
    assert not new, ("mypy errors (python -m mypy, configured in pyproject.toml): "
                     + ", ".join(f"{f}: {n} (known {KNOWN_ERRORS.get(f, 0)})" for f, n in sorted(new.items()))
                     + "\n" + "\n".join(line for line in out.splitlines() if ERROR_LINE.match(line)
                                        and ERROR_LINE.match(line)["path"] in new))
    fewer = {f: found.get(f, 0) for f, n in KNOWN_ERRORS.items() if found.get(f, 0) < n}
    assert not fewer, f"fewer mypy errors than KNOWN_ERRORS says: lower these counts (0: take it out): {fewer}"


# ----------------------------------------------------------------------------- type-only imports

#: cycles that only the ``if TYPE_CHECKING:`` imports close (sorted module lists) → why left. May only shrink.
KNOWN_TYPE_CYCLES = {
    ("profilegen.face.modification", "profilegen.face.stage"):
        "face/ (another engineer's, in progress): modification names FaceWidth, stage imports modification",
}


def _import_graph(type_only: bool) -> tuple[dict[str, set[str]], Callable]:
    """tests/unit/test_import_graph.py's graph of the package (its edges as that test reads them),
    with the ``if TYPE_CHECKING:`` imports as edges too when ``type_only``."""
    spec = importlib.util.spec_from_file_location("_graph_for_types", ROOT / "tests" / "unit" / "test_import_graph.py")
    assert spec is not None and spec.loader is not None
    graph = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(graph)
    if type_only:
        graph._is_type_checking = lambda node: False  # every import counts
    paths = sorted(graph.PACKAGE.rglob("*.py"))
    modules = {graph._module_name(p) for p in paths}
    edges = {graph._module_name(p): graph._imports(p, modules) for p in paths}
    edges = {m: {t for t in ts if not (m.startswith(t + ".") and t != "profilegen")} for m, ts in edges.items()}
    edges["profilegen"] = set()
    return edges, graph._cycles


def test_type_only_imports_close_no_cycle():
    """A module named only for an annotation (``if TYPE_CHECKING:``) still ties the two modules:
    the cycles of the graph with those imports are the runtime graph's (tests/unit/test_import_graph.py)."""
    runtime, cycles = _import_graph(False)
    typed, _ = _import_graph(True)
    before = {tuple(c) for c in cycles(runtime)}
    new = [c for c in map(tuple, cycles(typed)) if c not in before and c not in KNOWN_TYPE_CYCLES]
    assert new == [], f"cycles closed by TYPE_CHECKING imports: {new}"
    stale = [c for c in KNOWN_TYPE_CYCLES if c not in {tuple(x) for x in cycles(typed)}]
    assert stale == [], f"gone, take them out of KNOWN_TYPE_CYCLES: {stale}"


# ----------------------------------------------------------------------------- annotation coverage

def _load(spec: str):
    module, _, name = spec.partition(":")
    return getattr(importlib.import_module(module), name)


def public_surface() -> dict[str, object]:
    """``{qualified name: function}`` of every public callable of the declared surface: the
    functions in ``profilegen.__all__``; the public methods, class/static methods and property
    getters its classes and :data:`RESULT_CLASSES` define (their own, not inherited from outside
    the package); a class's ``__init__`` where the class writes one."""
    import profilegen

    out: dict[str, object] = {}
    classes = []
    for name in profilegen.__all__:
        obj = getattr(profilegen, name)
        if inspect.isclass(obj):
            classes.append(obj)
        elif inspect.isfunction(obj):
            out[f"profilegen.{name}"] = obj
        elif inspect.ismodule(obj):  # profilegen.optimize(spec, out_dir) calls profilegen.studies.optimize.optimize
            out[f"profilegen.{name}.{name}"] = getattr(obj, name)
    classes += [_load(s) for s in RESULT_CLASSES]
    for cls in dict.fromkeys(classes):
        if issubclass(cls, BaseException):
            continue  # the errors: their constructors are Exception's
        for klass in cls.__mro__:
            if not klass.__module__.startswith("profilegen"):
                continue
            for attr, raw in vars(klass).items():
                if attr.startswith("_") and attr != "__init__":
                    continue
                key = f"{cls.__module__}.{cls.__qualname__}.{attr}"
                if key in out:
                    continue
                if isinstance(raw, property):
                    out[key] = raw.fget
                elif isinstance(raw, (classmethod, staticmethod)):
                    out[key] = raw.__func__
                elif inspect.isfunction(raw) and raw.__code__.co_filename != "<string>":  # not a dataclass's own
                    out[key] = raw
    return out


def missing_annotations(fn) -> list[str]:
    """The parameters (``self``/``cls`` aside) and the return of ``fn`` that carry no annotation."""
    sig = inspect.signature(fn)
    missing = [p.name for i, p in enumerate(sig.parameters.values())
               if p.annotation is inspect.Parameter.empty and not (i == 0 and p.name in ("self", "cls"))]
    name = getattr(fn, "__name__", "")
    if sig.return_annotation is inspect.Signature.empty and name != "__init__":
        missing.append("return")
    return missing


def untyped_fields() -> list[str]:
    """The result classes' dataclass fields typed ``object`` (or ``Any``, or nothing)."""
    bad = []
    for spec in RESULT_CLASSES:
        cls = _load(spec)
        for f in dataclasses.fields(cls):
            if f.name.startswith("_"):
                continue
            if str(f.type).strip("'\"") in ("object", "Any", "typing.Any", "<class 'object'>"):
                bad.append(f"{cls.__qualname__}.{f.name}")
    return bad


def coverage() -> tuple[int, int, dict[str, list[str]]]:
    """(annotated slots, slots, {function: what is missing}) over :func:`public_surface`: a slot
    is a parameter or a return."""
    total = done = 0
    gaps = {}
    for name, fn in sorted(public_surface().items()):
        sig = inspect.signature(fn)
        slots = sum(1 for i, p in enumerate(sig.parameters.values()) if not (i == 0 and p.name in ("self", "cls")))
        slots += getattr(fn, "__name__", "") != "__init__"
        miss = missing_annotations(fn)
        total += slots
        done += slots - len(miss)
        if miss:
            gaps[name] = miss
    return done, total, gaps


def test_the_public_surface_is_annotated():
    done, total, gaps = coverage()
    assert total > 100  # the surface is read: design's, load_gearset's, Design's methods ...
    new = {f: [m for m in miss if m not in KNOWN_GAPS.get(f, ())] for f, miss in gaps.items()}
    new = {f: miss for f, miss in new.items() if miss}
    assert new == {}, f"{done}/{total} annotated; not annotated: {new}"
    stale = {f: [m for m in miss if m not in gaps.get(f, ())] for f, miss in KNOWN_GAPS.items()}
    assert not any(stale.values()), f"annotated now, take them out of KNOWN_GAPS: {stale}"


def test_the_result_fields_are_typed():
    untyped = untyped_fields()
    assert sorted(set(untyped) - set(KNOWN_UNTYPED_FIELDS)) == []
    assert sorted(set(KNOWN_UNTYPED_FIELDS) - set(untyped)) == [], "typed now: take them out of KNOWN_UNTYPED_FIELDS"


def test_the_coverage_finds_a_gap():
    """The check itself: a parameter, a keyword-only one and a return left bare are found."""
    def f(a: int, b, *, c=1) -> int:
        return a

    def g(x: int):
        return x

    class K:
        def m(self, y: int) -> None:
            pass

    assert missing_annotations(f) == ["b", "c"]
    assert missing_annotations(g) == ["return"]
    assert missing_annotations(K.m) == []


if __name__ == "__main__":
    done, total, gaps = coverage()
    print(f"public surface: {len(public_surface())} callables, {done}/{total} parameters and returns "
          f"annotated ({100 * done / total:.1f} %)")
    for name, miss in gaps.items():
        print(f"  {name}: {', '.join(miss)}")
    fields = untyped_fields()
    print(f"result fields typed object/Any: {len(fields)}" + "".join(f"\n  {f}" for f in fields))
