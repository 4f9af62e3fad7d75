"""The torsional curve across the face: N axial slices in parallel, each with its own no-load gaps.

:func:`~profilegen.contact.chain.torsional_curve` solves one 2D section and spreads its load
evenly over the face. The cup cones — its deformation grows from the diaphragm end toward the
open end — so each axial position of a tooth stands a little differently in its CS space, and at
low torque only part of the face carries load. This module turns one flank's 2D contact (its
points and :class:`~profilegen.contact.compliance.ContactCompliance`) into the same problem on N
slices, which the curve's own solvers solve unchanged: each slice the 2D section at its width
with its own gaps, the slices sharing the rotation, every ball one body across them, the rim
coupling them along the face over its shell decay length, optionally the tooth ring's own twist.

Entry points:

* :class:`FaceSlices` — the ``face_slices`` option of
  :func:`~profilegen.contact.chain.torsional_curve` (slices, coning, nodes, the rim's coupling
  length, the ring's twist): what a design's scene key ``face_slices`` sets;
* :func:`slice_layout` (the slices' positions and widths), :func:`slice_gap_shifts` (each
  point's change of separation in each slice's section), :func:`stack_slices` (the N-slice
  problem), :func:`slice_chain` (the series terms without the tooth ring's twist);
* the parts: :func:`local_fraction`, :func:`rim_coupling_length_mm`,
  :func:`slice_coupling_matrix`, :func:`ring_twist_kernel`, :func:`flank_offset_gap_mm`.

Errors: :class:`FaceCurveError` (a ``ValueError``) naming the bad argument: a slice count,
widths or positions, a gap array of the wrong shape, a gear set without a cup, a compliance whose
balls are not every ball one-sided (``ball_supports="all"``), flanks that do not share the balls.

The model, what it leaves out and its convergence: docs/theory/torsion.md, "Against the
catalogue, the gear as made (verify scene)" and "The slices' model".
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from functools import partial

import numpy as np

from .. import checks
from ..errors import ProfilegenError
from ..stagecache import checkpoint

__all__ = [
    "FaceCurveError",
    "FaceSlices",
    "flank_offset_gap_mm",
    "local_fraction",
    "rim_coupling_length_mm",
    "ring_twist_kernel",
    "slice_chain",
    "slice_coupling_matrix",
    "slice_layout",
    "slice_gap_shifts",
    "stack_slices",
]


class FaceCurveError(ProfilegenError, ValueError):
    """Bad input to the across-the-face curve; names the parameter, its value, unit and range."""


_whole = partial(checks.whole, error=FaceCurveError)
_positive = partial(checks.positive, error=FaceCurveError)

CONINGS = ("cup", "semi_membrane", "none")


NODES = ("midpoint", "ends", "graded")

#: "graded" nodes: each interval this many times the one before it, away from the design section.
#: The default set's verify curve (independent slices, the open end the design section): lost
#: motion 1.130 / 1.217 / 1.230 arcmin with 5 / 7 / 9 graded nodes, against 0.766 / 1.182 with 5 /
#: 9 evenly spaced ones (python tests/benchmarks/face_slices.py)
GRADING = 2.0


def _graded(length: float, intervals: int) -> np.ndarray:
    """Distances 0 … ``length`` of ``intervals`` intervals, each GRADING × the one before."""
    if intervals == 0:
        return np.zeros(1)
    steps = GRADING ** np.arange(intervals)
    return np.r_[0.0, np.cumsum(steps)] / steps.sum() * length


def slice_layout(face_width_mm: float, slices: int, nodes: str = "midpoint",
                 toward_mm: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(ζ_i, w_i) (mm): where each of N slices takes its section, measured from the face's
    diaphragm-end edge, and the width it stands for. ``nodes`` "midpoint": N equal slices, each
    at its mid-plane (the midpoint rule); "ends": N ≥ 2 nodes spaced h = b/(N − 1) from one face
    end to the other, the end ones standing for h/2 (the trapezoid rule; it puts a node on a
    face end, where the face stage's design section may lie and the first contact then is);
    "graded": N ≥ 2 nodes, one at ``toward_mm`` (ζ of the design section; default the open
    end, b) and the others at intervals growing by :data:`GRADING` away from it, each cell half
    of its two intervals (the trapezoid rule on uneven nodes). At low torque only a narrow strip
    of the face next to the design section carries load; graded nodes resolve it where evenly
    spaced ones need many more. The cells tile the face: Σ w_i = b."""
    b = _positive("face_width_mm", face_width_mm)
    n = _whole("slices", slices, 1)
    checks.choice("nodes", nodes, NODES, error=FaceCurveError)
    if nodes == "midpoint" or n == 1:
        h = b / n
        return (np.arange(n) + 0.5) * h, np.full(n, h)
    if nodes == "ends":
        h = b / (n - 1)
        w = np.full(n, h)
        w[[0, -1]] = 0.5 * h
        return np.arange(n) * h, w
    slack = 1e-9 * b  # a design section computed as z_d − (z_c − b/2) may land a rounding error past a face end
    t = b if toward_mm is None else min(b, max(0.0, checks.number(
        "toward_mm", toward_mm, "mm", -slack, b + slack, low_open=False, high_open=False, error=FaceCurveError)))
    lo = 0 if t <= slack else (n - 1 if t >= b - slack else int(np.clip(round((n - 1) * t / b), 1, n - 2)))
    if 0 < lo < n - 1 and n < 3:
        raise FaceCurveError(f"slices = {n}: graded nodes about an inner section need at least 3")
    zeta = np.r_[t - _graded(t, lo)[::-1], t + _graded(b - t, n - 1 - lo)[1:]]
    zeta[[0, -1]] = 0.0, b
    h = np.diff(zeta)
    return zeta, np.r_[0.5 * h[0], 0.5 * (h[:-1] + h[1:]), 0.5 * h[-1]]


