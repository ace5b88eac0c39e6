"""Frictionless penalty contact between neighbouring turns, solved by an active-set iteration.

A close-wound coil's turns touch along the wire. Node k and node k + m (one
turn up, same angle) carry a contact spring along the line joining them
(+z for a helix): gap g = g₀ + n·(u_{k+m} − u_k), where g₀ = p − d. A
negative gap is closed: the spring pushes with force k_c·(−g). Rotations do
not enter the gap to first order (n·(θ × n) = 0), so a centre-line pair is
exact for the normal gap of two round wires.

Initial tension is a preload: the unloaded coil is a state of self-stress,
each pair pressed with force f₀ and the wire pulling the turns together with
the same force (in linear theory only its nodal resultant −Bᵀf₀ enters). A
pair's force is then λ = max(0, f₀ − k_c·Bu) = k_c·max(0, −(g₀ − f₀/k_c + Bu))
(close-wound, g₀ = 0): the same penalty law with the gap shifted by −f₀/k_c
and the load −Bᵀf₀, so the unloaded coil does not move and a pair opens once
a load has taken off its preload.

Solution: the penalty problem minimises the convex, continuously
differentiable energy Π(u) = ½ uᵀKu − fᵀu + ½ Σ k_c min(g, 0)². A semismooth
Newton method (the primal active-set method; Wriggers, *Computational
Contact Mechanics*, §5.2; Hintermüller, Ito & Kunisch 2002) solves with the
currently closed pairs as linear springs; a backtracking line search on Π
guards against cycling between active sets (the plain iteration did not
settle on an end-plate model with an earlier, since replaced, preload). It
ends when u is the exact solution for a set that its own gaps reproduce —
then u solves the piecewise linear problem.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from softcath.fem.errors import SolverError

__all__ = ["ContactPairs", "solve_with_contact"]


@dataclass(frozen=True)
class ContactPairs:
    """Node pairs that may touch (all arrays of length n_pairs).

    Attributes
    ----------
    first, second
        Node indices (``second`` is one turn above ``first``).
    normal
        (n, 3) unit vectors from ``first`` to ``second``.
    gap0
        Gap at zero displacement [mm] (p − d; 0 for a close-wound coil).
    stiffness
        Penalty stiffness of each pair [N/mm].
    preload
        Contact force of each pair in the unloaded coil [N] (initial tension).
    """

    first: np.ndarray
    second: np.ndarray
    normal: np.ndarray
    gap0: np.ndarray
    stiffness: np.ndarray
    preload: np.ndarray

    @property
    def shifted_gap0(self) -> np.ndarray:
        """g₀ − f₀/k_c: the gap the penalty law sees (see module docstring)."""
        return self.gap0 - self.preload / self.stiffness

    def operator(self, n_dofs: int) -> sp.csr_matrix:
        """B (n_pairs × n_dofs): gap change = B u."""
        n = len(self.first)
        rows = np.repeat(np.arange(n), 6)
        cols = np.concatenate(
            [6 * self.first[:, None] + np.arange(3), 6 * self.second[:, None] + np.arange(3)], axis=1
        ).ravel()
        vals = np.concatenate([-self.normal, self.normal], axis=1).ravel()
        return sp.csr_matrix((vals, (rows, cols)), shape=(n, n_dofs))


def solve_with_contact(
    solve: Callable[[sp.spmatrix, np.ndarray], np.ndarray],
    stiffness: sp.spmatrix,
    load: np.ndarray,
    gap_operator: sp.spmatrix,
    gap0: np.ndarray,
    penalty: np.ndarray,
    *,
    active: np.ndarray | None = None,
    max_iterations: int = 200,
) -> tuple[np.ndarray, np.ndarray, int]:
    """Displacement, closed-pair mask and iteration count for one load.

    ``stiffness``, ``load`` and ``gap_operator`` are in the (reduced) unknowns;
    ``solve(K, f)`` solves one linear system. ``active`` is the starting
    active set (default: the pairs closed at zero displacement).
    """
    b = gap_operator

    def energy(u: np.ndarray) -> float:
        g = np.minimum(gap0 + b @ u, 0.0)
        return float(0.5 * u @ (stiffness @ u) - load @ u + 0.5 * np.sum(penalty * g**2))

    def newton_point(closed: np.ndarray) -> np.ndarray:
        kc = sp.diags(np.where(closed, penalty, 0.0))
        return solve((stiffness + b.T @ kc @ b).tocsc(), load - b.T @ (kc @ gap0))

    closed = (gap0 <= 0) if active is None else active.copy()
    u, exact = newton_point(closed), True  # exact: u is the solution for the set ``closed``
    for it in range(1, max_iterations + 1):
        gap = gap0 + b @ u
        # Gaps within round-off of zero (a close-wound coil's untouched pairs) keep their state.
        tol = 1e-9 * max(
            float(np.max(np.abs(gap - gap0), initial=0.0)), float(np.max(np.abs(gap0), initial=0.0))
        )
        now = np.where(gap < -tol, True, np.where(gap > tol, False, closed))
        if exact and np.array_equal(now, closed):
            return u, closed, it
        target = newton_point(now)
        step, e0 = target - u, energy(u)
        alpha = 1.0
        while energy(u + alpha * step) > e0 and alpha > 1e-6:
            alpha *= 0.5
        exact = alpha == 1.0
        u = target if exact else u + alpha * step
        closed = now
    raise SolverError(f"contact active set did not settle in {max_iterations} iterations")
