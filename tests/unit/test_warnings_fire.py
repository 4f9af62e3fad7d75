"""Every warning of the recently added contact modules reachable cheaply: a case that triggers
it and one that does not (issue 27 item 3: a removed warning escaped the suite). The cases are
built so that the condition the warning names holds or not by construction:

* ratchet._criterion (the linear diagnostics): the lowest torque already past the criterion;
  no separation at all (no ratcheting in the model); a separation that stops growing (the
  proportional bound); the criterion beyond the solved torques (extrapolated) — and a margin
  that crosses zero inside the torques (interpolated, no warning, the crossing where the
  straight line between the bracketing margins says);
* ratchet._climb: a climb that meets no criterion (the linear estimate kept, said so), a path
  that ends (said so), a limit point (neither);
* climb.climb on a hand model (one radial contact whose gap is G(s) − rφ): the torque cap
  reached with no criterion, no criterion within the steps allowed, the first rotation already
  past the margin — and the hand model's own limit point, which says none of these;
* face_load.solve_face: coning that closes slice gaps below zero (preloaded slices) — and
  identical slices, which do not; both balance the zone's torque (Σ F r = T/U in N·mm);
* ratcheting_torque with no catalogue value says the comparison is left out (with one:
  test_ratchet_ring.py).

Not reached here (each needs the face stage's 3D cup or a fitted design that misbehaves, too
slow for a unit test): face.stage (no section interference-free, the one CS profile interferes,
no tooth modification for a tooth kind), face.modification (still interfering, the LP failed,
no interference-free step), face_curve's two flanks overlapping, face_load.face_two_flanks'
logged fallback. rootfillet's two warnings are triggered in tests/unit/test_root_fillet.py.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from profilegen.contact import ratchet
from profilegen.contact.climb import climb
from research.dedoidal import TwoZoneClimb

T = np.array([100.0, 200.0, 300.0, 400.0])
OK = np.ones(4, bool)


def _crit(depth, sep):
    warnings = []
    out = ratchet._criterion(T, np.asarray(depth, float), np.asarray(sep, float), OK, warnings)
    return out, warnings


def test_criterion_inside_the_torques_is_interpolated_without_a_warning():
    (torque, extrapolated, *_), warnings = _crit([0.5] * 4, [0.1, 0.3, 0.6, 0.9])
    assert warnings == [] and not extrapolated
    assert torque == pytest.approx(200.0 + 0.2 / 0.3 * 100.0)  # margins 0.2 → −0.1 between 200 and 300 N·m


def test_criterion_met_at_the_lowest_torque_warns():
    (torque, extrapolated, *_), warnings = _crit([0.5] * 4, [0.6, 0.7, 0.8, 0.9])
    assert torque == 100.0 and not extrapolated
    assert len(warnings) == 1 and "lowest torque" in warnings[0]


def test_no_separation_predicts_no_ratcheting_and_says_so():
    (torque, extrapolated, *_), warnings = _crit([0.5] * 4, [0.0, -0.01, -0.02, 0.0])
    assert torque == math.inf and extrapolated
    assert len(warnings) == 1 and "predicts no ratcheting" in warnings[0]


def test_extrapolation_warns_and_a_falling_separation_warns_again():
    depth = [0.5] * 4
    (torque, extrapolated, p, fitted, prop), warnings = _crit(depth, [0.01, 0.02, 0.03, 0.04])  # Δr̄ ∝ T
    assert extrapolated and p == pytest.approx(1.0) and torque == pytest.approx(100.0 * 0.5 / 0.01)
    assert len(warnings) == 1 and "beyond the torques" in warnings[0]
    assert not any("does not grow" in w for w in warnings)
    (torque, extrapolated, p, fitted, prop), warnings = _crit(depth, [0.01, 0.04, 0.03, 0.02])  # falls at the end
    assert extrapolated and p < 0.0 and fitted is None
    assert torque == pytest.approx(min(t * 0.5 / s for t, s in zip(T, [0.01, 0.04, 0.03, 0.02])))
    assert any("does not grow" in w for w in warnings) and any("beyond the torques" in w for w in warnings)


@pytest.mark.parametrize("criterion, expect", [("none", "met no criterion"), ("end of path", "path ends"),
                                               ("limit point", None)])
def test_climb_outcome_warnings(monkeypatch, default_sketch, criterion, expect):
    from profilegen.contact import climb as climb_mod
    from profilegen.contact.inputs import ContactInput

    class Model:
        def __init__(self, inputs, **kw):
            self.n, self.teeth = 1, np.zeros(1)

        def first_rotation(self, torque):
            return 0.0, 1e-3

    def fake_climb(model, start, step, *, max_torque_nm):
        return SimpleNamespace(criterion=criterion, torque_nm=3000.0, phi_rad=1e-3, warnings=(),
                               column=lambda name: np.array([2000.0, 3000.0]))

    monkeypatch.setattr(climb_mod, "DesignClimb", Model)
    monkeypatch.setattr(climb_mod, "climb", fake_climb)
    inputs = ContactInput.from_design(default_sketch)
    warnings = []
    torque, _, info = ratchet._climb(inputs, inputs.gearset, side=1, bearing=None, cs_ring=False,
                                     race_thickness_mm=None, stations=3, max_gap_mm=0.1, linear=5000.0,
                                     max_torque_nm=None, ring_scale=1.0, extrapolated=False, warnings=warnings)
    assert torque == (5000.0 if criterion == "none" else 3000.0)  # no criterion: the linear estimate stays
    if expect is None:
        assert warnings == []
    else:
        assert len(warnings) == 1 and expect in warnings[0]


# --------------------------------------------------------------------------- climb() on a hand model

K, C0, R, SC = 1.0e4, 2.0e-5, 50.0, 0.02  # N/mm, mm/N, mm, mm (as tests/research/test_dedoidal.py)


class _Zone:
    """One radial contact (sin α = 1) whose gap is G(s) − rφ, G(s) = s − s²/(2 s_c)."""

    n = 1
    _ci = np.zeros(0, int)
    _a = _b = np.zeros(0)
    slot = np.array([0])
    corner = np.array([False])
    corner_criterion = False

    def __init__(self, depth_mm=10.0):
        self.sin_alpha = np.array([1.0])
        self.depth_mm = np.array([depth_mm])

    def geometry(self, s, phi=0.0):
        s = float(np.asarray(s)[0])
        return np.array([s - s * s / (2.0 * SC) - R * phi]), np.array([R])


def _hand(depth_mm=10.0):
    one = np.array([[1.0 / K + C0, 1.0 / K], [1.0 / K, 1.0 / K]])
    c = np.zeros((4, 4))
    c[:2, :2] = c[2:, 2:] = one
    dirs = np.array([[0.0, -1.0], [0.0, -1.0], [0.0, 1.0], [0.0, 1.0]])
    return TwoZoneClimb(_Zone(depth_mm), _Zone(depth_mm), c, dirs, wave_generator="held", cup_stiffness_n_per_mm=1.0)


OPTS = dict(max_retreat_step_mm=1e-3, tol_mm=1e-10, max_iterations=60)
T_STAR = 2.0 * R * K * SC * (1.0 + K * C0) / 1e3  # the hand model's largest torque (test_dedoidal)


def test_climb_limit_point_warns_of_nothing():
    path = climb(_hand(), 1e-5, 2e-5, max_steps=200, max_torque_nm=1e9, **OPTS)
    assert path.criterion in ("limit point", "end of path") and path.torque_nm <= T_STAR * (1 + 1e-9)
    assert not any(w.startswith(("the path stopped", "no criterion", "the first rotation")) for w in path.warnings)


def test_climb_torque_cap_warns():
    path = climb(_hand(), 1e-5, 2e-5, max_steps=200, max_torque_nm=0.2 * T_STAR, **OPTS)
    assert path.criterion == "none"
    assert any(w.startswith("the path stopped at") and "max_torque_nm" in w for w in path.warnings)
    assert any(w.startswith("no criterion was met") for w in path.warnings)
    assert path.torque_nm < 0.3 * T_STAR


def test_climb_out_of_steps_warns():
    path = climb(_hand(), 1e-5, 2e-5, max_steps=3, max_torque_nm=1e9, **OPTS)
    assert path.criterion == "none" and len(path.points) == 3
    assert any(w.startswith("no criterion was met") for w in path.warnings)
    assert not any(w.startswith("the path stopped at") for w in path.warnings)


def test_climb_margin_at_the_first_rotation_warns():
    """Corner depth 1 nm: the first point's retreat s = F/k is far beyond it (margin h − s < 0)."""
    path = climb(_hand(depth_mm=1e-6), 1e-5, 2e-5, max_steps=20, max_torque_nm=1e9, **OPTS)
    assert path.criterion == "margin"
    assert any("first rotation already meets the margin criterion" in w for w in path.warnings)
    deep = climb(_hand(), 1e-5, 2e-5, max_steps=3, max_torque_nm=1e9, **OPTS)
    assert not any("first rotation" in w for w in deep.warnings)


