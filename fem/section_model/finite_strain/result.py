"""The finite-strain section model's result: a design's response over increasing pressures."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, replace

import numpy as np

from softcath.core.response import TipResponse, tip_curvature
from softcath.fem.section_model.finite_strain.discretisation import Discretisation
from softcath.fem.section_model.finite_strain.newton import State

__all__ = ["CSV_COLUMNS", "SectionCurve"]


#: Columns of ``section.csv`` (the ``analytic.csv`` columns first).
CSV_COLUMNS = (
    "pressure_MPa",
    "curvature_per_mm",
    "elongation",
    "bend_angle_rad",
    "tip_x_mm",
    "tip_y_mm",
    "bend_rate_per_mm",
    "lumen_area_mm2",
    "lumen_volume_change_mm3",
    "max_strain",
    "newton_iterations",
    "residual",
)


@dataclass(frozen=True)
class SectionCurve:
    """The finite-strain section model's record of a design at increasing pressures (arrays over pressure).

    :meth:`to_response` gives the tiers' one result type, :class:`~softcath.core.response.TipResponse`.

    Attributes
    ----------
    pressure
        Lumen pressure [MPa].
    curvature_per_mm
        Curvature of the axial-stiffness centroid fibre [1/mm] (positive toward the channel).
    lateral_curvature_per_mm
        The same across the plane of symmetry (zero for a symmetric section).
    bend_rate_per_mm
        Section turn per unit undeformed length, lambda k_2 [rad/mm].
    elongation
        Axial strain of the centroid fibre, lambda (1 + k . x) - 1.
    bend_angle_rad, tip_x_mm, tip_y_mm
        The tip's angle and position (paper eq. 9 frame): the mid-span arc with the end zones
        (:mod:`softcath.fem.section_model.end_zones`).
    lumen_area_mm2
        Deformed lumen area.
    lumen_volume_change_mm3
        Volume the syringe adds to the lumen over the bending length.
    max_strain
        Largest principal (Biot) strain in the silicones.
    newton_iterations
        Newton iterations spent reaching each pressure from the previous one.
    residual
        Relative residual of each converged state.
    linear_curvature_per_mm_per_MPa
        The small-load slope dkappa/dp (the linear section model's gain on the same laws), or
        None when not asked for (``linear_gain=False``).
    tube_prestretch
        The as-built tube's axial stretch from its stress-free state (1: none).
    tube_squeeze
        The share of the squeeze from the catalogue annulus the tube's stress-free state
        carries (0: none; module ``squeeze``).
    rest_curvature_per_mm, rest_elongation
        Curvature and elongation of the centroid fibre at 0 MPa: zero unless the tube is
        pre-stretched or squeezed. ``curvature_per_mm`` and ``elongation`` include them
        (absolute, from the straight as-built section).
    interface_slip_per_element
        The tip as built: largest in-plane tangential slip at a sliding interface divided by
        the median interface edge length, per pressure (the normal tie is imposed in the
        reference configuration, valid while this stays well below 1); None for the bonded tip.
    """

    design_name: str
    load: str
    pressure: np.ndarray
    curvature_per_mm: np.ndarray
    lateral_curvature_per_mm: np.ndarray
    bend_rate_per_mm: np.ndarray
    elongation: np.ndarray
    bend_angle_rad: np.ndarray
    tip_x_mm: np.ndarray
    tip_y_mm: np.ndarray
    lumen_area_mm2: np.ndarray
    lumen_volume_change_mm3: np.ndarray
    max_strain: np.ndarray
    newton_iterations: np.ndarray
    residual: np.ndarray
    linear_curvature_per_mm_per_MPa: float | None
    length_mm: float
    lumen_area_rest_mm2: float
    dofs: int
    n_triangles: int
    mesh_size_mm: float
    poisson_ratio_silicone: float
    hoop_cap: float | None
    seconds: float
    mesh_seconds: float
    interface_slip_per_element: np.ndarray | None = None
    state: tuple[Discretisation | None, list[State]] | None = field(default=None, repr=False, compare=False)
    tube_prestretch: float = 1.0
    tube_squeeze: float = 0.0
    rest_curvature_per_mm: float = 0.0
    rest_elongation: float = 0.0

    def rows(self) -> list[dict[str, float]]:
        """One dict per pressure with the :data:`CSV_COLUMNS` keys."""
        cols = {
            "pressure_MPa": self.pressure,
            "curvature_per_mm": self.curvature_per_mm,
            "elongation": self.elongation,
            "bend_angle_rad": self.bend_angle_rad,
            "tip_x_mm": self.tip_x_mm,
            "tip_y_mm": self.tip_y_mm,
            "bend_rate_per_mm": self.bend_rate_per_mm,
            "lumen_area_mm2": self.lumen_area_mm2,
            "lumen_volume_change_mm3": self.lumen_volume_change_mm3,
            "max_strain": self.max_strain,
            "newton_iterations": self.newton_iterations,
            "residual": self.residual,
        }
        return [{k: float(v[i]) for k, v in cols.items()} for i in range(self.pressure.size)]

    def to_json(self) -> dict:
        """Plain-JSON summary (``section.json`` with ``"nonlinear": true``)."""
        d = asdict(replace(self, state=None))
        del d["state"]
        for k, v in d.items():
            if isinstance(v, np.ndarray):
                d[k] = v.tolist()
        d["nonlinear"] = True
        return d

    def to_response(
        self, *, tier: str = "section-nonlinear", warnings: tuple[str, ...] = (), parameters=None
    ) -> TipResponse:
        """This curve as a :class:`~softcath.core.response.TipResponse`: the ``section-nonlinear`` answer.

        The tip-level curvature is the uniform arc's bend angle over the stretched bending length
        (:func:`~softcath.core.response.tip_curvature`); the bend rate, lumen area, Newton
        iterations and residual go to ``extras``.

        Parameters
        ----------
        tier
            The tier's name in the response.
        warnings, parameters
            The response's validity warnings and the parameters used (default: the design's
            name and bending length, the mesh size).
        """
        used = {
            "design": self.design_name,
            "bending_length_mm": self.length_mm,
            "mesh_size": self.mesh_size_mm,
        }
        return TipResponse(
            tier=tier,
            load=self.load,
            pressures=self.pressure,
            curvature_per_mm=self.curvature_per_mm,
            tip_curvature_per_mm=tip_curvature(self.bend_angle_rad, self.elongation, self.length_mm),
            elongation=self.elongation,
            bend_angle_rad=self.bend_angle_rad,
            tip_x_mm=self.tip_x_mm,
            tip_y_mm=self.tip_y_mm,
            lumen_volume_change_mm3=self.lumen_volume_change_mm3,
            max_strain=self.max_strain,
            warnings=tuple(warnings),
            parameters=used if parameters is None else dict(parameters),
            seconds=self.seconds,
            extras={
                "bend_rate_per_mm": self.bend_rate_per_mm,
                "lumen_area_mm2": self.lumen_area_mm2,
                "newton_iterations": self.newton_iterations,
                "residual": self.residual,
            },
        )

    def pressure_for_angle(self, angle_rad: float) -> float:
        """Pressure [MPa] at which the uniform-arc bend reaches ``angle_rad`` (linear
        interpolation between computed pressures), or NaN if the curve stops short."""
        keep = self.pressure > 0
        a = np.concatenate([[0.0], self.bend_angle_rad[keep]])
        p = np.concatenate([[0.0], self.pressure[keep]])
        if not np.all(np.diff(a) > 0) or not (0.0 <= angle_rad <= a[-1]):
            return float("nan")
        return float(np.interp(angle_rad, a, p))