def ring_twist_kernel(widths_mm) -> np.ndarray:
    """L (N × N, mm): ⟨min(ζ, ζ′)⟩ over ζ in slice i and ζ′ in slice j, the slices the cells of
    widths ``widths_mm`` laid from the face's diaphragm-end edge (ζ = 0) in order — the tooth
    ring's twist at slice i per unit torque entering evenly over slice j, times G J. Diagonal
    a_i + w_i/3 (a_i the cell's lower edge), off-diagonal the lower cell's middle a_i + w_i/2;
    Σ_ij w_i w_j L_ij / b² = b/3 (an even load)."""
    w = np.atleast_1d(np.asarray(widths_mm, dtype=float))
    if w.ndim != 1 or w.size == 0 or not np.all(np.isfinite(w)) or np.any(w <= 0.0):
        raise FaceCurveError(f"widths_mm: must be one or more slice widths > 0 (mm), got shape {w.shape}")
    lo = np.r_[0.0, np.cumsum(w)[:-1]]
    mid = lo + 0.5 * w
    out = np.minimum.outer(mid, mid)
    out[np.diag_indices(w.size)] = lo + w / 3.0
    return out


def flank_offset_gap_mm(points, motion, thickness_change_mm) -> np.ndarray:
    """Δe_k (mm) of a change Δs of the FS tooth thickness (both flanks, Δs/2 each, along the
    tooth's tangent e_t; > 0 thicker), as :func:`profilegen.face.modification.modified_tooth`
    makes it: each point's flank (the sign of its tooth-frame x) moves by ±Δs/2 e_t(Φ), its
    separation by −n_k · that (turned into CS space 0's frame as
    the face-load study's ``gap_shift_mm`` (``research/face_load.py``)). ``thickness_change_mm``: one number
    or one per point."""
    local = np.asarray(points.local_mm, dtype=float)
    ds = np.broadcast_to(np.asarray(thickness_change_mm, dtype=float), (local.shape[0],))
    move = np.column_stack([0.5 * ds * np.sign(local[:, 0]), np.zeros(local.shape[0])])
    return _moved_gap_mm(points, motion, local, move)


def _moved_gap_mm(points, motion, local, move) -> np.ndarray:
    """−n_k · (the CS-frame move of each point when its tooth-frame position ``local`` moves by
    ``move``), turned into CS space 0's frame: the change in each point's separation."""
    pose = motion.pose(np.asarray(points.phi_rad, dtype=float))
    d = pose.to_cs(local + move) - pose.to_cs(local)
    angle = 2.0 * math.pi * np.asarray(points.tooth, dtype=float) / motion.cs_teeth
    c, s = np.cos(angle), np.sin(angle)
    d_turned = np.column_stack([d[:, 0] * c + d[:, 1] * s, d[:, 1] * c - d[:, 0] * s])
    return -np.einsum("ij,ij->i", np.asarray(points.normal, dtype=float), d_turned)


def radial_offset_gap_mm(points, motion, radial_shift_mm) -> np.ndarray:
    """Δe_k (mm) of the whole FS tooth moved radially by Δy (> 0 away from the gear centre, along
    the tooth frame's y), as :func:`profilegen.face.modification.modified_tooth` shifts it: each
    point moves by Δy e_r(Φ), its separation by −n_k · that (as :func:`flank_offset_gap_mm`)."""
    local = np.asarray(points.local_mm, dtype=float)
    dy = np.broadcast_to(np.asarray(radial_shift_mm, dtype=float), (local.shape[0],))
    move = np.column_stack([np.zeros(local.shape[0]), dy])
    return _moved_gap_mm(points, motion, local, move)


