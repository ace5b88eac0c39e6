"""Benchmark of the missing-effect workflow on hidden-effect data.

Prints the confusion matrix (truth vs first named effect, with a "none"
column) over ``--seeds`` data sets per class, per-class recall, the false-alarm
rate on no-effect data with its one-sided 95 % Clopper-Pearson upper bound, the
median held-out gap shrink per class, and timings: the workflow on a 60k-sample
set against the 30 s target, and the play-operator scan against the plain
recursion (baseline) in the same run.

Each data set: three sine frequencies (0.05, 0.1, 0.2 Hz) and a step-and-hold,
curvature noise log-uniform in 0.5-5 % of full scale (halved until the class can
reach the ENR, which only a dead zone at high noise needs), effect-to-noise
ratio ``--enr`` (default 2), random calibration error of +-20 %.

    python benchmarks/bench_effects.py [--seeds 60] [--enr 2] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from design.errors import DesignError  # noqa: E402
from hardware.plant import EFFECT_NAMES  # noqa: E402
from studies.discrepancy import run_workflow  # noqa: E402
from studies.hidden_effects import Protocol, make_case  # noqa: E402

CLASSES = ("none", *EFFECT_NAMES)


def clopper_pearson_upper(k: int, n: int, conf: float = 0.95) -> float:
    """One-sided upper confidence bound of a binomial proportion."""
    from scipy.stats import beta

    return 1.0 if k >= n else float(beta.ppf(conf, k + 1, n - k))


def one(cls: str, seed: int, enr: float) -> dict:
    rng = np.random.default_rng(10_000 + seed)
    noise = float(np.exp(rng.uniform(np.log(0.005), np.log(0.05))))
    effects = () if cls == "none" else (cls,)
    while True:
        try:
            case = make_case(effects, seed=seed, noise_fraction=noise, effect_to_noise=enr)
            break
        except DesignError:
            noise /= 2
    t0 = time.perf_counter()
    r = run_workflow(case.table)
    dt = time.perf_counter() - t0
    return {
        "recovery": recovery(cls, case, r),
        "truth": cls,
        "seed": seed,
        "noise": noise,
        "named": list(r.named),
        "first": r.named[0] if r.named else "none",
        "shrink": r.nrmse_before / r.nrmse_after,
        "ambiguous": r.ambiguous_with,
        "excess_removed": r.excess_removed,
        "seconds": dt,
        "samples": len(case.table),
    }


def recovery(cls: str, case, result) -> float | None:
    """Estimated / true value of the class's characteristic parameter (None if not named).

    lag: time constant (truth: Elmore time of the RC ladder); delay: latency;
    dead_zone: threshold; hysteresis: loop opening fraction * width (truth: fraction
    * mean relay width); viscoelastic: creep fraction; offset: pre-curvature
    (estimate over truth); nonlinear_gain: beta.
    """
    if not result.steps or result.steps[0]["effect"] != cls:
        return None
    est = result.steps[0]["params"]
    tru = case.truth_params[cls]
    if cls == "lag":
        return est["tau_s"] / tru["tau_s"]
    if cls == "delay":
        return est["delay_s"] / tru["delay_s"]
    if cls == "dead_zone":
        return est["threshold_MPa"] / tru["threshold_MPa"]
    if cls == "hysteresis":
        eff = case.plant.effects[0]
        a, b, _, _ = eff.relays()
        return est["fraction"] * est["loop_width_MPa"] / (tru["fraction"] * float(np.mean(a - b)))
    if cls == "viscoelastic":
        return est["creep_fraction"] / tru["creep_fraction"]
    if cls == "offset":
        return result.steps[0]["coefficient"] / tru["curvature_per_mm"]
    if cls == "nonlinear_gain":
        return est["beta_per_MPa"] / tru["beta_per_MPa"]
    return None


def timing_60k() -> tuple[float, int]:
    proto = Protocol(cycles=6, hold_s=30.0)  # ~300 s at 200 Hz
    case = make_case(("hysteresis",), seed=7, noise_fraction=0.01, effect_to_noise=3.0, protocol=proto)
    t0 = time.perf_counter()
    run_workflow(case.table)
    return time.perf_counter() - t0, len(case.table)


def timing_play() -> tuple[float, float]:
    from analytic.effects.hysteresis import play

    rng = np.random.default_rng(0)
    x = np.cumsum(rng.normal(size=6000))
    r = np.linspace(0, 3, 6)
    t0 = time.perf_counter()
    for _ in range(20):
        play(x, r)
    fast = (time.perf_counter() - t0) / 20
    t0 = time.perf_counter()
    y = x[0] - r
    out = np.empty((x.size, r.size))
    for k, xk in enumerate(x):  # the plain recursion, numpy per step
        y = np.minimum(np.maximum(y, xk - r), xk + r)
        out[k] = y
    slow = time.perf_counter() - t0
    return fast, slow


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=60)
    ap.add_argument("--enr", type=float, default=2.0)
    ap.add_argument("--json", type=Path)
    ap.add_argument("--classes", nargs="+", choices=CLASSES, default=list(CLASSES))
    args = ap.parse_args()
    from tqdm import tqdm

    rows = []
    classes = [c for c in CLASSES if c in args.classes]
    for cls in classes:
        for seed in tqdm(range(args.seeds), desc=cls, leave=False):
            rows.append(one(cls, seed, args.enr))
    cols = ["none", *EFFECT_NAMES]
    print(
        f"confusion matrix (rows: hidden effect, columns: first named), "
        f"{args.seeds} seeds/class, ENR {args.enr:g}"
    )
    w = 15
    print(" " * w + "".join(c[:9].rjust(10) for c in cols) + "    recall  exact")
    for cls in classes:
        sub = [r for r in rows if r["truth"] == cls]
        counts = [sum(r["first"] == c for r in sub) for c in cols]
        exact = sum(r["named"] == ([] if cls == "none" else [cls]) for r in sub) / len(sub)
        print(
            cls.ljust(w)
            + "".join(str(n).rjust(10) for n in counts)
            + f"{counts[cols.index(cls)] / len(sub):10.2f}{exact:7.2f}"
        )
    none = [r for r in rows if r["truth"] == "none"]
    k = sum(r["named"] != [] for r in none)
    if none:
        print(
            f"\nfalse alarms on no-effect data: {k}/{len(none)} = {k / len(none):.3f}, "
            f"95 % Clopper-Pearson upper bound {clopper_pearson_upper(k, len(none)):.3f}"
        )
    print("\nmedian held-out gap shrink (NRMSE before/after) and excess removed, per class:")
    for cls in [c for c in EFFECT_NAMES if c in classes]:
        sub = [r for r in rows if r["truth"] == cls]
        amb = sum(any(a) for a in (r["ambiguous"] for r in sub))
        print(
            f"  {cls:15s} shrink median {np.median([r['shrink'] for r in sub]):6.2f}  "
            f"min {np.min([r['shrink'] for r in sub]):6.2f}  excess removed median "
            f"{np.median([r['excess_removed'] for r in sub]):.3f}  flagged ambiguous {amb}"
        )
    print(
        "\nparameter recovery (estimate / truth of the characteristic parameter), "
        "median [10 %, 90 %] and share within 30 %:"
    )
    for cls in EFFECT_NAMES:
        rec = np.array([r["recovery"] for r in rows if r["truth"] == cls and r["recovery"] is not None])
        if rec.size:
            q = np.quantile(rec, [0.5, 0.1, 0.9])
            share = float(np.mean(np.abs(rec - 1) <= 0.3))
            print(f"  {cls:15s} {q[0]:6.2f} [{q[1]:.2f}, {q[2]:.2f}]  within 30 %: {share:.2f}")
    secs = np.array([r["seconds"] for r in rows])
    print(
        f"\nper data set (~{rows[0]['samples']} samples): median {np.median(secs):.2f} s, "
        f"max {secs.max():.2f} s"
    )
    t60, n60 = timing_60k()
    print(f"workflow on a {n60}-sample set: {t60:.1f} s (target <= 30 s): ratio to target {t60 / 30:.2f}")
    fast, slow = timing_play()
    print(
        f"play operator, 6000 samples x 6 radii: scan {fast * 1e3:.2f} ms vs plain recursion "
        f"{slow * 1e3:.1f} ms: {slow / fast:.0f}x faster"
    )
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
