"""Bend-angle-vs-pressure curve of a design by finite-strain FEM.

:func:`bend_curve` meshes the tip (or takes a mesh), assigns the finite-strain
laws, clamps the base, pressurises the lumen with a follower load and walks
the pressures with Newton. At each requested pressure it reports the bend
angle (rotation of the tip-end section), curvature θ/s, the mid-span
curvature dθ/ds and bend rate dθ/dZ (sections in the middle of the tip,
:func:`~softcath.fem.nonlinear.post.midspan_bend`), elongation, tip pose,
and next to them the linear FEM (same mesh, small-strain tangent at zero
load, scaled with p) and the analytic model. This is the function the
studies package calls.
"""

from __future__ import annotations

import functools
import logging
import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from softcath import analytic
from softcath.core.deprecation import renamed_names
from softcath.core.response import TipResponse
from softcath.design.load_cases import LOADS
from softcath.fem.geometry import FILLER, TUBE
from softcath.fem.nonlinear.body import FollowerPressure, HyperelasticBody
from softcath.fem.nonlinear.catheter import HOOP_CAP, CatheterMesh, catheter_laws, mesh_catheter
from softcath.fem.nonlinear.convergence import default_layers
from softcath.fem.nonlinear.errors import SettingError
from softcath.fem.nonlinear.hoop_cap import linear_unit_angle
from softcath.fem.nonlinear.load_path import check_predictor, first_load_steps
from softcath.fem.nonlinear.meshes import dofs_of_facets
from softcath.fem.nonlinear.newton import NonlinearResult, solve
from softcath.fem.nonlinear.post import (
    MIDSPAN,
    bend_angles,
    curvature_variation,
    max_principal_strain,
    measured_tip_pose,
    midspan_bend,
)

__all__ = ["NonlinearFemCurve", "bend_curve", "departure_angle", "axial_modulus", "needs_mixed", "LOADS"]

log = logging.getLogger(__name__)

SILICONE_LABELS = (TUBE, FILLER)
#: Poisson ratio from which ``bend_curve`` uses the mixed u–p formulation by default.
MIXED_POISSON = 0.45


