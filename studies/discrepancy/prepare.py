"""Turn a measurement table into filtered, decimated segments for fitting and scoring.

Steps, per run (``run`` column; one run if absent):

1. resample onto a uniform 200 Hz base if the samples are irregular (the paper
   filters on 200 Hz);
2. find the excitation: the dominant frequency of each sine-like run, and
   whether a run is a step-and-hold (mostly constant pressure);
3. choose the data low-pass so that it keeps the excitation band: the paper's
   0.5 Hz filter when the fastest sine is at most 0.2 Hz (its 5th-order
   Butterworth passes 0.2 Hz within 3e-5), otherwise the same shape scaled to
   put the passband at 2.5x the fastest sine;
4. anti-alias both pressure and curvature with the same shape at 4x the band,
   decimate to 40x the passband, and apply the data low-pass to the curvature
   (the target). The model input is the anti-aliased pressure; the model
   output gets the same data low-pass (``softcath.analytic.effects.fit``), so data and
   model see identical linear filtering (else the filter's delay looks like a
   missing delay);
5. estimate the noise floor: the raw curvature noise s.d. from what the
   anti-alias filter removes, propagated through both filters.

Quasi-static data (``time_s`` a step index: one point per pressure step, no
clock) skip all of this: ``softcath.studies.discrepancy.quasi_static``.
"""

from __future__ import annotations

import logging

import numpy as np
from scipy import signal

from softcath.analytic.effects import Scales
from softcath.analytic.effects.fit import Segment
from softcath.design.errors import DataError
from softcath.design.measurement import Measurement
from softcath.hardware.filtering import (
    PAPER_FILTER,
    PAPER_FS_HZ,
    FilterSpec,
    design_sos,
    filtfilt,
    resample_uniform,
)
from softcath.studies.discrepancy.prepared import MIN_RUN_SAMPLES, Prepared, RunInfo, _zero_phase
from softcath.studies.discrepancy.quasi_static import is_quasi_static, prepare_quasi_static

__all__ = ["RunInfo", "Prepared", "prepare", "prepare_static", "EXCITATIONS", "MIN_RUN_SAMPLES"]

log = logging.getLogger(__name__)

#: decimated sample rate over the data passband. At 40 the decimated Nyquist rate
#: is 20x the band: what folds into the data band (< 2x the band) comes from above
#: 38x the band, where the anti-alias filter (4x the band, order 5, zero-phase)
#: has removed more than 100 dB. Rate-independent candidates see the sampled
#: input and miss a peak between samples by ~(w h)^2/8 of the amplitude: 3e-4
#: at 0.2 Hz and 20 Hz, below the filtered noise at 0.5 % noise
DECIMATED_OVER_PASSBAND = 40.0
#: trimmed at each end of a run in fits and scores: two filter settling times
TRIM_OVER_PASSBAND = 1.0
#: what ``prepare(..., excitation=)`` accepts; "auto" recognises it from the data
EXCITATIONS = ("auto", "time-series", "quasi-static")
#: Largest reference curvature, 1/mm (a bend radius of 1 µm, far beyond any catheter).
MAX_REFERENCE_CURVATURE = 1e3


def _excitation(t: np.ndarray, p: np.ndarray, where: str = "") -> tuple[str, float]:
    span = np.ptp(p)
    if span <= 0:
        raise DataError(f"{where}pressure is constant: there is no excitation to compare against")
    # step-and-hold: in most half-second windows the pressure stays within 5 % of its
    # span (a range test, not a slope test: differentiated sensor noise would swamp it)
    fs = 1 / (t[1] - t[0])
    w = max(2, int(round(0.5 * fs)))
    nwin = p.size // w
    if nwin >= 4:
        win = p[: nwin * w].reshape(nwin, w)
        if np.mean(np.ptp(win, axis=1) < 0.05 * span) > 0.5:
            return "step", 0.0
    x = (p - p.mean()) * np.hanning(p.size)
    spec = np.abs(np.fft.rfft(x))
    f = np.fft.rfftfreq(p.size, 1 / fs)
    spec[0] = 0
    return "sine", float(f[np.argmax(spec)])


def _noise_gain(aa: FilterSpec, data: FilterSpec, fs: float) -> float:
    """Ratio of filtered to raw white-noise s.d. through anti-alias and data filters."""
    f = np.linspace(0, fs / 2, 20001)
    _, h1 = signal.sosfreqz(design_sos(aa), worN=f, fs=fs)
    f2 = f[f < data.fs_hz / 2]
    _, h2 = signal.sosfreqz(design_sos(data), worN=f2, fs=data.fs_hz)
    h2 = np.concatenate([np.abs(h2), np.zeros(f.size - f2.size)])
    # zero-phase (forward-backward) filtering squares each magnitude response
    power = np.abs(h1) ** 4 * h2**4
    return float(np.sqrt(np.trapezoid(power, f) / (fs / 2)))


