"""Post-processing of finite-strain fields against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from softcath.fem.nonlinear.post import curvature_variation, max_principal_strain


def test_max_principal_strain_closed_forms():
    gamma = 0.4
    shear = np.array([[1.0, gamma, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    c, s = np.cos(1.1), np.sin(1.1)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    f = np.stack([np.diag([1.1, 0.97, 1.0]), shear, rot, rot @ np.diag([1.0, 1.0, 1.25])])
    expected = [0.1, gamma / 2 + np.sqrt(1 + gamma**2 / 4) - 1.0, 0.0, 0.25]
    assert max_principal_strain(f) == pytest.approx(expected, abs=1e-14)


def _arc(nodes: np.ndarray, kappa_of_z) -> np.ndarray:
    """Displacement that bends the z axis toward -y with local curvature kappa(z); sections stay rigid."""
    z = nodes[:, 2]
    zz = np.linspace(0.0, z.max(), 4001)
    theta_grid = np.concatenate(
        [[0.0], np.cumsum(0.5 * (kappa_of_z(zz[1:]) + kappa_of_z(zz[:-1])) * np.diff(zz))]
    )
    yc = np.concatenate(
        [[0.0], np.cumsum(-0.5 * (np.sin(theta_grid[1:]) + np.sin(theta_grid[:-1])) * np.diff(zz))]
    )
    zc = np.concatenate(
        [[0.0], np.cumsum(0.5 * (np.cos(theta_grid[1:]) + np.cos(theta_grid[:-1])) * np.diff(zz))]
    )
    th, y0, z0 = (np.interp(z, zz, a) for a in (theta_grid, yc, zc))
    x, y = nodes[:, 0], nodes[:, 1]
    new = np.column_stack([x, y0 + y * np.cos(th), z0 + y * np.sin(th)])
    return new - nodes


def _grid(length=5.0, levels=21):
    x, y, z = np.meshgrid([-0.3, 0.0, 0.3], [-0.3, 0.0, 0.3], np.linspace(0.0, length, levels), indexing="ij")
    return np.column_stack([x.ravel(), y.ravel(), z.ravel()])


def test_curvature_variation_of_an_arc_is_zero_and_of_a_ramp_is_its_spread():
    nodes = _grid()
    arc = _arc(nodes, lambda z: np.full_like(z, 0.3))  # 1.5 rad over 5 mm: a large bend
    assert curvature_variation(nodes, arc, length=5.0, margin=0.8) == pytest.approx(0.0, abs=1e-6)
    ramp = _arc(nodes, lambda z: 0.1 + 0.04 * z)
    # intervals between the levels inside [0.8, 4.2] mm (spacing 0.25): curvature at interval midpoints
    levels = np.linspace(0.0, 5.0, 21)
    inside = levels[(levels >= 0.8) & (levels <= 4.2)]
    mids = 0.5 * (inside[1:] + inside[:-1])
    k = 0.1 + 0.04 * mids
    expected = (k.max() - k.min()) / k.mean()
    # Δθ over the chord between section centres, not the arc: relative error (κ Δs)²/24 ~ 2e-4 per
    # interval, plus the displacement field's own trapezoid integration
    assert curvature_variation(nodes, ramp, length=5.0, margin=0.8) == pytest.approx(expected, rel=2e-3)
