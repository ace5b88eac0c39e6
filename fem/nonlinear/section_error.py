"""The cross-section part of the 3-D bend's discretisation error: :func:`section_error`.

The half-layer solve of :func:`~softcath.fem.nonlinear.reference.reference_curve` states the
error of the element layers along the bending length; it leaves out the section mesh, which at
small and moderate bends is the larger part (docs/nonlinear.md).

:func:`section_error` solves the tip once more, at a small load (:func:`small_pressure`: about
:data:`SECTION_ANGLE_DEG` of bend, one load step) on :data:`SECTION_LAYERS` layers, with the run's
section and with that section refined by :data:`SECTION_RATIO` (:func:`refined_section`: size / r,
segments per circle × r), and states the run's section error by Richardson with an **assumed**
order (:func:`section_order`, :func:`section_correction`): :data:`SECTION_ORDER` on the plain
inscribed-polygon section (the default), :data:`AREA_TRUE_SECTION_ORDER` on an area-true one. At
~1.5° the layer error of 4 layers is ~1e-6 (the φ³ law of docs/nonlinear.md), so the difference is the
section's alone.

The part is taken as **load-independent**: measured at the small load, applied as the same
relative error at every pressure of the run (checked at 22° on the paper's design,
docs/nonlinear.md).
"""

from __future__ import annotations

import inspect
import logging
import math
import time
from dataclasses import dataclass

import numpy as np

from softcath.fem.nonlinear.bend import bend_curve
from softcath.fem.nonlinear.errors import SettingError

log = logging.getLogger(__name__)

__all__ = [
    "SECTION_ANGLE_DEG",
    "SECTION_LAYERS",
    "AREA_TRUE_SECTION_ORDER",
    "SECTION_ORDER",
    "SECTION_RATIO",
    "SectionError",
    "combined_error",
    "refined_section",
    "section_correction",
    "section_error",
    "section_order",
    "small_pressure",
]

#: Refinement ratio r of the companion section: size / r and segments per circle × r (one ratio for
#: both, so the Richardson step is defined; 1.5 costs ~2x the small solve's DOFs, 2 would cost ~3x).
SECTION_RATIO = 1.5
#: Order of convergence in the segment angle assumed on a plain section (the default,
#: ``true_area=False``): a circle's inscribed polygon misses an area ∝ (2π/n)², second order; the
#: P2 elements' own error converges faster. Observed ≈ 2.5 on the paper's design; against a converged
#: section it covers six designs of eight, short by at most 0.35 points (docs/nonlinear.md).
SECTION_ORDER = 2.0
#: Order assumed on an **area-true** section (``true_area=True``): its polygons hold their curves'
#: areas, so the second-order area deficit is gone and what is left (the curves' shape, the thin
#: walls' and thick coils' elements) is not in its asymptotic range at 12 segments (the paper's
#: 12 → 18 → 27 segments: +0.14 % then +0.36 %; a thick-wire design's: −1.36 % then −1.40 %;
#: docs/nonlinear.md). Order 1 (factor r / (r − 1) = 3) covers the distance to a converged section
#: on seven designs of eight (short by 0.08 points on the paper).
AREA_TRUE_SECTION_ORDER = 1.0
#: Tip bend [deg] of the small-load solves: large enough to read, small enough that the layers'
#: error (∝ turn per layer cubed) is ~1e-6 on :data:`SECTION_LAYERS` layers.
SECTION_ANGLE_DEG = 1.5
#: Element layers of the small-load solves (the cheapest mesh with three mid-span stations).
SECTION_LAYERS = 4

_BEND_DEFAULTS = {k: v.default for k, v in inspect.signature(bend_curve).parameters.items()}


