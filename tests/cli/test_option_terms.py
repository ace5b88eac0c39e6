"""Every refusal names the user's option: the one translation of library names (``cli.options``),
argparse's own refusals in the ``OPTION = VALUE: BOUND`` form, and the reported examples."""

from __future__ import annotations

import argparse

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from softcath.cli.main import build_parser
from softcath.cli.options import in_command_terms, option_terms
from softcath.design.errors import DesignError

SETTINGS = settings(
    max_examples=40,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)


def _commands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    out = {}
    sub_action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, sub in sub_action.choices.items():
        nested = [a for a in sub._actions if isinstance(a, argparse._SubParsersAction)]
        if nested:
            out.update({f"{name} {act}": leaf for act, leaf in nested[0].choices.items()})
        else:
            out[name] = sub
    return out


COMMANDS = _commands()
# (command, option dest): every long option of every command
OPTIONS = sorted((c, d) for c, p in COMMANDS.items() for d in option_terms(p))


@SETTINGS
@given(pick=st.sampled_from(OPTIONS), value=st.one_of(st.floats(allow_nan=True), st.text(max_size=8)))
def test_a_library_refusal_naming_an_options_dest_names_the_option(pick, value):
    command, dest = pick
    terms = option_terms(COMMANDS[command])
    said = in_command_terms(DesignError(dest, value, "must be sensible"), terms)
    assert isinstance(said, DesignError)
    assert said.parameter == terms[dest] and said.parameter.startswith("--")
    assert said.bound == "must be sensible" and said.value is value or said.value == value


@pytest.mark.parametrize(
    ("command", "library", "option"),
    [
        ("section", "silicone_poisson", "--poisson"),
        ("section", "pressures", "--pressure"),
        ("section", "hoop_cap", "--hoop-cap"),
        ("section", "mesh_size", "--mesh-size"),
        ("section", "out_dir", "--out"),
        ("optimise", "scheduler", "--scheduler"),
        ("optimise", "objectives", "--objective"),
        ("optimise", "backend", "--workers/--scheduler"),
        ("predict", "pressures", "--pressures"),
    ],
)
def test_known_aliases(command, library, option):
    said = in_command_terms(DesignError(library, 1.0, "b"), option_terms(COMMANDS[command]))
    assert isinstance(said, DesignError)
    assert said.parameter == option


def test_an_item_keeps_its_tail_and_a_design_path_stays():
    terms = option_terms(COMMANDS["optimise"])
    item = in_command_terms(DesignError("vary.tube.h", 1.0, "b"), terms)
    assert isinstance(item, DesignError) and item.parameter == "--vary tube.h"
    # a design file's own parameter is not an option, even where its head looks like one
    own = in_command_terms(DesignError("assembly.filler", "x", "b"), terms)
    assert isinstance(own, DesignError) and own.parameter == "assembly.filler"


@SETTINGS
@given(
    command=st.sampled_from(sorted(COMMANDS)),
    flag=st.from_regex(r"--[a-z][a-z-]{2,12}", fullmatch=True),
    value=st.from_regex(r"[a-z0-9_=.]{1,10}", fullmatch=True),
)
def test_an_unknown_option_is_one_line_naming_it_in_the_command(cli, command, flag, value):
    if any(flag == s for a in COMMANDS[command]._actions for s in a.option_strings) or any(
        s.startswith(flag) for a in COMMANDS[command]._actions for s in a.option_strings
    ):
        return  # a real option (or an abbreviation argparse accepts)
    r = cli(*command.split(), "paper", flag, value)
    line = r.error_line()
    assert line.startswith(f"softcath {command}: error: "), line
    if "required" not in line and "expected" not in line:
        assert f"{flag} = " in line, line


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["section", "paper", "--nonlinear", "--pressure=-0.5"], "--pressure = '-0.5': must be >= 0 MPa"),
        (["section", "paper", "--nonlinear", "--hoop-cap", "0"], "--hoop-cap = 0: must be finite and > 0"),
        (["section", "paper", "--nonlinear", "--mesh-size", "0"], "--mesh-size = 0: must be in"),
        (["section", "paper", "--nonlinear", "--poisson", "0.6"], "--poisson = 0.6: must be in [0, 0.49999]"),
        (["predict", "paper", "--assembly", "tube_coil=sliding"], "--assembly = 'tube_coil=sliding': not an"),
        (["section", "paper", "--mesher", "delaunay"], "--mesher = 'delaunay': invalid choice"),
        (["section", "paper", "--mesh-size", "abc"], "--mesh-size = 'abc': must be a float"),
        (
            [
                "optimise",
                "paper",
                "--vary",
                "tube.h=-0.04:0.04",
                "--objective",
                "maximise bend_angle_deg",
                "--scheduler",
                "bogus",
            ],
            "--scheduler = 'bogus': must be a Dask scheduler address",
        ),
    ],
)
def test_the_reported_refusals_name_the_option(cli, tmp_path, argv, expected):
    out = tmp_path / "o"
    line = cli(*argv, "--out", out).error_line()
    assert expected in line, line
    assert not out.exists()
