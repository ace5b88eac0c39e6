"""From converged states to a :class:`~softcath.fem.section_model.finite_strain.SectionCurve`.

Both Newton paths (the reference discretisation and the template path) give, per
converged state, the unknowns, the deformed section's stiffness centroid and the
lumen's volume; the curve's rows and columns are made here, once, and the
progress display over the pressures is set up for both.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from softcath.fem.section_model.end_zones import end_zones, tip_angle
from softcath.fem.section_model.end_zones import tip_pose as end_zone_pose
from softcath.fem.section_model.finite_strain.result import SectionCurve

__all__ = ["CurveFacts", "curve_from_rows", "progress_callback", "rest_row", "state_row"]


@dataclass(frozen=True)
class CurveFacts:
    """What a curve reports besides its rows: the section, its laws and the cost."""

    rest_area: float
    rest_volume: float
    gain: float | None
    dofs: int
    n_triangles: int
    mesh_size: float
    tube_law: object
    hoop_cap: float | None
    t0: float
    mesh_seconds: float
    tube_prestretch: float = 1.0
    tube_squeeze: float = 0.0
    rest_curvature: float = 0.0
    rest_elongation: float = 0.0


def state_row(state, centroid: np.ndarray, volume: float, area: float, n_u: int) -> dict:
    """One converged state's row: curvature and elongation of the centroid fibre, lumen, effort."""
    lam, k1, k2 = (float(v) for v in state.q[n_u : n_u + 3])
    stretch = 1.0 + k1 * centroid[0] + k2 * centroid[1]
    return {
        "curvature": k2 / stretch,
        "lateral": k1 / stretch,
        "rate": lam * k2,
        "elongation": lam * stretch - 1.0,
        "area": float(area),
        "volume": float(volume),
        "max_strain": state.max_strain,
        "iterations": state.iterations,
        "residual": state.residual,
    }


def rest_row(area: float, volume: float) -> dict:
    """The unloaded tip's row."""
    return {
        "curvature": 0.0,
        "lateral": 0.0,
        "rate": 0.0,
        "elongation": 0.0,
        "area": float(area),
        "volume": float(volume),
        "max_strain": 0.0,
        "iterations": 0,
        "residual": 0.0,
    }


def poisson(law) -> float:
    """Small-strain Poisson ratio of an isotropic law."""
    c = law.small_strain_tensor()
    lam, mu = c[0, 0, 1, 1], c[0, 1, 0, 1]
    return float(lam / (2 * (lam + mu)))


def curve_from_rows(d, load: str, p: np.ndarray, rows: list[dict], facts: CurveFacts, state):
    """The :class:`SectionCurve` of ``rows`` (rest rows first) at the first ``len(rows)`` pressures."""

    cols = {k: np.array([r[k] for r in rows]) for k in rows[0]} if rows else {}
    k_c = cols.get("curvature", np.zeros(0))
    length = float(d.tip.bending_length)
    zones = end_zones(d)
    # the plug's tilt was fitted under the lumen load only (end_zones): the cap load keeps the deficit
    tilt_p = p[: len(rows)] if load == "lumen" else None
    tip_x, tip_y, _ = end_zone_pose(k_c, cols.get("elongation", np.zeros(0)), zones, pressure=tilt_p)
    gain = facts.gain
    return SectionCurve(
        design_name=d.name,
        load=load,
        pressure=p[: len(rows)],
        curvature_per_mm=k_c,
        lateral_curvature_per_mm=cols.get("lateral", np.zeros(0)),
        bend_rate_per_mm=cols.get("rate", np.zeros(0)),
        elongation=cols.get("elongation", np.zeros(0)),
        bend_angle_rad=tip_angle(cols.get("rate", np.zeros(0)), zones, pressure=tilt_p),
        tip_x_mm=np.asarray(tip_x, float),
        tip_y_mm=np.asarray(tip_y, float),
        lumen_area_mm2=cols.get("area", np.zeros(0)),
        lumen_volume_change_mm3=(cols.get("volume", np.zeros(0)) - facts.rest_volume) * length,
        max_strain=cols.get("max_strain", np.zeros(0)),
        newton_iterations=cols.get("iterations", np.zeros(0, int)).astype(int),
        residual=cols.get("residual", np.zeros(0)),
        linear_curvature_per_mm_per_MPa=None if gain is None else float(gain),
        length_mm=length,
        lumen_area_rest_mm2=float(facts.rest_area),
        dofs=int(facts.dofs),
        n_triangles=int(facts.n_triangles),
        mesh_size_mm=float(facts.mesh_size),
        poisson_ratio_silicone=poisson(facts.tube_law),
        hoop_cap=facts.hoop_cap,
        seconds=float(time.perf_counter() - facts.t0),
        mesh_seconds=float(facts.mesh_seconds),
        state=state,
        tube_prestretch=float(facts.tube_prestretch),
        tube_squeeze=float(facts.tube_squeeze),
        rest_curvature_per_mm=float(facts.rest_curvature),
        rest_elongation=float(facts.rest_elongation),
    )


def progress_callback(total: int, progress: bool, on_pressure: Callable[[int, int], None] | None):
    """``(on_state or None, close)``: the progress bar and the caller's callback over ``total`` pressures."""
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=total, desc="finite-strain section", unit="pressure")
    done = [0]

    def on_state(_state) -> None:
        done[0] += 1
        if bar is not None:
            bar.update(1)
        if on_pressure is not None:
            on_pressure(done[0], total)

    def close() -> None:
        if bar is not None:
            bar.close()

    return (on_state if (bar is not None or on_pressure is not None) else None), close
