"""Generate realistic bench data with a hidden effect (or none) from the truth plant.

The data look like what the recorder writes (``docs/measurement-csv.md``,
raw, 200 Hz): by default several sine runs at different frequencies plus a
step-and-hold run (``softcath.virtualbench.hidden_protocols``: also steps only, or
quasi-static points, one per pressure step), curvature noise of a stated fraction of full scale, small
pressure-sensor noise, and a true gain that differs from the design's by a
random calibration error. The effect's strength is set so that its
*effect-to-noise ratio* hits a target:

    ENR = rms(effect signature) / noise s.d.,

where the signature is the clean curvature with the effect minus its best
pure-gain fit (what calibration cannot absorb), over all runs, and the noise
s.d. is that of the raw curvature samples. The truth forms (Preisach, RC
ladder, two Kelvin units, softplus threshold, exponential gain) differ from
the candidates in ``softcath.analytic.effects``; the workflow is not told which. Both
sensors have a 10 Hz causal response (the acquisition chain) before their
noise; the CSV holds raw samples, and the workflow applies the paper's filter.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from softcath.core.errors import DesignError
from softcath.virtualbench.hidden_protocols import (
    Protocol,
    default_protocol,
    quasi_static_protocol,
    step_protocol,
)
from softcath.virtualbench.plant import Plant
from softcath.virtualbench.truth_effects import EFFECT_NAMES, make_effect

__all__ = [
    "Protocol",
    "HiddenCase",
    "make_case",
    "default_protocol",
    "step_protocol",
    "quasi_static_protocol",
    "paper_demo_case",
    "signature_rms",
]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class HiddenCase:
    """A generated data set and the truth hidden in it."""

    effects: tuple[str, ...]
    truth_params: dict[str, dict[str, float]]
    effect_to_noise: dict[str, float]
    noise_fraction: float
    seed: int
    gain_per_mm_MPa: float
    table: pd.DataFrame = field(repr=False)
    plant: Plant = field(repr=False)


def signature_rms(kappa_effect: np.ndarray, pressure: np.ndarray) -> float:
    """RMS of what a pure gain cannot explain: ``kappa - g* p`` with g* least squares."""
    g = float(pressure @ kappa_effect) / float(pressure @ pressure)
    return float(np.sqrt(np.mean((kappa_effect - g * pressure) ** 2)))


def _sig(plant_kw, effect, runs):
    """Signature rms of ``effect`` over the recorded samples of ``runs`` (label, t, p, idx)."""
    plant = Plant(**plant_kw, effects=(effect,))
    k = np.concatenate([plant.simulate(t, p).curvature_per_mm[i] for _, t, p, i in runs])
    p = np.concatenate([p[i] for _, _, p, i in runs])
    return signature_rms(k, p)


def _scaled_effect(name, target_sig, rng, plant_kw, runs, p_max):
    """Truth effect of class ``name`` whose signature rms is ``target_sig`` (1/mm)."""
    if name == "hysteresis":
        width = p_max * rng.uniform(0.08, 0.2)
        for _ in range(4):
            s1 = _sig(plant_kw, make_effect(name, loop_width_MPa=width, fraction=1.0, range_MPa=p_max), runs)
            frac = target_sig / s1  # the signature is exactly linear in the fraction
            if frac <= 0.8:
                break
            width *= frac / 0.5
        if frac > 1.0:
            raise DesignError(
                "effect_to_noise * noise (signature, 1/mm)",
                target_sig,
                "too large for a hysteresis loop within the pressure range",
            )
        return make_effect(name, loop_width_MPa=width, fraction=frac, range_MPa=p_max)
    if name == "viscoelastic":
        tau = float(np.exp(rng.uniform(np.log(1.0), np.log(5.0))))
        s1 = _sig(plant_kw, make_effect(name, creep_fraction=1.0, tau_s=tau), runs)
        return make_effect(name, creep_fraction=target_sig / s1, tau_s=tau)
    if name == "offset":
        s1 = _sig(plant_kw, make_effect(name, curvature_per_mm=1.0), runs)
        return make_effect(name, curvature_per_mm=rng.choice([-1, 1]) * target_sig / s1)
    # the rest: bisection on the strength (log scale), signature monotone in it
    sign = rng.choice([-1.0, 1.0])
    build, lo, hi = {
        "lag": (lambda v: make_effect("lag", tau_s=v), 1e-3, 30.0),
        "delay": (lambda v: make_effect("delay", delay_s=v), 1e-4, 2.0),
        "dead_zone": (lambda v: make_effect("dead_zone", threshold_MPa=v), 1e-4 * p_max, 0.9 * p_max),
        "nonlinear_gain": (
            lambda v: make_effect("nonlinear_gain", beta_per_MPa=sign * v),
            1e-4 / p_max,
            3.0 / p_max,
        ),
    }[name]
    # the signature need not be monotone over the whole range (a dead zone near the
    # peak pressure removes the response it would distort): bracket the first
    # crossing on a log grid, then bisect inside the bracket
    grid = np.exp(np.linspace(np.log(lo), np.log(hi), 24))
    sig = [_sig(plant_kw, build(v), runs) for v in grid]
    above = [i for i, v in enumerate(sig) if v >= target_sig]
    if not above:
        raise DesignError(
            "effect_to_noise * noise (signature, 1/mm)",
            target_sig,
            f"must be <= {max(sig):.3g}, the most {name} can produce here",
        )
    i = above[0]
    if i == 0:
        return build(float(grid[0]))
    a, b = np.log(grid[i - 1]), np.log(grid[i])
    for _ in range(25):
        m = 0.5 * (a + b)
        if _sig(plant_kw, build(np.exp(m)), runs) < target_sig:
            a = m
        else:
            b = m
    return build(float(np.exp(0.5 * (a + b))))


def _sensor(bandwidth_hz: float | None, fs_hz: float):
    """Causal 2nd-order Butterworth sensor response, started in steady state."""
    if bandwidth_hz is None:
        return lambda x: x
    from scipy import signal

    if not 0 < bandwidth_hz < fs_hz / 2:
        raise DesignError("sensor_bandwidth_hz", bandwidth_hz, f"must be in (0, {fs_hz / 2:g})")
    sos = signal.butter(2, bandwidth_hz, fs=fs_hz, output="sos")
    zi = signal.sosfilt_zi(sos)

    def f(x):
        return signal.sosfilt(sos, x, zi=zi * x[0])[0]

    return f


def make_case(
    effects: Sequence[str] = (),
    *,
    seed: int = 0,
    effect_to_noise: float = 3.0,
    noise_fraction: float = 0.01,
    pressure_noise_fraction: float = 0.002,
    protocol: Protocol | None = None,
    gain_per_mm_MPa: float = 0.0756,
    elongation_per_MPa: float = 0.0103,
    length_mm: float = 5.0,
    gain_error: float = 0.2,
    sensor_bandwidth_hz: float | None = 10.0,
) -> HiddenCase:
    """Data with ``effects`` hidden in them (empty: no effect), as a measurement table.

    Parameters
    ----------
    effects
        Truth effect names (``softcath.virtualbench.truth_effects.EFFECT_NAMES``), each scaled to
        ``effect_to_noise`` on its own.
    seed
        Random seed: secondary effect parameters, calibration error, noise.
    effect_to_noise
        Target ENR of each effect (see the module docstring).
    noise_fraction
        Curvature noise s.d. as a fraction of the clean curvature's full scale.
    pressure_noise_fraction
        Pressure-sensor noise s.d. as a fraction of ``p_max``.
    protocol
        Excitation; default :func:`default_protocol`.
    gain_per_mm_MPa, elongation_per_MPa, length_mm
        Nominal model (defaults: the paper's design, cap load, from ``analytic.gains``).
    gain_error
        The true gain is the nominal one times ``U(1 - gain_error, 1 + gain_error)``.
    sensor_bandwidth_hz
        Both sensors (pressure transducer, camera + tip tracking) see the signal
        through a causal 2nd-order Butterworth low-pass of this bandwidth before
        their noise is added (None: ideal sensors). The same on both channels, as
        when both are read through the same acquisition chain.
    """
    _check_case(effects, noise_fraction, effect_to_noise)
    proto = protocol or default_protocol()
    rng = np.random.default_rng(seed)
    runs = [(label, t, p, proto.recorded(label, t)) for label, t, p in proto.runs()]
    gain = gain_per_mm_MPa * rng.uniform(1 - gain_error, 1 + gain_error)
    plant_kw = dict(curvature_per_mpa=gain, elongation_per_mpa=elongation_per_MPa, length_mm=length_mm)
    clean = Plant(**plant_kw)
    fs = np.ptp(np.concatenate([clean.simulate(t, p).curvature_per_mm[i] for _, t, p, i in runs]))
    sigma = noise_fraction * fs
    truth = [
        _scaled_effect(e, effect_to_noise * sigma, rng, plant_kw, runs, proto.p_max_MPa) for e in effects
    ]
    plant = Plant(**plant_kw, effects=tuple(truth))
    enr = {e.name: _sig(plant_kw, e, runs) / sigma for e in truth}
    sensor = _sensor(sensor_bandwidth_hz, proto.fs_hz)
    table = _table(
        plant, runs, sensor, rng, sigma=sigma, pressure_noise_fraction=pressure_noise_fraction, proto=proto
    )
    log.info("hidden case %s seed %d: ENR %s", effects, seed, enr)
    return HiddenCase(
        effects=tuple(effects),
        truth_params={e.name: e.params() for e in plant.effects},
        effect_to_noise=enr,
        noise_fraction=noise_fraction,
        seed=seed,
        gain_per_mm_MPa=gain,
        table=table,
        plant=plant,
    )


def _check_case(effects, noise_fraction, effect_to_noise) -> None:
    """Check the effect names, the noise fraction and the target ENR."""
    for e in effects:
        if e not in EFFECT_NAMES:
            raise DesignError("effect", e, f"must be one of {', '.join(EFFECT_NAMES)}")
    if not 0 < noise_fraction < 1:
        raise DesignError("noise_fraction", noise_fraction, "must be in (0, 1)")
    if not effect_to_noise > 0:
        raise DesignError("effect_to_noise", effect_to_noise, "must be > 0")


def _table(plant, runs, sensor, rng, *, sigma, pressure_noise_fraction, proto) -> pd.DataFrame:
    """Simulate every run from rest through the sensors and add the noise: the measurement table."""
    frames = []
    t_start = 0.0
    for label, t, p, idx in runs:
        r = plant.simulate(t, p)  # every run starts from rest
        n = idx.size
        p_seen, k_seen = sensor(p)[idx], sensor(r.curvature_per_mm)[idx]
        # time series: one continuous recording, runs 1 s apart, so time_s increases
        # through the file as the recorder writes it; quasi-static: the step index
        time_s = np.arange(n, dtype=float) if proto.quasi_static else t + t_start
        frames.append(
            pd.DataFrame(
                {
                    "time_s": time_s,
                    "pressure_MPa": p_seen + rng.normal(0, pressure_noise_fraction * proto.p_max_MPa, n),
                    "curvature_per_mm": k_seen + rng.normal(0, sigma, n),
                    "arc_length_mm": r.arc_length_mm[idx],
                    "bend_angle_rad": r.bend_angle_rad[idx],
                    "run": label,
                }
            )
        )
        t_start += t[-1] + 1.0
    return pd.concat(frames, ignore_index=True)


def paper_demo_case(*, seed: int = 0, two_frequencies: bool = True) -> HiddenCase:
    """The paper's data shape with its unexplained hysteresis, for the demo.

    Fig. 4 of the paper: a sinusoidal pressure repeated for 10 cycles, a
    hysteresis loop the linear model does not capture. Here: 10 cycles at
    0.1 Hz (plus, with ``two_frequencies``, 10 cycles at 0.2 Hz so that the
    workflow can tell rate-independent hysteresis from a lag), 0..2 MPa, 1 %
    curvature noise, Preisach hysteresis at an effect-to-noise ratio of 5.
    """
    freqs = (0.1, 0.2) if two_frequencies else (0.1,)
    proto = Protocol(p_max_MPa=2.0, frequencies_hz=freqs, cycles=10, step_hold=False)
    return make_case(("hysteresis",), seed=seed, effect_to_noise=5.0, noise_fraction=0.01, protocol=proto)
