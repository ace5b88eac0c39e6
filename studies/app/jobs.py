"""Background work where only the newest request matters, in a child process of its own.

:class:`LatestJob` hands requests to one worker process (``spawn``: a fresh
interpreter), at a lower OS priority and on one BLAS thread. A crash in
compiled code there (gmsh, a solver) cannot take the server down, and the
worker's gmsh calls never meet the server thread's (gmsh is not thread-safe).
Submitting a request supersedes every earlier one: a queued request never
starts, a running one stops at its next progress report (``progress`` raises
:class:`Superseded` in the worker), and the page only reads
:attr:`LatestJob.latest`. A failure in
the work is reported as the ticket's one-line ``message``; a worker that dies
(a crash in compiled code) fails its ticket and is started again by the next
request. The page calls :meth:`LatestJob.poll` to collect what the worker said.

The work is a module-level function ``fn(progress, *args)`` (the worker imports
it by name); ``progress(done, total)`` reports progress and is where a
superseded request stops.
"""

from __future__ import annotations

import logging
import multiprocessing as mp
import queue
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from softcath.core.errors import SoftcathError

__all__ = ["JobView", "LatestJob", "Superseded", "Ticket"]

log = logging.getLogger(__name__)

_ENDED = ("done", "failed", "cancelled")
#: The worker's OS priority increment: the server and the browser get the cores first.
WORKER_NICE = 5


class Superseded(Exception):
    """Raised inside work whose result nobody wants any more (a newer request came)."""


@dataclass(frozen=True)
class JobView:
    """A snapshot of a ticket for the page.

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
    """One submitted request: its state, progress and outcome (updated by :meth:`LatestJob.poll`)."""

    def __init__(self, number: int) -> None:
        self.number = number
        self.state = "queued"
        self.done = 0
        self.total = 0
        self.result: Any = None
        self.message = ""

    @property
    def ended(self) -> bool:
        return self.state in _ENDED

    def view(self) -> JobView:
        return JobView(self.number, self.state, self.done, self.total, self.message)


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    if isinstance(exc, SoftcathError):
        return text
    return f"unexpected {type(exc).__name__}: {text[:300] or '(no message)'}"


def _serve(fn: Callable[..., Any], requests: Any, replies: Any, latest: Any) -> None:
    """The worker process: run each request unless a newer one came; report on ``replies``."""
    import os

    from threadpoolctl import threadpool_limits

    try:
        os.nice(WORKER_NICE)
    except (AttributeError, OSError):
        pass
    threadpool_limits(limits=1)  # one core for the background; the other serves the page
    while True:
        item = requests.get()
        if item is None:
            return
        number, args = item
        if latest.value != number:
            replies.put((number, "cancelled", None))
            continue

        def progress(done: int, total: int, number: int = number) -> None:
            replies.put((number, "progress", (int(done), int(total))))
            if latest.value != number:
                raise Superseded(f"request {number} superseded")

        replies.put((number, "running", None))
        try:
            replies.put((number, "done", fn(progress, *args)))
        except Superseded:
            replies.put((number, "cancelled", None))
        except Exception as exc:  # one request's failure; the worker serves the next
            replies.put((number, "failed", _one_line(exc)))


class LatestJob:
    """One worker process running the newest of the requests submitted to it.

    Parameters
    ----------
    fn
        The work, a module-level function ``fn(progress, *args)``.
    """

    def __init__(self, fn: Callable[..., Any]) -> None:
        self._fn = fn
        self._ctx = mp.get_context("spawn")
        self._proc: Any = None
        self._requests: Any = None
        self._replies: Any = None
        self._latest_number: Any = None
        self._count = 0
        self._tickets: dict[int, Ticket] = {}
        self._latest: Ticket | None = None

    def start(self) -> None:
        """Start the worker now (it imports the models for a few seconds); submit starts it too."""
        if self._proc is not None and self._proc.is_alive():
            return
        self._requests, self._replies = self._ctx.Queue(), self._ctx.Queue()
        self._latest_number = self._ctx.Value("q", self._count)
        self._proc = self._ctx.Process(
            target=_serve,
            args=(self._fn, self._requests, self._replies, self._latest_number),
            name="softcath-app-worker",
            daemon=True,
        )
        self._proc.start()

    @property
    def latest(self) -> Ticket | None:
        """The newest ticket (the only one whose result the app shows), or None."""
        return self._latest

    def submit(self, *args: Any) -> Ticket:
        """Run ``fn(progress, *args)`` in the worker, superseding every earlier request."""
        self.start()
        self._count += 1
        ticket = Ticket(self._count)
        self._tickets[ticket.number] = ticket
        self._latest = ticket
        self._latest_number.value = ticket.number
        self._requests.put((ticket.number, args))
        return ticket

    def poll(self) -> Ticket | None:
        """Collect what the worker reported; returns :attr:`latest`."""
        if self._replies is None:
            return self._latest
        alive = self._proc.is_alive()  # before reading: a last message is not missed
        while True:
            try:
                number, kind, payload = self._replies.get_nowait()
            except queue.Empty:
                break
            ticket = self._tickets.get(number)
            if ticket is None:
                continue
            if kind == "progress":
                ticket.done, ticket.total = payload
            elif kind == "done":
                ticket.state, ticket.result = "done", payload
            elif kind == "failed":
                ticket.state, ticket.message = "failed", payload
            else:
                ticket.state = kind
        if not alive:
            code = self._proc.exitcode
            for ticket in self._tickets.values():
                if not ticket.ended:
                    ticket.state = "failed"
                    ticket.message = f"the background process ended (exit code {code}); try again"
            self._stop_worker()
        self._tickets = {n: t for n, t in self._tickets.items() if not t.ended}
        return self._latest

    def wait(self, ticket: Ticket, timeout: float) -> bool:
        """Poll until ``ticket`` ended (done, failed or cancelled); False on timeout."""
        end = time.monotonic() + timeout
        while not ticket.ended and time.monotonic() < end:
            self.poll()
            time.sleep(0.02)
        return ticket.ended

    def cancel(self) -> None:
        """Stop the newest request at its next progress report (an older one is already superseded)."""
        if self._latest_number is not None:
            self._latest_number.value = -1

    def close(self) -> None:
        """End the worker now (the page was closed; it holds nothing worth waiting for)."""
        self.cancel()
        self._stop_worker()

    def _stop_worker(self) -> None:
        if self._proc is not None:
            if self._proc.is_alive():
                self._proc.terminate()
            self._proc.join(timeout=5)
            self._proc = None
        for q in (self._requests, self._replies):
            if q is not None:
                q.cancel_join_thread()
                q.close()
        self._requests = self._replies = self._latest_number = None