@dataclass(frozen=True, kw_only=True)
class SectionError:
    """Estimated relative error of the 3-D bend's mid-span curvature from its cross-section mesh.

    Attributes
    ----------
    pressure
        The small load [MPa] of the two solves.
    layers
        Element layers of the two solves.
    default_section, refined_section
        (size [mm], segments per circle) of the run's section and of the refined one.
    default_value, refined_value
        Mid-span curvature [1/mm] at ``pressure`` on the two sections.
    ratio, order
        Refinement ratio and order of convergence of the Richardson step.
    order_source
        ``"assumed"``.
    seconds
        Wall time of the two solves [s].
    """

    pressure: float
    layers: int
    default_section: tuple[float, int]
    refined_section: tuple[float, int]
    default_value: float
    refined_value: float
    ratio: float
    order: float
    order_source: str
    seconds: float

    @property
    def correction(self) -> float:
        """Signed relative correction of the run's section: extrapolated / default − 1 [-]."""
        return section_correction(self.default_value, self.refined_value, ratio=self.ratio, order=self.order)

    @property
    def relative(self) -> float:
        """|error| / |value| of the run's section [-] (NaN where undefined)."""
        return abs(self.correction)

    @property
    def method(self) -> str:
        """One line saying how the estimate was made."""
        (s0, n0), (s1, n1) = self.default_section, self.refined_section
        return (
            f"Richardson from two solves at {self.pressure:.3g} MPa (one load step, "
            f"{self.layers} layers) on the run's section (size {s0:g} mm, {n0} segments per circle) "
            f"and a refined one (size {s1:g} mm, {n1} segments), ratio {self.ratio:g}, order "
            f"{self.order:g} in the segment angle ({self.order_source}): |f_fine - f_run| r^q / "
            f"(r^q - 1) / |f_run|; taken as load-independent and applied at every pressure"
        )

    def to_json(self) -> dict:
        """A JSON-ready dict (NaN as null)."""
        return {
            "relative": _none(self.relative),
            "correction": _none(self.correction),
            "pressure_MPa": self.pressure,
            "layers": self.layers,
            "default_section": {
                "size_mm": self.default_section[0],
                "curvature_points": self.default_section[1],
            },
            "refined_section": {
                "size_mm": self.refined_section[0],
                "curvature_points": self.refined_section[1],
            },
            "curvature_mid_per_mm": [_none(self.default_value), _none(self.refined_value)],
            "ratio": self.ratio,
            "order": self.order,
            "order_source": self.order_source,
            "seconds": self.seconds,
            "method": self.method,
        }


def _none(x) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def refined_section(size: float, curvature_points: int, *, ratio: float = SECTION_RATIO) -> tuple[float, int]:
    """The companion section of :func:`section_error`: (size / ratio, ⌈curvature_points × ratio⌉)."""
    if not (math.isfinite(size) and size > 0):
        raise SettingError("size", size, "must be > 0 mm")
    if not (isinstance(curvature_points, (int, np.integer)) and curvature_points >= 1):
        raise SettingError("curvature_points", curvature_points, "must be an integer >= 1")
    if not (math.isfinite(ratio) and ratio > 1):
        raise SettingError("ratio", ratio, "must be > 1")
    return (float(size) / ratio, math.ceil(int(curvature_points) * ratio - 1e-9))


def section_order(true_area: bool) -> float:
    """The assumed order of :func:`section_correction` for an area-true or a plain section."""
    return AREA_TRUE_SECTION_ORDER if true_area else SECTION_ORDER


def section_correction(
    default, refined, *, ratio: float = SECTION_RATIO, order: float = SECTION_ORDER
) -> float:
    """Signed relative error of the run's section, extrapolated / ``default`` − 1 (Richardson).

    With the error e ∝ h^order, h the segment angle, the converged value is
    refined + (refined − default) / (r^order − 1), so the run's section (the coarse one) misses
    (refined − default) r^order / (r^order − 1); returned relative to ``default`` (NaN where
    ``default`` is 0 or either value is not finite).
    """
    if not (math.isfinite(ratio) and ratio > 1):
        raise SettingError("ratio", ratio, "must be > 1")
    if not (math.isfinite(order) and order > 0):
        raise SettingError("order", order, "must be > 0")
    f0, f1 = float(default), float(refined)
    a = ratio**order
    if not (math.isfinite(f0) and math.isfinite(f1) and f0 != 0):
        return float("nan")
    return (f1 - f0) * a / (a - 1.0) / f0


