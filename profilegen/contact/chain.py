"""The compliance chain between input and output, and the torsional curve in both directions.

The loaded contact (:mod:`profilegen.contact.compliance`) models the mesh only. This module
adds what the torque passes through besides it — the cup wall and bottom in torsion, the CS body
outside the modelled sector (series terms: K_total⁻¹ = K_mesh⁻¹ + Σ K_i⁻¹) — and the
wave-generator balls as Hertz springs in the contact's ball supports, and solves the curve of
rotation against torque on both flanks. Units mm, N, MPa inside; stiffness N·m/rad, torque N·m
outside.

Entry points:

* :func:`whole_gear_curve` ``(design, contact=None)`` → :class:`TorsionalCurve`: what the
  contact stage runs — the curve's torques (:func:`curve_torques_nm`), K1–K3 on the catalogue
  row of the set's size and ratio (:func:`catalogue_for`), lost motion; its
  :meth:`~TorsionalCurve.to_dict` is ``contact.json["torsional"]``, its
  :meth:`~TorsionalCurve.headline` ``design.json["contact"]["torsional"]``;
* :func:`torsional_curve` ``(design, torques_nm)`` → :class:`TorsionalCurve` at given signed
  torques (``method="continuation"``, default, or the ``"lemke"`` reference; ``face_slices``:
  the face as axial slices, :mod:`profilegen.contact.face_curve`);
* :func:`compliance_chain` ``(gearset)`` → :class:`ComplianceChain` (its parts, each a
  :class:`ChainPart`, and the :class:`BallBearing`); the parts' formulas :func:`tube_torsion_stiffness`,
  :func:`thick_tube_torsion_stiffness`, :func:`annulus_torsion_stiffness`, the cup checked by
  :func:`cup_torsion_fem`; :func:`hertz_point_contact` → :class:`HertzContact`.

Errors: :class:`ChainError` (a ``ValueError``) naming the bad argument — a gear set without a cup
or with a wall too short for its tooth ring, a CS held inside the modelled sector, a bearing that
is not a :class:`BallBearing`, a torque that is zero or not finite, breakpoints missing where no
catalogue row applies; :class:`~profilegen.errors.ConvergenceError` when the Hertz ball springs
do not settle or the cup's FEM check fails.

The models (their formulas, the bearing, what is left out) and the curve's definitions (K1–K3,
backlash, lost motion): docs/theory/torsion.md, "The compliance chain".
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from functools import partial

import numpy as np

from .. import checks
from ..blas import one_blas_thread
from ..stagecache import checkpoint
from ..errors import ConvergenceError
from ..results import json_ready, readonly as _readonly
from ..geometry.wgbearing import BallBearing, ChainError, HertzContact, hertz_point_contact  # noqa: F401 (re-exported: the chain's bearing)
from .cs_ring import cs_held_radius  # noqa: F401 (re-exported: where the chain holds the CS)
from .springs import ball_totals
from .reduced import ReducedZone, zone_solution, SpringIteration  # noqa: F401 (the continuation's pieces, used here)

__all__ = [
    "ARCMIN_PER_RAD",
    "BallBearing",
    "ChainError",
    "ChainPart",
    "ComplianceChain",
    "HertzContact",
    "TorsionalCurve",
    "annulus_torsion_stiffness",
    "compliance_chain",
    "catalogue_for",
    "catalogue_size",
    "cup_torsion_fem",
    "curve_ladder_nm",
    "curve_torques_nm",
    "hertz_point_contact",
    "thick_tube_torsion_stiffness",
    "torsional_curve",
    "whole_gear_curve",
    "tube_torsion_stiffness",
]

log = logging.getLogger(__name__)

ARCMIN_PER_RAD = 180.0 * 60.0 / math.pi

#: The catalogue's sizes (CSF/CSG/SHF series): the nominal pitch diameter in tenths of an inch
CATALOGUE_SIZES = (8, 11, 14, 17, 20, 25, 32, 40, 45, 50, 58, 65, 80, 90, 100)


def catalogue_size(gearset) -> int | None:
    """The catalogue size of a gear set: the size whose nominal pitch diameter (size × 2.54 mm)
    is nearest the FS pitch diameter, within 8 % (size 40: 101.6 mm; the default set's 100 mm
    is size 40); None when no size is that near."""
    g = gearset.gear
    d = float(g.module_mm) * int(g.flexspline_teeth)
    size = min(CATALOGUE_SIZES, key=lambda n: abs(math.log(d / (2.54 * n))))
    return size if abs(d / (2.54 * size) - 1.0) <= 0.08 else None


def catalogue_for(gearset) -> dict | None:
    """The catalogue values the gear set is compared with, or None: the row of
    :func:`profilegen.contact.catalogue.catalogue_row` for its size (:func:`catalogue_size`)
    and ratio — with its ``source``, the ``ratio`` of the table used and a ``note`` when that
    is not the set's, the ratcheting torque — None when the catalogue module has no row for the
    size at or below the ratio (one source of truth: :mod:`profilegen.contact.catalogue`)."""
    from .catalogue import catalogue_row

    size = catalogue_size(gearset)
    if size is None:
        return None
    ratio = float(gearset.ratio)
    try:
        out = dict(catalogue_row(size, int(round(ratio))))
    except ValueError:  # no row for this size, or none at or below this ratio
        return None
    out["size"] = size
    if out.get("ratio") is not None and float(out["ratio"]) != ratio and not out.get("note"):
        out["note"] = (f"the catalogue's table is for ratio {float(out['ratio']):g}, this set's ratio is {ratio:g} "
                       "(the catalogue lists ratios ≥ 80 stiffer)")
    return out


#: the torsional curve's lowest magnitude as a fraction of its highest (the momentary torque): about
#: 2 % of the rated torque of a catalogue gear, whose momentary torque is ~4.5× the rated one — below
#: the lost motion's 3 %, which then starts from a rung just below it (a rated-torque change: 0.07
#: instead of 0.11 s on the default set's design scene, where 3 % fell below 0.007 × the momentary)
CURVE_LOWEST_PER_TOP = 0.005


def curve_ladder_nm(gearset, breakpoints_nm=None, *, count: int = 12) -> np.ndarray:
    """The magnitudes of a design's torsional curve that do not read the rated torque (N·m):
    ``count`` spaced geometrically from :data:`CURVE_LOWEST_PER_TOP` of the momentary torque (the
    peak when the set has none) to it, the peak torque, and the breakpoints T1, T2 when given."""
    count = _whole("count", count, 2)
    tq = gearset.torque
    peak = float(tq.peak_nm)
    top = float(tq.momentary_nm) if tq.momentary_nm is not None else peak
    levels = set(np.geomspace(CURVE_LOWEST_PER_TOP * top, top, count).round(6).tolist()) | {peak, top}
    if breakpoints_nm is not None:
        levels |= {float(t) for t in breakpoints_nm}
    return np.array(sorted(m for m in levels if m > 0.0))


def curve_torques_nm(gearset, breakpoints_nm=None, *, count: int = 12,
                     lost_motion_fraction: float = 0.03) -> np.ndarray:
    """The signed torques of a design's torsional curve (N·m): :func:`curve_ladder_nm`'s
    magnitudes, the rated torque and the lost motion's (``lost_motion_fraction`` of the rated
    torque), both directions — ≥ 2 × ``count`` torques."""
    rated = float(gearset.torque.rated_nm)
    mags = np.union1d(curve_ladder_nm(gearset, breakpoints_nm, count=count), [rated, lost_motion_fraction * rated])
    return np.concatenate([-mags[::-1], mags])


_positive = partial(checks.positive, error=ChainError)
_number = partial(checks.number, error=ChainError)
_whole = partial(checks.whole, error=ChainError)


# --------------------------------------------------------------------------- analytic models


def tube_torsion_stiffness(shear_modulus_mpa: float, radius_mm: float, thickness_mm: float,
                           length_mm: float) -> float:
    """Thin-walled circular tube in torsion: K = G J / L, J = 2π r³ t (N·mm/rad); r the wall's
    mid-surface radius."""
    g = _positive("shear_modulus_mpa", shear_modulus_mpa, "MPa")
    r = _positive("radius_mm", radius_mm)
    t = _positive("thickness_mm", thickness_mm)
    length = _positive("length_mm", length_mm)
    return g * 2.0 * math.pi * r ** 3 * t / length


def thick_tube_torsion_stiffness(shear_modulus_mpa: float, inner_radius_mm: float, outer_radius_mm: float,
                                 length_mm: float) -> float:
    """Circular tube in torsion, exact polar moment: K = G π (r_o⁴ − r_i⁴) / (2L) (N·mm/rad)."""
    g = _positive("shear_modulus_mpa", shear_modulus_mpa, "MPa")
    ri = _positive("inner_radius_mm", inner_radius_mm, allow_zero=True)
    ro = _number("outer_radius_mm", outer_radius_mm, "mm", ri)
    length = _positive("length_mm", length_mm)
    return g * 0.5 * math.pi * (ro ** 4 - ri ** 4) / length


def annulus_torsion_stiffness(shear_modulus_mpa: float, thickness_mm: float, inner_radius_mm: float,
                              outer_radius_mm: float) -> float:
    """Annular plate twisted in its plane (torque T on the inner edge, the outer held, or the
    reverse): τ_rθ = T/(2π r² t), rotation θ = T/(4π G t) (1/r_i² − 1/r_o²), so
    K = 4π G t / (1/r_i² − 1/r_o²) (N·mm/rad)."""
    g = _positive("shear_modulus_mpa", shear_modulus_mpa, "MPa")
    t = _positive("thickness_mm", thickness_mm)
    ri = _positive("inner_radius_mm", inner_radius_mm)
    ro = _number("outer_radius_mm", outer_radius_mm, "mm", ri)
    return 4.0 * math.pi * g * t / (ri ** -2 - ro ** -2)


# --------------------------------------------------------------------------- the chain


@dataclass(frozen=True, slots=True, eq=False)
class ChainPart:
    """One series compliance: ``name``, its ``model`` (words) and ``formula``, its stiffness
    (N·m/rad), the numbers that went in (mm, MPa) and which of them are estimates."""

    name: str
    model: str
    formula: str
    stiffness_nm_per_rad: float
    parameters: dict
    estimates: tuple[str, ...] = ()

    @property
    def compliance_rad_per_nm(self) -> float:
        return 1.0 / self.stiffness_nm_per_rad

    def to_dict(self) -> dict:
        return json_ready({"name": self.name, "model": self.model, "formula": self.formula,
                           "stiffness_nm_per_rad": self.stiffness_nm_per_rad,
                           "compliance_rad_per_nm": self.compliance_rad_per_nm,
                           "parameters": dict(self.parameters), "estimates": list(self.estimates)})


@dataclass(frozen=True, slots=True, eq=False)
class ComplianceChain:
    """The series parts (cup wall, cup bottom, CS body) and the ball bearing that enters the
    contact as springs. ``series_stiffness_nm_per_rad``: (Σ K_i⁻¹)⁻¹."""

    parts: tuple[ChainPart, ...]
    bearing: BallBearing | None
    left_out: tuple[str, ...]

    @property
    def series_compliance_rad_per_nm(self) -> float:
        return float(sum(p.compliance_rad_per_nm for p in self.parts))

    @property
    def series_stiffness_nm_per_rad(self) -> float:
        c = self.series_compliance_rad_per_nm
        return math.inf if c == 0.0 else 1.0 / c

    def part(self, name: str) -> ChainPart:
        for p in self.parts:
            if p.name == name:
                return p
        raise ChainError(f"name = {name!r}: no such part (have {', '.join(p.name for p in self.parts)})")

    def with_mesh(self, mesh_stiffness_nm_per_rad: float) -> float:
        """K_total = (K_mesh⁻¹ + Σ K_i⁻¹)⁻¹ (N·m/rad) for a mesh stiffness (secant or tangent)."""
        k = _positive("mesh_stiffness_nm_per_rad", mesh_stiffness_nm_per_rad, "N·m/rad")
        return 1.0 / (1.0 / k + self.series_compliance_rad_per_nm)

    def to_dict(self) -> dict:
        return json_ready({"parts": [p.to_dict() for p in self.parts],
                           "series_stiffness_nm_per_rad": self.series_stiffness_nm_per_rad,
                           "bearing": None if self.bearing is None else self.bearing.to_dict(),
                           "left_out": list(self.left_out)})


LEFT_OUT = (
    "the bearing's inner ring bending and its fit on the cam; the cam's own compliance",
    "the CS's bolted joint and housing: its ring ovalises as a free thin ring (the upper bound; contact.cs_ring)",
    "the sector model's fixed radial cuts (the CS ring between the zones taken rigid)",
    "coning of the cup (the load is taken even across the face; torsional_curve(face_slices=N) takes it, "
    "contact.face_curve) and the cup's bending under the tooth forces",
    "the balls' preload from pinching the rim (lightly loaded balls come out softer)",
    "friction: no hysteresis, loading and unloading give one curve",
)


def compliance_chain(gearset, *, cs_sector_radius_mm: float | None = None, cs_held_radius_mm: float | None = None,
                     cs_width_mm: float | None = None, bearing: BallBearing | None | bool = True) -> ComplianceChain:
    """The compliances between input and output that the mesh model leaves out (module
    docstring), for a gear set. ``cs_sector_radius_mm``: where the compliance model holds the
    CS (default its 1.1 × the CS pitch radius); ``cs_held_radius_mm``: where the CS is held
    (default the CS outer radius); ``cs_width_mm``: the CS's width (default the face width);
    ``bearing``: a :class:`BallBearing`, True for :meth:`BallBearing.from_gearset`, or
    None/False for rigid ball supports."""
    g, cup, mat = gearset.gear, gearset.cup, gearset.material
    if cup is None:
        raise ChainError("gearset.cup: the cup is needed (its fields default to estimates when the gear is valid)")
    shear = float(mat.shear_modulus_mpa)
    r_m, t = float(g.neutral_radius_mm), float(g.rim_thickness_mm)
    length, b, t_b, r0 = float(cup.length_mm), float(cup.face_width_mm), float(cup.bottom_thickness_mm), \
        float(cup.boss_radius_mm)
    # the wall below the tooth ring: [cup] wall_thickness_mm (same bore, turned thinner outside;
    # default the rim thickness), its mid-surface at r_bore + t_w/2
    t_w = getattr(cup, "wall_thickness_mm", None)
    t_w = t if t_w is None else float(t_w)
    r_w = r_m - 0.5 * t + 0.5 * t_w
    wall_len = length - 0.5 * b - 0.5 * t_b
    if not wall_len > 0.0:
        raise ChainError(f"cup.length_mm = {length:.6g} mm: the wall must reach below the tooth ring "
                         f"(length > face_width/2 + bottom_thickness/2 = {0.5 * b + 0.5 * t_b:.6g} mm)")
    eff_len = wall_len + b / 3.0
    # in series: the wall (t_w at r_w) and b/3 of the tooth ring (δ at r_m); one tube when t_w = δ
    k_wall = 1e-3 / (1.0 / tube_torsion_stiffness(shear, r_w, t_w, wall_len)
                     + 1.0 / tube_torsion_stiffness(shear, r_m, t, b / 3.0))
    k_bottom = annulus_torsion_stiffness(shear, t_b, r0, r_w) * 1e-3
    r_sector = 1.1 * float(g.cs_pitch_radius_mm) if cs_sector_radius_mm is None else \
        _positive("cs_sector_radius_mm", cs_sector_radius_mm)
    est_cs = []
    if cs_held_radius_mm is None:
        r_held, note = cs_held_radius(gearset)
        if note:
            est_cs.append(note)
        else:
            est_cs.append(f"cs_held_radius_mm = {r_held:.4g} (the CS outer radius; its bolt circle is a little inside)")
    else:
        r_held = _positive("cs_held_radius_mm", cs_held_radius_mm)
    if not r_held > r_sector:
        raise ChainError(f"cs_held_radius_mm = {r_held:.6g} mm: must be > the sector's outer radius {r_sector:.6g} mm")
    width = b if cs_width_mm is None else _positive("cs_width_mm", cs_width_mm)
    if cs_width_mm is None:
        est_cs.append(f"cs_width_mm = {width:.4g} (the face width)")
    k_cs = annulus_torsion_stiffness(shear, width, r_sector, r_held) * 1e-3
    cup_est = tuple(f"cup.{k} (default estimate)" for k in ("length_mm", "face_width_mm", "bottom_thickness_mm",
                                                             "boss_radius_mm"))
    parts = (
        ChainPart("cup_wall", "thin-walled tube in torsion: the wall below the tooth ring ([cup] wall_thickness_mm, "
                  "default the rim thickness) in series with the tooth ring as b/3 of tube (torque entering evenly "
                  "across the face)",
                  "1/K = (l − b/2 − t_b/2) / (G·2π r_w³ t_w) + (b/3) / (G·2π r_m³ δ), r_w = r_m − δ/2 + t_w/2", k_wall,
                  {"shear_modulus_mpa": shear, "radius_mm": r_m, "thickness_mm": t, "wall_thickness_mm": t_w,
                   "wall_radius_mm": r_w, "wall_length_mm": wall_len, "effective_length_mm": eff_len}, cup_est),
        ChainPart("cup_bottom", "annular plate twisted in its plane, boss to the wall's mid-surface",
                  "K = 4π G t_b / (1/r0² − 1/r_w²)", k_bottom,
                  {"shear_modulus_mpa": shear, "thickness_mm": t_b, "inner_radius_mm": r0, "outer_radius_mm": r_w},
                  cup_est),
        ChainPart("cs_body", "annulus in torsion from the compliance model's fixed CS edge to where the CS is held",
                  "K = 4π G w / (1/r_s² − 1/r_h²)", k_cs,
                  {"shear_modulus_mpa": shear, "width_mm": width, "inner_radius_mm": r_sector,
                   "outer_radius_mm": r_held}, tuple(est_cs) + ("CS of the FS's steel",)),
    )
    if bearing is True:
        bearing = BallBearing.from_gearset(gearset)
    elif bearing is False:
        bearing = None
    elif bearing is not None and not isinstance(bearing, BallBearing):
        raise ChainError(f"bearing = {bearing!r}: must be a BallBearing, True (estimated) or None (rigid balls)")
    return ComplianceChain(parts, bearing, LEFT_OUT)


# --------------------------------------------------------------------------- FE check of the cup


def cup_torsion_fem(geometry_or_gearset, *, element_mm: float = 2.0, layers: int = 2,
                    bottom_layers: int | None = None) -> float:
    """Torsional stiffness of the whole cup (N·m/rad) from the torsion harmonic n = 0 of the
    body-of-revolution model (:mod:`profilegen.rim.cup.fourier`, scikit-fem 9-node quads):
    boss clamped, the torque put on the bore as a uniform tangential traction over the tooth
    ring (l − b/2 … l + b/2), the stiffness T / θ with θ the work-conjugate (load-weighted
    mean) rotation of the loaded bore — the rotation the contact model's bore sees."""
    from ..rim.cup.fourier import harmonic_stiffness
    from ..rim.cup.geometry import CupGeometry, meridional_mesh

    geometry = geometry_or_gearset if isinstance(geometry_or_gearset, CupGeometry) else \
        CupGeometry.from_gearset(geometry_or_gearset)
    hb = harmonic_stiffness(meridional_mesh(geometry, element_mm=element_mm, layers=layers,
                                            bottom_layers=bottom_layers))
    iu, iw, iv = hb.components()
    r, z = hb.nodes
    g = geometry
    tol = 1e-9 * max(g.outer_radius_mm, g.open_end_mm)
    lo, hi = g.ring_span_mm
    boss = np.flatnonzero(np.abs(r - g.boss_radius_mm) < tol)
    line = np.flatnonzero((np.abs(r - g.bore_radius_mm) < tol) & (z > lo - tol) & (z < hi + tol))
    line = line[np.argsort(z[line])]
    if boss.size == 0 or line.size < 3 or line.size % 2 == 0:
        raise ConvergenceError("cup_torsion_fem: the meridional mesh has no quadratic node line on the tooth ring's bore")
    # consistent nodal forces of a uniform traction τ along z on quadratic edges (1/6, 4/6, 1/6 of each edge)
    zs = z[line]
    w = np.zeros(line.size)
    for k in range(0, line.size - 2, 2):
        h = zs[k + 2] - zs[k]
        w[k:k + 3] += h * np.array([1.0, 4.0, 1.0]) / 6.0
    rb = g.bore_radius_mm
    torque = 1.0e3  # N·mm; V is the physical u_θ, and K_0 carries the 2π of ∫dφ
    tau = torque / (2.0 * math.pi * rb * rb * (hi - lo))
    force = np.zeros(hb.dof)
    force[iv[line]] = 2.0 * math.pi * rb * tau * w
    stiff = hb.stiffness(0)
    fixed = np.concatenate([iu[boss], iw[boss], iv[boss]])
    free = np.setdiff1d(np.arange(hb.dof), fixed)
    from scipy.sparse.linalg import spsolve

    x = np.zeros(hb.dof)
    x[free] = spsolve(stiff[free][:, free].tocsc(), force[free])
    theta = float(force @ x) / torque
    if not (math.isfinite(theta) and theta > 0.0):
        raise ConvergenceError(f"cup_torsion_fem: the rotation came out {theta!r} rad")
    return torque / theta * 1e-3


