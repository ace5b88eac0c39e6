"""Benchmark of the section model, printed as ratios (with the machine's load).

In one run:

1. per design, mesh included, warm (imports loaded): the sweep path (batched
   section models on template meshes, templates already made, as in a long
   sweep where ~100 templates serve all designs) and the per-design section
   model on a fresh gmsh mesh, against ``fem.check`` on the same 6 random
   designs, both loads, once with the 3-D mesh made too (like for like) and
   once with the 3-D mesh from its cache (conservative);
2. a section sweep of N distinct designs (default 10^4, a Latin hypercube over
   coil and channel size, lumen shape, silicone moduli and tip length) through
   the ``softcath sweep`` machinery (``paper`` + ``section`` evaluators,
   3 pressures x 2 loads, results written) on 2 local worker processes;
   target: 10^5 designs in <= 10 min on 2 cores, extrapolated linearly from
   N (said so; the one-off template meshes make this conservative);
3. the time split of the sweep path per design (laws, template, morph,
   assembly, factorisation, solve, post) measured in-process on a sample, and
   the sweep machinery's own share (paper formula, tasks, serialisation,
   result writing): the sweep's wall time x 2 workers minus the in-process
   section time.

The process runs with one BLAS/OpenMP thread (unless the environment says otherwise),
as the sweep's worker processes do, so that the CPU clock of the time split is one core's.

Run: ``python benchmarks/bench_section.py [--designs N]`` (``make bench``).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def _variants(n: int, seed: int):
    from softcath.studies.sweep.random_designs import random_designs

    return random_designs(n, seed=seed)


def _load() -> str:
    import os

    return "load average " + ", ".join(f"{x:.2f}" for x in os.getloadavg()) + f" on {os.cpu_count()} cores"


def per_design() -> float:
    from softcath import fem
    from softcath.fem.section_model import section_model
    from softcath.fem.section_model.batch import section_models
    from softcath.fem.section_model.mesh import _catheter_cached

    designs = _variants(6, seed=5)
    section_model(designs[0], mesher="gmsh")  # imports, gmsh start-up
    section_models(designs)  # the templates, made once per topology and size class
    for d in designs:
        fem.check(d, pressures=[0.1])  # warm the 3-D mesh cache
    t_cached, t_meshed, t_sec, t_batch = [], [], [], []
    for d in designs:
        t = time.perf_counter()
        fem.check(d, pressures=[0.1])
        t_cached.append(time.perf_counter() - t)
        t = time.perf_counter()
        fem.check(d, pressures=[0.1], use_cache=False)
        t_meshed.append(time.perf_counter() - t)
        _catheter_cached.cache_clear()  # the section mesh is part of the section model's cost
        t = time.perf_counter()
        section_model(d, mesher="gmsh")
        t_sec.append(time.perf_counter() - t)
        t = time.perf_counter()
        section_models([d])
        t_batch.append(time.perf_counter() - t)
    s = sum(t_sec) / len(t_sec)
    b = sum(t_batch) / len(t_batch)
    print(f"per design, both loads, {len(designs)} designs, warm (imports loaded) [{_load()}]:")
    for label, ts in (
        ("3-D FEM, mesh made each time (like for like)", t_meshed),
        ("3-D FEM, mesh from its cache (conservative)", t_cached),
    ):
        f = sum(ts) / len(ts)
        print(
            f"  {label}: {f:6.2f} s   sweep path (template, batched) {b * 1e3:5.1f} ms  ratio {f / b:6.0f}x  "
            f" section model on a fresh gmsh mesh {s * 1e3:5.0f} ms  ratio {f / s:5.1f}x"
        )
    return b


def split(n: int) -> float:
    """In-process time split of the sweep path over ``n`` designs (templates made first); seconds per
    design."""
    from softcath.fem.section_model.batch import TIMERS, section_models
    from softcath.studies.sweep.spec import SECTION_CHUNK

    designs = _variants(n, seed=8)
    chunks = [designs[i : i + SECTION_CHUNK] for i in range(0, n, SECTION_CHUNK)]  # the sweep's tasks
    for c in chunks:
        section_models(c)
    TIMERS.clear()
    t, c0 = time.perf_counter(), time.process_time()
    for c in chunks:
        section_models(c)
    per, cpu = (time.perf_counter() - t) / n, (time.process_time() - c0) / n
    parts = "  ".join(f"{k} {v / n * 1e3:.2f}" for k, v in TIMERS.items())
    print(
        f"time split of the sweep path, {n} designs in tasks of {SECTION_CHUNK}, in-process, "
        f"templates made [{_load()}]: "
        f"{per * 1e3:.1f} ms/design wall, {cpu * 1e3:.1f} ms CPU = {parts} (ms, stage wall clocks)"
    )
    return cpu


def sweep(n: int, in_process: float | None = None) -> None:
    """``softcath sweep`` machinery, ``paper`` + ``section`` evaluators, 2 local workers, n distinct
    designs."""
    import tempfile

    from softcath.studies.sweep import load_spec, run_sweep
    from softcath.studies.sweep.random_designs import DEFAULT_RANGES

    params = "\n".join(f'"{path}" = {{ lhs = [{lo}, {hi}] }}' for path, (lo, hi) in DEFAULT_RANGES.items())
    spec_text = f"""[sweep]
