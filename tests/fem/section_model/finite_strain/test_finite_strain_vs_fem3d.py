"""The finite-strain section model against the 3-D finite-strain FEM (slow).

Equal materials: the section model is given the 3-D FEM's own laws
(``catheter_laws``: the coils' hoop modulus capped at 1000x the stiffest
silicone's E, nu_TT 0.3, its axial shear), so the comparison tests the
kinematics and the discretisations, not a material choice. Both read the
bend rate d(theta)/dZ, the sections' turn per undeformed length: the 3-D FEM
at mid-span (``bend_rate_mid``, sections between 0.3 L and 0.7 L, away from
the clamp and cap zones), which needs no choice of fibre.

The 3-D FEM's default mesh is not converged at large bends: measured on the
paper design (lumen load, nu = 0.49, mixed u-p), its mid-span bend rate over
the section model's is 0.964 -> 0.834 from 0.1 to 0.6 MPa on the default
mesh (0.15 mm, 4 layers, 18k DOFs) and 0.974 -> 0.938 on a finer one
(0.10 mm, 6 layers, 26k DOFs): the lumen's finite inflation (area +70 % at
0.6 MPa) is what the coarse mesh stiffens. The section model itself moves by
0.03 % from its default mesh to a 4x finer one at 0.6 MPa. So the test takes
both 3-D meshes and extrapolates to zero mesh size (Richardson, the P2
elements' second order): the extrapolated 3-D bend rate must agree with the
section model within 3 % at every pressure of 0.1-0.6 MPa (measured: -1.8 % to
+2.1 %), and the refinement must close at least half of the coarse mesh's gap at
0.6 MPa (the 3-D converges toward the section model, not away).
"""

from __future__ import annotations

import numpy as np
import pytest

from softcath import design

pytestmark = pytest.mark.slow

PRESSURES = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]
MESHES = ((0.15, 4), (0.10, 6))  # (section element size [mm], layers along the tip)


def test_paper_design_extrapolated_3d_within_3_percent():
    from softcath.fem.nonlinear import bend_curve
    from softcath.fem.nonlinear.catheter import catheter_laws
    from softcath.fem.section_model.finite_strain import section_curve

    d = design.preset("paper")
    section = section_curve(d, PRESSURES, laws=catheter_laws(d)).bend_rate_per_mm
    ratios = [
        np.asarray(bend_curve(d, PRESSURES, load="lumen", mixed=True, size=h, layers=n).bend_rate_mid)
        / section
        for h, n in MESHES
    ]
    coarse, fine = ratios
    refine = (MESHES[0][0] / MESHES[1][0]) ** 2
    extrapolated = fine + (fine - coarse) / (refine - 1)
    assert np.abs(extrapolated - 1).max() < 0.03, (coarse, fine, extrapolated)
    assert abs(fine[-1] - 1) < 0.5 * abs(coarse[-1] - 1), (coarse, fine)
