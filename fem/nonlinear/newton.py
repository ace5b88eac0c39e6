"""Newton's method with load stepping and step cutback.

The load factor λ runs from 0 to 1 in ``steps`` equal increments; at each λ
every pressure is λ·p and every prescribed displacement λ·value. A step
that does not converge within ``max_iter`` iterations — or produces a
non-finite residual or an inverted element — is undone and retried at half
the increment; after ``max_cutbacks`` halvings in a row :class:`ConvergenceError`
is raised with the load reached and the last residual. The next step grows
back toward the planned increment. Each accepted step records its
iterations and relative residual history.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from fem.nonlinear.body import FollowerPressure, HyperelasticBody
from fem.nonlinear.errors import ConvergenceError, NonlinearError

__all__ = ["StepRecord", "NonlinearResult", "solve", "linear_solver"]

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
    """

    steps: tuple[StepRecord, ...]
    displacements: np.ndarray

    @property
    def u(self) -> np.ndarray:
        """Final nodal displacements (n_nodes, 3) [mm]."""
        return self.displacements[-1]

    @property
    def newton_iterations(self) -> int:
        """Total Newton iterations over all accepted steps."""
        return int(sum(s.iterations for s in self.steps))


#: Below this many free DOFs SuperLU beats PARDISO's per-call overhead on this
#: machine (2k DOFs: 55 ms PARDISO against a few ms SuperLU per factorisation).
PARDISO_MIN_DOFS = 20000


def linear_solver(method: str | None = None, *, ndofs: int | None = None) -> Callable:
    """A sparse solve ``(A_csr, b) -> x`` for the (non-symmetric) tangent.

    PARDISO in general non-symmetric mode (follower loads make the tangent
    non-symmetric) when installed and the system is large, else SuperLU.
    """
    if method is None and ndofs is not None and ndofs < PARDISO_MIN_DOFS:
        method = "superlu"
    if method in (None, "pardiso"):
        try:
            import pypardiso
        except ImportError:
            if method == "pardiso":
                raise NonlinearError("solver method = 'pardiso': pypardiso is not installed") from None
        else:
            solver = pypardiso.PyPardisoSolver(mtype=11)

            def solve_pardiso(a, b):
                a = a.tocsr()
                a.sort_indices()
                solver.factorize(a)
                return solver.solve(a, b)

            return solve_pardiso
    if method not in (None, "superlu", "pardiso"):
        raise NonlinearError(f"solver method = {method!r}: must be 'pardiso' or 'superlu'")
    import scipy.sparse.linalg as spla

    return lambda a, b: spla.splu(a.tocsc()).solve(b)


