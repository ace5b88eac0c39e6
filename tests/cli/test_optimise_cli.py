"""softcath optimise: the files it writes, and its refusals naming the option."""

from __future__ import annotations

import json

import pandas as pd
import pytest

from softcath.cli.main import main

E_TUBE = "materials.medical_silicone_tubing.youngs_modulus"


def test_optimise_writes_optimum_history_designs_and_report(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr("softcath.studies.report.optimum.MAX_PICTURES", 2)  # pictures take ~0.3 s each
    out = tmp_path / "opt"
    rc = main(
        [
            "optimise",
            "paper",
            "--model",
            "paper",
            "--vary",
            f"{E_TUBE}=1:4",
            "--vary",
            "tube.h=-0.03:0.03",
            "--objective",
            "maximise bend_angle_deg at p=0.5",
            "--objective",
            "minimise max_strain at p=0.5",
            "--constraint",
            "bend_angle_deg >= 8 at p=0.5",
            "--budget",
            "30",
            "--no-fem-check",
            "--no-progress",
            "--out",
            str(out),
        ]
    )
    assert rc == 0
    doc = json.loads((out / "optimum.json").read_text())
    assert doc["model"] == "paper" and doc["evaluations"] <= 30
    assert doc["best"]
    for w in doc["best"]:
        assert set(w["parameters"]) == {E_TUBE, "tube.h"}
        assert set(w["objectives"]) == {"maximise bend_angle_deg at p=0.5", "minimise max_strain at p=0.5"}
        assert w["constraints"]["bend_angle_deg >= 8 at p=0.5"] >= 0
        assert (out / "designs" / f"{w['name']}.toml").is_file()
    hist = pd.read_parquet(out / "history.parquet")
    assert len(hist) == doc["evaluations"] and "margin bend_angle_deg >= 8 at p=0.5" in hist
    html = (out / "index.html").read_text()
    assert '<script src="plotly.min.js">' in html and (out / "plotly.min.js").stat().st_size > 1e6
    assert "NSGA-II" in capsys.readouterr().out
    assert len(list((out / "designs").glob("*.png"))) == min(2, len(doc["best"]))


def test_optimise_refusals_name_the_option(tmp_path, capsys):
    rc = main(
        [
            "optimise",
            "paper",
            "--vary",
            "tube.h=0.1:-0.1",
            "--objective",
            "maximise bend_angle_deg",
            "--out",
            str(tmp_path / "o"),
        ]
    )
    assert rc == 2
    assert "--vary tube.h" in capsys.readouterr().err
    rc = main(
        [
            "optimise",
            "paper",
            "--vary",
            "tube.h=0:0.01",
            "--objective",
            "maximise bend_angle_deg",
            "--robust",
            "1.5",
            "--model",
            "paper",
            "--out",
            str(tmp_path / "o"),
        ]
    )
    assert rc == 2
    assert "robust = 1.5" in capsys.readouterr().err


@pytest.mark.parametrize("bad", ["maximise bend_angle_deg ** 2", "bend_angle_deg", "maximise bend_angel_deg"])
def test_optimise_refuses_bad_objectives(tmp_path, capsys, bad):
    rc = main(
        [
            "optimise",
            "paper",
            "--vary",
            "tube.h=0:0.01",
            "--objective",
            bad,
            "--model",
            "paper",
            "--out",
            str(tmp_path / "o"),
        ]
    )
    assert rc == 2 and "error" in capsys.readouterr().err


def test_optimise_robust_reports_probabilities(tmp_path):
    out = tmp_path / "rob"
    rc = main(
        [
            "optimise",
            "paper",
            "--model",
            "paper",
            "--vary",
            f"{E_TUBE}=1:4",
            "--objective",
            "maximise bend_angle_deg at p=0.5",
            "--constraint",
            "bend_angle_deg <= 10 at p=0.5",
            "--robust",
            "0.8",
            "--robust-vary",
            "materials.ecoflex_00_30.youngs_modulus=0.069:0.118",
            "--samples",
            "8",
            "--budget",
            "30",
            "--no-fem-check",
            "--no-progress",
            "--out",
            str(out),
        ]
    )
    assert rc == 0
    doc = json.loads((out / "optimum.json").read_text())
    assert doc["robust"]["P"] == 0.8 and doc["model_runs"] == 8 * doc["evaluations"]
    best = doc["best"][0]
    assert best["probabilities"]["bend_angle_deg <= 10 at p=0.5"] >= 0.8
    assert set(best["percentiles"]["maximise bend_angle_deg at p=0.5"]) == {"p5", "p50", "p95"}


@pytest.mark.parametrize(
    ("extra", "expected"),
    [
        (["--pressures", "1e9"], "--pressures = 1e+09: must be within ±100 MPa"),
        (["--pressures", "nan"], "--pressures = nan"),
        (["--budget", "1000000000"], "--budget = 1000000000: 1000000000 section-model runs would take about"),
        (
            ["--robust", "0.9", "--samples", "1000000000"],
            "--samples = 1000000000: must be an integer in [2, 10000]",
        ),
        (
            ["--robust", "0.9", "--samples", "1000", "--budget", "1000"],
            "--budget = 1000: 1000000 section-model runs",
        ),
        (["--seed", "-1"], "invalid seed -1"),
    ],
)
def test_optimise_refuses_absurd_work_before_any_run_naming_the_option(tmp_path, capsys, extra, expected):
    """As every command: one line naming option, value and bound, before the folder or any model run."""
    out = tmp_path / "o"
    rc = main(
        [
            "optimise",
            "paper",
            "--vary",
            "tube.h=-0.03:0.03",
            "--objective",
            "maximise bend_angle_deg at p=0.5",
            "--no-fem-check",
            "--no-progress",
            *extra,
            "--out",
            str(out),
        ]
    )
    err = capsys.readouterr().err.strip()
    assert rc == 2 and expected in err and len(err.splitlines()) == 1
    assert not out.exists()


def test_optimise_leaves_no_partial_outputs_when_a_writer_fails(tmp_path, capsys, monkeypatch):
    """Record, designs and report appear together or not at all (as every command's outputs)."""
    from softcath.design.errors import DataError

    def broken(folder):
        raise DataError(f"{folder}: disk full")

    monkeypatch.setattr("softcath.studies.report.optimum.write_optimum_report", broken)
    out = tmp_path / "opt"
    rc = main(
        [
            "optimise",
            "paper",
            "--model",
            "paper",
            "--vary",
            "tube.h=-0.03:0.03",
            "--objective",
            "maximise bend_angle_deg at p=0.5",
            "--budget",
            "10",
            "--no-fem-check",
            "--no-progress",
            "--out",
            str(out),
        ]
    )
    assert rc == 2 and "disk full" in capsys.readouterr().err
    assert not out.exists() or not any(out.iterdir())


@pytest.mark.parametrize("load", ["lumen", "cap"])
def test_the_3d_fem_recheck_line_says_its_tier_and_load(tmp_path, cli, load):
    """The winners' 3-D FEM re-check runs under the search's load and its summary line says so."""
    argv = ["optimise", "paper", "--model", "section", "--load", load, "--vary", "tube.h=-0.03:0.03"]
    argv += ["--objective", "maximise bend_angle_deg at p=0.1", "--constraint", "max_strain <= 1 at p=0.1"]
    r = cli(*argv, "--pressures", "0.1", "--budget", "10", "--no-progress", "--out", tmp_path / "o")
    assert r.status == 0
    doc = json.loads((tmp_path / "o" / "optimum.json").read_text())
    assert doc["load"] == load and doc["best"][0]["fem_check"]["status"] == "ok"
    lines = [ln.strip() for ln in r.out.splitlines() if ln.strip().startswith("3-D FEM")]
    assert lines and all(f"[fem, {load} load]" in ln for ln in lines)
