"""The FEM bending check: mesh (cached), assemble, factorise once, solve the
load cases at unit pressure, scale to every pressure, post-process.

``run_tip`` works on a :class:`softcath.fem.geometry.TipGeometry` and a map region ->
elastic law; :func:`fem.check` (in ``softcath.fem.api``) adds the design adapter and
the analytic comparison.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from softcath.design.errors import DesignError
from softcath.design.load_cases import LOADS
from softcath.fem.elasticity import ElasticProblem
from softcath.fem.geometry import FILLER, TUBE, TipGeometry
from softcath.fem.interfaces3d import split_mesh, tied_problem
from softcath.fem.lumen_load import pressure_facets
from softcath.fem.mesh import TipMesh, mesh_tip
from softcath.fem.neutral_axis import axial_modulus, neutral_axis_y
from softcath.fem.post import BendingFit, bending_fit, principal_strain_max
from softcath.fem.tags import tag_facets

__all__ = ["LOADS", "TipSolution", "run_tip", "axial_modulus"]

log = logging.getLogger(__name__)

#: ``cap``: pressure on the cap's inner face only (the paper's end-cap force);
#: ``lumen``: pressure on the lumen wall and the cap (the real load; :mod:`softcath.fem.lumen_load`).
SILICONE = (TUBE, FILLER)


@dataclass
class TipSolution:
    """Unit-pressure (1 MPa) solutions of one tip, with everything to post-process.

    Attributes
    ----------
    mesh
        The :class:`softcath.fem.mesh.TipMesh`.
    problem
        The assembled :class:`softcath.fem.elasticity.ElasticProblem` (factorised).
    unit
        Load name -> displacements (n_p2_nodes, 3) in mm per MPa.
    fits
        Load name -> :class:`softcath.fem.post.BendingFit` per MPa.
    strain_range
        Load name -> (min, max) principal strain per MPa in the silicone,
        outside the clamp zone.
    element_strain
        Load name -> max principal strain per MPa per element (for pictures).
    residual
        Largest backward error of the solves.
    mesh_seconds, assemble_seconds, solve_seconds
        Wall times (mesh time is 0 on a cache hit; see ``mesh.cached``).
    tags
        Facet tag -> facet indices.
    """

    mesh: TipMesh
    problem: ElasticProblem
    unit: dict[str, np.ndarray]
    fits: dict[str, BendingFit]
    strain_range: dict[str, tuple[float, float]]
    element_strain: dict[str, np.ndarray]
    residual: float
    mesh_seconds: float
    assemble_seconds: float
    solve_seconds: float
    tags: dict[str, np.ndarray] = field(default_factory=dict)

    def max_strain(self, load: str, pressure_MPa: float) -> float:
        """Largest principal strain in the silicone at ``pressure_MPa`` (linear)."""
        lo, hi = self.strain_range[load]
        return float(pressure_MPa * (hi if pressure_MPa >= 0 else lo))


def run_tip(
    geometry: TipGeometry,
    laws: Mapping[int, object],
    *,
    loads: Sequence[str] = LOADS,
    mesh_size: float = 0.1,
    mesher: str = "gmsh",
    axial_ratio: float = 5.0,
    margin: float | None = None,
    use_cache: bool = True,
    method: str | None = None,
    progress=None,
    assembly=None,
) -> TipSolution:
    """Mesh, assemble, factorise once and solve every load case at 1 MPa.

    Parameters
    ----------
    geometry
        The tip (mm).
    laws
        Region label (``softcath.fem.geometry``) -> law (``softcath.fem.materials``).
    loads
        Subset of :data:`LOADS`.
    mesh_size, mesher, axial_ratio, use_cache
        Passed to :func:`softcath.fem.mesh.mesh_tip`.
    margin
        Length (mm) next to clamp and cap left out of the curvature fit;
        default one outer diameter (where the section is not yet free to warp).
    method
        Linear solver back-end (``softcath.fem.solver``).
    progress
        Optional callable ``progress(stage: str)`` for a status line.
    assembly
        As-built options (``softcath.design.assembly.Assembly``); a non-default one
        splits the regions at their interfaces and ties them
        (``softcath.fem.interfaces3d``).
    """
    loads = _checked_loads(loads)
    say = progress or (lambda stage: None)
    say("meshing")
    as_built = assembly is not None and not assembly.is_default
    mesh, mesh_seconds = _tip_mesh(geometry, mesh_size, mesher, axial_ratio, use_cache, as_built)
    say("assembling")
    t1 = time.perf_counter()
    problem, rhs, tags = _assemble_problem(
        mesh, geometry, laws, loads, assembly if as_built else None, method
    )
    assemble_seconds = time.perf_counter() - t1
    say("solving")
    t2 = time.perf_counter()
    unit, residual = _solve_unit_loads(problem, rhs, loads)
    solve_seconds = time.perf_counter() - t2
    say("post-processing")
    if margin is None:
        margin = 2.0 * geometry.coil_outer_radius
    fits, srange, estrain = _fit_loads(problem, mesh, laws, geometry, unit, loads=loads, margin=margin)
    log.info(
        "fem: %d dofs, mesh %.1f s, assemble %.1f s, solve %.1f s, backward error %.1e",
        problem.ndofs,
        mesh_seconds,
        assemble_seconds,
        solve_seconds,
        residual,
    )
    return TipSolution(
        mesh=mesh,
        problem=problem,
        unit=unit,
        fits=fits,
        strain_range=srange,
        element_strain=estrain,
        residual=residual,
        mesh_seconds=mesh_seconds,
        assemble_seconds=assemble_seconds,
        solve_seconds=solve_seconds,
        tags=tags,
    )


def _checked_loads(loads: Sequence[str]) -> tuple[str, ...]:
    """``loads`` as a tuple; :class:`DesignError` unless a non-empty subset of :data:`LOADS`."""
    loads = tuple(loads)
    bad = [ld for ld in loads if ld not in LOADS]
    if bad or not loads:
        raise DesignError("load", bad or loads, f"must be a non-empty subset of {LOADS}")
    return loads


def _tip_mesh(
    geometry: TipGeometry, mesh_size: float, mesher: str, axial_ratio: float, use_cache: bool, as_built: bool
) -> tuple[TipMesh, float]:
    """The tip's mesh (split at the interfaces when ``as_built``) and its meshing time (0 if cached)."""
    t0 = time.perf_counter()
    mesh = mesh_tip(
        geometry, mesh_size=mesh_size, mesher=mesher, axial_ratio=axial_ratio, use_cache=use_cache
    )
    mesh_seconds = 0.0 if mesh.cached else time.perf_counter() - t0
    if as_built:
        mesh = split_mesh(mesh)
    return mesh, mesh_seconds