def slice_gap_shifts(inputs, points, slices: int, *, coning: str = "cup", cup=None, design_z_mm: float | None = None,
                     modification=None, nodes: str = "midpoint") -> tuple[np.ndarray, np.ndarray]:
    """(z_i (N,) mm, Δe (N, n) mm): the slices' sections (:func:`slice_layout` with ``nodes``,
    from the cup bottom) and each point's change of initial separation in each slice, exact:
    the signed distance to the CS outline of the point's FS material point, placed by the
    slice's section at the point's pose and moved by the slice's tooth modification, less the
    same distance at the design section (:func:`_signed_gaps`). Near contact that distance is
    the pair's separation (to 0.1 nm), so the slice's separation is exact however far the
    coning and the modification move the tooth; the first-order shift −n_k · Δp_k
    (the face-load study's ``gap_shift_mm`` (``research/face_load.py``), :func:`flank_offset_gap_mm`,
    :func:`radial_offset_gap_mm`) is its limit for small moves, and on a ratio-50 set (csf32_50:
    radial shift to −147 µm, the coning) it was 4–137 µm off per slice at the points within
    30 µm of contact, enough to make the flanks overlap at no load (first contact −0.78 arcmin
    against +0.88) where the face stage's exact maps find the part clear.

    ``coning`` "cup" (the 3D cup's sections, :func:`~profilegen.contact.coning_sections.cup_sections`;
    ``cup`` a CupContact / CupDeformation, default :func:`~profilegen.rim.cup.contact.press_cup`
    of the set), "semi_membrane" (the design deformation × z/z_d) or "none" (the design
    deformation in every slice). ``design_z_mm``: the section the CS is conjugate to (default
    the cup's ``length_mm``, the mid-face: the design scene's 2D section; the verify scene's is
    its face stage's ``design_section_z_mm``). The slices are centred on the face (the cup's
    ``length_mm``) whatever it is. ``modification``: the FS tooth's change along the face — a
    (taper_mm_per_mm, crowning_mm) pair or an object with those fields and
    ``shift_mm_per_mm`` (the face stage's
    :class:`~profilegen.face.modification.ToothModification`) — the slice's tooth is
    :func:`profilegen.face.modification.modified_tooth` at its mid-plane; None: straight teeth."""
    z, _, _, shifts = _slice_gap_shifter(inputs, slices, coning=coning, cup=cup, design_z_mm=design_z_mm,
                                         modification=modification, nodes=nodes)
    return z, shifts(points)


def _slice_gap_shifter(inputs, slices: int, *, coning: str, cup, design_z_mm, modification, nodes: str):
    """(z_i, the layout's ζ_i and w_i (:func:`slice_layout` toward the design section), points →
    Δe): :func:`slice_gap_shifts` with the sections, the modification and the CS outline's
    distance built once, for both flanks."""
    from ..face.modification import radial_shift, thickness_change
    from ..geometry.kinematics import HarmonicDriveMotion
    from .coning_sections import cup_sections, semi_membrane_sections
    from .inputs import ContactInput

    inputs = ContactInput.from_design(inputs, name="inputs")
    n = _whole("slices", slices, 1)
    checks.choice("coning", coning, CONINGS, error=FaceCurveError)
    gs = inputs.gearset
    if gs.cup is None:
        raise FaceCurveError("inputs.gearset.cup: the cup is needed for the face width and the design section")
    b, zc = float(gs.cup.face_width_mm), float(gs.cup.length_mm)
    zd = zc if design_z_mm is None else checks.number("design_z_mm", design_z_mm, "mm", zc - 0.5 * b, zc + 0.5 * b,
                                                        low_open=False, high_open=False, error=FaceCurveError)
    zeta, widths = slice_layout(b, n, nodes, zd - (zc - 0.5 * b))
    z = zc - 0.5 * b + zeta
    motion = inputs.motion
    if coning == "cup":
        if cup is None:
            from ..rim.cup.contact import press_cup

            cup = press_cup(gs)
        secs = cup_sections(cup, np.r_[zd, z])
    elif coning == "semi_membrane":
        secs = [motion.deformation] + list(semi_membrane_sections(motion.deformation, z, zd))
    else:
        secs = [motion.deformation] * (n + 1)
    ds, dy = np.zeros(n), np.zeros(n)
    if modification is not None:
        if isinstance(modification, tuple | list):
            taper, crown = (float(v) for v in modification)
            shift = 0.0
        else:
            taper, crown = float(modification.taper_mm_per_mm), float(modification.crowning_mm)
            shift = float(getattr(modification, "shift_mm_per_mm", 0.0))
        ds = thickness_change(z, taper_mm_per_mm=taper, crowning_mm=crown, design_z_mm=zd,
                              ring_span_mm=(zc - 0.5 * b, zc + 0.5 * b))
        dy = radial_shift(z, shift_mm_per_mm=shift, design_z_mm=zd)

    def placed(section):
        return HarmonicDriveMotion(section, motion.neutral_radius_mm, motion.waves, motion.cs_teeth)

    checkpoint()  # (the cup's sections above; the CS outline's distance below: tens of ms each)
    cs = _cs_outline_distance(inputs)

    def shifts(points) -> np.ndarray:
        checkpoint()
        local = np.asarray(points.local_mm, dtype=float)
        reference = _signed_gaps(points, local, placed(secs[0]), cs)
        out = np.empty((n, points.count))
        for i in range(n):
            checkpoint()
            # the same material points of the modified tooth: Δs/2 along e_t on each flank, Δy along e_r
            moved = local + np.column_stack([0.5 * ds[i] * np.sign(local[:, 0]), np.full(len(local), dy[i])])
            out[i] = _signed_gaps(points, moved, placed(secs[i + 1]), cs) - reference
        return out

    return z, zeta, widths, shifts


