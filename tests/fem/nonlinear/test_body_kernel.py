"""The compiled element loop (fem.nonlinear.kernel) against the batched NumPy kernels it replaces."""

import numpy as np
import pytest
import scipy.sparse as sp

from softcath.fem.hyperelastic.laws import AnisotropicSVK, Yeoh, transversely_isotropic
from softcath.fem.nonlinear.body import HyperelasticBody
from softcath.fem.nonlinear.kernel import SVK, YEOH, law_code
from softcath.fem.nonlinear.meshes import box

# a Yeoh silicone with all three terms (so W'' ≠ 0 is exercised) and a stiff anisotropic coil
SOFT = Yeoh(c1=0.03, c2=-0.002, c3=0.0004, bulk_modulus=2.0)
COIL = AnisotropicSVK(
    transversely_isotropic(
        axial_modulus=2.0, transverse_modulus=200.0, axial_shear_modulus=1.0, coupling_poisson=0.1
    )
)


def _bodies(mixed):
    mesh = box(size=(1.0, 1.2, 2.0), cells=(2, 2, 3))
    labels = (mesh.p[2, mesh.t].mean(axis=0) > 1.0).astype(int)
    laws = {0: SOFT, 1: COIL}
    return (
        HyperelasticBody(mesh, labels, laws, mixed=mixed, compiled=True),
        HyperelasticBody(mesh, labels, laws, mixed=mixed, compiled=False),
    )


def _state(body, scale):
    # a smooth large deformation (rotation-like shear + stretch) plus noise: F far from I everywhere
    x = body.nodes
    rng = np.random.default_rng(3)
    u = np.column_stack([0.3 * x[:, 2] ** 2, 0.1 * x[:, 0] * x[:, 2], 0.15 * x[:, 2] - 0.1 * x[:, 0] ** 2])
    return (u + scale * rng.standard_normal(u.shape)).ravel()


def test_laws_are_classified():
    soft, coil = law_code(SOFT), law_code(COIL)
    assert soft is not None and soft[0] == YEOH
    assert coil is not None and coil[0] == SVK

    class Other(Yeoh):
        """A subclass may change the energy: it must take the NumPy path."""

    assert law_code(Other(c1=0.1, bulk_modulus=1.0)) is None


@pytest.mark.parametrize("mixed", [False, True])
def test_compiled_assembly_equals_numpy(mixed):
    fast, ref = _bodies(mixed)
    assert all(ch.compiled is not None for ch in fast._chunks)
    assert all(ch.compiled is None for ch in ref._chunks)
    u = _state(fast, 0.02)
    f1, d1 = fast.internal(u)
    f0, d0 = ref.internal(u)
    # the same sums in another order: round-off only, a few ulps of the largest entry each
    assert np.abs(f1 - f0).max() <= 1e-11 * np.abs(f0).max()
    assert np.abs(d1 - d0).max() <= 1e-11 * np.abs(d0).max()


@pytest.mark.parametrize("mixed", [False, True])
def test_compiled_tangent_is_derivative_of_forces(mixed):
    fast, _ = _bodies(mixed)
    u = _state(fast, 0.01)
    _, data = fast.internal(u)
    n = fast.ndofs
    k = sp.csr_matrix((data, (fast.pattern.rows, fast.pattern.cols)), shape=(n, n)).toarray()
    h = 1e-6
    cols = np.random.default_rng(5).choice(n, 40, replace=False)
    for j in cols:
        e = np.zeros(n)
        e[j] = h
        col = (fast.internal(u + e)[0] - fast.internal(u - e)[0]) / (2 * h)
        # central differences: error ~h² |f'''| + eps |f| / h, far below 1e-6 of the largest entry
        assert np.abs(k[:, j] - col).max() <= 1e-6 * np.abs(k).max()
