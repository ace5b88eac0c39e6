"""The 3-D finite-strain load path: quadratic predictor against the secant baseline.

The paper's tip walked from 0 to ``--pressure`` in ``--steps`` equal steps on ``--layers``
element layers (lumen load, the default section), twice: with Newton's default quadratic
predictor (``newton.solve(predictor="quadratic")``) and with the secant predictor that preceded
it. Both runs split the first step into the same ramp (``load_path.first_load_steps``). Prints, for
each, the tangent factorisations (PARDISO's numerical factorisation is ~80 % of a run), the
Newton iterations, the cutbacks and the wall time, their ratios, and how far the two answers
(mid-span curvature and tip angle at the top pressure) are apart: Newton's tolerance, nothing
more.

Run::

    python benchmarks/bench_load_path.py [--layers 8 --pressure 0.6 --steps 8]

``--layers 12`` is the size of ``softcath fem paper --nonlinear`` (a few minutes on 2 cores).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _timing import row  # noqa: E402

from softcath.design import preset  # noqa: E402
from softcath.fem.nonlinear.bend import bend_curve  # noqa: E402


def _run(pressures: np.ndarray, layers: int, predictor: str):
    t0 = time.perf_counter()
    curve = bend_curve(preset("paper"), pressures, layers=layers, predictor=predictor)
    return curve, time.perf_counter() - t0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="The 3-D load path: quadratic predictor against the secant.")
    ap.add_argument("--layers", type=int, default=8)
    ap.add_argument("--pressure", type=float, default=0.6)
    ap.add_argument("--steps", type=int, default=8)
    args = ap.parse_args(argv)
    pressures = args.pressure * np.arange(1, args.steps + 1) / args.steps
    new, t_new = _run(pressures, args.layers, "quadratic")
    old, t_old = _run(pressures, args.layers, "secant")
    print(
        f"paper tip, 0-{args.pressure:g} MPa in {args.steps} steps, {args.layers} layers, "
        f"{new.ndofs} DOFs, {np.degrees(new.bend_angle[-1]):.1f} deg at the top"
    )
    for label, c, t in (("secant predictor (baseline)", old, t_old), ("quadratic predictor", new, t_new)):
        cut = sum(s.cutbacks for s in c.result.steps)
        print(
            row(
                label,
                f"{c.result.factorisations} fact., {c.result.newton_iterations} its",
                f"{cut} cutbacks, {t:.1f} s",
            )
        )
    print(
        row(
            "factorisations, baseline / quadratic",
            f"{old.result.factorisations / new.result.factorisations:.2f}x",
            f"wall time {t_old / t_new:.2f}x",
        )
    )
    dk = abs(new.curvature_mid[-1] / old.curvature_mid[-1] - 1)
    da = abs(new.bend_angle[-1] / old.bend_angle[-1] - 1)
    ok = dk < 1e-6 and da < 1e-6
    print(row("answers apart (mid-span curvature, tip angle)", f"{dk:.1e}, {da:.1e}", "target < 1e-6", ok))
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