def _signed_gaps(points, tooth_local: np.ndarray, motion, cs) -> np.ndarray:
    """Each point's FS point (tooth-frame ``tooth_local``, (n, 2) mm) placed by ``motion`` at the
    point's pose, relative to its own CS space (the pose's frame is CS space 0's;
    :func:`~profilegen.contact.points.contact_points` turns tooth i into space i): its signed
    distance (mm, > 0 in the tooth space) to the CS outline ``cs`` (:func:`_cs_outline_distance`)."""
    import shapely

    distance, hollow = cs
    p = motion.pose(np.asarray(points.phi_rad, dtype=float)).to_cs(tooth_local)  # CS space 0's frame
    return np.where(shapely.contains_xy(hollow, p[:, 0], p[:, 1]), 1.0, -1.0) * distance.distance(p)


def _cs_outline_distance(inputs):
    """(PolylineDistance of CS spaces −1, 0, 1, the polygon of the CS's hollow) of the fitted CS
    outline (``inputs.cs_space`` repeated, sampled to 0.1 nm)."""
    return _cs_outline_distance_of(inputs.cs_space, float(inputs.cs_tip_radius_mm),
                                   int(inputs.gearset.gear.circular_spline_teeth), inputs.cs_outline)


@functools.lru_cache(maxsize=2)
def _cs_outline_distance_of(cs_space, tip_radius_mm: float, cs_teeth: int, outline=None):
    """:func:`_cs_outline_distance` of one CS space (a frozen Chain, cached by identity): a torque
    change in a warm process (the workbench) keeps the profile, and this ~0.25 s with it.
    ``outline``: the space's closed outline as the arc fit built it (None: built here)."""
    import shapely

    from ..profile.gearform import PolylineDistance, cs_local_chain, cs_outline

    if outline is None:
        outline = cs_outline(cs_space, tip_radius_mm=tip_radius_mm, cs_teeth=cs_teeth)
    local = cs_local_chain(cs_space, outline).sample(1e-7)
    # outline.sample(1e-5), its elements a few hundred at a time: an engine's design stops between them
    # when superseded (the whole outline's ~2800 elements: ~40 ms)
    els = outline.elements
    pts = [els[0].sample(1e-5)]
    for k in range(1, len(els)):
        if k % 512 == 0:
            checkpoint()
        pts.append(els[k].sample(1e-5)[1:])
    hollow = shapely.Polygon(np.vstack(pts))
    checkpoint()
    shapely.prepare(hollow)
    return PolylineDistance(local), hollow


