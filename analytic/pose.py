r"""Tip pose from constant curvature (paper eq. 9), and its θ → 0 limit.

Frame of the bending plane: the base at the origin, the catheter leaving
along +y ("up"), positive curvature bending toward +x::

    x_t = L (1 − cos θ)/θ,   y_t = L sin θ/θ,   θ = κ L.

Written as x_t = L·(θ/2)·sinc²(θ/2π) and y_t = L·sinc(θ/π) (numpy's
normalised sinc), which are exact and need no special case at θ = 0.
"""

from __future__ import annotations

import numpy as np

__all__ = ["tip_pose", "pose_matrix"]


def tip_pose(curvature, arc_length) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tip position and bend angle for curvature κ [1/mm] over arc length L [mm].

    Returns
    -------
    tip_x, tip_y
        Tip position [mm] in the bending plane (frame in the module docstring).
    theta
        Bend angle θ = κL [rad].
    """
    kappa = np.asarray(curvature, dtype=float)
    length = np.asarray(arc_length, dtype=float)
    theta = kappa * length
    half = theta / 2
    tip_x = length * half * np.sinc(half / np.pi) ** 2
    tip_y = length * np.sinc(theta / np.pi)
    return tip_x, tip_y, theta


def pose_matrix(curvature: float, arc_length: float) -> np.ndarray:
    """The homogeneous transform T of eq. 9 (4×4): tip orientation and position."""
    x, y, theta = tip_pose(curvature, arc_length)
    c, s = np.cos(theta), np.sin(theta)
    return np.array(
        [[-s, c, 0.0, float(x)], [c, s, 0.0, float(y)], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
    )
