"""Scripted runs without a window: a camera path played by a :class:`Viewer` on a headless context,
written as a video (and a screenshot of the last frame). The same frames as the window shows."""

from __future__ import annotations

import math
from contextlib import nullcontext
from pathlib import Path

from ..core.context import Context
from ..core.errors import InputError
from ..core.images import VideoWriter
from ..core.progress import phase
from .path import CameraPath
from .viewer import Viewer

__all__ = ["frame_count", "record"]


def frame_count(path: CameraPath | None, fps: float, exit_after: int | None) -> int:
    """How many frames a scripted run draws: ``exit_after`` if given, else the path's duration at
    ``fps`` (its first and last keyframe included)."""
    if exit_after is not None:
        if exit_after < 1:
            raise InputError(f"--exit-after must be at least 1 frame, got {exit_after}")
        return exit_after
    if path is None:
        return 1
    return int(math.floor(path.duration * fps + 1e-9)) + 1


def record(
    technique: str,
    source: str | None,
    variant: str | None,
    size: tuple[int, int],
    path: CameraPath | None,
    fps: float,
    output: Path | None = None,
    screenshot: Path | None = None,
    exit_after: int | None = None,
    ctx: Context | None = None,
    on_frame=None,
) -> int:
    """Play ``path`` in ``technique``'s mode at ``fps`` and write the frames to ``output`` (.mp4 or
    .gif) and the last to ``screenshot``. ``on_frame(index, viewer)`` is called after each frame
    (progress, tests). Returns the number of frames."""
    if not fps > 0:
        raise InputError(f"--fps must be positive, got {fps}")
    count = frame_count(path, fps, exit_after)
    viewer = Viewer(ctx or Context(), technique, source, variant, size, path)
    try:
        with (
            VideoWriter(output, fps) if output is not None else nullcontext() as video,
            phase(f"view: {count} frames of {technique}", total=count) as frame_done,
        ):
            for i in range(count):
                frame_done()
                viewer.step(1.0 / fps)
                if video is not None:
                    video.append(viewer.image())
                if on_frame is not None:
                    on_frame(i, viewer)
        if screenshot is not None:
            viewer.screenshot(screenshot)
    finally:
        viewer.release()
    return count
