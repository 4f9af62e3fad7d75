"""The bearing's outer race and the rim bending across the face between a ball and the face's
ends: a candidate for the compliance the whole-gear model leaves out (research/README.md).

The contact model is a plane-stress slice (:mod:`profilegen.contact.compliance`): a ball is a
radial support along the whole face width b, and the tooth load is spread evenly across b
(S = S_2D/b). In the gear a ball touches its raceway at the bearing's mid-width only; the
line load the teeth put on the rim over b reaches the ball through the race (and the rim
sliding on it) bending in the axial direction. Strip model (ESTIMATE of the geometry that
carries it): each ball collects the load of one ball pitch s = 2πR/Z of the ring (as the
slice's circumferential bending already does), so the axial strip is a beam of width s and
length b, of bending stiffness EI = E/(1 − ν²) · s (h_race³ + h_rim³)/12 (race and rim sliding
on each other: their stiffnesses add), under the even line load Q/b, held by the ball at mid-
width: two cantilevers of length L = b/2. The load's mean deflection against the ball (the
work-conjugate displacement, as the slice's even load is) is q L⁴/(20 EI), so the ball's
support gets the extra compliance

    c_ax = b³ / (320 EI)      (mm/N, in series with its Hertz contacts).

What it leaves out: the plate's two-way action (a wider strip near the ball, less far from it:
the strip of one pitch is a bound of neither sign), the race's groove, a bearing narrower or
off-centre under the face (``cup.bearing_width_mm``/``bearing_center_mm``: the cantilevers
then differ).
"""

from __future__ import annotations

import math
from functools import partial

from profilegen import checks
from profilegen.errors import ProfilegenError

__all__ = ["RaceFlexureError", "race_axial_flexure_compliance_mm_per_n"]


class RaceFlexureError(ProfilegenError, ValueError):
    """Bad input to the race-flexure estimate; names the parameter, its value, unit and range."""


_positive = partial(checks.positive, error=RaceFlexureError)


def race_axial_flexure_compliance_mm_per_n(face_width_mm: float, strip_width_mm: float, race_thickness_mm: float,
                                           rim_thickness_mm: float, youngs_modulus_mpa: float,
                                           poisson_ratio: float = 0.3) -> float:
    """c_ax = b³/(320 EI) (mm/N) of the strip model (module docstring): ``strip_width_mm`` the
    ball pitch s, the race and the rim bending in parallel (sliding), plate modulus E/(1 − ν²)."""
    b = _positive("face_width_mm", face_width_mm)
    s = _positive("strip_width_mm", strip_width_mm)
    hr = _positive("race_thickness_mm", race_thickness_mm, allow_zero=True)
    hf = _positive("rim_thickness_mm", rim_thickness_mm, allow_zero=True)
    if hr + hf <= 0.0:
        raise RaceFlexureError("race_thickness_mm, rim_thickness_mm: at least one must be > 0 mm")
    e = _positive("youngs_modulus_mpa", youngs_modulus_mpa, "MPa")
    nu = checks.within("poisson_ratio", poisson_ratio, "", 0.0, 0.5, error=RaceFlexureError)
    ei = e / (1.0 - nu * nu) * s * (hr ** 3 + hf ** 3) / 12.0
    if not math.isfinite(ei) or ei <= 0.0:
        raise RaceFlexureError(f"the strip's bending stiffness = {ei!r} N·mm²: must be > 0")
    return b ** 3 / (320.0 * ei)
