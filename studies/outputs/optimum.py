"""An optimisation run and its folder: ``optimum.json``, ``history.parquet``, designs and report.

:func:`optimum_run` is what ``softcath optimise`` does once its problem is made:
estimate where the problem's tier stands against its validity (a warning before the
search), search (:func:`softcath.studies.optimise.optimise`) and write the record,
history, winners' design files and the report ``index.html``. The record, designs and
report replace an earlier run's only together; an earlier run's designs that this one
did not write are removed.
"""

from __future__ import annotations

import dataclasses
import logging
from dataclasses import dataclass
from pathlib import Path

from softcath.core.atomic import prepare_out_dir, staged_dir, unstage
from softcath.core.output_ledger import check_inputs_outside, check_replace
from softcath.studies import optimise as search  # through the module: a test may replace its functions
from softcath.studies.optimise import Optimum, Problem, Robustness
from softcath.studies.optimise.validity import tier_validity
from softcath.studies.report import optimum as optimum_report

__all__ = ["OptimumRun", "optimum_run"]

#: The files an optimisation folder's earlier run may have written and this one replaces.
_REPLACED = ("optimum.json", "history.parquet", "index.html")


@dataclass(frozen=True)
class OptimumRun:
    """A finished search and where its files went.

    Attributes
    ----------
    optimum
        The search's result, its tier's ``validity`` included.
    paths
        :func:`~softcath.studies.optimise.write_optimum`'s files (``optimum``, ``history``,
        designs) in the folder.
    report
        The report page.
    """

    optimum: Optimum
    paths: dict[str, Path]
    report: Path


def optimum_run(
    problem: Problem,
    folder: str | Path,
    *,
    budget: int = 200,
    seed: int = 0,
    robust: Robustness | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    fem_check: bool = False,
    progress: bool = True,
) -> OptimumRun:
    """Search ``problem`` and write its record, history, designs and report into ``folder``.

    The keywords are :func:`softcath.studies.optimise.optimise`'s. ``folder`` is made if missing.

    Raises
    ------
    DesignError
        An input lives in ``folder/designs`` (refilled by the run), or a file the run would
        replace was not written by softcath.
    """
    validity = tier_validity(problem)
    if validity.get("warning"):  # said before the search: the user may stop it and change the model
        logging.getLogger("softcath.validity").warning(validity["warning"])
    out = prepare_out_dir(folder, param="folder")
    check_inputs_outside(out, "designs")  # the designs folder is refilled: no input may live there
    check_replace(out, [out / n for n in _REPLACED])
    opt = search.optimise(
        problem,
        budget=budget,
        seed=seed,
        robust=robust,
        workers=workers,
        scheduler=scheduler,
        fem_check=fem_check,
        progress=progress,
    )
    opt = dataclasses.replace(opt, validity=validity)
    with staged_dir(out, owner="optimise") as stage:
        paths = {k: unstage(v, stage, out) for k, v in search.write_optimum(opt, problem, stage).items()}
        report = unstage(optimum_report.write_optimum_report(stage), stage, out)
    return OptimumRun(optimum=opt, paths=paths, report=report)
