"""The finite-strain bend curve on the template path: :func:`template_curve`.

:func:`~softcath.fem.section_model.finite_strain.section_curve` with ``mesher="template"``
(the default) comes here first: the design's section is its topology's template mesh
morphed to it, the quadrature data are made from the node positions, and the Newton
walk runs on the compiled, condensed assembly
(:mod:`~softcath.fem.section_model.finite_strain.fast_walk`). Its converged states are
the reference discretisation's on the same mesh to the Newton tolerance
(tests/fem/section_model/finite_strain/test_finite_strain_fast.py). A design the template
refuses, or laws the compiled kernel does not know, raise
:class:`~softcath.fem.section_model.finite_strain.fast.Unsupported`: the caller takes the
reference path (with gmsh for a refused design).
"""

from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np

from softcath.fem.adapter import geometry_from_design
from softcath.fem.geometry import FILLER, TUBE
from softcath.fem.limits import check_section_budget
from softcath.fem.section_model.finite_strain.fast import Unsupported, fast_problem, fast_template
from softcath.fem.section_model.finite_strain.fast_walk import linear_rate, rest_state, walk
from softcath.fem.section_model.finite_strain.newton import SectionConvergenceError
from softcath.fem.section_model.finite_strain.rows import CurveFacts, curve_from_rows, rest_row, state_row
from softcath.fem.section_model.mesh import check_size
from softcath.fem.section_model.template import templated

__all__ = ["template_curve"]

log = logging.getLogger(__name__)


def template_curve(
    d,
    p: np.ndarray,
    load: str,
    *,
    mesh_size: float,
    segments: int,
    law_map: dict,
    hoop_cap: float | None,
    linear_gain: bool,
    on_state: Callable | None,
    t0: float,
):
    """``(curve, convergence error or None)`` of design ``d`` on its template.

    Raises :class:`~softcath.fem.section_model.finite_strain.fast.Unsupported` (its ``mesher``
    the one the reference path should use) when the template path does not take the design.

    Parameters
    ----------
    d, p, load
        The resolved design, checked pressures [MPa] and load.
    mesh_size, segments
        Section mesh controls.
    law_map
        Region label -> finite-strain law.
    hoop_cap, linear_gain, on_state
        As in :func:`~softcath.fem.section_model.finite_strain.section_curve` (``on_state`` is
        called after each converged positive pressure).
    t0
        ``time.perf_counter()`` at the call's start.
    """
    from softcath.fem.section_model.finite_strain.kernel import lumen  # numba: heavy, first use

    g = geometry_from_design(d)
    check_size(mesh_size, segments)
    check_section_budget(coil_outer_radius=g.coil_outer_radius, mesh_size=mesh_size)
    got = templated(g, mesh_size=mesh_size, segments=segments)  # logs a refusal
    if got is None:
        raise Unsupported("the template refused the design", mesher="gmsh")
    template, mesh = got
    tpl = fast_template(template)
    prob = fast_problem(tpl, mesh, law_map, tuple(k for k in (TUBE, FILLER) if k in law_map))
    positive = p[p > 0]
    p_top = float(positive[-1]) if positive.size else 1.0
    error = None
    with tpl.lock:
        rate, rest_tangent = linear_rate(prob, load, p_top)
        gain = float(rate[prob.n_u + 2]) / p_top if linear_gain else None
        try:
            states, converged = (
                walk(prob, p_top, load, positive / p_top, on_state=on_state, rest=rest_tangent)
                if positive.size
                else ([], [])
            )
        except SectionConvergenceError as exc:
            error = exc
            states, converged = list(exc.states), list(exc.assemblies)
    q0 = rest_state(prob)
    nf = tpl.l_local.shape[0]
    rest = np.zeros(4)
    scratch = (np.empty((nf, 14)), np.empty((nf, 14, 3)), np.empty((nf, 14, 14)))
    lumen(q0[tpl.l_local[:, :14]], q0[prob.n_u :], prob.l_points, prob.l_tangents, prob.l_weights,
          tpl.lphi, tpl.ldphi, rest, *scratch)  # fmt: skip
    rows = [rest_row(rest[1], rest[0])] * (p.size - positive.size)
    for s, a in zip(states, converged, strict=True):
        rows.append(state_row(s, prob.centroid(s.q[: prob.n_u]), a.volume[0], a.volume[1], prob.n_u))
    facts = CurveFacts(
        rest_area=float(rest[1]),
        rest_volume=float(rest[0]),
        gain=gain,
        dofs=prob.ndofs,
        n_triangles=int(mesh.triangles.shape[0]),
        mesh_size=float(mesh_size),
        tube_law=law_map[TUBE],
        hoop_cap=hoop_cap,
        t0=t0,
        mesh_seconds=float(mesh.seconds),
    )
    return curve_from_rows(d, load, p, rows, facts, (None, states)), error  # no per-process caches in a curve
