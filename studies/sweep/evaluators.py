"""Evaluate one task of a sweep: validate each design, run the analytic model (vectorised), section model and
FEM.

A task is a plain dict (picklable, so the same function runs in a local
process pool or on Dask workers) and its result a :class:`pandas.DataFrame`
with one row per design × pressure × load (columns in :mod:`softcath.studies.sweep.results`).
A design that cannot be built is reported with status ``failed`` and the
:class:`~design.errors.DesignError` reason; it never stops the task.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from softcath.design.errors import DesignError
from softcath.interrupts import raise_pending_stop
from softcath.studies.sweep.results import _FEM_RENAME, SECTION_NONLINEAR_COLUMNS
from softcath.studies.sweep.section_eval import SECTION_KEYS, section_blocks_many
from softcath.studies.sweep.section_nonlinear_eval import section_nonlinear_columns

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["evaluate_task", "fem_check_function", "fem_records", "FEM_UNAVAILABLE"]

log = logging.getLogger(__name__)

FEM_UNAVAILABLE = "fem evaluator unavailable"
_FEM_KEYS = (
    "curvature_per_mm",
    "elongation",
    "bend_angle_rad",
    "tip_x_mm",
    "tip_y_mm",
    "curvature_variation",
    "max_strain",
    "residual",
    "n_elements",
    "dofs",
    "mesh_seconds",
    "solve_seconds",
)


def fem_check_function():
    """``fem.check`` if the FEM package provides it, else ``None``."""
    try:
        from softcath.fem import check
    except ImportError:
        return None
    return check


_BUILDERS: dict[str, Any] = {}


def _builder(base_table: dict):
    """One :class:`VariantBuilder` per base design and process (tasks of a sweep share it)."""
    import json

    from softcath.studies.sweep.variants import VariantBuilder

    key = json.dumps(base_table, sort_keys=True, default=str)
    if key not in _BUILDERS:
        _BUILDERS.clear()
        _BUILDERS[key] = VariantBuilder(base_table)
    return _BUILDERS[key]


def _analytic(
    designs: list, pressures: np.ndarray, loads: tuple[str, ...]
) -> dict[str, dict[str, np.ndarray]]:
    """Analytic response of many designs per load: ``{load: {column: array (n_designs, n_pressures)}}``.

    The design inputs and the section are computed once for all loads (they do not depend on the load).
    """
    from softcath import analytic
    from softcath.analytic.section import section_arrays

    inp = {k: v[:, None] for k, v in analytic.design_inputs_many(designs).items()}
    s = section_arrays(inp)
    # Axial strain of the composite beam, ε + κ (y − ȳ), at the tube's top and bottom fibres:
    # the largest silicone strain of the Euler–Bernoulli section.
    y_top = s["tube_centre_y"] + s["b"] - s["neutral_axis_y"]
    y_bot = s["tube_centre_y"] - s["b"] - s["neutral_axis_y"]
    out = {}
    for load in loads:
        r = analytic.response_arrays(inp, pressures[None, :], load)
        strain = np.maximum(
            np.abs(r.elongation + r.curvature * y_top), np.abs(r.elongation + r.curvature * y_bot)
        )
        out[load] = {
            "curvature_analytic_per_mm": r.curvature,
            "elongation_analytic": r.elongation,
            "bend_angle_analytic_rad": r.bend_angle,
            "tip_x_analytic_mm": r.tip_x,
            "tip_y_analytic_mm": r.tip_y,
            "max_strain_analytic": strain,
        }
    return out


def _fem_rows(check, design, pressures: tuple[float, ...], loads: tuple[str, ...], mesh_size) -> dict:
    """``{(load, pressure): {key: value}}`` from ``fem.check`` (see :func:`fem_records`)."""
    kwargs: dict[str, Any] = {"pressures": list(pressures), "loads": tuple(loads)}
    if mesh_size is not None:
        kwargs["mesh_size"] = mesh_size
    return fem_records(check(design, **kwargs))


_CONTAINERS = ("cases", "results", "rows", "records")
_ANALYTIC_KEYS = (
    "curvature_analytic_per_mm",
    "elongation_analytic",
    "bend_angle_analytic_rad",
    "tip_x_analytic_mm",
    "tip_y_analytic_mm",
    "max_strain_analytic",
)


def _as_mapping(obj: Any) -> dict | None:
    if isinstance(obj, dict):
        return obj
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}
    return None


def fem_records(result: Any, load: str | None = None, defaults: dict | None = None) -> dict:
    """Normalise what ``fem.check`` returns to ``{(load, pressure_MPa): {fem.json key: float}}``.

    Accepted forms (the FEM package's result keys follow ``fem.json``): one
    record whose fields are scalars or arrays over the (load, pressure) cases
    — flat, or shaped (n_loads, n_pressures) with ``load`` and
    ``pressure_MPa`` listing the axes; a sequence of such records; a record
    holding them under ``cases``/``results``/``rows``/``records`` (its own
    run-level numbers, e.g. ``dofs``, ``mesh_seconds``, apply to every case);
    or a mapping from load name to records.
    """
    out: dict = {}
    defaults = dict(defaults or {})
    if isinstance(result, (list, tuple)):
        for r in result:
            out.update(fem_records(r, load, defaults))
        return out
    m = _as_mapping(result)
    if m is None:
        raise TypeError(f"cannot read a FEM result of type {type(result).__name__}")
    run_level = {
        k: m[k] for k in _FEM_KEYS if isinstance(m.get(k), (int, float)) and not isinstance(m[k], bool)
    }
    for key in _CONTAINERS:
        if isinstance(m.get(key), (list, tuple)) and "curvature_per_mm" not in m:
            return fem_records(m[key], load, {**defaults, **run_level})
    if "curvature_per_mm" not in m:
        for k, v in m.items():
            if k in ("cap", "lumen"):
                out.update(fem_records(v, k, {**defaults, **run_level}))
        if not out:
            raise KeyError("FEM result has no curvature_per_mm")
        return out
    loads_ = np.atleast_1d(np.asarray(m.get("load", load), dtype=object)).ravel()
    ps = np.atleast_1d(np.asarray(m["pressure_MPa"], dtype=float)).ravel()
    kappa = np.asarray(m["curvature_per_mm"], dtype=float)
    square = kappa.ndim == 2 and kappa.shape == (len(loads_), len(ps))
    product = len(loads_) != len(ps) and kappa.size == len(loads_) * len(ps) > max(len(loads_), len(ps))
    if square or product:
        loads_, ps = np.repeat(loads_, len(ps)), np.tile(ps, len(loads_))  # (n_loads, n_pressures) grid
    n = max(len(loads_), len(ps))
    loads_ = np.resize(loads_, n)
    ps = np.resize(ps, n)
    for i in range(n):
        row = {}
        for k in _FEM_KEYS:
            v = m.get(k, defaults.get(k))
            if v is None or isinstance(v, (dict, str)):
                row[k] = math.nan
                continue
            a = np.atleast_1d(np.asarray(v, dtype=float)).ravel()
            row[k] = float(a[i] if a.size == n else a[0])
        out[(str(loads_[i]), round(float(ps[i]), 12))] = row
    return out


_NONLINEAR_KEYS = {
    "nonlinear_bend_angle_rad": "bend_angle",
    "nonlinear_curvature_per_mm": "curvature",
    "nonlinear_max_strain": "max_strain",
}


def _nonlinear_columns(design, pressures: np.ndarray, load: str) -> dict[str, np.ndarray]:
    """Finite-strain bend angle [rad], curvature [1/mm] and max silicone strain at ``pressures`` (0 MPa:
    0)."""
    from softcath.fem.nonlinear import bend_curve

    positive = np.unique(pressures[pressures > 0])
    out = {k: np.zeros(pressures.size) for k in _NONLINEAR_KEYS}
    if positive.size:
        curve = bend_curve(design, positive, load=load)
        idx = np.searchsorted(positive, pressures)
        pos = pressures > 0
        for col, attr in _NONLINEAR_KEYS.items():
            out[col][pos] = np.asarray(getattr(curve, attr))[idx[pos]]
    for col in out:
        out[col][pressures < 0] = np.nan  # the finite-strain sweep loads upward only
    return out


def _nan_block(n_d: int, n_p: int) -> np.ndarray:
    return np.full((n_d, n_p), np.nan)


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
        ``mesh_size``, ``max_strain`` and, for the ``section`` evaluator, ``section``
        (options of :func:`softcath.fem.section_model.section_model`).
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

    blocks = [_analytic_blocks(designs, ok, pressures, loads)]
    analytic_seconds = (time.perf_counter() - t0) / max(n_d, 1)

    fem_reason = [""] * n_d
    evaluators = task["evaluators"]
    blocks.append(
        _fem_blocks(
            designs, ok, ids, pressures, loads, task.get("mesh_size"), "fem" in evaluators, fem_reason
        )
    )
    blocks.append(
        _nonlinear_blocks(designs, ok, ids, pressures, loads, "fem-nonlinear" in evaluators, fem_reason)
    )
    blocks.append(
        _section_blocks(
            designs, ok, ids, pressures, loads, task.get("section"), "section" in evaluators, fem_reason
        )
    )
    blocks.append(
        _section_nonlinear_blocks(
            designs,
            ok,
            ids,
            pressures,
            loads,
            task.get("section"),
            "section-nonlinear" in evaluators,
            fem_reason,
        )
    )

    cpu_seconds = (time.process_time() - c0) / max(n_d, 1)  # this worker's CPU per design, FEM included
    failures = [reasons[i] or fem_reason[i] for i in range(n_d)]
    per_load = [
        _load_columns(task, load, designs, pressures, blocks, failures, analytic_seconds, cpu_seconds)
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


def _analytic_blocks(designs: list, ok: list[int], pressures: np.ndarray, loads: tuple[str, ...]) -> dict:
    """Analytic columns per load, a design × pressure block each (NaN for invalid designs)."""
    n_d, n_p = len(designs), len(pressures)
    per_load = {load: {k: _nan_block(n_d, n_p) for k in _ANALYTIC_KEYS} for load in loads}
    if ok:
        for load, vals in _analytic([designs[i] for i in ok], pressures, loads).items():
            for k, v in vals.items():
                per_load[load][k][ok] = v
    return per_load


def _fem_blocks(designs, ok, ids, pressures, loads, mesh_size, enabled: bool, fem_reason: list[str]) -> dict:
    """FEM columns per load; a design's failure is written to ``fem_reason`` (never ends the sweep)."""
    n_d, n_p = len(designs), len(pressures)
    fem_cols = {load: {f"fem_{k}": _nan_block(n_d, n_p) for k in _FEM_KEYS} for load in loads}
    if not enabled:
        return fem_cols
    check = fem_check_function()
    for i in ok:
        if check is None:
            fem_reason[i] = FEM_UNAVAILABLE
            continue
        try:
            rows = _fem_rows(check, designs[i], tuple(pressures), loads, mesh_size)
        except Exception as exc:  # a FEM failure is reported per design, never ends the sweep
            raise_pending_stop()
            log.warning("FEM failed for design %s: %s", ids[i], exc)
            fem_reason[i] = f"fem failed: {type(exc).__name__}: {exc}"
            continue
        for load in loads:
            for j, p in enumerate(pressures):
                row = rows.get((load, round(float(p), 12)))
                if row is None:
                    fem_reason[i] = f"fem returned no result for load {load} at {p:g} MPa"
                    continue
                for k in _FEM_KEYS:
                    fem_cols[load][f"fem_{k}"][i, j] = row[k]
    return fem_cols


def _nonlinear_blocks(designs, ok, ids, pressures, loads, enabled: bool, fem_reason: list[str]) -> dict:
    """Nonlinear-FEM columns per load; a failed Newton solve is written to ``fem_reason``."""
    n_d, n_p = len(designs), len(pressures)
    nl_cols = {load: {k: _nan_block(n_d, n_p) for k in _NONLINEAR_KEYS} for load in loads}
    if not enabled:
        return nl_cols
    for i in ok:
        for load in loads:
            try:
                values = _nonlinear_columns(designs[i], pressures, load)
            except Exception as exc:  # a failed Newton solve is reported per design, never ends the sweep
                raise_pending_stop()
                log.warning("nonlinear FEM failed for design %s: %s", ids[i], exc)
                fem_reason[i] = f"nonlinear failed ({load}): {type(exc).__name__}: {exc}"
                continue
            for col, v in values.items():
                nl_cols[load][col][i] = v
    return nl_cols


def _section_blocks(
    designs, ok, ids, pressures, loads, options, enabled: bool, fem_reason: list[str]
) -> dict:
    """Section-model columns per load; a design's failure is appended to ``fem_reason``."""
    n_d, n_p = len(designs), len(pressures)
    sec_cols = {load: {k: _nan_block(n_d, n_p) for k in SECTION_KEYS} for load in loads}
    if not enabled:
        return sec_cols
    many, errors = section_blocks_many([designs[i] for i in ok], pressures, loads, options)
    for j, exc in errors.items():  # a section-model failure is reported per design
        _note_failure(fem_reason, ok[j], "section", exc, ids[ok[j]])
    for load, block in many.items():
        for k, v in block.items():
            sec_cols[load][k][ok] = v
    return sec_cols


def _section_nonlinear_blocks(
    designs, ok, ids, pressures, loads, options, enabled: bool, fem_reason: list[str]
) -> dict:
    """Finite-strain section-model columns per load; a stalled Newton walk is appended to ``fem_reason``."""
    n_d, n_p = len(designs), len(pressures)
    sn_cols = {load: {k: _nan_block(n_d, n_p) for k in SECTION_NONLINEAR_COLUMNS} for load in loads}
    if not enabled:
        return sn_cols
    for i in ok:
        try:
            values = section_nonlinear_columns(designs[i], pressures, loads, options)
        except Exception as exc:  # a stalled Newton walk is reported per design, never ends the sweep
            raise_pending_stop()
            _note_failure(fem_reason, i, "section-nonlinear", exc, ids[i])
            continue
        _fill(sn_cols, i, values)
    return sn_cols


def _note_failure(fem_reason: list[str], i: int, tier: str, exc: Exception, design_id) -> None:
    """Log a tier's failure on design ``i`` and append it to that design's reason."""
    log.warning("%s failed for design %s: %s", tier, design_id, exc)
    why = f"{tier} failed: {type(exc).__name__}: {exc}"
    fem_reason[i] = f"{fem_reason[i]}; {why}" if fem_reason[i] else why


def _fill(cols: dict, i: int, values: dict) -> None:
    """Copy design ``i``'s per-load column values into the sweep's column blocks."""
    for load, block in cols.items():
        for col, v in values[load].items():
            block[col][i] = v


def _load_columns(
    task: dict,
    load: str,
    designs: list,
    pressures: np.ndarray,
    blocks: list[dict],
    failures: list[str],
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
