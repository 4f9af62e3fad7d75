"""Loaded tooth contact (seed 000 §5): contact points, compliance, complementarity solve.

* :mod:`profilegen.contact.solvers` — the solvers on (S, θ, r, T): :func:`solve_lemke` (the
  package's solver), :func:`solve_qp_active_set` (cross-check) → :class:`ContactSolution`.
* :mod:`profilegen.contact.points` — the potential contact points of one engagement zone
  of a design: FS flank stations against the fitted CS flank (:func:`contact_points`).
* :mod:`profilegen.contact.inputs` — :class:`ContactInput`, what the contact reads of a
  design (gear set, FS tooth, motion, fitted CS space, CS tip radius, the rim's no-load
  contact angle): ``ContactInput.from_design(design)``.
"""

from .inputs import ContactInput
from .points import ContactPointError, ContactPoints, contact_points

from .solvers import (
    ContactError,
    ContactSolution,
    solve_lemke,
    solve_qp_active_set,
)

__all__ = [
    "ContactError",
    "ContactInput",
    "ContactPointError",
    "ContactPoints",
    "contact_points",
    "ContactSolution",
    "solve_lemke",
    "solve_qp_active_set",
]