# --------------------------------------------------------------------------- face_load


def test_coning_that_closes_gaps_warns_and_both_balance_the_torque():
    from research.face_load import solve_face

    pts = SimpleNamespace(gap_mm=np.array([0.0, 2e-3, 5e-3]), lever_mm=np.array([50.0, 51.0, 52.0]),
                          tooth=np.array([0, 1, 2]), zones=2)
    s = np.diag([2e-5, 2e-5, 2e-5]) + 1e-6
    torque = 100.0
    flat = solve_face(pts, s, np.zeros((2, 3)), torque, face_width_mm=20.0)
    coned = solve_face(pts, s, np.array([[-3e-3, -3e-3, -3e-3], [1e-3, 1e-3, 1e-3]]), torque, face_width_mm=20.0)
    assert not any("coning closes" in w for w in flat.warnings)
    assert any("coning closes 2 of 6 slice gaps" in w for w in coned.warnings)
    for res in (flat, coned):
        assert float(np.sum(res.force_n * pts.lever_mm[None, :])) == pytest.approx(torque / 2 * 1000.0, rel=1e-9)
        assert res.force_n.min() >= 0.0


# --------------------------------------------------------------------------- ratcheting_torque


def test_ratcheting_without_a_catalogue_value_says_the_comparison_is_left_out(default_sketch):
    r = ratchet.ratcheting_torque(default_sketch, options=dict(torques_nm=[132.5, 265.0], stations=3, climb=False))
    assert r.catalogue is None and r.ratio_to_catalogue is None
    assert any("no catalogue ratcheting torque" in w for w in r.warnings)
