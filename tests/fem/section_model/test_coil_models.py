"""Coil homogenisations of the section model against the resolved wire."""

from __future__ import annotations

import math

import pytest

from softcath import design
from softcath.fem.coil import resolved_coil_stiffness
from softcath.fem.section_model import section_model
from softcath.fem.section_model.coil_models import COIL_MODELS, coil_section_stiffness, model_options


@pytest.fixture(scope="module")
def paper():
    return design.resolve("paper")


@pytest.fixture(scope="module")
def wire(paper):
    return {"coil": resolved_coil_stiffness(paper.coil), "channel": resolved_coil_stiffness(paper.channel)}


@pytest.fixture(scope="module")
def carried():
    return {m: coil_section_stiffness("paper", coil_model=m) for m in COIL_MODELS}


def _worst(carried, wire, model) -> float:
    """Largest |log(section / resolved wire)| over EA and EI of both coils."""
    return max(
        abs(math.log(carried[model][n][k] / ref))
        for n, r in wire.items()
        for k, ref in (("EA_N", r.axial_tension), ("EI_N_mm2", r.bending))
    )


def test_resolved_model_carries_both_stiffnesses(carried, wire):
    # 0.5 %: the resolved wire's chord error at 48 elements per turn (EA 9/m^2 = 0.4 %,
    # EI 0.07 %) plus the meshed annulus's area error (0.2 % at the default mesh).
    for n, r in wire.items():
        assert carried["resolved"][n]["EA_N"] == pytest.approx(r.axial_tension, rel=5e-3)
        assert carried["resolved"][n]["EI_N_mm2"] == pytest.approx(r.bending, rel=5e-3)
    # Every other homogenisation misses one of the four numbers by more than 5 %.
    assert _worst(carried, wire, "resolved") < 5e-3
    for m in ("annulus", "annulus-bending", "wahl"):
        assert _worst(carried, wire, m) > 0.05, m


def test_annulus_models_match_their_closed_forms(carried, paper):
    # The annulus laws carry E A and E I_a of the exact annulus to the mesh's area error (0.3 %).
    for n, c in (("coil", paper.coil), ("channel", paper.channel)):
        k = design.coil_stiffness(c)
        t, b, w = carried["annulus"][n], carried["annulus-bending"][n], carried["wahl"][n]
        assert t["EA_N"] == pytest.approx(k.axial_modulus_tension * k.area, rel=3e-3)
        assert t["EI_N_mm2"] == pytest.approx(k.axial_modulus_tension * k.second_moment, rel=3e-3)
        assert b["EI_N_mm2"] == pytest.approx(k.bending_stiffness, rel=3e-3)
        assert w["EI_N_mm2"] == pytest.approx(k.bending_stiffness, rel=3e-3)
        assert w["EA_N"] == pytest.approx(t["EA_N"], rel=1e-12)
    # The spring-rate formula fails at the channel's D/d = 3 (direct shear): 6 % too stiff.
    assert carried["wahl"]["channel"]["EA_N"] / carried["resolved"]["channel"]["EA_N"] > 1.05


def test_coil_axial_modulus_enters_only_the_global_block(carried):
    # The section's EA and axial-bending coupling move exactly by the coils' own int E_z phi dA:
    # the in-plane field does not see the axial modulus (no Poisson coupling, nu_c = 0).
    a = section_model("paper", loads=("cap",), **model_options("wahl"))
    r = section_model("paper", loads=("cap",), **model_options("resolved"))
    d_ea = sum(carried["resolved"][n]["EA_N"] - carried["wahl"][n]["EA_N"] for n in ("coil", "channel"))
    d_s = sum(
        carried["resolved"][n]["EA_N"] * carried["resolved"][n]["y_mm"]
        - carried["wahl"][n]["EA_N"] * carried["wahl"][n]["y_mm"]
        for n in ("coil", "channel")
    )
    assert r.EA_N - a.EA_N == pytest.approx(d_ea, rel=1e-9)
    assert r.stiffness[0][2] - a.stiffness[0][2] == pytest.approx(d_s, rel=1e-7)


def test_resolved_bends_least_of_the_two_tension_models():
    # More own EI than the annulus: less curvature per MPa for both loads.
    a = section_model("paper", **model_options("annulus"))
    r = section_model("paper", **model_options("resolved"))
    for ld in ("cap", "lumen"):
        assert r.curvature_per_mm_per_MPa[ld] < 0.7 * a.curvature_per_mm_per_MPa[ld]
    assert r.coil_bending == "resolved"


def test_bad_coil_model_names_the_parameter():
    with pytest.raises(design.DesignError, match="coil_model"):
        model_options("spring")
    with pytest.raises(design.DesignError, match="coil_modulus"):
        section_model("paper", coil_modulus="bending", coil_bending="resolved")
