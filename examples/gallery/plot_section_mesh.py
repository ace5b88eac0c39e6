"""
The section model's mesh
========================

The as-assembled cross-section of the paper's design as the section model meshes it: the
homogenised coil annulus, the squeezed silicone tube with its lumen, the channel and the Ecoflex
filler, each region a colour. Beside it, the axial stress per MPa of lumen pressure.
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.tri import Triangulation

from softcath import design
from softcath.fem.section_model import section_model
from softcath.fem.section_model.picture import axial_stress

d = design.preset("paper")
result = section_model(d, loads=("lumen",), keep_fields=True)
mesh, op, sol = result.fields
xy = mesh.points
tri = Triangulation(xy[:, 0], xy[:, 1], mesh.triangles)

fig, axes = plt.subplots(1, 2, figsize=(9, 4.2))
axes[0].tripcolor(tri, facecolors=mesh.labels.astype(float), cmap="Pastel1", edgecolors="0.5", lw=0.2)
axes[0].set_title(f"regions and mesh ({mesh.triangles.shape[0]} triangles)")
stress = axial_stress(op, sol.loads["lumen"])
lim = float(np.percentile(np.abs(stress), 99)) or 1.0
pc = axes[1].tripcolor(tri, facecolors=stress, cmap="coolwarm", vmin=-lim, vmax=lim)
fig.colorbar(pc, ax=axes[1], label="σ_zz per MPa of lumen pressure")
axes[1].set_title("axial stress, lumen load")
for ax in axes:
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
axes[0].set_ylabel("y [mm]")
fig.tight_layout()
