"""Every bundled gear set runs end to end in the sketch and design scenes, as a new user runs
them (`profilegen design NAME --scene S`), and what comes out obeys the physics it claims:
the one-sided CS does not cut into the FS tooth, the CS outline closes, the loaded contact is
in moment equilibrium, and design.json lists exactly the files written. One set runs the verify
scene's tiers and stages on the design scene's grids (REDUCED_VERIFY, ~18 s); the full verify
scene of every set is in tests/benchmarks/bundled.py (about a minute per set)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from profilegen.output import cad
from profilegen.cli import main
from profilegen.gearset import list_profiles, load_gearset
from profilegen.pipeline.design import INTERFERENCE_TOL_MM

BUNDLED = sorted(p.stem for p in list_profiles())
# the default set in the design scene is `profilegen design` itself: tests/test_cli.py runs it; its
# sketch scene is the run tests/test_cli.py's progress and DXF tests check too (conftest.py:
# default_sketch_run), checked below by test_the_default_set_sketch_obeys_its_checks
CASES = [(name, scene) for name in BUNDLED for scene in ("sketch", "design") if name != "default"
         and name != "csf32_100"]  # csf32_100 (issue 16's second catalogue size): its design run is in
# tests/benchmarks/catalogue_stiffness.py (~27 s), out of the suite's time budget; test_cli checks it


def test_the_bundled_sets_are_the_four_seed_sets():
    assert BUNDLED == ["csf32_100", "default", "seed000_csf40", "seed001_shf25", "seed002_short_cup"]


@pytest.mark.slow
@pytest.mark.parametrize("name, scene", CASES, ids=[f"{n}-{s}" for n, s in CASES])
def test_bundled_set_runs_and_obeys_its_checks(name, scene, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["design", name, "--scene", scene, "--out", str(out)]) == 0
    printed = capsys.readouterr()
    _check(name, scene, out, printed.out, printed.err)


#: the verify scene's tiers and stages on the design scene's grids (the file says which)
REDUCED_VERIFY = Path(__file__).parent / "scenes" / "reduced_verify.toml"


@pytest.mark.slow
def test_a_bundled_set_in_the_verify_scenes_tiers(tmp_path, capsys):
    """seed001_shf25 through every stage the verify scene runs, as a user runs it: the checks
    every scene obeys, and the verify stages' own — the face stage chose a design section inside
    the face, the contact is in equilibrium at every load case, the ratcheting estimate lies above
    the momentary torque (a gear that ratchets below it could not be rated so) and is checked by
    the verdict, the transmission error is a finite non-zero ripple, the torsional curve is solved
    across the face in the scene's 3 slices."""
    name = "seed001_shf25"
    out = tmp_path / "out"
    assert main(["design", name, "--scene", str(REDUCED_VERIFY), "--out", str(out)]) == 0
    printed = capsys.readouterr()
    _check(name, "design", out, printed.out, printed.err)
    data = json.loads((out / "design.json").read_text())
    gs = load_gearset(next(p for p in list_profiles() if p.stem == name))
    face = data["face"]
    z = face["candidates"]["z_mm"]  # the sections the face stage weighed
    assert max(z) - min(z) == pytest.approx(gs.cup.face_width_mm)  # centred on the mid-face z = l
    assert min(z) <= face["design_section_z_mm"] <= max(z)
    ratch = data["contact"]["ratcheting"]
    momentary = gs.torque.momentary_nm or gs.torque.peak_nm
    assert np.isfinite(ratch["torque_nm"]) and ratch["torque_nm"] > momentary
    checks = {c["kind"]: c for c in data["verdict"]["checks"]}
    assert "ratcheting" in checks
    te = data["contact"]["transmission_error"]
    assert te is not None and 0.0 < te["peak_to_peak_arcsec"] < 60.0 and te["positions"] >= 2
    assert data["contact"]["torsional"] is not None


@pytest.mark.slow
@pytest.mark.xdist_group("default_sketch")
def test_the_default_set_sketch_obeys_its_checks(default_sketch_run):
    """`profilegen design default --scene sketch` (a subprocess, run once for three tests)."""
    res, out = default_sketch_run
    assert res.returncode == 0, res.stderr
    _check("default", "sketch", out, res.stdout, res.stderr)


def _check(name, scene, out, stdout, stderr):
    data = json.loads((out / "design.json").read_text())
    assert sorted(data["files"]) == sorted(p.name for p in out.iterdir())
    verdict = data["verdict"]
    # the verdict is the last line: on stdout when it passes, on stderr when it fails
    assert (stdout if verdict["passed"] else stderr).splitlines()[-1] == verdict["line"]
    # the CAD profile is the one-sided fit: it may touch the FS tooth, never cut into it beyond the
    # checks' numerical noise — the verdict's tolerance, 10x the ~1 nm the fit checks see (1.17 nm
    # on seed001_shf25 in the verify tiers, 1.39 nm on seed 002: pipeline.INTERFERENCE_TOL_MM)
    tol = max(INTERFERENCE_TOL_MM, data["envelope"]["chord_tol_mm"])
    assert data["profile"]["method"] == "one_sided" and data["profile"]["min_clearance_mm"] >= -tol
    # the CS outline in the DXF: LINE/ARC, one closed chain, z2 identical spaces (2π/z2 apart)
    gs = load_gearset(next(p for p in list_profiles() if p.stem == name))
    z2 = gs.gear.circular_spline_teeth
    cs = cad.read_dxf_contours(out / "circular_spline.dxf")["CS"]
    chain = cad.oriented_chain(cs)
    assert chain.gaps(closed=True).max() <= 1e-9 and len(cs) % z2 == 0
    pts = chain.sample(1e-3)
    turned = pts @ np.array([[np.cos(2 * np.pi / z2), np.sin(2 * np.pi / z2)],
                             [-np.sin(2 * np.pi / z2), np.cos(2 * np.pi / z2)]])
    assert chain.nearest(turned[::7])[0].max() < 1e-9  # one pitch turns it onto itself
    if scene == "design" and gs.gear.waves == 2:
        contact = json.loads((out / "contact.json").read_text())
        lever = np.array(contact["points"]["lever_mm"])
        for case in contact["cases"]:
            moment = np.sum(lever * np.array(case["solution"]["force_n"]))
            assert moment == pytest.approx(case["zone_torque_nm"] * 1e3, rel=1e-9)
