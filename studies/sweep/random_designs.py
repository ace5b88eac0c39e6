"""Seeded random valid designs around a base design (verification and benchmarks).

>>> from softcath.studies.sweep.random_designs import random_designs
>>> [d.name for d in random_designs(2, seed=1)]
['random 0', 'random 1']
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from softcath import design
from softcath.studies.sweep.spec import _base_table
from softcath.studies.sweep.variants import build_variant

__all__ = ["DEFAULT_RANGES", "random_designs"]

#: Uniform ranges (dotted design path -> (low, high)) around the paper design: outer coil
#: and channel size, lumen shape, silicone moduli and tip length, all in mm and MPa. Chosen
#: so that every draw is a valid design (measured 600/600): a wider lumen height or a larger
#: channel in a small coil leaves no room for the squeezed tube's wall (30 % invalid).
DEFAULT_RANGES: Mapping[str, tuple[float, float]] = {
    "coil.outer_diameter": (0.78, 0.9),
    "channel.outer_diameter": (0.25, 0.30),
    "tube.a_int": (0.06, 0.13),
    "tube.b_int": (0.05, 0.08),
    "materials.medical_silicone_tubing.youngs_modulus": (1.0, 3.0),
    "materials.ecoflex_00_30.youngs_modulus": (0.05, 0.3),
    "tip.bending_length": (4.0, 8.0),
}


def random_designs(
    n: int, *, seed: int, base: str = "paper", ranges: Mapping[str, tuple[float, float]] = DEFAULT_RANGES
) -> list:
    """``n`` valid designs: each path drawn uniformly in its range, invalid draws skipped.

    Every draw is validated exactly as a sweep validates its designs
    (:func:`softcath.studies.sweep.variants.build_variant`).
    """
    from pathlib import Path

    table = _base_table(base, Path("."))  # the TOML as written, so dotted paths match a sweep spec's
    rng = np.random.default_rng(seed)
    out: list = []
    tries = 0
    while len(out) < n:
        tries += 1
        if tries > 100 * max(n, 1):
            raise design.DesignError("ranges", dict(ranges), f"fewer than {n} valid designs in {tries} draws")
        over = {path: float(rng.uniform(lo, hi)) for path, (lo, hi) in ranges.items()}
        try:
            out.append(build_variant(table, over, name=f"random {len(out)}"))
        except design.DesignError:
            continue
    return out
