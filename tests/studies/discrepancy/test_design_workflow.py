"""The missing-effect workflow over design sweeps (section-model ingredients)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from softcath import analytic, design
from softcath.fem.section_model import section_model
from softcath.studies.discrepancy.design_workflow import DesignCase, run_design_workflow


def _cases(designs, reference, seed, noise):
    rng = np.random.default_rng(seed)
    cases = []
    for i, d in enumerate(designs):
        f = analytic.gains(d, "cap")[0]
        for load in ("cap", "lumen"):
            cases.append(
                DesignCase(i, load, d, reference(d, load, f) * (1 + noise * rng.standard_normal()), f)
            )
    return cases


@pytest.fixture(scope="module")
def designs():
    from softcath.studies.sweep.random_designs import random_designs

    return random_designs(12, seed=3)


def test_formula_plus_noise_names_nothing(designs):
    cases = _cases(designs, lambda d, load, f: f, seed=1, noise=0.01)
    r = run_design_workflow(cases, seed=0)
    assert r.named == ()
    assert r.gap_after == r.gap_before
    assert r.notes and "nothing beats" in r.notes[0]


def test_section_physics_as_reference_is_named_and_the_gap_shrinks(designs):
    """'FEM' = the full section model (cap nu 0.49, annulus coils, lumen wall load) + 0.2 % noise."""

    def full(d, load, f):
        return section_model(d, poisson_cap=0.49).curvature_per_mm_per_MPa[load]

    cases = _cases(designs, full, seed=2, noise=0.002)
    r = run_design_workflow(cases, seed=0)
    assert {"confinement", "coil_homogenisation", "poisson_mismatch"} <= set(r.named)
    assert r.gap_before / r.gap_after >= 5
    doc = r.to_json()
    assert {"named", "steps", "nrmse_before", "nrmse_after", "ambiguous_with"} <= set(doc)


def test_bad_candidates_are_refused(designs):
    cases = _cases(designs[:4], lambda d, load, f: f, seed=1, noise=0.0)
    with pytest.raises(design.DataError, match="candidates"):
        run_design_workflow(cases, candidates=["lumen_wall"])


@pytest.mark.slow
def test_real_fem_sweep_names_the_ingredients(tmp_path):
    """A real 3-D FEM sweep through ``softcath sweep`` and ``softcath discrepancy SWEEP --reference fem``."""
    from pathlib import Path

    from softcath.cli.main import main

    spec = Path(__file__).resolve().parents[3] / "examples" / "sweeps" / "ingredients_fem.toml"
    sweep = tmp_path / "sweep"
    assert main(["sweep", str(spec), "--out", str(sweep), "--workers", "1"]) == 0
    out = tmp_path / "disc"
    assert main(["discrepancy", str(sweep), "--reference", "fem", "--out", str(out)]) == 0
    doc = json.loads((out / "discrepancy.json").read_text())
    assert {"confinement", "coil_homogenisation"} <= set(doc["named"])
    assert doc["gap_before"] / doc["gap_after"] >= 5
    assert (out / "report.html").stat().st_size > 20_000
