"""The coning model each scene gives the face stage (one design intent in every scene).

The part to cut is chosen the same way in every scene that writes one: the face stage
(:func:`profilegen.face.face_width`) picks the CS's design section among the tooth ring's
sections and the FS taper/crowning that keep the one CS profile clear across the face. It needs
ω(φ, z), υ(φ, z) across the tooth ring, which the 2D rim tiers do not give. :func:`rim_tier_for`
names the rim model a scene's design runs:

* ``cup3d`` (verify): the 3D cup at its own mesh (2 mm elements, 16 contact angles);
* ``design``: the same 3D cup at a coarse mesh, :data:`DESIGN_CUP_TIER` (4 mm, 8 angles; its
  error companion at 8 mm, 4 angles). Measured on seed000_csf40: ω on the major axis at the open
  end 0.6270 mm against the fine cup's 0.6278 (0.8 µm), the same design section (z = 70 mm) and
  taper (1.21 against 1.19 µm/mm), 0.7 s against 3.2 s for the two cups;
* ``sketch``: no face stage (ring theory, one section): the design section and the FS
  modification are not decided (:data:`UNDECIDED`), and the files say so.

Why not the semi-membrane coning on the 2D ring's section (ω(φ, z) = ω(φ, z_b)·z/z_b about the
bearing's centre z_b, :func:`profilegen.contact.coning_sections.semi_membrane_sections`)? It scales the
minor axis inward with z as well as the major axis outward; the cup pressed onto the wave
generator over the bearing width stops the minor axis on the cam (ω_minor −0.503 mm at z = 65
and 70 mm on seed000_csf40, semi-membrane −0.543/−0.585). With it no section of seed000_csf40 is
interference-free (61 µm) and no taper helps, where the cup gives z = 70 mm and 1.2 µm/mm. It
describes a bearing free to tilt on one ball row, not the bearing the verify
scene models; the coarse cup follows whatever the verify scene's cup does.
"""

from __future__ import annotations

__all__ = ["DESIGN_CUP_TIER", "RING_FEM_LABEL", "UNDECIDED", "modification_lines", "rim_tier_for"]

#: what a scene without the face stage cannot decide (the sheet and design.json say it)
UNDECIDED = ("NOT THE PART TO CUT: this scene has no face stage (no model of the coning across the face), so the "
             "CS's design section and the FS tooth modification (taper) are not decided; run the design or verify "
             "scene (two waves) for the part to cut")


def _design_cup_tier():
    from ..rim.stage import RimTier

    return RimTier("cup3d", "cup", geometry="nonlinear", layers=2, divisions=0, max_order=16, sine_fit=False,
                   element_mm=4.0, angles=8, gap="exact")


DESIGN_CUP_TIER = None  # built on first use (the rim stage imports scipy)


#: a scene whose ``rim`` label is this (the design tier's label in :mod:`profilegen.pipeline.scenes`) keeps
#: the 2D ring FEM and has no face stage: the stage studies (tests/unit/test_bench_stages.py)
RING_FEM_LABEL = "ring FEM (nonlinear)"


def rim_tier_for(scene, gearset):
    """The rim stage's tier for ``scene`` on ``gearset`` (a tier name or a RimTier): the scene's
    own, except the ``design`` tier on a two-wave gear, which runs the 3D cup at a coarse mesh
    (:data:`DESIGN_CUP_TIER`) so that the face stage chooses its part as the verify scene does —
    unless the scene's ``rim`` label is :data:`RING_FEM_LABEL` (the 2D ring FEM asked for by name:
    one section, no face stage, its files not the part to cut)."""
    global DESIGN_CUP_TIER
    tier = scene.rim_tier
    if tier == "design" and gearset.gear.waves == 2 and scene.rim != RING_FEM_LABEL:
        if DESIGN_CUP_TIER is None:
            DESIGN_CUP_TIER = _design_cup_tier()
        return DESIGN_CUP_TIER
    return tier


def modification_lines(design) -> list[str]:
    """What the drawings and the sheet say about the face stage's choice, in plain words (ASCII
    for the DXF notes): the design section, the FS tooth modification (taper, crowning) when one
    is required, or :data:`UNDECIDED` when the scene has no face stage. [] for None."""
    face = getattr(design, "face", None)
    if face is None:
        return [UNDECIDED]
    z = face.design_section_z_mm
    lines = [f"CS profile: the design section z = {z:g} mm from the cup bottom ({face.design_choice})."]
    mod = face.modification
    shift = 0.0 if mod is None else float(getattr(mod, "shift_mm_per_mm", 0.0))
    if mod is None or (abs(mod.taper_mm_per_mm) < 1e-9 and abs(mod.crowning_mm) < 1e-9 and abs(shift) < 1e-9):
        lines.append("FS teeth: no modification along the face (straight teeth)." if mod is not None or
                     face.max_interference_mm <= face.interference_tol_mm else
                     f"FS teeth: UNMODIFIED, and they interfere with this CS by {face.max_interference_mm * 1e3:.3g} um "
                     "at some section: a modification is required.")
        return lines
    ds = [float(v) for v in mod.thickness_change_mm]
    if abs(mod.taper_mm_per_mm) >= 1e-9 or abs(mod.crowning_mm) >= 1e-9:
        crown = ("" if abs(mod.crowning_mm) < 1e-9 else
                 f" and by -{mod.crowning_mm * 1e3:.4g} um at the face ends against mid-face (crowning)")
        lines.append(f"FS teeth MODIFIED along the face: tooth thickness on the pitch line changes by "
                     f"{mod.taper_mm_per_mm * 1e3:.4g} um per mm toward the open end (taper){crown}, 0 at z = {z:g} mm; "
                     f"from {min(ds) * 1e3:.3g} to {max(ds) * 1e3:.3g} um over the face.")
    if abs(shift) >= 1e-9:
        dy = [float(v) for v in mod.radial_shift_mm]
        lines.append(f"FS teeth SHIFTED radially along the face (conical FS, tip and root circles alike): the whole "
                     f"tooth moves outward by {shift * 1e3:.4g} um per mm toward the open end, 0 at z = {z:g} mm; "
                     f"from {min(dy) * 1e3:.3g} to {max(dy) * 1e3:.3g} um over the face.")
    return lines
