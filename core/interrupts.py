"""A stop request (Ctrl-C, SIGTERM) that outlives the extensions that swallow it.

A signal handler's exception is raised wherever the interpreter happens to be.
When that is inside a ctypes call (gmsh's API), ctypes converts it into an
``ArgumentError``, an ordinary ``Exception``, and a fallback or a per-design
failure handler would then carry on as if nothing had been asked. The handler
therefore also records the request here, and every handler that keeps work
going after an ``Exception`` calls :func:`raise_pending_stop` first.

>>> clear_stop()
>>> raise_pending_stop()  # nothing asked: returns
>>> request_stop(KeyboardInterrupt)
>>> try:
...     raise_pending_stop()
... except KeyboardInterrupt:
...     print("stopped")
stopped
>>> clear_stop()
"""

from __future__ import annotations

__all__ = ["clear_stop", "raise_pending_stop", "request_stop"]

_pending: type[KeyboardInterrupt] | None = None


def request_stop(kind: type[KeyboardInterrupt] = KeyboardInterrupt) -> None:
    """Record that the process was asked to stop with ``kind`` (called by signal handlers)."""
    global _pending
    _pending = kind


def raise_pending_stop() -> None:
    """Raise the recorded stop request, if any; a no-op otherwise."""
    if _pending is not None:
        raise _pending()


def clear_stop() -> None:
    """Forget a recorded request (a new command starts)."""
    global _pending
    _pending = None
