"""Run a sweep: a local process pool by default, Dask distributed to scale out — the same task code.

Backends
--------
- ``workers=1``: in this process (no pickling; the baseline of the benchmarks);
- ``workers=N``: a :class:`concurrent.futures.ProcessPoolExecutor` of N processes;
- ``dask_local=N``: a :class:`distributed.LocalCluster` of N single-threaded worker
  processes on loopback;
- ``scheduler="tcp://host:port"``: an existing Dask scheduler (a cluster).

The two Dask backends are :mod:`softcath.studies.sweep.dask_scale_out`.

Every task's rows are written atomically as the task completes; a sweep
started again with the same spec and ``--out`` evaluates only the tasks that
have no result file.
"""

from __future__ import annotations

import logging
import time
import uuid
from dataclasses import dataclass
from pathlib import Path

from softcath.core.errors import DesignError
from softcath.core.interrupts import raise_pending_stop
from softcath.fem.limits import check_workers
from softcath.studies.sweep.dask_scale_out import connect, run_on_dask
from softcath.studies.sweep.evaluators import evaluate_task
from softcath.studies.sweep.lifeline import tie_to_parent
from softcath.studies.sweep.results import add_derived_columns, write_results
from softcath.studies.sweep.sampling import expand
from softcath.studies.sweep.spec import SweepSpec
from softcath.studies.sweep.store import SweepStore, design_counts
from softcath.studies.sweep.task_outcome import failed_frame as _failed_frame
from softcath.studies.sweep.task_outcome import outcome as _outcome

