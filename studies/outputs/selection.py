"""A sweep's designs ranked and written: ``selection.json`` and the chosen design files.

:func:`selection_run` is what ``softcath select`` does after parsing: rank a sweep's
results (:func:`softcath.studies.selection.select`), warn where a linear tier ranked
designs bending past its validity, re-check large-bend constraints on the
finite-strain section model, optionally re-evaluate the ranking under parameter
uncertainty (:class:`RobustSettings`), and write ``selection.json`` with the first
ranked designs as design files. The sweep's manifest (``sweep.json``) gives the
base design and pressures the re-check and the robust ranking need.
"""

from __future__ import annotations

import dataclasses
import json
import logging
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from softcath.core.atomic import prepare_out_dir
from softcath.design.errors import DataError, DesignError
from softcath.studies.selection import (
    Selection,
    large_bend_constraints,
    recheck_large_bends,
    robust_select,
    select,
    sweep_ranges,
    write_selection,
)
from softcath.studies.selection.designs import DEFAULT_DESIGN_FILES, chosen_design_files
from softcath.studies.selection.large_bends import LINEAR_MODELS, linear_validity_warning
from softcath.studies.sweep.results import model_columns, read_results

__all__ = ["RobustSettings", "SelectionRun", "selection_run"]

_log = logging.getLogger("softcath.validity")
#: The robust ranking's parameter names -> :class:`RobustSettings`' (``workers`` is the run's).
_ROBUST_NAMES = {
    "robust": "robust.probability",
    "samples": "robust.samples",
    "seed": "robust.seed",
    "ranges": "robust.ranges",
    "model": "robust.model",
    "vary": "robust.vary",
    "workers": "workers",
}


@dataclass(frozen=True)
class RobustSettings:
    """The robust ranking's settings (see :func:`softcath.studies.selection.robust_select`).

    Attributes
    ----------
    probability
        The probability every constraint must hold with.
    vary, ranges
        The uncertain parameters: ``--vary``-style items and a ranges file (default: the
        design's traced ranges).
    samples, seed
        Latin-hypercube sample size and seed.
    model
        The tier the variants run on.
    options
        Tier name -> its options (:attr:`softcath.models.Tier.options`) for the variants' runs.
    progress
        Report progress.
    """

    probability: float
    vary: Sequence[str] = ()
    ranges: str | Path | None = None
    samples: int = 64
    seed: int = 0
    model: str = "section"
    progress: bool = False
    options: Mapping[str, Mapping[str, Any]] = dataclasses.field(default_factory=dict)


@dataclass(frozen=True)
class SelectionRun:
    """A written selection: the ranking and where ``selection.json`` went."""

    selection: Selection
    path: Path
    out: Path


def selection_run(
    sweep_dir: str | Path,
    *,
    constraints: Sequence[str] = (),
    objectives: Sequence[str] = (),
    load: str | None = None,
    top: int | None = None,
    model: str | None = None,
    recheck: bool = True,
    robust: RobustSettings | None = None,
    designs: int = DEFAULT_DESIGN_FILES,
    workers: int | None = None,
    out: str | Path | None = None,
) -> SelectionRun:
    """Rank the designs of the sweep in ``sweep_dir`` and write ``selection.json``.

    Parameters
    ----------
    sweep_dir
        The sweep's folder (results table and ``sweep.json``).
    constraints, objectives, load, top, model
        As :func:`softcath.studies.selection.select` takes them.
    recheck
        Re-check a bend constraint beyond a linear tier's validity on the finite-strain
        section model (the linear ranking otherwise).
    robust
        Re-evaluate the ranking under parameter uncertainty, or None.
    designs
        How many ranked designs to write as design files.
    workers
        Processes for the re-check and the robust ranking (default 1).
    out
        Where ``selection.json`` goes (default: ``sweep_dir``, where the report finds it).

    Raises
    ------
    DataError
        ``sweep_dir`` is not a sweep folder, or its manifest cannot be read where needed.
    DesignError
        A robust setting out of its bounds, named ``robust.FIELD`` (``robust.vary PATH`` for
        one range) after :class:`RobustSettings`.
    """
    if not Path(sweep_dir).is_dir():
        raise DataError(f"{sweep_dir}: not a sweep directory (run `softcath sweep SPEC --out DIR` first)")
    df = read_results(sweep_dir)
    sel = select(df, constraints=constraints, objectives=objectives, load=load, top=top, model=model)
    folder = Path(sweep_dir) if out is None else prepare_out_dir(out)
    sel = _validity(sel, df, recheck=recheck)
    if recheck:
        sel = _recheck(sel, df, sweep_dir, workers=workers)
    if robust is not None:
        sel = _robust(sel, sweep_dir, robust, workers=workers)
    sel, files = chosen_design_files(sel, sweep_dir, count=designs)
    path = write_selection(sel, folder, designs=files)
    return SelectionRun(selection=sel, path=path, out=folder)


def _manifest(sweep_dir: str | Path, why: str) -> tuple[dict, dict]:
    """(spec, base_table) from the sweep's manifest."""
    manifest = Path(sweep_dir) / "sweep.json"
    try:
        doc = json.loads(manifest.read_text(encoding="utf-8"))
        return doc["spec"], doc["base_table"]
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise DataError(f"{manifest}: cannot read the sweep's manifest ({exc}); {why} needs it") from None


def _validity(sel: Selection, df, *, recheck: bool) -> Selection:
    """Warn (and record in the selection) when a linear tier ranked designs bending past its validity."""
    if sel.model not in LINEAR_MODELS:
        return sel
    cols = model_columns(df, sel.model)
    rechecked = recheck and bool(large_bend_constraints(sel, cols))
    msg = linear_validity_warning(sel, cols, rechecked=rechecked)
    if not msg:
        return sel
    _log.warning(msg)
    return dataclasses.replace(sel, warnings=(*sel.warnings, msg))


def _recheck(sel: Selection, df, sweep_dir, *, workers: int | None) -> Selection:
    """Re-check with the finite-strain section model a bend constraint beyond a linear model's validity."""
    if sel.model not in LINEAR_MODELS:
        return sel
    big = large_bend_constraints(sel, model_columns(df, sel.model))
    if not big:
        return sel
    spec, base_table = _manifest(sweep_dir, "the large-bend re-check (or give --no-recheck)")
    return recheck_large_bends(
        sel, base_table=base_table, pressures=spec["pressures_MPa"], constraints=big, workers=workers
    )


def _robust(sel: Selection, sweep_dir, r: RobustSettings, *, workers: int | None) -> Selection:
    """The robust re-evaluation of the nominal ranking."""
    spec, base_table = _manifest(sweep_dir, "--robust")
    try:
        ranges = sweep_ranges(spec.get("base", ""), base_table, r.vary, r.ranges)
        return robust_select(
            sel,
            base_table=base_table,
            pressures=spec["pressures_MPa"],
            probability=r.probability,
            ranges=ranges,
            samples=r.samples,
            seed=r.seed,
            model=r.model,
            workers=workers,
            progress=r.progress,
            options=r.options,
        )
    except DesignError as exc:  # named after the settings, as the caller gave them
        head, _, rest = exc.parameter.partition(" ")
        name = _ROBUST_NAMES.get(head)
        if name is None or (rest and head != "vary"):
            raise
        raise DesignError(f"{name} {rest}".strip(), exc.value, exc.bound) from None