# --------------------------------------------------------------------------- the torsional curve


@dataclass(frozen=True, slots=True, eq=False)
class TorsionalCurve:
    """Rotation of the FS against the CS (wave generator locked) at signed torques.

    ``torque_nm`` (sorted, no zero); rotations (rad, signed like the torque): ``mesh_rad``
    (the mesh on rigid balls: the contact model as it is), ``mesh_balls_rad`` (the mesh with
    the Hertz ball springs), ``rotation_rad`` (the latter plus the series parts: the whole
    gear as modelled). All include the free play to the loaded flank's first contact θ₀.
    ``flags``: per torque the reason it is beyond the contact model, or None.
    ``backlash_rad``: θ₀(+) + θ₀(−). ``k_nm_per_rad``: {"mesh", "mesh_balls", "total"} →
    per direction ("positive", "negative") {"K1", "K2", "K3", "secant_T1", "secant_T2"};
    ``lost_motion_rad``: {"mesh", "mesh_balls", "total"}. ``compliances_at_rated``: each
    part's compliance (rad per N·m) at the rated torque, the mesh's and the balls' as secants.
    """

    torque_nm: np.ndarray
    mesh_rad: np.ndarray
    mesh_balls_rad: np.ndarray
    rotation_rad: np.ndarray
    teeth_in_contact: np.ndarray
    active_balls: np.ndarray
    flags: tuple
    backlash_rad: float
    first_contact_rad: dict
    breakpoints_nm: dict
    k_nm_per_rad: dict
    lost_motion_rad: dict
    lost_motion_torque_nm: float
    compliances_at_rated: dict
    chain: ComplianceChain
    catalogue: dict | None
    odd_symmetry_defect: float
    time_s: float
    warnings: tuple[str, ...] = field(default=())
    #: "catalogue" (T1, T2 the catalogue's), "given", or "estimate" (fractions of the rated torque)
    breakpoints_source: str = "catalogue"
    #: {+1: (points, compliance), −1: (…)}: pass as ``sides`` to skip building them again
    sides: dict = field(default_factory=dict, repr=False)
    #: across the face (:func:`whole_gear_curve` with the scene's ``face_slices``): the slices'
    #: settings and the one-section curve's headline beside them; None for one section
    face: dict | None = None

    def __post_init__(self):
        for name in ("torque_nm", "mesh_rad", "mesh_balls_rad", "rotation_rad"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        object.__setattr__(self, "teeth_in_contact", _readonly(self.teeth_in_contact, int))
        object.__setattr__(self, "active_balls", _readonly(self.active_balls, int))

    @property
    def rotation_arcmin(self) -> np.ndarray:
        return self.rotation_rad * ARCMIN_PER_RAD

    def rotation_at(self, torque_nm: float) -> float:
        """The whole gear's rotation (rad) at a torque of the curve."""
        hit = np.flatnonzero(self.torque_nm == float(torque_nm))
        if hit.size == 0:
            raise ChainError(f"torque_nm = {torque_nm!r} N·m: not a torque of the curve")
        return float(self.rotation_rad[hit[0]])

    def catalogue_comparison(self) -> dict | None:
        """The catalogue's values, its source, and this model's against them (whole gear,
        positive direction): K1, K2 and the secants at T1 and T2 (the catalogue's secant at
        T2 from its bilinear curve, T2 / (T1/K1 + (T2 − T1)/K2)), and K3 and lost motion
        when the catalogue gives them."""
        cat = self.catalogue
        if cat is None:
            return None
        k = self.k_nm_per_rad["total"]["positive"]
        compared = {}

        def add(name, model, value):
            if value is not None:
                compared[name] = {"model": model, "catalogue": value, "model_over_catalogue": model / value}

        k1, k2, t1, t2 = (cat.get(n) for n in ("K1_nm_per_rad", "K2_nm_per_rad", "T1_nm", "T2_nm"))
        add("K1_nm_per_rad", k["K1"], k1)
        add("K2_nm_per_rad", k["K2"], k2)
        add("K3_nm_per_rad", k["K3"], cat.get("K3_nm_per_rad"))
        if k1 is not None:
            add("secant_T1_nm_per_rad", k["secant_T1"], k1)
        if k1 is not None and k2 is not None and t1 is not None and t2 is not None:
            add("secant_T2_nm_per_rad", k["secant_T2"], t2 / (t1 / k1 + (t2 - t1) / k2))
        add("lost_motion_arcmin", self.lost_motion_rad["total"] * ARCMIN_PER_RAD, cat.get("lost_motion_arcmin"))
        return json_ready({**cat, "compared": compared,
                           "breakpoints_from_catalogue": self.breakpoints_source == "catalogue"})

    def headline(self) -> dict:
        """The figures design.json["contact"]["torsional"] carries (whole gear, N·m/rad, arcmin)."""
        k = self.k_nm_per_rad["total"]
        cmp = self.catalogue_comparison()
        return json_ready({
            "k1_nm_per_rad": k["positive"]["K1"], "k2_nm_per_rad": k["positive"]["K2"],
            "k3_nm_per_rad": k["positive"]["K3"],
            "k1_k2_k3_negative_nm_per_rad": [k["negative"][n] for n in ("K1", "K2", "K3")],
            "secant_t1_nm_per_rad": k["positive"]["secant_T1"], "secant_t2_nm_per_rad": k["positive"]["secant_T2"],
            "breakpoints_nm": self.breakpoints_nm, "breakpoints_source": self.breakpoints_source,
            "lost_motion_arcmin": self.lost_motion_rad["total"] * ARCMIN_PER_RAD,
            "lost_motion_torque_nm": self.lost_motion_torque_nm,
            "backlash_arcmin": self.backlash_rad * ARCMIN_PER_RAD,
            "mesh_share_at_rated": self.compliances_at_rated["mesh_rad_per_nm"]
            / self.compliances_at_rated["total_rad_per_nm"],
            "torques": len(self.torque_nm),
            "beyond_capacity_nm": [float(t) for t, f in zip(self.torque_nm, self.flags) if f is not None],
            "catalogue_source": None if cmp is None else cmp.get("source"),
            "model_over_catalogue": None if cmp is None else
            {n: v["model_over_catalogue"] for n, v in cmp["compared"].items()},
            "face_slices": None if self.face is None else self.face["slices"],
            "one_section": None if self.face is None else self.face["one_section"],
        })

    def to_dict(self) -> dict:
        """JSON-ready, in the names of ``contact.json["torsional"]`` (docs/reference/outputs.md)."""
        k_total = self.k_nm_per_rad["total"]["positive"]
        return json_ready({
            "torque_nm": self.torque_nm.tolist(),
            "rotation_arcmin": self.rotation_arcmin.tolist(),
            "rotation_mesh_arcmin": (self.mesh_rad * ARCMIN_PER_RAD).tolist(),
            "rotation_mesh_balls_arcmin": (self.mesh_balls_rad * ARCMIN_PER_RAD).tolist(),
            "teeth_in_contact_per_zone": self.teeth_in_contact.tolist(),
            "active_balls": self.active_balls.tolist(),
            "beyond_capacity": list(self.flags),
            "k1_nm_per_rad": k_total["K1"], "k2_nm_per_rad": k_total["K2"], "k3_nm_per_rad": k_total["K3"],
            "stiffness_nm_per_rad": self.k_nm_per_rad,
            "breakpoints_nm": self.breakpoints_nm,
            "breakpoints_source": self.breakpoints_source,
            "lost_motion_arcmin": self.lost_motion_rad["total"] * ARCMIN_PER_RAD,
            "lost_motion_mesh_arcmin": self.lost_motion_rad["mesh"] * ARCMIN_PER_RAD,
            "lost_motion_torque_nm": self.lost_motion_torque_nm,
            "backlash_arcmin": self.backlash_rad * ARCMIN_PER_RAD,
            "first_contact_arcmin": {k: v * ARCMIN_PER_RAD for k, v in self.first_contact_rad.items()},
            "hysteresis_arcmin": None,
            "hysteresis_note": "no friction is modelled: loading and unloading give one curve",
            "compliances": self.compliances_at_rated,
            "chain": self.chain.to_dict(),
            "catalogue": self.catalogue_comparison(),
            "odd_symmetry_defect": self.odd_symmetry_defect,
            "face": self.face,
            "time_s": self.time_s,
            "warnings": list(self.warnings),
        })


def _checked_signed_torques(torques_nm) -> np.ndarray:
    try:
        t = np.atleast_1d(np.asarray(torques_nm, dtype=float))
    except (TypeError, ValueError) as exc:
        raise ChainError("torques_nm: must be a list of torques (N·m)") from exc
    if t.ndim != 1 or t.size == 0:
        raise ChainError("torques_nm: must be one torque or a list of torques (N·m)")
    bad = np.flatnonzero(~np.isfinite(t) | (t == 0.0))
    if bad.size:
        raise ChainError(f"torques_nm = {t[bad[0]]!r} N·m: every torque must be finite and ≠ 0 (zero torque is the "
                         "backlash, reported on its own; the sign is the direction)")
    return t


def _solve_side(points, compliance, magnitude_nm: float, bearing: BallBearing | None, *, settle_iterations: int,
                spring_iterations: int, spring_tol: float, start_springs=None):
    """The reference for one flank at |T|: the window's balls (:func:`_solve_side_window`) or
    every ball one-sided at its gap (:func:`_solve_side_unilateral`), as the compliance says."""
    if compliance.ball_supports == "all":
        return _solve_side_unilateral(points, compliance, magnitude_nm, bearing, spring_iterations=spring_iterations,
                                      spring_tol=spring_tol, start_springs=start_springs)
    return _solve_side_window(points, compliance, magnitude_nm, bearing, settle_iterations=settle_iterations,
                              spring_iterations=spring_iterations, spring_tol=spring_tol, start_springs=start_springs)


def _solve_side_unilateral(points, compliance, magnitude_nm: float, bearing: BallBearing | None, *,
                           spring_iterations: int, spring_tol: float, start_springs=None):
    """One flank at |T| with every ball a one-sided support at its no-load gap: Lemke from
    scratch on the teeth and balls (:meth:`~profilegen.contact.compliance.ContactCompliance.
    solve_unilateral`'s LCP) at rigid balls and at every step of the springs' fixed point
    (:class:`SpringIteration`). → (φ rigid balls, φ with springs, teeth, balls, springs)."""
    from dataclasses import replace

    from .analysis import BallReactions

    tz = magnitude_nm / points.zones * 1e3
    # across the face (face_slices) coning can close a slice's gap below zero: the LCP takes the
    # separations from the smallest (φ moves by that, nothing else) and φ gets it back
    shift = min(0.0, float(np.min(points.theta_rad)))

    def lcp(springs):
        sol, react, _ = compliance._solve_unilateral(points.theta_rad - shift, points.lever_mm, tz, springs)
        if shift:
            sol = replace(sol, phi_rad=float(sol.phi_rad) + shift)
        return sol, react

    sol, react = lcp(None)
    rigid_sol, phi_rigid = sol, float(sol.phi_rad)
    if bearing is None:
        return phi_rigid, phi_rigid, sol, rigid_sol, BallReactions(compliance.ball_angle_rad, react), None
    it = SpringIteration(bearing.hertz_coefficient(), spring_tol,
                          None if start_springs is None else np.log(start_springs))
    if start_springs is not None:
        sol, react = lcp(np.exp(it.x))
    for _ in range(spring_iterations):
        if it.step(ball_totals(react, compliance.ball_body)):
            break
        sol, react = lcp(np.exp(it.x))
    else:
        raise ConvergenceError(f"torsional_curve: the Hertz ball springs did not settle in {spring_iterations} "
                               f"iterations at {magnitude_nm:g} N·m")
    return phi_rigid, float(sol.phi_rad), sol, rigid_sol, BallReactions(compliance.ball_angle_rad, react), \
        it.springs


def _solve_side_window(points, compliance, magnitude_nm: float, bearing: BallBearing | None, *,
                       settle_iterations: int, spring_iterations: int, spring_tol: float, start_springs=None):
    """One flank at |T|: the zone's contact with ball settling; with a bearing, the Hertz
    springs iterated to their secant fixed point. → (φ rigid balls, φ with springs, teeth, balls)."""
    from .solvers import solve_lemke

    tz = magnitude_nm / points.zones * 1e3

    def forces_for(matrix):
        return solve_lemke(matrix, points.theta_rad, points.lever_mm, tz).force_n

    def settled_solve(comp):
        first = solve_lemke(comp.matrix_mm_per_n, points.theta_rad, points.lever_mm, tz)
        settled = comp.settle_balls(first.force_n, max_iterations=settle_iterations, solve=forces_for)
        sol = first if settled is comp else solve_lemke(settled.matrix_mm_per_n, points.theta_rad,
                                                        points.lever_mm, tz)
        return settled, sol

    comp, sol = settled_solve(compliance.with_balls(compliance.ball_active, ball_compliance_mm_per_n=None))
    phi_rigid = float(sol.phi_rad)
    rigid_sol = sol
    if bearing is None:
        return phi_rigid, phi_rigid, sol, rigid_sol, comp, None
    # the secant springs' fixed point (SpringIteration: Steffensen per ball in log c)
    it = SpringIteration(bearing.hertz_coefficient(), spring_tol,
                          None if start_springs is None else np.log(start_springs))
    if start_springs is not None:
        comp, sol = settled_solve(comp.with_balls(comp.ball_active, ball_compliance_mm_per_n=start_springs))
    iterations = 0
    for _ in range(spring_iterations):
        if it.step(ball_totals(comp.ball_reactions(sol.force_n), comp.ball_body)):
            break
        comp, sol = settled_solve(comp.with_balls(comp.ball_active, ball_compliance_mm_per_n=it.springs))
        iterations += 1
    else:
        raise ConvergenceError(f"torsional_curve: the Hertz ball springs did not settle in {spring_iterations} "
                               f"iterations at {magnitude_nm:g} N·m")
    log.debug("torsional_curve: %d spring iterations at %g N·m", iterations, magnitude_nm)
    return phi_rigid, float(sol.phi_rad), sol, rigid_sol, comp, it.springs


def _stiffnesses(phi_of, theta0: float, t1: float, t2: float, t3: float) -> dict:
    """The catalogue's K1, K2, K3 on the elastic rotation, and the secants T/φ at T1 and T2."""
    e1, e2, e3 = phi_of(t1) - theta0, phi_of(t2) - theta0, phi_of(t3) - theta0
    return {"K1": t1 / e1, "K2": (t2 - t1) / (e2 - e1), "K3": (t3 - t2) / (e3 - e2),
            "secant_T1": t1 / e1, "secant_T2": t2 / e2}


def _curve_breakpoints(gs, catalogue: dict | None | bool,
                       breakpoints_nm) -> tuple[dict | None, tuple[float, float, float], str]:
    """The catalogue row (True: the set's own, False/None: none), the breakpoints (T1, T2, T3
    = the peak torque) and where T1, T2 came from ("given" or "catalogue")."""
    if catalogue is True:
        catalogue = catalogue_for(gs)
    elif catalogue is False:
        catalogue = None
    source = "given"
    if breakpoints_nm is None:
        if catalogue is None:
            raise ChainError("breakpoints_nm: give (T1, T2) in N·m when no catalogue is given or the set's size has "
                             "no catalogue row")
        breakpoints_nm, source = (catalogue["T1_nm"], catalogue["T2_nm"]), "catalogue"
    t1 = _positive("breakpoints_nm[0]", breakpoints_nm[0], "N·m")
    t2 = _number("breakpoints_nm[1]", breakpoints_nm[1], "N·m", t1)
    t3 = float(gs.torque.peak_nm)
    if not t3 > t2:
        raise ChainError(f"torque.peak_nm = {t3:g} N·m: must exceed T2 = {t2:g} N·m for K3 (T2 … the peak torque)")
    return catalogue, (t1, t2, t3), source


def _flanks(inputs, sides: dict | None, *, stations: int, max_gap_mm: float, ball_supports: str) -> dict:
    """Both flanks' {±1: (points, compliance)}: ``sides`` checked, or built when None."""
    from .compliance import ContactCompliance
    from .points import contact_points

    if sides is None:
        sides = {}
        for s in (1, -1):
            pts = contact_points(inputs, side=s, stations=stations, max_gap_mm=max_gap_mm)
            comp = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                           ball_supports=ball_supports)
            sides[s] = (pts, comp)
    if set(sides) != {1, -1}:
        raise ChainError("sides: must map +1 and −1 to (points, compliance)")
    for s, (pts, _) in sides.items():
        if pts.side != s:
            raise ChainError(f"sides[{s}]: its points are of side {pts.side}")
    return sides