def _as_measurement(data) -> Measurement:
    return data if isinstance(data, Measurement) else Measurement.from_table(data)


def prepare(data, *, filter_spec: FilterSpec | None = None, excitation: str = "auto") -> Prepared:
    """Filtered, decimated segments of a measurement.

    Parameters
    ----------
    data
        A :class:`softcath.design.measurement.Measurement` or a table with its columns.
    filter_spec
        Force the data low-pass (default: chosen from the excitation, see above).
    excitation
        ``"auto"`` (default): quasi-static when ``time_s`` is a step index in
        runs shorter than 50 points, otherwise a time series whose runs are
        classified as sine or step-and-hold. ``"time-series"`` or
        ``"quasi-static"`` force the choice.
    """
    m = _as_measurement(data)
    if excitation not in EXCITATIONS:
        raise DataError(f"excitation = {excitation!r}: must be one of {', '.join(EXCITATIONS)}")

    if excitation == "quasi-static" or (excitation == "auto" and is_quasi_static(m)):
        return prepare_quasi_static(m)
    runs = _runs(m)
    raw, fs = _uniform_runs(runs)
    exc = [_excitation(t, p, f"{m.source}: run {label!r}: ") for label, t, p, _ in raw]
    spec = _data_low_pass(filter_spec, exc, fs)
    aa = spec.scaled(4.0)
    q = max(1, int(np.floor(fs / (DECIMATED_OVER_PASSBAND * spec.passband_hz) + 1e-6)))
    fs_d = fs / q
    fit_spec = FilterSpec(
        passband_hz=spec.passband_hz,
        stopband_hz=spec.stopband_hz,
        ripple_db=spec.ripple_db,
        attenuation_db=spec.attenuation_db,
        fs_hz=fs_d,
        family=spec.family,
    )
    gain = _noise_gain(aa, fit_spec, fs)
    data_filter = _zero_phase(fit_spec)
    trim = int(round(TRIM_OVER_PASSBAND / spec.passband_hz * fs_d))
    segments, infos, times, noise = _segments(raw, exc, aa, q, data_filter, trim, spec=spec, fs=fs)
    targets = np.concatenate([s.target[s.mask] for s in segments])
    pressures = np.concatenate([s.pressure_MPa for s in segments])
    # relative: a constant series comes out of the filters with 1e-16 of rounding ripple
    if not np.ptp(targets) > 1e-9 * np.max(np.abs(targets)):
        raise DataError(f"{m.source}: curvature is constant: there is no response to compare")
    return Prepared(
        segments=tuple(segments),
        runs=tuple(infos),
        data_filter=spec,
        fit_filter=fit_spec,
        fs_hz=fs_d,
        decimation=q,
        noise_floor_per_mm=float(np.sqrt(np.mean(np.square(noise))) * gain),
        full_scale_per_mm=float(np.ptp(targets)),
        scales=Scales(pressure_MPa=float(np.ptp(pressures)), duration_s=max(r.duration_s for r in infos)),
        times=tuple(times),
    )


def _runs(m: Measurement) -> list[tuple]:
    """(label, time, pressure, curvature) of every run, each long enough for a time series."""
    labels = m.run_labels()
    runs = []
    for label in m.runs:
        sel = labels == label
        t, p, k = m.time_s[sel], m.pressure_MPa[sel], m.curvature_per_mm[sel]
        if t.size < MIN_RUN_SAMPLES:
            raise DataError(
                f"{m.source}: run {label!r}: {t.size} samples, need at least {MIN_RUN_SAMPLES} "
                "for a time series (quasi-static points: time_s as a step index 0, 1, 2, ...)"
            )
        runs.append((str(label), t, p, k))
    return runs


def _uniform_runs(runs: list[tuple]) -> tuple[list[tuple], float]:
    """The runs on one uniform time base and its sample rate [Hz]."""
    # irregular runs go onto one uniform base: the paper's 200 Hz, or the file's median
    # rate when it is slower (a 25 Hz camera log gains nothing from 8x interpolation)
    rate = min(
        PAPER_FS_HZ, round(float(1 / np.median(np.concatenate([np.diff(t) for _, t, _, _ in runs]))), 3)
    )
    raw = []
    for label, t, p, k in runs:
        dt = np.diff(t)
        if np.ptp(dt) > 1e-6 * np.median(dt):
            tu, p = resample_uniform(t, p, fs_hz=rate)
            _, k = resample_uniform(t, k, fs_hz=rate)
            t = tu
        raw.append((label, t, p, k))
    # rounded to 1 mHz: time stamps like 107.985 carry 1e-12 s of binary noise
    fs_all = {round(float(1 / np.median(np.diff(t))), 3) for _, t, _, _ in raw}
    if len(fs_all) != 1:
        raise DataError(f"runs have different sample rates {sorted(fs_all)} Hz")
    fs = fs_all.pop()
    return raw, fs


