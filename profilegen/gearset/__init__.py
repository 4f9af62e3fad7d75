"""The gear set: the one input of the pipeline, read from a TOML file in ``profiles/``.

A :class:`GearSet` is a frozen, validated description of one strain wave gear:
the gear data (module, teeth, waves, rim), the flexspline tooth, the wave
generator, the material, the torques and the circular-spline clearances. The
schema (every field: meaning, unit, default, allowed range) is documented in
``docs/gearset.md``; this module is its single implementation.

Conventions
-----------
* Lengths in mm, moduli and stresses in MPa, torques in N·m (as in the files;
  ``Torque.*_nmm`` give N·mm for the solvers), angles in degrees in the file
  (``*_deg``) with ``*_rad`` properties for use inside the package.
* r1 = m·z1/2 is the flexspline (FS) pitch radius, r2 = m·z2/2 the circular
  spline (CS) pitch radius, r_m the radius of the undeformed neutral line of the
  FS rim, U the number of waves, w0 = ω*·m the radial deflection of the neutral
  line on the major axis.
* Tooth points (``kind = "points"``) are given in the *pitch frame* of one FS
  tooth: origin at the pitch point on the tooth axis (y = 0 on the pitch circle
  r1), y radially outward along the tooth axis, x tangential toward the right
  flank. The kinematics frame (origin on the neutral line) is this frame moved
  by ``gear.neutral_to_pitch_mm`` = r1 − r_m along y.

Validation collects every problem before raising one
:class:`~profilegen.errors.GearSetError`; each problem is one line naming the
field path, the value, the unit and the allowed range, e.g.
``gear.module_mm = -0.5 mm: must be in [1e-05, 10] (lower bound: ...)``.

>>> gs = load_gearset(default_gearset_path())
>>> gs.gear.pitch_radius_mm, round(gs.gear.neutral_radius_mm, 6), gs.deflection_mm
(50.0, 48.95, 0.5)
>>> gs.with_values({"wave_generator.deflection_coefficient": 0.8}).deflection_mm
0.4

The package, bottom to top (no module imports one above it):

* :mod:`~profilegen.gearset.sections` — the file schema and the section value types;
* :mod:`~profilegen.gearset.reader` — reading TOML/CSV files and checking every field;
* :mod:`~profilegen.gearset.types` — :class:`GearSet`, :func:`parse_gearset`, :func:`load_gearset`;
* :mod:`~profilegen.gearset.profiles` — the bundled profiles and name lookup.
"""

from __future__ import annotations

# Beyond __all__, the names other modules import from here are re-exported too (noqa: F401):
# looks_like_path, read_toml and read_limited (scene and sweep files), the size limits,
# COEFFICIENT_SUFFIX and Cup, and _points_tooth (a PointsTooth pickled before the package split
# names profilegen.gearset._points_tooth).
from .profiles import default_gearset_path, list_profiles, looks_like_path, profiles_dir, resolve_gearset  # noqa: F401
from .reader import (  # noqa: F401
    MAX_NAME_CHARS,
    MAX_POINTS,
    MAX_POINTS_FILE_BYTES,
    MAX_TEXT_CHARS,
    MAX_TOML_BYTES,
    RIM_PER_DEFLECTION_MIN,
    read_limited,
    read_toml,
)
from .sections import (  # noqa: F401
    _points_tooth,
    COEFFICIENT_SUFFIX,
    FIT_METHODS,
    SCENE_NAMES,
    TOOTH_KINDS,
    WAVE_GENERATOR_CONTOURS,
    CircularSpline,
    Cup,
    Face,
    DctaTooth,
    Gear,
    InvoluteTooth,
    Material,
    PointsTooth,
    Tooth,
    Torque,
    WaveGenerator,
)
from .types import GearSet, load_gearset, parse_gearset

__all__ = [
    "GearSet",
    "Gear",
    "DctaTooth",
    "InvoluteTooth",
    "PointsTooth",
    "Tooth",
    "WaveGenerator",
    "Material",
    "Torque",
    "CircularSpline",
    "FIT_METHODS",
    "SCENE_NAMES",
    "TOOTH_KINDS",
    "WAVE_GENERATOR_CONTOURS",
    "load_gearset",
    "parse_gearset",
    "default_gearset_path",
    "profiles_dir",
    "list_profiles",
    "resolve_gearset",
]