class _FlankSolver:
    """Each flank's solution at a torque magnitude, cached by (side, |T|): (rotation of the
    rigid-ball mesh, with the ball springs, the load case, its notes)."""

    def __init__(self, sides: dict, chain: ComplianceChain, *, settle_iterations: int, spring_iterations: int,
                 spring_tol: float):
        self.sides, self.chain = sides, chain
        self.settle_iterations, self.spring_iterations, self.spring_tol = (settle_iterations, spring_iterations,
                                                                           spring_tol)
        self.cache: dict[tuple[int, float], tuple] = {}
        # each flank's latest (|T|, converged springs): the next torque starts there
        self.last_springs: dict[int, tuple] = {}

    def start(self, side: int, magnitude: float):
        """The springs to start the reference solve from: the flank's latest, scaled to ``magnitude``."""
        if side not in self.last_springs:
            return None
        previous, springs = self.last_springs[side]
        return springs * (magnitude / previous) ** (-1.0 / 3.0)  # ball loads ∝ T roughly, c ∝ Q^(−1/3)

    def solve(self, side: int, magnitude: float):
        """The flank's solution at |T| = ``magnitude``: cached, else the reference (:func:`_solve_side`)."""
        from .analysis import load_case

        key = (side, float(magnitude))
        if key not in self.cache:
            checkpoint()
            pts, comp = self.sides[side]
            phi_r, phi_b, sol, rigid_sol, settled, springs = _solve_side(
                pts, comp, magnitude, self.chain.bearing, settle_iterations=self.settle_iterations,
                spring_iterations=self.spring_iterations, spring_tol=self.spring_tol,
                start_springs=self.start(side, magnitude))
            if springs is not None:
                self.last_springs[side] = (float(magnitude), springs)
            case, notes = load_case(pts, magnitude, sol, settled)
            self.cache[key] = (phi_r, phi_b, case, notes)
        return self.cache[key]

    def continuation(self, side: int, magnitudes, *, ladder=None, gearset=None) -> None:
        """Fill the cache for one flank at ``magnitudes`` (|T|).

        The rungs — the magnitudes in ``ladder`` (all of them when None) — are solved ascending,
        each from the one before (:meth:`_ladder`); every other magnitude from the rung just below
        it (the lowest from the start), alone. So each result is a function of the flank, the
        ladder and its own |T|, not of the other torques asked for: a caller whose ladder does not
        read the rated torque (:func:`whole_gear_curve`) gets, on a rated-torque change inside an
        engine's design, the rungs from the earlier design (``gearset``: the set, for the reuse's
        key) and solves only the few torques the rated torque sets."""
        mags = sorted({float(m) for m in magnitudes})
        keep = set(mags) if ladder is None else {float(m) for m in ladder}
        rungs = tuple(m for m in mags if m in keep)
        pts, comp = self.sides[side]
        bearing = self.chain.bearing
        caps = (self.settle_iterations, self.spring_iterations, self.spring_tol)

        def make():
            return self._ladder(side, rungs)

        if gearset is None:
            entries, states = make()
        else:
            from ..stagecache import reuse
            from .analysis import FLANK_SECTIONS

            key = (side, rungs, caps, None if bearing is None else bearing.to_dict())
            entries, states = reuse("curve_ladder", make, gearset=gearset, sections=FLANK_SECTIONS, key=key,
                                    owners=(pts, comp))
        for m in rungs:
            self.cache.setdefault((side, m), entries[m])
        zone = None
        for m in mags:
            if (side, m) in self.cache:
                continue
            below = [r for r in rungs if r < m and r in states]
            if zone is None:
                zone = ReducedZone(pts, comp, bearing)
            state = states[below[-1]] if below else self._initial(pts, comp)
            entry = self._step(zone, side, m, *state)
            self.cache[(side, m)] = entry[0] if entry is not None else self._reference(side, m, None)[:4]

    @staticmethod
    def _initial(pts, comp):
        """The continuation's start: the flank's first point loaded, the no-load ball set, no springs."""
        start = np.zeros(pts.count, bool)
        start[int(np.argmin(pts.theta_rad))] = True
        rigid = (start, np.asarray(comp.ball_active, bool), None)
        return rigid, rigid, None

    def _ladder(self, side: int, rungs) -> tuple[dict, dict]:
        """The rungs ascending, each from the one before: → ({|T|: cache entry}, {|T|: the state the
        next torque starts from}) — a rung solved by the reference (the reduced loop cycled)
        leaves no state, and the next starts from the last one that did."""
        pts, comp = self.sides[side]
        zone = ReducedZone(pts, comp, self.chain.bearing)
        state = self._initial(pts, comp)
        entries, states, last = {}, {}, None
        for m in rungs:
            checkpoint()  # an engine's design stops here when superseded (a torque's solve: milliseconds)
            step = self._step(zone, side, m, *state)
            if step is None:  # the reduced loop cycled or did not end: the reference for this torque
                entries[m] = self._reference(side, m, last)
                springs = entries[m][4]
                last = None if springs is None else (m, springs)
                entries[m] = entries[m][:4]
                continue
            entries[m], state = step
            states[m] = state
        return entries, states

    def _step(self, zone, side: int, m: float, rigid_state, spring_state, previous):
        """One torque of the continuation from a state: → (cache entry, the next state) or None."""
        from .analysis import BallReactions, load_case

        chain, spring_tol = self.chain, self.spring_tol
        pts, comp = self.sides[side]
        cap = self.settle_iterations + self.spring_iterations
        tm = time.perf_counter()
        rigid = zone.solve(m, rigid_state, springs_on=False, max_iterations=cap, spring_tol=spring_tol)
        loaded, active, x = spring_state
        if x is not None:
            x = x - math.log(m / previous) / 3.0  # ball loads ∝ T roughly, c ∝ Q^(−1/3)
        springs = None if rigid is None else zone.solve(
            m, (loaded, active, x), springs_on=chain.bearing is not None, max_iterations=cap, spring_tol=spring_tol)
        if springs is None:
            log.info("torsional_curve: the reference solve at %g N·m (side %+d)", m, side)
            return None
        sol = zone_solution(zone, m, springs, tm)
        balls = BallReactions(comp.ball_angle_rad, springs["reactions"], springs["active"])
        case, notes = load_case(pts, m, sol, balls)
        entry = (float(rigid["phi"]), float(springs["phi"]), case, notes)
        state = ((rigid["loaded"], rigid["active"], None), (springs["loaded"], springs["active"],
                                                          springs["log_springs"]), m)
        return entry, state

    def _reference(self, side: int, m: float, last):
        """The reference solve (:func:`_solve_side`) at |T| = ``m``, its springs started from
        ``last`` = (|T|, springs) scaled, or from none: → (φ rigid, φ springs, case, notes, springs)."""
        from .analysis import load_case

        pts, comp = self.sides[side]
        start = None if last is None else last[1] * (m / last[0]) ** (-1.0 / 3.0)
        phi_r, phi_b, sol, _, settled, springs = _solve_side(
            pts, comp, m, self.chain.bearing, settle_iterations=self.settle_iterations,
            spring_iterations=self.spring_iterations, spring_tol=self.spring_tol, start_springs=start)
        case, notes = load_case(pts, m, sol, settled)
        return phi_r, phi_b, case, notes, springs