def _data_low_pass(filter_spec: FilterSpec | None, exc, fs: float) -> FilterSpec:
    """The data low-pass: the given one, or chosen from the fastest sine; checked against ``fs``."""
    if filter_spec is None:
        fmax = max([f for kind, f in exc if kind == "sine"], default=0.0)
        spec = FilterSpec(fs_hz=fs) if fs != PAPER_FILTER.fs_hz else PAPER_FILTER
        if 2.5 * fmax > spec.passband_hz * (1 + 1e-6):  # FFT bins carry rounding noise
            spec = spec.scaled(2.5 * fmax / spec.passband_hz)
    else:
        spec = filter_spec
    if spec.stopband_hz * 4 >= fs / 2:
        raise DataError(
            f"sample rate {fs} Hz is too low for a {spec.passband_hz:g} Hz "
            f"data filter: need > {8 * spec.stopband_hz:g} Hz"
        )
    return spec


def _segments(raw, exc, aa: FilterSpec, q: int, data_filter, trim: int, *, spec: FilterSpec, fs: float):
    """Anti-alias, decimate and filter each run; returns (segments, run infos, times, noise s.d.)."""
    fs_d = fs / q
    segments, infos, times, noise = [], [], [], []
    for (label, t, p, k), (kind, f) in zip(raw, exc, strict=True):
        pa = filtfilt(p, aa)
        ka = filtfilt(k, aa)
        # what the anti-alias filter removes is (almost all) noise above 4x the band
        sd = float(np.std(k - ka)) / np.sqrt(max(1 - 2 * aa.stopband_hz / fs, 0.5))
        pd_, kd, td = pa[::q], ka[::q], t[::q]
        target = data_filter(kd)
        mask = np.zeros(td.size, dtype=bool)
        mask[trim : td.size - trim] = True
        if mask.sum() < 20:
            raise DataError(
                f"run {label!r} is too short ({t[-1] - t[0]:.3g} s) for a {spec.passband_hz:g} Hz filter"
            )
        segments.append(Segment(dt_s=1 / fs_d, pressure_MPa=pd_, target=target, mask=mask, label=label))
        infos.append(
            RunInfo(
                label=label, kind=kind, frequency_hz=f, duration_s=float(t[-1] - t[0]), noise_sd_per_mm=sd
            )
        )
        times.append(td)
        noise.append(sd)
    return segments, infos, times, noise


def prepare_static(pressure_MPa: np.ndarray, curvature_per_mm: np.ndarray) -> Prepared:
    """Quasi-static reference points (e.g. FEM over a pressure range) as one segment.

    No time, no filter, no noise: the points are sorted by pressure and held out
    interleaved (every third point) by the workflow.
    """
    p = np.asarray(pressure_MPa, dtype=float)
    k = np.asarray(curvature_per_mm, dtype=float)
    if p.shape != k.shape or p.ndim != 1 or p.size < 6:
        raise DataError(
            f"reference: need >= 6 (pressure, curvature) points of equal length, got {p.shape} and {k.shape}"
        )
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(k))):
        raise DataError("reference: pressures and curvatures must be finite")
    # The fit scales by the pressure span and the curvature span: a curve without either
    # has nothing to fit, and curvatures beyond a micrometre radius are a unit error.
    if not np.ptp(p) > 0:
        raise DataError(f"reference: all {p.size} pressures are {p[0]:g} MPa; need a pressure range")
    if not np.ptp(k) > 0:
        raise DataError(
            f"reference: all {k.size} curvatures are {k[0]:g} 1/mm; the curve has no gain to model"
        )
    if np.abs(k).max() > MAX_REFERENCE_CURVATURE:
        raise DataError(
            f"reference: curvature {k[np.argmax(np.abs(k))]:.3g} 1/mm exceeds {MAX_REFERENCE_CURVATURE:g} "
            "1/mm (a bend radius below 1 µm); check the units (1/mm)"
        )
    order = np.argsort(p)
    p, k = p[order], k[order]
    seg = Segment(dt_s=1.0, pressure_MPa=p, target=k, mask=np.ones(p.size, dtype=bool), label="reference")
    info = RunInfo(
        label="reference", kind="static", frequency_hz=0.0, duration_s=float(p.size), noise_sd_per_mm=0.0
    )
    return Prepared(
        segments=(seg,),
        runs=(info,),
        data_filter=PAPER_FILTER,
        fit_filter=PAPER_FILTER,
        fs_hz=1.0,
        decimation=1,
        noise_floor_per_mm=0.0,
        full_scale_per_mm=float(np.ptp(k)),
        scales=Scales(pressure_MPa=float(np.ptp(p)), duration_s=float(p.size)),
        times=(np.arange(p.size, dtype=float),),
        static=True,
    )
