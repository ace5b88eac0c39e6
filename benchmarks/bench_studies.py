"""Benchmarks of the design studies (run by `make bench`; prints times and ratios, asserts nothing).

1. Analytic-only sweep of 1e5 designs (target <= 10 s): our vectorised task path
   (validated variants + one analytic call per chunk) against the per-design
   baseline (design.from_dict + analytic.response for every design), on a
   sample, extrapolated; and the full sweep end to end (validation, evaluation,
   atomic task files, merged CSV + Parquet) with 2 local workers.
2. FEM sweep throughput in designs per minute: 1 worker (in this process), 2
   local workers, and 1- and 2-worker Dask LocalClusters, as ratios to 1 worker
   (target >= 1.8x on 2 cores), end to end and in the steady state after each
   worker's first design; plus Dask's own 2/1-worker ratio. Needs fem.check;
   without it the section says so.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

# One BLAS/MKL thread everywhere, so "1 worker" (in this process) uses one core like each pool or Dask
# worker does; set before numpy or the FEM solver is loaded.
for _var in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

N_BIG = int(os.environ.get("SOFTCATH_BENCH_DESIGNS", "100000"))


def _cpu() -> float:
    """CPU seconds of this process and its finished children (the worker processes)."""
    import resource

    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def _spec(tmp: Path, body: str):
    from softcath.studies.sweep import load_spec

    path = tmp / "spec.toml"
    path.write_text(body, encoding="utf-8")
    return load_spec(path)


def bench_analytic(tmp: Path) -> None:
    from softcath import analytic, design
    from softcath.studies.sweep import build_tasks, evaluate_task, expand, run_sweep
    from softcath.studies.sweep.variants import variant_table

    spec = _spec(
        tmp,
        f"""
[sweep]
name = "bench-analytic"
pressures_MPa = [1.0]
loads = ["cap", "lumen"]
chunk_size = 5000
seed = 1
[sample]
n = {N_BIG}
[parameters]
"tube.h" = {{ lhs = [-0.05, 0.05] }}
"tube.a_int" = {{ lhs = [0.06, 0.15] }}
"tip.bending_length" = {{ lhs = [3.0, 7.0] }}
"coil.outer_diameter" = {{ lhs = [0.75, 0.9] }}
""",
    )
    variants = expand(spec)
    sample = variants[:2000]
    # Baseline: the obvious per-design loop.
    t = time.perf_counter()
    for v in sample:
        try:
            d = design.from_dict(variant_table(spec.base_table, v))
        except design.DesignError:
            continue
        for load in spec.loads:
            analytic.response(d, np.array(spec.pressures), load)
    base = (time.perf_counter() - t) / len(sample)
    (task,) = build_tasks(spec.__class__(**{**spec.__dict__, "chunk_size": len(sample)}), sample)
    evaluate_task(task)  # warm imports
    t = time.perf_counter()
    evaluate_task(task)
    ours = (time.perf_counter() - t) / len(sample)
    print(
        f"per design: baseline loop {base * 1e6:.0f} us, our task path {ours * 1e6:.0f} us "
        f"-> {base / ours:.1f}x faster"
    )
    print(
        f"  extrapolated to {N_BIG} designs on 1 core: baseline {base * N_BIG:.1f} s, ours "
        f"{ours * N_BIG:.1f} s"
    )
    t = time.perf_counter()
    c0 = _cpu()
    s = run_sweep(spec, tmp / "big", workers=2, progress=False)
    wall = time.perf_counter() - t
    import pandas as pd

    # this process + the workers' CPU (pool workers are the fork server's children, not ours)
    per_design = pd.read_parquet(s.results_parquet, columns=["design_id", "cpu_seconds"])
    cpu = _cpu() - c0 + float(per_design.drop_duplicates("design_id").cpu_seconds.sum())
    load = os.getloadavg()[0]
    print(
        f"full sweep of {s.n_designs} designs x {len(spec.loads)} loads on {s.backend}: {wall:.1f} s wall "
        f"(target <= 10 s), {cpu:.1f} CPU-s in all processes (load average {load:.1f} on {os.cpu_count()} "
        f"cores: an idle machine needs about CPU-s / 2); {s.failed_designs} invalid designs reported; "
        f"results.csv {s.results_csv.stat().st_size / 1e6:.0f} MB"
    )


def bench_fem(tmp: Path) -> None:
    from softcath.studies.sweep import SweepStore, fem_check_function, load_spec, run_sweep
    from softcath.studies.sweep.results import read_results

    if fem_check_function() is None:
        print("FEM throughput: skipped (fem.check is not importable in this build)")
        return
    spec_path = tmp / "fem.toml"
    spec_path.write_text(
        """
[sweep]
name = "bench-fem"
pressures_MPa = [1.0]
loads = ["cap", "lumen"]
evaluators = ["analytic", "fem"]
[sweep.fem]
mesh_size = 0.12
[parameters]
"tube.h" = { values = [-0.03, -0.02, -0.01, 0.0, 0.01, 0.02, 0.03, 0.04] }
""",
        encoding="utf-8",
    )
    spec = load_spec(spec_path)
    # Warm the mesh cache and imports so the three runs time the same work.
    run_sweep(spec, tmp / "fem_warm", workers=1, progress=False)
    rates = {}
    for label, kw in (
        ("1 worker", {"workers": 1}),
        ("2 local workers", {"workers": 2}),
        ("Dask LocalCluster (1)", {"dask_local": 1}),
        ("Dask LocalCluster (2)", {"dask_local": 2}),
    ):
        t = time.perf_counter()
        s = run_sweep(spec, tmp / label.replace(" ", "_"), progress=False, **kw)
        wall = time.perf_counter() - t
        # Steady state: designs finished after each worker's first one, over the time they took
        # (start-up — process spawn, imports — is paid once per sweep and reported separately).
        w = kw.get("workers") or kw.get("dask_local")
        stamps = sorted(e["t"] for e in SweepStore(s.out_dir).events())
        steady = (len(stamps) - w) / ((stamps[-1] - stamps[w - 1]) / 60) if len(stamps) > w else float("nan")
        rates[label] = (s.ok_designs / (wall / 60), s.failed_designs, steady)
        df = read_results(s.out_dir)
        cpu = df.drop_duplicates("design_id").cpu_seconds.mean()
        print(f"  {label}: {wall:.1f} s wall, {cpu:.2f} CPU-s per design in its worker")
        if s.failed_designs:
            print(f"  {label}: first failure: {df[df.status == 'failed'].reason.iloc[0]}")
    base, base_steady = rates["1 worker"][0], rates["1 worker"][2]
    for label, (r, failed, steady) in rates.items():
        print(
            f"FEM sweep {label}: {r:.1f} designs/min end to end ({failed} failed), {r / base:.2f}x of "
            f"1 worker; steady state {steady:.1f} designs/min, {steady / base_steady:.2f}x (target >= 1.8x)"
        )
    # the same backend with one worker: Dask's own scaling, start-up included on both sides
    d1, d2 = rates["Dask LocalCluster (1)"], rates["Dask LocalCluster (2)"]
    print(
        f"Dask LocalCluster 2 workers / 1 worker: {d2[0] / d1[0]:.2f}x end to end, "
        f"{d2[2] / d1[2]:.2f}x steady state"
    )


def main(argv=None) -> int:
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--section", choices=("all", "analytic", "fem"), default="all")
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        if a.section in ("all", "analytic"):
            bench_analytic(tmp)
        if a.section in ("all", "fem"):
            bench_fem(tmp)
    return 0


if __name__ == "__main__":
    sys.exit(main())
