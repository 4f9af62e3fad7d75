"""The CS ring's ovalisation under the engagement zones' forces: a thin-ring compliance.

The contact's compliance model holds the circular spline fixed at ``cs_outer_radius_mm``
(1.1 × the CS pitch radius, :mod:`profilegen.contact.compliance`); the chain
(:mod:`profilegen.contact.chain`) adds the ring beyond it in torsion (harmonic n = 0 of
the tangential load). The other harmonics of the U zones' forces — above all n = U, the
two zones pushing the ring outward at the major axis — ovalise the ring, move the CS
flanks away from the FS teeth and let the gear turn further. This module gives that
compliance for the contact points, to add to S:

Thin inextensible ring (radius R, bending stiffness EI), harmonic n ≥ 2: a radial load
p_n cos nθ and a tangential load t_n sin nθ (per unit length) give the radial displacement
w_n cos nθ, w_n = R⁴ (p_n − t_n/n) / (EI (n² − 1)²), and the tangential v = −w_n/n sin nθ
(inextensibility w + dv/dθ = 0; the strain energy (EI/2R³)∫(w″ + w)² dθ against the loads'
work); likewise for the sin/cos pair. For a unit force with radial and tangential
components (a_j, b_j) at θ_j, the displacement along the unit vector (a_k, b_k) at θ_k is

    S_kj = Σ_n c_n [(a_k a_j + b_k b_j / n²) cos nψ + (a_k b_j − b_k a_j) sin nψ / n],
    c_n = R³ / (π EI (n² − 1)²),  ψ = θ_k − θ_j,

symmetric and positive semi-definite. The U zones carry the same forces turned by 2π/U:
only n = U, 2U, … survive, each U times. The uniform radial mode n = 0 (hoop extension,
w = U a_j R / (2π E A)) is included; the uniform tangential mode (torsion) is not — it is
the chain's ``cs_body`` term; n = 1 is a rigid translation that the U ≥ 2 zones cancel.
For the contact's S (per unit face width … the contact's S is for the whole face), the
ring's I and A are those of the CS's width.

Check: two opposite radial forces P on a ring: the diameter through them grows by
0.1488 P R³/EI and the one across shrinks by 0.1366 P R³/EI (Roark's Formulas for Stress
and Strain, thin circular rings, the two-load case) — ``tests/unit/test_coning_sections.py``.

The CS held in its housing (``foundation_radial_n_per_mm2`` k_r, ``foundation_tangential_n_per_mm2``
k_t, N/mm per mm of circumference): the CS is bolted by its face to a housing (component
sets) or is part of a housed unit, which restrains the ovalisation. As a ring on an elastic
(Winkler) foundation — the bolted, clamped face joint and the housing behind it as springs
per unit length of the ring, radial and tangential — the foundation adds its energy
½∫(k_r w² + k_t v²) R dθ = ½ π R w_n² (k_r + k_t/n²) to mode n (with v = −w_n/n sin nθ):

    w_n = R⁴ (p_n − t_n/n) / (EI (n² − 1)² + R⁴ (k_r + k_t/n²)),
    c_n = R³ / (π (EI (n² − 1)² + R⁴ (k_r + k_t/n²))),

and the hoop mode n = 0 becomes w_0 = p_0 / (EA/R² + k_r). k = 0 is the free ring (the upper
bound of this compliance), k → ∞ a rigid housing (zero). A housing ring of bending stiffness
EI_h fitted round the CS with no slip bends with it: for mode n that is k_r + k_t/n² =
EI_h (n² − 1)²/R⁴, i.e. EI → EI + EI_h (:func:`housing_ring_foundation`). A bolted face
joint: N bolts of lateral stiffness k_b each on the bolt circle R_b smeared round it,
k_r = k_t = N k_b/(2π R_b) (:func:`bolted_flange_foundation`). The teeth and the ring inside
1.1 r_p are in the contact model's CS sector already.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial

import numpy as np

from profilegen import checks
from profilegen.errors import ProfilegenError
from profilegen.results import json_ready

__all__ = ["CSRing", "CSRingError", "bolted_flange_foundation", "cs_ring_compliance", "housing_ring_foundation"]


class CSRingError(ProfilegenError, ValueError):
    """Bad input to the CS ring compliance; names the parameter, its value, unit and range."""


_positive = partial(checks.positive, error=CSRingError)
_whole = partial(checks.whole, error=CSRingError)


@dataclass(frozen=True, slots=True, eq=False)
class CSRing:
    """The CS ring outside the contact model's sector (mm, MPa): mean radius, radial
    thickness, width, Young's modulus; ``estimates`` the fields that are estimates."""

    inner_radius_mm: float
    outer_radius_mm: float
    width_mm: float
    youngs_modulus_mpa: float
    estimates: tuple[str, ...] = ()
    #: the housing as an elastic foundation of the ring (N/mm per mm of circumference): radial
    #: and tangential (module docstring); 0: a free ring
    foundation_radial_n_per_mm2: float = 0.0
    foundation_tangential_n_per_mm2: float = 0.0

    def __post_init__(self):
        ri = _positive("inner_radius_mm", self.inner_radius_mm)
        ro = _positive("outer_radius_mm", self.outer_radius_mm)
        if not ro > ri:
            raise CSRingError(f"outer_radius_mm = {ro!r} mm: must be > inner_radius_mm = {ri!r} mm")
        _positive("width_mm", self.width_mm)
        _positive("youngs_modulus_mpa", self.youngs_modulus_mpa, "MPa")
        for name in ("foundation_radial_n_per_mm2", "foundation_tangential_n_per_mm2"):
            _positive(name, getattr(self, name), "N/mm²", allow_zero=True)

    def held(self, radial_n_per_mm2: float, tangential_n_per_mm2: float | None = None, note: str = "") -> "CSRing":
        """This ring on an elastic foundation (the housing, N/mm per mm of circumference;
        tangential = radial when not given); ``note`` is added to the estimates."""
        import dataclasses

        kt = radial_n_per_mm2 if tangential_n_per_mm2 is None else tangential_n_per_mm2
        est = tuple(e for e in self.estimates if e != "a free ring (no housing)") + ((note,) if note else ())
        return dataclasses.replace(self, foundation_radial_n_per_mm2=float(radial_n_per_mm2),
                                   foundation_tangential_n_per_mm2=float(kt), estimates=est)

    @classmethod
    def from_gearset(cls, gearset, *, inner: str = "root") -> "CSRing":
        """The CS ring to where it is held (the chain's estimate: ``circular_spline.
        outer_diameter_mm``/2 or 1.25 × the estimated root diameter), the face width wide
        (ESTIMATE), of the FS's steel. ``inner``: "root" — the whole section from the CS root
        circle (estimated r1 + addendum + w0 + 0.25 m), which is what bends in ovalisation
        (the contact's CS sector models the teeth and the ring locally, not the ring's global
        bending); "sector" — only the ring outside the contact model's sector edge (1.1 × the
        CS pitch radius): about 4× softer in bending (h³), the upper bound."""
        from profilegen.contact.chain import cs_held_radius  # the chain's own estimate of where the CS is held

        checks.choice("inner", inner, ("root", "sector"), error=CSRingError)
        g = gearset.gear
        if inner == "sector":
            r_i = 1.1 * float(g.cs_pitch_radius_mm)
            est = ["inner_radius_mm = the contact model's CS sector edge, 1.1 r2"]
        else:
            r_i = float(g.pitch_radius_mm) + float(gearset.tooth.addendum_mm) + float(gearset.deflection_mm) \
                + 0.25 * float(g.module_mm)
            est = ["inner_radius_mm = the CS root radius estimated as r1 + addendum + w0 + 0.25 m"]
        r_o, note = cs_held_radius(gearset)
        est += ["width_mm = the face width", "the CS of the FS's steel", "a free ring (no housing)"]
        if note:
            est.append(note)
        return cls(r_i, float(r_o), float(gearset.cup.face_width_mm), float(gearset.material.youngs_modulus_mpa),
                   tuple(est))

    @property
    def radius_mm(self) -> float:
        return 0.5 * (self.inner_radius_mm + self.outer_radius_mm)

    @property
    def thickness_mm(self) -> float:
        return self.outer_radius_mm - self.inner_radius_mm

    @property
    def second_moment_mm4(self) -> float:
        return self.width_mm * self.thickness_mm ** 3 / 12.0

    @property
    def area_mm2(self) -> float:
        return self.width_mm * self.thickness_mm

    def to_dict(self) -> dict:
        return json_ready({"inner_radius_mm": self.inner_radius_mm, "outer_radius_mm": self.outer_radius_mm,
                           "width_mm": self.width_mm, "youngs_modulus_mpa": self.youngs_modulus_mpa,
                           "second_moment_mm4": self.second_moment_mm4,
                           "foundation_radial_n_per_mm2": self.foundation_radial_n_per_mm2,
                           "foundation_tangential_n_per_mm2": self.foundation_tangential_n_per_mm2,
                           "estimates": list(self.estimates)})


