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
outer diameter :math:`D`. The converged 3-D tips also need a turn that grows with
the pressure over the plug's modulus rather than with the bend rate, taken as a tilt
of the plug, on whose inner face the pressure acts (its mechanism was not resolved
level by level; a rigid plug, or zero pressure, has none):

.. math::

    \delta = t_\mathrm{cap} + C D, \qquad
    \theta_\mathrm{tip} = \dot\theta\,(L - \delta) + K\,(p / E_\mathrm{cap})^2,

:math:`E_\mathrm{cap}` the Young's modulus of the plug's silicone (the tube's: the
plug is the tube's sealed end, :mod:`softcath.design.cad`).

**Where C and K come from.** The 3-D tip angle converges at first order in the mesh's
element layers (its deficit), so it was extrapolated from 16 and 8 layers
(:func:`softcath.fem.nonlinear.reference.estimate_tip`). The 14 extrapolated tips
recorded in docs/validation.md ("The tip's angle": the paper's design at 0.1–0.7 MPa,
6.5°–68°; ``random_designs(2, seed=2)`` #1 at 0.05–0.45 MPa, 7.8°–102°, and #0 at 0.2
and 0.4 MPa) fix both constants by least squares on the relative tip angle, each
tip's own extrapolated bend rate given: :data:`C_SAINT_VENANT` = 0.033 and
:data:`K_CAP_TILT` = 0.157 rad, residuals ≤ 0.3 % (the former pure-deficit rule,
C = −0.012 and no tilt, left up to 0.7 %, falling with the bend). The fit spans
p/E_cap ≤ 0.35 (:data:`CAP_TILT_FITTED_MAX`); held out, on ``random_designs(5,
seed=4)`` #2 and #3 (coil 0.89–0.90 mm, the designs the former rule missed by up to
10 %) to p/E_cap = 0.74, the closed form on the 3-D's own bend rate gives the 3-D tip
within 0.992–1.015.

**Who applies the tilt.** Only the tiers that solve the finite-strain bend pass the
pressure (``pressure=`` of :func:`tip_angle` and :func:`tip_pose`) and only under the
lumen load, the load it was fitted on; the linear tiers and the tip-level factor
(:attr:`EndZones.factor`) keep the deficit alone, as their mid-span bend is linear.

**Pose** (:func:`tip_pose`): the mid-span arc over the stretched :math:`L - \delta`,
then, straight along its end tangent, the Saint-Venant deficit (stretched), and the
plug (unstretched) turned on by its tilt. With no end zones it is paper eq. 9.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath import design as design_pkg
from softcath.analytic.pose import tip_pose as arc_pose
from softcath.design.errors import DesignError

__all__ = [
    "CAP_TILT_FITTED_MAX",
    "C_SAINT_VENANT",
    "K_CAP_TILT",
    "EndZones",
    "end_zones",
    "tip_angle",
    "tip_pose",
    "tip_pose_arrays",
]

#: Net deficit of the Saint-Venant zones (clamp and cap) over the coil's outer diameter [-]: with
#: :data:`K_CAP_TILT`, the least-squares fit of the 14 extrapolated 3-D tips of docs/validation.md
#: (paper design, ``random_designs(2, seed=2)`` #0 and #1; module docstring), rounded.
C_SAINT_VENANT = 0.033

#: Tilt of the cap plug per (p / E_cap)² [rad], fitted with :data:`C_SAINT_VENANT`.
K_CAP_TILT = 0.157

#: Largest p / E_cap [-] among the tips :data:`K_CAP_TILT` was fitted on (held-out check to 0.74).
CAP_TILT_FITTED_MAX = 0.35


