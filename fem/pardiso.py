"""A thin MKL PARDISO handle: analyse a sparsity pattern once, factorise many times, free the factors.

pypardiso's ``PyPardisoSolver`` searches the file system for MKL on every
construction (~0.3 s), re-analyses the pattern on every ``factorize``, and
never frees MKL's factor memory unless told to: a solver dropped without
``free_memory`` leaks its factors (measured: a sweep process grew by
~0.5 GB per FEM design, 8 GB after 16 designs, and the page faults of that
memory pressure slowed every process on the machine). This handle loads MKL
once per process, keeps reordering and symbolic analysis (phase 11) for the
life of the pattern, and releases the factors (phase −1) on :meth:`release`
or when it is garbage-collected.
"""

from __future__ import annotations

import ctypes
import sys
import weakref
from pathlib import Path

import numpy as np

__all__ = ["PardisoHandle", "PardisoError", "available", "load_mkl"]

_MKL = None


class PardisoError(RuntimeError):
    """PARDISO returned an error code."""


def load_mkl():
    """The ``pardiso`` entry point of MKL, loaded once per process."""
    global _MKL
    if _MKL is None:
        # pip's mkl wheel puts libmkl_rt.so.N in <prefix>/lib; look there before pypardiso's recursive search
        found = sorted(Path(sys.prefix, "lib").glob("libmkl_rt.so*"))
        if found:
            lib = ctypes.CDLL(str(found[0]))
        else:
            import pypardiso

            lib = pypardiso.PyPardisoSolver().libmkl
        fn = lib.pardiso
        i32p = ctypes.POINTER(ctypes.c_int32)
        fn.argtypes = [ctypes.POINTER(ctypes.c_int64), i32p, i32p, i32p, i32p, i32p, ctypes.c_void_p]
        fn.argtypes += [i32p, i32p, i32p, i32p, i32p, i32p, ctypes.c_void_p, ctypes.c_void_p, i32p]
        fn.restype = None
        _MKL = fn
    return _MKL


def available() -> bool:
    """True when MKL PARDISO can be loaded (pypardiso installed with its MKL)."""
    import importlib.util

    # find_spec, not import: importing pypardiso builds a solver that searches the file system
    if importlib.util.find_spec("pypardiso") is None:
        return False
    try:
        load_mkl()
    except (ImportError, OSError, AttributeError):
        return False
    return True


def _call(fn, pt, mtype, phase, n, *, data, ia, ja, iparm, b) -> np.ndarray:
    b = np.asfortranarray(b, dtype=np.float64)
    x = np.zeros_like(b)
    err = ctypes.c_int32(0)
    i32 = ctypes.c_int32
    nrhs = 1 if b.ndim == 1 else b.shape[1]
    fn(
        pt.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)),
        ctypes.byref(i32(1)),
        ctypes.byref(i32(1)),
        ctypes.byref(i32(mtype)),
        ctypes.byref(i32(phase)),
        ctypes.byref(i32(n)),
        data.ctypes.data,
        ia.ctypes.data_as(ctypes.POINTER(i32)),
        ja.ctypes.data_as(ctypes.POINTER(i32)),
        None,
        ctypes.byref(i32(nrhs)),
        iparm.ctypes.data_as(ctypes.POINTER(i32)),
        ctypes.byref(i32(0)),
        b.ctypes.data,
        x.ctypes.data,
        ctypes.byref(err),
    )
    if err.value != 0:
        raise PardisoError(f"PARDISO phase {phase} (mtype {mtype}) failed with error {err.value}")
    return np.ascontiguousarray(x)


def _release(fn, pt, mtype, n, *, data, ia, ja, iparm, state) -> None:
    if state["factorised"]:
        state["factorised"] = False
        _call(fn, pt, mtype, -1, n, data=data, ia=ia, ja=ja, iparm=iparm, b=np.zeros(n))


class PardisoHandle:
    """PARDISO on one CSR pattern (0-based ``indptr``/``indices``; upper triangle for mtype 2/−2).

    Parameters
    ----------
    indptr, indices
        The fixed sparsity pattern.
    mtype
        PARDISO matrix type: 2 (SPD), −2 (symmetric indefinite), 1 (structurally
        symmetric), 11 (general).
    """

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, *, mtype: int) -> None:
        self._fn = load_mkl()
        self.n = int(np.asarray(indptr).size - 1)
        self.mtype = int(mtype)
        self.pt = np.zeros(64, np.int64)
        self.iparm = np.zeros(64, np.int32)  # iparm[0] = 0: PARDISO's defaults for mtype
        self.ia = np.ascontiguousarray(indptr, np.int32) + 1
        self.ja = np.ascontiguousarray(indices, np.int32) + 1
        self.data = np.zeros(self.ja.size)
        self._state = {"factorised": False}
        self._finalizer = weakref.finalize(
            self,
            _release,
            self._fn,
            self.pt,
            self.mtype,
            self.n,
            data=self.data,
            ia=self.ia,
            ja=self.ja,
            iparm=self.iparm,
            state=self._state,
        )

    def _run(self, phase: int, b: np.ndarray) -> np.ndarray:
        return _call(
            self._fn,
            self.pt,
            self.mtype,
            phase,
            self.n,
            data=self.data,
            ia=self.ia,
            ja=self.ja,
            iparm=self.iparm,
            b=b,
        )

    def factorise(self, data: np.ndarray) -> None:
        """Numerical factorisation of the matrix with these values (in pattern order)."""
        self.data[:] = data
        # the first call analyses too, on the real values: the non-symmetric ordering uses a
        # weighted matching, and analysing a zero matrix gave ~1.7x the fill
        self._run(22 if self._state["factorised"] else 12, np.zeros(self.n))
        self._state["factorised"] = True

    def solve(self, b: np.ndarray) -> np.ndarray:
        """Solve with the current factors; ``b`` (n,) or (n, k)."""
        if not self._state["factorised"]:
            raise PardisoError("solve before factorise")
        return self._run(33, b)

    def release(self) -> None:
        """Free MKL's factors now (also done when the handle is garbage-collected)."""
        self._finalizer()
