"""Newton's method with load stepping on the template path (:mod:`.fast`).

The same walk as :func:`~softcath.fem.section_model.finite_strain.newton.walk` (Euler
predictor along the load path, the mixed u-p Newton iteration, steps that grow after
easy convergence and halve after a failure, the same convergence test on the full
residual, a :class:`SectionConvergenceError` naming the pressure reached), on the
compiled assembly with the bubbles condensed: each iteration factorises the retained
block once (its analysis kept per template) and eliminates the globals through their
3 x 3 Schur complement. Pressure loads only (the catheter's; the verification moments
stay on the reference path).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import splu

from softcath.design.errors import DesignError
from softcath.fem.errors import SolverError
from softcath.fem.pardiso import PardisoError
from softcath.fem.section_model.finite_strain.fast import FastProblem
from softcath.fem.section_model.finite_strain.newton import SectionConvergenceError, State

__all__ = ["StateAssembly", "assemble", "walk", "linear_rate"]

log = logging.getLogger(__name__)

#: Modified Newton (the factorised tangent of an earlier iterate) goes on while its steps cut the
#: residual by this factor at least and are expected to converge within :data:`CHORD_STEPS` more
#: steps; otherwise the tangent is assembled and factorised afresh. A step of modified Newton
#: costs a residual assembly and a solve, about a fifth of a tangent and its factorisation.
CONTRACTION = 0.5
CHORD_STEPS = 2
PREDICTOR = "euler"


@dataclass
class StateAssembly:
    """Residual (and, with ``tangent``, the condensed tangent) of one state, and per-triangle data."""

    tangent: bool
    norm: float
    ext: float
    rowsum: float
    data: np.ndarray | None
    k_ug: np.ndarray | None  # (n_free, 3)
    k_gu: np.ndarray | None  # (3, n_free)
    k_gg: np.ndarray | None
    r_u: np.ndarray  # condensed, free retained
    r_g: np.ndarray  # condensed
    xb: np.ndarray
    kbi: np.ndarray
    xbr: np.ndarray
    pe: np.ndarray
    mg: np.ndarray
    max_strain: float
    volume: np.ndarray  # (V', a, s_1, s_2)
    load_u: np.ndarray  # unit-pressure forces on the free retained unknowns (lumen load)
    load_g: np.ndarray

    def tangent_blocks(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(data, k_ug, k_gu, k_gg): the condensed tangent of an assembly made with one."""
        if self.data is None or self.k_ug is None or self.k_gu is None or self.k_gg is None:
            raise SolverError("a residual-only assembly (a modified Newton step) has no tangent to factorise")
        return self.data, self.k_ug, self.k_gu, self.k_gg


