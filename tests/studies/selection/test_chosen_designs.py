"""``softcath select`` writes its chosen designs as design files the other commands take as they are."""

from __future__ import annotations

import json

from softcath import design
from softcath.cli.main import build_parser, main
from softcath.studies.report.html_report import design_of


def _select(small_spec, tmp_path, *extra):
    out = tmp_path / "o"
    assert main(["sweep", str(small_spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    argv = ["select", str(out), "--constraint", "max_strain <= 0.3"]
    argv += ["--objective", "maximise bend_per_MPa_deg"]
    assert main([*argv, *extra]) == 0
    return out


def test_select_writes_the_ranked_designs_and_they_round_trip(small_spec, tmp_path, capsys):
    out = _select(small_spec, tmp_path, "--designs", "3")
    stdout = capsys.readouterr().out
    data = json.loads((out / "selection.json").read_text())
    named = [r for r in data["ranked"] if "design_file" in r]
    assert [r["rank"] for r in named] == [1, 2, 3]
    assert sorted(p.name for p in (out / "designs").iterdir()) == sorted(
        r["design_file"].split("/")[-1] for r in named
    )
    for r in named:
        path = out / r["design_file"]
        assert f"design file: {path}" in stdout
        text = path.read_text()
        assert text.startswith("# softcath select: design") and "(paper), cap load" in text
        # the file is the swept design, field for field
        assert design.load(path) == design_of(out, r["design_id"])
        # and every command that takes a design takes it as it is
        capsys.readouterr()
        assert main(["design", "validate", str(path)]) == 0
        assert "valid design" in capsys.readouterr().out
        assert main(["section", str(path), "--out", str(tmp_path / f"s{r['design_id']}")]) == 0
        fem = ["fem", str(path), "--pressure", "0.1", "--out", str(tmp_path / "f")]
        args = build_parser().parse_args(fem)
        assert design.resolve(args.design) == design.load(path)


def test_a_new_selection_replaces_the_earlier_design_files(small_spec, tmp_path):
    out = _select(small_spec, tmp_path, "--designs", "4")
    assert len(list((out / "designs").iterdir())) == 4
    argv = ["select", str(out), "--constraint", "max_strain <= 0.3"]
    argv += ["--objective", "minimise bend_per_MPa_deg"]
    assert main([*argv, "--designs", "1"]) == 0
    data = json.loads((out / "selection.json").read_text())
    assert [p.name for p in (out / "designs").iterdir()] == [data["ranked"][0]["design_file"].split("/")[-1]]


def test_designs_zero_writes_none_and_a_negative_count_is_refused(small_spec, tmp_path, capsys):
    out = _select(small_spec, tmp_path, "--designs", "0")
    assert not (out / "designs").exists() or not any((out / "designs").iterdir())
    capsys.readouterr()
    argv = ["select", str(out), "--objective", "maximise bend_per_MPa_deg", "--designs", "-1"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["softcath select: error: --designs = -1: must be >= 0"]


def test_a_sweep_without_its_designs_table_still_selects_without_files(small_spec, tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["sweep", str(small_spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    (out / "designs.csv").unlink()
    capsys.readouterr()
    assert main(["select", str(out), "--objective", "maximise bend_per_MPa_deg"]) == 0
    assert "no design files written" in capsys.readouterr().err
    data = json.loads((out / "selection.json").read_text())
    assert data["ranked"] and not any("design_file" in r for r in data["ranked"])
