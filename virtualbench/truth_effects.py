"""The TRUTH effects hidden in the virtual bench's plant (:mod:`softcath.virtualbench.plant`).

The plant is the physical stand-in that the virtual bench measures and that the
hidden-effect generator (``softcath.virtualbench.hidden_effects``) hides these effects in.
They are deliberately written independently of the candidate library in
``softcath.analytic.effects``, and where the missing-effect issue asks for it the
truth forms differ from the candidate forms, so that the workflow is never
tested on a model that contains its own answer:

============== ========================================== ===========================
effect         truth form here                            candidate form (analytic)
============== ========================================== ===========================
hysteresis     Preisach: a grid of relay hysterons with   Prandtl–Ishlinskii play
               log-normally spread widths                 operators
lag            transmission line: 3-section RC ladder     first-order low-pass
               (Elmore time constant ``tau_s``)
delay          pure delay (camera latency)                pure delay
dead_zone      smooth threshold (softplus corner)         hard threshold
viscoelastic   two Kelvin–Voigt units (retardation times  standard linear solid
               ``tau_s/2`` and ``2 tau_s``)               (one retardation time)
offset         pre-curvature at zero pressure             pre-curvature
nonlinear_gain exponential ``(exp(beta p) - 1)/beta``      quadratic ``p + beta p^2/2``
============== ========================================== ===========================

Each effect knows its stage in the plant's signal chain (``stage``) and its
``kind``: a pressure map (MPa -> MPa), an added curvature, or a shift of every output.

Units: pressure MPa, time s, curvature 1/mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from softcath.analytic.effects.base import first_order
from softcath.core.errors import DesignError

__all__ = [
    "EFFECT_NAMES",
    "TruthEffect",
    "make_effect",
    "check_range",
    "PreisachHysteresis",
    "TransmissionLineLag",
    "PureDelay",
    "SmoothDeadZone",
    "KelvinViscoelastic",
    "CurvatureOffset",
    "ExponentialGain",
]

# Order in the signal chain (see the module docstring).
_STAGE = {
    "lag": 0,
    "dead_zone": 1,
    "nonlinear_gain": 2,
    "hysteresis": 3,
    "viscoelastic": 4,
    "offset": 5,
    "delay": 6,
}


def check_range(name: str, value: float, lo: float, hi: float, *, lo_open: bool = False) -> None:
    ok = math.isfinite(value) and (value > lo if lo_open else value >= lo) and value <= hi
    if not ok:
        bound = f"must be in {'(' if lo_open else '['}{lo:g}, {hi:g}]"
        raise DesignError(name, value, bound)


# ---------------------------------------------------------------- linear helpers


def _uniform_dt(t: np.ndarray) -> float | None:
    """The common step if ``t`` is uniformly sampled (to 1e-6 relative), else None."""
    dt = np.diff(t)
    h = float(np.median(dt))
    if np.all(np.abs(dt - h) <= 1e-6 * h):
        return h
    return None


def _first_order(t: np.ndarray, u: np.ndarray, tau: float) -> np.ndarray:
    """Exact response of ``tau z' = u - z`` to a piecewise-linear input, started at rest.

    With ``u`` linear between samples the update is exact:
    ``z[k+1] = a z[k] + u[k+1] - a u[k] - tau s (1 - a)``, ``a = exp(-h/tau)``,
    ``s`` the input slope, so the result does not depend on the sample rate.
    """
    if tau <= 0:
        return u.copy()
    h = _uniform_dt(t)
    if h is not None:
        return first_order(h, u, tau)  # the same exact update as a filter (the candidates' helper)
    z = np.empty_like(u)
    z[0] = u[0]
    for k in range(u.size - 1):
        hk = t[k + 1] - t[k]
        a = math.exp(-hk / tau)
        s = (u[k + 1] - u[k]) / hk
        z[k + 1] = a * z[k] + u[k + 1] - a * u[k] - tau * s * (1 - a)
    return z


# ---------------------------------------------------------------- truth effects


@dataclass(frozen=True)
class TruthEffect:
    """Base of the truth effects: a name, a kind (how the plant applies it) and its chain stage."""

    name: ClassVar[str] = ""
    kind: ClassVar[str] = "pressure"  # "pressure" (MPa -> MPa), "curvature" (add), "output" (shift)

    @property
    def stage(self) -> int:
        return _STAGE[self.name]

    def params(self) -> dict[str, float]:
        """The physical parameters as a plain dict (for records and reports)."""
        return {k: float(v) for k, v in self.__dict__.items()}


@dataclass(frozen=True)
class PreisachHysteresis(TruthEffect):
    """Rate-independent hysteresis as a Preisach model of relay hysterons.

    Parameters
    ----------
    loop_width_MPa
        Median switching width (up threshold minus down threshold) of the relays,
        MPa. Within the operating range the pressure–curvature loop is about this
        wide along the pressure axis.
    fraction
        Share of the response that passes through the hysterons, 0..1; the rest
        follows pressure elastically. The loop's vertical half-opening is about
        ``fraction * loop_width_MPa / 2`` in effective-pressure units.
    range_MPa
        Pressure range the relay centres cover (0..range); beyond it the
        hysteretic part saturates, as a Preisach density of finite support does.
    width_spread
        Log-normal spread (standard deviation of the log) of the relay widths.
    """

    # Defaults: the loop of the bundled bench data (examples/make_demo_data.py) over the bench's
    # default 0..2 MPa, so `softcath bench --effect hysteresis` gives a loop the workflow can name.
    name: ClassVar[str] = "hysteresis"
    loop_width_MPa: float = 0.4
    fraction: float = 0.3
    range_MPa: float = 2.0
    width_spread: float = 0.4
    n_centres: int = 80
    n_widths: int = 7

    def __post_init__(self) -> None:
        check_range("hysteresis.loop_width_MPa", self.loop_width_MPa, 0.0, 10.0, lo_open=True)
        check_range("hysteresis.fraction", self.fraction, 0.0, 1.0)
        check_range("hysteresis.range_MPa", self.range_MPa, 0.0, 100.0, lo_open=True)
        check_range("hysteresis.width_spread", self.width_spread, 0.0, 2.0)
        check_range("hysteresis.n_centres", self.n_centres, 2, 10_000)
        check_range("hysteresis.n_widths", self.n_widths, 1, 100)

    def relays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        """Up thresholds alpha, down thresholds beta (MPa), weights, and the base level (MPa).

        With every relay off the hysteretic part equals the base level.
        """
        w_med = self.loop_width_MPa
        q = (np.arange(self.n_widths) + 0.5) / self.n_widths
        from scipy.stats import norm

        widths = w_med * np.exp(self.width_spread * norm.ppf(q))
        # centres extend half a width past each end so the operating range is interior
        lo, hi = -0.5 * widths.max(), self.range_MPa + 0.5 * widths.max()
        centres = np.linspace(lo, hi, self.n_centres)
        c, w = np.meshgrid(centres, widths, indexing="ij")
        alpha = (c + w / 2).ravel()
        beta = (c - w / 2).ravel()
        # each relay carries an equal share of the span so that with zero width the
        # relay sum reproduces p itself (a staircase of step (hi-lo)/n_centres)
        weight = np.full(alpha.size, (hi - lo) / (self.n_centres * self.n_widths))
        return alpha, beta, weight, float(lo)

    def params(self) -> dict[str, float]:
        return {
            "loop_width_MPa": self.loop_width_MPa,
            "fraction": self.fraction,
            "range_MPa": self.range_MPa,
            "width_spread": self.width_spread,
        }

    def apply(self, t: np.ndarray, p: np.ndarray) -> np.ndarray:
        alpha, beta, weight, base = self.relays()
        # initial state: reached by loading from below, so a relay is on iff its
        # centre lies below the starting pressure
        state = (alpha + beta) / 2 <= p[0]
        h = np.empty_like(p)
        for k, pk in enumerate(p):
            state = np.where(pk >= alpha, True, np.where(pk <= beta, False, state))
            h[k] = weight @ state
        h += base
        return (1 - self.fraction) * p + self.fraction * h


@dataclass(frozen=True)
class TransmissionLineLag(TruthEffect):
    """Pressure lag of the long thin supply line, as an n-section RC ladder.

    Parameters
    ----------
    tau_s
        Elmore time constant of the line (s): the mean delay of its step response,
        ``R_hyd C`` of the whole line in the lumped picture.
    sections
        Number of RC sections (3 by default: more than the first-order candidate).
    """

    name: ClassVar[str] = "lag"
    tau_s: float = 0.1
    sections: int = 3

    def __post_init__(self) -> None:
        check_range("lag.tau_s", self.tau_s, 0.0, 1000.0)
        check_range("lag.sections", self.sections, 1, 50)

    def apply(self, t: np.ndarray, p: np.ndarray) -> np.ndarray:
        if self.tau_s == 0:
            return p.copy()
        n = self.sections
        # Elmore delay at the far end of n equal RC sections is RC n(n+1)/2
        rc = 2 * self.tau_s / (n * (n + 1))
        # node equations C v_i' = (v_{i-1} - v_i)/R - (v_i - v_{i+1})/R, open end
        a = np.zeros((n, n))
        for i in range(n):
            a[i, i] = -2.0 if i < n - 1 else -1.0
            if i > 0:
                a[i, i - 1] = 1.0
            if i < n - 1:
                a[i, i + 1] = 1.0
        a /= rc
        b = np.zeros(n)
        b[0] = 1.0 / rc
        # modal decomposition: every mode is a first-order lag with DC gain 1
        lam, vec = np.linalg.eig(a)
        lam, vec = lam.real, vec.real
        coef = np.linalg.solve(vec, b)
        out = np.zeros_like(p)
        for j in range(n):
            tau_j = -1.0 / lam[j]
            # mode z_j' = lam_j z_j + coef_j u  ->  z_j = coef_j tau_j * lag_tau_j(u)
            out += vec[-1, j] * coef[j] * tau_j * _first_order(t, p, tau_j)
        return out


@dataclass(frozen=True)
class PureDelay(TruthEffect):
    """Pure time delay of every measured output (camera/recorder latency).

    Parameters
    ----------
    delay_s
        Latency (s); the output at time t is the tip state at ``t - delay_s``.
    """

    name: ClassVar[str] = "delay"
    kind: ClassVar[str] = "output"
    delay_s: float = 0.05

    def __post_init__(self) -> None:
        check_range("delay.delay_s", self.delay_s, 0.0, 100.0)

    def apply(self, t: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.interp(t - self.delay_s, t, y)


@dataclass(frozen=True)
class SmoothDeadZone(TruthEffect):
    """Threshold pressure below which the tip does not respond (pre-stress, friction).

    Parameters
    ----------
    threshold_MPa
        Pressure (MPa) the tube needs before it starts to bend.
    smoothness_MPa
        Width of the rounded corner (softplus scale, MPa); 0 gives a hard corner.
        Defaults to a tenth of the threshold.
    """

    name: ClassVar[str] = "dead_zone"
    threshold_MPa: float = 0.01
    smoothness_MPa: float | None = None

    def __post_init__(self) -> None:
        check_range("dead_zone.threshold_MPa", self.threshold_MPa, 0.0, 100.0)
        if self.smoothness_MPa is not None:
            check_range("dead_zone.smoothness_MPa", self.smoothness_MPa, 0.0, 100.0)

    def params(self) -> dict[str, float]:
        s = self.threshold_MPa / 10 if self.smoothness_MPa is None else self.smoothness_MPa
        return {"threshold_MPa": self.threshold_MPa, "smoothness_MPa": s}

    def apply(self, t: np.ndarray, p: np.ndarray) -> np.ndarray:
        s = self.params()["smoothness_MPa"]
        x = p - self.threshold_MPa
        if s == 0:
            return np.maximum(x, 0.0)
        return s * np.logaddexp(0.0, x / s)


@dataclass(frozen=True)
class KelvinViscoelastic(TruthEffect):
    """Creep of the silicone: two Kelvin–Voigt units in series with the elastic part.

    Parameters
    ----------
    creep_fraction
        Delayed compliance over instantaneous compliance (-): after a long hold the
        response is ``1 + creep_fraction`` times the instantaneous one.
    tau_s
        Geometric-mean retardation time (s); the two units have ``tau_s/2`` and
        ``2 tau_s`` and share the delayed compliance equally.
    """

    name: ClassVar[str] = "viscoelastic"
    creep_fraction: float = 0.2
    tau_s: float = 2.0

    def __post_init__(self) -> None:
        check_range("viscoelastic.creep_fraction", self.creep_fraction, 0.0, 10.0)
        check_range("viscoelastic.tau_s", self.tau_s, 0.0, 1000.0, lo_open=True)

    def apply(self, t: np.ndarray, p: np.ndarray) -> np.ndarray:
        slow = 0.5 * _first_order(t, p, self.tau_s / 2) + 0.5 * _first_order(t, p, 2 * self.tau_s)
        return p + self.creep_fraction * slow


@dataclass(frozen=True)
class CurvatureOffset(TruthEffect):
    """Pre-curvature at zero pressure (residual bend from fabrication or gravity sag).

    Parameters
    ----------
    curvature_per_mm
        Curvature (1/mm) of the unpressurised tip, positive toward the channel.
    """

    name: ClassVar[str] = "offset"
    kind: ClassVar[str] = "curvature"
    curvature_per_mm: float = 0.005

    def __post_init__(self) -> None:
        check_range("offset.curvature_per_mm", self.curvature_per_mm, -10.0, 10.0)


@dataclass(frozen=True)
class ExponentialGain(TruthEffect):
    """Pressure-dependent gain: the incremental stiffness changes with pressure.

    Parameters
    ----------
    beta_per_MPa
        Relative change of incremental gain per MPa (1/MPa): the incremental gain
        at pressure p is ``exp(beta p)`` times the small-pressure gain; positive
        softens (gain grows), negative stiffens (ovalisation, geometric stiffening).
    """

    name: ClassVar[str] = "nonlinear_gain"
    beta_per_MPa: float = 1.0

    def __post_init__(self) -> None:
        check_range("nonlinear_gain.beta_per_MPa", self.beta_per_MPa, -1e4, 1e4)

    def apply(self, t: np.ndarray, p: np.ndarray) -> np.ndarray:
        b = self.beta_per_MPa
        if abs(b) < 1e-12:
            return p.copy()
        return np.expm1(b * p) / b


_CLASSES: dict[str, type[TruthEffect]] = {
    "hysteresis": PreisachHysteresis,
    "lag": TransmissionLineLag,
    "delay": PureDelay,
    "dead_zone": SmoothDeadZone,
    "viscoelastic": KelvinViscoelastic,
    "offset": CurvatureOffset,
    "nonlinear_gain": ExponentialGain,
}
# The truth's own vocabulary, in its own order (the candidates in analytic.effects are named alike on
# purpose).
EFFECT_NAMES: tuple[str, ...] = tuple(_CLASSES)


def make_effect(name: str, **params: float) -> TruthEffect:
    """Build a truth effect by name with its physical parameters (see each class).

    Raises
    ------
    DesignError
        Unknown name, unknown parameter, or a parameter outside its bound.
    """
    cls = _CLASSES.get(name)
    if cls is None:
        raise DesignError("effect", name, f"must be one of {', '.join(EFFECT_NAMES)}")
    allowed = {f for f in cls.__dataclass_fields__}
    for key in params:
        if key not in allowed:
            raise DesignError(f"{name}.{key}", params[key], f"unknown; allowed: {sorted(allowed)}")
    return cls(**params)
