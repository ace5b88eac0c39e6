"""A tier never answers an as-built design with its bonded model, an option that would have no
effect is refused, and a text field cannot be varied as a number."""

from __future__ import annotations

from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from softcath import design
from softcath.design.assembly import FILLERS, INTERFACE_KINDS, PROXIMAL, Assembly
from softcath.studies.tiers import ASSEMBLY_TIERS, TIERS, check_assembly

SETTINGS = settings(max_examples=80, deadline=None, derandomize=True, database=None)

assemblies = st.builds(
    Assembly,
    tube_coil=st.sampled_from(INTERFACE_KINDS),
    tube_channel=st.sampled_from(INTERFACE_KINDS),
    channel_coil=st.sampled_from(INTERFACE_KINDS),
    filler_coil=st.sampled_from(INTERFACE_KINDS),
    filler=st.sampled_from(FILLERS),
    proximal=st.sampled_from(PROXIMAL),
)


@SETTINGS
@given(a=assemblies, tier=st.sampled_from(sorted(set(TIERS) - {"fem-nonlinear"})))
def test_a_bonded_tier_refuses_every_as_built_option(a, tier):
    if a.is_default or tier in ASSEMBLY_TIERS:
        check_assembly(tier, a)
    else:
        with pytest.raises(design.DesignError, match="one bonded body"):
            check_assembly(tier, a)


@SETTINGS
@given(filler=st.sampled_from(FILLERS), thickness=st.floats(0.001, 0.2))
def test_a_coat_thickness_without_a_coat_is_refused(filler, thickness):
    if filler == "coat" or thickness == 0.02:
        assert Assembly(filler=filler, filler_coat_thickness=thickness).filler == filler
    else:
        with pytest.raises(design.DesignError, match=r"filler_coat_thickness = .*has no effect"):
            Assembly(filler=filler, filler_coat_thickness=thickness)


@pytest.fixture
def sliding(tmp_path):
    d = replace(design.preset("paper"), assembly=Assembly(tube_coil="sliding"))
    path = tmp_path / "sliding.toml"
    path.write_text(design.dumps(d), encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "argv",
    [
        ["predict", "{d}", "--model", "paper", "--vary", "tube.h=-0.01:0.01", "--samples", "20"],
        ["predict", "{d}", "--model", "section", "--compare", "paper", "--vary", "tube.h=-0.01:0.01"],
        ["optimise", "{d}", "--model", "paper", "--vary", "tube.h=-0.04:0.04", "--objective", "maximise x"],
        ["analytic", "{d}"],
    ],
    ids=["predict", "predict-compare", "optimise", "analytic"],
)
def test_the_paper_formula_refuses_a_sliding_design_in_every_command(cli, tmp_path, sliding, argv):
    out = tmp_path / "o"
    line = cli(*[sliding if a == "{d}" else a for a in argv], "--out", out).error_line()
    assert (
        "{'tube_coil': 'sliding'}: is modelled by the section model, the finite-strain section model "
        "and the 3-D FEM only" in line
    )
    assert not out.exists()


def test_predict_compare_names_an_unknown_tier(cli, tmp_path):
    line = cli("predict", "paper", "--compare", "bogus", "--out", tmp_path / "o").error_line()
    assert "--compare = 'bogus': 'bogus' is not a tier of predict" in line


def test_a_text_field_cannot_vary_between_numbers(cli, tmp_path):
    out = tmp_path / "o"
    argv = [
        "optimise",
        "paper",
        "--model",
        "paper",
        "--vary",
        "coil.material=0:1",
        "--objective",
        "maximise x",
    ]
    line = cli(*argv, "--out", out).error_line()
    assert "--vary coil.material = '0:1': coil.material is 'stainless_steel_sus304', not a number" in line
    assert not out.exists()


@SETTINGS
@given(t=st.floats(0.001, 2.0))
def test_a_coat_that_fills_every_void_is_refused(t):
    d = design.preset("paper")
    reach = d.coil.inner_diameter - d.channel.outer_diameter
    if t >= reach:
        with pytest.raises(design.DesignError, match=r"fills every void, the same as filler = \"full\""):
            replace(d, assembly=Assembly(filler="coat", filler_coat_thickness=t))
    else:
        assert replace(d, assembly=Assembly(filler="coat", filler_coat_thickness=t)).assembly.filler == "coat"


def test_vary_bounds_follow_the_design_number_rule(cli, tmp_path):
    argv = [
        "optimise",
        "paper",
        "--model",
        "paper",
        "--vary",
        "tube.h=-1e300:1e300",
        "--objective",
        "maximise x",
    ]
    line = cli(*argv, "--out", tmp_path / "o").error_line()
    assert "--vary tube.h = '-1e300:1e300': LO and HI must be within ±1e+09" in line
    assert not (tmp_path / "o").exists()
