"""Errors the FEM check raises."""

from __future__ import annotations

from softcath.design.errors import SoftcathError

__all__ = ["FemError", "MeshError", "SolverError"]


class FemError(SoftcathError):
    """A FEM check that cannot give a trustworthy answer."""


class MeshError(FemError):
    """A mesh that fails its checks (inverted elements, region volume off the CAD)."""


class SolverError(FemError):
    """A linear solve whose residual is above tolerance (the result is refused)."""
