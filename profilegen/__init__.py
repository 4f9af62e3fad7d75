"""profilegen — conjugate tooth profiles for strain wave gears (harmonic drives).

Conventions (used everywhere):

* units mm, N, MPa inside; torques in N·m in files and at the CLI; angles in
  radians inside and ``*_deg`` only in files and reports;
* φ is the angle from the wave-generator major axis to a flexspline tooth's
  *undeformed* position, in the wave-generator frame; ω(φ) is the radial
  displacement of the rim's neutral line (outward +), υ(φ) the tangential one
  (toward increasing φ), both read on the neutral line;
* the CS frame has its origin at the gear centre and y along the CS tooth-space
  axis; polar angles run from +y toward +x.

The pipeline, stage by stage:

>>> import profilegen as pg
>>> gs = pg.load_gearset(pg.default_gearset_path())
>>> round(gs.gear.neutral_radius_mm, 9), gs.deflection_mm  # r_m = r1 − dedendum − rim/2
(48.95, 0.5)
>>> rim = pg.solve_rim(gs, tier="design")  # nonlinear ring FEM on the cam + Fourier fit
>>> bool(abs(rim.fem.bore_omega_mm[0] - gs.deflection_mm) < 1e-6)  # the major axis stays on the cam
True
>>> tooth = pg.tooth_from_gearset(gs)
>>> motion = pg.HarmonicDriveMotion(rim.model, 48.95, 2, 202)
>>> env = pg.envelope_of(tooth, motion, cs_teeth=202, waves=2, chord_tol_mm=1e-5)
>>> sorted(env.counts())
['conjugate', 'interfering', 'tip_path']
>>> result = pg.design(gs, scene="sketch")   # all stages, with times and error estimates
>>> result.form.clearance.min_mm > -1e-4
True
"""

import logging

from .errors import ConvergenceError, EnvelopeError, ExportError, GearSetError, ProfilegenError, ToothError

# A library does not print: a script calling design() finds the warnings in the result
# (Design.warnings), not as log records through logging's last-resort handler on its stderr
# (one redesign of the default set printed the same flank-kink warning up to eight times).
# The CLI configures logging's output; a script that wants the records adds its own handler.
logging.getLogger(__name__).addHandler(logging.NullHandler())

__all__ = [
    "Cancelled",
    "CircularSplineForm",
    "ConvergenceError",
    "Design",
    "Engine",
    "Envelope",
    "EnvelopeError",
    "ExportError",
    "GearSet",
    "GearSetError",
    "HarmonicDeformation",
    "HarmonicDriveMotion",
    "ProfilegenError",
    "RackMotion",
    "RimDeformation",
    "SCENES",
    "Scene",
    "ToothError",
    "ToothProfile",
    "circular_spline_form",
    "clearance_map",
    "dcta_tooth",
    "default_gearset_path",
    "design",
    "envelope_of",
    "fit_fourier",
    "fit_sine_series",
    "involute_tooth",
    "list_profiles",
    "load_gearset",
    "new_gearset",
    "optimize",
    "parse_gearset",
    "points_tooth",
    "resolve_gearset",
    "ring_theory",
    "solve_rim",
    "solve_ring",
    "tooth_from_gearset",
    "write_design",
]

__version__ = "0.1.0"

# every name but the errors is loaded on first use: the rim FEM and the series fitters pull in scipy's
# solvers (~0.3 s), the output layer its writers, the stages numpy, scipy.spatial and shapely. The
# command line (``python -m profilegen``, the ``profilegen`` script) imports only the package and its
# cli before main() starts, so a Ctrl-C during the imports that follow ends it like one during the
# stages (exit 130, one line), not with a traceback out of the package's import.
_LAZY = {"write_design": "output.files", "RimDeformation": "rim", "solve_rim": "rim", "solve_ring": "rim", "fit_fourier": "geometry.series",
         "fit_sine_series": "geometry.series", "new_gearset": "gearset.new",
         **dict.fromkeys(("HarmonicDeformation", "ring_theory"), "geometry.deformation"),
         **dict.fromkeys(("Envelope", "envelope_of"), "profile.envelope"),
         **dict.fromkeys(("CircularSplineForm", "circular_spline_form", "clearance_map"), "profile.gearform"),
         **dict.fromkeys(("GearSet", "default_gearset_path", "list_profiles", "load_gearset", "parse_gearset",
                          "resolve_gearset"), "gearset"),
         **dict.fromkeys(("HarmonicDriveMotion", "RackMotion"), "geometry.kinematics"),
         **dict.fromkeys(("Design", "design"), "pipeline.design"),
         **dict.fromkeys(("Engine", "Cancelled"), "pipeline.engine"),
         **dict.fromkeys(("SCENES", "Scene"), "pipeline.scenes"),
         **dict.fromkeys(("ToothProfile", "dcta_tooth", "involute_tooth", "points_tooth", "tooth_from_gearset"), "geometry.teeth")}


def __getattr__(name):
    if name == "optimize":  # the subpackage, callable: profilegen.optimize(spec, out_dir) runs a spec (pymoo on first use)
        import importlib

        return importlib.import_module(".studies.optimize", __name__)
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    if not name.startswith("_"):  # a submodule not imported yet (profilegen.geometry.kinematics.turn, as when the package imported it)
        import importlib
        import importlib.util

        if importlib.util.find_spec(f"{__name__}.{name}") is not None:
            return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