def _assemble_problem(
    mesh: TipMesh,
    geometry: TipGeometry,
    laws: Mapping[int, object],
    loads: tuple[str, ...],
    assembly,
    method: str | None,
):
    """The elastic problem (tied at the interfaces when an as-built ``assembly`` is given), its
    right-hand side per load and the facet tags."""
    sk = mesh.skfem_mesh()
    tags = tag_facets(sk, geometry)
    if tags["cap"].size == 0 or tags["base"].size == 0:
        raise DesignError("mesh", mesh.key, "no cap or base facets found; the geometry is broken")
    present = {k: v for k, v in laws.items() if (mesh.labels == k).any()}
    if assembly is not None:
        problem = tied_problem(sk, mesh.labels, laws, tags, assembly, geometry, method=method)
    else:
        problem = ElasticProblem(sk, mesh.labels, present, [(tags["base"], (0, 1, 2))], method=method)
    rhs = {}
    for ld in loads:
        rhs[ld] = problem.pressure_load(pressure_facets(tags, ld))
    return problem, rhs, tags


def _solve_unit_loads(problem, rhs: dict, loads: tuple[str, ...]) -> tuple[dict, float]:
    """Factorise once and solve each load: the unit displacements and the largest backward error."""
    problem.factorize()
    unit, residual = {}, 0.0
    for ld in loads:
        sol = problem.solve(rhs[ld])
        unit[ld] = sol.u
        residual = max(residual, sol.residual)
    return unit, residual


def _fit_loads(
    problem,
    mesh: TipMesh,
    laws: Mapping[int, object],
    g: TipGeometry,
    unit: dict,
    *,
    loads: tuple[str, ...],
    margin: float,
) -> tuple[dict, dict, dict]:
    """Per load: the bending fit, the silicone strain range and the element strains."""
    ybar = neutral_axis_y(mesh, laws)
    fits, srange, estrain = {}, {}, {}
    for ld in loads:
        fits[ld] = bending_fit(
            problem.nodes,
            unit[ld],
            length=g.length,
            margin=margin,
            end_z=g.length,
            neutral_axis_y=ybar,
        )
        srange[ld], estrain[ld] = _silicone_strain(problem, mesh, unit[ld], margin)
    return fits, srange, estrain


def _silicone_strain(problem: ElasticProblem, mesh: TipMesh, u: np.ndarray, margin: float):
    """(min, max) principal strain per MPa in silicone away from the clamp; per-element max."""
    from skfem import CellBasis

    basis = CellBasis(problem.mesh, problem.element, intorder=2)
    grads = np.stack([basis.interpolate(u[:, c]).grad for c in range(3)])  # (3, 3, e, q)
    eps = 0.5 * (grads + np.swapaxes(grads, 0, 1))
    flat = np.moveaxis(eps.reshape(3, 3, -1), -1, 0)
    eig = np.linalg.eigvalsh(flat).reshape(grads.shape[2], grads.shape[3], 3)
    emax = eig[..., -1].max(axis=1)
    emin = eig[..., 0].min(axis=1)
    zc = mesh.points[mesh.tets].mean(axis=1)[:, 2]
    # The rigid clamp makes a singular corner the glued-in real tip does not have:
    # the silicone strain is read outside one margin from the base.
    sel = np.isin(mesh.labels, SILICONE) & (zc > margin)
    if not sel.any():
        return (0.0, 0.0), principal_strain_max(grads).max(axis=1)
    return (float(emin[sel].min()), float(emax[sel].max())), emax
