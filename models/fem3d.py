"""The ``fem`` tier: the 3-D linear FEM of the tip (``softcath.fem.check``), design by design.

Minutes a design. What :func:`softcath.fem.check` returns is read by :func:`fem_records`
(the sweep reads stored FEM results the same way); the run's size and timing go to the
response's ``extras``.
"""

from __future__ import annotations

import dataclasses
import math
import time
from typing import Any

import numpy as np

from softcath.core.interrupts import raise_pending_stop
from softcath.fem import check
from softcath.models.tier import LOADS, Tier
from softcath.models.validity import LINEAR_BEND_LIMIT_DEG

__all__ = ["FEM", "FEM_KEYS", "FemTier", "fem_check_function", "fem_records"]

#: The keys of a FEM result (``fem.json``) a response carries, per (load, pressure).
FEM_KEYS = (
    "curvature_per_mm",
    "elongation",
    "bend_angle_rad",
    "tip_x_mm",
    "tip_y_mm",
    "curvature_variation",
    "max_strain",
    "residual",
    "n_elements",
    "dofs",
    "mesh_seconds",
    "solve_seconds",
    "discretisation_error_estimate",
)

_CONTAINERS = ("cases", "results", "rows", "records")


def _as_mapping(obj: Any) -> dict | None:
    if isinstance(obj, dict):
        return obj
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}
    return None


def fem_records(result: Any, load: str | None = None, defaults: dict | None = None) -> dict:
    """Normalise what ``fem.check`` returns to ``{(load, pressure_MPa): {fem.json key: float}}``.

    Accepted forms (the FEM package's result keys follow ``fem.json``): one
    record whose fields are scalars or arrays over the (load, pressure) cases
    — flat, or shaped (n_loads, n_pressures) with ``load`` and
    ``pressure_MPa`` listing the axes; a sequence of such records; a record
    holding them under ``cases``/``results``/``rows``/``records`` (its own
    run-level numbers, e.g. ``dofs``, ``mesh_seconds``, apply to every case);
    or a mapping from load name to records.
    """
    out: dict = {}
    defaults = dict(defaults or {})
    if isinstance(result, (list, tuple)):
        for r in result:
            out.update(fem_records(r, load, defaults))
        return out
    m = _as_mapping(result)
    if m is None:
        raise TypeError(f"cannot read a FEM result of type {type(result).__name__}")
    run_level = {
        k: m[k] for k in FEM_KEYS if isinstance(m.get(k), (int, float)) and not isinstance(m[k], bool)
    }
    for key in _CONTAINERS:
        if isinstance(m.get(key), (list, tuple)) and "curvature_per_mm" not in m:
            return fem_records(m[key], load, {**defaults, **run_level})
    if "curvature_per_mm" not in m:
        for k, v in m.items():
            if k in ("cap", "lumen"):
                out.update(fem_records(v, k, {**defaults, **run_level}))
        if not out:
            raise KeyError("FEM result has no curvature_per_mm")
        return out
    loads_ = np.atleast_1d(np.asarray(m.get("load", load), dtype=object)).ravel()
    ps = np.atleast_1d(np.asarray(m["pressure_MPa"], dtype=float)).ravel()
    kappa = np.asarray(m["curvature_per_mm"], dtype=float)
    square = kappa.ndim == 2 and kappa.shape == (len(loads_), len(ps))
    product = len(loads_) != len(ps) and kappa.size == len(loads_) * len(ps) > max(len(loads_), len(ps))
    if square or product:
        loads_, ps = np.repeat(loads_, len(ps)), np.tile(ps, len(loads_))  # (n_loads, n_pressures) grid
    n = max(len(loads_), len(ps))
    loads_ = np.resize(loads_, n)
    ps = np.resize(ps, n)
    for i in range(n):
        row = {}
        for k in FEM_KEYS:
            v = m.get(k, defaults.get(k))
            if v is None or isinstance(v, (dict, str)):
                row[k] = math.nan
                continue
            a = np.atleast_1d(np.asarray(v, dtype=float)).ravel()
            row[k] = float(a[i] if a.size == n else a[0])
        out[(str(loads_[i]), round(float(ps[i]), 12))] = row
    return out


#: FEM record key -> response field (the other keys are extras).
_FIELDS = {
    "curvature_per_mm": "curvature_per_mm",
    "elongation": "elongation",
    "bend_angle_rad": "bend_angle_rad",
    "tip_x_mm": "tip_x_mm",
    "tip_y_mm": "tip_y_mm",
    "max_strain": "max_strain",
}


