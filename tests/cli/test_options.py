"""Every command spells DESIGN and ``--out`` the same way, and ``--out`` is honoured where files are
written."""

from __future__ import annotations

import argparse
import json

import pytest

from softcath.cli.main import SUBCOMMANDS, build_parser, main
from softcath.cli.options import design_or_data

# design validate prints its verdict only; app serves pages (its exports are the browser's downloads)
WRITES_NOTHING = {("design", "validate"), ("app", None)}
DESIGN_OPTIONAL = {"bench", "calibrate", "discrepancy", "demo", "app"}  # default: paper
NO_DESIGN = {"sweep", "report", "select", "measure", "record"}  # their subject is a spec, a sweep or a device


def _leaf_parsers():
    for name, sub in build_parser()._subparsers._group_actions[0].choices.items():
        actions = {a.dest: a for a in sub._actions}
        if "action" in actions and isinstance(actions["action"], argparse._SubParsersAction):
            for act, leaf in actions["action"].choices.items():
                yield (name, act), leaf
        else:
            yield (name, None), sub


LEAVES = dict(_leaf_parsers())


def test_every_subcommand_is_built():
    assert {name for name, _ in LEAVES} == {name for name, _ in SUBCOMMANDS}


@pytest.mark.parametrize("key", sorted(LEAVES, key=str), ids=lambda k: " ".join(filter(None, k)))
def test_out_is_one_option_named_the_same(key):
    outs = [a for a in LEAVES[key]._actions if "--out" in a.option_strings]
    if key in WRITES_NOTHING:
        assert outs == []
        return
    assert len(outs) == 1 and outs[0].metavar == "DIR"


@pytest.mark.parametrize("key", sorted(LEAVES, key=str), ids=lambda k: " ".join(filter(None, k)))
def test_design_is_the_first_positional(key):
    positionals = [a for a in LEAVES[key]._actions if not a.option_strings and a.dest != "help"]
    if key[0] in NO_DESIGN:
        assert all(a.dest != "design" for a in positionals)
        assert not any("--design" in a.option_strings for a in LEAVES[key]._actions)
        return
    first = positionals[0]
    assert first.dest == "design" and first.metavar == "DESIGN"
    assert (first.nargs == "?") == (key[0] in DESIGN_OPTIONAL)
    assert not any("--design" in a.option_strings for a in LEAVES[key]._actions)


def test_a_lone_data_positional_is_data_not_a_design(tmp_path):
    csv = tmp_path / "run.csv"
    assert design_or_data(str(csv), None) == ("paper", csv)
    assert design_or_data(str(tmp_path), None) == ("paper", tmp_path)
    assert design_or_data("my.toml", None) == ("my.toml", None)
    assert design_or_data("my.toml", csv) == ("my.toml", csv)


def test_calibrate_takes_design_then_data():
    args = build_parser().parse_args(["calibrate", "run.csv", "--out", "o"])
    assert (args.design, str(args.measured)) == ("paper", "run.csv")
    args = build_parser().parse_args(["calibrate", "my.toml", "run.csv", "--out", "o"])
    assert (args.design, str(args.measured)) == ("my.toml", "run.csv")


def test_design_export_writes_into_out(tmp_path, capsys):
    assert main(["design", "export", "paper", "--out", str(tmp_path / "cad")]) == 0
    assert sorted(p.name for p in (tmp_path / "cad").iterdir()) == ["paper.step", "paper.stl"]
    assert (tmp_path / "cad" / "paper.step").read_text(errors="replace").startswith("ISO-10303-21")
    assert main(["design", "export", "paper", "--out", str(tmp_path / "one"), "--stl", "tip.stl"]) == 0
    assert [p.name for p in (tmp_path / "one").iterdir()] == ["tip.stl"]


def test_report_and_select_honour_out(small_spec, tmp_path, capsys):
    sweep = tmp_path / "s"
    assert main(["sweep", str(small_spec), "--out", str(sweep), "--workers", "1", "--no-progress"]) == 0
    sel = [
        "select",
        str(sweep),
        "--constraint",
        "max_strain <= 0.3",
        "--objective",
        "maximise bend_per_MPa_deg",
    ]
    assert main([*sel, "--out", str(tmp_path / "chosen")]) == 0
    assert json.loads((tmp_path / "chosen" / "selection.json").read_text())["n_designs"] > 0
    assert not (sweep / "selection.json").exists()
    assert main(["report", str(sweep), "--out", str(tmp_path / "page")]) == 0
    assert (tmp_path / "page" / "index.html").is_file() and not (sweep / "report").exists()


def test_model_option_takes_the_tier_names_and_maps_an_old_spelling(caplog):
    from softcath.cli.options import model_name

    assert model_name("section-nonlinear") == "section-nonlinear"
    with caplog.at_level("WARNING"):
        assert model_name("analytic") == "paper"
    assert "deprecated" in caplog.text
