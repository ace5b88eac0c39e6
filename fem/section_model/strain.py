"""Silicone strain of the section model: the largest principal strain per MPa.

The generalised-plane-strain solution has, at every point, the in-plane
strains (xx, yy, xy) of the section's displacement and the axial strain
eps_0 + k_1 x + k_2 y; there is no transverse shear (no torsion or shear
force). Its largest principal strain in the silicone regions (tube and
filler) is the mid-span counterpart of the 3-D FEM's ``max_strain`` (which
also sees the clamp and cap zones, so it can be larger).
"""

from __future__ import annotations

import numpy as np

from softcath.design.errors import DesignError
from softcath.fem.geometry import FILLER, TUBE

__all__ = ["principal_strain_range", "silicone_strain_range"]


def silicone_strain_range(result, load: str) -> tuple[float, float]:
    """(smallest, largest) principal strain per MPa in the silicone of one load case.

    The response is linear in pressure, so the largest principal strain at
    pressure p is ``p * high`` for p >= 0 and ``p * low`` for p < 0.

    Parameters
    ----------
    result
        A :class:`~fem.section_model.SectionResult` computed with ``keep_fields=True``.
    load
        A load the result holds.
    """
    if result.fields is None:
        raise DesignError("result.fields", None, "needs section_model(..., keep_fields=True)")
    result._check(load)
    mesh, op, sol = result.fields
    return principal_strain_range(op, sol.loads[load], np.isin(np.asarray(mesh.labels), (TUBE, FILLER)))


def principal_strain_range(op, load_solution, elements: np.ndarray) -> tuple[float, float]:
    """(smallest, largest) principal strain of one load solution over the chosen elements.

    Sampled at the quadrature points (peaks on a boundary are seen a fraction
    of an element inside it).

    Parameters
    ----------
    op
        The :class:`~softcath.fem.section_model.element.SectionOperator`.
    load_solution
        One load's solution (in-plane field ``U`` and global ``strains``).
    elements
        Boolean mask over the mesh's triangles.
    """
    strain = op.strain_field(load_solution.U, load_solution.strains)  # (4, nel, nq)
    exx, eyy, ezz = strain[0][elements], strain[1][elements], strain[2][elements]
    exy = 0.5 * strain[3][elements]
    if exx.size == 0:
        return 0.0, 0.0
    # In-plane principal strains (the 2x2 block) and the axial one: the 3x3 tensor is block-diagonal.
    mean, radius = 0.5 * (exx + eyy), np.sqrt((0.5 * (exx - eyy)) ** 2 + exy**2)
    high = np.maximum(mean + radius, ezz)
    low = np.minimum(mean - radius, ezz)
    return float(low.min()), float(high.max())
