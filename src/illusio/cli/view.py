"""``illusio view``: each technique live in a window, or a camera path recorded offscreen."""

from __future__ import annotations

from pathlib import Path

import typer

from ..core.errors import InputError, did_you_mean
from ..core.images import check_output_path
from ..core.renderer import DEFAULT_SIZE
from ..core.technique import techniques
from .common import parse_size

#: the registry's techniques with a viewer mode, one name per mode as viewer.modes.MODES has them (sis
#: and sis-scene share one), read from the descriptors: nothing heavy loads
_VIEWABLE = list({t.viewer_mode: name for name, t in reversed(techniques().items()) if t.viewer_mode}.values())[::-1]


def view(
    source: str = typer.Argument(
        None,
        help="what to show: the technique's scene, mesh or folder (sis: the hidden shape, "
        "or the scene hosting it); default: the technique's own (illusio list techniques)",
    ),
    technique: str = typer.Option(
        "plain",
        "--technique",
        "-t",
        help=f"a technique with a viewer mode: {', '.join(_VIEWABLE)} (illusio list techniques)",
    ),
    variant: str = typer.Option(
        None,
        "--view",
        help="the technique's view (its views in illusio list techniques), "
        "e.g. sis tv|wall|interactive|raw, lines drawing|q1|t1|curvature",
    ),
    size: str = typer.Option(
        "x".join(map(str, DEFAULT_SIZE)),
        "--size",
        help="WIDTHxHEIGHT of the image or the video (the window adds the panel's column)",
    ),
    path: Path = typer.Option(None, "--path", help="play a camera path (JSON keyframes t, eye, target)"),
    output: Path = typer.Option(None, "-o", "--output", help="record to a video (.mp4 or .gif) offscreen, no window"),
    fps: float = typer.Option(30.0, "--fps", help="frames per second of the recorded video"),
    exit_after: int = typer.Option(None, "--exit-after", help="close after N frames"),
    screenshot: Path = typer.Option(None, "--screenshot", help="save the last frame (.png)"),
    screenshot_window: Path = typer.Option(
        None, "--screenshot-window", help="save the whole window at the end, the panel and its settings included (.png)"
    ),
    record: Path = typer.Option(
        None, "--record", help="record the walk as a camera path (JSON) when the window closes"
    ),
) -> None:
    """Watch a technique live in a window (WASD + mouse, Tab switches technique), or record a camera
    path to a video with no window (-o OUT.mp4 --path CAMERA.json)."""
    from ..viewer.modes import MODES
    from ..viewer.path import CameraPath

    if technique not in MODES:
        raise InputError(
            f"--technique must be one of {', '.join(MODES)}, got {technique!r}{did_you_mean(technique, MODES)}"
        )
    w, h = parse_size(size)
    inputs = [p for p in (source, path) if p is not None and Path(p).exists()]
    for out in (output, screenshot, record, screenshot_window):
        if out is not None:
            check_output_path(out, inputs)
    if screenshot_window is not None and (output is not None or _headless()):
        raise InputError("--screenshot-window needs the window (a display); --screenshot saves the frame alone")
    if output is not None and output.suffix.lower() not in (".mp4", ".gif"):
        raise InputError(f"{output.name}: the video must be an .mp4 or a .gif")
    camera_path = CameraPath.load(path) if path is not None else None
    if output is not None or (screenshot is not None and exit_after is not None and record is None and _headless()):
        from ..viewer.offscreen import record as record_offscreen

        if record is not None:
            raise InputError("--record needs the window (it records a walk); leave out -o")
        # record() reports its frames as a phase (core.progress)
        count = record_offscreen(technique, source, variant, (w, h), camera_path, fps, output, screenshot, exit_after)
        for out in (output, screenshot):
            if out is not None:
                typer.echo(f"wrote {out} ({count} frames, {w}×{h})" if out == output else f"wrote {out}")
        return
    from ..viewer.window import ViewerWindow

    window = ViewerWindow(technique, source, variant, (w, h), camera_path, record)
    window.run(exit_after, screenshot, screenshot_window)
    for out in (screenshot, record, screenshot_window):
        if out is not None and out.exists():
            typer.echo(f"wrote {out}")


def _headless() -> bool:
    import os

    return not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY")