def combined_error(layers_relative, section_relative) -> np.ndarray:
    """The stated relative error per pressure: the layers part plus the section part.

    Summed, not added in quadrature: each part is an estimate of its own error's size, and the two
    are of one sign on the measured designs (both meshes make the tip stiff), so the sum is the
    conservative total. A missing (NaN) section part leaves the layers part alone.
    """
    lay = np.asarray(layers_relative, float)
    sec = np.broadcast_to(np.asarray(section_relative, float), lay.shape)
    return lay + np.where(np.isfinite(sec), sec, 0.0)


def small_pressure(curve, *, angle_deg: float = SECTION_ANGLE_DEG) -> float:
    """The small load [MPa] of :func:`section_error`: ``angle_deg`` of tip bend by ``curve``'s linear FEM.

    The linear FEM's end rotation per MPa (``curve.linear_bend_angle / curve.pressure``, on the run's
    own mesh) sets it; never above the run's first pressure.
    """
    if not (math.isfinite(angle_deg) and angle_deg > 0):
        raise SettingError("angle_deg", angle_deg, "must be > 0 deg")
    p0 = float(np.asarray(curve.pressure, float)[0])
    unit = abs(float(np.asarray(curve.linear_bend_angle, float)[0])) / p0
    if not (math.isfinite(unit) and unit > 0):
        return p0
    return min(p0, math.radians(angle_deg) / unit)


def section_error(
    design,
    *,
    pressure: float,
    layers: int = SECTION_LAYERS,
    ratio: float = SECTION_RATIO,
    order: float | None = None,
    **options,
) -> SectionError:
    """The :class:`SectionError` of ``design``'s 3-D bend from two small-load solves.

    Parameters
    ----------
    design
        A ``design.TipDesign``.
    pressure
        The small load [MPa] (:func:`small_pressure`), one load step.
    layers
        Element layers of the two solves.
    ratio, order
        Refinement ratio of the companion section and the assumed order (default
        :func:`section_order` of the run's ``true_area``).
    **options
        The run's keyword options of :func:`~softcath.fem.nonlinear.bend.bend_curve` (``size`` and
        ``curvature_points`` the run's section; not ``mesh``, ``layers``, ``substeps``).
    """
    for key in ("mesh", "layers", "substeps"):
        if key in options:
            raise SettingError(key, options[key], "the section estimate meshes and steps its own solves")
    if not (math.isfinite(pressure) and pressure > 0):
        raise SettingError("pressure", pressure, "must be a finite pressure > 0 MPa")
    size = float(options.pop("size", _BEND_DEFAULTS["size"]))
    points = int(options.pop("curvature_points", _BEND_DEFAULTS["curvature_points"]))
    fine = refined_section(size, points, ratio=ratio)
    if order is None:
        order = section_order(bool(options.get("true_area", _BEND_DEFAULTS["true_area"])))
    t0 = time.perf_counter()
    values = []
    for s, n in ((size, points), fine):
        c = bend_curve(design, [pressure], layers=layers, size=s, curvature_points=n, **options)
        values.append(float(c.curvature_mid[0]))
    seconds = time.perf_counter() - t0
    log.info(
        "section estimate at %.3g MPa: %s on %s and %s (%.1f s)",
        pressure,
        values,
        (size, points),
        fine,
        seconds,
    )
    return SectionError(
        pressure=float(pressure),
        layers=int(layers),
        default_section=(size, points),
        refined_section=fine,
        default_value=values[0],
        refined_value=values[1],
        ratio=float(ratio),
        order=float(order),
        order_source="assumed",
        seconds=float(seconds),
    )
