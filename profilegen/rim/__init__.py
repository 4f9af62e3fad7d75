"""Rim deformation models: the flexspline rim pressed onto the wave-generator contour.

* :mod:`profilegen.rim.ring` — linear 2D plane-stress ring FEM (scikit-fem) with
  unilateral frictionless contact on a rigid contour (:func:`solve_ring`).
"""

from .ring import ConvergenceError, RingError, RingParameters, RingResult, solve_ring

__all__ = ["ConvergenceError", "RingError", "RingParameters", "RingResult", "solve_ring"]
