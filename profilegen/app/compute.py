"""The app's one way to compute a design: :func:`redesign`.

Every design the workbench shows goes through here: the process's shared engine
(:func:`profilegen.pipeline.engine.cached_design`), whose stage results are cached by the inputs they read,
so a torque change re-solves only the contact and the stresses, and every tab shares what the
others computed. The results are those of :func:`profilegen.design` (tests/unit/test_engine.py).
"""

from __future__ import annotations

from typing import Callable

from ..gearset import GearSet

__all__ = ["redesign"]


def redesign(gearset: GearSet, scene: str, *, progress: Callable[[str], None] | None = None,
             on_profile: Callable | None = None, on_stage: Callable | None = None,
             stop: Callable[[], bool] | None = None):
    """The design of ``gearset`` in ``scene`` (a :class:`profilegen.pipeline.design.Design`).

    ``progress`` is told each stage's name as it starts (it may raise to abandon the run: a
    newer request supersedes this one); ``on_profile`` gets the design once the CS profile is
    fitted, ``on_stage`` each partial design as the slower stages add to it; ``stop()`` is asked
    at every checkpoint of the engine (inside the stages' long loops too): True abandons the run
    (:class:`profilegen.pipeline.engine.Cancelled`) — a newer request of the tab superseded it."""
    from ..pipeline.engine import cached_design

    return cached_design(gearset, scene=scene, progress=progress, on_profile=on_profile, on_stage=on_stage, stop=stop)