__all__ = ["SweepSummary", "run_sweep", "build_tasks"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class SweepSummary:
    """What a sweep run did.

    Attributes
    ----------
    out_dir
        The sweep directory.
    backend
        ``"serial"``, ``"processes(N)"``, ``"dask-local(N)"`` or ``"dask(<address>)"``.
    n_designs, n_tasks
        Size of the sweep.
    skipped_tasks, evaluated_tasks
        Tasks found finished on disk, and tasks evaluated by this run.
    evaluated_designs
        Designs evaluated by this run.
    ok_designs, failed_designs
        Over the whole sweep (all tasks, this run and earlier ones).
    seconds
        Wall time of this run [s].
    results_csv, results_parquet
        The merged tables.
    lost_tasks
        Tasks whose worker crashed (not saved; a rerun retries them).
    """

    out_dir: Path
    backend: str
    n_designs: int
    n_tasks: int
    skipped_tasks: int
    evaluated_tasks: int
    evaluated_designs: int
    ok_designs: int
    failed_designs: int
    seconds: float
    results_csv: Path
    results_parquet: Path
    lost_tasks: int = 0


def build_tasks(spec: SweepSpec, variants: list[dict]) -> list[dict]:
    """Cut the variants into tasks of ``spec.effective_chunk_size`` consecutive designs."""
    size = spec.effective_chunk_size
    paths = [p.path for p in spec.parameters]
    tasks = []
    for t, start in enumerate(range(0, len(variants), size)):
        chunk = variants[start : start + size]
        tasks.append(
            {
                "task_id": t,
                "design_ids": list(range(start, start + len(chunk))),
                "variants": chunk,
                "param_paths": paths,
                "base_table": spec.base_table,
                "pressures_MPa": list(spec.pressures),
                "loads": list(spec.loads),
                "evaluators": list(spec.evaluators),
                "mesh_size": spec.mesh_size,
                "max_strain": spec.max_strain,
                "section": spec.section_options,
                "options": spec.options,
            }
        )
    return tasks


def _serial(tasks):
    for task in tasks:
        try:
            yield task, evaluate_task(task)
        except Exception as exc:  # reported per task; the sweep goes on
            raise_pending_stop()
            yield task, _failed_frame(task, exc)


def _single_threaded_worker(sweep_pid: int | None = None) -> None:
    """One BLAS/MKL thread per worker process (as Dask's nanny does): N workers use N cores, not N².

    With ``sweep_pid`` the worker also dies with the sweep process (``softcath.studies.sweep.lifeline``).
    """
    import os

    from threadpoolctl import threadpool_limits

    for var in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
        os.environ.setdefault(var, "1")  # for libraries loaded from here on
    # The process was preloaded with numpy: its BLAS read the variables already. One thread also
    # makes a worker's results bit-identical to a Dask worker's (BLAS rounding depends on threads).
    threadpool_limits(limits=1)
    if sweep_pid is not None:
        tie_to_parent(sweep_pid)


def _pool(tasks, workers: int):
    import multiprocessing
    import os
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # Not "fork": this process may already run OpenMP/MKL thread pools (e.g. the FEM's PARDISO after an
    # in-process evaluation), and a forked child of such a process deadlocks in its first solve. The fork
    # server is a clean process; preloading the evaluator there keeps worker start-up cheap.
    if "forkserver" in multiprocessing.get_all_start_methods():
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(["softcath.studies.sweep.evaluators"])
    else:  # Windows
        ctx = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(
        max_workers=workers, mp_context=ctx, initializer=_single_threaded_worker, initargs=(os.getpid(),)
    )
    try:
        futures = {pool.submit(evaluate_task, t): t for t in tasks}
        for fut in as_completed(futures):
            task = futures[fut]
            try:
                yield task, fut.result()
            except Exception as exc:
                raise_pending_stop()
                yield _outcome(task, exc)
    finally:
        # On Ctrl-C or an error, do not start the queued tasks: finished ones are on disk already.
        pool.shutdown(wait=True, cancel_futures=True)


def _check_options(workers, dask_local, scheduler) -> None:
    chosen = [n for n, v in (("workers", workers), ("dask_local", dask_local), ("scheduler", scheduler)) if v]
    if len(chosen) > 1:
        raise DesignError("backend", " ".join(chosen), "choose one of workers, dask_local, scheduler")

    for name, v in (("workers", workers), ("dask_local", dask_local)):
        check_workers(v, param=name)
    if scheduler is not None and not str(scheduler).startswith(("tcp://", "tls://", "inproc://", "ucx://")):
        raise DesignError("scheduler", scheduler, "must be a Dask scheduler address such as tcp://HOST:8786")


def run_sweep(
    spec: SweepSpec,
    out_dir: str | Path,
    *,
    workers: int | None = None,
    dask_local: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
) -> SweepSummary:
    """Evaluate every design of ``spec`` not yet finished in ``out_dir`` and merge the results.

    Parameters
    ----------
    spec
        The sweep (:func:`softcath.studies.sweep.load_spec`).
    out_dir
        Sweep directory (created; resumed if it holds the same sweep).
    workers
        Local worker processes (default: the number of CPUs; 1 runs in this process).
    dask_local
        Run on a Dask LocalCluster of this many worker processes instead.
    scheduler
        Run on the Dask scheduler at this address instead.
    progress
        Show a progress bar (count, failures, ETA) on stderr.
    """
    _check_options(workers, dask_local, scheduler)
    t0 = time.perf_counter()
    spec = _with_recorded_task_size(spec, out_dir)
    variants = expand(spec)
    tasks = build_tasks(spec, variants)
    store = _prepared_store(spec, out_dir, variants, tasks)
    done = store.finished()
    pending = [t for t in tasks if t["task_id"] not in done]
    skipped_designs = sum(len(t["design_ids"]) for t in tasks if t["task_id"] in done)
    run_id = uuid.uuid4().hex[:12]

    results, backend, client, cluster = _start_backend(pending, workers, dask_local, scheduler)
    evaluated_designs, lost = _store_results(
        results,
        store,
        run_id=run_id,
        total=len(variants),
        initial=skipped_designs,
        desc=f"sweep {spec.name}",
        progress=progress,
        closers=(client, cluster),
    )

    if lost:
        log.warning("%d tasks were lost to worker crashes; run the same command again to retry them", lost)
    df, csv_path, pq_path = _merge_results(store, spec)
    per_design = df.drop_duplicates("design_id")
    summary = SweepSummary(
        out_dir=store.root,
        backend=backend,
        n_designs=len(variants),
        n_tasks=len(tasks),
        skipped_tasks=len(tasks) - len(pending),
        evaluated_tasks=len(pending) - lost,
        lost_tasks=lost,
        evaluated_designs=evaluated_designs,
        ok_designs=int((per_design["status"] == "ok").sum()),
        failed_designs=int((per_design["status"] == "failed").sum()),
        seconds=time.perf_counter() - t0,
        results_csv=csv_path,
        results_parquet=pq_path,
    )
    log.info("sweep %s: %s", spec.name, summary)
    return summary


def _with_recorded_task_size(spec: SweepSpec, out_dir: str | Path) -> SweepSpec:
    """``spec`` with the task size ``out_dir``'s sweep was run with, when that is all that differs.

    The task size is part of the fingerprint (a task's file holds its designs), so a sweep
    written with another default task size resumes with the tasks it has.
    """
    import dataclasses

    recorded = SweepStore(out_dir).recorded_spec()
    if recorded is None or recorded.get("fingerprint") == spec.fingerprint():
        return spec
    size = recorded.get("chunk_size")
    if isinstance(size, bool) or not isinstance(size, int) or size < 1:
        return spec
    resumed = dataclasses.replace(spec, chunk_size=size)
    if resumed.effective_chunk_size != size or resumed.fingerprint() != recorded["fingerprint"]:
        return spec  # another sweep: prepare() refuses the folder
    log.info("%s: resuming with the sweep's recorded tasks of %d designs", out_dir, size)
    return resumed


def _prepared_store(
    spec: SweepSpec, out_dir: str | Path, variants: list[dict], tasks: list[dict]
) -> SweepStore:
    """The sweep directory, prepared with the manifest and the design table (resumed if it holds this
    sweep)."""
    import pandas as pd

    store = SweepStore(out_dir)
    designs = pd.DataFrame(variants) if spec.parameters else pd.DataFrame(index=range(len(variants)))
    designs.insert(0, "design_id", range(len(variants)))
    manifest = {
        "spec": spec.to_json(),
        "base_table": spec.base_table,
        "n_designs": len(variants),
        "n_tasks": len(tasks),
    }
    store.prepare(manifest, designs)
    return store


def _start_backend(pending: list[dict], workers, dask_local, scheduler):
    """Start evaluating ``pending``: the results iterator, the backend's name and the Dask client and
    cluster (``None`` for local processes)."""
    import os

    client = cluster = None
    if scheduler or dask_local:
        client, cluster, backend = connect(scheduler, dask_local)
        results = run_on_dask(pending, client)
    else:
        n = workers or os.cpu_count() or 1
        n = min(n, max(len(pending), 1))
        backend = "serial" if n == 1 else f"processes({n})"
        results = _serial(pending) if n == 1 else _pool(pending, n)
    return results, backend, client, cluster


def _store_results(
    results, store: SweepStore, *, run_id: str, total: int, initial: int, desc: str, progress: bool, closers
) -> tuple[int, int]:
    """Write each finished task to ``store`` with a progress bar, then stop the backend and close the
    Dask ``closers``: the designs evaluated and the tasks lost to worker crashes."""
    from tqdm import tqdm

    evaluated_designs = failed_now = lost = 0
    bar = tqdm(
        total=total,
        initial=initial,
        unit="design",
        desc=desc,
        disable=not progress,
        dynamic_ncols=True,
    )
    try:
        for task, frame in results:
            if frame is None:
                lost += 1
                continue
            store.write_task(task["task_id"], frame, run_id=run_id)
            n_d = len(task["design_ids"])
            failed_now += design_counts(frame)[1]
            evaluated_designs += n_d
            bar.update(n_d)
            bar.set_postfix(failed=failed_now, refresh=False)
    finally:
        bar.close()
        results.close()  # stops the backend generator (cancels queued work) if the loop ended early
        for closer in closers:
            if closer is not None:
                closer.close()
    return evaluated_designs, lost


def _merge_results(store: SweepStore, spec: SweepSpec):
    """The merged results with derived columns, and the CSV and Parquet files written from them."""
    df = store.read_all()
    # Derived columns are recomputed on the merged table (cheap) so files from any run agree.
    df = add_derived_columns(df, max_strain=spec.max_strain, p_max=spec.p_max)
    csv_path, pq_path = write_results(df, store.root)
    return df, csv_path, pq_path
