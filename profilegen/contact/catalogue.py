"""Catalogue values the whole-gear model is compared with, each with its source.

Source (all rows): Harmonic Drive LLC, "CSF & CSG Series, Cup Type Component Sets & Housed
Units" catalogue, as published at https://www.yumpu.com/en/document/view/46053898/csf-csg-pdf-harmonic-drive-llc
— page 50 ("Torsional Stiffness", tables 41 and 42) and page 14 ("Technical Terms": table 4,
CSF ratcheting torque; table 5, CSF buckling torque). Read through the project's search
index of stored public pages; the text of table 43 (ratio 1/80 and above — the table that
fits our ratio-100 sets, listed stiffer than ratio 1/50) is cut off in the stored page and
was not found elsewhere, nor K3 of table 42: they are None here, not guessed.

Definitions (catalogue, p. 50): the curve is approximated by three lines, K1 from 0 to T1,
K2 from T1 to T2, K3 above T2 (the rotation at T1 is φ1 = T1/K1, at T2 φ2 = φ1 + (T2 − T1)/K2),
measured at the output with the wave generator locked.

:func:`catalogue_row` returns the row :func:`profilegen.contact.chain.torsional_curve` takes as
``catalogue`` (``T1_nm``, ``K1_nm_per_rad``, ``T2_nm``, ``K2_nm_per_rad``, ``K3_nm_per_rad``,
``lost_motion_arcmin``, ``source``, ``ratio``) plus the ratcheting and buckling torques; for a
ratio whose table is not here (≥ 80) it returns the nearest lower ratio's row with that said in
``note`` — compare with the caveat that the catalogue's own row is likely stiffer (K1 grows
×2.3–2.5 from ratio 30 to 50 at sizes 25 and 32; the ≥ 80 values themselves are not here).
"""

from __future__ import annotations

from functools import partial

from .. import checks
from ..errors import ProfilegenError

__all__ = ["CatalogueError", "RATCHETING_TORQUE_NM", "SOURCE", "STIFFNESS", "catalogue_row"]


class CatalogueError(ProfilegenError, ValueError):
    """No catalogue row for the size asked; names the parameter, its value and what there is."""


SOURCE = ("Harmonic Drive LLC, CSF & CSG Series catalogue (yumpu.com/en/document/view/46053898/"
          "csf-csg-pdf-harmonic-drive-llc)")

#: (ratio, size) → T1, K1, T2, K2, K3 (N·m, N·m/rad; None where not in the stored page).
#: Table 41 "Ratio 1/30" and table 42 "Torsional Stiffness for Ratio 1/50", page 50.
STIFFNESS = {
    (30, 25): {"T1_nm": 14.0, "K1_nm_per_rad": 1.0e4, "T2_nm": 48.0, "K2_nm_per_rad": 1.3e4,
               "K3_nm_per_rad": 2.1e4, "table": "table 41 (ratio 1/30)"},
    (30, 32): {"T1_nm": 29.0, "K1_nm_per_rad": 2.4e4, "T2_nm": 108.0, "K2_nm_per_rad": 3.0e4,
               "K3_nm_per_rad": 4.9e4, "table": "table 41 (ratio 1/30)"},
    (50, 25): {"T1_nm": 14.0, "K1_nm_per_rad": 2.5e4, "T2_nm": 48.0, "K2_nm_per_rad": 3.4e4,
               "K3_nm_per_rad": None, "table": "table 42 (ratio 1/50)"},
    (50, 32): {"T1_nm": 29.0, "K1_nm_per_rad": 5.4e4, "T2_nm": 108.0, "K2_nm_per_rad": 7.8e4,
               "K3_nm_per_rad": None, "table": "table 42 (ratio 1/50)"},
    (50, 40): {"T1_nm": 54.0, "K1_nm_per_rad": 10e4, "T2_nm": 196.0, "K2_nm_per_rad": 14e4,
               "K3_nm_per_rad": None, "table": "table 42 (ratio 1/50)"},
}

#: (ratio, size) → ratcheting torque (N·m), table 4 "CSF Ratcheting Torque", page 14.
RATCHETING_TORQUE_NM = {
    (50, 25): 450.0, (80, 25): 680.0, (100, 25): 500.0,
    (50, 32): 980.0, (80, 32): 1400.0, (100, 32): 1000.0,
    (50, 40): 1800.0, (80, 40): 2800.0, (100, 40): 2100.0,
}

#: size → buckling torque (N·m, all ratios), table 5 "CSF Buckling Torque", page 14.
BUCKLING_TORQUE_NM = {25: 1000.0, 32: 2200.0, 40: 4300.0}

_whole = partial(checks.whole, error=CatalogueError)


def catalogue_row(size: int, ratio: int) -> dict:
    """The catalogue's comparison values for a CSF of ``size`` and ``ratio`` (see the module
    docstring): the stiffness row of ``ratio``'s table, or the nearest lower ratio's with a
    ``note`` when that table is not here; ``ratcheting_torque_nm`` and ``buckling_torque_nm``
    of the size and ratio (None when not listed)."""
    size = _whole("size", size, 1)
    ratio = _whole("ratio", ratio, 1)
    ratios = sorted({r for r, s in STIFFNESS if s == size})
    if not ratios:
        raise CatalogueError(f"size = {size}: no stiffness row here (sizes "
                             f"{sorted({s for _, s in STIFFNESS})})")
    lower = [r for r in ratios if r <= ratio]
    if not lower:
        raise CatalogueError(f"ratio = {ratio}: no stiffness row at or below it for size {size} (ratios {ratios})")
    used = lower[-1]
    row = dict(STIFFNESS[(used, size)])
    table = row.pop("table")
    note = None
    if used != ratio:
        note = (f"the catalogue's row for ratio {ratio} (table 43, ratio 1/80 and above) is not in the stored "
                f"source; this is the ratio-{used} row. The catalogue's K's grow with the ratio (sizes 25 and 32: "
                "K1 x2.3-2.5 from ratio 30 to 50), so its ratio-" + str(ratio) + " values are likely higher than "
                "these (not verified)")
    return {
        "source": f"{SOURCE}, p. 50, {table}, size {size}",
        "size": size, "ratio": used, "ratio_asked": ratio, "note": note, **row,
        "lost_motion_arcmin": None,
        "ratcheting_torque_nm": RATCHETING_TORQUE_NM.get((ratio, size)),
        "ratcheting_source": f"{SOURCE}, p. 14, table 4 (CSF ratcheting torque)",
        "buckling_torque_nm": BUCKLING_TORQUE_NM.get(size),
    }
