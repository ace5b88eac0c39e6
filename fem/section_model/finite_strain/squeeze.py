r"""The squeezed tube: its stress-free state the catalogue annulus, its law at :math:`F F_\text{pre}(X)`.

The catalogue tube is a circular annulus (radii :math:`r_i, r_o`); as built it is the
elliptical ring of :mod:`softcath.design.section` (outer ellipse :math:`a, b` centred at
:math:`(0, y_t)`, lumen :math:`a_\text{int}, b_\text{int}` centred at :math:`(0, y_t + h)`).
Both are parametrised by :math:`s \in [0, 1]` across the wall and the angle :math:`\theta`:

.. math::

    X(s, \theta) = c + (r_i + s (r_o - r_i)) (\cos\theta, \sin\theta), \qquad
    x(s, \theta) = (1 - s)\, x_\text{lumen}(\theta) + s\, x_\text{outer}(\theta),

with :math:`c = (0, y_t)` (a translation, which leaves every gradient unchanged). The tube's
stress-free state is :math:`X_t = (1 - t) x + t X` (:math:`t` = ``tube_squeeze``: 0 the tube
built stress-free, 1 the whole squeeze from the catalogue tube). The as-built section stays
the model's reference and

.. math::

    F_\text{pre} = \begin{pmatrix} J_x J_t^{-1} & 0 \\ 0 & \lambda_z \end{pmatrix},\quad
    J_x = \frac{\partial x}{\partial (s, \theta)},\;
    J_t = (1 - t) J_x + t \frac{\partial X}{\partial (s, \theta)},\quad
    \lambda_z = \frac{\det J_t}{\det J_x},

so :math:`\det F_\text{pre} = 1`: the incompressible silicone's thinner as-built wall is a
longer tube. ``tube_squeeze`` therefore includes the axial stretch, point by point, and does
not combine with the uniform ``tube_prestretch`` (module ``prestretch``; the curve refuses
both). The law is :math:`W(F F_\text{pre})`: :math:`P = P_0 F_\text{pre}^T`,
:math:`A_{iJkL} = A^0_{iMkN} F^\text{pre}_{JM} F^\text{pre}_{LN}`; the volumetric energy
depends on :math:`\det F` alone and keeps its split.

Points off the ring. The meshed tube is the ring plus the bonded lands at the contacts
(:mod:`softcath.fem.geometry`, strips up to ``land_gap`` thick just outside the outer
ellipse) and the slivers between the lumen ellipse and its polygon, less what the coil or
channel clip. The map is affine in :math:`s` at fixed :math:`\theta`, so it is continued
affinely there (:math:`s` a little outside [0, 1]): a land is squeezed as the wall it
continues, and a clipped part simply has no points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from softcath.design.errors import DesignError
from softcath.fem.geometry import TUBE
from softcath.fem.hyperelastic.laws import IsotropicLaw
from softcath.fem.section_model.finite_strain.newton import SectionProblem, State
from softcath.fem.section_model.finite_strain.prestretch import PreDeformed, ramped_rest_state

__all__ = ["Squeezed", "TubeRing", "check_squeeze", "squeeze_rest_state", "squeezed_laws"]

#: Bisection steps of the inversion for s: the bracket (< 4 wide) shrinks to round-off.
_BISECTIONS = 60


def check_squeeze(value) -> float:
    """``value`` as a float in [0, 1], else a :class:`DesignError` naming ``tube_squeeze``."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise DesignError("tube_squeeze", value, "must be a number in [0, 1]") from None
    if not (math.isfinite(v) and 0.0 <= v <= 1.0):
        raise DesignError("tube_squeeze", value, "must be in [0, 1] (0: built stress-free, 1: catalogue)")
    return v


