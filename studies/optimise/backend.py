"""Where an optimisation's evaluations run: this process, a pool of local processes, or Dask.

The same task dicts and :func:`softcath.studies.sweep.evaluators.evaluate_task`
as a sweep, so every sweep evaluator (model tier) works here as it is added.
Unlike a sweep, an optimiser sends many small batches (one per generation):
the pool or the Dask client is opened once and kept for the whole run.
Results come back in task order whatever the backend, so a seeded run gives
the same result on every backend.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

from softcath.design.errors import DesignError
from softcath.fem.limits import check_workers
from softcath.studies.sweep.evaluators import evaluate_task
from softcath.studies.sweep.runner import _single_threaded_worker

__all__ = ["Backend"]


class Backend:
    """A context manager that evaluates lists of sweep tasks.

    Parameters
    ----------
    workers
        Local worker processes (``None`` or 1: in this process).
    scheduler
        Address of a Dask scheduler (``tcp://host:port``) instead.
    client
        An existing :class:`distributed.Client` instead (e.g. of a ``LocalCluster``).
    """

    def __init__(self, *, workers: int | None = None, scheduler: str | None = None, client=None) -> None:
        if sum(x is not None for x in (workers, scheduler, client)) > 1:
            raise DesignError("backend", (workers, scheduler), "choose one of workers, scheduler, client")

        check_workers(workers)
        if scheduler is not None and not str(scheduler).startswith(("tcp://", "tls://", "inproc://")):
            raise DesignError(
                "scheduler", scheduler, "must be a Dask scheduler address such as tcp://HOST:8786"
            )
        self.workers = workers or 1
        self.scheduler = scheduler
        self._client = client
        self._own_client = False
        self._pool = None

    @property
    def slots(self) -> int:
        """How many tasks run at once (to cut a batch into that many tasks)."""
        if self._client is not None:
            return max(sum(self._client.nthreads().values()), 1)
        return self.workers

    @property
    def name(self) -> str:
        if self.scheduler:
            return f"dask({self.scheduler})"
        if self._client is not None:
            return "dask"
        return "serial" if self.workers == 1 else f"processes({self.workers})"

    def __enter__(self) -> Backend:
        if self.scheduler:
            from distributed import Client

            try:
                self._client = Client(self.scheduler, timeout="15s")
            except (OSError, TimeoutError) as exc:
                raise DesignError("scheduler", self.scheduler, f"cannot be reached: {exc}") from None
            self._own_client = True
        elif self.workers > 1 and self._client is None:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            method = "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"
            ctx = multiprocessing.get_context(method)
            self._pool = ProcessPoolExecutor(
                max_workers=self.workers,
                mp_context=ctx,
                initializer=_single_threaded_worker,
                initargs=(os.getpid(),),
            )
        return self

    def __exit__(self, *exc) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None
        if self._own_client and self._client is not None:
            self._client.close()
            self._client = None

    def map(self, tasks: Sequence[dict]) -> list:
        """The result frame of every task, in order."""
        if self._client is not None:
            futures = [self._client.submit(evaluate_task, t, pure=False) for t in tasks]
            return self._client.gather(futures)
        if self._pool is not None:
            return list(self._pool.map(evaluate_task, tasks))
        return [evaluate_task(t) for t in tasks]
