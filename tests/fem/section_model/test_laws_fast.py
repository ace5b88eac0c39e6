"""The section laws' shortcuts (coil stiffness cache, Voigt entries) give the straightforward laws."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from softcath.design.coil_mechanics import CoilStiffness, coil_stiffness, coil_stiffness_arrays
from softcath.fem.adapter import coil_law
from softcath.fem.geometry import CHANNEL, COIL
from softcath.fem.materials import TransverselyIsotropic
from softcath.fem.section_model.laws import from_tensor, section_laws_from_design
from softcath.studies.sweep.random_designs import random_designs


@pytest.fixture(scope="module")
def designs():
    return random_designs(20, seed=12)


def _computed(coil) -> CoilStiffness:
    values = coil_stiffness_arrays(
        outer_diameter=coil.outer_diameter,
        inner_diameter=coil.inner_diameter,
        wire_diameter=coil.wire_diameter,
        pitch=coil.pitch,
        youngs_modulus=coil.material.youngs_modulus,
        poisson_ratio=coil.material.poisson_ratio,
    )
    return CoilStiffness(**{k: float(v) for k, v in values.items()})


def test_cached_coil_stiffness_is_the_computed_one(designs):
    for d in designs:
        for coil in (d.coil, d.channel):
            assert coil_stiffness(coil) == _computed(coil)
            assert coil_stiffness(coil) == _computed(coil)  # from the cache
    coil = designs[0].coil
    stiffer = dataclasses.replace(coil, material=dataclasses.replace(coil.material, youngs_modulus=1e6))
    assert coil_stiffness(stiffer) == _computed(stiffer) != coil_stiffness(coil)


@pytest.mark.parametrize("coil_modulus", ["tension", "bending"])
@pytest.mark.parametrize("poisson", [True, False])
def test_coil_laws_are_the_tensor_entries(designs, coil_modulus, poisson):
    for d in designs:
        laws = section_laws_from_design(d, coil_modulus=coil_modulus, poisson=poisson)
        for coil, label in ((d.coil, COIL), (d.channel, CHANNEL)):
            law = coil_law(coil, coil_modulus)
            if not poisson:
                law = dataclasses.replace(law, transverse_poisson=0.0, coupling_poisson=0.0)
            want = from_tensor(law.tensor(), law.axial_modulus)
            got = laws[label]
            np.testing.assert_array_equal(got.D, want.D)
            assert (got.lam, got.axial_modulus) == (want.lam, want.axial_modulus)
            assert np.isnan(got.poisson_ratio) and got.D.flags.c_contiguous


def test_voigt_and_tensor_agree():
    law = TransverselyIsotropic(
        axial_modulus=3.0,
        transverse_modulus=2e5,
        transverse_poisson=0.3,
        coupling_poisson=0.1,
        axial_shear_modulus=1.1,
    )
    c, v = law.tensor(), law.voigt()
    pairs = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))
    for a, (i, j) in enumerate(pairs):
        for b, (k, m) in enumerate(pairs):
            assert c[i, j, k, m] == c[j, i, m, k] == v[a, b]
