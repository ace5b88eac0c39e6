"""Evaluate one task of a sweep: validate each design, then ask each of the sweep's tiers for its responses.

A task is a plain dict (picklable, so the same function runs in a local
process pool or on Dask workers) and its result a :class:`pandas.DataFrame`
with one row per design × pressure × load (columns in :mod:`softcath.studies.sweep.results`).
Every tier answers through the registry (:mod:`softcath.models`): the paper's formula
(always, vectorised over the task's designs), and those of the spec's ``evaluators``
(the section model batched, the others design by design); their
:class:`~softcath.models.ResponseBatch` fills the tier's columns
(:data:`~softcath.studies.sweep.results.TIER_COLUMNS`). A design that cannot be built is
reported with status ``failed`` and the :class:`~design.errors.DesignError` reason; a tier
that fails on a design adds its reason; neither ever stops the task.
"""

from __future__ import annotations

import json
import logging
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from softcath import models
from softcath.design.errors import DesignError
from softcath.models.fem3d import fem_check_function, fem_records
from softcath.studies.sweep.results import _FEM_RENAME, TIER_COLUMNS
from softcath.studies.sweep.variants import VariantBuilder

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["evaluate_task", "fem_check_function", "fem_records", "FEM_UNAVAILABLE"]

log = logging.getLogger(__name__)

#: The reason of a design whose tier this build cannot run (the 3-D FEM without its dependencies).
UNAVAILABLE = "{} evaluator unavailable"
FEM_UNAVAILABLE = UNAVAILABLE.format(models.get("fem").name)
#: The tier every sweep runs: its columns are the base of every comparison and best estimate.
ALWAYS = models.get("paper").name


_BUILDERS: dict[str, Any] = {}


def _builder(base_table: dict):
    """One :class:`VariantBuilder` per base design and process (tasks of a sweep share it)."""
    key = json.dumps(base_table, sort_keys=True, default=str)
    if key not in _BUILDERS:
        _BUILDERS.clear()
        _BUILDERS[key] = VariantBuilder(base_table)
    return _BUILDERS[key]


_MALLOC_TUNED = False


def restore_malloc_thresholds() -> bool:
    """Undo a fixed glibc trim threshold in this process (Dask's nanny sets one); True if it acted.

    Dask's nanny starts workers with ``MALLOC_TRIM_THRESHOLD_=65536``. Setting any
    malloc threshold turns off glibc's dynamic mmap threshold, so every array
    above 128 kB is a fresh mmap and page-faults in: measured here, one FEM
    design costs 8.2 CPU-s in such a process against 6.2 CPU-s without it
    (the main reason Dask workers scaled worse than the local pool). This sets
    the thresholds to the values the dynamic rule would reach (mmap 32 MB,
    trim 128 MB), which measured 5.9 CPU-s; memory above that is still
    returned to the system.
    """
    global _MALLOC_TUNED
    import os
    import sys

    if _MALLOC_TUNED or "MALLOC_TRIM_THRESHOLD_" not in os.environ or not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        libc = ctypes.CDLL("libc.so.6")
    except OSError:  # not glibc (e.g. musl): nothing to undo
        return False
    m_trim_threshold, m_mmap_threshold = -1, -3  # <malloc.h>
    libc.mallopt(m_mmap_threshold, 32 * 1024 * 1024)
    libc.mallopt(m_trim_threshold, 128 * 1024 * 1024)
    _MALLOC_TUNED = True
    return True


