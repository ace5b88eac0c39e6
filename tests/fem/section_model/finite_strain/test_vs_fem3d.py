"""The finite-strain section model against the 3-D finite-strain FEM (slow).

Equal materials: the section model is given the 3-D FEM's own laws
(``catheter_laws``: the coils' hoop modulus capped at 1000x the stiffest
silicone's E, nu_TT 0.3, its axial shear), so the comparison tests the
kinematics and the discretisations, not a material choice. The 3-D FEM runs
its mixed u-p formulation on the linear check's mesh (``mesh_tip`` at 0.16 mm,
the mesh of ``tests/fem/section_model/test_vs_fem3d.py``) and is read at
mid-span (``curvature_mid``/``bend_rate_mid``: the sections between 0.3 L and
0.7 L, away from the clamp and cap zones). The comparable quantity is the bend
rate d(theta)/dZ, the sections' turn per undeformed length, which needs no
choice of fibre.

Tolerance 3 % at every pressure of 0.1-0.6 MPa. The 3-D mesh's own error at
mid-span, measured at small load on the default catheter mesh against its
refinements (3 to 8 layers, 12 to 24 segments per circle), spans 2 %; the
section model's is below 0.1 % (its closed-form tests).
"""

from __future__ import annotations

import numpy as np
import pytest

from softcath import design

pytestmark = pytest.mark.slow

PRESSURES = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]


def _compare(d) -> np.ndarray:
    from softcath.fem.adapter import geometry_from_design
    from softcath.fem.mesh import mesh_tip
    from softcath.fem.nonlinear import bend_curve
    from softcath.fem.nonlinear.catheter import catheter_laws, from_tip_mesh
    from softcath.fem.section_model.finite_strain import section_curve

    section = section_curve(d, PRESSURES, laws=catheter_laws(d))
    mesh = from_tip_mesh(mesh_tip(geometry_from_design(d), mesh_size=0.16))
    fem = bend_curve(d, PRESSURES, load="lumen", mixed=True, mesh=mesh)
    return np.asarray(fem.bend_rate_mid) / section.bend_rate_per_mm - 1


def test_paper_design_mid_span_within_3_percent():
    err = _compare(design.preset("paper"))
    assert np.abs(err).max() < 0.03, err
