"""Seeded samples of the uncertain parameters: a Latin hypercube on the unit cube, mapped to values.

One seed decides everything random in a prediction: the unit sample here and
the bootstrap of the sensitivity indices.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from softcath.studies.predict.ranges import Range
from softcath.studies.sweep.sampling import latin_hypercube

__all__ = ["unit_sample", "sample_values", "split_overrides"]


def unit_sample(n: int, d: int, seed: int) -> np.ndarray:
    """``n`` Latin-hypercube points in [0, 1)^d (one point per stratum of every axis), seeded."""
    return latin_hypercube([(0.0, 1.0)] * d, n, seed)


def sample_values(unit: np.ndarray, ranges: list[Range]) -> list[dict[str, Any]]:
    """One ``{path: value}`` per row of ``unit`` (columns in ``ranges`` order)."""
    return [{r.path: r.value(float(u)) for r, u in zip(ranges, row, strict=True)} for row in unit]


def split_overrides(values: dict[str, Any]) -> tuple[dict[str, Any], dict[str, str]]:
    """(design path -> value, model option name -> level), e.g. ``{"coil_modulus": "bending"}``."""
    design, options = {}, {}
    for path, v in values.items():
        if path.startswith("model."):
            options[path.removeprefix("model.")] = v
        else:
            design[path] = v
    return design, options
