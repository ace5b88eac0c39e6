"""A silicone's Yeoh fit follows the design's modulus: the finite-strain tiers' small-load gain is
the linear section model's for any filler or tube modulus (it kept the material's fit before)."""

from __future__ import annotations

from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from softcath import design
from softcath.fem.hyperelastic.laws import isotropic_from_young, yeoh_at_modulus
from softcath.fem.section_model import section_model
from softcath.fem.section_model.finite_strain import section_curve


@settings(max_examples=50, deadline=None, derandomize=True, database=None)
@given(e=st.floats(1e-3, 1e3), nu=st.floats(0.0, 0.4999), c2=st.floats(-1.0, 1.0), c3=st.floats(0.0, 1.0))
def test_the_scaled_fit_has_the_designs_shear_modulus(e, nu, c2, c3):
    yeoh = yeoh_at_modulus((0.017, 0.017 * c2, 0.017 * c3), youngs_modulus=e, poisson_ratio=nu)
    law = isotropic_from_young(youngs_modulus=e, poisson_ratio=nu, yeoh=yeoh)
    assert 2 * law.c1 == pytest.approx(e / (2 * (1 + nu)), rel=1e-12)
    assert law.c2 / law.c1 == pytest.approx(c2, rel=1e-9, abs=1e-12)  # the curve's shape is kept


@settings(max_examples=6, deadline=None, derandomize=True, database=None)
@given(factor=st.sampled_from([0.1, 0.3, 1.0, 3.0, 10.0, 30.0]), part=st.sampled_from(["filler", "tube"]))
def test_finite_strain_small_load_gain_is_the_linear_tiers(factor, part):
    d = design.preset("paper")
    if part == "filler":
        assert d.filler is not None
        d = replace(d, filler=replace(d.filler, youngs_modulus=d.filler.youngs_modulus * factor))
    else:
        m = d.tube.material
        d = replace(d, tube=replace(d.tube, material=replace(m, youngs_modulus=m.youngs_modulus * factor)))
    linear = section_model(d).curvature_per_mm_per_MPa["lumen"]
    c = section_curve(d, [0.002])
    assert c.linear_curvature_per_mm_per_MPa == pytest.approx(linear, rel=1e-9)
    assert c.curvature_per_mm[0] / 0.002 == pytest.approx(linear, rel=0.02)  # the curve's first point


@pytest.mark.slow
def test_fem_nonlinear_draws_the_papers_formula_as_softcath_analytic(cli, tmp_path):
    """The paper's-formula column of ``fem --nonlinear`` (lumen load by default) is the formula at the
    same pressure that ``softcath analytic`` gives (it was the lumen-wall effect alone, 50x smaller)."""
    import csv
    import json

    fem = ["fem", "paper", "--nonlinear", "--pressure", "0.3", "--steps", "1", "--mesh-size", "0.3"]
    assert cli(*fem, "--out", tmp_path / "f").status == 0
    assert cli("analytic", "paper", "--pressure", "0.3", "--out", tmp_path / "a").status == 0
    with (tmp_path / "a" / "analytic.csv").open() as fh:
        ref = list(csv.DictReader(fh))[-1]
    with (tmp_path / "f" / "pressure_sweep.csv").open() as fh:
        row = list(csv.DictReader(fh))[-1]
    assert float(row["analytic_bend_angle_rad"]) == pytest.approx(float(ref["bend_angle_rad"]), rel=1e-6)
    doc = json.loads((tmp_path / "f" / "fem.json").read_text())
    assert doc["analytic"]["curvature_per_mm"] == pytest.approx(float(ref["curvature_per_mm"]), rel=1e-6)
    assert doc["analytic"]["load"] == "cap" and 1 < doc["ratio_fem_over_analytic"] < 10
