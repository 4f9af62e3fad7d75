"""The running design's stage cache, as the stages see it: where a long computation may stop
(:func:`checkpoint`) and torque-free work inside a stage kept between designs (:func:`reuse`).

:class:`profilegen.pipeline.engine.Engine` sets :data:`STAGE_CACHE` (a ContextVar, per thread) to its run
while it designs; a plain :func:`profilegen.design` call has none, so :func:`checkpoint` does
nothing and :func:`reuse` computes. This module imports nothing of the package, so every stage
may call it without an edge upward to the engine or the pipeline.
"""

from __future__ import annotations

import contextvars
import threading
from contextvars import ContextVar
from typing import Any, Callable

__all__ = ["STAGE_CACHE", "Beside", "checkpoint", "reuse"]

#: the stage cache :func:`profilegen.pipeline.design.design` looks each stage up in: the engine's run
#: (per thread); None — every plain design call — runs every stage. The cache keys each stage by
#: the gear-set fields and scene keys it reads and by its upstream stage's key
#: (profilegen.pipeline.engine.STAGE_INPUTS says which).
STAGE_CACHE: ContextVar = ContextVar("profilegen_stage_cache", default=None)


def checkpoint() -> None:
    """Where a long computation may stop: raises :class:`profilegen.pipeline.engine.Cancelled` when the
    engine design running in this thread was cancelled or superseded; nothing outside an engine's
    design (a few µs). A stage's own loop may call it (between face sections, FEM iterations, ...)
    for a quicker stop."""
    run = STAGE_CACHE.get()
    if run is not None:
        run.checkpoint()


def reuse(name: str, compute: Callable[[], Any], *, gearset: Any, sections: tuple[str, ...], key: tuple = (),
          owners: tuple = ()) -> Any:
    """``compute()``, or inside an engine's design its value from an earlier design of that engine
    with the same inputs: the gear-set ``sections`` (of ``GearSet.to_dict()``) ``compute`` reads, the
    plain values of ``key`` (compared by ``repr``) and the ``owners`` — objects it reads, compared by
    identity (the stage cache's results: the same object on a hit), which the entry keeps alive so
    an id cannot be reused while it lives. For work inside a stage that reads less than the stage:
    the contact stage's flanks (points and compliance) do not read the torques, so a torque change
    builds neither (:func:`profilegen.contact.analysis.flank`). Outside an engine: ``compute()``.
    Counted in the engine's ``runs`` and ``hits`` under ``name``; not a stage of ``last_run``."""
    run = STAGE_CACHE.get()
    if run is None:
        return compute()
    return run.reuse(name, compute, gearset, tuple(sections), tuple(key), tuple(owners))


class Beside:
    """``fn(*args)`` on a thread of its own, started at once, in a copy of the caller's context (so
    that its :func:`checkpoint` calls stop with the caller's design). For numpy-heavy work that can
    run beside the caller's (numpy lets go of the interpreter in its loops). :meth:`result` waits
    for it and returns its value or raises its error."""

    def __init__(self, fn: Callable[..., Any], *args: Any):
        self._value: Any = None
        self._error: BaseException | None = None
        context = contextvars.copy_context()

        def run() -> None:
            try:
                self._value = context.run(fn, *args)
            except BaseException as exc:  # noqa: BLE001 — handed to the caller at result()
                self._error = exc

        self._thread = threading.Thread(target=run, name=f"profilegen-beside-{getattr(fn, '__name__', 'call')}",
                                        daemon=True)
        self._thread.start()

    def result(self) -> Any:
        self._thread.join()
        if self._error is not None:
            raise self._error
        return self._value
