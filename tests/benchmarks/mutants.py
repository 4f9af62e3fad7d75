"""A mutation check of the suite (issue 27 item 4): plant each mutant of the list below, one at a
time, in a temporary copy of the repository, run only the tests that cover it there, and print
whether they caught it. Not collected by pytest (tests/benchmarks is ignored by addopts).

    python tests/benchmarks/mutants.py                 # every mutant, the table and the totals
    python tests/benchmarks/mutants.py --only NAME ... # some of them (names as --list prints)
    python tests/benchmarks/mutants.py --list          # the list: name, file, covering tests, why
    python tests/benchmarks/mutants.py --worktree      # the working tree's uncommitted files too

The copy is ``git archive HEAD`` (what is committed: the table names the commit), with
``--worktree`` overlaid by the working tree's modified and untracked files (others' work in
progress included: a baseline below catches a tree that is red on its own). Each mutant is one
exact snippet of a file replaced by another; a snippet that does not occur exactly once in the
copy is reported **stale** (the source moved on: update the mutant), never skipped silently.
For every set of covering tests the unmutated copy is run first (the **baseline**); a mutant
whose baseline is red is reported **baseline-red**, not caught. A mutant is **caught** when its
tests fail (or time out: a hang the suite would notice), **missed** when they pass.

Runs: ``python -m pytest -q -n 0 -x -p no:cacheprovider <tests>`` in the copy, PYTHONPATH at the
copy (so ``import profilegen`` and the ``profilegen`` command's interpreter load the copy, not
the editable install), at nice +10, address space capped (``--memory-gb``, default 4) and a
timeout per run (``--timeout``, default 600 s). Keep the list growing with each new module: a
mutant per planted-bug kind of the issue (a unit constant, a catalogue cell, an endpoint counted
twice, swapped section dimensions, a removed warning, a removed fsync, a checksum, an untested
branch) in every module added.

RESULTS (2026-11-28, 10:40-10:53 UTC, on the 2-core machine shared by ~6 sessions, load 6-11):
``nice -n 10 python tests/benchmarks/mutants.py`` at b303f7a, then ``--only sweep-journal-no-checksum
sweep-reruns-journal-points sweep-int-sample-endpoint`` at 09045ab (test_sweep was red at b303f7a
on its own: baseline-red there, green again at 09045ab). Caught 50 of 54 (92.6 %),
missed 4, stale 0; with figures-interrupt-waits, added after and run alone, 51 of 55 (92.7 %). (The first run, at e36a966 with 53 mutants, caught 46 (86.8 %); its escapes
contact-torque-in-nm, face-section-endpoint and optimize-max-not-negated got tests:
test_unit_constants.py, test_sampling_grids.py, test_optimize_senses.py.)

    mutant                             file                       result
    arcsec-is-arcmin                   contact/transmission.py    caught
    chain-arcmin-is-arcsec             contact/chain.py           caught
    analysis-arcmin-degrees            contact/analysis.py        caught
    loadzone-arcmin                    research/loadzone.py       caught
    contact-torque-in-nm               contact/analysis.py        caught
    contact-stage-torque-in-nm         contact/analysis.py        caught
    face-load-torque-one-zone          research/face_load.py      caught
    climb-torque-unit                  contact/climb.py           caught
    te-endpoint-twice                  contact/transmission.py    caught
    te-shift-ratio                     contact/transmission.py    caught
    climb-positions-endpoint           contact/ratchet.py         caught
    face-slices-left-ends              research/face_load.py      caught
    face-curve-ends-weight             contact/face_curve.py      caught
    balls-endpoint-twice               research/bearing_clearance.py caught
    ratchet-climb-section-swapped      contact/ratchet.py         caught
    ratchet-linear-section-swapped     contact/ratchet.py         caught
    ratchet-section-return-swapped     contact/ratchet.py         caught
    ring-inertia-swapped               contact/ratchet.py         caught
    ring-hoop-term                     contact/ratchet.py         caught
    csring-inertia-swapped             tests/oracles/cs_ring.py   caught
    ratchet-positions-max              contact/ratchet.py         caught
    ratchet-interpolation              contact/ratchet.py         caught
    ratchet-no-end-of-path-warning     contact/ratchet.py         caught
    ratchet-no-catalogue-warning       contact/ratchet.py         caught
    ratchet-no-growth-warning          contact/ratchet.py         caught
    climb-no-cap-warning               contact/climb.py           caught
    climb-no-first-rotation-warning    contact/climb.py           caught
    dedoidal-eccentricity-ignored      research/dedoidal.py       caught
    face-load-no-coning-warning        research/face_load.py      caught
    cup-bore-load-endpoint             rim/cup/fourier.py         caught
    cup-nonlinear-samples-endpoint     rim/cup/nonlinear.py       caught
    cup-contact-orders                 rim/cup/contact.py         caught
    cup-wall-layers                    rim/cup/geometry.py        caught
    face-parabola-sign                 face/clearance.py          caught
    face-engaged-strict                face/clearance.py          caught
    face-section-endpoint              face/sections.py           caught
    fillet-no-kept-sharp-warning       rootfillet.py              caught
    fillet-no-shrink-warning           rootfillet.py              caught
    fillet-wrong-side                  rootfillet.py              caught
    step-half-revolution               output/step.py             caught
    step-open-chain-accepted           output/step.py             caught
    step-wall-check                    output/step.py             caught
    drawing-diameter-is-radius         output/drawing.py          caught
    drawing-projection                 output/drawing.py          caught
    drawing-pair-label                 output/drawing.py          caught
    optimize-violation-sign            optimize/search.py         caught
    optimize-max-not-negated           optimize/search.py         caught
    optimize-equal-rows-last           optimize/search.py         caught
    sweep-journal-no-checksum          sweep.py                   MISSED (09045ab); caught at ba6e318
    sweep-reruns-journal-points        sweep.py                   caught (09045ab)
    sweep-int-sample-endpoint          sweep.py                   caught (09045ab)
    folder-no-parent-fsync             output/folder.py           MISSED; caught at ba6e318
    folder-fsync-dir-noop              output/folder.py           MISSED; caught at ba6e318
    folder-no-restore                  output/folder.py           MISSED; caught at ba6e318
    figures-interrupt-waits            output/report.py           caught (added after: --only, at 09045ab)

The four escapes are all in the output folder's swap and the sweep journal, whose fault-injection
tests (the parent fsync, the journal checksum) another engineer writes with the rewrite of
output/folder.py and the journal this session: none is an equivalent mutant — an fsync removed
is invisible to a test unless the test counts the calls or cuts the power (fault injection), the
checksum unchecked passes until a test feeds a line whose CRC is wrong, and the two-rename
swap's restore (no renameat2, the second rename failing) is a branch no test reaches. Rerun
``--only folder-no-parent-fsync folder-fsync-dir-noop folder-no-restore sweep-journal-no-checksum``
once those tests land.

They landed (tests/unit/test_output_owner.py: the parent fsync counted after the swap, a journal
line with a wrong CRC recomputed, the second rename made to fail): at ba6e318 (2026-11-28), with
test_output_owner.py added to those four mutants' covering tests, ``--only`` the four: caught 4 of
4. With the 51 of the full run above: 55 of 55 caught (100 %), 0 stale.

RESULTS with the modules added since (2026-11-28 13:04-14:10 UTC, load 14-21): 40 mutants more —
profilegen new (catalogue_set.py), the [requirements] fields, the verdict (pipeline.py's _judge,
Verdict.status, _ratcheting_check), the design scene's rim (face/coning.py rim_tier_for), the
output folder's owner rule, the memory check (budget.py), user paths (userpaths.py) and the face
stage's warnings. ``python tests/benchmarks/mutants.py --timeout 900`` at 2d3156e: caught 87 of 95
(91.6 %), missed 8, stale 0; the 55 above all caught again. The 8 escapes, none equivalent, each
got a test and was caught by it (``--only`` at 0fc1713 / 3049769-: 5 of 5, 1 of 1, 3 of 3), so 95 of
95:

    mutant                             file                       result
    new-pitch-diameter-rule            catalogue_set.py           caught
    new-momentary-ratio                catalogue_set.py           caught
    new-rim-rule                       catalogue_set.py           caught
    new-wire-gap-boundary              catalogue_set.py           MISSED -> test_catalogue_set_rules.py
    new-csg-factor-ignored             catalogue_set.py           caught
    new-ratio-range-endpoint           catalogue_set.py           MISSED -> test_catalogue_set_rules.py
    require-safety-range-open          gearset/requirements.py    caught
    require-fatigue-group              gearset/requirements.py    caught
    verdict-judge-boundary             pipeline.py                MISSED -> test_verdict_rules.py
    verdict-judge-max-sense            pipeline.py                MISSED -> test_verdict_rules.py
    verdict-ratcheting-no-ratio        pipeline.py                caught
    verdict-ratcheting-end-of-path     pipeline.py                caught
    verdict-face-unmodified-depth      pipeline.py                MISSED -> test_verdict_rules.py
    verdict-never-incomplete           pipeline.py                caught
    verdict-momentary-fallback         pipeline.py                caught
    coning-any-waves                   face/coning.py             caught
    coning-ring-fem-label              face/coning.py             caught
    coning-design-cup-mesh             face/coning.py             caught
    folder-marker-listing-unchecked    output/folder.py           caught
    folder-marker-lists-anything       output/folder.py           caught
    folder-link-is-regular             output/folder.py           caught
    folder-lock-follows-link           output/folder.py           caught (timeout: 900 s, a hang)
    budget-retrace-ignored             budget.py                  caught
    budget-whole-memory                budget.py                  caught
    budget-grid-advice-swapped         budget.py                  MISSED -> test_budget.py (unequal grid)
    budget-mebibyte                    budget.py                  caught
    budget-outline-one-tooth           budget.py                  caught
    userpaths-no-staging-room          userpaths.py               MISSED -> test_userpaths.py
    userpaths-relative-length          userpaths.py               MISSED -> test_userpaths.py
    userpaths-echoes-problems          userpaths.py               caught
    face-no-free-section-warning       face/stage.py              caught
    face-one-cs-warning                face/stage.py              caught
    face-one-cs-warning-always         face/stage.py              caught
    face-no-thickness-field-warning    face/stage.py              caught
    modification-still-interferes-warning face/modification.py   caught
    modification-lp-failed-warning     face/modification.py       caught
    modification-still-interfering-warning face/modification.py   caught
    modification-search-found-warning  face/modification.py       caught
    face-curve-overlap-warning         contact/face_curve.py      caught
    face-curve-overlap-threshold       contact/face_curve.py      caught

The escapes were boundaries no test stood on (the 0.1 mm wire's gap, ratio 30, a value exactly at
its requirement, a maximum checked as a minimum), a face check fed only designs whose modified and
unmodified depths agree, an advice tested only on a square grid, and the output path's limits
tested only far beyond them. folder-lock-follows-link is caught only by the timeout: with the lock
opened through the planted link the owner test blocks instead of failing (a hang the suite would
notice, slowly).
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


@dataclass(frozen=True)
class Mutant:
    name: str
    file: str
    original: str
    replacement: str
    tests: tuple[str, ...]
    why: str


U = "tests/unit/"

MUTANTS: tuple[Mutant, ...] = (
    # ------------------------------------------------------------------ contact: unit constants
    Mutant("arcsec-is-arcmin", "profilegen/contact/transmission.py",
           "ARCSEC_PER_RAD = 180.0 * 3600.0 / math.pi", "ARCSEC_PER_RAD = 180.0 * 60.0 / math.pi",
           (U + "test_unit_constants.py", U + "test_sampling_grids.py"),
           "unit constant: the transmission error in arcmin labelled arcsec (the issue's planted kind)"),
    Mutant("chain-arcmin-is-arcsec", "profilegen/contact/chain.py",
           "ARCMIN_PER_RAD = 180.0 * 60.0 / math.pi", "ARCMIN_PER_RAD = 180.0 * 3600.0 / math.pi",
           (U + "test_unit_constants.py",), "unit constant: the torsional curve's arcmin off by 60"),
    Mutant("analysis-arcmin-degrees", "profilegen/contact/analysis.py",
           "ARCMIN_PER_RAD = 180.0 * 60.0 / math.pi", "ARCMIN_PER_RAD = 180.0 / math.pi",
           (U + "test_unit_constants.py",), "unit constant: load-case rotations in degrees labelled arcmin"),
    Mutant("loadzone-arcmin", "research/loadzone.py",
           "ARCMIN_PER_RAD = 180.0 * 60.0 / math.pi", "ARCMIN_PER_RAD = 180.0 * 60.0 / 3.1416",
           ("tests/research/test_loadzone.py",), "unit constant: a rounded π (1e-5 relative)"),
    Mutant("contact-torque-in-nm", "profilegen/contact/analysis.py",
           "sol = _SOLVERS[solver](s, points.theta_rad, points.lever_mm, torque / points.zones * 1e3)",
           "sol = _SOLVERS[solver](s, points.theta_rad, points.lever_mm, torque / points.zones)",
           (U + "test_unit_constants.py",), "unit: N·m handed to a solver that balances N·mm"),
    Mutant("contact-stage-torque-in-nm", "profilegen/contact/analysis.py",
           "    torque_nmm = torque_nm / points.zones * 1e3\n    if solver == \"lemke\":",
           "    torque_nmm = torque_nm / points.zones\n    if solver == \"lemke\":",
           (U + "test_unit_constants.py",), "unit: N·m in the contact stage's every-ball solve (N·mm)"),
    Mutant("face-load-torque-one-zone", "research/face_load.py",
           "    tz = torque / points.zones * 1e3\n    theta = (e[None, :] + de) / r[None, :]",
           "    tz = torque * 1e3\n    theta = (e[None, :] + de) / r[None, :]",
           (U + "test_warnings_fire.py", "tests/research/test_face_load.py"), "the zone's torque is T/U, not T"),
    Mutant("climb-torque-unit", "profilegen/contact/climb.py",
           "torque = model.zones * float(f @ lever) / 1000.0", "torque = model.zones * float(f @ lever) / 100.0",
           (U + "test_warnings_fire.py", U + "test_ratchet_ring.py"), "unit: the climb's N·mm → N·m off by 10"),
    # ------------------------------------------------------------------ contact: sampling grids
    Mutant("te-endpoint-twice", "profilegen/contact/transmission.py",
           "return passage * np.arange(positions) / positions",
           "return passage * np.arange(positions) / (positions - 1)",
           (U + "test_sampling_grids.py",), "endpoint counted twice: ψ = 2π/z2 is ψ = 0 again"),
    Mutant("te-shift-ratio", "profilegen/contact/transmission.py",
           "shift_rad=-psi * g.circular_spline_teeth / g.flexspline_teeth,",
           "shift_rad=-psi * g.flexspline_teeth / g.circular_spline_teeth,",
           (U + "test_sampling_grids.py",), "the teeth's shift δ = −ψ z2/z1 with the ratio inverted"),
    Mutant("climb-positions-endpoint", "profilegen/contact/ratchet.py",
           "shifts = [shift_rad - k * passage / positions for k in range(positions)]",
           "shifts = [shift_rad - k * passage / max(positions - 1, 1) for k in range(positions)]",
           (U + "test_sampling_grids.py",), "endpoint counted twice: the last position is the first"),
    Mutant("face-slices-left-ends", "research/face_load.py",
           "return z0 - 0.5 * b + (np.arange(n) + 0.5) * b / n", "return z0 - 0.5 * b + np.arange(n) * b / n",
           (U + "test_sampling_grids.py", "tests/research/test_face_load.py"), "slices at their left edges, not mid-planes"),
    Mutant("face-curve-ends-weight", "profilegen/contact/face_curve.py",
           "w[[0, -1]] = 0.5 * h", "w[[0, -1]] = h",
           (U + "test_sampling_grids.py", U + "test_face_curve.py"), "trapezoid's end nodes counted whole: Σw > b"),
    Mutant("balls-endpoint-twice", "research/bearing_clearance.py",
           "psi = float(phase_rad) + 2.0 * math.pi * np.arange(z) / z",
           "psi = float(phase_rad) + 2.0 * math.pi * np.arange(z) / (z - 1)",
           (U + "test_sampling_grids.py",), "endpoint counted twice: the last ball on the first"),
    # ------------------------------------------------------------------ ratcheting
    Mutant("ratchet-climb-section-swapped", "profilegen/contact/ratchet.py",
           "return cs_ring_radial_compliance(ang, phis, mean_radius_mm=r_mean, thickness_mm=thick, width_mm=width,",
           "return cs_ring_radial_compliance(ang, phis, mean_radius_mm=r_mean, thickness_mm=width, width_mm=thick,",
           (U + "test_ratchet_ring.py",), "the issue's planted swap: +55 % on the estimate, 81 tests passed"),
    Mutant("ratchet-linear-section-swapped", "profilegen/contact/ratchet.py",
           "ring = cs_ring_radial_compliance(ang, phis, mean_radius_mm=r_mean, thickness_mm=thick, width_mm=width,",
           "ring = cs_ring_radial_compliance(ang, phis, mean_radius_mm=r_mean, thickness_mm=width, width_mm=thick,",
           (U + "test_ratchet_ring.py",), "swapped section in the linear diagnostics"),
    Mutant("ratchet-section-return-swapped", "profilegen/contact/cs_ring.py",
           "return cls(0.5 * (r_root + r_out), r_out - r_root, width,",
           "return cls(0.5 * (r_root + r_out), width, r_out - r_root,",
           (U + "test_ratchet_ring.py",), "swapped section where it is measured"),
    Mutant("ring-inertia-swapped", "profilegen/contact/cs_ring.py",
           "return self.width_mm * self.thickness_mm ** 3 / 12.0", "return self.thickness_mm * self.width_mm ** 3 / 12.0",
           (U + "test_ratchet_ring.py",), "I = b h³/12 with b and h swapped"),
    Mutant("ring-hoop-term", "profilegen/contact/cs_ring.py",
           "r / (2.0 * math.pi * e * ring.area_mm2)", "r / (math.pi * e * ring.area_mm2)",
           (U + "test_ratchet_ring.py",), "the n = 0 (hoop) term doubled"),
    Mutant("csring-inertia-swapped", "tests/oracles/cs_ring.py",
           "return self.width_mm * self.thickness_mm ** 3 / 12.0",
           "return self.thickness_mm * self.width_mm ** 3 / 12.0",
           (U + "test_ratchet_ring.py",), "swapped section in the CS ring module"),
    Mutant("ratchet-positions-max", "profilegen/contact/ratchet.py",
           "path, model, shift_rad = min(ok or runs,", "path, model, shift_rad = max(ok or runs,",
           (U + "test_sampling_grids.py",), "the running gear meets every position: the minimum, not the maximum"),
    Mutant("ratchet-interpolation", "profilegen/contact/ratchet.py",
           "return float(t[k - 1] + m0 / (m0 - m1) * (t[k] - t[k - 1])), False, None, None, None",
           "return float(t[k - 1] + m1 / (m0 - m1) * (t[k] - t[k - 1])), False, None, None, None",
           (U + "test_warnings_fire.py",), "the margin's zero interpolated from the wrong end"),
    Mutant("ratchet-no-end-of-path-warning", "profilegen/contact/ratchet.py",
           '    if path.criterion == "end of path":\n        warnings.append(',
           '    if False:\n        warnings.append(',
           (U + "test_warnings_fire.py",), "a removed warning (the path's end taken as the estimate)"),
    Mutant("ratchet-no-catalogue-warning", "profilegen/contact/ratchet.py",
           'warnings.append("no catalogue ratcheting torque with a source: the comparison is left out")',
           'pass',
           (U + "test_warnings_fire.py",), "a removed warning"),
    Mutant("ratchet-no-growth-warning", "profilegen/contact/ratchet.py",
           "if p is None or p <= 0.0:", "if p is None:",
           (U + "test_warnings_fire.py",), "a removed warning (Δr̄ falling: the proportional bound)"),
    Mutant("climb-no-cap-warning", "profilegen/contact/climb.py",
           'warnings.append(f"the path stopped at {p.torque_nm:.4g}',
           'print(f"the path stopped at {p.torque_nm:.4g}',
           (U + "test_warnings_fire.py",), "a removed warning (the torque cap reached)"),
    Mutant("climb-no-first-rotation-warning", "profilegen/contact/climb.py",
           'warnings.append(f"the first rotation already meets the {crit} criterion")', "pass",
           (U + "test_warnings_fire.py",), "a removed warning"),
    Mutant("dedoidal-eccentricity-ignored", "research/dedoidal.py",
           "        self._rest[:2] = ecc * np.array(", "        self._rest[:2] = 0.0 * np.array(",
           ("tests/research/test_dedoidal.py::test_eccentricity_is_the_cup_springs_load",),
           "the eccentricity dropped (the old test compared two runs that could not differ)"),
    Mutant("face-load-no-coning-warning", "research/face_load.py",
           "if np.any(theta < 0.0):", "if np.any(theta < -1.0):",
           (U + "test_warnings_fire.py", "tests/research/test_face_load.py"), "a removed warning (preloaded slices)"),
    # ------------------------------------------------------------------ cup (profilegen/rim/cup)
    Mutant("cup-bore-load-endpoint", "profilegen/rim/cup/fourier.py",
           "    phi = 2.0 * math.pi * np.arange(samples) / samples\n    values = np.asarray(contour.radius(phi)",
           "    phi = 2.0 * math.pi * np.arange(samples) / (samples - 1)\n    values = np.asarray(contour.radius(phi)",
           (U + "test_cup3d.py",), "endpoint counted twice in the cam's cosine series"),
    Mutant("cup-nonlinear-samples-endpoint", "profilegen/rim/cup/nonlinear.py",
           "phi = 2.0 * math.pi * np.arange(self.samples) / self.samples",
           "phi = 2.0 * math.pi * np.arange(self.samples) / (self.samples - 1)",
           (U + "test_cup_contact.py",), "endpoint counted twice in the trapezoid rule's samples"),
    Mutant("cup-contact-orders", "profilegen/rim/cup/contact.py",
           "orders = 2 * np.arange(angles)", "orders = 2 * np.arange(angles - 1)",
           (U + "test_cup_contact.py",), "one harmonic fewer than contact angles"),
    Mutant("cup-wall-layers", "profilegen/rim/cup/geometry.py",
           "r_wall = np.linspace(r_in, r_out, layers + 1)", "r_wall = np.linspace(r_in, 0.5 * (r_in + r_out), layers + 1)",
           (U + "test_cup3d.py",), "the wall meshed half as thick"),
    # ------------------------------------------------------------------ face (profilegen/face)
    Mutant("face-parabola-sign", "profilegen/face/clearance.py",
           "return float(c[i] - b * b / (4 * a)), float(phi[i] + x * h)",
           "return float(c[i] + b * b / (4 * a)), float(phi[i] + x * h)",
           (U + "test_face.py",), "the refined minimum above the sample"),
    Mutant("face-engaged-strict", "profilegen/face/clearance.py",
           "return np.asarray(clearance_mm) <= ENGAGED_MM", "return np.asarray(clearance_mm) <= 0.0",
           (U + "test_face.py",), "the engaged zone without its tolerance"),
    Mutant("face-section-endpoint", "profilegen/face/sections.py",
           "phi = period * np.arange(samples) / samples", "phi = period * np.arange(samples) / (samples - 1)",
           (U + "test_sampling_grids.py", U + "test_face.py"),
           "endpoint counted twice in a section's Fourier fit samples (missed on the first run: test added)"),
    # ------------------------------------------------------------------ fillet (rootfillet)
    Mutant("fillet-no-kept-sharp-warning", "profilegen/profile/rootfillet.py",
           "            log.warning(msg)\n            warnings.append(msg)\n    done = [d for d in done",
           "            log.warning(msg)\n    done = [d for d in done",
           (U + "test_root_fillet.py",), "a removed warning (a kink kept sharp)"),
    Mutant("fillet-no-shrink-warning", "profilegen/profile/rootfillet.py",
           "elif arc.radius < radius_mm * (1 - 1e-12):", "elif arc.radius < 0.0:",
           (U + "test_root_fillet.py",), "a removed warning (the tip round shrunk)"),
    Mutant("fillet-wrong-side", "profilegen/profile/rootfillet.py",
           "side = math.copysign(1.0, _cross(ta, tb))", "side = -math.copysign(1.0, _cross(ta, tb))",
           (U + "test_root_fillet.py",), "the fillet on the outside of the turn"),
    # ------------------------------------------------------------------ STEP (output/step.py)
    Mutant("step-half-revolution", "profilegen/output/step.py",
           "BRepPrimAPI_MakeRevol(face, axis, 2.0 * math.pi)", "BRepPrimAPI_MakeRevol(face, axis, math.pi)",
           (U + "test_step.py",), "the FS cup revolved half a turn"),
    Mutant("step-open-chain-accepted", "profilegen/output/step.py",
           "if gap.max() > _CLOSE_TOL_MM:", "if gap.max() > 1e9:",
           (U + "test_step.py",), "an untested branch? an open chain accepted"),
    Mutant("step-wall-check", "profilegen/output/step.py",
           "if not d_out >= 2.0 * (r_max + wall):", "if not d_out >= 2.0 * r_max:",
           (U + "test_step.py",), "the CS's minimum wall not checked (only the root circle)"),
    # ------------------------------------------------------------------ drawing (output/drawing.py)
    Mutant("drawing-diameter-is-radius", "profilegen/output/drawing.py",
           'text=f"%%c{_fmt(2.0 * r)}{note}"', 'text=f"%%c{_fmt(r)}{note}"',
           (U + "test_drawing.py",), "a diameter labelled with its radius"),
    Mutant("drawing-projection", "profilegen/output/drawing.py",
           '(1, 100, 180, "PROJECTION", "first angle"),', '(1, 100, 180, "PROJECTION", "third angle"),',
           (U + "test_drawing.py",), "the title block's projection"),
    Mutant("drawing-pair-label", "profilegen/output/drawing.py",
           'text = ("2x " if len(g) == 2 else "")', 'text = ("" if len(g) == 2 else "")',
           (U + "test_drawing.py",), "a mirrored pair of arcs dimensioned as one"),
    # ------------------------------------------------------------------ optimize
    Mutant("optimize-violation-sign", "profilegen/studies/optimize/search.py",
           "v = max(v, self.lo - value)", "v = max(v, value - self.lo)",
           (U + "test_optimize_senses.py", U + "test_optimize.py"), "a lower bound's violation with the sign flipped"),
    Mutant("optimize-max-not-negated", "profilegen/studies/optimize/search.py",
           'return 1.0 if self.sense == "min" else -1.0', "return 1.0",
           (U + "test_optimize_senses.py", U + "test_optimize.py"),
           "a max objective minimised (missed on the first run: no test had a max objective; test added)"),
    Mutant("optimize-equal-rows-last", "profilegen/studies/optimize/search.py",
           "earlier_equal = np.triu(equal, k=1).any(axis=0)", "earlier_equal = np.tril(equal, k=-1).any(axis=0)",
           (U + "test_optimize.py",), "of equal rows the last kept, not the first"),
    # ------------------------------------------------------------------ sweep
    Mutant("sweep-journal-no-checksum", "profilegen/studies/sweep.py",
           'if f"{zlib.crc32(chr(31).join(texts).encode()):08x}" != rec[-1]:', "if False:",
           (U + "test_sweep.py", U + "test_output_folder.py", U + "test_output_owner.py"),
           "the journal's checksum not checked on reading"),
    Mutant("sweep-reruns-journal-points", "profilegen/studies/sweep.py",
           "if pid not in done and pid not in todo:", "if pid not in todo:",
           (U + "test_sweep.py",), "points in the journal run again"),
    Mutant("sweep-int-sample-endpoint", "profilegen/studies/sweep.py",
           "point[f] = int(min(lo + math.floor(x * (hi - lo + 1)), hi))",
           "point[f] = int(min(lo + math.floor(x * (hi - lo)), hi))",
           (U + "test_sweep.py",), "an integer field's upper bound never drawn"),
    # ------------------------------------------------------------------ output folder
    Mutant("folder-no-parent-fsync", "profilegen/output/folder.py",
           "            _fsync_dir(self.out.parent)\n", "            pass\n",
           (U + "test_output_folder.py", U + "test_output_owner.py"), "the parent folder's fsync after the swap removed (the issue's kind)"),
    Mutant("folder-fsync-dir-noop", "profilegen/output/folder.py",
           "                os.fsync(fd)\n", "                pass\n",
           (U + "test_output_folder.py", U + "test_output_owner.py"), "_fsync_dir opens the folder but syncs nothing"),
    Mutant("folder-no-restore", "profilegen/output/folder.py",
           "        os.rename(parked, out)\n        raise", "        raise",
           (U + "test_output_folder.py", U + "test_output_owner.py"), "a failed two-rename swap leaves the old set parked"),
    # ------------------------------------------------------------------ figure workers (the timed test made a behaviour test)
    Mutant("figures-interrupt-waits", "profilegen/output/report.py",
           "self.close(error=kind is not None)", "self.close(error=False)",
           (U + "test_report_speed.py::test_an_interrupted_block_ends_its_workers",),
           "an interrupted block waits for its running figures (the test asserted < 30 s before; now the end marks)"),
    # ------------------------------------------------------------------ profilegen new (catalogue_set.py)
    Mutant("new-pitch-diameter-rule", "profilegen/gearset/new.py",
           "PITCH_DIAMETER_PER_SIZE_MM = 2.54", "PITCH_DIAMETER_PER_SIZE_MM = 2.4",
           (U + "test_catalogue_set.py",), "a unit constant: the size in tenths of an inch (2.54 mm) read as 2.4 mm"),
    Mutant("new-momentary-ratio", "profilegen/gearset/new.py",
           "MOMENTARY_PER_RATED = 304.0 / 67.0", "MOMENTARY_PER_RATED = 304.0 / 76.0",
           (U + "test_catalogue_set.py",), "a catalogue cell transcribed with its digits swapped (67 -> 76)"),
    Mutant("new-rim-rule", "profilegen/gearset/new.py",
           "(1.0 + frac / 2.0)", "(1.0 + frac)",
           (U + "test_catalogue_set.py",), "the rim solved from r_m = d/2 - dedendum - delta (not delta/2)"),
    Mutant("climb-first-fall-ends-path", "profilegen/contact/climb.py",
           "limit_drop: float = 0.01, limit_span: float = 0.1) -> ClimbPath:",
           "limit_drop: float = 0.01, limit_span: float = 0.0) -> ClimbPath:",
           (U + "test_ratchet.py",), "a fall of T that T climbs back out of taken for the limit point"),
    Mutant("climb-first-rotation-not-retried", "profilegen/contact/climb.py",
           "if halvings < max_halvings:  # a shorter step from the last point (or toward the start's own)",
           "if pts and halvings < max_halvings:",
           (U + "test_ratchet.py",), "a first rotation with no fixed point ends the path with no point"),
    Mutant("climb-gap-absolute", "profilegen/contact/ratchet.py",
           "max_gap_mm = CLIMB_GAP_PER_MODULE * float(gs.gear.module_mm)", "max_gap_mm = 0.15",
           (U + "test_climb_similarity.py",), "the climb's teeth cut at an absolute gap: similar gears climb on different teeth"),
    Mutant("climb-reach-unsaid", "profilegen/contact/ratchet.py",
           "if reach >= max_gap_mm:", "if reach >= 9e9:",
           (U + "test_climb_similarity.py",), "a path that turns its stations beyond the teeth's cut, unsaid"),
    Mutant("face-touch-refined", "profilegen/face/clearance.py",
           "if 0 < i < c.size - 1 and c[i] < -TOUCH_MM:", "if 0 < i < c.size - 1:",
           (U + "test_face.py",), "a touching minimum refined by a parabola through the kink"),
    Mutant("new-low-ratio-rule-lost", "profilegen/gearset/new.py",
           "f = min(1.0, max(0.0, (FULL_RATIO - ratio) / (FULL_RATIO - LOW_RATIO)))",
           "f = min(1.0, max(0.0, (FULL_RATIO - ratio) / (FULL_RATIO - 30)))",
           (U + "test_catalogue_set.py",), "the low-ratio ramp ending at ratio 30, not 50"),
    Mutant("new-wire-gap-boundary", "profilegen/gearset/new.py",
           "gap = 0.02 if diameter >= 0.1 else 0.01", "gap = 0.02 if diameter > 0.1 else 0.01",
           (U + "test_catalogue_set.py", U + "test_catalogue_set_rules.py"), "the 0.1 mm wire's spark gap on the wrong side of the boundary"),
    Mutant("new-csg-factor-ignored", "profilegen/gearset/new.py",
           'factor = CSG_TORQUE_FACTOR if series == "csg" else 1.0', "factor = 1.0",
           (U + "test_catalogue_set.py",), "the CSG's 30 % torque increase left out"),
    Mutant("new-ratio-range-endpoint", "profilegen/gearset/new.py",
           "if not RATIO_RANGE[0] <= ratio <= RATIO_RANGE[1]:", "if not RATIO_RANGE[0] < ratio <= RATIO_RANGE[1]:",
           (U + "test_catalogue_set.py", U + "test_catalogue_set_rules.py"), "ratio 30, the range's lower end, refused"),
    # ------------------------------------------------------------------ requirements (gearset/requirements.py)
    Mutant("require-safety-range-open", "profilegen/gearset/requirements.py",
           "_SAFETY_RANGE: dict[str, Any] = dict(lo=1.0, hi=10.0, lo_open=False)",
           "_SAFETY_RANGE: dict[str, Any] = dict(lo=1.0, hi=10.0, lo_open=True)",
           (U + "test_verdict.py",), "a required safety of exactly 1 refused (the range's closed end)"),
    Mutant("require-fatigue-group", "profilegen/gearset/requirements.py",
           '"fatigue_safety": tuple(f.key for f in REQUIREMENT_FIELDS if f.key.endswith("_fatigue_safety")),',
           '"fatigue_safety": tuple(f.key for f in REQUIREMENT_FIELDS if f.key.endswith("_safety")),',
           (U + "test_verdict.py",), "--require fatigue_safety=X sets the yield safeties too"),
    # ------------------------------------------------------------------ the verdict (pipeline.py, read-only there)
    Mutant("verdict-judge-boundary", "profilegen/pipeline/design.py",
           'ok = value >= required if sense == ">=" else value <= required',
           'ok = value > required if sense == ">=" else value <= required',
           (U + "test_verdict.py", U + "test_verdict_rules.py"), "a value exactly at its requirement fails (>= made >)"),
    Mutant("verdict-judge-max-sense", "profilegen/pipeline/design.py",
           'ok = value >= required if sense == ">=" else value <= required',
           'ok = value >= required if sense == ">=" else value >= required',
           (U + "test_verdict.py", U + "test_verdict_rules.py"), "a maximum (backlash, lost motion, interference) checked as a minimum"),
    Mutant("verdict-ratcheting-no-ratio", "profilegen/pipeline/design.py",
           "    bound = r.torque_nm / ratio\n", "    bound = r.torque_nm\n",
           (U + "test_verdict.py",), "the ratcheting estimate used as its own bound (the model's overestimate kept)"),
    Mutant("verdict-ratcheting-end-of-path", "profilegen/pipeline/design.py",
           'if criterion == "end of path":', 'if criterion == "end-of-path":',
           (U + "test_verdict.py",), "a climb whose path ended judged as an estimate"),
    Mutant("verdict-face-unmodified-depth", "profilegen/pipeline/design.py",
           "depth = face.max_interference_mm if mod is None else mod.max_interference_mm",
           "depth = face.max_interference_mm",
           (U + "test_verdict.py", U + "test_verdict_rules.py"), "the face check reads the unmodified teeth, not the teeth as made"),
    Mutant("verdict-never-incomplete", "profilegen/pipeline/design.py",
           "return INCOMPLETE if any(c.status == NOT_CHECKED for c in self.checks) else PASS", "return PASS",
           (U + "test_verdict.py",), "a design with NOT CHECKED checks reported PASS"),
    Mutant("verdict-momentary-fallback", "profilegen/pipeline/design.py",
           't_max, which = gs.torque.peak_nm, "peak (no momentary torque given)"',
           't_max, which = gs.torque.rated_nm, "peak (no momentary torque given)"',
           (U + "test_verdict.py",), "without a momentary torque the ratcheting bound is over the rated torque"),
    # ------------------------------------------------------------------ the design scene's rim (face/coning.py)
    Mutant("coning-any-waves", "profilegen/face/coning.py",
           'if tier == "design" and gearset.gear.waves == 2 and scene.rim != RING_FEM_LABEL:',
           'if tier == "design" and scene.rim != RING_FEM_LABEL:',
           (U + "test_scene_intent.py",), "the 3D cup (two-wave only) asked for on a three-wave gear"),
    Mutant("coning-ring-fem-label", "profilegen/face/coning.py",
           'if tier == "design" and gearset.gear.waves == 2 and scene.rim != RING_FEM_LABEL:',
           'if tier == "design" and gearset.gear.waves == 2:',
           (U + "test_scene_intent.py",), "the 2D ring FEM asked for by name replaced by the cup"),
    Mutant("coning-design-cup-mesh", "profilegen/face/coning.py",
           "element_mm=4.0, angles=8, gap=\"exact\")", "element_mm=2.0, angles=16, gap=\"exact\")",
           (U + "test_scene_intent.py",), "the design scene's cup at the verify mesh (4.6x the time)"),
    # ------------------------------------------------------------------ output folder: the owner rule
    Mutant("folder-marker-listing-unchecked", "profilegen/output/folder.py",
           "return (staging or rel in listed) and _writable(rel, ours, patterns)",
           "return _writable(rel, ours, patterns)",
           (U + "test_output_owner.py", U + "test_output_folder.py"),
           "a file the marker does not list taken as ours"),
    Mutant("folder-marker-lists-anything", "profilegen/output/folder.py",
           "return (staging or rel in listed) and _writable(rel, ours, patterns)",
           "return staging or rel in listed",
           (U + "test_output_owner.py", U + "test_output_folder.py"),
           "a planted marker listing a user's notes.txt makes it ours (the issue's case)"),
    Mutant("folder-link-is-regular", "profilegen/output/folder.py",
           "return entry.is_file(follow_symlinks=False)", "return entry.is_file()",
           (U + "test_output_owner.py", U + "test_output_folder.py"), "a symbolic link to a file taken for our file"),
    Mutant("folder-lock-follows-link", "profilegen/output/folder.py",
           "    flags = _O_NOFOLLOW | _O_CLOEXEC\n", "    flags = _O_CLOEXEC\n",
           (U + "test_output_owner.py", U + "test_output_folder.py"), "the lock file opened through a planted link"),
    # ------------------------------------------------------------------ the memory check (budget.py)
    Mutant("budget-retrace-ignored", "profilegen/pipeline/budget.py",
           "return chord_tol_mm / RETRACE_FACTOR**RETRACES", "return chord_tol_mm",
           (U + "test_budget.py", U + "test_messages_name_fields.py"), "the envelope's retrace left out of the estimate"),
    Mutant("budget-whole-memory", "profilegen/pipeline/budget.py",
           "return None if avail is None else 0.5 * avail", "return None if avail is None else avail",
           (U + "test_budget.py", U + "test_messages_name_fields.py"), "the budget all the memory, not half"),
    Mutant("budget-grid-advice-swapped", "profilegen/pipeline/budget.py",
           'f"{int(cells // scene.n_t)} (with n_t', 'f"{int(cells // scene.n_phi)} (with n_t',
           (U + "test_budget.py", U + "test_messages_name_fields.py"), "the n_phi advice divided by n_phi"),
    Mutant("budget-mebibyte", "profilegen/pipeline/budget.py",
           'scale = {"k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}', 'scale = {"k": 2**10, "m": 10**6, "g": 2**30, "t": 2**40}',
           (U + "test_budget.py", U + "test_messages_name_fields.py"), "a unit constant: M as 10^6 where G is 2^30"),
    Mutant("budget-outline-one-tooth", "profilegen/pipeline/budget.py",
           "OUTLINE_POINTS_PER_ENVELOPE_POINT * env * z2", "OUTLINE_POINTS_PER_ENVELOPE_POINT * env",
           (U + "test_budget.py", U + "test_messages_name_fields.py"), "the CS outline of one tooth space, not all z2"),
    # ------------------------------------------------------------------ user paths (userpaths.py)
    Mutant("userpaths-no-staging-room", "profilegen/output/userpaths.py",
           "limit = NAME_MAX - (BESIDE if k == len(parts) - 1 else 0)", "limit = NAME_MAX",
           (U + "test_messages_name_fields.py", U + "test_userpaths.py"), "the staging folder's extra characters not left room for"),
    Mutant("userpaths-relative-length", "profilegen/output/userpaths.py",
           "total = len(os.fsencode(os.path.abspath(text)))", "total = len(os.fsencode(text))",
           (U + "test_messages_name_fields.py", U + "test_userpaths.py"), "the path's length counted as given, not made absolute"),
    Mutant("userpaths-echoes-problems", "profilegen/output/userpaths.py",
           '    problems = getattr(exc, "problems", None) or [str(exc)]\n',
           '    return str(exc)\n',
           (U + "test_messages_name_fields.py", U + "test_userpaths.py"), "a spec's named file's problems echoed (its keys and values)"),
    # ------------------------------------------------------------------ face-stage warnings (test_face_warnings.py)
    Mutant("face-no-free-section-warning", "profilegen/face/stage.py",
           "warnings.append(f\"no computed section's CS is interference-free", "(f\"no computed section's CS is interference-free",
           (U + "test_face_warnings.py",), "a warning removed: no section's CS interference-free"),
    Mutant("face-one-cs-warning", "profilegen/face/stage.py",
           'warnings.append(f"the one CS profile (design section', '(f"the one CS profile (design section',
           (U + "test_face_warnings.py",), "a warning removed: the one CS profile interferes"),
    Mutant("face-one-cs-warning-always", "profilegen/face/stage.py",
           "    if result.max_interference_mm > tol:\n", "    if True:\n",
           (U + "test_face_warnings.py",), "the one-CS warning given when nothing interferes"),
    Mutant("face-no-thickness-field-warning", "profilegen/face/stage.py",
           'warnings.append(f"no tooth modification along the face', '(f"no tooth modification along the face',
           (U + "test_face_warnings.py",), "a warning removed: a tooth kind without a thickness field"),
    Mutant("modification-still-interferes-warning", "profilegen/face/modification.py",
           'warnings.append(f"with the tooth modification the CS still interferes', '(f"with the tooth modification the CS still interferes',
           (U + "test_face_warnings.py",), "a warning removed: the modification leaves interference"),
    Mutant("modification-lp-failed-warning", "profilegen/face/modification.py",
           'lp_failed = f"the LP failed at step {it} ({lp.message})"', 'lp_failed = ""',
           (U + "test_face_warnings.py",), "a warning's cause removed: the LP failed"),
    Mutant("modification-still-interfering-warning", "profilegen/face/modification.py",
           'warnings.append(f"tooth modification: still interfering', '(f"tooth modification: still interfering',
           (U + "test_face_warnings.py",), "a warning removed: nothing interference-free found"),
    Mutant("modification-search-found-warning", "profilegen/face/modification.py",
           'warnings.append(f"tooth modification: the LP found no interference-free step', '(f"tooth modification: the LP found no interference-free step',
           (U + "test_face_warnings.py",), "a warning removed: the fallback search, not the LP, gave the modification"),
    Mutant("face-curve-overlap-warning", "profilegen/contact/face_curve.py",
           'warnings.append(f"across the face ({self.slices} slices', '(f"across the face ({self.slices} slices',
           (U + "test_face_warnings.py",), "a warning removed: the two flanks overlap at no load"),
    Mutant("face-curve-overlap-threshold", "profilegen/contact/face_curve.py",
           "if np.any(play < 0.0):", "if np.any(play < -1.0):",
           (U + "test_face_warnings.py",), "the overlap warning's condition never met"),
)


# --------------------------------------------------------------------------- the copy


def _copy_tree(dest: Path, worktree: bool) -> str:
    """HEAD's files into ``dest`` (+ the working tree's uncommitted ones); returns the commit."""
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True,
                            check=True).stdout.strip()
    archive = subprocess.run(["git", "archive", "HEAD"], cwd=ROOT, capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    if worktree:
        listed = subprocess.run(["git", "ls-files", "-m", "-o", "--exclude-standard", "-z"], cwd=ROOT,
                                capture_output=True, check=True).stdout.decode().split("\0")
        for rel in filter(None, listed):
            src = ROOT / rel
            if rel.startswith("export/") or not src.is_file():
                continue
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / rel)
        commit += "+worktree"
    return commit


def _limits(memory_gb: float):
    def apply():
        cap = int(memory_gb * 1024 ** 3)
        resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
        os.nice(10)
    return apply


def _pytest(copy: Path, tests, timeout: float, memory_gb: float) -> tuple[str, float, str]:
    """('pass' | 'fail' | 'timeout', seconds, the last line of the output)."""
    env = {**os.environ, "PYTHONPATH": str(copy), "PYTHONDONTWRITEBYTECODE": "1"}
    cmd = [sys.executable, "-m", "pytest", "-q", "-n", "0", "-x", "-p", "no:cacheprovider", *tests]
    t0 = time.perf_counter()
    try:
        out = subprocess.run(cmd, cwd=copy, env=env, capture_output=True, text=True, timeout=timeout,
                             preexec_fn=_limits(memory_gb), start_new_session=True)
    except subprocess.TimeoutExpired:
        return "timeout", time.perf_counter() - t0, f"timeout after {timeout:g} s"
    lines = [ln for ln in out.stdout.splitlines() if ln.strip()]
    last = lines[-1] if lines else out.stderr.strip()[-200:]
    return ("pass" if out.returncode == 0 else "fail"), time.perf_counter() - t0, last


def _check_copy_imports_itself(copy: Path) -> None:
    env = {**os.environ, "PYTHONPATH": str(copy)}
    where = subprocess.run([sys.executable, "-c", "import profilegen; print(profilegen.__file__)"], cwd=copy,
                           env=env, capture_output=True, text=True, check=True).stdout.strip()
    if not Path(where).resolve().is_relative_to(copy.resolve()):
        raise SystemExit(f"the copy imports profilegen from {where}, not from {copy}: mutants would not be tested")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Plant each mutant in a copy of the repository and run its tests.")
    ap.add_argument("--only", nargs="+", metavar="NAME", help="run only these mutants")
    ap.add_argument("--list", action="store_true", help="list the mutants and exit")
    ap.add_argument("--worktree", action="store_true", help="overlay the working tree's uncommitted files")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per pytest run (default 600)")
    ap.add_argument("--memory-gb", type=float, default=4.0, help="address-space cap per run (default 4)")
    args = ap.parse_args(argv)

    names = [m.name for m in MUTANTS]
    dupes = {n for n in names if names.count(n) > 1}
    if dupes:
        raise SystemExit(f"duplicate mutant names: {sorted(dupes)}")
    chosen = list(MUTANTS)
    if args.only:
        unknown = set(args.only) - set(names)
        if unknown:
            raise SystemExit(f"unknown mutants: {', '.join(sorted(unknown))} (see --list)")
        chosen = [m for m in MUTANTS if m.name in args.only]
    if args.list:
        for m in chosen:
            print(f"{m.name:34s} {m.file:38s} {' '.join(t.removeprefix(U) for t in m.tests)}\n{'':34s} {m.why}")
        print(f"{len(chosen)} mutants")
        return 0

    with tempfile.TemporaryDirectory(prefix="profilegen-mutants-") as tmp:
        copy = Path(tmp) / "repo"
        copy.mkdir()
        commit = _copy_tree(copy, args.worktree)
        _check_copy_imports_itself(copy)
        print(f"profilegen mutants at {commit}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
              f"{len(chosen)} mutants", flush=True)
        baselines: dict[tuple[str, ...], tuple[str, float, str]] = {}
        rows = []
        for m in chosen:
            path = copy / m.file
            text = path.read_text(encoding="utf-8") if path.exists() else ""
            count = text.count(m.original)
            if count != 1:
                rows.append((m, "stale", 0.0, f"snippet found {count} times in {m.file}"))
                print(f"{m.name:34s} stale ({count} matches)", flush=True)
                continue
            if m.tests not in baselines:
                baselines[m.tests] = _pytest(copy, m.tests, args.timeout, args.memory_gb)
                if baselines[m.tests][0] != "pass":
                    print(f"  baseline red for {' '.join(m.tests)}: {baselines[m.tests][2]}", flush=True)
            if baselines[m.tests][0] != "pass":
                rows.append((m, "baseline-red", 0.0, baselines[m.tests][2]))
                print(f"{m.name:34s} baseline-red", flush=True)
                continue
            path.write_text(text.replace(m.original, m.replacement), encoding="utf-8")
            try:
                status, secs, last = _pytest(copy, m.tests, args.timeout, args.memory_gb)
            finally:
                path.write_text(text, encoding="utf-8")
            verdict = {"fail": "caught", "timeout": "caught (timeout)", "pass": "MISSED"}[status]
            rows.append((m, verdict, secs, last))
            print(f"{m.name:34s} {verdict:16s} {secs:6.1f} s  {last[:90]}", flush=True)

    print()
    print("| mutant | file | tests | result |")
    print("|---|---|---|---|")
    for m, verdict, secs, last in rows:
        print(f"| {m.name} | {m.file.removeprefix('profilegen/')} | {', '.join(t.removeprefix(U) for t in m.tests)} "
              f"| {verdict} |")
    judged = [r for r in rows if r[1] in ("caught", "caught (timeout)", "MISSED")]
    caught = sum(r[1].startswith("caught") for r in judged)
    stale = sum(r[1] == "stale" for r in rows)
    red = sum(r[1] == "baseline-red" for r in rows)
    share = 100.0 * caught / len(judged) if judged else 0.0
    print(f"\ncaught {caught} of {len(judged)} judged ({share:.1f} %); missed {len(judged) - caught}; "
          f"stale {stale}; baseline-red {red}; {len(rows)} mutants")
    for m, verdict, _, _ in rows:
        if verdict == "MISSED":
            print(f"  missed: {m.name} — {m.why}")
    return 0 if not (len(judged) - caught) and not stale and not red else 1


if __name__ == "__main__":
    sys.exit(main())
