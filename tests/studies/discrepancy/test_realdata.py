"""Real lab layouts through the converter, calibration and the missing-effect workflow.

Synthetic files in the two data sets' own layouts are generated here (never
copied: the real data have no licence); a last group runs on the real folder
``../shared/realdata`` when it is present and is skipped otherwise.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

from softcath import design
from softcath.design.errors import DataError
from softcath.design.measurement import read_measurement_csv
from softcath.studies.discrepancy import run_workflow
from softcath.studies.discrepancy.naming import _experiment
from softcath.studies.discrepancy.prepare import prepare

ROOT = Path(__file__).resolve().parents[3]
REAL = ROOT.parent / "shared" / "realdata"
EXAMPLES = ROOT / "examples" / "realdata"


def _convert_module():
    spec = importlib.util.spec_from_file_location("realdata_convert", EXAMPLES / "convert.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


convert = _convert_module()

# ------------------------------------------------------------ synthetic layouts

FS = 25.0
P_MAX = 0.06  # MPa, as the pneumatic actuator's pumps reach
GAIN = 0.15  # 1/(mm MPa)
THRESHOLD = 0.015  # MPa: the hidden dead zone of the synthetic pneumatic actuator


def _pump_pressure(t, on, off, rng):
    """A pump filling a chamber (time constant 0.8 s) and the chamber venting (3 s)."""
    p = np.where(t < on, 0.0, P_MAX * (1 - np.exp(-(np.maximum(t - on, 0)) / 0.8)))
    p_off = P_MAX * (1 - np.exp(-(off - on) / 0.8))
    p = np.where(t >= off, p_off * np.exp(-(t - off) / 3.0), p)
    return p + rng.normal(0, 2e-4, t.size)


def write_ijpelaar_like(folder: Path, seed: int = 0) -> None:
    """Three ``;``-separated 21-column logs as the actuator's logger writes them (25 Hz).

    Chamber A pumped 2-8 s, B 20-26 s, both 38-44 s; the bend follows the driven
    chamber's pressure through a dead zone of THRESHOLD, with 1 % noise.
    """
    raw = folder / convert.IJPELAAR / "raw"
    raw.mkdir(parents=True)
    for k, name in enumerate(convert.IJPELAAR_FILES):
        rng = np.random.default_rng(seed + k)
        t = np.arange(0, 50, 1 / FS) + rng.uniform(-1e-3, 1e-3, 1250)  # the logger's jitter
        t[0] = 0.0
        pa = _pump_pressure(t, 2, 8, rng) + _pump_pressure(t, 38, 44, rng)
        pb = _pump_pressure(t, 20, 26, rng) + _pump_pressure(t, 38, 44, rng)
        u1 = np.where(((t >= 2) & (t < 8)) | ((t >= 38) & (t < 44)), 1600, 0)
        u2 = np.where(((t >= 20) & (t < 26)) | ((t >= 38) & (t < 44)), 1600, 0)
        kap_m = GAIN * 1e3 * (np.maximum(pa - THRESHOLD, 0) - np.maximum(pb - THRESHOLD, 0))
        kap_m += rng.normal(0, 0.01 * GAIN * 1e3 * P_MAX, t.size)
        eps = 0.5 * (pa + pb)
        ang = np.degrees(kap_m * 0.07 * (1 + eps))
        x, y = -0.07 * np.sin(ang / 57.3) / 2, 0.07 * np.ones_like(t)
        p0 = 1013.0
        cols = [t, p0 + pa * 1e4, np.full_like(t, p0), p0 + pb * 1e4, np.full_like(t, p0), u1, u2, x, y]
        cols += [kap_m, eps, ang] + [np.zeros_like(t)] * 9
        lines = [";".join(f"{v:.6f}" for v in row) for row in np.column_stack(cols)]
        (raw / name).write_text("\n".join(lines) + "\n")


def write_marchese_like(folder: Path, seed: int = 0) -> dict[str, float]:
    """``raw_extracted.csv`` with three segments loaded in volume steps; returns each threshold."""
    rng = np.random.default_rng(seed)
    d = folder / convert.MARCHESE
    d.mkdir(parents=True)
    rows = ["segment,step,voltage_V,piston_bits,curvature_per_m,length_m"]
    truth = {"ribbed": 0.008, "cylindrical": 0.02, "pleated": 0.012}
    for seg, thr in truth.items():
        for step in range(18):
            p_kpa = 3.4 * step
            kappa = 400 * max(p_kpa / 1000 - thr, 0) * (1 + rng.normal(0, 0.01))
            volt = 0.51 + p_kpa / (convert.PSI_PER_VOLT * convert.KPA_PER_PSI)
            rows.append(f"{seg},{step},{volt:.4f},{200 * step},{kappa:.4f},0.06")
    (d / "raw_extracted.csv").write_text("\n".join(rows) + "\n")
    return truth


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory):
    src = tmp_path_factory.mktemp("realdata")
    write_ijpelaar_like(src)
    truth = write_marchese_like(src)
    out = tmp_path_factory.mktemp("converted")
    return convert.convert_all(src, out), truth, out


def test_converter_writes_the_schema_with_time_restarting_per_run(synthetic):
    files, _, _ = synthetic
    m = read_measurement_csv(files["ijpelaar"][0])
    # three files x (A, B): the both-chambers phases are left out
    assert m.runs == [f"{f}_{c}" for f in ("16069V", "16067V", "stepside") for c in "AB"]
    for r in m.runs:
        t = m.select_run(r).time_s
        assert t[0] == 0.0 and np.all(np.diff(t) > 0)
    # chamber B's bend is signed positive, like A's: the driven chamber bends it
    assert m.select_run("16069V_B").curvature_per_mm.max() > 0.5 * GAIN * (P_MAX - THRESHOLD)
    assert "other_chamber_pressure_MPa" in m.extra
    q = read_measurement_csv(files["marchese"][0])
    assert q.runs == ["marchese_ribbed", "marchese_cylindrical", "marchese_pleated"]
    assert q.is_step_index() and "volume_mL" in q.extra
    # pressure: the transducer's 15 psi over 4 V, zeroed at step 0: 3.4 kPa per step
    np.testing.assert_allclose(
        q.select_run("marchese_ribbed").pressure_MPa, 3.4e-3 * np.arange(18), atol=1e-6
    )


def test_converter_refuses_to_write_into_the_repository(tmp_path):
    with pytest.raises(DataError, match="inside the repository"):
        convert.convert_all(tmp_path, ROOT / "out" / "realdata")
    with pytest.raises(DataError, match="no such folder"):
        convert.convert_all(tmp_path / "absent", tmp_path / "o")


def test_step_data_are_recognised_and_no_step_is_asked_for(synthetic):
    files, _, _ = synthetic
    prep = prepare(read_measurement_csv(files["ijpelaar"][0]))
    assert prep.kinds() == {"step"} and not prep.static
    text = _experiment("viscoelastic", ["lag", "hysteresis"], prep)
    assert "step-and-hold" not in text and "sine runs at two frequencies" in text


def test_pneumatic_layout_names_the_threshold(synthetic):
    files, _, out = synthetic
    r = run_workflow(files["ijpelaar"][0], out / "ijpelaar_two_chamber.toml", max_effects=1)
    assert r.named == ("dead_zone",)
    est = r.steps[0]["params"]["threshold_MPa"]
    assert est == pytest.approx(THRESHOLD, rel=0.3)  # the parameter-recovery bar
    assert r.nrmse_after < 0.5 * r.nrmse_before


def test_quasi_static_points_refuse_time_dependent_candidates(synthetic):
    files, truth, out = synthetic
    seg = out / "marchese_cylindrical.csv"
    with pytest.raises(DataError, match=r"lag need a clock, but time_s here is a step index"):
        run_workflow(seg, candidates=("lag", "dead_zone"))
    r = run_workflow(seg, out / "marchese_cylindrical.toml", max_effects=1)
    assert {x["kind"] for x in r.runs} == {"quasi-static"}
    assert r.named == ("dead_zone",)
    assert r.steps[0]["params"]["threshold_MPa"] == pytest.approx(truth["cylindrical"], rel=0.3)
    assert any("lag, delay, viscoelastic were not tried" in n for n in r.notes)
    assert any("loading only" in n for n in r.notes)


def test_cli_quasi_static_refusal_is_one_line(synthetic, tmp_path, capsys):
    from softcath.cli.main import main

    _, _, out = synthetic
    code = main(
        ["discrepancy", str(out / "marchese_ribbed.csv"), "--candidates", "delay", "--out", str(tmp_path)]
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "need a clock" in err[0]


def test_stand_in_designs_carry_the_data_gain(synthetic):
    """The converter's stand-ins: the paper design with every modulus divided by one factor,
    so the formula gain is exactly that factor times the paper's, chosen (to 0.01) to equal
    the data's least-squares gain through the origin."""
    from softcath import analytic

    files, _, out = synthetic
    paper = design.preset("paper")
    g_paper = analytic.gains(paper, "cap")[0]
    assert {p.stem for p in files["stand_ins"]} == {
        "ijpelaar_two_chamber",
        "marchese_ribbed",
        "marchese_cylindrical",
        "marchese_pleated",
    }
    for path in files["stand_ins"]:
        d = design.load(path)
        factor = paper.tube.material.youngs_modulus / d.tube.material.youngs_modulus
        assert paper.filler.youngs_modulus / d.filler.youngs_modulus == pytest.approx(factor, rel=1e-12)
        assert analytic.gains(d, "cap")[0] == pytest.approx(g_paper * factor, rel=1e-9)
        csv = out / ("ijpelaar_steps.csv" if path.stem.startswith("ijpelaar") else f"{path.stem}.csv")
        m = read_measurement_csv(csv)
        p, k = m.pressure_MPa, m.curvature_per_mm
        data_gain = np.linalg.lstsq(p[:, None], k, rcond=None)[0][0]
        # the factor is rounded to 0.01: the gain is off by at most 0.005 / factor
        assert analytic.gains(d, "cap")[0] == pytest.approx(data_gain, rel=0.005 / factor + 1e-9)
    assert design.load(out / "ijpelaar_two_chamber.toml").tip.bending_length == convert.L0_MM


