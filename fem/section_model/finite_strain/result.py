"""The finite-strain section model's result: a design's response over increasing pressures."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, replace

import numpy as np

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
    """Finite-strain response of a design at increasing pressures (arrays over pressure).

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
        Uniform arc over the stretched bending length (paper eq. 9 frame).
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
    state: object = field(default=None, repr=False, compare=False)

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

    def pressure_for_angle(self, angle_rad: float) -> float:
        """Pressure [MPa] at which the uniform-arc bend reaches ``angle_rad`` (linear
        interpolation between computed pressures), or NaN if the curve stops short."""
        keep = self.pressure > 0
        a = np.concatenate([[0.0], self.bend_angle_rad[keep]])
        p = np.concatenate([[0.0], self.pressure[keep]])
        if not np.all(np.diff(a) > 0) or not (0.0 <= angle_rad <= a[-1]):
            return float("nan")
        return float(np.interp(angle_rad, a, p))
