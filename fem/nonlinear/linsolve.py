"""Linear solves for the Newton tangent.

The sparsity pattern of the tangent never changes during a solve, so
PARDISO's fill-reducing reordering and symbolic analysis (phase 11) run once
per pattern and each Newton iteration pays only the numerical factorisation
(phase 22) and the solve (phase 33): on the 5.9k-DOF benchmark cantilever
30 ms per iteration against 61 ms for pypardiso's analyse-and-factorise on
every call. A follower pressure makes the tangent non-symmetric, so it is
factorised by the general LU (mtype 11); a tangent that is exactly symmetric
(no follower load) takes the symmetric-indefinite LDLᵀ of its upper triangle
(mtype −2, 18 ms), checked by its residual. Preconditioning the follower-load
tangent with its symmetric part's LDLᵀ was measured and not kept: GMRES
needed 4–8 iterations (the load stiffness on a pressurised face is not
small), which cost more than the LU.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from softcath.fem import pardiso
from softcath.fem.nonlinear.errors import NonlinearError, SettingError

__all__ = ["TangentSolver", "PARDISO_MIN_DOFS"]

log = logging.getLogger(__name__)

#: Below this many free DOFs SuperLU beats PARDISO's per-call overhead on this
#: machine (2k DOFs: 55 ms PARDISO against a few ms SuperLU per factorisation;
#: 18k P2 DOFs of the catheter: PARDISO 5 s, SuperLU 12 s).
PARDISO_MIN_DOFS = 3000

#: Relative residual an LDLᵀ solve must reach (LU on these tangents: 1e-12 to 1e-9).
SYMMETRIC_RTOL = 1e-8


class TangentSolver:
    """Solves K x = b for tangents that share one CSR pattern.

    Parameters
    ----------
    template
        CSR matrix with the (structurally symmetric, sorted) pattern of every
        tangent to be solved.
    method
        ``"pardiso"`` (LDLᵀ for a symmetric tangent, else LU), ``"pardiso-lu"``
        (the general LU every time), ``"superlu"``; ``None`` picks PARDISO when
        installed and the system has at least :data:`PARDISO_MIN_DOFS` unknowns.

    Use as ``solver(k, b)`` with ``k`` on the template's pattern, and call
    :meth:`release` (or use it as a context manager) to free PARDISO's memory.
    """

    def __init__(self, template: sp.csr_matrix, method: str | None = None) -> None:
        if method not in (None, "pardiso", "pardiso-lu", "superlu"):
            raise SettingError("solver method", method, "must be 'pardiso', 'pardiso-lu' or 'superlu'")
        n = template.shape[0]
        if method is None:
            method = "pardiso" if n >= PARDISO_MIN_DOFS and pardiso.available() else "superlu"
        elif method.startswith("pardiso") and not pardiso.available():
            raise NonlinearError(f"solver method = {method!r}: pypardiso / MKL is not installed")
        self.method = method
        self.template = template
        self.lu_fallbacks = 0
        self.factorisations = 0
        self._sym = None
        self._lu = None
        #: solves with the factors of the last call (``resolve``), ``None`` before the first
        self._last = None
        if method == "pardiso":
            upper = template.copy()
            upper.data = np.arange(template.nnz, dtype=np.float64)
            transposed = upper.T.tocsr()
            transposed.sort_indices()
            if not (
                np.array_equal(transposed.indptr, template.indptr)
                and np.array_equal(transposed.indices, template.indices)
            ):
                raise NonlinearError("tangent pattern is not structurally symmetric; use method='pardiso-lu'")
            rows = np.repeat(np.arange(n), np.diff(template.indptr))
            keep = template.indices >= rows
            self._up = np.flatnonzero(keep)
            self._up_t = transposed.data.astype(np.int64)[keep]
            u_indptr = np.zeros(n + 1, np.int64)
            np.add.at(u_indptr, rows[keep] + 1, 1)
            self._upper_pattern = (np.cumsum(u_indptr), template.indices[keep])

    def __enter__(self) -> TangentSolver:
        return self

    def __exit__(self, *exc) -> None:
        self.release()

    def release(self) -> None:
        """Free PARDISO's factors (the solver cannot be used afterwards)."""
        for h in (self._sym, self._lu):
            if h is not None:
                h.release()

    def __call__(self, k: sp.csr_matrix, b: np.ndarray) -> np.ndarray:
        try:
            return self._solve(k, b)
        except pardiso.PardisoError as exc:
            raise NonlinearError(str(exc)) from None

    def resolve(self, b: np.ndarray) -> np.ndarray:
        """Solve with the factors of the last tangent solved (no new factorisation).

        For a modified Newton iteration: the answer is that of the last tangent, not the
        current one.
        """
        if self._last is None:
            raise NonlinearError("resolve: no tangent has been factorised yet")
        try:
            return self._last(b)
        except pardiso.PardisoError as exc:
            raise NonlinearError(str(exc)) from None

    def _solve(self, k: sp.csr_matrix, b: np.ndarray) -> np.ndarray:
        self.factorisations += 1
        if self.method == "superlu":
            self._last = spla.splu(k.tocsc(), permc_spec="MMD_AT_PLUS_A").solve
            return self._last(b)
        d = k.data
        if self.method == "pardiso-lu":
            return self._solve_lu(d, b)
        d_up, d_low = d[self._up], d[self._up_t]
        if np.max(np.abs(d_up - d_low), initial=0.0) <= 1e-13 * np.max(np.abs(d_up), initial=0.0):
            # K symmetric up to round-off (no follower load): LDLᵀ of the upper triangle, 0.6× the LU's cost
            if self._sym is None:
                self._sym = pardiso.PardisoHandle(*self._upper_pattern, mtype=-2)
            self._sym.factorise(0.5 * (d_up + d_low))
            x = self._sym.solve(b)
            # PARDISO perturbs tiny pivots; accept only an accurate answer
            if np.linalg.norm(b - k @ x) <= SYMMETRIC_RTOL * np.linalg.norm(b):
                self._last = self._sym.solve
                return x
            self.lu_fallbacks += 1
        return self._solve_lu(d, b)

    def _solve_lu(self, d: np.ndarray, b: np.ndarray) -> np.ndarray:
        if self._lu is None:
            self._lu = pardiso.PardisoHandle(self.template.indptr, self.template.indices, mtype=11)
        self._lu.factorise(d)
        self._last = self._lu.solve
        return self._lu.solve(b)
