"""The tangent's fixed sparsity pattern and its factorisation.

Every Newton step of one section assembles element, lumen-wall and global
blocks on the same DOF tables, so the map from block entries to the free
rows and columns of a CSR matrix is computed once (:class:`Pattern`) and each
assembly is a single weighted ``bincount``. The factorisation reuses PARDISO's
symbolic analysis for the life of the pattern: the symmetric-indefinite LDL^T
of the upper triangle when the tangent is symmetric (the lumen load is
conservative), the general LU otherwise (the ``cap`` load's area follows the
deformation, so its tangent is not symmetric). Small systems, or machines
without MKL, use SuperLU.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import splu

from softcath.fem import pardiso

__all__ = ["Pattern", "factorise"]

#: Below this many unknowns SuperLU is used: on the catheter's 4k-DOF sections PARDISO's
#: factorisation is 2x faster on a quiet machine but several times slower when its threads
#: compete with other processes (a sweep's workers, a test run), SuperLU's single thread never.
PARDISO_MIN_DOFS = 20000

#: Relative residual a symmetric solve must reach before it is accepted (PARDISO
#: perturbs tiny pivots of indefinite matrices); otherwise the LU is used.
SYMMETRIC_RTOL = 1e-8


class Pattern:
    """Free-row/free-column CSR structure of the blocks on ``tables``.

    Parameters
    ----------
    tables
        Local DOF tables (m, nl) of each block kind, in the order their values are given.
    n
        Number of DOFs.
    free
        The unknowns that are solved for (the others are fixed).
    """

    def __init__(self, tables: Sequence[np.ndarray], n: int, free: np.ndarray) -> None:
        rows = np.concatenate(
            [np.broadcast_to(t[:, :, None], (t.shape[0], t.shape[1], t.shape[1])).ravel() for t in tables]
        )
        cols = np.concatenate(
            [np.broadcast_to(t[:, None, :], (t.shape[0], t.shape[1], t.shape[1])).ravel() for t in tables]
        )
        where = np.full(n, -1, dtype=np.int64)
        where[free] = np.arange(free.size)
        r, c = where[rows], where[cols]
        self.keep = np.flatnonzero((r >= 0) & (c >= 0))
        nf = free.size
        keys, self.inverse = np.unique(r[self.keep] * nf + c[self.keep], return_inverse=True)
        self.n, self.nnz = nf, keys.size
        row, col = keys // nf, keys % nf
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(row, minlength=nf))]).astype(np.int64)
        self.indices = col.astype(np.int64)
        self.transpose = np.searchsorted(keys, col * nf + row)  # entry of (j, i) for each (i, j)
        upper = col >= row
        self.upper = np.flatnonzero(upper)
        self.upper_indptr = np.concatenate([[0], np.cumsum(np.bincount(row[upper], minlength=nf))]).astype(
            np.int64
        )
        self.upper_indices = col[upper].astype(np.int64)
        self.handles: dict[int, object] = {}

    def matrix(self, values: np.ndarray) -> sparse.csr_matrix:
        """The free-free CSR matrix of the concatenated, flattened block ``values``."""
        data = np.bincount(self.inverse, weights=values[self.keep], minlength=self.nnz)
        return sparse.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))

    def release(self) -> None:
        """Free PARDISO's factors held for this pattern."""
        for h in self.handles.values():
            h.release()
        self.handles.clear()


class _SuperLU:
    def __init__(self, k: sparse.csr_matrix) -> None:
        self._lu = splu(
            k.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.1, options={"SymmetricMode": True}
        )

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self._lu.solve(b)


class _Pardiso:
    def __init__(self, pattern: Pattern, k: sparse.csr_matrix) -> None:

        self.k = k
        d = k.data
        d_t = d[pattern.transpose]
        scale = np.max(np.abs(d), initial=0.0)
        self.handle = None
        if np.max(np.abs(d - d_t), initial=0.0) <= 1e-10 * scale:
            h = pattern.handles.get(-2)
            if h is None:
                h = pattern.handles[-2] = pardiso.PardisoHandle(
                    pattern.upper_indptr, pattern.upper_indices, mtype=-2
                )
            h.factorise(0.5 * (d + d_t)[pattern.upper])
            self.handle = h
        self.pattern = pattern

    def _lu(self):

        h = self.pattern.handles.get(11)
        if h is None:
            h = self.pattern.handles[11] = pardiso.PardisoHandle(
                self.pattern.indptr, self.pattern.indices, mtype=11
            )
        h.factorise(self.k.data)
        self.handle = h

    def solve(self, b: np.ndarray) -> np.ndarray:
        if self.handle is None:
            self._lu()
        x = self.handle.solve(b)
        if self.handle.mtype == -2 and np.linalg.norm(b - self.k @ x) > SYMMETRIC_RTOL * np.linalg.norm(b):
            self._lu()
            x = self.handle.solve(b)
        return x


def factorise(pattern: Pattern, k: sparse.csr_matrix):
    """A factorisation of ``k`` (on ``pattern``) with a ``solve(b)`` method.

    Valid until the next factorisation on the same pattern (PARDISO keeps one set of
    factors per pattern and matrix type).
    """

    if pattern.n >= PARDISO_MIN_DOFS and pardiso.available():
        return _Pardiso(pattern, k)
    return _SuperLU(k)
