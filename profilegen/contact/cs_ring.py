"""The circular spline's ring ovalising under the engagement zones' forces: one model for the
contact, the torsional curve and the ratcheting climb.

The contact's compliance holds the CS sector fixed at 1.1 × the CS pitch radius
(:mod:`profilegen.contact.compliance`), and the chain adds the CS body's twist in series
(harmonic n = 0 of the tangential load). The other harmonics of the U zones' forces — above all
n = U, the zones pushing the ring outward at the major axis — ovalise the ring: the CS flanks
move away from the FS teeth, the gear turns further under torque and the teeth ride up sooner.

The ring: a free thin ring of mean radius R between the fitted CS root circle and where the CS is
held (``circular_spline.outer_diameter_mm``/2, or 1.25 × the estimated root diameter: ESTIMATE),
radial thickness h, the face width b wide (ESTIMATE), of the FS's steel (ESTIMATE); I = b h³/12,
A = b h. Inextensible bending for n ≥ 2 (energy (EI/2R³)∫(w″ + w)² dθ against the loads' work),
the hoop extension for n = 0: a radial load p_n cos nθ and a tangential t_n sin nθ (per unit
length) give w_n = R⁴ (p_n − t_n/n) / (EI (n² − 1)²), v = −w_n/n sin nθ. For unit forces with
radial and tangential components (a_j, b_j) at θ_j and their U − 1 copies turned by 2π/U, the
displacement along (a_k, b_k) at θ_k is

    S_kj = U [a_k a_j R/(2π E A) + Σ_{n = U, 2U, … ≥ 2} c_n ((a_k a_j + b_k b_j/n²) cos nψ
                                                         + (a_k b_j − b_k a_j) sin nψ / n)],
    c_n = R³ / (π EI (n² − 1)²),   ψ = θ_k − θ_j,

symmetric positive semi-definite (the uniform tangential mode is the chain's CS body; n = 1 is a
rigid translation that U ≥ 2 zones cancel). Checked against Roark's thin ring with two opposite
loads (the diameter through them grows by 0.1488 P R³/EI, the one across shrinks by 0.1366) and
against a second implementation (tests). A CS bolted on its face and piloted in a housing is
stiffer: the free ring is the upper bound of this compliance (docs/catalogue_comparison.md).
Units mm, N, MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial

import numpy as np

from profilegen import checks
from profilegen.errors import ProfilegenError
from profilegen.results import json_ready

__all__ = ["CSRing", "CSRingError", "contact_ring_compliance", "cs_held_radius", "ring_compliance"]


class CSRingError(ProfilegenError, ValueError):
    """Bad input to the CS ring; names the parameter, its value, unit and range."""


_positive = partial(checks.positive, error=CSRingError)

#: harmonics summed (the terms fall as 1/n⁴: the tail beyond 200 is < 1e-9 of the n = 2 term)
HARMONICS = 200


def cs_held_radius(gearset) -> tuple[float, str | None]:
    """Where the CS is held (mm) — its outer radius, ``circular_spline.outer_diameter_mm``/2, or
    1.25 × the estimated CS root diameter — and the estimate's words (None when given)."""
    cs = getattr(gearset, "circular_spline", None)
    d_out = None if cs is None else cs.outer_diameter_mm
    if d_out is not None:
        return 0.5 * float(d_out), None
    from ..gearset.sections import CS_OUTER_DIAMETER_PER_ROOT

    g = gearset.gear
    w0 = float(gearset.wave_generator.deflection_coefficient) * float(g.module_mm)
    root = 2.0 * (float(g.pitch_radius_mm) + float(gearset.tooth.addendum_mm) + w0 + 0.25 * float(g.module_mm))
    r = 0.5 * math.ceil(CS_OUTER_DIAMETER_PER_ROOT * root)
    return r, f"cs_held_radius_mm = {r:.4g} (1.25 × the estimated CS root diameter)"


@dataclass(frozen=True, slots=True)
class CSRing:
    """The CS ring (mm, MPa): its mean radius, radial thickness, width and Young's modulus;
    ``estimates`` the fields that are estimates (words)."""

    mean_radius_mm: float
    thickness_mm: float
    width_mm: float
    youngs_modulus_mpa: float
    estimates: tuple[str, ...] = ()

    def __post_init__(self):
        _positive("mean_radius_mm", self.mean_radius_mm)
        h = _positive("thickness_mm", self.thickness_mm)
        if h >= 2.0 * self.mean_radius_mm:
            raise CSRingError(f"thickness_mm = {h!r} mm: must be < 2 × mean_radius_mm = {2 * self.mean_radius_mm!r} mm")
        _positive("width_mm", self.width_mm)
        _positive("youngs_modulus_mpa", self.youngs_modulus_mpa, "MPa")

    @classmethod
    def of(cls, inputs, *, width_mm: float | None = None) -> "CSRing":
        """The ring of a :class:`~profilegen.contact.inputs.ContactInput`: from the fitted CS
        space's root circle (its farthest point from the centre) to where the CS is held;
        ``width_mm`` default the face width."""
        gs = inputs.gearset
        r_out, note = cs_held_radius(gs)
        pts = np.asarray(inputs.cs_space.sample(1e-3), dtype=float)
        r_root = float(np.max(np.hypot(pts[:, 0], pts[:, 1])))
        if not r_out > r_root:
            raise CSRingError(f"the CS is held at r = {r_out:.6g} mm, inside its root circle r = {r_root:.6g} mm: "
                              "give circular_spline.outer_diameter_mm larger than the root diameter")
        width = float(gs.cup.face_width_mm) if width_mm is None else _positive("width_mm", width_mm)
        est = ([note] if note else []) + [f"width = {width:.4g} mm (the face width)", "the CS of the FS's steel",
                                           "a free ring (not bolted, no housing): the upper bound"]
        return cls(0.5 * (r_root + r_out), r_out - r_root, width, float(gs.material.youngs_modulus_mpa), tuple(est))

    @property
    def second_moment_mm4(self) -> float:
        return self.width_mm * self.thickness_mm ** 3 / 12.0

    @property
    def area_mm2(self) -> float:
        return self.width_mm * self.thickness_mm

    def to_dict(self) -> dict:
        return json_ready({"mean_radius_mm": self.mean_radius_mm, "thickness_mm": self.thickness_mm,
                           "width_mm": self.width_mm, "youngs_modulus_mpa": self.youngs_modulus_mpa,
                           "model": "free thin ring (bending n = U, 2U, …; hoop n = 0)",
                           "estimates": list(self.estimates)})


