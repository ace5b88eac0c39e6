"""Post-processing of finite-strain fields against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from softcath.fem.nonlinear.post import curvature_variation, max_principal_strain, midspan_bend


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


def _prism(length=5.0, levels=17):
    """Nodes of a prismatic body: an asymmetric section (its node centroid off the z axis) at z levels."""
    t = np.linspace(0.0, 2 * np.pi, 13, endpoint=False)
    ring = np.column_stack([0.4 * np.cos(t), 0.4 * np.sin(t)])
    inner = np.column_stack([0.1 + 0.12 * np.cos(t[::2]), -0.15 + 0.06 * np.sin(t[::2])])
    section = np.vstack([ring, inner, [[0.25, 0.1], [-0.05, 0.3]]])
    z = np.linspace(0.0, length, levels)
    return np.column_stack([np.tile(section, (z.size, 1)), np.repeat(z, section.shape[0])])


def _flexure(nodes, kappa, stretch, *, axis=None, contraction=1.0):
    """Displacement of Rivlin's flexure: the line through ``axis`` (X, Y) bends into a circle of curvature
    ``kappa`` toward -y with axial stretch ``stretch``; sections stay plane, are scaled in-plane by
    ``contraction`` about the axis and rotate rigidly by θ = kappa · stretch · Z. A rigid rotation about x
    and a translation are added on top (they change θ by a constant)."""
    ax, ay = nodes[:, :2].mean(axis=0) if axis is None else axis
    x, y, z = nodes.T
    theta = kappa * stretch * z
    rho = 1.0 / kappa
    r = rho + contraction * (y - ay)
    new = np.column_stack([ax + contraction * (x - ax), ay - rho + r * np.cos(theta), r * np.sin(theta)])
    c, s = np.cos(0.3), np.sin(0.3)
    rigid = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return new @ rigid.T + np.array([0.2, -0.1, 0.05]) - nodes


@pytest.mark.parametrize(
    ("kappa", "stretch"),
    [(0.02, 1.0005), (0.35, 1.08), (-0.2, 0.93), (1.2, 1.1)],  # the last turns 2.5 rad inside the window
)
def test_midspan_bend_recovers_flexure_exactly(kappa, stretch):
    nodes = _prism()
    u = _flexure(nodes, kappa, stretch, contraction=0.97)
    m = midspan_bend(nodes, u, length=5.0)
    assert m.stations == pytest.approx(np.linspace(0.0, 5.0, 17)[5:12])  # Z in [1.5, 3.5] mm
    assert m.curvature == pytest.approx(kappa, rel=1e-9)
    assert m.bend_rate == pytest.approx(stretch * kappa, rel=1e-9)
    assert m.stretch == pytest.approx(stretch, rel=1e-9)
    assert np.diff(m.angles) == pytest.approx(kappa * stretch * np.diff(m.stations), rel=1e-9)


def test_midspan_bend_follows_the_given_axis_and_ignores_the_end_zones():
    nodes = _prism()
    axis = (0.1, -0.3)  # a line other than the node centroid: its own stretch and curvature
    u = _flexure(nodes, 0.3, 1.05, axis=axis)
    z = nodes[:, 2]
    ends = (z < 1.5 - 1e-9) | (z > 3.5 + 1e-9)
    rng = np.random.default_rng(0)
    u[ends] += 0.05 * rng.standard_normal((ends.sum(), 3))  # clamp and cap zones: anything
    m = midspan_bend(nodes, u, length=5.0, axis_point=axis)
    assert (m.curvature, m.bend_rate) == pytest.approx((0.3, 0.3 * 1.05), rel=1e-9)
    # the same field read along the node centroid line: θ(Z) is the same, that line is longer
    # (it lies 0.3 + ȳ mm farther from the centre of curvature): stretch 1.05 (1 + 0.3 · Δy)
    ybar = nodes[:, 1].mean()
    m2 = midspan_bend(nodes, u, length=5.0)
    assert m2.bend_rate == pytest.approx(0.3 * 1.05, rel=1e-9)
    assert m2.stretch == pytest.approx(1.05 * (1 + 0.3 * (ybar - axis[1])), rel=1e-9)
    w = midspan_bend(nodes, u, length=5.0, window=(0.2, 0.8))  # reaches into the scrambled zones
    assert w.curvature != pytest.approx(0.3, rel=1e-3)


def test_midspan_bend_needs_two_stations_and_a_valid_window():
    nodes = _prism(levels=3)  # z = 0, 2.5, 5: one level inside [1.5, 3.5]
    m = midspan_bend(nodes, np.zeros_like(nodes), length=5.0)
    assert np.isnan(m.curvature) and np.isnan(m.bend_rate) and m.stations.size == 1
    with pytest.raises(ValueError, match=r"window = \(0.7, 0.3\): must be 0 <= start < end <= 1"):
        midspan_bend(nodes, np.zeros_like(nodes), length=5.0, window=(0.7, 0.3))
