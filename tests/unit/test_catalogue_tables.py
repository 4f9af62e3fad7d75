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
