"""The prediction band (p5, p50, p95) and where a measurement falls in it."""

from __future__ import annotations

import numpy as np

from softcath.design.errors import DesignError

__all__ = ["PERCENTILES", "percentiles", "measured_position"]

#: The band's percentiles: p5 and p95 bound the 90 % band, p50 is its median.
PERCENTILES = (5, 50, 95)


def percentiles(values: np.ndarray) -> dict[str, float]:
    """``{"p5": .., "p50": .., "p95": ..}`` of the finite ``values`` (linear interpolation)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        raise DesignError("samples", 0, "no feasible variant to take percentiles of")
    return {f"p{q}": float(np.percentile(v, q)) for q in PERCENTILES}


def measured_position(values: np.ndarray, measured: float) -> dict:
    """Where ``measured`` falls among the finite ``values``.

    Returns
    -------
    dict
        ``measured_percentile``: the share of the sample at or below the
        measurement, 0–100 (0 or 100 when it lies beyond every sample);
        ``measured_in_band``: p5 <= measured <= p95; ``measured_outside``:
        ``"below p5"``, ``"above p95"`` or ``None``; ``measured_over_p50``.
    """
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if not np.isfinite(measured):
        raise DesignError("measured_gain", measured, "must be finite")
    band = percentiles(v)
    pct = 100.0 * float(np.mean(v <= measured))
    outside = "below p5" if measured < band["p5"] else "above p95" if measured > band["p95"] else None
    return {
        "measured_percentile": pct,
        "measured_in_band": outside is None,
        "measured_outside": outside,
        "measured_over_p50": float(measured / band["p50"]) if band["p50"] != 0 else float("nan"),
    }
