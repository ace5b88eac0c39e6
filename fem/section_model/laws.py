"""Region laws of the section model in generalised plane strain.

A region's law is reduced to what the section sees: the 4x4 stiffness over the
strains (eps_xx, eps_yy, eps_zz, gamma_xy) — out-of-plane shears vanish for the
axial force and bending moments of a pressurised tip — plus, for isotropic
regions, the Lamé modulus lambda that the assembly treats by projection (the
locking-free mixed part, ``softcath.fem.section_model.element``).

Unlike the 3-D FEM (displacement-only P2, nu <= 0.49), the section model takes
silicone Poisson ratios up to 0.49999: the volumetric term is projected onto
piecewise-linear pressures, so it does not lock.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from softcath.design.errors import DesignError
from softcath.fem.adapter import COIL_MODULI, coil_law
from softcath.fem.geometry import CHANNEL, COIL, FILLER, TUBE
from softcath.fem.materials import TransverselyIsotropic

__all__ = ["SectionLaw", "isotropic", "from_tensor", "section_laws_from_design", "NU_MAX"]

#: Largest Poisson ratio accepted (lambda/mu = 5e4: a direct solve still has ~11 digits).
NU_MAX = 0.49999
_PLANE = (0, 1, 2)  # xx, yy, zz in tensor indices; gamma_xy handled separately
#: Voigt rows of (eps_xx, eps_yy, eps_zz, gamma_xy): what :func:`from_tensor` picks from the tensor.
_SECTION_VOIGT = np.ix_((0, 1, 2, 5), (0, 1, 2, 5))


@dataclass(frozen=True)
class SectionLaw:
    """Stiffness of one region as the section model uses it.

    Attributes
    ----------
    D
        4x4 stiffness (MPa) over (eps_xx, eps_yy, eps_zz, gamma_xy); for an isotropic
        region only its shear part diag(2 mu, 2 mu, 2 mu, mu).
    lam
        Lamé lambda (MPa) of the projected volumetric part (0 for anisotropic laws).
    axial_modulus
        E_z (MPa), the weight of the stiffness-weighted centroid.
    poisson_ratio
        nu of an isotropic law (NaN for anisotropic ones), as given.
    """

    D: np.ndarray
    lam: float
    axial_modulus: float
    poisson_ratio: float = float("nan")


def isotropic(youngs_modulus: float, poisson_ratio: float) -> SectionLaw:
    """Isotropic law, any nu in (-1, :data:`NU_MAX`]."""
    e, nu = float(youngs_modulus), float(poisson_ratio)
    if not (np.isfinite(e) and e > 0):
        raise DesignError("youngs_modulus", e, "must be finite and > 0")
    if not (-1.0 < nu <= NU_MAX):
        raise DesignError("poisson_ratio", nu, f"must be in (-1, {NU_MAX}] for the section model")
    lam = e * nu / ((1 + nu) * (1 - 2 * nu))
    mu = e / (2 * (1 + nu))
    return SectionLaw(np.diag([2 * mu, 2 * mu, 2 * mu, mu]), lam, e, nu)


def from_tensor(c: np.ndarray, axial_modulus: float) -> SectionLaw:
    """Law from a full stiffness tensor ``C[i, j, k, l]`` (``softcath.fem.materials``), no projection."""
    idx = [(0, 0), (1, 1), (2, 2), (0, 1)]
    d = np.array([[c[i, j, k, m] for (k, m) in idx] for (i, j) in idx])
    return SectionLaw(d, 0.0, float(axial_modulus))


def _coil(coil, coil_modulus: str, poisson: bool) -> SectionLaw:
    law = coil_law(coil, coil_modulus)
    if not poisson:
        law = TransverselyIsotropic(
            axial_modulus=law.axial_modulus,
            transverse_modulus=law.transverse_modulus,
            transverse_poisson=0.0,
            coupling_poisson=0.0,
            axial_shear_modulus=law.axial_shear_modulus,
        )
    # from_tensor(law.tensor(), ...) reads these entries back from the expanded tensor; taking
    # them from the Voigt matrix skips the expansion (~0.1 ms per design of a sweep).
    return SectionLaw(law.voigt()[_SECTION_VOIGT], 0.0, float(law.axial_modulus))


def section_laws_from_design(
    design,
    *,
    coil_modulus: str = "tension",
    poisson_cap: float | None = None,
    silicone_poisson: float | None = None,
    poisson: bool = True,
) -> Mapping[int, SectionLaw]:
    """Region label -> :class:`SectionLaw` for a :class:`design.TipDesign`.

    The section model's laws (2-D generalised plane strain, optional Poisson
    cap); the 3-D FEM's are :func:`softcath.fem.adapter.fem_laws_from_design`.

    Parameters
    ----------
    coil_modulus
        ``"tension"`` or ``"bending"``: the coils' homogenised axial modulus, as
        in the 3-D FEM (``softcath.fem.adapter``).
    poisson_cap
        Cap the silicones' Poisson ratios (0.49 reproduces the 3-D FEM's laws);
        ``None`` uses the design's own values.
    silicone_poisson
        Replace the Poisson ratio of every silicone (tube and filler), e.g. to
        trace the response as nu -> 0.5; applied before ``poisson_cap``.
    poisson
        ``False`` sets every Poisson ratio to 0 (the composite beam's assumption).
    """
    if coil_modulus not in COIL_MODULI:
        raise DesignError("coil_modulus", coil_modulus, f"must be one of {COIL_MODULI}")
    for name, value in (("poisson_cap", poisson_cap), ("silicone_poisson", silicone_poisson)):
        if value is not None and not (0.0 <= value <= NU_MAX):
            raise DesignError(name, value, f"must be in [0, {NU_MAX}]")

    def nu_of(material) -> float:
        if not poisson:
            return 0.0
        nu = material.poisson_ratio if silicone_poisson is None else silicone_poisson
        return min(nu, poisson_cap) if poisson_cap is not None else nu

    laws = {
        COIL: _coil(design.coil, coil_modulus, poisson),
        CHANNEL: _coil(design.channel, coil_modulus, poisson),
        TUBE: isotropic(design.tube.material.youngs_modulus, nu_of(design.tube.material)),
    }
    if design.filler is not None:
        laws[FILLER] = isotropic(design.filler.youngs_modulus, nu_of(design.filler))
    return laws