@dataclass(frozen=True, slots=True)
class FaceSlices:
    """The torsional curve's ``face_slices`` option (:func:`~profilegen.contact.chain.torsional_curve`):
    ``slices`` N, ``coning`` ("cup", "semi_membrane", "none"), ``cup`` (the 3D cup; default
    press_cup of the set, built once for both flanks), ``design_z_mm`` (the CS's section;
    default mid-face), ``modification`` (the FS tooth's taper and crowning; default straight),
    ``ring_twist`` (the tooth ring's twist in the slices, docs/theory/torsion.md, "The slices'
    model"), ``nodes`` (:func:`slice_layout`: "midpoint", "ends" or "graded" toward the design
    section), ``coupling_length_mm`` (the rim's coupling along the face, the same page: None, the FS
    rim's shell decay length :func:`rim_coupling_length_mm`; 0: independent slices, the soft
    bound; λ > 0 mm)."""

    slices: int = 4
    coning: str = "cup"
    cup: object = None
    design_z_mm: float | None = None
    modification: object = None
    ring_twist: bool = True
    nodes: str = "midpoint"
    coupling_length_mm: float | None = None

    def __post_init__(self):
        _whole("face_slices", self.slices, 1)
        checks.choice("coning", self.coning, CONINGS, error=FaceCurveError)
        checks.choice("nodes", self.nodes, NODES, error=FaceCurveError)

    @classmethod
    def of(cls, value) -> "FaceSlices":
        """An int N → the defaults with N slices; a FaceSlices as it is."""
        if isinstance(value, FaceSlices):
            return value
        if isinstance(value, bool) or not isinstance(value, int | np.integer):
            raise FaceCurveError(f"face_slices = {value!r}: must be a whole number ≥ 1 of slices or a FaceSlices")
        return cls(int(value))

    def apply(self, inputs, sides: dict, chain, *, keep: bool = True) -> tuple[dict, object, list[str]]:
        """The flanks ``sides`` {±1: (points, compliance)} as N slices each, and the chain for
        them (:func:`slice_chain`) → (sides, chain, warnings): a warning when some slice's two
        flanks' first contacts overlap (coning makes the tooth interfere at no load there; the
        one-flank curve reads the overlap as rotation, where both flanks would be preloaded).
        ``keep``: inside an engine's design, keep the slices for a later design with the same
        flanks (a torque change; ~60 MB on the default set's design scene); False for flanks that
        no later design will pass again (built for one curve)."""
        from .inputs import ContactInput

        inputs = ContactInput.from_design(inputs, name="inputs")
        gs = inputs.gearset
        cup = self.cup
        if cup is None and self.coning == "cup":
            from ..rim.cup.contact import press_cup

            cup = press_cup(gs)
        b = float(gs.cup.face_width_mm)
        balls = {comp.ball_angle_rad.size for _, comp in sides.values()}
        if len(balls) != 1:
            raise FaceCurveError(f"sides: the two flanks have {sorted(balls)} candidate balls; they must share the "
                                 "bearing")
        widths = slice_layout(b, _whole("slices", self.slices, 1), self.nodes,
                              self._design_z(gs) - (float(gs.cup.length_mm) - 0.5 * b))[1]
        new_chain, c_ring = slice_chain(chain, widths, b, ring_twist=self.ring_twist)
        lam = rim_coupling_length_mm(gs) if self.coupling_length_mm is None else self.coupling_length_mm

        def make():
            return self._stacked(inputs, sides, cup, c_ring, lam)

        # the slices read no torque: inside an engine's design, a torque change takes them from the
        # cache (the same flanks, FS tooth, deformation, CS space, cup and modification objects)
        from ..stagecache import reuse
        from .analysis import FLANK_SECTIONS

        m = inputs.motion
        key = (self.slices, self.coning, self.design_z_mm, self.ring_twist, self.nodes, self.coupling_length_mm,
               c_ring, lam, inputs.cs_tip_radius_mm, m.neutral_radius_mm, m.waves, m.cs_teeth, sorted(sides))
        owners = (inputs.tooth, m.deformation, inputs.cs_space, cup, self.modification,
                  *(x for s in sorted(sides) for x in sides[s]))
        out, warnings = reuse("face_slices", make, gearset=gs, sections=FLANK_SECTIONS, key=key, owners=owners) \
            if keep else make()
        return dict(out), new_chain, list(warnings)

    def _design_z(self, gs) -> float:
        """The design section z_d (mm): ``design_z_mm``, checked as :func:`_slice_gap_shifter` does, or mid-face."""
        b, zc = float(gs.cup.face_width_mm), float(gs.cup.length_mm)
        if self.design_z_mm is None:
            return zc
        return checks.number("design_z_mm", self.design_z_mm, "mm", zc - 0.5 * b, zc + 0.5 * b, low_open=False,
                             high_open=False, error=FaceCurveError)

    def _stacked(self, inputs, sides: dict, cup, c_ring: float, lam: float) -> tuple[dict, tuple[str, ...]]:
        """(:meth:`apply`'s sides as N slices, its warnings)."""
        z, zeta, widths, shifts = _slice_gap_shifter(inputs, self.slices, coning=self.coning, cup=cup,
                                                     nodes=self.nodes, design_z_mm=self.design_z_mm,
                                                     modification=self.modification)
        out, first = {}, {}
        for s, (pts, comp) in sides.items():
            de = shifts(pts)
            out[s] = stack_slices(pts, comp, de, widths_mm=widths, ring_compliance_rad_per_nmm=c_ring,
                                  coupling_length_mm=lam, positions_mm=zeta)
            first[s] = ((pts.gap_mm[None, :] + de) / pts.lever_mm[None, :]).min(axis=1)
        warnings = []
        play = first[1] + first[-1]
        if np.any(play < 0.0):
            i = int(np.argmin(play))
            g = inputs.gearset.gear
            um = -play[i] * 0.5 * float(g.module_mm) * int(g.flexspline_teeth) * 1e3  # at the pitch circle
            why = ("the teeth interfere there (a tooth modification along the face is needed)" if self.modification is None
                   else "the face stage's modification clears its own sections and poses within its tolerance, the "
                        "slices' stations see this much more")
            warnings.append(f"across the face ({self.slices} slices, {self.coning} coning): the two flanks overlap "
                            f"at no load in {int(np.count_nonzero(play < 0.0))} slice(s), most at z = {z[i]:.4g} mm "
                            f"({play[i] * 180.0 * 60.0 / math.pi:.3g} arcmin, {um:.2g} µm at the pitch circle): {why}; "
                            "the one-flank curve counts the overlap as rotation, where both flanks would be preloaded")
        return out, tuple(warnings)


