"""Coil-bound coils with initial tension in the finite-strain section model.

(a) A bar of the coil under a pure axial load N: the law S_33 = min(E_c E, E_t E + F0/A) in
the Green-Lagrange strain E = (lambda^2 - 1)/2, the force N = A lambda S_33. The turns open at
E_p = sigma_0 / (E_c - E_t), at the load N_p = A lambda_p E_c E_p = F0 E_c / (E_c - E_t) lambda_p,
F0 to 1e-5 for a steel coil (E_c / E_t ~ 1e5); below it the stretch is the coil-bound root,
above it the open coil's. Roots to 1e-12 (brentq), the law's smoothing 1e-8 in strain, so
the strains agree to 1e-7 of themselves.

(b) Small bends against the linear section model's bilinear coils (``bilinear.bend_curve``,
annulus placement: the finite-strain section's homogenised annulus): at F0 = 0 the share of
the homogenised curvature the coil-bound section lets through is the linear model's pivoting
gain over its linear gain (measured within 1.4e-4, 1e-3 below; the finite strain's O(strain)
at 0.004 MPa); with F0 the curve is near zero below the opening and the straight line through
two pressures past it meets zero at the linear model's threshold (measured 0.5 % cap, 1.0 %
lumen; 2.5 % below: the line's secant through the curvature's finite-strain bending of O(p)).
"""

from __future__ import annotations

import dataclasses
from typing import cast

import numpy as np
import pytest
from scipy.optimize import brentq

from softcath import design as design_pkg
from softcath.design import coil_stiffness
from softcath.design.errors import DesignError
from softcath.fem.geometry import CHANNEL, COIL
from softcath.fem.hyperelastic.laws import AnisotropicSVK
from softcath.fem.section_model.bilinear import bend_curve
from softcath.fem.section_model.finite_strain import section_curve, section_laws
from softcath.fem.section_model.finite_strain.coil_bound import HALF_WIDTH, CoilBoundSVK, axial_stress
from softcath.fem.section_model.finite_strain.curve import section_laws as section_laws_from_curve

F0 = 0.05  # N: inside the prototype's sourced range


@pytest.fixture(scope="module")
def paper():
    return design_pkg.resolve("paper")


@pytest.fixture(scope="module")
def coil_law(paper):
    return section_laws(paper, coil_bound=True, initial_tension=F0)[COIL]


def _bar(law, stretch):
    """(N / A, in-plane stress) of a bar of ``law`` at axial ``stretch`` (no axial-transverse coupling)."""
    f = np.diag([1.0, 1.0, stretch])
    p, _ = law.stress_tangent(f)
    return p[2, 2], abs(p[0, 0]) + abs(p[1, 1])


def test_the_bar_opens_at_the_initial_tension_and_follows_the_bilinear_law(paper, coil_law):
    k = coil_stiffness(paper.coil)
    et, ec, s0 = coil_law.tension_modulus, coil_law.compression_modulus, coil_law.prestress
    assert et == pytest.approx(k.axial_modulus_tension, rel=1e-12)
    assert ec == k.axial_modulus_compression and s0 * k.area == pytest.approx(F0, rel=1e-14)
    e_p = s0 / (ec - et)
    lam_p = np.sqrt(1 + 2 * e_p)
    n_open = F0 * ec / (ec - et) * lam_p
    assert n_open == pytest.approx(F0, rel=1e-5)
    for share in (-2.0, 0.3, 0.9, 1.1, 3.0):
        n = share * F0
        root = brentq(
            lambda x, n=n: k.area * _bar(coil_law, x)[0] - n, 0.9, 3.0, xtol=1e-15, rtol=np.float64(1e-15)
        )
        lam = cast(float, root)  # full_output=False: the root alone
        if n < n_open:  # coil-bound: A lam E_c E = N
            e = brentq(lambda e, n=n: k.area * np.sqrt(1 + 2 * e) * ec * e - n, -0.1, 0.1, xtol=1e-16)
        else:  # open: A lam (E_t E + sigma_0) = N
            e = brentq(lambda e, n=n: k.area * np.sqrt(1 + 2 * e) * (et * e + s0) - n, -0.1, 0.5, xtol=1e-16)
        assert 0.5 * (lam**2 - 1) == pytest.approx(e, rel=1e-7, abs=HALF_WIDTH)
        assert _bar(coil_law, lam)[1] == 0.0  # a uniaxial state: no in-plane stress


@pytest.mark.parametrize("f0", [0.0, F0])
def test_the_tangent_is_the_stress_derivative(paper, f0):
    law = section_laws(paper, coil_bound=True, initial_tension=f0)[COIL]
    rng = np.random.default_rng(3)
    # points 10 steps h or more from the kink (its rounding is 1e-8 wide: inside it, the scalar test)
    for e33 in (-1e-3, law.opening_strain + 1e-6, 2e-3, 0.05):
        f = np.eye(3) + 1e-3 * rng.standard_normal((3, 3))
        f[2, 2] = np.sqrt(1 + 2 * e33 - f[0, 2] ** 2 - f[1, 2] ** 2)
        p, a = law.stress_tangent(f)
        h = 1e-7
        num = np.zeros((3, 3, 3, 3))
        dw = np.zeros((3, 3))
        for i in range(3):
            for j in range(3):
                df = np.zeros((3, 3))
                df[i, j] = h
                num[:, :, i, j] = (law.stress_tangent(f + df)[0] - law.stress_tangent(f - df)[0]) / (2 * h)
                dw[i, j] = (law.energy(f + df) - law.energy(f - df)) / (2 * h)
        # central differences of O(h^2) on moduli up to 1.5e5 MPa: 1e-7 of the largest entry
        np.testing.assert_allclose(num, a, atol=1e-7 * np.abs(a).max())
        np.testing.assert_allclose(dw, p, atol=1e-7 * np.abs(p).max())


