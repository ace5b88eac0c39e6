"""Verification of the P2 elasticity kernel against closed forms."""

from __future__ import annotations

import numpy as np
import pytest
from skfem import MeshTet

from softcath.design.errors import DesignError
from softcath.fem.elasticity import ElasticProblem
from softcath.fem.errors import FemError, SolverError
from softcath.fem.materials import Isotropic, TransverselyIsotropic
from tests.fem._shapes import facets_where, quarter_annulus

E, NU = 2.0, 0.3


def _irregular_box(n=(4, 3, 3), jitter=0.2, seed=1):
    m = MeshTet.init_tensor(*(np.linspace(0, 1, k + 1) for k in n))
    rng = np.random.default_rng(seed)
    p = m.p.copy()
    inner = (p > 1e-9).all(axis=0) & (p < 1 - 1e-9).all(axis=0)
    p[:, inner] += jitter / max(n) * rng.uniform(-1, 1, (3, inner.sum()))
    return MeshTet(p, m.t)


def _patch_test(mesh, law):
    a = np.array([[1e-3, 2e-3, -1e-3], [0.5e-3, -2e-3, 1e-3], [3e-3, 1e-3, 2e-3]])
    b = np.array([1e-3, -2e-3, 0.5e-3])
    bf = mesh.boundary_facets()
    pb = ElasticProblem(mesh, np.zeros(mesh.t.shape[1], int), {0: law}, [(bf, (0, 1, 2))])
    exact = pb.nodes @ a.T + b
    sol = pb.solve(np.zeros(pb.ndofs), prescribed=exact)
    return np.abs(sol.u - exact).max() / np.abs(exact).max()


def test_patch_test_is_exact_on_an_irregular_mesh():
    # A linear field is in the P2 space: any consistent FE reproduces it to round-off.
    err = _patch_test(_irregular_box(), Isotropic(E, NU))
    assert err < 1e-10


def test_patch_test_transversely_isotropic():
    law = TransverselyIsotropic(
        axial_modulus=1.3,
        transverse_modulus=1e3,
        transverse_poisson=0.3,
        coupling_poisson=0.3,
        axial_shear_modulus=0.5,
    )
    assert _patch_test(_irregular_box(seed=2), law) < 1e-9


@pytest.mark.slow
def test_patch_test_on_a_pytetwild_mesh(tmp_path, monkeypatch):
    import warnings

    import pytetwild
    import pyvista as pv

    cube = pv.Cube(center=(0.5, 0.5, 0.5)).triangulate()
    monkeypatch.chdir(tmp_path)  # fTetWild writes __tracked_surface.stl into the working directory
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pytetwild uses a deprecated pyvista accessor
        grid = pytetwild.tetrahedralize_pv(cube, edge_length_fac=0.25)
    tets = grid.cells_dict[10]
    from softcath.fem.mesh import _orient

    mesh = MeshTet(np.asarray(grid.points, float).T, _orient(np.asarray(grid.points), tets).T)
    assert _patch_test(mesh, Isotropic(E, NU)) < 1e-9


def test_transversely_isotropic_reduces_to_isotropic():
    g = E / (2 * (1 + NU))
    # With nu_c = nu (E_L = E_T = E) the coupling term -nu_c/sqrt(E_L E_T) = -nu/E.
    ti = TransverselyIsotropic(
        axial_modulus=E,
        transverse_modulus=E,
        transverse_poisson=NU,
        coupling_poisson=NU,
        axial_shear_modulus=g,
    )
    np.testing.assert_allclose(ti.tensor(), Isotropic(E, NU).tensor(), rtol=1e-12, atol=1e-12)


def test_transversely_isotropic_uniaxial_moduli():
    law = TransverselyIsotropic(
        axial_modulus=1.5,
        transverse_modulus=300.0,
        transverse_poisson=0.25,
        coupling_poisson=0.2,
        axial_shear_modulus=0.7,
    )
    c = law.tensor()
    voigt = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]
    cm = np.array([[c[i, j, k, m] for (k, m) in voigt] for (i, j) in voigt])
    s = np.linalg.inv(cm)
    assert s[2, 2] == pytest.approx(1 / 1.5, rel=1e-12)
    assert s[0, 0] == pytest.approx(1 / 300.0, rel=1e-12)
    assert s[3, 3] == pytest.approx(1 / 0.7, rel=1e-12)  # engineering shear yz
    assert np.linalg.eigvalsh(cm).min() > 0


def test_bad_material_names_parameter_and_bound():
    with pytest.raises(DesignError, match=r"poisson_ratio = 0\.5: must be in"):
        Isotropic(1.0, 0.5)
    with pytest.raises(DesignError, match=r"coupling_poisson = 0\.9: must satisfy"):
        TransverselyIsotropic(
            axial_modulus=1.0,
            transverse_modulus=1e3,
            transverse_poisson=0.3,
            coupling_poisson=0.9,
            axial_shear_modulus=0.4,
        )


