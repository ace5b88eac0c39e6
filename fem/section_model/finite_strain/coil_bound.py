r"""A close-wound coil at finite strain: coil-bound in compression, initial tension in tension.

The homogenised coil of :func:`~softcath.fem.section_model.finite_strain.laws.section_laws`
is Saint Venant-Kirchhoff, :math:`S = \mathbb{C}_t : E`, with the spring's tensile axial
modulus :math:`E_t = \mathbb{C}_{t,3333}`. A close-wound coil is that only once its turns
have opened: while they touch, the axial load goes through the stacked wire
(:math:`E_c = E\varphi`, ``design.coil_stiffness``), and a coil wound with initial tension
:math:`F_0` keeps them touching until the tensile load has taken :math:`F_0` off them.
With the coil's area A, the axial law in the Green-Lagrange strain :math:`E_{33}` is

.. math::

    S_{33} = \min(E_c E_{33},\; E_t E_{33} + \sigma_0), \qquad \sigma_0 = F_0 / A,

the linear section model's bilinear fibre (``softcath.fem.section_model.fibres``) in the
rotated frame; the turns open at :math:`E_p = \sigma_0 / (E_c - E_t)`. The rest of the
law is the coil's tensor, so

.. math::

    W = \tfrac12 E:\mathbb{C}_t:E - \tfrac12 E_t E_{33}^2 + \psi(E_{33}),\qquad
    \psi(e) = \tfrac12 E_c e^2 - (E_c - E_t)\,R(e - E_p),

with R the ramp's integral. The kink of the min is rounded over a strain half-width
h = :data:`HALF_WIDTH` (R quadratic-spline smoothed: exact outside :math:`|e - E_p| < h`)
so that Newton's tangent is continuous; a strain of 1e-8 is far below anything the curve
reports, and the tests measure that h changes the curve by less than the Newton tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from softcath.design.errors import DesignError

__all__ = ["CoilBoundSVK", "HALF_WIDTH", "axial_stress"]

#: Green-Lagrange strain half-width over which the kink where the turns open is rounded.
HALF_WIDTH = 1e-8

_I = np.eye(3)


def _ramp(x: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(R, r, r') of the smoothed ramp r = max(x, 0): quadratic over |x| < h, exact outside."""
    inside = np.abs(x) < h
    xi = np.where(inside, x + h, 0.0)
    r = np.where(inside, xi**2 / (4 * h), np.maximum(x, 0.0))
    dr = np.where(inside, xi / (2 * h), (x > 0).astype(float))
    big_r = np.where(inside, xi**3 / (12 * h), np.where(x > 0, 0.5 * x**2 + h**2 / 6, 0.0))
    return big_r, r, dr


def axial_stress(
    strain,
    *,
    tension_modulus: float,
    compression_modulus: float,
    prestress: float,
    half_width: float = HALF_WIDTH,
):
    r"""(psi, S_33, dS_33/dE_33) of the smoothed bilinear law at Green-Lagrange strain ``strain``.

    Parameters
    ----------
    strain
        E_33 (any shape).
    tension_modulus, compression_modulus
        E_t and E_c [MPa].
    prestress
        sigma_0 = F_0 / A [MPa].
    half_width
        The kink's rounding half-width in strain.
    """
    e = np.asarray(strain, float)
    gap = compression_modulus - tension_modulus
    opening = prestress / gap if gap > 0 else 0.0
    big_r, r, dr = _ramp(e - opening, half_width)
    psi = 0.5 * compression_modulus * e**2 - gap * big_r
    return psi, compression_modulus * e - gap * r, compression_modulus - gap * dr


