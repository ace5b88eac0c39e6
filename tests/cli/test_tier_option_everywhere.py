"""A new option of a tier reaches every command without an edit outside the tier and the registry.

The test stands in for a maintainer: it gives the paper tier a new option, ``material_law``
(``"nominal"`` or ``"stiff"``, the stiff law doubling every Young's modulus), in one subclass
and registers it in the paper tier's place with the registry's own API; nothing else knows the
option. Each of the seven commands then runs with ``--model-option material_law=stiff`` (the sweep
also with its ``[sweep.options.paper]`` table) and its output files must show the option reached
the tier: eq. 7 is homogeneous of degree -1 in the moduli at fixed Poisson ratios, so every
curvature, elongation and gain of the formula is exactly half the default run's (rounding
aside: rel 1e-9), and the recorded options say ``stiff``. Where a command cannot take a tier
option by design (the report, select without --robust) it refuses it, naming why.
"""

from __future__ import annotations

import dataclasses
import json
import tomllib

import numpy as np
import pandas as pd
import pytest

from softcath import analytic, design, models
from softcath.cli.main import main
from softcath.core.errors import DesignError
from softcath.models.paper import PAPER, PaperTier
from softcath.studies.demo.sweep import demo_sweep_spec
from softcath.studies.report.html_blocks import fmt
from softcath.studies.sweep import parse_spec

#: The formula's answers under the stiff law over the default's: every modulus doubled.
RATIO = 0.5
REL = 1e-9
STIFF = ["--model-option", "material_law=stiff"]


def _stiffer(d, factor: float):
    """``d`` with every Young's modulus times ``factor`` (Poisson ratios kept)."""

    def scale(m):
        return dataclasses.replace(m, youngs_modulus=m.youngs_modulus * factor)

    return dataclasses.replace(
        d,
        tube=dataclasses.replace(d.tube, material=scale(d.tube.material)),
        coil=dataclasses.replace(d.coil, material=scale(d.coil.material)),
        channel=dataclasses.replace(d.channel, material=scale(d.channel.material)),
        filler=None if d.filler is None else scale(d.filler),
    )


class MaterialLawPaper(PaperTier):
    """The paper's formula with a new option: ``material_law = "stiff"`` doubles every modulus."""

    def _solve(self, designs, pressures, loads, options):
        if options.get("material_law", self.options["material_law"]) == "stiff":
            designs = [None if d is None else _stiffer(d, 2.0) for d in designs]
        return super()._solve(designs, pressures, loads, options)  # the formula records the options


def _tier() -> MaterialLawPaper:
    fields = {f.name: getattr(PAPER, f.name) for f in dataclasses.fields(PAPER)}
    fields["options"] = {**PAPER.options, "material_law": "nominal"}
    fields["option_choices"] = {"material_law": ("nominal", "stiff")}
    return MaterialLawPaper(**fields)


@pytest.fixture
def law():
    """The paper tier with the new option, in the registry for the test only."""
    with models.registered(_tier(), replace=True) as tier:
        yield tier
    assert models.get("paper") is PAPER and "material_law" not in PAPER.options


def test_the_tier_itself_answers_the_option_and_refuses_a_bad_value(law):
    d = design.preset("paper")
    k0, e0 = analytic.gains(d, "cap")
    r = models.response(d, [1.0], tier="paper", load="cap", options={"material_law": "stiff"})
    assert r.curvature_per_mm[0] == pytest.approx(RATIO * k0, rel=REL)
    assert r.elongation[0] == pytest.approx(RATIO * e0, rel=REL)
    assert r.parameters["material_law"] == "stiff"
    nominal = models.response(d, [1.0], tier="paper", load="cap")
    assert nominal.curvature_per_mm[0] == k0 and nominal.parameters["material_law"] == "nominal"
    with pytest.raises(DesignError, match=r"material_law.*'soft'.*paper takes nominal, stiff"):
        models.parse_tier_options(["material_law=soft"], tiers=["paper"])


def _sweep(tmp_path, name: str, table: str = "", extra=()) -> pd.DataFrame:
    spec = tmp_path / f"{name}.toml"
    spec.write_text(
        '[sweep]\nname = "law"\nbase = "paper"\npressures_MPa = [0.1, 0.5]\nloads = ["cap", "lumen"]\n'
        f'evaluators = ["paper"]\n{table}\n[parameters]\n"tube.h" = {{ values = [-0.02, 0.0, 0.02] }}\n',
        encoding="utf-8",
    )
    out = tmp_path / name
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress", *extra]) == 0
    return out


