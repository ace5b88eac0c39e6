r"""The tip's angle and pose from the uniform mid-span bend: the end zones (clamp and cap).

The section tiers solve the tip's uniform bending state, far from its ends: the
bend rate :math:`\dot\theta = \mathrm d\theta/\mathrm dZ` (section turn per mm of
undeformed length) and the curvature :math:`\kappa` and elongation
:math:`\varepsilon` of the centroid fibre, :math:`\kappa (1 + \varepsilon) = \dot\theta`.
A uniform arc over the whole bending length :math:`L` turns the end section by
:math:`\dot\theta L`; the clamped tip turns less. Its section rotation
:math:`\theta(Z)`, read level by level in converged 3-D finite-strain solves
(:mod:`softcath.fem.nonlinear`, lumen load), departs from the mid-span rate in
three zones:

- **the cap plug**, the last ``cap_thickness``, solid silicone beyond the lumen's
  sealed end: the pressure acts on its inner face and nothing lies beyond, so it
  carries no bending moment and neither bends nor stretches (measured: its turn is
  −1 to +3 % of the mid-span rate's over its thickness, its stretch 0.997–1.000);
- **the clamp's Saint-Venant zone**, where the rigid clamp holds the section's own
  deformation (local rate down to 0.74–0.90 in the first 0.15 mm);
- **the cap's Saint-Venant zone**, the last ≈ 0.7 mm of the lumen, where the wall
  pressure's action ends (0.93–0.98 at small bends, up to 1.04 at 54°).

A zone's *deficit* is :math:`\int (1 - \dot\theta(Z)/\dot\theta_\mathrm{mid})\,\mathrm dZ`,
a length. The plug's is its thickness; the two Saint-Venant zones decay over a
section dimension, so their net deficit is taken proportional to the coil's
outer diameter :math:`D`:

.. math::

    \delta = t_\mathrm{cap} + C D, \qquad
    \theta_\mathrm{tip} = \dot\theta\,(L - \delta).

**Where C comes from.** The deficit converges at first order in the 3-D mesh's
element layers, so it was extrapolated from 16 and 8 layers
(:func:`softcath.fem.nonlinear.reference.estimate_tip`). On the paper's design
(L = 5 mm, D = 0.8 mm, t_cap = 0.3 mm) the extrapolated deficit is
0.305, 0.302, 0.297, 0.278, 0.268 mm at 0.1, 0.2, 0.3, 0.6, 0.7 MPa (6.5°–68° of
tip bend); :data:`C_SAINT_VENANT` = −0.012 is the mean of (δ − t_cap)/D over them
(−0.010 mm for D = 0.8 mm). The clamp's and the cap's Saint-Venant deficits nearly
cancel: the plug is the end zone. The deficit drifts down with the bend (0.245 mm at
102° on a random design), a few tenths of a percent of the angle.

**Measured error** (docs/validation.md). On the 3-D's own extrapolated bend rate the
closed form gives the extrapolated 3-D tip angle within 0.5 % on the paper's design
(6.5°–68°) and within 0.7 % on the two seeded random valid designs that no one
chose (``random_designs(2, seed=2)``: L = 6.68 mm from 7.8° to 102°, L = 4.75 mm at
12° and 27°). The D scaling rests on D = 0.79–0.81 mm only (the random designs'
range); with C this small it moves the angle by < 0.2 %. The finite-strain section
model's bend rate with this correction is 1.008–1.030 × the 3-D tip angle on the 3-D's
materials (1.010–1.038 on its own): the rest is the tiers' mid-span offset, most of
which is the 3-D default section mesh's.

**Pose** (:func:`tip_pose`): the mid-span arc over the stretched :math:`L - \delta`,
then, straight along its end tangent, the Saint-Venant deficit (stretched) and the
plug (unstretched). With no end zones it is paper eq. 9.

Measured under the lumen load on bonded tips; the cap load alone has the same plug.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath import design as design_pkg
from softcath.analytic.pose import tip_pose as arc_pose
from softcath.design.errors import DesignError

__all__ = ["C_SAINT_VENANT", "EndZones", "end_zones", "tip_angle", "tip_pose", "tip_pose_arrays"]

#: Net deficit of the Saint-Venant zones (clamp and cap) over the coil's outer diameter [-]: the mean of
#: (δ − t_cap)/D = +0.007, +0.003, −0.004, −0.027, −0.040 measured on the paper's design at 0.1, 0.2,
#: 0.3, 0.6 and 0.7 MPa (3-D, extrapolated from 16 and 8 layers; module docstring), rounded.
C_SAINT_VENANT = -0.012


@dataclass(frozen=True)
class EndZones:
    """The end-zone deficits of a tip: lengths [mm] of the uniform arc its ends do not turn.

    Attributes
    ----------
    length_mm
        Bending length L [mm].
    plug_mm
        Thickness of the cap plug, which neither bends nor stretches [mm].
    saint_venant_mm
        Net deficit of the clamp's and the cap's Saint-Venant zones [mm] (may be
        negative: a zone that turns faster than the mid-span).
    """

    length_mm: float
    plug_mm: float
    saint_venant_mm: float = 0.0

    def __post_init__(self) -> None:
        for name in ("length_mm", "plug_mm", "saint_venant_mm"):
            v = getattr(self, name)
            if not np.isfinite(v):
                raise DesignError(name, v, "must be finite")
        if not self.length_mm > 0:
            raise DesignError("length_mm", self.length_mm, "must be > 0 mm")
        if not self.plug_mm >= 0:
            raise DesignError("plug_mm", self.plug_mm, "must be >= 0 mm")
        if not abs(self.saint_venant_mm) < self.length_mm / 2:
            raise DesignError("saint_venant_mm", self.saint_venant_mm, "must be within ±length_mm / 2")
        if not 0 <= self.deficit_mm < self.length_mm:
            bound = f"must be in [0, length_mm = {self.length_mm:g})"
            raise DesignError("deficit_mm", self.deficit_mm, bound)

    @property
    def deficit_mm(self) -> float:
        """Total deficit δ [mm]: the tip turns like a uniform arc over L − δ."""
        return self.plug_mm + self.saint_venant_mm

    @property
    def effective_length_mm(self) -> float:
        """L − δ [mm]: the tip angle is the bend rate times this."""
        return self.length_mm - self.deficit_mm

    @property
    def factor(self) -> float:
        """Tip angle over the uniform-arc angle, (L − δ)/L [-]."""
        return self.effective_length_mm / self.length_mm

    def to_json(self) -> dict:
        """A JSON-ready dict of the zones and the rule they came from."""
        return {
            "length_mm": self.length_mm,
            "plug_mm": self.plug_mm,
            "saint_venant_mm": self.saint_venant_mm,
            "deficit_mm": self.deficit_mm,
            "factor": self.factor,
            "rule": f"deficit = cap_thickness + {C_SAINT_VENANT:g} x coil outer diameter",
        }


def end_zones(design) -> EndZones:
    """The :class:`EndZones` of ``design`` (a ``TipDesign``, preset name or TOML path)."""

    d = design_pkg.resolve(design)
    return EndZones(
        length_mm=float(d.tip.bending_length),
        plug_mm=float(d.tip.cap_thickness),
        saint_venant_mm=C_SAINT_VENANT * float(d.coil.outer_diameter),
    )


def tip_angle(bend_rate, zones: EndZones) -> np.ndarray:
    """The end section's rotation [rad] from the mid-span bend rate dθ/dZ [rad/mm] (any shape)."""
    return np.asarray(bend_rate, float) * zones.effective_length_mm


