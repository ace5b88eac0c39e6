"""A finite-strain sweep asked for the rest state only answers it (it does not fail every design)."""

from __future__ import annotations

import numpy as np

from softcath import design
from softcath.models.section_nonlinear_eval import section_nonlinear_columns


def test_rest_only_pressures_give_the_rest_state():
    cols = section_nonlinear_columns(design.preset("paper"), np.array([0.0]), ("lumen", "cap"))
    for load in ("lumen", "cap"):
        c = cols[load]
        assert c["curvature_section_nonlinear_per_mm"].tolist() == [0.0]
        assert c["bend_angle_section_nonlinear_rad"].tolist() == [0.0]
        assert c["lumen_volume_change_section_nonlinear_mm3"].tolist() == [0.0]
        assert np.isfinite(c["tip_x_section_nonlinear_mm"]).all()


def test_rest_only_sweep_has_no_failed_design(cli, spec_writer, tmp_path):
    spec = spec_writer(
        """
        [sweep]
        base = "paper"
        pressures_MPa = [0.0]
        evaluators = ["section-nonlinear"]
        [parameters]
        "tube.h" = { values = [0.0, 0.02] }
        """
    )
    r = cli("sweep", spec, "--out", tmp_path / "s", "--workers", "1", "--no-progress")
    assert r.status == 0, r.err
    assert "(2 ok, 0 failed)" in r.out
