"""profilegen.contact.catalogue against a second transcription, typed here again from the
published pages in their own layout (rows as printed, one column per size and ratio), and the
catalogue's worked example of the torsion angle.

Source of the tables below: Harmonic Drive AG, CHA Series engineering data 1018854 12/2015 V01,
p. 50, section 3.3.4 "Accuracy" (tables 50.1, sizes 14-25, and 50.2, sizes 32-58) and 3.3.5
"Torsional Stiffness" (tables 50.3, 50.4); the same numbers in 1018854 8/2018 V03, p. 54,
tables 54.1-54.4. "-": printed as a dash (no value). The i > 50 column is the module's ratio 80.
"""

from __future__ import annotations

import math

import pytest

from profilegen.contact.catalogue import (
    ACCURACY_ARCMIN,
    STIFFNESS,
    CatalogueError,
    catalogue_row,
    torsion_angle_rad,
)

# table 50.3 / 50.4, "Limit torques" (one value per size, every ratio)
T1 = {14: 2, 17: 3.9, 20: 7, 25: 14, 32: 29, 40: 54, 50: 108, 58: 168}
T2 = {14: 6.9, 17: 12, 20: 25, 25: 48, 32: 108, 40: 196, 50: 382, 58: 598}
# the columns as printed: (size, i); i = 80 stands for "> 50"
COLUMNS = [(14, 30), (14, 50), (14, 80), (17, 30), (17, 50), (17, 80), (20, 30), (20, 50), (20, 80),
           (25, 30), (25, 50), (25, 80),  # table 50.3
           (32, 30), (32, 50), (32, 80), (40, 30), (40, 50), (40, 80), (50, 50), (50, 80), (58, 50), (58, 80)]  # 50.4
# [x 10^3 N.m/rad], rows K3, K2, K1 as printed (top to bottom)
K3 = [3.4, 5.7, 7.1, 6.7, 13, 16, 11, 23, 29, 21, 44, 57, 49, 98, 120, None, 180, 230, 340, 440, 540, 710]
K2 = [2.4, 4.7, 6.1, 4.4, 11, 14, 7.1, 18, 25, 13, 34, 50, 30, 78, 110, None, 140, 200, 280, 400, 440, 610]
K1 = [1.9, 3.4, 4.7, 3.4, 8.1, 10, 5.7, 13, 16, 10, 25, 31, 24, 54, 67, None, 100, 130, 200, 250, 310, 400]

# table 50.1 / 50.2 (arcmin, every cell "< x"); columns as printed (size 40-58: no i = 30 column)
ACC_COLUMNS = [c for c in COLUMNS if c != (40, 30)]
TRANSMISSION = [2, 1.2, 1, 2, 1.2, 1, 1.5, 1, 0.8, 1.5, 1, 0.8, 1.5, 1, 0.8, 0.7, 0.5, 0.7, 0.5, 0.7, 0.5]
HYSTERESIS = [3, 1, 1, 3, 1, 1, 3, 1, 1, 3, 1, 1, 3, 1, 1, 1, 1, 1, 1, 1, 1]


def test_the_transcriptions_have_one_value_per_column():
    assert len(K1) == len(K2) == len(K3) == len(COLUMNS) == 22
    assert len(TRANSMISSION) == len(HYSTERESIS) == len(ACC_COLUMNS) == 21


@pytest.mark.parametrize("i", range(len(COLUMNS)), ids=[f"size{s}-i{r}" for s, r in COLUMNS])
def test_stiffness_cell_equals_the_second_transcription(i):
    size, ratio = COLUMNS[i]
    if K1[i] is None:  # a dash: no value, and none invented
        assert (ratio, size) not in STIFFNESS
        return
    row = STIFFNESS[(ratio, size)]
    assert (row["T1_nm"], row["T2_nm"]) == (T1[size], T2[size])
    assert row["K1_nm_per_rad"] == pytest.approx(K1[i] * 1e3, rel=1e-12)
    assert row["K2_nm_per_rad"] == pytest.approx(K2[i] * 1e3, rel=1e-12)
    assert row["K3_nm_per_rad"] == pytest.approx(K3[i] * 1e3, rel=1e-12)
    # every cell names its document, page and table
    assert row["page"] and row["table"] and row["source"]


def test_no_stiffness_cell_beyond_the_tables():
    assert set(STIFFNESS) <= {(r, s) for s, r in COLUMNS}
    assert {(30, 50), (30, 58), (30, 40)}.isdisjoint(STIFFNESS)


@pytest.mark.parametrize("i", range(len(ACC_COLUMNS)), ids=[f"size{s}-i{r}" for s, r in ACC_COLUMNS])
def test_accuracy_cell_equals_the_second_transcription(i):
    size, ratio = ACC_COLUMNS[i]
    acc = ACCURACY_ARCMIN[(ratio, size)]
    assert acc["transmission_accuracy_max_arcmin"] == TRANSMISSION[i]
    assert acc["hysteresis_loss_max_arcmin"] == HYSTERESIS[i]
    assert acc["lost_motion_max_arcmin"] == 1  # "< 1" for every size
    row = catalogue_row(size, 100 if ratio == 80 else ratio)
    assert row["transmission_accuracy_max_arcmin"] == TRANSMISSION[i] and "table" in row["accuracy_source"]


