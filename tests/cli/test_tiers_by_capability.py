"""The commands choose tiers by their capabilities, with the same choices and messages as by name.

Each command's tier list and each branch once written as a comparison with a tier's name
(``--model paper``'s cap load, ``--nonlinear`` with the section model only, ``--fem-samples``
with the 3-D FEM only) is read off :mod:`softcath.models`; these tests pin the choices, the
defaults and the refusals to what the commands said before.
"""

from __future__ import annotations

import argparse

import numpy as np
import pytest

from softcath import design
from softcath.cli.main import build_parser
from softcath.cli.options import _slow_tier
from softcath.design.errors import DesignError
from softcath.studies.outputs.analytic import DEFAULT_LOAD, MODELS, analytic_run, load_and_reason
from softcath.studies.outputs.overlay import overlay


def _choices(command: str, dest: str) -> tuple:
    parser = build_parser(command)
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    action = next(a for a in sub.choices[command]._actions if a.dest == dest)
    return tuple(action.choices)


def test_the_command_choices_read_off_the_registry_are_the_ones_written_before():
    assert _choices("analytic", "model") == ("paper", "section")
    assert _choices("optimise", "model") == ("paper", "section", "section-nonlinear")
    assert _choices("predict", "model") == ("paper", "section", "fem")
    assert _choices("select", "model") == ("paper", "section", "section-nonlinear", "fem")
    assert _choices("select", "robust_model") == ("paper", "section", "section-nonlinear")


def test_each_analytic_model_runs_under_its_own_load_and_says_why():
    assert MODELS == ("paper", "section")
    formula = "the paper's formula is defined for the cap load"
    assert DEFAULT_LOAD["paper"] == ("cap", f"{formula}, the end-cap force")
    assert DEFAULT_LOAD["section"] == ("lumen", "the real load, lumen wall + cap")
    assert load_and_reason("paper", "cap") == DEFAULT_LOAD["paper"]
    assert load_and_reason("paper", "lumen") == (
        "lumen",
        f"as asked; {formula}, its lumen variant is the wall effect alone",
    )
    assert load_and_reason("section", "cap") == ("cap", "as asked: the paper's end-cap force alone")


def test_an_analytic_run_on_the_formula_is_the_formula_and_a_slow_tier_is_refused():
    d = design.preset("paper")
    p = np.array([0.1, 0.3])
    run = analytic_run(d, p, model="paper")
    assert (run.model, run.load, run.to_json()["tier"]) == ("paper", "cap", "paper")
    assert run.what == "paper's formula (cap load)"
    with pytest.raises(DesignError, match=r"model = 'fem': must be one of paper, section"):
        analytic_run(d, p, model="fem")


def test_an_overlay_takes_the_section_tiers_only():
    d = design.preset("paper")
    with pytest.raises(DesignError, match=r"tier = 'fem': must be one of section, section-nonlinear"):
        overlay([d], [0.1], sources=["paper"], tier="fem")


@pytest.mark.parametrize(
    ("model", "compare", "slow"),
    [
        ("fem", "", True),
        ("paper", "section, fem", True),
        ("section", "paper", False),
        ("paper", "fem-nonlinear", False),  # not a tier of predict: --compare refuses it, by its name
        ("paper", "nonlinear", False),
    ],
)
def test_fem_samples_act_with_the_slow_tier_of_predict(model, compare, slow):
    assert _slow_tier(argparse.Namespace(model=model, compare=compare)) is slow


def test_predict_nonlinear_names_the_tier_with_a_fast_finite_strain_counterpart(cli, tmp_path):
    r = cli("predict", "paper", "--model", "fem", "--nonlinear", "--out", tmp_path / "x")
    assert r.status == 2
    assert "--model = 'fem': must be section with --nonlinear (the finite-strain section model)" in r.err


def test_fem_samples_without_the_fem_tier_is_refused_with_the_same_words(cli, tmp_path):
    r = cli("predict", "paper", "--model", "paper", "--fem-samples", "4", "--out", tmp_path / "x")
    assert r.status == 2
    assert "has no effect without the fem tier (--model fem or --compare fem)" in r.err
    assert not (tmp_path / "x").exists()