def assemble(
    prob: FastProblem, q: np.ndarray, pressure: float, load: str, given, stale=None
) -> StateAssembly | None:
    """Residual and tangent at ``q`` under ``pressure`` [MPa] (None for an inverted state).

    ``stale``: an earlier :class:`StateAssembly` with a tangent; then the residual alone is
    assembled, condensed with that tangent's bubble maps (a modified Newton step).
    """
    # numba: heavy, loaded on first use
    from softcath.fem.section_model.finite_strain.kernel import assemble as kernel_assemble
    from softcath.fem.section_model.finite_strain.kernel import lumen

    tpl = prob.tpl
    k = tpl.k
    nel = k.nel
    tangent = stale is None
    ue = q[tpl.local[:, :14]]
    g = q[tpl.N :]
    data = np.zeros(k.nnz if tangent else 0)
    k_ug = np.zeros((tpl.n, 3))
    r_raw = np.zeros(tpl.n)
    r_cond = np.zeros(tpl.n)
    out_g = np.zeros((5, 3))
    xb = np.empty((nel, 2, 15)) if tangent else stale.xb
    kbi = np.empty((nel, 2, 2)) if tangent else stale.kbi
    xbr = np.empty((nel, 2))
    pe = np.zeros((nel, 3))
    mg = np.zeros((nel, 3, 17))
    stats = np.zeros(3)
    use_given = given is not None
    kernel_assemble(
        ue, g, prob.w, prob.gs, tpl.phi, prob.xq, prob.pq, prob.minv, prob.kind, prob.yeoh, prob.svk,
        prob.silicone, given if use_given else pe, use_given, k.slot_rr, tpl.rdof, tangent, data,
        k_ug, r_raw, r_cond, out_g, xb, kbi, xbr, pe, mg, stats,
    )  # fmt: skip
    if not stats[0] > 0:
        return None
    nf = tpl.l_local.shape[0]
    vol = np.zeros(4)
    du, dug, duu = np.empty((nf, 14)), np.empty((nf, 14, 3)), np.empty((nf, 14, 14))
    lumen(q[tpl.l_local[:, :14]], g, prob.l_points, prob.l_tangents, prob.l_weights, tpl.lphi, tpl.ldphi,
          vol, du, dug, duu)  # fmt: skip
    lam = g[0]
    base = vol[1] + g[1] * vol[2] + g[2] * vol[3]
    dg = np.array([base, lam * vol[2], lam * vol[3]])
    load_u = np.bincount(tpl.l_rdof.ravel(), du[:, :12].ravel(), minlength=tpl.n)
    r_g_raw, r_g, k_gg = out_g[0], out_g[1], out_g[2:]
    k_gu = k_ug.T.copy()
    ext = 0.0
    p = pressure
    if p != 0.0:
        if tangent:
            rows = tpl.l_rdof.ravel()
            dug_r = -p * dug[:, :12].reshape(-1, 3)
            np.add.at(k_gu.T, rows, dug_r)
            dgg = np.zeros((3, 3))
            dgg[0, 1:] = dgg[1:, 0] = vol[2:]
            k_gg = k_gg - p * dgg
        if load == "lumen":
            r_raw -= p * load_u
            r_cond -= p * load_u
            ext += float(np.sum((p * du) ** 2))
            if tangent:
                np.add.at(k_ug, rows, dug_r)
                slots = tpl.l_slot.ravel()
                ok = slots >= 0
                data += np.bincount(slots[ok], (-p * duu[:, :12, :12]).ravel()[ok], minlength=k.nnz)
        r_g_raw = r_g_raw - p * dg
        r_g = r_g - p * dg
        ext += float(np.sum((p * dg) ** 2))
    free = tpl.free
    norm = float(np.sqrt(np.sum(r_raw[free] ** 2) + stats[2] + np.sum(r_g_raw**2)))
    if tangent:
        a_rows = abs(sparse.csr_matrix((data, k.indices, k.indptr), shape=(free.size, free.size))).sum(axis=1)
        rowsum = float(np.max(np.asarray(a_rows).ravel() + np.abs(k_ug[free]).sum(axis=1)))
    else:
        rowsum = stale.rowsum
    return StateAssembly(
        tangent=tangent,
        norm=norm,
        ext=float(np.sqrt(ext)),
        rowsum=rowsum,
        data=data if tangent else None,
        k_ug=k_ug[free] if tangent else None,
        k_gu=k_gu[:, free] if tangent else None,
        k_gg=k_gg if tangent else None,
        r_u=r_cond[free],
        r_g=r_g,
        xb=xb,
        kbi=kbi,
        xbr=xbr,
        pe=pe,
        mg=mg,
        max_strain=float(stats[1]),
        volume=vol,
        load_u=load_u[free],
        load_g=dg,
    )