def _curve_stiffnesses(solve, theta0: dict, series: float, breakpoints: tuple[float, float, float], t_lm: float):
    """K1–K3 of the mesh, the mesh with the balls and the whole chain on each flank, and the
    lost motion (both flanks' rotations at ±``t_lm``) of each."""
    t1, t2, t3 = breakpoints
    k: dict = {}
    lost = {}
    for label, pick in (("mesh", 0), ("mesh_balls", 1), ("total", None)):
        k[label] = {}
        for s, name in ((1, "positive"), (-1, "negative")):
            def phi_of(m, s=s, pick=pick):
                r = solve(s, m)
                return r[1] + m * series if pick is None else r[pick]
            k[label][name] = _stiffnesses(phi_of, theta0[s], t1, t2, t3)
        at = (lambda m, s, pick=pick: (solve(s, m)[1] + m * series) if pick is None else solve(s, m)[pick])
        lost[label] = at(t_lm, 1) + at(t_lm, -1)
    return k, lost


def _odd_symmetry_defect(solve, torques, theta0: dict) -> float:
    """The largest relative difference of the two flanks' rotations at the same |T| both ways."""
    mags = sorted(set(np.abs(torques)) & set(-torques[torques < 0]))
    defect = 0.0
    for m in mags:
        a, b = solve(1, m)[1] - theta0[1], solve(-1, m)[1] - theta0[-1]
        defect = max(defect, abs(a - b) / max(abs(a), abs(b)))
    return defect


