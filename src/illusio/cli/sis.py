"""illusio sis, sis-scene, sis-decode: autostereograms from depth maps and inside 3D scenes."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import typer

from ..core.errors import InputError, did_you_mean
from ..core.gl import check_size
from ..core.images import check_output_path, read_image, write_image, write_video
from ..scene.camera import Screen
from ..sis.params import MultiSceneParams, StereogramParams
from .common import SCENE_HELP, on_turntable_option, parse_size, progress, scene_inputs
from .params_options import params_options

_DEFAULT = StereogramParams()
_MULTI = MultiSceneParams()
_SCREEN = Screen()


def _depth_input(source: str, size: tuple[int, int] | None, ctx_factory):
    """D (0 = near) from a depth file (white = near), or a mesh / built-in shape rendered to depth."""
    from ..core.renderer import DEFAULT_SIZE
    from ..scene.builtin import SHAPES
    from ..scene.sources import is_mesh_source, resolve_mesh
    from ..sis.depth import depth_from_scene, hidden_scene, read_depth

    p = Path(source)
    if is_mesh_source(source):
        return depth_from_scene(ctx_factory(), hidden_scene(resolve_mesh(source)), size or DEFAULT_SIZE)
    if not p.exists():
        raise InputError(
            f"{source}: no such file, and not a built-in shape ({', '.join(SHAPES)}){did_you_mean(source, SHAPES)}"
        )
    depth = read_depth(p)
    if size and (depth.shape[1], depth.shape[0]) != size:
        from ..sis.stereogram import resize_depth

        depth = resize_depth(depth, size)
    return depth


def _print_size(text: str, dpi: float) -> tuple[tuple[int, int], Screen]:
    """'20x15cm' at ``dpi`` → pixels, and the matching physical 'screen' (the print)."""
    body = text.lower().replace("×", "x").removesuffix("cm")
    try:
        w_cm, h_cm = (float(v) for v in body.split("x"))
    except ValueError:
        raise InputError(f"--print-size must look like 20x15cm, got {text!r}") from None
    if not (w_cm > 0 and h_cm > 0 and dpi > 0) or not np.isfinite([w_cm, h_cm, dpi]).all():
        raise InputError("--print-size and --dpi must be positive")
    w, h = int(round(w_cm / 2.54 * dpi)), int(round(h_cm / 2.54 * dpi))
    try:
        check_size((w, h))  # refused before anything is made, as --size is
    except InputError as exc:
        raise InputError(f"--print-size {text} at {dpi:g} dpi: {exc}; print smaller or lower --dpi") from None
    return (w, h), Screen(diagonal_cm=float(np.hypot(w_cm, h_cm)), aspect=w_cm / h_cm, width_px=w, height_px=h)


@params_options(params=StereogramParams)
def sis(
    depth: str = typer.Argument(
        ...,
        help="depth map: grey PNG (8/16-bit, white = near), .npy, a mesh file or a built-in shape; for a"
        " video, depth frames: a video (.mp4, white = near), a numbered sequence (depth_%04d.png) or a folder"
        " of images or .npy frames",
    ),
    output: Path = typer.Option(
        ...,
        "-o",
        "--output",
        help="stereogram to write (.png), or a video (.mp4, .gif) of depth frames or of a shape turning round",
    ),
    size: str = typer.Option(None, "--size", help="WIDTHxHEIGHT in pixels (default: the depth map's)"),
    print_size: str = typer.Option(
        None, "--print-size", help="WIDTHxHEIGHTcm for print (with --dpi); sets the size and the physical model"
    ),
    dpi: float = typer.Option(300.0, "--dpi", help="dots per inch with --print-size"),
    cpu: bool = typer.Option(False, "--cpu/--no-cpu", help="use the NumPy/numba reference instead of the GPU"),
    frames: int = typer.Option(
        None, "--frames", help="video: frames of a shape's turn (default 48), or the first N depth frames"
    ),
    fps: float = typer.Option(None, "--fps", help="video: frames a second (default: the depth video's, else 24)"),
    hold: bool = typer.Option(
        True,
        "--hold/--regenerate",
        help="video: keep each frame's colours where the depth stays (sis.video), or make every frame afresh",
    ),
    *,
    params: StereogramParams,
) -> None:
    """Make an autostereogram of DEPTH, or a stereogram video of depth frames or of a shape turning."""
    from ..core.context import Context
    from ..sis.stereogram import stereogram

    out = check_output_path(output, scene_inputs(depth) + scene_inputs(params.pattern))
    params = replace(params, screen=params.screen.derived())  # its height from the width and aspect given
    if out.suffix.lower() in (".mp4", ".gif"):
        if print_size:
            raise InputError("--print-size makes a print: write a .png")
        _sis_video(depth, out, parse_size(size) if size else None, frames, fps, hold, params)
        return
    if frames is not None or fps is not None:
        raise InputError("--frames and --fps make a video: write an .mp4 or a .gif")
    wanted = parse_size(size) if size else None
    if print_size:
        wanted, screen = _print_size(print_size, dpi)
        params = replace(params, screen=screen)
    contexts = []

    def ctx_factory():
        if not contexts:
            contexts.append(Context())
        return contexts[0]

    d = _depth_input(depth, wanted, ctx_factory)
    image = stereogram(d, params, None if cpu else ctx_factory(), cpu=cpu)
    # what made it, for sis-decode and for whoever finds the file later
    text = {
        f"illusio:{k}": str(getattr(params, k))
        for k in ("strip_width", "depth_factor", "algorithm", "cross_eyed", "invert", "exact", "seed", "pattern")
    }
    write_image(out, image, text=text)
    typer.echo(
        f"wrote {out} ({image.shape[1]}×{image.shape[0]}, {params.algorithm}, "
        f"separations {params.strip_width:g}..{params.far_separation:g} px)"
    )


#: frames of a shape's turn when --frames does not say
TURN_FRAMES = 48


def _sis_video(depth: str, out: Path, size, frames, fps, hold: bool, params: StereogramParams) -> None:
    """A stereogram video (sis.video): of depth frames, or of a shape turning once round."""
    from itertools import islice

    from ..core.context import default_context
    from ..core.images import VideoWriter
    from ..core.renderer import DEFAULT_SIZE
    from ..scene.sources import is_mesh_source, resolve_mesh
    from ..sis.stereogram import resize_depth
    from ..sis.video import DEFAULT_FPS, StereogramSequence, is_depth_sequence, open_depth_frames, turntable_depths

    if frames is not None and frames < 1:
        raise InputError(f"--frames must be at least 1, got {frames}")
    if fps is not None and not fps > 0:
        raise InputError(f"--fps must be positive, got {fps}")
    sequence = StereogramSequence(params, hold)  # refuses the symmetric algorithm before any work
    if is_depth_sequence(depth):
        source = open_depth_frames(depth, fps)
        count = min(source.count, frames or source.count)
        depths, rate, what = islice(iter(source), count), source.fps, f"{count} depth frames of {depth}"
    elif is_mesh_source(depth):
        count = frames or TURN_FRAMES
        depths = turntable_depths(default_context(), resolve_mesh(depth), size or DEFAULT_SIZE, count)
        rate, what = fps or DEFAULT_FPS, f"{depth} turning once round in {count} frames"
    else:
        raise InputError(
            f"{depth}: one depth map makes one picture (.png); a video needs depth frames (a video, a numbered"
            " sequence depth_%04d.png, a folder) or a shape to turn"
        )
    with VideoWriter(out, rate) as video, progress(count, "sis: frames") as advance:
        for d in depths:
            if size and (d.shape[1], d.shape[0]) != size:
                d = resize_depth(d, size)
            video.append(sequence.frame(d))
            advance()
    typer.echo(f"wrote {out} ({what}, {rate:g} frames a second, {'held' if hold else 'regenerated'})")


#: the share of checked pixels that must decode back for sis-decode's self-check to pass
SELF_CHECK_PASS = 0.8


def sis_decode(
    image: Path = typer.Argument(..., help="a stereogram (.png)"),
    output: Path = typer.Option(..., "-o", "--output", help="decoded depth (.png, white = near)"),
    strip_width: float = typer.Option(
        None,
        "--strip-width",
        help=f"W_s the stereogram was made with (default: from its PNG text, else {_DEFAULT.strip_width:g})",
    ),
    depth_factor: float = typer.Option(
        None, "--depth-factor", help=f"β it was made with (default: from its PNG text, else {_DEFAULT.depth_factor:g})"
    ),
    expected: Path = typer.Option(
        None, "--expected", help="the depth map it was made from: report how much decodes back; exit 1 when under 80 %"
    ),
    symmetric: bool = typer.Option(
        None, "--symmetric/--no-symmetric", help="made by the symmetric algorithm (default: from its PNG text)"
    ),
    cross_eyed: bool = typer.Option(
        None, "--cross-eyed/--no-cross-eyed", help="made for crossed eyes (default: from its PNG text, else no)"
    ),
) -> None:
    """Recover the depth map hidden in a stereogram by window matching (the self-check). The
    parameters it was made with are read from its PNG text when `illusio sis` wrote it."""
    from ..core.images import read_png_text
    from ..sis.decode import check, decode_separation, separation_to_depth
    from ..sis.depth import read_depth
    from ..sis.reference import separation

    out = check_output_path(output, [image] + ([expected] if expected else []))
    made = read_png_text(image)

    def given(value, key, default, kind):
        if value is not None:
            return value
        if f"illusio:{key}" in made:
            raw = made[f"illusio:{key}"]
            return raw == "True" if kind is bool else kind(raw)
        return default

    strip_width = given(strip_width, "strip_width", _DEFAULT.strip_width, float)
    depth_factor = given(depth_factor, "depth_factor", _DEFAULT.depth_factor, float)
    cross_eyed = given(cross_eyed, "cross_eyed", False, bool)
    flipped = cross_eyed != given(None, "invert", False, bool)
    symmetric = symmetric if symmetric is not None else made.get("illusio:algorithm") == "symmetric"
    img = read_image(image)[..., :3]
    lo, hi = int(strip_width) - 1, int(np.ceil(strip_width + depth_factor)) + 1
    decoded, _ = decode_separation(img, max(1, lo), hi)
    depth = separation_to_depth(decoded, strip_width, depth_factor)
    if flipped:  # cross-eyed (or inverted) stereograms carry the depth flipped
        depth = 1.0 - depth
    d = None
    if expected:
        d = read_depth(expected)
        if d.shape != img.shape[:2]:
            raise InputError(
                f"--expected is {d.shape[1]}×{d.shape[0]} but the stereogram is {img.shape[1]}×{img.shape[0]}"
            )
    write_image(out, 1.0 - depth, srgb=False)
    typer.echo(f"wrote {out}")
    if d is not None:
        encoded = 1.0 - d if flipped else d
        report = check(
            img,
            separation(encoded, strip_width, depth_factor),
            int(strip_width + depth_factor + 0.5),
            "centre" if symmetric else "left",
        )
        typer.echo(f"self-check: {report}")
        if report.matched < SELF_CHECK_PASS:
            typer.echo(f"self-check failed: under {SELF_CHECK_PASS:.0%} of the checked pixels decode back", err=True)
            raise typer.Exit(1)


@params_options(params=MultiSceneParams)
def sis_scene(
    scene: str = typer.Argument("living-room", help="the main scene, with a host surface: " + SCENE_HELP),
    on_turntable: bool = on_turntable_option(),
    output: Path = typer.Option(..., "-o", "--output", help="image to write (.png); with --frames, the first frame"),
    hidden: str = typer.Option(
        "torus-knot",
        "--hidden",
        help="what the stereogram hides: a built-in shape, a mesh or a scene file (its nodes where it places them)",
    ),
    camera: str = typer.Option(
        "tv", "--camera", help="a named camera of the scene or EYE:TARGET (x,y,z:x,y,z in metres)"
    ),
    size: str = typer.Option(
        f"{_MULTI.reference_width}x{_MULTI.reference_width * 9 // 16}", "--size", help="WIDTHxHEIGHT"
    ),
    frames: int = typer.Option(1, "--frames", help="number of frames (animated snow / spin)"),
    frame: int = typer.Option(0, "--frame", help="index of the first frame (its snow and spin; 24 frames a second)"),
    video: Path = typer.Option(None, "--video", help="write the frames as a video (.mp4 or .gif)"),
    *,
    params: MultiSceneParams,
) -> None:
    """Render SCENE with a stereogram on its host surface hiding another shape (Dehos et al. 2014,
    the multi-scene pipeline of Figure 22)."""
    from ..core.context import default_context
    from ..core.renderer import Frame
    from ..scene.camera import Pose, View
    from ..sis.depth import hidden_scene
    from ..sis.multiscene import MultiSceneRenderer, MultiSceneSubject
    from .common import parse_eye_target, resolve_mesh, resolve_scene

    out = check_output_path(output, scene_inputs(scene) + scene_inputs(hidden))
    if video:
        check_output_path(video, scene_inputs(scene) + scene_inputs(hidden))
        if video.suffix.lower() not in (".mp4", ".gif"):
            raise InputError(f"--video must end in .mp4 or .gif, got {video.name}")
    if frames < 1:
        raise InputError("--frames must be at least 1")
    if frame < 0:
        raise InputError(f"--frame must be ≥ 0, got {frame}")
    w, h = parse_size(size)
    main = resolve_scene(scene, on_turntable)
    pair = parse_eye_target(camera)
    view = main.camera(None if pair is not None or (camera == "tv" and "tv" not in main.cameras) else camera)
    if pair is not None:
        view = View(Pose(*pair), view.camera)
    hidden_mesh = resolve_mesh(hidden)
    params = replace(params, stereogram=replace(params.stereogram, screen=params.stereogram.screen.derived()))
    renderer = default_context().kept(MultiSceneRenderer)  # warm between the tasks of a batch
    renderer.prepare(MultiSceneSubject(main, hidden_scene(hidden_mesh)))
    images = []
    with progress(frames, "sis-scene: frames") as advance:
        for f in range(frame, frame + frames):
            images.append(renderer.render(Frame(view, (w, h), f / 24, f), params))
            advance()
    write_image(out, images[0])
    typer.echo(f"wrote {out} ({w}×{h})")
    if video:
        write_video(video, images)
        typer.echo(f"wrote {video} ({frames} frames)")
