"""Design sweeps: specification, sampling, evaluation, runners and the resumable result store.

Modules: ``spec``, ``sampling`` and ``variants`` (the designs), ``evaluators`` (one
task), ``runner`` (local processes), ``dask_scale_out`` (the Dask path), ``store``
(one file per finished task) and ``results`` (the merged results table).

>>> from softcath.studies.sweep import load_spec, run_sweep          # doctest: +SKIP
>>> summary = run_sweep(load_spec("examples/sweeps/quick_analytic.toml"), "out/quick")  # doctest: +SKIP
"""

from __future__ import annotations

from softcath.studies.sweep.evaluators import FEM_UNAVAILABLE, evaluate_task, fem_check_function
from softcath.studies.sweep.runner import SweepSummary, build_tasks, run_sweep
from softcath.studies.sweep.sampling import expand, latin_hypercube
from softcath.studies.sweep.spec import Parameter, SweepSpec, load_spec, parse_spec
from softcath.studies.sweep.store import SweepStore
from softcath.studies.sweep.variants import build_variant, variant_table

__all__ = [
    "FEM_UNAVAILABLE",
    "Parameter",
    "SweepSpec",
    "SweepStore",
    "SweepSummary",
    "build_tasks",
    "build_variant",
    "evaluate_task",
    "expand",
    "fem_check_function",
    "latin_hypercube",
    "load_spec",
    "parse_spec",
    "run_sweep",
    "variant_table",
]
