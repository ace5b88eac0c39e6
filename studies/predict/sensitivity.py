"""First-order sensitivity indices of the gain to each varied parameter (SALib RBD-FAST).

RBD-FAST (Tarantola et al. 2006; Plischke 2010) estimates each parameter's
first-order Sobol index S1 — the share of the gain's variance explained by
that parameter alone — from any sample by ordering it along each input; it
reuses the Latin-hypercube sample that makes the band, so no extra model
runs are needed. Confidence intervals come from SALib's bootstrap with the
prediction's seed. Below :data:`MIN_SAMPLES` the harmonics cannot be
resolved (8 FEM runs give nonsense indices) and the indices are left out,
saying so.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MIN_SAMPLES", "HARMONICS", "first_order"]

#: Fewest feasible samples for which indices are reported.
MIN_SAMPLES = 64
#: RBD-FAST harmonics (SALib's default).
HARMONICS = 10


def first_order(unit: np.ndarray, y: np.ndarray, names: list[str], *, seed: int) -> dict:
    """RBD-FAST S1 and its 95 % confidence half-width per parameter, ranked.

    Parameters
    ----------
    unit
        The unit-cube sample (rows = variants, columns = ``names``).
    y
        Model output per row (NaN rows, infeasible variants, are dropped).
    names
        Parameter paths, in column order.
    seed
        Bootstrap seed.
    """
    from SALib.analyze import rbd_fast

    ok = np.isfinite(y)
    x, y = unit[ok], np.asarray(y, float)[ok]
    out = {
        "method": "RBD-FAST first-order index S1 (SALib), 95 % bootstrap confidence",
        "indices": {},
        "ranking": [],
    }
    if not names:
        out["skipped"] = "no parameter varied"
        return out
    if x.shape[0] < MIN_SAMPLES:
        out["skipped"] = f"needs >= {MIN_SAMPLES} feasible samples, got {x.shape[0]}"
        return out
    if np.ptp(y) <= 1e-12 * max(1.0, float(np.max(np.abs(y)))):
        out["skipped"] = "the gain does not change over the sample"
        return out
    problem = {"num_vars": len(names), "names": list(names), "bounds": [[0.0, 1.0]] * len(names)}
    s = rbd_fast.analyze(problem, x, y, M=HARMONICS, seed=seed)
    for name, s1, conf in zip(names, s["S1"], s["S1_conf"], strict=True):
        out["indices"][name] = {"S1": float(s1), "S1_conf": float(conf)}
    out["ranking"] = sorted(names, key=lambda n: -out["indices"][n]["S1"])
    return out
