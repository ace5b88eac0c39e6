"""Post-processing of a deformed tip: end rotation, bend angle, tip pose, mid-span curvature.

The bend angle is measured from the cross-section at the tip end: the rigid
rotation that best maps its reference nodes onto their deformed positions
(Kabsch / orthogonal Procrustes). That is robust to the section's own
distortion and defined for any angle up to ±180°. :func:`midspan_bend` applies
the same fit to sections along the middle of the tip, away from the clamp and
the cap, for the curvature of the uniformly bent part.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "best_rotation",
    "bend_angle",
    "bend_angles",
    "MeasuredTipPose",
    "measured_tip_pose",
    "curvature_variation",
    "MIDSPAN",
    "MidspanBend",
    "midspan_bend",
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
    """Bend angle [rad] of the section at ``end_mask``: rotation of the axis ``axis`` toward
    ``sign·e_toward``.

    Default: the catheter axis z turning toward −y (positive curvature, the
    project's sign convention). Returns atan2(sign·t_toward, t_axis) with t = R e_axis,
    so the range is (−π, π].
    """
    r = best_rotation(nodes[end_mask], nodes[end_mask] + u[end_mask])
    return _section_angle(r, axis, toward, sign)


def bend_angles(nodes: np.ndarray, displacements: np.ndarray, end_mask: np.ndarray) -> np.ndarray:
    """Bend angle [rad] after each load step, unwrapped so it can pass ±π (a tip curling past a half turn)."""
    raw = np.array([bend_angle(nodes, u, end_mask) for u in displacements])
    return np.unwrap(np.concatenate([[0.0], raw]))[1:]


@dataclass(frozen=True)
class MeasuredTipPose:
    """Pose of a solved mesh's displaced end section (position, then angle, as eq. 9).

    Attributes
    ----------
    x_mm, y_mm
        End-section centroid in the bending plane [mm] (paper eq. 9 frame).
    angle_rad
        Bend angle of the end section [rad].
    arc_length_mm
        Arc length of the circular arc through the tip [mm], from chord and angle.
    """

    x_mm: float
    y_mm: float
    angle_rad: float
    arc_length_mm: float


def measured_tip_pose(
    nodes: np.ndarray, u: np.ndarray, end_mask: np.ndarray, *, axis_point=(0.0, 0.0)
) -> MeasuredTipPose:
    """Tip pose measured on displaced nodes, in the project's bending plane (paper eq. 9 frame).

    Not eq. 9 itself (:func:`softcath.analytic.pose.tip_pose`): the pose is read off
    the solved mesh's end section, whatever shape the tip bent into.

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
    return MeasuredTipPose(
        x_mm=float(tip_x), y_mm=float(tip_y), angle_rad=float(theta), arc_length_mm=float(arc)
    )


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


#: Default mid-span window, as fractions of the bending length L (see :func:`midspan_bend`).
MIDSPAN = (0.3, 0.7)


@dataclass(frozen=True)
class MidspanBend:
    """Bend of the middle of the tip (:func:`midspan_bend`).

    Attributes
    ----------
    bend_rate : float
        dθ/dZ [rad/mm]: least-squares slope of the section rotation over the
        undeformed axial coordinate Z.
    curvature : float
        dθ/ds [1/mm] = ``bend_rate / stretch``, s the arc length along the
        deformed centroid line.
    stretch : float
        λ_c [-]: arc length of the deformed centroid line between the first and
        last station over their distance in Z.
    stations : numpy.ndarray
        Z of the stations [mm], increasing.
    angles : numpy.ndarray
        Section rotation θ(Z) at each station [rad] (unwrapped along Z).
    centroids : numpy.ndarray
        (n, 3) deformed positions of the centroid line at the stations [mm].
    """

    bend_rate: float
    curvature: float
    stretch: float
    stations: np.ndarray
    angles: np.ndarray
    centroids: np.ndarray


def _section_angle(rotation: np.ndarray, axis: int, toward: int, sign: float) -> float:
    """atan2(sign·t_toward, t_axis) of t = R e_axis: the turn of ``axis`` toward ``sign·e_toward`` [rad]."""
    t = rotation[:, axis]
    return float(np.arctan2(sign * t[toward], t[axis]))


def midspan_bend(
    nodes: np.ndarray,
    u: np.ndarray,
    *,
    length: float,
    window: tuple[float, float] = MIDSPAN,
    axis_point: tuple[float, float] | None = None,
    min_nodes: int = 3,
) -> MidspanBend:
    """Curvature of the middle of the tip from the rotations of its sections.

    Every z level of the mesh's nodes with ``window[0]·L ≤ Z ≤ window[1]·L`` is a
    station. Each station's section is fitted with the rigid motion that best maps
    its reference nodes onto their deformed positions (Kabsch, as
    :func:`bend_angle`): its rotation gives θ(Z) (the axis z turning toward −y is
    positive), and the fitted motion carries the reference centroid line
    (``axis_point``, the same material line at every station) to its deformed
    position. Then

    - ``bend_rate`` = dθ/dZ, the least-squares slope of θ over the undeformed Z;
    - ``stretch`` λ_c: the deformed centroid line's arc length over the window's
      ΔZ, each interval's arc taken as the circular arc through its two centroid
      points whose tangent turns by the interval's Δθ (arc = chord · (Δθ/2) / sin(Δθ/2));
    - ``curvature`` = dθ/ds = ``bend_rate`` / λ_c.

    For a prismatic body bent into an arc of curvature κ with a centroid-line
    stretch λ (Rivlin's flexure: plane sections stay plane and rigidly rotated),
    this returns ``bend_rate`` = λκ and ``curvature`` = κ exactly, at any angle.

    The default window, the middle 40 % of L, keeps the stations out of the end
    zones, where the section is not in the uniform (Saint-Venant) bending state:
    the rigid clamp restrains the section's own deformation at Z = 0, and the
    sealed cap (a silicone plug, the last ``cap_thickness``) carries the pressure
    load into the wall at the far end. Such end disturbances decay over about
    one section diameter; for the paper's tip (L = 5 mm, coil OD 0.8 mm, cap
    0.3 mm) the window [1.5, 3.5] mm lies ≥ 1.9 diameters from the clamp and
    ≥ 1.5 from the cap's inner face, and on the default mesh (4 layers, P2
    nodes) it holds three stations, Z = 1.76, 2.35, 2.94 mm. Measured there
    (lumen load, 0.01 MPa, 6 and 8 layers): the local dθ/dZ between levels stays
    within ±4 % of the mid-span value from Z ≈ 1 to 4 mm and falls to about −15 %
    at 4.5 mm and −50 % at 0.2 mm; on 8 layers the windows [0.2, 0.8], [0.3, 0.7]
    and [0.4, 0.6] agree within 0.3 %.

    Parameters
    ----------
    nodes : numpy.ndarray
        (n, 3) reference node positions [mm], the tip's axis along z from the
        clamp (Z = 0) to the tip end (Z = ``length``).
    u : numpy.ndarray
        (n, 3) displacements [mm].
    length : float
        Bending length L [mm].
    window : tuple of float
        (start, end) of the mid-span as fractions of ``length``, 0 ≤ start < end ≤ 1.
    axis_point : tuple of float, optional
        Reference (X, Y) of the centroid line [mm]; default: the mean reference
        position of the stations' nodes.
    min_nodes : int
        z levels with fewer nodes (not a whole section) are not stations.

    Returns
    -------
    MidspanBend
        All NaN (and no stations) when the window holds fewer than two stations.

    Raises
    ------
    ValueError
        If ``window`` is not 0 ≤ start < end ≤ 1.
    """
    w0, w1 = _check_window(window)
    nodes = np.asarray(nodes, float)
    u = np.asarray(u, float).reshape(nodes.shape)
    z = np.round(nodes[:, 2], 9)
    levels = _stations(z, length, w0, w1, min_nodes)
    if levels.size < 2:
        return _no_stations(levels)
    return _bend_of_stations(nodes, u, z, levels, axis_point)


def _check_window(window) -> tuple[float, float]:
    """The mid-span window as (start, end) fractions, checked."""
    w0, w1 = (float(w) for w in window)
    if not (0.0 <= w0 < w1 <= 1.0):
        raise ValueError(f"window = {tuple(window)!r}: must be 0 <= start < end <= 1 (fractions of length)")
    return w0, w1


def _stations(z: np.ndarray, length: float, w0: float, w1: float, min_nodes: int) -> np.ndarray:
    """The z levels inside the window with at least ``min_nodes`` nodes, increasing."""
    tol = 1e-9 * max(float(length), 1.0)
    inside = (z >= w0 * length - tol) & (z <= w1 * length + tol)
    levels, counts = np.unique(z[inside], return_counts=True)
    return levels[counts >= min_nodes]


def _no_stations(levels: np.ndarray) -> MidspanBend:
    """The all-NaN result of a window with fewer than two stations."""
    nan = float("nan")
    return MidspanBend(nan, nan, nan, levels, np.full(levels.shape, nan), np.full((levels.size, 3), nan))


def _bend_of_stations(nodes, u, z, levels, axis_point) -> MidspanBend:
    """Fit each station's rigid rotation and reduce the rotations and centroids to the mid-span bend."""
    sections = [z == lv for lv in levels]
    if axis_point is None:
        in_sections = np.any(sections, axis=0)
        axis_point = nodes[in_sections, :2].mean(axis=0)
    theta, cent = [], []
    for lv, sel in zip(levels, sections, strict=True):
        ref, cur = nodes[sel], nodes[sel] + u[sel]
        r = best_rotation(ref, cur)
        theta.append(_section_angle(r, 2, 1, -1.0))
        a = np.array([axis_point[0], axis_point[1], lv])
        cent.append(cur.mean(axis=0) + r @ (a - ref.mean(axis=0)))
    theta = np.unwrap(np.asarray(theta))
    cent = np.asarray(cent)
    bend_rate = float(np.polyfit(levels, theta, 1)[0])
    chord = np.linalg.norm(np.diff(cent, axis=0), axis=1)
    arc = chord / np.sinc(np.diff(theta) / (2 * np.pi))  # np.sinc(x) = sin(πx)/(πx)
    stretch = float(arc.sum() / (levels[-1] - levels[0]))
    return MidspanBend(bend_rate, bend_rate / stretch, stretch, levels, theta, cent)


def max_principal_strain(f: np.ndarray) -> np.ndarray:
    """Largest principal (Biot) strain λ_max − 1 of deformation gradients ``f`` (..., 3, 3).

    The stretch-based strain equals the linear check's principal strain to
    first order, so the two ``max_strain`` values compare directly.
    """
    c = np.einsum("...aI,...aJ->...IJ", f, f)
    return np.sqrt(np.linalg.eigvalsh(c)[..., -1]) - 1.0
