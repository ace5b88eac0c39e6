"""Deprecated: moved to :mod:`softcath.models.section_eval`.

The old import path keeps working for a while: a name used from here warns (``DeprecationWarning``).
"""

from __future__ import annotations

import softcath.models.section_eval as _new
from softcath.core.deprecation import moved_names

__getattr__ = moved_names(
    __name__, _new, ("SECTION_KEYS", "SECTION_OPTIONS", "section_blocks_many", "section_columns")
)
