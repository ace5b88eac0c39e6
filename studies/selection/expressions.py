"""Deprecated: moved to :mod:`softcath.studies.criteria.expressions`.

The old import path keeps working for a while: a name used from here warns (``DeprecationWarning``).
"""

from __future__ import annotations

import softcath.studies.criteria.expressions as _new
from softcath.core.deprecation import moved_names

__getattr__ = moved_names(
    __name__,
    _new,
    (
        "SelectionError",
        "Expr",
        "COMPARE",
        "MAX_EXPR_CHARS",
        "MAX_EXPR_DEPTH",
        "check_tree",
        "parse_tree",
        "parse_expr",
        "finite_constant",
        "op_name",
        "short",
    ),
)
