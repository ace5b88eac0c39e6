"""Newton's method with load stepping and step cutback.

The load factor λ runs from 0 to 1 in ``steps`` equal increments; at each λ
every pressure is λ·p and every prescribed displacement λ·value. A step
that does not converge within ``max_iter`` iterations — or produces a
non-finite residual or an inverted element — is undone and retried at half
the increment; after ``max_cutbacks`` halvings in a row :class:`ConvergenceError`
is raised with the load reached and the last residual. The next step grows
back toward the planned increment. Each accepted step records its
iterations and relative residual history.

Every step after the first starts from an extrapolation of the accepted path
(:func:`~softcath.fem.nonlinear.load_path.predict`): quadratic through the last three equilibria, the secant
through two after the first step. On the paper's tip walked to 54° in 8 steps
(12 layers) the quadratic predictor, with the first planned step split into a
short ramp (``load_path.first_load_steps``), took the path from 90 tangent
factorisations (secant predictor, a failed first step) to 41, with the same
answer to 3e-11.
"""

from __future__ import annotations

import functools
import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from softcath.fem.nonlinear.body import FollowerPressure, HyperelasticBody
from softcath.fem.nonlinear.errors import ConvergenceError, NonlinearError, SettingError
from softcath.fem.nonlinear.linsolve import TangentSolver
from softcath.fem.nonlinear.load_path import check_predictor, predict