def _results(out) -> pd.DataFrame:
    return pd.read_csv(out / "results.csv").sort_values(["design_id", "load", "pressure_MPa"])


def _manifest(out) -> dict:
    return json.loads((out / "sweep.json").read_text(encoding="utf-8"))["spec"]


def test_sweep_select_and_report_take_the_option(law, tmp_path, capsys):
    default = _sweep(tmp_path, "default")
    table = _sweep(tmp_path, "table", '[sweep.options.paper]\nmaterial_law = "stiff"\n')
    flag = _sweep(tmp_path, "flag", extra=STIFF)
    d, t, f = _results(default), _results(table), _results(flag)
    for col in ("curvature_analytic_per_mm", "elongation_analytic"):
        np.testing.assert_allclose(t[col].to_numpy(), RATIO * d[col].to_numpy(), rtol=REL)
        np.testing.assert_array_equal(f[col].to_numpy(), t[col].to_numpy())  # flag = table
    assert "options" not in _manifest(default)  # a default sweep's manifest is as before
    assert _manifest(table)["options"] == _manifest(flag)["options"] == {"paper": {"material_law": "stiff"}}
    assert len({_manifest(o)["fingerprint"] for o in (default, table)}) == 2
    # a resume must not mix option sets: the default spec into the stiff folder is refused
    spec = tmp_path / "default.toml"
    assert main(["sweep", str(spec), "--out", str(table), "--workers", "1", "--no-progress"]) == 2
    capsys.readouterr()

    # select re-evaluates with the option only under --robust; its robust p50 is the formula's, halved
    obj = "maximise curvature_per_mm at p=0.5"
    robust = ["--robust", "0.5", "--robust-model", "paper", "--samples", "8", "--no-progress"]
    robust += ["--vary", "materials.ecoflex_00_30.youngs_modulus=0.09:0.11"]
    for name, extra in (("sel0", []), ("sel1", STIFF)):
        args = ["select", str(default), "--objective", obj, *robust, *extra, "--out", str(tmp_path / name)]
        assert main(args) == 0
    s0, s1 = (json.loads((tmp_path / n / "selection.json").read_text()) for n in ("sel0", "sel1"))
    assert "model_options" not in s0["robust"]
    assert s1["robust"]["model_options"] == {"paper": {"material_law": "stiff"}}
    for key, info in s0["robust"]["designs"].items():
        p50 = info["percentiles"][obj]["p50"]
        assert s1["robust"]["designs"][key]["percentiles"][obj]["p50"] == pytest.approx(RATIO * p50, rel=REL)
    assert main(["select", str(default), "--objective", obj, *STIFF, "--out", str(tmp_path / "s2")]) == 2
    assert "--model-option" in (err := capsys.readouterr().err) and "without --robust" in err

    # the report draws the stored results: it lists the sweep's options and refuses its own
    assert main(["report", str(table)]) == 0
    page = (table / "report" / "index.html").read_text(encoding="utf-8")
    assert "Model options of paper" in page and "material_law = stiff" in page
    assert "Model options" not in (main(["report", str(default)]) or "") + (
        default / "report" / "index.html"
    ).read_text(encoding="utf-8")
    capsys.readouterr()
    assert main(["report", str(table), *STIFF]) == 2
    assert "--model-option" in (err := capsys.readouterr().err) and "sweep's stored results" in err


def test_optimise_takes_the_option(law, tmp_path):
    obj = "maximise curvature_per_mm at p=0.5"
    base = ["optimise", "paper", "--vary", "tube.h=-0.02:0.02", "--objective", obj, "--model", "paper"]
    base += ["--budget", "12", "--no-fem-check", "--workers", "1", "--no-progress"]
    assert main([*base, "--out", str(tmp_path / "o0")]) == 0
    assert main([*base, *STIFF, "--out", str(tmp_path / "o1")]) == 0
    o0, o1 = (json.loads((tmp_path / n / "optimum.json").read_text()) for n in ("o0", "o1"))
    assert "model_options" not in o0 and o1["model_options"] == {"paper": {"material_law": "stiff"}}
    h0, h1 = (pd.read_parquet(tmp_path / n / "history.parquet") for n in ("o0", "o1"))
    both = h0.merge(h1, on="tube.h", suffixes=("_0", "_1"))  # designs both searches evaluated
    assert len(both) >= 1
    np.testing.assert_allclose(both[f"{obj}_1"], RATIO * both[f"{obj}_0"], rtol=REL)


