"""Errors that softcath raises for bad input (defined in :mod:`softcath.core.errors`).

Every error a user can cause derives from :class:`SoftcathError`, so the
command line can turn it into one line and a non-zero exit instead of a
traceback. The classes live on the ground floor so that every room raises them.
"""

from __future__ import annotations

from softcath.core.errors import DataError, DesignError, SoftcathError

__all__ = ["SoftcathError", "DesignError", "DataError"]
