"""Cross-section properties of simple shapes, vectorised with numpy broadcasting.

A shape is represented by its area moments about the horizontal axis y = 0:
A = ∫dA, Q = ∫y dA and I₀ = ∫y² dA. Composite shapes add and subtract these
moments; the centroid is Q/A and the second moment about any horizontal
axis y = y₀ follows from the parallel-axis theorem,
I(y₀) = I₀ − 2y₀Q + y₀²A. All lengths mm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Moments", "disc", "annulus", "ellipse", "hollow_ellipse"]


@dataclass(frozen=True)
class Moments:
    """Area moments of a plane region about y = 0 (arrays broadcast together).

    Attributes
    ----------
    area
        A [mm²].
    first
        Q = ∫ y dA [mm³].
    second
        I₀ = ∫ y² dA [mm⁴].
    """

    area: np.ndarray
    first: np.ndarray
    second: np.ndarray

    def __add__(self, other: Moments) -> Moments:
        return Moments(self.area + other.area, self.first + other.first, self.second + other.second)

    def __sub__(self, other: Moments) -> Moments:
        return Moments(self.area - other.area, self.first - other.first, self.second - other.second)

    @property
    def centroid(self) -> np.ndarray:
        """ȳ = Q/A [mm]."""
        return self.first / self.area

    def about(self, y0) -> np.ndarray:
        """Second moment about the horizontal axis y = y0 [mm⁴] (parallel-axis theorem)."""
        return self.second - 2 * y0 * self.first + np.square(y0) * self.area

    @property
    def centroidal(self) -> np.ndarray:
        """Second moment about the centroid's horizontal axis [mm⁴]."""
        return self.second - self.first**2 / self.area


def ellipse(a, b, yc=0.0) -> Moments:
    """Full ellipse, semi-axes a (x) and b (y), centre (0, yc): A = πab, I_c = πab³/4."""
    a, b, yc = np.asarray(a, float), np.asarray(b, float), np.asarray(yc, float)
    area = np.pi * a * b
    return Moments(area, area * yc, np.pi * a * b**3 / 4 + area * yc**2)


def disc(r, yc=0.0) -> Moments:
    """Full circle of radius r centred at (0, yc): I_c = πr⁴/4."""
    return ellipse(r, r, yc)


def annulus(r_outer, r_inner, yc=0.0) -> Moments:
    """Concentric ring: disc(r_outer) − disc(r_inner)."""
    return disc(r_outer, yc) - disc(r_inner, yc)


def hollow_ellipse(a, b, a_int, b_int, h, yc=0.0) -> Moments:
    """Ellipse (a, b) centred at (0, yc) minus a lumen ellipse (a_int, b_int) centred at (0, yc + h)."""
    return ellipse(a, b, yc) - ellipse(a_int, b_int, np.asarray(yc, float) + np.asarray(h, float))
