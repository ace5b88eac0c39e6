"""The 3-D bend with its discretisation error stated: :func:`reference_curve`.

A solve on ``layers`` element layers and a second on half as many give, per
pressure, the Richardson estimate of the fine solve's relative error in the
mid-span curvature (:func:`~softcath.fem.nonlinear.convergence.richardson_error`),
with the order of convergence assumed (:data:`~softcath.fem.nonlinear.convergence.ASSUMED_ORDER`)
or, from a three-mesh study (:mod:`softcath.fem.nonlinear.study`), observed; and
the tip's angle extrapolated from the same two solves (:func:`estimate_tip`:
the bend rate and the end-zone deficit each with its own order).

The stated error (:class:`StatedError`, ``discretisation_error_estimate`` of ``fem.json``) is that
layers part plus the cross-section part of two small-load solves
(:func:`~softcath.fem.nonlinear.section_error.section_error`), summed.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from softcath.fem.nonlinear.bend import NonlinearFemCurve, bend_curve
from softcath.fem.nonlinear.convergence import (
    ASSUMED_ORDER,
    MIN_ESTIMATE_LAYERS,
    coarse_layers,
    richardson_error,
)
from softcath.fem.nonlinear.errors import SettingError
from softcath.fem.nonlinear.section_error import (
    SectionError,
    combined_error,
    section_error,
    small_pressure,
)

log = logging.getLogger(__name__)

__all__ = [
    "ErrorEstimate",
    "StatedError",
    "TipEstimate",
    "ReferenceCurve",
    "estimate_error",
    "estimate_section",
    "estimate_tip",
    "reference_curve",
    "QUANTITY",
    "DEFICIT_ORDER",
]

#: The quantity whose error is estimated (a ``NonlinearFemCurve`` attribute and its output name).
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


#: Order in 1/layers of the end-zone deficit L − θ_tip / (dθ/dZ)_mid. Observed on the paper's design,
#: lumen load, 8/12/16 layers: 0.75, 0.84, 0.93, 0.96 at 0.1-0.4 MPa (docs/nonlinear.md).
DEFICIT_ORDER = 1.0


@dataclass(frozen=True)
class TipEstimate:
    """The tip's angle (end-section rotation) extrapolated in the layers, and the fine solve's error.

    The tip angle is the mid-span bend rate times L − δ, δ the end-zone deficit. The two converge
    differently in the layers: the bend rate with the mid-span curvature's order
    (:data:`~softcath.fem.nonlinear.convergence.ASSUMED_ORDER`), the deficit at first order
    (:data:`DEFICIT_ORDER`; the plug's and the clamp's corners). Each is extrapolated with its own
    order and the tip angle rebuilt from the two.

    Attributes
    ----------
    angle
        The fine solve's tip angle per pressure [rad].
    extrapolated
        The extrapolated tip angle per pressure [rad].
    relative
        |angle − extrapolated| / |extrapolated| per pressure [-].
    deficit
        The extrapolated end-zone deficit δ per pressure [mm].
    layers, coarse_layers
        Element layers of the two solves.
    """

    angle: np.ndarray
    extrapolated: np.ndarray
    relative: np.ndarray
    deficit: np.ndarray
    layers: int
    coarse_layers: int

    @property
    def method(self) -> str:
        """One line saying how the estimate was made."""
        return (
            f"tip angle = bend rate x (L - deficit) from {self.layers} and {self.coarse_layers} layers: "
            f"the mid-span bend rate extrapolated with order {ASSUMED_ORDER:g} (assumed), the end-zone "
            f"deficit L - angle / bend rate with order {DEFICIT_ORDER:g} (observed ~1)"
        )

    def to_json(self) -> dict:
        """A JSON-ready dict (NaN as null)."""
        return {
            "bend_angle_rad": [_none(x) for x in self.angle],
            "extrapolated_rad": [_none(x) for x in self.extrapolated],
            "relative": [_none(x) for x in self.relative],
            "deficit_mm": [_none(x) for x in self.deficit],
            "layers": self.layers,
            "coarse_layers": self.coarse_layers,
            "method": self.method,
        }


@dataclass(frozen=True)
class StatedError:
    """The stated discretisation error of the mid-span curvature: the layers part plus the section part.

    Reads as an :class:`ErrorEstimate` (a superset): ``relative`` and ``extrapolated`` are the
    combined ones; ``layers``, ``coarse_layers``, ``order`` and ``order_source`` are the layers
    part's.

    Attributes
    ----------
    layers_part
        The half-layer Richardson estimate, per pressure.
    section_part
        The section estimate (one relative error applied at every pressure), or None.
    """

    layers_part: ErrorEstimate
    section_part: SectionError | None = None

    @property
    def quantity(self) -> str:
        """Output name of the quantity estimated."""
        return self.layers_part.quantity

    @property
    def layers(self) -> int:
        """Element layers of the run (the layers part's fine mesh)."""
        return self.layers_part.layers

    @property
    def coarse_layers(self) -> int:
        """Element layers of the half-layer companion."""
        return self.layers_part.coarse_layers

    @property
    def order(self) -> float:
        """The layers part's order of convergence in 1/layers."""
        return self.layers_part.order

    @property
    def order_source(self) -> str:
        """The layers part's ``"assumed"`` or ``"observed"``."""
        return self.layers_part.order_source

    @property
    def relative(self) -> np.ndarray:
        """Layers part + section part per pressure [-] (:func:`~.section_error.combined_error`)."""
        sec = np.nan if self.section_part is None else self.section_part.relative
        return combined_error(self.layers_part.relative, sec)

    @property
    def extrapolated(self) -> np.ndarray:
        """The mid-span curvature extrapolated to infinitely many layers and corrected for the section:
        the layers part's extrapolation × (1 + the section's signed relative correction)."""
        if self.section_part is None or not np.isfinite(self.section_part.correction):
            return self.layers_part.extrapolated
        return self.layers_part.extrapolated * (1.0 + self.section_part.correction)

    @property
    def method(self) -> str:
        """One line saying how the estimate was made."""
        if self.section_part is None:
            return f"layers part only (no section estimate): {self.layers_part.method}"
        return (
            "layers part + section part, summed (conservative: both are magnitudes); extrapolated = "
            "the layers extrapolation x (1 + the section correction). Layers: "
            f"{self.layers_part.method}. Section: {self.section_part.method}"
        )

    def to_json(self) -> dict:
        """``ErrorEstimate.to_json`` with the combined values and ``parts``: ``layers`` and ``section``."""
        return {
            **self.layers_part.to_json(),
            "relative": [_none(x) for x in self.relative],
            "extrapolated": [_none(x) for x in self.extrapolated],
            "method": self.method,
            "parts": {
                "layers": self.layers_part.to_json(),
                "section": None if self.section_part is None else self.section_part.to_json(),
            },
        }


@dataclass(frozen=True)
class ReferenceCurve:
    """A 3-D bend curve, its half-layer companion and the error estimates from the two (None below
    :data:`~softcath.fem.nonlinear.convergence.MIN_ESTIMATE_LAYERS` layers: no half-layer mesh):
    ``error`` of the mid-span curvature in the layers, ``tip`` of the tip's angle, ``section`` the
    cross-section part (None when not asked for) and :attr:`stated` the two combined."""

    curve: NonlinearFemCurve
    coarse: NonlinearFemCurve | None = field(repr=False)
    error: ErrorEstimate | None
    tip: TipEstimate | None = None
    section: SectionError | None = None

    @property
    def stated(self) -> StatedError | None:
        """The stated error (layers + section part), None without a layers part."""
        return None if self.error is None else StatedError(self.error, self.section)


def _none(x) -> float | None:
    x = float(x)
    return x if np.isfinite(x) else None


def estimate_error(
    curve, coarse, *, order: float = ASSUMED_ORDER, order_source: str = "assumed"
) -> ErrorEstimate:
    """The :class:`ErrorEstimate` of ``curve`` from ``coarse`` (two ``NonlinearFemCurve`` records).

    Both need ``layers`` set and the same pressures.
    """

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


def estimate_tip(curve, coarse, *, length: float) -> TipEstimate:
    """The :class:`TipEstimate` of ``curve`` from ``coarse`` (both with ``layers`` set, same pressures),
    for a bending length ``length`` [mm]."""

    if curve.layers is None or coarse.layers is None or not coarse.layers < curve.layers:
        raise SettingError("layers", (curve.layers, coarse.layers), "must be known, coarse < fine")
    if not np.array_equal(curve.pressure, coarse.pressure):
        raise SettingError("pressure", coarse.pressure.tolist(), f"must equal {curve.pressure.tolist()}")
    r = curve.layers / coarse.layers
    rate_f, rate_c = np.asarray(curve.bend_rate_mid, float), np.asarray(coarse.bend_rate_mid, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        deficit_f = length - np.asarray(curve.bend_angle, float) / rate_f
        deficit_c = length - np.asarray(coarse.bend_angle, float) / rate_c
        rate = rate_f + (rate_f - rate_c) / (r**ASSUMED_ORDER - 1.0)
        deficit = deficit_f + (deficit_f - deficit_c) / (r**DEFICIT_ORDER - 1.0)
        tip = rate * (length - deficit)
        rel = np.abs(np.asarray(curve.bend_angle, float) - tip) / np.abs(tip)
    return TipEstimate(
        angle=np.asarray(curve.bend_angle, float),
        extrapolated=tip,
        relative=np.where(np.isfinite(rel), rel, np.nan),
        deficit=deficit,
        layers=int(curve.layers),
        coarse_layers=int(coarse.layers),
    )


def reference_curve(
    design, pressures, *, layers: int | None = None, section: bool = True, **options
) -> ReferenceCurve:
    """The 3-D bend of ``design`` (:func:`~softcath.fem.nonlinear.bend.bend_curve`) with its error stated.

    Parameters
    ----------
    design, pressures
        As :func:`~softcath.fem.nonlinear.bend.bend_curve`.
    layers
        Element layers (default: :func:`~softcath.fem.nonlinear.convergence.default_layers`);
        the companion solve has :func:`~softcath.fem.nonlinear.convergence.coarse_layers`.
    section
        Also estimate the cross-section part
        (:func:`~softcath.fem.nonlinear.section_error.section_error`: two small-load solves).
    **options
        Further keyword options of ``bend_curve`` (not ``mesh``: the layers must be known).
    """

    curve = bend_curve(design, pressures, layers=layers, **options)
    if curve.layers is None:
        raise SettingError("mesh", "given", "the reference curve meshes its own layers")
    if curve.layers < MIN_ESTIMATE_LAYERS:
        log.info("%d layers: no half-layer mesh, no error estimate", curve.layers)
        return ReferenceCurve(curve=curve, coarse=None, error=None)
    coarse = bend_curve(design, pressures, layers=coarse_layers(curve.layers), **options)
    tip = estimate_tip(curve, coarse, length=float(design.tip.bending_length))
    sec = estimate_section(design, curve, **options) if section else None
    return ReferenceCurve(
        curve=curve, coarse=coarse, error=estimate_error(curve, coarse), tip=tip, section=sec
    )


def estimate_section(design, curve, **options) -> SectionError:
    """The section part of ``curve``'s error: :func:`~.section_error.section_error` at the small load of
    :func:`~.section_error.small_pressure`, with ``curve``'s options (``bend_curve``'s keywords)."""
    opts = {k: v for k, v in options.items() if k not in ("substeps",)}
    return section_error(design, pressure=small_pressure(curve), **opts)