@dataclass(frozen=True)
class NonlinearFemCurve:
    """The 3-D finite-strain FEM's record of a design over pressures (arrays indexed like ``pressure``).

    :meth:`to_response` gives the tiers' one result type, :class:`~softcath.core.response.TipResponse`.

    Attributes
    ----------
    pressure
        Requested pressures [MPa], increasing.
    bend_angle
        Rotation of the tip-end section toward the channel side [rad] (nonlinear FEM).
    curvature
        θ / s [1/mm], s the arc length of a circle through the tip (clamp and cap zones included).
    curvature_mid
        Mid-span curvature dθ/ds [1/mm]: the rate of the section rotation along the
        deformed centroid line (the fibre through ``midspan_axis``) over the ``midspan`` window
        (:func:`~softcath.fem.nonlinear.post.midspan_bend`); NaN when the mesh has
        fewer than two z levels there.
    bend_rate_mid
        Mid-span bend rate dθ/dZ [rad/mm] per unit undeformed axial coordinate
        (= ``curvature_mid`` × the centroid-line stretch).
    midspan
        The mid-span window (start, end) as fractions of the bending length.
    midspan_axis
        Reference (X, Y) [mm] of the centroid line of ``curvature_mid``: the sections'
        axial-stiffness (E_z-weighted) centroid over the window.
    elongation
        s / L − 1 [-].
    tip_x, tip_y
        Tip-end centroid in the bending plane (paper eq. 9 frame) [mm].
    linear_bend_angle
        Linear FEM on the same mesh (small-strain, scaled with p) [rad].
    analytic_bend_angle
        The paper's formula (the composite beam under the cap load, as ``softcath analytic``) [rad].
    newton_iterations
        Newton iterations spent reaching each pressure (since the previous one).
    load
        ``"lumen"`` or ``"cap"``.
    ndofs, n_tets, n_nodes
        Model size (n_nodes: P2 nodes).
    max_strain
        Largest principal stretch strain λ_max − 1 in the silicone, more than two
        coil radii from the clamp (as the linear check), at each pressure [-].
    curvature_variation
        ``(max − min) / |mean|`` of the local curvature along the middle of the tip at
        each pressure (:func:`~fem.nonlinear.post.curvature_variation`).
    mesh_seconds
        Time spent meshing [s] (0 when a mesh was passed in).
    layers
        Element layers along the bending length (None when a mesh was passed in).
    layer_choice
        The :class:`~softcath.fem.nonlinear.convergence.LayerChoice` when ``layers`` was
        chosen by default, else None.
    mixed
        Whether the mixed u–p formulation was used.
    true_area
        Whether the section was meshed area-true (None when a mesh was passed in).
    result
        The full load path (every accepted step); not serialised.
    """

    pressure: np.ndarray
    bend_angle: np.ndarray
    curvature: np.ndarray
    curvature_mid: np.ndarray
    bend_rate_mid: np.ndarray
    midspan: tuple[float, float]
    midspan_axis: tuple[float, float]
    elongation: np.ndarray
    tip_x: np.ndarray
    tip_y: np.ndarray
    linear_bend_angle: np.ndarray
    analytic_bend_angle: np.ndarray
    newton_iterations: np.ndarray
    load: str
    ndofs: int
    n_tets: int
    n_nodes: int
    max_strain: np.ndarray
    curvature_variation: np.ndarray
    mesh_seconds: float
    result: NonlinearResult = field(repr=False, compare=False)
    model: object = field(repr=False, compare=False, default=None)
    layers: int | None = None
    layer_choice: object = field(repr=False, compare=False, default=None)
    mixed: bool = False
    true_area: bool | None = None

    def to_response(
        self,
        *,
        tier: str = "fem-nonlinear",
        warnings: tuple[str, ...] = (),
        parameters: Mapping[str, Any] | None = None,
        seconds: float = math.nan,
    ) -> TipResponse:
        """This curve as a :class:`~softcath.core.response.TipResponse` (the ``fem-nonlinear`` tier's answer).

        The mid-span curvature is :attr:`curvature_mid`, the tip-level curvature :attr:`curvature`
        (θ / s); the lumen volume change is not computed (NaN). The linear FEM's and the paper's
        bend angles, the Newton iterations and the curvature variation go to ``extras``.

        Parameters
        ----------
        tier
            The tier's name in the response.
        warnings, parameters, seconds
            The response's validity warnings, parameters used and wall time [s].
        """
        return TipResponse(
            tier=tier,
            load=self.load,
            pressures=self.pressure,
            curvature_per_mm=self.curvature_mid,
            tip_curvature_per_mm=self.curvature,
            elongation=self.elongation,
            bend_angle_rad=self.bend_angle,
            tip_x_mm=self.tip_x,
            tip_y_mm=self.tip_y,
            lumen_volume_change_mm3=np.full(np.shape(self.pressure), np.nan),
            max_strain=self.max_strain,
            warnings=tuple(warnings),
            parameters=dict(parameters or {}),
            seconds=float(seconds),
            extras={
                "linear_bend_angle_rad": self.linear_bend_angle,
                "analytic_bend_angle_rad": self.analytic_bend_angle,
                "newton_iterations": self.newton_iterations,
                "curvature_variation": self.curvature_variation,
            },
        )

    def departure(self, threshold: float = 0.05) -> dict[str, float | None]:
        """Bend angles [rad] at which linear FEM / analytic depart from the nonlinear curve by
        ``threshold``."""
        return {
            "linear_fem": departure_angle(self.bend_angle, self.linear_bend_angle, threshold),
            "analytic": departure_angle(self.bend_angle, self.analytic_bend_angle, threshold),
        }


def departure_angle(nonlinear: np.ndarray, other: np.ndarray, threshold: float = 0.05) -> float | None:
    """First nonlinear bend angle [rad] where |other − nonlinear| / |nonlinear| reaches ``threshold``.

    Linear interpolation between sweep points, starting from the unloaded state
    (0 rad, no deviation); ``None`` if it never departs in the sweep.
    """
    nl = np.concatenate([[0.0], np.asarray(nonlinear, float)])
    ot = np.concatenate([[0.0], np.asarray(other, float)])
    with np.errstate(divide="ignore", invalid="ignore"):
        dev = np.abs(ot - nl) / np.abs(nl)
    dev = np.where(np.abs(nl) > 0, dev, 0.0)
    idx = np.flatnonzero(dev >= threshold)
    if idx.size == 0:
        return None
    k = int(idx[0])
    t = (threshold - dev[k - 1]) / (dev[k] - dev[k - 1])
    return float(nl[k - 1] + t * (nl[k] - nl[k - 1]))


_VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))


def axial_modulus(law) -> float:
    """Small-strain Young's modulus along z of a law with ``small_strain_tensor()`` [MPa]: 1 / (ℂ⁻¹)_zzzz."""
    c = np.asarray(law.small_strain_tensor(), float)
    voigt = np.array([[c[i, j, k, m] for k, m in _VOIGT] for i, j in _VOIGT])
    return float(1.0 / np.linalg.inv(voigt)[2, 2])


class _Model:
    """Mesh + body + loads of one design, reused for the linear and nonlinear solves."""

    def __init__(
        self, design, cmesh: CatheterMesh, *, load: str, mixed: bool, hoop_cap: float | None = HOOP_CAP
    ) -> None:
        self.design = design
        self.cmesh = cmesh
        self.hoop_cap = hoop_cap
        self.body = HyperelasticBody(
            cmesh.mesh, cmesh.labels, catheter_laws(design, hoop_cap=hoop_cap), mixed=mixed
        )
        facets = cmesh.lumen_facets if load == "lumen" else cmesh.cap_facets
        self.pressure = FollowerPressure(self.body, facets)
        self.fixed = dofs_of_facets(self.body.basis, cmesh.base_facets)
        x = self.body.nodes
        self.end = np.isclose(x[:, 2], cmesh.length)
        # as the linear check: strain and curvature profile read two coil radii away from the
        # clamp (the rigid clamp's singular corner) and the cap
        self.margin = float(design.coil.outer_diameter)
        zc = x[self.body.basis.element_dofs[:4]].mean(axis=0)[:, 2]
        self._strain_cells = np.flatnonzero(np.isin(cmesh.labels, SILICONE_LABELS) & (zc > self.margin))

    def silicone_strain(self, u: np.ndarray) -> float:
        """Largest principal stretch strain in the silicone away from the clamp [-]."""
        if self._strain_cells.size == 0:
            return float("nan")
        f = self.body.deformation_gradient(u.ravel(), self._strain_cells)
        return float(max_principal_strain(f).max())

    def axial_centroid(self, window: tuple[float, float]) -> tuple[float, float]:
        """Reference (X, Y) [mm] of the sections' axial-stiffness centroid over ``window`` (fractions of L).

        The E_z-weighted mean of the quadrature points with Z in the window: the
        fibre the linear section model's elongation and the finite-strain section
        model's curvature refer to (paper eq. 5 on the mesh).
        """
        body = self.body
        moduli = {lab: axial_modulus(law) for lab, law in body.laws.items()}
        e_z = np.array([moduli[lab] for lab in body.labels.tolist()])
        x = np.asarray(body.basis.global_coordinates())  # (3, cells, points)
        z = x[2]
        length = self.cmesh.length
        w = body.weights * e_z[:, None] * ((z >= window[0] * length) & (z <= window[1] * length))
        if not w.sum() > 0:
            return (float("nan"), float("nan"))
        return (float((w * x[0]).sum() / w.sum()), float((w * x[1]).sum() / w.sum()))

    @functools.cached_property
    def linear_unit_angle(self) -> float:
        """dθ/dp [rad/MPa] of the linear FEM (tangent at zero load, unit pressure; solved once)."""
        return linear_unit_angle(self.body, self.pressure, self.fixed, self.end)


