"""The virtual bench: virtual devices and camera driven by a plant model, recorded for real.

What runs (mirroring the paper's rig, section II.A / IV.1):

1. A virtual Zaber-style stage on a pseudo-terminal is driven through the
   real :class:`softcath.hardware.stage.ZaberStage` driver: ``move sin`` for sine
   excitation (as the paper drove it from the Zaber console), timed
   ``move abs`` commands for triangle and step waveforms.
2. The syringe model turns the stage trajectory into inlet pressure; the
   plant (``softcath.virtualbench.plant``: the analytic model of the design plus optional
   hidden effects) turns pressure into curvature and arc length.
3. A virtual pressure sensor (kPa, framed, seeded noise) and encoder
   (stage microsteps) speak :mod:`softcath.hardware.protocol` on pseudo-terminals; a
   virtual camera renders frames of the bent tip (:mod:`softcath.virtualbench.render`).
4. The real :class:`softcath.hardware.recorder.Recorder` reads the ptys and the
   camera through the real measurement pipeline (:mod:`softcath.hardware.vision`)
   onto the 200 Hz base.

Everything runs on a virtual clock, faster than real time, and is
deterministic for a given seed: the recorder uses the devices' sequence
numbers as its clock and the camera's frame times.
"""

from __future__ import annotations

import json
import logging
import math
import threading
from collections.abc import Iterator
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from softcath import design as design_pkg
from softcath.core.errors import DesignError
from softcath.design.measurement import CsvSink, read_recording
from softcath.hardware.frames import VideoWriter
from softcath.hardware.recorder import Recorder, RecorderConfig, RecordSummary
from softcath.hardware.sensors import SerialSensor
from softcath.hardware.stage import DEFAULT_MICROSTEP_MM, SyringeModel, ZaberStage
from softcath.hardware.vision import Calibration, measure
from softcath.virtualbench.devices import VirtualClock, VirtualLineDevice, VirtualStage
from softcath.virtualbench.plant import Plant
from softcath.virtualbench.render import Scene, render_frame
from softcath.virtualbench.truth_effects import make_effect

__all__ = ["WAVEFORMS", "BenchConfig", "BenchResult", "make_plant", "run_bench"]

log = logging.getLogger(__name__)

WAVEFORMS = ("sine", "triangle", "steps")
FS_HZ = 200.0


@dataclass(frozen=True)
class BenchConfig:
    """Settings of one virtual-bench run.

    Parameters
    ----------
    waveform
        ``sine``, ``triangle`` or ``steps`` (an up-and-down staircase of 8 levels).
    freqs_hz
        Excitation frequencies, Hz; one ``run`` segment each.
    cycles
        Cycles per frequency.
    pressure_max_MPa
        Peak inlet pressure, MPa (the excitation spans 0 .. this).
    noise
        Noise level multiplier: 1 gives 2 kPa pressure-sensor noise and
        2 grey levels of camera noise; 0 gives none.
    seed
        Seed of every random draw.
    rest_s
        Rest at zero pressure before each segment, s.
    fps
        Camera frame rate, Hz (a divisor of 200 keeps frames on the time base).
    scene
        Camera and look; the tip leaves the base upward.
    syringe
        Displacement-to-pressure model.
    method
        Measurement method, ``default`` or ``paper``.
    """

    waveform: str = "sine"
    freqs_hz: tuple[float, ...] = (0.5, 1.0)
    cycles: int = 2
    pressure_max_MPa: float = 2.0
    noise: float = 1.0
    seed: int = 0
    rest_s: float = 0.5
    fps: float = 50.0
    scene: Scene = field(default_factory=Scene)
    syringe: SyringeModel = field(default_factory=SyringeModel)
    method: str = "default"

    def __post_init__(self) -> None:
        if self.waveform not in WAVEFORMS:
            raise DesignError("waveform", self.waveform, f"must be one of {', '.join(WAVEFORMS)}")
        if not self.freqs_hz:
            raise DesignError("freqs_hz", self.freqs_hz, "must list at least one frequency")
        for f in self.freqs_hz:
            if not (math.isfinite(f) and 0.01 <= f <= 10.0):
                raise DesignError("freq", f, "must be in [0.01, 10] Hz")
        if not 1 <= self.cycles <= 1000:
            raise DesignError("cycles", self.cycles, "must be in [1, 1000]")
        if not (math.isfinite(self.pressure_max_MPa) and 0 < self.pressure_max_MPa <= 10):
            raise DesignError("pressure_max_MPa", self.pressure_max_MPa, "must be in (0, 10] MPa")
        if not (math.isfinite(self.noise) and 0 <= self.noise <= 100):
            raise DesignError("noise", self.noise, "must be in [0, 100]")
        if not 1 <= self.fps <= FS_HZ:
            raise DesignError("fps", self.fps, f"must be in [1, {FS_HZ:g}] Hz")
        if self.rest_s < 0:
            raise DesignError("rest_s", self.rest_s, "must be >= 0 s")

    @property
    def duration_s(self) -> float:
        """Total length of the run, s."""
        return sum(self.rest_s + self.cycles / f for f in self.freqs_hz) + self.rest_s

    def segments(self) -> list[tuple[float, float, str]]:
        """``(t_start_excitation, frequency, label)`` per segment; labels name the frequency."""
        out = []
        t = 0.0
        for f in self.freqs_hz:
            t += self.rest_s
            out.append((t, f, f"{self.waveform}_{f:g}Hz"))
            t += self.cycles / f
        return out


