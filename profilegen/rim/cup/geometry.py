"""The cup flexspline as a body of revolution: its validated geometry and its meridional mesh.

Coordinates (mm): r the radius, z the axis, z = 0 the mid-plane of the cup bottom, z growing
toward the open end; φ from the wave-generator major axis (docs/reference/conventions.md). The meridional
section (r, z) is an L:

* the bottom (diaphragm) r0 ≤ r ≤ r_bore + t_w, −t_b/2 ≤ z ≤ t_b/2, clamped on the boss at r = r0;
* the wall r_bore ≤ r ≤ r_bore + t_w, t_b/2 ≤ z ≤ l − b/2 (t_w: ``wall_thickness_mm``, the
  gear set's ``[cup] wall_thickness_mm``, at most the ring's δ: a wall turned thinner on the
  outside, the bore one diameter);
* the tooth ring r_bore ≤ r ≤ r_m + δ/2, l − b/2 ≤ z ≤ z_open = l + b/2 (l: ``length_mm``,
  bottom to mid-face, seed 002's semi-membrane length; b: ``face_width_mm``; δ:
  ``ring_thickness_mm``, the rim thickness of the 2D models, r_bore = r_m − δ/2) is an
  equivalent band (no teeth); with t_w = δ (the default) wall and ring are one cylinder;
* the wave-generator bearing presses the bore r = r_bore over
  ``bearing_center_mm`` ± ``bearing_width_mm``/2, which must lie within the tooth ring.

The rules that relate these dimensions are the gear set's
(:func:`profilegen.gearset.sections.check_cup_geometry`): the gear-set reader and
:class:`CupGeometry` both apply them.

:func:`meridional_mesh` meshes the L with straight-sided quadrilaterals (``MeshQuad``;
quadratic ``MeshQuad2`` from it is exact), node lines on every break: the bore, r_m, the
outer surfaces of the wall and the ring, the bearing edges, the tooth-ring edges and the mid-face.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from ... import checks
from ...errors import ProfilegenError

if TYPE_CHECKING:
    from skfem import MeshQuad

__all__ = ["CupError", "CupGeometry", "CupMesh", "meridional_mesh"]


class CupError(ProfilegenError, ValueError):
    """Bad cup geometry or model input; the message names the field, its value, unit and allowed range."""


_number = partial(checks.number, error=CupError)
_whole = partial(checks.whole, error=CupError)


@dataclass(frozen=True, slots=True, eq=False)
class CupGeometry:
    """Geometry and material of the cup (mm, MPa); see the module docstring for the frame.

    ``wall_thickness_mm`` t_w is the wall's between the bottom and the tooth ring;
    ``ring_thickness_mm`` δ the tooth ring's (the rim thickness of the 2D models; None: t_w, a
    cup of one thickness); ``bearing_width_mm`` None: the face width; ``bearing_center_mm``
    None: the mid-face l. The dimensions are checked by the gear set's rules
    (:func:`~profilegen.gearset.sections.check_cup_geometry`), E and ν here."""

    neutral_radius_mm: float
    wall_thickness_mm: float
    length_mm: float
    face_width_mm: float
    bottom_thickness_mm: float
    boss_radius_mm: float
    youngs_modulus_mpa: float
    poisson_ratio: float
    bearing_width_mm: float | None = None
    bearing_center_mm: float | None = None
    ring_thickness_mm: float | None = None

    def __post_init__(self):
        from ...gearset.sections import check_cup_geometry

        one = self.ring_thickness_mm is None  # one thickness: the ring's is the wall's, named as such
        values = check_cup_geometry(
            neutral_radius_mm=self.neutral_radius_mm,
            ring_thickness_mm=self.wall_thickness_mm if one else self.ring_thickness_mm,
            length_mm=self.length_mm, face_width_mm=self.face_width_mm, bottom_thickness_mm=self.bottom_thickness_mm,
            boss_radius_mm=self.boss_radius_mm, wall_thickness_mm=None if one else self.wall_thickness_mm,
            bearing_width_mm=self.bearing_width_mm, bearing_center_mm=self.bearing_center_mm, error=CupError,
            ring_name="wall_thickness_mm" if one else "ring_thickness_mm")
        e = _number("youngs_modulus_mpa", self.youngs_modulus_mpa, "MPa", 0.0)
        nu = _number("poisson_ratio", self.poisson_ratio, "", -1.0, 0.5)
        for name, value in (*values.items(), ("youngs_modulus_mpa", e), ("poisson_ratio", nu)):
            object.__setattr__(self, name, value)

    @classmethod
    def from_gearset(cls, gearset, *, bearing_width_mm: float | None = None,
                     bearing_center_mm: float | None = None) -> CupGeometry:
        """From a GearSet: r_m, δ (the tooth ring) from ``[gear]``, E, ν from ``[material]``, the
        rest from ``[cup]`` (its ``wall_thickness_mm``, default δ; the bearing: the arguments,
        else the ``[cup]`` fields, else the face width centred on the mid-face)."""
        gear, mat, cup = gearset.gear, gearset.material, gearset.cup
        if bearing_width_mm is None:
            bearing_width_mm = getattr(cup, "bearing_width_mm", None)
        if bearing_center_mm is None:
            bearing_center_mm = getattr(cup, "bearing_center_mm", None)
        wall = getattr(cup, "wall_thickness_mm", None)
        return cls(gear.neutral_radius_mm, gear.rim_thickness_mm if wall is None else wall, cup.length_mm,
                   cup.face_width_mm, cup.bottom_thickness_mm, cup.boss_radius_mm, mat.youngs_modulus_mpa,
                   mat.poisson_ratio, bearing_width_mm=bearing_width_mm, bearing_center_mm=bearing_center_mm,
                   ring_thickness_mm=gear.rim_thickness_mm)

    def _filled(self, name: str) -> float:
        """A field that may be given as None (ring, bearing): __post_init__ has filled it in."""
        value = getattr(self, name)
        if value is None:
            raise CupError(f"{name}: not filled in (CupGeometry.__post_init__ sets it)")
        return value

    @property
    def bore_radius_mm(self) -> float:
        return self.neutral_radius_mm - 0.5 * self._filled("ring_thickness_mm")

    @property
    def outer_radius_mm(self) -> float:
        """Outer radius of the tooth ring (mm)."""
        return self.neutral_radius_mm + 0.5 * self._filled("ring_thickness_mm")

    @property
    def wall_outer_radius_mm(self) -> float:
        """Outer radius of the wall between the bottom and the tooth ring, and of the bottom (mm)."""
        if self.wall_thickness_mm >= self._filled("ring_thickness_mm"):  # one cylinder: exactly the ring's outer radius
            return self.outer_radius_mm
        return self.bore_radius_mm + self.wall_thickness_mm

    @property
    def open_end_mm(self) -> float:
        """z of the open end (mm)."""
        return self.length_mm + 0.5 * self.face_width_mm

    @property
    def ring_span_mm(self) -> tuple[float, float]:
        """(z at the diaphragm end, z at the open end) of the tooth ring (mm)."""
        return self.length_mm - 0.5 * self.face_width_mm, self.length_mm + 0.5 * self.face_width_mm

    @property
    def bearing_span_mm(self) -> tuple[float, float]:
        center, width = self._filled("bearing_center_mm"), self._filled("bearing_width_mm")
        return center - 0.5 * width, center + 0.5 * width

    def to_dict(self) -> dict:
        return {name: float(getattr(self, name)) for name in (
            "neutral_radius_mm", "wall_thickness_mm", "ring_thickness_mm", "length_mm", "face_width_mm", "bottom_thickness_mm",
            "boss_radius_mm", "bearing_width_mm", "bearing_center_mm", "youngs_modulus_mpa", "poisson_ratio")}


@dataclass(frozen=True, slots=True, eq=False)
class CupMesh:
    """A meridional mesh of the cup: ``mesh`` (MeshQuad, vertices (r, z)), the radial and axial
    breaks it was built on, and the element size along the meridian it was asked for."""

    geometry: CupGeometry
    mesh: MeshQuad
    r_breaks: np.ndarray
    z_breaks: np.ndarray
    element_mm: float
    layers: int

    @property
    def elements(self) -> int:
        return int(self.mesh.t.shape[1])


def meridional_mesh(geometry: CupGeometry, *, element_mm: float = 1.0, layers: int = 2,
                    bottom_layers: int | None = None, refine_mm: float | None = None) -> CupMesh:
    """The L-shaped meridional section meshed with quadrilaterals (vertices (r, z)).

    ``layers`` elements through the wall, ``bottom_layers`` (default ``layers``) through the
    bottom; along the meridian elements of at most ``element_mm``, and of at most
    ``refine_mm`` (default ``element_mm``/2) within √(r_m t) (the shell's bending boundary
    layer) of the wall–bottom junction and of the bearing edges."""
    g = geometry
    h = _number("element_mm", element_mm, "mm", 0.0)
    layers = _whole("layers", layers, 1)
    bottom_layers = layers if bottom_layers is None else _whole("bottom_layers", bottom_layers, 1)
    fine = 0.5 * h if refine_mm is None else _number("refine_mm", refine_mm, "mm", 0.0)
    fine = min(fine, h)
    decay = math.sqrt(g.neutral_radius_mm * g._filled("ring_thickness_mm"))
    r_in, r_out, t_b = g.bore_radius_mm, g.outer_radius_mm, g.bottom_thickness_mm
    z_lo = 0.5 * t_b
    z_open = g.open_end_mm
    ring_lo, ring_hi = g.ring_span_mm
    b_lo, b_hi = g.bearing_span_mm

    # axial breaks of the wall: the tooth ring, the bearing, the mid-face; fine pieces around the
    # junction and the bearing edges
    z_marks = sorted({z_lo, ring_lo, g.length_mm, ring_hi, b_lo, b_hi, z_open})
    fine_at = [z_lo, b_lo, b_hi]
    extra = []
    for c in fine_at:
        for d in (c - decay, c + decay):
            if z_lo < d < z_open:
                extra.append(d)
    z_points = sorted(set(np.round(z_marks + extra, 12)))
    z_wall = [z_points[0]]
    for a, b in zip(z_points[:-1], z_points[1:]):
        if b - a <= 1e-9:
            continue
        mid = 0.5 * (a + b)
        size = fine if min(abs(mid - c) for c in fine_at) < decay else h
        n = max(1, math.ceil((b - a) / size - 1e-9))
        z_wall.extend(np.linspace(a, b, n + 1)[1:])
    z_bottom = np.linspace(-0.5 * t_b, z_lo, bottom_layers + 1)
    z_all = np.concatenate([z_bottom[:-1], np.asarray(z_wall)])

    # radial breaks of the bottom: fine near the junction
    r_points = sorted({r0 := g.boss_radius_mm, max(r0, r_in - decay), r_in})
    r_plate = [r_points[0]]
    for a, b in zip(r_points[:-1], r_points[1:]):
        if b - a <= 1e-9:
            continue
        size = fine if b == r_in else h
        n = max(1, math.ceil((b - a) / size - 1e-9))
        r_plate.extend(np.linspace(a, b, n + 1)[1:])
    r_wall = np.linspace(r_in, r_out, layers + 1)
    r_w = g.wall_outer_radius_mm  # = r_out for a cup of one thickness (no extra break: the same mesh)
    if r_w < r_out:
        r_wall = np.union1d(r_wall, [r_w])
    r_all = np.concatenate([np.asarray(r_plate)[:-1], r_wall])

    from skfem import MeshQuad

    box = MeshQuad.init_tensor(r_all, z_all)
    centre = box.p[:, box.t].mean(axis=1)
    keep = (centre[1] < z_lo) | (centre[0] > r_in)
    if r_w < r_out:  # the wall and the bottom end at r_w, the tooth ring at r_out
        keep &= (centre[0] < r_w) | (centre[1] > ring_lo)
    t = box.t[:, keep]
    used = np.unique(t)
    renumber = -np.ones(box.p.shape[1], dtype=int)
    renumber[used] = np.arange(used.size)
    mesh = MeshQuad(box.p[:, used], renumber[t])
    return CupMesh(g, mesh, np.asarray(r_all), np.asarray(z_all), h, layers)
