"""The tip FEM against closed forms and the composite-beam model."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from softcath import analytic, design, fem
from softcath.fem.adapter import fem_laws_from_design, geometry_from_design
from softcath.fem.geometry import REGIONS
from softcath.fem.materials import Isotropic
from softcath.fem.pipeline import axial_modulus, run_tip
from softcath.fem.section_model.end_zones import end_zones

NU = 0.3


@pytest.fixture(scope="module")
def paper():
    return design.preset("paper")


@pytest.fixture(scope="module")
def geometry(paper):
    return geometry_from_design(paper)


def homogeneous_section(g):
    """Closed-form area, centroid y and I_x about it of the homogeneous section:
    the coil's outer disk minus the lumen ellipse minus the channel lumen."""
    ro, al, yl = g.coil_outer_radius, np.pi * g.lumen_a * g.lumen_b, g.lumen_y
    ac, yc = np.pi * g.channel_inner_radius**2, g.channel_y
    area = np.pi * ro**2 - al - ac
    ybar = (-al * yl - ac * yc) / area
    i0 = (
        np.pi * ro**4 / 4
        - (np.pi * g.lumen_a * g.lumen_b**3 / 4 + al * yl**2)
        - (np.pi * g.channel_inner_radius**4 / 4 + ac * yc**2)
    )
    return area, ybar, i0 - area * ybar**2, al


@pytest.mark.slow
def test_homogeneous_eccentric_tube_cap_and_lumen(geometry):
    law = Isotropic(1.0, NU)
    sol = run_tip(geometry, {k: law for k in REGIONS}, mesh_size=0.16)
    area, ybar, inertia, al = homogeneous_section(geometry)
    k_eb = al * (geometry.lumen_y - ybar) / (1.0 * inertia)  # per MPa
    e_eb = al / (1.0 * area)
    cap, lumen = sol.fits["cap"], sol.fits["lumen"]
    # 3 %: the bound for EB vs a 3-D solid with a clamp and a cap (L/D = 6);
    # measured 0.9996 for the cap and 0.992 for the lumen at this mesh.
    assert cap.curvature_per_mm == pytest.approx(k_eb, rel=0.03)
    assert cap.elongation == pytest.approx(e_eb, rel=0.03)
    # Lumen wall + cap, one Poisson ratio: both scaled by (1 - 2 nu) (generalised
    # plane strain: the wall pressure gives N = -2 nu p A_L at y_L).
    assert lumen.curvature_per_mm == pytest.approx((1 - 2 * NU) * k_eb, rel=0.03)
    assert lumen.elongation == pytest.approx((1 - 2 * NU) * e_eb, rel=0.03)
    assert cap.neutral_axis_y == pytest.approx(ybar, abs=1e-3)
    # the paper's claim of a constant-curvature arc holds: < 2 % spread
    assert cap.curvature_variation < 0.02
    assert sol.residual < 1e-12


def composite_gains(g, laws):
    """Composite Euler-Bernoulli (paper eqs. 4, 5, 7) of the same section and axial
    moduli as the FEM, by exact section integrals on a fine grid (not the mesh)."""
    n = 1500
    r = g.coil_outer_radius
    s = (np.arange(n) + 0.5) / n * 2 * r - r
    x, y = (a.ravel() for a in np.meshgrid(s, s))
    lab = g.classify(x, y)
    e = np.array([axial_modulus(laws[k]) if k in laws else 0.0 for k in range(5)])[lab]
    da = (2 * r / n) ** 2
    ea = (e * da).sum()
    ybar = (e * y * da).sum() / ea
    ei = (e * (y - ybar) ** 2 * da).sum()
    al = np.pi * g.lumen_a * g.lumen_b
    return al * (g.lumen_y - ybar) / ei, al / ea


@pytest.mark.slow
def test_catheter_cap_load_vs_composite_beam(geometry, paper):
    laws = fem_laws_from_design(paper)
    # Without confinement (coil hoop modulus lowered to its axial one) the 3-D
    # section bends as the composite beam: within 5 %. The
    # residual (measured 3.3 %) is the Poisson mismatch between bonded regions
    # (nu 0.49 silicone next to nu 0.29 coils), which a beam model has no term for.
    soft = {
        k: (replace(v, transverse_modulus=v.axial_modulus) if hasattr(v, "axial_modulus") else v)
        for k, v in laws.items()
    }
    k_beam, _ = composite_gains(geometry, soft)
    sol = run_tip(geometry, soft, loads=("cap",), mesh_size=0.16)
    assert sol.fits["cap"].curvature_per_mm == pytest.approx(k_beam, rel=0.05)


