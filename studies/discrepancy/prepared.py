"""A measurement prepared for fitting: its segments, the filters used and what each run holds."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import signal

from softcath.analytic.effects import Scales
from softcath.analytic.effects.fit import Segment
from softcath.hardware.filtering import FilterSpec, design_sos

__all__ = ["MIN_RUN_SAMPLES", "Prepared", "RunInfo"]

#: runs shorter than this are not a time series the filters can work on
MIN_RUN_SAMPLES = 50


@dataclass(frozen=True)
class RunInfo:
    """What the preparation found in one run."""

    label: str
    kind: str  # "sine", "step" or "quasi-static" ("static": a FEM reference)
    frequency_hz: float  # dominant excitation frequency (sine runs), else 0
    duration_s: float
    noise_sd_per_mm: float  # raw curvature noise s.d. estimate


@dataclass(frozen=True)
class Prepared:
    """Segments ready for fitting, the filters used, and what was found."""

    segments: tuple[Segment, ...]
    runs: tuple[RunInfo, ...]
    data_filter: FilterSpec  # at the original rate
    fit_filter: FilterSpec  # the same specification at the decimated rate
    fs_hz: float
    decimation: int
    noise_floor_per_mm: float  # s.d. of the noise left in the filtered target
    full_scale_per_mm: float  # peak-to-peak of the filtered curvature over all runs
    scales: Scales
    times: tuple[np.ndarray, ...]  # decimated time base of each segment (s)
    static: bool = False  # quasi-static points (FEM reference): no time, no filter

    def output_filter(self) -> Callable[[np.ndarray], np.ndarray]:
        """The data low-pass at the decimated rate (apply to model output)."""
        if self.static:
            return lambda x: np.asarray(x, dtype=float)
        return _zero_phase(self.fit_filter)

    def distinct_frequencies(self) -> int:
        """Number of distinct excitations: sine frequencies differing by >= 1.5x, + steps."""
        freqs = sorted(r.frequency_hz for r in self.runs if r.kind == "sine")
        distinct = []
        for f in freqs:
            if not distinct or f >= 1.5 * distinct[-1]:
                distinct.append(f)
        return len(distinct) + any(r.kind == "step" for r in self.runs)

    def kinds(self) -> set[str]:
        """The excitation kinds present ("sine", "step", "quasi-static", "static")."""
        return {r.kind for r in self.runs}


def _zero_phase(spec: FilterSpec) -> Callable[[np.ndarray], np.ndarray]:
    """``hardware.filtering.filtfilt(x, spec)`` along axis 0, with set-up done once.

    The same sections, odd padding of 2 s and steady-state initial conditions as
    ``scipy.signal.sosfiltfilt`` (tested equal to 1e-12); the filter design and
    ``sosfilt_zi`` cost more than the filtering, and the fits filter thousands
    of times, so they are computed once here. Accepts (n,) or (n, columns).
    """
    sos = design_sos(spec)
    zi0 = signal.sosfilt_zi(sos)  # (sections, 2)
    pad = 2.0 * spec.fs_hz

    def f(x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        n = x.shape[0]
        m = int(min(n - 1, round(pad)))
        ext = np.concatenate([2 * x[:1] - x[m:0:-1], x, 2 * x[-1:] - x[-2 : -(m + 2) : -1]])
        zi = zi0.reshape(zi0.shape + (1,) * (x.ndim - 1))
        y, _ = signal.sosfilt(sos, ext, axis=0, zi=zi * ext[:1])
        y, _ = signal.sosfilt(sos, y[::-1], axis=0, zi=zi * y[-1:])
        return y[::-1][m : m + n]

    return f
