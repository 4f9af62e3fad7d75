"""`profilegen bench`: where the speed-against-accuracy benchmarks are found.

The benchmarks are not part of the product: they live in the source checkout's
``tests/benchmarks/`` (``scenes.py``: the whole pipeline per scene, ``pipeline.{csv,png}``;
``stages.py``: every stage and tier against a converged reference, ``stages.{csv,png}``).
:func:`load_benchmark` loads one of them from the checkout this package was imported from
(an editable install or ``python -m profilegen`` in a clone). An installed wheel has no
``tests/``: there it raises :class:`~profilegen.errors.BenchmarkNotFoundError`, which the
command line reports as one line on stderr, exit code 2.

This module imports nothing heavy (no matplotlib, no solver): the benchmarks import what
they need, through the package's public names only.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

from .errors import BenchmarkNotFoundError

__all__ = ["BENCHMARKS", "benchmarks_dir", "load_benchmark"]

#: the benchmark modules ``profilegen bench`` runs, by name (``tests/benchmarks/<name>.py``)
BENCHMARKS = ("scenes", "stages")


def benchmarks_dir() -> Path:
    """``tests/benchmarks/`` of the source checkout holding this package (it need not exist:
    an installed wheel has none)."""
    return Path(__file__).resolve().parent.parent / "tests" / "benchmarks"


def load_benchmark(name: str) -> ModuleType:
    """The benchmark module ``tests/benchmarks/<name>.py`` of the source checkout: the module
    ``tests.benchmarks.<name>`` where it is already imported from that file (the test suite
    does), else that file loaded as ``profilegen_benchmark_<name>`` (``sys.path`` untouched:
    another package named ``tests`` cannot shadow it).

    Raises ``ValueError`` for a name not in :data:`BENCHMARKS`, and
    :class:`~profilegen.errors.BenchmarkNotFoundError` (one line, naming the file looked for)
    where the package is not in a source checkout (no such file beside it).
    """
    if name not in BENCHMARKS:
        raise ValueError(f"name = {name!r}: must be one of {', '.join(BENCHMARKS)}")
    folder = benchmarks_dir()
    path = folder / f"{name}.py"
    if not path.is_file():
        raise BenchmarkNotFoundError(
            f"the benchmarks live in the source checkout's tests/benchmarks/, not in an installed package: "
            f"run `profilegen bench` from a clone of the repository ({path} does not exist)")
    for qualified in (f"tests.benchmarks.{name}", f"profilegen_benchmark_{name}"):
        module = sys.modules.get(qualified)
        if module is not None and Path(getattr(module, "__file__", None) or "").resolve() == path:
            return module
    qualified = f"profilegen_benchmark_{name}"
    spec = importlib.util.spec_from_file_location(qualified, path)
    assert spec is not None and spec.loader is not None  # a .py file's
    module = importlib.util.module_from_spec(spec)
    sys.modules[qualified] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(qualified, None)
        raise
    return module
