"""A linear 3-D frame of straight two-node Timoshenko beams (6 DOF per node), round section.

DOFs per node: (u_x, u_y, u_z, θ_x, θ_y, θ_z), global axes. The element
stiffness is the shear-flexible beam of Przemieniecki (*Theory of Matrix
Structural Analysis*, 1968, §5.6): exact for end loads on a straight prismatic
beam (cubic deflection plus uniform shear strain), so a cantilever's tip
deflection is PL³/(3EI) + PL/(κGA) with one element. Shear coefficient of a
solid circle after Cowper (1966): κ = 6(1 + ν)/(7 + 6ν).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from softcath.design.errors import DesignError

__all__ = ["WireSection", "element_stiffness_local", "frame_stiffness", "element_frames"]


@dataclass(frozen=True, kw_only=True)
class WireSection:
    """Round wire of diameter ``diameter`` [mm], isotropic E [MPa], ν."""

    diameter: float
    youngs_modulus: float
    poisson_ratio: float

    def __post_init__(self) -> None:
        for name in ("diameter", "youngs_modulus"):
            if not getattr(self, name) > 0:
                raise DesignError(name, getattr(self, name), "must be > 0")
        if not -1 < self.poisson_ratio < 0.5:
            raise DesignError("poisson_ratio", self.poisson_ratio, "must be in (-1, 0.5)")

    @property
    def shear_modulus(self) -> float:
        return self.youngs_modulus / (2 * (1 + self.poisson_ratio))

    @property
    def area(self) -> float:
        return np.pi * self.diameter**2 / 4

    @property
    def second_moment(self) -> float:
        """I = π d⁴ / 64 about any diameter."""
        return np.pi * self.diameter**4 / 64

    @property
    def polar_moment(self) -> float:
        """J = π d⁴ / 32 (torsion constant of a solid circle)."""
        return np.pi * self.diameter**4 / 32

    @property
    def shear_coefficient(self) -> float:
        nu = self.poisson_ratio
        return 6 * (1 + nu) / (7 + 6 * nu)


def element_stiffness_local(length: np.ndarray, section: WireSection) -> np.ndarray:
    """(n, 12, 12) local stiffness matrices; local x along the element."""
    L = np.asarray(length, dtype=float)
    E, G = section.youngs_modulus, section.shear_modulus
    A, I, J = section.area, section.second_moment, section.polar_moment
    phi = 12 * E * I / (section.shear_coefficient * G * A * L**2)
    k = np.zeros((L.size, 12, 12))
    ea, gj = E * A / L, G * J / L
    for a, b, v in ((0, 6, ea), (3, 9, gj)):
        k[:, a, a] = k[:, b, b] = v
        k[:, a, b] = k[:, b, a] = -v
    c = E * I / ((1 + phi) * L**3)
    base = np.array(
        [
            [12 * c, 6 * c * L, -12 * c, 6 * c * L],
            [6 * c * L, (4 + phi) * c * L**2, -6 * c * L, (2 - phi) * c * L**2],
            [-12 * c, -6 * c * L, 12 * c, -6 * c * L],
            [6 * c * L, (2 - phi) * c * L**2, -6 * c * L, (4 + phi) * c * L**2],
        ]
    ).transpose(2, 0, 1)
    # x-y plane: (v1, θz1, v2, θz2); x-z plane: (w1, θy1, w2, θy2) with θy = -dw/dx.
    for dofs, sign in (((1, 5, 7, 11), np.array([1, 1, 1, 1])), ((2, 4, 8, 10), np.array([1, -1, 1, -1]))):
        idx = np.array(dofs)
        k[:, idx[:, None], idx[None, :]] = base * np.outer(sign, sign)
    return k


def element_frames(nodes: np.ndarray, elements: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lengths (n,) and rotation matrices (n, 3, 3) whose rows are the local axes (x along the element).

    The round section makes the choice of local y, z immaterial; y is taken
    perpendicular to x and to the global axis least aligned with x.
    """
    d = nodes[elements[:, 1]] - nodes[elements[:, 0]]
    length = np.linalg.norm(d, axis=1)
    if np.any(length <= 0):
        raise DesignError("elements", int(np.argmin(length)), "has zero length")
    ex = d / length[:, None]
    helper = np.eye(3)[np.argmin(np.abs(ex), axis=1)]
    ey = np.cross(helper, ex)
    ey /= np.linalg.norm(ey, axis=1)[:, None]
    ez = np.cross(ex, ey)
    return length, np.stack([ex, ey, ez], axis=1)


def frame_stiffness(nodes: np.ndarray, elements: np.ndarray, section: WireSection) -> sp.csr_matrix:
    """Global stiffness (6 n_nodes square, CSR) of the frame."""
    length, rot = element_frames(nodes, elements)
    k_local = element_stiffness_local(length, section)
    t = np.zeros((len(length), 12, 12))
    for b in range(4):
        t[:, 3 * b : 3 * b + 3, 3 * b : 3 * b + 3] = rot
    k_global = np.einsum("eji,ejk,ekl->eil", t, k_local, t)
    dofs = (6 * elements[:, :, None] + np.arange(6)).reshape(len(elements), 12)
    rows = np.broadcast_to(dofs[:, :, None], k_global.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], k_global.shape).ravel()
    n = 6 * len(nodes)
    return sp.coo_matrix((k_global.ravel(), (rows, cols)), shape=(n, n)).tocsr()
