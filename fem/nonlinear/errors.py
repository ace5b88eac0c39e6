"""Errors of the finite-strain solver."""

from __future__ import annotations

from softcath.design.errors import SoftcathError

__all__ = ["NonlinearError", "ConvergenceError", "SettingError"]


class NonlinearError(SoftcathError):
    """A finite-strain problem that is set up wrongly (bad mesh labels, facets, parameters)."""


class SettingError(NonlinearError):
    """A setting of the finite-strain check out of its bounds; ``parameter``, ``value`` and ``bound`` name it.

    The fields let a front end name the setting its own way (the command line
    says ``--steps`` where the library says ``steps``).
    """

    def __init__(self, parameter: str, value: object, bound: str) -> None:
        self.parameter, self.value, self.bound = parameter, value, bound
        super().__init__(f"{parameter} = {value!r}: {bound}")


class ConvergenceError(NonlinearError):
    """Newton's method failed even after cutting the load step down to its minimum.

    The message names the load factor and pressure reached, the residual and the
    number of cutbacks; no partial result is returned as if it were the answer.
    """
