"""The sweep's ``section-nonlinear`` evaluator: the finite-strain section model per design.

Valid at the large bends a tip is chosen for (where the linear tiers fall
short by 20 % and more), at about a second per design and load for a handful
of pressures. Each load walks once through the sweep's positive pressures; 0 MPa
is the rest state and negative pressures (which the finite-strain walk does not
take) are NaN. A design the model cannot solve, or whose Newton walk stops
short, is reported with its reason and never stops the task.
"""

from __future__ import annotations

import time

import numpy as np

__all__ = ["SECTION_NONLINEAR_KEYS", "section_nonlinear_columns"]

#: Result columns (per design x pressure x load) and the curve field each comes from.
SECTION_NONLINEAR_KEYS = {
    "curvature_section_nonlinear_per_mm": "curvature_per_mm",
    "elongation_section_nonlinear": "elongation",
    "bend_angle_section_nonlinear_rad": "bend_angle_rad",
    "tip_x_section_nonlinear_mm": "tip_x_mm",
    "tip_y_section_nonlinear_mm": "tip_y_mm",
    "max_strain_section_nonlinear": "max_strain",
    "lumen_volume_change_section_nonlinear_mm3": "lumen_volume_change_mm3",
}


def section_nonlinear_columns(
    design, pressures: np.ndarray, loads: tuple[str, ...], options: dict | None = None
) -> dict:
    """``{load: {column: array over pressures}}`` of the finite-strain section model for one design.

    ``options`` are the ``[sweep.section]`` table's; the mesh ones (``mesh_size``,
    ``mesher``) apply. ``section_nonlinear_seconds`` is the wall time for this design and load.
    """
    from softcath.fem.section_model.finite_strain import section_curve

    opts = {k: v for k, v in (options or {}).items() if k in ("mesh_size", "mesher") and v is not None}
    p = np.asarray(pressures, float)
    walk = np.unique(p[p >= 0])
    out = {}
    for load in loads:
        t0 = time.perf_counter()
        cols = {k: np.full(p.size, np.nan) for k in SECTION_NONLINEAR_KEYS}
        if walk.size:
            c = section_curve(design, walk, load=load, linear_gain=False, **opts)
            idx = np.searchsorted(walk, p)
            ok = p >= 0
            for col, attr in SECTION_NONLINEAR_KEYS.items():
                cols[col][ok] = np.asarray(getattr(c, attr), float)[idx[ok]]
        cols["section_nonlinear_seconds"] = np.full(p.size, time.perf_counter() - t0)
        out[load] = cols
    return out
