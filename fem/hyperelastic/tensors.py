"""Finite-strain kinematics on batches of 3x3 tensors.

Arrays carry the tensor indices last: ``F`` has shape ``(..., 3, 3)`` with
``F[..., i, J] = dx_i/dX_J`` (spatial index first, material index second).
"""

from __future__ import annotations

import numpy as np

__all__ = ["LEVI_CIVITA", "det", "cofactor", "dcofactor"]

LEVI_CIVITA = np.zeros((3, 3, 3))
LEVI_CIVITA[0, 1, 2] = LEVI_CIVITA[1, 2, 0] = LEVI_CIVITA[2, 0, 1] = 1.0
LEVI_CIVITA[0, 2, 1] = LEVI_CIVITA[2, 1, 0] = LEVI_CIVITA[1, 0, 2] = -1.0


def det(f: np.ndarray) -> np.ndarray:
    """J = det F, shape ``(...)``."""
    return (
        f[..., 0, 0] * (f[..., 1, 1] * f[..., 2, 2] - f[..., 1, 2] * f[..., 2, 1])
        - f[..., 0, 1] * (f[..., 1, 0] * f[..., 2, 2] - f[..., 1, 2] * f[..., 2, 0])
        + f[..., 0, 2] * (f[..., 1, 0] * f[..., 2, 1] - f[..., 1, 1] * f[..., 2, 0])
    )


def cofactor(f: np.ndarray) -> np.ndarray:
    """cof F = J F⁻ᵀ (Nanson: n da = cof F · N dA), shape ``(..., 3, 3)``."""
    c = np.empty_like(f)
    c[..., 0, 0] = f[..., 1, 1] * f[..., 2, 2] - f[..., 1, 2] * f[..., 2, 1]
    c[..., 0, 1] = f[..., 1, 2] * f[..., 2, 0] - f[..., 1, 0] * f[..., 2, 2]
    c[..., 0, 2] = f[..., 1, 0] * f[..., 2, 1] - f[..., 1, 1] * f[..., 2, 0]
    c[..., 1, 0] = f[..., 0, 2] * f[..., 2, 1] - f[..., 0, 1] * f[..., 2, 2]
    c[..., 1, 1] = f[..., 0, 0] * f[..., 2, 2] - f[..., 0, 2] * f[..., 2, 0]
    c[..., 1, 2] = f[..., 0, 1] * f[..., 2, 0] - f[..., 0, 0] * f[..., 2, 1]
    c[..., 2, 0] = f[..., 0, 1] * f[..., 1, 2] - f[..., 0, 2] * f[..., 1, 1]
    c[..., 2, 1] = f[..., 0, 2] * f[..., 1, 0] - f[..., 0, 0] * f[..., 1, 2]
    c[..., 2, 2] = f[..., 0, 0] * f[..., 1, 1] - f[..., 0, 1] * f[..., 1, 0]
    return c


def dcofactor(f: np.ndarray, cof: np.ndarray | None = None) -> np.ndarray:
    """d(cof F)_iJ / dF_kL = ε_ikm ε_JLM F_mM, shape ``(..., 3, 3, 3, 3)`` as ``[i, J, k, L]``.

    Evaluated as (C_iJ C_kL − C_iL C_kJ)/J with C = cof F, equal to the ε form for
    det F ≠ 0 and several times cheaper than the triple contraction.
    """
    c = cofactor(f) if cof is None else cof
    j = det(f)[..., None, None, None, None]
    return (c[..., :, :, None, None] * c[..., None, None, :, :] - np.einsum("...iL,...kJ->...iJkL", c, c)) / j
