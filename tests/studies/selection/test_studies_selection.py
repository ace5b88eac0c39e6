"""Selection expressions: parsing, evaluation against hand-computed answers, Pareto front, bad input."""

from __future__ import annotations

import itertools
import json

import numpy as np
import pandas as pd
import pytest

from softcath.cli.main import main
from softcath.studies.selection import SelectionError, pareto_front, parse_constraint, parse_objective, select


def _table() -> pd.DataFrame:
    """4 designs × 2 pressures × 1 load with hand-chosen numbers (design 3 failed)."""
    rows = []
    bend = {0: 40.0, 1: 100.0, 2: 120.0, 3: np.nan}
    strain = {0: 0.1, 1: 0.2, 2: 0.5, 3: np.nan}
    elong = {0: 0.01, 1: 0.03, 2: 0.02, 3: np.nan}
    for d, p in itertools.product(range(4), (0.5, 1.0)):
        rows.append(
            {
                "design_id": d,
                "task_id": 0,
                "tube.h": 0.01 * d,
                "outer_diameter_mm": 0.8,
                "pressure_MPa": p,
                "load": "cap",
                "bend_angle_deg": bend[d] * p,
                "max_strain": strain[d] * p,
                "elongation": elong[d] * p,
                "bend_per_MPa_deg": bend[d],
                "status": "failed" if d == 3 else "ok",
                "reason": "x" if d == 3 else "",
            }
        )
    return pd.DataFrame(rows)


def test_parse_forms():
    c = parse_constraint("bend_angle_deg >= 90 at p_max")
    assert (c.op, c.where, c.left.text, c.right.text) == (">=", "p_max", "bend_angle_deg", "90")
    c = parse_constraint("abs(tube.h) * 2 < 0.05 at p = 0.5")
    assert c.where == "p=0.5" and c.columns() == {"tube.h"}
    o = parse_objective("maximise bend_per_MPa_deg")
    assert o.sign == -1.0 and o.where is None
    assert parse_objective("minimize elongation at p_min").sign == 1.0


@pytest.mark.parametrize(
    ("constraint", "objective", "match"),
    [
        ("foo >= 1", "max bend_angle_deg", r"unknown column 'foo' in 'foo >= 1'"),
        (
            "bend_angel_deg >= 1",
            "max bend_angle_deg",
            r"unknown column 'bend_angel_deg'.*did you mean bend_angle_deg",
        ),
        ("bend_angle_deg ** 2 >= 1", "max bend_angle_deg", r"operator '\*\*' is not allowed"),
        ("bend_angle_deg >= 1 and max_strain < 1", "max bend_angle_deg", r"operator 'and' is not allowed"),
        ("bend_angle_deg in 1", "max bend_angle_deg", r"operator 'in' is not allowed"),
        ("0 < bend_angle_deg < 1", "max bend_angle_deg", r"one comparison per constraint"),
        ("bend_angle_deg", "max bend_angle_deg", r"is not a comparison"),
        ("bend_angle_deg >= ", "max bend_angle_deg", r"cannot parse"),
        ("sqrt(bend_angle_deg) > 1", "max bend_angle_deg", r"function 'sqrt' is not allowed"),
        ("bend_angle_deg > 1 at p_middle", "max bend_angle_deg", r"'at' must be followed by p_max"),
        ("bend_angle_deg > 'a'", "max bend_angle_deg", r"only numbers"),
        ("bend_angle_deg > 1", "bend_angle_deg", r"must start with maximise or minimise"),
        ("bend_angle_deg > 1", "maximise bend_angle_deg at p=3", r"no results at that pressure"),
        ("load > 1", "maximise bend_angle_deg", r"column 'load' is not numeric"),
    ],
)
def test_bad_expressions_name_the_problem(constraint, objective, match):
    with pytest.raises(SelectionError, match=match):
        select(_table(), constraints=[constraint], objectives=[objective])


def test_constraints_and_ranking_by_hand():
    df = _table()
    # design 0: bend 40 at p_max -> fails >= 90; design 2: strain 0.5 at p_max -> fails <= 0.3 (all pressures)
    sel = select(
        df,
        constraints=["bend_angle_deg >= 90 at p_max", "max_strain <= 0.3"],
        objectives=["maximise bend_per_MPa_deg"],
    )
    assert sel.n_designs == 4 and sel.n_feasible == 1
    assert sel.rejected == {"status failed": 1, "bend_angle_deg >= 90 at p_max": 1, "max_strain <= 0.3": 1}
    assert [r["design_id"] for r in sel.ranked] == [1]
    # A constraint at one pressure only: at 0.5 MPa design 2's strain is 0.25 <= 0.3.
    sel = select(df, constraints=["max_strain <= 0.3 at p_min"], objectives=["maximise bend_per_MPa_deg"])
    assert [r["design_id"] for r in sel.ranked] == [2, 1, 0]
    # Two objectives: maximise bend, minimise elongation at p_max -> all three are Pareto-optimal? No:
    # design 1 (100, 0.03) is dominated by design 2 (120, 0.02); designs 0 (40, 0.01) and 2 are not.
    sel = select(df, objectives=["maximise bend_per_MPa_deg", "minimise elongation"])
    assert sel.pareto_front == [0, 2]
    assert [r["design_id"] for r in sel.ranked] == [2, 0, 1]
    assert sel.ranked[0]["objectives"]["minimise elongation"] == pytest.approx(0.02)
    assert sel.ranked[0]["parameters"]["tube.h"] == pytest.approx(0.02)
    # points for the report's Pareto plot: [id, on front, objective values as defined (not negated)]
    assert sel.points == [
        [2, 1, 120.0, pytest.approx(0.02)],
        [0, 1, 40.0, pytest.approx(0.01)],
        [1, 0, 100.0, pytest.approx(0.03)],
    ]


def test_pareto_front_against_brute_force():
    rng = np.random.default_rng(5)
    v = np.round(rng.random((300, 3)), 1)  # rounding makes ties, the hard case
    dominated = np.array([np.any(np.all(v <= x, axis=1) & np.any(v < x, axis=1)) for x in v])
    np.testing.assert_array_equal(pareto_front(v), ~dominated)


def test_cli_select_writes_json_and_rejects_bad_input(small_spec, tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["sweep", str(small_spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    assert (
        main(
            [
                "select",
                str(out),
                "--constraint",
                "max_strain <= 0.3",
                "--objective",
                "maximise bend_per_MPa_deg",
                "--objective",
                "minimise elongation at p_max",
            ]
        )
        == 0
    )
    data = json.loads((out / "selection.json").read_text())
    assert data["n_designs"] == 12 and data["rejected"]["status failed"] == 2
    assert data["n_feasible"] == len(data["ranked"]) == 10
    assert set(data["pareto_front"]) <= {r["design_id"] for r in data["ranked"]}
    capsys.readouterr()
    assert main(["select", str(out), "--constraint", "nope > 1", "--objective", "max bend_angle_deg"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unknown column 'nope'" in err[0]
    assert main(["select", str(tmp_path / "empty"), "--objective", "max bend_angle_deg"]) == 2
