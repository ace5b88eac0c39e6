"""The hoop cap's effect on the linear tip angle, against the finite-strain section model."""

from __future__ import annotations

import pytest

from softcath.design import preset
from softcath.fem.nonlinear.bend import _Model
from softcath.fem.nonlinear.catheter import HOOP_CAP, mesh_catheter
from softcath.fem.nonlinear.hoop_cap import hoop_cap_effect
from softcath.fem.section_model.finite_strain.curve import section_curve


@pytest.fixture(scope="module")
def paper_mesh():
    return mesh_catheter(preset("paper"), size=0.15, layers=3, curvature_points=12)


@pytest.mark.parametrize("load", ["lumen", "cap"])
def test_the_caps_effect_is_the_section_models(paper_mesh, load):
    # Peer: the finite-strain section model at a small pressure with and without the same cap.
    # Measured on 4 layers: paper -0.640 % against -0.723 % (lumen), +0.184 % against +0.201 %
    # (cap); two random designs within 0.02 points. The coils' laws differ slightly (3-D:
    # nu_TT 0.3, G_L = E_L / 2.6; section: the wire's nu), hence 0.15 points (a fifth of the effect).
    d = preset("paper")
    effect = hoop_cap_effect(_Model(d, paper_mesh, load=load, mixed=True))
    capped = section_curve(d, [0.002], load=load, hoop_cap=HOOP_CAP).bend_angle_rad[-1]
    steel = section_curve(d, [0.002], load=load).bend_angle_rad[-1]
    assert effect.relative == pytest.approx(capped / steel - 1.0, abs=1.5e-3)
    assert effect.hoop_modulus == pytest.approx(HOOP_CAP * d.tube.material.youngs_modulus)
    assert effect.steel_hoop_modulus > 50 * effect.hoop_modulus
    if load == "lumen":  # the capped coil confines less: the lumen-loaded tip turns less
        assert -0.012 < effect.relative < -0.003


def test_a_cap_above_the_steel_modulus_changes_nothing(paper_mesh):
    effect = hoop_cap_effect(_Model(preset("paper"), paper_mesh, load="lumen", mixed=True, hoop_cap=1e9))
    assert effect.hoop_modulus == effect.steel_hoop_modulus
    assert effect.relative == pytest.approx(0.0, abs=1e-9)
    doc = effect.to_json()
    assert doc["relative"] == effect.relative and "not part of" in doc["method"]


def test_an_uncapped_model_is_its_own_steel_reference(paper_mesh):
    effect = hoop_cap_effect(_Model(preset("paper"), paper_mesh, load="lumen", mixed=True, hoop_cap=None))
    assert effect.cap is None
    assert effect.hoop_modulus == effect.steel_hoop_modulus
    assert effect.relative == 0.0
