"""The registry: names, old spellings, refusals naming the parameter, and capabilities as data."""

from __future__ import annotations

import inspect
import logging
import math

import numpy as np
import pytest

from softcath import design, models
from softcath.design.errors import DesignError
from softcath.models.validity import LINEAR_BEND_LIMIT_DEG

PAPER = design.preset("paper")


def test_the_five_tiers_in_order_with_their_one_name():
    assert models.names() == ("paper", "section", "section-nonlinear", "fem", "fem-nonlinear")
    assert [t.name for t in models.tiers()] == list(models.names())
    assert models.names(exclude=("fem",)) == ("paper", "section", "section-nonlinear", "fem-nonlinear")


def test_an_old_spelling_is_the_same_tier_with_a_logged_deprecation(caplog):
    with caplog.at_level(logging.WARNING):
        assert models.get("analytic") is models.get("paper")
        assert models.get("nonlinear") is models.get("fem-nonlinear")
    assert "'analytic' is deprecated: use 'paper'" in caplog.text


def test_an_unknown_tier_names_the_parameter_the_value_and_the_tiers():
    with pytest.raises(
        DesignError, match=r"tier = 'ansys': must be one of paper, section, section-nonlinear"
    ):
        models.response(PAPER, [0.1], tier="ansys")
    with pytest.raises(DesignError, match=r"model = 'fem': must be one of paper, section$"):
        models.get("fem", allowed=("paper", "section"))


def test_an_unsupported_load_names_the_loads_the_tier_answers():
    with pytest.raises(DesignError, match=r"load = 'wall': paper answers the loads cap, lumen"):
        models.response(PAPER, [0.1], tier="paper", load="wall")


def test_an_unsupported_option_names_the_option_and_what_the_tier_accepts():
    with pytest.raises(DesignError, match=r"options\.mesh_size = 0\.1: paper accepts the options none"):
        models.response(PAPER, [0.1], tier="paper", options={"mesh_size": 0.1})
    with pytest.raises(
        DesignError, match=r"options\.coil_bending = 'wahl': fem accepts the options mesh_size, mesher"
    ):
        models.get("fem").check_options({"coil_bending": "wahl"})
    # None means "the default": left out, never refused
    assert models.get("paper").check_options({"mesh_size": None}) == {}


def test_registering_twice_is_refused():
    with pytest.raises(DesignError, match=r"tier\.name = 'paper': is registered already"):
        models.register(models.get("paper"))
    with pytest.raises(DesignError, match=r"tier = 'paper': must be a softcath.models.Tier"):
        models.register("paper")  # pyright: ignore[reportArgumentType]  # a wrong type on purpose


def test_a_new_tier_is_one_register_call_and_answers_through_the_registry():
    # a tier of its own: the paper's formula scaled by 2, registered and asked by name
    paper = models.get("paper")

    class Doubled(type(paper)):
        def _solve(self, designs, pressures, loads, options):
            out = super()._solve(designs, pressures, loads, options)
            return {
                ld: self._batch(designs, pressures, ld, {"curvature_per_mm": 2 * b.curvature_per_mm})
                for ld, b in out.items()
            }

    t = Doubled("doubled", "a doubled formula", "2x", "test tier", "doubled", default_load="cap")
    models.register(t, aliases=("twice",))
    try:
        r = models.response(PAPER, [0.1], tier="twice")
        assert r.tier == "doubled"
        assert r.curvature_per_mm[0] == pytest.approx(2 * paper.response(PAPER, [0.1]).curvature_per_mm[0])
        assert np.isnan(r.bend_angle_rad[0])  # a field the tier does not give is NaN
    finally:
        del models.TIERS["doubled"], models.ALIASES["twice"]


def test_validity_is_one_rule_linear_tiers_to_five_degrees():
    assert models.linear_names() == ("paper", "section", "fem")
    for t in models.tiers():
        assert t.valid_to_deg == (LINEAR_BEND_LIMIT_DEG if t.linear else math.inf)
    from softcath.studies import model_validity

    assert model_validity.LINEAR_TIERS == models.linear_names()
    assert model_validity.LINEAR_BEND_LIMIT_DEG is LINEAR_BEND_LIMIT_DEG


def test_a_linear_response_past_its_range_says_so():
    # 1 MPa bends the paper tip far past 5 deg under the cap load (the formula: > 50 deg)
    r = models.response(PAPER, [1.0], tier="paper", load="cap")
    assert np.degrees(r.bend_angle_rad[0]) > LINEAR_BEND_LIMIT_DEG
    assert any("beyond the ~5 deg" in w and "the paper's formula" in w for w in r.warnings)
    assert models.response(PAPER, [0.001], tier="paper", load="cap").warnings == ()


def test_option_defaults_are_the_direct_calls_defaults():
    # a tier's declared defaults are those of the function it calls (so `parameters` is honest)
    from softcath.fem import check
    from softcath.fem.nonlinear.bend import bend_curve
    from softcath.fem.section_model import section_model
    from softcath.fem.section_model.mesh import MESH_SIZE

    def defaults(fn):
        return {k: p.default for k, p in inspect.signature(fn).parameters.items()}

    # ...except where the tier passes its own default explicitly: the 3-D check's companion solve
    # (its stated error, ~50 % of a solve) is not made for sweep rows, which do not carry it
    explicit = {("fem", "error_estimate"): (True, False)}
    for name, fn in (("section", section_model), ("fem", check), ("fem-nonlinear", bend_curve)):
        d = defaults(fn)
        for option, value in models.get(name).options.items():
            assert (d[option], value) == explicit.get((name, option), (value, value)), (name, option)
    assert models.get("section").options["mesh_size"] == MESH_SIZE


def test_the_as_built_capability_refuses_a_sliding_tip_on_a_bonded_tier():
    sliding = {"tube_coil": "sliding"}
    models.get("section").check_assembly(sliding)  # modelled
    with pytest.raises(
        DesignError,
        match=r"assembly = .*is modelled by the section model, the finite-strain section model "
        r"and the 3-D FEM only",
    ):
        models.get("paper").check_assembly(sliding)
    with pytest.raises(DesignError, match=r"assembly\.tube_coil = 'sliding'.*bonded interfaces only"):
        models.get("fem-nonlinear").check_assembly(sliding)
