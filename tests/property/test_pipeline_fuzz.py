"""Random gear sets through the whole pipeline (sketch scene, stress included) and into files:
every example ends in a result whose outputs — in memory and in the files ``write_design``
wrote — hold no NaN or infinity, or in a named ProfilegenError; never in another exception,
a MemoryError under a 4 GB address-space cap, or a run past its time limit.

Six strata (DCTA, involute and point-list teeth, valid — 20, 30, 20 examples — or with a
spoiled field — 90 each; every third result is written to files; sized to keep the suite near
5 minutes on 2 cores: every stratum and its property every run, the volume in the benchmark);
the gear sets span m
0.1–2 mm, z1 60–600, 2–4 waves, z2 − z1 = U or 2U, and the point lists include noisy,
crossing and looping ones. ``python tests/benchmarks/fuzz.py`` runs 10 000
and more, over the design and verify scenes as well. Fuzzing like this found two fit
failures, the stress stage's misreading of three-wave gears, and point lists that looped
into tens of GB. The strategies are in ``tests/property/gearsets.py``, the example runner in
``tests/property/fuzzrun.py``.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings

from tests.property.fuzzrun import memory_cap, outcome, time_limit
from tests.property.gearsets import gear_sets

#: examples per stratum: valid sets (~0.7-0.9 s CPU each where they reach a result, a third of
#: the results also written to files) and spoiled ones (almost all stop in validation, ~20 ms
#: each). The valid strata had 50/45/50 (120 s CPU, a third of the suite's budget); hypothesis's
#: later examples here mostly vary ones already tried, and the volume is tests/benchmarks/fuzz.py's
#: (10 000 examples, the design and verify scenes too). The involute stratum keeps its 45: most of
#: its sets now stop early at the EDM wire check (FilletError: circular_spline.wire_radius_mm, a
#: 0.145 mm fillet in small-module spaces), and its first 20 reached no result after the DCTA
#: stratum in one process (the "some example reaches a result" check failed; 45 reach some).
#: The points stratum has 20: with the wire, 3D-cup and face fields in the draws (2026-11-25) its
#: examples 21-25 reached results and took 22 s more; 15 reached none.
#: The involute stratum 45 -> 30 (2026-11-25, the suite's time): its examples 31-45 took 10-17 s
#: CPU (a third to a half of the stratum) and varied sets already drawn (in one run 11 results of
#: two sets, m 0.5 z1 260 and m 1 z1 498); in the two runs measured, alone and after the DCTA
#: stratum, the first result came at example 3 and 5, and 30 examples reached 5 and 9 results.
#: The involute stratum 30 -> 15 (2026-11-28, the suite's time): with the draws now the same in
#: every run (_same_draws_whatever_ran_before), its examples 16 and 17 are two sets with a 0.145 mm
#: wire in a module-0.4 space whose arc fit runs ~4400 SLP steps (and its retry) before the wire's
#: FilletError, 13 and 5 s; the first 15 reach 2 results and 3 kinds of named error in ~6 s.
#: (tests/benchmarks/fuzz.py keeps the volume: 2000 examples across the scenes.)
VALID = {"dcta": 20, "involute": 15, "points": 20}
SPOILED = 90
WRITE_EVERY = 3  # write the files of every third result (write_design costs about what the sketch design does)
TIME_LIMIT_S = 120.0  # per example; the slowest sketch example measured ~10 s on the busy machine

FUZZ = dict(deadline=None, derandomize=True, database=None,
            suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large])


def _same_draws_whatever_ran_before(monkeypatch):
    """Hypothesis mixes constants from the source of every local module already imported into its
    draws, so the examples of a derandomized run depended on what the xdist worker had run before
    (alone the involute stratum took 10 s; in the suite 30-35 s, drawing other sets). Without
    those constants the draws are the strategy's alone: the same sets in every run and order.
    (Internal names of hypothesis 6.13x; where they are gone the draws just stay order-dependent.)"""
    try:
        from hypothesis.internal.conjecture import providers
        from hypothesis.internal.constants_ast import Constants
    except ImportError:
        return
    if hasattr(providers, "_get_local_constants") and hasattr(getattr(providers, "CONSTANTS_CACHE", None), "max_size"):
        monkeypatch.setattr(providers, "_get_local_constants", Constants)
        monkeypatch.setattr(providers, "CONSTANTS_CACHE", type(providers.CONSTANTS_CACHE)(providers.CONSTANTS_CACHE.max_size))


@pytest.mark.parametrize("kind", sorted(VALID))
@pytest.mark.parametrize("spoil", [pytest.param(False, id="valid", marks=pytest.mark.slow),
                                   pytest.param(True, id="spoiled")])
def test_every_gear_set_gives_a_result_or_a_named_error(kind, spoil, tmp_path, monkeypatch):
    _same_draws_whatever_ran_before(monkeypatch)
    n = SPOILED if spoil else VALID[kind]
    seen: dict[str, int] = {}

    @settings(max_examples=n, **FUZZ)
    @given(gear_sets(kind=kind, spoil=spoil))
    def run(data):
        write = seen.get("ok", 0) % WRITE_EVERY == 0
        with time_limit(TIME_LIMIT_S):
            name = outcome(data, "sketch", tmp_path / "out" if write else None, write=write)
        seen[name] = seen.get(name, 0) + 1

    with memory_cap():
        run()
    assert sum(seen.values()) >= n
    if spoil:  # the validation named what was spoiled
        assert seen.get("GearSetError", 0) > n // 2, f"spoiled sets that passed validation: {seen}"
    else:
        assert seen.get("ok", 0) > 0, f"no example reached a result: {seen}"
