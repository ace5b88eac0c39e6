"""Background work where only the newest request matters: a newer one supersedes the older.

:class:`LatestJob` runs one computation at a time on its own thread. Submitting
work cancels whatever was submitted before: a queued request never starts, a
running one is told to stop at its next progress report (its ``Ticket.progress``
raises :class:`Superseded`), and whatever an old request still returns is never
shown, because the app only reads :attr:`LatestJob.latest`. A crash inside the
work is caught and kept as the ticket's one-line ``message``; the thread and
the app go on.

>>> job = LatestJob("demo")
>>> t = job.submit(lambda ticket, x: x * 2, 21)
>>> t.wait(5.0), t.result
(True, 42)
>>> job.close()
"""

from __future__ import annotations

import itertools
import logging
import threading
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

from softcath.design.errors import SoftcathError

__all__ = ["JobView", "LatestJob", "Superseded", "Ticket"]

log = logging.getLogger(__name__)


class Superseded(Exception):
    """Raised inside work whose result nobody wants any more (a newer request came)."""


@dataclass(frozen=True)
class JobView:
    """A snapshot of a ticket for the page: what to show about it.

    Attributes
    ----------
    number
        The ticket's number (increasing with each submission).
    state
        ``"queued"``, ``"running"``, ``"done"``, ``"failed"`` or ``"cancelled"``.
    done, total
        Progress (steps done of ``total``; ``total`` 0 when not known yet).
    message
        The one-line reason of a failure (empty otherwise).
    """

    number: int
    state: str
    done: int
    total: int
    message: str


class Ticket:
    """One submitted computation: its progress, its cancellation flag and its outcome."""

    def __init__(self, number: int) -> None:
        self.number = number
        self.state = "queued"
        self.done = 0
        self.total = 0
        self.result: Any = None
        self.message = ""
        self._cancel = threading.Event()
        self._finished = threading.Event()

    @property
    def cancelled(self) -> bool:
        return self._cancel.is_set()

    def cancel(self) -> None:
        """Ask the work to stop (it does at its next :meth:`progress` or :meth:`check`)."""
        self._cancel.set()

    def check(self) -> None:
        """Raise :class:`Superseded` if this ticket was cancelled."""
        if self._cancel.is_set():
            raise Superseded(f"request {self.number} superseded")

    def progress(self, done: int, total: int) -> None:
        """Record progress; raises :class:`Superseded` if this ticket was cancelled."""
        self.done, self.total = int(done), int(total)
        self.check()

    def sleep(self, seconds: float) -> None:
        """Wait ``seconds`` unless cancelled first (then raise :class:`Superseded` at once)."""
        if self._cancel.wait(seconds):
            raise Superseded(f"request {self.number} superseded")

    def wait(self, timeout: float | None = None) -> bool:
        """Block until the work ended (done, failed or cancelled); False on timeout."""
        return self._finished.wait(timeout)

    def view(self) -> JobView:
        return JobView(self.number, self.state, self.done, self.total, self.message)

    def _run(self, fn: Callable[..., Any], args: tuple, kwargs: dict) -> None:
        try:
            self.check()
            self.state = "running"
            self.result = fn(self, *args, **kwargs)
            self.state = "done"
        except Superseded:
            self.state = "cancelled"
        except SoftcathError as exc:
            self.state, self.message = "failed", " ".join(str(exc).split())
        except Exception as exc:  # a crash in one computation must leave the app running
            log.exception("background computation %d failed", self.number)
            text = " ".join(str(exc).split())[:300] or "(no message)"
            self.state, self.message = "failed", f"unexpected {type(exc).__name__}: {text}"
        finally:
            self._finished.set()


class LatestJob:
    """One worker thread running the newest of the computations submitted to it.

    Parameters
    ----------
    name
        Names the worker thread (``softcath-app-<name>``).
    """

    def __init__(self, name: str) -> None:
        self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix=f"softcath-app-{name}")
        self._numbers = itertools.count(1)
        self._lock = threading.Lock()
        self._latest: Ticket | None = None
        self._future: Future | None = None

    @property
    def latest(self) -> Ticket | None:
        """The newest ticket (the only one whose result the app shows), or None."""
        return self._latest

    def submit(self, fn: Callable[..., Any], *args: Any, **kwargs: Any) -> Ticket:
        """Run ``fn(ticket, *args, **kwargs)`` after cancelling every earlier request."""
        with self._lock:
            self.cancel()
            ticket = Ticket(next(self._numbers))
            self._latest = ticket
            self._future = self._pool.submit(ticket._run, fn, args, kwargs)
            return ticket

    def cancel(self) -> None:
        """Cancel the newest request (an older one is already cancelled)."""
        ticket, future = self._latest, self._future
        if ticket is not None and ticket.state in ("queued", "running"):
            ticket.cancel()
            if future is not None and future.cancel():  # never started
                ticket.state = "cancelled"
                ticket._finished.set()

    def close(self) -> None:
        """Cancel the work and let the thread end (no new submissions afterwards)."""
        self.cancel()
        self._pool.shutdown(wait=False, cancel_futures=True)
