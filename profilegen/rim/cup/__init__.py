"""The 3D cup tier of the rim stage: the flexspline cup — wall, tooth ring as an
equivalent band of the rim thickness, bottom (diaphragm) clamped on its boss — as a body of
revolution.

* :mod:`profilegen.rim.cup.geometry` — :class:`CupGeometry` (validated, from a GearSet's
  ``[gear]``, ``[material]``, ``[cup]``) and the meridional mesh.
* :mod:`profilegen.rim.cup.fourier` — the fast formulation: one 2D meridional FEM problem per
  Fourier harmonic n (:func:`solve_cup` → :class:`CupDeformation`: ω, υ, the axial
  displacement and the generator tilt at any (φ, z)).
* :mod:`profilegen.rim.cup.contact` — the cup pressed onto the wave-generator contour over the
  bearing's width, frictionless unilateral contact by collocation in φ, the harmonic solves as
  the compliance operator (:func:`press_cup` → :class:`CupContact`).
* :mod:`profilegen.rim.cup.bearing` — the wave-generator bearing's outer race under the bore, a
  ring on one ball row that bends, tilts and rests on Hertz balls (:class:`BearingRace`,
  ``press_cup(race=...)``; without one the bore is pressed onto a rigid band).
* :mod:`profilegen.rim.cup.assembly` — batched assembly of the stiffness matrices (the
  harmonic forms and 3D elasticity, equal to scikit-fem's BilinearForms to rounding).
"""

from .bearing import BearingRace
from .contact import CupContact, press_cup
from .fourier import CupDeformation, HarmonicBasis, bore_load, harmonic_stiffness, solve_cup
from .geometry import CupError, CupGeometry, CupMesh, meridional_mesh

__all__ = [
    "BearingRace",
    "CupContact",
    "CupDeformation",
    "CupError",
    "CupGeometry",
    "CupMesh",
    "HarmonicBasis",
    "bore_load",
    "harmonic_stiffness",
    "meridional_mesh",
    "press_cup",
    "solve_cup",
]
