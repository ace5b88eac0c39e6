"""Candidate ``hysteresis``: rate-independent hysteresis as a Prandtl–Ishlinskii operator.

The pressure reaching the bending mechanics passes partly through a bank of
play (backlash) operators with thresholds spread uniformly over
``[0, loop_width/2]``: friction between tube, coil and channel, and the
silicone's rate-independent losses. The loop does not change with the
excitation frequency, which is what separates it from ``lag`` and ``delay``
when the data hold more than one frequency.
"""

from __future__ import annotations

import numpy as np

from softcath.analytic.effects.base import Candidate, Param

N_PLAYS = 6


def play(x: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Play (backlash) operators of the given radii (MPa) on a series.

    ``y[k] = clip(y[k-1], x[k] - r, x[k] + r)``, started as if reached by loading
    from below (``y[-1] = x[0] - r``); returns shape ``(x.size, radii.size)``.

    The recursion is a chain of clamps, and clamps compose into clamps:
    ``clip(clip(y, a1, b1), a2, b2) = clip(y, clip(a1, a2, b2), clip(b1, a2, b2))``.
    So the whole history is a prefix scan of an associative operation, done in
    ``log2(n)`` vectorised passes (Hillis–Steele) instead of a Python loop.
    """
    x = np.asarray(x, dtype=float)
    r = np.atleast_1d(np.asarray(radii, dtype=float))
    lo = x[:, None] - r[None, :]
    hi = x[:, None] + r[None, :]
    shift = 1
    while shift < x.size:
        # compose the block ending at k with the block ending at k - shift
        # clip(v, a, b) as minimum(maximum(v, a), b): np.clip's wrapper costs more
        # than the arithmetic on these small arrays
        a, b = lo[shift:], hi[shift:]
        new_lo = np.minimum(np.maximum(lo[:-shift], a), b)
        new_hi = np.minimum(np.maximum(hi[:-shift], a), b)
        lo[shift:], hi[shift:] = new_lo, new_hi
        shift *= 2
    y0 = x[0] - r
    return np.minimum(np.maximum(y0[None, :], lo), hi)


class Hysteresis(Candidate):
    """``x = (1 - phi) p + phi * mean_i play_{r_i}(p)``, ``r_i`` uniform in ``[0, w/2]``.

    Parameters: ``fraction`` phi of the response that is hysteretic, and the mean
    full loop width ``loop_width_MPa`` w along the pressure axis.
    """

    name = "hysteresis"
    kind = "pressure"
    meaning = "rate-independent hysteresis (friction, material losses): Prandtl-Ishlinskii"
    params = (
        Param("fraction", "-", 0.0, 1.0, "share of the response passing through the plays"),
        Param(
            "loop_width_MPa",
            "MPa",
            0.002,
            0.6,
            "mean full width of the play operators",
            relative_to="pressure",
            log=True,
        ),
    )
    starts = (0.1, 0.35, 0.6, 0.85)

    def apply(self, dt_s: float, x: np.ndarray, *, fraction: float, loop_width_MPa: float) -> np.ndarray:
        # radii (i + 1/2)/n of w, so the mean full width 2*mean(r) is w
        radii = loop_width_MPa * (np.arange(N_PLAYS) + 0.5) / N_PLAYS
        return (1 - fraction) * x + fraction * play(x, radii).mean(axis=1)


CANDIDATE = Hysteresis()
