"""The error base types softcath raises for bad input.

Every error a user can cause derives from :class:`SoftcathError`, so the
command line can turn it into one line and a non-zero exit instead of a
traceback.
"""

from __future__ import annotations

import math

__all__ = ["SoftcathError", "DesignError", "DataError"]


class SoftcathError(Exception):
    """Base class for input errors a user can fix."""


class DesignError(SoftcathError, ValueError):
    """An impossible or malformed design.

    Parameters
    ----------
    parameter
        Dotted name of the offending parameter, e.g. ``"tube.material.poisson_ratio"``.
    value
        The value that was given.
    bound
        Human-readable statement of the violated bound, e.g. ``"must be < 0.5"``.
    """

    def __init__(self, parameter: str, value: object, bound: str) -> None:
        self.parameter = parameter
        self.value = value
        self.bound = bound
        super().__init__(f"{parameter} = {_fmt(value)}: {bound}")


class DataError(SoftcathError, ValueError):
    """A malformed measurement file or data series (names file, column and line)."""


def _fmt(value: object) -> str:
    if isinstance(value, float):  # includes numpy float64
        if not math.isfinite(value):
            return repr(float(value))
        short = f"{float(value):.6g}"
        # Six digits unless they round to another number (0.49999999 must not read as 0.5).
        return short if float(short) == float(value) else repr(float(value))
    if isinstance(value, str) and len(value) > _LONG:
        return f"{value[: _LONG - 20]!r}... ({len(value)} characters)"
    return repr(value)


#: Strings longer than this are quoted by their start and their length (a 10 000-character
#: expression must not fill the terminal).
_LONG = 120
