"""Solve the section operator: condensed beam stiffness and the pressure loads.

One sparse factorisation of the in-plane block serves every right-hand side:
the three unit global strains (which give the condensed 3x3 section stiffness
by static condensation) and the unit lumen pressure.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import splu

from softcath.design.errors import DesignError
from softcath.design.load_cases import LOADS
from softcath.fem.section_model.element import SectionOperator

__all__ = ["LOADS", "LoadSolution", "SectionSolution", "solve"]


@dataclass(frozen=True)
class LoadSolution:
    """Response to 1 MPa of one load case.

    ``strains`` = (eps_0, k_1, k_2) per MPa; ``U`` the in-plane field (mm/MPa)
    on the operator's full CCR basis (bubbles restored); ``lumen_area_change`` in mm^2/MPa.
    """

    strains: np.ndarray
    U: np.ndarray
    lumen_area_change: float


@dataclass(frozen=True)
class SectionSolution:
    """Condensed stiffness and unit-pressure responses of one section.

    Attributes
    ----------
    stiffness
        3x3 condensed section stiffness: (N, M_1, M_2) = K (eps_0, k_1, k_2),
        N and N mm; in-plane deformation free.
    loads
        Load name -> :class:`LoadSolution`.
    backward_error
        Largest normwise backward error of the in-plane solves.
    """

    stiffness: np.ndarray
    loads: dict[str, LoadSolution]
    backward_error: float


def solve(op: SectionOperator, loads=LOADS, *, extra_bending: float = 0.0) -> SectionSolution:
    """Condense the section and solve each load at 1 MPa.

    Parameters
    ----------
    op
        The assembled operator.
    loads
        Subset of :data:`LOADS`.
    extra_bending
        Pure bending stiffness (N mm^2) added to both bending axes, e.g. the part
        of a coil's helical-spring EI that its homogenised annulus does not carry.
    """
    loads = tuple(loads)
    bad = [ld for ld in loads if ld not in LOADS]
    if bad or not loads:
        raise DesignError("load", bad or loads, f"must be a non-empty subset of {LOADS}")
    n = op.K_uu.shape[0]
    free = np.setdiff1d(np.arange(n), op.pinned)
    kff = op.K_uu[free][:, free].tocsc()
    # SPD: symmetric mode without pivoting keeps MMD's fill (3x faster than default splu).
    lu = splu(kff, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    rhs = np.column_stack([op.K_ug[free], op.f_lumen[free]])
    sol = lu.solve(rhs)
    resid = kff @ sol - rhs
    scale = abs(kff).sum(axis=1).A.ravel().max() * np.abs(sol).max(axis=0) + np.abs(rhs).max(axis=0)
    backward = float((np.abs(resid).max(axis=0) / np.where(scale > 0, scale, 1.0)).max())
    x_g, x_p = sol[:, :3], sol[:, 3]
    k_sec = op.K_gg - op.K_ug[free].T @ x_g
    k_sec = 0.5 * (k_sec + k_sec.T)
    k_sec[1, 1] += extra_bending
    k_sec[2, 2] += extra_bending
    xl, yl = op.lumen_centroid
    cap = op.lumen_area * np.array([1.0, xl, yl])
    out = {}
    for ld in loads:
        f_g = cap.copy()
        u_p = np.zeros(n)
        if ld == "lumen":
            # The wall pressure reaches the global strains through the coupling block.
            f_g -= op.K_ug[free].T @ x_p
            u_p[free] = x_p
        g = np.linalg.solve(k_sec, f_g)
        u = u_p.copy()
        u[free] -= x_g @ g
        out[ld] = LoadSolution(strains=g, U=op.full_field(u, g), lumen_area_change=float(op.f_lumen @ u))
    return SectionSolution(stiffness=k_sec, loads=out, backward_error=backward)