@dataclass(frozen=True)
class BenchResult:
    """Paths and headline numbers of a bench run."""

    run_csv: str
    frames_avi: str
    truth_json: str
    rows: int
    frames: int
    frames_without_tip: int
    curvature_rms_error_per_mm: float
    curvature_peak_per_mm: float
    record: RecordSummary


def make_plant(design, *, effects=(), load: str = "cap"):
    """The bench's plant: :class:`~softcath.virtualbench.plant.Plant` (analytic model + hidden effects).

    ``effects`` is a sequence of ``(name, params_dict)`` for
    :func:`~softcath.virtualbench.truth_effects.make_effect`.
    """
    built = tuple(make_effect(name, **params) for name, params in effects)
    return Plant.from_design(design, effects=built, load=load)


def _drive_stage(cfg: BenchConfig, stage: ZaberStage, clock: VirtualClock) -> None:
    """Send the excitation to the stage at its virtual times (manual clock)."""
    syr = cfg.syringe
    x_max = float(syr.displacement_mm(cfg.pressure_max_MPa))
    clock.set(0.0)
    stage.home()
    for t0, f, _ in cfg.segments():
        period = 1.0 / f
        if cfg.waveform == "sine":
            clock.set(t0)
            stage.move_sine(x_max / 2, period, cycles=cfg.cycles)
        elif cfg.waveform == "triangle":
            stage.set_max_speed(2 * x_max * f)  # 0 -> x_max in half a period
            for c in range(cfg.cycles):
                clock.set(t0 + c * period)
                stage.move_abs(x_max)
                clock.set(t0 + (c + 0.5) * period)
                stage.move_abs(0.0)
        else:  # steps: 8 levels up and down per cycle, each moved at 20x the hold rate
            levels = [0.25, 0.5, 0.75, 1.0, 0.75, 0.5, 0.25, 0.0]
            hold = period / len(levels)
            stage.set_max_speed(20 * 0.25 * x_max / hold)
            for c in range(cfg.cycles):
                for j, lev in enumerate(levels):
                    clock.set(t0 + c * period + j * hold)
                    stage.move_abs(lev * x_max)
    clock.set(cfg.duration_s)


def _camera(
    cfg: BenchConfig,
    t_frames: np.ndarray,
    kappa: np.ndarray,
    arc: np.ndarray,
    writer: VideoWriter,
    *,
    cal: Calibration,
    rng: np.random.Generator,
    counts: dict,
) -> Iterator:
    """Render, save and measure each frame: the virtual camera feeding the real pipeline."""
    scene = cfg.scene
    for i, t in enumerate(t_frames):
        img = render_frame(scene, curvature_per_mm=kappa[i], arc_length_mm=arc[i], rng=rng)
        writer.write(img)
        counts["frames"] += 1
        yield float(t), measure(img, cal, method=cfg.method)