@dataclass(frozen=True, kw_only=True)
class TubeRing:
    """The catalogue annulus and the as-built ring of one tube [mm] (frame: the section's)."""

    inner_radius: float
    outer_radius: float
    a: float
    b: float
    a_int: float
    b_int: float
    h: float
    centre_y: float

    @classmethod
    def from_design(cls, design) -> TubeRing:
        """The ring of ``design``'s tube: catalogue diameters, as-built :attr:`design.section`."""
        s = design.section
        return cls(
            inner_radius=design.tube.catalogue_inner_diameter / 2,
            outer_radius=design.tube.catalogue_outer_diameter / 2,
            a=s.a,
            b=s.b,
            a_int=s.a_int,
            b_int=s.b_int,
            h=s.h,
            centre_y=s.tube_center_y,
        )

    def _axes(self, s):
        """Semi-axes A(s), B(s) and centre height C(s) of the as-built curve s = const."""
        return (
            self.a_int + s * (self.a - self.a_int),
            self.b_int + s * (self.b - self.b_int),
            self.centre_y + (1.0 - s) * self.h,
        )

    def as_built(self, s, theta) -> np.ndarray:
        """x(s, theta), shape (..., 2)."""
        aa, bb, cc = self._axes(np.asarray(s, float))
        return np.stack([aa * np.cos(theta), cc + bb * np.sin(theta)], axis=-1)

    def catalogue(self, s, theta) -> np.ndarray:
        """X(s, theta) on the catalogue annulus centred at (0, ``centre_y``), shape (..., 2)."""
        r = self.inner_radius + np.asarray(s, float) * (self.outer_radius - self.inner_radius)
        return np.stack([r * np.cos(theta), self.centre_y + r * np.sin(theta)], axis=-1)

    def coordinates(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(s, theta) of as-built ``points`` (..., 2): s solves (x/A)^2 + ((y - C)/B)^2 = 1.

        The left side falls as s grows across the ring (the curves s = const nest), so a
        bisection on a bracket reaching past the lands and the lumen's slivers finds s to
        round-off. Raises :class:`DesignError` for a point off that bracket.
        """
        x, y = (np.asarray(points, float)[..., i] for i in (0, 1))
        lo = -min(0.25, 0.5 * self.a_int / (self.a - self.a_int), 0.5 * self.b_int / (self.b - self.b_int))
        bounds = [np.full(x.shape, lo), np.full(x.shape, 3.0)]

        def excess(s):
            aa, bb, cc = self._axes(s)
            return (x / aa) ** 2 + ((y - cc) / bb) ** 2 - 1.0

        off = (excess(bounds[0]) < 0) | (excess(bounds[1]) > 0)
        if np.any(off):
            point = [float(x[off][0]), float(y[off][0])]
            raise DesignError("tube points", point, "must lie on the as-built ring's map (s in its bracket)")
        for _ in range(_BISECTIONS):
            mid = 0.5 * (bounds[0] + bounds[1])
            out = excess(mid) > 0
            bounds = [np.where(out, mid, bounds[0]), np.where(out, bounds[1], mid)]
        s = 0.5 * (bounds[0] + bounds[1])
        aa, bb, cc = self._axes(s)
        return s, np.arctan2((y - cc) / bb, x / aa)

    def jacobians(self, s, theta) -> tuple[np.ndarray, np.ndarray]:
        """(dx/d(s, theta), dX/d(s, theta)), each (..., 2, 2)."""
        c, n = np.cos(theta), np.sin(theta)
        aa, bb, _ = self._axes(s)
        dr = self.outer_radius - self.inner_radius
        r = self.inner_radius + s * dr
        jx = np.stack(
            [
                np.stack([(self.a - self.a_int) * c, -aa * n], axis=-1),
                np.stack([-self.h + (self.b - self.b_int) * n, bb * c], axis=-1),
            ],
            axis=-2,
        )
        jc = np.stack([np.stack([dr * c, -r * n], axis=-1), np.stack([dr * n, r * c], axis=-1)], axis=-2)
        return jx, jc

    def pre_deformation(self, points: np.ndarray, squeeze: float) -> np.ndarray:
        """F_pre (..., 3, 3) at as-built ``points`` (..., 2) for ``tube_squeeze`` = ``squeeze``."""
        s, theta = self.coordinates(points)
        jx, jc = self.jacobians(s, theta)
        jt = (1.0 - squeeze) * jx + squeeze * jc
        det_t = np.linalg.det(jt)
        if np.any(det_t <= 0):
            raise DesignError("tube_squeeze", squeeze, "folds the tube's stress-free state (det <= 0)")
        f = np.zeros(s.shape + (3, 3))
        f[..., :2, :2] = jx @ np.linalg.inv(jt)
        f[..., 2, 2] = det_t / np.linalg.det(jx)
        return f


@dataclass(frozen=True, eq=False)
class Squeezed(PreDeformed):
    """A finite-strain law evaluated at F F_pre, F_pre given per point (``pre``: (cells, nq, 3, 3)
    in the order of the region's cells, or one (3, 3) for all).

    Its small-strain tensor is the base law's (the centroid and the reported Poisson ratio stay
    those of the unsqueezed material).
    """

    law: IsotropicLaw
    pre: np.ndarray
    squeeze: float = 1.0

    def energy(self, f: np.ndarray, *, volumetric: bool = True) -> np.ndarray:
        """W(F F_pre) per as-built volume [MPa] (det F_pre = 1)."""
        return self.law.energy(f @ self.pre, volumetric=volumetric)

    def stress_tangent(self, f: np.ndarray, *, volumetric: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """P = P0(F F_pre) F_pre^T and A[i, J, k, L] = A0[i, M, k, N] F_pre[J, M] F_pre[L, N]."""
        g = self.pre
        p0, a0 = self.law.stress_tangent(f @ g, volumetric=volumetric)
        half = np.einsum("...iMkN,...JM->...iJkN", a0, g)
        return np.einsum("...iM,...JM->...iJ", p0, g), np.einsum("...iJkN,...LN->...iJkL", half, g)


def squeezed_laws(laws: dict, points: np.ndarray, ring: TubeRing, squeeze: float) -> dict:
    """``laws`` with the tube's law squeezed by ``squeeze`` at its quadrature ``points`` (the same
    dict at 0)."""
    if squeeze == 0.0:
        return dict(laws)
    base = laws[TUBE]
    base = base.law if isinstance(base, Squeezed) else base
    return {**laws, TUBE: Squeezed(base, ring.pre_deformation(points, squeeze), float(squeeze))}


def squeeze_rest_state(
    problem: SectionProblem, ring: TubeRing, squeeze: float, *, min_step: float = 1e-3
) -> tuple[SectionProblem, State]:
    """The squeezed ``problem`` and its equilibrium at zero pressure.

    ``problem`` carries the laws without squeeze; ``tube_squeeze`` is ramped from 0 (a full
    step first, halved after a failure; :class:`SectionConvergenceError` names it and the value
    reached when the step falls below ``min_step``).
    """
    disc = problem.disc
    points = disc.points[disc.cells[TUBE]]

    def at(t: float) -> SectionProblem:
        return replace(problem, disc=replace(disc, laws=squeezed_laws(disc.laws, points, ring, t)))

    return ramped_rest_state(at, (0.0, squeeze), name="tube_squeeze", min_step=min_step)
