"""
Curvature against pressure: the paper's formula and the section model
======================================================================

The paper's composite-beam formula (eq. 7) loads the tip with the end-cap force alone. The 2-D
section model solves the cross-section as the 3-D FEM would, under the cap force and under the real
load (pressure on the lumen wall too); the finite-strain section model follows the lumen load into
large bends.
"""

import matplotlib.pyplot as plt
import numpy as np

from softcath import analytic, design
from softcath.fem.section_model import section_response
from softcath.fem.section_model.finite_strain import section_curve

d = design.preset("paper")
p = np.linspace(0.0, 0.6, 13)

formula = analytic.response(d, p, load="cap")
section_cap = section_response(d, p, load="cap")
section_lumen = section_response(d, p, load="lumen")
large = section_curve(d, [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6], load="lumen", linear_gain=False)

fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(p, formula.curvature, "k--", label="paper's formula (cap load)")
ax.plot(p, section_cap.curvature, label="section model, cap load")
ax.plot(p, section_lumen.curvature, label="section model, lumen load")
ax.plot(large.pressure, large.curvature_per_mm, "o-", label="finite-strain section model, lumen load")
ax.set_xlabel("pressure p [MPa]")
ax.set_ylabel("curvature κ [1/mm]")
ax.set_title("paper design")
ax.legend()
fig.tight_layout()
