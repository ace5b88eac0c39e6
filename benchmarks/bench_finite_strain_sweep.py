"""Benchmark of the finite-strain section sweep against the linear section sweep, per design.

In one run, on the same random valid designs (the sweep's usual ranges,
``softcath.studies.sweep.random_designs.DEFAULT_RANGES``), templates made and code
compiled first (as in a long sweep, where ~100 templates serve all designs), one
BLAS thread per process as in a sweep worker:

1. in-process, alternating rounds: the linear section sweep path
   (``section_blocks_many``: 3 pressures 0, 0.5, 1 MPa, both loads, in tasks as the
   sweep cuts them) and the finite-strain sweep path (``section_nonlinear_columns``:
   7 pressures 0-0.6 MPa, lumen load), seconds per design (wall and CPU) and their
   ratio per round; target: finite-strain <= 6x linear;
2. with ``--sweep N``: both evaluators through ``softcath sweep`` (``paper`` +
   ``section`` against ``paper`` + ``section-nonlinear``) on 2 local workers, N
   distinct designs each, wall per design, the ratio, and the 10^5-design wall time
   extrapolated linearly (said so), and the workers' CPU per design (the table's
   ``cpu_seconds``: formula, model and task; less sensitive to a shared machine's
   load than the wall); ``--chunks 0 125`` runs the finite-strain sweep with the
   sweep's own task size and with tasks of 125 designs.

The machine may be shared: each round's ratio is measured on the same designs back to
back, and the spread of the rounds is printed.

Run: ``python benchmarks/bench_finite_strain_sweep.py [--designs 40 --rounds 5 --sweep 0]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

for _var in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # before NumPy is imported: one thread, like a sweep worker

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks._timing import row  # noqa: E402

LINEAR_PRESSURES = np.array([0.0, 0.5, 1.0])
FINITE_PRESSURES = np.linspace(0.0, 0.6, 7)


def _load() -> str:
    return "load average " + ", ".join(f"{x:.2f}" for x in os.getloadavg()) + f" on {os.cpu_count()} cores"


def linear_path(designs) -> None:
    from softcath.models.section_eval import section_blocks_many
    from softcath.studies.sweep.spec import SECTION_CHUNK

    for i in range(0, len(designs), SECTION_CHUNK):
        section_blocks_many(designs[i : i + SECTION_CHUNK], LINEAR_PRESSURES, ("cap", "lumen"), {})


def finite_path(designs) -> list[float]:
    """Runs the finite-strain evaluator; returns the bend angles at 0.6 MPa [deg]."""
    from softcath.models.section_nonlinear_eval import section_nonlinear_columns

    out = []
    for d in designs:
        cols = section_nonlinear_columns(d, FINITE_PRESSURES, ("lumen",))["lumen"]
        out.append(float(np.degrees(cols["bend_angle_section_nonlinear_rad"][-1])))
    return out


def _timed(fn, designs) -> tuple[float, float, object]:
    t, c = time.perf_counter(), time.process_time()
    out = fn(designs)
    n = len(designs)
    return (time.perf_counter() - t) / n, (time.process_time() - c) / n, out


def in_process(n: int, rounds: int, seed: int) -> None:
    from softcath.studies.sweep.random_designs import random_designs

    designs = random_designs(n, seed=seed)
    linear_path(designs)  # templates, kernels, compiled code
    angles = finite_path(designs)
    print(
        f"in-process, {n} random designs (bend at 0.6 MPa {min(angles):.0f}-{max(angles):.0f} deg), "
        f"{rounds} rounds [{_load()}]:"
    )
    ratios_wall, ratios_cpu = [], []
    for r in range(rounds):
        lw, lc, _ = _timed(linear_path, designs)
        fw, fc, _ = _timed(finite_path, designs)
        ratios_wall.append(fw / lw)
        ratios_cpu.append(fc / lc)
        print(
            f"  round {r + 1}: linear {lw * 1e3:6.1f} ms wall {lc * 1e3:6.1f} ms CPU; "
            f"finite-strain {fw * 1e3:6.1f} ms wall {fc * 1e3:6.1f} ms CPU; "
            f"ratio {fw / lw:4.2f} wall, {fc / lc:4.2f} CPU"
        )
    med_w, med_c = float(np.median(ratios_wall)), float(np.median(ratios_cpu))
    print(f"  [{_load()}]")
    print(
        row(
            "finite-strain / linear sweep design, in-process (median)",
            f"{med_w:.2f}x wall, {med_c:.2f}x CPU",
            f"rounds {min(ratios_wall):.2f}-{max(ratios_wall):.2f} wall; target <= 6x",
            med_w <= 6.0,
        )
    )


def _spec(name: str, evaluator: str, pressures, loads, n: int) -> str:
    from softcath.studies.sweep.random_designs import DEFAULT_RANGES

    params = "\n".join(f'"{path}" = {{ lhs = [{lo}, {hi}] }}' for path, (lo, hi) in DEFAULT_RANGES.items())
    return f"""[sweep]
