"""load_gearset takes what the CLI takes: a path, or a bundled set's name."""

import pytest

import profilegen as pg
from profilegen.errors import GearSetError


def test_a_bundled_name_loads_the_bundled_file():
    by_name = pg.load_gearset("seed000_csf40")
    by_path = pg.load_gearset(pg.default_gearset_path().parent / "seed000_csf40.toml")
    assert by_name.to_dict() == by_path.to_dict() and by_name.name == "seed000_csf40"


def test_an_unknown_name_lists_the_known_ones():
    with pytest.raises(GearSetError, match="known profiles: .*default"):
        pg.load_gearset("no_such_set")


def test_a_missing_path_is_named(tmp_path):
    with pytest.raises(GearSetError, match="missing.toml"):
        pg.load_gearset(str(tmp_path / "missing.toml"))
