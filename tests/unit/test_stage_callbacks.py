"""design(on_stage=...): the stages hand their results over as they come (the envelope, the
contact with its stresses, then the torsional curve), and the design is the one computed without the callback
(the stresses solved early are the same numbers, reported after the contact as before)."""

from __future__ import annotations

import math

import profilegen as pg


def _timeless(x):
    """``x`` without the keys naming a time (and the durations inside notes)."""
    import re

    if isinstance(x, dict):
        return {k: _timeless(v) for k, v in x.items() if "time" not in k}
    if isinstance(x, list):
        return [_timeless(v) for v in x]
    if isinstance(x, str):
        return re.sub(r"\d+(\.\d+)? (ms|s)\b", "#", x)
    return x


def _same(a, b, where=""):
    if isinstance(a, dict):
        assert set(a) == set(b), where
        for k in a:
            _same(a[k], b[k], f"{where}/{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{where}[{i}]")
    elif isinstance(a, float) and isinstance(b, float):
        assert a == b or (math.isnan(a) and math.isnan(b)), where
    else:
        assert a == b, where


def test_load_stages_handed_over_as_they_come(default_gearset, default_sketch_contact):
    seen = []
    result = pg.design(default_gearset, scene="sketch", contact=True, on_stage=seen.append)
    assert [(p.form is not None, p.contact is not None, p.stress is not None, p.torsional is not None)
            for p in seen] == [(False, False, False, False), (True, True, True, False), (True, True, True, True)]
    assert seen[0].envelope is result.envelope and seen[0].rim is result.rim  # the envelope's figure from here
    assert seen[1].stress is seen[2].stress is result.stress  # solved once, early, and reported
    assert seen[2].torsional is result.torsional and seen[1].contact is result.contact
    assert [s.stage for s in result.stages] == [s.stage for s in default_sketch_contact.stages]  # contact, then stress
    assert result.warnings == default_sketch_contact.warnings
    _same(_timeless(result.to_dict()), _timeless(default_sketch_contact.to_dict()))
    _same(_timeless(result.stress.to_dict()), _timeless(default_sketch_contact.stress.to_dict()))
