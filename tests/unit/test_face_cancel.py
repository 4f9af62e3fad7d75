"""A superseded design stops inside the face stage, not only between stages
(issue 31: cancellation within 0.1 s wherever it is; the times are tests/benchmarks/face_cancel.py's).
No wall time here: the stage that was running when Cancelled came is what is checked."""

import pytest

import profilegen as pg
from profilegen.pipeline.engine import Cancelled, Engine


@pytest.mark.slow
def test_a_stop_asked_inside_the_face_stage_is_taken_there():
    inside = "face"  # (fails without the face stage's checkpoints: Cancelled came in the envelope stage)
    gs = pg.load_gearset("default")
    stage = ["start"]
    calls = {"n": 0}

    def stop() -> bool:  # True at the third checkpoint after the stage began
        if stage[0].startswith(inside):
            calls["n"] += 1
        return calls["n"] >= 3

    def progress(name: str) -> None:
        stage[0] = name

    with pytest.raises(Cancelled):
        Engine().design(gs, scene="design", progress=progress, stop=stop)
    assert stage[0].startswith(inside), f"stopped in {stage[0]!r}: the {inside} stage has no checkpoints of its own"
