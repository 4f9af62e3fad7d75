"""Exceptions of profilegen.

Every package exception subclasses a builtin as well, so callers can catch
either ``GearSetError`` or plain ``ValueError``.
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = [
    "ProfilegenError",
    "GearSetError",
    "ToothError",
    "ConvergenceError",
    "RimSolverError",
    "EnvelopeError",
    "ExportError",
    "StressError",
    "SweepSpecError",
    "OptimizeSpecError",
    "BenchmarkNotFoundError",
    "FilletError",
    "did_you_mean",
]


def did_you_mean(word: object, choices: Iterable[object], n: int = 2) -> str:
    """``"; did you mean 'x'?"`` (or ``'x' or 'y'``) for the ``n`` choices closest to a misspelt
    ``word`` (difflib's ratio ≥ 0.6), ``""`` when none is close: the tail of a one-line error."""
    import difflib

    close = difflib.get_close_matches(str(word)[:100], [str(c) for c in choices], n=n)
    return f"; did you mean {' or '.join(repr(c) for c in close)}?" if close else ""


class ProfilegenError(Exception):
    """Base class of every error raised on purpose by profilegen."""


class GearSetError(ProfilegenError, ValueError):
    """A gear-set field is missing, unknown or out of range.

    ``problems`` holds one line per offending field, each naming the field,
    the value, the unit and the allowed range; ``str(error)`` joins them on one
    line.
    """

    def __init__(self, problems: str | list[str]):
        self.problems: list[str] = [problems] if isinstance(problems, str) else list(problems)
        super().__init__("; ".join(self.problems))


class ToothError(GearSetError):
    """The tooth fields describe no valid tooth (arc misses the addendum,
    flanks cross, tooth wider than the pitch, ...)."""


class ConvergenceError(ProfilegenError, RuntimeError):
    """A solver did not converge; the message names where (φ, t, residual)."""


class RimSolverError(ConvergenceError):
    """The rim FEM could not solve this gear set's rim (a singular or indefinite stiffness, a contact
    or Newton iteration that does not settle); the message names the gear-set fields likely
    responsible, with their values, and what the solver said."""


class EnvelopeError(ProfilegenError, RuntimeError):
    """The envelope could not be classified (e.g. no conjugate point at all)."""


class ExportError(ProfilegenError, OSError):
    """An output file could not be written; nothing partial is left behind."""


class StressError(ProfilegenError, ValueError):
    """A stress model got inputs it cannot take (a thickness ≤ 0, a boss radius ≥ the cup
    radius, fatigue asked for without the material's limits, ...); the message names the
    parameter, its value, unit and allowed range."""


class SweepSpecError(ProfilegenError, ValueError):
    """A sweep spec (TOML) is malformed: an unknown or missing key, a value of the wrong
    type or out of range, a field path the gear set does not have; the message names the
    file and the key."""


class OptimizeSpecError(ProfilegenError, ValueError):
    """An optimisation spec (TOML) is malformed: an unknown key, a design variable that is not a
    gear-set field or whose bounds the gear set refuses, an objective or constraint on an output
    that does not exist (or that the search scene does not compute); the message names the file
    and the key."""


class BenchmarkNotFoundError(ProfilegenError, FileNotFoundError):
    """``profilegen bench`` outside a source checkout: the benchmarks live in the checkout's
    ``tests/benchmarks/``, which an installed package does not have; the message names the
    file looked for."""


class FilletError(ProfilegenError, ValueError):
    """The CS corners cannot be rounded as wire EDM cuts them: the wire (radius + spark gap) is
    too thick for the root of the tooth space, or the root fillet it leaves would cut into the
    mesh (enter the FS tooth family's swept region); the message names the gear-set field, the
    radius asked and the largest that fits."""