def run_bench(
    design,
    out_dir: str | Path,
    cfg: BenchConfig = BenchConfig(),
    *,
    effects=(),
    load: str = "cap",
    design_label: str = "",
    progress=None,
) -> BenchResult:
    """Run the virtual bench; write ``run.csv``, ``frames.avi``, ``truth.json`` (and ``truth.csv``).

    Parameters
    ----------
    design
        A :class:`design.TipDesign`.
    out_dir
        Output folder.
    cfg
        :class:`BenchConfig`.
    effects
        ``[(name, params), ...]`` hidden effects of the plant (see :func:`make_plant`).
    load
        Analytic load case, ``cap`` or ``lumen``.
    design_label
        How the design was given (stored in truth.json).
    progress
        Optional callable ``(rows_written, rows_total)``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plant = make_plant(design, effects=effects, load=load)
    rng = np.random.default_rng(cfg.seed)
    scene = Scene(**{**asdict(cfg.scene), "noise": 2.0 * cfg.noise})
    n = int(round(cfg.duration_s * FS_HZ)) + 1
    t = np.arange(n) / FS_HZ

    # 1. drive the virtual stage through the real driver, on a manual virtual clock
    clock = VirtualClock(manual=True)
    stage_dev = VirtualStage(clock)
    press_dev, enc_dev = VirtualLineDevice(), VirtualLineDevice()
    try:
        with ZaberStage(stage_dev.url, microstep_mm=DEFAULT_MICROSTEP_MM) as stage:
            _drive_stage(cfg, stage, clock)
        sig = _plant_signals(cfg, plant, stage_dev, t, rng)

        # 2. record through the real recorder and measurement pipeline
        summary, frames = _record(
            out, cfg, scene, t, sig, press_dev=press_dev, enc_dev=enc_dev, progress=progress
        )
    finally:
        stage_dev.close()
        press_dev.close()
        enc_dev.close()

    # 3. truth and headline numbers
    rms = _curvature_rms(out / "run.csv", t, sig.kappa)
    _write_truth_csv(out / "truth.csv", t, sig.p_true, sig.x_mm, sig.resp)
    truth = _truth(
        design,
        design_label,
        load,
        plant,
        cfg=cfg,
        scene=scene,
        commands=stage_dev.commands,
        summary=summary,
        rms=rms,
        kappa=sig.kappa,
    )
    (out / "truth.json").write_text(json.dumps(truth, indent=2, default=_json_default))
    return BenchResult(
        run_csv=str(out / "run.csv"),
        frames_avi=str(out / "frames.avi"),
        truth_json=str(out / "truth.json"),
        rows=summary.rows,
        frames=frames,
        frames_without_tip=summary.camera_misses,
        curvature_rms_error_per_mm=rms,
        curvature_peak_per_mm=float(sig.kappa.max()),
        record=summary,
    )


@dataclass(frozen=True)
class _Signals:
    """The plant's signals on the 200 Hz rows and at the camera frames."""

    steps: np.ndarray
    x_mm: np.ndarray
    p_true: np.ndarray
    resp: object
    kappa: np.ndarray
    arc: np.ndarray
    sensor_kpa: np.ndarray
    t_frames: np.ndarray
    k_frames: np.ndarray
    arc_frames: np.ndarray


def _plant_signals(cfg: BenchConfig, plant, stage_dev: VirtualStage, t: np.ndarray, rng) -> _Signals:
    """Turn the stage trajectory into pressure, curvature and arc length, and the sensor readings."""
    n = t.size
    steps = stage_dev.trajectory_steps(t)
    x_mm = steps * DEFAULT_MICROSTEP_MM
    p_true = np.asarray(cfg.syringe.pressure_MPa(x_mm), float)
    resp = plant.simulate(t, p_true)
    kappa = np.asarray(resp.curvature_per_mm, float)
    arc = np.asarray(resp.arc_length_mm, float)
    sensor_kpa = (p_true + rng.normal(0.0, 0.002 * cfg.noise, n)) * 1e3
    # frames cover every row: the last frame is at or after the last row
    t_frames = np.arange(int(math.ceil(t[-1] * cfg.fps - 1e-9)) + 1) / cfg.fps
    return _Signals(
        steps=steps,
        x_mm=x_mm,
        p_true=p_true,
        resp=resp,
        kappa=kappa,
        arc=arc,
        sensor_kpa=sensor_kpa,
        t_frames=t_frames,
        k_frames=np.interp(t_frames, t, kappa),
        arc_frames=np.interp(t_frames, t, arc),
    )


