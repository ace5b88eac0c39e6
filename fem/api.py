"""The public FEM check: ``fem.check(design, pressures=..., loads=...)``.

One mesh (from the cache when the same tip and settings were meshed before),
one assembly, one factorisation; each load case is solved once at 1 MPa and
scaled to every pressure (linear elasticity). A second solve on a coarser mesh states the
curvature's discretisation error (:mod:`softcath.fem.discretisation`).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, fields, replace

import numpy as np

from softcath import analytic
from softcath import design as design_pkg
from softcath.core.limits import check_pressure
from softcath.design.assembly import INTERFACES
from softcath.design.errors import DesignError
from softcath.fem.adapter import fem_laws_from_design, geometry_from_design, silicone_parameters
from softcath.fem.discretisation import MAX_MESH_SIZE, DiscretisationEstimate, companion_estimate
from softcath.fem.limits import check_fem_budget
from softcath.fem.pipeline import LOADS, TipSolution, run_tip
from softcath.fem.section_model.end_zones import end_zones, tip_pose

__all__ = ["FemCase", "FemResult", "check", "check_assembly"]


@dataclass(frozen=True)
class FemCase:
    """FEM and analytic results for one load case at one pressure (``fem.json`` keys).

    Lengths mm, curvature 1/mm, pressure MPa, angles rad, strain and
    elongation dimensionless. ``curvature_variation`` is ``(max - min)/|mean|`` of
    the local curvature along the middle of the tip. ``max_strain`` is the
    largest principal strain in the silicone outside the clamp zone.
    ``bend_angle_rad`` and the tip position are the tip's: the mid-span fit's arc with the
    end zones taken off (:mod:`softcath.fem.section_model.end_zones`), as the section tiers
    give them; ``curvature_rotation_per_mm`` is this mesh's own end rotation over the length.
    ``analytic`` holds the analytic model's ``curvature_per_mm`` and
    ``elongation`` for the same design, pressure and load model, and
    ``ratio_fem_over_analytic`` their ratios (NaN at zero pressure).
    ``discretisation_error_estimate`` is the curvature's estimated relative discretisation error
    (the load's, the same at every pressure: the answer is proportional to pressure; NaN when
    not estimated; :mod:`softcath.fem.discretisation`).
    """

    load: str
    pressure_MPa: float
    curvature_per_mm: float
    curvature_rotation_per_mm: float
    elongation: float
    bend_angle_rad: float
    tip_x_mm: float
    tip_y_mm: float
    curvature_variation: float
    max_strain: float
    analytic: dict[str, float]
    ratio_fem_over_analytic: dict[str, float]
    discretisation_error_estimate: float = math.nan


@dataclass(frozen=True)
class FemResult:
    """Result of :func:`check`: one :class:`FemCase` per (load, pressure) plus run facts.

    ``residual`` is the largest normwise backward error of the solves
    (``softcath.fem.solver``); ``mesh_seconds`` is 0 when the mesh came from the cache
    (``mesh_cached``). ``solution`` keeps the unit-pressure fields for export
    (not compared, not printed). ``silicones`` states the moduli and Poisson ratios the
    FEM used for the tube and filler next to the design's (``fem.adapter.silicone_parameters``).
    ``discretisation_error`` is how the cases' ``discretisation_error_estimate`` was made (None:
    not estimated).
    """

    cases: tuple[FemCase, ...]
    design_name: str
    mesher: str
    mesh_size_mm: float
    n_nodes: int
    n_elements: int
    dofs: int
    mesh_seconds: float
    assemble_seconds: float
    solve_seconds: float
    residual: float
    mesh_cached: bool
    mesh_quality: dict[str, float]
    volume_errors: dict[str, float]
    land_half_widths_mm: dict[str, float]
    neutral_axis_y_mm: float
    coil_modulus: str
    silicones: dict[str, dict] = field(default_factory=dict)
    discretisation_error: DiscretisationEstimate | None = None
    solution: TipSolution | None = field(default=None, repr=False, compare=False)

    def case(self, load: str, pressure_MPa: float) -> FemCase:
        """The case for ``load`` at ``pressure_MPa``."""
        for c in self.cases:
            if c.load == load and math.isclose(c.pressure_MPa, pressure_MPa, rel_tol=1e-12):
                return c
        raise DesignError("case", (load, pressure_MPa), "not computed in this result")

    def to_json(self, load: str, pressure_MPa: float) -> dict:
        """The ``fem.json`` document for one case: every field of the case and of the run."""
        c = asdict(self.case(load, pressure_MPa))
        skip = ("cases", "solution", "discretisation_error")
        run = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in skip}
        est = self.discretisation_error
        run["discretisation_error"] = (
            {"method": "not estimated (error_estimate=False)"}
            if est is None
            else est.to_json(load, pressure_MPa)
        )
        return _finite_or_none({**c, **run})

    def with_estimate(self, estimate: DiscretisationEstimate) -> FemResult:
        """This result with ``estimate`` stated: its cases' ``discretisation_error_estimate`` and
        ``discretisation_error``."""
        cases = tuple(replace(c, discretisation_error_estimate=estimate.relative(c.load)) for c in self.cases)
        return replace(self, cases=cases, discretisation_error=estimate)


def _finite_or_none(obj):
    if isinstance(obj, dict):
        return {k: _finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, float) and not math.isfinite(obj):
        return None  # JSON has no NaN
    return obj


def check(
    design,
    *,
    pressures: Sequence[float] = (0.1,),
    loads: Sequence[str] = LOADS,
    mesh_size: float = 0.16,
    mesher: str = "gmsh",
    axial_ratio: float = 5.0,
    coil_modulus: str = "tension",
    use_cache: bool = True,
    method: str | None = None,
    progress=None,
    error_estimate: bool = True,
) -> FemResult:
    """Run the FEM bending check of a design and compare with the analytic model.

    Parameters
    ----------
    design
        A :class:`design.TipDesign`, a preset name or a TOML path.
    pressures
        Pressures in MPa (finite, magnitudes at most :data:`softcath.core.limits.MAX_PRESSURE_MPA`).
    loads
        Subset of ``("cap", "lumen")``: ``cap`` loads only the cap's inner face
        (the paper's model), ``lumen`` the lumen wall and the cap (the real load).
    mesh_size
        Section element size, mm (default 0.16: for the paper design the cap
        curvature is within 0.07 % of its Richardson extrapolation, the lumen
        curvature and elongation within 0.2 % of a 0.12 mm mesh; docs/fem.md).
    mesher
        ``"gmsh"`` (default, seconds) or ``"tetwild"`` (pytetwild, minutes).
    axial_ratio
        gmsh back-end: layer thickness / mesh_size.
    coil_modulus
        ``"tension"`` or ``"bending"``: which homogenised axial modulus the coils
        get (``softcath.fem.adapter``).
    use_cache
        Reuse / store meshes in the on-disk cache.
    method
        Solver back-end (``"pardiso"`` default, ``"superlu"``).
    progress
        Optional ``progress(stage)`` callable.
    error_estimate
        Solve again on a second mesh (:func:`softcath.fem.discretisation.companion_mesh_size`:
        twice the size, or half when twice exceeds the tip's radius; at the default 0.16 mm
        4 s more for the paper design) and state the curvature's
        discretisation error (``discretisation_error_estimate``, ``discretisation_error``).
    """
    d = design_pkg.resolve(design)
    p = _checked_pressures(pressures)
    check_fem_budget(d, mesh_size=mesh_size, axial_ratio=axial_ratio, param="mesh_size")
    geometry = geometry_from_design(d)
    laws = fem_laws_from_design(d, coil_modulus=coil_modulus)
    silicones = silicone_parameters(d)
    _warn_capped_poisson(silicones)

    def solve(h: float, say=None) -> TipSolution:
        return run_tip(
            geometry,
            laws,
            loads=loads,
            mesh_size=h,
            mesher=mesher,
            axial_ratio=axial_ratio,
            use_cache=use_cache,
            method=method,
            progress=say,
            assembly=d.assembly,
        )

    sol = solve(mesh_size, progress)
    cases = []
    for ld in loads:
        cases.extend(_load_cases(d, sol, ld, p))
    result = _fem_result(
        d,
        sol,
        geometry,
        tuple(cases),
        first_load=loads[0],
        mesh_size=mesh_size,
        coil_modulus=coil_modulus,
        silicones=silicones,
    )
    if not error_estimate:
        return result
    if progress is not None:
        progress("estimating the discretisation error")
    largest = min(MAX_MESH_SIZE, d.coil.outer_diameter / 2)  # check_fem_budget's bound
    return result.with_estimate(companion_estimate(sol, solve, mesh_size=mesh_size, largest=largest))


def _fem_result(
    d,
    sol: TipSolution,
    geometry,
    cases: tuple[FemCase, ...],
    *,
    first_load: str,
    mesh_size,
    coil_modulus,
    silicones,
) -> FemResult:
    """The :class:`FemResult` of a solved tip: its cases and the mesh, solver and material facts."""
    q = sol.mesh.quality
    return FemResult(
        cases=cases,
        design_name=d.name,
        mesher=sol.mesh.mesher,
        mesh_size_mm=float(mesh_size),
        n_nodes=int(sol.problem.n_nodes),
        n_elements=int(sol.mesh.tets.shape[0]),
        dofs=int(sol.problem.ndofs),
        mesh_seconds=float(sol.mesh_seconds),
        assemble_seconds=float(sol.assemble_seconds),
        solve_seconds=float(sol.solve_seconds),
        residual=float(sol.residual),
        mesh_cached=bool(sol.mesh.cached),
        mesh_quality={k: float(v) for k, v in asdict(q).items()},
        volume_errors=sol.mesh.volume_errors(),
        land_half_widths_mm=geometry.lands(),
        neutral_axis_y_mm=float(sol.fits[first_load].neutral_axis_y),
        coil_modulus=coil_modulus,
        silicones=silicones,
        solution=sol,
    )


def _checked_pressures(pressures: Sequence[float]) -> np.ndarray:
    """``pressures`` as a flat float array; :class:`DesignError` unless one or more finite numbers
    within the pressure bound (:data:`softcath.core.limits.MAX_PRESSURE_MPA`)."""
    p = np.asarray(list(pressures), dtype=float).ravel()
    if p.size == 0 or not np.all(np.isfinite(p)):
        raise DesignError("pressure", list(p), "must be one or more finite numbers (MPa)")
    return check_pressure(p, param="pressures")


def _warn_capped_poisson(silicones: dict) -> None:
    """Warn (``softcath.validity``) for each silicone whose Poisson ratio the linear FEM caps."""
    for name, used in silicones.items():
        if used["capped"]:
            logging.getLogger("softcath.validity").warning(
                "%s silicone Poisson ratio %r is solved as %g (the linear FEM's cap; nearly "
                "incompressible silicone comes out too compliant): fem.json states both; "
                "`softcath section` takes nu up to 0.49999",
                name,
                used["poisson_ratio_design"],
                used["poisson_ratio_used"],
            )


def _load_cases(d, sol: TipSolution, ld: str, p: np.ndarray) -> list[FemCase]:
    """The :class:`FemCase` of each pressure under load ``ld``, with the analytic model alongside."""
    fit = sol.fits[ld]
    ref = analytic.response(d, p, load=ld)
    kappa = fit.curvature_per_mm * p
    eps = fit.elongation * p
    # the tip's angle and pose from the mid-span fit, as the section tiers give them (end zones off)
    tx, ty, theta = tip_pose(kappa, eps, end_zones(d))
    cases = []
    for i, pi in enumerate(p):
        a_k, a_e = float(ref.curvature[i]), float(ref.elongation[i])
        cases.append(
            FemCase(
                load=ld,
                pressure_MPa=float(pi),
                curvature_per_mm=float(kappa[i]),
                curvature_rotation_per_mm=float(fit.curvature_rotation_per_mm * pi),
                elongation=float(eps[i]),
                bend_angle_rad=float(theta[i]),
                tip_x_mm=float(tx[i]),
                tip_y_mm=float(ty[i]),
                curvature_variation=fit.curvature_variation,
                max_strain=sol.max_strain(ld, float(pi)),
                analytic={"curvature_per_mm": a_k, "elongation": a_e},
                ratio_fem_over_analytic={
                    "curvature_per_mm": _ratio(kappa[i], a_k),
                    "elongation": _ratio(eps[i], a_e),
                },
            )
        )
    return cases


def check_assembly(assembly) -> None:
    """Refuse what the finite-strain 3-D FEM does not model: it meshes the filler as built
    (full, coat, none) but fuses every interface and clamps the whole base (the linear
    check honours them all, ``softcath.fem.interfaces3d``)."""
    for key, _, _ in INTERFACES:
        if getattr(assembly, key) != "bonded":
            raise DesignError(
                f"assembly.{key}",
                getattr(assembly, key),
                "the finite-strain FEM models bonded interfaces only; "
                "the linear FEM and the section model take sliding ones",
            )
    if assembly.proximal != "clamped":
        raise DesignError(
            "assembly.proximal", assembly.proximal, "the finite-strain FEM models a clamped base only"
        )


def _ratio(a: float, b: float) -> float:
    return float(a / b) if b != 0 else float("nan")