def evaluate_task(task: dict) -> pd.DataFrame:
    """Rows of one task (see module docstring).

    Parameters
    ----------
    task
        ``task_id``, ``design_ids``, ``variants`` (dotted path → value per design),
        ``param_paths``, ``base_table``, ``pressures_MPa``, ``loads``, ``evaluators``,
        ``mesh_size`` (the 3-D FEM's), ``max_strain`` and ``section`` (the ``[sweep.section]``
        options; each tier takes those it has, :meth:`~softcath.models.Tier.own_options`) and
        ``options`` (tier name -> its options, over the ``section`` table's).
    """
    import pandas as pd

    restore_malloc_thresholds()
    t0, c0 = time.perf_counter(), time.process_time()
    pressures = np.asarray(task["pressures_MPa"], dtype=float)
    loads = tuple(task["loads"])
    ids = list(task["design_ids"])
    # set by the runner when a task crashed: rows without evaluation
    designs, reasons = _build_designs(task, ids, task.get("fail_reason"))
    ok = [i for i, d in enumerate(designs) if d is not None]
    n_d = len(ids)

    tier_reason = [""] * n_d
    blocks, analytic_seconds = [], 0.0
    for name in TIER_COLUMNS:
        enabled = name in (ALWAYS, *task["evaluators"])
        blocks.append(
            _tier_blocks(models.get(name), designs, ok, task=task, enabled=enabled, tier_reason=tier_reason)
        )
        if len(blocks) == 1:  # the paper's formula, first in TIER_COLUMNS
            analytic_seconds = (time.perf_counter() - t0) / max(n_d, 1)

    cpu_seconds = (time.process_time() - c0) / max(n_d, 1)  # this worker's CPU per design, FEM included
    failures = [reasons[i] or tier_reason[i] for i in range(n_d)]
    per_load = [
        _load_columns(
            task,
            load,
            designs,
            pressures,
            blocks,
            failures,
            analytic_seconds=analytic_seconds,
            cpu_seconds=cpu_seconds,
        )
        for load in loads
    ]
    # Derived columns (degrees, differences, feasibility) are added once, on the merged table.
    return pd.DataFrame(_sorted_columns(per_load))


def _sorted_columns(per_load: list[dict[str, Any]]) -> dict[str, Any]:
    """The loads' columns stacked, FEM columns renamed, rows ordered by design, load and pressure.

    One frame built from numpy columns costs a fraction of a frame per load, concatenated,
    renamed and sorted by pandas; ``np.lexsort`` is stable like the ``kind="stable"`` sort
    it replaces, so the rows come in the same order.
    """
    n = len(per_load[0]["design_id"])
    stacked = {
        _FEM_RENAME.get(k, k): np.concatenate([_column(c[k], n) for c in per_load]) for k in per_load[0]
    }
    order = np.lexsort((stacked["pressure_MPa"], stacked["load"], stacked["design_id"]))
    return {k: v[order] for k, v in stacked.items()}


def _column(value: Any, n: int) -> np.ndarray:
    """``value`` as a column of ``n`` rows (a scalar is repeated, as the DataFrame constructor does)."""
    if np.ndim(value) == 0:
        return np.full(n, value)
    return np.asarray(value)


def _build_designs(task: dict, ids: list, forced: str | None) -> tuple[list, list[str]]:
    """Build each variant of ``task``: the designs (``None`` if invalid or forced) and the failure reasons."""
    builder = _builder(task["base_table"])
    designs, reasons = [], []
    for did, variant in zip(ids, task["variants"], strict=True):
        if forced:
            designs.append(None)
            reasons.append(forced)
            continue
        try:
            designs.append(builder.build(variant, name=f"design {did}"))
            reasons.append("")
        except DesignError as exc:
            designs.append(None)
            reasons.append(f"invalid design: {exc}")
    return designs, reasons


#: Tier -> how a task holds its options; every other tier takes its own of the ``[sweep.section]`` table.
_TASK_OPTIONS = {"fem": lambda task: {"mesh_size": task.get("mesh_size")}}  # the spec's mesh_size


def _tier_options(tier, task: dict) -> dict:
    """The task's options ``tier`` takes (:meth:`~softcath.models.Tier.own_options`), its own over them."""
    shared = _TASK_OPTIONS.get(tier.name, lambda t: t.get("section") or {})(task)
    return {**tier.own_options(shared), **models.options_of(task.get("options"), tier)}


