"""The gear-set file schema and its section value types.

The sections of a gear set — :class:`Gear`, the tooth (:class:`DctaTooth`,
:class:`InvoluteTooth`, :class:`PointsTooth`), :class:`WaveGenerator`, :class:`Material`,
:class:`Torque`, :class:`CircularSpline`, :class:`Cup` — as frozen values, and the keys and
allowed words of each section (``SCENE_NAMES``, ``TOOTH_KINDS``, ``FIT_METHODS``, ...). The reader
(:mod:`profilegen.gearset.reader`) builds the sections once every field is checked;
:class:`~profilegen.gearset.types.GearSet` holds them. Conventions: see :mod:`profilegen.gearset`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..errors import GearSetError
from .requirements import REQUIREMENTS_KEYS, Requirements  # the [requirements] table (the verdict's)


SCENE_NAMES = ("sketch", "design", "verify")
TOOTH_KINDS = ("dcta", "involute", "points")
WAVE_GENERATOR_CONTOURS = ("elliptical_cam", "cosine_cam", "rollers")


# The project's default double-circular-arc tooth for m = 0.5 mm, in mm: the defaults of a
# DctaTooth built directly (no module to scale with). In a gear-set file the defaults follow
# the module: TOOTH_LENGTHS' coefficients (0.05 mm = 0.1·m at m = 0.5 mm, ...).
DCTA_DEFAULTS = {
    "pressure_angle_deg": 10.0,
    "line_above_pitch_mm": 0.05,
    "line_below_pitch_mm": 0.20,
    "tip_arc_radius_mm": 0.65,
    "root_arc_radius_mm": 0.70,
    "addendum_mm": 0.40,
    "dedendum_mm": 0.60,
}

TOP_KEYS = ("name", "description", "source", "scene")
SECTIONS = ("gear", "tooth", "wave_generator", "material", "torque", "circular_spline", "cup", "face", "requirements")
GEAR_KEYS = (
    "module_mm",
    "flexspline_teeth",
    "circular_spline_teeth",
    "waves",
    "rim_thickness_mm",
    "neutral_radius_mm",
)
TOOTH_KEYS = {
    "dcta": (
        "kind",
        "pressure_angle_deg",
        "line_above_pitch_mm",
        "line_below_pitch_mm",
        "tip_arc_radius_mm",
        "root_arc_radius_mm",
        "addendum_mm",
        "dedendum_mm",
        "half_thickness_mm",
    ),
    "involute": ("kind", "pressure_angle_deg", "addendum_mm", "dedendum_mm", "half_thickness_mm"),
    "points": ("kind", "points", "points_file", "smoothing_mm"),
}


@dataclass(frozen=True, slots=True)
class _Length:
    """A tooth length: its range and default in units of the module m. In a file it is given
    in mm (``<name>_mm``) or in units of m (``<name>_coefficient``, the value times m)."""

    lo: float
    hi: float
    default: float | None  # times m; None: required (no tooth length is)
    lo_open: bool = True
    hi_open: bool = False
    note: str = ""


_HALF_PITCH = math.pi / 2.0
# The addendum and dedendum bounds: up to 3·m (a tooth three modules high is already far past any
# strain-wave-gear tooth, 1.6–2.2·m in total); at least 0.2·m, because a shorter tooth than that
# cannot clear the circular spline's default clearances of 0.25·m (and is a sign of a tooth in mm
# for another module: the default tooth's 0.4 mm on an m = 10 gear is 0.04·m).
TOOTH_LENGTHS: dict[str, dict[str, _Length]] = {
    "dcta": {
        "line_above_pitch": _Length(0.0, 5.0, 0.1, lo_open=False),
        "line_below_pitch": _Length(0.0, 5.0, 0.4, lo_open=False),
        "tip_arc_radius": _Length(0.0, 10.0, 1.3),
        "root_arc_radius": _Length(0.0, 10.0, 1.4),
        "addendum": _Length(0.2, 3.0, 0.8, lo_open=False),
        "dedendum": _Length(0.2, 3.0, 1.2, lo_open=False),
        "half_thickness": _Length(0.0, _HALF_PITCH, math.pi / 4.0, hi_open=True, note="half a pitch π·m/2"),
    },
    "involute": {
        "addendum": _Length(0.2, 3.0, 1.0, lo_open=False),
        "dedendum": _Length(0.2, 3.0, 1.25, lo_open=False),
        "half_thickness": _Length(0.0, _HALF_PITCH, math.pi / 4.0, hi_open=True, note="half a pitch π·m/2"),
    },
}
COEFFICIENT_SUFFIX = "_coefficient"
# every tooth length may be given in units of the module instead of mm
TOOTH_KEYS = {
    kind: keys + tuple(f"{name}{COEFFICIENT_SUFFIX}" for name in TOOTH_LENGTHS.get(kind, {}))
    for kind, keys in TOOTH_KEYS.items()
}
WAVE_GENERATOR_KEYS = (
    "deflection_coefficient",
    "contour",
    "roller_count",
    "roller_radius_mm",
    "roller_angle_deg",
    "bearing_thickness_mm",
)
# Four rollers touch the ring-theory bore at ±ROLLER_ANGLE_DEG_DEFAULT about each end of the
# major axis unless ``wave_generator.roller_angle_deg`` says otherwise.
ROLLER_ANGLE_DEG_DEFAULT = 30.0
MATERIAL_KEYS = (
    "youngs_modulus_mpa",
    "poisson_ratio",
    "yield_strength_mpa",
    "ultimate_strength_mpa",
    "bending_endurance_limit_mpa",
    "shear_endurance_limit_mpa",
)
TORQUE_KEYS = ("rated_nm", "peak_nm", "momentary_nm")
CIRCULAR_SPLINE_KEYS = ("root_clearance_mm", "tip_clearance_mm", "fit_method", "wire_radius_mm", "spark_gap_mm",
                         "corners", "outer_diameter_mm")
#: [circular_spline] outer_diameter_mm: default (ESTIMATE) this × the CS root diameter, rounded up to
#: a whole mm; it must leave a ring wall of at least CS_MIN_WALL_PER_MODULE · m beyond the root circle
CS_OUTER_DIAMETER_PER_ROOT = 1.25
CS_MIN_WALL_PER_MODULE = 2.0
CORNER_STYLES = ("fillet", "sharp")
FIT_METHODS = ("one_sided", "least_squares", "minimax")
CUP_KEYS = ("length_mm", "face_width_mm", "bottom_thickness_mm", "boss_radius_mm", "root_fillet_radius_mm",
             "wall_thickness_mm", "bearing_width_mm", "bearing_center_mm")
#: [face] (profilegen.face): the CS design section, the number of axial sections, the FS tooth modification
FACE_KEYS = ("design_section_z_mm", "sections", "taper_mm_per_mm", "crowning_mm")
FACE_SECTIONS_RANGE = (3, 41)
FACE_TAPER_LIMIT = 0.01  # mm of tooth thickness per mm of face
FACE_CROWNING_LIMIT = 0.1  # mm
_SECTION_KEYS = {
    "gear": GEAR_KEYS,
    "wave_generator": WAVE_GENERATOR_KEYS,
    "material": MATERIAL_KEYS,
    "torque": TORQUE_KEYS,
    "circular_spline": CIRCULAR_SPLINE_KEYS,
    "cup": CUP_KEYS,
    "face": FACE_KEYS,
    "requirements": REQUIREMENTS_KEYS,
}


# --------------------------------------------------------------------------- types


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class Gear:
    """Gear data of the set: module, teeth, waves and the flexspline rim."""

    module_mm: float
    flexspline_teeth: int
    circular_spline_teeth: int
    waves: int = 2
    rim_thickness_mm: float
    neutral_radius_mm: float
    """Radius r_m of the undeformed rim neutral line (resolved: given or derived)."""

    @property
    def pitch_radius_mm(self) -> float:
        """FS pitch radius r1 = m·z1/2 (mm)."""
        return self.module_mm * self.flexspline_teeth / 2.0

    @property
    def cs_pitch_radius_mm(self) -> float:
        """CS pitch radius r2 = m·z2/2 (mm)."""
        return self.module_mm * self.circular_spline_teeth / 2.0

    @property
    def circular_pitch_mm(self) -> float:
        """Circular pitch p = π·m (mm)."""
        return math.pi * self.module_mm

    @property
    def tooth_difference(self) -> int:
        """z2 − z1 (a positive multiple of the waves)."""
        return self.circular_spline_teeth - self.flexspline_teeth

    @property
    def neutral_to_pitch_mm(self) -> float:
        """r1 − r_m: y of the pitch point in the kinematics (neutral-line) tooth frame (mm)."""
        return self.pitch_radius_mm - self.neutral_radius_mm


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class DctaTooth:
    """Double-circular-arc tooth with a common tangent (DCTA), pitch frame.

    Right flank from root to tip: a concave root arc (radius ``root_arc_radius_mm``)
    from the root line (``dedendum_mm`` below the pitch line) to the point B, the
    common tangent B → A (a straight line through the pitch point
    ``(half_thickness_mm, 0)``, inclined by ``pressure_angle_deg`` to the tooth
    axis; A and B lie ``line_above_pitch_mm`` / ``line_below_pitch_mm`` from the
    pitch point *along the line*), then a convex tip arc (``tip_arc_radius_mm``)
    up to the tip line (``addendum_mm`` above the pitch line); G1 at A and B.
    Whether the arcs reach the tip and root lines is checked when the profile
    is built (``profilegen.geometry.teeth``, :class:`~profilegen.errors.ToothError`).
    """

    kind: ClassVar[str] = "dcta"
    pressure_angle_deg: float = DCTA_DEFAULTS["pressure_angle_deg"]
    line_above_pitch_mm: float = DCTA_DEFAULTS["line_above_pitch_mm"]
    line_below_pitch_mm: float = DCTA_DEFAULTS["line_below_pitch_mm"]
    tip_arc_radius_mm: float = DCTA_DEFAULTS["tip_arc_radius_mm"]
    root_arc_radius_mm: float = DCTA_DEFAULTS["root_arc_radius_mm"]
    addendum_mm: float = DCTA_DEFAULTS["addendum_mm"]
    dedendum_mm: float = DCTA_DEFAULTS["dedendum_mm"]
    half_thickness_mm: float
    coefficients: tuple[tuple[str, float], ...] = ()
    """The lengths the file gave in units of the module, as (``<name>_mm``, coefficient)
    pairs (``(("addendum_mm", 0.8),)``); the ``*_mm`` fields hold them resolved to mm."""

    @property
    def pressure_angle_rad(self) -> float:
        return math.radians(self.pressure_angle_deg)


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class InvoluteTooth:
    """Standard involute tooth (pitch frame): pressure angle, addendum, dedendum, thickness."""

    kind: ClassVar[str] = "involute"
    pressure_angle_deg: float = 20.0
    addendum_mm: float
    dedendum_mm: float
    half_thickness_mm: float
    coefficients: tuple[tuple[str, float], ...] = ()
    """As :attr:`DctaTooth.coefficients`."""

    @property
    def pressure_angle_rad(self) -> float:
        return math.radians(self.pressure_angle_deg)


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class PointsTooth:
    """A tooth given by points of its right flank (pitch frame, root to tip, mm).

    ``points`` is a read-only ``(n, 2)`` array; ``points_file`` names the CSV it
    was read from (informational only: :meth:`GearSet.to_dict` writes the points
    inline).
    """

    kind: ClassVar[str] = "points"
    points: np.ndarray
    smoothing_mm: float = 0.0005
    points_file: str | None = None

    def __post_init__(self):
        points = np.array(self.points, dtype=float)
        points.setflags(write=False)
        object.__setattr__(self, "points", points)

    def __reduce__(self):
        # through the constructor, so that an unpickled copy is read-only again
        return (_points_tooth, (self.points, self.smoothing_mm, self.points_file))

    @property
    def addendum_mm(self) -> float:
        """Height of the highest point above the pitch circle (mm)."""
        return float(self.points[:, 1].max())

    @property
    def dedendum_mm(self) -> float:
        """Depth of the lowest point below the pitch circle (mm)."""
        return float(-self.points[:, 1].min())

    @property
    def half_thickness_mm(self) -> float:
        """x where the flank first crosses the pitch circle (y = 0), linear interpolation (mm)."""
        return _pitch_crossing(self.points)


def _points_tooth(points, smoothing_mm, points_file) -> PointsTooth:
    return PointsTooth(points=points, smoothing_mm=smoothing_mm, points_file=points_file)


Tooth = DctaTooth | InvoluteTooth | PointsTooth
_TOOTH_TYPES = (DctaTooth, InvoluteTooth, PointsTooth)


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class WaveGenerator:
    """Wave generator: deflection coefficient ω* (w0 = ω*·m) and contour.

    ``roller_angle_deg`` (four rollers only): the polar angle from the major axis at which
    each roller touches the ring-theory bore r_bore + w0 cos 2θ (see
    :func:`profilegen.geometry.wavegen.from_gearset`); ``None`` for two rollers and for cams.
    """

    deflection_coefficient: float = 1.0
    contour: str = "elliptical_cam"
    roller_count: int | None = None
    roller_radius_mm: float | None = None
    roller_angle_deg: float | None = None
    bearing_thickness_mm: float | None = None

    @property
    def roller_angle_rad(self) -> float | None:
        return None if self.roller_angle_deg is None else math.radians(self.roller_angle_deg)


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class Material:
    """Flexspline material (linear elastic) and optional strength limits (MPa)."""

    #: the strength limits the yield checks and the fatigue checks need (the stress stage's)
    YIELD_LIMITS: ClassVar[tuple[str, ...]] = ("yield_strength_mpa",)
    FATIGUE_LIMITS: ClassVar[tuple[str, ...]] = ("bending_endurance_limit_mpa", "shear_endurance_limit_mpa",
                                                 "ultimate_strength_mpa")

    youngs_modulus_mpa: float
    poisson_ratio: float
    yield_strength_mpa: float | None = None
    ultimate_strength_mpa: float | None = None
    bending_endurance_limit_mpa: float | None = None
    shear_endurance_limit_mpa: float | None = None

    @property
    def missing_strength_limits(self) -> tuple[str, ...]:
        """The limits the stress stage's checks need and this material does not give: each missing
        one leaves its checks NOT CHECKED and the verdict INCOMPLETE."""
        return tuple(k for k in (*self.YIELD_LIMITS, *self.FATIGUE_LIMITS) if getattr(self, k) is None)

    @property
    def shear_modulus_mpa(self) -> float:
        """G = E / (2 (1 + ν)) (MPa)."""
        return self.youngs_modulus_mpa / (2.0 * (1.0 + self.poisson_ratio))


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class Torque:
    """Output torques (N·m, as in the files); ``*_nmm`` give N·mm."""

    rated_nm: float
    peak_nm: float
    momentary_nm: float | None = None

    @property
    def rated_nmm(self) -> float:
        return self.rated_nm * 1e3

    @property
    def peak_nmm(self) -> float:
        return self.peak_nm * 1e3

    @property
    def momentary_nmm(self) -> float | None:
        return None if self.momentary_nm is None else self.momentary_nm * 1e3


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class CircularSpline:
    """Radial clearances of the CS against the FS tooth (mm, resolved) and how its flank is
    fitted with an arc–line–arc (``one_sided``: never inside the swept region)."""

    root_clearance_mm: float
    tip_clearance_mm: float
    fit_method: str = "one_sided"
    #: wire EDM: the corners of the CS chain are rounded with wire radius + spark gap (mm)
    #: (``corners = "fillet"``; ``"sharp"`` keeps the sharp chain), see profilegen.profile.rootfillet
    wire_radius_mm: float = 0.125
    spark_gap_mm: float = 0.02
    corners: str = "fillet"
    #: the CS ring's outer diameter (mm), for its STEP solid; None: CS_OUTER_DIAMETER_PER_ROOT × root diameter
    outer_diameter_mm: float | None = None

    @property
    def corner_radius_mm(self) -> float:
        """The smallest inside-corner radius wire EDM cuts: wire radius + spark gap (mm)."""
        return self.wire_radius_mm + self.spark_gap_mm


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class Cup:
    """The cup flexspline beyond its tooth ring (mm), for the loaded contact and the stress
    stage: ``length_mm`` l, from the cup bottom to the tooth ring's mid-face (the
    semi-membrane length of seed 002, k = l / 2r_m); ``face_width_mm`` b, the teeth's face
    width; ``bottom_thickness_mm`` t of the cup bottom (seed 002's plate, seed 000's
    diaphragm); ``boss_radius_mm`` r0, where the bottom is clamped to its boss;
    ``root_fillet_radius_mm`` r1, the fillet where a tooth meets the rim (seed 001). For the 3D
    cup (:class:`profilegen.rim.cup.CupGeometry`, same frame: z from the mid-plane of the cup
    bottom toward the open end): ``wall_thickness_mm`` t_w of the wall between the bottom and
    the tooth ring (same bore; default the rim thickness δ), ``bearing_width_mm`` and
    ``bearing_center_mm`` (z) of the wave-generator bearing that presses the bore (default: the
    face width, centred on the mid-face z = l). Absent fields are ESTIMATES from the gear (see
    docs/gearset.md); :func:`check_cup_geometry` holds the rules that relate them."""

    length_mm: float
    face_width_mm: float
    bottom_thickness_mm: float
    boss_radius_mm: float
    root_fillet_radius_mm: float
    wall_thickness_mm: float | None = None
    bearing_width_mm: float | None = None
    bearing_center_mm: float | None = None


@dataclass(frozen=True, slots=True, eq=False, kw_only=True)
class Face:
    """The face width (:mod:`profilegen.face`, the cup3d rim tier): ``design_section_z_mm`` the
    axial section whose envelope the one CS profile is cut from (z from the cup bottom's
    mid-plane, on the tooth ring; None or "auto": the interference-free section with the least
    largest backlash); ``sections`` axial sections over the tooth ring; the FS tooth
    modification along the face, ``taper_mm_per_mm`` (tooth thickness change per mm toward the
    open end) and ``crowning_mm`` (thinning at both face ends against the mid-face) — None or
    "auto": computed (:func:`profilegen.face.solve_modification`)."""

    design_section_z_mm: float | None = None
    sections: int = 5
    taper_mm_per_mm: float | None = None
    crowning_mm: float | None = None


def check_cup_geometry(*, neutral_radius_mm, ring_thickness_mm, length_mm, face_width_mm, bottom_thickness_mm,
                       boss_radius_mm, wall_thickness_mm=None, bearing_width_mm=None, bearing_center_mm=None,
                       error: type = GearSetError, prefix: str = "", ring_name: str = "ring_thickness_mm") -> dict:
    """The rules that relate the cup's dimensions (mm), written once: the gear-set reader
    (``[cup]``, ``error=GearSetError``, ``prefix="cup."``) and
    :class:`profilegen.rim.cup.CupGeometry` (``error=CupError``) both call it. Checked in this
    order, each range from the values before it: r_m > 0; the tooth ring's thickness δ
    (``ring_name``) in (0, r_m); l > 0; the bottom t_b in (0, l); the boss r0 in (0, r_bore)
    with r_bore = r_m − δ/2, and t_b < r_bore − r0 (a bottom as thick as its annulus is wide is
    no diaphragm); the face b in (0, 2l − t_b) (the tooth ring must end above the bottom);
    the wall t_w in (δ/2, δ] (same bore as the ring; the 3D cup reads ω on r_m, which must
    run through the wall); the bearing's width in (0, b] and its centre z within the tooth ring
    (its edges at l ± b/2 at most). Returns the values with the defaults filled in (t_w = δ,
    bearing width b, centre l); raises ``error`` naming ``prefix + field``, its value, mm and
    the range."""
    from .. import checks

    def number(name, value, low, high=math.inf, *, low_open=True, high_open=True, why=""):
        try:  # a name with a section of its own ("gear.rim_thickness_mm") is not prefixed
            return checks.number(name if "." in name else prefix + name, value, "mm", low, high, low_open=low_open, high_open=high_open,
                                 error=error)
        except error as exc:
            raise error(f"{exc} ({why})" if why else str(exc)) from None

    r_m = number("neutral_radius_mm", neutral_radius_mm, 0.0)
    t = number(ring_name, ring_thickness_mm, 0.0, r_m, why="the tooth ring's radial thickness δ")
    length = number("length_mm", length_mm, 0.0, why="cup bottom to the tooth ring's mid-face")
    t_b = number("bottom_thickness_mm", bottom_thickness_mm, 0.0, length, why="thinner than the cup is long")
    r_bore = r_m - 0.5 * t
    r0 = number("boss_radius_mm", boss_radius_mm, 0.0, r_bore, why=f"inside the bore, r_bore = {r_bore:g} mm")
    number("bottom_thickness_mm", t_b, 0.0, r_bore - r0,
           why=f"thinner than the bottom's annulus from the boss to the bore is wide, r_bore − r0 = {r_bore - r0:g} mm")
    b = number("face_width_mm", face_width_mm, 0.0, 2.0 * length - t_b,
               why="the tooth ring l ± b/2 must end above the cup bottom: b < 2l − t_b")
    t_w = t if wall_thickness_mm is None else number(
        "wall_thickness_mm", wall_thickness_mm, 0.5 * t, t, high_open=False,
        why=f"the wall between the bottom and the tooth ring, same bore, at most the ring's δ = {t:g} mm and "
            "thicker than δ/2 (ω is read on r_m, which must run through the wall)")
    bw = b if bearing_width_mm is None else number("bearing_width_mm", bearing_width_mm, 0.0, b, high_open=False,
                                                   why="the bearing presses the bore within the tooth ring")
    lo, hi = length - 0.5 * b + 0.5 * bw, length + 0.5 * b - 0.5 * bw
    # round-off: a bearing as wide as the face has lo = hi = l only to the last bit (a file written
    # from a set whose l is 0.6·d read 7.199999999999999 against [7.2, 7.2]); 1e-9 mm is no geometry
    slack = 1e-9 * max(1.0, abs(length))
    bc = length if bearing_center_mm is None else min(max(number(
        "bearing_center_mm", bearing_center_mm, lo - slack, hi + slack, low_open=False, high_open=False,
        why=f"z from the cup bottom's mid-plane; the tooth ring l ± b/2 = [{length - 0.5 * b:g}, "
            f"{length + 0.5 * b:g}] mm must hold the whole bearing width"), lo), hi)
    return {"neutral_radius_mm": r_m, "ring_thickness_mm": t, "length_mm": length, "face_width_mm": b,
            "bottom_thickness_mm": t_b, "boss_radius_mm": r0, "wall_thickness_mm": t_w, "bearing_width_mm": bw,
            "bearing_center_mm": bc}


SECTION_TYPES = {
    "gear": Gear,
    "tooth": _TOOTH_TYPES,
    "wave_generator": WaveGenerator,
    "material": Material,
    "torque": Torque,
    "circular_spline": CircularSpline,
    "cup": Cup,
    "face": Face,
    "requirements": Requirements,
}


def _pitch_crossing(points: np.ndarray) -> float:
    y = points[:, 1]
    for i in range(len(y) - 1):
        y0, y1 = y[i], y[i + 1]
        if y0 == 0.0:
            return float(points[i, 0])
        if (y0 < 0.0) != (y1 < 0.0):
            s = y0 / (y0 - y1)
            return float(points[i, 0] + s * (points[i + 1, 0] - points[i, 0]))
    if y[-1] == 0.0:
        return float(points[-1, 0])
    raise GearSetError("tooth.points: the flank does not cross the pitch circle (y = 0)")
