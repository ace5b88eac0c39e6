"""The squeezed tube (module ``squeeze``): its pre-deformation field, its law and its rest state.

Independent checks:

- the field on a general ring (lumen off-centre, not homothetic) is checked by exact quadrature
  in (s, theta): det dx/d(s, theta) is quadratic in s and a trigonometric polynomial of degree 2
  in theta, so 3 Gauss points across the wall and 16 angles integrate it to round-off, and the
  as-built ring's area pi (a b - a_int b_int) and the catalogue annulus's pi (r_o^2 - r_i^2)
  follow to round-off when the map is one-to-one;
- the paper's nominal ring (concentric, lumen/outer = ID/OD on both axes) is the catalogue annulus
  scaled by D = diag(a, b) / r_o, so F_pre is uniform, the diagonal d / ((1 - t) d + t) with
  lambda_z = 1 / det: a closed form at every quadrature point, the lands included (the map is
  continued affinely past the outer ellipse);
- the wrapper's stress and tangent against ``Prestretched`` and against finite differences;
- the rest state: at small t the squeeze is the axial pre-stretch lambda_z(t) plus an in-plane
  deviatoric eigenstrain, so its rest state has the pre-stretch's signs and is near the
  pre-stretch's at that lambda_z (module ``prestretch``, itself checked against the composite
  beam).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from softcath import design as design_pkg
from softcath.design.assembly import Assembly
from softcath.design.errors import DesignError
from softcath.fem.geometry import TUBE
from softcath.fem.section_model.finite_strain import SectionConvergenceError, section_curve
from softcath.fem.section_model.finite_strain.laws import section_laws
from softcath.fem.section_model.finite_strain.prestretch import Prestretched
from softcath.fem.section_model.finite_strain.squeeze import Squeezed, TubeRing, check_squeeze
from softcath.models.section_nonlinear import SECTION_NONLINEAR

#: A general ring: lumen off-centre and flatter than the outer ellipse (mm).
GENERAL = TubeRing(
    inner_radius=0.15, outer_radius=0.3, a=0.21, b=0.15, a_int=0.12, b_int=0.06, h=0.02, centre_y=0.15
)


@pytest.fixture(scope="module")
def paper():
    return design_pkg.resolve("paper")


@pytest.fixture(scope="module")
def squeezed_paper(paper):
    """The paper design's curve at t = 0.01 (its discretisation and rest state)."""
    return section_curve(paper, [0.0, 0.01], tube_squeeze=0.01, linear_gain=False)


def test_no_squeeze_is_todays_curve(paper):
    p = [0.0, 0.2, 0.5]
    for mesher in ("template", "gmsh"):
        today = section_curve(paper, p, mesher=mesher)
        same = section_curve(paper, p, mesher=mesher, tube_squeeze=0.0)
        for name in ("curvature_per_mm", "elongation", "lumen_area_mm2", "bend_angle_rad"):
            assert np.array_equal(getattr(today, name), getattr(same, name))
        assert same.tube_squeeze == 0.0 and same.rest_curvature_per_mm == 0.0


def _grid(n_theta: int = 16):
    """3-point Gauss-Legendre in s on [0, 1] x n_theta uniform angles: (s, theta, weights)."""
    xg, wg = np.polynomial.legendre.leggauss(3)
    s, ws = (xg + 1) / 2, wg / 2
    theta = 2 * np.pi * np.arange(n_theta) / n_theta
    ss, tt = np.meshgrid(s, theta, indexing="ij")
    return ss, tt, ws[:, None] * np.full(n_theta, 2 * np.pi / n_theta)[None, :]


def test_general_ring_map_inverts_and_keeps_areas():
    ring = GENERAL
    s, theta, w = _grid()
    x = ring.as_built(s, theta)
    s_back, theta_back = ring.coordinates(x)
    # bisection to round-off: s and the point it gives back to 1e-12 (mm and 1)
    assert np.abs(s_back - s).max() < 1e-12
    assert np.abs(ring.as_built(s_back, theta_back) - x).max() < 1e-12
    f = ring.pre_deformation(x, 1.0)
    assert np.abs(np.linalg.det(f) - 1).max() < 1e-12
    # pushed back at t = 1 the points lie on the catalogue annulus at radius r_i + s (r_o - r_i)
    xc = ring.catalogue(s_back, theta_back)
    radius = np.hypot(xc[..., 0], xc[..., 1] - ring.centre_y)
    assert np.abs(radius - (0.15 + 0.15 * s)).max() < 1e-12
    assert radius.min() >= ring.inner_radius and radius.max() <= ring.outer_radius
    jx, _ = ring.jacobians(s_back, theta_back)
    da = w * np.linalg.det(jx)  # as-built area element
    assert da.sum() == pytest.approx(math.pi * (0.21 * 0.15 - 0.12 * 0.06), rel=1e-12)
    # lambda_z = 1 / det(in-plane F_pre) integrates over the as-built ring to the catalogue area
    assert (da * f[..., 2, 2]).sum() == pytest.approx(math.pi * (0.3**2 - 0.15**2), rel=1e-12)
    half = ring.pre_deformation(x, 0.5)
    assert np.abs(np.linalg.det(half) - 1).max() < 1e-12
    assert np.all(half[..., 2, 2] > 1) and np.all(half[..., 2, 2] < f[..., 2, 2])