def bolted_flange_foundation(bolts: int, bolt_lateral_stiffness_n_per_mm: float, bolt_circle_radius_mm: float) -> float:
    """k_r = k_t (N/mm²) of a face joint of ``bolts`` bolts of lateral stiffness k_b (N/mm, the
    clamped joint's shear stiffness per bolt, no slip) smeared round the bolt circle:
    N k_b / (2π R_b)."""
    n = _whole("bolts", bolts, 1)
    kb = _positive("bolt_lateral_stiffness_n_per_mm", bolt_lateral_stiffness_n_per_mm, "N/mm")
    rb = _positive("bolt_circle_radius_mm", bolt_circle_radius_mm)
    return n * kb / (2.0 * math.pi * rb)


def housing_ring_foundation(ring: CSRing, housing_thickness_mm: float, n: int = 2) -> float:
    """The radial foundation k_r (N/mm², k_t = 0) that stands for a housing ring of radial
    thickness ``housing_thickness_mm`` (the CS's width and E) fitted round the CS, taken at the
    CS ring's mean radius R (thin rings), bending with it without slip, in mode ``n`` (the two
    zones' ovalisation: n = 2): EI_h (n² − 1)² / R⁴ — the same as EI → EI + EI_h for that mode."""
    if not isinstance(ring, CSRing):
        raise CSRingError(f"ring: must be a CSRing, got {type(ring).__name__}")
    th = _positive("housing_thickness_mm", housing_thickness_mm)
    n = _whole("n", n, 2)
    ei_h = ring.youngs_modulus_mpa * ring.width_mm * th ** 3 / 12.0
    return ei_h * (n * n - 1) ** 2 / ring.radius_mm ** 4


