"""Push a sample of design variants through one model tier: gains κ/p and ε/p per variant.

The tiers are the linear ones of the registry (:func:`softcath.models.linear_names`: the
paper's formula, the section model, the 3-D linear FEM), whose responses are linear in
pressure: each variant's gains are its response at :data:`GAIN_PRESSURE` over that pressure.
Variants are answered through :meth:`softcath.models.Tier.responses`, grouped by their
model options (``model.<name>`` ranges): the formula vectorised over the sample, the
section model batched (meshes reused while only materials move), the 3-D FEM (~10 s a
variant; Poisson ratios capped at 0.49 there) one by one. Variants the design checks reject
(an impossible joint combination of shape parameters) are kept as NaN and counted, never
silently replaced.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from softcath.design.errors import DesignError
from softcath.models import LOADS, get, linear_names
from softcath.studies.predict.sampling import split_overrides
from softcath.studies.sweep.variants import VariantBuilder

__all__ = ["TIERS", "TIER_OPTIONS", "DEFAULT_LOAD", "GAIN_PRESSURE", "TierSample", "propagate"]

log = logging.getLogger(__name__)

#: The tiers (:mod:`softcath.models`) a prediction band can be drawn for: the linear ones.
TIERS = linear_names()
#: Model options each tier understands (``model.<name>`` ranges): :attr:`softcath.models.Tier.options`.
TIER_OPTIONS: dict[str, tuple[str, ...]] = {t: tuple(get(t).options) for t in TIERS}
#: The load each tier is about unless told (:attr:`softcath.models.Tier.default_load`).
DEFAULT_LOAD = {t: get(t).default_load for t in TIERS}
#: Pressure of the gain's response [MPa]: 1 MPa, so a response linear in p is its gain exactly.
GAIN_PRESSURE = 1.0


@dataclass(frozen=True)
class TierSample:
    """Gains of every variant of a sample (NaN where the variant is infeasible).

    Attributes
    ----------
    gain
        κ/p [1/(mm MPa)] per variant.
    elongation
        ε/p [1/MPa] per variant.
    feasible
        Which variants the design checks accepted.
    errors
        The first few rejection messages (for the report).
    """

    gain: np.ndarray
    elongation: np.ndarray
    feasible: np.ndarray
    errors: tuple[str, ...]


def _variants(table: Mapping[str, Any], values: list[dict[str, Any]]):
    """Yield (design or None, options, error) per sample row."""
    builder = VariantBuilder(table)
    for row in values:
        overrides, options = split_overrides(row)
        try:
            yield builder.build(overrides), options, None
        except DesignError as exc:
            yield None, options, str(exc)


def _bar(total: int, tier: str, progress: bool):
    from tqdm import tqdm

    return tqdm(total=total, desc=f"predict {tier}", unit="variant", leave=False, disable=not progress)


def propagate(
    tier: str,
    table: Mapping[str, Any],
    values: list[dict[str, Any]],
    *,
    load: str,
    progress: bool = False,
    options: Mapping[str, Any] | None = None,
) -> TierSample:
    """Gains of ``tier`` for every variant ``values`` (dotted path -> value) of the base ``table``.

    ``options`` are the tier's fixed options; a variant's sampled ``model.*`` values go over them.
    """
    model = get(tier, allowed=TIERS)
    fixed = dict(options or {})
    if load not in LOADS:
        raise DesignError("load", load, "must be cap or lumen")
    n = len(values)
    gain = np.full(n, np.nan)
    elong = np.full(n, np.nan)
    errors: list[str] = []
    groups: dict[tuple, list[tuple[int, Any]]] = {}
    for i, (d, sampled, err) in enumerate(_variants(table, values)):
        if err is not None:  # (no design: its error)
            errors.append(err)
        else:
            groups.setdefault(tuple(sorted(sampled.items())), []).append((i, d))
    with _bar(n, tier, progress) as bar:
        bar.update(len(errors))
        for group, members in groups.items():
            # a batched tier takes the group at once; the others one variant at a time (the bar moves)
            step = len(members) if model.batched else 1
            for start in range(0, len(members), step):
                part = members[start : start + step]
                batch = model.responses(
                    [d for _i, d in part], [GAIN_PRESSURE], loads=(load,), options={**fixed, **dict(group)}
                )[load]
                for j, (i, _d) in enumerate(part):
                    if j in batch.errors:
                        raise batch.errors[j]
                    gain[i] = batch.curvature_per_mm[j, 0] / GAIN_PRESSURE
                    elong[i] = batch.elongation[j, 0] / GAIN_PRESSURE
                bar.update(len(part))
    feasible = np.isfinite(gain)
    if errors:
        log.info("%s: %d of %d variants infeasible, e.g. %s", tier, len(errors), n, errors[0])
    return TierSample(gain, elong, feasible, tuple(errors[:5]))
