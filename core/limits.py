"""The one pressure bound every command and model checks against.

>>> check_pressure([0.0, 0.5]).tolist()
[0.0, 0.5]
>>> check_pressure(1e300, param="--pressure")
Traceback (most recent call last):
...
softcath.core.errors.DesignError: --pressure = 1e+300: must be within ±100 MPa (no model holds beyond)
"""

from __future__ import annotations

import math

import numpy as np

from softcath.core.errors import DesignError

__all__ = ["MAX_PRESSURE_MPA", "check_pressure"]

#: Largest pressure any command accepts, MPa: 100× the 1 MPa where the paper's tip already
#: bends > 50°; beyond it every model's answer is meaningless (and 1e300 overflows).
MAX_PRESSURE_MPA = 100.0


def check_pressure(values, *, param: str = "pressure") -> np.ndarray:
    """``values`` as a float array (at least 1-D), refused if one is not finite or exceeds the bound.

    Parameters
    ----------
    values
        One pressure or several, MPa (signed: a magnitude is checked).
    param
        The name the refusal gives (an option, a key, a keyword).

    Raises
    ------
    DesignError
        A value is not finite, or its magnitude exceeds :data:`MAX_PRESSURE_MPA`.
    """
    p = np.atleast_1d(np.asarray(values, dtype=float))
    for v in p.ravel():
        if not math.isfinite(v):
            raise DesignError(param, float(v), "must be a finite pressure in MPa")
        if abs(v) > MAX_PRESSURE_MPA:
            raise DesignError(
                param, float(v), f"must be within ±{MAX_PRESSURE_MPA:g} MPa (no model holds beyond)"
            )
    return p