def test_the_smoothed_kink_is_exact_outside_its_width():
    kw = {"tension_modulus": 2.0, "compression_modulus": 1e5, "prestress": 0.3}
    e_p = 0.3 / (1e5 - 2.0)
    e = np.array([-1e-3, e_p - 2 * HALF_WIDTH, e_p + 2 * HALF_WIDTH, 1e-2])
    _, s, ds = axial_stress(e, **kw)
    np.testing.assert_allclose(
        s, np.minimum(1e5 * e, 2.0 * e + 0.3), rtol=1e-12
    )  # E_c e - (E_c - E_t) e: cancellation
    np.testing.assert_array_equal(ds, [1e5, 1e5, 2.0, 2.0])
    _, s_p, ds_p = axial_stress(e_p, **kw)
    assert s_p == pytest.approx(1e5 * e_p - (1e5 - 2.0) * HALF_WIDTH / 4, rel=1e-12)  # the rounding's depth
    assert ds_p == pytest.approx(0.5 * (1e5 + 2.0))
    # inside the rounding the tangent is the stress's derivative too (steps of 1e-3 of its width)
    for x in e_p + HALF_WIDTH * np.array([-0.9, -0.3, 0.4, 0.9]):
        h = 1e-11
        psi, s_x, ds_x = axial_stress(x, **kw)
        dsig = (axial_stress(x + h, **kw)[1] - axial_stress(x - h, **kw)[1]) / (2 * h)
        dpsi = (axial_stress(x + h, **kw)[0] - axial_stress(x - h, **kw)[0]) / (2 * h)
        assert dsig == pytest.approx(ds_x, rel=1e-5)
        assert dpsi == pytest.approx(s_x, rel=1e-5)


def test_off_is_bit_for_bit_the_default(paper):
    p = [0.1, 0.3]
    a = section_curve(paper, p)
    b = section_curve(paper, p, coil_bound=False, initial_tension=F0, compression_modulus=1e4)
    for name in ("curvature_per_mm", "elongation", "bend_angle_rad", "tip_x_mm", "tip_y_mm"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    laws = section_laws(paper, coil_bound=False, initial_tension=F0)
    assert all(type(laws[k]) is AnisotropicSVK for k in (COIL, CHANNEL))
    assert section_laws_from_curve is section_laws  # the old import path stays


@pytest.mark.parametrize("load", ["cap", "lumen"])
def test_small_bends_match_the_linear_bilinear_model(paper, load):
    p = np.array([0.002, 0.004])
    off = section_curve(paper, p, load=load)
    on = section_curve(paper, p, load=load, coil_bound=True, initial_tension=0.0)
    lin = bend_curve(paper, p, load=load, coil_model="annulus", initial_tension=(0.0, 0.0))
    share = on.curvature_per_mm / off.curvature_per_mm
    np.testing.assert_allclose(share, lin.gain_pivoting / lin.gain_linear, rtol=1e-3)
    f0 = 0.001
    lin = bend_curve(paper, [0.1], load=load, coil_model="annulus", initial_tension=(f0, 0.0))
    q = lin.threshold_pressure * np.array([0.5, 2.0, 3.0])
    k = section_curve(paper, q, load=load, coil_bound=True, initial_tension=f0).curvature_per_mm
    assert abs(k[0]) < 1e-4 * k[2]  # closed: steel-stiff below the opening (measured 1.1e-5)
    threshold = q[1] - k[1] * (q[2] - q[1]) / (k[2] - k[1])
    assert threshold == pytest.approx(lin.threshold_pressure, rel=0.025)


def test_the_smoothing_does_not_change_the_curve(paper):
    """The kink's rounding 1e-8 against 1e-9 and 1e-7 on a curve through the opening (F0 = 5 mN
    opens at 0.03 MPa, E_p = 1.5e-7): measured 1.3e-14 and 5.1e-8 of the curve's largest curvature."""
    p = [0.02, 0.1, 0.3]
    base = section_laws(paper, coil_bound=True, initial_tension=0.005)
    ref = section_curve(paper, p, laws=base).curvature_per_mm
    for h, tol in ((1e-9, 1e-10), (1e-7, 1e-6)):
        laws = {**base, COIL: dataclasses.replace(base[COIL], half_width=h)}
        got = section_curve(paper, p, laws=laws).curvature_per_mm
        np.testing.assert_allclose(got, ref, rtol=0, atol=tol * ref.max())


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"initial_tension": -0.01}, "initial_tension"),
        ({"initial_tension": float("nan")}, "initial_tension"),
        ({"compression_modulus": -1.0}, "compression_modulus"),
        ({"compression_modulus": 0.5}, "compression_modulus"),  # below E_t
    ],
)
def test_bad_input_is_refused_naming_the_parameter(paper, kwargs, name):
    with pytest.raises(ValueError, match=name):
        section_curve(paper, [0.1], coil_bound=True, **kwargs)
    with pytest.raises(ValueError, match="coil_bound"):
        section_curve(paper, [0.1], coil_bound="no")  # pyright: ignore[reportArgumentType]  # a wrong type on purpose


def test_the_law_refuses_a_preload_without_a_stiffer_compression(coil_law):
    with pytest.raises(DesignError, match="prestress"):
        CoilBoundSVK(coil_law.tensor, compression_modulus=coil_law.tension_modulus, prestress=0.1)
    with pytest.raises(DesignError, match="half_width"):
        CoilBoundSVK(coil_law.tensor, compression_modulus=1e5, half_width=0.0)