def rim_coupling_length_mm(gearset) -> float:
    """L = √(r_m δ) / (3(1 − ν²))^{1/4} (mm): the length over which a cylindrical shell of radius
    r_m and thickness δ (the FS rim) spreads a load along its axis, the decay length of its
    bending boundary layer — the rim's coupling of the slices (docs/theory/torsion.md, "The slices' model")."""
    g = gearset.gear
    nu = float(gearset.material.poisson_ratio)
    return math.sqrt(float(g.neutral_radius_mm) * float(g.rim_thickness_mm)) / (3.0 * (1.0 - nu * nu)) ** 0.25


def local_fraction(points, compliance) -> float:
    """f (0 … 1): the share of the FS flexibility at a loaded point that is its tooth's own (the
    tooth and the contact deforming), the rest the rim's far field. For each point with teeth
    ±1, ±2 on both sides, the rim's response at its own tooth is the parabola through the mean
    responses at the teeth ±1 and ±2 (S₀ ≈ (4 S₁ − S₂)/3) and f = 1 − S₀ / its own tooth's mean;
    the median over the points (0 when no point has both neighbours). ``compliance``: the 2D
    section's, its balls held (``fs_matrix_mm_per_n``)."""
    s = np.asarray(compliance.fs_matrix_mm_per_n, dtype=float)
    tooth = np.asarray(points.tooth)
    members = {int(t): np.flatnonzero(tooth == t) for t in np.unique(tooth)}
    out = []
    for k, t in enumerate(tooth):
        near = [members.get(int(t) + o) for o in (-2, -1, 1, 2)]
        if any(m is None for m in near):
            continue
        s1 = 0.5 * (s[k, near[1]].mean() + s[k, near[2]].mean())
        s2 = 0.5 * (s[k, near[0]].mean() + s[k, near[3]].mean())
        out.append(1.0 - (4.0 * s1 - s2) / 3.0 / s[k, members[int(t)]].mean())
    return float(np.clip(np.median(out), 0.0, 1.0)) if out else 0.0


def slice_coupling_matrix(positions_mm, widths_mm, coupling_length_mm: float = 0.0) -> np.ndarray:
    """K (N × N): slice i's deflection is Σ_j K_ij S F_j (S the 2D compliance for the whole face
    b). Independent slices (λ = 0): K = diag(b/w_i). λ > 0 (``coupling_length_mm``): a Pasternak
    foundation along the face, k (w_i u_i + λ² Σ_j (u_i − u_j)/h_ij) = P_i between neighbouring
    nodes h_ij apart, so K = b (W + λ² L_h)⁻¹ — the face-load study's slice_coupling on unequal cells. An
    even line load (P ∝ w) deflects every slice alike, as the 2D section: (W + λ² L_h) 1 = w."""
    z = np.atleast_1d(np.asarray(positions_mm, dtype=float))
    w = np.atleast_1d(np.asarray(widths_mm, dtype=float))
    lam = checks.positive("coupling_length_mm", coupling_length_mm, "mm", allow_zero=True, error=FaceCurveError)
    if z.shape != w.shape or z.ndim != 1 or np.any(w <= 0.0) or np.any(np.diff(z) <= 0.0):
        raise FaceCurveError("positions_mm, widths_mm: must be N increasing positions and N widths > 0 (mm)")
    b = float(w.sum())
    if lam == 0.0 or z.size == 1:
        return np.diag(b / w)
    edge = 1.0 / np.diff(z)
    lap = np.diag(np.r_[edge, 0.0] + np.r_[0.0, edge]) - np.diag(edge, 1) - np.diag(edge, -1)
    k = b * np.linalg.inv(np.diag(w) + lam * lam * lap)
    return 0.5 * (k + k.T)