def torsional_curve(design, torques_nm, *, chain: ComplianceChain | None = None, sides: dict | None = None,
                    breakpoints_nm: tuple[float, float] | None = None, lost_motion_fraction: float = 0.03,
                    catalogue: dict | None | bool = True, stations: int = 5, max_gap_mm: float = 0.12,
                    settle_iterations: int = 20, spring_iterations: int = 60,
                    spring_tol: float = 1e-5, method: str = "continuation",
                    ball_supports: str = "all", face_slices=None, ladder_nm=None) -> TorsionalCurve:
    """Rotation against signed torque (N·m; ≠ 0) for a design (or a :class:`~profilegen.
    contact.inputs.ContactInput`), both flanks (docs/theory/torsion.md, "The compliance chain").

    ``chain``: the series parts and the bearing (default :func:`compliance_chain` of the
    design's gear set). ``sides``: {+1: (points, compliance), −1: (…)} from an earlier call
    (``result`` of :func:`~profilegen.contact.analysis.solve_contact` with ``side=±1``) to
    skip building them. ``breakpoints_nm``: (T1, T2) (default the catalogue's); K3 runs from
    T2 to the set's peak torque. ``catalogue``: True (default) for the row of the set's size and
    ratio (:func:`catalogue_for`, from :func:`profilegen.contact.catalogue.catalogue_row`), a
    table, or None. ``lost_motion_fraction``: f of the rated torque.

    ``method``: ``"continuation"`` (default) solves each flank's torques in increasing |T|,
    each from the previous one's loaded points, ball set and springs, on reduced systems
    (:class:`ReducedZone`); ``"lemke"`` is the reference: every torque from scratch by
    Lemke's method on the assembled compliance, settling and springs iterated around it
    (:func:`_solve_side`). Both solve the same problem, whose solution is unique: they agree
    to the springs' tolerance (tests/unit/test_compliance_chain.py).

    ``ball_supports``: how the flanks built here hold the rim (:meth:`~profilegen.contact.
    compliance.ContactCompliance.build`): "all" (default; every ball of the zone a one-sided
    support at its no-load gap) or "window" (the balls within the rim's no-load contact angle,
    rigid at zero gap, settled). Given ``sides`` keep their own.

    ``face_slices``: None (default: one section, the load even across the face) or N ≥ 1 / a
    :class:`~profilegen.contact.face_curve.FaceSlices`: each flank as N axial slices sharing the
    rotation, each with its own no-load gaps from the cup's coning (and the FS tooth's
    modification along the face, if given), every ball one-sided with its Hertz spring in every
    slice, the tooth ring's twist in the slices (:mod:`profilegen.contact.face_curve`). One
    slice is the 2D curve; the result's ``sides`` stay the 2D flanks.

    ``ladder_nm``: the magnitudes the continuation climbs through, each from the one before
    (default: every torque solved); any other torque is solved from the ladder's rung just below
    it (:meth:`_FlankSolver.continuation`): a ladder that does not depend on the rated torque
    (:func:`curve_ladder_nm`) makes a rated-torque change inside an engine's design re-solve only
    the torques it sets."""
    from .inputs import ContactInput

    t0 = time.perf_counter()
    torques = np.sort(_checked_signed_torques(torques_nm))
    if method not in ("continuation", "lemke"):
        raise ChainError(f"method = {method!r}: must be 'continuation' or 'lemke'")
    if ball_supports not in ("all", "window"):
        raise ChainError(f"ball_supports = {ball_supports!r}: must be 'all' (every ball one-sided at its no-load gap) "
                         "or 'window' (the balls within the rim's no-load contact angle)")
    f = _number("lost_motion_fraction", lost_motion_fraction, "", 0.0, 0.5)
    if chain is not None and not isinstance(chain, ComplianceChain):
        raise ChainError(f"chain = {chain!r}: must be a ComplianceChain (compliance_chain(gearset)) or None")
    inputs = ContactInput.from_design(design, name="design")
    gs = inputs.gearset
    chain = compliance_chain(gs) if chain is None else chain
    catalogue, (t1, t2, t3), source = _curve_breakpoints(gs, catalogue, breakpoints_nm)
    rated = float(gs.torque.rated_nm)
    t_lm = f * rated

    built_here = sides is None  # flanks of this call alone: their slices are not worth keeping (FaceSlices.apply)
    sides = _flanks(inputs, sides, stations=stations, max_gap_mm=max_gap_mm, ball_supports=ball_supports)
    # the direction of rotation that loads each flank, in the package's angle sense
    rot_pos, rot_neg = sides[1][0].rotation, sides[-1][0].rotation
    warnings: list[str] = []
    sides_2d = sides
    if face_slices is not None:  # each flank as N axial slices (contact.face_curve)
        from .face_curve import FaceSlices

        sides, sliced, notes = FaceSlices.of(face_slices).apply(inputs, sides, chain, keep=not built_here)
        if not isinstance(sliced, ComplianceChain):  # apply returns type(chain)(...); typed object (no import back)
            raise ChainError(f"face_slices: the sliced chain is a {type(sliced).__name__}, not a ComplianceChain")
        chain = sliced
        warnings += notes
    if rot_pos == rot_neg:
        warnings.append("both flanks are loaded by the same direction of rotation: the two sides are not opposite")

    series = chain.series_compliance_rad_per_nm  # rad per N·m
    flanks = _FlankSolver(sides, chain, settle_iterations=settle_iterations, spring_iterations=spring_iterations,
                          spring_tol=spring_tol)
    solve = flanks.solve

    with one_blas_thread():
        if method == "continuation":
            needed = {s: {t1, t2, t3, t_lm} for s in (1, -1)}
            needed[1].add(rated)
            for t in torques:
                needed[1 if t > 0 else -1].add(float(abs(t)))
            for s in (1, -1):
                flanks.continuation(s, needed[s], ladder=ladder_nm, gearset=gs)
        rows = []
        for t in torques:
            side = 1 if t > 0 else -1
            phi_r, phi_b, case, notes = solve(side, abs(t))
            sign = 1.0 if t > 0 else -1.0
            rows.append((sign * phi_r, sign * phi_b, sign * (phi_b + abs(t) * series), case))
            warnings += notes
        theta0 = {s: float(np.min(sides[s][0].theta_rad)) for s in (1, -1)}
        k, lost = _curve_stiffnesses(solve, theta0, series, (t1, t2, t3), t_lm)
        phi_r_rated, phi_b_rated = solve(1, rated)[:2]
    compliances = {
        "mesh_rad_per_nm": (phi_r_rated - theta0[1]) / rated,
        "ball_hertz_rad_per_nm": (phi_b_rated - phi_r_rated) / rated,
        **{f"{p.name}_rad_per_nm": p.compliance_rad_per_nm for p in chain.parts},
    }
    compliances["total_rad_per_nm"] = sum(compliances.values())
    defect = _odd_symmetry_defect(solve, torques, theta0)
    flags = tuple(r[3].beyond_capacity for r in rows)
    return TorsionalCurve(
        torque_nm=torques, mesh_rad=np.array([r[0] for r in rows]), mesh_balls_rad=np.array([r[1] for r in rows]),
        rotation_rad=np.array([r[2] for r in rows]), teeth_in_contact=np.array([r[3].teeth_in_contact for r in rows]),
        active_balls=np.array([int(r[3].ball_active.sum()) for r in rows]), flags=flags,
        backlash_rad=theta0[1] + theta0[-1], first_contact_rad={"positive": theta0[1], "negative": theta0[-1]},
        breakpoints_nm={"T1": t1, "T2": t2, "T3": t3}, k_nm_per_rad=k, lost_motion_rad=lost,
        lost_motion_torque_nm=t_lm, compliances_at_rated=compliances, chain=chain,
        catalogue=None if catalogue is None else dict(catalogue), odd_symmetry_defect=float(defect),
        time_s=time.perf_counter() - t0, warnings=tuple(dict.fromkeys(warnings)), sides=dict(sides_2d),
        breakpoints_source=source)


