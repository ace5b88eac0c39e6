"""Post-processing on synthetic fields with known curvature and elongation."""

from __future__ import annotations

import numpy as np
import pytest

from softcath.fem.post import bending_fit, principal_strain_max


def _beam_nodes(length=5.0, n=41):
    rng = np.random.default_rng(0)
    z = np.repeat(np.linspace(0, length, n), 30)
    xy = rng.uniform(-0.3, 0.3, (z.size, 2))
    return np.column_stack([xy, z])


def test_bending_fit_recovers_curvature_and_elongation():
    kappa, eps, ybar, length = 0.07, 0.004, -0.1, 5.0
    x = _beam_nodes(length)
    y, z = x[:, 1], x[:, 2]
    # small-strain pure bending toward -y plus stretch: u_y = -k z^2/2, u_z = (eps + k (y - ybar)) z
    u = np.column_stack([np.zeros(len(z)), -kappa * z**2 / 2, (eps + kappa * (y - ybar)) * z])
    fit = bending_fit(x, u, length=length, margin=0.8, end_z=length, neutral_axis_y=ybar)
    assert fit.curvature_per_mm == pytest.approx(kappa, rel=1e-10)
    assert fit.curvature_rotation_per_mm == pytest.approx(kappa, rel=1e-10)
    assert fit.elongation == pytest.approx(eps, rel=1e-10)
    assert fit.curvature_variation < 1e-8  # a perfect arc


def test_curvature_variation_sees_a_linear_moment():
    x = _beam_nodes()
    z = x[:, 2]
    # kappa(z) = 0.1 (1 - z/10): u_y'' = -kappa(z)
    u = np.column_stack([np.zeros(len(z)), -0.1 * (z**2 / 2 - z**3 / 60), np.zeros(len(z))])
    fit = bending_fit(x, u, length=5.0, margin=0.8, end_z=5.0, neutral_axis_y=0.0)
    # exact spread over the window centres, which lie inside [0.8, 4.2]
    zc = fit.z_profile
    expected = (0.1 * (zc.max() - zc.min()) / 10) / (0.1 * (1 - zc.mean() / 10))
    assert fit.curvature_variation == pytest.approx(expected, rel=1e-6)


def test_principal_strain_of_a_known_tensor():
    g = np.zeros((3, 3, 1))
    g[0, 0], g[1, 1], g[0, 1], g[1, 0] = 0.01, -0.02, 0.006, 0.0  # eps_xy = 0.003
    e = np.array([[0.01, 0.003], [0.003, -0.02]])
    assert principal_strain_max(g)[0] == pytest.approx(np.linalg.eigvalsh(e).max(), rel=1e-12)
