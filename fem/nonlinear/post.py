"""Post-processing of a deformed tip: end rotation, bend angle, tip pose.

The bend angle is measured from the cross-section at the tip end: the rigid
rotation that best maps its reference nodes onto their deformed positions
(Kabsch / orthogonal Procrustes). That is robust to the section's own
distortion and defined for any angle up to ±180°.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "best_rotation",
    "bend_angle",
    "bend_angles",
    "TipPose",
    "tip_pose",
    "curvature_variation",
    "max_principal_strain",
]


def best_rotation(reference: np.ndarray, deformed: np.ndarray) -> np.ndarray:
    """Proper rotation R (3, 3) minimising Σ‖R (X − X̄) − (x − x̄)‖² (Kabsch)."""
    x0 = reference - reference.mean(axis=0)
    x1 = deformed - deformed.mean(axis=0)
    u, _, vt = np.linalg.svd(x1.T @ x0)
    d = np.sign(np.linalg.det(u @ vt))
    return u @ np.diag([1.0, 1.0, d]) @ vt


def bend_angle(
    nodes: np.ndarray,
    u: np.ndarray,
    end_mask: np.ndarray,
    *,
    axis: int = 2,
    toward: int = 1,
    sign: float = -1.0,
) -> float:
    """Bend angle [rad] of the section at ``end_mask``: rotation of the axis ``axis`` toward ``sign·e_toward``.

    Default: the catheter axis z turning toward −y (positive curvature, the
    project's sign convention). Returns atan2(sign·t_toward, t_axis) with t = R e_axis,
    so the range is (−π, π].
    """
    r = best_rotation(nodes[end_mask], nodes[end_mask] + u[end_mask])
    t = r[:, axis]
    return float(np.arctan2(sign * t[toward], t[axis]))


def bend_angles(nodes: np.ndarray, displacements: np.ndarray, end_mask: np.ndarray) -> np.ndarray:
    """Bend angle [rad] after each load step, unwrapped so it can pass ±π (a tip curling past a half turn)."""
    raw = np.array([bend_angle(nodes, u, end_mask) for u in displacements])
    return np.unwrap(np.concatenate([[0.0], raw]))[1:]


class TipPose(tuple):
    """(bend_angle [rad], tip_x [mm], tip_y [mm], arc_length [mm])."""

    __slots__ = ()

    def __new__(cls, bend_angle, tip_x, tip_y, arc_length):
        return super().__new__(cls, (bend_angle, tip_x, tip_y, arc_length))

    bend_angle = property(lambda s: s[0])
    tip_x = property(lambda s: s[1])
    tip_y = property(lambda s: s[2])
    arc_length = property(lambda s: s[3])


def tip_pose(nodes: np.ndarray, u: np.ndarray, end_mask: np.ndarray, *, axis_point=(0.0, 0.0)) -> TipPose:
    """Tip pose in the project's bending plane (paper eq. 9 frame).

    tip_x is the lateral displacement of the end section's centroid toward −y
    (the bending side), tip_y its height along z (base at z = 0); the arc
    length is estimated from the chord and the bend angle of a circular arc
    (chord = 2 L sin(θ/2)/θ), which is exact when the tip bends into an arc.
    """
    theta = bend_angle(nodes, u, end_mask)
    c = (nodes[end_mask] + u[end_mask]).mean(axis=0)
    tip_x = -(c[1] - axis_point[1])
    tip_y = c[2]
    chord = float(np.hypot(tip_x - 0.0, tip_y))
    arc = chord if abs(theta) < 1e-9 else chord * (theta / 2) / np.sin(theta / 2)
    return TipPose(theta, float(tip_x), float(tip_y), float(arc))


def curvature_variation(nodes: np.ndarray, u: np.ndarray, *, length: float, margin: float) -> float:
    """(max − min)/|mean| of the local curvature along the middle of the tip (``fem.json`` key).

    The sections at each z level of the (extruded) mesh between ``margin`` and
    ``length − margin`` are fitted with rigid rotations (Kabsch); the local
    curvature of each interval is the change of the bend angle over the
    distance between the deformed section centroids, the finite-rotation
    counterpart of the linear check's windowed fits.
    """
    z = np.round(nodes[:, 2], 9)
    levels = np.unique(z[(z >= margin - 1e-9) & (z <= length - margin + 1e-9)])
    if levels.size < 3:
        return float("nan")
    theta, cent = [], []
    for lv in levels:
        sel = z == lv
        theta.append(bend_angle(nodes, u, sel))
        cent.append((nodes[sel] + u[sel]).mean(axis=0))
    dtheta = np.diff(np.unwrap(theta))
    ds = np.linalg.norm(np.diff(np.asarray(cent), axis=0), axis=1)
    kappa = dtheta / ds
    mean = kappa.mean()
    return float((kappa.max() - kappa.min()) / abs(mean)) if mean != 0 else float("nan")


def max_principal_strain(f: np.ndarray) -> np.ndarray:
    """Largest principal (Biot) strain λ_max − 1 of deformation gradients ``f`` (..., 3, 3).

    The stretch-based strain equals the linear check's principal strain to
    first order, so the two ``max_strain`` values compare directly.
    """
    c = np.einsum("...aI,...aJ->...IJ", f, f)
    return np.sqrt(np.linalg.eigvalsh(c)[..., -1]) - 1.0
