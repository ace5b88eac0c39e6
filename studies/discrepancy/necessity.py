"""Name an effect only when it is needed: the backward check after forward naming.

Forward naming adds the best candidate while it beats the current model by the
margin; an effect named early can become redundant once a later one is in (a
small hysteresis first fitted as an ``offset`` plus a ``nonlinear_gain`` bend of
the static curve, then the hysteresis itself). The backward check asks the same
question of every named effect in the final model, with the forward rule's two
parts: is the model with it better held out, by the margin, than the model
without it, and does it remove at least ``min_share`` of the original excess
error power above the noise floor? If not, it is dropped (the latest first) and
the reduced model becomes the final one.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

from softcath.studies.discrepancy.cross_validation import Step, cross_validate
from softcath.studies.discrepancy.prepare import Prepared

__all__ = ["drop_unneeded"]

log = logging.getLogger(__name__)


def drop_unneeded(
    prep: Prepared, steps: Sequence, *, margin: float, min_share: float, fixed_gain=None, context=None
) -> list:
    """``steps`` without the named effects the final model does not need (held out, by the rule).

    The returned list keeps the needed naming steps and ends with a stop step whose
    baseline is the reduced model and whose ``extra["not_needed"]`` lists the dropped effects.
    """

    named = [s.named for s in steps if s.named]
    if len(named) < 2:
        return list(steps)
    last = steps[-1]
    final = last.baseline if last.named is None else last.candidates[last.named]
    excess0 = max(steps[0].baseline.rmse_per_mm ** 2 - prep.noise_floor_per_mm**2, 1e-300)
    dropped: list[str] = []
    for effect in reversed(named):
        keep = [n for n in named if n != effect and n not in dropped]
        if not keep:
            break
        without = cross_validate(prep, keep, fixed_gain=fixed_gain, context=context)
        share = (without.rmse_per_mm**2 - final.rmse_per_mm**2) / excess0
        if final.rmse_per_mm > (1 - margin) * without.rmse_per_mm or share < min_share:
            log.info(
                "not needed: %s (held-out %.4g with, %.4g without)",
                effect,
                final.rmse_per_mm,
                without.rmse_per_mm,
            )
            dropped.append(effect)
            final = without
    if not dropped:
        return list(steps)
    kept = [s for s in steps if s.named and s.named not in dropped]
    stop = Step(
        baseline=final,
        candidates={},
        named=None,
        ambiguous_with=(),
        separating_experiment="",
        extra={"not_needed": dropped},
    )
    return [*kept, stop]
