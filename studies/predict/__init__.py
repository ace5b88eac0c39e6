"""Prediction bands: propagate parameter uncertainty through a model tier and place a measurement in them.

``softcath predict`` samples the uncertain parameters (dotted design paths as
in sweep specs, plus the coil-modulus choice of the FEM tiers) on a seeded
Latin hypercube, evaluates the paper's formula, the 2-D section model or the
3-D linear FEM for every variant, and reports the 5th/50th/95th percentiles
of κ/p and ε/p, where a measured gain falls among them, and first-order
RBD-FAST sensitivity indices. Default ranges, each with its source, ship as
``ranges_<preset>.toml``.

Modules: ``ranges`` (ranges, files, ``--vary``), ``sampling`` (seeded unit
sample → values), ``propagate`` (tiers), ``band`` (percentiles, measured
position), ``sensitivity`` (SALib RBD-FAST), ``tier`` (one tier's band),
``workflow`` (:func:`predict`), ``plot`` (the picture).
"""

from __future__ import annotations

from softcath.studies.predict.propagate import DEFAULT_LOAD, TIERS
from softcath.studies.predict.ranges import Range, load_ranges, parse_vary
from softcath.studies.predict.tier import TierPrediction, predict_tier
from softcath.studies.predict.workflow import DEFAULT_SAMPLES, predict, resolve_ranges

__all__ = [
    "DEFAULT_LOAD",
    "DEFAULT_SAMPLES",
    "TIERS",
    "Range",
    "TierPrediction",
    "load_ranges",
    "parse_vary",
    "predict",
    "predict_tier",
    "resolve_ranges",
]
