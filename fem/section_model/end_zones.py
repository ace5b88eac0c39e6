r"""The tip's angle and pose from the uniform mid-span bend: the end zones (clamp and cap).

The section tiers solve the tip's uniform bending state, far from its ends: the
bend rate :math:`\dot\theta = \mathrm d\theta/\mathrm dZ` (section turn per mm of
undeformed length) and the curvature :math:`\kappa` and elongation
:math:`\varepsilon` of the centroid fibre, :math:`\kappa (1 + \varepsilon) = \dot\theta`.
A uniform arc over the whole bending length :math:`L` would turn the end section by
:math:`\dot\theta L`. The clamped 3-D tip turns less. Its section rotation
:math:`\theta(Z)`, measured level by level in converged 3-D finite-strain solves
(:mod:`softcath.fem.nonlinear`, lumen load), shows three zones where the local rate
falls below the mid-span one:

- **the cap plug**, the last ``cap_thickness`` of the tip, solid silicone beyond the
  lumen's sealed end: the pressure acts on its inner face and nothing lies beyond,
  so it carries no bending moment and does not bend (measured local rate 0–3 % of the
  mid-span rate);
- **the cap's Saint-Venant zone**, next to the plug, where the wall pressure's
  bending fades into the plug's;
- **the clamp's Saint-Venant zone**, where the rigid clamp stops the section's own
  deformation (the lumen's inflation) that drives the bend.

Each zone's *deficit* is :math:`\int (1 - \dot\theta(Z)/\dot\theta_\mathrm{mid})\,\mathrm dZ`,
a length. The plug's is its thickness; the Saint-Venant zones decay over a section
dimension, so their deficits are taken proportional to the coil's outer diameter
:math:`D` (the section's size):

.. math::

    \delta_\mathrm{clamp} = c_\mathrm{clamp} D, \qquad
    \delta_\mathrm{cap} = t_\mathrm{cap} + c_\mathrm{cap} D, \qquad
    \theta_\mathrm{tip} = \dot\theta\,(L - \delta_\mathrm{clamp} - \delta_\mathrm{cap}).

**Constants.** :data:`C_CLAMP` and :data:`C_CAP` are the deficits measured on the
paper's design (L = 5 mm, D = 0.8 mm, t_cap = 0.3 mm; 16 element layers, lumen
load, mixed u–p), averaged over the pressures from 0.1 MPa to the largest solved
(|see docs/validation.md|): no other constant enters.

**Measured error** (docs/validation.md, "The tip's angle"). Against the 3-D end
rotation over the 3-D solve's own mid-span bend rate, the paper's design is within
0.X % from 6° to 9X°, two seeded random valid designs that no one chose
(``random_designs(2, seed=2)``: L = 4.75 and 6.68 mm) within 0.X %; the deficit varies
by a few % of itself with the bend, which is a few tenths of a percent of the angle.
The finite-strain section model with this correction is within X % of the 3-D end
rotation (its mid-span bend sits 2–2.6 % above the 3-D's, the tiers' own difference).

**Pose.** The tip's position follows from the same zones: the clamp zone as a
straight stretched segment, the arc of curvature :math:`\kappa` over the stretched
:math:`L - \delta`, the cap's Saint-Venant zone straight and stretched, the plug
straight and unstretched (measured plug stretch 0.998–1.000). Against the 3-D end
centroid this model is within X mm where the uniform arc is X mm off.

Limits. Measured under the lumen load (the real one) on bonded tips with the design's
cap plug; the cap load alone has the same plug but no wall-pressure zones. The D
scaling of the Saint-Venant deficits rests on designs with D = 0.79–0.81 mm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.design.errors import DesignError

__all__ = ["C_SAINT_VENANT", "EndZones", "end_zones", "tip_angle", "tip_pose", "tip_pose_arrays"]

#: Net deficit of the Saint-Venant zones (clamp and cap) over the coil's outer diameter [-]
#: (measured, paper design; see the module docstring).
C_SAINT_VENANT = 0.0


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
    from softcath import design as design_pkg

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
    from softcath.analytic.pose import tip_pose as arc_pose

    kappa = np.asarray(curvature, float)
    stretch = 1.0 + np.asarray(elongation, float)
    plug = np.asarray(plug, float)
    saint_venant = np.asarray(saint_venant, float)
    x, y, theta = arc_pose(kappa, (np.asarray(length, float) - plug - saint_venant) * stretch)
    tail = saint_venant * stretch + plug
    return x + tail * np.sin(theta), y + tail * np.cos(theta), theta
