"""Deprecated: moved to :mod:`softcath.fem.hyperelastic.laws`.

The old import path keeps working for a while: a name used from here warns (``DeprecationWarning``).
"""

from __future__ import annotations

import softcath.fem.hyperelastic.laws as _new
from softcath.core.deprecation import moved_names

__getattr__ = moved_names(
    __name__,
    _new,
    (
        "Yeoh",
        "AnisotropicSVK",
        "neo_hookean",
        "isotropic_from_young",
        "yeoh_at_modulus",
        "transversely_isotropic",
        "isotropic_tensor",
    ),
)
