"""The shape every candidate effect shares: bounded physical parameters and an operator.

A candidate is a named, physically meaningful augmentation of the analytic
model. It acts at one place in a fixed signal chain (the same order as the
truth plant in ``softcath.virtualbench.plant``, so chains compose the same way)::

    p -> lag -> dead_zone -> nonlinear_gain -> hysteresis -> viscoelastic -> x
    curvature = gain * x  [+ offset]  [+ lumen term]  -> delay -> measured

``kind`` says how it enters: ``"pressure"`` maps the effective pressure x
(MPa -> MPa), ``"column"`` adds a term with a free linear coefficient to the
curvature, ``"output"`` maps the curvature time series (a shift in time).

Parameter bounds are stated relative to the data's scales (pressure full
scale P in MPa, longest run duration T in s) so that one library serves any
operating range; :meth:`Param.bounds` turns them into absolute bounds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Param", "Scales", "Candidate", "STAGE_ORDER"]

STAGE_ORDER: tuple[str, ...] = (
    "lag",
    "dead_zone",
    "nonlinear_gain",
    "hysteresis",
    "viscoelastic",
    "offset",
    "lumen_wall",
    "delay",
)


@dataclass(frozen=True)
class Scales:
    """Scales of the data set the bounds refer to.

    Parameters
    ----------
    pressure_MPa
        Pressure full scale P (MPa), e.g. the peak-to-peak pressure of the data.
    duration_s
        Longest run duration T (s).
    """

    pressure_MPa: float
    duration_s: float


@dataclass(frozen=True)
class Param:
    """One bounded physical parameter of a candidate.

    Parameters
    ----------
    name, unit, doc
        Name (with its unit suffix), unit string, one-line meaning.
    lower, upper
        Bounds, in units of ``relative_to`` (``"pressure"``: times P MPa,
        ``"inverse_pressure"``: divided by P, ``"time"``: times T s,
        ``"absolute"``: as given).
    log
        Search on a logarithmic scale (positive time constants).
    upper_cap
        Absolute cap on the upper bound (e.g. a delay of at most 2 s).
    """

    name: str
    unit: str
    lower: float
    upper: float
    doc: str
    relative_to: str = "absolute"
    log: bool = False
    upper_cap: float = float("inf")

    def bounds(self, scales: Scales) -> tuple[float, float]:
        """Absolute (lower, upper) bounds for data with these ``scales``."""
        f = {
            "pressure": scales.pressure_MPa,
            "inverse_pressure": 1.0 / scales.pressure_MPa,
            "time": scales.duration_s,
            "absolute": 1.0,
        }[self.relative_to]
        return self.lower * f, min(self.upper * f, self.upper_cap)

    def to_value(self, z: float, scales: Scales) -> float:
        """Map the unit search coordinate z in [0, 1] to a parameter value."""
        lo, hi = self.bounds(scales)
        if self.log:
            return float(np.exp(np.log(lo) + z * (np.log(hi) - np.log(lo))))
        return float(lo + z * (hi - lo))

    def to_unit(self, value: float, scales: Scales) -> float:
        """Inverse of :meth:`to_value`, clipped into [0, 1]."""
        lo, hi = self.bounds(scales)
        if self.log:
            z = (np.log(max(value, lo)) - np.log(lo)) / (np.log(hi) - np.log(lo))
        else:
            z = (value - lo) / (hi - lo)
        return float(np.clip(z, 0.0, 1.0))


class Candidate:
    """Base class of a candidate effect (subclass per module, one instance registered).

    Subclasses set ``name``, ``kind``, ``params``, ``meaning`` and implement
    :meth:`apply` (``kind`` ``"pressure"`` or ``"output"``) or :meth:`column`
    (``kind`` ``"column"``).
    """

    name: str = ""
    kind: str = "pressure"
    params: tuple[Param, ...] = ()
    meaning: str = ""
    #: the unit search coordinates tried as starting points for each parameter
    starts: tuple[float, ...] = (0.2, 0.6)
    #: name of the linear coefficient for ``"column"`` effects, with unit
    coefficient: str = ""

    @property
    def stage(self) -> int:
        return STAGE_ORDER.index(self.name)

    def apply(self, dt_s: float, x: np.ndarray, **params: float) -> np.ndarray:
        """Transform a uniformly sampled series (pressure or output kind)."""
        raise NotImplementedError

    def column(self, dt_s: float, p: np.ndarray, **context: float) -> np.ndarray:
        """The regressor added to the curvature (column kind), before its coefficient."""
        raise NotImplementedError

    def describe(self) -> dict[str, object]:
        """Name, meaning and parameter table, for reports."""
        return {
            "name": self.name,
            "meaning": self.meaning,
            "params": [
                {
                    "name": q.name,
                    "unit": q.unit,
                    "doc": q.doc,
                    "lower": q.lower,
                    "upper": q.upper,
                    "relative_to": q.relative_to,
                }
                for q in self.params
            ],
        }


def first_order(dt_s: float, u: np.ndarray, tau_s: float) -> np.ndarray:
    """First-order low-pass ``tau z' = u - z`` of a uniformly sampled series, started at rest.

    Exact for an input that is linear between samples (first-order hold), so the
    result does not depend on the sample rate.
    """
    from scipy import signal

    if tau_s <= 0:
        return np.array(u, dtype=float)
    a = float(np.exp(-dt_s / tau_s))
    c = tau_s * (1 - a) / dt_s
    b = np.array([1 - c, c - a])
    den = np.array([1.0, -a])
    zi = signal.lfiltic(b, den, y=[u[0]], x=[u[0]])
    z, _ = signal.lfilter(b, den, u, zi=zi)
    return z
