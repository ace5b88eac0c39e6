"""Expand a sweep specification into its list of design variants (full factorial × seeded LHS)."""

from __future__ import annotations

import itertools

import numpy as np

from softcath.studies.sweep.spec import SweepSpec

__all__ = ["expand", "latin_hypercube"]


def latin_hypercube(bounds: list[tuple[float, float]], n: int, seed: int) -> np.ndarray:
    """``n`` points of a seeded Latin hypercube scaled to ``bounds`` (shape ``(n, len(bounds))``).

    Every parameter's range is cut into ``n`` equal strata and each stratum
    holds exactly one point, at a uniform random position inside it (McKay,
    Beckman & Conover 1979); the strata are paired across parameters by
    independent random permutations. The same seed gives the same sample.
    """
    rng = np.random.default_rng(seed)
    d = len(bounds)
    strata = np.stack([rng.permutation(n) for _ in range(d)], axis=1) if d else np.zeros((n, 0))
    unit = (strata + rng.random((n, d))) / n
    low = np.array([b[0] for b in bounds], dtype=float)
    high = np.array([b[1] for b in bounds], dtype=float)
    return low + unit * (high - low)


def expand(spec: SweepSpec) -> list[dict[str, object]]:
    """The variants of ``spec``: one ``{dotted path: value}`` per design, in design-id order.

    Factorial parameters vary slowest (in file order), the Latin-hypercube
    sample fastest. A sweep with no parameters is the base design alone.
    """
    factorial = [p for p in spec.parameters if p.kind != "lhs"]
    sampled = [p for p in spec.parameters if p.kind == "lhs"]
    grid = list(itertools.product(*(p.values for p in factorial)))
    if sampled:
        points = latin_hypercube([p.bounds for p in sampled], spec.n_samples, spec.seed)
    else:
        points = np.zeros((1, 0))
    sampled_paths = [p.path for p in sampled]
    rows = points.tolist()
    out = []
    for combo in grid:
        fixed = {p.path: v for p, v in zip(factorial, combo, strict=True)}
        for row in rows:
            variant = dict(fixed)
            variant.update(zip(sampled_paths, row, strict=True))
            out.append(variant)
    return out