def _record(
    out: Path,
    cfg: BenchConfig,
    scene: Scene,
    t: np.ndarray,
    sig: _Signals,
    *,
    press_dev: VirtualLineDevice,
    enc_dev: VirtualLineDevice,
    progress,
) -> tuple[RecordSummary, int]:
    """Feed the virtual devices to the real recorder; returns its summary and the frames written."""
    n = t.size
    cal = Calibration(px_per_mm=scene.px_per_mm, base_px=scene.base, base_angle_deg=scene.base_angle_deg)
    counts = {"frames": 0}
    writer = VideoWriter(out / "frames.avi", fps=cfg.fps, size=(scene.width_px, scene.height_px))
    cam_rng = np.random.default_rng([cfg.seed, 1])
    camera = _camera(
        replace(cfg, scene=scene),
        sig.t_frames,
        sig.k_frames,
        sig.arc_frames,
        writer,
        cal=cal,
        rng=cam_rng,
        counts=counts,
    )
    pressure = SerialSensor(press_dev.url, name="pressure sensor", scale=1e-3).open()
    encoder = SerialSensor(enc_dev.url, name="encoder", scale=DEFAULT_MICROSTEP_MM).open()
    labels = [(0.0, cfg.segments()[0][2])] + [(t0 - cfg.rest_s, lab) for t0, _, lab in cfg.segments()[1:]]
    rec = Recorder(
        out / "run.csv",
        pressure=pressure,
        encoder=encoder,
        camera=camera,
        config=RecorderConfig(clock="device", device_rate_hz=FS_HZ, reconnect_timeout_s=0.5),
        segments=labels,
        on_status=(lambda s: progress(s.rows, n)) if progress else None,
    )
    result: dict = {}

    def record() -> None:
        try:
            result["s"] = rec.run(duration_s=t[-1])
        except BaseException as exc:  # noqa: BLE001 - re-raised in the caller's thread
            result["error"] = exc

    th = threading.Thread(target=record, name="bench-recorder")
    th.start()
    try:
        for k in range(n):
            press_dev.emit(sig.sensor_kpa[k])
            enc_dev.emit(float(np.round(sig.steps[k])))
    except OSError:
        pass  # the recorder stopped reading (it failed): its error is raised below
    th.join()
    writer.close()
    if "error" in result:
        raise result["error"]
    return result["s"], counts["frames"]


def _curvature_rms(run_csv: Path, t: np.ndarray, kappa: np.ndarray) -> float:
    """RMS error of the recorded curvature against the plant's [1/mm]."""
    data = read_recording(run_csv)
    k_meas = data["curvature_per_mm"]
    k_true_rows = np.interp(data["time_s"], t, kappa)
    ok = np.isfinite(k_meas)
    return float(np.sqrt(np.mean((k_meas[ok] - k_true_rows[ok]) ** 2))) if ok.any() else math.nan


def _truth(
    design,
    design_label: str,
    load: str,
    plant,
    *,
    cfg: BenchConfig,
    scene: Scene,
    commands,
    summary: RecordSummary,
    rms: float,
    kappa: np.ndarray,
) -> dict:
    """The content of ``truth.json``."""
    try:
        design_toml = design_pkg.dumps(design)
    except Exception:  # noqa: BLE001 - a design object without TOML support still runs
        design_toml = None
    return {
        "design": design_label,
        "design_toml": design_toml,
        "load": load,
        "plant": {
            "kind": type(plant).__module__ + "." + type(plant).__name__,
            "curvature_per_mpa": float(plant.curvature_per_mpa),
            "elongation_per_mpa": float(plant.elongation_per_mpa),
            "length_mm": float(plant.length_mm),
            "effects": [{"name": e.name, "params": _params(e)} for e in getattr(plant, "effects", ())],
        },
        "excitation": {
            "waveform": cfg.waveform,
            "freqs_hz": list(cfg.freqs_hz),
            "cycles": cfg.cycles,
            "pressure_max_MPa": cfg.pressure_max_MPa,
            "rest_s": cfg.rest_s,
            "segments": [{"t_start_s": a, "freq_hz": f, "run": lab} for a, f, lab in cfg.segments()],
            "duration_s": cfg.duration_s,
        },
        "noise": {
            "level": cfg.noise,
            "pressure_sd_MPa": 0.002 * cfg.noise,
            "camera_sd_grey": scene.noise,
        },
        "seed": cfg.seed,
        "camera": {**asdict(scene), "fps": cfg.fps, "method": cfg.method},
        "syringe": asdict(cfg.syringe),
        "stage": {"microstep_mm": DEFAULT_MICROSTEP_MM, "commands": commands},
        "record": {
            "rows": summary.rows,
            "stop_reason": summary.stop_reason,
            "devices": summary.devices,
            "camera_frames": summary.camera_frames,
            "camera_misses": summary.camera_misses,
        },
        "check": {"curvature_rms_error_per_mm": rms, "curvature_peak_per_mm": float(kappa.max())},
    }


def _params(effect) -> dict:
    if hasattr(effect, "params"):
        try:
            return dict(effect.params())
        except TypeError:
            pass
    return {k: v for k, v in asdict(effect).items()}


def _json_default(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, tuple):
        return list(o)
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def _write_truth_csv(path: Path, t, p_true, x_mm, resp) -> None:
    cols = ("time_s", "pressure_MPa", "stage_mm", "curvature_per_mm", "arc_length_mm")
    sink = CsvSink(path, cols)
    for i in range(len(t)):
        sink.append(
            {
                "time_s": t[i],
                "pressure_MPa": p_true[i],
                "stage_mm": x_mm[i],
                "curvature_per_mm": resp.curvature_per_mm[i],
                "arc_length_mm": resp.arc_length_mm[i],
            }
        )
    sink.close()
