"""Benchmarks of the bench hardware paths (run by `make bench`).

1. Tip measurement at 1920x1080 on one core (cv2.setNumThreads(1)): the
   default centre-line method and the paper's pipeline, against a baseline of
   bare OpenCV pre-processing (grayscale + 5x5 blur + Canny on the full
   frame, the first steps of the paper's method). Target: >= 120 fps default.
2. Recorder sustained rows per second (pressure + encoder over ptys, device
   clock, CSV with fsync), against a baseline of a bare pyserial readline loop
   over the same lines.
"""

from __future__ import annotations

import math
import sys
import threading
import time
from pathlib import Path
from tempfile import TemporaryDirectory

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import cv2  # noqa: E402
import numpy as np  # noqa: E402

from softcath.hardware.recorder import Recorder, RecorderConfig  # noqa: E402
from softcath.hardware.sensors import SerialSensor  # noqa: E402
from softcath.hardware.vision import Calibration, measure  # noqa: E402
from softcath.virtualbench.devices import VirtualLineDevice  # noqa: E402
from softcath.virtualbench.render import Scene, render_frame  # noqa: E402


def _rate(fn, frames, min_time=2.0):
    n = 0
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < min_time:
        fn(frames[n % len(frames)])
        n += 1
    return n / (time.perf_counter() - t0)


def bench_vision() -> None:
    cv2.setNumThreads(1)
    scene = Scene(width_px=1920, height_px=1080, px_per_mm=80.0, noise=2.0)
    rng = np.random.default_rng(0)
    frames = [
        render_frame(scene, curvature_per_mm=math.radians(a) / 5.0, arc_length_mm=5.0, rng=rng)
        for a in (20, 60, 100, 140)
    ]
    cal = Calibration(px_per_mm=80.0, base_px=scene.base)
    cal_auto = Calibration(px_per_mm=80.0)

    def baseline(img):
        g = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
        cv2.Canny(cv2.GaussianBlur(g, (5, 5), 0), 50, 150)

    base = _rate(baseline, frames)
    default = _rate(lambda f: measure(f, cal), frames)
    auto = _rate(lambda f: measure(f, cal_auto), frames)
    paper = _rate(lambda f: measure(f, cal, method="paper"), frames)
    print("tip measurement, 1920x1080, one OpenCV thread")
    print(f"  baseline gray+blur+Canny : {base:7.1f} fps")
    print(
        f"  default (base given)     : {default:7.1f} fps  ratio to baseline {default / base:.2f}"
        f"  target >= 120 fps: {'met' if default >= 120 else 'NOT met'}"
    )
    print(f"  default (base found)     : {auto:7.1f} fps  ratio to baseline {auto / base:.2f}")
    print(f"  paper method             : {paper:7.1f} fps  ratio to baseline {paper / base:.2f}")
    print(f"  default / paper speed    : {default / paper:.2f}x")


def _feed(devs, n):
    for k in range(n):
        for d in devs:
            d.emit(0.001 * k)


def bench_recorder(n: int = 20000) -> None:
    # baseline: bare pyserial readline over one pty
    dev = VirtualLineDevice()
    import serial

    port = serial.serial_for_url(dev.url, timeout=0.5)
    th = threading.Thread(target=_feed, args=([dev], n))
    t0 = time.perf_counter()
    th.start()
    got = 0
    while got < n:
        if port.readline():
            got += 1
    base = n / (time.perf_counter() - t0)
    th.join()
    port.close()
    dev.close()

    press, enc = VirtualLineDevice(), VirtualLineDevice()
    with TemporaryDirectory() as tmp:
        rec = Recorder(
            Path(tmp) / "r.csv",
            pressure=SerialSensor(press.url, name="pressure").open(),
            encoder=SerialSensor(enc.url, name="encoder").open(),
            config=RecorderConfig(clock="device"),
        )
        th = threading.Thread(target=_feed, args=([press, enc], n))
        t0 = time.perf_counter()
        th.start()
        summary = rec.run(duration_s=(n - 1) / 200.0)
        rate = summary.rows / (time.perf_counter() - t0)
        th.join()
    press.close()
    enc.close()
    print("recorder, pressure + encoder over ptys, device clock, CSV + fsync")
    print(f"  baseline pyserial readline (1 port): {base:9.0f} lines/s")
    print(
        f"  recorder sustained                 : {rate:9.0f} rows/s "
        f"({rate / 200:.0f}x the paper's 200 Hz; ratio to baseline {rate / base:.2f})"
    )


if __name__ == "__main__":
    bench_vision()
    bench_recorder()