def stack_slices(points, compliance, gap_shift, *, widths_mm=None, ring_compliance_rad_per_nmm: float = 0.0,
                 coupling_length_mm: float = 0.0, positions_mm=None):
    """One flank's 2D contact (``points``, ``compliance``: every ball one-sided, ``ball_supports``
    "all") as N slices (``gap_shift`` (N, n) mm, Δe per slice and point; ``widths_mm`` (N,) the
    width each slice stands for, Σ = the face width b; default b/N each) in one problem of the
    same types: (points, compliance) with N·n points and N·n_b balls, slice-major. Slice i is
    the 2D section at width w_i: its FS and CS flexibility blocks × b/w_i (the compliance keeps
    the face width b, so the curve's solvers, which divide the rim's per-width flexibility by
    it, see each slice at its own width); when ``ring_compliance_rad_per_nmm`` = 1/(G J) of the
    tooth ring (rad per N·mm per mm) is > 0, the ring's twist r_k r_l U (1/(GJ)) L_ij
    (:func:`ring_twist_kernel`) is added. ``coupling_length_mm`` λ > 0 couples the rim along the
    face (docs/theory/torsion.md): the FS flexibility less its local part (:func:`local_fraction`), the
    balls' seats with it, as a Pasternak foundation (:func:`slice_coupling_matrix`;
    ``positions_mm`` the slices' sections, default the cells' middles); the local part and the CS
    stay per slice, but the CS ring's ovalisation (``compliance.cs_ring_mm_per_n``), one body
    across the face, couples every slice alike. An even load is the 2D section for any λ. Every slice's copy of a ball is a
    share of that ball (``ball_body``: one spring under their summed reaction, docs/theory/torsion.md).
    Solve it with the curve's solvers."""
    if getattr(compliance, "ball_supports", "window") != "all":
        raise FaceCurveError(f"compliance.ball_supports = {compliance.ball_supports!r}: the slices need every ball "
                             "one-sided at its no-load gap ('all')")
    de = np.atleast_2d(np.asarray(gap_shift, dtype=float))
    n = points.count
    if de.ndim != 2 or de.shape[1] != n or not np.all(np.isfinite(de)):
        raise FaceCurveError(f"gap_shift: shape {de.shape} must be (slices, {n}) finite mm")
    ns = de.shape[0]
    b = float(compliance.face_width_mm)
    w = np.full(ns, b / ns) if widths_mm is None else np.asarray(widths_mm, dtype=float)
    if w.shape != (ns,) or not np.all(np.isfinite(w)) or np.any(w <= 0.0) or abs(w.sum() - b) > 1e-9 * b:
        raise FaceCurveError(f"widths_mm: must be {ns} widths > 0 (mm) that sum to the face width {b:g} mm")
    c_ring = checks.positive("ring_compliance_rad_per_nmm", ring_compliance_rad_per_nmm, "rad/(N·mm²)",
                             allow_zero=True, error=FaceCurveError)
    zeta = np.r_[0.0, np.cumsum(w)[:-1]] + 0.5 * w if positions_mm is None else positions_mm
    scale = slice_coupling_matrix(zeta, w, coupling_length_mm)

    def tile(a):
        a = np.asarray(a)
        return np.concatenate([a] * ns, axis=0)

    r = np.asarray(points.lever_mm, dtype=float)
    gap = tile(points.gap_mm) + de.ravel()
    pts = dataclasses.replace(
        points, tooth=tile(points.tooth), phi_rad=tile(points.phi_rad), t_mm=tile(points.t_mm),
        local_mm=tile(points.local_mm), fs_point_mm=tile(points.fs_point_mm), cs_point_mm=tile(points.cs_point_mm),
        normal=tile(points.normal), gap_mm=gap, lever_mm=tile(r))
    # the CS and the FS's local part per slice (× b/w_i); the rim's far field coupled along the face
    alone = np.diag(b / w)
    ring = getattr(compliance, "cs_ring_mm_per_n", None)
    ring_all = None
    if ring is None:
        cs = np.kron(alone, np.asarray(compliance.cs_matrix_mm_per_n, dtype=float))
    else:  # the CS ring is one body across the face: a force on any slice moves every slice's points alike
        ring = np.asarray(ring, dtype=float)
        ring_all = np.kron(np.ones((ns, ns)), ring)
        cs = np.kron(alone, np.asarray(compliance.cs_matrix_mm_per_n, dtype=float) - ring) + ring_all
    if c_ring > 0.0:
        rr = np.tile(r, ns)
        cs = cs + np.kron(ring_twist_kernel(w), np.ones((n, n))) * np.outer(rr, rr) * (c_ring * points.zones)
    checkpoint()  # an engine's design stops here when superseded (each block: a few N·n × N·n products)
    flex_cc = np.asarray(compliance._flex_cc, dtype=float)
    if coupling_length_mm > 0.0 and ns > 1:
        same = np.asarray(points.tooth)[:, None] == np.asarray(points.tooth)[None, :]
        local = np.where(same, local_fraction(points, compliance) * b * np.asarray(
            compliance.fs_matrix_mm_per_n, dtype=float), 0.0)  # per width, as the flexibility blocks
        flex_cc_stacked = np.kron(alone, local) + np.kron(scale, flex_cc - local)
        checkpoint()
        fs = np.kron(alone, local / b) + np.kron(scale, np.asarray(compliance.fs_matrix_mm_per_n) - local / b)
    else:
        fs = np.kron(scale, np.asarray(compliance.fs_matrix_mm_per_n, dtype=float))
        flex_cc_stacked = np.kron(scale, flex_cc)
    checkpoint()
    gaps_b = None if compliance.ball_gap_mm is None else tile(compliance.ball_gap_mm)
    nb = compliance.ball_angle_rad.size
    # every slice's copy of a ball is a share of that one ball: its spring (given, or the Hertz
    # secant at the shares' summed reaction) couples the copies
    body = np.arange(nb) if compliance.ball_body is None else np.asarray(compliance.ball_body)
    springs = None if compliance.ball_compliance_mm_per_n is None else \
        tile(np.broadcast_to(compliance.ball_compliance_mm_per_n, (nb,)))
    comp = dataclasses.replace(
        compliance, matrix_mm_per_n=fs + cs, fs_matrix_mm_per_n=fs, cs_matrix_mm_per_n=cs,
        face_width_mm=b, tooth=tile(compliance.tooth), ball_angle_rad=tile(compliance.ball_angle_rad),
        ball_active=tile(compliance.ball_active), _flex_cc=flex_cc_stacked,
        _flex_cb=np.kron(scale, compliance._flex_cb), _flex_bb=np.kron(scale, compliance._flex_bb),
        ball_gap_mm=gaps_b, ball_compliance_mm_per_n=springs, ball_body=tile(body), cs_ring_mm_per_n=ring_all)
    return pts, comp