def fem_check_function():
    """``fem.check``, the 3-D linear FEM check."""
    return check


class FemTier(Tier):
    """The 3-D linear FEM.

    Its tip-level curvature is the end section's rotation over L (the FEM's own second
    estimate); extras: ``curvature_variation``, ``residual``, ``n_elements``, ``dofs``,
    ``mesh_seconds``, ``solve_seconds`` (the sweep's ``fem_*`` columns) and
    ``discretisation_error_estimate`` (the curvature's, relative; ``softcath.fem.discretisation``;
    NaN unless the option ``error_estimate`` is true).
    """

    def available(self) -> bool:
        return fem_check_function() is not None

    def record(self, design, pressures, *, loads=LOADS, options=None):
        """The 3-D FEM's own result of one design (``fem.check``: the cases, the solution for
        pictures), solved with this tier's ``options`` as its responses are.

        Raises
        ------
        DesignError
            A load or option the tier does not take.
        ImportError
            ``fem.check`` is not available in this build.
        """
        for load in loads:
            self.check_load(load)
        check = fem_check_function()
        if check is None:
            raise ImportError("softcath.fem.check is unavailable")
        p = np.atleast_1d(np.asarray(pressures, dtype=float))
        # the tier's default, not fem.check's: no companion solve unless asked for
        opts = {"error_estimate": self.options["error_estimate"], **self.check_options(options)}
        return check(design, pressures=list(p), loads=tuple(loads), **opts)

    def _solve(self, designs, pressures, loads, options):

        n, n_p = len(designs), pressures.size
        rows = {ld: {k: np.full((n, n_p), np.nan) for k in FEM_KEYS} for ld in loads}
        tip = {ld: np.full((n, n_p), np.nan) for ld in loads}
        seconds = np.full(n, np.nan)
        errors: dict[int, Exception] = {}
        for i, d in enumerate(designs):
            t0 = time.perf_counter()
            try:
                result = self.record(d, pressures, loads=loads, options=options)
                records = fem_records(result)
                rotation = {  # the end section's rotation over L: the FEM's own tip-level curvature
                    (c.load, round(float(c.pressure_MPa), 12)): c.curvature_rotation_per_mm
                    for c in getattr(result, "cases", ())
                    if hasattr(c, "curvature_rotation_per_mm")
                }
                for ld in loads:
                    for j, p in enumerate(pressures):
                        row = records.get((ld, round(float(p), 12)))
                        if row is None:
                            raise LookupError(f"fem returned no result for load {ld} at {p:g} MPa")
                        for k in FEM_KEYS:
                            rows[ld][k][i, j] = row[k]
                        tip[ld][i, j] = rotation.get((ld, round(float(p), 12)), np.nan)
            except Exception as exc:  # a FEM failure is this design's error, never the batch's
                raise_pending_stop()
                errors[i] = exc
                for ld in loads:
                    tip[ld][i] = np.nan
                    for k in FEM_KEYS:
                        rows[ld][k][i] = np.nan
            seconds[i] = time.perf_counter() - t0
        return {
            ld: self._batch(
                designs,
                pressures,
                ld,
                {**{f: rows[ld][k] for k, f in _FIELDS.items()}, "tip_curvature_per_mm": tip[ld]},
                seconds=seconds,
                options=options,
                extras={k: v for k, v in rows[ld].items() if k not in _FIELDS},
                errors=errors,
            )
            for ld in loads
        }


#: The 3-D linear FEM.
FEM = FemTier(
    "fem",
    "the 3-D FEM",
    "3-D linear FEM",
    "3-D linear FEM of the tip: minutes a design",
    "fem",
    # error_estimate: the companion solve that states the curvature's discretisation error costs
    # ~50 % more a design; sweeps' rows do not carry it, so the tier asks for it only when told
    # (`softcath fem` states it by default)
    options={
        "mesh_size": 0.16,
        "mesher": "gmsh",
        "axial_ratio": 5.0,
        "coil_modulus": "tension",
        "error_estimate": False,
    },
    valid_to_deg=LINEAR_BEND_LIMIT_DEG,
    as_built=True,
    range_notes={
        "poisson_ratio": "the 3-D FEM caps Poisson ratios at 0.49 (displacement-only P2 locks above)"
    },
    seconds_per_design=120.0,
    finite_strain_tier="fem-nonlinear",
)
