"""The gear set (see :mod:`profilegen.gearset.reader`); every name importers use, re-exported."""

from .reader import *  # noqa: F401,F403
from .reader import (  # noqa: F401  names importers use beyond __all__
    MAX_NAME_CHARS,
    MAX_POINTS,
    MAX_POINTS_FILE_BYTES,
    MAX_TEXT_CHARS,
    MAX_TOML_BYTES,
    RIM_PER_DEFLECTION_MIN,
    COEFFICIENT_SUFFIX,
    Cup,
    _points_tooth,
    looks_like_path,
    read_limited,
    read_toml,
)
from .reader import __all__  # noqa: F401
