"""Three-mesh convergence study of the linear 3-D check in its mesh size: :func:`mesh_study`.

The same design, load and pressures on mesh sizes h·r, h and h/r (r =
:data:`~softcath.fem.discretisation.COMPANION_RATIO`, h the check's size): the observed
order of convergence of the curvature in 1/h, its Richardson extrapolation to h -> 0, each
mesh's relative distance from it, and the middle mesh's result with its error stated from
the coarse one (the observed order when it lies in
:data:`~softcath.fem.nonlinear.study.TRUSTED_ORDER`, else the assumed one). The files are
the finite-strain study's (:func:`~softcath.fem.nonlinear.study.write_study_files`):
``softcath fem DESIGN --convergence`` writes them.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from softcath.design import resolve
from softcath.design.errors import DesignError
from softcath.fem.api import FemResult, check
from softcath.fem.discretisation import ASSUMED_ORDER, COMPANION_RATIO, MAX_MESH_SIZE, estimate_from
from softcath.fem.errors import FemError
from softcath.fem.limits import check_fem_budget
from softcath.fem.nonlinear.convergence import extrapolate, observed_order
from softcath.fem.nonlinear.study import TRUSTED_ORDER

__all__ = ["MeshStudy", "mesh_study", "MESH_STUDY_COLUMNS"]

#: Columns of the linear check's ``convergence.csv`` (one row per mesh and pressure).
MESH_STUDY_COLUMNS = (
    "load",
    "pressure_MPa",
    "mesh_size_mm",
    "ndofs",
    "seconds",
    "curvature_per_mm",
    "observed_order",
    "extrapolated_curvature_per_mm",
    "relative_error_vs_extrapolated",
)


@dataclass(frozen=True)
class MeshStudy:
    """The linear check on three mesh sizes, coarse to fine (arrays: mesh × pressure).

    Attributes
    ----------
    load
        The load case.
    pressure
        Pressures [MPa].
    mesh_size, ndofs, seconds
        Per mesh: size [mm], DOFs and wall time of the check [s].
    unit_curvature
        Per mesh: curvature per MPa [1/mm/MPa].
    result
        The middle mesh's :class:`~softcath.fem.api.FemResult`, its error stated from the coarse
        mesh (the other two meshes' solutions are not kept).
    """

    load: str
    pressure: np.ndarray
    mesh_size: tuple[float, float, float]
    ndofs: tuple[int, int, int]
    seconds: tuple[float, float, float]
    unit_curvature: np.ndarray
    result: FemResult

    @property
    def observed_order(self) -> float:
        """Observed order of convergence of the curvature in 1/h (NaN if not monotone)."""
        return observed_order(self.unit_curvature, [1 / h for h in self.mesh_size])

    @property
    def order(self) -> np.ndarray:
        """:attr:`observed_order` per pressure (one value: the answer is linear in pressure)."""
        return np.full(self.pressure.size, self.observed_order)

    @property
    def values(self) -> np.ndarray:
        """Curvature per mesh and pressure [1/mm]."""
        return np.outer(self.unit_curvature, self.pressure)

    @property
    def extrapolated(self) -> np.ndarray:
        """Richardson's extrapolation (observed order) per pressure [1/mm]; NaN without an order."""
        k = extrapolate(self.unit_curvature, [1 / h for h in self.mesh_size], self.observed_order)
        return k * self.pressure

    @property
    def relative_error(self) -> np.ndarray:
        """|κ − κ_extrapolated| / |κ_extrapolated| per mesh and pressure."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.abs(self.values - self.extrapolated) / np.abs(self.extrapolated)

    #: Axis labels of the shared picture (:func:`~softcath.fem.nonlinear.study.plot_study`).
    value_label = "curvature [1/mm]"
    spacing_label = "mesh size h [mm]"

    @property
    def mesh_labels(self) -> tuple[str, ...]:
        """Legend label of each mesh."""
        return tuple(f"h = {h:g} mm" for h in self.mesh_size)

    @property
    def spacing(self) -> np.ndarray:
        """Each mesh's size h [mm] (the picture's abscissa)."""
        return np.asarray(self.mesh_size, float)

    def rows(self) -> list[dict]:
        """``convergence.csv`` rows (:data:`MESH_STUDY_COLUMNS`)."""
        rel, ext, k = self.relative_error, self.extrapolated, self.values
        return [
            {
                "load": self.load,
                "pressure_MPa": float(p),
                "mesh_size_mm": self.mesh_size[m],
                "ndofs": self.ndofs[m],
                "seconds": self.seconds[m],
                "curvature_per_mm": float(k[m, j]),
                "observed_order": self.observed_order,
                "extrapolated_curvature_per_mm": float(ext[j]),
                "relative_error_vs_extrapolated": float(rel[m, j]),
            }
            for j, p in enumerate(self.pressure)
            for m in range(3)
        ]

    def to_json(self) -> dict:
        """A JSON-ready dict (NaN as null)."""
        return {
            "quantity": "curvature_per_mm",
            "load": self.load,
            "pressure_MPa": [float(x) for x in self.pressure],
            "mesh_size_mm": list(self.mesh_size),
            "ndofs": list(self.ndofs),
            "seconds": list(self.seconds),
            "curvature_per_mm": _clean(self.values),
            "observed_order": _none(self.observed_order),
            "extrapolated_curvature_per_mm": _clean(self.extrapolated)[0],
            "relative_error_vs_extrapolated": _clean(self.relative_error),
            "method": "three meshes h*r, h, h/r (r = mesh size ratio); observed order q from "
            "(f1 - f2)/(f2 - f3) = (h1^q - h2^q)/(h2^q - h3^q); Richardson extrapolation from the two "
            "finest with q; the linear answer is proportional to pressure, so one order and one "
            "relative error hold at every pressure",
        }


def _none(x) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def _clean(a) -> list[list[float | None]]:
    return [[_none(x) for x in row] for row in np.atleast_2d(a)]


def study_mesh_sizes(mesh_size: float, ratio: float = COMPANION_RATIO) -> tuple[float, float, float]:
    """The study's mesh sizes around ``mesh_size`` [mm]: (h·r, h, h/r)."""
    return (mesh_size * ratio, mesh_size, mesh_size / ratio)


