"""Closed forms for a helical coil of round wire, per unit of coil length.

Axial stiffness is reported as EA_coil = F / ε = F·p / δ_turn [N] and bending
stiffness as EI_coil = M / κ [N mm²], so a coil of any length compares with
the homogenised annulus (E·A, E·I) directly.
"""

from __future__ import annotations

import numpy as np

from softcath.fem.coil.frame import WireSection

__all__ = [
    "spring_rate_axial",
    "helix_axial_energy",
    "wahl_bending",
    "helix_bending_energy",
    "pivot_bending",
]


def spring_rate_axial(wire: WireSection, *, radius: float, pitch: float) -> float:
    """EA from the spring rate k = G d⁴/(8 D³ n): EA = k·L = G d⁴ p/(8 D³) (torsion only, α → 0)."""
    return wire.shear_modulus * wire.diameter**4 * pitch / (8 * (2 * radius) ** 3)


def helix_axial_energy(wire: WireSection, *, radius: float, pitch: float) -> float:
    """EA of a helix with helix angle α from the strain energy of a shear-flexible rod.

    A force F along the axis loads the wire with torque F R cos α, bending
    moment F R sin α, axial force F sin α and shear force F cos α; over one
    turn of wire (length 2πR / cos α) Castigliano gives
    δ = F·(2πR/cos α)·[R² cos²α/GJ + R² sin²α/EI + sin²α/EA + cos²α/(κGA)].
    The spring-rate formula is its α → 0, torsion-only limit.
    """
    a = np.arctan2(pitch, 2 * np.pi * radius)
    c2, s2 = np.cos(a) ** 2, np.sin(a) ** 2
    e, g = wire.youngs_modulus, wire.shear_modulus
    compliance = (2 * np.pi * radius / np.cos(a)) * (
        radius**2 * c2 / (g * wire.polar_moment)
        + radius**2 * s2 / (e * wire.second_moment)
        + s2 / (e * wire.area)
        + c2 / (wire.shear_coefficient * g * wire.area)
    )
    return float(pitch / compliance)


def wahl_bending(wire: WireSection, *, radius: float, pitch: float) -> float:
    """Wahl's bending stiffness of an open coil, EI = p E I_w / (π R (2 + ν)) (α → 0)."""
    return pitch * wire.youngs_modulus * wire.second_moment / (np.pi * radius * (2 + wire.poisson_ratio))


def helix_bending_energy(wire: WireSection, *, radius: float, pitch: float) -> float:
    """EI of a helix under a pure moment about a transverse axis, with the helix angle α.

    At wire angle φ the moment M splits into torque M sin φ cos α and bending
    M (cos²φ + sin²φ sin²α)^½; over one turn (length 2πR/cos α)
    θ = M πR/cos α · [cos²α/GJ + (1 + sin²α)/EI]. Wahl's formula is α → 0
    (GJ = E I_w /(1 + ν)).
    """
    a = np.arctan2(pitch, 2 * np.pi * radius)
    c2, s2 = np.cos(a) ** 2, np.sin(a) ** 2
    rot_per_moment = (np.pi * radius / np.cos(a)) * (
        c2 / (wire.shear_modulus * wire.polar_moment) + (1 + s2) / (wire.youngs_modulus * wire.second_moment)
    )
    return float(pitch / rot_per_moment)


def pivot_bending(wire: WireSection, *, radius: float, pitch: float) -> float:
    """EI of a close-wound coil bent at zero axial force with rigid, frictionless contact between turns.

    The turns pivot on the concave edge (y = −R): the per-turn stretch is
    ε = κR, so the energy per length is ½(EI + EA R²)κ² — the parallel-axis
    theorem on the open coil's EI and EA (axial force and bending about a
    transverse axis do not couple over a whole turn). Uses the exact-energy
    EA and EI of the helix.
    """
    ea = helix_axial_energy(wire, radius=radius, pitch=pitch)
    return helix_bending_energy(wire, radius=radius, pitch=pitch) + ea * radius**2