def _tier_blocks(
    tier, designs: list, ok: list[int], *, task: dict, enabled: bool, tier_reason: list[str]
) -> dict:
    """``{load: {column: (n_designs, n_pressures) block}}`` of one tier (NaN where it did not run).

    A design the tier fails on gets the failure appended to ``tier_reason`` (never ends the sweep).
    """
    pressures = np.asarray(task["pressures_MPa"], dtype=float)
    loads, ids = tuple(task["loads"]), list(task["design_ids"])
    n_d, n_p = len(designs), len(pressures)
    columns = TIER_COLUMNS[tier.name]
    cols = {load: {c: np.full((n_d, n_p), np.nan) for c in columns} for load in loads}
    if not enabled or not ok:
        return cols
    if not tier.available():
        for i in ok:
            tier_reason[i] = UNAVAILABLE.format(tier.name)
        return cols
    batches = tier.responses(
        [designs[i] for i in ok], pressures, loads=loads, options=_tier_options(tier, task)
    )
    for load, batch in batches.items():
        for c, source in columns.items():
            cols[load][c][ok] = _source(batch, source, n_p)
    _note_failures(tier, batches, ok, ids, tier_reason)
    return cols


def _source(batch, source: str, n_p: int) -> np.ndarray:
    """The (designs, pressures) values of ``source`` (a field, ``extras.<name>`` or ``seconds``)."""
    if source == "seconds":
        return np.repeat(np.asarray(batch.seconds, float)[:, None], n_p, axis=1)
    if source.startswith("extras."):
        return batch.extras[source.removeprefix("extras.")]
    return getattr(batch, source)


def _note_failures(tier, batches: dict, ok: list[int], ids: list, tier_reason: list[str]) -> None:
    """Log each design's failure of ``tier`` and append it to that design's reason (once per failure)."""
    per_design: dict[int, list] = {}
    for load, batch in batches.items():
        for j, exc in batch.errors.items():
            per_design.setdefault(j, [])
            if all(exc is not e for _l, e in per_design[j]):
                per_design[j].append((load, exc))
    for j, fails in sorted(per_design.items()):
        i = ok[j]
        for load, exc in fails:
            where = f" ({load})" if len(fails) > 1 or _per_load(batches, j) else ""
            log.warning("%s failed for design %s%s: %s", tier.name, ids[i], where, exc)
            why = f"{tier.name} failed{where}: {type(exc).__name__}: {exc}"
            tier_reason[i] = f"{tier_reason[i]}; {why}" if tier_reason[i] else why


def _per_load(batches: dict, j: int) -> bool:
    """Whether design ``j`` failed under some loads only (then its reason names the load)."""
    return any(j not in b.errors for b in batches.values())


def _load_columns(
    task: dict,
    load: str,
    designs: list,
    pressures: np.ndarray,
    blocks: list[dict],
    failures: list[str],
    *,
    analytic_seconds: float,
    cpu_seconds: float,
) -> dict[str, Any]:
    """Columns of one load's rows: identity, design parameters, every evaluator's block, status and timing."""
    ids = list(task["design_ids"])
    n_d, n_p = len(ids), len(pressures)
    cols: dict[str, Any] = {
        "design_id": np.repeat(ids, n_p),
        "task_id": task["task_id"],
    }
    for path in task["param_paths"]:
        cols[path] = np.repeat(np.array([v.get(path) for v in task["variants"]], dtype=object), n_p)
    cols["outer_diameter_mm"] = np.repeat([d.outer_diameter if d else np.nan for d in designs], n_p)
    cols["bending_length_mm"] = np.repeat([d.tip.bending_length if d else np.nan for d in designs], n_p)
    cols["catalogue_fits"] = np.repeat([bool(d.catalogue_fits) if d else False for d in designs], n_p)
    cols["pressure_MPa"] = np.tile(pressures, n_d)
    cols["load"] = load
    for block in blocks:
        for k, v in block[load].items():
            cols[k] = v.ravel()
    status, reason = [], []
    for r in failures:
        status += ["failed" if r else "ok"] * n_p
        reason += [r] * n_p
    cols["status"] = status
    cols["reason"] = reason
    cols["analytic_seconds"] = analytic_seconds
    cols["cpu_seconds"] = cpu_seconds
    return cols
