"""The missing-effect workflow: find, name and add what the model is missing.

>>> from softcath.studies.discrepancy import run_workflow, write_report
>>> result = run_workflow("bench.csv", "paper")          # doctest: +SKIP
>>> result.named, result.nrmse_before, result.nrmse_after  # doctest: +SKIP
>>> write_report(result, "out/discrepancy")               # doctest: +SKIP

See :mod:`softcath.studies.discrepancy.naming` for the method and
``docs/effects.md`` for what a user gets.
"""

from __future__ import annotations

from softcath.studies.discrepancy.report import write_report as _write
from softcath.studies.discrepancy.workflow import DiscrepancyResult, run_workflow


def write_report(result: DiscrepancyResult, out_dir):
    """Write ``discrepancy.json``, ``report.html`` and its PNG figures into ``out_dir``."""

    return _write(result, out_dir)


__all__ = ["DiscrepancyResult", "run_workflow", "write_report"]
