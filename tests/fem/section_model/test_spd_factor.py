"""Repeated SPD factorisations and the compiled backward error, against dense linear algebra."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import sparse

from softcath.fem import pardiso
from softcath.fem.section_model.spd_factor import SpdFactor, backward_error


def _spd(n: int, seed: int) -> sparse.csr_matrix:
    """A sparse SPD matrix with a 2-D Laplacian's pattern and random positive weights."""
    rng = np.random.default_rng(seed)
    side = int(np.sqrt(n))
    line = 2 * sparse.eye(side) - sparse.eye(side, k=1) - sparse.eye(side, k=-1)
    lap = sparse.kron(sparse.eye(side), line) + sparse.kron(line, sparse.eye(side))
    d = sparse.diags(rng.uniform(0.5, 2.0, side * side))
    k = (d @ lap @ d).tocsr()
    k.sort_indices()
    return k


def _dense_backward_error(k, x, b) -> float:
    k = k.toarray()
    norm_k = np.abs(k).sum(axis=1).max()
    r = np.abs(k @ x - b).max(axis=0)
    return float((r / (norm_k * np.abs(x).max(axis=0) + np.abs(b).max(axis=0))).max())


@pytest.mark.parametrize("triangle", [sparse.triu, sparse.tril])
def test_backward_error_from_either_triangle_equals_the_dense_one(triangle):
    k = _spd(144, seed=1)
    rng = np.random.default_rng(2)
    b = rng.normal(size=(144, 4))
    x = np.linalg.solve(k.toarray(), b) + 1e-6 * rng.normal(size=(144, 4))  # a visibly inexact solution
    half = triangle(k).tocsr()
    half.sort_indices()
    got = backward_error(half.indptr, half.indices, half.data, x, b)
    assert got == pytest.approx(_dense_backward_error(k, x, b), rel=1e-12)
    assert got > 1e-8


@pytest.mark.parametrize("use_pardiso", [True, False], ids=["pardiso", "qdldl"])
def test_refactorised_solves_are_backward_stable(monkeypatch, use_pardiso):
    if use_pardiso and not pardiso.available():
        pytest.skip("MKL PARDISO is not installed")
    if not use_pardiso:
        monkeypatch.setattr(pardiso, "available", lambda: False)
    k = _spd(400, seed=3)
    factor = SpdFactor(k.indptr, k.indices)
    rng = np.random.default_rng(4)
    for scale in (1.0, 3.0, 1e-3):  # same pattern, new values: the analysis is reused
        b = rng.normal(size=(400, 4))
        factor.factorise(scale * k.data)
        x, err = factor.solve(b)
        assert np.allclose(scale * (k @ x), b, rtol=0, atol=1e-10 * np.abs(b).max())
        assert err < 1e-14


def test_solve_before_factorise_is_refused(monkeypatch):
    monkeypatch.setattr(pardiso, "available", lambda: False)
    k = _spd(16, seed=5)
    with pytest.raises(RuntimeError, match="solve before factorise"):
        SpdFactor(k.indptr, k.indices).solve(np.ones((16, 1)))
