"""The section model's mesh size: its default and the range the section mesher accepts.

Below both the section mesher (:mod:`softcath.fem.section_model.mesh`) and the cost limits
(:mod:`softcath.fem.limits`), which check a size before estimating the work it makes.
"""

from __future__ import annotations

import math

from softcath.core.errors import DesignError

__all__ = ["MESH_SIZE", "SEGMENTS", "check_size"]

#: Default section element size (mm) and boundary points per full turn: the paper
#: section's cap and lumen curvatures are then within 0.05 % of their converged
#: values at nu = 0.4999 (tests/fem/section_model/test_convergence.py).
MESH_SIZE = 0.08
SEGMENTS = 20


def check_size(mesh_size: float, segments: int) -> None:
    """Refuse a section mesh size outside [0.005, 0.5] mm or segments outside [8, 256].

    Raises
    ------
    DesignError
        Naming ``mesh_size`` or ``segments``.
    """
    if not (math.isfinite(mesh_size) and 0.005 <= mesh_size <= 0.5):
        raise DesignError("mesh_size", mesh_size, "must be in [0.005, 0.5] mm")
    if not (8 <= int(segments) <= 256):
        raise DesignError("segments", segments, "must be in [8, 256] points per full turn")
