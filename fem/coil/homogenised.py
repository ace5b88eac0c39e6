"""The homogenised coil models the resolved wire is compared with, per unit length.

Each model gives the coil's axial stiffness in tension and in compression
(EA [N]) and its own bending stiffness (EI [N mm²] about the coil axis, or
about its neutral axis when the model is bimodular), all from
:func:`design.coil_stiffness` and the annulus (OD, ID):

- ``annulus_tension``: isotropic annulus with the spring's tension modulus
  E_t = k L / A (the paper's E_eq; the FEM's ``--coil-modulus tension``);
- ``annulus_bending``: annulus with Wahl's bending modulus EI_Wahl / I_a
  (``--coil-modulus bending``);
- ``spring_wahl``: the analytic model's pair, spring rate and Wahl's EI, one
  axial modulus for tension and compression;
- ``bimodular_annulus``: E_t in tension, the coil-bound E_c = E·φ in
  compression (a cracked-section law); in bending the neutral axis moves
  toward the compressed edge.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from softcath.design import coil_stiffness
from softcath.design.components import Coil

__all__ = ["homogenised_models", "bimodular_annulus_bending", "MODEL_LABELS"]

MODEL_LABELS = {
    "annulus_tension": "annulus, tension modulus E_t (paper E_eq; FEM default)",
    "annulus_bending": "annulus, bending modulus EI_Wahl/I_a (FEM --coil-modulus bending)",
    "spring_wahl": "spring rate + Wahl EI (analytic model)",
    "bimodular_annulus": "bimodular annulus, E_t tension / E_c = E·φ compression",
}


def _width(y: float, r_out: float, r_in: float) -> float:
    """Chord width of the annulus at height y."""
    return 2 * (np.sqrt(max(r_out**2 - y**2, 0.0)) - np.sqrt(max(r_in**2 - y**2, 0.0)))


def bimodular_annulus_bending(
    *, outer_radius: float, inner_radius: float, tension_modulus: float, compression_modulus: float
) -> tuple[float, float]:
    """(EI about the neutral axis [N mm²], neutral-axis height y_n [mm]) of a bimodular annulus.

    Positive curvature stretches y > y_n; y_n solves ∫ E(y)(y − y_n) dA = 0.
    """
    ro, ri = outer_radius, inner_radius
    breaks = sorted({-ro, -ri, ri, ro})

    def integral(fn, lo: float, hi: float) -> float:
        pts = [lo] + [b for b in breaks if lo < b < hi] + [hi]
        return sum(
            quad(lambda y: fn(y) * _width(y, ro, ri), a, b, limit=200)[0]
            for a, b in zip(pts[:-1], pts[1:], strict=True)
        )

    def first_moment(yn: float) -> float:
        return compression_modulus * integral(lambda y: y - yn, -ro, yn) + tension_modulus * integral(
            lambda y: y - yn, yn, ro
        )

    yn = brentq(first_moment, -ro, ro, xtol=1e-14 * ro)
    ei = compression_modulus * integral(lambda y: (y - yn) ** 2, -ro, yn) + tension_modulus * integral(
        lambda y: (y - yn) ** 2, yn, ro
    )
    return float(ei), float(yn)


def homogenised_models(coil: Coil) -> dict[str, dict[str, float]]:
    """Model name → {axial_tension_N, axial_compression_N, bending_N_mm2} (see module docstring)."""
    k = coil_stiffness(coil)
    e_t, e_c, e_b = k.axial_modulus_tension, k.axial_modulus_compression, k.bending_modulus
    ei_bi, _ = bimodular_annulus_bending(
        outer_radius=coil.outer_diameter / 2,
        inner_radius=coil.inner_diameter / 2,
        tension_modulus=e_t,
        compression_modulus=e_c,
    )

    def row(tension: float, compression: float, bending: float) -> dict[str, float]:
        return {"axial_tension_N": tension, "axial_compression_N": compression, "bending_N_mm2": bending}

    return {
        "annulus_tension": row(e_t * k.area, e_t * k.area, e_t * k.second_moment),
        "annulus_bending": row(e_b * k.area, e_b * k.area, k.bending_stiffness),
        "spring_wahl": row(e_t * k.area, e_t * k.area, k.bending_stiffness),
        "bimodular_annulus": row(e_t * k.area, e_c * k.area, ei_bi),
    }
