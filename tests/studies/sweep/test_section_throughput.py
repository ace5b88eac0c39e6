"""The batched section evaluator in a sweep: the same table from local processes and a Dask cluster."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from softcath.studies.sweep import load_spec, run_sweep
from softcath.studies.sweep.random_designs import DEFAULT_RANGES

#: Columns that depend on the run (timings), not on the designs.
_TIMINGS = ["section_seconds", "analytic_seconds", "cpu_seconds"]


def _spec(tmp_path, n: int):
    params = "\n".join(f'"{path}" = {{ lhs = [{lo}, {hi}] }}' for path, (lo, hi) in DEFAULT_RANGES.items())
    text = f"""[sweep]
name = "throughput"
base = "paper"
pressures_MPa = [0.0, 0.5, 1.0]
loads = ["cap", "lumen"]
evaluators = ["analytic", "section"]
seed = 3
chunk_size = 20
[sample]
n = {n}
[parameters]
{params}
"""
    path = tmp_path / "spec.toml"
    path.write_text(text, encoding="utf-8")
    return load_spec(path)


def _values(df: pd.DataFrame) -> pd.DataFrame:
    df = df.assign(reason=df["reason"].fillna(""))
    keep = [c for c in df.columns if c not in _TIMINGS]
    return df[keep].sort_values(["design_id", "load", "pressure_MPa"], ignore_index=True)


@pytest.mark.slow
def test_dask_local_cluster_equals_local_processes_for_batched_section_models(tmp_path):
    pytest.importorskip("distributed")
    spec = _spec(tmp_path, 60)
    pool = run_sweep(spec, tmp_path / "pool", workers=2, progress=False)
    dask = run_sweep(spec, tmp_path / "dask", dask_local=2, progress=False)
    assert dask.backend == "dask-local(2)" and pool.evaluated_tasks == dask.evaluated_tasks == 3
    a, b = _values(pd.read_parquet(pool.results_parquet)), _values(pd.read_parquet(dask.results_parquet))
    assert (a.status == "ok").all()
    assert np.isfinite(a.curvature_section_per_mm).all()
    pd.testing.assert_frame_equal(a, b, check_exact=True)
