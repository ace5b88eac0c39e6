"""From the time-series terms to the physical ingredients that produce them.

The time-series step names curve-fitting terms (a ``delay``, a ``dead_zone``,
a ``nonlinear_gain``, ...). This step takes the recording to physics: the
named delay is removed, each run is split in time into a first half (to fit)
and a second half (held out), each half is reduced to a quasi-static curve
(the median curvature in equal pressure bins), the physical hypotheses
(:mod:`.prototype`) are fitted on the first half, and the baseline and the
chosen hypothesis, with the parameters fitted there, are scored on the second.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from softcath.studies.discrepancy.model_bank import ModelBank
from softcath.studies.discrepancy.physical import nrmse, predict
from softcath.studies.discrepancy.prototype import explain_prototype

__all__ = ["TERM_CAUSES", "quasi_static_curve", "physical_step"]

#: Which physical ingredients can produce each time-series term.
TERM_CAUSES: dict[str, tuple[str, ...]] = {
    "dead_zone": ("coil_initial_tension", "pressure_offset"),
    "nonlinear_gain": ("filler_none", "tube_modulus", "nu_0.4999"),
    "offset": ("rest_curvature", "pressure_offset"),
    "delay": (),
    "lag": (),
    "hysteresis": (),
    "viscoelastic": (),
}
BINS = 13
_MIN_PER_BIN = 3


def quasi_static_curve(pressure: np.ndarray, curvature: np.ndarray, *, bins: int = BINS) -> dict:
    """Median pressure and curvature in ``bins`` equal pressure bins (bins with >= 3 samples)."""
    edges = np.linspace(pressure.min(), pressure.max(), bins + 1)
    which = np.clip(np.searchsorted(edges, pressure, side="right") - 1, 0, bins - 1)
    p, k = [], []
    for b in range(bins):
        sel = which == b
        if sel.sum() >= _MIN_PER_BIN:
            p.append(float(np.median(pressure[sel])))
            k.append(float(np.median(curvature[sel])))
    return {"pressure_MPa": np.array(p), "curvature_per_mm": np.array(k)}


def _halves(result, delay_s: float) -> tuple[dict, dict]:
    """The delay-corrected first and second halves of every run, as quasi-static curves."""
    first, second = [], []
    for seg in result.prepared.segments:
        t = np.arange(seg.target.size) * seg.dt_s
        keep = seg.mask & (t + delay_s <= t[-1])
        k = np.interp(t + delay_s, t, seg.target)  # the response the pressure at t produced
        p = np.asarray(seg.pressure_MPa)
        half = t[-1] / 2
        first.append((p[keep & (t < half)], k[keep & (t < half)]))
        second.append((p[keep & (t >= half)], k[keep & (t >= half)]))

    def curve(parts):
        return quasi_static_curve(
            np.concatenate([a for a, _ in parts]), np.concatenate([b for _, b in parts])
        )

    return curve(first), curve(second)


def physical_step(
    result, design, *, candidates: Sequence[str] | None = None, max_size: int = 2, tip_factor: float = 1.0
) -> dict:
    """The ``physical`` record: what produces the named terms, and the gap on held-out data.

    Parameters
    ----------
    result
        A time-series :class:`~softcath.studies.discrepancy.workflow.DiscrepancyResult`.
    design
        The built design.
    candidates, max_size, tip_factor
        As :func:`~softcath.studies.discrepancy.prototype.explain_prototype`.
    """
    delay = next((s["params"].get("delay_s", 0.0) for s in result.steps if s["effect"] == "delay"), 0.0)
    train, test = _halves(result, float(delay))
    p_max = float(max(train["pressure_MPa"].max(), test["pressure_MPa"].max()))
    bank = ModelBank(design, p_max=p_max)
    record = explain_prototype(
        design, train, candidates=candidates, max_size=max_size, tip_factor=tip_factor, bank=bank
    )
    by_name = {tuple(h["ingredients"]): h for h in record["hypotheses"]}
    chosen = record["equally_good"][0] if record["equally_good"] else record["best"]

    def held_out(ingredients) -> float:
        h = by_name[tuple(ingredients)]
        values = {n: v["value"] for n, v in h["parameters"].items()}
        k, _ = predict(bank, ingredients, values, test["pressure_MPa"], tip_factor)
        return nrmse(k, test["curvature_per_mm"])

    causes = {t: [c for c in TERM_CAUSES.get(t, ()) if c in chosen] for t in result.named}
    return {
        "named": record["named"],
        "explained": record["explained"],
        "chosen": list(chosen),
        "terms_produced_by": causes,
        "delay_removed_s": float(delay),
        "nrmse_before": held_out(()),
        "nrmse_after": held_out(chosen),
        "held_out": "the second half of every run in time (fitted on the first half)",
        "training_curve": {k: v.tolist() for k, v in train.items()},
        "held_out_curve": {k: v.tolist() for k, v in test.items()},
        "equally_good": record["equally_good"],
        "separating_measurement": record["separating_measurement"],
        "notes": record["notes"],
        "hypotheses": record["hypotheses"],
    }
