"""Newton with ``reuse_factors``: the same answer as full Newton, with fewer factorisations."""

import numpy as np
import pytest

from softcath.fem.hyperelastic.laws import AnisotropicSVK, neo_hookean, transversely_isotropic
from softcath.fem.nonlinear.body import FollowerPressure, HyperelasticBody
from softcath.fem.nonlinear.errors import NonlinearError
from softcath.fem.nonlinear.linsolve import TangentSolver
from softcath.fem.nonlinear.meshes import box, dofs_of_facets, facets_where
from softcath.fem.nonlinear.newton import solve

SOFT = neo_hookean(shear_modulus=0.3, bulk_modulus=5.0)
COIL = AnisotropicSVK(
    transversely_isotropic(axial_modulus=2.0, transverse_modulus=50.0, axial_shear_modulus=1.0)
)


def _cantilever():
    # a soft beam with a stiffer anisotropic half, bent by a follower pressure on its +y face
    mesh = box(size=(1.0, 1.0, 4.0), cells=(2, 2, 6))
    labels = (mesh.p[0, mesh.t].mean(axis=0) > 0.0).astype(int)
    body = HyperelasticBody(mesh, labels, {0: SOFT, 1: COIL})
    press = FollowerPressure(body, facets_where(mesh, lambda x: x[1] > 0.5 - 1e-9))
    fixed = dofs_of_facets(body.basis, facets_where(mesh, lambda x: x[2] < 1e-9))
    return body, press, fixed


@pytest.mark.parametrize("method", ["superlu", "pardiso-lu"])
def test_reused_factors_give_the_same_answer_with_fewer_factorisations(method):
    if method.startswith("pardiso"):
        pytest.importorskip("pypardiso")
    body, press, fixed = _cantilever()
    kw = {"fixed_dofs": fixed, "loads": [(press, 0.005)], "steps": 3, "rtol": 1e-9, "method": method}
    full = solve(body, **kw)
    reused = solve(body, **kw, reuse_factors=True)
    # a real large bend (the tip moves by about a third of the length), so the comparison means something
    assert np.abs(full.u).max() > 1.0
    # full Newton factorises every iteration (no cutback here); the reuse saves some of them
    assert all(s.cutbacks == 0 for s in full.steps)
    assert full.factorisations == full.newton_iterations
    assert reused.factorisations < full.factorisations
    # both stop at a residual ≤ rtol of the forces in play: their displacements agree to ~rtol times the
    # condition of the tangent; 1e-6 of the largest displacement leaves that margin and is far below any
    # difference a wrong iteration would leave
    assert np.abs(reused.u - full.u).max() <= 1e-6 * np.abs(full.u).max()
    assert all(s.residuals[-1] <= 1e-9 for s in reused.steps)


def test_resolve_before_any_factorisation_is_refused():
    body, _, fixed = _cantilever()
    free = np.setdiff1d(np.arange(body.ndofs), fixed)
    _, tmpl = body.pattern.restrict(free)
    with pytest.raises(NonlinearError, match="resolve"):
        TangentSolver(tmpl, "superlu").resolve(np.zeros(free.size))


def test_the_catheter_curve_reuses_factors_by_default():
    from softcath.design import preset
    from softcath.fem.nonlinear.bend import bend_curve

    kw = {"layers": 2, "size": 0.3, "curvature_points": 8}
    design = preset("paper")
    reused = bend_curve(design, [0.05, 0.1], **kw)
    full = bend_curve(design, [0.05, 0.1], reuse_factors=False, **kw)
    assert full.result.factorisations == full.result.newton_iterations
    assert reused.result.factorisations < full.result.factorisations
    # both stop within rtol = 1e-8 of the forces in play; the tip angle's spread that leaves is ~1e-6 of
    # itself on the catheter (1e-10 here, 5e-6 measured on the 4-layer paper tip), far below the mesh's error
    np.testing.assert_allclose(reused.bend_angle, full.bend_angle, rtol=1e-5)
    np.testing.assert_allclose(np.c_[reused.tip_x, reused.tip_y], np.c_[full.tip_x, full.tip_y], rtol=1e-5)
