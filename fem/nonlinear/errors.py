"""Errors of the finite-strain solver."""

from __future__ import annotations

from softcath.design.errors import DesignError, SoftcathError

__all__ = ["NonlinearError", "ConvergenceError", "SettingError"]


class NonlinearError(SoftcathError):
    """A finite-strain problem that is set up wrongly (bad mesh labels, facets, parameters)."""


class SettingError(NonlinearError, DesignError):
    """A setting of the finite-strain check out of its bounds; ``parameter``, ``value`` and ``bound`` name it.

    A :class:`~softcath.design.errors.DesignError` (the one error that names a
    parameter, its value and the bound) that is also a :class:`NonlinearError`.
    The fields let a front end name the setting its own way (the command line
    says ``--steps`` where the library says ``steps``).
    """


class ConvergenceError(NonlinearError):
    """Newton's method failed even after cutting the load step down to its minimum.

    The message names the load factor and pressure reached, the residual and the
    number of cutbacks; no partial result is returned as if it were the answer.
    """
