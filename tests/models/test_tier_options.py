"""Tier options from texts and tables: coerced to the default's type, refused with the tier's options."""

from __future__ import annotations

import pytest

from softcath import models
from softcath.core.errors import DesignError
from softcath.models.paper import PAPER


def test_a_text_is_read_as_its_default_type():
    got = models.parse_tier_options(
        ["mesh_size=0.1", "segments=12", "section.poisson=false", "poisson_cap=0.49", "mesher=gmsh"],
        tiers=["paper", "section", "fem"],
    )
    assert got == {
        "section": {
            "mesh_size": 0.1,
            "segments": 12,
            "poisson": False,
            "poisson_cap": 0.49,
            "mesher": "gmsh",
        },
        "fem": {"mesh_size": 0.1, "mesher": "gmsh"},  # NAME alone: each tier of the command taking it
    }
    assert type(got["section"]["segments"]) is int and type(got["section"]["mesh_size"]) is float
    assert models.parse_tier_options([], tiers=["section"]) == {}


@pytest.mark.parametrize(
    ("items", "match"),
    [
        (["mesh_size"], r"--model-option = 'mesh_size': must be NAME=VALUE or TIER\.NAME=VALUE"),
        (["foo=1"], r"unknown option 'foo': paper takes no options; section takes the options mesh_size"),
        (["segments=2.5"], r"--model-option segments = '2.5': must be an integer \(default 20\)"),
        (["mesh_size=fine"], r"--model-option mesh_size = 'fine': must be a number \(default 0.08\)"),
        (["poisson=maybe"], r"--model-option poisson = 'maybe': must be true or false"),
        (["fem.mesh_size=0.1"], r"names tier 'fem'; this command runs the tiers paper, section"),
    ],
)
def test_bad_items_are_refused_naming_the_option_and_the_bound(items, match):
    with pytest.raises(DesignError, match=match):
        models.parse_tier_options(items, tiers=["paper", "section"])


def test_a_table_is_checked_against_the_tiers_it_names():
    table = {"fem": {"mesh_size": 0.2}, "section": {"segments": 10, "mesh_size": 0.05}}
    assert models.check_tier_options(table, parameter="sweep.options") == {
        "section": {"segments": 10, "mesh_size": 0.05},  # registry order
        "fem": {"mesh_size": 0.2},
    }
    with pytest.raises(
        DesignError, match=r"sweep\.options\.fem = .*must name a tier run here: paper, section"
    ):
        models.check_tier_options(table, parameter="sweep.options", tiers=("paper", "section"))
    with pytest.raises(DesignError, match=r"sweep\.options\.section\.segments = True: must be of the type"):
        models.check_tier_options({"section": {"segments": True}}, parameter="sweep.options")
    with pytest.raises(DesignError, match=r"sweep\.options\.section\.segments = 2\.5: must be an integer"):
        models.check_tier_options({"section": {"segments": 2.5}}, parameter="sweep.options")
    with pytest.raises(DesignError, match=r"sweep\.options\.paper\.x = 1: is not an option of paper"):
        models.check_tier_options({"paper": {"x": 1}}, parameter="sweep.options")
    assert models.options_of({"section": {"segments": 10}}, models.get("section")) == {"segments": 10}
    assert models.options_of(None, "paper") == {}


def test_registered_restores_the_registry_and_unregister_removes_a_tier():
    before = dict(models.TIERS)
    extra = PAPER.__class__(**{**PAPER.__dict__, "name": "paper-test"})
    with models.registered(extra) as tier:
        assert models.get("paper-test") is tier and models.names()[-1] == "paper-test"
        with pytest.raises(DesignError, match="is registered already"):
            models.register(extra)
    assert models.TIERS == before
    models.register(extra, aliases=("paper-old",))
    assert models.unregister("paper-test") is extra
    assert "paper-test" not in models.TIERS and "paper-old" not in models.ALIASES
    with pytest.raises(DesignError, match=r"tier\.name = 'paper-test': is not registered"):
        models.unregister("paper-test")
    with models.registered(
        extra.__class__(**{**PAPER.__dict__, "option_choices": {"x": (1,)}}), replace=True
    ):
        assert models.names() == tuple(before)  # in the replaced tier's place
        assert models.get("paper") is not PAPER
    assert models.get("paper") is PAPER


def test_option_choices_are_checked_by_the_tier():
    tier = PAPER.__class__(
        **{**PAPER.__dict__, "options": {"law": "a"}, "option_choices": {"law": ("a", "b")}}
    )
    assert tier.check_options({"law": "b"}) == {"law": "b"}
    with pytest.raises(DesignError, match=r"options\.law = 'c': paper takes a, b"):
        tier.check_options({"law": "c"})
