"""The app's state logic without a browser: applying a value, refusing one, the fields it offers."""

from __future__ import annotations

import tomllib

import pytest

from softcath import design
from softcath.design import presets
from softcath.design.errors import DesignError
from softcath.studies.app import apply_value, design_fields, initial_state
from softcath.studies.sweep.variants import build_variant, check_path


def test_a_value_is_applied_as_a_sweep_applies_it():
    s = initial_state("paper")
    s2 = apply_value(s, "tube.h", 0.02)
    assert s2.version == 1 and s2.errors == {}
    assert s2.design.tube_shape["h"] == 0.02
    assert s2.design == build_variant(s.base_table, {"tube.h": 0.02}, name="paper")
    assert s.design == design.preset("paper")  # states are values: the old one is untouched


def test_changes_accumulate_and_follow_the_coil_rule():
    s = apply_value(initial_state("paper"), "coil.outer_diameter", 0.9)
    s = apply_value(s, "materials.ecoflex_00_30.youngs_modulus", 0.2)
    s = apply_value(s, "assembly.tube_coil", "sliding")
    assert s.version == 3
    assert s.design.coil.wire_diameter == pytest.approx(0.15)  # a single-layer coil: (OD - ID)/2
    assert s.design.filler is not None and s.design.filler.youngs_modulus == 0.2
    assert s.design.assembly.tube_coil == "sliding"


def test_an_invalid_value_keeps_the_last_valid_design_and_says_why():
    s = apply_value(initial_state("paper"), "tube.h", 0.01)
    bad = apply_value(s, "tube.catalogue_inner_diameter", 0.7)
    assert bad.design == s.design and bad.version == s.version and bad.overrides == s.overrides
    msg = bad.errors["tube.catalogue_inner_diameter"]
    # the validator's own one-line message, as loading the same design file gives it
    table = tomllib.loads(presets.text("paper"))
    table["tube"]["catalogue_inner_diameter"] = 0.7
    with pytest.raises(DesignError) as exc:
        design.from_dict(table)
    assert msg == str(exc.value) and "\n" not in msg
    fixed = apply_value(bad, "tube.catalogue_inner_diameter", 0.35)
    assert fixed.errors == {} and fixed.design.tube.catalogue_inner_diameter == 0.35


@pytest.mark.parametrize(
    ("path", "value", "expect"),
    [
        ("tip.bending_length", None, "tip.bending_length = None: must be a number (mm)"),
        ("tip.bending_length", "abc", "tip.bending_length = 'abc': must be a number (mm)"),
        ("tip.bending_length", float("nan"), "tip.bending_length = nan: must be finite"),
        ("assembly.filler", "foam", "assembly.filler = 'foam': must be one of full, coat, none"),
        ("materials.medical_silicone_tubing.poisson_ratio", 0.5, "poisson_ratio = 0.5"),
        ("channel.outer_diameter", 0.7, "channel"),  # the channel no longer fits beside the tube
    ],
)
def test_refused_values_name_the_parameter(path, value, expect):
    s = apply_value(initial_state("paper"), path, value)
    assert expect in s.errors[path] and s.version == 0


def test_a_path_that_is_no_input_is_a_programming_error():
    with pytest.raises(DesignError, match="is not an input of the app"):
        apply_value(initial_state("paper"), "tube.colour", 1.0)


def test_every_input_is_a_design_path_a_sweep_accepts():
    s = initial_state("paper")
    fields = design_fields(s.base_table)
    for f in fields:
        check_path(s.base_table, f.path)
    groups = list(dict.fromkeys(f.group for f in fields))
    assert groups == [
        "coil",
        "tube",
        "channel",
        "tip",
        "filler",
        "materials.stainless_steel_sus304",
        "materials.medical_silicone_tubing",
        "materials.ecoflex_00_30",
        "assembly",
    ]
    assert all(f.unit or f.is_choice for f in fields)


def test_a_design_file_starts_the_state(tmp_path):
    path = design.save(
        build_variant(initial_state("paper").base_table, {"tip.bending_length": 6.0}), tmp_path / "d.toml"
    )
    assert initial_state(path).design.tip.bending_length == 6.0
    with pytest.raises(DesignError):
        initial_state(tmp_path / "missing.toml")
