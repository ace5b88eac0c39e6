"""softcath's mechanics of the tip: section models, finite strain, the coil, and the 3-D FEM.

Subpackages, from fastest to fullest:

- :mod:`~softcath.fem.section_model`: the 2-D section model (linear, ~13 ms a design)
  and its finite-strain counterpart (:mod:`~softcath.fem.section_model.finite_strain`);
- :mod:`~softcath.fem.coil`: the helical coil's own mechanics;
- :mod:`~softcath.fem.mesh`: gmsh and TetWild meshes of the as-assembled tip, cached on disk;
- the 3-D FEM bending check (this package's :func:`check`: linear P2 elasticity with
  homogenised coils, verified against closed forms) and its finite-strain counterpart
  (:mod:`~softcath.fem.nonlinear`);
- :mod:`~softcath.fem.hyperelastic`: the finite-strain material laws both finite-strain models share.

>>> from softcath import fem
>>> r = fem.check("paper", pressures=[0.05], loads=("cap",))   # doctest: +SKIP
>>> r.case("cap", 0.05).curvature_per_mm                        # doctest: +SKIP

Heavy dependencies (scikit-fem, gmsh, pytetwild, pyvista, cadquery) are
imported inside the functions that need them.
"""

from __future__ import annotations

from softcath.fem.api import FemCase, FemResult, check
from softcath.fem.pipeline import LOADS

__all__ = ["FemCase", "FemResult", "LOADS", "check"]

if __name__ != "softcath.fem":  # the bare folder name would load a second copy of every module
    raise ImportError("import softcath.fem, not fem: the top-level folders are rooms of the softcath package")
