"""The loaded zone: which teeth carry the torque, where on the flank, at what pressure angle,
and what a profile relief near the wave generator's major axis does to it.

``load_zone(result_or_case, points)`` → :class:`LoadZone`: per FS tooth of one engagement
zone its normal force, the force-weighted effective pressure angle α = asin(n·e_r) (n the
common normal out of the FS tooth, e_r the radial direction at the point: the share of the
force that pushes the rim in), the force-weighted contact position along the FS flank (arc
length t from the root end of the working flank to the tip corner), the no-load gap of the
tooth's closest point, and the *bands* — runs of neighbouring loaded teeth.

Relief
------
:class:`ProfileRelief` adds an initial gap to the contact points (mm, along the common normal;
the same compliance, so the solve is the package's own with the new gaps):

* ``kind="major_axis"``: depth δ on the teeth within ±φ_r of the major axis, falling to zero
  at φ_r (``shape="linear"``: δ(1 − |φ|/φ_r); ``"flat"``: δ throughout). An FS tooth passes
  the major axis every half turn of the wave generator, so a gap that depends on φ is not a
  tooth modification: it stands for a wave-generator contour that lets the rim sit lower by δ
  near the major axis (a flattened cam) — the first-order effect of the relief, with the rim's
  no-load shape otherwise unchanged.
* ``kind="tip"``: an FS tip relief, a tooth modification: depth δ at the tip corner,
  ((t − t_r)/(L − t_r))² below it down to the start t_r (``start_mm``), zero below t_r. With
  the wave-generator balls inside the no-load window only (``ball_supports="window"``) the
  default set's contacts near the major axis sat on the FS tip arc (t ≈ 1.12 of L = 1.124 mm,
  α ≈ 45°); with every ball a one-sided support (the contact's default) they are gone: at
  265 N·m the bands are φ 0…9° (6 teeth, 41 % of the load, α 12.8°) and 30.6…52.2° (13 teeth,
  α 23.5°), and a 5 µm tip relief lowers the mesh stiffness by 2.2 % and raises the largest
  tooth force by 0.5 % (``python tests/benchmarks/loaded_zone.py profiles/default.toml``).

Relief depth 0 gives the same points object (the solve is bitwise unchanged).
:func:`relief_study` solves one torque with and without reliefs on the same compliance and
reports the load redistribution: the largest tooth force, teeth in contact, the rotation and
the secant mesh stiffness.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from profilegen import checks
from profilegen.errors import ProfilegenError
from profilegen.results import json_ready, readonly as _readonly

__all__ = ["LoadZone", "LoadZoneError", "ProfileRelief", "ReliefStudy", "load_zone", "relief_study"]

ARCMIN_PER_RAD = 180.0 * 60.0 / math.pi


class LoadZoneError(ProfilegenError, ValueError):
    """Bad input to the loaded-zone analysis or a relief; names the parameter, value, unit and range."""


# --------------------------------------------------------------------------- the zone


@dataclass(frozen=True, slots=True, eq=False)
class LoadZone:
    """One zone's load pattern at one torque (see the module docstring). Per tooth (``teeth``,
    sorted): ``tooth_phi_deg``, ``tooth_force_n``, ``pressure_angle_deg`` and ``flank_t_mm``
    (force-weighted over the tooth's points; NaN-free: the no-load closest point's for an
    unloaded tooth), ``min_gap_mm`` (the tooth's smallest no-load gap). ``bands``: runs of
    neighbouring loaded teeth, each {"teeth", "phi_deg": [first, last], "force_share",
    "max_force_n", "pressure_angle_deg" (force-weighted)}. ``teeth_total``: the FS teeth z1."""

    torque_nm: float
    rotation_rad: float
    first_contact_rad: float
    teeth: np.ndarray
    tooth_phi_deg: np.ndarray
    tooth_force_n: np.ndarray
    pressure_angle_deg: np.ndarray
    flank_t_mm: np.ndarray
    min_gap_mm: np.ndarray
    bands: tuple
    zones: int
    teeth_total: int
    flank_length_mm: float
    beyond_capacity: str | None = None

    def __post_init__(self):
        for name in ("tooth_phi_deg", "tooth_force_n", "pressure_angle_deg", "flank_t_mm", "min_gap_mm"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        object.__setattr__(self, "teeth", _readonly(self.teeth, int))

    @property
    def teeth_in_contact(self) -> int:
        """Loaded teeth in one zone."""
        return int(np.count_nonzero(self.tooth_force_n > 0.0))

    @property
    def fraction_in_contact(self) -> float:
        """Loaded teeth of the whole gear (U zones) over z1."""
        return self.zones * self.teeth_in_contact / self.teeth_total

    @property
    def max_tooth_force_n(self) -> float:
        return float(self.tooth_force_n.max())

    @property
    def secant_stiffness_nm_per_rad(self) -> float:
        """T / (φ − φ₀): the mesh's secant stiffness, the free play to first contact taken out."""
        return self.torque_nm / (self.rotation_rad - self.first_contact_rad)

    def to_dict(self) -> dict:
        return json_ready({
            "torque_nm": self.torque_nm,
            "rotation_arcmin": self.rotation_rad * ARCMIN_PER_RAD,
            "secant_stiffness_nm_per_rad": self.secant_stiffness_nm_per_rad,
            "teeth_in_contact_per_zone": self.teeth_in_contact,
            "fraction_in_contact": self.fraction_in_contact,
            "max_tooth_force_n": self.max_tooth_force_n,
            "bands": list(self.bands),
            "teeth": self.teeth.tolist(),
            "tooth_phi_deg": self.tooth_phi_deg.tolist(),
            "tooth_force_n": self.tooth_force_n.tolist(),
            "pressure_angle_deg": self.pressure_angle_deg.tolist(),
            "flank_t_mm": self.flank_t_mm.tolist(),
            "flank_length_mm": self.flank_length_mm,
            "min_gap_mm": self.min_gap_mm.tolist(),
            "beyond_capacity": self.beyond_capacity,
        })


def pressure_angle_rad(points) -> np.ndarray:
    """α_k = asin(n_k·e_r) at every contact point (rad; > 0: the force on the FS has an inward
    radial component)."""
    p = np.asarray(points.fs_point_mm, dtype=float)
    e_r = p / np.linalg.norm(p, axis=1)[:, None]
    return np.arcsin(np.clip(np.einsum("ij,ij->i", np.asarray(points.normal), e_r), -1.0, 1.0))


def _bands(teeth, phi_deg, force, alpha_deg) -> tuple:
    loaded = force > 0.0
    total = float(force.sum())
    out = []
    k = 0
    while k < teeth.size:
        if not loaded[k]:
            k += 1
            continue
        j = k
        while j + 1 < teeth.size and loaded[j + 1] and teeth[j + 1] == teeth[j] + 1:
            j += 1
        f = force[k:j + 1]
        out.append({"teeth": [int(teeth[k]), int(teeth[j])], "phi_deg": [float(phi_deg[k]), float(phi_deg[j])],
                    "count": int(j - k + 1), "force_share": float(f.sum() / total) if total > 0 else 0.0,
                    "max_force_n": float(f.max()),
                    "pressure_angle_deg": float(np.sum(f * alpha_deg[k:j + 1]) / f.sum())})
        k = j + 1
    return tuple(out)


def load_zone(case, points, *, teeth_total: int | None = None) -> LoadZone:
    """The load pattern of one :class:`~profilegen.contact.analysis.LoadCase` (``result.cases[i]``)
    on its ``points`` (``result.points``). ``teeth_total``: z1 (default 2·U·the zone's
    half-width, i.e. the points' zone size)."""
    from profilegen.contact.analysis import LoadCase

    if not isinstance(case, LoadCase):
        raise LoadZoneError(f"case: must be a LoadCase (result.cases[i]), got {type(case).__name__}")
    f = np.asarray(case.solution.force_n, dtype=float)
    if f.shape != (points.count,):
        raise LoadZoneError(f"points: {points.count} points do not match the case's {f.size} forces")
    teeth = case.teeth
    slot = np.searchsorted(teeth, points.tooth)
    alpha = np.degrees(pressure_angle_rad(points))
    per_tooth = np.bincount(slot, weights=f, minlength=teeth.size)
    w_alpha = np.bincount(slot, weights=f * alpha, minlength=teeth.size)
    w_t = np.bincount(slot, weights=f * points.t_mm, minlength=teeth.size)
    min_gap = np.full(teeth.size, np.inf)
    np.minimum.at(min_gap, slot, points.gap_mm)
    closest = np.zeros(teeth.size, dtype=int)
    for k in range(teeth.size):
        on = np.flatnonzero(slot == k)
        closest[k] = on[np.argmin(points.gap_mm[on])]
    loaded = per_tooth > 0.0
    alpha_t = np.where(loaded, w_alpha / np.where(loaded, per_tooth, 1.0), alpha[closest])
    t_t = np.where(loaded, w_t / np.where(loaded, per_tooth, 1.0), points.t_mm[closest])
    phi_deg = np.degrees(case.tooth_phi_rad)
    z1 = int(teeth_total) if teeth_total is not None else None
    if z1 is None:
        raise LoadZoneError("teeth_total: give z1 (gearset.gear.flexspline_teeth)")
    return LoadZone(float(case.torque_nm), float(case.rotation_rad), float(np.min(points.theta_rad)), teeth, phi_deg,
                    per_tooth, alpha_t, t_t, min_gap, _bands(teeth, phi_deg, per_tooth, alpha_t), int(points.zones), z1,
                    float(np.max(points.t_mm)), case.beyond_capacity)


# --------------------------------------------------------------------------- relief


@dataclass(frozen=True, slots=True)
class ProfileRelief:
    """An extra initial gap on the contact points (see the module docstring). ``kind``:
    "major_axis" or "tip"; ``depth_mm`` δ ≥ 0; ``half_angle_deg`` φ_r (major_axis); ``shape``:
    "linear" or "flat" (major_axis); ``start_mm`` t_r, arc length on the FS flank where a tip
    relief starts (tip; default 0.8 × the flank length)."""

    kind: str = "major_axis"
    depth_mm: float = 0.0
    half_angle_deg: float = 10.0
    shape: str = "linear"
    start_mm: float | None = None

    def __post_init__(self):
        checks.choice("kind", self.kind, ("major_axis", "tip"), error=LoadZoneError)
        checks.choice("shape", self.shape, ("linear", "flat"), error=LoadZoneError)
        object.__setattr__(self, "depth_mm", checks.number("depth_mm", self.depth_mm, "mm", 0.0, 0.5,
                                                           low_open=False, high_open=False, error=LoadZoneError))
        object.__setattr__(self, "half_angle_deg", checks.number("half_angle_deg", self.half_angle_deg, "deg", 0.0,
                                                                 90.0, high_open=False, error=LoadZoneError))
        if self.start_mm is not None:
            checks.positive("start_mm", self.start_mm, "mm", allow_zero=True, error=LoadZoneError)

    def extra_gap_mm(self, points) -> np.ndarray:
        """The extra gap of every point (mm, ≥ 0)."""
        n = points.count
        if self.depth_mm == 0.0:
            return np.zeros(n)
        if self.kind == "major_axis":
            x = np.abs(np.asarray(points.phi_rad)) / math.radians(self.half_angle_deg)
            inside = x < 1.0
            profile = np.where(inside, 1.0 if self.shape == "flat" else 1.0 - x, 0.0)
            return self.depth_mm * profile
        t = np.asarray(points.t_mm, dtype=float)
        top = float(np.max(t))  # the tip corner: every tooth's last station
        start = 0.8 * top if self.start_mm is None else float(self.start_mm)
        if not start < top:
            raise LoadZoneError(f"start_mm = {start!r} mm: must be below the tip corner's arc length {top:.6g} mm")
        u = np.clip((t - start) / (top - start), 0.0, 1.0)
        return self.depth_mm * u * u

    def apply(self, points):
        """``points`` with the relief added to their no-load gaps (the same object for δ = 0)."""
        if self.depth_mm == 0.0:
            return points
        return dataclasses.replace(points, gap_mm=np.asarray(points.gap_mm) + self.extra_gap_mm(points))

    def to_dict(self) -> dict:
        return {"kind": self.kind, "depth_mm": self.depth_mm, "half_angle_deg": self.half_angle_deg,
                "shape": self.shape, "start_mm": self.start_mm}


@dataclass(frozen=True, slots=True, eq=False)
class ReliefStudy:
    """One torque with no relief (``baseline``) and with each relief (``relieved``, in order)."""

    baseline: LoadZone
    reliefs: tuple[ProfileRelief, ...]
    relieved: tuple[LoadZone, ...]
    warnings: tuple[str, ...] = field(default=())

    def to_dict(self) -> dict:
        def row(z):
            return {"max_tooth_force_n": z.max_tooth_force_n, "teeth_in_contact_per_zone": z.teeth_in_contact,
                    "fraction_in_contact": z.fraction_in_contact, "rotation_arcmin": z.rotation_rad * ARCMIN_PER_RAD,
                    "secant_stiffness_nm_per_rad": z.secant_stiffness_nm_per_rad, "bands": list(z.bands),
                    "beyond_capacity": z.beyond_capacity}

        return json_ready({"torque_nm": self.baseline.torque_nm, "baseline": row(self.baseline),
                           "relieved": [{"relief": r.to_dict(), **row(z)} for r, z in zip(self.reliefs, self.relieved)],
                           "warnings": list(self.warnings)})


def relief_study(design, torque_nm: float, reliefs, *, result=None, stations: int = 5,
                 max_gap_mm: float = 0.12) -> ReliefStudy:
    """The loaded zone at ``torque_nm`` (N·m, > 0) without and with each of ``reliefs``
    (:class:`ProfileRelief`), on one set of points and one compliance (``result``: an earlier
    :func:`~profilegen.contact.analysis.solve_contact` result to take them from). The relieved
    solves are the package's :func:`~profilegen.contact.analysis.solve_contact` with the
    relieved points (ball settling included; rigid balls)."""
    from profilegen.contact.analysis import solve_contact
    from profilegen.contact.inputs import ContactInput

    torque = checks.number("torque_nm", torque_nm, "N·m", error=LoadZoneError)
    if not (math.isfinite(torque) and torque > 0.0):
        raise LoadZoneError(f"torque_nm = {torque_nm!r} N·m: must be finite and > 0")
    reliefs = tuple(reliefs)
    for k, r in enumerate(reliefs):
        if not isinstance(r, ProfileRelief):
            raise LoadZoneError(f"reliefs[{k}]: must be a ProfileRelief, got {type(r).__name__}")
    inputs = ContactInput.from_design(design, name="design")
    z1 = inputs.gearset.gear.flexspline_teeth
    if result is None:
        result = solve_contact(inputs, [torque], stations=stations, max_gap_mm=max_gap_mm)
        case = result.cases[0]
    else:
        case = solve_contact(inputs, [torque], points=result.points, compliance=result.compliance).cases[0]
    base = load_zone(case, result.points, teeth_total=z1)
    zones, warnings = [], []
    for r in reliefs:
        pts = r.apply(result.points)
        rc = solve_contact(inputs, [torque], points=pts, compliance=result.compliance)
        zones.append(load_zone(rc.cases[0], pts, teeth_total=z1))
        warnings += list(rc.warnings)
    return ReliefStudy(base, reliefs, tuple(zones), tuple(dict.fromkeys(warnings)))
