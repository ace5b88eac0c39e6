"""Homogenised stiffness of a close-wound helical coil.

A coil is modelled as an annulus (OD, ID) with direction-dependent moduli.
Formulas (Wahl, *Mechanical Springs*, 1963; Timoshenko & Gere):

- bending: EI_coil = p·E·I_w / (π·R·(2 + ν)), I_w = π d⁴/64, p the pitch,
  R the mean helix radius (Wahl's bending of a helical spring, small helix angle);
- axial, in tension: the spring rate k = G d⁴ / (8 D³ n) with D = 2R and
  n = L/p turns, so the equivalent modulus of the annulus is
  E_tension = k·L/A = G d⁴ p / (8 D³ A);
- axial, in compression: a close-wound coil is coil-bound — turns touch and
  the wire is loaded along its axis. We bound it by the wire's modulus times
  the wire volume fraction φ = π d/(4 p) of the annulus (π/4 when close-wound).
  Tension is ~10⁴ times softer than compression: the coil is a strongly
  **bimodular** material. The paper (and the default analytic model) uses one
  tension modulus for the whole section; with a compression-stiff coil the
  neutral axis moves toward the compressed (concave) side and the composite
  EI grows. This asymmetry is documented, not modelled, in the linear theory;
- hoop: the wire runs circumferentially, so the hoop modulus is E·φ. This is
  what confines the silicone tube radially.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from softcath.design.components import Coil

__all__ = ["CoilStiffness", "coil_stiffness", "coil_stiffness_arrays"]


@dataclass(frozen=True, kw_only=True)
class CoilStiffness:
    """Homogenised properties of a coil, all per the annulus (OD, ID).

    Attributes
    ----------
    area
        Annulus area A [mm²].
    second_moment
        Annulus second moment about its own centre I_a [mm⁴].
    axial_modulus_tension
        E_t = k·L/A [MPa] (spring-like).
    axial_modulus_compression
        E_c ≈ E_wire·φ [MPa] (coil-bound upper bound).
    bending_stiffness
        EI_coil [N mm²] from the helical-spring formula.
    bending_modulus
        EI_coil / I_a [MPa]: the modulus an isotropic annulus would need for the same EI.
    hoop_modulus
        E_wire·φ [MPa].
    wire_fraction
        φ = π d / (4 p), wire volume fraction of the annulus.
    """

    area: float
    second_moment: float
    axial_modulus_tension: float
    axial_modulus_compression: float
    bending_stiffness: float
    bending_modulus: float
    hoop_modulus: float
    wire_fraction: float


def coil_stiffness_arrays(
    *, outer_diameter, inner_diameter, wire_diameter, pitch, youngs_modulus, poisson_ratio
) -> dict[str, np.ndarray]:
    """The formulas of :func:`coil_stiffness` on numpy arrays (broadcast), for vectorised sweeps."""
    ro, ri = np.asarray(outer_diameter) / 2, np.asarray(inner_diameter) / 2
    d, p = np.asarray(wire_diameter), np.asarray(pitch)
    e_w, nu_w = np.asarray(youngs_modulus), np.asarray(poisson_ratio)
    mean_r = (ro + ri) / 2
    g_w = e_w / (2 * (1 + nu_w))
    area = np.pi * (ro**2 - ri**2)
    i_annulus = np.pi / 4 * (ro**4 - ri**4)
    i_wire = np.pi * d**4 / 64
    ei = p * e_w * i_wire / (np.pi * mean_r * (2 + nu_w))
    phi = np.pi * d / (4 * p)
    return {
        "area": area,
        "second_moment": i_annulus,
        "axial_modulus_tension": g_w * d**4 * p / (8 * (2 * mean_r) ** 3 * area),
        "axial_modulus_compression": e_w * phi,
        "bending_stiffness": ei,
        "bending_modulus": ei / i_annulus,
        "hoop_modulus": e_w * phi,
        "wire_fraction": phi,
    }


def coil_stiffness(coil: Coil) -> CoilStiffness:
    """Homogenised stiffness of ``coil`` (see module docstring for formulas)."""
    return _coil_stiffness(
        coil.outer_diameter,
        coil.inner_diameter,
        coil.wire_diameter,
        coil.pitch,
        coil.material.youngs_modulus,
        coil.material.poisson_ratio,
    )


# A section model asks twice per coil (its law, then its bending couple), and a sweep over
# silicones asks again for the same coils: cached on the six numbers (typed, so an int and a
# float are not taken for each other); a CoilStiffness is immutable, so sharing it is safe.
@functools.lru_cache(maxsize=256, typed=True)
def _coil_stiffness(od, idia, wire, pitch, youngs_modulus, poisson_ratio) -> CoilStiffness:
    """:func:`coil_stiffness` of a coil given by its six numbers."""
    values = coil_stiffness_arrays(
        outer_diameter=od,
        inner_diameter=idia,
        wire_diameter=wire,
        pitch=pitch,
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
    )
    return CoilStiffness(**{k: float(v) for k, v in values.items()})
