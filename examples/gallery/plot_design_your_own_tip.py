"""
Design your own tip
===================

From the paper's design to a design file of your own: change the tube, let the validator
check the edit, compare the bend curves of the old and the new tip on the linear section
model and the finite-strain section model, and export the design file that
``softcath design validate``, ``softcath section`` and ``softcath fem`` take as it is.
Every curve says its tier and its load: the lumen load (pressure on the lumen wall and
the sealed cap), the real one.
"""

# %%
# Start from the paper's design
# -----------------------------
# A design is validated data in mm and MPa. Its design-file table is a plain dictionary
# (the fields, units and bounds: the design-file page of these docs).

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from softcath import design
from softcath.fem.section_model import section_model
from softcath.fem.section_model.finite_strain import section_curve

paper = design.preset("paper")
table = design.to_dict(paper)
print(table["tube"])

# %%
# Change the tube
# ---------------
# A wider lumen: the catalogue tube's inner diameter from 0.3 to 0.4 mm. The validator
# refuses an impossible edit with the field, the value and the bound, before any model
# runs; a valid one comes back as a design, with a plain statement of how the parts fit.

table["tube"]["catalogue_inner_diameter"] = 0.7  # wider than the tube itself
try:
    design.from_dict(table)
except design.DesignError as exc:
    print("refused:", exc)

table["tube"]["catalogue_inner_diameter"] = 0.4
table["name"] = "wide lumen"
mine = design.from_dict(table)
print(mine.fit_report())

# %%
# Compare the bend curves on two tiers
# ------------------------------------
# The linear section model (milliseconds per design) is valid to about 5 degrees of bend;
# past that the finite-strain section model (about a second per curve) is the answer to
# trust. Both run here under the lumen load, from 0 to 0.6 MPa.

LOAD = "lumen"
pressures = np.linspace(0.0, 0.6, 7)
curves = {}
for d in (paper, mine):
    linear = section_model(d, loads=(LOAD,)).response(pressures, LOAD)
    finite = section_curve(d, pressures[1:], load=LOAD)
    curves[d.name] = {
        "section": np.degrees(linear.bend_angle),
        "section-nonlinear": np.degrees(np.concatenate([[0.0], finite.bend_angle_rad])),
        "max_strain": finite.max_strain[-1],
    }

fig, ax = plt.subplots(figsize=(6.4, 4.2))
for (name, c), colour in zip(curves.items(), ("C0", "C1"), strict=True):
    ax.plot(pressures, c["section"], "--", color=colour, label=f"{name} (section, {LOAD} load)")
    ax.plot(
        pressures,
        c["section-nonlinear"],
        "o-",
        color=colour,
        label=f"{name} (section-nonlinear, {LOAD} load)",
    )
ax.axhline(5.0, color="0.6", lw=0.8, ls=":")
ax.annotate("linear tiers valid below ~5 deg", (0.3, 1.0), fontsize=8, color="0.4")
ax.set_xlabel("pressure [MPa]")
ax.set_ylabel("bend angle [deg]")
ax.set_title("paper design vs a wider lumen")
ax.legend(fontsize=8)
fig.tight_layout()

for name, c in curves.items():
    print(
        f"{name}: at 0.6 MPa {c['section-nonlinear'][-1]:.1f} deg (section-nonlinear, {LOAD} load), "
        f"{c['section'][-1]:.1f} deg on the linear section model; max silicone strain {c['max_strain']:.2f}"
    )

# %%
# Export the design file
# ----------------------
# ``design.save`` writes the TOML design file; it loads back as exactly the same design.
# From the command line it is then checked, drawn and re-checked in 3-D::
#
#     softcath design validate wide_lumen.toml
#     softcath section paper wide_lumen.toml --pressure 0:0.6:7 --nonlinear --out overlay
#     softcath fem wide_lumen.toml --pressure 0.1 --out fem-check

with tempfile.TemporaryDirectory() as folder:
    path = Path(folder) / "wide_lumen.toml"
    design.save(mine, path)
    assert design.load(path) == mine  # the file is the design, field for field
    text = path.read_text()
print("[tube]" + text.split("[tube]")[1].split("\n\n")[0])
