"""The measurement noise of a measured curve, from the data themselves.

Never from the misfit of a model: a model that cannot follow the curve would
otherwise widen its own yardstick until it "fits". Two estimates, in order:

- **repeat points**: points measured more than once at the same pressure give
  the pooled within-pressure variance;
- **scatter about a smooth fit**: otherwise, a polynomial in pressure whose
  degree (1 to 4) is chosen by leave-one-out cross-validation, and the
  variance of the points about it with its degrees of freedom.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["NoiseEstimate", "data_noise"]

#: Smallest noise, relative to the largest |value|: a perfect curve still has round-off.
FLOOR = 1e-3


@dataclass(frozen=True)
class NoiseEstimate:
    """Standard deviation of one measured point, its degrees of freedom and how it was estimated."""

    sigma: float
    dof: int
    method: str

    def to_json(self) -> dict:
        """Plain-JSON record."""
        return {"sigma": self.sigma, "dof": self.dof, "method": self.method}


def _repeats(p: np.ndarray, y: np.ndarray) -> NoiseEstimate | None:
    """Pooled variance of the points that share a pressure (None when none repeats)."""
    _, inverse, counts = np.unique(np.round(p, 9), return_inverse=True, return_counts=True)
    if not np.any(counts > 1):
        return None
    means = np.bincount(inverse, weights=y) / counts
    ss = float(np.sum((y - means[inverse]) ** 2))
    dof = int(np.sum(counts - 1))
    return NoiseEstimate(sigma=float(np.sqrt(ss / dof)), dof=dof, method=f"repeat points ({dof} dof)")


def _loo_error(p: np.ndarray, y: np.ndarray, degree: int) -> float:
    """Leave-one-out squared prediction error of a polynomial of ``degree`` (hat-matrix identity)."""
    x = (p - p.mean()) / (np.ptp(p) or 1.0)
    v = np.vander(x, degree + 1)
    q, _ = np.linalg.qr(v)
    h = np.sum(q**2, axis=1)
    r = y - q @ (q.T @ y)
    if np.any(h > 1 - 1e-9):
        return float("inf")
    return float(np.mean((r / (1 - h)) ** 2))


def data_noise(pressure, values) -> NoiseEstimate:
    """The noise of one measured point of ``values`` against ``pressure``.

    Parameters
    ----------
    pressure, values
        The measured points (at least 4).

    Returns
    -------
    NoiseEstimate
        From repeat points if any pressure repeats, else the scatter about the
        smooth polynomial chosen by leave-one-out cross-validation.

    Examples
    --------
    >>> import numpy as np
    >>> p = np.linspace(0.1, 0.5, 13)
    >>> y = 0.1 * p + 0.5 * p**2 + 0.002 * np.random.default_rng(0).standard_normal(13)
    >>> n = data_noise(p, y)
    >>> n.method
    'scatter about a degree-2 polynomial chosen by leave-one-out (10 dof)'
    >>> round(n.sigma, 4)  # the sample's own scatter; 0.002 drawn
    0.0015
    """
    p = np.asarray(pressure, float)
    y = np.asarray(values, float)
    floor = FLOOR * float(np.max(np.abs(y)) or 1.0)
    rep = _repeats(p, y)
    if rep is not None:
        return NoiseEstimate(sigma=max(rep.sigma, floor), dof=rep.dof, method=rep.method)
    degrees = [d for d in range(1, 5) if p.size - d - 1 >= 2]
    if not degrees:
        return NoiseEstimate(sigma=floor, dof=0, method="too few points: the round-off floor")
    best = min(degrees, key=lambda d: _loo_error(p, y, d))
    x = (p - p.mean()) / (np.ptp(p) or 1.0)
    coef = np.polyfit(x, y, best)
    r = y - np.polyval(coef, x)
    dof = int(p.size - best - 1)
    sigma = float(np.sqrt(r @ r / dof))
    return NoiseEstimate(
        sigma=max(sigma, floor),
        dof=dof,
        method=f"scatter about a degree-{best} polynomial chosen by leave-one-out ({dof} dof)",
    )