# ------------------------------------------------------------ the real folder

needs_real = pytest.mark.skipif(not REAL.is_dir(), reason=f"real data folder {REAL} absent")


@needs_real
def test_real_files_convert_like_the_providers_own_conversion(tmp_path):
    import pandas as pd

    files = convert.convert_all(REAL, tmp_path)
    ours = pd.read_csv(files["ijpelaar"][0])
    theirs = pd.read_csv(REAL / convert.IJPELAAR / "ijpelaar_steps.csv")
    assert list(ours["run"]) == list(theirs["run"])
    # an independent conversion of the same raw logs (theirs does not restart time per run)
    for c in ("pressure_MPa", "curvature_per_mm", "bend_angle_rad", "arc_length_mm", "tip_x_mm"):
        np.testing.assert_allclose(ours[c], theirs[c], atol=1e-4 * np.abs(theirs[c]).max())
    m = pd.read_csv(files["marchese"][0])
    n = pd.read_csv(REAL / convert.MARCHESE / "marchese_static.csv")
    np.testing.assert_allclose(m["pressure_MPa"], n["pressure_MPa"], atol=1e-6)
    np.testing.assert_allclose(m["curvature_per_mm"], n["curvature_per_mm"], atol=1e-7)


@needs_real
def test_real_data_through_calibrate_and_discrepancy(tmp_path, capsys):
    from softcath.cli.main import main

    files = convert.convert_all(REAL, tmp_path / "csv")
    # the providers' own file, whose time_s restarts when the source log changes
    raw = read_measurement_csv(REAL / convert.IJPELAAR / "ijpelaar_steps.csv")
    assert len(raw.runs) == 5
    seg = tmp_path / "csv" / "marchese_cylindrical.csv"
    toml = str(tmp_path / "csv" / "marchese_cylindrical.toml")
    assert main(["calibrate", toml, str(seg), "--out", str(tmp_path / "c")]) == 0
    cal = json.loads((tmp_path / "c" / "calibration.json").read_text())
    assert cal["gain_data_uncertainty"]["curvature_per_mm_per_MPa_stderr"] > 0
    assert main(["discrepancy", toml, str(seg), "--out", str(tmp_path / "d")]) == 0
    rec = json.loads((tmp_path / "d" / "discrepancy.json").read_text())
    # the provenance: "almost no bending up to about 30 kPa, then a jump": a threshold
    assert rec["named"][0] == "dead_zone"
    assert 0.01 < rec["steps"][0]["params"]["threshold_MPa"] < 0.035
    assert rec["nrmse_after"] < rec["nrmse_before"]
    assert files["ijpelaar"][0].is_file()


@needs_real
@pytest.mark.slow
def test_real_pneumatic_steps_through_discrepancy(tmp_path):
    files = convert.convert_all(REAL, tmp_path)
    r = run_workflow(files["ijpelaar"][0], str(tmp_path / "ijpelaar_two_chamber.toml"))
    assert {x["kind"] for x in r.runs} == {"step"}
    assert r.named and r.nrmse_after < r.nrmse_before
    assert all("step-and-hold" not in s["separating_experiment"] for s in r.steps)
