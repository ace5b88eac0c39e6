"""The linear 3-D check's discretisation error: a companion solve, and the three-mesh study.

The linear check's mesh size h sets the section's triangles and the element layers along the
tip (``axial_ratio × h`` thick, rounded up to whole layers). Its curvature (per MPa: the
answer is proportional to pressure, so one relative error holds at every pressure) converges
with h:

- :func:`companion_estimate` solves the tip again on ``COMPANION_RATIO × h`` (a cheaper mesh)
  and states the first solve's relative error by Richardson with the order
  :data:`ASSUMED_ORDER`;
- :func:`softcath.fem.mesh_study.mesh_study` solves it on h·r, h and h/r, observes the order
  and extrapolates (``softcath fem DESIGN --convergence``).

The Richardson arithmetic is the finite-strain FEM's
(:func:`~softcath.fem.nonlinear.convergence.richardson_error`, ``observed_order``,
``extrapolate``), fed with 1/h where it takes element layers (a resolution ∝ 1/h).

Measured on the paper design at 0.1 MPa (docs/fem.md): from h = 0.32 (3 layers) to 0.16 (6)
to 0.08 mm (12) the lumen-load curvature moved 1.38 % then 0.29 % (observed order 2.2), the
cap-load curvature 1.6 % then 0.001 % (below the ~0.02 % scatter of the curvature fit between
meshes). Order 4, observed on the cap load from h = 0.36, 0.24, 0.16, was the cap's
pre-asymptotic decay (0.36 and 0.32 mm give the same 3-layer mesh) and understated the lumen
error threefold; order 2 bounds both loads' measured errors.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

from softcath.design.errors import DesignError
from softcath.fem.nonlinear.convergence import extrapolate
from softcath.fem.pipeline import TipSolution

__all__ = [
    "ASSUMED_ORDER",
    "COMPANION_RATIO",
    "MAX_MESH_SIZE",
    "DiscretisationEstimate",
    "companion_mesh_size",
    "companion_estimate",
    "estimate_from",
]

#: Order of convergence in 1/h assumed for the companion estimate (see the module notes).
ASSUMED_ORDER = 2.0
#: Companion mesh size / the check's mesh size: 2 halves the layers (paper design at 0.16 mm:
#: 33k instead of 59k DOFs, ~4 s more on a 6-9 s check).
COMPANION_RATIO = 2.0
#: Largest mesh size the mesher takes [mm] (``softcath.fem.mesh.mesh_tip``).
MAX_MESH_SIZE = 0.5


def companion_mesh_size(mesh_size: float, *, largest: float = MAX_MESH_SIZE) -> float:
    """The companion solve's mesh size [mm]: ``COMPANION_RATIO × mesh_size``, or that much finer
    when the coarser one would exceed ``largest`` (the tip's radius or :data:`MAX_MESH_SIZE`,
    the largest size the check resolves; a finer companion costs more, it still states the error).
    """
    if not (math.isfinite(mesh_size) and 0 < mesh_size <= largest):
        raise DesignError("mesh_size", mesh_size, f"must be in (0, {largest:g}] mm")
    coarse = COMPANION_RATIO * mesh_size
    return coarse if coarse <= largest else mesh_size / COMPANION_RATIO


@dataclass(frozen=True)
class DiscretisationEstimate:
    """The linear check's curvature error from two meshes, per load (the same at every pressure).

    Attributes
    ----------
    mesh_size_mm, companion_mesh_size_mm
        The check's mesh size and the second mesh's [mm].
    order
        Order of convergence in 1/h used.
    order_source
        ``"assumed"`` (:data:`ASSUMED_ORDER`) or ``"observed"`` (three-mesh study).
    unit_curvature, companion_unit_curvature
        Load -> curvature per MPa on the two meshes [1/mm/MPa].
    companion_dofs, companion_seconds
        The second solve's size and wall time [s] (mesh, assembly, solve, fit).
    """

    mesh_size_mm: float
    companion_mesh_size_mm: float
    order: float
    order_source: str
    unit_curvature: dict[str, float]
    companion_unit_curvature: dict[str, float]
    companion_dofs: int
    companion_seconds: float

    def _pair(self, load: str) -> tuple[list[float], list[float]]:
        """(values, resolutions 1/h) of ``load``, coarse mesh first."""
        k, kc = self.unit_curvature[load], self.companion_unit_curvature[load]
        h, hc = self.mesh_size_mm, self.companion_mesh_size_mm
        return ([kc, k], [1 / hc, 1 / h]) if hc > h else ([k, kc], [1 / h, 1 / hc])

    def extrapolated(self, load: str) -> float:
        """Richardson's extrapolation of ``load``'s curvature per MPa to h -> 0 [1/mm/MPa]."""
        values, resolution = self._pair(load)
        return extrapolate(values, resolution, self.order)

    def relative(self, load: str) -> float:
        """|κ − κ_extrapolated| / |κ| of the check's mesh under ``load`` (NaN when κ is 0)."""
        k, ext = self.unit_curvature[load], self.extrapolated(load)
        rel = abs(k - ext) / abs(k) if k != 0 else math.nan
        return rel if math.isfinite(rel) else math.nan

    @property
    def method(self) -> str:
        """One line saying how the estimate was made."""
        h, h2 = self.mesh_size_mm, self.companion_mesh_size_mm
        formula = (
            "|k_h - k_h2| / ((h2/h)^order - 1) / |k_h|, a coarser second mesh"
            if h2 > h
            else "|k_h - k_h2| (h/h2)^order / ((h/h2)^order - 1) / |k_h|, a finer second mesh"
        )
        return (
            f"Richardson from a second solve at mesh size {h2:g} mm beside {h:g} mm, order "
            f"{self.order:.3g} in 1/h ({self.order_source}): {formula}; the linear answer is "
            "proportional to pressure, so the relative error holds at every pressure"
        )

    def to_json(self, load: str, pressure_MPa: float) -> dict:
        """``fem.json``'s ``discretisation_error`` for ``load`` at ``pressure_MPa`` (NaN as null)."""
        p = float(pressure_MPa)
        return {
            "quantity": "curvature_per_mm",
            "relative": _none(self.relative(load)),
            "curvature_per_mm": _none(self.unit_curvature[load] * p),
            "companion_curvature_per_mm": _none(self.companion_unit_curvature[load] * p),
            "extrapolated_curvature_per_mm": _none(self.extrapolated(load) * p),
            "mesh_size_mm": self.mesh_size_mm,
            "companion_mesh_size_mm": self.companion_mesh_size_mm,
            "order": self.order,
            "order_source": self.order_source,
            "companion_dofs": self.companion_dofs,
            "companion_seconds": self.companion_seconds,
            "method": self.method,
        }


