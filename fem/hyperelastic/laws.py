"""Hyperelastic laws: first Piola–Kirchhoff stress P(F) and tangent A = dP/dF.

All laws are objective (they depend on F only through C = FᵀF) and reduce to
linear elasticity at small strain, which the tests check.

- :class:`Yeoh` — decoupled compressible Yeoh, W = Σ C_k (Ī₁ − 3)^k + U(J),
  Ī₁ = J^(−2/3) tr C, U(J) = κ/2 (J − 1)². With C₂ = C₃ = 0 it is the
  compressible neo-Hookean solid (μ = 2 C₁); :func:`neo_hookean` builds that.
  The split into an isochoric part and U(J) is what the mixed (P2–P0,
  mean-dilatation) formulation needs: it replaces U(J) at the quadrature
  points by U of the element's mean J.
- :class:`AnisotropicSVK` — Saint Venant–Kirchhoff, S = ℂ : E with E the Green
  strain and a constant (here transversely isotropic) ℂ. This is the finite-
  strain coil: the homogenised coil is steel wire, its strains stay small
  while the tip rotates by large angles, and for small strain + large rotation
  S = ℂ : E is exact (it is the linear law written in the rotated frame), so it
  is the justified equivalent of a full anisotropic hyperelastic law here.

Moduli in MPa. ``F`` arrays carry the tensor indices last (``(..., 3, 3)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from softcath.design.errors import DesignError
from softcath.fem.hyperelastic.tensors import cofactor, det

__all__ = [
    "Yeoh",
    "AnisotropicSVK",
    "IsotropicLaw",
    "neo_hookean",
    "isotropic_from_young",
    "yeoh_at_modulus",
    "transversely_isotropic",
    "isotropic_tensor",
]

_I = np.eye(3)
_II = np.einsum("ik,JL->iJkL", _I, _I)  # I⊠I: dF_iJ/dF_kL


class IsotropicLaw(Protocol):
    """An isotropic finite-strain law as the section model's wrappers (pre-stretch, squeeze) see
    it: :class:`Yeoh`, or one already wrapped."""

    @property
    def bulk_modulus(self) -> float: ...

    @property
    def shear_modulus(self) -> float: ...

    def small_strain_tensor(self) -> np.ndarray: ...

    def energy(self, f: np.ndarray, *, volumetric: bool = True) -> np.ndarray: ...

    def stress_tangent(self, f: np.ndarray, *, volumetric: bool = True) -> tuple[np.ndarray, np.ndarray]: ...


def _check_positive(name: str, value: float) -> float:
    value = float(value)
    if not (np.isfinite(value) and value > 0):
        raise DesignError(name, value, "must be finite and > 0")
    return value


@dataclass(frozen=True, kw_only=True)
class Yeoh:
    """Decoupled compressible Yeoh solid.

    Parameters
    ----------
    c1, c2, c3
        Yeoh coefficients [MPa]; small-strain shear modulus μ = 2 c1.
    bulk_modulus
        κ [MPa] of the volumetric energy U(J) = κ/2 (J − 1)².
    """

    c1: float
    c2: float = 0.0
    c3: float = 0.0
    bulk_modulus: float
    splits_volume: bool = field(default=True, init=False)

    def __post_init__(self) -> None:
        _check_positive("c1", self.c1)
        _check_positive("bulk_modulus", self.bulk_modulus)
        for name in ("c2", "c3"):
            if not np.isfinite(getattr(self, name)):
                raise DesignError(name, getattr(self, name), "must be finite")

    @property
    def shear_modulus(self) -> float:
        """Small-strain μ = 2 C₁ [MPa]."""
        return 2.0 * self.c1

    def small_strain_tensor(self) -> np.ndarray:
        """The linearised stiffness ℂ[i, j, k, l] [MPa] (λ = κ − 2μ/3)."""
        mu = self.shear_modulus
        return isotropic_tensor(lam=self.bulk_modulus - 2.0 * mu / 3.0, mu=mu)

    def volumetric(self, j: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """U(J), U'(J), U''(J)."""
        k = self.bulk_modulus
        return 0.5 * k * (j - 1.0) ** 2, k * (j - 1.0), np.full_like(j, k)

    def _w(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        c1, c2, c3 = self.c1, self.c2, self.c3
        return (
            c1 * x + c2 * x**2 + c3 * x**3,
            c1 + 2 * c2 * x + 3 * c3 * x**2,
            2 * c2 + 6 * c3 * x,
        )

    def energy(self, f: np.ndarray, *, volumetric: bool = True) -> np.ndarray:
        """Strain energy density W(F) [MPa = mJ/mm³]."""
        j = det(f)
        i1 = np.einsum("...iJ,...iJ->...", f, f)
        w = self._w(j ** (-2.0 / 3.0) * i1 - 3.0)[0]
        return w + self.volumetric(j)[0] if volumetric else w

    def stress_tangent(self, f: np.ndarray, *, volumetric: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """P [MPa] (..., 3, 3) and A = dP/dF [MPa] (..., 3, 3, 3, 3) as ``A[..., i, J, k, L]``.

        With H = F⁻ᵀ, d = dĪ₁/dF = J^(−2/3) (2F − ⅔ I₁ H) and the identities
        dH_iJ/dF_kL = −H_iL H_kJ, d(cof F)/dF = J (H⊗H − H⊠H):

            A = W'' d⊗d + W' J^(−2/3) [2 I⊠I − 4/3 (F⊗H + H⊗F) + 4/9 I₁ H⊗H + ⅔ I₁ H⊠H]
                + J² U'' H⊗H + J U' (H⊗H − H⊠H)

        (⊗: [iJkL] = a_iJ b_kL; ⊠: [iJkL] = a_iL b_kJ), summed as five outer
        products on the flattened 9-vectors: one pass each instead of the
        einsum outer products and their swapped copies (3.5× faster).
        """
        shape = f.shape[:-2]
        cof = cofactor(f)
        j = det(f)
        h = cof / j[..., None, None]  # F⁻ᵀ
        i1 = np.einsum("...iJ,...iJ->...", f, f)
        jm = j ** (-2.0 / 3.0)
        _, w1, w2 = self._w(jm * i1 - 3.0)
        d1 = jm[..., None, None] * (2.0 * f - (2.0 / 3.0) * i1[..., None, None] * h)  # dĪ₁/dF
        p = w1[..., None, None] * d1
        c_hh = (4.0 / 9.0) * w1 * jm * i1
        c_sw = (2.0 / 3.0) * w1 * jm * i1
        if volumetric:
            _, u1, u2 = self.volumetric(j)
            p = p + u1[..., None, None] * cof
            c_hh = c_hh + j * j * u2 + j * u1
            c_sw = c_sw - j * u1
        n = int(np.prod(shape, dtype=np.int64))
        h9, f9, d9 = h.reshape(n, 9), f.reshape(n, 9), d1.reshape(n, 9)
        hh = h9[:, :, None] * h9[:, None, :]
        fh = f9[:, :, None] * h9[:, None, :]
        a = c_hh.reshape(n, 1, 1) * hh
        a += (-(4.0 / 3.0) * w1 * jm).reshape(n, 1, 1) * (fh + fh.transpose(0, 2, 1))
        a += w2.reshape(n, 1, 1) * (d9[:, :, None] * d9[:, None, :])
        a = a.reshape(n, 3, 3, 3, 3)
        a += c_sw.reshape(n, 1, 1, 1, 1) * hh.reshape(n, 3, 3, 3, 3).transpose(0, 1, 4, 3, 2)
        a += (2.0 * w1 * jm).reshape(n, 1, 1, 1, 1) * _II
        return p, a.reshape(*shape, 3, 3, 3, 3)


def neo_hookean(*, shear_modulus: float, bulk_modulus: float) -> Yeoh:
    """Compressible (decoupled) neo-Hookean solid: Yeoh with C₁ = μ/2, C₂ = C₃ = 0."""
    return Yeoh(c1=0.5 * _check_positive("shear_modulus", shear_modulus), bulk_modulus=bulk_modulus)


def yeoh_at_modulus(
    yeoh: tuple[float, float, float] | None, *, youngs_modulus: float, poisson_ratio: float
) -> tuple[float, float, float] | None:
    """A material's Yeoh fit scaled to the design's modulus (``None`` stays ``None``).

    The fit gives the shape of the stress-strain curve; the design's E sets its small-strain
    stiffness, as in the linear models: every coefficient is multiplied by
    ``E / (2 (1 + nu)) / (2 C1)`` so that the initial shear modulus ``2 C1`` is the linear
    models' ``E / (2 (1 + nu))``. A design that changes a silicone's E (a sweep path
    ``materials.NAME.youngs_modulus``) therefore changes its finite-strain law too.
    """
    if yeoh is None:
        return None
    c1, c2, c3 = (float(c) for c in yeoh)
    if not (c1 > 0 and math.isfinite(c1)):
        return yeoh  # refused by isotropic_from_young, naming yeoh[0]
    scale = float(youngs_modulus) / (2.0 * (1.0 + float(poisson_ratio))) / (2.0 * c1)
    return (c1 * scale, c2 * scale, c3 * scale)


def isotropic_from_young(
    *, youngs_modulus: float, poisson_ratio: float, yeoh: tuple[float, float, float] | None = None
) -> Yeoh:
    """A silicone law from E [MPa], ν (and optional Yeoh C₁..C₃ [MPa]).

    With ``yeoh`` the deviatoric part is the Yeoh fit and κ follows from
    μ = 2 C₁ and ν (so the small-strain Poisson ratio is ν); otherwise
    neo-Hookean with μ = E/(2(1+ν)), κ = E/(3(1−2ν)).
    """
    e = _check_positive("youngs_modulus", youngs_modulus)
    nu = float(poisson_ratio)
    if not (-1.0 < nu < 0.5):
        raise DesignError("poisson_ratio", nu, "must be in (-1, 0.5)")
    if yeoh is not None:
        c1, c2, c3 = (float(c) for c in yeoh)
        mu = 2.0 * _check_positive("yeoh[0]", c1)
        return Yeoh(c1=c1, c2=c2, c3=c3, bulk_modulus=2.0 * mu * (1 + nu) / (3 * (1 - 2 * nu)))
    return neo_hookean(shear_modulus=e / (2 * (1 + nu)), bulk_modulus=e / (3 * (1 - 2 * nu)))


@dataclass(frozen=True)
class AnisotropicSVK:
    """Saint Venant–Kirchhoff solid S = ℂ : E with a constant anisotropic ℂ [MPa].

    Parameters
    ----------
    tensor
        ℂ[i, j, k, l] [MPa] with minor and major symmetry (3, 3, 3, 3).
    """

    tensor: np.ndarray
    splits_volume: bool = field(default=False, init=False)

    def __post_init__(self) -> None:
        c = np.asarray(self.tensor, float)
        if c.shape != (3, 3, 3, 3) or not np.all(np.isfinite(c)):
            raise DesignError("tensor", c.shape, "must be a finite (3, 3, 3, 3) array")
        if not np.allclose(c, np.transpose(c, (2, 3, 0, 1)), rtol=1e-10, atol=1e-12 * np.abs(c).max()):
            raise DesignError("tensor", "C[ijkl] != C[klij]", "must have major symmetry")
        object.__setattr__(self, "tensor", c)

    def small_strain_tensor(self) -> np.ndarray:
        """ℂ itself [MPa]."""
        return self.tensor

    def energy(self, f: np.ndarray, *, volumetric: bool = True) -> np.ndarray:
        """W = ½ E : ℂ : E [MPa]."""
        e = 0.5 * (np.einsum("...aI,...aJ->...IJ", f, f) - _I)
        return 0.5 * np.einsum("...IJ,IJKL,...KL->...", e, self.tensor, e, optimize=True)

    def stress_tangent(self, f: np.ndarray, *, volumetric: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """P = F S and A_iJkL = δ_ik S_JL + F_iM ℂ_MJLQ F_kQ."""
        e = 0.5 * (np.einsum("...aI,...aJ->...IJ", f, f) - _I)
        s = np.einsum("IJKL,...KL->...IJ", self.tensor, e, optimize=True)
        p = f @ s
        a = np.einsum("ik,...JL->...iJkL", _I, s)
        a += np.einsum("...iM,MJLQ,...kQ->...iJkL", f, self.tensor, f, optimize=True)
        return p, a


def isotropic_tensor(*, lam: float, mu: float) -> np.ndarray:
    """ℂ[i, j, k, l] = λ δij δkl + μ (δik δjl + δil δjk) [MPa]."""
    return lam * np.einsum("ij,kl->ijkl", _I, _I) + mu * (
        np.einsum("ik,jl->ijkl", _I, _I) + np.einsum("il,jk->ijkl", _I, _I)
    )


# Voigt order xx, yy, zz, yz, xz, xy (engineering shear strains).
_VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))


def transversely_isotropic(
    *,
    axial_modulus: float,
    transverse_modulus: float,
    axial_shear_modulus: float,
    transverse_poisson: float = 0.3,
    coupling_poisson: float = 0.0,
) -> np.ndarray:
    """ℂ[i, j, k, l] [MPa] of a transversely isotropic solid with its axis along z.

    Parameters
    ----------
    axial_modulus
        E_L along z [MPa] (the coil's spring-like tension modulus).
    transverse_modulus
        E_T in the x–y plane [MPa] (the coil's steel hoop).
    axial_shear_modulus
        G_L for the xz, yz shears [MPa].
    transverse_poisson
        ν_TT in the x–y plane.
    coupling_poisson
        Dimensionless axial/transverse coupling ν_c: compliance S_xz = −ν_c/√(E_L E_T).
        Written this way ℂ stays positive definite for any E_T/E_L if ν_c² < (1 − ν_TT)/2,
        which a coil with E_T/E_L ~ 10⁵ needs (the usual ν_LT would not). 0 decouples
        the coil's axial stretch from its hoop, as a spring does.
    """
    el = _check_positive("axial_modulus", axial_modulus)
    et = _check_positive("transverse_modulus", transverse_modulus)
    gl = _check_positive("axial_shear_modulus", axial_shear_modulus)
    ntt, nc = float(transverse_poisson), float(coupling_poisson)
    if not (-1.0 < ntt < 0.5):
        raise DesignError("transverse_poisson", ntt, "must be in (-1, 0.5)")
    bound = np.sqrt((1.0 - ntt) / 2.0)
    if not abs(nc) < bound:
        raise DesignError("coupling_poisson", nc, f"must satisfy |nu_c| < {bound:.4g}")
    s = np.zeros((6, 6))
    s[0, 0] = s[1, 1] = 1.0 / et
    s[0, 1] = s[1, 0] = -ntt / et
    s[0, 2] = s[2, 0] = s[1, 2] = s[2, 1] = -nc / np.sqrt(el * et)
    s[2, 2] = 1.0 / el
    s[3, 3] = s[4, 4] = 1.0 / gl
    s[5, 5] = 2.0 * (1.0 + ntt) / et
    cv = np.linalg.inv(s)
    c = np.zeros((3, 3, 3, 3))
    for a, (i, j) in enumerate(_VOIGT):
        for b, (k, m) in enumerate(_VOIGT):
            c[i, j, k, m] = c[j, i, k, m] = c[i, j, m, k] = c[j, i, m, k] = cv[a, b]
    return c
