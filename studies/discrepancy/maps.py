"""Where model and data disagree: residual maps over pressure, rate, direction, run, time."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.analytic.effects.fit import ChainFit, predict_chain
from softcath.studies.discrepancy.prepare import Prepared

__all__ = ["Residuals", "residuals", "binned"]


@dataclass(frozen=True)
class Residuals:
    """Residual (data - model, filtered, 1/mm) of every scored sample with its context."""

    residual: np.ndarray
    model: np.ndarray
    data: np.ndarray
    pressure_MPa: np.ndarray
    rate_MPa_per_s: np.ndarray
    loading: np.ndarray  # bool: pressure rising
    time_s: np.ndarray
    run: np.ndarray  # run index per sample
    labels: tuple[str, ...]
    frequency_hz: tuple[float, ...]

    def rms_by_run(self) -> dict[str, float]:
        return {
            lab: float(np.sqrt(np.mean(self.residual[self.run == i] ** 2)))
            for i, lab in enumerate(self.labels)
        }


def residuals(prep: Prepared, fit: ChainFit) -> Residuals:
    """Residuals of ``fit`` on every segment of ``prep`` (in-sample, for locating)."""
    filt = prep.output_filter()
    cols = {k: [] for k in ("r", "m", "d", "p", "dp", "t", "run")}
    for i, (s, t) in enumerate(zip(prep.segments, prep.times, strict=True)):
        m = predict_chain(fit, s, output_filter=filt)
        dp = np.gradient(s.pressure_MPa, s.dt_s) if not prep.static else np.zeros(s.target.size)
        sel = s.mask
        cols["r"].append((s.target - m)[sel])
        cols["m"].append(m[sel])
        cols["d"].append(s.target[sel])
        cols["p"].append(s.pressure_MPa[sel])
        cols["dp"].append(dp[sel])
        cols["t"].append(t[sel])
        cols["run"].append(np.full(int(sel.sum()), i))
    c = {k: np.concatenate(v) for k, v in cols.items()}
    return Residuals(
        residual=c["r"],
        model=c["m"],
        data=c["d"],
        pressure_MPa=c["p"],
        rate_MPa_per_s=c["dp"],
        loading=c["dp"] > 0,
        time_s=c["t"],
        run=c["run"],
        labels=tuple(r.label for r in prep.runs),
        frequency_hz=tuple(r.frequency_hz for r in prep.runs),
    )


def binned(x: np.ndarray, r: np.ndarray, bins: int = 12) -> tuple[np.ndarray, np.ndarray]:
    """Bin centres of ``x`` (equal-count bins) and the mean residual in each."""
    if x.size < bins:
        return x, r
    edges = np.unique(np.quantile(x, np.linspace(0, 1, bins + 1)))
    idx = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, edges.size - 2)
    centre = np.array([x[idx == i].mean() for i in range(edges.size - 1) if np.any(idx == i)])
    mean = np.array([r[idx == i].mean() for i in range(edges.size - 1) if np.any(idx == i)])
    return centre, mean
