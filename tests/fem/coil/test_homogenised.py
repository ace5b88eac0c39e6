"""Homogenised coil models used as the resolved wire's comparison."""

from __future__ import annotations

import doctest

import numpy as np
import pytest

import softcath.fem.coil
from softcath import design
from softcath.fem.coil.homogenised import bimodular_annulus_bending, homogenised_models


def test_bimodular_annulus_reduces_to_the_isotropic_annulus():
    ei, yn = bimodular_annulus_bending(
        outer_radius=0.4, inner_radius=0.3, tension_modulus=5.0, compression_modulus=5.0
    )
    assert yn == pytest.approx(0.0, abs=1e-12)
    assert ei == pytest.approx(5.0 * np.pi / 4 * (0.4**4 - 0.3**4), rel=1e-10)


def test_bimodular_thin_ring_pivots_on_its_compressed_edge():
    # E_c >> E_t: the neutral axis goes to the bottom of a thin ring, EI -> E_t (I + A R²) = 1.5 E_t A R².
    r, t = 1.0, 1e-3
    ei, yn = bimodular_annulus_bending(
        outer_radius=r + t / 2, inner_radius=r - t / 2, tension_modulus=1.0, compression_modulus=1e9
    )
    assert yn == pytest.approx(-r, rel=2e-3)
    assert ei == pytest.approx(1.5 * 2 * np.pi * r * t * r**2, rel=5e-3)


def test_homogenised_models_follow_design_coil_stiffness():
    coil = design.resolve("paper").coil
    k = design.coil_stiffness(coil)
    m = homogenised_models(coil)
    assert m["annulus_tension"]["bending_N_mm2"] == pytest.approx(k.axial_modulus_tension * k.second_moment)
    assert m["annulus_bending"]["axial_tension_N"] == pytest.approx(k.bending_modulus * k.area)
    assert m["spring_wahl"]["bending_N_mm2"] == pytest.approx(k.bending_stiffness)
    bi = m["bimodular_annulus"]
    assert bi["axial_compression_N"] == pytest.approx(k.axial_modulus_compression * k.area)
    # Between the annulus about its centre and the same annulus about its compressed edge.
    e_t, area, r_o = k.axial_modulus_tension, k.area, coil.outer_diameter / 2
    assert e_t * k.second_moment < bi["bending_N_mm2"] < e_t * (k.second_moment + area * r_o**2)


def test_package_docstring_example():
    result = doctest.testmod(softcath.fem.coil)
    assert result.attempted == 4 and result.failed == 0  # the four lines of the example
