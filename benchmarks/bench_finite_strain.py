"""Benchmark of the finite-strain section model against the 3-D finite-strain FEM.

In one run, on the same designs (the paper design and ``--designs - 1``
random valid designs):

1. the whole bend curve 0-0.6 MPa (7 pressures, lumen load) of the
   finite-strain section model, section mesh included (the design's template
   mesh morphed to it; the template itself made once per process, as in a
   sweep), warm imports; target <= 2 s per design;
2. the same pressures through the 3-D finite-strain FEM, what
   ``softcath fem --nonlinear --pressure 0.6 --steps 6`` runs (default mesh,
   mesh included), on the paper design (``--fem-designs`` for more);
   target: the section model >= 25x faster;
3. both models' mid-span bend rate at 0.6 MPa, so the speed is not bought with
   a different answer (the 3-D mesh and end zones account for a few percent).

Run: ``python benchmarks/bench_finite_strain.py [--designs 3 --fem-designs 1]`` (``make bench``).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks._timing import row  # noqa: E402

PRESSURES = np.linspace(0.0, 0.6, 7)


def _designs(n: int):
    from softcath import design
    from softcath.studies.sweep.random_designs import random_designs

    return [design.preset("paper"), *random_designs(max(n - 1, 0), seed=3)]


def section_time(d) -> tuple[float, object]:
    from softcath.fem.section_model.finite_strain import section_curve
    from softcath.fem.section_model.mesh import _catheter_cached

    _catheter_cached.cache_clear()  # a fresh gmsh mesh, for a design the template refuses
    t0 = time.perf_counter()
    curve = section_curve(d, PRESSURES, linear_gain=False)  # the curve alone
    return time.perf_counter() - t0, curve


def fem_time(d) -> tuple[float, object]:
    from softcath.fem.nonlinear import bend_curve

    t0 = time.perf_counter()
    curve = bend_curve(d, PRESSURES[1:], load="lumen")
    return time.perf_counter() - t0, curve


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=3, help="designs for the section model (paper first)")
    ap.add_argument("--fem-designs", type=int, default=1, help="of those, how many also run the 3-D FEM")
    args = ap.parse_args()
    designs = _designs(args.designs)
    section_time(designs[0])  # warm: imports, einsum paths, the first factorisation
    sec, fem = [], []
    print("finite-strain section model vs 3-D finite-strain FEM, 7 pressures 0-0.6 MPa, lumen load")
    for i, d in enumerate(designs):
        ts, sc = section_time(d)
        sec.append(ts)
        line = f"{d.name}: section {ts:.2f} s ({sc.dofs} DOFs, {int(sc.newton_iterations.sum())} Newton its)"
        if i < args.fem_designs:
            tf, fc = fem_time(d)
            fem.append(tf)
            rate3 = float(np.asarray(fc.bend_rate_mid)[-1])
            line += (
                f"; 3-D {tf:.1f} s ({fc.ndofs} DOFs), ratio {tf / ts:.0f}x; "
                f"mid-span bend rate at 0.6 MPa: section {sc.bend_rate_per_mm[-1]:.4f}, 3-D {rate3:.4f} /mm"
            )
        print("  " + line)
    worst = max(sec)
    print(row("section model, whole curve, worst design", f"{worst:.2f} s", "target <= 2 s", worst <= 2.0))
    if fem:
        ratio = min(f / s for f, s in zip(fem, sec, strict=False))
        print(
            row(
                "speed-up over softcath fem --nonlinear (smallest)",
                f"{ratio:.0f}x",
                "target >= 25x",
                ratio >= 25,
            )
        )
    print(row("finite-strain section sweep rate (1 process)", f"{3600 / np.mean(sec):.0f} designs/h"))


if __name__ == "__main__":
    main()
