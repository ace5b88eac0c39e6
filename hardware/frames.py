"""Frame sources (camera index, video file, image folder) and the overlay video writer.

OpenCV's readers and writers fail silently; every source here checks
``isOpened()`` and the first read, and says which source could not be read.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcath.hardware.errors import FrameSourceError

__all__ = ["Frame", "FrameSource", "open_source", "VideoWriter", "IMAGE_SUFFIXES"]

log = logging.getLogger(__name__)

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")


@dataclass(frozen=True)
class Frame:
    """One frame: index, time (s) and BGR image."""

    index: int
    time_s: float
    image: np.ndarray


class FrameSource:
    """Iterate over :class:`Frame` objects from a camera, a video file or an image folder.

    Times: video files use the frame index over the file's frame rate (or
    ``fps`` if given), image folders use ``fps`` (default 30), cameras the
    host clock from the first frame.
    """

    def __init__(self, spec: str | int | Path, *, fps: float | None = None) -> None:
        self.spec = spec
        self.kind, self._cap, self._files = self._open(spec)
        self.fps = float(fps) if fps else self._native_fps()
        self.frame_count = self._count()

    def _open(self, spec):
        import cv2

        if isinstance(spec, int) or (isinstance(spec, str) and spec.isdigit()):
            cap = cv2.VideoCapture(int(spec))
            if not cap.isOpened():
                raise FrameSourceError(f"camera {spec}: cannot be opened (no such camera?)")
            return "camera", cap, None
        path = Path(spec)
        if path.is_dir():
            files = sorted(p for p in path.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
            if not files:
                raise FrameSourceError(f"image folder {path}: holds no images ({', '.join(IMAGE_SUFFIXES)})")
            return "folder", None, files
        if not path.exists():
            raise FrameSourceError(f"video {path}: no such file")
        cap = cv2.VideoCapture(str(path))
        if not cap.isOpened():
            raise FrameSourceError(f"video {path}: cannot be opened by OpenCV (codec or format)")
        return "video", cap, None

    def _native_fps(self) -> float:
        import cv2

        if self._cap is not None:
            fps = self._cap.get(cv2.CAP_PROP_FPS)
            if fps and np.isfinite(fps) and fps > 0:
                return float(fps)
        return 30.0

    def _count(self) -> int | None:
        import cv2

        if self._files is not None:
            return len(self._files)
        if self.kind == "video":
            n = int(self._cap.get(cv2.CAP_PROP_FRAME_COUNT))
            return n if n > 0 else None
        return None

    def __iter__(self) -> Iterator[Frame]:
        import cv2

        if self._files is not None:
            for i, f in enumerate(self._files):
                img = cv2.imread(str(f), cv2.IMREAD_COLOR)
                if img is None:
                    raise FrameSourceError(f"image {f}: cannot be read")
                yield Frame(i, i / self.fps, img)
            return
        i = 0
        t0 = None
        while True:
            ok, img = self._cap.read()
            if not ok:
                if i == 0:
                    raise FrameSourceError(f"{self.kind} {self.spec}: no frame could be read")
                return
            if self.kind == "camera":
                now = time.monotonic()
                t0 = now if t0 is None else t0
                t = now - t0
            else:
                t = i / self.fps
            yield Frame(i, t, img)
            i += 1

    def close(self) -> None:
        """Release the capture."""
        if self._cap is not None:
            self._cap.release()

    def __enter__(self) -> FrameSource:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def open_source(spec: str | int | Path, *, fps: float | None = None) -> FrameSource:
    """Open a camera index (``"0"``), a video file or an image folder."""
    return FrameSource(spec, fps=fps)


class VideoWriter:
    """An MJPG AVI writer that checks it really opened (the FFmpeg in opencv-python has MJPG)."""

    def __init__(self, path: str | Path, *, fps: float, size: tuple[int, int]) -> None:
        import cv2

        self.path = Path(path)
        self._w = cv2.VideoWriter(str(self.path), cv2.VideoWriter_fourcc(*"MJPG"), fps, size)
        if not self._w.isOpened():
            raise FrameSourceError(f"video writer {self.path}: cannot be opened")
        self.size = size
        self.frames = 0

    def write(self, image: np.ndarray) -> None:
        """Append one BGR frame of the writer's size."""
        if (image.shape[1], image.shape[0]) != self.size:
            raise FrameSourceError(
                f"video writer {self.path}: frame size {image.shape[1]}x{image.shape[0]} "
                f"!= {self.size[0]}x{self.size[1]}"
            )
        self._w.write(image)
        self.frames += 1

    def close(self) -> None:
        """Finish the file."""
        self._w.release()

    def __enter__(self) -> VideoWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
