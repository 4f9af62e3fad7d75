"""Rim deformation models: the flexspline rim pressed onto the wave-generator contour.

* :mod:`profilegen.rim.stage` — the pipeline stage :func:`solve_rim` (tiers sketch / design /
  verify) → :class:`RimDeformation` (FEM samples, Fourier fit, general sine fit, estimate).
* :mod:`profilegen.rim.ring` — 2D plane-stress quarter-ring FEM (scikit-fem), linear or
  geometrically nonlinear, unilateral frictionless contact on a rigid contour (:func:`solve_ring`).
* :mod:`profilegen.rim.nonlinear` — total Lagrangian St Venant–Kirchhoff force and tangent.
* :mod:`profilegen.rim.toothed` — mapped mesh of the toothed rim (:func:`toothed_quarter_mesh`).
"""

from .ring import ConvergenceError, RingError, RingParameters, RingResult, solve_ring
from .stage import RIM_TIERS, RimDeformation, RimTier, solve_rim
from .toothed import ToothedMeshError, ToothedRimMesh, toothed_quarter_mesh

__all__ = [
    "RIM_TIERS",
    "ConvergenceError",
    "RimDeformation",
    "RimTier",
    "RingError",
    "RingParameters",
    "RingResult",
    "ToothedMeshError",
    "ToothedRimMesh",
    "solve_rim",
    "solve_ring",
    "toothed_quarter_mesh",
]
