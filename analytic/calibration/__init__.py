r"""The paper's cross-section shape optimisation (eq. 8), in CasADi (Opti + IPOPT).

Decision variables: the free subset of x = [a, a_int, b_int, h] (mm), scaled
by the coil's inner radius R so they are of order one; b is fixed by the
assembly. The geometric domain X is explicit:

- outer ellipse inside the coil: a ≤ √(R b) (a simple bound, exact; see
  :func:`softcath.design.section.max_outer_semi_axis`);
- lumen inside the outer ellipse shrunk by the minimum wall t: sampled at
  N = 41 values of s = sin φ on [−1, 1], each
  a_int²(1 − s²)(b − t)² + (h + b_int s)²(a − t)² ≤ (1 − m)(a − t)²(b − t)²,
  where the margin m = Δs²/4 bounds the quadratic's excursion between samples,
  so the sampled constraints imply the exact one;
- lumen semi-axes ≥ 0.01 mm (a lumen must exist);
- tangency to coil and channel holds by construction (b and the tube centre).

Objective (eq. 8): w_ε Σ(ε(x) p_k − ε_k)² + w_κ Σ(κ(x) p_k − κ_k)², where ε(x),
κ(x) are the gains per MPa of eqs. 4 and 7. The model is linear in p, so the
sums reduce to five sufficient statistics (S_pp, S_pε, S_εε, S_pκ, S_κκ),
passed as Opti *parameters*: the cost of a solve does not grow with the
series. Default weights w = 1/Σy² make both terms relative.

Multistart from a grid over X (as the paper does); the result reports how
many starts reached the best objective. All starts are solved in one IPOPT
run: the Opti problem stacks the starts as columns of a decision matrix and
sums their (independent) objectives, so each column converges to its own
local optimum while the solver's set-up cost is paid once (falls back to one
start at a time if the batch fails). With two measured gains and four
free shape numbers the optimum is a 2-D family, not a point: the tie among
optimal starts is broken toward the nominal shape, and the result says
whether x is identifiable (rank of ∂(gains)/∂x). Fix parameters (``free``)
to make it identifiable. If no x in X reaches the data's gains, the result
says so and returns the best constrained fit; it never returns an x outside X.

The problem (domain, statistics, CasADi block) is in :mod:`.problem`, the
multistart solve in :mod:`.solve`, the outcome in :mod:`.result`.
"""

from __future__ import annotations

from softcath.analytic.calibration.problem import (
    MIN_LUMEN_SEMI_AXIS,
    N_CONTAINMENT,
    SHAPE_KEYS,
    _bounds,
    _inside,
)
from softcath.analytic.calibration.result import CalibrationResult, nrmse
from softcath.analytic.calibration.solve import IPOPT_OPTIONS, calibrate

__all__ = [
    "CalibrationResult",
    "calibrate",
    "nrmse",
    "SHAPE_KEYS",
    "MIN_LUMEN_SEMI_AXIS",
    "N_CONTAINMENT",
    "IPOPT_OPTIONS",
    "_bounds",
    "_inside",
]
