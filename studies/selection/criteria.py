"""Deprecated: moved to :mod:`softcath.studies.criteria`.

The old import path keeps working for a while: a name used from here warns (``DeprecationWarning``).
"""

from __future__ import annotations

import softcath.studies.criteria as _new
from softcath.core.deprecation import moved_names

__getattr__ = moved_names(
    __name__,
    _new,
    (
        "Constraint",
        "Objective",
        "at_pressure",
        "parse_constraint",
        "parse_objective",
        "check_columns",
        "rows_at",
        "without_text",
    ),
)
