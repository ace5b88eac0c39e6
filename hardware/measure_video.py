"""Video (or camera, or image folder) to the per-frame measurement CSV plus an overlay video."""

from __future__ import annotations

import logging
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcath.design.measurement import CsvSink
from softcath.hardware.frames import FrameSource, VideoWriter
from softcath.hardware.recorder import CAMERA_COLUMNS
from softcath.hardware.vision import Calibration, TipMeasurement, draw_overlay, measure

__all__ = ["FRAME_COLUMNS", "MeasureSummary", "measured_frames", "measure_video"]

log = logging.getLogger(__name__)

FRAME_COLUMNS = ("frame", "time_s") + CAMERA_COLUMNS


@dataclass(frozen=True)
class MeasureSummary:
    """Outcome of measuring a frame source."""

    frames: int
    misses: int
    csv_path: str
    overlay_path: str | None
    base_px: tuple[float, float] | None
    base_angle_deg: float | None
    median_curvature_per_mm: float


def measured_frames(
    source: FrameSource,
    cal: Calibration,
    *,
    method: str = "default",
    dy_px: float = 10.0,
    overlay: VideoWriter | None = None,
    host_time: bool = False,
) -> Iterator[tuple[float | None, TipMeasurement]]:
    """Yield ``(time_s, measurement)`` per frame (``time_s`` None if ``host_time``)."""
    for fr in source:
        m = measure(fr.image, cal, method=method, dy_px=dy_px)
        if overlay is not None:
            overlay.write(draw_overlay(fr.image, m, cal))
        yield (None if host_time else fr.time_s), m


def measure_video(
    source: FrameSource,
    cal: Calibration,
    out_dir: str | Path,
    *,
    method: str = "default",
    dy_px: float = 10.0,
    progress: bool = True,
) -> MeasureSummary:
    """Measure every frame; write ``measurements.csv`` and ``overlay.avi`` into ``out_dir``.

    A frame without a detectable tip gets a row with empty values and is
    counted (and logged) as a miss. Without a base in ``cal`` the base is
    found in every frame; the median base is reported.
    """
    from tqdm import tqdm

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    sink = CsvSink(out / "measurements.csv", FRAME_COLUMNS)
    overlay = None
    frames = misses = 0
    bases, angles, curv = [], [], []
    bar = tqdm(total=source.frame_count, unit="frame", disable=not progress, leave=False)
    try:
        for fr in source:
            if overlay is None:
                h, w = fr.image.shape[:2]
                overlay = VideoWriter(out / "overlay.avi", fps=source.fps, size=(w, h))
            m = measure(fr.image, cal, method=method, dy_px=dy_px)
            overlay.write(draw_overlay(fr.image, m, cal))
            row = {"frame": fr.index, "time_s": fr.time_s}
            if m.ok:
                row.update(m.row())
                curv.append(m.curvature_per_mm)
                if cal.base_px is None and m.base_px is not None:
                    bases.append(m.base_px)
                    angles.append(m.base_angle_deg)
            else:
                misses += 1
                log.warning("frame %d: no tip measured (%s)", fr.index, m.reason)
            sink.append(row)
            sink.flush()
            frames += 1
            bar.update()
    finally:
        bar.close()
        sink.close()
        if overlay is not None:
            overlay.close()
    base = tuple(float(v) for v in np.median(bases, axis=0)) if bases else cal.base_px
    angle = float(np.median(angles)) if angles else cal.base_angle_deg
    return MeasureSummary(
        frames=frames,
        misses=misses,
        csv_path=str(out / "measurements.csv"),
        overlay_path=str(out / "overlay.avi") if overlay is not None else None,
        base_px=base,
        base_angle_deg=angle,
        median_curvature_per_mm=float(np.median(curv)) if curv else float("nan"),
    )
