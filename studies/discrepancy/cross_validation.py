"""Held-out scores of candidate models: the cross-validation every naming step decides on."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from softcath.analytic.effects.fit import ChainFit, Segment, fit_chain, predict_chain
from softcath.design.errors import DataError
from softcath.studies.discrepancy.prepare import Prepared

__all__ = ["CVScore", "Step", "cross_validate", "fit_all"]


@dataclass(frozen=True)
class CVScore:
    """Held-out score of one model (baseline + effects)."""

    effects: tuple[str, ...]
    rmse_per_mm: float
    nrmse: float
    fold_rmse: tuple[float, ...]
    fit: ChainFit  # fitted on all the data
    pruned: bool = False


@dataclass(frozen=True)
class Step:
    """One naming step: the candidates' scores and the decision."""

    baseline: CVScore
    candidates: dict[str, CVScore]
    named: str | None
    ambiguous_with: tuple[str, ...]
    separating_experiment: str
    fit: ChainFit | None = None  # the named model fitted on all data
    extra: dict = field(default_factory=dict)


def _folds(prep: Prepared, n_blocks: int = 3) -> list[tuple[list[Segment], list[Segment]]]:
    """(train, test) segment lists; masks select the samples of each side."""
    segs = prep.segments
    if prep.static:
        # interleaved: every third point of every run held out, so no fold extrapolates
        # in pressure
        out = []
        for k in range(3):
            train = [replace(s, mask=np.arange(s.target.size) % 3 != k) for s in segs]
            test = [replace(s, mask=np.arange(s.target.size) % 3 == k) for s in segs]
            out.append((train, test))
        return out
    if len(segs) >= 2:
        out = []
        for i in range(len(segs)):
            train = [s for j, s in enumerate(segs) if j != i]
            out.append((train, [segs[i]]))
        return out
    if not segs:
        raise DataError("cross-validation: no data segments to hold out")
    s = segs[0]
    idx = np.flatnonzero(s.mask)
    blocks = np.array_split(idx, n_blocks)
    out = []
    for b in blocks:
        test_mask = np.zeros_like(s.mask)
        test_mask[b] = True
        # a guard of one filter settling time around the held-out block keeps the
        # training samples from seeing it through the zero-phase filter
        guard = int(round(prep.fs_hz / prep.data_filter.passband_hz))
        train_mask = s.mask.copy()
        train_mask[max(b[0] - guard, 0) : b[-1] + guard + 1] = False
        out.append(([replace(s, mask=train_mask)], [replace(s, mask=test_mask)]))
    return out


def _n_eff(prep: Prepared, segments: Sequence[Segment]) -> float:
    # independent samples of a signal band-limited to B: about 2 B per second
    n = sum(int(s.mask.sum()) for s in segments)
    if prep.static:
        return float(n)
    return n * 2 * prep.data_filter.passband_hz / prep.fs_hz


def cross_validate(
    prep: Prepared,
    effects: Sequence[str],
    *,
    fixed_gain: float | None = None,
    context: dict | None = None,
    start: dict | None = None,
    prune_above: float | None = None,
) -> CVScore:
    """Held-out RMSE of baseline + ``effects`` over the folds of ``prep``.

    The model is first fitted on all the data (start-grid scan + local
    refinement); each fold's fit then starts from that estimate and is refined
    on the fold's training data only. Only the choice of basin sees the held-out
    data; every score is of a model whose parameters were fitted without it.

    ``prune_above``: skip the folds when the all-data (in-sample) RMSE is above
    this value: a candidate that does not even fit the data it was trained on
    well enough cannot clear the margin held out (held-out errors are the larger).
    The score is then NaN and ``pruned`` is set.
    """
    filt = prep.output_filter()
    full = fit_all(prep, effects, fixed_gain=fixed_gain, context=context, start=start)
    if prune_above is not None and full.rmse > prune_above:
        return CVScore(
            effects=tuple(effects),
            rmse_per_mm=float("nan"),
            nrmse=float("nan"),
            fold_rmse=(),
            fit=full,
            pruned=True,
        )
    res, fold = [], []
    for train, test in _folds(prep):
        # warm start: a short local refinement from the all-data estimate
        fit = fit_chain(
            effects,
            train,
            output_filter=filt,
            scales=prep.scales,
            fixed_gain=fixed_gain,
            context=context,
            start=full.params,
            max_nfev=20,
        )
        r = []
        for s in test:
            r.append((s.target - predict_chain(fit, s, output_filter=filt))[s.mask])
        r = np.concatenate(r)
        res.append(r)
        fold.append(float(np.sqrt(np.mean(r**2))))
    allr = np.concatenate(res)
    rmse = float(np.sqrt(np.mean(allr**2)))
    return CVScore(
        effects=tuple(effects),
        rmse_per_mm=rmse,
        nrmse=rmse / prep.full_scale_per_mm,
        fold_rmse=tuple(fold),
        fit=full,
    )


def fit_all(prep: Prepared, effects: Sequence[str], **kw) -> ChainFit:
    """Fit baseline + ``effects`` on all the data (for the reported estimates)."""
    return fit_chain(
        effects,
        prep.segments,
        output_filter=prep.output_filter(),
        scales=prep.scales,
        n_eff=_n_eff(prep, prep.segments),
        **kw,
    )
