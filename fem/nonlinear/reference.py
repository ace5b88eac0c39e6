"""The 3-D bend with its discretisation error stated: :func:`reference_curve`.

A solve on ``layers`` element layers and a second on half as many give, per
pressure, the Richardson estimate of the fine solve's relative error in the
mid-span curvature (:func:`~softcath.fem.nonlinear.convergence.richardson_error`),
with the order of convergence assumed (:data:`~softcath.fem.nonlinear.convergence.ASSUMED_ORDER`)
or, from a three-mesh study (:mod:`softcath.fem.nonlinear.study`), observed.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from softcath.fem.nonlinear.convergence import (
    ASSUMED_ORDER,
    MIN_ESTIMATE_LAYERS,
    coarse_layers,
    richardson_error,
)

log = logging.getLogger(__name__)

__all__ = ["ErrorEstimate", "ReferenceCurve", "estimate_error", "reference_curve", "QUANTITY"]

#: The quantity whose error is estimated (a ``BendCurve`` attribute and its output name).
QUANTITY = ("curvature_mid", "curvature_mid_per_mm")


@dataclass(frozen=True)
class ErrorEstimate:
    """Estimated relative discretisation error of a 3-D bend, per pressure.

    Attributes
    ----------
    quantity
        Output name of the quantity estimated (the mid-span curvature).
    relative
        |error| / |value| per pressure of the fine solve [-] (NaN where undefined).
    extrapolated
        The Richardson-extrapolated value per pressure (infinitely many layers).
    layers, coarse_layers
        Element layers of the solve and of the companion solve.
    order
        Order of convergence in 1/layers used.
    order_source
        ``"assumed"`` or ``"observed"`` (three-mesh study).
    """

    quantity: str
    relative: np.ndarray
    extrapolated: np.ndarray
    layers: int
    coarse_layers: int
    order: float
    order_source: str

    @property
    def method(self) -> str:
        """One line saying how the estimate was made."""
        return (
            f"Richardson from a second solve on {self.coarse_layers} instead of {self.layers} layers "
            f"along the bending length, order {self.order:.3g} in 1/layers ({self.order_source}): "
            f"|f_{self.layers} - f_{self.coarse_layers}| / ((layers ratio)^order - 1) / |f_{self.layers}|"
        )

    def to_json(self) -> dict:
        """A JSON-ready dict (NaN as null)."""
        return {
            "quantity": self.quantity,
            "relative": [_none(x) for x in self.relative],
            "extrapolated": [_none(x) for x in self.extrapolated],
            "layers": self.layers,
            "coarse_layers": self.coarse_layers,
            "order": self.order,
            "order_source": self.order_source,
            "method": self.method,
        }


@dataclass(frozen=True)
class ReferenceCurve:
    """A 3-D bend curve, its half-layer companion and the error estimate from the two (both None
    below :data:`~softcath.fem.nonlinear.convergence.MIN_ESTIMATE_LAYERS` layers: no half-layer mesh)."""

    curve: object
    coarse: object | None = field(repr=False)
    error: ErrorEstimate | None


def _none(x) -> float | None:
    x = float(x)
    return x if np.isfinite(x) else None


def estimate_error(
    curve, coarse, *, order: float = ASSUMED_ORDER, order_source: str = "assumed"
) -> ErrorEstimate:
    """The :class:`ErrorEstimate` of ``curve`` from ``coarse``, both :class:`~fem.nonlinear.bend.BendCurve`
    with ``layers`` set, at the same pressures."""
    from softcath.fem.nonlinear.errors import SettingError

    if curve.layers is None or coarse.layers is None:
        raise SettingError("layers", None, "both curves need their layer counts (meshed by bend_curve)")
    if not np.array_equal(curve.pressure, coarse.pressure):
        raise SettingError("pressure", coarse.pressure.tolist(), f"must equal {curve.pressure.tolist()}")
    attr, name = QUANTITY
    fine, crude = np.asarray(getattr(curve, attr)), np.asarray(getattr(coarse, attr))
    rel = richardson_error(fine, crude, layers=curve.layers, coarse_layers=coarse.layers, order=order)
    r = curve.layers / coarse.layers
    return ErrorEstimate(
        quantity=name,
        relative=rel,
        extrapolated=fine + (fine - crude) / (r**order - 1.0),
        layers=int(curve.layers),
        coarse_layers=int(coarse.layers),
        order=float(order),
        order_source=order_source,
    )


def reference_curve(design, pressures, *, layers: int | None = None, **options) -> ReferenceCurve:
    """The 3-D bend of ``design`` (:func:`~softcath.fem.nonlinear.bend.bend_curve`) with its error stated.

    Parameters
    ----------
    design, pressures
        As :func:`~softcath.fem.nonlinear.bend.bend_curve`.
    layers
        Element layers (default: :func:`~softcath.fem.nonlinear.convergence.default_layers`);
        the companion solve has :func:`~softcath.fem.nonlinear.convergence.coarse_layers`.
    **options
        Further keyword options of ``bend_curve`` (not ``mesh``: the layers must be known).
    """
    from softcath.fem.nonlinear.bend import bend_curve

    curve = bend_curve(design, pressures, layers=layers, **options)
    if curve.layers < MIN_ESTIMATE_LAYERS:
        log.info("%d layers: no half-layer mesh, no error estimate", curve.layers)
        return ReferenceCurve(curve=curve, coarse=None, error=None)
    coarse = bend_curve(design, pressures, layers=coarse_layers(curve.layers), **options)
    return ReferenceCurve(curve=curve, coarse=coarse, error=estimate_error(curve, coarse))
