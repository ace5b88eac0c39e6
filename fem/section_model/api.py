"""The section model's public API: gains, section stiffness and tip pose of a design.

>>> from softcath.fem.section_model import section_model
>>> r = section_model("paper")
>>> round(r.curvature_per_mm_per_MPa["lumen"], 3)   # the 3-D FEM gives 0.233 at nu = 0.49
0.234
>>> round(r.fem_formula_ratio["lumen"], 2)          # the paper's formula misses 3.1x
3.09
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field

import numpy as np

from softcath import design as design_pkg
from softcath.analytic import gains, response_from_gains
from softcath.design.errors import DesignError
from softcath.fem.adapter import geometry_from_design
from softcath.fem.geometry import TUBE
from softcath.fem.section_model.as_built import as_built_operator, summary
from softcath.fem.section_model.coil_models import coil_terms
from softcath.fem.section_model.element import assemble
from softcath.fem.section_model.end_zones import EndZones, end_zones, tip_pose
from softcath.fem.section_model.laws import section_laws_from_design
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS, catheter_section_mesh
from softcath.fem.section_model.solve import LOADS, solve

__all__ = ["SectionResult", "section_model", "section_response", "COIL_BENDING"]

#: ``annulus``: the coils bend as their homogenised annuli (the 3-D FEM's assumption);
#: ``wahl``: each coil additionally carries the rest of its helical-spring (Wahl)
#: bending stiffness, as the paper's formula assumes; ``resolved``: the coil's EA and
#: open-coil EI of the resolved wire (``softcath.fem.section_model.coil_models``).
COIL_BENDING = ("annulus", "wahl", "resolved")


@dataclass(frozen=True)
class SectionResult:
    """Section-model results of one design (per MPa; linear in pressure).

    Attributes
    ----------
    curvature_per_mm_per_MPa, elongation_per_MPa, lumen_area_change_mm2_per_MPa
        Load name -> kappa/p (positive toward the channel), eps/p at the
        stiffness-weighted centroid (the 3-D FEM's elongation) and dA_lumen/p.
    fem_formula_ratio
        Load name -> kappa over the paper's formula (eq. 7, cap load).
    EA_N, EI_N_mm2, EI_lateral_N_mm2, coupling_N_mm
        Condensed section stiffness with free in-plane deformation: axial, bending
        about the neutral axis (in the plane of the lumen offset and across it),
        and the axial-bending coupling about the origin (coil centre).
    neutral_axis_mm
        y where an axial force causes no curvature (coupling / EA).
    axial_centroid_mm
        E_z-weighted centroid y (paper eq. 5 on the mesh).
    stiffness
        The 3x3 matrix (N, M_x, M_y) per (eps_0, k_1, k_2) about the origin (as built:
        every axial group stretching alike; ``EI_N_mm2`` then lets each group stretch
        freely, the bending stiffness of the tip under a pure moment).
    assembly, axial_groups
        The as-built options used and the number of axial groups (1 when bonded).
    end_zones
        The tip's :class:`~softcath.fem.section_model.end_zones.EndZones` (clamp and cap),
        which :meth:`response` turns the mid-span bend into the tip's angle and pose with;
        None: the uniform arc over the whole length.
    """

    design_name: str
    loads: tuple[str, ...]
    curvature_per_mm_per_MPa: dict[str, float]
    elongation_per_MPa: dict[str, float]
    lumen_area_change_mm2_per_MPa: dict[str, float]
    fem_formula_ratio: dict[str, float]
    EA_N: float
    EI_N_mm2: float
    EI_lateral_N_mm2: float
    coupling_N_mm: float
    neutral_axis_mm: float
    axial_centroid_mm: float
    lumen_area_mm2: float
    lumen_centroid_y_mm: float
    stiffness: tuple[tuple[float, ...], ...]
    poisson_ratio_silicone: float
    coil_modulus: str
    coil_bending: str
    length_mm: float
    mesh_size_mm: float
    segments: int
    dofs: int
    n_triangles: int
    mesh_seconds: float
    seconds: float
    backward_error: float
    fields: object = field(default=None, repr=False, compare=False)
    assembly: dict | None = None
    axial_groups: int = 1
    end_zones: EndZones | None = None

    def gains(self, load: str) -> tuple[float, float]:
        """(kappa/p [1/(mm MPa)], eps/p [1/MPa]) for ``load``."""
        self._check(load)
        return self.curvature_per_mm_per_MPa[load], self.elongation_per_MPa[load]

    def response(self, pressure, load: str = "lumen"):
        """Curvature, elongation and the tip's pose at ``pressure`` [MPa]: an ``analytic.BeamResponse``.

        ``curvature`` and ``elongation`` are the uniform mid-span bend's; ``bend_angle``,
        ``tip_x`` and ``tip_y`` are the tip's, the mid-span arc with the clamp and cap end
        zones (:func:`~softcath.fem.section_model.end_zones.tip_pose`; eq. 9's uniform arc
        when ``end_zones`` is None).
        """
        from dataclasses import replace

        k, e = self.gains(load)
        r = response_from_gains(k, e, self.length_mm, pressure)
        if self.end_zones is None:
            return r
        x, y, theta = tip_pose(r.curvature, r.elongation, self.end_zones)
        return replace(r, bend_angle=theta, tip_x=x, tip_y=y)

    def to_json(self) -> dict:
        """Plain-JSON summary (``section.json`` keys; no fields)."""
        d = {k: v for k, v in asdict(self).items() if k != "fields"}
        d["stiffness"] = [list(r) for r in self.stiffness]
        d["end_zones"] = None if self.end_zones is None else self.end_zones.to_json()
        return d

    def _check(self, load: str) -> None:
        if load not in self.loads:
            raise DesignError("load", load, f"must be one of {self.loads} (computed)")


def section_model(
    design,
    *,
    loads: Sequence[str] = LOADS,
    mesh_size: float = MESH_SIZE,
    segments: int = SEGMENTS,
    mesher: str = "template",
    coil_modulus: str = "tension",
    coil_bending: str = "annulus",
    poisson_cap: float | None = None,
    silicone_poisson: float | None = None,
    poisson: bool = True,
    keep_fields: bool = False,
) -> SectionResult:
    """Solve the 2-D section model of a design.

    Parameters
    ----------
    design
        A :class:`design.TipDesign`, a preset name or a TOML path. Its ``assembly``
        (sliding interfaces, the filler as built, the base) is honoured
        (``softcath.fem.section_model.as_built``); the default bonded tip takes
        the original path unchanged.
    loads
        Subset of ``("cap", "lumen")``.
    mesh_size, segments
        Element size (mm) and boundary points per full turn.
    mesher
        ``template`` (default: the section topology's gmsh mesh morphed to the design,
        within 0.2 % of a fresh mesh) or ``gmsh`` (a fresh mesh per design).
    coil_modulus
        Coils' homogenised axial modulus, ``"tension"`` (default, as the 3-D FEM)
        or ``"bending"``.
    coil_bending
        One of :data:`COIL_BENDING`; ``resolved`` sets the coils' axial moduli
        itself and needs ``coil_modulus="tension"``.
    poisson_cap, silicone_poisson, poisson
        Poisson-ratio options (``softcath.fem.section_model.laws.section_laws_from_design``).
    keep_fields
        Keep the mesh, operator and displacement fields (for pictures).
    """

    _check_coil_options(coil_bending, coil_modulus)
    d = design_pkg.resolve(design)
    t0 = time.perf_counter()
    geometry = geometry_from_design(d)
    laws = section_laws_from_design(
        d,
        coil_modulus=coil_modulus,
        poisson_cap=poisson_cap,
        silicone_poisson=silicone_poisson,
        poisson=poisson,
    )
    laws, extra = coil_terms(d, coil_bending, laws)
    mesh = catheter_section_mesh(geometry, mesh_size=mesh_size, segments=segments, mesher=mesher)
    solved = _solve_section(d, mesh, laws, loads, sum(extra.values()))
    return _section_result(
        d,
        solved,
        nu_used=laws[TUBE].poisson_ratio,
        coil_modulus=coil_modulus,
        coil_bending=coil_bending,
        mesh_size=mesh_size,
        segments=segments,
        t0=t0,
        keep_fields=keep_fields,
    )


def _check_coil_options(coil_bending: str, coil_modulus: str) -> None:
    """Raise :class:`DesignError` for an unknown coil bending model or an incompatible coil modulus."""
    if coil_bending not in COIL_BENDING:
        raise DesignError("coil_bending", coil_bending, f"must be one of {COIL_BENDING}")
    if coil_bending == "resolved" and coil_modulus != "tension":
        raise DesignError("coil_modulus", coil_modulus, "must be 'tension' with coil_bending='resolved'")


@dataclass(frozen=True)
class _SolvedSection:
    """A solved section: mesh, operator, solution and the stiffness, curvatures and elongations read off
    it."""

    mesh: object
    op: object
    sol: object
    K: np.ndarray
    ei: float
    ei_lat: float
    kappa: dict
    eps: dict


def _solve_section(d, mesh, laws, loads: Sequence[str], extra_bending: float) -> _SolvedSection:
    """Assemble and solve the section (bonded tip, or the tip as built when its assembly is not the
    default)."""

    if d.assembly.is_default:
        op = assemble(mesh, laws)
        sol = solve(op, loads, extra_bending=extra_bending)
        K = sol.stiffness
        ei, ei_lat = float(K[2, 2] - K[0, 2] ** 2 / K[0, 0]), float(K[1, 1] - K[0, 1] ** 2 / K[0, 0])
        kappa = {ld: float(s.strains[2]) for ld, s in sol.loads.items()}
        eps = {ld: float(s.strains[0] + s.strains[2] * op.axial_centroid_y) for ld, s in sol.loads.items()}
    else:  # the tip as built (softcath.fem.section_model.as_built)
        mesh, op, sol = as_built_operator(mesh, laws, d.assembly, loads, extra_bending=extra_bending)
        sm = summary(op, sol)
        K, ei, ei_lat, kappa, eps = (
            sm["stiffness"],
            sm["EI"],
            sm["EI_lateral"],
            sm["curvature"],
            sm["elongation"],
        )
    return _SolvedSection(mesh=mesh, op=op, sol=sol, K=K, ei=ei, ei_lat=ei_lat, kappa=kappa, eps=eps)


def _section_result(
    d,
    solved: _SolvedSection,
    *,
    nu_used,
    coil_modulus: str,
    coil_bending: str,
    mesh_size: float,
    segments: int,
    t0: float,
    keep_fields: bool,
) -> SectionResult:
    """The :class:`SectionResult` of a solved section, with the gains relative to the paper's formula."""

    mesh, op, sol, K, kappa = solved.mesh, solved.op, solved.sol, solved.K, solved.kappa
    ea = float(K[0, 0])
    formula_k, _ = gains(d, "cap")
    d_area, ratio = {}, {}
    for ld, s in sol.loads.items():
        d_area[ld] = s.lumen_area_change
        ratio[ld] = float(kappa[ld] / formula_k) if formula_k != 0 else math.nan
    return SectionResult(
        design_name=d.name,
        loads=tuple(sol.loads),
        curvature_per_mm_per_MPa=kappa,
        elongation_per_MPa=solved.eps,
        lumen_area_change_mm2_per_MPa=d_area,
        fem_formula_ratio=ratio,
        EA_N=ea,
        EI_N_mm2=solved.ei,
        EI_lateral_N_mm2=solved.ei_lat,
        coupling_N_mm=float(K[0, 2]),
        neutral_axis_mm=float(K[0, 2] / ea),
        axial_centroid_mm=float(op.axial_centroid_y),
        lumen_area_mm2=float(op.lumen_area),
        lumen_centroid_y_mm=float(op.lumen_centroid[1]),
        stiffness=tuple(tuple(float(v) for v in row) for row in K),
        poisson_ratio_silicone=nu_used,
        coil_modulus=coil_modulus,
        coil_bending=coil_bending,
        length_mm=float(d.tip.bending_length),
        mesh_size_mm=float(mesh_size),
        segments=int(segments),
        dofs=int(op.ndofs),
        n_triangles=int(mesh.triangles.shape[0]),
        mesh_seconds=float(mesh.seconds),
        seconds=float(time.perf_counter() - t0),
        backward_error=sol.backward_error,
        fields=(mesh, op, sol) if keep_fields else None,
        assembly=d.assembly.to_dict(),
        axial_groups=1 if d.assembly.is_default else sol.plan.n_groups,
        end_zones=end_zones(d),
    )


def section_response(design, pressure, *, load: str = "lumen", **options):
    """Curvature, elongation and tip pose of ``design`` at ``pressure`` [MPa] from the section model.

    The section model's counterpart of ``analytic.response`` (an
    ``analytic.BeamResponse``); ``options`` go to :func:`section_model`.
    """
    return section_model(design, loads=(load,), **options).response(pressure, load)
