"""Input checks shared by the design dataclasses (raise DesignError naming the bound)."""

from __future__ import annotations

import math
import numbers

from softcath.design.errors import DesignError

# Design numbers are mm and MPa: nothing in a catheter (or its materials) lies outside
# [1e-9, 1e9] in magnitude, and staying inside keeps every derived quantity (I ~ length^4,
# EI ~ E length^4) far from float overflow and underflow.
MAX_MAGNITUDE = 1e9
MIN_POSITIVE = 1e-9


def finite(name: str, value: object) -> float:
    """Return ``value`` as a float, or raise if it is not a finite real number."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise DesignError(name, value, "must be a real number")
    v = float(value)
    if not math.isfinite(v):
        raise DesignError(name, value, "must be finite")
    if abs(v) > MAX_MAGNITUDE:
        raise DesignError(name, value, f"magnitude must be <= {MAX_MAGNITUDE:g} (mm, MPa)")
    return v


def positive(name: str, value: object) -> float:
    v = finite(name, value)
    if v <= 0:
        raise DesignError(name, value, "must be > 0")
    if v < MIN_POSITIVE:
        raise DesignError(name, value, f"must be >= {MIN_POSITIVE:g} (mm, MPa)")
    return v


def nonnegative(name: str, value: object) -> float:
    v = finite(name, value)
    if v < 0:
        raise DesignError(name, value, "must be >= 0")
    return v


def less_than(name: str, value: float, bound_name: str, bound: float) -> None:
    if not value < bound:
        raise DesignError(name, value, f"must be < {bound_name} = {bound:.6g}")


def in_open_interval(name: str, value: object, lo: float, hi: float) -> float:
    v = finite(name, value)
    if not lo < v < hi:
        raise DesignError(name, value, f"must be in ({lo:g}, {hi:g})")
    return v
