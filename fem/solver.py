"""Sparse direct solve of the clamped stiffness system, factorised once.

PARDISO (``pypardiso``, symmetric positive definite mode on the upper
triangle) is the default: on this 2-core machine it beat SuperLU by 5x on
a 125k-DOF catheter tip (``benchmarks/bench_fem.py`` re-measures it). AMG-CG was not available (pyamg is not
installed) and CHOLMOD neither.
SuperLU stays as the dependency-free fallback. Every solve is checked: a
backward error above ``tol`` raises :class:`softcath.fem.errors.SolverError`
instead of returning a result.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from softcath.fem import pardiso
from softcath.fem.errors import SolverError
from softcath.fem.pardiso import PardisoError, PardisoHandle

__all__ = ["Factorized", "DEFAULT_TOL", "available_methods", "backward_error"]

log = logging.getLogger(__name__)

#: Normwise backward error ||K u - f|| / (||K|| ||u|| + ||f||) (infinity norms)
#: above which a solve is refused. The plain relative residual ||K u - f||/||f||
#: is no criterion here: with steel (1e5 MPa) next to silicone (0.1 MPa) its
#: rounding floor is eps ||K|| ||u|| / ||f|| ~ 1e-6 even for an exact solve.
#: The backward error of a stable direct solve is ~1e-16..1e-14; 1e-10 refuses
#: a broken factorisation (singular, perturbed pivots) without false alarms.
DEFAULT_TOL = 1e-10


def available_methods() -> tuple[str, ...]:
    """Solver back-ends usable here, preferred first."""
    # through the module, so that a test can make PARDISO unavailable
    return ("pardiso", "superlu") if pardiso.available() else ("superlu",)


class Factorized:
    """A factorised symmetric positive definite matrix.

    Parameters
    ----------
    matrix
        Square sparse SPD matrix (the clamped stiffness, N/mm).
    method
        ``"pardiso"`` (default when installed) or ``"superlu"``.
    tol
        Refuse solves whose relative residual exceeds this.
    """

    def __init__(self, matrix: sp.spmatrix, *, method: str | None = None, tol: float = DEFAULT_TOL):
        methods = available_methods()
        method = method or methods[0]
        if method not in methods:
            raise SolverError(f"solver method = {method!r}: must be one of {methods}")
        self.method = method
        self.tol = tol
        self.refinement_steps = 2
        self.matrix = sp.csr_matrix(matrix)
        self._knorm = float(abs(self.matrix).sum(axis=1).max())  # infinity norm
        if method == "pardiso":
            self._upper = sp.triu(self.matrix, format="csr")
            self._upper.sort_indices()
            # freed when this object is garbage-collected or on close(): a dropped pypardiso
            # solver kept its factors (~0.5 GB per design in a sweep process)
            self._solver = PardisoHandle(self._upper.indptr, self._upper.indices, mtype=2)  # real SPD
            try:
                self._solver.factorise(self._upper.data)
            except PardisoError as exc:
                raise SolverError(f"PARDISO factorisation failed: {exc}") from None
        else:
            import scipy.sparse.linalg as spla

            self._lu = spla.splu(self.matrix.tocsc())
        log.debug("factorised %d dofs with %s", self.matrix.shape[0], method)

    def solve(self, rhs: np.ndarray) -> tuple[np.ndarray, float]:
        """Solve ``K u = rhs`` (one or several columns).

        Returns
        -------
        u, residual
            The solution and the largest normwise backward error over the columns.

        Raises
        ------
        SolverError
            If a column's backward error is above ``tol`` (or not finite).
        """
        rhs = np.asarray(rhs, dtype=float)
        u = self._raw_solve(rhs)
        res = backward_error(self.matrix, u, rhs, self._knorm)
        # Iterative refinement if the factorisation lost digits (pivot perturbation).
        for _ in range(self.refinement_steps):
            if res <= 0.01 * self.tol:
                break
            u = u + self._raw_solve(rhs - self.matrix @ u)
            res = backward_error(self.matrix, u, rhs, self._knorm)
        if not np.isfinite(res) or res > self.tol:
            raise SolverError(
                f"linear solve backward error = {res:.3g}: must be <= {self.tol:.1g}; result refused"
            )
        return u, res

    def close(self) -> None:
        """Free the factors now (otherwise when this object is garbage-collected)."""
        if self.method == "pardiso":
            self._solver.release()

    def _raw_solve(self, rhs: np.ndarray) -> np.ndarray:
        if self.method == "pardiso":
            u = self._solver.solve(rhs)
        else:
            u = self._lu.solve(rhs)
        return np.asarray(u).reshape(rhs.shape)


def backward_error(matrix: sp.spmatrix, u: np.ndarray, rhs: np.ndarray, knorm: float | None = None) -> float:
    """Largest column-wise normwise backward error ``||K u - f|| / (||K|| ||u|| + ||f||)``.

    Infinity norms (Rigal and Gaches 1967; Higham, *Accuracy and Stability of
    Numerical Algorithms*, sec. 7.1): the smallest relative perturbation of K
    and f for which ``u`` is an exact solution. 0 for ``u = f = 0``.
    """
    if knorm is None:
        knorm = float(abs(matrix).sum(axis=1).max())
    r = (matrix @ u - rhs).reshape(rhs.shape[0], -1)
    u2 = u.reshape(u.shape[0], -1)
    f2 = rhs.reshape(rhs.shape[0], -1)
    out = 0.0
    for j in range(r.shape[1]):
        den = knorm * np.abs(u2[:, j]).max() + np.abs(f2[:, j]).max()
        nr = np.abs(r[:, j]).max()
        out = max(out, nr / den if den > 0 else nr)
    return float(out)
