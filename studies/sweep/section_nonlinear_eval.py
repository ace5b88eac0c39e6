"""Deprecated: moved to :mod:`softcath.models.section_nonlinear_eval`.

The old import path keeps working for a while: a name used from here warns (``DeprecationWarning``).
"""

from __future__ import annotations

import softcath.models.section_nonlinear_eval as _new
from softcath.core.deprecation import moved_names

__getattr__ = moved_names(
    __name__,
    _new,
    ("REST_PROBE_MPA", "SECTION_NONLINEAR_KEYS", "curve_with_rest", "section_nonlinear_columns"),
)
