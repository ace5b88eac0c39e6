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
    "add_cli_arguments",
    "bend_curve",
    "run_cli",
]


def bend_curve(design, pressures, **kwargs):
    """Nonlinear bend-angle-vs-pressure curve of a design (see :func:`softcath.fem.nonlinear.bend.bend_curve`)."""
    from softcath.fem.nonlinear.bend import bend_curve as _bend_curve

    return _bend_curve(design, pressures, **kwargs)


def add_cli_arguments(parser) -> None:
    """Add ``--nonlinear`` and its options to ``softcath fem`` (see :mod:`softcath.fem.nonlinear.cli`)."""
    from softcath.fem.nonlinear.cli import add_cli_arguments as _add

    _add(parser)


def run_cli(args, echo=None) -> int:
    """Run ``softcath fem --nonlinear``; ``echo`` prints the summary (see :mod:`softcath.fem.nonlinear.cli`)."""
    from softcath.fem.nonlinear.cli import run_cli as _run

    return _run(args, echo=echo)
