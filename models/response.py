"""Deprecated: moved to :mod:`softcath.core.response`.

The old import path keeps working for a while: a name used from here warns (``DeprecationWarning``).
"""

from __future__ import annotations

import softcath.core.response as _new
from softcath.core.deprecation import moved_names

__getattr__ = moved_names(__name__, _new, ("OBSERVABLES", "ResponseBatch", "TipResponse"))