__all__ = ["StepRecord", "NonlinearResult", "solve"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class StepRecord:
    """One accepted load step.

    Attributes
    ----------
    load_factor
        λ reached (0, 1].
    pressures
        λ·p of each pressure load [MPa].
    iterations
        Newton iterations used.
    residuals
        Relative residual ‖R_free‖ / ‖f_ref‖ after each iteration.
    cutbacks
        Halvings of the increment before this step converged.
    """

    load_factor: float
    pressures: tuple[float, ...]
    iterations: int
    residuals: tuple[float, ...]
    cutbacks: int


@dataclass(frozen=True)
class NonlinearResult:
    """Displacement history of a converged load path.

    Attributes
    ----------
    steps
        The accepted steps in order.
    displacements
        (n_steps, n_nodes, 3) nodal displacements [mm] after each step.
    factorisations
        Tangent factorisations over the whole path, failed steps included (fewer than
        the Newton iterations with ``reuse_factors``).
    """

    steps: tuple[StepRecord, ...]
    displacements: np.ndarray
    factorisations: int = 0

    @property
    def u(self) -> np.ndarray:
        """Final nodal displacements (n_nodes, 3) [mm]."""
        return self.displacements[-1]

    @property
    def newton_iterations(self) -> int:
        """Total Newton iterations over all accepted steps."""
        return int(sum(s.iterations for s in self.steps))


def solve(
    body: HyperelasticBody,
    *,
    fixed_dofs: np.ndarray,
    fixed_values: np.ndarray | None = None,
    loads: Sequence[tuple[FollowerPressure, float]] = (),
    steps: int = 10,
    load_factors: Sequence[float] | np.ndarray | None = None,
    max_iter: int = 20,
    rtol: float = 1e-8,
    max_cutbacks: int = 8,
    method: str | None = None,
    progress: bool = False,
    reuse_factors: bool = False,
    predictor: str = "quadratic",
) -> NonlinearResult:
    """Solve the body under follower pressures and prescribed displacements.

    Parameters
    ----------
    body
        The hyperelastic body.
    fixed_dofs
        Constrained vector DOFs (``3 * node + component``).
    fixed_values
        Final values of the constrained DOFs [mm] (default 0), applied as λ·value.
    loads
        (pressure load, final pressure [MPa]) pairs, applied as λ·p.
    steps
        Planned number of equal load increments (≥ 1).
    load_factors
        Instead of ``steps``: the increasing load factors in (0, 1] to stop at (the last
        must be 1); each is reached exactly, cutbacks insert sub-steps between them.
    max_iter
        Newton iterations allowed per step before a cutback.
    rtol
        Convergence when ‖R_free‖ ≤ rtol·max(‖f_ext‖, ‖reactions‖), i.e. the
        out-of-balance forces are below rtol of the forces in play.
    max_cutbacks
        Consecutive halvings allowed before giving up.
    method
        Linear solver (:class:`softcath.fem.nonlinear.linsolve.TangentSolver`): ``"pardiso"``
        (default when installed and large), ``"pardiso-lu"``, ``"superlu"``.
    progress
        Show a tqdm bar over the load factor.
    reuse_factors
        Modified Newton while it converges fast: after an iteration that lowered the residual
        by at least :data:`REUSE_RATIO`, the next one solves with the same factors instead of
        factorising the new tangent (the first iteration of every step factorises). The
        answer is the same to the tolerance ``rtol``; off by default.
    predictor
        Starting guess of each step (:func:`~softcath.fem.nonlinear.load_path.predict`):
        ``"quadratic"`` (default) through the last three equilibria, ``"secant"`` through two.

    Raises
    ------
    ConvergenceError
        When a step fails after ``max_cutbacks`` halvings.
    """
    targets = _load_targets(steps, load_factors, rtol)
    depth = check_predictor(predictor)
    problem = _set_up(
        body,
        fixed_dofs,
        fixed_values,
        loads,
        method,
        max_iter,
        rtol=rtol,
        max_cutbacks=max_cutbacks,
        reuse_factors=bool(reuse_factors),
    )
    lin = problem.lin
    bar = _progress_bar() if progress else None
    try:
        records, history = _load_path(problem, targets, bar, depth=depth)
    finally:
        lin.release()
        if bar is not None:
            bar.close()
    log.info(
        "%d factorisations (%s), %d LDLᵀ answers rejected for their residual",
        lin.factorisations,
        lin.method,
        lin.lu_fallbacks,
    )
    return NonlinearResult(
        steps=tuple(records), displacements=np.stack(history), factorisations=lin.factorisations
    )


@dataclass(frozen=True)
class _Problem:
    """What every load step of :func:`solve` needs."""

    body: HyperelasticBody
    fixed: np.ndarray
    values: np.ndarray
    free: np.ndarray
    mask: np.ndarray
    tmpl: sp.csr_matrix
    lin: TangentSolver
    loads: list[tuple[FollowerPressure, float]]
    residual: Callable
    max_iter: int
    rtol: float
    max_cutbacks: int
    reuse_factors: bool = False


def _set_up(
    body, fixed_dofs, fixed_values, loads, method, max_iter, *, rtol, max_cutbacks, reuse_factors=False
) -> _Problem:
    """Constraints, sparsity pattern, linear solver and residual of the problem."""
    fixed, values, free = _constraints(body, fixed_dofs, fixed_values)
    mask, tmpl = body.pattern.restrict(free)
    lin = TangentSolver(tmpl, method)
    loads = [(ld, float(p)) for ld, p in loads]
    return _Problem(
        body=body,
        fixed=fixed,
        values=values,
        free=free,
        mask=mask,
        tmpl=tmpl,
        lin=lin,
        loads=loads,
        residual=functools.partial(_residual, body, loads, fixed),
        max_iter=max_iter,
        rtol=rtol,
        max_cutbacks=max_cutbacks,
        reuse_factors=reuse_factors,
    )


def _load_path(
    problem: _Problem, targets: np.ndarray, bar, *, depth: int
) -> tuple[list[StepRecord], list[np.ndarray]]:
    """Step the load factor to 1 with cutbacks; returns the step records and displacements."""
    free, fixed = problem.free, problem.fixed
    u = np.zeros(problem.body.ndofs)
    lam, cutbacks = 0.0, 0
    # the last ``depth`` accepted equilibria (λ, u), oldest first, for the predictor
    path: list[tuple[float, np.ndarray]] = [(lam, u)]
    k_target = 0
    dlam = targets[0]
    records: list[StepRecord] = []
    history: list[np.ndarray] = []
    while lam < 1.0 - 1e-12:
        dlam = min(dlam, targets[k_target] - lam)
        target = lam + dlam
        if abs(target - targets[k_target]) < 1e-12:
            target = targets[k_target]
        trial = predict(path, target, free)
        dfixed = (target - lam) * problem.values[fixed]
        ok, its, res = _newton(
            problem.body,
            trial,
            target,
            free,
            problem.mask,
            problem.tmpl,
            lin=problem.lin,
            residual=problem.residual,
            max_iter=problem.max_iter,
            rtol=problem.rtol,
            fixed=fixed,
            dfixed=dfixed,
            line_search=cutbacks > 0,
            reuse_factors=problem.reuse_factors,
        )
        if not ok:
            cutbacks += 1
            log.info("step to load factor %.4g failed (%s); cutting back", target, res[-1] if res else "-")
            if cutbacks > problem.max_cutbacks:
                raise _convergence_error(lam, target, cutbacks, res, problem.rtol)
            dlam *= 0.5
            continue
        u = trial
        lam = target
        path = [*path[-(depth - 1) :], (lam, u)]
        records.append(_step_record(lam, problem.loads, its, res, cutbacks))
        history.append(u.reshape(-1, 3).copy())
        log.info("load factor %.4g: %d Newton iterations, residual %.2e", lam, its, res[-1])
        if bar is not None:
            bar.n = lam
            bar.refresh()
        cutbacks = 0
        if lam == targets[k_target] and k_target + 1 < targets.size:
            k_target += 1
        # grow back after cutbacks, at most doubling, never past the next target
        dlam = 2.0 * dlam
    return records, history


def _load_targets(steps, load_factors, rtol) -> np.ndarray:
    """Check ``steps`` and ``rtol`` and return the load factors to stop at."""
    if not (isinstance(steps, (int, np.integer)) and steps >= 1):
        raise SettingError("steps", steps, "must be an integer >= 1")
    if not (np.isfinite(rtol) and 0 < rtol < 1):
        raise SettingError("rtol", rtol, "must be in (0, 1)")
    if load_factors is None:
        return np.arange(1, steps + 1) / steps
    targets = np.asarray(load_factors, float)
    if (
        targets.ndim != 1
        or targets.size == 0
        or np.any(np.diff(targets) <= 0)
        or targets[0] <= 0
        or not np.isclose(targets[-1], 1.0)
    ):
        raise NonlinearError(f"load_factors = {targets!r}: must increase strictly within (0, 1] and end at 1")
    targets[-1] = 1.0
    return targets


def _constraints(body, fixed_dofs, fixed_values) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return the constrained DOFs, the final value of every DOF and the free DOFs."""
    fixed = np.unique(np.asarray(fixed_dofs, dtype=np.int64))
    if fixed.size == 0:
        raise NonlinearError("fixed_dofs: none; the body would float")
    values = np.zeros(body.ndofs)
    if fixed_values is not None:
        fv = np.asarray(fixed_values, float)
        values[np.asarray(fixed_dofs, dtype=np.int64)] = fv
    free = np.setdiff1d(np.arange(body.ndofs), fixed)
    return fixed, values, free


def _residual(body, loads, fixed, u, lam):
    """Residual at load factor ``lam``: (R, tangent data, reference force)."""
    f, data = body.internal(u)
    fext = np.zeros(body.ndofs)
    for ld, p in loads:
        ld.add_to(u, lam * p, fext, data)
    r = f + fext
    # forces in play: the applied loads and the support reactions (not the unbalanced
    # internal forces of an iterate, which would make the measure meaningless)
    ref = max(np.linalg.norm(fext), np.linalg.norm(r[fixed]), 1e-300)
    return r, data, ref


def _progress_bar():
    """A tqdm bar over the load factor."""
    from tqdm import tqdm

    return tqdm(total=1.0, desc="load factor", unit="", bar_format="{l_bar}{bar}| {n:.3f}/1")


def _convergence_error(lam, target, cutbacks, res, rtol) -> ConvergenceError:
    """The error raised when a step fails after the last cutback."""
    last = f"{res[-1]:.3g}" if res else "n/a"
    return ConvergenceError(
        f"Newton failed: load factor {lam:.4g} reached, step to {target:.4g} did not converge "
        f"after {cutbacks - 1} cutbacks (last relative residual {last}, rtol {rtol:.1g}); "
        "no result returned — reduce the pressure or refine the mesh"
    )


def _step_record(lam, loads, its, res, cutbacks) -> StepRecord:
    """Record of an accepted step."""
    return StepRecord(
        load_factor=float(lam),
        pressures=tuple(lam * p for _, p in loads),
        iterations=its,
        residuals=tuple(res),
        cutbacks=cutbacks,
    )


#: A Newton correction this small relative to the displacement is round-off.
_DU_ROUNDOFF = 1e-11
#: Residual evaluations allowed in one line search.
_LS_TRIES = 5
#: A full Newton step is kept unless it multiplies the residual by more than this.
_LS_GROWTH = 100.0
#: With ``reuse_factors``: the factors are kept for the next iteration after one that divided the
#: residual by at least 1 / REUSE_RATIO (a modified-Newton step contracts about as much as the
#: tangent moved since its factorisation; below 0.1 the saved factorisation outweighs the extra
#: iteration it may cost).
REUSE_RATIO = 0.1


def _newton(
    body,
    u,
    lam,
    free,
    mask,
    tmpl,
    *,
    lin,
    residual,
    max_iter,
    rtol,
    fixed,
    dfixed,
    line_search=False,
    reuse_factors=False,
):
    """Newton iterations in place on ``u``; returns (converged, iterations, residual history).

    The first iteration starts from the previous equilibrium and carries the
    prescribed-displacement increment through the tangent,
    K_ff Δu_f = −(R_f + K_fc Δu_c), instead of jumping the constrained nodes
    alone (which would crush the boundary layer of a near-incompressible body).

    The full Newton step is kept when it does not multiply the residual by
    more than ``_LS_GROWTH`` (and always in the first iteration of a step, whose
    residual starts from the previous equilibrium). Otherwise — and on every
    iteration with ``line_search`` (the retry of a step that failed) — a line
    search on g(α) = Δu · R(u + α Δu) follows (secant steps, at most ``_LS_TRIES``): the
    homogenised coil is ~10³ times stiffer across than along and than the
    silicone, so a full step can overshoot through the coil's Green-strain
    terms and the plain iteration oscillate. Searching on every iteration was
    measured to cost more than it saves: on the FElupe benchmark cantilever it
    shortens accepted steps that converge anyway (32 against 26 iterations), on
    the paper tip 41 against 32; switching it on within a step once the
    residual oscillates stalled the fine (24 segments per circle) paper tip.

    With ``reuse_factors`` an iteration after a fast one (residual ratio ≤ ``REUSE_RATIO``)
    solves with the previous factors (modified Newton); a slower one factorises again.
    """
    res: list[float] = []
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        r, data, ref = residual(u, lam)
        for it in range(1, max_iter + 1):
            rf = r[free]
            if not np.all(np.isfinite(rf)) or not np.all(np.isfinite(data)):
                return False, it, res
            first_with_bc = it == 1 and np.any(dfixed != 0)
            if first_with_bc:
                full = sp.csr_matrix((data, (body.pattern.rows, body.pattern.cols)), shape=(body.ndofs,) * 2)
                rf = rf + full[free][:, fixed] @ dfixed
                u[fixed] += dfixed
            if it > 1:
                rel = float(np.linalg.norm(rf) / ref)
                res.append(rel)
                if rel <= rtol:
                    return True, it - 1, res
                if len(res) >= 4 and rel > 1e3 * res[0]:
                    return False, it, res  # diverging
            if reuse_factors and len(res) >= 2 and res[-1] <= REUSE_RATIO * res[-2]:
                du = lin.resolve(-rf)
            else:
                k = tmpl.copy()
                k.data = data[mask]
                du = lin(k, -rf)
            if not np.all(np.isfinite(du)):
                return False, it, res
            r, data, ref, alpha = _line_search(
                u,
                du,
                rf,
                lam,
                free,
                residual,
                line_search=line_search,
                first_iter=it == 1,
                last_rel=res[-1] if res else None,
                first_with_bc=first_with_bc,
            )
            if (
                it > 1
                and res[-1] <= 1e-5
                and np.linalg.norm(alpha * du) <= _DU_ROUNDOFF * np.linalg.norm(u[free])
            ):
                # the correction is at round-off: the residual has hit its floor (stiff coil next
                # to soft silicone), further iterations cannot lower it
                return True, it, res
            if body.min_jacobian(u) <= 0:
                return False, it, res
        rel = float(np.linalg.norm(r[free]) / ref)
        res.append(rel)
        return rel <= rtol, max_iter, res


def _line_search(u, du, rf, lam, free, residual, *, line_search, first_iter, last_rel, first_with_bc):
    """Step ``u[free]`` along ``du``, searching on g(α) = Δu · R; returns (R, data, ref, α)."""
    u0 = u[free].copy()
    g0 = float(du @ rf)
    alpha, a_prev, g_prev = 1.0, 0.0, g0
    for tries in range(_LS_TRIES):
        u[free] = u0 + alpha * du
        r, data, ref = residual(u, lam)
        if tries == 0 and not line_search and np.all(np.isfinite(r[free])):
            rel_full = float(np.linalg.norm(r[free]) / ref)
            if first_iter or rel_full <= _LS_GROWTH * last_rel:
                break  # the full Newton step is accepted unless it makes the residual grow
        g = float(du @ r[free])
        if first_with_bc or not np.isfinite(g):
            if np.isfinite(g) or alpha < 1e-3:
                break
            alpha *= 0.5  # inverted elements: halve
            continue
        if abs(g) <= 0.5 * abs(g0) or g0 >= 0:
            break
        # secant toward g = 0 between the last two points, kept inside (0.05, 1]
        a_new = alpha - g * (alpha - a_prev) / (g - g_prev) if g != g_prev else alpha
        a_prev, g_prev = alpha, g
        alpha = float(np.clip(a_new, 0.05, 1.0))
        if alpha == a_prev:
            break
    return r, data, ref, alpha