def cs_ring_compliance(ring: CSRing, points_mm, directions, *, zones: int = 2, harmonics: int = 400) -> np.ndarray:
    """S_ring (n × n, mm/N): the displacement of the ring along ``directions`` (unit, (n, 2),
    the direction a force on the CS acts: the common normals out of the FS) at ``points_mm``
    ((n, 2), CS frame, about the gear centre) under unit forces along the same directions at
    every point, with the ``zones`` U copies turned by 2π/U (module docstring). Harmonics
    n = U, 2U, … up to ``harmonics`` (the terms fall as 1/n⁴)."""
    if not isinstance(ring, CSRing):
        raise CSRingError(f"ring: must be a CSRing, got {type(ring).__name__}")
    u = _whole("zones", zones, 2)
    nmax = _whole("harmonics", harmonics, u)
    p = np.asarray(checks.finite_array("points_mm", points_mm, "mm", error=CSRingError), dtype=float)
    d = np.asarray(checks.finite_array("directions", directions, "", error=CSRingError), dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or d.shape != p.shape:
        raise CSRingError(f"points_mm, directions: must both be (n, 2), got {p.shape} and {d.shape}")
    theta = np.arctan2(p[:, 0], p[:, 1])  # the package's angle: from +y toward +x
    e_r = np.column_stack([np.sin(theta), np.cos(theta)])
    e_t = np.column_stack([np.cos(theta), -np.sin(theta)])  # d e_r / dθ
    a = np.einsum("ij,ij->i", d, e_r)
    b = np.einsum("ij,ij->i", d, e_t)
    r, ei = ring.radius_mm, ring.youngs_modulus_mpa * ring.second_moment_mm4
    kr, kt = ring.foundation_radial_n_per_mm2, ring.foundation_tangential_n_per_mm2
    psi = theta[:, None] - theta[None, :]
    aa, bb, ab = np.outer(a, a), np.outer(b, b), np.outer(a, b) - np.outer(b, a)
    # n = 0, radial (hoop, on the radial foundation): w_0 = p_0 / (EA/R² + k_r), p_0 = F/(2πR)
    s = u * aa / (2.0 * math.pi * r * (ring.youngs_modulus_mpa * ring.area_mm2 / r ** 2 + kr))
    for n in range(u, nmax + 1, u):
        if n < 2:
            continue
        c = u * r ** 3 / (math.pi * (ei * (n * n - 1) ** 2 + r ** 4 * (kr + kt / n ** 2)))
        s = s + c * ((aa + bb / n ** 2) * np.cos(n * psi) + ab * np.sin(n * psi) / n)
    return 0.5 * (s + s.T)
