"""Quasi-static measured points: recognised, prepared unfiltered, judged by static candidates.

A lab without a clock records one point per pressure step and writes
``time_s`` as the step index (docs/measurement-csv.md). There is no time
base, so nothing is filtered, every third point of every run is held out, and
a candidate with a time constant or a latency has no meaning.
"""

from __future__ import annotations

import numpy as np

from softcath.analytic.effects import Scales
from softcath.analytic.effects.fit import Segment
from softcath.design.errors import DataError
from softcath.design.measurement import Measurement
from softcath.hardware.filtering import PAPER_FILTER
from softcath.studies.discrepancy.prepared import MIN_RUN_SAMPLES, Prepared, RunInfo

__all__ = ["TIME_DEPENDENT", "is_quasi_static", "prepare_quasi_static", "candidates_for"]

#: candidates that need a clock (a time constant or a latency): meaningless on a step index
TIME_DEPENDENT = ("lag", "delay", "viscoelastic")


def is_quasi_static(m: Measurement) -> bool:
    """``time_s`` counts steps and every run is too short to be a time series."""
    lengths = [int(np.sum(m.run_labels() == r)) for r in m.runs]
    return m.is_step_index() and max(lengths) < MIN_RUN_SAMPLES


def _has_unloading(p: np.ndarray) -> bool:
    """The pressure comes down by more than 10 % of its span after its peak."""
    return bool(np.ptp(p) > 0 and p.max() - p[int(np.argmax(p)) :].min() > 0.1 * np.ptp(p))


def prepare_quasi_static(m: Measurement) -> Prepared:
    """Quasi-static measured points (``time_s`` a step index): one unfiltered segment per run.

    The points keep their order (loading, then unloading if recorded); the
    workflow holds out every third point of every run. There is no clock, so no
    filter and no noise-floor estimate (the floor is reported as 0, unknown).
    """
    segments, infos, times = [], [], []
    labels = m.run_labels()
    for label in m.runs:
        sel = labels == label
        p, k = m.pressure_MPa[sel], m.curvature_per_mm[sel]
        if p.size < 6:
            raise DataError(f"{m.source}: run {label!r}: {p.size} quasi-static points, need at least 6")
        if not np.ptp(p) > 0:
            raise DataError(f"{m.source}: run {label!r}: pressure is constant: there is no excitation")
        segments.append(
            Segment(dt_s=1.0, pressure_MPa=p, target=k, mask=np.ones(p.size, dtype=bool), label=str(label))
        )
        infos.append(
            RunInfo(
                label=str(label),
                kind="quasi-static",
                frequency_hz=0.0,
                duration_s=float(p.size),
                noise_sd_per_mm=0.0,
            )
        )
        times.append(m.time_s[sel])
    targets = np.concatenate([s.target for s in segments])
    if not np.ptp(targets) > 0:
        raise DataError(f"{m.source}: curvature is constant: there is no response to compare")
    pressures = np.concatenate([s.pressure_MPa for s in segments])
    return Prepared(
        segments=tuple(segments),
        runs=tuple(infos),
        data_filter=PAPER_FILTER,
        fit_filter=PAPER_FILTER,
        fs_hz=1.0,
        decimation=1,
        noise_floor_per_mm=0.0,
        full_scale_per_mm=float(np.ptp(targets)),
        scales=Scales(
            pressure_MPa=float(np.ptp(pressures)), duration_s=float(max(s.target.size for s in segments))
        ),
        times=tuple(times),
        static=True,
    )


def candidates_for(
    prep: Prepared, requested: tuple[str, ...] | None, default: tuple[str, ...]
) -> tuple[tuple[str, ...], list[str]]:
    """The candidates these data can judge, and notes saying what was left out and why.

    On quasi-static measured points ``time_s`` counts steps: a lag, a delay or
    creep has a time constant, which a step index does not carry. They are left
    out of the default set, and refused when asked for by name. Hysteresis
    needs an unloading branch: loading-only points cannot show a loop.
    """
    kinds = prep.kinds()
    if "quasi-static" not in kinds:
        return tuple(requested or default), []
    notes = [
        "quasi-static points carry no noise estimate: the noise floor is reported as 0 "
        "(unknown), so 'excess removed' is relative to a perfect fit"
    ]
    asked = [c for c in (requested or ()) if c in TIME_DEPENDENT]
    if asked:
        raise DataError(
            f"candidate(s) {', '.join(asked)} need a clock, but time_s here is a step index "
            "(quasi-static points, one per pressure step): a time constant or latency has no "
            "meaning; leave them out or record the response against time"
        )
    cands = [c for c in (requested or default) if c not in TIME_DEPENDENT]
    if not requested:
        notes.append(
            "quasi-static data (time_s is a step index, no clock): the time-dependent candidates "
            f"{', '.join(TIME_DEPENDENT)} were not tried; to judge them, record the response "
            "against time (a step-and-hold)"
        )
    if "hysteresis" in cands and not any(_has_unloading(s.pressure_MPa) for s in prep.segments):
        cands.remove("hysteresis")
        notes.append(
            "loading only (no unloading branch): hysteresis cannot show a loop and was not "
            "tried; to judge it, record the unloading steps too"
        )
    return tuple(cands), notes
