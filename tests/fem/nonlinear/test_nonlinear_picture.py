"""The finite-strain tip picture: a rendered surface coloured by strain, like the linear FEM's tip.png."""

from __future__ import annotations

import numpy as np
import pytest

from softcath import design
from softcath.fem.nonlinear.bend import bend_curve
from softcath.fem.nonlinear.catheter import mesh_catheter
from softcath.fem.nonlinear.outputs import deformed_grid, plot_deformed


@pytest.mark.slow
def test_deformed_grid_carries_the_curves_strain_and_renders(tmp_path):
    paper = design.preset("paper")
    cm = mesh_catheter(paper, size=0.15, layers=3)
    c = bend_curve(paper, [0.05, 0.1], load="lumen", mesh=cm)
    grid = deformed_grid(c)
    assert grid.n_cells == cm.mesh.t.shape[1] and grid.n_points == cm.mesh.p.shape[1]
    strain = np.asarray(grid.cell_data["max_principal_strain"])
    # the element strain is the measure of curve.max_strain (largest principal stretch strain): its largest
    # value over the cells the curve reads (silicone away from the clamp) is the curve's value
    assert strain[c.model._strain_cells].max() == pytest.approx(c.max_strain[-1], rel=1e-12)
    tip = np.isclose(cm.mesh.p[2], cm.length)
    assert np.abs(grid.point_data["displacement"][tip]).max() > 0
    path = tmp_path / "deformed_tip.png"
    plot_deformed(c, path)
    from PIL import Image

    img = np.asarray(Image.open(path).convert("RGB"))
    assert img.shape[:2] == (700, 1200)  # render_png's window: the same picture
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > 200  # a shaded, colour-mapped surface
