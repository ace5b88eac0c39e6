"""Post-processing of a tip solution: curvature, elongation, pose, strains.

All functions take the P2 node coordinates (mm) and displacements (mm) of one
load case at unit pressure or at a given pressure; linear results scale with
pressure.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["BendingFit", "bending_fit", "principal_strain_max"]


@dataclass(frozen=True)
class BendingFit:
    """Bending measures from one displacement field.

    Attributes
    ----------
    curvature_per_mm
        From the quadratic fit of u_y(z) over the middle of the tip; positive
        bends toward -y (the channel), the project's convention.
    curvature_rotation_per_mm
        End-section rotation about x divided by L (the second estimate).
    elongation
        Axial strain at the stiffness-weighted centroid ``neutral_axis_y`` in the
        middle of the tip (bilinear fit of u_z over the fitted nodes).
    neutral_axis_y
        The FEM section's own axial-stiffness-weighted centroid (mm).
    curvature_variation
        (max - min) / |mean| of the local curvature along the middle of the tip.
    z_profile, curvature_profile
        Local curvature (1/mm) at window centres z (mm).
    """

    curvature_per_mm: float
    curvature_rotation_per_mm: float
    elongation: float
    neutral_axis_y: float
    curvature_variation: float
    z_profile: np.ndarray
    curvature_profile: np.ndarray


def bending_fit(
    nodes: np.ndarray,
    u: np.ndarray,
    *,
    length: float,
    margin: float,
    end_z: float,
    neutral_axis_y: float,
    n_windows: int = 8,
) -> BendingFit:
    """Fit curvature and elongation to a displacement field.

    Parameters
    ----------
    nodes, u
        Node coordinates and displacements, (n, 3), mm.
    length
        Tip length L (mm).
    margin
        Length (mm) excluded next to the clamp and next to the cap, where the
        section is not free to warp (Saint-Venant: about one diameter).
    end_z
        z of the end face (= L).
    neutral_axis_y
        Axial-stiffness-weighted centroid y of the section (mm), where the
        elongation is read.
    n_windows
        About how many (half-overlapping) windows the local-curvature profile
        uses along the middle; each has at least 5 z levels.
    """
    z = nodes[:, 2]
    z0, z1 = margin, length - margin
    mid = (z >= z0) & (z <= z1)
    # Section-average u_y per z level: the transverse deflection of the axis
    # without the in-plane (Poisson, lumen-bulge) scatter of single nodes.
    zs, v = _level_means(z[mid], u[mid, 1])
    c2, _, _ = np.polyfit(zs, v, 2)
    kappa = -2.0 * c2  # u_y'' < 0 bends toward -y: positive curvature
    end = np.abs(z - end_z) < 1e-9 * max(1.0, length) + 1e-6
    a = np.column_stack([np.ones(end.sum()), nodes[end, 0], nodes[end, 1]])
    coef, *_ = np.linalg.lstsq(a, u[end, 2], rcond=None)
    kappa_rot = coef[2] / length  # top fibres (y > ybar) stretch when bending toward -y
    # Elongation: axial strain at ybar in the middle, where Saint-Venant holds (the
    # beam models' regime): u_z = c0 + c1 z + (c2 + c3 z) y + (c4 + c5 z) x.
    xm, ym, zm = nodes[mid, 0], nodes[mid, 1], z[mid]
    a = np.column_stack([np.ones(zm.size), zm, ym, ym * zm, xm, xm * zm])
    c, *_ = np.linalg.lstsq(a, u[mid, 2], rcond=None)
    elong = c[1] + c[3] * neutral_axis_y
    # Local curvature: quadratic fits over sliding windows of `window` levels.
    window = max(5, zs.size // n_windows)
    kz, kk = [], []
    for start in range(0, zs.size - window + 1, max(1, window // 2)):
        s = slice(start, start + window)
        kz.append(zs[s].mean())
        kk.append(-2.0 * np.polyfit(zs[s], v[s], 2)[0])
    kk_arr = np.asarray(kk)
    variation = float((kk_arr.max() - kk_arr.min()) / abs(kk_arr.mean())) if kk_arr.size else np.nan
    return BendingFit(
        curvature_per_mm=float(kappa),
        curvature_rotation_per_mm=float(kappa_rot),
        elongation=float(elong),
        neutral_axis_y=float(neutral_axis_y),
        curvature_variation=variation,
        z_profile=np.asarray(kz),
        curvature_profile=kk_arr,
    )


def _level_means(z: np.ndarray, val: np.ndarray, n_bins: int = 200):
    """Average ``val`` over nodes of equal z (extruded meshes) or over z bins."""
    levels, inv = np.unique(np.round(z, 9), return_inverse=True)
    if levels.size > n_bins:  # unstructured mesh: bin instead
        edges = np.linspace(z.min(), z.max(), n_bins + 1)
        inv = np.clip(np.searchsorted(edges, z) - 1, 0, n_bins - 1)
    cnt = np.bincount(inv)
    ok = cnt > 0
    zm = np.bincount(inv, weights=z)[ok] / cnt[ok]
    vm = np.bincount(inv, weights=val)[ok] / cnt[ok]
    return zm, vm


def principal_strain_max(grad_u: np.ndarray) -> np.ndarray:
    """Largest principal value of the small strain, per point.

    Parameters
    ----------
    grad_u
        Displacement gradients, shape (3, 3, ...) with ``grad_u[i, j] = du_i/dx_j``.
    """
    eps = 0.5 * (grad_u + np.swapaxes(grad_u, 0, 1))
    flat = np.moveaxis(eps.reshape(3, 3, -1), -1, 0)
    return np.linalg.eigvalsh(flat)[:, -1].reshape(grad_u.shape[2:])
