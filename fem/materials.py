"""Elastic laws for the linear FEM: isotropic and transversely isotropic.

A law is turned into a fourth-order stiffness tensor ``C[i, j, k, l]`` (MPa) so
the weak form is the same for every region: ``sigma = C : eps``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.design.errors import DesignError

__all__ = ["Isotropic", "TransverselyIsotropic", "voigt_to_tensor"]

# Voigt order xx, yy, zz, yz, xz, xy (engineering shear strains).
_VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))


def voigt_to_tensor(c_voigt: np.ndarray) -> np.ndarray:
    """Expand a 6x6 Voigt stiffness (engineering shear) into ``C[i, j, k, l]``."""
    c = np.zeros((3, 3, 3, 3))
    for a, (i, j) in enumerate(_VOIGT):
        for b, (k, m) in enumerate(_VOIGT):
            v = c_voigt[a, b]
            c[i, j, k, m] = c[j, i, k, m] = c[i, j, m, k] = c[j, i, m, k] = v
    return c


@dataclass(frozen=True)
class Isotropic:
    """Isotropic linear elastic law.

    Parameters
    ----------
    youngs_modulus
        E in MPa (> 0).
    poisson_ratio
        nu, -1 < nu <= 0.49 (displacement-only P2 locks above).
    """

    youngs_modulus: float
    poisson_ratio: float

    def __post_init__(self) -> None:
        _positive("youngs_modulus", self.youngs_modulus)
        if not (-1.0 < self.poisson_ratio <= 0.49):
            raise DesignError(
                "poisson_ratio",
                self.poisson_ratio,
                "must be in (-1, 0.49] (displacement-only P2 locks near 0.5)",
            )

    def tensor(self) -> np.ndarray:
        """Stiffness tensor ``C[i, j, k, l]`` in MPa."""
        e, nu = self.youngs_modulus, self.poisson_ratio
        lam = e * nu / ((1 + nu) * (1 - 2 * nu))
        mu = e / (2 * (1 + nu))
        d = np.eye(3)
        return lam * np.einsum("ij,kl->ijkl", d, d) + mu * (
            np.einsum("ik,jl->ijkl", d, d) + np.einsum("il,jk->ijkl", d, d)
        )


@dataclass(frozen=True)
class TransverselyIsotropic:
    """Transversely isotropic law with its axis along z (the catheter axis).

    Used for the homogenised coil: soft along the axis (the spring's
    equivalent modulus), stiff in the cross-section plane (the steel hoop).

    Parameters
    ----------
    axial_modulus
        E_L along z, MPa.
    transverse_modulus
        E_T in the x-y plane, MPa.
    transverse_poisson
        nu_TT, in-plane Poisson ratio.
    coupling_poisson
        Dimensionless axial/transverse coupling nu_c: the compliance term
        S_xz = -nu_c / sqrt(E_L E_T). Written this way it stays positive
        definite for any modulus ratio if nu_c^2 < (1 - nu_TT)/2, which a
        homogenised coil with E_T/E_L ~ 1e3 needs (the usual nu_LT would not).
    axial_shear_modulus
        G_L for the xz and yz shears, MPa.
    """

    axial_modulus: float
    transverse_modulus: float
    transverse_poisson: float
    coupling_poisson: float
    axial_shear_modulus: float

    def __post_init__(self) -> None:
        _positive("axial_modulus", self.axial_modulus)
        _positive("transverse_modulus", self.transverse_modulus)
        _positive("axial_shear_modulus", self.axial_shear_modulus)
        if not (-1.0 < self.transverse_poisson < 0.5):
            raise DesignError("transverse_poisson", self.transverse_poisson, "must be in (-1, 0.5)")
        bound = np.sqrt((1.0 - self.transverse_poisson) / 2.0)
        if not (abs(self.coupling_poisson) < bound):
            raise DesignError("coupling_poisson", self.coupling_poisson, f"must satisfy |nu_c| < {bound:.4g}")

    def tensor(self) -> np.ndarray:
        """Stiffness tensor ``C[i, j, k, l]`` in MPa."""
        return voigt_to_tensor(self.voigt())

    def voigt(self) -> np.ndarray:
        """6x6 Voigt stiffness (MPa, engineering shear; order of :func:`voigt_to_tensor`)."""
        el, et = self.axial_modulus, self.transverse_modulus
        ntt, nc, gl = self.transverse_poisson, self.coupling_poisson, self.axial_shear_modulus
        s13 = -nc / np.sqrt(el * et)
        s = np.zeros((6, 6))
        s[0, 0] = s[1, 1] = 1.0 / et
        s[0, 1] = s[1, 0] = -ntt / et
        s[0, 2] = s[2, 0] = s[1, 2] = s[2, 1] = s13
        s[2, 2] = 1.0 / el
        s[3, 3] = s[4, 4] = 1.0 / gl
        s[5, 5] = 2.0 * (1.0 + ntt) / et
        return np.linalg.inv(s)


def _positive(name: str, value: float) -> None:
    if not (np.isfinite(value) and value > 0):
        raise DesignError(name, value, "must be finite and > 0")
