"""Hypothesis strategies over gear-set fields, shared by the fuzz test and its benchmark.

``gear_sets(kind=...)`` draws a gear-set mapping (what ``profilegen.parse_gearset`` takes) over
every section: the gear (m 0.1–2 mm, z1 60–600, U = 2, 3 or 4 waves, z2 − z1 = U or 2U, rim,
sometimes the neutral radius), the tooth (DCTA or involute, each dimension scaled around its
default, or a point list — see ``point_teeth``), the wave generator (ω*, elliptical cam /
cosine cam / rollers with their parameters, bearing thickness), the material (E, ν, strengths,
sometimes without the endurance limits), the torques, the CS clearances and fit method, and the
optional cup section. ``spoil=True`` then spoils one field (zero, negative, NaN, infinity, huge,
a text, a boolean, an unknown key, or the field removed), so that the validation is fuzzed with
the stages; ``spoil=None`` (the default) spoils about one draw in six, ``spoil=False`` none.

``point_teeth`` draws the right flank of a ``kind = "points"`` tooth in the pitch frame: a
curved flank (pressure angle, curvature, thickness, addendum, dedendum drawn), 8–300 points,
evenly or unevenly spaced, then clean, noisy (σ 1e-4·m to 0.05·m), with two points swapped
(the polyline crosses) or a run of points reversed (it loops), with a smoothing of 0, the
default, or about the noise.

The ranges reach beyond what a designer would pick (ω* 0.3–1.9, pressure angles 1–35°,
rims 1–6 % of the pitch radius, noise far above the smoothing): the fuzz is after the edges of
every method, where a named error is the right answer.
"""

from __future__ import annotations

import copy
import math

import numpy as np
from hypothesis import strategies as st

KINDS = ("dcta", "involute", "points")

MODULES_MM = (0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0, 1.25, 1.5, 2.0)

POINT_VARIANTS = ("clean", "clean", "noisy", "noisy", "crossing", "loop")

BAD_VALUES = (0, 0.0, -1.0, -1e-9, math.nan, math.inf, -math.inf, 1e12, "text", True, [1.0], {})


@st.composite
def gear_sets(draw, kind: str | None = None, spoil: bool | None = None) -> dict:
    def u(lo: float, hi: float) -> float:
        return draw(st.floats(lo, hi, allow_nan=False, allow_infinity=False))

    m = draw(st.sampled_from(MODULES_MM))
    waves = draw(st.sampled_from([2, 2, 2, 3, 4]))
    z1 = draw(st.integers(30, 300)) * 2
    r1 = m * z1 / 2
    s = m / 0.5  # the default tooth is drawn for m = 0.5 mm
    gear = {"module_mm": m, "flexspline_teeth": z1, "circular_spline_teeth": z1 + waves * draw(st.sampled_from([1, 1, 2])),
            "waves": waves, "rim_thickness_mm": u(0.01, 0.06) * r1}
    kind = kind or draw(st.sampled_from(KINDS))
    if kind == "points":
        tooth = draw(point_teeth(m))
    elif kind == "involute":
        tooth = {"kind": "involute", "pressure_angle_deg": u(12, 35)}
        if draw(st.booleans()):
            tooth |= {"addendum_mm": m * u(0.6, 1.1), "dedendum_mm": m * u(1.0, 1.5)}
    else:
        tooth = {"kind": "dcta", "pressure_angle_deg": u(1, 25), "line_above_pitch_mm": 0.05 * s * u(0.2, 3),
                 "line_below_pitch_mm": 0.2 * s * u(0.3, 1.6), "tip_arc_radius_mm": 0.65 * s * u(0.75, 1.4),
                 "root_arc_radius_mm": 0.7 * s * u(0.8, 1.4), "addendum_mm": 0.4 * s * u(0.7, 1.3),
                 "dedendum_mm": 0.6 * s * u(0.7, 1.3)}
    if kind != "points" and draw(st.booleans()) and draw(st.booleans()):
        tooth["half_thickness_mm"] = math.pi * m / 4 * u(0.9, 1.1)
    if draw(st.booleans()) and draw(st.booleans()):  # r_m between the rim's middle and its inner part
        if kind == "points":
            dedendum = -min(y for _, y in tooth["points"])
        else:
            dedendum = tooth.get("dedendum_mm", 1.25 * m if kind == "involute" else 0.6 * s)
        gear["neutral_radius_mm"] = r1 - dedendum - gear["rim_thickness_mm"] * u(0.3, 0.7)
    contours = ["elliptical_cam", "elliptical_cam", "cosine_cam"] + (["rollers"] if waves == 2 else [])
    contour = draw(st.sampled_from(contours))
    wg = {"deflection_coefficient": u(0.3, 1.9), "contour": contour}
    if contour == "rollers":
        count = draw(st.sampled_from([2, 4]))
        wg |= {"roller_count": count, "roller_radius_mm": r1 * u(0.05, 0.4)}
        if count == 4 and draw(st.booleans()):
            wg["roller_angle_deg"] = u(5, 40)
    elif contour == "elliptical_cam" and draw(st.booleans()):
        wg["bearing_thickness_mm"] = r1 * u(0.02, 0.15)
    yield_mpa = u(300, 1500)
    material = {"youngs_modulus_mpa": u(7e4, 2.3e5), "poisson_ratio": u(0.2, 0.4), "yield_strength_mpa": yield_mpa,
                "ultimate_strength_mpa": yield_mpa * u(1.05, 1.6)}
    if draw(st.booleans()):
        material |= {"bending_endurance_limit_mpa": yield_mpa * u(0.3, 0.6),
                     "shear_endurance_limit_mpa": yield_mpa * u(0.15, 0.35)}
    rated = u(2.0, 2000.0)
    torque = {"rated_nm": rated, "peak_nm": rated * u(1.0, 3.0)}
    if draw(st.booleans()):
        torque["momentary_nm"] = torque["peak_nm"] * u(1.0, 2.5)
    d = {"name": "fuzz", "description": "hypothesis draw", "source": "tests/property/gearsets.py",
         "gear": gear, "tooth": tooth, "wave_generator": wg, "material": material, "torque": torque}
    if draw(st.booleans()):
        d["circular_spline"] = {"root_clearance_mm": m * u(0.05, 0.6), "tip_clearance_mm": m * u(0.05, 0.6),
                                "fit_method": draw(st.sampled_from(["one_sided", "least_squares", "minimax"]))}
        if draw(st.booleans()) and draw(st.booleans()):  # the wire-EDM corners (issue 17)
            d["circular_spline"] |= {"wire_radius_mm": m * u(0.02, 0.3), "spark_gap_mm": m * u(0.0, 0.05),
                                     "corners": draw(st.sampled_from(["fillet", "sharp"]))}
    if draw(st.booleans()):
        length, b = 2 * r1 * u(0.3, 1.0), 2 * r1 * u(0.1, 0.3)
        d["cup"] = {"length_mm": length, "face_width_mm": b,
                    "bottom_thickness_mm": gear["rim_thickness_mm"] * u(0.5, 3.0), "boss_radius_mm": r1 * u(0.2, 0.7),
                    "root_fillet_radius_mm": m * u(0.2, 1.0)}
        if draw(st.booleans()) and draw(st.booleans()):  # the 3D cup's fields (issue 15)
            width = b * u(0.2, 1.0)
            d["cup"] |= {"wall_thickness_mm": gear["rim_thickness_mm"] * u(0.55, 1.0), "bearing_width_mm": width,
                         "bearing_center_mm": length + 0.5 * (b - width) * u(-0.99, 0.99)}
        if draw(st.booleans()) and draw(st.booleans()):  # the face width (issue 15)
            auto = draw(st.booleans())
            d["face"] = {"design_section_z_mm": "auto" if auto else length + 0.5 * b * u(-1.0, 1.0),
                         "sections": draw(st.integers(3, 9)),
                         "taper_mm_per_mm": "auto" if auto else u(-0.005, 0.005),
                         "crowning_mm": "auto" if auto else u(-0.05, 0.05)}
    # (hypothesis leans to the first choice: False, so a mixture spoils about one draw in six)
    if spoil or (spoil is None and draw(st.sampled_from([False, False, False, False, False, True]))):
        d = _spoiled(draw, d)
    return d


