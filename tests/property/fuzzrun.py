"""One fuzz example end to end, shared by the fuzz test and its benchmark: validate the drawn
gear set, design it in a scene, write every output file (``write_design``) into a folder, and
check that nothing it holds or wrote is NaN or infinite.

``outcome`` returns ``"ok"`` or the name of the ProfilegenError that stopped the example; any
other exception propagates (a crash), a non-finite output is an AssertionError. The limits
that turn a runaway into a failure instead of an OOM kill of the machine or a hung run:
``memory_cap`` (RLIMIT_AS, restored on exit: a runaway allocation is a MemoryError) and
``time_limit`` (SIGALRM: ``OverTime``, a BaseException so that no ``except Exception`` in the
package swallows it).
"""

from __future__ import annotations

import contextlib
import json
import math
import resource
import signal
import tempfile
from pathlib import Path

import numpy as np

import profilegen as pg

#: Address-space cap of a fuzz process (bytes): a design needs < 1 GB.
MEMORY_CAP_BYTES = 4_000_000_000


class OverTime(BaseException):
    """An example ran past its time limit."""


@contextlib.contextmanager
def memory_cap(limit: int = MEMORY_CAP_BYTES):
    """Lower the soft RLIMIT_AS to ``limit`` (never raise it) for the block, then restore it."""
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    new = limit if soft == resource.RLIM_INFINITY else min(soft, limit)
    if hard != resource.RLIM_INFINITY:
        new = min(new, hard)
    resource.setrlimit(resource.RLIMIT_AS, (new, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


@contextlib.contextmanager
def time_limit(seconds: float | None):
    """Raise OverTime in the block after ``seconds`` of wall time (main thread only; None: no limit)."""
    if not seconds:
        yield
        return

    def expire(signum, frame):
        raise OverTime(f"over {seconds:g} s")

    old = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def outcome(data: dict, scene: str = "sketch", out_dir: str | Path | None = None, *, figure: bool = False,
            write: bool = True) -> str:
    """Run one gear set: 'ok' or the name of the ProfilegenError; asserts every output is finite.

    With ``write``, the files go into ``out_dir`` (a fresh temporary folder when None, removed
    afterwards) and are checked too.
    """
    try:
        gearset = pg.parse_gearset(data)
    except pg.ProfilegenError as exc:
        assert isinstance(exc, pg.GearSetError) and str(exc)
        return type(exc).__name__
    try:
        result = pg.design(gearset, scene=scene)
        assert_finite(result)
        if not write:
            pass
        elif out_dir is None:
            with tempfile.TemporaryDirectory(prefix="profilegen-fuzz-") as tmp:
                assert_files_finite(pg.write_design(result, Path(tmp) / "out", figure=figure))
        else:
            assert_files_finite(pg.write_design(result, Path(out_dir), figure=figure))
    except pg.ProfilegenError as exc:
        assert str(exc), "a named error must say what is wrong"
        return type(exc).__name__
    return "ok"


def assert_finite(result) -> None:
    """No NaN or infinity in anything the design holds: its JSON summary, the CS outline, the
    fitted profile, the tooth, the stage times, the stresses."""
    json.dumps(result.to_dict(), allow_nan=False)  # raises on NaN or inf
    assert np.isfinite(result.form.outline).all()
    assert np.isfinite(result.profile.space.sample(1e-3)).all()
    assert np.isfinite(result.tooth.outline(n_per_mm=200.0)).all()
    assert all(math.isfinite(s.time_s) and s.time_s >= 0 for s in result.stages)
    if result.stress is not None:
        json.dumps(result.stress.to_dict(), allow_nan=False)


_NON_FINITE = ("nan", "inf")


def assert_files_finite(paths) -> None:
    """Every written file exists and is non-empty; JSON files parse without NaN/Infinity and the
    CSV/DXF/SVG number fields hold no nan or inf."""
    assert paths, "write_design wrote no file"
    for path in map(Path, paths):
        assert path.is_file() and path.stat().st_size > 0, f"{path.name} missing or empty"
        if path.suffix == ".json":
            json.loads(path.read_text(), parse_constant=_refuse_constant)
        elif path.suffix in (".csv", ".dxf", ".svg"):
            words = path.read_text().lower().replace(",", " ").replace('"', " ").split()
            bad = [w for w in words if w.lstrip("+-") in _NON_FINITE]
            assert not bad, f"{path.name} holds {bad[0]!r}"


def _refuse_constant(name: str):
    raise AssertionError(f"JSON holds {name}")
