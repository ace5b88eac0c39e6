r"""Bilinear axial fibres: coil-bound compression and initial tension, solved on the beam strains.

A close-wound coil is soft in tension once its turns separate (the spring,
E_t) and coil-bound in compression (E_c = E·φ); wound with initial tension
F₀ its turns stay pressed together until the axial load has taken F₀ off
them (``softcath.fem.coil``, docs/coil.md). Per fibre of area a at (x, y), with the
strain eps = eps_0 + k_1 x + k_2 y measured from the unloaded (preloaded) state,

.. math::

    \sigma(\varepsilon) = \min(E_c\,\varepsilon,\; E_t\,\varepsilon + \sigma_0),
    \qquad \sigma_0 = F_0 / A,

closed (E_c) up to eps_p = sigma_0/(E_c - E_t), then open with the wire
carrying the released preload. sigma is continuous and increasing, so the
fibres' energy is convex and piecewise quadratic.

Because a coil's axial modulus enters the section only through the global
block (``softcath.fem.section_model.coil_models``), the in-plane field condenses out
exactly and the nonlinear problem has three unknowns g = (eps_0, k_1, k_2):
K_rest g + F_fibres(g) = f. It is solved by Newton's method on the active
set of closed fibres (the cracked-section iteration) with a backtracking
line search on the energy, stopping when an undamped Newton point's own
closed set reproduces the set it was computed with: the solution is then
exact to rounding.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.design.errors import DesignError

__all__ = ["Fibres", "solve_fibres", "ring_fibres", "MAX_ITERATIONS"]

#: Newton iterations before giving up (a few suffice; the set of closed fibres is monotone in practice).
MAX_ITERATIONS = 200


@dataclass(frozen=True)
class Fibres:
    """Axial fibres with a bilinear law (arrays of equal length).

    Attributes
    ----------
    x, y, area
        Position (mm) and area (mm^2).
    tension_modulus, compression_modulus
        E_t and E_c (MPa), E_c >= E_t.
    prestress
        sigma_0 = F_0 / A (MPa) of the initial tension, >= 0 (needs E_c > E_t).
    """

    x: np.ndarray
    y: np.ndarray
    area: np.ndarray
    tension_modulus: np.ndarray
    compression_modulus: np.ndarray
    prestress: np.ndarray

    def __post_init__(self) -> None:
        et, ec, s0 = self.tension_modulus, self.compression_modulus, self.prestress
        if np.any(ec < et):
            raise DesignError("compression_modulus", float(np.min(ec)), "must be >= the tension modulus")
        if np.any(s0 < 0) or np.any((s0 > 0) & (ec <= et)):
            raise DesignError("prestress", float(np.max(s0)), "must be >= 0, and 0 unless E_c > E_t")

    @property
    def phi(self) -> np.ndarray:
        """(n, 3): d eps / d g."""
        return np.column_stack([np.ones_like(self.x), self.x, self.y])

    def opening_strain(self) -> np.ndarray:
        """eps_p: the strain at which each fibre opens (0 without initial tension)."""
        gap = self.compression_modulus - self.tension_modulus
        return np.divide(self.prestress, gap, out=np.zeros_like(gap), where=gap > 0)

    def state(self, g: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        """(closed mask, resultant (N, M_1, M_2), tangent 3x3, energy) at beam strains ``g``."""
        phi = self.phi
        eps = phi @ g
        ep = self.opening_strain()
        closed = eps <= ep
        et, ec = self.tension_modulus, self.compression_modulus
        sigma = np.where(closed, ec * eps, et * eps + self.prestress)
        tangent = np.where(closed, ec, et) * self.area
        d = eps - ep
        psi = np.where(closed, 0.5 * ec * eps**2, 0.5 * ec * ep**2 + ec * ep * d + 0.5 * et * d**2)
        force = phi.T @ (sigma * self.area)
        return closed, force, (phi * tangent[:, None]).T @ phi, float(psi @ self.area)

    def linear_stiffness(self, modulus: np.ndarray) -> np.ndarray:
        """int E phi phi^T dA for per-fibre moduli ``modulus``."""
        phi = self.phi
        return (phi * (modulus * self.area)[:, None]).T @ phi

    def join(self, other: Fibres) -> Fibres:
        return Fibres(*(np.concatenate([getattr(self, k), getattr(other, k)]) for k in _FIELDS))


_FIELDS = ("x", "y", "area", "tension_modulus", "compression_modulus", "prestress")


def ring_fibres(
    *,
    centre: tuple[float, float],
    radius: float,
    area: float,
    tension_axial: float,
    compression_modulus: float,
    initial_tension: float,
    points: int = 720,
) -> Fibres:
    """A thin ring of fibres (the resolved wire's axial part): EA_t = ``tension_axial`` [N] in total.

    ``points`` equally spaced from angle 0, a multiple of 4 so that the ring's
    lowest point (the pivot of a coil bent toward -y) is a fibre.
    """
    if points < 8 or points % 4:
        raise DesignError("points", points, "must be a multiple of 4, >= 8")
    t = 2 * np.pi * np.arange(points) / points
    n = np.ones(points)
    return Fibres(
        x=centre[0] + radius * np.cos(t),
        y=centre[1] + radius * np.sin(t),
        area=n * area / points,
        tension_modulus=n * tension_axial / area,
        compression_modulus=n * compression_modulus,
        prestress=n * initial_tension / area,
    )


def solve_fibres(
    k_rest: np.ndarray, fibres: Fibres, load: np.ndarray, *, start: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, int]:
    """Beam strains g with K_rest g + F_fibres(g) = load: (g, closed mask, Newton iterations).

    ``k_rest`` is the condensed section stiffness without the fibres (SPD or
    semi-definite; the sum must be SPD), ``load`` the (N, M_1, M_2) resultant.
    """
    load = np.asarray(load, dtype=float)

    def energy(g):
        return 0.5 * g @ k_rest @ g + fibres.state(g)[3] - load @ g

    if start is None:
        start = np.linalg.solve(k_rest + fibres.linear_stiffness(fibres.tension_modulus), load)
    g = np.asarray(start, dtype=float)
    closed, force, tangent, _ = fibres.state(g)
    for it in range(1, MAX_ITERATIONS + 1):
        k_t = k_rest + tangent
        step = np.linalg.solve(k_t, load - k_rest @ g - force)
        trial = g + step
        closed_t, force_t, tangent_t, _ = fibres.state(trial)
        if np.array_equal(closed_t, closed):
            return trial, closed_t, it  # the Newton point of this set is consistent: exact
        e0, t = energy(g), 1.0
        while energy(g + t * step) > e0 and t > 1e-12:  # safeguard against cycling between sets
            t *= 0.5
        g = g + t * step
        closed, force, tangent, _ = fibres.state(g) if t < 1 else (closed_t, force_t, tangent_t, 0.0)
    raise DesignError("iterations", MAX_ITERATIONS, "the bilinear section solve did not converge")