name = "bench-section"
base = "paper"
pressures_MPa = [0.0, 0.5, 1.0]
loads = ["cap", "lumen"]
evaluators = ["paper", "section"]
seed = 9
[sample]
n = {n}
[parameters]
{params}
"""
    with tempfile.TemporaryDirectory() as tmp:
        spec_path = Path(tmp) / "spec.toml"
        spec_path.write_text(spec_text)
        t = time.perf_counter()
        summary = run_sweep(load_spec(spec_path), Path(tmp) / "run", workers=2, progress=False)
        wall = time.perf_counter() - t
        import pandas as pd

        t = time.perf_counter()
        table = pd.read_parquet(summary.results_parquet)
        cpu = float(table.groupby("design_id").cpu_seconds.first().mean())
        read = time.perf_counter() - t
    per = wall / n
    print(
        f"section sweep (softcath sweep, paper + section, 2 local workers), {n} designs: {wall:.1f} s "
        f"({per * 1000:.1f} ms/design wall; {summary}) [{_load()}]"
    )
    for total in (10_000, 100_000):
        label = "measured" if n >= total else f"extrapolated linearly from {n}"
        print(f"  {total:.0e} designs: {per * total / 60:.1f} min ({label})")
    print(f"  target 10^5 in <= 10 min (6 ms/design wall): {'OK' if per * 1e5 <= 600 else 'MISSED'}")
    print(
        f"  worker CPU per design (the table's cpu_seconds: formula + section + task): {cpu * 1e3:.1f} ms; "
        f"on 2 unshared cores 10^5 designs would take ~{cpu * 1e5 / 2 / 60:.1f} min (CPU-bound estimate)"
    )
    print(f"  reading the written table back: {read:.2f} s ({len(table)} rows)")
    if in_process is not None:
        print(
            f"  section path in-process {in_process * 1e3:.1f} ms CPU/design; the rest of the worker CPU "
            f"(paper formula, task building, frames): {(cpu - in_process) * 1e3:.1f} ms; the parent's share "
            f"(serialisation, writing, progress) is wall - CPU/2: {(per - cpu / 2) * 1e3:.1f} ms/design"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=10_000, help="designs in the sweep part (default 10^4)")
    ap.add_argument("--skip-fem", action="store_true", help="only the sweep part")
    ap.add_argument("--skip-sweep", action="store_true", help="only the per-design part")
    ap.add_argument("--split", type=int, default=1000, help="designs of the in-process time split")
    args = ap.parse_args()
    import os

    for var in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
        os.environ.setdefault(var, "1")  # before NumPy is imported: one thread, like a sweep worker
    if not args.skip_fem:
        per_design()
    in_process = split(args.split) if args.split else None
    if not args.skip_sweep:
        sweep(args.designs, in_process)


if __name__ == "__main__":
    main()
