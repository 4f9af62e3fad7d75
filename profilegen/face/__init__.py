"""Face width and FS tooth modification along the face (docs/theory/cup.md).

* :mod:`profilegen.face.sections` — one axial section of the tooth ring (its deformation from
  the 3D cup, motion, envelope) and the signed gap of CS points to its swept region;
* :mod:`profilegen.face.clearance` — one section's clearance map against the one CS outline,
  its minimum and backlash;
* :mod:`profilegen.face.stage` — :func:`face_width`: the sections, the design section, the one
  CS outline and the clearance map (axial position × φ) → :class:`FaceWidth`;
* :mod:`profilegen.face.modification` — the tooth-thickness taper and crowning along the face
  (:func:`solve_modification`, :func:`apply_modification`) → :class:`ToothModification`.
"""

from .modification import ToothModification, apply_modification, modified_tooth, solve_modification, thickness_change
from .sections import FaceError, FaceSection, ring_span, section_fit, signed_gap, solve_section
from .clearance import SectionClearance, section_clearance
from .stage import FaceWidth, face_width

__all__ = [
    "FaceError",
    "FaceSection",
    "FaceWidth",
    "SectionClearance",
    "ToothModification",
    "apply_modification",
    "face_width",
    "modified_tooth",
    "ring_span",
    "section_clearance",
    "section_fit",
    "signed_gap",
    "solve_modification",
    "solve_section",
    "thickness_change",
]
