"""Errors of the finite-strain solver."""

from __future__ import annotations

from softcath.design.errors import SoftcathError

__all__ = ["NonlinearError", "ConvergenceError"]


class NonlinearError(SoftcathError):
    """A finite-strain problem that is set up wrongly (bad mesh labels, facets, parameters)."""


class ConvergenceError(NonlinearError):
    """Newton's method failed even after cutting the load step down to its minimum.

    The message names the load factor and pressure reached, the residual and the
    number of cutbacks; no partial result is returned as if it were the answer.
    """
