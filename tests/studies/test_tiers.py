"""The model tiers' one name each: lookup, old spellings, refusals, stored sweeps."""

from __future__ import annotations

import logging
import tomllib

import pytest

from softcath.design.errors import DesignError
from softcath.studies.sweep.spec import EVALUATORS, parse_spec
from softcath.studies.tiers import ALIASES, TIERS, tier, tier_name, tier_names


def test_the_five_tiers_in_order_and_the_sweep_evaluators_are_them():
    assert tier_names() == ("paper", "section", "section-nonlinear", "fem", "fem-nonlinear")
    assert EVALUATORS == tier_names()
    assert tier("section").label == "the section model"


def test_an_old_spelling_maps_to_the_new_name_with_a_logged_deprecation(caplog):
    with caplog.at_level(logging.WARNING, logger="softcath.studies.tiers"):
        assert tier_name("analytic") == "paper"
        assert tier_name("nonlinear") == "fem-nonlinear"
    assert "'analytic' is deprecated: use 'paper'" in caplog.text
    assert set(ALIASES.values()) <= set(TIERS)


def test_an_unknown_tier_names_the_value_and_the_allowed_ones():
    with pytest.raises(DesignError, match=r"model = 'beam': must be one of paper, section, fem$"):
        tier("beam", allowed=("paper", "section", "fem"))
    with pytest.raises(
        DesignError, match=r"sweep\.evaluators = 'fem-nonlinear': must be one of paper, section"
    ):
        tier_name("fem-nonlinear", parameter="sweep.evaluators", allowed=("paper", "section"))


def _spec(evaluators: str):
    return parse_spec(
        tomllib.loads(
            f'[sweep]\nbase = "paper"\npressures_MPa = [1.0]\nevaluators = {evaluators}\n'
            '[parameters]\n"tube.h" = { values = [0.0] }\n'
        )
    )


def test_a_sweep_spec_with_the_old_names_is_the_same_sweep():
    old, new = _spec('["analytic", "fem", "nonlinear"]'), _spec('["paper", "fem", "fem-nonlinear"]')
    assert old.evaluators == new.evaluators == ("paper", "fem", "fem-nonlinear")
    assert old.fingerprint() == new.fingerprint()  # a sweep directory written before still resumes


def test_the_fingerprint_is_the_one_of_sweeps_written_before_the_tier_names():
    # hashed with the old spellings: the value a sweep.json from then holds
    assert _spec('["paper", "section"]').fingerprint() == "8b69a750ab3d4d29"
