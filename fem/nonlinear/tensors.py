"""Deprecated: moved to :mod:`softcath.fem.hyperelastic.tensors`.

The old import path keeps working for a while: a name used from here warns (``DeprecationWarning``).
"""

from __future__ import annotations

import softcath.fem.hyperelastic.tensors as _new
from softcath.core.deprecation import moved_names

__getattr__ = moved_names(__name__, _new, ("LEVI_CIVITA", "det", "cofactor", "dcofactor"))
