"""Choices on the valid tier: the pre-search validity estimate, margins by name, bests at a bound."""

from __future__ import annotations

import json
import tomllib

import pytest

from softcath.cli.main import main
from softcath.cli.optimise import _fem_line
from softcath.design import presets
from softcath.studies.model_validity import LINEAR_BEND_LIMIT_DEG, linear_tier_warning
from softcath.studies.optimise import make_problem, optimise
from softcath.studies.optimise.validity import tier_validity
from softcath.studies.selection import LINEAR_BEND_LIMIT_DEG as SELECTION_LIMIT

E_TUBE = "materials.medical_silicone_tubing.youngs_modulus"


@pytest.fixture(scope="module")
def table():
    return tomllib.loads(presets.text("paper"))


def test_one_validity_rule():
    assert SELECTION_LIMIT == LINEAR_BEND_LIMIT_DEG  # select's re-check and optimise's warning agree
    assert linear_tier_warning("section-nonlinear", 90.0, 0.6, how="x", way_out="y") is None
    assert linear_tier_warning("section", LINEAR_BEND_LIMIT_DEG * 0.9, 0.6, how="x", way_out="y") is None
    msg = linear_tier_warning("section", 106.7, 0.6, how="designs", way_out="give --model section-nonlinear")
    assert msg is not None
    assert "linear tier, valid to ~5 deg" in msg and "107 deg at 0.6 MPa" in msg


@pytest.mark.parametrize(
    ("model", "load", "p", "warned"),
    [("paper", "cap", 0.6, True), ("paper", "cap", 0.01, False), ("section", "lumen", 0.6, True)],
)
def test_the_estimate_warns_past_the_linear_range(table, model, load, p, warned):
    """Under the lumen load too: the section model bends ~40 deg there (the issue's case)."""
    prob = make_problem(
        table,
        variables=["tube.h=-0.03:0.03"],
        objectives=[f"maximise bend_angle_deg at p={p}"],
        constraints=[f"max_strain <= 1.0 at p={p}"],
        model=model,
        load=load,
        pressures=[p],
    )
    v = tier_validity(prob)
    assert v["linear"] and v["at_MPa"] == p and v["estimated_max_bend_deg"] > 0
    assert (v["warning"] is not None) == warned
    if warned:
        assert "--model section-nonlinear" in v["warning"]


def test_the_finite_strain_tier_needs_no_estimate(table):
    prob = make_problem(
        table,
        variables=["tube.h=-0.03:0.03"],
        objectives=["maximise bend_angle_deg"],
        model="section-nonlinear",
    )
    assert tier_validity(prob) == {
        "tier": "section-nonlinear",
        "linear": False,
        "limit_deg": LINEAR_BEND_LIMIT_DEG,
    }


def test_a_best_at_a_bound_is_flagged(table):
    p = make_problem(
        table,
        variables=[f"{E_TUBE}=1:4"],
        objectives=["maximise bend_angle_deg at p=0.5"],
        model="paper",
        load="cap",
    )
    best = optimise(p, budget=60, seed=3, progress=False).best[0]
    assert best.at_bounds == {E_TUBE: "low"}  # softer bends more: the optimum is the lower bound
    assert best.to_json()["at_bounds"] == {E_TUBE: "low"}


def test_the_fem_recheck_says_which_constraint_it_misses_and_by_how_much():
    check = {
        "status": "ok",
        "feasible": False,
        "curvature_rel_diff": 0.1,
        "missed": {"max_strain <= 1.0 at p=0.6": -0.36, "bend_angle_deg >= 90": None},
    }
    line = _fem_line(check)
    assert line.startswith("3-D FEM: MISSES max_strain <= 1.0 at p=0.6 by 0.36 (margin -0.36)")
    assert "bend_angle_deg >= 90 (undefined)" in line
    assert _fem_line({**check, "feasible": True, "missed": {}}).startswith("3-D FEM: meets the constraints")


def test_optimise_warns_before_the_search_and_records_it(tmp_path, capsys, monkeypatch):
    import softcath.studies.optimise as study

    real = study.optimise
    seen = {}

    def spy(*args, **kwargs):
        seen["stderr before the search"] = capsys.readouterr().err
        return real(*args, **kwargs)

    monkeypatch.setattr(study, "optimise", spy)
    monkeypatch.setattr("softcath.studies.report.optimum.MAX_PICTURES", 0)
    out = tmp_path / "opt"
    argv = ["optimise", "paper", "--model", "paper", "--vary", "tube.h=-0.03:0.03", "--pressures", "0.6"]
    argv += ["--objective", "maximise bend_angle_deg at p=0.6", "--constraint", "max_strain <= 1.0 at p=0.6"]
    argv += ["--budget", "20", "--no-fem-check", "--no-progress", "--out", str(out)]
    assert main(argv) == 0
    assert "linear tier, valid to ~5 deg" in seen["stderr before the search"]
    doc = json.loads((out / "optimum.json").read_text())
    assert doc["validity"]["tier"] == "paper" and doc["validity"]["warning"]
    for w in doc["best"]:
        assert set(w["margins"]) == {"max_strain <= 1.0 at p=0.6"}
        assert w["margins"] == w["constraints"]  # the old key, for earlier readers
