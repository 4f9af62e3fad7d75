"""The test cup and cam shared by the 3D cup's tests (tests/unit/test_cup_contact.py,
tests/unit/test_cup_bearing.py): a steel cup of the default set's rim (r_m 48.95 mm, δ 0.9 mm)
on an elliptical cam of the bore's perimeter."""

from __future__ import annotations

import math

from profilegen.rim.cup import CupGeometry
from profilegen.geometry.wavegen import EllipticalCam, ellipse_perimeter

E, NU = 209000.0, 0.295
R_M, T = 48.95, 0.9
R_B = R_M - 0.5 * T
W0 = 0.5


def cup(length=60.0, **kw):
    """The cup: ``length`` mm, a 20 mm tooth ring, wall and bottom δ thick, boss at r_m/2."""
    return CupGeometry(R_M, T, length, 20.0, T, 0.5 * R_M, E, NU, **kw)


def cam(w0=W0):
    """The default set's elliptical cam (no bearing): major radius r_bore + w0, the bore's perimeter."""
    from scipy.optimize import brentq

    a = R_B + w0
    return EllipticalCam(a, brentq(lambda b: ellipse_perimeter(a, b) - 2 * math.pi * R_B, 0.5 * a, a))
