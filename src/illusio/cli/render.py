"""illusio render: one image of a scene, a YAML scene, a mesh or a shape."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import typer

from ..core.errors import InputError
from ..core.images import check_output_path, write_image
from ..core.progress import phase
from ..core.renderer import DEFAULT_SIZE
from ..passes.scene_renderer import RenderSettings
from .common import (
    SCENE_HELP,
    on_turntable_option,
    parse_eye_target,
    parse_size,
    parse_view_angles,
    resolve_scene,
    scene_inputs,
)

_DEFAULT = RenderSettings()


def render(
    scene: str = typer.Argument(..., help=SCENE_HELP),
    output: Path = typer.Option(
        ...,
        "-o",
        "--output",
        help=(
            "image to write: .png (8-bit sRGB; 16-bit with --bit-depth 16), .jpg, .npy or .exr (linear "
            "float); .mp4 or .gif with --turntable"
        ),
    ),
    camera: str = typer.Option(
        None, "--camera", help="a named camera of the scene (default: main) or EYE:TARGET (x,y,z:x,y,z in metres)"
    ),
    view: str = typer.Option(
        None, "--view", help="AZ,EL: orbit the main camera's target at its distance, azimuth and elevation in degrees"
    ),
    turntable: int = typer.Option(0, "--turntable", help="N frames around the target (a video: -o .mp4 or .gif)"),
    size: str = typer.Option("x".join(map(str, DEFAULT_SIZE)), "--size", help="WIDTHxHEIGHT in pixels"),
    shadows: bool = typer.Option(_DEFAULT.shadows, "--shadows/--no-shadows", help="cube shadow maps"),
    exposure: float = typer.Option(_DEFAULT.exposure, "--exposure", help="scale on linear radiance before writing"),
    bit_depth: int = typer.Option(8, "--bit-depth", help="8, or 16 (16-bit PNG, half-float EXR)"),
    on_turntable: bool = on_turntable_option(),
) -> None:
    """Render SCENE to an image (or, with --turntable, a video around it)."""
    from ..core.context import default_context
    from ..core.images import VideoWriter
    from ..passes.scene_renderer import render_scene
    from ..scene.camera import Pose, View

    out = check_output_path(output, scene_inputs(scene))
    w, h = parse_size(size)
    if not exposure > 0:
        raise InputError(f"--exposure must be positive, got {exposure}")
    if view is not None and camera is not None:
        raise InputError("give --camera or --view, not both")
    if not 0 <= turntable <= 3600:
        raise InputError(f"--turntable takes 1..3600 frames, got {turntable}")
    video = out.suffix.lower() in (".mp4", ".gif")
    if bool(turntable) != video:
        raise InputError("--turntable N writes a video (-o .mp4 or .gif); a video needs --turntable N")
    angles = parse_view_angles(view) if view is not None else None
    pair = parse_eye_target(camera) if camera is not None else None
    sc = resolve_scene(scene, on_turntable)
    base = sc.camera(None if pair is not None else camera)
    if pair is not None:
        base = View(Pose(*pair), base.camera)
    target = np.asarray(base.pose.target, np.float64)
    offset = np.asarray(base.pose.position, np.float64) - target
    distance = float(np.linalg.norm(offset))
    azimuth = float(np.degrees(np.arctan2(offset[0], offset[2])))
    elevation = float(np.degrees(np.arcsin(np.clip(offset[1] / max(distance, 1e-12), -1, 1))))
    if angles is not None:
        azimuth, elevation = angles
        base = View(Pose.orbit(tuple(target), distance, azimuth, elevation), base.camera)
    sc.check_in_view(base, (w, h))  # refused before a context is made
    settings = RenderSettings(shadows=shadows, exposure=exposure)
    ctx = default_context()
    if not turntable:
        write_image(out, render_scene(sc, base, (w, h), ctx, settings), bit_depth=bit_depth)
        typer.echo(f"wrote {out} ({w}×{h})")
        return
    with VideoWriter(out) as video, phase(f"render: {turntable} frames", total=turntable) as frame_done:
        for k in range(turntable):  # frames streamed: an interrupted run leaves no file
            frame_done()
            video.append(
                render_scene(
                    sc,
                    View(Pose.orbit(tuple(target), distance, azimuth + 360.0 * k / turntable, elevation), base.camera),
                    (w, h),
                    ctx,
                    settings,
                )
            )
    typer.echo(f"wrote {out} ({turntable} frames, {w}×{h})")