@pytest.mark.parametrize("t", [0.3, 1.0])
def test_paper_ring_is_the_scaled_annulus(squeezed_paper, paper, t):
    disc = squeezed_paper.state[0]
    ring = TubeRing.from_design(paper)
    points = disc.points[disc.cells[TUBE]]
    f = ring.pre_deformation(points, t)
    d = np.array([paper.section.a, paper.section.b]) / ring.outer_radius
    inplane = d / ((1 - t) * d + t)
    expected = np.diag([*inplane, 1 / inplane.prod()])
    assert np.abs(f - expected).max() < 1e-12
    s, theta = ring.coordinates(points)
    assert np.abs(ring.as_built(s, theta) - points).max() < 1e-12
    on_ring = (s >= 0) & (s <= 1)  # the rest are the lands, just past the outer ellipse
    xc = ring.catalogue(s[on_ring], theta[on_ring])
    radius = np.hypot(xc[..., 0], xc[..., 1] - ring.centre_y)
    assert radius.min() >= ring.inner_radius and radius.max() <= ring.outer_radius
    if t == 1.0:  # lambda_z is the catalogue / as-built wall-area ratio (2.83 for the paper)
        wall = math.pi * (paper.section.a * paper.section.b - paper.section.a_int * paper.section.b_int)
        catalogue = math.pi * (ring.outer_radius**2 - ring.inner_radius**2)
        assert f[..., 2, 2] == pytest.approx(catalogue / wall, rel=1e-12)


def _random_f(rng, shape) -> np.ndarray:
    """Deformation gradients near the identity with the section's block structure."""
    f = np.eye(3) + 0.2 * rng.standard_normal(shape + (3, 3))
    f[..., :2, 2] = 0.0
    f[..., 2, :2] = 0.0
    return f


@pytest.mark.parametrize("volumetric", [True, False])
def test_uniform_pre_is_prestretched(paper, volumetric):
    law = section_laws(paper)[TUBE]
    f = _random_f(np.random.default_rng(1), (4, 6))
    lam = 1.7
    a = Squeezed(law, np.diag([lam**-0.5, lam**-0.5, lam]))
    b = Prestretched(law, lam)
    pa, ta = a.stress_tangent(f, volumetric=volumetric)
    pb, tb = b.stress_tangent(f, volumetric=volumetric)
    # the same products summed in another order: round-off on the largest entry
    assert np.abs(pa - pb).max() <= 1e-12 * np.abs(pb).max()
    assert np.abs(ta - tb).max() <= 1e-12 * np.abs(tb).max()
    assert np.allclose(a.energy(f), b.energy(f), rtol=1e-12, atol=0)


@pytest.mark.parametrize("volumetric", [True, False])
def test_tangent_is_the_stress_derivative(paper, volumetric):
    rng = np.random.default_rng(7)
    law = section_laws(paper)[TUBE]
    pre = _random_f(rng, (2, 3))
    pre[..., 2, 2] = 1 / np.linalg.det(pre[..., :2, :2])
    wrapped = Squeezed(law, pre)
    f = _random_f(rng, (2, 3))
    _, tangent = wrapped.stress_tangent(f, volumetric=volumetric)
    h = 1e-6
    fd = np.zeros_like(tangent)
    for k in range(3):
        for m in range(3):
            e = np.zeros((3, 3))
            e[k, m] = h
            plus, _ = wrapped.stress_tangent(f + e, volumetric=volumetric)
            minus, _ = wrapped.stress_tangent(f - e, volumetric=volumetric)
            fd[..., k, m] = (plus - minus) / (2 * h)
    # central differences: O(h^2) truncation (~1e-12 of the modulus) plus round-off eps |P| / h
    # (~1e-10 of it): 1e-7 of the largest entry bounds both with room
    assert np.abs(fd - tangent).max() <= 1e-7 * np.abs(tangent).max()
    # and the stress is the energy's derivative (the same differences on W)
    stress, _ = wrapped.stress_tangent(f, volumetric=volumetric)
    e = np.zeros((3, 3))
    e[0, 1] = h
    w_plus, w_minus = (wrapped.energy(f + s * e, volumetric=volumetric) for s in (1, -1))
    dw = (w_plus - w_minus) / (2 * h)
    assert np.abs(dw - stress[..., 0, 1]).max() <= 1e-7 * np.abs(stress).max()


