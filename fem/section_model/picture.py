"""Pictures of the section model: the deformed section coloured by axial stress."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from softcath.core.plotting import pyplot

__all__ = ["axial_stress", "section_picture"]


def axial_stress(op, load_solution) -> np.ndarray:
    """Element-mean axial stress sigma_zz (MPa per MPa of pressure) of one load case.

    The volumetric part uses the element mean of lambda tr(eps) (the P0 part of
    the projected pressure), enough for a picture.
    """
    w = op.basis.dx
    strain = op.strain_field(load_solution.U, load_solution.strains)  # (4, nel, nq)
    s_zz = np.einsum("ec,ceq->eq", op.D[:, 2, :], strain)
    tr = strain[0] + strain[1] + strain[2]
    area = w.sum(axis=1)
    s_zz = (s_zz * w).sum(axis=1) / area + op.lam * (tr * w).sum(axis=1) / area
    return s_zz


def section_picture(result, path: Path, *, load: str = "lumen", pressure: float = 0.1) -> Path:
    """Write a PNG of the section deformed at ``pressure`` (MPa), coloured by sigma_zz.

    ``result`` must come from ``section_model(..., keep_fields=True)``. The
    in-plane deformation is magnified so the largest displacement shows as 5 %
    of the section's width; the factor is printed in the title.
    """
    plt = pyplot()
    from matplotlib.tri import Triangulation  # heavy: matplotlib loads on the first picture

    if result.fields is None:
        raise ValueError("section_picture needs section_model(..., keep_fields=True)")
    mesh, op, sol = result.fields
    ls = sol.loads[load]
    nd = op.basis.nodal_dofs
    uv = ls.U[nd] * pressure  # (2, nverts)
    xy = mesh.points
    width = np.ptp(xy[:, 0])
    umax = float(np.abs(uv).max()) or 1.0
    scale = 0.05 * width / umax
    s = axial_stress(op, ls) * pressure
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6))
    tri0 = Triangulation(xy[:, 0], xy[:, 1], mesh.triangles)
    axes[0].tripcolor(tri0, facecolors=mesh.labels.astype(float), cmap="Pastel1", edgecolors="0.6", lw=0.2)
    axes[0].set_title("section regions and mesh")
    tri = Triangulation(xy[:, 0] + scale * uv[0], xy[:, 1] + scale * uv[1], mesh.triangles)
    lim = float(np.percentile(np.abs(s), 99)) or 1.0
    pc = axes[1].tripcolor(tri, facecolors=s, cmap="coolwarm", vmin=-lim, vmax=lim)
    axes[1].triplot(tri0, color="0.75", lw=0.2)
    fig.colorbar(pc, ax=axes[1], label="axial stress σ_zz [MPa]")
    k = result.curvature_per_mm_per_MPa[load] * pressure
    axes[1].set_title(f"{load} load, {pressure:g} MPa: κ = {k:.4f} /mm\nin-plane displacement ×{scale:.0f}")
    for ax in axes:
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm] (toward the coil wall)")
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path
