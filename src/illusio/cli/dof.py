"""``illusio dof``: a scene with depth of field, mono or as a stereo pair."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import typer

from ..core.errors import InputError
from ..core.images import check_output_path, write_image
from ..dof.params import DofParams
from .common import SCENE_HELP, on_turntable_option, parse_size, resolve_scene, scene_inputs
from .params_options import params_options


@params_options(params=DofParams)
def dof(
    scene: str = typer.Argument("living-room", help=SCENE_HELP),
    on_turntable: bool = on_turntable_option(),
    output: Path = typer.Option(
        None, "-o", "--output", help="image to write (.png, .exr, .npy); with --scenario, the first frame"
    ),
    focus_object: str = typer.Option(None, "--focus-object", help="focus on this object of the scene (by name or tag)"),
    camera: str = typer.Option(None, "--camera", help="named camera of the scene (default: main)"),
    size: str = typer.Option("1024x768", "--size", help="WIDTHxHEIGHT of each eye's image"),
    scenario: str = typer.Option(
        None, "--scenario", help="a scenario file (or a shipped one: futuristic) driving objects and focus"
    ),
    video: Path = typer.Option(None, "--video", help="with --scenario: the video to write (.mp4 or .gif)"),
    fps: float = typer.Option(12.0, "--fps", help="frames per second of the video"),
    duration: float = typer.Option(None, "--duration", help="seconds of video (default: the scenario's length)"),
    debug: str = typer.Option(
        None,
        "--debug",
        help="write a map instead: coc (pixels / max, white = most blur), depth, "
        "or planes (each pixel's plane in grey levels, Piranda & Desorbier, Figure 8)",
    ),
    *,
    params: DofParams,
) -> None:
    """Render SCENE with depth of field from a thin-lens eye (one focus for both eyes in stereo)."""
    from ..core.context import default_context
    from ..core.renderer import Frame
    from ..dof.debug import debug_map, debug_params
    from ..dof.focus import object_distance
    from ..dof.renderer import DofRenderer

    if output is None and video is None:
        raise InputError("give -o OUT.png, or --scenario FILE with --video OUT.mp4")
    if video is not None and scenario is None:
        raise InputError("--video needs --scenario")
    inputs = scene_inputs(scene) + (scene_inputs(scenario) if scenario else [])
    out = check_output_path(output, inputs) if output is not None else None
    if video is not None:
        check_output_path(video, inputs)
        if video.suffix.lower() not in (".mp4", ".gif"):
            raise InputError(f"{video.name}: the video must be an .mp4 or a .gif")
    if debug is not None:
        debug_params(params, debug)  # refuses an unknown map before any work
    w, h = parse_size(size)
    sc = resolve_scene(scene, on_turntable)
    view = sc.camera(camera)
    sc.check_in_view(view, (w, h))
    if focus_object:
        params = replace(params, focus_distance=object_distance(sc, focus_object, view))
    renderer = default_context().kept(DofRenderer)
    if scenario is not None:
        _play(renderer, sc, view, (w, h), params, scenario, out, video, fps, duration)
        return
    renderer.prepare(sc)
    if debug:
        write_image(out, debug_map(renderer, Frame(view, (w, h)), params, debug), srgb=False)
        typer.echo(f"wrote {out} ({debug} map)")
        return
    image = renderer.render(Frame(view, (w, h)), params)
    params = replace(params, focus_distance=renderer.result().focus_distance)
    if params.stereo == "left-right":  # the two eyes as two files
        half = image.shape[1] // 2
        for eye, part in (("left", image[:, :half]), ("right", image[:, half:])):
            path = out.with_name(f"{out.stem}-{eye}{out.suffix}")
            check_output_path(path, inputs)
            write_image(path, part)
            typer.echo(f"wrote {path}")
        return
    write_image(out, image)
    result = renderer.result()
    typer.echo(
        f"wrote {out} ({image.shape[1]}×{image.shape[0]}, {params.method}, focus {params.focus_distance:.2f} m, "
        f"aperture {params.aperture_mm:g} mm; screen {result.screen_distance:.2f} m, "
        f"vergence–accommodation {result.conflict_dioptres:.2f} D)"
    )


def _play(
    renderer,
    scene,
    view,
    size,
    params,
    scenario: str,
    first: Path | None,
    video: Path | None,
    fps: float,
    duration: float | None,
) -> None:
    """The scenario frame after frame: objects moved and shown as scripted, the focus on the
    scripted object (smoothly), written as a video (and the first frame as an image)."""
    from ..core.images import VideoWriter
    from ..core.renderer import Frame
    from ..dof.scenario import load_scenario, shipped_scenario
    from ..dof.timeline import ScenarioPlayer
    from .common import progress

    script = shipped_scenario(scenario) if not Path(scenario).exists() and shipped_scenario(scenario) else scenario
    player = ScenarioPlayer(load_scenario(script), scene)
    if not fps > 0:
        raise InputError(f"--fps must be positive, got {fps}")
    seconds = duration if duration is not None else (player.loop or player.scenario.duration_ms / 1000.0 or 1.0)
    if not seconds > 0:
        raise InputError(f"--duration must be positive, got {seconds}")
    count = int(round(seconds * fps)) or 1
    conflicts = []
    with (
        VideoWriter(video, fps) if video is not None else _Nothing() as writer,
        progress(count, "dof: frames") as advance,
    ):
        for i in range(count):
            t = i / fps
            player.apply(scene, t)
            renderer.prepare(scene)  # by value: the moved nodes are seen
            focus = player.focus_distance(view, t)
            frame_params = replace(params, focus_distance=focus) if focus is not None else params
            image = renderer.render(Frame(view, size, t, i), frame_params)
            conflicts.append(renderer.result().conflict_dioptres)
            if i == 0 and first is not None:
                write_image(first, image)
            if writer is not None:
                writer.append(image)
            advance()
    for path in (first, video):
        if path is not None:
            typer.echo(f"wrote {path}" + (f" ({count} frames at {fps:g} fps)" if path == video else ""))
    # the eyes converge on the screen and accommodate at the focus: how far apart, frame by frame
    typer.echo(
        f"vergence–accommodation difference: {min(conflicts):.2f} to {max(conflicts):.2f} D "
        f"(mean {sum(conflicts) / len(conflicts):.2f}; screen at {renderer.result().screen_distance:.2f} m)"
    )


class _Nothing:
    def __enter__(self):
        return None

    def __exit__(self, *exc):
        return False
