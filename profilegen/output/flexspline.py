"""The flexspline's drawings: one tooth with its root, the whole undeformed gear, and its teeth
posed in the assembly — true LINE / ARC entities from :mod:`profilegen.geometry.fsform`.

* ``flexspline_tooth.dxf``: the tooth chain (layer ``FS``) with construction (tip, pitch and
  root circle arcs over the tooth, the tooth axis) and a note saying how exact the flank is;
* ``flexspline.dxf``: the closed outline of all z1 teeth, with tip, pitch and root circles;
* the assembly's FS layer (:func:`posed_teeth`): the same tooth chain placed by the motion's
  rigid pose of each tooth, so arcs stay arcs.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..geometry.contour import Arc, Chain, Line
from ..geometry.fsform import flexspline_tooth_chain, ring_of_teeth

if TYPE_CHECKING:  # pragma: no cover
    from ..pipeline.design import Design

__all__ = ["FIT_TOL_MM", "FILES", "write_flexspline_dxfs", "tooth_layers", "gear_layers", "posed_teeth"]

#: Tolerance (mm) of the arc spline that replaces an involute or point-list flank in the drawings.
FIT_TOL_MM = 1e-4

#: The files :func:`write_flexspline_dxfs` writes.
FILES = ("flexspline_tooth.dxf", "flexspline.dxf")


def _radii(tooth) -> tuple[float, float, float]:
    """Root, pitch and tip radii about the gear centre (mm)."""
    r_m = tooth.neutral_radius_mm
    return r_m + tooth.dedendum_y_mm, tooth.pitch_radius_mm, r_m + tooth.addendum_y_mm


def _note(name: str, tooth, deviation_mm: float, tol_mm: float) -> tuple[str, str]:
    """Two lines: what the drawing is, and how exact its flank is."""
    exact = ("flank: the tooth's own arcs and line (exact)" if tooth.kind == "dcta" else
             f"flank: G1 arcs within {deviation_mm * 1e3:.4f} um of the exact {tooth.kind} flank "
             f"(tol {tol_mm * 1e3:g} um)")
    return (f"{name}: flexspline, m {tooth.module_mm:g} mm, z1 {tooth.teeth}, {tooth.kind} tooth, undeformed, mm",
            exact)


def tooth_layers(tooth, chain: Chain, note: tuple[str, ...]) -> tuple[dict, list]:
    """Layers and texts of ``flexspline_tooth.dxf``: the tooth chain, tip / pitch / root circle arcs
    over one and a half pitches, the tooth axis, the note below the root."""
    r_f, r_p, r_a = _radii(tooth)
    half = 1.5 * math.pi / tooth.teeth
    arcs = [Arc(np.zeros(2), r, math.pi / 2 - half, 2 * half) for r in (r_a, r_p, r_f)]
    m = tooth.module_mm
    axis = Line((0.0, r_f - 0.2 * m), (0.0, r_a + 0.2 * m))
    h = 0.05 * m
    x0 = -r_f * math.sin(half)
    texts = [("annotation", (x0, r_f - 0.4 * m - 2 * i * h), h, line) for i, line in enumerate(note)]
    return {"FS": [chain], "construction": arcs + [axis]}, texts


def gear_layers(tooth, outline: Chain, note: tuple[str, ...]) -> tuple[dict, list]:
    """Layers and texts of ``flexspline.dxf``: the closed outline, tip / pitch / root circles."""
    circles = [Arc(np.zeros(2), r, 0.0, 2 * math.pi) for r in _radii(tooth)]
    r_f, h = circles[0].radius, 0.02 * circles[0].radius
    texts = [("annotation", (-0.6 * r_f, -1.15 * r_f - 2 * i * h), h, line) for i, line in enumerate(note)]
    return {"FS": [outline], "construction": circles}, texts


def write_flexspline_dxfs(staging: Path, result: Design, *, tol_mm: float = FIT_TOL_MM) -> Chain:
    """Write ``flexspline_tooth.dxf`` and ``flexspline.dxf`` into ``staging``; return the tooth chain
    (for the assembly)."""
    from . import cad

    tooth, g = result.tooth, result.gearset
    chain, dev = flexspline_tooth_chain(tooth, g.gear, tol_mm=tol_mm)
    from ..face.coning import modification_lines  # the face stage's taper, or "not decided"

    note = _note(g.name, tooth, dev, tol_mm) + tuple(modification_lines(result))
    layers, texts = tooth_layers(tooth, chain, note)
    cad.write_contours_dxf(Path(staging) / FILES[0], layers, texts=texts)
    layers, texts = gear_layers(tooth, ring_of_teeth(chain, tooth.teeth), note)
    cad.write_contours_dxf(Path(staging) / FILES[1], layers, texts=texts)
    return chain


def posed_teeth(tooth_chain: Chain, motion: Any, teeth: int, neutral_radius_mm: float) -> list[Chain]:
    """The tooth chain (gear centre at the origin, axis +y) of every FS tooth in its assembled
    position, wave generator at ψ = 0 (major axis along +y): tooth k (carrier angle θ = 2πk/z1 = φ)
    is placed by the motion's pose, ``Q = R(Φ) p + O`` with p in the tooth frame (origin on the
    neutral line: the chain moved down by r_m), then turned by θ − (U/z2)θ about the centre into
    the carrier's position — a rotation and a shift per tooth, applied to the lines and arcs."""
    theta = 2.0 * np.pi * np.arange(teeth) / teeth
    pose = motion.pose(theta)
    c, s = pose.cos_sin
    turn = theta - motion.beta_rate * theta
    ct, st = np.cos(turn), np.sin(turn)
    out = []
    for k in range(teeth):
        rot = np.array([[c[k], s[k]], [-s[k], c[k]]])  # p ↦ p_x e_t(Φ) + p_y e_r(Φ)
        spin = np.array([[ct[k], st[k]], [-st[k], ct[k]]])  # kinematics.turn
        offset = spin @ (pose.origin[k] - rot @ np.array([0.0, neutral_radius_mm]))
        out.append(tooth_chain.transformed(spin @ rot, offset))
    return out
