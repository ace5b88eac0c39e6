"""The linear 3-D check's three-mesh study (softcath.fem.mesh_study)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from softcath import design
from softcath.fem.mesh_study import mesh_study, study_mesh_sizes
from softcath.fem.nonlinear.convergence import extrapolate, observed_order, richardson_error


def test_the_study_meshes_around_the_size_and_refuses_one_too_coarse():
    assert study_mesh_sizes(0.16) == pytest.approx((0.32, 0.16, 0.08))
    with pytest.raises(design.DesignError, match=r"mesh_size = 0.25: must be <= 0.2 mm"):
        mesh_study("paper", [0.1], load="cap", mesh_size=0.25)  # 0.5 mm would not resolve the tip


@pytest.mark.slow
def test_the_default_study_of_the_lumen_load(tmp_path):
    # Paper design, 0.32/0.16/0.08 mm (3/6/12 layers): measured observed order 2.23, the default
    # mesh 0.37 % from the extrapolation. P2 with curved boundaries would converge faster in the
    # asymptotic range; the layers along the tip keep it pre-asymptotic here, so the order is
    # asserted within [1.5, 3.5], above first order and below the cap load's decay (> 4).
    st = mesh_study("paper", [0.05, 0.1], load="lumen")
    assert st.mesh_size == pytest.approx((0.32, 0.16, 0.08))
    k = st.unit_curvature
    q = st.observed_order
    assert q == pytest.approx(observed_order(k, [1 / 0.32, 1 / 0.16, 1 / 0.08]), rel=1e-12)
    assert 1.5 <= q <= 3.5
    ext = extrapolate(k, [1 / 0.32, 1 / 0.16, 1 / 0.08], q)
    assert st.extrapolated == pytest.approx(ext * np.array([0.05, 0.1]), rel=1e-12)
    # the answer is the middle mesh, its error from the coarse one with the observed order
    c = st.result.case("lumen", 0.1)
    assert c.curvature_per_mm == pytest.approx(0.1 * k[1], rel=1e-12)
    est = st.result.discretisation_error
    assert est is not None
    assert est.order_source == "observed" and est.order == pytest.approx(q)
    stated = richardson_error([k[1]], [k[0]], layers=1 / 0.16, coarse_layers=1 / 0.32, order=q)[0]
    assert c.discretisation_error_estimate == pytest.approx(stated, rel=1e-9)
    assert 0 < st.relative_error[2, 1] < st.relative_error[1, 1] < st.relative_error[0, 1] < 0.05
    assert st.ndofs[0] < st.ndofs[1] < st.ndofs[2] and all(math.isfinite(s) for s in st.seconds)
