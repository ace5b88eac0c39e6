"""Assembly of the finite-strain body and the follower pressure: consistency and exact identities."""

import numpy as np
import pytest
import scipy.sparse as sp

from softcath.fem.hyperelastic.laws import AnisotropicSVK, neo_hookean, transversely_isotropic
from softcath.fem.nonlinear.body import FollowerPressure, HyperelasticBody
from softcath.fem.nonlinear.errors import ConvergenceError, NonlinearError
from softcath.fem.nonlinear.meshes import box, facets_where
from softcath.fem.nonlinear.newton import solve

SOFT = neo_hookean(shear_modulus=0.3, bulk_modulus=5.0)
COIL = AnisotropicSVK(
    transversely_isotropic(axial_modulus=2.0, transverse_modulus=200.0, axial_shear_modulus=1.0)
)


def _two_region_body(mixed):
    mesh = box(size=(1.0, 1.0, 2.0), cells=(1, 1, 2))
    labels = (mesh.p[2, mesh.t].mean(axis=0) > 1.0).astype(int)
    return mesh, HyperelasticBody(mesh, labels, {0: SOFT, 1: COIL}, mixed=mixed)


@pytest.mark.parametrize("mixed", [False, True])
def test_tangent_is_derivative_of_residual_with_follower_load(mixed):
    mesh, body = _two_region_body(mixed)
    top = facets_where(mesh, lambda x: x[2] > 2 - 1e-9)
    press = FollowerPressure(body, top, profile=lambda x: 1.0 + x[1])
    u = 0.03 * np.random.default_rng(1).standard_normal(body.ndofs)

    def r(v):
        f, d = body.internal(v)
        press.add_to(v, 0.7, f, d)
        return f, d

    _, data = r(u)
    k = sp.csr_matrix((data, (body.pattern.rows, body.pattern.cols)), shape=(body.ndofs,) * 2).toarray()
    h = 1e-6
    k_fd = np.empty_like(k)
    for j in range(body.ndofs):
        e = np.zeros(body.ndofs)
        e[j] = h
        k_fd[:, j] = (r(u + e)[0] - r(u - e)[0]) / (2 * h)
    # central differences of a smooth residual: error ~h^2 and eps/h, far below 1e-6 of the largest entry
    assert np.abs(k - k_fd).max() <= 1e-6 * np.abs(k).max()


def test_homogeneous_deformation_is_in_equilibrium_inside():
    # patch test: a uniform F gives zero internal force at every interior node (exact up to round-off)
    mesh = box(size=(1.0, 1.0, 1.0), cells=(3, 3, 3))
    body = HyperelasticBody(mesh, np.zeros(mesh.t.shape[1], int), {0: SOFT})
    fmat = np.array([[1.2, 0.1, 0.0], [-0.05, 0.9, 0.2], [0.0, 0.1, 1.1]])
    x = body.nodes
    u = (x @ (fmat - np.eye(3)).T).ravel()
    f, _ = body.internal(u)
    interior = (
        (np.abs(x[:, 0]) < 0.5 - 1e-9)
        & (np.abs(x[:, 1]) < 0.5 - 1e-9)
        & (x[:, 2] > 1e-9)
        & (x[:, 2] < 1 - 1e-9)
    )
    assert interior.sum() > 10
    scale = np.abs(f).max()
    assert np.abs(f.reshape(-1, 3)[interior]).max() <= 1e-12 * scale


def test_nanson_force_on_stretched_face_is_pressure_times_deformed_area():
    # uniform stretch: the face z = 1 (1 x 1) becomes lx x ly; the follower force is -p lx ly e_z exactly
    mesh = box(size=(1.0, 1.0, 1.0), cells=(2, 2, 2))
    body = HyperelasticBody(mesh, np.zeros(mesh.t.shape[1], int), {0: SOFT})
    press = FollowerPressure(body, facets_where(mesh, lambda x: x[2] > 1 - 1e-9))
    fmat = np.diag([1.3, 0.8, 1.1])
    u = (body.nodes @ (fmat - np.eye(3)).T).ravel()
    force = press.deformed_force(u, 0.25)
    np.testing.assert_allclose(force, [0.0, 0.0, -0.25 * 1.3 * 0.8], atol=1e-14)


def test_input_errors_are_named():
    mesh = box(size=(1.0, 1.0, 1.0), cells=(1, 1, 1))
    with pytest.raises(NonlinearError, match=r"labels: 3 given, mesh has 6 tetrahedra"):
        HyperelasticBody(mesh, np.zeros(3, int), {0: SOFT})
    with pytest.raises(NonlinearError, match=r"region labels \[1\]: have no material law"):
        HyperelasticBody(mesh, np.ones(6, int), {0: SOFT})
    body = HyperelasticBody(mesh, np.zeros(6, int), {0: SOFT})
    interior = np.setdiff1d(np.arange(mesh.facets.shape[1]), mesh.boundary_facets())
    with pytest.raises(NonlinearError, match="must all be boundary facets"):
        FollowerPressure(body, interior[:1])
    with pytest.raises(NonlinearError, match="steps = 0: must be an integer >= 1"):
        solve(body, fixed_dofs=[0, 1, 2], steps=0)
    with pytest.raises(NonlinearError, match="fixed_dofs: none"):
        solve(body, fixed_dofs=[], steps=1)


def test_newton_failure_raises_with_load_reached():
    # a soft cube crushed by a huge follower pressure cannot be followed: the solver must refuse,
    # naming the load factor reached, rather than return a wrong state
    mesh = box(size=(1.0, 1.0, 1.0), cells=(1, 1, 1))
    body = HyperelasticBody(mesh, np.zeros(6, int), {0: SOFT})
    base = facets_where(mesh, lambda x: x[2] < 1e-9)
    fixed = (3 * body.basis.get_dofs(base).all()[:, None] + np.arange(3)).ravel()
    press = FollowerPressure(body, facets_where(mesh, lambda x: x[2] > 1 - 1e-9))
    with pytest.raises(ConvergenceError, match=r"Newton failed: load factor [0-9.e-]+ reached.*cutbacks"):
        solve(body, fixed_dofs=fixed, loads=[(press, 50.0)], steps=1, max_iter=6, max_cutbacks=3)
