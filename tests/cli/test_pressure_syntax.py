"""One pressure syntax: ``P,P,...`` lists and ``START:STOP:N`` ranges wherever pressures are given."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from softcath.cli.main import build_parser, main
from softcath.cli.options import PRESSURE_SYNTAX, parse_pressures
from softcath.design.errors import DesignError

PROPS = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
PRESSURE = st.floats(-100, 100, allow_nan=False).map(lambda x: round(x, 6))
RANGE = st.tuples(PRESSURE, PRESSURE, st.integers(2, 40))
ITEM = st.one_of(PRESSURE, RANGE)


def _text(item) -> str:
    return f"{item[0]!r}:{item[1]!r}:{item[2]}" if isinstance(item, tuple) else repr(item)


def _values(item) -> np.ndarray:
    return np.linspace(*item) if isinstance(item, tuple) else np.array([item])


@PROPS
@given(items=st.lists(ITEM, min_size=1, max_size=5))
def test_lists_ranges_and_their_mixtures_read_as_written(items):
    text = ",".join(_text(i) for i in items)
    np.testing.assert_allclose(parse_pressures(text), np.concatenate([_values(i) for i in items]))


@PROPS
@given(text=st.text(alphabet="0123456789.:,-e+ ", max_size=20))
def test_any_text_is_read_exactly_or_refused_naming_the_option(text):
    try:
        p = parse_pressures(text, param="--pressures")
    except DesignError as exc:
        assert exc.parameter == "--pressures"  # the value named: the text, or the pressure out of bounds
        return
    items = [i for i in text.split(",") if i.strip()]
    assert all(len(i.split(":")) in (1, 3) for i in items)
    assert p.size == sum(1 if len(i.split(":")) == 1 else int(i.split(":")[2]) for i in items)
    assert np.all(np.isfinite(p)) and np.all(np.abs(p) <= 100)


@pytest.mark.parametrize(
    ("text", "bound"),
    [
        ("0:1:3:4", "expected START:STOP:N"),
        ("0.1,x", "expected START:STOP:N"),
        ("0:1:1", "count N = 1 must be in [2, 1000000]"),
        ("0.1,200", "within ±100 MPa"),
        (",", "at least one pressure"),
    ],
)
def test_refusals_name_the_bound(text, bound):
    with pytest.raises(DesignError) as info:
        parse_pressures(text)
    assert bound in info.value.bound


def test_increasing_when_asked():
    assert parse_pressures("0:0.4:3,0.5", increasing=True).tolist() == pytest.approx([0, 0.2, 0.4, 0.5])
    with pytest.raises(DesignError, match="strictly increasing"):
        parse_pressures("0:0.4:3,0.4", increasing=True)


@pytest.mark.parametrize(
    ("command", "option"),
    [
        ("section", "--pressure"),
        ("analytic", "--pressure"),
        ("optimise", "--pressures"),
        ("predict", "--pressures"),
    ],
)
def test_every_pressure_option_shows_the_one_syntax(command, option):
    sub = build_parser()._subparsers._group_actions[0].choices[command]  # pyright: ignore[reportOptionalMemberAccess, reportOptionalSubscript, reportIndexIssue]  # argparse's private parts
    action = next(a for a in sub._actions if option in a.option_strings)
    assert action.metavar == PRESSURE_SYNTAX


def test_section_takes_a_pressure_list(tmp_path, capsys):
    assert main(["section", "paper", "--pressure", "0.1,0.3,0.6", "--out", str(tmp_path / "s")]) == 0
    assert main(["analytic", "paper", "--pressure", "0,0.1:0.5:3", "--out", str(tmp_path / "a")]) == 0
    import csv

    with (tmp_path / "a" / "analytic.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert [float(r["pressure_MPa"]) for r in rows] == pytest.approx([0, 0.1, 0.3, 0.5])