def test_rest_state_is_the_pull_of_the_longer_tube(paper, squeezed_paper):
    c = squeezed_paper
    section = paper.section
    d1, d2 = section.a / 0.3, section.b / 0.3
    t = 0.01
    lam = ((1 - t) * d1 + t) * ((1 - t) * d2 + t) / (d1 * d2)
    p = section_curve(paper, [0.0, 0.01], tube_prestretch=lam, linear_gain=False)
    # the stress-free tube is longer (lambda_z > 1): it pulls the coil shorter, and lying above the
    # axial-stiffness centroid it bends the tip toward itself (k_2 < 0: away from the channel)
    assert c.rest_elongation < 0 and c.rest_curvature_per_mm < 0
    assert c.tube_squeeze == t and c.tube_prestretch == 1.0
    # the in-plane deviatoric part (-0.41 t, -t against the pre-stretch's -0.71 t twice) adds
    # 4.9 % to the curvature and 2.8 % to the elongation (measured): within 10 % of the pre-stretch
    assert c.rest_curvature_per_mm == pytest.approx(p.rest_curvature_per_mm, rel=0.1)
    assert c.rest_elongation == pytest.approx(p.rest_elongation, rel=0.1)
    # the tube, compressed in-plane and confined by the coils, bulges into its lumen
    assert c.lumen_area_mm2[0] < section_curve(paper, [0.0, 0.01], linear_gain=False).lumen_area_mm2[0]


def test_full_squeeze_on_coil_bound_coils_keeps_the_tip_straight(paper):
    c = section_curve(paper, [0.0, 0.3], tube_squeeze=1.0, coil_bound=True, linear_gain=False)
    today = section_curve(paper, [0.0, 0.3], coil_bound=True, linear_gain=False)
    ring = TubeRing.from_design(paper)
    lam = 1 / (paper.section.a * paper.section.b / ring.outer_radius**2)
    mu = section_laws(paper)[TUBE].shear_modulus
    # the tube's pull (the incompressible uniaxial force at lambda_z over the catalogue area, 0.47 N)
    # dwarfs the cap force p A_lumen (0.01 N at 0.3 MPa): the coil-bound coil's turns stay closed
    pull = mu * (lam - lam**-2) * math.pi * (ring.outer_radius**2 - ring.inner_radius**2)
    assert 0.3 * c.lumen_area_mm2[1] < 0.1 * pull
    # so the tip shortens and bends by the coil's stacked-wire compliance alone (measured 3.6e-5
    # /mm, 8e-6), three to four decades below the open coil's 0.0426 /mm at 0.3 MPa
    assert abs(c.rest_curvature_per_mm) < 1e-4 and abs(c.rest_elongation) < 1e-4
    assert np.abs(c.curvature_per_mm).max() < 1e-4
    # the in-plane pre-stress still narrows the rest lumen (the tube bulges into it)
    assert c.lumen_area_mm2[0] < today.lumen_area_mm2[0]


@pytest.mark.parametrize("bad", [-0.1, 1.5, float("nan"), "x", None])
def test_squeeze_out_of_range_is_refused(paper, bad):
    with pytest.raises(DesignError, match="tube_squeeze.*must be"):
        section_curve(paper, [0.1], tube_squeeze=bad)
    with pytest.raises(DesignError, match="tube_squeeze"):
        check_squeeze(bad)


def test_a_point_off_the_ring_is_refused():
    # the lumen's centre and a point past the coil: no s in the bracket maps there
    for point in ([0.0, 0.17], [0.0, 1.0]):
        with pytest.raises(DesignError, match=r"tube points = \[.*\]: must lie on the as-built ring's map"):
            GENERAL.coordinates(np.array([point]))


def test_squeeze_refuses_prestretch_and_the_tip_as_built(paper):
    with pytest.raises(DesignError, match=r"tube_squeeze = 0.5: does not combine with tube_prestretch = 1.5"):
        section_curve(paper, [0.1], tube_squeeze=0.5, tube_prestretch=1.5)
    built = dataclasses.replace(paper, assembly=Assembly(tube_coil="sliding"))
    with pytest.raises(DesignError, match=r"tube_squeeze = 0.5: takes the bonded tip only"):
        section_curve(built, [0.1], tube_squeeze=0.5)


def test_the_tier_takes_the_option(paper):
    r = SECTION_NONLINEAR.response(paper, [0.0, 0.3], options={"tube_squeeze": 0.05})
    c = section_curve(paper, [0.0, 0.3], tube_squeeze=0.05, linear_gain=False)
    assert np.allclose(r.curvature_per_mm, c.curvature_per_mm, rtol=1e-12, atol=0)
    assert r.curvature_per_mm[0] == c.rest_curvature_per_mm < 0
    with pytest.raises(DesignError, match=r"tube_squeeze = 2: must be in \[0, 1\]"):
        SECTION_NONLINEAR.response(paper, [0.3], options={"tube_squeeze": 2})


@pytest.mark.slow
def test_full_squeeze_rest_state_names_what_it_reached(paper):
    # the paper's lumen closes before the full squeeze (measured: Newton reaches t = 0.5625)
    with pytest.raises(SectionConvergenceError, match=r"tube_squeeze = 1: not reached.* up to 0\.5"):
        section_curve(paper, [0.0, 0.1], tube_squeeze=1.0, linear_gain=False)