@st.composite
def point_teeth(draw, m: float) -> dict:
    """A ``kind = "points"`` tooth section for module ``m`` (see the module docstring)."""
    def u(lo: float, hi: float) -> float:
        return draw(st.floats(lo, hi, allow_nan=False, allow_infinity=False))

    n = draw(st.integers(8, 300))
    addendum, dedendum = m * u(0.5, 1.1), m * u(0.9, 1.5)
    tan_a = math.tan(math.radians(u(3, 30)))
    curl = u(-0.4, 0.4) / m  # x'' of the flank: > 0 hollow, < 0 bulging
    half = math.pi * m / 4 * u(0.85, 1.1)
    spacing = draw(st.sampled_from([1.0, 1.0, 0.5, 2.0]))  # exponent: even, denser at the tip / root
    f = np.linspace(0.0, 1.0, n) ** spacing
    y = -dedendum + (addendum + dedendum) * f
    x = half - y * tan_a + curl * y**2
    variant = draw(st.sampled_from(POINT_VARIANTS))
    smoothing = draw(st.sampled_from([None, 0.0, "noise"]))
    sigma = 0.0
    if variant == "noisy":
        sigma = m * 10 ** u(-4, -1.3)
        rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
        x = x + rng.normal(0.0, sigma, n)
        y = y + rng.normal(0.0, sigma, n)
    elif variant == "crossing":
        i = draw(st.integers(1, n - 3))
        j = draw(st.integers(i + 2, n - 1))
        x[[i, j]], y[[i, j]] = x[[j, i]], y[[j, i]]
    elif variant == "loop":
        i = draw(st.integers(0, n - 3))
        j = draw(st.integers(i + 3, n))
        x[i:j], y[i:j] = x[i:j][::-1].copy(), y[i:j][::-1].copy()
    x = np.clip(x, 1e-6 * m, math.pi * m / 2)  # inside the range the gear set accepts
    tooth = {"kind": "points", "points": np.column_stack([x, y]).tolist()}
    if smoothing == "noise":
        tooth["smoothing_mm"] = min(0.1, max(sigma, 1e-5 * m) * u(0.1, 3.0))
    elif smoothing is not None:
        tooth["smoothing_mm"] = smoothing
    return tooth


def _spoiled(draw, d: dict) -> dict:
    """``d`` with one field made wrong: a bad value, an unknown key, or the field removed."""
    d = copy.deepcopy(d)
    leaves = [(sec, key) for sec, table in d.items() if isinstance(table, dict) for key in table]
    sec, key = draw(st.sampled_from(leaves))
    how = draw(st.sampled_from(["value", "value", "value", "unknown", "remove"]))
    if how == "value":
        d[sec][key] = draw(st.sampled_from(BAD_VALUES))
    elif how == "unknown":
        d[sec][key + "_typo"] = d[sec][key]
    else:
        del d[sec][key]
    return d
