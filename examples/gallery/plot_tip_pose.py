"""
The tip at a few pressures
==========================

The tip bends into a circular arc of curvature κ and length L(1 + ε) from its clamped base. The
section model under the lumen load gives κ and ε at each pressure; the arc follows from them (the
paper's eq. 9 gives its end, the tip position).
"""

import matplotlib.pyplot as plt
import numpy as np

from softcath import design
from softcath.fem.section_model import section_response

d = design.preset("paper")
pressures = np.array([0.0, 0.1, 0.2, 0.3, 0.4])
r = section_response(d, pressures, load="lumen")

fig, ax = plt.subplots(figsize=(5, 5))
for p, k, length, x_tip, y_tip in zip(pressures, r.curvature, r.arc_length, r.tip_x, r.tip_y, strict=True):
    s = np.linspace(0.0, float(length), 100)
    if abs(k) < 1e-12:
        x, y = s, np.zeros_like(s)
    else:
        x, y = np.sin(k * s) / k, (1 - np.cos(k * s)) / k
    (line,) = ax.plot(x, y, label=f"{p:.1f} MPa")
    ax.plot([x_tip], [y_tip], "o", color=line.get_color())
ax.set_aspect("equal")
ax.set_xlabel("x [mm] (along the undeformed tip)")
ax.set_ylabel("y [mm] (toward the channel)")
ax.set_title("paper design, section model, lumen load")
ax.legend()
fig.tight_layout()