def bend_curve(
    design,
    pressures,
    *,
    load: str = "lumen",
    mesh: CatheterMesh | None = None,
    size: float = 0.15,
    layers: int | None = None,
    curvature_points: int = 12,
    midspan: tuple[float, float] = MIDSPAN,
    mixed: bool | None = None,
    substeps: int = 1,
    max_iter: int = 20,
    progress: bool = False,
    reuse_factors: bool = True,
    true_area: bool = False,
    predictor: str = "quadratic",
) -> NonlinearFemCurve:
    """Nonlinear bend curve of ``design`` at increasing ``pressures`` [MPa].

    Parameters
    ----------
    design
        A ``design.TipDesign``.
    pressures
        Increasing positive pressures [MPa]; the solve walks through them.
    load
        ``"lumen"`` (wall + cap, the real load) or ``"cap"`` (end-cap force only).
    mesh
        A ready :class:`~fem.nonlinear.catheter.CatheterMesh` (or any object with the same
        attributes, e.g. built from another mesher); default: :func:`mesh_catheter`.
    size, layers, curvature_points
        Mesh controls of :func:`mesh_catheter` [mm, count, segments per circle].
        ``layers=None`` (default) picks the element layers along the bending length from
        the bend expected at the largest pressure
        (:func:`~softcath.fem.nonlinear.convergence.default_layers`: at most 5° per layer,
        8 to 16 layers); the layers, not the section size, set the mid-span curvature's
        error (docs/nonlinear.md). 12 segments per circle under-fill the coil's area by
        ~2 % (it spans ~17 segments at size 0.15), the finer 24 costs twice the DOFs and
        Newton cutbacks.
    midspan
        Window of the mid-span curvature, (start, end) as fractions of the bending
        length (default [0.3, 0.7]: out of the clamp and cap zones; see
        :func:`~softcath.fem.nonlinear.post.midspan_bend`).
    mixed
        Use the mixed u–p (P2–P0) formulation for the silicones; ``None`` (default): when a
        silicone's Poisson ratio is at least :data:`MIXED_POISSON` (near-incompressible).
    substeps
        Equal load steps between consecutive requested pressures (≥ 1).
    max_iter
        Newton iterations per step before a cutback.
    progress
        Show a progress bar.
    reuse_factors
        Newton reuses the tangent's factors while it converges fast (default; see
        :func:`~softcath.fem.nonlinear.newton.solve`): on the paper's 12-layer curve 104
        factorisations instead of 134 and 19 % less CPU, the answer within Newton's tolerance.
        ``False`` factorises every iteration (full Newton).
    true_area
        Mesh an area-true section (:func:`~softcath.fem.nonlinear.true_area.area_true`): every
        section polygon holds its curve's area. Off by default: on eight designs it moves the
        12-segment section's error by about +2 % (paper −2.2 → −0.5 %, large-wire coils
        +0.5 → +2.8 %), no better on average than the plain inscribed polygons (docs/nonlinear.md).
    predictor
        Newton's starting guess of each load step (``newton.solve``): ``"quadratic"`` (default)
        or ``"secant"``. The first planned step is split into a ramp of at most
        :data:`~softcath.fem.nonlinear.load_path.FIRST_STEP_DEG` of linear bend for either
        (:func:`~softcath.fem.nonlinear.load_path.first_load_steps`).

    Raises
    ------
    NonlinearError
        Bad pressures/load; :class:`~fem.nonlinear.errors.ConvergenceError` if Newton fails.
    """
    p, w = _check_inputs(pressures, load, midspan, substeps)
    check_predictor(predictor)  # before the meshing
    if mixed is None:
        mixed = needs_mixed(design)
    choice, cmesh, mesh_seconds = None, mesh, 0.0
    if cmesh is None:
        if layers is None:
            choice = default_layers(design, float(p[-1]), load=load)
            layers = choice.layers
            log.info("bend curve: %d layers (%s)", layers, choice.to_json())
        t0 = time.perf_counter()
        cmesh = mesh_catheter(
            design, size=size, layers=layers, curvature_points=curvature_points, true_area=true_area
        )
        mesh_seconds = time.perf_counter() - t0
    model = _Model(design, cmesh, load=load, mixed=mixed)
    p_max = float(p[-1])
    factors = _load_factors(p, substeps)
    ramp = first_load_steps(float(factors[0]), model.linear_unit_angle * p_max)
    res = solve(
        model.body,
        fixed_dofs=model.fixed,
        loads=[(model.pressure, p_max)],
        load_factors=np.concatenate([ramp, factors]),
        max_iter=max_iter,
        progress=progress,
        reuse_factors=reuse_factors,
        predictor=predictor,
    )
    curve = _curve(design, p, w, load, cmesh, model, res=res, mesh_seconds=mesh_seconds)
    return replace(
        curve,
        layers=layers if mesh is None else None,
        layer_choice=choice,
        mixed=bool(mixed),
        true_area=bool(true_area) if mesh is None else None,
    )


def needs_mixed(design) -> bool:
    """Whether the silicones of ``design`` are near-incompressible (ν ≥ :data:`MIXED_POISSON`)."""
    silicones = [design.tube.material] + ([design.filler] if design.filler is not None else [])
    return max(float(m.poisson_ratio) for m in silicones) >= MIXED_POISSON