def ring_compliance(ring: CSRing, at_rad, load_rad, *, at_directions=None, load_directions=None,
                    zones: int = 2, harmonics: int = HARMONICS) -> np.ndarray:
    """S (m × k, mm/N): the ring's displacement at the angles ``at_rad`` (m,) along
    ``at_directions`` per unit force at each of ``load_rad`` (k,) along ``load_directions``, with
    the load's ``zones`` − 1 copies turned by 2π/U (the module docstring). Angles in the
    package's convention (from +y toward +x); a direction is (radial, tangential) components,
    (m, 2) / (k, 2), default radial outward (1, 0); tangential along dθ. ``harmonics``: the
    highest n summed."""
    if not isinstance(ring, CSRing):
        raise CSRingError(f"ring: must be a CSRing, got {type(ring).__name__}")
    u = checks.whole("zones", zones, 1, error=CSRingError)
    n_max = checks.whole("harmonics", harmonics, max(u, 2), error=CSRingError)
    t = np.atleast_1d(np.asarray(checks.finite_array("at_rad", at_rad, "rad", error=CSRingError), dtype=float))
    s = np.atleast_1d(np.asarray(checks.finite_array("load_rad", load_rad, "rad", error=CSRingError), dtype=float))

    def components(d, n, name):
        if d is None:
            return np.ones(n), np.zeros(n)
        d = np.asarray(checks.finite_array(name, d, "", error=CSRingError), dtype=float)
        if d.shape != (n, 2):
            raise CSRingError(f"{name}: must be ({n}, 2) (radial, tangential), got {d.shape}")
        return d[:, 0], d[:, 1]

    a_k, b_k = components(at_directions, t.size, "at_directions")
    a_j, b_j = components(load_directions, s.size, "load_directions")
    r, e = ring.mean_radius_mm, ring.youngs_modulus_mpa
    ei = e * ring.second_moment_mm4
    psi = t[:, None] - s[None, :]
    aa, bb, ab = np.outer(a_k, a_j), np.outer(b_k, b_j), np.outer(a_k, b_j) - np.outer(b_k, a_j)
    # Σ_n over three kernels, e^{inψ} by repeated products (one complex product a harmonic)
    step = np.exp(1j * u * psi)
    z = np.ones_like(step)
    k_aa = np.zeros(psi.shape)
    k_bb = np.zeros(psi.shape)
    k_ab = np.zeros(psi.shape)
    for n in range(u, n_max + 1, u):
        z *= step
        if n < 2:
            continue
        c = r ** 3 / (math.pi * ei * (n * n - 1) ** 2)
        k_aa += c * z.real
        k_bb += (c / (n * n)) * z.real
        k_ab += (c / n) * z.imag
    out = aa * (r / (2.0 * math.pi * e * ring.area_mm2) + k_aa) + bb * k_bb + ab * k_ab
    return u * out


def contact_ring_compliance(ring: CSRing, cs_points_mm, directions, *, zones: int = 2) -> np.ndarray:
    """S_ring (n × n, mm/N, symmetric) at contact points: ``cs_points_mm`` (n, 2) in the CS frame
    about the gear centre, ``directions`` (n, 2) unit, the direction the force on the CS acts (the
    common normals out of the FS), loads and displacements along them."""
    p = np.asarray(checks.finite_array("cs_points_mm", cs_points_mm, "mm", error=CSRingError), dtype=float)
    d = np.asarray(checks.finite_array("directions", directions, "", error=CSRingError), dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or d.shape != p.shape:
        raise CSRingError(f"cs_points_mm, directions: must both be (n, 2), got {p.shape} and {d.shape}")
    theta = np.arctan2(p[:, 0], p[:, 1])
    e_r = np.column_stack([np.sin(theta), np.cos(theta)])
    e_t = np.column_stack([np.cos(theta), -np.sin(theta)])  # d e_r / dθ
    rt = np.column_stack([np.einsum("ij,ij->i", d, e_r), np.einsum("ij,ij->i", d, e_t)])
    s = ring_compliance(ring, theta, theta, at_directions=rt, load_directions=rt, zones=zones)
    return 0.5 * (s + s.T)
