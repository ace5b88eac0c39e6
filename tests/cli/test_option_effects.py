"""An option that acts only with another is refused without it, before any work, naming both
(``optimise --samples`` without ``--robust``, ``fem --steps`` without ``--nonlinear``, ...)."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from softcath.cli.options import _ACTS_ONLY_WITH

BASES = {
    "optimise": [
        "optimise",
        "paper",
        "--vary",
        "tube.h=-0.04:0.04",
        "--objective",
        "maximise bend_angle_deg",
    ],
    "select": ["select", "no-such-sweep", "--objective", "maximise bend_angle_deg"],
    "predict": ["predict", "paper", "--model", "paper"],
    "fem linear": ["fem", "paper", "--pressure", "0.1"],
    "fem nonlinear": ["fem", "paper", "--nonlinear"],
}
VALUES = {
    "samples": ["--samples", "50"],
    "robust_vary": ["--robust-vary", "tube.a_int=0.1:0.12"],
    "ranges": ["--ranges", "r.toml"],
    "vary": ["--vary", "tube.a_int=0.1:0.12"],
    "seed": ["--seed", "3"],
    "robust_model": ["--robust-model", "paper"],
    "curve_samples": ["--curve-samples", "8"],
    "fem_samples": ["--fem-samples", "4"],
    "steps": ["--steps", "3"],
    "layers": ["--layers", "3"],
    "curvature_points": ["--curvature-points", "16"],
    "area_true_section": ["--area-true-section"],
    "mixed": ["--mixed"],
    "compare_linear": ["--compare-linear"],
    "mesher": ["--mesher", "tetwild"],
    "coil_modulus": ["--coil-modulus", "bending"],
    "no_cache": ["--no-cache"],
    "no_png": ["--no-png"],
}
CASES = []
for command, rules in _ACTS_ONLY_WITH.items():
    for dests, _, why in rules:
        base = command
        if command == "fem":
            base = "fem linear" if "steps" in dests else "fem nonlinear"
        CASES += [(base, d, why) for d in dests]


@settings(
    max_examples=len(CASES) * 2,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(case=st.sampled_from(CASES))
def test_an_option_without_effect_is_refused_naming_what_it_needs(cli, tmp_path, case):
    base, dest, why = case
    out = tmp_path / "o"
    line = cli(*BASES[base], *VALUES[dest], "--out", out).error_line()
    assert f"{VALUES[dest][0]} = " in line and why in line, line
    assert not out.exists()


def test_the_same_options_are_taken_with_what_they_need(cli, tmp_path):
    argv = [*BASES["optimise"], "--model", "paper", "--budget", "10", "--no-fem-check", "--no-progress"]
    r = cli(*argv, "--robust", "0.9", "--samples", "4", "--out", tmp_path / "o")
    assert r.status == 0, r.err
