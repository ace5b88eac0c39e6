"""``softcath fem``: each mode's documented defaults are the ones the command applies.

The defaults are written in three places a user reads (``softcath fem
--help``, docs/fem.md, docs/nonlinear.md); one test per default checks the
command against the documents.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from softcath.cli import fem as fem_cmd
from softcath.cli.main import build_parser
from softcath.design.errors import DesignError

DOCS = Path(__file__).resolve().parents[2] / "docs"
NONLINEAR_DOC = (DOCS / "nonlinear.md").read_text()
LINEAR_DOC = (DOCS / "fem.md").read_text()


def _args(*extra):
    return build_parser().parse_args(["fem", "paper", "--out", "unused", *extra])


def _documented(doc: str, option: str) -> str:
    m = re.search(rf"`{option}[^`]*`[^`]*?default (\S+?)[),;]", doc)
    assert m, f"{option} has no documented default"
    return m.group(1)


@pytest.mark.parametrize(
    ("option", "field"),
    [
        ("--load", "load"),
        ("--mesh-size", "mesh_size"),
        ("--pressure", "pressure"),
        ("--steps", "steps"),
        ("--curvature-points", "curvature_points"),
    ],
)
def test_nonlinear_default_is_the_documented_one(option, field):
    applied = getattr(fem_cmd.nonlinear_settings(_args("--nonlinear")), field)
    documented = _documented(NONLINEAR_DOC, option)
    assert str(applied) == documented or float(applied) == pytest.approx(float(documented))


@pytest.mark.parametrize(("option", "field"), [("--load", "load"), ("--mesh-size", "mesh_size")])
def test_linear_default_is_the_documented_one(option, field):
    applied = getattr(fem_cmd.linear_settings(_args("--pressure", "0.1")), field)
    documented = _documented(LINEAR_DOC, option)
    assert str(applied) == documented or float(applied) == pytest.approx(float(documented))


def test_nonlinear_layers_and_formulation_default_to_the_documented_rules():
    s = fem_cmd.nonlinear_settings(_args("--nonlinear"))
    assert s.layers is None and s.mixed is None and not s.convergence  # chosen per design by bend_curve
    assert "`--layers N` (element layers along the bending length; default: from the expected bend" in (
        " ".join(NONLINEAR_DOC.split())
    )
    assert "`--mixed` / `--no-mixed` (mixed u–p formulation; default: when a silicone's ν ≥ 0.45)" in (
        " ".join(NONLINEAR_DOC.split())
    )
    assert not s.true_area
    assert "`--area-true-section` (area-true section polygons; default: plain inscribed polygons" in (
        " ".join(NONLINEAR_DOC.split())
    )
    given = fem_cmd.nonlinear_settings(
        _args("--nonlinear", "--layers", "6", "--no-mixed", "--convergence", "--area-true-section")
    )
    assert (given.layers, given.mixed, given.convergence, given.true_area) == (6, False, True, True)


def test_both_modes_take_the_real_load_by_default():
    # One default load for every 3-D check: the real one (lumen wall + cap); the paper's cap force
    # only when asked for (the linear check took the cap load before).
    assert fem_cmd.nonlinear_settings(_args("--nonlinear")).load == "lumen"
    assert fem_cmd.linear_settings(_args("--pressure", "0.1")).load == "lumen"
    assert fem_cmd.linear_settings(_args("--pressure", "0.1", "--load", "cap")).load == "cap"


def test_options_given_override_the_mode_defaults():
    s = fem_cmd.nonlinear_settings(
        _args("--nonlinear", "--load", "cap", "--mesh-size", "0.2", "--pressure", "0.5")
    )
    assert (s.load, s.mesh_size, s.pressure) == ("cap", 0.2, 0.5)


def test_help_states_both_modes_defaults(capsys):
    with pytest.raises(SystemExit):
        build_parser().parse_args(["fem", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "Default: lumen (both modes)" in text
    assert "default 0.16 linear, 0.15 --nonlinear" in text


def test_the_linear_check_needs_a_pressure():
    with pytest.raises(DesignError, match=r"--pressure.*required for the linear check"):
        fem_cmd.linear_settings(_args())


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (("--pressure", "-1"), r"--pressure = -1(\.0)?: must be > 0 MPa"),
        (("--steps", "0"), r"--steps = 0: must be an integer in \[1, 1000\]"),
        (("--layers", "0"), r"--layers = 0: must be an integer >= 1"),
        (("--layers", "5", "--convergence"), r"--layers = 5: must be >= 6 for a convergence study"),
    ],
)
def test_bad_nonlinear_options_are_refused_by_name(extra, message):
    with pytest.raises(DesignError, match=message):
        fem_cmd.nonlinear_settings(_args("--nonlinear", *extra))
