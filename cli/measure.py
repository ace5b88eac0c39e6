"""Measure tip curvature, arc length, bend angle and tip position in a video.

SRC is a video file, an image folder or a camera index. Writes
DIR/measurements.csv (frame, time_s, curvature_per_mm, arc_length_mm,
bend_angle_rad, tip_x_mm, tip_y_mm; mm relative to the base, x right, y up)
and DIR/overlay.avi (edges/centre line, fitted arc and numbers on every frame).
--base is in pixels (origin top-left, y down); --base-angle is
counter-clockwise from the image's +x axis (90: the tip leaves pointing up).
Without --base the base is found in the image and reported.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from softcath.cli.options import add_out
from softcath.core.atomic import staged_dir, unstage
from softcath.core.errors import DataError, DesignError
from softcath.hardware.errors import FrameSourceError
from softcath.hardware.frames import open_source
from softcath.hardware.measure_video import measure_video
from softcath.hardware.vision import Calibration
from softcath.hardware.vision.scale import scale_from_chessboard

HELP = "measure the tip in a video / image folder / camera into a CSV and an overlay video"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of ``softcath measure``."""
    parser.add_argument("src", metavar="SRC", help="video file, image folder or camera index")
    parser.add_argument(
        "--px-per-mm",
        type=float,
        metavar="S",
        help="image scale in the bending plane, px/mm (or give --chessboard)",
    )
    add_chessboard_arguments(parser)
    parser.add_argument("--base", metavar="X,Y", help="base position, pixels (origin top-left)")
    parser.add_argument(
        "--base-angle",
        type=float,
        default=90.0,
        metavar="DEG",
        help="base direction, degrees counter-clockwise from image +x (90: up)",
    )
    parser.add_argument(
        "--method",
        choices=("default", "paper"),
        default="default",
        help="centre-line fit (default) or the paper's edge/slice pipeline",
    )
    parser.add_argument(
        "--dy",
        type=float,
        default=10.0,
        metavar="PX",
        help="slice height of the paper's point reduction, px (--method paper)",
    )
    parser.add_argument("--diameter", type=float, default=0.8, metavar="MM", help="tube diameter, mm (0.8)")
    parser.add_argument(
        "--fps",
        type=float,
        metavar="HZ",
        help="frame rate for image folders (default 30) or to override a video's",
    )
    add_out(parser)


def add_chessboard_arguments(parser: argparse.ArgumentParser) -> None:
    """--chessboard IMAGE --pattern CxR --square-mm MM: the scale from a board in the bending plane."""
    parser.add_argument(
        "--chessboard",
        metavar="IMAGE",
        help="image of a chessboard lying in the bending plane: sets the scale instead of --px-per-mm",
    )
    parser.add_argument(
        "--pattern", default="9x6", metavar="CxR", help="inner corners of the chessboard (9x6)"
    )
    parser.add_argument("--square-mm", type=float, metavar="MM", help="chessboard square side, mm")


def _scale_from_args(args: argparse.Namespace) -> float:
    board = getattr(args, "chessboard", None)
    if board is None:
        if args.px_per_mm is None:
            raise DesignError("--px-per-mm", None, "is required (or give --chessboard)")
        return args.px_per_mm
    import cv2

    if args.square_mm is None:
        raise DesignError("--square-mm", None, "is required with --chessboard")
    try:
        cols, rows = (int(v) for v in args.pattern.lower().split("x"))
    except ValueError as exc:
        raise DesignError("--pattern", args.pattern, "must look like 9x6 (inner corners)") from exc
    img = cv2.imread(str(board), cv2.IMREAD_COLOR)
    if img is None:
        raise FrameSourceError(f"chessboard image {board}: cannot be read")
    return scale_from_chessboard(img, pattern=(cols, rows), square_mm=args.square_mm)


def calibration_from_args(args: argparse.Namespace):
    """A :class:`softcath.hardware.vision.Calibration` from --px-per-mm (or --chessboard), --base,
    --base-angle."""
    import math

    scale = _scale_from_args(args)  # the scale, base angle and diameter are checked by Calibration
    diameter = getattr(args, "diameter", 0.8)
    base = None
    if args.base:
        try:
            x, y = (float(v) for v in args.base.split(","))
        except ValueError as exc:
            raise DesignError("--base", args.base, "must be two numbers X,Y in pixels") from exc
        if not (math.isfinite(x) and math.isfinite(y) and x >= 0 and y >= 0):
            raise DesignError("--base", args.base, "must be finite pixel coordinates >= 0 (origin top-left)")
        base = (x, y)
    return Calibration(
        px_per_mm=scale,
        base_px=base,
        base_angle_deg=args.base_angle,
        diameter_mm=diameter,
    )


def run(args: argparse.Namespace) -> int:
    """Run ``softcath measure``."""
    import logging
    import math

    cal = calibration_from_args(args)
    if getattr(args, "chessboard", None):
        print(f"scale from the chessboard: {cal.px_per_mm:.3f} px/mm")
    # per-frame misses are counted and summarised below rather than logged one by one
    logging.getLogger("softcath.hardware.measure_video").setLevel(logging.ERROR)

    if args.fps is not None and not (math.isfinite(args.fps) and args.fps > 0):
        raise DesignError("--fps", args.fps, "must be a finite frame rate > 0 Hz")
    if not (math.isfinite(args.dy) and args.dy > 0):
        raise DesignError("--dy", args.dy, "must be a finite slice height > 0 px")
    out = Path(args.out)
    with staged_dir(out) as stage, open_source(args.src, fps=args.fps) as src:
        s = measure_video(src, cal, stage, method=args.method, dy_px=args.dy)
        if s.frames == 0:
            raise DataError(f"{args.src}: no frames to measure; nothing written")
        if s.misses == s.frames:  # every row empty: a wrong setting, not a measurement
            where = f"--base {args.base}" if args.base else "the base found in the image"
            raise DataError(
                f"no tip found in any of the {s.frames} frames ({where}, --base-angle {args.base_angle:g}, "
                f"{cal.px_per_mm:g} px/mm): check that the base lies on the tip inside the image "
                "(pixels, origin top-left) and the scale; nothing written"
            )
    csv_path, overlay_path = (
        unstage(s.csv_path, stage, out),
        s.overlay_path and unstage(s.overlay_path, stage, out),
    )
    print(f"measured {s.frames} frames ({args.method} method) -> {csv_path}, {overlay_path}")
    if s.misses:
        print(f"warning: {s.misses} of {s.frames} frames without a detectable tip (empty rows)")
    if cal.base_px is None and s.base_px is not None:
        print(
            f"base found in the image: X,Y = {s.base_px[0]:.1f},{s.base_px[1]:.1f} px, "
            f"angle {s.base_angle_deg:.1f} deg"
        )
    if math.isfinite(s.median_curvature_per_mm):
        print(f"median curvature {s.median_curvature_per_mm:.4f} 1/mm")
    return 0
