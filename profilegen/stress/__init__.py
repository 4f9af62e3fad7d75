"""Flexspline stresses (seeds 000, 001, 002) and the stress stage of a design.

* :mod:`~profilegen.stress.tooth_ring` — seed 001: the tooth ring under the wave
  generator's assembly bending and the mesh load;
* :mod:`~profilegen.stress.plate` — seed 002: the cup bottom as a Kirchhoff annular plate
  (consistent per-harmonic solution, and the paper's ``seed002`` variant);
* :mod:`~profilegen.stress.diaphragm` — seed 000: the diaphragm corner's shear and its
  Goodman check;
* :mod:`~profilegen.stress.stage` — :func:`solve_stress` feeds all three with a design's own
  deformation and contact forces (a :class:`StressInput`) and makes the safety checks.
"""

from .stage import SafetyCheck, StressInput, StressResult, solve_stress

__all__ = ["SafetyCheck", "StressInput", "StressResult", "solve_stress"]
