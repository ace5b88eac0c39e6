"""Hyperelastic laws: consistency of P and A, objectivity, small-strain limit, input checks."""

import numpy as np
import pytest

from softcath.design.errors import DesignError
from softcath.fem.hyperelastic.laws import (
    AnisotropicSVK,
    Yeoh,
    isotropic_from_young,
    isotropic_tensor,
    neo_hookean,
    transversely_isotropic,
)

LAWS = {
    "yeoh": Yeoh(c1=0.017, c2=-0.0002, c3=0.000023, bulk_modulus=0.85),
    "neo_hookean": neo_hookean(shear_modulus=0.8, bulk_modulus=20.0),
    "coil_svk": AnisotropicSVK(
        transversely_isotropic(axial_modulus=1.24, transverse_modulus=1.5e5, axial_shear_modulus=0.5)
    ),
}


def _random_f(n=6, scale=0.25, seed=0):
    rng = np.random.default_rng(seed)
    f = np.eye(3) + scale * rng.standard_normal((n, 3, 3))
    return f[np.linalg.det(f) > 0.2]


@pytest.mark.parametrize("name", sorted(LAWS))
@pytest.mark.parametrize("volumetric", [True, False])
def test_stress_and_tangent_are_derivatives(name, volumetric):
    law = LAWS[name]
    f = _random_f()
    p, a = law.stress_tangent(f, volumetric=volumetric)
    h = 1e-6
    p_fd, a_fd = np.zeros_like(p), np.zeros_like(a)
    for k in range(3):
        for m in range(3):
            d = np.zeros((3, 3))
            d[k, m] = h
            p_fd[..., k, m] = (
                law.energy(f + d, volumetric=volumetric) - law.energy(f - d, volumetric=volumetric)
            ) / (2 * h)
            a_fd[..., k, m] = (
                law.stress_tangent(f + d, volumetric=volumetric)[0]
                - law.stress_tangent(f - d, volumetric=volumetric)[0]
            ) / (2 * h)
    # central differences: truncation ~h^2 |W'''| plus round-off ~eps |W| / h, both far below 1e-6 relative
    assert np.abs(p - p_fd).max() <= 1e-6 * np.abs(p).max()
    assert np.abs(a - a_fd).max() <= 1e-6 * np.abs(a).max()


@pytest.mark.parametrize("name", sorted(LAWS))
def test_objective_under_rotation(name):
    law = LAWS[name]
    f = _random_f(seed=3)
    q, _ = np.linalg.qr(np.random.default_rng(7).standard_normal((3, 3)))
    q *= np.sign(np.linalg.det(q))
    p, _ = law.stress_tangent(f)
    pq, _ = law.stress_tangent(q @ f)
    # exact identities P(QF) = Q P(F), W(QF) = W(F): only round-off separates them
    np.testing.assert_allclose(pq, q @ p, atol=1e-12 * np.abs(p).max())
    np.testing.assert_allclose(law.energy(q @ f), law.energy(f), rtol=1e-11)


@pytest.mark.parametrize("name", sorted(LAWS))
def test_small_strain_limit_is_the_linear_law(name):
    law = LAWS[name]
    p, a = law.stress_tangent(np.eye(3)[None])
    c = law.small_strain_tensor()
    # at F = I the stress vanishes and A equals the linear stiffness exactly (up to round-off)
    assert np.abs(p).max() <= 1e-12 * np.abs(c).max()
    np.testing.assert_allclose(a[0], c, atol=1e-10 * np.abs(c).max())


def test_isotropic_from_young_reproduces_e_and_nu():
    law = isotropic_from_young(youngs_modulus=2.46, poisson_ratio=0.49)
    c = law.small_strain_tensor()
    # uniaxial compliance of the linearised law: E = 1/S_zzzz, nu = -S_xxzz/S_zzzz (exact)
    voigt = np.array([[c[i, i, j, j] for j in range(3)] for i in range(3)])
    s = np.linalg.inv(voigt)
    assert 1 / s[2, 2] == pytest.approx(2.46, rel=1e-12)
    assert -s[0, 2] / s[2, 2] == pytest.approx(0.49, rel=1e-12)


def test_yeoh_from_material_keeps_c1_and_nu():
    law = isotropic_from_young(youngs_modulus=0.102, poisson_ratio=0.49, yeoh=(0.017, -0.0002, 2.3e-5))
    assert law.shear_modulus == pytest.approx(0.034)
    lam_mu = isotropic_tensor(lam=law.bulk_modulus - 2 * 0.034 / 3, mu=0.034)
    np.testing.assert_allclose(law.small_strain_tensor(), lam_mu)
    nu = (3 * law.bulk_modulus - 2 * 0.034) / (2 * (3 * law.bulk_modulus + 0.034))
    assert nu == pytest.approx(0.49, rel=1e-12)


def test_neo_hookean_uniaxial_incompressible_closed_form():
    # near-incompressible (kappa/mu = 1e5) uniaxial stretch lam: P_zz = mu (lam - 1/lam^2) (Treloar);
    # compressibility shifts it by O(mu/kappa) = 1e-5, so 1e-4 relative is safe.
    mu, lam = 1.0, 1.8
    law = neo_hookean(shear_modulus=mu, bulk_modulus=1e5)
    lat = lam**-0.5
    for _ in range(30):  # Newton on the lateral stretch for zero lateral stress
        f = np.diag([lat, lat, lam])[None]
        p, a = law.stress_tangent(f)
        lat -= p[0, 0, 0] / (a[0, 0, 0, 0, 0] + a[0, 0, 0, 1, 1])
    p, _ = law.stress_tangent(np.diag([lat, lat, lam])[None])
    assert p[0, 2, 2] == pytest.approx(mu * (lam - lam**-2), rel=1e-4)


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: Yeoh(c1=-1.0, bulk_modulus=1.0), "c1 = -1: must be finite and > 0"),
        (lambda: Yeoh(c1=1.0, bulk_modulus=0.0), "bulk_modulus = 0: must be finite and > 0"),
        (
            lambda: isotropic_from_young(youngs_modulus=1.0, poisson_ratio=0.5),
            r"poisson_ratio = 0.5: must be in",
        ),
        (
            lambda: transversely_isotropic(
                axial_modulus=1.0, transverse_modulus=1e5, axial_shear_modulus=1.0, coupling_poisson=0.6
            ),
            r"coupling_poisson = 0.6: must satisfy \|nu_c\| < 0.5916",
        ),
        (lambda: AnisotropicSVK(np.ones((3, 3))), r"tensor = \(3, 3\): must be a finite"),
    ],
)
def test_bad_parameters_name_value_and_bound(build, match):
    with pytest.raises(DesignError, match=match):
        build()
