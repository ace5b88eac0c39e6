"""Linear-elastic (and optional Yeoh hyperelastic) material data, in MPa."""

from __future__ import annotations

from dataclasses import dataclass

from softcath.core.errors import DesignError
from softcath.design import validation

__all__ = ["Material"]


@dataclass(frozen=True, kw_only=True)
class Material:
    """An isotropic material.

    Parameters
    ----------
    name
        Label used in reports, e.g. ``"Ecoflex 00-30"``.
    youngs_modulus
        Small-strain Young's modulus E [MPa].
    poisson_ratio
        Poisson's ratio ν, strictly inside (−1, 0.5).
    yeoh
        Optional Yeoh coefficients (C1, C2, C3) [MPa] for finite-strain analyses.
        When given, the small-strain modulus should be close to 6·C1.
    source
        Where the numbers come from (free text, kept in the TOML file).
    """

    name: str
    youngs_modulus: float
    poisson_ratio: float
    yeoh: tuple[float, float, float] | None = None
    source: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise DesignError("name", self.name, "must be a non-empty string")
        object.__setattr__(self, "youngs_modulus", validation.positive("youngs_modulus", self.youngs_modulus))
        object.__setattr__(
            self,
            "poisson_ratio",
            validation.in_open_interval("poisson_ratio", self.poisson_ratio, -1.0, 0.5),
        )
        if self.yeoh is not None:
            if not isinstance(self.yeoh, (tuple, list)) or len(self.yeoh) != 3:
                raise DesignError("yeoh", self.yeoh, "must be three coefficients (C1, C2, C3) in MPa")
            c = tuple(validation.finite(f"yeoh[{i}]", v) for i, v in enumerate(self.yeoh))
            if c[0] <= 0:
                raise DesignError("yeoh[0]", c[0], "C1 must be > 0")
            object.__setattr__(self, "yeoh", c)
        if not isinstance(self.source, str):
            raise DesignError("source", self.source, "must be a string")

    @property
    def shear_modulus(self) -> float:
        """G = E / (2(1 + ν)) [MPa]."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def bulk_modulus(self) -> float:
        """K = E / (3(1 − 2ν)) [MPa]."""
        return self.youngs_modulus / (3.0 * (1.0 - 2.0 * self.poisson_ratio))

    @property
    def lame(self) -> tuple[float, float]:
        """Lamé parameters (λ, μ) [MPa]."""
        e, nu = self.youngs_modulus, self.poisson_ratio
        return e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))
