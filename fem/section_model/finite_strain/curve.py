r"""The finite-strain bend curve of a design: :func:`section_curve`.

One section mesh, one discretisation, a Newton walk through the requested
pressures. Per pressure the state gives the stretch lambda and the bend
vector k of the uniform mid-span arc, from which

- the **bend rate** :math:`\lambda k_2` [rad/mm of undeformed length]: the turn
  of the sections per unit reference length, the same for every fibre (the
  3-D FEM's ``bend_rate_mid_per_mm``);
- the **curvature** :math:`k_2 / (1 + k\cdot\bar x)` of the fibre through the
  deformed section's axial-stiffness centroid :math:`\bar x` (the 3-D FEM's
  ``curvature_mid_per_mm`` and the linear section model's curvature), and
  that fibre's **elongation** :math:`\lambda (1 + k\cdot\bar x) - 1`;
- the **bend angle** and **tip pose** of the tip: the arc of that curvature
  over the stretched L - deficit, then the end zones straight along its end
  tangent; the angle is :math:`\lambda k_2 (L - \delta)` (L the bending
  length, :math:`\delta` the end zones' deficit) plus, under the lumen load,
  the cap plug's tilt :math:`K (p / E_\mathrm{cap})^2`.

End zones. The uniform arc is the tip far from its ends. The clamped 3-D tip
turns less: the cap's plug carries no wall pressure and does not bend, and the
clamp's zone nearly cancels the cap's. :mod:`softcath.fem.section_model.end_zones`
reduces that to a closed form fitted on converged 3-D solves (within 0.3 % of
the 3-D end rotation on its own bend rate); ``bend_angle`` and the tip pose are
the tip's, the curvature is mid-span's (the 3-D FEM's ``curvature_mid_per_mm``).

The tip as built. A design whose ``assembly`` is not the bonded default is solved on
this reference path (:mod:`.as_built`: the filler's regions as built, the mesh split at
sliding interfaces with the normal tied, one stretch per axial group); its elongation
is the outer coil's group's, and the curve reports the largest in-plane interface slip
per element size at every pressure (the small-sliding limit of the normal tie).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from softcath import design as design_pkg
from softcath.core.limits import MAX_PRESSURE_MPA
from softcath.design.errors import DesignError
from softcath.fem.adapter import geometry_from_design
from softcath.fem.geometry import FILLER, TUBE
from softcath.fem.section_model.finite_strain.as_built import AsBuiltProblem, as_built_problem, split_section
from softcath.fem.section_model.finite_strain.discretisation import discretise
from softcath.fem.section_model.finite_strain.fast import Unsupported
from softcath.fem.section_model.finite_strain.fast_curve import template_curve
from softcath.fem.section_model.finite_strain.laws import COIL_AXIAL_SCALE_MAX, section_laws
from softcath.fem.section_model.finite_strain.lumen import lumen_volume, lumen_wall
from softcath.fem.section_model.finite_strain.newton import (
    LOADS,
    Loading,
    SectionConvergenceError,
    SectionProblem,
    factorise,
    load_vector,
    residual_tangent,
    walk,
)
from softcath.fem.section_model.finite_strain.prestretch import (
    Prestretched,
    check_prestretch,
    prestretched_laws,
    rest_state,
)
from softcath.fem.section_model.finite_strain.result import CSV_COLUMNS, SectionCurve
from softcath.fem.section_model.finite_strain.rows import (
    CurveFacts,
    curve_from_rows,
    progress_callback,
    rest_row,
    state_row,
)
from softcath.fem.section_model.finite_strain.squeeze import (
    Squeezed,
    TubeRing,
    check_squeeze,
    squeeze_rest_state,
)
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS, catheter_section_mesh

__all__ = [
    "COIL_AXIAL_SCALE_MAX",
    "CSV_COLUMNS",
    "SectionCurve",
    "section_curve",
    "section_laws",
    "PRESSURE_MAX",
]

log = logging.getLogger(__name__)

#: Interface slip [element sizes] past which a curve of the tip as built is logged as beyond the
#: small-sliding limit: half an element, where a tied node pair faces the neighbouring edge.
SLIP_LIMIT = 0.5

#: Largest pressure [MPa] the model accepts: the package's one bound (far past any tube's burst).
PRESSURE_MAX = MAX_PRESSURE_MPA


def _check_pressures(pressures) -> np.ndarray:
    p = np.atleast_1d(np.asarray(pressures, dtype=float))
    if p.ndim != 1 or p.size == 0:
        raise DesignError("pressures", pressures, "must be a non-empty list of pressures [MPa]")
    if not np.all(np.isfinite(p)) or np.any(p < 0) or np.any(p > PRESSURE_MAX):
        raise DesignError("pressures", p.tolist(), f"must be finite and in [0, {PRESSURE_MAX:g}] MPa")
    if np.any(np.diff(p) <= 0):
        raise DesignError("pressures", p.tolist(), "must be strictly increasing")
    return p


def section_curve(
    design,
    pressures: Sequence[float] | np.ndarray,
    *,
    load: str = "lumen",
    mesh_size: float | None = None,
    segments: int | None = None,
    silicone_poisson: float | None = None,
    hoop_cap: float | None = None,
    laws: Mapping[int, object] | None = None,
    mesher: str = "template",
    linear_gain: bool = True,
    progress: bool = False,
    on_pressure: Callable[[int, int], None] | None = None,
    tube_prestretch: float = 1.0,
    tube_squeeze: float = 0.0,
    coil_axial_scale: float = 1.0,
    coil_bound: bool = False,
    initial_tension: float | None = None,
    compression_modulus: float | None = None,
) -> SectionCurve:
    """Finite-strain bend curve of ``design`` at increasing ``pressures`` [MPa].

    Parameters
    ----------
    design
        A :class:`design.TipDesign`, a preset name or a TOML path.
    pressures
        Pressures [MPa], strictly increasing, in [0, :data:`PRESSURE_MAX`]; 0 gives the rest state.
    load
        ``"lumen"`` (follower pressure on the lumen wall plus the cap force; the real load)
        or ``"cap"`` (the cap force on the deformed lumen alone; the paper's load).
    mesh_size, segments, mesher
        Section mesh controls (default: the linear section model's; ``mesher`` ``template``
        morphs one mesh per section topology and solves on the compiled template path,
        ``gmsh`` meshes afresh and solves on the reference path; the same answers to the
        Newton tolerance on one mesh).
    silicone_poisson, hoop_cap, coil_axial_scale, coil_bound, initial_tension, compression_modulus
        Material options of :func:`section_laws` (unused where ``laws`` is given): with
        ``coil_bound`` the close-wound coils are coil-bound in compression and closed up to
        their initial tension (the outer coil's F0 ``initial_tension`` [N], default the
        design's; its coil-bound modulus ``compression_modulus`` [MPa], default E phi), solved
        on the reference path; False (the default) leaves the curve exactly as without it.
    laws
        Region label -> finite-strain law, overriding :func:`section_laws` (e.g. the 3-D
        FEM's ``catheter_laws`` for a comparison on equal materials).
    linear_gain
        Also solve the rest state's tangent for the small-load gain (one more factorisation,
        ~8 % of a 7-pressure curve; sweeps and bands leave it out).
    progress
        Show a progress bar over the pressures.
    on_pressure
        Called as ``on_pressure(done, total)`` after each converged positive pressure
        (a caller's progress display). An exception it raises stops the walk and
        propagates: the way a caller cancels a curve it no longer needs.
    tube_prestretch
        Axial stretch lambda_pre in [1, 4] of the as-built tube from its stress-free
        (catalogue) state (module ``prestretch``); 1, the default, is the tube built stress-free.
        Above 1 the walk starts from the pre-stretched rest state at 0 MPa (reported as
        ``rest_curvature_per_mm`` and ``rest_elongation``); curvature and elongation stay absolute
        (measured from the straight as-built section), and the curve is solved on the reference
        path (the compiled template path has no pre-stretch).
    tube_squeeze
        Share t in [0, 1] of the squeeze from the catalogue annulus to the as-built ring that the
        tube's stress-free state carries (module ``squeeze``: a per-point pre-deformation, its
        axial stretch included so that it keeps the silicone's volume); 0, the default, is the
        tube built stress-free. Above 0 it is solved as ``tube_prestretch`` is (the rest state
        first, the reference path) and does not combine with it (the squeeze carries its own
        axial stretch).

    Raises
    ------
    DesignError
        Bad input; :class:`SectionConvergenceError` (a ``DesignError``) names the
        pressure reached when Newton fails, with the converged part in ``.curve``.

    Examples
    --------
    >>> from softcath.fem.section_model.finite_strain import section_curve
    >>> c = section_curve("paper", [0.3, 0.6])
    >>> [round(float(a)) for a in c.bend_angle_rad * 180 / 3.141592653589793]  # degrees
    [23, 56]
    """
    d, p = _check_inputs(design, pressures, load)
    stretch = check_prestretch(tube_prestretch)
    squeeze = check_squeeze(tube_squeeze)
    if stretch != 1.0 and squeeze != 0.0:
        raise DesignError(
            "tube_squeeze",
            squeeze,
            f"does not combine with tube_prestretch = {stretch:g} (the squeeze carries its own axial "
            "stretch): give one of them",
        )
    material = {
        "silicone_poisson": silicone_poisson,
        "hoop_cap": hoop_cap,
        "coil_axial_scale": coil_axial_scale,
        "coil_bound": coil_bound,
        "initial_tension": initial_tension,
        "compression_modulus": compression_modulus,
    }
    if laws is None:  # the options' bounds checked before any mesh is made
        section_laws(d, **material)
    t0 = time.perf_counter()
    if stretch != 1.0 and not d.assembly.is_default:
        raise DesignError(
            "tube_prestretch",
            stretch,
            "takes the bonded tip only (1 for a tip built with an [assembly] of interfaces or fillers)",
        )
    if squeeze != 0.0 and not d.assembly.is_default:
        raise DesignError(
            "tube_squeeze",
            squeeze,
            "takes the bonded tip only (0 for a tip built with an [assembly] of interfaces or fillers)",
        )
    if mesher == "template" and (stretch != 1.0 or squeeze != 0.0):
        log.info(
            "finite-strain section: tube pre-stretch %.4g, squeeze %.4g; solved on the reference path",
            stretch,
            squeeze,
        )
    elif mesher == "template" and not d.assembly.is_default:
        log.info(
            "finite-strain section: %s is built as %s; solved on the reference path",
            d.name,
            d.assembly.to_dict(),
        )
    elif mesher == "template":
        law_map = dict(laws) if laws is not None else section_laws(d, **material)
        total = int(np.count_nonzero(p > 0))
        on_state, close = progress_callback(total, progress, on_pressure)
        try:
            curve, error = template_curve(
                d,
                p,
                load,
                mesh_size=MESH_SIZE if mesh_size is None else mesh_size,
                segments=SEGMENTS if segments is None else segments,
                law_map=law_map,
                hoop_cap=hoop_cap,
                linear_gain=linear_gain,
                on_state=on_state,
                t0=t0,
            )
            return _finish(curve, error)
        except Unsupported as exc:
            log.info("finite-strain section: %s; solved on the reference path", exc)
            mesher = exc.mesher
        finally:
            close()
    setup = _set_up(
        d,
        p,
        load,
        mesh_size=mesh_size,
        segments=segments,
        mesher=mesher,
        laws=laws,
        material=material,
        linear_gain=linear_gain,
        stretch=stretch,
        squeeze=squeeze,
    )
    states, error = _walk(setup, progress, on_pressure)
    return _finish(_curve(d, load, p, setup, states, hoop_cap, t0=t0), error)


def _finish(curve: SectionCurve, error) -> SectionCurve:
    """Log the curve's cost; raise the walk's convergence error (carrying the curve) if any."""
    log.info(
        "finite-strain section: %d pressures in %.3g s (%d DOFs)",
        curve.pressure.size,
        curve.seconds,
        curve.dofs,
    )
    if error is not None:
        error.curve = curve
        raise error
    return curve


def _check_inputs(design, pressures, load):
    """Check the load and pressures and resolve the design; returns (design, pressures)."""

    if load not in LOADS:
        raise DesignError("load", load, f"must be one of {LOADS}")
    p = _check_pressures(pressures)
    d = design_pkg.resolve(design)
    return d, p


@dataclass(frozen=True)
class _Setup:
    """The discretised section and its loading, ready for the Newton walk."""

    section: Any
    mesh_size: float
    law_map: dict
    disc: Any
    wall: Any
    problem: Any
    positive: np.ndarray
    p_top: float
    loading: Any
    rest: Any
    gain: float | None
    rest_state: Any = None  # the pre-stretched tip's equilibrium at 0 MPa (None: the reference section)


def _set_up(
    d,
    p,
    load,
    *,
    mesh_size,
    segments,
    mesher,
    laws,
    material,
    linear_gain,
    stretch=1.0,
    squeeze=0.0,
) -> _Setup:
    """Mesh and discretise the section, set up its loading and the rest state."""

    mesh_size = MESH_SIZE if mesh_size is None else mesh_size
    segments = SEGMENTS if segments is None else segments
    section = catheter_section_mesh(
        geometry_from_design(d), mesh_size=mesh_size, segments=segments, mesher=mesher
    )
    law_map = dict(laws) if laws is not None else section_laws(d, **material)
    silicone = tuple(k for k in (TUBE, FILLER) if k in law_map)
    if d.assembly.is_default:
        disc = discretise(section, law_map)
        wall = lumen_wall(section, disc)
        problem = SectionProblem(disc, wall, disc.pinned, silicone)
    else:  # the tip as built: the split mesh, its ties and axial groups
        split, tie, plan = split_section(section, d.assembly)
        section = split.mesh
        disc = discretise(section, law_map)
        wall = lumen_wall(section, disc)
        problem = as_built_problem(split, tie, plan, disc, wall, silicone=silicone)
    positive = p[p > 0]
    p_top = float(positive[-1]) if positive.size else 1.0
    loading = Loading(pressure=p_top, load=load)
    q_rest = problem.initial_state()
    rest = lumen_volume(wall, np.zeros(disc.n_u), np.array([1.0, 0.0, 0.0]))
    at_rest = None
    if stretch != 1.0 and isinstance(problem, SectionProblem):  # the bonded tip only (section_curve)
        problem, at_rest = rest_state(problem, stretch)
        disc, law_map, q_rest = problem.disc, prestretched_laws(law_map, stretch), at_rest.q
        rest = lumen_volume(wall, q_rest[: disc.n_u], q_rest[disc.n_u :])
    if squeeze != 0.0 and isinstance(problem, SectionProblem):  # the bonded tip only, never pre-stretched
        problem, at_rest = squeeze_rest_state(problem, TubeRing.from_design(d), squeeze)
        disc, law_map, q_rest = problem.disc, problem.disc.laws, at_rest.q
        rest = lumen_volume(wall, q_rest[: disc.n_u], q_rest[disc.n_u :])
    gain = _linear_gain(problem, q_rest, loading) / p_top if linear_gain else None
    return _Setup(
        section=section,
        mesh_size=mesh_size,
        law_map=law_map,
        disc=disc,
        wall=wall,
        problem=problem,
        positive=positive,
        p_top=p_top,
        loading=loading,
        rest=rest,
        gain=gain,
        rest_state=at_rest,
    )


def _walk(setup: _Setup, progress: bool, on_pressure: Callable[[int, int], None] | None = None):
    """Newton walk through the positive pressures; returns (states, convergence error or None)."""

    on_state, close = progress_callback(int(setup.positive.size), progress, on_pressure)
    error = None
    try:
        start = None if setup.rest_state is None else setup.rest_state.q
        states = walk(
            setup.problem, setup.loading, setup.positive / setup.p_top, on_state=on_state, start=start
        )
    except SectionConvergenceError as exc:
        error = exc
        states = list(exc.states)
    finally:
        close()
    return states, error


def _curve(d, load, p, setup: _Setup, states, hoop_cap, *, t0) -> SectionCurve:
    """The :class:`SectionCurve` of the rest rows and the converged states."""

    disc, wall, rest = setup.disc, setup.wall, setup.rest
    tube = setup.law_map[TUBE]
    n_zero = p.size - setup.positive.size
    rest_at = rest_row(rest.area, rest.volume)
    if setup.rest_state is not None:
        u0 = setup.rest_state.q[: disc.n_u]
        rest_at = state_row(setup.rest_state, _centroid(disc, u0), rest.volume, rest.area, disc.n_u)
    rows = [rest_at] * n_zero
    slip = None
    if isinstance(setup.problem, AsBuiltProblem):
        slip = np.array([0.0] * n_zero + [setup.problem.slip_ratio(s.q) for s in states])
        if slip.size and slip.max() > SLIP_LIMIT:
            log.warning(
                "finite-strain section: interface slip of %.2g elements at %.3g MPa, past the "
                "small-sliding limit (%.2g) of the normal tie in the reference configuration",
                slip.max(),
                p[int(np.argmax(slip))],
                SLIP_LIMIT,
            )
        states = [setup.problem.section_state(s) for s in states]
    for s in states:
        u, g = s.q[: disc.n_u], s.q[disc.n_u :]
        lv = lumen_volume(wall, u, g)
        rows.append(state_row(s, _centroid(disc, u), lv.volume, lv.area, disc.n_u))
    facts = CurveFacts(
        rest_area=float(rest.area),
        rest_volume=float(rest.volume),
        gain=setup.gain,
        dofs=int(disc.ndofs),
        n_triangles=int(setup.section.triangles.shape[0]),
        mesh_size=float(setup.mesh_size),
        tube_law=setup.law_map[TUBE],
        hoop_cap=hoop_cap,
        t0=t0,
        mesh_seconds=float(setup.section.seconds),
        tube_prestretch=float(tube.stretch) if isinstance(tube, Prestretched) else 1.0,
        tube_squeeze=float(tube.squeeze) if isinstance(tube, Squeezed) else 0.0,
        rest_curvature=float(rest_at["curvature"]),
        rest_elongation=float(rest_at["elongation"]),
    )
    curve = curve_from_rows(d, load, p, rows, facts, (disc, states))
    return curve if slip is None else replace(curve, interface_slip_per_element=slip)


def _centroid(disc, u) -> np.ndarray:
    """Axial-stiffness-weighted centroid of the deformed section (small-strain E_z weights)."""
    _, x = disc.element_fields(u)
    w = disc.weights * disc.axial_modulus[:, None]
    return np.einsum("cq,cqa->a", w, x) / w.sum()


def _linear_gain(problem, q_rest, loading) -> float:
    """dk_2/dfactor at rest (= dkappa/dfactor there): one solve with the rest-state tangent."""

    _, k, _, _ = residual_tangent(problem, q_rest, loading, 0.0)
    free = problem.free
    rate = np.zeros(q_rest.size)
    rate[free] = factorise(problem, k).solve(load_vector(problem, q_rest, loading)[free])
    return float(rate[-1])  # k_2: the last unknown of either problem
