"""Newton's method with load stepping on the finite-strain section.

A :class:`SectionProblem` is one discretised section with its lumen wall and fixed
DOFs; :func:`walk` follows a load path through requested load factors: a
secant predictor from the last two converged states, Newton on the full
tangent (SuperLU), steps that grow after easy convergence and halve after a
failure, and a :class:`SectionConvergenceError` naming the load reached when
the step falls below its floor.

Every problem answers the same four calls (``residual_tangent``, ``load_vector``,
``factorise``, ``pressures_after``), which the module's functions of those names ask
of it: the bonded section here, and the tip as built
(:class:`~softcath.fem.section_model.finite_strain.as_built.AsBuiltProblem`: tied
interfaces and one stretch per axial group), which reuses the bonded load blocks per
group and returns the same quantities on its own unknowns.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from softcath.design.errors import DesignError
from softcath.design.load_cases import LOADS
from softcath.fem.section_model.finite_strain.as_built import AsBuiltProblem
from softcath.fem.section_model.finite_strain.discretisation import N_GLOBAL, Discretisation
from softcath.fem.section_model.finite_strain.lumen import LumenWall, lumen_volume
from softcath.fem.section_model.finite_strain.residual import internal, with_globals
from softcath.fem.section_model.finite_strain.sparse import Pattern
from softcath.fem.section_model.finite_strain.sparse import factorise as _factorise

__all__ = [
    "Loading",
    "SectionProblem",
    "State",
    "SectionConvergenceError",
    "walk",
    "factorise",
    "load_vector",
    "LOADS",
]

log = logging.getLogger(__name__)


class SectionConvergenceError(DesignError):
    """Newton did not converge; names the last load reached."""

    assemblies: list  # set by the fast walk (``fast_walk.walk``): the converged states' assemblies

    def __init__(self, reached: float, target: float, what: str = "pressure") -> None:
        self.reached, self.target = float(reached), float(target)
        self.states: list = []  # the states converged before the failure
        self.curve = None  # filled by callers that turn the states into a result
        super().__init__(what, target, f"not reached: Newton converged up to {reached:.6g} only")


@dataclass(frozen=True)
class Loading:
    """Loads at unit factor: a lumen pressure [MPa] of kind ``load`` and end moments [N mm].

    Both loads of :data:`~softcath.design.load_cases.LOADS` act on the deformed configuration:
    ``lumen`` is a follower pressure on the deformed lumen wall plus the cap force on the
    deformed lumen.

    The moments (M_1, M_2) do work on the section's turning rate lambda k; they are
    for verification (Rivlin's flexure), the catheter's loads are pressures.
    """

    pressure: float = 0.0
    load: str = "lumen"
    moment: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        if self.load not in LOADS:
            raise DesignError("load", self.load, f"must be one of {LOADS}")


@dataclass(frozen=True)
class SectionProblem:
    """A discretised section, its lumen wall (or None) and its fixed DOFs."""

    disc: Discretisation
    wall: LumenWall | None
    fixed: np.ndarray
    silicone: tuple[int, ...] = ()

    @cached_property
    def free(self) -> np.ndarray:
        """The unknowns solved for."""
        return np.setdiff1d(np.arange(self.disc.ndofs), self.fixed)

    def initial_state(self) -> np.ndarray:
        """The unloaded tip: no displacement, lambda = 1, no curvature."""
        q = np.zeros(self.disc.ndofs)
        q[self.disc.n_u] = 1.0
        return q

    # The problem protocol the walk calls (the tip as built, ``as_built.AsBuiltProblem``, has its own):
    # ``load_blocks`` is the bonded section's load assembly, which an as-built problem reuses per group.
    def residual_tangent(self, q, loading, factor, pressure, load_blocks):
        """Global residual, free-free tangent, external-force norm and diagnostics at ``q``."""
        return _bonded_residual_tangent(self, q, loading, factor, pressure)

    def load_vector(self, q, loading, load_blocks) -> np.ndarray:
        """External forces of the unit load factor at ``q``."""
        return _bonded_load_vector(self, q, loading)

    def factorise(self, k):
        """Factorise a free-free tangent; the result has ``solve(b)``."""
        return _bonded_factorise(self, k)

    def pressures_after(self, tan, step: np.ndarray) -> dict:
        """The projected pressures linearised along ``step`` from the state of ``tan``."""
        return _bonded_pressures_after(self, tan, step)

    @cached_property
    def size(self) -> float:
        """Largest distance of a node from the origin [mm]."""
        return float(np.abs(np.asarray(self.disc.mesh.p)).max())

    @cached_property
    def tables(self) -> list[np.ndarray]:
        """Local DOF tables of the element, lumen-wall and global blocks (assembly order)."""
        disc = self.disc
        tables = [with_globals(disc, disc.dofs)]
        if self.wall is not None:
            tables.append(with_globals(disc, self.wall.dofs))
        tables.append(np.arange(disc.n_u, disc.n_u + N_GLOBAL)[None, :])
        return tables

    @cached_property
    def pattern(self) -> Pattern:
        """The tangent's free-free sparsity pattern (computed once)."""
        return Pattern(self.tables, self.disc.ndofs, self.free)


@dataclass(frozen=True)
class State:
    """A converged state: unknowns, load factor, Newton effort and diagnostics."""

    q: np.ndarray
    factor: float
    iterations: int
    residual: float
    max_strain: float


def _bonded_residual_tangent(
    problem: SectionProblem, q: np.ndarray, loading: Loading, factor: float, pressure=None
):
    """Global residual (all DOFs), free-free sparse tangent, external-force norm and diagnostics.

    ``pressure``: the mixed iteration's projected pressures (``residual.internal``).
    """
    disc = problem.disc
    u, g = q[: disc.n_u], q[disc.n_u :]
    tan = internal(disc, u, g, silicone=problem.silicone, pressure=pressure)
    if tan.min_jacobian <= 0:
        return None, None, 0.0, tan
    loads, ext = _load_blocks(problem, u, g, loading, factor)
    res = [tan.residual, *(r for r, _ in loads)]
    stiff = [tan.stiffness, *(k for _, k in loads)]
    r = np.bincount(
        np.concatenate([t.ravel() for t in problem.tables]),
        weights=np.concatenate([x.ravel() for x in res]),
        minlength=disc.ndofs,
    )
    k = problem.pattern.matrix(np.concatenate([x.ravel() for x in stiff]))
    return r, k, ext, tan


def _bonded_load_vector(problem: SectionProblem, q: np.ndarray, loading: Loading) -> np.ndarray:
    """External forces of the unit load factor at the state ``q`` (follower loads move with it).

    The load-path tangent is ``dq/dfactor = K^-1 load_vector`` (K the full tangent).
    """
    disc = problem.disc
    blocks, _ = _load_blocks(problem, q[: disc.n_u], q[disc.n_u :], loading, 1.0)
    r = np.bincount(
        np.concatenate([t.ravel() for t in problem.tables[1:]]),
        weights=np.concatenate([res.ravel() for res, _ in blocks]),
        minlength=disc.ndofs,
    )
    return -r


def _load_blocks(problem: SectionProblem, u: np.ndarray, g: np.ndarray, loading: Loading, factor: float):
    """(residual, tangent) blocks of the loads at ``factor`` on ``problem.tables[1:]``, and their force
    norm."""
    r_g = np.zeros((1, N_GLOBAL))
    k_g = np.zeros((1, N_GLOBAL, N_GLOBAL))
    blocks = []
    p = factor * loading.pressure
    ext = 0.0
    if p != 0.0 and problem.wall is None:
        raise DesignError("pressure", p, "needs a section with a lumen")
    if problem.wall is not None:
        nf, nb = problem.wall.dofs.shape
        r_l = np.zeros((nf, nb + N_GLOBAL))
        k_l = np.zeros((nf, nb + N_GLOBAL, nb + N_GLOBAL))
        blocks.append((r_l, k_l))
    if p != 0.0:
        lv = lumen_volume(problem.wall, u, g)
        k_l[:, nb:, :nb] = -p * lv.dug.transpose(0, 2, 1)
        if loading.load == "lumen":
            r_l[:, :nb] = -p * lv.du
            k_l[:, :nb, :nb] = -p * lv.duu
            k_l[:, :nb, nb:] = -p * lv.dug
            ext += float(np.linalg.norm(p * lv.du)) ** 2
        r_g[0] -= p * lv.dg
        k_g[0] -= p * lv.dgg
        ext += float(np.linalg.norm(p * lv.dg)) ** 2
    m1, m2 = (factor * m for m in loading.moment)
    if m1 or m2:
        lam, k1, k2 = g
        r_g[0] -= np.array([m1 * k1 + m2 * k2, m1 * lam, m2 * lam])
        k_g[0, 0, 1:] -= (m1, m2)
        k_g[0, 1:, 0] -= (m1, m2)
        ext += (m1 * lam) ** 2 + (m2 * lam) ** 2
    blocks.append((r_g, k_g))
    return blocks, float(np.sqrt(ext))


def _bonded_factorise(problem: SectionProblem, k):
    """Factorise a free-free tangent of ``problem``; the result has ``solve(b)``."""
    return _factorise(problem.pattern, k)


def _bonded_pressures_after(problem: SectionProblem, tan, step: np.ndarray) -> dict:
    """The projected pressures linearised along the global ``step`` from the state of ``tan``."""
    local = step[with_globals(problem.disc, problem.disc.dofs)]
    return {label: v.pressure_after(local[v.cells]) for label, v in tan.volumetric.items()}


def residual_tangent(problem, q: np.ndarray, loading: Loading, factor: float, pressure=None):
    """Global residual (all DOFs), free-free sparse tangent, external-force norm and diagnostics.

    ``pressure``: the mixed iteration's projected pressures (``residual.internal``).
    """
    return problem.residual_tangent(q, loading, factor, pressure, _load_blocks)


def load_vector(problem, q: np.ndarray, loading: Loading) -> np.ndarray:
    """External forces of the unit load factor at the state ``q`` (follower loads move with it).

    The load-path tangent is ``dq/dfactor = K^-1 load_vector`` (K the full tangent).
    """
    return problem.load_vector(q, loading, _load_blocks)


def factorise(problem, k):
    """Factorise a free-free tangent of ``problem``; the result has ``solve(b)``."""
    return problem.factorise(k)


def pressures_after(problem, tan, step: np.ndarray) -> dict:
    """The projected pressures linearised along the global ``step`` from the state of ``tan``."""
    return problem.pressures_after(tan, step)


def newton(
    problem: SectionProblem | AsBuiltProblem,
    q0: np.ndarray,
    loading: Loading,
    factor: float,
    *,
    tol: float,
    max_iter: int,
    pressure: dict | None = None,
):
    """Newton iterations on the u-p pair at one load factor from ``q0`` (and ``pressure``).

    The projected pressures are carried as the mixed formulation's unknowns: each
    step updates them by their linearisation, and the tangent's geometric term uses
    them. Returns the converged :class:`State`, the last factorised tangent and the
    converged state's internal data, or (None, None, None).
    """
    free = problem.free
    q = q0.copy()
    lu = None
    fail = (None, None, None)
    for it in range(1, max_iter + 1):
        r, k, ext, tan = residual_tangent(problem, q, loading, factor, pressure)
        if r is None:
            return fail
        norm = float(np.linalg.norm(r[free]))
        log.debug("factor %.4g iteration %d residual %.3e of %.3e", factor, it, norm, ext)
        scale = max(ext, 1e-300)
        # round-off floor of the forces: the stiff coils' stresses carry an absolute error of
        # eps * modulus, i.e. eps * |K| * (section size) per row, far above tol * ext at tiny loads
        floor = np.finfo(float).eps * float(abs(k).sum(axis=1).max()) * problem.size
        if norm <= max(tol * scale, floor):
            return State(q, factor, it - 1, norm / scale, tan.max_strain), lu, tan
        if not np.isfinite(norm):
            return fail
        try:
            lu = factorise(problem, k)
            dq = lu.solve(-r[free])
        except RuntimeError:  # singular tangent: a buckled or torn state
            return fail
        if not np.all(np.isfinite(dq)):
            return fail
        step = np.zeros_like(q)
        step[free] = dq
        pressure = pressures_after(problem, tan, step)
        q += step
    return fail


def walk(
    problem: SectionProblem | AsBuiltProblem,
    loading: Loading,
    factors: Sequence[float] | np.ndarray,
    *,
    tol: float = 1e-6,
    max_iter: int = 25,
    min_step: float = 1e-4,
    on_state: Callable[[State], None] | None = None,
    start: np.ndarray | None = None,
) -> list[State]:
    """Converged states at each requested load factor (increasing, > 0), from the unloaded
    state ``start`` (default: the problem's initial state, the reference section)."""
    q = problem.initial_state() if start is None else np.array(start, dtype=float)
    f = np.asarray(factors, float)
    if f.ndim != 1 or f.size == 0 or np.any(f <= 0) or np.any(np.diff(f) <= 0):
        raise DesignError("load factors", f.tolist(), "must be positive and strictly increasing")
    states: list[State] = []
    done, rate, lu, tan = 0.0, None, None, None
    free = problem.free
    step = float(f[0])
    scale = loading.pressure if loading.pressure else 1.0  # errors speak in pressure when there is one
    for target in f:
        spent = 0
        while done < target * (1 - 1e-12):
            trial = min(step, target - done)
            state = None
            if rate is not None:  # Euler predictor along the load path's tangent
                state, new_lu, new_tan = newton(
                    problem,
                    q + trial * rate,
                    loading,
                    done + trial,
                    tol=tol,
                    max_iter=max_iter,
                    pressure=pressures_after(problem, tan, trial * rate),
                )
            if state is None:
                state, new_lu, new_tan = newton(problem, q, loading, done + trial, tol=tol, max_iter=max_iter)
            if state is None:
                step = trial / 2
                if step < min_step * f[-1]:
                    what = "pressure" if loading.pressure else "load factor"
                    error = SectionConvergenceError(done * scale, target * scale, what)
                    error.states = states
                    raise error
                log.debug("cut back to step %.3g at factor %.4g", step, done)
                continue
            q, done, tan = state.q, state.factor, new_tan
            lu = new_lu if new_lu is not None else lu
            rate = None
            if lu is not None:
                rate = np.zeros_like(q)
                rate[free] = lu.solve(load_vector(problem, q, loading)[free])
            spent += state.iterations
            if state.iterations <= 3:
                step = trial * 2.0
            last = state
        last = replace(last, iterations=spent)
        states.append(last)
        if on_state is not None:
            on_state(last)
    return states
