"""Verification cases with closed forms (design-independent).

Each function builds a small structured mesh, solves it with the
finite-strain solver and returns the numbers to compare, next to the
closed-form values. The tests assert them; ``docs/nonlinear.md`` quotes them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.fem.hyperelastic.laws import isotropic_from_young, neo_hookean
from softcath.fem.nonlinear.body import FollowerPressure, HyperelasticBody
from softcath.fem.nonlinear.meshes import box, dofs_of_facets, facets_where, hollow_cylinder
from softcath.fem.nonlinear.newton import NonlinearResult, solve
from softcath.fem.nonlinear.post import bend_angles

__all__ = [
    "closed_cylinder_exact",
    "closed_cylinder",
    "CylinderResult",
    "end_moment_cantilever",
    "MomentResult",
]


def closed_cylinder_exact(
    *, inner_radius: float, outer_radius: float, shear_modulus: float, pressure: float
) -> tuple[float, float, float]:
    """Closed-end thick tube of incompressible neo-Hookean solid under internal pressure.

    Rivlin's finite-strain solution (Ogden, *Non-linear elastic deformations*,
    §5.3): r² = a² + (R² − A²)/λz; σθθ − σrr = μ(λθ² − λr²), σzz − σrr =
    μ(λz² − λr²); p = ∫ₐᵇ (σθθ − σrr) dr/r; closed ends: the axial force
    ∫ σzz 2πr dr equals the cap force p π a². Solved for (a, λz) by quadrature
    and root finding.

    Returns
    -------
    a, lambda_z, axial_force
        Deformed inner radius [mm], axial stretch, axial force = p π a² [N].
    """
    from scipy import integrate, optimize

    big_a, big_b, mu = inner_radius, outer_radius, shear_modulus

    def forms(a, lz):
        def ref_r(r):
            return np.sqrt(big_a**2 + lz * (r**2 - a**2))

        b = np.sqrt(a**2 + (big_b**2 - big_a**2) / lz)

        def diff(r):
            return mu * ((r / ref_r(r)) ** 2 - (ref_r(r) / (r * lz)) ** 2)

        p = integrate.quad(lambda r: diff(r) / r, a, b, epsabs=1e-14, epsrel=1e-12)[0]

        def szz(r):
            srr = -integrate.quad(lambda s: diff(s) / s, r, b, epsabs=1e-14, epsrel=1e-12)[0]
            return srr + mu * (lz**2 - (ref_r(r) / (r * lz)) ** 2)

        n = integrate.quad(lambda r: szz(r) * 2 * np.pi * r, a, b, epsabs=1e-13, epsrel=1e-11)[0]
        return p, n

    def eqs(x):
        p, n = forms(*x)
        return [p - pressure, n - p * np.pi * x[0] ** 2]

    (a, lz), info, ok, msg = optimize.fsolve(eqs, [big_a * 1.05, 1.0], xtol=1e-12, full_output=True)
    if ok != 1:  # pragma: no cover - the closed form always has a root in the loads used here
        raise RuntimeError(f"closed-cylinder closed form did not converge: {msg}")
    return float(a), float(lz), float(pressure * np.pi * a**2)


@dataclass(frozen=True)
class CylinderResult:
    """FEM of the closed tube at the exact axial stretch: inner radius and axial reaction."""

    inner_radius: float
    axial_force: float
    newton_iterations: int
    ndofs: int


def closed_cylinder(
    *,
    inner_radius: float = 1.0,
    outer_radius: float = 2.0,
    shear_modulus: float = 1.0,
    poisson_ratio: float = 0.4999,
    pressure: float = 0.25,
    mixed: bool = True,
    cells: tuple[int, int] = (4, 12),
    steps: int = 5,
) -> CylinderResult:
    """Quarter of a closed tube, one layer thick (the exact solution is uniform in z).

    Symmetry planes x = 0 and y = 0; the end faces stay plane at the axial stretch
    of :func:`closed_cylinder_exact`; the follower pressure acts on the bore. The
    axial reaction on the end face must then equal the cap force p π a².
    """
    a_ex, lz, _ = closed_cylinder_exact(
        inner_radius=inner_radius, outer_radius=outer_radius, shear_modulus=shear_modulus, pressure=pressure
    )
    length = 0.25 * inner_radius
    mesh = hollow_cylinder(
        inner_radius=inner_radius, outer_radius=outer_radius, length=length, cells=(cells[0], cells[1], 1)
    )
    nu = poisson_ratio
    law = neo_hookean(
        shear_modulus=shear_modulus, bulk_modulus=2 * shear_modulus * (1 + nu) / (3 * (1 - 2 * nu))
    )
    body = HyperelasticBody(mesh, np.zeros(mesh.t.shape[1], int), {0: law}, mixed=mixed)
    bore = facets_where(mesh, lambda x: np.hypot(x[0], x[1]) < inner_radius * (1 + 1e-9))
    press = FollowerPressure(body, bore)
    fx = dofs_of_facets(body.basis, facets_where(mesh, lambda x: np.abs(x[0]) < 1e-9), (0,))
    fy = dofs_of_facets(body.basis, facets_where(mesh, lambda x: np.abs(x[1]) < 1e-9), (1,))
    f0 = dofs_of_facets(body.basis, facets_where(mesh, lambda x: x[2] < 1e-9), (2,))
    f1 = dofs_of_facets(body.basis, facets_where(mesh, lambda x: x[2] > length * (1 - 1e-9)), (2,))
    fixed = np.concatenate([fx, fy, f0, f1])
    values = np.concatenate([np.zeros(fx.size + fy.size + f0.size), np.full(f1.size, (lz - 1) * length)])
    res = solve(body, fixed_dofs=fixed, fixed_values=values, loads=[(press, pressure)], steps=steps)
    x = body.nodes
    on_bore = np.isclose(np.hypot(x[:, 0], x[:, 1]), inner_radius)
    a = float(np.hypot(*(x[on_bore, :2] + res.u[on_bore, :2]).T).mean())
    f_int, _ = body.internal(res.u.ravel())
    return CylinderResult(
        inner_radius=a,
        axial_force=float(4 * f_int[np.unique(f1)].sum()),
        newton_iterations=res.newton_iterations,
        ndofs=body.ndofs,
    )


@dataclass(frozen=True)
class MomentResult:
    """Cantilever under a follower end moment: tip rotation and centre-line circle fit.

    ``radius_scatter`` is the spread (max − min) of the centre-line radii about the
    fitted centre over the expected radius; ``nodes`` the reference P2 nodes [mm].
    """

    bend_angle: float
    expected_angle: float
    radius: float
    expected_radius: float
    radius_scatter: float
    result: NonlinearResult
    nodes: np.ndarray


def end_moment_cantilever(
    *,
    length: float = 10.0,
    thickness: float = 1.0,
    bend_angle: float = np.pi / 2,
    youngs_modulus: float = 1.0,
    cells: tuple[int, int] = (2, 10),
    steps: int = 8,
) -> MomentResult:
    """Square cantilever closed by a follower end moment M = θ E I / L.

    The moment is a follower normal traction varying linearly over the end
    face (p(Y) = M Y / I on the deformed face), so it stays a pure moment as
    the end rotates; Euler–Bernoulli with large rotations then bends the
    beam into a circular arc of radius EI/M and end rotation θ = ML/EI. ν is
    0 (no anticlastic coupling with the clamp) and L/h large so the strains
    hθ/(2L) stay small.
    """
    h = thickness
    mesh = box(size=(h, h, length), cells=(cells[0], cells[0], cells[1]))
    law = isotropic_from_young(youngs_modulus=youngs_modulus, poisson_ratio=0.0)
    body = HyperelasticBody(mesh, np.zeros(mesh.t.shape[1], int), {0: law})
    inertia = h**4 / 12
    moment = bend_angle * youngs_modulus * inertia / length
    press = FollowerPressure(
        body, facets_where(mesh, lambda x: x[2] > length * (1 - 1e-9)), profile=lambda x: -x[1] / inertia
    )
    fixed = dofs_of_facets(body.basis, facets_where(mesh, lambda x: x[2] < 1e-9))
    res = solve(body, fixed_dofs=fixed, loads=[(press, moment)], steps=steps)
    x = body.nodes
    end = np.isclose(x[:, 2], length)
    theta = float(bend_angles(x, res.displacements, end)[-1])
    # circle fit of the deformed centre line (nodes on x = y = 0) in the y-z plane
    axis = np.isclose(x[:, 0], 0) & np.isclose(x[:, 1], 0)
    c = x[axis] + res.u[axis]
    r_expected = youngs_modulus * inertia / moment
    centre = _circle_centre(c[:, 1], c[:, 2])
    radii = np.hypot(c[:, 1] - centre[0], c[:, 2] - centre[1])
    return MomentResult(
        bend_angle=theta,
        expected_angle=bend_angle,
        radius=float(radii.mean()),
        expected_radius=float(r_expected),
        radius_scatter=float(np.ptp(radii) / r_expected),
        result=res,
        nodes=x,
    )


def _circle_centre(y: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Least-squares (Kåsa) circle centre of points in the y–z plane."""
    a = np.column_stack([2 * y, 2 * z, np.ones_like(y)])
    sol, *_ = np.linalg.lstsq(a, y**2 + z**2, rcond=None)
    return sol[:2]
