"""Benchmark of the section model (issue 11 section 3), printed as ratios.

In one run:

1. per design, mesh included, warm (imports loaded; the section mesh is made
   for every design, as in a sweep where every design has its own geometry):
   the section model of 6 random designs against ``fem.check`` on the same
   designs, both loads, once with the 3-D mesh made too (like for like) and
   once with the 3-D mesh from its cache (conservative); target >= 50x;
2. a section sweep of N distinct designs (default 10^4, a Latin hypercube over
   coil and channel size, lumen shape, silicone moduli and tip length) through
   the ``softcath sweep`` machinery (``analytic`` + ``section`` evaluators,
   3 pressures x 2 loads, results written) on 2 local worker processes;
   target <= 10 min on 2 cores. ``--designs N`` runs a smaller sweep and
   extrapolates (said so in the output).

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


def per_design() -> None:
    from softcath import fem
    from softcath.fem.section_model import section_model
    from softcath.fem.section_model.mesh import _catheter_cached

    designs = _variants(6, seed=5)
    section_model(designs[0])  # imports, gmsh start-up
    for d in designs:
        fem.check(d, pressures=[0.1])  # warm the 3-D mesh cache
    t_cached, t_meshed, t_sec = [], [], []
    for d in designs:
        t = time.perf_counter()
        fem.check(d, pressures=[0.1])
        t_cached.append(time.perf_counter() - t)
        t = time.perf_counter()
        fem.check(d, pressures=[0.1], use_cache=False)
        t_meshed.append(time.perf_counter() - t)
        _catheter_cached.cache_clear()  # the section mesh is part of the section model's cost
        t = time.perf_counter()
        section_model(d)
        t_sec.append(time.perf_counter() - t)
    s = sum(t_sec) / len(t_sec)
    print(
        f"per design, both loads, {len(designs)} designs, warm (imports loaded), section mesh made each time:"
    )
    for label, ts in (("3-D FEM, mesh made each time (like for like)", t_meshed),
                      ("3-D FEM, mesh from its cache (conservative)", t_cached)):  # fmt: skip
        f = sum(ts) / len(ts)
        ratio = f / s
        print(f"  {label}: {f:6.2f} s   section model {s:5.3f} s   ratio {ratio:5.1f}x   "
              f"target >= 50x  {'OK' if ratio >= 50 else 'MISSED'}")  # fmt: skip


def sweep(n: int) -> None:
    """``softcath sweep`` machinery, ``analytic`` + ``section`` evaluators, 2 local workers, n distinct designs."""
    import tempfile

    from softcath.studies.sweep import load_spec, run_sweep
    from softcath.studies.sweep.random_designs import DEFAULT_RANGES

    params = "\n".join(f'"{path}" = {{ lhs = [{lo}, {hi}] }}' for path, (lo, hi) in DEFAULT_RANGES.items())
    spec_text = f"""[sweep]
name = "bench-section"
base = "paper"
pressures_MPa = [0.0, 0.5, 1.0]
loads = ["cap", "lumen"]
evaluators = ["analytic", "section"]
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
        summary = run_sweep(load_spec(spec_path), Path(tmp) / "run", workers=2, progress=True)
        wall = time.perf_counter() - t
    per = wall / n
    ten_k = per * 1e4
    print(f"section sweep (softcath sweep, analytic + section, 2 local workers), {n} designs: {wall:.1f} s "
          f"({per * 1000:.0f} ms/design; {summary})")  # fmt: skip
    label = "measured" if n >= 10_000 else f"extrapolated from {n}"
    print(
        f"  10^4 designs: {ten_k / 60:.1f} min ({label})   target <= 10 min  {'OK' if ten_k <= 600 else 'MISSED'}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=10_000, help="designs in the sweep part (default 10^4)")
    ap.add_argument("--skip-fem", action="store_true", help="only the sweep part")
    ap.add_argument("--skip-sweep", action="store_true", help="only the per-design part")
    args = ap.parse_args()
    if not args.skip_fem:
        per_design()
    if not args.skip_sweep:
        sweep(args.designs)


if __name__ == "__main__":
    main()
