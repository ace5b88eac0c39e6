"""The centre line of a helical coil's wire, cut into straight frame elements.

The helix runs along +z from z = 0: node ``k`` sits at angle φ_k = 2π k / m
(m elements per turn) and height p φ_k / (2π). Node ``k`` and node ``k + m``
are one turn apart at the same angle, directly above each other: that pair
is where neighbouring turns of a close-wound coil touch (``softcath.fem.coil.contact``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.design.errors import DesignError

__all__ = ["HelixMesh", "helix_mesh"]


@dataclass(frozen=True)
class HelixMesh:
    """Nodes and two-node elements along a helix.

    Attributes
    ----------
    nodes
        (n_nodes, 3) coordinates [mm].
    elements
        (n_elements, 2) node indices, consecutive along the wire.
    radius
        Helix (mean coil) radius R [mm].
    pitch
        Axial advance per turn p [mm].
    turns
        Number of turns N.
    elements_per_turn
        m; node k + m is one turn above node k.
    """

    nodes: np.ndarray
    elements: np.ndarray
    radius: float
    pitch: float
    turns: int
    elements_per_turn: int

    @property
    def helix_angle(self) -> float:
        """α = atan(p / (2πR)) [rad], the wire's inclination to the coil's cross-section."""
        return float(np.arctan2(self.pitch, 2 * np.pi * self.radius))

    @property
    def length(self) -> float:
        """Axial length N·p of the helix centre line [mm]."""
        return self.turns * self.pitch

    def turn_nodes(self, turn: int) -> np.ndarray:
        """Node indices of turn ``turn`` (0-based), both end nodes included (m + 1 nodes)."""
        m = self.elements_per_turn
        return np.arange(turn * m, (turn + 1) * m + 1)


#: Most frame elements per turn: the stiffnesses converge to 0.1 % by 96 (48 is the default);
#: beyond 10⁴ the model only grows (10⁸ reached 10 GB) without changing the answer.
MAX_ELEMENTS_PER_TURN = 10_000


def helix_mesh(*, radius: float, pitch: float, turns: int, elements_per_turn: int) -> HelixMesh:
    """A helix of ``turns`` turns, ``elements_per_turn`` straight elements per turn."""
    if not radius > 0:
        raise DesignError("radius", radius, "must be > 0 mm")
    if not pitch > 0:
        raise DesignError("pitch", pitch, "must be > 0 mm")
    if isinstance(turns, bool) or not isinstance(turns, (int, np.integer)) or turns < 1:
        raise DesignError("turns", turns, "must be an integer >= 1")
    m = elements_per_turn
    if isinstance(m, bool) or not isinstance(m, (int, np.integer)) or m < 6:
        raise DesignError("elements_per_turn", m, "must be an integer >= 6")
    if m > MAX_ELEMENTS_PER_TURN:
        raise DesignError(
            "elements_per_turn", m, f"must be <= {MAX_ELEMENTS_PER_TURN} (the stiffnesses converge by 96)"
        )
    phi = 2 * np.pi * np.arange(turns * m + 1) / m
    nodes = np.column_stack([radius * np.cos(phi), radius * np.sin(phi), pitch * phi / (2 * np.pi)])
    elements = np.column_stack([np.arange(turns * m), np.arange(1, turns * m + 1)])
    return HelixMesh(nodes, elements, float(radius), float(pitch), int(turns), int(m))
