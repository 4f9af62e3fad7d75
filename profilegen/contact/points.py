"""Potential contact points of the loaded mesh: FS flank stations against the fitted CS flank.

For the wave generator at ψ = 0 (major axis along +y), FS tooth i sits at φ_i = 2πi/z1
from the major axis. By closure (successive FS teeth generate CS spaces 2π/z2 apart,
docs/theory/envelope.md) tooth i stands in CS space i exactly as the generating tooth stands in space 0
at φ = φ_i: its CS-frame position is ``turn(pose(φ_i).to_cs(p), 2πi/z2)``. So every tooth is
placed with the kinematics the CS profile was generated with, and the no-load deformation
(the rim stage's fit) is in it.

Engagement zone: the teeth around the major axis, −z1/(2U) < i ≤ z1/(2U) (one of the U
zones; the U zones carry equal shares of the torque by the wave generator's U-fold
symmetry, a rotation by 2π/U that maps the loads of one zone onto the next — so each
zone takes T/U). Per tooth, ``stations`` points along the loaded FS flank from the start
of its working part to the tip corner; for each, the initial separation e_k (mm) is the
distance from the station to the fitted CS flank (the true arcs and lines of
``inputs.cs_space``, exact distances to them), measured along the FS flank's outward
normal n_k (the common normal at contact). A rigid rotation Δφ of the FS relative to
the CS closes the gap by r_k Δφ, r_k = (p × n)·(−z), the lever arm of the normal about
the gear centre in the package's angle sense (+y toward +x); the loaded flank is the one
whose lever arms are positive for the chosen direction of rotation. θ_k = e_k / r_k is the
angular separation of seed 000.

The stations sample the separation along the flank, and it is sharply curved there: on the
default set it rises from its minimum by ~17 µm within 0.11 mm (a relative curvature of
~2.6 /mm — the flanks meet like two cylinders, not conformally), so a station a few
hundredths of a millimetre off a tooth's closest point overstates that tooth's separation
by µm, as much as the separations differ from tooth to tooth. So every local minimum of a
tooth's separation (a tooth can touch at two places: inside the flank and at the tip
corner), found on a 401-point scan of the flank and refined by a golden-section search to
1e-7 mm of arc length, takes the place of the station nearest to it. Without that, the
largest tooth force changed by 20–40 % between 5 and 17 stations (233 → 147 N at 54 N·m,
default set); with it, 5, 9 and 17 stations give the same 129.1 N. Spreading each force
over its station's stretch of flank instead of a point changed it by < 1.5 %: it was the
gaps, not the point loads.

Only stations whose separation is below ``max_gap_mm`` are kept. A station farther away
can touch only once the FS has turned by more than max_gap / r against the CS, so a load
case whose rotation φ reaches that (φ · max r_k ≥ max_gap) is flagged as beyond what the
searched points can carry (:attr:`profilegen.contact.analysis.LoadCase.beyond_capacity`).
The default 0.12 mm covers the default set up to its momentary torque (φ · r = 0.08 mm at
1200 N·m); 0.05 mm did not, and its largest tooth force there was 24 % off.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ProfilegenError
from ..results import readonly as _readonly
from .inputs import ContactInput

__all__ = ["ContactPoints", "ContactPointError", "contact_points"]


#: points of the fine scan of each tooth's separation along its working flank
_SCAN = 401


class ContactPointError(ProfilegenError, ValueError):
    """Bad input to the contact-point search; names the parameter, value, unit and range."""



@dataclass(frozen=True, slots=True, eq=False)
class ContactPoints:
    """Potential contact points, one row per (tooth, station), CS frame, mm and rad.

    ``tooth``: FS tooth index i (its CS space is i); ``phi_rad``: φ_i = 2πi/z1;
    ``t_mm``: arc length of the station on the FS flank (root → tip); ``local_mm``: the
    station in the FS tooth frame (for the compliance model); ``fs_point_mm``: the
    station in the CS frame; ``cs_point_mm``: the nearest point of the fitted CS flank;
    ``normal``: unit common normal, pointing out of the FS tooth (the direction the FS
    pushes); ``gap_mm``: initial separation e_k ≥ 0; ``lever_mm``: r_k > 0;
    ``theta_rad``: e_k / r_k. ``side``: +1 (right FS flank loaded) or −1 (left);
    ``rotation``: +1 if the loaded rotation of the FS is in the package's positive angle
    sense (+y toward +x), −1 otherwise.
    """

    tooth: np.ndarray
    phi_rad: np.ndarray
    t_mm: np.ndarray
    local_mm: np.ndarray
    fs_point_mm: np.ndarray
    cs_point_mm: np.ndarray
    normal: np.ndarray
    gap_mm: np.ndarray
    lever_mm: np.ndarray
    side: int
    rotation: int
    zones: int
    stations: int
    max_gap_mm: float

    def __post_init__(self):
        for name in ("phi_rad", "t_mm", "local_mm", "fs_point_mm", "cs_point_mm", "normal", "gap_mm", "lever_mm"):
            object.__setattr__(self, name, _readonly(getattr(self, name)))
        object.__setattr__(self, "tooth", _readonly(self.tooth, int))

    @property
    def theta_rad(self) -> np.ndarray:
        return self.gap_mm / self.lever_mm

    @property
    def count(self) -> int:
        return int(self.tooth.size)

    @property
    def teeth(self) -> np.ndarray:
        """The FS teeth with at least one point, in order."""
        return np.unique(self.tooth)

    def to_dict(self) -> dict:
        return {
            "count": self.count,
            "teeth": self.teeth.tolist(),
            "side": self.side,
            "rotation": self.rotation,
            "zones": self.zones,
            "stations_per_tooth": self.stations,
            "max_gap_mm": self.max_gap_mm,
            "tooth": self.tooth.tolist(),
            "phi_deg": np.degrees(self.phi_rad).tolist(),
            "t_mm": self.t_mm.tolist(),
            "gap_mm": self.gap_mm.tolist(),
            "lever_mm": self.lever_mm.tolist(),
            "fs_point_mm": self.fs_point_mm.tolist(),
            "normal": self.normal.tolist(),
        }


def _flank_start(tooth, inputs: ContactInput) -> float:
    """Arc length where the FS flank can first touch: the lowest station that ever comes
    within reach of the CS tip circle (below it the FS flank is out of mesh)."""
    t = np.linspace(0.0, tooth.length_mm, 801)
    p = tooth.point(t)
    r = np.hypot(p[:, 0], p[:, 1] + tooth.neutral_radius_mm)
    # an FS point at tooth-frame radius r reaches at most r + w0 + (r − r_m)(…) ≈ r + w0
    reach = r + inputs.gearset.deflection_mm
    ok = np.flatnonzero(reach >= inputs.cs_tip_radius_mm)
    return float(t[ok[0]]) if ok.size else 0.0


def contact_points(inputs: ContactInput, *, side: int = 1, stations: int = 5,
                   max_gap_mm: float = 0.12, shift_rad: float = 0.0) -> ContactPoints:
    """The potential contact points of one engagement zone of a design, from its
    :class:`~profilegen.contact.inputs.ContactInput` (``ContactInput.from_design(design)``).
    See the module docstring. ``shift_rad``: every FS tooth i at φ_i = 2πi/z1 + shift from
    the major axis instead (another wave-generator position; still in CS space i, by the
    same closure: :mod:`profilegen.contact.transmission`)."""
    inputs = ContactInput.of(inputs, error=ContactPointError)
    if side not in (1, -1):
        raise ContactPointError(f"side = {side!r}: must be +1 (right FS flank loaded) or −1 (left)")
    if isinstance(stations, bool) or not isinstance(stations, (int, np.integer)) or stations < 2:
        raise ContactPointError(f"stations = {stations!r}: must be a whole number ≥ 2 (points per tooth)")
    try:
        max_gap_mm = float(max_gap_mm)
    except (TypeError, ValueError) as exc:
        raise ContactPointError(f"max_gap_mm = {max_gap_mm!r}: must be a number (mm)") from exc
    if not (math.isfinite(max_gap_mm) and max_gap_mm > 0.0):
        raise ContactPointError(f"max_gap_mm = {max_gap_mm!r} mm: must be finite and > 0")

    g = inputs.gearset.gear
    z1, z2, waves = g.flexspline_teeth, g.circular_spline_teeth, g.waves
    tooth, motion = inputs.tooth, inputs.motion
    space = inputs.cs_space  # true arcs and lines: exact distances and feet

    t = np.linspace(_flank_start(tooth, inputs), tooth.length_mm, stations)
    # outward normal of the flank in the tooth frame (below): the right flank runs root → tip
    # with the tooth material on its left (−x side), so the outward normal is the tangent turned clockwise

    half = z1 // (2 * waves)
    teeth = np.arange(-half + 1, half + 1)
    phis = 2.0 * math.pi * teeth / z1 + float(shift_rad)
    pose = motion.pose(phis)
    cos, sin = np.cos(pose.angle), np.sin(pose.angle)

    def place(p, j):  # tooth-frame points (…, 2) of teeth j (broadcast) → CS space 0's frame
        c, s = cos[j], sin[j]
        return np.stack([p[..., 0] * c + p[..., 1] * s, p[..., 1] * c - p[..., 0] * s], -1) + pose.origin[j]

    # every tooth's separation on a fine scan of the flank; each local minimum found to
    # 1e-7 mm takes the place of the station nearest to it
    scan = np.linspace(t[0], t[-1], _SCAN)
    gaps = space.distance(place(tooth.evaluate(scan, side=side)[0][None, :, :],
                                np.arange(teeth.size)[:, None]).reshape(-1, 2)).reshape(teeth.size, _SCAN)
    padded = np.pad(gaps, ((0, 0), (1, 1)), constant_values=np.inf)
    j_min, k_min = np.nonzero((gaps <= padded[:, :-2]) & (gaps < padded[:, 2:]))
    t_min = _golden_minimum(
        lambda u: space.distance(place(tooth.evaluate(u, side=side)[0], j_min)),
        scan[np.maximum(k_min - 1, 0)], scan[np.minimum(k_min + 1, _SCAN - 1)])
    all_t = np.broadcast_to(t, (teeth.size, stations)).copy()
    moved = np.zeros(all_t.shape, bool)
    for j, tm in zip(j_min, t_min):
        free = np.flatnonzero(~moved[j])
        if free.size:
            k = free[np.argmin(np.abs(t[free] - tm))]
            all_t[j, k], moved[j, k] = tm, True
    all_t.sort(axis=1)
    # every tooth's stations at once (the same arithmetic as tooth by tooth, element for element)
    j_all = np.arange(teeth.size)[:, None]
    local, dp, _ = tooth.evaluate(all_t, side=side)
    nrm = np.stack([dp[..., 1], -dp[..., 0]], -1) * side
    nrm /= np.linalg.norm(nrm, axis=-1)[..., None]
    c, s = cos[j_all], sin[j_all]
    placed = place(local, j_all)
    normal = np.stack([nrm[..., 0] * c + nrm[..., 1] * s, nrm[..., 1] * c - nrm[..., 0] * s], -1)
    gap, foot = space.nearest(placed.reshape(-1, 2))
    gap, foot = gap.reshape(all_t.shape), foot.reshape(all_t.shape + (2,))
    keep = gap <= max_gap_mm
    if not keep.any():
        raise ContactPointError(
            f"max_gap_mm = {max_gap_mm} mm: no FS flank station comes that close to the CS flank in the engagement zone"
        )
    # each tooth's turn into its CS space (cos and sin of the one angle, as kinematics.turn takes them)
    angle = [2.0 * math.pi * i / z2 for i in teeth]
    tc = np.array([np.cos(a) for a in angle])[:, None]
    ts = np.array([np.sin(a) for a in angle])[:, None]

    def turned(p):
        return np.stack([p[..., 0] * tc + p[..., 1] * ts, -p[..., 0] * ts + p[..., 1] * tc], -1)[keep]

    tooth_i = np.broadcast_to(teeth[:, None], keep.shape)[keep]
    phi_i = np.broadcast_to(phis[:, None], keep.shape)[keep]
    t_k, local_k, gap_k = all_t[keep], local[keep], gap[keep]
    fs_k, cs_k, n_k = turned(placed), turned(foot), turned(normal)
    # lever arm in the package's angle sense: a rotation dα of the FS moves p by dα (p_y, −p_x)
    lever = fs_k[:, 1] * n_k[:, 0] - fs_k[:, 0] * n_k[:, 1]
    rotation = 1 if np.median(lever) > 0 else -1
    lever = rotation * lever
    ok = lever > 1e-3 * g.pitch_radius_mm  # a normal through the centre cannot carry torque
    sel = np.flatnonzero(ok)
    return ContactPoints(tooth_i[sel], phi_i[sel], t_k[sel], local_k[sel], fs_k[sel], cs_k[sel], n_k[sel],
                         np.maximum(gap_k[sel], 0.0), lever[sel], side, rotation, waves, stations, max_gap_mm)


def _golden_minimum(f, lo: np.ndarray, hi: np.ndarray, tol_mm: float = 1e-7) -> np.ndarray:
    """Golden-section search for the minimum of ``f`` on each interval [lo_k, hi_k], to
    ``tol_mm``, vectorised: ``f`` maps an array of arguments to an array of values. The
    ends are candidates too (a minimum at the end of the working flank)."""
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    a, b = lo.copy(), hi.copy()
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    width = max(float(np.max(b - a)), tol_mm)
    for _ in range(int(math.ceil(math.log(tol_mm / width) / math.log(g)))):
        left = fc < fd  # the minimum is in [a, d]: drop (d, b]
        a, b = np.where(left, a, c), np.where(left, d, b)
        x = np.where(left, b - g * (b - a), a + g * (b - a))  # the one new interior point
        fx = f(x)
        c, d, fc, fd = (np.where(left, x, d), np.where(left, c, x), np.where(left, fx, fd), np.where(left, fc, fx))
    mid = 0.5 * (a + b)
    candidates = np.stack([lo, mid, hi])
    values = np.stack([f(lo), f(mid), f(hi)])
    return candidates[np.argmin(values, axis=0), np.arange(mid.size)]