#: T1, T2 as fractions of the rated torque when no catalogue table is at hand (ESTIMATE: the
#: size-40 table's 54 and 196 N·m against the CSF-40's ~265 N·m rated torque)
ESTIMATED_BREAKPOINTS_PER_RATED = (0.2, 0.75)


def whole_gear_curve(design, contact=None, *, count: int = 12, catalogue: dict | None | bool = True,
                     **options) -> TorsionalCurve:
    """The torsional curve a design run reports: :func:`curve_torques_nm` (≥ 24 torques, both
    directions up to the momentary torque), K1–K3 on the breakpoints of the catalogue table
    for the set's size (:func:`catalogue_for`; without one, T1 and T2 at
    :data:`ESTIMATED_BREAKPOINTS_PER_RATED` of the rated torque, ``breakpoints_source`` =
    "estimate"). ``contact``: the design's :class:`~profilegen.contact.analysis.ContactResult`
    (right flank): its points are reused (its compliance too if it has the ``ball_supports``
    asked for, "all" by default), the left flank is built.
    ``catalogue``: True for :func:`catalogue_for`, or a table, or None. The result keeps no
    flanks (``sides`` empty: it is small enough to pickle and keep in a Design).
    ``options``: :func:`torsional_curve`'s.

    Across the face: when the design's scene asks for ``face_slices`` = N > 0 and the design
    has a face stage (the cup3d tier: the 3D cup's sections, the CS's design section and the
    FS tooth modification the files are made with) and ``options`` give no ``face_slices``,
    the curve is solved as N axial slices with nodes on both face ends (:class:`~profilegen.
    contact.face_curve.FaceSlices`: independent slices, the soft bound; coning of the cup
    pressed on the wave generator), and the one-section curve's headline is kept beside it
    (``face["one_section"]``). Where a slice's coning moves its loaded zone to the edge of the
    teeth searched for the section (a torque flagged "edge tooth"), the slices are solved again on
    both flanks searched twice as deep (``face["max_gap_mm"]``). A scene that asks for slices on a
    run without a face stage gets the one-section curve and a warning saying so."""
    from dataclasses import replace

    from .analysis import flank
    from .compliance import ContactCompliance
    from .inputs import ContactInput

    inputs = ContactInput.from_design(design, name="design")
    gs = inputs.gearset
    cat = catalogue_for(gs) if catalogue is True else (catalogue or None)
    if cat is not None:
        bp, source = (float(cat["T1_nm"]), float(cat["T2_nm"])), "catalogue"
    else:
        rated = float(gs.torque.rated_nm)
        low, high = ESTIMATED_BREAKPOINTS_PER_RATED
        bp, source = (low * rated, high * rated), "estimate"
    stations, max_gap = options.get("stations", 5), options.get("max_gap_mm", 0.12)
    supports = options.get("ball_supports", "all")
    sides = options.pop("sides", None)
    if sides is None and contact is not None and getattr(contact, "compliance", None) is not None:
        pts = contact.points
        if pts.side == 1 and pts.stations == stations and pts.max_gap_mm == max_gap:
            # the right flank's wrap angle: without a rim FEM (sketch) it is a flat-ring solve, the same for both
            wrap = contact.compliance.wrap_half_angle_rad
            left, comp = flank(inputs, -1, stations=stations, max_gap_mm=max_gap, wrap_half_angle_rad=wrap,
                               ball_supports=supports)  # (an engine's design: built once for the geometry)
            right = contact.compliance
            if right.ball_supports != supports:  # a contact solved with other balls: the right flank again
                right = ContactCompliance.build(inputs, pts.fs_point_mm, pts.normal, pts.tooth, pts.cs_point_mm,
                                                wrap_half_angle_rad=wrap, ball_supports=supports)
            sides = {1: (pts, right), -1: (left, comp)}
    torques = curve_torques_nm(gs, bp, count=count, lost_motion_fraction=options.get("lost_motion_fraction", 0.03))
    # the magnitudes that do not read the rated torque (the estimated breakpoints do): a rated-torque
    # change inside an engine's design climbs none of them again
    options.setdefault("ladder_nm", curve_ladder_nm(gs, bp if source == "catalogue" else None, count=count))
    spec, note = _scene_face_slices(design, options)
    deeper = {**options, "max_gap_mm": 2.0 * float(max_gap)}
    if spec is None:
        curve = torsional_curve(inputs, torques, sides=sides, breakpoints_nm=bp, catalogue=cat, **options)
        if _searched_too_shallow(curve):
            curve = torsional_curve(inputs, torques, breakpoints_nm=bp, catalogue=cat, **deeper)
        return replace(curve, sides={}, breakpoints_source=source,
                       warnings=curve.warnings + ((note,) if note else ()))
    t0 = time.perf_counter()
    one = torsional_curve(inputs, torques, sides=sides, breakpoints_nm=bp, catalogue=cat, **options)
    one = replace(one, breakpoints_source=source)
    sliced = torsional_curve(inputs, torques, sides=one.sides, breakpoints_nm=bp, catalogue=cat, face_slices=spec,
                             **options)
    if _searched_too_shallow(sliced):
        # a slice's coning moved its loaded zone to the edge of the teeth searched for the section, or
        # the rotation reached past the separation searched: search twice as deep (both flanks built
        # again) and solve the slices once more
        sliced = torsional_curve(inputs, torques, breakpoints_nm=bp, catalogue=cat, face_slices=spec, **deeper)
    from .face_curve import rim_coupling_length_mm

    mod = spec.modification
    face = {
        "slices": spec.slices, "nodes": spec.nodes, "coning": spec.coning,
        "coupling_length_mm": (rim_coupling_length_mm(gs) if spec.coupling_length_mm is None
                               else spec.coupling_length_mm),
        "design_section_z_mm": spec.design_z_mm,
        "taper_um_per_mm": None if mod is None else float(mod.taper_mm_per_mm) * 1e3,
        "crowning_um": None if mod is None else float(mod.crowning_mm) * 1e3,
        "shift_um_per_mm": None if mod is None else float(getattr(mod, "shift_mm_per_mm", 0.0)) * 1e3,
        "model": ("axial slices graded toward the design section, each with the 3D cup's coning and the face stage's "
                  "tooth modification, sharing the rotation; the FS rim's far field (and the balls' seats) coupled "
                  "along the face over the rim's shell decay length, the teeth's and contacts' local compliance and "
                  "the CS sector per slice, its ring one body across the face; every ball one body, its Hertz "
                  "spring under its shares' summed load (contact.face_curve)"),
        "one_section": one.headline(),
        "max_gap_mm": float(sliced.sides[1][0].max_gap_mm) if sliced.sides else float(max_gap),
    }
    return replace(sliced, sides={}, breakpoints_source=source, face=json_ready(face),
                   time_s=time.perf_counter() - t0)


