"""What the loaded tooth contact reads of a design: :class:`ContactInput`.

The contact stage (:func:`~profilegen.contact.analysis.solve_contact`,
:func:`~profilegen.contact.points.contact_points`,
:meth:`~profilegen.contact.compliance.ContactCompliance.build`) takes these fields and
nothing else of a :class:`profilegen.pipeline.design.Design`: the gear set (teeth, waves, radii,
deflection, material, cup face width, wave generator), the FS tooth, the motion of the FS
tooth frame in the CS frame (the no-load deformation is in it), one tooth space of the
fitted CS profile (its true arcs and lines), the CS tip radius (where the FS flank can
first touch), and the rim stage's no-load contact angle when a rim FEM found one (it
selects the wave-generator balls; without it a flat-ring solve on the gear set's contour
gives it).

:meth:`ContactInput.from_design` is the one place a design is read for them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..geometry.contour import Chain
from ..gearset import GearSet
from ..geometry.kinematics import HarmonicDriveMotion
from ..geometry.teeth import ToothProfile
from .solvers import ContactError

__all__ = ["ContactInput"]


def _typed(name: str, value, kind: type, what: str) -> None:
    if not isinstance(value, kind):
        raise ContactError(f"{name}: must be {what}, got {type(value).__name__}")


@dataclass(frozen=True, slots=True, eq=False)
class ContactInput:
    """The contact stage's inputs (see the module docstring).

    ``gearset``: the :class:`~profilegen.gearset.GearSet`; ``tooth``: the FS tooth
    (:class:`~profilegen.geometry.teeth.ToothProfile`); ``motion``: the FS tooth frame in the CS frame
    (:class:`~profilegen.geometry.kinematics.HarmonicDriveMotion`, built with the design's deformation);
    ``cs_space``: one CS tooth space of the fitted profile, a
    :class:`~profilegen.geometry.contour.Chain` of arcs and lines (``design.profile.space``);
    ``cs_tip_radius_mm``: the CS tip circle (``design.form.tip_radius_mm``);
    ``rim_contact_angle_rad``: the half angle over which the rim sits on the wave generator at
    no load, from the rim FEM (None: not known, the compliance solves a flat ring for it);
    ``cs_outline``: the closed CS outline, ``cs_space`` repeated z2 times and joined on the tip
    circle, as the arc fit built it (``design.profile.outline``; None: built from ``cs_space``
    where needed).
    """

    gearset: GearSet
    tooth: ToothProfile
    motion: HarmonicDriveMotion
    cs_space: Chain
    cs_tip_radius_mm: float
    rim_contact_angle_rad: float | None = None
    cs_outline: Chain | None = None

    def __post_init__(self):
        _typed("gearset", self.gearset, GearSet, "a GearSet")
        _typed("tooth", self.tooth, ToothProfile, "a ToothProfile (the FS tooth)")
        _typed("motion", self.motion, HarmonicDriveMotion, "a HarmonicDriveMotion")
        _typed("cs_space", self.cs_space, Chain, "a Chain (one tooth space of the fitted CS profile)")
        if self.cs_outline is not None:
            _typed("cs_outline", self.cs_outline, Chain, "None or a Chain (the CS outline of cs_space)")
        g = self.gearset.gear
        if (self.motion.cs_teeth, self.motion.waves) != (g.circular_spline_teeth, g.waves):
            raise ContactError(f"motion: cs_teeth = {self.motion.cs_teeth}, waves = {self.motion.waves} do not match "
                               f"the gear set's gear.circular_spline_teeth = {g.circular_spline_teeth}, "
                               f"gear.waves = {g.waves}")
        tip = self.cs_tip_radius_mm
        if isinstance(tip, bool) or not isinstance(tip, (int, float)) or not (math.isfinite(tip) and tip > 0.0):
            raise ContactError(f"cs_tip_radius_mm = {tip!r} mm: must be finite and > 0")
        object.__setattr__(self, "cs_tip_radius_mm", float(tip))
        angle = self.rim_contact_angle_rad
        if angle is not None:
            if isinstance(angle, bool) or not isinstance(angle, (int, float)) or not 0.0 <= angle <= math.pi:
                raise ContactError(f"rim_contact_angle_rad = {angle!r} rad: must be None (not known) or in [0, π]")
            object.__setattr__(self, "rim_contact_angle_rad", float(angle))

    @classmethod
    def from_design(cls, design, *, name: str = "design") -> "ContactInput":
        """The contact inputs of a :class:`profilegen.pipeline.design.Design` (with a fitted CS
        profile); a ContactInput is returned as it is. ``name``: the argument the error names."""
        if isinstance(design, cls):
            return design
        try:
            gearset, tooth, motion = design.gearset, design.tooth, design.motion
            profile, form, rim = design.profile, design.form, design.rim
        except AttributeError:
            raise ContactError(f"{name}: must be a ContactInput or a profilegen Design, got "
                               f"{type(design).__name__}") from None
        if profile is None:
            raise ContactError(f"{name}: has no fitted CS profile (design.profile is None)")
        fem = None if rim is None else rim.fem
        angle = float(fem.contact_angle_rad) if fem is not None and fem.contact_phi_rad.size else None
        return cls(gearset, tooth, motion, profile.space, form.tip_radius_mm, angle, profile.outline)

    @classmethod
    def of(cls, value, name: str = "inputs", *, error: type = ContactError) -> "ContactInput":
        """``value`` if it is a ContactInput, else ``error`` (the caller's error class) naming ``name``."""
        if isinstance(value, cls):
            return value
        raise error(f"{name}: must be a ContactInput (ContactInput.from_design(design) builds one from a "
                           f"Design), got {type(value).__name__}")
