"""How many element layers the 3-D bend needs, and how large its discretisation error is.

The finite-strain 3-D tip is meshed fine across the section and in ``layers``
prism layers along the bending length (:func:`~softcath.fem.nonlinear.catheter.mesh_catheter`).
The mid-span curvature converges with the layers, not with the section size
(measured on the paper's design at 0.6 MPa, lumen load, mixed u–p: 4 → 8 → 12
layers gave 0.1686 → 0.1944 → 0.1970 mm⁻¹, section size 0.15 → 0.10 mm moved it
1 %; docs/nonlinear.md). What sets the error is how far each layer turns, so:

- :func:`default_layers` picks the layers from the bend the finite-strain section
  model predicts at the top pressure: at most :data:`DEG_PER_LAYER` degrees per
  layer, at least :data:`MIN_LAYERS`, at most :data:`MAX_LAYERS` (cost).
- :func:`richardson_error` states the error of a solve from a second solve on a
  mesh with fewer layers (Richardson, with an assumed order).
- :func:`observed_order` and :func:`extrapolate` do the same from three meshes
  with the order observed (:mod:`softcath.fem.nonlinear.study`).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import cast

import numpy as np

from softcath import design as design_pkg
from softcath.design.errors import DesignError
from softcath.fem.nonlinear.errors import SettingError
from softcath.fem.section_model.api import section_response
from softcath.fem.section_model.finite_strain import section_curve

__all__ = [
    "DEG_PER_LAYER",
    "MIN_LAYERS",
    "MAX_LAYERS",
    "ASSUMED_ORDER",
    "LayerChoice",
    "default_layers",
    "coarse_layers",
    "layers_for_angle",
    "MIN_ESTIMATE_LAYERS",
    "richardson_error",
    "observed_order",
    "extrapolate",
]

log = logging.getLogger(__name__)

#: Largest section rotation per element layer [deg] of the default mesh.
DEG_PER_LAYER = 5.0
#: Fewest layers of the default mesh (a small bend still needs the clamp and cap zones resolved).
MIN_LAYERS = 8
#: Most layers of the default mesh: cost grows faster than linearly with the layers.
MAX_LAYERS = 16
#: Order of convergence in 1/layers assumed by :func:`richardson_error`. Observed on the paper's design,
#: lumen load, mixed u–p: 2.9-3.2 at 0.6 MPa (layers 4/6/8/12, ~54 deg), 4.1 at 0.02 MPa (3/6/12,
#: ~1 deg); so the estimate is about right at large bends and an overestimate at small ones
#: (docs/nonlinear.md).
ASSUMED_ORDER = 3.0


@dataclass(frozen=True)
class LayerChoice:
    """The default number of element layers and why.

    Attributes
    ----------
    layers
        Element layers along the bending length.
    predicted_angle_rad
        The bend [rad] at the top pressure the choice was made for.
    source
        The model that predicted it (``"finite-strain section model"`` or
        ``"linear section model"`` when the former did not converge).
    deg_per_layer
        Predicted rotation per layer [deg] on the chosen mesh.
    """

    layers: int
    predicted_angle_rad: float
    source: str
    deg_per_layer: float

    def to_json(self) -> dict:
        """A JSON-ready dict of the choice."""
        return {
            "layers": self.layers,
            "predicted_angle_deg": math.degrees(self.predicted_angle_rad),
            "source": self.source,
            "deg_per_layer": self.deg_per_layer,
            "rule": f"ceil(angle / {DEG_PER_LAYER:g} deg), within [{MIN_LAYERS}, {MAX_LAYERS}]",
        }


def layers_for_angle(
    angle_rad: float,
    *,
    deg_per_layer: float = DEG_PER_LAYER,
    min_layers: int = MIN_LAYERS,
    max_layers: int = MAX_LAYERS,
) -> int:
    """Layers so that a bend of ``angle_rad`` turns each by at most ``deg_per_layer``, within the bounds."""
    if not (math.isfinite(angle_rad)):
        raise SettingError("angle_rad", angle_rad, "must be finite")
    if not deg_per_layer > 0:
        raise SettingError("deg_per_layer", deg_per_layer, "must be > 0 deg")
    if not (1 <= min_layers <= max_layers):
        raise SettingError("min_layers", min_layers, f"must be in [1, max_layers = {max_layers}]")
    n = math.ceil(abs(math.degrees(angle_rad)) / deg_per_layer - 1e-9)
    return int(min(max(n, min_layers), max_layers))


def default_layers(design, pressure: float, *, load: str = "lumen") -> LayerChoice:
    """Element layers for the 3-D bend of ``design`` up to ``pressure`` [MPa].

    The bend at ``pressure`` comes from the finite-strain section model (its
    uniform-arc angle, the mid-span bend rate times the bending length, a fraction of
    a second; it exceeds the clamped 3-D tip's end rotation by the end zones, so the
    rule errs on the fine side); when that model does not converge, from the linear
    section model (its curvature times the stretched length).
    """

    length = float(design_pkg.resolve(design).tip.bending_length)
    try:
        curve = section_curve(design, [pressure], load=load, linear_gain=False)
        angle = float(curve.bend_rate_per_mm[-1]) * length
        source = "finite-strain section model"
    except DesignError as exc:  # the section Newton failed: the linear model still bounds the order
        log.info("layer choice: finite-strain section model failed (%s); linear section model", exc)
        r = section_response(design, pressure, load=load)
        angle = float(r.curvature) * float(r.arc_length)
        source = "linear section model"
    n = layers_for_angle(angle)
    return LayerChoice(
        layers=n, predicted_angle_rad=angle, source=source, deg_per_layer=abs(math.degrees(angle)) / n
    )


#: Fewest layers with an error estimate: the half-layer mesh needs >= 3 layers for two mid-span stations.
MIN_ESTIMATE_LAYERS = 6


def coarse_layers(layers: int) -> int:
    """The companion mesh of the error estimate: half the layers (rounded down)."""
    if not (isinstance(layers, (int, np.integer)) and layers >= MIN_ESTIMATE_LAYERS):
        raise SettingError(
            "layers",
            layers,
            f"must be an integer >= {MIN_ESTIMATE_LAYERS} for an error estimate (half-layer mesh)",
        )
    return int(layers) // 2


def richardson_error(
    fine, coarse, *, layers: float, coarse_layers: float, order: float = ASSUMED_ORDER
) -> np.ndarray:
    """Relative discretisation error of ``fine`` estimated from a coarser solve (Richardson).

    With the error e ∝ (1/layers)^order, the fine solve's error is
    (fine − coarse) / (r^order − 1), r = layers / coarse_layers; returned relative
    to |fine| (NaN where ``fine`` is 0 or either value is not finite).

    Parameters
    ----------
    fine, coarse
        The same quantity (e.g. the mid-span curvature per pressure) on the two meshes.
    layers, coarse_layers
        Layer counts of the two meshes (``layers > coarse_layers``), or any two mesh densities 1/h.
    order
        Assumed order of convergence in 1/layers (> 0).
    """
    if not coarse_layers < layers:
        raise SettingError("coarse_layers", coarse_layers, f"must be < layers = {layers}")
    if not order > 0:
        raise SettingError("order", order, "must be > 0")
    f = np.asarray(fine, float)
    c = np.asarray(coarse, float)
    r = layers / coarse_layers
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.abs(f - c) / (r**order - 1.0) / np.abs(f)
    return np.where(np.isfinite(rel), rel, np.nan)


def _order_equation(q: float, h: np.ndarray, ratio: float) -> float:
    """(h1^q − h2^q)/(h2^q − h3^q) − ratio: zero at the observed order."""
    a = h**q
    return (a[0] - a[1]) / (a[1] - a[2]) - ratio


def observed_order(values, layers) -> float:
    """Observed order of convergence in 1/layers from three meshes (NaN if not monotone).

    Solves (f₁ − f₂)/(f₂ − f₃) = (h₁^q − h₂^q)/(h₂^q − h₃^q), h = 1/layers, for q in
    [0.05, 20]; for a constant refinement ratio r this is q = ln((f₁ − f₂)/(f₂ − f₃)) / ln r.
    """
    from scipy.optimize import brentq

    f = np.asarray(values, float)
    n = np.asarray(layers, float)
    if f.shape != (3,) or n.shape != (3,) or not np.all(np.diff(n) > 0):
        raise SettingError("layers", list(np.ravel(layers)), "must be three increasing layer counts")
    d1, d2 = f[0] - f[1], f[1] - f[2]
    if not (np.all(np.isfinite(f)) and d1 * d2 > 0):  # oscillating or stagnant: no asymptotic range
        return float("nan")
    h = 1.0 / n
    ratio = d1 / d2
    lo, hi = 0.05, 20.0
    g_lo, g_hi = _order_equation(lo, h, ratio), _order_equation(hi, h, ratio)
    if g_lo * g_hi > 0:
        return float("nan")
    root = cast(
        float, brentq(_order_equation, lo, hi, args=(h, ratio), xtol=1e-10)
    )  # full_output=False: the root
    return float(root)


def extrapolate(values, layers, order: float) -> float:
    """Richardson extrapolation to infinitely many layers from the two finest of ``values``."""
    f = np.asarray(values, float)
    n = np.asarray(layers, float)
    if not (math.isfinite(order) and order > 0):
        return float("nan")
    r = n[-1] / n[-2]
    return float(f[-1] + (f[-1] - f[-2]) / (r**order - 1.0))
