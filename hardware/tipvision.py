"""The tip vision's former module path: re-exports :mod:`softcath.hardware.vision`.

Kept so that ``from softcath.hardware.tipvision import Calibration, measure`` keeps working.
"""

from __future__ import annotations

from softcath.hardware import vision as _vision
from softcath.hardware.vision import *  # noqa: F403 - the same names, by design

__all__ = list(_vision.__all__)
