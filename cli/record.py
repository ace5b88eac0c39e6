"""Record pressure, encoder (and optionally stage position and camera measurements) live.

Rows land on the paper's 200 Hz time base in DIR/measurements.csv (the
measurement schema), appended and fsync-ed at least every second, so a
crash or kill leaves a valid file. DIR/record.json summarises the run.
Stop with Ctrl-C or --duration.
"""

from __future__ import annotations

import argparse
import sys

from softcath.cli.measure import add_chessboard_arguments, calibration_from_args
from softcath.cli.options import add_out
from softcath.core.atomic import prepare_out_dir, write_text
from softcath.core.errors import DataError, DesignError
from softcath.hardware.frames import open_source
from softcath.hardware.measure_video import measured_frames
from softcath.hardware.recorder import Recorder, RecorderConfig
from softcath.hardware.sensors import SerialSensor
from softcath.hardware.stage import ZaberStage

HELP = "record serial sensors (and a camera) into the measurement CSV at 200 Hz"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of ``softcath record``."""
    parser.add_argument(
        "--pressure-port",
        required=True,
        metavar="URL",
        help="pressure sensor: port or pyserial URL (loop://, socket://, /dev/pts/N)",
    )
    parser.add_argument("--encoder-port", required=True, metavar="URL", help="encoder port / URL")
    parser.add_argument(
        "--stage-port", metavar="URL", help="Zaber-style stage to poll for its position (optional)"
    )
    parser.add_argument(
        "--camera",
        metavar="SRC",
        help="camera index, video file or image folder measured into the rows",
    )
    add_out(parser)
    parser.add_argument("--duration", type=float, metavar="S", help="stop after S seconds")
    parser.add_argument(
        "--clock",
        choices=("host", "device"),
        default="host",
        help="time from arrival (host) or from sequence numbers (device)",
    )
    parser.add_argument(
        "--device-rate",
        type=float,
        default=200.0,
        metavar="HZ",
        help="sample rate of the framed devices for --clock device (200)",
    )
    parser.add_argument(
        "--plain",
        action="store_true",
        help="devices print plain numbers instead of $seq,value*CS frames",
    )
    parser.add_argument(
        "--pressure-scale",
        type=float,
        default=1.0,
        metavar="K",
        help="MPa per raw pressure unit (1e-3 for a kPa sensor)",
    )
    parser.add_argument(
        "--encoder-scale", type=float, default=1.0, metavar="K", help="mm per raw encoder unit"
    )
    parser.add_argument("--px-per-mm", type=float, metavar="S", help="camera scale (with --camera)")
    add_chessboard_arguments(parser)
    parser.add_argument("--base", metavar="X,Y", help="base position in pixels (with --camera)")
    parser.add_argument(
        "--base-angle",
        type=float,
        default=90.0,
        metavar="DEG",
        help="base direction, counter-clockwise from image +x (90: up)",
    )
    parser.add_argument("--method", choices=("default", "paper"), default="default")
    parser.add_argument("--run", default="", metavar="LABEL", help="value of the run column")


def _refuse_an_earlier_recording(out) -> None:
    """A recording streams into DIR/measurements.csv from its first row (so a kill keeps it): an
    earlier recording there would be truncated before the new one knows it has data. Refused."""
    for name in ("measurements.csv", "record.json"):
        if (out / name).exists():
            raise DesignError(
                "--out",
                str(out),
                f"holds an earlier recording ({name}); a new one would replace it: give a new folder",
            )


def run(args: argparse.Namespace) -> int:
    """Run ``softcath record``."""

    _check_args(args)
    out = prepare_out_dir(args.out)
    _refuse_an_earlier_recording(out)
    framed = not args.plain
    pressure = SerialSensor(
        args.pressure_port, name="pressure sensor", framed=framed, scale=args.pressure_scale
    )
    encoder = SerialSensor(args.encoder_port, name="encoder", framed=framed, scale=args.encoder_scale)
    cfg = RecorderConfig(clock=args.clock, device_rate_hz=args.device_rate)
    camera = stage = source = None
    if args.camera is not None:
        cal = calibration_from_args(args)
        source = open_source(args.camera)
        camera = measured_frames(source, cal, method=args.method, host_time=source.kind == "camera")
    if args.stage_port:
        stage = ZaberStage(args.stage_port).open()

    def status(s) -> None:
        print("\r" + s.line()[:110].ljust(110), end="", file=sys.stderr, flush=True)

    rec = Recorder(
        out / "measurements.csv",
        pressure=pressure,
        encoder=encoder,
        camera=camera,
        stage=stage,
        config=cfg,
        segments=[(0.0, args.run)] if args.run else None,
        on_status=status,
    )
    try:
        summary = rec.run(duration_s=args.duration)  # Ctrl-C ends it cleanly
    finally:
        if stage is not None:
            stage.close()
        if source is not None:
            source.close()
    print(file=sys.stderr)
    write_text(out / "record.json", summary.to_json())
    if summary.rows == 0:
        heard = ", ".join(
            f"{name} on {st['url']}: {st['received']} lines" for name, st in summary.devices.items()
        )
        raise DataError(
            f"no rows recorded ({summary.stop_reason}): no device spoke"
            + (f" within {args.duration:g} s" if args.duration else "")
            + f" ({heard}); check the ports, the baud rate and --plain; summary in {out / 'record.json'}"
        )
    _print_summary(summary)
    return 0


def _check_args(args: argparse.Namespace) -> None:
    """Refuse a bad duration, scale or device rate."""
    import math

    if args.duration is not None and not (math.isfinite(args.duration) and args.duration > 0):
        raise DesignError("--duration", args.duration, "must be a finite time > 0 s")
    for flag, value in (("--pressure-scale", args.pressure_scale), ("--encoder-scale", args.encoder_scale)):
        if not (math.isfinite(value) and value != 0):
            raise DesignError(flag, value, "must be a finite, non-zero number")
    if not (math.isfinite(args.device_rate) and args.device_rate > 0):
        raise DesignError("--device-rate", args.device_rate, "must be a finite rate > 0 Hz")


def _print_summary(summary) -> None:
    """Print the rows recorded and each device's line counts."""
    print(
        f"recorded {summary.rows} rows ({summary.duration_s:.2f} s) -> {summary.csv_path}; "
        f"stop: {summary.stop_reason}"
    )
    for name, st in summary.devices.items():
        print(
            f"  {name}: {st['received']} lines, {st['corrupted']} corrupted, "
            f"{st['partial']} partial, {st['gaps']} gaps"
        )
    if summary.camera_frames:
        print(f"  camera: {summary.camera_frames} frames, {summary.camera_misses} without a tip")