def test_predict_takes_the_option(law, tmp_path, capsys):
    base = ["predict", "paper", "--model", "paper", "--samples", "64", "--no-progress"]
    assert main([*base, "--out", str(tmp_path / "p0")]) == 0
    assert main([*base, *STIFF, "--out", str(tmp_path / "p1")]) == 0
    p0, p1 = (json.loads((tmp_path / n / "prediction.json").read_text()) for n in ("p0", "p1"))
    assert "model_options" not in p0 and p1["model_options"] == {"material_law": "stiff"}
    k0 = analytic.gains(design.preset("paper"), "cap")[0]
    assert p0["nominal_gain"] == pytest.approx(k0, rel=REL)
    assert p1["nominal_gain"] == pytest.approx(RATIO * k0, rel=REL)
    for q, v in p0["gain_percentiles"].items():
        assert p1["gain_percentiles"][q] == pytest.approx(RATIO * v, rel=REL)
    # an option no tier of the command takes is refused, naming the tier and its options
    assert main([*base, "--model-option", "mesh_size=0.1", "--out", str(tmp_path / "p2")]) == 2
    assert "unknown option 'mesh_size'" in (err := capsys.readouterr().err) and "material_law" in err


def test_discrepancy_takes_the_option(law, tmp_path, capsys):
    csv = tmp_path / "fem.csv"
    p = np.linspace(0.0, 1.0, 12)
    csv.write_text(
        "pressure_MPa,curvature_per_mm\n" + "".join(f"{a},{0.05 * a + 0.004 * a * a}\n" for a in p),
        encoding="utf-8",
    )
    base = ["discrepancy", "paper", str(csv), "--reference", "fem"]
    assert main([*base, "--out", str(tmp_path / "d0")]) == 0
    assert main([*base, *STIFF, "--out", str(tmp_path / "d1")]) == 0
    d0, d1 = (json.loads((tmp_path / n / "discrepancy.json").read_text()) for n in ("d0", "d1"))
    assert "model_options" not in d0 and d1["model_options"] == {"paper": {"material_law": "stiff"}}
    k0 = analytic.gains(design.preset("paper"), "cap")[0]
    assert d0["calibration"]["nominal_gain_per_mm_MPa"] == k0  # the tier's gain is the formula's, bit for bit
    assert d1["calibration"]["nominal_gain_per_mm_MPa"] == pytest.approx(RATIO * k0, rel=REL)
    assert d1["calibration"]["gain_per_mm_MPa"] == pytest.approx(RATIO * k0, rel=REL)  # the fixed gain
    capsys.readouterr()
    args = [
        "discrepancy",
        "paper",
        str(csv),
        "--reference",
        "prototype",
        *STIFF,
        "--out",
        str(tmp_path / "d2"),
    ]
    assert main(args) == 2
    assert "--model-option" in (err := capsys.readouterr().err) and "prototype" in err


def test_demo_takes_the_option(law, tmp_path):
    base = ["demo", "paper", "--only", "model", "--no-fem"]
    assert main([*base, "--out", str(tmp_path / "m0")]) == 0
    assert main([*base, *STIFF, "--out", str(tmp_path / "m1")]) == 0
    j0, j1 = (json.loads((tmp_path / n / "demo.json").read_text()) for n in ("m0", "m1"))
    assert "model_options" not in j0 and j1["model_options"] == {"paper": {"material_law": "stiff"}}
    k0, e0 = analytic.gains(design.preset("paper"), "cap")
    h0, h1 = ((tmp_path / n / "index.html").read_text(encoding="utf-8") for n in ("m0", "m1"))
    assert fmt(k0) in h0 and fmt(RATIO * k0) in h1 and fmt(RATIO * k0) not in h0
    assert fmt(e0) in h0 and fmt(RATIO * e0) in h1


def test_the_demo_sweep_spec_carries_the_option(law):
    text = demo_sweep_spec({"paper": {"material_law": "stiff"}})
    spec = parse_spec(tomllib.loads(text))
    assert spec.options == {"paper": {"material_law": "stiff"}}
    assert demo_sweep_spec({}) == demo_sweep_spec() and "[sweep.options" not in demo_sweep_spec()
    assert parse_spec(tomllib.loads(demo_sweep_spec())).options == {}
