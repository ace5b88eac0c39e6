"""Analytic model and calibration speed.

1. Analytic evaluations per second over 1e6 (design, pressure) pairs, vectorised, against the
   per-point scalar loop a script would write (``analytic.response`` on one design and pressure).
   Target ≥ 1e7 pairs/s.
2. The eq. 8 calibration (CasADi Opti + IPOPT, full multistart) on a 10-cycle, 200 Hz series,
   against a scipy SLSQP multistart from the same starts with the same constraints, evaluating
   the model over the series with finite-difference gradients (the MATLAB-script way).
   Targets: ≤ 2 s, ≥ 5× faster, same optimum.
Run: ``python benchmarks/bench_analytic.py``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from scipy import optimize

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).parents[1]))

from _timing import best_of, row  # noqa: E402

from softcath import (
    analytic,  # noqa: E402
    design,  # noqa: E402
)
from softcath.analytic.calibration import N_CONTAINMENT, _bounds, _inside, calibrate  # noqa: E402
from softcath.design.measurement import Measurement  # noqa: E402


def bench_evaluations() -> None:
    print("analytic evaluations")
    base = analytic.design_inputs(design.preset("paper"))
    rng = np.random.default_rng(0)
    # (a) 1000 designs x 1000 pressures, broadcast
    n_d = 1000
    inp = {k: np.full((n_d, 1), v) for k, v in base.items()}
    inp["a_int"] = rng.uniform(0.05, 0.15, (n_d, 1))
    inp["h"] = rng.uniform(-0.03, 0.03, (n_d, 1))
    p = np.linspace(0, 3, 1000)
    t_grid, _ = best_of(lambda: analytic.response_arrays(inp, p))
    # (b) 1e6 distinct designs, one pressure each: the swept inputs are arrays, the rest scalars
    n = 1_000_000
    inp2 = dict(base)
    inp2["a_int"] = rng.uniform(0.05, 0.15, n)
    inp2["h"] = rng.uniform(-0.03, 0.03, n)
    p2 = rng.uniform(0, 3, n)
    t_flat, _ = best_of(lambda: analytic.response_arrays(inp2, p2))
    inp3 = {k: np.full(n, v) for k, v in inp2.items()}
    t_all, _ = best_of(lambda: analytic.response_arrays(inp3, p2))
    # baseline: scalar loop over 2000 pairs
    d = design.preset("paper")
    m = 2000
    t0 = time.perf_counter()
    for q in np.linspace(0, 3, m):
        analytic.response(d, float(q))
    rate_loop = m / (time.perf_counter() - t0)
    r_grid, r_flat = 1e6 / t_grid, 1e6 / t_flat
    print(
        row(
            "1000 designs x 1000 pressures (broadcast)",
            f"{r_grid:.3g} pairs/s",
            "target >= 1e7",
            r_grid >= 1e7,
        )
    )
    print(
        row(
            "1e6 distinct designs (a_int, h swept) x 1 pressure",
            f"{r_flat:.3g} pairs/s",
            "target >= 1e7",
            r_flat >= 1e7,
        )
    )
    print(row("1e6 distinct designs, every input an array", f"{1e6 / t_all:.3g} pairs/s"))
    print(row("baseline: scalar loop (analytic.response per point)", f"{rate_loop:.3g} pairs/s"))
    print(row("ratio vectorised / scalar loop", f"{r_grid / rate_loop:.0f}x / {r_flat / rate_loop:.0f}x"))


def slsqp_multistart(m: Measurement, d: design.TipDesign, starts: list[np.ndarray]) -> tuple[float, dict]:
    """The baseline: model over the whole series, SLSQP with finite differences, same X and starts."""
    p, k = m.pressure_MPa, m.curvature_per_mm
    eps = m.elongation(d.tip.bending_length)
    w_k, w_e = 1 / (k @ k), 1 / (eps @ eps)
    base = analytic.design_inputs(d)
    keys = ("a", "a_int", "b_int", "h")
    b, t = d.vertical_semi_axis, d.tube.min_wall
    s_grid = np.linspace(-1, 1, N_CONTAINMENT)
    margin = (s_grid[1] - s_grid[0]) ** 2 / 4
    bounds = _bounds(d)

    def objective(x):
        inp = dict(base, **dict(zip(keys, x, strict=True)))
        r = analytic.response_arrays(inp, p)
        return w_e * np.sum((r.elongation - eps) ** 2) + w_k * np.sum((r.curvature - k) ** 2)

    def containment(x):
        a, ai, bi, h = x
        am, bm = a - t, b - t
        lhs = ai**2 * (1 - s_grid**2) * bm**2 + (h + bi * s_grid) ** 2 * am**2
        return ((1 - margin) * am**2 * bm**2 - lhs) / 0.3**4

    best = (np.inf, None)
    for x0 in starts:
        res = optimize.minimize(
            objective,
            x0,
            method="SLSQP",
            bounds=[bounds[q] for q in keys],
            constraints=[{"type": "ineq", "fun": containment}],
            options={"ftol": 1e-14, "maxiter": 300},
        )
        shape = dict(zip(keys, res.x, strict=True))
        if _inside(d, shape) and res.fun < best[0]:
            best = (float(res.fun), shape)
    return best


def bench_calibration() -> None:
    print("calibration (eq. 8), 10 cycles at 200 Hz")
    d = design.preset("paper")
    truth = d.with_tube_shape(a=0.2, a_int=0.12, b_int=0.09, h=0.02)
    t = np.arange(0, 40.0, 1 / 200)  # 10 cycles of 0.25 Hz
    pr = 2.0 * (1 - np.cos(2 * np.pi * 0.25 * t)) / 2
    r = analytic.response(truth, pr)
    rng = np.random.default_rng(1)
    m = Measurement.from_arrays(
        time_s=t,
        pressure_MPa=pr,
        curvature_per_mm=r.curvature + 0.002 * rng.standard_normal(t.size),
        arc_length_mm=r.arc_length + 0.002 * rng.standard_normal(t.size),
    )
    t_ca, res = best_of(lambda: calibrate(m, d), repeat=3)
    # the same feasible grid starts the CasADi multistart used
    bounds = _bounds(d)
    keys = ("a", "a_int", "b_int", "h")
    import itertools

    axes = [bounds[q][0] + (bounds[q][1] - bounds[q][0]) * (np.arange(3) + 0.5) / 3 for q in keys]
    starts = [
        np.array(c) for c in itertools.product(*axes) if _inside(d, dict(zip(keys, c, strict=True)), 1e-9)
    ]
    starts.append(np.array([d.tube_shape[q] for q in keys]))
    t0 = time.perf_counter()
    f_sp, _ = slsqp_multistart(m, d, starts)
    t_sp = time.perf_counter() - t0
    print(
        row(
            f"CasADi/IPOPT multistart ({res.starts} starts, {m.time_s.size} samples)",
            f"{t_ca:.3f} s",
            "target <= 2 s",
            t_ca <= 2,
        )
    )
    print(row("scipy SLSQP multistart, same starts and X (baseline)", f"{t_sp:.3f} s"))
    print(row("ratio SLSQP / CasADi", f"{t_sp / t_ca:.1f}x", "target >= 5x", t_sp / t_ca >= 5))
    print(
        row(
            "objective: CasADi vs SLSQP",
            f"{res.objective:.6g} vs {f_sp:.6g}",
            "same optimum",
            abs(res.objective - f_sp) <= 1e-6 * max(1, f_sp) + 1e-9,
        )
    )


if __name__ == "__main__":
    bench_evaluations()
    bench_calibration()
