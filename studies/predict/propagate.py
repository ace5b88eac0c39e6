"""Push a sample of design variants through one model tier: gains κ/p and ε/p per variant.

Tiers: ``paper`` (the composite-beam formula, eq. 7, vectorised over the
sample with ``analytic.design_inputs`` / ``gains_arrays``), ``section`` (the
2-D generalised-plane-strain section model, ~0.25 s a variant; meshes are
reused while only materials move) and ``fem`` (the 3-D linear FEM,
``fem.check``, ~10 s a variant; Poisson ratios capped at 0.49 there).
Variants the design checks reject (an impossible joint combination of shape
parameters) are kept as NaN and counted, never silently replaced.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from softcath.design.errors import DesignError
from softcath.studies.predict.sampling import split_overrides

__all__ = ["TIERS", "TIER_OPTIONS", "DEFAULT_LOAD", "TierSample", "propagate"]

log = logging.getLogger(__name__)

#: The tiers (:mod:`softcath.studies.tiers`) a prediction band can be drawn for.
TIERS = ("paper", "section", "fem")
#: Model options each tier understands (``model.<name>`` ranges).
TIER_OPTIONS: dict[str, tuple[str, ...]] = {
    "paper": (),
    "section": ("coil_modulus", "coil_bending"),
    "fem": ("coil_modulus",),
}
#: The load each tier is about unless told: the paper's formula is a cap-load model.
DEFAULT_LOAD = {"paper": "cap", "section": "lumen", "fem": "lumen"}
#: Pressure of the linear FEM solve [MPa]; the gains are per MPa whatever it is.
_FEM_PRESSURE = 0.1


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
    from softcath.studies.sweep.variants import VariantBuilder

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
    tier: str, table: Mapping[str, Any], values: list[dict[str, Any]], *, load: str, progress: bool = False
) -> TierSample:
    """Gains of ``tier`` for every variant ``values`` (dotted path -> value) of the base ``table``."""
    if tier not in TIERS:
        raise DesignError("model", tier, f"must be one of {TIERS}")
    if load not in ("cap", "lumen"):
        raise DesignError("load", load, "must be cap or lumen")
    n = len(values)
    gain = np.full(n, np.nan)
    elong = np.full(n, np.nan)
    errors: list[str] = []
    if tier == "paper":
        _paper(table, values, load, gain, elong, errors)
    else:
        with _bar(n, tier, progress) as bar:
            for i, (d, options, err) in enumerate(_variants(table, values)):
                if d is None:
                    errors.append(err)
                else:
                    gain[i], elong[i] = _solve(tier, d, options, load)
                bar.update()
    feasible = np.isfinite(gain)
    if errors:
        log.info("%s: %d of %d variants infeasible, e.g. %s", tier, len(errors), n, errors[0])
    return TierSample(gain, elong, feasible, tuple(errors[:5]))


def _paper(table, values, load, gain, elong, errors) -> None:
    """The formula over the whole sample at once: one dict of input arrays."""
    from softcath.analytic import design_inputs_many, gains_arrays

    designs, idx = [], []
    for i, (d, _options, err) in enumerate(_variants(table, values)):
        if d is None:
            errors.append(err)
        else:
            designs.append(d)
            idx.append(i)
    if not designs:
        return
    inputs = design_inputs_many(designs)
    k, e = gains_arrays(inputs, load)
    gain[idx], elong[idx] = k, e


def _solve(tier: str, d, options: dict[str, str], load: str) -> tuple[float, float]:
    if tier == "section":
        from softcath.fem.section_model import section_model

        r = section_model(d, loads=(load,), **options)
        return r.curvature_per_mm_per_MPa[load], r.elongation_per_MPa[load]
    from softcath import fem

    r = fem.check(d, pressures=(_FEM_PRESSURE,), loads=(load,), **options)
    case = r.cases[0]
    return case.curvature_per_mm / _FEM_PRESSURE, case.elongation / _FEM_PRESSURE