def tip_pose(curvature, elongation, zones: EndZones) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tip position and angle of a bent tip with its end zones (paper eq. 9 frame).

    The arc of ``curvature`` over the stretched L − δ, then, straight along its end
    tangent, the Saint-Venant deficit (stretched by ``1 + elongation``) and the plug
    (unstretched). With zero-length end zones this is :func:`softcath.analytic.tip_pose`
    over L (1 + ε).

    Parameters
    ----------
    curvature
        κ [1/mm] of the centroid fibre in the uniform part (broadcast with ``elongation``).
    elongation
        ε [-] of the same fibre.
    zones
        The tip's :class:`EndZones`.

    Returns
    -------
    tip_x, tip_y, theta
        Tip position [mm] (base at the origin, the tip along +y, bending toward +x) and
        the end section's angle θ = κ (1 + ε)(L − δ) [rad].
    """
    return tip_pose_arrays(
        curvature,
        elongation,
        length=zones.length_mm,
        plug=zones.plug_mm,
        saint_venant=zones.saint_venant_mm,
    )


def tip_pose_arrays(
    curvature, elongation, *, length, plug, saint_venant
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`tip_pose` with the zones as arrays broadcast against the curvature (many designs at once).

    ``length``, ``plug`` and ``saint_venant`` are the :class:`EndZones` fields [mm] (not checked here:
    build them from checked :class:`EndZones`).
    """

    kappa = np.asarray(curvature, float)
    stretch = 1.0 + np.asarray(elongation, float)
    plug = np.asarray(plug, float)
    saint_venant = np.asarray(saint_venant, float)
    x, y, theta = arc_pose(kappa, (np.asarray(length, float) - plug - saint_venant) * stretch)
    tail = saint_venant * stretch + plug
    return x + tail * np.sin(theta), y + tail * np.cos(theta), theta