def _check_inputs(pressures, load, midspan, substeps) -> tuple[np.ndarray, tuple[float, ...]]:
    """Check the inputs of :func:`bend_curve`; returns the pressures and the mid-span window."""
    if load not in LOADS:
        raise SettingError("load", load, f"must be one of {LOADS}")
    p = np.atleast_1d(np.asarray(pressures, float))
    if p.ndim != 1 or p.size == 0 or not np.all(np.isfinite(p)) or np.any(p <= 0) or np.any(np.diff(p) <= 0):
        raise SettingError("pressures", p.tolist(), "must be finite, > 0 MPa and strictly increasing")
    w = tuple(float(x) for x in np.ravel(midspan))
    if len(w) != 2 or not (0.0 <= w[0] < w[1] <= 1.0):
        raise SettingError("midspan", midspan, "must be (start, end) with 0 <= start < end <= 1")
    if not (isinstance(substeps, (int, np.integer)) and substeps >= 1):
        raise SettingError("substeps", substeps, "must be an integer >= 1")
    return p, w


def _load_factors(p: np.ndarray, substeps: int):
    """Load factors: ``substeps`` equal steps between consecutive pressures, ending at 1."""
    edges = np.concatenate([[0.0], p / float(p[-1])])
    return np.concatenate([np.linspace(edges[i], edges[i + 1], substeps + 1)[1:] for i in range(p.size)])


def _curve(design, p, w, load, cmesh, model, *, res: NonlinearResult, mesh_seconds) -> NonlinearFemCurve:
    """Post-process the solved load path at the requested pressures into a :class:`NonlinearFemCurve`."""

    p_max = float(p[-1])
    lam = np.array([s.load_factor for s in res.steps])
    angles_all = bend_angles(model.body.nodes, res.displacements, model.end)
    its_all = np.array([s.iterations for s in res.steps])
    pick = np.array([int(np.argmin(np.abs(lam - f))) for f in p / p_max])
    cum = np.cumsum(its_all)[pick]
    poses = [measured_tip_pose(model.body.nodes, res.displacements[k], model.end) for k in pick]
    theta = angles_all[pick]
    length = cmesh.length
    arc = np.array([ps.arc_length_mm for ps in poses])
    with np.errstate(divide="ignore", invalid="ignore"):
        curvature = np.where(arc > 0, theta / arc, 0.0)
    axis = model.axial_centroid(w)
    mids = [
        midspan_bend(model.body.nodes, res.displacements[k], length=length, window=w, axis_point=axis)
        for k in pick
    ]
    if mids[0].stations.size < 2:
        log.info("mid-span curvature: fewer than two mesh z levels in Z/L in %s; refine layers", w)
    lin = model.linear_unit_angle * p
    # The paper's formula is the cap-load composite beam (eq. 7), whatever the FEM's load: its
    # "lumen" variant is the wall-load effect alone (50x smaller), not the paper's prediction.
    ana = analytic.response(design, p, load="cap").bend_angle
    log.info(
        "bend curve: %d pressures, %d Newton iterations, final angle %.4g rad",
        p.size,
        res.newton_iterations,
        theta[-1],
    )
    return NonlinearFemCurve(
        pressure=p,
        bend_angle=theta,
        curvature=curvature,
        curvature_mid=np.array([m.curvature for m in mids]),
        bend_rate_mid=np.array([m.bend_rate for m in mids]),
        midspan=w,
        midspan_axis=axis,
        elongation=arc / length - 1.0,
        tip_x=np.array([ps.x_mm for ps in poses]),
        tip_y=np.array([ps.y_mm for ps in poses]),
        linear_bend_angle=lin,
        analytic_bend_angle=np.asarray(ana, float),
        newton_iterations=np.diff(np.concatenate([[0], cum])),
        load=load,
        ndofs=model.body.ndofs,
        n_tets=int(cmesh.mesh.t.shape[1]),
        n_nodes=int(model.body.n_nodes),
        max_strain=np.array([model.silicone_strain(res.displacements[k]) for k in pick]),
        curvature_variation=np.array(
            [
                curvature_variation(
                    model.body.nodes, res.displacements[k], length=length, margin=model.margin
                )
                for k in pick
            ]
        ),
        mesh_seconds=float(mesh_seconds),
        result=res,
        model=model,
    )


#: The old name of the record, before every tier's record had its own.
__getattr__ = renamed_names(__name__, BendCurve=NonlinearFemCurve)