@dataclass(frozen=True)
class EndZones:
    """The end zones of a tip: the lengths [mm] of the uniform arc its ends do not turn, and its plug's tilt.

    Attributes
    ----------
    length_mm
        Bending length L [mm].
    plug_mm
        Thickness of the cap plug, which neither bends nor stretches [mm].
    saint_venant_mm
        Net deficit of the clamp's and the cap's Saint-Venant zones [mm] (may be
        negative: a zone that turns faster than the mid-span).
    cap_modulus_mpa
        Young's modulus of the plug's silicone E_cap [MPa], which sets its tilt
        (:meth:`cap_tilt`); None for a plug that does not tilt.
    """

    length_mm: float
    plug_mm: float
    saint_venant_mm: float = 0.0
    cap_modulus_mpa: float | None = None

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
        e = self.cap_modulus_mpa
        if e is not None and not (np.isfinite(e) and e > 0):
            raise DesignError("cap_modulus_mpa", e, "must be finite and > 0 MPa (or None)")

    @property
    def deficit_mm(self) -> float:
        """Total deficit δ [mm]: the tip turns like a uniform arc over L − δ."""
        return self.plug_mm + self.saint_venant_mm

    @property
    def effective_length_mm(self) -> float:
        """L − δ [mm]: the tip angle is the bend rate times this (plus the plug's tilt)."""
        return self.length_mm - self.deficit_mm

    @property
    def factor(self) -> float:
        """Tip angle over the uniform-arc angle without the plug's tilt, (L − δ)/L [-]."""
        return self.effective_length_mm / self.length_mm

    def cap_tilt(self, pressure) -> np.ndarray:
        """The plug's tilt K (p / E_cap)² [rad] at lumen ``pressure`` [MPa] (any shape; zero without E_cap).

        Fitted for p / E_cap ≤ :data:`CAP_TILT_FITTED_MAX`, checked held out to 0.74.
        """
        p = np.asarray(pressure, float)
        if not (np.all(np.isfinite(p)) and np.all(p >= 0)):
            raise DesignError("pressure", p.tolist(), "must be finite and >= 0 MPa")
        if self.cap_modulus_mpa is None:
            return np.zeros_like(p)
        return K_CAP_TILT * (p / self.cap_modulus_mpa) ** 2

    def to_json(self) -> dict:
        """A JSON-ready dict of the zones and the rule they came from."""
        return {
            "length_mm": self.length_mm,
            "plug_mm": self.plug_mm,
            "saint_venant_mm": self.saint_venant_mm,
            "deficit_mm": self.deficit_mm,
            "factor": self.factor,
            "cap_modulus_mpa": self.cap_modulus_mpa,
            "rule": (
                f"deficit = cap_thickness + {C_SAINT_VENANT:g} x coil outer diameter; "
                f"finite-strain tiers add the cap's tilt {K_CAP_TILT:g} x (p / cap_modulus)^2 rad"
            ),
        }


def end_zones(design) -> EndZones:
    """The :class:`EndZones` of ``design`` (a ``TipDesign``, preset name or TOML path)."""

    d = design_pkg.resolve(design)
    return EndZones(
        length_mm=float(d.tip.bending_length),
        plug_mm=float(d.tip.cap_thickness),
        saint_venant_mm=C_SAINT_VENANT * float(d.coil.outer_diameter),
        # the plug is the tube's sealed end (design.cad): the tube's silicone
        cap_modulus_mpa=float(d.tube.material.youngs_modulus),
    )


def tip_angle(bend_rate, zones: EndZones, *, pressure=None) -> np.ndarray:
    """The end section's rotation [rad] from the mid-span bend rate dθ/dZ [rad/mm] (any shape).

    With ``pressure`` [MPa] (broadcast with ``bend_rate``; the finite-strain tiers under the lumen
    load), the plug's tilt :meth:`EndZones.cap_tilt` is added.
    """
    theta = np.asarray(bend_rate, float) * zones.effective_length_mm
    if pressure is None:
        return theta
    return theta + zones.cap_tilt(pressure)


def tip_pose(
    curvature, elongation, zones: EndZones, *, pressure=None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tip position and angle of a bent tip with its end zones (paper eq. 9 frame).

    The arc of ``curvature`` over the stretched L − δ, then, straight along its end
    tangent, the Saint-Venant deficit (stretched by ``1 + elongation``), then the plug
    (unstretched), turned on by its tilt when ``pressure`` is given. With zero-length
    end zones and no pressure this is :func:`softcath.analytic.tip_pose` over L (1 + ε).

    Parameters
    ----------
    curvature
        κ [1/mm] of the centroid fibre in the uniform part (broadcast with ``elongation``).
    elongation
        ε [-] of the same fibre.
    zones
        The tip's :class:`EndZones`.
    pressure
        Lumen pressure [MPa] (broadcast with ``curvature``) for the plug's tilt, or None
        for none (the linear tiers).

    Returns
    -------
    tip_x, tip_y, theta
        Tip position [mm] (base at the origin, the tip along +y, bending toward +x) and
        the end section's angle θ = κ (1 + ε)(L − δ) + K (p / E_cap)² [rad].
    """
    return tip_pose_arrays(
        curvature,
        elongation,
        length=zones.length_mm,
        plug=zones.plug_mm,
        saint_venant=zones.saint_venant_mm,
        tilt=0.0 if pressure is None else zones.cap_tilt(pressure),
    )


def tip_pose_arrays(
    curvature, elongation, *, length, plug, saint_venant, tilt: float | np.ndarray = 0.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`tip_pose` with the zones as arrays broadcast against the curvature (many designs at once).

    ``length``, ``plug`` and ``saint_venant`` are the :class:`EndZones` fields [mm] and ``tilt`` the
    plug's tilt [rad] (not checked here: build them from checked :class:`EndZones`).
    """

    kappa = np.asarray(curvature, float)
    stretch = 1.0 + np.asarray(elongation, float)
    plug = np.asarray(plug, float)
    saint_venant = np.asarray(saint_venant, float)
    x, y, theta = arc_pose(kappa, (np.asarray(length, float) - plug - saint_venant) * stretch)
    tail = saint_venant * stretch
    end = theta + np.asarray(tilt, float)
    x = x + tail * np.sin(theta) + plug * np.sin(end)
    y = y + tail * np.cos(theta) + plug * np.cos(end)
    return x, y, end
