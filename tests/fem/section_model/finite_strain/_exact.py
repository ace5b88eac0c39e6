"""Closed-form finite-strain solutions of incompressible neo-Hookean bodies (verification)."""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

_T, _W = np.polynomial.legendre.leggauss(80)


def _integral(f, a: float, b: float) -> float:
    """Gauss-Legendre on 80 points: exact to round-off for these smooth integrands."""
    r = 0.5 * (b - a) * _T + 0.5 * (a + b)
    return float(0.5 * (b - a) * np.dot(_W, f(r)))


def flexure_radii(alpha: float, h: float) -> tuple[float, float]:
    """Inner and outer radii of Rivlin's flexure of a block of thickness h turned alpha per length.

    Plane strain, no axial force: r^2 = r_a^2 + 2 (X + h/2)/alpha, and the free faces give
    r_a r_b = 1/alpha^2.
    """
    d, p = 2.0 * h / alpha, 1.0 / alpha**2
    ra2 = 0.5 * (-d + math.sqrt(d * d + 4 * p * p))
    return math.sqrt(ra2), math.sqrt(ra2 + d)


def flexure_moment(alpha: float, h: float, *, mu: float, width: float) -> float:
    """End moment of Rivlin's flexure (hoop stretch alpha r, radial 1/(alpha r))."""
    ra, rb = flexure_radii(alpha, h)

    def s_rr(r):
        return mu * (alpha**2 * (r * r - ra * ra) / 2 + (1 / r**2 - 1 / ra**2) / (2 * alpha**2))

    def s_tt(r):
        return s_rr(r) + mu * (alpha**2 * r * r - 1 / (alpha**2 * r * r))

    return width * _integral(lambda r: s_tt(r) * r, ra, rb)


def closed_tube(p: float, *, inner: float, outer: float, mu: float) -> tuple[float, float]:
    """Deformed inner radius and axial stretch of a closed thick tube under internal pressure p.

    Incompressible: R^2 = A^2 + lambda_z (r^2 - a^2); radial equilibrium gives
    p = int_a^b mu (l_t^2 - l_r^2) dr / r, and the axial force int s_zz 2 pi r dr equals
    the cap force p pi a^2.
    """

    def fields(a, lz, p):
        b = math.sqrt(a * a + (outer**2 - inner**2) / lz)

        def stretches(r):
            lt = r / np.sqrt(inner**2 + lz * (r * r - a * a))
            return lt, 1.0 / (lz * lt)

        def hoop(r):
            lt, lr = stretches(r)
            return mu * (lt * lt - lr * lr) / r

        def s_zz(r):
            s_rr = np.array([-p + _integral(hoop, a, ri) for ri in np.atleast_1d(r)])
            _, lr = stretches(r)
            return s_rr + mu * (lz * lz - lr * lr)

        return b, hoop, s_zz

    def equations(x, p):
        a, lz = x
        b, hoop, s_zz = fields(a, lz, p)
        radial = _integral(hoop, a, b) - p
        axial = 2 * math.pi * _integral(lambda r: s_zz(r) * r, a, b) - p * math.pi * a * a
        return [radial / mu, axial / (mu * outer**2)]

    guess = [inner, 1.0]
    for step in np.linspace(0.0, p, 11)[1:]:  # continuation from the rest state
        guess, _, ok, msg = optimize.fsolve(equations, guess, args=(step,), full_output=True, xtol=1e-12)
        if ok != 1:
            raise RuntimeError(msg)
    return float(guess[0]), float(guess[1])


def observed_rates(sizes, errors) -> np.ndarray:
    """log(e_i / e_{i+1}) / log(h_i / h_{i+1}) between consecutive meshes."""
    h, e = np.asarray(sizes, float), np.asarray(errors, float)
    return np.log(e[:-1] / e[1:]) / np.log(h[:-1] / h[1:])
