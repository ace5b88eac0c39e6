"""
The tip at a few pressures
==========================

The tip bends into a circular arc of curvature κ and length L(1 + ε) from its clamped base; the
paper's eq. 9 gives its end, the tip position. Under the lumen load the linear section model
(dashed) and the finite-strain section model (solid) give κ and ε at each pressure: they part as
the bend grows.
"""

import matplotlib.pyplot as plt
import numpy as np

from softcath import design
from softcath.fem.section_model import section_response
from softcath.fem.section_model.finite_strain import section_curve

d = design.preset("paper")
pressures = np.array([0.0, 0.2, 0.4, 0.6, 0.8])
linear = section_response(d, pressures, load="lumen")
large = section_curve(d, pressures, load="lumen", linear_gain=False)
length = d.tip.bending_length


def arc(kappa, arc_length):
    """Points of the arc from the clamped base (origin, along +y), bending toward +x (eq. 9's frame)."""
    s = np.linspace(0.0, float(arc_length), 100)
    x = s * (kappa * s / 2) * np.sinc(kappa * s / (2 * np.pi)) ** 2  # (1 - cos κs)/κ, also at κ = 0
    y = s * np.sinc(kappa * s / np.pi)  # sin(κs)/κ
    return x, y


fig, ax = plt.subplots(figsize=(6, 5))
for i, p in enumerate(pressures):
    color = f"C{i}"
    ax.plot(*arc(linear.curvature[i], linear.arc_length[i]), "--", color=color)
    x, y = arc(large.curvature_per_mm[i], length * (1 + large.elongation[i]))
    ax.plot(x, y, color=color, label=f"{p:.1f} MPa")
    ax.plot([large.tip_x_mm[i]], [large.tip_y_mm[i]], "o", color=color)
ax.set_aspect("equal")
ax.set_xlabel("x [mm] (deflection, toward the channel)")
ax.set_ylabel("y [mm] (along the undeformed tip)")
ax.set_title("paper design, lumen load")
ax.legend(loc="lower right")
fig.tight_layout()
