"""
A tiny design sweep
===================

The formula broadcasts over many designs at once: here the lumen offset ``h`` of the squeezed tube
and the lumen half-width ``a_int`` vary on a grid, each against a range of pressures, and the
figure shows the bending gain κ/p of each design. Larger sweeps, on the section model and the FEM
too, run with ``softcath sweep``.
"""

import matplotlib.pyplot as plt
import numpy as np

from softcath import analytic, design

d = design.preset("paper")
h = np.linspace(-0.05, 0.05, 41)
a_int = np.array([0.08, 0.10, 0.12])
inp = analytic.design_inputs(d) | {"h": h[None, :, None], "a_int": a_int[:, None, None]}
p = np.linspace(0.0, 1.0, 11)
r = analytic.response_arrays(inp, p)
gain = r.curvature[..., -1] / p[-1]  # κ/p, the model being linear in p

fig, ax = plt.subplots(figsize=(6, 4))
for a, g in zip(a_int, gain, strict=True):
    ax.plot(h, g, label=f"a_int = {a:.2f} mm")
ax.axvline(d.section.h, color="0.5", ls=":", label="paper design's h")
ax.set_xlabel("lumen offset h [mm]")
ax.set_ylabel("κ/p [1/(mm·MPa)] (paper's formula, cap load)")
ax.legend()
fig.tight_layout()
