"""The ``section-nonlinear`` tier's evaluator: the finite-strain section model per design, as sweep columns.

The tier (:mod:`softcath.models.section_nonlinear`), the sweep and the overlays share it.

Valid at the large bends a tip is chosen for (where the linear tiers fall
short by 20 % and more), at ~50 ms of CPU per design and load for seven
pressures: :func:`~softcath.fem.section_model.finite_strain.section_curve`'s
template path (the design's template mesh morphed, compiled assembly, one
Cholesky analysis per template, templates and compiled code kept per process).
Each load walks once through the sweep's positive pressures; 0 MPa is the rest
state and negative pressures (which the finite-strain walk does not take) are
NaN. A design the model cannot solve, or whose Newton walk stops short, is
reported with its reason and never stops the task.
"""

from __future__ import annotations

import time

import numpy as np

from softcath.fem.section_model.finite_strain import section_curve

__all__ = [
    "REST_PROBE_MPA",
    "SECTION_NONLINEAR_KEYS",
    "SECTION_NONLINEAR_OPTIONS",
    "curve_with_rest",
    "load_columns",
    "partial_columns",
    "section_nonlinear_columns",
    "section_nonlinear_curve",
]

#: The ``section-nonlinear`` tier's options, name -> default: each is the keyword of
#: :func:`~softcath.fem.section_model.finite_strain.section_curve` of the same name, so an
#: option added here reaches the model with no other edit (``None``: the design's own).
#: ``silicone_poisson`` replaces every silicone's Poisson ratio; ``coil_axial_scale``
#: multiplies the outer coil's axial spring rate (its axial and axial shear moduli);
#: ``tube_prestretch`` is the as-built tube's axial stretch from its catalogue state (1: none;
#: above 1 the curve is solved on the reference path); ``tube_squeeze`` is the share of the
#: squeeze from the catalogue annulus the tube's stress-free state carries (0: none; its own axial
#: stretch included, so not with ``tube_prestretch``; reference path); ``coil_bound`` makes the close-wound
#: coils coil-bound in compression and closed up to their initial tension (the design's
#: ``coil.initial_tension``; also on the reference path).
SECTION_NONLINEAR_OPTIONS = {
    "mesh_size": None,
    "mesher": "template",
    "tube_prestretch": 1.0,
    "tube_squeeze": 0.0,
    "silicone_poisson": None,
    "coil_axial_scale": 1.0,
    "coil_bound": False,
}

#: Pressure [MPa] walked to when only the rest state is asked for (the walk needs a load to scale);
#: its row is dropped again. Far inside the linear range: one or two Newton iterations.
REST_PROBE_MPA = 1e-3

#: Result columns (per design x pressure x load) and the response field each comes from
#: (:meth:`~softcath.fem.section_model.finite_strain.SectionCurve.to_response`).
SECTION_NONLINEAR_KEYS = {
    "curvature_section_nonlinear_per_mm": "curvature_per_mm",
    "elongation_section_nonlinear": "elongation",
    "bend_angle_section_nonlinear_rad": "bend_angle_rad",
    "tip_x_section_nonlinear_mm": "tip_x_mm",
    "tip_y_section_nonlinear_mm": "tip_y_mm",
    "max_strain_section_nonlinear": "max_strain",
    "lumen_volume_change_section_nonlinear_mm3": "lumen_volume_change_mm3",
}


def curve_with_rest(design, pressures, **options):
    """The finite-strain curve at ``pressures`` (>= 0, increasing), the rest state alone included.

    :func:`~softcath.fem.section_model.finite_strain.section_curve` scales its load to the
    highest positive pressure, so pressures of only 0 MPa walk to :data:`REST_PROBE_MPA` as
    well and that row is dropped: the rest state is a valid answer, not an error.
    """
    from dataclasses import fields, replace

    p = [float(x) for x in np.atleast_1d(np.asarray(pressures, float))]
    if any(x > 0 for x in p):
        return section_curve(design, p, **options)
    c = section_curve(design, [*p, REST_PROBE_MPA], **options)
    n = len(p)
    cut = {
        f.name: getattr(c, f.name)[:n]
        for f in fields(c)
        if isinstance(getattr(c, f.name), np.ndarray) and getattr(c, f.name).shape[:1] == (n + 1,)
    }
    return replace(c, **cut)


def section_nonlinear_curve(design, pressures, load: str, options: dict | None = None):
    """The finite-strain curve of one design under ``load`` at ``pressures`` (>= 0, increasing).

    The one way the tier's options (:data:`SECTION_NONLINEAR_OPTIONS`; ``None`` is the design's
    own) reach the curve; others, e.g. of a shared ``[sweep.section]`` table, are left out. The
    columns below and the tier's record
    (:meth:`softcath.models.section_nonlinear.SectionNonlinearTier.record`) use it.
    """
    opts = {k: v for k, v in (options or {}).items() if k in SECTION_NONLINEAR_OPTIONS and v is not None}
    return curve_with_rest(design, pressures, load=load, linear_gain=False, **opts)


def section_nonlinear_columns(
    design, pressures: np.ndarray, loads: tuple[str, ...], options: dict | None = None
) -> dict:
    """``{load: {column: array over pressures}}`` of the finite-strain section model for one design.

    ``options`` are the tier's (:data:`SECTION_NONLINEAR_OPTIONS`; others, e.g. of a shared
    ``[sweep.section]`` table, are not this model's and are left out).
    ``section_nonlinear_seconds`` is the wall time for this design and load.

    Raises
    ------
    SectionConvergenceError
        A walk that stopped short (its curve so far in ``.curve``, :func:`partial_columns`).
    """
    return {load: load_columns(design, pressures, load, options) for load in loads}


def load_columns(design, pressures: np.ndarray, load: str, options: dict | None = None) -> dict:
    """``{column: array over pressures}`` of one ``load`` (:func:`section_nonlinear_columns`)."""
    p = np.asarray(pressures, float)
    walk = np.unique(p[p >= 0])
    t0 = time.perf_counter()
    cols = {k: np.full(p.size, np.nan) for k in SECTION_NONLINEAR_KEYS}
    if walk.size:
        cols = partial_columns(section_nonlinear_curve(design, walk, load, options), p)
    cols["section_nonlinear_seconds"] = np.full(p.size, time.perf_counter() - t0)
    return cols


def partial_columns(curve, pressures: np.ndarray) -> dict:
    """``{column: array over pressures}`` of a finite-strain ``curve`` walked through the
    non-negative ``pressures`` in increasing order, or through a first part of them (a walk that
    stalled): a pressure the curve does not reach, or a negative one, is NaN."""
    p = np.asarray(pressures, float)
    walk = np.unique(p[p >= 0])
    r = curve.to_response()
    reached = min(np.asarray(r.pressures).size, walk.size)
    idx = np.searchsorted(walk, p)
    ok = (p >= 0) & (idx < reached)
    cols = {k: np.full(p.size, np.nan) for k in SECTION_NONLINEAR_KEYS}
    for col, name in SECTION_NONLINEAR_KEYS.items():
        cols[col][ok] = np.asarray(getattr(r, name), float)[idx[ok]]
    return cols
