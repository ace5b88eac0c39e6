"""Design validation: the input checks every design dataclass runs (raise DesignError naming the bound)."""

from __future__ import annotations

import math
import numbers

from softcath.core.errors import DesignError

# Design numbers are mm and MPa: nothing in a catheter (or its materials) lies outside
# [1e-9, 1e9] in magnitude, and staying inside keeps every derived quantity (I ~ length^4,
# EI ~ E length^4) far from float overflow and underflow.
MAX_MAGNITUDE = 1e9
MIN_POSITIVE = 1e-9

# What no catheter can have. The numbers are far outside any catheter yet inside the range
# the models were checked on; a design beyond them is a typo or a unit error, and the models
# would answer it (a 10⁶ mm tip bends "feasibly" in a sweep) or spend hours meshing it.
#: Largest coil outer diameter, mm: 36 Fr, above the largest intravascular catheters (~34 Fr).
MAX_COIL_DIAMETER_MM = 12.0
#: Longest bending segment, mm: steerable catheter tips bend over 5-100 mm.
MAX_BENDING_LENGTH_MM = 200.0
#: Largest spring index D/d (mean coil diameter over wire diameter): wound coils stay below ~25;
#: beyond 100 the wire cannot hold its helix and the frame model of the coil is singular.
MAX_SPRING_INDEX = 100.0
#: Largest initial torsional stress 8 F0 D / (pi d^3) of a close-wound coil, as a fraction of
#: the wire's Young's modulus: about the shear strength of the best spring wire (music wire
#: 1.1 GPa at E = 207 GPa); the usual wound-in stress is a tenth of it.
MAX_INITIAL_STRESS_OVER_E = 0.006


def finite(name: str, value: object) -> float:
    """Return ``value`` as a float, or raise if it is not a finite real number."""
    # A plain float skips the ABC check (a sweep validates ~25 numbers per design this way).
    if type(value) is not float and (isinstance(value, bool) or not isinstance(value, numbers.Real)):
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


def at_most(name: str, value: float, bound: float, why: str) -> None:
    """Refuse ``value > bound``; ``why`` says what the bound is (e.g. "36 Fr, no catheter is larger")."""
    if value > bound:
        raise DesignError(name, value, f"must be <= {bound:g} ({why})")


def less_than(name: str, value: float, bound_name: str, bound: float) -> None:
    if not value < bound:
        raise DesignError(name, value, f"must be < {bound_name} = {bound:.6g}")


def in_open_interval(name: str, value: object, lo: float, hi: float) -> float:
    v = finite(name, value)
    if not lo < v < hi:
        raise DesignError(name, value, f"must be in ({lo:g}, {hi:g})")
    return v