@dataclass(frozen=True)
class CoilBoundSVK:
    """Saint Venant-Kirchhoff coil whose axial law is coil-bound below its initial tension.

    Parameters
    ----------
    tensor
        The open coil's homogenised tensor C_t[i, j, k, l] [MPa] (its C_3333 is E_t).
    compression_modulus
        E_c [MPa], >= E_t: the axial modulus of the touching turns.
    prestress
        sigma_0 = F_0 / A [MPa], >= 0 (> 0 needs E_c > E_t).
    half_width
        Strain half-width of the kink's rounding (:data:`HALF_WIDTH`).
    """

    tensor: np.ndarray
    compression_modulus: float
    prestress: float = 0.0
    half_width: float = HALF_WIDTH
    splits_volume: bool = field(default=False, init=False)

    def __post_init__(self) -> None:
        c = np.asarray(self.tensor, float)
        if c.shape != (3, 3, 3, 3) or not np.all(np.isfinite(c)):
            raise DesignError("tensor", c.shape, "must be a finite (3, 3, 3, 3) array")
        object.__setattr__(self, "tensor", c)
        et, ec, s0 = self.tension_modulus, float(self.compression_modulus), float(self.prestress)
        if not (np.isfinite(ec) and ec >= et):
            raise DesignError("compression_modulus", ec, f"must be finite and >= E_t = {et:.6g} MPa")
        if not (np.isfinite(s0) and s0 >= 0):
            raise DesignError("prestress", s0, "must be finite and >= 0 MPa")
        if s0 > 0 and ec <= et:
            raise DesignError("prestress", s0, "must be 0 unless E_c > E_t")
        if not (np.isfinite(self.half_width) and 0 < self.half_width < 1e-3):
            raise DesignError("half_width", self.half_width, "must be in (0, 1e-3)")

    @property
    def tension_modulus(self) -> float:
        """E_t = C_3333 [MPa]."""
        return float(self.tensor[2, 2, 2, 2])

    @property
    def opening_strain(self) -> float:
        """E_p: the Green-Lagrange strain at which the turns open."""
        gap = self.compression_modulus - self.tension_modulus
        return self.prestress / gap if gap > 0 else 0.0

    def small_strain_tensor(self) -> np.ndarray:
        """The open coil's tensor: the section's stiffness-weighted centroid stays the linear model's."""
        return self.tensor

    def _axial(self, e33):
        return axial_stress(
            e33,
            tension_modulus=self.tension_modulus,
            compression_modulus=self.compression_modulus,
            prestress=self.prestress,
            half_width=self.half_width,
        )

    def energy(self, f: np.ndarray, *, volumetric: bool = True) -> np.ndarray:
        """W = 1/2 E:C_t:E - 1/2 E_t E_33^2 + psi(E_33) [MPa]."""
        e = 0.5 * (np.einsum("...aI,...aJ->...IJ", f, f) - _I)
        w = 0.5 * np.einsum("...IJ,IJKL,...KL->...", e, self.tensor, e, optimize=True)
        psi, _, _ = self._axial(e[..., 2, 2])
        return w - 0.5 * self.tension_modulus * e[..., 2, 2] ** 2 + psi

    def stress_tangent(self, f: np.ndarray, *, volumetric: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """P = F S and A_iJkL = delta_ik S_JL + F_iM dS_MJ/dE_LQ F_kQ, the axial part replaced."""
        e = 0.5 * (np.einsum("...aI,...aJ->...IJ", f, f) - _I)
        s = np.einsum("IJKL,...KL->...IJ", self.tensor, e, optimize=True)
        _, s33, ds33 = self._axial(e[..., 2, 2])
        et = self.tension_modulus
        s[..., 2, 2] += s33 - et * e[..., 2, 2]
        p = f @ s
        a = np.einsum("ik,...JL->...iJkL", _I, s)
        a += np.einsum("...iM,MJLQ,...kQ->...iJkL", f, self.tensor, f, optimize=True)
        # the axial modulus's change: F_i3 (dS33/dE33 - E_t) F_k3 on the (3, 3) material slots
        f3 = f[..., :, 2]
        a[..., :, 2, :, 2] += (ds33 - et)[..., None, None] * f3[..., :, None] * f3[..., None, :]
        return p, a
