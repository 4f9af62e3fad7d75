"""Inside an engine's design a face section's Fourier fit — it reads the rim's deformation and the
section's z, not the tooth — is kept for a tooth change, and is the fit a plain call makes."""

from __future__ import annotations

import numpy as np

from profilegen.face.sections import section_fit, solve_section
from profilegen.gearset import load_gearset
from profilegen.geometry.teeth import tooth_from_gearset
from profilegen.pipeline.engine import Engine, _Run
from profilegen.stagecache import STAGE_CACHE


class _Ring:
    """ω = w(z) cos 2φ, υ = −w(z)/2 sin 2φ (ring theory), w growing along the face."""

    ring_span_mm = (50.0, 70.0)

    def omega(self, phi, z):
        return 0.3 * (1.0 + 0.002 * np.asarray(z, float)) * np.cos(2 * np.asarray(phi, float))

    def upsilon(self, phi, z):
        return -0.15 * (1.0 + 0.002 * np.asarray(z, float)) * np.sin(2 * np.asarray(phi, float))


def test_a_tooth_change_keeps_the_section_fits():
    gs = load_gearset("profiles/default.toml")
    changed = gs.with_values({"tooth.pressure_angle_deg": 10.02})
    ring = _Ring()
    engine = Engine()
    opts = {"chord_tol_mm": 1e-3, "n_t": 48, "n_phi": 121}
    token = STAGE_CACHE.set(_Run(engine, engine._generation))
    try:
        first = solve_section(gs, ring, 60.0, tooth_from_gearset(gs), **opts)
        again = solve_section(changed, ring, 60.0, tooth_from_gearset(changed), **opts)
        other = solve_section(changed, ring, 65.0, tooth_from_gearset(changed), **opts)
    finally:
        STAGE_CACHE.reset(token)
    assert again.fit is first.fit and engine.hits["face_section_fit"] == 1
    assert other.fit is not first.fit and engine.runs["face_section_fit"] == 2  # another z: another fit
    plain = section_fit(ring, 60.0, waves=gs.gear.waves)[0]
    for name in ("cos_mm", "sin_mm"):
        np.testing.assert_array_equal(getattr(first.fit.model, name), getattr(plain.model, name))
    assert first.fit.model.mean_mm == plain.model.mean_mm
    assert not np.array_equal(again.envelope.flank["boundary"][:5], first.envelope.flank["boundary"][:5])