class _Factor:
    """The condensed tangent of one assembly, factorised: retained block and the globals' Schur
    complement. ``b_u`` (optional) is solved with the globals' columns in the same pass."""

    def __init__(self, prob: FastProblem, a: StateAssembly, b_u: np.ndarray | None = None) -> None:
        self.tpl = prob.tpl
        self.a = a
        self.data, self.k_ug, self.k_gu, k_gg = a.tangent_blocks()
        rhs = self.k_ug if b_u is None else np.column_stack([self.k_ug, b_u])
        try:  # Cholesky: a stable state's retained block is positive definite
            y = self._cholesky(np.ascontiguousarray(rhs))
            self._solve = self._spd_solve
        except PardisoError:  # not positive definite: SuperLU on the same block
            k = self.tpl.k
            mat = sparse.csc_matrix((self.data, k.indices, k.indptr), shape=(k.free.size, k.free.size))
            lu = splu(mat, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.1)
            y = lu.solve(rhs)
            self._solve = lu.solve
        self.y = y[:, :3]
        self.first = None if b_u is None else y[:, 3]
        self.schur = k_gg - self.k_gu @ self.y

    def _cholesky(self, rhs: np.ndarray) -> np.ndarray:
        spd = self.tpl.spd()
        spd.factorise(self.data)
        self.tpl.factorisations += 1
        self.stamp = self.tpl.factorisations
        return spd.solve(rhs, check=False)[0]

    def _spd_solve(self, b: np.ndarray) -> np.ndarray:
        if self.tpl.factorisations != self.stamp:  # the template's handle was refactorised since
            self._cholesky(self.k_ug)
        return self.tpl.spd().solve(b, check=False)[0]

    def solve(self, b_u: np.ndarray | None, b_g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(retained, global) solution with right-hand side (b_u, b_g); ``b_u`` None: the one given
        at factorisation."""
        if b_u is not None:
            y0 = self._solve(np.ascontiguousarray(b_u[:, None]))[:, 0]
        elif self.first is not None:
            y0 = self.first
        else:
            raise SolverError("no right-hand side: none was given at factorisation")
        dg = np.linalg.solve(self.schur, b_g - self.k_gu @ y0)
        return y0 - self.y @ dg, dg


def _full_step(prob: FastProblem, xb: np.ndarray, xbr, du: np.ndarray, dg: np.ndarray):
    """The step over all unknowns: retained and globals given, bubbles recovered with the maps ``xb``
    (and ``xbr``, the bubbles' residual term, or None for a load rate)."""
    tpl = prob.tpl
    step = np.zeros(prob.ndofs)
    step[tpl.free] = du
    step[tpl.N :] = dg
    local = np.concatenate([step[tpl.rdof], np.broadcast_to(dg, (tpl.rdof.shape[0], 3))], axis=1)
    bub = -np.einsum("ebm,em->eb", xb, local)
    if xbr is not None:
        bub -= xbr
    step[tpl.bdof] = bub
    return step


def _pressures_after(prob: FastProblem, a: StateAssembly, step: np.ndarray) -> np.ndarray:
    """Projected pressures linearised along ``step`` from ``a``'s state (``newton.pressures_after``)."""
    return a.pe + np.einsum("eal,el->ea", a.mg, step[prob.tpl.local])


def _renew(norm: float, previous: float, target: float) -> bool:
    """Whether a modified Newton iteration that took the residual from ``previous`` to ``norm``
    should stop for a fresh tangent (too slow to reach ``target`` in :data:`CHORD_STEPS` steps)."""
    rate = norm / previous
    if not rate < CONTRACTION:
        return True
    return np.log(target / norm) / np.log(rate) > CHORD_STEPS


def _newton(prob, q0, p, load, given, lu: _Factor | None, *, tol, max_iter):
    """Newton iterations on the u-p pair at pressure ``p`` from ``q0``: the factorised tangent ``lu``
    (of an earlier state, or None) is kept while its steps cut the residual by :data:`CONTRACTION`,
    and renewed at the iterate where they do not. Returns (state, factor, the state's assembly)."""
    q = q0.copy()
    fail = (None, None, None)
    previous = None
    for it in range(1, max_iter + 1):
        a = assemble(prob, q, p, load, given, None if lu is None else lu.a)
        if a is None:
            return fail
        scale = max(a.ext, 1e-300)
        floor = np.finfo(float).eps * a.rowsum * prob.size
        if a.norm <= max(tol * scale, floor):
            return State(q, p, it - 1, a.norm / scale, a.max_strain), lu, a
        if not np.isfinite(a.norm):
            return fail
        try:
            if not a.tangent and previous is not None and _renew(a.norm, previous, tol * scale):
                a = assemble(prob, q, p, load, given)  # the old tangent is too far off: renew it here
                if a is None:
                    return fail
            if a.tangent or lu is None:  # (lu is None only for an assembly with its tangent)
                lu = _Factor(prob, a, -a.r_u)
                du, dg = lu.solve(None, -a.r_g)
            else:
                du, dg = lu.solve(-a.r_u, -a.r_g)
        except (RuntimeError, np.linalg.LinAlgError):  # singular tangent: a buckled or torn state
            return fail
        if not (np.all(np.isfinite(du)) and np.all(np.isfinite(dg))):
            return fail
        step = _full_step(prob, lu.a.xb, a.xbr, du, dg)
        given = _pressures_after(prob, a, step)
        previous = a.norm
        q = q + step
    return fail


def _rate(prob, lu: _Factor, a: StateAssembly, load: str, p_top: float) -> np.ndarray:
    """dq/dfactor at ``a``'s state with the factorised tangent ``lu`` (Euler predictor)."""
    f_u = p_top * a.load_u if load == "lumen" else np.zeros_like(a.load_u)
    du, dg = lu.solve(f_u, p_top * a.load_g)
    return _full_step(prob, lu.a.xb, None, du, dg)


def rest_state(prob: FastProblem) -> np.ndarray:
    """The unloaded tip: no displacement, lambda = 1, no curvature."""
    q = np.zeros(prob.ndofs)
    q[prob.n_u] = 1.0
    return q


def linear_rate(
    prob: FastProblem, load: str, p_top: float
) -> tuple[np.ndarray, tuple[StateAssembly, _Factor, np.ndarray]]:
    """dq/dfactor at rest, the linear solution under ``p_top`` (its k_2 is ``curve._linear_gain``),
    and the rest state's (assembly, factor, rate) for :func:`walk`'s first predictor."""
    q = rest_state(prob)
    a = assemble(prob, q, 0.0, load, None)
    if a is None:
        raise SolverError("the rest state of the template assembled as an inverted state")
    lu = _Factor(prob, a)
    rate = _rate(prob, lu, a, load, p_top)
    return rate, (a, lu, rate)


def walk(
    prob: FastProblem,
    p_top: float,
    load: str,
    factors: Sequence[float] | np.ndarray,
    *,
    tol: float = 1e-6,
    max_iter: int = 25,
    min_step: float = 1e-4,
    on_state: Callable[[State], None] | None = None,
    rest: tuple[StateAssembly, _Factor, np.ndarray] | None = None,
) -> tuple[list[State], list[StateAssembly]]:
    """Converged states at each load factor of the pressure ``p_top`` (``newton.walk``), with the
    assembly of each converged state (its lumen volume).

    The first predictor is the linear solution (``rest``, from :func:`linear_rate`, or made here).
    """
    q = rest_state(prob)
    f = np.asarray(factors, float)
    if f.ndim != 1 or f.size == 0 or np.any(f <= 0) or np.any(np.diff(f) <= 0):
        raise DesignError("load factors", f.tolist(), "must be positive and strictly increasing")
    states: list[State] = []
    converged: list[StateAssembly] = []
    done, previous = 0.0, None
    tan, lu, rate = linear_rate(prob, load, p_top)[1] if rest is None else rest
    step = float(f[0])
    for target in f:
        spent = 0
        while done < target * (1 - 1e-12):
            trial = min(step, target - done)
            state = None
            if rate is not None:  # predictor along the load path (tangent, and curvature once known)
                move = trial * rate
                if previous is not None and PREDICTOR == "hermite":
                    back = previous[1] - done
                    move += (trial / back) ** 2 * (previous[0] - q - back * rate)
                state, new_lu, new_tan = _newton(
                    prob,
                    q + move,
                    (done + trial) * p_top,
                    load,
                    _pressures_after(prob, tan, move),
                    None,  # a fresh tangent at the predicted state: an older one contracts poorly
                    tol=tol,
                    max_iter=max_iter,
                )
            if state is None:
                state, new_lu, new_tan = _newton(
                    prob, q, (done + trial) * p_top, load, None, None, tol=tol, max_iter=max_iter
                )
            if state is None:
                step = trial / 2
                if step < min_step * f[-1]:
                    error = SectionConvergenceError(done * p_top, target * p_top, "pressure")
                    error.states = states
                    error.assemblies = converged
                    raise error
                log.debug("cut back to step %.3g at factor %.4g", step, done)
                continue
            if new_tan is None:
                raise SolverError("a converged Newton state came without its assembly")
            previous = (q, done)
            q, done, tan = state.q, state.factor / p_top, new_tan
            lu = new_lu if new_lu is not None else lu
            rate = _rate(prob, lu, tan, load, p_top) if lu is not None else None
            spent += state.iterations
            if state.iterations <= 3:
                step = trial * 2.0
            last = replace(state, factor=done)
        states.append(replace(last, iterations=spent))
        converged.append(tan)
        if on_state is not None:
            on_state(states[-1])
    return states, converged
