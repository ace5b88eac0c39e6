"""The sweep's Dask path (scale-out): a LocalCluster or an existing scheduler runs the same tasks.

:func:`softcath.studies.sweep.runner.run_sweep` comes here for ``dask_local=N``
(a :class:`distributed.LocalCluster` of N single-threaded worker processes on
loopback) or ``scheduler="tcp://host:port"`` (an existing Dask scheduler: the
workers need softcath installed; results come back to the sweep's process,
which alone writes the sweep directory, so the workers need no shared file
system).
"""

from __future__ import annotations

import uuid

from softcath.core.errors import DesignError
from softcath.core.interrupts import raise_pending_stop
from softcath.studies.sweep.evaluators import evaluate_task
from softcath.studies.sweep.task_outcome import outcome

__all__ = ["connect", "run_on_dask"]


def connect(scheduler: str | None, dask_local: int | None):
    """A Dask client for the sweep: ``(client, cluster or None, backend label)``.

    Raises
    ------
    DesignError
        If the scheduler at ``scheduler`` cannot be reached.
    """
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout="15s")
        except (OSError, TimeoutError) as exc:
            raise DesignError("scheduler", scheduler, f"cannot be reached: {exc}") from None
        return client, None, f"dask({scheduler})"
    import dask

    # The workers' statistical profiler samples every thread every 10 ms: about 10 % more CPU
    # per FEM design measured here, for a profile nobody reads in a batch sweep. The nanny's
    # MALLOC_TRIM_THRESHOLD_ costs ~30 % more CPU per FEM design (evaluators.restore_malloc_thresholds);
    # the workers keep glibc's dynamic thresholds and one BLAS thread each.
    environ = {
        k: v
        for k, v in dask.config.get("distributed.nanny.pre-spawn-environ").items()
        if k != "MALLOC_TRIM_THRESHOLD_"
    }
    with dask.config.set(
        {"distributed.worker.profile.enabled": False, "distributed.nanny.pre-spawn-environ": environ}
    ):
        cluster = LocalCluster(
            n_workers=dask_local,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
        )
    # (its worker processes die with this one by themselves: Dask's parent-alive pipe)
    return Client(cluster), cluster, f"dask-local({dask_local})"


def run_on_dask(tasks, client):
    """Yield ``(task, frame)`` as each task finishes on ``client`` (``frame`` None: task lost)."""
    from distributed import as_completed

    futures = {
        client.submit(evaluate_task, t, pure=False, key=f"softcath-task-{uuid.uuid4().hex}"): t for t in tasks
    }
    for fut in as_completed(list(futures)):
        task = futures[fut]
        try:
            yield task, fut.result()
        except Exception as exc:
            raise_pending_stop()
            yield outcome(task, exc)