def test_cantilever_end_shear_between_euler_bernoulli_and_timoshenko():
    length, h, force = 2.0, 0.2, 1e-3  # L/h = 10
    m = MeshTet.init_tensor(np.linspace(0, h, 3), np.linspace(0, h, 3), np.linspace(0, length, 21))
    pb = ElasticProblem(
        m,
        np.zeros(m.t.shape[1], int),
        {0: Isotropic(E, NU)},
        [(m.facets_satisfying(lambda x: x[2] < 1e-9), (0, 1, 2))],
    )
    end = m.facets_satisfying(lambda x: x[2] > length - 1e-9)
    sol = pb.solve(pb.traction_load(end, (0.0, -force / h**2, 0.0)))
    tip = np.isclose(pb.nodes[:, 2], length)
    deflection = -sol.u[tip, 1].mean()
    inertia = h**4 / 12
    eb = force * length**3 / (3 * E * inertia)
    shear_k = 10 * (1 + NU) / (12 + 11 * NU)  # Cowper, rectangle
    timo = eb + force * length / (shear_k * E / (2 * (1 + NU)) * h**2)
    # A 3-D clamp is stiffer than Timoshenko's (no warping at the wall) but softer
    # than Euler-Bernoulli; P2 should land between them within 1 %.
    assert 0.99 * eb <= deflection <= 1.01 * timo
    assert sol.residual < 1e-12


def test_lame_thick_cylinder_closed_ends():
    ri, ro, length, p = 0.3, 0.6, 0.6, 0.1
    mesh = quarter_annulus(ri, ro, 0.06, length, 4)
    pb = ElasticProblem(
        mesh,
        np.zeros(mesh.t.shape[1], int),
        {0: Isotropic(E, NU)},
        [
            (facets_where(mesh, lambda x, y, z: z < 1e-9), (2,)),
            (facets_where(mesh, lambda x, y, z: np.abs(x) < 1e-9), (0,)),
            (facets_where(mesh, lambda x, y, z: np.abs(y) < 1e-9), (1,)),
        ],
    )
    a = p * ri**2 / (ro**2 - ri**2)
    # Inner wall only: centroids within a sliver of ri (other faces' centroids
    # stay ~size/3 away), not the end or symmetry faces.
    inner = facets_where(
        mesh,
        lambda x, y, z: (
            (np.hypot(x, y) < ri + 0.005)
            & (np.abs(x) > 1e-9)
            & (np.abs(y) > 1e-9)
            & (z > 1e-9)
            & (z < length - 1e-9)
        ),
    )
    end = facets_where(mesh, lambda x, y, z: z > length - 1e-9)
    # Closed ends: the end cap's pull is a uniform axial stress a = p ri^2/(ro^2 - ri^2).
    load = p * pb.pressure_load(inner) + pb.traction_load(end, (0.0, 0.0, a))
    sol = pb.solve(load)
    x = pb.nodes
    r = np.hypot(x[:, 0], x[:, 1])
    on_inner = np.abs(r - ri) < 1e-9
    ur = (sol.u[on_inner, 0] * x[on_inner, 0] + sol.u[on_inner, 1] * x[on_inner, 1]) / ri
    b = p * ri**2 * ro**2 / (ro**2 - ri**2)
    ur_exact = ri * (a * (1 - 2 * NU) + b * (1 + NU) / ri**2) / E
    uz_exact = length * a * (1 - 2 * NU) / E
    top = np.isclose(x[:, 2], length)
    # 1 %: the bound. Midside nodes sit on the exact circles, so the
    # faceting error that dominated straight P2 (1.2 % at 24 segments) is gone.
    assert ur.mean() == pytest.approx(ur_exact, rel=0.01)
    assert np.ptp(ur) < 0.01 * ur_exact
    assert sol.u[top, 2].mean() == pytest.approx(uz_exact, rel=0.01)


def test_solver_refuses_a_bad_solve():
    import scipy.sparse as sp

    from softcath.fem.solver import Factorized

    k = sp.diags([1.0, 2.0, 3.0]).tocsr()
    fac = Factorized(k, method="superlu", tol=1e-10)
    u, res = fac.solve(np.array([1.0, 2.0, 3.0]))
    np.testing.assert_allclose(u, 1.0)
    fac.tol = -1.0  # nothing passes a negative tolerance: the refusal path
    with pytest.raises(SolverError, match="backward error"):
        fac.solve(np.array([1.0, 2.0, 3.0]))


def test_missing_law_and_missing_clamp_are_errors():
    m = MeshTet.init_tensor(*(np.linspace(0, 1, 2),) * 3)
    with pytest.raises(FemError, match=r"region labels \[0\]"):
        ElasticProblem(m, np.zeros(m.t.shape[1], int), {1: Isotropic(E, NU)}, [])
    with pytest.raises(FemError, match="no facets"):
        ElasticProblem(m, np.zeros(m.t.shape[1], int), {0: Isotropic(E, NU)}, [])


def test_pardiso_matches_superlu():
    m = _irregular_box(n=(6, 2, 2))
    base = m.facets_satisfying(lambda x: x[0] < 1e-9)
    end = m.facets_satisfying(lambda x: x[0] > 1 - 1e-9)
    out = {}
    for method in ("pardiso", "superlu"):
        pb = ElasticProblem(
            m,
            np.zeros(m.t.shape[1], int),
            {0: Isotropic(E, NU)},
            [(base, (0, 1, 2))],
            method=method,
        )
        out[method] = pb.solve(pb.pressure_load(end)).u
    np.testing.assert_allclose(out["pardiso"], out["superlu"], rtol=0, atol=1e-10)