def mesh_study(design, pressures, *, load: str = "lumen", mesh_size: float = 0.16, **options) -> MeshStudy:
    """Run the linear check of ``design`` at ``pressures`` under ``load`` on three mesh sizes.

    Parameters
    ----------
    design, pressures
        As :func:`~softcath.fem.api.check`.
    load
        One load case (``"lumen"`` or ``"cap"``).
    mesh_size
        The middle mesh's size h [mm]; the others are h·r and h/r
        (:func:`study_mesh_sizes`; h·r at most the tip's radius and 0.5 mm).
    **options
        Further keywords of :func:`~softcath.fem.api.check` (``mesher``, ``axial_ratio``,
        ``coil_modulus``, ``use_cache``, ``method``, ``progress``).
    """
    sizes = study_mesh_sizes(mesh_size)
    d = resolve(design)
    largest = min(MAX_MESH_SIZE, d.coil.outer_diameter / 2)  # check_fem_budget's bound
    if not sizes[0] <= largest:
        raise DesignError(
            "mesh_size",
            mesh_size,
            f"must be <= {largest / COMPANION_RATIO:g} mm for a three-mesh study "
            f"(its coarse mesh, {COMPANION_RATIO:g} x, must resolve the section: <= {largest:g} mm)",
        )
    # the finest mesh is the costly one: refused before any solve, not after two
    check_fem_budget(d, mesh_size=sizes[-1], axial_ratio=options.get("axial_ratio", 5.0), param="mesh_size")
    results, seconds, unit = [], [], []
    for h in sizes:
        t0 = time.perf_counter()
        r = check(d, pressures=pressures, loads=(load,), mesh_size=h, error_estimate=False, **options)
        seconds.append(time.perf_counter() - t0)
        if r.solution is None:
            raise FemError("the FEM check kept no solution to read the unit curvature from")
        unit.append(float(r.solution.fits[load].curvature_per_mm))
        results.append(r if h == mesh_size else replace(r, solution=None))  # frees the factors
    k = np.array(unit)
    q = observed_order(k, [1 / h for h in sizes])
    trusted = math.isfinite(q) and TRUSTED_ORDER[0] <= q <= TRUSTED_ORDER[1]
    estimate = estimate_from(
        {load: k[1]},
        {load: k[0]},
        mesh_size=sizes[1],
        companion_mesh_size=sizes[0],
        order=q if trusted else ASSUMED_ORDER,
        order_source="observed" if trusted else "assumed",
        companion_dofs=results[0].dofs,
        companion_seconds=seconds[0],
    )
    return MeshStudy(
        load=load,
        pressure=np.array([c.pressure_MPa for c in results[1].cases], float),
        mesh_size=sizes,
        ndofs=tuple(r.dofs for r in results),
        seconds=tuple(seconds),
        unit_curvature=k,
        result=results[1].with_estimate(estimate),
    )