@pytest.mark.slow
def test_paper_check_cap_and_lumen(paper):
    r = fem.check(paper, pressures=[0.05, 0.1], loads=("cap", "lumen"), mesh_size=0.16)
    cap1, cap2 = r.case("cap", 0.05), r.case("cap", 0.1)
    # linear in pressure, factorised once: exact scaling
    assert cap2.curvature_per_mm == pytest.approx(2 * cap1.curvature_per_mm, rel=1e-12)
    assert cap2.max_strain == pytest.approx(2 * cap1.max_strain, rel=1e-12)
    k_an, e_an = analytic.gains(paper, "cap")
    assert cap2.analytic["curvature_per_mm"] == pytest.approx(0.1 * k_an, rel=1e-12)
    assert cap2.ratio_fem_over_analytic["curvature_per_mm"] == pytest.approx(
        cap2.curvature_per_mm / (0.1 * k_an), rel=1e-12
    )
    # The real (hoop-stiff) coil confines the near-incompressible silicone, which
    # then resists axial strain with ~ its P-wave modulus: the FEM bends less than
    # the composite beam of the same moduli (measured 0.75) and stretches less.
    k_beam, e_beam = composite_gains(geometry_from_design(paper), fem_laws_from_design(paper))
    assert cap2.curvature_per_mm < 0.9 * 0.1 * k_beam
    assert cap2.elongation < 0.9 * 0.1 * e_beam
    # The (1 - 2 nu) closed form predicts that the wall load
    # cancels 98 % of the cap's bending (nu = 0.49). Confined, the opposite: the
    # squeezed silicone pushes axially and the lumen case bends *more* than the cap.
    lum = r.case("lumen", 0.1)
    assert lum.analytic["curvature_per_mm"] == pytest.approx(
        (1 - 2 * 0.49) * cap2.analytic["curvature_per_mm"], rel=1e-9
    )
    assert lum.curvature_per_mm > cap2.curvature_per_mm
    assert cap2.curvature_variation < 0.05 and lum.curvature_variation < 0.05
    doc = r.to_json("lumen", 0.1)
    for key in (
        "curvature_per_mm",
        "elongation",
        "bend_angle_rad",
        "tip_x_mm",
        "tip_y_mm",
        "curvature_variation",
        "max_strain",
        "load",
        "pressure_MPa",
        "n_nodes",
        "n_elements",
        "dofs",
        "mesh_seconds",
        "solve_seconds",
        "residual",
        "analytic",
        "ratio_fem_over_analytic",
    ):
        assert key in doc
    # the tip's angle and pose (end zones off the mid-span arc), written out: an arc over the
    # stretched L - deficit, then the deficit (stretched) and the plug along its end tangent
    zones = end_zones(paper)
    stretch = 1 + lum.elongation
    theta = lum.curvature_per_mm * (5.0 - zones.deficit_mm) * stretch
    tail = zones.saint_venant_mm * stretch + zones.plug_mm
    assert lum.bend_angle_rad == pytest.approx(theta, rel=1e-12)
    x = (1 - np.cos(theta)) / lum.curvature_per_mm + tail * np.sin(theta)
    assert lum.tip_x_mm == pytest.approx(x, rel=1e-9)


def test_check_json_and_linear_scaling_on_a_coarse_mesh(paper):
    r = fem.check(paper, pressures=[0.0, 0.05, 0.1], loads=("cap",), mesh_size=0.25)
    c0, c1, c2 = (r.case("cap", p) for p in (0.0, 0.05, 0.1))
    assert c0.curvature_per_mm == 0.0 and c0.tip_x_mm == 0.0 and c0.tip_y_mm == 5.0
    assert c2.curvature_per_mm == pytest.approx(2 * c1.curvature_per_mm, rel=1e-12)
    assert c2.elongation == pytest.approx(2 * c1.elongation, rel=1e-12)
    assert c1.curvature_per_mm > 0  # bends toward the channel, the project's sign
    doc = r.to_json("cap", 0.0)
    assert doc["ratio_fem_over_analytic"]["curvature_per_mm"] is None  # 0/0 -> null
    assert r.residual < 1e-12 and r.dofs == 3 * r.n_nodes
    with pytest.raises(design.DesignError, match="not computed"):
        r.case("lumen", 0.1)


def test_bad_inputs_name_the_parameter(paper):
    with pytest.raises(design.DesignError, match="pressure"):
        fem.check(paper, pressures=[float("nan")])
    with pytest.raises(design.DesignError, match=r"load = \['torsion'\]"):
        fem.check(paper, pressures=[0.1], loads=("torsion",))
    with pytest.raises(design.DesignError, match="coil_modulus = 'steel'"):
        fem_laws_from_design(paper, coil_modulus="steel")


@pytest.mark.slow
def test_mesh_convergence_observed_order(paper, geometry):
    laws = fem_laws_from_design(paper)
    sizes = (0.36, 0.24, 0.16)  # ratio 1.5 nominally: the layers round up (3, 4, 6 of them)
    kappa = [run_tip(geometry, laws, loads=("cap",), mesh_size=h).fits["cap"].curvature_per_mm for h in sizes]
    r = sizes[0] / sizes[1]
    d1, d2 = kappa[0] - kappa[1], kappa[1] - kappa[2]
    order = np.log(abs(d1 / d2)) / np.log(r)
    extrapolated = kappa[2] - d2 / (r**order - 1)  # d2 = coarse - fine
    print(f"kappa {kappa}, observed order {order:.2f}, Richardson {extrapolated:.6g}")
    # P2 with curved boundaries: order >= 2 expected for kappa (measured ~4 here on these
    # rounded layer counts, cap load: pre-asymptotic; the stated error assumes 2, which the
    # lumen load observes, docs/fem.md). The default mesh (0.16 mm) and the next coarser
    # one must be within 1 % of the extrapolation (benchmark target).
    assert order > 2
    assert kappa[2] == pytest.approx(extrapolated, rel=0.01)
    assert kappa[1] == pytest.approx(extrapolated, rel=0.01)