def slice_chain(chain, widths_mm, face_width_mm: float, *, ring_twist: bool = True):
    """The compliance chain for slices of widths ``widths_mm``: the bearing the whole gear's (a
    ball is one body, its shares coupled in :func:`stack_slices`); with ``ring_twist`` the cup
    wall's series part without its b/3 of tooth ring (which the slices carry) — returns
    (chain, 1/(G J) of the ring in rad/(N·mm·mm), 0 without ``ring_twist``)."""
    # the chain's own types (contact.chain imports this module: no import back)
    b = _positive("face_width_mm", face_width_mm)
    w = np.atleast_1d(np.asarray(widths_mm, dtype=float))
    if w.ndim != 1 or not np.all(np.isfinite(w)) or np.any(w <= 0.0) or abs(w.sum() - b) > 1e-9 * b:
        raise FaceCurveError(f"widths_mm: must be widths > 0 (mm) that sum to the face width {b:g} mm")
    parts = list(chain.parts)
    c_ring = 0.0
    if ring_twist:
        wall = chain.part("cup_wall")
        p = wall.parameters
        gj = float(p["shear_modulus_mpa"]) * 2.0 * math.pi * float(p["radius_mm"]) ** 3 * float(p["thickness_mm"])
        c_ring = 1.0 / gj
        # the wall below the ring alone: 1/K_wall − (b/3)/(GJ) (N·m/rad ← N·mm/rad: × 1e3)
        k_below = 1.0 / (wall.compliance_rad_per_nm - b / 3.0 * c_ring * 1e3)
        parts[parts.index(wall)] = type(wall)(
            "cup_wall", wall.model + "; the tooth ring's twist in the slices (contact.face_curve)",
            wall.formula + " — here without the (b/3) ring term", k_below,
            {**p, "ring_in_slices": True, "ring_compliance_rad_per_nmm2": c_ring}, wall.estimates)
    # the slices take the cup's coning: the chain's left-out list says so instead of leaving it out
    left_out = tuple(SLICED_CONING if item.startswith("coning of the cup") else item for item in chain.left_out)
    return type(chain)(tuple(parts), chain.bearing, left_out), c_ring


#: what the sliced curve still leaves out of the face (replaces the chain's "coning" item)
SLICED_CONING = ("across the face: the rim couples the slices over its own shell length, without the bearing's race "
                 "(one body across its width, it would spread the load further), the CS's teeth not at all (its ring, "
                 "one body, couples them alike); and their no-load "
                 "gaps are the cup's coning pressed on the wave generator, not its bending under the tooth forces")
