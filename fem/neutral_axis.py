"""The axial-stiffness-weighted centroid of the meshed tip: where the FEM reads curvature and elongation.

The linear check (:mod:`softcath.fem.pipeline`) and the as-built one
(:mod:`softcath.fem.interfaces3d`) read the bending fit about the same axis, so both take it
from here.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from softcath.fem.geometry import REGIONS
from softcath.fem.mesh import TipMesh, tet_volumes

__all__ = ["axial_modulus", "neutral_axis_y"]


def axial_modulus(law) -> float:
    """Axial (z) Young's modulus of a law (MPa)."""
    return float(getattr(law, "axial_modulus", getattr(law, "youngs_modulus", np.nan)))


def neutral_axis_y(mesh: TipMesh, laws: Mapping[int, object]) -> float:
    """Axial-stiffness-weighted centroid y of the lumen part (paper eq. 5 on the mesh), mm."""
    c = mesh.points[mesh.tets].mean(axis=1)
    body = c[:, 2] < mesh.geometry.length - mesh.geometry.cap_thickness
    v = tet_volumes(mesh.points, mesh.tets)
    e = np.array([axial_modulus(laws[k]) if k in laws else 0.0 for k in range(max(REGIONS) + 1)])
    w = e[mesh.labels] * v * body
    return float((w * c[:, 1]).sum() / w.sum())