def _searched_too_shallow(curve) -> bool:
    """Whether some torque of ``curve`` reached the edge of what its flanks searched: a loaded
    edge tooth, every point loaded, or the rotation past the separation searched (the flags of
    :attr:`~profilegen.contact.analysis.LoadCase.beyond_capacity`) — an answer the points searched
    cannot give (shf50_160, verify scene: the sliced curve's rotation reached 133 µm at the
    momentary torque against 120 µm searched, and the stiffness there read 5 % soft)."""
    return any(f is not None for f in curve.flags)


def _scene_face_slices(design, options: dict):
    """(FaceSlices or None, a warning or None) for :func:`whole_gear_curve`: the scene's
    ``face_slices`` on a design with a face stage, unless ``options`` already name them."""
    n = int(getattr(getattr(design, "scene", None), "face_slices", 0) or 0)
    if n <= 0 or "face_slices" in options:
        return None, None
    face = getattr(design, "face", None)
    cup = getattr(getattr(design, "rim", None), "cup", None)
    if face is None or cup is None:
        tier = getattr(getattr(design, "rim", None), "tier", "?")
        return None, (f"the scene asks for face_slices = {n}, but this run has no face stage (rim tier {tier}; "
                      "the face stage runs on the cup3d tier): one section, the load even across the face")
    from .face_curve import FaceSlices

    return FaceSlices(n, "cup", cup, float(face.design_section_z_mm), face.modification, nodes="graded"), None