def _none(x: float) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def estimate_from(
    unit_curvature: dict,
    companion_unit_curvature: dict,
    *,
    mesh_size: float,
    companion_mesh_size: float,
    order: float = ASSUMED_ORDER,
    order_source: str = "assumed",
    companion_dofs: int = 0,
    companion_seconds: float = 0.0,
) -> DiscretisationEstimate:
    """The :class:`DiscretisationEstimate` of two solves' curvatures per MPa (load -> 1/mm/MPa)
    on ``mesh_size`` and ``companion_mesh_size`` [mm], with ``order`` (``order_source`` says
    whether assumed or observed) and the second solve's size and wall time [s]."""
    if math.isclose(mesh_size, companion_mesh_size):
        raise DesignError("companion_mesh_size", companion_mesh_size, f"must differ from {mesh_size:g} mm")
    if not (math.isfinite(order) and order > 0):
        raise DesignError("order", order, "must be > 0")
    return DiscretisationEstimate(
        mesh_size_mm=float(mesh_size),
        companion_mesh_size_mm=float(companion_mesh_size),
        order=float(order),
        order_source=order_source,
        unit_curvature={ld: float(k) for ld, k in unit_curvature.items()},
        companion_unit_curvature={ld: float(companion_unit_curvature[ld]) for ld in unit_curvature},
        companion_dofs=int(companion_dofs),
        companion_seconds=float(companion_seconds),
    )


def companion_estimate(
    sol: TipSolution,
    solve: Callable[[float], TipSolution],
    *,
    mesh_size: float,
    largest: float = MAX_MESH_SIZE,
) -> DiscretisationEstimate:
    """Solve again with ``solve(companion_mesh_size(mesh_size, largest=largest))`` (a
    ``TipSolution``) and estimate the error of ``sol`` (the check's ``TipSolution``) with the
    assumed order.

    The companion solution is dropped here (its factorisation with it); only its curvatures,
    size and time are kept.
    """
    h2 = companion_mesh_size(mesh_size, largest=largest)
    t0 = time.perf_counter()
    other = solve(h2)
    seconds = time.perf_counter() - t0
    return estimate_from(
        {ld: f.curvature_per_mm for ld, f in sol.fits.items()},
        {ld: f.curvature_per_mm for ld, f in other.fits.items()},
        mesh_size=mesh_size,
        companion_mesh_size=h2,
        companion_dofs=int(other.problem.ndofs),
        companion_seconds=seconds,
    )