name = "{name}"
base = "paper"
pressures_MPa = {[float(p) for p in pressures]}
loads = {list(loads)}
evaluators = ["paper", "{evaluator}"]
seed = 9
[sample]
n = {n}
[parameters]
{params}
"""


def through_sweep(n: int, chunks: list[int]) -> None:
    """Both sweeps of ``n`` designs; the finite-strain one once per task size in ``chunks`` (0: the
    sweep's own, ``spec.SECTION_NONLINEAR_CHUNK``; another value replaces that constant for the run)."""
    import tempfile

    import pandas as pd

    from softcath.studies.sweep import load_spec, run_sweep
    from softcath.studies.sweep import spec as spec_module

    walls = {}
    own = spec_module.SECTION_NONLINEAR_CHUNK
    runs = [("linear", "section", LINEAR_PRESSURES, ("cap", "lumen"), own)]
    runs += [("finite", "section-nonlinear", FINITE_PRESSURES, ("lumen",), c or own) for c in chunks]
    with tempfile.TemporaryDirectory() as tmp:
        for i, (name, evaluator, pressures, loads, chunk) in enumerate(runs):
            spec_module.SECTION_NONLINEAR_CHUNK = chunk
            name = "linear" if i == 0 else f"tasks of {chunk}"
            path = Path(tmp) / f"run{i}.toml"
            path.write_text(_spec(f"run{i}", evaluator, pressures, loads, n))
            spec = load_spec(path)
            t = time.perf_counter()
            summary = run_sweep(spec, Path(tmp) / f"run{i}", workers=2, progress=False)
            wall = (time.perf_counter() - t) / n
            table = pd.read_parquet(summary.results_parquet)
            cpu = float(table.groupby("design_id").cpu_seconds.first().mean())  # the worker's, per design
            walls[name] = (wall, cpu)
            print(
                f"softcath sweep, paper + {evaluator}, {n} designs, 2 local workers, tasks of "
                f"{spec.effective_chunk_size}: {wall * n:.1f} s ({wall * 1e3:.1f} ms/design wall, "
                f"worker CPU {cpu * 1e3:.1f} ms/design; {summary.failed_designs} failed) [{_load()}]"
            )
            spec_module.SECTION_NONLINEAR_CHUNK = own
    lin_wall, lin_cpu = walls.pop("linear")
    for name, (wall, cpu) in walls.items():
        print(
            row(
                f"finite-strain ({name}) / linear sweep design",
                f"{wall / lin_wall:.2f}x wall, {cpu / lin_cpu:.2f}x CPU",
                "target <= 6x",
                wall / lin_wall <= 6,
            )
        )
        print(
            f"  10^5 finite-strain designs ({name}): {wall * 1e5 / 60:.0f} min wall at this load "
            f"(extrapolated linearly from {n}); CPU-bound on 2 unshared cores: {cpu * 1e5 / 2 / 60:.0f} min"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--designs", type=int, default=40, help="random designs of the in-process part")
    ap.add_argument("--rounds", type=int, default=5, help="alternating rounds of the in-process part")
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--sweep", type=int, default=0, help="designs of each softcath sweep (0: skip)")
    ap.add_argument(
        "--chunks",
        type=int,
        nargs="+",
        default=[0],
        help="finite-strain task sizes to run (0: the sweep's own SECTION_NONLINEAR_CHUNK)",
    )
    args = ap.parse_args()
    if args.designs:
        in_process(args.designs, args.rounds, args.seed)
    if args.sweep:
        through_sweep(args.sweep, args.chunks)


if __name__ == "__main__":
    main()
