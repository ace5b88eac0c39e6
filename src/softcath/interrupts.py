"""A stop request that outlives the extensions that swallow it (:mod:`softcath.core.interrupts`)."""

from softcath.core.interrupts import clear_stop, raise_pending_stop, request_stop

__all__ = ["clear_stop", "raise_pending_stop", "request_stop"]
