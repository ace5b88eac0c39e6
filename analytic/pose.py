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
    """Tip position and bend angle for curvature κ [1/mm] over arc length L [mm] (eq. 9).

    The one eq. 9 of the package: the 3-D FEM, the section models and the
    virtual bench take their arc-end pose from here. The pose of a solved mesh's
    displaced end section is :func:`softcath.fem.nonlinear.post.measured_tip_pose`.

    Parameters
    ----------
    curvature
        κ [1/mm], a number or an array.
    arc_length
        L [mm], the deformed arc length L₀(1 + ε); broadcast against ``curvature``.

    Returns
    -------
    tip_x, tip_y, theta
        Position first, then orientation, the order of eq. 9's transform
        (:func:`pose_matrix`): tip position [mm] in the bending plane (frame in
        the module docstring) and bend angle θ = κL [rad]. A plain tuple of
        arrays, so the pose of a whole sweep of designs unpacks in one line.
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
