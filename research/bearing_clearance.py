"""The wave-generator bearing's radial internal clearance: a candidate for the compliance the
whole-gear model leaves out (research/README.md).

The contact model (:mod:`profilegen.contact.compliance`) supports the rim on the balls at
their no-load gaps — 0 within the no-load contact angle (the rim pressed on the cam), the
design's bore-to-contour gap outside it (``ball_supports="all"``). A real bearing has a
radial internal clearance c_r: the distance one ring can move radially against the other
(ISO 5753-1's definition, a diameter-like quantity). With the inner ring centred on its cam,
each ball has c_r/2 of play between its two raceways. The flexspline pinches the outer race
onto the balls round the major axes — those balls' play is taken up by the no-load
preload (the rim's pinching force, a small extra ovalisation of the flexible race) — and the
others keep theirs: :func:`clearance_ball_gaps_mm` adds c_r/2 to every ball outside the
window. Which c_r: a flexible wave-generator bearing is a special bearing whose clearance is
not published; the standard deep-groove ball bearing groups bracket it
(:func:`iso5753_radial_clearance_um`, ISO 5753-1 as tabulated by bearing makers, e.g.
http://www.bmzbearings.com/?mod=technical&id=4 and
https://www.ktaiballbearing.com/bearing-technical-info/internal-clearance/ — the same rows).

Analytic check of the clearance model on a whole bearing (:func:`radial_load_with_clearance_n`):
a ring pushed by δ_r against Z balls at ψ_i, each a Hertz contact Q = (δ_i/c_H)^{3/2} with
δ_i = δ_r cos ψ_i − c_r/2 (Stribeck/Palmgren; Harris, Rolling Bearing Analysis): F_r =
Σ Q_i cos ψ_i. Without clearance Z Q_max / F_r → 4.37 for many balls (Stribeck's constant,
1/J_r(½) = 1/0.2288); with clearance nothing is carried until δ_r = c_r/2.
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np

from profilegen import checks
from profilegen.errors import ProfilegenError

__all__ = ["ClearanceError", "ISO5753_DEEP_GROOVE_UM", "clearance_ball_gaps_mm", "iso5753_radial_clearance_um",
           "radial_load_with_clearance_n", "with_clearance_and_housing"]


class ClearanceError(ProfilegenError, ValueError):
    """Bad input to the bearing-clearance model; names the parameter, its value, unit and range."""


_positive = partial(checks.positive, error=ClearanceError)

#: ISO 5753-1 radial internal clearance of deep groove ball bearings (µm): bore over, incl →
#: (C2, Normal, C3) as (min, max) each. Rows as the sources in the module docstring give them.
ISO5753_DEEP_GROOVE_UM = {
    (40.0, 50.0): ((1, 11), (6, 23), (18, 36)),
    (50.0, 65.0): ((1, 15), (8, 28), (23, 43)),
    (65.0, 80.0): ((1, 15), (10, 30), (25, 51)),
    (80.0, 100.0): ((1, 18), (12, 36), (30, 58)),
}
_GROUPS = ("C2", "Normal", "C3")


def iso5753_radial_clearance_um(bore_mm: float, group: str = "Normal") -> tuple[float, float]:
    """(min, max) radial internal clearance (µm) of a deep groove ball bearing of bore
    ``bore_mm`` in clearance ``group`` (C2, Normal, C3)."""
    d = _positive("bore_mm", bore_mm)
    checks.choice("group", group, _GROUPS, error=ClearanceError)
    for (lo, hi), rows in ISO5753_DEEP_GROOVE_UM.items():
        if lo < d <= hi:
            return tuple(float(v) for v in rows[_GROUPS.index(group)])
    rng = (min(k[0] for k in ISO5753_DEEP_GROOVE_UM), max(k[1] for k in ISO5753_DEEP_GROOVE_UM))
    raise ClearanceError(f"bore_mm = {d!r} mm: outside the tabulated range ({rng[0]:g}, {rng[1]:g}] mm")


def clearance_ball_gaps_mm(no_load_gap_mm, radial_clearance_mm: float) -> np.ndarray:
    """The balls' gaps (mm) with a radial internal clearance c_r: c_r/2 added to every ball
    outside the no-load window (those whose no-load gap is > 0); the window's balls stay at 0
    (the flexspline's preload takes their play up)."""
    g = np.asarray(checks.finite_array("no_load_gap_mm", no_load_gap_mm, "mm", error=ClearanceError), dtype=float)
    if np.any(g < 0.0):
        raise ClearanceError("no_load_gap_mm: every gap must be ≥ 0 mm")
    c = _positive("radial_clearance_mm", radial_clearance_mm, allow_zero=True)
    return np.where(g > 0.0, g + 0.5 * c, 0.0)


def radial_load_with_clearance_n(radial_displacement_mm, radial_clearance_mm: float, ball_count: int,
                                 hertz_constant_mm_per_n23: float, *, phase_rad: float = 0.0):
    """F_r (N) of a ball bearing whose rings are pushed δ_r (mm) apart radially: Z balls at
    ψ_i = phase + 2πi/Z, ball i compressed δ_i = δ_r cos ψ_i − c_r/2 (none if < 0), Hertz
    Q_i = (δ_i/c_H)^{3/2} (c_H the total approach constant of one ball, mm/N^{2/3}, e.g.
    :class:`~profilegen.contact.chain.BallBearing`'s), F_r = Σ Q_i cos ψ_i. Returns (F_r, Q)."""
    dr = np.asarray(checks.finite_array("radial_displacement_mm", radial_displacement_mm, "mm",
                                        error=ClearanceError), dtype=float)
    c = _positive("radial_clearance_mm", radial_clearance_mm, allow_zero=True)
    z = checks.whole("ball_count", ball_count, 3, error=ClearanceError)
    ch = _positive("hertz_constant_mm_per_n23", hertz_constant_mm_per_n23, "mm/N^(2/3)")
    psi = float(phase_rad) + 2.0 * math.pi * np.arange(z) / z
    delta = dr[..., None] * np.cos(psi) - 0.5 * c
    q = np.where(delta > 0.0, np.clip(delta, 0.0, None) / ch, 0.0) ** 1.5
    return (q * np.cos(psi)).sum(axis=-1), q


def with_clearance_and_housing(compliance, points, gearset, *, radial_clearance_mm: float = 0.0,
                               cs_ring=None):
    """The contact compliance with the two candidates this module and :mod:`~tests.oracles.
    cs_ring` measure, as the chain would take them (docs/catalogue_comparison.md):

    * ``radial_clearance_mm`` c_r: every ball outside the window c_r/2 further away
      (:func:`clearance_ball_gaps_mm` on ``compliance.ball_gap_mm``) — only with every ball a
      one-sided support (``ball_supports="all"``; the window has no ball outside it: a
      ClearanceError if c_r > 0 there);
    * ``cs_ring``: a :class:`~tests.oracles.cs_ring.CSRing` (e.g. ``CSRing.from_gearset(gs)
      .held(k)``) whose ovalisation compliance at the contact points is added to the CS block
      (parallel to the contact's CS sector), or None.

    ``points``: the :class:`~profilegen.contact.points.ContactPoints` the compliance was built
    for; ``gearset`` is not read beyond that (kept for the chain's signature). Returns a new
    compliance (the matrix reassembled with the same active balls)."""
    import dataclasses

    from tests.oracles.cs_ring import CSRing, cs_ring_compliance

    del gearset
    c = _positive("radial_clearance_mm", radial_clearance_mm, allow_zero=True)
    out = compliance
    if c > 0.0:
        if getattr(compliance, "ball_supports", "window") != "all":
            raise ClearanceError(f"radial_clearance_mm = {c!r} mm: needs every ball a one-sided support "
                                 "(ball_supports='all'); the window's balls have no play to add")
        gaps = np.zeros(compliance.ball_angle_rad.size) if compliance.ball_gap_mm is None else compliance.ball_gap_mm
        out = dataclasses.replace(out, ball_gap_mm=clearance_ball_gaps_mm(gaps, c))
    if cs_ring is not None:
        if not isinstance(cs_ring, CSRing):
            raise ClearanceError(f"cs_ring: must be a CSRing or None, got {type(cs_ring).__name__}")
        s_ring = cs_ring_compliance(cs_ring, points.cs_point_mm, points.normal, zones=points.zones)
        out = dataclasses.replace(out, cs_matrix_mm_per_n=out.cs_matrix_mm_per_n + s_ring)
    return out.with_balls(out.ball_active) if out is not compliance else out
