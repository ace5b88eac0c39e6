"""Geometrically nonlinear (finite-strain) FEM of the catheter tip.

Total-Lagrangian P2 tetrahedra, compressible Yeoh / neo-Hookean silicone,
a transversely isotropic Saint Venant–Kirchhoff coil, follower pressure
(Nanson) with its load stiffness, Newton with load stepping, line search
and cutback, and an optional mixed u–p (P2–P0) formulation.

>>> from softcath.fem.nonlinear import bend_curve          # doctest: +SKIP
>>> c = bend_curve(design.preset("paper"), [0.5, 1.0])   # doctest: +SKIP

Heavy imports (scikit-fem, gmsh, pyvista, matplotlib) happen inside functions. The material
laws it shares with the finite-strain section model are in :mod:`softcath.fem.hyperelastic`.
"""

from __future__ import annotations

from softcath.fem.nonlinear.bend import NonlinearFemCurve, bend_curve
from softcath.fem.nonlinear.errors import ConvergenceError, NonlinearError
from softcath.fem.nonlinear.outputs import NonlinearSettings, run_check
from softcath.fem.nonlinear.reference import reference_curve
from softcath.fem.nonlinear.study import convergence_study

__all__ = [
    "ConvergenceError",
    "NonlinearError",
    "NonlinearFemCurve",
    "NonlinearSettings",
    "bend_curve",
    "convergence_study",
    "reference_curve",
    "run_check",
]
