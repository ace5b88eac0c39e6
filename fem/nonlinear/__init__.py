"""Geometrically nonlinear (finite-strain) FEM of the catheter tip.

Total-Lagrangian P2 tetrahedra, compressible Yeoh / neo-Hookean silicone,
a transversely isotropic Saint Venant–Kirchhoff coil, follower pressure
(Nanson) with its load stiffness, Newton with load stepping, line search
and cutback, and an optional mixed u–p (P2–P0) formulation.

>>> from softcath.fem.nonlinear import bend_curve          # doctest: +SKIP
>>> c = bend_curve(design.preset("paper"), [0.5, 1.0])   # doctest: +SKIP

Heavy imports (scikit-fem, gmsh, pyvista, matplotlib) happen inside functions.
"""

from __future__ import annotations

from softcath.fem.nonlinear.errors import ConvergenceError, NonlinearError

__all__ = [
    "ConvergenceError",
    "NonlinearError",
    "NonlinearSettings",
    "bend_curve",
    "convergence_study",
    "reference_curve",
    "run_check",
]


def bend_curve(design, pressures, **kwargs):
    """Nonlinear bend-angle-vs-pressure curve of a design (see
    :func:`softcath.fem.nonlinear.bend.bend_curve`)."""
    # lazy: the section model imports fem.nonlinear.laws, and the 3-D solvers here import it back
    from softcath.fem.nonlinear.bend import bend_curve as _bend_curve

    return _bend_curve(design, pressures, **kwargs)


def __getattr__(name: str):  # lazy: the check's writers pull in pyvista and matplotlib
    if name in ("NonlinearSettings", "run_check"):
        from softcath.fem.nonlinear import outputs

        return getattr(outputs, name)
    if name == "reference_curve":  # the bend with its discretisation error stated
        from softcath.fem.nonlinear.reference import reference_curve

        return reference_curve
    if name == "convergence_study":
        from softcath.fem.nonlinear.study import convergence_study

        return convergence_study
    raise AttributeError(name)
