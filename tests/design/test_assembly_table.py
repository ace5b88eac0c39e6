"""The as-built options: parsing, validation, TOML round trip, defaults."""

from dataclasses import replace

import pytest

from softcath import design
from softcath.design.assembly import Assembly


def test_defaults_are_todays_tip():
    a = Assembly()
    assert (a.tube_coil, a.filler, a.proximal) == ("bonded", "full", "clamped")
    assert a.is_default
    assert design.preset("paper").assembly.is_default


@pytest.mark.parametrize(
    ("key", "value", "allowed"),
    [
        ("tube_coil", "glued", "bonded, sliding, tied-at-tip"),
        ("filler", "half", "full, coat, none"),
        ("proximal", "free", "clamped, tube-free"),
    ],
)
def test_bad_value_names_key_value_and_allowed(key, value, allowed):
    with pytest.raises(design.DesignError, match=rf"assembly\.{key} = '{value}': must be one of {allowed}"):
        Assembly(**{key: value})


def test_bad_thickness_and_unknown_key():
    with pytest.raises(design.DesignError, match=r"assembly\.filler_coat_thickness = -0\.1: must be > 0"):
        Assembly(filler_coat_thickness=-0.1)
    with pytest.raises(design.DesignError, match=r"assembly\.tube_core = 'sliding': unknown key; allowed"):
        Assembly.from_dict({"tube_core": "sliding"})


def test_overrides():
    a = Assembly().with_overrides(["tube_coil=sliding", "filler=coat", "filler_coat_thickness=0.03"])
    assert (a.tube_coil, a.filler, a.filler_coat_thickness) == ("sliding", "coat", 0.03)
    with pytest.raises(design.DesignError, match=r"assembly = 'tube_coil': must be KEY=VALUE"):
        Assembly().with_overrides(["tube_coil"])
    with pytest.raises(
        design.DesignError, match=r"assembly\.filler_coat_thickness = 'thin': must be a number"
    ):
        Assembly().with_overrides(["filler_coat_thickness=thin"])


def test_toml_round_trip_and_default_not_written():
    d = design.preset("paper")
    assert "[assembly]" not in design.dumps(d)
    built = replace(d, assembly=Assembly(tube_coil="tied-at-tip", filler="coat", proximal="tube-free"))
    text = design.dumps(built)
    assert "[assembly]" in text
    assert design.loads(text) == built


def test_toml_assembly_table_errors():
    text = design.dumps(design.preset("paper")) + '\n[assembly]\nchannel_coil = "welded"\n'
    with pytest.raises(design.DesignError, match=r"assembly\.channel_coil = 'welded': must be one of"):
        design.loads(text)


def test_coat_needs_a_filler_material():
    d = design.preset("paper")
    with pytest.raises(design.DesignError, match=r"assembly\.filler = 'coat': needs a filler material"):
        replace(d, filler=None, assembly=Assembly(filler="coat"))