def test_torsion_angle_worked_example():
    """CHA manual 1018854 12/2015 V01, p. 68, section 4.2 (and the LynxDrive manual 1018856
    08/2018 V04, p. 42): T = 60 N.m with K1 = 6.7e4, T1 = 29, K2 = 1.1e5, T2 = 108, K3 = 1.2e5
    gives φ = 29/6.7e4 + (60 − 29)/1.1e5 = 7.15e-4 rad = 2.5 arcmin."""
    row = catalogue_row(32, 100)
    phi = torsion_angle_rad(row, 60.0)
    assert phi == pytest.approx(7.15e-4, abs=0.005e-4)
    assert math.degrees(phi) * 60 == pytest.approx(2.5, abs=0.05)
    # the three lines meet at T1 and T2 and the slope above T2 is 1/K3
    assert torsion_angle_rad(row, 29.0) == pytest.approx(29 / 6.7e4)
    assert torsion_angle_rad(row, 108.0) == pytest.approx(29 / 6.7e4 + 79 / 1.1e5)
    assert torsion_angle_rad(row, 208.0) - torsion_angle_rad(row, 108.0) == pytest.approx(100 / 1.2e5)
    assert torsion_angle_rad(row, 0.0) == 0.0
    with pytest.raises(CatalogueError, match="torque_nm"):
        torsion_angle_rad(row, -1.0)


def test_rows_for_every_size_and_the_ratio_columns():
    for size in T1:
        assert catalogue_row(size, 100)["ratio"] == 80 and catalogue_row(size, 50)["ratio"] == 50
    assert catalogue_row(14, 30)["K1_nm_per_rad"] == 1.9e3
    with pytest.raises(CatalogueError, match="ratio"):
        catalogue_row(50, 30)  # sizes 50 and 58: no i = 30 column


# Harmonic Drive LLC, CSF & CSG catalogue, p. 14 ("Technical Terms"), typed again as printed: one
# line per size, the ratios' columns in the table's order, "-" a dash. Table 4 (CSF ratcheting
# torque, N·m; ratios 30 50 80 100 120 160), table 5 (CSF buckling torque, all ratios), tables 6
# and 7 (CSG; ratios 50 80 100 120 160).
TABLE_4 = """
8 11 12 - 14 - -
11 29 34 - 43 - -
14 59 88 110 84 - -
17 100 150 200 160 120 -
20 170 220 350 260 240 220
25 340 450 680 500 470 450
32 720 980 1400 1000 980 980
40 - 1800 2800 2100 1900 1800
45 - 2700 3900 3100 2800 2600
50 - 3700 5400 4100 3800 3600
58 - 5800 8200 6400 5800 5600
65 - 7800 11000 9400 8300 8000
80 - 14000 22000 16000 15000 14000
90 - 20000 30000 23000 21000 20000
100 - 29000 44000 33000 30000 28000
"""
TABLE_5 = "8 35 11 90 14 190 17 330 20 560 25 1000 32 2200 40 4300 45 5800 50 8000 58 12000 65 17000 80 31000 90 45000 100 58000"
TABLE_6 = """
14 110 140 100 - -
17 190 260 200 150 -
20 280 450 330 310 280
25 580 880 650 610 580
32 1200 1800 1300 1200 1200
40 2300 3600 2700 2400 2300
"""
TABLE_7 = "14 260 17 500 20 800 25 1700 32 3500 40 6700"


def _printed(text: str, ratios: tuple[int, ...]) -> dict:
    out = {}
    for line in text.strip().splitlines():
        size, *cells = line.split()
        assert len(cells) == len(ratios), line
        out.update({(r, int(size)): None if c == "-" else float(c) for r, c in zip(ratios, cells)})
    return out


def _pairs(text: str) -> dict:
    v = text.split()
    return {int(v[i]): float(v[i + 1]) for i in range(0, len(v), 2)}


@pytest.mark.parametrize("printed, module, ratios", [
    (TABLE_4, "RATCHETING_TORQUE_NM", (30, 50, 80, 100, 120, 160)),
    (TABLE_6, "RATCHETING_TORQUE_CSG_NM", (50, 80, 100, 120, 160)),
])
def test_ratcheting_tables_equal_the_second_transcription(printed, module, ratios):
    from profilegen.contact import catalogue

    table, kept = _printed(printed, ratios), getattr(catalogue, module)
    assert {k: v for k, v in table.items() if v is not None} == kept  # every value, and no dash filled in


def test_buckling_tables_equal_the_second_transcription():
    from profilegen.contact.catalogue import BUCKLING_TORQUE_CSG_NM, BUCKLING_TORQUE_NM

    assert _pairs(TABLE_5) == BUCKLING_TORQUE_NM and _pairs(TABLE_7) == BUCKLING_TORQUE_CSG_NM


def test_ratcheting_rows_read_as_the_catalogue_says():
    """What the tables say together, which a typing slip in either copy would break: every size's
    ratio-80 torque is its largest (80 engages deepest of the ratios > 50), the CSG's is 1.19-1.30×
    the CSF's ("a 30 % increase in torque capacity", p. 4), and buckling lies above ratcheting."""
    from profilegen.contact.catalogue import (BUCKLING_TORQUE_NM, RATCHETING_TORQUE_CSG_NM,
                                              RATCHETING_TORQUE_NM)

    for (ratio, size), t in RATCHETING_TORQUE_NM.items():
        if (80, size) in RATCHETING_TORQUE_NM:
            assert t <= RATCHETING_TORQUE_NM[(80, size)]
        assert t < BUCKLING_TORQUE_NM[size]
    for key, t in RATCHETING_TORQUE_CSG_NM.items():
        assert 1.15 <= t / RATCHETING_TORQUE_NM[key] <= 1.31
    assert catalogue_row(58, 100)["ratcheting_torque_nm"] == 6400.0
    assert catalogue_row(14, 120)["ratcheting_torque_nm"] is None  # printed "-"