def solve(
    body: HyperelasticBody,
    *,
    fixed_dofs: np.ndarray,
    fixed_values: np.ndarray | None = None,
    loads: Sequence[tuple[FollowerPressure, float]] = (),
    steps: int = 10,
    max_iter: int = 20,
    rtol: float = 1e-8,
    max_cutbacks: int = 8,
    method: str | None = None,
    progress: bool = False,
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
    max_iter
        Newton iterations allowed per step before a cutback.
    rtol
        Convergence when ‖R_free‖ ≤ rtol·max(‖f_int‖, ‖f_ext‖) (reactions included),
        i.e. out-of-balance forces below rtol of the forces in play.
    max_cutbacks
        Consecutive halvings allowed before giving up.
    method
        Linear solver (``"pardiso"`` default when installed, ``"superlu"``).
    progress
        Show a tqdm bar over the load factor.

    Raises
    ------
    ConvergenceError
        When a step fails after ``max_cutbacks`` halvings.
    """
    if not (isinstance(steps, (int, np.integer)) and steps >= 1):
        raise NonlinearError(f"steps = {steps!r}: must be an integer >= 1")
    if not (np.isfinite(rtol) and 0 < rtol < 1):
        raise NonlinearError(f"rtol = {rtol!r}: must be in (0, 1)")
    fixed = np.unique(np.asarray(fixed_dofs, dtype=np.int64))
    if fixed.size == 0:
        raise NonlinearError("fixed_dofs: none; the body would float")
    values = np.zeros(body.ndofs)
    if fixed_values is not None:
        fv = np.asarray(fixed_values, float)
        values[np.asarray(fixed_dofs, dtype=np.int64)] = fv
    free = np.setdiff1d(np.arange(body.ndofs), fixed)
    mask, tmpl = body.pattern.restrict(free)
    lin = linear_solver(method, ndofs=free.size)
    loads = [(ld, float(p)) for ld, p in loads]

    def residual(u, lam, want_tangent=True):
        f, data = body.internal(u)
        fint_norm = np.linalg.norm(f)
        fext = np.zeros(body.ndofs)
        for ld, p in loads:
            ld.add_to(u, lam * p, fext, data)
        r = f + fext
        ref = max(fint_norm, np.linalg.norm(fext), 1e-300)
        return r, data, ref

    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=1.0, desc="load factor", unit="", bar_format="{l_bar}{bar}| {n:.3f}/1")
    u = np.zeros(body.ndofs)
    lam, dlam0 = 0.0, 1.0 / steps
    dlam, cutbacks = dlam0, 0
    records: list[StepRecord] = []
    history: list[np.ndarray] = []
    try:
        while lam < 1.0 - 1e-12:
            dlam = min(dlam, 1.0 - lam)
            target = lam + dlam
            trial = u.copy()
            dfixed = (target - lam) * values[fixed]
            ok, its, res = _newton(
                body, trial, target, free, mask, tmpl, lin, residual, max_iter, rtol, fixed=fixed, dfixed=dfixed
            )
            if not ok:
                cutbacks += 1
                log.info("step to load factor %.4g failed (%s); cutting back", target, res[-1] if res else "-")
                if cutbacks > max_cutbacks:
                    last = f"{res[-1]:.3g}" if res else "n/a"
                    raise ConvergenceError(
                        f"Newton failed: load factor {lam:.4g} reached, step to {target:.4g} did not converge "
                        f"after {cutbacks - 1} cutbacks (last relative residual {last}, rtol {rtol:.1g}); "
                        "no result returned — reduce the pressure or refine the mesh"
                    )
                dlam *= 0.5
                continue
            u = trial
            lam = target
            records.append(
                StepRecord(
                    load_factor=lam,
                    pressures=tuple(lam * p for _, p in loads),
                    iterations=its,
                    residuals=tuple(res),
                    cutbacks=cutbacks,
                )
            )
            history.append(u.reshape(-1, 3).copy())
            log.info("load factor %.4g: %d Newton iterations, residual %.2e", lam, its, res[-1])
            if bar is not None:
                bar.n = lam
                bar.refresh()
            cutbacks = 0
            dlam = min(2.0 * dlam, dlam0)
    finally:
        if bar is not None:
            bar.close()
    return NonlinearResult(steps=tuple(records), displacements=np.stack(history))


#: A Newton correction this small relative to the displacement is round-off.
_DU_ROUNDOFF = 1e-11


def _newton(body, u, lam, free, mask, tmpl, lin, residual, max_iter, rtol, *, fixed, dfixed):
    """Newton iterations in place on ``u``; returns (converged, iterations, residual history).

    The first iteration starts from the previous equilibrium and carries the
    prescribed-displacement increment through the tangent,
    K_ff Δu_f = −(R_f + K_fc Δu_c), instead of jumping the constrained nodes
    alone (which would crush the boundary layer of a near-incompressible body).
    """
    res: list[float] = []
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for it in range(1, max_iter + 1):
            r, data, ref = residual(u, lam)
            rf = r[free]
            if not np.all(np.isfinite(rf)) or not np.all(np.isfinite(data)):
                return False, it, res
            if it == 1 and np.any(dfixed != 0):
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
            k = tmpl.copy()
            k.data = data[mask]
            du = lin(k, -rf)
            if not np.all(np.isfinite(du)):
                return False, it, res
            u[free] += du
            if it > 1 and res[-1] <= 1e-5 and np.linalg.norm(du) <= _DU_ROUNDOFF * np.linalg.norm(u[free]):
                # the correction is at round-off: the residual has hit its floor (stiff coil next
                # to soft silicone), further iterations cannot lower it
                return True, it, res
            if body.min_jacobian(u) <= 0:
                return False, it, res
        r, _, ref = residual(u, lam)
        rel = float(np.linalg.norm(r[free]) / ref)
        res.append(rel)
        return rel <= rtol, max_iter, res
